// Plain result records of the solvers that other layers read: the io layer
// writes and draws them (chatter/io/plot.hpp, table_writer.hpp) without
// depending on the solver classes. No behaviour here but to_string().
//  - MultiplierType: how the dominant Floquet multiplier leaves the unit
//    circle (semi-discretisation, semi_discretization.hpp);
//  - SimulationResult: one time-domain run (time_domain.hpp);
//  - ForcedResponse: the forced vibration of a stable cut, its surface
//    location error and where the linear model stops holding (forced.hpp).
// Units: SI (s, m, N, Hz).
#pragma once

#include <complex>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace chatter {

/// A tooth leaves the cut when its linear chip is negative over more than
/// this fraction of its engaged arc (docs/forced.md, docs/physics.md §11).
/// Where the static chip vanishes (the exit of down milling, the entry of up
/// milling) any wall offset δ between consecutive teeth (variable pitch,
/// runout) makes the chip negative over about δ / f_j rad: real but
/// harmless. 5 % of a half-immersion arc (4.5°) is δ ≈ 0.08 f_j, an offset
/// no longer small against the chip; a forced vibration that exceeds the
/// chip (the case the linear limit misses) empties far more of the arc.
/// The time domain judges its per-tooth out-of-cut fraction by the same
/// number.
inline constexpr double kLeaveCutArcFraction = 0.05;

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
  /// Fraction of the analysed window's cutting-arc time that the teeth in
  /// the arc spent out of the cut (chip below the contact margin): over
  /// every tooth and, for a helical cutter, every axial slice, each weighted
  /// by its engaged share (so a helical cutter in saturated chatter, whose
  /// slices leave the cut in turn while others still cut, shows it). 0 in
  /// linear mode. (Until issue 27: the time when all teeth in the arc were
  /// in air, which stays 0 for a helix; the verdict still reads that one.)
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
  /// Per spectrum line: k >= 1 when the line lies within the harmonic
  /// window (2.5 frequency resolutions 1/T_window) of k / floquet_period_s,
  /// else 0. The one definition of "a harmonic": the chatter frequency
  /// (dominant_nonharmonic_hz) is never taken from such a line, and the
  /// spectrum CSV's `harmonic` column marks exactly these lines.
  std::vector<int> spectrum_harmonic;
  /// The forced lines k / floquet_period_s (tooth-passing harmonics for a
  /// uniform cutter, spindle harmonics for an irregular one) up to the
  /// highest natural frequency × 3.
  std::vector<SpectralPeak> harmonics;

  // ---- issue 27: what the run says about the forced vibration (measured
  // over the last Floquet period of the run, after the transient) and the
  // teeth leaving the cut. JSON keys: the marked block of
  // src/cli/cmd_simulate.cpp and python/chatter_module.cpp's simulate.
  /// True when the once-per-period increments converged (a periodic forced
  /// response: the numbers below are its steady state); false when the run
  /// ended still growing, decaying or chattering (then they describe the
  /// last period only).
  bool forced_steady = false;
  /// Peak to peak of the relative displacement over the last period, m.
  double forced_peak_to_peak_x_m = 0.0, forced_peak_to_peak_y_m = 0.0;
  /// Mean of the relative displacement over the last period, m.
  double forced_static_x_m = 0.0, forced_static_y_m = 0.0;
  /// Surface location error of the last period's wall passes (docs/forced.md:
  /// −n·r when a tooth slice is at the wall, φ = π down / 0 up, minus its
  /// runout; the machined wall at each height is the deepest pass; this is
  /// the value of largest magnitude over the heights), m; NaN in turning
  /// and in linear mode without a feed.
  double forced_surface_location_error_m = std::numeric_limits<double>::quiet_NaN();
  /// Fraction of each tooth's cutting-arc time (its slices weighted by
  /// their engaged share) in which it was out of the cut (chip below the
  /// contact margin) over the analysed window; empty in linear mode.
  std::vector<double> out_of_cut_fraction_per_tooth;
  /// Some tooth was out of the cut over more than kLeaveCutArcFraction of
  /// its arc time (nonlinear mode).
  bool teeth_leave_cut = false;
  /// Non-empty when the run is stable (periodic) but teeth leave the cut:
  /// "the linear stability limit does not hold: forced vibration X um peak
  /// to peak exceeds the chip (...)". The CLI prints it on stderr.
  std::string linear_limit_warning;

  // Cost of the run.
  long steps = 0, rhs_evaluations = 0, restarts = 0, root_stops = 0;
  /// History ring buffer: capacity and the most entries held at once.
  std::size_t history_capacity = 0, history_max_entries = 0;
  int samples_per_period = 0;
  /// How the cut was resolved along the tool axis (milling): 0 = the exact
  /// integral along each tooth's helical edge (one helix angle, automatic
  /// slices), N >= 1 = N axial slices per tooth (1: straight teeth, the
  /// uniform path). 1 in turning.
  int axial_slices = 1;
};

