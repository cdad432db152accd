// The real cutter's path of the time-domain model (the general path: a
// helix, variable pitch or helix, a profile, process damping, runout): the
// cut elements (tooth × axial slice) and their delays, the elements' angles
// and engaged fractions at an instant, the delayed displacements, and the
// chips, forces and right-hand side summed over the elements
// (time_domain_model.hpp; the uniform cutter and turning: time_domain_model.cpp).
#include "time_domain_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "chatter/error.hpp"
#include "chatter/kinematics.hpp"

namespace chatter::td_detail {
namespace {

// Axial slices of a helical cutter when the options leave it automatic:
// 20 slices put the growth per period within 1.4e-5 (relative) of 80
// slices near the limit of case C with a 30° helix (second-order
// convergence, tests/test_time_domain_cutters.cpp).
constexpr int kDefaultHelixSlices = 20;

}  // namespace

void Model::build_elements(const TimeDomainOptions& o) {
  const double a = settings_.depth_m, rpm = settings_.spindle_rpm;
  slices_ = o.axial_slices > 0 ? o.axial_slices : (process_.has_helix() ? kDefaultHelixSlices : 1);
  // A cutter profile: the process's slices (the same as every method's).
  profile_ = process_.has_profile();
  std::vector<AxialSlice> cut;
  if (profile_) {
    cut = process_.axial_slices(a);
    slices_ = static_cast<int>(cut.size());
  }
  // Multiple regeneration: the chip is cut from the nearest of the surfaces
  // the N_t earlier teeth left (one revolution back).
  const int surfaces = (!settings_.linear && settings_.multiple_regeneration) ? teeth_ : 1;
  auto wrap_tooth = [&](int j) { return ((j % teeth_) + teeth_) % teeth_; };
  for (int j = 0; j < teeth_; ++j) {
    for (int sl = 0; sl < slices_; ++sl) {
      CutElement e;
      e.tooth = j;
      e.dz = a / slices_;
      e.z = (sl + 0.5) * e.dz;
      if (profile_) {
        const AxialSlice& c = cut[static_cast<std::size_t>(sl)];
        e.z = c.z_m;
        e.dz = c.height_m();
        e.kr = c.radial_coefficient_n_per_m2;
        e.en = c.entry_rad;
        e.ex = c.exit_rad;
        e.engaged = c.engaged;
        e.lag = process_.helix_lag_rad(j, c.z_m);
        e.width = process_.helix_lag_rad(j, c.z_hi_m) - process_.helix_lag_rad(j, c.z_lo_m);
      }
      double delay = 0.0, pitch = 0.0;
      for (int k = 1; k <= surfaces; ++k) {
        const int cur = wrap_tooth(j - k + 1), prev = wrap_tooth(j - k);
        const double dk = process_.tooth_delay_s(cur, e.z, rpm);
        if (!(dk > 0.0))
          throw InputError("time-domain: at height " + std::to_string(e.z * 1e3) + " mm tooth " +
                           std::to_string(cur + 1) + " passes before tooth " + std::to_string(prev + 1) +
                           " (the helix difference exceeds the pitch): reduce the depth or the helix variation");
        delay += dk;
        pitch += process_.pitch_angle_rad(cur);
        e.delay_index.push_back(delay_slot(delay));
        e.advance.push_back(pitch / (2.0 * kPi));
        e.runout_diff.push_back(process_.runout_m(j) - process_.runout_m(prev));
      }
      double next = 0.0;
      for (int k = 1; k <= kRootImagesMultiple; ++k) {
        next += process_.tooth_delay_s(wrap_tooth(j + k), e.z, rpm);
        e.next_delay_sum.push_back(next);
      }
      elements_.push_back(std::move(e));
    }
  }
  delayed_.assign(2 * delays_.size(), 0.0);
  engaged_.assign(elements_.size(), 0.0);
  phi_.assign(elements_.size(), 0.0);
  sin_.assign(elements_.size(), 0.0);
  for (int j = 0; j < teeth_; ++j) {
    const double d = process_.helix_lag_rad_per_m(j) * a / slices_;  // δ_j = κ_j dz
    slice_lag_.push_back(d);
    slice_cos_.push_back(std::cos(d));
    slice_sin_.push_back(std::sin(d));
  }
  cos_.assign(elements_.size(), 0.0);
  runout_ = process_.has_runout() && !settings_.linear;
  init_edge(o);
}

bool Model::continuous_arc_events() const {
  if (!general_ || slices_ < 2 || profile_) return false;
  const double f_max = mm_.omega.maxCoeff() / (2.0 * kPi);
  double ramp = std::numeric_limits<double>::infinity();  // s
  for (int j = 0; j < teeth_; ++j)
    ramp = std::min(ramp, std::abs(process_.helix_lag_rad_per_m(j)) * settings_.depth_m / omega_spindle_);
  return ramp * f_max >= kMinRampCycles;
}

int Model::delay_slot(double d) {
  for (std::size_t i = 0; i < delays_.size(); ++i)
    if (std::abs(delays_[i] - d) <= 1e-13 * d) return static_cast<int>(i);
  delays_.push_back(d);
  return static_cast<int>(delays_.size()) - 1;
}

double Model::element_angle(const CutElement& e, double t) const {
  return process_.tooth_angle_rad(e.tooth, mean_time(t), e.z, settings_.spindle_rpm);
}

bool Model::in_window(double phi) const { return process_.in_cut(phi); }  // (in_cut wraps as wrap() does)


// How far (rad) a tooth's edge must miss the arc for element_angles to skip
// its slices: far above the rotation chain's round-off (~1e-16 per slice).
constexpr double kOutOfArcMargin = 1e-9;

// Engaged fraction of a slice whose edge spans the angles φ ± w/2 (w =
// κ dz, the helix lag over the slice height): the part of that interval
// inside the arc [φ_en, φ_ex] (mod 2π), over w. It ramps linearly while
// the slice enters or leaves, so the sliced force is continuous in time
// (the exact windowed integral over the slice height, with the chip and
// direction taken at the midpoint). w = 0: the arc test.
// φ is wrapped to [0, 2π).
// With several arcs (Process::engaged_arcs) the fractions add: the arcs are disjoint.
double Model::engaged_fraction(double phi, double w) const {
  const auto& arcs = process_.engaged_arcs();
  double f = engaged_fraction(phi, w, arcs[0].first, arcs[0].second);
  for (std::size_t k = 1; k < arcs.size(); ++k) f += engaged_fraction(phi, w, arcs[k].first, arcs[k].second);
  return f;
}

// The same for an arc [en, ex] of its own (a slice of a cutter profile).
double Model::engaged_fraction(double phi, double w, double en, double ex) const {
  if (!(w > 0.0)) return (phi >= en && phi <= ex) ? 1.0 : 0.0;
  double lo = phi - 0.5 * w;
  while (lo < 0.0) lo += 2.0 * kPi;
  const double hi = lo + w;
  const double first = std::min(hi, ex) - std::max(lo, en);
  const double second = std::min(hi, ex + 2.0 * kPi) - std::max(lo, en + 2.0 * kPi);
  if (!(first > 0.0) && !(second > 0.0)) return 0.0;  // outside the arc (what the formula gives)
  return std::min(1.0, (std::max(0.0, first) + std::max(0.0, second)) / w);
}

// φ (wrapped to [0, 2π)), sin φ, cos φ of every element at t. With
// several slices one wrap, sine and cosine per tooth: the slices of a
// tooth step back by δ = κ_j dz each, a rotation (round-off ~1e-16 per
// slice).
void Model::element_angles(double t) const {
  if (profile_) {  // each slice its own lag: one angle per element
    tooth_out_.assign(static_cast<std::size_t>(teeth_), 0);
    const double base = omega_spindle_ * t;
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const CutElement& e = elements_[ei];
      const double phi = wrap(base - process_.tooth_offset_rad(e.tooth) - e.lag);
      phi_[ei] = phi;
      sin_[ei] = std::sin(phi);
      cos_[ei] = std::cos(phi);
    }
    return;
  }
  if (slices_ == 1) {
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const double phi = wrap(element_angle(elements_[ei], t));
      phi_[ei] = phi;
      sin_[ei] = std::sin(phi);
      cos_[ei] = std::cos(phi);
    }
    return;
  }
  // The slices of two teeth at a time: their rotations are independent
  // chains, stepped together so that neither waits on the other's latency
  // (the same operations per tooth as one at a time: the same values).
  const double tm = mean_time(t);  // t at constant speed
  struct Chain {
    std::size_t ei;
    double phi, sn, cs, d, cd, sd;
  };
  auto start = [&](int j) {
    const auto ju = static_cast<std::size_t>(j);
    const double d = slice_lag_[ju];
    const double phi = wrap(process_.tooth_angle_rad(j, tm, 0.0, settings_.spindle_rpm) - 0.5 * d);
    return Chain{ju * static_cast<std::size_t>(slices_), phi, std::sin(phi), std::cos(phi), d, slice_cos_[ju], slice_sin_[ju]};
  };
  auto advance = [&](Chain& c) {
    phi_[c.ei] = c.phi;
    sin_[c.ei] = c.sn;
    cos_[c.ei] = c.cs;
    ++c.ei;
    c.phi -= c.d;
    while (c.phi < 0.0) c.phi += 2.0 * kPi;
    const double sn1 = c.sn * c.cd - c.cs * c.sd;
    c.cs = c.cs * c.cd + c.sn * c.sd;
    c.sn = sn1;
  };
  // A tooth whose slices all miss the arc (the span [φ_0 − S δ, φ_0] of its
  // edge, φ_0 its angle at z = 0, widened by kOutOfArcMargin, far beyond the
  // chain's round-off) is marked out: engaged_fraction would give exactly 0
  // for each of its slices, so general_chips skips them (the same values,
  // about half the work at half immersion).
  tooth_out_.assign(static_cast<std::size_t>(teeth_), 0);
  std::vector<int>& in = teeth_in_;
  in.clear();
  for (int j = 0; j < teeth_; ++j) {
    const double span = slices_ * std::abs(slice_lag_[static_cast<std::size_t>(j)]) + 2.0 * kOutOfArcMargin;
    if (span < 2.0 * kPi) {
      const double lo = wrap(process_.tooth_angle_rad(j, tm, 0.0, settings_.spindle_rpm) -
                             slices_ * std::abs(slice_lag_[static_cast<std::size_t>(j)]) - kOutOfArcMargin);
      const double hi = lo + span;
      bool meets = false;
      for (const auto& [en, ex] : process_.engaged_arcs())
        meets = meets || std::min(hi, ex) >= std::max(lo, en) || std::min(hi, ex + 2.0 * kPi) >= std::max(lo, en + 2.0 * kPi);
      if (!meets) {
        tooth_out_[static_cast<std::size_t>(j)] = 1;
        continue;
      }
    }
    in.push_back(j);
  }
  std::size_t k = 0;
  for (; k + 1 < in.size(); k += 2) {
    Chain c0 = start(in[k]), c1 = start(in[k + 1]);
    for (int sl = 0; sl < slices_; ++sl) {
      advance(c0);
      advance(c1);
    }
  }
  if (k < in.size()) {
    Chain c0 = start(in[k]);
    for (int sl = 0; sl < slices_; ++sl) advance(c0);
  }
}

