// The record of `chatter design-pitch` (chatter.design_pitch): the arguments
// checked once for both front ends (messages name the CLI's flags or
// Python's keywords: ArgStyle), the design (ops: chatter/pitch_design.hpp),
// its JSON record, its band table and its config fragment
// (docs/design_pitch.md; keys in docs/results.md style: mm, rev/min, deg).
//
// Layer: records (core + io + ops, nlohmann-json); see chatter/records.hpp.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "chatter/io/config.hpp"
#include "chatter/pitch_design.hpp"
#include "chatter/records.hpp"

namespace chatter {

/// The arguments in shop units, as the flags and keywords give them; empty =
/// not given (then the default, or the error "required").
struct PitchDesignArgs {
  std::optional<double> rpm_min, rpm_max;  ///< the band, rev/min (required)
  std::optional<int> teeth;                ///< must equal the config's teeth (a check of the cutter meant)
  int rpm_points = kDefaultPitchBandPoints;
  std::optional<double> depth_max_mm;      ///< default: sweep.depth_max_mm, else kDefaultSearchDepthMm
  std::string family = "linear";           ///< "linear" or "alternating"
  double min_pitch_ratio = kDefaultMinPitchRatio;
  int scan_points = kDefaultPitchScanPoints;
  std::string method = "sdm";
  SolverValues solver_options;             ///< already checked against the method's options
  unsigned threads = 0;
};

/// The design options from the config and the arguments, every argument
/// checked: the band (both given, each in (0, 500000] rev/min, rpm_max >
/// rpm_min), teeth (>= 2 and the config's), depth (0, 1000] mm, the
/// family, the ratio, the counts, the method; the config milling with equal
/// pitch (design_pitch's own refusals, before any solve).
/// @throws InputError naming the argument and the rule.
PitchDesignOptions pitch_design_options(const Config& config, const PitchDesignArgs& args, ArgStyle style);

/// The design with its refusals named as the front end names them
/// (design_pitch's InputError about depth_max_m gets `depth_max_mm` /
/// `--depth-max-mm`). @throws InputError.
PitchDesign run_pitch_design(const Config& config, const PitchDesignOptions& options, ArgStyle style);

/// `chatter design-pitch --json`: format "chatter-pitch-design", the inputs,
/// method, family, pitch_angles_deg (designed), equal/start/designed each
/// {step_deg, pitch_angles_deg, worst_limit_mm (null = none below
/// depth_max_mm), worst_rpm}, the rule {spindle_rpm, chatter_frequency_hz,
/// step_deg (as the formula gives it), clipped}, step_max_deg, gain,
/// gain_is_lower_bound, evaluated [{step_deg, worst_limit_mm}], the band
/// table {spindle_rpm, depth_limit_equal_mm, depth_limit_designed_mm},
/// on_min_pitch_bound and chip_load_ratio (below).
nlohmann::json pitch_design_record(const PitchDesign& d, const PitchDesignOptions& options,
                                   const RecordSource& source);

/// True when the designed step is the largest the minimum-pitch ratio allows
/// (step_max_rad): the design sits on that bound, and a better one may lie
/// beyond it.
bool on_min_pitch_bound(const PitchDesign& d);
/// The largest over the smallest designed pitch angle: the ratio of the
/// teeth's chip loads (a tooth's chip is the feed over the pitch in front of
/// it, at the mean feed per tooth times pitch / equal pitch).
double chip_load_ratio(const PitchDesign& d);

/// CSV: spindle_rpm,depth_limit_equal_mm,depth_limit_designed_mm (one row
/// per band speed; a limit above the searched depth prints as inf).
std::string pitch_design_csv(const PitchDesign& d);

/// The [process] fragment: a comment and `pitch_angles_deg = [...]` (12
/// significant digits: 60, not 59.999999999999993; summing to 360 within
/// the config's 0.001°).
std::string pitch_design_fragment(const PitchDesign& d, const std::string& config_name);

/// A few lines for a person: angles, worst limits, gain, the rule.
std::string pitch_design_summary(const PitchDesign& d);

}  // namespace chatter
