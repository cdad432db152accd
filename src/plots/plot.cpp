// Plots through gnuplot (see include/chatter/io/plot.hpp and docs/plots.md):
// the plumbing every plot kind shares (plot_kit.hpp) and running gnuplot.
// The kinds: plot_lobes.cpp, plot_frf.cpp, plot_map.cpp (Floquet stability
// maps), plot_compare.cpp, plot_simulation.cpp; and the commands' own
// families (plot_forced.cpp, plot_surface.cpp, plot_uncertainty.cpp, ...).
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
#include "plot_kit.hpp"

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

namespace plot_kit {



// A number for the .dat file: 10 significant digits (or `digits`), `?` when
// not finite.
std::string num(double x, int digits) {
  if (!std::isfinite(x)) return "?";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

// A number for the script and for labels: `digits` significant digits.
std::string short_num(double x, int digits) {
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


Target make_target(const fs::path& image, const PlotOptions& options) {
  Target t{check_plot_path(image), image, image, image, "", "", nullptr, ""};
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
  Target t{ImageFormat::png, {}, {}, {}, "", kLiveDataBlock, nullptr, ""};
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

// Type code in the .dat files.
const char* type_word(MultiplierType t) {
  switch (t) {
    case MultiplierType::kHopf: return "hopf";
    case MultiplierType::kFlip: return "flip";
    case MultiplierType::kFold: return "fold";
  }
  return "hopf";
}

}  // namespace plot_kit

using namespace plot_kit;

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

}  // namespace chatter

