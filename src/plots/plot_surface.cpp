// The lobe-surface plot (include/chatter/io/plot_surface.hpp).
#include "chatter/io/plot_surface.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "chatter/io/table_writer.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;

std::string g(double x, int digits = 8) { return gnuplot_number(x, digits); }

void check_surface(const std::string& where, const LobeSurfaceData& s) {
  const std::size_t np = s.positions_mm.size();
  if (np < 2 || s.limits.size() != np)
    throw InputError(where + "needs >= 2 positions, one row of limits each (got " + std::to_string(np) +
                     " positions, " + std::to_string(s.limits.size()) + " rows)");
  for (std::size_t p = 0; p < np; ++p) {
    if (!std::isfinite(s.positions_mm[p]) || (p > 0 && !(s.positions_mm[p] > s.positions_mm[p - 1])))
      throw InputError(where + "positions must be finite and strictly increasing");
    if (s.limits[p].size() < 2 || s.limits[p].size() != s.limits[0].size())
      throw InputError(where + "every position needs the same >= 2 speeds");
    for (std::size_t i = 0; i < s.limits[p].size(); ++i)
      if (s.limits[p][i].spindle_rpm != s.limits[0][i].spindle_rpm)
        throw InputError(where + "every position needs the same speeds");
  }
  if (!(std::isfinite(s.depth_max_mm) && s.depth_max_mm > 0.0))
    throw InputError(where + "depth_max_mm must be > 0");
}

}  // namespace

std::vector<double> default_contour_depths_mm(const LobeSurfaceData& surface) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& row : surface.limits)
    for (const auto& r : row)
      if (r.bounded()) {
        lo = std::min(lo, r.depth_limit_m * 1e3);
        hi = std::max(hi, r.depth_limit_m * 1e3);
      }
  if (!(hi > lo)) return {};
  // The smallest 1-2-5 step giving at most 5 levels strictly inside (lo, hi).
  constexpr int kMaxLevels = 5;
  const double raw = (hi - lo) / kMaxLevels;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = decade * 10.0;
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= raw) {
      step = m * decade;
      break;
    }
  std::vector<double> out;
  for (double v = std::floor(lo / step + 1.0) * step; v < hi && out.size() < kMaxLevels; v += step)
    if (v > lo) out.push_back(v);
  return out;
}

std::vector<StabilityLimit> best_speed_per_position(const LobeSurfaceData& surface) {
  std::vector<StabilityLimit> best;
  for (const auto& row : surface.limits) {
    const StabilityLimit* b = nullptr;
    for (const auto& r : row)
      if (!b || r.depth_limit_m > b->depth_limit_m) b = &r;
    if (b) best.push_back(*b);
  }
  return best;
}

