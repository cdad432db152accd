// The step maps of one period of the semi-discretised delay equation at one
// depth, and Φ y: the monodromy applied as the sequence of step maps, never
// formed (docs/sdm.md). Part of the `sdm` solver (sdm_internal.hpp).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <unsupported/Eigen/MatrixFunctions>

namespace chatter::sdm_detail {
namespace {

// A delayed time within this fraction of a step from a sample is that sample
// (the interpolation weight would only carry round-off).
constexpr double kSnap = 1e-9;

// Smallest scale of the input blocks of a real-cutter step exponential: the
// blocks come out about this small, with relative round-off ~1e-16/this.
constexpr double kMinBlockScale = 1e-6;

// exp of a small matrix in a fixed-size / stack-allocated type (no heap
// traffic, unrolled products in the Padé evaluation and the squaring).
template <int N>
MatrixXd fixed_exp(const MatrixXd& m) {
  const Eigen::Matrix<double, N, N> r = Eigen::Matrix<double, N, N>(m).exp();
  return r;
}
void small_exp(const MatrixXd& m, MatrixXd& out) {
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
bool augmented_exp(const MatrixXd& X, const MatrixXd& Y, double s, MatrixXd& P, MatrixXd& G1, MatrixXd& G2) {
  return augmented_exp_fixed(X, Y, s, [&](const auto& p, const auto& g1, const auto& g2) {
    P = p;
    G1 = g1;
    G2 = g2;
  });
}

// One straight-teeth step map from X = (A − Bt Wx) h and Y = Bt h: P =
// e^X, R1 = ∫₀¹ e^{X(1−u)} Y u du, R0 = ∫₀¹ e^{X(1−u)} Y du − R1 (the blocks
// of the exponential of [[X, Y, 0], [0, 0, I], [0, 0, 0]]); false for the
// sizes augmented_exp_fixed does not have.
template <class XM, class YM>
bool step_exp_by_blocks(const XM& X, const YM& Y, StepMap& sm) {
  return augmented_exp_fixed(X, Y, 1.0, [&](const auto& p, const auto& g1, const auto& g2) {
    sm.P = p;
    sm.R1 = g2;
    sm.R0 = g1 - g2;
  });
}

}  // namespace

void SdmKernel::build_map(const Grid& g, double depth, PeriodMap& pm) const {
  if (g.cutter) return build_cutter(g, depth, pm);
  const int n2 = static_cast<int>(A_.rows());
  const int nr = static_cast<int>(Wx_.rows());
  pm.n2 = n2;
  pm.nr = nr;
  pm.m = g.m;
  pm.nodes = g.nodes;
  pm.cutter = false;
  pm.constant = g.constant;
  pm.free_flight = g.free_time > 0.0;
  // Stored samples: s per cutting step with collocation (none for free
  // flight); else one per step start, and one at the free flight's start.
  pm.nz = g.nodes > 0 ? g.m * g.nodes : pm.free_flight ? g.m + 1 : g.m;
  pm.dim = n2 + pm.nz * nr;
  pm.E = pm.free_flight ? &g.E_free : nullptr;
  pm.tau = g.tau;
  pm.branch_roots = g.branch_roots && nr == 1;
  pm.steps.resize(g.steps.size());
  if (g.nodes > 0) return build_collocation(g, depth, pm);
  if (n2 + 2 * nr <= kSmallAugmented)
    build_steps<SmallMatrix>(g, depth, pm);  // no heap traffic: most models
  else
    build_steps<MatrixXd>(g, depth, pm);
}

// The step map of one step is read off the exponential of the augmented
// matrix [[(A − Bt Wx) h, Bt h, 0], [0, 0, I], [0, 0, 0]], Bt = a B Ĥ U
// (the first-order interpolation of the delayed term). M is the matrix
// type of the augmented system: a stack-allocated one for small models.
template <class M>
void SdmKernel::build_steps(const Grid& g, double depth, PeriodMap& pm) const {
  const int n2 = pm.n2, nr = pm.nr, na = n2 + 2 * nr;
  M aug = M::Zero(na, na);
  M Bt(n2, nr);
  for (std::size_t i = 0; i < g.steps.size(); ++i) {
    const Step& s = g.steps[i];
    if (g.nose) {  // a nose radius: a H(a) = b d nᵀ and b n nᵀ at this depth
      Bt.noalias() = B_ * g.nose->turning_force_matrix(depth) * U_;
      if (g.nose_Sv.size() > 0)
        aug.topLeftCorner(n2, n2).noalias() =
            (A_ - Bt * Wx_ - g.nose_cbar * B_ * g.nose->turning_damping_matrix(depth) * g.nose_Sv) * s.h;
      else
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_) * s.h;
    } else {
      Bt.noalias() = (depth * s.BHU);  // 2n × n_r
      if (g.damping.size() > 0)  // process damping (turning): − a c̄ B D Sv
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_ - depth * g.damping) * s.h;
      else
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_) * s.h;
    }
    StepMap& sm = pm.steps[i];
    // The common sizes (up to four modes in the plane, two on a line):
    // the exponential by blocks (augmented_exp: Padé on the block structure,
    // no (2n + 2 n_r)² work on the zero blocks); else the dense one.
    if (step_exp_by_blocks(aug.topLeftCorner(n2, n2), Bt * s.h, sm)) continue;
    aug.block(0, n2, n2, nr) = Bt * s.h;
    aug.block(n2, n2 + nr, nr, nr).setIdentity();
    const M E = aug.exp();
    sm.P = E.topLeftCorner(n2, n2);
    sm.R1 = E.block(0, n2 + nr, n2, nr);
    sm.R0 = E.block(0, n2, n2, nr) - sm.R1;
  }
}

