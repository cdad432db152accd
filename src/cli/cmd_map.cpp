// `chatter map`: the Floquet spectral radius on a speed x depth grid (the
// sdm solver's own analysis), as a table and a heat map (docs/sdm.md).
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
#include <algorithm>

#include "chatter/io/config.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"
#include "chatter/semi_discretization.hpp"

namespace po = boost::program_options;

namespace chatter::cli {

int cmd_map(const std::vector<std::string>& args) {
  Common common;
  // Maps are the Floquet methods' (their spectral radius on a grid).
  for (const auto& m : chatter::solver_registry())
    if (m.kind == chatter::SolverKind::kFloquet && common.method.empty()) common.method = m.name;
  const std::string floquet_method = common.method;
  std::string out_path, plot_path;
  int depth_points = 100;
  po::options_description d("Options");
  d.add_options()
      ("method", po::value<std::string>(&common.method)->default_value(floquet_method),
       ("only '" + floquet_method + "' draws maps").c_str())
      ("rpm-min", po::value<double>(), "lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("rpm-points", po::value<int>(), "number of speeds (default: sweep.rpm_points or 400)")
      ("depth-max-mm", po::value<double>(), "deepest cut, mm (default: sweep.depth_max_mm or 50)")
      ("depth-points", po::value<int>(&depth_points)->default_value(100), "number of depths from 0 to --depth-max-mm (>= 2)")
      ("out", po::value<std::string>(&out_path), "write the CSV here ('-': standard output; by default standard "
                                                 "output only when --plot is not given)")
      ("plot", po::value<std::string>(&plot_path), "draw the map to this .png, .svg or .pdf (with its gnuplot script and data beside it)");
  add_solver_options(d);
  po::variables_map vm;
  if (!parse(args, "Usage: chatter map CONFIG [--method sdm] [options] [--out map.csv] [--plot map.png]\n\n"
                   "Spectral radius of the Floquet map on a speed x depth grid (the stability chart of\n"
                   "the papers): below 1 stable, above 1 chatter. CSV columns:\n"
                   "spindle_rpm,depth_mm,spectral_radius, one row per grid point, speeds outermost.\n"
                   "--plot draws it as a heat map (spindle speed x depth, colour = spectral radius)\n"
                   "with the boundary rho = 1 as a line, its Hopf and flip (period-doubling) parts in\n"
                   "different styles and the flip-dominated unstable points marked; this also finds\n"
                   "the type of the dominant multiplier at every unstable point (slower).\n",
             d, common, vm))
    return 0;
  if (common.method == chatter::kAutoMethod) common.method = floquet_method;
  if (common.method != floquet_method || floquet_method.empty())
    throw InputError("--method " + common.method + ": map needs --method " + floquet_method);
  if (depth_points < 2) throw InputError("--depth-points = " + std::to_string(depth_points) + ": must be >= 2");
  const bool table_to_stdout = out_path == "-" || (out_path.empty() && plot_path.empty());
  if (out_path == "-") out_path.clear();
  check_outputs({{"--out", out_path}, {"--plot", plot_path, true}});  // before computing
  const chatter::Config cfg = load_checked(common);
  const Sweep s = resolve_sweep(vm, cfg);
  const unsigned threads = thread_count(vm);
  const BuiltSolver built = build_solver(floquet_method, cfg, s.depth_max_mm * 1e-3, vm);
  // The spectral-radius map is the Floquet solver's own analysis.
  const auto* sdm = dynamic_cast<const chatter::SemiDiscretizationSolver*>(built.solver.get());
  if (!sdm) throw InputError("--method " + floquet_method + ": this method draws no spectral-radius map");
  if (static_cast<long long>(s.rpm_points) * depth_points > kMaxMapPoints)
    throw InputError("--rpm-points x --depth-points = " + std::to_string(s.rpm_points) + " x " +
                     std::to_string(depth_points) + ": at most " + std::to_string(kMaxMapPoints) +
                     " grid points (memory and time); use fewer points or a smaller range");
  const auto speeds = chatter::evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  std::vector<double> depths(static_cast<std::size_t>(depth_points));
  for (int k = 0; k < depth_points; ++k)
    depths[static_cast<std::size_t>(k)] = s.depth_max_mm * 1e-3 * k / (depth_points - 1);
  std::vector<double> rho(speeds.size() * depths.size());
  {
    Progress progress(vm, speeds.size(), "map (sdm)");
    chatter::parallel_for(
        speeds.size(), threads,
        [&](std::size_t i) {
          const auto row = sdm->spectral_radius_map({speeds[i]}, depths);
          std::copy(row.begin(), row.end(), rho.begin() + static_cast<std::ptrdiff_t>(i * depths.size()));
        },
        [&](std::size_t done) { progress.tick(done); });
  }
  std::ostringstream os;
  os << "spindle_rpm,depth_mm,spectral_radius\n";
  for (std::size_t i = 0; i < speeds.size(); ++i)
    for (std::size_t k = 0; k < depths.size(); ++k)
      os << chatter::table_number(speeds[i]) << ',' << chatter::table_number(depths[k] * 1e3) << ','
         << chatter::table_number(rho[i * depths.size() + k]) << '\n';
  if (table_to_stdout) std::cout << os.str();
  if (!out_path.empty()) chatter::write_text_file(out_path, os.str());
  {
    std::size_t unstable = 0;
    for (double r : rho) unstable += r >= 1.0;
    (table_to_stdout ? std::cerr : std::cout) << cfg.name << " (sdm): " << speeds.size() << " x " << depths.size()
                                              << " points, " << unstable << " unstable"
                                              << (out_path.empty() ? "" : "; wrote map: " + out_path) << "\n";
  }
  if (!plot_path.empty()) {
    // The plot tells Hopf from flip: the type of the dominant multiplier at
    // every unstable point (the stable points' types are not drawn).
    chatter::StabilityMapGrid grid;
    grid.spindle_rpm = speeds;
    grid.depth_m = depths;
    grid.spectral_radius = rho;
    grid.multiplier_type.assign(rho.size(), chatter::MultiplierType::kHopf);
    {
      Progress progress(vm, speeds.size(), "map types (sdm)");
      chatter::parallel_for(
          speeds.size(), threads,
          [&](std::size_t i) {
            for (std::size_t k = 0; k < depths.size(); ++k)
              if (rho[i * depths.size() + k] >= 1.0)
                grid.multiplier_type[i * depths.size() + k] = sdm->analyse(speeds[i], depths[k]).type;
          },
          [&](std::size_t done) { progress.tick(done); });
    }
    const auto files = chatter::plot_stability_map(plot_path, cfg.name + ": spectral radius (sdm)", grid);
    (table_to_stdout ? std::cerr : std::cout) << "wrote plot: " << files.image.string() << " (gnuplot script "
                                               << files.script.string() << ", data " << files.data.string()
                                               << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
