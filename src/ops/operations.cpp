// Operation check, recommendation and fast lobe-table queries
// (include/chatter/operations.hpp, docs/operations.md).
#include "chatter/operations.hpp"

#include <algorithm>
#include <atomic>
#include <initializer_list>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <sstream>
#include <tuple>

#include "chatter/error.hpp"
#include "chatter/report.hpp"
#include "chatter/solvers.hpp"
#include "../io/text.hpp"
#include "../solvers/extremum.hpp"

namespace chatter {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;

// Interval splitting stops at this fraction of the table's 1/rpm range: about
// 21 halvings below a 400-point base grid, far below any lobe feature.
constexpr double kMinRelativeWidth = 1e-9;
// Speed maximisations (Brent: golden section with parabolic steps,
// src/solvers/extremum.hpp) stop when x is located to this
// fraction of the speed (≈ 1e-4 rev/min at 10 000 rev/min: well below what a
// spindle holds); at most kGoldenMaxIterations limit_at() calls.
constexpr double kGoldenRelativeWidth = 1e-8;
constexpr int kGoldenMaxIterations = 100;
// Two MRR values this close (relative) are a tie: power-bound MRR is the same
// at every speed up to round-off.
constexpr double kTieRelative = 1e-9;
// A depth cap within this relative distance of the chosen depth binds too.
// The speed search locates the optimum to 1e-8 of the speed; on a
// steep lobe flank (d ln limit / d ln N up to ~10³) two caps that cross at the
// optimum then differ by up to ~1e-5.
constexpr double kBindingRelative = 1e-5;
// With a speed tolerance the optimum is bracketed to kRobustRelativeWidth
// (1e-4 of the speed): on a flank of log-slope up to 10 crossing caps then
// differ by up to 1e-3.
constexpr double kRobustBindingRelative = 1e-3;
// The recommendation searches limits up to this multiple of depth_max/safety,
// so a limit near the tool's depth cap is still reported (and can co-bind).
constexpr double kRecommendSearchFactor = 2.0;

std::string num(double x) {
  std::ostringstream os;
  os.precision(10);
  os << x;
  return os.str();
}

// A limit above `search_depth` counts as "none below the searched depth".
StabilityLimit clip(StabilityLimit lim, double search_depth_m) {
  if (lim.bounded() && lim.depth_limit_m > search_depth_m) {
    const double rpm = lim.spindle_rpm;
    lim = StabilityLimit{};
    lim.spindle_rpm = rpm;
  }
  return lim;
}

std::string known_methods() {
  std::string s;
  for (const auto& m : lobe_methods()) s += (s.empty() ? "" : ", ") + m;
  return s;
}

}  // namespace

// ================================================================ machine

std::string MachineLimits::validate() const {
  std::ostringstream os;
  if (!(std::isfinite(rpm_min) && rpm_min > 0.0))
    os << "MachineLimits::rpm_min = " << rpm_min << ": must be > 0 rev/min";
  else if (!(std::isfinite(rpm_max) && rpm_max > rpm_min))
    os << "MachineLimits::rpm_max = " << rpm_max << ": must be > rpm_min (" << rpm_min << ")";
  else if (!(max_power_w > 0.0))
    os << "MachineLimits::max_power_w = " << max_power_w << ": must be > 0 W (+inf = no limit)";
  else if (!(max_torque_n_m > 0.0))
    os << "MachineLimits::max_torque_n_m = " << max_torque_n_m << ": must be > 0 N·m (+inf = no limit)";
  return os.str();
}

// ===================================================== fast lobe queries

std::string LobeTableQueryOptions::validate() const {
  std::ostringstream os;
  if (base_points < 2)
    os << "LobeTableQueryOptions::base_points = " << base_points << ": must be >= 2";
  else if (!(std::isfinite(tolerance_m) && tolerance_m >= 0.0))
    os << "LobeTableQueryOptions::tolerance_m = " << tolerance_m << ": must be >= 0 m (0 = relative_tolerance)";
  else if (!(relative_tolerance > 0.0 && relative_tolerance < 1.0))
    os << "LobeTableQueryOptions::relative_tolerance = " << relative_tolerance << ": must be in (0, 1)";
  else if (max_points < base_points)
    os << "LobeTableQueryOptions::max_points = " << max_points << ": must be >= base_points (" << base_points << ")";
  return os.str();
}

