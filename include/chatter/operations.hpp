// Operations for CAM post-processing (issue 6): read a list of planned
// operations, check each against the stability lobes, recommend the spindle
// speed and depth that remove the most material, and answer "is (rpm, depth)
// stable?" fast from a precomputed, adaptively refined lobe table.
//
// Units: SI inside (m, W, N·m, N/m²); spindle speeds in rev/min where a name
// says `rpm`. The operations file itself is in shop units (mm), converted on
// reading. The user guide is docs/operations.md.
//
// Solvers come only from make_lobe_solver() (chatter/solvers.hpp); method
// "auto" (the default) is resolved by resolve_lobe_method there.
//
// Thread safety: every function here is re-entrant; LobeTableQuery is
// immutable after construction, so any number of threads may query one table.
#pragma once

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"
#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/results.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

// ============================================================== machine

/// What the machine allows. The speed range bounds every suggestion and every
/// row of an operations file; power and torque bound the recommendation.
struct MachineLimits {
  double rpm_min = 0.0;  ///< lowest spindle speed, rev/min (> 0).
  double rpm_max = 0.0;  ///< highest spindle speed, rev/min (> rpm_min).
  /// Largest mean cutting power at the spindle, W (> 0; +inf = no limit).
  double max_power_w = std::numeric_limits<double>::infinity();
  /// Largest mean cutting torque at the spindle, N·m (> 0; +inf = no limit).
  double max_torque_n_m = std::numeric_limits<double>::infinity();

  /// Empty string when valid, else the violated rule, e.g.
  /// "MachineLimits::rpm_max = 100: must be > rpm_min (200)".
  std::string validate() const;
};

// ======================================================= fast lobe queries

struct LobeTableQueryOptions {
  /// Exact solves on a base grid evenly spaced in the delay τ ∝ 1/rpm (>= 2):
  /// lobes are evenly spaced in τ, so every lobe gets about the same number
  /// of points whatever the speed.
  int base_points = 400;
  /// Target interpolation error, m (>= 0). 0: relative_tolerance × the
  /// smallest finite depth limit of the base grid (the scale of the lobes).
  double tolerance_m = 0.0;
  /// Used when tolerance_m == 0 (in (0, 1)).
  double relative_tolerance = 1e-3;
  /// Stop refining at this many table points (>= base_points); intervals left
  /// unresolved are counted and widen the stated error bound.
  int max_points = 200000;
  /// Threads solving the table points (0 = every core). The table is the
  /// same whatever the count: points are solved a round of midpoints at a
  /// time and stored in a fixed order.
  unsigned threads = 1;

  /// Empty string when valid, else the violated rule (Ceres-style).
  std::string validate() const;
};

/// What a query says about a (speed, depth) point.
enum class QueryVerdict {
  kStable,     ///< depth below the interpolated limit by more than the error bound
  kUnstable,   ///< depth above the interpolated limit by more than the error bound
  kUncertain,  ///< within the error bound of the limit (or at/above depth_max): solve exactly
};

