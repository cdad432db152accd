// The peers' benchmark (issue 32): 2-DOF milling of Insperger & Stépán (922 Hz
// in X and Y, ζ 0.011, 0.03993 kg, 2 teeth, K_t 6e8, K_r 2e8 N/m², a_e/D =
// 0.05, up-milling), 101 speeds 5 000–25 000 rev/min, depths 0–10 mm.
//
// The two public methods the field's codes ship, written here from the
// papers (not from their code) and run as those codes run them: m = 40 steps
// per tooth period, the augmented state [y_i; x_{i−1} … x_{i−m}] (4 + 2m =
// 84), the one-period map Φ as the product of m dense step matrices, dense
// eigenvalues of Φ at every point of a 101 × 21 speed × depth grid, and the
// limit read off the ρ = 1 contour (linear in ρ between grid depths):
//  - first-order semi-discretisation (Insperger & Stépán 2004, Int. J.
//    Numer. Meth. Engng 61, 117–141): on each step the periodic coefficient
//    averaged, the state term exact, the delayed term linear between its two
//    neighbouring samples;
//  - second-order full discretisation (Ding, Zhu, Zhang & Ding 2010, Int. J.
//    Mach. Tools Manuf. 50, 926–932): only the constant part A0 exact; the
//    periodic state term A(t) y(t) by second-order Lagrange interpolation
//    through t_{i−1}, t_i, t_{i+1}, the delayed term A(t) y(t − τ) linear
//    between its ends (our reading of the method; the step is implicit in
//    y_{i+1}).
// Against them, `sdm` (SemiDiscretizationSolver): 101 exact limits (the
// depth search of docs/sdm.md) at its default steps and at 2× and 4× them,
// and with Gauss collocation (3 nodes at 8 and 6 steps, 2 nodes at 16).
// Counters: each method's median and worst relative error of the limit
// against the converged one (converged_limits: sdm at 4× and 8× its default
// steps, extrapolated), over the speeds where the converged limit is below
// 10 mm.
// Run: ./build/bench/bench_peers --benchmark_repetitions=3
//      --benchmark_report_aggregates_only=true   (docs/performance.md)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

#include "chatter/lobes.hpp"
#include "chatter/semi_discretization.hpp"

namespace {

using namespace chatter;
using Eigen::Matrix2d;
using Eigen::Matrix4d;
using Eigen::MatrixXd;

constexpr double kF = 922.0, kZeta = 0.011, kMass = 0.03993;
constexpr int kPeerSteps = 40, kSpeeds = 101, kDepths = 21;
constexpr double kRpmMin = 5000.0, kRpmMax = 25000.0, kDepthMax = 0.01;

StructuralModel peers_model() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(kF, kZeta, kMass, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(kF, kZeta, kMass, {0.0, 1.0}));
  return m;
}
Process peers_process() { return Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kUp}); }

std::vector<double> peer_depths() {
  std::vector<double> d;
  for (int j = 0; j < kDepths; ++j) d.push_back(kDepthMax * j / (kDepths - 1));
  return d;
}

// ẏ = (A0 + A(t)) y − A(t) y(t − τ), y = [x; ẋ] (x in the plane), A(t) =
// [0 0; −a H(t)/m 0] with H the process's directional matrix (N/m²).
Matrix4d constant_part() {
  const double w = 2.0 * std::numbers::pi * kF;
  Matrix4d A0 = Matrix4d::Zero();
  A0.topRightCorner<2, 2>().setIdentity();
  A0.bottomLeftCorner<2, 2>() = -w * w * Matrix2d::Identity();
  A0.bottomRightCorner<2, 2>() = -2.0 * kZeta * w * Matrix2d::Identity();
  return A0;
}

// H averaged over [t0, t0 + h] by 10 midpoint samples (the codes integrate
// numerically too).
Matrix2d step_average(const Process& p, double t0, double h, double rpm) {
  Matrix2d s = Matrix2d::Zero();
  for (int k = 0; k < 10; ++k) s += p.directional_matrix(t0 + (k + 0.5) / 10.0 * h, rpm) / 10.0;
  return s;
}

// Index of x_{i−k} (k = 1 … m) in the augmented state.
int delayed(int k) { return 4 + 2 * (k - 1); }

