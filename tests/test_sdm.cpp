// The `sdm` solver (first-order semi-discretisation, docs/physics.md §5) against
// the transfer-function solvers where the two must agree (turning, slotting
// with a constant H), against a known multiplier (the analytic boundary point
// of case A lies on the unit circle), where they must differ (flip lobes of
// low-immersion milling), and for its order of convergence.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * std::numbers::pi;

// Tolerances (relative unless said otherwise).
// Default steps (64 per period and per vibration cycle) give at most 0.2 %
// on the depth limit of cases A and B over 60 speeds each (docs/sdm.md); the
// issue asks for 0.5 %.
constexpr double kTurningAgree = 5e-3;
// The chatter frequency converges faster than the depth (0.01 % measured).
constexpr double kFrequencyAgree = 2e-3;
// Slotting with 4 teeth: H(t) = T(φ) + T(φ + π/2) is constant and equal to H₀,
// so sdm and zeroth-order solve the same equation: discretisation error only.
constexpr double kSlottingAgree = 5e-3;
// At the exact boundary point of case A, with 192 steps per vibration cycle
// (depth error ~2e-4): |μ| − 1 and arg μ − ωτ, absolute.
constexpr double kUnitCircle = 1e-3;
constexpr double kPhase = 1e-3;  // rad
// A real multiplier: |μ + 1| at the limit when the type is flip (absolute;
// the limit is found to 1e-4 in depth).
constexpr double kFlipMultiplier = 1e-3;
// Second order: halving the step divides the error by 4; accepted band.
constexpr double kOrderRatioMin = 3.0, kOrderRatioMax = 5.5;

// docs/physics.md case A.
constexpr double kA_f = 94.22, kA_zeta = 0.033, kA_k = 45e6, kA_Kf = 2.4e9;
StructuralModel case_a() {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(kA_f, kA_zeta, kA_k, {1.0, 0.0}));
  return m;
}

// docs/physics.md case B, tool condition 1 × workpiece condition 1.
constexpr double kB_Kf = 684e6;
StructuralModel case_b11() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1, 0}));
  m.workpiece.modes.push_back(Mode::from_stiffness(326.71, 0.025, 43.972e6, {1, 0}));
  return m;
}

// docs/physics.md case C: one tool mode along X.
StructuralModel case_c() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  return m;
}
Process case_c_process(int teeth, double immersion) {
  return Process::milling({teeth, 6e8, 2e8, immersion, MillingDirection::kDown});
}

// Default options but depth_max_m; `steps` (if > 0) per period and per vibration cycle.
SemiDiscretizationOptions sdm_options(double depth_max_m, int steps = 0) {
  SemiDiscretizationOptions o;
  o.depth_max_m = depth_max_m;
  if (steps > 0) {
    o.steps_per_period = steps;
    o.steps_per_vibration_cycle = steps;
  }
  return o;
}

TransferFunctionOptions tf_options(double depth_max_m) {
  TransferFunctionOptions o;
  o.depth_max_m = depth_max_m;
  return o;
}

double wrap_pi(double x) { return std::remainder(x, kTwoPi); }  // into [−π, π]

void expect_agree(const SemiDiscretizationSolver& sdm, const TransferFunctionSolver& tf, double rpm, double tol) {
  const StabilityLimit s = sdm.limit_at(SpindleSpeed(rpm));
  const StabilityLimit t = tf.limit_at(SpindleSpeed(rpm));
  ASSERT_TRUE(t.bounded()) << rpm;
  ASSERT_TRUE(s.bounded()) << rpm;
  EXPECT_NEAR(s.depth_limit_m / t.depth_limit_m, 1.0, tol)
      << "depth at " << rpm << " rev/min: sdm " << s.depth_limit_m << " vs " << tf.method() << " "
      << t.depth_limit_m;
  EXPECT_NEAR(s.chatter_frequency_hz / t.chatter_frequency_hz, 1.0, kFrequencyAgree)
      << "frequency at " << rpm << " rev/min: " << s.chatter_frequency_hz << " vs " << t.chatter_frequency_hz;
  EXPECT_EQ(s.lobe, t.lobe) << rpm;
}

TEST(SdmTurning, CaseAAgreesWithAnalytic) {
  const Process p = Process::turning({kA_Kf});
  const SemiDiscretizationSolver sdm(case_a(), p, sdm_options(0.05));
  const AnalyticSolver an(case_a(), p, tf_options(0.05));
  for (double rpm : {100.0, 250.0, 1000.0, 2000.0, 3600.0, 6000.0}) expect_agree(sdm, an, rpm, kTurningAgree);
}

