// chatter.coefficients, chatter.detect, chatter.fit: the shop measurements
// (cutting tests, a recording of the cut, a tap test) through the same
// library functions as the CLI (chatter/records/shop.hpp): the record as a
// dict, plus the arrays a plot needs (docs/python.md, docs/shop_data.md,
// docs/frf.md).
#include <cmath>
#include <complex>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/records/shop.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

std::string fspath(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

// ------------------------------------------------------------------ coefficients

// Kienzle's law from turning tests (a table with feed_mm_per_rev), as the CLI.
py::dict kienzle(const std::string& path, std::optional<double> lead_angle_deg) {
  chatter::KienzleResult r;
  {
    py::gil_scoped_release release;
    r = chatter::fit_kienzle_tests(path, lead_angle_deg.value_or(90.0), chatter::ArgStyle::kKeyword);
  }
  return to_python(chatter::kienzle_record_with_fragment(r, chatter::ArgStyle::kKeyword));
}

py::dict coefficients(const py::object& tests, std::optional<int> teeth, std::optional<double> radial_immersion,
                      std::optional<std::string> milling_direction, std::optional<double> diameter_mm,
                      std::optional<double> lead_angle_deg) {
  const std::string path = fspath(tests);
  if (chatter::is_turning_tests_table(path)) {
    for (const auto& [given, name] : {std::pair{teeth.has_value(), "teeth"}, {radial_immersion.has_value(), "radial_immersion"},
                                      {milling_direction.has_value(), "milling_direction"}, {diameter_mm.has_value(), "diameter_mm"}})
      if (given)
        throw InputError(std::string(name) + ": for milling tests; " + path +
                         " holds turning tests (feed_mm_per_rev): Kienzle's law takes lead_angle_deg only");
    return kienzle(path, lead_angle_deg);
  }
  if (lead_angle_deg)
    throw InputError("lead_angle_deg: for turning tests (a table with feed_mm_per_rev); " + path + " holds milling tests");
  for (const auto& [given, name] : {std::pair{teeth.has_value(), "teeth"}, {radial_immersion.has_value(), "radial_immersion"},
                                    {milling_direction.has_value(), "milling_direction"}})
    if (!given) throw InputError(std::string(name) + ": required for milling tests (a turning table names feed_mm_per_rev)");
  chatter::CoefficientArgs a;
  a.tests = path;
  a.teeth = *teeth;
  a.radial_immersion = *radial_immersion;
  a.milling_direction = *milling_direction;
  a.diameter_mm = diameter_mm;
  chatter::CoefficientResult r;
  {
    py::gil_scoped_release release;
    r = chatter::fit_cutting_coefficients(a, chatter::ArgStyle::kKeyword);
  }
  return to_python(chatter::coefficients_record_with_fragment(r, chatter::ArgStyle::kKeyword));
}

// ------------------------------------------------------------------ detect

py::dict detect(const py::object& recording, double rpm, int teeth, std::optional<double> rpm_min,
                std::optional<double> rpm_max, int channel, double peak_ratio, const py::object& config,
                std::optional<double> depth_mm, bool force) {
  chatter::DetectArgs a;
  a.recording = fspath(recording);
  a.rpm = rpm;
  a.teeth = teeth;
  a.rpm_min = rpm_min;
  a.rpm_max = rpm_max;
  a.channel = channel;
  a.peak_ratio = peak_ratio;
  a.depth_mm = depth_mm;
  a.force = force;
  std::shared_ptr<const chatter::Config> cfg;
  if (!config.is_none()) {
    if (py::isinstance<Job>(config)) cfg = config.cast<const Job&>().cfg;
    else cfg = std::make_shared<const chatter::Config>(chatter::load_config(fspath(config)));
    a.config = cfg.get();
  }
  chatter::DetectResult r;
  {
    py::gil_scoped_release release;
    r = chatter::detect_recording(a, chatter::ArgStyle::kKeyword);
  }
  return to_python(chatter::detect_columns(r));
}

// ------------------------------------------------------------------ fit

py::dict fit(const py::object& file, const std::string& format, const std::string& quantity, double scale,
             const std::string& term, std::optional<int> record, std::optional<int> modes, bool residuals,
             const std::optional<std::pair<double, double>>& band, const std::string& body,
             const std::string& direction) {
  chatter::FitArgs a;
  a.file = fspath(file);
  a.format = format;
  a.quantity = quantity;
  a.scale = scale;
  a.term = term;
  a.record = record;
  a.modes = modes;
  a.residuals = residuals;
  a.band = band;
  a.body = body;
  a.direction = direction;
  chatter::FitReport r;
  {
    py::gil_scoped_release release;
    r = chatter::fit_frf_file(a, chatter::ArgStyle::kKeyword);
  }
  return to_python(chatter::fit_columns(r));
}

}  // namespace

void bind_shop(py::module_& m) {
  m.def("coefficients", &coefficients, "tests"_a, py::kw_only(), "teeth"_a = py::none(),
        "radial_immersion"_a = py::none(), "milling_direction"_a = py::none(), "diameter_mm"_a = py::none(),
        "lead_angle_deg"_a = py::none(),
        "Cutting coefficients from test cuts (chatter coefficients --json), plus 'fragment': the [process] table "
        "of --out, or None. Milling tests need teeth, radial_immersion and milling_direction; turning tests (a "
        "table with feed_mm_per_rev) give Kienzle's law (k_1.1 and m per direction) and take lead_angle_deg.");
  m.def("detect", &detect, "recording"_a, py::kw_only(), "rpm"_a, "teeth"_a, "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "channel"_a = 1, "peak_ratio"_a = 0.25, "config"_a = py::none(),
        "depth_mm"_a = py::none(), "force"_a = false,
        "Chatter in a recording of the cut and the spindle speeds to try (chatter detect --json), plus the "
        "spectrum.");
  m.def("fit", &fit, "frf_file"_a, py::kw_only(), "format"_a = "", "quantity"_a = "", "scale"_a = 1.0, "term"_a = "",
        "record"_a = py::none(), "modes"_a = py::none(), "residuals"_a = false, "band"_a = py::none(),
        "body"_a = "tool", "direction"_a = "",
        "Modes fitted to a measured FRF (chatter fit): the record with 'fragment' (the [[<body>.modes]] TOML of "
        "--out), and per record the measured and fitted receptance.");
}

}  // namespace chatter_py
