// The uncertain-lobes plot of `chatter lobes --samples` (docs/uncertainty.md,
// docs/plots.md): the probability of stability over (spindle speed, depth) as
// a colour map, the 5 / 50 / 95 % quantile lobes and the nominal lobe on top.
// Like every plot (io/plot.hpp): <stem>.dat and <stem>.gp beside the image,
// rendered by gnuplot.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/lobes.hpp"
#include "chatter/uncertainty.hpp"

namespace chatter {

/// Draws x = spindle speed (rev/min), y = depth of cut (mm), colour = the
/// fraction of samples stable there (0 red to 1 blue), a line per quantile
/// level of `lobes` ("95 % of samples stable below" for level 0.05) and the
/// nominal envelope (black). Limits at +inf (no chatter below `depth_max_mm`)
/// are drawn at depth_max_mm. The depth axis ends at `depth_axis_mm`.
/// @pre lobes come from reduce_monte_carlo with >= 2 speeds and >= 2 depths;
///      nominal has the same speeds.
/// @throws InputError on a bad path or inconsistent data; GnuplotNotFound;
///         PlotError (io/plot.hpp).
PlotFiles plot_uncertain_lobes(const std::filesystem::path& image, const std::string& title, const UncertainLobes& lobes,
                               const std::vector<StabilityLimit>& nominal, double depth_max_mm, double depth_axis_mm);
/// The same plot in a live window (io/plot.hpp's PlotWindow).
void plot_uncertain_lobes(PlotWindow& window, const std::string& title, const UncertainLobes& lobes,
                          const std::vector<StabilityLimit>& nominal, double depth_max_mm, double depth_axis_mm);

}  // namespace chatter
