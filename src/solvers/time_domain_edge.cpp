// The exact edge of a uniformly helical cutter in the time domain: the
// force of each tooth as the closed-form integral of the chip along its
// helical edge, instead of a sum over axial slices (time_domain_model.hpp,
// docs/time_domain.md "Real cutters").
//
// When every height of a tooth cuts the surface left the same delay earlier
// (one helix angle on every tooth, with or without a variable pitch: the
// delay between two teeth is then their pitch over Ω at every height), the
// chip at a point of the edge at angle φ is
//   h(φ) = A sin φ + B cos φ + C,
//   A = N_t f_z θ_j/2π + Δr_x,  B = Δr_y,  Δr = r(t) − r(t − τ_j),
// with C = the runout difference in the linear forced mode, 0 otherwise;
// and the edge of tooth j at height z sits at φ_j(t, z) = φ_j(t, 0) − κ_j z
// (κ_j = tan β / R), so dz = dφ / |κ_j|. The force on the tool,
//   F = −(1/|κ_j|) ∫ (K_t cos φ + K_r sin φ, −K_t sin φ + K_r cos φ) max(0, h) dφ
// over the part of the edge [φ_j(t, a), φ_j(t, 0)] inside the arc and, in
// nonlinear mode, where h > 0, is a sum of sin², cos², sin cos, sin and cos
// integrals between the ends of those pieces: closed form, O(teeth) per
// right-hand side instead of O(teeth × slices), and the exact limit of the
// slices (their error falls as 1/N_z²; tests/test_time_domain_cutters.cpp).
// The force is then smooth between the instants an end of the edge enters
// or leaves the arc (the stops of Process::engagement_events_s): no kink per
// slice for the integrator to resolve. Process damping, −(C_pd/V) ∫ (n·ṙ) n dz
// over the cutting part, is closed form the same way.
#include "time_domain_model.hpp"

#include <algorithm>
#include <cmath>

