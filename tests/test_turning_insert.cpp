// Turning inserts (docs/turning_inserts.md): lead angle, nose radius and the
// radial force coefficient, in the geometry (the chord of the engaged edge),
// in every method (analytic, coupled, sdm, time-domain), and in the config.
//
// The answers are built in: the chord is recomputed here from a different
// construction (a sharp wedge rounded by a circle on its bisector); the 1-DOF
// limits are Tlusty's closed form times the oriented direction and width
// factors derived here; the methods are checked against each other.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// Tolerances, each with its reason.
// The chord from two constructions of the same geometry: round-off only.
constexpr double kGeometry = 1e-12;
// Tlusty's closed form against the analytic search (roots refined to
// round-off, docs/physics.md §4): relative.
constexpr double kClosedForm = 1e-9;
// analytic vs coupled: no shared algebra but the root search (as
// tests/test_coupled.cpp); with a nose radius both iterate on the depth to
// 1e-12 relative, so the limit agrees to the same order: relative.
constexpr double kMethodsAgree = 1e-8;
// sdm (64 steps per period, first-order) vs the exact averaged limit of
// turning: within 0.5 % (tests/test_sdm.cpp kTurningAgree), relative.
constexpr double kSdmAgree = 5e-3;
// The linear simulation's growth per period vs sdm's spectral radius
// (tests/test_time_domain.cpp kGrowthVsSdm): relative.
constexpr double kGrowthVsSdm = 5e-3;

// Case A (docs/physics.md §7): k = 45e6 N/m, ζ = 0.033, f = 94.22 Hz, K_f = 2.4e9.
constexpr double kK = 45e6, kZeta = 0.033, kF = 94.22, kKf = 2.4e9;

StructuralModel one_mode(Eigen::Vector2d direction) {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(kF, kZeta, kK, direction));
  return m;
}

// Tool along x at 100.66 Hz, workpiece along y at 150 Hz (two directions,
// so the chip direction n and the force direction d both matter).
StructuralModel two_modes() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1.0, 0.0}));
  m.workpiece.modes.push_back(Mode::from_stiffness(150.0, 0.025, 30e6, {0.0, 1.0}));
  return m;
}

Process insert(double lead_deg, double nose_mm, double kr = 0.0, double kf = kKf) {
  TurningParameters p;
  p.feed_force_coefficient_n_per_m2 = kf;
  p.radial_force_coefficient_n_per_m2 = kr;
  p.lead_angle_rad = lead_deg / 180.0 * kPi;
  p.nose_radius_m = nose_mm * 1e-3;
  return Process::turning(p);
}

TransferFunctionOptions depth_max(double d) {
  TransferFunctionOptions o;
  o.depth_max_m = d;
  return o;
}

// ------------------------------------------------------ the independent chord

// The insert as a sharp wedge rounded by a circle: corner at the origin,
// minor edge along −X (on the finished surface z = 0), major edge along
// (cos κ_r, sin κ_r). The nose circle of radius r touches both edges, so
// its centre lies on the bisector of the wedge's angle π − κ_r at distance
// r / sin((π − κ_r)/2) from the corner. The tip is the circle's lowest point;
// at height z the edge is on the circle up to the foot of the perpendicular
// from the centre on the major edge, on the major edge above it. The chord
// joins the tip to the edge point at height a.
struct Chord {
  double width, lead;
};
Chord wedge_chord(double kappa, double r, double a) {
  const Eigen::Vector2d minor(-1.0, 0.0), major(std::cos(kappa), std::sin(kappa));
  const Eigen::Vector2d tip_x_edge_point = [&] {
    if (r == 0.0) return Eigen::Vector2d(a * std::cos(kappa) / std::sin(kappa), a);
    const Eigen::Vector2d bisector = (minor + major).normalized();
    const Eigen::Vector2d c = r / std::sin(0.5 * (kPi - kappa)) * bisector;
    const Eigen::Vector2d foot = c.dot(major) * major;
    if (a <= foot.y()) return Eigen::Vector2d(c.x() + std::sqrt(r * r - (r - a) * (r - a)), a);
    return Eigen::Vector2d(a * std::cos(kappa) / std::sin(kappa), a);
  }();
  // The tip: (c.x, 0) with a nose, the corner without one.
  const double tip_x = r == 0.0 ? 0.0 : (r / std::sin(0.5 * (kPi - kappa)) * (minor + major).normalized()).x();
  const Eigen::Vector2d v(tip_x_edge_point.x() - tip_x, tip_x_edge_point.y());
  return {v.norm(), std::atan2(v.y(), v.x())};
}

