// `chatter point`: one operating point, the limit at its speed and the
// method's analysis at the depth (chatter/report.hpp), printed as the
// library's record (chatter/records.hpp; every key: docs/results.md).
#include <boost/program_options.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "chatter/io/config.hpp"
#include "chatter/records.hpp"
#include "chatter/report.hpp"

namespace po = boost::program_options;

namespace chatter::cli {

int cmd_point(const std::vector<std::string>& args) {
  Common common;
  double rpm = 0.0, depth_mm = 0.0;
  po::options_description d("Options");
  add_common(d, common);
  d.add_options()
      ("rpm", po::value<double>(&rpm)->required(), "spindle speed, rev/min (required)")
      ("depth-mm", po::value<double>(&depth_mm)->required(), "depth of cut, mm (required; axial depth in milling)")
      ("depth-max-mm", po::value<double>(), "deepest cut searched, mm (default: the larger of sweep.depth_max_mm or 50, and 2 x --depth-mm)")
      ("fail-on-chatter", "exit with status 3 when the point chatters (for scripts: 0 stable, 3 chatter, 2 bad input)");
  add_speed_variation_options(d);
  add_solver_options(d);
  po::variables_map vm;
  if (!parse(args, "Usage: chatter point CONFIG --rpm R --depth-mm D [options]\n\n"
                   "Says whether cutting D mm deep at R rev/min is stable, and prints one JSON object:\n"
                   "stable, depth_limit_mm (null = no limit below the searched depth),\n"
                   "chatter_frequency_hz, lobe and margin = depth_limit / depth (> 1 is stable).\n"
                   "With --method sdm also the Floquet verdict at the point: spectral_radius (< 1 is\n"
                   "stable), multiplier_type (hopf, flip, fold) and the dominant multiplier.\n",
             d, common, vm))
    return 0;
  chatter::Config cfg = load_checked(common);
  apply_speed_variation_options(vm, common, cfg);
  chatter::check_spindle_rpm(rpm, "--rpm");
  chatter::check_depth_mm(depth_mm, "--depth-mm");
  double depth_max_mm = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 2.0 * depth_mm);
  if (vm.count("depth-max-mm")) {
    depth_max_mm = vm["depth-max-mm"].as<double>();
    if (!(std::isfinite(depth_max_mm) && depth_max_mm > depth_mm))
      throw InputError("--depth-max-mm = " + fmt(depth_max_mm) + ": must be > --depth-mm (" + fmt(depth_mm) + ")");
  }
  const BuiltSolver built = build_solver(common.method, cfg, depth_max_mm * 1e-3, vm);
  // The limit (the lobe-table row), the process's frequencies and the
  // method's own analysis at the depth: one report, one record
  // (chatter/report.hpp, chatter/records.hpp; docs/results.md).
  const chatter::PointReport report = chatter::report_point(*built.solver, cfg.process, rpm, depth_mm);
  chatter::RecordSource source = chatter::record_source(cfg, common.position_mm);
  source.notes = built.notes;
  // The config's speed range is the machine's (check's default): a speed
  // outside it is said, as check says it of a row (issue 44: --rpm 300 on a
  // 500-24 000 machine passed silently).
  const auto& sw = cfg.sweep;
  if ((sw.rpm_min && rpm < *sw.rpm_min) || (sw.rpm_max && rpm > *sw.rpm_max))
    source.notes.push_back("--rpm " + fmt(rpm) + ": outside the config's speed range [" +
                           (sw.rpm_min ? fmt(*sw.rpm_min) : std::string("-")) + ", " +
                           (sw.rpm_max ? fmt(*sw.rpm_max) : std::string("-")) + "] rev/min (sweep.rpm_min/rpm_max, "
                           "the machine's range for check)");
  for (std::size_t i = built.notes.size(); i < source.notes.size(); ++i) std::cerr << "note: " << source.notes[i] << "\n";
  for (const std::string& n : report.notes) std::cerr << "note: " << n << "\n";
  std::cout << chatter::point_record(report, source).dump(2) << "\n";
  return (vm.count("fail-on-chatter") && !report.stable) ? kExitChatter : 0;
}

}  // namespace chatter::cli
