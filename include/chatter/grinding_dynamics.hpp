// The impacts per turn from a model: the compliant robot holding the wheel,
// pressed against the part by its power loop, integrated on SUNDIALS CVODE.
// `chatter grind simulate`; user guide docs/grinding.md, "Dynamics".
//
// The seeds give no robot modes and no dynamic model of the contact: this is
// a lumped model built on seed 001's quasi-static one, for a user to
// calibrate (its modes from a tap test of the robot, its outcome against an
// impact count of `grind impacts`). Along the normal to the part:
//
//  Structure. The modes of the config's [[tool.modes]] (the robot with its
//  spindle) and [[workpiece.modes]], each acting through the y component of
//  its direction (+y points into the part): modal coordinates q_i,
//    q_i'' + 2 zeta_i w_i q_i' + w_i^2 q_i = S_i (F_p [tool mode] - F_c) / m_i,
//  the wheel's depth below the uncut surface x = x0 + sum S_i q_i, x0 such
//  that the static equilibrium is seed 001's groove depth h0 at the power.
//
//  Power loop. The robot pushes with F_p, adjusted by an integral loop
//  (time constant tau, many turns: the robot's controller is slow next to
//  the wheel) so that the mean contact force is the quasi-static one,
//  P / (mu V_c), i.e. the mean power is the set power P:
//    F_p' = (P / (mu V_c) - F_c) / tau.
//
//  Groove memory (regeneration). The wheel meets the surface the previous
//  turn left, s(t) = (1 - r) d(t - T), T = 1/N one turn, d the depth the
//  wheel left (d = x where it cut, else the surface it found), r = v_f/(N E)
//  (<= 1) the fraction of the wheel width that meets uncut material each turn
//  as the wheel is fed along its axis. The memory is kept per wheel angle, as
//  turning keeps it per spindle angle: exact when the contact recurs at the
//  same wheel angle every turn (seed 001's one-impact regime), a lumped
//  approximation otherwise.
//
//  Contact (force only while the wheel penetrates, p = x - s > 0). Seed 001's
//  power balance with the contact width w(x) = 2 sqrt(2 R x) and the chip
//  swept at the rate Z(t) = (2/3) w(x) p v_f / r:
//    F_c = [k_e n_c N (3/4) E w(x) + k_c Z(t)] / (mu V_c),   0 when p <= 0,
//  n_c the config's impacts per turn at P. In steady continuous contact
//  p = r h0, Z = A v_f and F_c = P / (mu V_c): the quasi-static model exactly.
//
// Integrator: CVODE Adams-Moulton with fixed-point iteration (the modes are
// lightly damped, not stiff), stopping at every point of the groove grid
// (points_per_turn a turn, where the memory is written) and, by root
// finding, wherever contact starts or ends (the force jumps there: the
// integrator restarts). The memory between grid points is interpolated
// linearly. Thread safety: simulate_grinding allocates its own SUNDIALS
// context; concurrent calls are safe.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "chatter/grinding.hpp"
#include "chatter/structural_model.hpp"

namespace chatter::grinding {

struct DynamicsOptions {
  int turns = 400;                  ///< wheel turns simulated, in [20, 100000]
  double analysed_fraction = 0.5;   ///< the last fraction of the turns analysed, in (0, 1]
  int points_per_turn = 400;        ///< groove grid per turn, in [50, 20000]
  /// tau in wheel turns, > 0. 3: the mean force settles within a fraction
  /// of a percent in the 200 analysed turns of the default run (a slower
  /// loop needs more turns: the push a bouncing wheel needs is found slowly).
  double power_loop_turns = 3.0;
  /// The wheel starts in the quasi-static groove with the push at its
  /// steady value, lifted by this fraction of its steady penetration r h0:
  /// a disturbance that decays in a stable process and grows into impacts in
  /// an unstable one. In [0, 10].
  double initial_lift = 0.5;
  double relative_tolerance = 1e-7; ///< CVODE's, in [1e-12, 1e-3]
  int series_turns = 10;            ///< last turns kept as a time series (0: none), <= turns
};

/// Simulates the grinding at useful power P (W).
/// @throws InputError when P is not > 0, the process has no mechanistic
///   model, no tool mode acts along the normal (y), or an option is out of
///   range (named as DynamicsOptions::field). NumericalError when CVODE fails.
/// Cost: turns x points_per_turn grid steps, a few CVODE steps each
/// (400 turns x 400 points: ~0.3 s).
DynamicsResult simulate_grinding(const Process& p, const StructuralModel& robot, double power_w,
                                 const DynamicsOptions& options = {});

}  // namespace chatter::grinding