TEST(InsertChord, MatchesTheRoundedWedgeOnTheArcAndOnTheStraightEdge) {
  for (const double kappa_deg : {15.0, 45.0, 60.0, 75.0, 90.0})
    for (const double r_mm : {0.0, 0.4, 0.8, 2.4})
      for (const double a_mm : {0.01, 0.1, 0.3, 1.0, 2.5, 6.0}) {
        const double kappa = kappa_deg * kDeg, r = r_mm * 1e-3, a = a_mm * 1e-3;
        const InsertChord got = insert_chord(kappa, r, a);
        const Chord want = wedge_chord(kappa, r, a);
        SCOPED_TRACE("kappa " + std::to_string(kappa_deg) + " deg, r " + std::to_string(r_mm) + " mm, a " +
                     std::to_string(a_mm) + " mm");
        EXPECT_NEAR(got.width_m / want.width, 1.0, kGeometry) << got.width_m << " vs " << want.width;
        EXPECT_NEAR(got.lead_angle_rad, want.lead, kGeometry) << got.lead_angle_rad << " vs " << want.lead;
        // The chord spans the depth: b sin κ_eq = a (so b h = a f).
        EXPECT_NEAR(got.width_m * std::sin(got.lead_angle_rad) / a, 1.0, kGeometry);
        EXPECT_EQ(got.nose_only, r > 0.0 && a <= r * (1.0 - std::cos(kappa)));
      }
}

TEST(InsertChord, SmallDepthIsPurelyOnTheArc) {
  // a below the nose height r(1 − cos κ_r): only the arc cuts; its chord is
  // sqrt(2 r a) long at κ_eq = asin(sqrt(a / 2r)), whatever κ_r, and turns
  // towards the feed direction as a → 0.
  const double r = 0.8e-3;
  for (const double kappa_deg : {45.0, 75.0, 90.0}) {
    const double kappa = kappa_deg * kDeg, height = r * (1.0 - std::cos(kappa));
    for (const double frac : {1e-6, 0.01, 0.5, 1.0}) {
      const double a = frac * height;
      const InsertChord c = insert_chord(kappa, r, a);
      EXPECT_TRUE(c.nose_only) << kappa_deg << " " << frac;
      EXPECT_NEAR(c.width_m / std::sqrt(2.0 * r * a), 1.0, kGeometry);
      EXPECT_NEAR(std::sin(c.lead_angle_rad) / std::sqrt(a / (2.0 * r)), 1.0, kGeometry);
    }
    EXPECT_FALSE(insert_chord(kappa, r, 1.001 * height).nose_only);
    EXPECT_LT(insert_chord(kappa, r, 1e-9).lead_angle_rad, 0.01);
  }
  // κ_eq grows with the depth towards κ_r (the straight edge dominates).
  double last = 0.0;
  for (double a = 1e-6; a < 0.05; a *= 1.5) {
    const double k = insert_chord(60 * kDeg, r, a).lead_angle_rad;
    EXPECT_GT(k, last) << a;
    EXPECT_LT(k, 60 * kDeg) << a;
    last = k;
  }
  EXPECT_NEAR(last, 60 * kDeg, 0.02);
}

// ------------------------------------------------ the seed case is unchanged

