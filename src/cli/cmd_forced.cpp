// chatter forced and chatter sle (issue 27, docs/forced.md): the forced
// vibration of a stable cut, its surface location error (milling) or
// diametral error (turning), where the linear limit stops holding, and the
// SLE against spindle speed under the lobes. The numbers come from the
// library (chatter/forced.hpp), the records and plots from the io layer
// (io/forced_records.hpp, io/plot_forced.hpp).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/records/forced.hpp"
#include "chatter/io/plot_forced.hpp"
#include "chatter/io/table_writer.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {

namespace {

// Largest feed accepted, mm (per tooth or per revolution): 100 mm is a unit
// mistake, as in chatter simulate.
constexpr double kMaxFeedMm = 100.0;
constexpr double kMaxDepthMm = 1000.0;
constexpr int kDefaultShaftPoints = 21;


// The feed in mm from the flag of the config's operation, else the config.
double feed_mm_of(const po::variables_map& vm, const Config& cfg) {
  const bool milling = cfg.process.rotating_edges();
  const std::string right = milling ? "feed-per-tooth-mm" : "feed-mm-per-rev";
  const std::string wrong = milling ? "feed-mm-per-rev" : "feed-per-tooth-mm";
  if (vm.count(wrong))
    throw InputError("--" + wrong + ": " + cfg.source.string() + " is " +
                     (milling ? "milling: give the feed per tooth with --feed-per-tooth-mm"
                              : "turning: give the feed per revolution with --feed-mm-per-rev"));
  double f = 0.0;
  if (vm.count(right)) f = vm[right].as<double>();
  else if (cfg.feed_mm) f = *cfg.feed_mm;
  else
    throw InputError("missing --" + right + " (or [process] " + (milling ? "feed_per_tooth_mm" : "feed_per_rev_mm") +
                     " in " + cfg.source.string() + ")");
  if (!(std::isfinite(f) && f > 0.0 && f <= kMaxFeedMm))
    throw InputError("--" + right + " = " + fmt(f) + ": must be in (0, " + fmt(kMaxFeedMm) + "] mm");
  return f;
}

double depth_mm_of(const po::variables_map& vm) {
  const double a = vm["depth-mm"].as<double>();
  if (!(std::isfinite(a) && a > 0.0 && a <= kMaxDepthMm))
    throw InputError("--depth-mm = " + fmt(a) + ": must be in (0, " + fmt(kMaxDepthMm) + "] mm");
  return a;
}

// --radial-immersion: the config's milling process with another a_e/D.
void apply_immersion(const po::variables_map& vm, Config& cfg) {
  if (!vm.count("radial-immersion")) return;
  if (!cfg.process.rotating_edges()) throw InputError("--radial-immersion: " + cfg.source.string() + " is turning (milling only)");
  MillingParameters mp = cfg.process.milling_parameters();
  mp.radial_immersion = vm["radial-immersion"].as<double>();
  const SpeedVariation ssv = cfg.process.speed_variation();
  cfg.process = with_flag("--radial-immersion = " + fmt(mp.radial_immersion), [&] { return Process::milling(mp); });
  cfg.process.set_speed_variation(ssv);
}

ForcedOptions forced_options(const po::variables_map& vm, double depth_max_mm) {
  ForcedOptions o;
  o.sdm.depth_max_m = depth_max_mm * 1e-3;
  if (vm.count("steps")) {
    const int steps = vm["steps"].as<int>();
    if (steps < 1 || steps > 100000) throw InputError("--steps = " + std::to_string(steps) + ": must be in [1, 100000]");
    o.sdm.steps_per_period = o.sdm.steps_per_vibration_cycle = steps;
  }
  return o;
}

void add_model_options(po::options_description& d) {
  d.add_options()
      ("feed-per-tooth-mm", po::value<double>(), "milling: feed per tooth, mm (default: [process] feed_per_tooth_mm)")
      ("feed-mm-per-rev", po::value<double>(), "turning: feed per revolution, mm (default: [process] feed_per_rev_mm)")
      ("radial-immersion", po::value<double>(), "milling: radial immersion a_e/D in (0, 1] instead of the config's "
                                                "(e.g. 0.05 for a 0.5 mm finishing pass with a 10 mm cutter)")
      ("steps", po::value<int>(), "sdm steps per tooth period and per vibration cycle (default 64): the step of the "
                                  "stability verdict and of the periodic solve");
}

std::string um_text(double m) {
  std::ostringstream os;
  os.precision(4);
  os << m * 1e6 << " um";
  return os.str();
}

// The human summary of one response (stdout, or stderr when JSON goes there).
void summary(std::ostream& os, const Config& cfg, const ForcedResponse& r, const StabilityLimit& limit) {
  os << cfg.name << ": " << fmt(r.spindle_rpm) << " rev/min, " << fmt(r.depth_m * 1e3) << " mm deep, "
     << fmt(r.feed_m * 1e3) << (r.milling ? " mm per tooth" : " mm per revolution") << "\n";
  const std::string lim = limit.bounded() ? fmt(limit.depth_limit_m * 1e3, 4) + " mm" : "none below the searched depth";
  if (!r.stable) {
    os << "  unstable: sdm spectral radius " << fmt(r.spectral_radius, 4) << " >= 1 (depth limit at this speed: " << lim
       << "): the vibration grows, there is no forced response\n";
    return;
  }
  os << "  stable: sdm spectral radius " << fmt(r.spectral_radius, 4) << " (depth limit at this speed: " << lim << ")\n";
  // Deeper than the first limit yet stable: an island of sdm's map (issue
  // 44: an SLE reported for a cut the lobes call chatter, without a word).
  if (limit.bounded() && r.depth_m > limit.depth_limit_m)
    os << "  above the first limit: stable only in an island of the stability map; a small change of speed or\n"
          "  depth chatters, and the numbers below hold only inside it (chatter map shows the island)\n";
  if (!r.milling) {
    os << "  static deflection along the radius " << um_text(r.surface_location_error_m) << ": diametral error "
       << um_text(r.diametral_error_m) << " (material left)\n";
    return;
  }
  os << "  surface location error " << um_text(r.surface_location_error_m) << " (+ = material left";
  if (r.sle_max_m - r.sle_min_m > 1e-3 * std::max(std::abs(r.sle_min_m), std::abs(r.sle_max_m)))
    os << "; over the wall height " << um_text(r.sle_min_m) << " to " << um_text(r.sle_max_m);
  os << ")\n  peak to peak          x " << um_text(r.peak_to_peak_x_m) << ", y " << um_text(r.peak_to_peak_y_m)
     << "\n  static deflection     x " << um_text(r.static_x_m) << ", y " << um_text(r.static_y_m)
     << "\n  smallest chip         " << um_text(r.min_chip_m) << "\n";
  if (r.teeth_leave_cut)
    os << "  teeth leave the cut: the linear chip is negative over " << fmt(r.negative_chip_arc_deg, 3)
       << " deg of the arc (" << fmt(100.0 * r.negative_chip_fraction, 3)
       << " %): the linear stability limit does not hold here; run chatter simulate\n";
  else if (r.negative_chip_arc_deg > 0.0)
    os << "  linear model holds (negative chip over " << fmt(r.negative_chip_arc_deg, 3)
       << " deg at the edge of the arc: harmless)\n";
  else
    os << "  linear model holds (every tooth stays in the cut)\n";
}

int forced_along_shaft(const po::variables_map& vm, const Config& cfg, const std::string& table_path,
                       const std::string& plot_path) {
  if (cfg.process.rotating_edges()) throw InputError("--along-shaft: " + cfg.source.string() + " is milling (turning only)");
  if (vm.count("rpm"))
    throw InputError("--rpm: not used with --along-shaft (the static deflection does not depend on the speed; "
                     "chatter surface gives the stability along the part)");
  const double depth_mm = depth_mm_of(vm), feed_mm = feed_mm_of(vm, cfg);
  std::optional<double> lo, hi;
  if (vm.count("position-min-mm")) lo = vm["position-min-mm"].as<double>();
  if (vm.count("position-max-mm")) hi = vm["position-max-mm"].as<double>();
  const SurfacePositions pos = surface_positions(cfg, lo, hi, vm["position-points"].as<int>(),
                                                 {"--position-min-mm", "--position-max-mm", "--position-points"});
  const auto rows = diametral_error_along(cfg.model, cfg.position, cfg.process, pos.m, depth_mm * 1e-3, feed_mm * 1e-3);
  const std::string table = shaft_table_csv(pos.mm, rows);
  const bool to_stdout = table_path.empty() || table_path == "-";
  if (to_stdout) std::cout << table;
  else write_text_file(table_path, table);
  std::ostream& info = to_stdout ? std::cerr : std::cout;
  if (!to_stdout) info << "wrote diametral error table (" << rows.size() << " positions): " << table_path << "\n";
  if (!plot_path.empty()) {
    const auto files = plot_shaft_deflection(plot_path, cfg.name + ": diametral error, " + fmt(depth_mm) + " mm deep, " +
                                                            fmt(feed_mm) + " mm/rev",
                                             pos.mm, rows);
    info << "wrote plot: " << files.image.string() << " (gnuplot script " << files.script.string() << ")\n";
  }
  return 0;
}

// forced's usage text.
const char* const kForcedUsage =
    "Usage: chatter forced CONFIG --rpm N --depth-mm A [--feed-per-tooth-mm F | --feed-mm-per-rev F] [options]\n"
    "       chatter forced CONFIG --along-shaft --depth-mm B --feed-mm-per-rev F [--plot p.png]\n\n"
    "The forced vibration of a stable cut (docs/forced.md): below the stability limit the\n"
    "cutting force still drives the structure. Milling: the surface location error (SLE,\n"
    "the wall's offset normal to it when a tooth passes it, + = material left), the peak-\n"
    "to-peak vibration, the static deflection, the smallest chip thickness and whether a\n"
    "tooth leaves the cut (then the linear limit of the lobes does not hold). Turning: the\n"
    "static deflection and the diametral error 2 delta at the tool position (--position-mm)\n"
    "or along the part (--along-shaft). Exit 3 when the cut is unstable (no forced response;\n"
    "the message names the depth limit), 2 on bad input.\n\n"
    "Example:\n"
    "  chatter forced configs/milling_benchmark_ae005_down.toml --rpm 16000 --depth-mm 2 \\\n"
    "      --feed-per-tooth-mm 0.05 --plot forced.png\n";

}  // namespace

