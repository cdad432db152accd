// Plots through gnuplot: stability lobes, receptance (FRF) charts, Floquet
// stability maps and method comparisons.
//
// Every plot writes three files side by side, named after the image:
//   <stem>.dat  the plotted data, whitespace-separated columns under a `#`
//               header naming each column and its unit; several data sets
//               are separated by two blank lines (gnuplot `index`). Missing
//               values are `?` (gnuplot's `set datafile missing "?"`), never
//               nan or inf.
//   <stem>.gp   a self-contained gnuplot script that reads <stem>.dat and
//               writes <stem>.<ext>, both by relative name, so
//               `cd DIR && gnuplot <stem>.gp` reproduces the image and a user
//               can restyle it without the engine.
//   <stem>.<ext> the image, rendered by running gnuplot on that script.
// The terminal follows the image extension (case-insensitive): .png
// (pngcairo), .svg (svg), .pdf (pdfcairo). Units are the shop units of the
// tables: spindle speed rev/min, depth mm, frequency Hz; receptance m/N.
// Full description: docs/plots.md.
//
// Error channels:
//  - unknown image extension -> InputError, before anything is written
//    (call check_plot_path() first to fail before any computation);
//  - unwritable directory -> InputError naming the path (nothing rendered);
//  - gnuplot not on PATH -> GnuplotNotFound (an InputError), thrown AFTER the
//    .dat and .gp files were written; its message says how to install gnuplot;
//  - gnuplot failing on the script -> PlotError (internal failure).
//
// Live plots: each plot function that the CLI's --show draws (lobes, map,
// compare, simulation, and plot_surface / plot_uncertain_lobes) also takes a
// PlotWindow instead of an image path: the same data and the same script,
// without the terminal and output lines and with the data in a gnuplot
// datablock, handed to the window (the CLI feeds a gnuplot process through
// gnuplot-iostream: src/cli/live_plot.cpp). Nothing is written to disk.
//
// Thread safety: the functions share no state; concurrent calls must write
// different files.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/lobes.hpp"
#include "chatter/results.hpp"  // MultiplierType, SimulationResult: plain data, no solver
#include "chatter/structural_model.hpp"

namespace chatter {

/// gnuplot is not installed (not found on PATH). The data and script files
/// were written before this is thrown; the message names them.
class GnuplotNotFound : public InputError {
 public:
  using InputError::InputError;
};

/// gnuplot ran but failed (non-zero exit status); the message carries its
/// standard error. Not the user's fault: an internal failure.
class PlotError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ImageFormat { png, svg, pdf };

/// The `set terminal` line (with its newline) of a 1200 × 800 px image
/// (12 × 8 in for PDF) in the house style, for scripts that define the
/// gnuplot variable `fs` (font size) before it: pngcairo, svg on white, or
/// pdfcairo. Shared by every fixed-size plot script (fit, shop data).
std::string fixed_size_terminal(ImageFormat format);

/// The format chosen by the image extension (.png, .svg, .pdf; any case).
/// @throws InputError "<path>: unknown image type '<ext>' (use .png, .svg or .pdf)".
ImageFormat check_plot_path(const std::filesystem::path& image);

/// What a FRF chart shows in its two panels.
enum class FrfParts {
  magnitude_phase,  ///< |G| (m/N, log axis) over phase (deg).
  real_imaginary,   ///< Re G over Im G (m/N, linear axes).
};

/// Size and style shared by all plots.
struct PlotOptions {
  /// Image size in pixels (.png, .svg); .pdf uses width/100 × height/100 inches.
  int width_px = 1200;
  int height_px = 800;
  /// Base font size, points (scaled with the image as gnuplot does).
  int font_size = 14;
  /// plot_frf only: which parts of the receptance are drawn.
  FrfParts frf_parts = FrfParts::magnitude_phase;
  /// plot_lobes only: a lower panel with the chatter frequency (Hz) at the
  /// limit against spindle speed.
  bool chatter_frequency_panel = false;
  /// plot_lobes and plot_compare: top of the depth axis, mm (> 0), or 0 for
  /// the automatic range (see plot_lobes). Not capped: the caller chose it.
  double depth_axis_max_mm = 0.0;

