// The depth search of the `sdm` solver (SemiDiscretizationSolver::limit_at,
// and limit_above, the same search stopped once its answer is sure):
// the first depth from 0 up where the spectral radius reaches 1, as a
// continuation in depth that follows the largest multipliers of both
// half-planes, looks for thin unstable bands, then refines the crossing
// with Brent's method on ln ρ (docs/sdm.md). Part of the `sdm` solver
// (sdm_internal.hpp).
#include "chatter/report.hpp"
#include "sdm_internal.hpp"

#include "depth_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "chatter/error.hpp"

namespace chatter {
using namespace sdm_detail;
namespace {

// Depth search: a climbing step aims this far (relative) beyond the crossing
// the secant predicts, so that the bracket closes in one step when the
// prediction is good; and always climbs at least this ratio − 1.
constexpr double kSecantOvershoot = 0.01;
constexpr double kMinClimb = 1e-3;
const double kLogQuarter = std::log(0.25);
// Continuation step: no followed multiplier may be predicted to move more
// than this fraction of its distance to the unit circle in one step. 1: a
// step ends where the nearest followed multiplier is predicted to reach the
// circle. Half (before 2026-11-30) made the approach a halving sequence of
// ~3 extra maps per limit and found the same bands: on 10 000 random speeds
// (1–3 modes, 1–4 teeth, 2–100 % immersion) both missed 6 that a dense scan
// finds, and the climb took 23 % fewer maps (docs/sdm.md).
constexpr double kMoveFraction = 1.0;
// A local maximum of ln ρ below the crossing is searched with this many
// golden-section steps (it ends on ρ ≥ 1 as soon as one is found).
constexpr int kBandSearchSteps = 12;
// Most divisions by bracket_ratio when the first depth is already unstable
// (ρ(0) < 1, so a stable depth exists; this only bounds a broken model).
constexpr int kMaxDescentSteps = 200;
// Relative error of ln ρ from an early-stopped (decide-mode) Arnoldi: it stops
// once | |θ| − 1 | exceeds kDecideFactor residuals, so |θ| is within 1/20 of
// its distance to the circle; a fall of ln ρ smaller than this is noise.
constexpr double kDecideError = 0.1;

// The largest multipliers at a depth: overall (ln ρ), and in the left
// (Re μ < 0) and right half-planes.
struct Radii {
  double all = 0.0;
  Cplx left{0.0, 0.0}, right{0.0, 0.0};
};

// At zero depth the multipliers are known exactly: e^{λτ} of the free modes
// (poles λ, 1/s; slowest decay rate, 1/s; period τ, s), followed as every
// later depth's (SdmKernel::half_plane_radii).
Radii zero_depth_radii(const std::vector<Cplx>& free_poles, double slowest_decay_per_s, double tau) {
  Eigen::VectorXcd mu(static_cast<Eigen::Index>(free_poles.size()));
  for (std::size_t i = 0; i < free_poles.size(); ++i) mu(static_cast<Eigen::Index>(i)) = std::exp(free_poles[i] * tau);
  Dominant d;
  SdmKernel::half_plane_radii(mu, d);
  return Radii{-slowest_decay_per_s * tau, d.mu_left, d.mu_right};
}

// The next climbing step (m) from depth lo (radii r_lo), the depth before it
// a_prev (r_prev). The largest multipliers of the left half-plane (where flip
// bands start: a pair meets on the negative real axis and one multiplier
// runs out through −1, often for a short range of depth) and of the right
// one are followed; from the distance each moved over the last step, the
// step is sized so that neither is predicted to cover more than
// kMoveFraction of its distance to the unit circle. The secant of ln ρ
// shortens the step further to just beyond the predicted crossing, and the
// ratio stays within [1 + kMinClimb, bracket_ratio⁴]. Early-stopped Arnoldi
// values (large maps) are trusted only with ρ >= 1/4 and then move at most
// by bracket_ratio; `accurate`: ρ is exact (branch roots).
double climb_step(double a_prev, const Radii& r_prev, double lo, const Radii& r_lo, bool accurate,
                  const SemiDiscretizationOptions& o) {
  const bool trusted = accurate || (r_lo.all > kLogQuarter && (a_prev == 0.0 || r_prev.all > kLogQuarter));
  double step = (std::pow(o.bracket_ratio, trusted ? 4 : 1) - 1.0) * lo;
  double move = kInf;
  for (auto [now, before] : {std::pair{r_lo.left, r_prev.left}, std::pair{r_lo.right, r_prev.right}}) {
    const double moved = std::abs(now - before);
    if (moved > 0.0) move = std::min(move, kMoveFraction * (1.0 - std::abs(now)) * (lo - a_prev) / moved);
  }
  // Never shorter than bracket_min_ratio − 1 of the depth on that account,
  // or the approach of a multiplier to the circle would never end.
  step = std::min(step, std::max(move, (o.bracket_min_ratio - 1.0) * lo));
  const double slope = (r_lo.all - r_prev.all) / (lo - a_prev);
  if (trusted && slope > 0.0) step = std::min(step, (-r_lo.all / slope) * (1.0 + kSecantOvershoot) + kSecantOvershoot * lo);
  return std::max(step, kMinClimb * lo);
}

// Golden-section search for a point where ln ρ >= 0 inside a local maximum
// bracketed by a < b < c with f(b) >= f(a) and f(b) > f(c) (fb = f(b)).
// Returns true with the first such point found, false when the maximum found
// stays below 0 after kBandSearchSteps evaluations.
template <class F>
bool find_band(F&& f, double a, double b, double c, double fb, double& at, double& f_at) {
  constexpr double kGolden = 0.3819660112501051;
  for (int i = 0; i < kBandSearchSteps; ++i) {
    const bool right = (c - b) > (b - a);
    const double x = right ? b + kGolden * (c - b) : b - kGolden * (b - a);
    const double fx = f(x);
    if (fx >= 0.0) {
      at = x;
      f_at = fx;
      return true;
    }
    if (fx > fb) {
      (right ? a : c) = b;
      b = x;
      fb = fx;
    } else {
      (right ? c : a) = x;
    }
  }
  return false;
}

// ln ρ rose from a_prev (f_prev) to lo (flo), then fell to hi (fhi): looks
// for a thin unstable band at the local maximum in (a_prev, hi). Found: the
// bracket [lo, hi] of the first crossing becomes [lo, band] or, when the
// band lies below lo, [a_prev, band]; true.
template <class F>
bool bracket_band(F&& log_rho, double a_prev, double f_prev, double& lo, double& flo, double& hi, double& fhi) {
  double band = 0.0, fband = 0.0;
  if (!find_band(log_rho, a_prev, lo, hi, log_rho(lo), band, fband)) return false;
  const bool left = band < lo;  // the first crossing lies below the band
  hi = band;
  fhi = fband;
  if (left) {
    lo = a_prev;
    flo = f_prev;
  }
  return true;
}

// The last two period maps of a depth search, by depth: a depth met again
// (the band search re-reads its lower end, Brent returns a point it has
// evaluated, which the final analysis then reads) reuses its map, and its
// converged dominant multiplier with the eigenvector (the final analysis
// asks for exactly that: dominant(map, true)).
class MapCache {
 public:
  MapCache(const SdmKernel& kernel, const Grid& g) : kernel_(kernel), g_(g) {}
  const PeriodMap& at(double depth) { return maps_[slot(depth)]; }
  const Dominant& dominant_at(double depth) {
    const int i = slot(depth);
    if (!has_dominant_[i]) {
      dominant_[i] = kernel_.dominant(maps_[i], true);
      has_dominant_[i] = true;
    }
    return dominant_[i];
  }

