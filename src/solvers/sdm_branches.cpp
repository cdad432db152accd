// The branch roots of turning (SdmKernel::branches): the Floquet
// multipliers of a constant step map from a scalar equation per branch
// instead of an eigenproblem of size m (docs/sdm.md "Turning at low speed").
// Part of the `sdm` solver (sdm_internal.hpp).
//
// Every step of turning is the same map D and Φ = D^m (τ = m h). With the
// history x_i = ν^i v (ν an eigenvalue of D, μ = ν^m a multiplier of Φ):
//
// First-order steps, x_{i+1} = P x_i + R0 z_{i−m} + R1 z_{i−m+1}, z = W x
// (one delayed quantity): ν^m = g(ν), g(ν) = W (νI − P)⁻¹ (R0 + R1 ν)
// (matrix determinant lemma).
//
// Gauss collocation with s nodes (sdm_collocation.cpp), per unit depth the
// weights E = e^{Ah}, WxEc, K = WxK, VB of the step and the depth a: the
// node values Z of step i solve (I + aK) Z = WxEc x_i + aK ζ, ζ = Z of step
// i − m = ν^{−m} Z, and x_{i+1} = E x_i + a VB (ζ − Z). With c = a(ν^{−m} − 1)
// that is (I − cK) Z = WxEc v, (νI − E) v = c VB Z, so
//     det(I − c M(ν)) = 0,   M(ν) = K + WxEc (νI − E)⁻¹ VB   (s × s),
// and for each eigenvalue λ_j(ν) of M: ν^m = g_j(ν) = aλ_j / (1 + aλ_j), s
// sheets of the first-order g. The root on sheet j has Re sτ = ln|g_j|, so
// the sheet of largest |g_j| holds the branch's most unstable root (the
// physical one, λ ≈ the structure's node response; the others come from the
// interpolation and are deeply damped).
//
// Writing ν = e^{sh}, each branch k = 0 … m/2 of
//     s τ = Ln g(e^{sh}) + 2πjk
// has one root while the map s ↦ (Ln g(e^{sh}) + 2πjk)/τ contracts, which
// holds near the unit circle when τ min ζω is large (|d Ln g/ds| is about
// 1/|s − λ| for a mode pole λ); the roots it misses lie within ~1/τ of the
// poles, |μ| ≈ e^{−ζωτ}, never dominant there. Newton on each branch from
// s = 2πjk/τ: cost O(m) per map instead of an eigenproblem of size m whose
// multipliers crowd the unit circle. The multiplier is exact for the
// discretised map; μ = e^{sτ}, and Im s is the chatter frequency (rad/s).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace chatter::sdm_detail {
namespace {

// Newton's iteration budget and tolerance (on s τ, rad).
constexpr int kBranchIterations = 50;
constexpr double kBranchTolerance = 1e-11;
// A branch whose Newton iterates stay below e^this times the dominant
// multiplier's modulus cannot be dominant.
constexpr double kNegligibleLog = -3.0;

using MatrixXcd = Eigen::MatrixXcd;
using VectorXcd = Eigen::VectorXcd;

// The eigen-decomposition E = V diag(λ) V⁻¹ of a step's free map (P of the
// first order, e^{Ah} of collocation); false when E is not diagonalisable
// to round-off (the caller falls back to the eigen-solvers).
struct Diagonal {
  VectorXcd lam;
  MatrixXcd V;
  Eigen::PartialPivLU<MatrixXcd> lu;
};
bool diagonalise(const MatrixXd& E, Diagonal& d) {
  const Index n2 = E.rows();
  Eigen::ComplexEigenSolver<MatrixXcd> es(E.cast<Cplx>());
  if (es.info() != Eigen::Success) return false;
  d.V = es.eigenvectors();
  d.lam = es.eigenvalues();
  d.lu.compute(d.V);
  const MatrixXcd I = MatrixXcd::Identity(n2, n2);
  return (d.V * d.lu.solve(I) - I).norm() < 1e-8;
}

// g(ν) and g'(ν) of the first-order step map; false when g vanishes (no
// regeneration seen on this branch).
class FirstOrderSheet {
 public:
  FirstOrderSheet(const Diagonal& d, const MatrixXd& Wx, const StepMap& st)
      : lam_(d.lam),
        c_(Wx.row(0).cast<Cplx>() * d.V),
        d0_(d.lu.solve(st.R0.col(0).cast<Cplx>())),
        d1_(d.lu.solve(st.R1.col(0).cast<Cplx>())) {}
  bool operator()(Cplx nu, Cplx& G, Cplx& Gp) const {
    G = Gp = Cplx(0.0, 0.0);
    for (Index i = 0; i < lam_.size(); ++i) {
      const Cplx den = nu - lam_(i);
      G += c_(i) * (d0_(i) + d1_(i) * nu) / den;
      Gp -= c_(i) * (d0_(i) + d1_(i) * lam_(i)) / (den * den);
    }
    return G != Cplx(0.0, 0.0);
  }

