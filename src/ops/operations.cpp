// Operation check, recommendation and fast lobe-table queries
// (include/chatter/operations.hpp, docs/operations.md).
#include "chatter/operations.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <sstream>
#include <tuple>

#include "chatter/error.hpp"
#include "chatter/solvers.hpp"

namespace chatter {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;

// Interval splitting stops at this fraction of the table's 1/rpm range: about
// 21 halvings below a 400-point base grid, far below any lobe feature.
constexpr double kMinRelativeWidth = 1e-9;
// Golden-section searches stop when the bracket is narrower than this
// fraction of the speed (≈ 1e-4 rev/min at 10 000 rev/min: well below what a
// spindle holds); at most kGoldenMaxIterations limit_at() calls.
constexpr double kGoldenRelativeWidth = 1e-8;
constexpr int kGoldenMaxIterations = 100;
// Two MRR values this close (relative) are a tie: power-bound MRR is the same
// at every speed up to round-off.
constexpr double kTieRelative = 1e-9;
// A depth cap within this relative distance of the chosen depth binds too.
// The golden-section search stops at a bracket of 1e-8 of the speed; on a
// steep lobe flank (d ln limit / d ln N up to ~10³) two caps that cross at the
// optimum then differ by up to ~1e-5.
constexpr double kBindingRelative = 1e-5;
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

std::string resolve_lobe_method(const Process& process, const std::string& requested, std::string* warning) {
  if (requested == "auto") {
    if (process.operation() == Operation::kTurning) return "analytic";
    if (has_lobe_method("sdm")) return "sdm";
    if (warning) *warning = std::string(kFlipLobeWarning);
    return "analytic";
  }
  if (!has_lobe_method(requested))
    throw InputError("--method " + requested + ": unknown method (this build has: auto, " + known_methods() + ")");
  if (requested == "analytic" && process.operation() == Operation::kMilling && warning)
    *warning = std::string(kFlipLobeWarning);
  return requested;
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

// Golden-section search for the maximum of `f` on [a, b]; returns the best
// point evaluated (including the ends' values passed in, if better).
template <class F>
double golden_maximize(F&& f, double a, double b) {
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = b - r * (b - a), x2 = a + r * (b - a);
  double f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < kGoldenMaxIterations && (b - a) > kGoldenRelativeWidth * b; ++it) {
    if (f1 >= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - r * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + r * (b - a);
      f2 = f(x2);
    }
  }
  return f1 >= f2 ? x1 : x2;
}

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
  golden_maximize(f, a, b);
  return top;
}

// ===================================================== operations file

namespace {

const std::vector<std::string> kRequiredColumns = {"id", "spindle_rpm", "depth_mm", "radial_immersion",
                                                   "feed_per_tooth_mm"};
const std::vector<std::string> kOptionalColumns = {"teeth", "milling_direction"};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Splits one CSV line; fields may be double-quoted with "" for a quote.
// Returns false (and sets *error) on an unterminated quote.
bool split_csv(std::string_view line, std::vector<std::string>& out, std::string* error) {
  out.clear();
  std::string cur;
  bool quoted = false, was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < line.size() && line[i + 1] == '"') {
          cur += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        cur += c;
      }
    } else if (c == '"' && trim(cur).empty()) {
      cur.clear();
      quoted = was_quoted = true;
    } else if (c == ',') {
      out.emplace_back(was_quoted ? cur : std::string(trim(cur)));
      cur.clear();
      was_quoted = false;
    } else {
      cur += c;
    }
  }
  if (quoted) {
    *error = "unterminated quote";
    return false;
  }
  out.emplace_back(was_quoted ? cur : std::string(trim(cur)));
  return true;
}

// Parses a finite number; "" if fine, else the reason.
std::string parse_number(std::string_view s, double& x) {
  std::string_view t = s;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
  if (t.empty() || ec != std::errc() || p != t.data() + t.size()) return "not a number";
  if (!std::isfinite(x)) return "must be a finite number";
  return "";
}

