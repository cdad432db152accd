// The cutting process: turning or milling, with the real cutter of
// docs/physics.md §8 (helix, variable pitch and helix, runout, process
// damping). This is the one description of the cut every solver reads.
//
// Straight, equally spaced, true-running teeth (§3): every operation reduces
// to the regenerative force on the tool
//   F(t) = −a · H(t) · (r(t) − r(t − τ)),
// with a the depth of cut (m), H(t) the 2×2 directional cutting-coefficient
// matrix (N/m²), r the relative tool − workpiece displacement (m) and τ the
// delay (s). A real cutter (§8): tooth j, slice z (0 ≤ z ≤ a) is at
//   φ_j(t, z) = Ω t − Θ_j − z tan β_j / R,   Θ_j = θ_1 + … + θ_j,
// and cuts the surface tooth j−1 left τ_j(z) = [θ_j + z (tan β_j −
// tan β_{j−1})/R] / Ω earlier; the force is the slice force integrated over z:
//   F(t) = −Σ_j ∫₀ᵃ H₁(φ_j(t,z)) (r(t) − r(t − τ_j(z))) dz
// (H₁: the per-tooth matrix for unit depth, zero out of the cut), plus the
// process damping −C_pd (a/V) (n·ṙ) n of each cutting slice.
//
// What a solver asks of it:
//  - uniform_cutter(): one delay, period = delay_s() (one tooth period); else
//    period_s() is one revolution with one delay per tooth (and per slice for
//    a variable helix);
//  - tooth_force_integral(): the exact time–height integral of H₁ over a step
//    (sdm step averages, the averaged H₀), tooth_damping_integral() likewise
//    for the process-damping direction n nᵀ;
//  - engagement_events_s(): the times a tooth tip or the top of the cut enters
//    or leaves the arc (step grids and integrator stops);
//  - static_chip_m(): the static chip with runout (time domain).
// Units are SI; spindle speeds in rev/min only where a name says so; angles
// in rad, measured clockwise from +Y.
#pragma once

#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "chatter/cutter_profile.hpp"
#include "chatter/kienzle.hpp"
#include "chatter/speed_variation.hpp"

