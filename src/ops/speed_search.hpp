// Internal to the ops layer: the robust speed search behind robust_speed(),
// check_operations() and recommend() (docs/operations.md, "Search"). Exact
// solves of one solver, cached by speed; the scan evenly spaced in 1/rpm;
// the worst limit over a speed band; the robust optimum; pocket edges.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/operations.hpp"
#include "../solvers/extremum.hpp"
#include "ops_internal.hpp"

namespace chatter::detail::ops {


// Scan: kScanStart solves evenly spaced in 1/rpm, then each interval is
// divided so that every lobe gets about kScanPointsPerLobe points (the lobe
// count from the spread of lobe numbers of the first scan), at most
// kScanMaxPoints in all. 8 points per lobe locate every cusp and lobe bottom
// to 1/16 of a lobe; the refinements below work from there.
inline constexpr int kScanStart = 24;
inline constexpr double kScanPointsPerLobe = 8.0;
inline constexpr int kScanMaxPoints = 2000;
// Refined candidates: every local maximum of the scanned objective within
// kCandidateSpread (relative) of the best, at most kMaxCandidates (two
// pockets of nearly equal height are both refined).
inline constexpr double kCandidateSpread = 0.1;
inline constexpr std::size_t kMaxCandidates = 3;
// Maximiser resolution for a robust optimum: 1e-4 of the speed (1 rev/min
// at 10 000), far below a spindle's speed error; at tolerance 0 the optimum
// is a cusp and the old kGoldenRelativeWidth (1e-8) applies.
inline constexpr double kRobustRelativeWidth = 1e-4;
// Lobe bottoms inside a band: 1e-5 of the speed; a bottom is smooth
// (quadratic), so its value is then exact to ~1e-10 relative. Pocket edges:
// 1e-4 of the speed (1 rev/min at 10 000; they are printed in whole rev/min).
inline constexpr double kBottomRelativeWidth = 1e-5;
inline constexpr double kEdgeRelativeWidth = 1e-4;
// The band's two ends are balanced when their limits agree to this (relative).
inline constexpr double kBalanceRelative = 1e-6;
inline constexpr int kEdgeMaxIterations = 60;

// Exact solves of one solver, cached by speed, with the scan and the band
// and pocket searches built on them. Not thread-safe itself; the scan solves
// in parallel.
class SpeedSearch {
 public:
  SpeedSearch(const LobeSolver& solver, double rpm_min, double rpm_max, double tol, unsigned threads)
      : solver_(solver), lo_(rpm_min), hi_(rpm_max), tol_(tol), dmax_(solver.depth_max_m()), threads_(threads) {}

  double tolerance() const { return tol_; }
  double rpm_min() const { return lo_; }
  double rpm_max() const { return hi_; }
  std::size_t solves() const { return solves_; }

  const StabilityLimit& at(double rpm) {
    auto it = cache_.find(rpm);
    if (it == cache_.end()) {
      it = cache_.emplace(rpm, solver_.limit_at(rpm)).first;
      ++solves_;
      if (on_solve) on_solve();
    }
    return it->second;
  }
  /// Called after every exact solve (from worker threads during the scan).
  std::function<void()> on_solve;
  double g(double rpm) { return at(rpm).depth_limit_m; }
  // Solves the speeds not cached yet in parallel (a band's two ends).
  void prefetch(std::initializer_list<double> rpms) {
    std::vector<double> todo;
    for (double r : rpms)
      if (!cache_.count(r) && std::find(todo.begin(), todo.end(), r) == todo.end()) todo.push_back(r);
    if (todo.size() > 1 && threads_ != 1) solve_all(todo);
  }

