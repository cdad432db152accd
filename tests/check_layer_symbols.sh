#!/usr/bin/env bash
# The layer rules on the built libraries (docs/architecture.md): every
# function a layer's archive calls that one of the project's archives
# defines must be defined in that layer or a layer it may use:
#   core    -> core
#   io      -> core, io
#   ops     -> core, ops            (no io: the operations take plain data)
#   records -> core, io, ops, records
#   capi    -> everything above
# check_layers.sh checks the #include lines; this checks the calls, which an
# include rule cannot see (a declaration copied by hand, a header classified
# in the wrong layer). Usage: check_layer_symbols.sh CORE.a IO.a OPS.a RECORDS.a CAPI.a
set -uo pipefail
if [[ $# -ne 5 ]]; then
  echo "usage: check_layer_symbols.sh CORE.a IO.a OPS.a RECORDS.a CAPI.a" >&2
  exit 2
fi
names=(core io ops records capi)
declare -A lib=([core]=$1 [io]=$2 [ops]=$3 [records]=$4 [capi]=$5)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for n in "${names[@]}"; do
  [[ -f ${lib[$n]} ]] || { echo "no archive ${lib[$n]}" >&2; exit 2; }
  # Defined (any section, weak included) and undefined symbols, mangled.
  nm --defined-only "${lib[$n]}" 2>/dev/null | awk 'NF == 3 {print $3}' | sort -u > "$tmp/$n.def"
  nm --undefined-only "${lib[$n]}" 2>/dev/null | awk '{print $NF}' | grep -v ':$' | sort -u > "$tmp/$n.und"
done
allowed() {
  case $1 in
    core) echo core ;;
    io) echo core io ;;
    ops) echo core ops ;;
    records) echo core io ops records ;;
    capi) echo core io ops records capi ;;
  esac
}
bad=0
for n in "${names[@]}"; do
  cat $(for a in $(allowed "$n"); do echo "$tmp/$a.def"; done) | sort -u > "$tmp/allowed"
  for other in "${names[@]}"; do
    grep -qw "$other" <<< "$(allowed "$n")" && continue
    # Called by n, defined in a layer n may not use, and not in one it may.
    hits=$(comm -12 "$tmp/$n.und" "$tmp/$other.def" | comm -23 - "$tmp/allowed")
    if [[ -n $hits ]]; then
      echo "$n calls $other:"
      c++filt <<< "$hits" | sed 's/^/  /'
      bad=1
    fi
  done
done
if [[ $bad -ne 0 ]]; then
  echo "layer rules broken (docs/architecture.md)"
  exit 1
fi
echo "layer call rules: ok (core, io, ops, records, capi)"