/// A lobe table over [rpm_min, rpm_max] built from exact solves, answering
/// depth-limit and stability queries by interpolation, O(log n) per query.
///
/// Construction (cost: one limit_at per table point, shared among
/// options.threads threads):
///  1. exact limit_at() on `base_points` speeds evenly spaced in 1/rpm;
///  2. every interval [a, b] (in 1/rpm) is checked at its midpoint m: it is
///     split while |g(m) − (g(a) + g(b))/2| > tolerance/2 (steep flanks,
///     curvature, cusps where two lobes meet) or while the lobe numbers at a
///     and b differ by more than one (a whole lobe could hide between them),
///     with g = min(depth limit, depth_max). The midpoint is kept as a table
///     point either way. An interval whose ends lie on different lobes (a cusp
///     inside, where the convex lobe bottom and the cusp can cancel at the
///     midpoint) must pass twice: its two halves are checked again. Splitting
///     stops at a width of 1e-9 of the range; such an interval is
///     "unresolved".
/// Interpolation is linear in 1/rpm between the two neighbouring points.
///
/// Error bound (error_bound_m()): the tolerance when every interval was
/// resolved, else the largest midpoint error of an unresolved interval (×2).
/// It is an estimate, not a proof: on an interval holding one cusp between
/// two nearly straight lobe flanks the interpolation error is at most twice
/// the midpoint error (hence the split threshold tolerance/2), and on a
/// smooth piece about a quarter of it once the midpoint is inserted.
/// Measured against exact solves at 200 000 random speeds on the four shipped
/// configs with 50–1 000 base points and relative tolerances 1e-2–1e-4: worst
/// error 0.95 × the bound (docs/operations.md); tests/test_operations.cpp
/// checks it at random speeds.
/// Limits above the solver's depth_max are stored as depth_max, so the bound
/// holds for min(limit, depth_max).
class LobeTableQuery {
 public:
  /// @pre 0 < rpm_min < rpm_max.
  /// @throws InputError on an invalid range or options.
  LobeTableQuery(const LobeSolver& solver, double rpm_min, double rpm_max, LobeTableQueryOptions options = {});

  /// Interpolated depth limit at `rpm` (m), within error_bound_m() of
  /// min(exact limit, depth_max_m()); +inf when both neighbouring table points
  /// have no limit below depth_max_m().
  /// @throws InputError if rpm is outside [rpm_min(), rpm_max()].
  double depth_limit(double rpm) const;
  /// depth_m < depth_limit(rpm). Agrees with the exact solver except when
  /// depth_m is within error_bound_m() of the limit (or >= depth_max_m()).
  bool is_stable(double rpm, double depth_m) const;
  /// Stable / unstable with the error bound as a guard band, else uncertain.
  QueryVerdict classify(double rpm, double depth_m) const;

  /// The stated interpolation error bound, m.
  double error_bound_m() const { return error_bound_m_; }
  /// Target tolerance used for refinement, m.
  double tolerance_m() const { return tolerance_m_; }
  /// Intervals that reached the minimum width (or the point budget) with an
  /// error estimate above the tolerance; 0 in a healthy table.
  std::size_t unresolved_intervals() const { return unresolved_; }
  double rpm_min() const { return rpm_.front(); }
  double rpm_max() const { return rpm_.back(); }
  double depth_max_m() const { return depth_max_m_; }
  std::string method() const { return method_; }
  /// The exact table points (ascending speed), as limit_at() returned them.
  const std::vector<StabilityLimit>& points() const { return points_; }
  std::size_t size() const { return rpm_.size(); }

 private:
  std::size_t interval(double rpm) const;  // i with rpm_[i] <= rpm <= rpm_[i+1]
  std::vector<double> rpm_;                // ascending
  std::vector<double> inv_rpm_;            // 1/rpm_
  std::vector<double> g_;                  // min(limit, depth_max), m
  std::vector<unsigned char> bounded_;     // limit below depth_max
  std::vector<StabilityLimit> points_;
  double depth_max_m_ = 0.0;
  double tolerance_m_ = 0.0;
  double error_bound_m_ = 0.0;
  std::size_t unresolved_ = 0;
  std::string method_;
};

/// The speed in [table range] with the largest exact depth limit: the best
/// table point, refined by Brent's minimiser (golden section with parabolic
/// steps, Boost.Math brent_find_minima) on solver.limit_at() between its two
/// neighbours (the maximum of the envelope is a cusp between two lobes or a
/// smooth peak; the search stops once the speed is located to about 1e-8 of
/// itself, ≈ 20–40 solves). The best of every evaluated point is
/// returned. When no table
/// point has a limit below depth_max, returns the table point nearest to
/// (rpm_min + rpm_max)/2 with depth_limit_m = +inf.
StabilityLimit best_speed(const LobeSolver& solver, const LobeTableQuery& table);

// ========================================================= robust speeds

/// Default speed tolerance of check and recommend: a spindle holds its set
/// speed to about ±1–2 % under load, and the model is not exact either.
inline constexpr double kDefaultSpeedTolerance = 0.02;

