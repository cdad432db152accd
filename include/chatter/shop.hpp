// Shop data (issue 18): cutting coefficients identified from cutting tests
// (average dynamometer forces or spindle power), and chatter found in a
// recording (microphone or accelerometer) with the classic speed correction.
// Depends on Eigen only; reading files lives in include/chatter/io/shop_io.hpp.
// User guide: docs/shop_data.md; the formulas: docs/physics.md "Shop data".
//
// Force model (mechanistic, with edge forces; Altintas, "Manufacturing
// Automation", ch. 2, average-force method; Budak, Altintas & Armarego 1996):
// per tooth in the cut, straight teeth, angle φ measured clockwise from +Y,
//   F_t = K_tc a h + K_te a,  F_r = K_rc a h + K_re a,  h = f_z sin φ,
//   F_x = −F_t cos φ − F_r sin φ,  F_y = F_t sin φ − F_r cos φ.
// Averaged over a revolution and summed over N_t teeth, with
// c = N_t a / 2π and the integrals over [φ_en, φ_ex]
//   S = ∫ sin φ cos φ, Q = ∫ sin² φ, C = ∫ cos φ, Sn = ∫ sin φ, W = φ_ex − φ_en:
//   F̄x = c [ −f_z (K_tc S + K_rc Q) − (K_te C + K_re Sn) ]
//   F̄y = c [  f_z (K_tc Q − K_rc S) + (K_te Sn − K_re C) ]
//   mean tangential force of all teeth Σ F̄_t = c (K_tc f_z Sn + K_te W),
//   net cutting power P̄ = Ω R Σ F̄_t.
// Both are linear in the coefficients: a least-squares fit over the tests.
//
// Units: SI throughout (m, N, s, rad/s, W, Hz); speeds in rev/min are named so.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "chatter/kienzle.hpp"
#include "chatter/process.hpp"