namespace chatter {

enum class Operation { kTurning, kMilling };

/// The words of an operation, one definition for every record, message and
/// front end (docs/results.md): "milling" / "turning".
std::string_view operation_name(Operation op);
/// The operation named `name` ("milling" or "turning").
/// @throws InputError naming the rule for any other word.
Operation operation_named(std::string_view name);
/// True for an operation whose cutting edges rotate with the spindle through
/// an engaged arc (milling): the directional matrix varies over a tooth
/// period. False for one fixed edge (turning): it is constant in time.
bool rotating_edges(Operation op);
/// The key under which a record reports the feed (mm): "feed_per_tooth_mm"
/// (milling) or "feed_mm_per_rev" (turning).
std::string_view feed_record_key(Operation op);
/// What one feed is per: "tooth" (milling) or "revolution" (turning).
std::string_view feed_basis(Operation op);
enum class MillingDirection { kDown, kUp };

/// Turning with an insert (docs/turning_inserts.md). Plane of the model: X
/// the feed direction, Y the radial (depth) direction, positive into the
/// workpiece. The insert's major edge makes the lead angle κ_r with the feed
/// direction and meets the minor edge in a nose arc of radius r_ε. At depth
/// a the engaged edge is replaced by its chord (Colwell 1954): width b (the
/// chord's length), equivalent lead angle κ_eq (the chord's angle to X),
/// chip thickness h = f sin κ_eq along the chord's normal
///   n = (sin κ_eq, cos κ_eq),
/// and the force on the tool −b h d, d = K_f n + K_r e with e = (−cos κ_eq,
/// sin κ_eq) along the chord, pointing into the workpiece. b sin κ_eq = a
/// always, so H = (1/sin κ_eq) d nᵀ. The defaults (κ_r = 90°, r_ε = 0,
/// K_r = 0) are the orthogonal cut of §3: H = [[K_f, 0], [0, 0]].
struct TurningParameters {
  /// K_f: specific cutting force normal to the engaged edge (its chord), in
  /// the X-Y plane, N/m² (> 0); at κ_r = 90° the feed force.
  double feed_force_coefficient_n_per_m2 = 0.0;
  /// C_pd >= 0, N/m: process damping (§8), the flank force −C_pd (b/V)
  /// (n·ṙ) n, V = π D_w N / 60 (at κ_r = 90°: −C_pd (a/V) ẋ along X). 0 = none.
  double process_damping_coefficient_n_per_m = 0.0;
  /// D_w, m: workpiece diameter, for the cutting speed V. Required (> 0)
  /// when C_pd > 0; else 0 (= not given).
  double workpiece_diameter_m = 0.0;
  /// K_r >= 0: specific cutting force along the engaged edge (its chord),
  /// pushing the tool out of the workpiece, N/m²; at κ_r = 90° the radial
  /// force. 0 = the in-plane force along the chip thickness (§3).
  double radial_force_coefficient_n_per_m2 = 0.0;
  /// κ_r in (0, π/2], rad: lead (approach) angle, from the feed direction to
  /// the major cutting edge. π/2 = the edge perpendicular to the feed.
  double lead_angle_rad = 0.5 * std::numbers::pi;
  /// r_ε >= 0, m: nose radius. 0 = a sharp corner.
  double nose_radius_m = 0.0;
  /// Kienzle's size effect (chatter/kienzle.hpp), or none (the linear law).
  /// When set, Process::turning derives K_f and K_r from it: the tangents
  /// (1 − m) k(h₀) at the mean chip h₀ = f sin κ_r of its feed, so that
  /// every linear stability method reads the regenerative coefficient in
  /// the two fields above (K_f given here is ignored); the static side
  /// (CuttingLaw, the static deflection) reads the secants k(h) at each
  /// point's own feed, and the time-domain simulation the force itself.
  std::optional<KienzleLaw> kienzle{};
};

/// Largest nose radius accepted, m: round inserts reach 16 mm (32 mm
/// diameter); the cap catches a diameter or a unit mistake.
inline constexpr double kMaxNoseRadiusM = 0.025;  // 25 mm

/// The chord of the engaged edge of a turning insert at one depth of cut
/// (Colwell 1954; docs/turning_inserts.md).
struct InsertChord {
  double width_m = 0.0;         ///< b: length of the chord = chip width, m
  double lead_angle_rad = 0.0;  ///< κ_eq: angle from the feed direction X to the chord, rad
  bool nose_only = false;       ///< true when a <= r_ε (1 − cos κ_r): only the nose arc cuts
};

/// The chord from the lowest point of the nose (the tip, on the finished
/// surface) to the point where the edge leaves the uncut surface at depth
/// a (m, >= 0), for lead angle κ_r (rad, in (0, π/2]) and nose radius r_ε
/// (m, >= 0). Sharp corner: b = a / sin κ_r, κ_eq = κ_r. Nose arc only
/// (a <= r_ε(1 − cos κ_r)): b = sqrt(2 r_ε a), sin κ_eq = sqrt(a / 2r_ε).
/// Else the end point is (r_ε sin κ_r + (a − r_ε(1 − cos κ_r)) cot κ_r, a)
/// from the tip. Always b sin κ_eq = a. Feeds small against r_ε are
/// assumed (the trailing arc of length ~f/2 is left out). Cost O(1).
InsertChord insert_chord(double lead_angle_rad, double nose_radius_m, double depth_m);

/// Most teeth a milling cutter may have. Slitting saws reach ~200; the cap
/// keeps a unit mistake (or a fuzzed 57 483 648) from allocating per-tooth
/// tables of gigabytes.
inline constexpr int kMaxTeeth = 1000;

/// The milling force law of §3, the one formula every method uses (Process's
/// directional matrices, the time-domain right-hand side, the forced
/// response): the force on the tool per unit chip thickness and unit depth
/// of a tooth at angle φ (given by sin φ, cos φ) with tangential and radial
/// coefficients K_t, K_r (N/m²) is −v, v = (K_t cos φ + K_r sin φ,
/// −(K_t sin φ − K_r cos φ)); the tooth's chip direction is n = (sin φ, cos φ).
inline Eigen::Vector2d milling_force_direction(double kt, double kr, double sin_phi, double cos_phi) {
  return Eigen::Vector2d(kt * cos_phi + kr * sin_phi, -(kt * sin_phi - kr * cos_phi));
}

/// The largest feed (per tooth in milling, per revolution in turning) any
/// input takes, mm: the config's feed keys and the time-domain option.
inline constexpr double kMaxFeedMm = 10.0;

struct MillingParameters {
  int teeth = 0;                                     ///< N_t in [1, kMaxTeeth].
  double tangential_coefficient_n_per_m2 = 0.0;      ///< K_t > 0, N/m².
  double radial_coefficient_n_per_m2 = 0.0;          ///< K_r >= 0, N/m².
  double radial_immersion = 1.0;                     ///< a_e / D in (0, 1].
  MillingDirection direction = MillingDirection::kDown;
  // The cutter (§8). The defaults are the straight, equally spaced,
  // true-running cutter of §3.
  /// D, m: tool diameter. Required (> 0) by a helix and by process damping;
  /// 0 = not given.
  double tool_diameter_m = 0.0;
  /// θ_j, rad: the angle from tooth j−1 (cyclic: θ_0 from tooth N_t−1) to
  /// tooth j. Empty = equal pitch 2π/N_t; else N_t values > 0 summing to 2π.
  std::vector<double> pitch_angles_rad{};
  /// β_j, rad, each in [0, π/2): empty = straight teeth; one value = every
  /// tooth; N_t values = variable helix.
  std::vector<double> helix_angles_rad{};
  /// ρ_j, m: radial offset of tooth j (cuts at radius R + ρ_j). Empty = none;
  /// else N_t values. Changes the static chip only (nonlinear time domain).
  std::vector<double> runout_m{};
  /// C_pd >= 0, N/m: process damping per tooth and slice in the cut. 0 = none.
  double process_damping_coefficient_n_per_m = 0.0;
  /// The cutter's shape along its axis (docs/cutter_geometry.md): flat (the
  /// default, the cylinder above), ball, bull nose or a general profile.
  CutterProfileParameters cutter{};
  /// K_a >= 0, N/m²: axial force coefficient of Lee & Altintas (1996). Only
  /// a slice with lead angle κ < 90° (ball, bull nose, profile) turns part
  /// of it into the x-y plane: K_a cos κ adds to the radial coefficient.
  double axial_coefficient_n_per_m2 = 0.0;
  /// The engaged arcs [φ_en, φ_ex] (rad, clockwise from +Y, §3) when the
  /// material is not one straight wall beside the cutter: what a simulated
  /// stock gives (chatter/stock.hpp: a pocket's corner; two arcs where a pass
  /// crosses an earlier slot, the material on both sides of it). Empty = the
  /// one arc of radial_immersion and direction (milling_arc_rad). When
  /// given: sorted, disjoint, each 0 <= φ_en < φ_ex <= π; a flat cutter only
  /// (a profile's slices take their arcs from a straight wall); milling()
  /// sets radial_immersion to Σ (cos φ_en − cos φ_ex)/2, the arcs' width
  /// across the feed over D (what the removal rate reads). A tooth cuts
  /// while it is in any arc: every solver reads that through this Process
  /// (in_cut, the directional integrals, engagement_events_s) and the cut.
  std::vector<std::pair<double, double>> engaged_arcs_rad{};
};

/// One axial slice z_lo <= z <= z_hi of the cut of a cutter with a profile
/// (Process::axial_slices). With the lead angle κ at its mid height the
/// Lee–Altintas slice force per unit regenerative displacement is that of a
/// flat-cutter slice of height dz with the radial coefficient replaced by
/// K_r sin κ + K_a cos κ: the chip h = Δr·n sin κ and the width dz / sin κ
/// cancel their sin κ, the radial force (along the surface normal) has the
/// in-plane part sin κ and the axial force cos κ (the z part of both is
/// dropped: the structural modes act in the x-y plane).
struct AxialSlice {
  double z_lo_m = 0.0, z_hi_m = 0.0;  ///< heights above the tip, m
  double z_m = 0.0;                   ///< mid height, m
  double radius_m = 0.0;              ///< R at mid height, m
  double lead_angle_rad = 0.0;        ///< κ at mid height, rad
  double lag_lo = 0.0, lag_hi = 0.0;  ///< Λ(z_lo), Λ(z_hi): lag per unit tan β, rad
  double entry_rad = 0.0, exit_rad = 0.0;  ///< the slice's cutting arc (slice_engagement)
  bool engaged = false;               ///< false: the slice's circle misses the cut
  /// K_r sin κ + K_a cos κ, N/m²: the in-plane radial coefficient of the slice.
  double radial_coefficient_n_per_m2 = 0.0;
  double height_m() const { return z_hi_m - z_lo_m; }
};

/// The process description. Build with Process::turning / Process::milling,
/// which validate their arguments.
class Process {
 public:
  /// @throws InputError if K_f <= 0 or not finite, K_r < 0, C_pd < 0, C_pd
  ///         > 0 without a workpiece diameter > 0, a lead angle outside
  ///         (0, 90] deg or a nose radius outside [0, kMaxNoseRadiusM].
  static Process turning(TurningParameters p);
  /// @throws InputError if teeth < 1, K_t <= 0, K_r < 0, radial immersion
  ///         outside (0, 1], pitch angles not N_t values > 0 summing to 2π
  ///         (to 1e-6 rad), helix angles not 1 or N_t values in [0, π/2),
  ///         a helix or process damping without a diameter > 0, runout not
  ///         N_t finite values with |ρ_j| < R (when D is given), C_pd < 0,
  ///         K_a < 0, a cutter profile CutterProfile::make refuses, a profile
  ///         with process damping (not modelled), a helix on a general
  ///         profile with a radius 0.
  static Process milling(MillingParameters p);

