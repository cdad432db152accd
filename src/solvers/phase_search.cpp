#include "phase_search.hpp"

#include "extremum.hpp"
#include "roots.hpp"

#include <algorithm>
#include <cstdint>
#include <string>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <Eigen/SVD>

#include "chatter/report.hpp"
#include "chatter/error.hpp"

namespace chatter::detail {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Intervals whose sampled depth is more than this factor above depth_max are
// skipped; the grid criteria bound the variation inside an interval to a few %.
constexpr double kActiveFactor = 2.0;
// Guards against delays holding absurd numbers of vibration cycles (a mode at
// MHz, or a spindle at a fraction of a rev/min): refuse rather than loop.
constexpr double kMaxLobeIndex = 1e12;
constexpr std::size_t kMaxCandidates = 5'000'000;
constexpr double kMaxCurveLobes = 20000;
// Smallest interval the grid refines to, relative to ω.
constexpr double kMinRelativeWidth = 1e-12;
// Branch values below this fraction of the largest one are treated as zero
// (e.g. the null eigenvalue of a rank-one H₀G): their phase is meaningless.
constexpr double kNegligible = 1e-9;
// Evaluation budget of the lowest-depth search (Brent needs ~30 on the two
// grid intervals around the sampled maximum).
constexpr std::uintmax_t kMaximumEvaluations = 200;

double wrap_pi(double d) {  // into (−π, π]
  d = std::remainder(d, kTwoPi);
  return d;
}

}  // namespace

std::pair<double, double> search_band(const StructuralModel& model, const Eigen::Matrix2d& H0,
                                     double depth_max_m) {
  const double h = H0.jacobiSvd().singularValues()(0);
  const double s_min = 1.0 / (kActiveFactor * depth_max_m);
  // Upper bound of 2|λ| >= −2 Re λ = s at ω, valid away from every resonance.
  auto bound = [&](double w, bool above) {
    double g = 0.0;
    for (const Body* body : {&model.tool, &model.workpiece})
      for (const Mode& m : body->modes) {
        const double r = w / m.omega();
        const double d = above ? r * r - 1.0 : 1.0 - r * r;
        if (d <= 0.0) return kInf;
        g += 1.0 / (m.stiffness_n_per_m * d);
      }
    return 2.0 * h * g;
  };
  if (model.has_measured()) {
    // Measured terms are known only on their range: search exactly there.
    const auto [mlo, mhi] = model.measured_band();
    if (!(mhi > mlo)) throw InputError("measured FRFs: their frequency ranges do not overlap");
    return {std::max(mlo, 1e-6 * mhi), mhi};
  }
  const double w_min = model.min_omega(), w_max = model.max_omega();
  double hi = 2.0 * w_max;
  while (bound(hi, true) >= s_min && hi < 1e4 * w_max) hi *= 1.25;
  double lo = 0.5 * w_min;
  while (bound(lo, false) >= s_min && lo > 1e-3 * w_min) lo *= 0.5;
  return {lo, hi};
}


PhaseSearch::PhaseSearch(BranchEvaluator eval, int branches, double omega_lo, double omega_hi,
                         double depth_max_m, PhaseSearchOptions options)
    : eval_(std::move(eval)), branches_(branches), depth_max_m_(depth_max_m), opt_(options) {
  if (branches_ < 0 || branches_ > 2 || !(omega_lo > 0.0) || !(omega_hi > omega_lo) || !(depth_max_m > 0.0))
    throw NumericalError("PhaseSearch: invalid band or depth");
  if (branches_ == 0) {  // the cutting force cannot excite the structure: nothing to search
    omega_ = {omega_lo, omega_hi};
    values_.assign(2, {});
    unwrapped_.assign(2, {0.0, 0.0});
    active_.assign(1, {false, false});
    return;
  }
  const int n0 = std::max(16, static_cast<int>(std::ceil(std::log(omega_hi / omega_lo) / opt_.max_log_step))) + 1;
  std::vector<double> base(static_cast<std::size_t>(n0));
  std::vector<std::array<BranchValue, 2>> base_values(base.size());
  for (int i = 0; i < n0; ++i) {
    base[static_cast<std::size_t>(i)] = omega_lo * std::pow(omega_hi / omega_lo, static_cast<double>(i) / (n0 - 1));
    eval_(base[static_cast<std::size_t>(i)], base_values[static_cast<std::size_t>(i)]);
    for (int b = 0; b < branches_; ++b)
      z_scale_ = std::max(z_scale_, std::abs(base_values[static_cast<std::size_t>(i)][static_cast<std::size_t>(b)].z));
  }
  if (!std::isfinite(z_scale_)) throw NumericalError("PhaseSearch: branch values overflow");
  if (!(z_scale_ > 0.0)) {
    // H₀G vanishes at every frequency (e.g. turning, whose force is along X,
    // on modes along Y only): no depth can be unstable.
    branches_ = 0;
    omega_ = {omega_lo, omega_hi};
    values_.assign(2, {});
    unwrapped_.assign(2, {0.0, 0.0});
    active_.assign(1, {false, false});
    return;
  }

  // Left-to-right adaptive refinement: each new sample is matched to the last
  // accepted one, and an interval is split while it moves too much.
  omega_.push_back(base[0]);
  values_.push_back(base_values[0]);
  std::vector<std::pair<double, std::array<BranchValue, 2>>> stack;
  for (std::size_t j = 1; j < base.size(); ++j) {
    stack.clear();
    stack.emplace_back(base[j], base_values[j]);
    while (!stack.empty()) {
      auto [wb, vb] = stack.back();
      const double wa = omega_.back();
      match(values_.back(), vb);
      if (needs_split(values_.back(), vb, wa, wb) && (wb - wa) > kMinRelativeWidth * wb) {
        const double wm = 0.5 * (wa + wb);
        std::array<BranchValue, 2> vm;
        eval_(wm, vm);
        stack.emplace_back(wm, vm);
      } else {
        omega_.push_back(wb);
        values_.push_back(vb);
        stack.pop_back();
      }
    }
  }

  const std::size_t n = omega_.size();
  unwrapped_.resize(n);
  for (int b = 0; b < branches_; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    unwrapped_[0][bi] = values_[0][bi].phase;
    for (std::size_t i = 1; i < n; ++i)
      unwrapped_[i][bi] = unwrapped_[i - 1][bi] + wrap_pi(values_[i][bi].phase - values_[i - 1][bi].phase);
  }
  active_.assign(n > 0 ? n - 1 : 0, {false, false});
  const double s_min = 1.0 / (kActiveFactor * depth_max_m_);
  for (std::size_t i = 0; i + 1 < n; ++i)
    for (int b = 0; b < branches_; ++b) {
      const auto bi = static_cast<std::size_t>(b);
      active_[i][bi] = std::max(values_[i][bi].s, values_[i + 1][bi].s) > s_min;
    }
}

