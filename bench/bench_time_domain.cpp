// Speed of the time-domain simulator (issue 4): one simulation of case C
// (a_e/D = 0.05 down, 2 teeth, 922 Hz), 200 tooth periods, default tolerance
// (rtol 1e-7): target under 50 ms on one core. Counters: integrator steps,
// right-hand-side evaluations, restarts (stop points) and root stops per run.
// Also one depth limit by simulation (lobes --method time-domain, per speed).
// Real cutters (issue 16): case C with a 10 mm cutter and a 30° helix on 20
// axial slices, 200 tooth periods: target under 100 ms.
// Lobes by simulation of a real cutter (issue 27): one depth limit per speed
// on the issue's 4-flute variable-pitch (85/95°) 30° helix 12 mm cutter,
// modes 1 150 / 1 230 Hz, 12 / 14 N/µm, ζ 0.02, half immersion climb, at
// 6 000 … 16 000 rev/min: target 0.3 s per speed on one core.
// Run: ./build/bench/bench_time_domain --benchmark_repetitions=5
// (figures in docs/performance.md).
#include <benchmark/benchmark.h>

#include "chatter/time_domain.hpp"

namespace {

using namespace chatter;

StructuralModel case_c() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  return m;
}
Process case_c_process() { return Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kDown}); }

Process case_c_helix(double helix_deg) {
  MillingParameters p{2, 6e8, 2e8, 0.05, MillingDirection::kDown};
  p.tool_diameter_m = 0.01;
  p.helix_angles_rad = {helix_deg * 3.14159265358979323846 / 180.0};
  return Process::milling(p);
}

void run(benchmark::State& state, double rpm, double depth_m, bool linear, bool multiple,
         const Process& process = case_c_process(), int slices = 0) {
  TimeDomainOptions o;
  o.axial_slices = slices;
  TimeDomainSimulator sim(case_c(), process, o);
  SimulationSettings s;
  s.spindle_rpm = rpm;
  s.depth_m = depth_m;
  s.periods = 200;
  s.linear = linear;
  s.multiple_regeneration = multiple;
  s.record_series = false;
  SimulationResult r;
  for (auto _ : state) {
    r = sim.simulate(s);
    benchmark::DoNotOptimize(r.growth_per_period);
  }
  state.counters["steps"] = static_cast<double>(r.steps);
  state.counters["rhs_evals"] = static_cast<double>(r.rhs_evaluations);
  state.counters["restarts"] = static_cast<double>(r.restarts);
  state.counters["root_stops"] = static_cast<double>(r.root_stops);
  state.counters["chatter"] = r.verdict == SimulationVerdict::kChatter ? 1 : 0;
}

// Stable forced vibration (Hopf region, 0.9 x the sdm limit).
void BM_CaseC_Stable_20000rpm(benchmark::State& st) { run(st, 20000, 2.07e-3, false, false); }
// Flip-lobe chatter, the tool leaves the cut (root stops).
void BM_CaseC_FlipChatter_17000rpm(benchmark::State& st) { run(st, 17000, 3.67e-3, false, false); }
// Same with multiple regeneration.
void BM_CaseC_FlipChatter_Multiple_17000rpm(benchmark::State& st) { run(st, 17000, 3.67e-3, false, true); }
// Linear mode (growth factor vs sdm).
void BM_CaseC_Linear_10000rpm(benchmark::State& st) { run(st, 10000, 3.7e-3, true, false); }

// Helix 30°, 20 slices (the default), 200 tooth periods: stable forced
// vibration, chatter (the slices leave the cut: clipped, no roots), linear.
void BM_CaseC_Helix20_Stable_20000rpm(benchmark::State& st) { run(st, 20000, 2e-3, false, false, case_c_helix(30)); }
void BM_CaseC_Helix20_Chatter_10000rpm(benchmark::State& st) { run(st, 10000, 8e-3, false, false, case_c_helix(30)); }
void BM_CaseC_Helix20_Linear_10000rpm(benchmark::State& st) { run(st, 10000, 6e-3, true, false, case_c_helix(30)); }
// Where the time goes: the same stable run on 1 and 80 slices.
void BM_CaseC_Helix1_Stable_20000rpm(benchmark::State& st) { run(st, 20000, 2e-3, false, false, case_c_helix(30), 1); }
void BM_CaseC_Helix80_Stable_20000rpm(benchmark::State& st) { run(st, 20000, 2e-3, false, false, case_c_helix(30), 80); }

void BM_CaseC_LimitAt_20000rpm(benchmark::State& state) {
  TimeDomainSolver td(case_c(), case_c_process());
  for (auto _ : state) benchmark::DoNotOptimize(td.limit_at(SpindleSpeed(20000)).depth_limit_m);
}

StructuralModel issue27_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(1150.0, 0.02, 12e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(1230.0, 0.02, 14e6, {0.0, 1.0}));
  return m;
}
Process issue27_cutter() {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  MillingParameters p{4, 6e8, 1.8e8, 0.5, MillingDirection::kDown};
  p.tool_diameter_m = 0.012;
  p.helix_angles_rad = {30.0 * kDeg};
  p.pitch_angles_rad = {85.0 * kDeg, 95.0 * kDeg, 85.0 * kDeg, 95.0 * kDeg};
  return Process::milling(p);
}

// One limit per speed, the speed given in the argument (rev/min): what
// `chatter lobes --method time-domain` spends per row on one core.
void BM_VariablePitchHelix_LimitAt(benchmark::State& state) {
  TimeDomainSolver td(issue27_tool(), issue27_cutter());
  for (auto _ : state) benchmark::DoNotOptimize(td.limit_at(SpindleSpeed(static_cast<double>(state.range(0)))).depth_limit_m);
}

BENCHMARK(BM_CaseC_Stable_20000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_FlipChatter_17000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_FlipChatter_Multiple_17000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_Linear_10000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_LimitAt_20000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_Helix20_Stable_20000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_Helix20_Chatter_10000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_Helix20_Linear_10000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_Helix1_Stable_20000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseC_Helix80_Stable_20000rpm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VariablePitchHelix_LimitAt)->Arg(8000)->Arg(10000)->Arg(12000)->Arg(14000)->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
