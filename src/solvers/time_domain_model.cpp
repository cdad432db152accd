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

}  // namespace chatter::td_detail

