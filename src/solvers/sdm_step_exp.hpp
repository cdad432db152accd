// The matrix exponentials of the `sdm` step maps (internal to the solver):
// small exponentials in stack-allocated types, and the augmented step
// exponential [[X, Y, 0], [0, 0, s I], [0, 0, 0]] by blocks. Shared by the
// straight-teeth and turning step maps (sdm_map.cpp) and the first-order
// real-cutter map (sdm_cutter_map.cpp). Part of the `sdm` solver
// (sdm_internal.hpp).
#pragma once

#include <type_traits>

#include <unsupported/Eigen/MatrixFunctions>

#include "sdm_internal.hpp"

namespace chatter::sdm_detail::step_exp {

// exp of a small matrix in a fixed-size / stack-allocated type (no heap
// traffic, unrolled products in the Padé evaluation and the squaring).
template <int N>
inline MatrixXd fixed_exp(const MatrixXd& m) {
  const Eigen::Matrix<double, N, N> r = Eigen::Matrix<double, N, N>(m).exp();
  return r;
}
inline void small_exp(const MatrixXd& m, MatrixXd& out) {
  const SmallMatrix r = SmallMatrix(m).exp();
  out = r;
}

// exp of the augmented step matrix M = [[X, Y, 0], [0, 0, s I], [0, 0, 0]]
// (X: N × N, Y: N × K, I: K × K) by blocks. M and all its powers and Padé
// polynomials keep the form [[A, B, C], [0, α I, β I], [0, 0, α I]], so the
// diagonal Padé approximant r_m(M) = (V − U)⁻¹ (V + U) of Higham ("The
// scaling and squaring method for the matrix exponential revisited", SIAM J.
// Matrix Anal. Appl. 26, 2005) — the degree m ∈ {3, 5, 7, 9, 13} and the
// scaling 2^−q chosen by ‖M‖₁ as in Eigen's MatrixBase::exp, which the
// dense path applies to the whole matrix — needs products of N × N and
// N × K blocks and one N × N inverse instead of (N + 2K)² work. Same
// approximant, so the same blocks up to round-off. Returns e^X in P, the
// (1,2) block in G1 and the (1,3) block in G2.
template <int N, int K>
struct AugmentedBlocks {
  Eigen::Matrix<double, N, N> A;
  Eigen::Matrix<double, N, K> B, C;
  double al = 0.0, be = 0.0;

