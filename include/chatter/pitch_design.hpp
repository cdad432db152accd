// Variable-pitch cutter design (issue 31 item 5, docs/design_pitch.md): the
// pitch angles of an N_t-tooth milling cutter that maximise the worst depth
// limit over a band of spindle speeds, started from Budak's analytical design
// rule and polished with a lobe solver (sdm by default) that handles variable
// pitch. `chatter design-pitch` and chatter.design_pitch print its record.
//
// The families (one parameter ΔP each, rad; docs/design_pitch.md):
//   linear:       θ_j = 2π/N_t + (j − (N_t − 1)/2)·ΔP,  j = 0 … N_t − 1
//   alternating:  θ_j = 2π/N_t + (−1)^j·ΔP/2            (N_t even)
// Both sum to 2π; ΔP = 0 is the equal-pitch cutter. Every angle is kept
// >= min_pitch_ratio · 2π/N_t, which bounds ΔP to [0, max_pitch_step_rad].
//
// The rule (Budak 2003, part I; Altintas, Engin & Budak 1999): in the
// averaged characteristic equation the teeth enter through
// Σ_j (1 − e^{−iω_c τ_j}), τ_j = θ_j/Ω. For the linear family
// Σ_j e^{−iω_c θ_j/Ω} = e^{−iω_c θ̄/Ω} Σ_j e^{−i(j − (N_t−1)/2)ψ}, ψ = ω_c ΔP/Ω,
// a geometric sum of modulus |sin(N_t ψ/2) / sin(ψ/2)|: the regeneration of
// the teeth cancels first at ψ = 2π/N_t, i.e.
//   ΔP = 2π Ω / (N_t ω_c)   (= 360° · n / (60 · N_t · f_c), n in rev/min, f_c in Hz).
// For the alternating family the two delays cancel in pairs at ψ = π:
//   ΔP = π Ω / ω_c.
// ω_c and n are the chatter frequency and the speed of the equal-pitch
// cutter's worst limit in the band.
//
// Units: SI (m, rad, Hz); spindle speeds in rev/min where a name says rpm.
// Layer: ops (core only). Thread safety: re-entrant.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

enum class PitchFamily { kLinear, kAlternating };
/// "linear", "alternating".
std::string to_string(PitchFamily f);
/// The family named `name`, or empty.
std::optional<PitchFamily> pitch_family_from_string(std::string_view name);

/// θ_j (rad) of `family` with step ΔP (rad) on `teeth` teeth (>= 2; even for
/// alternating). Sums to 2π to round-off (Process::milling accepts it).
std::vector<double> family_pitch_angles(PitchFamily family, int teeth, double step_rad);
/// The largest ΔP (rad) keeping every angle >= min_pitch_ratio · 2π/N_t
/// (ratio r in (0, 1)): linear 4π(1 − r)/(N_t(N_t − 1)), alternating 4π(1 − r)/N_t.
double max_pitch_step_rad(PitchFamily family, int teeth, double min_pitch_ratio);
/// Budak's rule (see the top of this header), rad: linear 2πΩ/(N_t ω_c),
/// alternating πΩ/ω_c, Ω = 2π rpm/60, ω_c = 2π f_c. @pre rpm, f_c > 0.
double budak_pitch_step_rad(PitchFamily family, int teeth, double spindle_rpm, double chatter_frequency_hz);

/// Defaults of PitchDesignOptions (also the front ends' defaults).
inline constexpr int kDefaultPitchBandPoints = 41;
inline constexpr int kDefaultPitchScanPoints = 12;
inline constexpr double kDefaultMinPitchRatio = 0.5;

