// The records of `chatter compare`, `chatter map` and `chatter frf`: each
// command's work from a loaded config to its table and JSON record, built
// once here for the CLI (src/cli/cmd_compare.cpp, cmd_map.cpp, cmd_frf.cpp)
// and Python (python/bind_tables.cpp). Messages name arguments as the caller
// does (ArgStyle: the CLI's flags, Python's keywords). Keys: docs/results.md.
//
// Layer: records (core + io + ops, nlohmann-json); see chatter/records.hpp.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/io/config.hpp"
#include "chatter/io/plot.hpp"  // MethodLimits, StabilityMapGrid: plain data
#include "chatter/io/table_writer.hpp"  // ExtraColumn
#include "chatter/uncertainty.hpp"
#include "chatter/lobes.hpp"
#include "chatter/records.hpp"
#include "chatter/records/columns.hpp"
#include "chatter/solvers.hpp"

namespace chatter {

class SemiDiscretizationSolver;

// --------------------------------------------------------------- lobe table

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
  nlohmann::json options;             ///< the solver's effective options (an object; null: {})
  std::vector<std::string> notes;     ///< what the method does not see of the cutter (ignored_feature_notes)
  /// The tool position the table is for (`--position-mm`, mm; docs/position.md):
  /// written as "position_mm" when set, absent otherwise.
  std::optional<double> position_mm;
};
/// The JSON record of a lobe table ("chatter-lobe-table"): {"format",
/// "version", "method", "config" (file, name, process as read with the
/// [process] keys as written, tool and workpiece modes), "warnings" (the
/// config's plausibility warnings, [] if none), "notes", ["position_mm"],
/// "sweep", "options", ["absolute_limit"], "units", "null_means", "rows":
/// [{spindle_rpm, depth_limit_mm, chatter_frequency_hz, lobe, extra
/// columns}]}, null where the CSV is `inf`/empty; numbers rounded as the CSV.
/// @pre every extra column has rows.size() values.
nlohmann::json lobe_table_record(const std::vector<StabilityLimit>& rows, const TableProvenance& p,
                                 const std::vector<ExtraColumn>& extra = {});

/// What the uncertainty block of `lobes --samples` says besides the spreads.
struct UncertaintyRecordInputs {
  std::uint64_t samples = 0, seed = 1;
  int depth_points = 0;
  double depth_grid_top_mm = 0.0;
  std::string summary;  ///< one line for the machinist
};
/// The "uncertainty" object of the lobe table's record (docs/uncertainty.md):
/// samples, seed, spreads in percent (milling: K_t and K_r; turning: K_f),
/// the distribution, the generator, the quantile definition and columns,
/// the probability grid and the summary.
nlohmann::json uncertainty_record(const UncertaintySpreads& s, bool milling, const UncertaintyRecordInputs& in);

// ------------------------------------------- the lobe tables as columns (Python)

/// What a lobe table's columns do not hold: the method, the config's name
/// and warnings, the method's notes, the depth searched (mm).
struct LobeColumnsSource {
  std::string method;
  const Config* config = nullptr;  ///< name and warnings (null: none)
  std::vector<std::string> notes;
  double depth_max_mm = 0.0;
};
/// Its fields: method, name, warnings, notes, depth_max_mm.
nlohmann::json lobe_columns_fields(const LobeColumnsSource& source);

/// The lobe table as columns (chatter.lobes; the CSV's columns, full
/// precision): spindle_rpm, depth_limit_mm (+inf where no limit below the
/// searched depth), chatter_frequency_hz (NaN there), lobe (−1 there), then
/// each diagnostic column: numbers (NaN where none) or text ("" where none).
/// Fields: lobe_columns_fields. @pre values is empty or has rows.size() rows.
ColumnRecord lobe_columns(const std::vector<StabilityLimit>& rows, const std::vector<DiagnosticColumn>& diagnostics,
                          const std::vector<std::vector<SolverValue>>& values, const LobeColumnsSource& source);

