// chatter.forced and chatter.sle (docs/python.md, docs/forced.md): the
// forced response of `chatter forced` and the SLE sweep of `chatter sle`,
// through the same library calls. chatter.forced returns the record of
// `chatter forced --json` (chatter/records/forced.hpp, converted by
// to_python) plus the tool path as NumPy arrays; chatter.sle the table's
// columns as NumPy arrays (sle_columns). An unstable cut is not an error here: stable is False and
// the response numbers are None (the CLI exits 3).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/io/config.hpp"
#include "chatter/records/forced.hpp"
#include "chatter/usual_bands.hpp"
#include "module.hpp"
#include "chatter/lobes.hpp"

namespace py = pybind11;
using namespace pybind11::literals;
using chatter::InputError;

namespace {

// As the CLI (src/cli/cmd_forced.cpp, cli_common.hpp); the defaults every
// binding shares and the message number come from module.hpp.
constexpr double kMaxFeedMm = 100.0;
constexpr double kMaxDepthMm = 1000.0;
using chatter_py::fmt;
using chatter_py::kDefaultDepthMaxMm;
using chatter_py::kDefaultRpmPoints;
using chatter_py::kMaxRpmPoints;

// The job's config, at the tool position if one is given, with the radial
// immersion replaced if one is given (keyword names in messages).
chatter::Config job_at(const py::object& job, std::optional<double> position_mm, std::optional<double> immersion) {
  chatter::Config cfg = *job_config(job);
  if (position_mm) cfg = chatter::config_at_position(cfg, *position_mm, "position_mm");
  if (immersion) {
    if (!cfg.process.rotating_edges())
      throw InputError("radial_immersion: " + cfg.name + " is turning (milling only)");
    chatter::MillingParameters mp = cfg.process.milling_parameters();
    mp.radial_immersion = *immersion;
    try {
      cfg.process = chatter::Process::milling(mp);
    } catch (const InputError& e) {
      throw InputError("radial_immersion = " + fmt(*immersion) + ": " + e.what());
    }
  }
  return cfg;
}

double feed_mm_of(const chatter::Config& cfg, std::optional<double> per_tooth, std::optional<double> per_rev) {
  const bool milling = cfg.process.rotating_edges();
  const std::string right(cfg.process.feed_record_key());
  if (milling ? per_rev.has_value() : per_tooth.has_value())
    throw InputError(std::string(milling ? "feed_mm_per_rev" : "feed_per_tooth_mm") + ": " + cfg.name + " is " +
                     (milling ? "milling: give feed_per_tooth_mm" : "turning: give feed_mm_per_rev"));
  const std::optional<double> given = milling ? per_tooth : per_rev;
  if (!given && !cfg.feed_mm)
    throw InputError(std::string("missing ") + right + " (or [process] " +
                     (milling ? "feed_per_tooth_mm" : "feed_per_rev_mm") + " in the config)");
  const double f = given ? *given : *cfg.feed_mm;
  if (!(std::isfinite(f) && f > 0.0 && f <= kMaxFeedMm))
    throw InputError(std::string(right) + " = " + fmt(f) + ": must be in (0, " + fmt(kMaxFeedMm) + "] mm");
  return f;
}

void check_depth(double depth_mm) {
  if (!(std::isfinite(depth_mm) && depth_mm > 0.0 && depth_mm <= kMaxDepthMm))
    throw InputError("depth_mm = " + fmt(depth_mm) + ": must be in (0, " + fmt(kMaxDepthMm) + "] mm");
}

chatter::ForcedOptions options_of(std::optional<int> steps, double depth_max_mm) {
  chatter::ForcedOptions o;
  o.sdm.depth_max_m = depth_max_mm * 1e-3;
  if (steps) {
    if (*steps < 1 || *steps > 100000) throw InputError("steps = " + std::to_string(*steps) + ": must be in [1, 100000]");
    o.sdm.steps_per_period = o.sdm.steps_per_vibration_cycle = *steps;
  }
  return o;
}

py::dict forced(const py::object& job, double rpm, double depth_mm, std::optional<double> feed_per_tooth_mm,
                std::optional<double> feed_mm_per_rev, std::optional<double> radial_immersion,
                std::optional<double> position_mm, std::optional<int> steps, bool record_path) {
  const chatter::Config cfg = job_at(job, position_mm, radial_immersion);
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError("rpm = " + fmt(rpm) + ": must be > 0 rev/min");
  check_depth(depth_mm);
  const double feed_mm = feed_mm_of(cfg, feed_per_tooth_mm, feed_mm_per_rev);
  const double depth_max_mm = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 2.0 * depth_mm);
  chatter::ForcedResponse r;
  chatter::StabilityLimit limit;
  {
    py::gil_scoped_release release;
    const chatter::ForcedResponseSolver solver(cfg.model, cfg.process, options_of(steps, depth_max_mm));
    chatter::ForcedSettings st;
    st.spindle_rpm = rpm;
    st.depth_m = depth_mm * 1e-3;
    st.feed_m = feed_mm * 1e-3;
    st.record_path = record_path;
    r = solver.response(st);
    limit = solver.stability().limit_at(chatter::SpindleSpeed(rpm));
  }
  chatter::ForcedRecordContext ctx;
  ctx.config = cfg.name;
  ctx.warnings = cfg.warnings;
  // The keywords given (a feed from the config has had its warning there).
  std::vector<std::pair<std::string, double>> given{{"rpm", rpm}, {"depth_mm", depth_mm}};
  if (feed_per_tooth_mm) given.emplace_back("feed_per_tooth_mm", *feed_per_tooth_mm);
  if (feed_mm_per_rev) given.emplace_back("feed_mm_per_rev", *feed_mm_per_rev);
  for (std::string& w : chatter::unusual_arguments(given)) ctx.warnings.push_back(std::move(w));
  ctx.position_mm = position_mm;
  if (cfg.process.rotating_edges())
    ctx.radial_immersion = cfg.process.milling_parameters().radial_immersion;
  ctx.limit = limit;
  return chatter_py::to_python(chatter::forced_columns(r, ctx, record_path));
}

