// `chatter compare`: several methods at the same spindle speeds (--methods;
// by default analytic, coupled and sdm where they apply, time-domain only on
// request since it is slow), one table, and the largest difference between
// each pair of methods: the cross-check people use to trust the numbers
// (issue 5).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <variant>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {

namespace {

bool has(const std::vector<std::string>& v, const std::string& x) { return std::find(v.begin(), v.end(), x) != v.end(); }

std::string methods_rule() {
  std::string known;
  const auto names = lobe_methods();
  for (std::size_t i = 0; i < names.size(); ++i) known += (i == 0 ? "" : ", ") + names[i];
  return "a comma-separated list of distinct methods from " + known + ", or 'all'";
}

// --methods as given: the names in order (empty for "all"). Syntax only; the
// config decides later which methods apply. @throws InputError.
std::vector<std::string> parse_methods(const std::string& list, bool& all) {
  const std::string given = "--methods '" + list + "': ";
  all = list == "all";
  if (all) return {};
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = list.find(',', start);
    const std::string name = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (name.empty())
      throw InputError(given + (list.empty() ? "empty list" : "empty name") + "; must be " + methods_rule());
    if (name == "all") throw InputError(given + "'all' must stand alone; must be " + methods_rule());
    if (!has_lobe_method(name)) throw InputError(given + "unknown method '" + name + "'; must be " + methods_rule());
    if (has(out, name)) throw InputError(given + "'" + name + "' given twice; must be " + methods_rule());
    out.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

// The methods to run: those asked for (all must apply to the config), every
// one that applies ('all'), or the registry's default ones that apply.
std::vector<std::string> chosen_methods(std::vector<std::string> methods, bool all, const std::string& methods_list,
                                        const Config& cfg) {
  const FeatureSet needed = needed_features(cfg.model, cfg.process);
  const auto applies = [&](const SolverDescriptor& d) { return d.accepts.missing(needed).empty(); };
  if (all || methods.empty()) {
    for (const auto& d : solver_registry())
      if (applies(d) && (all || d.in_default_compare)) methods.push_back(d.name);
    return methods;
  }
  std::string able;
  for (const auto& d : solver_registry())
    if (applies(d)) able += (able.empty() ? "" : ", ") + d.name;
  for (const auto& m : methods) {
    const SolverDescriptor& d = find_lobe_method(m);
    if (applies(d)) continue;
    const auto missing = d.accepts.missing(needed);
    if (missing.front() == SolverFeature::kMeasuredFrf)
      throw InputError("--methods '" + methods_list + "': " + m + " does not apply to " + cfg.source.string() +
                       ": it has measured FRFs, and only " + able +
                       " works from measured data (fit modes with chatter fit for the others)");
    throw InputError("--methods '" + methods_list + "': " + m + " does not apply to " + cfg.source.string() +
                     ": it does not handle " + to_string(missing.front()) + " (methods that do: " + able + ")");
  }
  return methods;
}

// One method's rows and per-speed diagnostics.
struct MethodRun {
  const SolverDescriptor* descriptor = nullptr;
  BuiltSolver built;
  SolverValues options;  // effective options
  std::vector<DiagnosticColumn> columns;
  std::vector<StabilityLimit> rows;
  std::vector<std::vector<SolverValue>> values;  // per speed, in column order

  // The value of diagnostic `name` at speed i (monostate if none).
  SolverValue value(const std::string& name, std::size_t i) const {
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (columns[c].name == name && c < values[i].size()) return values[i][c];
    return std::monostate{};
  }
  bool is_flip(std::size_t i) const {
    const SolverValue v = value("multiplier_type", i);
    return rows[i].bounded() && std::holds_alternative<std::string>(v) &&
           std::get<std::string>(v) == to_string(MultiplierType::kFlip);
  }
};

void run_method(MethodRun& r, const std::vector<double>& speeds, unsigned threads, const po::variables_map& vm) {
  const LobeSolver& solver = *r.built.solver;
  Progress progress(vm, speeds.size(), "compare (" + r.descriptor->name + ")");
  r.rows.resize(speeds.size());
  r.values.resize(speeds.size());
  parallel_for(
      speeds.size(), threads,
      [&](std::size_t i) {
        if (r.columns.empty()) {
          r.rows[i] = solver.limit_at(speeds[i]);
          return;
        }
        DiagnosedLimit d = solver.limit_with_diagnostics(speeds[i]);
        r.rows[i] = d.limit;
        r.values[i] = std::move(d.values);
      },
      [&](std::size_t done) { progress.tick(done); });
}

std::string compare_csv(const std::vector<double>& speeds, const std::vector<MethodRun>& runs) {
  std::ostringstream csv;
  csv << "spindle_rpm";
  for (const auto& r : runs) csv << ",depth_limit_mm_" << r.descriptor->name;
  for (const auto& r : runs)
    for (const auto& c : r.descriptor->compare_columns) csv << ',' << c << '_' << r.descriptor->name;
  csv << '\n';
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    csv << table_number(speeds[i]);
    for (const auto& r : runs) csv << ',' << table_number(r.rows[i].depth_limit_m * 1e3);
    for (const auto& r : runs)
      for (const auto& c : r.descriptor->compare_columns)
        csv << ',' << (r.rows[i].bounded() ? cell_text(r.value(c, i)) : "");
    csv << '\n';
  }
  return csv.str();
}

// Largest relative difference per pair, over speeds where both are bounded;
// speeds where only one of them finds a limit are counted apart.
nlohmann::json compare_pairs(const std::vector<double>& speeds, const std::vector<MethodRun>& runs,
                             const Sweep& s, std::ostream& report) {
  nlohmann::json pairs = nlohmann::json::array();
  for (std::size_t a = 0; a < runs.size(); ++a)
    for (std::size_t b = a + 1; b < runs.size(); ++b) {
      const std::string &ma = runs[a].descriptor->name, &mb = runs[b].descriptor->name;
      double worst = 0.0, at = 0.0;
      std::size_t only_a = 0, only_b = 0;
      for (std::size_t i = 0; i < speeds.size(); ++i) {
        const auto &la = runs[a].rows[i], &lb = runs[b].rows[i];
        if (la.bounded() && lb.bounded()) {
          const double r = std::abs(lb.depth_limit_m / la.depth_limit_m - 1.0);
          if (r > worst) {
            worst = r;
            at = speeds[i];
          }
        } else if (la.bounded()) {
          ++only_a;
        } else if (lb.bounded()) {
          ++only_b;
        }
      }
      report << "  " << ma << " vs " << mb << ": largest relative difference " << fmt(worst, 3) << " (at "
             << fmt(at) << " rev/min)";
      if (only_a + only_b > 0)
        report << "; a limit below " << fmt(s.depth_max_mm) << " mm found only by " << ma << " at " << only_a
               << " speeds, only by " << mb << " at " << only_b;
      report << '\n';
      pairs.push_back({{"methods", {ma, mb}},
                       {"largest_relative_difference", worst},
                       {"at_spindle_rpm", at},
                       {"bounded_only_by_first", only_a},
                       {"bounded_only_by_second", only_b}});
    }
  return pairs;
}

// Below this radial immersion a_e/D the cut is intermittent enough for flip
// (period-doubling) lobes to be wide and set the limit over whole speed
// ranges (Insperger & Stepan 2004; case C at 0.05); above it they are few
// and narrow, so "low radial immersion" is not said as the reason.
constexpr double kLowImmersion = 0.25;
// A flip-limited speed counts as missed by the averaged method when the
// averaged limit there is this much deeper.
constexpr double kFlipMissedRel = 0.05;

std::string speeds_word(std::size_t n) { return std::to_string(n) + (n == 1 ? " speed" : " speeds"); }

// The radial immersion a_e/D of a milling config (1 for turning).
double immersion(const Config& cfg) {
  return cfg.process.operation() == Operation::kMilling ? cfg.process.milling_parameters().radial_immersion : 1.0;
}

// What a Floquet method finds that the averaged (zeroth-order) one cannot;
// each sentence only where the compared numbers (or the config) support it.
// Returns the number of flip-limited speeds.
std::size_t explain_floquet(const MethodRun& f, const MethodRun* averaged, const Config& cfg, std::size_t speeds,
                            std::ostream& report) {
  const std::string& name = f.descriptor->name;
  const bool turning = cfg.process.operation() == Operation::kTurning;
  std::size_t flips = 0, flips_deeper_tf = 0;
  for (std::size_t i = 0; i < speeds; ++i)
    if (f.is_flip(i)) {
      ++flips;
      if (averaged && averaged->rows[i].depth_limit_m > (1.0 + kFlipMissedRel) * f.rows[i].depth_limit_m)
        ++flips_deeper_tf;
    }
  const double ae_d = immersion(cfg);
  const std::string why_flip = ae_d < kLowImmersion ? " (low radial immersion, a_e/D = " + fmt(ae_d, 3) + ")" : "";
  if (flips > 0 && averaged && flips_deeper_tf > 0) {
    report << "  " << name << " finds period-doubling (flip) chatter at " << speeds_word(flips) << "; at "
           << flips_deeper_tf << " of them the " << averaged->descriptor->name
           << " limit is more than 5 % deeper: the transfer-function method averages\n"
              "  the cutting force over the tooth period and cannot see flip lobes"
           << why_flip << ".\n";
  } else if (flips > 0 && averaged) {
    report << "  " << name << " finds period-doubling (flip) chatter at " << speeds_word(flips) << "; there the "
           << averaged->descriptor->name << " limit is within 5 %: no flip lobe cuts below the averaged\n"
              "  lobes in this sweep.\n";
  } else if (flips > 0) {
    std::string averaged_names;
    for (const auto& d : solver_registry())
      if (d.kind == SolverKind::kAveraged) averaged_names += (averaged_names.empty() ? "" : ", ") + d.name;
    report << "  " << name << " finds period-doubling (flip) chatter at " << speeds_word(flips)
           << ": the transfer-function methods (" << averaged_names << ") cannot see flip lobes" << why_flip
           << ".\n";
  } else if (turning && averaged) {
    report << "  turning has constant coefficients: " << name << " differs from the exact "
           << averaged->descriptor->name << " limit only by its\n  discretisation error.\n";
  }
  return flips;
}

// How a simulation method's limits are found, from its effective options.
// `flips`: flip-limited speeds found by the Floquet methods compared (0 if none ran).
void explain_simulation(const MethodRun& r, bool turning, std::size_t flips, std::ostream& report) {
  const auto get = [&](const char* k) { return r.options.at(k); };
  const double tol = std::get<double>(get("depth_tolerance"));
  const int periods = std::get<int>(get("periods"));
  const bool linear = std::get<bool>(get("linear"));
  report << "  " << r.descriptor->name << ": each limit is the middle of a depth bracket " << fmt(tol * 100, 3)
         << " % wide, every depth judged by simulating\n  " << periods << " delay periods"
         << (linear ? " of the linear equation" : " with the nonlinear chip (the tool may leave the cut)");
  if (turning)
    report << "; turning has constant\n  coefficients: " << r.descriptor->name
           << " should match the exact limit to about the bracket width.\n";
  else if (flips > 0)
    report << "; like sdm it sees the\n  intermittent cut of milling (the flip lobes sdm finds at " << speeds_word(flips)
           << ") that the averaged methods miss.\n";
  else
    report << "; it follows the\n  intermittent cut of milling tooth by tooth, which the averaged methods "
              "average out.\n";
}

// A simulation deeper than the linear methods by more than this (relative)
// at some speed is checked for teeth leaving the cut below the linear limit.
constexpr double kForcedExplainRel = 0.05;
// The forced response is read this far below the linear limit (a stable
// cut: a forced response exists).
constexpr double kBelowLinearLimit = 0.95;

// Issue 27: the simulation with the real chip finds a cut stable deeper than
// the linear methods when the forced vibration below the linear limit
// already throws the teeth out of the cut (the linear limit does not hold
// there). At the speed where the simulation is deepest relative to the
// linear reference (sdm, else the averaged method), the forced response at
// 0.95 x that limit says whether this is the cause.
void explain_forced(const Config& cfg, const std::vector<MethodRun>& runs, const std::vector<double>& speeds,
                    std::ostream& report) {
  const MethodRun *sim = nullptr, *lin = nullptr;
  for (const auto& r : runs) {
    if (r.descriptor->kind == SolverKind::kSimulation && !sim) sim = &r;
    if (r.descriptor->kind == SolverKind::kFloquet && !lin) lin = &r;
  }
  for (const auto& r : runs)
    if (!lin && r.descriptor->kind == SolverKind::kAveraged) lin = &r;
  if (!sim || !lin || cfg.process.operation() != Operation::kMilling) return;
  if (const auto it = sim->options.find("linear"); it != sim->options.end() && std::get<bool>(it->second)) return;
  std::size_t at = speeds.size();
  double worst = kForcedExplainRel;
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    const StabilityLimit &a = sim->rows[i], &b = lin->rows[i];
    if (!b.bounded()) continue;
    const double rel = a.bounded() ? a.depth_limit_m / b.depth_limit_m - 1.0 : 1.0;
    if (rel > worst) {
      worst = rel;
      at = i;
    }
  }
  if (at == speeds.size()) return;
  const double feed_m = std::get<double>(sim->options.at("feed_m"));
  ForcedResponse f;
  try {
    ForcedSettings st;
    st.spindle_rpm = speeds[at];
    st.depth_m = kBelowLinearLimit * lin->rows[at].depth_limit_m;
    st.feed_m = feed_m;
    st.record_path = false;
    f = ForcedResponseSolver(cfg.model, cfg.process).response(st);
  } catch (const InputError&) {
    return;  // e.g. measured FRFs: no forced response to explain with
  }
  if (!f.stable) return;
  report << "  " << sim->descriptor->name << " is " << fmt(100.0 * worst, 3) << " % deeper than "
         << lin->descriptor->name << " at " << fmt(speeds[at]) << " rev/min. ";
  if (f.teeth_leave_cut)
    report << "There the forced vibration at " << fmt(100.0 * kBelowLinearLimit, 3) << " % of the\n  "
           << lin->descriptor->name << " limit (" << fmt(f.depth_m * 1e3, 4) << " mm, feed " << fmt(feed_m * 1e3, 4)
           << " mm) is " << fmt(1e6 * std::max(f.peak_to_peak_x_m, f.peak_to_peak_y_m), 3)
           << " um peak to peak and the teeth leave the cut (linear chip negative over "
           << fmt(f.negative_chip_arc_deg, 3) << " deg,\n  " << fmt(100.0 * f.negative_chip_fraction, 3)
           << " % of the arc): below its limit the linear model no longer holds, and the simulation with the real "
              "chip\n  finds the cut stable deeper (check the part with chatter forced / chatter sle; "
              "docs/forced.md).\n";
  else
    report << "The forced vibration there stays inside the chip (no tooth leaves the cut at\n  "
           << fmt(100.0 * kBelowLinearLimit, 3) << " % of the " << lin->descriptor->name
           << " limit): the difference is not the forced vibration.\n";
}

