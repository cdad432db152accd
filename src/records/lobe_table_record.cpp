// The lobe table's JSON record and the uncertainty block of `lobes
// --samples` (include/chatter/records/lobes.hpp): the contract CAM
// integrators parse, built once here; the CSV is io's (write_lobe_csv).
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/records/lobes.hpp"
#include "chatter/uncertainty.hpp"

namespace chatter {
namespace {

nlohmann::json json_num(double x) {
  if (!std::isfinite(x)) return nullptr;
  return std::stod(table_number(x));  // same rounding as the CSV
}

nlohmann::json body_json(const Body& b) {
  nlohmann::json modes = nlohmann::json::array();
  for (const Mode& m : b.modes)
    modes.push_back({{"frequency_hz", m.natural_frequency_hz},
                     {"damping_ratio", m.damping_ratio},
                     {"stiffness_n_per_m", m.stiffness_n_per_m},
                     {"mass_kg", m.mass_kg()},
                     {"direction", {m.direction.x(), m.direction.y()}}});
  return {{"modes", modes}};
}

nlohmann::json model_process_json(const Process& p) {
  if (!p.rotating_edges()) {
    const TurningParameters& t = p.turning_parameters();
    nlohmann::json j = {{"operation", "turning"}, {"feed_force_coefficient_n_per_m2", t.feed_force_coefficient_n_per_m2}};
    if (p.has_process_damping()) {
      j["process_damping_coefficient_n_per_m"] = t.process_damping_coefficient_n_per_m;
      j["workpiece_diameter_mm"] = t.workpiece_diameter_m * 1e3;
    }
    if (!p.orthogonal_turning()) {  // the insert (docs/turning_inserts.md)
      j["radial_force_coefficient_n_per_m2"] = t.radial_force_coefficient_n_per_m2;
      j["lead_angle_deg"] = t.lead_angle_rad * 180.0 / std::numbers::pi;
      j["nose_radius_mm"] = t.nose_radius_m * 1e3;
    }
    return j;
  }
  const MillingParameters& m = p.milling_parameters();
  nlohmann::json j = {{"operation", "milling"},
                      {"teeth", m.teeth},
                      {"tangential_coefficient_n_per_m2", m.tangential_coefficient_n_per_m2},
                      {"radial_coefficient_n_per_m2", m.radial_coefficient_n_per_m2},
                      {"radial_immersion", m.radial_immersion},
                      {"milling_direction", m.direction == MillingDirection::kDown ? "down" : "up"}};
  // The cutter (docs/physics.md §8), only what was given: a straight,
  // equally spaced, true-running cutter writes the same JSON as before.
  constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
  if (m.tool_diameter_m > 0.0) j["tool_diameter_mm"] = m.tool_diameter_m * 1e3;
  if (p.has_helix()) {
    std::vector<double> deg;
    for (int t = 0; t < m.teeth; ++t) deg.push_back(p.helix_angle_rad(t) * kRadToDeg);
    j["helix_angle_deg"] = deg;
  }
  if (!m.pitch_angles_rad.empty()) {
    std::vector<double> deg;
    for (int t = 0; t < m.teeth; ++t) deg.push_back(p.pitch_angle_rad(t) * kRadToDeg);
    j["pitch_angles_deg"] = deg;
  }
  if (p.has_runout()) {
    std::vector<double> um;
    for (int t = 0; t < m.teeth; ++t) um.push_back(p.runout_m(t) * 1e6);
    j["runout_um"] = um;
  }
  if (p.has_process_damping()) j["process_damping_coefficient_n_per_m"] = m.process_damping_coefficient_n_per_m;
  return j;
}

nlohmann::json given_json(const SolverValue& v) {
  return std::visit(
      [](const auto& x) -> nlohmann::json {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, std::monostate>) return nullptr;
        else return nlohmann::json(x);
      },
      v);
}

// The process of the model (SI keys), with every key of the config's
// [process] table as written on top (docs/results.md: "Inputs echoed"): the
// cutter keys in their own units (degrees, um, mm) exactly as given.
nlohmann::json process_json(const Process& p, const std::vector<std::pair<std::string, SolverValue>>& given) {
  nlohmann::json j = model_process_json(p);
  for (const auto& [key, value] : given) j[key] = given_json(value);
  return j;
}

}  // namespace

