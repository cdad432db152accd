// The cutting law's regenerative side (chatter/regenerative_cut.hpp): the cut
// at one speed and depth as edges with delays and exact step integrals, and
// the `sdm` general path that reads a cut only through it.
//
// Independent answers: the integrals over a whole revolution against a H₀(a)
// (the closed-form average of Altintas & Budak, Process::average_directional_matrix,
// which no edge code computes) for straight, helical, variable-helix and
// ball-end cutters; turning's constant a H(a) against the insert's chord;
// and sdm's limits on the general path against its fast paths (a different
// grid and state basis of the same equation) for the orthogonal cut, an
// insert with a lead angle and a nose radius, and process damping.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/regenerative_cut.hpp"
#include "chatter/semi_discretization.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// ---- tolerances ----
// A revolution's integral against a H₀(a): both closed forms, round-off
// only (relative to |a H₀| · revolution; measured 5e-16 at most).
constexpr double kClosedForm = 1e-12;
// A ball end: its slices' arcs and lead angles are taken at mid height
// (AxialSlice), and H₀(a) integrates the same slices: round-off again
// (measured 3e-16).
constexpr double kSlices = 1e-12;
// sdm on the general path against the fast path: the same equation and step
// count; the state basis (full 2-D delayed displacement instead of the
// rank-1 chip direction) and the per-step maps differ only in round-off
// and in the depth search's tolerance (1e-7 here). Measured: 6e-12 on the
// orthogonal cut, 4e-9 on the inserts, 2.5e-8 with process damping.
constexpr double kPathsAgree = 1e-6;

Process straight_mill(double immersion, MillingDirection dir) {
  MillingParameters mp;
  mp.teeth = 3;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 2e8;
  mp.radial_immersion = immersion;
  mp.direction = dir;
  mp.tool_diameter_m = 0.012;
  return Process::milling(mp);
}

Eigen::Matrix2d revolution_integral(const RegenerativeCut& cut, double rev_s, int pieces) {
  // Split at the events (the integrals are exact anyway; the split also
  // exercises force_integrals on pieces that start and end inside the arc).
  std::vector<double> b{0.0};
  for (int i = 1; i < pieces; ++i) b.push_back(rev_s * i / pieces);
  b.push_back(rev_s);
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  std::vector<Eigen::Matrix2d> per_edge;
  for (std::size_t i = 0; i + 1 < b.size(); ++i) {
    cut.force_integrals(b[i], b[i + 1], per_edge);
    EXPECT_EQ(per_edge.size(), cut.edge_delays_s().size());
    Eigen::Matrix2d piece = Eigen::Matrix2d::Zero();
    for (const Eigen::Matrix2d& e : per_edge) piece += e;
    // The edges sum to the total (per-slice differences against the whole height).
    const Eigen::Matrix2d tot = cut.total_force_integral(b[i], b[i + 1]);
    EXPECT_LE((piece - tot).norm(), 1e-12 * (tot.norm() + 1.0));
    sum += piece;
  }
  return sum;
}

