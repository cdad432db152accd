// Shared pieces of the `chatter` subcommands: option parsing with a
// positional CONFIG, the --method option, sweep resolution from flags and the
// config's [sweep] table. Only the CLI includes Boost.Program_options.
#pragma once

#include <boost/program_options.hpp>

#include <optional>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"

namespace chatter::cli {

namespace po = boost::program_options;

inline constexpr double kDefaultDepthMaxMm = 50.0;
inline constexpr int kDefaultRpmPoints = 400;
/// Exit status of a command that predicts chatter when asked to fail on it
/// (--fail-on-chatter; check and detect always): 0 stable, 3 chatter, 2 bad input.
inline constexpr int kExitChatter = 3;
/// Largest sweep a command computes: speeds of a lobe table, and grid points
/// of a map (rows held in memory, and the time: ~1e6 sdm solves is hours).
inline constexpr long long kMaxRpmPoints = 1'000'000;
inline constexpr long long kMaxMapPoints = 4'000'000;

/// Runs f(); an InputError from the library is rethrown with "<flag>: " in
/// front (library messages do not name command-line flags).
template <class F>
auto with_flag(const std::string& flag, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(flag + ": " + e.what());
  }
}

/// A number for messages and summaries.
std::string fmt(double x, int digits = 6);

struct Common {
  std::string config_path;
  std::string method;  ///< --method as given; add_common() sets the default "auto" (build_solver resolves it)
  bool strict = false;  ///< --strict: the config's plausibility warnings are errors
  /// --position-mm: the tool position along a position-dependent model
  /// (docs/position.md); load_checked() then returns the model there.
  std::optional<double> position_mm;
  /// The numbers given as flags outside their usual band (flag_warnings);
  /// load_checked adds them to the config's warnings.
  std::vector<std::string> flag_warnings;
};

/// "--<flag> = v: outside <band>; is it in <unit> (...)?" for each flag of
/// `vm` given on the command line (not defaulted) with a number outside its
/// usual band (chatter/usual_bands.hpp kFlagBands). Warned, never refused
/// (--strict refuses them with the config's warnings).
std::vector<std::string> flag_warnings(const po::variables_map& vm);
/// flag_warnings printed on stderr ("warning: --rpm = ..."), for the
/// commands without a machining config (detect, coefficients, grind); with
/// `strict` they are errors: @throws InputError listing them.
void print_flag_warnings(const po::variables_map& vm, bool strict);

/// Adds --method to `d`.
void add_common(po::options_description& d, Common& c);

/// po::store of a command line against `all`; an unknown long option is
/// rethrown as a po::error that adds the nearest option of `all` ("did you
/// mean --rpm-points?", by edit distance), when one is close.
void store_command_line(const std::vector<std::string>& args, const po::options_description& all,
                        const po::positional_options_description& pos, po::variables_map& vm);

/// Parses a subcommand's arguments (positional CONFIG, --strict); returns
/// false if --help was printed. @throws po::error on a usage error.
bool parse(const std::vector<std::string>& args, const std::string& usage, po::options_description& visible,
           Common& common, po::variables_map& vm);

/// Loads CONFIG and prints each plausibility warning on stderr as
/// "warning: <file>: <key> = <value>: <what>", the flags' after them. With --strict the warnings are
/// errors: @throws InputError listing them (before anything is written).
/// With --position-mm the returned config's model is the structure at that
/// position (config_at_position); @throws InputError naming --position-mm when
/// the config has no position-dependent model or the position is outside it.
Config load_checked(const Common& common);

// position_m() and position_range_text(): in the io layer (chatter/io/config.hpp).

/// --ssv-amplitude / --ssv-frequency: spindle speed variation on the
/// command line (lobes, point, map; docs/ssv.md).
void add_speed_variation_options(po::options_description& d);
/// Sets cfg.process's speed variation from the flags: both flags, or one of
/// them on top of the config's [process] speed_variation (the other kept).
/// Prints a warning above kLargeSpeedVariation (an error with --strict).
/// @throws InputError naming the flag and the rule.
void apply_speed_variation_options(const po::variables_map& vm, const Common& common, Config& cfg);

/// Speeds and depth from --rpm-min/--rpm-max/--rpm-points/--depth-max-mm,
/// falling back on the config's [sweep]. @throws InputError.
struct Sweep {
  double rpm_min = 0.0, rpm_max = 0.0, depth_max_mm = kDefaultDepthMaxMm;
  int rpm_points = kDefaultRpmPoints;
};
Sweep resolve_sweep(const po::variables_map& vm, const Config& cfg);

/// One output file of a command: the flag that named it and the path ("" =
/// not asked or standard output: skipped by check_outputs). A plot
/// also writes <stem>.gp and <stem>.dat beside the image.
struct Output {
  std::string flag;  ///< e.g. "--table"
  std::string path;
  bool plot = false;
};
/// Checks, before anything is computed, that every output can be written:
/// the image type of a plot (check_plot_path), the directory exists and a
/// file can be created in it (probed by creating and removing
/// <path>.partial, the name the writer uses), the path is not a directory,
/// an existing special file (/dev/null, a pipe) is writable, and no two
/// outputs (plot siblings included) are the same file. Cost: a few system
/// calls per output. @throws InputError "<flag> <path>: <why> (nothing
/// written)".
void check_outputs(const std::vector<Output>& outputs);

