// `chatter lobes`: the stability-lobe table, its JSON, plot and Monte Carlo
// (src/cli/cmd_lobes.hpp).
#include "cmd_lobes.hpp"

#include "chatter/records/lobes.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/plot_uncertainty.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"
#include "commands.hpp"

namespace chatter::cli {
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

}  // namespace

std::optional<LobesPlan> plan_lobes(const std::vector<std::string>& args, bool check_output_files) {
  LobesPlan plan;
  Common& common = plan.common;
  std::string& table_path = plan.table_path;
  std::string& json_path = plan.json_path;
  std::string& plot_path = plan.plot_path;
  std::string& spacing = plan.spacing;
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
      ("json", po::value<std::string>(&json_path),
       "write the table with its provenance as JSON ('-': standard output, the summary then goes to standard "
       "error)")
      ("plot", po::value<std::string>(&plot_path), "draw the lobe diagram to this .png, .svg or .pdf (with its gnuplot script and data beside it)")
      ("plot-frequency", "with --plot or --show: add a panel with the chatter frequency")
      ("plot-depth-max-mm", po::value<double>(), kPlotDepthMaxHelp)
      ("depth-mm", po::value<double>(), "a planned depth of cut, mm (< --depth-max-mm): say on standard error at how "
                                        "many speeds of the table it chatters")
      ("fail-on-chatter", "with --depth-mm: exit with status 3 when that depth chatters at any speed of the table "
                          "(for scripts: 0 stable everywhere, 3 chatter, 2 bad input)");
  add_show_option(d);
  add_uncertainty_options(d);
  add_speed_variation_options(d);
  add_solver_options(d);
  po::variables_map& vm = plan.vm;
  if (!parse(args, "Usage: chatter lobes CONFIG [options]\n\n"
                   "Computes the stability-lobe envelope: for each spindle speed, the largest depth of\n"
                   "cut (mm) that does not chatter, the chatter frequency (Hz) you would hear just above\n"
                   "it and the lobe number. Pick a speed at a peak between lobes to cut deeper.\n"
                   "CSV columns: spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe ('inf' = stable\n"
                   "at every depth up to --depth-max-mm); --method sdm adds multiplier_type (hopf, flip,\n"
                   "fold) and spectral_radius_check. Use sdm for milling at low radial immersion: the\n"
                   "transfer-function methods miss its flip lobes. --method time-domain simulates the\n"
                   "cut at each speed and bisects on depth (slow: about 0.3 s per speed for a straight\n"
                   "cutter, 0.7-0.9 s for a helical variable-pitch one; 1 % bracket).\n"
                   "--rpm-spacing adaptive places the speeds where the envelope bends: the exact limit at\n"
                   "the middle of every two neighbouring rows is within 0.5 % of the straight line between\n"
                   "them (when --rpm-points allows; the summary says if not). The plotted envelope is\n"
                   "always refined that way, from the table's rows, whatever the spacing.\n"
                   "--samples N solves N models drawn from the config's [uncertainty] spreads (--seed S,\n"
                   "default 1): the table gains depth_limit_p05_mm, _p50_mm, _p95_mm (95 %, 50 %, 5 % of\n"
                   "samples stable below), --plot draws the probability of stability with those lobes and\n"
                   "the nominal one, --probability-table writes it (docs/uncertainty.md).\n",
             d, common, vm))
    return std::nullopt;
  if (spacing != "even" && spacing != "adaptive")
    throw InputError("--rpm-spacing = '" + spacing + "': must be even or adaptive");
  const bool adaptive = plan.adaptive = spacing == "adaptive";
  if (vm.count("fail-on-chatter") && !vm.count("depth-mm"))
    throw InputError("--fail-on-chatter: give --depth-mm D too (the depth of cut to judge at every speed)");
  // The table goes to standard output when asked ('-') or when nothing else is.
  plan.show = show_request(vm);  // a display or GNUPLOT_TERM, before anything is computed
  plan.json_to_stdout = json_path == "-";
  if (plan.json_to_stdout && table_path == "-")
    throw InputError("--table - and --json -: only one of them can go to standard output");
  plan.table_to_stdout =
      table_path == "-" || (table_path.empty() && json_path.empty() && plot_path.empty() && !plan.show.requested);
  if (table_path == "-") table_path.clear();
  if (check_output_files)
    check_outputs({{"--table", table_path},
                   {"--json", plan.json_to_stdout ? std::string() : json_path},
                   {"--plot", plot_path, true},
                   {"--probability-table",
                    vm.count("probability-table") ? vm["probability-table"].as<std::string>() : std::string()}});
  plan.plot_depth_axis_mm = plot_depth_max_mm(vm, !plot_path.empty() || plan.show.requested);
  plan.cfg = load_checked(common);
  apply_speed_variation_options(vm, common, plan.cfg);
  const Config& cfg = plan.cfg;
  const Sweep s = plan.sweep = resolve_sweep(vm, cfg);
  plan.uncertainty = uncertainty_request(vm, adaptive, s.rpm_points);
  if (vm.count("depth-mm")) {
    const double planned_mm = *(plan.planned_mm = vm["depth-mm"].as<double>());
    if (!(std::isfinite(planned_mm) && planned_mm > 0.0 && planned_mm < s.depth_max_mm))
      throw InputError("--depth-mm = " + fmt(planned_mm) + ": must be > 0 and < --depth-max-mm (" +
                       fmt(s.depth_max_mm) + " mm; deeper cuts are not searched)");
  }
  plan.threads = thread_count(vm);
  plan.built = build_solver(common.method, cfg, s.depth_max_mm * 1e-3, vm);
  plan.common.method = plan.built.method;  // "auto" resolved: the samples use the same method
  if (plan.uncertainty) check_uncertainty_config(cfg);  // before any solve
  if (!adaptive) plan.speeds_rpm = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  return plan;
}