std::string parse_integer(std::string_view s, int& x) {
  std::string_view t = s;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
  if (t.empty() || ec != std::errc() || p != t.data() + t.size()) return "not an integer";
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
          std::string names;
          for (const auto* list : {&kRequiredColumns, &kOptionalColumns})
            for (const auto& c : *list) names += (names.empty() ? "" : ",") + c;
          throw InputError(where + "header column " + in_quotes(h) + ": unknown column (known: " + names +
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
    if (row.id.empty()) reasons.push_back("id: empty");

    auto number = [&](const std::string& name, double& x) -> bool {
      const std::string_view s = field(name);
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
    if (number("depth_mm", depth_mm) && !(depth_mm > 0.0))
      reasons.push_back("depth_mm = " + num(depth_mm) + ": must be > 0 mm");
    row.spindle_rpm = rpm;
    row.depth_m = depth_mm * 1e-3;

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
        else row.feed_per_tooth_m = fz * 1e-3;
      }
    }
    if (const std::string_view s = field("teeth"); !s.empty()) {
      int nt = 0;
      if (!milling) reasons.push_back("teeth = " + in_quotes(s) + ": only for milling (leave empty for turning)");
      else if (const std::string e = parse_integer(s, nt); !e.empty())
        reasons.push_back("teeth = " + in_quotes(s) + ": " + e);
      else if (nt < 1) reasons.push_back("teeth = " + std::to_string(nt) + ": must be >= 1");
      else row.teeth = nt;
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
        reasons.push_back("id " + in_quotes(row.id) + ": duplicate (first on line " + std::to_string(it->second) + ")");
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
  return out;
}

OperationsFile read_operations(const std::filesystem::path& file, Operation operation, const MachineLimits& machine) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot read file");
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
    return Process::milling(p);
  } catch (const std::invalid_argument& e) {
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
  else if (const std::string t = table.validate(); !t.empty()) os << t;
  return os.str();
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

  // One solver, table and best speed per distinct process.
  struct Group {
    Process process = Process::turning({1.0});
    std::string method;
    double depth_max_m = 0.0;
    std::unique_ptr<LobeSolver> solver;
    std::unique_ptr<LobeTableQuery> table;
    StabilityLimit best;
  };
  using Key = std::tuple<double, int, int>;
  auto key_of = [&](const OperationRow& r) -> Key {
    if (process.operation() == Operation::kTurning) return {0.0, 0, 0};
    const auto& m = process.milling_parameters();
    return {r.radial_immersion.value_or(m.radial_immersion), r.teeth.value_or(m.teeth),
            static_cast<int>(r.direction.value_or(m.direction))};
  };
  std::map<Key, Group> groups;
  for (const auto& r : rows) {
    Group& g = groups[key_of(r)];
    if (g.method.empty()) {
      g.process = process_for(process, r);
      std::string warning;
      g.method = resolve_lobe_method(g.process, options.method, &warning);
      if (!warning.empty() &&
          std::find(report.warnings.begin(), report.warnings.end(), warning) == report.warnings.end())
        report.warnings.push_back(warning);
    }
    g.depth_max_m = std::max(g.depth_max_m, search_depth(r));
  }
  LobeTableQueryOptions table_options = options.table;
  table_options.threads = options.threads;
  for (auto& [key, g] : groups) {
    g.solver = make_lobe_solver(g.method, model, g.process, g.depth_max_m);
    g.table = std::make_unique<LobeTableQuery>(*g.solver, options.machine.rpm_min, options.machine.rpm_max,
                                               table_options);
    g.best = best_speed(*g.solver, *g.table);
  }
  std::vector<StabilityLimit> own(rows.size());  // exact limit at each row's speed
  parallel_for(rows.size(), options.threads, [&](std::size_t i) {
    own[i] = groups.at(key_of(rows[i])).solver->limit_at(rows[i].spindle_rpm);
  });

  for (std::size_t i = 0; i < rows.size(); ++i) {
    const OperationRow& r = rows[i];
    const Group& g = groups.at(key_of(r));
    const double ds = search_depth(r);
    OperationCheck c;
    c.op = r;
    c.method = g.method;
    c.search_depth_m = ds;
    c.limit = clip(own[i], ds);
    c.stable = r.depth_m < c.limit.depth_limit_m;
    c.margin = c.limit.depth_limit_m / r.depth_m;
    if (!c.limit.bounded()) {  // no limit below the searched depth here: stay
      c.suggestion = c.limit;
      c.suggestion_margin = kInf;
    } else {
      // Unbounded stretches (limit above this row's searched depth): nearest one.
      const StabilityLimit* near = nullptr;
      for (const auto& p : g.table->points())
        if (!p.bounded() || p.depth_limit_m > ds)
          if (!near || std::abs(p.spindle_rpm - r.spindle_rpm) < std::abs(near->spindle_rpm - r.spindle_rpm))
            near = &p;
      if (near) {
        c.suggestion = clip(*near, ds);
        c.suggestion_margin = kInf;
      } else {
        const StabilityLimit best = c.limit.depth_limit_m >= g.best.depth_limit_m ? c.limit : clip(g.best, ds);
        if (best.depth_limit_m > r.depth_m) {
          c.suggestion = best;
          c.suggestion_margin = best.depth_limit_m / r.depth_m;
        }
      }
    }
    report.checks.push_back(std::move(c));
  }
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
  else if (const std::string t = table.validate(); !t.empty()) os << t;
  return os.str();
}

