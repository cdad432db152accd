// Modal identification from one measured direction term of a receptance
// (e.g. xx): modes (frequency, damping, stiffness) whose receptance
// Σ 1/(k_i (1 − r_i² + 2jζ_i r_i)) matches the measured FRF over a band.
// Reference: docs/frf.md ("Modal fit").
//
// Method:
//  1. Peak picking for starting values: a resonance is a line whose |G| is
//     above every line around it until |G| has fallen below |G|max/√2 on
//     both sides (noise cannot fake that); f from a parabola through the
//     three top lines, ζ = (f₂ − f₁)/(2f) from the half-power crossings
//     (interpolated), k = 1/(2ζ|G|max).
//  2. Levenberg–Marquardt (Eigen's port of MINPACK lmder, Moré 1978: trust
//     region on the scaled step) on the complex
//     residual G_model − G_measured over the band, parameters
//     (ln f_i, ln ζ_i, ln k_i) so that all stay positive, analytic Jacobian,
//     optionally two residual terms for modes outside the band:
//     G_res = R_upper − R_lower (ω_c/ω)², R in m/N.
// Cost: O(L P²) per iteration for L lines and P = 3 n (+2) parameters.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "chatter/frf_data.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

struct ModalFitOptions {
  /// Number of modes to fit; 0 = as many as there are significant resonance
  /// peaks in the band (see peak_threshold).
  int modes = 0;
  /// Band of lines used, Hz (inclusive). Default: every line.
  double f_min_hz = 0.0;
  double f_max_hz = std::numeric_limits<double>::infinity();
  /// With `modes = 0`: ignore peaks lower than this fraction of the highest.
  double peak_threshold = 0.05;
  /// Fit upper and lower residual terms (out-of-band modes). Useful when the
  /// band cuts through the FRF next to other modes; lines at 0 Hz are then
  /// left out.
  bool residuals = false;
  /// Direction given to the fitted modes (unit vector in the X-Y plane). For
  /// a direct term (xx, yy) the fitted k is the stiffness along it.
  Eigen::Vector2d direction{1.0, 0.0};
  /// Levenberg–Marquardt budget (evaluations of the residual) and stop rule:
  /// stop when a step lowers the cost by less than `tolerance` (relative), or
  /// moves the log parameters by less than 1e-10 (relative).
  int max_iterations = 200;
  double tolerance = 1e-12;
};

struct ModalFitResult {
  std::vector<Mode> modes;          ///< fitted modes, by increasing frequency.
  std::vector<Mode> initial_modes;  ///< peak-picking estimates (same order).
  double residual_upper = 0.0;      ///< R_upper, m/N (0 without residuals).
  double residual_lower = 0.0;      ///< R_lower, m/N at ω_c (0 without residuals).
  double residual_omega = 0.0;      ///< ω_c, rad/s (band centre).
  /// Relative RMS of the complex residual over the band:
  /// sqrt(Σ|G_fit − G|² / Σ|G|²).
  double fit_error = 0.0;
  double initial_error = 0.0;       ///< the same for the peak-picking modes.
  int iterations = 0;               ///< evaluations of the residual (accepted steps or not).
  bool converged = false;           ///< stop rule met within max_iterations.
  std::size_t lines = 0;            ///< lines in the band.
  /// Per fitted mode (same order as `modes`): the standard errors of
  /// ln f, ln ζ and ln k, i.e. the relative (fractional) 1σ errors of the
  /// frequency, damping ratio and stiffness to first order (σ_p / p). From
  /// the linearised covariance at the solution, the heteroscedasticity-
  /// consistent "sandwich" (HC1; White 1980):
  /// (JᵀJ)⁻¹ Jᵀ diag(r²) J (JᵀJ)⁻¹ · n / (n − P), J the Jacobian of the
  /// n = 2L real residuals r (real and imaginary parts) in the log
  /// parameters: the noise may differ from line to line (a tap test's grows
  /// with |G|) but is assumed independent between lines.
  /// NaN where not identified (JᵀJ singular, or ζ held at its bound).
  /// Reference: docs/frf.md, "Standard errors".
  struct LogStandardErrors {
    double frequency = 0.0, damping = 0.0, stiffness = 0.0;
  };
  std::vector<LogStandardErrors> standard_errors;
  double f_min_hz = 0.0, f_max_hz = 0.0;  ///< band actually used (first and last line).

  /// The fitted receptance (modes along their direction, plus residuals), m/N.
  Complex receptance(double frequency_hz) const;
};

/// Peak picking alone (step 1). `options.modes` > 0 keeps the highest that
/// many peaks.
/// @throws InputError if the band holds fewer than 3 lines or fewer peaks
///         than asked (the message says how many it found).
std::vector<Mode> pick_peaks(const FrfTable& receptance, const ModalFitOptions& options = {});

/// Fits modes to one direction term of a receptance (m/N), see above.
/// @pre receptance passes validate().
/// @throws InputError for a bad band or option, or too few lines / peaks;
///         NumericalError if the fit leaves the physical range (ζ >= 1).
///         Not converging within the budget is reported in the result.
ModalFitResult fit_modes(const FrfTable& receptance, const ModalFitOptions& options = {});

}  // namespace chatter
