// Plots of the forced response (include/chatter/io/plot_forced.hpp).
#include "chatter/io/plot_forced.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/io/table_writer.hpp"
#include "plot_kit.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;
using namespace plot_kit;

std::string g(double x, int digits = 8) { return gnuplot_number(x, digits); }
// A value for the data file: '?' (missing) unless finite.
std::string d(double x, int digits = 8) { return std::isfinite(x) ? g(x, digits) : std::string("?"); }

// The files of an image (the data and script beside it), as every plot's
// (plot_kit.hpp), at the default size.
Target files_of(const fs::path& image) { return make_target(image, PlotOptions{}); }

// The script's head: how to reproduce it, the terminal, the data file, and
// the grid these charts share.
std::string preamble(const Target& f, const std::string& what) {
  return script_preamble(f, PlotOptions{}, what) + "set grid lc rgb '#d9d9d9' lw 0.6\nset border lw 0.8\n";
}

}  // namespace

PlotFiles plot_forced(const fs::path& image, const std::string& title, const ForcedResponse& r) {
  const Target f = files_of(image);
  const std::string where = image.string() + ": forced response: ";
  if (!r.milling)
    throw InputError(where + "turning has a constant deflection, no path to draw (the diametral error along a "
                             "shaft is plot_shaft_deflection)");
  if (!r.stable) throw InputError(where + "the cut is unstable: there is no forced response to draw");
  if (r.t_s.size() < 2) throw InputError(where + "the tool path was not recorded");
  const std::string head = one_line(title);
  const std::size_t nz = r.wall_z_m.size(), nt = r.tooth_wall_t_s.size();
  std::ostringstream dat;
  dat << "# " << head << ": forced response over one period (chatter " << version() << ")\n"
      << "# method " << r.method << ", period " << g(r.period_s) << " s, spectral radius " << g(r.spectral_radius, 6)
      << "\n\n# index 0: the tool path relative to the workpiece\n"
      << "# time_ms rel_x_um rel_y_um wall_normal_um (-n_w.r: into the wall, + = material left)\n";
  for (std::size_t i = 0; i < r.t_s.size(); ++i)
    dat << g(r.t_s[i] * 1e3, 10) << ' ' << g(r.rel_x_m[i] * 1e6) << ' ' << g(r.rel_y_m[i] * 1e6) << ' '
        << g(r.wall_normal_m[i] * 1e6) << '\n';
  dat << "\n\n# index 1: the wall passes of the tooth tips (z = 0)\n# time_ms sle_um tooth\n";
  for (std::size_t j = 0; j < nt; ++j)
    dat << g(r.tooth_wall_t_s[j] * 1e3, 10) << ' ' << g(r.tooth_wall_sle_m[j * nz] * 1e6) << ' ' << j + 1 << '\n';
  if (nt == 0) dat << "? ? ?\n";
  dat << "\n\n# index 2: the machined wall: height z, the wall (deepest pass), then each tooth's pass\n"
      << "# z_mm wall_sle_um";
  for (std::size_t j = 0; j < nt; ++j) dat << " tooth" << j + 1 << "_sle_um";
  dat << '\n';
  // Straight teeth: one height; drawn as the wall from 0 to the depth.
  const std::size_t rows = nz == 1 ? 2 : nz;
  for (std::size_t k = 0; k < rows; ++k) {
    const std::size_t i = nz == 1 ? 0 : k;
    const double z = nz == 1 ? (k == 0 ? 0.0 : r.depth_m) : r.wall_z_m[i];
    dat << g(z * 1e3) << ' ' << g(r.wall_sle_m[i] * 1e6);
    for (std::size_t j = 0; j < nt; ++j) dat << ' ' << g(r.tooth_wall_sle_m[j * nz + i] * 1e6);
    dat << '\n';
  }

  // The SLE axis: every pass and the nominal wall (0), with a margin.
  double sle_lo = 0.0, sle_hi = 0.0;
  for (const double v : r.tooth_wall_sle_m) {
    sle_lo = std::min(sle_lo, v * 1e6);
    sle_hi = std::max(sle_hi, v * 1e6);
  }
  const double pad = std::max(0.1 * (sle_hi - sle_lo), 0.5);
  sle_lo -= pad;
  sle_hi += pad;
  std::ostringstream gp;
  gp << preamble(f, "Forced response: tool path and machined wall");
  std::ostringstream t;
  t.precision(3);
  t << "SLE " << r.surface_location_error_m * 1e6 << " µm, peak to peak " << r.peak_to_peak_x_m * 1e6 << " / "
    << r.peak_to_peak_y_m * 1e6 << " µm (x / y), smallest chip " << r.min_chip_m * 1e6 << " µm"
    << (r.teeth_leave_cut ? ": teeth leave the cut, the linear limit does not hold" : "");
  gp << "set multiplot layout 1,2 title " << gnuplot_quote(head) << ".\"\\n\"." << gnuplot_quote(t.str())
     << " noenhanced font ','.(fs-1) margins 0.08,0.97,0.11,0.86 spacing 0.09,0\n"
     << "set key top left opaque box lc rgb '#d9d9d9' font ','.(fs-3)\n"
     << "set xlabel 'time over one period (ms)'\nset ylabel 'relative displacement (µm)'\n"
     << "set xrange [0:" << g(r.period_s * 1e3, 10) << "]\n"
     << "set offsets 0, 0, graph 0.25, graph 0.05\n"
     << "plot data index 0 using 1:4 with lines lw 6 lc rgb '#c7c7c7' title 'into the wall, -n_w·r', \\\n"
     << "     data index 0 using 1:2 with lines lw 1.4 lc rgb '#1f77b4' title 'x (feed)', \\\n"
     << "     data index 0 using 1:3 with lines lw 1.4 lc rgb '#ff7f0e' title 'y', \\\n"
     << "     data index 1 using 1:2 with points pt 7 ps 1.3 lc rgb '#d62728' title 'tooth at the wall', \\\n"
     << "     data index 1 using 1:2:(sprintf('%d', $3)) with labels offset 0,1.1 font ','.(fs-3) notitle\n"
     << "set offsets 0, 0, 0, 0\n"
     << "set xlabel 'surface location error (µm, + = material left)'\nset ylabel 'height above the tool tip (mm)'\n"
     << "set xrange [" << g(sle_lo) << ":" << g(sle_hi) << "]   # the nominal wall (0) always in view\n"
     << "set yrange [0:" << g(r.depth_m * 1e3) << "]\n"
     << "set arrow from 0, graph 0 to 0, graph 1 nohead dt 3 lw 1 lc rgb '#7f7f7f'\n"
     << "plot ";
  for (std::size_t j = 0; j < nt; ++j)
    gp << "data index 2 using " << j + 3 << ":1 with lines lw 1 dt 2 lc rgb '#7f7f7f' "
       << (j == 0 ? "title 'each tooth'" : "notitle") << ", \\\n     ";
  gp << "data index 2 using 2:1 with lines lw 3 lc rgb '#2ca02c' title 'machined wall'\n"
     << "unset multiplot\n";
  write_and_render(f, dat.str(), gp.str());
  return {f.image, f.script, f.data};
}

