// chatter.performance, chatter.optimize, chatter.adapt and chatter.adapt_step
// (docs/python.md, docs/optimization.md): the records of `chatter performance
// --json`, `optimize --json` and `adapt --json` (chatter/records.hpp) as
// dicts, and the one step of the adaptive loop a controller calls with its
// measurement; its `state` goes back into the next call.
#include <cmath>
#include <optional>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/optimization_files.hpp"
#include "chatter/optimization.hpp"
#include "chatter/records.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

// The config's [optimization] with the call's overrides, on its structure.
struct Problem {
  Job job;
  std::optional<chatter::OptimizationModel> model;
  chatter::RecordSource source;
};

std::optional<chatter::Bounds> depth_bounds(const py::object& depth_mm) {
  if (depth_mm.is_none()) return std::nullopt;
  std::vector<double> v;
  if (py::isinstance<py::float_>(depth_mm) || py::isinstance<py::int_>(depth_mm)) v.push_back(depth_mm.cast<double>());
  else v = depth_mm.cast<std::vector<double>>();
  if (v.empty() || v.size() > 2 || !(v.front() > 0.0) || !(v.back() >= v.front()) || !std::isfinite(v.back()))
    throw InputError("depth_mm: must be a depth > 0 (fixed) or (lower, upper) with 0 < lower <= upper, mm");
  return chatter::Bounds{v.front() * 1e-3, v.back() * 1e-3};
}

std::unique_ptr<Problem> problem(const Job& job, const std::string& method, std::optional<double> position_mm,
                                 bool stability, const py::object& depth_mm, int threads) {
  auto p = std::make_unique<Problem>();
  p->job = job;
  const chatter::Config& cfg = *job.cfg;
  if (!cfg.optimization)
    throw InputError(cfg.source.string() + ": no [optimization] table (docs/config.md, \"Optimization\")");
  chatter::OptimizationSpec spec = *cfg.optimization;
  if (!stability) spec.constraints.stability = false;
  if (const auto d = depth_bounds(depth_mm)) spec.depth_m = *d;
  chatter::ModelOptions o;
  o.method = method;
  o.threads = thread_count(threads);
  if (position_mm) o.position_m = chatter::position_m(cfg, *position_mm, "position_mm");
  try {
    p->model.emplace(cfg.model, cfg.position, cfg.process, spec, o);
  } catch (const InputError& e) {
    throw InputError(std::string("method: ") + e.what());
  }
  p->source = chatter::record_source(cfg, position_mm);
  return p;
}

// {name: value} of measured indices.
chatter::IndexValues indices_of(const std::optional<py::dict>& d, chatter::Operation op, const char* arg) {
  chatter::IndexValues v = chatter::unknown_indices();
  if (!d) return v;
  for (auto kv : *d) {
    const std::string name = py::str(kv.first).cast<std::string>();
    const auto i = chatter::index_from_name(name, op);
    if (!i) throw InputError(std::string(arg) + ": '" + name + "': unknown index (" + chatter::index_names(op) + ")");
    if (kv.second.is_none()) continue;
    const double x = kv.second.cast<double>();
    if (!(std::isfinite(x) && x > 0.0)) throw InputError(std::string(arg) + "['" + name + "'] = " + fmt(x) + ": must be > 0");
    v[static_cast<std::size_t>(*i)] = x;
  }
  return v;
}

double positive(const py::handle& x, const std::string& name) {
  const double v = x.cast<double>();
  if (!(std::isfinite(v) && v > 0.0)) throw InputError(name + " = " + fmt(v) + ": must be > 0");
  return v;
}

std::string feed_key(const chatter::OptimizationModel& m) { return std::string(m.process().feed_record_key()); }

