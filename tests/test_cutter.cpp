// The real cutter of docs/physics.md §8 in the process description: the
// closed-form time–height integrals against slice-by-slice quadrature, the
// delays, the engagement events, the runout chip worked by hand, and the
// refusals of impossible geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "chatter/error.hpp"
#include "chatter/process.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

MillingParameters base(int teeth, double immersion, MillingDirection dir) {
  MillingParameters p;
  p.teeth = teeth;
  p.tangential_coefficient_n_per_m2 = 6e8;
  p.radial_coefficient_n_per_m2 = 2e8;
  p.radial_immersion = immersion;
  p.direction = dir;
  p.tool_diameter_m = 0.012;
  return p;
}

// ∫_{ta}^{tb} ∫_0^a g H₁(φ_j(t, z)) dz dt by the composite midpoint rule in
// z (n slices) with the exact time integral of each straight slice.
Eigen::Matrix2d slice_quadrature(const Process& p, int j, double ta, double tb, double a, double rpm, int n,
                                 bool damping) {
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  const double dz = a / n;
  // One slice at height z is a straight tooth shifted by κ z; integrate it in
  // time with 4000 midpoint steps (the window edges cost O(h) per slice).
  for (int i = 0; i < n; ++i) {
    const double z = (i + 0.5) * dz;
    const int steps = 4000;
    const double h = (tb - ta) / steps;
    for (int k = 0; k < steps; ++k) {
      const double t = ta + (k + 0.5) * h;
      const double phi = p.tooth_angle_rad(j, t, z, rpm);
      if (!p.in_cut(phi)) continue;
      sum += (damping ? Process::damping_direction(phi) : p.tooth_matrix(phi)) * (h * dz);
    }
  }
  return sum;
}

TEST(Cutter, StraightToothIntegralIsDepthTimesTheAntiderivative) {
  MillingParameters mp = base(3, 0.4, MillingDirection::kUp);
  mp.pitch_angles_rad = {100 * kDeg, 130 * kDeg, 130 * kDeg};
  const Process p = Process::milling(mp);
  const double rpm = 9000.0, omega = 2.0 * kPi * rpm / 60.0, a = 2e-3;
  // A window inside one pass of tooth 1 through the arc.
  const double en = p.entry_angle(), ex = p.exit_angle();
  const double t0 = (en + p.tooth_offset_rad(1)) / omega, t1 = (ex + p.tooth_offset_rad(1)) / omega;
  const Eigen::Matrix2d got = p.tooth_force_integral(1, t0, t1, a, rpm);
  const Eigen::Matrix2d want = a / omega * (p.tooth_matrix_antiderivative(ex) - p.tooth_matrix_antiderivative(en));
  EXPECT_LT((got - want).norm(), 1e-12 * want.norm());
}

TEST(Cutter, HelixIntegralMatchesSliceQuadrature) {
  MillingParameters mp = base(4, 0.5, MillingDirection::kDown);
  mp.helix_angles_rad = {30 * kDeg, 35 * kDeg, 30 * kDeg, 35 * kDeg};
  const Process p = Process::milling(mp);
  const double rpm = 6000.0, T = 60.0 / rpm;
  // Spans across the arc edges, across a whole revolution and before t = 0.
  for (const auto& [ta, tb, a] : {std::tuple{0.1 * T, 0.35 * T, 3e-3}, std::tuple{-0.4 * T, 1.3 * T, 8e-3},
                                  std::tuple{0.52 * T, 0.53 * T, 0.5e-3}}) {
    for (int j = 0; j < 4; ++j) {
      const Eigen::Matrix2d got = p.tooth_force_integral(j, ta, tb, a, rpm);
      const Eigen::Matrix2d want = slice_quadrature(p, j, ta, tb, a, rpm, 200, false);
      // Quadrature error: a window edge inside a time step, O(h) per slice.
      EXPECT_LT((got - want).norm(), 2e-3 * std::max(want.norm(), 1e-9 * 6e8 * a * (tb - ta)))
          << "tooth " << j << " span " << ta << " .. " << tb;
      const Eigen::Matrix2d gd = p.tooth_damping_integral(j, ta, tb, a, rpm);
      const Eigen::Matrix2d wd = slice_quadrature(p, j, ta, tb, a, rpm, 200, true);
      EXPECT_LT((gd - wd).norm(), 2e-3 * std::max(wd.norm(), 1e-9 * a * (tb - ta)));
    }
  }
}

