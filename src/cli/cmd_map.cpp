// `chatter map`: the Floquet spectral radius on a speed x depth grid (the
// sdm solver's own analysis), as a table, a JSON record, a heat map and a
// live window (docs/sdm.md). The work and the record: stability_map
// (chatter/records/lobes.hpp), shared with Python's chatter.map.
#include <boost/program_options.hpp>

#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"
#include "chatter/records/lobes.hpp"
#include "chatter/semi_discretization.hpp"
#include "cli_common.hpp"
#include "cmd_map_ssv.hpp"
#include "commands.hpp"
#include "live_plot.hpp"

namespace po = boost::program_options;

namespace chatter::cli {

namespace {

// A map's outputs (the speed map and the radial map alike): the CSV and the
// record written all or nothing, then whichever of them goes to standard
// output. Returns the stream for the summary lines (standard error when
// standard output carries the table or the JSON).
std::ostream& write_map_outputs(const std::string& csv, const nlohmann::json& record, const std::string& out_path,
                                const std::string& json_path, bool table_to_stdout, bool json_to_stdout) {
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!out_path.empty()) files.emplace_back(out_path, csv);
  if (!json_path.empty()) files.emplace_back(json_path, record.dump(2) + "\n");
  write_text_files(files);  // all or nothing
  if (table_to_stdout) std::cout << csv;
  if (json_to_stdout) std::cout << record.dump(2) << "\n";
  return table_to_stdout || json_to_stdout ? std::cerr : std::cout;
}

// `chatter map --axes radial-axial`: immersion x axial depth at one speed
// (radial_stability_map, chatter/records/lobes.hpp).
int map_radial_axial(const Common& common, const std::string& floquet_method, const po::variables_map& vm,
                     std::string out_path, std::string json_path, const std::string& plot_path, int depth_points) {
  for (const char* flag : {"rpm-min", "rpm-max", "rpm-points"})
    if (vm.count(flag))
      throw InputError(std::string("--") + flag + ": only with --axes speed-axial (the radial-axial map is at one "
                       "speed: --rpm)");
  if (!vm.count("rpm"))
    throw InputError("--rpm: required with --axes radial-axial (the one spindle speed of the map, rev/min)");
  const double rpm = vm["rpm"].as<double>();
  check_spindle_rpm(rpm, "--rpm");
  const double imin = vm.count("immersion-min") ? vm["immersion-min"].as<double>() : 0.05;
  const double imax = vm.count("immersion-max") ? vm["immersion-max"].as<double>() : 1.0;
  const int ipoints = vm.count("immersion-points") ? vm["immersion-points"].as<int>() : 20;
  const std::vector<double> depths_check = map_depths_m(1.0, depth_points, 1, ArgStyle::kFlag);  // the rule, early
  const std::vector<double> immersions = map_immersions(imin, imax, ipoints, depths_check.size(), ArgStyle::kFlag);
  const ShowRequest show = show_request(vm);
  const bool drawn = !plot_path.empty() || show.requested;
  const bool json_to_stdout = json_path == "-";
  const bool table_to_stdout = out_path == "-" || (out_path.empty() && json_path.empty() && !drawn);
  if (out_path == "-") out_path.clear();
  if (json_to_stdout) json_path.clear();
  if (table_to_stdout && json_to_stdout) throw InputError("--out - and --json -: only one of them on standard output");
  check_outputs({{"--out", out_path}, {"--json", json_path}, {"--plot", plot_path, true}});  // before computing
  const Config cfg = load_checked(common);
  if (!cfg.process.rotating_edges())
    throw InputError("--axes radial-axial: " + cfg.source.string() +
                     " is a turning process, which has no radial immersion (use --axes speed-axial)");
  double depth_max_mm = cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm);
  if (vm.count("depth-max-mm")) depth_max_mm = vm["depth-max-mm"].as<double>();
  if (!(std::isfinite(depth_max_mm) && depth_max_mm > 0.0))
    throw InputError("--depth-max-mm = " + fmt(depth_max_mm) + ": must be > 0 mm");
  const std::vector<double> depths = map_depths_m(depth_max_mm, depth_points, immersions.size(), ArgStyle::kFlag);
  const unsigned threads = thread_count(vm);
  // The config's own solver: its notes and effective options for the record;
  // every immersion gets one built the same way.
  const BuiltSolver built = build_solver(floquet_method, cfg, depth_max_mm * 1e-3, vm);
  const ProcessSolverFactory factory = [&](const Process& p) {
    return built.recipe.build(cfg.model, p, depth_max_mm * 1e-3);
  };
  RadialStabilityMapGrid grid;
  {
    Progress progress(vm, immersions.size(), "radial map (sdm)");
    grid = radial_stability_map(cfg.process, rpm, immersions, depths, factory, drawn, threads,
                                [&](std::size_t done, std::size_t) { progress.tick(done); });
  }
  const std::string csv = radial_map_csv(grid);
  RecordSource source = record_source(cfg, common.position_mm);
  source.notes = built.notes;
  const nlohmann::json record = radial_map_record(grid, built.descriptor->effective_options(*built.solver), source);
  std::ostream& info = write_map_outputs(csv, record, out_path, json_path, table_to_stdout, json_to_stdout);
  std::size_t unstable = 0;
  for (double r : grid.spectral_radius) unstable += r >= 1.0;
  info << cfg.name << " (sdm) at " << fmt(rpm) << " rev/min: " << immersions.size() << " immersions x "
       << depths.size() << " depths, " << unstable << " unstable"
       << (out_path.empty() ? "" : "; wrote map: " + out_path)
       << (json_path.empty() ? "" : "; wrote JSON: " + json_path) << "\n";
  const std::string title = cfg.name + ": spectral radius (sdm) at " + fmt(rpm) + " rev/min";
  if (!plot_path.empty()) {
    const auto pf = plot_radial_stability_map(plot_path, title, grid);
    info << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
         << pf.data.string() << ")\n";
  }
  if (show.requested) {
    {
      LiveWindow window(show);
      plot_radial_stability_map(window, title, grid);
    }
    report_shown(info, show);
  }
  return 0;
}