TEST(SdmTurning, CaseAAtTheAbsoluteLimitSpeed) {
  // The speed where lobe k = 2 touches the absolute limit: ω_abs from the
  // analytic solver, ε from the eigenvalue there, τ = (ε + 2πk)/ω.
  const Process p = Process::turning({kA_Kf});
  const AnalyticSolver an(case_a(), p, tf_options(0.05));
  const AbsoluteLimit abs = an.absolute_limit();
  const double w = kTwoPi * abs.chatter_frequency_hz;
  const double eps = std::fmod(3 * kPi + 2 * std::arg(an.eigenvalues(w)[0]), kTwoPi);
  const double rpm = 60.0 / ((eps + 2 * kPi * 2) / w);
  const SemiDiscretizationSolver sdm(case_a(), p, sdm_options(0.05));
  const StabilityLimit s = sdm.limit_at(SpindleSpeed(rpm));
  const double closed = 2 * kA_k * kA_zeta * (1 + kA_zeta) / kA_Kf;  // 1.2783 mm
  EXPECT_NEAR(s.depth_limit_m / closed, 1.0, kTurningAgree) << s.depth_limit_m << " vs " << closed << " at " << rpm;
  EXPECT_EQ(s.lobe, 2);
}

TEST(SdmTurning, CoupledCaseBAgreesWithCoupledSolver) {
  const Process p = Process::turning({kB_Kf});
  const SemiDiscretizationSolver sdm(case_b11(), p, sdm_options(0.05));
  const CoupledSolver co(case_b11(), p, tf_options(0.05));
  for (double rpm : {500.0, 1500.0, 3000.0, 6000.0, 9000.0, 14000.0}) expect_agree(sdm, co, rpm, kTurningAgree);
}

TEST(SdmTurning, StableUpToDepthMaxIsInfinity) {
  // 0.5 mm is below the absolute limit 1.2783 mm of case A.
  const SemiDiscretizationSolver sdm(case_a(), Process::turning({kA_Kf}), sdm_options(0.0005));
  for (double rpm : {300.0, 2500.0}) {
    const StabilityLimit s = sdm.limit_at(SpindleSpeed(rpm));
    EXPECT_FALSE(s.bounded()) << rpm;
    EXPECT_EQ(s.lobe, -1);
    EXPECT_TRUE(std::isnan(s.chatter_frequency_hz));
  }
}

TEST(SdmKnownAnswer, MultiplierAtTheAnalyticBoundaryIsOnTheUnitCircle) {
  // At the exact boundary (a*, ω) of the delay equation, e^{jωτ} is a
  // characteristic multiplier: the dominant μ must sit on it.
  const Process p = Process::turning({kA_Kf});
  const AnalyticSolver an(case_a(), p, tf_options(0.05));
  const SemiDiscretizationSolver sdm(case_a(), p, sdm_options(0.05, 192));
  for (double rpm : {1000.0, 3000.0}) {
    const StabilityLimit t = an.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(t.bounded());
    const double tau = 60.0 / rpm, w = kTwoPi * t.chatter_frequency_hz;
    const FloquetResult f = sdm.analyse(rpm, t.depth_limit_m);
    EXPECT_NEAR(f.spectral_radius, 1.0, kUnitCircle) << rpm;
    // μ is reported with Im μ >= 0: e^{jωτ} or its conjugate partner.
    EXPECT_NEAR(std::arg(f.dominant_multiplier), std::abs(wrap_pi(w * tau)), kPhase)
        << "arg mu " << std::arg(f.dominant_multiplier) << " vs omega tau " << wrap_pi(w * tau);
    EXPECT_EQ(f.type, MultiplierType::kHopf);
    EXPECT_NEAR(f.chatter_frequency_hz / t.chatter_frequency_hz, 1.0, kFrequencyAgree);
    // Just below and above the boundary.
    EXPECT_LT(sdm.analyse(rpm, 0.99 * t.depth_limit_m).spectral_radius, 1.0);
    EXPECT_GT(sdm.analyse(rpm, 1.01 * t.depth_limit_m).spectral_radius, 1.0);
  }
}

