// Results shared by every lobe solver, and the interface they implement.
// Depths are in m and speeds in rev/min inside these structs; the table
// writers convert to mm at the edge.
#pragma once

#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "chatter/kinematics.hpp"  // SpindleSpeed
#include "chatter/results.hpp"     // MultiplierType

namespace chatter {

/// The stability limit (lobe envelope) at one spindle speed.
struct StabilityLimit {
  double spindle_rpm = 0.0;
  /// Largest depth (m) that is asymptotically stable at this speed;
  /// +inf when no instability exists below the searched depth.
  double depth_limit_m = std::numeric_limits<double>::infinity();
  /// Chatter frequency (Hz) at the limit; NaN when depth_limit_m is +inf.
  double chatter_frequency_hz = std::numeric_limits<double>::quiet_NaN();
  /// Lobe number k >= 0 (ωτ = ε + 2πk); −1 when depth_limit_m is +inf.
  int lobe = -1;
  /// Eigenvalue branch (0 or 1) of the transfer-function solvers; −1 if none.
  int branch = -1;

  bool bounded() const { return std::isfinite(depth_limit_m); }
};

/// One point of a lobe curve.
struct LobePoint {
  double spindle_rpm = 0.0;
  double depth_m = 0.0;
  double chatter_frequency_hz = 0.0;
};

/// A continuous piece of one lobe (fixed lobe number and branch), ordered by
/// chatter frequency.
struct LobeCurve {
  int lobe = 0;
  int branch = 0;
  std::vector<LobePoint> points;
};

/// The speed-independent minimum of every lobe (the "absolute" limit).
struct AbsoluteLimit {
  double depth_m = std::numeric_limits<double>::infinity();  ///< +inf if above the searched depth.
  double chatter_frequency_hz = std::numeric_limits<double>::quiet_NaN();
  int branch = -1;
};

/// A value a solver reports or accepts by name: a solver option or a
/// diagnostic. std::monostate = not applicable (null in JSON, empty in CSV).
/// Units are SI unless the name says otherwise (e.g. "max_amplitude_mm").
using SolverValue = std::variant<std::monostate, bool, int, double, std::string, std::vector<double>>;
/// Named values, ordered by name.
using SolverValues = std::map<std::string, SolverValue>;

/// An extra per-speed column a solver adds after the four standard ones of a
/// lobe table (e.g. sdm's "multiplier_type").
struct DiagnosticColumn {
  std::string name;
  bool numeric = false;  ///< numbers (double) in JSON; else strings
  bool operator==(const DiagnosticColumn&) const = default;
};

/// limit_at() plus the solver's per-speed diagnostics, one value per entry of
/// LobeSolver::diagnostic_columns(), in that order (std::monostate where a
/// value does not apply, e.g. at a speed with no limit).
struct DiagnosedLimit {
  StabilityLimit limit;
  std::vector<SolverValue> values;
};

/// A method's own analysis at one (speed, depth) point: what belongs to the
/// asked depth, never to the limit (docs/results.md). What a method does not
/// give stays empty (the analytic methods give nothing: their verdict is the
/// depth against the limit).
struct PointAnalysis {
  /// The method's verdict at the depth: sdm ρ < 1, time-domain its simulation.
  std::optional<bool> stable;
  /// ρ = max |μ| over the multipliers of the Floquet map at the depth (sdm),
  /// per floquet_period_s; < 1 is stable.
  std::optional<double> spectral_radius;
  /// The same measured: the growth per Floquet period of a simulation
  /// (time-domain); NaN-free (empty when it could not be measured).
  std::optional<double> growth_per_period;
  /// The dominant multiplier μ (Im μ >= 0), per floquet_period_s.
  std::optional<std::complex<double>> dominant_multiplier;
  /// The frequency (Hz) of the dominant vibration at the depth: sdm the
  /// chatter-frequency rule applied to the dominant multiplier; time-domain
  /// the largest spectral line that is not a forced one.
  std::optional<double> dominant_frequency_hz;
  /// How the dominant multiplier lies: complex pair (hopf), real negative
  /// (flip), real positive (fold).
  std::optional<MultiplierType> dominant_multiplier_type;
  /// The period (s) multipliers and growth refer to (Process::floquet_period_s).
  std::optional<double> floquet_period_s;
  /// Method-specific values, names with units (sdm steps_per_period;
  /// time-domain verdict, verdict_measure, max_amplitude_mm, ...).
  SolverValues extra;
};

/// What every lobe solver offers. Implementations are immutable after
/// construction: every const member is safe to call from several threads.
class LobeSolver {
 public:
  virtual ~LobeSolver() = default;
  /// Short method name, the key of the solver registry (solvers.hpp).
  virtual std::string method() const = 0;
  /// The exact envelope at one spindle speed (> 0).
  virtual StabilityLimit limit_at(SpindleSpeed speed) const = 0;
  /// Deepest cut (m) the solver searches; limits above it are reported as +inf.
  virtual double depth_max_m() const = 0;

