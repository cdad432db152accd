// The solver registry: one descriptor per lobe method, the single place that
// knows the method names. The CLI (lobes, point, compare, its --help and
// per-method options), the plots, the C API and the operation check all read
// it; each solver's own header documents its method and paper.
//
// How to add a solver:
//  1. Implement LobeSolver in one new source file (with its header): limit_at,
//     and, if it reports more than the limit, diagnostic_columns() /
//     limit_with_diagnostics() (extra table columns) and analyse_point()
//     (the `chatter point` verdict).
//  2. Add one SolverDescriptor to the table in src/solvers/factory.cpp: its
//     name, summary, the inputs it accepts (SolverFeature), its tuning
//     options, the factory, effective_options (the JSON provenance), its plot
//     style and its diagnostic columns.
// Nothing else switches on method names: the CLI options, the table columns,
// the compare notes and the plot style follow from the descriptor.
#pragma once

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

/// An input a solver may or may not handle; a solver that does not list a
/// feature refuses a config that needs it (check_accepts). Runout is the
/// exception: it changes the static chip only, so a linear method ignores it
/// with a warning (ignored_features) instead of refusing.
enum class SolverFeature : std::uint32_t {
  kModalModel = 0,      ///< structure given by modes
  kMeasuredFrf = 1,     ///< structure given by measured FRFs (tabulated receptances)
  kMilling = 2,         ///< intermittent cut of a rotating cutter
  kTurning = 3,         ///< continuous single-point cut
  kHelix = 4,           ///< helical teeth (one helix angle for all)
  kVariablePitch = 5,   ///< unequal pitch angles: one delay per tooth over a revolution
  kVariableHelix = 6,   ///< unequal helix angles: delays that vary along the flute
  kRunout = 7,          ///< teeth at unequal radii (static chip only)
  kProcessDamping = 8,  ///< flank rubbing damping C_pd a / V
  kSpeedVariation = 9,  ///< spindle speed variation: a time-varying delay (docs/ssv.md)
  kCutterProfile = 10,  ///< ball, bull-nose or general cutter: axial slices (docs/cutter_geometry.md)
};

/// Name of a feature for messages ("measured FRFs", "milling", ...).
std::string to_string(SolverFeature f);

/// A set of SolverFeature (up to 32).
class FeatureSet {
 public:
  FeatureSet() = default;
  FeatureSet(std::initializer_list<SolverFeature> fs) {
    for (SolverFeature f : fs) insert(f);
  }
  void insert(SolverFeature f) { bits_ |= bit(f); }
  bool contains(SolverFeature f) const { return (bits_ & bit(f)) != 0; }
  bool empty() const { return bits_ == 0; }
  /// The features of `needed` not in this set, in enum order.
  std::vector<SolverFeature> missing(const FeatureSet& needed) const;

 private:
  static std::uint32_t bit(SolverFeature f) { return std::uint32_t{1} << static_cast<std::uint32_t>(f); }
  std::uint32_t bits_ = 0;
};

/// The features a (model, process) pair needs (runout excluded: see
/// ignored_features).
FeatureSet needed_features(const StructuralModel& model, const Process& process);

/// A tuning option of one solver (beyond the search depth every solver takes).
/// The CLI offers it as --<name with '_' → '-'>; the factory receives it under
/// `name` in its SolverValues.
struct SolverOption {
  enum class Kind { kInt, kReal, kFlag };
  std::string name;  ///< e.g. "steps", "feed_per_tooth_mm" (units in the name)
  Kind kind = Kind::kInt;
  std::string help;  ///< one line for --help (default and effect)
  /// Accepted range (kInt, kReal), inclusive; max = +inf for none.
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  std::string unit;  ///< for messages, e.g. "mm"; may be empty
  bool cli = true;   ///< offered on the command line (false: library callers only)
};

/// Empty when `value` is a valid value of `option` (kind and range), else the
/// rule it breaks, e.g. "must be in [20, 100000]" or "must be >= 1".
std::string option_violation(const SolverOption& option, const SolverValue& value);

/// How plots draw one method (plot_compare; the same on every chart).
struct PlotStyle {
  const char* colour = "#000000";  ///< "#rrggbb"
  double width = 1.0;              ///< line width (gnuplot units)
  const char* dash = "";           ///< gnuplot dash spec, e.g. " dt (6,4)"; "" = solid
  int point_type = 0;              ///< 0 = drawn as a line; else gnuplot point type, drawn as points
};