std::string to_string(Binding b) {
  switch (b) {
    case Binding::kStability: return "stability";
    case Binding::kPower: return "power";
    case Binding::kTorque: return "torque";
    case Binding::kDepthMax: return "depth_max";
    case Binding::kSpeedRange: return "speed_range";
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
                     (process.operation() == Operation::kMilling ? "tool diameter (--tool-diameter-mm)"
                                                                 : "workpiece diameter (--workpiece-diameter-mm)"));
  Recommendation rec;
  std::string warning;
  rec.method = resolve_lobe_method(process, options.method, &warning);
  if (!warning.empty()) rec.warnings.push_back(warning);
  std::vector<std::string> model_warnings;
  const CutModel cm = cut_model(process, options, model_warnings);
  if (options.diameter_m > 0.0)
    rec.warnings.insert(rec.warnings.end(), model_warnings.begin(), model_warnings.end());

  rec.search_depth_m = kRecommendSearchFactor * options.depth_max_m / options.safety;
  const auto solver = make_lobe_solver(rec.method, model, process, rec.search_depth_m);
  LobeTableQueryOptions table_options = options.table;
  table_options.threads = options.threads;
  const LobeTableQuery table(*solver, mc.rpm_min, mc.rpm_max, table_options);

  struct Cand {
    StabilityLimit lim;
    double stab, power, torque, cap, depth, objective, margin;
  };
  auto evaluate = [&](const StabilityLimit& lim0) {
    Cand c;
    c.lim = clip(lim0, rec.search_depth_m);
    const double n = c.lim.spindle_rpm;
    c.stab = c.lim.bounded() ? options.safety * c.lim.depth_limit_m : kInf;
    c.power = std::isfinite(mc.max_power_w) ? mc.max_power_w / (cm.power_per_depth_rpm * n) : kInf;
    c.torque = std::isfinite(mc.max_torque_n_m) ? mc.max_torque_n_m / cm.torque_per_depth : kInf;
    c.cap = options.depth_max_m;
    c.depth = std::min({c.stab, c.power, c.torque, c.cap});
    c.objective = n * c.depth;  // MRR / (mrr per depth·rpm)
    c.margin = c.lim.depth_limit_m / c.depth;
    return c;
  };
  auto better = [](const Cand& x, const Cand& y) {  // x strictly better than y
    if (x.objective > y.objective * (1.0 + kTieRelative)) return true;
    if (x.objective < y.objective * (1.0 - kTieRelative)) return false;
    return x.margin > y.margin;
  };

  const auto& pts = table.points();
  std::vector<Cand> cands;
  cands.reserve(pts.size());
  for (const auto& p : pts) cands.push_back(evaluate(p));
  std::size_t ib = 0;
  for (std::size_t i = 1; i < cands.size(); ++i)
    if (better(cands[i], cands[ib])) ib = i;
  Cand best = cands[ib];
  const bool power_bound = best.depth == best.power;
  if (!power_bound && ib > 0 && ib + 1 < cands.size()) {
    auto f = [&](double rpm) {
      const Cand c = evaluate(solver->limit_at(rpm));
      if (better(c, best)) best = c;
      return c.objective;
    };
    golden_maximize(f, pts[ib - 1].spindle_rpm, pts[ib + 1].spindle_rpm);
  }

  rec.spindle_rpm = best.lim.spindle_rpm;
  rec.depth_m = best.depth;
  rec.limit = best.lim;
  rec.margin = best.margin;
  rec.depth_stability_m = best.stab;
  rec.depth_power_m = best.power;
  rec.depth_torque_m = best.torque;
  rec.depth_cap_m = best.cap;
  rec.force_n = cm.force_per_depth * rec.depth_m;
  rec.torque_n_m = cm.torque_per_depth * rec.depth_m;
  rec.power_w = cm.power_per_depth_rpm * rec.depth_m * rec.spindle_rpm;
  rec.mrr_m3_per_s = cm.mrr_per_depth_rpm * rec.depth_m * rec.spindle_rpm;
  rec.mrr_per_diameter_m2_per_s = cm.mrr_per_diam_depth_rpm * rec.depth_m * rec.spindle_rpm;
  auto binds = [&](double cap) { return std::isfinite(cap) && cap <= rec.depth_m * (1.0 + kBindingRelative); };
  if (binds(best.stab)) rec.binding.push_back(Binding::kStability);
  if (binds(best.power)) rec.binding.push_back(Binding::kPower);
  if (binds(best.torque)) rec.binding.push_back(Binding::kTorque);
  if (binds(best.cap)) rec.binding.push_back(Binding::kDepthMax);
  // The speed range binds when the optimum sits on an end of the range and MRR
  // still grows towards it (a power-bound MRR is flat in speed: it does not).
  if (!binds(best.power) && (ib == 0 || ib + 1 == cands.size()) &&
      best.lim.spindle_rpm == pts[ib].spindle_rpm) {
    const Cand& inner = cands[ib == 0 ? 1 : ib - 1];
    if (best.objective > inner.objective * (1.0 + kTieRelative)) rec.binding.push_back(Binding::kSpeedRange);
  }
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
      case Binding::kSpeedRange:
        os << "speed range (at the machine's "
           << (r.spindle_rpm >= o.machine.rpm_max ? "maximum " : "minimum ") << f(r.spindle_rpm, 0)
           << " rev/min; more MRR lies beyond it)";
        break;
    }
  }
  os << "\n";
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