TEST(SdmMilling, SlottingWithFourTeethMatchesZerothOrder) {
  // Two of four teeth always cut, 90° apart: the sin², cos², sin·cos terms of
  // T(φ) + T(φ + π/2) sum to constants, H(t) = H₀ exactly.
  const Process p = case_c_process(4, 1.0);
  const SemiDiscretizationSolver sdm(case_c(), p, sdm_options(0.01));
  const AnalyticSolver an(case_c(), p, tf_options(0.01));
  for (double t : {0.3e-3, 1.1e-3, 2.9e-3})  // away from entry/exit instants
    EXPECT_LT((p.directional_matrix(t, 9000.0) - p.average_directional_matrix()).norm(),
              1e-9 * p.average_directional_matrix().norm());
  for (double rpm : {5000.0, 8000.0, 12000.0, 18000.0, 22000.0}) expect_agree(sdm, an, rpm, kSlottingAgree);
}

TEST(SdmMilling, LowImmersionFlipLobeThatTheTransferFunctionMisses) {
  // Case C at a_e/D = 0.05, down-milling, 2 teeth: the tooth cuts 14 % of
  // the period. Around 2/3 of the natural frequency (tooth passing
  // 2·922/3 Hz ≈ 18 440 rev/min) the one-period map loses stability through
  // μ = −1 (period doubling). The zeroth-order transfer function, which
  // averages H over the period, cannot produce it.
  const Process p = case_c_process(2, 0.05);
  const SemiDiscretizationSolver sdm(case_c(), p, sdm_options(0.01));
  const AnalyticSolver an(case_c(), p, tf_options(0.01));
  // 16 000 rev/min: analytic finds nothing below 10 mm, sdm a flip lobe.
  {
    FloquetResult f;
    const StabilityLimit s = sdm.limit_at(SpindleSpeed(16000.0), &f);
    EXPECT_FALSE(an.limit_at(SpindleSpeed(16000.0)).bounded());
    ASSERT_TRUE(s.bounded());
    EXPECT_EQ(f.type, MultiplierType::kFlip);
    EXPECT_NEAR(std::abs(f.dominant_multiplier + 1.0), 0.0, kFlipMultiplier);
    // f = (k + 1/2)/τ: half-integer multiple of the tooth passing frequency.
    const double tooth_hz = 2 * 16000.0 / 60.0;
    EXPECT_NEAR(std::abs(std::remainder(s.chatter_frequency_hz / tooth_hz, 1.0)), 0.5, 1e-9);
  }
  // 17 500 and 18 000 rev/min: sdm's flip limit is far below analytic's.
  for (double rpm : {17500.0, 18000.0}) {
    FloquetResult f;
    const StabilityLimit s = sdm.limit_at(SpindleSpeed(rpm), &f);
    const StabilityLimit t = an.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(s.bounded() && t.bounded()) << rpm;
    EXPECT_EQ(f.type, MultiplierType::kFlip) << rpm;
    EXPECT_LT(s.depth_limit_m, 0.5 * t.depth_limit_m) << "sdm " << s.depth_limit_m << " vs analytic " << t.depth_limit_m;
  }
  // Below 14 000 rev/min the chart has Hopf lobes (one flip lobe near
  // 2·922/5 Hz ≈ 11 000 rev/min aside): complex multipliers at the limit.
  for (double rpm : {5000.0, 8000.0, 12000.0}) {
    FloquetResult f;
    const StabilityLimit s = sdm.limit_at(SpindleSpeed(rpm), &f);
    ASSERT_TRUE(s.bounded()) << rpm;
    EXPECT_EQ(f.type, MultiplierType::kHopf) << rpm;
    EXPECT_NEAR(f.spectral_radius, 1.0, 1e-3);
  }
}

TEST(SdmPlanar, TwoDirectionSlottingMatchesBothBranchesOfZerothOrder) {
  // Modes along X and Y (different frequencies and masses) and slotting with
  // 4 teeth (H = H₀ of full rank): the delayed quantity is the whole planar
  // displacement, and both eigenvalue branches of H₀G matter.
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(1010.0, 0.015, 0.05, {0.0, 1.0}));
  const Process p = case_c_process(4, 1.0);
  const SemiDiscretizationSolver sdm(m, p, sdm_options(0.01));
  const AnalyticSolver an(m, p, tf_options(0.01));
  for (double rpm : {6000.0, 11000.0, 17000.0}) expect_agree(sdm, an, rpm, kSlottingAgree);
}

