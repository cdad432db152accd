// The `analytic` transfer-function solver against closed forms, residuals of
// the characteristic equation and an independent brute-force root scan.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include "chatter/error.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

using C = std::complex<double>;
constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Tolerances (relative unless said otherwise).
constexpr double kClosedForm = 1e-9;   // issue: absolute limit of case A to 1e-9
constexpr double kResidual = 1e-9;     // |characteristic function| at a reported root (O(1) terms)
constexpr double kBruteForce = 1e-6;   // scan of 400 000 points, linear root interpolation
constexpr double kScaling = 1e-9;      // exact invariances, round-off only

// docs/physics.md case A.
constexpr double kA_f = 94.22, kA_zeta = 0.033, kA_k = 45e6, kA_Kf = 2.4e9;

StructuralModel case_a_model(double zeta = kA_zeta, double k = kA_k) {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(kA_f, zeta, k, {1.0, 0.0}));
  return m;
}

TransferFunctionOptions depth_max(double m) {
  TransferFunctionOptions o;
  o.depth_max_m = m;
  return o;
}

// Receptance of one mode, written here from docs/physics.md §2.
C g1(double w, double f, double zeta, double k) {
  const double r = w / (2 * kPi * f);
  return 1.0 / (k * C(1 - r * r, 2 * zeta * r));
}

TEST(AnalyticCaseA, AbsoluteLimitIsTlustyClosedForm) {
  const AnalyticSolver s(case_a_model(), Process::turning({kA_Kf}), depth_max(0.02));
  const double closed = 2 * kA_k * kA_zeta * (1 + kA_zeta) / kA_Kf;  // 1.2783 mm
  const AbsoluteLimit a = s.absolute_limit();
  EXPECT_NEAR(a.depth_m / closed, 1.0, kClosedForm) << a.depth_m << " vs " << closed;
  // Where Re G is minimal: r² = 1 + 2ζ.
  EXPECT_NEAR(a.chatter_frequency_hz / (kA_f * std::sqrt(1 + 2 * kA_zeta)), 1.0, 1e-6);
}

TEST(AnalyticCaseA, ResidualOfCharacteristicEquationAtReportedRoots) {
  const AnalyticSolver s(case_a_model(), Process::turning({kA_Kf}), depth_max(0.05));
  for (double rpm : {55.0, 100.0, 333.0, 612.0, 1000.0, 1234.5, 2000.0, 3600.0, 5000.0, 7000.0}) {
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(l.bounded()) << rpm;
    const double w = 2 * kPi * l.chatter_frequency_hz, tau = 60.0 / rpm;
    const C res = 1.0 + l.depth_limit_m * (1.0 - std::exp(C(0, -w * tau))) * kA_Kf * g1(w, kA_f, kA_zeta, kA_k);
    EXPECT_LT(std::abs(res), kResidual) << "at " << rpm << " rev/min";
    // The lobe number satisfies ωτ = ε + 2πk with ε in (0, 2π).
    const double eps = w * tau - 2 * kPi * l.lobe;
    EXPECT_GT(eps, 0.0);
    EXPECT_LT(eps, 2 * kPi);
    EXPECT_GE(l.depth_limit_m, 2 * kA_k * kA_zeta * (1 + kA_zeta) / kA_Kf * (1 - kClosedForm));
  }
}

// Independent check that no root is missed: at a fixed delay, scan ω on a
// uniform grid, find every sign change of wrap(ωτ − ε(ω)) and take the
// lowest depth. The solver's envelope must equal it.
double brute_force_envelope(const AnalyticSolver& s, double tau, int branches) {
  const auto band = s.band();
  const int n = 400000;
  double best = kInf;
  std::array<C, 2> prev{};
  std::array<double, 2> gprev{};
  for (int i = 0; i < n; ++i) {
    const double w = band.omega_min_rad_s + (band.omega_max_rad_s - band.omega_min_rad_s) * i / (n - 1);
    auto l = s.eigenvalues(w);
    if (i > 0 && branches == 2 &&
        std::abs(l[1] - prev[0]) + std::abs(l[0] - prev[1]) < std::abs(l[0] - prev[0]) + std::abs(l[1] - prev[1]))
      std::swap(l[0], l[1]);
    for (int b = 0; b < branches; ++b) {
      const double eps = 3 * kPi + 2 * std::arg(l[b]);
      const double g = std::remainder(w * tau - eps, 2 * kPi);
      if (i > 0 && gprev[b] < 0 && g >= 0 && g - gprev[b] < kPi) {
        const double t = -gprev[b] / (g - gprev[b]);
        const C lam = prev[b] + t * (l[b] - prev[b]);
        if (lam.real() < 0) best = std::min(best, -1.0 / (2 * lam.real()));
      }
      gprev[b] = g;
    }
    prev = l;
  }
  return best;
}

