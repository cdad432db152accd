// Plots through gnuplot: stability lobes (envelope, lobes, absolute limit, chatter-frequency panel).
// The shared plumbing is plot_kit.hpp (plot.cpp); docs/plots.md shows each plot.
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

namespace chatter {

namespace fs = std::filesystem;
using namespace plot_kit;

// ---------------------------------------------------------------------------
// Stability lobes

namespace {

// Top of the depth axis (mm): every finite limit visible with a 10 % margin
// (the deepest stable pocket, e.g. a flip/Hopf pocket of sdm at low
// immersion, must not be cut off), and at least 4 × the absolute limit (if
// any, else the lowest depth) so that the pockets stand out from it; rounded
// up to a nice value and capped at depth_max_mm. `bounded`: the bounded
// depths (mm, clipped to depth_max_mm).
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

}  // namespace chatter