// The shift of the delayed positions: x_{i} becomes the newest, the oldest drops.
void shift_rows(MatrixXd& D, int m) {
  D.block(delayed(1), 0, 2, 2).setIdentity();  // x_i (the first two of y_i)
  for (int k = 2; k <= m; ++k) D.block(delayed(k), delayed(k - 1), 2, 2).setIdentity();
}

double spectral_radius(const MatrixXd& Phi) {
  Eigen::EigenSolver<MatrixXd> es(Phi, false);
  return es.eigenvalues().cwiseAbs().maxCoeff();
}

// First-order semi-discretisation, m steps: ρ(Φ) at (rpm, depth).
double sdm1_rho(const Process& p, double rpm, double depth, int m) {
  const double tau = p.delay_s(rpm), h = tau / m;
  const int dim = 4 + 2 * m;
  const Matrix4d A0 = constant_part();
  MatrixXd Phi = MatrixXd::Identity(dim, dim), D(dim, dim);
  for (int i = 0; i < m; ++i) {
    const Matrix2d Hs = depth * step_average(p, i * h, h, rpm) / kMass;
    Matrix4d A = A0;
    A.bottomLeftCorner<2, 2>() -= Hs;
    Eigen::Matrix<double, 4, 2> B = Eigen::Matrix<double, 4, 2>::Zero();
    B.bottomRows<2>() = Hs;
    // [P, F0, F1] from one exponential: F0 = ∫₀ʰ e^{A(h−s)} ds B,
    // F1 = ∫₀ʰ e^{A(h−s)} (s/h) ds B.
    Eigen::Matrix<double, 8, 8> aug = Eigen::Matrix<double, 8, 8>::Zero();
    aug.topLeftCorner<4, 4>() = A * h;
    aug.block<4, 2>(0, 4) = B * h;
    aug.block<2, 2>(4, 6).setIdentity();
    const Eigen::Matrix<double, 8, 8> E = aug.exp();
    const Matrix4d P = E.topLeftCorner<4, 4>();
    const Eigen::Matrix<double, 4, 2> F1 = E.block<4, 2>(0, 6), F0 = E.block<4, 2>(0, 4);
    // y(t − τ) ≈ x_{i−m} + (s/h)(x_{i−m+1} − x_{i−m}) on the step.
    D.setZero();
    D.topLeftCorner(4, 4) = P;
    D.block(0, delayed(m), 4, 2) += F0 - F1;
    D.block(0, delayed(m - 1), 4, 2) += F1;
    shift_rows(D, m);
    Phi = D * Phi;  // dense, as the codes multiply
  }
  return spectral_radius(Phi);
}

