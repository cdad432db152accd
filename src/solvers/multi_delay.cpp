// The general per-speed solver of the averaged method (multi_delay.hpp).
#include "multi_delay.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "chatter/error.hpp"
#include "phase_search.hpp"
#include "roots.hpp"

namespace chatter::detail {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
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

// Larger eigenvalue first, the other from the product (no cancellation), as
// AnalyticSolver::eigenvalues.
std::array<Complex, 2> eig2(const Matrix2c& M) {
  const Complex tr = M.trace();
  const Complex det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
  const Complex q = std::sqrt(0.25 * tr * tr - det);
  const Complex big = (std::real(std::conj(tr) * q) >= 0.0) ? 0.5 * tr + q : 0.5 * tr - q;
  const Complex small = (big == Complex(0.0)) ? Complex(0.0) : det / big;
  return {big, small};
}

// Orders v so that its branches continue those of ref.
void match(const std::array<Complex, 2>& ref, std::array<Complex, 2>& v) {
  const double same = std::abs(v[0] - ref[0]) + std::abs(v[1] - ref[1]);
  const double swap = std::abs(v[1] - ref[0]) + std::abs(v[0] - ref[1]);
  if (swap < same) std::swap(v[0], v[1]);
}

}  // namespace

struct MultiDelaySearch::Speed {
  std::vector<double> tau;  // τ_j, s
  double tau_max = 0.0;
  double tau_mean = 0.0;    // mean tooth period (turning: one revolution), s
  double c = 0.0;           // C_pd / V, N·s/m²
};

MultiDelaySearch::MultiDelaySearch(StructuralModel model, Process process, MultiDelayOptions options)
    : model_(std::move(model)), process_(std::move(process)), opt_(options) {
  if (process_.has_variable_helix())
    throw InputError("a variable helix (one process.helix_angle_deg per tooth): the averaged method does not "
                     "handle it (its delays change along the flute)");
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

MultiDelaySearch::Speed MultiDelaySearch::speed(double rpm) const {
  Speed sp;
  if (process_.operation() == Operation::kTurning) {
    sp.tau = {process_.delay_s(rpm)};
  } else {
    for (int j = 0; j < process_.teeth(); ++j) sp.tau.push_back(process_.tooth_delay_s(j, 0.0, rpm));
  }
  sp.tau_max = *std::max_element(sp.tau.begin(), sp.tau.end());
  sp.tau_mean = process_.delay_s(rpm);
  sp.c = process_.process_damping_per_depth(rpm);
  return sp;
}

Matrix2c MultiDelaySearch::characteristic_matrix(double omega, double rpm) const {
  const Speed sp = speed(rpm);
  Complex m(0.0);
  for (double t : sp.tau) m += 1.0 - std::polar(1.0, -omega * t);
  return m * H0_tooth_.cast<Complex>() + Complex(0.0, omega * sp.c) * P0_.cast<Complex>();
}

std::array<Complex, 2> MultiDelaySearch::eigenvalues(double omega, const Speed& sp) const {
  Complex m(0.0);
  for (double t : sp.tau) m += 1.0 - std::polar(1.0, -omega * t);
  const Matrix2c M = m * H0_tooth_.cast<Complex>() + Complex(0.0, omega * sp.c) * P0_.cast<Complex>();
  return eig2(M * model_.receptance(omega));
}

std::array<Complex, 2> MultiDelaySearch::eigenvalues(double omega, double rpm) const {
  return eigenvalues(omega, speed(rpm));
}

StabilityLimit MultiDelaySearch::limit_at(double rpm) const {
  const Speed sp = speed(rpm);
  StabilityLimit lim;
  lim.spindle_rpm = rpm;

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
    lim.lobe = static_cast<int>(std::floor(w * sp.tau_mean / kTwoPi));
    lim.branch = c.branch;
  }
  return lim;
}

}  // namespace chatter::detail