NominalTable lobes_nominal(const LobesPlan& plan, unsigned threads, bool show_progress) {
  const Sweep& s = plan.sweep;
  const po::variables_map& vm = plan.vm;
  const LobeSolver& solver = *plan.built.solver;
  EnvelopeRefinement table_refinement;
  table_refinement.depth_rel_tol = kEnvelopeDepthRelTol;
  table_refinement.cusp_rel_tol = kTableCuspRelTol;
  NominalTable out;
  std::vector<StabilityLimit>& rows = out.rows;
  std::vector<ExtraColumn>& extra = out.extra;
  const std::vector<double>& speeds = plan.speeds_rpm;
  if (!plan.adaptive) rows.resize(speeds.size());
  // The solver's extra per-speed columns (e.g. sdm's multiplier type), from
  // the same solves as the rows.
  const std::vector<DiagnosticColumn> columns = solver.diagnostic_columns();
  if (plan.adaptive) {
    Progress progress(vm, show_progress ? static_cast<std::size_t>(s.rpm_points) : 0,
                      "lobes (" + solver.method() + ", adaptive)");
    const auto tick = [&](std::size_t done) { progress.tick(done); };
    // Keep the diagnostics of every solve, by speed, for the extra columns.
    std::map<double, std::vector<SolverValue>> diagnostics;
    std::mutex diagnostics_mutex;
    const auto limit = [&](double rpm) {
      if (columns.empty()) return solver.limit_at(SpindleSpeed(rpm));
      DiagnosedLimit r = solver.limit_with_diagnostics(SpindleSpeed(rpm));
      std::lock_guard<std::mutex> lock(diagnostics_mutex);
      diagnostics[rpm] = std::move(r.values);
      return r.limit;
    };
    const RefinedEnvelope r = adaptive_envelope(limit, s.rpm_min, s.rpm_max, s.rpm_points, table_refinement, threads, tick);
    rows = r.rows;
    out.tolerance_met = r.converged;
    if (!columns.empty()) {
      std::vector<std::vector<SolverValue>> values;
      for (const auto& row : rows) values.push_back(diagnostics.at(row.spindle_rpm));
      extra = extra_columns(columns, values);
    }
  } else {
    Progress progress(vm, show_progress ? speeds.size() : 0, "lobes (" + solver.method() + ")");
    const auto tick = [&](std::size_t done) { progress.tick(done); };
    if (!columns.empty()) {
      std::vector<std::vector<SolverValue>> values(speeds.size());
      parallel_for(
          speeds.size(), threads,
          [&](std::size_t i) {
            DiagnosedLimit r = solver.limit_with_diagnostics(SpindleSpeed(speeds[i]));
            rows[i] = r.limit;
            values[i] = std::move(r.values);
          },
          tick);
      extra = extra_columns(columns, values);
    } else {
      rows = lobe_envelope(solver, speeds, threads, tick);
    }
  }
  return out;
}

