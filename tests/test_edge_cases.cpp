// Numerical edge cases of issue 8: each either works to the stated accuracy
// or is refused with a message, never a silent wrong number.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

using C = std::complex<double>;
constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kClosedForm = 1e-9;   // relative, round-off of the absolute-limit search
constexpr double kResidual = 1e-9;     // |1 + a(1 − e^{−jωτ}) K_f G| at a reported root
constexpr double kMethodsAgree = 1e-7;
// Two modes 1e-6 apart in frequency act as one of stiffness k/2 up to terms of
// that order: allowed 1e-5.
constexpr double kTwinModes = 1e-5;
// Stiffnesses 1e8 apart: the coupled determinant mixes terms of that ratio and
// loses about that many digits of 1e-16·1e8; allowed 1e-6 between methods.
constexpr double kStiffRatioAgree = 1e-6;
// The rigid mode adds 1e4/1e12 = 1e-8 of the soft mode's compliance: the
// soft closed form holds to that; allowed 1e-6.
constexpr double kStiffShare = 1e-6;
// The sdm discretisation's stated accuracy on the depth limit (docs/sdm.md): 0.5 %.
constexpr double kSdmAccuracy = 5e-3;

TransferFunctionOptions depth_max(double d) {
  TransferFunctionOptions o;
  o.depth_max_m = d;
  return o;
}

StructuralModel one_mode(double f, double zeta, double k) {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(f, zeta, k, {1, 0}));
  return m;
}

double tlusty_min(double k, double zeta, double kf) { return 2 * k * zeta * (1 + zeta) / kf; }

class Damping : public ::testing::TestWithParam<double> {};

TEST_P(Damping, AbsoluteLimitIsTheClosedFormAtBothEnds) {
  // ζ = 1e-6 (the smallest the config accepts): the resonance is 2e-6 wide,
  // the adaptive grid must find it. ζ = 0.99: nearly critical damping.
  const double zeta = GetParam();
  const double kf = 2.4e9, k = 45e6;
  const double closed = tlusty_min(k, zeta, kf);
  const AnalyticSolver s(one_mode(94.22, zeta, k), Process::turning({kf}), depth_max(std::max(0.02, 10 * closed)));
  EXPECT_NEAR(s.absolute_limit().depth_m / closed, 1.0, kClosedForm);
  for (double rpm : {300.0, 3000.0}) {
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(l.bounded()) << rpm;
    EXPECT_GE(l.depth_limit_m, closed * (1 - kClosedForm));
    const double w = kTwoPi * l.chatter_frequency_hz, tau = 60 / rpm;
    const C g = s.model().workpiece.modes[0].receptance(w);
    EXPECT_LT(std::abs(1.0 + l.depth_limit_m * (1.0 - std::exp(C(0, -w * tau))) * kf * g), kResidual) << rpm;
  }
}
INSTANTIATE_TEST_SUITE_P(NearZeroAndNearOne, Damping, ::testing::Values(1e-6, 1e-4, 0.5, 0.99));

TEST(EdgeCases, ModesOneMillionthApartAgreeAcrossMethods) {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(100.0, 0.02, 2e7, {1, 0}));
  m.workpiece.modes.push_back(Mode::from_stiffness(100.0001, 0.02, 2e7, {1, 0}));
  const AnalyticSolver a(m, Process::turning({1e9}), depth_max(0.05));
  const CoupledSolver c(m, Process::turning({1e9}), depth_max(0.05));
  // Two identical modes in series act as one of stiffness k/2.
  EXPECT_NEAR(a.absolute_limit().depth_m / tlusty_min(1e7, 0.02, 1e9), 1.0, kTwinModes);
  for (double rpm : {400.0, 2500.0, 6000.0}) {
    const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lc = c.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(la.bounded() && lc.bounded()) << rpm;
    EXPECT_NEAR(lc.depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree) << rpm;
  }
}

TEST(EdgeCases, VeryStiffNextToVerySoftAgreeAcrossMethods) {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(3000.0, 0.02, 1e12, {1, 0}));  // nearly rigid
  m.workpiece.modes.push_back(Mode::from_stiffness(50.0, 0.03, 1e4, {1, 0}));  // a thin wall
  const AnalyticSolver a(m, Process::turning({1e9}), depth_max(0.05));
  const CoupledSolver c(m, Process::turning({1e9}), depth_max(0.05));
  for (double rpm : {200.0, 2000.0}) {
    const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lc = c.limit_at(SpindleSpeed(rpm));
    ASSERT_EQ(la.bounded(), lc.bounded()) << rpm;
    if (la.bounded()) {
      EXPECT_NEAR(lc.depth_limit_m / la.depth_limit_m, 1.0, kStiffRatioAgree) << rpm;
    }
  }
  // The soft mode dominates: its own closed form, to the stiff mode's share.
  EXPECT_NEAR(a.absolute_limit().depth_m / tlusty_min(1e4, 0.03, 1e9), 1.0, kStiffShare);
}

