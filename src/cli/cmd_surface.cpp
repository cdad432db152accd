// `chatter surface`: the lobe surface a_lim(position, speed) of a
// position-dependent structure (docs/position.md).
#include <cmath>
#include <optional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/plot_surface.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"
#include "chatter/position.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"
#include "cmd_surface.hpp"
#include "commands.hpp"

namespace chatter::cli {
namespace {

constexpr int kDefaultPositionPoints = 21;
constexpr const char* kSurfaceUsage =
    "Usage: chatter surface CONFIG [--position-min-mm A --position-max-mm B --position-points P]\n"
    "                       [--rpm-min --rpm-max --rpm-points --depth-max-mm --method] [--table out.csv]\n"
    "                       [--plot surface.png]\n\n"
    "The lobe surface of a structure that changes along the part (a cantilever workpiece:\n"
    "position = distance from the clamp; or [[positions]] mode sets): the lobe table at\n"
    "each of P evenly spaced positions (both ends included), at the same evenly spaced\n"
    "speeds. CSV columns: position_mm,spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe\n"
    "('inf' = stable at every depth up to --depth-max-mm). The plot shows the depth limit\n"
    "over (speed, position) as colours, contours of chosen depths and the best speed at\n"
    "each position. Positions default to the whole part.\n";

// "1,2,5" -> {1, 2, 5}, each > 0.
std::vector<double> parse_depth_list(const std::string& text, const std::string& flag) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && item[used] == ' ') ++used;
    if (item.empty() || used != item.size() || !std::isfinite(v) || !(v > 0.0))
      throw InputError(flag + " = '" + text + "': must be depths in mm > 0 separated by commas (e.g. 1,2,5)");
    out.push_back(v);
  }
  if (out.empty()) throw InputError(flag + " = '" + text + "': give at least one depth, mm");
  return out;
}

}  // namespace

std::optional<SurfacePlan> plan_surface(const std::vector<std::string>& args, bool check_output_files) {
  SurfacePlan plan;
  Common& common = plan.common;
  std::string& table_path = plan.table_path;
  std::string& plot_path = plan.plot_path;
  std::string contours_text;
  po::options_description d("Options");
  add_common(d, common);
  d.add_options()
      ("position-min-mm", po::value<double>(), "first tool position, mm (default: the start of the part: the clamp, "
                                               "or the first [[positions]])")
      ("position-max-mm", po::value<double>(), "last tool position, mm (default: the end of the part: the free end, "
                                               "or the last [[positions]])")
      ("position-points", po::value<int>(), "number of positions, both ends included (>= 2; default 21)")
      ("rpm-min", po::value<double>(), "lowest spindle speed, rev/min (default: sweep.rpm_min)")
      ("rpm-max", po::value<double>(), "highest spindle speed, rev/min (default: sweep.rpm_max)")
      ("rpm-points", po::value<int>(), "number of speeds, both ends included (default: sweep.rpm_points or 400)")
      ("depth-max-mm", po::value<double>(), "deepest cut searched, mm; deeper limits print as inf (default: "
                                            "sweep.depth_max_mm or 50)")
      ("table", po::value<std::string>(&table_path), "write the CSV table here ('-': standard output; by default "
                                                     "standard output when --plot is not given)")
      ("plot", po::value<std::string>(&plot_path), "draw the surface to this .png, .svg or .pdf (with its gnuplot "
                                                   "script and data beside it)")
      ("plot-contours-mm", po::value<std::string>(&contours_text), "with --plot or --show: depths of the contour "
                                                                   "lines, mm, comma-separated (default: up to 5 "
                                                                   "round values)");
  add_show_option(d);
  add_solver_options(d);
  po::variables_map& vm = plan.vm;
  if (!parse(args, kSurfaceUsage, d, common, vm)) return std::nullopt;
  if (common.position_mm)
    throw InputError("--position-mm: not with surface (it sweeps --position-min-mm to --position-max-mm)");
  plan.show = show_request(vm);  // a display or GNUPLOT_TERM, before anything is computed
  if (vm.count("plot-contours-mm")) {
    if (plot_path.empty() && !plan.show.requested)
      throw InputError("--plot-contours-mm: only with --plot or --show (it sets the plot's contours)");
    plan.contours_mm = parse_depth_list(contours_text, "--plot-contours-mm");
  }
  plan.table_to_stdout = table_path == "-" || (table_path.empty() && plot_path.empty() && !plan.show.requested);
  if (table_path == "-") table_path.clear();
  if (check_output_files) check_outputs({{"--table", table_path}, {"--plot", plot_path, true}});  // before computing

  plan.cfg = load_checked(common);
  const Config& cfg = plan.cfg;
  const std::optional<double> min_arg =
      vm.count("position-min-mm") ? std::optional<double>(vm["position-min-mm"].as<double>()) : std::nullopt;
  const std::optional<double> max_arg =
      vm.count("position-max-mm") ? std::optional<double>(vm["position-max-mm"].as<double>()) : std::nullopt;
  const int points = vm.count("position-points") ? vm["position-points"].as<int>() : kDefaultPositionPoints;
  auto check_size = [&](const Sweep& s) {
    if (static_cast<long long>(points) * s.rpm_points > kMaxMapPoints)
      throw InputError("--position-points x --rpm-points = " + std::to_string(points) + " x " +
                       std::to_string(s.rpm_points) + ": at most " + std::to_string(kMaxMapPoints) +
                       " solves (a surface that size would not finish)");
  };
  // A count that fails the size rule at any speed count is refused before
  // the positions are laid out (they would not fit in memory).
  if (points > kMaxMapPoints) check_size(resolve_sweep(vm, cfg));
  // Positions evenly spaced in mm as typed (the table's column), in m for the
  // model, the ends exactly the checked ends (the io layer's rule, as the C
  // API and Python lay them out).
  SurfacePositions positions = surface_positions(
      cfg, min_arg, max_arg, points, {"--position-min-mm", "--position-max-mm", "--position-points"});
  const auto [part_lo_m, part_hi_m] = cfg.position.range_m();
  plan.min_mm = min_arg.value_or(part_lo_m * 1e3);
  plan.max_mm = max_arg.value_or(part_hi_m * 1e3);
  const Sweep s = plan.sweep = resolve_sweep(vm, cfg);
  check_size(s);
  plan.positions_mm = std::move(positions.mm);
  plan.positions_m = std::move(positions.m);
  const std::vector<double>& positions_m = plan.positions_m;
  plan.speeds_rpm = evenly_spaced_speeds(s.rpm_min, s.rpm_max, s.rpm_points);

  // One solver checked (options, notes, what the method accepts) at the first
  // position; the others built the same way inside the sweep.
  plan.depth_max_m = s.depth_max_mm * 1e-3;
  Config first = cfg;
  first.model = with_flag("--position-min-mm", [&] { return model_at_position(cfg, positions_m.front()); });
  const BuiltSolver built = build_solver(common.method, first, plan.depth_max_m, vm);
  plan.common.method = built.method;  // "auto" resolved
  plan.recipe = built.recipe;
  plan.method = built.solver->method();
  plan.threads = thread_count(vm);
  return plan;
}

