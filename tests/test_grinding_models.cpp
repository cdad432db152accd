// The grinding engineer's models beyond one prediction (docs/grinding.md):
// beta of the power partition by power and feed (seed 001 table 2.2);
// intervals on the empirical models' predictions from their fit.
// Each number against the seed's table or a hand computation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/grinding_data.hpp"
#include "grinding_cases.hpp"

namespace chatter::grinding {
namespace {

constexpr double kIdentityRel = 1e-12;

// Seed 001 table 2.2: beta by feed (mm/s) and power (W), alpha = 0.76.
BetaTable seed001_table_2_2() {
  return BetaTable({{0.040, {1000, 1250, 1500}, {0.49, 0.33, 0.20}},
                    {0.060, {1000, 1250, 1500, 1750}, {0.36, 0.21, 0.13, 0.08}},
                    {0.080, {1000, 1250, 1500, 1750, 2000}, {0.27, 0.17, 0.09, 0.05, 0.03}}});
}

TEST(GrindingBetaTable, NodesAreTheSeedsTable) {
  const BetaTable t = seed001_table_2_2();
  std::vector<std::string> notes;
  EXPECT_EQ(t.at(1000, 0.040, &notes), 0.49);
  EXPECT_EQ(t.at(1750, 0.060, &notes), 0.08);
  EXPECT_EQ(t.at(2000, 0.080, &notes), 0.03);
  EXPECT_EQ(t.at(1250, 0.080, &notes), 0.17);
  EXPECT_TRUE(notes.empty());
}

TEST(GrindingBetaTable, InterpolatedInPowerThenFeedAndHeldWithANote) {
  const BetaTable t = seed001_table_2_2();
  std::vector<std::string> notes;
  // 70 mm/s, 1125 W: rows 60 and 80 at 1125 W are 0.285 and 0.22, halfway 0.2525.
  EXPECT_NEAR(t.at(1125, 0.070, &notes), 0.5 * (0.5 * (0.36 + 0.21) + 0.5 * (0.27 + 0.17)), kIdentityRel);
  EXPECT_TRUE(notes.empty());
  // 70 mm/s, 1900 W: the 60 mm/s row ends at 1750 W (held at 0.08); the
  // 80 mm/s row gives 0.05 + 0.6 (0.03 - 0.05) = 0.038; halfway 0.059.
  EXPECT_NEAR(t.at(1900, 0.070, &notes), 0.5 * (0.08 + 0.038), kIdentityRel);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("60 mm/s"), std::string::npos) << notes[0];
  // Beyond the feeds: the nearest row, said.
  notes.clear();
  EXPECT_EQ(t.at(1500, 0.100, &notes), 0.09);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("100 mm/s"), std::string::npos) << notes[0];
}

TEST(GrindingBetaTable, RefusesWhatIsNotATable) {
  EXPECT_THROW(BetaTable(std::vector<BetaTable::Row>{}), InputError);
  EXPECT_THROW(BetaTable({{0.08, {1000, 900}, {0.2, 0.1}}}), InputError);             // powers not increasing
  EXPECT_THROW(BetaTable({{0.08, {1000}, {1.2}}}), InputError);                       // beta > 1
  EXPECT_THROW(BetaTable({{0.08, {1000}, {0.2}}, {0.06, {1000}, {0.3}}}), InputError);  // feeds not increasing
  EXPECT_THROW(BetaTable({{0.08, {1000, 1500}, {0.2}}}), InputError);                 // one beta per power
}

// The power partition (seed 001 eq. 2.18) at each power of table 4.1 with
// the 80 mm/s row: eps = (0.76 P_friction + beta P_chip) / P from the
// prediction's own split, and the record carries the beta used.
TEST(GrindingBetaTable, PowerPartitionReadsBetaAtItsPowerAndFeed) {
  Process p = cases::seed001_ch4();
  p.partition->model = PartitionModel::kPower;
  p.partition->alpha = 0.76;
  p.partition->beta_table = seed001_table_2_2();
  const double beta[] = {0.27, 0.17, 0.09, 0.05, 0.03};
  for (int i = 0; i < 5; ++i) {
    const double P = 1000.0 + 250.0 * i;
    const Prediction r = predict_at_power(p, P);
    ASSERT_TRUE(r.energy_partition && r.energy_partition->beta);
    EXPECT_EQ(*r.energy_partition->beta, beta[i]);
    EXPECT_NEAR(r.energy_partition->fraction, (0.76 * *r.friction_power_w + beta[i] * *r.chip_power_w) / P,
                kIdentityRel);
  }
  // At 60 mm/s the 60 mm/s row: 1250 W -> 0.21.
  p.feed_m_per_s = 0.060;
  EXPECT_EQ(*predict_at_power(p, 1250).energy_partition->beta, 0.21);
  // Past 1750 W at 60 mm/s: held, and a warning says so.
  const Prediction h = predict_at_power(p, 2000);
  EXPECT_EQ(*h.energy_partition->beta, 0.08);
  bool said = false;
  for (const auto& w : h.warnings) said = said || w.find("beta table") != std::string::npos;
  EXPECT_TRUE(said);
}