LobeTableQuery::LobeTableQuery(const LobeSolver& solver, double rpm_min, double rpm_max,
                               LobeTableQueryOptions options)
    : depth_max_m_(solver.depth_max_m()), method_(solver.method()) {
  if (const std::string e = options.validate(); !e.empty()) throw InputError("lobe table: " + e);
  if (!(std::isfinite(rpm_min) && rpm_min > 0.0 && std::isfinite(rpm_max) && rpm_max > rpm_min))
    throw InputError("lobe table: speed range [" + num(rpm_min) + ", " + num(rpm_max) +
                     "] rev/min: need 0 < rpm_min < rpm_max");

  struct Node {
    double u;  // 1/rpm
    StabilityLimit lim;
    double g;  // min(limit, depth_max)
  };
  std::vector<Node> nodes;
  // Solves at the given speeds (in parallel) and appends the nodes in order,
  // so the table is the same whatever the thread count.
  auto eval_all = [&](const std::vector<double>& us, const std::vector<double>& rpms) {
    std::vector<StabilityLimit> lims(us.size());
    parallel_for(us.size(), options.threads, [&](std::size_t i) { lims[i] = solver.limit_at(rpms[i]); });
    for (std::size_t i = 0; i < us.size(); ++i) {
      Node n{us[i], lims[i], depth_max_m_};
      if (n.lim.bounded()) n.g = std::min(n.lim.depth_limit_m, depth_max_m_);
      nodes.push_back(n);
    }
  };

  // 1. Base grid, evenly spaced in u = 1/rpm, the ends exactly at the range.
  const double u_lo = 1.0 / rpm_max, u_hi = 1.0 / rpm_min;
  const int nb = options.base_points;
  {
    std::vector<double> us(static_cast<std::size_t>(nb)), rpms(us.size());
    for (int i = 0; i < nb; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (i == 0) {
        us[k] = u_lo;
        rpms[k] = rpm_max;
      } else if (i == nb - 1) {
        us[k] = u_hi;
        rpms[k] = rpm_min;
      } else {
        us[k] = u_lo + (u_hi - u_lo) * static_cast<double>(i) / (nb - 1);
        rpms[k] = 1.0 / us[k];
      }
    }
    nodes.reserve(us.size() * 4);
    eval_all(us, rpms);
  }
  if (options.tolerance_m > 0.0) {
    tolerance_m_ = options.tolerance_m;
  } else {
    double smallest = kInf;
    for (const auto& n : nodes)
      if (n.lim.bounded()) smallest = std::min(smallest, n.g);
    tolerance_m_ = options.relative_tolerance * (std::isfinite(smallest) ? smallest : depth_max_m_);
  }

  // 2. Split intervals at their midpoints until the midpoint error is below
  //    tolerance/2 and no lobe number jumps by more than one; one round of
  //    midpoints at a time, solved in parallel.
  const double min_width = kMinRelativeWidth * (u_hi - u_lo);
  // A "kink" interval has its ends on different lobes, branches or sides of
  // depth_max: a cusp lies inside. There the convex lobe bottom and the cusp
  // can cancel at the midpoint, so when a kink interval passes, both its
  // halves are checked once more at their own midpoints before acceptance.
  auto kink = [](const Node& x, const Node& y) {
    return x.lim.bounded() != y.lim.bounded() ||
           (x.lim.bounded() && (x.lim.lobe != y.lim.lobe || x.lim.branch != y.lim.branch));
  };
  struct Interval {
    std::size_t a, b;
    bool passed_once;  // a kink interval whose parent passed its midpoint test
  };
  std::vector<Interval> round;
  for (std::size_t i = 0; i + 1 < static_cast<std::size_t>(nb); ++i) round.push_back({i, i + 1, false});
  double worst_unresolved = 0.0;
  while (!round.empty()) {
    std::vector<double> us(round.size()), rpms(round.size());
    for (std::size_t k = 0; k < round.size(); ++k) {
      us[k] = 0.5 * (nodes[round[k].a].u + nodes[round[k].b].u);
      rpms[k] = 1.0 / us[k];
    }
    const std::size_t first = nodes.size();
    eval_all(us, rpms);
    // The point budget is checked once per round (deterministic).
    const bool budget_left = nodes.size() + 2 * round.size() <= static_cast<std::size_t>(options.max_points);
    std::vector<Interval> next;
    for (std::size_t k = 0; k < round.size(); ++k) {
      const Interval iv = round[k];
      const std::size_t im = first + k;
      const Node &a = nodes[iv.a], &b = nodes[iv.b], &m = nodes[im];
      const double err = std::abs(m.g - 0.5 * (a.g + b.g));
      const bool lobe_jump = a.lim.bounded() && b.lim.bounded() && a.lim.branch == b.lim.branch &&
                             std::abs(a.lim.lobe - b.lim.lobe) > 1;
      const bool too_large = err > 0.5 * tolerance_m_;
      const bool can_split = 0.5 * (b.u - a.u) > min_width && budget_left;
      if (!too_large && !lobe_jump) {
        if (!iv.passed_once && can_split && kink(a, b)) {  // check both halves once more
          next.push_back({iv.a, im, true});
          next.push_back({im, iv.b, true});
        }
        continue;
      }
      if (can_split) {
        next.push_back({iv.a, im, false});
        next.push_back({im, iv.b, false});
      } else if (too_large) {
        ++unresolved_;
        worst_unresolved = std::max(worst_unresolved, 2.0 * err);
      }
    }
    round = std::move(next);
  }
  error_bound_m_ = std::max(tolerance_m_, worst_unresolved);

  // 3. Store ascending in speed (descending u).
  std::sort(nodes.begin(), nodes.end(), [](const Node& x, const Node& y) { return x.u > y.u; });
  const std::size_t n = nodes.size();
  rpm_.resize(n);
  inv_rpm_.resize(n);
  g_.resize(n);
  bounded_.resize(n);
  points_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    rpm_[i] = nodes[i].lim.spindle_rpm;
    inv_rpm_[i] = nodes[i].u;
    g_[i] = nodes[i].g;
    bounded_[i] = nodes[i].lim.bounded() ? 1 : 0;
    points_[i] = nodes[i].lim;
  }
}

std::size_t LobeTableQuery::interval(double rpm) const {
  if (!(rpm >= rpm_.front() && rpm <= rpm_.back()))
    throw InputError("lobe table query: spindle speed " + num(rpm) + " rev/min is outside the table range [" +
                     num(rpm_.front()) + ", " + num(rpm_.back()) + "]");
  const auto it = std::upper_bound(rpm_.begin(), rpm_.end(), rpm);
  const std::size_t i = static_cast<std::size_t>(it - rpm_.begin());
  return std::min(i == 0 ? 0 : i - 1, rpm_.size() - 2);
}

double LobeTableQuery::depth_limit(double rpm) const {
  const std::size_t i = interval(rpm);
  if (!bounded_[i] && !bounded_[i + 1]) return kInf;
  const double w = (1.0 / rpm - inv_rpm_[i]) / (inv_rpm_[i + 1] - inv_rpm_[i]);
  return g_[i] + w * (g_[i + 1] - g_[i]);
}

bool LobeTableQuery::is_stable(double rpm, double depth_m) const { return depth_m < depth_limit(rpm); }

QueryVerdict LobeTableQuery::classify(double rpm, double depth_m) const {
  const double d = depth_limit(rpm);
  if (std::isinf(d)) return depth_m < depth_max_m_ ? QueryVerdict::kStable : QueryVerdict::kUncertain;
  if (depth_m < d - error_bound_m_) return QueryVerdict::kStable;
  // Unstable only if the exact limit is surely below depth_max (g = limit there).
  if (depth_m > d + error_bound_m_ && d + error_bound_m_ < depth_max_m_) return QueryVerdict::kUnstable;
  return QueryVerdict::kUncertain;
}

namespace {

}  // namespace

StabilityLimit best_speed(const LobeSolver& solver, const LobeTableQuery& table) {
  const auto& pts = table.points();
  std::size_t best = pts.size();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].bounded()) continue;
    if (best == pts.size() || pts[i].depth_limit_m > pts[best].depth_limit_m) best = i;
  }
  if (best == pts.size()) {  // unbounded everywhere: the point nearest the middle
    const double mid = 0.5 * (table.rpm_min() + table.rpm_max());
    std::size_t k = 0;
    for (std::size_t i = 1; i < pts.size(); ++i)
      if (std::abs(pts[i].spindle_rpm - mid) < std::abs(pts[k].spindle_rpm - mid)) k = i;
    return pts[k];
  }
  StabilityLimit top = pts[best];
  const double a = pts[best == 0 ? 0 : best - 1].spindle_rpm;
  const double b = pts[std::min(best + 1, pts.size() - 1)].spindle_rpm;
  auto f = [&](double rpm) {
    const StabilityLimit l = solver.limit_at(rpm);
    if (l.depth_limit_m > top.depth_limit_m) top = l;  // +inf wins too
    return l.depth_limit_m;
  };
  detail::maximize_on(f, a, b, kGoldenRelativeWidth * b, kGoldenMaxIterations);
  return top;
}

// ========================================================= robust speeds

