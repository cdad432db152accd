// The repair plan of seed 000 §6.6 (include/chatter/grinding.hpp: plan_repair,
// compare_plan_objectives): a wheel worn from new to used up, at a fixed wheel
// speed or at the speed of the largest removal or G-ratio at every diameter;
// wheels, grinding time and wheel changes for a volume.
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

const char* plan_objective_name(PlanObjective o) {
  switch (o) {
    case PlanObjective::kFixedSpeed: return "fixed_speed";
    case PlanObjective::kRemoval: return "removal";
    case PlanObjective::kGRatio: return "g-ratio";
  }
  return "?";
}

PlanObjective plan_objective_from_name(const std::string& name, const std::string& what) {
  if (name == "removal") return PlanObjective::kRemoval;
  if (name == "g-ratio") return PlanObjective::kGRatio;
  throw InputError(what + " " + name + ": must be removal or g-ratio");
}

namespace {

void check_options(const Process& p, const PlanOptions& o) {
  if (!(std::isfinite(o.volume_m3) && o.volume_m3 > 0.0))
    throw InputError("volume_mm3 = " + detail::num(o.volume_m3 * 1e9) + ": must be > 0 mm^3");
  if (o.current_a && o.power_w != 0.0) throw InputError("give the power or the motor current, not both");
  if (!o.current_a && !(std::isfinite(o.power_w) && o.power_w > 0.0))
    throw InputError("power_w = " + detail::num(o.power_w) + ": must be > 0 W");
  if (o.current_a && !p.motor) throw InputError("a motor current needs the motor's map: [grinding.motor]");
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
  if (o.g_ratio == 0.0 && !p.empirical.wear)
    throw InputError("planning needs a wear rate: a [grinding.models.wear] model or a G-ratio (g_ratio)");
  if (o.objective == PlanObjective::kFixedSpeed) return;
  if (o.objective == PlanObjective::kGRatio && o.g_ratio > 0.0)
    throw InputError("the G-ratio objective needs the wear model: with a constant G-ratio every speed gives the same");
  if (!(std::isfinite(o.wheel_rpm_min) && o.wheel_rpm_min > 0.0 && std::isfinite(o.wheel_rpm_max) &&
        o.wheel_rpm_max > o.wheel_rpm_min))
    throw InputError("wheel speeds searched [" + detail::num(o.wheel_rpm_min) + ", " + detail::num(o.wheel_rpm_max) +
                     "] rev/min: need 0 < min < max");
  if (o.speed_points < 2 || o.speed_points > 100000)
    throw InputError("speed_points = " + std::to_string(o.speed_points) + ": must be in [2, 100000]");
}

// Whether the empirical models were tested at this point: every model with
// a tested cutting speed or power holds it (the diameter is not searched).
bool inside_tested(const EmpiricalModels& m, double vc, double power_w) {
  for (const auto* e : {&m.removal, &m.wear, &m.normal_force}) {
    if (!*e) continue;
    const TestedDomain& d = (*e)->domain;
    if (d.cutting_speed_m_per_s && !d.cutting_speed_m_per_s->contains(vc)) return false;
    if ((*e)->variable == EmpiricalVariable::kUsefulPower && d.useful_power_w && !d.useful_power_w->contains(power_w))
      return false;
  }
  return true;
}

// The rates at one diameter and wheel speed, or nullopt where the power
// from the motor current does not reach the wheel or a rate is not > 0.
struct Point {
  PlanStep step;
  Prediction prediction;
};
std::optional<Point> point_at(Process& q, const PlanOptions& o, double d, double rpm, bool throw_on_bad) {
  q.wheel.diameter_m = d;
  q.wheel.speed_rev_per_s = revolutions_per_s(rpm);
  Point pt;
  PlanStep& s = pt.step;
  s.diameter_m = d;
  s.wheel_rpm = rpm;
  s.cutting_speed_m_per_s = q.wheel.cutting_speed_m_per_s();
  if (o.current_a) {
    std::vector<std::string> notes;
    try {
      s.power_w = useful_power_from_current(q, *o.current_a, notes);
    } catch (const InputError&) {
      if (throw_on_bad) throw;
      return std::nullopt;
    }
  } else {
    s.power_w = o.power_w;
  }
  try {
    pt.prediction = predict_at_power(q, s.power_w);
  } catch (const InputError&) {
    if (throw_on_bad) throw;
    return std::nullopt;
  }
  s.removal_rate_m3_per_s = pt.prediction.removal_rate_m3_per_s;
  std::vector<std::string> ignored;
  s.wear_rate_m3_per_s = o.g_ratio == 0.0
                             ? predict_empirical(q, s.power_w, ignored).wear_rate_m3_per_s.value_or(0.0)
                             : s.removal_rate_m3_per_s / o.g_ratio;
  if (s.removal_rate_m3_per_s > 0.0 && s.wear_rate_m3_per_s > 0.0) return pt;
  if (throw_on_bad)
    throw InputError("planning: at wheel diameter " + detail::num(d * 1e3) + " mm and " + detail::num(s.power_w) +
                     " W the " + (s.removal_rate_m3_per_s > 0.0 ? "wear" : "removal") + " rate is " +
                     detail::num((s.removal_rate_m3_per_s > 0.0 ? s.wear_rate_m3_per_s : s.removal_rate_m3_per_s) * 1e9) +
                     " mm^3/s (not > 0): the model does not hold over the wheel's life");
  return std::nullopt;
}

// The point ground at diameter d: the process's speed, or the searched speed
// of the objective's largest value inside the tested domain.
Point choose(const Process& p, Process& q, const PlanOptions& o, double d) {
  if (o.objective == PlanObjective::kFixedSpeed)
    return *point_at(q, o, d, rpm_from_revolutions_per_s(p.wheel.speed_rev_per_s), true);
  std::optional<Point> best;
  double best_value = -1.0;
  for (int k = 0; k < o.speed_points; ++k) {
    const double rpm = o.wheel_rpm_min + (o.wheel_rpm_max - o.wheel_rpm_min) * k / (o.speed_points - 1);
    auto pt = point_at(q, o, d, rpm, false);
    if (!pt || !inside_tested(p.empirical, pt->step.cutting_speed_m_per_s, pt->step.power_w)) continue;
    const double g = pt->step.removal_rate_m3_per_s / pt->step.wear_rate_m3_per_s;
    if (o.objective == PlanObjective::kGRatio && !detail::unusual_g_ratio(g).empty()) continue;
    const double v = o.objective == PlanObjective::kRemoval ? pt->step.removal_rate_m3_per_s : g;
    if (v > best_value) best_value = v, best = std::move(pt);
  }
  if (!best)
    throw InputError("planning: at wheel diameter " + detail::num(d * 1e3) + " mm no wheel speed of " +
                     detail::num(o.wheel_rpm_min) + " to " + detail::num(o.wheel_rpm_max) +
                     " rev/min stays inside the models' tested cutting speed and power with removal and wear > 0" +
                     (o.objective == PlanObjective::kGRatio ? " and a G-ratio in 0.2 to 20" : "") +
                     ": widen the speeds, or plan at a fixed speed");
  return *best;
}

// One warning per model and variable outside its tested domain, with the
// diameters it spans (the text up to the value names both).
struct Outside {
  std::string key;
  double first_m, last_m;
  std::string last_text;
};
void note_outside(std::vector<Outside>& outside, const Prediction& pr, double d) {
  for (const std::string& w : pr.warnings) {
    if (w.find("outside the tested") == std::string::npos) continue;
    const std::string key = w.substr(0, w.find_first_of("0123456789-", w.find(": ")));
    auto it = std::find_if(outside.begin(), outside.end(), [&](const Outside& x) { return x.key == key; });
    if (it == outside.end()) {
      outside.push_back({key, d, d, w});
    } else {
      it->first_m = std::max(it->first_m, d);
      it->last_m = std::min(it->last_m, d);
      it->last_text = w;
    }
  }
}

}  // namespace

