// Plots through gnuplot (see include/chatter/io/plot.hpp and docs/plots.md):
// stability lobes, receptance, Floquet stability maps, method comparisons.
//
// Each plot is built as two texts, the data (<stem>.dat) and a gnuplot script
// (<stem>.gp) that reads it by relative name; both are written next to the
// image, then gnuplot is run on the script in that directory. gnuplot is
// found on PATH and started with posix_spawn (no shell, so no quoting of user
// paths), so the library needs no extra link dependency.
#include "chatter/io/plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <iterator>
#include <numbers>
#include <sstream>
#include <system_error>
#include <utility>

#include "chatter/io/table_writer.hpp"
#include "chatter/solvers.hpp"

extern char** environ;

namespace chatter {

// A gnuplot single-quoted string: only ' needs escaping (doubled); no
// backslash processing, so paths and titles pass through unchanged.
std::string gnuplot_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "''";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out + "'";
}

namespace fs = std::filesystem;

std::string fixed_size_terminal(ImageFormat format) {
  switch (format) {
    case ImageFormat::png:
      return "set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2\n";
    case ImageFormat::svg:
      return "set terminal svg size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2 background '#ffffff'\n";
    case ImageFormat::pdf:
      return "set terminal pdfcairo size 12in,8in enhanced font 'DejaVu Sans,'.fs linewidth 1\n";
  }
  return "";
}

namespace {

constexpr const char* kInstallHint =
    "install gnuplot (Debian/Ubuntu: apt-get install gnuplot-nox; Fedora: dnf install gnuplot; "
    "macOS: brew install gnuplot)";

// Colours (a light, print-friendly palette).
constexpr const char* kStableFill = "#8cc97e";  // drawn 40 % opaque
constexpr const char* kChatterFill = "#f08a7e";  // drawn 30 % opaque
constexpr const char* kEnvelope = "#1a4d80";
constexpr const char* kLobe = "#606a6a6a";  // ARGB: 38 % transparent
constexpr const char* kAbsolute = "#c0392b";
constexpr const char* kLabel = "#3a3a3a";
constexpr const char* kGrid = "#c8c8c8";
constexpr const char* kTool = "#1f77b4";
constexpr const char* kWorkpiece = "#e07b00";
constexpr const char* kRelative = "#202020";

// A number for the .dat file: 10 significant digits (or `digits`), `?` when
// not finite.
std::string num(double x, int digits = 10) {
  if (!std::isfinite(x)) return "?";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

// A number for the script and for labels: `digits` significant digits.
std::string short_num(double x, int digits = 4) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

std::string quote(const std::string& s) { return gnuplot_quote(s); }

// Text for a `#` comment line: line breaks become spaces.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

// A shell word for the "run this" hint in messages.
std::string shell_word(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./+") ==
                        std::string::npos)
    return s;
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Smallest "nice" number (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 × 10^n) >= x > 0.
double nice_ceil(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0})
    if (m * p >= x * (1 - 1e-12)) return m * p;
  return 10 * p;
}

struct Target {
  ImageFormat format;
  fs::path image, script, data;
  std::string image_name, data_name;  // relative names used inside the script
  PlotWindow* window = nullptr;       // a live plot (--show): no files, the data in a datablock
  std::string label;                  // what messages name: the image, or "live plot"
};

Target make_target(const fs::path& image, const PlotOptions& options) {
  Target t{check_plot_path(image), image, image, image, "", ""};
  if (const std::string rule = options.validate(); !rule.empty())
    throw InputError("plot options: " + rule);
  if (image.filename().empty() || image.stem().empty())
    throw InputError(image.string() + ": not an image file name");
  t.script.replace_extension(".gp");
  t.data.replace_extension(".dat");
  t.image_name = image.filename().string();
  t.data_name = t.data.filename().string();
  t.label = image.string();
  return t;
}

// A live plot: the image's script and data with the PNG's proportions, no
// terminal or output line, the data in the datablock kLiveDataBlock.
Target live_target(PlotWindow& window, const PlotOptions& options) {
  if (const std::string rule = options.validate(); !rule.empty()) throw InputError("plot options: " + rule);
  Target t{ImageFormat::png, {}, {}, {}, "", kLiveDataBlock};
  t.window = &window;
  t.label = "live plot";
  return t;
}

// Terminal, output and common settings at the top of every script.
std::string script_preamble(const Target& t, const PlotOptions& o, const std::string& what) {
  std::ostringstream gp;
  if (t.window) return live_script_head(what, o.font_size);
  gp << "# " << what << ", written by chatter " << version() << ".\n"
     << "# Reproduce or restyle: cd into this directory, edit, then run\n"
     << "#   gnuplot " << t.script.filename().string() << "\n"
     << "# It reads " << t.data_name << " and writes " << t.image_name << " (both by relative name).\n\n";
  // Base font size (pt). The bitmap terminals draw a point as a pixel; the
  // PDF page is width/100 inches wide (72 pt per inch), so 0.72 × the size
  // keeps the same proportions as the PNG.
  const int base_pt =
      t.format == ImageFormat::pdf ? std::max(4, static_cast<int>(std::lround(o.font_size * 0.72))) : o.font_size;
  gp << "fs = " << base_pt << "   # base font size (pt); title, key and labels are relative to it\n";
  const std::string font = "font 'DejaVu Sans,'.fs";
  switch (t.format) {
    case ImageFormat::png:
      gp << "set terminal pngcairo size " << o.width_px << "," << o.height_px << " enhanced " << font
         << " linewidth 1.2\n";
      break;
    case ImageFormat::svg:
      gp << "set terminal svg size " << o.width_px << "," << o.height_px << " enhanced " << font
         << " linewidth 1.2 background '#ffffff'\n";
      break;
    case ImageFormat::pdf:
      gp << "set terminal pdfcairo size " << short_num(o.width_px / 100.0) << "in," << short_num(o.height_px / 100.0)
         << "in enhanced " << font << " fontscale 1 linewidth 1\n";
      break;
  }
  gp << "set output " << quote(t.image_name) << "\n"
     << "set encoding utf8\n"
     << "set datafile missing '?'\n"
     << "data = " << quote(t.data_name) << "\n\n";
  return gp.str();
}

// The executable `name` in one of the PATH directories, or empty.
fs::path find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::string dirs = path;
  std::size_t start = 0;
  while (start <= dirs.size()) {
    std::size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = dirs.substr(start, end - start);
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return {};
}

void write_and_render(const Target& t, const std::string& data, const std::string& script) {
  if (t.window) {
    t.window->draw(data, script);
    return;
  }
  write_text_file(t.data, data);
  write_text_file(t.script, script);
  render_gnuplot_image(t.script, t.image);
}

}  // namespace

std::string live_script_head(const std::string& what, int font_size) {
  std::ostringstream gp;
  gp << "# " << what << ", drawn live by chatter " << version() << " (the data are in the datablock "
     << kLiveDataBlock << ").\n"
     << "fs = " << font_size << "   # base font size (pt); title, key and labels are relative to it\n"
     << "set encoding utf8\n"
     << "set datafile missing '?'\n"
     << "data = " << quote(kLiveDataBlock) << "\n\n";
  return gp.str();
}

void render_gnuplot_image(const fs::path& script, const fs::path& image) {
  std::error_code ec;
  fs::remove(image, ec);  // no stale image survives a failed run
  run_gnuplot(script);
  if (!fs::is_regular_file(image, ec) || fs::file_size(image, ec) == 0)
    throw PlotError("gnuplot ran on " + script.string() + " but wrote no image " + image.string());
}

