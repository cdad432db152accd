// Real cutters across methods (docs/physics.md §8): the Floquet multipliers
// of sdm against the linear growth of the time-domain simulation on both
// sides of the limit (helix, variable pitch, process damping), and sdm
// against the averaged (analytic) method at full immersion, where averaging
// is accurate. Each solver's own tests check it against closed forms; this
// file checks that the four read the one cutter description the same way.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "chatter/process.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/solvers.hpp"
#include "chatter/structural_model.hpp"
#include "chatter/time_domain.hpp"

namespace chatter {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// Growth per period of the linear simulation (exact DMD of the sampled
// once-per-period map) vs sdm's spectral radius: the same bound as the
// straight-tooth cross-check of test_time_domain.cpp.
constexpr double kGrowthVsSdm = 5e-3;
// Points either side of the sdm limit, as a fraction of it: far enough that
// ρ differs from 1 by more than the two methods' disagreement.
constexpr double kBelow = 0.85, kAbove = 1.15;

Mode mode_along(double f_hz, double zeta, double k, Eigen::Vector2d dir) {
  Mode m;
  m.natural_frequency_hz = f_hz;
  m.damping_ratio = zeta;
  m.stiffness_n_per_m = k;
  m.direction = dir;
  return m;
}

// Case C's mode (physics §7): 922 Hz, ζ = 0.011, m = 0.03993 kg, along X.
StructuralModel case_c_mode() {
  StructuralModel s;
  const double m = 0.03993, w = 2.0 * std::numbers::pi * 922.0;
  s.tool.modes.push_back(mode_along(922.0, 0.011, m * w * w, {1.0, 0.0}));
  return s;
}

StructuralModel two_modes() {
  StructuralModel s;
  s.tool.modes.push_back(mode_along(800.0, 0.02, 2e7, {1.0, 0.0}));
  s.tool.modes.push_back(mode_along(860.0, 0.02, 2.4e7, {0.0, 1.0}));
  return s;
}

MillingParameters cutter(int teeth, double immersion, MillingDirection dir, double kt, double kr) {
  MillingParameters p;
  p.teeth = teeth;
  p.tangential_coefficient_n_per_m2 = kt;
  p.radial_coefficient_n_per_m2 = kr;
  p.radial_immersion = immersion;
  p.direction = dir;
  p.tool_diameter_m = 0.012;
  return p;
}

double linear_growth(const StructuralModel& model, const Process& process, double rpm, double depth_m, int periods) {
  TimeDomainSimulator sim(model, process);
  SimulationSettings s;
  s.spindle_rpm = rpm;
  s.depth_m = depth_m;
  s.periods = periods;
  s.linear = true;
  s.record_series = false;
  return sim.simulate(s).growth_per_period;
}

void expect_growth_matches_sdm(const StructuralModel& model, const Process& process, const std::vector<double>& rpms,
                               int periods) {
  SemiDiscretizationSolver sdm(model, process);
  for (const double rpm : rpms) {
    const StabilityLimit lim = sdm.limit_at(rpm);
    ASSERT_TRUE(lim.bounded()) << rpm;
    for (const double f : {kBelow, kAbove}) {
      const double a = f * lim.depth_limit_m;
      const FloquetResult fl = sdm.analyse(rpm, a);
      const double g = linear_growth(model, process, rpm, a, periods);
      SCOPED_TRACE(std::to_string(rpm) + " rev/min, " + std::to_string(a * 1e3) + " mm");
      EXPECT_NEAR(g / fl.spectral_radius, 1.0, kGrowthVsSdm) << "time-domain " << g << " sdm " << fl.spectral_radius;
      EXPECT_EQ(g < 1.0, f < 1.0) << "growth " << g;
    }
  }
}

TEST(CuttersAcrossMethods, HelixSdmAgreesWithSimulatedGrowth) {
  // 2 teeth, 30° helix, case C coefficients and mode, a_e/D = 0.05 down.
  MillingParameters p = cutter(2, 0.05, MillingDirection::kDown, 6e8, 2e8);
  p.helix_angles_rad = {30 * kDeg};
  const Process process = Process::milling(p);
  expect_growth_matches_sdm(case_c_mode(), process, {8000.0, 12000.0, 17000.0}, 120);
}

TEST(CuttersAcrossMethods, VariablePitchSdmAgreesWithSimulatedGrowth) {
  MillingParameters p = cutter(4, 0.5, MillingDirection::kDown, 6e8, 1.8e8);
  p.pitch_angles_rad = {80 * kDeg, 100 * kDeg, 80 * kDeg, 100 * kDeg};
  const Process process = Process::milling(p);
  expect_growth_matches_sdm(two_modes(), process, {6000.0, 9000.0}, 60);
}

TEST(CuttersAcrossMethods, VariablePitchSdmNearAnalyticAtFullImmersion) {
  // At full immersion the directional matrix varies least over a tooth
  // period and the averaged method is close to Floquet.
  MillingParameters p = cutter(4, 1.0, MillingDirection::kDown, 6e8, 1.8e8);
  p.pitch_angles_rad = {75 * kDeg, 105 * kDeg, 75 * kDeg, 105 * kDeg};
  const Process process = Process::milling(p);
  const StructuralModel model = two_modes();
  const auto sdm = make_lobe_solver("sdm", model, process, 0.05);
  const auto analytic = make_lobe_solver("analytic", model, process, 0.05);
  // Tolerance: the straight uniform cutter at full immersion, 2 modes, shows
  // the same spread between the two methods (measured below on the same
  // speeds), so variable pitch must not add to it by more than a little.
  MillingParameters u = cutter(4, 1.0, MillingDirection::kDown, 6e8, 1.8e8);
  const Process uniform = Process::milling(u);
  const auto sdm_u = make_lobe_solver("sdm", model, uniform, 0.05);
  const auto analytic_u = make_lobe_solver("analytic", model, uniform, 0.05);
  double worst_uniform = 0.0, worst_pitch = 0.0;
  for (double rpm = 4000.0; rpm <= 12000.0; rpm += 1000.0) {
    const double s = sdm->limit_at(rpm).depth_limit_m, a = analytic->limit_at(rpm).depth_limit_m;
    const double su = sdm_u->limit_at(rpm).depth_limit_m, au = analytic_u->limit_at(rpm).depth_limit_m;
    worst_pitch = std::max(worst_pitch, std::abs(s / a - 1.0));
    worst_uniform = std::max(worst_uniform, std::abs(su / au - 1.0));
  }
  RecordProperty("worst_relative_difference_variable_pitch", std::to_string(worst_pitch));
  RecordProperty("worst_relative_difference_uniform", std::to_string(worst_uniform));
  // Measured: see docs/method.md ("Real cutters").
  constexpr double kAveragingSpread = 0.05;
  EXPECT_LT(worst_pitch, std::max(kAveragingSpread, 1.5 * worst_uniform))
      << "uniform spread " << worst_uniform << ", variable pitch " << worst_pitch;
}

}  // namespace
}  // namespace chatter
