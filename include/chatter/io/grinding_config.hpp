// Grinding configs: a TOML file with a [grinding] table (the wheel, the
// kinematics, seed 001's mechanistic model and/or seed 000's empirical
// models) and, for `chatter grind simulate`, the robot's modes in [tool]
// (and [workpiece]). Key reference: docs/grinding.md and docs/config.md,
// "[grinding]".
//
// A config is a cutting-process config ([process]: turning or milling, read
// by load_config) or a grinding config ([grinding], read here), never both:
// [grinding] decides. load_config refuses a grinding config with one message
// naming the grinding readers; load_grinding_config refuses [process],
// [sweep], [[positions]] and [uncertainty]. Both share the reader: the same
// messages (<file>: <key path> = <value>: <rule>), every error at once, the
// same plausibility warnings (values that load but are unusual; the CLI's
// --strict refuses them).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/grinding.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

struct GrindingConfig {
  std::string name;                ///< `name`, or the file stem.
  std::filesystem::path source;    ///< the file it was read from (empty if parsed from text).
  grinding::Process process;       ///< [grinding] in SI.
  /// [tool] and [workpiece] modes (the robot holding the wheel, the part):
  /// rigid when absent; only `chatter grind simulate` reads them.
  StructuralModel robot;
  /// Plausibility warnings, "<file>: <key path> = <value>: <what is odd>".
  std::vector<std::string> warnings;
};

/// Reads and validates a grinding config. @throws InputError listing every
/// error of the file (up to 20), as load_config does.
GrindingConfig load_grinding_config(const std::filesystem::path& file);

/// Same, from TOML text; `origin` names the source in messages.
GrindingConfig parse_grinding_config(const std::string& toml_text, const std::string& origin);

}  // namespace chatter
