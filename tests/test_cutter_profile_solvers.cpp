// Every method on a ball-end cutter (docs/cutter_geometry.md): the flat
// cutter through the general-profile path gives today's limits, the sdm
// limit converges with the slices, sdm agrees with the averaged method at
// wide immersion, the coupled method with the analytic one, and the linear
// simulation's growth with sdm's multiplier.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/process.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- tolerances (relative) ----
// The flat cutter through the general path: the same equation, its
// integrals summed over slices instead of taken at once (round-off only).
// Measured: analytic 1.2e-15, sdm 2.3e-14 (the same step grid and search).
constexpr double kFlatGeneralAnalytic = 1e-12;
constexpr double kFlatGeneralSdm = 1e-12;
// Time domain (linear growth per period): slice angles by rotation (flat)
// or one by one (profile), so CVODE (rtol 1e-9) takes other steps; measured 9e-9.
constexpr double kFlatGeneralGrowth = 1e-7;
// Wide immersion (4-flute slot) on a ball: the zeroth-order average against
// the Floquet limit; measured 0.04 % at most on these speeds (4 teeth in a
// slot keep H(t) nearly constant; with 2 the flat cutter is 10 % off too).
constexpr double kSdmVsAnalyticSlot = 2e-3;
// coupled and analytic solve the same averaged equation.
constexpr double kCoupledVsAnalytic = 1e-6;
// Linear growth per tooth period against sdm's spectral radius (128 steps):
// measured 6.1e-4; both methods' discretisation errors (16 slices each).
constexpr double kGrowthVsRho = 3e-3;

::testing::AssertionResult RelNear(double actual, double expected, double tol) {
  const double err = std::abs(actual - expected) / std::abs(expected);
  if (err <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "actual " << actual << ", expected " << expected << ", relative error " << err
                                       << " > " << tol;
}

// configs/milling_ball_end.toml: a 10 mm 2-flute ball on a long overhang.
StructuralModel ball_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(1350.0, 0.025, 4e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(1400.0, 0.025, 4.5e6, {0.0, 1.0}));
  return m;
}

MillingParameters ball(double immersion, int slices = 0) {
  MillingParameters p;
  p.teeth = 2;
  p.tangential_coefficient_n_per_m2 = 1.8e9;
  p.radial_coefficient_n_per_m2 = 0.63e9;
  p.axial_coefficient_n_per_m2 = 0.4e9;
  p.radial_immersion = immersion;
  p.direction = MillingDirection::kDown;
  p.tool_diameter_m = 10e-3;
  p.helix_angles_rad = {30.0 * kPi / 180.0};
  p.cutter.geometry = CutterGeometry::kBall;
  p.cutter.slices = slices;
  return p;
}

SemiDiscretizationOptions sdm_opts(int steps = 64) {
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.01;
  o.steps_per_period = steps;
  o.steps_per_vibration_cycle = steps;
  return o;
}

TransferFunctionOptions tf_opts() {
  TransferFunctionOptions o;
  o.depth_max_m = 0.01;
  return o;
}

double growth(const StructuralModel& m, const Process& p, double rpm, double depth_m, int axial_slices = 0) {
  TimeDomainOptions o;
  o.relative_tolerance = 1e-9;
  o.axial_slices = axial_slices;
  TimeDomainSimulator sim(m, p, o);
  SimulationSettings s;
  s.spindle_rpm = rpm;
  s.depth_m = depth_m;
  s.periods = 60;
  s.linear = true;
  s.record_series = false;
  return sim.simulate(s).growth_per_period;
}

MillingParameters flat_as_general(double immersion) {
  MillingParameters p = ball(immersion, 20);
  p.cutter.geometry = CutterGeometry::kGeneral;
  p.cutter.profile = {{0.0, 5e-3, 0.5 * kPi}, {30e-3, 5e-3, 0.5 * kPi}};
  return p;
}

TEST(CutterProfileSolvers, FlatThroughGeneralPathGivesTodaysLimits) {
  const StructuralModel m = ball_tool();
  const MillingParameters g = flat_as_general(0.3);
  MillingParameters f = g;
  f.cutter = {};
  const Process general = Process::milling(g), flat = Process::milling(f);
  const AnalyticSolver ag(m, general, tf_opts()), af(m, flat, tf_opts());
  const SemiDiscretizationSolver sg(m, general, sdm_opts()), sf(m, flat, sdm_opts());
  for (const double rpm : {9000.0, 14000.0, 21000.0}) {
    const double a_flat = af.limit_at(SpindleSpeed(rpm)).depth_limit_m, a_gen = ag.limit_at(SpindleSpeed(rpm)).depth_limit_m;
    EXPECT_TRUE(RelNear(a_gen, a_flat, kFlatGeneralAnalytic)) << "analytic at " << rpm << " rev/min";
    const double s_flat = sf.limit_at(SpindleSpeed(rpm)).depth_limit_m, s_gen = sg.limit_at(SpindleSpeed(rpm)).depth_limit_m;
    EXPECT_TRUE(RelNear(s_gen, s_flat, kFlatGeneralSdm)) << "sdm at " << rpm << " rev/min";
  }
  // The time domain: the flat cutter on the profile's 20 slices (on its
  // own it takes the exact edge, their limit: TimeDomainCutters.ExactEdge*).
  EXPECT_TRUE(RelNear(growth(m, general, 14000.0, 2e-3), growth(m, flat, 14000.0, 2e-3, 20), kFlatGeneralGrowth))
      << "linear growth per period at 14000 rev/min, 2 mm";
}

