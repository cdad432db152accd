// First-order semi-discretisation (Insperger & Stépán 2004) of the periodic
// delay equation of docs/physics.md §3, the `sdm` solver. See
// include/chatter/semi_discretization.hpp for the method and docs/sdm.md for
// the convergence study.
#include "chatter/report.hpp"
#include "chatter/semi_discretization.hpp"

#include "depth_search.hpp"
#include "roots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <type_traits>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <unsupported/Eigen/MatrixFunctions>

#include "chatter/error.hpp"

namespace chatter {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Cplx = std::complex<double>;

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A multiplier is real when |arg μ| or π − |arg μ| is below this (rad): real
// eigenvalues come out of the real Schur form with Im exactly 0; the margin
// only absorbs round-off of nearly coalescing real pairs.
constexpr double kRealAngle = 1e-6;
// Augmented step systems up to this size use stack-allocated matrices.
constexpr int kSmallAugmented = 12;
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kSmallAugmented, kSmallAugmented>;
// Relative rank threshold for the delayed quantity (entries of S are O(1)).
constexpr double kRankTol = 1e-10;
// Arnoldi: relative residual of the dominant Ritz pair, and restart budget.
constexpr double kArnoldiTol = 1e-10;
constexpr int kArnoldiMaxRestarts = 60;
// Depth search: a climbing step aims this far (relative) beyond the crossing
// the secant predicts, so that the bracket closes in one step when the
// prediction is good; and always climbs at least this ratio − 1.
constexpr double kSecantOvershoot = 0.01;
constexpr double kMinClimb = 1e-3;
const double kLogQuarter = std::log(0.25);
// Real cutter: events closer than this fraction of the period are one event
// (Process merges at 1e-12 too); delays equal to it are one delay group.
constexpr double kEventMerge = 1e-12;
// A delayed time within this fraction of a step from a sample is that sample
// (the interpolation weight would only carry round-off).
constexpr double kSnap = 1e-9;
// A step whose force integral is below this times (K_t + K_r) a h is free
// flight: the windowed integral of a free span is 0 up to round-off.
constexpr double kFreeForce = 1e-12;
// Smallest scale of the input blocks of a real-cutter step exponential: the
// blocks come out about this small, with relative round-off ~1e-16/this.
constexpr double kMinBlockScale = 1e-6;
// Branch roots of turning (SdmKernel::branches): used when τ min ζω is at
// least kBranchMinDecay (contraction factor about 1/kBranchMinDecay) and the
// map is larger than dense_max_dimension; Newton's iteration budget and
// tolerance (on s τ, rad).
constexpr double kBranchMinDecay = 4.0;
constexpr int kBranchIterations = 50;
constexpr double kBranchTolerance = 1e-11;
// A branch whose Newton iterates stay below e^this times the dominant
// multiplier's modulus cannot be dominant.
constexpr double kNegligibleLog = -3.0;
// Continuation step: no followed multiplier may be predicted to move more
// than this fraction of its distance to the unit circle in one step.
constexpr double kMoveFraction = 0.5;
// A local maximum of ln ρ below the crossing is searched with this many
// golden-section steps (it ends on ρ ≥ 1 as soon as one is found).
constexpr int kBandSearchSteps = 12;
// Most divisions by bracket_ratio when the first depth is already unstable
// (ρ(0) < 1, so a stable depth exists; this only bounds a broken model).
constexpr int kMaxDescentSteps = 200;
// Relative error of ln ρ from an early-stopped (decide-mode) Arnoldi: it stops
// once | |θ| − 1 | exceeds kDecideFactor residuals, so |θ| is within 1/20 of
// its distance to the circle; a fall of ln ρ smaller than this is noise.
constexpr double kDecideError = 0.1;
// While bracketing, Arnoldi stops once | |θ| − 1 | exceeds this many residuals.
constexpr double kDecideFactor = 20.0;

// One step of the delay period, independent of the depth.
struct Step {
  double h = 0.0;     // s
  MatrixXd BHU;       // B Ĥ U with Ĥ the step average of Ĥ(t): 2n × n_r (per unit depth)
};

// Real-cutter grid of one period (cutter_grid): boundaries, and per step the
// exact integrals ∫∫ H₁ per delay group and Σ_j ∫∫ n nᵀ at depth `depth`.
struct CutterGrid {
  double depth = 0.0;              // m
  std::vector<double> t;           // t_0 = 0 … t_M = T
  std::vector<double> h;           // step lengths, s
  std::vector<char> free;          // 1: free flight (exact step)
  std::vector<Eigen::Matrix2d> F;  // M × groups, row-major
  std::vector<Eigen::Matrix2d> D;  // M
  std::vector<double> gtau;        // delay of each group, s
};

// The step grid of one delay period at one spindle speed.
struct Grid {
  double tau = 0.0;
  std::vector<Step> steps;     // cutting steps, in time order from a tooth entry
  bool constant = false;       // turning: every step identical (steps.size() == 1, count m)
  int m = 0;                   // number of cutting steps
  double free_time = 0.0;      // free-flight duration (s), 0 if a tooth always cuts
  MatrixXd E_free;             // exp(A t_free), depth-independent: built once per speed
  bool branch_roots = false;   // see SdmKernel::branches
  // Turning with process damping: c̄ B D Sv (2n × 2n, per unit depth), D =
  // e_x e_xᵀ; empty without it.
  MatrixXd damping;
  // Real cutter (milling with helix, variable pitch or helix, or process
  // damping): steps are built per depth by SdmKernel::build_cutter; tau is
  // then the period of H (tooth period, or one revolution).
  bool cutter = false;
  double rpm = 0.0;
  double h_target = 0.0;       // longest cutting step, s
  std::shared_ptr<const CutterGrid> cutter_grid;  // straight teeth: built once per speed at 1 m
};

CutterGrid cutter_grid(const Process& p, const Grid& g, int axial_slices, double a);

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

// The augmented step exponential for the common sizes (N = 2n of one or two
// modes, K <= 2 input columns); false for others (then the dense
// exponential of the whole matrix is used).
bool augmented_exp(const MatrixXd& X, const MatrixXd& Y, double s, MatrixXd& P, MatrixXd& G1, MatrixXd& G2) {
  auto run = [&](auto n_tag, auto k_tag) {
    constexpr int N = decltype(n_tag)::value, K = decltype(k_tag)::value;
    Eigen::Matrix<double, N, N> p;
    Eigen::Matrix<double, N, K> g1, g2;
    augmented_exp<N, K>(X, Y, s, p, g1, g2);
    P = p;
    G1 = g1;
    G2 = g2;
    return true;
  };
  using I1 = std::integral_constant<int, 1>;
  using I2 = std::integral_constant<int, 2>;
  using I4 = std::integral_constant<int, 4>;
  if (X.rows() == 4 && Y.cols() == 2) return run(I4{}, I2{});
  if (X.rows() == 4 && Y.cols() == 1) return run(I4{}, I1{});
  if (X.rows() == 2 && Y.cols() == 2) return run(I2{}, I2{});
  if (X.rows() == 2 && Y.cols() == 1) return run(I2{}, I1{});
  return false;
}

// Real-cutter step: x_{i+1} = P x_i + Σ C z_g over stored samples z_g.
struct CutterStep {
  double h = 0.0;
  bool free = false;                             // no slice cuts: P = exp(A h)
  MatrixXd P;
  // (sample index g, 2n × n_r): the first n_terms are the step's terms (the
  // rest is storage kept from an earlier depth, reused without reallocation).
  std::vector<std::pair<int, MatrixXd>> terms;
  int n_terms = 0;
};

// Where each delayed sample of a step falls on the stored samples: for the
// start and end of the step, z(t − τ) ≈ (1 − w) z_g + w z_{g+1}.
struct Located {
  int g0 = 0, g1 = 0;
  double w0 = 0.0, w1 = 0.0;
};

// Depth-independent work of a real-cutter map whose grid is shared by every
// depth of one speed (straight teeth): the free-flight exponentials and the
// located delayed samples per step and delay group, filled on first use.
struct CutterCache {
  std::shared_ptr<const CutterGrid> grid;  // the grid they belong to (kept alive: a unique key)
  std::vector<MatrixXd> free_P;            // per step: exp(A h) of a free step
  std::vector<char> located;               // per step × group: 1 once `where` is set
  std::vector<Located> where;              // per step × group
};

// One period of the real-cutter map. Sample g is z at t_g = t[g mod M] +
// floor(g/M) T; the state is [x(0); z_{−1}; …; z_{−L}].
struct CutterMap {
  std::vector<double> t;  // step boundaries t_0 = 0 … t_M = T
  std::vector<CutterStep> steps;
  int L = 0;
  CutterCache cache;
  mutable std::vector<double> buf, x, xn;  // apply() workspace
  // cutter_map() workspace (kept to avoid reallocating at every depth).
  std::vector<MatrixXd> Bt, R0, R1, HU;
  std::vector<int> gid;
  MatrixXd At, aug, E, Q0, Q1, Xh, Yh, G1, G2;
};

// Step maps x_{i+1} = P x_i + R0 z_{i−m} + R1 z_{i−m+1} at one depth.
struct StepMap {
  MatrixXd P, R0, R1;
};

struct PeriodMap {
  std::vector<StepMap> steps;  // one when constant
  bool constant = false;
  int m = 0;
  bool free_flight = false;
  const MatrixXd* E = nullptr;  // exp(A t_free), owned by the Grid
  int n2 = 0, nr = 0, nz = 0, dim = 0;
  double tau = 0.0;             // s
  bool branch_roots = false;    // turning with many steps: multipliers from ν^m = g(ν)
  bool cutter = false;          // the real-cutter map `cm` (general path)
  CutterMap cm;
};

// Dominant eigenpair of the one-period map.
struct Dominant {
  Cplx mu{0.0, 0.0};
  // Largest |μ| among the multipliers (Ritz values for Arnoldi) in the left
  // (Re μ < 0: where flip bands come from) and the right half-plane.
  double rho_left = 0.0, rho_right = 0.0;
  Cplx mu_left{0.0, 0.0}, mu_right{0.0, 0.0};  // those multipliers, Im >= 0
  // Exponent s of the dominant multiplier μ = e^{sτ} when it came from the
  // branch roots of turning (Im s: chatter frequency, rad/s); else 0.
  Cplx branch_s{0.0, 0.0};
  bool converged = true;
  Eigen::VectorXcd vec;  // empty unless requested
};

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

std::string bad_speed(double rpm) {
  std::ostringstream os;
  os << "spindle speed " << rpm << " rev/min: must be > 0 and finite";
  return os.str();
}

}  // namespace

