// Forced vibration of a stable cut, its surface location error (SLE) and
// diametral error, and where the linear stability limit stops holding
// (docs/physics.md §11, docs/forced.md).
//
// Below the stability limit the vibration does not die out: the cutting
// force keeps driving the structure, and the motion converges to the
// periodic response of the linear delay equation of §3 with the static chip
// added (h_j = f_j sin φ_j + ρ_j − ρ_{j−1} + n_j·(r(t) − r(t − τ_j))).
//  - Equal pitch, one helix angle, no runout, no process damping (and
//    turning): the response is tooth-periodic, the regenerative term
//    vanishes, and r(t) = Σ_k G(k ω_T) F_k e^{j k ω_T t} (ω_T: tooth passing;
//    F_k: Fourier coefficients of the static force, in closed form, helix
//    included through Z(m) = ∫₀ᵃ e^{−jmκz} dz). Schmitz & Mann (2006), Int.
//    J. Mach. Tools Manuf. 46, 1199–1206: frequency-domain SLE; Kline &
//    DeVor (1983) static deflection.
//  - Variable pitch or helix, runout, process damping: the regenerative term
//    does not vanish; the periodic response is one linear solve
//    (I − Φ) y = r over one revolution on the sdm grid (the same step maps,
//    semi_discretization.hpp, with the static chip force held at its exact
//    step average: a forcing gain ∫₀ʰ e^{Ã s} ds B per step). Why not
//    harmonic balance: the step maps already hold the delays, the tooth
//    entries and exits and the helix exactly, and their error (O(h²)) is the
//    one of the stability verdict the response must agree with; harmonic
//    balance would need the Fourier coefficients of H(t) times r for every
//    pair of harmonics, many more for the jumps of straight teeth.
//  - Turning: a constant force F = K_f b f along the chip direction; δ =
//    F Σ (u·n)²/k (static_deflection_turning), diametral error 2 δ.
// The response is meaningful only for a stable cut (spectral radius < 1);
// the linear model holds only while no tooth leaves the cut
// (ForcedResponse::teeth_leave_cut). Units: SI.
//
// Thread safety: ForcedResponseSolver is immutable after construction; its
// const members may be called from several threads at once.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "chatter/position.hpp"
#include "chatter/process.hpp"
#include "chatter/results.hpp"  // ForcedResponse
#include "chatter/semi_discretization.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

struct ForcedOptions {
  /// The sdm options of the stability verdict and of the periodic solve
  /// (steps per period, steps per vibration cycle: the step count, and the
  /// O(h²) error, of the periodic response). depth_max_m is unused.
  SemiDiscretizationOptions sdm{};
  /// Fourier path: tooth-passing harmonics summed; 0 = automatic: every
  /// harmonic up to kAutoHarmonicFactor × the highest natural frequency, at
  /// least 64, at most max_harmonics. Beyond the modes the receptance falls
  /// as 1/f² and the force coefficients as 1/k, so the truncation error of
  /// the displacement is about (f_max / f_top)² of the static response:
  /// 1/2 500 at the automatic top.
  int harmonics = 0;
  int max_harmonics = 200000;
  /// Samples of the recorded tool path per period (>= 16).
  int samples_per_period = 720;
  /// Heights at which a helical wall is evaluated (the surface profile,
  /// 0 … a in this many equal parts; >= 1) and slices of a helical tooth
  /// whose chip is checked.
  int axial_points = 20;
  /// Points of the engaged arc at which each tooth's chip is checked
  /// (>= 16): the negative arc is resolved to arc / this.
  int arc_points = 720;
  /// Cross-checks: send even an equal-pitch cutter through the periodic solve.
  bool periodic_solve_always = false;

  /// Empty when valid, else the violated rule ("axial_points = 0: must be >= 1").
  std::string validate() const;
};

struct ForcedSettings {
  double spindle_rpm = 0.0;  ///< > 0, rev/min.
  double depth_m = 0.0;      ///< >= 0: axial depth (milling), width of cut (turning).
  /// Feed per tooth (milling) or per revolution (turning), m (>= 0).
  double feed_m = 0.0;
  /// Record the tool path over one period (t_s, rel_x_m, ...). A sweep
  /// (sle_sweep) turns it off.
  bool record_path = true;
};

/// The static deflection of turning (TurningDeflection, results.hpp): the
/// one place every feature (forced, optimize) takes the diametral error from.
/// @throws InputError unless the process is turning, depth >= 0, feed >= 0
///         (finite), and the model has modes only (no measured FRF).
/// Cost: O(modes).
TurningDeflection static_deflection_turning(const StructuralModel& model, const Process& process, double depth_m,
                                            double feed_per_rev_m);

/// The turning deflection along a position-dependent part (a cantilever
/// shaft: k(x) = k_tip / φ(x/L)², docs/physics.md §10; or [[positions]]):
/// static_deflection_turning on model_at_position at each position.
/// @throws InputError as model_at_position and static_deflection_turning.
std::vector<ShaftDeflection> diametral_error_along(const StructuralModel& base, const PositionDependence& dependence,
                                                   const Process& process, const std::vector<double>& positions_m,
                                                   double depth_m, double feed_per_rev_m);

class ForcedResponseSolver {
 public:
  /// @throws InputError if the options are invalid, both bodies are rigid,
  ///         or the model has measured FRFs (fit modes first).
  ForcedResponseSolver(StructuralModel model, Process process, ForcedOptions options = {});

  /// The forced response at one point. An unstable cut (spectral radius >=
  /// 1) returns stable = false, its spectral radius and NaN / empty
  /// response fields. Cost: one sdm analysis at the point (about one
  /// `chatter point --method sdm`) plus, on the Fourier path, O(harmonics ×
  /// samples), or on the periodic path one dense solve of the one-revolution
  /// map (dimension 2n + n_r × steps back to the longest delay: a few
  /// hundred; ~10 ms).
  /// @throws InputError on rpm <= 0, depth < 0 or feed < 0 (or not finite),
  ///         or a speed needing more than max_steps_per_period steps.
  ForcedResponse response(const ForcedSettings& settings) const;

  /// The stability solver of the verdicts (for the lobes under an SLE plot).
  const SemiDiscretizationSolver& stability() const { return sdm_; }
  const StructuralModel& model() const { return model_; }
  const Process& process() const { return process_; }
  const ForcedOptions& options() const { return options_; }

 private:
  StructuralModel model_;
  Process process_;
  ForcedOptions options_;
  SemiDiscretizationSolver sdm_;
};

/// The forced response at each speed (record_path off), on `threads`
/// threads (0 = every core); the rows do not depend on the thread count.
/// `per_speed` (optional) is called with the number done.
std::vector<ForcedResponse> sle_sweep(const ForcedResponseSolver& solver, const std::vector<double>& speeds_rpm,
                                      double depth_m, double feed_m, unsigned threads = 1,
                                      const std::function<void(std::size_t done)>& per_speed = {});

}  // namespace chatter
