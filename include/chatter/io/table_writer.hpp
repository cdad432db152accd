// Lobe tables as CSV (the contract CAM integrators parse; the JSON record:
// chatter/records/lobes.hpp lobe_table_record).
//
// CSV: header `spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe` then one
// row per speed; a speed with no instability below the searched depth has
// `inf` as depth and empty frequency and lobe. Numbers use up to 10
// significant digits; the output is byte-identical for identical input.

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


/// @pre every extra column has rows.size() values.
void write_lobe_csv(std::ostream& os, const std::vector<StabilityLimit>& rows,
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
