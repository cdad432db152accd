// Plots of the forced response (docs/forced.md, docs/plots.md): the tool
// path relative to the wall over one period with the machined surface
// profile (`chatter forced --plot`), the SLE and peak-to-peak vibration under
// the lobes (`chatter sle --plot`), and the diametral error along a turned
// shaft (`chatter forced --along-shaft --plot`). Like every plot
// (io/plot.hpp): <stem>.dat and <stem>.gp beside the image, rendered by
// gnuplot; plain data in, no solver.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/lobes.hpp"
#include "chatter/results.hpp"

namespace chatter {

/// Two panels: the relative displacement x, y and its component into the
/// wall (−n_w·r) over one period (µm against ms), the wall passes of the
/// teeth marked; and the machined wall: SLE (µm) against the height z (mm),
/// each tooth's pass and the wall they leave (the deepest).
/// @throws InputError on a bad path, a turning or unstable response, or one
///         without a recorded path; GnuplotNotFound; PlotError.
PlotFiles plot_forced(const std::filesystem::path& image, const std::string& title, const ForcedResponse& response);

/// Two panels sharing the speed axis (the way CutPro shows it): the lobes
/// (`limits`, depth limit in mm) with the cut's depth as a line; below, the
/// surface location error and the peak-to-peak vibration x, y (µm) at each
/// speed, gaps where the cut is unstable, speeds where teeth leave the cut
/// marked. `rows` and `limits` at the same speeds (>= 2).
/// @throws InputError on a bad path or mismatched speeds; GnuplotNotFound; PlotError.
PlotFiles plot_sle(const std::filesystem::path& image, const std::string& title, const std::vector<ForcedResponse>& rows,
                   const std::vector<StabilityLimit>& limits, double depth_mm);

/// The diametral error (µm) and the deflection along the chip direction
/// against the tool position (mm) along a turned part.
/// @throws InputError on a bad path or fewer than 2 rows; GnuplotNotFound; PlotError.
PlotFiles plot_shaft_deflection(const std::filesystem::path& image, const std::string& title,
                                const std::vector<double>& positions_mm, const std::vector<ShaftDeflection>& rows);

}  // namespace chatter
