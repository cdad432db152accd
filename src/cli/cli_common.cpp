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
       "solver: 'analytic' (transfer function, eigenvalues of H0*G) or 'coupled' "
       "(tool-workpiece characteristic determinant); both are exact and must agree");
}

// Parses a subcommand's arguments; returns false if --help was printed.
bool parse(const std::vector<std::string>& args, const std::string& usage, po::options_description& visible,
           Common& common, po::variables_map& vm) {
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
  if (common.config_path.empty()) throw po::error("missing CONFIG (a .toml file, see configs/)");
  return true;
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
