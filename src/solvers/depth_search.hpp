// Internal: the depth search shared by the lobe solvers that decide
// stability point by point (sdm, time-domain). Not part of the public API.
//
// Both look for the first depth of cut a at which a verdict changes from
// stable to unstable, by (1) a bracket [lo stable, hi unstable] of that
// crossing and (2) a refinement of the bracket to a tolerance. The verdict
// comes from a probe a -> V (V: a number such as ln ρ, or a whole
// simulation result) and a predicate `unstable(V)`; every bracket end keeps
// the probe's value there, so a caller reads its diagnostics (ρ, chatter
// frequency) at the final ends without probing again.
//
// Depths in m. The stability is assumed monotone-ish in depth: stable at
// a -> 0 (damped structure), unstable from the crossing on, with the first
// crossing being the one found when the scan steps by a fixed ratio
// (a narrower unstable band between two scan points can be missed; sdm
// searches for such bands itself before refining).
#pragma once

#include <algorithm>
#include <utility>

#include "roots.hpp"

namespace chatter::detail {

/// A bracket [lo, hi] of the first crossing and the probe's values there.
/// `found` false: no stable depth was met going down (descend_to_stable) or
/// no unstable one going up to the searched maximum (climb_to_unstable).
template <class V>
struct DepthBracket {
  double lo = 0.0, hi = 0.0;  ///< m
  V at_lo{}, at_hi{};
  bool found = false;
};

/// From `hi`, already unstable with value `at_hi`, divides the depth by
/// `ratio` (> 1) until the probe is stable, at most `max_steps` probes.
/// found: lo = the stable depth, hi = the last unstable one above it. Not
/// found: lo = hi = the last (unstable) depth probed, both values its value.
/// Cost: at most max_steps probes.
template <class V, class Probe, class Unstable>
DepthBracket<V> descend_to_stable(double hi, V at_hi, double ratio, int max_steps, Probe&& probe,
                                  Unstable&& unstable) {
  DepthBracket<V> b;
  b.hi = hi;
  b.at_hi = std::move(at_hi);
  for (int i = 0; i < max_steps; ++i) {
    const double lo = b.hi / ratio;
    V v = probe(lo);
    if (!unstable(v)) {
      b.lo = lo;
      b.at_lo = std::move(v);
      b.found = true;
      return b;
    }
    b.hi = lo;
    b.at_hi = std::move(v);
  }
  b.lo = b.hi;
  b.at_lo = b.at_hi;
  return b;
}

/// From `lo`, stable with value `at_lo`, multiplies the depth by `ratio`
/// (> 1, capped at depth_max) until the probe is unstable. Not found when
/// depth_max itself is stable (lo = depth_max, hi unset). Cost: about
/// log(depth_max / lo) / log(ratio) probes.
template <class V, class Probe, class Unstable>
DepthBracket<V> climb_to_unstable(double lo, V at_lo, double ratio, double depth_max, Probe&& probe,
                                  Unstable&& unstable) {
  DepthBracket<V> b;
  b.lo = lo;
  b.at_lo = std::move(at_lo);
  while (b.lo < depth_max) {
    const double a = std::min(ratio * b.lo, depth_max);
    V v = probe(a);
    if (unstable(v)) {
      b.hi = a;
      b.at_hi = std::move(v);
      b.found = true;
      return b;
    }
    b.lo = a;
    b.at_lo = std::move(v);
  }
  return b;
}

/// Bisection of a found bracket until hi − lo <= rel_tolerance × hi, each
/// end keeping its value. Only the verdict is used (no margin needed).
/// Cost: about log2(1 / rel_tolerance) probes.
template <class V, class Probe, class Unstable>
void bisect_bracket(DepthBracket<V>& b, double rel_tolerance, Probe&& probe, Unstable&& unstable) {
  while (b.hi - b.lo > rel_tolerance * b.hi) {
    const double mid = 0.5 * (b.lo + b.hi);
    V v = probe(mid);
    if (unstable(v)) {
      b.hi = mid;
      b.at_hi = std::move(v);
    } else {
      b.lo = mid;
      b.at_lo = std::move(v);
    }
  }
}

/// Root of a continuous margin g (g < 0 stable, g >= 0 unstable, e.g. ln ρ)
/// inside a bracket whose values are the margins at its ends, by Brent's
/// method to an absolute tolerance xtol (m). Cost: superlinear, a few probes
/// for smooth g. @throws NumericalError if the ends have the same sign and
/// neither is zero.
template <class Margin>
double refine_root(const DepthBracket<double>& b, Margin&& g, double xtol) {
  return brent_root(std::forward<Margin>(g), b.lo, b.hi, b.at_lo, b.at_hi, xtol);
}

}  // namespace chatter::detail
