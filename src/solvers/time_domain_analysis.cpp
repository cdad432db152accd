// What a time-domain run returns (SimulationRun::finish): the integrator's
// cost, the growth per period (exact DMD of the once-per-period snapshots),
// the spectrum with the tooth-passing harmonics and the chatter frequency,
// and the stable / chatter verdict, from the analysers of
// time_domain_parts.hpp (each tested on its own). docs/time_domain.md.
#include "chatter/time_domain.hpp"
#include "time_domain_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "chatter/error.hpp"
#include "chatter/kinematics.hpp"

namespace chatter::td_detail {
namespace {

using detail::GrowthEstimate;
using detail::Spectrum;
using detail::VerdictInput;
using detail::VerdictOutcome;
using detail::amplitude_spectrum;
using detail::decide_verdict;
using detail::dominant_nonharmonic_hz;
using detail::harmonic_index;
using detail::growth_per_period;
using detail::tooth_passing_harmonics;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Heights at which a helical wall is read (0 … a in this many parts), as
// ForcedOptions::axial_points.
constexpr int kWallHeights = 20;

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
  res_.axial_slices = m_.exact_edge() ? 0 : m_.slices();
  res_.max_amplitude_m = max_amp_;

  const double rtol = options_.relative_tolerance;
  const GrowthEstimate growth = growth_per_period(snapshots_, first_analysed_, homogeneous(s_), rtol);
  res_.dominant_multiplier = growth.multiplier;
  res_.growth_per_period = std::abs(growth.multiplier);

  const Spectrum sp = amplitude_spectrum(win_x_, win_y_, dt_);
  res_.spectrum_hz = sp.f;
  res_.spectrum_amplitude_m = sp.amp;
  res_.spectrum_harmonic.assign(sp.f.size(), 0);
  for (std::size_t k = 0; k < sp.f.size(); ++k)
    res_.spectrum_harmonic[k] = std::max(0, harmonic_index(sp.f[k], 1.0 / tau_, sp.resolution_hz));
  const double best_f = dominant_nonharmonic_hz(sp, 1.0 / tau_);
  res_.dominant_nonharmonic_hz = best_f;
  res_.harmonics = tooth_passing_harmonics(sp, 1.0 / tau_, 3.0 * f_max_);