  Operation operation() const { return operation_; }
  /// chatter::rotating_edges(operation()): the question a solver, record or
  /// front end asks of the operation (edges sweeping an arc, or one fixed edge).
  bool rotating_edges() const { return chatter::rotating_edges(operation_); }
  std::string_view operation_name() const { return chatter::operation_name(operation_); }
  std::string_view feed_record_key() const { return chatter::feed_record_key(operation_); }
  std::string_view feed_basis() const { return chatter::feed_basis(operation_); }
  const TurningParameters& turning_parameters() const { return turning_; }
  const MillingParameters& milling_parameters() const { return milling_; }

  /// Delay τ (s) at spindle speed `rpm` (rev/min): one revolution for turning,
  /// one (mean) tooth period 60/(N·N_t) for milling. For a uniform cutter it
  /// is the delay and the period of H(t). @pre rpm > 0.
  double delay_s(double rpm) const;
  /// Inverse of delay_s: the spindle speed (rev/min) whose delay is `tau_s`.
  double rpm_from_delay(double tau_s) const;
  /// Tooth-passing frequency N·N_t/60, Hz (turning: the spindle frequency
  /// N/60): the one definition every report uses (docs/results.md), whatever
  /// the pitch. = 1 / delay_s(rpm). @pre rpm > 0.
  double tooth_passing_hz(double rpm) const;
  /// The diameter a control's cutter compensation (G41/G42) offsets by, m:
  /// the tool's diameter in milling (0 when not given), twice the insert's
  /// nose radius in turning.
  double compensation_diameter_m() const;
  /// Number of (mean) tooth periods per spindle revolution: 1 (turning) or N_t.
  int delays_per_revolution() const;

