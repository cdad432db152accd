#include "cli_common.hpp"

#include "chatter/number_text.hpp"
#include "chatter/usual_bands.hpp"

#include <cmath>
#include <iostream>
#include <optional>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "chatter/error.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/records.hpp"
#include "chatter/report.hpp"
#include "../formats/text.hpp"

namespace chatter::cli {

std::string fmt(double x, int digits) {
  return number_text(x, digits);
}

void add_common(po::options_description& d, Common& c) {
  std::string help = "solver: 'auto' (the default: turning analytic, milling sdm; the output names the method used), ";
  const auto& registry = solver_registry();
  for (std::size_t i = 0; i < registry.size(); ++i)
    help += (i == 0 ? "" : i + 1 == registry.size() ? " or " : ", ") + ("'" + registry[i].name + "' (") +
            registry[i].summary + ")";
  c.method = kAutoMethod;
  d.add_options()("method", po::value<std::string>(&c.method)->default_value(c.method), help.c_str());
}

void store_command_line(const std::vector<std::string>& args, const po::options_description& all,
                        const po::positional_options_description& pos, po::variables_map& vm) {
  try {
    po::store(po::command_line_parser(args).options(all).positional(pos).run(), vm);
  } catch (const po::unknown_option& e) {
    std::string given = e.get_option_name();
    given.erase(0, given.find_first_not_of('-'));
    given = given.substr(0, given.find('='));
    // Every long option but the hidden positional ones (CONFIG, FRF-FILE, ...).
    std::vector<std::string> positional;
    for (unsigned i = 0; i < std::min(pos.max_total_count(), 8u); ++i) positional.push_back(pos.name_for_position(i));
    std::vector<std::string> names;
    for (const auto& o : all.options())
      if (!o->long_name().empty() &&
          std::find(positional.begin(), positional.end(), o->long_name()) == positional.end())
        names.push_back(o->long_name());
    const std::vector<std::string_view> views(names.begin(), names.end());
    const std::string_view meant = detail::text::near_miss(given, views);
    if (meant.empty()) throw;
    throw po::error(std::string(e.what()) + " (did you mean --" + std::string(meant) + "?)");
  }
}

// Parses a subcommand's arguments; returns false if --help was printed.
bool parse(const std::vector<std::string>& args, const std::string& usage, po::options_description& visible,
           Common& common, po::variables_map& vm) {
  visible.add_options()("strict", "refuse a config that raises a plausibility warning (exit 2, nothing written)");
  visible.add_options()("position-mm", po::value<double>(),
                        "tool position along a position-dependent structure, mm: from the clamp of a cantilever "
                        "workpiece, or along the path of [[positions]] (docs/position.md)");
  po::options_description hidden;
  hidden.add_options()("config", po::value<std::string>(&common.config_path), "config file");
  po::options_description all;
  all.add(visible).add(hidden);
  all.add_options()("help,h", "show this help");
  po::positional_options_description pos;
  pos.add("config", 1);
  store_command_line(args, all, pos, vm);
  if (vm.count("help")) {
    std::cout << usage << "\n" << visible << "  -h [ --help ]            show this help\n";
    return false;
  }
  po::notify(vm);
  common.strict = vm.count("strict") > 0;
  if (vm.count("position-mm")) common.position_mm = vm["position-mm"].as<double>();
  common.flag_warnings = flag_warnings(vm);
  if (common.config_path.empty()) throw po::error("missing CONFIG (a .toml file, see configs/)");
  return true;
}

std::vector<std::string> flag_warnings(const po::variables_map& vm) {
  std::vector<std::pair<std::string, double>> given;
  for (const auto& [name, value] : vm) {
    if (value.defaulted()) continue;
    const boost::any& v = value.value();
    if (const double* d = boost::any_cast<double>(&v)) given.emplace_back("--" + name, *d);
    else if (const int* i = boost::any_cast<int>(&v)) given.emplace_back("--" + name, *i);
  }
  return unusual_arguments(given);
}

void print_flag_warnings(const po::variables_map& vm, bool strict) {
  const std::vector<std::string> w = flag_warnings(vm);
  if (strict && !w.empty()) {
    std::string message;
    for (const std::string& x : w) message += (message.empty() ? "" : "\n") + x + " (--strict)";
    throw InputError(message);
  }
  for (const std::string& x : w) std::cerr << "warning: " << x << "\n";
}

Config load_checked(const Common& common) {
  Config cfg = load_config(common.config_path);
  cfg.warnings.insert(cfg.warnings.end(), common.flag_warnings.begin(), common.flag_warnings.end());
  if (!cfg.warnings.empty()) {
    if (common.strict) {
      std::string message;
      for (const std::string& w : cfg.warnings) message += (message.empty() ? "" : "\n") + w + " (--strict)";
      throw InputError(message);
    }
    for (const std::string& w : cfg.warnings) std::cerr << "warning: " << w << "\n";
  }
  if (common.position_mm) return config_at_position(cfg, *common.position_mm, "--position-mm");
  return cfg;
}

void add_speed_variation_options(po::options_description& d) {
  d.add_options()
      ("ssv-amplitude", po::value<double>(), "spindle speed variation: amplitude ratio R_VA in [0, 1), the speed "
       "swings +-R_VA around the mean (replaces process.speed_variation.amplitude_ratio; 0: constant speed; methods: "
       "sdm, time-domain)")
      ("ssv-frequency", po::value<double>(), "spindle speed variation: frequency ratio R_VF > 0, modulation "
       "frequency / spindle frequency (replaces process.speed_variation.frequency_ratio)");
}

void apply_speed_variation_options(const po::variables_map& vm, const Common& common, Config& cfg) {
  const bool amp = vm.count("ssv-amplitude") > 0, freq = vm.count("ssv-frequency") > 0;
  if (!amp && !freq) return;
  SpeedVariation v = cfg.process.speed_variation();
  if (!cfg.process.has_speed_variation() && amp != freq)
    throw InputError(std::string(amp ? "--ssv-amplitude" : "--ssv-frequency") + ": needs " +
                     (amp ? "--ssv-frequency" : "--ssv-amplitude") + " too (" + cfg.source.string() +
                     " has no process.speed_variation to take it from)");
  if (amp) v.amplitude_ratio = vm["ssv-amplitude"].as<double>();
  if (freq) v.frequency_ratio = vm["ssv-frequency"].as<double>();
  if (const std::string why = v.validate(); !why.empty()) {
    const bool amplitude_rule = why.rfind("amplitude_ratio", 0) == 0;
    throw InputError(std::string(amplitude_rule ? "--ssv-amplitude" : "--ssv-frequency") +
                     why.substr(why.find(" =")));
  }
  if (v.amplitude_ratio > kLargeSpeedVariation) {
    const std::string w = "--ssv-amplitude = " + fmt(v.amplitude_ratio) + ": a swing of more than +-" +
                          fmt(100.0 * kLargeSpeedVariation) +
                          " % of the mean speed is beyond what spindle drives follow (usual R_VA: 0.05 to 0.3)";
    if (common.strict) throw InputError(w + " (--strict)");
    std::cerr << "warning: " << w << "\n";
    cfg.warnings.push_back(w);
  }
  cfg.process.set_speed_variation(v);
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
  check_spindle_rpm(s.rpm_min, "--rpm-min");
  check_spindle_rpm(s.rpm_max, "--rpm-max");
  if (!(std::isfinite(s.rpm_max) && s.rpm_max > s.rpm_min))
    throw InputError("--rpm-max = " + fmt(s.rpm_max) + ": must be > --rpm-min (" + fmt(s.rpm_min) + ")");
  if (s.rpm_points < 2) throw InputError("--rpm-points = " + std::to_string(s.rpm_points) + ": must be >= 2");
  if (s.rpm_points > kMaxRpmPoints)
    throw InputError("--rpm-points = " + std::to_string(s.rpm_points) + ": at most " + std::to_string(kMaxRpmPoints) +
                     " speeds (a table that size would not finish; refine a speed range instead)");
  if (!(std::isfinite(s.depth_max_mm) && s.depth_max_mm > 0.0))
    throw InputError("--depth-max-mm = " + fmt(s.depth_max_mm) + ": must be > 0 mm");
  return s;
}

namespace {

// Why `file` (named by `flag` on the command line) cannot be written, or "".
std::string unwritable(const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (fs::is_directory(st)) return "is a directory; give a file name";
  if (fs::exists(st) && !fs::is_regular_file(st))  // /dev/null, a pipe: written in place
    return ::access(file.c_str(), W_OK) == 0 ? "" : "cannot write (" + std::string(std::strerror(errno)) + ")";
  const fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  if (!fs::exists(dir, ec)) return "directory " + dir.string() + " does not exist";
  if (!fs::is_directory(dir, ec)) return dir.string() + " is not a directory";
  // The writer creates <file>.partial and renames it: probe exactly that.
  fs::path probe = file;
  probe += ".partial";
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return "";
    return "cannot create a file in " + dir.string() + " (" + std::strerror(errno) + ")";
  }
  ::close(fd);
  fs::remove(probe, ec);
  return "";
}

}  // namespace

