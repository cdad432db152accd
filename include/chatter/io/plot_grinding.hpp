// Plots of the grinding commands (docs/grinding.md), drawn like every other
// plot (include/chatter/io/plot.hpp): <stem>.dat, <stem>.gp and the image.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/grinding.hpp"
#include "chatter/grinding_data.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/io/plot.hpp"

namespace chatter {

/// Three panels against the power (W): removal rate (mm^3/s), maximum depth
/// (mm) and normal force (N), one curve per feed (the empirical models'
/// removal and normal force dashed beside them when given); the operating
/// envelope shaded: the impacts table's powers and the empirical models'
/// tested powers. @throws as plot_lobes.
PlotFiles plot_grinding_sweep(const std::filesystem::path& image, const std::string& title,
                              const std::vector<grinding::SweepCurve>& curves, const grinding::Envelope& envelope);

/// Measured against fitted values of each fitted target, with the line of
/// equality. @throws as plot_lobes.
PlotFiles plot_grinding_fit(const std::filesystem::path& image, const std::string& title, const GrindingFitReport& r);

/// The record with the detected impacts marked and the threshold (upper
/// panel, the first 20 turns at most), the histogram of impacts per turn
/// (lower panel). @throws as plot_lobes.
PlotFiles plot_grinding_impacts(const std::filesystem::path& image, const std::string& title,
                                const ImpactRecord& record, const grinding::ImpactCount& count, double wheel_rpm);

/// The simulated last turns: wheel depth and the surface it meets (mm), and
/// the contact force (N). @throws as plot_lobes; InputError without a series.
PlotFiles plot_grinding_simulation(const std::filesystem::path& image, const std::string& title,
                                   const grinding::DynamicsResult& r);

}  // namespace chatter
