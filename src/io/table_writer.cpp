#include "chatter/io/table_writer.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"

namespace chatter {
namespace {

// printf's "%.10g" (the standard defines to_chars with a precision as that
// conversion in the C locale), without printf's cost: a simulated series
// prints millions of numbers.
std::string num(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, 10).ptr;
  return std::string(buf, end);
}

nlohmann::json json_num(double x) {
  if (!std::isfinite(x)) return nullptr;
  return std::stod(num(x));  // same rounding as the CSV
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

std::string version() { return CHATTER_VERSION; }

std::string table_number(double x) { return num(x); }

void write_lobe_csv(std::ostream& os, const std::vector<StabilityLimit>& rows, const std::vector<ExtraColumn>& extra) {
  os << "spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe";
  for (const ExtraColumn& c : extra) os << ',' << c.name;
  os << '\n';
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const StabilityLimit& r = rows[i];
    os << num(r.spindle_rpm) << ',' << num(r.depth_limit_m * 1e3) << ',';
    if (r.bounded()) os << num(r.chatter_frequency_hz) << ',' << r.lobe;
    else os << ',';
    for (const ExtraColumn& c : extra) os << ',' << c.values.at(i);
    os << '\n';
  }
}

void write_lobe_json(std::ostream& os, const std::vector<StabilityLimit>& rows, const TableProvenance& p,
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
  j["options"] = nlohmann::json::parse(p.options_json);
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
  os << j.dump(2) << '\n';
}

void write_text_files(const std::vector<std::pair<std::filesystem::path, std::string>>& files) {
  std::vector<std::filesystem::path> temps;
  auto discard = [&] {
    std::error_code ec;
    for (const auto& t : temps)
      if (!t.empty()) std::filesystem::remove(t, ec);
  };
  // Special files (/dev/stdout, a pipe) are written in place, after every
  // regular file has been prepared: they cannot be replaced by a rename.
  // A symbolic link is written through, never replaced.
  auto special = [](const std::filesystem::path& p) {
    std::error_code ec;
    const auto st = std::filesystem::symlink_status(p, ec);
    return p == "/dev/stdout" || (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st));
  };
  for (const auto& [path, text] : files) {
    if (special(path)) {
      temps.emplace_back();
      continue;
    }
    std::filesystem::path tmp = path;
    tmp += ".partial";
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) {
      discard();
      throw InputError(path.string() + ": cannot open for writing (does the directory exist?)");
    }
    temps.push_back(tmp);
    f << text;
    f.close();
    if (!f) {
      discard();
      throw InputError(path.string() + ": write failed (disk full?)");
    }
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (temps[i].empty()) {
      if (files[i].first == "/dev/stdout") {  // share std::cout's buffer and file offset
        std::cout << files[i].second << std::flush;
        continue;
      }
      std::error_code ec;
      const bool regular_target = std::filesystem::is_regular_file(files[i].first, ec);
      std::ofstream f(files[i].first, std::ios::binary | (regular_target ? std::ios::trunc : std::ios::app));
      f << files[i].second;
      f.close();
      if (!f) {
        discard();
        throw InputError(files[i].first.string() + ": write failed");
      }
      continue;
    }
    std::error_code ec;
    std::filesystem::rename(temps[i], files[i].first, ec);
    if (ec) {
      discard();
      throw InputError(files[i].first.string() + ": cannot replace (" + ec.message() + ")");
    }
  }
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  write_text_files({{path, text}});
}

}  // namespace chatter