// Second-order full discretisation, m steps: ρ(Φ) at (rpm, depth).
double fdm2_rho(const Process& p, double rpm, double depth, int m) {
  const double tau = p.delay_s(rpm), h = tau / m;
  const int dim = 4 + 2 * m;
  const Matrix4d A0 = constant_part();
  // Weights of e^{A0(h−s)} against the Lagrange basis in s ∈ [0, h] (nodes
  // −h, 0, h for the state term; 0, h for the delayed one), from one
  // exponential of the augmented matrix [[A0 h, I h, 0, 0], [0, 0, I, 0],
  // [0, 0, 0, I], [0, 0, 0, 0]]: its blocks give G_k = ∫₀ʰ e^{A0(h−s)}
  // (s/h)^k ds for k = 0, 1, 2 (scaled by k!).
  Eigen::Matrix<double, 16, 16> aug = Eigen::Matrix<double, 16, 16>::Zero();
  aug.block<4, 4>(0, 0) = A0 * h;
  aug.block<4, 4>(0, 4) = Matrix4d::Identity() * h;
  aug.block<4, 4>(4, 8).setIdentity();
  aug.block<4, 4>(8, 12).setIdentity();
  const Eigen::Matrix<double, 16, 16> E = aug.exp();
  const Matrix4d Phi0 = E.block<4, 4>(0, 0), G0 = E.block<4, 4>(0, 4), G1 = E.block<4, 4>(0, 8),
                 G2 = 2.0 * E.block<4, 4>(0, 12);
  // Lagrange basis in u = s/h through u = −1, 0, 1: ℓ₋ = u(u−1)/2, ℓ₀ = 1−u², ℓ₊ = u(u+1)/2.
  const Matrix4d Wm = 0.5 * (G2 - G1), W0 = G0 - G2, Wp = 0.5 * (G2 + G1);
  // Linear basis in u through 0, 1: (1 − u), u.
  const Matrix4d V0 = G0 - G1, V1 = G1;
  auto Aof = [&](int i) {  // A(t_i) y = [0; −a H(t_i) x / m]: the 4 × 2 block on x (H is τ-periodic)
    Eigen::Matrix<double, 4, 2> a = Eigen::Matrix<double, 4, 2>::Zero();
    a.bottomRows<2>() = -depth * p.directional_matrix(((i + m) % m) * h, rpm) / kMass;
    return a;
  };
  MatrixXd Phi = MatrixXd::Identity(dim, dim), D(dim, dim);
  for (int i = 0; i < m; ++i) {
    const Eigen::Matrix<double, 4, 2> Am = Aof(i - 1), A0i = Aof(i), Ap = Aof(i + 1);
    // y_{i+1} = Φ0 y_i + Wm Am x_{i−1} + W0 A0i x_i + Wp Ap x_{i+1}
    //           − V0 A0i x_{i−m} − V1 Ap x_{i+1−m},  x = [I 0] y: implicit in y_{i+1}.
    Matrix4d L = Matrix4d::Identity();
    L.leftCols<2>() -= Wp * Ap;
    const Eigen::PartialPivLU<Matrix4d> lu(L);
    Eigen::Matrix<double, 4, Eigen::Dynamic> rhs = Eigen::Matrix<double, 4, Eigen::Dynamic>::Zero(4, dim);
    rhs.leftCols<4>() = Phi0;
    rhs.leftCols<2>() += W0 * A0i;
    rhs.block<4, 2>(0, delayed(1)) += Wm * Am;
    rhs.block<4, 2>(0, delayed(m)) -= V0 * A0i;
    rhs.block<4, 2>(0, delayed(m - 1)) -= V1 * Ap;
    D.setZero();
    D.topRows(4) = lu.solve(rhs);
    shift_rows(D, m);
    Phi = D * Phi;
  }
  return spectral_radius(Phi);
}

// The ρ = 1 contour along depth at one speed: the first grid interval where ρ
// reaches 1, linear in ρ; +inf when ρ < 1 on the whole grid.
double contour_limit(const std::vector<double>& depths, const std::vector<double>& rho) {
  for (std::size_t j = 1; j < depths.size(); ++j)
    if (rho[j] >= 1.0) {
      const double f = (1.0 - rho[j - 1]) / (rho[j] - rho[j - 1]);
      return depths[j - 1] + std::clamp(f, 0.0, 1.0) * (depths[j] - depths[j - 1]);
    }
  return std::numeric_limits<double>::infinity();
}

// Converged limits: sdm at 4× and 8× its default steps (both the steps per
// period and per vibration cycle), Richardson-extrapolated for its O(h²)
// error: L = L₈ + (L₈ − L₄)/3 (at the worst speed, 18 400 rev/min,
// the limits at 64 … 1 024 steps fall as 3.7258, 3.6921, 3.6837, 3.6817,
// 3.6811 mm: ratios of successive differences 4.0, 4.0, 3.8).
const std::vector<double>& converged_limits() {
  static const std::vector<double> ref = [] {
    auto limits = [](int factor) {
      SemiDiscretizationOptions o;
      o.depth_max_m = kDepthMax;
      o.steps_per_period *= factor;
      o.steps_per_vibration_cycle *= factor;
      o.depth_tolerance = 1e-7;
      const SemiDiscretizationSolver s(peers_model(), peers_process(), o);
      std::vector<double> out;
      for (const StabilityLimit& l : lobe_envelope(s, evenly_spaced_speeds(kRpmMin, kRpmMax, kSpeeds), 1))
        out.push_back(l.depth_limit_m);
      return out;
    };
    const std::vector<double> l4 = limits(4), l8 = limits(8);
    std::vector<double> out(l8.size());
    for (std::size_t i = 0; i < l8.size(); ++i)
      out[i] = std::isfinite(l4[i]) && std::isfinite(l8[i]) ? l8[i] + (l8[i] - l4[i]) / 3.0 : l8[i];
    return out;
  }();
  return ref;
}