std::string gnuplot_number(double x, int digits) {
  if (!std::isfinite(x)) return "?";
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

std::string PlotOptions::validate() const {
  if (width_px < 200 || width_px > 10000) return "width_px must be in [200, 10000]";
  if (height_px < 150 || height_px > 10000) return "height_px must be in [150, 10000]";
  if (font_size < 4 || font_size > 72) return "font_size must be in [4, 72]";
  if (!(std::isfinite(depth_axis_max_mm) && depth_axis_max_mm >= 0.0))
    return "depth_axis_max_mm must be > 0 mm (or 0: automatic)";
  return {};
}

ImageFormat check_plot_path(const fs::path& image) {
  const std::string ext = lower(image.extension().string());
  if (ext == ".png") return ImageFormat::png;
  if (ext == ".svg") return ImageFormat::svg;
  if (ext == ".pdf") return ImageFormat::pdf;
  throw InputError(image.string() + ": unknown image type '" + image.extension().string() +
                   "' (use .png, .svg or .pdf)");
}

void run_gnuplot(const fs::path& script) {
  const fs::path gnuplot = find_on_path("gnuplot");
  const fs::path dir = script.parent_path().empty() ? fs::path(".") : script.parent_path();
  const std::string name = script.filename().string();
  const std::string rerun = "cd " + shell_word(dir.string()) + " && gnuplot " + shell_word(name);
  if (gnuplot.empty())
    throw GnuplotNotFound("gnuplot not found on PATH, so no image was drawn; " + std::string(kInstallHint) +
                          ". The plot data and script were written; once gnuplot is installed run: " + rerun);

  int err_pipe[2];
  if (::pipe(err_pipe) != 0) throw PlotError(std::string("cannot create a pipe for gnuplot: ") + std::strerror(errno));
  // Close-on-exec, so that a process spawned by another thread does not
  // inherit the pipe (dup2 onto stderr clears the flag for gnuplot itself).
  ::fcntl(err_pipe[0], F_SETFD, FD_CLOEXEC);
  ::fcntl(err_pipe[1], F_SETFD, FD_CLOEXEC);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, err_pipe[0]);
  posix_spawn_file_actions_addclose(&actions, err_pipe[1]);
  std::string arg0 = "gnuplot", arg1 = name;
  char* argv[] = {arg0.data(), arg1.data(), nullptr};
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, gnuplot.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(err_pipe[1]);
  if (rc != 0) {
    ::close(err_pipe[0]);
    if (rc == ENOENT)
      throw GnuplotNotFound("cannot start gnuplot (" + gnuplot.string() + ") in " + dir.string() + ": " +
                            std::strerror(rc) + "; " + kInstallHint + ". Then run: " + rerun);
    throw PlotError("cannot start gnuplot (" + gnuplot.string() + ") in " + dir.string() + ": " + std::strerror(rc));
  }
  std::string err;
  std::array<char, 4096> buf;
  for (;;) {
    const ssize_t n = ::read(err_pipe[0], buf.data(), buf.size());
    if (n > 0) err.append(buf.data(), static_cast<std::size_t>(n));
    else if (n == 0 || errno != EINTR) break;
  }
  ::close(err_pipe[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
      throw GnuplotNotFound("cannot run gnuplot in " + dir.string() + "; " + kInstallHint + ". Then run: " + rerun);
    while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
    throw PlotError("gnuplot failed on " + script.string() + " (" +
                    (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                       : std::string("killed by a signal")) +
                    ")" + (err.empty() ? std::string() : ":\n" + err));
  }
}

// ---------------------------------------------------------------------------
// Stability lobes

namespace {

// The speed axis of a set of rows: their range, ±5 % around a single speed.
std::pair<double, double> speed_axis(const std::vector<StabilityLimit>& rows) {
  double rpm_lo = rows.front().spindle_rpm, rpm_hi = rows.front().spindle_rpm;
  for (const auto& r : rows) {
    rpm_lo = std::min(rpm_lo, r.spindle_rpm);
    rpm_hi = std::max(rpm_hi, r.spindle_rpm);
  }
  if (!(rpm_hi > rpm_lo)) {  // one speed: show ±5 % around it
    rpm_lo *= 0.95;
    rpm_hi *= 1.05;
  }
  return {rpm_lo, rpm_hi};
}

// Top of the depth axis (mm): every finite limit visible with a 10 % margin
// (the deepest stable pocket, e.g. a flip/Hopf pocket of sdm at low
// immersion, must not be cut off), and at least 4 × the absolute limit (if
// any, else the lowest depth) so that the pockets stand out from it; rounded
// up to a nice value and capped at depth_max_mm. `bounded`: the bounded
// depths (mm, clipped to depth_max_mm).
constexpr double kDepthAxisMargin = 1.1;
double lobes_y_max(const std::vector<double>& bounded, double depth_max_mm, bool has_abs, double abs_mm) {
  double y_max = depth_max_mm;
  if (!bounded.empty()) {
    const double lowest = *std::min_element(bounded.begin(), bounded.end());
    const double highest = *std::max_element(bounded.begin(), bounded.end());
    const double want = std::max(4.0 * (has_abs ? abs_mm : lowest), kDepthAxisMargin * highest);
    y_max = std::min(depth_max_mm, nice_ceil(want));
  }
  return y_max;
}

struct Label {
  double rpm, depth_mm;
  int lobe;
};

// Lobe-number labels: each piece's minimum, if it is a true minimum (not an
// end point cut by the speed range) inside the plot, thinned so that labels
// are only written for lobes whose minimum has no other lobe minimum within
// 5 % of the width (the crowded low-speed lobes stay unlabelled).
std::vector<Label> lobe_labels(const std::vector<LobeCurve>& curves, double rpm_lo, double rpm_hi, double y_max) {
  std::vector<Label> candidates;
  for (const auto& c : curves) {
    if (c.points.size() < 3) continue;
    std::size_t imin = 0;
    for (std::size_t i = 1; i < c.points.size(); ++i)
      if (c.points[i].depth_m < c.points[imin].depth_m) imin = i;
    if (imin == 0 || imin + 1 == c.points.size()) continue;
    const auto& p = c.points[imin];
    const double d = p.depth_m * 1e3;
    if (p.spindle_rpm <= rpm_lo || p.spindle_rpm >= rpm_hi || d >= 0.9 * y_max) continue;
    candidates.push_back({p.spindle_rpm, d, c.lobe});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Label& a, const Label& b) { return a.rpm > b.rpm; });
  std::vector<Label> labels;
  const double span = rpm_hi - rpm_lo;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Label& c = candidates[i];
    if (c.rpm - rpm_lo < 0.03 * span || rpm_hi - c.rpm < 0.03 * span) continue;
    bool clear = true;  // no other lobe minimum (of any lobe) close by
    for (std::size_t j = 0; j < candidates.size() && clear; ++j)
      if (j != i && std::abs(candidates[j].rpm - c.rpm) < 0.05 * span &&
          std::abs(candidates[j].depth_mm - c.depth_mm) < 0.1 * y_max)
        clear = false;
    if (clear) labels.push_back(c);
  }
  std::sort(labels.begin(), labels.end(), [](const Label& a, const Label& b) { return a.rpm < b.rpm; });
  return labels;
}

// The .dat of plot_lobes: envelope (index 0), lobe pieces (1), labels (2).
// `curve_points` = rows written to index 1.
std::string lobes_data(const std::string& title, const std::vector<StabilityLimit>& envelope,
                       const std::vector<LobeCurve>& curves, const std::vector<Label>& labels, double depth_max_mm,
                       bool has_abs, double abs_mm, double y_max, std::size_t& curve_points) {
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": stability lobes (chatter " << version() << ")\n"
      << "# depth_max_mm = " << num(depth_max_mm) << " (deepest cut searched)\n"
      << "# absolute_limit_mm = " << num(has_abs ? abs_mm : INFINITY) << " ('?' = none below depth_max_mm)\n"
      << "# Missing values are '?' (gnuplot: set datafile missing '?').\n\n"
      << "# index 0: lobe envelope, one row per spindle speed. depth_limit_mm is '?' where no\n"
      << "# instability exists below depth_max_mm; depth_filled_mm is then depth_max_mm and bounded 0.\n"
      << "# spindle_rpm depth_limit_mm depth_filled_mm chatter_frequency_hz lobe bounded\n";
  for (const auto& r : envelope) {
    const bool b = r.bounded();
    dat << num(r.spindle_rpm) << ' ' << (b ? num(r.depth_limit_m * 1e3) : "?") << ' '
        << num(b ? std::min(r.depth_limit_m * 1e3, depth_max_mm) : depth_max_mm) << ' '
        << (b ? num(r.chatter_frequency_hz) : "?") << ' ' << (b && r.lobe >= 0 ? std::to_string(r.lobe) : "?")
        << ' ' << (b ? 1 : 0) << '\n';
  }
  dat << "\n\n# index 1: individual lobes, one block per lobe piece (blocks separated by one blank line);\n"
      << "# 7 significant digits; parts above the top of the plot (" << num(y_max)
      << " mm) are left out, except the point\n"
      << "# just beyond it so that lines reach the edge.\n"
      << "# spindle_rpm depth_mm chatter_frequency_hz lobe branch\n";
  bool first_block = true;
  curve_points = 0;
  for (const auto& c : curves) {
    const auto& pts = c.points;
    auto inside = [&](std::size_t i) {
      return std::isfinite(pts[i].depth_m) && std::isfinite(pts[i].spindle_rpm) && pts[i].depth_m * 1e3 <= y_max;
    };
    bool in_block = false;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const bool keep = std::isfinite(pts[i].depth_m) && std::isfinite(pts[i].spindle_rpm) &&
                        (inside(i) || (i > 0 && inside(i - 1)) || (i + 1 < pts.size() && inside(i + 1)));
      if (!keep) {
        in_block = false;
        continue;
      }
      if (!in_block && !first_block) dat << '\n';
      in_block = true;
      first_block = false;
      const auto& p = pts[i];
      dat << num(p.spindle_rpm, 7) << ' ' << num(p.depth_m * 1e3, 7) << ' ' << num(p.chatter_frequency_hz, 7)
          << ' ' << c.lobe << ' ' << c.branch << '\n';
      ++curve_points;
    }
  }
  dat << "\n\n# index 2: lobe-number labels at the minimum of a lobe\n# spindle_rpm depth_mm lobe\n";
  for (const auto& l : labels) dat << num(l.rpm) << ' ' << num(l.depth_mm) << ' ' << l.lobe << '\n';
  return dat.str();
}

// The lower panel of plot_lobes: the chatter frequency at the limit.
std::string frequency_panel_script(bool any_bounded) {
  std::ostringstream gp;
  gp << "\n# Lower panel: chatter frequency at the limit\n"
     << "unset label 1; unset label 3; unset title; unset key\n"
     << "set tmargin at screen 0.36; set bmargin at screen 0.10\n"
     << "set format x '%g'\n"
     << "set xlabel 'spindle speed (rev/min)'\n"
     << "set ylabel 'chatter frequency (Hz)'\n"
     << "set ytics autofreq\n";
  if (any_bounded)
    gp << "set autoscale y\n"
       << "plot data index 0 using 1:4 with points pt 7 ps 0.35 lc rgb c_envelope notitle\n";
  else  // nothing to show: an empty panel that says why
    gp << "set yrange [0:1]; set format y ''\n"
       << "set label 2 sprintf('no chatter below %g mm at any speed', depth_max) at graph 0.5, graph 0.5 center\n"
       << "plot -1 with lines notitle\n";
  return gp.str();
}

