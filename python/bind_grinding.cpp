// The grinding functions of the Python module `chatter` (docs/python.md,
// docs/grinding.md): the records of `chatter grind predict --json` and
// `chatter grind fit --json`, key for key (the io layer writes them once;
// here they become dicts). Errors as the rest of the module: InputError ->
// chatter.InputError with the library's message. The work runs with the GIL
// released.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/grinding_data.hpp"
#include "chatter/grinding_dynamics.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/records/grinding.hpp"
#include "module.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace {

std::string fspath(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}


chatter::GrindingConfig load(const std::string& path, bool strict) {
  chatter::GrindingConfig c = chatter::load_grinding_config(path);
  if (strict && !c.warnings.empty()) {
    std::string message;
    for (const std::string& w : c.warnings) message += (message.empty() ? "" : "\n") + w + " (strict)";
    throw chatter::InputError(message);
  }
  return c;
}

py::object grind_predict(const py::object& config, std::optional<double> power_w, std::optional<double> target_depth_mm,
                         std::optional<double> target_removal_mm3_per_s, std::optional<double> current_a, bool strict) {
  const int given =
      (power_w ? 1 : 0) + (target_depth_mm ? 1 : 0) + (target_removal_mm3_per_s ? 1 : 0) + (current_a ? 1 : 0);
  if (given != 1)
    throw chatter::InputError("give exactly one of power_w, target_depth_mm, target_removal_mm3_per_s, current_a (" +
                              std::to_string(given) + " given)");
  const std::string path = fspath(config);
  nlohmann::json json;
  {
    py::gil_scoped_release release;
    const chatter::GrindingConfig c = load(path, strict);
    chatter::grinding::Prediction p;
    if (power_w) p = chatter::grinding::predict_at_power(c.process, *power_w);
    else if (current_a) p = chatter::grinding::predict_at_current(c.process, *current_a);
    else if (target_depth_mm) p = chatter::grinding::predict_for_depth(c.process, *target_depth_mm * 1e-3);
    else p = chatter::grinding::predict_for_removal(c.process, *target_removal_mm3_per_s * 1e-9);
    json = chatter::grinding_prediction_record(p, c);
  }
  return chatter_py::to_python(json);
}

py::object grind_fit(const py::object& tests, const std::string& model, const std::string& variable,
                     std::optional<double> force_ratio, const py::dict& defaults) {
  chatter::GrindingTestDefaults d;
  for (auto item : defaults) {
    const std::string key = py::str(item.first).cast<std::string>();
    const double v = item.second.cast<double>();
    if (!(v > 0.0)) throw chatter::InputError("defaults: " + key + " = " + py::repr(item.second).cast<std::string>() + ": must be > 0");
    if (key == "wheel_diameter_mm") d.wheel_diameter_mm = v;
    else if (key == "wheel_width_mm") d.wheel_width_mm = v;
    else if (key == "wheel_rpm") d.wheel_rpm = v;
    else if (key == "feed_mm_per_s") d.feed_mm_per_s = v;
    else if (key == "impacts_per_turn") d.impacts_per_turn = v;
    else
      throw chatter::InputError("defaults: '" + key + "': not a test column with a default (wheel_diameter_mm, "
                                "wheel_width_mm, wheel_rpm, feed_mm_per_s, impacts_per_turn)");
  }
  if (force_ratio && !(*force_ratio > 0.0 && *force_ratio <= 10.0))
    throw chatter::InputError("force_ratio: must be in (0, 10]");
  const std::string path = fspath(tests);
  nlohmann::json json;
  {
    py::gil_scoped_release release;
    const chatter::GrindingFitReport r =
        chatter::fit_grinding_tests(chatter::read_grinding_tests(path, d), model, variable, path);
    std::optional<std::string> fragment;
    try {
      fragment = chatter::grinding_fit_fragment(r, force_ratio);
    } catch (const chatter::InputError&) {
      // Not every fit makes a [grinding] table (no wheel, no force ratio): None.
    }
    json = chatter::grinding_fit_record(r, fragment);
  }
  return chatter_py::to_python(json);
}

void positive(std::optional<double> x, const char* name, const char* unit) {
  if (x && !(std::isfinite(*x) && *x > 0.0))
    throw chatter::InputError(std::string(name) + " = " + chatter_py::fmt(*x) + ": must be > 0" + (*unit ? " " : "") +
                              unit);
}

