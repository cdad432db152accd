// First-order semi-discretisation (Insperger & Stépán 2004) of the periodic
// delay equation of docs/physics.md §3, the `sdm` solver. See
// include/chatter/semi_discretization.hpp for the method and docs/sdm.md for
// the convergence study.
#include "chatter/semi_discretization.hpp"

#include "roots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

#include <Eigen/Eigenvalues>
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
// Relative rank threshold for the delayed quantity (entries of S are O(1)).
constexpr double kRankTol = 1e-10;
// Arnoldi: relative residual of the dominant Ritz pair, and restart budget.
constexpr double kArnoldiTol = 1e-10;
constexpr int kArnoldiMaxRestarts = 60;
// While bracketing, Arnoldi stops once | |θ| − 1 | exceeds this many residuals.
constexpr double kDecideFactor = 20.0;

// Antiderivative in φ of Process::tooth_matrix (same closed form as the one
// Process::average_directional_matrix uses).
Eigen::Matrix2d tooth_antiderivative(double kt, double kr, double phi) {
  const double s2 = 0.5 * std::sin(phi) * std::sin(phi);
  const double c = 0.25 * std::sin(2.0 * phi);
  const double ss = 0.5 * phi - c;
  const double cc = 0.5 * phi + c;
  Eigen::Matrix2d m;
  m << kt * s2 + kr * ss, kt * cc + kr * s2, -kt * ss + kr * s2, -kt * s2 + kr * cc;
  return m;
}

// One step of the delay period, independent of the depth.
struct Step {
  double h = 0.0;     // s
  MatrixXd Hhat;      // step average of Ĥ(t): 2 × n_L, N/m²
};

// The step grid of one delay period at one spindle speed.
struct Grid {
  double tau = 0.0;
  std::vector<Step> steps;     // cutting steps, in time order from a tooth entry
  bool constant = false;       // turning: every step identical (steps.size() == 1, count m)
  int m = 0;                   // number of cutting steps
  double free_time = 0.0;      // free-flight duration (s), 0 if a tooth always cuts
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
  MatrixXd E;                  // exp(A t_free)
  int n2 = 0, nr = 0, nz = 0, dim = 0;
};

