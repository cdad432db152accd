// Speed of the semi-discretisation solver `sdm` (issue 3):
//  - case C (a_e/D = 0.05 down, 2 teeth), 200 spindle speeds over
//    5 000–25 000 rev/min, depth up to 10 mm, default 0.5 % accuracy:
//    target <= 1 s on one core;
//  - case A at 100 rev/min (≈57 vibration cycles per revolution), one depth
//    limit: target <= 50 ms;
//  - for comparison, the classic brute-force approach of the original papers'
//    code: a 200 × 100 rpm × depth grid, 40 steps per period, the monodromy
//    matrix as a product of dense (m+2)×(m+2) step matrices and a dense
//    eigen-decomposition at each point.
// Run: ./build/bench/bench_sdm --benchmark_repetitions=3 (figures in docs/sdm.md).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

#include "chatter/lobes.hpp"
#include "chatter/semi_discretization.hpp"

namespace {

using namespace chatter;

constexpr double kCaseCf = 922.0, kCaseCzeta = 0.011, kCaseCmass = 0.03993;

StructuralModel case_c() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(kCaseCf, kCaseCzeta, kCaseCmass, {1.0, 0.0}));
  return m;
}
Process case_c_process() { return Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kDown}); }

StructuralModel case_a() {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0}));
  return m;
}

void BM_CaseC_200Speeds(benchmark::State& state) {
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.01;
  const SemiDiscretizationSolver solver(case_c(), case_c_process(), o);
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
BENCHMARK(BM_CaseC_200Speeds)->Unit(benchmark::kMillisecond);

void BM_CaseA_100rpm(benchmark::State& state) {
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.05;
  const SemiDiscretizationSolver solver(case_a(), Process::turning({2.4e9}), o);
  StabilityLimit l;
  for (auto _ : state) {
    l = solver.limit_at(SpindleSpeed(100.0));
    benchmark::DoNotOptimize(&l);
  }
  state.SetLabel("depth " + std::to_string(l.depth_limit_m * 1e3) + " mm");
}
BENCHMARK(BM_CaseA_100rpm)->Unit(benchmark::kMillisecond);

// How the cost of one turning limit grows as the speed falls (steps per
// revolution m ∝ 1/rpm): the branch roots make each map O(m).
void BM_CaseA_LowSpeed(benchmark::State& state) {
  const double rpm = static_cast<double>(state.range(0));
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.05;
  const SemiDiscretizationSolver solver(case_a(), Process::turning({2.4e9}), o);
  StabilityLimit l;
  for (auto _ : state) {
    l = solver.limit_at(SpindleSpeed(rpm));
    benchmark::DoNotOptimize(&l);
  }
  FloquetResult fr = solver.analyse(rpm, 1e-3);
  state.counters["steps"] = fr.steps;
  state.SetLabel("depth " + std::to_string(l.depth_limit_m * 1e3) + " mm");
}
BENCHMARK(BM_CaseA_LowSpeed)->Arg(300)->Arg(100)->Arg(30)->Arg(10)->Arg(5)->Arg(3)->Unit(benchmark::kMillisecond);

// The spectral-radius map the CLI `map` command draws, same grid as the
// brute force below but with the solver's own step rule and eigen-solver.
void BM_CaseC_Map200x100(benchmark::State& state) {
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.01;
  const SemiDiscretizationSolver solver(case_c(), case_c_process(), o);
  const auto speeds = evenly_spaced_speeds(5000.0, 25000.0, 200);
  std::vector<double> depths;
  for (int j = 0; j < 100; ++j) depths.push_back(0.01 * (j + 1) / 100.0);
  for (auto _ : state) {
    auto map = solver.spectral_radius_map(speeds, depths);
    benchmark::DoNotOptimize(map.data());
  }
}
BENCHMARK(BM_CaseC_Map200x100)->Unit(benchmark::kMillisecond)->Iterations(1);

// Classic brute force (Insperger & Stépán 2004, appendix code): 1-DOF along
// X, m = 40 steps per period, state [x, ẋ, x(t−h), …, x(t−mh)], dense step
// matrices multiplied into Φ, dense eigenvalues of Φ.
double brute_force_rho(const Process& p, double rpm, double depth, int m) {
  const double w = 2 * std::numbers::pi * kCaseCf;
  const double tau = p.delay_s(rpm), h = tau / m;
  const int dim = m + 2;
  Eigen::MatrixXd Phi = Eigen::MatrixXd::Identity(dim, dim);
  Eigen::MatrixXd Pi = Eigen::MatrixXd::Zero(dim, dim);
  for (int i = 0; i < m; ++i) {
    // h(t) averaged over the step by 10-point midpoint sampling, as the
    // original code does with a numerical integral.
    double hx = 0.0;
    for (int s = 0; s < 10; ++s) hx += p.directional_matrix((i + (s + 0.5) / 10.0) * h, rpm)(0, 0) / 10.0;
    Eigen::Matrix2d A;
    A << 0.0, 1.0, -w * w - depth * hx / kCaseCmass, -2 * kCaseCzeta * w;
    const Eigen::Matrix2d P = (A * h).exp();
    const Eigen::Matrix2d Ainv = A.inverse();
    const Eigen::Vector2d b(0.0, depth * hx / kCaseCmass);
    const Eigen::Vector2d R = (P - Eigen::Matrix2d::Identity()) * Ainv * b;  // zeroth order
    Pi.setZero();
    Pi.topLeftCorner(2, 2) = P;
    Pi.block(0, dim - 2, 2, 1) = 0.5 * R;
    Pi.block(0, dim - 1, 2, 1) = 0.5 * R;
    Pi(2, 0) = 1.0;
    for (int r = 3; r < dim; ++r) Pi(r, r - 1) = 1.0;
    Phi = Pi * Phi;
  }
  Eigen::EigenSolver<Eigen::MatrixXd> es(Phi, false);
  return es.eigenvalues().cwiseAbs().maxCoeff();
}

void BM_BruteForceGrid200x100(benchmark::State& state) {
  const Process p = case_c_process();
  const auto speeds = evenly_spaced_speeds(5000.0, 25000.0, 200);
  for (auto _ : state) {
    double acc = 0.0;
    for (double rpm : speeds)
      for (int j = 0; j < 100; ++j) acc += brute_force_rho(p, rpm, 0.01 * (j + 1) / 100.0, 40);
    benchmark::DoNotOptimize(acc);
  }
}
BENCHMARK(BM_BruteForceGrid200x100)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