std::string compare_report(const Config& cfg, const Sweep& s, const std::vector<double>& speeds,
                           const std::vector<MethodRun>& runs, nlohmann::json& pairs) {
  std::ostringstream report;
  report << cfg.name << ": " << speeds.size() << " speeds " << fmt(s.rpm_min) << "-" << fmt(s.rpm_max)
         << " rev/min, depth searched to " << fmt(s.depth_max_mm) << " mm\n";
  pairs = compare_pairs(speeds, runs, s, report);
  // The zeroth-order (averaged) method the others are measured against: the
  // first of that kind in registry order.
  const MethodRun* averaged = nullptr;
  for (const auto& d : solver_registry())
    for (const auto& r : runs)
      if (!averaged && r.descriptor == &d && d.kind == SolverKind::kAveraged) averaged = &r;
  const bool turning = cfg.process.operation() == Operation::kTurning;
  std::size_t flips = 0;
  for (const auto& r : runs)
    if (r.descriptor->kind == SolverKind::kFloquet)
      flips = std::max(flips, explain_floquet(r, averaged, cfg, speeds.size(), report));
  for (const auto& r : runs)
    if (r.descriptor->kind == SolverKind::kSimulation) explain_simulation(r, turning, flips, report);
  explain_forced(cfg, runs, speeds, report);
  return report.str();
}

