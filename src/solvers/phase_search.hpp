// Internal: the search machinery shared by the transfer-function solvers
// (analytic, coupled). Not part of the public API.
//
// A solver supplies, at any frequency ω, the values of its characteristic
// branches (eigenvalues λ of H₀G for `analytic`, roots c of the coupled
// determinant for `coupled`). Each branch value gives
//   s     = 1/a_lim (1/m): the inverse of the depth at which the branch meets
//           the stability boundary; s <= 0 means no positive depth exists;
//   phase = ε in [0, 2π): on the boundary ωτ = ε + 2πk, k = 0, 1, 2, ...
// PhaseSearch samples the branches once on an adaptive frequency grid (fine
// enough that the phase moves by at most `max_phase_step_rad` and the value by
// at most `max_relative_step` per interval), then for any delay τ finds every
// crossing of ωτ − ε_unwrapped(ω) through a multiple of 2π, and refines the
// ones that can set the envelope with Brent's method on exact evaluations.
#pragma once

#include <array>
#include <complex>
#include <functional>
#include <vector>

#include <utility>

#include <Eigen/Core>

#include "chatter/lobes.hpp"
#include "chatter/structural_model.hpp"

namespace chatter::detail {

struct BranchValue {
  std::complex<double> z;  ///< the branch's underlying complex value (for continuity).
  double s = 0.0;          ///< 1 / depth limit, 1/m (<= 0: no positive depth).
  double phase = 0.0;      ///< ε in [0, 2π).
};

/// Fills `out[0 .. branches-1]` at ω (rad/s), in any order.
using BranchEvaluator = std::function<void(double omega, std::array<BranchValue, 2>& out)>;

struct PhaseSearchOptions {
  double max_phase_step_rad = 0.05;   ///< grid: largest phase change per interval.
  double max_relative_step = 0.05;    ///< grid: largest |Δz|/|z| per interval.
  double max_log_step = 0.02;         ///< grid: largest ln(ω_{i+1}/ω_i).
  double candidate_margin = 0.05;     ///< refine candidates within this relative margin of the best.
};

/// Root of the phase equation at one delay, exact to round-off.
struct PhaseRoot {
  double omega = 0.0;  ///< rad/s
  double depth_m = 0.0;
  int lobe = -1;
  int branch = -1;
};

class PhaseSearch {
 public:
  /// @param branches 0 (nothing can be unstable), 1 or 2.
  /// @param omega_lo, omega_hi frequency band searched, rad/s.
  /// @param depth_max_m deepest limit of interest, m.
  PhaseSearch(BranchEvaluator eval, int branches, double omega_lo, double omega_hi, double depth_max_m,
              PhaseSearchOptions options = {});

  /// Lowest boundary depth over all branches and lobes at delay τ (s);
  /// depth_m = +inf (lobe −1) when none is below depth_max.
  PhaseRoot lowest_root(double tau_s) const;

  /// Lobe curves as (ω, depth, τ) triples: for each branch and lobe k with
  /// τ in [tau_min, tau_max], the grid points where the depth is below
  /// depth_max. Pieces are split where the phase wraps.
  struct CurvePoint { double omega, depth_m, tau_s; };
  struct Curve { int lobe, branch; std::vector<CurvePoint> points; };
  std::vector<Curve> curves(double tau_min_s, double tau_max_s) const;

  /// Global minimum of the boundary depth over ω (exact to round-off).
  PhaseRoot minimum_depth() const;

  std::size_t grid_size() const { return omega_.size(); }
  double omega_lo() const { return omega_.front(); }
  double omega_hi() const { return omega_.back(); }

  /// Exact branch value at ω continued from the grid (branch identity and
  /// unwrapped phase follow the neighbouring samples).
  BranchValue continued(int branch, double omega, std::size_t interval, double* unwrapped_phase) const;

 private:
  void match(const std::array<BranchValue, 2>& ref, std::array<BranchValue, 2>& v) const;
  bool needs_split(const std::array<BranchValue, 2>& a, const std::array<BranchValue, 2>& b,
                   double wa, double wb) const;
  void refine(double wa, const std::array<BranchValue, 2>& a, double wb, std::array<BranchValue, 2> b,
              int depth);

  BranchEvaluator eval_;
  int branches_;
  double depth_max_m_;
  PhaseSearchOptions opt_;
  double z_scale_ = 0.0;  // largest |z| on the base grid, for the "negligible branch" floor
  std::vector<double> omega_;
  std::vector<std::array<BranchValue, 2>> values_;
  std::vector<std::array<double, 2>> unwrapped_;     // unwrapped phase per branch
  std::vector<std::array<bool, 2>> active_;          // interval i may hold a boundary below depth_max
};

/// Frequency band (rad/s) outside which no branch can reach a depth below
/// depth_max: a bound from ||H₀||·Σ|G_i| (each mode's |1 − r² + 2jζr| >= |1 − r²|).
/// Starts at [0.5 ω_min, 2 ω_max] and widens (down to 1e-3 ω_min).
std::pair<double, double> search_band(const StructuralModel& model, const Eigen::Matrix2d& H0, double depth_max_m);



}  // namespace chatter::detail
