// Time-domain simulation on SUNDIALS CVODE (see include/chatter/time_domain.hpp
// for the equations and docs/time_domain.md for the design).
#include "chatter/report.hpp"
#include "chatter/time_domain.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/transfer_function.hpp"
#include "depth_search.hpp"
#include "sundials_raii.hpp"
#include "time_domain_parts.hpp"

namespace chatter {

namespace {

using detail::AirCounts;
using detail::GrowthEstimate;
using detail::History;
using detail::HistoryEntry;
using detail::PeriodSnapshots;
using detail::Spectrum;
using detail::VerdictInput;
using detail::VerdictOutcome;
using detail::amplitude_spectrum;
using detail::decide_verdict;
using detail::dominant_nonharmonic_hz;
using detail::growth_per_period;
using detail::tooth_passing_harmonics;

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Delay-propagated images of the start discontinuity that are stop points:
// the k-th image is a jump in the k-th derivative, beyond Adams order 5 after 6.
constexpr int kStartImages = 6;
// Delay-propagated images t_r + kτ of a chip zero crossing t_r that are stop
// points. The force has a kink at t_r (max(h, 0)), so d³r/dt³ jumps there and
// the delayed term jumps in its 3rd derivative at t_r + τ, its 5th at
// t_r + 2τ. With multiple regeneration the surface itself keeps the kink: the
// chip jumps in slope at t_r + τ, then in the 3rd and 5th derivatives.
constexpr int kRootImagesSingle = 2;
constexpr int kRootImagesMultiple = 3;
constexpr int kMaxAdamsOrder = 5;
// Axial slices of a helical cutter when the options leave it automatic:
// 20 slices put the growth per period within 1.4e-5 (relative) of 80
// slices near the limit of case C with a 30° helix (second-order
// convergence, tests/test_time_domain_cutters.cpp).
constexpr int kDefaultHelixSlices = 20;
// Up to this many distinct delays, the multiples of each are start stops.
constexpr std::size_t kMaxStartImageDelays = 8;

// ---------------------------------------------------------------------------
// The right-hand side and everything it needs.
struct Diagnostics {
  double force[2] = {0, 0};
  double chip_max = 0.0;
  bool any_in_arc = false;
  bool in_cut = false;
  /// Every tooth in the arc is in air by more than the contact margin.
  bool in_air = false;
};

// The real cutter (docs/time_domain.md "Real cutters"): one cutting element
// per tooth j and axial slice s, a straight tooth of height dz at the slice
// midpoint z, with the surfaces it may cut: the one left by the tooth k
// places before it (k = 1 … K), passed `delay[k−1]` earlier, whose nominal
// position is N_t f_z `advance[k−1]` sin φ + `runout_diff[k−1]` away.
struct CutElement {
  int tooth = 0;
  double z = 0.0, dz = 0.0;
  std::vector<int> delay_index;   // into Model::delays_ (k = 1 … K)
  std::vector<double> advance;    // (θ_j + … + θ_{j−k+1}) / 2π
  std::vector<double> runout_diff;  // ρ_j − ρ_{j−k}, m
  std::vector<double> next_delay_sum;  // τ_{j+1}(z) + … + τ_{j+k}(z), s (root images)
};

/// True when the run takes the per-tooth, per-slice path (real cutters):
/// milling with a helix, a variable pitch or helix, process damping, runout
/// (nonlinear mode only: linear mode ignores it), or an explicit axial_slices.
bool general_cutter(const Process& p, const TimeDomainOptions& o, bool linear) {
  if (p.operation() != Operation::kMilling) return false;
  return o.axial_slices > 0 || p.has_helix() || !p.uniform_cutter() || p.has_process_damping() ||
         (p.has_runout() && !linear);
}

/// The period of a run (s): the Floquet period of the process
/// (Process::floquet_period_s), the same as sdm's: the tooth period for a
/// uniform cutter, the shortest repeat of the pitch and helix pattern
/// otherwise, and of the runout too in nonlinear mode (the linear equation
/// has no static chip, which is all runout changes).
double simulation_period(const Process& p, const SimulationSettings& s) {
  return p.floquet_period_s(s.spindle_rpm, p.has_runout() && !s.linear);
}

}  // namespace

double simulation_period_s(const Process& process, double rpm, bool linear) {
  SimulationSettings s;
  s.spindle_rpm = rpm;
  s.linear = linear;
  return simulation_period(process, s);
}

int simulation_periods_per_revolution(const Process& process, double rpm, bool linear) {
  return static_cast<int>(std::lround(60.0 / (rpm * simulation_period_s(process, rpm, linear))));
}

namespace {

class Model {
 public:
  Model(const StructuralModel& model, const Process& process, const SimulationSettings& s, double tau,
        const TimeDomainOptions& options)
      : mm_(modal_matrices(model)), process_(process), settings_(s), tau_(tau) {
    n_ = static_cast<int>(mm_.omega.size());
    tool_modes_ = static_cast<int>(model.tool.modes.size());
    milling_ = process.operation() == Operation::kMilling;
    teeth_ = milling_ ? process.milling_parameters().teeth : 1;
    omega_spindle_ = 2.0 * kPi * s.spindle_rpm / 60.0;
    if (milling_) {
      kt_ = process.milling_parameters().tangential_coefficient_n_per_m2;
      kr_ = process.milling_parameters().radial_coefficient_n_per_m2;
      phi_en_ = process.entry_angle();
      phi_ex_ = process.exit_angle();
    } else {
      kf_ = process.turning_parameters().feed_force_coefficient_n_per_m2;
    }
    pd_per_depth_ = process.process_damping_per_depth(s.spindle_rpm);
    general_ = general_cutter(process, options, s.linear);
    if (general_) build_elements(options);
    in_arc_.assign(general_ ? elements_.size() : static_cast<std::size_t>(teeth_), milling_ ? 0 : 1);
    chips_.assign(in_arc_.size(), 0.0);
  }

  int n() const { return n_; }
  int teeth() const { return teeth_; }
  bool milling() const { return milling_; }
  const ModalMatrices& modal() const { return mm_; }
  int tool_modes() const { return tool_modes_; }

