// Floquet stability of the periodic delay equation by first-order
// semi-discretisation: the `sdm` solver (docs/physics.md §5).
//
// Method: T. Insperger, G. Stépán, "Updated semi-discretization method for
// periodic delay-differential equations with discrete delay", Int. J. Numer.
// Meth. Engng 61 (2004) 117–141. In modal coordinates (docs/physics.md §2–3)
//   ẋ = A x − a B H(t) S q(t) + a B H(t) S q(t − τ),   x = [q; q̇],
// the delay period τ is split into steps; on each step H is replaced by its
// exact average over the step, the delayed term by the straight line through
// its two neighbouring samples, and the rest is solved exactly (matrix
// exponential). Only the part of S q that H can see is carried as delayed
// state (1 number per sample for turning or one-direction models, 2 in the
// plane), so the one-period map Φ has size 2n + (m + 1) n_r.
//
// Accuracy by design:
//  - milling: step boundaries fall on tooth entry and exit; the free flight
//    (no tooth cutting) is one exact step, exp(A t_free);
//  - the step is at most τ / steps_per_period and at most one
//    steps_per_vibration_cycle-th of the shortest natural period, so the step
//    count grows with τ f_max (case A at 100 rev/min: ≈57 vibration cycles);
//  - turning has constant coefficients: one step map D is built once and Φ =
//    D^m is applied as m cheap step operations, never formed;
//  - the spectral radius comes from a dense eigen-decomposition of Φ when Φ
//    is small, else from a restarted Arnoldi iteration on Φ applied as the
//    sequence of step maps (cost O(m n²) per product, no dense product).
// Error: O(h²) in the step h (second-order convergence, see docs/sdm.md).
//
// Collocation (collocation_nodes = s > 0, milling, turning with a sharp edge;
// with process damping the velocity at the nodes too): each cutting step instead collocates the cutting term at
// its s Gauss–Legendre nodes (H sampled there, the delayed state read at the
// nodes one period back, interpolated in degree 2s − 1 where a delay is not
// the period), the free dynamics still exact; error O(h^{2s}) measured
// (docs/sdm.md "Collocation"; after Breda, Maset & Vermiglio, SIAM J.
// Numer. Anal. 50 (2012) 1456–1483). The map holds s samples per cutting
// step. By default (kAutoCollocation) real cutters and turning with a sharp
// edge take it (3 nodes, kRealCutterSteps steps) and straight teeth keep the
// first-order steps. Turning's constant step then finds its multipliers from
// the s sheets of the branch roots at low speed (docs/sdm.md "Collocation in
// turning").
//
// Real cutters (docs/physics.md §8, docs/sdm.md "Real cutters"): a helix,
// variable pitch or helix, or process damping in milling take a second path.
// The period is one tooth period for a uniform cutter, else one revolution
// with one delay per tooth (per axial slice with a variable helix); step
// boundaries fall on Process::engagement_events_s (rebuilt per depth with a
// helix); step averages are the exact Process::tooth_force_integral /
// tooth_damping_integral; every delayed value is linearly interpolated in
// the stored history, and process damping −a (C_pd/V) Sᵀ D̄ S q̇ enters the
// free dynamics of each cutting step. Cost: one exponential of size 2n + 4
// (at most) per step and depth; a revolution holds N_t tooth periods of
// steps. Turning with process damping keeps the constant step. Runout is not
// seen (linear method).
//
// Spindle speed variation (Process::speed_variation, docs/ssv.md; Insperger
// & Stépán 2004 turning, Seguy et al. 2010 milling): the same real-cutter
// path over the principal period p T_m = q T_F (speed_variation_period),
// with the delay τ(t_i) at every step boundary from the integral of the
// speed; ρ and μ are per that period (FloquetResult::period_s). Not with
// process damping (InputError). Collocation there reads H at each node's
// mean-speed time and the delay τ_g(t_k) at the node.
//
// Thread safety: the solver is immutable after construction; every const
// member allocates its own workspace, so several threads may call them.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/results.hpp"  // MultiplierType
#include "chatter/structural_model.hpp"

