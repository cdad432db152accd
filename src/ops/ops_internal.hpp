// Internal to the ops layer (src/ops): helpers and constants shared by the
// lobe-table queries, the robust speed search, the operations-file reader,
// check and recommend. Not part of the public API.
#pragma once

#include <algorithm>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/cutting_law.hpp"
#include "chatter/lobes.hpp"

namespace chatter::detail::ops {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Speed maximisations (Brent: golden section with parabolic steps,
// src/solvers/extremum.hpp) stop when x is located to this
// fraction of the speed (≈ 1e-4 rev/min at 10 000 rev/min: well below what a
// spindle holds); at most kGoldenMaxIterations limit_at() calls.
inline constexpr double kGoldenRelativeWidth = 1e-8;
inline constexpr int kGoldenMaxIterations = 100;

// Progress estimates (solves): a scan of a few lobes and its refinements per
// process, the band and pocket searches per row; the reported fraction stops
// at kProgressCeiling until the work is done.
inline constexpr std::size_t kProgressSolvesPerProcess = 150;
inline constexpr std::size_t kProgressSolvesPerRow = 30;
inline constexpr double kProgressCeiling = 0.99;

/// A number with 10 significant digits, for messages.
inline std::string num(double x) {
  std::ostringstream os;
  os.precision(10);
  os << x;
  return os.str();
}

/// The cutting law's options of recommend and check (docs/cutting_law.md):
/// turning takes K_c when given, else the feed-force coefficient K_f as its
/// cutting pressure, said once in `warnings`; milling needs nothing more.
inline CuttingLawOptions cutting_law_options(const Process& p, std::optional<double> kc,
                                             std::vector<std::string>& warnings) {
  CuttingLawOptions o;
  if (p.operation() != Operation::kTurning) return o;
  o.turning_tangential_coefficient_n_per_m2 = kc.value_or(p.turning_parameters().feed_force_coefficient_n_per_m2);
  if (!kc) {
    const std::string w = "turning power and torque use the feed-force coefficient K_f as cutting pressure (no "
                          "tangential coefficient given); with force angle θ the true value is K_f·tanθ, larger";
    if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
  }
  return o;
}

/// `s` in single quotes, for messages.
inline std::string in_quotes(std::string_view s) { return "'" + std::string(s) + "'"; }

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