void PhaseSearch::match(const std::array<BranchValue, 2>& ref, std::array<BranchValue, 2>& v) const {
  if (branches_ < 2) return;
  const double same = std::abs(v[0].z - ref[0].z) + std::abs(v[1].z - ref[1].z);
  const double swap = std::abs(v[1].z - ref[0].z) + std::abs(v[0].z - ref[1].z);
  if (swap < same) std::swap(v[0], v[1]);
}

bool PhaseSearch::needs_split(const std::array<BranchValue, 2>& a, const std::array<BranchValue, 2>& b,
                              double wa, double wb) const {
  if (std::log(wb / wa) > opt_.max_log_step) return true;
  const double floor = kNegligible * z_scale_;
  for (int k = 0; k < branches_; ++k) {
    const auto ki = static_cast<std::size_t>(k);
    const double big = std::max(std::abs(a[ki].z), std::abs(b[ki].z));
    if (big < floor) continue;
    if (std::abs(b[ki].z - a[ki].z) > opt_.max_relative_step * big) return true;
    if (std::abs(wrap_pi(b[ki].phase - a[ki].phase)) > opt_.max_phase_step_rad) return true;
  }
  return false;
}

BranchValue PhaseSearch::continued(int branch, double omega, std::size_t interval, double* unwrapped_phase) const {
  const std::size_t i = std::min(interval, omega_.size() - 2);
  const double t = (omega - omega_[i]) / (omega_[i + 1] - omega_[i]);
  std::array<BranchValue, 2> ref;
  for (int b = 0; b < branches_; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    ref[bi].z = values_[i][bi].z + t * (values_[i + 1][bi].z - values_[i][bi].z);
  }
  std::array<BranchValue, 2> v;
  eval_(omega, v);
  match(ref, v);
  const auto bi = static_cast<std::size_t>(branch);
  if (unwrapped_phase) {
    const double u_ref = unwrapped_[i][bi] + t * (unwrapped_[i + 1][bi] - unwrapped_[i][bi]);
    *unwrapped_phase = v[bi].phase + kTwoPi * std::round((u_ref - v[bi].phase) / kTwoPi);
  }
  return v[bi];
}

