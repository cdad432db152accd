// chatter.compare, chatter.map, chatter.frf: the records and tables of
// `chatter compare`, `chatter map` and `chatter frf`, computed by the same
// library functions as the CLI (chatter/records/lobes.hpp): the record as a
// dict, each table column as a NumPy array named as its CSV column
// (docs/python.md).
#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/records.hpp"
#include "chatter/records/lobes.hpp"
#include "chatter/report.hpp"
#include "chatter/semi_discretization.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

// The depth searched: the argument, else the config's sweep, else 50 mm.
double depth_max(const chatter::Config& cfg, std::optional<double> depth_max_mm) {
  const double d = depth_max_mm.value_or(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm));
  if (!(std::isfinite(d) && d > 0.0)) throw InputError("depth_max_mm = " + fmt(d) + ": must be > 0 mm");
  return d;
}

// `methods` as the CLI's --methods text: None, "all", "a,b" or a list of names.
std::optional<std::string> methods_text(const py::object& methods) {
  if (methods.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(methods)) return methods.cast<std::string>();
  std::string text;
  for (auto m : methods) text += (text.empty() ? "" : ",") + py::str(m).cast<std::string>();
  return text;
}

// ------------------------------------------------------------------ compare

py::dict compare(const Job& job_in, const py::object& methods, std::optional<double> rpm_min,
                 std::optional<double> rpm_max, std::optional<int> rpm_points, std::optional<double> depth_max_mm,
                 int threads, const std::optional<py::dict>& options, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  chatter::CompareRequest q;
  q.methods = chatter::choose_compare_methods(methods_text(methods), cfg, chatter::ArgStyle::kKeyword);
  // Each option must belong to one of the methods compared (the CLI's rule);
  // each method gets the ones it has.
  if (options)
    for (auto item : *options) {
      const std::string name = py::str(item.first).cast<std::string>();
      bool owned = false;
      for (const std::string& m : q.methods)
        for (const auto& o : chatter::find_lobe_method(m).options) owned = owned || o.name == name;
      if (!owned) {
        std::string list;
        for (const std::string& m : q.methods) list += (list.empty() ? "" : ", ") + m;
        throw InputError("options: '" + name + "': not an option of the methods compared (" + list + ")");
      }
    }
  // Each method's options, checked with the GIL held (read from the dict).
  std::map<std::string, chatter::SolverValues> values;
  for (const std::string& name : q.methods) {
    const chatter::SolverDescriptor& d = chatter::find_lobe_method(name);
    std::optional<py::dict> own;
    if (options) {
      own = py::dict();
      for (auto item : *options)
        for (const auto& o : d.options)
          if (o.name == py::str(item.first).cast<std::string>()) (*own)[item.first] = item.second;
    }
    values[name] = solver_values(cfg, d, d.name, own);
  }
  q.options = [values](const chatter::SolverDescriptor& d) { return values.at(d.name); };
  q.speeds_rpm = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  q.depth_max_mm = depth_max(cfg, depth_max_mm);
  q.threads = thread_count(threads);
  q.style = chatter::ArgStyle::kKeyword;
  chatter::Comparison c;
  {
    py::gil_scoped_release release;
    c = chatter::compare_methods(cfg, q);
  }
  return to_python(chatter::comparison_columns(c, chatter::record_source(cfg, position_mm)));
}

// ------------------------------------------------------------------ map

// axes="radial-axial": immersion x axial depth at one speed (the CLI's
// map --axes radial-axial, radial_stability_map).

py::dict radial_map(const Job& job, const std::string& floquet, std::optional<double> rpm,
                    std::optional<double> immersion_min, std::optional<double> immersion_max,
                    std::optional<int> immersion_points, std::optional<double> depth_max_mm, int depth_points,
                    bool multiplier_types, int threads, const std::optional<py::dict>& options,
                    std::optional<double> position_mm) {
  const chatter::Config& cfg = *job.cfg;
  if (!rpm) throw InputError("rpm: required with axes=\"radial-axial\" (the one spindle speed of the map, rev/min)");
  chatter::check_spindle_rpm(*rpm, "rpm");
  if (!cfg.process.rotating_edges())
    throw InputError("axes=\"radial-axial\": a turning process has no radial immersion (use axes=\"speed-axial\")");
  const double dmax = depth_max(cfg, depth_max_mm);
  const std::vector<double> immersions =
      chatter::map_immersions(immersion_min.value_or(0.05), immersion_max.value_or(1.0), immersion_points.value_or(20),
                              static_cast<std::size_t>(std::max(depth_points, 0)), chatter::ArgStyle::kKeyword);
  const std::vector<double> depths = chatter::map_depths_m(dmax, depth_points, immersions.size(), chatter::ArgStyle::kKeyword);
  const unsigned nthreads = thread_count(threads);
  const std::shared_ptr<const Built> built = build_solver(job, floquet, dmax * 1e-3, options);
  const chatter::ProcessSolverFactory factory = [&](const chatter::Process& p) {
    return built->recipe.build(cfg.model, p, dmax * 1e-3);
  };
  chatter::RadialStabilityMapGrid grid;
  {
    py::gil_scoped_release release;
    grid = chatter::radial_stability_map(cfg.process, *rpm, immersions, depths, factory, multiplier_types, nthreads);
  }
  chatter::RecordSource source = chatter::record_source(cfg, position_mm);
  source.notes = built->notes;
  return to_python(chatter::radial_map_columns(grid, built->descriptor->effective_options(*built->solver), source,
                                               multiplier_types));
}