namespace {

// Scan: kScanStart solves evenly spaced in 1/rpm, then each interval is
// divided so that every lobe gets about kScanPointsPerLobe points (the lobe
// count from the spread of lobe numbers of the first scan), at most
// kScanMaxPoints in all. 8 points per lobe locate every cusp and lobe bottom
// to 1/16 of a lobe; the refinements below work from there.
constexpr int kScanStart = 24;
constexpr double kScanPointsPerLobe = 8.0;
constexpr int kScanMaxPoints = 2000;
// Refined candidates: every local maximum of the scanned objective within
// kCandidateSpread (relative) of the best, at most kMaxCandidates (two
// pockets of nearly equal height are both refined).
constexpr double kCandidateSpread = 0.1;
constexpr std::size_t kMaxCandidates = 3;
// Maximiser resolution for a robust optimum: 1e-4 of the speed (1 rev/min
// at 10 000), far below a spindle's speed error; at tolerance 0 the optimum
// is a cusp and the old kGoldenRelativeWidth (1e-8) applies.
constexpr double kRobustRelativeWidth = 1e-4;
// Lobe bottoms inside a band: 1e-5 of the speed; a bottom is smooth
// (quadratic), so its value is then exact to ~1e-10 relative. Pocket edges:
// 1e-4 of the speed (1 rev/min at 10 000; they are printed in whole rev/min).
constexpr double kBottomRelativeWidth = 1e-5;
constexpr double kEdgeRelativeWidth = 1e-4;
// The band's two ends are balanced when their limits agree to this (relative).
constexpr double kBalanceRelative = 1e-6;
constexpr int kEdgeMaxIterations = 60;
// A row deeper than this many times its own limit is probably typed in the
// wrong unit (um for mm): warned, naming the row. Feeds above 1 mm per tooth
// (or per revolution in turning) likewise.
constexpr double kImplausibleMarginFactor = 10.0;
constexpr double kPlausibleFeedM = 1e-3;
// Progress estimates (solves): a scan of a few lobes and its refinements per
// process, the band and pocket searches per row; the reported fraction stops
// at kProgressCeiling until the work is done.
constexpr std::size_t kProgressSolvesPerProcess = 150;
constexpr std::size_t kProgressSolvesPerRow = 30;
constexpr double kProgressCeiling = 0.99;

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
    return detail::maximize_on(f, a, b, rel * b, kGoldenMaxIterations).x;
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

}  // namespace

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
  s.scan();
  const double n = s.best(kInf, 0.5 * (rpm_min + rpm_max));
  if (!(s.band_min(n) > depth_m)) return std::nullopt;
  return make_pocket(s, n, depth_m, depth_m);
}

// ===================================================== operations file

namespace {

const std::vector<std::string> kRequiredColumns = {"id", "spindle_rpm", "depth_mm", "radial_immersion",
                                                   "feed_per_tooth_mm"};
const std::vector<std::string> kOptionalColumns = {"teeth", "milling_direction", "max_sle_um", "tolerance_um"};

using detail::text::trim;

// Splits one CSV line; fields may be double-quoted with "" for a quote.
// Returns false (and sets *error) on an unterminated quote.
bool split_csv(std::string_view line, std::vector<std::string>& out, std::string* error) {
  if (detail::text::split_delimited(line, ',', /*quotes=*/true, out)) return true;
  *error = "unterminated quote";
  return false;
}

// Parses a finite number; "" if fine, else the reason.
std::string parse_number(std::string_view s, double& x) {
  const std::optional<double> v = detail::text::parse_double(s);
  if (!v) return "not a number";
  x = *v;
  if (!std::isfinite(x)) return "must be a finite number";
  return "";
}

std::string parse_integer(std::string_view s, int& x) {
  const std::optional<int> v = detail::text::parse_integer<int>(s);
  if (!v) return "not an integer";
  x = *v;
  return "";
}

std::string in_quotes(std::string_view s) { return "'" + std::string(s) + "'"; }

}  // namespace