 private:
  VectorXcd lam_;
  Eigen::RowVectorXcd c_;
  VectorXcd d0_, d1_;
};

// g_j(ν) = aλ_j/(1 + aλ_j) and its derivative on the sheet of largest |g_j|
// (collocation); false when that g vanishes or is not finite.
class CollocationSheet {
 public:
  CollocationSheet(const Diagonal& d, const Step& st, double depth)
      : lam_(d.lam),
        K_(st.WxK.cast<Cplx>()),
        C_(st.WxEc.cast<Cplx>() * d.V),
        D_(d.lu.solve(st.VB.cast<Cplx>())),
        a_(depth) {}
  bool operator()(Cplx nu, Cplx& G, Cplx& Gp) const {
    const Index s = K_.rows();
    NodeMatrix M = K_, Mp = NodeMatrix::Zero(s, s);
    for (Index i = 0; i < lam_.size(); ++i) {
      const Cplx r = 1.0 / (nu - lam_(i));
      M.noalias() += (r * C_.col(i)) * D_.row(i);
      Mp.noalias() -= (r * r * C_.col(i)) * D_.row(i);
    }
    Eigen::ComplexEigenSolver<NodeMatrix> es(M);
    if (es.info() != Eigen::Success) return false;
    Index best = 0;
    double best_abs = -1.0;
    for (Index j = 0; j < s; ++j) {
      const Cplx al = a_ * es.eigenvalues()(j);
      const double g = std::abs(al / (1.0 + al));
      if (g > best_abs) {
        best_abs = g;
        best = j;
      }
    }
    const NodeMatrix& X = es.eigenvectors();
    const Eigen::PartialPivLU<NodeMatrix> lu(X);
    // dλ_j/dν = (X⁻¹ M' X)_jj (left eigenvectors: the rows of X⁻¹).
    const Cplx dlam = lu.solve(Mp * X.col(best))(best);
    const Cplx al = a_ * es.eigenvalues()(best);
    G = al / (1.0 + al);
    Gp = a_ * dlam / ((1.0 + al) * (1.0 + al));
    return G != Cplx(0.0, 0.0) && std::isfinite(std::abs(G)) && std::isfinite(std::abs(Gp));
  }

 private:
  using NodeMatrix = Eigen::Matrix<Cplx, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCollocationNodes, kMaxCollocationNodes>;
  VectorXcd lam_;
  NodeMatrix K_;
  MatrixXcd C_, D_;
  double a_;
};

// Newton on each branch k = 0 … m/2 of s τ = Ln g(e^{sh}) + 2πjk, g from
// `sheet` (FirstOrderSheet or CollocationSheet). False when a branch that
// did not converge could hold the dominant multiplier.
template <class Sheet>
bool branch_roots(const Sheet& sheet, double tau, int m, Dominant& out) {
  const double h = tau / m;
  const int kmax = m / 2;
  out = Dominant{};
  double best_re = -kInf;
  double worst_failed = -kInf;  // largest Re s τ at which a branch gave up
  Cplx best_s{0.0, 0.0};
  for (int k = 0; k <= kmax; ++k) {
    const Cplx twopik(0.0, kTwoPi * k);
    Cplx s = twopik / tau;
    bool ok = false;
    for (int it = 0; it < kBranchIterations; ++it) {
      const Cplx nu = std::exp(s * h);
      Cplx G, Gp;
      if (!sheet(nu, G, Gp)) break;
      const Cplx F = s * tau - std::log(G) - twopik;
      const Cplx dF = tau - h * nu * Gp / G;
      Cplx ds = F / dF;
      if (std::abs(ds) * tau > kPi) ds *= kPi / (std::abs(ds) * tau);  // stay near branch k
      s -= ds;
      if (std::abs(ds) * tau < kBranchTolerance) {
        ok = true;
        break;
      }
    }
    if (!ok) {
      // Far from the modes g can vanish (Ln g → −∞) and Newton wanders at
      // deeply damped values. Decided after all branches are known.
      worst_failed = std::max(worst_failed, s.real() * tau);
      continue;
    }
    const Cplx mu = std::exp(s * tau);
    const Cplx mu_up = mu.imag() >= 0.0 ? mu : std::conj(mu);
    const bool left = mu.real() < 0.0;
    double& r = left ? out.rho_left : out.rho_right;
    if (std::abs(mu) > r) {
      r = std::abs(mu);
      (left ? out.mu_left : out.mu_right) = mu_up;
    }
    if (s.real() > best_re) {
      best_re = s.real();
      best_s = s;
    }
  }
  // A branch that did not converge cannot hold the dominant multiplier if
  // its iterates stayed kNegligibleLog below it; else let the eigen-solvers decide.
  if (worst_failed > best_re * tau + kNegligibleLog || best_re == -kInf) return false;
  out.mu = std::exp(best_s * tau);
  if (out.mu.imag() < 0.0) out.mu = std::conj(out.mu);
  out.branch_s = best_s;
  return true;
}

}  // namespace

// Returns false (the caller falls back to the eigen-solvers) if the free
// step map cannot be diagonalised or a branch does not converge.
bool SdmKernel::branches(const PeriodMap& pm, Dominant& out) const {
  Diagonal d;
  if (pm.path == MapPath::kToothCollocation) {
    if (!pm.node_step || !diagonalise(pm.node_step->Eh, d)) return false;
    return branch_roots(CollocationSheet(d, *pm.node_step, pm.depth), pm.tau, pm.m, out);
  }
  if (!diagonalise(pm.steps[0].P, d)) return false;
  return branch_roots(FirstOrderSheet(d, Wx_, pm.steps[0]), pm.tau, pm.m, out);
}

}  // namespace chatter::sdm_detail
