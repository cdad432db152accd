// Internal: Brent's root finder (zeroin, Brent 1973 ch. 4: bisection, secant
// and inverse quadratic interpolation), shared by the transfer-function root
// search and the sdm depth search. Not part of the public API.
//
// Kept hand-written on purpose (measured, docs/performance.md): Boost.Math's
// toms748_solve gives byte-identical lobe tables on the phase-search path but
// makes the 1 000-speed envelope 5–9 % slower (it shrinks the bracket from
// both sides, Brent stops from one); on the sdm depth search (tolerance 1e-4)
// it moves the stored limits by up to 2.7e-5 relative.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

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

}  // namespace chatter::detail
