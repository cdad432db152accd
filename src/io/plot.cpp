// Plots through gnuplot (see include/chatter/io/plot.hpp and docs/plots.md).
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
#include <numbers>
#include <sstream>
#include <system_error>

#include "chatter/io/table_writer.hpp"

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
  return t;
}

// Terminal, output and common settings at the top of every script.
std::string script_preamble(const Target& t, const PlotOptions& o, const std::string& what) {
  std::ostringstream gp;
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
  write_text_file(t.data, data);
  write_text_file(t.script, script);
  std::error_code ec;
  fs::remove(t.image, ec);  // no stale image survives a failed run
  run_gnuplot(t.script);
  if (!fs::is_regular_file(t.image, ec) || fs::file_size(t.image, ec) == 0)
    throw PlotError("gnuplot ran on " + t.script.string() + " but wrote no image " + t.image.string());
}

}  // namespace

std::string PlotOptions::validate() const {
  if (width_px < 200 || width_px > 10000) return "width_px must be in [200, 10000]";
  if (height_px < 150 || height_px > 10000) return "height_px must be in [150, 10000]";
  if (font_size < 4 || font_size > 72) return "font_size must be in [4, 72]";
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

PlotFiles plot_lobes(const fs::path& image, const std::string& title, const std::vector<StabilityLimit>& envelope,
                     const std::vector<LobeCurve>& curves, const AbsoluteLimit& absolute_limit, double depth_max_m,
                     const PlotOptions& options) {
  const Target t = make_target(image, options);
  if (envelope.empty()) throw InputError(image.string() + ": no lobe envelope rows to plot");
  if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    throw InputError(image.string() + ": depth_max = " + short_num(depth_max_m) + " m: must be > 0");

  const double depth_max_mm = depth_max_m * 1e3;
  double rpm_lo = envelope.front().spindle_rpm, rpm_hi = envelope.front().spindle_rpm;
  for (const auto& r : envelope) {
    rpm_lo = std::min(rpm_lo, r.spindle_rpm);
    rpm_hi = std::max(rpm_hi, r.spindle_rpm);
  }
  if (!(rpm_hi > rpm_lo)) {  // one speed: show ±5 % around it
    rpm_lo *= 0.95;
    rpm_hi *= 1.05;
  }

  // y range: enough to show the pockets between lobes, not dominated by the
  // narrow peaks (which reach depth_max).
  std::vector<double> bounded;
  for (const auto& r : envelope)
    if (r.bounded()) bounded.push_back(std::min(r.depth_limit_m * 1e3, depth_max_mm));
  const bool has_abs = std::isfinite(absolute_limit.depth_m) && absolute_limit.depth_m > 0.0;
  const double abs_mm = has_abs ? absolute_limit.depth_m * 1e3 : 0.0;
  double y_max = depth_max_mm;
  if (!bounded.empty()) {
    std::nth_element(bounded.begin(), bounded.begin() + static_cast<std::ptrdiff_t>(bounded.size() / 2),
                     bounded.end());
    const double median = bounded[bounded.size() / 2];
    const double lowest = *std::min_element(bounded.begin(), bounded.end());
    const double want = std::max({4.0 * (has_abs ? abs_mm : lowest), 1.5 * median, 1.2 * lowest});
    y_max = std::min(depth_max_mm, nice_ceil(want));
  }

  // Lobe-number labels: each piece's minimum, if it is a true minimum (not an
  // end point cut by the speed range) inside the plot, thinned so that labels
  // are only written for lobes whose minimum has no other lobe minimum within
  // 5 % of the width (the crowded low-speed lobes stay unlabelled).
  struct Label {
    double rpm, depth_mm;
    int lobe;
  };
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

  // --- data ---
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
  std::size_t curve_points = 0;
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

  // --- script ---
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
  if (bounded.empty())
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
  if (!labels.empty())
    gp << ", \\\n  data index 2 using 1:2:(sprintf('k=%d', int($3))) with labels boxed offset 0,0.9 font ','.(fs-2) "
          "tc rgb "
       << quote(kLabel) << " notitle";
  gp << "\n";
  if (freq_panel) {
    gp << "\n# Lower panel: chatter frequency at the limit\n"
       << "unset label 1; unset label 3; unset title; unset key\n"
       << "set tmargin at screen 0.36; set bmargin at screen 0.10\n"
       << "set format x '%g'\n"
       << "set xlabel 'spindle speed (rev/min)'\n"
       << "set ylabel 'chatter frequency (Hz)'\n"
       << "set ytics autofreq\n";
    if (!bounded.empty())
      gp << "set autoscale y\n"
         << "plot data index 0 using 1:4 with points pt 7 ps 0.35 lc rgb c_envelope notitle\n";
    else  // nothing to show: an empty panel that says why
      gp << "set yrange [0:1]; set format y ''\n"
         << "set label 2 sprintf('no chatter below %g mm at any speed', depth_max) at graph 0.5, graph 0.5 center\n"
         << "plot -1 with lines notitle\n";
  }
  gp << "unset multiplot\n";
  write_and_render(t, dat.str(), gp.str());
  return {t.image, t.script, t.data};
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
      << "# Relative receptance = tool + workpiece (PHYSICS.md section 2). '?' = rigid body (no value).\n"
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

}  // namespace chatter