py::dict stability_map(const Job& job_in, const std::string& method, const std::string& axes_text,
                       std::optional<double> rpm, std::optional<double> immersion_min,
                       std::optional<double> immersion_max, std::optional<int> immersion_points,
                       std::optional<double> rpm_min, std::optional<double> rpm_max, std::optional<int> rpm_points,
                       std::optional<double> depth_max_mm, int depth_points, bool multiplier_types, int threads,
                       const std::optional<py::dict>& options, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  const std::string floquet = chatter::map_method(method, chatter::ArgStyle::kKeyword);
  const chatter::MapAxes axes = chatter::parse_map_axes(axes_text, chatter::ArgStyle::kKeyword);
  if (axes == chatter::MapAxes::kRadialAxial) {
    for (const auto& [given, name] : {std::pair{rpm_min.has_value(), "rpm_min"}, std::pair{rpm_max.has_value(), "rpm_max"},
                                      std::pair{rpm_points.has_value(), "rpm_points"}})
      if (given)
        throw InputError(std::string(name) + ": only with axes=\"speed-axial\" (the radial-axial map is at one speed: rpm)");
    return radial_map(job, floquet, rpm, immersion_min, immersion_max, immersion_points, depth_max_mm, depth_points,
                      multiplier_types, threads, options, position_mm);
  }
  for (const auto& [given, name] :
       {std::pair{rpm.has_value(), "rpm"}, std::pair{immersion_min.has_value(), "immersion_min"},
        std::pair{immersion_max.has_value(), "immersion_max"}, std::pair{immersion_points.has_value(), "immersion_points"}})
    if (given)
      throw InputError(std::string(name) + ": only with axes=\"radial-axial\" (the speed x depth map takes rpm_min, "
                       "rpm_max, rpm_points)");
  const std::vector<double> speeds = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  const double dmax = depth_max(cfg, depth_max_mm);
  const std::vector<double> depths = chatter::map_depths_m(dmax, depth_points, speeds.size(), chatter::ArgStyle::kKeyword);
  const unsigned nthreads = thread_count(threads);
  const std::shared_ptr<const Built> built = build_solver(job, floquet, dmax * 1e-3, options);
  const auto* sdm = dynamic_cast<const chatter::SemiDiscretizationSolver*>(built->solver.get());
  if (!sdm) throw InputError("method " + floquet + ": this method draws no spectral-radius map");
  chatter::StabilityMapGrid grid;
  {
    py::gil_scoped_release release;
    grid = chatter::stability_map(*sdm, speeds, depths, multiplier_types, nthreads);
  }
  chatter::RecordSource source = chatter::record_source(cfg, position_mm);
  source.notes = built->notes;
  return to_python(chatter::stability_map_columns(grid, built->descriptor->effective_options(*built->solver), source,
                                                  multiplier_types));
}

// ------------------------------------------------------------------ frf

py::dict frf(const Job& job_in, std::optional<double> fmin, std::optional<double> fmax, int points, bool log,
             std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  const chatter::FrfGrid grid = chatter::frf_grid(cfg.model, fmin, fmax, points, log, chatter::ArgStyle::kKeyword);
  chatter::NamedColumns t;
  {
    py::gil_scoped_release release;
    t = chatter::receptance_table(cfg.model, grid);
  }
  return to_python(chatter::receptance_columns(t, chatter::record_source(cfg, position_mm)));
}

}  // namespace

void bind_tables(py::module_& m) {
  m.def("compare", &compare, "job"_a, "methods"_a = py::none(), py::kw_only(), "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "rpm_points"_a = py::none(), "depth_max_mm"_a = py::none(), "threads"_a = 0,
        "options"_a = py::none(), "position_mm"_a = py::none(),
        "Every method at the same speeds and how far they differ (chatter compare): the record and the table.");
  m.def("map", &stability_map, "job"_a, "method"_a = "auto", py::kw_only(), "axes"_a = "speed-axial",
        "rpm"_a = py::none(), "immersion_min"_a = py::none(), "immersion_max"_a = py::none(),
        "immersion_points"_a = py::none(), "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "rpm_points"_a = py::none(), "depth_max_mm"_a = py::none(),
        "depth_points"_a = 100, "multiplier_types"_a = false, "threads"_a = 0, "options"_a = py::none(),
        "position_mm"_a = py::none(),
        "The Floquet spectral radius over speed x depth, or (axes=\"radial-axial\") over radial immersion x "
        "axial depth at one speed with the depth limit at each immersion (chatter map): the record and the grid.");
  m.def("frf", &frf, "job"_a, py::kw_only(), "fmin"_a = py::none(), "fmax"_a = py::none(), "points"_a = 1000,
        "log"_a = false, "position_mm"_a = py::none(),
        "The receptance of tool, workpiece and their relative motion (chatter frf's table).");
}

}  // namespace chatter_py
