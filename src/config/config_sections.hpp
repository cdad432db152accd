// Internal (not installed): the section readers of the TOML config reader,
// one file each, called by read_config (src/config/config.cpp) in this order:
// process, tool and workpiece, positions, sweep, then (only when everything
// above read without errors) uncertainty and optimization; after the errors, the warnings
// that need the whole config (warn_frequency_vs_speeds). Each reader records
// its errors on the Document and throws Skip to abandon its table
// (config_read.hpp explains the pattern; a new section is one more file and
// one more declaration here). Key reference: docs/config.md. A grinding
// config ([grinding]) is read by read_grinding_config (config.cpp) instead:
// [grinding], then [tool] and [workpiece] (the robot's modes).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/grinding.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/job.hpp"
#include "config_read.hpp"

namespace chatter::config_detail {

// config_include.cpp
/// A file merged in by `include`: its name as written (relative names joined
/// to the including file's directory), its text as parsed (for messages) and
/// the key paths it gave.
struct IncludedFile {
  std::string origin;
  std::string text;
  std::vector<Path> paths;
};
/// Reads and parses one file (the reader's own parsing: sanitised, NUL
/// refused), setting `text` to the text parsed. @throws InputError.
using ParseFile = std::function<toml::table(const std::filesystem::path& file, std::string* text)>;
/// Merges the files named by `root`'s top-level `include` (and the files
/// they include) into `root` and removes the key; `origin` is the file
/// `root` was read from (relative names are relative to its directory).
/// @throws InputError: a bad `include` value, an unreadable file, a cycle,
///         a key given in two files (both named).
std::vector<IncludedFile> merge_includes(toml::table& root, const std::string& origin, const ParseFile& parse);

// config_job.cpp
/// JOB.toml as read, before the tool configs are loaded (load_job in
/// config.cpp does that, naming each tool's key path).
struct JobText {
  struct Tool {
    int number = 0;
    std::string config;  ///< as written
    Path path;           ///< tools[i].config, for messages
  };
  JobStock stock;
  JobMachine machine;
  std::vector<Tool> tools;
  bool has_workpiece = false;
  Body workpiece;
  std::vector<CantileverModeRef> cantilever;
  double speed_tolerance = 0.02;
  bool cache = true;
  std::optional<double> default_spindle_rpm;
};
JobText read_job(const toml::table& root_table, const Document& doc);

// config_process.cpp
/// `[process]`: turning or milling (with the real-cutter keys). Also sets the
/// feed (`feed_per_rev_mm` / `feed_per_tooth_mm`) and the flute length when given.
Process read_process(const Table& root, std::optional<double>* feed_mm, std::optional<double>* flute_length_m);

// config_kienzle.cpp
/// `[process] force_law` of turning: nullopt for "linear" (the default; the
/// Kienzle keys refused), else Kienzle's law from specific_force_n_per_mm2
/// and exponent, linearised at `feed_mm` (required with it). Errors recorded;
/// Skip when the law is asked for but cannot be built.
std::optional<KienzleLaw> read_kienzle(const Table& process, std::optional<double> feed_mm);

// config_cutter.cpp
/// The milling cutter's shape along its axis (cutter_geometry,
/// corner_radius_mm, [[process.profile]], profile_slices) and K_a
/// (axial_force_coefficient_n_per_m2) into `p`; errors recorded.
void read_cutter(const Table& process, std::optional<double> diameter_mm, MillingParameters* p);

// config_speed_variation.cpp
/// `[process] speed_variation = { amplitude_ratio, frequency_ratio }`: both
/// required together; nullopt when absent (errors recorded, Skip on errors).
std::optional<SpeedVariation> read_speed_variation(const Table& process);

// config_structure.cpp
/// `[tool]` / `[workpiece]`: modes (given, or from a cantilever bar) and
/// measured FRF terms; absent, or without `modes`, means rigid.
Body read_body(const Table& root, std::string_view name);
/// The cantilever workpiece modes of a config read without errors: their
/// index in model.workpiece.modes and their bar length (m).
std::vector<CantileverModeRef> cantilever_refs(const toml::table& root_table);

// config_positions.cpp
/// `[[positions]]`: mode sets along the path; `top` is the model of the
/// top-level [tool] and [workpiece].
std::vector<PositionStation> read_positions(const Table& root, const StructuralModel& top);

// config_sweep.cpp
/// `[sweep]`: defaults for the CLI sweep flags.
SweepDefaults read_sweep(const Table& root);
/// Warns about modes the [sweep] speeds cannot excite in a usual lobe.
void warn_frequency_vs_speeds(const toml::table& root_table, const Document& doc, const Config& config);

// config_uncertainty.cpp
/// `[uncertainty]`: spreads checked against the model and process read.
std::optional<UncertaintySpreads> read_uncertainty(const Table& root, const StructuralModel& model,
                                                   const Process& process);

// config_optimization.cpp
/// `[optimization]`: the objective, bounds, loss, constraints and index
/// models of performance / optimize / adapt, checked against the process read.
std::optional<OptimizationSpec> read_optimization(const Table& root, const Process& process);

// config_grinding.cpp
/// `[grinding]` of a grinding config (include/chatter/io/grinding_config.hpp):
/// the wheel, kinematics and models, in SI.
grinding::Process read_grinding(const Table& root);

}  // namespace chatter::config_detail