/// The lobe surface as columns (chatter.surface), one row per (position,
/// speed), positions outer: position_mm, then lobe_columns' four.
/// @pre positions_mm.size() == rows.size().
ColumnRecord surface_columns(const std::vector<double>& positions_mm,
                             const std::vector<std::vector<StabilityLimit>>& rows, const LobeColumnsSource& source);

/// Monte Carlo lobes as columns (chatter.uncertain_lobes): fields method,
/// warnings, notes, samples, seed, [position_mm]; columns spindle_rpm,
/// depth_limit_mm (the nominal model's), one quantile column per level
/// (quantile_column_name), depth_mm (the probability grid) and
/// probability_stable (speeds × depths).
ColumnRecord uncertain_lobe_columns(const std::vector<StabilityLimit>& nominal, const UncertainLobes& mc,
                                    const LobeColumnsSource& source, long long samples, long long seed,
                                    std::optional<double> position_mm);

// ------------------------------------------------------------------ compare

/// The methods `compare` runs, from `list` as given: none = the registry's
/// default ones (in_default_compare) that apply to the config, "all" = every
/// method that applies, else comma-separated distinct names in column order,
/// each of which must apply. parse_compare_methods checks the syntax alone
/// (before the config is read); choose_compare_methods the config.
/// @throws InputError "<methods> '<list>': <why>; must be ...".
std::vector<std::string> parse_compare_methods(const std::optional<std::string>& list, ArgStyle style);
std::vector<std::string> choose_compare_methods(const std::optional<std::string>& list, const Config& config,
                                                ArgStyle style);

/// One method of a comparison: its solver, rows and diagnostics.
struct ComparedMethod {
  const SolverDescriptor* descriptor = nullptr;
  std::unique_ptr<LobeSolver> solver;
  SolverValues options;                     ///< effective options (descriptor->effective_options)
  std::vector<std::string> notes;           ///< method_notes: what this method does not see
  std::vector<DiagnosticColumn> columns;    ///< the solver's diagnostic columns
  std::vector<StabilityLimit> rows;         ///< one per speed
  std::vector<std::vector<SolverValue>> values;  ///< per speed, in column order (empty without columns)

  /// The value of diagnostic `name` at speed i (monostate if none).
  SolverValue value(const std::string& name, std::size_t i) const;
  /// Speed i is limited by a flip (period-doubling) multiplier.
  bool is_flip(std::size_t i) const;
};

/// The largest relative difference of the depth limit between two methods
/// over the speeds where both are bounded; speeds where one alone finds a
/// limit are counted apart.
struct ComparedPair {
  std::string first, second;
  double largest_relative_difference = 0.0;
  double at_spindle_rpm = 0.0;
  std::size_t bounded_only_by_first = 0, bounded_only_by_second = 0;
};

struct Comparison {
  std::vector<double> speeds_rpm;
  double depth_max_mm = 0.0;
  std::vector<ComparedMethod> methods;  ///< in column order
  std::vector<ComparedPair> pairs;      ///< every pair (a, b), a before b
  std::string explanation;              ///< the text `chatter compare` prints: the pairs, then why methods differ
};

/// What `compare` needs besides the config.
struct CompareRequest {
  std::vector<std::string> methods;  ///< choose_compare_methods
  std::vector<double> speeds_rpm;    ///< evenly spaced, increasing
  double depth_max_mm = 50.0;
  /// The options of one method (checked): the CLI's flags or Python's dict.
  std::function<SolverValues(const SolverDescriptor&)> options;
  unsigned threads = 0;  ///< 0 = every core; the result does not depend on it
  ArgStyle style = ArgStyle::kFlag;  ///< how the notes name solver options
  /// Called before each method is solved (its name) and after each speed
  /// (done of total); may be empty.
  std::function<void(const std::string& method, std::size_t done, std::size_t total)> progress;
};

