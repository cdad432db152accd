// Gauss collocation on the real-cutter grid of the `sdm` solver (docs/sdm.md
// "Collocation on real cutters"): H sampled at the nodes
// (RegenerativeCut::force_rates) against the closed-form step integrals, the
// automatic choice, the limits against the first-order real-cutter path
// extrapolated to zero step (an independent discretisation) and against a
// finer collocation, the order of convergence, the multiplier type, chatter
// frequency and lobe the first order reports, and the straight cutter on
// the general path against the tooth-period grid.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "chatter/regenerative_cut.hpp"
#include "chatter/semi_discretization.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- tolerances (relative) ----
// ∫ force_rates over a span between edge events by composite Gauss–Legendre
// (20 × 5 points), summed per delay, against the closed-form force_integrals: quadrature error of a
// smooth trigonometric integrand, round-off otherwise (measured ≤ 4e-15).
constexpr double kRatesIntegrate = 1e-11;
// The automatic choice (3 nodes, kRealCutterSteps steps) against 3 nodes at
// 16 steps (error ~1e-9 by the order below): measured 5.5e-5 at most over
// 200 speeds 500–24 000 rev/min on the issue-45 cutter.
constexpr double kAutoAgree = 1e-4;
// 3 nodes at 16 steps against the first-order real-cutter path at 256 and
// 512 steps, Richardson-extrapolated for its h² error: two independent
// discretisations of the same equation (the extrapolation's own error is
// the margin: measured 4.6e-6 at most on these cases; from 128 and 256 steps
// it is 2.6e-5 on the variable pitch, whose first order settles slowly).
constexpr double kFirstOrderAgree = 1e-5;
// The default on the variable pitch, helix and ball below against that
// reference: measured 2.4e-4 at most (variable pitch at 14 000 rev/min, 4
// steps of a 90° cut: its delayed samples are interpolated), 2.0e-5 on the
// others. The first order's default 64 steps is 2e-3 off there.
constexpr double kAutoAgreeVariable = 3e-4;
// kRealCutterSteps under process damping ~360 times the structure's own
// (StrongProcessDamping... below): measured 1.06e-3.
constexpr double kAutoAgreeStrongDamping = 2e-3;
// The same with speed variation (SpeedVariation... below): measured 6.9e-7
// (variable pitch) and 1.1e-8 (straight teeth, low immersion).
constexpr double kSsvFirstOrderAgree = 1e-5;
// Order 2s = 6: halving the step divides the error by 64; accepted from 24.
constexpr double kOrderSixRatioMin = 24.0;
// The straight cutter through the general path (one revolution, one delay
// per tooth, steps on the events) and the tooth-period grid, both at 3 nodes
// and 8 steps: two grids of the same equation, each within ~1e-6.
constexpr double kGeneralVsToothGrid = 5e-6;
// The search's depth tolerance for the comparisons above.
constexpr double kTightDepth = 1e-9;

// Issue 45's cutter (examples/real_cutter/aluminium_slot_16mm_3flute.toml):
// a 16 mm 3-flute 30° helix end mill slotting aluminium, two modes per direction.
StructuralModel issue45_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(650.0, 0.03, 12e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(1900.0, 0.02, 25e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(670.0, 0.03, 13e6, {0.0, 1.0}));
  m.tool.modes.push_back(Mode::from_stiffness(2000.0, 0.02, 28e6, {0.0, 1.0}));
  return m;
}
MillingParameters issue45_cutter() {
  MillingParameters mp;
  mp.teeth = 3;
  mp.tangential_coefficient_n_per_m2 = 700e6;
  mp.radial_coefficient_n_per_m2 = 0.3 * 700e6;
  mp.radial_immersion = 1.0;
  mp.direction = MillingDirection::kDown;
  mp.tool_diameter_m = 16e-3;
  mp.helix_angles_rad = {30.0 * kPi / 180.0};
  return mp;
}
// Two modes of different frequency in X and Y (tests/test_sdm_cutters.cpp).
StructuralModel two_mode() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(1150.0, 0.015, 0.05, {0.0, 1.0}));
  return m;
}
MillingParameters half_immersion(int teeth) {
  MillingParameters mp;
  mp.teeth = teeth;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 2e8;
  mp.radial_immersion = 0.5;
  mp.direction = MillingDirection::kDown;
  mp.tool_diameter_m = 10e-3;
  return mp;
}
Process variable_pitch() {
  MillingParameters mp = half_immersion(2);
  mp.pitch_angles_rad = {164.0 * kPi / 180.0, 196.0 * kPi / 180.0};
  return Process::milling(mp);
}
Process variable_helix() {
  MillingParameters mp = half_immersion(2);
  mp.helix_angles_rad = {25.0 * kPi / 180.0, 35.0 * kPi / 180.0};
  return Process::milling(mp);
}
Process ball_end() {
  MillingParameters mp = half_immersion(2);
  mp.axial_coefficient_n_per_m2 = 1.5e8;
  mp.helix_angles_rad = {30.0 * kPi / 180.0};
  mp.cutter.geometry = CutterGeometry::kBall;
  return Process::milling(mp);
}

