// The cutting law's static side (include/chatter/cutting_law.hpp): the
// closed-form means against an independent quadrature of the force law of
// docs/physics.md §3, the sampled revolution (runout path) against the
// closed form, helix and pitch leaving the means alone, the removal rate of
// a ball end against the circular segment, power = K_t × removal rate, the
// turning insert, the shop fit's prediction and the forced response's mean
// force read from the same law, and the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "chatter/cutting_force.hpp"
#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/shop.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

MillingParameters cutter(int teeth, double immersion, MillingDirection dir) {
  MillingParameters p;
  p.teeth = teeth;
  p.tangential_coefficient_n_per_m2 = 7e8;
  p.radial_coefficient_n_per_m2 = 2.1e8;
  p.radial_immersion = immersion;
  p.direction = dir;
  p.tool_diameter_m = 0.016;
  return p;
}

// The mean force on the tool by a midpoint rule over one revolution, written
// from §3 alone: tooth j at φ = Ωt + 2πj/N_t cuts h = f sin φ inside the arc,
// F_t = K_t a h + K_te a, F_r = K_r a h + K_re a, F_x = −F_t cos φ − F_r sin φ,
// F_y = F_t sin φ − F_r cos φ; and the summed tangential force.
struct Quadrature {
  Eigen::Vector2d force{0.0, 0.0};
  double tangential = 0.0;
};
Quadrature quadrature(const MillingParameters& p, double f, double a, double kte, double kre) {
  const double en = p.direction == MillingDirection::kDown ? std::acos(2 * p.radial_immersion - 1) : 0.0;
  const double ex = p.direction == MillingDirection::kDown ? kPi : std::acos(1 - 2 * p.radial_immersion);
  const int n = 200000;
  Quadrature q;
  for (int i = 0; i < n; ++i) {
    const double th = 2 * kPi * (i + 0.5) / n;
    for (int j = 0; j < p.teeth; ++j) {
      const double phi = std::fmod(th + 2 * kPi * j / p.teeth, 2 * kPi);
      if (phi < en || phi > ex) continue;
      const double h = f * std::sin(phi);
      const double ft = p.tangential_coefficient_n_per_m2 * a * h + kte * a;
      const double fr = p.radial_coefficient_n_per_m2 * a * h + kre * a;
      q.force += Eigen::Vector2d(-ft * std::cos(phi) - fr * std::sin(phi), ft * std::sin(phi) - fr * std::cos(phi));
      q.tangential += ft;
    }
  }
  q.force /= n;
  q.tangential /= n;
  return q;
}

TEST(CuttingLaw, MillingMeansMatchAQuadratureOfTheForceLaw) {
  const double f = 1e-4, a = 2e-3, rpm = 9000.0, D = 0.016;
  for (const double ae : {0.05, 0.3, 0.5, 1.0})
    for (const MillingDirection dir : {MillingDirection::kDown, MillingDirection::kUp}) {
      const MillingParameters mp = cutter(3, ae, dir);
      const EdgeCoefficients edge{2.4e4, 1.1e4};
      const MeanCut m = CuttingLaw::of(Process::milling(mp), {0.0, edge})->mean({rpm, a, f, D});
      const Quadrature q = quadrature(mp, f, a, edge.tangential_n_per_m, edge.radial_n_per_m);
      const double scale = q.force.norm() + 1.0;
      EXPECT_LT((m.force_n - q.force).norm(), 2e-4 * scale) << "a_e/D " << ae;
      EXPECT_NEAR(m.tangential_force_n, q.tangential, 2e-4 * q.tangential) << "a_e/D " << ae;
      EXPECT_DOUBLE_EQ(m.torque_n_m, m.tangential_force_n * D / 2);
      EXPECT_NEAR(m.power_w, m.torque_n_m * 2 * kPi * rpm / 60, 1e-12 * m.power_w);
      // a × a_e × f N_t N / 60.
      EXPECT_NEAR(m.removal_rate_m3_per_s, a * ae * D * f * 3 * rpm / 60, 1e-15 * m.removal_rate_m3_per_s + 1e-30);
      EXPECT_NEAR(m.cutting_speed_m_per_s, kPi * D * rpm / 60, 1e-15);
    }
}