/// A spindle speed with the stability around it: the pocket and the worst
/// limit the spindle meets when its speed is off by up to ± tolerance.
struct SpeedPocket {
  StabilityLimit limit;            ///< exact at limit.spindle_rpm (+inf above the searched depth)
  double speed_tolerance = 0.0;    ///< fraction (0.02 = ±2 %)
  /// Smallest exact limit over [N(1 − tol), N(1 + tol)], m (the band may
  /// reach past the machine range: the spindle's error does not stop there);
  /// +inf when none is below the searched depth anywhere in the band. A band
  /// holding many lobes at low speed is sampled (see robust_speed(): the
  /// smallest of exact limits in the band, within 5 % of the full search).
  double worst_limit_m = 0.0;
  double worst_margin = 0.0;       ///< worst_limit_m / depth (+inf if unbounded)
  /// The connected speed interval around N where the limit exceeds the
  /// threshold depth (the depth itself in check, depth / safety in
  /// recommend), rev/min, searched inside the machine range: an edge equal
  /// to rpm_min or rpm_max means the pocket reaches the end of the range.
  double pocket_min_rpm = 0.0, pocket_max_rpm = 0.0;
};

/// The speed in [rpm_min, rpm_max] whose worst limit over ± speed_tolerance is
/// largest (with speed_tolerance = 0: the highest point of the envelope, a
/// cusp), and its pocket at `depth_m`. Empty when even that worst limit is
/// not above depth_m (no speed in range is stable over the whole band).
///
/// Method (docs/operations.md "Search"): a scan evenly spaced in 1/rpm — 24
/// solves, then ≈ 8 per lobe, the lobe count from the lobe numbers of the
/// first 24 (at most 2 000 solves) — ranks the speeds by the worst limit in
/// their band; the best (and any other within 10 %, at most 3) is refined by
/// Brent's minimiser on exact solves (speed located to 1e-4 of itself, 1e-8 at
/// tolerance 0). The worst limit in a band is the smaller end value or a
/// lobe bottom inside (found by the same minimiser between scan
/// points); pocket edges by bracketed regula falsi (Illinois) to 1e-4 of the
/// speed. Cost: the scan plus ≈ 40–80 solves.
///
/// Low speed (speed_tolerance > 0), where lobes crowd and every solve is
/// dearer (sdm: steps ∝ 1/rpm): the first 24 solves cover only speeds >=
/// rpm_max / 10 and the scan stops where a band holds a quarter of a lobe.
/// Below (the dense region), rules that are stated and bounded:
///  - the optimum: it is kept only if every band of the dense region holds a
///    speed where the solver finds the depth of the optimum's worst limit
///    unstable (LobeSolver::stable_at, or an exact limit at or below it):
///    then no speed there has a higher worst limit; the test speeds are a
///    band's width apart. Where that cannot be shown, the scan is extended
///    down past it (at least ×1.5 in speed) and the optimum ranked again. No
///    approximation: the optimum is the one the full scan would rank.
///  - the worst limit of a band outside the scan holding two lobes or more
///    (lobe numbers at its ends): the smallest exact limit at 9 speeds evenly
///    spaced in 1/rpm (ends included), its centre and the vertex of the
///    parabola through each of the two lowest sampled local minima. An exact
///    limit in the band, so never below the true worst limit; measured above
///    the full search's by at most 0.22 % on the shipped configs, except
///    case C at 100–260 rev/min: up to 4.5 %, where the sdm envelope is
///    jagged (docs/operations.md); held to 5 % (tests/test_operations.cpp).
///    Fewer lobes: 8 samples per lobe and every sampled local minimum
///    refined by Brent, as in the scan.
///  - pocket edges below the scan: the limit is tested (limit_above) at
///    speeds a band's width apart; a dip below the threshold narrower than
///    that can be missed.
/// Case C, a 0.5 mm row at 200 rev/min over 100–25 000 rev/min (check): 61
/// solves for the scan, 35 further exact solves, 97 stable_at verdicts and
/// 95 limit_above tests.
/// @pre 0 < rpm_min < rpm_max, depth_m > 0, 0 <= speed_tolerance < 0.5.
/// @throws InputError on a violated precondition.
std::optional<SpeedPocket> robust_speed(const LobeSolver& solver, double rpm_min, double rpm_max, double depth_m,
                                        double speed_tolerance = kDefaultSpeedTolerance, unsigned threads = 1);