SemiDiscretizationOptions options(int nodes, int steps, double depth_max_m = 0.02) {
  SemiDiscretizationOptions o;
  o.depth_max_m = depth_max_m;
  o.collocation_nodes = nodes;
  if (steps > 0) o.steps_per_period = o.steps_per_vibration_cycle = steps;
  o.depth_tolerance = kTightDepth;
  return o;
}
double limit(const StructuralModel& m, const Process& p, const SemiDiscretizationOptions& o, double rpm) {
  const StabilityLimit l = SemiDiscretizationSolver(m, p, o).limit_at(SpindleSpeed(rpm));
  EXPECT_TRUE(l.bounded()) << rpm;
  return l.depth_limit_m;
}
double first_order_zero_step(const StructuralModel& m, const Process& p, double rpm) {
  const double a = limit(m, p, options(0, 256), rpm), b = limit(m, p, options(0, 512), rpm);
  return b + (b - a) / 3.0;
}

// ---------------------------------------------------------------- H at an instant
void expect_rates_integrate(const Process& p, double rpm, double depth_m) {
  const std::unique_ptr<const RegenerativeCut> cut = RegenerativeCut::of(p, rpm, depth_m, 8);
  std::vector<double> ev = cut->edge_events_s();
  ev.push_back(cut->pattern_period_s());
  if (ev.front() > 0.0) ev.insert(ev.begin(), 0.0);
  constexpr double kGauss5[5][2] = {{-0.9061798459386640, 0.2369268850561891}, {-0.5384693101056831, 0.4786286704993665},
                                    {0.0, 0.5688888888888889},
                                    {0.5384693101056831, 0.4786286704993665}, {0.9061798459386640, 0.2369268850561891}};
  std::vector<Eigen::Matrix2d> exact, rates;
  cut->force_integrals(0.0, cut->pattern_period_s(), exact);
  double scale = 0.0;  // the largest edge's integral over the period
  for (const auto& m : exact) scale = std::max(scale, m.norm());
  for (std::size_t k = 0; k + 1 < ev.size(); ++k) {
    const double ta = ev[k], tb = ev[k + 1];
    if (tb - ta < 1e-9 * cut->pattern_period_s()) continue;
    cut->force_integrals(ta, tb, exact);
    std::vector<Eigen::Matrix2d> sum(exact.size(), Eigen::Matrix2d::Zero());
    constexpr int kPanels = 20;
    const double w = (tb - ta) / kPanels;
    for (int panel = 0; panel < kPanels; ++panel)
      for (const auto& [x, wt] : kGauss5) {
        cut->force_rates(ta + w * (panel + 0.5 * (x + 1.0)), rates);
        ASSERT_EQ(rates.size(), exact.size());
        for (std::size_t e = 0; e < rates.size(); ++e) sum[e] += rates[e] * (0.5 * w * wt);
      }
    // Per delay: the edges of one delay sum to what the solver samples
    // (one slice's share of a tooth may kink between events; the sum not).
    const std::vector<double>& delays = cut->edge_delays_s();
    for (std::size_t e = 0; e < exact.size(); ++e) {
      Eigen::Matrix2d q = Eigen::Matrix2d::Zero(), x = Eigen::Matrix2d::Zero();
      bool first = true;
      for (std::size_t f = 0; f < exact.size(); ++f)
        if (delays[f] == delays[e]) {
          if (f < e) first = false;
          q += sum[f];
          x += exact[f];
        }
      if (!first) continue;
      EXPECT_LE((q - x).norm(), kRatesIntegrate * scale)
          << "delay " << delays[e] << " s on [" << ta << ", " << tb << "] s: quadrature " << q << " vs " << x;
    }
  }
}