/// --show: a live gnuplot window instead of (or beside) the image files
/// (lobes, map, compare, surface, simulate; docs/plots.md).
inline constexpr const char* kShowHelp =
    "open the plot in a live gnuplot window (zoom, pan; it stays open after chatter ends; needs a display and a "
    "gnuplot with a window terminal: qt, wxt or x11); with GNUPLOT_TERM set, draw on that gnuplot terminal "
    "instead (GNUPLOT_TERM=dumb: a text plot on standard output)";
/// What --show asked for, checked before anything is computed.
struct ShowRequest {
  bool requested = false;
  /// The `set terminal` argument: GNUPLOT_TERM as given, or the window
  /// terminal chosen (qt, wxt or x11) with the image's size and font.
  std::string terminal;
  std::string where;  ///< for the message after drawing: "a gnuplot qt window", "gnuplot terminal dumb"
  bool text = false;  ///< a text terminal (dumb): the plot is printed on standard output
};
/// Adds --show to a command's options.
void add_show_option(po::options_description& d);
/// --show checked: gnuplot on PATH, then GNUPLOT_TERM, else a display
/// ($DISPLAY or $WAYLAND_DISPLAY) and a window terminal in this gnuplot.
/// Costs one gnuplot start (to list its terminals) when --show is given.
/// @throws InputError "--show: ..." saying what is missing and what to do
/// (the CLI exits 2 before computing anything).
ShowRequest show_request(const po::variables_map& vm);

/// The help of --plot-depth-max-mm (lobes, compare).
inline constexpr const char* kPlotDepthMaxHelp =
    "with --plot or --show: top of the depth axis, mm (> 0; default: 1.1 x the deepest finite limit, rounded up, "
    "at most --depth-max-mm, so every stable pocket is visible)";
/// --plot-depth-max-mm: 0 when not given (automatic axis). @throws InputError
/// if it is not finite and > 0, or given without --plot (`plotting` false).
double plot_depth_max_mm(const po::variables_map& vm, bool plotting);

}  // namespace chatter::cli

#include <chrono>
#include <memory>
#include <mutex>

#include <nlohmann/json.hpp>

#include "chatter/io/table_writer.hpp"
#include "chatter/records.hpp"  // SolverRecipe
#include "chatter/lobes.hpp"
#include "chatter/solvers.hpp"

namespace chatter::cli {

/// Adds the solver-tuning options: --threads, --quiet and the command-line
/// options of every registered method (SolverDescriptor::options, help
/// prefixed by the method name).
void add_solver_options(po::options_description& d);

/// The command-line flag of a solver option: "--" + name with '_' → '-'.
std::string option_flag(const SolverOption& o);

/// The solver chosen by --method, built with the sweep depth.
struct BuiltSolver {
  std::string method;  ///< the method used ("auto" resolved: resolve_lobe_method)
  const SolverDescriptor* descriptor = nullptr;
  std::unique_ptr<LobeSolver> solver;
  SolverRecipe recipe;     ///< the method and its values: the same solver on another structure or process
  nlohmann::json options;  ///< the solver's effective options (an object), for the JSON provenance
  /// What the method does not see of the cutter (ignored_feature_notes),
  /// printed as "note: ..." on stderr by build_solver and kept for the JSON.
  std::vector<std::string> notes;
};
/// A solver value as JSON (std::monostate → null).
nlohmann::json to_json(const SolverValue& v);
/// A diagnostic as a table cell: "" for std::monostate, numbers as table_number.
std::string cell_text(const SolverValue& v);
/// The extra table columns of `columns` from per-row diagnostics
/// (values[i] = the values of row i, in column order).
std::vector<ExtraColumn> extra_columns(const std::vector<DiagnosticColumn>& columns,
                                       const std::vector<std::vector<SolverValue>>& values);
/// The descriptor named by --method (or --methods). @throws InputError
/// `<flag>: method "x": unknown (...)`.
const SolverDescriptor& method_descriptor(const std::string& method, const std::string& flag = "--method");
/// Refuses a solver option that none of `methods` uses (each registered
/// option belongs to the methods whose descriptor lists it). `chooser` is
/// the option that picked the methods ("--method" or "--methods"), for the
/// message. @throws InputError.
void check_solver_options(const std::vector<std::string>& methods, const po::variables_map& vm,
                          const std::string& chooser);

/// The solver options given on the command line for `descriptor`'s method
/// (and the config's feed for the time-domain chip), checked.
/// @throws InputError "<flag> = X: <rule>".
SolverValues solver_option_values(const SolverDescriptor& descriptor, const Config& cfg, const po::variables_map& vm);

/// @throws InputError on an unknown method or bad option. Unless
/// `check_options` is false (the caller already ran check_solver_options over
/// all the methods it builds, as `compare` does), first refuses the options
/// `method` does not use.
BuiltSolver build_solver(const std::string& method, const Config& cfg, double depth_max_m,
                         const po::variables_map& vm, bool check_options = true);

/// Threads from --threads (0 = every core).
unsigned thread_count(const po::variables_map& vm);

/// A progress bar with the time left, on stderr, only when stderr is a
/// terminal and --quiet is not given, and only once `show_after_s` seconds
/// have passed (short runs stay silent). Safe to tick from worker threads.
class Progress {
 public:
  Progress(const po::variables_map& vm, std::size_t total, std::string label, double show_after_s = 0.0);
  ~Progress();
  void tick(std::size_t done);

 private:
  bool enabled_;
  bool lines_ = false;  ///< --progress on a non-terminal: one line per second, newline-terminated
  std::size_t total_;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_;
  std::chrono::duration<double> show_after_;
  bool shown_ = false;
};

}  // namespace chatter::cli