TEST(InsertDefaults, NinetyDegreesAndNoNoseAreTheOrthogonalCutBitForBit) {
  const Process plain = Process::turning({kKf});
  const Process explicit_insert = insert(90.0, 0.0);
  EXPECT_TRUE(plain.orthogonal_turning());
  EXPECT_TRUE(explicit_insert.orthogonal_turning());
  Eigen::Matrix2d seed = Eigen::Matrix2d::Zero();
  seed(0, 0) = kKf;
  for (const Process* p : {&plain, &explicit_insert}) {
    EXPECT_EQ(p->turning_matrix(0.002), seed);
    EXPECT_EQ(p->average_directional_matrix(), seed);
    EXPECT_EQ(p->chip_direction(0.002), Eigen::Vector2d(1.0, 0.0));
    EXPECT_EQ(p->chord(0.002).width_m, 0.002);
  }
  // Every method: the same limit, bit for bit, as the process without the keys.
  const StructuralModel m = one_mode({1.0, 0.0});
  AnalyticSolver a1(m, plain, depth_max(0.02)), a2(m, explicit_insert, depth_max(0.02));
  CoupledSolver c1(m, plain, depth_max(0.02)), c2(m, explicit_insert, depth_max(0.02));
  SemiDiscretizationOptions so;
  so.depth_max_m = 0.02;
  SemiDiscretizationSolver s1(m, plain, so), s2(m, explicit_insert, so);
  for (const double rpm : {300.0, 1000.0, 1700.0}) {
    EXPECT_EQ(a1.limit_at(SpindleSpeed(rpm)).depth_limit_m, a2.limit_at(SpindleSpeed(rpm)).depth_limit_m) << rpm;
    EXPECT_EQ(c1.limit_at(SpindleSpeed(rpm)).depth_limit_m, c2.limit_at(SpindleSpeed(rpm)).depth_limit_m) << rpm;
    EXPECT_EQ(s1.limit_at(SpindleSpeed(rpm)).depth_limit_m, s2.limit_at(SpindleSpeed(rpm)).depth_limit_m) << rpm;
  }
  TimeDomainSimulator t1(m, plain), t2(m, explicit_insert);
  SimulationSettings st;
  st.spindle_rpm = 1000;
  st.depth_m = 1.5e-3;
  st.periods = 30;
  st.record_series = false;
  EXPECT_EQ(t1.simulate(st).growth_per_period, t2.simulate(st).growth_per_period);
}

// ------------------------------------- the lead angle on 1-DOF: closed form

// With H = (1/sin κ) d nᵀ and one mode along u, H G = (1/sin κ) g d (nᵀu) uᵀ
// has the single eigenvalue g (u·n)(u·d)/sin κ: Tlusty's 1-DOF lobe with K_f
// replaced by K_oriented = (u·n)(u·d)/sin κ, so its minimum is
// 2kζ(1+ζ)/K_oriented. n = (sin κ, cos κ), d = K_f n + K_r (−cos κ, sin κ).
double oriented(double kappa, double kf, double kr, Eigen::Vector2d u) {
  const Eigen::Vector2d n(std::sin(kappa), std::cos(kappa)), e(-std::cos(kappa), std::sin(kappa));
  const Eigen::Vector2d d = kf * n + kr * e;
  return u.dot(n) * u.dot(d) / std::sin(kappa);
}

TEST(InsertLeadAngle, OneDofLimitIsTheClosedFormWithTheOrientedCoefficient) {
  struct Case {
    double lead_deg, kr;
    Eigen::Vector2d u;
  };
  const std::vector<Case> cases = {
      {90.0, 0.0, {1.0, 0.0}},           // the seed: 2kζ(1+ζ)/K_f = 1.2783 mm
      {60.0, 0.0, {1.0, 0.0}},           // X mode: K_f sin κ
      {45.0, 0.0, {1.0, 0.0}},
      {45.0, 0.0, {0.0, 1.0}},           // Y (radial) mode: K_f cos²κ / sin κ
      {75.0, 0.5 * kKf, {0.0, 1.0}},     // with K_r: cos κ (K_f cos κ + K_r sin κ) / sin κ
      {60.0, 0.3 * kKf, {1.0, 0.0}},     // K_f sin κ − K_r cos κ
  };
  for (const Case& c : cases) {
    const double k_or = oriented(c.lead_deg * kDeg, kKf, c.kr, c.u);
    ASSERT_GT(k_or, 0.0);
    const double closed = 2.0 * kK * kZeta * (1.0 + kZeta) / k_or;
    AnalyticSolver s(one_mode(c.u), insert(c.lead_deg, 0.0, c.kr), depth_max(0.5));
    const AbsoluteLimit a = s.absolute_limit();
    EXPECT_NEAR(a.depth_m / closed, 1.0, kClosedForm)
        << c.lead_deg << " deg, K_r " << c.kr << ": " << a.depth_m << " vs closed form " << closed;
    if (c.lead_deg == 90.0 && c.kr == 0.0) {
      EXPECT_NEAR(closed * 1e3, 1.2783, 1e-4);
    }
  }
  // The X mode: the limit scales with 1/sin κ, the width factor 1/sin κ
  // times the direction factor sin² κ.
  AnalyticSolver s90(one_mode({1, 0}), insert(90, 0), depth_max(0.5)), s45(one_mode({1, 0}), insert(45, 0), depth_max(0.5));
  EXPECT_NEAR(s45.absolute_limit().depth_m / s90.absolute_limit().depth_m, 1.0 / std::sin(45 * kDeg), kClosedForm);
}

