// Grinding models from test data (include/chatter/grinding_data.hpp): fits
// that recover known coefficients from data generated here with noise, their
// statistics, and the impact count of a synthetic force record. Kernels only.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding_data.hpp"
#include "grinding_cases.hpp"

namespace chatter::grinding {
namespace {

// A deterministic normal noise (splitmix64 + Box-Muller): the same numbers on
// every platform, unlike std::normal_distribution.
class Noise {
 public:
  explicit Noise(std::uint64_t seed) : s_(seed) {}
  double uniform() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 0.5) / 9007199254740992.0;
  }
  double normal() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::uint64_t s_;
};

// A recovered coefficient lies within this many standard errors of the truth:
// 4 sigma fails by chance once in ~16 000 coefficients (the noise is fixed,
// so a pass is a pass for good), and a wrong model misses by far more.
constexpr double kSigmas = 4.0;

void expect_recovered(const FitStatistics& f, const std::vector<double>& truth) {
  ASSERT_EQ(f.coefficients.size(), truth.size());
  for (std::size_t j = 0; j < truth.size(); ++j) {
    EXPECT_GT(f.standard_error[j], 0.0) << f.names[j];
    EXPECT_NEAR(f.coefficients[j], truth[j], kSigmas * f.standard_error[j])
        << f.names[j] << ": fitted " << f.coefficients[j] << " +- " << f.standard_error[j] << ", truth " << truth[j];
    EXPECT_LE(f.lower_95[j], f.coefficients[j]);
    EXPECT_GE(f.upper_95[j], f.coefficients[j]);
  }
}

TEST(GrindingFit, MechanisticRecoversKeAndKc) {
  // Seed 001's set, tests at 500..2000 W and three feeds, the power logged
  // with 2 % noise, n_c from the table.
  const Process base = cases::seed001_ch4();
  Noise noise(28);
  std::vector<MechanisticTest> tests;
  for (double feed : {0.040, 0.060, 0.080})
    for (double P : {500.0, 750.0, 1000.0, 1250.0, 1500.0, 1750.0, 2000.0}) {
      Process p = base;
      p.feed_m_per_s = feed;
      const Prediction r = predict_at_power(p, P);
      MechanisticTest t;
      t.power_w = P * (1.0 + 0.02 * noise.normal());
      t.removal_m3_per_s = r.removal_rate_m3_per_s;
      t.impacts_per_turn = *r.impacts_per_turn;
      t.wheel = p.wheel;
      t.feed_m_per_s = feed;
      tests.push_back(t);
    }
  const FitStatistics f = fit_mechanistic(tests);
  expect_recovered(f, {75e3, 10020e6});
  EXPECT_EQ(f.degrees_of_freedom, 19);
  EXPECT_GT(f.r_squared, 0.99);
  EXPECT_GT(f.rmse, 0.0);
  EXPECT_LT(f.mape_percent, 4.0);  // 2 % noise: a mean absolute error near 1.6 %
  EXPECT_TRUE(f.warnings.empty());
  // Residuals are measured - fitted.
  for (std::size_t i = 0; i < tests.size(); ++i)
    EXPECT_NEAR(f.residuals[i], tests[i].power_w - f.fitted[i], 1e-9);
}

TEST(GrindingFit, ExactDataGivesExactStatistics) {
  // Noise-free data: R^2 = 1, zero errors, the truth to rounding.
  const Process p = cases::seed001_ch4();
  std::vector<MechanisticTest> tests;
  for (double P : {600.0, 1100.0, 1700.0, 2300.0}) {
    const Prediction r = predict_at_power(p, P);
    tests.push_back({P, r.removal_rate_m3_per_s, *r.impacts_per_turn, p.wheel, p.feed_m_per_s});
  }
  const FitStatistics f = fit_mechanistic(tests);
  EXPECT_NEAR(f.coefficients[0], 75e3, 1e-6 * 75e3);
  EXPECT_NEAR(f.coefficients[1], 10020e6, 1e-6 * 10020e6);
  EXPECT_NEAR(f.r_squared, 1.0, 1e-9);
  EXPECT_NEAR(f.mae, 0.0, 1e-6);
  EXPECT_NEAR(f.mape_percent, 0.0, 1e-7);
}

