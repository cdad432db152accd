// The lobe-surface plot of `chatter surface` (docs/position.md, docs/plots.md):
// depth limit over (spindle speed, tool position) as a colour map, contours
// of chosen depths, and the best speed at each position. Like every plot
// (io/plot.hpp): <stem>.dat and <stem>.gp beside the image, rendered by gnuplot.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/lobes.hpp"

namespace chatter {

/// A lobe surface as plain data: limits[p][s] at positions_mm[p] and the
/// speed limits[p][s].spindle_rpm (the same speeds at every position).
struct LobeSurfaceData {
  std::vector<double> positions_mm;                  ///< strictly increasing, >= 2
  std::vector<std::vector<StabilityLimit>> limits;   ///< one row per position, >= 2 speeds each
  double depth_max_mm = 0.0;                         ///< deepest cut searched (> 0): the colour scale's top
};

/// The contour depths drawn when none are chosen: up to 5 round values
/// (1, 2 or 5 × 10^k steps) strictly between the smallest and the largest
/// bounded limit of the surface, mm; empty when no limit is bounded.
std::vector<double> default_contour_depths_mm(const LobeSurfaceData& surface);

/// The speed with the deepest limit at each position (the first such speed
/// on a tie; a speed stable to the searched depth beats any bounded one).
std::vector<StabilityLimit> best_speed_per_position(const LobeSurfaceData& surface);

/// Draws the surface: x = spindle speed (rev/min), y = position (mm), colour
/// = depth limit (mm; limits beyond depth_max_mm at the top colour), thin
/// labelled lines at `contour_depths_mm` (gnuplot's contouring of the grid),
/// and the best speed at each position as a white line with points.
/// @throws InputError on a bad path, inconsistent data or a contour depth
///         not > 0; GnuplotNotFound; PlotError (io/plot.hpp).
PlotFiles plot_surface(const std::filesystem::path& image, const std::string& title, const LobeSurfaceData& surface,
                       const std::vector<double>& contour_depths_mm);
/// The same plot in a live window (io/plot.hpp's PlotWindow).
void plot_surface(PlotWindow& window, const std::string& title, const LobeSurfaceData& surface,
                  const std::vector<double>& contour_depths_mm);

}  // namespace chatter