nlohmann::json lobe_table_record(const std::vector<StabilityLimit>& rows, const TableProvenance& p,
                                 const std::vector<ExtraColumn>& extra) {
  nlohmann::json j;
  j["format"] = "chatter-lobe-table";
  j["version"] = version();
  j["method"] = p.method;
  if (p.config) {
    j["config"] = {{"file", p.config->source.string()},
                   {"name", p.config->name},
                   {"process", process_json(p.config->process, p.config->process_given)},
                   {"tool", body_json(p.config->model.tool)},
                   {"workpiece", body_json(p.config->model.workpiece)}};
  }
  j["warnings"] = p.config ? p.config->warnings : std::vector<std::string>{};
  j["notes"] = p.notes;
  if (p.position_mm) j["position_mm"] = *p.position_mm;
  j["sweep"] = {{"rpm_min", p.rpm_min}, {"rpm_max", p.rpm_max}, {"rpm_points", p.rpm_points},
                {"depth_max_mm", p.depth_max_mm}, {"rpm_spacing", p.rpm_spacing}};
  if (p.rpm_spacing == "adaptive") {
    j["sweep"]["depth_rel_tol"] = p.adaptive_depth_rel_tol;
    j["sweep"]["tolerance_met"] = p.adaptive_tolerance_met;
  }
  j["options"] = p.options.is_null() ? nlohmann::json::object() : p.options;
  if (p.absolute_limit) {
    j["absolute_limit"] = {{"depth_mm", json_num(p.absolute_limit->depth_m * 1e3)},
                           {"chatter_frequency_hz", json_num(p.absolute_limit->chatter_frequency_hz)}};
  }
  j["units"] = {{"spindle_rpm", "rev/min"}, {"depth_limit_mm", "mm"}, {"chatter_frequency_hz", "Hz"}};
  j["null_means"] = "no instability below depth_max_mm at this speed";
  nlohmann::json arr = nlohmann::json::array();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const StabilityLimit& r = rows[i];
    nlohmann::json row = {{"spindle_rpm", json_num(r.spindle_rpm)},
                          {"depth_limit_mm", json_num(r.depth_limit_m * 1e3)},
                          {"chatter_frequency_hz", json_num(r.chatter_frequency_hz)},
                          {"lobe", r.bounded() ? nlohmann::json(r.lobe) : nlohmann::json(nullptr)}};
    for (const ExtraColumn& c : extra) {
      const std::string& v = c.values.at(i);
      if (!c.numeric) row[c.name] = v;
      else if (v.empty() || v == "inf") row[c.name] = nullptr;
      else row[c.name] = std::stod(v);
    }
    arr.push_back(std::move(row));
  }
  j["rows"] = std::move(arr);
  return j;
}

nlohmann::json uncertainty_record(const UncertaintySpreads& s, bool milling, const UncertaintyRecordInputs& in) {
  auto percents = [](const std::vector<double>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (const double x : v) a.push_back(100.0 * x);
    return a;
  };
  nlohmann::json spreads = {{"frequency_percent", percents(s.frequency)},
                            {"damping_percent", percents(s.damping)},
                            {"stiffness_percent", percents(s.stiffness)}};
  if (milling) {
    spreads["tangential_coefficient_percent"] = 100.0 * s.tangential;
    spreads["radial_coefficient_percent"] = 100.0 * s.radial;
  } else {
    spreads["feed_force_coefficient_percent"] = 100.0 * s.tangential;
  }
  return {{"samples", in.samples},
          {"seed", in.seed},
          {"spreads", spreads},
          {"mode_order", "tool modes, then workpiece modes (one value: every mode)"},
          {"distribution", "p (1 + s z), z standard normal truncated to |z| <= 3, every parameter independent"},
          {"rng", "SplitMix64 hash of (seed, sample, parameter), inverse-CDF truncated normal"},
          {"quantile_definition", "linear interpolation between order statistics (Hyndman-Fan type 7); null = inf"},
          {"quantile_columns", {"depth_limit_p05_mm", "depth_limit_p50_mm", "depth_limit_p95_mm"}},
          {"probability_depth_max_mm", in.depth_grid_top_mm},
          {"probability_depth_points", in.depth_points},
          {"summary", in.summary}};
}

// ------------------------------------------- the lobe tables as columns (Python)

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// spindle_rpm, depth_limit_mm, chatter_frequency_hz, lobe of `rows`,
// appended to the columns already there (in the same order).
void add_limit_columns(const std::vector<StabilityLimit>& rows, std::vector<double>& rpm, std::vector<double>& depth,
                       std::vector<double>& freq, std::vector<int>& lobe) {
  for (const StabilityLimit& r : rows) {
    rpm.push_back(r.spindle_rpm);
    depth.push_back(r.depth_limit_m * 1e3);  // +inf where unbounded, as the CSV
    freq.push_back(r.bounded() ? r.chatter_frequency_hz : kNaN);
    lobe.push_back(r.bounded() ? r.lobe : -1);
  }
}

