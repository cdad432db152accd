// Robust spindle speeds: the pocket of a speed and robust_speed()
// (include/chatter/operations.hpp, docs/operations.md "Search"); the search
// itself is src/ops/speed_search.hpp.
#include <cmath>
#include <optional>
#include <string>
#include <tuple>

#include "chatter/error.hpp"
#include "chatter/operations.hpp"
#include "ops_internal.hpp"
#include "speed_search.hpp"

namespace chatter {
namespace detail::ops {

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
  s.scan();
  const double n = s.best(kInf, 0.5 * (rpm_min + rpm_max));
  if (!(s.band_min(n) > depth_m)) return std::nullopt;
  return make_pocket(s, n, depth_m, depth_m);
}

}  // namespace chatter
