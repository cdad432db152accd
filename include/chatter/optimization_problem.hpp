// The process-optimisation problem as plain data (docs/optimization.md,
// docs/optimization.md): the performance indices of a cut, the weighted loss
// that combines them (a Taguchi-style loss, seed 003), the constraints, the
// bounds of the set-point and the closed-form index models (removal rate,
// roughness, tool life, cost and production rate). Read from a config's
// `[optimization]` table by the io layer; evaluated, optimised and corrected
// online by the ops layer (chatter/optimization.hpp).
//
// Units: the indices are in the units of their names (µm, mm³/s, per hour,
// N: the loss coefficients α are defined in these units, as in the seed);
// set-points in SI (m, rev/min) like the rest of the library.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/process.hpp"

namespace chatter {

// ============================================================== the indices

/// The performance indices, in a fixed order (the C API's index numbers).
/// The first kLossIndexCount enter the loss; the force is a constraint and a
/// measurement only.
enum class PerformanceIndex : int {
  kDimensionalError = 0,  ///< turning: diametral error 2δ; milling: |surface location error|, µm
  kRoughness = 1,         ///< arithmetic mean roughness Ra, µm
  kRemovalRate = 2,       ///< material removal rate, mm³/s
  kCost = 3,              ///< cost of the operation per part (the shop's currency)
  kProductionRate = 4,    ///< parts per hour
  kForce = 5,             ///< largest resultant cutting force, N
};
inline constexpr std::size_t kIndexCount = 6;
inline constexpr std::size_t kLossIndexCount = 5;
using IndexValues = std::array<double, kIndexCount>;
/// Every index NaN (not known).
IndexValues unknown_indices();

/// The key of an index in configs, records and `--index`: "diametral_error_um"
/// (turning) or "surface_location_error_um" (milling), "surface_roughness_um",
/// "removal_rate_mm3_per_s", "cost", "production_rate_per_h", "force_n".
std::string_view index_name(PerformanceIndex index, Operation operation);
/// The index named `name` for this operation; nullopt when none is.
std::optional<PerformanceIndex> index_from_name(std::string_view name, Operation operation);
/// The names of the operation's indices, comma separated (for messages).
std::string index_names(Operation operation);

/// Which way an index is better. A smaller-is-better index has a largest
/// acceptable ("max") critical value and the loss term α x²; a larger-is-
/// better one a smallest acceptable ("min") critical value and α / x.
enum class Sense { kSmallerIsBetter, kLargerIsBetter };
Sense index_sense(PerformanceIndex index);
/// "max" (the critical value is a maximum) or "min".
std::string_view sense_name(Sense sense);

// ================================================================= the loss

/// P = Σ α_i g_i(x_i): α_i = β_i P_c / x_c,i² with g = x² for a smaller-is-
/// better index, α_i = β_i P_c x_c,i with g = 1/x for a larger-is-better
/// one (docs/optimization.md; seed 003 eq. 1.13–1.18).
struct LossSpec {
  /// P_c, the critical loss (currency per part, > 0): the part's value plus
  /// the cost of the operations before and of this one in the seed.
  double critical_loss = 0.0;
  /// β_i, fractions in [0, 1] summing to 1 (the config gives percent).
  std::array<double, kLossIndexCount> weight{};
  /// x_c,i (> 0 where the weight is > 0; NaN where it is 0).
  std::array<double, kLossIndexCount> critical{};
};
/// α_i (0 where β_i = 0).
std::array<double, kLossIndexCount> loss_alpha(const LossSpec& spec);
/// α_i g_i(x_i): 0 when α_i = 0; +inf for x <= 0 of a larger-is-better
/// index; NaN when x is NaN and α_i > 0.
double loss_term(PerformanceIndex index, double alpha, double value);

// ============================================================ index models

/// Surface roughness Ra. Geometric: the feed marks of a round nose (or edge)
/// of radius r_ε: Ra = f²/(32 r_ε) (f the feed per revolution in turning, per
/// tooth in milling). Fit: a polynomial of second order at most in the
/// cutting speed V (m/min), the feed f (mm) and the depth d (mm), Ra in µm,
/// floored at 0 (seed 003's Ra = 3.133 − 0.0082 V + 12.54 f + 0.195 d).
struct RoughnessModel {
  enum class Kind { kGeometric, kFit };
  Kind kind = Kind::kGeometric;
  double nose_radius_m = 0.0;  ///< geometric: r_ε (> 0)
  /// Fit: Ra = c0 + cv V + cf f + cd d + cvv V² + cff f² + cdd d² + cvf V f + cvd V d + cfd f d.
  double c0 = 0.0, cv = 0.0, cf = 0.0, cd = 0.0, cvv = 0.0, cff = 0.0, cdd = 0.0, cvf = 0.0, cvd = 0.0, cfd = 0.0;
  /// Ra in µm at V (m/min), feed (m) and depth (m).
  double roughness_um(double cutting_speed_m_per_min, double feed_m, double depth_m) const;
};

/// Tool life, cost and production rate of one operation per part (seed 003
/// eq. 0.2–0.9, with Taylor's law the right way round: V T^n = C, T =
/// (C/V)^(1/n); docs/optimization.md). Times in minutes, rates per hour.
struct Economics {
  double taylor_c_m_per_min = 0.0;  ///< C: the speed of a one-minute tool life, m/min (> 0)
  double taylor_n = 0.0;            ///< n in (0, 1)
  double cut_length_mm = 0.0;       ///< L + e: the tool's path in the cut and its margin, mm (> 0)
  double setup_time_min = 0.0;      ///< t_regl: setting up, per part (>= 0)
  double index_time_min = 0.0;      ///< t_i: indexing or changing to the tool (>= 0)
  double approach_time_min = 0.0;   ///< t_a: rapid approach and return (>= 0)
  double tool_change_time_min = 0.0;  ///< t_r: replacing a worn tool (>= 0)
  double machine_rate_per_h = 0.0;  ///< S_usinage: machine and operator, per hour (>= 0)
  double tool_cost = 0.0;           ///< C_outil: one tool (insert) (>= 0)
  double tool_uses = 1.0;           ///< n_utilisation: cutting edges (or regrinds) per tool (>= 1)
  double tooling_rate_per_h = 0.0;  ///< S_outillage: the tool room, per hour (>= 0)
  double sharpening_time_min = 0.0;  ///< t_affutage (>= 0)
  double preset_time_min = 0.0;     ///< t_préréglage (>= 0)
};
/// The times and money of one operation at a set-point.
struct OperationEconomics {
  double tool_life_min = 0.0;       ///< T = (C/V)^(1/n)
  double cutting_time_min = 0.0;    ///< t_c = (L + e)/(f_rev N)
  double operation_time_min = 0.0;  ///< t_op = t_i + t_a + t_c + (t_c/T) t_r
  double cost = 0.0;                ///< C_op = S t_op + (t_c/T)(C_tool/n + S_tool (t_sharp + t_preset))
  double production_rate_per_h = 0.0;  ///< 60 / (t_regl + t_op)
};
/// @pre V > 0, feed per revolution > 0, rpm > 0.
OperationEconomics operation_economics(const Economics& e, double cutting_speed_m_per_min,
                                       double feed_per_rev_m, double spindle_rpm);

// =========================================================== the constraints

/// Limits on the indices and the cut (absent: not constrained). Stability is
/// on by default: depth <= depth limit / stability_margin, the depth limit
/// the smallest over the positions evaluated (docs/optimization.md).
struct ConstraintLimits {
  std::optional<double> max_force_n, max_power_w, max_torque_n_m;
  std::optional<double> max_dimensional_error_um, max_roughness_um, min_removal_rate_mm3_per_s;
  std::optional<double> max_cost, min_production_rate_per_h;
  bool stability = true;
  double stability_margin = 1.0;  ///< >= 1
};

// ============================================================= the problem

enum class Objective { kLoss, kRemovalRate, kCost, kProductionRate };
/// "loss", "removal_rate", "cost", "production_rate".
std::string_view objective_name(Objective objective);

/// A closed interval; lo == hi: the variable is fixed.
struct Bounds {
  double lo = 0.0, hi = 0.0;
  bool fixed() const { return lo == hi; }
};

/// The adaptive loop's tuning (docs/optimization.md).
struct AdaptSettings {
  /// γ in (0, 1]: each step aims at a loss γ × the current one (never below
  /// the corrected optimum's); 0.95 in seed 003.
  double gamma = 0.95;
  /// Largest move per iteration, a fraction of each variable's bound range
  /// (the Euclidean length of the move in those units), in (0, 1].
  double max_step = 0.1;
};

/// Everything `[optimization]` says (docs/config.md, "Optimization").
struct OptimizationSpec {
  Objective objective = Objective::kLoss;
  /// Spindle speed bounds, rev/min (given as cutting speed m/min or as rpm).
  Bounds speed_rpm;
  bool speed_as_cutting_speed = true;  ///< the config gave cutting_speed_m_per_min
  /// Feed per revolution (turning) or per tooth (milling), m.
  Bounds feed_m;
  /// Depth of cut (turning: the chip width b; milling: the axial depth), m.
  Bounds depth_m;
  /// Workpiece (turning) or tool (milling) diameter, m (> 0): from [process].
  double diameter_m = 0.0;
  /// Turning: the tangential specific cutting force K_c, N/m² (0 = not given:
  /// no force, power or torque; must be 0 when the process follows Kienzle's
  /// law, whose tangential term gives them). Milling uses the process's K_t
  /// and K_r.
  double cutting_coefficient_n_per_m2 = 0.0;
  LossSpec loss;
  ConstraintLimits constraints;
  std::optional<RoughnessModel> roughness;
  std::optional<Economics> economics;
  /// Positions evaluated along a position-dependent part when no tool
  /// position is given (>= 2): the worst diametral error and the smallest
  /// depth limit over them.
  int position_points = 9;
  AdaptSettings adapt;

