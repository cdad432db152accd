// The `chatter` command line. The only file that knows Boost.Program_options;
// it reads a config, runs a library solver and writes what the library returns.
// Exit status: 0 success, 2 bad input or usage, 1 internal failure.
#include <boost/program_options.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "cli_common.hpp"
#include "cmd_uncertainty.hpp"
#include "commands.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/plot_uncertainty.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/transfer_function.hpp"

namespace po = boost::program_options;
using chatter::InputError;
using namespace chatter::cli;

namespace {

const char* const kMainHelp = R"(chatter - predict regenerative chatter and draw stability lobes

Usage: chatter <command> CONFIG [options]

Commands:
  lobes      Stability-lobe table: the deepest stable cut (mm) at each spindle
             speed (rev/min). Below the curve: stable; above it: chatter.
  point      Is one operating point (spindle speed, depth of cut) stable?
             Prints one JSON object with the depth limit and the margin.
  check      Check every operation of a part program (CSV) and suggest a
             spindle speed where each one is stable with the largest margin.
  recommend  The speed and depth that remove the most material while stable
             (with a safety factor) and within spindle power and torque.
  map        Floquet spectral radius on a speed x depth grid (--method sdm).
  compare    Every method at the same speeds, one table, and how far they differ
             (--methods picks them, e.g. analytic,sdm,time-domain).
  simulate   Simulate the cut in time (the tool may leave the cut): stable or
             chatter, vibration amplitude, chatter frequency, time series.
  fit        Fit modes (frequency, damping, stiffness) to a measured FRF (tap
             test: CSV, .frf or UFF 58) and write them as config modes.
  frf        Receptance (m/N) of the tool, the workpiece and the relative motion,
             the frequency response the lobes are computed from.
  coefficients  Cutting coefficients (K_tc, K_rc, edge) from test cuts: average
             forces, dynamometer series or spindle power; writes a [process] table.
  detect     Chatter in a recording of the cut (WAV/FLAC/AIFF/CSV): frequency,
             and the spindle speeds that should cure it. Exit 3 on chatter.
  surface    Lobe surface along the part: the lobe table at evenly spaced tool
             positions of a position-dependent structure (cantilever workpiece
             or [[positions]]); --position-mm X gives lobes, point, check the
             structure at one position.
  forced     The forced vibration of a stable cut: surface location error,
             peak to peak, diametral error (turning), and whether the teeth
             leave the cut (then the linear limit does not hold).
  sle        Surface location error and peak-to-peak vibration against spindle
             speed, under the lobes.

On the shop floor:
  1. Describe the tool and workpiece modes (from a tap test) and the cut in a
     TOML config; start from one in configs/ (keys: docs/config.md).
  2. chatter lobes CONFIG --plot lobes.png: pick a spindle speed at a peak
     between two lobes; cut below the curve there, with margin.
  3. chatter check CONFIG --operations ops.csv before running a program.
  Milling with a small radial immersion: add --method sdm (flip lobes).
  4. To see what a cut does in time: chatter simulate CONFIG --rpm R --depth-mm D.

Examples:
  chatter lobes configs/seed_turning_1dof.toml --table lobes.csv --plot lobes.png
  chatter point configs/seed_turning_1dof.toml --rpm 1200 --depth-mm 1.5
  chatter lobes configs/milling_benchmark_ae005_down.toml --method sdm --plot sdm.png
  chatter check configs/seed_turning_1dof.toml --operations examples/operations/case_a_ops.csv
  chatter frf configs/coupled_tool1_workpiece1.toml --out frf.csv --plot frf.png
  chatter simulate configs/milling_benchmark_ae005_down.toml --rpm 17000 --depth-mm 4 --plot sim.png

Run 'chatter <command> --help' for the options of a command.
Options: --help, --version. Every command that reads a config prints its
plausibility warnings ("warning: FILE: KEY = VALUE: ...; did you mean ...?")
and takes --strict to refuse a config that raises one.
Exit status: 0 success, 2 bad input or usage, 1 internal failure
(check: 3 when some operations are unstable; lobes --depth-mm D, point and
simulate with --fail-on-chatter: 3 on chatter; forced: 3 when the cut is unstable).
)";

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
  const chatter::Config cfg = load_checked(common);
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError("--rpm = " + fmt(rpm) + ": must be > 0 rev/min");
  if (!(std::isfinite(depth_mm) && depth_mm > 0.0))
    throw InputError("--depth-mm = " + fmt(depth_mm) + ": must be > 0 mm (a cut of no depth cannot chatter)");
  double depth_max_mm = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 2.0 * depth_mm);
  if (vm.count("depth-max-mm")) {
    depth_max_mm = vm["depth-max-mm"].as<double>();
    if (!(std::isfinite(depth_max_mm) && depth_max_mm > depth_mm))
      throw InputError("--depth-max-mm = " + fmt(depth_max_mm) + ": must be > --depth-mm (" + fmt(depth_mm) + ")");
  }
  const BuiltSolver built = build_solver(common.method, cfg, depth_max_mm * 1e-3, vm);
  const chatter::StabilityLimit lim = built.solver->limit_at(rpm);
  const double depth_m = depth_mm * 1e-3;
  nlohmann::json j;
  j["method"] = built.solver->method();
  j["warnings"] = cfg.warnings;
  j["notes"] = built.notes;
  if (common.position_mm) j["position_mm"] = *common.position_mm;
  j["spindle_rpm"] = rpm;
  j["depth_mm"] = depth_mm;
  j["stable"] = depth_m < lim.depth_limit_m;
  j["depth_limit_mm"] = lim.bounded() ? nlohmann::json(lim.depth_limit_m * 1e3) : nlohmann::json(nullptr);
  j["chatter_frequency_hz"] = lim.bounded() ? nlohmann::json(lim.chatter_frequency_hz) : nlohmann::json(nullptr);
  j["lobe"] = lim.bounded() ? nlohmann::json(lim.lobe) : nlohmann::json(nullptr);
  j["margin"] = (lim.bounded() && depth_m > 0.0) ? nlohmann::json(lim.depth_limit_m / depth_m) : nlohmann::json(nullptr);
  j["depth_max_mm"] = depth_max_mm;
  // The method's own verdict at the point itself (sdm: Floquet analysis;
  // time-domain: one simulation), where it gives one.
  for (const auto& [key, value] : built.solver->point_diagnostics(rpm, depth_m)) j[key] = to_json(value);
  std::cout << j.dump(2) << "\n";
  return (vm.count("fail-on-chatter") && !(depth_m < lim.depth_limit_m)) ? kExitChatter : 0;
}

