// `chatter compare`: several methods at the same spindle speeds (--methods;
// by default analytic, coupled and sdm where they apply, time-domain only on
// request since it is slow), one table, and the largest difference between
// each pair of methods: the cross-check people use to trust the numbers
// (issue 5). The work and the record: compare_methods (chatter/records/lobes.hpp).
#include <iostream>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/lobes.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "live_plot.hpp"

namespace chatter::cli {

namespace {

// compare's usage text.
const char* const kCompareUsage =
    "Usage: chatter compare CONFIG [--methods LIST] [options]\n\n"
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
    "--plot (or --show) overlays the methods' limits (mm) against spindle speed, sdm's\n"
    "flip-limited speeds marked.\n";

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
      ("json", po::value<std::string>(&json_path), "write the pairwise differences as JSON ('-': standard output, the report then goes "
       "to standard error)")
      ("plot", po::value<std::string>(&plot_path), "draw every method's depth limit on one chart to this .png, .svg or .pdf (with its gnuplot script and data beside it)")
      ("plot-depth-max-mm", po::value<double>(), kPlotDepthMaxHelp);
  add_show_option(d);
  add_solver_options(d);
  po::variables_map vm;
  if (!parse(args, kCompareUsage, d, common, vm)) return 0;
  std::optional<std::string> methods_given;
  if (vm.count("methods")) methods_given = methods_list;
  parse_compare_methods(methods_given, ArgStyle::kFlag);  // fail before reading the config
  const ShowRequest show = show_request(vm);              // a display or GNUPLOT_TERM, before computing
  const bool table_to_stdout =
      table_path == "-" || (table_path.empty() && json_path.empty() && plot_path.empty() && !show.requested);
  const bool json_to_stdout = json_path == "-";
  if (table_path == "-" && json_to_stdout)
    throw InputError("--table - and --json -: only one of them can go to standard output");
  if (table_path == "-") table_path.clear();
  if (json_to_stdout) json_path.clear();
  check_outputs({{"--table", table_path}, {"--json", json_path}, {"--plot", plot_path, true}});  // before computing
  const double plot_depth_axis_mm = plot_depth_max_mm(vm, !plot_path.empty() || show.requested);
  const Config cfg = load_checked(common);
  CompareRequest q;
  q.methods = choose_compare_methods(methods_given, cfg, ArgStyle::kFlag);
  check_solver_options(q.methods, vm, "--methods");
  const Sweep s = resolve_sweep(vm, cfg);
  q.speeds_rpm = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);
  q.depth_max_mm = s.depth_max_mm;
  q.options = [&](const SolverDescriptor& method) { return solver_option_values(method, cfg, vm); };
  q.threads = thread_count(vm);
  std::unique_ptr<Progress> progress;
  q.progress = [&](const std::string& method, std::size_t done, std::size_t total) {
    if (done == 0) progress = std::make_unique<Progress>(vm, total, "compare (" + method + ")");
    else progress->tick(done);
  };
  const Comparison c = compare_methods(cfg, q);
  progress.reset();
  for (const auto& m : c.methods)
    for (const std::string& n : m.notes) std::cerr << "note: " << n << "\n";

  const std::string csv = comparison_csv(c);
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  if (!table_path.empty()) files.emplace_back(table_path, csv);
  const std::string json_text =
      json_path.empty() && !json_to_stdout ? std::string()
                                           : comparison_record(c, record_source(cfg, common.position_mm)).dump(2) + "\n";
  if (!json_path.empty()) files.emplace_back(json_path, json_text);
  write_text_files(files);
  if (table_to_stdout) std::cout << csv;
  if (json_to_stdout) std::cout << json_text;
  std::ostream& info = table_to_stdout || json_to_stdout ? std::cerr : std::cout;
  info << c.explanation;
  for (const auto& [file, text] : files) info << "wrote " << file.string() << "\n";  // every file, not only the plot
  PlotOptions options;
  options.depth_axis_max_mm = plot_depth_axis_mm;
  const std::string title = cfg.name + ": depth limit by method";
  if (!plot_path.empty()) {
    const auto plot = plot_compare(plot_path, title, comparison_plot_lines(c), s.depth_max_mm * 1e-3, options);
    info << "wrote plot: " << plot.image.string() << " (gnuplot script " << plot.script.string() << ", data "
         << plot.data.string() << ")\n";
  }
  if (show.requested) {
    {
      LiveWindow window(show);
      plot_compare(window, title, comparison_plot_lines(c), s.depth_max_mm * 1e-3, options);
    }
    report_shown(info, show);
  }
  return 0;
}

}  // namespace chatter::cli
