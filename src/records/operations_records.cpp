// The records of check and recommend (chatter/records.hpp): the same JSON
// for `chatter check --json`, `chatter recommend --json`, Python's
// chatter.check / chatter.recommend and the C API.
#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/records.hpp"
#include "chatter/records/forced.hpp"  // forced_check_record
#include "chatter/io/table_writer.hpp"    // version()

namespace chatter {

using nlohmann::json;

namespace {

json pocket_json(const SpeedPocket& p) {
  return {{"speed_tolerance_pct", p.speed_tolerance * 100.0},
          {"worst_limit_mm", finite_or_null(p.worst_limit_m * 1e3)},
          {"worst_margin", finite_or_null(p.worst_margin)},
          {"pocket_min_rpm", p.pocket_min_rpm},
          {"pocket_max_rpm", p.pocket_max_rpm}};
}

json limit_json(const StabilityLimit& l) {
  return {{"spindle_rpm", l.spindle_rpm},
          {"depth_limit_mm", l.bounded() ? json(l.depth_limit_m * 1e3) : json(nullptr)},
          {"chatter_frequency_hz", l.bounded() ? finite_or_null(l.chatter_frequency_hz) : json(nullptr)},
          {"lobe", l.bounded() && l.lobe >= 0 ? json(l.lobe) : json(nullptr)}};
}

const char* direction_name(MillingDirection d) { return d == MillingDirection::kDown ? "down" : "up"; }

// A number for messages (6 significant digits, as the CLI prints them).
}  // namespace

MachineLimits machine_range(const Config& cfg, std::optional<double> rpm_min, std::optional<double> rpm_max,
                            ArgStyle style) {
  const auto pick = [&](const std::optional<double>& given, const std::optional<double>& from_cfg, const char* key,
                        const char* cfg_key) {
    if (given) return *given;
    if (from_cfg) return *from_cfg;
    throw InputError(cfg.source.string() + ": missing " + arg_name(style, key) + " (or " + cfg_key +
                     " in the config): the machine's spindle speed range");
  };
  MachineLimits m;
  m.rpm_min = pick(rpm_min, cfg.sweep.rpm_min, "rpm_min", "sweep.rpm_min");
  m.rpm_max = pick(rpm_max, cfg.sweep.rpm_max, "rpm_max", "sweep.rpm_max");
  if (!(std::isfinite(m.rpm_min) && m.rpm_min > 0.0))
    throw InputError(arg_name(style, "rpm_min") + " = " + number_text(m.rpm_min) + ": must be > 0 rev/min");
  if (!(std::isfinite(m.rpm_max) && m.rpm_max > m.rpm_min))
    throw InputError(arg_name(style, "rpm_max") + " = " + number_text(m.rpm_max) + ": must be > " +
                     arg_name(style, "rpm_min") + " (" + number_text(m.rpm_min) + ")");
  return m;
}

namespace {

// The speed tolerance in percent as a fraction. @throws InputError.
double speed_tolerance(double pct, ArgStyle style) {
  if (const std::string e = validate_speed_tolerance(pct / 100.0, arg_name(style, "speed_tolerance_pct"));
      !e.empty())
    throw InputError(e);
  return pct / 100.0;
}

// The method as given, checked against the config ("auto" resolved later).
void check_method(const std::string& method, const Config& cfg, ArgStyle style) {
  try {
    resolve_lobe_method(method, cfg.model, cfg.process);
  } catch (const InputError& e) {
    throw InputError(arg_name(style, "method") + ": " + e.what());
  }
}

// x itself when finite and > 0. @throws InputError "<arg> = x: must be > 0".
double positive_arg(ArgStyle style, const char* key, double x) {
  if (!(std::isfinite(x) && x > 0.0)) throw InputError(arg_name(style, key) + " = " + number_text(x) + ": must be > 0");
  return x;
}

// @throws InputError "<arg>: only for <op> (the config's operation is ...)"
// when the argument is given and `ok` is false.
void only_for_operation(ArgStyle style, const char* key, bool given, bool ok, const char* op, bool milling) {
  if (given && !ok)
    throw InputError(arg_name(style, key) + ": only for " + op + " (the config's operation is " +
                     (milling ? "milling" : "turning") + ")");
}

// The cutting-load arguments of check and recommend, checked: the machine's
// power and torque, the diameter (default the config's process.tool_diameter_mm
// or process.workpiece_diameter_mm) and turning's K_c.
struct LoadInputs {
  double diameter_m = 0.0;
  std::optional<double> kc;
};
LoadInputs load_inputs(const Config& cfg, const CheckLoadArgs& a, MachineLimits& machine, ArgStyle style) {
  const bool milling = cfg.process.rotating_edges();
  const auto name = [&](const char* key) { return arg_name(style, key); };
  const auto positive = [&](const char* key, double x) { return positive_arg(style, key, x); };
  const auto only = [&](const char* key, bool given, bool ok, const char* op) {
    only_for_operation(style, key, given, ok, op, milling);
  };
  only("tool_diameter_mm", a.tool_diameter_mm.has_value(), milling, "milling");
  only("workpiece_diameter_mm", a.workpiece_diameter_mm.has_value(), !milling, "turning");
  only("tangential_coefficient_n_per_m2", a.tangential_coefficient_n_per_m2.has_value(), !milling, "turning");
  if (a.max_power_kw) machine.max_power_w = positive("max_power_kw", *a.max_power_kw) * 1e3;
  if (a.max_torque_nm) machine.max_torque_n_m = positive("max_torque_nm", *a.max_torque_nm);
  LoadInputs in;
  in.diameter_m = milling ? cfg.process.milling_parameters().tool_diameter_m
                          : cfg.process.turning_parameters().workpiece_diameter_m;
  if (a.tool_diameter_mm) in.diameter_m = positive("tool_diameter_mm", *a.tool_diameter_mm) * 1e-3;
  if (a.workpiece_diameter_mm) in.diameter_m = positive("workpiece_diameter_mm", *a.workpiece_diameter_mm) * 1e-3;
  if (a.tangential_coefficient_n_per_m2)
    in.kc = positive("tangential_coefficient_n_per_m2", *a.tangential_coefficient_n_per_m2);
  if ((std::isfinite(machine.max_power_w) || std::isfinite(machine.max_torque_n_m)) && !(in.diameter_m > 0.0))
    throw InputError(std::string("a power or torque limit needs the ") +
                     (milling ? "tool diameter (" + name("tool_diameter_mm") + ")"
                              : "workpiece diameter (" + name("workpiece_diameter_mm") + ")"));
  return in;
}

}  // namespace

CheckOptions check_options(const Config& cfg, std::optional<double> rpm_min, std::optional<double> rpm_max,
                           const std::string& method, double speed_tolerance_pct, unsigned threads, ArgStyle style,
                           const CheckLoadArgs& load) {
  CheckOptions opt;
  opt.machine = machine_range(cfg, rpm_min, rpm_max, style);
  opt.method = method;
  opt.threads = threads;
  opt.speed_tolerance = speed_tolerance(speed_tolerance_pct, style);
  opt.flute_length_m = cfg.flute_length_m;
  check_method(method, cfg, style);
  const LoadInputs in = load_inputs(cfg, load, opt.machine, style);
  opt.diameter_m = in.diameter_m;
  opt.cutting_coefficient_n_per_m2 = in.kc;
  return opt;
}

RecommendPlan recommend_plan(const Config& cfg, const RecommendArgs& a, ArgStyle style) {
  const bool milling = cfg.process.rotating_edges();
  const auto name = [&](const char* key) { return arg_name(style, key); };
  RecommendOptions opt;
  opt.machine = machine_range(cfg, a.rpm_min, a.rpm_max, style);
  const auto positive = [&](const char* key, double x) { return positive_arg(style, key, x); };
  const auto only = [&](const char* key, bool given, bool ok, const char* op) {
    only_for_operation(style, key, given, ok, op, milling);
  };
  only("radial_immersion", a.radial_immersion.has_value(), milling, "milling");
  only("teeth", a.teeth.has_value(), milling, "milling");
  only("milling_direction", a.milling_direction.has_value(), milling, "milling");
  const LoadInputs load = load_inputs(
      cfg, {a.max_power_kw, a.max_torque_nm, a.tool_diameter_mm, a.workpiece_diameter_mm, a.tangential_coefficient_n_per_m2},
      opt.machine, style);
  opt.diameter_m = load.diameter_m;
  opt.cutting_coefficient_n_per_m2 = load.kc;
  opt.feed_per_tooth_m = positive("feed_per_tooth_mm", a.feed_per_tooth_mm) * 1e-3;
  if (!(a.safety > 0.0 && a.safety <= 1.0)) throw InputError(name("safety") + " = " + number_text(a.safety) + ": must be in (0, 1]");
  opt.safety = a.safety;
  opt.depth_max_m =
      (a.depth_max_mm ? positive("depth_max_mm", *a.depth_max_mm) : cfg.sweep.depth_max_mm.value_or(kDefaultSearchDepthMm)) * 1e-3;
  opt.method = a.method;
  check_method(a.method, cfg, style);
  opt.threads = a.threads;
  opt.speed_tolerance = speed_tolerance(a.speed_tolerance_pct, style);
  if (milling) opt.flute_length_m = cfg.flute_length_m;
  if (a.max_sle_um) opt.max_part_error_m = positive("max_sle_um", *a.max_sle_um) * 1e-6;

  Process process = cfg.process;
  if (milling) {
    OperationRow row;
    row.id = "recommend";
    if (a.radial_immersion) {
      const double ae = *a.radial_immersion;
      if (!(ae > 0.0 && ae <= 1.0)) throw InputError(name("radial_immersion") + " = " + number_text(ae) + ": must be in (0, 1]");
      row.radial_immersion = ae;
    }
    if (a.teeth) {
      if (*a.teeth < 1) throw InputError(name("teeth") + " = " + std::to_string(*a.teeth) + ": must be >= 1");
      row.teeth = *a.teeth;
    }
    if (a.milling_direction) {
      const std::string& d = *a.milling_direction;
      if (d == "down") row.direction = MillingDirection::kDown;
      else if (d == "up") row.direction = MillingDirection::kUp;
      else throw InputError(name("milling_direction") + " = " + d + ": must be 'down' or 'up'");
    }
    process = process_for(cfg.process, row);
  }
  return {opt, process};
}

int check_exit_status(const CheckReport& report, const OperationsFile& file) {
  if (!file.rejected.empty() || !report.not_judged.empty()) return 2;
  return report.unstable() > 0 || report.out_of_tolerance() > 0 || report.overloaded() > 0 ? 3 : 0;
}

json check_record(const CheckReport& report, const OperationsFile& file, const CheckRecordInputs& in,
                  const RecordSource& source) {
  const CheckOptions& opt = *in.options;
  const bool milling = in.process->rotating_edges();
  json j;
  j["format"] = "chatter-operation-check";
  j["version"] = version();
  j["config"] = source.config_path;
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  j["operations_file"] = in.operations_origin;
  j["machine"] = {{"rpm_min", opt.machine.rpm_min},
                  {"rpm_max", opt.machine.rpm_max},
                  {"max_power_kw", finite_or_null(opt.machine.max_power_w * 1e-3)},
                  {"max_torque_nm", finite_or_null(opt.machine.max_torque_n_m)}};
  j["diameter_mm"] = opt.diameter_m > 0.0 ? json(opt.diameter_m * 1e3) : json(nullptr);
  j["method_requested"] = in.method_requested;
  j["warnings"] = source.warnings;  // the config's plausibility warnings, then the check's
  for (const auto& w : report.warnings) j["warnings"].push_back(w);
  j["search_depth_rule"] = "max(4 x depth_mm, 20 mm)";
  j["speed_tolerance_pct"] = opt.speed_tolerance * 100.0;
  j["flute_length_mm"] = opt.flute_length_m ? json(*opt.flute_length_m * 1e3) : json(nullptr);
  json ops = json::array();
  for (const auto& c : report.checks) {
    json o = {{"id", c.op.id},
              {"line", c.op.line},
              {"spindle_rpm", c.op.spindle_rpm},
              {"depth_mm", c.op.depth_mm > 0.0 ? c.op.depth_mm : c.op.depth_m * 1e3},  // as written
              {"feed_per_tooth_mm", c.op.feed_per_tooth_mm   ? json(*c.op.feed_per_tooth_mm)
                                    : c.op.feed_per_tooth_m ? json(*c.op.feed_per_tooth_m * 1e3)
                                                            : json(nullptr)},
              {"method", c.method},
              {"stable", c.stable},
              {"depth_limit_mm", c.limit.bounded() ? json(c.limit.depth_limit_m * 1e3) : json(nullptr)},
              {"searched_depth_mm", c.search_depth_m * 1e3},
              {"margin", finite_or_null(c.margin)},
              {"worst_margin", finite_or_null(c.worst_margin)},
              {"chatter_frequency_hz", c.limit.bounded() ? finite_or_null(c.limit.chatter_frequency_hz) : json(nullptr)},
              {"lobe", c.limit.bounded() && c.limit.lobe >= 0 ? json(c.limit.lobe) : json(nullptr)}};
    if (milling) {
      const auto& mp = in.process->milling_parameters();
      o["radial_immersion"] = c.op.radial_immersion.value_or(mp.radial_immersion);
      o["teeth"] = c.op.teeth.value_or(mp.teeth);
      o["milling_direction"] = direction_name(c.op.direction.value_or(mp.direction));
    }
    // The forced vibration (null without a feed; docs/forced.md).
    o["forced"] = c.forced ? forced_check_record(c.forced->response, c.op.max_error_m, c.forced->within_tolerance)
                           : json(nullptr);
    // The mean cutting load (null without a feed; docs/cutting_law.md).
    if (c.load) {
      o["load"] = {{"mean_force_n", finite_or_null(c.load->mean_force_n)},
                   {"torque_nm", finite_or_null(c.load->torque_n_m)},
                   {"power_kw", finite_or_null(c.load->power_w * 1e-3)},
                   {"mrr_cm3_per_min", finite_or_null(c.load->removal_rate_m3_per_s * 6e7)},
                   {"within_power", c.load->within_power},
                   {"within_torque", c.load->within_torque}};
    } else {
      o["load"] = nullptr;
    }
    if (c.suggestion) {
      json s = limit_json(*c.suggestion);
      s["margin"] = finite_or_null(c.suggestion_margin);
      s.update(pocket_json(*c.suggestion_pocket));
      // Part quality beside the suggestion: the forced response there.
      if (const auto& f = c.suggestion_forced) {
        const bool have = f->response.stable;
        s["part_error_um"] = have ? finite_or_null(f->part_error_m * 1e6) : json(nullptr);
        s["peak_to_peak_um"] =
            have ? finite_or_null(std::max(f->response.peak_to_peak_x_m, f->response.peak_to_peak_y_m) * 1e6)
                 : json(nullptr);
        s["within_tolerance"] = f->within_tolerance ? json(*f->within_tolerance) : json(nullptr);
      }
      s["note"] = c.suggestion_note.empty() ? json(nullptr) : json(c.suggestion_note);
      o["suggestion"] = s;
    } else {
      o["suggestion"] = nullptr;
    }
    ops.push_back(o);
  }
  j["operations"] = ops;
  json rej = json::array();
  for (const auto& b : file.rejected) rej.push_back({{"line", b.line}, {"id", b.id}, {"reason", b.reason}});
  j["rejected"] = rej;
  json nj = json::array();
  for (const auto& b : report.not_judged) nj.push_back({{"line", b.line}, {"id", b.id}, {"reason", b.reason}});
  j["not_judged"] = nj;
  j["summary"] = {{"checked", report.checks.size()},
                  {"stable", report.checks.size() - report.unstable()},
                  {"unstable", report.unstable()},
                  {"rejected", file.rejected.size()},
                  {"not_judged", report.not_judged.size()},
                  {"out_of_tolerance", report.out_of_tolerance()},
                  {"overloaded", report.overloaded()}};
  j["exit_status"] = check_exit_status(report, file);
  return j;
}

json recommend_record(const Recommendation& r, const RecommendOptions& opt, const Process& process,
                      const RecordSource& source) {
  json j;
  j["format"] = "chatter-recommendation";
  j["version"] = version();
  j["config"] = source.config_path;
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  j["method"] = r.method;
  j["inputs"] = {{"rpm_min", opt.machine.rpm_min},
                 {"rpm_max", opt.machine.rpm_max},
                 {"max_power_kw", finite_or_null(opt.machine.max_power_w * 1e-3)},
                 {"max_torque_nm", finite_or_null(opt.machine.max_torque_n_m)},
                 {"feed_per_tooth_mm", opt.feed_per_tooth_m * 1e3},
                 {"safety", opt.safety},
                 {"depth_max_mm", opt.depth_max_m * 1e3},
                 {"flute_length_mm", opt.flute_length_m ? json(*opt.flute_length_m * 1e3) : json(nullptr)},
                 {"speed_tolerance_pct", opt.speed_tolerance * 100.0},
                 {"diameter_mm", opt.diameter_m > 0.0 ? json(opt.diameter_m * 1e3) : json(nullptr)},
                 {"max_sle_um", opt.max_part_error_m ? json(*opt.max_part_error_m * 1e6) : json(nullptr)}};
  if (process.rotating_edges()) {
    const auto& mp = process.milling_parameters();
    j["inputs"]["radial_immersion"] = mp.radial_immersion;
    j["inputs"]["teeth"] = mp.teeth;
    j["inputs"]["milling_direction"] = direction_name(mp.direction);
  }
  j["spindle_rpm"] = r.spindle_rpm;
  j["depth_mm"] = r.depth_m * 1e3;
  j["limit"] = limit_json(r.limit);
  j["searched_depth_mm"] = r.search_depth_m * 1e3;
  j["skipped_solves"] = r.skipped_solves;
  j["margin"] = finite_or_null(r.margin);
  j["depth_caps_mm"] = {{"stability", finite_or_null(r.depth_stability_m * 1e3)},
                        {"power", finite_or_null(r.depth_power_m * 1e3)},
                        {"torque", finite_or_null(r.depth_torque_m * 1e3)},
                        {"depth_max", finite_or_null(r.depth_cap_m * 1e3)},
                        {"flute_length", finite_or_null(r.depth_flute_m * 1e3)},
                        {"surface_error", finite_or_null(r.depth_part_error_m * 1e3)}};
  // The forced vibration's part error at the recommended cut (|SLE| milling,
  // diametral error turning) and its peak-to-peak: beside every suggestion.
  j["part_error_um"] = finite_or_null(r.part_error_m * 1e6);
  j["peak_to_peak_um"] = finite_or_null(r.peak_to_peak_m * 1e6);
  j["speed_band"] = pocket_json(r.pocket);
  json b = json::array();
  for (auto x : r.binding) b.push_back(to_string(x));
  j["binding"] = b;
  j["mean_force_n"] = finite_or_null(r.force_n);
  j["torque_nm"] = finite_or_null(r.torque_n_m);
  j["power_kw"] = finite_or_null(r.power_w * 1e-3);
  j["mrr_cm3_per_min"] = finite_or_null(r.mrr_m3_per_s * 6e7);
  j["mrr_cm3_per_min_per_mm_diameter"] = r.mrr_per_diameter_m2_per_s * 6e7 * 1e-3;
  j["warnings"] = source.warnings;  // the config's plausibility warnings, then the recommendation's
  for (const auto& w : r.warnings) j["warnings"].push_back(w);
  j["explanation"] = explain(r, opt);
  return j;
}

}  // namespace chatter