/// What kind of answer a method gives, for the explanations of `compare`.
enum class SolverKind {
  kAveraged,    ///< zeroth-order (tooth-period averaged) transfer function: exact in turning, no flip lobes
  kFloquet,     ///< discretised Floquet analysis: sees flip lobes, discretisation error
  kSimulation,  ///< time-domain simulation: limit is the middle of a depth bracket
};

/// Everything the rest of the code needs to know about one method.
struct SolverDescriptor {
  std::string name;     ///< method name, unique (e.g. "sdm")
  std::string summary;  ///< one line for --help
  SolverKind kind = SolverKind::kAveraged;
  FeatureSet accepts;   ///< inputs it handles; others are refused by make_lobe_solver
  bool in_default_compare = false;  ///< run by `chatter compare` without --methods
  std::vector<SolverOption> options;
  /// Builds the solver. depth_max_m > 0; `options` holds only names from
  /// `options` (kInt → int, kReal → double, kFlag → bool), already in range.
  /// @throws InputError on an invalid value.
  std::function<std::unique_ptr<LobeSolver>(const StructuralModel&, const Process&, double depth_max_m,
                                            const SolverValues& options)>
      make;
  /// The options a built solver (made by `make`) actually uses, for the JSON
  /// provenance ("depth_max_m" and the solver's own, defaults included).
  std::function<SolverValues(const LobeSolver&)> effective_options;
  PlotStyle plot;
  /// = the built solver's diagnostic_columns().
  std::vector<DiagnosticColumn> columns;
  /// The columns `compare` adds per method, as "<column>_<method>".
  std::vector<std::string> compare_columns;
};

/// Every registered method, in a fixed order (the default column order).
const std::vector<SolverDescriptor>& solver_registry();

/// The descriptor named `method`. @throws InputError
/// `method "x": unknown (this build has: analytic, ...)`.
const SolverDescriptor& find_lobe_method(const std::string& method);

/// The method names this build provides, in registry order.
std::vector<std::string> lobe_methods();

/// True when `method` names a solver this build provides.
bool has_lobe_method(const std::string& method);

/// The default method of every command and interface (CLI --method, Python
/// method=, C API NULL): resolved per job by resolve_lobe_method.
inline constexpr const char* kAutoMethod = "auto";

/// The warning given when milling is judged by an averaged method.
inline constexpr std::string_view kFlipLobeWarning =
    "milling checked with the zeroth-order analytic method, which misses flip lobes at low radial immersion";

/// The method `requested` stands for on (model, process): a registered name
/// is itself; "auto" picks by the registry's rule (docs/results.md): turning
/// → the first averaged method that accepts the inputs (exact for turning:
/// analytic); milling → the first Floquet method that accepts them (sdm: it
/// sees flip lobes), else the first method that does (measured FRFs:
/// analytic). Whenever milling ends up with an averaged method (auto or
/// asked for), `*warning` (if not null) is set to kFlipLobeWarning.
/// @throws InputError on an unknown name ("method \"x\": unknown (this build
///         has: auto, analytic, ...)"), or, for "auto", when no method accepts
///         the inputs (check_accepts' message).
std::string resolve_lobe_method(const std::string& requested, const StructuralModel& model, const Process& process,
                                std::string* warning = nullptr);

/// Refuses a (model, process) the method does not handle. @throws InputError
/// `method "x" does not handle <feature> (<what>)`, naming the first missing feature.
void check_accepts(const SolverDescriptor& d, const StructuralModel& model, const Process& process);

/// Notes for the cutter features method `d` accepts but does not see: runout
/// for a method without kRunout ("runout ... is ignored by method ..."), a
/// helix for an averaged method (the average over a revolution does not
/// change). Empty when there is nothing to say. For warnings and JSON notes.
std::vector<std::string> ignored_feature_notes(const SolverDescriptor& d, const Process& process);

/// Builds the solver named `method` with the given search depth (m, > 0) and
/// tuning options (names from its descriptor; defaults for those absent).
/// @throws InputError on an unknown method or option, an input the method
///         does not accept (check_accepts) or an invalid depth or option.
std::unique_ptr<LobeSolver> make_lobe_solver(const std::string& method, const StructuralModel& model,
                                             const Process& process, double depth_max_m,
                                             const SolverValues& options = {});

}  // namespace chatter