  /// Empty when the spec is usable for `process` (its operation, and
  /// whether its cutting law gives the turning force), else the first
  /// violated rule naming the field ("OptimizationSpec::feed_m: lo = 0: must
  /// be > 0"). The config reader checks every rule with its key first.
  std::string validate(const Process& process) const;
};

// ============================================== what the io layer draws

/// The objective over the (speed, feed) plane at one depth, and where each
/// constraint fails (`chatter optimize --plot`, io/plot_optimization.hpp).
struct LossMap {
  bool milling = false;
  double depth_m = 0.0;
  std::vector<double> speeds_rpm;           ///< ascending
  std::vector<double> feeds_m;              ///< ascending
  /// The loss (objective "loss"; else the objective's own value: removal
  /// rate mm³/s, cost, parts per hour) at [speed × feeds + feed]; NaN where
  /// it does not exist (an unstable milling cut has no surface location error).
  std::vector<double> value;
  std::string value_label;                  ///< "loss", "removal rate, mm^3/s", ...
  /// The constraints that can fail, in the order of `failing`'s bits.
  std::vector<std::string> constraint_names;
  /// Bit c set: constraint c fails at the cell (same layout as `value`).
  std::vector<unsigned> failing;
  /// Index of "stability_margin" in constraint_names, or -1 without it.
  int stability_bit = -1;
  double cutting_speed_per_rpm = 0.0;       ///< V (m/min) per rev/min: π D
};

/// Cutting speed V = π D N, m/min (D in m, N in rev/min).
double cutting_speed_m_per_min(double diameter_m, double spindle_rpm);
/// N = V / (π D), rev/min (V in m/min, D in m).
double spindle_rpm_of(double diameter_m, double cutting_speed_m_per_min);

}  // namespace chatter