  // ---- the real cutter (§8) ----
  /// Number of teeth (1 for turning).
  int teeth() const;
  /// True when the cut has one delay and H(t) repeats every delay_s():
  /// turning, or milling with equal pitch and one helix angle for all teeth.
  bool uniform_cutter() const;
  /// Period (s) of the delay equation: delay_s(rpm) for a uniform cutter,
  /// one revolution 60/rpm otherwise. @pre rpm > 0.
  double period_s(double rpm) const;
  /// The fewest teeth r (a divisor of N_t) after which the cutter repeats
  /// itself: the pitch angles and helix lags of tooth j and j + r agree for
  /// every j (and the runout offsets, with `with_runout`). 1 for turning and
  /// for a uniform cutter; N_t/2 for 70/110/70/110°; N_t for an irregular one.
  int repeat_teeth(bool with_runout = false) const;
  /// The Floquet period (s): the period of the equation a Floquet method
  /// (sdm) builds its map over and a simulation measures its growth over,
  /// repeat_teeth(with_runout) tooth periods (60/rpm exactly when that is
  /// N_t). Multipliers, spectral radii and growth factors are per this period
  /// (docs/results.md). @pre rpm > 0.
  double floquet_period_s(double rpm, bool with_runout = false) const;
  /// True with a helix angle > 0 on some tooth (milling).
  bool has_helix() const;
  /// True with unequal pitch angles, or unequal helix angles (milling).
  bool has_variable_pitch() const;
  bool has_variable_helix() const;
  /// True with a runout offset != 0 on some tooth (milling).
  bool has_runout() const;
  /// True with C_pd > 0.
  bool has_process_damping() const;