  /// Empty when valid, else the violated rule.
  std::string validate() const;
};

/// Where a live plot goes (the CLI's --show). The io layer hands it text;
/// the window (outside the io layer) owns the gnuplot process.
class PlotWindow {
 public:
  virtual ~PlotWindow() = default;
  /// Draws (or redraws) one plot: `data` is the text of the plot's .dat
  /// file, `script` its .gp script without terminal and output, reading the
  /// data from the datablock kLiveDataBlock (the window defines it first).
  /// @throws whatever the window's transport throws (the CLI: InputError
  /// when gnuplot has gone, having failed to open its terminal).
  virtual void draw(const std::string& data, const std::string& script) = 0;
};

/// The gnuplot datablock a live plot's script reads (`data = '$data'`).
inline constexpr const char* kLiveDataBlock = "$data";

/// The head of a live plot's script: the image script's settings without
/// its terminal and output (`fs`, encoding, missing values, `data`).
std::string live_script_head(const std::string& what, int font_size = 14);

/// The files a plot wrote.
struct PlotFiles {
  std::filesystem::path image;
  std::filesystem::path script;  ///< <stem>.gp
  std::filesystem::path data;    ///< <stem>.dat
};

/// Stability-lobe diagram: x = spindle speed (rev/min), y = depth of cut (mm).
/// The envelope as a thick line with the stable region below it filled (rows
/// with no limit below the searched depth fill up to depth_max_m, the line
/// has a gap there); the region above shaded as chatter; each lobe curve as a
/// thin line, numbered k near its minimum when that minimum lies inside the
/// plot; the absolute limit as a dashed line labelled with its value (omitted
/// when infinite). The y range is 0 to a rounded value around 4× the absolute
/// limit and 1.1× the largest bounded envelope depth (so that every finite
/// limit, the deepest stable pocket included, is drawn with a margin),
/// capped at depth_max_m; PlotOptions::depth_axis_max_mm overrides it.
/// @param envelope  rows of lobe_envelope() in increasing speed (>= 1 row).
/// @param curves    lobe_curves() over the same speed range (may be empty).
/// @param depth_max_m  deepest cut searched (the solver's depth_max_m()).
/// @throws InputError (bad path, extension, options or empty envelope),
///         GnuplotNotFound, PlotError; see the file comment.
PlotFiles plot_lobes(const std::filesystem::path& image, const std::string& title,
                     const std::vector<StabilityLimit>& envelope, const std::vector<LobeCurve>& curves,
                     const AbsoluteLimit& absolute_limit, double depth_max_m, const PlotOptions& options = {});
/// The same diagram in a live window (see PlotWindow).
void plot_lobes(PlotWindow& window, const std::string& title, const std::vector<StabilityLimit>& envelope,
                const std::vector<LobeCurve>& curves, const AbsoluteLimit& absolute_limit, double depth_max_m,
                const PlotOptions& options = {});

/// Receptance chart, two stacked panels against frequency (Hz): magnitude
/// (m/N, log axis) and phase (deg), or real and imaginary parts (see
/// PlotOptions::frf_parts), of the xx term of the tool, the workpiece and the
/// relative receptance G = G_tool + G_workpiece — and of the yy term when any
/// mode has a Y component. Rigid bodies are listed in the key as rigid, not
/// drawn. `points` frequencies from f_min_hz to f_max_hz, evenly or (with
/// log_frequency) logarithmically spaced; log_frequency also makes the
/// frequency axis logarithmic.
/// @throws InputError on f_min_hz < 0 (<= 0 with log_frequency),
///         f_max_hz <= f_min_hz, points < 2, a model with no mode, or as
///         plot_lobes.
PlotFiles plot_frf(const std::filesystem::path& image, const std::string& title, const StructuralModel& model,
                   double f_min_hz, double f_max_hz, int points, bool log_frequency,
                   const PlotOptions& options = {});

/// A Floquet stability map on a regular speed × depth grid: what
/// SemiDiscretizationSolver::spectral_radius_map() returns, plus (optionally)
/// the type of the dominant multiplier where the map is unstable.
struct StabilityMapGrid {
  /// Spindle speeds, rev/min: >= 2 values, finite, > 0, strictly increasing.
  std::vector<double> spindle_rpm;
  /// Depths of cut, m: >= 2 values, finite, >= 0, strictly increasing.
  std::vector<double> depth_m;
  /// Spectral radius ρ (dimensionless, finite, >= 0) at
  /// (spindle_rpm[i], depth_m[j]) as element i * depth_m.size() + j (speeds
  /// outermost, the layout of spectral_radius_map()).
  std::vector<double> spectral_radius;
  /// Empty, or the type of the dominant multiplier at every grid point (same
  /// layout, e.g. FloquetResult::type from analyse()). Only the entries where
  /// ρ >= 1 are read, so a caller may fill the stable points with anything.
  std::vector<MultiplierType> multiplier_type;
};

/// Stability map (heat map): x = spindle speed (rev/min), y = depth of cut
/// (mm), colour = spectral radius ρ on a logarithmic scale centred on ρ = 1
/// (blues below 1, stable; oranges to reds above 1, chatter; clipped at
/// 1/R and R, R from {1.5, 2, 3, 5, 10} chosen to cover 90 % of the grid's
/// |ln ρ|). The ρ = 1 contour (linear interpolation of ln ρ along the grid
/// edges) is drawn as a line; with multiplier types, its Hopf, flip and fold
/// parts are drawn in different styles and the unstable grid points where the
/// dominant multiplier is flip (or fold) are marked (thinned to at most about
/// 40 × 25 marks), each named in the legend.
/// @throws InputError (bad path, extension or options; a grid that breaks a
///         rule of StabilityMapGrid), GnuplotNotFound, PlotError.
PlotFiles plot_stability_map(const std::filesystem::path& image, const std::string& title,
                             const StabilityMapGrid& map, const PlotOptions& options = {});
/// The same map in a live window (see PlotWindow).
void plot_stability_map(PlotWindow& window, const std::string& title, const StabilityMapGrid& map,
                        const PlotOptions& options = {});

/// A Floquet stability map at one spindle speed over radial immersion
/// (a_e / D) × axial depth (`chatter map --axes radial-axial`), with the
/// depth limit searched at each immersion.
struct RadialStabilityMapGrid {
  double spindle_rpm = 0.0;  ///< the speed of the whole map, rev/min
  /// a_e / D: >= 2 values in (0, 1], strictly increasing.
  std::vector<double> radial_immersion;
  /// D, m: > 0 draws the x axis as a_e in mm, 0 (not given) as a_e / D.
  double tool_diameter_m = 0.0;
  /// Axial depths of cut a_p, m: >= 2 values, finite, >= 0, strictly increasing.
  std::vector<double> depth_m;
  /// ρ at (radial_immersion[i], depth_m[j]) as element i * depth_m.size() + j.
  std::vector<double> spectral_radius;
  /// Empty, or the dominant multiplier's type at every point (as StabilityMapGrid).
  std::vector<MultiplierType> multiplier_type;
  /// Empty, or per immersion the limit of the lobe table's search at
  /// spindle_rpm (depth_limit_m = +inf: none below the depth searched).
  std::vector<StabilityLimit> limit;
};

/// The radial × axial map drawn as plot_stability_map draws the speed ×
/// depth one (x: a_e in mm, or a_e / D without a diameter; y: a_p in mm),
/// the searched limits as black points. @throws as plot_stability_map.
PlotFiles plot_radial_stability_map(const std::filesystem::path& image, const std::string& title,
                                    const RadialStabilityMapGrid& map, const PlotOptions& options = {});
/// The same map in a live window (see PlotWindow).
void plot_radial_stability_map(PlotWindow& window, const std::string& title, const RadialStabilityMapGrid& map,
                               const PlotOptions& options = {});

/// One method's depth limits for plot_compare().
struct MethodLimits {
  /// Name in the legend and the data columns (e.g. "analytic"); not empty.
  std::string method;
  /// One row per spindle speed (the same speeds, in the same order, for every
  /// method); +inf depth = no limit below the searched depth (a gap).
  std::vector<StabilityLimit> limits;
  /// Empty, or one entry per row (sdm: FloquetResult::type at the limit);
  /// the bounded rows of type flip or fold are marked on the line.
  std::vector<MultiplierType> multiplier_type;
};

/// Method comparison: every method's depth limit (mm) against spindle speed
/// (rev/min) on one chart, one line style per method (analytic, coupled, sdm
/// and time-domain always get the same styles; wider lines are drawn first,
/// so that curves that coincide all stay visible), the stretches where a
/// method with multiplier types is limited by a flip (or fold) multiplier
/// drawn over its line, a legend naming the methods; speeds with no limit
/// below depth_max_m leave a gap. The y range is 0 to a rounded value at or
/// above 1.1× the largest bounded limit of all methods and 3× the smallest,
/// capped at depth_max_m; PlotOptions::depth_axis_max_mm overrides it.
/// @param methods  1 to 8 methods, each with the same (>= 1) speeds.
/// @param depth_max_m  deepest cut searched, m (> 0).
/// @throws InputError (bad path, extension or options; no method, an empty
///         or duplicate name, different speeds, a multiplier_type list of the
///         wrong size), GnuplotNotFound, PlotError.
PlotFiles plot_compare(const std::filesystem::path& image, const std::string& title,
                       const std::vector<MethodLimits>& methods, double depth_max_m,
                       const PlotOptions& options = {});
/// The same chart in a live window (see PlotWindow).
void plot_compare(PlotWindow& window, const std::string& title, const std::vector<MethodLimits>& methods,
                  double depth_max_m, const PlotOptions& options = {});

/// One time-domain run (TimeDomainSimulator::simulate with record_series):
/// three stacked panels — the relative displacement (µm) along X and, when
/// it moves, Y against time (ms) with the once-per-period samples drawn over
/// it as dots (they converge to one point in a stable cut, scatter or
/// alternate in chatter); the cutting force (N) on the tool; and the
/// amplitude spectrum (µm, log axis) of the relative displacement over the
/// analysed window against frequency (Hz), the tooth-passing (spindle, in
/// turning) harmonics marked by dashed lines and circles, the chatter
/// frequency labelled. The title carries the verdict.
/// @param f_max_hz  highest natural frequency of the model (Hz, > 0): the
///                  spectrum is drawn up to 2.5× it.
/// @throws InputError (bad path, extension or options; no series — run with
///         record_series), GnuplotNotFound, PlotError.
PlotFiles plot_simulation(const std::filesystem::path& image, const std::string& title,
                          const SimulationResult& result, double f_max_hz, const PlotOptions& options = {});
/// The same panels in a live window (see PlotWindow). With `running` the
/// result is a run still integrating (SimulationSettings::on_period): the
/// title counts the periods done instead of giving a verdict, and the
/// spectrum panel stays empty until the last call.
void plot_simulation(PlotWindow& window, const std::string& title, const SimulationResult& result, double f_max_hz,
                     bool running, const PlotOptions& options = {});

/// Runs `gnuplot <script filename>` with the script's directory as working
/// directory (what the plot functions do after writing the files).
/// @throws GnuplotNotFound, PlotError.
void run_gnuplot(const std::filesystem::path& script);

/// What every plot does once its .dat and .gp are written: removes a stale
/// `image` (none survives a failed run), runs gnuplot on `script`
/// (run_gnuplot) and checks that it wrote a non-empty `image`.
/// @throws GnuplotNotFound, PlotError.
void render_gnuplot_image(const std::filesystem::path& script, const std::filesystem::path& image);

/// A number for a plot's .dat file or script: `digits` significant digits,
/// "?" when not finite (the scripts declare `set datafile missing '?'`).
std::string gnuplot_number(double x, int digits = 8);

/// `s` as a gnuplot single-quoted string (' doubled, line breaks as spaces),
/// for scripts written beside an image.
std::string gnuplot_quote(const std::string& s);

}  // namespace chatter