TEST(EdgeCases, SpindleSpeedsAtTheExtremes) {
  const double kf = 2.4e9;
  const AnalyticSolver s(one_mode(94.22, 0.033, 45e6), Process::turning({kf}), depth_max(0.5));
  // 1 rev/min (5 650 vibration cycles per revolution) and 30 000 rev/min (a
  // revolution a fifth of a vibration period): exact roots.
  for (double rpm : {1.0, 30000.0}) {
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(l.bounded()) << rpm;
    const double w = kTwoPi * l.chatter_frequency_hz, tau = 60 / rpm;
    const C g = s.model().workpiece.modes[0].receptance(w);
    EXPECT_LT(std::abs(1.0 + l.depth_limit_m * (1.0 - std::exp(C(0, -w * tau))) * kf * g), kResidual) << rpm;
  }
  // 10⁶ rev/min: the first lobe would chatter above 8 kHz, far above the
  // mode, at a depth beyond half a metre: no limit below the searched depth.
  EXPECT_FALSE(s.limit_at(SpindleSpeed(1e6)).bounded());
  // Far below: refused with a message, not computed for minutes.
  EXPECT_THROW(s.limit_at(SpindleSpeed(1e-6)), InputError);
}

TEST(EdgeCases, ImmersionNearZeroAndExactlyOne) {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922, 0.011, 0.03993, {1, 0}));
  // One mode along X: H₀G has the single non-zero eigenvalue H₀xx·g(ω), so a
  // reported limit solves 1 + a(1 − e^{−jωτ}) H₀xx g(ω) = 0 and, when
  // H₀xx > 0, lies at or above the 1-DOF minimum 2kζ(1+ζ)/H₀xx.
  int bounded = 0;
  for (double ae : {1e-9, 1e-4, 1.0}) {
    const Process p = Process::milling({2, 6e8, 2e8, ae, MillingDirection::kDown});
    const double hxx = p.average_directional_matrix()(0, 0);
    const Mode& mode = m.tool.modes[0];
    const double floor = 2.0 * mode.stiffness_n_per_m * mode.damping_ratio * (1.0 + mode.damping_ratio) / hxx;
    const AnalyticSolver s(m, p, depth_max(0.05));
    for (double rpm : {6000.0, 20000.0}) {
      const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
      if (!l.bounded()) {
        EXPECT_EQ(l.depth_limit_m, std::numeric_limits<double>::infinity()) << "a_e/D " << ae << ", " << rpm;
        continue;
      }
      ++bounded;
      ASSERT_TRUE(std::isfinite(l.depth_limit_m)) << ae;
      EXPECT_GT(l.depth_limit_m, 0.0) << ae;
      EXPECT_LE(l.depth_limit_m, 0.05) << ae;
      const double w = kTwoPi * l.chatter_frequency_hz, tau = p.delay_s(rpm);
      EXPECT_LT(std::abs(1.0 + l.depth_limit_m * (1.0 - std::exp(C(0, -w * tau))) * hxx * mode.receptance(w)),
                kResidual)
          << "a_e/D " << ae << ", " << rpm << " rev/min: a = " << l.depth_limit_m;
      if (hxx > 0.0) {
        EXPECT_GE(l.depth_limit_m, floor * (1.0 - kClosedForm)) << "1-DOF minimum " << floor;
      }
    }
  }
  EXPECT_GE(bounded, 2) << "full immersion must be bounded at both speeds";
  // a_e/D → 0: the average force vanishes, so no limit below 5 cm.
  const AnalyticSolver thin(m, Process::milling({2, 6e8, 2e8, 1e-9, MillingDirection::kDown}), depth_max(0.05));
  EXPECT_FALSE(thin.limit_at(SpindleSpeed(10000)).bounded());
  EXPECT_THROW(Process::milling({2, 6e8, 2e8, 0.0, MillingDirection::kDown}), chatter::InputError);
  EXPECT_THROW(Process::milling({2, 6e8, 2e8, 1.0 + 1e-12, MillingDirection::kDown}), chatter::InputError);
}

TEST(EdgeCases, DelayMuchShorterThanAVibrationPeriodSdmAgreesWithAnalytic) {
  // Case A at 30 000 rev/min: one revolution is 2 ms, the vibration period 10.6 ms.
  const StructuralModel m = one_mode(94.22, 0.033, 45e6);
  const AnalyticSolver a(m, Process::turning({2.4e9}), depth_max(0.5));
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.5;
  const SemiDiscretizationSolver s(m, Process::turning({2.4e9}), o);
  for (double rpm : {30000.0, 60000.0}) {
    const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), ls = s.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(la.bounded() && ls.bounded()) << rpm;
    EXPECT_NEAR(ls.depth_limit_m / la.depth_limit_m, 1.0, kSdmAccuracy) << rpm;
  }
}

}  // namespace
}  // namespace chatter
