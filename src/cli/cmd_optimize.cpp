// chatter performance, optimize and adapt (issue 29, docs/optimization.md):
// the indices and loss of one set-point, the constrained optimum with its
// loss map, and the adaptive loop of seed 003. The numbers come from the
// library (chatter/optimization.hpp), the records from the records layer,
// the plot from the io layer (io/plot_optimization.hpp).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/optimization_files.hpp"
#include "chatter/io/plot_optimization.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/optimization.hpp"
#include "chatter/records.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {

namespace {

using nlohmann::json;

// Loss map resolution of --plot: 121 speeds x 81 feeds (~10 000 evaluations,
// the speeds' depth limits solved once each).
constexpr int kMapSpeeds = 121;
constexpr int kMapFeeds = 81;
constexpr int kMaxIterations = 10000;

std::string feed_flag(const Config& cfg) { return cfg.process.rotating_edges() ? "feed-per-tooth-mm" : "feed-mm-per-rev"; }

void emit(const std::string& path, const json& j) {
  const std::string text = j.dump(2) + "\n";
  if (path == "-") std::cout << text;
  else write_text_file(path, text);
}

// The config without the position applied (the model evaluates the part
// itself), and the position in m when --position-mm was given.
struct Loaded {
  Config cfg;
  std::optional<double> position_m;
};
Loaded load(const Common& common) {
  Common plain = common;
  plain.position_mm.reset();
  Loaded l{load_checked(plain), std::nullopt};
  if (!l.cfg.optimization)
    throw InputError(l.cfg.source.string() + ": no [optimization] table (the objective, bounds, loss and "
                                             "constraints: docs/config.md, \"Optimization\")");
  if (common.position_mm) l.position_m = position_m(l.cfg, *common.position_mm, "--position-mm");
  return l;
}

void add_model_options(po::options_description& d) {
  d.add_options()
      ("method", po::value<std::string>()->default_value("auto"), "lobe method of the stability constraint (auto: "
                                                                  "analytic for turning, sdm for milling)")
      ("no-stability", "leave the stability constraint out (as a loss without a lobe model): for comparison only")
      ("threads", po::value<int>()->default_value(0), "threads of the scans (0 = every core); the result does not "
                                                     "depend on it");
}

// --depth-mm X (fixed) or LO,HI (free) instead of the config's bounds.
std::optional<Bounds> depth_override(const po::variables_map& vm) {
  if (!vm.count("depth-mm")) return std::nullopt;
  const std::string s = vm["depth-mm"].as<std::string>();
  std::vector<double> v;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, ',');) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !std::isfinite(x) || !(x > 0.0))
      throw InputError("--depth-mm = " + s + ": must be D or LO,HI in mm, each > 0");
    v.push_back(x * 1e-3);
  }
  if (v.empty() || v.size() > 2 || v.back() < v.front())
    throw InputError("--depth-mm = " + s + ": must be D (fixed) or LO,HI with LO <= HI (free), mm");
  return Bounds{v.front(), v.back()};
}

// `performance_depth_m`: performance's one depth (a number, not bounds): the
// bounds widen to take it, so the lobe solvers search deep enough for it.
OptimizationModel build_model(const Loaded& l, const po::variables_map& vm,
                              std::optional<double> performance_depth_m = std::nullopt) {
  OptimizationSpec spec = *l.cfg.optimization;
  if (vm.count("no-stability")) spec.constraints.stability = false;
  if (performance_depth_m)
    spec.depth_m = {std::min(spec.depth_m.lo, *performance_depth_m), std::max(spec.depth_m.hi, *performance_depth_m)};
  else if (const auto d = depth_override(vm))
    spec.depth_m = *d;
  ModelOptions o;
  o.method = vm["method"].as<std::string>();
  o.position_m = l.position_m;
  o.threads = thread_count(vm);
  return with_flag("--method", [&] { return OptimizationModel(l.cfg.model, l.cfg.position, l.cfg.process, spec, o); });
}

RecordSource source_of(const Loaded& l, const Common& common) { return record_source(l.cfg, common.position_mm); }

std::string value_text(double x) { return std::isfinite(x) ? fmt(x, 5) : std::string("-"); }