// out = Φ y (both of length pm.dim, distinct). work: >= 2 n2 + nr doubles.
// Dispatches to fixed-size loops for the common small models.
void SdmKernel::apply(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work) {
  if (pm.cutter)
    return pm.nodes > 0 ? apply_cutter_collocation(pm, y, out, nullptr) : apply_cutter(pm, Wx, y, out, nullptr);
  if (pm.nodes > 0) return apply_collocation(pm, y, out, work);
  if (pm.n2 == 2 && pm.nr == 1) return apply_n<2, 1>(pm, Wx, y, out, work);
  if (pm.n2 == 4 && pm.nr == 1) return apply_n<4, 1>(pm, Wx, y, out, work);
  if (pm.n2 == 4 && pm.nr == 2) return apply_n<4, 2>(pm, Wx, y, out, work);
  return apply_n<0, 0>(pm, Wx, y, out, work);
}

// N2, NR: compile-time sizes, or 0 for run-time ones.
template <int N2, int NR>
void SdmKernel::apply_n(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work) {
  const int n2 = N2 > 0 ? N2 : pm.n2;
  const int nr = NR > 0 ? NR : pm.nr;
  double* x = work;
  double* xn = work + n2;
  double* zw = work + 2 * n2;
  const double* W = Wx.data();
  auto project = [&](const double* xv, double* z) {  // z = Wx x
    for (int r = 0; r < nr; ++r) {
      double acc = 0.0;
      for (int c = 0; c < n2; ++c) acc += W[r + c * nr] * xv[c];
      z[r] = acc;
    }
  };
  std::copy(y, y + n2, x);
  project(x, zw);
  for (int i = 0; i < pm.m; ++i) {
    const StepMap& s = pm.constant ? pm.steps[0] : pm.steps[static_cast<std::size_t>(i)];
    project(x, out + n2 + i * nr);
    const double* z0 = y + n2 + i * nr;
    const double* z1 = (i + 1 < pm.nz) ? y + n2 + (i + 1) * nr : zw;
    const double* P = s.P.data();
    const double* R0 = s.R0.data();
    const double* R1 = s.R1.data();
    for (int row = 0; row < n2; ++row) {
      double acc = 0.0;
      for (int c = 0; c < n2; ++c) acc += P[row + c * n2] * x[c];
      for (int r = 0; r < nr; ++r) acc += R0[row + r * n2] * z0[r] + R1[row + r * n2] * z1[r];
      xn[row] = acc;
    }
    std::swap(x, xn);
  }
  if (pm.free_flight) {
    project(x, out + n2 + pm.m * nr);
    free_flight_step(*pm.E, n2, x, xn);
    std::swap(x, xn);
  }
  std::copy(x, x + n2, out);
}