std::vector<std::vector<StabilityLimit>> lobes_samples(const LobesPlan& plan, std::uint64_t begin, std::uint64_t end,
                                                       unsigned threads,
                                                       const std::function<void(std::size_t)>& per_sample) {
  return sample_limits(*plan.uncertainty, plan.cfg, plan.common.method, plan.sweep.depth_max_mm, plan.vm,
                       plan.speeds_rpm, begin, end, threads, per_sample);
}

namespace {

// The JSON lobe table: the rows, the extra columns, the provenance and, with
// --samples, the uncertainty block.
std::string lobes_json(const LobesPlan& plan, const std::vector<StabilityLimit>& rows,
                       const std::vector<ExtraColumn>& extra, bool tolerance_met,
                       const std::optional<AbsoluteLimit>& abs_lim, const std::optional<UncertaintyOutputs>& mc) {
  const Config& cfg = plan.cfg;
  const Sweep& s = plan.sweep;
  const LobeSolver& solver = *plan.built.solver;
  const BuiltSolver& built = plan.built;
  const bool adaptive = plan.adaptive;
  const std::optional<UncertaintyRequest>& uncertainty = plan.uncertainty;
  TableProvenance p;
  p.method = solver.method();
  p.config = &cfg;
  p.rpm_min = s.rpm_min;
  p.rpm_max = s.rpm_max;
  p.rpm_points = s.rpm_points;
  p.rpm_spacing = plan.spacing;
  if (adaptive) {
    p.adaptive_depth_rel_tol = kEnvelopeDepthRelTol;  // the tolerance lobes_nominal used
    p.adaptive_tolerance_met = tolerance_met;
  }
  p.depth_max_mm = s.depth_max_mm;
  p.absolute_limit = abs_lim;
  p.options = built.options;
  p.notes = built.notes;
  p.position_mm = plan.common.position_mm;
  nlohmann::json record = lobe_table_record(rows, p, extra);
  if (mc)
    record["uncertainty"] = uncertainty_record(*cfg.uncertainty, cfg.process.rotating_edges(),
                                               {uncertainty->samples, uncertainty->seed, uncertainty->depth_points,
                                                mc->depth_grid_top_mm, mc->summary});
  return record.dump(2) + "\n";
}

// The summary for the person at the terminal: speeds, the absolute limit,
// the deepest sampled row, the adaptive spacing's tolerance.
std::string lobes_summary(const LobesPlan& plan, const std::vector<StabilityLimit>& rows, bool tolerance_met,
                          const std::optional<AbsoluteLimit>& abs_lim) {
  const Sweep& s = plan.sweep;
  const LobeSolver& solver = *plan.built.solver;
  const bool adaptive = plan.adaptive;
  const StabilityLimit* best = nullptr;  // deepest stable cut in the sweep
  std::size_t bounded = 0;
  for (const auto& r : rows) {
    if (r.bounded()) ++bounded;
    if (!best || r.depth_limit_m > best->depth_limit_m) best = &r;
  }
  std::ostringstream summary;
  summary << plan.cfg.name << " (" << solver.method() << "): " << rows.size() << " speeds "
          << fmt(s.rpm_min) << "-" << fmt(s.rpm_max) << " rev/min";
  if (abs_lim && abs_lim->depth_m < INFINITY)
    summary << "; stable at any speed below " << fmt(abs_lim->depth_m * 1e3, 5) << " mm";
  if (best) {
    // The table's rows, not the envelope's peak: between two rows it may be
    // deeper (issue 44: 2.13, 2.49, 2.61 mm for one cutter at three samplings).
    summary << "; deepest sampled row: ";
    if (best->bounded()) summary << fmt(best->depth_limit_m * 1e3, 5) << " mm";
    else summary << "none below " << fmt(s.depth_max_mm) << " mm";
    summary << " at " << fmt(best->spindle_rpm) << " rev/min";
    if (best->bounded() && rows.size() > 1)
      summary << " (the peak between rows may be deeper: chatter recommend refines it)";
  }
  if (bounded == 0) summary << "; no chatter below " << fmt(s.depth_max_mm) << " mm at any speed";
  if (adaptive)
    summary << "; adaptive spacing: "
            << (tolerance_met ? "every midpoint within 0.5 % of the line between rows"
                              : "0.5 % midpoint tolerance not met everywhere within --rpm-points " +
                                    std::to_string(s.rpm_points) + " (raise it)");
  return summary.str();
}

// The plot (file and/or window): the uncertain lobes with --samples, else
// the table's envelope refined where the line through its rows leaves it.
void plot_lobe_outputs(const LobesPlan& plan, const std::vector<StabilityLimit>& rows,
                       const std::optional<AbsoluteLimit>& abs_lim, const std::optional<UncertaintyOutputs>& mc,
                       PlotWindow* window, std::ostream& info) {
  const Config& cfg = plan.cfg;
  const Sweep& s = plan.sweep;
  const po::variables_map& vm = plan.vm;
  const LobeSolver& solver = *plan.built.solver;
  const std::string& plot_path = plan.plot_path;
  const std::optional<UncertaintyRequest>& uncertainty = plan.uncertainty;
  const std::string plot_title = cfg.name + " (" + solver.method() + ")";
  if (mc) {
    const std::string title = cfg.name + " (" + solver.method() + ", " + std::to_string(uncertainty->samples) + " samples)";
    if (!plot_path.empty()) {
      const auto plot_files =
          plot_uncertain_lobes(plot_path, title, mc->lobes, rows, s.depth_max_mm, mc->depth_grid_top_mm);
      info << "wrote plot: " << plot_files.image.string() << " (gnuplot script " << plot_files.script.string()
           << ", data " << plot_files.data.string() << ")\n";
    }
    if (window) plot_uncertain_lobes(*window, title, mc->lobes, rows, s.depth_max_mm, mc->depth_grid_top_mm);
  } else {
    PlotOptions po_;
    po_.chatter_frequency_panel = vm.count("plot-frequency") > 0;
    po_.depth_axis_max_mm = plan.plot_depth_axis_mm;
    // The plotted envelope: the table's rows refined where the line through
    // them leaves the exact envelope, cusps between lobes located.
    EnvelopeRefinement plot_refinement;
    plot_refinement.depth_rel_tol = kEnvelopeDepthRelTol;
    plot_refinement.cusp_rel_tol = kPlotCuspRelTol;
    // Methods that give their absolute limit (transfer function) are cheap per solve.
    const std::vector<LobeCurve> curves = solver.lobe_curves(SpindleSpeed(s.rpm_min), SpindleSpeed(s.rpm_max));
    plot_refinement.max_solves = abs_lim ? kPlotSolvesTransferFunction : rows.size();
    std::vector<StabilityLimit> plotted;
    {
      Progress progress(vm, plot_refinement.max_solves, "plot envelope (" + solver.method() + ")");
      plotted = refine_envelope(solver, rows, plot_refinement, plan.threads,
                                [&](std::size_t done) { progress.tick(done); })
                    .rows;
    }
    if (!plot_path.empty()) {
      const auto plot_files = plot_lobes(plot_path, plot_title, plotted, curves, abs_lim.value_or(AbsoluteLimit{}),
                                         solver.depth_max_m(), po_);
      info << "wrote plot: " << plot_files.image.string() << " (gnuplot script " << plot_files.script.string()
           << ", data " << plot_files.data.string() << ")\n";
    }
    if (window)
      plot_lobes(*window, plot_title, plotted, curves, abs_lim.value_or(AbsoluteLimit{}), solver.depth_max_m(), po_);
  }
}

// --depth-mm: the planned depth against every row of the table, one line on
// stderr; false when it chatters somewhere and --fail-on-chatter is given.
bool planned_depth_report(const LobesPlan& plan, const std::vector<StabilityLimit>& rows) {
  const double planned_mm = *plan.planned_mm;
  constexpr std::size_t kSpeedsListed = 5;
  std::vector<double> chatter_rpm;
  for (const auto& r : rows)
    if (!(planned_mm * 1e-3 < r.depth_limit_m)) chatter_rpm.push_back(r.spindle_rpm);
  if (chatter_rpm.empty()) {
    std::cerr << "depth " << fmt(planned_mm) << " mm: stable at all " << rows.size() << " speeds of the table\n";
  } else {
    std::cerr << "depth " << fmt(planned_mm) << " mm: chatter at " << chatter_rpm.size() << " of " << rows.size()
              << " speeds of the table";
    for (std::size_t i = 0; i < chatter_rpm.size() && i < kSpeedsListed; ++i)
      std::cerr << (i == 0 ? " (" : ", ") << fmt(chatter_rpm[i]);
    std::cerr << (chatter_rpm.size() > kSpeedsListed ? ", ..." : "") << " rev/min)\n";
    if (plan.vm.count("fail-on-chatter")) return false;
  }
  return true;
}

}  // namespace