// The gnuplot script of plot_lobes.
std::string lobes_script(const Target& t, const std::string& title, const PlotOptions& options, double rpm_lo,
                         double rpm_hi, double y_max, double depth_max_mm, bool has_abs, double abs_mm,
                         bool any_bounded, std::size_t curve_points, bool any_labels) {
  const PlotOptions& o = options;
  const bool freq_panel = o.chatter_frequency_panel;
  std::ostringstream gp;
  gp << script_preamble(t, o, "Stability-lobe diagram")
     << "# Values from the engine (mm, rev/min)\n"
     << "y_max = " << short_num(y_max, 6) << "          # top of the depth axis\n"
     << "depth_max = " << short_num(depth_max_mm, 6) << "      # deepest cut searched\n";
  if (has_abs) gp << "abs_limit = " << short_num(abs_mm, 6) << "      # absolute (speed-independent) limit\n";
  gp << "\n# Colours\n"
     << "c_stable = " << quote(kStableFill) << "; c_chatter = " << quote(kChatterFill) << "\n"
     << "c_envelope = " << quote(kEnvelope) << "; c_lobe = " << quote(kLobe) << "; c_abs = " << quote(kAbsolute)
     << "\n\n";
  // Layout in screen coordinates so that the optional lower panel lines up.
  const double top = 0.85, bottom = freq_panel ? 0.40 : 0.11;
  gp << "set multiplot title " << quote(title) << " noenhanced font ','.(fs+3)\n"
     << "set lmargin at screen 0.085; set rmargin at screen 0.975\n"
     << "set tmargin at screen " << top << "; set bmargin at screen " << bottom << "\n"
     << "set key at screen 0.53, screen 0.895 center center horizontal reverse Left samplen 2 width -1 "
        "font ','.(fs-1)\n"
     << "set border lw 1 lc rgb '#404040'\n"
     << "set grid xtics ytics mxtics mytics back lw 1 lc rgb " << quote(kGrid) << ", lw 0.5 lc rgb '#e4e4e4'\n"
     << "set mxtics 2; set mytics 2\n"
     << "set xrange [" << short_num(rpm_lo, 10) << ":" << short_num(rpm_hi, 10) << "]\n"
     << "set yrange [0:y_max]\n"
     << "set ylabel 'depth of cut (mm)'\n";
  if (freq_panel) gp << "set format x ''\nunset xlabel\n";
  else gp << "set xlabel 'spindle speed (rev/min)'\n";

  if (has_abs)
    gp << "set label 1 sprintf('absolute limit %.4g mm: stable at any speed below it', abs_limit) "
          "at graph 0.012, first abs_limit "
          "left offset 0,-0.9 font ','.(fs-1) tc rgb c_abs front\n";
  if (!any_bounded)
    gp << "set label 3 sprintf('no chatter below %g mm at any speed in the sweep', depth_max) "
          "at graph 0.5, graph 0.5 center front\n";
  gp << "set style textbox opaque fc rgb '#50ffffff' noborder margins 1,1   # behind the lobe numbers\n"
     << "plot \\\n"
     << "  data index 0 using 1:3:(depth_max > y_max ? depth_max : y_max) with filledcurves "
        "fs transparent solid 0.3 noborder fc rgb c_chatter "
        "title 'chatter', \\\n"
     << "  data index 0 using 1:(0):3 with filledcurves fs transparent solid 0.4 noborder fc rgb c_stable "
        "title 'stable', \\\n";
  if (curve_points > 0)
    gp << "  data index 1 using 1:2 with lines lw 0.7 lc rgb c_lobe title 'lobes', \\\n";
  if (has_abs)
    gp << "  abs_limit with lines dt (8,5) lw 2 lc rgb c_abs title 'absolute limit', "
          "\\\n";
  // The line breaks where there is no limit: NaN makes a point undefined
  // (a `?` row would be skipped and the line drawn across the gap).
  gp << "  data index 0 using 1:($6 > 0 ? $3 : NaN) with lines lw 3 lc rgb c_envelope title 'stability limit'";
  if (any_labels)
    gp << ", \\\n  data index 2 using 1:2:(sprintf('k=%d', int($3))) with labels boxed offset 0,0.9 font ','.(fs-2) "
          "tc rgb "
       << quote(kLabel) << " notitle";
  gp << "\n";
  if (freq_panel) gp << frequency_panel_script(any_bounded);
  gp << "unset multiplot\n";
  return gp.str();
}

}  // namespace

namespace {

void draw_lobes(const Target& t, const std::string& title, const std::vector<StabilityLimit>& envelope,
                const std::vector<LobeCurve>& curves, const AbsoluteLimit& absolute_limit, double depth_max_m,
                const PlotOptions& options) {
  if (envelope.empty()) throw InputError(t.label + ": no lobe envelope rows to plot");
  if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    throw InputError(t.label + ": depth_max = " + short_num(depth_max_m) + " m: must be > 0");

  const double depth_max_mm = depth_max_m * 1e3;
  const auto [rpm_lo, rpm_hi] = speed_axis(envelope);
  std::vector<double> bounded;
  for (const auto& r : envelope)
    if (r.bounded()) bounded.push_back(std::min(r.depth_limit_m * 1e3, depth_max_mm));
  const bool has_abs = std::isfinite(absolute_limit.depth_m) && absolute_limit.depth_m > 0.0;
  const double abs_mm = has_abs ? absolute_limit.depth_m * 1e3 : 0.0;
  const double y_max =
      options.depth_axis_max_mm > 0.0 ? options.depth_axis_max_mm : lobes_y_max(bounded, depth_max_mm, has_abs, abs_mm);
  const std::vector<Label> labels = lobe_labels(curves, rpm_lo, rpm_hi, y_max);
  std::size_t curve_points = 0;
  const std::string dat =
      lobes_data(title, envelope, curves, labels, depth_max_mm, has_abs, abs_mm, y_max, curve_points);
  const std::string gp = lobes_script(t, title, options, rpm_lo, rpm_hi, y_max, depth_max_mm, has_abs, abs_mm,
                                      !bounded.empty(), curve_points, !labels.empty());
  write_and_render(t, dat, gp);
}

}  // namespace

PlotFiles plot_lobes(const fs::path& image, const std::string& title, const std::vector<StabilityLimit>& envelope,
                     const std::vector<LobeCurve>& curves, const AbsoluteLimit& absolute_limit, double depth_max_m,
                     const PlotOptions& options) {
  const Target t = make_target(image, options);
  draw_lobes(t, title, envelope, curves, absolute_limit, depth_max_m, options);
  return {t.image, t.script, t.data};
}

void plot_lobes(PlotWindow& window, const std::string& title, const std::vector<StabilityLimit>& envelope,
                const std::vector<LobeCurve>& curves, const AbsoluteLimit& absolute_limit, double depth_max_m,
                const PlotOptions& options) {
  draw_lobes(live_target(window, options), title, envelope, curves, absolute_limit, depth_max_m, options);
}

// ---------------------------------------------------------------------------
// Receptance (FRF)

PlotFiles plot_frf(const fs::path& image, const std::string& title, const StructuralModel& model, double f_min_hz,
                   double f_max_hz, int points, bool log_frequency, const PlotOptions& options) {
  const Target t = make_target(image, options);
  if (!(std::isfinite(f_min_hz) && (log_frequency ? f_min_hz > 0.0 : f_min_hz >= 0.0)))
    throw InputError(image.string() + ": f_min = " + short_num(f_min_hz) + " Hz: must be " +
                     (log_frequency ? "> 0 with a log frequency axis" : ">= 0"));
  if (!(std::isfinite(f_max_hz) && f_max_hz > f_min_hz))
    throw InputError(image.string() + ": f_max = " + short_num(f_max_hz) + " Hz: must be > f_min (" +
                     short_num(f_min_hz) + " Hz)");
  if (points < 2) throw InputError(image.string() + ": points = " + std::to_string(points) + ": must be >= 2");
  if (model.rigid()) throw InputError(image.string() + ": the model has no mode (both bodies rigid)");

  bool has_y = false;
  for (const Body* b : {&model.tool, &model.workpiece})
    for (const Mode& m : b->modes)
      if (std::abs(m.direction.y()) > 1e-12) has_y = true;
  const bool tool_flex = !model.tool.rigid(), work_flex = !model.workpiece.rigid();

  struct Term {
    const char* name;
    int index;
  };
  std::vector<Term> terms = {{"xx", 0}};
  if (has_y) terms.push_back({"yy", 1});
  const char* bodies[] = {"tool", "workpiece", "relative"};

  // --- data ---
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": receptance (chatter " << version() << ")\n"
      << "# Relative receptance = tool + workpiece (docs/physics.md section 2). '?' = rigid body (no value).\n"
      << "# Per body and term: magnitude (m/N), phase (deg), real and imaginary parts (m/N).\n"
      << "# frequency_hz";
  for (const auto& term : terms)
    for (const char* body : bodies)
      dat << ' ' << body << '_' << term.name << "_abs_m_per_n " << body << '_' << term.name << "_phase_deg "
          << body << '_' << term.name << "_real_m_per_n " << body << '_' << term.name << "_imag_m_per_n";
  dat << '\n';
  for (int i = 0; i < points; ++i) {
    const double s = static_cast<double>(i) / (points - 1);
    const double f = log_frequency ? f_min_hz * std::pow(f_max_hz / f_min_hz, s) : f_min_hz + (f_max_hz - f_min_hz) * s;
    const double w = 2 * std::numbers::pi * f;
    const Matrix2c gt = model.tool.receptance(w), gw = model.workpiece.receptance(w);
    const Matrix2c gr = gt + gw;
    dat << num(f);
    for (const auto& term : terms) {
      const Matrix2c* g[] = {&gt, &gw, &gr};
      const bool flex[] = {tool_flex, work_flex, true};
      for (int b = 0; b < 3; ++b) {
        const Complex z = (*g[b])(term.index, term.index);
        if (!flex[b] || std::abs(z) == 0.0) {
          dat << " ? ? ? ?";
          continue;
        }
        dat << ' ' << num(std::abs(z)) << ' ' << num(std::arg(z) * 180.0 / std::numbers::pi) << ' ' << num(z.real())
            << ' ' << num(z.imag());
      }
    }
    dat << '\n';
  }

  // --- script ---
  const bool mag_phase = options.frf_parts == FrfParts::magnitude_phase;
  std::ostringstream gp;
  gp << script_preamble(t, options, "Receptance (FRF) chart") << "# Colours\n"
     << "c_tool = " << quote(kTool) << "; c_workpiece = " << quote(kWorkpiece) << "; c_relative = "
     << quote(kRelative) << "\n"
     << "# Column of body b (0 tool, 1 workpiece, 2 relative), term t (0 xx, 1 yy), part p\n"
     << "# (0 magnitude, 1 phase, 2 real, 3 imaginary)\n"
     << "col(b, t, p) = 2 + 12*t + 4*b + p\n\n"
     << "set multiplot title " << quote(title) << " noenhanced font ','.(fs+3)\n"
     << "set lmargin at screen 0.11; set rmargin at screen 0.975\n"
     << "set border lw 1 lc rgb '#404040'\n"
     << "set grid xtics ytics mxtics mytics back lw 1 lc rgb " << quote(kGrid) << ", lw 0.5 lc rgb '#e4e4e4'\n"
     << "set xrange [" << short_num(f_min_hz, 10) << ":" << short_num(f_max_hz, 10) << "]\n";
  if (log_frequency) {
    gp << "set logscale x\nset mxtics 10\n";
    // Less than two decades: label 1-2-3-5 steps, not just the decades.
    if (f_max_hz / f_min_hz < 100.0) {
      std::string tics;
      for (double p = std::pow(10.0, std::floor(std::log10(f_min_hz))); p <= f_max_hz; p *= 10.0)
        for (double m : {1.0, 2.0, 3.0, 5.0})
          if (m * p >= f_min_hz * (1 - 1e-9) && m * p <= f_max_hz * (1 + 1e-9))
            tics += (tics.empty() ? "" : ", ") + short_num(m * p, 6);
      if (!tics.empty()) gp << "set xtics (" << tics << ")\n";
    }
  }
  else gp << "set mxtics 2\n";
  gp << "set key at screen 0.54, screen 0.9 center center horizontal reverse Left samplen 2 width -1 font ','.(fs-1)\n";

  // One plot command over the bodies and terms for part p.
  auto plot_part = [&](int p) {
    std::ostringstream pl;
    pl << "plot";
    bool first = true;
    auto add = [&](const std::string& clause) {
      pl << (first ? " \\\n  " : ", \\\n  ") << clause;
      first = false;
    };
    for (std::size_t ti = 0; ti < terms.size(); ++ti) {
      const std::string tn = terms[ti].name;
      const std::string dash = ti == 0 ? "" : " dt (6,4)";
      const std::string suffix = has_y ? " " + tn : "";
      const int bs[] = {2, 1, 0};  // relative first (underneath), bodies on top
      for (int b : bs) {
        if ((b == 0 && !tool_flex) || (b == 1 && !work_flex)) continue;
        const char* colour = b == 0 ? "c_tool" : b == 1 ? "c_workpiece" : "c_relative";
        const std::string lw = b == 2 ? "3.2" : "1.6";
        const std::string name = b == 0 ? "tool" : b == 1 ? "workpiece" : "relative = tool + workpiece";
        const std::string column =
            "col(" + std::to_string(b) + "," + std::to_string(ti) + "," + std::to_string(p) + ")";
        add("data using 1:" + (p >= 2 ? "(column(" + column + ") * 1e6)" : column) + " with lines lw " + lw +
            dash + " lc rgb " + colour + " title " + quote(name + suffix));
      }
    }
    if (!tool_flex) add("keyentry with lines lt nodraw title 'tool: rigid'");
    if (!work_flex) add("keyentry with lines lt nodraw title 'workpiece: rigid'");
    return pl.str() + "\n";
  };

  gp << "\n# Upper panel\n"
     << "set tmargin at screen 0.86; set bmargin at screen 0.515\n"
     << "set format x ''; unset xlabel\n";
  if (mag_phase)
    gp << "set logscale y\nset format y '10^{%L}'\nset mytics 10\nset ylabel 'magnitude |G| (m/N)'\n" << plot_part(0);
  else
    gp << "set format y '%g'\nset mytics 2\nset ylabel 'real part Re G (µm/N)'\n" << plot_part(2);
  gp << "\n# Lower panel\n"
     << "unset key\n"
     << "set tmargin at screen 0.465; set bmargin at screen 0.10\n"
     << "set format x '%g'\nset xlabel 'frequency (Hz)'\n";
  if (mag_phase)
    gp << "unset logscale y\nset format y '%g'\nset yrange [-180:0]\nset ytics 45\nset mytics 3\n"
       << "set ylabel 'phase (deg)'\n"
       << plot_part(1);
  else
    gp << "set format y '%g'\nset ylabel 'imaginary part Im G (µm/N)'\n" << plot_part(3);
  gp << "unset multiplot\n";
  write_and_render(t, dat.str(), gp.str());
  return {t.image, t.script, t.data};
}

