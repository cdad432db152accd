// chatter.simulate: chatter simulate's record (chatter/records.hpp) as a
// dict, plus the series, once-per-period samples and spectrum as NumPy
// arrays (docs/python.md).
#include <cmath>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/records.hpp"
#include "chatter/report.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/usual_bands.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

// ------------------------------------------------------------------ simulate

py::dict simulate(const Job& job_in, double rpm, double depth_mm, std::optional<double> feed_per_tooth_mm,
                  std::optional<int> revolutions, std::optional<int> periods, bool linear, bool multiple_regeneration,
                  double rtol, bool record_series, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  const double feed_mm = feed_per_tooth_mm.value_or(cfg.feed_mm.value_or(kDefaultFeedMm));
  chatter::check_spindle_rpm(rpm, "rpm");
  chatter::check_depth_mm(depth_mm, "depth_mm", /*allow_zero=*/true);
  if (!(std::isfinite(feed_mm) && feed_mm >= 0.0 && feed_mm <= 100.0))
    throw InputError("feed_per_tooth_mm = " + fmt(feed_mm) + ": must be in [0, 100] mm");
  if (revolutions && periods) throw InputError("revolutions and periods: give one of them");
  int n_periods = chatter::default_simulation_periods(cfg.process, rpm, linear);
  if (revolutions) {
    if (*revolutions < 1 || *revolutions > 1000000)
      throw InputError("revolutions = " + std::to_string(*revolutions) + ": must be in [1, 1000000]");
    n_periods = chatter::simulation_periods_in_revolutions(cfg.process, rpm, linear, *revolutions);
  } else if (periods) {
    n_periods = *periods;
  }
  if (n_periods < 4 || n_periods > 10000000)
    throw InputError("periods = " + std::to_string(n_periods) + ": must be in [4, 10000000]");
  if (!(rtol >= 1e-12 && rtol <= 1e-2)) throw InputError("rtol = " + fmt(rtol) + ": must be in [1e-12, 1e-2]");
  chatter::TimeDomainOptions o;
  o.relative_tolerance = rtol;
  chatter::SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_mm * 1e-3;
  st.periods = n_periods;
  st.feed_m = feed_mm * 1e-3;
  st.linear = linear;
  st.multiple_regeneration = multiple_regeneration;
  st.record_series = record_series;
  chatter::SimulationResult r;
  {
    py::gil_scoped_release release;
    const chatter::TimeDomainSimulator sim(cfg.model, cfg.process, o);
    sim.require_chip(st);  // a cut with no chip is refused, not judged (docs/results.md)
    r = sim.simulate(st);
  }
  // The record of chatter simulate with its series and spectrum (chatter/records.hpp).
  chatter::RecordSource source = chatter::record_source(cfg, position_mm);
  // The keywords given (a feed from the config has had its warning there).
  std::vector<std::pair<std::string, double>> given{{"rpm", rpm}, {"depth_mm", depth_mm}};
  if (feed_per_tooth_mm) given.emplace_back("feed_per_tooth_mm", *feed_per_tooth_mm);
  for (std::string& w : chatter::unusual_arguments(given)) source.warnings.push_back(std::move(w));
  return chatter_py::to_python(chatter::simulation_columns(
      r, chatter::simulation_request(st, cfg.process, rtol, depth_mm, feed_mm), source));
}

}  // namespace

void bind_simulate(py::module_& m) {
  m.def("simulate", &simulate, "job"_a, py::kw_only(), "rpm"_a, "depth_mm"_a, "feed_per_tooth_mm"_a = py::none(),
        "revolutions"_a = py::none(), "periods"_a = py::none(), "linear"_a = false,
        "multiple_regeneration"_a = false, "rtol"_a = kDefaultSimRtol, "record_series"_a = true,
        "position_mm"_a = py::none(),
        "One time-domain simulation (chatter simulate's JSON plus the series arrays).");
}

}  // namespace chatter_py