void check_outputs(const std::vector<Output>& outputs) {
  namespace fs = std::filesystem;
  std::vector<std::pair<fs::path, std::string>> seen;  // absolute path, flag
  for (const Output& o : outputs) {
    if (o.path.empty()) continue;
    const std::string given = o.flag + " " + o.path + ": ";
    std::vector<fs::path> files{o.path};
    if (o.plot) {
      with_flag(o.flag, [&] { return check_plot_path(o.path); });
      if (fs::path(o.path).stem().empty()) throw InputError(given + "not an image file name");
      for (const char* ext : {".gp", ".dat"}) files.push_back(fs::path(o.path).replace_extension(ext));
    }
    for (const fs::path& f : files) {
      if (const std::string why = unwritable(f); !why.empty())
        throw InputError(given + (f == fs::path(o.path) ? "" : f.string() + ": ") + why + " (nothing written)");
      std::error_code ec;
      const fs::path key = fs::weakly_canonical(fs::absolute(f), ec);
      const std::string what = f == fs::path(o.path) ? std::string()
                               : "the " + o.flag + (f.extension() == ".gp" ? " script " : " data file ") +
                                     f.string() + " is ";
      for (const auto& [p, flag] : seen)
        if (p == key && !(f.string().rfind("/dev/", 0) == 0))
          throw InputError(given + what + "the same file as " + flag + " (nothing written)");
      seen.emplace_back(key, o.flag);
    }
  }
}