// The human summary of one set-point.
void summary(std::ostream& os, const OptimizationModel& m, const Performance& p) {
  const bool mill = m.milling();
  os << "  " << fmt(p.cutting_speed_m_per_min, 5) << " m/min (" << fmt(p.point.spindle_rpm, 6) << " rev/min), "
     << fmt(p.point.feed_m * 1e3, 5) << (mill ? " mm/tooth, " : " mm/rev, ") << fmt(p.point.depth_m * 1e3, 5)
     << " mm deep\n";
  for (std::size_t i = 0; i < kIndexCount; ++i) {
    std::string name(index_name(static_cast<PerformanceIndex>(i), m.operation()));
    name.resize(26, ' ');
    os << "  " << name << value_text(p.value[i]) << (p.measured[i] ? "  (measured; model " + value_text(p.model[i]) + ")" : "");
    if (i < kLossIndexCount && m.alpha()[i] > 0.0)
      os << "   loss term " << value_text(p.loss_terms[i]) << " (alpha " << fmt(m.alpha()[i], 5) << ")";
    os << "\n";
  }
  os << "  loss " << value_text(p.loss) << "\n";
  for (const ConstraintCheck& c : p.constraints) {
    std::string name = c.name;
    name.resize(30, ' ');
    os << "  " << (c.ok ? "ok    " : "FAILS ") << name << value_text(c.value) << (c.name.rfind("min_", 0) == 0 || c.name == "stability_margin" ? " >= " : " <= ")
       << fmt(c.limit, 5) << "\n";
  }
  if (m.spec().constraints.stability)
    os << "  depth limit " << (std::isfinite(p.depth_limit_m) ? fmt(p.depth_limit_m * 1e3, 5) + " mm" : "none below the searched depth")
       << (std::isfinite(p.weakest_position_m) ? " (weakest at " + fmt(p.weakest_position_m * 1e3, 5) + " mm)" : "")
       << ", method " << m.method() << "\n";
  os << "  " << (p.feasible ? "every constraint holds" : "some constraint fails") << "\n";
}

// One "--index NAME=VALUE" into `measured`.
void parse_index(const std::string& arg, Operation op, IndexValues& measured) {
  const auto eq = arg.find('=');
  const std::string name = arg.substr(0, eq);
  const auto index = index_from_name(name, op);
  if (eq == std::string::npos || !index)
    throw InputError("--index " + arg + ": must be NAME=VALUE with NAME one of " + index_names(op));
  std::size_t used = 0;
  double v = 0.0;
  const std::string text = arg.substr(eq + 1);
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v) || !(v > 0.0))
    throw InputError("--index " + arg + ": the value must be a number > 0");
  measured[static_cast<std::size_t>(*index)] = v;
}

}  // namespace