void plot_runs(const std::string& plot_path, double depth_axis_max_mm, const Config& cfg, const Sweep& s,
               const std::vector<MethodRun>& runs, std::ostream& info) {
  std::vector<MethodLimits> lines(runs.size());
  for (std::size_t m = 0; m < runs.size(); ++m) {
    lines[m].method = runs[m].descriptor->name;
    lines[m].limits = runs[m].rows;
    const bool typed = std::any_of(runs[m].columns.begin(), runs[m].columns.end(),
                                   [](const DiagnosticColumn& c) { return c.name == "multiplier_type"; });
    if (!typed) continue;
    for (std::size_t i = 0; i < runs[m].rows.size(); ++i) {
      // The text back to the type (rows without a limit are not marked).
      MultiplierType type = MultiplierType::kHopf;
      const SolverValue v = runs[m].value("multiplier_type", i);
      if (const auto* t = std::get_if<std::string>(&v))
        for (MultiplierType k : {MultiplierType::kHopf, MultiplierType::kFlip, MultiplierType::kFold})
          if (*t == to_string(k)) type = k;
      lines[m].multiplier_type.push_back(type);
    }
  }
  PlotOptions options;
  options.depth_axis_max_mm = depth_axis_max_mm;
  const auto plot =
      plot_compare(plot_path, cfg.name + ": depth limit by method", lines, s.depth_max_mm * 1e-3, options);
  info << "wrote plot: " << plot.image.string() << " (gnuplot script " << plot.script.string() << ", data "
       << plot.data.string() << ")\n";
}

}  // namespace
int cmd_compare(const std::vector<std::string>& args) {
  Common common;
  std::string table_path, json_path, plot_path, methods_list;
  po::options_description d("Options");
  d.add_options()
      ("methods", po::value<std::string>(&methods_list),
       "comma-separated methods to run, in column order: analytic, coupled, sdm, time-domain; 'all' = every "
       "method that applies, time-domain included (default: analytic,coupled,sdm, less those that do not apply: "
       "only analytic on measured FRFs)")
      ("rpm-min", po::value<double>(), "lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("rpm-points", po::value<int>(), "number of evenly spaced speeds (default: sweep.rpm_points or 400)")
      ("depth-max-mm", po::value<double>(), "deepest cut searched, mm (default: sweep.depth_max_mm or 50)")
      ("table", po::value<std::string>(&table_path), "write the comparison CSV here ('-': standard output; by "
                                                     "default standard output only when neither --json nor --plot "
                                                     "is given)")
      ("json", po::value<std::string>(&json_path), "write the pairwise differences as JSON")
      ("plot", po::value<std::string>(&plot_path), "draw every method's depth limit on one chart to this .png, .svg or .pdf (with its gnuplot script and data beside it)")
      ("plot-depth-max-mm", po::value<double>(), kPlotDepthMaxHelp);
  add_solver_options(d);
  po::variables_map vm;
  if (!parse(args, "Usage: chatter compare CONFIG [--methods LIST] [options]\n\n"
                   "Runs several methods at the same spindle speeds and prints one table,\n"
                   "spindle_rpm then depth_limit_mm_<method> for each, plus sdm's multiplier type\n"
                   "when sdm runs, and the largest relative difference of the depth limit between\n"
                   "each pair. By default: analytic, and coupled and sdm when the structure is given\n"
                   "by modes (measured FRFs allow analytic only).\n"
                   "analytic and coupled must agree to round-off; sdm agrees with them in turning\n"
                   "(to its discretisation error, ~0.2 %) and differs in milling where the cutting\n"
                   "force is intermittent (flip lobes at low radial immersion).\n"
                   "time-domain (lobes by simulating the nonlinear cut, --periods etc. below) is\n"
                   "opt-in because it is slow: 0.3-0.4 s per speed and core, a hundred times sdm or\n"
                   "more, so 400 speeds take about a minute on 2 cores. Ask for it with --methods all\n"
                   "or e.g. --methods analytic,sdm,time-domain, with fewer --rpm-points. Its limit is\n"
                   "the middle of a 1 % depth bracket: in turning it agrees with analytic to about that.\n"
                   "--plot overlays the methods' limits (mm) against spindle speed, sdm's\n"
                   "flip-limited speeds marked.\n",
             d, common, vm))
    return 0;
  bool all = false;
  std::vector<std::string> methods;
  if (vm.count("methods")) methods = parse_methods(methods_list, all);  // fail before reading the config
  const bool table_to_stdout = table_path == "-" || (table_path.empty() && json_path.empty() && plot_path.empty());
  if (table_path == "-") table_path.clear();
  check_outputs({{"--table", table_path}, {"--json", json_path}, {"--plot", plot_path, true}});  // before computing
  const double plot_depth_axis_mm = plot_depth_max_mm(vm, !plot_path.empty());
  const Config cfg = load_checked(common);
  methods = chosen_methods(std::move(methods), all, methods_list, cfg);
  check_solver_options(methods, vm, "--methods");
  const Sweep s = resolve_sweep(vm, cfg);
  const unsigned threads = thread_count(vm);
  const auto speeds = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  // Build every solver before running any: a bad option fails at once.
  std::vector<MethodRun> runs(methods.size());
  nlohmann::json solver_options = nlohmann::json::object();
  for (std::size_t m = 0; m < methods.size(); ++m) {
    MethodRun& r = runs[m];
    r.built = build_solver(methods[m], cfg, s.depth_max_mm * 1e-3, vm, /*check_options=*/false);
    r.descriptor = r.built.descriptor;
    r.options = r.descriptor->effective_options(*r.built.solver);
    r.columns = r.built.solver->diagnostic_columns();
    solver_options[methods[m]] = nlohmann::json::parse(r.built.options_json);
  }
  for (MethodRun& r : runs) run_method(r, speeds, threads, vm);

  const std::string csv = compare_csv(speeds, runs);
  nlohmann::json pairs;
  const std::string report = compare_report(cfg, s, speeds, runs, pairs);

  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!table_path.empty()) files.emplace_back(table_path, csv);
  if (!json_path.empty()) {
    nlohmann::json j = {{"config", cfg.source.string()}, {"name", cfg.name}, {"methods", methods},
                        {"rpm_min", s.rpm_min},          {"rpm_max", s.rpm_max}, {"rpm_points", s.rpm_points},
                        {"depth_max_mm", s.depth_max_mm}, {"solver_options", solver_options}, {"warnings", cfg.warnings},
                        {"pairs", pairs}};
    files.emplace_back(json_path, j.dump(2) + "\n");
  }
  write_text_files(files);
  if (table_to_stdout) std::cout << csv;
  std::ostream& info = table_to_stdout ? std::cerr : std::cout;
  info << report;
  if (!plot_path.empty()) plot_runs(plot_path, plot_depth_axis_mm, cfg, s, runs, info);
  return 0;
}

}  // namespace chatter::cli
