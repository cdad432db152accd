// The records a user reads: one function per command result turns the
// library's result struct into its JSON record (shop units: mm, rev/min, Hz,
// µm where a key says so). The CLI prints these records, Python hands them on
// as dicts (python/, through one JSON -> Python converter), the C API returns
// them as text: nobody builds a record twice (docs/results.md defines every
// key once).
//
// Layer: above io (Config) and ops (check, recommend); below the CLI, the C
// API and Python. Uses nlohmann-json (header-only): a consumer of these
// functions includes <nlohmann/json.hpp> to use the returned values.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "chatter/io/config.hpp"
#include "chatter/lobes.hpp"
#include "chatter/records/columns.hpp"
#include "chatter/operations.hpp"
#include "chatter/optimization.hpp"
#include "chatter/report.hpp"
#include "chatter/results.hpp"
#include "chatter/solvers.hpp"
#include "chatter/time_domain.hpp"

namespace chatter {

/// The deepest cut searched when neither the arguments nor the config's
/// sweep.depth_max_mm give one, mm (every command and interface).
inline constexpr double kDefaultSearchDepthMm = 50.0;

/// How a message names an argument: the CLI's flag or Python's keyword. The
/// library functions that check a command's arguments (recommend_plan,
/// check_options, the records of compare, map, frf, coefficients, detect
/// and fit) take it, so that both front ends give the same message with
/// their own names.
enum class ArgStyle { kFlag, kKeyword };
/// `key` (snake_case, Python's keyword) as `style` names it: "--rpm-min"
/// (underscores to dashes) or "rpm_min".
std::string arg_name(ArgStyle style, const std::string& key);

/// What a lobe method does not see of this input, for the `notes` of the
/// records (and the CLI's "note:" lines): auto's fallback to an averaged
/// method for milling (`averaged_milling`: resolve_lobe_method's reason, ""
/// when none), the cutter features the method ignores
/// (ignored_feature_notes), runout ignored by a linear simulation.
std::vector<std::string> method_notes(const std::string& requested, const SolverDescriptor& descriptor,
                                      const Process& process, const SolverValues& options,
                                      const std::string& averaged_milling, ArgStyle style);

/// The options of `descriptor`'s method as the front ends use them: the
/// ones the user gave (`given`, already checked against the option's rule),
/// plus the config's defaults for those not given — today the time-domain
/// chip's feed from [process] feed_per_tooth_mm / feed_per_rev_mm. The one
/// place the config feeds a solver option (CLI, Python, C API, compare,
/// Monte Carlo).
SolverValues with_config_defaults(const SolverDescriptor& descriptor, const Config& config, SolverValues given);

/// A resolved method and its options as a front end completed them
/// (with_config_defaults): builds the same solver on another structure or
/// process — a position along the part (surface), a Monte Carlo sample, a
/// map's radial immersion, each method of a comparison. With
/// configure_solver, the only way a front end (CLI, Python, C API, records)
/// makes a lobe solver; make_lobe_solver stays behind these two.
struct SolverRecipe {
  std::string method;  ///< a registry name ("auto" already resolved)
  SolverValues values;
  /// @throws InputError as make_lobe_solver. @pre depth_max_m > 0.
  std::unique_ptr<LobeSolver> build(const StructuralModel& model, const Process& process, double depth_max_m) const;
};

/// A lobe solver built for a front end: the method ("auto" resolved by
/// resolve_lobe_method), its descriptor, the solver, the options it was
/// built with (with_config_defaults) and the notes of what it does not see
/// (method_notes). Every front end builds its solvers here.
struct ConfiguredSolver {
  std::string method;
  const SolverDescriptor* descriptor = nullptr;
  std::unique_ptr<LobeSolver> solver;
  SolverValues values;
  std::vector<std::string> notes;
  /// The method and values, to build the same solver elsewhere.
  SolverRecipe recipe() const { return {method, values}; }
};
/// @throws InputError on an unknown method or an input the method refuses
///         (make_lobe_solver). @pre depth_max_m > 0.
ConfiguredSolver configure_solver(const std::string& requested, const Config& config, double depth_max_m,
                                  SolverValues given, ArgStyle style);

/// What every record says about its inputs.
struct RecordSource {
  std::string config_name;     ///< the config's `name`
  std::string config_path;     ///< the file it came from ("" for text)
  std::vector<std::string> warnings;  ///< the config's plausibility warnings
  std::vector<std::string> notes;     ///< what the method does not see (ignored_feature_notes)
  std::optional<double> position_mm;  ///< --position-mm / position_mm=, when given
};
/// The source of a loaded config (warnings copied), with the given position.
RecordSource record_source(const Config& config, std::optional<double> position_mm = std::nullopt);

/// A number, or null when it is not finite (JSON has no inf/NaN).
nlohmann::json finite_or_null(double x);
/// A solver value (option or diagnostic) as JSON (monostate: null).
nlohmann::json value_json(const SolverValue& v);
/// A solver value as a table cell: "" for monostate, numbers as
/// table_number, flags as true/false.
std::string value_text(const SolverValue& v);

/// `chatter point`: the limit (the lobe-table row at the speed, with the
/// method's columns), stable and margin, tooth_passing_hz, tooth_period_s,
/// and what belongs to the asked depth under its own keys (spectral_radius,
/// growth_per_period, dominant_multiplier [re, im], dominant_frequency_hz,
/// dominant_multiplier_type, floquet_period_s, and the method's extras).
nlohmann::json point_record(const PointReport& report, const RecordSource& source);

/// What a simulation was asked (for its record).
struct SimulationRequest {
  SimulationSettings settings;
  double relative_tolerance = 1e-7;
  /// Floquet periods per revolution (simulation_periods_per_revolution).
  int periods_per_revolution = 1;
  double tooth_period_s = 0.0;  ///< Process::delay_s at the speed
  double depth_mm = 0.0;        ///< the depth as given (echoed as is)
  double feed_mm = 0.0;         ///< the feed as given (echoed as is)
  /// Spindle speed variation (docs/ssv.md): the modulation asked and the
  /// principal period the run is over; empty at constant speed.
  std::optional<SpeedVariation> speed_variation;
  SpeedVariationPeriod speed_variation_period;
};
/// The request of a run as the user gave it: depth and feed in mm as typed,
/// the periods per revolution and the tooth period from the process.
SimulationRequest simulation_request(const SimulationSettings& settings, const Process& process,
                                     double relative_tolerance, double depth_mm, double feed_mm);

/// `chatter simulate`: verdict and its measure, growth per Floquet period,
/// frequencies and periods, amplitude, the first ten forced lines, the
/// integrator's cost. The series and spectrum are tables, not in the record.
nlohmann::json simulation_record(const SimulationResult& result, const SimulationRequest& request,
                                 const RecordSource& source);

/// The spectrum's harmonic index per line (SimulationResult::spectrum_harmonic:
/// k >= 1 within the harmonic window of k / floquet_period_s, else 0), the
/// `harmonic` column of simulate --spectrum and of Python's spectrum; all 0
/// for a result without it.
std::vector<int> spectrum_harmonics(const SimulationResult& result);
/// chatter.simulate's result: simulation_record's fields and the groups
/// "series" and "periodic" (every sample, and one per Floquet period:
/// time_s, tool_x_um, tool_y_um, workpiece_x_um, workpiece_y_um, rel_x_um,
/// rel_y_um, force_x_n, force_y_n, chip_um, in_cut: simulate --out's
/// columns) and "spectrum" (frequency_hz, amplitude_um, harmonic).
ColumnRecord simulation_columns(const SimulationResult& result, const SimulationRequest& request,
                                const RecordSource& source);

/// `chatter check --json`: every operation (verdict, limit, margins,
/// suggestion and pocket), the rows that could not be read (`rejected`) or
/// judged (`not_judged`: a solver failure, overrides that make no cutter),
/// the summary and the exit status (0 all stable, 3 some unstable, out of
/// tolerance or over the machine's power or torque, 2 some
/// rows not read or not judged: the others are still reported).
struct CheckRecordInputs {
  std::string operations_origin;   ///< the file (or "<operations>")
  std::string method_requested;    ///< "auto" or a method name
  const CheckOptions* options = nullptr;
  const Process* process = nullptr;  ///< the config's process (row overrides on top)
};
nlohmann::json check_record(const CheckReport& report, const OperationsFile& file, const CheckRecordInputs& in,
                            const RecordSource& source);
/// The exit status of a check (0, 2 or 3; docs/operations.md).
int check_exit_status(const CheckReport& report, const OperationsFile& file);

/// The machine's speed range: the arguments, else the config's [sweep].
/// @throws InputError "<file>: missing <rpm_min> (or sweep.rpm_min in the
/// config): the machine's spindle speed range", or a range that is not > 0
/// and increasing.
MachineLimits machine_range(const Config& config, std::optional<double> rpm_min, std::optional<double> rpm_max,
                            ArgStyle style);

/// The options of `chatter check` (and chatter.check) from the config and
/// the arguments: machine range, method (checked: "<method>: method ..."),
/// speed tolerance in percent, threads, the config's flute length.
/// @throws InputError naming the argument.
/// `load`: the machine's power and torque and what the cutting load needs
/// (docs/cutting_law.md), in shop units as the flags; the diameter defaults
/// to the config's process.tool_diameter_mm / workpiece_diameter_mm.
struct CheckLoadArgs {
  std::optional<double> max_power_kw, max_torque_nm;
  std::optional<double> tool_diameter_mm, workpiece_diameter_mm, tangential_coefficient_n_per_m2;
};
CheckOptions check_options(const Config& config, std::optional<double> rpm_min, std::optional<double> rpm_max,
                           const std::string& method, double speed_tolerance_pct, unsigned threads, ArgStyle style,
                           const CheckLoadArgs& load = {});

/// The arguments of `chatter recommend` (chatter.recommend): shop units, as
/// the flags; empty = the default (the config's, or no limit).
struct RecommendArgs {
  double feed_per_tooth_mm = 0.0;  ///< required
  std::optional<double> rpm_min, rpm_max, max_power_kw, max_torque_nm;
  double safety = 0.8;
  std::optional<double> depth_max_mm;
  double speed_tolerance_pct = 2.0;
  std::optional<double> tool_diameter_mm, workpiece_diameter_mm, tangential_coefficient_n_per_m2;
  std::optional<double> radial_immersion;
  std::optional<int> teeth;
  std::optional<std::string> milling_direction;
  /// The part's tolerance on the forced vibration's error, um: milling
  /// |SLE|, turning the diametral error (RecommendOptions::max_part_error_m).
  std::optional<double> max_sle_um;
  std::string method = "auto";
  unsigned threads = 0;
};
/// The options and the process (with the milling overrides) of a
/// recommendation, every argument checked. @throws InputError naming it.
struct RecommendPlan {
  RecommendOptions options;
  Process process;
};
RecommendPlan recommend_plan(const Config& config, const RecommendArgs& args, ArgStyle style);

/// `chatter recommend --json`: the speed, depth, limit, caps, binding
/// constraints, force, torque, power, removal rate and the explanation.
nlohmann::json recommend_record(const Recommendation& r, const RecommendOptions& options, const Process& process,
                                const RecordSource& source);

// ============================================ optimisation (docs/optimization.md)

/// One set-point as every optimisation record shows it: the set-point, each
/// index (the measured value where one was given), `measured` (their names),
/// `predicted` (the models), `alpha`, `loss_terms`, `loss`, `constraints`
/// ({name, value, limit, ok}), `stability_margin`, `depth_limit_mm`,
/// `feasible`, power, torque, tool life, cutting time.
nlohmann::json performance_json(const Performance& p, const OptimizationModel& model);

/// `chatter performance --json`: what every record says about its inputs, then performance_json.
nlohmann::json performance_record(const Performance& p, const OptimizationModel& model, const RecordSource& source);

/// `chatter optimize --json`: found, the objective, the binding constraints,
/// the bounds, the scan and polish counts and the optimum (performance_json).
nlohmann::json optimize_record(const Optimum& o, const OptimizationModel& model, const RecordSource& source);

/// The controller's state (adapt_step's `state`): the set-point, the
/// corrections per index, the iteration, the last loss, converged.
nlohmann::json adapt_state_json(const AdaptState& s, const OptimizationModel& model);

/// One step (the C API's and Python's adapt_step): the next state and
/// set-point, the measurement's performance, the corrected optimum, target, step.
nlohmann::json adapt_step_record(const AdaptStepResult& step, const OptimizationModel& model);

/// `chatter adapt --json`: one row per iteration (iteration, speed, feed,
/// depth, loss, each index, feasible, target, step), the uncorrected optimum,
/// the final state and the plan.
struct AdaptRecordInputs {
  const AdaptPlan* plan = nullptr;
  const AdaptSettings* settings = nullptr;
  std::string measurements_origin;  ///< the measurements file, or "" for the simulated plant
};
nlohmann::json adapt_record(const AdaptRun& run, const OptimizationModel& model, const AdaptRecordInputs& in,
                            const RecordSource& source);
/// The rows of an adapt record as CSV (`chatter adapt`'s table): its keys in
/// record order, numbers as the record has them, empty for null.
std::string adapt_table_csv(const nlohmann::json& adapt_record);

}  // namespace chatter
