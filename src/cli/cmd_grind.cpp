// `chatter grind predict|sweep|simulate|plan` (and the dispatch of fit and
// impacts, src/cli/cmd_grind_data.cpp): robotic grinding at controlled power
// (docs/grinding.md). The numbers come from the library (chatter/grinding*.hpp),
// the records from the io layer (chatter/io/grinding_io.hpp): this file parses
// flags, checks outputs before computing, prints a short report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/grinding_dynamics.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/records/grinding.hpp"
#include "chatter/io/plot_grinding.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/kinematics.hpp"
#include "cli_common.hpp"
#include "cmd_grind.hpp"
#include "commands.hpp"

namespace chatter::cli {

namespace {

const char* const kGrindHelp = R"(Usage: chatter grind <command> ... [options]

Robotic grinding at controlled power (docs/grinding.md): a compliant robot
holds the wheel against the part and controls the spindle power; removal,
depth and forces follow from the power. The config has a [grinding] table
(see configs/grinding_*.toml).

Commands:
  predict   CONFIG --power-w P | --target-depth-mm H | --target-removal-mm3-per-s Z
            removal rate, depth, groove width, forces, friction/chip power,
            energy into the part, impacts per turn; the inverse modes give the
            power for a target.
  sweep     CONFIG --power-w-min A --power-w-max B [--feed-mm-per-s-list 40,60,80]
            table and plot of depth, removal and force against power.
  fit       TESTS.csv --model mechanistic|poly11|poly22|poly33|power_law|hahn_lindsay
            coefficients from test logs, with 95 % intervals, R^2, RMSE, MAE,
            MAPE, residuals; --out writes a [grinding] table.
  impacts   FORCE.csv --wheel-rpm N
            impacts per wheel turn in a normal-force (or wheel-speed) record.
  simulate  CONFIG --power-w P
            the robot's modes ([[tool.modes]]) pressed by its power loop:
            impacts per turn, contact, force peaks (a model to calibrate).
  plan      CONFIG --volume-mm3 V (or --area-mm2 A --depth-mm D) --power-w P (or --current-a I)
            [--objective removal|g-ratio --wheel-rpm-min A --wheel-rpm-max B]
            wheels, grinding time and wheel changes for a repair.

Run 'chatter grind <command> --help' for its options.
)";

}  // namespace

bool parse_grind(const std::vector<std::string>& args, const char* usage, po::options_description& d, const char* name,
                 po::variables_map& vm, std::string& positional, bool config) {
  if (config)
    d.add_options()("strict", "refuse a config that raises a plausibility warning (exit 2, nothing written)");
  po::options_description hidden;
  hidden.add_options()(name, po::value<std::string>(&positional), name);
  po::options_description all;
  all.add(d).add(hidden);
  all.add_options()("help,h", "show this help");
  po::positional_options_description pos;
  pos.add(name, 1);
  store_command_line(args, all, pos, vm);
  if (vm.count("help")) {
    std::cout << usage << "\n" << d << "  -h [ --help ]            show this help\n";
    return false;
  }
  po::notify(vm);
  print_flag_warnings(vm, vm.count("strict") > 0);
  if (positional.empty()) throw po::error(std::string("missing ") + name);
  return true;
}

GrindingConfig load_grinding_checked(const std::string& path, bool strict) {
  GrindingConfig c = load_grinding_config(path);
  if (!c.warnings.empty()) {
    if (strict) {
      std::string message;
      for (const std::string& w : c.warnings) message += (message.empty() ? "" : "\n") + w + " (--strict)";
      throw InputError(message);
    }
    for (const std::string& w : c.warnings) std::cerr << "warning: " << w << "\n";
  }
  return c;
}

void require_positive(const po::variables_map& vm, const char* flag, const char* unit) {
  if (!vm.count(flag)) return;
  const double v = vm[flag].as<double>();
  if (!(std::isfinite(v) && v > 0.0))
    throw InputError(std::string("--") + flag + " = " + fmt(v) + ": must be > 0" + (*unit ? " " : "") + unit);
}

void print_plot(std::ostream& os, const PlotFiles& pf) {
  os << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
     << pf.data.string() << ")\n";
}

std::string grind_number(double x) { return fmt(x, 4); }