// map's usage text.
const char* const kMapUsage =
    "Usage: chatter map CONFIG [--method sdm] [options] [--out map.csv] [--plot map.png]\n"
    "       chatter map CONFIG --axes radial-axial --rpm N [options]\n\n"
    "Spectral radius of the Floquet map on a speed x depth grid (the stability chart of\n"
    "the papers): below 1 stable, above 1 chatter. CSV columns:\n"
    "spindle_rpm,depth_mm,spectral_radius, one row per grid point, speeds outermost.\n"
    "--plot (or --show) draws it as a heat map (spindle speed x depth, colour = spectral\n"
    "radius) with the boundary rho = 1 as a line, its Hopf and flip (period-doubling)\n"
    "parts in different styles and the flip-dominated unstable points marked; this also\n"
    "finds the type of the dominant multiplier at every unstable point (slower).\n\n"
    "--axes radial-axial --rpm N (milling): the same over radial immersion a_e/D x axial\n"
    "depth a_p at one speed, plus the depth limit a_p,lim searched at each a_e. CSV columns:\n"
    "radial_immersion,[radial_depth_mm,]depth_mm,spectral_radius,depth_limit_mm\n"
    "(radial_depth_mm when the config gives tool_diameter_mm).\n\n"
    "--ssv-map --rpm N --depth-mm D: the spectral radius per revolution over the spindle\n"
    "speed variation (amplitude ratio x frequency ratio) at that speed and depth instead\n"
    "(CSV columns amplitude_ratio,frequency_ratio,frequency_ratio_used,exact_period,\n"
    "spectral_radius_per_revolution; docs/ssv.md).\n";

// map's options, into the caller's variables.
void describe_map(po::options_description& d, Common& common, const std::string& floquet_method, std::string& axes_text,
                  int& depth_points, std::string& out_path, std::string& json_path, std::string& plot_path) {
  d.add_options()
      ("method", po::value<std::string>(&common.method)->default_value(floquet_method),
       ("only '" + floquet_method + "' draws maps").c_str())
      ("axes", po::value<std::string>(&axes_text)->default_value("speed-axial"),
       "speed-axial: spindle speed x axial depth; radial-axial: radial immersion a_e/D x axial depth at one "
       "speed (--rpm; milling only)")
      ("rpm", po::value<double>(), "with --axes radial-axial or --ssv-map: the spindle speed of the map, rev/min "
                                   "(required there)")
      ("immersion-min", po::value<double>(), "with --axes radial-axial: smallest radial immersion a_e/D, in (0, 1] "
                                             "(default 0.05)")
      ("immersion-max", po::value<double>(), "with --axes radial-axial: largest radial immersion a_e/D, in (0, 1] "
                                             "(default 1, a slot)")
      ("immersion-points", po::value<int>(), "with --axes radial-axial: number of immersions, evenly spaced (>= 2, "
                                             "default 20); each gets its own sdm limit search")
      ("rpm-min", po::value<double>(), "lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("rpm-points", po::value<int>(), "number of speeds (default: sweep.rpm_points or 400)")
      ("depth-max-mm", po::value<double>(), "deepest cut, mm (default: sweep.depth_max_mm or 50)")
      ("depth-points", po::value<int>(&depth_points)->default_value(100), "number of depths from 0 to --depth-max-mm (>= 2)")
      ("out", po::value<std::string>(&out_path), "write the CSV here ('-': standard output; by default standard "
                                                 "output only when neither --json, --plot nor --show is given)")
      ("json", po::value<std::string>(&json_path), "write the map's record (grid, unstable points, solver options) "
                                                   "as JSON ('-': standard output)")
      ("plot", po::value<std::string>(&plot_path), "draw the map to this .png, .svg or .pdf (with its gnuplot script and data beside it)");
  add_show_option(d);
  add_ssv_map_options(d);
  add_solver_options(d);
}

}  // namespace

