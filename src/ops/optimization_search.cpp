// The constrained optimum (optimize) and the loss map (loss_map) of
// include/chatter/optimization.hpp: scan the bounds, then polish the best
// local minima over speed with nested Brent minimisers (Boost.Math
// brent_find_minima, through src/solvers/extremum.hpp).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>

#include "chatter/error.hpp"
#include "chatter/lobes.hpp"  // parallel_for
#include "chatter/optimization.hpp"
#include "../solvers/extremum.hpp"

namespace chatter {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Scan points when OptimizeOptions leaves them 0. Speeds: the depth limit has
// a pocket per lobe; 121 speeds over the bounds resolve pockets wider than
// 1/60 of the range (turning: one analytic solve each, cheap). Milling: each
// speed is an sdm limit and forced responses, ~0.1 s: 41.
constexpr int kTurningSpeedPoints = 121;
constexpr int kMillingSpeedPoints = 41;
constexpr int kFeedPoints = 41;
constexpr int kDepthPoints = 9;
// Brent's minimiser stops once the variable is located to this fraction of
// its bracket (two scan spacings), or after kPolishEvaluations evaluations.
constexpr double kPolishWidth = 1e-7;
constexpr std::uintmax_t kPolishEvaluations = 80;
// A polished variable this close to a bound (fraction of its range) is tried
// at the bound itself: Brent never evaluates the ends of its bracket.
constexpr double kSnapFraction = 1e-4;

std::vector<double> spaced(const Bounds& b, int n) {
  if (b.fixed()) return {b.lo};
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = i == n - 1 ? b.hi : b.lo + (b.hi - b.lo) * i / (n - 1);
  return x;
}

// How far a point is from feasible: the relative excess of each failing
// constraint (1 for a value that does not exist), plus 1 for an objective
// that does not.
double violation(const Performance& r) {
  double v = std::isfinite(r.objective) ? 0.0 : 1.0;
  for (const ConstraintCheck& c : r.constraints)
    if (!c.ok) v += std::isfinite(c.value) ? std::abs(c.value - c.limit) / std::max(std::abs(c.limit), 1e-300) : 1.0;
  return v;
}

// The value the polish minimises: the objective where feasible, else more
// than any feasible value, growing with the violation (finite, so Brent's
// parabolic steps stay defined).
struct Merit {
  double penalty = 1.0;
  double operator()(const Performance& r) const { return r.feasible ? r.objective : penalty + violation(r); }
};

// Minimum of f on [a, b] by Brent's method (a == b: f(a)).
template <class F>
void minimise(F&& f, double a, double b) {
  if (!(b > a)) {
    f(a);
    return;
  }
  detail::maximize_on([&](double x) { return -f(x); }, a, b, kPolishWidth * (b - a), kPolishEvaluations);
}

std::pair<double, double> bracket(const std::vector<double>& x, std::size_t i) {
  return {x[i == 0 ? 0 : i - 1], x[std::min(i + 1, x.size() - 1)]};
}

std::string feed_key(const OptimizationModel& m) { return std::string(m.process().feed_record_key()); }

// Every point of the grid S × D × F, index (i · nD + k) · nF + j: each speed
// on its own thread (the depth limit is solved once per speed).
std::vector<Performance> scan_grid(const OptimizationModel& model, const Corrections& correction,
                                   const std::vector<double>& S, const std::vector<double>& F,
                                   const std::vector<double>& D) {
  const IndexValues none = unknown_indices();
  const std::size_t nF = F.size(), nD = D.size();
  std::vector<Performance> scan(S.size() * nD * nF);
  parallel_for(S.size(), model.threads(), [&](std::size_t i) {
    for (std::size_t k = 0; k < nD; ++k)
      for (std::size_t j = 0; j < nF; ++j) scan[(i * nD + k) * nF + j] = model.evaluate({S[i], F[j], D[k]}, correction, none);
  });
  return scan;
}

// The local minima over speed of the rows' best merits (feasible rows only;
// of a plateau its first speed), best first, at most `count`.
std::vector<std::size_t> best_local_minima(const std::vector<double>& row, const std::vector<bool>& feasible,
                                           std::size_t count) {
  const std::size_t n = row.size();
  std::vector<std::size_t> minima;
  for (std::size_t i = 0; i < n; ++i) {
    if (!feasible[i]) continue;
    const bool left = i == 0 || row[i] <= row[i - 1];
    const bool right = i + 1 == n || row[i] <= row[i + 1];
    const bool plateau = i > 0 && row[i] == row[i - 1] && !minima.empty() && minima.back() == i - 1;
    if (left && right && !plateau) minima.push_back(i);
  }
  std::sort(minima.begin(), minima.end(), [&](std::size_t a, std::size_t b) { return row[a] < row[b]; });
  minima.resize(std::min(minima.size(), count));
  return minima;
}

// What holds the optimum where it is: the constraints at their limit (within
// kBindingTolerance) and the set-point bounds it sits on.
std::vector<std::string> binding_constraints(const Performance& best, const OptimizationModel& model) {
  const OptimizationSpec& spec = model.spec();
  std::vector<std::string> out;
  for (const ConstraintCheck& c : best.constraints)
    if (std::isfinite(c.value) && std::abs(c.value - c.limit) <= kBindingTolerance * std::abs(c.limit))
      out.push_back(c.name);
  auto on_bound = [&](double x, const Bounds& b, const std::string& name) {
    if (b.fixed()) return;
    if (x == b.lo) out.push_back(name + " lower bound");
    if (x == b.hi) out.push_back(name + " upper bound");
  };
  on_bound(best.point.spindle_rpm, spec.speed_rpm, spec.speed_as_cutting_speed ? "cutting_speed_m_per_min" : "spindle_rpm");
  on_bound(best.point.feed_m, spec.feed_m, feed_key(model));
  on_bound(best.point.depth_m, spec.depth_m, "depth_mm");
  return out;
}

}  // namespace