OperationsFile parse_operations(std::string_view text, const std::string& origin, Operation operation,
                                const MachineLimits& machine) {
  if (const std::string e = machine.validate(); !e.empty()) throw InputError(origin + ": " + e);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte-order mark
  const bool milling = operation == Operation::kMilling;

  OperationsFile out;
  std::map<std::string, std::size_t> column;  // name -> index
  std::size_t n_columns = 0;
  std::vector<std::string> header;
  std::map<std::string, int> first_line_of_id;
  std::vector<std::string> f;
  int line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view t = trim(line);
    if (t.empty() || t.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    std::string err;
    const std::string where = origin + ":" + std::to_string(line_no) + ": ";
    if (header.empty()) {  // ---- header
      if (!split_csv(line, header, &err)) throw InputError(where + "header: " + err);
      for (std::size_t i = 0; i < header.size(); ++i) {
        const std::string& h = header[i];
        const bool known = std::find(kRequiredColumns.begin(), kRequiredColumns.end(), h) != kRequiredColumns.end() ||
                           std::find(kOptionalColumns.begin(), kOptionalColumns.end(), h) != kOptionalColumns.end();
        if (!known) {
          // A spreadsheet exported with ';' (a decimal-comma locale): one
          // unknown column holding the separators.
          if (h.find(';') != std::string::npos)
            throw InputError(where + "header " + in_quotes(trim(line)) +
                             ": the file seems to use ';' as separator; chatter reads ',' (export as CSV with "
                             "commas)");
          std::string names;
          std::vector<std::string_view> known_names;
          for (const auto* list : {&kRequiredColumns, &kOptionalColumns})
            for (const auto& c : *list) {
              names += (names.empty() ? "" : ",") + c;
              known_names.emplace_back(c);
            }
          const std::string_view meant = detail::text::near_miss(h, known_names);
          throw InputError(where + "header column " + in_quotes(h) + ": unknown column (" +
                           (meant.empty() ? "" : "did you mean " + std::string(meant) + "? ") + "known: " + names +
                           "; a header line is required)");
        }
        if (column.count(h)) throw InputError(where + "header column " + in_quotes(h) + ": given twice");
        column[h] = i;
      }
      for (const auto& c : kRequiredColumns)
        if (!column.count(c)) {
          std::string req;
          for (const auto& r : kRequiredColumns) req += (req.empty() ? "" : ",") + r;
          throw InputError(where + "header lacks column " + in_quotes(c) + " (required: " + req + ")");
        }
      n_columns = header.size();
      if (end == text.size()) break;
      continue;
    }

    // ---- one operation
    RejectedRow bad{line_no, "", ""};
    std::vector<std::string> reasons;
    if (!split_csv(line, f, &err)) {
      out.rejected.push_back({line_no, "", err});
      if (end == text.size()) break;
      continue;
    }
    if (f.size() < n_columns) {
      std::string missing;
      for (std::size_t i = f.size(); i < n_columns; ++i) missing += (missing.empty() ? "" : ", ") + header[i];
      if (column.count("id") && column["id"] < f.size()) bad.id = f[column["id"]];
      bad.reason = "has " + std::to_string(f.size()) + " fields, the header has " + std::to_string(n_columns) +
                   " (missing column" + (n_columns - f.size() > 1 ? "s " : " ") + missing + ")";
      out.rejected.push_back(bad);
      if (end == text.size()) break;
      continue;
    }
    if (f.size() > n_columns) {
      bad.id = f[column["id"]];
      bad.reason = "has " + std::to_string(f.size()) + " fields, the header has " + std::to_string(n_columns) +
                   " (an unquoted comma?)";
      out.rejected.push_back(bad);
      if (end == text.size()) break;
      continue;
    }
    auto field = [&](const std::string& name) -> std::string_view {
      const auto it = column.find(name);
      return it == column.end() ? std::string_view{} : std::string_view(f[it->second]);
    };

    OperationRow row;
    row.line = line_no;
    row.id = std::string(field("id"));
    bad.id = row.id;
    if (row.id.empty()) reasons.push_back("id: missing (required)");

    auto number = [&](const std::string& name, double& x) -> bool {
      const std::string_view s = field(name);
      if (s.empty()) {  // only the required columns are read without a value
        reasons.push_back(name + ": missing (required)");
        return false;
      }
      if (const std::string e = parse_number(s, x); !e.empty()) {
        reasons.push_back(name + " = " + in_quotes(s) + ": " + e);
        return false;
      }
      return true;
    };
    double rpm = 0.0, depth_mm = 0.0;
    if (number("spindle_rpm", rpm)) {
      if (!(rpm > 0.0))
        reasons.push_back("spindle_rpm = " + num(rpm) + ": must be > 0 rev/min");
      else if (rpm < machine.rpm_min || rpm > machine.rpm_max)
        reasons.push_back("spindle_rpm = " + num(rpm) + ": outside the machine range [" + num(machine.rpm_min) +
                          ", " + num(machine.rpm_max) + "] rev/min");
    }
    if (number("depth_mm", depth_mm)) {
      if (!(depth_mm > 0.0)) reasons.push_back("depth_mm = " + num(depth_mm) + ": must be > 0 mm");
      else if (depth_mm > kMaxDepthMm)
        reasons.push_back("depth_mm = " + num(depth_mm) + ": at most " + num(kMaxDepthMm) +
                          " mm (no cut is a metre deep); a depth in um?");
    }
    row.spindle_rpm = rpm;
    row.depth_m = depth_mm * 1e-3;
    row.depth_mm = depth_mm;

    if (const std::string_view s = field("radial_immersion"); !s.empty()) {
      double ae = 0.0;
      if (!milling)
        reasons.push_back("radial_immersion = " + in_quotes(s) + ": only for milling (leave empty for turning)");
      else if (number("radial_immersion", ae)) {
        if (!(ae > 0.0 && ae <= 1.0)) reasons.push_back("radial_immersion = " + num(ae) + ": must be in (0, 1] (a_e/D)");
        else row.radial_immersion = ae;
      }
    }
    if (const std::string_view s = field("feed_per_tooth_mm"); !s.empty()) {
      double fz = 0.0;
      if (number("feed_per_tooth_mm", fz)) {
        if (!(fz > 0.0)) reasons.push_back("feed_per_tooth_mm = " + num(fz) + ": must be > 0 mm");
        else {
          row.feed_per_tooth_m = fz * 1e-3;
          row.feed_per_tooth_mm = fz;
        }
      }
    }
    if (const std::string_view s = field("teeth"); !s.empty()) {
      int nt = 0;
      if (!milling) reasons.push_back("teeth = " + in_quotes(s) + ": only for milling (leave empty for turning)");
      else if (const std::string e = parse_integer(s, nt); !e.empty())
        reasons.push_back("teeth = " + in_quotes(s) + ": " + e);
      else if (nt < 1) reasons.push_back("teeth = " + std::to_string(nt) + ": must be >= 1");
      else if (nt > kMaxTeeth) reasons.push_back("teeth = " + std::to_string(nt) + ": must be <= " + std::to_string(kMaxTeeth));
      else row.teeth = nt;
    }
    // Issue 27: the part's tolerance on the surface location error (milling)
    // or the diametral error (turning), µm; either name.
    for (const char* name : {"max_sle_um", "tolerance_um"})
      if (const std::string_view s = field(name); !s.empty()) {
        double tol = 0.0;
        if (number(name, tol)) {
          if (!(tol > 0.0)) reasons.push_back(std::string(name) + " = " + num(tol) + ": must be > 0 um");
          else if (row.max_error_m) reasons.push_back(std::string(name) + ": max_sle_um and tolerance_um both given");
          else row.max_error_m = tol * 1e-6;
        }
      }
    if (const std::string_view s = field("milling_direction"); !s.empty()) {
      if (!milling)
        reasons.push_back("milling_direction = " + in_quotes(s) + ": only for milling (leave empty for turning)");
      else if (s == "down") row.direction = MillingDirection::kDown;
      else if (s == "up") row.direction = MillingDirection::kUp;
      else reasons.push_back("milling_direction = " + in_quotes(s) + ": must be \"down\" or \"up\"");
    }
    if (!row.id.empty()) {
      const auto [it, inserted] = first_line_of_id.emplace(row.id, line_no);
      if (!inserted)
        reasons.push_back("duplicate id (first on line " + std::to_string(it->second) + ")");
    }
    if (reasons.empty()) {
      out.rows.push_back(std::move(row));
    } else {
      for (const auto& r : reasons) bad.reason += (bad.reason.empty() ? "" : "; ") + r;
      out.rejected.push_back(std::move(bad));
    }
    if (end == text.size()) break;
  }
  if (header.empty()) {
    std::string req;
    for (const auto& r : kRequiredColumns) req += (req.empty() ? "" : ",") + r;
    throw InputError(origin + ": no header line (expected the columns " + req + ")");
  }
  // A file that lists nothing must not read as "all stable" to a
  // post-processor: nothing checked is an error.
  if (out.rows.empty() && out.rejected.empty())
    throw InputError(origin + ": no operations (a header and no rows): nothing to check");
  return out;
}

OperationsFile read_operations(const std::filesystem::path& file, Operation operation, const MachineLimits& machine) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(file.string() + ": cannot read file (" + (err ? std::strerror(err) : "unknown reason") + ")");
  }
  std::ostringstream os;
  os << in.rdbuf();
  return parse_operations(os.str(), file.string(), operation, machine);
}

