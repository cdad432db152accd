// Uncertain lobes (docs/uncertainty.md): the modes and the cutting
// coefficients are never known exactly. A Monte Carlo over their spread gives,
// at each spindle speed, the distribution of the depth limit: the probability
// that a cut (speed, depth) is stable, and quantile lobes.
//
// Three pieces, so that a sweep can be split across threads or processes
// (an MPI runner calls (b) on ranges of samples and (c) once):
//  (a) sample_inputs(nominal, spreads, seed, i): sample i's model and process,
//      a pure function of its arguments (counter-based random numbers: a
//      sample never depends on which thread or process draws it, or in which
//      order);
//  (b) monte_carlo_limits(..., begin, end, ...): rows[i - begin][s] = the
//      depth limit of sample i at speed s, threads inside, bitwise the same
//      for any thread count;
//  (c) reduce_monte_carlo(rows, ...): probability of stability over a
//      (speed, depth) grid and the quantile lobes, from all rows.
//
// Distribution. Each uncertain parameter p (natural frequency, damping ratio
// and stiffness of each mode; K_t and K_r of milling or K_f of turning) is
//     p_i = p · (1 + s · z),   z standard normal truncated to |z| <= 3,
// s the relative 1σ spread of the untruncated normal (the truncation lowers
// the standard deviation by 1.4 %). Every parameter of every sample is drawn
// independently (no correlation between modes, between a mode's frequency and
// stiffness, or between K_t and K_r). A spread with 3 s >= 1 could make a
// parameter <= 0, and a damping spread with ζ (1 + 3 s) >= 1 a damping ratio
// >= 1: UncertaintySpreads::validate refuses both. A mode's direction is not
// uncertain; the modal mass follows from the drawn stiffness and frequency.
// Measured FRF terms of the model (no modes) are used as measured.
//
// Random numbers. z of (seed, sample i, parameter j) is a pure function:
// three rounds of the SplitMix64 finaliser (Steele, Lea & Flood 2014) hash
// the seed, then i, then j into 64 bits; the top 53 bits give u in (0, 1);
// z = Φ⁻¹(Φ(−3) + u (Φ(3) − Φ(−3))) (inverse-CDF truncation, one draw, no
// rejection; Φ⁻¹ by boost::math::erf_inv). Exact integer arithmetic up to
// u, so the stream is the same on every platform; z then goes through
// Boost.Math's erf / erf_inv rational approximations in double (the same
// bits wherever std::sqrt / std::exp / std::log round the same).
// Parameter j: 0 = K_t (milling) or K_f (turning), 1 = K_r (milling), then
// 2 + 3 m + {0 frequency, 1 damping, 2 stiffness} for mode m (tool modes
// first, then workpiece modes, in config order); so a sample's draws do not
// change when another spread is switched on.
//
// Units: SI inside; spreads as fractions (0.05 = 5 %).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

/// The truncation of the standard normal draws: |z| <= 3.
inline constexpr double kUncertaintyTruncationSigma = 3.0;

/// Relative 1σ spreads (fractions, >= 0). A mode list holds one value for
/// every mode (size 1), one value per mode (tool modes, then workpiece modes),
/// or nothing (no spread).
struct UncertaintySpreads {
  std::vector<double> frequency;  ///< of each mode's natural frequency
  std::vector<double> damping;    ///< of each mode's damping ratio
  std::vector<double> stiffness;  ///< of each mode's stiffness
  double tangential = 0.0;        ///< of K_t (milling) or K_f (turning)
  double radial = 0.0;            ///< of K_r (milling only)

  /// The spread of mode m (0 when the list is empty). @pre validate() passed.
  double frequency_of(std::size_t m) const;
  double damping_of(std::size_t m) const;
  double stiffness_of(std::size_t m) const;
  /// True when every spread is 0 (every sample is the nominal input).
  bool zero() const;
  /// Empty when the spreads suit `model` and `process`, else the violated rule
  /// naming the field ("damping[1] = 0.5: with damping_ratio 0.8 a 3-sigma
  /// draw reaches 2: must be < 0.4167"). Rules: every spread finite and
  /// >= 0; 3 s < 1; per-mode lists of size 1 or the mode count; damping
  /// ζ (1 + 3 s) < 1; radial only for milling.
  std::string validate(const StructuralModel& model, const Process& process) const;
};

/// The truncated standard normal z of (seed, sample, parameter), |z| <= 3.
/// Pure: the same arguments give the same bits in any thread or process.
/// Cost: a few integer operations and one erf_inv.
double uncertainty_normal(std::uint64_t seed, std::uint64_t sample, std::uint64_t parameter);

/// One Monte Carlo sample: the model and process it solves.
struct UncertainSample {
  StructuralModel model;
  Process process;
};

/// Sample `sample`'s inputs: every uncertain parameter of `model` / `process`
/// times (1 + s z) (see above). With zero spreads the nominal input, bit for
/// bit. Cost: O(modes). @throws InputError if `spreads` are invalid.
UncertainSample sample_inputs(const StructuralModel& model, const Process& process, const UncertaintySpreads& spreads,
                              std::uint64_t seed, std::uint64_t sample);

