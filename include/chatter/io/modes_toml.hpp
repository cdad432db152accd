// Writes fitted modes (modal_fit.hpp) as a fragment of a chatter TOML config.
// Reference: docs/frf.md ("Modal fit"), docs/config.md.
#pragma once

#include <string>
#include <vector>

#include "chatter/structural_model.hpp"

namespace chatter {

/// A TOML fragment with one `[[<body>.modes]]` block per mode
/// (frequency_hz, damping_ratio, stiffness_n_per_m, direction), 10
/// significant digits, that the config loader accepts (docs/config.md).
/// `comment` (may be several lines) goes first, each line prefixed by `# `.
/// Cost O(modes).
/// @throws InputError if body is not "tool" or "workpiece".
std::string modes_to_toml(const std::vector<Mode>& modes, const std::string& body = "tool",
                          const std::string& comment = "");

/// One key of an `[uncertainty]` table (docs/uncertainty.md): 1σ spreads in
/// percent of the value, one number or (list = true) one per mode.
struct UncertaintyKey {
  std::string key;               ///< e.g. "frequency_percent"
  std::vector<double> percent;   ///< finite, >= 0
  bool list = false;             ///< write as an array even with one value
};

/// An `[uncertainty]` table commented out so that a user opts in: `comment`
/// lines as `# ...`, then `#[uncertainty]` and one `#key = value` line per
/// key (4 significant digits). Removing the `#` in front of `[` and of each
/// key line gives a table the config loader reads. Cost O(values).
std::string commented_uncertainty_toml(const std::vector<UncertaintyKey>& keys, const std::string& comment);

/// The largest spread (percent) `[uncertainty]` accepts for any parameter,
/// just inside its rule 3 s < 1 (33.3 %); for a damping ratio ζ also
/// ζ (1 + 3 s) < 1. `percent` itself when it is allowed.
double allowed_spread_percent(double percent, double damping_ratio = 0.0);

}  // namespace chatter