Process process_for(const Process& base, const OperationRow& row) {
  if (base.operation() == Operation::kTurning) {
    if (row.radial_immersion || row.teeth || row.direction)
      throw InputError("operation " + in_quotes(row.id) + ": immersion, teeth and direction are for milling only");
    return base;
  }
  MillingParameters p = base.milling_parameters();
  if (row.radial_immersion) p.radial_immersion = *row.radial_immersion;
  if (row.teeth) p.teeth = *row.teeth;
  if (row.direction) p.direction = *row.direction;
  try {
    Process out = Process::milling(p);
    out.set_speed_variation(base.speed_variation());
    return out;
  } catch (const InputError& e) {
    throw InputError("operation " + in_quotes(row.id) + ": " + e.what());
  }
}

// ============================================================== check

std::string CheckOptions::validate() const {
  std::ostringstream os;
  if (const std::string e = machine.validate(); !e.empty()) os << e;
  else if (!(std::isfinite(search_depth_factor) && search_depth_factor > 1.0))
    os << "CheckOptions::search_depth_factor = " << search_depth_factor << ": must be > 1";
  else if (!(std::isfinite(search_depth_min_m) && search_depth_min_m > 0.0))
    os << "CheckOptions::search_depth_min_m = " << search_depth_min_m << ": must be > 0 m";
  else if (const std::string t = validate_speed_tolerance(speed_tolerance, "CheckOptions::speed_tolerance x 100"); !t.empty())
    os << t;
  else if (flute_length_m && !(std::isfinite(*flute_length_m) && *flute_length_m > 0.0))
    os << "CheckOptions::flute_length_m = " << *flute_length_m << ": must be > 0 m";
  return os.str();
}

std::size_t CheckReport::out_of_tolerance() const {
  return static_cast<std::size_t>(std::count_if(checks.begin(), checks.end(), [](const OperationCheck& c) {
    return c.forced && c.op.max_error_m && !c.forced->within_tolerance;
  }));
}

std::size_t CheckReport::unstable() const {
  return static_cast<std::size_t>(std::count_if(checks.begin(), checks.end(), [](const auto& c) { return !c.stable; }));
}

CheckReport check_operations(const StructuralModel& model, const Process& process,
                             const std::vector<OperationRow>& rows, const CheckOptions& options) {
  if (const std::string e = options.validate(); !e.empty()) throw InputError("check: " + e);
  CheckReport report;
  auto search_depth = [&](const OperationRow& r) {
    return std::max(options.search_depth_factor * r.depth_m, options.search_depth_min_m);
  };

  // One solver and one speed search per distinct process.
  struct Group {
    Process process = Process::turning({1.0});
    std::string method;
    double depth_max_m = 0.0;
    std::vector<std::size_t> rows;
  };
  using Key = std::tuple<double, int, int>;
  auto key_of = [&](const OperationRow& r) -> Key {
    if (process.operation() == Operation::kTurning) return {0.0, 0, 0};
    const auto& m = process.milling_parameters();
    return {r.radial_immersion.value_or(m.radial_immersion), r.teeth.value_or(m.teeth),
            static_cast<int>(r.direction.value_or(m.direction))};
  };
  std::map<Key, Group> by_key;
  std::vector<char> judged(rows.size(), 1);  // 0: the row could not be judged (report.not_judged says why)
  auto not_judged = [&](std::size_t i, const std::string& why) {
    judged[i] = 0;
    report.not_judged.push_back({rows[i].line, rows[i].id, why});
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const OperationRow& r = rows[i];
    if (!by_key.count(key_of(r))) {
      // A row whose overrides make no cutter (e.g. teeth that contradict
      // the config's pitch angles) is that row's error, not the file's.
      try {
        (void)process_for(process, r);
      } catch (const InputError& e) {
        not_judged(i, e.what());
        continue;
      }
    }
    Group& g = by_key[key_of(r)];
    if (g.method.empty()) {
      g.process = process_for(process, r);
      std::string warning;
      g.method = resolve_lobe_method(options.method, model, g.process, &warning);
      std::vector<std::string> notes = ignored_feature_notes(find_lobe_method(g.method), g.process);
      if (!warning.empty()) notes.insert(notes.begin(), warning);
      for (const std::string& n : notes)
        if (std::find(report.warnings.begin(), report.warnings.end(), n) == report.warnings.end())
          report.warnings.push_back(n);
    }
    g.depth_max_m = std::max(g.depth_max_m, search_depth(r));
    g.rows.push_back(i);
    if (options.flute_length_m && r.depth_m > *options.flute_length_m)
      report.warnings.push_back("operation '" + r.id + "' (line " + std::to_string(r.line) + "): depth " +
                                num(r.depth_m * 1e3) + " mm exceeds the usable flute length " +
                                num(*options.flute_length_m * 1e3) + " mm");
    if (r.feed_per_tooth_m && *r.feed_per_tooth_m > kPlausibleFeedM)
      report.warnings.push_back("operation '" + r.id + "' (line " + std::to_string(r.line) + "): feed " +
                                num(*r.feed_per_tooth_m * 1e3) + " mm per " +
                                (process.operation() == Operation::kMilling ? "tooth" : "revolution") +
                                " is above 1 mm: a feed in um, or per revolution?");
  }
  std::vector<Group*> groups;
  for (auto& [key, g] : by_key) groups.push_back(&g);

  // Groups are independent: solved in parallel (each deterministic, so the
  // report does not depend on the thread count); a lone group scans in parallel.
  std::vector<OperationCheck> checks(rows.size());
  const unsigned scan_threads = groups.size() == 1 ? options.threads : 1;
  // Progress: exact solves against a rough estimate of the total (a scan of
  // a few lobes plus the refinements), never reaching 1 before the end.
  std::atomic<std::size_t> solves{0};
  const double expected = static_cast<double>(kProgressSolvesPerProcess * groups.size() +
                                              kProgressSolvesPerRow * rows.size());
  auto tick = [&] {
    const double f = static_cast<double>(++solves) / expected;
    if (options.progress) options.progress(std::min(f, kProgressCeiling));
  };
  const double tol = options.speed_tolerance;
  // One row: its exact limit and margins, and the suggested speed with its
  // pocket (SpeedSearch caches the solves shared by the rows of a process).
  auto check_row = [&](SpeedSearch& s, const Group& g, std::size_t i) {
    const OperationRow& r = rows[i];
    const double ds = search_depth(r);
    auto clipped = [&](double w) { return w > ds ? kInf : w; };
    OperationCheck& c = checks[i];
    c.op = r;
    c.method = g.method;
    c.search_depth_m = ds;
    c.limit = clip(s.at(r.spindle_rpm), ds);
    c.stable = r.depth_m < c.limit.depth_limit_m;
    c.margin = c.limit.depth_limit_m / r.depth_m;
    const double own_worst = clipped(s.band_min(r.spindle_rpm));
    c.worst_margin = own_worst / r.depth_m;
    // The speed whose band has the largest worst limit (unbounded for this
    // row's searched depth: the nearest such speed); the row's own speed
    // when it is as good.
    double n = r.spindle_rpm;
    if (std::isfinite(own_worst)) {
      const double best = s.best(ds, r.spindle_rpm);
      if (clipped(s.band_min(best)) > own_worst) n = best;
    }
    const double worst = clipped(s.band_min(n));
    if (worst > r.depth_m) {
      c.suggestion = clip(s.at(n), ds);
      c.suggestion_margin = c.suggestion->depth_limit_m / r.depth_m;
      SpeedPocket p = make_pocket(s, n, r.depth_m, r.depth_m);
      p.limit = *c.suggestion;
      p.worst_limit_m = worst;
      p.worst_margin = worst / r.depth_m;
      c.suggestion_pocket = p;
    }
  };
  std::vector<std::vector<std::pair<std::size_t, std::string>>> failed(groups.size());  // per group, in row order
  parallel_for(groups.size(), options.threads, [&](std::size_t gi) {
    const Group& g = *groups[gi];
    std::unique_ptr<LobeSolver> solver;
    std::optional<SpeedSearch> search;
    try {
      solver = make_lobe_solver(g.method, model, g.process, g.depth_max_m);
      search.emplace(*solver, options.machine.rpm_min, options.machine.rpm_max, tol, scan_threads);
      search->on_solve = tick;
      search->scan();
    } catch (const std::exception& e) {
      // A solver that fails on this process fails every row of it; the
      // other processes' rows are still checked.
      for (const std::size_t i : g.rows)
        failed[gi].emplace_back(i, std::string("the ") + g.method + " solver failed on this row's process: " +
                                       e.what());
      return;
    }
    SpeedSearch& s = *search;
    for (const std::size_t i : g.rows) {
      try {
        check_row(s, g, i);
      } catch (const std::exception& e) {
        failed[gi].emplace_back(i, std::string("the ") + g.method + " solver failed at this row: " + e.what());
      }
    }
  });
  for (const auto& f : failed)
    for (const auto& [i, why] : f) not_judged(i, why);
  std::sort(report.not_judged.begin(), report.not_judged.end(),
            [](const RejectedRow& a, const RejectedRow& b) { return a.line < b.line; });
  // Depths far beyond the limit are probably typed in the wrong unit.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const OperationCheck& c = checks[i];
    if (judged[i] && c.limit.bounded() && rows[i].depth_m > kImplausibleMarginFactor * c.limit.depth_limit_m)
      report.warnings.push_back("operation '" + rows[i].id + "' (line " + std::to_string(rows[i].line) + "): depth " +
                                num(rows[i].depth_m * 1e3) + " mm is over " + num(kImplausibleMarginFactor) +
                                " times the stability limit " + num(c.limit.depth_limit_m * 1e3) +
                                " mm at its speed: a depth in um?");
  }
  // The forced vibration of every judged row with a feed (issue 27): its
  // surface location or diametral error and the part's tolerance. A solver
  // that cannot give it (e.g. measured FRFs) leaves the row without it, said
  // once in the warnings.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!judged[i]) continue;
    try {
      checks[i].forced = forced_check(model, process, rows[i]);
    } catch (const std::exception& e) {
      const std::string w = std::string("forced vibration not computed: ") + e.what();
      if (std::find(report.warnings.begin(), report.warnings.end(), w) == report.warnings.end())
        report.warnings.push_back(w);
    }
  }
  if (options.progress) options.progress(1.0);
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (judged[i]) report.checks.push_back(std::move(checks[i]));
  return report;
}