TEST(AnalyticCaseA, EnvelopeEqualsBruteForceScan) {
  const AnalyticSolver s(case_a_model(), Process::turning({kA_Kf}), depth_max(0.02));
  for (double rpm : {80.0, 450.0, 1500.0, 3000.0, 6500.0}) {
    const double brute = brute_force_envelope(s, 60.0 / rpm, 1);
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(std::isfinite(brute));
    EXPECT_NEAR(l.depth_limit_m / brute, 1.0, kBruteForce) << "at " << rpm << " rev/min";
  }
}

TEST(AnalyticOblique, EnvelopeEqualsBruteForceScanOnTwoBranches) {
  // Half-immersion up-milling on a tool with two oblique modes: H₀ has full
  // rank, both eigenvalue branches of H₀G matter.
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(600.0, 0.02, 0.2, {1.0, 0.3}));
  m.tool.modes.push_back(Mode::from_mass(750.0, 0.03, 0.25, {-0.2, 1.0}));
  const Process p = Process::milling({4, 6e8, 2e8, 0.5, MillingDirection::kUp});
  const AnalyticSolver s(m, p, depth_max(0.02));
  for (double rpm : {3000.0, 7000.0, 12000.0}) {
    const double brute = brute_force_envelope(s, p.delay_s(rpm), 2);
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(std::isfinite(brute)) << rpm;
    EXPECT_NEAR(l.depth_limit_m / brute, 1.0, kBruteForce) << "at " << rpm << " rev/min";
  }
}

std::vector<StabilityLimit> sweep(const StructuralModel& m, double kf) {
  const AnalyticSolver s(m, Process::turning({kf}), depth_max(0.2));
  return lobe_envelope(s, evenly_spaced_speeds(100.0, 8000.0, 150));
}

TEST(AnalyticPhysics, MoreDampingOrStiffnessRaisesEveryLimit) {
  const auto base = sweep(case_a_model(), kA_Kf);
  const auto damped = sweep(case_a_model(kA_zeta * 1.3), kA_Kf);
  const auto stiffer = sweep(case_a_model(kA_zeta, kA_k * 1.3), kA_Kf);
  for (std::size_t i = 0; i < base.size(); ++i) {
    ASSERT_TRUE(base[i].bounded());
    EXPECT_GT(damped[i].depth_limit_m, base[i].depth_limit_m) << base[i].spindle_rpm;
    EXPECT_GT(stiffer[i].depth_limit_m, base[i].depth_limit_m) << base[i].spindle_rpm;
  }
}

TEST(AnalyticPhysics, DepthLimitIsInverselyProportionalToKf) {
  const auto base = sweep(case_a_model(), kA_Kf);
  const auto doubled = sweep(case_a_model(), 2 * kA_Kf);
  for (std::size_t i = 0; i < base.size(); ++i) {
    EXPECT_NEAR(doubled[i].depth_limit_m * 2 / base[i].depth_limit_m, 1.0, kScaling) << base[i].spindle_rpm;
    EXPECT_NEAR(doubled[i].chatter_frequency_hz / base[i].chatter_frequency_hz, 1.0, kScaling);
    EXPECT_EQ(doubled[i].lobe, base[i].lobe);
  }
}

TEST(AnalyticPhysics, NoInstabilityBelowDepthMaxIsInfinity) {
  // Case A at 0.5 mm search depth: below the absolute limit, so every speed is stable.
  const AnalyticSolver s(case_a_model(), Process::turning({kA_Kf}), depth_max(0.0005));
  for (const auto& l : lobe_envelope(s, evenly_spaced_speeds(100, 3000, 20))) {
    EXPECT_FALSE(l.bounded());
    EXPECT_EQ(l.depth_limit_m, kInf);
    EXPECT_EQ(l.lobe, -1);
  }
  EXPECT_EQ(s.absolute_limit().depth_m, kInf);
}