  // The scan over [rpm_min, rpm_max], evenly spaced in 1/rpm.
  void scan() {
    const double u_lo = 1.0 / hi_, u_hi = 1.0 / lo_;
    auto grid = [&](int n) {
      std::vector<double> r(static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i)
        r[static_cast<std::size_t>(i)] =
            i == 0 ? hi_ : i == n - 1 ? lo_ : 1.0 / (u_lo + (u_hi - u_lo) * static_cast<double>(i) / (n - 1));
      return r;
    };
    solve_all(grid(kScanStart));
    int lobe_lo = std::numeric_limits<int>::max(), lobe_hi = std::numeric_limits<int>::min();
    for (const auto& [rpm, l] : cache_)
      if (l.bounded()) {
        lobe_lo = std::min(lobe_lo, l.lobe);
        lobe_hi = std::max(lobe_hi, l.lobe);
      }
    const double lobes = lobe_hi >= lobe_lo ? static_cast<double>(lobe_hi - lobe_lo + 1) : 1.0;
    const double want = std::min(kScanPointsPerLobe * lobes + 1.0, static_cast<double>(kScanMaxPoints));
    const int split = static_cast<int>(std::ceil((want - 1.0) / (kScanStart - 1)));  // sub-intervals per interval
    if (split > 1) {
      const std::vector<double> all = grid((kScanStart - 1) * split + 1);
      std::vector<double> extra;
      for (std::size_t i = 0; i < all.size(); ++i)
        if (i % static_cast<std::size_t>(split) != 0) extra.push_back(all[i]);
      solve_all(extra);
    }
    for (const auto& [rpm, l] : cache_) scan_.push_back(rpm);  // ascending speed
  }
  const std::vector<double>& scan_speeds() const { return scan_; }

  // Linear interpolation of min(limit, cap) in 1/rpm between scanned speeds
  // (clamped to the scan's ends): the cheap estimate used for ranking.
  double g_scan(double rpm, double cap) {
    cap = std::min(cap, dmax_);
    if (rpm <= scan_.front()) return std::min(g(scan_.front()), cap);
    if (rpm >= scan_.back()) return std::min(g(scan_.back()), cap);
    const auto it = std::upper_bound(scan_.begin(), scan_.end(), rpm);
    const double b = *it, a = *(it - 1);
    const double ga = std::min(g(a), cap), gb = std::min(g(b), cap);
    const double w = (1.0 / rpm - 1.0 / a) / (1.0 / b - 1.0 / a);
    return ga + w * (gb - ga);
  }
  // Scan estimate of the worst limit over the band of `rpm` (no solves).
  double band_min_scan(double rpm, double cap) {
    cap = std::min(cap, dmax_);
    const double a = rpm * (1.0 - tol_), b = rpm * (1.0 + tol_);
    double m = std::min(g_scan(a, cap), g_scan(b, cap));
    for (auto it = std::upper_bound(scan_.begin(), scan_.end(), a); it != scan_.end() && *it < b; ++it)
      m = std::min(m, std::min(g(*it), cap));
    return m;
  }

  // Exact worst limit over [rpm(1 − tol), rpm(1 + tol)]: the band's ends, the
  // scanned speeds inside, and the refined bottom of every lobe whose scanned
  // minimum lies inside (between a scan point's two neighbours; the bottom
  // itself is used only if it lies inside the band — outside it, the limit
  // is monotone towards the band's end, which is already counted).
  double band_min(double rpm) {
    if (tol_ == 0.0) return g(rpm);
    const double a = rpm * (1.0 - tol_), b = rpm * (1.0 + tol_);
    prefetch({a, b});
    double m = std::min(g(a), g(b));
    const auto first = std::upper_bound(scan_.begin(), scan_.end(), a);
    for (auto it = first; it != scan_.end() && *it < b; ++it) {
      const double gi = g(*it);
      m = std::min(m, gi);
      if (!std::isfinite(gi) || it == scan_.begin() || it + 1 == scan_.end()) continue;
      if (gi <= g(*(it - 1)) && gi <= g(*(it + 1))) {  // a scanned lobe bottom
        const auto [x, gx] = bottom(*(it - 1), *(it + 1));
        if (x > a && x < b) m = std::min(m, gx);
      }
    }
    return m;
  }

  // Maximisation of f on [a, b] down to `rel` of the speed (Brent's
  // minimiser, golden section with parabolic steps); returns the best
  // evaluated point.
  template <class F>
  double maximize(F&& f, double a, double b, double rel) {
    return maximize_on(f, a, b, rel * b, kGoldenMaxIterations).x;
  }