// ------------------------------------------------------ the methods agree

TEST(InsertMethods, LeadAngleAnalyticCoupledAndSdmAgreeOnTwoModes) {
  const StructuralModel m = two_modes();
  const Process p = insert(60.0, 0.0, 0.3 * 684e6, 684e6);
  AnalyticSolver an(m, p, depth_max(0.02));
  CoupledSolver co(m, p, depth_max(0.02));
  SemiDiscretizationOptions so;
  so.depth_max_m = 0.02;
  SemiDiscretizationSolver sd(m, p, so);
  int bounded = 0;
  for (const double rpm : {1500.0, 2500.0, 3400.0, 4700.0, 6000.0, 8000.0}) {
    const StabilityLimit la = an.limit_at(SpindleSpeed(rpm)), lc = co.limit_at(SpindleSpeed(rpm)), ls = sd.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(la.bounded()) << rpm;
    ++bounded;
    EXPECT_NEAR(lc.depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree) << rpm;
    EXPECT_NEAR(lc.chatter_frequency_hz / la.chatter_frequency_hz, 1.0, kMethodsAgree) << rpm;
    EXPECT_NEAR(ls.depth_limit_m / la.depth_limit_m, 1.0, kSdmAgree)
        << rpm << " rev/min: sdm " << ls.depth_limit_m << " analytic " << la.depth_limit_m;
  }
  EXPECT_EQ(bounded, 6);
  // The insert matters: the orthogonal cut gives another limit.
  AnalyticSolver orth(m, insert(90.0, 0.0, 0.0, 684e6), depth_max(0.02));
  EXPECT_GT(std::abs(orth.limit_at(SpindleSpeed(2500)).depth_limit_m / an.limit_at(SpindleSpeed(2500)).depth_limit_m - 1.0), 0.05);
}

