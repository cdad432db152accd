// Transfer-function (frequency-domain) stability lobes: the `analytic` and
// `coupled` solvers (docs/physics.md §4).
//
// Both replace H(t) by its average H₀ (turning: H itself; milling: the
// zeroth-order approximation of Altintas & Budak, CIRP Annals 44(1), 1995) and
// solve det(I + a(1 − e^{−jωτ}) H₀ G(jω)) = 0 for the depth a (m) and chatter
// frequency ω (rad/s) at a delay τ (s). Turning with one mode along X is
// Tlusty's b_lim = −1/(2 K_f Re G), minimum 2kζ(1+ζ)/K_f.
//
// - AnalyticSolver works with the eigenvalues λ of H₀G(jω):
//     a = −1/(2 Re λ),  ε = 3π + 2 atan2(Im λ, Re λ) (mod 2π),  ωτ = ε + 2πk.
// - CoupledSolver works with the determinant of the coupled modal system
//   (tool and workpiece modes together, docs/physics.md §4 / seed ch. III with its
//   sign errors corrected):  det(D(jω) + c Sᵀ H₀ S) = 0, with
//   D = diag(m_i(ω_i² − ω² + 2jζ_iω_iω)) and c = a(1 − e^{−jωτ}); the
//   determinant is a polynomial of degree rank(Sᵀ H₀ S) <= 2 in c, and each
//   root c gives a = |c|²/(2 Re c), ωτ = 2 atan2(Re c, Im c) + 2πk.
//   It never forms a receptance, so the two solvers check each other.
//
// For a requested spindle speed both return the exact envelope: every root of
// the phase equation at that delay is bracketed on a frequency grid sampled
// once per solver (fine enough that the phase moves < 0.05 rad per interval)
// and refined with Brent's method to round-off. Cost: construction O(grid ×
// n) (grid of a few hundred to a few thousand points), then per speed
// O(grid) plus a handful of exact evaluations.
//
// Real cutters (docs/physics.md §8): `analytic` solves variable pitch and
// helix and process damping with a general per-speed search instead,
//   det(I + a M(ω) G(jω)) = 0,  M = Σ_j (1 − e^{−jωτ_j}) H₀/N_t + jω (C_pd/V) P₀
// (Altintas, Engin & Budak 1999; Altintas, Eynian & Onozuka 2008): the
// eigenvalues λ of M G are tracked over a frequency grid refined per speed,
// and a = −1/λ where λ is real and negative. Its lobe number is
// floor(f_c · T), T the mean tooth period 60/(N N_t) (turning: one
// revolution). Cost per speed O(band · τ_max / max_phase_step_rad) 2×2
// eigenproblems (measured in docs/performance.md). The helix does not change
// the averaged equation (accepted, ignored with a note); a variable helix
// averages each tooth's delay over the height, which makes M depend on a:
// solved by an iteration on a (about 9 searches per speed). The uniform
// cutter keeps the path above.
//
// Turning inserts (docs/turning_inserts.md): a lead angle only changes H₀
// (a constant rank-one matrix), so both methods solve it as above. A nose
// radius makes H depend on the depth through the chord of the engaged edge,
// H(a) = d nᵀ / sin κ_eq(a): both methods then find the smallest a with
// F(a) <= a, F(a) the limit of the same method with the chord frozen at a
// (a sharp-corner insert at lead angle κ_eq(a), Process::with_chord_at), by
// the march and Brent iteration of the variable helix (about 14 frozen
// solvers per speed); no lobe curves and no absolute limit then.
//
// Thread safety: solvers are immutable after construction; all const members
// may be called from several threads at once.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

namespace detail {
class PhaseSearch;
class MultiDelaySearch;
struct BranchValue;
}

struct TransferFunctionOptions {
  /// Deepest cut searched, m (> 0). Limits above it are reported as +inf.
  double depth_max_m = 0.05;
  /// Largest change of the lobe phase ε between two samples of the
  /// frequency grid, rad (> 0). Smaller: a denser grid, slower construction.
  double max_phase_step_rad = 0.05;

  /// Empty string when valid, else the violated rule (Ceres-style).
  std::string validate() const;
};

/// Frequency band searched and the grid it was sampled on.
struct SearchBand {
  double omega_min_rad_s = 0.0;
  double omega_max_rad_s = 0.0;
  std::size_t grid_points = 0;
};

/// Behaviour shared by both transfer-function solvers.
class TransferFunctionSolver : public LobeSolver {
 public:
  ~TransferFunctionSolver() override;
  StabilityLimit limit_at(SpindleSpeed speed) const override;
  double depth_max_m() const override { return options_.depth_max_m; }