// A library message prefixed as the CLI's with_flag does ("sweep: ...").
template <class F>
auto prefixed(const char* what, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const chatter::InputError& e) {
    throw chatter::InputError(std::string(what) + ": " + e.what());
  }
}

py::object grind_sweep(const py::object& config, double power_w_min, double power_w_max, int points,
                       const std::optional<std::vector<double>>& feed_mm_per_s_list, bool strict) {
  const std::string path = fspath(config);
  chatter::ColumnRecord table;
  {
    py::gil_scoped_release release;
    const chatter::GrindingConfig c = load(path, strict);
    std::vector<double> feeds;
    if (feed_mm_per_s_list)
      for (double f : *feed_mm_per_s_list) feeds.push_back(f * 1e-3);
    const auto curves = prefixed(
        "sweep", [&] { return chatter::grinding::sweep_power(c.process, power_w_min, power_w_max, points, feeds); });
    table = chatter::grinding_sweep_columns(curves);
  }
  return chatter_py::to_python(table);
}

py::object grind_plan(const py::object& config, std::optional<double> power_w, std::optional<double> current_a,
                      std::optional<double> volume_mm3, std::optional<double> area_mm2, std::optional<double> depth_mm,
                      std::optional<double> g_ratio, double wheel_change_min, std::optional<std::string> objective,
                      std::optional<double> wheel_rpm_min, std::optional<double> wheel_rpm_max, int speed_points,
                      bool strict) {
  const bool by_volume = volume_mm3.has_value(), by_area = area_mm2 || depth_mm;
  if (by_volume == by_area)
    throw chatter::InputError("give volume_mm3, or area_mm2 with depth_mm (one way, not both)");
  if (power_w.has_value() == current_a.has_value()) throw chatter::InputError("give power_w or current_a (one of them)");
  positive(volume_mm3, "volume_mm3", "mm^3");
  positive(area_mm2, "area_mm2", "mm^2");
  positive(depth_mm, "depth_mm", "mm");
  positive(g_ratio, "g_ratio", "");
  positive(power_w, "power_w", "W");
  positive(current_a, "current_a", "A");
  if (by_area && !(area_mm2 && depth_mm))
    throw chatter::InputError("area_mm2 and depth_mm go together (the volume is their product)");
  chatter::grinding::PlanOptions o;
  o.power_w = power_w.value_or(0.0);
  o.current_a = current_a;
  o.g_ratio = g_ratio.value_or(0.0);
  o.volume_m3 = by_volume ? *volume_mm3 * 1e-9 : *area_mm2 * *depth_mm * 1e-9;
  o.wheel_change_s = wheel_change_min * 60.0;
  if (objective) {
    o.objective = chatter::grinding::plan_objective_from_name(*objective, "objective");
    if (!wheel_rpm_min || !wheel_rpm_max)
      throw chatter::InputError("objective searches the wheel speed: give wheel_rpm_min and wheel_rpm_max");
    o.wheel_rpm_min = *wheel_rpm_min;
    o.wheel_rpm_max = *wheel_rpm_max;
    o.speed_points = speed_points;
  } else if (wheel_rpm_min || wheel_rpm_max) {
    throw chatter::InputError("wheel_rpm_min/wheel_rpm_max go with objective (without it the config's wheel speed is used)");
  }
  const std::string path = fspath(config);
  chatter::ColumnRecord result;
  {
    py::gil_scoped_release release;
    const chatter::GrindingConfig c = load(path, strict);
    result = chatter::grinding_plan_columns(prefixed("plan", [&] { return chatter::run_grinding_plan(c, o); }));
  }
  return chatter_py::to_python(result);
}