/// The static deflection of turning (docs/physics.md §11): the force F =
/// K_f b f along the chip-thickness direction n = x and the relative
/// deflection it causes through the static compliance G(0) = Σ u uᵀ / k of
/// the structure given (the tool at its position: pass model_at_position).
/// The one place every feature (forced, sle, optimize) takes the diametral
/// error from.
struct TurningDeflection {
  double force_n = 0.0;             ///< F = K_f b f (on the tool, along −x), N.
  double deflection_m = 0.0;        ///< δ = F Σ (u·n)²/k, m (> 0: material left).
  double deflection_x_m = 0.0;      ///< relative displacement tool − workpiece, m
  double deflection_y_m = 0.0;
  double diametral_error_m = 0.0;   ///< 2 δ, m.
};
/// One position of diametral_error_along.
struct ShaftDeflection {
  double position_m = 0.0;
  TurningDeflection deflection;
};
/// The forced vibration of a stable cut (docs/physics.md §11, docs/forced.md;
/// built by ForcedResponseSolver, chatter/forced.hpp). SI units; NaN where
/// a quantity does not apply (turning has no wall pass, milling no
/// diametral error) and for an unstable cut, which has no forced response.
struct ForcedResponse {
  double spindle_rpm = 0.0;
  double depth_m = 0.0;
  /// Feed per tooth (milling) or per revolution (turning), m.
  double feed_m = 0.0;
  bool milling = true;
  /// The Floquet verdict at the point (sdm, the same as `chatter point
  /// --method sdm`): a forced response exists only when stable.
  bool stable = false;
  double spectral_radius = std::numeric_limits<double>::quiet_NaN();
  /// "fourier": equal pitch, one helix angle, no runout or process damping
  /// (and turning): the response to the static force alone, Σ G(kω_T) F_k
  /// e^{jkω_T t}; "periodic-solve": one linear solve (I − Φ) x = r over one
  /// revolution on the sdm grid, regeneration included.
  std::string method;
  /// Fourier path: tooth-passing harmonics summed (0 otherwise).
  int harmonics = 0;
  /// Period of the response, s: one tooth period (fourier), one revolution
  /// (periodic-solve), one revolution in turning.
  double period_s = 0.0;
  /// The tool path relative to the workpiece over one period (empty unless
  /// recorded): time, relative displacement (tool − workpiece) x, y, and
  /// its component into the wall, −n_w·r (the SLE a tooth would leave if it
  /// passed the wall then; turning: −r_x), m.
  std::vector<double> t_s, rel_x_m, rel_y_m, wall_normal_m;
  /// Mean relative displacement over the period, m: G(0) F̄ (Kline & DeVor's
  /// static deflection).
  double static_x_m = 0.0, static_y_m = 0.0;
  /// Mean cutting force on the tool over the period, N.
  double mean_force_x_n = 0.0, mean_force_y_n = 0.0;
  double peak_to_peak_x_m = 0.0, peak_to_peak_y_m = 0.0;
  /// Surface location error, m: the machined wall's offset from where it
  /// should be, positive = material left (undercut). At height z the wall
  /// is the deepest of the teeth's passes through φ_w (π down, 0 up):
  /// SLE(z) = min_j [−n_w·r(t_j(z)) − ρ_j]; this is the SLE(z) of largest
  /// magnitude over 0 ≤ z ≤ a (the one value for straight teeth). Turning:
  /// the deflection δ along the chip direction (material left on the radius).
  double surface_location_error_m = std::numeric_limits<double>::quiet_NaN();
  /// The smallest and largest SLE(z), m.
  double sle_min_m = std::numeric_limits<double>::quiet_NaN();
  double sle_max_m = std::numeric_limits<double>::quiet_NaN();
  /// The machined surface profile: heights z (0 … a) and SLE(z), m; and
  /// per tooth j its own pass −n_w·r(t_j(z)) − ρ_j (row-major, tooth × z).
  std::vector<double> wall_z_m, wall_sle_m, tooth_wall_sle_m;
  /// When each tooth's tip (z = 0) passes the wall, in [0, period_s), s.
  std::vector<double> tooth_wall_t_s;
  /// The smallest linear chip f_j sin φ + ρ_j − ρ_{j−1} + n·(r(t) −
  /// r(t − τ_j(z))) over the teeth, heights and engaged arc, m (turning:
  /// the feed).
  double min_chip_m = std::numeric_limits<double>::quiet_NaN();
  /// The longest arc over which one tooth (slice) has a negative linear chip,
  /// degrees, and that arc over the engaged arc.
  double negative_chip_arc_deg = 0.0;
  double negative_chip_fraction = 0.0;
  /// negative_chip_fraction > kLeaveCutArcFraction: the forced vibration
  /// exceeds the chip and a tooth leaves the cut.
  bool teeth_leave_cut = false;
  /// Stable and no tooth leaves the cut: the linear model (the lobes of
  /// analytic and sdm, this response) describes the cut. False: only the
  /// nonlinear simulation (chatter simulate) does.
  bool linear_limit_holds = false;
  /// Turning: 2 δ, the diametral error of a deflection along the radius, m.
  double diametral_error_m = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace chatter