std::unique_ptr<LobeSolver> surface_solver(const SurfacePlan& plan, const StructuralModel& model) {
  return plan.recipe.build(model, plan.cfg.process, plan.depth_max_m);
}

std::vector<std::vector<StabilityLimit>> surface_rows(const SurfacePlan& plan) {
  const SolverFactory factory = [&](const StructuralModel& model) { return surface_solver(plan, model); };
  Progress progress(plan.vm, plan.positions_m.size(), "surface (" + plan.method + ")");
  return lobe_surface(plan.cfg.model, plan.cfg.position, plan.positions_m, plan.speeds_rpm, factory, plan.threads,
                      [&](std::size_t done) { progress.tick(done); });
}

int write_surface(const SurfacePlan& plan, const std::vector<std::vector<StabilityLimit>>& rows,
                  PlotWindow* window) {
  const Config& cfg = plan.cfg;
  const Sweep& s = plan.sweep;
  const std::vector<double>& positions_mm = plan.positions_mm;
  const std::vector<double>& speeds = plan.speeds_rpm;
  const std::string& table_path = plan.table_path;
  const std::string& plot_path = plan.plot_path;
  const bool table_to_stdout = plan.table_to_stdout;
  const double min_mm = plan.min_mm, max_mm = plan.max_mm;
  const std::size_t points = positions_mm.size();
  std::vector<double> contours = plan.contours_mm;

  // The table: each position's lobe table, its rows prefixed by the position.
  std::ostringstream csv;
  csv << "position_mm,spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe\n";
  for (std::size_t p = 0; p < rows.size(); ++p) {
    std::ostringstream one;
    write_lobe_csv(one, rows[p]);
    std::string line;
    std::istringstream in(one.str());
    std::getline(in, line);  // the lobe table's header
    while (std::getline(in, line)) csv << table_number(positions_mm[p]) << ',' << line << '\n';
  }

  LobeSurfaceData surface{positions_mm, rows, s.depth_max_mm};
  const std::vector<StabilityLimit> best = best_speed_per_position(surface);
  std::size_t weakest = 0;  // the position whose best speed is shallowest
  for (std::size_t p = 1; p < best.size(); ++p)
    if (best[p].depth_limit_m < best[weakest].depth_limit_m) weakest = p;
  auto depth_text = [&](const StabilityLimit& r) {
    return r.bounded() ? fmt(r.depth_limit_m * 1e3, 5) + " mm" : "no limit below " + fmt(s.depth_max_mm) + " mm";
  };
  std::ostringstream summary;
  summary << cfg.name << " (" << plan.method << "): " << points << " positions " << fmt(min_mm) << "-"
          << fmt(max_mm) << " mm x " << speeds.size() << " speeds " << fmt(s.rpm_min) << "-" << fmt(s.rpm_max)
          << " rev/min; weakest position " << fmt(positions_mm[weakest]) << " mm (best there: "
          << depth_text(best[weakest]) << " at " << fmt(best[weakest].spindle_rpm) << " rev/min); at "
          << fmt(positions_mm.front()) << " mm: " << depth_text(best.front()) << " at "
          << fmt(best.front().spindle_rpm) << " rev/min; at " << fmt(positions_mm.back())
          << " mm: " << depth_text(best.back()) << " at " << fmt(best.back().spindle_rpm) << " rev/min";

  if (!table_path.empty()) write_text_files({{table_path, csv.str()}});
  if (table_to_stdout) std::cout << csv.str();
  std::ostream& info = table_to_stdout ? std::cerr : std::cout;
  info << summary.str() << "\n";
  if (!table_path.empty()) info << "wrote surface table: " << table_path << "\n";
  if (contours.empty() && (!plot_path.empty() || window)) contours = default_contour_depths_mm(surface);
  const std::string title = cfg.name + " (" + plan.method + "): lobe surface";
  if (!plot_path.empty()) {
    const auto files = plot_surface(plot_path, title, surface, contours);
    info << "wrote plot: " << files.image.string() << " (gnuplot script " << files.script.string() << ", data "
         << files.data.string() << ")\n";
  }
  if (window) plot_surface(*window, title, surface, contours);
  return 0;
}

}  // namespace chatter::cli
