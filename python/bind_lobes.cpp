// chatter.lobes, chatter.point, chatter.surface, chatter.uncertain_lobes:
// the lobe commands' numbers as NumPy arrays, and point's record as a dict
// (docs/python.md). Each follows the CLI command of the same name.
#include <chrono>
#include <cmath>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/position.hpp"
#include "chatter/records.hpp"
#include "chatter/records/lobes.hpp"
#include "chatter/report.hpp"
#include "chatter/uncertainty.hpp"
#include "chatter/usual_bands.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

// What a table's dict does not hold (its keys are the CSV's columns): the
// method used, the config's name and warnings, the method's notes, the depth
// searched (chatter::lobe_columns_fields). The Python package keeps it beside
// the table (Lobes.info).
chatter::LobeColumnsSource table_source(const chatter::Config& cfg, const Built& built, double depth_max_mm) {
  return {built.solver->method(), &cfg, built.notes, depth_max_mm};
}

py::tuple lobes(const Job& job_in, const std::string& method, std::optional<double> rpm_min,
               std::optional<double> rpm_max, std::optional<int> rpm_points, std::optional<double> depth_max_mm,
               const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& rpm, int threads,
               const std::optional<py::dict>& options, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  std::vector<double> speeds;
  if (rpm) {
    if (rpm_min || rpm_max || rpm_points) throw InputError("rpm: give either rpm or rpm_min/rpm_max/rpm_points");
    if (rpm->ndim() != 1) throw InputError("rpm: must be a one-dimensional array of speeds, rev/min");
    speeds.assign(rpm->data(), rpm->data() + rpm->size());
    if (speeds.empty()) throw InputError("rpm: empty (give at least one speed)");
    for (std::size_t i = 0; i < speeds.size(); ++i)
      if (!(std::isfinite(speeds[i]) && speeds[i] > 0.0))
        throw InputError("rpm[" + std::to_string(i) + "] = " + fmt(speeds[i]) + ": must be > 0 rev/min");
  } else {
    speeds = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  }
  const double dmax = depth_max_mm.value_or(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm));
  if (!(std::isfinite(dmax) && dmax > 0.0)) throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > 0 mm");
  const unsigned nthreads = thread_count(threads);
  const std::shared_ptr<const Built> built = build_solver(job, method, dmax * 1e-3, options);
  const chatter::LobeSolver& solver = *built->solver;
  const std::vector<chatter::DiagnosticColumn> columns = solver.diagnostic_columns();

  std::vector<chatter::StabilityLimit> rows(speeds.size());
  std::vector<std::vector<chatter::SolverValue>> values;
  {
    py::gil_scoped_release release;
    if (!columns.empty()) {
      values.resize(speeds.size());
      chatter::parallel_for(speeds.size(), nthreads, [&](std::size_t i) {
        chatter::DiagnosedLimit r = solver.limit_with_diagnostics(chatter::SpindleSpeed(speeds[i]));
        rows[i] = r.limit;
        values[i] = std::move(r.values);
      });
    } else {
      rows = chatter::lobe_envelope(solver, speeds, nthreads);
    }
  }

  return to_python_table(chatter::lobe_columns(rows, columns, values, table_source(cfg, *built, dmax)));
}

// ------------------------------------------------------------------ point

/// chatter point's record (chatter/records.hpp), as a dict.
py::dict point(const Job& job_in, double rpm, double depth_mm, const std::string& method,
               std::optional<double> depth_max_mm, const std::optional<py::dict>& options,
               std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  chatter::check_spindle_rpm(rpm, "rpm");
  chatter::check_depth_mm(depth_mm, "depth_mm");
  double dmax = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 2.0 * depth_mm);
  if (depth_max_mm) {
    dmax = *depth_max_mm;
    if (!(std::isfinite(dmax) && dmax > depth_mm))
      throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > depth_mm (" + fmt(depth_mm) + ")");
  }
  const std::shared_ptr<const Built> built = build_solver(job, method, dmax * 1e-3, options);
  chatter::PointReport report;
  {
    py::gil_scoped_release release;
    report = chatter::report_point(*built->solver, cfg.process, rpm, depth_mm);
  }
  chatter::RecordSource source = chatter::record_source(cfg, position_mm);
  source.notes = built->notes;
  // Keyword arguments outside their usual band, as the CLI's flags (docs/results.md, rule 2).
  for (std::string& w : chatter::unusual_arguments({{"rpm", rpm}, {"depth_mm", depth_mm}}))
    source.warnings.push_back(std::move(w));
  return chatter_py::to_python(chatter::point_record(report, source));
}