// --------------------------------------------------------------- intervals

// Tests of a known poly11 removal (V_c 14-24 m/s, P_u 1100-2700 W) with
// noise of standard deviation sigma.
constexpr double kTrue[3] = {60.0, -5.0, 0.044};
constexpr double kSigma = 5.0;
std::vector<EmpiricalSample> noisy_tests(std::mt19937& rng, int m) {
  std::uniform_real_distribution<double> vc(14.0, 24.0), pu(1100.0, 2700.0);
  std::normal_distribution<double> noise(0.0, kSigma);
  std::vector<EmpiricalSample> s(static_cast<std::size_t>(m));
  for (auto& x : s) {
    x.inputs.cutting_speed_m_per_s = vc(rng);
    x.inputs.useful_power_w = pu(rng);
    x.value = kTrue[0] + kTrue[1] * x.inputs.cutting_speed_m_per_s + kTrue[2] * x.inputs.useful_power_w + noise(rng);
  }
  return s;
}
EmpiricalModel model_of(const FitStatistics& f, EmpiricalForm form) {
  EmpiricalModel m;
  m.form = form;
  m.coefficients = f.coefficients;
  m.uncertainty = f.uncertainty;
  return m;
}

// The fit's covariance is s^2 (X'X)^-1 by the normal equations, and at the
// tests' centroid a model with a constant term has se of the mean s / sqrt(m)
// exactly (g C g' = s^2 / m there).
TEST(GrindingIntervals, CovarianceAndTheCentroidClosedForm) {
  std::mt19937 rng(7);
  const auto tests = noisy_tests(rng, 12);
  const FitStatistics f = fit_empirical(EmpiricalForm::kPoly11, EmpiricalVariable::kUsefulPower, tests);
  Eigen::MatrixXd X(12, 3);
  double rss = 0.0, xm = 0.0, ym = 0.0;
  for (int i = 0; i < 12; ++i) {
    const auto& in = tests[static_cast<std::size_t>(i)].inputs;
    X.row(i) << 1.0, in.cutting_speed_m_per_s, in.useful_power_w;
    rss += f.residuals[static_cast<std::size_t>(i)] * f.residuals[static_cast<std::size_t>(i)];
    xm += in.cutting_speed_m_per_s / 12.0;
    ym += in.useful_power_w / 12.0;
  }
  const double s2 = rss / 9.0;
  EXPECT_NEAR(f.uncertainty.residual_variance, s2, 1e-10 * s2);
  EXPECT_EQ(f.uncertainty.degrees_of_freedom, 9);
  const Eigen::MatrixXd C = s2 * (X.transpose() * X).ldlt().solve(Eigen::MatrixXd::Identity(3, 3));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(f.uncertainty.covariance[static_cast<std::size_t>(3 * i + j)], C(i, j),
                  1e-8 * std::sqrt(C(i, i) * C(j, j)));
  const EmpiricalModel m = model_of(f, EmpiricalForm::kPoly11);
  EmpiricalInputs centroid;
  centroid.cutting_speed_m_per_s = xm;
  centroid.useful_power_w = ym;
  const auto i = m.interval(centroid);
  ASSERT_TRUE(i);
  EXPECT_NEAR(i->standard_error_mean, std::sqrt(s2 / 12.0), 1e-9 * std::sqrt(s2));
  EXPECT_NEAR(i->standard_error_test, std::sqrt(s2 + s2 / 12.0), 1e-9 * std::sqrt(s2));
  // t(0.975, 9) = 2.262157 (tables).
  EXPECT_NEAR(i->mean_95.hi - i->value, 2.262157 * i->standard_error_mean, 1e-6 * i->standard_error_mean);
}

