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

// Midpoint tolerance of --rpm-spacing adaptive and of the plotted envelope:
// 0.5 % of the local depth (under a pixel on a default plot whose depth axis
// reaches about 4x the absolute limit).
constexpr double kEnvelopeDepthRelTol = 0.005;
// Cusps located to 1e-5 x the speed in an adaptive table (0.01 rev/min at
// 1000 rev/min: about 10 rows per cusp), 1e-6 in a plot.
constexpr double kTableCuspRelTol = 1e-5;
constexpr double kPlotCuspRelTol = 1e-6;
// Extra limit_at solves for the plotted envelope: the transfer-function
// solvers are cheap (tens of microseconds per speed); sdm and time-domain get
// as many as the table has rows, so the plot at most doubles the run time.
constexpr std::size_t kPlotSolvesTransferFunction = 20000;

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
simulate with --fail-on-chatter: 3 on chatter).
)";

int cmd_lobes(const std::vector<std::string>& args) {
  Common common;
  std::string table_path, json_path, plot_path, spacing = "even";
  po::options_description d("Options");
  add_common(d, common);
  d.add_options()
      ("rpm-min", po::value<double>(), "lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("rpm-points", po::value<int>(), "number of speeds, both ends included (default: sweep.rpm_points or 400); "
                                       "with --rpm-spacing adaptive the most rows written")
      ("rpm-spacing", po::value<std::string>(&spacing), "even (default): evenly spaced speeds; adaptive: a quarter of "
                                                        "--rpm-points evenly spaced, the rest halving the intervals where the "
                                                        "envelope bends (0.5 % depth midpoint test, cusps between lobes located)")
      ("depth-max-mm", po::value<double>(), "deepest cut searched, mm; deeper limits print as inf (default: sweep.depth_max_mm or 50)")
      ("table", po::value<std::string>(&table_path), "write the CSV table here ('-': standard output; by default "
                                                     "standard output only when neither --json nor --plot is given)")
      ("json", po::value<std::string>(&json_path), "write the table with its provenance as JSON")
      ("plot", po::value<std::string>(&plot_path), "draw the lobe diagram to this .png, .svg or .pdf (with its gnuplot script and data beside it)")
      ("plot-frequency", "with --plot: add a panel with the chatter frequency")
      ("plot-depth-max-mm", po::value<double>(), kPlotDepthMaxHelp)
      ("depth-mm", po::value<double>(), "a planned depth of cut, mm (< --depth-max-mm): say on standard error at how "
                                        "many speeds of the table it chatters")
      ("fail-on-chatter", "with --depth-mm: exit with status 3 when that depth chatters at any speed of the table "
                          "(for scripts: 0 stable everywhere, 3 chatter, 2 bad input)");
  add_uncertainty_options(d);
  add_solver_options(d);
  po::variables_map vm;
  if (!parse(args, "Usage: chatter lobes CONFIG [options]\n\n"
                   "Computes the stability-lobe envelope: for each spindle speed, the largest depth of\n"
                   "cut (mm) that does not chatter, the chatter frequency (Hz) you would hear just above\n"
                   "it and the lobe number. Pick a speed at a peak between lobes to cut deeper.\n"
                   "CSV columns: spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe ('inf' = stable\n"
                   "at every depth up to --depth-max-mm); --method sdm adds multiplier_type (hopf, flip,\n"
                   "fold) and spectral_radius_check. Use sdm for milling at low radial immersion: the\n"
                   "transfer-function methods miss its flip lobes. --method time-domain simulates the\n"
                   "cut at each speed and bisects on depth (slow: about 0.3 s per speed, 1 % bracket).\n"
                   "--rpm-spacing adaptive places the speeds where the envelope bends: the exact limit at\n"
                   "the middle of every two neighbouring rows is within 0.5 % of the straight line between\n"
                   "them (when --rpm-points allows; the summary says if not). The plotted envelope is\n"
                   "always refined that way, from the table's rows, whatever the spacing.\n"
                   "--samples N solves N models drawn from the config's [uncertainty] spreads (--seed S,\n"
                   "default 1): the table gains depth_limit_p05_mm, _p50_mm, _p95_mm (95 %, 50 %, 5 % of\n"
                   "samples stable below), --plot draws the probability of stability with those lobes and\n"
                   "the nominal one, --probability-table writes it (docs/uncertainty.md).\n",
             d, common, vm))
    return 0;
  if (spacing != "even" && spacing != "adaptive")
    throw InputError("--rpm-spacing = '" + spacing + "': must be even or adaptive");
  const bool adaptive = spacing == "adaptive";
  if (vm.count("fail-on-chatter") && !vm.count("depth-mm"))
    throw InputError("--fail-on-chatter: give --depth-mm D too (the depth of cut to judge at every speed)");
  // The table goes to standard output when asked ('-') or when nothing else is.
  const bool table_to_stdout = table_path == "-" || (table_path.empty() && json_path.empty() && plot_path.empty());
  if (table_path == "-") table_path.clear();
  check_outputs({{"--table", table_path},
                 {"--json", json_path},
                 {"--plot", plot_path, true},
                 {"--probability-table",
                  vm.count("probability-table") ? vm["probability-table"].as<std::string>() : std::string()}});
  const double plot_depth_axis_mm = plot_depth_max_mm(vm, !plot_path.empty());
  const chatter::Config cfg = load_checked(common);
  const Sweep s = resolve_sweep(vm, cfg);
  const std::optional<UncertaintyRequest> uncertainty = uncertainty_request(vm, adaptive, s.rpm_points);
  std::optional<double> planned_mm;  // --depth-mm
  if (vm.count("depth-mm")) {
    planned_mm = vm["depth-mm"].as<double>();
    if (!(std::isfinite(*planned_mm) && *planned_mm > 0.0 && *planned_mm < s.depth_max_mm))
      throw InputError("--depth-mm = " + fmt(*planned_mm) + ": must be > 0 and < --depth-max-mm (" +
                       fmt(s.depth_max_mm) + " mm; deeper cuts are not searched)");
  }
  const unsigned threads = thread_count(vm);
  const BuiltSolver built = build_solver(common.method, cfg, s.depth_max_mm * 1e-3, vm);
  const chatter::LobeSolver& solver = *built.solver;
  chatter::EnvelopeRefinement table_refinement;
  table_refinement.depth_rel_tol = kEnvelopeDepthRelTol;
  table_refinement.cusp_rel_tol = kTableCuspRelTol;
  bool tolerance_met = false;
  std::vector<double> speeds;
  std::vector<chatter::StabilityLimit> rows;
  std::vector<chatter::ExtraColumn> extra;
  if (!adaptive) {
    speeds = chatter::evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
    rows.resize(speeds.size());
  }
  // The solver's extra per-speed columns (e.g. sdm's multiplier type), from
  // the same solves as the rows.
  const std::vector<chatter::DiagnosticColumn> columns = solver.diagnostic_columns();
  if (adaptive) {
    Progress progress(vm, static_cast<std::size_t>(s.rpm_points), "lobes (" + solver.method() + ", adaptive)");
    const auto tick = [&](std::size_t done) { progress.tick(done); };
    // Keep the diagnostics of every solve, by speed, for the extra columns.
    std::map<double, std::vector<chatter::SolverValue>> diagnostics;
    std::mutex diagnostics_mutex;
    const auto limit = [&](double rpm) {
      if (columns.empty()) return solver.limit_at(rpm);
      chatter::DiagnosedLimit r = solver.limit_with_diagnostics(rpm);
      std::lock_guard<std::mutex> lock(diagnostics_mutex);
      diagnostics[rpm] = std::move(r.values);
      return r.limit;
    };
    const chatter::RefinedEnvelope r =
        chatter::adaptive_envelope(limit, s.rpm_min, s.rpm_max, s.rpm_points, table_refinement, threads, tick);
    rows = r.rows;
    tolerance_met = r.converged;
    if (!columns.empty()) {
      std::vector<std::vector<chatter::SolverValue>> values;
      for (const auto& row : rows) values.push_back(diagnostics.at(row.spindle_rpm));
      extra = extra_columns(columns, values);
    }
  } else {
    Progress progress(vm, speeds.size(), "lobes (" + solver.method() + ")");
    const auto tick = [&](std::size_t done) { progress.tick(done); };
    if (!columns.empty()) {
      std::vector<std::vector<chatter::SolverValue>> values(speeds.size());
      chatter::parallel_for(
          speeds.size(), threads,
          [&](std::size_t i) {
            chatter::DiagnosedLimit r = solver.limit_with_diagnostics(speeds[i]);
            rows[i] = r.limit;
            values[i] = std::move(r.values);
          },
          tick);
      extra = extra_columns(columns, values);
    } else {
      rows = chatter::lobe_envelope(solver, speeds, threads, tick);
    }
  }
  const std::optional<chatter::AbsoluteLimit> abs_lim = solver.known_absolute_limit();
  // --samples: the Monte Carlo at the table's speeds; its quantile lobes are
  // columns after the nominal ones.
  std::optional<UncertaintyOutputs> mc;
  if (uncertainty) {
    mc = run_uncertainty(*uncertainty, cfg, common.method, s.depth_max_mm, vm, speeds, rows, threads);
    extra.insert(extra.end(), mc->columns.begin(), mc->columns.end());
  }

  std::ostringstream csv;
  chatter::write_lobe_csv(csv, rows, extra);
  std::string json_text;
  if (!json_path.empty()) {
    chatter::TableProvenance p;
    p.method = solver.method();
    p.config = &cfg;
    p.rpm_min = s.rpm_min;
    p.rpm_max = s.rpm_max;
    p.rpm_points = s.rpm_points;
    p.rpm_spacing = spacing;
    if (adaptive) {
      p.adaptive_depth_rel_tol = table_refinement.depth_rel_tol;
      p.adaptive_tolerance_met = tolerance_met;
    }
    p.depth_max_mm = s.depth_max_mm;
    p.absolute_limit = abs_lim;
    p.options_json = built.options_json;
    p.notes = built.notes;
    p.position_mm = common.position_mm;
    std::ostringstream js;
    chatter::write_lobe_json(js, rows, p, extra);
    json_text = js.str();
    if (mc) json_text = add_uncertainty_json(json_text, *uncertainty, cfg, *mc);
  }

  // Summary for the person at the terminal.
  const chatter::StabilityLimit* best = nullptr;  // deepest stable cut in the sweep
  std::size_t bounded = 0;
  for (const auto& r : rows) {
    if (r.bounded()) ++bounded;
    if (!best || r.depth_limit_m > best->depth_limit_m) best = &r;
  }
  std::ostringstream summary;
  summary << cfg.name << " (" << solver.method() << "): " << rows.size() << " speeds "
          << fmt(s.rpm_min) << "-" << fmt(s.rpm_max) << " rev/min";
  if (abs_lim && abs_lim->depth_m < INFINITY)
    summary << "; stable at any speed below " << fmt(abs_lim->depth_m * 1e3, 5) << " mm";
  if (best) {
    summary << "; deepest limit in the sweep: ";
    if (best->bounded()) summary << fmt(best->depth_limit_m * 1e3, 5) << " mm";
    else summary << "none below " << fmt(s.depth_max_mm) << " mm";
    summary << " at " << fmt(best->spindle_rpm) << " rev/min";
  }
  if (bounded == 0) summary << "; no chatter below " << fmt(s.depth_max_mm) << " mm at any speed";
  if (adaptive)
    summary << "; adaptive spacing: "
            << (tolerance_met ? "every midpoint within 0.5 % of the line between rows"
                              : "0.5 % midpoint tolerance not met everywhere within --rpm-points " +
                                    std::to_string(s.rpm_points) + " (raise it)");

  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!table_path.empty()) files.emplace_back(table_path, csv.str());
  if (!json_path.empty()) files.emplace_back(json_path, json_text);
  if (mc && !uncertainty->probability_table.empty())
    files.emplace_back(uncertainty->probability_table, mc->probability_csv);
  chatter::write_text_files(files);  // all or nothing
  if (table_to_stdout) std::cout << csv.str();
  std::ostream& info = table_to_stdout ? std::cerr : std::cout;
  info << summary.str() << "\n";
  if (mc) info << mc->summary << "\n";
  if (mc && !uncertainty->probability_table.empty())
    info << "wrote probability table: " << uncertainty->probability_table << "\n";
  if (!table_path.empty()) info << "wrote lobe table: " << table_path << "\n";
  if (!json_path.empty()) info << "wrote JSON table: " << json_path << "\n";
  if (!plot_path.empty() && mc) {
    const auto plot_files = chatter::plot_uncertain_lobes(
        plot_path, cfg.name + " (" + solver.method() + ", " + std::to_string(uncertainty->samples) + " samples)",
        mc->lobes, rows, s.depth_max_mm, mc->depth_grid_top_mm);
    info << "wrote plot: " << plot_files.image.string() << " (gnuplot script " << plot_files.script.string() << ", data "
         << plot_files.data.string() << ")\n";
  } else if (!plot_path.empty()) {
    chatter::PlotOptions po_;
    po_.chatter_frequency_panel = vm.count("plot-frequency") > 0;
    po_.depth_axis_max_mm = plot_depth_axis_mm;
    // The plotted envelope: the table's rows refined where the line through
    // them leaves the exact envelope, cusps between lobes located.
    chatter::EnvelopeRefinement plot_refinement;
    plot_refinement.depth_rel_tol = kEnvelopeDepthRelTol;
    plot_refinement.cusp_rel_tol = kPlotCuspRelTol;
    // Methods that give their absolute limit (transfer function) are cheap per solve.
    const std::vector<chatter::LobeCurve> curves = solver.lobe_curves(s.rpm_min, s.rpm_max);
    plot_refinement.max_solves = abs_lim ? kPlotSolvesTransferFunction : rows.size();
    std::vector<chatter::StabilityLimit> plotted;
    {
      Progress progress(vm, plot_refinement.max_solves, "plot envelope (" + solver.method() + ")");
      plotted = chatter::refine_envelope(solver, rows, plot_refinement, threads,
                                         [&](std::size_t done) { progress.tick(done); })
                    .rows;
    }
    const auto plot_files = chatter::plot_lobes(
        plot_path, cfg.name + " (" + solver.method() + ")", plotted,
        curves,
        abs_lim.value_or(chatter::AbsoluteLimit{}), solver.depth_max_m(), po_);
    info << "wrote plot: " << plot_files.image.string() << " (gnuplot script " << plot_files.script.string() << ", data "
         << plot_files.data.string() << ")\n";
  }
  if (planned_mm) {
    // The planned depth against every row of the table: one line on stderr.
    constexpr std::size_t kSpeedsListed = 5;
    std::vector<double> chatter_rpm;
    for (const auto& r : rows)
      if (!(*planned_mm * 1e-3 < r.depth_limit_m)) chatter_rpm.push_back(r.spindle_rpm);
    if (chatter_rpm.empty()) {
      std::cerr << "depth " << fmt(*planned_mm) << " mm: stable at all " << rows.size() << " speeds of the table\n";
    } else {
      std::cerr << "depth " << fmt(*planned_mm) << " mm: chatter at " << chatter_rpm.size() << " of " << rows.size()
                << " speeds of the table";
      for (std::size_t i = 0; i < chatter_rpm.size() && i < kSpeedsListed; ++i)
        std::cerr << (i == 0 ? " (" : ", ") << fmt(chatter_rpm[i]);
      std::cerr << (chatter_rpm.size() > kSpeedsListed ? ", ..." : "") << " rev/min)\n";
      if (vm.count("fail-on-chatter")) return kExitChatter;
    }
  }
  return 0;
}

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
        cmd == "surface")
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
    std::cerr << "chatter: unknown command '" << cmd
              << "' (commands: lobes, point, check, recommend, map, compare, simulate, fit, frf, coefficients, detect, surface; see chatter --help)\n";
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