/// Checks a speed tolerance (a fraction); "" when valid, else the rule with
/// `name` (the option or field) in percent, e.g.
/// "--speed-tolerance-pct = -1: must be >= 0 and < 50 (percent)".
std::string validate_speed_tolerance(double speed_tolerance, const std::string& name);

/// Table options for locating optima on a table: relative_tolerance 1e-2,
/// the rest default (≈ 1 200 sdm solves on case C; check and recommend no
/// longer build a table, see robust_speed()).
inline LobeTableQueryOptions coarse_table() {
  LobeTableQueryOptions o;
  o.relative_tolerance = 1e-2;
  return o;
}

// ===================================================== operations file

/// One operation as read from an operations file.
struct OperationRow {
  int line = 0;                                  ///< 1-based line in the file.
  std::string id;                                ///< unique, non-empty
  double spindle_rpm = 0.0;                      ///< rev/min, in the machine range
  double depth_m = 0.0;                          ///< depth of cut (axial in milling), m, > 0
  double depth_mm = 0.0;                         ///< the same as written (mm): what the reports echo
  std::optional<double> radial_immersion;        ///< a_e/D in (0, 1]; empty = the config's (milling only)
  std::optional<double> feed_per_tooth_m;        ///< m (per revolution in turning), > 0; empty = not given
  std::optional<double> feed_per_tooth_mm;       ///< the same as written (mm)
  std::optional<int> teeth;                      ///< override of the config's teeth (milling only)
  std::optional<MillingDirection> direction;     ///< override of the config's direction (milling only)
  /// The part's tolerance, m (> 0; the `max_sle_um` or `tolerance_um`
  /// column): on |SLE| in milling, on the diametral error in turning
  /// (forced_check); empty = not given.
  std::optional<double> max_error_m;
};

/// A row that could not be read; the others are still checked.
struct RejectedRow {
  int line = 0;       ///< 1-based line in the file
  std::string id;     ///< as written (may be empty)
  std::string reason; ///< e.g. "depth_mm = -1: must be > 0"
};

struct OperationsFile {
  std::vector<OperationRow> rows;
  std::vector<RejectedRow> rejected;
};

/// Parses an operations CSV (docs/operations.md): a header line naming the
/// columns `id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm` (any
/// order; optional `teeth`, `milling_direction`), then one operation per line.
/// Blank lines and lines starting with '#' are skipped; fields may be quoted
/// ("a,b"); a UTF-8 byte-order mark and CR line ends are accepted.
/// A row is rejected (with its line and reason) when it has too few or too
/// many fields, a non-numeric or non-finite number, depth <= 0, rpm <= 0 or
/// outside [machine.rpm_min, machine.rpm_max], immersion outside (0, 1],
/// feed <= 0, teeth < 1, an unknown direction, a milling-only field in a
/// turning process, an empty or duplicate id.
/// @throws InputError "<origin>:<line>: ..." on a file-level problem: no
///         header, an unknown, duplicated or missing column in the header.
OperationsFile parse_operations(std::string_view text, const std::string& origin, Operation operation,
                                const MachineLimits& machine);
/// Same, from a file. @throws InputError also if the file cannot be read.
OperationsFile read_operations(const std::filesystem::path& file, Operation operation, const MachineLimits& machine);

/// The process of one row: `base` with the row's immersion, teeth and
/// direction overrides (milling), linearised at the row's feed when the
/// turning process follows Kienzle's law (Process::at_feed).
/// @throws InputError if the result is invalid.
Process process_for(const Process& base, const OperationRow& row);

