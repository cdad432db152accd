// Speed of the forced response (issue 27, docs/forced.md): one response of
// case C on the Fourier path (equal pitch) and of the issue-27 cutter on
// the periodic solve (85/95° pitch, 30° helix), each with its sdm verdict;
// an SLE sweep of 201 speeds on one thread.
// Run: ./build/bench/bench_forced --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// (figures in docs/performance.md).
#include <benchmark/benchmark.h>

#include "chatter/forced.hpp"
#include "chatter/lobes.hpp"

namespace {

using namespace chatter;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

StructuralModel case_c() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  return m;
}
Process case_c_process() { return Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kDown}); }

StructuralModel issue27_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(1150.0, 0.02, 12e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(1230.0, 0.02, 14e6, {0.0, 1.0}));
  return m;
}
Process issue27_cutter() {
  MillingParameters p{4, 6e8, 1.8e8, 0.5, MillingDirection::kDown};
  p.tool_diameter_m = 0.012;
  p.helix_angles_rad = {30.0 * kDeg};
  p.pitch_angles_rad = {85.0 * kDeg, 95.0 * kDeg, 85.0 * kDeg, 95.0 * kDeg};
  return Process::milling(p);
}

void BM_Forced_Fourier_CaseC(benchmark::State& state) {
  const ForcedResponseSolver s(case_c(), case_c_process());
  for (auto _ : state) benchmark::DoNotOptimize(s.response({14000.0, 2e-3, 0.05e-3, true}).surface_location_error_m);
}

void BM_Forced_PeriodicSolve_Issue27(benchmark::State& state) {
  const ForcedResponseSolver s(issue27_tool(), issue27_cutter());
  for (auto _ : state) benchmark::DoNotOptimize(s.response({12000.0, 1e-3, 0.05e-3, true}).surface_location_error_m);
}

void BM_Sle201_CaseC(benchmark::State& state) {
  const ForcedResponseSolver s(case_c(), case_c_process());
  const auto speeds = evenly_spaced_speeds(5000.0, 25000.0, 201);
  for (auto _ : state) benchmark::DoNotOptimize(sle_sweep(s, speeds, 2e-3, 0.05e-3, 1).size());
}

BENCHMARK(BM_Forced_Fourier_CaseC)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(BM_Forced_PeriodicSolve_Issue27)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(BM_Sle201_CaseC)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
