// The loss map (include/chatter/io/plot_optimization.hpp).
#include "chatter/io/plot_optimization.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/error.hpp"
#include "plot_files.hpp"

namespace chatter {

namespace {

std::string g(double x, int digits = 8) { return gnuplot_number(x, digits); }
std::string d(double x) { return std::isfinite(x) ? g(x) : std::string("?"); }

// Hatch patterns (gnuplot's fill patterns, skipping the empty 0 and the solid
// 3) and colours of the constraints, in the order of LossMap::constraint_names.
constexpr int kPatterns[] = {4, 5, 6, 7, 1, 2};
constexpr const char* kColours[] = {"#d62728", "#1f77b4", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
                                    "#ff7f0e"};

}  // namespace

PlotFiles plot_loss_map(const std::filesystem::path& image, const std::string& title, const LossMap& map,
                        const std::optional<MapPoint>& optimum, const std::vector<MapPoint>& trajectory) {
  const plot_detail::Files f = plot_detail::files_for(image);
  const std::size_t ns = map.speeds_rpm.size(), nf = map.feeds_m.size();
  if (ns < 2 || nf < 2 || map.value.size() != ns * nf || map.failing.size() != ns * nf)
    throw InputError(image.string() + ": loss map: needs a grid of at least 2 x 2 cells");
  // Turning reads the cutting speed, milling the spindle speed.
  const double xs = map.milling ? 1.0 : map.cutting_speed_per_rpm;
  auto x_of = [&](double rpm) { return rpm * xs; };
  const double dx = 0.5 * (x_of(map.speeds_rpm[1]) - x_of(map.speeds_rpm[0]));
  const double dy = 0.5 * (map.feeds_m[1] - map.feeds_m[0]) * 1e3;
  std::ostringstream dat;
  std::string head = title;
  std::replace(head.begin(), head.end(), '\n', ' ');
  dat << "# " << head << ": " << map.value_label << " over speed x feed at depth " << g(map.depth_m * 1e3)
      << " mm (chatter " << version() << ")\n# index 0: " << (map.milling ? "spindle_rpm" : "cutting_speed_m_per_min")
      << " feed_mm value\n";
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (std::size_t i = 0; i < ns; ++i) {
    for (std::size_t j = 0; j < nf; ++j) {
      const double v = map.value[i * nf + j];
      if (std::isfinite(v) && v > 0.0) lo = std::min(lo, v), hi = std::max(hi, v);
      dat << g(x_of(map.speeds_rpm[i])) << ' ' << g(map.feeds_m[j] * 1e3) << ' ' << d(v) << '\n';
    }
    dat << '\n';
  }
  // One block per constraint: the cells where it fails.
  for (std::size_t c = 0; c < map.constraint_names.size(); ++c) {
    dat << "\n\n# index " << c + 1 << ": cells failing " << map.constraint_names[c] << " (x y dx dy)\n";
    bool any = false;
    for (std::size_t i = 0; i < ns; ++i)
      for (std::size_t j = 0; j < nf; ++j)
        if (map.failing[i * nf + j] & (1u << c)) {
          dat << g(x_of(map.speeds_rpm[i])) << ' ' << g(map.feeds_m[j] * 1e3) << ' ' << g(dx) << ' ' << g(dy) << '\n';
          any = true;
        }
    if (!any) dat << "? ? ? ?\n";
  }
  const std::size_t marks = map.constraint_names.size() + 1;
  dat << "\n\n# index " << marks << ": the optimum\n";
  if (optimum) dat << g(x_of(optimum->spindle_rpm)) << ' ' << g(optimum->feed_m * 1e3) << '\n';
  else dat << "? ?\n";
  dat << "\n\n# index " << marks + 1 << ": the adaptive loop's set-points, in order\n";
  for (const MapPoint& p : trajectory) dat << g(x_of(p.spindle_rpm)) << ' ' << g(p.feed_m * 1e3) << '\n';
  if (trajectory.empty()) dat << "? ?\n";

  std::ostringstream gp;
  gp << plot_detail::terminal(f, "Loss map");
  gp << "set title " << gnuplot_quote(head) << " noenhanced font ','.(fs+1)\n"
     << "set xlabel " << gnuplot_quote(map.milling ? "spindle speed (rev/min)" : "cutting speed (m/min)") << "\n"
     << "set ylabel " << gnuplot_quote(map.milling ? "feed per tooth (mm)" : "feed (mm/rev)") << "\n"
     << "set cblabel " << gnuplot_quote(map.value_label) << "\n"
     << "set xrange [" << g(x_of(map.speeds_rpm.front()) - dx) << ":" << g(x_of(map.speeds_rpm.back()) + dx) << "]\n"
     << "set yrange [" << g(map.feeds_m.front() * 1e3 - dy) << ":" << g(map.feeds_m.back() * 1e3 + dy) << "]\n"
     << "set palette defined (0 '#f7fbff', 1 '#c6dbef', 2 '#6baed6', 3 '#2171b5', 4 '#08306b')\n"
     << "set key outside right top font ','.(fs-3) spacing 1.1\n"
     << "set grid front\n";
  if (std::isfinite(lo) && hi > lo) gp << "set logscale cb\nset cbrange [" << g(lo) << ":" << g(hi) << "]\n";
  gp << "plot data index 0 using 1:2:3 with image notitle";
  for (std::size_t c = 0; c < map.constraint_names.size(); ++c) {
    const std::string& name = map.constraint_names[c];
    gp << ", \\\n     data index " << c + 1 << " using 1:2:3:4 with boxxyerror ";
    if (static_cast<int>(c) == map.stability_bit)
      gp << "fs transparent solid 0.45 noborder lc rgb '#505050' title 'unstable (lobes, margin)'";
    else
      gp << "fs transparent pattern " << kPatterns[c % std::size(kPatterns)] << " noborder lc rgb '"
         << kColours[c % std::size(kColours)] << "' title " << gnuplot_quote("fails " + name) << " noenhanced";
  }
  gp << ", \\\n     data index " << marks + 1
     << " using 1:2 with linespoints lw 1.6 pt 6 ps 0.8 lc rgb '#ff7f0e' title 'adaptive loop'"
     << ", \\\n     data index " << marks
     << " using 1:2 with points pt 7 ps 2.2 lc rgb '#000000' title 'optimum'\n";
  return plot_detail::render(f, dat.str(), gp.str());
}

}  // namespace chatter