// ====================================================== recommendation

std::string RecommendOptions::validate() const {
  std::ostringstream os;
  if (const std::string e = machine.validate(); !e.empty()) os << e;
  else if (!(safety > 0.0 && safety <= 1.0))
    os << "safety = " << safety << ": must be in (0, 1] (fraction of the depth limit)";
  else if (!(std::isfinite(feed_per_tooth_m) && feed_per_tooth_m > 0.0))
    os << "feed_per_tooth = " << feed_per_tooth_m * 1e3 << " mm: must be > 0";
  else if (!(std::isfinite(diameter_m) && diameter_m >= 0.0))
    os << "diameter = " << diameter_m * 1e3 << " mm: must be > 0 (or 0 = unknown)";
  else if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    os << "depth_max = " << depth_max_m * 1e3 << " mm: must be > 0";
  else if (cutting_coefficient_n_per_m2 && !(std::isfinite(*cutting_coefficient_n_per_m2) && *cutting_coefficient_n_per_m2 > 0.0))
    os << "cutting coefficient = " << *cutting_coefficient_n_per_m2 << " N/m²: must be > 0";
  else if (flute_length_m && !(std::isfinite(*flute_length_m) && *flute_length_m > 0.0))
    os << "flute_length = " << *flute_length_m * 1e3 << " mm: must be > 0";
  else if (const std::string t = validate_speed_tolerance(speed_tolerance, "speed tolerance x 100"); !t.empty())
    os << t;
  return os.str();
}

std::string to_string(Binding b) {
  switch (b) {
    case Binding::kStability: return "stability";
    case Binding::kPower: return "power";
    case Binding::kTorque: return "torque";
    case Binding::kDepthMax: return "depth_max";
    case Binding::kSpeedRange: return "speed_range";
    case Binding::kFluteLength: return "flute_length";
  }
  return "?";
}

namespace {

// Mean-force model per unit depth (see recommend()).
struct CutModel {
  double force_per_depth = 0.0;         // N/m
  double torque_per_depth = 0.0;        // N·m/m (NaN without diameter)
  double power_per_depth_rpm = 0.0;     // W/(m·rev/min)
  double mrr_per_depth_rpm = 0.0;       // m³/s per (m·rev/min) (NaN without diameter)
  double mrr_per_diam_depth_rpm = 0.0;  // m²/s per (m·rev/min)
};

CutModel cut_model(const Process& p, const RecommendOptions& o, std::vector<std::string>& warnings) {
  CutModel c;
  const double D = o.diameter_m > 0.0 ? o.diameter_m : kNaN;
  const double f = o.feed_per_tooth_m;
  if (p.operation() == Operation::kTurning) {
    const double kc = o.cutting_coefficient_n_per_m2.value_or(p.turning_parameters().feed_force_coefficient_n_per_m2);
    if (!o.cutting_coefficient_n_per_m2)
      warnings.push_back("turning power and torque use the feed-force coefficient K_f as cutting pressure (no "
                         "tangential coefficient given); with force angle θ the true value is K_f·tanθ, larger");
    c.force_per_depth = kc * f;                           // F_c = K_c b f
    c.torque_per_depth = c.force_per_depth * D / 2.0;     // T = F_c D/2
    c.power_per_depth_rpm = c.force_per_depth * kPi * D / 60.0;  // P = F_c v_c, v_c = πDN/60
    c.mrr_per_depth_rpm = f * kPi * D / 60.0;             // b f v_c
    c.mrr_per_diam_depth_rpm = f * kPi / 60.0;
  } else {
    const auto& m = p.milling_parameters();
    const double span = std::cos(p.entry_angle()) - std::cos(p.exit_angle());  // ∫ sinφ dφ over the cut
    // Sum of the teeth's tangential forces averaged over a revolution.
    c.force_per_depth = m.teeth / (2.0 * kPi) * m.tangential_coefficient_n_per_m2 * f * span;
    c.torque_per_depth = c.force_per_depth * D / 2.0;
    c.power_per_depth_rpm = c.torque_per_depth * 2.0 * kPi / 60.0;
    c.mrr_per_diam_depth_rpm = m.radial_immersion * f * m.teeth / 60.0;  // a·(a_e/D)·f_z·N_t·N/60 per D
    c.mrr_per_depth_rpm = c.mrr_per_diam_depth_rpm * D;
  }
  return c;
}

}  // namespace