namespace chatter {

/// Most Gauss collocation nodes per step (SemiDiscretizationOptions::collocation_nodes).
inline constexpr int kMaxCollocationNodes = 3;
/// The steps per period and per vibration cycle the `sdm` method takes with
/// collocation when none are given (the registry's "collocation" option):
/// 3 nodes at 8 steps keep the peers' 2-DOF case within 0.02 % (docs/sdm.md).
inline constexpr int kCollocationSteps = 8;
/// SemiDiscretizationOptions::collocation_nodes: chosen by the cut. A real
/// cutter (a helix, variable pitch or helix, a profile, two engaged arcs;
/// not on general_cutter_path) without process damping, and turning with a
/// sharp edge (no nose radius) without it, with or without speed variation, take
/// kRealCutterNodes nodes, and kRealCutterSteps steps per period and per
/// vibration cycle when those are left at their defaults (64, 64); every
/// other cut the first-order steps.
inline constexpr int kAutoCollocation = -1;
/// 3 nodes at 4 steps per vibration cycle: the 16 mm 3-flute 30° helix end
/// mill of docs/performance.md within 6e-5 of its converged limits over
/// 500–24 000 rev/min, where the first-order default is within 6e-4
/// (docs/sdm.md "Collocation on real cutters").
inline constexpr int kRealCutterNodes = 3;
inline constexpr int kRealCutterSteps = 4;

struct SemiDiscretizationOptions {
  /// The step h is at most τ / steps_per_period (>= 1) ...
  int steps_per_period = 64;
  /// ... and at most 1 / (steps_per_vibration_cycle · f_max) (>= 1), f_max
  /// the highest natural frequency, so the step count grows with τ f_max at
  /// low spindle speed. Each cutting segment of a milling period (between
  /// tooth entries and exits) gets ceil(duration / h) equal steps, at least
  /// one; free flight is always one exact step. The error falls as h²; the
  /// defaults (64, 64) keep the depth limit within 0.5 % of the converged
  /// value on cases A, B and C (max 0.44 % over 240 speeds, convergence
  /// study in docs/sdm.md). Cost grows linearly with both.
  int steps_per_vibration_cycle = 64;
  /// Largest number of steps in one delay period (>= 1): guards memory and
  /// time at very low spindle speed (the map holds about this many samples).
  int max_steps_per_period = 200000;
  /// Deepest cut searched, m (> 0). Limits above it are reported as +inf.
  double depth_max_m = 0.05;
  /// Relative tolerance of the depth limit (in (0, 0.1)).
  double depth_tolerance = 1e-4;
  /// Ratio between successive depths while bracketing the first crossing of
  /// ρ = 1 from below, used while ρ <= 1/4 (in (1, 10]).
  double bracket_ratio = 2.0;
  /// Ratio used as ρ approaches 1: the ratio falls from bracket_ratio at
  /// ρ = 1/4 to this at ρ = 1 as ((1 − ρ)/(3/4))² (in (1, bracket_ratio]).
  /// An unstable band narrower than the local ratio (near the tip of a flip
  /// lobe) may still be stepped over (docs/sdm.md).
  double bracket_min_ratio = 1.05;
  /// Number of bracketing depths below depth_max_m: the search starts at
  /// depth_max_m / bracket_ratio^bracket_steps (>= 1).
  int bracket_steps = 8;
  /// Largest one-period map solved with a dense eigen-decomposition (>= 1);
  /// bigger maps use the restarted Arnoldi iteration.
  int dense_max_dimension = 12;
  /// Krylov subspace dimension of the Arnoldi iteration (in [4, 400]).
  int krylov_dimension = 30;
  /// Turning with a map larger than dense_max_dimension and τ·min ζω >= 4
  /// (low speed, many vibration cycles per revolution): take the multipliers
  /// from the scalar branch equation ν^m = g(ν) of the one-step map, O(m) per
  /// map, instead of Arnoldi on Φ, whose multipliers crowd the unit circle
  /// there (docs/sdm.md). false: always the eigen-solvers (cross-checks).
  bool turning_branch_roots = true;
  /// Variable helix: each tooth's cut (0 … a) is split into this many equal
  /// axial slices, each with its own delay τ_j(z) at its mid-height and its
  /// exact share of H (>= 1). Unused otherwise (one helix angle keeps one
  /// delay per tooth and the exact integral over the height). Default from
  /// the convergence study in docs/sdm.md.
  int axial_slices = 8;
  /// Cross-checks: send every cut through the general path, the step grid
  /// built from the cutting law's regenerative side alone
  /// (chatter/regenerative_cut.hpp): the straight, equally spaced milling
  /// cutter over one revolution with one delay per tooth, turning as one
  /// edge one revolution back. false: those keep their fast paths (the
  /// tooth-period grid, the constant turning step; byte-identical tables).
  bool general_cutter_path = false;
  /// Gauss collocation nodes per cutting step (0 … 3, or kAutoCollocation;
  /// milling, or turning with a sharp edge). 0: first-order
  /// semi-discretisation (H averaged over the step, the delayed term linear
  /// between samples; error O(h²)). s >= 1: exponential collocation at the s
  /// Gauss–Legendre nodes of each step — the free dynamics still exact, H
  /// sampled at the nodes, the cutting term (present and delayed, read at
  /// the nodes one period back: exactly on a node when the delay is the
  /// period, else interpolated in degree 2s − 1) a polynomial of degree
  /// s − 1 — so the error falls as h^{2s} (h⁴ at s = 2, h⁶ at s = 3,
  /// measured in docs/sdm.md) and a few steps per vibration cycle suffice:
  /// with s = 3 and 8 steps (steps_per_period = steps_per_vibration_cycle =
  /// kCollocationSteps) the peers' 2-DOF case is within 0.014 % of its
  /// converged limits, the default first-order steps within 1.2 %.
  /// The map holds s samples per cutting step (none for free flight).
  /// The solver's constructor throws InputError for turning with a nose
  /// radius or process damping (collocation_refusal).
  /// kAutoCollocation (the default): chosen by
  /// the cut (see kAutoCollocation); the solver's options() say which.
  int collocation_nodes = kAutoCollocation;

