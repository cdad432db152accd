// The first-order step maps of the real-cutter grid of the `sdm` solver at
// one depth (SdmKernel::build_cutter, cutter_map) and Φ y on them
// (apply_cutter): per step the exact step averages of H per delay group, the
// delayed values interpolated linearly between stored samples (docs/sdm.md
// "Real cutters"). Collocation on the same grid: sdm_cutter_collocation.cpp.
// Part of the `sdm` solver (sdm_internal.hpp).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>

#include "sdm_step_exp.hpp"

namespace chatter::sdm_detail {
namespace {

// A delayed time within this fraction of a step from a sample is that sample
// (the interpolation weight would only carry round-off).
constexpr double kSnap = 1e-9;

// Smallest scale of the input blocks of a real-cutter step exponential: the
// blocks come out about this small, with relative round-off ~1e-16/this.
constexpr double kMinBlockScale = 1e-6;

}  // namespace

using namespace step_exp;

namespace {

// The stored sample a delayed time s (s, may be negative) falls on, over the
// step boundaries t of one period T (M = t.size() − 1 steps):
// z(s) ≈ (1 − w) z_gi + w z_{gi+1}, gi = period · M + step; a time within
// kSnap of a step of a sample is that sample (w = 0).
void locate_delayed(const std::vector<double>& t, double T, double s, int& gi, double& w) {
  const int M = static_cast<int>(t.size()) - 1;
  const GridTime at = grid_time(t, T, s);
  int k = at.k, pr = at.period;
  const auto ku = static_cast<std::size_t>(k);
  w = (at.loc - t[ku]) / (t[ku + 1] - t[ku]);
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
}

// Adds w · C to the step's term of sample gi (a new term if it has none);
// gmin follows the oldest sample read.
void add_term(CutterStep& st, int gi, double w, const MatrixXd& C, int& gmin) {
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
}

// The delay groups that cut in step iu (their force over the step above
// kFreeForce): for each, HU_k = H̄_k U and Bt_k = B HU_k (cm.HU, cm.Bt, its
// group in cm.gid), and Ã = A − Σ Bt_k Wx in cm.At; returns their number.
// `scale` multiplies the grid's integrals (its depth to a).
int cutting_groups(const CutterGrid& cg, std::size_t iu, double a, double scale, const Process& p, const MatrixXd& A_,
                   const MatrixXd& B_, const MatrixXd& Wx_, const MatrixXd& U_, CutterMap& cm) {
  const int ng = static_cast<int>(cg.gtau.size());
  const double h = cg.h[iu], kscale = cg.force_scale_n_per_m2;
  std::vector<MatrixXd>&Bt = cm.Bt, &HU = cm.HU;
  std::vector<int>& gid = cm.gid;
  MatrixXd& At = cm.At;
  int nd = 0;
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
  return nd;
}

// A cutting step's P, R0_k and R1_k from Ã = cm.At and the nd delay
// groups' Bt_k = B H̄_k U (cm.Bt, cm.HU), by one augmented exponential
// (docs/sdm.md "Real cutters"; the workspace is cm's).
void step_inputs(const MatrixXd& B_, int nd, int nr, double h, CutterMap& cm, CutterStep& st) {
  std::vector<MatrixXd>&Bt = cm.Bt, &R0 = cm.R0, &R1 = cm.R1, &HU = cm.HU;
  MatrixXd &At = cm.At, &aug = cm.aug, &E = cm.E, &Q0 = cm.Q0, &Q1 = cm.Q1, &Xh = cm.Xh, &Yh = cm.Yh, &G1 = cm.G1,
           &G2 = cm.G2;
  const int n2 = static_cast<int>(At.rows());
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
}

// The forced response's gain of a step (forced_periodic.cpp): G = ∫₀ʰ e^{Ã s} ds B,
// the (1,2) block of exp([[Ã h, B h], [0, 0]]) (Xh = Ã h).
MatrixXd forcing_gain(const MatrixXd& Xh, const MatrixXd& B, double h) {
  const int n2 = static_cast<int>(Xh.rows()), nb = static_cast<int>(B.cols());
  MatrixXd Pf, Gf, Gf2;
  const MatrixXd Bh = B * h;
  if (!augmented_exp(Xh, Bh, 0.0, Pf, Gf, Gf2)) {
    MatrixXd augf = MatrixXd::Zero(n2 + nb, n2 + nb);
    augf.topLeftCorner(n2, n2) = Xh;
    augf.topRightCorner(n2, nb) = Bh;
    const MatrixXd Ef = augf.exp();
    Gf = Ef.topRightCorner(n2, nb);
  }
  return Gf;
}

}  // namespace

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
  if (g.path == MapPath::kCutterCollocation) return build_cutter_collocation(g, a, pm);
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
  pm.path = MapPath::kCutterSteps;
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
  int gmin = 0;
  std::vector<MatrixXd>&R0 = cm.R0, &R1 = cm.R1;
  const std::vector<int>& gid = cm.gid;
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
      nd = cutting_groups(cg, iu, a, scale, p, A_, B_, Wx_, U_, cm);
      if (cbar > 0.0) cm.At.noalias() -= (cbar * scale / h) * (B_ * cg.D[iu] * *Sv_);
      if (R0.size() < static_cast<std::size_t>(nd)) {
        R0.resize(static_cast<std::size_t>(nd));
        R1.resize(static_cast<std::size_t>(nd));
      }
      step_inputs(B_, nd, nr, h, cm, st);
      if (cm.forcing) st.G = forcing_gain(cm.Xh, B_, h);
    }
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
        locate_delayed(cm.t, T, cm.t[iu] - tau0, l.g0, l.w0);
        locate_delayed(cm.t, T, cm.t[iu + 1] - tau1, l.g1, l.w1);
        if (shared) {
          cache.where[key] = l;
          cache.located[key] = 1;
        }
      }
      add_term(st, l.g0, 1.0 - l.w0, R0[ku], gmin);
      add_term(st, l.g0 + 1, l.w0, R0[ku], gmin);
      add_term(st, l.g1, 1.0 - l.w1, R1[ku], gmin);
      add_term(st, l.g1 + 1, l.w1, R1[ku], gmin);
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
