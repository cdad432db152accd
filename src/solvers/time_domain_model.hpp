// Internal parts of the time-domain solver (not part of the public API):
// the modal equations with the chip and the force of each tooth (and slice
// of a real cutter) — the right-hand side CVODE integrates. The solver is
// one concept per file:
//   time_domain_model.cpp     Model: the right-hand side, the chips, the
//                             arc events (this header);
//   time_domain_edge.cpp      the exact edge of a uniform helix: each
//                             tooth's force in closed form along its edge;
//   time_domain_run.cpp       SimulationRun: one run on CVODE (set-up,
//                             stepping, stop points, roots, restarts;
//                             time_domain_run.hpp);
//   time_domain_analysis.cpp  what a run returns: growth per period,
//                             spectrum, verdict (with the analysers of
//                             time_domain_parts.hpp);
//   time_domain_lobes.cpp     TimeDomainSolver: lobes by simulation;
//   time_domain_ssv.cpp       spindle speed variation: the modulated
//                             spindle angle, delays and event times
//                             (docs/ssv.md "In the time domain").
// Equations: include/chatter/time_domain.hpp; design: docs/time_domain.md.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <vector>

#include "chatter/process.hpp"
#include "chatter/speed_variation.hpp"
#include "chatter/structural_model.hpp"
#include "chatter/time_domain.hpp"
#include "time_domain_parts.hpp"

namespace chatter::td_detail {

using detail::History;

inline constexpr double kPi = std::numbers::pi;
// Delay-propagated images t_r + kτ of a chip zero crossing t_r that are stop
// points. The force has a kink at t_r (max(h, 0)), so d³r/dt³ jumps there and
// the delayed term jumps in its 3rd derivative at t_r + τ, its 5th at
// t_r + 2τ. With multiple regeneration the surface itself keeps the kink: the
// chip jumps in slope at t_r + τ, then in the 3rd and 5th derivatives.
inline constexpr int kRootImagesSingle = 2;
inline constexpr int kRootImagesMultiple = 3;
// An edge that takes at least this fraction of the shortest natural period
// to pass an end of the arc makes its arc events soft stops (no restart):
// the integrator (about 90 steps per cycle at rtol 1e-7) steps through the
// ramp.
inline constexpr double kMinRampCycles = 0.125;
// Up to this many distinct delays, the multiples of each are start stops.
inline constexpr std::size_t kMaxStartImageDelays = 8;

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
  // A cutter profile (Process::axial_slices; unused otherwise): the slice's
  // radial coefficient K_r sin κ + K_a cos κ (N/m²), its arc, its lag at mid
  // height tan β Λ(z) and across its height (rad); engaged = 0: never cuts.
  double kr = 0.0, en = 0.0, ex = 0.0, lag = 0.0, width = 0.0;
  bool engaged = true;
  std::vector<int> delay_index;   // into Model::delays_ (k = 1 … K)
  std::vector<double> advance;    // (θ_j + … + θ_{j−k+1}) / 2π
  std::vector<double> runout_diff;  // ρ_j − ρ_{j−k}, m
  std::vector<double> next_delay_sum;  // τ_{j+1}(z) + … + τ_{j+k}(z), s (root images)
};

/// The homogeneous linear equation (linear mode without the static chip):
/// the run measures the growth of a perturbation, sdm's multiplier.
inline bool homogeneous(const SimulationSettings& s) { return s.linear && !s.linear_static_chip; }

/// True when the run takes the per-tooth, per-slice path (real cutters):
/// milling with a helix, a variable pitch or helix, process damping, runout
/// (nonlinear mode only: linear mode ignores it), or an explicit axial_slices.
bool general_cutter(const Process& p, const TimeDomainOptions& o, bool linear);

/// True when a run's force is the exact, closed-form integral along each
/// tooth's edge (time_domain_edge.cpp): milling with automatic slices and
/// one helix angle (a variable pitch allowed: every height then reads the
/// same delay), no profile and, in nonlinear mode, no runout and no
/// multiple regeneration.
bool exact_edge_applies(const Process& p, const TimeDomainOptions& o, bool linear, bool multiple_regeneration);