  /// Empty string when valid, else the violated rule (Ceres-style).
  std::string validate() const;
};

// MultiplierType (hopf / flip / fold) is in chatter/results.hpp.

/// Floquet analysis at one (spindle speed, depth) point.
struct FloquetResult {
  double spindle_rpm = 0.0;
  double depth_m = 0.0;
  /// ρ = max |μ| over the multipliers of the one-period map; < 1 is stable.
  double spectral_radius = 0.0;
  /// The dominant multiplier (the one with Im μ >= 0 of a complex pair).
  std::complex<double> dominant_multiplier{0.0, 0.0};
  MultiplierType type = MultiplierType::kHopf;
  /// Chatter frequency (Hz): the member |f_k| = |arg μ + 2πk|/(2πτ), k ∈ ℤ,
  /// of the dominant multiplier's family that the motion shows. The Floquet
  /// solution x(t) = p(t) μ^{t/τ} (p τ-periodic) is rebuilt over one period
  /// from the dominant eigenvector (step maps through the cut, exact free
  /// vibration through free flight); k is the one whose Fourier coefficient
  /// of p, for the displacement the cut sees (X and Y power summed in
  /// milling, X in turning), is the largest, over |f_k| <= 2 f_max + 2/τ.
  /// A flip gives (k + ½)/τ, a Hopf the line nearest the dominant vibration.
  /// Cost: O(samples × members) once per call, about 3 ms at 3 600 steps and
  /// 230 members (case A at 100 rev/min). Rule and tests: docs/sdm.md.
  double chatter_frequency_hz = 0.0;
  /// Steps per delay period used (cutting steps + 1 when there is free flight).
  int steps = 0;
  /// The period of the map, s: one tooth period for a uniform cutter; for
  /// variable pitch or helix the shortest repeat of the pattern (one
  /// revolution, or half of one for 70/110/70/110°). ρ and μ are per this
  /// period: per revolution they are ρ^(60/(N·period_s)).
  double period_s = 0.0;
  /// Dimension of the one-period map.
  int map_dimension = 0;
  /// False if the Arnoldi iteration stopped on its restart budget before
  /// the dominant Ritz pair converged (the values are then its best estimate).
  bool converged = true;
  bool stable() const { return spectral_radius < 1.0; }
};

class SemiDiscretizationSolver final : public LobeSolver {
 public:
  /// @throws InputError if the options are invalid or both bodies are rigid.
  SemiDiscretizationSolver(StructuralModel model, Process process, SemiDiscretizationOptions options = {});

