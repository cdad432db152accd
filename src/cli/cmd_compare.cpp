// `chatter compare`: every method that applies to a config at the same
// spindle speeds, one table, and the largest difference between each pair of
// methods: the cross-check people use to trust the numbers (issue 5).
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

int cmd_compare(const std::vector<std::string>& args) {
  Common common;
  std::string table_path, json_path, plot_path;
  po::options_description d("Options");
  d.add_options()
      ("rpm-min", po::value<double>(), "lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("rpm-points", po::value<int>(), "number of evenly spaced speeds (default: sweep.rpm_points or 400)")
      ("depth-max-mm", po::value<double>(), "deepest cut searched, mm (default: sweep.depth_max_mm or 50)")
      ("table", po::value<std::string>(&table_path), "write the comparison CSV here (default: standard output)")
      ("json", po::value<std::string>(&json_path), "also write the pairwise differences as JSON")
      ("plot", po::value<std::string>(&plot_path), "draw every method's depth limit on one chart to this .png, .svg or .pdf (with its gnuplot script and data beside it)");
  add_solver_options(d);
  po::variables_map vm;
  if (!parse(args, "Usage: chatter compare CONFIG [options]\n\n"
                   "Runs every method that applies to the config (analytic; coupled and sdm when the\n"
                   "structure is given by modes) at the same spindle speeds and prints one table,\n"
                   "spindle_rpm then depth_limit_mm_<method> for each, plus sdm's multiplier type,\n"
                   "and the largest relative difference of the depth limit between each pair.\n"
                   "analytic and coupled must agree to round-off; sdm agrees with them in turning\n"
                   "(to its discretisation error, ~0.2 %) and differs in milling where the cutting\n"
                   "force is intermittent (flip lobes at low radial immersion). --plot overlays the\n"
                   "methods' limits (mm) against spindle speed, sdm's flip-limited speeds marked.\n",
             d, common, vm))
    return 0;
  if (!plot_path.empty()) check_plot_path(plot_path);  // fail before computing
  const Config cfg = load_config(common.config_path);
  const Sweep s = resolve_sweep(vm, cfg);
  const unsigned threads = thread_count(vm);
  std::vector<std::string> methods = {"analytic"};
  if (!cfg.model.has_measured()) {
    methods.push_back("coupled");
    methods.push_back("sdm");
  }
  const auto speeds = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  std::vector<std::vector<StabilityLimit>> rows(methods.size());
  std::vector<FloquetResult> floquet(speeds.size());
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const BuiltSolver b = build_solver(methods[m], cfg, s.depth_max_mm * 1e-3, vm);
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
  const bool has_sdm = methods.back() == "sdm";
  if (has_sdm) csv << ",multiplier_type_sdm";
  csv << '\n';
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    csv << table_number(speeds[i]);
    for (std::size_t m = 0; m < methods.size(); ++m) csv << ',' << table_number(rows[m][i].depth_limit_m * 1e3);
    if (has_sdm) csv << ',' << (rows.back()[i].bounded() ? to_string(floquet[i].type) : "");
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
  if (has_sdm) {
    // Explain where sdm and the averaged (zeroth-order) method must differ.
    std::size_t flips = 0, flips_deeper_tf = 0;
    for (std::size_t i = 0; i < speeds.size(); ++i)
      if (rows.back()[i].bounded() && floquet[i].type == MultiplierType::kFlip) {
        ++flips;
        if (rows[0][i].depth_limit_m > 1.05 * rows.back()[i].depth_limit_m) ++flips_deeper_tf;
      }
    if (flips > 0)
      report << "  sdm finds period-doubling (flip) chatter at " << flips << " speeds; at " << flips_deeper_tf
             << " of them the analytic limit is more than 5 % deeper: the transfer-function method averages\n"
                "  the cutting force over the tooth period and cannot see flip lobes (low radial immersion).\n";
    else if (cfg.process.operation() == Operation::kTurning)
      report << "  turning has constant coefficients: sdm differs from the exact analytic limit only by its\n"
                "  discretisation error.\n";
  }

  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!table_path.empty()) files.emplace_back(table_path, csv.str());
  if (!json_path.empty()) {
    nlohmann::json j = {{"config", cfg.source.string()}, {"name", cfg.name}, {"methods", methods},
                        {"rpm_min", s.rpm_min},          {"rpm_max", s.rpm_max}, {"rpm_points", s.rpm_points},
                        {"depth_max_mm", s.depth_max_mm}, {"pairs", pairs}};
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
