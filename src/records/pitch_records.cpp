// The record of `chatter design-pitch` (include/chatter/records/pitch.hpp,
// docs/design_pitch.md): the arguments checked once, the design, its JSON,
// its band table, its config fragment and its summary.
#include "chatter/records/pitch.hpp"
#include "chatter/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/report.hpp"
#include "chatter/solvers.hpp"

namespace chatter {

using json = nlohmann::json;

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// Limits in mm for the record: null where there is none below the searched depth.
json limit_mm(double m) { return std::isfinite(m) ? json(m * 1e3) : json(nullptr); }

json candidate_json(const PitchCandidate& c) {
  json angles = json::array();
  for (double th : c.angles_rad) angles.push_back(th * kDegPerRad);
  return {{"step_deg", c.step_rad * kDegPerRad},
          {"pitch_angles_deg", angles},
          {"worst_limit_mm", limit_mm(c.worst_limit_m)},
          {"worst_rpm", c.worst_rpm}};
}

std::string depth_text(double m) { return std::isfinite(m) ? number_text(m * 1e3, 4) + " mm" : "none below the searched depth"; }

}  // namespace

PitchDesignOptions pitch_design_options(const Config& cfg, const PitchDesignArgs& a, ArgStyle style) {
  const auto name = [&](const char* key) { return arg_name(style, key); };
  PitchDesignOptions o;
  if (!a.rpm_min)
    throw InputError(name("rpm_min") + ": required: the lowest spindle speed of the band, rev/min");
  if (!a.rpm_max)
    throw InputError(name("rpm_max") + ": required: the highest spindle speed of the band, rev/min");
  check_spindle_rpm(*a.rpm_min, name("rpm_min"));
  check_spindle_rpm(*a.rpm_max, name("rpm_max"));
  if (!(*a.rpm_max > *a.rpm_min))
    throw InputError(name("rpm_max") + " = " + number_text(*a.rpm_max) + ": must be > " + name("rpm_min") + " = " +
                     number_text(*a.rpm_min) + " (the band is empty or inverted)");
  o.rpm_min = *a.rpm_min;
  o.rpm_max = *a.rpm_max;
  if (a.rpm_points < 2 || a.rpm_points > 100000)
    throw InputError(name("rpm_points") + " = " + std::to_string(a.rpm_points) + ": must be in [2, 100000]");
  o.rpm_points = a.rpm_points;
  const double depth_mm = a.depth_max_mm ? *a.depth_max_mm : cfg.sweep.depth_max_mm.value_or(kDefaultSearchDepthMm);
  if (a.depth_max_mm) check_depth_mm(*a.depth_max_mm, name("depth_max_mm"));
  o.depth_max_m = depth_mm * 1e-3;
  const auto family = pitch_family_from_string(a.family);
  if (!family)
    throw InputError(name("family") + " = '" + a.family + "': must be 'linear' or 'alternating'");
  o.family = *family;
  if (!(a.min_pitch_ratio >= 0.1 && a.min_pitch_ratio < 1.0))
    throw InputError(name("min_pitch_ratio") + " = " + number_text(a.min_pitch_ratio) +
                     ": must be in [0.1, 1) (each pitch angle >= ratio x 360/teeth)");
  o.min_pitch_ratio = a.min_pitch_ratio;
  if (a.scan_points < 0 || a.scan_points > 200)
    throw InputError(name("scan_points") + " = " + std::to_string(a.scan_points) + ": must be in [0, 200]");
  o.scan_points = a.scan_points;
  // The config: a milling cutter of the asked teeth, equal pitch.
  const std::string where = cfg.source.empty() ? std::string("the config") : cfg.source.string();
  if (!cfg.process.rotating_edges())
    throw InputError(where + ": process.operation = \"turning\": design-pitch designs a milling cutter");
  const int teeth = cfg.process.teeth();
  if (a.teeth) {
    if (*a.teeth < 2)
      throw InputError(name("teeth") + " = " + std::to_string(*a.teeth) + ": must be >= 2 (a pitch needs two teeth)");
    if (*a.teeth != teeth)
      throw InputError(name("teeth") + " = " + std::to_string(*a.teeth) + ": the config's cutter has " +
                       std::to_string(teeth) + " teeth (process.teeth); the design keeps the config's cutter: give " +
                       std::to_string(teeth) + " or edit the config");
  }
  if (teeth < 2)
    throw InputError(where + ": process.teeth = " + std::to_string(teeth) + ": a pitch needs >= 2 teeth");
  if (o.family == PitchFamily::kAlternating && teeth % 2 != 0)
    throw InputError(name("family") + " = 'alternating': needs an even number of teeth (the config has " +
                     std::to_string(teeth) + "); use 'linear'");
  if (cfg.process.has_variable_pitch())
    throw InputError(where + ": process.pitch_angles_deg: the cutter already has unequal pitch; design-pitch starts "
                     "from the equal-pitch cutter it compares with: remove pitch_angles_deg");
  if (cfg.process.has_variable_helix())
    throw InputError(where + ": process.helix_angles_deg: unequal helix angles; design-pitch needs one helix angle "
                     "for every tooth");
  if (cfg.process.has_speed_variation())
    throw InputError(where + ": process.speed_variation: design-pitch assumes a constant spindle speed");
  o.method = a.method;
  try {
    const std::string m = a.method == kAutoMethod ? std::string("sdm") : a.method;
    const SolverDescriptor& d = find_lobe_method(m);
    if (d.kind == SolverKind::kSimulation)
      throw InputError("method \"" + m + "\": a simulation's limit is a depth bracket, too coarse and slow for a "
                       "search; use sdm or analytic");
    if (!d.accepts.contains(SolverFeature::kVariablePitch))
      throw InputError("method \"" + m + "\" does not handle variable pitch; use sdm or analytic");
    o.method = m;
  } catch (const InputError& e) {
    throw InputError(name("method") + ": " + e.what());
  }
  o.solver_options = a.solver_options;
  o.threads = a.threads;
  return o;
}