namespace {

std::string f6(double x) { return grind_number(x); }

// ------------------------------------------------------------------ predict

const char* const kPredictUsage = R"(Usage: chatter grind predict CONFIG (--power-w P | --target-depth-mm H | --target-removal-mm3-per-s Z | --current-a I) [options]

What a power set-point gives (or a motor current, through the config's motor
map and no-load loss), or the power for a target depth (the groove's maximum
depth h0) or removal rate: removal (mm^3/s, kg/h), depth, groove
width, depth per pass, tangential and normal force, friction and chip power,
specific energy, energy partition and heat into the part, impacts per turn,
contact half-angle and duration, cutting speed; the empirical models beside
the mechanistic ones, with a warning outside their tested domain, and their
intervals when the config carries the fit's statistics ([grinding.models.X.fit],
as `grind fit --out` writes them): the 95 % confidence interval of the fitted
mean (the seed's "59.28 +- 2.03 mm^3/s") and the wider 95 % prediction
interval of one test.

Example:
  chatter grind predict configs/grinding_scompi_ch4.toml --power-w 1000 --json -
)";

// The empirical models' intervals, one line each.
void print_intervals(std::ostream& os, const grinding::EmpiricalPrediction& e) {
  auto line = [&](const char* what, const std::optional<grinding::PredictionInterval>& i, const char* unit) {
    if (!i) return;
    os << "    " << what << " " << f6(i->value) << " " << unit << ": 95 % of the mean " << f6(i->mean_95.lo) << " to "
       << f6(i->mean_95.hi) << ", 95 % of one test " << f6(i->test_95.lo) << " to " << f6(i->test_95.hi);
    if (!i->log_scale) os << " (standard error of the mean " << f6(i->standard_error_mean) << ")";
    os << "\n";
  };
  line("removal        ", e.removal_interval, "mm^3/s");
  line("depth per pass ", e.depth_per_pass_interval, "mm");
  line("wear           ", e.wear_interval, "mm^3/s");
  line("normal force   ", e.normal_force_interval, "N");
}