  /// The extra per-speed columns limit_with_diagnostics() fills; none by default.
  virtual std::vector<DiagnosticColumn> diagnostic_columns() const { return {}; }
  /// limit_at() with the diagnostics of diagnostic_columns(), from the same
  /// search (no extra cost beyond what the solver keeps). The limit is
  /// bitwise the one limit_at() returns. Default: limit_at(), no values.
  virtual DiagnosedLimit limit_with_diagnostics(SpindleSpeed speed) const { return {limit_at(speed), {}}; }
  /// The solver's own analysis at one point (rev/min > 0, depth m >= 0);
  /// empty by default (the caller then judges from limit_at()). Cost: one
  /// analysis at the point (sdm: one Floquet map; time-domain: one simulation).
  virtual PointAnalysis analyse_point(SpindleSpeed speed, double depth_m) const {
    (void)speed;
    (void)depth_m;
    return {};
  }
  /// Whether the depth limit at `spindle_rpm` lies above `depth_m` (m >= 0):
  /// always the answer of limit_at(speed).depth_limit_m > depth_m, and
  /// cheaper where the method can stop its search once the answer is sure
  /// (sdm: the depth climb up to just past `depth_m`, no refinement and no
  /// chatter frequency when the crossing is not near `depth_m`). Default:
  /// limit_at().
  virtual bool limit_above(SpindleSpeed speed, double depth_m) const {
    return limit_at(speed).depth_limit_m > depth_m;
  }
  /// The method's own stability verdict at one depth (true: stable) when it
  /// has one much cheaper than a limit search (sdm: ρ < 1 of one period map,
  /// without the eigenvector and chatter frequency analyse_point() adds);
  /// nullopt by default (compare with limit_at() then). An unstable verdict
  /// means a stability boundary at this speed lies below `depth_m`; a stable
  /// one says nothing about smaller depths (an unstable band may lie below).
  virtual std::optional<bool> stable_at(SpindleSpeed speed, double depth_m) const {
    (void)speed;
    (void)depth_m;
    return std::nullopt;
  }
  /// The speed-independent minimum of every lobe when the method gives it
  /// directly (transfer-function methods); nullopt by default.
  virtual std::optional<AbsoluteLimit> known_absolute_limit() const { return std::nullopt; }
  /// The individual lobes between two speeds (rev/min) when the method
  /// traces them (transfer-function methods); empty by default.
  virtual std::vector<LobeCurve> lobe_curves(SpindleSpeed from, SpindleSpeed to) const {
    (void)from;
    (void)to;
    return {};
  }
};

/// `count` spindle speeds evenly spaced from rpm_min to rpm_max, both
/// included (count >= 2, or count == 1 with rpm_min == rpm_max).
/// @throws InputError on an empty, negative or non-finite range.
std::vector<double> evenly_spaced_speeds(double rpm_min, double rpm_max, int count);

/// limit_at() at each speed, in order. With threads > 1 the speeds are shared
/// among that many threads (each speed is independent, so the result is
/// bitwise the same whatever the thread count); threads = 0 uses the
/// hardware concurrency. `per_speed`, if given, is called after each speed
/// with the number done so far (from the worker threads; keep it cheap and
/// thread-safe).
std::vector<StabilityLimit> lobe_envelope(const LobeSolver& solver, const std::vector<double>& speeds_rpm,
                                          unsigned threads = 1,
                                          const std::function<void(std::size_t done)>& per_speed = {});

/// Settings of refine_envelope() / adaptive_envelope().
///
/// Error criterion (the midpoint test): an interval [a, b] between two
/// solved speeds is accepted when the exact limit d_m at its midpoint is
/// within depth_rel_tol · d_m + depth_abs_tol_m of the straight line through
/// the ends, (d_a + d_b) / 2; the midpoint is kept as a row either way, so
/// on a smooth stretch the line through the final rows is off by about a
/// quarter of what was tested. An interval whose ends differ in lobe number,
/// branch or boundedness (a cusp between two lobes, a flip/Hopf switch, the
/// edge of a stretch with no limit below depth_max) is halved further, until
/// it is narrower than cusp_rel_tol × its speed, so the rows on either side
/// of a cusp are exact solves that close to it. No interval is ever split
/// below that width (jumps terminate), and at most max_solves limit_at calls
/// are made.
struct EnvelopeRefinement {
  /// Depth tolerance relative to the local depth (> 0; 0.005 = 0.5 %).
  double depth_rel_tol = 0.005;
  /// Absolute depth tolerance, m (>= 0), for limits near zero.
  double depth_abs_tol_m = 1e-7;
  /// Narrowest interval split, relative to its speed (in [1e-12, 0.1]):
  /// the precision to which cusps and jumps are located.
  double cusp_rel_tol = 1e-6;
  /// Most limit_at calls (new rows) refinement may add.
  std::size_t max_solves = 20000;

