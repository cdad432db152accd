// Speed of the general per-speed search of `analytic` (real cutters, issue
// 16): 4 teeth with variable pitch on 2 oblique modes, 200 speeds; the same
// cutter with equal pitch on the phase search for comparison; a variable
// helix; process damping in turning at low speed (many vibration cycles per
// revolution).
#include <benchmark/benchmark.h>

#include <numbers>
#include <vector>

#include "chatter/transfer_function.hpp"

namespace {

using namespace chatter;

StructuralModel two_modes() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(600.0, 0.02, 0.2, {1.0, 0.3}));
  m.tool.modes.push_back(Mode::from_mass(750.0, 0.03, 0.25, {-0.2, 1.0}));
  return m;
}

Process four_teeth(double d) {
  MillingParameters p;
  p.teeth = 4;
  p.tangential_coefficient_n_per_m2 = 6e8;
  p.radial_coefficient_n_per_m2 = 2e8;
  p.radial_immersion = 0.5;
  p.direction = MillingDirection::kUp;
  if (d != 0.0)
    for (int j = 0; j < 4; ++j) p.pitch_angles_rad.push_back(std::numbers::pi / 2 + (j % 2 == 0 ? d : -d));
  return Process::milling(p);
}

TransferFunctionOptions options(double depth_max_m) {
  TransferFunctionOptions o;
  o.depth_max_m = depth_max_m;
  return o;
}

void run(benchmark::State& state, const AnalyticSolver& solver, const std::vector<double>& speeds) {
  for (auto _ : state) {
    auto rows = lobe_envelope(solver, speeds);
    benchmark::DoNotOptimize(rows.data());
  }
  state.counters["base_grid"] = static_cast<double>(solver.band().grid_points);
}

// 4 teeth, pitches 90° ± 11.5°, 2 modes, 200 speeds 2 000–14 000 rev/min.
void BM_VariablePitch4Teeth2Modes200Speeds(benchmark::State& state) {
  const AnalyticSolver solver(two_modes(), four_teeth(0.2), options(0.02));
  run(state, solver, evenly_spaced_speeds(2000.0, 14000.0, 200));
}
BENCHMARK(BM_VariablePitch4Teeth2Modes200Speeds)->Unit(benchmark::kMillisecond);

// The same cutter with equal pitch: the phase search of the uniform cutter.
void BM_EqualPitch4Teeth2Modes200Speeds(benchmark::State& state) {
  const AnalyticSolver solver(two_modes(), four_teeth(0.0), options(0.02));
  run(state, solver, evenly_spaced_speeds(2000.0, 14000.0, 200));
}
BENCHMARK(BM_EqualPitch4Teeth2Modes200Speeds)->Unit(benchmark::kMillisecond);

// Variable helix 30°/35° alternating, equal pitch, D = 12 mm: the depth
// iteration (a few per-speed searches per speed).
void BM_VariableHelix4Teeth2Modes200Speeds(benchmark::State& state) {
  MillingParameters p;
  p.teeth = 4;
  p.tangential_coefficient_n_per_m2 = 6e8;
  p.radial_coefficient_n_per_m2 = 2e8;
  p.radial_immersion = 0.5;
  p.direction = MillingDirection::kUp;
  p.tool_diameter_m = 0.012;
  const double deg = std::numbers::pi / 180.0;
  p.helix_angles_rad = {30 * deg, 35 * deg, 30 * deg, 35 * deg};
  const AnalyticSolver solver(two_modes(), Process::milling(p), options(0.02));
  run(state, solver, evenly_spaced_speeds(2000.0, 14000.0, 200));
}
BENCHMARK(BM_VariableHelix4Teeth2Modes200Speeds)->Unit(benchmark::kMillisecond);

// Case A turning with process damping C_pd = 4e5 N/m, D_w = 0.1 m, 200
// speeds 50–1 000 rev/min (up to 113 vibration cycles per revolution).
void BM_ProcessDampingTurning200Speeds(benchmark::State& state) {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0}));
  TurningParameters t;
  t.feed_force_coefficient_n_per_m2 = 2.4e9;
  t.process_damping_coefficient_n_per_m = 4e5;
  t.workpiece_diameter_m = 0.1;
  const AnalyticSolver solver(m, Process::turning(t), options(0.05));
  run(state, solver, evenly_spaced_speeds(50.0, 1000.0, 200));
}
BENCHMARK(BM_ProcessDampingTurning200Speeds)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