int cmd_predict(const std::vector<std::string>& args) {
  std::string config, json_path;
  po::options_description d("Options");
  d.add_options()("power-w", po::value<double>(), "useful grinding power at the wheel, W")
      ("target-depth-mm", po::value<double>(), "target maximum depth of the groove, mm (gives the power)")
      ("target-removal-mm3-per-s", po::value<double>(), "target removal rate, mm^3/s (gives the power)")
      ("current-a", po::value<double>(), "the motor current the operator sets, A: the useful power is the motor "
                                         "map's ([grinding.motor]) minus the no-load loss")
      ("json", po::value<std::string>(&json_path), "write the JSON record to this file ('-': standard output, the "
                                                  "report then goes to standard error)");
  po::variables_map vm;
  if (!parse_grind(args, kPredictUsage, d, "config", vm, config)) return 0;
  const int modes = static_cast<int>(vm.count("power-w") + vm.count("target-depth-mm") +
                                     vm.count("target-removal-mm3-per-s") + vm.count("current-a"));
  if (modes != 1)
    throw InputError("give exactly one of --power-w, --target-depth-mm, --target-removal-mm3-per-s, --current-a (" +
                     std::to_string(modes) + " given)");
  check_outputs({{"--json", json_path == "-" ? "" : json_path}});
  const GrindingConfig c = load_grinding_checked(config, vm.count("strict") > 0);
  grinding::Prediction p;
  if (vm.count("power-w"))
    p = with_flag("--power-w", [&] { return grinding::predict_at_power(c.process, vm["power-w"].as<double>()); });
  else if (vm.count("current-a"))
    p = with_flag("--current-a", [&] { return grinding::predict_at_current(c.process, vm["current-a"].as<double>()); });
  else if (vm.count("target-depth-mm"))
    p = with_flag("--target-depth-mm",
                  [&] { return grinding::predict_for_depth(c.process, vm["target-depth-mm"].as<double>() * 1e-3); });
  else
    p = with_flag("--target-removal-mm3-per-s", [&] {
      return grinding::predict_for_removal(c.process, vm["target-removal-mm3-per-s"].as<double>() * 1e-9);
    });
  const std::string json = grinding_prediction_record(p, c).dump(2) + "\n";
  if (!json_path.empty() && json_path != "-") write_text_file(json_path, json);

  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << config << " (" << c.name << "): " << f6(p.power_w) << " W at " << f6(rpm_from_revolutions_per_s(c.process.wheel.speed_rev_per_s))
     << " rev/min, " << f6(c.process.feed_m_per_s * 1e3) << " mm/s (" << p.removal_source << " removal model)\n"
     << "  removal rate       " << f6(p.removal_rate_m3_per_s * 1e9) << " mm^3/s";
  if (p.removal_rate_kg_per_h) os << " (" << f6(*p.removal_rate_kg_per_h) << " kg/h)";
  os << "\n  maximum depth      " << f6(p.max_depth_m * 1e3) << " mm; groove width " << f6(p.groove_width_m * 1e3)
     << " mm; depth per pass " << f6(p.depth_per_pass_m * 1e3) << " mm\n"
     << "  forces             tangential " << f6(p.tangential_force_n) << " N, normal " << f6(p.normal_force_n)
     << " N (power / cutting speed, normal = tangential / force_ratio)\n";
  if (p.friction_power_w)
    os << "  power split        friction " << f6(*p.friction_power_w) << " W + chip " << f6(*p.chip_power_w) << " W\n";
  os << "  specific energy    " << f6(p.specific_energy_j_per_m3 * 1e-9) << " J/mm^3\n";
  if (p.energy_partition) {
    os << "  into the part      " << f6(p.energy_partition->fraction) << " ("
       << grinding::partition_model_name(p.energy_partition->model);
    if (p.energy_partition->beta)
      os << ", alpha " << f6(*p.energy_partition->alpha) << ", beta " << f6(*p.energy_partition->beta);
    os << "): " << f6(p.energy_partition->heat_into_part_w) << " W\n";
  }
  if (p.impacts_per_turn) os << "  impacts per turn   " << f6(*p.impacts_per_turn) << "\n";
  os << "  contact            half-angle " << f6(p.contact_half_angle_rad * 180 / 3.14159265358979) << " deg, "
     << f6(p.contact_duration_s * 1e3) << " ms per impact; cutting speed " << f6(p.cutting_speed_m_per_s) << " m/s\n";
  if (p.motor_power_w) {
    os << "  motor power        " << f6(*p.motor_power_w) << " W";
    if (p.motor_current_a) os << " at " << f6(*p.motor_current_a) << " A";
    if (p.no_load_loss_w) os << " (no-load loss " << f6(*p.no_load_loss_w) << " W)";
    os << "\n";
  }
  if (p.empirical) {
    os << "  empirical models  ";
    if (p.empirical->removal_rate_m3_per_s) os << " removal " << f6(*p.empirical->removal_rate_m3_per_s * 1e9) << " mm^3/s;";
    if (p.empirical->normal_force_n)
      os << " normal force " << f6(*p.empirical->normal_force_n) << " N (the fitted model's, beside the force ratio's above);";
    if (p.empirical->wear_rate_m3_per_s) os << " wear " << f6(*p.empirical->wear_rate_m3_per_s * 1e9) << " mm^3/s;";
    if (p.empirical->g_ratio) os << " G-ratio " << f6(*p.empirical->g_ratio) << ";";
    os << "\n";
    print_intervals(os, *p.empirical);
  }
  for (const std::string& w : p.warnings) std::cerr << "warning: " << w << "\n";
  if (json_path == "-") std::cout << json;
  else if (!json_path.empty()) os << "wrote JSON: " << json_path << "\n";
  return 0;
}

// -------------------------------------------------------------------- sweep

const char* const kSweepUsage = R"(Usage: chatter grind sweep CONFIG --power-w-min A --power-w-max B [options]

Depth, removal and force against power: a CSV table (units in the column
names; standard output unless --table) and a plot (three panels, one curve
per feed; the powers the impacts table and the empirical models were measured
over shaded).

Example:
  chatter grind sweep configs/grinding_scompi_ch4.toml --power-w-min 250 --power-w-max 2500 \
      --feed-mm-per-s-list 40,60,80 --table sweep.csv --plot sweep.png
)";

std::vector<double> parse_list(const std::string& text, const char* flag) {
  std::vector<double> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && item[used] == ' ') ++used;
    if (item.empty() || used != item.size())
      throw InputError(std::string("--") + flag + " '" + text + "': '" + item + "' is not a number (a comma-separated list)");
    out.push_back(v);
  }
  return out;
}