py::dict sle(const py::object& job, std::optional<double> rpm_min, std::optional<double> rpm_max,
             std::optional<int> rpm_points, double depth_mm, std::optional<double> feed_per_tooth_mm,
             std::optional<double> feed_mm_per_rev, std::optional<double> radial_immersion, int threads,
             std::optional<double> position_mm, std::optional<int> steps) {
  const chatter::Config cfg = job_at(job, position_mm, radial_immersion);
  auto pick = [&](const std::optional<double>& given, const std::optional<double>& from_cfg, const char* arg,
                  const char* key) {
    if (given) return *given;
    if (from_cfg) return *from_cfg;
    throw InputError(cfg.name + ": missing " + arg + " (or " + key + " in the config)");
  };
  const double lo = pick(rpm_min, cfg.sweep.rpm_min, "rpm_min", "sweep.rpm_min");
  const double hi = pick(rpm_max, cfg.sweep.rpm_max, "rpm_max", "sweep.rpm_max");
  const int n = rpm_points.value_or(cfg.sweep.rpm_points.value_or(kDefaultRpmPoints));
  if (!(std::isfinite(lo) && lo > 0.0)) throw InputError("rpm_min = " + fmt(lo) + ": must be > 0 rev/min");
  if (!(std::isfinite(hi) && hi > lo)) throw InputError("rpm_max = " + fmt(hi) + ": must be > rpm_min (" + fmt(lo) + ")");
  if (n < 2 || n > kMaxRpmPoints)
    throw InputError("rpm_points = " + std::to_string(n) + ": must be in [2, " + std::to_string(kMaxRpmPoints) + "]");
  if (threads < 0 || threads > 1024)
    throw InputError("threads = " + std::to_string(threads) + ": must be in [0, 1024] (0 = every core)");
  check_depth(depth_mm);
  const double feed_mm = feed_mm_of(cfg, feed_per_tooth_mm, feed_mm_per_rev);
  const double depth_max_mm = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 1.01 * depth_mm);
  const std::vector<double> speeds = chatter::evenly_spaced_speeds(lo, hi, n);
  std::vector<chatter::ForcedResponse> rows;
  {
    py::gil_scoped_release release;
    const chatter::ForcedResponseSolver solver(cfg.model, cfg.process, options_of(steps, depth_max_mm));
    rows = chatter::sle_sweep(solver, speeds, depth_mm * 1e-3, feed_mm * 1e-3, static_cast<unsigned>(threads));
  }
  chatter::SleContext ctx;
  ctx.config = cfg.name;
  ctx.depth_mm = depth_mm;
  ctx.feed_mm = feed_mm;
  ctx.feed_key = std::string(cfg.process.feed_record_key());
  ctx.position_mm = position_mm;
  return chatter_py::to_python(chatter::sle_columns(rows, ctx));
}

}  // namespace

void bind_forced(py::module_& m) {
  m.def("forced", &forced, "job"_a, py::kw_only(), "rpm"_a, "depth_mm"_a, "feed_per_tooth_mm"_a = py::none(),
        "feed_mm_per_rev"_a = py::none(), "radial_immersion"_a = py::none(), "position_mm"_a = py::none(),
        "steps"_a = py::none(), "record_path"_a = true,
        "The forced response of a stable cut (chatter forced --json's record; with record_path the tool path over "
        "one period as NumPy arrays under 'path'). Unstable: stable False, the response numbers None.");
  m.def("sle", &sle, "job"_a, py::kw_only(), "rpm_min"_a = py::none(), "rpm_max"_a = py::none(),
        "rpm_points"_a = py::none(), "depth_mm"_a, "feed_per_tooth_mm"_a = py::none(), "feed_mm_per_rev"_a = py::none(),
        "radial_immersion"_a = py::none(), "threads"_a = 0, "position_mm"_a = py::none(), "steps"_a = py::none(),
        "Surface location error and peak-to-peak vibration against spindle speed as NumPy arrays (chatter sle's "
        "table; NaN where unstable) plus stable and teeth_leave_cut.");
}
