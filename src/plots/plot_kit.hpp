// Internal to the io layer: the gnuplot plumbing every plot kind shares
// (plot.cpp defines it; plot_lobes.cpp, plot_frf.cpp, plot_map.cpp,
// plot_compare.cpp and plot_simulation.cpp draw one kind each): the target
// of a plot (three files beside the image, or a live window), the script's
// head, the palette, number formatting and the all-or-nothing render.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/lobes.hpp"
#include "chatter/results.hpp"

namespace chatter::plot_kit {

namespace fs = std::filesystem;

inline constexpr const char* kInstallHint =
    "install gnuplot (Debian/Ubuntu: apt-get install gnuplot-nox; Fedora: dnf install gnuplot; "
    "macOS: brew install gnuplot)";
// Colours (a light, print-friendly palette).
inline constexpr const char* kStableFill = "#8cc97e";  // drawn 40 % opaque
inline constexpr const char* kChatterFill = "#f08a7e";  // drawn 30 % opaque
inline constexpr const char* kEnvelope = "#1a4d80";
inline constexpr const char* kLobe = "#606a6a6a";  // ARGB: 38 % transparent
inline constexpr const char* kAbsolute = "#c0392b";
inline constexpr const char* kLabel = "#3a3a3a";
inline constexpr const char* kGrid = "#c8c8c8";
inline constexpr const char* kTool = "#1f77b4";
inline constexpr const char* kWorkpiece = "#e07b00";
inline constexpr const char* kRelative = "#202020";

// The stability boundary's colours by multiplier type (maps, comparisons).
inline constexpr const char* kHopfLine = "#101010";
inline constexpr const char* kFlipLine = "#7b1fa2";
inline constexpr const char* kFoldLine = "#00796b";
/// Headroom of the depth axis over the deepest finite limit (lobes, comparisons).
inline constexpr double kDepthAxisMargin = 1.1;

/// Where a plot goes: an image with its script and data, or a live window.
struct Target {
  ImageFormat format;
  fs::path image, script, data;
  std::string image_name, data_name;  // relative names used inside the script
  PlotWindow* window = nullptr;       // a live plot (--show): no files, the data in a datablock
  std::string label;                  // what messages name: the image, or "live plot"
};

/// A number for the .dat file: 10 significant digits (or `digits`), `?` when not finite.
std::string num(double x, int digits = 10);
/// A number for the script and for labels: `digits` significant digits.
std::string short_num(double x, int digits = 4);
/// gnuplot_quote.
std::string quote(const std::string& s);
/// A gnuplot `plot` command built clause by clause, each on its own
/// continued line ("plot", then " \\", a line break and two spaces before
/// the first clause and ", \\" and the same before each next one).
class PlotCommand {
 public:
  void add(const std::string& clause) {
    text_ += (first_ ? " \\\n  " : ", \\\n  ") + clause;
    first_ = false;
  }
  const std::string& str() const { return text_; }

 private:
  std::string text_ = "plot";
  bool first_ = true;
};
/// Text for a `#` comment line: line breaks become spaces.
std::string one_line(std::string s);
/// A shell word for the "run this" hint in messages.
std::string shell_word(const std::string& s);
std::string lower(std::string s);
/// Smallest "nice" number (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 × 10^n) >= x > 0.
double nice_ceil(double x);
/// The three files of an image plot. @throws InputError on a bad name or options.
Target make_target(const fs::path& image, const PlotOptions& options);
/// A live plot: the image's script and data with the PNG's proportions, no
/// terminal or output line, the data in the datablock kLiveDataBlock.
Target live_target(PlotWindow& window, const PlotOptions& options);
/// Terminal, output and common settings at the top of every script.
std::string script_preamble(const Target& t, const PlotOptions& o, const std::string& what);
/// The executable `name` in one of the PATH directories, or empty.
fs::path find_on_path(const std::string& name);
/// Writes data and script and renders the image, or draws in the live window.
void write_and_render(const Target& t, const std::string& data, const std::string& script);

/// The speed axis of a set of rows: their range, ±5 % around a single speed.
std::pair<double, double> speed_axis(const std::vector<StabilityLimit>& rows);
/// The multiplier type's code in the .dat files ("hopf", "flip", "fold").
const char* type_word(MultiplierType t);

}  // namespace chatter::plot_kit
