// The general per-speed solver of the averaged method (multi_delay.hpp).
#include "multi_delay.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "chatter/report.hpp"
#include "chatter/error.hpp"
#include "phase_search.hpp"
#include "roots.hpp"

namespace chatter::detail {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Base grid: largest ln(ω_{i+1}/ω_i), as the phase search.
constexpr double kMaxLogStep = 0.02;
// Smallest base interval, relative to ω (a kink of a measured FRF must not
// make the bisection run forever).
constexpr double kMinRelativeWidth = 1e-9;
// Intervals whose bound of |λ| is below 1/(kActiveFactor·depth_max) are
// skipped; G varies by a few % inside a base interval, the factor covers it.
constexpr double kActiveFactor = 2.0;
// Candidates within this relative margin of the best sampled one are refined
// (the grid bounds the error of the linear estimate to well below it).
constexpr double kCandidateMargin = 0.05;
// Refuse speeds whose sub-grid would need more samples than this (a spindle
// at a fraction of a rev/min on a kHz mode).
constexpr double kMaxSamples = 2e7;
// Variable helix: the fixed point on the depth of the height average stops
// when the depth moves by less than this (relative), after at most so many
// iterations (each a full per-speed search).
constexpr double kHelixDepthTolerance = 1e-12;
constexpr int kMaxHelixIterations = 200;


// Orders v so that its branches continue those of ref.
void match(const std::array<Complex, 2>& ref, std::array<Complex, 2>& v) {
  const double same = std::abs(v[0] - ref[0]) + std::abs(v[1] - ref[1]);
  const double swap = std::abs(v[1] - ref[0]) + std::abs(v[0] - ref[1]);
  if (swap < same) std::swap(v[0], v[1]);
}

}  // namespace

struct MultiDelaySearch::Speed {
  std::vector<double> tau;    // τ_j(0), s
  std::vector<double> slope;  // dτ_j/dz, s/m (variable helix; else 0)
  double depth = 0.0;         // a of the height average (variable helix), m
  double tau_max = 0.0;       // largest τ_j(z) over 0 <= z <= depth, s
  double tau_mean = 0.0;      // mean tooth period (turning: one revolution), s
  double c = 0.0;             // C_pd / V, N·s/m²
  double rpm = 0.0;           // spindle speed, rev/min
};

namespace {

// (1 − e^{−x})/x for x = jy (y real), with its series near 0.
Complex phi1(double y) {
  if (std::abs(y) < 1e-4) return Complex(1.0 - y * y / 6.0, -y / 2.0 + y * y * y / 24.0);
  const Complex x(0.0, y);
  return (1.0 - std::exp(-x)) / x;
}

// Σ_j of the height average (1/a)∫₀ᵃ (1 − e^{−jωτ_j(z)}) dz, τ_j(z) = τ_j + z·slope_j:
// 1 − e^{−jωτ_j} (1 − e^{−jωa·slope_j})/(jωa·slope_j).
template <class Sp>
Complex regeneration(double omega, const Sp& sp) {
  Complex m(0.0);
  for (std::size_t j = 0; j < sp.tau.size(); ++j) {
    const Complex e = std::polar(1.0, -omega * sp.tau[j]);
    m += sp.slope[j] == 0.0 ? 1.0 - e : 1.0 - e * phi1(omega * sp.depth * sp.slope[j]);
  }
  return m;
}

}  // namespace

std::array<Complex, 2> eigenvalues_2x2(const Matrix2c& M) {
  const Complex tr = M.trace();
  const Complex det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
  const Complex q = std::sqrt(0.25 * tr * tr - det);
  const Complex big = (std::real(std::conj(tr) * q) >= 0.0) ? 0.5 * tr + q : 0.5 * tr - q;
  const Complex small = (big == Complex(0.0)) ? Complex(0.0) : det / big;
  return {big, small};
}

MultiDelaySearch::MultiDelaySearch(StructuralModel model, Process process, MultiDelayOptions options)
    : model_(std::move(model)), process_(std::move(process)), opt_(options) {
  const Eigen::Matrix2d H0 = process_.average_directional_matrix();
  H0_tooth_ = H0 / static_cast<double>(process_.teeth());
  P0_ = process_.average_damping_direction();
  bound_h_ = 2.0 * process_.teeth() * H0_tooth_.norm();
  bound_p_ = P0_.norm();

  // Base grid over the band of the phase search (process damping only adds to
  // the damping, so the band where a depth below depth_max can exist is the
  // undamped one for a single mode, and a bound for several).
  const auto [lo, hi] = search_band(model_, H0, opt_.depth_max_m);
  const int n0 = std::max(16, static_cast<int>(std::ceil(std::log(hi / lo) / kMaxLogStep))) + 1;
  auto gnorm = [&](double w) { return model_.receptance(w).norm(); };
  grid_.push_back(lo);
  g_norm_.push_back(gnorm(lo));
  Matrix2c g_prev = model_.receptance(lo);
  for (int i = 1; i < n0; ++i) {
    const double wb0 = lo * std::pow(hi / lo, static_cast<double>(i) / (n0 - 1));
    std::vector<double> stack{wb0};
    while (!stack.empty()) {
      const double wb = stack.back();
      const double wa = grid_.back();
      const Matrix2c gb = model_.receptance(wb);
      const double big = std::max(g_prev.norm(), gb.norm());
      if ((gb - g_prev).norm() > opt_.max_phase_step_rad * big && (wb - wa) > kMinRelativeWidth * wb) {
        stack.push_back(0.5 * (wa + wb));
      } else {
        grid_.push_back(wb);
        g_norm_.push_back(gb.norm());
        g_prev = gb;
        stack.pop_back();
      }
    }
  }
}