// Coverage: over 4 000 repetitions of a 12-test campaign, the 95 %
// confidence interval of the mean holds the true mean, and the 95 %
// prediction interval a new test, 95 % of the time (binomial standard error
// 0.34 %; tolerance 1.2 %, 3.5 of them).
TEST(GrindingIntervals, NinetyFivePercentCoverage) {
  std::mt19937 rng(2026);
  std::normal_distribution<double> noise(0.0, kSigma);
  const int kRuns = 4000;
  int mean_in = 0, test_in = 0;
  EmpiricalInputs at;
  at.cutting_speed_m_per_s = 22.0;  // off-centre: a leverage above p/m
  at.useful_power_w = 1300.0;
  const double truth = kTrue[0] + kTrue[1] * 22.0 + kTrue[2] * 1300.0;
  for (int r = 0; r < kRuns; ++r) {
    const FitStatistics f =
        fit_empirical(EmpiricalForm::kPoly11, EmpiricalVariable::kUsefulPower, noisy_tests(rng, 12));
    const auto i = model_of(f, EmpiricalForm::kPoly11).interval(at);
    mean_in += i->mean_95.contains(truth) ? 1 : 0;
    test_in += i->test_95.contains(truth + noise(rng)) ? 1 : 0;
  }
  EXPECT_NEAR(mean_in / static_cast<double>(kRuns), 0.95, 0.012);
  EXPECT_NEAR(test_in / static_cast<double>(kRuns), 0.95, 0.012);
}

// A power law's intervals are exp of ln y's: symmetric in ln, and the
// depth per pass's is the removal's over v_f E.
TEST(GrindingIntervals, PowerLawOnLogarithmsAndTheDepthPerPass) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> n(1500, 3000), y(1100, 2700), d(110, 200);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<EmpiricalSample> s(15);
  for (auto& x : s) {
    x.inputs.wheel_rpm = n(rng);
    x.inputs.useful_power_w = y(rng);
    x.inputs.wheel_diameter_mm = d(rng);
    x.value = 0.02 * std::pow(x.inputs.wheel_rpm, 0.3) * std::pow(x.inputs.useful_power_w, 0.9) *
              std::pow(x.inputs.wheel_diameter_mm, -0.4) * std::exp(noise(rng));
  }
  const FitStatistics f = fit_empirical(EmpiricalForm::kPowerLaw, EmpiricalVariable::kUsefulPower, s);
  const auto i = model_of(f, EmpiricalForm::kPowerLaw).interval(s[4].inputs);
  ASSERT_TRUE(i);
  EXPECT_TRUE(i->log_scale);
  EXPECT_NEAR(std::log(i->mean_95.hi) - std::log(i->value), std::log(i->value) - std::log(i->mean_95.lo), 1e-12);
  EXPECT_GT(i->test_95.hi, i->mean_95.hi);
  const PredictionInterval depth = i->scaled(0.5);
  EXPECT_DOUBLE_EQ(depth.mean_95.hi, 0.5 * i->mean_95.hi);
  EXPECT_EQ(depth.standard_error_mean, i->standard_error_mean);  // of ln y: unchanged
  // Through predict: the underwater annex point with the fitted removal.
  Process p = cases::seed000_annex6();
  p.empirical.removal->uncertainty = FitUncertainty{{4.0, 0.0, 0.0, 0.0, 0.01, 0.0, 0.0, 0.0, 1e-6}, 25.0, 80};
  const Prediction r = predict_at_power(p, cases::kAnnexPower);
  ASSERT_TRUE(r.empirical && r.empirical->removal_interval && r.empirical->depth_per_pass_interval);
  const PredictionInterval& ri = *r.empirical->removal_interval;
  const double g[3] = {1.0, r.cutting_speed_m_per_s, cases::kAnnexPower};
  EXPECT_NEAR(ri.standard_error_mean, std::sqrt(4.0 + 0.01 * g[1] * g[1] + 1e-6 * g[2] * g[2]), 1e-12);
  EXPECT_NEAR(r.empirical->depth_per_pass_interval->mean_95.hi, ri.mean_95.hi / (50.0 * 25.0), 1e-15);
  EXPECT_NEAR(r.empirical->depth_per_pass_interval->value * 1e-3, r.depth_per_pass_m, 1e-12);
}