  // Edges of the connected interval around `rpm` (where limit > threshold is
  // known) in which the limit stays above `threshold`, inside the range.
  std::pair<double, double> pocket(double rpm, double threshold) {
    return {edge(rpm, threshold, -1), edge(rpm, threshold, +1)};
  }

  // The robust optimum: the speed in range maximising band_min (capped at
  // `cap`: above it every speed is as good, then the one nearest `near`).
  double best(double cap, double near) {
    cap = std::min(cap, dmax_);  // limits are below depth_max or +inf
    std::vector<double> est(scan_.size());
    for (std::size_t i = 0; i < scan_.size(); ++i) est[i] = band_min_scan(scan_[i], cap);
    const double top = *std::max_element(est.begin(), est.end());
    if (top >= cap) {  // speeds with no limit below the cap: the nearest one that holds exactly
      std::vector<std::size_t> idx;
      for (std::size_t i = 0; i < scan_.size(); ++i)
        if (est[i] >= cap) idx.push_back(i);
      std::sort(idx.begin(), idx.end(), [&](std::size_t x, std::size_t y) {
        return std::abs(scan_[x] - near) < std::abs(scan_[y] - near);
      });
      for (std::size_t k = 0; k < std::min(idx.size(), kMaxCandidates); ++k)
        if (band_min(scan_[idx[k]]) >= cap) return scan_[idx[k]];
    }
    std::vector<std::size_t> cand;
    for (std::size_t i = 0; i < scan_.size(); ++i) {
      const bool local = (i == 0 || est[i] >= est[i - 1]) && (i + 1 == scan_.size() || est[i] >= est[i + 1]);
      if (local && est[i] >= (1.0 - kCandidateSpread) * top) cand.push_back(i);
    }
    if (cand.empty())  // only with NaN estimates: the largest one
      cand.push_back(static_cast<std::size_t>(std::max_element(est.begin(), est.end()) - est.begin()));
    std::sort(cand.begin(), cand.end(), [&](std::size_t x, std::size_t y) { return est[x] > est[y]; });
    if (cand.size() > kMaxCandidates) cand.resize(kMaxCandidates);
    const double rel = tol_ > 0.0 ? kRobustRelativeWidth : kGoldenRelativeWidth;
    double best_x = scan_[cand.front()], best_f = band_min(best_x);
    for (std::size_t i : cand) {
      const double a = scan_[i == 0 ? 0 : i - 1], b = scan_[std::min(i + 1, scan_.size() - 1)];
      double x = tol_ > 0.0 ? balance(a, b, rel) : 0.0;
      if (!(x > 0.0)) x = maximize([&](double n) { return std::min(band_min(n), cap); }, a, b, rel);
      for (double y : {x, scan_[i]}) {
        const double fy = std::min(band_min(y), cap);
        if (fy > best_f) best_f = fy, best_x = y;
      }
    }
    return best_x;
  }

  // The band straddling a cusp is best placed where its two ends see the same
  // limit: d(N) = g(N(1 − tol)) − g(N(1 + tol)) = 0, d < 0 left of it. Found
  // by regula falsi (Illinois) in [a, b] when d changes sign there and the
  // band's worst limit at the root is at its ends (no lobe bottom inside);
  // else 0 (the caller falls back on golden-section search). ≈ 2 solves per
  // step, superlinear on the smooth lobe flanks.
  double balance(double a, double b, double rel) {
    if (tol_ == 0.0) return 0.0;
    auto d = [&](double n) {
      prefetch({n * (1.0 - tol_), n * (1.0 + tol_)});
      const double l = g(n * (1.0 - tol_)), r = g(n * (1.0 + tol_));
      if (!std::isfinite(l) || !std::isfinite(r)) return std::numeric_limits<double>::quiet_NaN();
      return l - r;
    };
    prefetch({a * (1.0 - tol_), a * (1.0 + tol_), b * (1.0 - tol_), b * (1.0 + tol_)});
    double fa = d(a), fb = d(b);
    if (!(fa < 0.0 && fb > 0.0)) return 0.0;
    int side = 0;
    double x = a;
    for (int it = 0; it < kEdgeMaxIterations && (b - a) > rel * b; ++it) {
      x = a - fa * (b - a) / (fb - fa);
      if (!(x > a && x < b)) x = 0.5 * (a + b);
      const double fx = d(x);
      if (!std::isfinite(fx)) return 0.0;
      if (fx == 0.0) break;
      if (fx < 0.0) {
        a = x, fa = fx;
        if (side == -1) fb *= 0.5;
        side = -1;
      } else {
        b = x, fb = fx;
        if (side == +1) fa *= 0.5;
        side = +1;
      }
      if (std::abs(fx) <= kBalanceRelative * g(x * (1.0 - tol_))) break;
    }
    const double ends = std::min(g(x * (1.0 - tol_)), g(x * (1.0 + tol_)));
    return band_min(x) < ends ? 0.0 : x;
  }

