// The static cutting load of a cut, as `optimize` and `performance` read it
// (docs/optimization.md): the cutting law's largest resultant force and its
// mean torque and power (chatter/cutting_law.hpp, where the formulas are).
//
//  turning: F_c = K_c a f (tangential), in the plane F = a f |(K_f, K_r)|,
//           force = |(F_c, F)|, torque = F_c D/2, power = F_c V;
//  milling: force = the largest |F(t)| of the teeth's in-plane forces over
//           a revolution (helix by slices, runout included), torque =
//           (D/2) × the mean summed tangential force (a profile: each
//           slice's own radius), power = torque × 2πN/60.
// Units: SI. Cost: turning O(1); milling O(samples × teeth × slices) ≈ 0.1 ms.
#pragma once

#include "chatter/process.hpp"

namespace chatter {

struct CuttingLoad {
  double force_n = 0.0;     ///< largest resultant cutting force on the tool, N
  double torque_n_m = 0.0;  ///< mean cutting torque at the spindle, N·m
  double power_w = 0.0;     ///< mean cutting power, W
};

/// The load at `spindle_rpm` (> 0), depth (m, >= 0) and feed (m per
/// revolution in turning, per tooth in milling, >= 0). `diameter_m`: the
/// workpiece's (turning) or the tool's (milling), > 0. Turning needs the
/// tangential coefficient K_c (N/m², > 0), or Kienzle's law in the process
/// and K_c = 0 (its tangential term is the force); milling ignores it.
/// @throws InputError on a violated precondition.
CuttingLoad cutting_load(const Process& process, double spindle_rpm, double depth_m, double feed_m, double diameter_m,
                         double turning_tangential_coefficient_n_per_m2);

}  // namespace chatter