// ---------------------------------------------------------------------------
// Floquet stability map

namespace {

// Contour colours and the colour scale of the map.
constexpr const char* kHopfLine = "#101010";
constexpr const char* kFlipLine = "#7b1fa2";
constexpr const char* kFoldLine = "#00796b";
constexpr const char* kStableKey = "#6fa3d2";   // a stable colour of the palette, for the key
constexpr const char* kChatterKey = "#f0804a";  // an unstable one

// Type code in the .dat files.
const char* type_word(MultiplierType t) {
  switch (t) {
    case MultiplierType::kHopf: return "hopf";
    case MultiplierType::kFlip: return "flip";
    case MultiplierType::kFold: return "fold";
  }
  return "hopf";
}

// One piece of the ρ = 1 contour: a polyline along which the dominant
// multiplier on the unstable side has one type (-1 = not known).
struct ContourPiece {
  std::vector<std::pair<double, double>> points;  // (rev/min, mm)
  int type = -1;
};

// The ρ = 1 contour of the grid by marching squares on ln ρ (linear
// interpolation along each cell edge; saddle cells resolved by the mean of
// the four corners), chained into polylines and split where the type of the
// dominant multiplier on the unstable side changes.
std::vector<ContourPiece> unit_contour(const StabilityMapGrid& m) {
  const std::size_t n = m.spindle_rpm.size(), k = m.depth_m.size();
  const bool typed = !m.multiplier_type.empty();
  auto at = [&](std::size_t i, std::size_t j) { return i * k + j; };
  auto f = [&](std::size_t p) { return std::log(std::max(m.spectral_radius[p], 1e-300)); };
  auto unstable = [&](std::size_t p) { return m.spectral_radius[p] >= 1.0; };

  // Edge ids: horizontal (i,j)-(i+1,j) first, then vertical (i,j)-(i,j+1).
  const std::size_t n_h = (n - 1) * k;
  auto h_edge = [&](std::size_t i, std::size_t j) { return i * k + j; };
  auto v_edge = [&](std::size_t i, std::size_t j) { return n_h + i * (k - 1) + j; };
  const std::size_t n_edges = n_h + n * (k - 1);
  // Crossing point of an edge (between grid points a and b, one unstable).
  auto crossing = [&](std::size_t a, std::size_t b) {
    const double fa = f(a), fb = f(b);
    const double t = std::clamp(fa / (fa - fb), 0.0, 1.0);
    const double xa = m.spindle_rpm[a / k], xb = m.spindle_rpm[b / k];
    const double ya = m.depth_m[a % k] * 1e3, yb = m.depth_m[b % k] * 1e3;
    return std::make_pair(xa + t * (xb - xa), ya + t * (yb - ya));
  };

  struct Segment {
    std::size_t e0, e1;
    int type;
  };
  std::vector<Segment> segs;
  std::vector<std::pair<double, double>> point(n_edges);
  std::vector<std::array<int, 2>> at_edge(n_edges, {-1, -1});
  auto add_segment = [&](std::size_t e0, std::size_t e1, int type) {
    const int id = static_cast<int>(segs.size());
    segs.push_back({e0, e1, type});
    for (std::size_t e : {e0, e1}) (at_edge[e][0] < 0 ? at_edge[e][0] : at_edge[e][1]) = id;
  };
  for (std::size_t i = 0; i + 1 < n; ++i)
    for (std::size_t j = 0; j + 1 < k; ++j) {
      const std::size_t c[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      // Edge q joins corners q and q+1 (mod 4).
      const std::size_t e[4] = {h_edge(i, j), v_edge(i + 1, j), h_edge(i, j + 1), v_edge(i, j)};
      bool u[4];
      for (int q = 0; q < 4; ++q) u[q] = unstable(c[q]);
      int crossings = 0;
      for (int q = 0; q < 4; ++q)
        if (u[q] != u[(q + 1) % 4]) {
          point[e[q]] = crossing(c[q], c[(q + 1) % 4]);
          ++crossings;
        }
      if (crossings == 0) continue;
      // The type on the unstable side: that of the least unstable of the
      // given corners (the one nearest the crossing).
      auto type_of = [&](std::initializer_list<int> corners) {
        if (!typed) return -1;
        int best = -1;
        for (int q : corners)
          if (u[q] && (best < 0 || m.spectral_radius[c[q]] < m.spectral_radius[c[best]])) best = q;
        return best < 0 ? -1 : static_cast<int>(m.multiplier_type[c[best]]);
      };
      if (crossings == 2) {
        int a = -1, b = -1;
        for (int q = 0; q < 4; ++q)
          if (u[q] != u[(q + 1) % 4]) (a < 0 ? a : b) = q;
        add_segment(e[a], e[b], type_of({0, 1, 2, 3}));
      } else {  // saddle: the mean of the corners decides which pairs connect
        const double centre = (f(c[0]) + f(c[1]) + f(c[2]) + f(c[3])) / 4.0;
        const bool centre_unstable = centre >= 0.0;
        for (int q = 0; q < 4; ++q) {
          if (u[q] == centre_unstable) continue;  // cut off the corners unlike the centre
          const int prev = (q + 3) % 4, next = (q + 1) % 4;
          add_segment(e[prev], e[q], u[q] ? type_of({q}) : type_of({prev, next}));
        }
      }
    }

  // Chain the segments: open chains from their ends first, then loops.
  std::vector<char> used(segs.size(), 0);
  std::vector<ContourPiece> pieces;
  auto walk = [&](int s, std::size_t start_edge) {
    ContourPiece piece;
    piece.type = segs[static_cast<std::size_t>(s)].type;
    piece.points.push_back(point[start_edge]);
    std::size_t edge = start_edge;
    while (s >= 0 && !used[static_cast<std::size_t>(s)]) {
      const Segment& g = segs[static_cast<std::size_t>(s)];
      used[static_cast<std::size_t>(s)] = 1;
      if (g.type != piece.type) {  // a new piece from the shared point
        const auto last = piece.points.back();
        pieces.push_back(std::move(piece));
        piece = ContourPiece{{last}, g.type};
      }
      edge = g.e0 == edge ? g.e1 : g.e0;
      piece.points.push_back(point[edge]);
      const auto& both = at_edge[edge];
      s = both[0] == s ? both[1] : both[0];
    }
    pieces.push_back(std::move(piece));
  };
  for (std::size_t s = 0; s < segs.size(); ++s)
    for (std::size_t e : {segs[s].e0, segs[s].e1})
      if (!used[s] && at_edge[e][1] < 0) walk(static_cast<int>(s), e);
  for (std::size_t s = 0; s < segs.size(); ++s)
    if (!used[s]) walk(static_cast<int>(s), segs[s].e0);
  return pieces;
}

// Colour-box tics for the clip value R (a round list inside (1/R, R)).
std::vector<double> map_tics(double r) {
  if (r <= 1.5) return {0.8, 0.9, 1.0, 1.1, 1.25};
  if (r <= 2.0) return {0.7, 0.8, 1.0, 1.25, 1.5};
  if (r <= 3.0) return {0.5, 0.7, 1.0, 1.5, 2.0};
  if (r <= 5.0) return {0.3, 0.5, 1.0, 2.0, 3.0};
  return {0.2, 0.5, 1.0, 2.0, 5.0};
}

bool strictly_increasing(const std::vector<double>& v) {
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1])) return false;
  return true;
}

}  // namespace

