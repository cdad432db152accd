// Gauss collocation on the real-cutter grid of the `sdm` solver (helix,
// variable pitch or helix, a profile, two engaged arcs, process damping, the
// general path, spindle speed variation; docs/sdm.md
// "Collocation on real cutters", "Collocation with process damping",
// "Collocation in turning"): the step maps at one depth
// (SdmKernel::build_cutter_collocation) and Φ y
// (SdmKernel::apply_cutter_collocation). Part of the `sdm` solver
// (sdm_internal.hpp).
//
// The grid is the real-cutter grid (cutter_grid: boundaries at every
// engagement event, so H is smooth inside each step). On a cutting step
// [t_i, t_i + h] with Gauss nodes t_k = t_i + c_k h,
//   ẋ = A x + B Σ_g H_g(t) U (z(t − τ_g) − z(t)),
// H_g the directional matrix of delay group g integrated over its height at
// the instant (RegenerativeCut::force_rates), the cutting term replaced by
// its Lagrange polynomial through the nodes and the rest exact, as on the
// straight-teeth grid (sdm_collocation.cpp, whose step weights it shares):
//   (I + [G_jk Hs_k]) Z = WxEc x_i + G d,   x_{i+1} = e^{A h} x_i + VB d − VBH Z,
// G_jk = Wx W_jk B, Hs_k = Σ_g H_g(t_k) U, d_k = Σ_g H_g(t_k) U z(t_k − τ_g).
// With speed variation the delay of group g at each node is τ_g(t_k), the
// time over which the spindle turns the group's angle, and H is the cut's
// at the node's mean-speed time θ(t_k)/Ω₀ (NodeClock; turning: H = a ĥ nᵀ).
// The delayed z(t_k − τ_g) is read from the stored node samples: the sample
// itself when it falls on a node (one delay equal to the period: a uniform
// cutter), else the Lagrange polynomial through the 2s nodes of the step it
// falls in and of its nearer neighbour in the same span between events
// (degree 2s − 1, so the interpolation keeps the order 2s of the steps).
// References: Breda, Maset & Vermiglio, SIAM J. Numer. Anal. 50 (2012),
// 1456–1483 (piecewise collocation of the monodromy operator); Insperger &
// Stépán, Int. J. Numer. Meth. Eng. 61 (2004) 117–141 (exact free dynamics).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <Eigen/LU>
#include <unsupported/Eigen/MatrixFunctions>

#include "chatter/regenerative_cut.hpp"
#include "chatter/speed_variation.hpp"

namespace chatter::sdm_detail {
namespace {

// A delayed time within this fraction of a step from a node is that node
// (a uniform cutter: the delay is the period; the weight would only carry
// round-off).
constexpr double kNodeSnap = 1e-9;

// Where the node samples of one period lie, and how a delayed time is read
// from them (the stencil of docs/sdm.md "Collocation on real cutters").
class NodeLayout {
 public:
  NodeLayout(const CutterGrid& cg, const std::vector<double>& c, double T)
      : cg_(cg), c_(c), T_(T), M_(static_cast<int>(cg.h.size())), s_(static_cast<int>(c.size())) {
    first_.assign(static_cast<std::size_t>(M_), -1);
    for (int i = 0; i < M_; ++i)
      if (!cg.free[static_cast<std::size_t>(i)]) {
        first_[static_cast<std::size_t>(i)] = N_;
        N_ += s_;
      }
  }
  int nodes() const { return N_; }
  int first_node(int i) const { return first_[static_cast<std::size_t>(i)]; }