  void attach(History* h) { history_ = h; }
  bool general() const { return general_; }
  /// Root functions: one per tooth (uniform path) or per element when every
  /// element's entry and exit is a stop (one slice); none with several
  /// slices (their chips are clipped, see docs/time_domain.md).
  int root_count() const { return general_ ? (slices_ == 1 ? static_cast<int>(elements_.size()) : 0) : teeth_; }
  /// Largest delay any element reads (s): the history must hold it.
  double max_delay() const {
    return delays_.empty() ? tau_ : *std::max_element(delays_.begin(), delays_.end());
  }
  double min_delay() const {
    return delays_.empty() ? tau_ : *std::min_element(delays_.begin(), delays_.end());
  }
  /// Distinct delays whose multiples carry the start discontinuity (stops);
  /// empty when they are many (distributed delays smear the start jump).
  std::vector<double> start_image_delays() const {
    if (!general_) return {tau_};
    if (delays_.size() > kMaxStartImageDelays) return {};
    return delays_;
  }
  /// The delay images of a chip zero crossing of root function `i`: the
  /// later teeth that cut the surface it leaves, k = 1 … count.
  double root_image_offset(int i, int k) const {
    return general_ ? elements_[static_cast<std::size_t>(i)].next_delay_sum[static_cast<std::size_t>(k - 1)]
                    : k * tau_;
  }
  /// Sets which teeth are inside the cutting arc for the segment around `t`.
  void set_segment(double t_mid) {
    if (!milling_) return;
    if (general_) {
      if (slices_ != 1) return;  // several slices: tested in the right-hand side
      for (std::size_t e = 0; e < elements_.size(); ++e)
        in_arc_[e] = in_window(element_angle(elements_[e], t_mid)) ? 1 : 0;
      return;
    }
    for (int j = 0; j < teeth_; ++j) {
      const double phi = wrap(angle(t_mid, j));
      in_arc_[j] = (phi >= phi_en_ && phi <= phi_ex_) ? 1 : 0;
    }
  }
  double angle(double t, int j) const { return omega_spindle_ * t + 2.0 * kPi * j / teeth_; }
  static double wrap(double phi) {
    phi = std::fmod(phi, 2.0 * kPi);
    return phi < 0 ? phi + 2.0 * kPi : phi;
  }
  /// Times in [0, t_end] at which a tooth enters or leaves the arc (milling).
  /// Real cutters: every element's entry and exit with one slice; with
  /// several, the instants a tooth tip or the top of the cut enters or leaves
  /// (Process::engagement_events_s), where the sliced force has its kinks.
  std::vector<double> arc_events(double t_end) const {
    std::vector<double> out;
    if (!milling_) return out;
    if (general_) {
      const double rpm = settings_.spindle_rpm, rev = 60.0 / rpm;
      auto repeat = [&](double t0, double every) {
        for (long k = 0; t0 + static_cast<double>(k) * every <= t_end; ++k)
          out.push_back(t0 + static_cast<double>(k) * every);
      };
      if (slices_ == 1) {
        for (const CutElement& e : elements_)
          for (const double edge : {phi_en_, phi_ex_}) {
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
    for (double phi : {phi_en_, phi_ex_}) {
      const double t0 = std::fmod(phi, pitch) / omega_spindle_;
      for (long k = 0; t0 + static_cast<double>(k) * tau_ <= t_end; ++k) out.push_back(t0 + static_cast<double>(k) * tau_);
    }
    return out;
  }

  /// Unclipped chip thickness of every tooth in the arc at time t for state
  /// q (m); teeth outside the arc get +1 (a constant, for root finding).
  void chips(double t, const double* q, double* h) const {
    if (general_) {
      general_chips(t, q, h);
      return;
    }
    double r[2] = {0, 0};
    relative(q, r);
    double rd[2];
    history_->displacement(t - tau_, rd);
    const double dx = r[0] - rd[0], dy = r[1] - rd[1];
    const double feed = settings_.linear ? 0.0 : settings_.feed_m;
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
      } else {
        hj = feed + dx;
      }
      if (settings_.multiple_regeneration && !settings_.linear)
        hj -= history_->gap(t - tau_, (j + teeth_ - 1) % teeth_);
      h[j] = hj;
    }
  }

  /// ẏ = f(t, y); fills `diag` when given. y = [q; q̇].
  /// What one right-hand-side call reports (both force paths).
  Diagnostics diagnostics(const double* F, double chip_max, bool any_arc, bool cutting, bool touching) const {
    Diagnostics d;
    d.force[0] = F[0];
    d.force[1] = F[1];
    d.chip_max = chip_max;
    d.any_in_arc = any_arc;
    d.in_cut = cutting;
    d.in_air = any_arc && !touching && !settings_.linear;
    return d;
  }

  void rhs(double t, const double* y, double* ydot, Diagnostics* diag) const {
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
        const double sn = std::sin(phi), cs = std::cos(phi);
        F[0] += -a * (kt_ * cs + kr_ * sn) * hc;
        F[1] += a * (kt_ * sn - kr_ * cs) * hc;
      } else {
        F[0] += -a * kf_ * hc;
        if (pd_per_depth_ > 0.0 && (settings_.linear || h > 0.0)) {
          // Process damping (turning, n = x): −C_pd (a/V) ṙ_x while cutting.
          double rv[2];
          relative(qd, rv);
          F[0] -= pd_per_depth_ * a * rv[0];
        }
      }
    }
    modal_accelerations(q, qd, F, ydot);
    if (diag) *diag = diagnostics(F, chip_max, any_arc, cutting, touching);
  }

  void modal_accelerations(const double* q, const double* qd, const double F[2], double* ydot) const {
    for (int i = 0; i < n_; ++i) {
      const double w = mm_.omega(i);
      ydot[i] = qd[i];
      ydot[n_ + i] = -2.0 * mm_.damping_ratio(i) * w * qd[i] - w * w * q[i] +
                     (mm_.S(0, i) * F[0] + mm_.S(1, i) * F[1]) / mm_.mass_kg(i);
    }
  }

  void relative(const double* q, double r[2]) const {
    r[0] = r[1] = 0.0;
    for (int i = 0; i < n_; ++i) {
      r[0] += mm_.S(0, i) * q[i];
      r[1] += mm_.S(1, i) * q[i];
    }
  }

  long rhs_count() const { return rhs_count_; }
  /// A tooth counts as in air only when its chip is below −margin (m): the
  /// chip of a converged forced response touches 0 at the arc ends.
  void set_air_margin(double margin) { air_margin_ = margin; }
  const std::vector<char>& in_arc() const { return in_arc_; }