TEST(CutterProfileSolvers, SdmLimitConvergesWithSlices) {
  const StructuralModel m = ball_tool();
  const double rpm = 14000.0;
  const double ref = SemiDiscretizationSolver(m, Process::milling(ball(0.5, 256)), sdm_opts()).limit_at(SpindleSpeed(rpm)).depth_limit_m;
  double previous = 1.0;
  for (const int s : {4, 8, 16, 32}) {
    const double a = SemiDiscretizationSolver(m, Process::milling(ball(0.5, s)), sdm_opts()).limit_at(SpindleSpeed(rpm)).depth_limit_m;
    const double err = std::abs(a - ref) / ref;
    EXPECT_LT(err, previous) << s << " slices: limit " << a << " vs " << ref << " (256 slices), error " << err;
    previous = err;
  }
  // Measured 1.8e-3, 8.0e-4, 3.2e-4, 1.2e-4 at 4 … 32 slices (order ~1.3:
  // the ball's tip, where κ ~ sqrt(z), limits the mid-point slices).
  EXPECT_LT(previous, 5e-4) << "32 slices (the default) within 0.05 % of 256";
}

// A 4-flute slot of the cutter `mp`: sdm, analytic and coupled limits agree
// at four speeds (2-flute slotting varies too much in time for the average:
// a flat cutter is 10 % off sdm there).
void expect_slot_methods_agree(MillingParameters mp, const char* what) {
  const StructuralModel m = ball_tool();
  mp.teeth = 4;
  const Process p = Process::milling(mp);
  const SemiDiscretizationSolver sdm(m, p, sdm_opts());
  const AnalyticSolver analytic(m, p, tf_opts());
  const CoupledSolver coupled(m, p, tf_opts());
  for (const double rpm : {10000.0, 14000.0, 18000.0, 22000.0}) {
    const double a_sdm = sdm.limit_at(SpindleSpeed(rpm)).depth_limit_m, a_an = analytic.limit_at(SpindleSpeed(rpm)).depth_limit_m;
    EXPECT_TRUE(RelNear(a_an, a_sdm, kSdmVsAnalyticSlot)) << what << " at " << rpm << " rev/min: analytic vs sdm";
    EXPECT_TRUE(RelNear(coupled.limit_at(SpindleSpeed(rpm)).depth_limit_m, a_an, kCoupledVsAnalytic)) << rpm << " rev/min";
  }
}

TEST(CutterProfileSolvers, SdmAgreesWithAnalyticAtWideImmersion) { expect_slot_methods_agree(ball(1.0), "slot"); }

TEST(CutterProfileSolvers, LinearGrowthMatchesSdmMultiplier) {
  const StructuralModel m = ball_tool();
  const Process p = Process::milling(ball(0.5, 16));
  const SemiDiscretizationSolver sdm(m, p, sdm_opts(128));
  const double rpm = 14000.0, a = 1.2e-3;  // just above the limit (1.05 mm)
  const double rho = sdm.analyse(rpm, a).spectral_radius;
  const double g = growth(m, p, rpm, a);
  EXPECT_TRUE(RelNear(g, rho, kGrowthVsRho)) << "growth per tooth period vs sdm |mu|";
  EXPECT_GT(g, 1.0);
}

// A bull nose (corner radius 1.5 mm on the 10 mm cutter): the limits lie in
// the torus corner (z < 1.5 mm), where radius and lead angle change along
// the edge as on the ball but reach the full radius at the corner's top.
MillingParameters bull_nose(double immersion, int slices = 0) {
  MillingParameters p = ball(immersion, slices);
  p.cutter.geometry = CutterGeometry::kBullNose;
  p.cutter.corner_radius_m = 1.5e-3;
  return p;
}

TEST(CutterProfileSolvers, BullNoseSdmAgreesWithAnalyticAndCoupledInASlot) {
  expect_slot_methods_agree(bull_nose(1.0), "bull-nose slot");
}

// Narrow engagement (a_e/D = 0.1): the corner's slices of small radius do
// not reach the band, the others cut shorter arcs than the full radius; the
// time domain and sdm read the same slices, so the linear growth just above
// sdm's limit must be its spectral radius. 64 slices: at a_e/D = 0.1 the
// time domain's entering / leaving ramp over each slice's lag is a larger
// part of the short arc; measured at 8.84 mm, 14 000 rev/min: 16 slices
// 1.05268 against ρ 1.04750 (0.49 %; a flat cutter with 16 time-domain
// slices is 0.47 % off its exact sdm ρ the same way), 64 slices 1.04701
// against 1.04664 (3.5e-4).
TEST(CutterProfileSolvers, BullNoseLinearGrowthMatchesSdmAtNarrowImmersion) {
  const StructuralModel m = ball_tool();
  const Process p = Process::milling(bull_nose(0.1, 64));
  const SemiDiscretizationSolver sdm(m, p, sdm_opts(128));
  const double rpm = 14000.0;
  const StabilityLimit lim = sdm.limit_at(SpindleSpeed(rpm));
  ASSERT_TRUE(lim.bounded());
  const double a = 1.1 * lim.depth_limit_m;
  const double rho = sdm.analyse(rpm, a).spectral_radius;
  const double g = growth(m, p, rpm, a);
  EXPECT_TRUE(RelNear(g, rho, kGrowthVsRho)) << "growth per period vs sdm |mu| at " << a * 1e3 << " mm";
  EXPECT_GT(g, 1.0);
}

// The forced response does not follow the wall a curved edge leaves: refused
// with the key named, never a flat cutter's answer for a ball.
TEST(CutterProfileSolvers, ForcedResponseRefusesAProfileNamingTheKey) {
  try {
    const ForcedResponseSolver f(ball_tool(), Process::milling(ball(0.5)));
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("process.cutter_geometry = \"ball\""), std::string::npos) << w;
  }
}

}  // namespace
}  // namespace chatter