Recommendation recommend(const StructuralModel& model, const Process& process, const RecommendOptions& options) {
  if (const std::string e = options.validate(); !e.empty()) throw InputError("recommend: " + e);
  const MachineLimits& mc = options.machine;
  const bool limits = std::isfinite(mc.max_power_w) || std::isfinite(mc.max_torque_n_m);
  if (limits && !(options.diameter_m > 0.0))
    throw InputError(std::string("recommend: a power or torque limit needs the ") +
                     (process.operation() == Operation::kMilling ? "tool diameter (RecommendOptions::diameter_m)"
                                                                 : "workpiece diameter (RecommendOptions::diameter_m)"));
  Recommendation rec;
  std::string warning;
  rec.method = resolve_lobe_method(options.method, model, process, &warning);
  if (!warning.empty()) rec.warnings.push_back(warning);
  for (const std::string& n : ignored_feature_notes(find_lobe_method(rec.method), process)) rec.warnings.push_back(n);
  std::vector<std::string> model_warnings;
  const CutModel cm = cut_model(process, options, model_warnings);
  if (options.diameter_m > 0.0)
    rec.warnings.insert(rec.warnings.end(), model_warnings.begin(), model_warnings.end());

  const double flute = options.flute_length_m.value_or(kInf);
  rec.search_depth_m = kRecommendSearchFactor * std::min(options.depth_max_m, flute) / options.safety;
  const auto solver = make_lobe_solver(rec.method, model, process, rec.search_depth_m);
  SpeedSearch s(*solver, mc.rpm_min, mc.rpm_max, options.speed_tolerance, options.threads);
  std::atomic<std::size_t> solves{0};
  s.on_solve = [&] {
    const double f = static_cast<double>(++solves) / static_cast<double>(kProgressSolvesPerProcess);
    if (options.progress) options.progress(std::min(f, kProgressCeiling));
  };
  s.scan();

  struct Cand {
    double rpm, worst, stab, power, torque, cap, flute, depth, objective, margin;
  };
  // `exact`: the worst limit over the band from exact solves, else the scan's estimate.
  auto evaluate = [&](double n, bool exact) {
    Cand c;
    c.rpm = n;
    const double w = exact ? s.band_min(n) : s.band_min_scan(n, kInf);
    c.worst = w > rec.search_depth_m || w >= solver->depth_max_m() ? kInf : w;
    c.stab = options.safety * c.worst;
    c.power = std::isfinite(mc.max_power_w) ? mc.max_power_w / (cm.power_per_depth_rpm * n) : kInf;
    c.torque = std::isfinite(mc.max_torque_n_m) ? mc.max_torque_n_m / cm.torque_per_depth : kInf;
    c.cap = options.depth_max_m;
    c.flute = flute;
    c.depth = std::min({c.stab, c.power, c.torque, c.cap, c.flute});
    c.objective = n * c.depth;  // MRR / (mrr per depth·rpm)
    c.margin = c.worst / c.depth;
    return c;
  };
  auto better = [](const Cand& x, const Cand& y) {  // x strictly better than y
    if (x.objective > y.objective * (1.0 + kTieRelative)) return true;
    if (x.objective < y.objective * (1.0 - kTieRelative)) return false;
    return x.margin > y.margin;
  };

  // Rank the scanned speeds, refine the best local maxima with exact solves.
  const std::vector<double>& pts = s.scan_speeds();
  std::vector<Cand> scanned;
  for (double n : pts) scanned.push_back(evaluate(n, false));
  std::vector<std::size_t> cand;
  double top = 0.0;
  for (const auto& c : scanned) top = std::max(top, c.objective);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const bool local = (i == 0 || !better(scanned[i - 1], scanned[i])) &&
                       (i + 1 == pts.size() || !better(scanned[i + 1], scanned[i]));
    if (local && scanned[i].objective >= (1.0 - kCandidateSpread) * top) cand.push_back(i);
  }
  if (cand.empty()) cand.push_back(0);  // only with NaN objectives
  std::sort(cand.begin(), cand.end(), [&](std::size_t x, std::size_t y) { return better(scanned[x], scanned[y]); });
  if (cand.size() > kMaxCandidates) cand.resize(kMaxCandidates);
  const double rel = options.speed_tolerance > 0.0 ? kRobustRelativeWidth : kGoldenRelativeWidth;
  Cand best = evaluate(pts[cand.front()], true);
  std::size_t ib = cand.front();
  for (const std::size_t i : cand) {
    const Cand at_point = evaluate(pts[i], true);
    if (better(at_point, best)) best = at_point, ib = i;
    const double a = pts[i == 0 ? 0 : i - 1], b = pts[std::min(i + 1, pts.size() - 1)];
    // Power-bound MRR is flat in speed: then the largest worst margin.
    const bool power_bound = at_point.depth == at_point.power;
    auto f = [&](double n) {
      const Cand c = evaluate(n, true);
      if (better(c, best)) best = c, ib = i;
      return power_bound ? c.margin : c.objective;
    };
    // Bound by stability or power near a cusp, the optimum is where the band's
    // two ends balance (MRR ∝ N·worst limit has its kink there; beyond it the
    // lobe flank falls faster than 1/N); bound by a fixed depth cap, MRR grows
    // with N up to where stability takes over: Brent's minimiser.
    const bool stability_bound = at_point.depth == at_point.stab;
    const double x = (power_bound || stability_bound) && options.speed_tolerance > 0.0 ? s.balance(a, b, rel) : 0.0;
    if (x > 0.0) f(x);
    else s.maximize(f, a, b, rel);
  }

  rec.spindle_rpm = best.rpm;
  rec.depth_m = best.depth;
  rec.limit = clip(s.at(best.rpm), rec.search_depth_m);
  rec.margin = rec.limit.depth_limit_m / rec.depth_m;
  rec.depth_stability_m = best.stab;
  rec.depth_power_m = best.power;
  rec.depth_torque_m = best.torque;
  rec.depth_cap_m = best.cap;
  rec.depth_flute_m = best.flute;
  rec.pocket = make_pocket(s, best.rpm, rec.depth_m, rec.depth_m / options.safety);
  rec.pocket.limit = rec.limit;
  rec.pocket.worst_limit_m = best.worst;
  rec.pocket.worst_margin = best.margin;
  rec.force_n = cm.force_per_depth * rec.depth_m;
  rec.torque_n_m = cm.torque_per_depth * rec.depth_m;
  rec.power_w = cm.power_per_depth_rpm * rec.depth_m * rec.spindle_rpm;
  rec.mrr_m3_per_s = cm.mrr_per_depth_rpm * rec.depth_m * rec.spindle_rpm;
  rec.mrr_per_diameter_m2_per_s = cm.mrr_per_diam_depth_rpm * rec.depth_m * rec.spindle_rpm;
  const double bind_rel = options.speed_tolerance > 0.0 ? kRobustBindingRelative : kBindingRelative;
  auto binds = [&](double cap) { return std::isfinite(cap) && cap <= rec.depth_m * (1.0 + bind_rel); };
  if (binds(best.stab)) rec.binding.push_back(Binding::kStability);
  if (binds(best.power)) rec.binding.push_back(Binding::kPower);
  if (binds(best.torque)) rec.binding.push_back(Binding::kTorque);
  if (binds(best.cap)) rec.binding.push_back(Binding::kDepthMax);
  if (binds(best.flute)) rec.binding.push_back(Binding::kFluteLength);
  // The speed range binds when the optimum sits on an end of the range and MRR
  // still grows towards it (a power-bound MRR is flat in speed: it does not).
  if (!binds(best.power) && (ib == 0 || ib + 1 == pts.size()) && best.rpm == pts[ib]) {
    const Cand inner = evaluate(pts[ib == 0 ? 1 : ib - 1], true);
    if (best.objective > inner.objective * (1.0 + kTieRelative)) rec.binding.push_back(Binding::kSpeedRange);
  }
  if (options.progress) options.progress(1.0);
  return rec;
}