// ---------------------------------------------------------------------------
namespace {

// Everything that depends on the speed and depth lives here, created per call.
class SdmKernel {
 public:
  SdmKernel(const MatrixXd& A, const MatrixXd& B, const MatrixXd& Wx, const MatrixXd& U,
            const SemiDiscretizationOptions& o, const Process* p = nullptr, const MatrixXd* Sv = nullptr)
      : A_(A), B_(B), Wx_(Wx), U_(U), o_(o), p_(p), Sv_(Sv) {}

  void build_map(const Grid& g, double depth, PeriodMap& pm) const {
    if (g.cutter) return build_cutter(g, depth, pm);
    const int n2 = static_cast<int>(A_.rows());
    const int nr = static_cast<int>(Wx_.rows());
    pm.n2 = n2;
    pm.nr = nr;
    pm.m = g.m;
    pm.constant = g.constant;
    pm.free_flight = g.free_time > 0.0;
    pm.nz = pm.free_flight ? g.m + 1 : g.m;
    pm.dim = n2 + pm.nz * nr;
    pm.E = pm.free_flight ? &g.E_free : nullptr;
    pm.tau = g.tau;
    pm.branch_roots = g.branch_roots && nr == 1;
    pm.steps.resize(g.steps.size());
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
  void build_steps(const Grid& g, double depth, PeriodMap& pm) const {
    const int n2 = pm.n2, nr = pm.nr, na = n2 + 2 * nr;
    M aug = M::Zero(na, na);
    M Bt(n2, nr);
    for (std::size_t i = 0; i < g.steps.size(); ++i) {
      const Step& s = g.steps[i];
      Bt.noalias() = (depth * s.BHU);  // 2n × n_r
      if (g.damping.size() > 0)  // process damping (turning): − a c̄ B D Sv
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_ - depth * g.damping) * s.h;
      else
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_) * s.h;
      aug.block(0, n2, n2, nr) = Bt * s.h;
      aug.block(n2, n2 + nr, nr, nr).setIdentity();
      const M E = aug.exp();
      StepMap& sm = pm.steps[i];
      sm.P = E.topLeftCorner(n2, n2);
      sm.R1 = E.block(0, n2 + nr, n2, nr);
      sm.R0 = E.block(0, n2, n2, nr) - sm.R1;
    }
  }

  // out = Φ y (both of length pm.dim, distinct). work: >= 2 n2 + nr doubles.
  // Dispatches to fixed-size loops for the common small models.
  static void apply(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work) {
    if (pm.cutter) return apply_cutter(pm, Wx, y, out, nullptr);
    if (pm.n2 == 2 && pm.nr == 1) return apply_n<2, 1>(pm, Wx, y, out, work);
    if (pm.n2 == 4 && pm.nr == 1) return apply_n<4, 1>(pm, Wx, y, out, work);
    if (pm.n2 == 4 && pm.nr == 2) return apply_n<4, 2>(pm, Wx, y, out, work);
    return apply_n<0, 0>(pm, Wx, y, out, work);
  }