MultiDelaySearch::Speed MultiDelaySearch::speed(double rpm, double depth_m) const {
  Speed sp;
  if (!process_.rotating_edges()) {
    sp.tau = {process_.delay_s(rpm)};
    sp.slope = {0.0};
  } else {
    for (int j = 0; j < process_.teeth(); ++j) {
      sp.tau.push_back(process_.tooth_delay_s(j, 0.0, rpm));
      // τ_j(z) is linear in z: its slope from the process (0 unless the
      // helix angles differ between neighbouring teeth).
      sp.slope.push_back(process_.has_variable_helix() ? process_.tooth_delay_s(j, 1.0, rpm) - sp.tau.back() : 0.0);
    }
  }
  sp.depth = depth_m;
  for (std::size_t j = 0; j < sp.tau.size(); ++j)
    sp.tau_max = std::max(sp.tau_max, sp.tau[j] + std::max(0.0, sp.slope[j] * depth_m));
  sp.tau_mean = process_.delay_s(rpm);
  sp.c = process_.process_damping_per_depth(rpm);
  sp.rpm = rpm;
  return sp;
}

Matrix2c MultiDelaySearch::characteristic_matrix(double omega, double rpm, double depth_m) const {
  const Speed sp = speed(rpm, depth_m);
  return regeneration(omega, sp) * H0_tooth_.cast<Complex>() + Complex(0.0, omega * sp.c) * P0_.cast<Complex>();
}

std::array<Complex, 2> MultiDelaySearch::eigenvalues(double omega, const Speed& sp) const {
  const Matrix2c M =
      regeneration(omega, sp) * H0_tooth_.cast<Complex>() + Complex(0.0, omega * sp.c) * P0_.cast<Complex>();
  return eigenvalues_2x2(M * model_.receptance(omega));
}

std::array<Complex, 2> MultiDelaySearch::eigenvalues(double omega, double rpm, double depth_m) const {
  return eigenvalues(omega, speed(rpm, depth_m));
}

StabilityLimit MultiDelaySearch::limit_at(double rpm) const {
  if (!process_.has_variable_helix()) return limit_at(speed(rpm, 0.0));
  // Variable helix: M depends on the depth through the height average of the
  // delays. F(a) = the limit with M frozen at a; the boundary is the smallest
  // a with F(a) = a, where h(a) = F(a) − a changes sign (h(0) = F(0) > 0;
  // F = +inf, no limit below depth_max, counts as h > 0). March up from a = 0
  // with the fixed-point step a → F(a), never shorter than the step before
  // (a plain fixed point crawls where h nearly touches 0), until h <= 0
  // brackets the root; then Brent's method on h.
  auto limit_with = [&](double a) { return limit_at(speed(rpm, a)); };
  auto h_of = [&](const StabilityLimit& l, double a) {
    return (l.bounded() ? l.depth_limit_m : opt_.depth_max_m + 1.0) - a;  // finite, > 0 when unbounded
  };
  double lo = 0.0, h_lo = 0.0, hi = 0.0, h_hi = 0.0, stride = 0.0, a = 0.0;
  bool bracketed = false;
  for (int it = 0; it < kMaxHelixIterations && !bracketed; ++it) {
    const StabilityLimit l = limit_with(a);
    const double h = h_of(l, a);
    if (l.bounded() && std::abs(h) <= kHelixDepthTolerance * l.depth_limit_m) return l;
    if (h <= 0.0) {
      hi = a;
      h_hi = h;
      bracketed = true;
      break;
    }
    if (a >= opt_.depth_max_m) return StabilityLimit{rpm};  // no self-consistent limit below depth_max
    lo = a;
    h_lo = h;
    stride = std::max(stride, std::min(h, opt_.depth_max_m - a));
    a = std::min(opt_.depth_max_m, a + stride);
  }
  if (!bracketed)
    throw NumericalError("variable helix at " + std::to_string(rpm) +
                         " rev/min: the depth iteration of the height-averaged delays did not converge");
  const double root = brent_root([&](double x) { return h_of(limit_with(x), x); }, lo, hi, h_lo, h_hi,
                                 kHelixDepthTolerance * hi);
  // At a root of h, F(root) = root; where h jumps between lobes instead, the
  // limit is the jump depth (F above it on one side, below on the other),
  // reported with the frequency and lobe of the side just above.
  StabilityLimit l = limit_with(root);
  if (!l.bounded() || l.depth_limit_m > root) l = limit_with(std::min(hi, root * (1.0 + 4.0 * kHelixDepthTolerance)));
  if (l.bounded()) l.depth_limit_m = std::min(l.depth_limit_m, root);
  return l;
}