  // z(t) on the global time axis (t < 0: earlier periods) as Σ w z_sample,
  // from nodes whose sample index is below `before`. Returns the count.
  int stencil(double t, int before, int* sample, double* w) const {
    const GridTime at = grid_time(cg_.t, T_, t);
    const double loc = at.loc;
    int k = at.k, p = at.period;
    if (free(k)) {  // only at an event, to round-off: the nearer cutting neighbour
      const bool back = loc - cg_.t[static_cast<std::size_t>(k)] < cg_.t[static_cast<std::size_t>(k) + 1] - loc;
      step_by(back ? -1 : 1, k, p);
      if (free(k)) throw std::logic_error("sdm collocation: a delayed time falls in free flight");
    }
    const double h = cg_.h[static_cast<std::size_t>(k)];
    int n = 0;
    double times[2 * kMaxCollocationNodes];
    auto take = [&](int step, int period) {
      const double t0 = period * T_ + cg_.t[static_cast<std::size_t>(step)];
      for (int j = 0; j < s_; ++j) {
        sample[n] = period * N_ + first_node(step) + j;
        times[n++] = t0 + c_[static_cast<std::size_t>(j)] * cg_.h[static_cast<std::size_t>(step)];
      }
    };
    take(k, p);
    for (int j = 0; j < s_; ++j)
      if (std::abs(times[j] - t) <= kNodeSnap * h) {
        sample[0] = sample[j];
        w[0] = 1.0;
        return 1;
      }
    // The neighbour on the side of t, else the other one: same span, already computed.
    const bool before_mid = t - (p * T_ + cg_.t[static_cast<std::size_t>(k)]) < 0.5 * h;
    for (const int dir : {before_mid ? -1 : 1, before_mid ? 1 : -1}) {
      int kn = k, pn = p;
      step_by(dir, kn, pn);
      const int seg = cg_.segment.empty() ? 0 : cg_.segment[static_cast<std::size_t>(k)];
      const bool same_span = !free(kn) && pn == p && (cg_.segment.empty() || cg_.segment[static_cast<std::size_t>(kn)] == seg);
      if (!same_span || pn * N_ + first_node(kn) + s_ - 1 >= before) continue;
      take(kn, pn);
      break;
    }
    for (int a = 0; a < n; ++a) {  // Lagrange weights at t
      double l = 1.0;
      for (int b = 0; b < n; ++b)
        if (b != a) l *= (t - times[b]) / (times[a] - times[b]);
      w[a] = l;
    }
    return n;
  }

 private:
  bool free(int k) const { return cg_.free[static_cast<std::size_t>(k)] != 0; }
  void step_by(int dir, int& k, int& p) const {
    k += dir;
    if (k < 0) {
      k = M_ - 1;
      --p;
    } else if (k == M_) {
      k = 0;
      ++p;
    }
  }