int write_lobes(const LobesPlan& plan, const NominalTable& nominal,
                const std::vector<std::vector<StabilityLimit>>& samples, PlotWindow* window) {
  const Sweep& s = plan.sweep;
  const std::string& table_path = plan.table_path;
  const std::string& json_path = plan.json_path;
  const bool table_to_stdout = plan.table_to_stdout;
  const std::optional<UncertaintyRequest>& uncertainty = plan.uncertainty;
  const std::vector<StabilityLimit>& rows = nominal.rows;
  std::vector<ExtraColumn> extra = nominal.extra;
  const bool tolerance_met = nominal.tolerance_met;
  const std::optional<AbsoluteLimit> abs_lim = plan.built.solver->known_absolute_limit();
  // --samples: the Monte Carlo at the table's speeds; its quantile lobes are
  // columns after the nominal ones.
  std::optional<UncertaintyOutputs> mc;
  if (uncertainty) {
    mc = reduce_uncertainty(*uncertainty, s.depth_max_mm, plan.vm, plan.speeds_rpm, rows, samples);
    extra.insert(extra.end(), mc->columns.begin(), mc->columns.end());
  }

  std::ostringstream csv;
  write_lobe_csv(csv, rows, extra);
  const std::string json_text = json_path.empty() ? std::string() : lobes_json(plan, rows, extra, tolerance_met, abs_lim, mc);
  const std::string summary = lobes_summary(plan, rows, tolerance_met, abs_lim);

  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!table_path.empty()) files.emplace_back(table_path, csv.str());
  if (!json_path.empty() && !plan.json_to_stdout) files.emplace_back(json_path, json_text);
  if (mc && !uncertainty->probability_table.empty())
    files.emplace_back(uncertainty->probability_table, mc->probability_csv);
  write_text_files(files);  // all or nothing
  if (table_to_stdout) std::cout << csv.str();
  if (plan.json_to_stdout) std::cout << json_text;
  std::ostream& info = table_to_stdout || plan.json_to_stdout ? std::cerr : std::cout;
  info << summary << "\n";
  if (mc) info << mc->summary << "\n";
  if (mc && !uncertainty->probability_table.empty())
    info << "wrote probability table: " << uncertainty->probability_table << "\n";
  if (!table_path.empty()) info << "wrote lobe table: " << table_path << "\n";
  if (!json_path.empty() && !plan.json_to_stdout) info << "wrote JSON table: " << json_path << "\n";
  if (!plan.plot_path.empty() || window) plot_lobe_outputs(plan, rows, abs_lim, mc, window, info);
  if (plan.planned_mm && !planned_depth_report(plan, rows)) return kExitChatter;
  return 0;
}


}  // namespace chatter::cli