  static AugmentedBlocks identity() {
    AugmentedBlocks r;
    r.A.setIdentity();
    r.B.setZero();
    r.C.setZero();
    r.al = 1.0;
    r.be = 0.0;
    return r;
  }
  AugmentedBlocks operator*(const AugmentedBlocks& o) const {
    AugmentedBlocks r;
    r.A.noalias() = A * o.A;
    r.B.noalias() = A * o.B;
    r.B += B * o.al;
    r.C.noalias() = A * o.C;
    r.C += B * o.be + C * o.al;
    r.al = al * o.al;
    r.be = al * o.be + be * o.al;
    return r;
  }
  // this += c · o
  void add(double c, const AugmentedBlocks& o) {
    A += c * o.A;
    B += c * o.B;
    C += c * o.C;
    al += c * o.al;
    be += c * o.be;
  }
};

template <int N, int K>
void augmented_exp(const Eigen::Matrix<double, N, N>& X, const Eigen::Matrix<double, N, K>& Y, double s,
                   Eigen::Matrix<double, N, N>& P, Eigen::Matrix<double, N, K>& G1, Eigen::Matrix<double, N, K>& G2) {
  using Blk = AugmentedBlocks<N, K>;
  // Higham's θ_m for double (the largest ‖M‖₁ at which degree m is accurate
  // to unit round-off), and the Padé coefficients b_0 … b_m.
  static constexpr double kTheta[] = {1.495585217958292e-2, 2.539398330063230e-1, 9.504178996162932e-1,
                                      2.097847961257068e0, 5.371920351148152e0};
  static constexpr int kDegree[] = {3, 5, 7, 9, 13};
  static constexpr double b3[] = {120.0, 60.0, 12.0, 1.0};
  static constexpr double b5[] = {30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0};
  static constexpr double b7[] = {17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0};
  static constexpr double b9[] = {17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0,
                                  2162160.0,     110880.0,      3960.0,        90.0,        1.0};
  static constexpr double b13[] = {64764752532480000.0, 32382376266240000.0, 7771770303897600.0,
                                   1187353796428800.0,  129060195264000.0,   10559470521600.0,
                                   670442572800.0,      33522128640.0,       1323241920.0,
                                   40840800.0,          960960.0,            16380.0,
                                   182.0,               1.0};
  // ‖M‖₁: the largest column sum over the X, Y and s I columns.
  double norm = std::max(X.cwiseAbs().colwise().sum().maxCoeff(), std::abs(s));
  if (K > 0) norm = std::max(norm, Y.cwiseAbs().colwise().sum().maxCoeff());
  int pick = 4, q = 0;
  for (int i = 0; i < 4; ++i)
    if (norm < kTheta[i]) {
      pick = i;
      break;
    }
  Blk M;
  M.A = X;
  M.B = Y;
  M.C.setZero();
  M.al = 0.0;
  M.be = s;
  if (pick == 4) {
    std::frexp(norm / kTheta[4], &q);
    q = std::max(q, 0);
    const double f = std::ldexp(1.0, -q);
    M.A *= f;
    M.B *= f;
    M.be *= f;
  }
  const int m = kDegree[pick];
  const double* b = pick == 0 ? b3 : pick == 1 ? b5 : pick == 2 ? b7 : pick == 3 ? b9 : b13;
  // Even powers M², M⁴, …, M^(m−1); U = M Σ b_odd M^(k−1), V = Σ b_even M^k.
  const Blk M2 = M * M;
  Blk even = Blk::identity();
  Blk odd_sum = Blk::identity();
  odd_sum.A *= b[1];
  odd_sum.al *= b[1];
  Blk V = Blk::identity();
  V.A *= b[0];
  V.al *= b[0];
  for (int k = 2; k < m; k += 2) {
    even = even * M2;
    V.add(b[k], even);
    odd_sum.add(b[k + 1], even);
  }
  const Blk U = M * odd_sum;
  Blk num = V, den = V;
  num.add(1.0, U);
  den.add(-1.0, U);
  // (V − U) R = (V + U), block back-substitution.
  const Eigen::Matrix<double, N, N> Ainv = den.A.inverse();
  Blk R;
  R.al = num.al / den.al;
  R.be = (num.be - den.be * R.al) / den.al;
  R.A.noalias() = Ainv * num.A;
  R.B.noalias() = Ainv * (num.B - den.B * R.al);
  R.C.noalias() = Ainv * (num.C - den.B * R.be - den.C * R.al);
  for (int i = 0; i < q; ++i) R = R * R;
  P = R.A;
  G1 = R.B;
  G2 = R.C;
}

// The augmented step exponential for the common sizes (N = 2n: one to four
// modes with K = 2 delayed components (milling in the plane), one or two
// with K <= 2): runs augmented_exp<N, K> and hands its fixed-size blocks
// (P, G1, G2) to `out`; false for other sizes (then the dense exponential of
// the whole matrix is used).
template <class XM, class YM, class Out>
bool augmented_exp_fixed(const XM& X, const YM& Y, double s, Out&& out) {
  auto run = [&](auto n_tag, auto k_tag) {
    constexpr int N = decltype(n_tag)::value, K = decltype(k_tag)::value;
    Eigen::Matrix<double, N, N> p;
    Eigen::Matrix<double, N, K> g1, g2;
    augmented_exp<N, K>(X, Y, s, p, g1, g2);
    out(p, g1, g2);
    return true;
  };
  using I1 = std::integral_constant<int, 1>;
  using I2 = std::integral_constant<int, 2>;
  using I4 = std::integral_constant<int, 4>;
  using I6 = std::integral_constant<int, 6>;
  using I8 = std::integral_constant<int, 8>;
  if (X.rows() == 8 && Y.cols() == 2) return run(I8{}, I2{});
  if (X.rows() == 6 && Y.cols() == 2) return run(I6{}, I2{});
  if (X.rows() == 4 && Y.cols() == 2) return run(I4{}, I2{});
  if (X.rows() == 4 && Y.cols() == 1) return run(I4{}, I1{});
  if (X.rows() == 2 && Y.cols() == 2) return run(I2{}, I2{});
  if (X.rows() == 2 && Y.cols() == 1) return run(I2{}, I1{});
  return false;
}

// The real-cutter step: P = e^X and the blocks G1, G2 (scaled by s) into
// dynamic matrices.
inline bool augmented_exp(const MatrixXd& X, const MatrixXd& Y, double s, MatrixXd& P, MatrixXd& G1, MatrixXd& G2) {
  return augmented_exp_fixed(X, Y, s, [&](const auto& p, const auto& g1, const auto& g2) {
    P = p;
    G1 = g1;
    G2 = g2;
  });
}

}  // namespace chatter::sdm_detail::step_exp