 private:
  int slot(double depth) {
    for (int i = 0; i < 2; ++i)
      if (depth_[i] == depth) return i;
    last_ = 1 - last_;
    depth_[last_] = std::numeric_limits<double>::quiet_NaN();  // not valid if the build throws
    has_dominant_[last_] = false;
    kernel_.build_map(g_, depth, maps_[last_]);
    depth_[last_] = depth;
    return last_;
  }

  const SdmKernel& kernel_;
  const Grid& g_;
  PeriodMap maps_[2];
  Dominant dominant_[2];
  bool has_dominant_[2] = {false, false};
  double depth_[2] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  int last_ = 1;
};

}  // namespace


StabilityLimit SemiDiscretizationSolver::limit_at(SpindleSpeed speed) const { return limit_at(speed, nullptr); }

StabilityLimit SemiDiscretizationSolver::limit_at(SpindleSpeed speed, FloquetResult* floquet) const {
  return search(speed.rpm(), floquet, std::numeric_limits<double>::quiet_NaN(), nullptr);
}

bool SemiDiscretizationSolver::limit_above(SpindleSpeed speed, double depth_m) const {
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  bool above = false;
  search(speed.rpm(), nullptr, depth_m, &above);
  return above;
}

StabilityLimit SemiDiscretizationSolver::search(double rpm, FloquetResult* floquet, double decide_depth,
                                                bool* above) const {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  // Deciding limit > decide_depth only: the search below stops as soon as
  // the answer is sure (it takes the same steps as the whole search).
  const bool deciding = !std::isnan(decide_depth);
  StabilityLimit lim;
  lim.spindle_rpm = rpm;
  if (Wx_.rows() == 0) {  // the process cannot see any mode: never unstable
    if (deciding) *above = true;
    return lim;
  }
  const Grid g = period_grid(process_, options_, f_max_hz_, slowest_decay_per_s_, rpm, A_, B_, Wx_, U_, Sv_);
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  MapCache maps(kernel, g);
  auto log_rho = [&](double a) { return std::log(std::abs(maps.dominant_at(a).mu)); };
  // Early-stopped Arnoldi for large maps.
  auto radii = [&](double a) {
    const Dominant d = kernel.dominant(maps.at(a), false, true);
    return Radii{std::log(std::abs(d.mu)), d.mu_left, d.mu_right};
  };
  const double dmax = options_.depth_max_m;
  // While climbing, ρ comes from Arnoldi stopped as soon as the verdict ρ < 1
  // or >= 1 is sure (cheaper than a dense decomposition even for small maps),
  // except for the branch roots of low-speed turning, which are exact.
  const bool accurate = g.branch_roots;
  const Radii r_zero = zero_depth_radii(free_poles_, slowest_decay_per_s_, g.tau);
  double a = dmax / std::pow(options_.bracket_ratio, options_.bracket_steps);
  Radii r = radii(a);
  double lo = 0.0, flo = r_zero.all, hi = a, fhi = r.all;
  auto unstable = [](double log_rho_value) { return log_rho_value >= 0.0; };
  if (r.all >= 0.0) {
    // Unstable already: go down until stable (ρ(0) < 1 always: damped modes).
    const detail::DepthBracket<double> down = detail::descend_to_stable(
        hi, fhi, options_.bracket_ratio, kMaxDescentSteps, [&](double d) { return radii(d).all; }, unstable);
    lo = down.lo;
    flo = down.at_lo;
    hi = down.hi;
    fhi = down.at_hi;
  } else {
    // Climb from a towards the first crossing of ρ = 1 as a continuation in
    // depth, following the largest multipliers of the left half-plane (where
    // flip bands start) and of the right one (climb_step sizes the steps).
    double a_prev = 0.0;
    Radii r_prev = r_zero;
    lo = a;
    flo = r.all;
    Radii r_lo = r;
    while (true) {
      if (lo >= dmax) {
        if (deciding) {
          *above = true;
          return lim;
        }
        if (floquet) *floquet = floquet_of(kernel, g, maps.at(dmax), rpm, dmax, A_, Wx_, f_max_hz_);
        return lim;  // stable up to depth_max
      }
      // The root will lie at or above a_prev (a band search below looks no
      // lower), and at or above lo when ρ(lo) <= 1/4 (no band search starts
      // from lo then): above decide_depth, the answer is sure.
      if (deciding && (a_prev > decide_depth || (lo > decide_depth && flo <= kLogQuarter))) {
        *above = true;
        return lim;
      }
      hi = std::min(lo + climb_step(a_prev, r_prev, lo, r_lo, accurate, options_), dmax);
      const Radii r_hi = radii(hi);
      fhi = r_hi.all;
      if (fhi >= 0.0) break;
      // ln ρ rose, then fell: a local maximum lies in (a_prev, hi), where a
      // thin unstable band would sit. Look for it.
      if (flo >= r_prev.all && fhi < flo - (accurate ? 0.0 : kDecideError * std::abs(flo)) && flo > kLogQuarter &&
          bracket_band(log_rho, a_prev, r_prev.all, lo, flo, hi, fhi))
        break;
      a_prev = lo;
      r_prev = r_lo;
      lo = hi;
      r_lo = r_hi;
      flo = fhi;
    }
  }
  // The root lies in [lo, hi].
  if (deciding && (hi <= decide_depth || lo > decide_depth)) {
    *above = lo > decide_depth;
    return lim;
  }
  const double root = detail::refine_root(detail::DepthBracket<double>{lo, hi, flo, fhi, true}, log_rho,
                                          options_.depth_tolerance * lo);
  if (deciding) {
    *above = root > decide_depth;
    return lim;
  }
  lim.depth_limit_m = root;
  const FloquetResult fr = floquet_of(kernel, g, maps.at(root), rpm, root, A_, Wx_, f_max_hz_, &maps.dominant_at(root));
  lim.chatter_frequency_hz = fr.chatter_frequency_hz;
  lim.lobe = lobe_number(fr.chatter_frequency_hz, process_.tooth_passing_hz(rpm));
  if (floquet) *floquet = fr;
  return lim;
}

}  // namespace chatter