TEST(CuttingLaw, WithoutEdgeForcesPowerIsTheTangentialCoefficientTimesTheRemovalRate) {
  // P = Ω R F̄t = Ω R (N_t a / 2π) K_t f (cos φ_en − cos φ_ex), and the cut's
  // width across the feed is R (cos φ_en − cos φ_ex) = a_e: P = K_t × MRR.
  for (const double ae : {0.1, 0.5, 1.0}) {
    const MeanCut m = CuttingLaw::of(Process::milling(cutter(4, ae, MillingDirection::kUp)))->mean({6000, 3e-3, 8e-5, 0.016});
    EXPECT_NEAR(m.power_w, 7e8 * m.removal_rate_m3_per_s, 1e-12 * m.power_w);
  }
}

TEST(CuttingLaw, HelixPitchAndTheSampledRevolutionAgreeWithTheClosedForm) {
  // A helical variable-pitch cutter with a runout of 1e-12 m takes the
  // sampled path (360 samples per tooth, 16 slices); its means are those of
  // the straight, equally spaced cutter (§8) to the sampling error.
  MillingParameters mp = cutter(4, 0.5, MillingDirection::kDown);
  const Process straight = Process::milling(mp);
  mp.pitch_angles_rad = {80 * kPi / 180, 100 * kPi / 180, 80 * kPi / 180, 100 * kPi / 180};
  mp.helix_angles_rad = {30 * kPi / 180};
  const Process helix = Process::milling(mp);
  mp.runout_m = {1e-12, 0.0, 0.0, 0.0};
  const Process sampled = Process::milling(mp);
  ASSERT_TRUE(sampled.has_runout());
  const CutPoint p{8000, 4e-3, 1e-4, 0.016};
  const MeanCut a = CuttingLaw::of(straight)->mean(p), b = CuttingLaw::of(helix)->mean(p),
                c = CuttingLaw::of(sampled)->mean(p);
  EXPECT_LT((a.force_n - b.force_n).norm(), 1e-12 * a.force_n.norm());
  EXPECT_LT((a.force_n - c.force_n).norm(), 2e-3 * a.force_n.norm());
  EXPECT_NEAR(c.tangential_force_n, a.tangential_force_n, 2e-3 * a.tangential_force_n);
  EXPECT_NEAR(c.torque_n_m, a.torque_n_m, 2e-3 * a.torque_n_m);
  EXPECT_DOUBLE_EQ(c.removal_rate_m3_per_s, a.removal_rate_m3_per_s);
  // The peak is at least the mean resultant and the cutting_load wrapper reads the law.
  const double peak = CuttingLaw::of(helix)->peak_force_n(p);
  EXPECT_GT(peak, a.force_n.norm());
  const CuttingLoad load = cutting_load(helix, p.spindle_rpm, p.depth_m, p.feed_m, p.diameter_m, 0.0);
  EXPECT_EQ(load.force_n, peak);
  EXPECT_EQ(load.torque_n_m, b.torque_n_m);
}

TEST(CuttingLaw, BallEndSlotRemovesTheCircularSegment) {
  // A ball end of radius R in a slot at depth a <= R cuts the circular
  // segment R² acos((R − a)/R) − (R − a) sqrt(2Ra − a²) across the feed.
  MillingParameters mp = cutter(2, 1.0, MillingDirection::kDown);
  mp.tool_diameter_m = 0.010;
  mp.cutter.geometry = CutterGeometry::kBall;
  mp.cutter.slices = 400;
  const Process ball = Process::milling(mp);
  const double R = 0.005, f = 1e-4, rpm = 10000;
  for (const double a : {1e-3, 2.5e-3, 5e-3}) {
    const double segment = R * R * std::acos((R - a) / R) - (R - a) * std::sqrt(2 * R * a - a * a);
    const MeanCut m = CuttingLaw::of(ball)->mean({rpm, a, f, 0.010});
    EXPECT_NEAR(m.removal_rate_m3_per_s, segment * f * 2 * rpm / 60, 2e-4 * segment * f * 2 * rpm / 60) << a;
    // Without an axial coefficient the slice's specific energy is still K_t.
    EXPECT_NEAR(m.power_w, 7e8 * m.removal_rate_m3_per_s, 1e-10 * m.power_w) << a;
  }
}