TEST(InsertMethods, NoseRadiusAnalyticCoupledAndSdmAgreeAtTheirOwnChord) {
  // κ_r = 75°, K_r = 0.4 K_f. The shipped example (0.8 mm nose, K_f = 684
  // N/mm²): limits of 3 to 20 mm, where the chord is mostly the straight
  // edge (κ_eq 65 to 73°). A 2.4 mm nose with K_f = 2.4e3 N/mm²: limits of
  // 0.1 to 2.5 mm, across the nose height r(1 − cos κ_r) = 1.78 mm, most of
  // them on the arc alone (κ_eq 8 to 40°).
  struct Case {
    double nose_mm, kf;
    std::vector<double> speeds;
    int on_arc;  // how many of the limits lie on the arc alone
  };
  const std::vector<Case> cases = {{0.8, 684e6, {1500.0, 2500.0, 3400.0, 4700.0, 6000.0}, 0},
                                   {2.4, 2.4e9, {1000.0, 2000.0, 3000.0, 4000.0, 7000.0}, 4}};
  const StructuralModel m = two_modes();
  for (const Case& c : cases) {
    const Process p = insert(75.0, c.nose_mm, 0.4 * c.kf, c.kf);
    AnalyticSolver an(m, p, depth_max(0.02));
    CoupledSolver co(m, p, depth_max(0.02));
    SemiDiscretizationOptions so;
    so.depth_max_m = 0.02;
    SemiDiscretizationSolver sd(m, p, so);
    EXPECT_FALSE(an.known_absolute_limit().has_value());
    EXPECT_TRUE(an.lobe_curves(SpindleSpeed(1000), SpindleSpeed(8000)).empty());
    int on_arc = 0;
    for (const double rpm : c.speeds) {
      SCOPED_TRACE(std::to_string(c.nose_mm) + " mm nose at " + std::to_string(rpm) + " rev/min");
      const StabilityLimit la = an.limit_at(SpindleSpeed(rpm)), lc = co.limit_at(SpindleSpeed(rpm)), ls = sd.limit_at(SpindleSpeed(rpm));
      ASSERT_TRUE(la.bounded());
      if (p.chord(la.depth_limit_m).nose_only) ++on_arc;
      EXPECT_NEAR(lc.depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree);
      EXPECT_NEAR(ls.depth_limit_m / la.depth_limit_m, 1.0, kSdmAgree)
          << "sdm " << ls.depth_limit_m << " analytic " << la.depth_limit_m;
      // Self-consistent: the sharp insert frozen at the chord of the limit
      // depth has its limit at that same depth.
      AnalyticSolver frozen(m, p.with_chord_at(la.depth_limit_m), depth_max(0.02));
      EXPECT_NEAR(frozen.limit_at(SpindleSpeed(rpm)).depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree);
    }
    EXPECT_EQ(on_arc, c.on_arc) << c.nose_mm << " mm";
  }
}

TEST(InsertMethods, LinearSimulationGrowthMatchesSdmWithLeadAngleAndNose) {
  const StructuralModel m = two_modes();
  const Process p = insert(75.0, 0.8, 0.4 * 684e6, 684e6);
  SemiDiscretizationSolver sd(m, p);
  TimeDomainSimulator sim(m, p);
  for (const double depth_mm : {0.4, 2.0}) {  // on the nose alone, and across it
    const double rpm = 2500.0;
    const FloquetResult f = sd.analyse(rpm, depth_mm * 1e-3);
    SimulationSettings s;
    s.spindle_rpm = rpm;
    s.depth_m = depth_mm * 1e-3;
    s.periods = 120;
    s.linear = true;
    s.record_series = false;
    const SimulationResult r = sim.simulate(s);
    EXPECT_NEAR(r.growth_per_period / f.spectral_radius, 1.0, kGrowthVsSdm)
        << depth_mm << " mm: td " << r.growth_per_period << " sdm " << f.spectral_radius;
  }
}

TEST(InsertMethods, ProcessDampingActsAlongTheChipDirectionInEveryMethod) {
  // C_pd (b/V) (n·ṙ) n: analytic (its per-speed search, with the frozen chord
  // for the nose) and sdm agree within sdm's discretisation error, and the
  // linear simulation's growth equals sdm's spectral radius, at low speed
  // where the damping raises the limit.
  const StructuralModel m = two_modes();
  for (const double nose_mm : {0.0, 0.8}) {
    TurningParameters tp;
    tp.feed_force_coefficient_n_per_m2 = 684e6;
    tp.radial_force_coefficient_n_per_m2 = 0.4 * 684e6;
    tp.lead_angle_rad = 75 * kDeg;
    tp.nose_radius_m = nose_mm * 1e-3;
    tp.process_damping_coefficient_n_per_m = 2e5;
    tp.workpiece_diameter_m = 0.06;
    const Process p = Process::turning(tp);
    AnalyticSolver an(m, p, depth_max(0.02));
    SemiDiscretizationOptions so;
    so.depth_max_m = 0.02;
    SemiDiscretizationSolver sd(m, p, so);
    tp.process_damping_coefficient_n_per_m = 0.0;
    AnalyticSolver without(m, Process::turning(tp), depth_max(0.02));
    for (const double rpm : {200.0, 700.0}) {
      SCOPED_TRACE(std::to_string(nose_mm) + " mm nose at " + std::to_string(rpm) + " rev/min");
      const StabilityLimit la = an.limit_at(SpindleSpeed(rpm)), ls = sd.limit_at(SpindleSpeed(rpm));
      ASSERT_TRUE(la.bounded());
      EXPECT_NEAR(ls.depth_limit_m / la.depth_limit_m, 1.0, kSdmAgree);
      EXPECT_GT(la.depth_limit_m, 1.05 * without.limit_at(SpindleSpeed(rpm)).depth_limit_m);  // the damping helps
    }
    TimeDomainSimulator sim(m, p);
    SimulationSettings s;
    s.spindle_rpm = 700.0;
    s.depth_m = 3e-3;
    s.periods = 60;
    s.linear = true;
    s.record_series = false;
    const double rho = sd.analyse(s.spindle_rpm, s.depth_m).spectral_radius;
    EXPECT_NEAR(sim.simulate(s).growth_per_period / rho, 1.0, kGrowthVsSdm) << nose_mm;
  }
}

