// Kienzle's size effect in turning (chatter/kienzle.hpp, docs/cutting_law.md):
// the law against its closed form and a finite difference, seed 003's table 14
// reproduced, the regenerative coefficient (the tangent) read by every linear
// method and linearised by the nonlinear simulation, the static side (the
// secant) in the forced deflection and the optimisation, and the config's
// rules.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <string>

#include <Eigen/Dense>

#include "chatter/cutting_force.hpp"
#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/io/config.hpp"
#include "chatter/kienzle.hpp"
#include "chatter/operations.hpp"
#include "chatter/optimization.hpp"
#include "chatter/shop.hpp"
#include "chatter/solvers.hpp"
#include "chatter/time_domain.hpp"

namespace chatter {
namespace {

Config seed003(const std::string& which) {
  return load_config(std::string(CHATTER_SOURCE_DIR) + "/configs/turning_seed003_" + which + ".toml");
}

// The law through seed 003's two tests of table 14 (1.5 mm deep, 90° lead):
// 736 N / 501 N at 0.35 mm/rev, 342 N / 175 N at 0.089 mm/rev, solved here
// from the four forces (independent of the config's rounded constants).
struct TwoPointLaw {
  double k11_n_per_mm2, m;
};
TwoPointLaw through(double f1_n, double f2_n) {
  const double b = 1.5, h1 = 0.35, h2 = 0.089;
  const double one_minus_m = std::log(f1_n / f2_n) / std::log(h1 / h2);
  return {f1_n / (b * std::pow(h1, one_minus_m)), 1.0 - one_minus_m};
}

TEST(Kienzle, SecantTangentAndForceAgainstClosedFormAndFiniteDifference) {
  const KienzleTerm t{1700e6, 0.25};
  for (const double h : {0.02e-3, 0.1e-3, 0.35e-3, 1e-3, 2e-3}) {
    const double h_mm = h * 1e3;
    EXPECT_NEAR(t.secant_n_per_m2(h), 1700e6 * std::pow(h_mm, -0.25), 1e-6 * t.secant_n_per_m2(h));
    // F per width in N/m: k_1.1 (N/mm²) · h^(1−m) (mm) per mm of width = ×1e3 N/m.
    EXPECT_NEAR(t.force_per_width_n_per_m(h), 1700.0 * std::pow(h_mm, 0.75) * 1e3, 1e-9 * t.force_per_width_n_per_m(h));
    const double dh = 1e-4 * h;
    const double fd = (t.force_per_width_n_per_m(h + dh) - t.force_per_width_n_per_m(h - dh)) / (2.0 * dh);
    EXPECT_NEAR(t.tangent_n_per_m2(h), fd, 1e-7 * fd);
    EXPECT_NEAR(t.tangent_n_per_m2(h), 0.75 * t.secant_n_per_m2(h), 1e-9 * t.secant_n_per_m2(h));
  }
  EXPECT_EQ(t.force_per_width_n_per_m(0.0), 0.0);
  EXPECT_EQ(t.force_per_width_n_per_m(-1e-5), 0.0);
  // m = 0 is the linear law: secant = tangent = k_1.1.
  const KienzleTerm linear{2e9, 0.0};
  EXPECT_DOUBLE_EQ(linear.tangent_n_per_m2(0.07e-3), 2e9);
}

TEST(Kienzle, SeedTable14ForcesFromTheShippedConfig) {
  const Config c = seed003("kienzle");
  ASSERT_TRUE(c.process.has_size_effect());
  std::vector<std::string> warnings;
  const auto law = CuttingLaw::of(c.process, cutting_law_options(c.process, std::nullopt, warnings));
  EXPECT_TRUE(warnings.empty());  // no "K_f as cutting pressure": the law has its tangential term
  // Seed 003 table 14: (feed mm/rev, Fx tangential N, Fz feed N). The config
  // rounds k_1.1 and m to three digits: 0.3 % on the forces.
  const double rows[][3] = {{0.35, 736.0, 501.0}, {0.089, 342.0, 175.0}};
  for (const auto& r : rows) {
    const MeanCut m = law->mean(CutPoint{3654.0, 1.5e-3, r[0] * 1e-3, 0.025});
    EXPECT_NEAR(m.tangential_force_n, r[1], 3e-3 * r[1]) << "feed " << r[0];
    EXPECT_NEAR(-m.force_n.x(), r[2], 3e-3 * r[2]) << "feed " << r[0];
    EXPECT_NEAR(m.force_n.y(), 0.0, 1e-9);
    // The specific cutting force the seed quotes: 1 402 and 2 562 N/mm².
    EXPECT_NEAR(m.tangential_force_n / (1.5 * r[0]), r[1] / (1.5 * r[0]), 5.0);
  }
  // The constants of the config against the two-point solution.
  const TwoPointLaw tc = through(736.0, 342.0), ff = through(501.0, 175.0);
  const KienzleLaw& k = *c.process.turning_parameters().kienzle;
  EXPECT_NEAR(k.tangential.specific_force_n_per_m2 * 1e-6, tc.k11_n_per_mm2, 1.0);
  EXPECT_NEAR(k.tangential.exponent, tc.m, 1e-3);
  EXPECT_NEAR(k.feed.specific_force_n_per_m2 * 1e-6, ff.k11_n_per_mm2, 1.0);
  EXPECT_NEAR(k.feed.exponent, ff.m, 1e-3);
}

TEST(Kienzle, RegenerativeCoefficientIsTheTangentAtTheProcessFeed) {
  const Config c = seed003("kienzle");
  const KienzleLaw& k = *c.process.turning_parameters().kienzle;
  EXPECT_NEAR(c.process.turning_parameters().feed_force_coefficient_n_per_m2, k.feed.tangent_n_per_m2(0.35e-3), 1.0);
  const Process thin = c.process.at_feed(0.089e-3);
  EXPECT_NEAR(thin.turning_parameters().feed_force_coefficient_n_per_m2, k.feed.tangent_n_per_m2(0.089e-3), 1.0);
  EXPECT_THROW((void)c.process.at_feed(0.0), InputError);
  // The orthogonal cut's limit is 1/(2 K_f |min Re G|): the limits at two
  // feeds are in the inverse ratio of the tangents, for every method that
  // reads the process (analytic closed form, sdm's Floquet map).
  const double ratio = k.feed.tangent_n_per_m2(0.35e-3) / k.feed.tangent_n_per_m2(0.089e-3);
  for (const char* method : {"analytic", "sdm"}) {
    const auto thick = make_lobe_solver(method, c.model, c.process, 0.01);
    const auto thin_solver = make_lobe_solver(method, c.model, thin, 0.01);
    const double a1 = thick->limit_at(SpindleSpeed(3654.0)).depth_limit_m, a2 = thin_solver->limit_at(SpindleSpeed(3654.0)).depth_limit_m;
    EXPECT_NEAR(a2 / a1, ratio, 2e-3 * ratio) << method;
  }
  // And a linear config with K_f = the tangent gives the same limit bitwise.
  TurningParameters p = c.process.turning_parameters();
  p.kienzle.reset();
  const auto linear = make_lobe_solver("analytic", c.model, Process::turning(p), 0.01);
  EXPECT_EQ(linear->limit_at(SpindleSpeed(3654.0)).depth_limit_m,
            make_lobe_solver("analytic", c.model, c.process, 0.01)->limit_at(SpindleSpeed(3654.0)).depth_limit_m);
}

TEST(Kienzle, InsertWithNoseRadiusTakesTheTangentAtTheChordsChip) {
  // A 75° insert with a 0.8 mm nose: at depth a the chip is f sin κ_eq(a),
  // and the regenerative d is the law's tangents there; at a = 0 nothing cuts.
  TurningParameters p;
  p.lead_angle_rad = 75.0 * std::numbers::pi / 180.0;
  p.nose_radius_m = 0.8e-3;
  p.kienzle = KienzleLaw{{1700e6, 0.25}, {600e6, 0.3}, {400e6, 0.35}, 0.2e-3};
  const Process pr = Process::turning(p);
  for (const double a : {0.1e-3, 0.5e-3, 2e-3}) {
    const InsertChord c = pr.chord(a);
    const double h0 = 0.2e-3 * std::sin(c.lead_angle_rad), s = std::sin(c.lead_angle_rad), co = std::cos(c.lead_angle_rad);
    const double kf = 0.7 * 600e6 * std::pow(h0 * 1e3, -0.3), kr = 0.65 * 400e6 * std::pow(h0 * 1e3, -0.35);
    const Eigen::Vector2d d = pr.edge_force(a);
    EXPECT_NEAR(d.x(), kf * s - kr * co, 1e-9 * kf) << a;
    EXPECT_NEAR(d.y(), kf * co + kr * s, 1e-9 * kf) << a;
  }
  const Eigen::Matrix2d at_zero = pr.turning_force_matrix(0.0);
  EXPECT_TRUE(at_zero.allFinite());
  EXPECT_EQ(at_zero.norm(), 0.0);
}

TEST(Kienzle, NonlinearSimulationFeelsTheSecantStaticallyAndTheTangentDynamically) {
  const Config c = seed003("kienzle");
  const double rpm = 3654.0, feed = 0.2e-3;
  const Process p = c.process.at_feed(feed);
  const double limit = make_lobe_solver("analytic", c.model, p, 0.01)->limit_at(SpindleSpeed(rpm)).depth_limit_m;
  const TimeDomainSimulator sim(c.model, p);
  SimulationSettings s;
  s.spindle_rpm = rpm;
  s.feed_m = feed;
  s.periods = 240;
  // Below the limit: the run settles where the secant force puts it (the
  // static deflection of the cutting law, an independent path).
  s.depth_m = 0.8 * limit;
  const SimulationResult stable = sim.simulate(s);
  EXPECT_EQ(stable.verdict, SimulationVerdict::kStable);
  EXPECT_FALSE(stable.growth_per_period >= 1.0);  // NaN: the increments fell to the integration noise
  const TurningDeflection d = static_deflection_turning(c.model, p, s.depth_m, feed);
  EXPECT_NEAR(stable.forced_static_x_m, d.deflection_x_m, 2e-3 * std::abs(d.deflection_x_m));
  // The secant, not the tangent: the tangent's force is (1 − m) of it.
  EXPECT_GT(std::abs(d.deflection_x_m), 1.2 * (1.0 - 0.232) * std::abs(d.deflection_x_m));
  // Just above the limit the increments grow: the linearisation of the
  // nonlinear force about the mean chip is the tangent the limit used.
  s.depth_m = 1.1 * limit;
  s.periods = 120;
  const SimulationResult above = sim.simulate(s);
  EXPECT_GT(above.growth_per_period, 1.0);
  s.depth_m = 0.95 * limit;
  const SimulationResult below = sim.simulate(s);
  EXPECT_LT(below.growth_per_period, 1.0);
  EXPECT_GT(below.growth_per_period, 0.9);  // near the limit: barely damped
}

TEST(Kienzle, OptimisationReadsTheSecantForceAndTheTangentLimitAtEachFeed) {
  const Config k = seed003("kienzle"), lin = seed003("shaft");
  const OptimizationModel mk(k.model, k.position, k.process, *k.optimization);
  const OptimizationModel ml(lin.model, lin.position, lin.process, *lin.optimization);
  // Seed 003's optimum: 287 m/min, 0.089 mm/rev, 1.5 mm.
  const SetPoint sp{spindle_rpm_of(0.025, 287.0), 0.089e-3, 1.5e-3};
  const Performance pk = mk.evaluate(sp), pl = ml.evaluate(sp);
  // force_n: the peak resultant |(F_c, F_f)|; the seed measured 342 N and 175 N.
  EXPECT_NEAR(pk.model[static_cast<std::size_t>(PerformanceIndex::kForce)], std::hypot(342.0, 175.0), 2.0);
  // The linear law (K_c = 1 400, K_f = 954 N/mm², fitted at 0.35 mm/rev): 187 N and 127 N.
  EXPECT_NEAR(pl.model[static_cast<std::size_t>(PerformanceIndex::kForce)],
              std::hypot(1400.0 * 1.5 * 0.089, 954.0 * 1.5 * 0.089), 0.5);
  // The diametral error scales with the feed force: 175 / 127.4.
  const double ek = pk.model[static_cast<std::size_t>(PerformanceIndex::kDimensionalError)];
  const double el = pl.model[static_cast<std::size_t>(PerformanceIndex::kDimensionalError)];
  EXPECT_NEAR(ek / el, 175.0 / (954.0 * 1.5 * 0.089), 5e-3);
  // The limit at this feed: the linear limit × K_f / tangent(0.089 mm).
  const KienzleLaw& law = *k.process.turning_parameters().kienzle;
  EXPECT_NEAR(pk.depth_limit_m / pl.depth_limit_m, 954e6 / law.feed.tangent_n_per_m2(0.089e-3), 1e-3);
  // And at another feed another limit (the cache is per feed).
  const Performance pk2 = mk.evaluate(SetPoint{sp.spindle_rpm, 0.3e-3, 1.5e-3});
  EXPECT_NEAR(pk2.depth_limit_m / pl.depth_limit_m, 954e6 / law.feed.tangent_n_per_m2(0.3e-3), 1e-3);
  // The orthogonal cut's limits are scaled from one solve per speed: equal to
  // a solve of the process at that feed (at the free end, the weakest place).
  ModelOptions at_end;
  at_end.position_m = 0.08;
  const OptimizationModel me(k.model, k.position, k.process, *k.optimization, at_end);
  const auto solve = make_lobe_solver(me.method(), model_at_position(k, 0.08), k.process.at_feed(0.089e-3),
                                      me.depth_search_m());
  EXPECT_NEAR(me.evaluate(sp).depth_limit_m, solve->limit_at(SpindleSpeed(sp.spindle_rpm)).depth_limit_m,
              1e-6 * pk.depth_limit_m);
}

TEST(Kienzle, ForcedResponseAndRecommendJudgeStabilityAtTheirOwnFeed) {
  const Config c = seed003("kienzle");
  const double rpm = 3654.0;
  const double thin = make_lobe_solver("analytic", c.model, c.process.at_feed(0.089e-3), 0.01)->limit_at(SpindleSpeed(rpm)).depth_limit_m;
  const double thick = make_lobe_solver("analytic", c.model, c.process.at_feed(0.35e-3), 0.01)->limit_at(SpindleSpeed(rpm)).depth_limit_m;
  ASSERT_LT(thin, thick);  // the thin chip's tangent is the larger
  const ForcedResponseSolver forced(c.model, c.process);
  ForcedSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = 0.5 * (thin + thick);
  st.record_path = false;
  st.feed_m = 0.35e-3;
  EXPECT_TRUE(forced.response(st).stable);
  st.feed_m = 0.089e-3;
  EXPECT_FALSE(forced.response(st).stable);
  // recommend: the limit it reports at its speed is the one at its feed.
  RecommendOptions o;
  o.machine.rpm_min = 600;
  o.machine.rpm_max = 4500;
  o.feed_per_tooth_m = 0.089e-3;
  o.diameter_m = 0.025;
  o.depth_max_m = 0.01;
  const Recommendation r = recommend(c.model, c.process, o);
  const double at = make_lobe_solver("analytic", c.model, c.process.at_feed(0.089e-3), 0.05)->limit_at(SpindleSpeed(r.spindle_rpm)).depth_limit_m;
  ASSERT_TRUE(r.limit.bounded());
  EXPECT_NEAR(r.limit.depth_limit_m, at, 1e-6 * at);
}

TEST(Kienzle, ATangentialCoefficientBesideTheLawIsRefused) {
  const Config c = seed003("kienzle");
  std::vector<std::string> warnings;
  EXPECT_THROW((void)cutting_law_options(c.process, 1400e6, warnings), InputError);
  CuttingLawOptions o;
  o.turning_tangential_coefficient_n_per_m2 = 1400e6;
  EXPECT_THROW((void)CuttingLaw::of(c.process, o), InputError);
  EXPECT_THROW((void)cutting_load(c.process, 3000.0, 1e-3, 1e-4, 0.025, 1400e6), InputError);
  EXPECT_NO_THROW((void)cutting_load(c.process, 3000.0, 1e-3, 1e-4, 0.025, 0.0));
  EXPECT_TRUE(warnings.empty());
}

// The config's rules: each message names the key and the rule.
std::string refusal(const std::string& process_keys) {
  const std::string text = "[process]\noperation = \"turning\"\n" + process_keys +
                           "\n[[tool.modes]]\nfrequency_hz = 500\ndamping_ratio = 0.03\nstiffness_n_per_m = 2e7\n"
                           "direction = \"x\"\n";
  try {
    (void)parse_config(text, "k.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Kienzle, ConfigRulesNameTheKey) {
  const std::string law =
      "force_law = \"kienzle\"\nspecific_force_n_per_mm2 = { tangential = 1700, feed = 600 }\n"
      "exponent = { tangential = 0.25, feed = 0.3 }\n";
  EXPECT_EQ(refusal(law + "feed_per_rev_mm = 0.2"), "");
  EXPECT_NE(refusal(law).find("process.feed_per_rev_mm: missing: force_law = \"kienzle\" needs the feed"),
            std::string::npos);
  EXPECT_NE(refusal(law + "feed_per_rev_mm = 0.2\nfeed_force_coefficient_n_per_mm2 = 900")
                .find("process.feed_force_coefficient_n_per_mm2 = 900: not with force_law = \"kienzle\""),
            std::string::npos);
  EXPECT_NE(refusal("force_law = \"kienzel\"\nfeed_force_coefficient_n_per_m2 = 9e8").find("process.force_law"),
            std::string::npos);
  EXPECT_NE(refusal("feed_force_coefficient_n_per_m2 = 9e8\nexponent = { feed = 0.2 }")
                .find("process.exponent = { feed = 0.2 }: only with force_law = \"kienzle\""),
            std::string::npos);
  EXPECT_NE(refusal("force_law = \"kienzle\"\nspecific_force_n_per_mm2 = { tangential = 1700, feed = 600 }\n"
                    "exponent = { tangential = 1.2, feed = 0.3 }\nfeed_per_rev_mm = 0.2")
                .find("process.exponent.tangential = 1.2: must be in [0, 1)"),
            std::string::npos);
  EXPECT_NE(refusal("force_law = \"kienzle\"\nspecific_force_n_per_mm2 = { tangential = 1700, feed = 600, radial = 300 }\n"
                    "exponent = { tangential = 0.25, feed = 0.3 }\nfeed_per_rev_mm = 0.2")
                .find("process.exponent.radial: missing"),
            std::string::npos);
  // A k_1.1 in N/m² in the N/mm² key: loads, with the unit named.
  const Config c = parse_config("[process]\noperation = \"turning\"\nforce_law = \"kienzle\"\n"
                                "specific_force_n_per_mm2 = { tangential = 1.7e9, feed = 600 }\n"
                                "exponent = { tangential = 0.25, feed = 0.3 }\nfeed_per_rev_mm = 0.2\n"
                                "[[tool.modes]]\nfrequency_hz = 500\ndamping_ratio = 0.03\nstiffness_n_per_m = 2e7\n"
                                "direction = \"x\"\n",
                                "k.toml");
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("is it in N/m^2 (tangential = 1700)?"), std::string::npos) << c.warnings[0];
  // Milling has no Kienzle law here: the key belongs to turning.
  const std::string milling = "[process]\noperation = \"milling\"\nteeth = 2\ntangential_coefficient_n_per_m2 = 6e8\n"
                              "radial_coefficient_n_per_m2 = 2e8\nradial_immersion = 0.5\nforce_law = \"kienzle\"\n"
                              "[[tool.modes]]\nfrequency_hz = 500\ndamping_ratio = 0.03\nstiffness_n_per_m = 2e7\n"
                              "direction = \"x\"\n";
  try {
    (void)parse_config(milling, "m.toml");
    ADD_FAILURE() << "milling with force_law loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("process.force_law = \"kienzle\": only for operation = \"turning\""),
              std::string::npos)
        << e.what();
  }
}


// ------------------------------------------------------------ the fit

TEST(KienzleFit, SeedTwoTestsGiveTheLawExactlyWithoutErrors) {
  const std::vector<TurningForceTest> tests{{0.35e-3, 1.5e-3, 736.0, 501.0}, {0.089e-3, 1.5e-3, 342.0, 175.0}};
  const KienzleFit f = fit_kienzle(tests, std::numbers::pi / 2.0);
  const TwoPointLaw tc = through(736.0, 342.0), ff = through(501.0, 175.0);
  EXPECT_NEAR(f.tangential.term.specific_force_n_per_m2 * 1e-6, tc.k11_n_per_mm2, 1e-9 * tc.k11_n_per_mm2);
  EXPECT_NEAR(f.tangential.term.exponent, tc.m, 1e-12);
  EXPECT_NEAR(f.feed.term.specific_force_n_per_m2 * 1e-6, ff.k11_n_per_mm2, 1e-9 * ff.k11_n_per_mm2);
  EXPECT_NEAR(f.feed.term.exponent, ff.m, 1e-12);
  EXPECT_NEAR(tc.k11_n_per_mm2, 883.4, 0.5);  // the shipped config's 883
  EXPECT_NEAR(tc.m, 0.4403, 1e-4);
  EXPECT_EQ(f.degrees_of_freedom, 0);
  EXPECT_TRUE(std::isnan(f.tangential.m_standard_error));
  EXPECT_EQ(f.radial.term.specific_force_n_per_m2, 0.0);  // not measured
  ASSERT_EQ(f.warnings.size(), 1u);
  EXPECT_NE(f.warnings[0].find("two tests"), std::string::npos);
  for (const double r : f.tangential.residual_n) EXPECT_NEAR(r, 0.0, 1e-9);
}

TEST(KienzleFit, StandardErrorsAgainstTheMatrixLeastSquares) {
  // Six tests of a 75° insert from k = 1700 N/mm², m = 0.25 (tangential),
  // 600, 0.30 (feed), 400, 0.35 (radial), each force off by a known factor.
  const double lead = 75.0 * std::numbers::pi / 180.0, s = std::sin(lead);
  const double feeds[] = {0.08, 0.12, 0.18, 0.25, 0.32, 0.4}, depths[] = {1.0, 2.0, 1.5, 1.0, 2.5, 2.0};
  const double noise[] = {1.02, 0.985, 1.01, 0.99, 1.015, 0.98};
  auto law = [&](double k, double m, double f, double a) { return k * (a / s) * std::pow(f * s, 1.0 - m); };
  std::vector<TurningForceTest> tests;
  for (int i = 0; i < 6; ++i)
    tests.push_back({feeds[i] * 1e-3, depths[i] * 1e-3, law(1700, 0.25, feeds[i], depths[i]) * noise[i],
                     law(600, 0.30, feeds[i], depths[i]) / noise[i], law(400, 0.35, feeds[i], depths[i]) * noise[5 - i]});
  const KienzleFit f = fit_kienzle(tests, lead);
  EXPECT_EQ(f.degrees_of_freedom, 4);
  ASSERT_GT(f.radial.term.specific_force_n_per_m2, 0.0);
  // The reference: QR least squares on the design [1, ln h] and the
  // covariance s² (XᵀX)⁻¹ (a different path from the fit's closed-form sums).
  const std::pair<const KienzleDirectionFit*, double TurningForceTest::*> dirs[] = {
      {&f.tangential, &TurningForceTest::tangential_n}, {&f.feed, &TurningForceTest::feed_n},
      {&f.radial, &TurningForceTest::radial_n}};
  for (const auto& [d, force] : dirs) {
    Eigen::MatrixXd X(6, 2);
    Eigen::VectorXd y(6);
    for (int i = 0; i < 6; ++i) {
      X(i, 0) = 1.0;
      X(i, 1) = std::log(feeds[i] * s);
      y(i) = std::log(tests[static_cast<std::size_t>(i)].*force / (depths[i] / s));
    }
    const Eigen::Vector2d beta = X.colPivHouseholderQr().solve(y);
    const double s2 = (y - X * beta).squaredNorm() / 4.0;
    const Eigen::Matrix2d cov = s2 * (X.transpose() * X).inverse();
    EXPECT_NEAR(d->term.specific_force_n_per_m2 * 1e-6, std::exp(beta(0)), 1e-9 * std::exp(beta(0)));
    EXPECT_NEAR(d->term.exponent, 1.0 - beta(1), 1e-10);
    EXPECT_NEAR(d->m_standard_error, std::sqrt(cov(1, 1)), 1e-9 * std::sqrt(cov(1, 1)));
    EXPECT_NEAR(d->k_standard_error_n_per_m2 * 1e-6, std::exp(beta(0)) * std::sqrt(cov(0, 0)),
                1e-8 * std::exp(beta(0)) * std::sqrt(cov(0, 0)));
    EXPECT_NEAR(d->m_confidence_95, 2.776445 * d->m_standard_error, 1e-5 * d->m_standard_error);  // t(0.975, 4)
    EXPECT_GT(d->r_squared, 0.9);
  }
  // Close to the law the tests came from (2 % noise).
  EXPECT_NEAR(f.tangential.term.exponent, 0.25, 0.05);
  EXPECT_NEAR(f.feed.term.specific_force_n_per_m2 * 1e-6, 600.0, 60.0);
  EXPECT_TRUE(f.warnings.empty());
  // Refusals: one feed only, one test, a zero force.
  std::vector<TurningForceTest> one_feed{tests[0], tests[0]};
  EXPECT_THROW((void)fit_kienzle(one_feed, lead), InputError);
  EXPECT_THROW((void)fit_kienzle({tests[0]}, lead), InputError);
  std::vector<TurningForceTest> zero{tests[0], tests[1]};
  zero[1].feed_n = 0.0;
  EXPECT_THROW((void)fit_kienzle(zero, lead), InputError);
}

TEST(KienzleFit, CliFragmentMakesAConfigThatGivesTheTestsForces) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "chatter_kienzle_cli";
  std::filesystem::create_directories(dir);
  {
    std::ofstream t(dir / "tests.csv");
    t << "# seed 003, table 14\nfeed_mm_per_rev,depth_mm,tangential_force_n,feed_force_n\n0.35,1.5,736,501\n"
         "0.089,1.5,342,175\n";
  }
  const std::string cmd = std::string("'") + CHATTER_CLI + "' coefficients '" + (dir / "tests.csv").string() +
                          "' --out '" + (dir / "law.toml").string() + "' > '" + (dir / "report.txt").string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream frag(dir / "law.toml");
  const std::string fragment((std::istreambuf_iterator<char>(frag)), {});
  EXPECT_NE(fragment.find("force_law = \"kienzle\""), std::string::npos) << fragment;
  const Config c = parse_config(fragment + "workpiece_diameter_mm = 25\nfeed_per_rev_mm = 0.2\n"
                                "[[workpiece.modes]]\nfrequency_hz = 2790\ndamping_ratio = 0.04\n"
                                "stiffness_n_per_m = 2.3e7\ndirection = \"x\"\n",
                                (dir / "law.toml").string());
  std::vector<std::string> warnings;
  const auto law = CuttingLaw::of(c.process, cutting_law_options(c.process, std::nullopt, warnings));
  const MeanCut m = law->mean(CutPoint{3000.0, 1.5e-3, 0.089e-3, 0.025});
  EXPECT_NEAR(m.tangential_force_n, 342.0, 1e-3);  // the fragment's digits: 6 significant
  EXPECT_NEAR(-m.force_n.x(), 175.0, 1e-3);
  std::ifstream rep(dir / "report.txt");
  const std::string report((std::istreambuf_iterator<char>(rep)), {});
  EXPECT_NE(report.find("warning: two tests"), std::string::npos) << report;
  // A milling flag on turning tests is refused by name.
  const std::string bad = std::string("'") + CHATTER_CLI + "' coefficients '" + (dir / "tests.csv").string() +
                          "' --teeth 3 > /dev/null 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace chatter