PitchDesign run_pitch_design(const Config& cfg, const PitchDesignOptions& o, ArgStyle style) {
  try {
    return design_pitch(cfg.model, cfg.process, o);
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.rfind("depth_max_m = ", 0) == 0 && what.find(": ") != std::string::npos)
      throw InputError(arg_name(style, "depth_max_mm") + " = " + number_text(o.depth_max_m * 1e3) + " mm" +
                       what.substr(what.find(": ")));
    throw InputError(what);
  }
}

json pitch_design_record(const PitchDesign& d, const PitchDesignOptions& o, const RecordSource& source) {
  json j;
  j["format"] = "chatter-pitch-design";
  j["version"] = version();
  j["config"] = source.config_path;
  j["warnings"] = source.warnings;
  j["method"] = d.method;
  j["family"] = to_string(d.family);
  j["inputs"] = {{"rpm_min", o.rpm_min},
                 {"rpm_max", o.rpm_max},
                 {"rpm_points", o.rpm_points},
                 {"depth_max_mm", o.depth_max_m * 1e3},
                 {"teeth", static_cast<int>(d.equal.angles_rad.size())},
                 {"family", to_string(o.family)},
                 {"min_pitch_ratio", o.min_pitch_ratio},
                 {"scan_points", o.scan_points}};
  json angles = json::array();
  for (double th : d.designed.angles_rad) angles.push_back(th * kDegPerRad);
  j["pitch_angles_deg"] = angles;
  j["equal"] = candidate_json(d.equal);
  j["start"] = candidate_json(d.start);
  j["designed"] = candidate_json(d.designed);
  j["rule"] = {{"spindle_rpm", d.rule_rpm},
               {"chatter_frequency_hz", d.rule_chatter_frequency_hz},
               {"step_deg", d.rule_step_rad * kDegPerRad},
               {"clipped", d.rule_clipped}};
  j["step_max_deg"] = d.step_max_rad * kDegPerRad;
  j["on_min_pitch_bound"] = on_min_pitch_bound(d);
  j["chip_load_ratio"] = chip_load_ratio(d);
  j["gain"] = d.gain;
  j["gain_is_lower_bound"] = d.gain_is_lower_bound;
  json ev = json::array();
  for (const auto& [step, worst] : d.evaluated)
    ev.push_back({{"step_deg", step * kDegPerRad}, {"worst_limit_mm", limit_mm(worst)}});
  j["evaluated"] = ev;
  json rows = json::array();
  for (std::size_t i = 0; i < d.speeds_rpm.size(); ++i) {
    const StabilityLimit& e = d.equal.limits[i];
    const StabilityLimit& g = d.designed.limits[i];
    rows.push_back({{"spindle_rpm", d.speeds_rpm[i]},
                    {"depth_limit_equal_mm", e.bounded() ? json(e.depth_limit_m * 1e3) : json(nullptr)},
                    {"depth_limit_designed_mm", g.bounded() ? json(g.depth_limit_m * 1e3) : json(nullptr)}});
  }
  j["band"] = rows;
  j["summary"] = pitch_design_summary(d);
  return j;
}

