// Spindle speed variation (docs/ssv.md): the modulated speed and its delay,
// the principal period, and the `sdm` solver with the time-varying delay —
// against constant speed at R_VA -> 0, against an independent first-order
// semi-discretisation of 1-DOF turning written here (plain Eigen, dense
// monodromy matrix), and the low-speed gain on case A.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/solvers.hpp"
#include "chatter/speed_variation.hpp"

namespace chatter {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

// Tolerances (relative unless said otherwise).
// The delay solves θ(t) − θ(t − τ) = θ_p by Newton to round-off: the
// residual in angle, rad (absolute).
constexpr double kAngleResidual = 1e-9;
// R_VA -> 0: the grid and samples are the constant-speed solver's, so the
// limits differ by the depth search's tolerance (1e-4) at most; twice that.
constexpr double kConstantLimit = 2e-4;
// The same first-order scheme, built twice (here dense, in the library
// through step maps and Arnoldi): ρ agrees to the eigen-solvers' accuracy.
constexpr double kIndependentRho = 1e-9;  // measured: 2e-11

// Depth limits of the two implementations: each is bisected to 1e-6 here and
// searched to the library's depth tolerance 1e-4; the gain is a ratio of two.
constexpr double kIndependentGain = 3e-4;

// docs/physics.md case A (configs/seed_turning_1dof.toml).
constexpr double kA_f = 94.22, kA_zeta = 0.033, kA_k = 45e6, kA_Kf = 2.4e9;
StructuralModel case_a() {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(kA_f, kA_zeta, kA_k, {1.0, 0.0}));
  return m;
}
Process turning_a(double rva = 0.0, double rvf = 0.1) {
  Process p = Process::turning({kA_Kf});
  p.set_speed_variation({rva, rvf});
  return p;
}

// ------------------------------------------------- the speed and its delay

TEST(ModulatedSpeed, AngleIsTheIntegralOfTheSpeed) {
  const ModulatedSpeed s(600.0, {0.2, 0.3});
  // Trapezoid rule on a fine grid against the closed form.
  const double t_end = 0.37;
  const int n = 200000;
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    const double a = t_end * i / n, b = t_end * (i + 1) / n;
    integral += 0.5 * (s.omega(a) + s.omega(b)) * (b - a);
  }
  EXPECT_NEAR(s.angle(t_end), integral, 1e-8) << "closed form " << s.angle(t_end) << " vs quadrature " << integral;
  EXPECT_NEAR(s.time_at_angle(s.angle(t_end)), t_end, 1e-13);
}

TEST(ModulatedSpeed, DelaySolvesTheAngleEquation) {
  const ModulatedSpeed s(300.0, {0.25, 0.05});
  for (double t : {0.0, 0.1, 1.3, 2.7, 4.0}) {
    const double tau = s.delay(t, kTwoPi);
    EXPECT_NEAR(s.angle(t) - s.angle(t - tau), kTwoPi, kAngleResidual) << "t = " << t;
    // Between one revolution at the fastest and at the slowest speed.
    EXPECT_GT(tau, 0.2 / 1.25);
    EXPECT_LT(tau, 0.2 / 0.75);
  }
  // Constant speed: one revolution.
  EXPECT_DOUBLE_EQ(ModulatedSpeed(300.0, {}).delay(1.0, kTwoPi), 0.2);
}

TEST(ModulatedSpeed, InvalidVariationIsRefusedWithTheRule) {
  Process p = Process::turning({kA_Kf});
  EXPECT_THROW(p.set_speed_variation({1.0, 0.1}), InputError);
  EXPECT_THROW(p.set_speed_variation({-0.1, 0.1}), InputError);
  EXPECT_THROW(p.set_speed_variation({0.1, 0.0}), InputError);
  try {
    p.set_speed_variation({0.1, -2.0});
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frequency_ratio"), std::string::npos) << e.what();
  }
  p.set_speed_variation({0.0, 0.1});
  EXPECT_FALSE(p.has_speed_variation());
}

// --------------------------------------------------------------- the period

