// Gauss collocation of the cutting steps of the `sdm` solver
// (SemiDiscretizationOptions::collocation_nodes, docs/sdm.md "Collocation"):
// the weights of one step length, mode by mode (node_weights, shared with
// the real-cutter grid's collocation), the depth-independent node matrices
// of each step (add_collocation), the step maps at one depth (SdmKernel::build_collocation) and Φ y
// (SdmKernel::apply_collocation). Part of the `sdm` solver (sdm_internal.hpp).
//
// On a cutting step [t_i, t_i + h] of the straight-teeth milling grid,
//   ẋ = A x + a B H(t) U (ζ(t) − Wx x),   ζ(t) = z(t − τ),
// the cutting term f(t) = a B H U (ζ − Wx x) is replaced by its Lagrange
// polynomial through the s Gauss–Legendre nodes t_i + c_j h, and the rest is
// exact (variation of constants):
//   X_j = e^{A c_j h} x_i + Σ_k W_jk f_k,   x_{i+1} = e^{A h} x_i + Σ_k V_k f_k,
//   W_jk = ∫₀^{c_j h} e^{A(c_j h − σ)} ℓ_k(σ/h) dσ,  V_k = ∫₀^h e^{A(h − σ)} ℓ_k(σ/h) dσ,
// X_j the state at node j. The delay is the period of the grid, so ζ at a
// node is the sample z = Wx X at the same node one period back: the map
// stores z at every node and needs no interpolation. Only Z_j = Wx X_j feeds
// back, so each step solves an s n_r system at each depth:
//   (I + a WxK) Z = WxEc x_i + a WxK ζ,   x_{i+1} = e^{A h} x_i + a VB (ζ − Z).
// This is an exponential collocation method (the free dynamics exact as in
// the first-order semi-discretisation of Insperger & Stépán 2004; the
// collocation of the cutting term as in the piecewise collocation of the
// monodromy operator of Breda, Maset & Vermiglio, SIAM J. Numer. Anal. 50,
// 2012, 1456–1483). Measured order of the depth limit: 2s (4 at s = 2, 6 at
// s = 3: Gauss superconvergence at the step ends; docs/sdm.md).
#include "sdm_internal.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include <Eigen/LU>
#include <unsupported/Eigen/MatrixFunctions>
#include "chatter/kinematics.hpp"

