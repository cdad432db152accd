#!/usr/bin/env bash
# One command from a fresh Debian 12 machine to a lobe table: installs what is
# missing, builds, and computes the lobes of the seed turning case (docs/physics.md case A).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
mkdir -p out
./build/chatter lobes configs/seed_turning_1dof.toml --table out/seed_turning_1dof.csv --json out/seed_turning_1dof.json