double plot_depth_max_mm(const po::variables_map& vm, bool plotting) {
  if (vm.count("plot-depth-max-mm") == 0) return 0.0;
  const double v = vm["plot-depth-max-mm"].as<double>();
  if (!plotting)
    throw InputError("--plot-depth-max-mm: only with --plot or --show (it sets the plot's depth axis)");
  if (!(std::isfinite(v) && v > 0.0)) throw InputError("--plot-depth-max-mm = " + fmt(v) + ": must be > 0 mm");
  return v;
}

}  // namespace chatter::cli

#include <unistd.h>

#include <algorithm>
#include <numbers>
#include <thread>
#include <type_traits>
#include <variant>

namespace chatter::cli {

std::string option_flag(const SolverOption& o) {
  std::string f = "--" + o.name;
  std::replace(f.begin(), f.end(), '_', '-');
  return f;
}

namespace {

// Every command-line solver option once (the first method that lists it
// gives the help), with the methods that take it.
struct CliOption {
  const SolverOption* option;
  std::vector<std::string> methods;
};
std::vector<CliOption> cli_options() {
  std::vector<CliOption> out;
  for (const auto& d : solver_registry())
    for (const auto& o : d.options) {
      if (!o.cli) continue;
      auto it = std::find_if(out.begin(), out.end(), [&](const CliOption& c) { return c.option->name == o.name; });
      if (it == out.end()) out.push_back({&o, {d.name}});
      else it->methods.push_back(d.name);
    }
  return out;
}

}  // namespace

void add_solver_options(po::options_description& d) {
  for (const CliOption& c : cli_options()) {
    const std::string name = option_flag(*c.option).substr(2);
    std::string help;
    for (const auto& m : c.methods) help += (help.empty() ? "" : ", ") + m;
    help += ": " + c.option->help;
    switch (c.option->kind) {
      case SolverOption::Kind::kInt: d.add_options()(name.c_str(), po::value<int>(), help.c_str()); break;
      case SolverOption::Kind::kReal: d.add_options()(name.c_str(), po::value<double>(), help.c_str()); break;
      case SolverOption::Kind::kFlag: d.add_options()(name.c_str(), help.c_str()); break;
    }
  }
  d.add_options()
      ("threads", po::value<int>()->default_value(0), "threads for the sweep (0 = every core); the result does not "
                                                      "depend on it")
      ("quiet,q", "no progress bar");
}

unsigned thread_count(const po::variables_map& vm) {
  const int t = vm.count("threads") ? vm["threads"].as<int>() : 0;
  if (t < 0 || t > 1024) throw InputError("--threads = " + std::to_string(t) + ": must be in [0, 1024] (0 = every core)");
  return static_cast<unsigned>(t);
}

const SolverDescriptor& method_descriptor(const std::string& method, const std::string& flag) {
  return with_flag(flag, [&]() -> const SolverDescriptor& { return find_lobe_method(method); });
}

void check_solver_options(const std::vector<std::string>& methods, const po::variables_map& vm,
                          const std::string& chooser) {
  for (const CliOption& c : cli_options()) {
    const std::string flag = option_flag(*c.option);
    if (vm.count(flag.substr(2)) == 0) continue;
    if (std::any_of(methods.begin(), methods.end(),
                    [&](const std::string& m) { return std::find(c.methods.begin(), c.methods.end(), m) != c.methods.end(); }))
      continue;
    std::string owners;
    for (const auto& m : c.methods) owners += (owners.empty() ? "" : " or ") + m;
    throw InputError(flag + ": only with " +
                     (chooser == "--method" ? "--method " + owners : owners + " among " + chooser));
  }
}

nlohmann::json to_json(const SolverValue& v) {
  return std::visit(
      [](const auto& x) -> nlohmann::json {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, std::monostate>) return nullptr;
        else return x;
      },
      v);
}