/// The forced vibration of one operation (issue 27, docs/forced.md;
/// src/ops/forced_check.cpp): what `check` reports per row with a feed.
struct OperationForced {
  ForcedResponse response;     ///< at the row's speed, depth and feed, on its process
  /// The part error the tolerance applies to, m: |SLE| in milling, the
  /// diametral error 2δ in turning; NaN when the cut is unstable.
  double part_error_m = 0.0;
  /// part_error_m <= row.max_error_m (true without a tolerance); empty when
  /// the cut is unstable: no steady part error exists to hold against a
  /// tolerance (the row counts as unstable, not as out of tolerance).
  std::optional<bool> within_tolerance;
};
/// The forced response of `row` (its process_for(base, row)), empty when the
/// row gives no feed. Cost: one ForcedResponseSolver response (~1–10 ms).
/// @throws InputError as ForcedResponseSolver (e.g. measured FRFs).
std::optional<OperationForced> forced_check(const StructuralModel& model, const Process& base, const OperationRow& row);

// ====================================================== the cutting load

/// The cutting law's options of the commands that report a cut's power and
/// torque (check, recommend, chatter_cutting_load; docs/cutting_law.md):
/// turning takes the tangential coefficient K_c when given, else the
/// feed-force coefficient K_f as its cutting pressure (an underestimate: with
/// force angle θ the true value is K_f·tanθ), said once in `warnings`;
/// milling needs nothing more (K_t is the process's).
inline CuttingLawOptions cutting_law_options(const Process& process, std::optional<double> kc,
                                             std::vector<std::string>& warnings) {
  CuttingLawOptions o;
  if (process.operation() != Operation::kTurning) return o;
  if (process.has_size_effect()) {  // Kienzle's tangential term is the cutting force
    if (kc) throw InputError(kKienzleTakesTheTangential);
    return o;
  }
  o.turning_tangential_coefficient_n_per_m2 = kc.value_or(process.turning_parameters().feed_force_coefficient_n_per_m2);
  if (!kc) {
    const std::string w = "turning power and torque use the feed-force coefficient K_f as cutting pressure (no "
                          "tangential coefficient given); with force angle θ the true value is K_f·tanθ, larger";
    if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
  }
  return o;
}

// ============================================================== check

struct CheckOptions {
  /// Speed range for the row checks and suggestions; the power and torque
  /// limits judge the rows' cutting load (OperationCheck::load).
  MachineLimits machine;
  std::string method = "auto";      ///< "auto" or a name from lobe_methods()
  /// Depth searched for each operation: max(search_depth_factor × depth,
  /// search_depth_min_m). A limit above it is reported as +inf (margin +inf).
  double search_depth_factor = 4.0;
  double search_depth_min_m = 0.02;
  /// Speed error the suggestion must tolerate, a fraction in [0, 0.5): the
  /// suggested speed maximises the worst limit over ± this (robust_speed()).
  /// 0: the old exact-speed behaviour (the highest cusp).
  double speed_tolerance = kDefaultSpeedTolerance;
  /// Usable flute length of the cutter, m (milling; empty = not known): a
  /// row deeper than it gets a warning.
  std::optional<double> flute_length_m;
  /// Threads for the scans and the per-row solves (0 = every core); the
  /// report is the same whatever the count.
  unsigned threads = 1;
  /// Called with an estimate of the fraction of the work done (0..1; 1 at
  /// the end) after every exact solve, from worker threads: keep it cheap and
  /// thread-safe. For a progress bar; may be empty.
  std::function<void(double)> progress;
  /// The cutting load of the rows with a feed (docs/cutting_law.md): the
  /// tool's diameter in milling, the workpiece's at the cut in turning, m;
  /// 0 = not known (torque, power and removal rate are then NaN, and a
  /// power or torque limit cannot be judged: validate() refuses it).
  double diameter_m = 0.0;
  /// Turning: the tangential coefficient K_c, N/m² (> 0), for power and
  /// torque; empty = the feed-force coefficient K_f, with a warning (as
  /// recommend). Milling: unused (K_t is the process's).
  std::optional<double> cutting_coefficient_n_per_m2;

  std::string validate() const;
};