namespace {

// What the map's x values are (map.spindle_rpm holds them): spindle speed
// for the speed x depth map, radial depth for the radial x axial one.
struct MapXAxis {
  std::string label = "spindle speed (rev/min)";  // axis title, with the unit
  std::string column = "spindle_rpm";             // .dat column name, with the unit
  std::string plural = "spindle speeds";          // in messages and the .dat header
  std::string y_label = "depth of cut (mm)";
  int digits = 10;                                 // of the range in the script
};

// `limit_depth_m` (empty, or one per x value: m, +inf = none) is drawn as
// points over the map: the depth limit searched at each x.
void draw_stability_map(const Target& t, const std::string& title, const StabilityMapGrid& map,
                        const PlotOptions& options, const MapXAxis& xaxis = {},
                        const std::vector<double>& limit_depth_m = {}) {
  const std::size_t n = map.spindle_rpm.size(), k = map.depth_m.size();
  const std::string where = t.label + ": stability map: ";
  if (n < 2 || k < 2)
    throw InputError(where + "needs >= 2 " + xaxis.plural + " and >= 2 depths (got " + std::to_string(n) + " x " +
                     std::to_string(k) + ")");
  for (double r : map.spindle_rpm)
    if (!(std::isfinite(r) && r > 0.0)) throw InputError(where + xaxis.plural + " must be finite and > 0");
  for (double d : map.depth_m)
    if (!(std::isfinite(d) && d >= 0.0)) throw InputError(where + "depths must be finite and >= 0");
  if (!strictly_increasing(map.spindle_rpm) || !strictly_increasing(map.depth_m))
    throw InputError(where + xaxis.plural + " and depths must be strictly increasing");
  if (!limit_depth_m.empty() && limit_depth_m.size() != n)
    throw InputError(where + std::to_string(limit_depth_m.size()) + " depth limits for " + std::to_string(n) + " " +
                     xaxis.plural);
  if (map.spectral_radius.size() != n * k)
    throw InputError(where + std::to_string(map.spectral_radius.size()) + " spectral radii for " +
                     std::to_string(n) + " x " + std::to_string(k) + " grid points");
  for (double r : map.spectral_radius)
    if (!(std::isfinite(r) && r >= 0.0)) throw InputError(where + "spectral radii must be finite and >= 0");
  const bool typed = !map.multiplier_type.empty();
  if (typed && map.multiplier_type.size() != n * k)
    throw InputError(where + std::to_string(map.multiplier_type.size()) + " multiplier types for " +
                     std::to_string(n * k) + " grid points");

  // Colour clip R: the smallest of a few round values covering 90 % of |ln ρ|.
  std::vector<double> spread;
  spread.reserve(n * k);
  for (double r : map.spectral_radius) spread.push_back(std::abs(std::log(std::max(r, 1e-300))));
  const auto q90 = spread.begin() + static_cast<std::ptrdiff_t>((spread.size() - 1) * 9 / 10);
  std::nth_element(spread.begin(), q90, spread.end());
  double rho_clip = 10.0;
  for (double r : {1.5, 2.0, 3.0, 5.0, 10.0})
    if (std::log(r) >= *q90) {
      rho_clip = r;
      break;
    }

  std::size_t unstable = 0;
  for (double r : map.spectral_radius) unstable += r >= 1.0;
  const std::vector<ContourPiece> contour = unit_contour(map);
  bool contour_type[4] = {false, false, false, false};  // hopf, flip, fold, unknown
  for (const auto& c : contour) contour_type[c.type < 0 ? 3 : c.type] = true;

  // --- data ---
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": Floquet spectral radius map (chatter " << version() << ")\n"
      << "# " << n << " " << xaxis.plural << " x " << k << " depths; rho < 1 stable, rho >= 1 chatter.\n"
      << "# Missing values are '?' (gnuplot: set datafile missing '?').\n\n"
      << "# index 0: the grid, one block per " << xaxis.column << " value (blocks separated by one blank line);\n"
      << "# 7 significant digits.\n"
      << "# multiplier_type: type of the dominant multiplier (hopf, flip, fold) where rho >= 1, else '?'.\n"
      << "# " << xaxis.column << " depth_mm spectral_radius multiplier_type\n";
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) dat << '\n';
    for (std::size_t j = 0; j < k; ++j) {
      const std::size_t p = i * k + j;
      const double r = map.spectral_radius[p];
      dat << num(map.spindle_rpm[i], 7) << ' ' << num(map.depth_m[j] * 1e3, 7) << ' ' << num(r, 7) << ' '
          << (typed && r >= 1.0 ? type_word(map.multiplier_type[p]) : "?") << '\n';
    }
  }
  dat << "\n\n# index 1: the rho = 1 contour (linear interpolation of ln rho along the grid edges), one block\n"
      << "# per piece; multiplier_type: the type on the unstable side (hopf, flip, fold; '?' if not given).\n"
      << "# " << xaxis.column << " depth_mm multiplier_type\n";
  for (std::size_t c = 0; c < contour.size(); ++c) {
    if (c > 0) dat << '\n';
    const char* word = contour[c].type < 0 ? "?" : type_word(static_cast<MultiplierType>(contour[c].type));
    for (const auto& [x, y] : contour[c].points) dat << num(x, 7) << ' ' << num(y, 7) << ' ' << word << '\n';
  }
  // Marks on the unstable points where flip or fold dominates, thinned to a
  // regular subset so that they read as a hatch.
  const std::size_t si = std::max<std::size_t>(1, (n + 39) / 40), sj = std::max<std::size_t>(1, (k + 24) / 25);
  dat << "\n\n# index 2: marks on unstable grid points where the dominant multiplier is flip or fold\n"
      << "# (every " << si << " speed(s) and " << sj << " depth(s))\n"
      << "# " << xaxis.column << " depth_mm multiplier_type\n";
  std::size_t marks[3] = {0, 0, 0};  // per type
  if (typed)
    for (std::size_t i = si / 2; i < n; i += si)
      for (std::size_t j = sj / 2; j < k; j += sj) {
        const std::size_t p = i * k + j;
        if (map.spectral_radius[p] < 1.0 || map.multiplier_type[p] == MultiplierType::kHopf) continue;
        dat << num(map.spindle_rpm[i]) << ' ' << num(map.depth_m[j] * 1e3) << ' '
            << type_word(map.multiplier_type[p]) << '\n';
        ++marks[static_cast<int>(map.multiplier_type[p])];
      }

  std::size_t limit_points = 0;
  if (!limit_depth_m.empty()) {
    dat << "\n\n# index 3: the depth limit searched at each " << xaxis.column
        << " (the limit search of the lobe table; none where no limit below the depths searched)\n"
        << "# " << xaxis.column << " depth_limit_mm\n";
    for (std::size_t i = 0; i < n; ++i)
      if (std::isfinite(limit_depth_m[i]) && limit_depth_m[i] * 1e3 <= map.depth_m.back() * 1e3) {
        dat << num(map.spindle_rpm[i], 7) << ' ' << num(limit_depth_m[i] * 1e3, 7) << '\n';
        ++limit_points;
      }
    if (limit_points == 0) dat << "? ?\n";  // gnuplot needs a block to read
  }

  // --- script ---
  std::ostringstream gp;
  gp << script_preamble(t, options, "Floquet stability map (spectral radius)")
     << "# Colour scale: spectral radius from 1/rho_clip to rho_clip on a log axis, centred on 1\n"
     << "# (values beyond are drawn in the end colours).\n"
     << "rho_clip = " << short_num(rho_clip) << "\n"
     << "clip(r) = r < 1.0/rho_clip ? 1.0/rho_clip : (r > rho_clip ? rho_clip : r)\n\n"
     << "# Colours: contour pieces by multiplier type, key swatches\n"
     << "c_hopf = " << quote(kHopfLine) << "; c_flip = " << quote(kFlipLine) << "; c_fold = " << quote(kFoldLine)
     << "\n"
     << "c_stable = " << quote(kStableKey) << "; c_chatter = " << quote(kChatterKey) << "\n"
     << "# Blues below rho = 1, oranges to reds above, with a step at 1.\n"
     << "set palette defined (0 '#0b3a6e', 0.25 '#3f7fbf', 0.5 '#bcd7ee', 0.5 '#fdc793', 0.75 '#ee7640', "
        "1 '#7a0c0c')\n\n"
     << "set multiplot title " << quote(title) << " noenhanced font ','.(fs+3)\n"
     << "set lmargin at screen 0.085; set rmargin at screen 0.855\n"
     << "set tmargin at screen 0.83; set bmargin at screen 0.11\n"
     << "set key at screen 0.47, screen 0.885 center center horizontal reverse Left samplen 2 width -1 "
        "font ','.(fs-1)\n"
     << "set border lw 1 lc rgb '#404040' front\n"
     << "set tics front\n"
     << "set mxtics 2; set mytics 2\n"
     << "set xrange [" << short_num(map.spindle_rpm.front(), xaxis.digits) << ":"
     << short_num(map.spindle_rpm.back(), xaxis.digits) << "]\n"
     << "set yrange [" << short_num(map.depth_m.front() * 1e3, 10) << ":" << short_num(map.depth_m.back() * 1e3, 10)
     << "]\n"
     << "set xlabel " << quote(xaxis.label) << "\n"
     << "set ylabel " << quote(xaxis.y_label) << "\n"
     << "set logscale cb\n"
     << "set cbrange [1.0/rho_clip:rho_clip]\n"
     << "set colorbox user origin screen 0.875, screen 0.11 size screen 0.022, screen 0.72 front border\n"
     << "set cblabel 'spectral radius ρ' offset 0.5,0\n"
     << "set cbtics (";
  gp << "sprintf('≤ %g', 1.0/rho_clip) 1.0/rho_clip";
  for (double v : map_tics(rho_clip)) gp << ", '" << short_num(v) << "' " << short_num(v);
  gp << ", sprintf('≥ %g', rho_clip) rho_clip) out nomirror\n"
     << "set mcbtics 1\n";
  if (contour.empty())
    gp << "set label 3 " << quote(unstable == 0 ? "ρ < 1 on the whole grid: stable everywhere"
                                                : "ρ ≥ 1 on the whole grid: chatter everywhere")
       << " at graph 0.5, graph 0.5 center front\n";
  gp << "plot \\\n"
     << "  data index 0 using 1:2:(clip($3)) with image notitle, \\\n"
     << "  keyentry with boxes fs solid 1.0 noborder fc rgb c_stable title 'stable (ρ < 1)', \\\n"
     << "  keyentry with boxes fs solid 1.0 noborder fc rgb c_chatter title 'chatter (ρ > 1)'";
  // Each contour piece: a white casing under the coloured line, so that it
  // reads on every colour of the map.
  struct Kind {
    int index;
    const char* word;
    const char* colour;
    const char* dash;
    const char* line_title;
    const char* mark_title;
    int point_type;
  };
  const Kind kinds[3] = {
      {0, "hopf", "c_hopf", "", "ρ = 1, Hopf (complex μ)", "", 0},
      {1, "flip", "c_flip", " dt (5,3)", "ρ = 1, flip (μ = −1)", "flip dominates (μ ≈ −1)", 2},
      {2, "fold", "c_fold", " dt (2,2)", "ρ = 1, fold (μ = +1)", "fold dominates (μ ≈ +1)", 6},
  };
  auto contour_clause = [&](const std::string& filter, const std::string& colour, const std::string& dash,
                            const std::string& line_title) {
    gp << ", \\\n  data index 1 using 1:" << filter << " with lines lw 5.5 lc rgb '#50ffffff' notitle"
       << ", \\\n  data index 1 using 1:" << filter << " with lines lw 2.6" << dash << " lc rgb " << colour
       << " title " << quote(line_title);
  };
  if (contour_type[3]) contour_clause("2", "c_hopf", "", "ρ = 1 (stability boundary)");
  for (const Kind& kd : kinds)
    if (contour_type[kd.index])
      contour_clause("(strcol(3) eq '" + std::string(kd.word) + "' ? $2 : NaN)", kd.colour, kd.dash, kd.line_title);
  for (const Kind& kd : kinds)
    if (kd.index > 0 && marks[kd.index] > 0)
      gp << ", \\\n  data index 2 using 1:(strcol(3) eq '" << kd.word << "' ? $2 : NaN) with points pt "
         << kd.point_type << " ps 0.7 lw 1.5 lc rgb " << kd.colour << " title " << quote(kd.mark_title);
  if (limit_points > 0)
    gp << ", \\\n  data index 3 using 1:2 with points pt 7 ps 0.9 lc rgb '#ffffff' notitle"
       << ", \\\n  data index 3 using 1:2 with points pt 7 ps 0.55 lc rgb '#000000' title "
       << quote("limit search");
  gp << "\nunset multiplot\n";
  write_and_render(t, dat.str(), gp.str());
}

}  // namespace

