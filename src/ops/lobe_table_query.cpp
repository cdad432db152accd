// Fast lobe queries: LobeTableQuery and best_speed()
// (include/chatter/operations.hpp, docs/operations.md "Fast queries").
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/operations.hpp"
#include "../solvers/extremum.hpp"
#include "ops_internal.hpp"

namespace chatter {

using namespace detail::ops;
using detail::maximize_on;

namespace {

// Interval splitting stops at this fraction of the table's 1/rpm range: about
// 21 halvings below a 400-point base grid, far below any lobe feature.
constexpr double kMinRelativeWidth = 1e-9;

// A solved speed of the table.
struct Node {
  double u;  // 1/rpm, min/rev
  StabilityLimit lim;
  double g;  // min(limit, depth_max), m
};

// Solves at the given speeds (in parallel) and appends the nodes in order,
// so the table is the same whatever the thread count.
void solve_nodes(const LobeSolver& solver, const std::vector<double>& us, const std::vector<double>& rpms,
                 unsigned threads, std::vector<Node>& nodes) {
  const double depth_max = solver.depth_max_m();
  std::vector<StabilityLimit> lims(us.size());
  parallel_for(us.size(), threads, [&](std::size_t i) { lims[i] = solver.limit_at(SpindleSpeed(rpms[i])); });
  for (std::size_t i = 0; i < us.size(); ++i) {
    Node n{us[i], lims[i], depth_max};
    if (n.lim.bounded()) n.g = std::min(n.lim.depth_limit_m, depth_max);
    nodes.push_back(n);
  }
}

// The base grid: nb speeds evenly spaced in u = 1/rpm, the ends exactly at
// the range (rpm_min, rpm_max, not 1/(1/rpm)).
void base_grid(double rpm_min, double rpm_max, int nb, std::vector<double>& us, std::vector<double>& rpms) {
  const double u_lo = 1.0 / rpm_max, u_hi = 1.0 / rpm_min;
  us.resize(static_cast<std::size_t>(nb));
  rpms.resize(us.size());
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
}

// The smallest bounded limit of the nodes (m); depth_max when none is.
double smallest_limit(const std::vector<Node>& nodes, double depth_max) {
  double smallest = kInf;
  for (const auto& n : nodes)
    if (n.lim.bounded()) smallest = std::min(smallest, n.g);
  return std::isfinite(smallest) ? smallest : depth_max;
}

}  // namespace

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

  std::vector<Node> nodes;
  auto eval_all = [&](const std::vector<double>& us, const std::vector<double>& rpms) {
    solve_nodes(solver, us, rpms, options.threads, nodes);
  };

  // 1. Base grid, evenly spaced in u = 1/rpm, the ends exactly at the range.
  const double u_lo = 1.0 / rpm_max, u_hi = 1.0 / rpm_min;
  const int nb = options.base_points;
  {
    std::vector<double> us, rpms;
    base_grid(rpm_min, rpm_max, nb, us, rpms);
    nodes.reserve(us.size() * 4);
    eval_all(us, rpms);
  }
  tolerance_m_ = options.tolerance_m > 0.0 ? options.tolerance_m
                                           : options.relative_tolerance * smallest_limit(nodes, depth_max_m_);

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
    const StabilityLimit l = solver.limit_at(SpindleSpeed(rpm));
    if (l.depth_limit_m > top.depth_limit_m) top = l;  // +inf wins too
    return l.depth_limit_m;
  };
  maximize_on(f, a, b, kGoldenRelativeWidth * b, kGoldenMaxIterations);
  return top;
}

}  // namespace chatter