TEST(Cutter, ForceDirectionIntegralMatchesSliceQuadrature) {
  // ∫∫ g v(φ) dz dt, v = (K_t cos φ + K_r sin φ, −(K_t sin φ − K_r cos φ)) (§3,
  // the force per unit chip): the force of a runout offset over a step.
  MillingParameters mp = base(4, 0.5, MillingDirection::kDown);
  mp.helix_angles_rad = {30 * kDeg, 35 * kDeg, 30 * kDeg, 35 * kDeg};
  const Process p = Process::milling(mp);
  const double rpm = 6000.0, T = 60.0 / rpm;
  for (const auto& [ta, tb, a] : {std::tuple{0.1 * T, 0.35 * T, 3e-3}, std::tuple{-0.4 * T, 1.3 * T, 8e-3}}) {
    for (int j = 0; j < 4; ++j) {
      const Eigen::Vector2d got = p.tooth_force_direction_integral(j, ta, tb, a, rpm);
      Eigen::Vector2d want = Eigen::Vector2d::Zero();
      const int n = 200, steps = 4000;
      const double dz = a / n, h = (tb - ta) / steps;
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < steps; ++k) {
          const double phi = p.tooth_angle_rad(j, ta + (k + 0.5) * h, (i + 0.5) * dz, rpm);
          if (!p.in_cut(phi)) continue;
          want += Eigen::Vector2d(6e8 * std::cos(phi) + 2e8 * std::sin(phi), -(6e8 * std::sin(phi) - 2e8 * std::cos(phi))) *
                  (h * dz);
        }
      // Quadrature error: a window edge inside a time step, O(h) per slice.
      EXPECT_LT((got - want).norm(), 2e-3 * std::max(want.norm(), 1e-9 * 6e8 * a * (tb - ta))) << "tooth " << j;
      // And the same direction as force_direction, the §3 law.
      EXPECT_LT((p.force_direction(0.7) - Eigen::Vector2d(6e8 * std::cos(0.7) + 2e8 * std::sin(0.7),
                                                          -(6e8 * std::sin(0.7) - 2e8 * std::cos(0.7))))
                    .norm(),
                1e-6);
    }
  }
  // The feed of a tooth: N_t f_z θ_j / 2π.
  MillingParameters vp = base(4, 0.5, MillingDirection::kDown);
  vp.pitch_angles_rad = {80 * kDeg, 100 * kDeg, 80 * kDeg, 100 * kDeg};
  const Process q = Process::milling(vp);
  EXPECT_NEAR(q.feed_of_tooth_m(1, 0.1e-3), 4 * 0.1e-3 * 100.0 / 360.0, 1e-18);
}

TEST(Cutter, HelixLeavesTheRevolutionAverageUnchanged) {
  // ∫ over one revolution of every tooth's H₁ / T = a H₀ whatever the helix.
  MillingParameters mp = base(4, 0.3, MillingDirection::kDown);
  const Process straight = Process::milling(mp);
  mp.helix_angles_rad = {40 * kDeg};
  mp.pitch_angles_rad = {80 * kDeg, 100 * kDeg, 80 * kDeg, 100 * kDeg};
  const Process helix = Process::milling(mp);
  const double rpm = 3000.0, T = 60.0 / rpm, a = 5e-3;
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  for (int j = 0; j < 4; ++j) sum += helix.tooth_force_integral(j, 0.17 * T, 1.17 * T, a, rpm);
  const Eigen::Matrix2d want = a * T * straight.average_directional_matrix();
  EXPECT_LT((sum - want).norm(), 1e-12 * want.norm());
  Eigen::Matrix2d dsum = Eigen::Matrix2d::Zero();
  for (int j = 0; j < 4; ++j) dsum += helix.tooth_damping_integral(j, 0.0, T, a, rpm);
  EXPECT_LT((dsum - a * T * helix.average_damping_direction()).norm(), 1e-12 * a * T);
}

TEST(Cutter, AverageDampingDirectionByQuadrature) {
  const Process p = Process::milling(base(3, 0.25, MillingDirection::kUp));
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  const int n = 100000;
  const double en = p.entry_angle(), ex = p.exit_angle(), h = (ex - en) / n;
  for (int i = 0; i < n; ++i) q += Process::damping_direction(en + (i + 0.5) * h) * h;
  q *= 3.0 / (2.0 * kPi);
  EXPECT_LT((q - p.average_damping_direction()).norm(), 1e-9);
  EXPECT_DOUBLE_EQ(Process::turning({1e9}).average_damping_direction()(0, 0), 1.0);
}

