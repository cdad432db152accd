// Results shared by every lobe solver, and the interface they implement.
// Depths are in m and speeds in rev/min inside these structs; the table
// writers convert to mm at the edge.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace chatter {

/// The stability limit (lobe envelope) at one spindle speed.
struct StabilityLimit {
  double spindle_rpm = 0.0;
  /// Largest depth (m) that is asymptotically stable at this speed;
  /// +inf when no instability exists below the searched depth.
  double depth_limit_m = std::numeric_limits<double>::infinity();
  /// Chatter frequency (Hz) at the limit; NaN when depth_limit_m is +inf.
  double chatter_frequency_hz = std::numeric_limits<double>::quiet_NaN();
  /// Lobe number k >= 0 (ωτ = ε + 2πk); −1 when depth_limit_m is +inf.
  int lobe = -1;
  /// Eigenvalue branch (0 or 1) of the transfer-function solvers; −1 if none.
  int branch = -1;

  bool bounded() const { return std::isfinite(depth_limit_m); }
};

/// One point of a lobe curve.
struct LobePoint {
  double spindle_rpm = 0.0;
  double depth_m = 0.0;
  double chatter_frequency_hz = 0.0;
};

/// A continuous piece of one lobe (fixed lobe number and branch), ordered by
/// chatter frequency.
struct LobeCurve {
  int lobe = 0;
  int branch = 0;
  std::vector<LobePoint> points;
};

/// The speed-independent minimum of every lobe (the "absolute" limit).
struct AbsoluteLimit {
  double depth_m = std::numeric_limits<double>::infinity();  ///< +inf if above the searched depth.
  double chatter_frequency_hz = std::numeric_limits<double>::quiet_NaN();
  int branch = -1;
};

/// What every lobe solver offers. Implementations are immutable after
/// construction: every const member is safe to call from several threads.
class LobeSolver {
 public:
  virtual ~LobeSolver() = default;
  /// Short method name as used on the command line ("analytic", "coupled").
  virtual std::string method() const = 0;
  /// The exact envelope at one spindle speed (rev/min > 0).
  virtual StabilityLimit limit_at(double spindle_rpm) const = 0;
  /// Deepest cut (m) the solver searches; limits above it are reported as +inf.
  virtual double depth_max_m() const = 0;
};

/// `count` spindle speeds evenly spaced from rpm_min to rpm_max, both
/// included (count >= 2, or count == 1 with rpm_min == rpm_max).
/// @throws InputError on an empty, negative or non-finite range.
std::vector<double> evenly_spaced_speeds(double rpm_min, double rpm_max, int count);

/// limit_at() at each speed, in order. With threads > 1 the speeds are shared
/// among that many threads (each speed is independent, so the result is
/// bitwise the same whatever the thread count); threads = 0 uses the
/// hardware concurrency. `per_speed`, if given, is called after each speed
/// with the number done so far (from the worker threads; keep it cheap and
/// thread-safe).
std::vector<StabilityLimit> lobe_envelope(const LobeSolver& solver, const std::vector<double>& speeds_rpm,
                                          unsigned threads = 1,
                                          const std::function<void(std::size_t done)>& per_speed = {});

/// The same loop for any per-speed computation: out[i] = f(i) for i < n.
void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& f,
                  const std::function<void(std::size_t done)>& per_item = {});

}  // namespace chatter
