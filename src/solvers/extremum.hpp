// Internal: the one bracketed one-dimensional maximiser the solvers and the
// operations layer share (the lowest-depth search of PhaseSearch, the best
// speed between two table points). Not part of the public API.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include <boost/math/tools/minima.hpp>

namespace chatter::detail {

struct Maximum {
  double x = 0.0;       ///< argument of the largest value found
  double value = 0.0;   ///< f(x)
  std::uintmax_t evaluations = 0;
};

/// Maximum of f on [a, b] (a < b) by Brent's minimiser (golden section with
/// parabolic steps; Brent 1973, ch. 5) from Boost.Math `brent_find_minima`,
/// run on the unit variable u = (x − a)/(b − a) so that its relative
/// tolerance becomes an absolute one on the bracket: it stops once x is
/// located to about `width` (same unit as x; the tolerance is capped below by
/// Boost at √ε·(b − a)) or after `max_evaluations` calls of f.
/// For a unimodal f the result is within `width` of the maximiser; otherwise a
/// local maximum. f must not return NaN. Cost: the evaluations of f, typically
/// 10–40.
template <class F>
Maximum maximize_on(F&& f, double a, double b, double width, std::uintmax_t max_evaluations) {
  if (!(b > a)) return {a, f(a), 1};
  const double span = b - a;
  // brent_find_minima stops when |x − m| <= 2 tol·|u| + tol/2 − (bracket)/2 with
  // tol = 2^(1−bits): a bracket of about 4·tol on u ∈ [0, 1].
  const double tol_u = std::max(0.25 * width / span, 0x1p-40);
  const int bits = std::clamp(1 + static_cast<int>(std::ceil(-std::log2(tol_u))), 4, 52);
  std::uintmax_t iters = max_evaluations;
  const auto [u, neg] = boost::math::tools::brent_find_minima(
      [&](double v) { return -f(a + v * span); }, 0.0, 1.0, bits, iters);
  return {a + u * span, -neg, iters};
}

}  // namespace chatter::detail