namespace chatter::td_detail {
namespace {

constexpr double kTwoPiEdge = 2.0 * kPi;

// Calls f(a, b) for every non-empty piece of [u, v] ∩ ∪_m [p0 + 2πm, p1 + 2πm]
// (p0 < p1 <= p0 + 2π), in increasing order.
template <class F>
void periodic_pieces(double u, double v, double p0, double p1, F&& f) {
  const double m0 = std::floor((u - p1) / kTwoPiEdge), m1 = std::ceil((v - p0) / kTwoPiEdge);
  for (double m = m0; m <= m1; m += 1.0) {
    const double a = std::max(u, p0 + kTwoPiEdge * m), b = std::min(v, p1 + kTwoPiEdge * m);
    if (b > a) f(a, b);
  }
}

// ∫ₐᵇ of sin², cos², sin cos, sin, cos, from the sines and cosines of the ends.
struct TrigIntegrals {
  double ss = 0.0, cc = 0.0, sc = 0.0, s = 0.0, c = 0.0;
  TrigIntegrals(double a, double b, double sa, double ca, double sb, double cb) {
    const double half = 0.5 * (b - a);
    const double sin2 = 0.5 * (sb * cb - sa * ca);  // (sin 2b − sin 2a)/4
    ss = half - sin2;
    cc = half + sin2;
    sc = 0.5 * (sb * sb - sa * sa);
    s = ca - cb;
    c = sb - sa;
  }
};

// Largest and smallest value of h(φ) = A sin φ + B cos φ + C on [a, b],
// given its values at the ends and R = |(A, B)|, ψ = atan2(B, A): the
// interior extremes are C ± R at φ = π/2 − ψ + mπ (+R for even m).
void chip_range(double R, double psi, double C, double a, double b, double ha, double hb, double& hi, double& lo) {
  hi = std::max(ha, hb);
  lo = std::min(ha, hb);
  if (!(R > 0.0)) return;
  const double p0 = 0.5 * kPi - psi;
  const double m0 = std::ceil((a - p0) / kPi), m1 = std::floor((b - p0) / kPi);
  for (double m = m0; m <= m1; m += 1.0) {
    const double v = (static_cast<long>(m) % 2 == 0 ? R : -R) + C;
    hi = std::max(hi, v);
    lo = std::min(lo, v);
  }
}

}  // namespace

bool exact_edge_applies(const Process& p, const TimeDomainOptions& o, bool linear, bool multiple_regeneration) {
  // The exact edge replaces the automatic slices only: an explicit
  // axial_slices keeps the slices (cross-checks), and a profile, a variable
  // helix (delays that vary along the edge), runout (a floored, piecewise
  // static chip) and multiple regeneration (the nearest of several
  // surfaces) keep them too.
  if (!p.rotating_edges() || o.axial_slices != 0 || !p.has_helix() || p.has_variable_helix() ||
      p.has_profile())
    return false;
  if (!linear && (p.has_runout() || multiple_regeneration)) return false;
  // One arc, inside [0, π] (sin φ >= 0 there); several arcs take the slices.
  return !p.split_engagement() && p.entry_angle() >= 0.0 && p.exit_angle() <= kPi;
}

void Model::init_edge(const TimeDomainOptions& o) {
  edge_ = false;
  if (!exact_edge_applies(process_, o, settings_.linear, settings_.multiple_regeneration) || slices_ < 2) return;
  const auto per_tooth = static_cast<std::size_t>(slices_);
  for (int j = 0; j < teeth_; ++j) {
    const CutElement& first = elements_[static_cast<std::size_t>(j) * per_tooth];
    for (std::size_t s = 1; s < per_tooth; ++s) {
      const CutElement& e = elements_[static_cast<std::size_t>(j) * per_tooth + s];
      if (e.delay_index[0] != first.delay_index[0] || e.advance[0] != first.advance[0] ||
          e.runout_diff[0] != first.runout_diff[0])
        return;
    }
  }
  edge_ = true;
  edge_kappa_.clear();
  edge_delay_.clear();
  edge_advance_.clear();
  edge_runout_.clear();
  edge_offset_.clear();
  for (int j = 0; j < teeth_; ++j) {
    const CutElement& first = elements_[static_cast<std::size_t>(j) * per_tooth];
    edge_offset_.push_back(process_.tooth_offset_rad(j));
    edge_kappa_.push_back(process_.helix_lag_rad_per_m(j));
    edge_delay_.push_back(first.delay_index[0]);
    edge_advance_.push_back(first.advance[0]);
    edge_runout_.push_back(first.runout_diff[0]);
  }
  edge_arc_.assign(static_cast<std::size_t>(teeth_), 0.0);
  edge_air_.assign(static_cast<std::size_t>(teeth_), 0.0);
}

void Model::edge_rhs(double t, const double* q, const double* qd, double* ydot, Diagnostics* diag) const {
  double r[2];
  relative(q, r);
  read_delayed(t);
  double rv[2] = {0, 0};
  if (pd_per_depth_ > 0.0) relative(qd, rv);
  const double pd_now = pd_per_depth_ > 0.0 ? process_damping_now(t) : 0.0;
  const double feed = homogeneous(settings_) ? 0.0 : settings_.feed_m;
  const bool linear = settings_.linear;
  const bool static_chip = !linear || settings_.linear_static_chip;
  const double a = settings_.depth_m;
  // Ω t at constant speed (θ(t) with speed variation), wrapped once: tooth
  // j's edge at z = 0 is at that minus its offset (Process::tooth_angle_rad).
  const double base = wrap(omega_spindle_ * mean_time(t));
  double F[2] = {0, 0};
  double chip_max = 0.0;
  bool any_arc = false, cutting = false, touching = false;
  for (int j = 0; j < teeth_; ++j) {
    const auto ju = static_cast<std::size_t>(j);
    const double kappa = edge_kappa_[ju];
    const double len = std::abs(kappa) * a;  // the edge's angular span, rad
    double phi0 = base - edge_offset_[ju];
    while (phi0 < 0.0) phi0 += kTwoPiEdge;
    // The edge spans [lo, lo + len]: z = 0 at the upper end for κ > 0.
    const double lo = kappa > 0.0 ? phi0 - len : phi0;
    const double* rd = &delayed_[2 * static_cast<std::size_t>(edge_delay_[ju])];
    const double A = (static_chip ? teeth_ * feed * edge_advance_[ju] : 0.0) + (r[0] - rd[0]);
    const double B = r[1] - rd[1];
    const double C = linear && settings_.linear_static_chip ? edge_runout_[ju] : 0.0;
    const double inv = 1.0 / std::abs(kappa);
    double arc_len = 0.0, air_len = 0.0;
    // Force (and process damping) over a cutting piece [u, v].
    auto cut = [&](double u, double v, double su, double cu, double sv, double cv) {
      const TrigIntegrals I(u, v, su, cu, sv, cv);
      const double ax = kt_ * (A * I.sc + B * I.cc + C * I.c) + kr_ * (A * I.ss + B * I.sc + C * I.s);
      const double ay = -kt_ * (A * I.ss + B * I.sc + C * I.s) + kr_ * (A * I.sc + B * I.cc + C * I.c);
      F[0] -= inv * ax;
      F[1] -= inv * ay;
      if (pd_per_depth_ > 0.0) {
        F[0] -= pd_now * inv * (I.ss * rv[0] + I.sc * rv[1]);
        F[1] -= pd_now * inv * (I.sc * rv[0] + I.cc * rv[1]);
      }
    };
    // h = R sin(φ + ψ) + C, R = |(A, B)|, ψ = atan2(B, A): computed once per
    // tooth, when needed (diagnostics, or a zero of h on the edge).
    double R = -1.0, psi = 0.0;
    auto polar = [&] {
      if (R < 0.0) {
        R = std::hypot(A, B);
        psi = std::atan2(B, A);
      }
    };
    periodic_pieces(lo, lo + len, phi_en_, phi_ex_, [&](double u, double v) {
      any_arc = true;
      arc_len += v - u;
      const double su = std::sin(u), cu = std::cos(u), sv = std::sin(v), cv = std::cos(v);
      const double hu = A * su + B * cu + C, hv = A * sv + B * cv + C;
      if (diag) {
        polar();
        double hi = 0.0, hlo = 0.0;
        chip_range(R, psi, C, u, v, hu, hv, hi, hlo);
        if (hi > 0.0) cutting = true;  // as the slices: some of the edge has h > 0
        if (hi > -air_margin_) touching = true;
        chip_max = linear ? std::max({chip_max, std::abs(hi), std::abs(hlo)}) : std::max(chip_max, hi);
      }
      if (linear) {
        cut(u, v, su, cu, sv, cv);
        return;
      }
      // Nonlinear (C = 0): the zeros of h are π apart. The arc is at most π
      // long, so a piece shorter than π whose ends have one sign has no
      // zero inside.
      if (v - u < kPi && hu >= 0.0 && hv >= 0.0) {
        cut(u, v, su, cu, sv, cv);
      } else if (!(v - u < kPi && hu <= 0.0 && hv <= 0.0)) {
        polar();
        periodic_pieces(u, v, -psi, kPi - psi, [&](double x, double y) {  // where h > 0
          cut(x, y, std::sin(x), std::cos(x), std::sin(y), std::cos(y));
        });
      }
      if (diag && R > air_margin_) {  // where h < −margin: in air
        const double al = std::asin(air_margin_ / R);
        periodic_pieces(u, v, kPi + al - psi, kTwoPiEdge - al - psi, [&](double x, double y) { air_len += y - x; });
      }
    });
    if (diag) {  // shares of the edge (none at zero depth)
      edge_arc_[ju] = len > 0.0 ? arc_len / len : 0.0;
      edge_air_[ju] = len > 0.0 ? air_len / len : 0.0;
    }
  }
  modal_accelerations(q, qd, F, ydot);
  if (diag) *diag = diagnostics(F, chip_max, any_arc, cutting, touching);
}

}  // namespace chatter::td_detail