TEST(GrindingIntervals, ABadCovarianceIsRefused) {
  EmpiricalModel m;
  m.coefficients = {1, 2, 3};
  m.uncertainty = FitUncertainty{{1, 0, 0, 0, 1, 0, 0, 0}, 1.0, 5};
  EXPECT_NE(m.validate().find("3 x 3"), std::string::npos);
  m.uncertainty = FitUncertainty{{1, 0.5, 0, 0, 1, 0, 0, 0, 1}, 1.0, 5};
  EXPECT_NE(m.validate().find("symmetric"), std::string::npos);
  m.uncertainty = FitUncertainty{{1, 0, 0, 0, -1, 0, 0, 0, 1}, 1.0, 5};
  EXPECT_NE(m.validate().find(">= 0"), std::string::npos);
  m.uncertainty = FitUncertainty{{1, 0, 0, 0, 1, 0, 0, 0, 1}, 1.0, 0};
  EXPECT_NE(m.validate().find("degrees of freedom"), std::string::npos);
}

// ------------------------------------------------------------------- motor

// Annex VI's screen: 19 A at 2000 rev/min of the motor gives 2491.4 W of
// mechanical power through the illustrative DC map of the shipped config
// (P_m = p11 I n + p01 n); the useful power is that minus the table 4.5
// loss c0 omega^k D^x, by hand.
MotorMap dc_map() {
  MotorMap m;
  m.form = EmpiricalForm::kPoly22;
  const double p11 = 2491.4 / 36000.0;
  m.coefficients = {0.0, 0.0, -p11, 0.0, p11, 0.0};
  m.max_current_a = 19.0;
  return m;
}

TEST(GrindingMotor, UsefulPowerIsTheMapLessTheNoLoadLoss) {
  Process p = cases::seed000_annex6();
  p.transmission_ratio = 1.125;
  p.motor = dc_map();
  p.no_load_loss = NoLoadLoss{6.841e-2, 1.314, 0.350};
  ASSERT_EQ(p.validate(), "");
  const double omega = 2.0 * 3.14159265358979323846 * 2250.0 / 60.0;
  const double loss = 6.841e-2 * std::pow(omega, 1.314) * std::pow(p.wheel.diameter_m * 1e3, 0.350);
  std::vector<std::string> w;
  EXPECT_NEAR(useful_power_from_current(p, 19.0, w), 2491.4 - loss, 1e-9);
  EXPECT_TRUE(w.empty());
  const Prediction r = predict_at_current(p, 19.0);
  EXPECT_EQ(r.mode, "current");
  EXPECT_NEAR(r.power_w, 2491.4 - loss, 1e-9);
  EXPECT_NEAR(*r.motor_power_w, 2491.4, 1e-9);
  EXPECT_EQ(*r.motor_current_a, 19.0);
  EXPECT_NEAR(r.removal_rate_m3_per_s, predict_at_power(p, 2491.4 - loss).removal_rate_m3_per_s, 1e-18);
  // Above the continuous limit: said.
  w.clear();
  useful_power_from_current(p, 22.0, w);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("continuous limit 19 A"), std::string::npos);
  // Outside the measured range: said.
  p.motor->current_a = Interval{10.0, 19.0};
  w.clear();
  useful_power_from_current(p, 8.0, w);
  EXPECT_NE(w.front().find("current 8 A outside the measured 10 to 19 A"), std::string::npos) << w.front();
  // A current whose power the loss eats: refused.
  EXPECT_THROW(useful_power_from_current(p, 2.0, w), InputError);
  // Without a loss model the motor's power is all of it, and a warning says so.
  p.no_load_loss.reset();
  w.clear();
  EXPECT_NEAR(useful_power_from_current(p, 19.0, w), 2491.4, 1e-9);
  EXPECT_NE(w.front().find("no [grinding.no_load_loss]"), std::string::npos);
  // Without a map: refused, naming the table.
  p.motor.reset();
  try {
    useful_power_from_current(p, 19.0, w);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[grinding.motor]"), std::string::npos);
  }
}

// ------------------------------------------------------- plan objectives

// A wheel whose removal falls with the cutting speed, Z = 100 - 2 V_c, and
// whose wear W = 210 - 20 V_c + 0.5 V_c^2 (mm^3/s) has its G-ratio Z/W
// largest where Z' W = Z W': V_c^2 - 100 V_c + 1580 = 0, V* = 50 - sqrt(920)
// = 19.668 m/s, G* = 6.033; the removal is largest at the lowest tested
// speed, 14 m/s, where G = 72/28.
Process objective_case() {
  Process p;
  p.wheel.diameter_m = 0.200;
  p.wheel.width_m = 0.025;
  p.wheel.speed_rev_per_s = 25.0;
  p.feed_m_per_s = 0.050;
  p.force_ratio = 0.5;
  p.min_wheel_diameter_m = 0.140;
  EmpiricalModel removal, wear;
  removal.form = EmpiricalForm::kPoly11;
  removal.coefficients = {100.0, -2.0, 0.0};
  removal.domain.cutting_speed_m_per_s = Interval{14.0, 24.0};
  wear.form = EmpiricalForm::kPoly22;
  wear.coefficients = {210.0, -20.0, 0.0, 0.5, 0.0, 0.0};
  p.empirical.removal = removal;
  p.empirical.wear = wear;
  return p;
}