  // ---- the cutter's shape along its axis (docs/cutter_geometry.md) ----
  /// True for a ball, bull-nose or general cutter (milling): the cut is
  /// integrated over axial_slices(); false for the flat end mill, whose
  /// closed forms (and results) are those of the cylinder, bit for bit.
  bool has_profile() const { return operation_ == Operation::kMilling && !profile_.flat(); }
  const CutterProfile& cutter_profile() const { return profile_; }
  /// The slices of the cut at depth a (m > 0): cutter_profile().slices()
  /// equal heights a/S from the tip, each with R, κ and Λ at its heights,
  /// its arc and its radial coefficient. Cost O(S). @pre has_profile().
  std::vector<AxialSlice> axial_slices(double depth_m) const;
  /// Why the cut at depth a (m) has no chip, or "" when it has one: the
  /// rule of docs/results.md "No cut" (a cut with no chip is refused, never
  /// judged stable or chatter). A depth <= 0, or a profiled cutter none of
  /// whose axial_slices(a) reaches the radial depth's band (a bull nose or a
  /// ball shallower than its corner: the edge stays inside the band's inner
  /// radius R |1 − 2 a_e/D|). The feed's part of the rule (no static chip at
  /// feed 0) belongs to the nonlinear time domain, which reads the feed.
  std::string no_chip_reason(double depth_m) const;
  /// ∫_{t_a}^{t_b} ∫_{z_lo}^{z_hi} g(φ) H₁,κ(φ) dz dt over slice `s` of tooth
  /// j, φ = Ω t − Θ_j − tan β_j Λ(z) with Λ linear over the slice, g the
  /// slice's arc, in closed form (N/m² · m · s). @pre has_profile().
  Eigen::Matrix2d slice_force_integral(int j, const AxialSlice& s, double t_a, double t_b, double rpm) const;
  /// The integrand of slice_force_integral over the slice's height at one
  /// instant t (N/m): its derivative in t_b. @pre has_profile().
  Eigen::Matrix2d slice_force_rate(int j, const AxialSlice& s, double t, double rpm) const;
  /// The same for the force direction v (the constant-chip force).
  Eigen::Vector2d slice_force_direction_integral(int j, const AxialSlice& s, double t_a, double t_b, double rpm) const;
  /// tan β_j · Λ(z) (rad): how far the edge of tooth j at height z (m) lags
  /// its tip; z tan β_j / R for the flat cutter.
  double helix_lag_rad(int j, double z_m) const;
  /// True when H (the average H₀ too) depends on the depth: a turning nose
  /// radius, or a cutter profile not frozen by at_depth().
  bool depth_dependent_force() const;
  /// This process with its depth-dependent force frozen at depth a (m > 0):
  /// the insert's chord (with_chord_at), or the profile's slices at a, whose
  /// average_directional_matrix() is then H₀(a). What the averaged methods
  /// solve for one depth. Other processes: a copy.
  Process at_depth(double depth_m) const;
  /// H₀(a), N/m²: the average of H over a revolution, integrated over the
  /// slices of depth a and divided by a; = average_directional_matrix() for
  /// a cutter without a profile. @pre milling, a > 0.
  Eigen::Matrix2d average_directional_matrix_at(double depth_m) const;