/// The period of a run (s): the Floquet period of the process
/// (Process::floquet_period_s), the same as sdm's: the tooth period for a
/// uniform cutter, the shortest repeat of the pitch and helix pattern
/// otherwise, and of the runout too in nonlinear mode (the linear equation
/// has no static chip, which is all runout changes).
/// With spindle speed variation: the principal period of the delay
/// equation, speed_variation_period(p, rpm).period_s, sdm's (docs/ssv.md).
double simulation_period(const Process& p, const SimulationSettings& s);

class Model {
 public:
  Model(const StructuralModel& model, const Process& process, const SimulationSettings& s, double tau,
        const TimeDomainOptions& options);

  int n() const { return n_; }
  int teeth() const { return teeth_; }
  bool milling() const { return milling_; }
  const ModalMatrices& modal() const { return mm_; }
  int tool_modes() const { return tool_modes_; }

  void attach(History* h) { history_ = h; }
  bool general() const { return general_; }
  /// True when each tooth's force is the closed-form integral along its
  /// helical edge (time_domain_edge.cpp) rather than a sum over slices.
  bool exact_edge() const { return edge_; }
  /// Axial slices per tooth (1: straight teeth or turning).
  int slices() const { return slices_; }
  /// True when the force is continuous at every arc event and changes
  /// slowly enough there for the integrator to follow without a restart:
  /// several slices ramping in and out of the arc, or the exact edge (only
  /// the slope of the force changes at an event), with each edge taking at
  /// least kMinRampCycles of the shortest natural period to pass an arc end
  /// (a near-straight helix ramps in a few ns: a jump for the integrator).
  bool continuous_arc_events() const;
  /// Root functions: one per tooth (uniform path) or per element when every
  /// element's entry and exit is a stop (one slice); none with several
  /// slices (their chips are clipped, see docs/time_domain.md).
  int root_count() const {
    return general_ ? (slices_ == 1 && !profile_ ? static_cast<int>(elements_.size()) : 0) : teeth_;
  }
  /// Largest delay any element reads (s): the history must hold it.
  /// With speed variation: the longest delay, at the lowest speed.
  double max_delay() const {
    if (ssv_) return (delays_.empty() ? mean_delay_ : *std::max_element(delays_.begin(), delays_.end())) /
                     (1.0 - speed_.variation().amplitude_ratio);
    return delays_.empty() ? tau_ : *std::max_element(delays_.begin(), delays_.end());
  }
  /// With speed variation: the shortest delay, at the highest speed.
  double min_delay() const {
    if (ssv_) return (delays_.empty() ? mean_delay_ : *std::min_element(delays_.begin(), delays_.end())) /
                     (1.0 + speed_.variation().amplitude_ratio);
    return delays_.empty() ? tau_ : *std::min_element(delays_.begin(), delays_.end());
  }
  /// Distinct delays whose multiples carry the start discontinuity (stops);
  /// empty when they are many (distributed delays smear the start jump).
  /// With speed variation these are mean-speed delays: the stops are at
  /// real_time(k d).
  std::vector<double> start_image_delays() const {
    if (!general_) return {ssv_ ? mean_delay_ : tau_};
    if (delays_.size() > kMaxStartImageDelays) return {};
    return delays_;
  }
  /// The delay images of a chip zero crossing of root function `i` at t_r:
  /// the times the later teeth (k = 1 … count) cut the surface it leaves.
  double root_image_time(double t_r, int i, int k) const {
    const double offset = general_ ? elements_[static_cast<std::size_t>(i)].next_delay_sum[static_cast<std::size_t>(k - 1)]
                                   : k * (ssv_ ? mean_delay_ : tau_);
    if (ssv_) return image_time(t_r, offset);
    return t_r + offset;
  }
  // ---- spindle speed variation (time_domain_ssv.cpp) ----
  /// True when the spindle speed is modulated (Process::has_speed_variation).
  bool ssv() const { return ssv_; }
  /// The modulated speed the run integrates (frequency ratio: the one the
  /// principal period is exact for, SpeedVariationPeriod::frequency_ratio_used).
  const ModulatedSpeed& speed() const { return speed_; }
  /// Mean-speed time t' = θ(t)/Ω₀ at which the constant-speed spindle has
  /// turned as far as the modulated one at t (s); t at constant speed.
  double mean_time(double t) const { return ssv_ ? speed_.angle(t) / omega_spindle_ : t; }
  /// The inverse: the real time t with θ(t) = Ω₀ t' (s); t' at constant speed.
  double real_time(double t_mean) const { return ssv_ ? speed_.time_at_angle(omega_spindle_ * t_mean) : t_mean; }
  /// Sets which teeth are inside the cutting arc for the segment around `t`.
  void set_segment(double t_mid);
  /// Tooth j's angle (rad): Ω t + 2π j / N_t, or θ(t) + 2π j / N_t with speed variation.
  double angle(double t, int j) const {
    return (ssv_ ? speed_.angle(t) : omega_spindle_ * t) + 2.0 * kPi * j / teeth_;
  }
  static double wrap(double phi) {
    phi = std::fmod(phi, 2.0 * kPi);
    return phi < 0 ? phi + 2.0 * kPi : phi;
  }
  /// Times in [0, t_end] at which a tooth enters or leaves the arc (milling).
  /// Real cutters: every element's entry and exit with one slice; with
  /// several, the instants a tooth tip or the top of the cut enters or leaves
  /// (Process::engagement_events_s), where the sliced force has its kinks.
  std::vector<double> arc_events(double t_end) const;