PlotFiles plot_sle(const fs::path& image, const std::string& title, const std::vector<ForcedResponse>& rows,
                   const std::vector<StabilityLimit>& limits, double depth_mm) {
  const Target f = files_of(image);
  const std::string where = image.string() + ": SLE plot: ";
  if (rows.size() < 2 || rows.size() != limits.size())
    throw InputError(where + "needs >= 2 speeds, one limit each (got " + std::to_string(rows.size()) + " and " +
                     std::to_string(limits.size()) + ")");
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].spindle_rpm != limits[i].spindle_rpm) throw InputError(where + "rows and limits at different speeds");
  const std::string head = one_line(title);
  std::ostringstream dat;
  dat << "# " << head << ": surface location error and forced vibration under the lobes (chatter " << version()
      << ")\n# depth of cut " << g(depth_mm) << " mm\n\n"
      << "# index 0: the lobes (sdm), '?' where no limit was found below the searched depth\n"
      << "# spindle_rpm depth_limit_mm\n";
  double deepest = depth_mm;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const StabilityLimit& l = limits[i];
    if (l.bounded()) deepest = std::max(deepest, l.depth_limit_m * 1e3);
    dat << g(l.spindle_rpm, 10) << ' ' << (l.bounded() ? g(l.depth_limit_m * 1e3) : "?") << '\n';
  }
  dat << "\n\n# index 1: the stable speeds (the unstable ones have no forced response: a blank line\n"
      << "# ends a run of stable speeds, so the lines break there)\n"
      << "# spindle_rpm sle_um peak_to_peak_x_um peak_to_peak_y_um teeth_leave_cut_sle_um ('?' where they stay in)\n";
  bool any = false, gap = false;
  for (const ForcedResponse& r : rows) {
    if (!r.stable) {
      gap = any;
      continue;
    }
    if (gap) dat << '\n';
    gap = false;
    any = true;
    dat << g(r.spindle_rpm, 10) << ' ' << d(r.surface_location_error_m * 1e6) << ' ' << d(r.peak_to_peak_x_m * 1e6)
        << ' ' << d(r.peak_to_peak_y_m * 1e6) << ' '
        << (r.teeth_leave_cut ? d(r.surface_location_error_m * 1e6) : "?") << '\n';
  }
  if (!any) dat << "? ? ? ? ?\n";
  std::ostringstream gp;
  gp << preamble(f, "Surface location error and forced vibration under the lobes");
  gp << "set multiplot layout 2,1 title " << gnuplot_quote(head) << " noenhanced font ','.(fs+2) "
     << "margins 0.09,0.97,0.08,0.91 spacing 0,0.06\n"
     << "set xrange [" << g(rows.front().spindle_rpm, 10) << ":" << g(rows.back().spindle_rpm, 10) << "]\n"
     << "set key top right opaque box lc rgb '#d9d9d9' font ','.(fs-3)\n"
     << "set format x ''\nset ylabel 'depth (mm)'\n"
     << "set yrange [0:" << g(1.15 * deepest) << "]\n"
     << "set arrow from graph 0, first " << g(depth_mm) << " to graph 1, first " << g(depth_mm)
     << " nohead lw 1.6 dt 2 lc rgb '#d62728'\n"
     << "set label " << gnuplot_quote("this cut: " + g(depth_mm, 4) + " mm") << " at graph 0.01, first "
     << g(depth_mm) << " offset 0,0.7 tc rgb '#d62728' font ','.(fs-3)\n"
     << "plot data index 0 using 1:2 with lines lw 2 lc rgb '#d95f02' title 'stability limit (sdm)'\n"
     << "unset arrow\nunset label\nset format x '%g'\n"
     << "set xlabel 'spindle speed (rev/min)'\nset ylabel 'µm'\nset autoscale y\n"
     << "set offsets 0, 0, graph 0.2, graph 0.05\n"
     << "plot data index 1 using 1:2 with lines lw 2.4 lc rgb '#202020' title 'surface location error (+ = "
        "material left)', \\\n"
     << "     data index 1 using 1:3 with lines lw 1.2 lc rgb '#1f77b4' title 'peak to peak x', \\\n"
     << "     data index 1 using 1:4 with lines lw 1.2 lc rgb '#ff7f0e' title 'peak to peak y', \\\n"
     << "     data index 1 using 1:5 with points pt 6 ps 0.9 lc rgb '#d62728' title 'teeth leave the cut "
        "(linear model not valid)'\n"
     << "unset multiplot\n";
  write_and_render(f, dat.str(), gp.str());
  return {f.image, f.script, f.data};
}