int cmd_map(const std::vector<std::string>& args) {
  Common common;
  const std::string floquet_method = map_method(kAutoMethod, ArgStyle::kFlag);  // maps are the Floquet method's
  std::string out_path, json_path, plot_path, axes_text = "speed-axial";
  int depth_points = 100;
  po::options_description d("Options");
  describe_map(d, common, floquet_method, axes_text, depth_points, out_path, json_path, plot_path);
  po::variables_map vm;
  if (!parse(args, kMapUsage, d, common, vm)) return 0;
  map_method(common.method, ArgStyle::kFlag);
  if (vm.count("ssv-map")) return run_ssv_map(vm, common, floquet_method, out_path, plot_path);
  check_no_ssv_map_options(vm);
  const MapAxes axes = parse_map_axes(axes_text, ArgStyle::kFlag);
  if (axes == MapAxes::kRadialAxial) return map_radial_axial(common, floquet_method, vm, out_path, json_path, plot_path, depth_points);
  for (const char* flag : {"rpm", "immersion-min", "immersion-max", "immersion-points"})
    if (vm.count(flag))
      throw InputError(std::string("--") + flag + ": only with --axes radial-axial or --ssv-map (the speed x depth "
                       "map takes --rpm-min, --rpm-max, --rpm-points)");
  const ShowRequest show = show_request(vm);  // a display or GNUPLOT_TERM, before computing
  const bool drawn = !plot_path.empty() || show.requested;
  const bool json_to_stdout = json_path == "-";
  const bool table_to_stdout = out_path == "-" || (out_path.empty() && json_path.empty() && !drawn);
  if (out_path == "-") out_path.clear();
  if (json_to_stdout) json_path.clear();
  if (table_to_stdout && json_to_stdout) throw InputError("--out - and --json -: only one of them on standard output");
  check_outputs({{"--out", out_path}, {"--json", json_path}, {"--plot", plot_path, true}});  // before computing
  const Config cfg = load_checked(common);
  const Sweep s = resolve_sweep(vm, cfg);
  const unsigned threads = thread_count(vm);
  const BuiltSolver built = build_solver(floquet_method, cfg, s.depth_max_mm * 1e-3, vm);
  // The spectral-radius map is the Floquet solver's own analysis.
  const auto* sdm = dynamic_cast<const SemiDiscretizationSolver*>(built.solver.get());
  if (!sdm) throw InputError("--method " + floquet_method + ": this method draws no spectral-radius map");
  const std::vector<double> depths = map_depths_m(s.depth_max_mm, depth_points, static_cast<std::size_t>(s.rpm_points),
                                                  ArgStyle::kFlag);
  const auto speeds = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  StabilityMapGrid grid;
  {
    // The plot tells Hopf from flip: the types only when it is drawn.
    Progress progress(vm, drawn ? 2 * speeds.size() : speeds.size(), "map (sdm)");
    grid = stability_map(*sdm, speeds, depths, drawn, threads,
                         [&](std::size_t done, std::size_t) { progress.tick(done); });
  }
  const std::string csv = stability_map_csv(grid);
  RecordSource source = record_source(cfg, common.position_mm);
  source.notes = built.notes;
  const nlohmann::json record = stability_map_record(grid, built.descriptor->effective_options(*built.solver), source);
  std::ostream& info = write_map_outputs(csv, record, out_path, json_path, table_to_stdout, json_to_stdout);
  info << cfg.name << " (sdm): " << speeds.size() << " x " << depths.size() << " points, " << unstable_points(grid)
       << " unstable" << (out_path.empty() ? "" : "; wrote map: " + out_path)
       << (json_path.empty() ? "" : "; wrote JSON: " + json_path) << "\n";
  const std::string title = cfg.name + ": spectral radius (sdm)";
  if (!plot_path.empty()) {
    const auto pf = plot_stability_map(plot_path, title, grid);
    info << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ", data "
         << pf.data.string() << ")\n";
  }
  if (show.requested) {
    {
      LiveWindow window(show);
      plot_stability_map(window, title, grid);
    }
    report_shown(info, show);
  }
  return 0;
}

}  // namespace chatter::cli
