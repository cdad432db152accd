// Speed of the fast lobe-table queries (issue 6: at least 10⁵ queries per
// second on one core) and the cost of building the table.
// Run: ./build/bench/bench_query --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "chatter/operations.hpp"
#include "chatter/solvers.hpp"

namespace {

using namespace chatter;

// docs/physics.md case A (seed 1-DOF turning), 50–2 000 rev/min: ~110 lobes, the
// densest table of the shipped configs.
StructuralModel case_a() {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0}));
  return m;
}
// docs/physics.md case C (milling benchmark, a_e/D = 0.05, 5 000–25 000 rev/min).
StructuralModel case_c() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  return m;
}
Process case_c_process() {
  MillingParameters p;
  p.teeth = 2;
  p.tangential_coefficient_n_per_m2 = 6e8;
  p.radial_coefficient_n_per_m2 = 2e8;
  p.radial_immersion = 0.05;
  return Process::milling(p);
}

struct Queries {
  std::vector<double> rpm, depth;
  Queries(double lo, double hi, double dmax, std::size_t n) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> r(lo, hi), d(0.0, dmax);
    for (std::size_t i = 0; i < n; ++i) {
      rpm.push_back(r(rng));
      depth.push_back(d(rng));
    }
  }
};

void run_queries(benchmark::State& state, const LobeTableQuery& table, const Queries& q) {
  std::size_t i = 0, stable = 0;
  for (auto _ : state) {
    stable += table.is_stable(q.rpm[i], q.depth[i]) ? 1 : 0;
    if (++i == q.rpm.size()) i = 0;
  }
  benchmark::DoNotOptimize(stable);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
  state.counters["table_points"] = static_cast<double>(table.size());
  state.counters["error_bound_um"] = table.error_bound_m() * 1e6;
}

void BM_IsStable_CaseA(benchmark::State& state) {
  const auto solver = make_lobe_solver("analytic", case_a(), Process::turning({2.4e9}), 0.02);
  const LobeTableQuery table(*solver, 50.0, 2000.0);
  run_queries(state, table, Queries(50.0, 2000.0, 0.006, 1 << 16));
}
BENCHMARK(BM_IsStable_CaseA);

void BM_IsStable_CaseC(benchmark::State& state) {
  const auto solver = make_lobe_solver("analytic", case_c(), case_c_process(), 0.01);
  const LobeTableQuery table(*solver, 5000.0, 25000.0);
  run_queries(state, table, Queries(5000.0, 25000.0, 0.01, 1 << 16));
}
BENCHMARK(BM_IsStable_CaseC);

// For comparison: one exact solve per query.
void BM_ExactLimitAt_CaseA(benchmark::State& state) {
  const auto solver = make_lobe_solver("analytic", case_a(), Process::turning({2.4e9}), 0.02);
  const Queries q(50.0, 2000.0, 0.006, 1 << 12);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(solver->limit_at(SpindleSpeed(q.rpm[i])));
    if (++i == q.rpm.size()) i = 0;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_ExactLimitAt_CaseA);

void BM_BuildTable_CaseA(benchmark::State& state) {
  const auto solver = make_lobe_solver("analytic", case_a(), Process::turning({2.4e9}), 0.02);
  for (auto _ : state) {
    const LobeTableQuery table(*solver, 50.0, 2000.0);
    benchmark::DoNotOptimize(table.size());
    state.counters["table_points"] = static_cast<double>(table.size());
  }
}
BENCHMARK(BM_BuildTable_CaseA)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