TEST(SdmPlanar, ObliqueTurningModesAgreeWithAnalytic) {
  // A workpiece mode at 30° to the feed and a tool mode along Y that the
  // turning force cannot excite: only the X part of r(t − τ) is carried.
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(kA_f, kA_zeta, kA_k, {std::cos(kPi / 6), std::sin(kPi / 6)}));
  m.tool.modes.push_back(Mode::from_stiffness(150.0, 0.03, 30e6, {0.0, 1.0}));
  const Process p = Process::turning({kA_Kf});
  const SemiDiscretizationSolver sdm(m, p, sdm_options(0.05));
  const AnalyticSolver an(m, p, tf_options(0.05));
  for (double rpm : {400.0, 1800.0, 5000.0}) expect_agree(sdm, an, rpm, kTurningAgree);
}

TEST(SdmEigen, ArnoldiAgreesWithDenseDecomposition) {
  // Planar two-mode tool, 3 teeth, 30 % up-milling (free flight, n_r = 2):
  // the same map solved by restarted Arnoldi and by a dense decomposition.
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(1010.0, 0.015, 0.05, {0.0, 1.0}));
  const Process p = Process::milling({3, 6e8, 2e8, 0.3, MillingDirection::kUp});
  SemiDiscretizationOptions arnoldi = sdm_options(0.01), dense = sdm_options(0.01);
  arnoldi.dense_max_dimension = 1;
  dense.dense_max_dimension = 100000;
  const SemiDiscretizationSolver sa(m, p, arnoldi), sd(m, p, dense);
  for (double rpm : {9000.0, 15000.0})
    for (double depth : {0.2e-3, 1e-3, 3e-3}) {
      const FloquetResult a = sa.analyse(rpm, depth), d = sd.analyse(rpm, depth);
      ASSERT_GT(a.map_dimension, 30) << "map too small to exercise Arnoldi restarts";
      EXPECT_TRUE(a.converged);
      EXPECT_NEAR(a.spectral_radius / d.spectral_radius, 1.0, 1e-9) << rpm << " rev/min, " << depth << " m";
      EXPECT_LT(std::abs(a.dominant_multiplier - d.dominant_multiplier), 1e-8 * d.spectral_radius);
    }
}

TEST(SdmThreads, ConstMembersGiveIdenticalResultsFromTwoThreads) {
  const SemiDiscretizationSolver sdm(case_c(), case_c_process(2, 0.05), sdm_options(0.01));
  const std::vector<double> speeds = evenly_spaced_speeds(6000.0, 24000.0, 16);
  const std::vector<StabilityLimit> serial = lobe_envelope(sdm, speeds);
  std::vector<StabilityLimit> a, b;
  std::thread t1([&] { a = lobe_envelope(sdm, speeds); });
  std::thread t2([&] { b = lobe_envelope(sdm, speeds); });
  t1.join();
  t2.join();
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    EXPECT_EQ(a[i].depth_limit_m, serial[i].depth_limit_m) << speeds[i];  // bit-identical
    EXPECT_EQ(b[i].depth_limit_m, serial[i].depth_limit_m) << speeds[i];
  }
}

// Independent check by time integration (no semi-discretisation): RK4 on
//   m ẍ + c ẋ + k x = −a h(t) (x − x(t − τ)),  h = Process::directional_matrix(t)(0, 0),
// with τ = N dt and the delayed x at half steps by cubic Hermite interpolation
// of the stored history. Returns the growth factor per period of the
// amplitude envelope (max |x| over a period) between periods P/2 and P, and
// the once-per-period samples of the last periods.
struct Growth {
  double per_period = 0.0;
  std::vector<double> samples;
};
Growth time_domain_growth(const Process& p, double rpm, double depth, int N, int P) {
  const double m = 0.03993, w = kTwoPi * 922.0, zeta = 0.011;
  const double dt = p.delay_s(rpm) / N;
  std::vector<double> X, V;
  for (int i = 0; i <= N; ++i) {  // smooth initial history, not an eigenfunction
    X.push_back(1e-6 * std::sin(10.7 * i / N));
    V.push_back(1e-6 * 10.7 / (N * dt) * std::cos(10.7 * i / N));
  }
  auto delayed = [&](std::size_t i, double s) {
    const double x0 = X[i - N], x1 = X[i - N + 1], v0 = V[i - N] * dt, v1 = V[i - N + 1] * dt;
    return (2 * s * s * s - 3 * s * s + 1) * x0 + (s * s * s - 2 * s * s + s) * v0 + (-2 * s * s * s + 3 * s * s) * x1 +
           (s * s * s - s * s) * v1;
  };
  auto accel = [&](double t, double x, double v, double xd) {
    return -2 * zeta * w * v - w * w * x - depth * p.directional_matrix(t, rpm)(0, 0) / m * (x - xd);
  };
  Growth g;
  for (int k = 0; k < P * N; ++k) {
    const std::size_t i = X.size() - 1;
    const double t = static_cast<double>(i) * dt, x = X[i], v = V[i];
    const double xh = delayed(i, 0.5);
    const double k1x = v, k1v = accel(t, x, v, delayed(i, 0.0));
    const double k2x = v + dt / 2 * k1v, k2v = accel(t + dt / 2, x + dt / 2 * k1x, v + dt / 2 * k1v, xh);
    const double k3x = v + dt / 2 * k2v, k3v = accel(t + dt / 2, x + dt / 2 * k2x, v + dt / 2 * k2v, xh);
    const double k4x = v + dt * k3v, k4v = accel(t + dt, x + dt * k3x, v + dt * k3v, delayed(i, 1.0));
    X.push_back(x + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x));
    V.push_back(v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v));
    if ((k + 1) % N == 0) g.samples.push_back(X.back());
  }
  auto envelope = [&](int q) {
    double a = 0.0;
    for (int j = q * N; j < (q + 1) * N; ++j) a = std::max(a, std::abs(X[static_cast<std::size_t>(j)]));
    return a;
  };
  g.per_period = std::pow(envelope(P) / envelope(P / 2), 1.0 / (P - P / 2));
  return g;
}