namespace chatter::sdm_detail {
namespace {

// e^{A T} and G_q(T) = ∫₀^T e^{A(T−σ)} (σ/T)^q dσ, q < s, from one
// exponential of the augmented matrix [[A T, I T, 0, …], [0, 0, I, …], …,
// [0, …, 0]] (size N (s + 1) for A of size N): its block (0, q + 1) is
// G_q(T) / q!. M: the (stack-allocated) matrix type of the augmented matrix.
template <class M>
void augmented_integrals(const MatrixXd& A, double T, int s, MatrixXd& E, std::vector<MatrixXd>& G) {
  const Index n = A.rows(), na = n * (s + 1);
  M aug = M::Zero(na, na);
  aug.topLeftCorner(n, n) = A * T;
  aug.block(0, n, n, n) = MatrixXd::Identity(n, n) * T;
  for (int q = 1; q < s; ++q) aug.block(n * q, n * (q + 1), n, n).setIdentity();
  const M X = aug.exp();
  E = X.topLeftCorner(n, n);
  G.assign(static_cast<std::size_t>(s), MatrixXd());
  double factorial = 1.0;
  for (int q = 0; q < s; ++q) {
    if (q > 0) factorial *= q;
    G[static_cast<std::size_t>(q)] = factorial * X.block(0, n * (q + 1), n, n);
  }
}

// Largest augmented matrix of one mode (2 (s + 1), s <= kMaxCollocationNodes).
constexpr int kModeAugmented = 2 * (kMaxCollocationNodes + 1);
using ModeMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kModeAugmented, kModeAugmented>;

// φ_0(z) … φ_kmax(z), φ_k(z) = ∫₀¹ e^{(1−θ) z} θ^{k−1} dθ / (k − 1)! (φ_0 =
// e^z). Below |z| = 1: φ_kmax from its Taylor series Σ z^m/(m + kmax)!, the
// lower ones by φ_k = z φ_{k+1} + 1/k! (stable downwards there). Else the
// recurrence upwards φ_{k+1} = (φ_k − 1/k!)/z from e^z (no cancellation
// worse than |z|^{-k} k! there).
void phi_functions(Cplx z, int kmax, Cplx* phi) {
  std::array<double, kMaxCollocationNodes + 2> inv_fact{};  // 1/k!
  inv_fact[0] = 1.0;
  for (int k = 1; k <= kmax; ++k) inv_fact[static_cast<std::size_t>(k)] = inv_fact[static_cast<std::size_t>(k - 1)] / k;
  if (z.real() * z.real() + z.imag() * z.imag() < 1.0) {
    auto norm2 = [](const Cplx& c) { return c.real() * c.real() + c.imag() * c.imag(); };  // no hypot
    Cplx term(inv_fact[static_cast<std::size_t>(kmax)], 0.0), sum(0.0, 0.0);
    for (int m = 1; m < 40 && norm2(term) > 1e-36 * norm2(sum + term); ++m) {
      sum += term;
      term *= z / static_cast<double>(m + kmax);
    }
    phi[kmax] = sum + term;
    for (int k = kmax - 1; k >= 0; --k) phi[k] = z * phi[k + 1] + inv_fact[static_cast<std::size_t>(k)];
    return;
  }
  phi[0] = std::exp(z);
  for (int k = 0; k < kmax; ++k) phi[k + 1] = (phi[k] - inv_fact[static_cast<std::size_t>(k)]) / z;
}

// Closed form of augmented_integrals for one underdamped mode block a =
// [[0, ω], [−ω, −2ζω]] (ζ <= kClosedFormMaxDamping): a function f of a 2 × 2
// matrix with eigenvalues λ, λ̄ is f(a) = α I + β a, β = Im f(λ)/Im λ, α = Re
// f(λ) − β Re λ; e^{aT} has f = e^{λT}, G_q(T) has f = T q! φ_{q+1}(λT).
// False for other blocks (then the augmented exponential).
constexpr double kClosedFormMaxDamping = 0.9;
bool closed_form_integrals(const Eigen::Matrix2d& a, double T, int s, Eigen::Matrix2d& E, Eigen::Matrix2d* G) {
  const double w = a(0, 1);
  if (!(a(0, 0) == 0.0 && w > 0.0 && a(1, 0) == -w)) return false;
  const double zeta = -a(1, 1) / (2.0 * w);
  if (!(zeta >= 0.0 && zeta <= kClosedFormMaxDamping)) return false;
  const Cplx lambda(-zeta * w, w * std::sqrt(1.0 - zeta * zeta));
  Cplx phi[kMaxCollocationNodes + 1];
  phi_functions(lambda * T, s, phi);
  auto of = [&](const Cplx& f) {
    const double beta = f.imag() / lambda.imag(), alpha = f.real() - beta * lambda.real();
    Eigen::Matrix2d m = beta * a;
    m.diagonal().array() += alpha;
    return m;
  };
  E = of(phi[0]);
  double qfact = 1.0;
  for (int q = 0; q < s; ++q) {
    if (q > 0) qfact *= q;
    G[q] = of(T * qfact * phi[q + 1]);
  }
  return true;
}

}  // namespace

void mode_integrals(const Eigen::Matrix2d& a, double T, int s, Eigen::Matrix2d& E, Eigen::Matrix2d* G) {
  if (closed_form_integrals(a, T, s, E, G)) return;
  MatrixXd e;
  std::vector<MatrixXd> g;
  augmented_integrals<ModeMatrix>(a, T, s, e, g);
  E = e;
  for (int q = 0; q < s; ++q) G[q] = g[static_cast<std::size_t>(q)];
}

std::vector<double> gauss_nodes(int s) {
  switch (s) {
    case 1: return {0.5};
    case 2: {
      const double d = 0.5 / std::sqrt(3.0);
      return {0.5 - d, 0.5 + d};
    }
    default: {
      const double d = 0.5 * std::sqrt(0.6);
      return {0.5 - d, 0.5, 0.5 + d};
    }
  }
}

// The collocation weights of step length h, mode by mode: A couples only q_i and
// q̇_i/ω_i of each mode (rows and columns i and n + i, state_space), so every
// weight is block-diagonal in those pairs and Wx, B touch each pair through
// 2 columns and 2 rows: O(n) work per weight instead of dense (2n)³.
NodeWeights node_weights(const MatrixXd& A, const MatrixXd& B, const MatrixXd& Wx, double h,
                         const std::vector<double>& c) {
  const int s = static_cast<int>(c.size());
  const Index nr = Wx.rows(), n2 = A.rows(), n = n2 / 2;
  // ℓ_k(u) = Σ_q L(q, k) u^q: the inverse of the Vandermonde matrix of the nodes.
  MatrixXd Vd(s, s);
  for (int i = 0; i < s; ++i)
    for (int q = 0; q < s; ++q) Vd(i, q) = std::pow(c[static_cast<std::size_t>(i)], q);
  const MatrixXd L = Vd.inverse();
  // Wc(j, k) (per q): L(q, k) c_j^q, the weight of G_q(c_j h) in W_jk.
  std::vector<double> lc(static_cast<std::size_t>(s * s * s));
  auto lc_at = [&](int j, int k, int q) -> double& { return lc[static_cast<std::size_t>((j * s + k) * s + q)]; };
  for (int j = 0; j < s; ++j)
    for (int k = 0; k < s; ++k)
      for (int q = 0; q < s; ++q) lc_at(j, k, q) = L(q, k) * Vd(j, q);
  NodeWeights out;
  out.Eh = MatrixXd::Zero(n2, n2);
  out.WxEc = MatrixXd::Zero(s * nr, n2);
  out.G = MatrixXd::Zero(s * nr, 2 * s);
  out.VB = MatrixXd::Zero(n2, 2 * s);
  Eigen::Matrix2d a, e, g[kMaxCollocationNodes];
  Eigen::Matrix<double, Eigen::Dynamic, 2> Wxi(nr, 2);
  Eigen::Matrix2d Bi;
  for (Index i = 0; i < n; ++i) {
    const Index at[2] = {i, n + i};
    for (int r = 0; r < 2; ++r) {
      for (int col = 0; col < 2; ++col) a(r, col) = A(at[r], at[col]);
      Wxi.col(r) = Wx.col(at[r]);
      Bi.row(r) = B.row(at[r]);
    }
    for (int j = 0; j < s; ++j) {
      const double cj = c[static_cast<std::size_t>(j)];
      mode_integrals(a, cj * h, s, e, g);
      const Eigen::Matrix<double, Eigen::Dynamic, 2> we = Wxi * e;  // Wx e^{A c_j h} on this pair
      for (int r = 0; r < 2; ++r) out.WxEc.block(j * nr, at[r], nr, 1) += we.col(r);
      // W_jk = Σ_q L(q, k) c_j^q G_q(c_j h)  (∫₀^{c h} e^{A(c h − σ)} (σ/h)^q dσ = c^q G_q(c h)).
      for (int k = 0; k < s; ++k) {
        Eigen::Matrix2d w = Eigen::Matrix2d::Zero();
        for (int q = 0; q < s; ++q) w += lc_at(j, k, q) * g[q];
        out.G.block(j * nr, 2 * k, nr, 2) += Wxi * (w * Bi);
      }
    }
    mode_integrals(a, h, s, e, g);
    for (int r = 0; r < 2; ++r)
      for (int col = 0; col < 2; ++col) out.Eh(at[r], at[col]) = e(r, col);
    for (int k = 0; k < s; ++k) {
      Eigen::Matrix2d v = Eigen::Matrix2d::Zero();
      for (int q = 0; q < s; ++q) v += L(q, k) * g[q];
      const Eigen::Matrix2d vb = v * Bi;
      for (int r = 0; r < 2; ++r) out.VB.block(at[r], 2 * k, 1, 2) = vb.row(r);
    }
  }
  return out;
}

void add_collocation(Grid& g, const Process& p, int nodes, const MatrixXd& A, const MatrixXd& B,
                     const MatrixXd& Wx, const MatrixXd& U) {
  const bool turning = g.constant && !p.rotating_edges() && !g.nose && g.damping.size() == 0;
  if (g.path != MapPath::kToothSteps || g.ssv || (g.constant && !turning))
    throw std::logic_error("add_collocation: not a straight-teeth milling grid or a sharp turning edge "
                           "(collocation_refusal lets it through)");
  g.path = MapPath::kToothCollocation;
  g.nodes = nodes;
  const std::vector<double> c = gauss_nodes(nodes);
  const Index n2 = A.rows(), nr = Wx.rows(), snr = nodes * nr;
  // Turning: H = ĥ nᵀ is constant (Ĥ U, 2 × n_r, per unit depth at every node).
  const MatrixXd turning_HU = turning ? MatrixXd(turning_hhat_of(p) * U) : MatrixXd();
  const double omega = turning ? 0.0 : angular_speed_rad_per_s(g.rpm);
  const double t_entry = turning ? 0.0 : p.entry_angle() / omega;  // tooth 0 enters here (Process::directional_matrix)
  std::map<double, NodeWeights> by_length;  // one per milling segment
  for (Step& st : g.steps) {
    auto it = by_length.find(st.h);
    if (it == by_length.end()) it = by_length.emplace(st.h, node_weights(A, B, Wx, st.h, c)).first;
    const NodeWeights& w = it->second;
    st.Eh = w.Eh;
    st.WxEc = w.WxEc;
    st.WxK.resize(snr, snr);
    st.VB.resize(n2, snr);
    for (int k = 0; k < nodes; ++k) {
      const double t = t_entry + st.t0 + c[static_cast<std::size_t>(k)] * st.h;
      const MatrixXd HU = turning ? turning_HU : MatrixXd(p.directional_matrix(t, g.rpm) * U);  // 2 × n_r, per unit depth
      st.VB.middleCols(k * nr, nr) = w.VB.middleCols(2 * k, 2) * HU;  // V_k B H U
      for (int j = 0; j < nodes; ++j)
        st.WxK.block(j * nr, k * nr, nr, nr) = w.G.block(j * nr, 2 * k, nr, 2) * HU;  // Wx W_jk B H U
    }
  }
}

namespace {

// The step maps of one period at depth a (SdmKernel::build_collocation).
// N2, SNR: compile-time sizes of the common models (two modes in the plane,
// 2 or 3 nodes), or Eigen::Dynamic; the same operations either way.
template <int N2, int SNR>
void collocation_steps(const Grid& g, double a, int n2, int snr, PeriodMap& pm) {
  using NodeSystem = Eigen::Matrix<double, SNR, SNR>;
  using NodeRhs = Eigen::Matrix<double, SNR, (N2 == Eigen::Dynamic || SNR == Eigen::Dynamic) ? Eigen::Dynamic : N2 + SNR>;
  NodeSystem M(snr, snr);
  NodeRhs rhs(snr, n2 + snr), Q(snr, n2 + snr);
  Eigen::PartialPivLU<NodeSystem> lu(snr);
  for (std::size_t i = 0; i < g.steps.size(); ++i) {
    const Step& st = g.steps[i];
    StepMap& sm = pm.steps[i];
    const Eigen::Map<const Eigen::Matrix<double, SNR, SNR>> WxK(st.WxK.data(), snr, snr);
    const Eigen::Map<const Eigen::Matrix<double, SNR, N2>> WxEc(st.WxEc.data(), snr, n2);
    const Eigen::Map<const Eigen::Matrix<double, N2, SNR>> VB(st.VB.data(), n2, snr);
    const Eigen::Map<const Eigen::Matrix<double, N2, N2>> Eh(st.Eh.data(), n2, n2);
    M.setIdentity();
    M.noalias() += a * WxK;
    rhs.leftCols(n2) = WxEc;
    rhs.rightCols(snr) = a * WxK;
    lu.compute(M);
    Q.noalias() = lu.solve(rhs);  // [Z_j] = Q [x_i; ζ_i]
    sm.Qc = Q;
    const Eigen::Matrix<double, N2, N2> P = Eh - a * (VB * Q.leftCols(n2));
    const Eigen::Matrix<double, N2, SNR> R = a * (VB - VB * Q.rightCols(snr));
    sm.P = P;
    sm.Rc = R;
  }
}

}  // namespace

// pm's sizes and fields are set by build_map, which calls this for a grid
// with nodes > 0.
void SdmKernel::build_collocation(const Grid& g, double depth, PeriodMap& pm) const {
  const int n2 = pm.n2, snr = g.nodes * pm.nr;
  if (n2 == 4 && snr == 6) return collocation_steps<4, 6>(g, depth, n2, snr, pm);
  if (n2 == 4 && snr == 4) return collocation_steps<4, 4>(g, depth, n2, snr, pm);
  collocation_steps<Eigen::Dynamic, Eigen::Dynamic>(g, depth, n2, snr, pm);
}

namespace {

// y = [x(0); ζ of step 0 (s n_r); …; ζ of step m − 1]: the node samples one
// period back. work: >= 2 n2 doubles. N2, SNR: compile-time sizes of the
// common models (two modes in the plane), or 0 for run-time ones (the same
// operations in the same order either way).
template <int N2, int SNR>
void apply_collocation_n(const PeriodMap& pm, const double* y, double* out, double* work) {
  const int n2 = N2 > 0 ? N2 : pm.n2, snr = SNR > 0 ? SNR : pm.nodes * pm.nr;
  double* x = work;
  double* xn = work + n2;
  std::copy(y, y + n2, x);
  for (int i = 0; i < pm.m; ++i) {
    const StepMap& sm = pm.constant ? pm.steps[0] : pm.steps[static_cast<std::size_t>(i)];
    const double* zeta = y + n2 + i * snr;
    double* zo = out + n2 + i * snr;
    const double* Q = sm.Qc.data();
    for (int r = 0; r < snr; ++r) {
      double acc = 0.0;
      for (int c = 0; c < n2; ++c) acc += Q[r + c * snr] * x[c];
      for (int c = 0; c < snr; ++c) acc += Q[r + (n2 + c) * snr] * zeta[c];
      zo[r] = acc;
    }
    const double* P = sm.P.data();
    const double* R = sm.Rc.data();
    for (int r = 0; r < n2; ++r) {
      double acc = 0.0;
      for (int c = 0; c < n2; ++c) acc += P[r + c * n2] * x[c];
      for (int c = 0; c < snr; ++c) acc += R[r + c * n2] * zeta[c];
      xn[r] = acc;
    }
    std::swap(x, xn);
  }
  if (pm.free_flight) {
    free_flight_step(*pm.E, n2, x, xn);
    std::swap(x, xn);
  }
  std::copy(x, x + n2, out);
}

}  // namespace

void SdmKernel::apply_collocation(const PeriodMap& pm, const double* y, double* out, double* work) {
  const int snr = pm.nodes * pm.nr;
  if (pm.n2 == 4 && snr == 6) return apply_collocation_n<4, 6>(pm, y, out, work);
  if (pm.n2 == 4 && snr == 4) return apply_collocation_n<4, 4>(pm, y, out, work);
  apply_collocation_n<0, 0>(pm, y, out, work);
}

}  // namespace chatter::sdm_detail
