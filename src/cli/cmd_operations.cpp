// `chatter check` and `chatter recommend`: the operation check and the speed
// recommendation of include/chatter/operations.hpp, for CAM post-processors.
// User guide: docs/operations.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/operations.hpp"
#include "chatter/records.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {
namespace {

using nlohmann::json;

std::string method_help() {
  std::string known;
  for (const auto& m : lobe_methods()) known += ", '" + m + "'";
  return "solver: 'auto' (the default, as every command: turning analytic; milling sdm, or analytic with a "
         "flip-lobe warning when sdm does not handle the input)" + known;
}

// An optional flag's value.
std::optional<double> opt_value(const po::variables_map& vm, const char* flag) {
  return vm.count(flag) ? std::optional<double>(vm[flag].as<double>()) : std::nullopt;
}

// The progress bar of check and recommend: on a terminal, after a second.
constexpr double kProgressAfterS = 1.0;
constexpr std::size_t kProgressSteps = 1000;

std::string fixed(double x, int digits) {
  if (std::isinf(x)) return "inf";
  if (std::isnan(x)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

// A plain text table: first column left-aligned, the others right-aligned.
std::string text_table(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> w;
  for (const auto& r : rows)
    for (std::size_t i = 0; i < r.size(); ++i) {
      if (w.size() <= i) w.push_back(0);
      w[i] = std::max(w[i], r[i].size());
    }
  std::ostringstream os;
  for (const auto& r : rows) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const std::string pad(w[i] - r[i].size(), ' ');
      if (i) os << "  ";
      os << (i == 0 ? r[i] + pad : pad + r[i]);
    }
    os << '\n';
  }
  return os.str();
}

// Writes `text` to stdout for "-", else to the file (all or nothing).
void emit_json(const std::string& path, const json& j) {
  const std::string text = j.dump(2) + "\n";
  if (path == "-") std::cout << text;
  else write_text_file(path, text);
}

const char* const kCheckUsage = R"(Usage: chatter check CONFIG --operations OPS.csv [options]

Checks each planned operation against the stability lobes. OPS.csv has a header
and one operation per line:
  id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm[,teeth,milling_direction,max_sle_um|tolerance_um]
(radial_immersion = a_e/D, empty = the config's; leave it, teeth and
milling_direction empty for turning; feed_per_tooth_mm may be empty.)
For each operation: stable?, margin = depth limit / depth (> 1 is stable; 'inf'
= no chatter below max(4 x depth, 20 mm)), chatter frequency and lobe, and a
suggested spindle speed in [rpm-min, rpm-max] where the same depth stays
stable with the largest worst margin while the speed is off by up to
+/- --speed-tolerance-pct (default 2 %), with its stable pocket (edges in
rev/min); 'none' if no speed in range is stable over the whole band.
worst_margin is the smallest margin over the row's own speed band.
Rows that cannot be read are listed with their line number and reason; the
other rows are still checked.

With a feed, each row also gets its forced vibration (docs/forced.md): the
surface location error (milling) or diametral error (turning), whether the
teeth leave the cut, and with a max_sle_um (or tolerance_um) column whether
the part is within that tolerance; and its mean cutting load (power, torque,
MRR: docs/cutting_law.md; torque, power and MRR need the tool's diameter in
milling, the workpiece's in turning), judged against --max-power-kw and
--max-torque-nm when given (spindle: ok or OVER).

Exit status: 0 every row read and judged, every operation stable (and within
               its tolerance and the spindle's power and torque);
             3 every row read and judged, some operations unstable (chatter
               predicted), out of their tolerance or over the spindle's
               power or torque;
             2 some rows invalid or not judged (a row whose overrides make no
               cutter, a solver that failed on it: each listed with its line
               and reason; the others are still checked and reported), or the
               config, the options or the file header is invalid, or the file
               has no operations (then nothing is checked);
             1 internal failure.
)";

// check's table: a row per operation (speed, depth, limit, margin,
// verdict, the worst margin over the speed band, the suggestion and its
// pocket; milling: a_e/D).
std::vector<std::vector<std::string>> check_table(const CheckReport& report, const Process& process) {
  const bool milling = process.rotating_edges();
  std::vector<std::vector<std::string>> t;
  t.push_back({"id", "line", "rpm", "depth_mm", "limit_mm", "margin", "verdict", "worst_margin", "chatter_hz", "lobe",
               "suggest_rpm", "limit_there_mm", "worst_margin_there", "pocket_rpm"});
  if (milling) t.front().insert(t.front().begin() + 4, "a_e/D");
  for (const auto& c : report.checks) {
    std::vector<std::string> r = {c.op.id,
                                  std::to_string(c.op.line),
                                  fixed(c.op.spindle_rpm, 1),
                                  fixed(c.op.depth_m * 1e3, 4),
                                  c.limit.bounded() ? fixed(c.limit.depth_limit_m * 1e3, 4) : "inf",
                                  fixed(c.margin, 3),
                                  c.stable ? "stable" : "UNSTABLE",
                                  fixed(c.worst_margin, 3),
                                  c.limit.bounded() ? fixed(c.limit.chatter_frequency_hz, 1) : "-",
                                  c.limit.bounded() ? std::to_string(c.limit.lobe) : "-"};
    if (c.suggestion) {
      r.push_back(fixed(c.suggestion->spindle_rpm, 1));
      r.push_back(c.suggestion->bounded() ? fixed(c.suggestion->depth_limit_m * 1e3, 4) : "inf");
      const SpeedPocket& p = *c.suggestion_pocket;
      r.push_back(fixed(p.worst_margin, 3));
      r.push_back(fixed(p.pocket_min_rpm, 0) + "-" + fixed(p.pocket_max_rpm, 0));
    } else {
      r.insert(r.end(), {"none", "-", "-", "-"});
    }
    if (milling) {
      const double ae = c.op.radial_immersion.value_or(process.milling_parameters().radial_immersion);
      r.insert(r.begin() + 4, fixed(ae, 3));
    }
    t.push_back(std::move(r));
  }

  return t;
}

// The forced vibration of the rows with a feed: their part error, teeth
// leaving the cut, the tolerance, and the part error at the suggestion.
// Whether any row has a tolerance.
bool add_forced_columns(std::vector<std::vector<std::string>>& t, const CheckReport& report, bool milling) {
  const bool any_forced = std::any_of(report.checks.begin(), report.checks.end(),
                                      [](const OperationCheck& c) { return c.forced.has_value(); });
  const bool any_tolerance = std::any_of(report.checks.begin(), report.checks.end(),
                                         [](const OperationCheck& c) { return c.forced && c.op.max_error_m; });
  if (any_forced) {
    t.front().insert(t.front().end(), {milling ? "sle_um" : "diam_err_um", "leaves_cut", "tolerance"});
    for (std::size_t i = 0; i < report.checks.size(); ++i) {
      const auto& f = report.checks[i].forced;
      const auto& op = report.checks[i].op;
      if (!f || !f->response.stable) {
        t[i + 1].insert(t[i + 1].end(), {"-", "-", "-"});  // unstable: no steady part error to hold
        continue;
      }
      t[i + 1].push_back(fixed((milling ? f->response.surface_location_error_m : f->part_error_m) * 1e6, 2));
      t[i + 1].push_back(f->response.teeth_leave_cut ? "YES" : "no");
      t[i + 1].push_back(!op.max_error_m ? "-" : *f->within_tolerance ? "ok" : "OUT");
    }
    // The part error at the suggested speed: quality beside the suggestion.
    t.front().push_back(milling ? "sugg_sle_um" : "sugg_diam_err_um");
    for (std::size_t i = 0; i < report.checks.size(); ++i) {
      const auto& s = report.checks[i].suggestion_forced;
      t[i + 1].push_back(!s || !s->response.stable ? "-"
                         : fixed((milling ? s->response.surface_location_error_m : s->part_error_m) * 1e6, 2));
    }
  }
  return any_tolerance;
}

// The mean cutting load of the rows with a feed against the machine's power
// and torque (docs/cutting_law.md). Whether any row has a load.
bool add_load_columns(std::vector<std::vector<std::string>>& t, const CheckReport& report, bool limited) {
  const bool any_load = std::any_of(report.checks.begin(), report.checks.end(),
                                    [](const OperationCheck& c) { return c.load.has_value(); });
  if (any_load) {
    t.front().insert(t.front().end(), {"power_kw", "torque_nm", "mrr_cm3_min"});
    if (limited) t.front().push_back("spindle");
    for (std::size_t i = 0; i < report.checks.size(); ++i) {
      const auto& l = report.checks[i].load;
      auto cell = [](double x, int digits) { return std::isfinite(x) ? fixed(x, digits) : std::string("-"); };
      if (!l) {
        t[i + 1].insert(t[i + 1].end(), {"-", "-", "-"});
        if (limited) t[i + 1].push_back("-");
        continue;
      }
      t[i + 1].push_back(cell(l->power_w * 1e-3, 3));
      t[i + 1].push_back(cell(l->torque_n_m, 2));
      t[i + 1].push_back(cell(l->removal_rate_m3_per_s * 6e7, 2));
      if (limited) t[i + 1].push_back(l->within_power && l->within_torque ? "ok" : "OVER");
    }
  }
  return any_load;
}

}  // namespace

int cmd_check(const std::vector<std::string>& args) {
  Common common;
  std::string ops_path, json_path, method = "auto";
  po::options_description d("Options");
  d.add_options()
      ("operations", po::value<std::string>(&ops_path)->required(), "operations file (CSV, see above; required)")
      ("json", po::value<std::string>(&json_path), "also write every number as JSON to this file ('-': standard output, the table then goes to standard error)")
      ("rpm-min", po::value<double>(), "machine's lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "machine's highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("method", po::value<std::string>(&method)->default_value("auto"), method_help().c_str())
      ("speed-tolerance-pct", po::value<double>()->default_value(2.0, "2"), "speed error the suggestion must tolerate, % in [0, 50) (0 = exact speed: the lobe's cusp)")
      ("max-power-kw", po::value<double>(), "spindle power available for cutting, kW: a row with a feed whose mean cutting power exceeds it is OVER (default: no limit)")
      ("max-torque-nm", po::value<double>(), "spindle torque available for cutting, N*m: likewise (default: no limit)")
      ("tool-diameter-mm", po::value<double>(), "milling: tool diameter, mm, for torque, power and MRR (default: process.tool_diameter_mm)")
      ("workpiece-diameter-mm", po::value<double>(), "turning: workpiece diameter at the cut, mm, for torque, power and MRR (default: process.workpiece_diameter_mm)")
      ("tangential-coefficient-n-per-m2", po::value<double>(), "turning: tangential (cutting) coefficient K_c, N/m^2, for power and torque (default: the feed-force coefficient K_f, with a warning)")
      ("threads", po::value<int>()->default_value(0), "threads for the solves (0 = every core); the result does not depend on it")
      ("quiet,q", "no progress bar")
      ("progress", "show the progress (fraction done, time left) even when standard error is not a terminal: "
                   "one line a second, for logs");
  po::variables_map vm;
  if (!parse(args, kCheckUsage, d, common, vm)) return 0;
  check_outputs({{"--json", json_path == "-" ? "" : json_path}});  // before computing
  const Config cfg = load_checked(common);
  CheckOptions opt = check_options(cfg, opt_value(vm, "rpm-min"), opt_value(vm, "rpm-max"), method,
                                   vm["speed-tolerance-pct"].as<double>(), thread_count(vm), ArgStyle::kFlag,
                                   {opt_value(vm, "max-power-kw"), opt_value(vm, "max-torque-nm"),
                                    opt_value(vm, "tool-diameter-mm"), opt_value(vm, "workpiece-diameter-mm"),
                                    opt_value(vm, "tangential-coefficient-n-per-m2")});
  const OperationsFile file = read_operations(ops_path, cfg.process.operation(), opt.machine);
  CheckReport report;
  {
    Progress bar(vm, kProgressSteps, "check", kProgressAfterS);
    opt.progress = [&](double f) { bar.tick(static_cast<std::size_t>(f * kProgressSteps)); };
    report = check_operations(cfg.model, cfg.process, file.rows, opt);
  }

  const bool milling = cfg.process.rotating_edges();
  std::vector<std::vector<std::string>> t = check_table(report, cfg.process);
  const bool any_tolerance = add_forced_columns(t, report, milling);
  const bool limited = std::isfinite(opt.machine.max_power_w) || std::isfinite(opt.machine.max_torque_n_m);
  const bool any_load = add_load_columns(t, report, limited);
  const int status = check_exit_status(report, file);
  std::ostringstream out;
  out << cfg.name << ": " << report.checks.size() << " operation(s) checked, machine range "
      << fmt(opt.machine.rpm_min) << "-" << fmt(opt.machine.rpm_max) << " rev/min";
  if (!report.checks.empty()) out << ", method " << report.checks.front().method;
  out << "\n";
  for (const auto& w : report.warnings) out << "warning: " << w << "\n";
  if (!report.checks.empty()) out << text_table(t);
  for (const OperationCheck& c : report.checks)
    if (!c.suggestion_note.empty()) out << "suggestion for '" << c.op.id << "': " << c.suggestion_note << "\n";
  if (!file.rejected.empty()) {
    out << "rejected rows (not checked):\n";
    for (const auto& b : file.rejected)
      out << "  " << ops_path << ":" << b.line << ": " << (b.id.empty() ? "" : "id '" + b.id + "': ") << b.reason
          << "\n";
  }
  if (!report.not_judged.empty()) {
    out << "rows that could not be judged (the others are checked):\n";
    for (const auto& b : report.not_judged)
      out << "  " << ops_path << ":" << b.line << ": " << (b.id.empty() ? "" : "id '" + b.id + "': ") << b.reason
          << "\n";
  }
  out << "summary: " << (report.checks.size() - report.unstable()) << " stable, " << report.unstable()
      << " unstable, " << file.rejected.size() << " rejected, " << report.not_judged.size() << " not judged"
      << (any_tolerance ? ", " + std::to_string(report.out_of_tolerance()) + " out of tolerance" : "")
      << (limited && any_load ? ", " + std::to_string(report.overloaded()) + " over the spindle's power or torque" : "")
      << "; exit status " << status << "\n";

  if (!json_path.empty()) {
    CheckRecordInputs in;
    in.operations_origin = ops_path;
    in.method_requested = method;
    in.options = &opt;
    in.process = &cfg.process;
    emit_json(json_path, check_record(report, file, in, record_source(cfg, common.position_mm)));
  }
  (json_path == "-" ? std::cerr : std::cout) << out.str();
  return status;
}

int cmd_recommend(const std::vector<std::string>& args) {
  Common common;
  std::string json_path, method = "auto";
  double safety = 0.8;
  po::options_description d("Options");
  d.add_options()
      ("feed-per-tooth-mm", po::value<double>()->required(), "feed per tooth, mm (turning: per revolution; required)")
      ("rpm-min", po::value<double>(), "machine's lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "machine's highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("max-power-kw", po::value<double>(), "spindle power available for cutting, kW (default: no limit)")
      ("max-torque-nm", po::value<double>(), "spindle torque available for cutting, N*m (default: no limit)")
      ("safety", po::value<double>(&safety)->default_value(0.8, "0.8"), "use at most this fraction of the depth limit, in (0, 1]")
      ("depth-max-mm", po::value<double>(), "deepest cut the tool allows, mm (default: sweep.depth_max_mm or 50); milling: also process.flute_length_mm caps the depth")
      ("speed-tolerance-pct", po::value<double>()->default_value(2.0, "2"), "speed error the recommendation must tolerate, % in [0, 50): depth <= safety x the worst limit over the band")
      ("tool-diameter-mm", po::value<double>(), "milling: tool diameter, mm (needed for power, torque and MRR; default: process.tool_diameter_mm)")
      ("workpiece-diameter-mm", po::value<double>(), "turning: workpiece diameter at the cut, mm (needed for power, torque and MRR; default: process.workpiece_diameter_mm)")
      ("tangential-coefficient-n-per-m2", po::value<double>(), "turning: specific cutting force K_c for power and torque, N/m^2 (default: the config's K_f, which underestimates them)")
      ("radial-immersion", po::value<double>(), "milling: a_e/D in (0, 1] (default: the config's)")
      ("teeth", po::value<int>(), "milling: number of teeth (default: the config's)")
      ("milling-direction", po::value<std::string>(), "milling: 'down' or 'up' (default: the config's)")
      ("max-sle-um", po::value<double>(), "the part's tolerance, um: the forced vibration's surface location error (milling, |SLE|) or diametral error (turning) of the recommended cut stays within it (docs/forced.md; default: not a constraint)")
      ("json", po::value<std::string>(&json_path), "also write every number as JSON to this file ('-': standard output, the explanation then goes to standard error)")
      ("method", po::value<std::string>(&method)->default_value("auto"), method_help().c_str())
      ("threads", po::value<int>()->default_value(0), "threads for the solves (0 = every core); the result does not depend on it")
      ("quiet,q", "no progress bar")
      ("progress", "show the progress (fraction done, time left) even when standard error is not a terminal: "
                   "one line a second, for logs");
  po::variables_map vm;
  if (!parse(args,
             "Usage: chatter recommend CONFIG --feed-per-tooth-mm F [options]\n\n"
             "Finds the spindle speed in [rpm-min, rpm-max] and the depth of cut that remove the most\n"
             "material (MRR) while the depth stays below safety x the stability limit and the mean\n"
             "cutting power and torque stay within the spindle's. Explains which limit binds\n"
             "(stability, power, torque, depth_max, flute_length, speed_range, surface_error), the margin\n"
             "and the MRR. --max-sle-um adds the part's tolerance on the forced vibration's error.\n"
             "The speed is robust: the depth stays below safety x the worst limit while the speed is\n"
             "off by up to +/- --speed-tolerance-pct; the stable pocket around it is reported.\n"
             "Mean cutting force: turning F_c = K_c b f; milling from K_t a h(phi) averaged over the\n"
             "engagement (docs/operations.md).\n"
             "Output: the explanation on standard output; --json adds every number.\n"
             "Exit status: 0 a recommendation was made, 2 bad input or usage, 1 internal failure.\n",
             d, common, vm))
    return 0;
  check_outputs({{"--json", json_path == "-" ? "" : json_path}});  // before computing
  const Config cfg = load_checked(common);
  RecommendArgs a;
  a.feed_per_tooth_mm = vm["feed-per-tooth-mm"].as<double>();
  a.rpm_min = opt_value(vm, "rpm-min");
  a.rpm_max = opt_value(vm, "rpm-max");
  a.max_power_kw = opt_value(vm, "max-power-kw");
  a.max_torque_nm = opt_value(vm, "max-torque-nm");
  a.safety = safety;
  a.depth_max_mm = opt_value(vm, "depth-max-mm");
  a.speed_tolerance_pct = vm["speed-tolerance-pct"].as<double>();
  a.tool_diameter_mm = opt_value(vm, "tool-diameter-mm");
  a.workpiece_diameter_mm = opt_value(vm, "workpiece-diameter-mm");
  a.tangential_coefficient_n_per_m2 = opt_value(vm, "tangential-coefficient-n-per-m2");
  a.radial_immersion = opt_value(vm, "radial-immersion");
  if (vm.count("teeth")) a.teeth = vm["teeth"].as<int>();
  if (vm.count("milling-direction")) a.milling_direction = vm["milling-direction"].as<std::string>();
  a.max_sle_um = opt_value(vm, "max-sle-um");
  a.method = method;
  a.threads = thread_count(vm);
  RecommendPlan plan = recommend_plan(cfg, a, ArgStyle::kFlag);
  RecommendOptions& opt = plan.options;
  const Process& process = plan.process;
  Recommendation r;
  {
    Progress bar(vm, kProgressSteps, "recommend", kProgressAfterS);
    opt.progress = [&](double f) { bar.tick(static_cast<std::size_t>(f * kProgressSteps)); };
    r = recommend(cfg.model, process, opt);
  }
  const std::string text = explain(r, opt);

  if (!json_path.empty()) emit_json(json_path, recommend_record(r, opt, process, record_source(cfg, common.position_mm)));
  (json_path == "-" ? std::cerr : std::cout) << text;
  return 0;
}

}  // namespace chatter::cli
