#include "cli_common.hpp"

#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "chatter/error.hpp"

namespace chatter::cli {

std::string fmt(double x, int digits) {
  std::ostringstream os;
  os.precision(digits);
  os << x;
  return os.str();
}

void add_common(po::options_description& d, Common& c) {
  d.add_options()
      ("method", po::value<std::string>(&c.method)->default_value("analytic"),
       "solver: 'analytic' (transfer function, eigenvalues of H0*G), 'coupled' "
       "(tool-workpiece characteristic determinant; must agree with analytic) or 'sdm' "
       "(semi-discretisation / Floquet: sees the flip lobes of low-immersion milling; slower) or "
       "'time-domain' (simulation with the real chip; the depth where the simulated cut starts to chatter; "
       "about 0.3 s per speed)");
}

// Parses a subcommand's arguments; returns false if --help was printed.
bool parse(const std::vector<std::string>& args, const std::string& usage, po::options_description& visible,
           Common& common, po::variables_map& vm) {
  visible.add_options()("strict", "refuse a config that raises a plausibility warning (exit 2, nothing written)");
  po::options_description hidden;
  hidden.add_options()("config", po::value<std::string>(&common.config_path), "config file");
  po::options_description all;
  all.add(visible).add(hidden);
  all.add_options()("help,h", "show this help");
  po::positional_options_description pos;
  pos.add("config", 1);
  po::store(po::command_line_parser(args).options(all).positional(pos).run(), vm);
  if (vm.count("help")) {
    std::cout << usage << "\n" << visible << "  -h [ --help ]            show this help\n";
    return false;
  }
  po::notify(vm);
  common.strict = vm.count("strict") > 0;
  if (common.config_path.empty()) throw po::error("missing CONFIG (a .toml file, see configs/)");
  return true;
}

Config load_checked(const Common& common) {
  Config cfg = load_config(common.config_path);
  if (cfg.warnings.empty()) return cfg;
  if (common.strict) {
    std::string message;
    for (const std::string& w : cfg.warnings) message += (message.empty() ? "" : "\n") + w + " (--strict)";
    throw InputError(message);
  }
  for (const std::string& w : cfg.warnings) std::cerr << "warning: " << w << "\n";
  return cfg;
}

Sweep resolve_sweep(const po::variables_map& vm, const Config& cfg) {
  Sweep s;
  auto pick = [&](const char* flag, const std::optional<double>& from_cfg, const char* key) -> double {
    if (vm.count(flag)) return vm[flag].as<double>();
    if (from_cfg) return *from_cfg;
    throw InputError(cfg.source.string() + ": missing --" + flag + " (or " + key + " in the config)");
  };
  s.rpm_min = pick("rpm-min", cfg.sweep.rpm_min, "sweep.rpm_min");
  s.rpm_max = pick("rpm-max", cfg.sweep.rpm_max, "sweep.rpm_max");
  if (vm.count("rpm-points")) s.rpm_points = vm["rpm-points"].as<int>();
  else if (cfg.sweep.rpm_points) s.rpm_points = *cfg.sweep.rpm_points;
  if (vm.count("depth-max-mm")) s.depth_max_mm = vm["depth-max-mm"].as<double>();
  else if (cfg.sweep.depth_max_mm) s.depth_max_mm = *cfg.sweep.depth_max_mm;
  if (!(std::isfinite(s.rpm_min) && s.rpm_min > 0.0))
    throw InputError("--rpm-min = " + fmt(s.rpm_min) + ": must be > 0 rev/min");
  if (!(std::isfinite(s.rpm_max) && s.rpm_max > s.rpm_min))
    throw InputError("--rpm-max = " + fmt(s.rpm_max) + ": must be > --rpm-min (" + fmt(s.rpm_min) + ")");
  if (s.rpm_points < 2) throw InputError("--rpm-points = " + std::to_string(s.rpm_points) + ": must be >= 2");
  if (!(std::isfinite(s.depth_max_mm) && s.depth_max_mm > 0.0))
    throw InputError("--depth-max-mm = " + fmt(s.depth_max_mm) + ": must be > 0 mm");
  return s;
}

}  // namespace chatter::cli

#include <unistd.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <numbers>
#include <thread>