Optimum optimize(const OptimizationModel& model, const Corrections& correction, const OptimizeOptions& options) {
  const OptimizationSpec& spec = model.spec();
  const IndexValues none = unknown_indices();
  const int ns = options.speed_points > 0 ? options.speed_points
                                          : (model.milling() ? kMillingSpeedPoints : kTurningSpeedPoints);
  const int nf = options.feed_points > 0 ? options.feed_points : kFeedPoints;
  const int nd = options.depth_points > 0 ? options.depth_points : kDepthPoints;
  if (ns < 2 || nf < 2 || nd < 2) throw InputError("OptimizeOptions: scan points must be >= 2");
  const std::vector<double> S = spaced(spec.speed_rpm, ns), F = spaced(spec.feed_m, nf), D = spaced(spec.depth_m, nd);
  const std::size_t nS = S.size(), nF = F.size(), nD = D.size();
  std::atomic<std::size_t> evaluations{0};

  // 1. The scan of the whole grid.
  const std::vector<Performance> scan = scan_grid(model, correction, S, F, D);
  evaluations += scan.size();
  double largest = 0.0;
  bool any_feasible = false;
  for (const Performance& r : scan)
    if (r.feasible) any_feasible = true, largest = std::max(largest, std::abs(r.objective));
  const Merit merit{2.0 * largest + 1.0};

  // The best point of each speed row, and the local minima over speed.
  std::vector<double> row(nS, kInf);
  std::vector<std::size_t> row_at(nS, 0);
  for (std::size_t i = 0; i < nS; ++i)
    for (std::size_t c = 0; c < nD * nF; ++c)
      if (const double m = merit(scan[i * nD * nF + c]); m < row[i]) row[i] = m, row_at[i] = c;
  Optimum out;
  if (!any_feasible) {
    const std::size_t i = static_cast<std::size_t>(std::min_element(row.begin(), row.end()) - row.begin());
    out.best = scan[i * nD * nF + row_at[i]];
    out.evaluations = evaluations;
    return out;
  }
  out.found = true;
  std::vector<bool> feasible(nS);
  for (std::size_t i = 0; i < nS; ++i) feasible[i] = scan[i * nD * nF + row_at[i]].feasible;
  const std::vector<std::size_t> minima =
      best_local_minima(row, feasible, static_cast<std::size_t>(std::max(options.candidates, 1)));

  // 2. Polish each: Brent over speed of (Brent over depth of (Brent over
  //    feed)), each bracketed by the scan's neighbours; the best point any
  //    evaluation met is kept.
  std::vector<Performance> polished(minima.size());
  parallel_for(minima.size(), model.threads(), [&](std::size_t c) {
    const std::size_t i = minima[c], k = row_at[i] / nF, j = row_at[i] % nF;
    Performance best = scan[i * nD * nF + row_at[i]];
    double best_merit = merit(best);
    std::size_t count = 0;
    auto at = [&](double rpm, double d, double f) {
      Performance r = model.evaluate({rpm, f, d}, correction, none);
      ++count;
      const double m = merit(r);
      if (m < best_merit) best_merit = m, best = std::move(r);
      return m;
    };
    // Plain variables, not structured bindings: the lambdas below capture
    // them (clang before 16, which the fuzz build uses, cannot).
    const auto fb = bracket(F, j), db = bracket(D, k), sb = bracket(S, i);
    const double f_lo = fb.first, f_hi = fb.second, d_lo = db.first, d_hi = db.second, s_lo = sb.first,
                 s_hi = sb.second;
    auto over_feed = [&](double rpm, double d) {
      double low = kInf;
      minimise([&](double f) { const double v = at(rpm, d, f); low = std::min(low, v); return v; }, f_lo, f_hi);
      return low;
    };
    auto over_depth = [&](double rpm) {
      double low = kInf;
      minimise([&](double d) { const double v = over_feed(rpm, d); low = std::min(low, v); return v; }, d_lo, d_hi);
      return low;
    };
    minimise([&](double rpm) { return over_depth(rpm); }, s_lo, s_hi);
    // Snap to a bound the polish came close to (Brent stays inside).
    auto snap = [&](double SetPoint::*x, const Bounds& b) {
      if (b.fixed()) return;
      for (const double end : {b.lo, b.hi}) {
        SetPoint p = best.point;
        if (p.*x == end || std::abs(p.*x - end) > kSnapFraction * (b.hi - b.lo)) continue;
        p.*x = end;
        Performance r = model.evaluate(p, correction, none);
        ++count;
        if (const double m = merit(r); m <= best_merit) best_merit = m, best = std::move(r);
      }
    };
    snap(&SetPoint::feed_m, spec.feed_m);
    snap(&SetPoint::depth_m, spec.depth_m);
    snap(&SetPoint::spindle_rpm, spec.speed_rpm);
    polished[c] = std::move(best);
    evaluations += count;
  });
  out.candidates_polished = static_cast<int>(minima.size());
  out.best = *std::min_element(polished.begin(), polished.end(), [&](const Performance& a, const Performance& b) {
    return merit(a) < merit(b);
  });
  out.evaluations = evaluations;

  out.binding = binding_constraints(out.best, model);
  return out;
}

