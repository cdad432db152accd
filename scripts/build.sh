#!/usr/bin/env bash
# Configures and builds chatter (Release) in build/, quietly unless something
# goes wrong. Usage: scripts/build.sh [extra cmake args]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
mkdir -p build
if ! cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" > build/configure.log 2>&1; then
  cat build/configure.log >&2
  exit 1
fi
if ! cmake --build build -j "$jobs" > build/build.log 2>&1; then
  grep -E -A5 'error' build/build.log | head -80 >&2 || true
  tail -n 20 build/build.log >&2
  exit 1
fi
grep -E 'warning:' build/build.log | head -20 >&2 || true