void Model::read_delayed(double t) const {
  for (std::size_t i = 0; i < delays_.size(); ++i)
    history_->displacement(ssv_ ? delayed_time(t, delays_[i]) : t - delays_[i], &delayed_[2 * i], i);
}

// Chips of every element (unclipped; +1 out of the arc); engaged_, sin_,
// cos_ set for the right-hand side.
// Nonlinear: the static chip of Process::static_chip_m (pitch, runout)
// plus the regeneration against the previous tooth; with multiple
// regeneration the nearest of the N_t earlier surfaces,
//   h = min_k [N_t f_z (θ_j + … + θ_{j−k+1})/2π sin φ + ρ_j − ρ_{j−k} + n·(r(t) − r(t − τ_{j,k}))],
// which is static_chip_m (before its floor) on a still tool. Linear:
// n·(r(t) − r(t − τ_j(z))).
void Model::general_chips(double t, const double* q, double* h) const {
  double r[2];
  relative(q, r);
  read_delayed(t);
  const double feed = homogeneous(settings_) ? 0.0 : settings_.feed_m;
  const bool multiple = !settings_.linear && settings_.multiple_regeneration;
  element_angles(t);
  for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
    const CutElement& e = elements_[ei];
    if (slices_ > 1 && tooth_out_[static_cast<std::size_t>(e.tooth)]) {  // no slice of the tooth in the arc
      engaged_[ei] = 0.0;
      h[ei] = 1.0;
      continue;
    }
    const double phi = phi_[ei];
    const double frac = profile_ ? (e.engaged ? engaged_fraction(phi, e.width, e.en, e.ex) : 0.0)
                        : slices_ == 1 ? (in_arc_[ei] != 0 ? 1.0 : 0.0)
                                       : engaged_fraction(phi, slice_lag_[e.tooth]);
    engaged_[ei] = frac;
    if (!(frac > 0.0)) {
      h[ei] = 1.0;
      continue;
    }
    const double sn = sin_[ei], cs = cos_[ei];
    auto regen = [&](int k) {
      const double* rd = &delayed_[2 * static_cast<std::size_t>(e.delay_index[static_cast<std::size_t>(k)])];
      return sn * (r[0] - rd[0]) + cs * (r[1] - rd[1]);
    };
    if (settings_.linear) {
      h[ei] = regen(0);
      // Linear forced run: the static chip, never clipped (docs/forced.md).
      if (settings_.linear_static_chip) h[ei] += teeth_ * feed * e.advance[0] * sn + e.runout_diff[0];
    } else if (!multiple) {
      // Without runout static_chip_m is N_t f_z θ_j/2π sin φ (k = 1), taken
      // directly here (sin φ is at hand; the arc has sin φ >= 0 but for
      // the ramp of a slice entering at φ = 0 or leaving at π).
      h[ei] = (runout_ ? process_.static_chip_m(e.tooth, phi, feed) : std::max(0.0, teeth_ * feed * e.advance[0] * sn)) +
              regen(0);
    } else {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < e.delay_index.size(); ++k)
        best = std::min(best, teeth_ * feed * e.advance[k] * sn + e.runout_diff[k] + regen(static_cast<int>(k)));
      h[ei] = best;
    }
  }
}