int cmd_forced(const std::vector<std::string>& args) {
  Common common;
  std::string json_path, out_path, plot_path, table_path;
  po::options_description d("Options");
  d.add_options()
      ("rpm", po::value<double>(), "spindle speed, rev/min (required but with --along-shaft)")
      ("depth-mm", po::value<double>()->required(), "depth of cut, mm (required; axial depth in milling)");
  add_model_options(d);
  d.add_options()
      ("depth-max-mm", po::value<double>(), "deepest cut of the depth-limit search, mm (default: the larger of "
                                            "sweep.depth_max_mm or 50, and 2 x --depth-mm)")
      ("json", po::value<std::string>(&json_path), "write the numbers as JSON to this file ('-': standard output, "
                                                   "the summary then goes to standard error)")
      ("out", po::value<std::string>(&out_path), "write the tool path over one period (CSV: time_s, rel_x_um, "
                                                 "rel_y_um, wall_normal_um)")
      ("plot", po::value<std::string>(&plot_path), "draw the tool path relative to the wall over one period and the "
                                                   "machined surface profile (.png, .svg or .pdf; with --along-shaft: "
                                                   "the diametral error along the part)")
      ("along-shaft", "turning on a position-dependent part (cantilever shaft or [[positions]]): the static deflection "
                      "and diametral error at evenly spaced tool positions (CSV: position_mm, force_n, "
                      "deflection_x_um, deflection_y_um, diametral_error_um)")
      ("position-min-mm", po::value<double>(), "with --along-shaft: first position, mm (default: the clamp)")
      ("position-max-mm", po::value<double>(), "with --along-shaft: last position, mm (default: the free end)")
      ("position-points", po::value<int>()->default_value(kDefaultShaftPoints),
       "with --along-shaft: number of positions (>= 2)")
      ("table", po::value<std::string>(&table_path), "with --along-shaft: write the table here (default: standard output)");
  po::variables_map vm;
  if (!parse(args, kForcedUsage, d, common, vm)) return 0;
  const bool along = vm.count("along-shaft") > 0;
  if (!along)
    for (const char* f : {"position-min-mm", "position-max-mm", "table"})
      if (vm.count(f)) throw InputError(std::string("--") + f + ": only with --along-shaft");
  if (!along && !vm["position-points"].defaulted()) throw InputError("--position-points: only with --along-shaft");
  if (along && (!json_path.empty() || !out_path.empty()))
    throw InputError(std::string(!json_path.empty() ? "--json" : "--out") + ": not with --along-shaft (its table is the output)");
  check_outputs({{"--json", json_path == "-" ? "" : json_path},
                 {"--out", out_path},
                 {"--table", table_path == "-" ? "" : table_path},
                 {"--plot", plot_path, true}});
  Config cfg = load_checked(common);
  if (along) return forced_along_shaft(vm, cfg, table_path, plot_path);
  if (!vm.count("rpm")) throw InputError("missing --rpm (spindle speed, rev/min)");
  const double rpm = vm["rpm"].as<double>();
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError("--rpm = " + fmt(rpm) + ": must be > 0 rev/min");
  const double depth_mm = depth_mm_of(vm);
  apply_immersion(vm, cfg);
  const double feed_mm = feed_mm_of(vm, cfg);
  if (!plot_path.empty() && !cfg.process.rotating_edges())
    throw InputError("--plot: turning has a constant deflection (no path to draw); --along-shaft --plot draws the "
                     "diametral error along the part");
  double depth_max_mm = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 2.0 * depth_mm);
  if (vm.count("depth-max-mm")) {
    depth_max_mm = vm["depth-max-mm"].as<double>();
    if (!(std::isfinite(depth_max_mm) && depth_max_mm > depth_mm))
      throw InputError("--depth-max-mm = " + fmt(depth_max_mm) + ": must be > --depth-mm (" + fmt(depth_mm) + ")");
  }
  const ForcedResponseSolver solver(cfg.model, cfg.process, forced_options(vm, depth_max_mm));
  ForcedSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_mm * 1e-3;
  st.feed_m = feed_mm * 1e-3;
  st.record_path = !out_path.empty() || !plot_path.empty();
  const ForcedResponse r = solver.response(st);
  const StabilityLimit limit = solver.stability().limit_at(SpindleSpeed(rpm));

  ForcedRecordContext ctx;
  ctx.config = cfg.name;
  ctx.warnings = cfg.warnings;
  ctx.position_mm = common.position_mm;
  if (cfg.process.rotating_edges()) ctx.radial_immersion = cfg.process.milling_parameters().radial_immersion;
  ctx.limit = limit;
  const bool json_to_stdout = json_path == "-";
  summary(json_to_stdout ? std::cerr : std::cout, cfg, r, limit);
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (json_to_stdout) std::cout << forced_record(r, ctx).dump(2) << "\n";
  else if (!json_path.empty()) files.emplace_back(json_path, forced_record(r, ctx).dump(2) + "\n");
  if (!r.stable) {
    if (!files.empty()) write_text_files(files);
    std::cerr << "chatter: forced: unstable at " << fmt(rpm) << " rev/min and " << fmt(depth_mm)
              << " mm (sdm spectral radius " << fmt(r.spectral_radius, 4) << "; depth limit at this speed "
              << (limit.bounded() ? fmt(limit.depth_limit_m * 1e3, 4) + " mm" : std::string("above the searched depth"))
              << "): a forced response exists only for a stable cut"
              << (out_path.empty() && plot_path.empty() ? "" : " (--out / --plot not written)") << "\n";
    return kExitChatter;
  }
  if (!out_path.empty()) files.emplace_back(out_path, forced_path_csv(r));
  if (!files.empty()) write_text_files(files);
  if (!plot_path.empty()) {
    std::ostringstream title;
    title << cfg.name << ", " << fmt(rpm) << " rev/min, " << fmt(depth_mm) << " mm, " << fmt(feed_mm) << " mm/tooth";
    const auto pf = plot_forced(plot_path, title.str(), r);
    (json_to_stdout ? std::cerr : std::cout) << "wrote plot: " << pf.image.string() << " (gnuplot script "
                                             << pf.script.string() << ")\n";
  }
  return 0;
}

