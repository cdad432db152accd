#!/usr/bin/env bash
# Regenerates plots/: the lobe diagram and the receptance plot of every config
# in configs/, the semi-discretisation lobes and stability map of the milling
# configs, the method comparison of case A and case C (case C also with the
# time-domain solver), and time-domain
# simulations of case C (chatter and stable) and case A, each with its
# gnuplot script (.gp) and data (.dat) beside it.
# Usage: bash scripts/render_plots.sh   (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/chatter ] || bash scripts/build.sh
mkdir -p plots
for cfg in configs/*.toml; do
  stem=$(basename "$cfg" .toml)
  [[ $stem == grinding_* ]] && continue  # grinding configs: below
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
# Milling: the Floquet stability map (spectral radius, Hopf and flip parts of
# the boundary), on an 80 rev/min x 0.1 mm grid (a smaller .dat than the default).
for cfg in configs/milling_*.toml; do
  stem=$(basename "$cfg" .toml)
  ./build/chatter map "$cfg" --quiet --rpm-points 251 --depth-points 101 --out /dev/null \
    --plot "plots/${stem}_map.png" > /dev/null
  echo "plots/${stem}_map.png"
done
# Every method's limit on one chart: the seed turning case (all agree) and the
# milling benchmark (sdm's flip lobes).
for stem in seed_turning_1dof milling_benchmark_ae005_down; do
  ./build/chatter compare "configs/${stem}.toml" --quiet --table "plots/${stem}_compare.csv" \
    --plot "plots/${stem}_compare.png" > /dev/null
  echo "plots/${stem}_compare.png"
done
# The turning insert (docs/turning_inserts.md): lead angle and nose radius,
# analytic, coupled and sdm on one chart (they agree).
./build/chatter compare configs/turning_insert_lead_angle.toml --methods analytic,coupled,sdm --quiet \
  --table plots/turning_insert_lead_angle_compare.csv --plot plots/turning_insert_lead_angle_compare.png > /dev/null
echo "plots/turning_insert_lead_angle_compare.png"
# Case C by all four methods, the simulation included (81 speeds: about 20 s
# on 2 cores): time-domain follows sdm into the flip lobe the transfer-function
# methods miss.
./build/chatter compare configs/milling_benchmark_ae005_down.toml --methods all --rpm-points 81 --quiet \
  --table plots/milling_benchmark_ae005_down_compare_all.csv \
  --plot plots/milling_benchmark_ae005_down_compare_all.png > /dev/null
echo "plots/milling_benchmark_ae005_down_compare_all.png"
# Time-domain simulations: case C in its flip lobe (chatter, the tool leaves
# the cut, 1.5 x tooth passing) and just below its limit at 20 000 rev/min
# (stable forced vibration), case A below its limit (decaying transient).
./build/chatter simulate configs/milling_benchmark_ae005_down.toml --rpm 17000 --depth-mm 3.6 \
  --multiple-regeneration --plot plots/milling_benchmark_ae005_down_simulate_chatter.png > /dev/null
./build/chatter simulate configs/milling_benchmark_ae005_down.toml --rpm 20000 --depth-mm 2.0 \
  --plot plots/milling_benchmark_ae005_down_simulate_stable.png > /dev/null
./build/chatter simulate configs/seed_turning_1dof.toml --rpm 3000 --depth-mm 2.0 \
  --plot plots/seed_turning_1dof_simulate.png > /dev/null
echo "plots/*_simulate*.png"
# Position-dependent structure (docs/position.md): the lobe surface along the
# cantilever shaft of case B 1 (analytic) and along case C's tool path (sdm,
# 20 positions x 200 speeds: a few seconds).
./build/chatter surface configs/coupled_tool1_workpiece1.toml --position-points 50 --rpm-points 200 --quiet \
  --table plots/coupled_tool1_workpiece1_surface.csv --plot plots/coupled_tool1_workpiece1_surface.png > /dev/null
./build/chatter surface configs/milling_case_c_positions.toml --method sdm --position-points 20 --rpm-points 200 --quiet \
  --table plots/milling_case_c_positions_surface.csv --plot plots/milling_case_c_positions_surface.png > /dev/null
echo "plots/*_surface.png"
# Uncertain modes and K_f (docs/uncertainty.md): probability of stability and
# the 5/50/95 % lobes from 1 000 samples (seed 1).
./build/chatter lobes configs/seed_turning_1dof_uncertain.toml --samples 1000 --quiet \
  --table plots/seed_turning_1dof_uncertain_samples.csv \
  --probability-table plots/seed_turning_1dof_uncertain_probability.csv \
  --plot plots/seed_turning_1dof_uncertain_samples.png > /dev/null
echo "plots/seed_turning_1dof_uncertain_samples.png"
# Grinding (docs/grinding.md): seed 001's sweep against power at three feeds,
# its simulated last turns, and the fit of seed 000's printed tests.
./build/chatter grind sweep configs/grinding_scompi_ch4.toml --power-w-min 250 --power-w-max 2500 \
  --feed-mm-per-s-list 40,60,80 --table plots/grinding_scompi_ch4_sweep.csv --plot plots/grinding_scompi_ch4_sweep.png \
  2> /dev/null > /dev/null
./build/chatter grind simulate configs/grinding_scompi_ch4.toml --power-w 1000 \
  --plot plots/grinding_scompi_ch4_simulate.png > /dev/null
./build/chatter grind fit examples/grinding/underwater_tests_seed000.csv --model poly11 \
  --plot plots/grinding_underwater_seed000_fit.png > /dev/null 2>&1
echo "plots/grinding_scompi_ch4_sweep.png plots/grinding_scompi_ch4_simulate.png plots/grinding_underwater_seed000_fit.png"
# Forced vibration and surface location error (docs/forced.md): case C as a
# finishing pass (0.5 mm radial on a 10 mm cutter = its a_e/D 0.05, 2 mm
# axial, 0.05 mm per tooth) and the same pass with the mode along X and Y
# (examples/forced/case_c_xy.toml); the SLE against speed under the lobes;
# the shipped variable-pitch cutter, whose teeth leave the cut; the
# diametral error along the cantilever shaft of case B.
./build/chatter forced configs/milling_benchmark_ae005_down.toml --rpm 14000 --depth-mm 2 --feed-per-tooth-mm 0.05 \
  --plot plots/milling_benchmark_ae005_down_forced.png > /dev/null
./build/chatter forced examples/forced/case_c_xy.toml --rpm 14000 --depth-mm 2 --plot plots/case_c_xy_forced.png \
  > /dev/null
./build/chatter sle configs/milling_benchmark_ae005_down.toml --depth-mm 2 --feed-per-tooth-mm 0.05 --rpm-points 201 \
  --quiet --table plots/milling_benchmark_ae005_down_sle.csv --plot plots/milling_benchmark_ae005_down_sle.png > /dev/null
./build/chatter sle examples/forced/case_c_xy.toml --depth-mm 2 --rpm-points 201 --quiet \
  --table plots/case_c_xy_sle.csv --plot plots/case_c_xy_sle.png > /dev/null
./build/chatter forced configs/milling_variable_pitch_helix.toml --rpm 9000 --depth-mm 2 \
  --plot plots/milling_variable_pitch_helix_forced.png > /dev/null
./build/chatter forced configs/coupled_tool1_workpiece1.toml --along-shaft --depth-mm 1 --feed-mm-per-rev 0.2 \
  --table plots/coupled_tool1_workpiece1_diametral.csv --plot plots/coupled_tool1_workpiece1_diametral.png > /dev/null
echo "plots/*_forced.png plots/*_sle.png plots/coupled_tool1_workpiece1_diametral.png"
# Variable-pitch design (docs/design_pitch.md): the 4-flute example over the
# band around its equal-pitch lobe bottom, equal vs designed pitch.
./build/chatter design-pitch configs/milling_pitch_design_4flute.toml --rpm-min 6600 --rpm-max 8000 --teeth 4 --quiet \
  --table plots/milling_pitch_design_4flute_pitch.csv --plot plots/milling_pitch_design_4flute_pitch.png > /dev/null
echo "plots/milling_pitch_design_4flute_pitch.png"
# A whole NC program (docs/program.md, "Worked examples"): the shaft whose
# free end chatters, the pocket whose corners overload the spindle. Exit 3
# is their verdict (a block unstable or overloaded), not a failure.
for job in shaft pocket; do
  rc=0
  ./build/chatter program "examples/program/${job}.ngc" --config "examples/program/${job}_job.toml" \
    --plot "plots/program_${job}.png" > /dev/null || rc=$?
  [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || exit "$rc"
done
echo "plots/program_shaft.png plots/program_pocket.png"