  // ---- the turning insert (docs/turning_inserts.md) ----
  /// True for turning with κ_r = 90°, r_ε = 0 and K_r = 0: the orthogonal
  /// cut of §3, H = [[K_f, 0], [0, 0]] exactly. False for milling.
  bool orthogonal_turning() const;
  /// True for turning with a nose radius > 0: the chord, hence H, depends on
  /// the depth (solvers rebuild H per depth; docs/turning_inserts.md).
  bool has_nose_radius() const;
  /// The chord of the engaged edge at depth a (m >= 0). @pre turning.
  InsertChord chord(double depth_m) const;
  /// n: unit chip-thickness direction at depth a (the chord's normal),
  /// exactly (1, 0) for the orthogonal cut. @pre turning.
  Eigen::Vector2d chip_direction(double depth_m) const;
  /// d = K_f n + K_r e (N/m²): the force on the tool is −b h d. @pre turning.
  /// With Kienzle's law the regenerative (tangent) coefficients at the mean
  /// chip h₀ = f sin κ_eq(a).
  Eigen::Vector2d edge_force(double depth_m) const;
  /// d of the static force at chip thickness h (m, > 0): K_f and K_r as
  /// edge_force without Kienzle's law, its secants k(h) with it (the mean
  /// force on the tool is −b h d). @pre turning.
  Eigen::Vector2d secant_edge_force(double depth_m, double chip_m) const;
  /// h = f sin κ_eq(a), m: the chip the insert cuts at depth a (m) and feed f
  /// (m per revolution), what Kienzle's law reads (the orthogonal cut: f).
  /// @pre turning.
  double chip_thickness_m(double depth_m, double feed_per_rev_m) const;
  /// True when a turning process follows Kienzle's law (turning_parameters().kienzle).
  bool has_size_effect() const;
  /// This process with its regenerative coefficients linearised at the mean
  /// chip of `feed_per_rev_m` (m, > 0): itself without Kienzle's law. What a
  /// command calls for a row's, block's or set-point's own feed.
  /// @throws InputError if the feed is not > 0 (with Kienzle's law).
  Process at_feed(double feed_per_rev_m) const;
  /// H(a) = (b/a) d nᵀ = d nᵀ / sin κ_eq, N/m²: the turning directional
  /// matrix at depth a (m; > 0 with a nose radius, any otherwise, where it
  /// does not depend on a). @pre turning.
  Eigen::Matrix2d turning_matrix(double depth_m) const;
  /// a H(a) = b d nᵀ, N/m: finite at a = 0 (= 0) also with a nose radius.
  Eigen::Matrix2d turning_force_matrix(double depth_m) const;
  /// b n nᵀ (m): the process-damping direction times the chip width at
  /// depth a (the flank force is −(C_pd/V) b (n·ṙ) n). @pre turning.
  Eigen::Matrix2d turning_damping_matrix(double depth_m) const;
  /// This process with the insert of a sharp corner at the lead angle
  /// κ_eq(a): the same H as this one at depth a (m > 0), independent of the
  /// depth. What the averaged methods solve for a frozen chord. @pre turning.
  Process with_chord_at(double depth_m) const;

