#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>
#include <sstream>
#include <utility>

#include "chatter/error.hpp"
#include "chatter/lobes.hpp"

namespace chatter {

std::vector<double> evenly_spaced_speeds(double rpm_min, double rpm_max, int count) {
  std::ostringstream os;
  if (!(std::isfinite(rpm_min) && rpm_min > 0.0))
    os << "rpm_min = " << rpm_min << ": must be > 0 rev/min";
  else if (!(std::isfinite(rpm_max) && rpm_max >= rpm_min))
    os << "rpm_max = " << rpm_max << ": must be >= rpm_min (" << rpm_min << ")";
  else if (count < 1)
    os << "rpm_points = " << count << ": must be >= 1";
  else if (count == 1 && rpm_max != rpm_min)
    os << "rpm_points = 1: needs rpm_min == rpm_max";
  else if (count > 1 && rpm_max == rpm_min)
    os << "rpm_max = rpm_min = " << rpm_min << ": empty range for " << count << " points";
  if (!os.str().empty()) throw InputError(os.str());
  std::vector<double> v(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
    v[static_cast<std::size_t>(i)] =
        count == 1 ? rpm_min : rpm_min + (rpm_max - rpm_min) * static_cast<double>(i) / (count - 1);
  if (count > 1) v.back() = rpm_max;  // exactly, whatever the rounding
  return v;
}

void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& f,
                  const std::function<void(std::size_t done)>& per_item) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(n, 1)));
  std::atomic<std::size_t> next{0}, done{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        f(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;  // stop handing out work
        return;
      }
      const std::size_t d = ++done;
      if (per_item) per_item(d);
    }
  };
  if (threads <= 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads);
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
  }
  if (error) std::rethrow_exception(error);
}

std::vector<StabilityLimit> lobe_envelope(const LobeSolver& solver, const std::vector<double>& speeds_rpm,
                                          unsigned threads, const std::function<void(std::size_t done)>& per_speed) {
  std::vector<StabilityLimit> rows(speeds_rpm.size());
  parallel_for(
      speeds_rpm.size(), threads, [&](std::size_t i) { rows[i] = solver.limit_at(SpindleSpeed(speeds_rpm[i])); }, per_speed);
  return rows;
}

// ---------------------------------------------------------------------------
// Adaptive speeds (EnvelopeRefinement in lobes.hpp)

std::string EnvelopeRefinement::validate() const {
  std::ostringstream os;
  if (!(std::isfinite(depth_rel_tol) && depth_rel_tol > 0.0))
    os << "depth_rel_tol = " << depth_rel_tol << ": must be > 0";
  else if (!(std::isfinite(depth_abs_tol_m) && depth_abs_tol_m >= 0.0))
    os << "depth_abs_tol_m = " << depth_abs_tol_m << ": must be >= 0";
  else if (!(cusp_rel_tol >= 1e-12 && cusp_rel_tol <= 0.1))
    os << "cusp_rel_tol = " << cusp_rel_tol << ": must be in [1e-12, 0.1]";
  return os.str();
}

namespace {

// Priority of an interval whose error cannot be measured (a gap edge, a
// lobe tip dipping below depth_max inside): before every finite error.
constexpr double kUnmeasured = 1e12;

bool same_piece(const StabilityLimit& a, const StabilityLimit& b) {
  return a.bounded() == b.bounded() && (!a.bounded() || (a.lobe == b.lobe && a.branch == b.branch));
}

// Error of the straight line a-b at the midpoint m, in units of the
// tolerance (<= 1: accepted); kUnmeasured when the ends and midpoint are
// not all bounded (0 when none is).
double midpoint_error(const StabilityLimit& a, const StabilityLimit& m, const StabilityLimit& b,
                      const EnvelopeRefinement& o) {
  if (!a.bounded() && !m.bounded() && !b.bounded()) return 0.0;
  if (!(a.bounded() && m.bounded() && b.bounded())) return kUnmeasured;
  const double line = 0.5 * (a.depth_limit_m + b.depth_limit_m);
  const double err = std::abs(m.depth_limit_m - line) / (o.depth_rel_tol * m.depth_limit_m + o.depth_abs_tol_m);
  return std::isfinite(err) ? std::min(err, kUnmeasured) : kUnmeasured;
}

// An interval to split further: not narrower than cusp_rel_tol × speed,
// and either its error is over the tolerance or it holds a lobe change.
bool still_open(const StabilityLimit& a, const StabilityLimit& b, double error, const EnvelopeRefinement& o) {
  const double width = b.spindle_rpm - a.spindle_rpm;
  if (!(width > o.cusp_rel_tol * 0.5 * (a.spindle_rpm + b.spindle_rpm))) return false;
  return error > 1.0 || !same_piece(a, b);
}

}  // namespace