/// The mean cutting load of one operation (the cutting law,
/// docs/cutting_law.md) against the machine's power and torque.
struct OperationLoad {
  double mean_force_n = 0.0;          ///< mean tangential (cutting) force, teeth summed, N
  double torque_n_m = 0.0;            ///< mean spindle torque, N·m (NaN without a diameter)
  double power_w = 0.0;               ///< mean cutting power, W (NaN without a diameter)
  double removal_rate_m3_per_s = 0.0; ///< material removal rate, m³/s (NaN without a diameter)
  bool within_power = true;           ///< power <= machine.max_power_w
  bool within_torque = true;          ///< torque <= machine.max_torque_n_m
};

/// The verdict on one operation.
struct OperationCheck {
  OperationRow op;
  std::string method;               ///< solver used
  double search_depth_m = 0.0;      ///< deepest limit searched for this row
  StabilityLimit limit;             ///< exact, at op.spindle_rpm; +inf above search_depth_m
  bool stable = false;              ///< op.depth_m < limit.depth_limit_m
  double margin = 0.0;              ///< limit / depth; +inf when unbounded
  /// Suggested speed in the machine range with the largest worst margin
  /// over its band speed × (1 ± options.speed_tolerance) for the same depth
  /// (exact limit at the speed itself); empty when no speed in range is
  /// stable over its whole band at this depth ("none in range"). When the
  /// worst limit exceeds the searched depth at several speeds (margin +inf),
  /// the scanned one nearest op.spindle_rpm (the row's own speed if its band
  /// is such). With speed_tolerance 0: the largest exact margin (a cusp).
  std::optional<StabilityLimit> suggestion;
  double suggestion_margin = 0.0;   ///< suggestion limit / depth (+inf if unbounded)
  /// Worst margin (smallest limit / depth) over op.spindle_rpm × (1 ± tol):
  /// below 1 the row is stable only if the spindle holds its speed exactly.
  /// A band holding two lobes or more below the scan (low speed) is sampled
  /// (robust_speed(): an exact limit in the band, within 5 % of the full
  /// search).
  double worst_margin = 0.0;
  /// The suggestion's band and pocket (worst_margin there; pocket edges at
  /// this row's depth); set whenever `suggestion` is.
  std::optional<SpeedPocket> suggestion_pocket;
  /// The forced vibration at the row's speed, depth and feed (its SLE or
  /// diametral error, teeth leaving the cut, the part's tolerance): set when
  /// the row gives a feed (forced_check).
  std::optional<OperationForced> forced;
  /// The same at the suggested speed (the row's depth, feed and tolerance):
  /// the part quality beside the suggestion; set when both are.
  std::optional<OperationForced> suggestion_forced;
  /// Why the suggestion is not the best-margin speed, or what it cannot
  /// hold: set when the best-margin speed breaks the row's part tolerance
  /// ("moved from N rev/min (part error ...) to ...", or "no other stable
  /// scanned speed holds it ..."); empty otherwise.
  std::string suggestion_note;
  /// The mean cutting load at the row's speed, depth and feed on its
  /// process: set when the row gives a feed.
  std::optional<OperationLoad> load;
};

struct CheckReport {
  std::vector<OperationCheck> checks;    ///< in file order (the rows that could be judged)
  /// Rows read but not judged, in line order, with the reason: overrides
  /// that make no cutter (teeth that contradict the config's pitch angles),
  /// or a solver that failed on the row. The other rows are still checked.
  std::vector<RejectedRow> not_judged;
  std::vector<std::string> warnings;     ///< e.g. kFlipLobeWarning, once each; per-row plausibility
  std::size_t unstable() const;
  /// Rows whose mean cutting power or torque exceeds the machine's.
  std::size_t overloaded() const;
  /// Rows with a tolerance (max_sle_um / tolerance_um) whose forced part
  /// error exceeds it, or that are unstable at their feed.
  std::size_t out_of_tolerance() const;
};

