#!/usr/bin/env bash
# Installs the built tree into a temporary prefix, then builds and runs
# (1) examples/consumer with find_package(chatter CONFIG), shared and static;
# (2) its consumer_core against chatter::core alone: the kernels link without
#     the io layer, and no toml++ / JSON / plot code is in the binary;
# (3) examples/c_consumer.c with the flags pkg-config gives, and
#     examples/consumer/core_main.cpp with those of chatter-core.pc.
# Usage: install_consumer.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cmake -S "$src/examples/consumer" -B "$tmp/consumer" -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/consumer" -j 2 >/dev/null
cfg="$src/configs/seed_turning_1dof.toml"
out=$("$tmp/consumer/consumer" "$cfg")
echo "$out"
grep -q "1200 rev/min, 1.00 mm: stable" <<<"$out"
grep -q "1200 rev/min, 1.50 mm: CHATTER" <<<"$out"
"$tmp/consumer/consumer_static" "$cfg" | grep -q "1800 rev/min, 2.50 mm: stable"
core=$("$tmp/consumer/consumer_core")
echo "$core"
grep -q "absolute limit 1.2783 mm (closed form 1.2783 mm)" <<<"$core"
if nm -C "$tmp/consumer/consumer_core" | grep -E -m3 'toml::|nlohmann::|chatter::(load_config|plot_|write_)'; then
  echo "consumer_core holds io-layer code (above): chatter::core must not need it" >&2
  exit 1
fi
libdir=$(ls -d "$tmp"/prefix/lib*/ | head -n1)
export PKG_CONFIG_PATH="$libdir/pkgconfig"
cc "$src/examples/c_consumer.c" $(pkg-config --cflags --libs chatter) -o "$tmp/c_consumer"
LD_LIBRARY_PATH="$libdir" "$tmp/c_consumer" "$cfg" | tee /dev/stderr | grep -q "depth limit is 2.97"
# The kernels alone through pkg-config (chatter-core.pc): static, no io layer.
c++ -std=c++20 "$src/examples/consumer/core_main.cpp" $(pkg-config --cflags --libs chatter-core) -o "$tmp/core_pc"
"$tmp/core_pc" | grep -q "absolute limit 1.2783 mm (closed form 1.2783 mm)"
echo "installed-tree consumers: ok"