  /// Unclipped chip thickness of every tooth in the arc at time t for state
  /// q (m); teeth outside the arc get +1 (a constant, for root finding).
  void chips(double t, const double* q, double* h) const;

  /// ẏ = f(t, y); fills `diag` when given. y = [q; q̇].
  /// What one right-hand-side call reports (both force paths).
  Diagnostics diagnostics(const double* F, double chip_max, bool any_arc, bool cutting, bool touching) const;

  void rhs(double t, const double* y, double* ydot, Diagnostics* diag) const;

  void modal_accelerations(const double* q, const double* qd, const double F[2], double* ydot) const;

  void relative(const double* q, double r[2]) const;

  long rhs_count() const { return rhs_count_; }
  /// A tooth counts as in air only when its chip is below −margin (m): the
  /// chip of a converged forced response touches 0 at the arc ends.
  void set_air_margin(double margin) { air_margin_ = margin; }
  const std::vector<char>& in_arc() const { return in_arc_; }
  /// Adds, per tooth, the share of it inside the arc at the last chips()
  /// call (1 per tooth; the engaged fraction of each slice of a real
  /// cutter) to `arc`, and the part of that share out of the cut (chip
  /// below −margin) to `air`.
  void tally_air(std::vector<double>& arc, std::vector<double>& air) const;

 private:
  // ---- spindle speed variation (time_domain_ssv.cpp) ----
  void init_speed_variation();
  // The time at which the spindle has turned Ω₀ `mean_offset` beyond θ(t_r), s.
  double image_time(double t_r, double mean_offset) const;
  // The time t − τ(t) the tooth now at t cuts the surface left behind by
  // the tooth `mean_delay` (s, at the mean speed) earlier: θ(t) − θ(t − τ) = Ω₀ mean_delay.
  double delayed_time(double t, double mean_delay) const {
    return ssv_ ? t - speed_.delay(t, omega_spindle_ * mean_delay) : t - mean_delay;
  }
  // C_pd / V at time t: the cutting speed follows Ω(t) (N·s/m²).
  double process_damping_now(double t) const {
    return ssv_ ? pd_per_depth_ * omega_spindle_ / speed_.omega(t) : pd_per_depth_;
  }
  // Arc events (milling) in [0, t_end] of the mean-speed time, the uniform
  // path's repeating every `tooth_period` (s).
  std::vector<double> arc_events_mean(double t_end, double tooth_period) const;

  // ---- the real cutter (general path) ----
  void build_elements(const TimeDomainOptions& o);
  int delay_slot(double d);
  double element_angle(const CutElement& e, double t) const;
  bool in_window(double phi) const;
  // Engaged fraction of a slice whose edge spans φ ± w/2 (ramps in and out).
  double engaged_fraction(double phi, double w) const;
  double engaged_fraction(double phi, double w, double en, double ex) const;
  // φ, sin φ, cos φ of every element at t.
  void element_angles(double t) const;
  // Chips of every element (unclipped; +1 out of the arc).
  void general_chips(double t, const double* q, double* h) const;
  // delayed_ = r(t − d) for every distinct delay d of the general path.
  void read_delayed(double t) const;
  // The sliced force and the modal accelerations.
  void general_rhs(double t, const double* q, const double* qd, double* ydot, Diagnostics* diag) const;
  // ---- the exact edge of a uniform helix (time_domain_edge.cpp) ----
  // Takes the edge path when the slices are automatic and every height of a
  // tooth reads the same delay (one helix angle), without a profile, runout
  // or multiple regeneration: sets edge_ and the per-tooth data.
  void init_edge(const TimeDomainOptions& o);
  // The force as the closed-form integral along each tooth's edge.
  void edge_rhs(double t, const double* q, const double* qd, double* ydot, Diagnostics* diag) const;