// The real-cutter map at depth a (docs/sdm.md "Real cutters"). Step
// boundaries: 0, T and every engagement event (tooth tip or top of the cut
// entering or leaving the arc) in [0, T); between two events the cut is
// either free (one exact step exp(A h)) or cut in ceil(d / h_target) equal
// steps. On a cutting step, per distinct delay τ_k (a tooth, or a slice of
// a tooth with a variable helix), the exact step average of its share of H
// gives Bt_k = B H̄_k U, and
//   ẋ = (A − Σ Bt_k Wx − c̄ B D̄ Sv) x + Σ Bt_k z(t − τ_k),
// with z(t − τ_k) linear over the step between its values at the step ends,
// each interpolated linearly between stored samples. R0_k, R1_k come from
// one augmented exponential: [[Ãh, Bt_1 h … Bt_d h, 0], [0, 0, I], [0, 0, 0]]
// when d n_r <= 2 (force inputs), else Q0, Q1 from [[Ãh, B h, 0], [0, 0,
// I], [0, 0, 0]] and R0_k = Q0 H̄_k U, R1_k = Q1 H̄_k U (size 2n + 4,
// independent of the number of delays: B has 2 columns, the force).
void SdmKernel::build_cutter(const Grid& g, double a, PeriodMap& pm) const {
  if (g.nodes > 0) return build_cutter_collocation(g, a, pm);
  if (g.cutter_grid) return cutter_map(g, *g.cutter_grid, a, a / g.cutter_grid->depth, pm, &g.cutter_grid);
  const CutterGrid cg = g.ssv ? ssv_cutter_grid(*p_, g, o_.axial_slices, a) : cutter_grid(*p_, g, o_.axial_slices, a);
  cutter_map(g, cg, a, 1.0, pm, nullptr);
}