RefinedEnvelope refine_envelope(const std::function<StabilityLimit(double)>& limit_at,
                                std::vector<StabilityLimit> start, const EnvelopeRefinement& options,
                                unsigned threads, const std::function<void(std::size_t done)>& per_speed) {
  if (const std::string rule = options.validate(); !rule.empty())
    throw InputError("envelope refinement: " + rule);
  if (start.empty()) throw InputError("envelope refinement: no start rows");
  std::sort(start.begin(), start.end(),
            [](const StabilityLimit& a, const StabilityLimit& b) { return a.spindle_rpm < b.spindle_rpm; });
  for (std::size_t i = 0; i + 1 < start.size(); ++i)
    if (!(start[i].spindle_rpm < start[i + 1].spindle_rpm))
      throw InputError("envelope refinement: speed " + std::to_string(start[i].spindle_rpm) +
                       " rev/min given twice (or not finite)");

  RefinedEnvelope out;
  out.rows = std::move(start);
  // State of interval i (rows i, i+1): open or not, and its priority (the
  // measured error in tolerance units; before any test, an estimate).
  struct Interval {
    bool open = false;
    double priority = 0.0;
  };
  std::vector<Interval> iv(out.rows.size() - 1);
  for (std::size_t i = 0; i < iv.size(); ++i) {
    const StabilityLimit &a = out.rows[i], &b = out.rows[i + 1];
    double estimate = kUnmeasured;
    if (same_piece(a, b))
      estimate = !a.bounded() ? 0.0
                              : std::abs(b.depth_limit_m - a.depth_limit_m) /
                                    (options.depth_rel_tol * std::min(a.depth_limit_m, b.depth_limit_m) +
                                     options.depth_abs_tol_m);
    // Untested: open unless narrower than the cusp width.
    iv[i] = {still_open(a, b, kUnmeasured, options), std::min(estimate, kUnmeasured)};
  }

  std::size_t done = 0;
  for (;;) {
    std::vector<std::size_t> todo;
    for (std::size_t i = 0; i < iv.size(); ++i)
      if (iv[i].open) todo.push_back(i);
    if (todo.empty()) {
      out.converged = true;
      break;
    }
    const std::size_t budget = options.max_solves - out.solves;
    if (budget == 0) break;
    if (todo.size() > budget) {
      std::stable_sort(todo.begin(), todo.end(),
                       [&](std::size_t x, std::size_t y) { return iv[x].priority > iv[y].priority; });
      todo.resize(budget);
      std::sort(todo.begin(), todo.end());
    }
    std::vector<StabilityLimit> mid(todo.size());
    parallel_for(
        todo.size(), threads,
        [&](std::size_t j) {
          const double ra = out.rows[todo[j]].spindle_rpm, rb = out.rows[todo[j] + 1].spindle_rpm;
          mid[j] = limit_at(0.5 * (ra + rb));
          mid[j].spindle_rpm = 0.5 * (ra + rb);
        },
        [&](std::size_t d) {
          if (per_speed) per_speed(done + d);
        });
    done += todo.size();
    out.solves += todo.size();

    // Merge the midpoints in and set the state of the halves.
    std::vector<StabilityLimit> rows;
    std::vector<Interval> next;
    rows.reserve(out.rows.size() + todo.size());
    next.reserve(iv.size() + todo.size());
    std::size_t j = 0;
    for (std::size_t i = 0; i < out.rows.size(); ++i) {
      rows.push_back(out.rows[i]);
      if (i == iv.size()) break;
      if (j < todo.size() && todo[j] == i) {
        const StabilityLimit &a = out.rows[i], &m = mid[j], &b = out.rows[i + 1];
        const double e = midpoint_error(a, m, b, options);
        rows.push_back(m);
        // The test only vouches for the halves when a-b was one smooth piece:
        // across a cusp the line a-b says nothing about either side, so both
        // halves get their own test.
        const double e_half = same_piece(a, b) ? e : std::max(e, kUnmeasured);
        next.push_back({still_open(a, m, e_half, options), e});
        next.push_back({still_open(m, b, e_half, options), e});
        ++j;
      } else {
        next.push_back(iv[i]);
      }
    }
    out.rows = std::move(rows);
    iv = std::move(next);
  }
  return out;
}

RefinedEnvelope refine_envelope(const LobeSolver& solver, std::vector<StabilityLimit> start,
                                const EnvelopeRefinement& options, unsigned threads,
                                const std::function<void(std::size_t done)>& per_speed) {
  return refine_envelope([&solver](double rpm) { return solver.limit_at(SpindleSpeed(rpm)); }, std::move(start), options,
                         threads, per_speed);
}

RefinedEnvelope adaptive_envelope(const std::function<StabilityLimit(double)>& limit_at, double rpm_min,
                                  double rpm_max, int max_points, const EnvelopeRefinement& options,
                                  unsigned threads, const std::function<void(std::size_t done)>& per_speed) {
  if (max_points < 2) throw InputError("rpm_points = " + std::to_string(max_points) + ": must be >= 2");
  const int base = std::max(2, max_points / 4);
  const std::vector<double> speeds = evenly_spaced_speeds(rpm_min, rpm_max, base);
  if (const std::string rule = options.validate(); !rule.empty())
    throw InputError("envelope refinement: " + rule);
  std::vector<StabilityLimit> rows(speeds.size());
  parallel_for(
      speeds.size(), threads,
      [&](std::size_t i) {
        rows[i] = limit_at(speeds[i]);
        rows[i].spindle_rpm = speeds[i];
      },
      per_speed);
  EnvelopeRefinement o = options;
  o.max_solves = static_cast<std::size_t>(max_points - base);
  RefinedEnvelope r = refine_envelope(
      limit_at, std::move(rows), o, threads,
      [&](std::size_t d) {
        if (per_speed) per_speed(static_cast<std::size_t>(base) + d);
      });
  r.solves += static_cast<std::size_t>(base);
  return r;
}

}  // namespace chatter
