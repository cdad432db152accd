// Choosing and correcting cutting parameters under every constraint,
// stability included (issue 29, docs/optimization.md):
// the forward models of the performance indices at a set-point
// (OptimizationModel::evaluate: `chatter performance`), the constrained
// optimum over the bounds (optimize: `chatter optimize`), and the adaptive
// loop of seed 003 (adapt_step, the one step a machine controller calls;
// adapt, the loop against a plant: `chatter adapt`).
//
// The models (ops layer, over core):
//  - removal rate: exact (f d V, or a a_e f_z N_t N);
//  - force, power, torque: the static cutting load (chatter/cutting_force.hpp);
//  - dimensional error: turning, the diametral error 2δ of the static
//    deflection (static_deflection_turning, chatter/forced.hpp, the one place),
//    the largest over the positions evaluated; milling, |SLE| of the forced
//    response (ForcedResponseSolver), the largest over the positions;
//  - roughness, tool life, cost, production rate: optimization_problem.hpp;
//  - stability: the depth limit of the lobe solver (make_lobe_solver; "auto":
//    analytic for turning, sdm for milling), the smallest over the positions.
// Units: SI in the set-points (m, rev/min); the indices in their names' units.
//
// Thread safety: OptimizationModel is immutable after construction but for
// its caches of solved limits and responses, which are guarded; const members
// may be called from several threads at once.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "chatter/forced.hpp"
#include "chatter/lobes.hpp"
#include "chatter/optimization_problem.hpp"
#include "chatter/position.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

/// Where the tool cuts: spindle speed, feed (per revolution in turning, per
/// tooth in milling) and depth.
struct SetPoint {
  double spindle_rpm = 0.0;
  double feed_m = 0.0;
  double depth_m = 0.0;
};

/// Multiplicative corrections of the index models (measured / predicted);
/// 1 = none.
using Corrections = IndexValues;
Corrections no_corrections();

/// One constraint at a set-point: `name` is the config key (max_force_n,
/// stability_margin, ...), value and limit in its unit; ok = value within
/// the limit.
struct ConstraintCheck {
  std::string name;
  double value = 0.0;
  double limit = 0.0;
  bool ok = false;
};

/// Everything known about one set-point (`chatter performance`).
struct Performance {
  SetPoint point;
  double cutting_speed_m_per_min = 0.0;
  /// The forward models (times the corrections).
  IndexValues model{};
  /// What the loss and the constraints use: the measurement where one is
  /// given, else the model.
  IndexValues value{};
  std::array<bool, kIndexCount> measured{};
  double power_w = 0.0, torque_n_m = 0.0;  ///< NaN without a cutting coefficient (turning)
  std::optional<OperationEconomics> economics;
  /// The smallest depth limit over the positions evaluated, m (+inf: none
  /// below the searched depth; NaN: stability not evaluated).
  double depth_limit_m = 0.0;
  /// Where that limit is (m along the part; NaN without positions).
  double weakest_position_m = 0.0;
  /// depth_limit / depth (+inf unbounded; NaN not evaluated, or a depth
  /// beyond the searched depth / the required margin with no limit found).
  double stability_margin = 0.0;
  /// Where the dimensional error is largest (m; NaN without positions).
  double worst_error_position_m = 0.0;
  std::array<double, kLossIndexCount> loss_terms{};
  double loss = 0.0;
  std::vector<ConstraintCheck> constraints;
  /// Every constraint holds and the objective is finite.
  bool feasible = false;
  /// The value minimised: the loss, −removal rate, the cost or −production rate.
  double objective = 0.0;
};

struct ModelOptions {
  std::string method = "auto";  ///< the lobe method ("auto" or a registry name)
  /// The tool position along a position-dependent part, m; empty: the
  /// spec's position_points positions over the part (the worst of them).
  std::optional<double> position_m;
  /// Threads of the scans (0 = every core); results do not depend on it.
  unsigned threads = 1;
};

/// The forward models of one config's [optimization] on its structure.
class OptimizationModel {
 public:
  /// @throws InputError on an invalid spec (the io layer checks the config's;
  ///         this re-checks what the models need: a diameter, a roughness model
  ///         for a roughness weight or limit, economics for cost and production
  ///         rate), an unknown method, a position outside the part, or a
  ///         milling structure with measured FRFs (the forced response needs modes).
  OptimizationModel(const StructuralModel& base, const PositionDependence& dependence, const Process& process,
                    OptimizationSpec spec, ModelOptions options = {});