// A set-point from a dict with spindle_rpm or cutting_speed_m_per_min, the
// feed and depth_mm (the keys of every optimisation record).
chatter::SetPoint set_point_of(const py::dict& d, const chatter::OptimizationModel& m, const std::string& arg) {
  chatter::SetPoint p;
  if (d.contains("spindle_rpm")) p.spindle_rpm = positive(d["spindle_rpm"], arg + "['spindle_rpm']");
  else if (d.contains("cutting_speed_m_per_min"))
    p.spindle_rpm = chatter::spindle_rpm_of(m.spec().diameter_m,
                                            positive(d["cutting_speed_m_per_min"], arg + "['cutting_speed_m_per_min']"));
  else throw InputError(arg + ": needs 'spindle_rpm' or 'cutting_speed_m_per_min'");
  const std::string fk = feed_key(m);
  if (!d.contains(fk.c_str())) throw InputError(arg + ": needs '" + fk + "'");
  p.feed_m = positive(d[fk.c_str()], arg + "['" + fk + "']") * 1e-3;
  if (!d.contains("depth_mm")) throw InputError(arg + ": needs 'depth_mm'");
  p.depth_m = positive(d["depth_mm"], arg + "['depth_mm']") * 1e-3;
  return p;
}

chatter::AdaptSettings settings_of(const chatter::OptimizationModel& m, std::optional<double> gamma,
                                   std::optional<double> max_step_pct) {
  chatter::AdaptSettings s = m.spec().adapt;
  if (gamma) s.gamma = *gamma;
  if (max_step_pct) s.max_step = *max_step_pct / 100.0;
  if (!(s.gamma > 0.0 && s.gamma <= 1.0)) throw InputError("gamma = " + fmt(s.gamma) + ": must be in (0, 1]");
  if (!(s.max_step > 0.0 && s.max_step <= 1.0))
    throw InputError("max_step_pct = " + fmt(s.max_step * 100.0) + ": must be in (0, 100]");
  return s;
}

py::dict performance(const Job& job, std::optional<double> cutting_speed, std::optional<double> rpm,
                     std::optional<double> feed_mm_per_rev, std::optional<double> feed_per_tooth_mm, double depth_mm,
                     const std::optional<py::dict>& index, const std::string& method, std::optional<double> position_mm,
                     bool stability, int threads) {
  const auto p = problem(job, method, position_mm, stability, py::none(), threads);
  const chatter::OptimizationModel& m = *p->model;
  if (cutting_speed.has_value() == rpm.has_value())
    throw InputError("give the speed as cutting_speed_m_per_min or rpm (one of them)");
  const auto feed = m.milling() ? feed_per_tooth_mm : feed_mm_per_rev;
  if ((m.milling() ? feed_mm_per_rev : feed_per_tooth_mm).has_value() || !feed)
    throw InputError(std::string(m.milling() ? "milling: give feed_per_tooth_mm" : "turning: give feed_mm_per_rev"));
  chatter::SetPoint s;
  s.spindle_rpm = rpm ? positive(py::float_(*rpm), "rpm")
                      : chatter::spindle_rpm_of(m.spec().diameter_m, positive(py::float_(*cutting_speed),
                                                                              "cutting_speed_m_per_min"));
  s.feed_m = positive(py::float_(*feed), feed_key(m)) * 1e-3;
  s.depth_m = positive(py::float_(depth_mm), "depth_mm") * 1e-3;
  const chatter::IndexValues measured = indices_of(index, m.operation(), "index");
  chatter::Performance r;
  {
    py::gil_scoped_release release;
    r = m.evaluate(s, chatter::no_corrections(), measured);
  }
  return to_python(chatter::performance_record(r, m, p->source));
}

py::dict optimize(const Job& job, const py::object& depth_mm, const std::string& method,
                  std::optional<double> position_mm, bool stability, int threads) {
  const auto p = problem(job, method, position_mm, stability, depth_mm, threads);
  chatter::Optimum o;
  {
    py::gil_scoped_release release;
    o = chatter::optimize(*p->model);
  }
  return to_python(chatter::optimize_record(o, *p->model, p->source));
}

