// Speed of the lobe surface (issue 20: analytic surface, 50 positions x 200
// speeds, target <= 0.5 s on one core). Case B 1 (docs/physics.md §7): the
// tool mode and the cantilever workpiece bar L = 0.5 m, D = 0.12 m, scaled
// by its first mode shape from the clamp (0) to the free end (0.5 m).
// And the sdm surface of case C geometry (docs/physics.md §7, a_e/D = 0.05
// down, 2 teeth) with the tool mode of configs/milling_case_c_positions.toml
// along the path (922 -> 860 -> 780 Hz over 0-120 mm), 20 positions x 200
// speeds 5 000-25 000 rev/min, depth <= 10 mm: target <= 20 s on 2 cores
// (threads = 2; wall time).
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

// Argument: threads.
void BM_SdmSurfaceCaseC20x200(benchmark::State& state) {
  StructuralModel base;
  PositionDependence dep;
  // (position m, frequency Hz, damping ratio, stiffness N/m): the config's stations.
  const double stations[3][4] = {{0.0, 922.0, 0.011, 1.340e6}, {0.06, 860.0, 0.012, 1.10e6}, {0.12, 780.0, 0.014, 0.85e6}};
  for (const auto& st : stations) {
    PositionStation s;
    s.position_m = st[0];
    s.model.tool.modes.push_back(Mode::from_stiffness(st[1], st[2], st[3], {1.0, 0.0}));
    dep.stations.push_back(s);
  }
  base = dep.stations.front().model;
  const auto positions = evenly_spaced_positions(0.0, 0.12, 20);
  const auto speeds = evenly_spaced_speeds(5000.0, 25000.0, 200);
  const Process process = Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kDown});
  const SolverFactory make = [&](const StructuralModel& m) { return make_lobe_solver("sdm", m, process, 0.01, {}); };
  const auto threads = static_cast<unsigned>(state.range(0));
  std::size_t bounded = 0;
  for (auto _ : state) {
    auto rows = lobe_surface(base, dep, positions, speeds, make, threads);
    benchmark::DoNotOptimize(rows.data());
    bounded = 0;
    for (const auto& row : rows)
      for (const auto& r : row) bounded += r.bounded();
  }
  state.counters["solves"] = static_cast<double>(positions.size() * speeds.size());
  state.counters["bounded"] = static_cast<double>(bounded);
}
BENCHMARK(BM_SdmSurfaceCaseC20x200)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