  const CutterGrid& cg_;
  const std::vector<double>& c_;
  double T_;
  int M_, s_, N_ = 0;
  std::vector<int> first_;
};

}  // namespace

namespace {

// Spindle speed variation at the nodes (the grid's principal period and
// frequency ratio, as ssv_cutter_grid reads them at the step boundaries):
// the delay of a group whose mean-speed delay is τ₀, the time τ(t) over
// which the spindle turns Ω₀ τ₀ (ModulatedSpeed::delay), and the
// mean-speed time θ(t)/Ω₀ at which the cut (built at the mean speed) gives
// H. Without speed variation (`on` false) both are the identity.
struct NodeClock {
  NodeClock() = default;
  NodeClock(const Process& p, const Grid& g)
      : on(true), speed(g.rpm, {p.speed_variation().amplitude_ratio, g.ssv_period.frequency_ratio_used}) {}
  double delay(double t, double tau0) const { return on ? speed.delay(t, speed.mean_rad_s() * tau0) : tau0; }
  double mean_time(double t) const { return on ? speed.angle(t) / speed.mean_rad_s() : t; }
  bool on = false;
  ModulatedSpeed speed{1.0, {}};
};

// The step matrices of one cutting step from its weights and the node
// matrices Hs = [Σ_g H_g(t_k) U]_k (2 × s n_r): Qx, Qd, P, Rd. N2, SNR, ND:
// compile-time sizes of the common models (2n, s n_r, 2s), or Eigen::Dynamic
// (the same operations either way; fixed sizes keep the small products off
// the heap and out of the blocked kernels).
template <int N2, int SNR, int ND>
void step_matrices(const NodeWeights& w, const MatrixXd& Hs, int n2, int nr, int s, CollocationStep& st) {
  using Mss = Eigen::Matrix<double, SNR, SNR>;
  using Ms2 = Eigen::Matrix<double, SNR, N2>;
  using Msd = Eigen::Matrix<double, SNR, ND>;
  using M2s = Eigen::Matrix<double, N2, SNR>;
  using M2d = Eigen::Matrix<double, N2, ND>;
  using M22 = Eigen::Matrix<double, N2, N2>;
  const int snr = s * nr, nd = 2 * s;
  const Eigen::Map<const Ms2> WxEc(w.WxEc.data(), snr, n2);
  const Eigen::Map<const Msd> G(w.G.data(), snr, nd);
  const Eigen::Map<const M2d> VB(w.VB.data(), n2, nd);
  const Eigen::Map<const M22> Eh(w.Eh.data(), n2, n2);
  Mss M = Mss::Identity(snr, snr);
  for (int j = 0; j < s; ++j)
    for (int k = 0; k < s; ++k)
      M.block(j * nr, k * nr, nr, nr).noalias() += G.block(j * nr, 2 * k, nr, 2).lazyProduct(Hs.middleCols(k * nr, nr));
  // M⁻¹ once, then lazy products (tiny fixed sizes: the blocked triangular
  // solves cost more than the products).
  const Mss Minv = Eigen::PartialPivLU<Mss>(M).inverse();
  const Ms2 Qx = Minv.lazyProduct(WxEc);
  const Msd Qd = Minv.lazyProduct(G);
  M2s VBH(n2, snr);
  for (int k = 0; k < s; ++k) VBH.middleCols(k * nr, nr).noalias() = VB.middleCols(2 * k, 2).lazyProduct(Hs.middleCols(k * nr, nr));
  st.Qx = Qx;
  st.Qd = Qd;
  st.P = Eh - VBH.lazyProduct(Qx);
  st.Rd = VB - VBH.lazyProduct(Qd);
}

// The same with process damping (docs/sdm.md "Collocation with process
// damping"): the node unknowns are z_k and v_k = Sv x(t_k), the force at node
// k is d_k − Hs_k z_k − Dn_k v_k (Dn_k = C̄ D(t_k), 2 × 2 each in Dn), so
//   (I + Gc K) Y = Ec x_i + Gc d,   Y = [Z; V], Gc = [G; Gv], Ec = [WxEc; SvEc],
// K = the node blocks [Hs_k at z_k, Dn_k at v_k]; x_{i+1} = Eh x_i + VB d −
// VB K Y. Only Y's z rows are kept (Qx, Qd): the delayed reads and Φ y need
// no more. Run-time sizes (process damping is the rarer case).
void step_matrices_damped(const NodeWeights& w, const MatrixXd& Hs, const MatrixXd& Dn, int n2, int nr, int s,
                          CollocationStep& st) {
  const int snr = s * nr, nd = 2 * s, ny = snr + nd;
  MatrixXd Gc(ny, nd), Ec(ny, n2), K = MatrixXd::Zero(nd, ny);
  Gc << w.G, w.Gv;
  Ec << w.WxEc, w.SvEc;
  for (int k = 0; k < s; ++k) {
    K.block(2 * k, k * nr, 2, nr) = Hs.middleCols(k * nr, nr);
    K.block(2 * k, snr + 2 * k, 2, 2) = Dn.middleCols(2 * k, 2);
  }
  const Eigen::PartialPivLU<MatrixXd> lu(MatrixXd::Identity(ny, ny) + Gc * K);
  const MatrixXd Qx = lu.solve(Ec), Qd = lu.solve(Gc), VBK = w.VB * K;
  st.Qx = Qx.topRows(snr);
  st.Qd = Qd.topRows(snr);
  st.P = w.Eh - VBK * Qx;
  st.Rd = w.VB - VBK * Qd;
}

void step_matrices_any(const NodeWeights& w, const MatrixXd& Hs, int n2, int nr, int s, CollocationStep& st) {
  if (nr == 2 && s == 3 && n2 == 8) return step_matrices<8, 6, 6>(w, Hs, n2, nr, s, st);
  if (nr == 2 && s == 3 && n2 == 4) return step_matrices<4, 6, 6>(w, Hs, n2, nr, s, st);
  if (nr == 2 && s == 2 && n2 == 8) return step_matrices<8, 4, 4>(w, Hs, n2, nr, s, st);
  if (nr == 2 && s == 2 && n2 == 4) return step_matrices<4, 4, 4>(w, Hs, n2, nr, s, st);
  step_matrices<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>(w, Hs, n2, nr, s, st);
}

// Most step lengths whose weights a map keeps between depths (a helix moves
// its events with the depth, so the lengths of its spans change).
constexpr std::size_t kWeightsKept = 256;

// pm's fields for a collocation map of the steps between boundaries t with
// N node samples per period, its cc emptied of the last depth's terms (its
// step storage and weights kept for the same A and s).
void start_map(PeriodMap& pm, int n2, int nr, double T, int s, const std::vector<double>& t, int N,
               const double* A_data) {
  pm.n2 = n2;
  pm.nr = nr;
  pm.tau = T;
  pm.path = MapPath::kCutterCollocation;
  pm.nodes = s;
  pm.constant = pm.free_flight = pm.branch_roots = false;
  pm.E = nullptr;
  pm.steps.clear();
  pm.m = static_cast<int>(t.size()) - 1;
  CollocationCutterMap& cc = pm.cc;
  cc.t = t;
  cc.s = s;
  cc.N = N;
  cc.steps.resize(static_cast<std::size_t>(pm.m));  // kept between depths: no reallocation
  cc.terms.clear();
  cc.term_c.clear();
  if (cc.weights_for != A_data || cc.weights_nodes != s || cc.weights.size() > kWeightsKept) {
    cc.weights.clear();
    cc.weights_for = A_data;
    cc.weights_nodes = s;
  }
}

// The weights of step length h from cc's cache, computed on first use (with
// process damping, Sv non-null, also SvEc and Gv).
const NodeWeights& step_weights(CollocationCutterMap& cc, const MatrixXd& A, const MatrixXd& B, const MatrixXd& Wx,
                                const MatrixXd* Sv, double h, const std::vector<double>& c) {
  auto it = cc.weights.find(h);
  if (it != cc.weights.end()) return it->second;
  NodeWeights w = node_weights(A, B, Wx, h, c);
  if (Sv) {
    NodeWeights v = node_weights(A, B, *Sv, h, c);
    w.SvEc = std::move(v.WxEc);
    w.Gv = std::move(v.G);
  }
  return cc.weights.emplace(h, std::move(w)).first->second;
}

}  // namespace

void SdmKernel::build_cutter_collocation(const Grid& g, double a, PeriodMap& pm) const {
  const Process& p = *p_;
  const int n2 = static_cast<int>(A_.rows()), nr = static_cast<int>(Wx_.rows());
  const int s = g.nodes, snr = s * nr;
  if (B_.cols() != 2) throw std::logic_error("sdm collocation: the force input must be 2 components");
  // The grid at this depth (a helix or a profile moves its events with the
  // depth), or the speed's grid at 1 m scaled (straight teeth: H ∝ a).
  CutterGrid local;
  if (!g.cutter_grid)
    local = g.ssv ? ssv_cutter_grid(p, g, o_.axial_slices, a, true) : cutter_grid(p, g, o_.axial_slices, a, true);
  const CutterGrid& cg = g.cutter_grid ? *g.cutter_grid : local;
  const double scale = g.cutter_grid ? a / cg.depth : 1.0;
  const RegenerativeCut* cut = cg.cut.get();  // at cg.depth
  const NodeClock clock = g.ssv ? NodeClock(p, g) : NodeClock();
  // Turning with speed variation: H = a ĥ nᵀ at every node (no cut).
  const bool ssv_turning = g.ssv && !p.rotating_edges();
  if (!cut && !ssv_turning) throw std::logic_error("sdm collocation: a milling grid without its cut");
  const MatrixXd ssv_HU = ssv_turning ? MatrixXd(a * turning_hhat_of(p) * U_) : MatrixXd();
  const double T = g.tau, h_zero = kFreeForce * cg.force_scale_n_per_m2 * a;  // N/m: a group not cutting
  // Process damping: C̄ D(t) Sv x at every node (C̄ = C_pd / V).
  const double cbar = p.process_damping_per_depth(g.rpm);
  const bool damped = cbar > 0.0 && Sv_ && Sv_->size() > 0;
  const std::vector<double> c = gauss_nodes(s);
  const NodeLayout layout(cg, c, T);
  const int M = static_cast<int>(cg.h.size()), ng = static_cast<int>(cg.gtau.size());

  start_map(pm, n2, nr, T, s, cg.t, layout.nodes(), A_.data());
  CollocationCutterMap& cc = pm.cc;
  std::vector<Eigen::Matrix2d> per_edge, Hg(static_cast<std::size_t>(ng));
  MatrixXd Hs(2, snr), HU(2, nr), Dn(2, 2 * s);
  int lowest = 0;
  int sample[2 * kMaxCollocationNodes];
  double weight[2 * kMaxCollocationNodes];
  for (int i = 0; i < M; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    CollocationStep& st = cc.steps[iu];
    st.h = cg.h[iu];
    st.free = cg.free[iu] != 0;
    st.n_terms = 0;
    if (st.free) {
      st.P = (A_ * st.h).exp();
      continue;
    }
    const NodeWeights& w = step_weights(cc, A_, B_, Wx_, damped ? Sv_ : nullptr, st.h, c);
    st.first_node = layout.first_node(i);
    st.first_term = static_cast<int>(cc.terms.size());
    auto add_terms = [&](int k, const MatrixXd& hu, double delayed) {  // d_k += hu z(delayed)
      const int n = layout.stencil(delayed, st.first_node, sample, weight);
      for (int q = 0; q < n; ++q) {
        lowest = std::min(lowest, sample[q]);
        cc.terms.push_back({k, sample[q]});
        for (int e = 0; e < 2 * nr; ++e) cc.term_c.push_back(weight[q] * hu.data()[e]);
      }
    };
    for (int k = 0; k < s; ++k) {
      const double tk = cg.t[iu] + c[static_cast<std::size_t>(k)] * st.h;
      if (ssv_turning) {
        Hs.middleCols(k * nr, nr) = ssv_HU;
        add_terms(k, ssv_HU, tk - clock.delay(tk, cg.gtau[0]));
        continue;
      }
      const double tq = clock.mean_time(tk);  // the cut's time (tk at constant speed)
      cut->force_rates(tq, per_edge);
      if (damped) Dn.middleCols(2 * k, 2) = (cbar * scale) * cut->damping_rate(tq);
      for (auto& m : Hg) m.setZero();
      for (std::size_t e = 0; e < per_edge.size(); ++e) Hg[static_cast<std::size_t>(cg.edge_group[e])] += per_edge[e];
      Hs.middleCols(k * nr, nr).setZero();
      for (int gi = 0; gi < ng; ++gi) {
        const Eigen::Matrix2d H = Hg[static_cast<std::size_t>(gi)] * scale;
        if (H.norm() <= h_zero) continue;
        HU.noalias() = H * U_;  // 2 × n_r
        Hs.middleCols(k * nr, nr) += HU;
        add_terms(k, HU, tk - clock.delay(tk, cg.gtau[static_cast<std::size_t>(gi)]));
      }
    }
    st.n_terms = static_cast<int>(cc.terms.size()) - st.first_term;
    if (damped) step_matrices_damped(w, Hs, Dn, n2, nr, s, st);
    else step_matrices_any(w, Hs, n2, nr, s, st);
  }
  cc.L = -lowest;
  pm.nz = cc.L;
  pm.dim = n2 + cc.L * nr;
}

namespace {

// Φ y on the collocation map. N2, NR, S: compile-time sizes of the common
// models (2n, n_r, s), or 0 for run-time ones (the same operations in the
// same order either way: fixed sizes keep the state in registers).
template <int N2, int NR, int S>
void apply_cc(const PeriodMap& pm, const double* y, double* out, std::vector<double>* record) {
  const CollocationCutterMap& c = pm.cc;
  const int n2 = N2 > 0 ? N2 : pm.n2, nr = NR > 0 ? NR : pm.nr, s = S > 0 ? S : c.s;
  const int L = c.L, N = c.N, nd = 2 * s, snr = s * nr;
  c.buf.resize(static_cast<std::size_t>((L + N) * nr));
  constexpr int kLocal = N2 > 0 ? N2 : 1, kNodes = S > 0 ? 2 * S : 1;
  double xl[kLocal], xnl[kLocal], dl[kNodes];
  if (N2 == 0) {
    c.x.resize(static_cast<std::size_t>(n2));
    c.xn.resize(static_cast<std::size_t>(n2));
  }
  if (S == 0) c.d.resize(static_cast<std::size_t>(nd));
  double* x = N2 > 0 ? xl : c.x.data();
  double* xn = N2 > 0 ? xnl : c.xn.data();
  double* d = S > 0 ? dl : c.d.data();
  std::copy(y, y + n2, x);
  double* buf = c.buf.data();
  std::copy(y + n2, y + n2 + L * nr, buf);  // samples −L … −1
  if (record) record->assign(x, x + n2);
  for (const CollocationStep& st : c.steps) {
    const double* P = st.P.data();
    for (int r = 0; r < n2; ++r) xn[r] = 0.0 + P[r] * x[0];
    for (int col = 1; col < n2; ++col)
      for (int r = 0; r < n2; ++r) xn[r] += P[r + col * n2] * x[col];
    if (!st.free) {
      for (int k = 0; k < nd; ++k) d[k] = 0.0;
      const double* C = c.term_c.data() + static_cast<std::size_t>(st.first_term) * 2 * static_cast<std::size_t>(nr);
      for (int q = st.first_term; q < st.first_term + st.n_terms; ++q, C += 2 * nr) {
        const NodeTerm& tm = c.terms[static_cast<std::size_t>(q)];
        const double* z = buf + (tm.sample + L) * nr;
        double* dk = d + 2 * tm.node;
        for (int col = 0; col < nr; ++col) {
          dk[0] += C[2 * col] * z[col];
          dk[1] += C[2 * col + 1] * z[col];
        }
      }
      double* Z = buf + (st.first_node + L) * nr;
      const double* Qx = st.Qx.data();
      const double* Qd = st.Qd.data();
      for (int r = 0; r < snr; ++r) Z[r] = 0.0;
      for (int col = 0; col < n2; ++col)
        for (int r = 0; r < snr; ++r) Z[r] += Qx[r + col * snr] * x[col];
      for (int col = 0; col < nd; ++col)
        for (int r = 0; r < snr; ++r) Z[r] += Qd[r + col * snr] * d[col];
      const double* Rd = st.Rd.data();
      for (int col = 0; col < nd; ++col)
        for (int r = 0; r < n2; ++r) xn[r] += Rd[r + col * n2] * d[col];
    }
    std::copy(xn, xn + n2, x);
    if (record) record->insert(record->end(), x, x + n2);
  }
  std::copy(x, x + n2, out);
  std::copy(buf + N * nr, buf + (N + L) * nr, out + n2);  // samples N − L … N − 1
}

}  // namespace

void SdmKernel::apply_cutter_collocation(const PeriodMap& pm, const double* y, double* out,
                                         std::vector<double>* record) {
  const int s = pm.cc.s;
  if (pm.nr == 2 && pm.n2 == 8 && s == 3) return apply_cc<8, 2, 3>(pm, y, out, record);
  if (pm.nr == 2 && pm.n2 == 4 && s == 3) return apply_cc<4, 2, 3>(pm, y, out, record);
  if (pm.nr == 2 && pm.n2 == 8 && s == 2) return apply_cc<8, 2, 2>(pm, y, out, record);
  if (pm.nr == 2 && pm.n2 == 4 && s == 2) return apply_cc<4, 2, 2>(pm, y, out, record);
  apply_cc<0, 0, 0>(pm, y, out, record);
}

}  // namespace chatter::sdm_detail