// Median and worst relative error of `limits` against the converged limits,
// over the speeds whose converged limit is below the grid's top.
void error_counters(benchmark::State& state, const std::vector<double>& limits) {
  const std::vector<double>& ref = converged_limits();
  std::vector<double> err;
  for (std::size_t i = 0; i < ref.size(); ++i)
    if (std::isfinite(ref[i])) err.push_back(std::isfinite(limits[i]) ? std::abs(limits[i] - ref[i]) / ref[i] : 1.0);
  std::sort(err.begin(), err.end());
  state.counters["median_error_pct"] = 100.0 * err[err.size() / 2];
  state.counters["worst_error_pct"] = 100.0 * err.back();
  state.counters["speeds_compared"] = static_cast<double>(err.size());
}

template <double (*Rho)(const Process&, double, double, int)>
void BM_PeerGrid(benchmark::State& state) {
  const Process p = peers_process();
  const auto speeds = evenly_spaced_speeds(kRpmMin, kRpmMax, kSpeeds);
  const auto depths = peer_depths();
  std::vector<double> limits;
  for (auto _ : state) {
    limits.clear();
    for (double rpm : speeds) {
      std::vector<double> rho;
      for (double a : depths) rho.push_back(Rho(p, rpm, a, kPeerSteps));
      limits.push_back(contour_limit(depths, rho));
    }
    benchmark::DoNotOptimize(limits.data());
  }
  error_counters(state, limits);
}

void BM_Peers_FirstOrderSdm_m40_101x21(benchmark::State& state) { BM_PeerGrid<sdm1_rho>(state); }
void BM_Peers_SecondOrderFdm_m40_101x21(benchmark::State& state) { BM_PeerGrid<fdm2_rho>(state); }
BENCHMARK(BM_Peers_FirstOrderSdm_m40_101x21)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Peers_SecondOrderFdm_m40_101x21)->Unit(benchmark::kMillisecond)->Iterations(1);

// Ours: 101 exact limits on one thread with options `o`, the solver built in
// the loop (what a run spends after start-up).
void run_ours(benchmark::State& state, const SemiDiscretizationOptions& o) {
  const auto speeds = evenly_spaced_speeds(kRpmMin, kRpmMax, kSpeeds);
  std::vector<StabilityLimit> rows;
  for (auto _ : state) {
    const SemiDiscretizationSolver s(peers_model(), peers_process(), o);
    rows = lobe_envelope(s, speeds, 1);
    benchmark::DoNotOptimize(rows.data());
  }
  std::vector<double> limits;
  for (const StabilityLimit& l : rows) limits.push_back(l.depth_limit_m);
  error_counters(state, limits);
}

// The first order at the default steps (argument 1) and at 2× and 4× them
// (steps per period and per vibration cycle): the error falls as h².
void BM_Peers_ChatterSdm_101Limits(benchmark::State& state) {
  SemiDiscretizationOptions o;
  o.depth_max_m = kDepthMax;
  o.steps_per_period *= static_cast<int>(state.range(0));
  o.steps_per_vibration_cycle *= static_cast<int>(state.range(0));
  run_ours(state, o);
}
BENCHMARK(BM_Peers_ChatterSdm_101Limits)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond);

// Gauss collocation (SemiDiscretizationOptions::collocation_nodes, the CLI's
// --collocation): arguments nodes and steps per period and per vibration
// cycle; (3, 8) is what --collocation 3 runs.
void BM_Peers_ChatterSdmCollocation_101Limits(benchmark::State& state) {
  SemiDiscretizationOptions o;
  o.depth_max_m = kDepthMax;
  o.collocation_nodes = static_cast<int>(state.range(0));
  o.steps_per_period = o.steps_per_vibration_cycle = static_cast<int>(state.range(1));
  run_ours(state, o);
}
BENCHMARK(BM_Peers_ChatterSdmCollocation_101Limits)
    ->Args({3, kCollocationSteps})
    ->Args({3, 6})
    ->Args({2, 16})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