LossMap loss_map(const OptimizationModel& model, double depth_m, int speed_points, int feed_points,
                 const Corrections& correction) {
  if (speed_points < 2 || feed_points < 2) throw InputError("loss_map: speed_points and feed_points must be >= 2");
  const OptimizationSpec& spec = model.spec();
  LossMap map;
  map.milling = model.milling();
  map.depth_m = depth_m;
  map.cutting_speed_per_rpm = model.cutting_speed_m_per_min(1.0);
  Bounds s = spec.speed_rpm, f = spec.feed_m;
  if (s.fixed()) s = {s.lo * 0.9, s.hi * 1.1};  // a fixed speed still gets a plane around it
  if (f.fixed()) f = {f.lo * 0.9, f.hi * 1.1};
  map.speeds_rpm = spaced(s, speed_points);
  map.feeds_m = spaced(f, feed_points);
  const std::size_t ns = map.speeds_rpm.size(), nf = map.feeds_m.size();
  map.value.assign(ns * nf, 0.0);
  map.failing.assign(ns * nf, 0u);
  switch (spec.objective) {
    case Objective::kLoss: map.value_label = "loss"; break;
    case Objective::kRemovalRate: map.value_label = "removal rate, mm^3/s"; break;
    case Objective::kCost: map.value_label = "cost per part"; break;
    case Objective::kProductionRate: map.value_label = "parts per hour"; break;
  }
  const IndexValues none = unknown_indices();
  std::vector<std::vector<std::string>> names(ns);
  parallel_for(ns, model.threads(), [&](std::size_t i) {
    for (std::size_t j = 0; j < nf; ++j) {
      const Performance r = model.evaluate({map.speeds_rpm[i], map.feeds_m[j], depth_m}, correction, none);
      const std::size_t cell = i * nf + j;
      map.value[cell] = spec.objective == Objective::kLoss ? r.loss : std::abs(r.objective);
      if (names[i].empty())
        for (const ConstraintCheck& c : r.constraints) names[i].push_back(c.name);
      for (std::size_t c = 0; c < r.constraints.size(); ++c)
        if (!r.constraints[c].ok) map.failing[cell] |= 1u << c;
    }
  });
  map.constraint_names = names.front();
  for (std::size_t c = 0; c < map.constraint_names.size(); ++c)
    if (map.constraint_names[c] == "stability_margin") map.stability_bit = static_cast<int>(c);
  return map;
}

}  // namespace chatter