  // ---- spindle speed variation (docs/ssv.md, chatter/speed_variation.hpp) ----
  /// The modulation of the spindle speed; inactive (R_VA = 0) by default.
  const SpeedVariation& speed_variation() const { return speed_variation_; }
  /// True with R_VA > 0: the delay varies in time (only methods that accept
  /// SolverFeature::kSpeedVariation handle it).
  bool has_speed_variation() const { return speed_variation_.active(); }
  /// Sets the modulation (R_VA = 0 turns it off). @throws InputError naming
  /// the rule (SpeedVariation::validate).
  void set_speed_variation(SpeedVariation v);
  /// This process at constant speed (the reference of the SSV gain).
  Process at_constant_speed() const {
    Process p = *this;
    p.speed_variation_ = {};
    return p;
  }
  /// θ_j (rad), Θ_j = θ_1 + … + θ_j (Θ_0 = 0), β_j (rad), ρ_j (m) of tooth
  /// j in [0, N_t). @pre operation() == kMilling.
  double pitch_angle_rad(int j) const;
  double tooth_offset_rad(int j) const;
  double helix_angle_rad(int j) const;
  double runout_m(int j) const;
  /// tan β_j / R (rad per m of height): how far a slice lags the tooth tip.
  double helix_lag_rad_per_m(int j) const;
  /// φ_j(t, z) = Ω t − Θ_j − z tan β_j / R (rad, not wrapped); with a
  /// profile Ω t − Θ_j − helix_lag_rad(j, z).
  double tooth_angle_rad(int j, double t_s, double z_m, double rpm) const;
  /// τ_j(z) = [θ_j + z (tan β_j − tan β_{j−1}) / R] / Ω, s (with a profile
  /// Λ(z) in place of z / R).
  double tooth_delay_s(int j, double z_m, double rpm) const;
  /// True when φ (any real, wrapped to [0, 2π)) lies in [φ_en, φ_ex].
  bool in_cut(double phi) const;
  /// ∫_{t_a}^{t_b} ∫_0^a g(φ) H₁(φ) dz dt with φ = φ_j(t, z) and g the
  /// cutting window (in_cut), in closed form (N/m² · m · s; exact for any
  /// helix; for β_j = 0 it is a times the time integral). Cost O(1).
  /// @pre operation() == kMilling, t_b >= t_a, a >= 0, rpm > 0.
  Eigen::Matrix2d tooth_force_integral(int j, double t_a, double t_b, double a_m, double rpm) const;
  /// ∫_0^a g(φ) H₁(φ) dz at one instant t, φ = φ_j(t, z) (N/m): the
  /// integrand of tooth_force_integral in t (what collocation samples).
  /// Closed form, cost O(1) (O(slices) with a profile). @pre as tooth_force_integral.
  Eigen::Matrix2d tooth_force_rate(int j, double t_s, double a_m, double rpm) const;
  /// ∫_{t_a}^{t_b} ∫_0^a g(φ) v(φ) dz dt, φ = φ_j(t, z), of the force
  /// direction v of force_direction() (N/m² · m · s), in closed form for
  /// any helix: the force of a chip of constant thickness (a runout offset,
  /// docs/forced.md) over a step. @pre as tooth_force_integral.
  Eigen::Vector2d tooth_force_direction_integral(int j, double t_a, double t_b, double a_m, double rpm) const;
  /// The same integral of the process-damping direction n nᵀ, n = (sin φ,
  /// cos φ) (m · s).
  Eigen::Matrix2d tooth_damping_integral(int j, double t_a, double t_b, double a_m, double rpm) const;
  /// Its integrand in t: ∫_0^a g(φ) n nᵀ dz at one instant (m; what
  /// collocation samples at its nodes). @pre as tooth_force_integral.
  Eigen::Matrix2d tooth_damping_rate(int j, double t_s, double a_m, double rpm) const;
  /// n nᵀ at φ (dimensionless; the process-damping direction of a slice).
  static Eigen::Matrix2d damping_direction(double phi);
  /// Process damping per unit depth, C_pd / V (N·s/m²); 0 without it.
  /// V = π D N / 60 (tool diameter in milling, workpiece in turning).
  double process_damping_per_depth(double rpm) const;
  /// Average over one revolution of the process-damping direction of all
  /// teeth in the cut: milling N_t/(2π) ∫_{φ_en}^{φ_ex} n nᵀ dφ, turning
  /// (b/a) n nᵀ ([[1, 0], [0, 0]] for the orthogonal cut). The averaged (§4)
  /// methods use a·(C_pd/V)·this. @throws std::logic_error for turning with
  /// a nose radius (depth-dependent: turning_damping_matrix).
  Eigen::Matrix2d average_damping_direction() const;
  /// The times in [0, period_s(rpm)) at which a tooth tip (z = 0) or the
  /// top of the cut (z = a) enters or leaves the arc, sorted, duplicates
  /// (within 1e-12 of the period) merged. Empty for turning.
  std::vector<double> engagement_events_s(double rpm, double depth_m) const;
  /// The force on the tool per unit chip thickness and unit depth of a
  /// cutting tooth at φ, N/m²: v(φ) = (K_t cos φ + K_r sin φ, −(K_t sin φ −
  /// K_r cos φ)) (§3: F = −a h v, and tooth_matrix(φ) = v nᵀ). @pre milling.
  Eigen::Vector2d force_direction(double phi) const;
  /// The feed of tooth j, m: the table advance since the tooth before it,
  /// N_t f_z θ_j / 2π (f_z for equal pitch; the feed per revolution itself
  /// in turning). What the static chip f_j sin φ of the linear model uses
  /// (docs/physics.md §11).
  double feed_of_tooth_m(int j, double feed_per_tooth_m) const;
  /// Static (feed) chip of tooth j at angle φ with runout (§8): the smallest
  /// over earlier teeth j−k (k = 1 … N_t) of N_t f_z (θ_j + … + θ_{j−k+1})/2π ·
  /// sin φ + ρ_j − ρ_{j−k}, floored at 0 (m). Without runout: f_z sin φ
  /// (equal pitch) floored at 0.
  double static_chip_m(int j, double phi, double feed_per_tooth_m) const;

