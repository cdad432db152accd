// chatter.design_pitch: chatter design-pitch --json's record
// (chatter/records/pitch.hpp) as a dict (docs/python.md, docs/design_pitch.md),
// with the CLI's checks and defaults (chatter::pitch_design_options) naming
// the keywords.
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/records/pitch.hpp"
#include "chatter/solvers.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

py::dict design_pitch(const Job& job, std::optional<double> rpm_min, std::optional<double> rpm_max,
                      std::optional<int> teeth, int rpm_points, std::optional<double> depth_max_mm,
                      const std::string& family, double min_pitch_ratio, int scan_points, const std::string& method,
                      const std::optional<py::dict>& options, int threads) {
  const chatter::Config& cfg = *job.cfg;
  chatter::PitchDesignArgs a;
  a.rpm_min = rpm_min;
  a.rpm_max = rpm_max;
  a.teeth = teeth;
  a.rpm_points = rpm_points;
  a.depth_max_mm = depth_max_mm;
  a.family = family;
  a.min_pitch_ratio = min_pitch_ratio;
  a.scan_points = scan_points;
  a.method = method;
  a.threads = thread_count(threads);
  chatter::PitchDesignOptions o = chatter::pitch_design_options(cfg, a, chatter::ArgStyle::kKeyword);
  o.solver_options = solver_values(cfg, chatter::find_lobe_method(o.method), o.method, options);
  chatter::PitchDesign d;
  {
    py::gil_scoped_release release;
    d = chatter::run_pitch_design(cfg, o, chatter::ArgStyle::kKeyword);
  }
  return to_python(chatter::pitch_design_record(d, o, chatter::record_source(cfg)));
}

}  // namespace

void bind_pitch(py::module_& m) {
  m.def("design_pitch", &design_pitch, "job"_a, py::kw_only(), "rpm_min"_a = py::none(), "rpm_max"_a = py::none(),
        "teeth"_a = py::none(), "rpm_points"_a = chatter::kDefaultPitchBandPoints, "depth_max_mm"_a = py::none(),
        "family"_a = "linear", "min_pitch_ratio"_a = chatter::kDefaultMinPitchRatio,
        "scan_points"_a = chatter::kDefaultPitchScanPoints, "method"_a = "sdm", "options"_a = py::none(),
        "threads"_a = 0,
        "Variable-pitch angles that maximise the worst stability limit over [rpm_min, rpm_max]: the record of "
        "chatter design-pitch --json (docs/design_pitch.md).");
}

}  // namespace chatter_py