  std::string method() const override { return "sdm"; }
  /// multiplier_type (hopf, flip, fold) and spectral_radius_check (ρ at the
  /// reported limit, 1 to within the depth tolerance); empty at +inf limits.
  /// Defined with the registry entry (factory.cpp).
  std::vector<DiagnosticColumn> diagnostic_columns() const override;
  DiagnosedLimit limit_with_diagnostics(SpindleSpeed speed) const override;
  /// analyse() at the point: stable, spectral_radius, the dominant
  /// multiplier, its frequency and type, floquet_period_s, steps_per_period.
  PointAnalysis analyse_point(SpindleSpeed speed, double depth_m) const override;
  /// Depth limit (m) at `speed`: the first depth from 0 up where the
  /// spectral radius reaches 1 (bracketing, then Brent's method on ln ρ to
  /// depth_tolerance); +inf if stable up to depth_max_m. `lobe` is the number
  /// of whole chatter waves per delay, floor(f_c τ); `branch` is −1.
  /// Cost: about 20–40 evaluations of ρ, each one matrix exponential per
  /// step (one in all for turning) plus O(m n²) per map product; measured
  /// 2.3 ms per speed for case C, 12 ms for case A at 100 rev/min.
  /// @throws InputError if the speed is not > 0, or needs more than
  ///         max_steps_per_period steps.
  StabilityLimit limit_at(SpindleSpeed speed) const override;
  double depth_max_m() const override { return options_.depth_max_m; }

  /// Same search, also returning the Floquet analysis at the returned depth
  /// (ρ = 1 to within the depth tolerance), or at depth_max_m when the limit
  /// is +inf. `floquet` may be null.
  StabilityLimit limit_at(SpindleSpeed speed, FloquetResult* floquet) const;
  /// limit_at(speed).depth_limit_m > depth_m, from the same depth
  /// climb stopped as soon as the answer is sure: once two climbed depths
  /// above depth_m are stable (or one with ρ <= 1/4, where no band search can
  /// start), or once the crossing is bracketed below depth_m. Only a bracket
  /// holding depth_m is refined as limit_at() refines it; the chatter
  /// frequency is never computed. Cost at a third of the limit: a median
  /// 22–35 % of limit_at() (6 configs; case C at 200 rev/min: 3.5 ms
  /// against 22 ms).
  bool limit_above(SpindleSpeed speed, double depth_m) const override;
  /// ρ < 1 at the point: one period map and its dominant multiplier, as
  /// spectral_radius_map() computes it (no eigenvector, no chatter
  /// frequency). Case C at 200 rev/min: ≈ 1.5 ms, against 10 ms for analyse().
  std::optional<bool> stable_at(SpindleSpeed speed, double depth_m) const override;

  /// Floquet analysis at one point. @throws InputError if rpm <= 0 or
  /// depth < 0, or if the speed needs more than max_steps_per_period steps.
  FloquetResult analyse(double spindle_rpm, double depth_m) const;

  /// Spectral radius on a grid, row-major: value(i, j) at
  /// (rpms[i], depths_m[j]) is element i * depths_m.size() + j.
  /// @throws InputError on a non-positive speed or a negative depth.
  std::vector<double> spectral_radius_map(const std::vector<double>& rpms,
                                          const std::vector<double>& depths_m) const;

  const StructuralModel& model() const { return model_; }
  const Process& process() const { return process_; }
  const SemiDiscretizationOptions& options() const { return options_; }

 private:
  // limit_at() and limit_above(): the depth search at one speed. With
  // `decide_depth` NaN the whole search (`floquet` may be null); else it
  // stops once `limit > decide_depth` is sure, sets *above and returns a
  // limit whose depth is meaningful only when the search ran to the end.
  StabilityLimit search(double spindle_rpm, FloquetResult* floquet, double decide_depth, bool* above) const;

  StructuralModel model_;
  Process process_;
  SemiDiscretizationOptions options_;
  // Modal data and the reduced delayed quantity z = W q (n_r × n) with
  // H(t) S q = Ĥ(t) U W q; Ĥ = H U for milling, [K_f; 0] for turning.
  Eigen::MatrixXd A_;       // 2n × 2n free dynamics
  Eigen::MatrixXd B_;       // 2n × 2 force input
  Eigen::MatrixXd Wx_;      // n_r × 2n, z = Wx x
  Eigen::MatrixXd U_;       // n_L × n_r
  Eigen::MatrixXd Sv_;      // 2 × 2n: relative velocity ṙ = Sv x (process damping)
  double f_max_hz_ = 0.0;
  double slowest_decay_per_s_ = 0.0;  // min −Re λ_i (= min ζ_i ω_i): ln ρ at zero depth is −τ times this
  std::vector<std::complex<double>> free_poles_;  // λ_i = −ζω + jω√(1−ζ²) (1/s), or real pairs
};

}  // namespace chatter
