// The right-hand side of the time-domain simulation: the chip and the force
// of every tooth (uniform path) or tooth slice (real cutters), the modal
// accelerations, and the instants the teeth enter and leave the arc
// (time_domain_model.hpp; equations in include/chatter/time_domain.hpp).
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

/// True when the run takes the per-tooth, per-slice path (real cutters):
/// milling with a helix, a variable pitch or helix, process damping, runout
/// (nonlinear mode only: linear mode ignores it), or an explicit axial_slices.
bool general_cutter(const Process& p, const TimeDomainOptions& o, bool linear) {
  if (!p.rotating_edges()) return false;
  return o.axial_slices > 0 || p.has_helix() || !p.uniform_cutter() || p.has_process_damping() ||
         (p.has_runout() && !linear) || p.has_profile();
}

/// The period of a run (s): the Floquet period of the process
/// (Process::floquet_period_s), the same as sdm's: the tooth period for a
/// uniform cutter, the shortest repeat of the pitch and helix pattern
/// otherwise, and of the runout too in nonlinear mode (the linear equation
/// has no static chip, which is all runout changes). With speed variation
/// the principal period of the equation, sdm's (speed_variation_period).
double simulation_period(const Process& p, const SimulationSettings& s) {
  if (p.has_speed_variation()) return speed_variation_period(p, s.spindle_rpm).period_s;
  return p.floquet_period_s(s.spindle_rpm, p.has_runout() && !homogeneous(s));
}

Model::Model(const StructuralModel& model, const Process& process, const SimulationSettings& s, double tau,
             const TimeDomainOptions& options)
    : mm_(modal_matrices(model)), process_(process), settings_(s), tau_(tau) {
  n_ = static_cast<int>(mm_.omega.size());
  tool_modes_ = static_cast<int>(model.tool.modes.size());
  milling_ = process.rotating_edges();
  teeth_ = milling_ ? process.milling_parameters().teeth : 1;
  omega_spindle_ = angular_speed_rad_per_s(s.spindle_rpm);
  if (milling_) {
    kt_ = process.milling_parameters().tangential_coefficient_n_per_m2;
    kr_ = process.milling_parameters().radial_coefficient_n_per_m2;
    phi_en_ = process.entry_angle();  // the one arc's ends (the exact edge's window)
    phi_ex_ = process.exit_angle();
  } else {
    kf_ = process.turning_parameters().feed_force_coefficient_n_per_m2;
    orthogonal_ = process.orthogonal_turning();
    if (!s.linear) kienzle_ = process.turning_parameters().kienzle;
    if (!orthogonal_) {  // the chord at this run's depth: exact for the nonlinear chip too
      const InsertChord c = process.chord(s.depth_m);
      const Eigen::Vector2d n = process.chip_direction(s.depth_m), d = process.edge_force(s.depth_m);
      chip_n_[0] = n.x();
      chip_n_[1] = n.y();
      d_[0] = d.x();
      d_[1] = d.y();
      width_m_ = c.width_m;
      chip_per_feed_ = std::sin(c.lead_angle_rad);
    }
  }
  pd_per_depth_ = process.process_damping_per_depth(s.spindle_rpm);
  init_speed_variation();
  general_ = general_cutter(process, options, homogeneous(s));
  if (general_) build_elements(options);
  in_arc_.assign(general_ ? elements_.size() : static_cast<std::size_t>(teeth_), milling_ ? 0 : 1);
  chips_.assign(in_arc_.size(), 0.0);
}

void Model::set_segment(double t_mid) {
  if (!milling_) return;
  if (general_) {
    if (slices_ != 1 || profile_) return;  // several slices, a profile: tested in the right-hand side
    for (std::size_t e = 0; e < elements_.size(); ++e)
      in_arc_[e] = in_window(element_angle(elements_[e], t_mid)) ? 1 : 0;
    return;
  }
  for (int j = 0; j < teeth_; ++j) {
    in_arc_[j] = process_.in_cut(angle(t_mid, j)) ? 1 : 0;  // (in_cut wraps as wrap() does)
  }
}

