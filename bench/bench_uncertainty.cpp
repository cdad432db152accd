// Speed of the Monte Carlo over uncertain inputs (issue 20: 1 000 samples x
// 200 speeds, analytic, target <= 5 s). Case B 1 (docs/physics.md §7) at the
// free end: tool mode 100.66 Hz and the cantilever workpiece bar, K_f 684e6;
// spreads 1σ: frequency 3 %, damping 20 %, stiffness 5 %, K_f 5 %. The
// timed loop is the whole study: samples drawn, 200 000 solves, and the
// reduction to a 101-depth probability grid and 3 quantile lobes.
// ./build/bench/bench_uncertainty --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "chatter/solvers.hpp"
#include "chatter/uncertainty.hpp"

namespace {

using namespace chatter;

constexpr double kKf = 684e6;  // case B feed-force coefficient, N/m²

void BM_MonteCarloAnalytic1000x200(benchmark::State& state) {
  StructuralModel model;
  model.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1.0, 0.0}));
  const CantileverBar bar{180e9, 7600.0, 0.5, 0.12};
  model.workpiece.modes.push_back(first_bending_mode(bar, 0.025, {1.0, 0.0}));
  const Process process = Process::turning({kKf});
  const UncertaintySpreads spreads{{0.03}, {0.2}, {0.05}, 0.05, 0.0};
  const auto speeds = evenly_spaced_speeds(500.0, 10000.0, 200);
  const SampleSolverFactory make = [](const StructuralModel& m, const Process& p) {
    return make_lobe_solver("analytic", m, p, 0.02, {});
  };
  std::vector<double> depths(101);
  for (std::size_t d = 0; d < depths.size(); ++d) depths[d] = 0.01 * static_cast<double>(d) / 100.0;
  const auto threads = static_cast<unsigned>(state.range(0));
  for (auto _ : state) {
    const auto rows = monte_carlo_limits(model, process, spreads, 1, 0, 1000, speeds, make, threads);
    const UncertainLobes lobes = reduce_monte_carlo(rows, depths, {0.05, 0.5, 0.95});
    benchmark::DoNotOptimize(lobes.quantile_depth_m.data());
  }
  state.counters["solves"] = 1000.0 * static_cast<double>(speeds.size());
}
BENCHMARK(BM_MonteCarloAnalytic1000x200)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
