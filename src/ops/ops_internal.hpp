// Internal to the ops layer (src/ops): helpers and constants shared by the
// lobe-table queries, the robust speed search, the operations-file reader,
// check and recommend. Not part of the public API.
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <string_view>

#include "chatter/number_text.hpp"
#include "chatter/lobes.hpp"
#include "chatter/results.hpp"  // ForcedResponse

namespace chatter::detail::ops {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Speed maximisations (Brent: golden section with parabolic steps,
// src/solvers/extremum.hpp) stop when x is located to this
// fraction of the speed (≈ 1e-4 rev/min at 10 000 rev/min: well below what a
// spindle holds); at most kGoldenMaxIterations limit_at() calls.
inline constexpr double kGoldenRelativeWidth = 1e-8;

/// The part error a tolerance applies to (docs/results.md), m: |SLE| in
/// milling, the diametral error 2δ in turning; NaN when the cut is unstable
/// (no steady error). The one definition check and recommend read.
inline double part_error_m(const ForcedResponse& r) {
  if (!r.stable) return kNaN;
  return r.milling ? std::abs(r.surface_location_error_m) : r.diametral_error_m;
}
inline constexpr int kGoldenMaxIterations = 100;

// Progress estimates (solves): a scan of a few lobes and its refinements per
// process, the band and pocket searches per row; the reported fraction stops
// at kProgressCeiling until the work is done.
inline constexpr std::size_t kProgressSolvesPerProcess = 150;
inline constexpr std::size_t kProgressSolvesPerRow = 30;
inline constexpr double kProgressCeiling = 0.99;

/// A number with 10 significant digits, for messages.
inline std::string num(double x) {
  return number_text(x, 10);
}

/// `s` in single quotes, for messages.
/// (Appended, not `"'" + std::string(s)`: GCC 12 reports a false
/// -Wstringop-overflow on that operator+ once inlined.)
inline std::string in_quotes(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 2);
  out.append(1, '\'').append(s).append(1, '\'');
  return out;
}

/// A limit above `search_depth` counts as "none below the searched depth".
inline StabilityLimit clip(StabilityLimit lim, double search_depth_m) {
  if (lim.bounded() && lim.depth_limit_m > search_depth_m) {
    const double rpm = lim.spindle_rpm;
    lim = StabilityLimit{};
    lim.spindle_rpm = rpm;
  }
  return lim;
}

}  // namespace chatter::detail::ops