  /// Entry and exit angles φ_en, φ_ex (rad, clockwise from +Y) of a milling
  /// tooth: down-milling [arccos(2a_e/D − 1), π], up-milling [0, arccos(1 − 2a_e/D)].
  /// The one definition: milling_arc_rad (chatter/cutting_law.hpp), computed
  /// once by milling(). With several engaged arcs: the first arc's entry and
  /// the last arc's exit (their hull; engaged_arcs gives each).
  /// @pre operation() == kMilling.
  double entry_angle() const { return arcs_.front().first; }
  double exit_angle() const { return arcs_.back().second; }
  /// The engaged arcs [φ_en, φ_ex] (rad), sorted and disjoint: one from a
  /// radial immersion, or MillingParameters::engaged_arcs_rad. @pre milling.
  const std::vector<std::pair<double, double>>& engaged_arcs() const { return arcs_; }
  /// More than one engaged arc: a path that assumes one window (sdm's
  /// straight-teeth grid, collocation, the exact-edge time domain, the forced
  /// response) gives way to the general one or refuses.
  bool split_engagement() const { return arcs_.size() > 1; }
  /// Every arc's entry and exit (rad), in order: the angles at which a
  /// straight tooth enters or leaves the cut. @pre milling.
  std::vector<double> arc_edges_rad() const;

  /// Directional matrix of one milling tooth at angle φ (rad) while it cuts,
  /// N/m²: [[(K_t cosφ + K_r sinφ) sinφ, (K_t cosφ + K_r sinφ) cosφ],
  ///        [−(K_t sinφ − K_r cosφ) sinφ, −(K_t sinφ − K_r cosφ) cosφ]].
  Eigen::Matrix2d tooth_matrix(double phi) const;

  /// An antiderivative in φ of tooth_matrix (closed form), N/m²·rad:
  /// ∫_{φa}^{φb} tooth_matrix(φ) dφ = F(φb) − F(φa). Used for H₀ and for the
  /// step averages of the semi-discretisation. Cost O(1). @pre operation() == kMilling.
  Eigen::Matrix2d tooth_matrix_antiderivative(double phi) const;

  /// Directional matrix H(t) at time t (s) after tooth 0 passes φ = 0, for
  /// spindle speed `rpm`, N/m²: Σ_j g_j(φ_j) tooth_matrix(φ_j) with
  /// φ_j = Ωt + 2πj/N_t (straight, equally spaced teeth: the §3 cutter).
  /// Turning: the constant turning_matrix ([[K_f, 0], [0, 0]] for the
  /// orthogonal cut). @throws std::logic_error for turning with a nose
  /// radius (depth-dependent: turning_matrix(depth)).
  Eigen::Matrix2d directional_matrix(double t_s, double rpm) const;

  /// Average of H over one delay, H₀ (N/m²): turning H itself; milling
  /// (N_t/2π) ∫_{φ_en}^{φ_ex} tooth_matrix(φ) dφ, integrated in closed form
  /// (zeroth-order approximation, Altintas & Budak 1995).
  /// Neither helix nor pitch changes it (§8: the average over a revolution
  /// of every tooth's H₁ is the same).
  Eigen::Matrix2d average_directional_matrix() const;

 private:
  Operation operation_ = Operation::kTurning;
  TurningParameters turning_;
  MillingParameters milling_;
  // Filled by milling(): per tooth θ_j, Θ_j, tan β_j / R, ρ_j.
  std::vector<double> pitch_, offset_, lag_, runout_;
  // The cutter's shape; per tooth tan β_j (with a profile); the depth frozen
  // by at_depth (0 = not frozen).
  CutterProfile profile_{};
  std::vector<double> tan_helix_;
  double frozen_depth_m_ = 0.0;
  // Entry and exit times (s, not wrapped) of the profile's slices (engagement_events_s).
  std::vector<double> profile_events_s(double rpm, double depth_m) const;
  SpeedVariation speed_variation_{};
  // The milling arcs (set by milling(); the default is the default
  // MillingParameters' full-immersion down-milling arc [0, π]).
  std::vector<std::pair<double, double>> arcs_{{0.0, std::numbers::pi}};
};

}  // namespace chatter