std::string explain(const Recommendation& r, const RecommendOptions& o) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  auto f = [](double x, int d) {
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(d);
    s << x;
    return s.str();
  };
  const double d_mm = r.depth_m * 1e3;
  os << "Recommended: " << f(r.spindle_rpm, 0) << " rev/min, depth " << f(d_mm, 3) << " mm (" << r.method
     << " lobes, feed " << f(o.feed_per_tooth_m * 1e3, 3) << " mm)\n";
  os << "Binding: ";
  for (std::size_t i = 0; i < r.binding.size(); ++i) {
    if (i) os << "; ";
    switch (r.binding[i]) {
      case Binding::kStability:
        // The cap is safety x the worst limit over the speed band (the limit
        // at the speed itself when the tolerance is 0).
        if (o.speed_tolerance > 0.0)
          os << "stability (depth = " << f(o.safety, 3) << " x the worst limit "
             << f(r.pocket.worst_limit_m * 1e3, 3) << " mm over the speed band +/-"
             << f(o.speed_tolerance * 100.0, 1) << " %; " << f(r.limit.depth_limit_m * 1e3, 3)
             << " mm at this speed)";
        else
          os << "stability (depth = " << f(o.safety, 3) << " x limit " << f(r.limit.depth_limit_m * 1e3, 3)
             << " mm at this speed)";
        break;
      case Binding::kPower:
        os << "spindle power (mean cutting power = " << f(o.machine.max_power_w * 1e-3, 3) << " kW limit)";
        break;
      case Binding::kTorque:
        os << "spindle torque (mean cutting torque = " << f(o.machine.max_torque_n_m, 2) << " N*m limit)";
        break;
      case Binding::kDepthMax: os << "the tool's maximum depth " << f(r.depth_cap_m * 1e3, 3) << " mm"; break;
      case Binding::kFluteLength:
        os << "the cutter's usable flute length " << f(r.depth_flute_m * 1e3, 3) << " mm";
        break;
      case Binding::kSpeedRange:
        os << "speed range (at the machine's "
           << (r.spindle_rpm >= o.machine.rpm_max ? "maximum " : "minimum ") << f(r.spindle_rpm, 0)
           << " rev/min; more MRR lies beyond it)";
        break;
    }
  }
  os << "\n";
  const SpeedPocket& p = r.pocket;
  os << "Speed band +/-" << f(p.speed_tolerance * 100.0, 1) << " %: ";
  if (std::isfinite(p.worst_limit_m))
    os << "worst limit " << f(p.worst_limit_m * 1e3, 3) << " mm, worst margin " << f(p.worst_margin, 3);
  else
    os << "no chatter below " << f(r.search_depth_m * 1e3, 3) << " mm";
  os << "; stable pocket " << f(p.pocket_min_rpm, 0) << "-" << f(p.pocket_max_rpm, 0)
     << " rev/min (safety x limit >= depth)\n";
  if (r.limit.bounded())
    os << "Stability margin: " << f(r.margin, 3) << " (limit " << f(r.limit.depth_limit_m * 1e3, 3)
       << " mm / depth; chatter would start at " << f(r.limit.chatter_frequency_hz, 1) << " Hz, lobe "
       << r.limit.lobe << ")\n";
  else
    os << "Stability margin: no chatter below " << f(r.search_depth_m * 1e3, 3) << " mm at this speed\n";
  if (std::isfinite(r.mrr_m3_per_s)) {
    os << "MRR: " << f(r.mrr_m3_per_s * 6e7, 2) << " cm^3/min; mean power " << f(r.power_w * 1e-3, 3) << " kW";
    if (std::isfinite(o.machine.max_power_w)) os << " of " << f(o.machine.max_power_w * 1e-3, 3) << " kW";
    os << ", torque " << f(r.torque_n_m, 2) << " N*m";
    if (std::isfinite(o.machine.max_torque_n_m)) os << " of " << f(o.machine.max_torque_n_m, 2) << " N*m";
    os << "\n";
  } else {
    os << "MRR: " << f(r.mrr_per_diameter_m2_per_s * 6e7 * 1e-3, 4)
       << " cm^3/min per mm of diameter (give the diameter for MRR, power and torque)\n";
  }
  for (const auto& w : r.warnings) os << "warning: " << w << "\n";
  return os.str();
}

}  // namespace chatter