TEST(Cutter, DelaysAndPeriod) {
  MillingParameters mp = base(4, 1.0, MillingDirection::kDown);
  const Process uniform = Process::milling(mp);
  EXPECT_TRUE(uniform.uniform_cutter());
  EXPECT_DOUBLE_EQ(uniform.period_s(6000.0), 60.0 / (6000.0 * 4));
  mp.pitch_angles_rad = {70 * kDeg, 110 * kDeg, 70 * kDeg, 110 * kDeg};
  const Process pitch = Process::milling(mp);
  EXPECT_FALSE(pitch.uniform_cutter());
  EXPECT_TRUE(pitch.has_variable_pitch());
  EXPECT_DOUBLE_EQ(pitch.period_s(6000.0), 0.01);
  EXPECT_NEAR(pitch.tooth_delay_s(0, 0.0, 6000.0), 0.01 * 70.0 / 360.0, 1e-15);
  EXPECT_NEAR(pitch.tooth_offset_rad(2), 180 * kDeg, 1e-12);
  // Variable helix: τ_j(z) = [θ_j + z (tan β_j − tan β_{j−1})/R]/Ω.
  mp.pitch_angles_rad.clear();
  mp.helix_angles_rad = {30 * kDeg, 40 * kDeg, 30 * kDeg, 40 * kDeg};
  const Process vh = Process::milling(mp);
  EXPECT_TRUE(vh.has_variable_helix());
  EXPECT_FALSE(vh.uniform_cutter());
  const double omega = 2.0 * kPi * 6000.0 / 60.0, z = 4e-3, R = 0.006;
  EXPECT_NEAR(vh.tooth_delay_s(1, z, 6000.0), (90 * kDeg + z * (std::tan(40 * kDeg) - std::tan(30 * kDeg)) / R) / omega,
              1e-15);
  EXPECT_NEAR(vh.tooth_delay_s(0, z, 6000.0), (90 * kDeg + z * (std::tan(30 * kDeg) - std::tan(40 * kDeg)) / R) / omega,
              1e-15);
  // One helix on every tooth keeps one delay.
  mp.helix_angles_rad = {30 * kDeg};
  EXPECT_TRUE(Process::milling(mp).uniform_cutter());
}

TEST(Cutter, EngagementEventsAreWhereTheCutChanges) {
  MillingParameters mp = base(2, 0.25, MillingDirection::kDown);
  mp.helix_angles_rad = {30 * kDeg};
  const Process p = Process::milling(mp);
  const double rpm = 12000.0, a = 2e-3, T = p.period_s(rpm);
  const auto ev = p.engagement_events_s(rpm, a);
  ASSERT_EQ(ev.size(), 4u);  // tip and top, entry and exit, of one tooth per period
  for (const double t : ev) {
    EXPECT_GE(t, 0.0);
    EXPECT_LT(t, T);
  }
  // Between events the set of (tooth, end) in the cut is constant; at each
  // event one of them changes.
  auto state = [&](double t) {
    int s = 0, bit = 0;
    for (int j = 0; j < 2; ++j)
      for (const double z : {0.0, a}) s |= (p.in_cut(p.tooth_angle_rad(j, t, z, rpm)) ? 1 : 0) << bit++;
    return s;
  };
  for (std::size_t i = 0; i < ev.size(); ++i) {
    const double e = ev[i];
    EXPECT_NE(state(e - 1e-9 * T), state(e + 1e-9 * T)) << "event " << i;
  }
}