// Dominant eigenpair of the one-period map.
struct Dominant {
  Cplx mu{0.0, 0.0};
  bool converged = true;
  Eigen::VectorXcd vec;  // empty unless requested
};

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
            const SemiDiscretizationOptions& o)
      : A_(A), B_(B), Wx_(Wx), U_(U), o_(o) {}

  void build_map(const Grid& g, double depth, PeriodMap& pm) const {
    const int n2 = static_cast<int>(A_.rows());
    const int nr = static_cast<int>(Wx_.rows());
    pm.n2 = n2;
    pm.nr = nr;
    pm.m = g.m;
    pm.constant = g.constant;
    pm.free_flight = g.free_time > 0.0;
    pm.nz = pm.free_flight ? g.m + 1 : g.m;
    pm.dim = n2 + pm.nz * nr;
    pm.steps.resize(g.steps.size());
    MatrixXd M = MatrixXd::Zero(n2 + 2 * nr, n2 + 2 * nr);
    for (std::size_t i = 0; i < g.steps.size(); ++i) {
      const Step& s = g.steps[i];
      const MatrixXd Bt = depth * B_ * s.Hhat * U_;  // 2n × n_r
      M.setZero();
      M.topLeftCorner(n2, n2) = (A_ - Bt * Wx_) * s.h;
      M.block(0, n2, n2, nr) = Bt * s.h;
      M.block(n2, n2 + nr, nr, nr).setIdentity();
      const MatrixXd E = M.exp();
      StepMap& sm = pm.steps[i];
      sm.P = E.topLeftCorner(n2, n2);
      sm.R1 = E.block(0, n2 + nr, n2, nr);
      sm.R0 = E.block(0, n2, n2, nr) - sm.R1;
    }
    if (pm.free_flight) pm.E = (A_ * g.free_time).exp();
  }

  // out = Φ y (both of length pm.dim, distinct). work: >= 2 n2 + nr doubles.
  // Dispatches to fixed-size loops for the common small models.
  static void apply(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work) {
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
      const double* E = pm.E.data();
      for (int row = 0; row < n2; ++row) {
        double acc = 0.0;
        for (int c = 0; c < n2; ++c) acc += E[row + c * n2] * x[c];
        xn[row] = acc;
      }
      std::swap(x, xn);
    }
    std::copy(x, x + n2, out);
  }

  // `decide`: only the verdict ρ < 1 or ρ >= 1 matters (bracketing); the
  // Arnoldi iteration can then stop after a few steps, even for small maps.
  Dominant dominant(const PeriodMap& pm, bool want_vector, bool decide = false) const {
    if (pm.dim <= o_.dense_max_dimension && !decide) return dense(pm, want_vector);
    return arnoldi(pm, want_vector, decide);
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
    Eigen::EigenSolver<MatrixXd> es(Phi, want_vector);
    if (es.info() != Eigen::Success) throw NumericalError("sdm: eigen-decomposition of the period map failed");
    Dominant out;
    Index best = 0;
    for (Index i = 1; i < d; ++i)
      if (better(es.eigenvalues()(i), es.eigenvalues()(best))) best = i;
    out.mu = es.eigenvalues()(best);
    if (want_vector) out.vec = es.eigenvectors().col(best);
    return out;
  }

  // Dominant eigenvalue of a small Hessenberg matrix and its unit eigenvector.
  static void hessenberg_dominant(const MatrixXd& Hk, Cplx& theta, Eigen::VectorXcd& y,
                                  std::vector<std::pair<double, Index>>* order, Eigen::VectorXcd* eigs) {
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
      *eigs = es.eigenvalues();
    }
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
        if (decide && j + 1 >= 8 && j + 1 < k && (j + 1) % 6 == 2) {
          // Early verdict: far from the unit circle a short Krylov space is enough.
          Cplx th;
          Eigen::VectorXcd yy;
          hessenberg_dominant(H.topLeftCorner(j + 1, j + 1), th, yy, nullptr, nullptr);
          const double res = beta * std::abs(yy(j));
          if (std::abs(std::abs(th) - 1.0) > kDecideFactor * res) {
            out.mu = th;
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
  return os.str();
}

namespace {

// Step grid of one delay period at `rpm`, from a tooth entry (milling).
Grid make_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double rpm,
               const MatrixXd& turning_hhat) {
  Grid g;
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
    g.steps.push_back({g.tau / g.m, turning_hhat});
    return g;
  }
  const MillingParameters& mp = p.milling_parameters();
  const double kt = mp.tangential_coefficient_n_per_m2, kr = mp.radial_coefficient_n_per_m2;
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
        integral += tooth_antiderivative(kt, kr, en + tb + j * theta_p) -
                    tooth_antiderivative(kt, kr, en + ta + j * theta_p);
      g.steps.push_back({duration / ns, integral / (tb - ta)});
    }
  }
  g.m = static_cast<int>(g.steps.size());
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
                     "or use --method analytic");
  const ModalMatrices mm = modal_matrices(model_);
  const Index n = mm.omega.size();
  // Scaled state x = [q; q̇/ω] keeps the exponentials well balanced.
  A_ = MatrixXd::Zero(2 * n, 2 * n);
  B_ = MatrixXd::Zero(2 * n, 2);
  for (Index i = 0; i < n; ++i) {
    const double w = mm.omega(i);
    A_(i, n + i) = w;
    A_(n + i, i) = -w;
    A_(n + i, n + i) = -2.0 * mm.damping_ratio(i) * w;
    B_.row(n + i) = mm.S.col(i).transpose() / (mm.mass_kg(i) * w);
    natural_hz_.push_back(w / kTwoPi);
  }
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

// Chatter frequency from the dominant multiplier (rule in docs/sdm.md).
double chatter_frequency(const Cplx& mu, const Eigen::VectorXcd& vec, const PeriodMap& pm, const Grid& g,
                         const std::vector<double>& natural_hz) {
  const double tau = g.tau;
  const double arg = std::arg(mu);
  if (!pm.free_flight && pm.nr > 0 && vec.size() == pm.dim && pm.m >= 2) {
    // No free flight: the delayed samples of the eigenvector cover one whole
    // period; their phase advance per step is the chatter frequency (of the
    // dominant harmonic), which fixes k.
    double num = 0.0, den = 0.0;
    for (int i = 0; i + 1 < pm.nz; ++i) {
      const Cplx c = vec.segment(pm.n2 + i * pm.nr, pm.nr).dot(vec.segment(pm.n2 + (i + 1) * pm.nr, pm.nr));
      const double h = g.constant ? g.steps[0].h : g.steps[static_cast<std::size_t>(i)].h;
      num += std::abs(c) * std::arg(c) / h;
      den += std::abs(c);
    }
    if (den > 0.0) {
      const double w_est = num / den;  // rad/s
      const double k = std::round((w_est * tau - arg) / kTwoPi);
      return std::abs((arg + kTwoPi * k) / (kTwoPi * tau));
    }
  }
  // Free flight: f = (k ± |arg μ|/2π)/τ closest to a natural frequency.
  double best = std::abs(arg) / (kTwoPi * tau), err = kInf;
  for (double fn : natural_hz)
    for (double sgn : {1.0, -1.0}) {
      const double base = sgn * std::abs(arg) / kTwoPi;
      const double k = std::round(fn * tau - base);
      const double f = std::abs((base + k) / tau);
      if (std::abs(f - fn) < err) {
        err = std::abs(f - fn);
        best = f;
      }
    }
  return best;
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

}  // namespace