TEST(GrindingPlanObjective, EachDiameterAtTheObjectivesBestSpeed) {
  const Process p = objective_case();
  PlanOptions o;
  o.volume_m3 = 3e-3;
  o.power_w = 2000.0;
  o.wheel_change_s = 3 * 3600.0;
  o.wheel_rpm_min = 1000.0;
  o.wheel_rpm_max = 4000.0;
  o.speed_points = 301;  // 10 rev/min apart
  const double v_star = 50.0 - std::sqrt(920.0);
  const double g_star = (100.0 - 2.0 * v_star) / (210.0 - 20.0 * v_star + 0.5 * v_star * v_star);
  const PlanComparison c = compare_plan_objectives(p, o);
  const double pi = 3.14159265358979323846;
  for (const PlanStep& s : c.g_ratio.life) {
    // The grid's speed nearest to V*: within half a step of cutting speed.
    const double half_step = pi * s.diameter_m * 5.0 / 60.0;
    EXPECT_LE(std::abs(s.cutting_speed_m_per_s - v_star), half_step + 1e-12) << s.diameter_m;
  }
  for (const PlanStep& s : c.removal.life) {
    // The lowest grid speed at or above 14 m/s.
    const double step = pi * s.diameter_m * 10.0 / 60.0;
    EXPECT_GE(s.cutting_speed_m_per_s, 14.0);
    EXPECT_LT(s.cutting_speed_m_per_s, 14.0 + step) << s.diameter_m;
  }
  // G is flat at its maximum: the life's mean G is G* to the grid's
  // resolution (second order in the half step, ~1e-4 relative); at 14 m/s
  // it is 72/28 to first order in the step (~2 %).
  EXPECT_NEAR(c.g_ratio.mean_g_ratio, g_star, 1e-3 * g_star);
  EXPECT_NEAR(c.removal.mean_g_ratio, 72.0 / 28.0, 0.03 * 72.0 / 28.0);
  // Wheels and time follow from the mean G-ratio and the usable volume.
  const double usable = pi / 4.0 * 0.025 * (0.2 * 0.2 - 0.14 * 0.14);
  EXPECT_NEAR(c.g_ratio.removal_per_wheel_m3, c.g_ratio.mean_g_ratio * usable, 1e-12 * usable);
  EXPECT_EQ(c.g_ratio.wheels_needed, static_cast<int>(std::ceil(o.volume_m3 / (c.g_ratio.mean_g_ratio * usable))));
  EXPECT_EQ(c.wheels_saved, c.removal.wheels_needed - c.g_ratio.wheels_needed);
  EXPECT_GT(c.wheels_saved, 0);
  EXPECT_NEAR(c.time_saved_s, c.removal.total_time_s - c.g_ratio.total_time_s, 1e-9);
  // The removal strategy removes faster: its wheel's grinding time per mm^3 is shorter.
  EXPECT_LT(c.removal.grinding_time_s, c.g_ratio.grinding_time_s);
}

TEST(GrindingPlanObjective, RefusalsSayWhatIsMissing) {
  Process p = objective_case();
  PlanOptions o;
  o.volume_m3 = 1e-3;
  o.power_w = 2000.0;
  o.objective = PlanObjective::kGRatio;
  EXPECT_THROW(plan_repair(p, o), InputError);  // no speed range
  o.wheel_rpm_min = 1000.0;
  o.wheel_rpm_max = 1200.0;  // 10.5 to 12.6 m/s at 200 mm: below the tested 14 m/s
  try {
    plan_repair(p, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no wheel speed of 1000 to 1200 rev/min"), std::string::npos) << e.what();
  }
  o.wheel_rpm_max = 4000.0;
  o.g_ratio = 2.0;  // a constant G-ratio: every speed the same
  EXPECT_THROW(plan_repair(p, o), InputError);
  o.g_ratio = 0.0;
  o.power_w = 0.0;
  o.current_a = 19.0;  // no motor map
  EXPECT_THROW(plan_repair(p, o), InputError);
}

}  // namespace
}  // namespace chatter::grinding
