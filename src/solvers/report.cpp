// The one definition of the reported quantities (chatter/report.hpp).
#include "chatter/report.hpp"

#include <cmath>
#include <memory>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/number_text.hpp"

namespace chatter {

int lobe_number(double chatter_frequency_hz, double tooth_passing_hz) {
  if (!(std::isfinite(chatter_frequency_hz) && chatter_frequency_hz >= 0.0 && tooth_passing_hz > 0.0)) return -1;
  const double x = chatter_frequency_hz / tooth_passing_hz;
  if (!(x < 1e9)) return -1;
  const double k = std::round(x);
  if (std::abs(x - k) <= 1e-9 * std::max(1.0, x)) return static_cast<int>(k);
  return static_cast<int>(std::floor(x));
}

namespace {

std::string number(double x) { return number_text(x, 6); }

}  // namespace

void check_spindle_rpm(double rpm, const std::string& name) {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(name + " = " + number(rpm) + ": must be > 0 rev/min");
  if (rpm > kMaxSpindleRpm)
    throw InputError(name + " = " + number(rpm) + ": at most " + number(kMaxSpindleRpm) +
                     " rev/min (the fastest spindles turn about 200 000 rev/min): check the unit");
}

void check_depth_mm(double depth_mm, const std::string& name, bool allow_zero) {
  if (!(std::isfinite(depth_mm) && (allow_zero ? depth_mm >= 0.0 : depth_mm > 0.0)))
    throw InputError(name + " = " + number(depth_mm) +
                     (allow_zero ? ": must be >= 0 mm" : ": must be > 0 mm (a cut of no depth cannot chatter)"));
  if (depth_mm > kMaxDepthMm)
    throw InputError(name + " = " + number(depth_mm) + ": at most " + number(kMaxDepthMm) +
                     " mm (no cut is a metre deep): typed in um?");
}

std::string depth_unit_hint(double depth_mm) {
  if (depth_mm > 0.0 && depth_mm < kPlausibleDepthMm[0])
    return "depth " + number(depth_mm) + " mm is thinner than a sharp edge's radius (" + number(kPlausibleDepthMm[0]) +
           " mm): a depth in m?";
  if (depth_mm > kPlausibleDepthMm[1])
    return "depth " + number(depth_mm) + " mm is deeper than any flute (" + number(kPlausibleDepthMm[1]) +
           " mm): a depth in um?";
  return "";
}

PointReport report_point(const LobeSolver& solver, const Process& process, double spindle_rpm, double depth_mm,
                         const LobeSolver* constant_speed) {
  const double depth_m = depth_mm * 1e-3;
  if (const std::string why = process.no_chip_reason(depth_m); !why.empty()) throw InputError(why);
  PointReport r;
  r.depth_mm = depth_mm;
  if (const std::string hint = depth_unit_hint(depth_mm); !hint.empty()) r.notes.push_back(hint);
  r.method = solver.method();
  r.spindle_rpm = spindle_rpm;
  r.depth_m = depth_m;
  r.depth_max_m = solver.depth_max_m();
  r.limit = solver.limit_with_diagnostics(SpindleSpeed(spindle_rpm));
  r.columns = solver.diagnostic_columns();
  r.tooth_passing_hz = process.tooth_passing_hz(spindle_rpm);
  r.tooth_period_s = process.delay_s(spindle_rpm);
  r.at_depth = solver.analyse_point(SpindleSpeed(spindle_rpm), depth_m);
  const bool below_limit = depth_m < r.limit.limit.depth_limit_m;
  r.stable = r.at_depth.stable.value_or(below_limit);
  r.margin = r.limit.limit.bounded() ? r.limit.limit.depth_limit_m / depth_m : std::numeric_limits<double>::infinity();
  // Speed variation: the same method at constant speed — the caller's, or
  // for sdm and time-domain (the methods that solve SSV) one built here from its own model,
  // process and options, so every front end reports the same record.
  std::unique_ptr<LobeSolver> own;
  if (process.has_speed_variation() && !constant_speed) {
    if (const auto* sdm = dynamic_cast<const SemiDiscretizationSolver*>(&solver)) {
      own = std::make_unique<SemiDiscretizationSolver>(sdm->model(), sdm->process().at_constant_speed(), sdm->options());
    } else if (const auto* td = dynamic_cast<const TimeDomainSolver*>(&solver)) {
      // The simulation solves SSV too (docs/ssv.md): the same options at constant speed.
      const TimeDomainSimulator& sim = td->simulator();
      own = std::make_unique<TimeDomainSolver>(sim.model(), sim.process().at_constant_speed(), sim.options());
    }
    constant_speed = own.get();
  }
  if (process.has_speed_variation() && constant_speed) {
    SpeedVariationGain g;
    g.asked = process.speed_variation();
    g.period = speed_variation_period(process, spindle_rpm);
    const StabilityLimit base = constant_speed->limit_at(SpindleSpeed(spindle_rpm));
    g.constant_speed_limit_m = base.depth_limit_m;
    if (base.bounded() && r.limit.limit.bounded()) g.gain = r.limit.limit.depth_limit_m / base.depth_limit_m;
    r.speed_variation = g;
  }
  if (r.at_depth.stable && *r.at_depth.stable != below_limit) {
    std::ostringstream os;
    os.precision(4);
    os << "method \"" << r.method << "\" finds the cut " << (r.stable ? "stable" : "unstable") << " at "
       << depth_m * 1e3 << " mm although the first limit at this speed is at " << r.limit.limit.depth_limit_m * 1e3
       << " mm: "
       << (r.stable ? "a stable band above the first limit (deeper cuts chatter again); the limit is the safe depth"
                    : "an unstable band below the first limit that the depth search stepped over, or a verdict "
                      "this close to the limit within the method's tolerance");
    r.notes.push_back(os.str());
  }
  return r;
}

}  // namespace chatter