TEST(InsertMethods, NonlinearSimulationVerdictChangesAcrossTheLimit) {
  // The static chip f sin κ_eq along n (nonlinear: the tool may leave the cut).
  const StructuralModel m = one_mode({1.0, 0.0});
  const Process p = insert(60.0, 0.8);
  AnalyticSolver an(m, p, depth_max(0.05));
  const double rpm = 1000.0, limit = an.limit_at(SpindleSpeed(rpm)).depth_limit_m;
  TimeDomainSimulator sim(m, p);
  for (const double factor : {0.8, 1.3}) {
    SimulationSettings s;
    s.spindle_rpm = rpm;
    s.depth_m = factor * limit;
    s.feed_m = 0.1e-3;
    s.periods = 150;
    s.record_series = false;
    const SimulationResult r = sim.simulate(s);
    EXPECT_EQ(r.verdict == SimulationVerdict::kStable, factor < 1.0) << factor << " x " << limit << " m";
  }
}

// ------------------------------------------------------------------ input

::testing::AssertionResult refused(const std::string& process_keys, std::initializer_list<std::string> parts) {
  const std::string text = "[process]\n" + process_keys +
                           "\n[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n";
  try {
    (void)parse_config(text, "mem/insert.toml");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts)
      if (msg.find(p) == std::string::npos) return ::testing::AssertionFailure() << "\"" << msg << "\" lacks " << p;
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "accepted";
}

const std::string kTurning = "operation = \"turning\"\nfeed_force_coefficient_n_per_m2 = 2.4e9\n";
const std::string kMilling =
    "operation = \"milling\"\nteeth = 2\ntangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_n_per_m2 = "
    "2e8\nradial_immersion = 0.5\n";

TEST(InsertConfig, KeysAreReadInDegreesAndMillimetres) {
  const Config c = parse_config("[process]\n" + kTurning +
                                    "lead_angle_deg = 60\nnose_radius_mm = 0.8\nradial_force_coefficient_n_per_mm2 = "
                                    "700\n[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n",
                                "mem/insert.toml");
  const TurningParameters& t = c.process.turning_parameters();
  EXPECT_DOUBLE_EQ(t.lead_angle_rad, 60 * kDeg);
  EXPECT_DOUBLE_EQ(t.nose_radius_m, 0.8e-3);
  EXPECT_DOUBLE_EQ(t.radial_force_coefficient_n_per_m2, 700e6);
  const Config d = parse_config("[process]\n" + kTurning +
                                    "lead_angle_deg = 90\nnose_radius_mm = 0\n[[tool.modes]]\nfrequency_hz = 100\n"
                                    "damping_ratio = 0.03\nstiffness_n_per_m = 1e7\n",
                                "mem/insert.toml");
  EXPECT_TRUE(d.process.orthogonal_turning());  // 90 deg is π/2 exactly
}