// The sliced force: per element in the arc −dz max(0, h) (K_t cos φ +
// K_r sin φ, −(K_t sin φ − K_r cos φ)), plus the process damping
// −(C_pd/V) dz (n·ṙ) n while it cuts (h > 0; always in linear mode).
void Model::general_rhs(double t, const double* q, const double* qd, double* ydot, Diagnostics* diag) const {
  if (edge_) return edge_rhs(t, q, qd, ydot, diag);
  general_chips(t, q, chips_.data());
  double rv[2] = {0, 0};
  if (pd_per_depth_ > 0.0) relative(qd, rv);
  const double pd_now = pd_per_depth_ > 0.0 ? process_damping_now(t) : 0.0;
  double F[2] = {0, 0};
  double chip_max = 0.0;
  bool any_arc = false, cutting = false, touching = false;
  for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
    const double frac = engaged_[ei];
    if (!(frac > 0.0)) continue;
    any_arc = true;
    const CutElement& e = elements_[ei];
    const double dz = frac * e.dz;
    const double h = chips_[ei];
    const double hc = settings_.linear ? h : std::max(0.0, h);
    if (h > 0.0) cutting = true;
    if (h > -air_margin_) touching = true;
    chip_max = std::max(chip_max, settings_.linear ? std::abs(h) : hc);
    const double sn = sin_[ei], cs = cos_[ei];
    const Eigen::Vector2d v = milling_force_direction(kt_, profile_ ? e.kr : kr_, sn, cs);
    F[0] -= dz * v[0] * hc;
    F[1] -= dz * v[1] * hc;
    if (pd_per_depth_ > 0.0 && (settings_.linear || h > 0.0)) {
      const double vn = sn * rv[0] + cs * rv[1];
      F[0] -= pd_now * dz * vn * sn;
      F[1] -= pd_now * dz * vn * cs;
    }
  }
  modal_accelerations(q, qd, F, ydot);
  if (diag) *diag = diagnostics(F, chip_max, any_arc, cutting, touching);
}

void Model::tally_air(std::vector<double>& arc, std::vector<double>& air) const {
  if (edge_) {
    for (std::size_t j = 0; j < edge_arc_.size(); ++j) {
      arc[j] += edge_arc_[j];
      air[j] += edge_air_[j];
    }
    return;
  }
  if (general_) {
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const double frac = engaged_[ei];
      if (!(frac > 0.0)) continue;
      const auto j = static_cast<std::size_t>(elements_[ei].tooth);
      arc[j] += frac;
      if (chips_[ei] < -air_margin_) air[j] += frac;
    }
    return;
  }
  for (int j = 0; j < teeth_; ++j) {
    if (!in_arc_[static_cast<std::size_t>(j)]) continue;
    arc[static_cast<std::size_t>(j)] += 1.0;
    if (chips_[static_cast<std::size_t>(j)] < -air_margin_) air[static_cast<std::size_t>(j)] += 1.0;
  }
}

}  // namespace chatter::td_detail