// One diagnostic column over every row: numbers (NaN where none) or text.
Column diagnostic_column(const DiagnosticColumn& d, std::size_t c, const std::vector<std::vector<SolverValue>>& values) {
  auto value_of = [&](const std::vector<SolverValue>& row) { return c < row.size() ? row[c] : SolverValue{}; };
  if (d.numeric) {
    std::vector<double> col;
    for (const auto& row : values) {
      const SolverValue v = value_of(row);
      if (const auto* x = std::get_if<double>(&v)) col.push_back(*x);
      else if (const auto* i = std::get_if<int>(&v)) col.push_back(*i);
      else col.push_back(kNaN);
    }
    return {d.name, std::move(col)};
  }
  std::vector<std::string> col;
  for (const auto& row : values) {
    const SolverValue v = value_of(row);
    if (const auto* t = std::get_if<std::string>(&v)) col.push_back(*t);
    else if (const auto* b = std::get_if<bool>(&v)) col.push_back(*b ? "true" : "false");
    else col.emplace_back();
  }
  return {d.name, std::move(col)};
}

}  // namespace

nlohmann::json lobe_columns_fields(const LobeColumnsSource& source) {
  return {{"method", source.method},
          {"name", source.config ? source.config->name : std::string()},
          {"warnings", source.config ? source.config->warnings : std::vector<std::string>{}},
          {"notes", source.notes},
          {"depth_max_mm", source.depth_max_mm}};
}

ColumnRecord lobe_columns(const std::vector<StabilityLimit>& rows, const std::vector<DiagnosticColumn>& diagnostics,
                          const std::vector<std::vector<SolverValue>>& values, const LobeColumnsSource& source) {
  std::vector<double> rpm, depth, freq;
  std::vector<int> lobe;
  add_limit_columns(rows, rpm, depth, freq, lobe);
  ColumnRecord out;
  out.fields = lobe_columns_fields(source);
  out.columns = {{"spindle_rpm", std::move(rpm)},
                 {"depth_limit_mm", std::move(depth)},
                 {"chatter_frequency_hz", std::move(freq)},
                 {"lobe", std::move(lobe)}};
  if (!values.empty())
    for (std::size_t c = 0; c < diagnostics.size(); ++c) out.columns.push_back(diagnostic_column(diagnostics[c], c, values));
  return out;
}

ColumnRecord surface_columns(const std::vector<double>& positions_mm,
                             const std::vector<std::vector<StabilityLimit>>& rows, const LobeColumnsSource& source) {
  std::vector<double> x, rpm, depth, freq;
  std::vector<int> lobe;
  for (std::size_t p = 0; p < rows.size(); ++p) {
    x.insert(x.end(), rows[p].size(), positions_mm.at(p));
    add_limit_columns(rows[p], rpm, depth, freq, lobe);
  }
  ColumnRecord out;
  out.fields = lobe_columns_fields(source);
  out.columns = {{"position_mm", std::move(x)},
                 {"spindle_rpm", std::move(rpm)},
                 {"depth_limit_mm", std::move(depth)},
                 {"chatter_frequency_hz", std::move(freq)},
                 {"lobe", std::move(lobe)}};
  return out;
}

ColumnRecord uncertain_lobe_columns(const std::vector<StabilityLimit>& nominal, const UncertainLobes& mc,
                                    const LobeColumnsSource& source, long long samples, long long seed,
                                    std::optional<double> position_mm) {
  ColumnRecord out;
  out.fields = {{"method", source.method},
                {"warnings", source.config ? source.config->warnings : std::vector<std::string>{}},
                {"notes", source.notes},
                {"samples", samples},
                {"seed", seed}};
  if (position_mm) out.fields["position_mm"] = *position_mm;
  std::vector<double> rpm, depth;
  for (const StabilityLimit& r : nominal) {
    rpm.push_back(r.spindle_rpm);
    depth.push_back(r.depth_limit_m * 1e3);  // +inf where unbounded, as lobes()
  }
  out.columns = {{"spindle_rpm", std::move(rpm)}, {"depth_limit_mm", std::move(depth)}};
  for (std::size_t l = 0; l < mc.levels.size(); ++l)
    out.columns.emplace_back(quantile_column_name(mc.levels[l]), scaled(mc.quantile_depth_m[l], 1e3));
  std::vector<double> prob;
  for (const auto& row : mc.probability_stable) prob.insert(prob.end(), row.begin(), row.end());
  out.columns.emplace_back("depth_mm", scaled(mc.depths_m, 1e3));
  out.columns.emplace_back("probability_stable", std::move(prob), mc.depths_m.size());
  return out;
}

}  // namespace chatter
