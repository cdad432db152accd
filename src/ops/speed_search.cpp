// Robust spindle speeds: the speed search (src/ops/speed_search.hpp), the
// pocket of a speed and robust_speed() (include/chatter/operations.hpp,
// docs/operations.md "Search").
#include "speed_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <tuple>

#include "chatter/error.hpp"
#include "chatter/operations.hpp"

namespace chatter {
namespace detail::ops {

namespace {

// `n` speeds evenly spaced in 1/rpm from 1/u_a to 1/u_b, both included; the
// ends are the given speeds exactly.
std::vector<double> u_grid(double rpm_a, double rpm_b, int n) {
  const double u_a = 1.0 / rpm_a, u_b = 1.0 / rpm_b;
  std::vector<double> r(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    r[static_cast<std::size_t>(i)] =
        i == 0 ? rpm_a : i == n - 1 ? rpm_b : 1.0 / (u_a + (u_b - u_a) * static_cast<double>(i) / (n - 1));
  return r;
}

}  // namespace

SpeedSearch::SpeedSearch(const LobeSolver& solver, double rpm_min, double rpm_max, double tol, unsigned threads)
    : solver_(solver), lo_(rpm_min), hi_(rpm_max), tol_(tol), dmax_(solver.depth_max_m()), threads_(threads),
      dense_below_(rpm_min) {}

const StabilityLimit& SpeedSearch::at(double rpm) {
  auto it = cache_.find(rpm);
  if (it == cache_.end()) {
    it = cache_.emplace(rpm, solver_.limit_at(SpindleSpeed(rpm))).first;
    ++solves_;
    if (on_solve) on_solve();
  }
  return it->second;
}

void SpeedSearch::prefetch(const std::vector<double>& rpms) {
  std::vector<double> todo;
  for (double r : rpms)
    if (!cache_.count(r) && std::find(todo.begin(), todo.end(), r) == todo.end()) todo.push_back(r);
  if (todo.size() > 1 && threads_ != 1) solve_all(todo);
}

void SpeedSearch::solve_all(const std::vector<double>& all) {
  std::vector<double> rpms;
  for (const double r : all)
    if (!cache_.count(r)) rpms.push_back(r);
  std::vector<StabilityLimit> lims(rpms.size());
  parallel_for(rpms.size(), threads_, [&](std::size_t i) {
    lims[i] = solver_.limit_at(SpindleSpeed(rpms[i]));
    if (on_solve) on_solve();
  });
  for (std::size_t i = 0; i < rpms.size(); ++i) cache_.emplace(rpms[i], lims[i]);
  solves_ += rpms.size();
}

// ------------------------------------------------------------------ scan

void SpeedSearch::scan(bool split_dense) {
  const bool split = split_dense && tol_ > 0.0;
  // The first scan: the whole range, or only its top kProbeSpeedRatio.
  const double probe_lo = split && hi_ / lo_ > kProbeSpeedRatio ? hi_ / kProbeSpeedRatio : lo_;
  solve_all(u_grid(hi_, probe_lo, kScanStart));
  int lobe_lo = std::numeric_limits<int>::max(), lobe_hi = std::numeric_limits<int>::min();
  for (const auto& [rpm, l] : cache_)
    if (l.bounded()) {
      lobe_lo = std::min(lobe_lo, l.lobe);
      lobe_hi = std::max(lobe_hi, l.lobe);
    }
  const double lobes = lobe_hi >= lobe_lo ? static_cast<double>(lobe_hi - lobe_lo + 1) : 1.0;
  const double want = std::min(kScanPointsPerLobe * lobes + 1.0, static_cast<double>(kScanMaxPoints));
  const int split_n = static_cast<int>(std::ceil((want - 1.0) / (kScanStart - 1)));  // sub-intervals per interval
  const double u_top = 1.0 / hi_, u_probe = 1.0 / probe_lo;
  lobes_per_u_ = lobes / (u_probe - u_top);
  scan_step_u_ = (u_probe - u_top) / ((kScanStart - 1) * split_n);

  // Where a band holds kDenseBandLobes lobes: a band spans
  // u (1/(1 − tol) − 1/(1 + tol)) = u 2 tol/(1 − tol²) in 1/rpm.
  double u_end = 1.0 / lo_;
  if (split) {
    const double u_dense = kDenseBandLobes * (1.0 - tol_ * tol_) / (2.0 * tol_ * lobes_per_u_);
    // Scan down to the lower band end of that speed, so that its band is covered.
    u_end = std::min(u_end, u_dense / (1.0 - tol_));
  }
  if (u_end >= 1.0 / lo_ && probe_lo == lo_) {
    // The whole range, as the first scan refined (the same speeds whatever the split).
    if (split_n > 1) {
      const std::vector<double> all = u_grid(hi_, lo_, (kScanStart - 1) * split_n + 1);
      std::vector<double> extra;
      for (std::size_t i = 0; i < all.size(); ++i)
        if (i % static_cast<std::size_t>(split_n) != 0) extra.push_back(all[i]);
      if (!refinement_floor) {
        solve_all(extra);
      } else {
        // From the top down, kRefineChunk speeds at a time, each chunk above
        // the floor the speeds solved so far give (it only rises).
        std::vector<double> solved = u_grid(hi_, probe_lo, kScanStart);
        for (std::size_t k = 0; k < extra.size(); k += kRefineChunk) {
          const double floor = refinement_floor(solved);
          const std::size_t end = std::min(extra.size(), k + kRefineChunk);
          std::size_t j = k;  // extra falls: the speeds from j on are below the floor
          while (j < end && extra[j] >= floor) ++j;
          const std::vector<double> chunk(extra.begin() + static_cast<std::ptrdiff_t>(k),
                                          extra.begin() + static_cast<std::ptrdiff_t>(j));
          solve_all(chunk);
          solved.insert(solved.end(), chunk.begin(), chunk.end());
          if (j < end) {
            skipped_.assign(extra.begin() + static_cast<std::ptrdiff_t>(j), extra.end());
            break;
          }
        }
      }
    }
    for (const auto& [rpm, l] : cache_) scan_.push_back(rpm);  // ascending speed
    dense_below_ = lo_;
    return;
  }
  // Down to u_end at the same spacing (coarser if kScanMaxPoints needs it),
  // the last point at rpm_min if the scan reaches it.
  const double u_lo_end = 1.0 / lo_;
  double step = scan_step_u_;
  const bool refined = std::ceil((u_end - u_top) / step - 1e-9) + 1.0 <= kScanMaxPoints;
  if (!refined) step = (u_end - u_top) / (kScanMaxPoints - 1);
  const auto n = static_cast<int>(std::ceil((u_end - u_top) / step - 1e-9));
  std::vector<double> extra;
  double last = hi_;
  for (int i = 1; i <= n; ++i) {
    const double u = u_top + step * i;
    last = u >= u_lo_end ? lo_ : 1.0 / u;
    if (last == lo_) {
      if (!cache_.count(lo_)) extra.push_back(lo_);
      break;
    }
    // Every split_n-th point of the refined grid is a point of the first scan.
    if (!(refined && i % split_n == 0 && i <= (kScanStart - 1) * split_n)) extra.push_back(last);
  }
  if (refined && n <= (kScanStart - 1) * split_n && n % split_n == 0)
    last = u_grid(hi_, probe_lo, kScanStart)[static_cast<std::size_t>(n / split_n)];  // that point exactly
  solve_all(extra);
  for (const auto& [rpm, l] : cache_)
    if (rpm >= last) scan_.push_back(rpm);
  // Bands of speeds >= dense_below_ lie inside the scan.
  dense_below_ = last > lo_ ? std::min(last / (1.0 - tol_), hi_) : lo_;
}

void SpeedSearch::fill_skipped() {
  if (skipped_.empty()) return;
  solve_all(skipped_);
  scan_.insert(scan_.end(), skipped_.begin(), skipped_.end());
  std::sort(scan_.begin(), scan_.end());
  scan_.erase(std::unique(scan_.begin(), scan_.end()), scan_.end());
  skipped_.clear();
  bands_.clear();
}

void SpeedSearch::extend_scan(double down_to) {
  if (!(dense_below_ > lo_)) return;
  // At least kExtendRatio lower each time (the loop in best() ends).
  down_to = std::max(std::min(down_to, scan_.front() / kExtendRatio), lo_);
  const double u_start = 1.0 / scan_.front(), u_end = 1.0 / down_to, u_lo_end = 1.0 / lo_;
  if (!(u_end > u_start)) return;
  // The scan's spacing, coarser only if kScanMaxPoints needs it.
  double step = scan_step_u_;
  const std::size_t room = scan_.size() + 1 < static_cast<std::size_t>(kScanMaxPoints)
                               ? static_cast<std::size_t>(kScanMaxPoints) - scan_.size()
                               : 1;
  if ((u_end - u_start) / step > static_cast<double>(room)) step = (u_end - u_start) / static_cast<double>(room);
  std::vector<double> extra;
  for (int i = 1;; ++i) {
    const double u = u_start + step * i;
    const double r = u >= u_lo_end ? lo_ : 1.0 / u;
    extra.push_back(r);
    if (r == lo_ || u >= u_end) break;
  }
  solve_all(extra);
  scan_.insert(scan_.end(), extra.begin(), extra.end());
  std::sort(scan_.begin(), scan_.end());
  scan_.erase(std::unique(scan_.begin(), scan_.end()), scan_.end());
  dense_below_ = scan_.front() > lo_ ? std::min(scan_.front() / (1.0 - tol_), hi_) : lo_;
  extensions_ += 1;
}

// --------------------------------------------------------- band minima

double SpeedSearch::g_scan(double rpm, double cap) {
  cap = std::min(cap, dmax_);
  if (rpm <= scan_.front()) return std::min(g(scan_.front()), cap);
  if (rpm >= scan_.back()) return std::min(g(scan_.back()), cap);
  const auto it = std::upper_bound(scan_.begin(), scan_.end(), rpm);
  const double b = *it, a = *(it - 1);
  const double ga = std::min(g(a), cap), gb = std::min(g(b), cap);
  const double w = (1.0 / rpm - 1.0 / a) / (1.0 / b - 1.0 / a);
  return ga + w * (gb - ga);
}

double SpeedSearch::band_min_scan(double rpm, double cap) {
  cap = std::min(cap, dmax_);
  const double a = rpm * (1.0 - tol_), b = rpm * (1.0 + tol_);
  double m = std::min(g_scan(a, cap), g_scan(b, cap));
  for (auto it = std::upper_bound(scan_.begin(), scan_.end(), a); it != scan_.end() && *it < b; ++it)
    m = std::min(m, std::min(g(*it), cap));
  return m;
}

double SpeedSearch::band_min(double rpm) {
  if (tol_ == 0.0) return g(rpm);
  if (const auto it = bands_.find(rpm); it != bands_.end()) return it->second;
  const double a = rpm * (1.0 - tol_), b = rpm * (1.0 + tol_);
  const double m = a >= scan_.front() ? band_min_scanned(a, b) : band_min_sampled(rpm, a, b);
  bands_.emplace(rpm, m);
  return m;
}

// Exact worst limit over [a, b]: the band's ends, the scanned speeds inside,
// and the refined bottom of every lobe whose scanned minimum lies inside
// (between a scan point's two neighbours; the bottom itself is used only if
// it lies inside the band — outside it, the limit is monotone towards the
// band's end, which is already counted).
double SpeedSearch::band_min_scanned(double a, double b) {
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

// A band outside the scan, sampled on its own. Lobe count: the difference of
// the lobe numbers at its ends (+inf limits: the scan's lobe density).
double SpeedSearch::band_min_sampled(double rpm, double a, double b) {
  prefetch({a, b, rpm});
  const StabilityLimit la = at(a), lb = at(b);
  const double lobes = la.bounded() && lb.bounded() ? std::abs(la.lobe - lb.lobe)
                                                    : lobes_per_u_ * (1.0 / a - 1.0 / b);
  if (lobes >= kManyLobes) {
    // kManyLobesSamples speeds evenly in 1/rpm and the band's centre; the
    // lowest sampled local minima refined at their parabola's vertex.
    std::vector<double> x = u_grid(b, a, kManyLobesSamples);
    x.push_back(rpm);
    std::sort(x.begin(), x.end());
    x.erase(std::unique(x.begin(), x.end()), x.end());
    prefetch(x);
    std::vector<double> y(x.size());
    double m = kInf;
    for (std::size_t i = 0; i < x.size(); ++i) m = std::min(m, y[i] = g(x[i]));
    std::vector<std::size_t> minima;
    for (std::size_t i = 1; i + 1 < x.size(); ++i)
      if (std::isfinite(y[i]) && y[i] <= y[i - 1] && y[i] <= y[i + 1]) minima.push_back(i);
    std::sort(minima.begin(), minima.end(), [&](std::size_t p, std::size_t q) { return y[p] < y[q]; });
    if (minima.size() > kManyLobesRefined) minima.resize(kManyLobesRefined);
    std::vector<double> vertices;
    for (const std::size_t i : minima) {
      if (!std::isfinite(y[i - 1]) || !std::isfinite(y[i + 1])) continue;
      const double u0 = 1.0 / x[i - 1], u1 = 1.0 / x[i], u2 = 1.0 / x[i + 1];
      const double d01 = (y[i] - y[i - 1]) / (u1 - u0), d12 = (y[i + 1] - y[i]) / (u2 - u1);
      const double c = (d12 - d01) / (u2 - u0);
      if (!(c > 0.0)) continue;
      const double uv = 0.5 * (u0 + u1) - d01 / (2.0 * c);
      if (uv < std::min(u0, u2) || uv > std::max(u0, u2)) continue;
      vertices.push_back(1.0 / uv);
    }
    prefetch(vertices);
    for (const double v : vertices) m = std::min(m, g(v));
    return m;
  }
  // Few lobes: kScanPointsPerLobe per lobe, every local minimum by Brent.
  const int n = static_cast<int>(std::ceil(kScanPointsPerLobe * std::max(lobes, 1.0))) + 1;
  std::vector<double> x = u_grid(b, a, n);
  std::sort(x.begin(), x.end());
  prefetch(x);
  double m = kInf;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double gi = g(x[i]);
    m = std::min(m, gi);
    if (i == 0 || i + 1 == x.size() || !std::isfinite(gi)) continue;
    if (gi <= g(x[i - 1]) && gi <= g(x[i + 1])) m = std::min(m, bottom(x[i - 1], x[i + 1]).second);
  }
  return m;
}

std::pair<double, double> SpeedSearch::bottom(double a, double b) {
  const auto key = std::make_pair(a, b);
  if (const auto it = bottoms_.find(key); it != bottoms_.end()) return it->second;
  const double x = maximize([&](double n) { return -g(n); }, a, b, kBottomRelativeWidth);
  return bottoms_[key] = {x, g(x)};
}

// ---------------------------------------------------------- the optimum

double SpeedSearch::best(double cap, double near) {
  cap = std::min(cap, dmax_);  // limits are below depth_max or +inf
  double x = best_scanned(cap, near);
  // The dense region cannot beat x if each of its bands holds a speed whose
  // limit is at most x's worst limit. Where that fails, the scan is extended
  // down past the highest failure (at least by kExtendRatio) and the optimum
  // ranked again, until it holds or the scan reaches rpm_min.
  while (dense_below_ > lo_) {
    const double fail = dense_cannot_beat(std::min(band_min(x), cap));
    if (!(fail > 0.0)) break;
    extend_scan(fail);
    x = best_scanned(cap, near);
  }
  return x;
}

double SpeedSearch::best_scanned(double cap, double near) {
  // Candidates: scanned speeds whose band lies inside the scan.
  std::vector<double> est(scan_.size(), -kInf);
  for (std::size_t i = 0; i < scan_.size(); ++i)
    if (scan_[i] >= dense_below_) est[i] = band_min_scan(scan_[i], cap);
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
    if (scan_[i] < dense_below_) continue;
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

double SpeedSearch::dense_cannot_beat(double depth) {
  if (!(dense_below_ > lo_)) return 0.0;
  if (depth >= cleared_depth_) return 0.0;  // shown at a smaller depth already
  // Speeds s_j = rpm_min (1 − tol) r^j, r just below (1 + tol)/(1 − tol), up
  // to dense_below (1 + tol): every band N(1 ± tol) of the region (ratio
  // (1 + tol)/(1 − tol)) holds one of them.
  const double ratio = (1.0 + tol_) / (1.0 - tol_) * (1.0 - 1e-12);
  std::vector<double> s;
  for (double x = lo_ * (1.0 - tol_);; x *= ratio) {
    s.push_back(x);
    if (x >= dense_below_ * (1.0 + tol_)) break;
  }
  // Is the limit at x at most `depth`? From a cached solve, an earlier
  // verdict, else the solver's verdict at the depth (an exact solve when it
  // has none).
  auto known_low = [&](double x) {
    if (const auto it = cache_.find(x); it != cache_.end()) return it->second.depth_limit_m <= depth;
    const auto it = unstable_at_.find(x);
    return it != unstable_at_.end() && it->second <= depth;
  };
  auto settle = [&](const std::vector<double>& xs) {
    std::vector<double> todo;
    for (const double x : xs)
      if (!known_low(x) && !cache_.count(x)) todo.push_back(x);
    std::vector<std::optional<bool>> stable(todo.size());
    parallel_for(todo.size(), threads_, [&](std::size_t i) {
      stable[i] = solver_.stable_at(SpindleSpeed(todo[i]), depth);
      if (on_solve) on_solve();
    });
    std::vector<double> exact;
    for (std::size_t i = 0; i < todo.size(); ++i) {
      if (!stable[i]) exact.push_back(todo[i]);
      else if (!*stable[i]) {
        auto [it, fresh] = unstable_at_.emplace(todo[i], depth);
        if (!fresh) it->second = std::min(it->second, depth);
      }
    }
    solve_all(exact);
  };
  settle(s);
  // A speed not shown low is replaced by two at r^(±1/2) around it: a band
  // (ratio >= r) holding it holds one of those.
  std::vector<double> extra;
  const double half = std::sqrt(ratio);
  for (const double x : s)
    if (!known_low(x)) {
      extra.push_back(x / half);
      extra.push_back(x * half);
    }
  settle(extra);
  // The lowest speed not shown low: the bands of the speeds down to
  // x / (1 + tol) may hold nothing lower, so the scan must reach their
  // lower ends.
  double fail = 0.0;
  for (const double x : extra)
    if (!known_low(x)) fail = std::max(fail, x / (1.0 + tol_) * (1.0 - tol_));
  if (fail > 0.0) return fail;
  cleared_depth_ = depth;
  return 0.0;
}

double SpeedSearch::balance(double a, double b, double rel) {
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

// --------------------------------------------------------------- pockets

bool SpeedSearch::above(double rpm, double depth) {
  if (const auto it = cache_.find(rpm); it != cache_.end()) return it->second.depth_limit_m > depth;
  const auto key = std::make_pair(rpm, depth);
  if (const auto it = above_.find(key); it != above_.end()) return it->second;
  const bool r = solver_.limit_above(SpindleSpeed(rpm), depth);
  if (on_solve) on_solve();
  return above_[key] = r;
}

double SpeedSearch::edge(double rpm, double threshold, int dir) {
  const double end = dir < 0 ? lo_ : hi_;
  // The speeds walked outwards from rpm: the scanned ones, and in the dense
  // region (below the scan) speeds a band's width apart, ending at rpm_min.
  const double step = tol_ > 0.0 ? (1.0 + tol_) / (1.0 - tol_) : 1.0;
  std::vector<double> walk;
  if (dir > 0) {
    if (rpm < scan_.front())
      for (double x = rpm * step; x < scan_.front(); x *= step) walk.push_back(x);
    for (auto it = std::upper_bound(scan_.begin(), scan_.end(), rpm); it != scan_.end(); ++it) walk.push_back(*it);
  } else {
    for (auto it = std::lower_bound(scan_.begin(), scan_.end(), rpm); it != scan_.begin();) walk.push_back(*--it);
    const double from = std::min(rpm, scan_.front());
    if (from > lo_ && step > 1.0) {
      for (double x = from / step; x > lo_; x /= step) walk.push_back(x);
      walk.push_back(lo_);
    }
  }
  // Walk to the first speed at or below the threshold; with several threads
  // the next speeds not known yet are asked in parallel, as many as threads.
  const std::size_t chunk = threads_ == 0 ? std::max(1u, std::thread::hardware_concurrency()) : threads_;
  double inside = rpm, outside = end;
  bool found = false;
  for (std::size_t k = 0; k < walk.size() && !found; ++k) {
    if (chunk > 1) {
      std::vector<double> next;
      for (std::size_t j = k; j < walk.size() && next.size() < chunk; ++j)
        if (!cache_.count(walk[j]) && !above_.count({walk[j], threshold})) next.push_back(walk[j]);
      if (next.size() > 1) {
        std::vector<char> r(next.size(), 0);
        parallel_for(next.size(), threads_, [&](std::size_t i) {
          r[i] = solver_.limit_above(SpindleSpeed(next[i]), threshold) ? 1 : 0;
          if (on_solve) on_solve();
        });
        for (std::size_t i = 0; i < next.size(); ++i) above_[{next[i], threshold}] = r[i] != 0;
      }
    }
    if (!above(walk[k], threshold)) {
      outside = walk[k];
      found = true;
    } else {
      inside = walk[k];
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

SpeedPocket make_pocket(SpeedSearch& s, double rpm, double depth_m, double threshold_m) {
  SpeedPocket p;
  p.limit = s.at(rpm);
  p.speed_tolerance = s.tolerance();
  p.worst_limit_m = s.band_min(rpm);
  p.worst_margin = p.worst_limit_m / depth_m;
  if (s.g(rpm) > threshold_m) std::tie(p.pocket_min_rpm, p.pocket_max_rpm) = s.pocket(rpm, threshold_m);
  else p.pocket_min_rpm = p.pocket_max_rpm = rpm;
  return p;
}

}  // namespace detail::ops

using namespace detail::ops;

std::string validate_speed_tolerance(double tol, const std::string& name) {
  if (std::isfinite(tol) && tol >= 0.0 && tol < 0.5) return "";
  return name + " = " + num(tol * 100.0) + ": must be >= 0 and < 50 (percent)";
}

std::optional<SpeedPocket> robust_speed(const LobeSolver& solver, double rpm_min, double rpm_max, double depth_m,
                                        double speed_tolerance, unsigned threads) {
  if (!(std::isfinite(rpm_min) && rpm_min > 0.0 && std::isfinite(rpm_max) && rpm_max > rpm_min))
    throw InputError("robust_speed: speed range [" + num(rpm_min) + ", " + num(rpm_max) +
                     "] rev/min: need 0 < rpm_min < rpm_max");
  if (!(std::isfinite(depth_m) && depth_m > 0.0))
    throw InputError("robust_speed: depth = " + num(depth_m * 1e3) + " mm: must be > 0");
  if (const std::string e = validate_speed_tolerance(speed_tolerance, "robust_speed: speed tolerance"); !e.empty())
    throw InputError(e);
  SpeedSearch s(solver, rpm_min, rpm_max, speed_tolerance, threads);
  s.scan(true);
  const double n = s.best(kInf, 0.5 * (rpm_min + rpm_max));
  if (!(s.band_min(n) > depth_m)) return std::nullopt;
  return make_pocket(s, n, depth_m, depth_m);
}

}  // namespace chatter