TEST(SdmCutterCollocation, ForceRatesIntegrateToTheClosedFormStepIntegrals) {
  expect_rates_integrate(Process::milling(issue45_cutter()), 9000.0, 4e-3);
  expect_rates_integrate(variable_pitch(), 12000.0, 1e-3);
  expect_rates_integrate(variable_helix(), 12000.0, 2e-3);
  expect_rates_integrate(ball_end(), 14000.0, 2e-3);
  MillingParameters straight = half_immersion(4);
  straight.radial_immersion = 0.3;
  expect_rates_integrate(Process::milling(straight), 8000.0, 1e-3);
  TurningParameters t;
  t.feed_force_coefficient_n_per_m2 = 2.4e9;
  expect_rates_integrate(Process::turning(t), 500.0, 1e-3);
}

// ---------------------------------------------------------------- the choice
TEST(SdmCutterCollocation, TheDefaultTakesCollocationOnRealCuttersOnly) {
  const SemiDiscretizationOptions def;
  EXPECT_EQ(def.collocation_nodes, kAutoCollocation);
  auto chosen = [&](const StructuralModel& m, const Process& p, SemiDiscretizationOptions o = {}) {
    return SemiDiscretizationSolver(m, p, o).options();
  };
  const SemiDiscretizationOptions helix = chosen(issue45_tool(), Process::milling(issue45_cutter()));
  EXPECT_EQ(helix.collocation_nodes, kRealCutterNodes);
  EXPECT_EQ(helix.steps_per_period, kRealCutterSteps);
  EXPECT_EQ(helix.steps_per_vibration_cycle, kRealCutterSteps);
  EXPECT_EQ(chosen(two_mode(), variable_pitch()).collocation_nodes, kRealCutterNodes);
  EXPECT_EQ(chosen(two_mode(), ball_end()).collocation_nodes, kRealCutterNodes);
  // Steps the caller gave are kept.
  SemiDiscretizationOptions given;
  given.steps_per_period = given.steps_per_vibration_cycle = 6;
  EXPECT_EQ(chosen(two_mode(), variable_pitch(), given).steps_per_period, 6);
  // Straight teeth keep the first-order tooth-period grid (and its 64 steps).
  const SemiDiscretizationOptions straight = chosen(two_mode(), Process::milling(half_immersion(2)));
  EXPECT_EQ(straight.collocation_nodes, 0);
  EXPECT_EQ(straight.steps_per_period, def.steps_per_period);
  // So do the cross-check path and process damping (which takes
  // collocation when asked: ProcessDamping... below); speed variation
  // collocates as at constant speed (SpeedVariation... below).
  SemiDiscretizationOptions general;
  general.general_cutter_path = true;
  EXPECT_EQ(chosen(two_mode(), variable_pitch(), general).collocation_nodes, 0);
  MillingParameters damped = issue45_cutter();
  damped.process_damping_coefficient_n_per_m = 1e4;
  EXPECT_EQ(chosen(issue45_tool(), Process::milling(damped)).collocation_nodes, 0);
  Process ssv = Process::milling(issue45_cutter());
  SpeedVariation v;
  v.amplitude_ratio = 0.1;
  v.frequency_ratio = 0.01;
  ssv.set_speed_variation(v);
  EXPECT_EQ(chosen(issue45_tool(), ssv).collocation_nodes, kRealCutterNodes);
}

// ---------------------------------------------------------------- accuracy
TEST(SdmCutterCollocation, HelixDefaultIsWithinTolOfTheConvergedLimitOverTheRange) {
  const StructuralModel m = issue45_tool();
  const Process p = Process::milling(issue45_cutter());
  SemiDiscretizationOptions def;
  def.depth_max_m = 0.02;
  def.depth_tolerance = kTightDepth;
  for (double rpm : {700.0, 3000.0, 9000.0, 16000.0, 23000.0}) {
    const double ref = limit(m, p, options(3, 16), rpm), got = limit(m, p, def, rpm);
    EXPECT_NEAR(got / ref, 1.0, kAutoAgree) << rpm << " rev/min: default " << got << " vs " << ref;
  }
  // The reference against the first-order path at zero step (independent).
  const double rpm = 6000.0;
  EXPECT_NEAR(limit(m, p, options(3, 16), rpm) / first_order_zero_step(m, p, rpm), 1.0, kFirstOrderAgree);
}