bool on_min_pitch_bound(const PitchDesign& d) {
  return d.step_max_rad > 0.0 && d.designed.step_rad >= d.step_max_rad * (1.0 - 1e-9);
}

double chip_load_ratio(const PitchDesign& d) {
  const auto [lo, hi] = std::minmax_element(d.designed.angles_rad.begin(), d.designed.angles_rad.end());
  return *hi / *lo;
}

std::string pitch_design_csv(const PitchDesign& d) {
  std::ostringstream os;
  os << "spindle_rpm,depth_limit_equal_mm,depth_limit_designed_mm\n";
  for (std::size_t i = 0; i < d.speeds_rpm.size(); ++i) {
    const StabilityLimit& e = d.equal.limits[i];
    const StabilityLimit& g = d.designed.limits[i];
    os << table_number(d.speeds_rpm[i]) << ',' << table_number(e.bounded() ? e.depth_limit_m * 1e3 : e.depth_limit_m)
       << ',' << table_number(g.bounded() ? g.depth_limit_m * 1e3 : g.depth_limit_m) << '\n';
  }
  return os.str();
}

std::string pitch_design_fragment(const PitchDesign& d, const std::string& config_name) {
  std::ostringstream os;
  os << "# Pitch designed by chatter design-pitch " << version() << " for '" << config_name << "'\n"
     << "# (" << to_string(d.family) << " family, step " << number_text(d.designed.step_rad * kDegPerRad, 6) << " deg; "
     << "worst limit over " << number_text(d.speeds_rpm.front()) << "-" << number_text(d.speeds_rpm.back())
     << " rev/min: " << depth_text(d.designed.worst_limit_m) << " vs " << depth_text(d.equal.worst_limit_m)
     << " equal pitch, " << d.method << ").\n"
     << "# Put this line in [process]:\n"
     << "pitch_angles_deg = [";
  for (std::size_t j = 0; j < d.designed.angles_rad.size(); ++j) {
    // 12 digits: 60, not 59.999999999999993 (the sum stays 360 deg to 1e-9).
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.12g", d.designed.angles_rad[j] * kDegPerRad);
    os << (j ? ", " : "") << buf;
  }
  os << "]\n";
  return os.str();
}

std::string pitch_design_summary(const PitchDesign& d) {
  std::ostringstream os;
  os << "designed pitch (" << to_string(d.family) << ", " << d.method << "): ";
  for (std::size_t j = 0; j < d.designed.angles_rad.size(); ++j)
    os << (j ? " / " : "") << number_text(d.designed.angles_rad[j] * kDegPerRad, 5);
  os << " deg (step " << number_text(d.designed.step_rad * kDegPerRad, 4) << " deg)\n"
     << "worst limit over " << number_text(d.speeds_rpm.front()) << "-" << number_text(d.speeds_rpm.back()) << " rev/min ("
     << d.speeds_rpm.size() << " speeds):\n"
     << "  equal pitch:    " << depth_text(d.equal.worst_limit_m) << " at " << number_text(d.equal.worst_rpm) << " rev/min\n"
     << "  designed pitch: " << depth_text(d.designed.worst_limit_m);
  if (std::isfinite(d.designed.worst_limit_m)) os << " at " << number_text(d.designed.worst_rpm) << " rev/min";
  os << "\ngain: " << (d.gain_is_lower_bound ? ">= " : "") << number_text(d.gain, 4) << " x equal pitch\n"
     << "start (Budak's rule at " << number_text(d.rule_rpm) << " rev/min, chatter " << number_text(d.rule_chatter_frequency_hz)
     << " Hz): step " << number_text(d.rule_step_rad * kDegPerRad, 4) << " deg"
     << (d.rule_clipped ? " (beyond the largest step " + number_text(d.step_max_rad * kDegPerRad, 4) + " deg: started there)"
                        : "")
     << ", worst limit " << depth_text(d.start.worst_limit_m) << "\n";
  if (on_min_pitch_bound(d))
    os << "on the bound: the smallest pitch is " << number_text(kDegPerRad * *std::min_element(d.designed.angles_rad.begin(), d.designed.angles_rad.end()), 5)
       << " deg, the minimum-pitch ratio times the equal pitch (--min-pitch-ratio); the best design may lie beyond it\n";
  os << "chip loads: the largest " << number_text(chip_load_ratio(d), 3)
     << " x the smallest (a tooth's chip grows with the pitch in front of it)\n";
  return os.str();
}

}  // namespace chatter
