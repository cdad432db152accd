// Lobe tables as CSV and JSON (the contract CAM integrators parse).
//
// CSV: header `spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe` then one
// row per speed; a speed with no instability below the searched depth has
// `inf` as depth and empty frequency and lobe. Numbers use up to 10
// significant digits; the output is byte-identical for identical input.
//
// JSON: {"format": "chatter-lobe-table", "version", "method", "config",
// "warnings" (the config's plausibility warnings, [] if none), "options", "absolute_limit", "rows": [{spindle_rpm, depth_limit_mm,
// chatter_frequency_hz, lobe}]}, with null where the CSV is `inf`/empty.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "chatter/io/config.hpp"
#include "chatter/lobes.hpp"

namespace chatter {

/// A method-specific column after the four standard ones (e.g. sdm's
/// multiplier_type). One entry per row; numeric columns are written as
/// numbers in the JSON (an empty entry: null), others as strings.
struct ExtraColumn {
  std::string name;
  std::vector<std::string> values;
  bool numeric = false;
};

/// What produced a table, recorded in the JSON.
struct TableProvenance {
  std::string method;                 ///< "analytic", "coupled", ...
  const Config* config = nullptr;     ///< model, process and file (may be null)
  double rpm_min = 0.0, rpm_max = 0.0;
  int rpm_points = 0;                 ///< even: the row count; adaptive: the most rows allowed
  std::string rpm_spacing = "even";   ///< "even" or "adaptive" (speeds placed where the envelope bends)
  double adaptive_depth_rel_tol = 0.0;  ///< adaptive only: the midpoint tolerance (relative depth)
  bool adaptive_tolerance_met = false;  ///< adaptive only: met on every interval within rpm_points
  double depth_max_mm = 0.0;
  std::optional<AbsoluteLimit> absolute_limit;
  std::string options_json = "{}";    ///< solver options as a JSON object text
  std::vector<std::string> notes;     ///< what the method does not see of the cutter (ignored_feature_notes)
  /// The tool position the table is for (`--position-mm`, mm; docs/position.md):
  /// written as "position_mm" when set, absent otherwise.
  std::optional<double> position_mm;
};

/// @pre every extra column has rows.size() values.
void write_lobe_csv(std::ostream& os, const std::vector<StabilityLimit>& rows,
                    const std::vector<ExtraColumn>& extra = {});
void write_lobe_json(std::ostream& os, const std::vector<StabilityLimit>& rows, const TableProvenance& p,
                     const std::vector<ExtraColumn>& extra = {});

/// A number as the tables print it (up to 10 significant digits; "inf").
std::string table_number(double x);

/// Writes several files all-or-nothing: each text goes first to a temporary
/// file beside its target, and the targets are replaced only once every
/// temporary is complete. On failure no target is created or changed.
/// @throws InputError naming the path that cannot be written.
void write_text_files(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

/// write_text_files with one file.
void write_text_file(const std::filesystem::path& path, const std::string& text);

/// Library version, "MAJOR.MINOR.PATCH".
std::string version();

}  // namespace chatter
