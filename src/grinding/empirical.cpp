// Seed 000's empirical models (include/chatter/grinding.hpp): forms, term
// order, evaluation, tested domain, predictions.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/kinematics.hpp"
#include "grinding_internal.hpp"
#include "grinding_text.hpp"

namespace chatter::grinding {

const char* empirical_form_name(EmpiricalForm f) {
  switch (f) {
    case EmpiricalForm::kPoly11: return "poly11";
    case EmpiricalForm::kPoly22: return "poly22";
    case EmpiricalForm::kPoly33: return "poly33";
    case EmpiricalForm::kPowerLaw: return "power_law";
    case EmpiricalForm::kHahnLindsay: return "hahn_lindsay";
  }
  return "?";
}

std::size_t coefficient_count(EmpiricalForm f) {
  switch (f) {
    case EmpiricalForm::kPoly11: return 3;
    case EmpiricalForm::kPoly22: return 6;
    case EmpiricalForm::kPoly33: return 10;
    case EmpiricalForm::kPowerLaw: return 4;
    case EmpiricalForm::kHahnLindsay: return 2;
  }
  return 0;
}

std::vector<std::string> coefficient_names(EmpiricalForm f) {
  switch (f) {
    case EmpiricalForm::kPoly11: return {"p00", "p10", "p01"};
    case EmpiricalForm::kPoly22: return {"p00", "p10", "p01", "p20", "p11", "p02"};
    case EmpiricalForm::kPoly33: return {"p00", "p10", "p01", "p20", "p11", "p02", "p30", "p21", "p12", "p03"};
    case EmpiricalForm::kPowerLaw: return {"C", "b1", "b2", "b3"};
    case EmpiricalForm::kHahnLindsay: return {"K_p", "F_th"};
  }
  return {};
}

namespace detail {

std::string validate_coefficients(EmpiricalForm form, const std::vector<double>& coefficients) {
  const std::size_t n = coefficient_count(form);
  if (coefficients.size() != n)
    return std::string(empirical_form_name(form)) + " needs " + std::to_string(n) + " coefficients, got " +
           std::to_string(coefficients.size());
  for (double c : coefficients)
    if (!std::isfinite(c)) return "coefficients must be finite numbers";
  return "";
}

}  // namespace detail

std::string EmpiricalModel::validate() const {
  const std::size_t n = coefficient_count(form);
  if (const std::string e = detail::validate_coefficients(form, coefficients); !e.empty()) return e;
  if (form == EmpiricalForm::kHahnLindsay && variable != EmpiricalVariable::kNormalForce)
    return "hahn_lindsay reads the normal force: its variable must be normal_force_n";
  if (form == EmpiricalForm::kPowerLaw && !(coefficients[0] > 0.0)) return "power_law: the constant C must be > 0";
  if (uncertainty) return detail::validate_uncertainty(*uncertainty, n);
  return "";
}

namespace detail {

double poly_value(EmpiricalForm form, const std::vector<double>& c, double x, double y) {
  double v = c[0] + c[1] * x + c[2] * y;
  if (form == EmpiricalForm::kPoly11) return v;
  v += c[3] * x * x + c[4] * x * y + c[5] * y * y;
  if (form == EmpiricalForm::kPoly22) return v;
  return v + c[6] * x * x * x + c[7] * x * x * y + c[8] * x * y * y + c[9] * y * y * y;
}

}  // namespace detail

double EmpiricalModel::evaluate(const EmpiricalInputs& in) const {
  const double x = in.cutting_speed_m_per_s;
  const double y = variable == EmpiricalVariable::kUsefulPower ? in.useful_power_w : in.normal_force_n;
  const std::vector<double>& c = coefficients;
  switch (form) {
    case EmpiricalForm::kPoly11:
    case EmpiricalForm::kPoly22:
    case EmpiricalForm::kPoly33: return detail::poly_value(form, c, x, y);
    case EmpiricalForm::kPowerLaw:
      return c[0] * std::pow(in.wheel_rpm, c[1]) * std::pow(y, c[2]) * std::pow(in.wheel_diameter_mm, c[3]);
    case EmpiricalForm::kHahnLindsay: return c[0] * (in.normal_force_n - c[1]) * x;
  }
  return 0.0;
}

std::vector<std::string> EmpiricalModel::outside_domain(const EmpiricalInputs& in) const {
  std::vector<std::string> out;
  auto check = [&](const std::optional<Interval>& i, double v, const char* what, const char* unit) {
    if (i && !i->contains(v))
      out.push_back(std::string(what) + " " + detail::num(v) + " " + unit + " outside the tested " +
                    detail::num(i->lo) + " to " + detail::num(i->hi) + " " + unit);
  };
  check(domain.cutting_speed_m_per_s, in.cutting_speed_m_per_s, "cutting speed", "m/s");
  check(domain.useful_power_w, in.useful_power_w, "useful power", "W");
  check(domain.normal_force_n, in.normal_force_n, "normal force", "N");
  check(domain.wheel_diameter_mm, in.wheel_diameter_mm, "wheel diameter", "mm");
  check(domain.wheel_rpm, in.wheel_rpm, "wheel speed", "rev/min");
  return out;
}

// The G-ratios of rough grinding with resin-bonded discs (seed 000 measured
// 1.9 on its underwater tests): outside, a wear model near zero (or below
// it) makes the ratio of two fits meaningless. "" inside.
namespace detail {
constexpr double kUsualGRatio[2] = {0.2, 20.0};
std::string unusual_g_ratio(double g) {
  if (g >= kUsualGRatio[0] && g <= kUsualGRatio[1]) return "";
  return "outside the " + detail::num(kUsualGRatio[0]) + " to " + detail::num(kUsualGRatio[1]) +
         " of rough grinding with resin-bonded discs (seed 000 measured 1.9): the wear model is near zero here, "
         "its relative error large; give a measured G-ratio (grind plan --g-ratio)";
}
}  // namespace detail

EmpiricalPrediction predict_empirical(const Process& p, double power_w, std::vector<std::string>& warnings) {
  EmpiricalPrediction e;
  EmpiricalInputs in;
  in.cutting_speed_m_per_s = p.wheel.cutting_speed_m_per_s();
  in.useful_power_w = power_w;
  in.wheel_rpm = rpm_from_revolutions_per_s(p.wheel.speed_rev_per_s);
  in.wheel_diameter_mm = p.wheel.diameter_m * 1e3;
  in.normal_force_n = power_w / (in.cutting_speed_m_per_s * p.force_ratio);
  // A model's value, or nothing (with a warning) where it overflows: the
  // outputs never hold a NaN or an infinity.
  auto read = [&](const EmpiricalModel& m, const char* name) -> std::optional<double> {
    for (const std::string& w : m.outside_domain(in))
      warnings.push_back(std::string("grinding.models.") + name + ": " + w + " (an extrapolation)");
    const double v = m.evaluate(in);
    if (std::isfinite(v)) return v;
    warnings.push_back(std::string("grinding.models.") + name + ": not a finite number at " + detail::num(power_w) +
                       " W (the model overflows there): left out");
    return std::nullopt;
  };
  // Its interval where its fit's statistics are known and the value is finite.
  auto interval = [&](const EmpiricalModel& m, const std::optional<double>& v) -> std::optional<PredictionInterval> {
    if (!v) return std::nullopt;
    const auto i = m.interval(in);
    if (i && std::isfinite(i->test_95.lo) && std::isfinite(i->test_95.hi)) return i;
    return std::nullopt;
  };
  if (p.empirical.normal_force) {
    e.normal_force_n = read(*p.empirical.normal_force, "normal_force");
    e.normal_force_interval = interval(*p.empirical.normal_force, e.normal_force_n);
    if (e.normal_force_n) in.normal_force_n = *e.normal_force_n;
  }
  if (p.empirical.removal) {
    const auto v = read(*p.empirical.removal, "removal");
    if (v) e.removal_rate_m3_per_s = *v * 1e-9;
    e.removal_interval = interval(*p.empirical.removal, v);
    // depth per pass = removal / (v_f E): mm^3/s over mm^2/s.
    if (e.removal_interval)
      e.depth_per_pass_interval = e.removal_interval->scaled(1.0 / (p.feed_m_per_s * 1e3 * p.wheel.width_m * 1e3));
  }
  if (p.empirical.wear) {
    const auto v = read(*p.empirical.wear, "wear");
    if (v) e.wear_rate_m3_per_s = *v * 1e-9;
    e.wear_interval = interval(*p.empirical.wear, v);
  }
  if (e.removal_rate_m3_per_s && e.wear_rate_m3_per_s && *e.wear_rate_m3_per_s > 0.0)
    e.g_ratio = *e.removal_rate_m3_per_s / *e.wear_rate_m3_per_s;
  else if (e.wear_rate_m3_per_s)
    warnings.push_back("grinding.models.wear: " + detail::num(*e.wear_rate_m3_per_s * 1e9) + " mm^3/s at " +
                       detail::num(power_w) + " W (not > 0): no G-ratio; the wear model does not hold here");
  if (e.g_ratio)
    if (const std::string w = detail::unusual_g_ratio(*e.g_ratio); !w.empty())
      warnings.push_back("G-ratio " + detail::num(*e.g_ratio) + " at " + detail::num(power_w) + " W (removal / wear "
                         "models): " + w);
  return e;
}

}  // namespace chatter::grinding
