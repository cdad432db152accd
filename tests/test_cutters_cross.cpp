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
    const StabilityLimit lim = sdm.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(lim.bounded()) << rpm;
    for (const double f : {kBelow, kAbove}) {
      const double a = f * lim.depth_limit_m;
      const FloquetResult fl = sdm.analyse(rpm, a);
      const double g = linear_growth(model, process, rpm, a, periods);
      SCOPED_TRACE(std::to_string(rpm) + " rev/min, " + std::to_string(a * 1e3) + " mm");
      // One Floquet period for both (Process::floquet_period_s): the
      // simulation's growth and sdm's multiplier are per the same period.
      ASSERT_DOUBLE_EQ(fl.period_s, process.floquet_period_s(rpm));
      const double rho = fl.spectral_radius;
      EXPECT_NEAR(g / rho, 1.0, kGrowthVsSdm) << "time-domain " << g << " sdm " << rho << " (period "
                                               << fl.period_s << " s)";
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
  // 60 periods: with 30 the exact DMD's growth at 9 000 rev/min swings
  // between 0.848 and 0.896 for depths 3e-4 apart (sdm: 0.8479 at both).
  expect_growth_matches_sdm(two_modes(), process, {6000.0, 9000.0}, 60);
}

TEST(CuttersAcrossMethods, VariablePitchSdmNearAnalyticAtFullImmersion) {
  // Full immersion, 4 teeth at 75/105/75/105°, two modes. With equal pitch
  // the averaged and Floquet limits agree to 6e-4 here (the sum of the
  // teeth's directional matrices hardly varies in slotting). With variable
  // pitch each tooth carries its own delay, so the per-tooth matrices, which
  // do vary over a revolution, no longer sum before they are averaged: the
  // zeroth-order method of Altintas, Engin & Budak (1999) keeps only their
  // mean. Measured on 4000–12000 rev/min (step 1000): depth within 14 %
  // (5 000 rev/min: 3.86 vs 4.38 mm), chatter frequency within 0.7 %; sdm
  // itself agrees with the simulated growth (test above). So: the averaged
  // method is a fast estimate for variable pitch, not a replacement for sdm.
  constexpr double kDepthSpread = 0.20;      // measured 0.14
  constexpr double kFrequencySpread = 0.015; // measured 0.007
  constexpr double kUniformSpread = 2e-3;    // measured 6e-4
  MillingParameters p = cutter(4, 1.0, MillingDirection::kDown, 6e8, 1.8e8);
  p.pitch_angles_rad = {75 * kDeg, 105 * kDeg, 75 * kDeg, 105 * kDeg};
  const Process process = Process::milling(p);
  const Process uniform = Process::milling(cutter(4, 1.0, MillingDirection::kDown, 6e8, 1.8e8));
  const StructuralModel model = two_modes();
  const auto sdm = make_lobe_solver("sdm", model, process, 0.05);
  const auto analytic = make_lobe_solver("analytic", model, process, 0.05);
  const auto sdm_u = make_lobe_solver("sdm", model, uniform, 0.05);
  const auto analytic_u = make_lobe_solver("analytic", model, uniform, 0.05);
  for (double rpm = 4000.0; rpm <= 12000.0; rpm += 1000.0) {
    SCOPED_TRACE(std::to_string(rpm) + " rev/min");
    const StabilityLimit s = sdm->limit_at(SpindleSpeed(rpm)), a = analytic->limit_at(SpindleSpeed(rpm));
    const StabilityLimit su = sdm_u->limit_at(SpindleSpeed(rpm)), au = analytic_u->limit_at(SpindleSpeed(rpm));
    EXPECT_NEAR(a.depth_limit_m / s.depth_limit_m, 1.0, kDepthSpread) << a.depth_limit_m << " vs " << s.depth_limit_m;
    EXPECT_NEAR(a.chatter_frequency_hz / s.chatter_frequency_hz, 1.0, kFrequencySpread);
    EXPECT_NEAR(au.depth_limit_m / su.depth_limit_m, 1.0, kUniformSpread);
    // Both methods say the same about where variable pitch helps.
    EXPECT_EQ(a.depth_limit_m > au.depth_limit_m, s.depth_limit_m > su.depth_limit_m)
        << "analytic " << au.depth_limit_m << " -> " << a.depth_limit_m << ", sdm " << su.depth_limit_m << " -> "
        << s.depth_limit_m;
  }
}

}  // namespace
}  // namespace chatter