 private:
  // ---- the real cutter (general path) ----
  void build_elements(const TimeDomainOptions& o) {
    const double a = settings_.depth_m, rpm = settings_.spindle_rpm;
    slices_ = o.axial_slices > 0 ? o.axial_slices : (process_.has_helix() ? kDefaultHelixSlices : 1);
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
  }
  int delay_slot(double d) {
    for (std::size_t i = 0; i < delays_.size(); ++i)
      if (std::abs(delays_[i] - d) <= 1e-13 * d) return static_cast<int>(i);
    delays_.push_back(d);
    return static_cast<int>(delays_.size()) - 1;
  }
  double element_angle(const CutElement& e, double t) const {
    return process_.tooth_angle_rad(e.tooth, t, e.z, settings_.spindle_rpm);
  }
  bool in_window(double phi) const {
    phi = wrap(phi);
    return phi >= phi_en_ && phi <= phi_ex_;
  }
  // Engaged fraction of a slice whose edge spans the angles φ ± w/2 (w =
  // κ dz, the helix lag over the slice height): the part of that interval
  // inside the arc [φ_en, φ_ex] (mod 2π), over w. It ramps linearly while
  // the slice enters or leaves, so the sliced force is continuous in time
  // (the exact windowed integral over the slice height, with the chip and
  // direction taken at the midpoint). w = 0: the arc test.
  // φ is wrapped to [0, 2π).
  double engaged_fraction(double phi, double w) const {
    if (!(w > 0.0)) return (phi >= phi_en_ && phi <= phi_ex_) ? 1.0 : 0.0;
    double lo = phi - 0.5 * w;
    while (lo < 0.0) lo += 2.0 * kPi;
    const double hi = lo + w;
    const double first = std::min(hi, phi_ex_) - std::max(lo, phi_en_);
    const double second = std::min(hi, phi_ex_ + 2.0 * kPi) - std::max(lo, phi_en_ + 2.0 * kPi);
    if (!(first > 0.0) && !(second > 0.0)) return 0.0;  // outside the arc (what the formula gives)
    return std::min(1.0, (std::max(0.0, first) + std::max(0.0, second)) / w);
  }
  // φ (wrapped to [0, 2π)), sin φ, cos φ of every element at t. With
  // several slices one wrap, sine and cosine per tooth: the slices of a
  // tooth step back by δ = κ_j dz each, a rotation (round-off ~1e-16 per
  // slice).
  void element_angles(double t) const {
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
    struct Chain {
      std::size_t ei;
      double phi, sn, cs, d, cd, sd;
    };
    auto start = [&](int j) {
      const auto ju = static_cast<std::size_t>(j);
      const double d = slice_lag_[ju];
      const double phi = wrap(process_.tooth_angle_rad(j, t, 0.0, settings_.spindle_rpm) - 0.5 * d);
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
    int j = 0;
    for (; j + 1 < teeth_; j += 2) {
      Chain c0 = start(j), c1 = start(j + 1);
      for (int sl = 0; sl < slices_; ++sl) {
        advance(c0);
        advance(c1);
      }
    }
    if (j < teeth_) {
      Chain c0 = start(j);
      for (int sl = 0; sl < slices_; ++sl) advance(c0);
    }
  }
  // Chips of every element (unclipped; +1 out of the arc); engaged_, sin_,
  // cos_ set for the right-hand side.
  // Nonlinear: the static chip of Process::static_chip_m (pitch, runout)
  // plus the regeneration against the previous tooth; with multiple
  // regeneration the nearest of the N_t earlier surfaces,
  //   h = min_k [N_t f_z (θ_j + … + θ_{j−k+1})/2π sin φ + ρ_j − ρ_{j−k} + n·(r(t) − r(t − τ_{j,k}))],
  // which is static_chip_m (before its floor) on a still tool. Linear:
  // n·(r(t) − r(t − τ_j(z))).
  void general_chips(double t, const double* q, double* h) const {
    double r[2];
    relative(q, r);
    for (std::size_t i = 0; i < delays_.size(); ++i) history_->displacement(t - delays_[i], &delayed_[2 * i]);
    const double feed = settings_.linear ? 0.0 : settings_.feed_m;
    const bool multiple = !settings_.linear && settings_.multiple_regeneration;
    element_angles(t);
    for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
      const CutElement& e = elements_[ei];
      const double phi = phi_[ei];
      const double frac = slices_ == 1 ? (in_arc_[ei] != 0 ? 1.0 : 0.0) : engaged_fraction(phi, slice_lag_[e.tooth]);
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
  void general_rhs(double t, const double* q, const double* qd, double* ydot, Diagnostics* diag) const {
    general_chips(t, q, chips_.data());
    double rv[2] = {0, 0};
    if (pd_per_depth_ > 0.0) relative(qd, rv);
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
      F[0] += -dz * (kt_ * cs + kr_ * sn) * hc;
      F[1] += dz * (kt_ * sn - kr_ * cs) * hc;
      if (pd_per_depth_ > 0.0 && (settings_.linear || h > 0.0)) {
        const double vn = sn * rv[0] + cs * rv[1];
        F[0] -= pd_per_depth_ * dz * vn * sn;
        F[1] -= pd_per_depth_ * dz * vn * cs;
      }
    }
    modal_accelerations(q, qd, F, ydot);
    if (diag) *diag = diagnostics(F, chip_max, any_arc, cutting, touching);
  }

  ModalMatrices mm_;
  const Process& process_;
  const SimulationSettings& settings_;
  double tau_;
  int n_ = 0, tool_modes_ = 0, teeth_ = 1;
  bool milling_ = false;
  double omega_spindle_ = 0.0, kt_ = 0.0, kr_ = 0.0, kf_ = 0.0, phi_en_ = 0.0, phi_ex_ = 0.0;
  double pd_per_depth_ = 0.0;  // C_pd / V, N·s/m²
  bool general_ = false;
  int slices_ = 1;
  std::vector<CutElement> elements_;
  std::vector<double> delays_;            // distinct delays read by the elements, s
  mutable std::vector<double> delayed_;   // r(t − delays_[i]) (x, y) per rhs
  bool runout_ = false;                   // static chip from Process::static_chip_m
  // At the last chips() call, per element: engaged fraction, sin φ, cos φ.
  mutable std::vector<double> engaged_, phi_, sin_, cos_;
  std::vector<double> slice_lag_, slice_cos_, slice_sin_;  // per tooth: δ_j = κ_j dz, cos δ_j, sin δ_j
  std::vector<char> in_arc_;
  History* history_ = nullptr;
  mutable std::vector<double> chips_;
  mutable long rhs_count_ = 0;
  double air_margin_ = 0.0;
};

int cvode_rhs(double t, N_Vector y, N_Vector ydot, void* user) {
  static_cast<const Model*>(user)->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), nullptr);
  return 0;
}
int cvode_roots(double t, N_Vector y, double* g, void* user) {
  static_cast<const Model*>(user)->chips(t, N_VGetArrayPointer(y), g);
  return 0;
}