std::string cell_text(const SolverValue& v) { return value_text(v); }

std::vector<ExtraColumn> extra_columns(const std::vector<DiagnosticColumn>& columns,
                                       const std::vector<std::vector<SolverValue>>& values) {
  std::vector<ExtraColumn> out;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    ExtraColumn e{columns[c].name, {}, columns[c].numeric};
    for (const auto& row : values) e.values.push_back(c < row.size() ? cell_text(row[c]) : "");
    out.push_back(std::move(e));
  }
  return out;
}

SolverValues solver_option_values(const SolverDescriptor& descriptor, const Config& cfg, const po::variables_map& vm) {
  SolverValues options;
  for (const SolverOption& o : descriptor.options) {
    if (!o.cli) continue;
    const std::string flag = option_flag(o);
    const std::string key = flag.substr(2);
    if (vm.count(key) == 0) continue;
    SolverValue v;
    switch (o.kind) {
      case SolverOption::Kind::kInt: v = vm[key].as<int>(); break;
      case SolverOption::Kind::kReal: v = vm[key].as<double>(); break;
      case SolverOption::Kind::kFlag: v = true; break;
    }
    if (const std::string why = option_violation(o, v); !why.empty()) {
      const std::string given = std::holds_alternative<int>(v) ? std::to_string(std::get<int>(v))
                                                               : fmt(std::get<double>(v));
      throw InputError(flag + " = " + given + ": " + why);
    }
    options[o.name] = v;
  }
  // The config's defaults (the time-domain chip's feed) for the options not given.
  return with_config_defaults(descriptor, cfg, std::move(options));
}

BuiltSolver build_solver(const std::string& requested, const Config& cfg, double depth_max_m,
                         const po::variables_map& vm, bool check_options) {
  // The method as "auto" resolves it, for the options' check and parse.
  const std::string method = with_flag("--method", [&] { return resolve_lobe_method(requested, cfg.model, cfg.process); });
  if (check_options) check_solver_options({method}, vm, "--method");
  const SolverValues given = solver_option_values(method_descriptor(method), cfg, vm);
  ConfiguredSolver c = configure_solver(requested, cfg, depth_max_m, given, ArgStyle::kFlag);
  BuiltSolver b;
  b.method = c.method;
  b.descriptor = c.descriptor;
  b.solver = std::move(c.solver);
  b.recipe = c.recipe();
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : b.descriptor->effective_options(*b.solver)) j[k] = to_json(v);
  b.options = std::move(j);
  b.notes = std::move(c.notes);
  for (const std::string& n : b.notes) std::cerr << "note: " << n << "\n";
  return b;
}

void add_show_option(po::options_description& d) { d.add_options()("show", kShowHelp); }

namespace {

// The executable `name` in a PATH directory, or "".
std::string on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  const std::string dirs = path;
  for (std::size_t start = 0; start <= dirs.size();) {
    std::size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = dirs.substr(start, end - start);
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return {};
}

// The terminals this gnuplot was built with (GPVAL_TERMINALS), one start of gnuplot.
std::string gnuplot_terminals(const std::string& gnuplot) {
  std::string out;
  const std::string cmd = "'" + gnuplot + "' -e 'print GPVAL_TERMINALS' 2>&1 </dev/null";
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    ::pclose(p);
  }
  return " " + out + " ";
}