PlotFiles plot_stability_map(const fs::path& image, const std::string& title, const StabilityMapGrid& map,
                             const PlotOptions& options) {
  const Target t = make_target(image, options);
  draw_stability_map(t, title, map, options);
  return {t.image, t.script, t.data};
}

void plot_stability_map(PlotWindow& window, const std::string& title, const StabilityMapGrid& map,
                        const PlotOptions& options) {
  draw_stability_map(live_target(window, options), title, map, options);
}

namespace {

// The radial map as a StabilityMapGrid whose x values are a_e in mm (or
// a_e/D without a diameter), and the axis that says so.
std::pair<StabilityMapGrid, MapXAxis> radial_view(const RadialStabilityMapGrid& r) {
  StabilityMapGrid g;
  const bool mm = r.tool_diameter_m > 0.0;
  for (double e : r.radial_immersion) g.spindle_rpm.push_back(mm ? e * r.tool_diameter_m * 1e3 : e);
  g.depth_m = r.depth_m;
  g.spectral_radius = r.spectral_radius;
  g.multiplier_type = r.multiplier_type;
  MapXAxis x;
  x.label = mm ? "radial depth of cut a_e (mm)" : "radial immersion a_e/D (-)";
  x.column = mm ? "radial_depth_mm" : "radial_immersion";
  x.plural = mm ? "radial depths" : "radial immersions";
  x.digits = 6;
  x.y_label = "axial depth of cut a_p (mm)";
  return {g, x};
}

std::vector<double> radial_limits(const RadialStabilityMapGrid& r) {
  std::vector<double> v;
  for (const StabilityLimit& l : r.limit) v.push_back(l.depth_limit_m);
  return v;
}

}  // namespace

PlotFiles plot_radial_stability_map(const fs::path& image, const std::string& title, const RadialStabilityMapGrid& map,
                                    const PlotOptions& options) {
  const Target t = make_target(image, options);
  const auto [grid, x] = radial_view(map);
  draw_stability_map(t, title, grid, options, x, radial_limits(map));
  return {t.image, t.script, t.data};
}

void plot_radial_stability_map(PlotWindow& window, const std::string& title, const RadialStabilityMapGrid& map,
                               const PlotOptions& options) {
  const auto [grid, x] = radial_view(map);
  draw_stability_map(live_target(window, options), title, grid, options, x, radial_limits(map));
}

// ---------------------------------------------------------------------------
// Method comparison

namespace {

// One style per method: every registered method has its own (solver registry,
// PlotStyle: a method looks the same on every chart), other names take the
// next unused one of kMethodStyles. The lines are drawn widest first, so that methods that agree
// (analytic and coupled to round-off, sdm in turning) all stay visible: a wide
// light band, a medium line on it, a thin dashed line on top. time-domain is
// drawn as open circles, one per simulated speed, on top of everything (the
// flip marks included): it lies on sdm's line where they agree, and a line on
// a line would hide one of them.
struct MethodStyle {
  const char* colour;
  double width;
  const char* dash;  // "" = solid
  int point_type;    // 0 = a line; else gnuplot's point type, drawn as points
};
// The styles of unregistered names, after those of the registry.
constexpr MethodStyle kExtraStyles[] = {
    {"#7570b3", 2.2, " dt (10,4,2,4)", 0}, {"#e7298a", 2.0, "", 0},
    {"#66a61e", 1.8, " dt (6,3,2,3)", 0}, {"#7a5a1d", 1.4, " dt (3,3)", 0},
};
// The registry's styles, in registry order, then kExtraStyles.
const std::vector<MethodStyle>& method_styles() {
  static const std::vector<MethodStyle> styles = [] {
    std::vector<MethodStyle> s;
    for (const auto& d : solver_registry()) s.push_back({d.plot.colour, d.plot.width, d.plot.dash, d.plot.point_type});
    for (const auto& e : kExtraStyles) s.push_back(e);
    return s;
  }();
  return styles;
}

// A method name as a column name: anything but letters, digits and _ becomes _.
std::string column_word(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  return out;
}

}  // namespace

namespace {

// Refuses an empty, inconsistent or too long list of methods. @throws InputError.
void check_compare_input(const std::string& where, const std::vector<MethodLimits>& methods, double depth_max_m,
                         std::size_t kMaxMethods) {
  if (methods.empty() || methods.size() > kMaxMethods)
    throw InputError(where + std::to_string(methods.size()) + " methods: must be 1 to " +
                     std::to_string(kMaxMethods));
  if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    throw InputError(where + "depth_max = " + short_num(depth_max_m) + " m: must be > 0");
  const std::size_t rows = methods.front().limits.size();
  if (rows == 0) throw InputError(where + "no speeds to plot");
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const MethodLimits& ml = methods[m];
    if (ml.method.empty()) throw InputError(where + "method " + std::to_string(m + 1) + " has no name");
    for (std::size_t o = 0; o < m; ++o)
      if (methods[o].method == ml.method) throw InputError(where + "method '" + ml.method + "' given twice");
    if (ml.limits.size() != rows)
      throw InputError(where + "method '" + ml.method + "' has " + std::to_string(ml.limits.size()) +
                       " speeds, '" + methods.front().method + "' has " + std::to_string(rows));
    if (!ml.multiplier_type.empty() && ml.multiplier_type.size() != rows)
      throw InputError(where + "method '" + ml.method + "': " + std::to_string(ml.multiplier_type.size()) +
                       " multiplier types for " + std::to_string(rows) + " speeds");
    for (std::size_t i = 0; i < rows; ++i) {
      const double a = methods.front().limits[i].spindle_rpm, b = ml.limits[i].spindle_rpm;
      if (!(std::isfinite(b) && b > 0.0)) throw InputError(where + "spindle speeds must be finite and > 0");
      if (std::abs(a - b) > 1e-9 * std::abs(a))
        throw InputError(where + "method '" + ml.method + "' row " + std::to_string(i + 1) + " is at " +
                         short_num(b, 10) + " rev/min, '" + methods.front().method + "' at " + short_num(a, 10));
    }
  }
}

// The style (index into method_styles()) of each method: registered methods
// keep theirs, the others take the next unused.
std::vector<std::size_t> compare_styles(const std::vector<MethodLimits>& methods) {
  const std::size_t kMaxMethods = method_styles().size();
  std::vector<std::size_t> style_of(methods.size(), kMaxMethods);
  std::vector<bool> taken(kMaxMethods, false);
  const auto& registry = solver_registry();
  for (std::size_t m = 0; m < methods.size(); ++m)
    for (std::size_t k = 0; k < registry.size(); ++k)
      if (methods[m].method == registry[k].name) {
        style_of[m] = k;
        taken[k] = true;
      }
  for (std::size_t m = 0; m < methods.size(); ++m)
    if (style_of[m] == kMaxMethods) {
      std::size_t k = 0;
      while (taken[k]) ++k;  // methods.size() <= kMaxMethods: there is one
      style_of[m] = k;
      taken[k] = true;
    }
  return style_of;
}

// Top of the depth axis (mm): every bounded limit of every method visible
// with a margin (as lobes_y_max), at least 3 × the smallest one.
double compare_y_max(const std::vector<double>& bounded, double depth_max_mm) {
  double y_max = depth_max_mm;
  if (!bounded.empty()) {
    const double lowest = *std::min_element(bounded.begin(), bounded.end());
    const double highest = *std::max_element(bounded.begin(), bounded.end());
    y_max = std::min(depth_max_mm, nice_ceil(std::max(kDepthAxisMargin * highest, 3.0 * lowest)));
  }
  return y_max;
}