// Spindle speed variation (docs/ssv.md): H at each node's mean-speed time,
// the delays τ_g(t_k) at the node. Variable pitch (period one revolution)
// with R_VA = 0.1, R_VF = 0.5 (principal period two revolutions), and the
// straight 2-tooth cutter at low immersion (flip lobes) with R_VF = 0.25:
// 3 nodes at 16 steps against the first order at 256 and 512 steps
// extrapolated to zero step.
TEST(SdmCutterCollocation, SpeedVariationAgreesWithTheFirstOrderAtZeroStep) {
  Process vp = variable_pitch();
  vp.set_speed_variation({0.1, 0.5});
  MillingParameters low = half_immersion(2);
  low.radial_immersion = 0.1;
  Process straight = Process::milling(low);
  straight.set_speed_variation({0.1, 0.25});
  struct Case { const Process* p; double rpm; };
  for (const Case c : {Case{&vp, 12000.0}, Case{&straight, 9000.0}}) {
    const double ref = first_order_zero_step(two_mode(), *c.p, c.rpm);
    const double got = limit(two_mode(), *c.p, options(3, 16), c.rpm);
    EXPECT_NEAR(got / ref, 1.0, kSsvFirstOrderAgree) << c.rpm << " rev/min: collocation " << got << " vs " << ref;
  }
}

TEST(SdmCutterCollocation, HalvingTheStepDividesTheErrorBySixtyFour) {
  const StructuralModel m = issue45_tool();
  const Process p = Process::milling(issue45_cutter());
  const double rpm = 6000.0, ref = limit(m, p, options(3, 24), rpm);
  const double e4 = std::abs(limit(m, p, options(3, 4), rpm) / ref - 1.0);
  const double e8 = std::abs(limit(m, p, options(3, 8), rpm) / ref - 1.0);
  EXPECT_GT(e4 / e8, kOrderSixRatioMin) << "4 steps: " << e4 << ", 8 steps: " << e8;
}

// Delays that are not the period (the node samples interpolated in degree
// 2s − 1), sliced delays, and a profile's slices.
TEST(SdmCutterCollocation, VariablePitchHelixAndBallAgreeWithTheFirstOrderAtZeroStep) {
  const StructuralModel m = two_mode();
  for (const Process& p : {variable_pitch(), variable_helix(), ball_end()})
    for (double rpm : {8500.0, 14000.0}) {
      const double ref = first_order_zero_step(m, p, rpm);
      EXPECT_NEAR(limit(m, p, options(3, 16), rpm) / ref, 1.0, kFirstOrderAgree) << rpm;
      SemiDiscretizationOptions def;
      def.depth_max_m = 0.02;
      def.depth_tolerance = kTightDepth;
      EXPECT_NEAR(limit(m, p, def, rpm) / ref, 1.0, kAutoAgreeVariable) << rpm;
    }
}