// ---------------------------------------------------------------------------
// Settings checks that need neither the model nor the speed's sampling.
void validate_settings(const SimulationSettings& s) {
  if (!(s.spindle_rpm > 0.0 && std::isfinite(s.spindle_rpm)))
    throw InputError("spindle speed " + std::to_string(s.spindle_rpm) + " rev/min: must be > 0");
  if (!(s.depth_m >= 0.0 && std::isfinite(s.depth_m)))
    throw InputError("depth " + std::to_string(s.depth_m * 1e3) + " mm: must be >= 0");
  if (s.periods < 4) throw InputError("periods = " + std::to_string(s.periods) + ": must be >= 4");
  if (!(s.feed_m >= 0.0 && std::isfinite(s.feed_m)))
    throw InputError("feed " + std::to_string(s.feed_m * 1e3) + " mm: must be >= 0");
  if (!(s.analysed_fraction > 0.0 && s.analysed_fraction <= 1.0))
    throw InputError("analysed_fraction must be in (0, 1]");
}

// ---------------------------------------------------------------------------
// One run of TimeDomainSimulator::simulate.
//   set-up (constructor): sampling, initial state and tolerance scale,
//     history, stop points, CVODE;
//   stepping (run): the uniform grid of M samples per delay; between grid
//     points the fixed stop points (arc events, start images), the chip zero
//     crossings (CVODE roots) and their delay images, each stored in the
//     history and followed by a restart;
//   outputs (finish): counters, then the analysers of time_domain_parts.hpp
//     (growth per period, spectrum, verdict).
// Lives on the stack of simulate(); not copyable (CVODE holds its address).
class SimulationRun {
 public:
  SimulationRun(const StructuralModel& model, const Process& process, const TimeDomainOptions& options,
                const SimulationSettings& s);
  SimulationRun(const SimulationRun&) = delete;
  SimulationRun& operator=(const SimulationRun&) = delete;

  SimulationResult run();

 private:
  // --- set-up ---
  void choose_sampling();
  void set_initial_state();
  void init_history();
  void init_stops();
  void init_integrator();
  // --- stepping ---
  void start();
  void step_to_grid_point(long i);
  void end_of_period(bool at_stop, bool& root_at_grid);
  double next_event(int skip) const;
  void pass_event(double tt);
  void on_root(double tr);
  double segment_mid(double tt, double t_next) const;
  void restart(double tt);
  Diagnostics store(double t, bool segment_changes, double t_next_mid);
  SeriesSample make_sample(double t, const double* yy, const Diagnostics& d) const;
  // --- outputs ---
  SimulationResult finish();

  const Process& process_;
  const TimeDomainOptions& options_;
  const SimulationSettings& s_;
  const double tau_;
  Model m_;
  const int n_, teeth_;

  // Sampling: M grid samples per delay, spacing dt; highest natural frequency.
  double f_max_ = 0.0, dt_ = 0.0;
  int M_ = 0;
  // Initial state [q; q̇] and the displacement scale of the tolerances.
  std::vector<double> y0_;
  double scale_ = 0.0;
  int root_cap_ = 0, root_images_ = 0, root_count_ = 0;
  double hold_ = 0.0;  // history kept behind the newest entry, s
  std::optional<History> history_;
  double t_end_ = 0.0;
  std::vector<double> stops_;  // fixed stop points, sorted, t_end last

  sundials::Context ctx_;
  std::optional<sundials::SerialVector> y_, atol_;
  std::optional<sundials::Cvode> cv_;
  std::optional<sundials::FixedPointSolver> nls_;
  void* mem_ = nullptr;
  bool use_roots_ = false, roots_on_ = false;

  SimulationResult res_;
  int first_analysed_ = 0;
  // Per-period observables for the DMD: r at the M grid points of the period
  // just ended, plus the modal state at its end (velocities / ω).
  int zdim_ = 0;
  PeriodSnapshots snapshots_;
  Eigen::VectorXd period_r_;
  double log_scale_ = 0.0;  // linear mode: true state = stored × exp(log_scale)
  std::vector<double> win_x_, win_y_;  // uniform samples of r over the analysed window
  AirCounts air_;
  double max_amp_ = 0.0;

  std::vector<double> ydot_;
  Diagnostics dg_;
  // Pending images of the chip zero crossings, sorted; they lie within
  // root_images delays ahead, so at most about (root_cap + 1) x root_images
  // are held, whatever the simulated time.
  std::deque<double> images_;
  std::size_t next_stop_ = 0;
  long restarts_ = 0, root_stops_ = 0;
  double t_ = 0.0;
  int roots_this_period_ = 0;
  long steps_done_ = 0, rhs_done_ = 0;  // CVodeReInit resets CVODE's counters
};

SimulationRun::SimulationRun(const StructuralModel& model, const Process& process, const TimeDomainOptions& options,
                             const SimulationSettings& s)
    : process_(process),
      options_(options),
      s_(s),
      tau_(simulation_period(process, s)),
      m_(model, process, s, tau_, options),
      n_(m_.n()),
      teeth_(m_.teeth()) {
  if (!s.initial_state.empty() && static_cast<int>(s.initial_state.size()) != 2 * n_)
    throw InputError("initial state has " + std::to_string(s.initial_state.size()) + " values: needs 2 x " +
                     std::to_string(n_) + " modes");
  choose_sampling();
  set_initial_state();
  init_history();
  init_stops();
  init_integrator();
}

void SimulationRun::choose_sampling() {
  for (int i = 0; i < n_; ++i) f_max_ = std::max(f_max_, m_.modal().omega(i) / (2.0 * kPi));
  const double need = std::ceil(options_.samples_per_vibration_cycle * tau_ * f_max_);
  if (need > options_.max_samples_per_period)
    throw InputError("time-domain: " + std::to_string(s_.spindle_rpm) + " rev/min needs " +
                     std::to_string(static_cast<long>(need)) + " history samples per delay (limit " +
                     std::to_string(options_.max_samples_per_period) + "): raise the speed");
  M_ = std::max(options_.samples_per_period, static_cast<int>(need));
  if (m_.general()) {
    // samples_per_period per tooth period; at least 2 samples per shortest delay.
    const int tooth_periods = static_cast<int>(std::lround(tau_ / process_.delay_s(s_.spindle_rpm)));
    M_ = std::max({M_, options_.samples_per_period * tooth_periods,
                   static_cast<int>(std::ceil(2.0 * tau_ / m_.min_delay()))});
    if (M_ > options_.max_samples_per_period)
      throw InputError("time-domain: " + std::to_string(s_.spindle_rpm) + " rev/min needs " + std::to_string(M_) +
                       " history samples per period (limit " + std::to_string(options_.max_samples_per_period) + ")");
  }
  dt_ = tau_ / M_;
}

