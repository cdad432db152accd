// Speed of the `sdm` solver on real cutters (issue 16, docs/sdm.md "Real
// cutters"):
//  - 4 teeth, variable pitch (70/110/70/110°), two modes (X 922 Hz, Y 1150 Hz),
//    a_e/D = 0.5 down, 200 speeds over 5 000–25 000 rev/min: target <= 1 s;
//  - 2 teeth, 30° helix, case C geometry (a_e/D = 0.05 down, tool 10 mm),
//    200 speeds over 5 000–25 000 rev/min: target <= 1 s;
//  - for comparison, the straight uniform case C (the tooth-period path).
// Run: ./build/bench/bench_sdm_cutters --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <numbers>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/semi_discretization.hpp"

namespace {

using namespace chatter;
constexpr double kDeg = std::numbers::pi / 180.0;

StructuralModel case_c() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  return m;
}
StructuralModel two_mode() {
  StructuralModel m = case_c();
  m.tool.modes.push_back(Mode::from_mass(1150.0, 0.015, 0.05, {0.0, 1.0}));
  return m;
}
MillingParameters cutter(int teeth, double immersion) {
  MillingParameters mp;
  mp.teeth = teeth;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 2e8;
  mp.radial_immersion = immersion;
  mp.direction = MillingDirection::kDown;
  return mp;
}

void run(benchmark::State& state, const StructuralModel& model, const Process& p) {
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.01;
  const SemiDiscretizationSolver solver(model, p, o);
  const auto speeds = evenly_spaced_speeds(5000.0, 25000.0, 200);
  int bounded = 0;
  for (auto _ : state) {
    auto rows = lobe_envelope(solver, speeds);
    benchmark::DoNotOptimize(rows.data());
    bounded = 0;
    for (const auto& r : rows) bounded += r.bounded();
  }
  state.counters["bounded_speeds"] = bounded;
}

void BM_VariablePitch4Teeth2Modes_200Speeds(benchmark::State& state) {
  MillingParameters mp = cutter(4, 0.5);
  mp.pitch_angles_rad = {70 * kDeg, 110 * kDeg, 70 * kDeg, 110 * kDeg};
  run(state, two_mode(), Process::milling(mp));
}
BENCHMARK(BM_VariablePitch4Teeth2Modes_200Speeds)->Unit(benchmark::kMillisecond);

void BM_Helix30CaseC_200Speeds(benchmark::State& state) {
  MillingParameters mp = cutter(2, 0.05);
  mp.tool_diameter_m = 0.010;
  mp.helix_angles_rad = {30 * kDeg};
  run(state, case_c(), Process::milling(mp));
}
BENCHMARK(BM_Helix30CaseC_200Speeds)->Unit(benchmark::kMillisecond);

void BM_StraightCaseC_200Speeds(benchmark::State& state) { run(state, case_c(), Process::milling(cutter(2, 0.05))); }
BENCHMARK(BM_StraightCaseC_200Speeds)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