TEST(RegenerativeCut, MillingRevolutionIntegralIsTheDepthTimesTheAverageMatrix) {
  const double rpm = 9000.0, rev = 60.0 / rpm, a = 0.002;
  std::vector<Process> cutters;
  for (const MillingDirection dir : {MillingDirection::kDown, MillingDirection::kUp})
    for (const double ae : {0.05, 0.5, 1.0}) cutters.push_back(straight_mill(ae, dir));
  {  // helix 30°, variable pitch 100/140/120°, variable helix 28/32/30°
    MillingParameters mp = straight_mill(0.4, MillingDirection::kDown).milling_parameters();
    mp.helix_angles_rad = {30 * kDeg};
    cutters.push_back(Process::milling(mp));
    mp.pitch_angles_rad = {100 * kDeg, 140 * kDeg, 120 * kDeg};
    cutters.push_back(Process::milling(mp));
    mp.helix_angles_rad = {28 * kDeg, 32 * kDeg, 30 * kDeg};
    cutters.push_back(Process::milling(mp));
  }
  for (const Process& p : cutters) {
    const auto cut = RegenerativeCut::of(p, rpm, a, 8);
    const Eigen::Matrix2d want = a * p.average_directional_matrix() * rev;
    for (const int pieces : {1, 7}) {
      const Eigen::Matrix2d got = revolution_integral(*cut, rev, pieces);
      EXPECT_LE((got - want).norm(), kClosedForm * want.norm())
          << "immersion " << p.milling_parameters().radial_immersion << ", " << pieces << " pieces:\n"
          << got << "\nvs a H0 T\n" << want;
    }
    // Edges: a tooth each, or 8 slices each with a variable helix; delays a
    // pitch (mean 60/(N N_t) over the teeth).
    const std::vector<double>& d = cut->edge_delays_s();
    const int slices = p.has_variable_helix() ? 8 : 1;
    ASSERT_EQ(d.size(), static_cast<std::size_t>(3 * slices));
    double mean = 0.0;
    for (const double t : d) mean += t;
    EXPECT_NEAR(mean / static_cast<double>(d.size()), p.delay_s(rpm), 1e-12 * p.delay_s(rpm));
    EXPECT_FALSE(cut->engagement_events_s().empty());
    EXPECT_DOUBLE_EQ(cut->pattern_period_s(), p.period_s(rpm));
    EXPECT_DOUBLE_EQ(cut->force_scale_n_per_m2(), 8e8);
    EXPECT_EQ(cut->damping_integral(0.0, rev).norm(), 0.0);  // no process damping given
  }
}

TEST(RegenerativeCut, BallEndRevolutionIntegralIsTheDepthTimesItsAverageMatrix) {
  MillingParameters mp = straight_mill(0.5, MillingDirection::kDown).milling_parameters();
  mp.cutter.geometry = CutterGeometry::kBall;
  mp.axial_coefficient_n_per_m2 = 1e8;
  const Process p = Process::milling(mp);
  const double rpm = 12000.0, rev = 60.0 / rpm;
  for (const double a : {0.0005, 0.003}) {
    const auto cut = RegenerativeCut::of(p, rpm, a, 8);
    const Eigen::Matrix2d want = a * p.average_directional_matrix_at(a) * rev;
    const Eigen::Matrix2d got = revolution_integral(*cut, rev, 5);
    EXPECT_LE((got - want).norm(), kSlices * want.norm()) << a << ":\n" << got << "\nvs\n" << want;
    EXPECT_EQ(cut->edge_delays_s().size(), 3 * p.axial_slices(a).size());  // a tooth × the profile's slices
  }
}

TEST(RegenerativeCut, TurningIsOneEdgeOneRevolutionBackWithTheChordsMatrix) {
  TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = 684e6;
  tp.radial_force_coefficient_n_per_m2 = 0.3 * 684e6;
  tp.lead_angle_rad = 75 * kDeg;
  tp.nose_radius_m = 0.8e-3;
  tp.process_damping_coefficient_n_per_m = 2e5;
  tp.workpiece_diameter_m = 0.06;
  const Process p = Process::turning(tp);
  const double rpm = 700.0, a = 0.0015, dt = 1e-3;
  const auto cut = RegenerativeCut::of(p, rpm, a, 8);
  ASSERT_EQ(cut->edge_delays_s().size(), 1u);
  EXPECT_DOUBLE_EQ(cut->edge_delays_s()[0], 60.0 / rpm);
  EXPECT_DOUBLE_EQ(cut->pattern_period_s(), 60.0 / rpm);
  EXPECT_TRUE(cut->engagement_events_s().empty());
  // a H(a) = b d nᵀ from the chord, written here: b, κ_eq, n, e.
  const InsertChord c = insert_chord(tp.lead_angle_rad, tp.nose_radius_m, a);
  const Eigen::Vector2d n(std::sin(c.lead_angle_rad), std::cos(c.lead_angle_rad));
  const Eigen::Vector2d e(-std::cos(c.lead_angle_rad), std::sin(c.lead_angle_rad));
  const Eigen::Vector2d d = tp.feed_force_coefficient_n_per_m2 * n + tp.radial_force_coefficient_n_per_m2 * e;
  const Eigen::Matrix2d want = c.width_m * d * n.transpose() * dt;
  std::vector<Eigen::Matrix2d> per_edge;
  cut->force_integrals(0.25, 0.25 + dt, per_edge);
  ASSERT_EQ(per_edge.size(), 1u);
  EXPECT_LE((per_edge[0] - want).norm(), 1e-12 * want.norm()) << per_edge[0] << "\nvs\n" << want;
  EXPECT_LE((cut->total_force_integral(0.25, 0.25 + dt) - want).norm(), 1e-12 * want.norm());
  const Eigen::Matrix2d damp = c.width_m * n * n.transpose() * dt;
  EXPECT_LE((cut->damping_integral(0.25, 0.25 + dt) - damp).norm(), 1e-12 * damp.norm());
  EXPECT_DOUBLE_EQ(cut->force_scale_n_per_m2(), 1.3 * 684e6);
}

