// The plot of `chatter program` (docs/program.md, docs/plots.md): margin,
// power and depth limit against cutting time with the block boundaries;
// beside it, for milling, the toolpath from above coloured by margin, for
// turning the margin and diametral error along the bar.
#pragma once

#include <array>

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"

namespace chatter {

/// Plain data (the records layer fills it from a ProgramReport).
struct ProgramPlotData {
  std::string title;
  bool turning = false;
  struct Block {
    int line = 0;
    double t0_s = 0.0, t1_s = 0.0;       ///< cutting time at the block's start and end (air: 0 length)
    bool air = true;
    bool overloaded = false;             ///< over the machine's power, torque or speed range
    double margin = 0.0, power_kw = 0.0, depth_limit_mm = 0.0, depth_mm = 0.0;
    double part_error_um = 0.0;
    double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;  ///< mm
    double position_mm = 0.0;            ///< turning
    /// Turning: the block's samples along the bar (position mm, margin, diametral error µm).
    std::vector<std::array<double, 3>> along_bar;
  };
  std::vector<Block> blocks;
  double max_power_kw = 0.0;             ///< 0 = no limit drawn
};

/// Image files (the image, its .gp and .dat). @throws InputError on a bad
/// image name, no cutting block, or gnuplot's failure.
PlotFiles plot_program(const ProgramPlotData& data, const std::filesystem::path& image);
/// The same in a live window (--show).
void plot_program(const ProgramPlotData& data, PlotWindow& window);

}  // namespace chatter
