// Speed of the lobe surface (issue 20: analytic surface, 50 positions x 200
// speeds, target <= 0.5 s on one core). Case B 1 (docs/physics.md §7): the
// tool mode and the cantilever workpiece bar L = 0.5 m, D = 0.12 m, scaled
// by its first mode shape from the clamp (0) to the free end (0.5 m).
// ./build/bench/bench_position --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "chatter/position.hpp"
#include "chatter/solvers.hpp"

namespace {

using namespace chatter;

constexpr double kKf = 684e6;  // case B feed-force coefficient, N/m²

void BM_AnalyticSurface50x200(benchmark::State& state) {
  StructuralModel base;
  base.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1.0, 0.0}));
  CantileverBar bar{180e9, 7600.0, 0.5, 0.12};
  base.workpiece.modes.push_back(first_bending_mode(bar, 0.025, {1.0, 0.0}));
  PositionDependence dep;
  dep.cantilever.push_back({0, bar.length_m});
  const auto positions = evenly_spaced_positions(0.0, bar.length_m, 50);
  const auto speeds = evenly_spaced_speeds(500.0, 10000.0, 200);
  const Process process = Process::turning({kKf});
  const SolverFactory make = [&](const StructuralModel& m) {
    return make_lobe_solver("analytic", m, process, 0.02, {});
  };
  for (auto _ : state) {
    auto rows = lobe_surface(base, dep, positions, speeds, make, 1);
    benchmark::DoNotOptimize(rows.data());
  }
  state.counters["solves"] = static_cast<double>(positions.size() * speeds.size());
}
BENCHMARK(BM_AnalyticSurface50x200)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