TEST(InsertConfig, BadValuesAndMillingAreRefusedNamingFileKeyAndRule) {
  for (const char* bad : {"0", "-10", "95", "180"})
    EXPECT_TRUE(refused(kTurning + "lead_angle_deg = " + bad + "\n",
                        {"mem/insert.toml", "process.lead_angle_deg", "in (0, 90] (deg)"}))
        << bad;
  for (const char* bad : {"-0.4", "30", "1e9"})
    EXPECT_TRUE(refused(kTurning + "nose_radius_mm = " + bad + "\n",
                        {"mem/insert.toml", "process.nose_radius_mm", "in [0, 25] (mm)"}))
        << bad;
  EXPECT_TRUE(refused(kTurning + "radial_force_coefficient_n_per_m2 = -1e8\n",
                      {"process.radial_force_coefficient_n_per_m2", ">= 0"}));
  EXPECT_TRUE(refused(kTurning + "lead_angle_deg = \"steep\"\n", {"process.lead_angle_deg", "must be a number"}));
  for (const char* key : {"lead_angle_deg = 60", "nose_radius_mm = 0.8", "radial_force_coefficient_n_per_m2 = 1e8"})
    EXPECT_TRUE(refused(kMilling + key + "\n", {"mem/insert.toml", "only for operation = \"turning\""})) << key;
  // The library refuses what the config would: lead angle, nose radius, K_r.
  EXPECT_THROW(insert(0.0, 0.0), InputError);
  EXPECT_THROW(insert(91.0, 0.0), InputError);
  EXPECT_THROW(insert(60.0, -0.1), InputError);
  EXPECT_THROW(insert(60.0, 26.0), InputError);
  EXPECT_THROW(insert(60.0, 0.8, -1.0), InputError);
}

// The shipped example: every bounded row of its analytic table solves the
// characteristic equation at the chord of its own depth, with H built here
// from the rounded-wedge chord (docs/physics.md §4: 1 + a(1 − e^{−jωτ}) λ = 0,
// λ the eigenvalue of H(a) G(jω), rank one).
TEST(InsertExample, ShippedConfigRowsSolveTheEquationAtTheirOwnChord) {
  const Config cfg = load_config(std::string(CHATTER_SOURCE_DIR) + "/configs/turning_insert_lead_angle.toml");
  const TurningParameters& t = cfg.process.turning_parameters();
  ASSERT_GT(t.nose_radius_m, 0.0);
  ASSERT_LT(t.lead_angle_rad, 0.5 * kPi);
  AnalyticSolver s(cfg.model, cfg.process, depth_max(cfg.sweep.depth_max_mm.value_or(20.0) * 1e-3));
  int bounded = 0;
  for (const double rpm : evenly_spaced_speeds(*cfg.sweep.rpm_min, *cfg.sweep.rpm_max, 25)) {
    const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
    if (!l.bounded()) continue;
    ++bounded;
    const double a = l.depth_limit_m, w = 2 * kPi * l.chatter_frequency_hz, tau = 60.0 / rpm;
    const Chord c = wedge_chord(t.lead_angle_rad, t.nose_radius_m, a);
    const Eigen::Vector2d n(std::sin(c.lead), std::cos(c.lead)), e(-std::cos(c.lead), std::sin(c.lead));
    const Eigen::Vector2d d = t.feed_force_coefficient_n_per_m2 * n + t.radial_force_coefficient_n_per_m2 * e;
    std::complex<double> lambda = 0.0;  // nᵀ G d / sin κ_eq with G from the modes
    for (const auto* body : {&cfg.model.tool, &cfg.model.workpiece})
      for (const Mode& md : body->modes) {
        const double r = w / (2 * kPi * md.natural_frequency_hz);
        const std::complex<double> g = 1.0 / (md.stiffness_n_per_m * std::complex<double>(1 - r * r, 2 * md.damping_ratio * r));
        lambda += g * n.dot(md.direction) * md.direction.dot(d) / std::sin(c.lead);
      }
    const std::complex<double> residual = 1.0 + a * (1.0 - std::exp(std::complex<double>(0.0, -w * tau))) * lambda;
    EXPECT_LT(std::abs(residual), 1e-6) << rpm << " rev/min, " << a * 1e3 << " mm, " << l.chatter_frequency_hz << " Hz";
  }
  EXPECT_GT(bounded, 20);
}

}  // namespace
}  // namespace chatter