std::vector<double> Model::arc_events(double t_end) const {
  if (!ssv_) return arc_events_mean(t_end, tau_);
  // Speed variation: the constant-speed events of the mean-speed time up to
  // θ(t_end)/Ω₀, each at the real time the spindle reaches its angle.
  std::vector<double> out;
  for (const double tm : arc_events_mean(mean_time(t_end), mean_delay_)) {
    const double t = real_time(tm);
    if (t <= t_end) out.push_back(t);
  }
  return out;
}

std::vector<double> Model::arc_events_mean(double t_end, double tooth_period) const {
  std::vector<double> out;
  if (!milling_) return out;
  if (general_) {
    const double rpm = settings_.spindle_rpm, rev = revolution_s(rpm);
    auto repeat = [&](double t0, double every) {
      for (long k = 0; t0 + static_cast<double>(k) * every <= t_end; ++k)
        out.push_back(t0 + static_cast<double>(k) * every);
    };
    if (slices_ == 1 && !profile_) {
      for (const CutElement& e : elements_)
        for (const double edge : process_.arc_edges_rad()) {
          const double lag = process_.tooth_offset_rad(e.tooth) + e.z * process_.helix_lag_rad_per_m(e.tooth);
          double t0 = std::fmod((edge + lag) / omega_spindle_, rev);
          if (t0 < 0.0) t0 += rev;
          repeat(t0, rev);
        }
    } else {
      for (const double t0 : process_.engagement_events_s(rpm, settings_.depth_m)) repeat(t0, process_.period_s(rpm));
    }
    std::sort(out.begin(), out.end());
    return out;
  }
  const double pitch = 2.0 * kPi / teeth_;
  for (double phi : process_.arc_edges_rad()) {
    const double t0 = std::fmod(phi, pitch) / omega_spindle_;
    for (long k = 0; t0 + static_cast<double>(k) * tooth_period <= t_end; ++k)
      out.push_back(t0 + static_cast<double>(k) * tooth_period);
  }
  return out;
}

void Model::chips(double t, const double* q, double* h) const {
  if (general_) {
    general_chips(t, q, h);
    return;
  }
  double r[2] = {0, 0};
  relative(q, r);
  double rd[2];
  // The surface the previous tooth left: τ earlier (time-varying with speed variation).
  const double t_delayed = ssv_ ? delayed_time(t, mean_delay_) : t - tau_;
  history_->displacement(t_delayed, rd);
  const double dx = r[0] - rd[0], dy = r[1] - rd[1];
  const double feed = homogeneous(settings_) ? 0.0 : settings_.feed_m;
  for (int j = 0; j < teeth_; ++j) {
    if (!in_arc_[j]) {
      h[j] = 1.0;
      continue;
    }
    double hj;
    if (milling_) {
      const double phi = angle(t, j);
      const double sn = std::sin(phi), cs = std::cos(phi);
      hj = feed * sn + sn * dx + cs * dy;
    } else if (orthogonal_) {
      hj = feed + dx;
    } else {  // h = f sin κ_eq + n·Δr
      hj = feed * chip_per_feed_ + chip_n_[0] * dx + chip_n_[1] * dy;
    }
    if (settings_.multiple_regeneration && !settings_.linear)
      hj -= history_->gap(t_delayed, (j + teeth_ - 1) % teeth_);
    h[j] = hj;
  }
}

Diagnostics Model::diagnostics(const double* F, double chip_max, bool any_arc, bool cutting, bool touching) const {
  Diagnostics d;
  d.force[0] = F[0];
  d.force[1] = F[1];
  d.chip_max = chip_max;
  d.any_in_arc = any_arc;
  d.in_cut = cutting;
  d.in_air = any_arc && !touching && !settings_.linear;
  return d;
}

