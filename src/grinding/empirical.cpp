// Seed 000's empirical models (include/chatter/grinding.hpp): forms, term
// order, evaluation, tested domain; and the repair plan of its §6.6.
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

std::string EmpiricalModel::validate() const {
  const std::size_t n = coefficient_count(form);
  if (coefficients.size() != n)
    return std::string(empirical_form_name(form)) + " needs " + std::to_string(n) + " coefficients, got " +
           std::to_string(coefficients.size());
  for (double c : coefficients)
    if (!std::isfinite(c)) return "coefficients must be finite numbers";
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
namespace {
constexpr double kUsualGRatio[2] = {0.2, 20.0};
std::string unusual_g_ratio(double g) {
  if (g >= kUsualGRatio[0] && g <= kUsualGRatio[1]) return "";
  return "outside the " + detail::num(kUsualGRatio[0]) + " to " + detail::num(kUsualGRatio[1]) +
         " of rough grinding with resin-bonded discs (seed 000 measured 1.9): the wear model is near zero here, "
         "its relative error large; give a measured G-ratio (grind plan --g-ratio)";
}
}  // namespace

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
    if (const std::string w = unusual_g_ratio(*e.g_ratio); !w.empty())
      warnings.push_back("G-ratio " + detail::num(*e.g_ratio) + " at " + detail::num(power_w) + " W (removal / wear "
                         "models): " + w);
  return e;
}

// ------------------------------------------------------------------ planning

Plan plan_repair(const Process& p, const PlanOptions& o) {
  if (!(std::isfinite(o.volume_m3) && o.volume_m3 > 0.0))
    throw InputError("volume_mm3 = " + detail::num(o.volume_m3 * 1e9) + ": must be > 0 mm^3");
  if (!(std::isfinite(o.power_w) && o.power_w > 0.0))
    throw InputError("power_w = " + detail::num(o.power_w) + ": must be > 0 W");
  if (!(std::isfinite(o.wheel_change_s) && o.wheel_change_s >= 0.0))
    throw InputError("wheel_change_min = " + detail::num(o.wheel_change_s / 60.0) + ": must be >= 0 min");
  if (!(std::isfinite(o.g_ratio) && o.g_ratio >= 0.0))
    throw InputError("g_ratio = " + detail::num(o.g_ratio) + ": must be > 0");
  if (o.diameter_steps < 10 || o.diameter_steps > 100000)
    throw InputError("diameter_steps = " + std::to_string(o.diameter_steps) + ": must be in [10, 100000]");
  if (!p.min_wheel_diameter_m)
    throw InputError("planning needs the used-up wheel diameter: grinding.wheel_min_diameter_mm");
  const double d0 = p.wheel.diameter_m, d1 = *p.min_wheel_diameter_m;
  if (!(d1 > 0.0 && d1 < d0))
    throw InputError("grinding.wheel_min_diameter_mm = " + detail::num(d1 * 1e3) +
                     ": must be > 0 and below the wheel diameter " + detail::num(d0 * 1e3) + " mm");
  const bool model_wear = o.g_ratio == 0.0;
  if (model_wear && !p.empirical.wear)
    throw InputError("planning needs a wear rate: a [grinding.models.wear] model or a G-ratio (g_ratio)");

  Plan plan;
  struct Outside {
    std::string key;
    double first_m, last_m;
    std::string last_text;
  };
  std::vector<Outside> outside;
  plan.usable_wheel_volume_m3 = std::numbers::pi / 4.0 * p.wheel.width_m * (d0 * d0 - d1 * d1);
  Process q = p;
  auto rates = [&](double d, PlanStep& s) {
    q.wheel.diameter_m = d;
    std::vector<std::string> ignored;
    const Prediction pr = predict_at_power(q, o.power_w);
    s.diameter_m = d;
    s.removal_rate_m3_per_s = pr.removal_rate_m3_per_s;
    s.wear_rate_m3_per_s = model_wear ? predict_empirical(q, o.power_w, ignored).wear_rate_m3_per_s.value_or(0.0)
                                      : s.removal_rate_m3_per_s / o.g_ratio;
    if (!(s.removal_rate_m3_per_s > 0.0 && s.wear_rate_m3_per_s > 0.0))
      throw InputError("planning: at wheel diameter " + detail::num(d * 1e3) + " mm and " + detail::num(o.power_w) +
                       " W the " + (s.removal_rate_m3_per_s > 0.0 ? "wear" : "removal") + " rate is " +
                       detail::num((s.removal_rate_m3_per_s > 0.0 ? s.wear_rate_m3_per_s : s.removal_rate_m3_per_s) *
                                   1e9) +
                       " mm^3/s (not > 0): the model does not hold over the wheel's life");
    // One warning per model and variable outside its tested domain, with
    // the diameters it spans (the text up to the value names both).
    for (const std::string& w : pr.warnings) {
      if (w.find("outside the tested") == std::string::npos) continue;
      const std::string key = w.substr(0, w.find_first_of("0123456789-", w.find(": ")));
      auto it = std::find_if(outside.begin(), outside.end(), [&](const Outside& x) { return x.key == key; });
      if (it == outside.end()) outside.push_back({key, d, d, w});
      else {
        it->first_m = std::max(it->first_m, d);
        it->last_m = std::min(it->last_m, d);
        it->last_text = w;
      }
    }
  };
  // Midpoint rule in the diameter: each step wears the ring between two
  // diameters at the rates of the middle one.
  PlanStep start;
  rates(d0, start);
  plan.life.push_back(start);
  double removed = 0.0, time = 0.0;
  const int n = o.diameter_steps;
  for (int i = 0; i < n; ++i) {
    const double da = d0 - (d0 - d1) * i / n, db = d0 - (d0 - d1) * (i + 1) / n;
    PlanStep mid;
    rates(0.5 * (da + db), mid);
    const double ring = std::numbers::pi / 4.0 * p.wheel.width_m * (da * da - db * db);
    const double dt = ring / mid.wear_rate_m3_per_s;
    time += dt;
    removed += mid.removal_rate_m3_per_s * dt;
    PlanStep end;
    rates(db, end);
    end.removed_m3 = removed;
    end.time_s = time;
    plan.life.push_back(end);
  }
  for (const Outside& x : outside) {
    std::string at = x.last_text.substr(x.last_text.find(": ") + 2);
    at = at.substr(0, at.find(" (an extrapolation)"));
    plan.warnings.push_back(x.key + "outside its tested domain for wheel diameters from " + detail::num(x.first_m * 1e3) +
                            " to " + detail::num(x.last_m * 1e3) + " mm (an extrapolation; at " +
                            detail::num(x.last_m * 1e3) + " mm: " + at + ")");
  }
  plan.removal_per_wheel_m3 = removed;
  plan.wheel_life_s = time;
  plan.mean_g_ratio = removed / plan.usable_wheel_volume_m3;
  if (model_wear)
    if (const std::string w = unusual_g_ratio(plan.mean_g_ratio); !w.empty())
      plan.warnings.push_back("mean G-ratio " + detail::num(plan.mean_g_ratio) + " over the wheel's life: " + w);
  plan.wheels = o.volume_m3 / removed;
  plan.wheels_needed = static_cast<int>(std::ceil(plan.wheels - 1e-9));
  plan.wheel_changes = std::max(0, plan.wheels_needed - 1);
  plan.grinding_time_s = plan.wheels * time;
  plan.total_time_s = plan.grinding_time_s + plan.wheel_changes * o.wheel_change_s;
  return plan;
}

}  // namespace chatter::grinding