FloquetResult SemiDiscretizationSolver::analyse(double rpm, double depth_m) const {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  const MatrixXd turning_hhat = turning_hhat_of(process_);
  const Grid g = make_grid(process_, options_, f_max_hz_, rpm, turning_hhat);
  const SdmKernel kernel(A_, B_, Wx_, U_, options_);
  PeriodMap pm;
  kernel.build_map(g, depth_m, pm);
  const Dominant d = kernel.dominant(pm, true);
  FloquetResult r;
  r.spindle_rpm = rpm;
  r.depth_m = depth_m;
  r.spectral_radius = std::abs(d.mu);
  r.dominant_multiplier = d.mu;
  r.type = classify(d.mu);
  r.chatter_frequency_hz = chatter_frequency(d.mu, d.vec, pm, g, natural_hz_);
  r.steps = g.m + (pm.free_flight ? 1 : 0);
  r.map_dimension = pm.dim;
  r.converged = d.converged;
  return r;
}

StabilityLimit SemiDiscretizationSolver::limit_at(double rpm) const { return limit_at(rpm, nullptr); }

StabilityLimit SemiDiscretizationSolver::limit_at(double rpm, FloquetResult* floquet) const {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  StabilityLimit lim;
  lim.spindle_rpm = rpm;
  if (Wx_.rows() == 0) return lim;  // the process cannot see any mode: never unstable
  const MatrixXd turning_hhat = turning_hhat_of(process_);
  const Grid g = make_grid(process_, options_, f_max_hz_, rpm, turning_hhat);
  const SdmKernel kernel(A_, B_, Wx_, U_, options_);
  PeriodMap pm;
  auto log_rho = [&](double a) {
    kernel.build_map(g, a, pm);
    return std::log(std::abs(kernel.dominant(pm, false).mu));
  };
  auto log_rho_decide = [&](double a) {
    kernel.build_map(g, a, pm);
    return std::log(std::abs(kernel.dominant(pm, false, true).mu));
  };
  const double dmax = options_.depth_max_m;
  double a = dmax / std::pow(options_.bracket_ratio, options_.bracket_steps);
  double f = log_rho_decide(a);
  double lo = 0.0, flo = -kInf, hi = a, fhi = f;
  if (f >= 0.0) {
    // Unstable already: go down until stable (ρ(0) < 1 always: damped modes).
    for (int i = 0; i < 200 && fhi >= 0.0; ++i) {
      lo = hi / options_.bracket_ratio;
      flo = log_rho_decide(lo);
      if (flo < 0.0) break;
      hi = lo;
      fhi = flo;
    }
  } else {
    lo = a;
    flo = f;
    while (true) {
      if (lo >= dmax) {
        if (floquet) *floquet = analyse(rpm, dmax);
        return lim;  // stable up to depth_max
      }
      // The step shrinks as ρ approaches 1, from bracket_ratio (ρ <= 1/4) to
      // bracket_min_ratio (ρ = 1) as ((1 − ρ)/(3/4))², so that a thin
      // unstable band near the tip of a lobe is not stepped over.
      const double closeness = std::pow(std::clamp((1.0 - std::exp(flo)) / 0.75, 0.0, 1.0), 2);
      const double ratio = options_.bracket_min_ratio +
                           (options_.bracket_ratio - options_.bracket_min_ratio) * closeness;
      hi = std::min(lo * ratio, dmax);
      fhi = log_rho_decide(hi);
      if (fhi >= 0.0) break;
      lo = hi;
      flo = fhi;
    }
  }
  const double root = detail::brent_root(log_rho, lo, hi, flo, fhi, options_.depth_tolerance * lo);
  lim.depth_limit_m = root;
  const FloquetResult fr = analyse(rpm, root);
  lim.chatter_frequency_hz = fr.chatter_frequency_hz;
  lim.lobe = static_cast<int>(std::floor(fr.chatter_frequency_hz * g.tau));
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
  const SdmKernel kernel(A_, B_, Wx_, U_, options_);
  PeriodMap pm;
  for (double rpm : rpms) {
    if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
    const Grid g = make_grid(process_, options_, f_max_hz_, rpm, turning_hhat);
    for (double d : depths_m) {
      kernel.build_map(g, d, pm);
      out.push_back(std::abs(kernel.dominant(pm, false).mu));
    }
  }
  return out;
}

}  // namespace chatter