int cmd_sle(const std::vector<std::string>& args) {
  Common common;
  std::string table_path, plot_path;
  po::options_description d("Options");
  d.add_options()
      ("rpm-min", po::value<double>(), "lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("rpm-points", po::value<int>(), "number of speeds (default: sweep.rpm_points or 400)")
      ("depth-mm", po::value<double>()->required(), "depth of cut, mm (required; axial depth in milling)")
      ("depth-max-mm", po::value<double>(), "deepest cut of the lobes drawn above, mm (default: sweep.depth_max_mm "
                                            "or 50)");
  add_model_options(d);
  d.add_options()
      ("table", po::value<std::string>(&table_path), "write the table here ('-' or absent: standard output)")
      ("plot", po::value<std::string>(&plot_path), "draw the lobes and, below on the same speed axis, the SLE and "
                                                   "peak-to-peak vibration (.png, .svg or .pdf)")
      ("threads", po::value<int>(), "threads (default 0: every core; the table does not depend on it)")
      ("quiet", "no progress bar");
  po::variables_map vm;
  if (!parse(args,
             "Usage: chatter sle CONFIG --rpm-min A --rpm-max B --rpm-points N --depth-mm D\n"
             "           [--feed-per-tooth-mm F | --feed-mm-per-rev F] [--table sle.csv] [--plot sle.png]\n\n"
             "The surface location error and the forced vibration against spindle speed for one\n"
             "depth and feed (docs/forced.md). CSV columns: spindle_rpm, surface_location_error_um,\n"
             "peak_to_peak_x_um, peak_to_peak_y_um, min_chip_thickness_um, stable (1/0; the numbers\n"
             "are empty where the cut is unstable). --plot draws the lobes (sdm) with the depth as a\n"
             "line and, below, the SLE and peak to peak on the same speed axis.\n",
             d, common, vm))
    return 0;
  check_outputs({{"--table", table_path == "-" ? "" : table_path}, {"--plot", plot_path, true}});
  Config cfg = load_checked(common);
  const Sweep s = resolve_sweep(vm, cfg);
  if (s.rpm_points < 2 || s.rpm_points > kMaxRpmPoints)
    throw InputError("--rpm-points = " + std::to_string(s.rpm_points) + ": must be in [2, " +
                     std::to_string(kMaxRpmPoints) + "]");
  const double depth_mm = depth_mm_of(vm);
  apply_immersion(vm, cfg);
  const double feed_mm = feed_mm_of(vm, cfg);
  const unsigned threads = thread_count(vm);
  const ForcedResponseSolver solver(cfg.model, cfg.process,
                                    forced_options(vm, std::max(s.depth_max_mm, 1.01 * depth_mm)));
  const auto speeds = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  std::vector<ForcedResponse> rows;
  {
    Progress progress(vm, speeds.size(), "sle");
    rows = sle_sweep(solver, speeds, depth_mm * 1e-3, feed_mm * 1e-3, threads,
                     [&](std::size_t done) { progress.tick(done); });
  }
  const std::string table = sle_table_csv(rows);
  const bool to_stdout = table_path.empty() || table_path == "-";
  if (to_stdout) std::cout << table;
  else write_text_file(table_path, table);
  std::ostream& info = to_stdout ? std::cerr : std::cout;
  std::size_t stable = 0, leave = 0;
  for (const ForcedResponse& r : rows) {
    stable += r.stable;
    leave += r.stable && r.teeth_leave_cut;
  }
  info << cfg.name << " (sle): " << rows.size() << " speeds " << fmt(s.rpm_min) << "-" << fmt(s.rpm_max)
       << " rev/min at " << fmt(depth_mm) << " mm: " << stable << " stable";
  if (leave > 0) info << ", at " << leave << " of them teeth leave the cut (the linear limit does not hold there)";
  info << (to_stdout ? "" : "; wrote " + table_path) << "\n";
  if (!plot_path.empty()) {
    std::vector<StabilityLimit> limits(speeds.size());
    {
      Progress progress(vm, speeds.size(), "lobes (sdm)");
      parallel_for(
          speeds.size(), threads, [&](std::size_t i) { limits[i] = solver.stability().limit_at(SpindleSpeed(speeds[i])); },
          [&](std::size_t done) { progress.tick(done); });
    }
    std::ostringstream title;
    title << cfg.name << ": " << fmt(depth_mm) << " mm, " << fmt(feed_mm)
          << (cfg.process.rotating_edges() ? " mm/tooth" : " mm/rev");
    const auto pf = plot_sle(plot_path, title.str(), rows, limits, depth_mm);
    info << "wrote plot: " << pf.image.string() << " (gnuplot script " << pf.script.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
