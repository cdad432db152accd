// The Floquet analysis at one point of the `sdm` solver: the type of the
// dominant multiplier (hopf, flip, fold) and the chatter-frequency rule
// (which member of the family (arg μ + 2πk)/(2πτ) the motion shows;
// docs/sdm.md). Part of the `sdm` solver (sdm_internal.hpp).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>

#include <unsupported/Eigen/MatrixFunctions>

namespace chatter::sdm_detail {
namespace {

// A multiplier is real when |arg μ| or π − |arg μ| is below this (rad): real
// eigenvalues come out of the real Schur form with Im exactly 0; the margin
// only absorbs round-off of nearly coalescing real pairs.
constexpr double kRealAngle = 1e-6;

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
// Sample-major storage, no allocation per sample: the free flight alone has
// hundreds of samples, and a vector per sample cost as much as the rest of
// the analysis.
struct PeriodSamples {
  struct Run {
    double t0 = 0.0, h = 0.0;  // first sample time and spacing, s
    std::size_t first = 0;     // index of the first sample; the run has n + 1 samples
    std::size_t n = 0;         // intervals
  };
  explicit PeriodSamples(int components) : nr(components), zr_(components), zi_(components) {}
  std::vector<Run> runs;  // consecutive runs share their end samples
  int nr;                 // components of z
  std::vector<double> zr, zi;  // Re z, Im z of sample i, component c at i nr + c
  std::vector<double> t;       // sample times, s
  std::size_t size() const { return t.size(); }
  // Appends the sample z = Wx (x_re + j x_im) at time `at`.
  void add(double at, const MatrixXd& Wx, const VectorXd& x_re, const VectorXd& x_im) {
    zr_.noalias() = Wx * x_re;
    zi_.noalias() = Wx * x_im;
    zr.insert(zr.end(), zr_.data(), zr_.data() + nr);
    zi.insert(zi.end(), zi_.data(), zi_.data() + nr);
    t.push_back(at);
  }
  // The same, opening an interval of length h (a new run when h changes).
  void add_opening(double at, double h, const MatrixXd& Wx, const VectorXd& x_re, const VectorXd& x_im) {
    if (runs.empty() || runs.back().h != h) runs.push_back({at, h, size(), 0});
    ++runs.back().n;
    add(at, Wx, x_re, x_im);
  }