namespace chatter::cli {

void add_solver_options(po::options_description& d) {
  d.add_options()
      ("steps", po::value<int>(), "sdm: steps per delay period (default 64; the step is also at most 1/64 of the "
                                  "shortest natural period); more steps: more accurate, slower")
      ("periods", po::value<int>(), "time-domain: delay periods simulated per verdict (default 200; the last half is "
                                    "analysed); more: sharper verdict near the limit, slower")
      ("feed-per-tooth-mm", po::value<double>(), "time-domain: feed per tooth (milling) or per revolution (turning), "
                                                 "mm (default: [process] feed_per_tooth_mm / feed_per_rev_mm, else 0.1); "
                                                 "sets where the tool leaves the cut")
      ("multiple-regeneration", "time-domain: the chip is cut from the surface left by all earlier passes")
      ("linear", "time-domain: linear delay equation (no static chip, the tool never leaves the cut); the verdict "
                 "is the growth factor per period")
      ("threads", po::value<int>()->default_value(0), "threads for the sweep (0 = every core); the result does not "
                                                      "depend on it")
      ("quiet,q", "no progress bar");
}

unsigned thread_count(const po::variables_map& vm) {
  const int t = vm.count("threads") ? vm["threads"].as<int>() : 0;
  if (t < 0 || t > 1024) throw InputError("--threads = " + std::to_string(t) + ": must be in [0, 1024] (0 = every core)");
  return static_cast<unsigned>(t);
}

void check_solver_options(const std::vector<std::string>& methods, const po::variables_map& vm,
                          const std::string& chooser) {
  const auto refuse_without = [&](const char* opt, const std::string& method) {
    if (vm.count(opt) == 0 || std::find(methods.begin(), methods.end(), method) != methods.end()) return;
    throw InputError(std::string("--") + opt + ": only with " +
                     (chooser == "--method" ? "--method " + method : method + " among " + chooser));
  };
  for (const char* opt : {"periods", "feed-per-tooth-mm", "multiple-regeneration", "linear"})
    refuse_without(opt, "time-domain");
  refuse_without("steps", "sdm");
}

BuiltSolver build_solver(const std::string& method, const Config& cfg, double depth_max_m,
                         const po::variables_map& vm, bool check_options) {
  BuiltSolver b;
  if (check_options) check_solver_options({method}, vm, "--method");
  if (method == "sdm") {
    SemiDiscretizationOptions o;
    o.depth_max_m = depth_max_m;
    if (vm.count("steps")) {
      o.steps_per_period = vm["steps"].as<int>();
      if (o.steps_per_period < 1)
        throw InputError("--steps = " + std::to_string(o.steps_per_period) + ": must be >= 1");
      o.steps_per_vibration_cycle = o.steps_per_period;
    }
    auto s = std::make_unique<SemiDiscretizationSolver>(cfg.model, cfg.process, o);
    b.sdm = s.get();
    b.solver = std::move(s);
    b.options_json = nlohmann::json{{"depth_max_m", o.depth_max_m},
                                    {"steps_per_period", o.steps_per_period},
                                    {"steps_per_vibration_cycle", o.steps_per_vibration_cycle},
                                    {"depth_tolerance", o.depth_tolerance}}
                         .dump();
    return b;
  }
  if (method == "time-domain") {
    TimeDomainOptions o;
    o.depth_max_m = depth_max_m;
    if (vm.count("periods")) {
      o.periods = vm["periods"].as<int>();
      if (o.periods < 20 || o.periods > 100000)
        throw InputError("--periods = " + std::to_string(o.periods) + ": must be in [20, 100000]");
    }
    if (vm.count("feed-per-tooth-mm")) {
      const double f = vm["feed-per-tooth-mm"].as<double>();
      if (!(std::isfinite(f) && f >= 0.0 && f <= 100.0))
        throw InputError("--feed-per-tooth-mm = " + fmt(f) + ": must be in [0, 100] mm");
      o.feed_m = f * 1e-3;
    } else if (cfg.feed_mm) {
      o.feed_m = *cfg.feed_mm * 1e-3;  // [process] feed_per_tooth_mm / feed_per_rev_mm, validated by the loader
    }
    o.multiple_regeneration = vm.count("multiple-regeneration") > 0;
    o.linear = vm.count("linear") > 0;
    auto s = std::make_unique<TimeDomainSolver>(cfg.model, cfg.process, o);
    b.td = s.get();
    b.solver = std::move(s);
    b.options_json = nlohmann::json{{"depth_max_m", o.depth_max_m},
                                    {"periods", o.periods},
                                    {"feed_m", o.feed_m},
                                    {"linear", o.linear},
                                    {"multiple_regeneration", o.multiple_regeneration},
                                    {"relative_tolerance", o.relative_tolerance},
                                    {"depth_tolerance", o.depth_tolerance}}
                         .dump();
    return b;
  }
  TransferFunctionOptions o;
  o.depth_max_m = depth_max_m;
  auto s = make_transfer_function_solver(method, cfg.model, cfg.process, o);
  const auto band = s->band();
  b.options_json = nlohmann::json{{"depth_max_m", o.depth_max_m},
                                  {"max_phase_step_rad", o.max_phase_step_rad},
                                  {"search_band_hz",
                                   {band.omega_min_rad_s / (2 * std::numbers::pi),
                                    band.omega_max_rad_s / (2 * std::numbers::pi)}},
                                  {"frequency_grid_points", band.grid_points},
                                  {"frequency_resolution_hz", cfg.model.frequency_resolution_hz()}}
                       .dump();
  b.tf = s.get();
  b.solver = std::move(s);
  return b;
}

Progress::Progress(const po::variables_map& vm, std::size_t total, std::string label, double show_after_s)
    : enabled_(vm.count("quiet") == 0 && ::isatty(STDERR_FILENO) == 1 && total > 1),
      total_(total),
      label_(std::move(label)),
      start_(std::chrono::steady_clock::now()),
      last_(start_),
      show_after_(show_after_s) {}

Progress::~Progress() {
  if (enabled_ && shown_) std::cerr << "\r\033[K" << std::flush;  // clear the line
}

void Progress::tick(std::size_t done) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < show_after_) return;
  if (shown_ && done < total_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  shown_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double frac = static_cast<double>(done) / static_cast<double>(total_);
  const double left = frac > 0 ? elapsed * (1 - frac) / frac : 0.0;
  const int width = 30, filled = static_cast<int>(frac * width);
  std::cerr << "\r" << label_ << " [" << std::string(static_cast<std::size_t>(filled), '#')
            << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << static_cast<int>(frac * 100)
            << "%  " << fmt(left, 2) << " s left   " << std::flush;
}

}  // namespace chatter::cli