  /// The indices, loss terms, constraints and stability margin at `p`, with
  /// the index models multiplied by `correction` and `measured` (NaN: not
  /// measured) replacing them where given.
  /// @throws InputError on a set-point outside (0, ∞) or a non-finite one.
  Performance evaluate(const SetPoint& p, const Corrections& correction, const IndexValues& measured) const;
  Performance evaluate(const SetPoint& p) const { return evaluate(p, no_corrections(), unknown_indices()); }

  /// The smallest depth limit over the positions at `rpm`, m (+inf when
  /// none below the searched depth), and the index of the weakest position.
  /// `feed_m`: the set-point's feed; with Kienzle's law the regenerative
  /// coefficient is the tangent at its chip (Process::at_feed), so the limit
  /// depends on it (ignored otherwise). Cached: each (speed, feed) is solved once.
  std::pair<double, std::size_t> depth_limit_m(double rpm, double feed_m) const;

  const OptimizationSpec& spec() const { return spec_; }
  const Process& process() const { return process_; }
  Operation operation() const { return process_.operation(); }
  bool milling() const { return process_.operation() == Operation::kMilling; }
  /// The lobe method used ("auto" resolved); empty when stability is off.
  const std::string& method() const { return method_; }
  /// What the method does not see and the flip-lobe warning, for the records.
  const std::vector<std::string>& notes() const { return notes_; }
  /// The positions evaluated, m (empty: the structure does not depend on the
  /// position); one when a tool position was given.
  const std::vector<double>& positions_m() const { return positions_m_; }
  bool position_given() const { return position_given_; }
  const std::array<double, kLossIndexCount>& alpha() const { return alpha_; }
  double cutting_speed_m_per_min(double rpm) const;
  /// The deepest cut the lobe solvers search, m.
  double depth_search_m() const { return depth_search_m_; }
  unsigned threads() const { return threads_; }

 private:
  double dimensional_error_um(const SetPoint& p, double* worst_position_m) const;
  double sle_um(std::size_t position, const SetPoint& p) const;

  OptimizationSpec spec_;
  Process process_;
  std::string method_;
  std::vector<std::string> notes_;
  std::vector<double> positions_m_;
  bool position_given_ = false;
  std::vector<StructuralModel> models_;
  // The lobe solvers per position, for the process at a feed (one entry,
  // key 0, without Kienzle's law: the limit does not depend on the feed);
  // built on first use, guarded by cache_mutex_.
  const std::vector<std::unique_ptr<LobeSolver>>& solvers_at(double feed_m) const;
  // The process's own feed is key 0 (the solvers built first).
  double feed_key(double feed_m) const {
    return process_.has_size_effect() && feed_m != process_.turning_parameters().kienzle->feed_m ? feed_m : 0.0;
  }
  mutable std::map<double, std::vector<std::unique_ptr<LobeSolver>>> solvers_;
  std::vector<std::unique_ptr<ForcedResponseSolver>> forced_;
  std::array<double, kLossIndexCount> alpha_{};
  double depth_search_m_ = 0.0;
  unsigned threads_ = 1;
  // Caches (guarded): depth limit per speed; milling SLE per unit feed per
  // (position, speed, depth) (the forced response is linear in the feed
  // without runout).
  mutable std::mutex cache_mutex_;
  mutable std::map<std::pair<double, double>, std::pair<double, std::size_t>> limit_cache_;  // (feed key, rpm)
  mutable std::map<std::tuple<std::size_t, double, double>, double> sle_cache_;
};

// ============================================================== optimize

struct OptimizeOptions {
  /// Scan points per variable (speeds evenly spaced in rpm, feeds and, when
  /// the depth is free, depths evenly spaced). 0: automatic (turning 121
  /// speeds, milling 41; 41 feeds; 9 depths).
  int speed_points = 0, feed_points = 0, depth_points = 0;
  /// Scan minima polished (the best local minima of the scan over speed, at
  /// least 1): the loss has a pocket per stable speed range.
  int candidates = 4;
};

struct Optimum {
  /// A feasible point exists on the scan (else `best` is the scan point that
  /// fails the fewest constraints and `binding` is empty).
  bool found = false;
  Performance best;
  /// The constraints within kBindingTolerance of their limit at the optimum
  /// (config key names), then the bounds the optimum sits on
  /// ("feed_mm_per_rev lower bound", ...).
  std::vector<std::string> binding;
  std::size_t evaluations = 0;     ///< forward-model evaluations
  int candidates_polished = 0;
};
/// A constraint is binding when |value − limit| <= this × |limit|: the polish
/// locates the optimum to ~1e-6 of the scan spacing, so a binding constraint
/// is met far closer than this; a constraint this close without binding is
/// reported too (it is then as good as binding).
inline constexpr double kBindingTolerance = 1e-3;