// Zeroth-order milling (Altintas & Budak), 1-DOF along X: λ = H₀xx G with
// H₀xx = (N_t/2π)[K_t sin²φ/2 + K_r(φ/2 − sin2φ/4)] from φ_en to φ_ex (the
// integral of (K_t cosφ + K_r sinφ) sinφ). Re G ranges over
// [−1/(4kζ(1+ζ)), 1/(4kζ(1−ζ))], so the absolute limit is
// 2kζ(1+ζ)/H₀xx if H₀xx > 0 and 2kζ(1−ζ)/(−H₀xx) if H₀xx < 0.
double h0xx(int teeth, double kt, double kr, double en, double ex) {
  auto F = [&](double p) { return kt * std::sin(p) * std::sin(p) / 2 + kr * (p / 2 - std::sin(2 * p) / 4); };
  return teeth / (2 * kPi) * (F(ex) - F(en));
}

class ZerothOrderMilling1Dof : public ::testing::TestWithParam<std::pair<double, MillingDirection>> {};

TEST_P(ZerothOrderMilling1Dof, AbsoluteLimitAndRootsMatchClosedForm) {
  const auto [ae, dir] = GetParam();
  const double f = 922, zeta = 0.011, mass = 0.03993;  // docs/physics.md case C
  const double k = mass * std::pow(2 * kPi * f, 2);
  const double en = dir == MillingDirection::kDown ? std::acos(2 * ae - 1) : 0.0;
  const double ex = dir == MillingDirection::kDown ? kPi : std::acos(1 - 2 * ae);
  const double h = h0xx(2, 6e8, 2e8, en, ex);
  const double closed = h > 0 ? 2 * k * zeta * (1 + zeta) / h : 2 * k * zeta * (1 - zeta) / (-h);
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(f, zeta, mass, {1.0, 0.0}));
  const Process p = Process::milling({2, 6e8, 2e8, ae, dir});
  const AnalyticSolver s(m, p, depth_max(0.5));
  EXPECT_NEAR(s.absolute_limit().depth_m / closed, 1.0, kClosedForm) << "H0xx = " << h;
  for (double rpm : {5000.0, 9000.0, 14000.0, 21000.0}) {
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    if (!l.bounded()) continue;
    const double w = 2 * kPi * l.chatter_frequency_hz;
    const C lam = h * g1(w, f, zeta, k);
    EXPECT_NEAR(l.depth_limit_m * (-2 * lam.real()), 1.0, 1e-9) << rpm;
    const double eps = std::fmod(3 * kPi + 2 * std::arg(lam), 2 * kPi);
    EXPECT_NEAR(60.0 / (2 * (eps + 2 * kPi * l.lobe) / w), rpm, 1e-7 * rpm);
  }
}
INSTANTIATE_TEST_SUITE_P(Immersions, ZerothOrderMilling1Dof,
                         ::testing::Values(std::pair{0.05, MillingDirection::kDown}, std::pair{0.5, MillingDirection::kDown},
                                           std::pair{1.0, MillingDirection::kDown}, std::pair{0.1, MillingDirection::kUp}));

TEST(ZerothOrderMillingSymmetric, SlottingMatchesEigenvaluesOfH0) {
  // Symmetric tool (identical modes along X and Y): G = g I, so the
  // eigenvalues of H₀G are g μ with μ the eigenvalues of H₀. For slotting
  // H₀ = (N_t/4)[[K_r, K_t], [−K_t, K_r]], μ = (N_t/4)(K_r ± j K_t), and the
  // limit is a(ω) = −1/(2 Re(g μ)) minimised over ω and both μ.
  const double f = 922, zeta = 0.011, mass = 0.03993, kt = 6e8, kr = 2e8;
  const int teeth = 3;
  const double k = mass * std::pow(2 * kPi * f, 2);
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(f, zeta, mass, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(f, zeta, mass, {0.0, 1.0}));
  const AnalyticSolver s(m, Process::milling({teeth, kt, kr, 1.0, MillingDirection::kDown}), depth_max(0.5));
  const std::array<C, 2> mu{teeth / 4.0 * C(kr, kt), teeth / 4.0 * C(kr, -kt)};
  auto depth = [&](double w, const C& u) {
    const double re = (g1(w, f, zeta, k) * u).real();
    return re < 0 ? -1.0 / (2 * re) : kInf;
  };
  // Minimum of the closed form by golden section on a bracket from a scan.
  double closed = kInf;
  for (const C& u : mu) {
    double wbest = 0, dbest = kInf;
    for (int i = 1; i < 200000; ++i) {
      const double w = 2 * kPi * f * (0.5 + 1.5 * i / 200000.0);
      if (depth(w, u) < dbest) { dbest = depth(w, u); wbest = w; }
    }
    double lo = wbest * (1 - 1e-4), hi = wbest * (1 + 1e-4);
    for (int it = 0; it < 200; ++it) {
      const double a = lo + (hi - lo) * 0.382, b = lo + (hi - lo) * 0.618;
      if (depth(a, u) < depth(b, u)) hi = b; else lo = a;
    }
    closed = std::min(closed, depth(0.5 * (lo + hi), u));
  }
  EXPECT_NEAR(s.absolute_limit().depth_m / closed, 1.0, kClosedForm);
  for (double rpm : {6000.0, 11000.0, 17000.0}) {
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(l.bounded());
    const double w = 2 * kPi * l.chatter_frequency_hz;
    const double d = std::min(depth(w, mu[0]), depth(w, mu[1]));
    const double other = std::max(depth(w, mu[0]), depth(w, mu[1]));
    // The reported depth belongs to one of the two branches.
    EXPECT_TRUE(std::abs(l.depth_limit_m / d - 1) < 1e-9 || std::abs(l.depth_limit_m / other - 1) < 1e-9)
        << rpm << ": " << l.depth_limit_m << " vs " << d << " / " << other;
  }
}