namespace {

// The .dat file: the grid (index 0: the limit, or depth_max where none is
// below it) and the best speed at each position (index 1).
std::string surface_data(const std::string& one_line_title, const LobeSurfaceData& surface,
                         const std::vector<StabilityLimit>& best) {
  const std::size_t np = surface.positions_mm.size(), ns = surface.limits[0].size();
  std::ostringstream dat;
  dat << "# " << one_line_title << ": lobe surface (chatter " << version() << ")\n"
      << "# " << np << " positions x " << ns << " spindle speeds.\n\n"
      << "# index 0: the grid, one block per position (blocks separated by one blank line).\n"
      << "# depth_shown_mm: the limit, or depth_max_mm (" << g(surface.depth_max_mm)
      << ") where no chatter was found below it (stable: 1 then 0).\n"
      << "# spindle_rpm position_mm depth_shown_mm stable_to_depth_max\n";
  for (std::size_t p = 0; p < np; ++p) {
    if (p > 0) dat << '\n';
    for (const auto& r : surface.limits[p]) {
      const bool b = r.bounded();
      dat << g(r.spindle_rpm, 10) << ' ' << g(surface.positions_mm[p], 10) << ' '
          << g(b ? std::min(r.depth_limit_m * 1e3, surface.depth_max_mm) : surface.depth_max_mm, 7) << ' '
          << (b ? 0 : 1) << '\n';
    }
  }
  dat << "\n\n# index 1: the best speed at each position (deepest limit; '?' depth = none below depth_max_mm)\n"
      << "# spindle_rpm position_mm depth_limit_mm\n";
  for (std::size_t p = 0; p < np; ++p)
    dat << g(best[p].spindle_rpm, 10) << ' ' << g(surface.positions_mm[p], 10) << ' '
        << g(best[p].depth_limit_m * 1e3, 7) << '\n';
  return dat.str();
}

// The surface plot to image files, or (window) to a live window.
PlotFiles draw_surface(PlotWindow* window, const fs::path& image, const std::string& title,
                       const LobeSurfaceData& surface, const std::vector<double>& contour_depths_mm) {
  const ImageFormat format = window ? ImageFormat::png : check_plot_path(image);
  const std::string where = (window ? std::string("live plot") : image.string()) + ": lobe surface: ";
  if (!window && (image.filename().empty() || image.stem().empty()))
    throw InputError(image.string() + ": not an image file name");
  check_surface(where, surface);
  for (const double c : contour_depths_mm)
    if (!(std::isfinite(c) && c > 0.0)) throw InputError(where + "contour depth " + g(c) + " mm: must be > 0");
  fs::path data = image, script = image;
  data.replace_extension(".dat");
  script.replace_extension(".gp");
  const std::vector<StabilityLimit> best = best_speed_per_position(surface);
  // Colour scale: 0 to 1.1 x the deepest bounded limit (at most depth_max),
  // so the colours resolve the limits; deeper ones take the top colour.
  double deepest = 0.0;
  for (const auto& row : surface.limits)
    for (const auto& r : row)
      if (r.bounded()) deepest = std::max(deepest, r.depth_limit_m * 1e3);
  const double top = deepest > 0.0 ? std::min(surface.depth_max_mm, 1.1 * deepest) : surface.depth_max_mm;
  std::size_t clipped = 0;
  for (const auto& row : surface.limits)
    for (const auto& r : row) clipped += !(r.depth_limit_m * 1e3 <= top);

  std::string one_line_title = title;
  std::replace(one_line_title.begin(), one_line_title.end(), '\n', ' ');
  const std::string dat = surface_data(one_line_title, surface, best);

  std::ostringstream gp;
  if (window)
    gp << live_script_head("Lobe surface: depth limit over spindle speed and tool position");
  else
    gp << "# Lobe surface: depth limit over spindle speed and tool position, written by chatter " << version()
       << ".\n# Reproduce or restyle: cd into this directory, edit, then run\n#   gnuplot "
       << script.filename().string() << "\n# It reads " << data.filename().string() << " and writes "
       << image.filename().string() << ".\n\n"
       << "fs = " << (format == ImageFormat::pdf ? 10 : 14) << "\n"
       << fixed_size_terminal(format) << "set output " << gnuplot_quote(image.filename().string()) << "\n"
       << "set encoding utf8\nset datafile missing '?'\ndata = " << gnuplot_quote(data.filename().string()) << "\n";
  gp << "depth_top = " << g(top) << "   # mm: the top of the colour scale (deeper limits take its colour)\n";
  gp << "\n# Contours of the chosen depths (mm), traced by gnuplot on the grid into a datablock.\n";
  if (!contour_depths_mm.empty()) {
    gp << "set contour base\nunset surface\nset view map\nset cntrparam linear\nset cntrparam levels discrete ";
    for (std::size_t i = 0; i < contour_depths_mm.size(); ++i) gp << (i ? "," : "") << g(contour_depths_mm[i]);
    gp << "\nset table $contours\nsplot data index 0 using 1:2:3 with lines notitle\nunset table\n"
       << "unset contour\nset surface\n";
  }
  gp << "\nset title " << gnuplot_quote(one_line_title) << " noenhanced font ','.(fs+2)\n"
     << "set xlabel 'spindle speed (rev/min)'\nset ylabel 'tool position (mm)'\n"
     << "set cblabel 'depth limit (mm)'\n"
     << "set xrange [" << g(surface.limits[0].front().spindle_rpm, 10) << ":"
     << g(surface.limits[0].back().spindle_rpm, 10) << "]\n"
     << "set yrange [" << g(surface.positions_mm.front(), 10) << ":" << g(surface.positions_mm.back(), 10) << "]\n"
     << "set cbrange [0:depth_top]\n"
     << "set palette defined (0 '#7a0c0c', 0.15 '#d7301f', 0.35 '#fc8d59', 0.55 '#fee090', 0.75 '#91bfdb', "
        "1 '#2c5aa0')\n"
     << "set key top right opaque box font ','.(fs-2)\nset tics front\nset border front\n";
  if (clipped > 0)
    gp << "# The top colour also marks deeper limits (and speeds stable to depth_max_mm).\n"
       << "set cbtics add (sprintf('≥ %g', depth_top) depth_top)\n";
  gp << "plot data index 0 using 1:2:($3 > depth_top ? depth_top : $3) with image notitle";
  if (!contour_depths_mm.empty())
    gp << ", \\\n  $contours using 1:2 with lines lw 1.6 lc rgb '#202020' title 'depth contours (" ;
  if (!contour_depths_mm.empty()) {
    for (std::size_t i = 0; i < contour_depths_mm.size(); ++i) gp << (i ? ", " : "") << g(contour_depths_mm[i]);
    gp << " mm)'"
       << ", \\\n  $contours using 1:2:(sprintf('%g', $3)) every 25 with labels font ','.(fs-3) tc rgb '#202020' "
          "notitle";
  }
  gp << ", \\\n  data index 1 using 1:2 with lines lw 5 lc rgb '#202020' notitle"
     << ", \\\n  data index 1 using 1:2 with linespoints lw 2.5 pt 7 ps 0.8 lc rgb '#ffffff' "
        "title 'best speed at each position'\n";

  if (window) {
    window->draw(dat, gp.str());
    return {};
  }
  write_text_files({{data, dat}, {script, gp.str()}});
  render_gnuplot_image(script, image);
  return {image, script, data};
}

}  // namespace

PlotFiles plot_surface(const fs::path& image, const std::string& title, const LobeSurfaceData& surface,
                       const std::vector<double>& contour_depths_mm) {
  return draw_surface(nullptr, image, title, surface, contour_depths_mm);
}

void plot_surface(PlotWindow& window, const std::string& title, const LobeSurfaceData& surface,
                  const std::vector<double>& contour_depths_mm) {
  draw_surface(&window, {}, title, surface, contour_depths_mm);
}

}  // namespace chatter
