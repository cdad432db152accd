// The spindle-speed-variation map of `chatter map CONFIG --ssv-map`
// (docs/ssv.md): its CSV table and its heat map, drawn like every other
// plot (chatter/io/plot.hpp): <stem>.dat, <stem>.gp and the image.
#pragma once

#include <filesystem>
#include <string>

#include "chatter/io/plot.hpp"
#include "chatter/ssv_map.hpp"

namespace chatter {

/// CSV: amplitude_ratio,frequency_ratio,frequency_ratio_used,exact_period,
/// spectral_radius_per_revolution (one row per grid point, amplitudes
/// outermost; an overflowed ρ prints as inf).
std::string ssv_map_csv(const SsvMapGrid& grid);

/// Heat map: x = R_VF, y = R_VA, colour = ln ρ per revolution on a diverging
/// scale centred on 0 (blue < 0 stable, red > 0 chatter; clipped at ±ln 10),
/// the ρ = 1 contour as a line. @throws as plot_lobes.
PlotFiles plot_ssv_map(const std::filesystem::path& image, const std::string& title, const SsvMapGrid& grid);

}  // namespace chatter
