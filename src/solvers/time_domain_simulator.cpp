// The time-domain simulator's public surface (chatter/time_domain.hpp): the
// checks of its options and of one run's settings, the "no cut" refusal a
// front end asks for (docs/results.md), and simulate(), which hands one run
// to SimulationRun (time_domain_run.cpp); the period of a run the records
// report (simulation_period_s). Design: docs/time_domain.md.
#include "chatter/time_domain.hpp"
#include "time_domain_run.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "chatter/error.hpp"
#include "chatter/kinematics.hpp"

namespace chatter::td_detail {

// Settings checks that need neither the model nor the speed's sampling.
void validate_settings(const SimulationSettings& s) {
  if (!(s.spindle_rpm > 0.0 && std::isfinite(s.spindle_rpm)))
    throw InputError("spindle speed " + std::to_string(s.spindle_rpm) + " rev/min: must be > 0");
  if (!(s.depth_m >= 0.0 && std::isfinite(s.depth_m)))
    throw InputError("depth " + std::to_string(s.depth_m * 1e3) + " mm: must be >= 0");
  if (s.periods < 4) throw InputError("periods = " + std::to_string(s.periods) + ": must be >= 4");
  if (s.linear_static_chip && !s.linear) throw InputError("linear_static_chip: only in linear mode (linear = true)");
  if (!(s.feed_m >= 0.0 && std::isfinite(s.feed_m)))
    throw InputError("feed " + std::to_string(s.feed_m * 1e3) + " mm: must be >= 0");
  if (!s.linear && s.feed_m == 0.0 && s.depth_m > 0.0) throw InputError(std::string(kNoChipFeed));
  if (!(s.analysed_fraction > 0.0 && s.analysed_fraction <= 1.0))
    throw InputError("analysed_fraction must be in (0, 1]");
}

}  // namespace chatter::td_detail

namespace chatter {

using td_detail::SimulationRun;
using td_detail::simulation_period;
using td_detail::validate_settings;

std::string TimeDomainOptions::validate() const {
  std::ostringstream os;
  if (!(relative_tolerance >= 1e-12 && relative_tolerance <= 1e-2))
    os << "relative_tolerance = " << relative_tolerance << ": must be in [1e-12, 1e-2]";
  else if (samples_per_period < 8)
    os << "samples_per_period = " << samples_per_period << ": must be >= 8";
  else if (samples_per_vibration_cycle < 8)
    os << "samples_per_vibration_cycle = " << samples_per_vibration_cycle << ": must be >= 8";
  else if (max_samples_per_period < samples_per_period)
    os << "max_samples_per_period = " << max_samples_per_period << ": must be >= samples_per_period";
  else if (max_steps < 1000)
    os << "max_steps = " << max_steps << ": must be >= 1000";
  else if (axial_slices < 0 || axial_slices > 1000)
    os << "axial_slices = " << axial_slices << ": must be in [0, 1000] (0 = automatic)";
  else if (periods < kMinVerdictPeriods || periods > kMaxVerdictPeriods)
    os << "periods = " << periods << ": must be in [" << kMinVerdictPeriods << ", " << kMaxVerdictPeriods << "]";
  else if (!(depth_max_m > 0.0 && std::isfinite(depth_max_m)))
    os << "depth_max_m = " << depth_max_m << ": must be > 0 and finite";
  else if (!(depth_tolerance > 0.0 && depth_tolerance < 0.5))
    os << "depth_tolerance = " << depth_tolerance << ": must be in (0, 0.5)";
  else if (!(feed_m >= 0.0 && std::isfinite(feed_m)))
    os << "feed_m = " << feed_m << ": must be >= 0 and finite";
  else if (!linear && feed_m == 0.0)
    os << kNoChipFeed;
  return os.str();
}

TimeDomainSimulator::TimeDomainSimulator(StructuralModel model, Process process, TimeDomainOptions options)
    : model_(std::move(model)), process_(std::move(process)), options_(options) {
  const std::string why = options_.validate();
  if (!why.empty()) throw InputError("time-domain options: " + why);
  if (model_.mode_count() == 0)
    throw InputError("structural model: both bodies are rigid: give at least one mode");
  if (model_.has_measured())
    throw InputError("time-domain needs modes, not measured FRFs: fit modes to the measurement first "
                     "(chatter fit) and use them in the config");
}

void TimeDomainSimulator::require_chip(const SimulationSettings& s) const {
  validate_settings(s);
  if (const std::string why = process_.no_chip_reason(s.depth_m); !why.empty()) throw InputError(why);
}

SimulationResult TimeDomainSimulator::simulate(const SimulationSettings& s) const {
  validate_settings(s);
  SimulationRun run(model_, process_, options_, s);
  SimulationResult r = run.run();
  if (process_.has_speed_variation()) td_detail::check_locked_orbit(*this, s, r);
  return r;
}

double simulation_period_s(const Process& process, double rpm, bool linear) {
  SimulationSettings s;
  s.spindle_rpm = rpm;
  s.linear = linear;
  return simulation_period(process, s);
}

int simulation_periods_per_revolution(const Process& process, double rpm, bool linear) {
  if (process.has_speed_variation()) return 0;  // a period of several revolutions
  return static_cast<int>(std::lround(revolution_s(rpm) / simulation_period_s(process, rpm, linear)));
}

}  // namespace chatter
