// The records of the grinding commands (include/chatter/io/grinding_io.hpp):
// JSON, CSV tables and the [grinding] fragment of a fit. Shop units at the
// edge: mm, mm^3/s, N, W, J/mm^3, s, m/s, rev/min. Never a NaN: a quantity
// that is not known is null.
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/kinematics.hpp"

namespace chatter {
namespace {

using nlohmann::json;
namespace g = grinding;

json num(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }
json opt(const std::optional<double>& x, double scale = 1.0) { return x ? num(*x * scale) : json(nullptr); }

std::string cell(double x) { return std::isfinite(x) ? table_number(x) : std::string(); }
std::string cell(const std::optional<double>& x, double scale = 1.0) { return x ? cell(*x * scale) : std::string(); }

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
                             {"clamped", r.energy_partition->clamped}};
  else
    j["energy_partition"] = nullptr;
  j["impacts_per_turn"] = opt(r.impacts_per_turn);
  j["contact_half_angle_deg"] = num(r.contact_half_angle_rad * 180.0 / std::numbers::pi);
  j["contact_duration_s"] = num(r.contact_duration_s);
  j["cutting_speed_m_per_s"] = num(r.cutting_speed_m_per_s);
  j["no_load_loss_w"] = opt(r.no_load_loss_w);
  j["motor_power_w"] = opt(r.motor_power_w);
  if (r.empirical)
    j["empirical"] = {{"removal_rate_mm3_per_s", opt(r.empirical->removal_rate_m3_per_s, 1e9)},
                      {"normal_force_n", opt(r.empirical->normal_force_n)},
                      {"wear_rate_mm3_per_s", opt(r.empirical->wear_rate_m3_per_s, 1e9)},
                      {"g_ratio", opt(r.empirical->g_ratio)}};
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

std::string grinding_prediction_json(const g::Prediction& p, const GrindingConfig& config) {
  json j = header("chatter-grinding-prediction");
  j["config"] = config_json(config);
  j.update(prediction_json(p));
  json w = config.warnings;
  for (const std::string& s : p.warnings) w.push_back(s);
  j["warnings"] = w;
  return j.dump(2) + "\n";
}

std::string grinding_fit_json(const GrindingFitReport& r) {
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
  return j.dump(2) + "\n";
}

std::string grinding_fit_fragment(const GrindingFitReport& r, std::optional<double> force_ratio) {
  if (r.tests.empty() || r.targets.empty()) throw InputError("--out: nothing was fitted");
  const GrindingTest& t0 = r.tests.front();
  if (!(t0.wheel_diameter_mm && t0.wheel_width_mm && t0.wheel_rpm && t0.feed_mm_per_s))
    throw InputError("--out: a [grinding] table needs the wheel and feed: give the columns wheel_diameter_mm, "
                     "wheel_width_mm, wheel_rpm, feed_mm_per_s (or the options)");
  if (!force_ratio) {
    double sum = 0.0;
    int n = 0;
    for (const GrindingTest& t : r.tests)
      if (t.friction_coefficient) {
        sum += *t.friction_coefficient;
        ++n;
      }
    if (n > 0) force_ratio = sum / n;
  }
  if (!force_ratio)
    throw InputError("--out: the force ratio F_T/F_N is not in the tests (no normal_force_n column): give --force-ratio");
  std::ostringstream o;
  o << "# Fitted by `chatter grind fit --model " << r.model << "` (chatter " << version() << ") from "
    << r.tests_file << ".\n# The wheel and feed are the first test's; force_ratio "
    << (t0.friction_coefficient ? "is the tests' mean P / (V_c F_N)" : "as given") << ".\n"
    << "[grinding]\nwheel_diameter_mm = " << table_number(*t0.wheel_diameter_mm)
    << "\nwheel_width_mm = " << table_number(*t0.wheel_width_mm) << "\nwheel_rpm = " << table_number(*t0.wheel_rpm)
    << "\nfeed_mm_per_s = " << table_number(*t0.feed_mm_per_s) << "\nforce_ratio = " << table_number(*force_ratio)
    << "\n";
  if (r.model == "mechanistic") {
    const g::FitStatistics& f = r.targets.front().fit;
    if (!(f.coefficients[1] > 0.0) || f.coefficients[0] < 0.0)
      throw InputError("--out: the fitted coefficients (k_e = " + table_number(f.coefficients[0] * 1e-3) +
                       " N/mm, k_c = " + table_number(f.coefficients[1] * 1e-6) +
                       " N/mm^2) are not a valid [grinding] model (k_e >= 0, k_c > 0): check the tests");
    o << "edge_coefficient_n_per_mm = " << table_number(f.coefficients[0] * 1e-3) << "   # +- "
      << table_number(f.confidence_95[0] * 1e-3) << " (95 %)\n"
      << "cutting_coefficient_n_per_mm2 = " << table_number(f.coefficients[1] * 1e-6) << "   # +- "
      << table_number(f.confidence_95[1] * 1e-6) << " (95 %)\n";
    // n_c: one value, or the mean per power as a table.
    std::map<double, std::pair<double, int>> by_power;
    for (std::size_t i : r.targets.front().rows) {
      const GrindingTest& t = r.tests[i];
      auto& e = by_power[*t.power_w];
      e.first += *t.impacts_per_turn;
      ++e.second;
    }
    double first = by_power.begin()->second.first / by_power.begin()->second.second;
    bool constant = true;
    for (const auto& [p, e] : by_power) constant = constant && std::abs(e.first / e.second - first) <= 1e-12 * first;
    if (constant) {
      o << "impacts_per_turn = " << table_number(first) << "\n";
    } else {
      for (const auto& [p, e] : by_power)
        o << "\n[[grinding.impacts]]\npower_w = " << table_number(p)
          << "\nimpacts_per_turn = " << table_number(e.first / e.second) << "\n";
    }
    return o.str();
  }
  for (const auto& t : r.targets) {
    const g::FitStatistics& f = t.fit;
    if (r.model == "power_law" && !(f.coefficients[0] > 0.0))
      throw InputError("--out: the power law's constant C = " + table_number(f.coefficients[0]) + " is not > 0");
    o << "\n[grinding.models." << t.name << "]   # R^2 = " << table_number(f.r_squared) << ", RMSE = "
      << table_number(f.rmse) << (t.name == "normal_force" ? " N" : " mm^3/s") << "\nform = \"" << r.model
      << "\"\ncoefficients = [";
    for (std::size_t i = 0; i < f.coefficients.size(); ++i) o << (i ? ", " : "") << table_number(f.coefficients[i]);
    o << "]   # " << (f.names.empty() ? "" : f.names.front());
    for (std::size_t i = 1; i < f.names.size(); ++i) o << ", " << f.names[i];
    const bool force = r.variable == "normal_force_n";
    o << "\nvariables = [\"cutting_speed_m_per_s\", \"" << (force ? "normal_force_n" : "useful_power_w") << "\"]\n";
    // The tested domain: the tests' range of each variable.
    auto range = [&](auto get) {
      double lo = INFINITY, hi = -INFINITY;
      for (std::size_t i : t.rows)
        if (const auto v = get(r.tests[i])) {
          lo = std::min(lo, *v);
          hi = std::max(hi, *v);
        }
      return std::pair<double, double>{lo, hi};
    };
    o << "[grinding.models." << t.name << ".domain]   # the tests' range\n";
    auto line = [&](const char* key, std::pair<double, double> lh) {
      if (lh.first < lh.second) o << key << " = [" << table_number(lh.first) << ", " << table_number(lh.second) << "]\n";
    };
    line("cutting_speed_m_per_s", range([](const GrindingTest& x) { return x.cutting_speed_m_per_s; }));
    if (force) line("normal_force_n", range([](const GrindingTest& x) { return x.normal_force_n; }));
    else line("useful_power_w", range([](const GrindingTest& x) { return x.power_w; }));
    line("wheel_diameter_mm", range([](const GrindingTest& x) { return x.wheel_diameter_mm; }));
  }
  return o.str();
}

std::string grinding_impacts_json(const g::ImpactCount& c, const ImpactRecord& record, const std::string& file,
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
  return j.dump(2) + "\n";
}

std::string grinding_simulation_json(const g::DynamicsResult& r, const GrindingConfig& config) {
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
  return j.dump(2) + "\n";
}

std::string grinding_plan_json(const g::Plan& p, const g::PlanOptions& o, const GrindingConfig& config) {
  json j = header("chatter-grinding-plan");
  j["config"] = config_json(config);
  j["volume_mm3"] = o.volume_m3 * 1e9;
  j["power_w"] = o.power_w;
  j["g_ratio_source"] = o.g_ratio > 0.0 ? "given" : "wear model";
  j["wheel_min_diameter_mm"] = opt(config.process.min_wheel_diameter_m, 1e3);
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
  json w = config.warnings;
  for (const std::string& s : p.warnings) w.push_back(s);
  j["warnings"] = w;
  return j.dump(2) + "\n";
}

std::string grinding_sweep_csv(const std::vector<g::SweepCurve>& curves) {
  std::ostringstream o;
  const bool mech = !curves.empty() && !curves.front().points.empty() && curves.front().points.front().friction_power_w;
  const bool emp = !curves.empty() && !curves.front().points.empty() && curves.front().points.front().empirical;
  o << "feed_mm_per_s,power_w,removal_rate_mm3_per_s,max_depth_mm,groove_width_mm,depth_per_pass_mm,"
       "tangential_force_n,normal_force_n,specific_energy_j_per_mm3";
  if (mech) o << ",friction_power_w,chip_power_w,impacts_per_turn";
  o << ",energy_partition,heat_into_part_w";
  if (emp) o << ",empirical_removal_rate_mm3_per_s,empirical_normal_force_n,empirical_wear_rate_mm3_per_s";
  o << "\n";
  for (const auto& c : curves)
    for (const g::Prediction& p : c.points) {
      o << cell(c.feed_m_per_s * 1e3) << ',' << cell(p.power_w) << ',' << cell(p.removal_rate_m3_per_s * 1e9) << ','
        << cell(p.max_depth_m * 1e3) << ',' << cell(p.groove_width_m * 1e3) << ',' << cell(p.depth_per_pass_m * 1e3)
        << ',' << cell(p.tangential_force_n) << ',' << cell(p.normal_force_n) << ','
        << cell(p.specific_energy_j_per_m3 * 1e-9);
      if (mech) o << ',' << cell(p.friction_power_w) << ',' << cell(p.chip_power_w) << ',' << cell(p.impacts_per_turn);
      o << ',' << (p.energy_partition ? cell(p.energy_partition->fraction) : "") << ','
        << (p.energy_partition ? cell(p.energy_partition->heat_into_part_w) : "");
      if (emp)
        o << ',' << cell(p.empirical->removal_rate_m3_per_s, 1e9) << ',' << cell(p.empirical->normal_force_n) << ','
          << cell(p.empirical->wear_rate_m3_per_s, 1e9);
      o << "\n";
    }
  return o.str();
}

std::string grinding_series_csv(const g::DynamicsResult& r) {
  std::ostringstream o;
  o << "time_s,depth_mm,surface_mm,contact_force_n,push_n\n";
  for (const auto& s : r.series)
    o << cell(s.time_s) << ',' << cell(s.depth_m * 1e3) << ',' << cell(s.surface_m * 1e3) << ','
      << cell(s.contact_force_n) << ',' << cell(s.push_n) << "\n";
  return o.str();
}

std::string grinding_impacts_csv(const g::ImpactCount& c, const ImpactRecord& record) {
  std::ostringstream o;
  o << "turn,impacts,first_peak_time_s,largest_peak_" << (record.kind == g::ImpactSignal::kNormalForce ? "n" : "rpm_drop")
    << "\n";
  std::size_t k = 0;  // peaks are in time order, as the turns
  for (std::size_t i = 0; i < c.per_turn.size(); ++i) {
    double first = NAN, largest = NAN;
    for (int n = 0; n < c.per_turn[i] && k < c.peak_value.size(); ++n, ++k) {
      if (n == 0) first = c.peak_time_s[k];
      largest = std::isnan(largest) ? c.peak_value[k] : std::max(largest, c.peak_value[k]);
    }
    o << i << ',' << c.per_turn[i] << ',' << cell(first) << ',' << cell(largest) << "\n";
  }
  return o.str();
}

std::string grinding_plan_csv(const g::Plan& p) {
  std::ostringstream o;
  o << "wheel_diameter_mm,removal_rate_mm3_per_s,wear_rate_mm3_per_s,g_ratio,removed_mm3,time_s\n";
  for (const auto& s : p.life)
    o << cell(s.diameter_m * 1e3) << ',' << cell(s.removal_rate_m3_per_s * 1e9) << ','
      << cell(s.wear_rate_m3_per_s * 1e9) << ',' << cell(s.removal_rate_m3_per_s / s.wear_rate_m3_per_s) << ','
      << cell(s.removed_m3 * 1e9) << ',' << cell(s.time_s) << "\n";
  return o.str();
}

}  // namespace chatter