void SimulationRun::set_initial_state() {
  y0_.assign(2 * n_, 0.0);
  if (!s_.initial_state.empty()) {
    y0_ = s_.initial_state;
  } else if (s_.linear || s_.feed_m == 0.0) {
    for (int i = 0; i < n_; ++i) {
      y0_[i] = 1e-6;
      y0_[n_ + i] = 0.5e-6 * m_.modal().omega(i);
    }
  }
  double scale = 0.0;
  for (int i = 0; i < n_; ++i) scale = std::max(scale, std::abs(y0_[i]));
  if (!s_.linear && s_.feed_m > 0.0) {
    double kmin = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n_; ++i)
      kmin = std::min(kmin, m_.modal().mass_kg(i) * m_.modal().omega(i) * m_.modal().omega(i));
    const double coeff = m_.milling() ? process_.milling_parameters().tangential_coefficient_n_per_m2
                                      : process_.turning_parameters().feed_force_coefficient_n_per_m2;
    scale = std::max(scale, s_.depth_m * coeff * s_.feed_m / kmin);
  }
  if (!(scale > 0.0)) scale = 1e-9;
  scale_ = scale;
  m_.set_air_margin(1e-6 * std::max(scale_, s_.feed_m));
}

void SimulationRun::init_history() {
  // History: constant at the initial displacement before t = 0.
  // Entries held: about 1.5 delays of grid samples, the arc events and start
  // images in that span, at most root_cap + 1 root stops per period and as
  // many stops at each of their root_images delay images.
  root_cap_ = 8 * teeth_ + 8;
  root_images_ = s_.linear ? 0 : (s_.multiple_regeneration ? kRootImagesMultiple : kRootImagesSingle);
  // Real cutters hold the largest delay read (up to one revolution).
  hold_ = m_.general() ? std::max(1.5 * tau_, m_.max_delay() + 0.5 * tau_) : 1.5 * tau_;
  const std::size_t held = m_.general() ? static_cast<std::size_t>(std::ceil(hold_ / dt_))
                                         : static_cast<std::size_t>(M_ + M_ / 2);
  const std::size_t capacity =
      held + static_cast<std::size_t>(2 * (root_cap_ + 1) * (1 + root_images_) + 4 * teeth_ + 16);
  history_.emplace(capacity, m_.general() ? 1 : teeth_);
  m_.attach(&*history_);
  std::vector<double> zero_gaps(teeth_, 0.0);
  HistoryEntry e;
  m_.relative(y0_.data(), e.r);
  e.t = -(m_.general() ? m_.max_delay() : tau_) - 2.0 * dt_;
  history_->push(e, zero_gaps.data());
  e.t = 0.0;
  history_->push(e, zero_gaps.data());
}

void SimulationRun::init_stops() {
  t_end_ = s_.periods * tau_;
  std::vector<double> stops = m_.arc_events(t_end_);
  if (!m_.general()) {
    for (int k = 1; k <= kStartImages && k <= s_.periods; ++k) stops.push_back(k * tau_);
  } else {
    for (const double d : m_.start_image_delays())
      for (int k = 1; k <= kStartImages && k * d < t_end_; ++k) stops.push_back(k * d);
  }
  stops.push_back(t_end_);
  std::sort(stops.begin(), stops.end());
  std::vector<double> merged;
  for (double t : stops) {
    if (t <= 1e-9 * tau_ || t >= t_end_ - 1e-9 * tau_) continue;
    if (merged.empty() || t - merged.back() > 1e-9 * tau_) merged.push_back(t);
  }
  merged.push_back(t_end_);  // always the last stop, exactly
  stops_.swap(merged);
}

void SimulationRun::init_integrator() {
  y_.emplace(2 * n_, ctx_);
  atol_.emplace(2 * n_, ctx_);
  std::copy(y0_.begin(), y0_.end(), y_->data());
  const double rtol = options_.relative_tolerance;
  for (int i = 0; i < n_; ++i) {
    const double sc = std::max(1e-300, scale_);
    atol_->data()[i] = rtol * sc;
    atol_->data()[n_ + i] = rtol * sc * m_.modal().omega(i);
  }
  cv_.emplace(CV_ADAMS, ctx_);
  mem_ = cv_->get();
  cv_->check(CVodeInit(mem_, cvode_rhs, 0.0, *y_), "CVodeInit");
  cv_->check(CVodeSVtolerances(mem_, rtol, *atol_), "CVodeSVtolerances");
  nls_.emplace(*y_, 0, ctx_);
  cv_->check(CVodeSetNonlinearSolver(mem_, *nls_), "CVodeSetNonlinearSolver");
  cv_->check(CVodeSetUserData(mem_, &m_), "CVodeSetUserData");
  cv_->check(CVodeSetMaxOrd(mem_, kMaxAdamsOrder), "CVodeSetMaxOrd");
  cv_->check(CVodeSetMaxStep(mem_, 0.5 * (m_.general() ? std::min(tau_, m_.min_delay()) : tau_)), "CVodeSetMaxStep");
  cv_->check(CVodeSetMaxNumSteps(mem_, options_.max_steps), "CVodeSetMaxNumSteps");
  root_count_ = m_.root_count();
  use_roots_ = !s_.linear && root_count_ > 0;
  if (use_roots_) {
    cv_->check(CVodeRootInit(mem_, root_count_, cvode_roots), "CVodeRootInit");
    cv_->check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
  }
  roots_on_ = use_roots_;

  res_.floquet_period_s = tau_;
  res_.tooth_passing_hz = process_.tooth_passing_hz(s_.spindle_rpm);
  res_.periods = s_.periods;
  res_.samples_per_period = M_;
  first_analysed_ = std::clamp(static_cast<int>(std::floor(s_.periods * (1.0 - s_.analysed_fraction))), 0,
                               s_.periods - 2);
  res_.analysed_from_period = first_analysed_;
  zdim_ = 2 * M_ + 2 * n_;
  period_r_.resize(2 * M_);
  ydot_.assign(2 * n_, 0.0);
}

SeriesSample SimulationRun::make_sample(double t, const double* yy, const Diagnostics& d) const {
  SeriesSample smp;
  smp.t_s = t;
  const auto& mm = m_.modal();
  const double ex = std::exp(log_scale_);
  for (int i = 0; i < n_; ++i) {
    // S column = ±u_i; the body's own displacement is u_i q_i.
    const double sign = i < m_.tool_modes() ? 1.0 : -1.0;
    const double dx = sign * mm.S(0, i) * yy[i] * ex, dy = sign * mm.S(1, i) * yy[i] * ex;
    if (i < m_.tool_modes()) {
      smp.tool_x_m += dx;
      smp.tool_y_m += dy;
    } else {
      smp.workpiece_x_m += dx;
      smp.workpiece_y_m += dy;
    }
  }
  smp.rel_x_m = smp.tool_x_m - smp.workpiece_x_m;
  smp.rel_y_m = smp.tool_y_m - smp.workpiece_y_m;
  smp.force_x_n = d.force[0] * ex;
  smp.force_y_n = d.force[1] * ex;
  smp.chip_m = d.chip_max * (s_.linear ? ex : 1.0);
  smp.in_cut = d.in_cut;
  return smp;
}

