// The measurements file of `chatter adapt --measurements` (docs/optimization.md):
// what the machine's sensors (or an inspection) gave at each iteration of the
// adaptive loop.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/optimization_problem.hpp"

namespace chatter {

/// A CSV file: a header naming its columns, each an index of the operation
/// (optimization_problem.hpp's index_name: diametral_error_um or
/// surface_location_error_um, surface_roughness_um, removal_rate_mm3_per_s,
/// cost, production_rate_per_h, force_n) or `iteration` (1, 2, ... in order;
/// optional), then one row per iteration. An empty cell: not measured (the
/// model's value is used and its correction kept). Blank lines and lines
/// starting with '#' are skipped; CR line ends are accepted. Row i (0-based)
/// is the measurement of iteration i + 1, NaN where not measured.
/// @throws InputError "<origin>:<line>: <rule>": no header, an unknown or
///         repeated column, a row with another number of fields, a value that
///         is not a finite number > 0, iterations out of order, no rows.
std::vector<IndexValues> parse_measurements(std::string_view text, const std::string& origin, Operation operation);
/// Same, from a file. @throws InputError also if it cannot be read.
std::vector<IndexValues> read_measurements(const std::filesystem::path& file, Operation operation);

}  // namespace chatter