  /// Empty when valid, else the violated rule.
  std::string validate() const;
};

/// Rows placed by refine_envelope() / adaptive_envelope().
struct RefinedEnvelope {
  /// Every row solved, start rows included, in increasing speed (distinct).
  std::vector<StabilityLimit> rows;
  /// limit_at calls made by the refinement (start rows not counted).
  std::size_t solves = 0;
  /// True when every interval met the criterion (or reached the narrowest
  /// width) before the solve budget ran out.
  bool converged = false;
};

/// Adds speeds to `start` where the envelope bends, until the midpoint test
/// of EnvelopeRefinement holds on every interval or max_solves is spent.
/// Passes: all open intervals are halved at once (their midpoints solved in
/// parallel as in lobe_envelope), so the result is bitwise the same whatever
/// the thread count. When the budget cannot cover a pass, the intervals with
/// the largest error (measured, or estimated from the start rows: lobe
/// changes first, then the relative depth change) are halved first, ties by
/// lower speed. Cost: the limit_at calls made, at most max_solves; each
/// cusp costs about log2(interval / (cusp_rel_tol × speed)) of them.
/// @param limit_at  the exact limit at a speed (rev/min); called from worker
///                  threads, so it must be thread-safe.
/// @param start     solved rows (>= 1), any order; distinct speeds.
/// @param per_speed called after each solve with the number done so far.
/// @throws InputError on invalid options, an empty start or repeated speeds.
RefinedEnvelope refine_envelope(const std::function<StabilityLimit(double spindle_rpm)>& limit_at,
                                std::vector<StabilityLimit> start, const EnvelopeRefinement& options = {},
                                unsigned threads = 1, const std::function<void(std::size_t done)>& per_speed = {});
/// The same with solver.limit_at.
RefinedEnvelope refine_envelope(const LobeSolver& solver, std::vector<StabilityLimit> start,
                                const EnvelopeRefinement& options = {}, unsigned threads = 1,
                                const std::function<void(std::size_t done)>& per_speed = {});

/// An adaptively spaced table of at most `max_points` rows from rpm_min to
/// rpm_max (both included, increasing): max(2, max_points / 4) evenly spaced
/// speeds, then refine_envelope() with max_solves = max_points minus those
/// (options.max_solves is ignored). Fewer rows when the tolerance is met
/// earlier; `solves` counts every limit_at call, the even ones included
/// (= rows.size()). @throws InputError as evenly_spaced_speeds
/// (max_points >= 2) or on invalid options.
RefinedEnvelope adaptive_envelope(const std::function<StabilityLimit(double spindle_rpm)>& limit_at,
                                  double rpm_min, double rpm_max, int max_points,
                                  const EnvelopeRefinement& options = {}, unsigned threads = 1,
                                  const std::function<void(std::size_t done)>& per_speed = {});

/// The same loop for any per-speed computation: out[i] = f(i) for i < n.
void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& f,
                  const std::function<void(std::size_t done)>& per_item = {});

}  // namespace chatter