  // N2, NR: compile-time sizes, or 0 for run-time ones.
  template <int N2, int NR>
  static void apply_n(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work) {
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
      const double* E = pm.E->data();
      for (int row = 0; row < n2; ++row) {
        double acc = 0.0;
        for (int c = 0; c < n2; ++c) acc += E[row + c * n2] * x[c];
        xn[row] = acc;
      }
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
  void build_cutter(const Grid& g, double a, PeriodMap& pm) const {
    if (g.cutter_grid) return cutter_map(g, *g.cutter_grid, a, a / g.cutter_grid->depth, pm, &g.cutter_grid);
    const CutterGrid cg = cutter_grid(*p_, g, o_.axial_slices, a);
    cutter_map(g, cg, a, 1.0, pm, nullptr);
  }

  // Second pass: the step maps from the grid, its integrals times `scale`.
  // `shared`: the grid is shared by every depth of the speed, so the
  // depth-independent parts are kept in pm.cm.cache (else nullptr).
  void cutter_map(const Grid& g, const CutterGrid& cg, double a, double scale, PeriodMap& pm,
                  const std::shared_ptr<const CutterGrid>* shared) const {
    const Process& p = *p_;
    const int n2 = static_cast<int>(A_.rows()), nr = static_cast<int>(Wx_.rows());
    const double T = g.tau;
    pm.n2 = n2;
    pm.nr = nr;
    pm.tau = T;
    pm.cutter = true;
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
    const MillingParameters& mp = p.milling_parameters();
    const double cbar = p.process_damping_per_depth(g.rpm);
    const double kscale = mp.tangential_coefficient_n_per_m2 + mp.radial_coefficient_n_per_m2;
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
      int nd = 0;  // delay groups cutting in this step: Bt, HU, gid [0, nd)
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
          const double tau = cg.gtau[static_cast<std::size_t>(gid[ku])];
          locate(cm.t[iu] - tau, l.g0, l.w0);
          locate(cm.t[iu + 1] - tau, l.g1, l.w1);
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
  static void apply_cutter(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out,
                           std::vector<double>* record) {
    if (pm.n2 == 4 && pm.nr == 2) return apply_cutter_n<4, 2>(pm, Wx, y, out, record);
    if (pm.n2 == 2 && pm.nr == 1) return apply_cutter_n<2, 1>(pm, Wx, y, out, record);
    return apply_cutter_n<0, 0>(pm, Wx, y, out, record);
  }

  // N2, NR: compile-time sizes, or 0 for run-time ones (same operations in
  // the same order either way).
  template <int N2, int NR>
  static void apply_cutter_n(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out,
                             std::vector<double>* record) {
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
      std::copy(xn, xn + n2, x);
      project(x, buf + (L + i + 1) * nr);
      if (record) record->insert(record->end(), x, x + n2);
    }
    std::copy(x, x + n2, out);
    for (int l = 1; l <= L; ++l)
      std::copy(buf + (L + M - l) * nr, buf + (L + M - l + 1) * nr, out + n2 + (l - 1) * nr);
  }

  // `decide`: only the verdict ρ < 1 or ρ >= 1 matters (bracketing); the
  // Arnoldi iteration can then stop after a few steps, even for small maps.
  // A map whose values overflow (growth beyond 1e308 per period: a depth far
  // above the limit, e.g. on a mode of 12 N/m) is unstable beyond doubt: ρ =
  // +inf, never an error (the depth search then goes down).
  Dominant dominant(const PeriodMap& pm, bool want_vector, bool decide = false) const {
    try {
      Dominant d;
      if (pm.branch_roots && branches(pm, d) && std::isfinite(std::abs(d.mu))) return d;
      d = pm.dim <= o_.dense_max_dimension && !decide ? dense(pm, want_vector) : arnoldi(pm, want_vector, decide);
      return std::isfinite(std::abs(d.mu)) ? d : overflowed();
    } catch (const MapOverflow&) {
      return overflowed();
    }
  }

  // Turning: every step is the same map D, x_{i+1} = P x_i + R0 z_{i−m} +
  // R1 z_{i−m+1}, z = W x (one delayed quantity), and Φ = D^m. With x_i =
  // ν^i v the eigenvalues of D solve ν^m = g(ν), g(ν) = W (νI − P)⁻¹ (R0 +
  // R1 ν) (matrix determinant lemma), and the multipliers of Φ are μ = ν^m.
  // Writing ν = e^{sh} (τ = m h), each branch k = 0 … m/2 of
  //     s τ = Ln g(e^{sh}) + 2πjk
  // has one root while the map s ↦ (Ln g(e^{sh}) + 2πjk)/τ contracts, which
  // holds near the unit circle when τ min ζω is large (|d Ln g/ds| is about
  // 1/|s − λ| for a mode pole λ); the roots it misses lie within ~1/τ of the
  // poles, |μ| ≈ e^{−ζωτ}, never dominant there. Newton on each branch from
  // s = 2πjk/τ: cost O(m) per map instead of an eigenproblem of size m whose
  // multipliers crowd the unit circle. The multiplier is exact for the
  // discretised map; μ = e^{sτ}, and Im s is the chatter frequency (rad/s).
  // Returns false (caller falls back to the eigen-solvers) if P cannot be
  // diagonalised or a branch does not converge.
  bool branches(const PeriodMap& pm, Dominant& out) const {
    const StepMap& st = pm.steps[0];
    const int n2 = pm.n2;
    Eigen::ComplexEigenSolver<Eigen::MatrixXcd> es(st.P.cast<Cplx>());
    if (es.info() != Eigen::Success) return false;
    const Eigen::MatrixXcd& V = es.eigenvectors();
    const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(V);
    if (!((V * lu.solve(Eigen::MatrixXcd::Identity(n2, n2)) - Eigen::MatrixXcd::Identity(n2, n2)).norm() < 1e-8))
      return false;
    const Eigen::VectorXcd lam = es.eigenvalues();
    const Eigen::RowVectorXcd c = Wx_.row(0).cast<Cplx>() * V;
    const Eigen::VectorXcd d0 = lu.solve(st.R0.col(0).cast<Cplx>());
    const Eigen::VectorXcd d1 = lu.solve(st.R1.col(0).cast<Cplx>());
    const double tau = pm.tau, h = tau / pm.m;
    const int kmax = pm.m / 2;
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
        Cplx G(0.0, 0.0), Gp(0.0, 0.0);
        for (int i = 0; i < n2; ++i) {
          const Cplx den = nu - lam(i);
          G += c(i) * (d0(i) + d1(i) * nu) / den;
          Gp -= c(i) * (d0(i) + d1(i) * lam(i)) / (den * den);
        }
        if (G == Cplx(0.0, 0.0)) break;  // no regeneration seen on this branch
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
    if (worst_failed > best_re * tau + kNegligibleLog) return false;
    out.mu = std::exp(best_s * tau);
    if (out.mu.imag() < 0.0) out.mu = std::conj(out.mu);
    out.branch_s = best_s;
    return true;
  }

 private:
  static bool better(const Cplx& a, const Cplx& b) {  // a dominates b
    const double ra = std::abs(a), rb = std::abs(b);
    if (ra > rb * (1.0 + 1e-13)) return true;
    if (rb > ra * (1.0 + 1e-13)) return false;
    return a.imag() > b.imag();  // of a conjugate pair, the one with Im >= 0
  }

  Dominant dense(const PeriodMap& pm, bool want_vector) const {
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

  static void half_plane_radii(const Eigen::VectorXcd& eigs, Dominant& out) {
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
  static void hessenberg_dominant(const MatrixXd& Hk, Cplx& theta, Eigen::VectorXcd& y,
                                  std::vector<std::pair<double, Index>>* order, Eigen::VectorXcd* eigs) {
    if (!Hk.allFinite()) throw MapOverflow{};
    Eigen::EigenSolver<MatrixXd> es(Hk, false);
    if (es.info() != Eigen::Success) throw NumericalError("sdm: Arnoldi Hessenberg eigen-decomposition failed");
    const Index kk = Hk.rows();
    Index best = 0;
    for (Index i = 1; i < kk; ++i)
      if (better(es.eigenvalues()(i), es.eigenvalues()(best))) best = i;
    theta = es.eigenvalues()(best);
    // Eigenvector by inverse iteration with a slightly perturbed shift.
    const Cplx shift = theta * (1.0 + 1e-12) + Cplx(0.0, 1e-14 * std::abs(theta));
    const Eigen::MatrixXcd T = Hk.cast<Cplx>() - shift * Eigen::MatrixXcd::Identity(kk, kk);
    const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(T);
    y = Eigen::VectorXcd::Ones(kk);
    for (int it = 0; it < 3; ++it) {
      y = lu.solve(y);
      y /= y.norm();
    }
    if (order) {
      order->clear();
      for (Index i = 0; i < kk; ++i) order->emplace_back(-std::abs(es.eigenvalues()(i)), i);
      std::sort(order->begin(), order->end());
    }
    if (eigs) *eigs = es.eigenvalues();
  }

  // Restarted Arnoldi on Φ applied as the sequence of step maps. In `decide`
  // mode it stops as soon as the residual of the dominant Ritz value cannot
  // change the verdict ρ < 1 or ρ >= 1 (bracketing needs no more).
  Dominant arnoldi(const PeriodMap& pm, bool want_vector, bool decide = false) const {
    const int d = pm.dim;
    const int k = std::min(d, o_.krylov_dimension);
    MatrixXd V(d, k + 1);
    MatrixXd H = MatrixXd::Zero(k + 1, k);
    std::vector<double> work(static_cast<std::size_t>(2 * pm.n2 + pm.nr + 1));
    // Deterministic, generic start vector.
    VectorXd v(d);
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < d; ++i) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      v(i) = 0.5 + static_cast<double>(state >> 11) * 0x1.0p-53;
    }
    VectorXd w(d), h(k + 1), h2(k + 1);
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
        if (j + 1 >= 8 && j + 1 < k && (j + 1) % 6 == 2) {
          // Early verdict (decide) or early convergence of the dominant Ritz
          // value: a short Krylov space is often enough.
          Cplx th;
          Eigen::VectorXcd yy;
          hessenberg_dominant(H.topLeftCorner(j + 1, j + 1), th, yy, nullptr, &eigs);
          const double res = beta * std::abs(yy(j));
          if ((decide && std::abs(std::abs(th) - 1.0) > kDecideFactor * res) ||
              (!want_vector && res <= kArnoldiTol * std::abs(th))) {
            out.mu = th;
            half_plane_radii(eigs, out);
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
        if (want_vector) out.vec = V.leftCols(kk).cast<Cplx>() * y;
        return out;
      }
      // Restart with the real span of the dominant Ritz vector, plus a little
      // of the next Ritz vectors so that a near-tie is not lost.
      const Eigen::VectorXcd yc = V.leftCols(kk).cast<Cplx>() * y;
      v = yc.real() + yc.imag();
      for (std::size_t t = 1; t < std::min<std::size_t>(order.size(), 5); ++t) {
        const Cplx ti = eigs(order[t].second);
        const Eigen::MatrixXcd T = H.topLeftCorner(kk, kk).cast<Cplx>() -
                                   (ti * (1.0 + 1e-12) + Cplx(0.0, 1e-14 * std::abs(ti))) *
                                       Eigen::MatrixXcd::Identity(kk, kk);
        Eigen::VectorXcd yi = T.partialPivLu().solve(Eigen::VectorXcd::Ones(kk));
        yi /= yi.norm();
        const Eigen::VectorXcd zi = V.leftCols(kk).cast<Cplx>() * yi;
        v += 0.1 * (zi.real() + zi.imag());
      }
      if (!(v.norm() > 0.0)) v = V.col(0);
    }
    return out;
  }

  const MatrixXd& A_;
  const MatrixXd& B_;
  const MatrixXd& Wx_;
  const MatrixXd& U_;
  const SemiDiscretizationOptions& o_;
  const Process* p_;    // real-cutter path only
  const MatrixXd* Sv_;  // 2 × 2n, ṙ = Sv x
};


}  // namespace

