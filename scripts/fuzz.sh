#!/usr/bin/env bash
# Fuzzes one parser with libFuzzer (+ ASan + UBSan) for a set time.
# Usage: scripts/fuzz.sh [TARGET=config] [seconds=60] [runs]
#   runs: stop after exactly this many executions (libFuzzer -runs), or at
#   `seconds`, whichever comes first. runs = 0: replay the target's whole
#   corpus (seeds and every input found so far) once, no new inputs.
# Environment:
#   FUZZ_SANITIZE=address,undefined (default) or undefined: the deep runs of
#     docs/reliability.md use `undefined` (UBSan only, ~1.5-2x the executions
#     per second), then replay everything they found with the default.
#   FUZZ_JOBS=2: parallel compiles.
#   FUZZ_TIMEOUT=10: seconds of wall time one input may take before libFuzzer
#     calls it a hang. The deep runs use 60: at nice 19 on a machine busy with
#     builds a 0.2 s input once took > 10 s of wall time (a false hang).
#   config      the TOML config loader, and the analytic solver on what it accepts (fuzz/fuzz_config.cpp)
#   frf         the FRF readers: CSV, tab .frf, UFF 58/58b (fuzz/fuzz_frf.cpp)
#   operations  the operations-file reader (fuzz/fuzz_operations.cpp)
#   shop        the shop-data readers: cutting-tests table, force series, CSV and
#               audio recordings, then the coefficient fit and the detector (fuzz/fuzz_shop.cpp)
#   fit         the modal fit on fuzzed FRF tables (fuzz/fuzz_fit.cpp)
#   logs        the grinding tests table (then its fits) and the adapt measurement log (fuzz/fuzz_logs.cpp)
#   program     JOB.toml and the interpreter's canonical-call log of chatter program (fuzz/fuzz_program.cpp)
# `scripts/fuzz.sh 300` (a number first) fuzzes the config loader for 300 s.
# Needs clang and its runtime (Debian: clang libclang-rt-14-dev); installs them if missing.
# Seeds: fuzz/corpus/TARGET/. New inputs that increase coverage go to
# build-fuzz/corpus/ (config) or build-fuzz/corpus-TARGET/; a crash leaves
# crash-* (config) or TARGET-crash-* files in build-fuzz/: copy each into
# fuzz/corpus/TARGET/ as crash_<what>.<ext> and fix it. The binary is
# build-fuzz/fuzz_TARGET_SANITIZERS (address-undefined or undefined), the whole
# libFuzzer log (the #N lines with cov/ft and exec/s) build-fuzz/fuzz_TARGET_SANITIZERS.log.
set -euo pipefail
cd "$(dirname "$0")/.."

target=config
if [ $# -gt 0 ] && ! [[ "$1" =~ ^[0-9]+$ ]]; then
  target=$1
  shift
fi
seconds=${1:-60}
runs=${2:--1}
libs=${libs:-}
target_flags=""  # one target's own defines (program: where the shipped tool configs are)
# The sources of a layer as CMakeLists.txt lists them (set(CHATTER_<L>_SOURCES
# ...) and list(APPEND CHATTER_<L>_SOURCES ...)), so the fuzz builds follow the
# library instead of a copied list that drifts.
layer_sources() {
  awk -v L="CHATTER_$1_SOURCES" '
    ($0 ~ "^set\\(" L "( |$)") || ($0 ~ "^list\\(APPEND " L "( |$)") { on = 1 }
    on { for (i = 1; i <= NF; i++) { s = $i; gsub(/[()]/, "", s); if (s ~ /^src\/.*\.cpp$/) print s } }
    on && !/^[[:space:]]*#/ && /\)/ { on = 0 }' CMakeLists.txt
}
case "$target" in
  config)
    srcs="$(layer_sources CORE) $(layer_sources IO)"
    libs="-lsundials_cvode -lsundials_nvecserial -lsndfile" max_len=4096 corpus=corpus prefix="" ;;
  frf)
    srcs="src/formats/frf_reader.cpp src/formats/frf_uff.cpp src/model/frf_data.cpp src/model/structural_model.cpp src/model/number_text.cpp"
    max_len=8192 corpus=corpus-frf prefix="frf-" ;;
  operations)
    srcs="$(layer_sources CORE) $(layer_sources OPS)"
    libs="-lsundials_cvode -lsundials_nvecserial" max_len=4096 corpus=corpus-operations prefix="operations-" ;;
  shop)
    srcs="src/formats/shop_io.cpp src/shop/coefficients.cpp src/shop/detect.cpp src/model/process.cpp src/model/process_profile.cpp src/model/process_integrals.cpp src/model/cutter_profile.cpp src/model/spindle_speed.cpp src/model/cutting/cutting_law.cpp src/model/cutting/turning_law.cpp src/model/cutting/milling_law.cpp src/model/cutting/kienzle.cpp src/model/number_text.cpp"
    libs="-lsndfile" max_len=8192 corpus=corpus-shop prefix="shop-" ;;
  fit)
    srcs="src/model/modal_fit.cpp src/model/frf_data.cpp src/model/structural_model.cpp src/model/number_text.cpp"
    max_len=512 corpus=corpus-fit prefix="fit-" ;;
  logs)
    srcs="$(layer_sources CORE) $(layer_sources IO)"
    libs="-lsundials_cvode -lsundials_nvecserial -lsndfile" max_len=8192 corpus=corpus-logs prefix="logs-" ;;
  program)
    srcs="$(layer_sources CORE) $(layer_sources IO)"
    libs="-lsundials_cvode -lsundials_nvecserial -lsndfile" max_len=16384 corpus=corpus-program prefix="program-"
    target_flags="-DCHATTER_SOURCE_DIR=\"$PWD\"" ;;
  *)
    echo "fuzz.sh: unknown target '$target' (config, frf, operations, shop, fit, logs or program)" >&2
    exit 2 ;;
