#!/usr/bin/env bash
# Fuzzes the config loader (and the analytic solver on what it accepts) with
# libFuzzer for a set time. Usage: scripts/fuzz.sh [seconds=60]
# Needs clang and its runtime (Debian: clang libclang-rt-14-dev); installs them if missing.
# New inputs that increase coverage go to build-fuzz/corpus/; a crash leaves
# crash-* files in build-fuzz/: copy each into fuzz/corpus/config/ and fix it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
if ! command -v clang++ >/dev/null || ! dpkg-query -W -f='${Status}' libclang-rt-14-dev 2>/dev/null | grep -q "ok installed"; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq clang libclang-rt-14-dev >/dev/null
fi
seconds=${1:-60}
mkdir -p build-fuzz/corpus
srcs="src/io/config.cpp src/model/structural_model.cpp src/model/process.cpp src/solvers/phase_search.cpp
      src/solvers/analytic.cpp src/solvers/coupled.cpp src/solvers/lobe_table.cpp fuzz/fuzz_config.cpp"
# shellcheck disable=SC2086
clang++ -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -Iinclude -Isrc/solvers -I/usr/include/eigen3 $srcs -ltomlplusplus -o build-fuzz/fuzz_config
cp -n fuzz/corpus/config/* build-fuzz/corpus/ 2>/dev/null || true
cd build-fuzz
./fuzz_config -max_total_time="$seconds" -max_len=4096 -timeout=10 -print_final_stats=1 corpus 2>&1 | tail -n 25
