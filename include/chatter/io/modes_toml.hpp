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

}  // namespace chatter
