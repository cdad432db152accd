// The static cutting load of a cut: the largest resultant force, the mean
// torque and power at the spindle (docs/physics.md §3 force model; used by
// `performance` and `optimize`, docs/optimization.md). A small shared
// function: `recommend`'s mean-force model (src/ops/operations.cpp) computes
// the same means for its caps and may call this once that file is split.
//
//  turning: F_c = K_c a f (tangential), in the plane F = a f |(K_f, K_r)|
//           (the insert's −b h d, b h = a f for any lead angle and nose
//           radius, docs/turning_inserts.md), force = |(F_c, F)|, torque =
//           F_c D/2, power = F_c V;
//  milling: the teeth's forces F = Σ_j ∫₀ᵃ h_j(φ_j(t, z)) v(φ_j) dz over one
//           revolution (v the process's force direction, h_j its static chip
//           with runout, the helix by slices), force = the largest |F|, torque
//           = (D/2) Σ_j ∫ K_t h_j dz averaged over the revolution, power =
//           torque × 2πN/60.
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
/// tangential coefficient K_c (N/m², > 0); milling ignores it.
/// @throws InputError on a violated precondition.
CuttingLoad cutting_load(const Process& process, double spindle_rpm, double depth_m, double feed_m, double diameter_m,
                         double turning_tangential_coefficient_n_per_m2);

}  // namespace chatter