// ---------------------------------------------------------------------------

std::string to_string(MultiplierType t) {
  switch (t) {
    case MultiplierType::kHopf: return "hopf";
    case MultiplierType::kFlip: return "flip";
    case MultiplierType::kFold: return "fold";
  }
  return "hopf";
}

std::string SemiDiscretizationOptions::validate() const {
  std::ostringstream os;
  if (steps_per_period < 1)
    os << "steps_per_period = " << steps_per_period << ": must be >= 1";
  else if (steps_per_vibration_cycle < 1)
    os << "steps_per_vibration_cycle = " << steps_per_vibration_cycle << ": must be >= 1";
  else if (max_steps_per_period < 1)
    os << "max_steps_per_period = " << max_steps_per_period << ": must be >= 1";
  else if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    os << "depth_max_m = " << depth_max_m << ": must be > 0 and finite";
  else if (!(depth_tolerance > 0.0 && depth_tolerance < 0.1))
    os << "depth_tolerance = " << depth_tolerance << ": must be in (0, 0.1)";
  else if (!(bracket_ratio > 1.0 && bracket_ratio <= 10.0))
    os << "bracket_ratio = " << bracket_ratio << ": must be in (1, 10]";
  else if (!(bracket_min_ratio > 1.0 && bracket_min_ratio <= bracket_ratio))
    os << "bracket_min_ratio = " << bracket_min_ratio << ": must be in (1, bracket_ratio]";
  else if (bracket_steps < 1)
    os << "bracket_steps = " << bracket_steps << ": must be >= 1";
  else if (dense_max_dimension < 1)
    os << "dense_max_dimension = " << dense_max_dimension << ": must be >= 1";
  else if (krylov_dimension < 4 || krylov_dimension > 400)
    os << "krylov_dimension = " << krylov_dimension << ": must be in [4, 400]";
  else if (axial_slices < 1)
    os << "axial_slices = " << axial_slices << ": must be >= 1";
  return os.str();
}

namespace {

// First pass of the real-cutter map (SdmKernel::build_cutter) at depth a:
// step boundaries 0, T and every engagement event in [0, T); between two
// events the cut is free (one exact step) or cut in ceil(d / h_target) equal
// steps, each with the exact integrals of its share of H per delay group
// (distinct delays τ_k: a tooth, or a slice of a tooth with a variable
// helix) and of the damping direction. Straight teeth: every integral is
// proportional to a, so the grid is built once per speed (a = 1 m) and
// scaled.
CutterGrid cutter_grid(const Process& p, const Grid& g, int axial_slices, double a) {
  CutterGrid cg;
  cg.depth = a;
  const double T = g.tau, rpm = g.rpm;
  const int nt = p.teeth();
  const double ph = p.period_s(rpm);
  const int reps = std::max(1, static_cast<int>(std::lround(T / ph)));
  std::vector<double> bnd{0.0, T};
  const std::vector<double> ev = p.engagement_events_s(rpm, a);
  for (int r = 0; r < reps; ++r)
    for (const double e : ev)
      if (r * ph + e > 0.0 && r * ph + e < T) bnd.push_back(r * ph + e);
  std::sort(bnd.begin(), bnd.end());
  std::vector<double> b;
  for (const double t : bnd)
    if (b.empty() || t - b.back() > kEventMerge * T) b.push_back(t);
  b.back() = T;
  const int slices = (p.has_variable_helix() && a > 0.0) ? axial_slices : 1;
  std::vector<int> group(static_cast<std::size_t>(nt * slices));
  for (int j = 0; j < nt; ++j)
    for (int s = 0; s < slices; ++s) {
      const double tau = p.tooth_delay_s(j, a * (s + 0.5) / slices, rpm);
      std::size_t k = 0;
      while (k < cg.gtau.size() && std::abs(cg.gtau[k] - tau) > kEventMerge * T) ++k;
      if (k == cg.gtau.size()) cg.gtau.push_back(tau);
      group[static_cast<std::size_t>(j * slices + s)] = static_cast<int>(k);
    }
  const std::size_t ng = cg.gtau.size();
  const double h_target = std::min(g.h_target, *std::min_element(cg.gtau.begin(), cg.gtau.end()));
  const MillingParameters& mp = p.milling_parameters();
  const bool damping = p.has_process_damping();
  const double kscale = mp.tangential_coefficient_n_per_m2 + mp.radial_coefficient_n_per_m2;
  cg.t.assign(1, 0.0);
  for (std::size_t s = 0; s + 1 < b.size(); ++s) {
    const double ta = b[s], tb = b[s + 1], d = tb - ta;
    Eigen::Matrix2d tot = Eigen::Matrix2d::Zero();
    for (int j = 0; j < nt; ++j) tot += p.tooth_force_integral(j, ta, tb, a, rpm);
    if (tot.norm() <= kFreeForce * kscale * a * d) {  // free flight: one step with any free neighbour
      if (!cg.free.empty() && cg.free.back()) {
        cg.h.back() += d;
        cg.t.back() = tb;
      } else {
        cg.h.push_back(d);
        cg.free.push_back(1);
        cg.t.push_back(tb);
        cg.F.resize(cg.F.size() + ng, Eigen::Matrix2d::Zero());
        cg.D.push_back(Eigen::Matrix2d::Zero());
      }
      continue;
    }
    const int ns = std::max(1, static_cast<int>(std::ceil(d / h_target - 1e-9)));
    for (int i = 0; i < ns; ++i) {
      const double sa = ta + d * i / ns, sb = (i + 1 == ns) ? tb : ta + d * (i + 1) / ns;
      const std::size_t first = cg.F.size();
      cg.F.resize(first + ng, Eigen::Matrix2d::Zero());
      Eigen::Matrix2d D = Eigen::Matrix2d::Zero();
      for (int j = 0; j < nt; ++j) {
        Eigen::Matrix2d below = Eigen::Matrix2d::Zero();
        for (int sl = 0; sl < slices; ++sl) {
          const Eigen::Matrix2d upto = p.tooth_force_integral(j, sa, sb, a * (sl + 1) / slices, rpm);
          cg.F[first + static_cast<std::size_t>(group[static_cast<std::size_t>(j * slices + sl)])] += upto - below;
          below = upto;
        }
        if (damping) D += p.tooth_damping_integral(j, sa, sb, a, rpm);
      }
      cg.D.push_back(D);
      cg.h.push_back(sb - sa);
      cg.free.push_back(0);
      cg.t.push_back(sb);
    }
  }
  return cg;
}

// Step grid of one delay period at `rpm`, from a tooth entry (milling).
// A, B, U: the solver's free dynamics, force input and delayed-quantity basis.
// Sv: ṙ = Sv x (process damping).
Grid make_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double rpm,
               const MatrixXd& turning_hhat, const MatrixXd& A, const MatrixXd& B, const MatrixXd& U,
               const MatrixXd& Sv) {
  Grid g;
  if (p.operation() == Operation::kMilling &&
      (o.general_cutter_path || p.has_helix() || !p.uniform_cutter() || p.has_process_damping())) {
    // Real cutter: the steps depend on the depth (SdmKernel::build_cutter).
    g.cutter = true;
    g.rpm = rpm;
    // Period: the shortest shift of teeth after which the pitch and helix
    // pattern repeats (Process::floquet_period_s): one tooth period for a
    // uniform cutter, half a revolution for 70/110/70/110°, one revolution
    // for an irregular cutter (and always with general_cutter_path).
    g.tau = o.general_cutter_path ? 60.0 / rpm : p.floquet_period_s(rpm);
    const double tooth = p.delay_s(rpm);
    g.h_target = std::min(tooth / o.steps_per_period, 1.0 / (o.steps_per_vibration_cycle * f_max_hz));
    const double needed = std::ceil(tooth / g.h_target - 1e-9);
    if (needed > o.max_steps_per_period) {
      std::ostringstream os;
      os << "sdm at " << rpm << " rev/min needs about " << needed << " steps per tooth period, more than "
         << "max_steps_per_period = " << o.max_steps_per_period
         << ": raise the speed or max_steps_per_period, or lower steps_per_vibration_cycle";
      throw InputError(os.str());
    }
    if (!p.has_helix()) g.cutter_grid = std::make_shared<const CutterGrid>(cutter_grid(p, g, o.axial_slices, 1.0));
    return g;
  }
  g.tau = p.delay_s(rpm);
  const double h_target = std::min(g.tau / o.steps_per_period, 1.0 / (o.steps_per_vibration_cycle * f_max_hz));
  const double needed = std::ceil(g.tau / h_target - 1e-9);
  if (needed > o.max_steps_per_period) {
    std::ostringstream os;
    os << "sdm at " << rpm << " rev/min needs about " << needed << " steps per delay period, more than "
       << "max_steps_per_period = " << o.max_steps_per_period
       << ": raise the speed or max_steps_per_period, or lower steps_per_vibration_cycle";
    throw InputError(os.str());
  }
  auto count = [&](double duration) {
    return std::max(1, static_cast<int>(std::ceil(duration / h_target - 1e-9)));
  };
  if (p.operation() == Operation::kTurning) {
    g.constant = true;
    g.m = count(g.tau);
    g.steps.push_back({g.tau / g.m, B * turning_hhat * U});
    if (p.has_process_damping()) {  // − a (C_pd/V) B e_x e_xᵀ ṙ
      MatrixXd D = MatrixXd::Zero(2, 2);
      D(0, 0) = p.process_damping_per_depth(rpm);
      g.damping = B * D * Sv;
    }
    return g;
  }
  const MillingParameters& mp = p.milling_parameters();
  const double omega = kTwoPi * rpm / 60.0;          // rad/s
  const double theta_p = kTwoPi / mp.teeth;           // tooth pitch, rad
  const double en = p.entry_angle();
  const double delta = p.exit_angle() - en;            // cutting arc of one tooth
  int K = static_cast<int>(std::floor(delta / theta_p + 1e-12));
  double r = delta - K * theta_p;
  if (r < 1e-12 * theta_p) r = 0.0;
  // Segments [θa, θb] (rad after tooth 0 enters) with `teeth` teeth cutting.
  struct Seg { double a, b; int teeth; };
  std::vector<Seg> segs;
  if (r > 0.0) {
    segs.push_back({0.0, r, K + 1});
    segs.push_back({r, theta_p, K});
  } else {
    segs.push_back({0.0, theta_p, K});
  }
  for (const Seg& s : segs) {
    const double duration = (s.b - s.a) / omega;
    if (s.teeth == 0) {
      g.free_time += duration;
      continue;
    }
    const int ns = count(duration);
    for (int i = 0; i < ns; ++i) {
      const double ta = s.a + (s.b - s.a) * i / ns, tb = s.a + (s.b - s.a) * (i + 1) / ns;
      Eigen::Matrix2d integral = Eigen::Matrix2d::Zero();
      for (int j = 0; j < s.teeth; ++j)
        integral += p.tooth_matrix_antiderivative(en + tb + j * theta_p) -
                    p.tooth_matrix_antiderivative(en + ta + j * theta_p);
      g.steps.push_back({duration / ns, B * (integral / (tb - ta)) * U});
    }
  }
  g.m = static_cast<int>(g.steps.size());
  if (g.free_time > 0.0) g.E_free = (A * g.free_time).exp();
  return g;
}

}  // namespace