int cmd_sweep(const std::vector<std::string>& args) {
  std::string config, table_path, plot_path, feeds_text;
  double pmin = 0.0, pmax = 0.0;
  int points = 46;
  po::options_description d("Options");
  d.add_options()("power-w-min", po::value<double>(&pmin)->required(), "lowest power, W (required)")
      ("power-w-max", po::value<double>(&pmax)->required(), "highest power, W (required)")
      ("points", po::value<int>(&points)->default_value(46), "powers, evenly spaced, both ends included")
      ("feed-mm-per-s-list", po::value<std::string>(&feeds_text), "feeds, mm/s, comma-separated (default: the config's)")
      ("table", po::value<std::string>(&table_path), "write the CSV table here (default: standard output)")
      ("plot", po::value<std::string>(&plot_path), "draw the sweep (.png, .svg or .pdf; script and data beside it)");
  po::variables_map vm;
  if (!parse_grind(args, kSweepUsage, d, "config", vm, config)) return 0;
  std::vector<double> feeds;
  if (!feeds_text.empty())
    for (double f : parse_list(feeds_text, "feed-mm-per-s-list")) feeds.push_back(f * 1e-3);
  check_outputs({{"--table", table_path == "-" ? "" : table_path}, {"--plot", plot_path, true}});
  const GrindingConfig c = load_grinding_checked(config, vm.count("strict") > 0);
  const auto curves = with_flag("sweep", [&] { return grinding::sweep_power(c.process, pmin, pmax, points, feeds); });
  const std::string csv = grinding_sweep_csv(curves);
  const bool to_stdout = table_path.empty() || table_path == "-";
  if (!to_stdout) write_text_file(table_path, csv);
  std::ostream& os = to_stdout ? std::cerr : std::cout;
  // One warning per kind (the text before its first number), with how many
  // points of the sweep raised it.
  std::vector<std::pair<std::string, int>> warned;
  for (const auto& curve : curves)
    for (const auto& p : curve.points)
      for (const auto& w : p.warnings) {
        const std::string key = w.substr(0, w.find_first_of("0123456789"));
        auto it = std::find_if(warned.begin(), warned.end(),
                               [&](const auto& x) { return x.first.substr(0, key.size()) == key; });
        if (it == warned.end()) warned.emplace_back(w, 1);
        else ++it->second;
      }
  for (const auto& [w, n] : warned)
    std::cerr << "warning: " << w << (n > 1 ? " (and " + std::to_string(n - 1) + " more points of the sweep like it)" : "")
              << "\n";
  if (to_stdout) std::cout << csv;
  else os << "wrote table: " << table_path << " (" << curves.size() * curves.front().points.size() << " rows)\n";
  if (!plot_path.empty())
    print_plot(os, plot_grinding_sweep(plot_path, c.name + ": grinding against power", curves,
                                       grinding::operating_envelope(c.process)));
  return 0;
}

// ----------------------------------------------------------------- simulate

const char* const kSimulateUsage = R"(Usage: chatter grind simulate CONFIG --power-w P [options]

The robot's modes along the normal ([[tool.modes]], direction y into the
part) pressed against the part by its power loop, with seed 001's contact
force only while the wheel penetrates the surface the previous turn left
(docs/grinding.md, "Dynamics": a model to calibrate, the seeds give no robot
modes). Reports impacts per turn, turns without contact, contact fraction,
force peaks, and the removal it implies; JSON, the last turns as CSV, a plot.

Example:
  chatter grind simulate configs/grinding_scompi_ch4.toml --power-w 1000 --plot sim.png
)";