StabilityLimit MultiDelaySearch::limit_at(const Speed& sp) const {
  StabilityLimit lim;
  lim.spindle_rpm = sp.rpm;

  // The sub-grid: each active base interval split so that ω τ_max moves by at
  // most max_phase_step_rad; runs of active intervals keep branch identity.
  struct Sample {
    double w;
    std::array<Complex, 2> l;
  };
  struct Candidate {
    double s_est;
    int branch;
    Sample a, b;
  };
  std::vector<Candidate> cands;
  const double s_floor = 1.0 / (kActiveFactor * opt_.depth_max_m);
  double samples = 0.0;
  std::vector<Sample> run;
  auto scan_run = [&] {
    for (std::size_t i = 0; i + 1 < run.size(); ++i)
      for (int b = 0; b < 2; ++b) {
        const Complex la = run[i].l[static_cast<std::size_t>(b)], lb = run[i + 1].l[static_cast<std::size_t>(b)];
        if ((la.imag() > 0.0) == (lb.imag() > 0.0) && la.imag() != 0.0 && lb.imag() != 0.0) continue;
        if (!(la.real() < 0.0 || lb.real() < 0.0)) continue;
        const double den = la.imag() - lb.imag();
        const double t = den == 0.0 ? 0.5 : la.imag() / den;
        const double s_est = -(la.real() + t * (lb.real() - la.real()));
        if (s_est > s_floor) cands.push_back({s_est, b, run[i], run[i + 1]});
      }
    run.clear();
  };
  for (std::size_t i = 0; i + 1 < grid_.size(); ++i) {
    const double wa = grid_[i], wb = grid_[i + 1];
    const double bound = (bound_h_ + wb * sp.c * bound_p_) * std::max(g_norm_[i], g_norm_[i + 1]);
    if (!(bound > s_floor)) {
      scan_run();
      continue;
    }
    const int n = std::max(1, static_cast<int>(std::ceil((wb - wa) * sp.tau_max / opt_.max_phase_step_rad)));
    samples += n;
    if (samples > kMaxSamples)
      throw InputError("one delay holds too many vibration cycles of the modes searched (more than " +
                       std::to_string(static_cast<long long>(kMaxSamples)) +
                       " frequency samples needed): raise the spindle speed");
    if (run.empty()) run.push_back({wa, eigenvalues(wa, sp)});
    for (int k = 1; k <= n; ++k) {
      const double w = (k == n) ? wb : wa + (wb - wa) * static_cast<double>(k) / n;
      Sample s{w, eigenvalues(w, sp)};
      match(run.back().l, s.l);
      run.push_back(s);
    }
  }
  scan_run();

  std::sort(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) {
    if (x.s_est != y.s_est) return x.s_est > y.s_est;
    if (x.branch != y.branch) return x.branch < y.branch;
    return x.a.w < y.a.w;
  });
  double best_s = 1.0 / opt_.depth_max_m;  // only limits at or below depth_max count
  for (const Candidate& c : cands) {
    if (c.s_est < best_s * (1.0 - kCandidateMargin)) break;
    const auto bi = static_cast<std::size_t>(c.branch);
    // The branch at ω, identified by the interpolation between the ends.
    auto branch_at = [&](double w) {
      const double t = (w - c.a.w) / (c.b.w - c.a.w);
      std::array<Complex, 2> ref{c.a.l[0] + t * (c.b.l[0] - c.a.l[0]), c.a.l[1] + t * (c.b.l[1] - c.a.l[1])};
      std::array<Complex, 2> v = eigenvalues(w, sp);
      match(ref, v);
      return v[bi];
    };
    const double w = brent_root([&](double x) { return branch_at(x).imag(); }, c.a.w, c.b.w, c.a.l[bi].imag(),
                                c.b.l[bi].imag(), 1e-15 * c.b.w);
    const Complex l = branch_at(w);
    const double s = -l.real();
    if (!(s >= best_s)) continue;
    best_s = s;
    lim.depth_limit_m = 1.0 / s;
    lim.chatter_frequency_hz = w / kTwoPi;
    lim.lobe = lobe_number(w / kTwoPi, 1.0 / sp.tau_mean);
    lim.branch = c.branch;
  }
  return lim;
}

}  // namespace chatter::detail