  /// Lobe curves with speeds in [from, to], one per lobe number,
  /// branch and continuous piece; depths below depth_max only. Empty for a
  /// cutter with several delays (variable pitch or helix) or process damping (the per-speed search
  /// traces no lobes: its lobes are not curves of one frequency parameter).
  std::vector<LobeCurve> lobe_curves(SpindleSpeed from, SpindleSpeed to) const override;
  /// The speed-independent minimum over every lobe (depth in m).
  /// @throws InputError for a cutter with several delays (variable pitch or
  ///         helix) or process damping
  ///         (the limit then depends on the speed in more than the lobe
  ///         phase: no speed-independent minimum; use limit_at).
  AbsoluteLimit absolute_limit() const;
  /// absolute_limit(), or nullopt where it is not defined (see above).
  std::optional<AbsoluteLimit> known_absolute_limit() const override;
  /// True when limit_at uses the general per-speed search (variable pitch or
  /// helix, process damping), false for the phase search of the uniform cutter.
  bool per_speed_search() const { return general_ != nullptr || chord_iteration_; }
  SearchBand band() const;
  const StructuralModel& model() const { return model_; }
  const Process& process() const { return process_; }
  const TransferFunctionOptions& options() const { return options_; }

 protected:
  /// @throws InputError if options are invalid or the model has no mode.
  TransferFunctionSolver(StructuralModel model, Process process, TransferFunctionOptions options);
  /// Derived constructors call this once they can evaluate their branches.
  void build_search(int branches);
  /// Or this, for the general per-speed search of a real cutter.
  void build_general_search();
  /// Fills the branch values at ω (see src/solvers/phase_search.hpp).
  virtual void evaluate(double omega, std::array<detail::BranchValue, 2>& out) const = 0;
  /// The same method on the same model for another process (the frozen
  /// chord of a nose radius).
  virtual std::unique_ptr<TransferFunctionSolver> with_process(Process process) const = 0;
  /// Turning with a nose radius: limit_at iterates on the depth over frozen
  /// chords (chord_limit_at) instead of a search of its own.
  bool chord_iteration_ = false;

  StructuralModel model_;
  Process process_;
  TransferFunctionOptions options_;
  Eigen::Matrix2d H0_;

 private:
  StabilityLimit chord_limit_at(double rpm) const;
  std::unique_ptr<detail::PhaseSearch> search_;
  std::unique_ptr<detail::MultiDelaySearch> general_;
};

class AnalyticSolver final : public TransferFunctionSolver {
 public:
  AnalyticSolver(StructuralModel model, Process process, TransferFunctionOptions options = {});
  std::string method() const override { return "analytic"; }
  /// Eigenvalues of H₀G(jω), 1/m (the second is 0 when H₀G has rank one).
  std::array<Complex, 2> eigenvalues(double omega_rad_s) const;

 protected:
  void evaluate(double omega, std::array<detail::BranchValue, 2>& out) const override;
  std::unique_ptr<TransferFunctionSolver> with_process(Process process) const override;

 private:
  bool rank_one_ = false;
};

class CoupledSolver final : public TransferFunctionSolver {
 public:
  CoupledSolver(StructuralModel model, Process process, TransferFunctionOptions options = {});
  std::string method() const override { return "coupled"; }
  /// Roots c (m) of det(D(jω) + c Sᵀ H₀ S) = 0; `count` is 1 or 2.
  std::array<Complex, 2> roots(double omega_rad_s, int* count) const;

 protected:
  void evaluate(double omega, std::array<detail::BranchValue, 2>& out) const override;
  std::unique_ptr<TransferFunctionSolver> with_process(Process process) const override;

 private:
  Eigen::VectorXd omega_n_, zeta_, mass_;
  Eigen::MatrixXd P_;  // Sᵀ H₀ S, N/m² per unit modal coordinate
  int rank_ = 0;
  double sigma_ = 1.0;  // scale of c used to interpolate the determinant
};

/// Builds the transfer-function solver named `method` through the solver
/// registry (solvers.hpp): "analytic" or "coupled".
/// @throws InputError on an unknown or non-transfer-function method, or as make_lobe_solver.
std::unique_ptr<TransferFunctionSolver> make_transfer_function_solver(const std::string& method,
                                                                      const StructuralModel& model,
                                                                      const Process& process,
                                                                      const TransferFunctionOptions& options);

}  // namespace chatter