/// Builds every solver (a bad option fails before any solve), then solves
/// each method at every speed. Cost: one limit_at (sdm: with diagnostics)
/// per method and speed. @throws InputError.
Comparison compare_methods(const Config& config, const CompareRequest& request);

/// The table: spindle_rpm, depth_limit_mm_<method> per method, then each
/// method's compare_columns as <column>_<method> (`chatter compare --table`).
std::string comparison_csv(const Comparison& c);
/// The record: config, name, methods, speeds and depth searched,
/// solver_options by method, warnings, notes, pairs, explanation.
nlohmann::json comparison_record(const Comparison& c, const RecordSource& source);
/// chatter.compare's result: comparison_record's fields; columns
/// spindle_rpm, depth_limit_mm_<method> (+inf where no limit) and each
/// method's compare columns as text, <column>_<method> ("" where no limit).
ColumnRecord comparison_columns(const Comparison& c, const RecordSource& source);
/// The methods' limits in the form plot_compare draws (flip rows marked).
std::vector<MethodLimits> comparison_plot_lines(const Comparison& c);

// ------------------------------------------------------------------ map

/// `chatter map`'s method: only the Floquet method draws maps ("auto" is
/// that method). @throws InputError "<method> X: map needs <method> sdm".
std::string map_method(const std::string& requested, ArgStyle style);

/// Depths 0 .. depth_max_mm, `depth_points` of them, checked with the grid's
/// size (speeds × depths <= 4e6). @throws InputError naming the argument.
std::vector<double> map_depths_m(double depth_max_mm, int depth_points, std::size_t speeds, ArgStyle style);

/// The spectral radius on the grid (speeds outermost), and with
/// `multiplier_types` the type of the dominant multiplier at every unstable
/// point (stable points: hopf, never read). Cost: one Floquet map per grid
/// point, plus one analysis per unstable point with types.
StabilityMapGrid stability_map(const SemiDiscretizationSolver& sdm, const std::vector<double>& speeds_rpm,
                               const std::vector<double>& depths_m, bool multiplier_types, unsigned threads,
                               const std::function<void(std::size_t done, std::size_t total)>& progress = {});
/// spindle_rpm,depth_mm,spectral_radius, one row per grid point (`chatter map --out`).
std::string stability_map_csv(const StabilityMapGrid& grid);
/// Grid points with spectral radius >= 1.
std::size_t unstable_points(const StabilityMapGrid& grid);
/// The record: method, config, name, warnings, notes, the grid's extent,
/// unstable_points, solver_options (`chatter map --json`).
nlohmann::json stability_map_record(const StabilityMapGrid& grid, const SolverValues& solver_options,
                                    const RecordSource& source);
/// chatter.map's result: stability_map_record's fields; columns
/// spindle_rpm, depth_mm and the grids (speeds × depths) spectral_radius
/// and, with `multiplier_types`, multiplier_type ("" where ρ < 1).
ColumnRecord stability_map_columns(const StabilityMapGrid& grid, const SolverValues& solver_options,
                                   const RecordSource& source, bool multiplier_types);

// ------------------------------------------------------- radial x axial map

/// The axes of `chatter map`: speed x axial depth (the default) or, at one
/// speed, radial immersion x axial depth.
enum class MapAxes { kSpeedAxial, kRadialAxial };
/// "speed-axial" or "radial-axial". @throws InputError
/// "<axes> 'x': unknown; use speed-axial (spindle speed x axial depth) or radial-axial (...)".
MapAxes parse_map_axes(const std::string& text, ArgStyle style);

/// Radial immersions a_e / D from `min` to `max`, `points` of them evenly
/// spaced, checked: 0 < min < max <= 1, points >= 2, points × depths <= 4e6.
/// @throws InputError naming the argument and the rule.
std::vector<double> map_immersions(double min, double max, int points, std::size_t depths, ArgStyle style);

/// Builds the solver for one process (the config's, with another immersion).
using ProcessSolverFactory = std::function<std::unique_ptr<LobeSolver>(const Process&)>;

