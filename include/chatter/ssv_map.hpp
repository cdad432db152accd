// Stability over the spindle speed variation itself (docs/ssv.md, "Choosing
// the modulation"): at one mean speed and depth, the Floquet spectral
// radius of the sdm solver on a grid of amplitude ratios R_VA × frequency
// ratios R_VF — the chart `chatter map CONFIG --ssv-map` draws.
//
// Each grid point is its own principal period (speed_variation_period), so
// ρ is reported per spindle revolution, ρ_rev = ρ^(T_rev / T): comparable
// across the grid (and with R_VA = 0, the constant-speed map over T_F), and
// < 1 exactly where ρ < 1. Method and sources: chatter/speed_variation.hpp,
// chatter/semi_discretization.hpp.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "chatter/process.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {

struct SsvMapGrid {
  double spindle_rpm = 0.0;  ///< mean speed, rev/min
  double depth_m = 0.0;      ///< depth of cut, m
  std::vector<double> amplitude_ratios;  ///< R_VA, rows
  std::vector<double> frequency_ratios;  ///< R_VF, columns
  /// Row-major (amplitude i, frequency j) at i · frequency_ratios.size() + j:
  /// ρ per revolution (+inf when the map overflowed), the frequency ratio
  /// the period was exact for, and whether that is the one asked (1) or a
  /// nearby fraction (0, docs/ssv.md). R_VA = 0: constant speed, exact.
  std::vector<double> rho_per_revolution;
  std::vector<double> frequency_ratio_used;
  std::vector<char> exact;
};

/// The map. `process` gives everything but the modulation (its own
/// speed_variation is replaced at every point). threads = 0: every core.
/// `progress(done, total)` (may be empty) is called after each row.
/// Cost: one sdm analysis per point, over its principal period (q
/// revolutions for R_VF = 1/q in turning).
/// @throws InputError if rpm is not in (0, 5e5], depth not > 0, a ratio
///         breaks SpeedVariation::validate, or a grid is empty; as
///         SemiDiscretizationSolver otherwise.
SsvMapGrid ssv_stability_map(const StructuralModel& model, const Process& process, double spindle_rpm,
                             double depth_m, const std::vector<double>& amplitude_ratios,
                             const std::vector<double>& frequency_ratios, const SemiDiscretizationOptions& options,
                             unsigned threads = 1,
                             const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace chatter
