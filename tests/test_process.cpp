// The process: directional matrix against the force law of docs/physics.md §3 and
// H₀ against numerical quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "chatter/error.hpp"
#include "chatter/process.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;

Process case_c(double immersion, MillingDirection dir) {
  return Process::milling({2, 6e8, 2e8, immersion, dir});
}

TEST(Process, TurningDelayIsOneRevolution) {
  const Process p = Process::turning({2.4e9});
  EXPECT_DOUBLE_EQ(p.delay_s(600.0), 0.1);
  EXPECT_DOUBLE_EQ(p.rpm_from_delay(0.1), 600.0);
  const Eigen::Matrix2d H = p.average_directional_matrix();
  EXPECT_DOUBLE_EQ(H(0, 0), 2.4e9);
  EXPECT_DOUBLE_EQ(H(0, 1) + H(1, 0) + H(1, 1), 0.0);
}

TEST(Process, MillingDelayIsOneToothPeriod) {
  const Process p = case_c(0.05, MillingDirection::kDown);
  EXPECT_DOUBLE_EQ(p.delay_s(10000.0), 60.0 / (10000.0 * 2));
  EXPECT_NEAR(p.rpm_from_delay(p.delay_s(12345.0)), 12345.0, 1e-9);
}

TEST(Process, EntryAndExitAngles) {
  EXPECT_NEAR(case_c(0.05, MillingDirection::kDown).entry_angle(), std::acos(-0.9), 1e-15);
  EXPECT_NEAR(case_c(0.05, MillingDirection::kDown).exit_angle(), kPi, 1e-15);
  EXPECT_NEAR(case_c(0.05, MillingDirection::kUp).entry_angle(), 0.0, 1e-15);
  EXPECT_NEAR(case_c(0.05, MillingDirection::kUp).exit_angle(), std::acos(0.9), 1e-15);
  EXPECT_NEAR(case_c(1.0, MillingDirection::kDown).entry_angle(), 0.0, 1e-15);
  EXPECT_NEAR(case_c(0.5, MillingDirection::kUp).exit_angle(), kPi / 2, 1e-15);
}

TEST(Process, ToothMatrixReproducesTheForceLaw) {
  // F = −a H Δr with h = Δx sinφ + Δy cosφ, F_t = K_t a h, F_r = K_r a h,
  // F_x = −F_t cosφ − F_r sinφ, F_y = F_t sinφ − F_r cosφ (docs/physics.md §3).
  const Process p = case_c(1.0, MillingDirection::kDown);
  const double a = 2e-3, dx = 1e-5, dy = -3e-6;
  for (double phi : {0.1, 0.7, 1.5, 2.2, 3.0}) {
    const double h = dx * std::sin(phi) + dy * std::cos(phi);
    const double ft = 6e8 * a * h, fr = 2e8 * a * h;
    const Eigen::Vector2d F_law(-ft * std::cos(phi) - fr * std::sin(phi), ft * std::sin(phi) - fr * std::cos(phi));
    const Eigen::Vector2d F = -a * p.tooth_matrix(phi) * Eigen::Vector2d(dx, dy);
    EXPECT_LT((F - F_law).norm(), 1e-12 * F_law.norm()) << "phi = " << phi;
  }
}

TEST(Process, DirectionalMatrixSwitchesTeethInAndOut) {
  const Process p = case_c(0.05, MillingDirection::kDown);
  const double rpm = 6000.0, omega = 2 * kPi * rpm / 60;
  // Tooth 0 at φ = 3.0 rad (inside [acos(-0.9), π]); tooth 1 at φ = 3 + π (out).
  const Eigen::Matrix2d H = p.directional_matrix(3.0 / omega, rpm);
  EXPECT_LT((H - p.tooth_matrix(3.0)).norm(), 1e-6 * p.tooth_matrix(3.0).norm());
  // At φ = 1.0 neither tooth cuts.
  EXPECT_EQ(p.directional_matrix(1.0 / omega, rpm).norm(), 0.0);
}

class AverageMatrix : public ::testing::TestWithParam<std::pair<double, MillingDirection>> {};

TEST_P(AverageMatrix, EqualsTimeAverageOfH) {
  // H₀ must equal the average of H(t) over one tooth period, computed here by
  // the midpoint rule over one spindle revolution (every tooth sweeps once).
  const auto [immersion, dir] = GetParam();
  const Process p = case_c(immersion, dir);
  const double rpm = 9000.0;
  const double T = 60.0 / rpm;
  const int n = 400000;
  Eigen::Matrix2d avg = Eigen::Matrix2d::Zero();
  for (int i = 0; i < n; ++i) avg += p.directional_matrix((i + 0.5) * T / n, rpm);
  avg /= n;
  const Eigen::Matrix2d H0 = p.average_directional_matrix();
  // Midpoint rule on a discontinuous integrand: error O(1/n) of the jump.
  EXPECT_LT((avg - H0).norm(), 2e-5 * (6e8 + 2e8)) << "H0 =\n" << H0 << "\naverage =\n" << avg;
}
INSTANTIATE_TEST_SUITE_P(Immersions, AverageMatrix,
                         ::testing::Values(std::pair{0.05, MillingDirection::kDown}, std::pair{0.5, MillingDirection::kDown},
                                           std::pair{1.0, MillingDirection::kDown}, std::pair{0.1, MillingDirection::kUp},
                                           std::pair{0.5, MillingDirection::kUp}));

TEST(Process, FullImmersionAverageIsTheAltintasClosedForm) {
  // Slotting (φ_en = 0, φ_ex = π): ∫ sinφcosφ = 0, ∫ sin² = ∫ cos² = π/2, so
  // H₀ = (N_t/2π)(π/2)[[K_r, K_t], [−K_t, K_r]] = (N_t/4)[[K_r, K_t], [−K_t, K_r]].
  const Process p = case_c(1.0, MillingDirection::kDown);
  Eigen::Matrix2d expected;
  expected << 2e8, 6e8, -6e8, 2e8;
  expected *= 2.0 / 4.0;
  EXPECT_LT((p.average_directional_matrix() - expected).norm(), 1e-6);
}

TEST(Process, RefusesNonPhysicalParameters) {
  EXPECT_THROW(Process::turning({0.0}), chatter::InputError);
  EXPECT_THROW(Process::milling({0, 6e8, 2e8, 0.5, MillingDirection::kDown}), chatter::InputError);
  EXPECT_THROW(Process::milling({2, 6e8, 2e8, 0.0, MillingDirection::kDown}), chatter::InputError);
  EXPECT_THROW(Process::milling({2, 6e8, 2e8, 1.5, MillingDirection::kDown}), chatter::InputError);
  EXPECT_THROW(Process::milling({2, -1.0, 2e8, 0.5, MillingDirection::kDown}), chatter::InputError);
}

}  // namespace
}  // namespace chatter