 private:
  VectorXd zr_, zi_;  // one sample's product, reused
};

// From the dominant eigenvector `vec` = [x(0); z(t_i − τ), i < n_z] of Φ:
// step maps through the cut (x complex, carried as real and imaginary parts
// so the real step matrices apply without conversion), then exp(A δ) on a
// grid fine enough for f_top_hz through free flight.
PeriodSamples eigen_solution_samples(const Eigen::VectorXcd& vec, const PeriodMap& pm, const Grid& g,
                                     const MatrixXd& A, const MatrixXd& Wx, double f_top_hz) {
  const int n2 = pm.n2, nr = pm.nr;
  PeriodSamples out(nr);
  VectorXd xr = vec.head(n2).real(), xi = vec.head(n2).imag(), xr_next(n2), xi_next(n2);
  Eigen::VectorXcd z_start(nr);  // z(0) = W x(0), read again at the period's end
  z_start.real() = Wx * xr;
  z_start.imag() = Wx * xi;
  double now = 0.0;
  for (int i = 0; i < pm.m; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const StepMap& s = pm.constant ? pm.steps[0] : pm.steps[si];
    const double h = g.constant ? g.steps[0].h : g.steps[si].h;
    out.add_opening(now, h, Wx, xr, xi);
    now += h;
    if (pm.path == MapPath::kToothCollocation) {  // collocation: x_{i+1} = P x_i + Rc ζ_i
      const int snr = pm.nodes * nr;
      const Eigen::VectorXcd zeta = vec.segment(n2 + i * snr, snr);
      xr_next.noalias() = s.P * xr;
      xr_next.noalias() += s.Rc * zeta.real();
      xi_next.noalias() = s.P * xi;
      xi_next.noalias() += s.Rc * zeta.imag();
      xr.swap(xr_next);
      xi.swap(xi_next);
      continue;
    }
    const Eigen::VectorXcd z0 = vec.segment(n2 + i * nr, nr);
    const Eigen::VectorXcd z1 = (i + 1 < pm.nz) ? Eigen::VectorXcd(vec.segment(n2 + (i + 1) * nr, nr)) : z_start;
    xr_next.noalias() = s.P * xr;
    xr_next.noalias() += s.R0 * z0.real() + s.R1 * z1.real();
    xi_next.noalias() = s.P * xi;
    xi_next.noalias() += s.R0 * z0.imag() + s.R1 * z1.imag();
    xr.swap(xr_next);
    xi.swap(xi_next);
  }
  if (pm.free_flight) {
    const int pieces = std::max(1, static_cast<int>(std::ceil(g.free_time * f_top_hz * kFreeFlightSamplesPerCycle)));
    const double dt = g.free_time / pieces;
    const MatrixXd E = (A * dt).exp();
    for (int j = 0; j < pieces; ++j) {
      out.add_opening(now + j * dt, dt, Wx, xr, xi);
      xr_next.noalias() = E * xr;
      xi_next.noalias() = E * xi;
      xr.swap(xr_next);
      xi.swap(xi_next);
    }
  }
  out.add(g.tau, Wx, xr, xi);
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
  const bool nodes = pm.path == MapPath::kCutterCollocation;  // pm.cc, or first-order steps (pm.cm)
  for (auto [y, rec] : {std::pair{&yr, &rr}, std::pair{&yi, &ri}}) {
    if (nodes)
      SdmKernel::apply_cutter_collocation(pm, y->data(), out.data(), rec);
    else
      SdmKernel::apply_cutter(pm, Wx, y->data(), out.data(), rec);
  }
  PeriodSamples ps(nr);
  const std::vector<double>& t = nodes ? pm.cc.t : pm.cm.t;
  const std::size_t M = t.size() - 1;
  VectorXd xr(n2), xi(n2);
  for (std::size_t i = 0; i < M; ++i) {
    xr = Eigen::Map<const VectorXd>(rr.data() + i * n2, n2);
    xi = Eigen::Map<const VectorXd>(ri.data() + i * n2, n2);
    const double h = nodes ? pm.cc.steps[i].h : pm.cm.steps[i].h;
    if (!(nodes ? pm.cc.steps[i].free : pm.cm.steps[i].free)) {
      ps.add_opening(t[i], h, Wx, xr, xi);
      continue;
    }
    const int pieces = std::max(1, static_cast<int>(std::ceil(h * f_top_hz * kFreeFlightSamplesPerCycle)));
    const double dt = h / pieces;
    const MatrixXd E = (A * dt).exp();
    for (int j = 0; j < pieces; ++j) {
      ps.add_opening(t[i] + j * dt, dt, Wx, xr, xi);
      xr = E * xr;
      xi = E * xi;
    }
  }
  const std::size_t last = M * n2;
  xr = Eigen::Map<const VectorXd>(rr.data() + last, n2);
  xi = Eigen::Map<const VectorXd>(ri.data() + last, n2);
  ps.add(pm.tau, Wx, xr, xi);
  return ps;
}

}  // namespace

double chatter_frequency(const Cplx& mu, const Eigen::VectorXcd& vec, const PeriodMap& pm, const Grid& g,
                         const MatrixXd& A, const MatrixXd& Wx, double f_max_hz) {
  const double tau = g.tau;
  const double arg = std::arg(mu);
  const double alpha = arg / kTwoPi;  // f_k τ = k + α
  const double f_top = kFrequencyMarginFactor * f_max_hz + kFrequencyMarginMembers / tau;
  if (vec.size() != pm.dim || pm.nr == 0) return std::abs(alpha) / tau;  // nothing to look at: k = 0
  PeriodSamples ps = on_cutter_grid(pm.path) ? cutter_solution_samples(vec, pm, A, Wx, f_top)
                               : eigen_solution_samples(vec, pm, g, A, Wx, f_top);
  // p(t) = z(t) μ^{−t/τ}: periodic for the exact eigen-solution.
  const double log_rho = std::abs(mu) > 0.0 ? std::log(std::abs(mu)) : 0.0;
  const std::size_t ns = ps.size();
  const auto nr = static_cast<std::size_t>(pm.nr);
  // Component-major: component c of sample i at c ns + i.
  std::vector<double> zr(ns * nr), zi(zr.size());
  for (std::size_t i = 0; i < ns; ++i) {
    const Cplx e = std::exp(Cplx(-log_rho, -arg) * (ps.t[i] / tau));
    for (std::size_t comp = 0; comp < nr; ++comp) {
      Cplx z(ps.zr[i * nr + comp], ps.zi[i * nr + comp]);
      z *= e;
      zr[comp * ns + i] = z.real();
      zi[comp * ns + i] = z.imag();
    }
  }
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

MultiplierType classify(const Cplx& mu) {
  const double a = std::abs(std::arg(mu));
  if (a < kRealAngle) return MultiplierType::kFold;
  if (kPi - a < kRealAngle) return MultiplierType::kFlip;
  return MultiplierType::kHopf;
}

// The Floquet analysis of the map `pm`, built at `depth_m` on grid `g`
// (SemiDiscretizationSolver::analyse after its checks).
FloquetResult floquet_of(const SdmKernel& kernel, const Grid& g, const PeriodMap& pm, double rpm, double depth_m,
                         const MatrixXd& A, const MatrixXd& Wx, double f_max_hz, const Dominant* known) {
  const Dominant d = known ? *known : kernel.dominant(pm, true);
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
  r.steps = on_cutter_grid(pm.path) ? pm.m : g.m + (pm.free_flight ? 1 : 0);
  r.map_dimension = pm.dim;
  r.period_s = pm.tau;
  r.converged = d.converged;
  return r;
}

}  // namespace chatter::sdm_detail