int cmd_performance(const std::vector<std::string>& args) {
  Common common;
  std::string json_path;
  po::options_description d("Options");
  d.add_options()
      ("cutting-speed-m-per-min", po::value<double>(), "cutting speed, m/min (or --rpm)")
      ("rpm", po::value<double>(), "spindle speed, rev/min (or --cutting-speed-m-per-min)")
      ("feed-mm-per-rev", po::value<double>(), "turning: feed per revolution, mm")
      ("feed-per-tooth-mm", po::value<double>(), "milling: feed per tooth, mm")
      ("depth-mm", po::value<double>()->required(), "depth of cut, mm (turning: the chip width; milling: axial)")
      ("index", po::value<std::vector<std::string>>()->composing(),
       "NAME=VALUE: a measured index replaces the model's (repeatable; names: diametral_error_um or "
       "surface_location_error_um, surface_roughness_um, removal_rate_mm3_per_s, cost, production_rate_per_h, force_n)")
      ("json", po::value<std::string>(&json_path), "write every number as JSON to this file ('-': standard output, "
                                                   "the summary then goes to standard error)");
  add_model_options(d);
  po::variables_map vm;
  if (!parse(args,
             "Usage: chatter performance CONFIG --cutting-speed-m-per-min V --feed-mm-per-rev f --depth-mm d\n"
             "                           [--index NAME=VALUE ...] [--json -]\n\n"
             "Every performance index of one set-point (docs/optimization.md): removal rate, diametral\n"
             "error (turning; milling: surface location error), roughness, cost, production rate, force;\n"
             "the loss coefficients alpha, each loss term and the total loss; each constraint of the\n"
             "config's [optimization] with its value, limit and verdict; the stability margin (depth\n"
             "limit over depth, the smallest over the part without --position-mm). --index replaces a\n"
             "predicted index by a measured one: this is how measurements enter.\n"
             "Exit status: 0 every constraint holds, 3 some constraint fails, 2 bad input.\n",
             d, common, vm))
    return 0;
  check_outputs({{"--json", json_path == "-" ? "" : json_path}});
  const Loaded l = load(common);
  const Operation op = l.cfg.process.operation();
  if (vm.count("cutting-speed-m-per-min") == vm.count("rpm"))
    throw InputError("give the speed with --cutting-speed-m-per-min or --rpm (one of them)");
  const std::string right = feed_flag(l.cfg), wrong = l.cfg.process.rotating_edges() ? "feed-mm-per-rev" : "feed-per-tooth-mm";
  if (vm.count(wrong))
    throw InputError("--" + wrong + ": " + l.cfg.source.string() + " is " + std::string(l.cfg.process.operation_name()) +
                     ": give --" + right);
  if (!vm.count(right)) throw InputError("missing --" + right);
  IndexValues measured = unknown_indices();
  if (vm.count("index"))
    for (const std::string& a : vm["index"].as<std::vector<std::string>>()) parse_index(a, op, measured);
  auto positive = [&](const std::string& flag) {
    const double x = vm[flag].as<double>();
    if (!(std::isfinite(x) && x > 0.0)) throw InputError("--" + flag + " = " + fmt(x) + ": must be > 0");
    return x;
  };
  const OptimizationModel model = build_model(l, vm, positive("depth-mm") * 1e-3);
  const double diameter = l.cfg.optimization->diameter_m;
  SetPoint p;
  p.spindle_rpm = vm.count("rpm") ? positive("rpm") : spindle_rpm_of(diameter, positive("cutting-speed-m-per-min"));
  p.feed_m = positive(right) * 1e-3;
  p.depth_m = positive("depth-mm") * 1e-3;
  const Performance r = model.evaluate(p, no_corrections(), measured);
  // A set-point outside the [optimization] bounds is evaluated (the models
  // extrapolate) but said: far outside, it is usually a unit slip (issue 44:
  // --feed-mm-per-rev 35 against 0.05-0.5 passed without a word).
  RecordSource source = source_of(l, common);
  const OptimizationSpec& spec = model.spec();
  const std::string unit = model.milling() ? " mm/tooth" : " mm/rev";
  auto outside = [&](const char* what, double x, const Bounds& b, double scale, const std::string& u) {
    if (b.lo > 0.0 && (x < b.lo * (1.0 - 1e-12) || x > b.hi * (1.0 + 1e-12)))
      source.warnings.push_back(std::string(what) + " " + fmt(x * scale, 5) + u + " is outside the [optimization] bounds " +
                                fmt(b.lo * scale, 5) + "-" + fmt(b.hi * scale, 5) + u +
                                (x > 10.0 * b.hi || x < 0.1 * b.lo ? ": a unit slip?" : ": the models extrapolate"));
  };
  outside("feed", p.feed_m, spec.feed_m, 1e3, unit);
  outside("depth", p.depth_m, spec.depth_m, 1e3, " mm");
  outside("spindle speed", p.spindle_rpm, spec.speed_rpm, 1.0, " rev/min");
  for (std::size_t i = l.cfg.warnings.size(); i < source.warnings.size(); ++i)
    std::cerr << "warning: " << source.warnings[i] << "\n";
  if (!json_path.empty()) emit(json_path, performance_record(r, model, source));
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << l.cfg.name << ":\n";
  summary(os, model, r);
  return r.feasible ? 0 : kExitChatter;
}

