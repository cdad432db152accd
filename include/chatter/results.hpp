// Plain result records of the solvers that other layers read: the io layer
// writes and draws them (chatter/io/plot.hpp, table_writer.hpp) without
// depending on the solver classes. No behaviour here but to_string().
//  - MultiplierType: how the dominant Floquet multiplier leaves the unit
//    circle (semi-discretisation, semi_discretization.hpp);
//  - SimulationResult: one time-domain run (time_domain.hpp).
// Units: SI (s, m, N, Hz).
#pragma once

#include <complex>
#include <cstddef>
#include <string>
#include <vector>

namespace chatter {

/// How the dominant multiplier leaves the unit circle.
enum class MultiplierType {
  kHopf,  ///< complex pair: chatter at a non-harmonic frequency (secondary Hopf)
  kFlip,  ///< real, negative (μ ≈ −1): period doubling
  kFold,  ///< real, positive (μ ≈ +1)
};
/// "hopf", "flip" or "fold".
std::string to_string(MultiplierType t);

/// One row of the time series (SI units).
struct SeriesSample {
  double t_s = 0.0;
  double tool_x_m = 0.0, tool_y_m = 0.0;
  double workpiece_x_m = 0.0, workpiece_y_m = 0.0;
  double rel_x_m = 0.0, rel_y_m = 0.0;   ///< tool − workpiece.
  double force_x_n = 0.0, force_y_n = 0.0;  ///< on the tool.
  /// Largest chip thickness over the teeth inside the cutting arc, m
  /// (0 when none is or all are in air). Linear mode: the unclipped value.
  double chip_m = 0.0;
  /// True when at least one tooth is removing material (h > 0 inside the arc).
  bool in_cut = false;
};

/// A peak of the relative-displacement spectrum.
struct SpectralPeak {
  double frequency_hz = 0.0;
  double amplitude_m = 0.0;
  int harmonic = 0;  ///< k for k / floquet_period_s (the tooth passing for a uniform cutter); 0 if not a harmonic.
};

enum class SimulationVerdict { kStable, kChatter };
/// "stable" or "chatter".
std::string to_string(SimulationVerdict v);

struct SimulationResult {
  SimulationVerdict verdict = SimulationVerdict::kStable;
  /// The measure the verdict rests on, in words with its numbers.
  std::string verdict_measure;
  /// Estimate of the dominant Floquet multiplier |μ| per delay period from
  /// the once-per-period states of the analysed window (exact dynamic mode
  /// decomposition of the period-to-period map). Linear mode: of the states;
  /// nonlinear mode: of the increments between consecutive periods, which
  /// obey the linear map while the tool stays in the cut. NaN when the
  /// increments had already fallen to the integration noise.
  double growth_per_period = 0.0;
  /// The corresponding multiplier (Im >= 0).
  std::complex<double> dominant_multiplier{0.0, 0.0};
  /// Chatter frequency (Hz): the largest spectral peak that is not a
  /// tooth-passing harmonic, when the verdict is chatter; NaN otherwise.
  double chatter_frequency_hz = 0.0;
  /// That peak whatever the verdict (the least damped vibration); NaN if none.
  double dominant_nonharmonic_hz = 0.0;
  /// Largest |r| (relative displacement, m) over the analysed window.
  double max_amplitude_m = 0.0;
  /// Fraction of the analysed window's cutting-arc time in which the teeth in
  /// the arc were all in air (h <= 0). 0 in linear mode.
  double out_of_cut_fraction = 0.0;
  /// The run's period τ_F, s: the Floquet period of the process
  /// (Process::floquet_period_s, the same as sdm's): the tooth period for a
  /// uniform cutter; the shortest repeat of the pitch and helix pattern (and
  /// of the runout in nonlinear mode) otherwise. periods, once_per_period and
  /// growth_per_period count it; `harmonics` are multiples of 1/τ_F.
  double floquet_period_s = 0.0;
  /// N·N_t/60 (Hz), Process::tooth_passing_hz: whatever the pitch.
  double tooth_passing_hz = 0.0;
  int periods = 0;
  int analysed_from_period = 0;

  std::vector<SeriesSample> series;          ///< empty unless record_series.
  std::vector<SeriesSample> once_per_period; ///< at t = kτ, k = 0..periods.
  /// Amplitude spectrum (m) of the relative displacement over the analysed
  /// window (Hann window, |X| combined over x and y), from 0 to Nyquist.
  std::vector<double> spectrum_hz, spectrum_amplitude_m;
  /// The forced lines k / floquet_period_s (tooth-passing harmonics for a
  /// uniform cutter, spindle harmonics for an irregular one) up to the
  /// highest natural frequency × 3.
  std::vector<SpectralPeak> harmonics;

  // Cost of the run.
  long steps = 0, rhs_evaluations = 0, restarts = 0, root_stops = 0;
  /// History ring buffer: capacity and the most entries held at once.
  std::size_t history_capacity = 0, history_max_entries = 0;
  int samples_per_period = 0;
};

}  // namespace chatter
