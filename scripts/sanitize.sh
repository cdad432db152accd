#!/usr/bin/env bash
# Builds with AddressSanitizer + UndefinedBehaviorSanitizer (preset asan-ubsan)
# and runs the whole test suite under it; then ThreadSanitizer (preset tsan)
# over the multi-threaded tests. Usage: scripts/sanitize.sh [asan-ubsan|tsan|all]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
which=${1:-all}
run() {
  local preset=$1
  cmake --preset "$preset" > /dev/null
  if ! cmake --build --preset "$preset" -j "$(nproc 2>/dev/null || echo 2)" > "build-$preset.log" 2>&1; then
    grep -E -A5 'error' "build-$preset.log" | head -60 >&2
    exit 1
  fi
  ctest --preset "$preset" -j "$(nproc 2>/dev/null || echo 2)"
}
case "$which" in
  asan-ubsan|tsan) run "$which" ;;
  all) run asan-ubsan; run tsan ;;
  *) echo "usage: scripts/sanitize.sh [asan-ubsan|tsan|all]" >&2; exit 2 ;;
esac