TEST(RegenerativeCut, RefusesBadArguments) {
  const Process p = straight_mill(0.5, MillingDirection::kDown);
  EXPECT_THROW(RegenerativeCut::of(p, 0.0, 0.001, 8), InputError);
  EXPECT_THROW(RegenerativeCut::of(p, std::nan(""), 0.001, 8), InputError);
  EXPECT_THROW(RegenerativeCut::of(p, 1000.0, -0.001, 8), InputError);
  EXPECT_THROW(RegenerativeCut::of(p, 1000.0, 0.001, 0), InputError);
  EXPECT_NO_THROW(RegenerativeCut::of(p, 1000.0, 0.0, 1));
}

// ---- sdm: the general path (the law's cut only) against the fast paths ----
StructuralModel two_modes() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1.0, 0.0}));
  m.workpiece.modes.push_back(Mode::from_stiffness(150.0, 0.025, 30e6, {0.0, 1.0}));
  return m;
}

void expect_paths_agree(const StructuralModel& m, const Process& p, const std::vector<double>& speeds,
                        double depth_max_m) {
  SemiDiscretizationOptions fast;
  fast.depth_max_m = depth_max_m;
  fast.depth_tolerance = 1e-7;
  fast.collocation_nodes = 0;  // the first-order scheme on both paths
  SemiDiscretizationOptions general = fast;
  general.general_cutter_path = true;
  const SemiDiscretizationSolver a(m, p, fast), b(m, p, general);
  for (const double rpm : speeds) {
    SCOPED_TRACE(std::to_string(rpm) + " rev/min");
    const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lb = b.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(la.bounded() && lb.bounded());
    EXPECT_NEAR(lb.depth_limit_m / la.depth_limit_m, 1.0, kPathsAgree)
        << "general " << lb.depth_limit_m << " vs fast " << la.depth_limit_m;
    EXPECT_NEAR(lb.chatter_frequency_hz / la.chatter_frequency_hz, 1.0, kPathsAgree)
        << lb.chatter_frequency_hz << " vs " << la.chatter_frequency_hz;
    EXPECT_EQ(lb.lobe, la.lobe);
  }
}

TEST(RegenerativeCutSdm, OrthogonalTurningOnTheGeneralPathEqualsTheConstantStep) {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0}));
  TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = 2.4e9;
  expect_paths_agree(m, Process::turning(tp), {1200.0, 1800.0, 2600.0}, 0.01);
}

TEST(RegenerativeCutSdm, InsertWithLeadAngleAndNoseRadiusOnTheGeneralPath) {
  for (const double nose_mm : {0.0, 0.8}) {
    SCOPED_TRACE(std::to_string(nose_mm) + " mm nose");
    TurningParameters tp;
    tp.feed_force_coefficient_n_per_m2 = 684e6;
    tp.radial_force_coefficient_n_per_m2 = 0.3 * 684e6;
    tp.lead_angle_rad = 60 * kDeg;
    tp.nose_radius_m = nose_mm * 1e-3;
    expect_paths_agree(two_modes(), Process::turning(tp), {900.0, 1500.0}, 0.02);
  }
}

TEST(RegenerativeCutSdm, TurningProcessDampingOnTheGeneralPath) {
  TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = 684e6;
  tp.lead_angle_rad = 75 * kDeg;
  tp.process_damping_coefficient_n_per_m = 2e5;
  tp.workpiece_diameter_m = 0.06;
  expect_paths_agree(two_modes(), Process::turning(tp), {200.0, 700.0}, 0.02);
}

}  // namespace
}  // namespace chatter