  VerdictInput vin;
  vin.linear = homogeneous(s_);
  vin.growth = growth;
  vin.air = air_;
  vin.analysed_periods = res_.periods - first_analysed_;
  vin.relative_tolerance = rtol;
  const VerdictOutcome v = decide_verdict(vin);
  res_.verdict = v.verdict;
  res_.verdict_measure = v.measure;
  if (res_.periods < s_.periods)
    res_.verdict_measure += " (settled: stopped after " + std::to_string(res_.periods) + " of " +
                            std::to_string(s_.periods) + " periods)";
  res_.chatter_frequency_hz = res_.verdict == SimulationVerdict::kChatter ? best_f : kNaN;
  measure_forced(growth.converged);
  if (history_->extrapolations() > 0)
    throw NumericalError("time-domain: internal error: the delayed state was needed outside the stored history (" +
                         std::to_string(history_->extrapolations()) + " times)");
  return std::move(res_);
}

// What the run says about the forced vibration (docs/forced.md "In the
// simulation"): peak to peak and mean over the last period (its M grid
// samples), the wall left by the passes of the last period (read from the
// history, which holds 1.5 periods), and the teeth out of the cut.
void SimulationRun::measure_forced(bool converged) {
  res_.forced_steady = converged;
  const std::size_t n = win_x_.size(), M = static_cast<std::size_t>(M_);
  if (n >= M) {
    double lx = win_x_[n - M], hx = lx, ly = win_y_[n - M], hy = ly, sx = 0.0, sy = 0.0;
    for (std::size_t i = n - M; i < n; ++i) {
      lx = std::min(lx, win_x_[i]);
      hx = std::max(hx, win_x_[i]);
      ly = std::min(ly, win_y_[i]);
      hy = std::max(hy, win_y_[i]);
      sx += win_x_[i];
      sy += win_y_[i];
    }
    res_.forced_peak_to_peak_x_m = hx - lx;
    res_.forced_peak_to_peak_y_m = hy - ly;
    res_.forced_static_x_m = sx / static_cast<double>(M);
    res_.forced_static_y_m = sy / static_cast<double>(M);
  }
  if (!homogeneous(s_)) {
    if (!m_.milling()) {
      res_.forced_surface_location_error_m = -res_.forced_static_x_m;  // the chip direction is x
    } else {
      // Tooth j's slice at height z passes φ_w (π down, 0 up) at t = (φ_w +
      // Θ_j + κ_j z)/Ω + k·rev; the last pass of each within the last
      // period leaves −n_w·r − ρ_j; the wall at z is the deepest pass.
      const double phi_w =
          process_.milling_parameters().direction == MillingDirection::kDown ? std::numbers::pi : 0.0;
      const double nx = 0.0, ny = phi_w == 0.0 ? 1.0 : -1.0;  // n_w = (sin φ_w, cos φ_w), exactly
      const double rev = revolution_s(s_.spindle_rpm), omega = 2.0 * std::numbers::pi / rev, ex = std::exp(log_scale_);
      const int heights = process_.has_helix() || process_.has_profile() ? kWallHeights : 0;
      const double t_now = history_->newest().t;  // the end of the run (the last grid point)
      double worst = kNaN;
      for (int i = 0; i <= heights; ++i) {
        const double z = heights > 0 ? s_.depth_m * i / heights : 0.0;
        double wall = std::numeric_limits<double>::infinity();
        for (int j = 0; j < teeth_; ++j) {
          const double base =
              process_.has_profile()
                  ? (phi_w + process_.tooth_offset_rad(j) + process_.helix_lag_rad(j, z)) / omega
                  : (phi_w + process_.tooth_offset_rad(j) + process_.helix_lag_rad_per_m(j) * z) / omega;
          // The last pass, <= t_end (min: round-off may put a pass at t_end a hair beyond it).
          // (Speed variation: in the mean-speed time θ(t)/Ω₀, then back to t.)
          const double t_mean = m_.mean_time(t_now);
          const double t = std::min(m_.real_time(base + std::floor((t_mean - base) / rev) * rev), t_now);
          if (!(t > t_now - tau_ * (1.0 + 1e-9))) continue;                   // not in the last period
          double r[2];
          history_->displacement(t, r, History::kAnalysisSlot);
          wall = std::min(wall, -(nx * r[0] + ny * r[1]) * ex - process_.runout_m(j) + 0.0);
        }
        if (std::isfinite(wall) && !(std::abs(wall) <= std::abs(worst))) worst = wall;
      }
      res_.forced_surface_location_error_m = worst;
    }
  }
  // Teeth out of the cut over the analysed window.
  if (!s_.linear) {
    double arc = 0.0, air = 0.0, worst = 0.0;
    res_.out_of_cut_fraction_per_tooth.assign(tooth_arc_.size(), 0.0);
    for (std::size_t j = 0; j < tooth_arc_.size(); ++j) {
      arc += tooth_arc_[j];
      air += tooth_air_[j];
      const double f = tooth_arc_[j] > 0.0 ? tooth_air_[j] / tooth_arc_[j] : 0.0;
      res_.out_of_cut_fraction_per_tooth[j] = f;
      worst = std::max(worst, f);
    }
    res_.out_of_cut_fraction = arc > 0.0 ? air / arc : 0.0;
    res_.teeth_leave_cut = worst > kLeaveCutArcFraction;
    if (res_.teeth_leave_cut && res_.verdict == SimulationVerdict::kStable) {
      std::ostringstream os;
      os.precision(3);
      os << "the linear stability limit does not hold: forced vibration "
         << 1e6 * std::max(res_.forced_peak_to_peak_x_m, res_.forced_peak_to_peak_y_m)
         << " um peak to peak exceeds the chip (feed " << 1e6 * s_.feed_m << " um; teeth out of the cut "
         << 100.0 * res_.out_of_cut_fraction << " % of their arc time";
      // The reported fraction (out_of_cut_fraction) is the one quoted; the
      // worst tooth's share, which decides teeth_leave_cut, beside it.
      if (std::abs(worst - res_.out_of_cut_fraction) > 5e-4) os << ", the worst tooth " << 100.0 * worst << " %";
      os << "): the cut is stable in the simulation but the lobes of the "
         << "linear methods (analytic, sdm) do not describe it; see chatter forced";
      res_.linear_limit_warning = os.str();
    }
  }
}

}  // namespace chatter::td_detail

namespace chatter {

std::string to_string(SimulationVerdict v) { return v == SimulationVerdict::kStable ? "stable" : "chatter"; }

}  // namespace chatter