// The .dat of plot_compare: limits per speed (index 0), flip/fold runs (1).
// marks[m][type] counts the rows of method m marked with that type.
std::string compare_data(const std::string& title, const std::vector<MethodLimits>& methods, double depth_max_mm,
                         std::vector<std::array<std::size_t, 3>>& marks) {
  const std::size_t rows = methods.front().limits.size();
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": depth limit by method (chatter " << version() << ")\n"
      << "# depth_max_mm = " << num(depth_max_mm) << " (deepest cut searched)\n"
      << "# methods:";
  for (std::size_t m = 0; m < methods.size(); ++m) dat << ' ' << m << '=' << one_line(methods[m].method);
  dat << "\n# Missing values are '?' (gnuplot: set datafile missing '?').\n\n"
      << "# index 0: one row per spindle speed; per method the depth limit (mm; '?' where there is no\n"
      << "# limit below depth_max_mm) and bounded (1 = a limit, 0 = none).\n"
      << "# spindle_rpm";
  for (const auto& ml : methods) {
    const std::string w = column_word(ml.method);
    dat << " depth_limit_mm_" << w << " bounded_" << w;
  }
  dat << '\n';
  for (std::size_t i = 0; i < rows; ++i) {
    dat << num(methods.front().limits[i].spindle_rpm);
    for (const auto& ml : methods) {
      const auto& r = ml.limits[i];
      dat << ' ' << (r.bounded() ? num(r.depth_limit_m * 1e3) : "?") << ' ' << (r.bounded() ? 1 : 0);
    }
    dat << '\n';
  }
  // Runs of consecutive speeds where a method's limit is set by a flip or a
  // fold multiplier: one block each, drawn over that method's line.
  dat << "\n\n# index 1: speeds where a method's limit is set by a flip (period doubling) or fold\n"
      << "# multiplier (methods that report the multiplier type, e.g. sdm); one block per run of\n"
      << "# consecutive speeds (blocks separated by one blank line); method = its number above\n"
      << "# spindle_rpm depth_limit_mm method multiplier_type\n";
  marks.assign(methods.size(), {0, 0, 0});
  bool first_run = true;
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const MethodLimits& ml = methods[m];
    if (ml.multiplier_type.empty()) continue;
    int run_type = -1;  // type of the open run, -1 if none
    for (std::size_t i = 0; i < rows; ++i) {
      const auto& r = ml.limits[i];
      const int ty = r.bounded() ? static_cast<int>(ml.multiplier_type[i]) : -1;
      if (ty <= 0) {  // Hopf or no limit: the run ends
        run_type = -1;
        continue;
      }
      if (ty != run_type) {
        if (!first_run) dat << '\n';
        first_run = false;
        run_type = ty;
      }
      dat << num(r.spindle_rpm) << ' ' << num(r.depth_limit_m * 1e3) << ' ' << m << ' '
          << type_word(ml.multiplier_type[i]) << '\n';
      ++marks[m][static_cast<std::size_t>(ty)];
    }
  }
  return dat.str();
}

// The variables, colours and axes of the plot_compare script, up to "plot".
std::string compare_script_head(const Target& t, const PlotOptions& options, const std::string& title,
                                const std::vector<MethodLimits>& methods, const std::vector<std::size_t>& style_of,
                                double rpm_lo, double rpm_hi, double y_max, double depth_max_mm, bool any_bounded) {
  const std::vector<MethodStyle>& kMethodStyles = method_styles();
  std::ostringstream gp;
  gp << script_preamble(t, options, "Depth limit by method (chatter compare)")
     << "# Values from the engine (mm, rev/min)\n"
     << "y_max = " << short_num(y_max, 6) << "          # top of the depth axis\n"
     << "depth_max = " << short_num(depth_max_mm, 6) << "      # deepest cut searched\n"
     << "# Columns of method m (0 = first): depth limit and bounded flag\n"
     << "col_depth(m) = 2 + 2*m\n"
     << "col_bounded(m) = 3 + 2*m\n"
     << "# A gap where a method has no limit (a NaN breaks the line; a '?' row would be joined across).\n"
     << "limit(m) = column(col_bounded(m)) > 0 ? column(col_depth(m)) : NaN\n\n"
     << "# Colours, one per method\n";
  for (std::size_t m = 0; m < methods.size(); ++m)
    gp << "c_m" << m << " = " << quote(kMethodStyles[style_of[m]].colour) << "   # " << one_line(methods[m].method)
       << "\n";
  gp << "c_flip = " << quote(kFlipLine) << "; c_fold = " << quote(kFoldLine)
     << "   # where a limit is set by a flip / fold multiplier\n"
     << "\nset multiplot title " << quote(title) << " noenhanced font ','.(fs+3)\n"
     << "set lmargin at screen 0.085; set rmargin at screen 0.975\n"
     << "set tmargin at screen 0.85; set bmargin at screen 0.11\n"
     << "set key at screen 0.53, screen 0.895 center center horizontal reverse Left samplen 3 width 1 "
        "font ','.(fs-1)\n"
     << "set border lw 1 lc rgb '#404040'\n"
     << "set grid xtics ytics mxtics mytics back lw 1 lc rgb " << quote(kGrid) << ", lw 0.5 lc rgb '#e4e4e4'\n"
     << "set mxtics 2; set mytics 2\n"
     << "set xrange [" << short_num(rpm_lo, 10) << ":" << short_num(rpm_hi, 10) << "]\n"
     << "set yrange [0:y_max]\n"
     << "set xlabel 'spindle speed (rev/min)'\n"
     << "set ylabel 'depth limit (mm)'\n";
  if (!any_bounded)
    gp << "set label 3 sprintf('no method finds chatter below %g mm at any speed in the sweep', depth_max) "
          "at graph 0.5, graph 0.5 center front\n";
  return gp.str();
}

// The plot command of plot_compare: the lines widest first, the key, the
// flip/fold marks, then the methods drawn as points on top.
std::string compare_plot_clauses(const std::vector<MethodLimits>& methods, const std::vector<std::size_t>& style_of,
                                 const std::vector<std::array<std::size_t, 3>>& marks, bool gaps, bool any_bounded) {
  const std::vector<MethodStyle>& kMethodStyles = method_styles();
  const std::size_t rows = methods.front().limits.size();
  std::ostringstream gp;
  gp << "plot";
  bool first = true;
  auto add = [&](const std::string& clause) {
    gp << (first ? " \\\n  " : ", \\\n  ") << clause;
    first = false;
  };
  // Lines widest first (untitled), then the key in the methods' order.
  std::vector<std::size_t> order(methods.size());
  for (std::size_t m = 0; m < order.size(); ++m) order[m] = m;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return kMethodStyles[style_of[a]].width > kMethodStyles[style_of[b]].width;
  });
  auto style = [&](std::size_t m) {
    const MethodStyle& st = kMethodStyles[style_of[m]];
    if (st.point_type != 0)
      return "points pt " + std::to_string(st.point_type) + " ps 1.1 lw " + short_num(st.width) + " lc rgb c_m" +
             std::to_string(m);
    return "lines lw " + short_num(st.width) + st.dash + " lc rgb c_m" + std::to_string(m);
  };
  auto drawn_as_points = [&](std::size_t m) { return kMethodStyles[style_of[m]].point_type != 0; };
  // Points: at most about 100 per method, or they merge into a thick line.
  const std::size_t point_every = std::max<std::size_t>(1, (rows + 99) / 100);
  auto draw = [&](std::size_t m) {
    add("data index 0" + (drawn_as_points(m) ? " every " + std::to_string(point_every) : std::string()) +
        " using 1:(limit(" + std::to_string(m) + ")) with " + style(m) + " notitle");
  };
  for (std::size_t m : order)
    if (!drawn_as_points(m)) draw(m);
  for (std::size_t m = 0; m < methods.size(); ++m)
    add("keyentry with " + style(m) + " title " + quote(methods[m].method));
  for (std::size_t m = 0; m < methods.size(); ++m)
    for (int ty : {1, 2})
      if (marks[m][static_cast<std::size_t>(ty)] > 0) {
        const std::string word = type_word(static_cast<MultiplierType>(ty));
        add("data index 1 using 1:($3 == " + std::to_string(m) + " && strcol(4) eq '" + word +
            "' ? $2 : NaN) with linespoints lw 3.5 pt 7 ps 0.6 pi 4 lc rgb " + (ty == 1 ? "c_flip" : "c_fold") +
            " title " + quote(methods[m].method + (ty == 1 ? ": flip (period doubling)" : ": fold")));
      }
  for (std::size_t m : order)
    if (drawn_as_points(m)) draw(m);
  if (gaps && any_bounded)
    add("keyentry with lines lt nodraw title sprintf('gap: no limit below %g mm', depth_max)");
  return gp.str();
}

}  // namespace

namespace {

void draw_compare(const Target& t, const std::string& title, const std::vector<MethodLimits>& methods,
                  double depth_max_m, const PlotOptions& options) {
  check_compare_input(t.label + ": comparison: ", methods, depth_max_m, method_styles().size());
  const std::vector<std::size_t> style_of = compare_styles(methods);
  const double depth_max_mm = depth_max_m * 1e3;
  const auto [rpm_lo, rpm_hi] = speed_axis(methods.front().limits);
  std::vector<double> bounded;
  bool gaps = false;
  for (const auto& ml : methods)
    for (const auto& r : ml.limits) {
      if (r.bounded()) bounded.push_back(std::min(r.depth_limit_m * 1e3, depth_max_mm));
      else gaps = true;
    }
  const double y_max = options.depth_axis_max_mm > 0.0 ? options.depth_axis_max_mm : compare_y_max(bounded, depth_max_mm);
  std::vector<std::array<std::size_t, 3>> marks;
  const std::string dat = compare_data(title, methods, depth_max_mm, marks);
  const std::string gp =
      compare_script_head(t, options, title, methods, style_of, rpm_lo, rpm_hi, y_max, depth_max_mm,
                          !bounded.empty()) +
      compare_plot_clauses(methods, style_of, marks, gaps, !bounded.empty()) + "\nunset multiplot\n";
  write_and_render(t, dat, gp);
}

}  // namespace

PlotFiles plot_compare(const fs::path& image, const std::string& title, const std::vector<MethodLimits>& methods,
                       double depth_max_m, const PlotOptions& options) {
  const Target t = make_target(image, options);
  draw_compare(t, title, methods, depth_max_m, options);
  return {t.image, t.script, t.data};
}

