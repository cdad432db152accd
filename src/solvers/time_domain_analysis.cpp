// What a time-domain run returns (SimulationRun::finish): the integrator's
// cost, the growth per period (exact DMD of the once-per-period snapshots),
// the spectrum with the tooth-passing harmonics and the chatter frequency,
// and the stable / chatter verdict, from the analysers of
// time_domain_parts.hpp (each tested on its own). docs/time_domain.md.
#include "chatter/time_domain.hpp"
#include "time_domain_run.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "chatter/error.hpp"

namespace chatter::td_detail {
namespace {

using detail::GrowthEstimate;
using detail::Spectrum;
using detail::VerdictInput;
using detail::VerdictOutcome;
using detail::amplitude_spectrum;
using detail::decide_verdict;
using detail::dominant_nonharmonic_hz;
using detail::growth_per_period;
using detail::tooth_passing_harmonics;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

SimulationResult SimulationRun::finish() {
  long nsteps = 0;
  CVodeGetNumSteps(mem_, &nsteps);
  res_.steps = steps_done_ + nsteps;
  long nrhs = 0;
  CVodeGetNumRhsEvals(mem_, &nrhs);
  res_.rhs_evaluations = rhs_done_ + nrhs;
  res_.restarts = restarts_;
  res_.root_stops = root_stops_;
  res_.history_capacity = history_->capacity();
  res_.history_max_entries = history_->max_count();
  res_.max_amplitude_m = max_amp_;
  res_.out_of_cut_fraction = air_.fraction();

  const double rtol = options_.relative_tolerance;
  const GrowthEstimate growth = growth_per_period(snapshots_, first_analysed_, s_.linear, rtol);
  res_.dominant_multiplier = growth.multiplier;
  res_.growth_per_period = std::abs(growth.multiplier);

  const Spectrum sp = amplitude_spectrum(win_x_, win_y_, dt_);
  res_.spectrum_hz = sp.f;
  res_.spectrum_amplitude_m = sp.amp;
  const double best_f = dominant_nonharmonic_hz(sp, 1.0 / tau_);
  res_.dominant_nonharmonic_hz = best_f;
  res_.harmonics = tooth_passing_harmonics(sp, 1.0 / tau_, 3.0 * f_max_);

  VerdictInput vin;
  vin.linear = s_.linear;
  vin.growth = growth;
  vin.air = air_;
  vin.analysed_periods = s_.periods - first_analysed_;
  vin.relative_tolerance = rtol;
  const VerdictOutcome v = decide_verdict(vin);
  res_.verdict = v.verdict;
  res_.verdict_measure = v.measure;
  res_.chatter_frequency_hz = res_.verdict == SimulationVerdict::kChatter ? best_f : kNaN;
  if (history_->extrapolations() > 0)
    throw NumericalError("time-domain: internal error: the delayed state was needed outside the stored history (" +
                         std::to_string(history_->extrapolations()) + " times)");
  return std::move(res_);
}

}  // namespace chatter::td_detail

namespace chatter {

std::string to_string(SimulationVerdict v) { return v == SimulationVerdict::kStable ? "stable" : "chatter"; }

}  // namespace chatter
