// Spindle speed variation in the time-domain simulation (docs/ssv.md "In
// the time domain"): the modulated speed of the run, and the times of the
// events that move with it. Part of Model (time_domain_model.hpp).
//
// The spindle turns θ(t) = Ω₀ t + (R_VA / R_VF)(1 − cos(R_VF Ω₀ t)) (rad,
// chatter/speed_variation.hpp). Every angle of the constant-speed model is
// kept, read at the mean-speed time t' = θ(t)/Ω₀ instead of t:
//  - the tooth angles φ_j(t) = θ(t) + …;
//  - the delay of a surface left by the tooth the angle Ω₀ d before (d the
//    constant-speed delay: a tooth period, a pitch over Ω₀, one revolution
//    in turning) is τ(t) with θ(t) − θ(t − τ) = Ω₀ d (ModulatedSpeed::delay,
//    Newton to round-off), read from the history at t − τ(t);
//  - the arc events, start images and the delay images of a chip zero
//    crossing are the constant-speed ones in t', at the real times
//    t = θ⁻¹(Ω₀ t') (ModulatedSpeed::time_at_angle);
//  - process damping C_pd a / V follows the cutting speed V ∝ Ω(t).
// The run's period is the principal period p T_m = q T_F of
// speed_variation_period (sdm's), and the modulation is integrated with the
// frequency ratio that period is exact for (frequency_ratio_used), so that
// the simulated equation is periodic over it and its growth per period is
// sdm's multiplier |μ| of the same equation.
// Method: the delay-differential equation with a time-varying delay of
// Insperger & Stépán (2004, turning) and Seguy et al. (2010, milling),
// integrated as the constant-speed simulation (Altintas, Manufacturing
// Automation, 2nd ed. 2012, ch. 3; docs/time_domain.md).
// Units: SI (s, rad, rad/s).
#include "time_domain_model.hpp"
#include "time_domain_run.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/kinematics.hpp"

namespace chatter::td_detail {

void Model::init_speed_variation() {
  if (!process_.has_speed_variation()) return;  // constant speed: the code path of old, untouched
  if (process_.has_runout() && !homogeneous(settings_))
    throw InputError(
        "time-domain with spindle speed variation does not model runout (process.runout_um): its static chip "
        "repeats once per revolution, which the principal period of the modulation need not hold; remove "
        "process.runout_um or process.speed_variation");
  // A cutter profile's slices (their own arcs and lags) are not mapped
  // through the modulated angle: a cylinder given as a general profile
  // moved the growth per period 6 % off the flat cutter's with R_VA 0.1
  // (0.386 against 0.364; 4e-5 apart at constant speed). Refused, as sdm
  // refuses it.
  if (process_.has_profile())
    throw InputError("time-domain with spindle speed variation (process.speed_variation) does not handle a cutter "
                     "profile (process.cutter_geometry = \"" + std::string(to_string(process_.cutter_profile().geometry())) +
                     "\", docs/cutter_geometry.md): remove process.speed_variation or use a flat cutter");
  const SpeedVariationPeriod per = speed_variation_period(process_, settings_.spindle_rpm);
  ssv_ = true;
  speed_ = ModulatedSpeed(settings_.spindle_rpm, {process_.speed_variation().amplitude_ratio, per.frequency_ratio_used});
  mean_delay_ = process_.delay_s(settings_.spindle_rpm);
}

double Model::image_time(double t_r, double mean_offset) const {
  return speed_.time_at_angle(speed_.angle(t_r) + omega_spindle_ * mean_offset);
}

}  // namespace chatter::td_detail

namespace chatter {

// A run counted in whole periods of the equation; with speed variation the
// principal period holds q Floquet periods (several revolutions).
constexpr int kDefaultRunPeriods = 200;
constexpr int kMinSpeedVariationPeriods = 20;
constexpr int kMinRunPeriods = 4;

int simulation_periods_in_revolutions(const Process& process, double rpm, bool linear, int revolutions) {
  if (!process.has_speed_variation()) return revolutions * simulation_periods_per_revolution(process, rpm, linear);
  const double periods = revolutions * revolution_s(rpm) / simulation_period_s(process, rpm, linear);
  return std::max(kMinRunPeriods, static_cast<int>(std::ceil(periods - 1e-9)));
}

int default_simulation_periods(const Process& process, double rpm, bool linear) {
  if (!process.has_speed_variation()) return kDefaultRunPeriods;
  const double tooth_periods = simulation_period_s(process, rpm, linear) / process.delay_s(rpm);
  return std::max(kMinSpeedVariationPeriods, static_cast<int>(std::ceil(kDefaultRunPeriods / tooth_periods - 1e-9)));
}

}  // namespace chatter

namespace chatter::td_detail {

// The linear run of check_locked_orbit: enough periods for the DMD's four
// pairs in the analysed half (the growth per period is sdm's |μ| to 1e-3 at
// 12 on case A and case C, tests/test_time_domain_ssv.cpp).
constexpr int kLockedCheckPeriods = 12;

void check_locked_orbit(const TimeDomainSimulator& sim, const SimulationSettings& s, SimulationResult& r) {
  if (s.linear || r.verdict != SimulationVerdict::kStable || !r.forced_steady ||
      !(r.out_of_cut_fraction > detail::kAirFraction))
    return;
  SimulationSettings lin;
  lin.spindle_rpm = s.spindle_rpm;
  lin.depth_m = s.depth_m;
  lin.periods = kLockedCheckPeriods;
  lin.linear = true;
  lin.record_series = false;
  const SimulationResult l = sim.simulate(lin);
  if (!(l.growth_per_period >= 1.0)) return;  // the forced response, leaving the cut: stable (with its warning)
  std::ostringstream os;
  os.precision(4);
  os << "locked chatter: the run settled into an orbit periodic over the principal period with the tool out of the "
        "cut during "
     << 100.0 * r.out_of_cut_fraction << " % of the cutting-arc time, and the forced response it left is unstable "
     << "(linear run: growth per period |mu| = " << l.growth_per_period << ")";
  r.verdict = SimulationVerdict::kChatter;
  r.verdict_measure = os.str();
  // The orbit's lines are all harmonics of the principal period: the
  // chatter frequency is the growing linear run's largest line (a
  // homogeneous run has no forced lines; with a window of a few principal
  // periods the harmonic windows k / T ± 2.5 / T_window would hide most of
  // its spectrum).
  std::size_t peak = 0;
  for (std::size_t k = 1; k < l.spectrum_amplitude_m.size(); ++k)
    if (peak == 0 || l.spectrum_amplitude_m[k] > l.spectrum_amplitude_m[peak]) peak = k;
  r.chatter_frequency_hz = peak > 0 ? l.spectrum_hz[peak] : l.dominant_nonharmonic_hz;
  r.linear_limit_warning.clear();
}

}  // namespace chatter::td_detail