py::dict adapt(const Job& job, int iterations, std::optional<double> gamma, std::optional<double> max_step_pct,
               const std::optional<py::dict>& start, const std::optional<std::vector<std::string>>& bias,
               const py::object& measurements, const py::object& depth_mm, const std::string& method,
               std::optional<double> position_mm, bool stability, int threads) {
  const auto p = problem(job, method, position_mm, stability, depth_mm, threads);
  const chatter::OptimizationModel& m = *p->model;
  const chatter::AdaptSettings settings = settings_of(m, gamma, max_step_pct);
  chatter::AdaptPlan plan;
  plan.iterations = iterations;
  if (start) plan.start = set_point_of(*start, m, "start");
  if (bias)
    for (const std::string& b : *bias) {
      try {
        plan.biases.push_back(chatter::parse_plant_bias(b, m.operation()));
      } catch (const InputError& e) {
        throw InputError(std::string("bias: ") + e.what());
      }
    }
  std::string origin;
  if (!measurements.is_none()) {
    if (py::isinstance<py::str>(measurements) || py::hasattr(measurements, "__fspath__")) {
      origin = py::str(py::module_::import("os").attr("fspath")(measurements)).cast<std::string>();
      plan.measurements = chatter::read_measurements(origin, m.operation());
    } else {
      origin = "<measurements>";
      std::size_t k = 0;
      for (auto row : measurements.cast<py::list>())
        plan.measurements.push_back(
            indices_of(row.cast<py::dict>(), m.operation(), ("measurements[" + std::to_string(k++) + "]").c_str()));
    }
  }
  chatter::AdaptRun run;
  {
    py::gil_scoped_release release;
    run = chatter::adapt(m, plan, settings);
  }
  const chatter::AdaptRecordInputs in{&plan, &settings, origin};
  return to_python(chatter::adapt_record(run, m, in, p->source));
}

py::dict adapt_step(const Job& job, const py::dict& state, const std::optional<py::dict>& measurement,
                    std::optional<double> gamma, std::optional<double> max_step_pct, const py::object& depth_mm,
                    const std::string& method, std::optional<double> position_mm, bool stability, int threads) {
  const auto p = problem(job, method, position_mm, stability, depth_mm, threads);
  const chatter::OptimizationModel& m = *p->model;
  chatter::AdaptState s;
  s.point = set_point_of(state, m, "state");
  if (state.contains("correction") && !state["correction"].is_none()) {
    const chatter::IndexValues c = indices_of(state["correction"].cast<py::dict>(), m.operation(), "state['correction']");
    for (std::size_t i = 0; i < chatter::kIndexCount; ++i)
      if (std::isfinite(c[i])) s.correction[i] = c[i];
  }
  if (state.contains("iteration")) s.iteration = state["iteration"].cast<int>();
  const chatter::IndexValues measured = indices_of(measurement, m.operation(), "measurement");
  const chatter::AdaptSettings settings = settings_of(m, gamma, max_step_pct);
  chatter::AdaptStepResult r;
  {
    py::gil_scoped_release release;
    r = chatter::adapt_step(m, s, measured, settings);
  }
  return to_python(chatter::adapt_step_record(r, m));
}

}  // namespace

void bind_optimization(py::module_& m) {
  m.def("performance", &performance, "job"_a, py::kw_only(), "cutting_speed_m_per_min"_a = py::none(),
        "rpm"_a = py::none(), "feed_mm_per_rev"_a = py::none(), "feed_per_tooth_mm"_a = py::none(), "depth_mm"_a,
        "index"_a = py::none(), "method"_a = "auto", "position_mm"_a = py::none(), "stability"_a = true,
        "threads"_a = 0, "Every index, loss term and constraint of one set-point, as chatter performance --json.");
  m.def("optimize", &optimize, "job"_a, py::kw_only(), "depth_mm"_a = py::none(), "method"_a = "auto",
        "position_mm"_a = py::none(), "stability"_a = true, "threads"_a = 0,
        "The constrained optimum of [optimization], as chatter optimize --json.");
  m.def("adapt", &adapt, "job"_a, "iterations"_a, py::kw_only(), "gamma"_a = py::none(), "max_step_pct"_a = py::none(),
        "start"_a = py::none(), "bias"_a = py::none(), "measurements"_a = py::none(), "depth_mm"_a = py::none(),
        "method"_a = "auto", "position_mm"_a = py::none(), "stability"_a = true, "threads"_a = 0,
        "The adaptive loop against a plant (biases) or measurements, as chatter adapt --json.");
  m.def("adapt_step", &adapt_step, "job"_a, "state"_a, "measurement"_a = py::none(), py::kw_only(),
        "gamma"_a = py::none(), "max_step_pct"_a = py::none(), "depth_mm"_a = py::none(), "method"_a = "auto",
        "position_mm"_a = py::none(), "stability"_a = true, "threads"_a = 0,
        "One step of the adaptive loop: the measurement at state's set-point in, the next state out "
        "(its 'state' goes into the next call).");
}

}  // namespace chatter_py