bool has_word(const std::string& list, const std::string& word) {
  return list.find(" " + word + " ") != std::string::npos || list.find(" " + word + "\n") != std::string::npos;
}

}  // namespace

ShowRequest show_request(const po::variables_map& vm) {
  ShowRequest r;
  if (!vm.count("show")) return r;
  r.requested = true;
  const std::string gnuplot = on_path("gnuplot");
  if (gnuplot.empty())
    throw InputError("--show: gnuplot not found on PATH (Debian: apt install gnuplot-qt for windows, gnuplot-nox "
                     "for images and text plots)");
  const char* env_term = std::getenv("GNUPLOT_TERM");
  if (env_term && *env_term) {
    // Sent as `set terminal` (gnuplot reading a pipe starts on no terminal);
    // checked here so that a typo fails before the computation, not after it.
    std::string term = env_term;
    term = term.substr(0, term.find(' '));
    if (!has_word(gnuplot_terminals(gnuplot), term))
      throw InputError("--show: GNUPLOT_TERM=" + std::string(env_term) + ": not a terminal of " + gnuplot +
                       " (gnuplot -e 'print GPVAL_TERMINALS' lists them; dumb draws text)");
    r.terminal = env_term;
    r.where = "gnuplot terminal " + std::string(env_term);
    r.text = term == "dumb";
    return r;
  }
  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if (!(display && *display) && !(wayland && *wayland))
    throw InputError("--show: no display (DISPLAY is not set), so no window can open; draw an image with --plot FILE, "
                     "or set GNUPLOT_TERM=dumb for a text plot on standard output");
  const std::string terminals = gnuplot_terminals(gnuplot);
  for (const char* t : {"qt", "wxt", "x11"})
    if (has_word(terminals, t)) {
      r.terminal = std::string(t) + " size 1200,800 enhanced font 'DejaVu Sans,12'";
      r.where = std::string("a gnuplot ") + t + " window";
      return r;
    }
  throw InputError("--show: " + gnuplot + " has no window terminal (qt, wxt or x11; Debian's gnuplot-nox has none): "
                   "install gnuplot-qt, draw an image with --plot FILE, or set GNUPLOT_TERM=dumb for a text plot");
}

Progress::Progress(const po::variables_map& vm, std::size_t total, std::string label, double show_after_s)
    : enabled_(vm.count("quiet") == 0 && total > 1 && (::isatty(STDERR_FILENO) == 1 || vm.count("progress") > 0)),
      lines_(::isatty(STDERR_FILENO) != 1),
      total_(total),
      label_(std::move(label)),
      start_(std::chrono::steady_clock::now()),
      last_(start_),
      show_after_(show_after_s) {}

Progress::~Progress() {
  if (enabled_ && shown_ && !lines_) std::cerr << "\r\033[K" << std::flush;  // clear the line
  // A log asked for with --progress ends with a line saying so, however short the work.
  if (enabled_ && lines_)
    std::cerr << label_ << ": done after "
              << fmt(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(), 3) << " s\n"
              << std::flush;
}

void Progress::tick(std::size_t done) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < show_after_) return;
  // A log (--progress on a non-terminal) gets a line a second, a terminal a
  // redrawn bar ten times a second.
  if (shown_ && done < total_ && now - last_ < std::chrono::milliseconds(lines_ ? 1000 : 100)) return;
  last_ = now;
  shown_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double frac = static_cast<double>(done) / static_cast<double>(total_);
  const double left = frac > 0 ? elapsed * (1 - frac) / frac : 0.0;
  if (lines_) {
    std::cerr << label_ << ": " << static_cast<int>(frac * 100) << "% after " << fmt(elapsed, 3) << " s, about "
              << fmt(left, 2) << " s left\n"
              << std::flush;
    return;
  }
  const int width = 30, filled = static_cast<int>(frac * width);
  std::cerr << "\r" << label_ << " [" << std::string(static_cast<std::size_t>(filled), '#')
            << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << static_cast<int>(frac * 100)
            << "%  " << fmt(left, 2) << " s left   " << std::flush;
}

}  // namespace chatter::cli