TEST(SdmCrossCheck, TimeDomainGrowthRateMatchesSpectralRadius) {
  // The growth per period of a simulated solution tends to ρ. Tolerance:
  // the envelope over 100 periods still carries the sub-dominant
  // multipliers and, for a complex pair, beating (measured differences
  // ≤ 8e-4 with 500 RK4 steps per period; RK4 drops to low order at the
  // tooth entry/exit jumps).
  constexpr double kGrowthAgree = 2e-3;  // absolute, on ρ
  const Process p = case_c_process(2, 0.05);
  const SemiDiscretizationSolver sdm(case_c(), p, sdm_options(0.01));
  struct Point { double rpm, depth; };
  for (const Point pt : {Point{18000.0, 1.2e-3}, Point{18000.0, 1.4e-3}, Point{20000.0, 2.0e-3}, Point{20000.0, 2.6e-3}}) {
    const FloquetResult f = sdm.analyse(pt.rpm, pt.depth);
    const Growth g = time_domain_growth(p, pt.rpm, pt.depth, 500, 200);
    EXPECT_NEAR(g.per_period, f.spectral_radius, kGrowthAgree) << pt.rpm << " rev/min, " << pt.depth << " m";
    EXPECT_EQ(g.per_period < 1.0, f.stable()) << pt.rpm << " rev/min, " << pt.depth << " m";
    if (f.type == MultiplierType::kFlip) {
      // Period doubling: the once-per-period samples alternate in sign.
      const auto& s = g.samples;
      for (std::size_t i = s.size() - 4; i + 1 < s.size(); ++i) EXPECT_LT(s[i] * s[i + 1], 0.0);
    }
  }
}

// Spectral radius at a fixed point for N steps per period and per vibration
// cycle, with the first-order steps (turning's default collocation:
// tests/test_sdm_collocation.cpp).
double rho(const StructuralModel& m, const Process& p, double rpm, double depth, int steps) {
  SemiDiscretizationOptions o = sdm_options(0.05, steps);
  o.collocation_nodes = 0;
  return SemiDiscretizationSolver(m, p, o).analyse(rpm, depth).spectral_radius;
}

void expect_second_order(const StructuralModel& m, const Process& p, double rpm, double depth) {
  const double ref = rho(m, p, rpm, depth, 1536);
  const double e1 = std::abs(rho(m, p, rpm, depth, 12) - ref);
  const double e2 = std::abs(rho(m, p, rpm, depth, 24) - ref);
  const double e3 = std::abs(rho(m, p, rpm, depth, 48) - ref);
  EXPECT_GT(e1 / e2, kOrderRatioMin) << e1 << " " << e2 << " " << e3;
  EXPECT_LT(e1 / e2, kOrderRatioMax) << e1 << " " << e2 << " " << e3;
  EXPECT_GT(e2 / e3, kOrderRatioMin) << e1 << " " << e2 << " " << e3;
  EXPECT_LT(e2 / e3, kOrderRatioMax) << e1 << " " << e2 << " " << e3;
}

TEST(SdmConvergence, HalvingTheStepDividesTheErrorByFourInTurning) {
  expect_second_order(case_a(), Process::turning({kA_Kf}), 2000.0, 2.0e-3);
}