void Model::rhs(double t, const double* y, double* ydot, Diagnostics* diag) const {
  ++rhs_count_;
  const double* q = y;
  const double* qd = y + n_;
  if (general_) {
    general_rhs(t, q, qd, ydot, diag);
    return;
  }
  chips(t, q, chips_.data());
  double F[2] = {0, 0};
  const double a = settings_.depth_m;
  double chip_max = 0.0;
  bool any_arc = false, cutting = false, touching = false;
  for (int j = 0; j < teeth_; ++j) {
    if (!in_arc_[j]) continue;
    any_arc = true;
    const double h = chips_[j];
    const double hc = settings_.linear ? h : std::max(0.0, h);
    if (h > 0.0) cutting = true;
    if (h > -air_margin_) touching = true;
    chip_max = std::max(chip_max, settings_.linear ? std::abs(h) : hc);
    if (milling_) {
      const double phi = angle(t, j);
      const Eigen::Vector2d v = milling_force_direction(kt_, kr_, std::sin(phi), std::cos(phi));
      F[0] -= a * v[0] * hc;
      F[1] -= a * v[1] * hc;
    } else if (orthogonal_) {
      turning_force(hc, F);
      if (pd_per_depth_ > 0.0 && (settings_.linear || h > 0.0)) {
        // Process damping (turning, n = x): −C_pd (a/V) ṙ_x while cutting.
        double rv[2];
        relative(qd, rv);
        F[0] -= process_damping_now(t) * a * rv[0];
      }
    } else {  // an insert: F = −b h d, process damping −C_pd (b/V) (n·ṙ) n
      turning_force(hc, F);
      if (pd_per_depth_ > 0.0 && (settings_.linear || h > 0.0)) {
        double rv[2];
        relative(qd, rv);
        const double vn = chip_n_[0] * rv[0] + chip_n_[1] * rv[1];
        const double pd = process_damping_now(t);
        F[0] -= pd * width_m_ * vn * chip_n_[0];
        F[1] -= pd * width_m_ * vn * chip_n_[1];
      }
    }
  }
  modal_accelerations(q, qd, F, ydot);
  if (diag) *diag = diagnostics(F, chip_max, any_arc, cutting, touching);
}

void Model::turning_force(double hc, double F[2]) const {
  const double a = settings_.depth_m;
  if (!kienzle_) {
    if (orthogonal_) {
      F[0] += -a * kf_ * hc;
    } else {
      F[0] += -width_m_ * d_[0] * hc;
      F[1] += -width_m_ * d_[1] * hc;
    }
    return;
  }
  // k(h) h per unit width (0 without a chip); an insert's directions are the
  // chord's normal n and its edge e = (−n_y, n_x) (K_f n + K_r e).
  const double ff = kienzle_->feed.force_per_width_n_per_m(hc);
  if (orthogonal_) {
    F[0] += -a * ff;
    return;
  }
  const double fr = kienzle_->has_radial() ? kienzle_->radial.force_per_width_n_per_m(hc) : 0.0;
  F[0] += -width_m_ * (ff * chip_n_[0] - fr * chip_n_[1]);
  F[1] += -width_m_ * (ff * chip_n_[1] + fr * chip_n_[0]);
}

void Model::modal_accelerations(const double* q, const double* qd, const double F[2], double* ydot) const {
  for (int i = 0; i < n_; ++i) {
    const double w = mm_.omega(i);
    ydot[i] = qd[i];
    ydot[n_ + i] = -2.0 * mm_.damping_ratio(i) * w * qd[i] - w * w * q[i] +
                   (mm_.S(0, i) * F[0] + mm_.S(1, i) * F[1]) / mm_.mass_kg(i);
  }
}

void Model::relative(const double* q, double r[2]) const {
  r[0] = r[1] = 0.0;
  for (int i = 0; i < n_; ++i) {
    r[0] += mm_.S(0, i) * q[i];
    r[1] += mm_.S(1, i) * q[i];
  }
}

// ---- the real cutter (general path) ----
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