int cmd_frf(const std::vector<std::string>& args) {
  Common common;
  std::string out_path, plot_path;
  int points = 1000;
  po::options_description d("Options");
  d.add_options()
      ("fmin", po::value<double>(), "lowest frequency, Hz (default: half the lowest natural frequency)")
      ("fmax", po::value<double>(), "highest frequency, Hz (default: twice the highest natural frequency)")
      ("points", po::value<int>(&points)->default_value(1000), "number of frequencies (>= 2)")
      ("log", "space the frequencies logarithmically (default: evenly)")
      ("out", po::value<std::string>(&out_path), "write the CSV here ('-': standard output; by default standard "
                                                 "output only when --plot is not given)")
      ("plot", po::value<std::string>(&plot_path), "draw magnitude and phase to this .png, .svg or .pdf (script and data beside it)")
      ("re-im", "with --plot: draw real and imaginary parts instead of magnitude and phase");
  po::variables_map vm;
  if (!parse(args, "Usage: chatter frf CONFIG [options]\n\n"
                   "Tabulates the receptance (m/N) of the tool, the workpiece and the relative motion\n"
                   "tool - workpiece (their sum): real and imaginary parts of the xx, xy and yy terms.\n"
                   "The lobes come from the relative receptance: compare it with a tap test.\n",
             d, common, vm))
    return 0;
  const bool table_to_stdout = out_path == "-" || (out_path.empty() && plot_path.empty());
  if (out_path == "-") out_path.clear();
  check_outputs({{"--out", out_path}, {"--plot", plot_path, true}});  // before computing
  const chatter::Config cfg = load_checked(common);
  const double f_lo_default = 0.5 * cfg.model.min_omega() / (2 * std::numbers::pi);
  const double f_hi_default = 2.0 * cfg.model.max_omega() / (2 * std::numbers::pi);
  const double fmin = vm.count("fmin") ? vm["fmin"].as<double>() : f_lo_default;
  const double fmax = vm.count("fmax") ? vm["fmax"].as<double>() : f_hi_default;
  const bool log_spacing = vm.count("log") > 0;
  if (!(std::isfinite(fmin) && (log_spacing ? fmin > 0.0 : fmin >= 0.0)))
    throw InputError("--fmin = " + fmt(fmin) + (log_spacing ? ": must be > 0 Hz with --log" : ": must be >= 0 Hz"));
  if (!(std::isfinite(fmax) && fmax > fmin))
    throw InputError("--fmax = " + fmt(fmax) + ": must be > --fmin (" + fmt(fmin) + ")");
  if (points < 2) throw InputError("--points = " + std::to_string(points) + ": must be >= 2");

  std::ostringstream os;
  os << "frequency_hz";
  for (const char* body : {"tool", "workpiece", "relative"})
    for (const char* term : {"xx", "xy", "yy"})
      os << ',' << body << '_' << term << "_real_m_per_n," << body << '_' << term << "_imag_m_per_n";
  os << '\n';
  char buf[40];
  auto put = [&](double x) {
    std::snprintf(buf, sizeof buf, ",%.10g", x);
    os << buf;
  };
  for (int i = 0; i < points; ++i) {
    const double t = static_cast<double>(i) / (points - 1);
    const double f = log_spacing ? fmin * std::pow(fmax / fmin, t) : fmin + (fmax - fmin) * t;
    const double w = 2 * std::numbers::pi * f;
    std::snprintf(buf, sizeof buf, "%.10g", f);
    os << buf;
    const chatter::Matrix2c gt = cfg.model.tool.receptance(w), gw = cfg.model.workpiece.receptance(w);
    const chatter::Matrix2c gr = gt + gw;
    for (const chatter::Matrix2c* g : {&gt, &gw, &gr})
      for (auto [r, c] : {std::pair{0, 0}, std::pair{0, 1}, std::pair{1, 1}}) {
        put((*g)(r, c).real());
        put((*g)(r, c).imag());
      }
    os << '\n';
  }
  if (table_to_stdout) std::cout << os.str();
  if (!out_path.empty()) {
    chatter::write_text_file(out_path, os.str());
    std::cout << "wrote receptance table (" << points << " frequencies, " << fmt(fmin) << "-" << fmt(fmax)
              << " Hz): " << out_path << "\n";
  }
  if (!plot_path.empty()) {
    chatter::PlotOptions po_;
    if (vm.count("re-im")) po_.frf_parts = chatter::FrfParts::real_imaginary;
    const auto files = chatter::plot_frf(plot_path, cfg.name, cfg.model, fmin, fmax, points, log_spacing, po_);
    (table_to_stdout ? std::cerr : std::cout) << "wrote plot: " << files.image.string() << " (gnuplot script "
                                               << files.script.string() << ")\n";
  }
  return 0;
}

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

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string command;  // the subcommand, once recognised
  try {
    if (args.empty()) {
      std::cerr << kMainHelp;
      return 2;
    }
    const std::string cmd = args.front();
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::cout << kMainHelp;
      return 0;
    }
    if (cmd == "--version") {
      std::cout << "chatter " << chatter::version() << "\n";
      return 0;
    }
    args.erase(args.begin());
    if (cmd == "lobes" || cmd == "point" || cmd == "frf" || cmd == "map" || cmd == "check" || cmd == "recommend" ||
        cmd == "simulate" || cmd == "fit" || cmd == "compare" || cmd == "coefficients" || cmd == "detect" ||
        cmd == "surface" || cmd == "forced" || cmd == "sle")
      command = cmd;
    if (cmd == "coefficients") return chatter::cli::cmd_coefficients(args);
    if (cmd == "detect") return chatter::cli::cmd_detect(args);
    if (cmd == "lobes") return cmd_lobes(args);
    if (cmd == "point") return cmd_point(args);
    if (cmd == "frf") return cmd_frf(args);
    if (cmd == "map") return cmd_map(args);
    if (cmd == "simulate") return chatter::cli::cmd_simulate(args);
    if (cmd == "check") return cmd_check(args);
    if (cmd == "recommend") return cmd_recommend(args);
    if (cmd == "fit") return cmd_fit(args);
    if (cmd == "compare") return cmd_compare(args);
    if (cmd == "surface") return chatter::cli::cmd_surface(args);
    if (cmd == "forced") return chatter::cli::cmd_forced(args);
    if (cmd == "sle") return chatter::cli::cmd_sle(args);
    std::cerr << "chatter: unknown command '" << cmd
              << "' (commands: lobes, point, check, recommend, map, compare, simulate, fit, frf, coefficients, detect, surface, forced, sle; see chatter --help)\n";
    return 2;
  } catch (const po::error& e) {
    // A malformed value (e.g. --revolutions 0.5): say what it must look like.
    const char* hint = dynamic_cast<const po::invalid_option_value*>(&e)
                           ? ": expected a number (a whole number for counts such as --revolutions, --periods, "
                             "--rpm-points)"
                           : "";
    std::cerr << "chatter: " << e.what() << hint << " (see chatter " << command << (command.empty() ? "" : " ")
              << "--help)\n";
    return 2;
  } catch (const InputError& e) {
    // One line per error (a config reports all of its errors at once).
    std::istringstream lines(e.what());
    for (std::string line; std::getline(lines, line);) std::cerr << "chatter: " << line << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "chatter: internal error: " << e.what() << "\n";
    return 1;
  }
}