// A grid of operating points like seed 000's: speeds 10-31 m/s, powers
// 1100-2800 W, diameters 110-197 mm.
std::vector<EmpiricalInputs> grid() {
  std::vector<EmpiricalInputs> g;
  for (double d : {110.0, 140.0, 170.0, 197.0})
    for (double rpm : {1500.0, 2000.0, 2500.0, 3000.0})
      for (double P : {1100.0, 1600.0, 2200.0, 2800.0}) {
        EmpiricalInputs in;
        in.wheel_diameter_mm = d;
        in.wheel_rpm = rpm;
        in.cutting_speed_m_per_s = std::numbers::pi * d * 1e-3 * rpm / 60.0;
        in.useful_power_w = P;
        in.normal_force_n = 100.0 + 0.06 * P - 2.0 * in.cutting_speed_m_per_s;
        g.push_back(in);
      }
  return g;
}

TEST(GrindingFit, PolynomialsRecoverTheirCoefficients) {
  Noise noise(7);
  const std::vector<std::pair<EmpiricalForm, std::vector<double>>> cases_ = {
      {EmpiricalForm::kPoly11, {63.1, -5.05, 0.0439}},  // seed 000 annex IV removal
      {EmpiricalForm::kPoly22, {53.1, -6.74, 0.0715, 0.0883, -1.0e-3, -1.74e-6}},
      {EmpiricalForm::kPoly33, {20.0, -2.0, 0.05, 0.02, -1e-3, 1e-5, -2e-4, 1e-5, -2e-7, 1e-10}},
  };
  for (const auto& [form, truth] : cases_) {
    EmpiricalModel m;
    m.form = form;
    m.coefficients = truth;
    std::vector<EmpiricalSample> s;
    for (const EmpiricalInputs& in : grid()) s.push_back({in, m.evaluate(in) + 0.5 * noise.normal()});
    const FitStatistics f = fit_empirical(form, EmpiricalVariable::kUsefulPower, s);
    SCOPED_TRACE(empirical_form_name(form));
    expect_recovered(f, truth);
    EXPECT_EQ(f.degrees_of_freedom, static_cast<int>(s.size() - truth.size()));
    EXPECT_NEAR(f.rmse, 0.5, 0.15);  // the noise's sigma
  }
}

TEST(GrindingFit, PowerLawAndHahnLindsay) {
  Noise noise(11);
  {
    EmpiricalModel m;
    m.form = EmpiricalForm::kPowerLaw;
    m.coefficients = {8.53e7, -3.37, 2.93, -2.07};  // seed 000 annex IV, removal on the power
    std::vector<EmpiricalSample> s;
    for (const EmpiricalInputs& in : grid()) s.push_back({in, m.evaluate(in) * std::exp(0.03 * noise.normal())});
    const FitStatistics f = fit_empirical(EmpiricalForm::kPowerLaw, EmpiricalVariable::kUsefulPower, s);
    // Exponents within 4 standard errors; C through ln C's interval.
    for (std::size_t j = 1; j < 4; ++j)
      EXPECT_NEAR(f.coefficients[j], m.coefficients[j], kSigmas * f.standard_error[j]) << f.names[j];
    EXPECT_NEAR(std::log(f.coefficients[0]), std::log(8.53e7), kSigmas * f.standard_error[0]);
    EXPECT_LT(f.lower_95[0], f.coefficients[0]);
    EXPECT_GT(f.upper_95[0], f.coefficients[0]);
  }
  {
    EmpiricalModel m;
    m.form = EmpiricalForm::kHahnLindsay;
    m.variable = EmpiricalVariable::kNormalForce;
    m.coefficients = {1.98e-2, 103.0};  // seed 000 annex IV
    std::vector<EmpiricalSample> s;
    for (const EmpiricalInputs& in : grid()) s.push_back({in, m.evaluate(in) + 1.0 * noise.normal()});
    const FitStatistics f = fit_empirical(EmpiricalForm::kHahnLindsay, EmpiricalVariable::kNormalForce, s);
    expect_recovered(f, m.coefficients);
  }
}

TEST(GrindingFit, BadInput) {
  const std::vector<MechanisticTest> two(2);
  EXPECT_THROW(fit_mechanistic(two), InputError);
  // The same ratio of friction to chip regressors in every test: not separable.
  const Process p = cases::seed001_ch4();
  const Prediction r = predict_at_power(p, 1000.0);
  std::vector<MechanisticTest> same(4, {1000.0, r.removal_rate_m3_per_s, 1.29, p.wheel, p.feed_m_per_s});
  EXPECT_THROW(fit_mechanistic(same), InputError);
  std::vector<EmpiricalSample> s(3);
  EXPECT_THROW(fit_empirical(EmpiricalForm::kPoly11, EmpiricalVariable::kUsefulPower, s), InputError);  // 3 < 4
  EXPECT_THROW(fit_empirical(EmpiricalForm::kHahnLindsay, EmpiricalVariable::kUsefulPower, s), InputError);
  std::vector<EmpiricalSample> bad_log(6);
  EXPECT_THROW(fit_empirical(EmpiricalForm::kPowerLaw, EmpiricalVariable::kUsefulPower, bad_log), InputError);
}