PlotFiles plot_shaft_deflection(const fs::path& image, const std::string& title, const std::vector<double>& positions_mm,
                                const std::vector<ShaftDeflection>& rows) {
  const Target f = files_of(image);
  const std::string where = image.string() + ": diametral error plot: ";
  if (rows.size() < 2 || positions_mm.size() != rows.size())
    throw InputError(where + "needs >= 2 positions, one deflection each");
  const std::string head = one_line(title);
  std::ostringstream dat;
  dat << "# " << head << ": static deflection along the part (chatter " << version() << ")\n"
      << "# position_mm diametral_error_um deflection_um force_n\n";
  for (std::size_t i = 0; i < rows.size(); ++i)
    dat << g(positions_mm[i], 10) << ' ' << g(rows[i].deflection.diametral_error_m * 1e6) << ' '
        << g(rows[i].deflection.deflection_m * 1e6) << ' ' << g(rows[i].deflection.force_n) << '\n';
  std::ostringstream gp;
  gp << preamble(f, "Diametral error along the part");
  gp << "set title " << gnuplot_quote(head) << " noenhanced font ','.(fs+2)\n"
     << "set key top left opaque box lc rgb '#d9d9d9' font ','.(fs-2)\n"
     << "set xlabel 'tool position (mm)'\nset ylabel 'µm'\n"
     << "plot data using 1:2 with linespoints lw 2.4 pt 7 ps 0.7 lc rgb '#202020' title 'diametral error 2δ', \\\n"
     << "     data using 1:3 with lines lw 1.2 dt 2 lc rgb '#1f77b4' title 'deflection δ along the radius'\n";
  write_and_render(f, dat.str(), gp.str());
  return {f.image, f.script, f.data};
}

}  // namespace chatter
