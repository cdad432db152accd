// The `coupled` solver (characteristic determinant of the modal system)
// against the `analytic` solver (eigenvalues of H₀G), against the closed-form
// two-body equation of docs/physics.md §4, and in the rigid-body limit.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

using C = std::complex<double>;
constexpr double kPi = std::numbers::pi;

// The two solvers share no algebra, only the root search; agreement is
// limited by round-off in each characteristic function (issue: 1e-8).
constexpr double kMethodsAgree = 1e-8;
// A body 10⁶ times stiffer changes the compliance sum by ~1e-6 relative.
constexpr double kRigidLimit = 1e-5;
constexpr double kResidual = 1e-9;

// docs/physics.md case B: K_f = 2000e6·cos 70°, tool cond. 1 or 2, workpiece cond. 1 or 2.
constexpr double kKf = 684e6;
StructuralModel case_b(int cond) {
  StructuralModel m;
  if (cond == 1) {
    m.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1, 0}));
    m.workpiece.modes.push_back(Mode::from_stiffness(326.71, 0.025, 43.972e6, {1, 0}));
  } else {
    m.tool.modes.push_back(Mode::from_stiffness(185.0, 0.032, 7.465e6, {1, 0}));
    m.workpiece.modes.push_back(Mode::from_stiffness(190.58, 0.025, 5.092e6, {1, 0}));
  }
  return m;
}

TransferFunctionOptions depth_max(double d) {
  TransferFunctionOptions o;
  o.depth_max_m = d;
  return o;
}

void expect_same_envelope(const TransferFunctionSolver& a, const TransferFunctionSolver& b,
                          const std::vector<double>& speeds) {
  int bounded = 0;
  for (double rpm : speeds) {
    const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lb = b.limit_at(SpindleSpeed(rpm));
    ASSERT_EQ(la.bounded(), lb.bounded()) << rpm;
    if (!la.bounded()) continue;
    ++bounded;
    EXPECT_NEAR(lb.depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree) << "depth at " << rpm << " rev/min";
    EXPECT_NEAR(lb.chatter_frequency_hz / la.chatter_frequency_hz, 1.0, kMethodsAgree) << "frequency at " << rpm;
    EXPECT_EQ(lb.lobe, la.lobe) << rpm;
  }
  EXPECT_GT(bounded, static_cast<int>(speeds.size()) / 2) << "too few bounded speeds to compare";
}

class CaseB : public ::testing::TestWithParam<int> {};

TEST_P(CaseB, CoupledAgreesWithAnalytic) {
  const StructuralModel m = case_b(GetParam());
  const AnalyticSolver a(m, Process::turning({kKf}), depth_max(0.05));
  const CoupledSolver c(m, Process::turning({kKf}), depth_max(0.05));
  expect_same_envelope(a, c, evenly_spaced_speeds(300.0, 16000.0, 300));
  EXPECT_NEAR(c.absolute_limit().depth_m / a.absolute_limit().depth_m, 1.0, kMethodsAgree);
}

TEST_P(CaseB, ResidualOfTheTwoBodyEquation) {
  // m₁φ₁ m₂φ₂ + K_f b (1 − e^{−jωτ}) (m₁φ₁ + m₂φ₂) = 0, φ_i = ω_i² − ω² + 2jζ_iω_iω.
  const StructuralModel m = case_b(GetParam());
  const CoupledSolver c(m, Process::turning({kKf}), depth_max(0.05));
  const Mode& t = m.tool.modes[0];
  const Mode& w = m.workpiece.modes[0];
  for (double rpm : {700.0, 2500.0, 6100.0, 9000.0, 14000.0}) {
    const StabilityLimit l = c.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(l.bounded()) << rpm;
    const double om = 2 * kPi * l.chatter_frequency_hz, tau = 60.0 / rpm;
    auto mphi = [&](const Mode& md) {
      return md.mass_kg() * C(md.omega() * md.omega() - om * om, 2 * md.damping_ratio * md.omega() * om);
    };
    const C a = mphi(t) * mphi(w);
    const C b = kKf * l.depth_limit_m * (1.0 - std::exp(C(0, -om * tau))) * (mphi(t) + mphi(w));
    EXPECT_LT(std::abs(a + b) / (std::abs(a) + std::abs(b)), kResidual) << rpm;
  }
}
INSTANTIATE_TEST_SUITE_P(ToolAndWorkpieceConditions, CaseB, ::testing::Values(1, 2));

