// Position-dependent structure (docs/position.md): the modes the tool sees
// change as it moves along the part, and the stability limit becomes a
// surface a_lim(position, speed).
//
// Two models, both plain data read by model_at_position():
//  - a cantilever workpiece (a bar clamped at one end, `cantilever` modes of
//    the config): the tool at distance x from the clamp sees the bar's first
//    bending mode scaled by its shape φ(x/L), normalised to φ(1) = 1 at the
//    free end: stiffness k_tip / φ², mass m_tip / φ², frequency and damping
//    unchanged (the modal reduction at a point of a mode shape; the seed
//    thesis of the coupled-turning case studies this shaft);
//  - stations: complete mode sets at positions along the path (modal, or
//    fitted from tap tests at those positions), interpolated between them.
//    Each mode parameter (natural frequency, damping ratio, stiffness) is
//    interpolated on its own by a monotone piecewise-cubic Hermite curve
//    (Fritsch & Carlson 1980, SIAM J. Numer. Anal. 17(2), with the
//    Fritsch–Butland harmonic-mean slopes): C¹ in position, exact at every
//    station, no overshoot (a parameter never leaves the range of its two
//    neighbours, so a stiffness stays > 0 and a damping ratio in (0, 1)).
//    Frequency and stiffness are interpolated in their logarithm (they vary
//    by factors along a part: the cantilever's k ∝ 1/φ² spans decades), the
//    damping ratio as it is. Never the raw FRF: interpolating receptances
//    would split one moving resonance into two fixed ones.
//
// Units: SI (positions in m).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

/// β and σ of the first clamped-free bending mode (values of docs/physics.md §10).
inline constexpr double kCantileverBeta = 1.8751;
inline constexpr double kCantileverSigma = 0.7341;

/// First bending-mode shape of a clamped-free bar at ξ = x / L in [0, 1]
/// (0 at the clamp), normalised to 1 at the free end:
///   φ(ξ) = [cosh βξ − cos βξ − σ (sinh βξ − sin βξ)] / (the same at ξ = 1).
/// φ(0) = 0, φ(1) = 1 exactly. Cost: a few transcendental calls.
/// @throws InputError if ξ is outside [0, 1] or not finite.
double cantilever_mode_shape(double xi);

/// A workpiece mode built from a cantilever bar: which one (index into
/// StructuralModel::workpiece.modes) and the bar length, m.
struct CantileverModeRef {
  std::size_t workpiece_mode = 0;
  double length_m = 0.0;
};

/// A complete mode set measured or computed at one position along the path.
struct PositionStation {
  double position_m = 0.0;   ///< distance along the path, m (>= 0)
  StructuralModel model;     ///< modes only (no measured FRF terms)
};

/// How the structure changes along the path. Empty (no cantilever mode, no
/// station): the structure does not depend on the position.
struct PositionDependence {
  /// Cantilever workpiece modes (all of the same bar length: one part).
  std::vector<CantileverModeRef> cantilever;
  /// Stations in strictly increasing position (>= 2), each with the same
  /// number of tool and of workpiece modes, mode i in the same direction at
  /// every station. Never together with `cantilever`.
  std::vector<PositionStation> stations;

  bool empty() const { return cantilever.empty() && stations.empty(); }
  /// The positions a model is defined at, m: [0, L] for a cantilever (clamp to
  /// free end), [first, last] station otherwise. @pre !empty().
  std::pair<double, double> range_m() const;
  /// Empty when the data follow the rules above, else the violated rule
  /// naming the field ("stations[2].position_m = 0.1: must be > stations[1]...").
  std::string validate() const;
};

/// The structure the tool sees at `position_m`.
///  - cantilever: `base` with every listed workpiece mode's stiffness divided
///    by φ(x/L)² (frequency, damping, direction kept: at x = L the model is
///    `base` bit for bit). At x = 0 (φ = 0) the mode is rigid and left out.
///  - stations: at a station's position exactly that station's model; between
///    two stations the interpolated modes (see above); a parameter equal at
///    every station is copied, not interpolated.
///  - empty dependence: `base`.
/// Cost: O(modes) (stations: plus a binary search over the stations).
/// @throws InputError if `position_m` is outside range_m() or not finite
///         ("position_m = 0.6: outside the part [0, 0.5] m"), if `dep` is
///         invalid, or if the structure left is rigid (every mode at the clamp).
StructuralModel model_at_position(const StructuralModel& base, const PositionDependence& dep, double position_m);

/// `count` positions evenly spaced from lo to hi, both included, m.
/// @throws InputError unless lo, hi finite, hi > lo and count >= 2.
std::vector<double> evenly_spaced_positions(double lo_m, double hi_m, int count);

/// Builds the solver for one structure (same method, process and options at
/// every position). Called from worker threads: must be thread-safe.
using SolverFactory = std::function<std::unique_ptr<LobeSolver>(const StructuralModel& model)>;

/// The lobe surface: rows[p][s] = limit at positions_m[p] and speeds_rpm[s].
/// The positions are shared among `threads` threads (0 = hardware
/// concurrency); each builds the solver of its position and solves every
/// speed in order, so each row is bitwise what lobe_envelope() gives for that
/// model and the result does not depend on the thread count. `per_position`,
/// if given, is called after each position with the number done (from the
/// worker threads). Cost: positions × (one solver build + speeds × limit_at).
/// @throws InputError as model_at_position (checked for every position
///         before any solve) or from the factory.
std::vector<std::vector<StabilityLimit>> lobe_surface(const StructuralModel& base, const PositionDependence& dep,
                                                      const std::vector<double>& positions_m,
                                                      const std::vector<double>& speeds_rpm,
                                                      const SolverFactory& make_solver, unsigned threads = 1,
                                                      const std::function<void(std::size_t done)>& per_position = {});

}  // namespace chatter