int cmd_optimize(const std::vector<std::string>& args) {
  Common common;
  std::string json_path, plot_path;
  po::options_description d("Options");
  d.add_options()
      ("depth-mm", po::value<std::string>(), "the depth instead of the config's: D (fixed) or LO,HI (free), mm")
      ("json", po::value<std::string>(&json_path), "write every number as JSON to this file ('-': standard output, "
                                                   "the summary then goes to standard error)")
      ("plot", po::value<std::string>(&plot_path), "draw the loss map at the optimum's depth (.png, .svg or .pdf): "
                                                   "the loss over speed x feed, infeasible regions hatched by "
                                                   "constraint, the lobes' unstable region, the optimum");
  add_model_options(d);
  po::variables_map vm;
  if (!parse(args,
             "Usage: chatter optimize CONFIG [--json -] [--plot map.png]\n\n"
             "The constrained optimum of the config's [optimization] objective over its bounds\n"
             "(docs/optimization.md): cutting speed (turning; milling: spindle speed) and feed, the\n"
             "depth fixed or free; a scan of the bounds, then the best pockets polished by Brent's\n"
             "minimiser. Names the binding constraints, gives the loss terms at the optimum.\n"
             "Exit status: 0 an optimum was found, 3 no set-point meets every constraint, 2 bad input.\n",
             d, common, vm))
    return 0;
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--plot", plot_path, true}});
  const Loaded l = load(common);
  const OptimizationModel model = build_model(l, vm);
  const Optimum o = optimize(model);
  if (!json_path.empty()) emit(json_path, optimize_record(o, model, source_of(l, common)));
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << l.cfg.name << ": " << (o.found ? "optimum of " : "no set-point meets every constraint; the nearest, for ")
     << objective_name(model.spec().objective) << "\n";
  summary(os, model, o.best);
  if (o.found) {
    os << "  binding:";
    for (const std::string& b : o.binding) os << " " << b;
    os << (o.binding.empty() ? " none (an interior optimum)\n" : "\n");
  }
  if (!plot_path.empty()) {
    const LossMap map = loss_map(model, o.best.point.depth_m, kMapSpeeds, kMapFeeds);
    const auto files = plot_loss_map(plot_path, l.cfg.name + ": " + std::string(objective_name(model.spec().objective)) +
                                                    " at " + fmt(o.best.point.depth_m * 1e3, 4) + " mm deep",
                                     map, MapPoint{o.best.point.spindle_rpm, o.best.point.feed_m});
    os << "wrote plot: " << files.image.string() << " (gnuplot script " << files.script.string() << ")\n";
  }
  return o.found ? 0 : kExitChatter;
}

namespace {

// "--start V,f[,d]": speed in m/min (turning; milling rev/min), feed and depth in mm.
SetPoint parse_start(const std::string& s, const OptimizationModel& m) {
  const std::string form = m.milling() ? "RPM,F[,D] (rev/min, mm per tooth, mm)" : "V,F[,D] (m/min, mm/rev, mm)";
  std::vector<double> v;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, ',');) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !std::isfinite(x) || !(x > 0.0))
      throw InputError("--start " + s + ": must be " + form + ", each > 0");
    v.push_back(x);
  }
  if (v.size() < 2 || v.size() > 3) throw InputError("--start " + s + ": must be " + form);
  const OptimizationSpec& spec = m.spec();
  return {m.milling() ? v[0] : spindle_rpm_of(spec.diameter_m, v[0]), v[1] * 1e-3,
          v.size() == 3 ? v[2] * 1e-3 : (spec.depth_m.lo + spec.depth_m.hi) / 2.0};
}

}  // namespace