// For bench/bench_python.py: seconds of the bare C++ work of lobes() on a
// built solver (lobe_envelope or the diagnosed loop; a repeated lobes() call
// finds its solver in the job's cache), no Python objects, so the module's
// overhead can be measured against it.
double time_lobes_cpp(const Job& job, const std::string& method,
                      const py::array_t<double, py::array::c_style | py::array::forcecast>& rpm, double depth_max_mm,
                      int threads) {
  const std::vector<double> speeds(rpm.data(), rpm.data() + rpm.size());
  const unsigned n = thread_count(threads);
  const std::shared_ptr<const Built> built = build_solver(job, method, depth_max_mm * 1e-3, std::nullopt);
  const chatter::LobeSolver* solver = built->solver.get();
  py::gil_scoped_release release;
  const auto t0 = std::chrono::steady_clock::now();
  if (solver->diagnostic_columns().empty()) {
    const auto rows = chatter::lobe_envelope(*solver, speeds, n);
  } else {
    std::vector<chatter::DiagnosedLimit> rows(speeds.size());
    chatter::parallel_for(speeds.size(), n, [&](std::size_t i) { rows[i] = solver->limit_with_diagnostics(chatter::SpindleSpeed(speeds[i])); });
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ------------------------------------------------------------------ surface

/// `chatter surface`'s table as arrays: positions placed by the io layer
/// (chatter::surface_positions, the CLI's), the sweep by lobe_surface.
py::tuple surface(const Job& job, const std::string& requested, std::optional<double> position_min_mm,
                 std::optional<double> position_max_mm, int position_points, std::optional<double> rpm_min,
                 std::optional<double> rpm_max, std::optional<int> rpm_points, std::optional<double> depth_max_mm,
                 int threads, const std::optional<py::dict>& options) {
  const chatter::Config& cfg = *job.cfg;
  const chatter::SurfacePositions pos = chatter::surface_positions(cfg, position_min_mm, position_max_mm, position_points);
  const std::vector<double> speeds = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  if (static_cast<long long>(pos.m.size()) * static_cast<long long>(speeds.size()) > kMaxSurfacePoints)
    throw InputError("position_points x rpm_points = " + std::to_string(pos.m.size()) + " x " +
                     std::to_string(speeds.size()) + ": at most " + std::to_string(kMaxSurfacePoints) +
                     " solves (a surface that size would not finish)");
  const double dmax = depth_max_mm.value_or(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm));
  if (!(std::isfinite(dmax) && dmax > 0.0)) throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > 0 mm");
  const unsigned nthreads = thread_count(threads);
  // "auto" resolved on the first position's structure (the CLI's surface: build_solver there).
  const std::string method = chatter::resolve_lobe_method(
      requested, chatter::model_at_position(cfg, pos.m.front()), cfg.process);
  const chatter::SolverDescriptor& descriptor = chatter::find_lobe_method(method);
  const chatter::SolverValues values = solver_values(cfg, descriptor, method, options);
  const double depth_max_m = dmax * 1e-3;
  std::vector<std::vector<chatter::StabilityLimit>> rows;
  {
    py::gil_scoped_release release;
    // The method checked at the first position before the sweep (as the CLI).
    const chatter::SolverRecipe recipe{method, values};
    (void)recipe.build(chatter::model_at_position(cfg, pos.m.front()), cfg.process, depth_max_m);
    const chatter::SolverFactory factory = [&](const chatter::StructuralModel& model) {
      return recipe.build(model, cfg.process, depth_max_m);
    };
    rows = chatter::lobe_surface(cfg.model, cfg.position, pos.m, speeds, factory, nthreads);
  }
  const chatter::LobeColumnsSource source{
      method, &cfg,
      chatter::method_notes(requested, descriptor, cfg.process, values, "", chatter::ArgStyle::kKeyword), dmax};
  return to_python_table(chatter::surface_columns(pos.mm, rows, source));
}

// ------------------------------------------------------------------ Monte Carlo

/// `chatter lobes --samples N`'s numbers as arrays (docs/uncertainty.md): the
/// nominal lobes, the 5/50/95 % quantile lobes of N models drawn from the
/// config's [uncertainty] spreads, and the probability of stability over a
/// (speed, depth) grid chosen as the CLI's (chatter::probability_depth_grid).
/// Same seed, same numbers as the CLI, whatever `threads`.
py::dict uncertain_lobes(const Job& job_in, const std::string& method, long long samples, long long seed,
                         std::optional<double> rpm_min, std::optional<double> rpm_max, std::optional<int> rpm_points,
                         std::optional<double> depth_max_mm, int depth_points,
                         std::optional<double> probability_depth_max_mm, int threads,
                         const std::optional<py::dict>& options, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  if (!cfg.uncertainty)
    throw InputError(cfg.source.string() +
                     ": no [uncertainty] table (give the 1-sigma spreads in percent; docs/config.md)");
  if (const std::string why = cfg.uncertainty->validate(cfg.model, cfg.process); !why.empty())
    throw InputError(cfg.source.string() + ": uncertainty: " + why);
  const std::vector<double> speeds = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  if (samples < 1) throw InputError("samples = " + std::to_string(samples) + ": must be >= 1");
  if (samples > kMaxMonteCarloSolves / static_cast<long long>(speeds.size()))
    throw InputError("samples x rpm_points = " + std::to_string(samples) + " x " + std::to_string(speeds.size()) +
                     ": at most " + std::to_string(kMaxMonteCarloSolves) +
                     " limits are held in memory (32 bytes each); use fewer samples or speeds");
  if (seed < 0) throw InputError("seed = " + std::to_string(seed) + ": must be an integer >= 0");
  if (depth_points < 2 || depth_points > 10000)
    throw InputError("depth_points = " + std::to_string(depth_points) + ": must be in [2, 10000]");
  const double dmax = depth_max_mm.value_or(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm));
  if (!(std::isfinite(dmax) && dmax > 0.0)) throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > 0 mm");
  if (probability_depth_max_mm && !(std::isfinite(*probability_depth_max_mm) && *probability_depth_max_mm > 0.0))
    throw InputError("probability_depth_max_mm = " + fmt(*probability_depth_max_mm) + ": must be > 0 mm");
  const unsigned nthreads = thread_count(threads);
  const std::shared_ptr<const Built> built = build_solver(job, method, dmax * 1e-3, options);
  const double depth_max_m = dmax * 1e-3;
  std::vector<chatter::StabilityLimit> nominal;
  chatter::UncertainLobes mc;
  chatter::ProbabilityDepthGrid grid;
  {
    py::gil_scoped_release release;
    nominal = chatter::lobe_envelope(*built->solver, speeds, nthreads);
    const chatter::SampleSolverFactory factory = [&](const chatter::StructuralModel& model,
                                                     const chatter::Process& process) {
      return built->recipe.build(model, process, depth_max_m);
    };
    const auto rows = chatter::monte_carlo_limits(cfg.model, cfg.process, *cfg.uncertainty,
                                                  static_cast<std::uint64_t>(seed), 0,
                                                  static_cast<std::uint64_t>(samples), speeds, factory, nthreads);
    grid = chatter::probability_depth_grid(rows, dmax, depth_points, probability_depth_max_mm);
    mc = chatter::reduce_monte_carlo(
        rows, grid.depths_m,
        std::vector<double>(std::begin(chatter::kUncertaintyLevels), std::end(chatter::kUncertaintyLevels)));
  }
  return to_python(chatter::uncertain_lobe_columns(nominal, mc, table_source(cfg, *built, dmax), samples, seed,
                                                    position_mm));
}

}  // namespace