TEST(SdmConvergence, HalvingTheStepDividesTheErrorByFourInSlotting) {
  expect_second_order(case_c(), case_c_process(4, 1.0), 9000.0, 0.5e-3);
}

// The map stops Arnoldi as soon as the dominant Ritz value has converged to a
// residual of 1e-10 of its modulus; analyse() (which also wants the
// eigenvector) may run it further: the two agree to about that residual.
constexpr double kMapVsAnalyse = 1e-9;

TEST(SdmMap, SpectralRadiusMapIsRowMajorAndMatchesAnalyse) {
  const SemiDiscretizationSolver sdm(case_c(), case_c_process(2, 0.05), sdm_options(0.01));
  const std::vector<double> rpms{9000.0, 18000.0}, depths{0.0, 1e-3, 4e-3};
  const std::vector<double> map = sdm.spectral_radius_map(rpms, depths);
  ASSERT_EQ(map.size(), rpms.size() * depths.size());
  for (std::size_t i = 0; i < rpms.size(); ++i)
    for (std::size_t j = 0; j < depths.size(); ++j)
      EXPECT_NEAR(map[i * depths.size() + j], sdm.analyse(rpms[i], depths[j]).spectral_radius,
                  kMapVsAnalyse * map[i * depths.size() + j]);
  // Depth 0: free vibration over one delay, ρ = e^{−ζωτ}.
  const double tau = 60.0 / (2 * 9000.0);
  EXPECT_NEAR(map[0], std::exp(-0.011 * kTwoPi * 922.0 * tau), 1e-9);
}

TEST(SdmMap, LimitSeparatesStableFromUnstable) {
  const SemiDiscretizationSolver sdm(case_c(), case_c_process(2, 0.05), sdm_options(0.01));
  for (double rpm : {7000.0, 17000.0, 23000.0}) {
    const StabilityLimit s = sdm.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(s.bounded()) << rpm;
    EXPECT_LT(sdm.analyse(rpm, s.depth_limit_m * (1 - 1e-3)).spectral_radius, 1.0) << rpm;
    EXPECT_GT(sdm.analyse(rpm, s.depth_limit_m * (1 + 1e-3)).spectral_radius, 1.0) << rpm;
  }
}

SemiDiscretizationOptions with(void (*edit)(SemiDiscretizationOptions&)) {
  SemiDiscretizationOptions o;
  edit(o);
  return o;
}

void expect_input_error(const SemiDiscretizationOptions& o, const std::string& names) {
  try {
    SemiDiscretizationSolver s(case_a(), Process::turning({kA_Kf}), o);
    ADD_FAILURE() << "no InputError for " << names;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
  }
}

TEST(SdmInput, RefusesBadOptionsNamingTheRule) {
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.steps_per_period = 0; }), "steps_per_period = 0");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.steps_per_vibration_cycle = -3; }),
                     "steps_per_vibration_cycle = -3");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.depth_tolerance = 0.0; }), "depth_tolerance");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.depth_tolerance = -1e-4; }), "depth_tolerance");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.depth_max_m = 0.0; }), "depth_max_m");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.depth_max_m = -0.01; }), "depth_max_m");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.bracket_ratio = 1.0; }), "bracket_ratio");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.krylov_dimension = 2; }), "krylov_dimension");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.bracket_min_ratio = 3.0; }), "bracket_min_ratio");
  expect_input_error(with([](SemiDiscretizationOptions& o) { o.max_steps_per_period = 0; }), "max_steps_per_period");
  EXPECT_TRUE(SemiDiscretizationOptions{}.validate().empty());
  EXPECT_THROW(SemiDiscretizationSolver(StructuralModel{}, Process::turning({kA_Kf})), InputError);
  const SemiDiscretizationSolver s(case_a(), Process::turning({kA_Kf}));
  EXPECT_THROW(s.limit_at(SpindleSpeed(0.0)), InputError);
  EXPECT_THROW(s.limit_at(SpindleSpeed(NAN)), InputError);
  EXPECT_THROW(s.analyse(1000.0, -1e-3), InputError);
  EXPECT_THROW(s.spectral_radius_map({-5.0}, {1e-3}), InputError);
  // 0.1 rev/min: 600 s per revolution, ≈3.6 million steps at the defaults.
  EXPECT_THROW(s.limit_at(SpindleSpeed(0.1)), InputError);
  EXPECT_EQ(s.method(), "sdm");
  EXPECT_EQ(to_string(MultiplierType::kFlip), "flip");
}

}  // namespace
}  // namespace chatter
