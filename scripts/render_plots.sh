#!/usr/bin/env bash
# Regenerates plots/: the lobe diagram and the receptance plot of every config
# in configs/, each with its gnuplot script (.gp) and data (.dat) beside it.
# Usage: bash scripts/render_plots.sh   (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/chatter ] || bash scripts/build.sh
mkdir -p plots
for cfg in configs/*.toml; do
  stem=$(basename "$cfg" .toml)
  ./build/chatter lobes "$cfg" --table "plots/${stem}_lobes.csv" --plot "plots/${stem}_lobes.png" > /dev/null
  ./build/chatter frf "$cfg" --out /dev/null --plot "plots/${stem}_frf.png" > /dev/null
  echo "plots/${stem}_lobes.png plots/${stem}_frf.png"
done
# Milling: the semi-discretisation lobes too (flip lobes), with the chatter frequency.
for cfg in configs/milling_*.toml; do
  stem=$(basename "$cfg" .toml)
  ./build/chatter lobes "$cfg" --method sdm --quiet --table "plots/${stem}_sdm_lobes.csv" \
    --plot "plots/${stem}_sdm_lobes.png" --plot-frequency > /dev/null
  echo "plots/${stem}_sdm_lobes.png"
done