int cmd_simulate_grinding(const std::vector<std::string>& args) {
  std::string config, json_path, series_path, plot_path;
  double power = 0.0;
  grinding::DynamicsOptions o;
  po::options_description d("Options");
  d.add_options()("power-w", po::value<double>(&power)->required(), "useful grinding power, W (required)")
      ("turns", po::value<int>(&o.turns)->default_value(o.turns), "wheel turns simulated (the last half analysed)")
      ("points-per-turn", po::value<int>(&o.points_per_turn)->default_value(o.points_per_turn),
       "grid of the groove memory per turn")
      ("power-loop-turns", po::value<double>(&o.power_loop_turns)->default_value(o.power_loop_turns),
       "time constant of the robot's power loop, wheel turns")
      ("series-turns", po::value<int>(&o.series_turns)->default_value(o.series_turns), "last turns kept for --series and --plot")
      ("json", po::value<std::string>(&json_path), "write the JSON record here ('-': standard output)")
      ("series", po::value<std::string>(&series_path), "write the last turns as CSV (time_s, depth_mm, surface_mm, "
                                                      "contact_force_n, push_n)")
      ("plot", po::value<std::string>(&plot_path), "draw the last turns (.png, .svg or .pdf)");
  po::variables_map vm;
  if (!parse_grind(args, kSimulateUsage, d, "config", vm, config)) return 0;
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--series", series_path}, {"--plot", plot_path, true}});
  const GrindingConfig c = load_grinding_checked(config, vm.count("strict") > 0);
  auto flagged = [](const std::string& msg) {
    // Library option names to the flags that set them.
    for (const char* n : {"turns", "points_per_turn", "power_loop_turns", "series_turns", "power_w"}) {
      std::string flag = n;
      for (char& ch : flag) ch = ch == '_' ? '-' : ch;
      if (msg.rfind(std::string(n) + " = ", 0) == 0) return "--" + flag + msg.substr(std::string(n).size());
    }
    return msg;
  };
  grinding::DynamicsResult r;
  try {
    r = grinding::simulate_grinding(c.process, c.robot, power, o);
  } catch (const InputError& e) {
    throw InputError(c.source.string() + ": " + flagged(e.what()));
  }
  const std::string json = grinding_simulation_record(r, c).dump(2) + "\n";
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!json_path.empty() && json_path != "-") files.emplace_back(json_path, json);
  if (!series_path.empty()) files.emplace_back(series_path, grinding_series_csv(r));
  write_text_files(files);
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << config << ": " << f6(power) << " W, " << r.turns << " turns simulated (analysed from turn "
     << r.analysed_from_turn << ")\n"
     << "  impacts per turn      " << f6(r.impacts_per_turn) << (r.continuous ? " (continuous contact)" : "") << "\n"
     << "  turns without contact " << f6(100 * r.turns_without_contact) << " %; in contact "
     << f6(100 * r.contact_fraction) << " % of the time\n"
     << "  normal force          mean " << f6(r.mean_normal_force_n) << " N, peak " << f6(r.peak_normal_force_n)
     << " N (mean of contact peaks " << f6(r.mean_contact_peak_n) << " N)\n"
     << "  removal               " << f6(r.removal_rate_m3_per_s * 1e9) << " mm^3/s (quasi-static "
     << f6(r.quasi_static.removal_rate_m3_per_s * 1e9) << " mm^3/s";
  if (r.removal_at_simulated_impacts_m3_per_s)
    os << "; with the simulated impacts as n_c " << f6(*r.removal_at_simulated_impacts_m3_per_s * 1e9) << " mm^3/s";
  os << ")\n  stiffness             robot " << fmt(r.robot_stiffness_n_per_m, 3) << " N/m, contact "
     << fmt(r.contact_stiffness_n_per_m, 3) << " N/m\n";
  if (json_path == "-") std::cout << json;
  if (!series_path.empty()) os << "wrote series: " << series_path << "\n";
  if (!plot_path.empty())
    print_plot(os, plot_grinding_simulation(plot_path, c.name + ": " + f6(power) + " W, last turns", r));
  return 0;
}

}  // namespace

int cmd_grind(const std::vector<std::string>& args) {
  if (args.empty() || args.front() == "--help" || args.front() == "-h" || args.front() == "help") {
    (args.empty() ? std::cerr : std::cout) << kGrindHelp;
    return args.empty() ? 2 : 0;
  }
  const std::string sub = args.front();
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (sub == "predict") return cmd_predict(rest);
  if (sub == "sweep") return cmd_sweep(rest);
  if (sub == "fit") return cmd_grind_fit(rest);
  if (sub == "impacts") return cmd_grind_impacts(rest);
  if (sub == "simulate") return cmd_simulate_grinding(rest);
  if (sub == "plan") return cmd_grind_plan(rest);
  throw InputError("grind: unknown command '" + sub +
                   "' (commands: predict, sweep, fit, impacts, simulate, plan; see chatter grind --help)");
}

}  // namespace chatter::cli
