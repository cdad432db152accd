// Internal: bracketed root finders shared by the transfer-function root
// search and the sdm depth search. Not part of the public API.
//   toms748_root: Boost.Math's TOMS 748 (Alefeld, Potra & Shi 1995: cubic
//                 inverse interpolation + double-length secant steps, at most
//                 ~2.7 evaluations per digit asymptotically);
//   brent_root:   Brent's zeroin (Brent 1973, ch. 4: bisection, secant and
//                 inverse quadratic interpolation).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <boost/math/tools/roots.hpp>

#include "chatter/error.hpp"

namespace chatter::detail {

/// Root of f on [a, b] given f(a) = fa and f(b) = fb of opposite signs (or
/// zero), to an absolute tolerance xtol (plus a few ulps of the root).
/// @throws NumericalError if the root is not bracketed.
template <class F>
double brent_root(F&& f, double a, double b, double fa, double fb, double xtol) {
  if (fa == 0.0) return a;
  if (fb == 0.0) return b;
  if ((fa > 0.0) == (fb > 0.0)) throw NumericalError("brent_root: root not bracketed");
  double c = a, fc = fa, d = b - a, e = d;
  for (int iter = 0; iter < 200; ++iter) {
    if ((fb > 0.0) == (fc > 0.0)) {
      c = a;
      fc = fa;
      d = e = b - a;
    }
    if (std::abs(fc) < std::abs(fb)) {
      a = b; b = c; c = a;
      fa = fb; fb = fc; fc = fa;
    }
    const double tol = 2.0 * std::numeric_limits<double>::epsilon() * std::abs(b) + 0.5 * xtol;
    const double m = 0.5 * (c - b);
    if (std::abs(m) <= tol || fb == 0.0) return b;
    if (std::abs(e) >= tol && std::abs(fa) > std::abs(fb)) {
      double p, q;
      const double s = fb / fa;
      if (a == c) {  // secant
        p = 2.0 * m * s;
        q = 1.0 - s;
      } else {  // inverse quadratic interpolation
        const double qq = fa / fc, r = fb / fc;
        p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
        q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
      }
      if (p > 0.0) q = -q; else p = -p;
      if (2.0 * p < std::min(3.0 * m * q - std::abs(tol * q), std::abs(e * q))) {
        e = d;
        d = p / q;
      } else {
        d = m;
        e = m;
      }
    } else {
      d = m;
      e = m;
    }
    a = b;
    fa = fb;
    b += (std::abs(d) > tol) ? d : (m > 0.0 ? tol : -tol);
    fb = f(b);
  }
  return b;
}

/// Root of f on [a, b] given f(a) = fa and f(b) = fb of opposite signs (or
/// zero), by Boost.Math toms748_solve: stops once the bracket is narrower than
/// xtol + 4 ulps of its ends and returns its midpoint (so within xtol/2 + a few
/// ulps of a root). At most `max_evaluations` calls of f (then the midpoint of
/// the last bracket). Cost: typically 5–15 evaluations for xtol ≈ 1e-15·|root|.
/// @throws NumericalError if the root is not bracketed.
template <class F>
double toms748_root(F&& f, double a, double b, double fa, double fb, double xtol,
                    std::uintmax_t max_evaluations = 200) {
  if (fa == 0.0) return a;
  if (fb == 0.0) return b;
  if ((fa > 0.0) == (fb > 0.0)) throw NumericalError("toms748_root: root not bracketed");
  if (a > b) {
    std::swap(a, b);
    std::swap(fa, fb);
  }
  const auto narrow = [xtol](double l, double r) {
    return r - l <= xtol + 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(l), std::abs(r));
  };
  std::uintmax_t iters = max_evaluations;
  const auto [lo, hi] = boost::math::tools::toms748_solve([&](double x) { return f(x); }, a, b, fa, fb, narrow, iters);
  return lo + 0.5 * (hi - lo);
}

}  // namespace chatter::detail