TEST(Coupled, AgreesWithAnalyticOnOrientedMillingWithTwoBranches) {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(600.0, 0.02, 0.2, {1.0, 0.3}));
  m.tool.modes.push_back(Mode::from_mass(750.0, 0.03, 0.25, {-0.2, 1.0}));
  m.workpiece.modes.push_back(Mode::from_stiffness(1100.0, 0.015, 4e7, {0.0, 1.0}));
  const Process p = Process::milling({4, 6e8, 2e8, 0.5, MillingDirection::kUp});
  const AnalyticSolver a(m, p, depth_max(0.02));
  const CoupledSolver c(m, p, depth_max(0.02));
  expect_same_envelope(a, c, evenly_spaced_speeds(2000.0, 20000.0, 200));
}

TEST(Coupled, VeryStiffToolReproducesTheOneDofWorkpiece) {
  // Case A workpiece with a tool mode 10⁶ times stiffer (same mass scale).
  StructuralModel one;
  one.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1, 0}));
  StructuralModel two = one;
  two.tool.modes.push_back(Mode::from_stiffness(94.22e3, 0.03, 45e12, {1, 0}));
  const AnalyticSolver ref(one, Process::turning({2.4e9}), depth_max(0.02));
  const CoupledSolver c(two, Process::turning({2.4e9}), depth_max(0.02));
  for (double rpm : evenly_spaced_speeds(60.0, 6000.0, 60)) {
    const StabilityLimit lr = ref.limit_at(SpindleSpeed(rpm)), lc = c.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(lr.bounded() && lc.bounded()) << rpm;
    EXPECT_NEAR(lc.depth_limit_m / lr.depth_limit_m, 1.0, kRigidLimit) << rpm;
    EXPECT_NEAR(lc.chatter_frequency_hz / lr.chatter_frequency_hz, 1.0, kRigidLimit) << rpm;
  }
  EXPECT_NEAR(c.absolute_limit().depth_m / (2 * 45e6 * 0.033 * 1.033 / 2.4e9), 1.0, kRigidLimit);
}

TEST(Coupled, SwappingWhichBodyHoldsAModeLeavesTurningLobesUnchanged) {
  // The compliances add, so moving a mode from workpiece to tool changes nothing.
  StructuralModel swapped;
  swapped.tool = case_b(1).workpiece;
  swapped.workpiece = case_b(1).tool;
  const CoupledSolver a(case_b(1), Process::turning({kKf}), depth_max(0.05));
  const CoupledSolver b(swapped, Process::turning({kKf}), depth_max(0.05));
  expect_same_envelope(a, b, evenly_spaced_speeds(500.0, 12000.0, 80));
}

TEST(Coupled, SeedSignErrorWouldGiveDifferentLobes) {
  // The seed (eqs. III-29/32) subtracts the two compliances. Show the
  // difference is not small on case B 1, so the sign is actually tested:
  // the correct G = G₁ + G₂ gives the reported depth, G₁ − G₂ does not.
  const StructuralModel m = case_b(1);
  const CoupledSolver c(m, Process::turning({kKf}), depth_max(0.05));
  const StabilityLimit l = c.limit_at(SpindleSpeed(3000.0));
  ASSERT_TRUE(l.bounded());
  const double w = 2 * kPi * l.chatter_frequency_hz;
  const C g1 = m.tool.modes[0].receptance(w), g2 = m.workpiece.modes[0].receptance(w);
  EXPECT_NEAR(-1.0 / (2 * kKf * (g1 + g2).real()) / l.depth_limit_m, 1.0, 1e-9);
  EXPECT_GT(std::abs(-1.0 / (2 * kKf * (g1 - g2).real()) / l.depth_limit_m - 1.0), 0.05);
}

}  // namespace
}  // namespace chatter