/// The constrained optimum of the spec's objective over its bounds with the
/// corrected models (docs/optimization.md): a scan of the bounds (the depth
/// limits at the scan speeds solved once, on model.threads() threads), the
/// best local minima over speed polished by nested Brent minimisers (Boost.Math
/// brent_find_minima: over speed, of the best over depth, of the best over
/// feed; an infeasible point costs more than any feasible one), the best
/// polished point returned. Cost: turning a few ms to 0.1 s; milling the sdm
/// limits and forced responses at the scan and polish speeds (seconds).
Optimum optimize(const OptimizationModel& model, const Corrections& correction = no_corrections(),
                 const OptimizeOptions& options = {});

/// The objective and the failing constraints over speed × feed at depth_m
/// (`speed_points`, `feed_points` >= 2 evenly spaced over the bounds).
LossMap loss_map(const OptimizationModel& model, double depth_m, int speed_points, int feed_points,
                 const Corrections& correction = no_corrections());

// ================================================================ adapt

/// The controller's state between two measurements.
struct AdaptState {
  SetPoint point;                        ///< the set-point being cut (measured next)
  Corrections correction = no_corrections();  ///< measured / predicted per index so far
  int iteration = 0;                     ///< measurements taken
  double loss = std::numeric_limits<double>::quiet_NaN();  ///< loss of the last measurement
  bool converged = false;                ///< the last step moved less than kAdaptConvergedStep
};
/// A step shorter than this (in bound ranges) is convergence.
inline constexpr double kAdaptConvergedStep = 1e-3;

struct AdaptStepResult {
  AdaptState next;                 ///< the corrected models and the next set-point
  Performance measured;            ///< at state.point: the measurement, its loss and constraints
  Performance corrected_optimum;   ///< the optimum of the corrected models
  bool optimum_found = false;
  double target = 0.0;             ///< the objective aimed at: max(γ P, P_min) for the loss
  double step = 0.0;               ///< the move, in bound ranges
};

/// One step of the loop (docs/optimization.md): correct each measured index's
/// model by measured / predicted at state.point (an unmeasured index keeps
/// its correction), find the corrected optimum, and move toward it: along
/// the segment from the set-point to the optimum, at most settings.max_step
/// (in bound ranges), to the first point whose corrected loss reaches the
/// relaxed target max(γ × measured loss, optimum's loss) (another objective:
/// the optimum itself), never to a point that fails a constraint. From an
/// infeasible set-point: to the first feasible point on that segment. When a
/// band of infeasible points (an unstable speed range) lies on the way, the
/// move jumps it to its first feasible point when nothing before it improves.
/// `measurement`: the indices measured at state.point (NaN: not measured).
AdaptStepResult adapt_step(const OptimizationModel& model, const AdaptState& state, const IndexValues& measurement,
                           const AdaptSettings& settings, const OptimizeOptions& options = {});

/// A bias of the simulated plant: index `index` (or every index when empty)
/// reads `fraction` × the model higher from iteration `from_iteration` on.
struct PlantBias {
  std::optional<PerformanceIndex> index;
  double fraction = 0.0;
  int from_iteration = 1;
};
/// A bias written "INDEX=PERCENT@ITERATION" (INDEX "all" or an index name of
/// the operation; e.g. "all=5@15"), as `chatter adapt --bias` and Python take it.
/// @throws InputError naming the text and the form.
PlantBias parse_plant_bias(const std::string& text, Operation operation);

struct AdaptPlan {
  int iterations = 0;                    ///< >= 1
  std::optional<SetPoint> start;         ///< default: the centre of the bounds
  std::vector<PlantBias> biases;         ///< the plant: the forward models with these biases
  /// Or measurements, one row per iteration (NaN: not measured; the loop
  /// stops when they run out). Not with biases.
  std::vector<IndexValues> measurements;
};
/// One iteration: the set-point cut, what was measured there and its loss.
struct AdaptRow {
  int iteration = 0;
  Performance measured;
  double target = 0.0;
  double step = 0.0;
};
struct AdaptRun {
  std::vector<AdaptRow> rows;
  AdaptState final_state;
  Optimum reference;  ///< the optimum of the uncorrected models
};
/// The loop over plan.iterations (or the measurement rows).
/// @throws InputError on a bad plan (iterations < 1, biases with measurements,
///         a start outside the bounds).
AdaptRun adapt(const OptimizationModel& model, const AdaptPlan& plan, const AdaptSettings& settings,
               const OptimizeOptions& options = {});

}  // namespace chatter
