// The structural-mode description: receptance, modal/state-space views and
// the cantilever-bar helper, against hand formulas and the seed's table IV.1.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/LU>

#include "chatter/error.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRoundOff = 1e-12;  // relative: closed forms evaluated in double

StructuralModel two_body_oblique() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(420.0, 0.02, 5.0, {1.0, 1.0}));
  m.workpiece.modes.push_back(Mode::from_stiffness(326.71, 0.025, 43.972e6, {0.0, 1.0}));
  return m;
}

TEST(Mode, ReceptanceIsTheSingleDofFormula) {
  const Mode m = Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0});
  const double wn = 2 * kPi * 94.22;
  for (double r : {0.0, 0.5, 1.0, 1.033, 2.0}) {
    const std::complex<double> expected = 1.0 / (45e6 * std::complex<double>(1 - r * r, 2 * 0.033 * r));
    EXPECT_NEAR(std::abs(m.receptance(r * wn) - expected), 0.0, kRoundOff * std::abs(expected));
  }
  // At resonance the receptance is −j/(2kζ).
  EXPECT_NEAR(m.receptance(wn).imag(), -1.0 / (2 * 45e6 * 0.033), kRoundOff / (2 * 45e6 * 0.033));
}

TEST(Mode, MassAndStiffnessAreTheSameMode) {
  const Mode a = Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0});
  const double w = 2 * kPi * 922.0;
  EXPECT_NEAR(a.stiffness_n_per_m, 0.03993 * w * w, kRoundOff * a.stiffness_n_per_m);
  EXPECT_NEAR(a.mass_kg(), 0.03993, kRoundOff);
}

TEST(Mode, DirectionIsNormalised) {
  const Mode m = Mode::from_stiffness(100, 0.05, 1e7, {3.0, 4.0});
  EXPECT_NEAR(m.direction.x(), 0.6, kRoundOff);
  EXPECT_NEAR(m.direction.y(), 0.8, kRoundOff);
}

TEST(Mode, NonPhysicalValuesAreRefused) {
  const Eigen::Vector2d x{1.0, 0.0};
  EXPECT_THROW(Mode::from_stiffness(0.0, 0.03, 1e7, x), chatter::InputError);
  EXPECT_THROW(Mode::from_stiffness(100, 0.0, 1e7, x), chatter::InputError);
  EXPECT_THROW(Mode::from_stiffness(100, 1.0, 1e7, x), chatter::InputError);
  EXPECT_THROW(Mode::from_stiffness(100, 0.03, -1.0, x), chatter::InputError);
  EXPECT_THROW(Mode::from_stiffness(100, 0.03, 1e7, {0.0, 0.0}), chatter::InputError);
  EXPECT_THROW(Mode::from_mass(100, 0.03, 0.0, x), chatter::InputError);
  EXPECT_THROW(Mode::from_stiffness(NAN, 0.03, 1e7, x), chatter::InputError);
}

TEST(Body, ReceptanceSumsOrientedModes) {
  const StructuralModel m = two_body_oblique();
  const double w = 2 * kPi * 150.0;
  Matrix2c expected = Matrix2c::Zero();
  for (const Body* b : {&m.tool, &m.workpiece})
    for (const Mode& md : b->modes) {
      const double r = w / md.omega();
      const std::complex<double> h = 1.0 / (md.stiffness_n_per_m * std::complex<double>(1 - r * r, 2 * md.damping_ratio * r));
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) expected(i, j) += h * md.direction(i) * md.direction(j);
    }
  const Matrix2c G = m.receptance(w);
  EXPECT_LT((G - expected).norm(), kRoundOff * expected.norm());
  EXPECT_LT((G - G.transpose()).norm(), kRoundOff * G.norm()) << "receptance must be symmetric";
  EXPECT_LT((G - m.tool.receptance(w) - m.workpiece.receptance(w)).norm(), kRoundOff * G.norm());
}

TEST(StateSpace, TransferFunctionEqualsReceptance) {
  // C (jωI − A)⁻¹ B must reproduce G_tool + G_workpiece: the workpiece sign
  // s_i = −1 appears twice (force and displacement) and cancels.
  const StructuralModel m = two_body_oblique();
  const StateSpace ss = state_space(m);
  ASSERT_EQ(ss.A.rows(), 6);
  for (double f : {10.0, 100.66, 200.0, 326.71, 1000.0}) {
    const double w = 2 * kPi * f;
    const Eigen::MatrixXcd jwI = std::complex<double>(0, w) * Eigen::MatrixXcd::Identity(6, 6);
    const Eigen::MatrixXcd T = ss.C.cast<std::complex<double>>() *
                               (jwI - ss.A.cast<std::complex<double>>()).partialPivLu().solve(ss.B.cast<std::complex<double>>());
    const Matrix2c G = m.receptance(w);
    EXPECT_LT((T - G).norm(), 1e-10 * G.norm()) << "at " << f << " Hz";
  }
}

TEST(ModalMatrices, SignsAndOrder) {
  const ModalMatrices mm = modal_matrices(two_body_oblique());
  ASSERT_EQ(mm.S.cols(), 3);
  EXPECT_DOUBLE_EQ(mm.S(0, 0), 1.0);   // tool mode along +X
  EXPECT_DOUBLE_EQ(mm.S(1, 2), -1.0);  // workpiece mode along Y, s = −1
  EXPECT_NEAR(mm.mass_kg(1), 5.0, kRoundOff);
}

// Seed thesis table IV.1 (docs/physics.md case B): steel bar E = 180 GPa, ρ = 7600.
struct BarCase {
  double length, diameter, k_expected, f_expected;
};
class CantileverTable : public ::testing::TestWithParam<BarCase> {};

TEST_P(CantileverTable, MatchesSeedTable) {
  const BarCase c = GetParam();
  const Mode m = first_bending_mode({180e9, 7600.0, c.length, c.diameter}, 0.025, {1.0, 0.0});
  // The table is printed to 5 significant digits.
  EXPECT_NEAR(m.stiffness_n_per_m / c.k_expected, 1.0, 1e-4);
  EXPECT_NEAR(m.natural_frequency_hz / c.f_expected, 1.0, 3e-4);
  EXPECT_DOUBLE_EQ(m.damping_ratio, 0.025);
}
INSTANTIATE_TEST_SUITE_P(SeedTableIV1, CantileverTable,
                         ::testing::Values(BarCase{0.5, 0.12, 43.972e6, 326.71}, BarCase{0.5, 0.07, 5.092e6, 190.58},
                                           BarCase{0.25, 0.12, 351.778e6, 1306.82},
                                           BarCase{0.25, 0.07, 40.732e6, 762.31}));

TEST(Cantilever, RefusesNonPhysicalBars) {
  EXPECT_THROW(first_bending_mode({0.0, 7600, 0.5, 0.1}, 0.02, {1, 0}), chatter::InputError);
  EXPECT_THROW(first_bending_mode({180e9, 7600, -0.5, 0.1}, 0.02, {1, 0}), chatter::InputError);
  EXPECT_THROW(first_bending_mode({180e9, 7600, 0.5, 0.1}, 1.2, {1, 0}), chatter::InputError);
}

}  // namespace
}  // namespace chatter
