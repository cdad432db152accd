// The grinding functions of the Python module `chatter` (docs/python.md,
// docs/grinding.md): the records of `chatter grind predict --json` and
// `chatter grind fit --json`, key for key (the io layer writes them once;
// here they become dicts). Errors as the rest of the module: InputError ->
// chatter.InputError with the library's message. The work runs with the GIL
// released.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "bindings.hpp"
#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/io/grinding_io.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace {

std::string fspath(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

py::object json_loads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

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
                         std::optional<double> target_removal_mm3_per_s, bool strict) {
  const int given = (power_w ? 1 : 0) + (target_depth_mm ? 1 : 0) + (target_removal_mm3_per_s ? 1 : 0);
  if (given != 1)
    throw chatter::InputError("give exactly one of power_w, target_depth_mm, target_removal_mm3_per_s (" +
                              std::to_string(given) + " given)");
  const std::string path = fspath(config);
  std::string json;
  {
    py::gil_scoped_release release;
    const chatter::GrindingConfig c = load(path, strict);
    chatter::grinding::Prediction p;
    if (power_w) p = chatter::grinding::predict_at_power(c.process, *power_w);
    else if (target_depth_mm) p = chatter::grinding::predict_for_depth(c.process, *target_depth_mm * 1e-3);
    else p = chatter::grinding::predict_for_removal(c.process, *target_removal_mm3_per_s * 1e-9);
    json = chatter::grinding_prediction_json(p, c);
  }
  return json_loads(json);
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
  std::string json, fragment;
  bool has_fragment = false;
  {
    py::gil_scoped_release release;
    const chatter::GrindingFitReport r =
        chatter::fit_grinding_tests(chatter::read_grinding_tests(path, d), model, variable, path);
    json = chatter::grinding_fit_json(r);
    try {
      fragment = chatter::grinding_fit_fragment(r, force_ratio);
      has_fragment = true;
    } catch (const chatter::InputError&) {
      // Not every fit makes a [grinding] table (no wheel, no force ratio): None.
    }
  }
  py::object record = json_loads(json);
  record["fragment"] = has_fragment ? py::object(py::str(fragment)) : py::object(py::none());
  return record;
}

}  // namespace

void bind_grinding(py::module_& m) {
  m.def("grind_predict", &grind_predict, "config"_a, py::kw_only(), "power_w"_a = py::none(),
        "target_depth_mm"_a = py::none(), "target_removal_mm3_per_s"_a = py::none(), "strict"_a = false,
        "Grinding at controlled power (a [grinding] config): the record of `chatter grind predict --json`.");
  m.def("grind_fit", &grind_fit, "tests"_a, py::kw_only(), "model"_a, "variable"_a = "",
        "force_ratio"_a = py::none(), "defaults"_a = py::dict(),
        "Grinding model coefficients from a tests table: the record of `chatter grind fit --json`, plus "
        "'fragment', the [grinding] table of --out (None when the tests do not give one).");
}