/// Checks every row (see OperationCheck). One solver and one robust speed
/// search per distinct (immersion, teeth, direction); per row one exact solve
/// at its speed (the verdict), the worst limit over its speed band and the
/// pocket edges of the suggestion. Cost: per distinct process the scan of
/// robust_speed() (≈ 24 + 8 per lobe solves, the dense low-speed region left
/// out) and ≈ 30 refining solves, per row ≈ 10–30 solves; a row at low speed
/// adds its band's samples and, when its suggestion's pocket reaches into
/// the dense region, one limit_above test per band width there. The row
/// loop is check_row() in src/ops/check.cpp.
/// @throws InputError on invalid options or an unknown method.
CheckReport check_operations(const StructuralModel& model, const Process& process,
                             const std::vector<OperationRow>& rows, const CheckOptions& options);

// ====================================================== recommendation

struct RecommendOptions {
  MachineLimits machine;
  /// Depth used ≤ safety × depth limit (in (0, 1]).
  double safety = 0.8;
  /// Feed per tooth, m (> 0); per revolution in turning.
  double feed_per_tooth_m = 0.0;
  /// Milling: tool diameter; turning: workpiece diameter at the cut, m
  /// (> 0, or 0 = unknown). Needed for power and torque limits and for MRR in
  /// m³/s; without it MRR is reported per metre of diameter.
  double diameter_m = 0.0;
  /// Deepest cut the tool allows, m (> 0); also sets the depth searched
  /// (2 × min(depth_max_m, flute_length_m) / safety).
  double depth_max_m = 0.05;
  /// Usable flute length of the cutter, m (milling; > 0; empty = not known):
  /// the depth never exceeds it (Binding::kFluteLength).
  std::optional<double> flute_length_m;
  /// Speed error the recommendation must tolerate, a fraction in [0, 0.5):
  /// depth ≤ safety × the worst limit over spindle_rpm × (1 ± tol).
  double speed_tolerance = kDefaultSpeedTolerance;
  /// Turning only: specific cutting force K_c (N/m²) in the mean cutting
  /// force F_c = K_c·b·f. Empty: the config's feed-force coefficient K_f
  /// (the only coefficient a turning config has; with a force angle θ the
  /// true K_c = K_f·tanθ is larger, so power and torque are then
  /// underestimated — a warning says so).
  std::optional<double> cutting_coefficient_n_per_m2;
  /// The part's tolerance on the forced vibration's error, m (> 0; empty =
  /// not a constraint): milling |surface location error|, turning the
  /// diametral error, of the linear forced response at the recommended feed
  /// (forced_check's part error; docs/forced.md). Binding::kSurfaceError.
  std::optional<double> max_part_error_m;
  std::string method = "auto";
  /// Threads for the scan (0 = every core); the result does not depend on it.
  unsigned threads = 1;
  /// Progress callback as in CheckOptions (may be empty).
  std::function<void(double)> progress;
  /// Leave unsolved the scan's speeds where no cut within the depth caps
  /// (power, torque, depth_max, flute) could remove as much as what the
  /// faster speeds already found (Recommendation::skipped_solves); the
  /// result is then checked against them and they are solved if it is not
  /// out of their reach. false: every scan speed solved.
  bool skip_out_of_reach = true;

  std::string validate() const;
};

/// What limits the recommended cut.
enum class Binding {
  kStability,   ///< depth = safety × depth limit
  kPower,       ///< mean power = max_power
  kTorque,      ///< mean torque = max_torque
  kDepthMax,    ///< depth = the tool's depth_max
  kSpeedRange,  ///< speed at rpm_min or rpm_max and MRR would grow beyond it
  kFluteLength, ///< depth = the cutter's usable flute length
  kSurfaceError,  ///< the forced vibration's part error = max_part_error_m
};
/// "stability", "power", "torque", "depth_max", "speed_range", "flute_length",
/// "surface_error".
std::string to_string(Binding b);