  ModalMatrices mm_;
  const Process& process_;
  const SimulationSettings& settings_;
  double tau_;
  int n_ = 0, tool_modes_ = 0, teeth_ = 1;
  bool milling_ = false;
  double omega_spindle_ = 0.0, kt_ = 0.0, kr_ = 0.0, kf_ = 0.0, phi_en_ = 0.0, phi_ex_ = 0.0;
  double pd_per_depth_ = 0.0;  // C_pd / V, N·s/m² (at the mean speed)
  // Spindle speed variation: on, the modulated speed, and the uniform
  // path's delay at the mean speed (tooth period; one revolution in turning), s.
  bool ssv_ = false;
  ModulatedSpeed speed_{1.0, {}};
  double mean_delay_ = 0.0;
  // Turning insert at this run's depth (docs/turning_inserts.md): chip
  // direction n, force vector d (the force on the tool is −b h d), chip
  // width b, static chip per unit feed sin κ_eq. Unused for the orthogonal
  // cut, which keeps h = f + Δx, F_x = −a K_f h exactly.
  bool orthogonal_ = true;
  double chip_n_[2] = {1.0, 0.0}, d_[2] = {0.0, 0.0};
  double width_m_ = 0.0, chip_per_feed_ = 1.0;
  // Kienzle's size effect in the nonlinear run (chatter/kienzle.hpp): the
  // force of the chip itself, k(h) h per unit width in each direction (the
  // linear run keeps the tangents the other methods read in kf_ and d_).
  std::optional<KienzleLaw> kienzle_;
  // F = −b h d(h) (an insert) or −a h K_f(h) (orthogonal): with Kienzle's law
  // in a nonlinear run the secants at the chip h >= 0, else the constants.
  void turning_force(double hc, double F[2]) const;
  bool general_ = false;
  bool profile_ = false;  // a cutter profile: per-element arcs, coefficients and lags
  int slices_ = 1;
  std::vector<CutElement> elements_;
  std::vector<double> delays_;            // distinct delays read by the elements, s
  mutable std::vector<double> delayed_;   // r(t − delays_[i]) (x, y) per rhs
  bool runout_ = false;                   // static chip from Process::static_chip_m
  // At the last chips() call, per element: engaged fraction, sin φ, cos φ.
  mutable std::vector<double> engaged_, phi_, sin_, cos_;
  std::vector<double> slice_lag_, slice_cos_, slice_sin_;  // per tooth: δ_j = κ_j dz, cos δ_j, sin δ_j
  // The exact edge (init_edge): per tooth κ_j (rad/m, signed), the index of
  // its delay in delays_, θ_j/2π, the runout difference (m) and its angular
  // offset (Process::tooth_offset_rad); at the last
  // right-hand side with diagnostics, the share of the edge in the arc and
  // in air (tally_air).
  bool edge_ = false;
  std::vector<double> edge_kappa_, edge_advance_, edge_runout_, edge_offset_;
  std::vector<int> edge_delay_;
  mutable std::vector<double> edge_arc_, edge_air_;
  std::vector<char> in_arc_;
  // At the last element_angles() call (several slices), per tooth: 1 when
  // every slice of the tooth lies outside the arc by more than
  // kOutOfArcMargin (its slices' engaged fractions are all exactly 0, so
  // their angles are not computed).
  mutable std::vector<char> tooth_out_;
  mutable std::vector<int> teeth_in_;  // the teeth not out, in order (scratch of element_angles)
  History* history_ = nullptr;
  mutable std::vector<double> chips_;
  mutable long rhs_count_ = 0;
  double air_margin_ = 0.0;
};

}  // namespace chatter::td_detail
