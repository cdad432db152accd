// Speed of the `sdm` solver on real cutters (issue 16, docs/sdm.md "Real
// cutters"):
//  - 4 teeth, variable pitch (70/110/70/110°), two modes (X 922 Hz, Y 1150 Hz),
//    a_e/D = 0.5 down, 200 speeds over 5 000–25 000 rev/min: target <= 1 s;
//  - 2 teeth, 30° helix, case C geometry (a_e/D = 0.05 down, tool 10 mm),
//    200 speeds over 5 000–25 000 rev/min: target <= 1 s;
//  - for comparison, the straight uniform case C (the tooth-period path);
//  - issue 45's cutter (examples/real_cutter/aluminium_slot_16mm_3flute.toml:
//    16 mm 3-flute 30° helix slotting aluminium, two modes per direction),
//    200 speeds over the machine's range 500–24 000 rev/min, with the
//    default (collocation, 3 nodes at 4 steps) and the first-order steps:
//    target <= 0.3 s.
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

void run(benchmark::State& state, const StructuralModel& model, const Process& p, double rpm_min = 5000.0,
         double rpm_max = 25000.0, int collocation = kAutoCollocation, double depth_max_m = 0.01) {
  SemiDiscretizationOptions o;
  o.depth_max_m = depth_max_m;
  o.collocation_nodes = collocation;
  const SemiDiscretizationSolver solver(model, p, o);
  const auto speeds = evenly_spaced_speeds(rpm_min, rpm_max, 200);
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

StructuralModel issue45_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(650.0, 0.03, 12e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(1900.0, 0.02, 25e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(670.0, 0.03, 13e6, {0.0, 1.0}));
  m.tool.modes.push_back(Mode::from_stiffness(2000.0, 0.02, 28e6, {0.0, 1.0}));
  return m;
}
Process issue45_cutter() {
  MillingParameters mp;
  mp.teeth = 3;
  mp.tangential_coefficient_n_per_m2 = 700e6;
  mp.radial_coefficient_n_per_m2 = 210e6;
  mp.radial_immersion = 1.0;
  mp.direction = MillingDirection::kDown;
  mp.tool_diameter_m = 16e-3;
  mp.helix_angles_rad = {30 * kDeg};
  return Process::milling(mp);
}
void BM_EndMill16mm3FluteSlot_500To24000_Default(benchmark::State& state) {
  run(state, issue45_tool(), issue45_cutter(), 500.0, 24000.0, kAutoCollocation, 0.02);
}
BENCHMARK(BM_EndMill16mm3FluteSlot_500To24000_Default)->Unit(benchmark::kMillisecond);
void BM_EndMill16mm3FluteSlot_500To24000_FirstOrder(benchmark::State& state) {
  run(state, issue45_tool(), issue45_cutter(), 500.0, 24000.0, 0, 0.02);
}
BENCHMARK(BM_EndMill16mm3FluteSlot_500To24000_FirstOrder)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
