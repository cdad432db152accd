// The plot of `chatter design-pitch --plot` (docs/design_pitch.md): the depth
// limit over the speed band for the equal-pitch and the designed cutter,
// with each worst limit marked; drawn like every other plot
// (chatter/io/plot.hpp): <stem>.dat, <stem>.gp and the image.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/lobes.hpp"

namespace chatter {

/// x = spindle speed (rev/min), y = depth limit (mm): `equal` and `designed`
/// (the same speeds, in order; +inf = no limit below depth_max_m, drawn as a
/// gap) as two lines, each worst limit as a dashed horizontal line with its
/// value; `designed_label` names the designed cutter in the key (its angles).
/// @throws InputError (bad path or extension, no rows, different speeds),
///         GnuplotNotFound, PlotError.
PlotFiles plot_pitch_design(const std::filesystem::path& image, const std::string& title,
                            const std::vector<StabilityLimit>& equal, const std::vector<StabilityLimit>& designed,
                            const std::string& designed_label, double depth_max_m);

}  // namespace chatter
