// Coupled tool–workpiece lobes from the characteristic determinant of the
// modal system (docs/physics.md §4; seed thesis ch. III with its sign errors
// corrected: the compliances of the two bodies add).
//
// Modal equations (docs/physics.md §2–3) with the averaged force give, at s = jω,
//   [D(jω) + c Sᵀ H₀ S] q = 0,  D = diag(m_i(ω_i² − ω² + 2jζ_iω_iω)),
//   c = a(1 − e^{−jωτ}).
// For one tool and one workpiece mode along X in turning this is
//   m₁φ₁ m₂φ₂ + K_f c (m₁φ₁ + m₂φ₂) = 0.
// Sᵀ H₀ S has rank r <= 2, so det(D + cP) is a polynomial of degree r in c,
// recovered exactly from its values at c = 0, ±σ. Each root c = a(1 − e^{−jθ})
// with a > 0 needs Re c > 0 and gives
//   a = |c|² / (2 Re c),   θ = ωτ = 2 atan2(Re c, Im c) + 2πk,
// since 1 − e^{−jθ} = 2 sin(θ/2) (sin(θ/2) + j cos(θ/2)).
#include <cmath>
#include <numbers>
#include <string>
#include <memory>
#include <utility>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "chatter/error.hpp"
#include "chatter/transfer_function.hpp"
#include "phase_search.hpp"

namespace chatter {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

detail::BranchValue from_root(Complex c) {
  const double re = c.real();
  double theta = std::fmod(2.0 * std::atan2(re, c.imag()), kTwoPi);
  if (theta < 0.0) theta += kTwoPi;
  return {c, 2.0 * re / std::norm(c), theta};
}

}  // namespace

CoupledSolver::CoupledSolver(StructuralModel model, Process process, TransferFunctionOptions options)
    : TransferFunctionSolver(std::move(model), std::move(process), options) {
  // One delay and no velocity term: the determinant below is a polynomial in
  // c = a(1 − e^{−jωτ}). Variable pitch and process damping break that form;
  // the analytic method solves them (through the registry the refusal names
  // every method that does).
  for (const auto& [has, what] : {std::pair{process_.has_variable_helix(), "a variable helix"},
                                  std::pair{process_.has_variable_pitch(), "variable pitch"},
                                  std::pair{process_.has_process_damping(), "process damping"}})
    if (has)
      throw InputError(std::string("method \"coupled\" does not handle ") + what +
                       " (its determinant assumes one delay and no process damping): use the analytic method");
  if (model_.has_measured())
    throw InputError("coupled needs modes, not measured FRFs: fit modes to the measurement first (chatter fit) "
                     "or use the analytic method");
  if (chord_iteration_) return;  // per speed over frozen chords (chord_limit_at)
  const ModalMatrices mm = modal_matrices(model_);
  omega_n_ = mm.omega;
  zeta_ = mm.damping_ratio;
  mass_ = mm.mass_kg;
  P_ = mm.S.transpose() * H0_ * mm.S;
  const Eigen::VectorXd sv = P_.jacobiSvd().singularValues();
  rank_ = 0;
  for (Eigen::Index i = 0; i < sv.size(); ++i)
    if (sv(i) > 1e-12 * sv(0)) ++rank_;
  if (rank_ > 2) throw NumericalError("coupled solver: rank of S^T H0 S must be at most 2");
  // rank 0: the cutting force cannot excite any mode; nothing is unstable.
  const double d_scale = (mass_.array() * omega_n_.array().square()).maxCoeff();
  sigma_ = rank_ > 0 ? d_scale / P_.cwiseAbs().maxCoeff() : 1.0;
  build_search(rank_);
}

std::unique_ptr<TransferFunctionSolver> CoupledSolver::with_process(Process process) const {
  return std::make_unique<CoupledSolver>(model_, std::move(process), options_);
}

std::array<Complex, 2> CoupledSolver::roots(double omega, int* count) const {
  const Eigen::Index n = omega_n_.size();
  Eigen::MatrixXcd D = Eigen::MatrixXcd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double wi = omega_n_(i);
    D(i, i) = mass_(i) * Complex(wi * wi - omega * omega, 2.0 * zeta_(i) * wi * omega);
  }
  const Eigen::MatrixXcd Pc = P_.cast<Complex>();
  auto f = [&](double c) -> Complex { return (D + c * Pc).partialPivLu().determinant(); };
  const Complex p0 = D.diagonal().prod();
  const Complex fp = f(sigma_), fm = f(-sigma_);
  const Complex p1 = (fp - fm) / (2.0 * sigma_);
  if (count) *count = rank_;
  if (rank_ == 1) return {-p0 / p1, Complex(0.0)};
  const Complex p2 = (fp + fm - 2.0 * p0) / (2.0 * sigma_ * sigma_);
  const Complex disc = std::sqrt(p1 * p1 - 4.0 * p2 * p0);
  const Complex q = -0.5 * ((std::real(std::conj(p1) * disc) >= 0.0) ? p1 + disc : p1 - disc);
  return {q / p2, p0 / q};
}

void CoupledSolver::evaluate(double omega, std::array<detail::BranchValue, 2>& out) const {
  int count = 0;
  const auto c = roots(omega, &count);
  for (int i = 0; i < count; ++i) out[static_cast<std::size_t>(i)] = from_root(c[static_cast<std::size_t>(i)]);
}

}  // namespace chatter