 private:
  void solve_all(const std::vector<double>& rpms) {
    std::vector<StabilityLimit> lims(rpms.size());
    parallel_for(rpms.size(), threads_, [&](std::size_t i) {
      lims[i] = solver_.limit_at(rpms[i]);
      if (on_solve) on_solve();
    });
    for (std::size_t i = 0; i < rpms.size(); ++i) cache_.emplace(rpms[i], lims[i]);
    solves_ += rpms.size();
  }

  // Minimum of the limit on [a, b] by Brent's minimiser (memoised per bracket).
  std::pair<double, double> bottom(double a, double b) {
    const auto key = std::make_pair(a, b);
    if (const auto it = bottoms_.find(key); it != bottoms_.end()) return it->second;
    const double x = maximize([&](double n) { return -g(n); }, a, b, kBottomRelativeWidth);
    return bottoms_[key] = {x, g(x)};
  }

  // The pocket edge on side `dir` (−1 lower, +1 upper) of `rpm`.
  double edge(double rpm, double threshold, int dir) {
    auto above = [&](double n) { return g(n) > threshold; };
    const double end = dir < 0 ? lo_ : hi_;
    // Walk the scanned speeds outwards to the first one at or below the threshold.
    double inside = rpm, outside = end;
    bool found = false;
    if (dir > 0) {
      for (auto it = std::upper_bound(scan_.begin(), scan_.end(), rpm); it != scan_.end(); ++it) {
        if (!above(*it)) { outside = *it; found = true; break; }
        inside = *it;
      }
    } else {
      for (auto it = std::lower_bound(scan_.begin(), scan_.end(), rpm); it != scan_.begin();) {
        --it;
        if (!above(*it)) { outside = *it; found = true; break; }
        inside = *it;
      }
    }
    if (!found) return end;
    // Regula falsi (Illinois) on limit − threshold, in 1/rpm; an infinite
    // limit is handled by bisection.
    double fi = g(inside) - threshold, fo = g(outside) - threshold;
    int side = 0;
    for (int it = 0; it < kEdgeMaxIterations && std::abs(outside - inside) > kEdgeRelativeWidth * inside; ++it) {
      const double ui = 1.0 / inside, uo = 1.0 / outside;
      double u = std::isfinite(fi) ? uo - fo * (uo - ui) / (fo - fi) : 0.5 * (ui + uo);
      const double lo_u = std::min(ui, uo), hi_u = std::max(ui, uo);
      if (!(u > lo_u && u < hi_u)) u = 0.5 * (ui + uo);
      const double x = 1.0 / u, fx = g(x) - threshold;
      if (fx > 0.0) {
        inside = x, fi = fx;
        if (side == +1) fo *= 0.5;
        side = +1;
      } else {
        outside = x, fo = fx;
        if (side == -1 && std::isfinite(fi)) fi *= 0.5;
        side = -1;
      }
    }
    return inside;
  }

  const LobeSolver& solver_;
  double lo_, hi_, tol_, dmax_;
  unsigned threads_;
  std::map<double, StabilityLimit> cache_;
  std::map<std::pair<double, double>, std::pair<double, double>> bottoms_;
  std::vector<double> scan_;
  std::size_t solves_ = 0;
};

/// The pocket of `rpm`: its exact limit, the worst limit over its band
/// (worst_margin against `depth_m`) and the edges where the limit falls to
/// `threshold_m`.
SpeedPocket make_pocket(SpeedSearch& s, double rpm, double depth_m, double threshold_m);

}  // namespace chatter::detail::ops
