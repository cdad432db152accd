// The records of the forced response (docs/forced.md): the one place its
// JSON object and its tables are written, for `chatter forced`, `chatter
// sle`, `chatter check`'s forced column, Python (chatter.forced converts the
// same record) and
// the C API (the same numbers in a struct). Shop units at this edge: µm,
// mm, rev/min, N.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/lobes.hpp"
#include "chatter/records/columns.hpp"
#include "chatter/results.hpp"  // ForcedResponse, ShaftDeflection: plain data

namespace chatter {

/// What the JSON object says besides the response.
struct ForcedRecordContext {
  std::string config;                 ///< the config's name
  std::vector<std::string> warnings;  ///< its plausibility warnings
  std::optional<double> position_mm;  ///< the tool position, when one was given
  /// Milling: the radial immersion a_e/D the response is for.
  std::optional<double> radial_immersion;
  /// The sdm depth limit at the speed (depth_limit_mm), when computed.
  std::optional<StabilityLimit> limit;
};

/// The JSON object of `chatter forced --json` (keys: docs/forced.md):
/// config, warnings, [position_mm], operation, spindle_rpm, depth_mm,
/// feed_per_tooth_mm (milling) or feed_mm_per_rev (turning),
/// [radial_immersion], stable, spectral_radius, [depth_limit_mm], method,
/// period_s, harmonics, surface_location_error_um,
/// surface_location_error_range_um {min, max}, peak_to_peak_um {x, y},
/// static_deflection_um {x, y}, mean_force_n {x, y},
/// min_chip_thickness_um, negative_chip_arc_deg, negative_chip_fraction,
/// teeth_leave_cut, linear_limit_holds, diametral_error_um (turning), and
/// wall_profile {z_mm, sle_um} (milling). Unstable: the response numbers
/// are null. The CLI prints it, Python converts it (to_python), as every
/// record of the records layer.
nlohmann::json forced_record(const ForcedResponse& r, const ForcedRecordContext& context);

/// chatter.forced's result: forced_record's fields and, when `with_path`
/// and the cut is a stable milling cut, the group "path" (time_s, rel_x_um,
/// rel_y_um, wall_normal_um: the tool path over one period, the columns of
/// forced_path_csv at full precision).
ColumnRecord forced_columns(const ForcedResponse& r, const ForcedRecordContext& context, bool with_path);

/// What chatter.sle's columns do not hold.
struct SleContext {
  std::string config;                 ///< the config's name
  double depth_mm = 0.0;              ///< the axial (milling) or radial (turning) depth
  double feed_mm = 0.0;               ///< per tooth (milling) or per revolution (turning)
  std::string feed_key;               ///< Process::feed_record_key(): which of the two
  std::optional<double> position_mm;  ///< the tool position, when one was given
};
/// chatter.sle's result: fields config, depth_mm, <feed_key>, [position_mm];
/// columns spindle_rpm, surface_location_error_um, peak_to_peak_x_um,
/// peak_to_peak_y_um, min_chip_thickness_um (NaN where the cut is unstable:
/// sle_table_csv's empty cells), stable, teeth_leave_cut (booleans).
ColumnRecord sle_columns(const std::vector<ForcedResponse>& rows, const SleContext& context);

/// The `forced` object of one `chatter check --json` operation (issue 27,
/// docs/operations.md): stable, surface_location_error_um (milling) or
/// diametral_error_um (turning), peak_to_peak_um {x, y},
/// min_chip_thickness_um, teeth_leave_cut, linear_limit_holds, max_error_um
/// (null without a tolerance) and within_tolerance (null when the cut is
/// unstable: no steady error to hold against a tolerance).
nlohmann::json forced_check_record(const ForcedResponse& r, std::optional<double> max_error_m,
                                   std::optional<bool> within_tolerance);

/// The tool path over one period as CSV:
/// time_s,rel_x_um,rel_y_um,wall_normal_um (empty table when not recorded).
std::string forced_path_csv(const ForcedResponse& r);

/// The SLE table of `chatter sle`, one row per speed:
/// spindle_rpm,surface_location_error_um,peak_to_peak_x_um,peak_to_peak_y_um,min_chip_thickness_um,stable
/// (stable 1 or 0; the numbers empty where the cut is unstable).
std::string sle_table_csv(const std::vector<ForcedResponse>& rows);

/// The diametral error along a turned part (`chatter forced --along-shaft`):
/// position_mm,force_n,deflection_x_um,deflection_y_um,diametral_error_um
/// (position_mm as typed, one per row).
std::string shaft_table_csv(const std::vector<double>& positions_mm, const std::vector<ShaftDeflection>& rows);

}  // namespace chatter