esac
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "fuzz.sh: seconds must be a positive integer, got '$seconds'" >&2
  exit 2
fi

bash scripts/setup.sh
if ! command -v clang++ >/dev/null || ! dpkg-query -W -f='${Status}' libclang-rt-14-dev 2>/dev/null | grep -q "ok installed"; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq clang libclang-rt-14-dev >/dev/null
fi
sanitize=${FUZZ_SANITIZE:-address,undefined}
case "$sanitize" in
  address,undefined|undefined) ;;
  *) echo "fuzz.sh: FUZZ_SANITIZE must be 'address,undefined' or 'undefined', got '$sanitize'" >&2; exit 2 ;;
esac
tag=${sanitize//,/-}
# Objects are shared by the targets built from the same sources (config, logs
# and program all link CORE + IO) and rebuilt only when their source or a
# header they include (clang's -MMD list) is newer: a second target or a
# replay costs a link, not ~95 compiles.
case "$target" in
  config|logs|program) objdir="build-fuzz/obj-core-io-$tag" ;;
  *) objdir="build-fuzz/obj-$target-$tag" ;;
esac
mkdir -p "build-fuzz/$corpus" "$objdir"
# -O2 and EIGEN_NO_DEBUG: Eigen's range checks and un-inlined accessors were
# most of the modal fit's time; chatter's own assert()s stay on. Coverage is
# not traced in Eigen and the standard library (fuzz/coverage_ignorelist.txt).
flags=(-std=c++20 -O2 -g -DEIGEN_NO_DEBUG -DCHATTER_VERSION=\"fuzz\" "-fsanitize=fuzzer-no-link,$sanitize" -fno-sanitize-recover=undefined
       -fsanitize-coverage-ignorelist=fuzz/coverage_ignorelist.txt -Iinclude -Isrc/solvers -I/usr/include/eigen3 -MMD)
cc=clang++
command -v ccache >/dev/null && cc="ccache clang++"
# stale OBJECT: true when OBJECT is missing or older than anything its .d lists.
stale() {
  local obj=$1 dep="${1%.o}.d" f
  [ -f "$obj" ] && [ -f "$dep" ] || return 0
  for f in $(sed -e 's/^[^:]*://' -e 's/\\$//' "$dep"); do
    [ "$f" -nt "$obj" ] && return 0
  done
  return 1
}
objs=()
todo=()
for src in $srcs "fuzz/fuzz_$target.cpp"; do
  obj="$objdir/$(echo "$src" | tr / _).o"  # by path: model/ and grinding/ both hold a process.cpp
  objs+=("$obj")
  if stale "$obj"; then todo+=("$src"); fi
done
echo "fuzz.sh: ${#todo[@]} of ${#objs[@]} objects to compile in $objdir"
# The target's own file gets its defines (program: where the tool configs are).
compile() {
  local src=$1 extra=()
  if [ "$src" = "fuzz/fuzz_$target.cpp" ] && [ -n "$target_flags" ]; then extra=("$target_flags"); fi
  $cc "${flags[@]}" "${extra[@]}" -c "$src" -o "$objdir/$(echo "$src" | tr / _).o"
}
running=0
for src in "${todo[@]}"; do
  if [ "$running" -ge "${FUZZ_JOBS:-2}" ]; then wait -n; running=$((running - 1)); fi
  compile "$src" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do wait -n; running=$((running - 1)); done  # set -e: a failed compile stops here
# shellcheck disable=SC2086
clang++ "-fsanitize=fuzzer,$sanitize" "${objs[@]}" -ltomlplusplus $libs -o "build-fuzz/fuzz_${target}_$tag"
cp -n "fuzz/corpus/$target"/* "build-fuzz/$corpus/" 2>/dev/null || true
cd build-fuzz
"./fuzz_${target}_$tag" -max_total_time="$seconds" -runs="$runs" -max_len="$max_len" -timeout="${FUZZ_TIMEOUT:-10}" -print_final_stats=1 \
  -artifact_prefix="./$prefix" "$corpus" 2>&1 | tee "fuzz_${target}_$tag.log" | tail -n 25
