// Speed of the transfer-function solvers (issue: exact envelope at 1 000
// spindle speeds for a 3-mode turning model, target < 20 ms on one core).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "chatter/transfer_function.hpp"

namespace {

using namespace chatter;

// Three modes on two bodies, one of them oblique, so both the rank-one
// (turning) path and general receptances are exercised.
StructuralModel three_mode_model() {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0}));  // docs/physics.md case A
  m.tool.modes.push_back(Mode::from_stiffness(150.0, 0.03, 30e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(420.0, 0.02, 60e6,
                                              {std::cos(std::numbers::pi / 6), std::sin(std::numbers::pi / 6)}));
  return m;
}

TransferFunctionOptions options() {
  TransferFunctionOptions o;
  o.depth_max_m = 0.02;
  return o;
}

template <class Solver>
void BM_Envelope1000Speeds(benchmark::State& state) {
  const Solver solver(three_mode_model(), Process::turning({2.4e9}), options());
  const auto speeds = evenly_spaced_speeds(200.0, 6000.0, 1000);
  for (auto _ : state) {
    auto rows = lobe_envelope(solver, speeds);
    benchmark::DoNotOptimize(rows.data());
  }
  state.counters["grid_points"] = static_cast<double>(solver.band().grid_points);
}
BENCHMARK(BM_Envelope1000Speeds<AnalyticSolver>)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Envelope1000Speeds<CoupledSolver>)->Unit(benchmark::kMillisecond);

template <class Solver>
void BM_Construct(benchmark::State& state) {
  const auto model = three_mode_model();
  for (auto _ : state) {
    Solver solver(model, Process::turning({2.4e9}), options());
    benchmark::DoNotOptimize(&solver);
  }
}
BENCHMARK(BM_Construct<AnalyticSolver>)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Construct<CoupledSolver>)->Unit(benchmark::kMillisecond);

// Whole job as the CLI runs it: construction + 1 000 speeds.
void BM_ConstructAndEnvelope(benchmark::State& state) {
  const auto model = three_mode_model();
  const auto speeds = evenly_spaced_speeds(200.0, 6000.0, 1000);
  for (auto _ : state) {
    AnalyticSolver solver(model, Process::turning({2.4e9}), options());
    auto rows = lobe_envelope(solver, speeds);
    benchmark::DoNotOptimize(rows.data());
  }
}
BENCHMARK(BM_ConstructAndEnvelope)->Unit(benchmark::kMillisecond);

// The absolute limit (lowest depth over all speeds): the maximiser of
// PhaseSearch::minimum_depth on a built solver.
void BM_AbsoluteLimit(benchmark::State& state) {
  const AnalyticSolver solver(three_mode_model(), Process::turning({2.4e9}), options());
  for (auto _ : state) {
    const AbsoluteLimit a = solver.absolute_limit();
    benchmark::DoNotOptimize(a.depth_m);
  }
}
BENCHMARK(BM_AbsoluteLimit)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