struct PitchDesignOptions {
  double rpm_min = 0.0;  ///< lowest speed of the band, rev/min (> 0)
  double rpm_max = 0.0;  ///< highest, rev/min (> rpm_min)
  /// Speeds of the band, evenly spaced with both ends (>= 2): the worst limit
  /// is the smallest over these rows.
  int rpm_points = kDefaultPitchBandPoints;
  double depth_max_m = 0.05;  ///< deepest cut searched, m (> 0)
  PitchFamily family = PitchFamily::kLinear;
  /// Every angle >= this × 2π/N_t, in [0.1, 1): 0.5 keeps the shortest gap at
  /// half the equal one (room for the chip; docs/design_pitch.md).
  double min_pitch_ratio = kDefaultMinPitchRatio;
  /// ΔP scanned evenly over (0, max_pitch_step_rad] besides the rule, in
  /// [0, 200]: what keeps the polish from a poor local maximum.
  int scan_points = kDefaultPitchScanPoints;
  /// The method of every limit (registry name, "auto" = sdm for milling): one
  /// that accepts variable pitch and is not a simulation.
  std::string method = "sdm";
  SolverValues solver_options;  ///< that method's tuning options (checked by make_lobe_solver)
  unsigned threads = 1;         ///< threads over the band's speeds (0 = every core); result independent of it
  /// Fraction done (0..1) after each candidate cutter; may be empty.
  std::function<void(double)> progress;

  /// Empty when valid, else the rule broken, naming the field.
  std::string validate() const;
};

/// One cutter evaluated over the band.
struct PitchCandidate {
  double step_rad = 0.0;            ///< ΔP of the family (0 = equal pitch)
  std::vector<double> angles_rad;   ///< θ_j as the Process holds them (what the solver saw)
  std::vector<StabilityLimit> limits;  ///< one per band speed (+inf above depth_max_m)
  double worst_limit_m = 0.0;       ///< smallest limit over `limits` (+inf if none is bounded)
  double worst_rpm = 0.0;           ///< the speed of it (the first such row; rpm_min when unbounded)
};

struct PitchDesign {
  std::string method;               ///< the method of every limit ("auto" resolved)
  PitchFamily family = PitchFamily::kLinear;
  std::vector<double> speeds_rpm;   ///< the band's speeds
  double depth_max_m = 0.0;
  double step_max_rad = 0.0;        ///< max_pitch_step_rad of the options
  PitchCandidate equal;             ///< the config's cutter (equal pitch)
  /// The rule: at the equal-pitch worst speed and its chatter frequency.
  double rule_rpm = 0.0, rule_chatter_frequency_hz = 0.0;
  double rule_step_rad = 0.0;       ///< Budak's ΔP as the formula gives it
  bool rule_clipped = false;        ///< the formula exceeded step_max_rad: the start is step_max_rad
  PitchCandidate start;             ///< the rule's cutter (ΔP = min(rule, step_max))
  PitchCandidate designed;          ///< the best cutter evaluated (never worse than start or equal)
  /// Every ΔP evaluated (rule, scan, polish) with its worst limit (m, +inf
  /// where unbounded), in evaluation order.
  std::vector<std::pair<double, double>> evaluated;
  /// designed.worst / equal.worst; when designed has no limit below
  /// depth_max_m anywhere in the band, depth_max_m / equal.worst and
  /// gain_is_lower_bound.
  double gain = 1.0;
  bool gain_is_lower_bound = false;
};

/// The design (docs/design_pitch.md): the equal-pitch table over the band;
/// Budak's ΔP from its worst speed and chatter frequency (clipped to
/// step_max); the worst limit of the rule's cutter, of `scan_points` ΔP
/// evenly spaced over (0, step_max] and of equal pitch (ΔP = 0); then
/// Brent's maximiser (Boost.Math brent_find_minima) of the worst limit
/// between the neighbours of the best of these, to 1e-3 of step_max or 20
/// evaluations. The designed cutter is the best of all evaluated (an
/// unbounded limit counts as depth_max_m). Cost: (2 + scan_points + ≤ 20)
/// band tables of rpm_points limits each (sdm, 4 teeth: ~10 ms per limit).
/// @throws InputError on invalid options (validate), a process that is not
///         milling, has fewer than 2 teeth, an odd tooth count with the
///         alternating family, already unequal pitch or helix angles or a
///         speed variation; a method that does not accept variable pitch or
///         is a simulation; and when equal pitch has no limit below
///         depth_max_m anywhere in the band (nothing to improve).
PitchDesign design_pitch(const StructuralModel& model, const Process& process, const PitchDesignOptions& options);

}  // namespace chatter