// Process damping (− C̄ B D(t) Sv x, the velocity at the nodes): the issue-45
// cutter and a straight two-tooth half-immersion cutter at low speed, where
// the damping raises the limit, against the first-order real-cutter path
// (which integrates D exactly over each step) at zero step; and the order 2s
// holds. Measured: 3 nodes at 16 steps within 2e-7 of that reference; at
// kRealCutterSteps (4) within 6.3e-5, where the first order's default 64
// steps is 9.3e-4 off.
Process with_damping(MillingParameters mp, double c_pd) {
  mp.process_damping_coefficient_n_per_m = c_pd;
  return Process::milling(mp);
}
TEST(SdmCutterCollocation, ProcessDampingAgreesWithTheFirstOrderAtZeroStep) {
  const std::pair<StructuralModel, Process> cases[] = {
      {issue45_tool(), with_damping(issue45_cutter(), 2e5)},
      {two_mode(), with_damping(half_immersion(2), 2e4)},
  };
  for (const auto& [m, p] : cases)
    for (double rpm : {1500.0, 4000.0}) {
      const double ref = first_order_zero_step(m, p, rpm);
      EXPECT_NEAR(limit(m, p, options(3, 16), rpm) / ref, 1.0, kFirstOrderAgree) << rpm;
      EXPECT_NEAR(limit(m, p, options(3, kRealCutterSteps), rpm) / ref, 1.0, kAutoAgreeVariable) << rpm;
      if (rpm < 2000.0) {  // the damping is seen: the same cut without it chatters earlier
        MillingParameters bare = p.milling_parameters();
        bare.process_damping_coefficient_n_per_m = 0.0;
        EXPECT_LT(limit(m, Process::milling(bare), options(3, 16), rpm), 0.95 * ref) << rpm;
      }
    }
}
// Damping far above the structure's: the straight cutter at C_pd = 1e5 N/m
// and 1 500 rev/min chatters at 14.5 mm, where C̄ a is ~360 times the modes'
// own damping and the damped motion decays within a fraction of a step.
// The node polynomial then carries a force that varies within the step:
// 16 steps stay within kFirstOrderAgree, 4 within kAutoAgreeStrongDamping
// (measured 1.06e-3; the first order's 64 steps 2.4e-4). This is why process
// damping keeps the first order unless collocation is asked for.
TEST(SdmCutterCollocation, StrongProcessDampingStaysWithinItsStatedTolerance) {
  const StructuralModel m = two_mode();
  const Process p = with_damping(half_immersion(2), 1e5);
  const double ref = first_order_zero_step(m, p, 1500.0);
  EXPECT_NEAR(limit(m, p, options(3, 16), 1500.0) / ref, 1.0, kFirstOrderAgree);
  EXPECT_NEAR(limit(m, p, options(3, kRealCutterSteps), 1500.0) / ref, 1.0, kAutoAgreeStrongDamping);
}
TEST(SdmCutterCollocation, ProcessDampingKeepsOrderSix) {
  const StructuralModel m = issue45_tool();
  const Process p = with_damping(issue45_cutter(), 2e5);
  const double rpm = 3000.0, ref = limit(m, p, options(3, 24), rpm);
  const double e4 = std::abs(limit(m, p, options(3, 4), rpm) / ref - 1.0);
  const double e8 = std::abs(limit(m, p, options(3, 8), rpm) / ref - 1.0);
  EXPECT_GT(e4 / e8, kOrderSixRatioMin) << "4 steps: " << e4 << ", 8 steps: " << e8;
}

TEST(SdmCutterCollocation, TypeFrequencyAndLobeAreTheFirstOrders) {
  const StructuralModel m = issue45_tool();
  const Process p = Process::milling(issue45_cutter());
  const SemiDiscretizationSolver first(m, p, options(0, 128)), coll(m, p, options(kRealCutterNodes, kRealCutterSteps));
  for (double rpm : {1000.0, 5000.0, 12000.0, 20000.0}) {
    FloquetResult ff, fc;
    const StabilityLimit a = first.limit_at(SpindleSpeed(rpm), &ff), b = coll.limit_at(SpindleSpeed(rpm), &fc);
    ASSERT_TRUE(a.bounded() && b.bounded()) << rpm;
    EXPECT_EQ(fc.type, ff.type) << rpm;
    EXPECT_EQ(b.lobe, a.lobe) << rpm;
    EXPECT_NEAR(b.chatter_frequency_hz, a.chatter_frequency_hz, 1.0) << rpm;  // Hz
    EXPECT_NEAR(fc.spectral_radius, 1.0, 1e-6) << rpm;
    // ρ on both sides of the limit, from the same map.
    EXPECT_LT(coll.analyse(rpm, 0.99 * b.depth_limit_m).spectral_radius, 1.0) << rpm;
    EXPECT_GT(coll.analyse(rpm, 1.01 * b.depth_limit_m).spectral_radius, 1.0) << rpm;
  }
}

TEST(SdmCutterCollocation, StraightCutterOnTheGeneralPathEqualsTheToothPeriodGrid) {
  const StructuralModel m = two_mode();
  const Process p = Process::milling(half_immersion(3));
  SemiDiscretizationOptions general = options(3, kCollocationSteps);
  general.general_cutter_path = true;
  for (double rpm : {6000.0, 11000.0, 17000.0}) {
    const double a = limit(m, p, options(3, kCollocationSteps), rpm), b = limit(m, p, general, rpm);
    EXPECT_NEAR(b / a, 1.0, kGeneralVsToothGrid) << rpm << ": general " << b << " vs tooth grid " << a;
  }
}

}  // namespace
}  // namespace chatter
