// The dominant Floquet multiplier of one period map: a dense
// eigen-decomposition of Φ for small maps, a restarted Arnoldi iteration on
// Φ applied as its step maps for large ones, or (turning at low speed) the
// branch roots of sdm_branches.cpp (docs/sdm.md). Part of the `sdm` solver
// (sdm_internal.hpp).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "chatter/error.hpp"
#include "hessenberg_eigen.hpp"

namespace chatter::sdm_detail {
namespace {

// Arnoldi: relative residual of the dominant Ritz pair, and restart budget.
constexpr double kArnoldiTol = 1e-10;
constexpr int kArnoldiMaxRestarts = 60;

}  // namespace

// `decide`: only the verdict ρ < 1 or ρ >= 1 matters (bracketing); the
// Arnoldi iteration can then stop after a few steps, even for small maps.
namespace {

// Thrown inside the eigen-solvers when the period map's values overflowed
// (a cut so far beyond the limit that the vibration grows by more than 1e308
// per period): caught by SdmKernel::dominant, which reports ρ = +inf.
struct MapOverflow {};

// The Dominant of a map that overflowed: ρ = +inf (unstable beyond doubt;
// the depth searches then go down, analyse() reports no finite multiplier).
Dominant overflowed() {
  Dominant d;
  const double inf = std::numeric_limits<double>::infinity();
  d.mu = Cplx(inf, 0.0);
  d.rho_left = d.rho_right = inf;
  d.mu_left = d.mu_right = Cplx(inf, 0.0);
  return d;
}

}  // namespace

// A map whose values overflow (growth beyond 1e308 per period: a depth far
// above the limit, e.g. on a mode of 12 N/m) is unstable beyond doubt: ρ =
// +inf, never an error (the depth search then goes down).
Dominant SdmKernel::dominant(const PeriodMap& pm, bool want_vector, bool decide) const {
  try {
    Dominant d;
    if (pm.branch_roots && branches(pm, d) && std::isfinite(std::abs(d.mu))) return d;
    d = pm.dim <= o_.dense_max_dimension && !decide ? dense(pm, want_vector) : arnoldi(pm, want_vector, decide);
    return std::isfinite(std::abs(d.mu)) ? d : overflowed();
  } catch (const MapOverflow&) {
    return overflowed();
  }
}

bool SdmKernel::better(const Cplx& a, const Cplx& b) {  // a dominates b
  const double ra = std::abs(a), rb = std::abs(b);
  if (ra > rb * (1.0 + 1e-13)) return true;
  if (rb > ra * (1.0 + 1e-13)) return false;
  return a.imag() > b.imag();  // of a conjugate pair, the one with Im >= 0
}

Dominant SdmKernel::dense(const PeriodMap& pm, bool want_vector) const {
  const int d = pm.dim;
  MatrixXd Phi(d, d);
  VectorXd e = VectorXd::Zero(d);
  std::vector<double> work(static_cast<std::size_t>(2 * pm.n2 + pm.nr + 1));
  for (int j = 0; j < d; ++j) {
    e.setZero();
    e(j) = 1.0;
    apply(pm, Wx_, e.data(), Phi.col(j).data(), work.data());
  }
  if (!Phi.allFinite()) throw MapOverflow{};
  Eigen::EigenSolver<MatrixXd> es(Phi, want_vector);
  if (es.info() != Eigen::Success) throw NumericalError("sdm: eigen-decomposition of the period map failed");
  Dominant out;
  Index best = 0;
  for (Index i = 1; i < d; ++i)
    if (better(es.eigenvalues()(i), es.eigenvalues()(best))) best = i;
  out.mu = es.eigenvalues()(best);
  half_plane_radii(es.eigenvalues(), out);
  if (want_vector) out.vec = es.eigenvectors().col(best);
  return out;
}

void SdmKernel::half_plane_radii(const Eigen::VectorXcd& eigs, Dominant& out) {
  out.rho_left = out.rho_right = 0.0;
  for (Index i = 0; i < eigs.size(); ++i) {
    const bool left = eigs(i).real() < 0.0;
    double& r = left ? out.rho_left : out.rho_right;
    if (std::abs(eigs(i)) > r) {
      r = std::abs(eigs(i));
      (left ? out.mu_left : out.mu_right) = eigs(i).imag() >= 0.0 ? eigs(i) : std::conj(eigs(i));
    }
  }
}

// Dominant eigenvalue of a small Hessenberg matrix and its unit eigenvector.
// The eigenvalues by the Francis QR iteration on Hk as it is (already
// Hessenberg: no reduction; hessenberg_eigen.hpp), the eigenvector by inverse iteration with
// Gaussian elimination that pivots between neighbouring rows only (the
// partial pivoting of a Hessenberg matrix): O(k²) per solve.
void SdmKernel::hessenberg_dominant(const MatrixXd& Hk, Cplx& theta, Eigen::VectorXcd& y,
                                    std::vector<std::pair<double, Index>>* order, Eigen::VectorXcd* eigs) {
  if (!Hk.allFinite()) throw MapOverflow{};
  const Index kk = Hk.rows();
  Eigen::VectorXcd ev(kk);
  detail::hessenberg_eigenvalues(Hk, ev);
  Index best = 0;
  for (Index i = 1; i < kk; ++i)
    if (better(ev(i), ev(best))) best = i;
  theta = ev(best);
  // Eigenvector by inverse iteration with a slightly perturbed shift.
  const Cplx shift = theta * (1.0 + 1e-12) + Cplx(0.0, 1e-14 * std::abs(theta));
  Eigen::MatrixXcd L = Hk.cast<Cplx>();
  L.diagonal().array() -= shift;
  std::vector<char> swapped(static_cast<std::size_t>(kk), 0);
  std::vector<Cplx> mult(static_cast<std::size_t>(kk), Cplx(0.0, 0.0));
  for (Index j = 0; j + 1 < kk; ++j) {  // eliminate L(j + 1, j)
    const auto ju = static_cast<std::size_t>(j);
    if (std::norm(L(j + 1, j)) > std::norm(L(j, j))) {  // |·|² (no hypot): only the pivot's choice
      L.row(j).tail(kk - j).swap(L.row(j + 1).tail(kk - j));
      swapped[ju] = 1;
    }
    if (L(j, j) == Cplx(0.0, 0.0)) continue;  // L(j + 1, j) is 0 too
    mult[ju] = L(j + 1, j) / L(j, j);
    L.row(j + 1).tail(kk - j - 1) -= mult[ju] * L.row(j).tail(kk - j - 1);
  }
  const double tiny = 1e-300 + 1e-16 * (Hk.cwiseAbs().maxCoeff() + std::abs(shift));
  for (Index j = 0; j < kk; ++j)
    if (std::abs(L(j, j)) < tiny) L(j, j) = tiny;  // an exact eigenvalue: any large multiple of the vector
  y = Eigen::VectorXcd::Ones(kk);
  for (int it = 0; it < 3; ++it) {
    for (Index j = 0; j + 1 < kk; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      if (swapped[ju]) std::swap(y(j), y(j + 1));
      y(j + 1) -= mult[ju] * y(j);
    }
    y = L.triangularView<Eigen::Upper>().solve(y);
    y /= y.norm();
  }
  if (order) {
    order->clear();
    for (Index i = 0; i < kk; ++i) order->emplace_back(-std::abs(ev(i)), i);
    std::sort(order->begin(), order->end());
  }
  if (eigs) *eigs = ev;
}

namespace {

// V y for a real basis V and complex coefficients y, as two real products
// (the same values as V.cast<Cplx>() * y, without complex arithmetic on the
// zero imaginary parts of V).
Eigen::VectorXcd basis_times(const Eigen::Ref<const MatrixXd>& V, const Eigen::VectorXcd& y) {
  Eigen::VectorXcd out(V.rows());
  out.real().noalias() = V * y.real();
  out.imag().noalias() = V * y.imag();
  return out;
}

}  // namespace

// Restarted Arnoldi on Φ applied as the sequence of step maps. In `decide`
// mode it stops as soon as the residual of the dominant Ritz value cannot
// change the verdict ρ < 1 or ρ >= 1 (bracketing needs no more).
Dominant SdmKernel::arnoldi(const PeriodMap& pm, bool want_vector, bool decide) const {
  const int d = pm.dim;
  const int k = std::min(d, o_.krylov_dimension);
  ArnoldiWorkspace& ws = arnoldi_work_;
  ws.size_for(d, k, static_cast<std::size_t>(2 * pm.n2 + pm.nr + 1));
  MatrixXd& V = ws.V;
  MatrixXd& H = ws.H;  // zeroed at each (re)start below
  VectorXd &v = ws.v, &w = ws.w, &h = ws.h, &h2 = ws.h2;
  std::vector<double>& work = ws.work;
  // Deterministic, generic start vector.
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < d; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    v(i) = 0.5 + static_cast<double>(state >> 11) * 0x1.0p-53;
  }
  Dominant out;
  std::vector<std::pair<double, Index>> order;
  Eigen::VectorXcd eigs;
  for (int restart = 0; restart <= kArnoldiMaxRestarts; ++restart) {
    V.col(0) = v / v.norm();
    H.setZero();
    int kk = k;
    double beta = 0.0;
    for (int j = 0; j < k; ++j) {
      apply(pm, Wx_, V.col(j).data(), w.data(), work.data());
      const double wnorm0 = w.norm();
      // Classical Gram–Schmidt, repeated when it cancels badly (DGKS).
      auto Vj = V.leftCols(j + 1);
      h.head(j + 1).noalias() = Vj.transpose() * w;
      w.noalias() -= Vj * h.head(j + 1);
      beta = w.norm();
      if (beta < 0.7 * wnorm0) {
        h2.head(j + 1).noalias() = Vj.transpose() * w;
        w.noalias() -= Vj * h2.head(j + 1);
        h.head(j + 1) += h2.head(j + 1);
        beta = w.norm();
      }
      H.col(j).head(j + 1) = h.head(j + 1);
      H(j + 1, j) = beta;
      if (beta <= 1e-13 * std::max(wnorm0, 1e-300)) {  // invariant subspace: exact
        kk = j + 1;
        beta = 0.0;
        break;
      }
      V.col(j + 1) = w / beta;
      if (j + 1 >= (decide ? 8 : 14) && j + 1 < k && (j + 1) % 6 == 2) {
        // Early verdict (decide) or early convergence of the dominant Ritz
        // pair: a short Krylov space is often enough (the Ritz vector, when
        // asked for, has the same residual as a restarted one's).
        Cplx th;
        Eigen::VectorXcd yy;
        hessenberg_dominant(H.topLeftCorner(j + 1, j + 1), th, yy, nullptr, &eigs);
        const double res = beta * std::abs(yy(j));
        if ((decide && std::abs(std::abs(th) - 1.0) > kDecideFactor * res) || res <= kArnoldiTol * std::abs(th)) {
          out.mu = th;
          half_plane_radii(eigs, out);
          if (want_vector) out.vec = basis_times(V.leftCols(j + 1), yy);
          return out;
        }
      }
    }
    Cplx theta;
    Eigen::VectorXcd y;
    hessenberg_dominant(H.topLeftCorner(kk, kk), theta, y, &order, &eigs);
    const double resid = beta * std::abs(y(kk - 1));
    const double mag = std::max(std::abs(theta), 1e-300);
    out.mu = theta;
    half_plane_radii(eigs, out);
    const bool converged = resid <= kArnoldiTol * mag;
    const bool decided = decide && std::abs(mag - 1.0) > kDecideFactor * resid;
    if (converged || decided || restart == kArnoldiMaxRestarts) {
      out.converged = converged || decided;
      if (want_vector) out.vec = basis_times(V.leftCols(kk), y);
      return out;
    }
    // Restart with the real span of the dominant Ritz vector, plus a little
    // of the next Ritz vectors so that a near-tie is not lost.
    const Eigen::VectorXcd yc = basis_times(V.leftCols(kk), y);
    v = yc.real() + yc.imag();
    for (std::size_t t = 1; t < std::min<std::size_t>(order.size(), 5); ++t) {
      const Cplx ti = eigs(order[t].second);
      const Eigen::MatrixXcd T = H.topLeftCorner(kk, kk).cast<Cplx>() -
                                 (ti * (1.0 + 1e-12) + Cplx(0.0, 1e-14 * std::abs(ti))) *
                                     Eigen::MatrixXcd::Identity(kk, kk);
      Eigen::VectorXcd yi = T.partialPivLu().solve(Eigen::VectorXcd::Ones(kk));
      yi /= yi.norm();
      const Eigen::VectorXcd zi = basis_times(V.leftCols(kk), yi);
      v += 0.1 * (zi.real() + zi.imag());
    }
    if (!(v.norm() > 0.0)) v = V.col(0);
  }
  return out;
}

}  // namespace chatter::sdm_detail