Plan plan_repair(const Process& p, const PlanOptions& o) {
  check_options(p, o);
  const double d0 = p.wheel.diameter_m, d1 = *p.min_wheel_diameter_m;
  Plan plan;
  plan.objective = o.objective;
  std::vector<Outside> outside;
  plan.usable_wheel_volume_m3 = std::numbers::pi / 4.0 * p.wheel.width_m * (d0 * d0 - d1 * d1);
  Process q = p;
  auto at = [&](double d) {
    Point pt = choose(p, q, o, d);
    note_outside(outside, pt.prediction, d);
    return pt.step;
  };
  // Midpoint rule in the diameter: each step wears the ring between two
  // diameters at the rates of the middle one.
  plan.life.push_back(at(d0));
  double removed = 0.0, time = 0.0;
  const int n = o.diameter_steps;
  for (int i = 0; i < n; ++i) {
    const double da = d0 - (d0 - d1) * i / n, db = d0 - (d0 - d1) * (i + 1) / n;
    const PlanStep mid = at(0.5 * (da + db));
    const double ring = std::numbers::pi / 4.0 * p.wheel.width_m * (da * da - db * db);
    const double dt = ring / mid.wear_rate_m3_per_s;
    time += dt;
    removed += mid.removal_rate_m3_per_s * dt;
    PlanStep end = at(db);
    end.removed_m3 = removed;
    end.time_s = time;
    plan.life.push_back(end);
  }
  for (const Outside& x : outside) {
    std::string where = x.last_text.substr(x.last_text.find(": ") + 2);
    where = where.substr(0, where.find(" (an extrapolation)"));
    plan.warnings.push_back(x.key + "outside its tested domain for wheel diameters from " + detail::num(x.first_m * 1e3) +
                            " to " + detail::num(x.last_m * 1e3) + " mm (an extrapolation; at " +
                            detail::num(x.last_m * 1e3) + " mm: " + where + ")");
  }
  plan.removal_per_wheel_m3 = removed;
  plan.wheel_life_s = time;
  plan.mean_g_ratio = removed / plan.usable_wheel_volume_m3;
  if (o.g_ratio == 0.0)
    if (const std::string w = detail::unusual_g_ratio(plan.mean_g_ratio); !w.empty())
      plan.warnings.push_back("mean G-ratio " + detail::num(plan.mean_g_ratio) + " over the wheel's life: " + w);
  plan.wheels = o.volume_m3 / removed;
  plan.wheels_needed = static_cast<int>(std::ceil(plan.wheels - 1e-9));
  plan.wheel_changes = std::max(0, plan.wheels_needed - 1);
  plan.grinding_time_s = plan.wheels * time;
  plan.total_time_s = plan.grinding_time_s + plan.wheel_changes * o.wheel_change_s;
  return plan;
}

PlanComparison compare_plan_objectives(const Process& p, const PlanOptions& options) {
  PlanOptions o = options;
  PlanComparison c;
  o.objective = PlanObjective::kRemoval;
  c.removal = plan_repair(p, o);
  o.objective = PlanObjective::kGRatio;
  c.g_ratio = plan_repair(p, o);
  c.wheels_saved = c.removal.wheels_needed - c.g_ratio.wheels_needed;
  c.time_saved_s = c.removal.total_time_s - c.g_ratio.total_time_s;
  return c;
}

}  // namespace chatter::grinding