py::object grind_impacts(const py::object& record_file, double wheel_rpm, std::optional<double> threshold_n,
                         std::optional<double> threshold_rpm) {
  positive(wheel_rpm, "wheel_rpm", "rev/min");
  positive(threshold_n, "threshold_n", "N");
  positive(threshold_rpm, "threshold_rpm", "rev/min");
  const std::string path = fspath(record_file);
  chatter::ColumnRecord result;
  {
    py::gil_scoped_release release;
    const chatter::ImpactRecord rec = chatter::read_impact_record(path);
    const bool force = rec.kind == chatter::grinding::ImpactSignal::kNormalForce;
    if (force ? threshold_rpm.has_value() : threshold_n.has_value())
      throw chatter::InputError(std::string(force ? "threshold_rpm" : "threshold_n") + ": " + path + " is a " +
                                (force ? "force" : "wheel-speed") + " record: use " +
                                (force ? "threshold_n" : "threshold_rpm"));
    chatter::grinding::ImpactCountOptions o;
    o.wheel_rpm = wheel_rpm;
    if (force && threshold_n) o.threshold = *threshold_n;
    if (!force && threshold_rpm) o.threshold = *threshold_rpm;
    chatter::grinding::ImpactCount c = prefixed(path.c_str(), [&] {
      return chatter::grinding::count_impacts(rec.time_s, rec.signal, rec.kind, o);
    });
    result = chatter::grinding_impacts_columns(c, rec, path, wheel_rpm);
  }
  return chatter_py::to_python(result);
}

py::object grind_simulate(const py::object& config, double power_w, int turns, int points_per_turn,
                          double power_loop_turns, int series_turns, bool strict) {
  chatter::grinding::DynamicsOptions o;
  o.turns = turns;
  o.points_per_turn = points_per_turn;
  o.power_loop_turns = power_loop_turns;
  o.series_turns = series_turns;
  const std::string path = fspath(config);
  chatter::ColumnRecord result;
  {
    py::gil_scoped_release release;
    const chatter::GrindingConfig c = load(path, strict);
    chatter::grinding::DynamicsResult r;
    try {
      r = chatter::grinding::simulate_grinding(c.process, c.robot, power_w, o);
    } catch (const chatter::InputError& e) {
      throw chatter::InputError(c.source.string() + ": " + e.what());
    }
    result = chatter::grinding_simulation_columns(r, c);
  }
  return chatter_py::to_python(result);
}

}  // namespace

void bind_grinding(py::module_& m) {
  m.def("grind_predict", &grind_predict, "config"_a, py::kw_only(), "power_w"_a = py::none(),
        "target_depth_mm"_a = py::none(), "target_removal_mm3_per_s"_a = py::none(), "current_a"_a = py::none(),
        "strict"_a = false,
        "Grinding at controlled power (a [grinding] config): the record of `chatter grind predict --json`.");
  m.def("grind_fit", &grind_fit, "tests"_a, py::kw_only(), "model"_a, "variable"_a = "",
        "force_ratio"_a = py::none(), "defaults"_a = py::dict(),
        "Grinding model coefficients from a tests table: the record of `chatter grind fit --json`, plus "
        "'fragment', the [grinding] table of --out (None when the tests do not give one).");
  const chatter::grinding::DynamicsOptions dyn;
  m.def("grind_sweep", &grind_sweep, "config"_a, py::kw_only(), "power_w_min"_a, "power_w_max"_a, "points"_a = 46,
        "feed_mm_per_s_list"_a = py::none(), "strict"_a = false,
        "Depth, removal and force against power (chatter grind sweep's table, columns as NumPy arrays).");
  m.def("grind_plan", &grind_plan, "config"_a, py::kw_only(), "power_w"_a = py::none(), "current_a"_a = py::none(),
        "volume_mm3"_a = py::none(), "area_mm2"_a = py::none(), "depth_mm"_a = py::none(), "g_ratio"_a = py::none(),
        "wheel_change_min"_a = 0.0, "objective"_a = py::none(), "wheel_rpm_min"_a = py::none(),
        "wheel_rpm_max"_a = py::none(), "speed_points"_a = 200, "strict"_a = false,
        "Wheels, grinding time and wheel changes for a repair: the record of chatter grind plan --json, plus "
        "'wheel_life' (its --table as arrays).");
  m.def("grind_impacts", &grind_impacts, "record"_a, py::kw_only(), "wheel_rpm"_a, "threshold_n"_a = py::none(),
        "threshold_rpm"_a = py::none(),
        "Impacts per wheel turn in a force or wheel-speed record: the record of chatter grind impacts --json, plus "
        "'turns_table' (its --table as arrays).");
  m.def("grind_simulate", &grind_simulate, "config"_a, py::kw_only(), "power_w"_a, "turns"_a = dyn.turns,
        "points_per_turn"_a = dyn.points_per_turn, "power_loop_turns"_a = dyn.power_loop_turns,
        "series_turns"_a = dyn.series_turns, "strict"_a = false,
        "The robot pressed against the part by its power loop: the record of chatter grind simulate --json, plus "
        "'series' (the last turns, as --series).");
}