struct Recommendation {
  std::string method;
  /// Speeds of the scan left unsolved: no cut there, however deep its limit,
  /// removes as much as the recommendation within the depth caps (power,
  /// torque, depth_max, flute); 0 when every speed was solved.
  std::size_t skipped_solves = 0;
  double spindle_rpm = 0.0;
  double depth_m = 0.0;
  StabilityLimit limit;            ///< exact at spindle_rpm (+inf above the searched depth)
  double search_depth_m = 0.0;     ///< depth searched (2 × depth_max / safety)
  double margin = 0.0;             ///< limit / depth (>= 1/safety; +inf if unbounded)
  /// The four depth caps at spindle_rpm (m; +inf when not limited); depth_m
  /// is their minimum.
  double depth_stability_m = 0.0;  ///< safety × the worst limit over the speed band (pocket.worst_limit_m)
  double depth_power_m = 0.0;
  double depth_torque_m = 0.0;
  double depth_cap_m = 0.0;        ///< options.depth_max_m
  double depth_flute_m = 0.0;      ///< options.flute_length_m (+inf when not given)
  /// The deepest cut whose part error stays within max_part_error_m (+inf
  /// when not given or not binding below the other caps).
  double depth_part_error_m = std::numeric_limits<double>::infinity();
  /// The part error of the recommended cut (|SLE| milling, diametral error
  /// turning), m, from its forced response whether or not max_part_error_m
  /// is given; NaN for a measured-FRF model (no forced response).
  double part_error_m = std::numeric_limits<double>::quiet_NaN();
  /// The larger of the forced vibration's x and y peak-to-peak there, m
  /// (NaN as part_error_m).
  double peak_to_peak_m = std::numeric_limits<double>::quiet_NaN();
  /// Stability over the speed band: worst_limit_m is the smallest limit over
  /// spindle_rpm × (1 ± tol), worst_margin = worst_limit / depth (>= 1/safety),
  /// pocket edges where safety × limit >= depth.
  SpeedPocket pocket;
  /// Mean cutting force (N), torque (N·m), power (W); NaN without a diameter.
  double force_n = 0.0, torque_n_m = 0.0, power_w = 0.0;
  /// Material removal rate, m³/s (NaN without a diameter) and per metre of
  /// diameter, m²/s (always).
  double mrr_m3_per_s = 0.0;
  double mrr_per_diameter_m2_per_s = 0.0;
  std::vector<Binding> binding;    ///< every constraint that binds (at least one)
  std::vector<std::string> warnings;
};

/// The speed in [rpm_min, rpm_max] and depth maximising MRR subject to
/// depth ≤ safety × limit(rpm), mean power ≤ max_power, mean torque ≤
/// max_torque, depth ≤ depth_max and, when max_part_error_m is given, the
/// forced vibration's part error ≤ it (docs/physics.md §3 force model; see
/// docs/operations.md):
///   turning:  F_c = K_c b f,  T = F_c D/2,  P = F_c π D N/60,  MRR = b f π D N/60;
///   milling:  T = (D/2)(N_t/2π) K_t a f_z (cos φ_en − cos φ_ex),  P = T·2πN/60,
///             MRR = a (a_e/D·D) f_z N_t N/60   (so P = K_t·MRR).
/// For each speed the depth is the smallest cap, the stability cap being
/// safety × the worst limit over the speed band N(1 ± speed_tolerance); MRR is
/// maximised over the scan of robust_speed() (evenly spaced in 1/rpm, ≈ 8
/// solves per lobe), then by Brent's minimiser on exact solves between
/// the best scan points' neighbours. Ties in MRR (power-bound: MRR = P_max/K
/// is then the same at every speed) go to the largest worst margin. The
/// part-error cap at a speed: the depth where the error reaches the
/// tolerance, by Illinois regula falsi on [0, the other caps' minimum] to
/// 1e-4 of the depth (the error grows with depth, linearly for straight
/// teeth: one or two forced responses then), each a forced response (about
/// one sdm analysis).
/// @throws InputError on invalid options, or on a power/torque limit without
///         a diameter.
Recommendation recommend(const StructuralModel& model, const Process& process, const RecommendOptions& options);

/// A few lines for a person: speed, depth, what binds, margin, MRR, power.
std::string explain(const Recommendation& r, const RecommendOptions& options);

}  // namespace chatter