int cmd_adapt(const std::vector<std::string>& args) {
  Common common;
  std::string json_path, plot_path, table_path, measurements_path;
  po::options_description d("Options");
  d.add_options()
      ("iterations", po::value<int>()->required(), "measurements (iterations of the loop), >= 1 (required)")
      ("gamma", po::value<double>(), "relaxed target: each step aims at gamma x the loss, in (0, 1] (default: "
                                     "[optimization.adapt] gamma, else 0.95)")
      ("max-step-pct", po::value<double>(), "largest move per iteration, % of each bound range (default: "
                                            "[optimization.adapt] max_step_percent, else 10)")
      ("start", po::value<std::string>(), "first set-point V,F[,D]: cutting speed m/min (milling: rev/min), feed "
                                          "mm, depth mm (default: the centre of the bounds)")
      ("bias", po::value<std::vector<std::string>>()->composing(),
       "INDEX=PCT@ITER: the simulated plant reads INDEX (or all) PCT % above the model from iteration ITER on "
       "(repeatable)")
      ("measurements", po::value<std::string>(&measurements_path), "CSV of measured indices, one row per iteration "
                                                                   "(header: iteration and index names; empty cell: "
                                                                   "not measured), instead of the simulated plant")
      ("depth-mm", po::value<std::string>(), "the depth instead of the config's: D (fixed) or LO,HI (free), mm")
      ("table", po::value<std::string>(&table_path), "write the rows as CSV here (default: standard output)")
      ("json", po::value<std::string>(&json_path), "write every number as JSON to this file ('-': standard output)")
      ("plot", po::value<std::string>(&plot_path), "draw the trajectory on the loss map (.png, .svg or .pdf)");
  add_model_options(d);
  po::variables_map vm;
  if (!parse(args,
             "Usage: chatter adapt CONFIG --iterations K [--gamma 0.95] [--start V,f] [--bias INDEX=PCT@ITER ...]\n"
             "                     [--measurements FILE] [--json -] [--plot loop.png]\n\n"
             "The adaptive loop of an inverse-model controller (docs/optimization.md): measure the indices at the current\n"
             "set-point (a plant: the forward models with the given biases, or the rows of a measurements\n"
             "file), correct each index's model by measured / predicted, move toward the corrected\n"
             "optimum with the relaxed target gamma x loss and a step limit, never to a set-point that\n"
             "fails a constraint or the stability margin. One row per iteration.\n"
             "Exit status: 0, 2 bad input.\n",
             d, common, vm))
    return 0;
  const bool table_stdout = table_path.empty() || table_path == "-";
  if (json_path == "-" && table_stdout && !table_path.empty())
    throw InputError("--json - and --table -: only one of them can go to standard output");
  check_outputs({{"--json", json_path == "-" ? "" : json_path},
                 {"--table", table_stdout ? "" : table_path},
                 {"--plot", plot_path, true}});
  const Loaded l = load(common);
  const Operation op = l.cfg.process.operation();
  const OptimizationModel model = build_model(l, vm);
  AdaptSettings settings = model.spec().adapt;
  if (vm.count("gamma")) settings.gamma = vm["gamma"].as<double>();
  if (!(settings.gamma > 0.0 && settings.gamma <= 1.0)) throw InputError("--gamma = " + fmt(settings.gamma) + ": must be in (0, 1]");
  if (vm.count("max-step-pct")) {
    const double pct = vm["max-step-pct"].as<double>();
    if (!(pct > 0.0 && pct <= 100.0)) throw InputError("--max-step-pct = " + fmt(pct) + ": must be in (0, 100]");
    settings.max_step = pct / 100.0;
  }
  AdaptPlan plan;
  plan.iterations = vm["iterations"].as<int>();
  if (plan.iterations < 1 || plan.iterations > kMaxIterations)
    throw InputError("--iterations = " + std::to_string(plan.iterations) + ": must be in [1, " +
                     std::to_string(kMaxIterations) + "]");
  if (vm.count("start")) plan.start = parse_start(vm["start"].as<std::string>(), model);
  if (vm.count("bias"))
    for (const std::string& b : vm["bias"].as<std::vector<std::string>>()) plan.biases.push_back(with_flag("--bias", [&] { return parse_plant_bias(b, op); }));
  if (!measurements_path.empty()) {
    if (!plan.biases.empty()) throw InputError("--bias: not with --measurements (the biases are the simulated plant's)");
    plan.measurements = read_measurements(measurements_path, op);
  }
  const AdaptRun run = with_flag("--start", [&] { return adapt(model, plan, settings); });
  AdaptRecordInputs in{&plan, &settings, measurements_path};
  const json record = adapt_record(run, model, in, source_of(l, common));
  const std::string table = adapt_table_csv(record);
  if (table_stdout && json_path != "-") std::cout << table;
  else if (!table_stdout) write_text_file(table_path, table);
  if (!json_path.empty()) emit(json_path, record);
  std::ostream& info = table_stdout || json_path == "-" ? std::cerr : std::cout;
  const AdaptRow& last = run.rows.back();
  info << l.cfg.name << ": " << run.rows.size() << " iterations, last loss " << value_text(last.measured.loss)
       << " at " << fmt(last.measured.cutting_speed_m_per_min, 5) << " m/min, " << fmt(last.measured.point.feed_m * 1e3, 4)
       << (model.milling() ? " mm/tooth" : " mm/rev") << (run.final_state.converged ? " (converged)" : "")
       << "; the uncorrected optimum's loss " << value_text(run.reference.best.loss) << "\n";
  if (!plot_path.empty()) {
    std::vector<MapPoint> path;
    for (const AdaptRow& r : run.rows) path.push_back({r.measured.point.spindle_rpm, r.measured.point.feed_m});
    path.push_back({run.final_state.point.spindle_rpm, run.final_state.point.feed_m});
    const LossMap map = loss_map(model, run.final_state.point.depth_m, kMapSpeeds, kMapFeeds);
    const auto files = plot_loss_map(plot_path, l.cfg.name + ": adaptive loop, gamma " + fmt(settings.gamma, 3), map,
                                     MapPoint{run.reference.best.point.spindle_rpm, run.reference.best.point.feed_m},
                                     path);
    info << "wrote plot: " << files.image.string() << " (gnuplot script " << files.script.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