/// Builds the solver for one sample (same method, depth and options for every
/// sample). Called from worker threads: must be thread-safe.
using SampleSolverFactory =
    std::function<std::unique_ptr<LobeSolver>(const StructuralModel& model, const Process& process)>;

/// The depth limits of samples [begin, end): rows[i - begin][s] at
/// speeds_rpm[s]. The samples are shared among `threads` threads (0 =
/// hardware concurrency); each sample's solver is built and its speeds solved
/// in order by one thread, so the rows are bitwise independent of the thread
/// count and of how [0, N) is split into ranges. `per_sample`, if given, is
/// called with the number of samples done (from worker threads).
/// Cost: (end − begin) × (one solver build + speeds × limit_at).
/// @throws InputError if end < begin, the spreads are invalid, or from the
///         factory (every sample's inputs are built before any solve).
std::vector<std::vector<StabilityLimit>> monte_carlo_limits(
    const StructuralModel& model, const Process& process, const UncertaintySpreads& spreads, std::uint64_t seed,
    std::uint64_t begin, std::uint64_t end, const std::vector<double>& speeds_rpm, const SampleSolverFactory& make_solver,
    unsigned threads = 1, const std::function<void(std::size_t done)>& per_sample = {});

/// The q-quantile (q in [0, 1]) of `values` (any order, not empty), by linear
/// interpolation between order statistics (Hyndman & Fan 1996, type 7: h =
/// (n − 1) q, x_(⌊h⌋) + (h − ⌊h⌋)(x_(⌊h⌋+1) − x_(⌊h⌋))). +inf counts as larger
/// than every finite value; an interpolation that touches +inf is +inf, and
/// equal neighbours give that value exactly (so n equal values give it bit
/// for bit). Cost O(n log n). @throws InputError if empty or q outside [0, 1].
double quantile_type7(std::vector<double> values, double q);

/// What the Monte Carlo says over the speeds.
struct UncertainLobes {
  std::vector<double> speeds_rpm;  ///< the speeds of the rows
  std::vector<double> depths_m;    ///< the depth grid of `probability_stable`
  /// probability_stable[s][d]: the fraction of samples stable at speeds_rpm[s]
  /// and depths_m[d], i.e. whose limit there is > depths_m[d] (the stable
  /// region at a speed is taken to be every depth below its limit, as the
  /// lobe table says). Multiples of 1/N.
  std::vector<std::vector<double>> probability_stable;
  std::vector<double> levels;  ///< the quantile levels, e.g. 0.05, 0.5, 0.95
  /// quantile_depth_m[l][s]: the levels[l]-quantile of the N limits at
  /// speeds_rpm[s] (quantile_type7): a fraction levels[l] of the samples
  /// chatter below it, so 1 − levels[l] are stable below it. +inf when that
  /// many samples find no chatter below the searched depth.
  std::vector<std::vector<double>> quantile_depth_m;
};

/// Reduces the rows of all N samples (rows[i][s], every row over the same
/// speeds, in sample order; any order gives the same result) to
/// probabilities over `depths_m` and the quantile lobes at `levels`.
/// Pure. Cost O(N S (log N + D)).
/// @throws InputError if rows is empty, rows differ in length, or a level
///         is outside [0, 1].
UncertainLobes reduce_monte_carlo(const std::vector<std::vector<StabilityLimit>>& rows,
                                  const std::vector<double>& depths_m, const std::vector<double>& levels);

/// The quantile levels every front end reports: 5 %, 50 % and 95 %.
inline constexpr double kUncertaintyLevels[] = {0.05, 0.50, 0.95};
/// The name of a quantile lobe's column or key: "depth_limit_p05_mm" for
/// level 0.05 (the level in whole percent, two digits at least).
std::string quantile_column_name(double level);

/// The depth grid of the probability of stability (the one place the CLI's
/// `lobes --samples`, chatter-mpi and the Python module choose it).
struct ProbabilityDepthGrid {
  double top_mm = 0.0;         ///< the deepest depth of the grid, mm
  std::vector<double> depths_m;  ///< `points` depths from 0 to top_mm, both included, m
};
/// `points` depths evenly from 0 to `top_mm` if given, else to 1.2 times the
/// deepest finite limit of any sample rounded up to two significant digits
/// (round numbers for the axis) and at most `depth_max_mm`; `depth_max_mm`
/// when no sample found chatter below it. Depths are in mm in the arguments
/// because that is how the grid is chosen and printed; the returned depths
/// are m, as reduce_monte_carlo takes them. Pure, O(N S + points).
/// @throws InputError unless points >= 2 and the top is finite and > 0.
ProbabilityDepthGrid probability_depth_grid(const std::vector<std::vector<StabilityLimit>>& rows, double depth_max_mm,
                                            int points, std::optional<double> top_mm = std::nullopt);

}  // namespace chatter