// Stores a history entry at the current (t, y): a_left from the segment
// that ends here, a_right from the one that starts (same when no event).
// Returns the diagnostics of the segment that ends here.
Diagnostics SimulationRun::store(double t, bool segment_changes, double t_next_mid) {
  double* y = y_->data();
  HistoryEntry e;
  e.t = t;
  m_.relative(y, e.r);
  m_.rhs(t, y, ydot_.data(), &dg_);
  // ṙ and r̈ from q̇ and q̈.
  double v[2] = {0, 0}, a[2] = {0, 0};
  for (int i = 0; i < n_; ++i) {
    v[0] += m_.modal().S(0, i) * ydot_[i];
    v[1] += m_.modal().S(1, i) * ydot_[i];
    a[0] += m_.modal().S(0, i) * ydot_[n_ + i];
    a[1] += m_.modal().S(1, i) * ydot_[n_ + i];
  }
  e.v[0] = v[0];
  e.v[1] = v[1];
  e.a_left[0] = e.a_right[0] = a[0];
  e.a_left[1] = e.a_right[1] = a[1];
  Diagnostics left = dg_;
  if (segment_changes) {
    m_.set_segment(t_next_mid);
    m_.rhs(t, y, ydot_.data(), &dg_);
    double ar[2] = {0, 0};
    for (int i = 0; i < n_; ++i) {
      ar[0] += m_.modal().S(0, i) * ydot_[n_ + i];
      ar[1] += m_.modal().S(1, i) * ydot_[n_ + i];
    }
    e.a_right[0] = ar[0];
    e.a_right[1] = ar[1];
  }
  // Gaps in air (multiple regeneration), from the chips after the event.
  std::vector<double> gaps(teeth_, 0.0);
  if (s_.multiple_regeneration && !s_.linear && !m_.general()) {
    std::vector<double> h(teeth_);
    m_.chips(t, y, h.data());
    for (int j = 0; j < teeth_; ++j) gaps[j] = m_.in_arc()[j] ? std::max(0.0, -h[j]) : 0.0;
  }
  history_->push(e, gaps.data());
  history_->drop_before(t - hold_);
  return left;
}

// The next stop (skip = 0) or the one after it (skip = 1): the earlier of
// the fixed list and the pending images; two within 1e-9 τ are one.
double SimulationRun::next_event(int skip) const {
  double a[2] = {t_end_, t_end_};
  std::size_t i = next_stop_, j = 0;
  for (int k = 0; k < 2; ++k) {
    const double si = i < stops_.size() ? stops_[i] : t_end_, ij = j < images_.size() ? images_[j] : t_end_;
    a[k] = std::min(si, ij);
    while (i < stops_.size() && stops_[i] - a[k] <= 1e-9 * tau_) ++i;
    while (j < images_.size() && images_[j] - a[k] <= 1e-9 * tau_) ++j;
  }
  return a[skip];
}

// Passes the event at tt (the fixed stop and / or the images there).
void SimulationRun::pass_event(double tt) {
  if (next_stop_ < stops_.size() && stops_[next_stop_] - tt <= 1e-9 * tau_) ++next_stop_;
  while (!images_.empty() && images_.front() - tt <= 1e-9 * tau_) images_.pop_front();
}

// A chip zero crossing at tr: count it and queue its delay images.
void SimulationRun::on_root(double tr) {
  ++root_stops_;
  // Uniform path: images at tr + kτ. Real cutter: at the times the next
  // teeth pass over the surface the root's element left.
  std::vector<int> which{0};
  if (m_.general()) {
    std::vector<int> found(static_cast<std::size_t>(root_count_), 0);
    cv_->check(CVodeGetRootInfo(mem_, found.data()), "CVodeGetRootInfo");
    which.clear();
    for (int i = 0; i < root_count_; ++i)
      if (found[static_cast<std::size_t>(i)] != 0) which.push_back(i);
  }
  for (const int i : which) {
    for (int k = 1; k <= root_images_; ++k) {
      const double ti = tr + m_.root_image_offset(i, k);
      if (ti >= t_end_ - 1e-9 * tau_) break;
      const auto at = std::lower_bound(images_.begin(), images_.end(), ti - 1e-9 * tau_);
      if (at != images_.end() && *at - ti <= 1e-9 * tau_) continue;  // already there (e.g. roots at tooth exit)
      images_.insert(at, ti);
    }
  }
}

// A time inside the segment that starts at tt and ends at the next event
// t_next (the arc test at an event itself would be ambiguous).
double SimulationRun::segment_mid(double tt, double t_next) const {
  return 0.5 * (tt + (t_next > tt + 1e-9 * tau_ ? std::min(t_next, tt + dt_) : tt + dt_));
}

void SimulationRun::restart(double tt) {
  long ns = 0, nf = 0;
  CVodeGetNumSteps(mem_, &ns);
  CVodeGetNumRhsEvals(mem_, &nf);
  steps_done_ += ns;
  rhs_done_ += nf;
  cv_->check(CVodeReInit(mem_, tt, *y_), "CVodeReInit");
  cv_->check(CVodeSetStopTime(mem_, next_event(0)), "CVodeSetStopTime");
  ++restarts_;
}

// t = 0: the segment, the right-limit acceleration of the newest (t = 0)
// history entry, the first samples and the first stop time.
void SimulationRun::start() {
  m_.set_segment(stops_.empty() ? 0.5 * dt_ : 0.5 * std::min(stops_.front(), dt_));
  m_.rhs(0.0, y_->data(), ydot_.data(), &dg_);
  HistoryEntry& e0 = history_->newest_mutable();
  double a[2] = {0, 0};
  for (int i = 0; i < n_; ++i) {
    a[0] += m_.modal().S(0, i) * ydot_[n_ + i];
    a[1] += m_.modal().S(1, i) * ydot_[n_ + i];
  }
  e0.a_right[0] = a[0];
  e0.a_right[1] = a[1];
  if (s_.record_series) res_.series.push_back(make_sample(0.0, y_->data(), dg_));
  res_.once_per_period.push_back(make_sample(0.0, y_->data(), dg_));
  cv_->check(CVodeSetStopTime(mem_, stops_[0]), "CVodeSetStopTime");
}