TEST(Cutter, RunoutChipWorkedByHand) {
  // 3 equal teeth, f_z = 0.1 mm, at φ = 90° (sin φ = 1). Tooth 3 (index 2)
  // sits 0.15 mm in: after tooth 2 it reaches 0.1 − 0.15 < 0, so it cuts
  // nothing; tooth 1 then cuts what tooth 2 left (0.2 mm, not 0.1 + 0.15).
  MillingParameters mp = base(3, 1.0, MillingDirection::kDown);
  mp.runout_m = {0.0, 0.0, -0.15e-3};
  const Process p = Process::milling(mp);
  const double fz = 0.1e-3, phi = kPi / 2;
  EXPECT_EQ(p.static_chip_m(2, phi, fz), 0.0);
  EXPECT_NEAR(p.static_chip_m(0, phi, fz), 0.2e-3, 1e-15);  // min(0.25, 0.2, 0.3)
  EXPECT_NEAR(p.static_chip_m(1, phi, fz), 0.1e-3, 1e-15);  // min(0.1, 0.35, 0.3)
  // 0.05 mm in: tooth 3 cuts 0.1 − 0.05, tooth 1 then 0.1 + 0.05.
  mp.runout_m = {0.0, 0.0, -0.05e-3};
  const Process q = Process::milling(mp);
  EXPECT_NEAR(q.static_chip_m(2, phi, fz), 0.05e-3, 1e-15);
  EXPECT_NEAR(q.static_chip_m(0, phi, fz), 0.15e-3, 1e-15);
  EXPECT_NEAR(q.static_chip_m(0, kPi / 6, fz), std::min(0.05e-3 + 0.05e-3, 0.1e-3), 1e-15);  // sin 30° = 1/2
  // Variable pitch: the advance is N_t f_z θ_j / 2π.
  MillingParameters vp = base(2, 1.0, MillingDirection::kDown);
  vp.pitch_angles_rad = {150 * kDeg, 210 * kDeg};
  const Process v = Process::milling(vp);
  EXPECT_NEAR(v.static_chip_m(1, phi, fz), 2 * fz * 210.0 / 360.0, 1e-15);
  EXPECT_NEAR(v.static_chip_m(0, phi, fz), 2 * fz * 150.0 / 360.0, 1e-15);
  // Without runout: f_z sin φ, floored at 0.
  const Process r = Process::milling(base(3, 1.0, MillingDirection::kDown));
  EXPECT_NEAR(r.static_chip_m(1, 0.7, fz), fz * std::sin(0.7), 1e-18);
  EXPECT_EQ(r.static_chip_m(1, -0.7, fz), 0.0);
}

void expect_refused(const MillingParameters& mp, const std::string& fragment) {
  try {
    (void)Process::milling(mp);
    ADD_FAILURE() << "accepted; wanted: " << fragment;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Cutter, ImpossibleGeometryIsRefused) {
  MillingParameters mp = base(4, 1.0, MillingDirection::kDown);
  MillingParameters bad = mp;
  bad.pitch_angles_rad = {90 * kDeg, 90 * kDeg, 90 * kDeg, 80 * kDeg};
  expect_refused(bad, "must sum to 360 deg");
  bad.pitch_angles_rad = {90 * kDeg, 90 * kDeg, 180 * kDeg};
  expect_refused(bad, "need one per tooth (4)");
  bad.pitch_angles_rad = {0.0, 180 * kDeg, 90 * kDeg, 90 * kDeg};
  expect_refused(bad, "must be > 0");
  bad = mp;
  bad.helix_angles_rad = {90 * kDeg};
  expect_refused(bad, "must be in [0, 90) deg");
  bad.helix_angles_rad = {-1 * kDeg};
  expect_refused(bad, "must be in [0, 90) deg");
  bad.helix_angles_rad = {30 * kDeg, 30 * kDeg};
  expect_refused(bad, "need 1 (every tooth) or one per tooth (4)");
  bad = mp;
  bad.tool_diameter_m = 0.0;
  bad.helix_angles_rad = {30 * kDeg};
  expect_refused(bad, "a helix needs the tool diameter");
  bad = mp;
  bad.runout_m = {1e-5, 0.0};
  expect_refused(bad, "need one per tooth (4)");
  bad.runout_m = {1e-5, 0.0, 0.0, 0.007};
  expect_refused(bad, "smaller than the tool radius");
  bad = mp;
  bad.process_damping_coefficient_n_per_m = -1.0;
  expect_refused(bad, "must be >= 0 N/m");
  TurningParameters t{1e9};
  t.process_damping_coefficient_n_per_m = 1e5;
  EXPECT_THROW((void)Process::turning(t), InputError);
  t.workpiece_diameter_m = 0.05;
  EXPECT_NO_THROW((void)Process::turning(t));
}

TEST(Cutter, ProcessDampingPerDepthIsCOverV) {
  MillingParameters mp = base(2, 1.0, MillingDirection::kDown);
  mp.process_damping_coefficient_n_per_m = 2e5;
  const Process p = Process::milling(mp);
  EXPECT_NEAR(p.process_damping_per_depth(1000.0), 2e5 / (kPi * 0.012 * 1000.0 / 60.0), 1e-9);
  EXPECT_EQ(Process::milling(base(2, 1.0, MillingDirection::kDown)).process_damping_per_depth(1000.0), 0.0);
}

}  // namespace
}  // namespace chatter