void bind_lobes(py::module_& m) {
  m.def("lobes", &lobes, "job"_a, "method"_a = "auto", py::kw_only(), "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "rpm_points"_a = py::none(), "depth_max_mm"_a = py::none(), "rpm"_a = py::none(),
        "threads"_a = 0, "options"_a = py::none(), "position_mm"_a = py::none(),
        "The stability-lobe table as NumPy arrays (chatter lobes).");
  m.def("point", &point, "job"_a, py::kw_only(), "rpm"_a, "depth_mm"_a, "method"_a = "auto",
        "depth_max_mm"_a = py::none(), "options"_a = py::none(), "position_mm"_a = py::none(),
        "One operating point (chatter point's JSON).");
  m.def("surface", &surface, "job"_a, "method"_a = "auto", py::kw_only(), "position_min_mm"_a = py::none(),
        "position_max_mm"_a = py::none(), "position_points"_a = kDefaultPositionPoints, "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "rpm_points"_a = py::none(), "depth_max_mm"_a = py::none(), "threads"_a = 0,
        "options"_a = py::none(), "The lobe surface over (position, speed) as NumPy arrays (chatter surface).");
  m.def("uncertain_lobes", &uncertain_lobes, "job"_a, "method"_a = "auto", py::kw_only(), "samples"_a,
        "seed"_a = 1, "rpm_min"_a = py::none(), "rpm_max"_a = py::none(), "rpm_points"_a = py::none(),
        "depth_max_mm"_a = py::none(), "depth_points"_a = kDefaultDepthPoints,
        "probability_depth_max_mm"_a = py::none(), "threads"_a = 0, "options"_a = py::none(),
        "position_mm"_a = py::none(),
        "Monte Carlo lobes over the config's [uncertainty] spreads as NumPy arrays (chatter lobes --samples).");
  m.def("_time_lobes_cpp", &time_lobes_cpp, "job"_a, "method"_a, "rpm"_a, "depth_max_mm"_a, "threads"_a = 1,
        "Benchmark hook: seconds of the C++ work of lobes() alone.");
}

}  // namespace chatter_py