TEST(SpeedVariationPeriod, CommensurateIsExact) {
  // Turning, R_VF = 0.1: ten revolutions per modulation period.
  const SpeedVariationPeriod t = speed_variation_period(turning_a(0.1, 0.1), 300.0);
  EXPECT_TRUE(t.exact);
  EXPECT_EQ(t.modulation_periods, 1);
  EXPECT_DOUBLE_EQ(t.floquet_periods, 10.0);
  EXPECT_NEAR(t.period_s, 2.0, 1e-12);
  // Milling, 2 teeth, R_VF = 0.3: T_F/T_m = 0.15 = 3/20.
  MillingParameters mp;
  mp.teeth = 2;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 2e8;
  mp.radial_immersion = 0.5;
  Process m = Process::milling(mp);
  m.set_speed_variation({0.1, 0.3});
  const SpeedVariationPeriod mi = speed_variation_period(m, 6000.0);
  EXPECT_TRUE(mi.exact);
  EXPECT_EQ(mi.modulation_periods, 3);
  EXPECT_DOUBLE_EQ(mi.floquet_periods, 20.0);
}

TEST(SpeedVariationPeriod, IncommensurateIsANearbyFraction) {
  // R_VF = 1/π: no fraction; the nearest with p <= 8 within 1e-3, reported.
  const double rvf = 1.0 / std::numbers::pi;
  const SpeedVariationPeriod t = speed_variation_period(turning_a(0.1, rvf), 300.0);
  EXPECT_FALSE(t.exact);
  EXPECT_LE(t.modulation_periods, kMaxModulationPeriods);
  EXPECT_NEAR(t.frequency_ratio_used, rvf, kSpeedVariationRatioTolerance * rvf);
  // The period holds whole numbers of both: p modulation periods of the used ratio, q revolutions.
  const double tm = 60.0 / 300.0 / t.frequency_ratio_used;
  EXPECT_NEAR(t.period_s, t.modulation_periods * tm, 1e-12 * t.period_s);
  EXPECT_NEAR(t.period_s, t.floquet_periods * 0.2, 1e-12 * t.period_s);
}

// ---------------------------------------------------- the solver, R_VA -> 0

TEST(SsvSdm, VanishingAmplitudeGivesTheConstantSpeedLimit) {
  for (double rpm : {300.0, 1200.0}) {
    const SemiDiscretizationSolver steady(case_a(), turning_a(0.0));
    const SemiDiscretizationSolver ssv(case_a(), turning_a(1e-9, 0.25));
    const double a0 = steady.limit_at(SpindleSpeed(rpm)).depth_limit_m, a1 = ssv.limit_at(SpindleSpeed(rpm)).depth_limit_m;
    EXPECT_NEAR(a1 / a0, 1.0, kConstantLimit) << rpm << " rev/min: constant " << a0 * 1e3 << " mm, R_VA = 1e-9 "
                                               << a1 * 1e3 << " mm";
  }
}

TEST(SsvSdm, VanishingAmplitudeGivesTheConstantSpeedLimitInMilling) {
  // docs/physics.md case C, a_e/D = 0.05 down-milling, 2 teeth: the SSV grid
  // is the constant-speed real-cutter grid over 20 tooth periods.
  MillingParameters mp;
  mp.teeth = 2;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 2e8;
  mp.radial_immersion = 0.05;
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  const Process steady = Process::milling(mp);
  Process tiny = steady;
  tiny.set_speed_variation({1e-9, 0.1});
  for (double rpm : {6000.0, 17000.0}) {
    const double a0 = SemiDiscretizationSolver(m, steady).limit_at(SpindleSpeed(rpm)).depth_limit_m;
    const double a1 = SemiDiscretizationSolver(m, tiny).limit_at(SpindleSpeed(rpm)).depth_limit_m;
    EXPECT_NEAR(a1 / a0, 1.0, kConstantLimit) << rpm << " rev/min: constant " << a0 * 1e3 << " mm, R_VA = 1e-9 "
                                               << a1 * 1e3 << " mm";
  }
}

TEST(SsvSdm, TooLongAPeriodIsRefusedWithWhatToChange) {
  // 50 rev/min, R_VF = 0.001: 1 000 revolutions of 7 238 steps.
  try {
    SemiDiscretizationSolver(case_a(), turning_a(0.1, 0.001)).limit_at(SpindleSpeed(50.0));
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frequency ratio"), std::string::npos) << e.what();
  }
}

TEST(SsvSdm, AnalyticMethodRefusesAndNamesSdm) {
  try {
    make_lobe_solver("analytic", case_a(), turning_a(0.1, 0.1), 0.02);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("analytic"), std::string::npos) << m;
    EXPECT_NE(m.find("speed variation"), std::string::npos) << m;
    EXPECT_NE(m.find("sdm"), std::string::npos) << m;
  }
  EXPECT_THROW(make_lobe_solver("coupled", case_a(), turning_a(0.1, 0.1), 0.02), InputError);
  // auto picks sdm for turning with SSV.
  EXPECT_EQ(resolve_lobe_method(kAutoMethod, case_a(), turning_a(0.1, 0.1)), "sdm");
}