// Second pass: the step maps from the grid, its integrals times `scale`.
// `shared`: the grid is shared by every depth of the speed, so the
// depth-independent parts are kept in pm.cm.cache (else nullptr).
void SdmKernel::cutter_map(const Grid& g, const CutterGrid& cg, double a, double scale, PeriodMap& pm,
                           const std::shared_ptr<const CutterGrid>* shared) const {
  const Process& p = *p_;
  const int n2 = static_cast<int>(A_.rows()), nr = static_cast<int>(Wx_.rows());
  const double T = g.tau;
  pm.n2 = n2;
  pm.nr = nr;
  pm.tau = T;
  pm.cutter = true;
  pm.nodes = 0;
  pm.constant = false;
  pm.free_flight = false;
  pm.branch_roots = false;
  pm.E = nullptr;
  pm.steps.clear();
  CutterMap& cm = pm.cm;
  cm.t = cg.t;
  const int M = static_cast<int>(cg.h.size());
  cm.steps.resize(static_cast<std::size_t>(M));
  pm.m = M;
  const int ng = static_cast<int>(cg.gtau.size());
  CutterCache& cache = cm.cache;
  if (shared && cache.grid != *shared) {
    cache.grid = *shared;
    cache.free_P.assign(static_cast<std::size_t>(M), MatrixXd());
    cache.located.assign(static_cast<std::size_t>(M) * static_cast<std::size_t>(ng), 0);
    cache.where.assign(static_cast<std::size_t>(M) * static_cast<std::size_t>(ng), Located{});
  }
  const double cbar = p.process_damping_per_depth(g.rpm);
  const double kscale = cg.force_scale_n_per_m2;
  int gmin = 0;
  auto locate = [&](double s, int& gi, double& w) {  // z(s) ≈ (1 − w) z_gi + w z_{gi+1}
    const double per = std::floor(s / T);
    const double loc = s - per * T;
    int k = static_cast<int>(std::upper_bound(cm.t.begin(), cm.t.end(), loc) - cm.t.begin()) - 1;
    k = std::clamp(k, 0, M - 1);
    int pr = static_cast<int>(per);
    const auto ku = static_cast<std::size_t>(k);
    w = (loc - cm.t[ku]) / (cm.t[ku + 1] - cm.t[ku]);
    if (w < kSnap) {
      w = 0.0;
    } else if (w > 1.0 - kSnap) {
      w = 0.0;
      if (++k == M) {
        k = 0;
        ++pr;
      }
    }
    gi = pr * M + k;
  };
  std::vector<MatrixXd>&Bt = cm.Bt, &R0 = cm.R0, &R1 = cm.R1, &HU = cm.HU;
  std::vector<int>& gid = cm.gid;
  MatrixXd &At = cm.At, &aug = cm.aug, &E = cm.E, &Q0 = cm.Q0, &Q1 = cm.Q1, &Xh = cm.Xh, &Yh = cm.Yh, &G1 = cm.G1,
           &G2 = cm.G2;
  int nd = 0;  // delay groups cutting in the current step: Bt, HU, gid [0, nd)
  for (int i = 0; i < M; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    CutterStep& st = cm.steps[iu];
    const double h = cg.h[iu];
    st.h = h;
    st.free = cg.free[iu] != 0;
    st.n_terms = 0;
    if (st.free) {
      if (shared && cache.free_P[iu].size() > 0) {
        st.P = cache.free_P[iu];
        continue;
      }
      const MatrixXd Ah = A_ * h;
      st.P = n2 == 2 ? fixed_exp<2>(Ah) : n2 == 4 ? fixed_exp<4>(Ah) : MatrixXd(Ah.exp());
      if (shared) cache.free_P[iu] = st.P;
      continue;
    }
    // A cutting step equal to the one before (the equal steps of turning
    // with speed variation: same length, same integrals) has the same P, R0
    // and R1; only where its delayed samples fall differs.
    bool repeat = i > 0 && !cm.forcing && !cg.free[iu - 1] && cg.h[iu - 1] == h && cg.D[iu - 1] == cg.D[iu];
    for (int k = 0; k < ng && repeat; ++k) {
      const auto kk = static_cast<std::size_t>(k), ngu = static_cast<std::size_t>(ng);
      repeat = cg.F[(iu - 1) * ngu + kk] == cg.F[iu * ngu + kk];
    }
    if (repeat) {
      st.P = cm.steps[iu - 1].P;
    } else {
      nd = 0;
      At = A_;
      for (int k = 0; k < ng; ++k) {
        const Eigen::Matrix2d F = cg.F[iu * static_cast<std::size_t>(ng) + static_cast<std::size_t>(k)] * scale;
        if (F.norm() <= kFreeForce * kscale * a * h) continue;
        const auto ku = static_cast<std::size_t>(nd);
        if (ku == HU.size()) {
          HU.emplace_back();
          Bt.emplace_back();
          gid.push_back(0);
        }
        // Turning (SSV): H = ĥ nᵀ and nᵀ S = U W, so H S = F n U W (n = e_x
        // for the orthogonal cut: F's first column).
        if (U_.rows() == 1 && p.orthogonal_turning())
          HU[ku].noalias() = (F.col(0) / h) * U_;
        else if (U_.rows() == 1)
          HU[ku].noalias() = ((F * p.chip_direction(a)) / h) * U_;
        else
          HU[ku].noalias() = (F / h) * U_;
        Bt[ku].noalias() = B_ * HU[ku];
        At.noalias() -= Bt[ku] * Wx_;
        gid[ku] = k;
        ++nd;
      }
      if (cbar > 0.0) At.noalias() -= (cbar * scale / h) * (B_ * cg.D[iu] * *Sv_);
      if (R0.size() < static_cast<std::size_t>(nd)) {
        R0.resize(static_cast<std::size_t>(nd));
        R1.resize(static_cast<std::size_t>(nd));
      }
      // Every Bt_k = B (H̄_k U): with more delay columns than force inputs,
      // augment with B once (R0_k = Q0 H̄_k U, R1_k = Q1 H̄_k U).
      const int nb = static_cast<int>(B_.cols());
      const bool stacked = nd * nr <= nb;
      const int na = stacked ? n2 + 2 * nd * nr : n2 + 2 * nb;
      // The input and identity blocks are scaled by sc ≈ ‖Ã h‖ (the blocks of
      // the exponential scale by sc and sc², undone below): the norm of the
      // augmented matrix is then that of Ã h, so the Padé degree and the
      // squarings stay low (with I of norm 1, every step took degree 9).
      Xh = At * h;
      const double sc = std::clamp(Xh.cwiseAbs().colwise().sum().maxCoeff(), kMinBlockScale, 1.0);
      const int nk = stacked ? nd * nr : nb;  // input columns
      Yh.resize(n2, nk);
      if (stacked) {
        for (int k = 0; k < nd; ++k) Yh.middleCols(k * nr, nr) = Bt[static_cast<std::size_t>(k)] * (h * sc);
      } else {
        Yh = B_ * (h * sc);
      }
      // The blocks of the exponential: by blocks for the common sizes (1 or
      // 2 modes, augmented_exp), else of the whole matrix, stack-allocated up
      // to kSmallAugmented (no heap traffic), else dynamic.
      if (!augmented_exp(Xh, Yh, sc, st.P, G1, G2)) {
        aug.setZero(na, na);
        aug.topLeftCorner(n2, n2) = Xh;
        aug.block(0, n2, n2, nk) = Yh;
        aug.block(n2, n2 + nk, nk, nk) = MatrixXd::Identity(nk, nk) * sc;
        if (na <= kSmallAugmented)
          small_exp(aug, E);
        else
          E = aug.exp();
        st.P = E.topLeftCorner(n2, n2);
        G1 = E.block(0, n2, n2, nk);
        G2 = E.block(0, n2 + nk, n2, nk);
      }
      if (stacked) {
        for (int k = 0; k < nd; ++k) {
          const auto ku = static_cast<std::size_t>(k);
          R1[ku] = G2.middleCols(k * nr, nr) / (sc * sc);
          R0[ku] = G1.middleCols(k * nr, nr) / sc - R1[ku];
        }
      } else {
        Q1 = G2 / (sc * sc);
        Q0 = G1 / sc - Q1;
        for (int k = 0; k < nd; ++k) {
          const auto ku = static_cast<std::size_t>(k);
          R0[ku].noalias() = Q0 * HU[ku];
          R1[ku].noalias() = Q1 * HU[ku];
        }
      }
      if (cm.forcing) {
        // The forced response (forced_periodic.cpp): G = ∫₀ʰ e^{Ã s} ds B, the
        // (1,2) block of exp([[Ã h, B h], [0, 0]]).
        MatrixXd Pf, Gf, Gf2;
        const MatrixXd Bh = B_ * h;
        if (!augmented_exp(Xh, Bh, 0.0, Pf, Gf, Gf2)) {
          MatrixXd augf = MatrixXd::Zero(n2 + nb, n2 + nb);
          augf.topLeftCorner(n2, n2) = Xh;
          augf.topRightCorner(n2, nb) = Bh;
          const MatrixXd Ef = augf.exp();
          Gf = Ef.topRightCorner(n2, nb);
        }
        st.G = Gf;
      }
    }
    auto add = [&](int gi, double w, const MatrixXd& C) {
      if (w == 0.0) return;
      gmin = std::min(gmin, gi);
      for (int j = 0; j < st.n_terms; ++j) {
        auto& [idx, mat] = st.terms[static_cast<std::size_t>(j)];
        if (idx == gi) {
          mat += w * C;
          return;
        }
      }
      if (static_cast<std::size_t>(st.n_terms) == st.terms.size()) st.terms.emplace_back();
      auto& slot = st.terms[static_cast<std::size_t>(st.n_terms++)];
      slot.first = gi;
      slot.second = w * C;
    };
    for (int k = 0; k < nd; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      const std::size_t key = iu * static_cast<std::size_t>(ng) + static_cast<std::size_t>(gid[ku]);
      Located l;
      if (shared && cache.located[key]) {
        l = cache.where[key];
      } else {
        const auto gk = static_cast<std::size_t>(gid[ku]);
        // The delay at the two ends of the step: constant, or (speed
        // variation) τ(t_i) and τ(t_{i+1}); the delayed value is linear over
        // the step between them, each interpolated linearly in the samples.
        const double tau0 = cg.tau_at.empty() ? cg.gtau[gk] : cg.tau_at[iu * static_cast<std::size_t>(ng) + gk];
        const double tau1 =
            cg.tau_at.empty() ? cg.gtau[gk] : cg.tau_at[(iu + 1) * static_cast<std::size_t>(ng) + gk];
        locate(cm.t[iu] - tau0, l.g0, l.w0);
        locate(cm.t[iu + 1] - tau1, l.g1, l.w1);
        if (shared) {
          cache.where[key] = l;
          cache.located[key] = 1;
        }
      }
      add(l.g0, 1.0 - l.w0, R0[ku]);
      add(l.g0 + 1, l.w0, R0[ku]);
      add(l.g1, 1.0 - l.w1, R1[ku]);
      add(l.g1 + 1, l.w1, R1[ku]);
    }
  }
  cm.L = -gmin;
  pm.nz = cm.L;
  pm.dim = n2 + cm.L * nr;
}

