// Gauss collocation of the `sdm` solver in turning (docs/sdm.md "Collocation
// in turning"): the default for a sharp edge, against the exact limit of
// the transfer function (turning has one constant delay, so the analytic
// method is exact), its order of convergence (2s = 6), with spindle speed
// variation against the first-order scheme extrapolated to zero step, and
// what it refuses. The branch roots of its constant step against the
// Arnoldi iteration: tests/test_sdm_search.cpp (SdmTurningBranches).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

// docs/physics.md case A: 1-DOF turning, 94.22 Hz, ζ 0.033, k 45 MN/m, K_f 2.4e9 N/m².
constexpr double kKf = 2.4e9;
StructuralModel case_a() {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0}));
  return m;
}

// Tolerances (relative).
// The default (3 nodes, 4 steps per cycle) against the exact limit: measured
// 7.9e-5, 8.1e-5, 6.9e-5, 5.2e-5 at 50, 300, 1 000, 2 000 rev/min (400
// speeds of the shipped config: at most 1.6e-4, median 7.9e-5; the first
// order at its 64 steps 4.6e-3 and 7.4e-4).
constexpr double kDefaultAgree = 2.5e-4;
// 8 steps: measured at most 1.2e-6 (order 6: 64 times closer per halving).
constexpr double kEightStepsAgree = 5e-6;
// Chatter frequency at the limit: measured within 8e-7 at 4 steps.
constexpr double kFrequencyAgree = 1e-5;
// Order 6: halving the step divides the error of ρ by 64; measured 48 and
// 63 at 2 000 rev/min, 2 mm (4 → 8 → 16 steps against 64).
constexpr double kOrderSixRatioMin = 32.0;
// With speed variation (case A, R_VA = R_VF = 0.1) against the first order
// at 128 and 256 steps, Richardson-extrapolated: measured 8e-7 (300
// rev/min) and 2e-6 (1 900 rev/min) at 8 steps.
constexpr double kSsvAgree = 2e-5;
constexpr double kTightDepth = 1e-8;

SemiDiscretizationOptions options(int nodes, int steps, double depth_tolerance = kTightDepth) {
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.02;
  o.depth_tolerance = depth_tolerance;
  o.collocation_nodes = nodes;
  if (steps > 0) o.steps_per_period = o.steps_per_vibration_cycle = steps;
  return o;
}

TEST(SdmTurningCollocation, DefaultCollocatesAndMatchesTheExactLimit) {
  const Process p = Process::turning({kKf});
  const SemiDiscretizationSolver dflt(case_a(), p, options(kAutoCollocation, 0));
  EXPECT_EQ(dflt.options().collocation_nodes, kRealCutterNodes);
  EXPECT_EQ(dflt.options().steps_per_period, kRealCutterSteps);
  const SemiDiscretizationSolver eight(case_a(), p, options(3, 8)), first(case_a(), p, options(0, 0));
  TransferFunctionOptions to;
  to.depth_max_m = 0.02;
  const AnalyticSolver exact(case_a(), p, to);
  for (const double rpm : {50.0, 300.0, 1000.0, 2000.0}) {
    SCOPED_TRACE(std::to_string(rpm) + " rev/min");
    const StabilityLimit e = exact.limit_at(SpindleSpeed(rpm)), d = dflt.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(e.bounded() && d.bounded());
    EXPECT_NEAR(d.depth_limit_m / e.depth_limit_m, 1.0, kDefaultAgree);
    EXPECT_NEAR(d.chatter_frequency_hz / e.chatter_frequency_hz, 1.0, kFrequencyAgree);
    EXPECT_EQ(d.lobe, e.lobe);
    EXPECT_NEAR(eight.limit_at(SpindleSpeed(rpm)).depth_limit_m / e.depth_limit_m, 1.0, kEightStepsAgree);
    // The first order at its default steps is several times further off.
    const double f = first.limit_at(SpindleSpeed(rpm)).depth_limit_m;
    EXPECT_GT(std::abs(f / e.depth_limit_m - 1.0), 3.0 * std::abs(d.depth_limit_m / e.depth_limit_m - 1.0));
  }
}

double rho(int steps) {
  const SemiDiscretizationSolver s(case_a(), Process::turning({kKf}), options(3, steps));
  return s.analyse(2000.0, 2.0e-3).spectral_radius;
}

TEST(SdmTurningCollocation, HalvingTheStepDividesTheErrorBySixtyFour) {
  const double ref = rho(64);
  const double e4 = std::abs(rho(4) - ref), e8 = std::abs(rho(8) - ref), e16 = std::abs(rho(16) - ref);
  EXPECT_GT(e4 / e8, kOrderSixRatioMin) << e4 << " " << e8 << " " << e16;
  EXPECT_GT(e8 / e16, kOrderSixRatioMin) << e4 << " " << e8 << " " << e16;
}

double ssv_limit(int nodes, int steps, double rpm) {
  Process p = Process::turning({kKf});
  p.set_speed_variation({0.1, 0.1});
  const SemiDiscretizationSolver s(case_a(), p, options(nodes, steps, 1e-9));
  const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
  EXPECT_TRUE(l.bounded()) << rpm;
  return l.depth_limit_m;
}

TEST(SdmTurningCollocation, SpeedVariationMatchesTheExtrapolatedFirstOrder) {
  for (const double rpm : {300.0, 1900.0}) {
    const double a = ssv_limit(0, 128, rpm), b = ssv_limit(0, 256, rpm);
    const double ref = b + (b - a) / 3.0;  // h²
    const double c = ssv_limit(3, 8, rpm);
    EXPECT_NEAR(c / ref, 1.0, kSsvAgree) << rpm << " rev/min: collocation " << c << " m vs " << ref;
  }
}

void expect_refused(const Process& p, const std::string& words) {
  SemiDiscretizationOptions o = options(3, 8);
  try {
    const SemiDiscretizationSolver s(case_a(), p, o);
    ADD_FAILURE() << "no InputError; expected: " << words;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("collocation_nodes = 3"), std::string::npos) << e.what();
  }
  // Chosen automatically, the first-order steps run instead.
  const SemiDiscretizationSolver s(case_a(), p, options(kAutoCollocation, 0));
  EXPECT_EQ(s.options().collocation_nodes, 0) << words;
}

TEST(SdmTurningCollocation, RefusesANoseRadiusAndProcessDamping) {
  TurningParameters nose;
  nose.feed_force_coefficient_n_per_m2 = kKf;
  nose.lead_angle_rad = 1.0;
  nose.nose_radius_m = 0.8e-3;
  expect_refused(Process::turning(nose), "turning with a nose radius");
  TurningParameters damped;
  damped.feed_force_coefficient_n_per_m2 = kKf;
  damped.process_damping_coefficient_n_per_m = 2e5;
  damped.workpiece_diameter_m = 0.05;
  expect_refused(Process::turning(damped), "turning with process damping");
}

}  // namespace
}  // namespace chatter