// ------------------------------------------------------------- impact count

// A normal-force record at 6000 rev/min: per turn the impacts of `pattern`,
// each a 0.15 ms half-sine of 2 to 4 kN, over a 5 N noise floor.
struct Record {
  std::vector<double> t, f;
};
Record force_record(const std::vector<int>& pattern, double rpm) {
  Record r;
  const double turn = 60.0 / rpm, dt = 5e-6, width = 0.15e-3;
  Noise noise(3);
  std::vector<double> centres;
  for (std::size_t k = 0; k < pattern.size(); ++k)
    for (int j = 0; j < pattern[k]; ++j)
      centres.push_back((static_cast<double>(k) + (j + 0.5) / (pattern[k] + 0.5)) * turn + 0.05 * turn);
  const double end = static_cast<double>(pattern.size()) * turn;
  for (double t = 0; t <= end + 1e-12; t += dt) {
    double f = 5.0 * noise.normal();
    for (std::size_t c = 0; c < centres.size(); ++c)
      if (std::abs(t - centres[c]) < width / 2)
        f += (2000.0 + 500.0 * static_cast<double>(c % 5)) * std::cos(std::numbers::pi * (t - centres[c]) / width);
    r.t.push_back(t);
    r.f.push_back(f);
  }
  return r;
}

TEST(GrindingImpacts, CountsPeaksPerTurn) {
  const std::vector<int> pattern = {1, 2, 0, 1, 3, 1, 0, 0, 2, 1, 1, 2};
  const Record r = force_record(pattern, 6000.0);
  ImpactCountOptions o;
  o.wheel_rpm = 6000.0;
  const ImpactCount c = count_impacts(r.t, r.f, ImpactSignal::kNormalForce, o);
  ASSERT_EQ(c.turns, static_cast<int>(pattern.size()));
  EXPECT_EQ(c.per_turn, pattern);
  // histogram: 3 turns with 0, 5 with 1, 3 with 2, 1 with 3.
  EXPECT_EQ(c.histogram, (std::vector<int>{3, 5, 3, 1}));
  EXPECT_DOUBLE_EQ(c.mean_per_turn, 14.0 / 12.0);
  EXPECT_DOUBLE_EQ(c.turns_without_contact, 3.0 / 12.0);
  ASSERT_EQ(c.peak_value.size(), 14u);
  for (double v : c.peak_value) EXPECT_GT(v, 1900.0);
}

TEST(GrindingImpacts, WheelSpeedDipsCountLikeForcePeaks) {
  const std::vector<int> pattern = {1, 1, 2, 0, 1, 2};
  const Record r = force_record(pattern, 6000.0);
  std::vector<double> speed(r.f.size());
  for (std::size_t i = 0; i < speed.size(); ++i) speed[i] = 6000.0 - 0.02 * r.f[i];  // the wheel is braked
  ImpactCountOptions o;
  o.wheel_rpm = 6000.0;
  const ImpactCount c = count_impacts(r.t, speed, ImpactSignal::kWheelSpeed, o);
  EXPECT_EQ(c.per_turn, pattern);
}

TEST(GrindingImpacts, BadInput) {
  const Record r = force_record({1, 1, 1}, 6000.0);
  ImpactCountOptions o;
  o.wheel_rpm = 0.0;
  EXPECT_THROW(count_impacts(r.t, r.f, ImpactSignal::kNormalForce, o), InputError);
  o.wheel_rpm = 600.0;  // a turn of 0.1 s: the 30 ms record is shorter than two
  EXPECT_THROW(count_impacts(r.t, r.f, ImpactSignal::kNormalForce, o), InputError);
  o.wheel_rpm = 6000.0;
  const std::vector<double> flat(r.t.size(), 10.0);
  EXPECT_THROW(count_impacts(r.t, flat, ImpactSignal::kNormalForce, o), InputError);
}

}  // namespace
}  // namespace chatter::grinding