/// The radial x axial map at `spindle_rpm`: for each immersion the config's
/// milling process with that radial_immersion (everything else unchanged), a
/// solver from `make_solver` (must be the Floquet solver: sdm), its spectral
/// radius at every depth, its limit search at the speed (the lobe table's
/// limit_at, what `chatter point` reports), and with `multiplier_types` the
/// dominant multiplier's type at every unstable point. Immersions run in
/// parallel on `threads` (each has its own solver).
/// @pre spindle_rpm > 0, immersions from map_immersions, depths from map_depths_m.
/// @throws InputError when `process` is not milling (turning has no
///         immersion) or the solver is not the Floquet one.
/// Cost per immersion: one solver build, one Floquet map per depth, one
/// limit search, plus one analysis per unstable point with types.
RadialStabilityMapGrid radial_stability_map(const Process& process, double spindle_rpm,
                                            const std::vector<double>& immersions, const std::vector<double>& depths_m,
                                            const ProcessSolverFactory& make_solver, bool multiplier_types,
                                            unsigned threads,
                                            const std::function<void(std::size_t done, std::size_t total)>& progress = {});
/// radial_immersion,[radial_depth_mm,]depth_mm,spectral_radius,depth_limit_mm:
/// one row per grid point, immersions outermost; radial_depth_mm only when the
/// tool diameter is known; depth_limit_mm is the searched limit at the row's
/// immersion (the same on every row of it; `inf` when none below the depth searched).
std::string radial_map_csv(const RadialStabilityMapGrid& grid);
/// The record of `chatter map --axes radial-axial --json`: axes, spindle_rpm,
/// the grid's extent, unstable_points, max_spectral_radius, `boundary` (per
/// immersion: radial_immersion, radial_depth_mm or null, depth_limit_mm or
/// null, chatter_frequency_hz or null, lobe), solver_options, source.
nlohmann::json radial_map_record(const RadialStabilityMapGrid& grid, const SolverValues& solver_options,
                                 const RecordSource& source);
/// chatter.map(axes="radial-axial")'s result: radial_map_record's fields;
/// columns radial_immersion, [radial_depth_mm] (with a tool diameter),
/// depth_mm, depth_limit_mm and chatter_frequency_hz per immersion (+inf,
/// NaN where no limit), and the grids (immersions × depths) as
/// stability_map_columns.
ColumnRecord radial_map_columns(const RadialStabilityMapGrid& grid, const SolverValues& solver_options,
                                const RecordSource& source, bool multiplier_types);

// ------------------------------------------------------------------ frf

/// The frequencies of `chatter frf`: from fmin to fmax (defaults: half the
/// lowest and twice the highest natural frequency), evenly or (log)
/// logarithmically spaced. @throws InputError naming the argument.
struct FrfGrid {
  double fmin_hz = 0.0, fmax_hz = 0.0;
  int points = 1000;
  bool log = false;
  std::vector<double> frequencies_hz() const;
};
FrfGrid frf_grid(const StructuralModel& model, std::optional<double> fmin_hz, std::optional<double> fmax_hz,
                 int points, bool log, ArgStyle style);

/// A table of named numeric columns of equal length.
struct NamedColumns {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
};
/// frequency_hz, then <body>_<term>_real_m_per_n and _imag_m_per_n for body
/// tool, workpiece, relative (their sum) and term xx, xy, yy: the receptance
/// in m/N (`chatter frf`'s columns).
NamedColumns receptance_table(const StructuralModel& model, const FrfGrid& grid);
/// The columns as CSV, every cell with 10 significant digits (%.10g).
std::string named_columns_csv(const NamedColumns& t);
/// chatter.frf's result: fields name, warnings, [position_mm]; the columns
/// of receptance_table.
ColumnRecord receptance_columns(const NamedColumns& t, const RecordSource& source);

}  // namespace chatter