SemiDiscretizationSolver::SemiDiscretizationSolver(StructuralModel model, Process process,
                                                   SemiDiscretizationOptions options)
    : model_(std::move(model)), process_(std::move(process)), options_(options) {
  if (const std::string e = options_.validate(); !e.empty()) throw InputError("sdm options: " + e);
  if (model_.mode_count() == 0)
    throw InputError("structural model: both bodies are rigid: give at least one mode");
  if (model_.has_measured())
    throw InputError("sdm needs modes, not measured FRFs: fit modes to the measurement first (chatter fit) "
                     "or use the analytic method");
  const ModalMatrices mm = modal_matrices(model_);
  const Index n = mm.omega.size();
  // Scaled state x = [q; q̇/ω] keeps the exponentials well balanced.
  A_ = MatrixXd::Zero(2 * n, 2 * n);
  B_ = MatrixXd::Zero(2 * n, 2);
  Sv_ = MatrixXd::Zero(2, 2 * n);
  for (Index i = 0; i < n; ++i) {
    const double w = mm.omega(i);
    A_(i, n + i) = w;
    A_(n + i, i) = -w;
    A_(n + i, n + i) = -2.0 * mm.damping_ratio(i) * w;
    B_.row(n + i) = mm.S.col(i).transpose() / (mm.mass_kg(i) * w);
    Sv_.col(n + i) = mm.S.col(i) * w;  // ṙ = S q̇ = S diag(ω) (q̇/ω)
    const double z = mm.damping_ratio(i);
    if (z < 1.0) {
      free_poles_.emplace_back(-z * w, w * std::sqrt(1.0 - z * z));
    } else {  // overdamped: two real poles
      free_poles_.emplace_back(-w * (z - std::sqrt(z * z - 1.0)), 0.0);
      free_poles_.emplace_back(-w * (z + std::sqrt(z * z - 1.0)), 0.0);
    }
  }
  // The slowest free decay, from the same poles (so the two cannot disagree).
  slowest_decay_per_s_ = kInf;
  for (const Cplx& l : free_poles_) slowest_decay_per_s_ = std::min(slowest_decay_per_s_, -l.real());
  f_max_hz_ = model_.max_omega() / kTwoPi;
  // H(t) = Ĥ(t) L: L = e_xᵀ for turning, I for milling. L S = U W by SVD.
  MatrixXd LS = process_.operation() == Operation::kTurning ? MatrixXd(mm.S.topRows(1)) : MatrixXd(mm.S);
  Eigen::JacobiSVD<MatrixXd> svd(LS, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const auto& sv = svd.singularValues();
  Index nr = 0;
  for (Index i = 0; i < sv.size(); ++i)
    if (sv(i) > kRankTol * std::max(sv(0), 1e-300)) ++nr;
  U_ = svd.matrixU().leftCols(nr);
  const MatrixXd W = sv.head(nr).asDiagonal() * svd.matrixV().leftCols(nr).transpose();  // n_r × n
  Wx_ = MatrixXd::Zero(nr, 2 * n);
  Wx_.leftCols(n) = W;
}

namespace {

// Chatter frequency: which member of the family f_k = (arg μ + 2πk)/(2πτ)
// the motion shows (rule in docs/sdm.md). The Floquet solution is
// x(t) = p(t) μ^{t/τ}, p τ-periodic; its spectrum has one line per k with
// the amplitude of the k-th Fourier coefficient of p. The cut-seen
// displacement z = W q of the eigen-solution is reconstructed over one period
// (step maps through the cut, exact exp(A t) through free flight), divided by
// μ^{t/τ}, and its Fourier coefficients are integrated exactly on the
// piecewise-linear interpolant (so that aliases of a line are attenuated by
// sinc², never tied with it). The k with the largest |c_k|² (summed over the
// components of z; |z| = |S q| in milling, the feed direction in turning) wins.

// Highest |f_k| considered, Hz: the natural frequencies with a margin of 100 %
// (milling chatter lies near a mode, above it by a few tens of % at most)
// plus two members above, so that every line near a mode is a candidate.
constexpr double kFrequencyMarginFactor = 2.0;
constexpr int kFrequencyMarginMembers = 2;
// Free flight is sampled at least this many times per period of that
// highest frequency (linear interpolation error of a line's amplitude
// ≈ (π/16)²/6 ≈ 0.6 % at the top of the range, less below).
constexpr int kFreeFlightSamplesPerCycle = 16;
// Below this |u| = |ω h| the Filon weight uses its Taylor series (the closed
// form cancels, losing ~1e-13 there): the first omitted term, u⁶/8!, is
// below 1e-12 relative.
constexpr double kFilonSeriesBelow = 0.05;

// ∫₀¹ (1 − s) e^{−j u s} ds = 1/(ju) + (1 − e^{−ju})/u², given e^{−ju}.
Cplx filon_weight(double u, const Cplx& e_minus_ju) {
  if (std::abs(u) < kFilonSeriesBelow) {
    // Σ (−ju)ⁿ/(n + 2)!
    const Cplx minus_ju(0.0, -u);
    Cplx term(0.5, 0.0), sum(0.0, 0.0);
    for (int n = 0; n < 6; ++n) {
      sum += term;
      term *= minus_ju / static_cast<double>(n + 3);
    }
    return sum;
  }
  return Cplx(0.0, -1.0 / u) + (1.0 - e_minus_ju) / (u * u);
}

// The eigen-solution over one period [0, τ]: the cut-seen displacement
// z = W q at the sample points, stored as runs of equally spaced samples
// (one run per milling segment, one for free flight, one for turning).
struct PeriodSamples {
  struct Run {
    double t0 = 0.0, h = 0.0;  // first sample time and spacing, s
    std::size_t first = 0;     // index of the first sample; the run has n + 1 samples
    std::size_t n = 0;         // intervals
  };
  std::vector<Run> runs;             // consecutive runs share their end samples
  std::vector<Eigen::VectorXcd> z;   // n_r components per sample
  std::vector<double> t;             // sample times, s
};

// From the dominant eigenvector `vec` = [x(0); z(t_i − τ), i < n_z] of Φ:
// step maps through the cut (x complex, carried as real and imaginary parts
// so the real step matrices apply without conversion), then exp(A δ) on a
// grid fine enough for f_top_hz through free flight.
PeriodSamples eigen_solution_samples(const Eigen::VectorXcd& vec, const PeriodMap& pm, const Grid& g,
                                     const MatrixXd& A, const MatrixXd& Wx, double f_top_hz) {
  const int n2 = pm.n2, nr = pm.nr;
  PeriodSamples out;
  VectorXd xr = vec.head(n2).real(), xi = vec.head(n2).imag(), xr_next(n2), xi_next(n2);
  auto z_of = [&](const VectorXd& a, const VectorXd& b) {
    Eigen::VectorXcd z(nr);
    z.real() = Wx * a;
    z.imag() = Wx * b;
    return z;
  };
  const Eigen::VectorXcd z_start = z_of(xr, xi);
  auto push = [&](double t, double h) {  // sample at t, opening an interval of length h
    if (out.runs.empty() || out.runs.back().h != h) out.runs.push_back({t, h, out.z.size(), 0});
    ++out.runs.back().n;
    out.t.push_back(t);
    out.z.push_back(z_of(xr, xi));
  };
  double now = 0.0;
  for (int i = 0; i < pm.m; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const StepMap& s = pm.constant ? pm.steps[0] : pm.steps[si];
    const double h = g.constant ? g.steps[0].h : g.steps[si].h;
    push(now, h);
    const Eigen::VectorXcd z0 = vec.segment(n2 + i * nr, nr);
    const Eigen::VectorXcd z1 = (i + 1 < pm.nz) ? Eigen::VectorXcd(vec.segment(n2 + (i + 1) * nr, nr)) : z_start;
    xr_next.noalias() = s.P * xr;
    xr_next.noalias() += s.R0 * z0.real() + s.R1 * z1.real();
    xi_next.noalias() = s.P * xi;
    xi_next.noalias() += s.R0 * z0.imag() + s.R1 * z1.imag();
    xr.swap(xr_next);
    xi.swap(xi_next);
    now += h;
  }
  if (pm.free_flight) {
    const int pieces = std::max(1, static_cast<int>(std::ceil(g.free_time * f_top_hz * kFreeFlightSamplesPerCycle)));
    const double dt = g.free_time / pieces;
    const MatrixXd E = (A * dt).exp();
    for (int j = 0; j < pieces; ++j) {
      push(now + j * dt, dt);
      xr_next.noalias() = E * xr;
      xi_next.noalias() = E * xi;
      xr.swap(xr_next);
      xi.swap(xi_next);
    }
  }
  out.t.push_back(g.tau);
  out.z.push_back(z_of(xr, xi));
  return out;
}

// The same over one period of the real-cutter map: the map is applied to
// the real and imaginary parts, x recorded at every boundary; free flight is
// sampled as in eigen_solution_samples.
PeriodSamples cutter_solution_samples(const Eigen::VectorXcd& vec, const PeriodMap& pm, const MatrixXd& A,
                                      const MatrixXd& Wx, double f_top_hz) {
  const int n2 = pm.n2, nr = pm.nr;
  const VectorXd yr = vec.real(), yi = vec.imag();
  VectorXd out(pm.dim);
  std::vector<double> rr, ri;
  SdmKernel::apply_cutter(pm, Wx, yr.data(), out.data(), &rr);
  SdmKernel::apply_cutter(pm, Wx, yi.data(), out.data(), &ri);
  PeriodSamples ps;
  auto push = [&](double t, double h, const VectorXd& xr, const VectorXd& xi) {
    if (ps.runs.empty() || ps.runs.back().h != h) ps.runs.push_back({t, h, ps.z.size(), 0});
    ++ps.runs.back().n;
    ps.t.push_back(t);
    Eigen::VectorXcd z(nr);
    z.real() = Wx * xr;
    z.imag() = Wx * xi;
    ps.z.push_back(z);
  };
  const auto& c = pm.cm;
  VectorXd xr(n2), xi(n2);
  for (std::size_t i = 0; i < c.steps.size(); ++i) {
    xr = Eigen::Map<const VectorXd>(rr.data() + i * n2, n2);
    xi = Eigen::Map<const VectorXd>(ri.data() + i * n2, n2);
    const double h = c.steps[i].h;
    if (!c.steps[i].free) {
      push(c.t[i], h, xr, xi);
      continue;
    }
    const int pieces = std::max(1, static_cast<int>(std::ceil(h * f_top_hz * kFreeFlightSamplesPerCycle)));
    const double dt = h / pieces;
    const MatrixXd E = (A * dt).exp();
    for (int j = 0; j < pieces; ++j) {
      push(c.t[i] + j * dt, dt, xr, xi);
      xr = E * xr;
      xi = E * xi;
    }
  }
  const std::size_t last = c.steps.size() * n2;
  Eigen::VectorXcd z(nr);
  z.real() = Wx * Eigen::Map<const VectorXd>(rr.data() + last, n2);
  z.imag() = Wx * Eigen::Map<const VectorXd>(ri.data() + last, n2);
  ps.t.push_back(pm.tau);
  ps.z.push_back(z);
  return ps;
}

double chatter_frequency(const Cplx& mu, const Eigen::VectorXcd& vec, const PeriodMap& pm, const Grid& g,
                         const MatrixXd& A, const MatrixXd& Wx, double f_max_hz) {
  const double tau = g.tau;
  const double arg = std::arg(mu);
  const double alpha = arg / kTwoPi;  // f_k τ = k + α
  const double f_top = kFrequencyMarginFactor * f_max_hz + kFrequencyMarginMembers / tau;
  if (vec.size() != pm.dim || pm.nr == 0) return std::abs(alpha) / tau;  // nothing to look at: k = 0
  PeriodSamples ps = pm.cutter ? cutter_solution_samples(vec, pm, A, Wx, f_top)
                               : eigen_solution_samples(vec, pm, g, A, Wx, f_top);
  // p(t) = z(t) μ^{−t/τ}: periodic for the exact eigen-solution.
  const double log_rho = std::abs(mu) > 0.0 ? std::log(std::abs(mu)) : 0.0;
  for (std::size_t i = 0; i < ps.t.size(); ++i) ps.z[i] *= std::exp(Cplx(-log_rho, -arg) * (ps.t[i] / tau));
  const int k_lo = static_cast<int>(std::ceil(-f_top * tau - alpha));
  const int k_hi = static_cast<int>(std::floor(f_top * tau - alpha));
  const int nk = k_hi - k_lo + 1;
  // On a run of n equal intervals h from t0 (samples p_0 … p_n), with
  // ω = 2πk/τ, u = ω h, e_i = e^{−jω(t0 + i h)} and T = Σ_{i=0..n} p_i e_i:
  //   ∫ (piecewise-linear p) e^{−jωt} dt = h (F(u) (T − p_n e_n) + F(−u) (T − p_0 e_0)),
  // F = filon_weight; T by the recurrence e_{i+1} = e_i e^{−ju}: O(n) per k.
  // Samples as contiguous real and imaginary parts per component, and the
  // products written out in real arithmetic (std::complex's operator* guards
  // against NaN through a library call: 5× slower in this inner loop).
  const std::size_t ns = ps.z.size();
  std::vector<double> zr(ns * static_cast<std::size_t>(pm.nr)), zi(zr.size());
  for (int comp = 0; comp < pm.nr; ++comp)
    for (std::size_t i = 0; i < ns; ++i) {
      zr[comp * ns + i] = ps.z[i](comp).real();
      zi[comp * ns + i] = ps.z[i](comp).imag();
    }
  Eigen::MatrixXcd c = Eigen::MatrixXcd::Zero(pm.nr, nk);
  for (const PeriodSamples::Run& run : ps.runs) {
    for (int j = 0; j < nk; ++j) {
      const double omega = kTwoPi * (k_lo + j) / tau;
      const double u = omega * run.h;
      const Cplx w = std::polar(1.0, -u), e0 = std::polar(1.0, -omega * run.t0);
      for (int comp = 0; comp < pm.nr; ++comp) {
        const double* pr = zr.data() + comp * ns + run.first;
        const double* pi = zi.data() + comp * ns + run.first;
        double er = e0.real(), ei = e0.imag(), tr = 0.0, ti = 0.0;
        const double wr = w.real(), wi = w.imag();
        for (std::size_t i = 0; i <= run.n; ++i) {
          tr += er * pr[i] - ei * pi[i];
          ti += er * pi[i] + ei * pr[i];
          if (i < run.n) {
            const double t = er * wr - ei * wi;
            ei = er * wi + ei * wr;
            er = t;
          }
        }
        const Cplx T(tr, ti), e_end(er, ei), p0(pr[0], pi[0]), pn(pr[run.n], pi[run.n]);
        c(comp, j) += run.h * (filon_weight(u, w) * (T - e_end * pn) + filon_weight(-u, std::conj(w)) * (T - e0 * p0));
      }
    }
  }
  int best = 0;
  double best_power = -1.0;
  for (int j = 0; j < nk; ++j) {
    const double power = c.col(j).squaredNorm();
    if (power > best_power) {
      best_power = power;
      best = j;
    }
  }
  return std::abs((k_lo + best + alpha) / tau);
}

// Ĥ of turning: H = [K_f; 0] e_xᵀ (unused for milling).
MatrixXd turning_hhat_of(const Process& p) {
  MatrixXd h = MatrixXd::Zero(2, 1);
  if (p.operation() == Operation::kTurning) h(0, 0) = p.turning_parameters().feed_force_coefficient_n_per_m2;
  return h;
}

MultiplierType classify(const Cplx& mu) {
  const double a = std::abs(std::arg(mu));
  if (a < kRealAngle) return MultiplierType::kFold;
  if (kPi - a < kRealAngle) return MultiplierType::kFlip;
  return MultiplierType::kHopf;
}

// Turning with a map larger than dense_max_dimension and τ min ζω >=
// kBranchMinDecay: multipliers from the branch roots (SdmKernel::branches).
Grid with_branch_choice(Grid g, double slowest_decay, const SemiDiscretizationOptions& o, Index n2, Index nr) {
  g.branch_roots = o.turning_branch_roots && g.constant && nr == 1 && n2 + g.m * nr > o.dense_max_dimension &&
                   g.tau * slowest_decay >= kBranchMinDecay;
  return g;
}


// Golden-section search for a point where ln ρ >= 0 inside a local maximum
// bracketed by a < b < c with f(b) >= f(a) and f(b) > f(c) (fb = f(b)).
// Returns true with the first such point found, false when the maximum found
// stays below 0 after kBandSearchSteps evaluations.
template <class F>
bool find_band(F&& f, double a, double b, double c, double fb, double& at, double& f_at) {
  constexpr double kGolden = 0.3819660112501051;
  for (int i = 0; i < kBandSearchSteps; ++i) {
    const bool right = (c - b) > (b - a);
    const double x = right ? b + kGolden * (c - b) : b - kGolden * (b - a);
    const double fx = f(x);
    if (fx >= 0.0) {
      at = x;
      f_at = fx;
      return true;
    }
    if (fx > fb) {
      (right ? a : c) = b;
      b = x;
      fb = fx;
    } else {
      (right ? c : a) = x;
    }
  }
  return false;
}

// The Floquet analysis of the map `pm`, built at `depth_m` on grid `g`
// (SemiDiscretizationSolver::analyse after its checks).
FloquetResult floquet_of(const SdmKernel& kernel, const Grid& g, const PeriodMap& pm, double rpm, double depth_m,
                         const MatrixXd& A, const MatrixXd& Wx, double f_max_hz) {
  const Dominant d = kernel.dominant(pm, true);
  FloquetResult r;
  r.spindle_rpm = rpm;
  r.depth_m = depth_m;
  r.spectral_radius = std::abs(d.mu);
  r.dominant_multiplier = d.mu;
  r.type = classify(d.mu);
  // Branch roots (turning at low speed) give the exponent s itself: the
  // solution is e^{st} sampled at the steps, Im s its frequency. A map that
  // overflowed (ρ = +inf) has no eigenvector to take a frequency from: NaN.
  r.chatter_frequency_hz = !std::isfinite(r.spectral_radius) ? std::numeric_limits<double>::quiet_NaN()
                           : d.branch_s != Cplx(0.0, 0.0)    ? std::abs(d.branch_s.imag()) / kTwoPi
                                                              : chatter_frequency(d.mu, d.vec, pm, g, A, Wx, f_max_hz);
  r.steps = pm.cutter ? pm.m : g.m + (pm.free_flight ? 1 : 0);
  r.map_dimension = pm.dim;
  r.period_s = pm.tau;
  r.converged = d.converged;
  return r;
}

// The last two period maps of a depth search, by depth: a depth met again
// (the band search re-reads its lower end, Brent returns a point it has
// evaluated, which the final analysis then reads) reuses its map.
class MapCache {
 public:
  MapCache(const SdmKernel& kernel, const Grid& g) : kernel_(kernel), g_(g) {}
  const PeriodMap& at(double depth) {
    for (int i = 0; i < 2; ++i)
      if (depth_[i] == depth) return maps_[i];
    last_ = 1 - last_;
    depth_[last_] = std::numeric_limits<double>::quiet_NaN();  // not valid if the build throws
    kernel_.build_map(g_, depth, maps_[last_]);
    depth_[last_] = depth;
    return maps_[last_];
  }

 private:
  const SdmKernel& kernel_;
  const Grid& g_;
  PeriodMap maps_[2];
  double depth_[2] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  int last_ = 1;
};

}  // namespace

FloquetResult SemiDiscretizationSolver::analyse(double rpm, double depth_m) const {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  const MatrixXd turning_hhat = turning_hhat_of(process_);
  const Grid g = with_branch_choice(make_grid(process_, options_, f_max_hz_, rpm, turning_hhat, A_, B_, U_, Sv_), slowest_decay_per_s_, options_, A_.rows(), Wx_.rows());
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  PeriodMap pm;
  kernel.build_map(g, depth_m, pm);
  return floquet_of(kernel, g, pm, rpm, depth_m, A_, Wx_, f_max_hz_);
}

StabilityLimit SemiDiscretizationSolver::limit_at(double rpm) const { return limit_at(rpm, nullptr); }

StabilityLimit SemiDiscretizationSolver::limit_at(double rpm, FloquetResult* floquet) const {
  return search(rpm, floquet, std::numeric_limits<double>::quiet_NaN(), nullptr);
}

bool SemiDiscretizationSolver::limit_above(double rpm, double depth_m) const {
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  bool above = false;
  search(rpm, nullptr, depth_m, &above);
  return above;
}

std::optional<bool> SemiDiscretizationSolver::stable_at(double rpm, double depth_m) const {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  if (Wx_.rows() == 0) return true;  // the process cannot see any mode
  const MatrixXd turning_hhat = turning_hhat_of(process_);
  const Grid g = with_branch_choice(make_grid(process_, options_, f_max_hz_, rpm, turning_hhat, A_, B_, U_, Sv_), slowest_decay_per_s_, options_, A_.rows(), Wx_.rows());
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  PeriodMap pm;
  kernel.build_map(g, depth_m, pm);
  // The converged dominant multiplier, not the early-stopped verdict of the
  // depth climb: with many vibration cycles per period the map is far from
  // normal, and a Ritz value with a small residual can lie outside the unit
  // circle while every multiplier lies inside (case C at 100 rev/min).
  return std::abs(kernel.dominant(pm, false).mu) < 1.0;
}

StabilityLimit SemiDiscretizationSolver::search(double rpm, FloquetResult* floquet, double decide_depth,
                                                bool* above) const {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  // Deciding limit > decide_depth only: the search below stops as soon as
  // the answer is sure (it takes the same steps as the whole search).
  const bool deciding = !std::isnan(decide_depth);
  StabilityLimit lim;
  lim.spindle_rpm = rpm;
  if (Wx_.rows() == 0) {  // the process cannot see any mode: never unstable
    if (deciding) *above = true;
    return lim;
  }
  const MatrixXd turning_hhat = turning_hhat_of(process_);
  const Grid g = with_branch_choice(make_grid(process_, options_, f_max_hz_, rpm, turning_hhat, A_, B_, U_, Sv_), slowest_decay_per_s_, options_, A_.rows(), Wx_.rows());
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  MapCache maps(kernel, g);
  auto log_rho = [&](double a) { return std::log(std::abs(kernel.dominant(maps.at(a), false).mu)); };
  // The largest multipliers at depth a: overall (ln ρ), and in the left
  // (Re μ < 0) and right half-planes (early-stopped Arnoldi for large maps).
  struct Radii {
    double all = 0.0;
    Cplx left{0.0, 0.0}, right{0.0, 0.0};
  };
  auto radii = [&](double a) {
    const Dominant d = kernel.dominant(maps.at(a), false, true);
    return Radii{std::log(std::abs(d.mu)), d.mu_left, d.mu_right};
  };
  const double dmax = options_.depth_max_m;
  // While climbing, ρ comes from Arnoldi stopped as soon as the verdict ρ < 1
  // or >= 1 is sure (cheaper than a dense decomposition even for small maps),
  // except for the branch roots of low-speed turning, which are exact.
  const bool accurate = g.branch_roots;
  // At zero depth the multipliers are known exactly: e^{λτ} of the free modes.
  Radii r_zero;
  r_zero.all = -slowest_decay_per_s_ * g.tau;
  for (const Cplx& l : free_poles_) {
    const Cplx mu = std::exp(l * g.tau);
    Cplx& slot = mu.real() < 0.0 ? r_zero.left : r_zero.right;
    if (std::abs(mu) > std::abs(slot)) slot = mu;
  }
  double a = dmax / std::pow(options_.bracket_ratio, options_.bracket_steps);
  Radii r = radii(a);
  double lo = 0.0, flo = r_zero.all, hi = a, fhi = r.all;
  auto unstable = [](double log_rho_value) { return log_rho_value >= 0.0; };
  if (r.all >= 0.0) {
    // Unstable already: go down until stable (ρ(0) < 1 always: damped modes).
    const detail::DepthBracket<double> down = detail::descend_to_stable(
        hi, fhi, options_.bracket_ratio, kMaxDescentSteps, [&](double d) { return radii(d).all; }, unstable);
    lo = down.lo;
    flo = down.at_lo;
    hi = down.hi;
    fhi = down.at_hi;
  } else {
    // Climb from a towards the first crossing of ρ = 1 as a continuation in
    // depth. The largest multipliers of the left half-plane (where flip bands
    // start: a pair meets on the negative real axis and one multiplier runs
    // out through −1, often for a short range of depth) and of the right one
    // are followed; from the distance each moved over the last step, the next
    // step is sized so that neither is predicted to cover more than
    // kMoveFraction of its distance to the unit circle. The secant of ln ρ
    // shortens the step further to just beyond the predicted crossing, and
    // the ratio stays within [1 + kMinClimb, bracket_ratio⁴]. Early-stopped
    // Arnoldi values (large maps) are trusted only with ρ >= 1/4 and then
    // move at most by bracket_ratio.
    double a_prev = 0.0;
    Radii r_prev = r_zero;
    lo = a;
    flo = r.all;
    Radii r_lo = r;
    while (true) {
      if (lo >= dmax) {
        if (deciding) {
          *above = true;
          return lim;
        }
        if (floquet) *floquet = floquet_of(kernel, g, maps.at(dmax), rpm, dmax, A_, Wx_, f_max_hz_);
        return lim;  // stable up to depth_max
      }
      // The root will lie at or above a_prev (a band search below looks no
      // lower), and at or above lo when ρ(lo) <= 1/4 (no band search starts
      // from lo then): above decide_depth, the answer is sure.
      if (deciding && (a_prev > decide_depth || (lo > decide_depth && flo <= kLogQuarter))) {
        *above = true;
        return lim;
      }
      const bool trusted = accurate || (r_lo.all > kLogQuarter && (a_prev == 0.0 || r_prev.all > kLogQuarter));
      double step = (std::pow(options_.bracket_ratio, trusted ? 4 : 1) - 1.0) * lo;
      double move = kInf;
      for (auto [now, before] : {std::pair{r_lo.left, r_prev.left}, std::pair{r_lo.right, r_prev.right}}) {
        const double moved = std::abs(now - before);
        if (moved > 0.0) move = std::min(move, kMoveFraction * (1.0 - std::abs(now)) * (lo - a_prev) / moved);
      }
      // Never shorter than bracket_min_ratio − 1 of the depth on that account,
      // or the approach of a multiplier to the circle would never end.
      step = std::min(step, std::max(move, (options_.bracket_min_ratio - 1.0) * lo));
      const double slope = (flo - r_prev.all) / (lo - a_prev);
      if (trusted && slope > 0.0) step = std::min(step, (-flo / slope) * (1.0 + kSecantOvershoot) + kSecantOvershoot * lo);
      step = std::max(step, kMinClimb * lo);
      hi = std::min(lo + step, dmax);
      const Radii r_hi = radii(hi);
      fhi = r_hi.all;
      if (fhi >= 0.0) break;
      // ln ρ rose, then fell: a local maximum lies in (a_prev, hi), where a
      // thin unstable band would sit. Look for it.
      if (flo >= r_prev.all && fhi < flo - (accurate ? 0.0 : kDecideError * std::abs(flo)) && flo > kLogQuarter) {
        double band = 0.0, fband = 0.0;
        if (find_band(log_rho, a_prev, lo, hi, log_rho(lo), band, fband)) {
          const bool left = band < lo;  // the first crossing lies below the band
          hi = band;
          fhi = fband;
          if (left) {
            lo = a_prev;
            flo = r_prev.all;
          }
          break;
        }
      }
      a_prev = lo;
      r_prev = r_lo;
      lo = hi;
      r_lo = r_hi;
      flo = fhi;
    }
  }
  // The root lies in [lo, hi].
  if (deciding && (hi <= decide_depth || lo > decide_depth)) {
    *above = lo > decide_depth;
    return lim;
  }
  const double root = detail::refine_root(detail::DepthBracket<double>{lo, hi, flo, fhi, true}, log_rho,
                                          options_.depth_tolerance * lo);
  if (deciding) {
    *above = root > decide_depth;
    return lim;
  }
  lim.depth_limit_m = root;
  const FloquetResult fr = floquet_of(kernel, g, maps.at(root), rpm, root, A_, Wx_, f_max_hz_);
  lim.chatter_frequency_hz = fr.chatter_frequency_hz;
  lim.lobe = lobe_number(fr.chatter_frequency_hz, process_.tooth_passing_hz(rpm));
  if (floquet) *floquet = fr;
  return lim;
}

std::vector<double> SemiDiscretizationSolver::spectral_radius_map(const std::vector<double>& rpms,
                                                                  const std::vector<double>& depths_m) const {
  for (double d : depths_m)
    if (!(std::isfinite(d) && d >= 0.0)) throw InputError("stability map: depths must be >= 0 and finite");
  std::vector<double> out;
  out.reserve(rpms.size() * depths_m.size());
  const MatrixXd turning_hhat = turning_hhat_of(process_);
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  PeriodMap pm;
  for (double rpm : rpms) {
    if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
    const Grid g = with_branch_choice(make_grid(process_, options_, f_max_hz_, rpm, turning_hhat, A_, B_, U_, Sv_), slowest_decay_per_s_, options_, A_.rows(), Wx_.rows());
    for (double d : depths_m) {
      kernel.build_map(g, d, pm);
      out.push_back(std::abs(kernel.dominant(pm, false).mu));
    }
  }
  return out;
}

}  // namespace chatter
