// Internal: the general per-speed solver of the averaged (transfer-function)
// method, for cutters with several delays (variable pitch) and/or process
// damping (docs/physics.md §8, docs/method.md "Real cutters"). Not part of the
// public API; `analytic` uses it when the cutter is not the uniform straight
// one of §3 (that one keeps the phase search of phase_search.hpp).
//
// At spindle speed N the averaged characteristic equation is
//   det(I + a M(ω) G(jω)) = 0,
//   M(ω) = Σ_j (1 − e^{−jωτ_j}) H₀ⱼ + jω (C_pd/V) P₀,
// with τ_j = θ_j/Ω the delay of tooth j (Altintas, Engin & Budak 1999),
// H₀ⱼ = (1/2π) ∫ H₁ dφ = H₀/N_t (the same for every tooth; turning: one
// "tooth", H₀ = H), P₀ = Process::average_damping_direction() and C_pd/V =
// Process::process_damping_per_depth(N) (Altintas, Eynian & Onozuka 2008).
// It is linear in a: for each eigenvalue λ(ω) of M(ω)G(jω) a real positive
// depth exists where λ is real and negative, a = −1/λ.
// Variable helix: the delay of tooth j changes along the flute, τ_j(z) =
// τ_j + z s_j, and each slice carries H₀ⱼ dz/a, so its term becomes the height
// average (1/a)∫₀ᵃ (1 − e^{−jωτ_j(z)}) dz = 1 − e^{−jωτ_j}(1 − e^{−jωa s_j})/(jωa s_j):
// M depends on a. With F(a) the limit for M frozen at a, the boundary is the
// smallest root of F(a) = a: a march up from a = 0 with fixed-point steps
// (never shorter than the step before) brackets it, Brent's method refines it
// (about 9 searches per speed; NumericalError if 200 steps find no bracket).
//
// Algorithm: a base frequency grid resolving G (built once: log steps
// <= 0.02, bisected until G changes by < max_phase_step_rad relative per
// interval) is subdivided per speed so that ω τ_max moves by at most
// max_phase_step_rad per interval; intervals where a bound of |λ|
// (||M||·||G||) cannot reach 1/(2 depth_max) are skipped. The two eigenvalue
// branches are tracked over the grid (matched by distance), every sign change
// of Im λ with Re λ < 0 is a candidate, and the candidates that can set the
// envelope are refined by Brent's method on Im λ to round-off. Cost per
// speed: O(band · τ_max / max_phase_step_rad) evaluations of a 2×2
// eigenproblem (a few thousand for a mode near 1 kHz at 5 000 rev/min) plus
// ~30 per refined candidate.
//
// Thread safety: immutable after construction; limit_at may be called from
// several threads at once.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"

namespace chatter::detail {

/// The two eigenvalues of a complex 2×2 matrix, the larger in modulus
/// first, the other from the product (no cancellation). Shared by
/// AnalyticSolver::eigenvalues and the multi-delay search.
std::array<Complex, 2> eigenvalues_2x2(const Matrix2c& M);

struct MultiDelayOptions {
  /// Deepest cut searched, m (> 0); limits above it are +inf.
  double depth_max_m = 0.05;
  /// Grid resolution, rad: the largest change of ω τ_max between two samples,
  /// and the largest relative change of G on the base grid.
  double max_phase_step_rad = 0.05;
};

class MultiDelaySearch {
 public:
  /// @pre model has at least one mode or measured FRF; options valid.
  MultiDelaySearch(StructuralModel model, Process process, MultiDelayOptions options);

  /// The envelope at one speed (rev/min > 0): the smallest depth over all
  /// roots. lobe = floor(f_c · T) with T the mean tooth period 60/(N N_t)
  /// (turning: one revolution), the lobe number of §4 for a uniform cutter;
  /// branch = the tracked eigenvalue branch (0 or 1).
  StabilityLimit limit_at(double spindle_rpm) const;

  /// M(ω) at speed `spindle_rpm`, N/m² (see above); with a variable helix the
  /// delays are averaged over the height 0 <= z <= depth_m (m).
  Matrix2c characteristic_matrix(double omega_rad_s, double spindle_rpm, double depth_m = 0.0) const;
  /// Eigenvalues of M(ω)G(jω), 1/m (larger modulus first).
  std::array<Complex, 2> eigenvalues(double omega_rad_s, double spindle_rpm, double depth_m = 0.0) const;

  double omega_lo() const { return grid_.front(); }
  double omega_hi() const { return grid_.back(); }
  std::size_t grid_size() const { return grid_.size(); }

 private:
  struct Speed;  // per-speed constants (delays, process damping)
  Speed speed(double rpm, double depth_m) const;
  std::array<Complex, 2> eigenvalues(double omega, const Speed& sp) const;
  StabilityLimit limit_at(const Speed& sp) const;

  StructuralModel model_;
  Process process_;
  MultiDelayOptions opt_;
  Eigen::Matrix2d H0_tooth_;     // H₀ⱼ, N/m²
  Eigen::Matrix2d P0_;           // average process-damping direction
  double bound_h_ = 0.0;         // Σ_j 2||H₀ⱼ||
  double bound_p_ = 0.0;         // ||P₀||
  std::vector<double> grid_;     // base grid, rad/s
  std::vector<double> g_norm_;   // ||G||_F on the base grid
};

}  // namespace chatter::detail