TEST(CuttingLaw, BallEndWithRunoutSamplesTheForcesAndKeepsTheVolume) {
  // Runout on a ball end: the forces from the sampled revolution (its own
  // slices), within the sampling error of the closed form for a runout of
  // 1e-12 m — each slice's arc is counted in steps of 1/720 of a revolution,
  // ~0.5 % of a 90° arc (measured 0.47 %), which the helix's phase shifts do
  // not average out on a ball's slices of different arcs; the removal rate
  // is the profile's, unchanged.
  MillingParameters mp = cutter(2, 0.5, MillingDirection::kDown);
  mp.tool_diameter_m = 0.010;
  mp.cutter.geometry = CutterGeometry::kBall;
  const Process ball = Process::milling(mp);
  mp.runout_m = {1e-12, 0.0};
  const Process runout = Process::milling(mp);
  const CutPoint p{9000, 3e-3, 1e-4, 0.010};
  const MeanCut a = CuttingLaw::of(ball)->mean(p), b = CuttingLaw::of(runout)->mean(p);
  EXPECT_GT(a.removal_rate_m3_per_s, 0.0);
  EXPECT_EQ(b.removal_rate_m3_per_s, a.removal_rate_m3_per_s);
  EXPECT_LT((b.force_n - a.force_n).norm(), 1e-2 * a.force_n.norm());
  EXPECT_NEAR(b.torque_n_m, a.torque_n_m, 1e-2 * a.torque_n_m);
}

TEST(CuttingLaw, TurningInsertForceTorquePowerAndRemoval) {
  TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = 1.2e9;
  tp.radial_force_coefficient_n_per_m2 = 0.5e9;
  tp.lead_angle_rad = 60 * kPi / 180;
  const Process insert = Process::turning(tp);
  const double kc = 2.0e9, a = 2e-3, f = 2e-4, D = 0.06, rpm = 800;
  const auto law = CuttingLaw::of(insert, {kc, {}});
  const MeanCut m = law->mean({rpm, a, f, D});
  // −a f d, d = K_f n + K_r e at κ = 60°: n = (sin κ, cos κ), e = (−cos κ, sin κ).
  const double k = 60 * kPi / 180;
  const Eigen::Vector2d d = 1.2e9 * Eigen::Vector2d(std::sin(k), std::cos(k)) + 0.5e9 * Eigen::Vector2d(-std::cos(k), std::sin(k));
  EXPECT_LT((m.force_n + a * f * d).norm(), 1e-12 * (a * f * d).norm());
  EXPECT_DOUBLE_EQ(m.tangential_force_n, kc * a * f);
  EXPECT_NEAR(m.torque_n_m, kc * a * f * D / 2, 1e-15);
  EXPECT_NEAR(m.power_w, kc * a * f * kPi * D * rpm / 60, 1e-12 * m.power_w);
  EXPECT_NEAR(m.removal_rate_m3_per_s, a * f * kPi * D * rpm / 60, 1e-20);
  EXPECT_NEAR(law->peak_force_n({rpm, a, f, D}), std::hypot(kc * a * f, a * f * std::hypot(1.2e9, 0.5e9)), 1e-9);
  // Without K_c: the in-plane force and the removal are known, the rest NaN.
  const MeanCut u = CuttingLaw::of(insert)->mean({rpm, a, f, D});
  EXPECT_EQ(u.force_n, m.force_n);
  EXPECT_TRUE(std::isnan(u.power_w) && std::isnan(u.torque_n_m));
  EXPECT_EQ(u.removal_rate_m3_per_s, m.removal_rate_m3_per_s);
  EXPECT_THROW(CuttingLaw::of(insert)->peak_force_n({rpm, a, f, D}), InputError);
}

