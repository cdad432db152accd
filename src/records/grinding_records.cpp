// The JSON records of the grinding commands (include/chatter/records/grinding.hpp):
// `grind predict`, `fit`, `impacts`, `simulate`, `plan`, built once for the
// CLI, Python (converted by the one converter) and the C API. Shop units at
// the edge: mm, mm^3/s, N, W, J/mm^3, s, m/s, rev/min. Never a NaN: a
// quantity that is not known is null.
#include "chatter/records/grinding.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"  // version()
#include "chatter/kinematics.hpp"

namespace chatter {
namespace {

using nlohmann::json;
namespace g = grinding;

using nlohmann::json;
namespace g = grinding;

json num(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }
json opt(const std::optional<double>& x, double scale = 1.0) { return x ? num(*x * scale) : json(nullptr); }

// One prediction interval (docs/grinding.md, "Intervals"): the standard
// errors are of ln value for a power law (log_scale).
json interval_json(const g::PredictionInterval& i) {
  return {{"value", num(i.value)},
          {"standard_error_of_mean", num(i.standard_error_mean)},
          {"standard_error_of_one_test", num(i.standard_error_test)},
          {"confidence_95_of_mean", {num(i.mean_95.lo), num(i.mean_95.hi)}},
          {"prediction_95_of_one_test", {num(i.test_95.lo), num(i.test_95.hi)}},
          {"degrees_of_freedom", i.degrees_of_freedom},
          {"standard_errors_of_ln_value", i.log_scale}};
}


json header(const char* format) { return {{"format", format}, {"version", version()}}; }

json config_json(const GrindingConfig& c) {
  const g::Process& p = c.process;
  json j = {{"name", c.name},
            {"file", c.source.string()},
            {"wheel_diameter_mm", p.wheel.diameter_m * 1e3},
            {"wheel_width_mm", p.wheel.width_m * 1e3},
            {"wheel_rpm", rpm_from_revolutions_per_s(p.wheel.speed_rev_per_s)},
            {"feed_mm_per_s", p.feed_m_per_s * 1e3},
            {"force_ratio", p.force_ratio}};
  if (p.mechanistic) {
    j["edge_coefficient_n_per_mm"] = p.mechanistic->edge_coefficient_n_per_m * 1e-3;
    j["cutting_coefficient_n_per_mm2"] = p.mechanistic->cutting_coefficient_n_per_m2 * 1e-6;
  }
  return j;
}

json prediction_json(const g::Prediction& r) {
  json j;
  j["mode"] = r.mode;
  j["removal_source"] = r.removal_source;
  j["power_w"] = num(r.power_w);
  j["removal_rate_mm3_per_s"] = num(r.removal_rate_m3_per_s * 1e9);
  j["removal_rate_kg_per_h"] = opt(r.removal_rate_kg_per_h);
  j["max_depth_mm"] = num(r.max_depth_m * 1e3);
  j["groove_width_mm"] = num(r.groove_width_m * 1e3);
  j["depth_per_pass_mm"] = num(r.depth_per_pass_m * 1e3);
  j["tangential_force_n"] = num(r.tangential_force_n);
  j["normal_force_n"] = num(r.normal_force_n);
  j["friction_power_w"] = opt(r.friction_power_w);
  j["chip_power_w"] = opt(r.chip_power_w);
  j["specific_energy_j_per_mm3"] = num(r.specific_energy_j_per_m3 * 1e-9);
  if (r.energy_partition)
    j["energy_partition"] = {{"model", g::partition_model_name(r.energy_partition->model)},
                             {"fraction", num(r.energy_partition->fraction)},
                             {"heat_into_part_w", num(r.energy_partition->heat_into_part_w)},
                             {"clamped", r.energy_partition->clamped},
                             {"alpha", opt(r.energy_partition->alpha)},
                             {"beta", opt(r.energy_partition->beta)}};
  else
    j["energy_partition"] = nullptr;
  j["impacts_per_turn"] = opt(r.impacts_per_turn);
  j["contact_half_angle_deg"] = num(r.contact_half_angle_rad * 180.0 / std::numbers::pi);
  j["contact_duration_s"] = num(r.contact_duration_s);
  j["cutting_speed_m_per_s"] = num(r.cutting_speed_m_per_s);
  j["no_load_loss_w"] = opt(r.no_load_loss_w);
  j["motor_power_w"] = opt(r.motor_power_w);
  j["motor_current_a"] = opt(r.motor_current_a);
  if (r.empirical) {
    j["empirical"] = {{"removal_rate_mm3_per_s", opt(r.empirical->removal_rate_m3_per_s, 1e9)},
                      {"normal_force_n", opt(r.empirical->normal_force_n)},
                      {"wear_rate_mm3_per_s", opt(r.empirical->wear_rate_m3_per_s, 1e9)},
                      {"g_ratio", opt(r.empirical->g_ratio)}};
    // Intervals, where the config carries the fit's statistics.
    json iv = json::object();
    auto add = [&](const char* key, const std::optional<g::PredictionInterval>& i) {
      if (i) iv[key] = interval_json(*i);
    };
    add("removal_rate_mm3_per_s", r.empirical->removal_interval);
    add("depth_per_pass_mm", r.empirical->depth_per_pass_interval);
    add("wear_rate_mm3_per_s", r.empirical->wear_interval);
    add("normal_force_n", r.empirical->normal_force_interval);
    j["empirical"]["intervals"] = iv;
  }
  return j;
}

json stats_json(const g::FitStatistics& f, const std::vector<double>& to_config) {
  json c = json::object(), se = json::object(), ci = json::object(), lo = json::object(), hi = json::object();
  for (std::size_t i = 0; i < f.names.size(); ++i) {
    const double s = to_config.empty() ? 1.0 : to_config[i];
    c[f.names[i]] = num(f.coefficients[i] * s);
    se[f.names[i]] = num(f.standard_error[i] * s);
    ci[f.names[i]] = num(f.confidence_95[i] * s);
    lo[f.names[i]] = num(f.lower_95[i] * s);
    hi[f.names[i]] = num(f.upper_95[i] * s);
  }
  return {{"coefficients", c},  {"standard_error", se},         {"confidence_95", ci},
          {"lower_95", lo},     {"upper_95", hi},               {"tests", f.tests},
          {"degrees_of_freedom", f.degrees_of_freedom},         {"r_squared", num(f.r_squared)},
          {"rmse", num(f.rmse)}, {"mae", num(f.mae)},           {"mape_percent", num(f.mape_percent)},
          {"warnings", f.warnings}};
}

// The mechanistic coefficients in the config's units (N/mm, N/mm^2), and
// their names there.
const std::vector<double> kMechanisticToConfig{1e-3, 1e-6};
const std::vector<std::string> kMechanisticConfigNames{"edge_coefficient_n_per_mm", "cutting_coefficient_n_per_mm2"};

}  // namespace

json grinding_prediction_record(const g::Prediction& p, const GrindingConfig& config) {
  json j = header("chatter-grinding-prediction");
  j["config"] = config_json(config);
  j.update(prediction_json(p));
  json w = config.warnings;
  for (const std::string& s : p.warnings) w.push_back(s);
  j["warnings"] = w;
  return j;
}

json grinding_fit_record(const GrindingFitReport& r, const std::optional<std::string>& fragment) {
  json j = header("chatter-grinding-fit");
  j["tests_file"] = r.tests_file;
  j["model"] = r.model;
  if (!r.variable.empty()) j["variable"] = r.variable;
  json targets = json::object();
  for (const auto& t : r.targets) {
    json s = stats_json(t.fit, r.model == "mechanistic" ? kMechanisticToConfig : std::vector<double>{});
    if (r.model == "mechanistic") {
      // Name the coefficients as the config does.
      for (const char* k : {"coefficients", "standard_error", "confidence_95", "lower_95", "upper_95"}) {
        json renamed = json::object();
        for (std::size_t i = 0; i < t.fit.names.size(); ++i) renamed[kMechanisticConfigNames[i]] = s[k][t.fit.names[i]];
        s[k] = renamed;
      }
      s["unit"] = "W";
    } else {
      s["unit"] = t.name == "normal_force" ? "N" : "mm^3/s";
      s["form"] = r.model;
    }
    json res = json::array();
    for (std::size_t i = 0; i < t.rows.size(); ++i)
      res.push_back({{"line", r.tests[t.rows[i]].line},
                     {"measured", num(t.fit.fitted[i] + t.fit.residuals[i])},
                     {"fitted", num(t.fit.fitted[i])},
                     {"residual", num(t.fit.residuals[i])}});
    s["residuals"] = res;
    targets[t.name] = s;
  }
  j["fits"] = targets;
  json tests = json::array();
  for (const GrindingTest& t : r.tests)
    tests.push_back({{"line", t.line},
                     {"power_w", opt(t.power_w)},
                     {"removal_mm3_per_s", opt(t.removal_mm3_per_s)},
                     {"wear_mm3_per_s", opt(t.wear_mm3_per_s)},
                     {"normal_force_n", opt(t.normal_force_n)},
                     {"impacts_per_turn", opt(t.impacts_per_turn)},
                     {"cutting_speed_m_per_s", opt(t.cutting_speed_m_per_s)},
                     {"friction_coefficient", opt(t.friction_coefficient)},
                     {"g_ratio", opt(t.g_ratio)},
                     {"depth_per_pass_mm", opt(t.depth_per_pass_mm)},
                     {"specific_energy_j_per_mm3", opt(t.specific_energy_j_per_mm3)}});
  j["tests"] = tests;
  j["fragment"] = fragment ? json(*fragment) : json(nullptr);
  return j;
}

json grinding_impacts_record(const g::ImpactCount& c, const ImpactRecord& record, const std::string& file,
                                  double wheel_rpm) {
  json j = header("chatter-grinding-impacts");
  j["record_file"] = file;
  j["signal"] = record.column;
  j["wheel_rpm"] = wheel_rpm;
  j["threshold"] = num(c.threshold);
  j["turns"] = c.turns;
  j["impacts_per_turn"] = num(c.mean_per_turn);
  j["turns_without_contact"] = num(c.turns_without_contact);
  j["histogram"] = c.histogram;
  j["per_turn"] = c.per_turn;
  json peaks = json::array();
  for (std::size_t i = 0; i < c.peak_value.size(); ++i)
    peaks.push_back({{"time_s", num(c.peak_time_s[i])}, {"value", num(c.peak_value[i])}});
  j["peaks"] = peaks;
  j["peak_unit"] = record.kind == g::ImpactSignal::kNormalForce ? "N" : "rev/min below the median speed";
  return j;
}

json grinding_simulation_record(const g::DynamicsResult& r, const GrindingConfig& config) {
  json j = header("chatter-grinding-simulation");
  j["config"] = config_json(config);
  j["power_w"] = r.power_w;
  j["wheel_rpm"] = r.wheel_rpm;
  j["turns"] = r.turns;
  j["analysed_from_turn"] = r.analysed_from_turn;
  j["impacts_per_turn"] = num(r.impacts_per_turn);
  j["histogram"] = r.histogram;
  j["turns_without_contact"] = num(r.turns_without_contact);
  j["contact_fraction"] = num(r.contact_fraction);
  j["continuous"] = r.continuous;
  j["mean_normal_force_n"] = num(r.mean_normal_force_n);
  j["peak_normal_force_n"] = num(r.peak_normal_force_n);
  j["mean_contact_peak_n"] = num(r.mean_contact_peak_n);
  j["removal_rate_mm3_per_s"] = num(r.removal_rate_m3_per_s * 1e9);
  j["removal_at_simulated_impacts_mm3_per_s"] = opt(r.removal_at_simulated_impacts_m3_per_s, 1e9);
  j["mean_power_w"] = num(r.mean_power_w);
  j["contact_stiffness_n_per_m"] = num(r.contact_stiffness_n_per_m);
  j["robot_stiffness_n_per_m"] = num(r.robot_stiffness_n_per_m);
  j["quasi_static"] = prediction_json(r.quasi_static);
  j["integrator"] = {{"steps", r.steps}, {"rhs_evaluations", r.rhs_evaluations}, {"restarts", r.restarts}};
  json w = config.warnings;
  for (const std::string& s : r.quasi_static.warnings) w.push_back(s);
  j["warnings"] = w;
  return j;
}

namespace {

// One plan's numbers (shared by the plan record and each strategy of a comparison).
json plan_json(const g::Plan& p, const g::PlanOptions& o) {
  json j;
  j["objective"] = g::plan_objective_name(p.objective);
  j["usable_wheel_volume_mm3"] = num(p.usable_wheel_volume_m3 * 1e9);
  j["removal_per_wheel_mm3"] = num(p.removal_per_wheel_m3 * 1e9);
  j["mean_g_ratio"] = num(p.mean_g_ratio);
  j["wheel_life_s"] = num(p.wheel_life_s);
  j["wheels"] = num(p.wheels);
  j["wheels_needed"] = p.wheels_needed;
  j["wheel_changes"] = p.wheel_changes;
  j["wheel_change_s"] = o.wheel_change_s;
  j["grinding_time_s"] = num(p.grinding_time_s);
  j["total_time_s"] = num(p.total_time_s);
  if (!p.life.empty()) {
    const g::PlanStep &a = p.life.front(), &b = p.life.back();
    j["new_wheel"] = {{"diameter_mm", num(a.diameter_m * 1e3)}, {"wheel_rpm", num(a.wheel_rpm)},
                      {"cutting_speed_m_per_s", num(a.cutting_speed_m_per_s)}, {"power_w", num(a.power_w)}};
    j["used_wheel"] = {{"diameter_mm", num(b.diameter_m * 1e3)}, {"wheel_rpm", num(b.wheel_rpm)},
                       {"cutting_speed_m_per_s", num(b.cutting_speed_m_per_s)}, {"power_w", num(b.power_w)}};
  }
  return j;
}

json plan_header(const char* kind, const g::PlanOptions& o, const GrindingConfig& config) {
  json j = header(kind);
  j["config"] = config_json(config);
  j["volume_mm3"] = o.volume_m3 * 1e9;
  j["power_w"] = o.current_a ? json(nullptr) : json(o.power_w);
  j["current_a"] = opt(o.current_a);
  j["g_ratio_source"] = o.g_ratio > 0.0 ? "given" : "wear model";
  j["wheel_min_diameter_mm"] = opt(config.process.min_wheel_diameter_m, 1e3);
  return j;
}

}  // namespace

json grinding_plan_record(const g::Plan& p, const g::PlanOptions& o, const GrindingConfig& config) {
  json j = plan_header("chatter-grinding-plan", o, config);
  j.update(plan_json(p, o));
  json w = config.warnings;
  for (const std::string& s : p.warnings) w.push_back(s);
  j["warnings"] = w;
  return j;
}

json grinding_plan_comparison_record(const g::PlanComparison& c, const g::PlanOptions& o,
                                     const GrindingConfig& config) {
  json j = plan_header("chatter-grinding-plan-comparison", o, config);
  j["objective"] = g::plan_objective_name(o.objective);
  j["wheel_rpm_searched"] = {o.wheel_rpm_min, o.wheel_rpm_max};
  j["speed_points"] = o.speed_points;
  j["removal"] = plan_json(c.removal, o);
  j["g_ratio"] = plan_json(c.g_ratio, o);
  j["wheels_saved_by_g_ratio"] = c.wheels_saved;
  j["time_saved_by_g_ratio_s"] = num(c.time_saved_s);
  json w = config.warnings;
  for (const auto* p : {&c.removal, &c.g_ratio})
    for (const std::string& s : p->warnings)
      if (std::find(w.begin(), w.end(), s) == w.end()) w.push_back(s);
  j["warnings"] = w;
  return j;
}

GrindingPlanRun run_grinding_plan(const GrindingConfig& config, const g::PlanOptions& o) {
  GrindingPlanRun r;
  if (o.objective == g::PlanObjective::kFixedSpeed) {
    r.plan = g::plan_repair(config.process, o);
    r.record = grinding_plan_record(r.plan, o, config);
  } else {
    r.both = g::compare_plan_objectives(config.process, o);
    r.plan = o.objective == g::PlanObjective::kRemoval ? r.both->removal : r.both->g_ratio;
    r.record = grinding_plan_comparison_record(*r.both, o, config);
  }
  r.csv = grinding_plan_csv(r.plan);
  return r;
}

ColumnRecord grinding_sweep_columns(const std::vector<grinding::SweepCurve>& curves) {
  ColumnRecord out;
  out.columns = grinding_sweep_table(curves);
  return out;
}

ColumnRecord grinding_plan_columns(const GrindingPlanRun& run) {
  return {run.record, {}, {{"/wheel_life", grinding_plan_table(run.plan)}}};
}

ColumnRecord grinding_impacts_columns(const grinding::ImpactCount& c, const ImpactRecord& record,
                                      const std::string& file, double wheel_rpm) {
  return {grinding_impacts_record(c, record, file, wheel_rpm), {}, {{"/turns_table", grinding_impacts_table(c, record)}}};
}

ColumnRecord grinding_simulation_columns(const grinding::DynamicsResult& r, const GrindingConfig& config) {
  return {grinding_simulation_record(r, config), {}, {{"/series", grinding_series_table(r)}}};
}

}  // namespace chatter