void plot_compare(PlotWindow& window, const std::string& title, const std::vector<MethodLimits>& methods,
                  double depth_max_m, const PlotOptions& options) {
  draw_compare(live_target(window, options), title, methods, depth_max_m, options);
}

namespace {

void draw_simulation(const Target& t, const std::string& title, const SimulationResult& r, double f_max_hz,
                     const PlotOptions& options, bool running) {
  const std::string where = t.label + ": simulation: ";
  if (r.series.size() < 2)
    throw InputError(where + "no time series to draw (simulate with record_series)");
  if (!(std::isfinite(f_max_hz) && f_max_hz > 0.0))
    throw InputError(where + "highest natural frequency " + short_num(f_max_hz) + " Hz: must be > 0");

  bool moves_y = false;
  double peak_x = 0.0, peak_y = 0.0;
  for (const SeriesSample& s : r.series) {
    peak_x = std::max(peak_x, std::abs(s.rel_x_m));
    peak_y = std::max(peak_y, std::abs(s.rel_y_m));
  }
  moves_y = peak_y > 1e-3 * peak_x && peak_y > 0.0;
  bool force_y = false;
  {
    double fx = 0.0, fy = 0.0;
    for (const SeriesSample& s : r.series) {
      fx = std::max(fx, std::abs(s.force_x_n));
      fy = std::max(fy, std::abs(s.force_y_n));
    }
    force_y = fy > 1e-3 * fx && fy > 0.0;
  }
  const double f_hi = std::min(r.spectrum_hz.empty() ? 2.5 * f_max_hz : r.spectrum_hz.back(), 2.5 * f_max_hz);
  double amp_max = 0.0;
  for (std::size_t k = 1; k < r.spectrum_hz.size() && r.spectrum_hz[k] <= f_hi; ++k)
    amp_max = std::max(amp_max, r.spectrum_amplitude_m[k]);
  const double amp_floor = amp_max > 0.0 ? amp_max * 1e-7 : 1e-12;

  // --- data ---
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": time-domain simulation (chatter " << version() << ")\n"
      << "# verdict: " << to_string(r.verdict) << " (" << one_line(r.verdict_measure) << ")\n"
      << "# Floquet period = " << num(r.floquet_period_s) << " s, tooth passing = " << num(r.tooth_passing_hz) << " Hz, periods = "
      << r.periods << ", analysed from period " << r.analysed_from_period << "\n"
      << "# Missing values are '?'.\n\n"
      << "# index 0: time series\n"
      << "# time_ms rel_x_um rel_y_um force_x_n force_y_n chip_um in_cut\n";
  for (const SeriesSample& s : r.series)
    dat << num(s.t_s * 1e3) << ' ' << num(s.rel_x_m * 1e6) << ' ' << num(s.rel_y_m * 1e6) << ' ' << num(s.force_x_n)
        << ' ' << num(s.force_y_n) << ' ' << num(s.chip_m * 1e6) << ' ' << (s.in_cut ? 1 : 0) << '\n';
  dat << "\n\n# index 1: once-per-period samples (t = k tau)\n# time_ms rel_x_um rel_y_um\n";
  for (const SeriesSample& s : r.once_per_period)
    dat << num(s.t_s * 1e3) << ' ' << num(s.rel_x_m * 1e6) << ' ' << num(s.rel_y_m * 1e6) << '\n';
  dat << "\n\n# index 2: amplitude spectrum of the relative displacement over the analysed window\n"
      << "# frequency_hz amplitude_um (floored at 1e-7 of the peak for the log axis)\n";
  for (std::size_t k = 0; k < r.spectrum_hz.size() && r.spectrum_hz[k] <= f_hi; ++k)
    dat << num(r.spectrum_hz[k]) << ' ' << num(std::max(r.spectrum_amplitude_m[k], amp_floor) * 1e6) << '\n';
  if (r.spectrum_hz.empty()) dat << "? ?\n";
  dat << "\n\n# index 3: tooth-passing harmonics\n# frequency_hz amplitude_um harmonic\n";
  int harmonics = 0;
  for (const SpectralPeak& h : r.harmonics)
    if (h.frequency_hz <= f_hi) {
      dat << num(h.frequency_hz) << ' ' << num(std::max(h.amplitude_m, amp_floor) * 1e6) << ' ' << h.harmonic << '\n';
      ++harmonics;
    }
  if (harmonics == 0) dat << "? ? ?\n";

  // --- script ---
  std::ostringstream gp;
  gp << script_preamble(t, options, "Time-domain simulation");
  const bool chatter = r.verdict == SimulationVerdict::kChatter;
  std::string head = title + ": " + to_string(r.verdict);
  if (chatter && std::isfinite(r.chatter_frequency_hz)) head += " at " + short_num(r.chatter_frequency_hz, 4) + " Hz";
  if (std::isfinite(r.growth_per_period)) head += ", |{/Symbol m}| = " + short_num(r.growth_per_period, 4);
  // A run still integrating has no verdict yet: its periods so far.
  if (running)
    head = title + ": integrating, " + std::to_string(r.once_per_period.size() - 1) + " of " +
           std::to_string(r.periods) + " periods";
  gp << "c_x = '" << kTool << "'\nc_y = '" << kWorkpiece << "'\nc_sample = '" << kAbsolute << "'\nc_spec = '"
     << kRelative << "'\nc_grid = '" << kGrid << "'\nc_label = '" << kLabel << "'\n"
     << "set grid lc rgb c_grid lw 0.6\n"
     << "set border lw 0.8\n"
     << "set key top left horizontal opaque box lc rgb c_grid font ','.(fs-2)\n"
     << "set multiplot layout " << (running ? 2 : 3) << ",1 title " << quote(head)
     << " font ','.(fs+2) margins 0.09,0.97,0.07,0.91 spacing 0,0.09\n"
     << "set offsets 0, 0, graph 0.28, graph 0.04   # room for the key above the curves\n"
     // A run still integrating is drawn on the time axis of the whole run: it grows across the window.
     << "set xrange [0:"
     << short_num((running ? r.periods * r.floquet_period_s : r.series.back().t_s) * 1e3, 8) << "]\n"
     << "set xlabel 'time (ms)' offset 0,0.4\n"
     << "set ylabel 'relative displacement ({/Symbol m}m)'\n"
     << "plot data index 0 using 1:2 with lines lc rgb c_x lw 1 title 'x (feed direction)'";
  if (moves_y) gp << ", \\\n     data index 0 using 1:3 with lines lc rgb c_y lw 1 title 'y'";
  gp << ", \\\n     data index 1 using 1:2 with points pt 7 ps 0.45 lc rgb c_sample title 'x once per "
     << (r.tooth_passing_hz > 0 && r.periods > 0 ? "period" : "period") << "'\n"
     << "set ylabel 'force on the tool (N)'\n"
     << "plot ";
  if (force_y) gp << "data index 0 using 1:5 with lines lc rgb c_y lw 1 title 'F_y', \\\n     ";
  gp << "data index 0 using 1:4 with lines lc rgb c_x lw 1 title 'F_x'\n";
  if (running) {  // no spectrum before the run ends
    gp << "unset multiplot\n";
    write_and_render(t, dat.str(), gp.str());
    return;
  }
  gp << "set offsets 0, 0, 0, 0\n"
     << "set xlabel 'frequency (Hz)' offset 0,0.4\n"
     << "set ylabel 'amplitude ({/Symbol m}m)'\n"
     << "set logscale y\nset format y '10^{%L}'\n"
     << "set key top right vertical\n"
     << "set xrange [0:" << short_num(f_hi, 6) << "]\n"
     << "set yrange [" << short_num(amp_floor * 1e6 * 10, 4) << ":" << short_num(std::max(amp_max, 1e-300) * 1e6 * 300, 4)
     << "]   # headroom for the key\n";
  int arrows = 0;
  for (const SpectralPeak& h : r.harmonics)
    if (h.frequency_hz <= f_hi && arrows < 40) {
      gp << "set arrow from " << short_num(h.frequency_hz, 8) << ", graph 0 to " << short_num(h.frequency_hz, 8)
         << ", graph 1 nohead dt 3 lw 0.8 lc rgb c_grid\n";
      ++arrows;
    }
  if (std::isfinite(r.dominant_nonharmonic_hz) && r.dominant_nonharmonic_hz <= f_hi) {
    const std::string what = chatter ? "chatter " : "least damped ";
    gp << "set label " << quote(what + short_num(r.dominant_nonharmonic_hz, 4) + " Hz") << " at "
       << short_num(r.dominant_nonharmonic_hz, 8) << ", graph 0.62 left offset 0.6,0 tc rgb c_sample font ','.(fs-1)\n"
       << "set arrow from " << short_num(r.dominant_nonharmonic_hz, 8) << ", graph 0 to "
       << short_num(r.dominant_nonharmonic_hz, 8) << ", graph 1 nohead lw 1.2 lc rgb c_sample\n";
  }
  const int analysed = r.periods - r.analysed_from_period;
  gp << "plot data index 2 using 1:2 with lines lc rgb c_spec lw 1 title "
     << quote("relative displacement, last " + std::to_string(analysed) + " periods") << ", \\\n"
     << "     data index 3 using 1:2 with points pt 6 ps 1.1 lw 1.2 lc rgb c_x title "
     << quote("harmonics of 1/{/Symbol t} = " + short_num(1.0 / r.floquet_period_s, 5) + " Hz (" + (std::abs(r.floquet_period_s * r.tooth_passing_hz - 1.0) < 1e-9 ? "tooth passing" : "Floquet period") + ")") << "\n"
     << "unset multiplot\n";

  write_and_render(t, dat.str(), gp.str());
}

}  // namespace

PlotFiles plot_simulation(const fs::path& image, const std::string& title, const SimulationResult& result,
                          double f_max_hz, const PlotOptions& options) {
  const Target t = make_target(image, options);
  draw_simulation(t, title, result, f_max_hz, options, false);
  return {t.image, t.script, t.data};
}

void plot_simulation(PlotWindow& window, const std::string& title, const SimulationResult& result, double f_max_hz,
                     bool running, const PlotOptions& options) {
  draw_simulation(live_target(window, options), title, result, f_max_hz, options, running);
}

}  // namespace chatter