// Integrates to grid point i (t = i τ / M), stopping at every event and root
// on the way, and records the grid point.
void SimulationRun::step_to_grid_point(long i) {
  const double target = static_cast<double>(i) * tau_ / M_;
  bool root_at_grid = false;
  while (true) {
    const int flag = CVode(mem_, target, *y_, &t_, CV_NORMAL);
    cv_->check(flag, "CVode");
    if (t_ >= target - 1e-12 * tau_) {  // at the grid point (possibly also a stop or a root)
      if (flag == CV_ROOT_RETURN) {
        on_root(t_);
        root_at_grid = true;
      }
      break;
    }
    if (next_event(0) - t_ <= 1e-9 * tau_) {
      // An event before the grid point (reached as a stop, or a root that
      // fell on it): step onto it and change segment.
      const double t_next = next_event(1);
      store(t_, true, segment_mid(t_, t_next));
      pass_event(t_);
      if (flag == CV_ROOT_RETURN) on_root(t_);
      restart(t_);
      continue;
    }
    if (flag == CV_ROOT_RETURN) {
      on_root(t_);
      store(t_, false, 0.0);
      if (++roots_this_period_ > root_cap_ && roots_on_) {
        cv_->check(CVodeRootInit(mem_, 0, nullptr), "CVodeRootInit");
        roots_on_ = false;
      }
      restart(t_);
      continue;
    }
    throw NumericalError("time-domain: internal error: CVODE stopped at t = " + std::to_string(t_) +
                         " s, neither a grid point, a stop nor a root");
  }
  t_ = target;
  const bool at_stop = std::abs(next_event(0) - target) <= 1e-9 * tau_;
  const double t_next = at_stop ? next_event(1) : t_end_;
  const Diagnostics left = store(target, at_stop, segment_mid(target, t_next));
  if (at_stop) pass_event(target);
  const long period = (i - 1) / M_;  // 0-based period this sample ends or lies in
  const long in_period = (i - 1) % M_;
  period_r_(2 * in_period) = history_->newest().r[0];
  period_r_(2 * in_period + 1) = history_->newest().r[1];
  const SeriesSample smp = make_sample(target, y_->data(), left);
  if (s_.record_series) res_.series.push_back(smp);
  if (period >= first_analysed_) {
    win_x_.push_back(smp.rel_x_m);
    win_y_.push_back(smp.rel_y_m);
    max_amp_ = std::max(max_amp_, std::hypot(smp.rel_x_m, smp.rel_y_m));
    if (left.any_in_arc) air_.add(left.in_air, 2 * (period - first_analysed_) >= (s_.periods - first_analysed_));
  }
  if ((i % M_) == 0) {
    res_.once_per_period.push_back(smp);
    end_of_period(at_stop, root_at_grid);
    if (s_.on_period) s_.on_period(res_);
  }
  if (at_stop || root_at_grid) restart(target);
}

// At t = kτ: the DMD snapshot, roots back on, and (linear mode) the exact
// rescaling that keeps the state near its initial size.
void SimulationRun::end_of_period(bool at_stop, bool& root_at_grid) {
  double* y = y_->data();
  Eigen::VectorXd z(zdim_);
  z.head(2 * M_) = period_r_;
  for (int k = 0; k < n_; ++k) {
    z(2 * M_ + k) = y[k];
    z(2 * M_ + n_ + k) = y[n_ + k] / m_.modal().omega(k);
  }
  snapshots_.states.push_back(z);
  snapshots_.log_scale.push_back(log_scale_);
  roots_this_period_ = 0;
  bool need_restart = at_stop;
  if (use_roots_ && !roots_on_) {
    cv_->check(CVodeRootInit(mem_, root_count_, cvode_roots), "CVodeRootInit");
    roots_on_ = true;
    need_restart = true;
  }
  if (s_.linear) {
    // Keep the state near the initial scale (linear: exact rescaling).
    double norm = 0.0;
    for (int k = 0; k < n_; ++k) norm = std::max(norm, std::abs(y[k]));
    if (norm > 0.0 && (norm > 1e3 * scale_ || norm < 1e-3 * scale_)) {
      const double f = scale_ / norm;
      for (int k = 0; k < 2 * n_; ++k) y[k] *= f;
      history_->scale(f);
      log_scale_ -= std::log(f);
      need_restart = true;
    }
  }
  if (need_restart) root_at_grid = true;
}

SimulationResult SimulationRun::finish() {
  long nsteps = 0;
  CVodeGetNumSteps(mem_, &nsteps);
  res_.steps = steps_done_ + nsteps;
  long nrhs = 0;
  CVodeGetNumRhsEvals(mem_, &nrhs);
  res_.rhs_evaluations = rhs_done_ + nrhs;
  res_.restarts = restarts_;
  res_.root_stops = root_stops_;
  res_.history_capacity = history_->capacity();
  res_.history_max_entries = history_->max_count();
  res_.max_amplitude_m = max_amp_;
  res_.out_of_cut_fraction = air_.fraction();

  const double rtol = options_.relative_tolerance;
  const GrowthEstimate growth = growth_per_period(snapshots_, first_analysed_, s_.linear, rtol);
  res_.dominant_multiplier = growth.multiplier;
  res_.growth_per_period = std::abs(growth.multiplier);

  const Spectrum sp = amplitude_spectrum(win_x_, win_y_, dt_);
  res_.spectrum_hz = sp.f;
  res_.spectrum_amplitude_m = sp.amp;
  const double best_f = dominant_nonharmonic_hz(sp, 1.0 / tau_);
  res_.dominant_nonharmonic_hz = best_f;
  res_.harmonics = tooth_passing_harmonics(sp, 1.0 / tau_, 3.0 * f_max_);

  VerdictInput vin;
  vin.linear = s_.linear;
  vin.growth = growth;
  vin.air = air_;
  vin.analysed_periods = s_.periods - first_analysed_;
  vin.relative_tolerance = rtol;
  const VerdictOutcome v = decide_verdict(vin);
  res_.verdict = v.verdict;
  res_.verdict_measure = v.measure;
  res_.chatter_frequency_hz = res_.verdict == SimulationVerdict::kChatter ? best_f : kNaN;
  if (history_->extrapolations() > 0)
    throw NumericalError("time-domain: internal error: the delayed state was needed outside the stored history (" +
                         std::to_string(history_->extrapolations()) + " times)");
  return std::move(res_);
}

SimulationResult SimulationRun::run() {
  start();
  const long total = static_cast<long>(s_.periods) * M_;
  for (long i = 1; i <= total; ++i) step_to_grid_point(i);
  return finish();
}

}  // namespace

