// The one definition of every number the engine reports about stability
// (docs/results.md): each quantity is computed here, or by the one member
// of Process named here, and every command, method, output format, the C
// API and Python take it from here.
//
//   quantity            definition                                   where
//   tooth_passing_hz    N·N_t/60 (turning N/60), any pitch            Process::tooth_passing_hz
//   tooth_period_s      1 / tooth_passing_hz                          Process::delay_s
//   floquet_period_s    shortest repeat of the cutter (pitch, helix,  Process::floquet_period_s
//                       runout when the method sees it): the period
//                       multipliers and growth factors refer to
//   lobe                ⌊f_c / f_tp⌋ of the limit's chatter frequency  lobe_number
//   depth_limit, chatter_frequency, lobe, multiplier_type: of the limit (the lobe-table row);
//   spectral_radius, dominant_*: of the asked depth (PointReport::at_depth).
//
// Units: SI (m, s, Hz) inside the structs; the records (chatter/records.hpp)
// write mm and rev/min.
#pragma once

#include <complex>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "chatter/usual_bands.hpp"
#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/results.hpp"

namespace chatter {

/// Lobe number of a chatter frequency f_c at tooth-passing frequency f_tp
/// (Hz): k = ⌊f_c / f_tp⌋, the number of whole chatter waves per tooth
/// period — the k of ωτ = ε + 2πk (ε in (0, 2π)) of the transfer-function
/// lobes, and for every other method the same count. A flip (f_c = (k + ½)
/// f_tp) is lobe k; a fold or a frequency on a harmonic (f_c = k f_tp) is lobe
/// k: a ratio within 1e-9 (relative) of a whole number counts as that number,
/// so round-off never flips the number between neighbouring rows.
/// −1 when f_c is not a finite number >= 0 or f_tp is not > 0.
int lobe_number(double chatter_frequency_hz, double tooth_passing_hz);

/// The physical range of an asked operating point (docs/results.md): the
/// fastest spindles turn about 200 000 rev/min, and no cut is a metre deep,
/// so a value outside is a unit mistake (rev/s, µm), refused with the rule.
inline constexpr double kMaxSpindleRpm = 500000.0;
inline constexpr double kMaxDepthMm = 1000.0;
/// @throws InputError "<name> = x: must be > 0 rev/min" or "... at most
///         500000 rev/min (...)" when rpm is outside (0, kMaxSpindleRpm].
void check_spindle_rpm(double rpm, const std::string& name);
/// @throws InputError when depth_mm is outside (0, kMaxDepthMm] (`allow_zero`:
///         [0, kMaxDepthMm]).
void check_depth_mm(double depth_mm, const std::string& name, bool allow_zero = false);
/// The plausible band of a depth of cut, mm: thinner than a sharp edge's
/// radius, or deeper than any flute, is probably a unit slip (m, µm).
inline constexpr double kPlausibleDepthMm[2] = {usual::kDepthOfCutMm.lo, usual::kDepthOfCutMm.hi};
/// A sentence naming the likely unit slip of a depth outside
/// kPlausibleDepthMm, or "" inside it. report_point adds it to the point's
/// notes; `check` to its warnings.
std::string depth_unit_hint(double depth_mm);

/// What `chatter point` adds with spindle speed variation (docs/ssv.md): the
/// modulation, the principal period it was solved over, and the gain over
/// constant speed at the mean speed.
struct SpeedVariationGain {
  SpeedVariation asked;          ///< the modulation as given
  SpeedVariationPeriod period;   ///< speed_variation_period at the speed
  double constant_speed_limit_m = std::numeric_limits<double>::infinity();  ///< same method, R_VA = 0
  /// depth limit with SSV / at constant speed (> 1: SSV raises the limit);
  /// NaN when either limit is beyond the searched depth.
  double gain = std::numeric_limits<double>::quiet_NaN();
};

/// Everything `chatter point` reports (and Python's chatter.point, the C API's
/// chatter_point): the lobe-table row at the speed, the process's
/// frequencies, and the method's own analysis at the asked depth, each in
/// its own field (docs/results.md).
struct PointReport {
  std::string method;
  double spindle_rpm = 0.0;
  double depth_m = 0.0;      ///< the asked depth, m
  double depth_mm = 0.0;     ///< the asked depth as given, mm (echoed as is: docs/results.md)
  double depth_max_m = 0.0;  ///< the deepest cut searched for the limit
  /// The limit: exactly the lobe-table row at this speed (depth limit,
  /// chatter frequency and lobe of the limit, and the method's table
  /// columns, e.g. sdm's multiplier_type at the limit).
  DiagnosedLimit limit;
  std::vector<DiagnosticColumn> columns;  ///< the names of limit.values
  double tooth_passing_hz = 0.0;  ///< Process::tooth_passing_hz
  double tooth_period_s = 0.0;    ///< 1 / tooth_passing_hz
  /// The verdict at the asked depth: the method's own (at_depth.stable) when
  /// it has one, else depth < limit.
  bool stable = false;
  /// depth limit / asked depth (> 1: stable with that factor to spare);
  /// +inf when no limit lies below depth_max_m.
  double margin = std::numeric_limits<double>::infinity();
  PointAnalysis at_depth;  ///< the method's analysis at the asked depth
  /// With speed variation and a constant-speed solver given (report_point).
  std::optional<SpeedVariationGain> speed_variation;
  /// Sentences for the reader, e.g. when the method's verdict at the depth
  /// differs from the depth against the first limit (a stable island).
  std::vector<std::string> notes;
};

/// The report of one point: limit_with_diagnostics(rpm) (the table row),
/// analyse_point(rpm, depth), the process's frequencies. The depth is taken
/// in mm as the user gave it (the report echoes it unchanged). Cost: one
/// limit and one analysis. With speed variation, also the limit at constant
/// speed and the gain (PointReport::speed_variation): one more limit, by
/// `constant_speed` (the same method on process.at_constant_speed()) when
/// given, else, for sdm and time-domain, by a solver of the same method
/// built from the solver's own model, process at constant speed and options
/// (what every front end gets).
/// @pre rpm > 0, depth_mm > 0 (check_spindle_rpm, check_depth_mm).
PointReport report_point(const LobeSolver& solver, const Process& process, double spindle_rpm, double depth_mm,
                         const LobeSolver* constant_speed = nullptr);

}  // namespace chatter