// out = Φ y on the real-cutter map; `record` (if given) receives x at t_0 … t_M.
void SdmKernel::apply_cutter(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out,
                             std::vector<double>* record, bool forcing) {
  if (pm.n2 == 4 && pm.nr == 2) return apply_cutter_n<4, 2>(pm, Wx, y, out, record, forcing);
  if (pm.n2 == 2 && pm.nr == 1) return apply_cutter_n<2, 1>(pm, Wx, y, out, record, forcing);
  return apply_cutter_n<0, 0>(pm, Wx, y, out, record, forcing);
}

// N2, NR: compile-time sizes, or 0 for run-time ones (same operations in
// the same order either way).
template <int N2, int NR>
void SdmKernel::apply_cutter_n(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out,
                               std::vector<double>* record, bool forcing) {
  const CutterMap& c = pm.cm;
  const int n2 = N2 > 0 ? N2 : pm.n2, nr = NR > 0 ? NR : pm.nr, L = c.L, M = static_cast<int>(c.steps.size());
  c.buf.resize(static_cast<std::size_t>((L + M + 1) * nr));
  // The state in local arrays for fixed sizes (kept in registers: no
  // aliasing with the maps or the samples), else in the map's workspace.
  constexpr int kLocal = N2 > 0 ? N2 : 1;
  double xl[kLocal], xnl[kLocal];
  if (N2 == 0) {
    c.x.resize(static_cast<std::size_t>(n2));
    c.xn.resize(static_cast<std::size_t>(n2));
  }
  double* x = N2 > 0 ? xl : c.x.data();
  double* xn = N2 > 0 ? xnl : c.xn.data();
  std::copy(y, y + n2, x);
  double* buf = c.buf.data();
  const double* W = Wx.data();
  auto project = [&](const double* xv, double* z) {  // z = Wx x
    for (int r = 0; r < nr; ++r) {
      double acc = 0.0;
      for (int col = 0; col < n2; ++col) acc += W[r + col * nr] * xv[col];
      z[r] = acc;
    }
  };
  for (int l = 1; l <= L; ++l) std::copy(y + n2 + (l - 1) * nr, y + n2 + l * nr, buf + (L - l) * nr);
  project(x, buf + L * nr);
  if (record) record->assign(x, x + n2);
  for (int i = 0; i < M; ++i) {
    const CutterStep& st = c.steps[static_cast<std::size_t>(i)];
    const double* P = st.P.data();
    // xn = P x by columns (each row still sums its products in column
    // order from 0: the same value as a row-wise dot product).
    for (int row = 0; row < n2; ++row) xn[row] = 0.0 + P[row] * x[0];
    for (int col = 1; col < n2; ++col)
      for (int row = 0; row < n2; ++row) xn[row] += P[row + col * n2] * x[col];
    for (int j = 0; j < st.n_terms; ++j) {
      const auto& [gi, C] = st.terms[static_cast<std::size_t>(j)];
      const double* z = buf + (gi + L) * nr;
      const double* Cd = C.data();
      for (int r = 0; r < nr; ++r)
        for (int row = 0; row < n2; ++row) xn[row] += Cd[row + r * n2] * z[r];
    }
    if (forcing && st.gF.size() == n2)  // the static chip force (forced response)
      for (int row = 0; row < n2; ++row) xn[row] += st.gF[row];
    std::copy(xn, xn + n2, x);
    project(x, buf + (L + i + 1) * nr);
    if (record) record->insert(record->end(), x, x + n2);
  }
  std::copy(x, x + n2, out);
  for (int l = 1; l <= L; ++l)
    std::copy(buf + (L + M - l) * nr, buf + (L + M - l + 1) * nr, out + n2 + (l - 1) * nr);
}

}  // namespace chatter::sdm_detail
