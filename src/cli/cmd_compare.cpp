// `chatter compare`: several methods at the same spindle speeds (--methods;
// by default analytic, coupled and sdm where they apply, time-domain only on
// request since it is slow), one table, and the largest difference between
// each pair of methods: the cross-check people use to trust the numbers
// (issue 5).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {

namespace {

// Every method compare knows, in its default order.
const std::vector<std::string> kMethods = {"analytic", "coupled", "sdm", "time-domain"};
const std::string kMethodsRule =
    "a comma-separated list of distinct methods from analytic, coupled, sdm, time-domain, or 'all'";

bool has(const std::vector<std::string>& v, const std::string& x) { return std::find(v.begin(), v.end(), x) != v.end(); }

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
      throw InputError(given + (list.empty() ? "empty list" : "empty name") + "; must be " + kMethodsRule);
    if (name == "all") throw InputError(given + "'all' must stand alone; must be " + kMethodsRule);
    if (!has(kMethods, name)) throw InputError(given + "unknown method '" + name + "'; must be " + kMethodsRule);
    if (has(out, name)) throw InputError(given + "'" + name + "' given twice; must be " + kMethodsRule);
    out.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
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
      ("table", po::value<std::string>(&table_path), "write the comparison CSV here (default: standard output)")
      ("json", po::value<std::string>(&json_path), "also write the pairwise differences as JSON")
      ("plot", po::value<std::string>(&plot_path), "draw every method's depth limit on one chart to this .png, .svg or .pdf (with its gnuplot script and data beside it)");
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
  if (!plot_path.empty()) check_plot_path(plot_path);  // fail before computing
  const Config cfg = load_checked(common);
  const bool measured = cfg.model.has_measured();
  const auto applies = [&](const std::string& m) { return m == "analytic" || !measured; };
  if (all) {
    for (const auto& m : kMethods)
      if (applies(m)) methods.push_back(m);
  } else if (methods.empty()) {
    for (const auto& m : {"analytic", "coupled", "sdm"})
      if (applies(m)) methods.emplace_back(m);
  } else {
    for (const auto& m : methods)
      if (!applies(m))
        throw InputError("--methods '" + methods_list + "': " + m + " does not apply to " + cfg.source.string() +
                         ": it has measured FRFs, and only analytic works from measured data (fit modes with "
                         "chatter fit for the others)");
  }
  check_solver_options(methods, vm, "--methods");
  const Sweep s = resolve_sweep(vm, cfg);
  const unsigned threads = thread_count(vm);
  const auto speeds = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  std::vector<std::vector<StabilityLimit>> rows(methods.size());
  std::vector<FloquetResult> floquet(speeds.size());
  // Build every solver before running any: a bad option fails at once.
  std::vector<BuiltSolver> built;
  nlohmann::json solver_options = nlohmann::json::object();
  for (const auto& m : methods) {
    built.push_back(build_solver(m, cfg, s.depth_max_mm * 1e-3, vm, /*check_options=*/false));
    solver_options[m] = nlohmann::json::parse(built.back().options_json);
  }
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const BuiltSolver& b = built[m];
    Progress progress(vm, speeds.size(), "compare (" + methods[m] + ")");
    rows[m].resize(speeds.size());
    parallel_for(
        speeds.size(), threads,
        [&](std::size_t i) {
          rows[m][i] = b.sdm ? b.sdm->limit_at(speeds[i], &floquet[i]) : b.solver->limit_at(speeds[i]);
        },
        [&](std::size_t done) { progress.tick(done); });
  }

  std::ostringstream csv;
  csv << "spindle_rpm";
  for (const auto& m : methods) csv << ",depth_limit_mm_" << m;
  const auto index_of = [&](const std::string& m) -> std::ptrdiff_t {
    const auto it = std::find(methods.begin(), methods.end(), m);
    return it == methods.end() ? -1 : it - methods.begin();
  };
  const std::ptrdiff_t sdm = index_of("sdm");
  const bool has_sdm = sdm >= 0;
  if (has_sdm) csv << ",multiplier_type_sdm";
  csv << '\n';
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    csv << table_number(speeds[i]);
    for (std::size_t m = 0; m < methods.size(); ++m) csv << ',' << table_number(rows[m][i].depth_limit_m * 1e3);
    if (has_sdm) csv << ',' << (rows[sdm][i].bounded() ? to_string(floquet[i].type) : "");
    csv << '\n';
  }

  // Largest relative difference per pair, over speeds where both are bounded;
  // speeds where only one of them finds a limit are counted apart.
  nlohmann::json pairs = nlohmann::json::array();
  std::ostringstream report;
  report << cfg.name << ": " << speeds.size() << " speeds " << fmt(s.rpm_min) << "-" << fmt(s.rpm_max)
         << " rev/min, depth searched to " << fmt(s.depth_max_mm) << " mm\n";
  for (std::size_t a = 0; a < methods.size(); ++a)
    for (std::size_t b = a + 1; b < methods.size(); ++b) {
      double worst = 0.0, at = 0.0;
      std::size_t only_a = 0, only_b = 0;
      for (std::size_t i = 0; i < speeds.size(); ++i) {
        const auto &la = rows[a][i], &lb = rows[b][i];
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
      report << "  " << methods[a] << " vs " << methods[b] << ": largest relative difference " << fmt(worst, 3)
             << " (at " << fmt(at) << " rev/min)";
      if (only_a + only_b > 0)
        report << "; a limit below " << fmt(s.depth_max_mm) << " mm found only by " << methods[a] << " at "
               << only_a << " speeds, only by " << methods[b] << " at " << only_b;
      report << '\n';
      pairs.push_back({{"methods", {methods[a], methods[b]}},
                       {"largest_relative_difference", worst},
                       {"at_spindle_rpm", at},
                       {"bounded_only_by_first", only_a},
                       {"bounded_only_by_second", only_b}});
    }
  // The zeroth-order (averaged) method the others are measured against.
  const std::ptrdiff_t averaged = index_of("analytic") >= 0 ? index_of("analytic") : index_of("coupled");
  const bool turning = cfg.process.operation() == Operation::kTurning;
  if (has_sdm) {
    // Explain where sdm and the averaged (zeroth-order) method must differ.
    std::size_t flips = 0, flips_deeper_tf = 0;
    for (std::size_t i = 0; i < speeds.size(); ++i)
      if (rows[sdm][i].bounded() && floquet[i].type == MultiplierType::kFlip) {
        ++flips;
        if (averaged >= 0 && rows[averaged][i].depth_limit_m > 1.05 * rows[sdm][i].depth_limit_m) ++flips_deeper_tf;
      }
    if (flips > 0 && averaged >= 0)
      report << "  sdm finds period-doubling (flip) chatter at " << flips << " speeds; at " << flips_deeper_tf
             << " of them the " << methods[averaged]
             << " limit is more than 5 % deeper: the transfer-function method averages\n"
                "  the cutting force over the tooth period and cannot see flip lobes (low radial immersion).\n";
    else if (flips > 0)
      report << "  sdm finds period-doubling (flip) chatter at " << flips
             << " speeds: the transfer-function methods (analytic, coupled) cannot see flip lobes.\n";
    else if (turning && averaged >= 0)
      report << "  turning has constant coefficients: sdm differs from the exact " << methods[averaged]
             << " limit only by its\n  discretisation error.\n";
  }
  if (const std::ptrdiff_t td = index_of("time-domain"); td >= 0) {
    const auto& o = built[td].td->simulator().options();
    report << "  time-domain: each limit is the middle of a depth bracket " << fmt(o.depth_tolerance * 100, 3)
           << " % wide, every depth judged by simulating\n  " << o.periods << " delay periods"
           << (o.linear ? " of the linear equation" : " with the nonlinear chip (the tool may leave the cut)");
    if (turning)
      report << "; turning has constant\n  coefficients: time-domain should match the exact limit to about "
                "the bracket width.\n";
    else
      report << "; like sdm it sees the\n  intermittent cut of milling (flip lobes) that the averaged methods "
                "miss.\n";
  }

  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!table_path.empty()) files.emplace_back(table_path, csv.str());
  if (!json_path.empty()) {
    nlohmann::json j = {{"config", cfg.source.string()}, {"name", cfg.name}, {"methods", methods},
                        {"rpm_min", s.rpm_min},          {"rpm_max", s.rpm_max}, {"rpm_points", s.rpm_points},
                        {"depth_max_mm", s.depth_max_mm}, {"solver_options", solver_options}, {"warnings", cfg.warnings},
                        {"pairs", pairs}};
    files.emplace_back(json_path, j.dump(2) + "\n");
  }
  write_text_files(files);
  if (table_path.empty()) std::cout << csv.str();
  std::ostream& info = table_path.empty() ? std::cerr : std::cout;
  info << report.str();
  if (!plot_path.empty()) {
    std::vector<MethodLimits> lines(methods.size());
    for (std::size_t m = 0; m < methods.size(); ++m) {
      lines[m].method = methods[m];
      lines[m].limits = rows[m];
      if (methods[m] == "sdm")
        for (const auto& f : floquet) lines[m].multiplier_type.push_back(f.type);
    }
    const auto plot = plot_compare(plot_path, cfg.name + ": depth limit by method", lines, s.depth_max_mm * 1e-3);
    info << "wrote plot: " << plot.image.string() << " (gnuplot script " << plot.script.string() << ", data "
         << plot.data.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
