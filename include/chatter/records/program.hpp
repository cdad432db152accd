// `chatter program`: a whole NC program checked block by block
// (docs/program.md): the stock simulated along the toolpath gives each feed
// move its engagement (turning: depth of cut and position along the bar;
// milling: axial depth and the engaged arc from a Z-map), the cut goes to
// the registry's method for the tool (`auto`, built by configure_solver as
// every command's) for the depth limit `chatter point` gives for the same
// cut, the cutting law for power, torque and force, the forced response for
// the part error; then one record (JSON, CSV) and, on request, the program
// annotated and fixed (--out, --fix-speed, --fix-feed).
//
// The cache: every solve is keyed by what the limit depends on — tool,
// spindle speed, engaged arc (milling) or position (turning), the same
// numbers the row reports — so a cached answer is the answer for the row's
// reported cut, bit for bit (tests/test_program.cpp runs a program with the
// cache on and off). The measurement, not the cache, is quantised: arcs to
// kArcStepDeg, turning positions to the bar's cells, G96 speeds to 1 rev/min.
//
// Layer: records (it reads a Job from io, builds solvers as the front ends
// do, and returns the record every front end hands on).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "chatter/io/job.hpp"
#include "chatter/io/plot_program.hpp"
#include "chatter/toolpath.hpp"

namespace chatter {

/// Engaged arcs are reported (and solved) on this grid, degrees.
inline constexpr double kArcStepDeg = 0.5;

struct ProgramOptions {
  unsigned threads = 1;           ///< solves in parallel (0 = every core); the record does not depend on it
  bool fix_speed = false;         ///< suggest (and with --out write) a robust stable speed per unstable block
  bool fix_feed = false;          ///< scale an overloaded block's feed to the machine's power and torque
  std::optional<bool> cache;      ///< override JOB.toml's [program] cache
  std::function<void(double)> progress;  ///< fraction done, from worker threads; may be empty
};

/// One feed move: the worst sample of the block (the smallest margin), the
/// load columns the block's peak. NaN = not defined (air, unstable, no feed).
struct ProgramRow {
  int line = 0, tool = 0;
  bool air = true;
  double spindle_rpm = 0.0;
  double feed = 0.0;                   ///< per tooth (milling) or per revolution (turning), mm
  double axial_depth_mm = 0.0;         ///< milling
  double radial_depth_mm = 0.0;        ///< milling: R (cos entry − cos exit)
  double entry_angle_deg = 0.0, exit_angle_deg = 0.0;  ///< milling: the first arc's entry, the last arc's exit
  std::vector<std::pair<double, double>> arcs_deg;     ///< milling: every engaged arc (one unless split)
  double depth_mm = 0.0;               ///< depth of cut (turning); the axial depth (milling)
  double position_mm = 0.0;            ///< turning: from the clamp
  double diameter_mm = 0.0;            ///< turning: the bar's diameter where it cuts
  double removal_rate_mm3_per_s = 0.0, power_kw = 0.0, torque_nm = 0.0, force_n = 0.0;
  double depth_limit_mm = 0.0;         ///< +inf: none below the searched depth
  double margin = 0.0;                 ///< limit / depth
  bool stable = true;
  double chatter_frequency_hz = 0.0;
  double part_error_um = 0.0;          ///< milling: SLE (signed); turning: diametral error
  bool overloaded = false;
  double length_mm = 0.0, time_s = 0.0;
  std::vector<std::string> notes;      ///< facing, plunge, two arcs merged, ...
  std::optional<double> fixed_rpm;     ///< --fix-speed's speed (robust over ± the speed tolerance)
  std::optional<double> fixed_feed;    ///< --fix-feed's F word (program units of the block)
  double original_feed = 0.0;          ///< the block's own F word (program units), restored after a fixed one
  std::string fix_note;                ///< why a block could not be fixed
  Eigen::Vector3d start{0, 0, 0}, end{0, 0, 0};  ///< mm, for the plots
  /// Turning, for the plot (not in the record): every sample of the block
  /// along the bar — position from the clamp (mm), margin, diametral error
  /// (µm; NaN where unstable).
  struct AlongBar {
    double position_mm = 0.0, margin = 0.0, part_error_um = 0.0;
  };
  std::vector<AlongBar> along_bar;
};

struct ProgramSummary {
  std::size_t blocks = 0, cutting_blocks = 0, air_blocks = 0, unstable_blocks = 0, overloaded_blocks = 0;
  double worst_margin = 0.0;           ///< over cutting blocks (+inf when none is bounded)
  int worst_line = 0;
  double removed_volume_mm3 = 0.0, cutting_time_s = 0.0;
  std::size_t solves = 0, cache_hits = 0;  ///< limit solves made, and samples answered from the cache
};

struct ProgramReport {
  std::string program, job;
  bool turning = false;
  std::vector<ProgramRow> rows;
  ProgramSummary summary;
  std::vector<std::string> warnings;
  std::vector<std::pair<int, double>> depth_max_mm;  ///< per tool: the deepest cut searched (`point --depth-max-mm`)
  std::vector<std::pair<int, std::string>> methods;  ///< per tool: the method `auto` resolved to
  bool ok() const { return summary.unstable_blocks == 0 && summary.overloaded_blocks == 0; }
};

/// Checks `path` against `job`. @throws InputError naming the line: a T
/// word with no tool in the job (the interpreter's message), a cutting move
/// with no tool or the spindle stopped, a speed outside the machine's range;
/// a program that never cuts the stock.
ProgramReport check_program(const Job& job, const Toolpath& path, const ProgramOptions& options);

/// The whole command: reads `program` with LinuxCNC's interpreter, the
/// job's tools as its tool table (milling: the diameter; turning: twice the
/// nose radius, for G41/G42), then check_program. What the CLI and Python run.
/// @throws InputError as read_nc_program and check_program.
ProgramReport run_program(const std::filesystem::path& program, const Job& job, const ProgramOptions& options);

/// The record (docs/program.md "The record"): rows, summary, warnings.
nlohmann::json program_record(const ProgramReport& report);
/// The plot's data: blocks along the cutting time, the toolpath or the bar.
ProgramPlotData program_plot_data(const ProgramReport& report, double max_power_kw = 0.0);
/// The rows as CSV, the record's columns.
std::string program_csv(const ProgramReport& report);
/// The program text with a comment on every unstable or overloaded block
/// and, where the report has them, the fixed S and F words (the old value
/// restored on a block of its own after it).
std::string annotate_program(const std::string& program_text, const ProgramReport& report);

}  // namespace chatter
