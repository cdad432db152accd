// Plots of the shop-data commands (issue 18), drawn like every other plot
// (include/chatter/io/plot.hpp): <stem>.dat, <stem>.gp and the image.
#pragma once

#include <filesystem>
#include <string>

#include "chatter/io/plot.hpp"
#include "chatter/io/shop_io.hpp"
#include "chatter/shop.hpp"

namespace chatter {

/// Measured average forces per unit depth (N/mm) against feed per tooth (mm)
/// with the fitted straight lines (force routes: F̄x/a and F̄y/a; power
/// route: mean tangential force of all teeth per unit depth, P̄/(Ω R a)).
/// @throws as plot_lobes.
PlotFiles plot_coefficient_fit(const std::filesystem::path& image, const std::string& title,
                               const CoefficientTests& tests, const CoefficientFit& fit,
                               const MillingEngagement& engagement, double tool_diameter_m);

/// Amplitude spectrum (log axis) against frequency (Hz), tooth-passing
/// harmonics as dashed lines, spindle harmonics as dots, the chatter line
/// labelled. The x range ends at 3× the higher of the chatter and
/// tooth-passing frequencies (at most the Nyquist frequency).
/// @throws as plot_lobes; InputError when the detection holds no spectrum.
PlotFiles plot_detection(const std::filesystem::path& image, const std::string& title, const ChatterDetection& d);

}  // namespace chatter