TEST(CuttingLaw, TheShopFitPredictsWithTheSameLaw) {
  const MillingEngagement e{3, 0.3, MillingDirection::kUp};
  const std::array<double, 4> k{7e8, 2.1e8, 2.4e4, 1.1e4};
  const auto shop = mean_forces(e, 1e-4, 2e-3, k);
  const MeanCut m = CuttingLaw::of(Process::milling(cutter(3, 0.3, MillingDirection::kUp)), {0.0, {k[2], k[3]}})
                        ->mean({5000, 2e-3, 1e-4, 0.016});
  EXPECT_DOUBLE_EQ(shop[0], m.force_n.x());
  EXPECT_DOUBLE_EQ(shop[1], m.force_n.y());
  EXPECT_NEAR(mean_power(e, 1e-4, 2e-3, 5000, 0.016, k[0], k[2]), m.power_w, 1e-12 * m.power_w);
  double en = 0, ex = 0;
  engagement_angles(e, en, ex);
  const Process p = Process::milling(cutter(3, 0.3, MillingDirection::kUp));
  EXPECT_EQ(en, p.entry_angle());
  EXPECT_EQ(ex, p.exit_angle());
}

TEST(CuttingLaw, TheForcedResponsesMeanForceIsTheLaws) {
  // The forced response builds its mean force as the zeroth Fourier
  // coefficient of the tooth force (complex arc exponentials, helix factor):
  // an independent path to the same number.
  StructuralModel model;
  model.tool.modes.push_back(Mode::from_stiffness(700.0, 0.02, 6e6, {1.0, 0.0}));
  model.tool.modes.push_back(Mode::from_stiffness(820.0, 0.03, 9e6, {0.2, 1.0}));
  MillingParameters mp = cutter(3, 0.4, MillingDirection::kDown);
  mp.helix_angles_rad = {30 * kPi / 180};
  const Process helix = Process::milling(mp);
  ForcedSettings st;
  st.spindle_rpm = 7000;
  st.depth_m = 0.5e-3;
  st.feed_m = 1e-4;
  st.record_path = false;
  const ForcedResponse r = ForcedResponseSolver(model, helix).response(st);
  const MeanCut m = CuttingLaw::of(helix)->mean({7000, 0.5e-3, 1e-4, kNaN});
  EXPECT_NEAR(r.mean_force_x_n, m.force_n.x(), 1e-10 * m.force_n.norm());
  EXPECT_NEAR(r.mean_force_y_n, m.force_n.y(), 1e-10 * m.force_n.norm());
  // An unknown diameter leaves torque, power and removal unknown, not wrong.
  EXPECT_TRUE(std::isnan(m.torque_n_m) && std::isnan(m.power_w) && std::isnan(m.removal_rate_m3_per_s));
}

TEST(CuttingLaw, RefusesWhatItDoesNotModel) {
  const Process mill = Process::milling(cutter(2, 0.5, MillingDirection::kDown));
  const Process turn = Process::turning({1e9});
  MillingParameters bp = cutter(2, 0.5, MillingDirection::kDown);
  bp.cutter.geometry = CutterGeometry::kBall;
  const Process ball = Process::milling(bp);
  EXPECT_THROW(CuttingLaw::of(turn, {0.0, {1e4, 0.0}}), InputError);
  EXPECT_THROW(CuttingLaw::of(ball, {0.0, {1e4, 0.0}}), InputError);
  EXPECT_THROW(CuttingLaw::of(mill, {0.0, {-1.0, 0.0}}), InputError);
  EXPECT_THROW(CuttingLaw::of(turn, {-1.0, {}}), InputError);
  const auto law = CuttingLaw::of(mill);
  EXPECT_THROW(law->mean({0.0, 1e-3, 1e-4, 0.016}), InputError);
  EXPECT_THROW(law->mean({1000, -1e-3, 1e-4, 0.016}), InputError);
  EXPECT_THROW(law->mean({1000, 1e-3, kNaN, 0.016}), InputError);
  EXPECT_THROW(law->mean({1000, 1e-3, 1e-4, 0.0}), InputError);
  EXPECT_NO_THROW(law->mean({1000, 1e-3, 1e-4, kNaN}));
}

}  // namespace
}  // namespace chatter