// -------------------------------- an independent semi-discretisation (1 DOF)

// 1-DOF turning m ẍ + c ẋ + k x = −K_f b (x(t) − x(t − τ(t))), first-order
// semi-discretisation over the principal period T (q revolutions = p
// modulation periods) in M equal steps h (a whole number per revolution):
// over a step, x(t − τ(t)) is the straight line between its values at the
// step's ends, each interpolated linearly between the samples x(k h). The
// monodromy matrix is formed column by column (dense) and its eigenvalues
// taken by Eigen. The delay comes from bisection on the angle written out
// here, not from the library.
struct IndependentSsv {
  double f_hz, zeta, k, kf, rpm, rva, rvf;
  int steps_per_cycle;  // the library's steps_per_period = steps_per_vibration_cycle

  double omega0() const { return kTwoPi * rpm / 60.0; }
  double angle(double t) const {
    const double nu = rvf * omega0();
    return omega0() * t + rva * omega0() / nu * (1.0 - std::cos(nu * t));
  }
  double delay(double t) const {
    double lo = 0.0, hi = 2.0 * kTwoPi / omega0() / (1.0 - rva);
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (angle(t) - angle(t - mid) < kTwoPi ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }

  double spectral_radius(double b, int revolutions) const {
    const double rev = 60.0 / rpm, w = kTwoPi * f_hz, m = k / (w * w);
    const double h_target = std::min(rev / steps_per_cycle, 1.0 / (steps_per_cycle * f_hz));
    const int per_rev = static_cast<int>(std::ceil(rev / h_target - 1e-9));
    const int M = per_rev * revolutions;
    const double T = revolutions * rev, h = T / M;
    // ẏ = A y + e₂ g u(t), y = [x; ẋ], u = x(t − τ(t)).
    Eigen::Matrix2d A;
    A << 0.0, 1.0, -w * w - kf * b / m, -2.0 * zeta * w;
    const double g = kf * b / m;
    Eigen::Matrix4d aug = Eigen::Matrix4d::Zero();
    aug.topLeftCorner<2, 2>() = A * h;
    aug(1, 2) = g * h;
    aug(2, 3) = 1.0;
    const Eigen::Matrix4d E = aug.exp();
    const Eigen::Matrix2d P = E.topLeftCorner<2, 2>();
    const Eigen::Vector2d G1 = E.block<2, 1>(0, 2), G2 = E.block<2, 1>(0, 3);
    // Delayed positions (in steps) at every boundary, and the history length.
    std::vector<double> u(static_cast<std::size_t>(M) + 1);
    int L = 1;
    for (int i = 0; i <= M; ++i) {
      u[static_cast<std::size_t>(i)] = (i * h - delay(i * h)) / h;
      L = std::max(L, 1 - static_cast<int>(std::floor(u[static_cast<std::size_t>(i)])));
    }
    // State: [x(0), ẋ(0), x(−h), …, x(−L h)].
    const int dim = 2 + L;
    Eigen::MatrixXd Phi(dim, dim);
    std::vector<double> X(static_cast<std::size_t>(L + M + 2));  // X[L + k] = x(k h)
    for (int col = 0; col < dim; ++col) {
      Eigen::VectorXd y0 = Eigen::VectorXd::Unit(dim, col);
      Eigen::Vector2d y(y0(0), y0(1));
      for (int l = 1; l <= L; ++l) X[static_cast<std::size_t>(L - l)] = y0(1 + l);
      X[static_cast<std::size_t>(L)] = y(0);
      auto sample = [&](double pos) {
        const double f = std::floor(pos);
        const double frac = pos - f;
        const auto k0 = static_cast<std::size_t>(L + static_cast<int>(f));
        return frac == 0.0 ? X[k0] : (1.0 - frac) * X[k0] + frac * X[k0 + 1];
      };
      for (int i = 0; i < M; ++i) {
        const double c0 = sample(u[static_cast<std::size_t>(i)]), c1 = sample(u[static_cast<std::size_t>(i) + 1]);
        y = P * y + G1 * c0 + G2 * (c1 - c0);
        X[static_cast<std::size_t>(L + i + 1)] = y(0);
      }
      Phi(0, col) = y(0);
      Phi(1, col) = y(1);
      for (int l = 1; l <= L; ++l) Phi(1 + l, col) = X[static_cast<std::size_t>(L + M - l)];
    }
    return Phi.eigenvalues().cwiseAbs().maxCoeff();
  }
};

TEST(SsvSdm, AgreesWithAnIndependentSemiDiscretisation) {
  // Coarse steps (16 per cycle) keep the dense monodromy small (~350).
  constexpr int kSteps = 16;
  SemiDiscretizationOptions o;
  o.steps_per_period = kSteps;
  o.steps_per_vibration_cycle = kSteps;
  o.collocation_nodes = 0;  // the independent scheme's first-order steps
  struct Point {
    double rpm, rva, rvf, depth_mm;
  };
  for (const Point& pt : {Point{300.0, 0.1, 0.1, 2.0}, Point{300.0, 0.2, 0.25, 3.0}, Point{600.0, 0.15, 0.5, 1.5}}) {
    const SemiDiscretizationSolver sdm(case_a(), turning_a(pt.rva, pt.rvf), o);
    const FloquetResult fr = sdm.analyse(pt.rpm, pt.depth_mm * 1e-3);
    const SpeedVariationPeriod per = speed_variation_period(turning_a(pt.rva, pt.rvf), pt.rpm);
    ASSERT_TRUE(per.exact);
    const IndependentSsv ind{kA_f, kA_zeta, kA_k, kA_Kf, pt.rpm, pt.rva, pt.rvf, kSteps};
    const double rho = ind.spectral_radius(pt.depth_mm * 1e-3, static_cast<int>(per.floquet_periods));
    EXPECT_NEAR(fr.spectral_radius / rho, 1.0, kIndependentRho)
        << pt.rpm << " rev/min, R_VA " << pt.rva << ", R_VF " << pt.rvf << ", " << pt.depth_mm << " mm: library "
        << fr.spectral_radius << ", independent " << rho;
    EXPECT_NEAR(fr.period_s, per.period_s, 1e-12);
  }
}

// The first depth from 0 where the independent ρ reaches 1: scanned in
// `scan_m` steps, then bisected to 1e-6 relative.
double independent_limit(IndependentSsv ind, int revolutions, double scan_m) {
  double lo = 0.0, hi = scan_m;
  while (ind.spectral_radius(hi, revolutions) < 1.0) {
    lo = hi;
    hi += scan_m;
  }
  while (hi - lo > 1e-6 * hi) {
    const double mid = 0.5 * (lo + hi);
    (ind.spectral_radius(mid, revolutions) < 1.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(SsvSdm, CaseAGainAgreesWithTheIndependentSemiDiscretisation) {
  // Case A, R_VA = 0.1, R_VF = 0.1 (ten revolutions per modulation period).
  // Low speed (300 rev/min, 56 vibration cycles per revolution): SSV about
  // doubles the limit; at the top of lobe k = 2 (1 900 rev/min) it adds
  // little. Both gains from the library against the same first-order
  // scheme written above (16 steps per cycle for both, to keep it small).
  constexpr int kSteps = 16;
  SemiDiscretizationOptions o;
  o.steps_per_period = kSteps;
  o.steps_per_vibration_cycle = kSteps;
  o.collocation_nodes = 0;  // the independent scheme's first-order steps
  const SemiDiscretizationSolver steady(case_a(), turning_a(0.0), o), ssv(case_a(), turning_a(0.1, 0.1), o);
  double gain_low = 0.0, gain_peak = 0.0;
  for (double rpm : {300.0, 1900.0}) {
    const double lib = ssv.limit_at(SpindleSpeed(rpm)).depth_limit_m / steady.limit_at(SpindleSpeed(rpm)).depth_limit_m;
    const IndependentSsv with{kA_f, kA_zeta, kA_k, kA_Kf, rpm, 0.1, 0.1, kSteps};
    IndependentSsv without = with;
    without.rva = 0.0;
    const double ind = independent_limit(with, 10, 2e-4) / independent_limit(without, 1, 2e-4);
    EXPECT_NEAR(lib / ind, 1.0, kIndependentGain) << rpm << " rev/min: gain " << lib << " (library), " << ind
                                                  << " (independent)";
    (rpm < 1000.0 ? gain_low : gain_peak) = lib;
  }
  // The physics: a large gain where the lobes are dense, a small one on a lobe top.
  EXPECT_GT(gain_low, 1.5) << "low-speed gain " << gain_low;
  EXPECT_LT(std::abs(gain_peak - 1.0), 0.2) << "gain near the lobe peak " << gain_peak;
}

}  // namespace
}  // namespace chatter