namespace chatter {

// ---------------------------------------------------------------- coefficients

/// Engagement of the tests: the same cutter and radial immersion for all.
struct MillingEngagement {
  int teeth = 0;                                       ///< N_t >= 1, equally spaced straight teeth.
  double radial_immersion = 1.0;                       ///< a_e / D in (0, 1].
  MillingDirection direction = MillingDirection::kDown;
};

/// Entry and exit angles (rad) of §3 for the engagement.
/// @pre radial_immersion in (0, 1].
void engagement_angles(const MillingEngagement& e, double& phi_entry_rad, double& phi_exit_rad);

/// One cutting test whose forces were averaged over whole revolutions.
struct ForceTest {
  double feed_per_tooth_m = 0.0;  ///< f_z > 0
  double depth_m = 0.0;           ///< axial depth a > 0
  double fx_mean_n = 0.0;         ///< F̄x, N (feed direction)
  double fy_mean_n = 0.0;         ///< F̄y, N (normal to the feed)
};

/// One cutting test measured by net spindle power (cutting power minus the
/// idle power at the same speed).
struct PowerTest {
  double feed_per_tooth_m = 0.0;  ///< f_z > 0
  double depth_m = 0.0;           ///< a > 0
  double spindle_rpm = 0.0;       ///< N > 0
  double power_w = 0.0;           ///< P̄ >= 0, W
};

/// Predicted average forces (N) of the model at one test: {F̄x, F̄y}.
/// `k` = {K_tc N/m², K_rc N/m², K_te N/m, K_re N/m}. Cost O(1).
std::array<double, 2> mean_forces(const MillingEngagement& e, double feed_per_tooth_m, double depth_m,
                                  const std::array<double, 4>& k);

/// Predicted net cutting power (W): Ω R Σ F̄_t. `tool_diameter_m` = 2R.
double mean_power(const MillingEngagement& e, double feed_per_tooth_m, double depth_m, double spindle_rpm,
                  double tool_diameter_m, double tangential_n_per_m2, double tangential_edge_n_per_m);

/// A least-squares fit of the coefficients and its quality.
struct CoefficientFit {
  /// K_tc, N/m² (§3's K_t).
  double tangential_coefficient_n_per_m2 = 0.0;
  /// K_rc, N/m² (§3's K_r). NaN for the power route (not identifiable).
  double radial_coefficient_n_per_m2 = std::numeric_limits<double>::quiet_NaN();
  /// K_te, N/m.
  double tangential_edge_coefficient_n_per_m = 0.0;
  /// K_re, N/m. NaN for the power route.
  double radial_edge_coefficient_n_per_m = std::numeric_limits<double>::quiet_NaN();
  /// Standard errors of the four, same units and order (NaN where not
  /// identified, or with no degree of freedom left). From the residual
  /// variance s² = RSS / (m − p) and (AᵀA)⁻¹ (m equations, p unknowns);
  /// a 95 % interval is ± t(0.975, m − p) × standard error.
  std::array<double, 4> standard_error{};
  /// Half-widths of the 95 % confidence intervals (Student t, m − p d.o.f.).
  std::array<double, 4> confidence_95{};
  int degrees_of_freedom = 0;  ///< m − p
  /// Coefficient of determination 1 − RSS/TSS, TSS about the mean of each
  /// measured quantity (x and y separately, then summed). Power route: of P̄.
  double r_squared = 0.0;
  double r_squared_x = std::numeric_limits<double>::quiet_NaN();  ///< of F̄x alone (force route)
  double r_squared_y = std::numeric_limits<double>::quiet_NaN();  ///< of F̄y alone (force route)
  /// Per test: measured − fitted. Force route: x and y, N; power route:
  /// residual_x_n holds the power residual in W, residual_y_n is empty.
  std::vector<double> residual_x_n, residual_y_n;
  /// Plausibility warnings, each naming the coefficient or measure
  /// ("radial_coefficient_n_per_m2 = -1e8 N/m^2 is negative ...", "R^2 = 0.8 < 0.9 ...").
  std::vector<std::string> warnings;
};

/// Identifies K_tc, K_rc, K_te, K_re from average forces.
/// @pre tests valid (f_z > 0, a > 0, forces finite), e.teeth >= 1.
/// @throws InputError (message without a file name: the caller prefixes it)
///   when fewer than 3 tests (4 unknowns, 2 equations per test, at least 2
///   left for the error estimate) or fewer than 2 distinct feeds (cutting and
///   edge parts cannot be told apart), or the design is singular.
/// Cost O(n) for n tests.
CoefficientFit fit_coefficients_from_forces(const std::vector<ForceTest>& tests, const MillingEngagement& e);

/// Identifies K_tc and K_te alone from net spindle power.
/// @pre tool_diameter_m > 0. @throws InputError with fewer than 3 tests or
/// fewer than 2 distinct feeds. Cost O(n).
CoefficientFit fit_coefficients_from_power(const std::vector<PowerTest>& tests, const MillingEngagement& e,
                                           double tool_diameter_m);

// ------------------------------------------------- Kienzle's law (turning)

/// One turning test: the average forces of a cut at one feed and depth
/// (dynamometer components: tangential = cutting force F_c, feed = along
/// the feed F_f, radial = passive F_p; NaN = not measured).
struct TurningForceTest {
  double feed_per_rev_m = 0.0;  ///< f > 0
  double depth_m = 0.0;         ///< a > 0
  double tangential_n = 0.0;    ///< F_c > 0
  double feed_n = 0.0;          ///< F_f > 0
  double radial_n = std::numeric_limits<double>::quiet_NaN();  ///< F_p > 0, or NaN
};

/// Kienzle's law fitted per direction (chatter/kienzle.hpp): ln(F / b) =
/// ln k_1.1 + (1 − m) ln h with h = f sin κ_r, b = a / sin κ_r (mm),
/// ordinary least squares in (ln k_1.1, 1 − m).
struct KienzleDirectionFit {
  KienzleTerm term;                  ///< k_1.1 (N/m²) and m; k_1.1 = 0 when not measured
  double k_standard_error_n_per_m2 = std::numeric_limits<double>::quiet_NaN();  ///< k_1.1 × se(ln k_1.1)
  double m_standard_error = std::numeric_limits<double>::quiet_NaN();
  double k_confidence_95_n_per_m2 = std::numeric_limits<double>::quiet_NaN();   ///< half-widths, Student t
  double m_confidence_95 = std::numeric_limits<double>::quiet_NaN();
  double r_squared = std::numeric_limits<double>::quiet_NaN();  ///< of ln F (NaN with no degree of freedom)
  std::vector<double> residual_n;    ///< per test: measured − fitted force, N
};
struct KienzleFit {
  KienzleDirectionFit tangential, feed, radial;  ///< radial: only when every test measured it
  double lead_angle_rad = 0.0;
  int degrees_of_freedom = 0;  ///< tests − 2 (0: the law passes through two tests exactly; no errors)
  std::vector<std::string> warnings;
};

/// Fits Kienzle's law to turning tests at lead angle κ_r (rad, in (0, π/2]).
/// @throws InputError with fewer than 2 tests, fewer than 2 distinct chip
/// thicknesses, or a force <= 0 (messages without a file: the caller
/// prefixes it). Warns (by name) on an exponent outside [0, 1), R² < 0.9,
/// and two tests only. Cost O(n).
KienzleFit fit_kienzle(const std::vector<TurningForceTest>& tests, double lead_angle_rad);

/// Averages of a dynamometer series over the largest whole number of spindle
/// revolutions from the first sample (trapezoidal rule; the end point
/// interpolated linearly), so the runout and tooth harmonics cancel.
struct RevolutionAverage {
  double fx_mean_n = 0.0, fy_mean_n = 0.0;
  int revolutions = 0;      ///< whole revolutions averaged (>= 1)
  double duration_s = 0.0;  ///< revolutions × 60 / N
};
/// @pre time_s strictly increasing, same length as fx/fy, spindle_rpm > 0.
/// @throws InputError "shorter than one revolution" when the series spans
/// less than 60/N seconds. Cost O(samples).
RevolutionAverage average_whole_revolutions(const std::vector<double>& time_s, const std::vector<double>& fx_n,
                                            const std::vector<double>& fy_n, double spindle_rpm);

// ----------------------------------------------------------- chatter detection

/// Knobs of detect_chatter(), with the reasons for their defaults.
struct DetectOptions {
  double spindle_rpm = 0.0;  ///< N > 0, the programmed spindle speed
  int teeth = 0;             ///< N_t >= 1
  /// A peak is chatter when its amplitude is at least this fraction of the
  /// largest forced (spindle or tooth-passing harmonic) peak. 0.25: a forced
  /// response that is 4× stronger than the strongest non-harmonic line is
  /// the ordinary look of a stable cut's spectrum; chatter typically reaches
  /// or exceeds the forced lines.
  double peak_ratio_threshold = 0.25;
  /// ... and stands this many times above the median (noise floor) of the
  /// non-harmonic spectrum, so broadband noise is never called chatter.
  double prominence_threshold = 20.0;
  /// Shortest recording accepted, in spindle revolutions (fewer cannot
  /// separate spindle harmonics from a chatter line).
  double min_revolutions = 5.0;
  /// Speed search for the suggestions, rev/min (0: 0.5 N and 1.5 N).
  double rpm_min = 0.0, rpm_max = 0.0;
  /// Most suggestions listed.
  int max_suggestions = 8;
};

/// A line of the spectrum the detector classified.
struct DetectedPeak {
  double frequency_hz = 0.0;
  double amplitude = 0.0;  ///< in the recording's unit (single-sided amplitude)
  std::string kind;        ///< "tooth-passing", "spindle", "chatter"
  int harmonic = 0;        ///< multiple of the tooth-passing or spindle frequency; 0 for chatter
};

/// A speed the classic correction proposes: N_k = 60 f_c / (N_t k).
struct SpeedSuggestion {
  double spindle_rpm = 0.0;
  int k = 0;  ///< tooth-passing harmonic put on the chatter frequency
};

/// The detector's verdict and its evidence.
struct ChatterDetection {
  bool chatter = false;
  double chatter_frequency_hz = std::numeric_limits<double>::quiet_NaN();  ///< NaN when none
  /// Strongest non-harmonic line (reported even when it is not chatter).
  double candidate_frequency_hz = std::numeric_limits<double>::quiet_NaN();
  double tooth_passing_hz = 0.0;  ///< N N_t / 60 from the refined spindle frequency
  double spindle_hz = 0.0;        ///< refined from the tooth-passing line when it is clear, else N/60
  double frequency_resolution_hz = 0.0;  ///< FFT bin width
  double peak_ratio = 0.0;   ///< candidate amplitude / largest forced amplitude
  double prominence = 0.0;   ///< candidate amplitude / median non-harmonic amplitude
  /// Amplitude at the candidate frequency in the last window over the first
  /// (windows of ~1/8 of the recording): > 1 grows.
  double growth_ratio = std::numeric_limits<double>::quiet_NaN();
  /// Start of the first window where the candidate line reaches half its
  /// largest windowed amplitude, s from the recording's start; NaN without chatter.
  double onset_s = std::numeric_limits<double>::quiet_NaN();
  double duration_s = 0.0;
  std::vector<DetectedPeak> peaks;  ///< forced harmonics found, then the chatter line
  std::vector<SpeedSuggestion> suggestions;  ///< nearest to N first; empty without chatter
  /// The amplitude spectrum (single-sided, Hann window), for plots.
  std::vector<double> spectrum_frequency_hz, spectrum_amplitude;
  std::vector<std::string> warnings;  ///< e.g. clipping, a chatter line steady from t = 0
  /// A line stands (kLineOverFloor x the noise floor) within ±2 % of the
  /// tooth-passing frequency N N_t / 60 or its second harmonic. false: the
  /// given speed or teeth do not match the recording (the CLI refuses to
  /// judge it unless --force).
  bool tooth_passing_found = false;
  /// The speeds the spectrum's strongest line implies, rev/min: that line as
  /// the tooth passing (k = 1) or its k-th harmonic (k = 2, 3), 60 f/(N_t k).
  std::vector<double> implied_rpm;
  double strongest_line_hz = std::numeric_limits<double>::quiet_NaN();
};

/// Spectrum of `samples` (uniformly sampled at sample_rate_hz), classified
/// lines, verdict and the speed correction (see DetectOptions for the
/// measure). FFT: Eigen's unsupported FFT module (kissfft), zero-padded to a
/// power of two. Cost O(n log n) for n samples.
/// @throws InputError when the recording is shorter than min_revolutions
///   revolutions or has fewer than 64 samples, when the tooth-passing
///   frequency is above the Nyquist frequency, or the options are invalid.
ChatterDetection detect_chatter(const std::vector<double>& samples, double sample_rate_hz, const DetectOptions& o);

/// The classic correction: N_k = 60 f_c / (N_t k), k = 1, 2, …, inside
/// [rpm_min, rpm_max], sorted by distance from current_rpm, at most `max_count`.
std::vector<SpeedSuggestion> speed_corrections(double chatter_frequency_hz, int teeth, double current_rpm,
                                               double rpm_min, double rpm_max, int max_count);

}  // namespace chatter
