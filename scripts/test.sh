#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to a full test run: installs what
# is missing, builds, runs every test with ctest. Exit status non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