std::string to_string(SimulationVerdict v) { return v == SimulationVerdict::kStable ? "stable" : "chatter"; }

std::string TimeDomainOptions::validate() const {
  std::ostringstream os;
  if (!(relative_tolerance >= 1e-12 && relative_tolerance <= 1e-2))
    os << "relative_tolerance = " << relative_tolerance << ": must be in [1e-12, 1e-2]";
  else if (samples_per_period < 8)
    os << "samples_per_period = " << samples_per_period << ": must be >= 8";
  else if (samples_per_vibration_cycle < 8)
    os << "samples_per_vibration_cycle = " << samples_per_vibration_cycle << ": must be >= 8";
  else if (max_samples_per_period < samples_per_period)
    os << "max_samples_per_period = " << max_samples_per_period << ": must be >= samples_per_period";
  else if (max_steps < 1000)
    os << "max_steps = " << max_steps << ": must be >= 1000";
  else if (axial_slices < 0 || axial_slices > 1000)
    os << "axial_slices = " << axial_slices << ": must be in [0, 1000] (0 = automatic)";
  else if (periods < 20)
    os << "periods = " << periods << ": must be >= 20";
  else if (!(depth_max_m > 0.0 && std::isfinite(depth_max_m)))
    os << "depth_max_m = " << depth_max_m << ": must be > 0 and finite";
  else if (!(depth_tolerance > 0.0 && depth_tolerance < 0.5))
    os << "depth_tolerance = " << depth_tolerance << ": must be in (0, 0.5)";
  else if (!(feed_m >= 0.0 && std::isfinite(feed_m)))
    os << "feed_m = " << feed_m << ": must be >= 0 and finite";
  return os.str();
}

TimeDomainSimulator::TimeDomainSimulator(StructuralModel model, Process process, TimeDomainOptions options)
    : model_(std::move(model)), process_(std::move(process)), options_(options) {
  const std::string why = options_.validate();
  if (!why.empty()) throw InputError("time-domain options: " + why);
  if (model_.mode_count() == 0)
    throw InputError("structural model: both bodies are rigid: give at least one mode");
  if (model_.has_measured())
    throw InputError("time-domain needs modes, not measured FRFs: fit modes to the measurement first "
                     "(chatter fit) and use them in the config");
}

SimulationResult TimeDomainSimulator::simulate(const SimulationSettings& s) const {
  validate_settings(s);
  SimulationRun run(model_, process_, options_, s);
  return run.run();
}

// ---------------------------------------------------------------------------
namespace {

/// The zeroth-order analytic solver as the depth search's starting guess, or
/// null when the analytic method does not apply to this model and process
/// (its constructor's rules, e.g. a model with both bodies rigid).
std::shared_ptr<const LobeSolver> default_starting_guess(const TimeDomainSimulator& sim) {
  TransferFunctionOptions to;
  to.depth_max_m = sim.options().depth_max_m;
  if (!to.validate().empty() || sim.model().rigid()) return nullptr;
  try {
    return std::make_shared<const AnalyticSolver>(sim.model(), sim.process(), to);
  } catch (const InputError&) {
    return nullptr;  // e.g. a cutter feature the analytic method refuses: no guess
  }
}

}  // namespace

TimeDomainSolver::TimeDomainSolver(StructuralModel model, Process process, TimeDomainOptions options,
                                   std::shared_ptr<const LobeSolver> starting_guess)
    : simulator_(std::move(model), std::move(process), options), starting_guess_(std::move(starting_guess)) {
  if (!starting_guess_) starting_guess_ = default_starting_guess(simulator_);
}

SimulationResult TimeDomainSolver::verdict_run(double rpm, double depth_m) const {
  SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_m;
  st.feed_m = simulator_.options().feed_m;
  st.linear = simulator_.options().linear;
  // options.periods counts tooth periods (header): the same simulated time
  // when the run's period is a revolution.
  const double tooth_periods_per_period = simulation_period(simulator_.process(), st) / simulator_.process().delay_s(rpm);
  st.periods = tooth_periods_per_period > 1.5
                   ? std::max(20, static_cast<int>(std::ceil(simulator_.options().periods / tooth_periods_per_period)))
                   : simulator_.options().periods;
  st.multiple_regeneration = simulator_.options().multiple_regeneration;
  st.record_series = false;
  return simulator_.simulate(st);
}

StabilityLimit TimeDomainSolver::limit_at(double rpm) const {
  if (!(rpm > 0.0 && std::isfinite(rpm))) throw InputError("spindle speed must be > 0 rev/min");
  const TimeDomainOptions& o = simulator_.options();
  StabilityLimit out;
  out.spindle_rpm = rpm;
  // Starting guess (header): only places the scan, never the answer.
  double guess = o.depth_max_m / 4.0;
  if (starting_guess_) {
    std::optional<StabilityLimit> g;
    try {
      g = starting_guess_->limit_at(rpm);
    } catch (const InputError&) {
      // The guess refuses this speed (documented in the header): no guess.
    }
    if (g && g->bounded() && g->depth_limit_m > 0.0) guess = std::min(g->depth_limit_m, o.depth_max_m);
  }
  // Scan by factors of 2 from guess / 16 (down if already chatter), then
  // bisection to depth_tolerance (depth_search.hpp, shared with sdm).
  auto probe = [&](double depth) { return verdict_run(rpm, depth); };
  auto chatter = [](const SimulationResult& r) { return r.verdict == SimulationVerdict::kChatter; };
  constexpr double kScanRatio = 2.0;
  constexpr int kMaxHalvings = 30;
  const double a = guess / 16.0;
  SimulationResult first = probe(a);
  detail::DepthBracket<SimulationResult> b;
  if (chatter(first)) {
    b = detail::descend_to_stable(a, std::move(first), kScanRatio, kMaxHalvings, probe, chatter);
    if (!b.found) {
      out.depth_limit_m = 0.0;
      return out;
    }
  } else {
    b = detail::climb_to_unstable(a, std::move(first), kScanRatio, o.depth_max_m, probe, chatter);
    if (!b.found) return out;  // stable up to the searched depth
  }
  detail::bisect_bracket(b, o.depth_tolerance, probe, chatter);
  const double lo = b.lo, hi = b.hi;
  const SimulationResult& at_hi = b.at_hi;
  out.depth_limit_m = 0.5 * (lo + hi);
  out.chatter_frequency_hz = at_hi.chatter_frequency_hz;
  if (std::isnan(out.chatter_frequency_hz)) out.chatter_frequency_hz = at_hi.dominant_nonharmonic_hz;
  out.lobe = lobe_number(out.chatter_frequency_hz, at_hi.tooth_passing_hz);
  return out;
}

}  // namespace chatter
