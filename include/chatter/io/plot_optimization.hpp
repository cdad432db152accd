// The loss map of `chatter optimize --plot` and `chatter adapt --plot`
// (docs/optimization.md, docs/plots.md): the objective as colour over cutting
// speed (turning, m/min; milling, rev/min) × feed, each failing constraint's
// region hatched in its own pattern and colour, the lobes' unstable region
// shaded, the optimum marked, and the adaptive loop's trajectory. Like every
// plot (io/plot.hpp): <stem>.dat and <stem>.gp beside the image, rendered by
// gnuplot; plain data in (LossMap, chatter/optimization_problem.hpp).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/optimization_problem.hpp"

namespace chatter {

/// A point on the map: spindle speed (rev/min) and feed (m).
struct MapPoint {
  double spindle_rpm = 0.0;
  double feed_m = 0.0;
};

/// @throws InputError on a bad path or a map without cells; GnuplotNotFound; PlotError.
PlotFiles plot_loss_map(const std::filesystem::path& image, const std::string& title, const LossMap& map,
                        const std::optional<MapPoint>& optimum, const std::vector<MapPoint>& trajectory = {});

}  // namespace chatter
