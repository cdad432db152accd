// [optimization] of the TOML config (docs/config.md, "Optimization";
// docs/optimization.md): the objective, the bounds of the set-point, the loss,
// the constraints and the index models of `chatter performance`, `optimize`
// and `adapt`. Every rule of OptimizationSpec::validate is checked here with
// its key and the value as written; plausibility warnings name the likely slip.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "config_sections.hpp"

namespace chatter::config_detail {

namespace {

// Hard bounds (errors): beyond them a value is a unit slip, not machining.
constexpr Plausible kCuttingSpeedBound{0.1, 20000.0, "must be in [0.1, 20000] m/min"};
constexpr Plausible kRpmBound{1.0, 1e6, "must be in [1, 1e6] rev/min"};
constexpr Plausible kFeedBound{1e-6, 0.1, "must be in [0.001, 100] mm"};
constexpr Plausible kDepthBound{1e-6, 1.0, "must be in [0.001, 1000] mm"};
// Usual bands (warnings).
constexpr UnitKey kKcKeys[] = {{"cutting_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
const Band kKcBand{3e8, 1e10, "K_c", "N/m^2", " the 300 to 10 000 N/mm^2 of metal cutting"};
constexpr UnitKey kTaylorNKeys[] = {{"taylor_n", 1.0, ""}};
const Band kTaylorNBand{0.05, 0.8, "n", "", " the 0.1 (HSS) to 0.7 (ceramics) of Taylor's exponent"};
constexpr UnitKey kNoseKeys[] = {{"nose_radius_mm", 1e-3, "mm"}};
const Band kNoseBand{0.05e-3, 5e-3, "r", "m", " the 0.05 to 5 mm of tool nose radii"};
constexpr UnitKey kGammaKeys[] = {{"gamma", 1.0, ""}};
const Band kGammaBand{0.8, 1.0, "gamma", "", " the 0.9 to 0.98 of inverse-model control (0.95 usual)"};

constexpr Range kPercent{"in [0, 100]", 0.0, false, 100.0, false};
constexpr Range kMargin{">= 1", 1.0, false, kInf, true};
constexpr Range kStepPercent{"in (0, 100]", 0.0, true, 100.0, false};
constexpr Range kAtLeastOne{">= 1", 1.0, false, kInf, true};

// A bound key: one number (fixed) or [lo, hi] with 0 < lo <= hi, in SI by `to_si`.
std::optional<Bounds> read_bounds(const Table& t, std::string_view key, double to_si, const Plausible& hard) {
  const auto v = t.number_list(key, kPositive);
  if (!v) return std::nullopt;
  const toml::node& n = *t.find(key);
  if (v->size() > 2 || v->empty()) {
    t.doc().error(t.path_of(key), n, "must be one number (fixed) or [lower, upper]");
    return std::nullopt;
  }
  Bounds b{v->front() * to_si, v->back() * to_si};
  if (b.hi < b.lo) {
    t.doc().error(t.path_of(key), n, "must be [lower, upper] with lower <= upper");
    return std::nullopt;
  }
  if (!t.plausible(key, b.lo, hard) || !t.plausible(key, b.hi, hard)) return std::nullopt;
  return b;
}

std::optional<bool> boolean(const Table& t, std::string_view key) {
  const toml::node* n = t.find(key);
  if (!n) return std::nullopt;
  if (const auto* b = n->as_boolean()) return b->get();
  t.doc().error(t.path_of(key), *n, "must be true or false");
  return std::nullopt;
}

LossSpec read_loss(const Table& opt, Operation op, Objective objective) {
  LossSpec s;
  s.critical.fill(std::numeric_limits<double>::quiet_NaN());
  const auto t = opt.table("loss");
  if (!t) {
    if (objective == Objective::kLoss)
      opt.doc().error_key(opt.path_of("loss"), "missing (required with objective \"loss\": critical_loss, "
                                               "weights_percent, critical)");
    return s;
  }
  constexpr std::string_view kKeys[] = {"critical_loss", "part_value", "previous_operations_cost", "operation_cost",
                                        "weights_percent", "critical"};
  t->reject_unknown(kKeys);
  const Document& doc = t->doc();
  const auto pc = t->number("critical_loss", kPositive);
  const auto part = t->number("part_value", kNonNegative);
  const auto before = t->number("previous_operations_cost", kNonNegative);
  const auto here = t->number("operation_cost", kNonNegative);
  const bool parts = t->has("part_value") || t->has("previous_operations_cost") || t->has("operation_cost");
  if (t->has("critical_loss") && parts)
    doc.error_key(t->path(), "give critical_loss or its parts (part_value, previous_operations_cost, "
                             "operation_cost), not both");
  else if (parts && !(t->has("part_value") && t->has("previous_operations_cost") && t->has("operation_cost")))
    doc.error_key(t->path(), "critical_loss from its parts needs all three: part_value, previous_operations_cost, "
                             "operation_cost");
  else if (!t->has("critical_loss") && !parts)
    doc.error_key(t->path_of("critical_loss"), "missing (required: the critical loss P_c per part, or its parts "
                                               "part_value, previous_operations_cost, operation_cost)");
  if (pc) s.critical_loss = *pc;
  if (parts && part && before && here) {
    s.critical_loss = *part + *before + *here;
    if (!(s.critical_loss > 0.0)) doc.error_key(t->path(), "the parts of the critical loss must sum to > 0");
  }
  // weights_percent and critical: one key per index of the loss.
  std::vector<std::string_view> names;
  for (std::size_t i = 0; i < kLossIndexCount; ++i) names.push_back(index_name(static_cast<PerformanceIndex>(i), op));
  auto per_index = [&](std::string_view key, const Range& range, std::array<double, kLossIndexCount>& out) {
    const auto sub = t->table(key);
    if (!sub) return false;
    sub->reject_unknown(names);
    for (std::size_t i = 0; i < kLossIndexCount; ++i)
      if (const auto v = sub->number(names[i], range)) out[i] = *v;
    return true;
  };
  std::array<double, kLossIndexCount> weights{};
  if (!per_index("weights_percent", kPercent, weights))
    doc.error_key(t->path_of("weights_percent"), "missing (required: the weight of each index in percent, summing "
                                                 "to 100: " + std::string(names[0]) + ", ...)");
  // An index left out of weights_percent weighs 0: said, not silent (issue 44).
  if (const auto w = t->table("weights_percent")) {
    std::string omitted;
    for (const std::string_view n : names)
      if (!w->has(n)) omitted += (omitted.empty() ? "" : ", ") + std::string(n);
    if (!omitted.empty())
      doc.warn_key(t->path_of("weights_percent"),
                   omitted + " not given: each weighs 0 % (the loss ignores it; write 0 to say so)");
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < kLossIndexCount; ++i) sum += weights[i], s.weight[i] = weights[i] / 100.0;
  if (t->has("weights_percent") && std::abs(sum - 100.0) > 1e-6)
    doc.error(t->path_of("weights_percent"), *t->find("weights_percent"),
              "must sum to 100 (they sum to " + number_text(sum) + ")");
  per_index("critical", kPositive, s.critical);
  for (std::size_t i = 0; i < kLossIndexCount; ++i)
    if (s.weight[i] > 0.0 && std::isnan(s.critical[i]))
      doc.error_key(child(t->path_of("critical"), names[i]),
                    std::string("missing (required: its weight is > 0; the ") +
                        (index_sense(static_cast<PerformanceIndex>(i)) == Sense::kSmallerIsBetter ? "largest"
                                                                                                  : "smallest") +
                        " acceptable value)");
  if (objective == Objective::kLoss && sum == 0.0 && t->has("weights_percent"))
    doc.error_key(t->path_of("weights_percent"), "all zero: the loss needs a weight > 0");
  return s;
}

ConstraintLimits read_constraints(const Table& opt, Operation op) {
  ConstraintLimits c;
  const auto t = opt.table("constraints");
  if (!t) return c;
  const bool milling = rotating_edges(op);
  const std::string_view dim = milling ? "max_surface_location_error_um" : "max_diametral_error_um";
  const std::string_view kKeys[] = {"max_force_n",       "max_power_kw", "max_torque_nm", dim,
                                    "max_roughness_um",  "min_removal_rate_mm3_per_s", "max_cost",
                                    "min_production_rate_per_h", "stability", "stability_margin"};
  t->reject_unknown(kKeys);
  c.max_force_n = t->number("max_force_n", kPositive);
  if (const auto p = t->number("max_power_kw", kPositive)) c.max_power_w = *p * 1e3;
  c.max_torque_n_m = t->number("max_torque_nm", kPositive);
  c.max_dimensional_error_um = t->number(dim, kPositive);
  c.max_roughness_um = t->number("max_roughness_um", kPositive);
  c.min_removal_rate_mm3_per_s = t->number("min_removal_rate_mm3_per_s", kPositive);
  c.max_cost = t->number("max_cost", kPositive);
  c.min_production_rate_per_h = t->number("min_production_rate_per_h", kPositive);
  if (const auto s = boolean(*t, "stability")) c.stability = *s;
  if (const auto m = t->number("stability_margin", kMargin)) c.stability_margin = *m;
  // Usual bands (docs/config.md, "Plausibility warnings"): a limit 1000 times
  // off is a unit slip (N for kN, um for mm), named rather than optimised.
  warn_usual(*t, "max_force_n", c.max_force_n, {10.0, 1e5, "the 10 N to 100 kN of cutting forces", 1e3, "kN"});
  warn_usual(*t, dim, c.max_dimensional_error_um, usual::kPartErrorUm);
  warn_usual(*t, "max_roughness_um", c.max_roughness_um, {0.05, 50.0, "the 0.05 to 50 um Ra of machined surfaces", 1e3, "mm"});
  warn_usual(*t, "min_removal_rate_mm3_per_s", c.min_removal_rate_mm3_per_s,
             {1.0, 1e5, "the 1 to 100 000 mm^3/s of removal rates", 1e3, "cm^3/s"});
  warn_usual(*t, "min_production_rate_per_h", c.min_production_rate_per_h,
             {0.1, 1e4, "the 0.1 to 10 000 parts per hour of one operation"});
  if (t->has("stability_margin"))
    warn_usual(*t, "stability_margin", c.stability_margin, usual::kSafetyFactor);
  if (!c.stability && t->has("stability_margin"))
    t->doc().error_key(t->path_of("stability_margin"), "not with stability = false (no stability constraint)");
  return c;
}

std::optional<RoughnessModel> read_roughness(const Table& opt) {
  const auto t = opt.table("roughness");
  if (!t) return std::nullopt;
  constexpr std::string_view kFit[] = {"constant",       "speed",         "feed",          "depth",
                                       "speed_squared",  "feed_squared",  "depth_squared", "speed_feed",
                                       "speed_depth",    "feed_depth"};
  constexpr std::string_view kKeys[] = {"model",         "nose_radius_mm", "constant",      "speed",
                                        "feed",          "depth",          "speed_squared", "feed_squared",
                                        "depth_squared", "speed_feed",     "speed_depth",   "feed_depth"};
  t->reject_unknown(kKeys);
  const Document& doc = t->doc();
  RoughnessModel r;
  const auto model = t->string("model", "must be \"geometric\" or \"fit\"");
  if (!model) {
    if (!t->has("model")) doc.error_key(t->path_of("model"), "missing (required: \"geometric\" or \"fit\")");
    throw Skip{};
  }
  if (*model == "geometric") {
    r.kind = RoughnessModel::Kind::kGeometric;
    const Given g = t->required_quantity(Quantity{kNoseKeys}, kPositive);
    for (const std::string_view k : kFit)
      if (t->has(k)) doc.error(t->path_of(k), *t->find(k), "only with model = \"fit\"");
    if (!g.si) throw Skip{};
    r.nose_radius_m = *g.si;
    warn_band(*t, g, Quantity{kNoseKeys}, kNoseBand);
  } else if (*model == "fit") {
    r.kind = RoughnessModel::Kind::kFit;
    if (t->has("nose_radius_mm"))
      doc.error(t->path_of("nose_radius_mm"), *t->find("nose_radius_mm"), "only with model = \"geometric\"");
    if (!t->has("constant")) doc.error_key(t->path_of("constant"), "missing (required with model = \"fit\", um)");
    double* slots[] = {&r.c0, &r.cv, &r.cf, &r.cd, &r.cvv, &r.cff, &r.cdd, &r.cvf, &r.cvd, &r.cfd};
    for (std::size_t i = 0; i < std::size(kFit); ++i)
      if (const auto v = t->number(kFit[i], kAnyNumber)) *slots[i] = *v;
  } else {
    doc.fail(t->path_of("model"), *t->find("model"), "must be \"geometric\" or \"fit\"");
  }
  return r;
}

std::optional<Economics> read_economics(const Table& opt) {
  const auto t = opt.table("economics");
  if (!t) return std::nullopt;
  constexpr std::string_view kKeys[] = {"taylor_c_m_per_min", "taylor_n",           "cut_length_mm",
                                        "setup_time_min",     "index_time_min",     "approach_time_min",
                                        "tool_change_time_min", "machine_rate_per_h", "tool_cost",
                                        "tool_uses",          "tooling_rate_per_h", "sharpening_time_min",
                                        "preset_time_min"};
  t->reject_unknown(kKeys);
  Economics e;
  const std::size_t mark = t->doc().error_count();
  const auto c = t->required_number("taylor_c_m_per_min", kPositive, "m/min");
  const Given n = t->required_quantity(Quantity{kTaylorNKeys}, kOpenUnit);
  const auto len = t->required_number("cut_length_mm", kPositive, "mm");
  double* optional_slots[] = {&e.setup_time_min,     &e.index_time_min, &e.approach_time_min,
                              &e.tool_change_time_min, &e.machine_rate_per_h, &e.tool_cost,
                              &e.tooling_rate_per_h, &e.sharpening_time_min, &e.preset_time_min};
  constexpr std::string_view kOptional[] = {"setup_time_min",     "index_time_min",     "approach_time_min",
                                            "tool_change_time_min", "machine_rate_per_h", "tool_cost",
                                            "tooling_rate_per_h", "sharpening_time_min", "preset_time_min"};
  for (std::size_t i = 0; i < std::size(kOptional); ++i)
    if (const auto v = t->number(kOptional[i], kNonNegative)) {
      *optional_slots[i] = *v;
      // The times of one part or one tool change: 0.3 s to an hour (money
      // has no band: any currency).
      if (kOptional[i].ends_with("_time_min") && *v > 0.0)
        warn_usual(*t, kOptional[i], v, {0.005, 60.0, "the 0.005 to 60 min of one part's or one tool's times", 1.0 / 60.0, "s"});
    }
  if (const auto u = t->number("tool_uses", kAtLeastOne)) e.tool_uses = *u;
  stop_if_errors_since(t->doc(), mark);
  if (!c || !n.si || !len) throw Skip{};
  e.taylor_c_m_per_min = *c;
  e.taylor_n = *n.si;
  e.cut_length_mm = *len;
  warn_band(*t, n, Quantity{kTaylorNKeys}, kTaylorNBand);
  warn_usual(*t, "taylor_c_m_per_min", c, {10.0, 5000.0, "the 10 to 5 000 m/min of Taylor constants", 60.0, "m/s"});
  warn_usual(*t, "cut_length_mm", len, {1.0, 1e4, "the 1 mm to 10 m of one cut's length", 1e3, "m"});
  return e;
}

// A fitted roughness model's coefficients carry the units of its variables
// (um per m/min, per mm, ...), so no band holds the coefficient itself; the
// size of its term over the optimisation's bounds can: a term under 0.01 um
// or over 50 um (the Ra of machined surfaces) is a coefficient in another
// unit. Also warned: a model that goes negative inside the bounds.
void warn_roughness_fit(const Table& opt, const OptimizationSpec& s) {
  if (!s.roughness || s.roughness->kind != RoughnessModel::Kind::kFit || !(s.diameter_m > 0.0)) return;
  const auto t = opt.table("roughness");
  const RoughnessModel& r = *s.roughness;
  const Bounds v{cutting_speed_m_per_min(s.diameter_m, s.speed_rpm.lo), cutting_speed_m_per_min(s.diameter_m, s.speed_rpm.hi)};
  const Bounds f{s.feed_m.lo * 1e3, s.feed_m.hi * 1e3}, d{s.depth_m.lo * 1e3, s.depth_m.hi * 1e3};
  const double V = v.hi, F = f.hi, D = d.hi;  // the largest |x| of each (bounds > 0)
  const std::pair<std::string_view, double> terms[] = {
      {"constant", r.c0},           {"speed", r.cv * V},          {"feed", r.cf * F},
      {"depth", r.cd * D},          {"speed_squared", r.cvv * V * V}, {"feed_squared", r.cff * F * F},
      {"depth_squared", r.cdd * D * D}, {"speed_feed", r.cvf * V * F}, {"speed_depth", r.cvd * V * D},
      {"feed_depth", r.cfd * F * D}};
  const std::string box = "V " + number_text(v.lo) + "-" + number_text(v.hi) + " m/min, f " + number_text(f.lo) + "-" +
                          number_text(f.hi) + " mm, d " + number_text(d.lo) + "-" + number_text(d.hi) + " mm";
  for (const auto& [key, term] : terms) {
    const double a = std::abs(term);
    if (!t->has(key) || a == 0.0 || (a >= 0.01 && a <= 50.0)) continue;
    t->doc().warn(t->path_of(key), *t->find(key),
                  "its term reaches " + number_text(a) + " um of Ra over the bounds (" + box + "), " +
                      (a < 0.01 ? "under 0.01 um" : "over the 50 um of machined surfaces") +
                      ": is the coefficient in another unit (um, mm, m/s)?");
  }
  double lowest = kInf;
  for (const double vv : {v.lo, v.hi})
    for (const double ff : {s.feed_m.lo, s.feed_m.hi})
      for (const double dd : {s.depth_m.lo, s.depth_m.hi}) lowest = std::min(lowest, r.roughness_um(vv, ff, dd));
  if (lowest < 0.0)
    t->doc().warn(t->path_of("model"), *t->find("model"),
                  "the fit gives Ra = " + number_text(lowest) + " um at a corner of the bounds (" + box +
                      "): negative, the model is used outside the tests it was fitted to");
}

Objective read_objective(const Table& t) {
  const auto s = t.string("objective", "must be \"loss\", \"removal_rate\", \"cost\" or \"production_rate\"");
  if (!s) return Objective::kLoss;
  for (const Objective o : {Objective::kLoss, Objective::kRemovalRate, Objective::kCost, Objective::kProductionRate})
    if (*s == objective_name(o)) return o;
  t.doc().error(t.path_of("objective"), *t.find("objective"),
                "must be \"loss\", \"removal_rate\", \"cost\" or \"production_rate\"");
  return Objective::kLoss;
}

// The speed bounds: as cutting speed (m/min, turned into rev/min at the
// diameter) or as spindle speed (rev/min), one of them.
void read_speed(const Table& t, OptimizationSpec& s) {
  const bool by_v = t.has("cutting_speed_m_per_min"), by_n = t.has("spindle_rpm");
  if (by_v && by_n)
    t.doc().error_key(t.path(), "give cutting_speed_m_per_min or spindle_rpm, not both");
  else if (!by_v && !by_n)
    t.doc().error_key(t.path_of("cutting_speed_m_per_min"),
                      "missing (required: the speed bounds [lower, upper] in m/min, or spindle_rpm in rev/min)");
  std::optional<Bounds> speed;
  if (by_v && !by_n) {
    speed = read_bounds(t, "cutting_speed_m_per_min", 1.0, kCuttingSpeedBound);
    if (speed && s.diameter_m > 0.0)
      s.speed_rpm = {spindle_rpm_of(s.diameter_m, speed->lo), spindle_rpm_of(s.diameter_m, speed->hi)};
  } else if (by_n && !by_v) {
    speed = read_bounds(t, "spindle_rpm", 1.0, kRpmBound);
    if (speed) s.speed_rpm = *speed;
    s.speed_as_cutting_speed = false;
  }
}

// [optimization.adapt]: the adaptive control's gain and largest step.
AdaptSettings read_adapt(const Table& a) {
  AdaptSettings adapt;
  constexpr std::string_view kAdaptKeys[] = {"gamma", "max_step_percent"};
  a.reject_unknown(kAdaptKeys);
  const Given g = a.quantity(Quantity{kGammaKeys}, kUnitInterval);
  if (g.si) adapt.gamma = *g.si;
  warn_band(a, g, Quantity{kGammaKeys}, kGammaBand);
  if (const auto m = a.number("max_step_percent", kStepPercent)) {
    adapt.max_step = *m / 100.0;
    warn_usual(a, "max_step_percent", m, {0.5, 100.0, "the 0.5 to 100 % of one adaptation step", 100.0,
                                          "fractions, not percent"});
  }
  return adapt;
}

}  // namespace

std::optional<OptimizationSpec> read_optimization(const Table& root, const Process& process) {
  const auto t = root.table("optimization");
  if (!t) return std::nullopt;
  const Document& doc = root.doc();
  const std::size_t mark = doc.error_count();
  const Operation op = process.operation();
  const bool milling = rotating_edges(op);
  const std::string_view feed_key = feed_record_key(op);
  const std::string_view wrong_feed = milling ? "feed_mm_per_rev" : "feed_per_tooth_mm";
  const std::string_view kKeys[] = {"objective", "cutting_speed_m_per_min", "spindle_rpm", feed_key, "depth_mm",
                                    "cutting_coefficient_n_per_mm2", "position_points", "loss", "constraints",
                                    "roughness", "economics", "adapt"};
  if (t->has(wrong_feed))
    doc.error(t->path_of(wrong_feed), *t->find(wrong_feed),
              milling ? "milling: give the feed per tooth (feed_per_tooth_mm)"
                      : "turning: give the feed per revolution (feed_mm_per_rev)");
  else
    t->reject_unknown(kKeys);

  OptimizationSpec s;
  s.objective = read_objective(*t);
  s.diameter_m = milling ? process.milling_parameters().tool_diameter_m
                         : process.turning_parameters().workpiece_diameter_m;
  if (!(s.diameter_m > 0.0))
    doc.error_key(t->path(), milling ? "needs the tool diameter for the cutting speed and removal rate: give "
                                       "process.tool_diameter_mm"
                                     : "needs the workpiece diameter for the cutting speed: give "
                                       "process.workpiece_diameter_mm");
  read_speed(*t, s);
  if (const auto f = read_bounds(*t, feed_key, 1e-3, kFeedBound)) s.feed_m = *f;
  else if (!t->has(feed_key))
    doc.error_key(t->path_of(feed_key), "missing (required: one number or [lower, upper], mm)");
  if (const auto d = read_bounds(*t, "depth_mm", 1e-3, kDepthBound)) {
    s.depth_m = *d;
    for (const double v : d->hi > d->lo ? std::vector{d->lo, d->hi} : std::vector{d->lo})
      warn_usual(*t, "depth_mm", v * 1e3, usual::kDepthOfCutMm);
  }
  else if (!t->has("depth_mm"))
    doc.error_key(t->path_of("depth_mm"), "missing (required: one number (fixed) or [lower, upper], mm)");
  if (milling && t->has("cutting_coefficient_n_per_mm2"))
    doc.error(t->path_of("cutting_coefficient_n_per_mm2"), *t->find("cutting_coefficient_n_per_mm2"),
              "turning only (milling takes K_t and K_r from [process])");
  if (process.has_size_effect() && t->has("cutting_coefficient_n_per_mm2"))
    doc.error(t->path_of("cutting_coefficient_n_per_mm2"), *t->find("cutting_coefficient_n_per_mm2"),
              "not with [process] force_law = \"kienzle\": its tangential term k_c1.1, m_c gives the cutting force "
              "at each feed (drop this key)");
  const Given kc = t->quantity(Quantity{kKcKeys}, kPositive);
  if (kc.si) s.cutting_coefficient_n_per_m2 = *kc.si;
  if (const auto n = t->integer("position_points", 2, 1000)) s.position_points = *n;

  attempt_void([&] { s.loss = read_loss(*t, op, s.objective); });
  attempt_void([&] { s.constraints = read_constraints(*t, op); });
  attempt_void([&] { s.roughness = read_roughness(*t); });
  attempt_void([&] { s.economics = read_economics(*t); });
  if (const auto a = t->table("adapt")) s.adapt = read_adapt(*a);
  // What the models need, named by the key that needs it.
  const auto weight = [&](PerformanceIndex i) { return s.loss.weight[static_cast<std::size_t>(i)] > 0.0; };
  if (!s.roughness && (weight(PerformanceIndex::kRoughness) || s.constraints.max_roughness_um))
    doc.error_key(t->path_of("roughness"), "missing (required by the roughness weight or max_roughness_um: model = "
                                           "\"geometric\" with nose_radius_mm, or \"fit\")");
  const bool money = weight(PerformanceIndex::kCost) || weight(PerformanceIndex::kProductionRate) ||
                     s.constraints.max_cost || s.constraints.min_production_rate_per_h ||
                     s.objective == Objective::kCost || s.objective == Objective::kProductionRate;
  if (money && !t->has("economics"))
    doc.error_key(t->path_of("economics"), "missing (required by the cost or production rate: weight, limit or "
                                           "objective; taylor_c_m_per_min, taylor_n, cut_length_mm, ...)");
  if (!milling && !process.has_size_effect() && !(s.cutting_coefficient_n_per_m2 > 0.0) &&
      !t->has("cutting_coefficient_n_per_mm2") &&
      (s.constraints.max_force_n || s.constraints.max_power_w || s.constraints.max_torque_n_m))
    doc.error_key(t->path_of("cutting_coefficient_n_per_mm2"),
                  "missing (required by max_force_n, max_power_kw or max_torque_nm in turning: the tangential "
                  "specific cutting force K_c, N/mm^2)");
  stop_if_errors_since(doc, mark);
  warn_band(*t, kc, Quantity{kKcKeys}, kKcBand);
  warn_roughness_fit(*t, s);
  if (const std::string why = s.validate(process); !why.empty()) doc.fail_key(t->path(), why);  // a rule above is missing
  return s;
}

}  // namespace chatter::config_detail
