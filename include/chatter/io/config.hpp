// TOML configuration: the structural model, the process and sweep defaults.
// The key reference is docs/config.md. Paths in messages are as given.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"  // SolverValue
#include "chatter/optimization_problem.hpp"
#include "chatter/position.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"
#include "chatter/uncertainty.hpp"

namespace chatter {

/// Defaults for the CLI sweep flags ([sweep] table); every field optional.
struct SweepDefaults {
  std::optional<double> rpm_min;       ///< rev/min.
  std::optional<double> rpm_max;       ///< rev/min.
  std::optional<int> rpm_points;       ///< number of evenly spaced speeds, both ends included.
  std::optional<double> depth_max_mm;  ///< deepest cut searched, mm.
};

struct Config {
  std::string name;                 ///< `name`, or the file stem when absent.
  std::filesystem::path source;     ///< the file it was read from (empty if parsed from text).
  StructuralModel model;
  Process process = Process::turning({1.0});
  SweepDefaults sweep;
  /// Feed (mm) for the static chip of the time-domain simulation:
  /// `[process] feed_per_rev_mm` (turning) or `feed_per_tooth_mm` (milling);
  /// absent: the command line's default (0.1 mm).
  std::optional<double> feed_mm;
  /// Plausibility warnings: values that load but lie outside what machining
  /// usually sees (a cutting coefficient 1e6 below metals, a stiffness of
  /// 20 N/m, ...), each "<file>: <key path> = <value>: <what is odd; the
  /// likely mistake>". Bands and reasons: docs/config.md. Empty for every
  /// shipped config. The CLI prints them on stderr, records them in its JSON
  /// and, with --strict, refuses the config.
  std::vector<std::string> warnings;
  /// Usable flute length of the milling cutter, m (`[process]
  /// flute_length_mm`, milling only, > 0): `recommend` never proposes a
  /// deeper cut, `check` warns about one. Absent: not known.
  std::optional<double> flute_length_m;
  /// How the structure changes along the tool path (docs/position.md): the
  /// `cantilever` workpiece modes (scaled by the bar's first mode shape), or
  /// the `[[positions]]` mode sets; empty when neither. With `[[positions]]`,
  /// `model` is the set of the first position (what the commands use when
  /// no position is given); with a cantilever, `model` is the free end.
  PositionDependence position;
  /// `[uncertainty]`: relative 1σ spreads of the modes and the cutting
  /// coefficients for `chatter lobes --samples` (docs/uncertainty.md), as
  /// fractions, checked against `model` (the first [[positions]] set, whose
  /// mode count every set shares) and `process`; absent without the table.
  std::optional<UncertaintySpreads> uncertainty;
  /// `[optimization]`: the objective, bounds, loss, constraints and index
  /// models of `chatter performance`, `optimize` and `adapt`
  /// (docs/optimization.md); absent without the table.
  std::optional<OptimizationSpec> optimization;
  /// The `[process]` table exactly as written, key by key (in key order)
  /// (numbers as parsed: they write back as the shortest decimal that reads
  /// the same, so `helix_angle_deg = 30` is echoed as 30; arrays of numbers
  /// as lists; other values as text). The records echo it (docs/results.md).
  std::vector<std::pair<std::string, SolverValue>> process_given;
};

/// The structure the tool sees at `position_m` (m from the clamp of a
/// cantilever workpiece, or along the path of `[[positions]]`): see
/// chatter::model_at_position (include/chatter/position.hpp). The one place
/// the CLI, the C API and other front ends map a position to a model.
/// Cost: O(modes). @throws InputError "<file>: ..." when the config has no
/// position-dependent model, or the position is outside it.
StructuralModel model_at_position(const Config& config, double position_m);

/// The position range of a position-dependent config for messages, mm:
/// "[0, 500] mm (clamp to free end of workpiece.modes[0].cantilever)" or
/// "[10, 90] mm (first to last [[positions]])". @pre !config.position.empty().
std::string position_range_text(const Config& config);

/// A position typed in mm (`name` = `position_mm`: "--position-mm" in the
/// CLI, "position_mm" in the C API and Python) as m, checked against the
/// config's range; an end typed in mm snaps to the end in m (they differ by
/// rounding only). Cost: O(1).
/// @throws InputError "<name>: <file>: the structure does not depend on the
///         position: ..." or "<name> = 600: outside the part [0, 500] mm (...)".
double position_m(const Config& config, double position_mm, const std::string& name);

/// The config with `model` replaced by the structure at `position_mm` (mm):
/// what `--position-mm` gives every command, and `position_mm` the C API and
/// Python. Messages name `name` as position_m() does, and the file.
/// Cost: a copy of the config plus O(modes).
Config config_at_position(const Config& config, double position_mm, const std::string& name);

/// The positions of a lobe surface (`chatter surface`): `points` evenly
/// spaced from min_mm to max_mm, both included, in mm as typed (the table's
/// `position_mm` column; the last exactly max_mm) and in m for the model (the
/// ends exactly the checked ends). Absent ends: the ends of the part.
struct SurfacePositions {
  std::vector<double> mm;
  std::vector<double> m;
};
/// Names of the three arguments in messages ("--position-min-mm", ... in
/// the CLI; "position_min_mm", ... in the C API and Python).
struct SurfacePositionNames {
  std::string min = "position_min_mm", max = "position_max_mm", points = "position_points";
};
/// @throws InputError when the config does not depend on the position ("<file>:
///         surface: the structure does not depend on the position: ..."), an
///         end is outside the part (position_m), max <= min, or points < 2.
SurfacePositions surface_positions(const Config& config, std::optional<double> min_mm, std::optional<double> max_mm,
                                   int points, const SurfacePositionNames& names = {});

/// Reads and validates a config file. Quantities may be given in SI or in
/// the shop-unit key beside it (`stiffness_n_per_um`, `mass_g`,
/// `tangential_coefficient_n_per_mm2`, ...; one key per quantity); the
/// Config holds SI. Cost: linear in the file, plus reading measured FRFs.
/// @throws InputError on any bad input: unreadable file, syntax error
///         ("<file>:<line>:<col>: <TOML syntax error>"), unknown or missing
///         key, wrong type, non-physical value. Every error of the file is
///         reported (up to 20, then a count), one per line, each
///         "<file>: <key path> = <value>: <rule>" or "<file>: <key path>: <rule>".
Config load_config(const std::filesystem::path& file);

/// Same, from TOML text; `origin` names the source in messages.
Config parse_config(const std::string& toml_text, const std::string& origin);

}  // namespace chatter