PhaseRoot PhaseSearch::lowest_root(double tau) const {
  struct Candidate {
    double s_est;
    int branch;
    std::size_t interval;
    double target;  // 2πn
  };
  std::vector<Candidate> cands;
  const double s_min = 1.0 / (kActiveFactor * depth_max_m_);
  const std::size_t n = omega_.size();
  for (int b = 0; b < branches_; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      if (!active_[i][bi]) continue;
      const double tl = omega_[i] * tau - unwrapped_[i][bi];
      const double tr = omega_[i + 1] * tau - unwrapped_[i + 1][bi];
      const double nl = std::floor(tl / kTwoPi), nr = std::floor(tr / kTwoPi);
      if (nl == nr) continue;
      if (!(std::abs(nl) < kMaxLobeIndex && std::abs(nr) < kMaxLobeIndex) ||
          cands.size() + static_cast<std::size_t>(std::abs(nr - nl)) > kMaxCandidates)
        throw InputError("one delay holds about " + std::to_string(std::llround(omega_.back() * tau / kTwoPi)) +
                         " vibration cycles of the highest mode searched: too many lobes to resolve; raise the "
                         "spindle speed");
      const auto lo = static_cast<std::int64_t>(std::min(nl, nr)) + 1;
      const auto hi = static_cast<std::int64_t>(std::max(nl, nr));
      const double sl = values_[i][bi].s, sr = values_[i + 1][bi].s;
      for (std::int64_t m = lo; m <= hi; ++m) {
        const double target = kTwoPi * static_cast<double>(m);
        const double t = (target - tl) / (tr - tl);
        const double s_est = sl + t * (sr - sl);
        if (s_est > s_min) cands.push_back({s_est, b, i, target});
      }
    }
  }
  std::sort(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) {
    if (x.s_est != y.s_est) return x.s_est > y.s_est;
    if (x.branch != y.branch) return x.branch < y.branch;
    return x.interval < y.interval;
  });

  PhaseRoot best;
  best.depth_m = kInf;
  double best_s = 1.0 / depth_max_m_;  // only limits at or below depth_max count
  for (const Candidate& c : cands) {
    if (c.s_est < best_s * (1.0 - opt_.candidate_margin)) break;
    const std::size_t i = c.interval;
    const auto bi = static_cast<std::size_t>(c.branch);
    auto f = [&](double w) {
      double u;
      continued(c.branch, w, i, &u);
      return w * tau - u - c.target;
    };
    const double fa = omega_[i] * tau - unwrapped_[i][bi] - c.target;
    const double fb = omega_[i + 1] * tau - unwrapped_[i + 1][bi] - c.target;
    const double w = brent_root(f, omega_[i], omega_[i + 1], fa, fb, 1e-15 * omega_[i + 1]);
    const BranchValue v = continued(c.branch, w, i, nullptr);
    if (!(v.s >= best_s)) continue;
    best_s = v.s;
    best.omega = w;
    best.depth_m = 1.0 / v.s;
    best.branch = c.branch;
    best.lobe = lobe_number(w / kTwoPi, 1.0 / tau);
  }
  return best;
}

std::vector<PhaseSearch::Curve> PhaseSearch::curves(double tau_min, double tau_max) const {
  std::vector<Curve> out;
  const double s_min = 1.0 / depth_max_m_;
  const std::size_t n = omega_.size();
  for (int b = 0; b < branches_; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    int k_max = -1;
    double k_top = -1.0;
    for (std::size_t i = 0; i < n; ++i)
      if (values_[i][bi].s > s_min) k_top = std::max(k_top, std::floor(omega_[i] * tau_max / kTwoPi));
    if (k_top > kMaxCurveLobes)
      throw InputError("lobe curves: " + std::to_string(k_top) + " lobes in the speed range (more than " +
                       std::to_string(static_cast<int>(kMaxCurveLobes)) + "); raise the lowest spindle speed");
    k_max = static_cast<int>(k_top);
    for (int k = 0; k <= k_max; ++k) {
      Curve cur{k, b, {}};
      auto flush = [&] {
        if (cur.points.size() >= 2) out.push_back(cur);
        cur.points.clear();
      };
      for (std::size_t i = 0; i < n; ++i) {
        const BranchValue& v = values_[i][bi];
        const double tau = (v.phase + kTwoPi * k) / omega_[i];
        const bool wrapped = i > 0 && std::abs(v.phase - values_[i - 1][bi].phase) > kPi;
        if (wrapped) flush();
        if (v.s > s_min && tau >= tau_min && tau <= tau_max)
          cur.points.push_back({omega_[i], 1.0 / v.s, tau});
        else
          flush();
      }
      flush();
    }
  }
  return out;
}

PhaseRoot PhaseSearch::minimum_depth() const {
  PhaseRoot best;
  best.depth_m = kInf;
  double best_s = 1.0 / depth_max_m_;
  const std::size_t n = omega_.size();
  for (int b = 0; b < branches_; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    std::size_t imax = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (values_[i][bi].s > values_[imax][bi].s) imax = i;
    if (!(values_[imax][bi].s > 0.0)) continue;
    // Brent's maximiser of s on the two intervals around imax (located to
    // √ε of their width: s is flat at its maximum, so its value is exact).
    const double lo = omega_[imax > 0 ? imax - 1 : 0], hi = omega_[std::min(imax + 1, n - 1)];
    auto s_at = [&](double w) {
      const std::size_t i = static_cast<std::size_t>(
          std::max<std::ptrdiff_t>(0, std::upper_bound(omega_.begin(), omega_.end(), w) - omega_.begin() - 1));
      return continued(b, w, i, nullptr).s;
    };
    const Maximum top = maximize_on(s_at, lo, hi, 0.0, kMaximumEvaluations);
    const double w = top.x;
    const double s = top.value;
    if (s > best_s) {
      best_s = s;
      best.omega = w;
      best.depth_m = 1.0 / s;
      best.branch = b;
    }
  }
  return best;
}

}  // namespace chatter::detail