TEST(AnalyticInput, RefusesBadOptionsAndRigidModels) {
  EXPECT_THROW(AnalyticSolver(case_a_model(), Process::turning({kA_Kf}), depth_max(0.0)), InputError);
  EXPECT_THROW(AnalyticSolver(case_a_model(), Process::turning({kA_Kf}), depth_max(-1.0)), InputError);
  EXPECT_THROW(AnalyticSolver(StructuralModel{}, Process::turning({kA_Kf})), InputError);
  const AnalyticSolver s(case_a_model(), Process::turning({kA_Kf}), depth_max(0.02));
  EXPECT_THROW(s.limit_at(SpindleSpeed(0.0)), InputError);
  EXPECT_THROW(s.limit_at(SpindleSpeed(-100.0)), InputError);
  EXPECT_THROW(s.limit_at(SpindleSpeed(NAN)), InputError);
}

TEST(AnalyticInput, AbsurdlyLowSpeedIsRefusedNotLooped) {
  // 0.001 rev/min: one revolution holds ~14 million vibration cycles.
  const AnalyticSolver s(case_a_model(), Process::turning({kA_Kf}), depth_max(0.02));
  try {
    s.limit_at(SpindleSpeed(0.001));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("spindle speed 0.001 rev/min"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("raise the spindle speed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(s.lobe_curves(SpindleSpeed(0.001), SpindleSpeed(1.0)), InputError);
}

TEST(AnalyticPhysics, ModeOrthogonalToTheChipCannotChatter) {
  // Turning cuts along X; a structure flexible only along Y is never excited
  // (found by fuzzing: this used to be an internal error).
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(190.58, 0.025, 5.092e6, {0.0, 1.0}));
  const AnalyticSolver a(m, Process::turning({684e6}), depth_max(0.02));
  const CoupledSolver c(m, Process::turning({684e6}), depth_max(0.02));
  for (double rpm : {500.0, 5000.0}) {
    EXPECT_FALSE(a.limit_at(SpindleSpeed(rpm)).bounded());
    EXPECT_FALSE(c.limit_at(SpindleSpeed(rpm)).bounded());
  }
  EXPECT_FALSE(std::isfinite(a.absolute_limit().depth_m));
  EXPECT_TRUE(a.lobe_curves(SpindleSpeed(500), SpindleSpeed(5000)).empty());
}

TEST(AnalyticCurves, LobePointsLieOnTheEnvelopeOrAbove) {
  const AnalyticSolver s(case_a_model(), Process::turning({kA_Kf}), depth_max(0.02));
  const auto curves = s.lobe_curves(SpindleSpeed(500), SpindleSpeed(3000));
  ASSERT_FALSE(curves.empty());
  std::size_t checked = 0;
  for (const auto& c : curves)
    for (std::size_t i = 0; i < c.points.size(); i += 7) {
      const LobePoint& p = c.points[i];
      ASSERT_GE(p.spindle_rpm, 500);
      ASSERT_LE(p.spindle_rpm, 3000);
      const StabilityLimit l = s.limit_at(SpindleSpeed(p.spindle_rpm));
      EXPECT_LE(l.depth_limit_m, p.depth_m * (1 + 1e-9));
      ++checked;
    }
  EXPECT_GT(checked, 50u);
}

}  // namespace
}  // namespace chatter
