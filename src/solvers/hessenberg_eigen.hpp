// Eigenvalues of a small upper Hessenberg matrix by the Francis double-shift
// QR iteration (Golub & Van Loan, Matrix Computations, 4th ed., §7.5:
// Algorithm 7.5.1 for the step, §7.5.6 for deflation and the exceptional
// shifts). Internal to the solvers (the `sdm` Arnoldi's Ritz values):
// eigenvalues only, so each step works on the active unreduced window alone
// and no Schur vectors are accumulated. For the k ≤ 30 matrices of the
// Arnoldi iteration this is 2–3 times cheaper than Eigen::RealSchur, whose
// generic blocks and Householder products dominate at that size.
#pragma once

#include <Eigen/Core>

namespace chatter::detail {

/// The n eigenvalues of the upper Hessenberg matrix `h` (entries below the
/// first subdiagonal are ignored), complex pairs as conjugates (Im > 0
/// first), in no particular order.
/// @throws NumericalError if the iteration does not converge (30 n steps) or
///         `h` holds a non-finite value.
void hessenberg_eigenvalues(const Eigen::MatrixXd& h, Eigen::VectorXcd& eigenvalues);

}  // namespace chatter::detail
