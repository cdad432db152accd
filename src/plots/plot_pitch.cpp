// The band plot of `chatter design-pitch` (include/chatter/io/plot_pitch.hpp,
// docs/design_pitch.md).
#include "chatter/io/plot_pitch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"
#include "plot_files.hpp"

namespace chatter {
namespace {

std::string g(double x, int digits = 10) { return gnuplot_number(x, digits); }

// The smallest bounded limit (m), +inf if none.
double worst(const std::vector<StabilityLimit>& rows) {
  double w = std::numeric_limits<double>::infinity();
  for (const auto& r : rows)
    if (r.bounded()) w = std::min(w, r.depth_limit_m);
  return w;
}

}  // namespace

PlotFiles plot_pitch_design(const std::filesystem::path& image, const std::string& title,
                            const std::vector<StabilityLimit>& equal, const std::vector<StabilityLimit>& designed,
                            const std::string& designed_label, double depth_max_m) {
  const plot_detail::Files f = plot_detail::files_for(image);
  if (equal.empty() || equal.size() != designed.size())
    throw InputError("plot_pitch_design: " + std::to_string(equal.size()) + " equal-pitch rows and " +
                     std::to_string(designed.size()) + " designed rows: must be the same number, > 0");
  for (std::size_t i = 0; i < equal.size(); ++i)
    if (equal[i].spindle_rpm != designed[i].spindle_rpm)
      throw InputError("plot_pitch_design: row " + std::to_string(i + 1) + " is at different speeds");
  std::ostringstream d;
  d << "# chatter design-pitch: depth limit over the band (mm; '?' = none below " << g(depth_max_m * 1e3, 6)
    << " mm)\n# spindle_rpm depth_limit_equal_mm depth_limit_designed_mm\n";
  double top = 0.0;
  for (std::size_t i = 0; i < equal.size(); ++i) {
    const auto cell = [&](const StabilityLimit& r) {
      if (!r.bounded()) return std::string("?");
      top = std::max(top, r.depth_limit_m * 1e3);
      return g(r.depth_limit_m * 1e3);
    };
    d << g(equal[i].spindle_rpm) << ' ' << cell(equal[i]) << ' ' << cell(designed[i]) << '\n';
  }
  const double w_equal = worst(equal), w_designed = worst(designed);
  const double y_max = top > 0.0 ? std::min(depth_max_m * 1e3, 1.15 * top) : depth_max_m * 1e3;
  std::ostringstream s;
  s << plot_detail::terminal(f, "Pitch design over a speed band (chatter design-pitch)")
    << "set title " << gnuplot_quote(title) << " noenhanced\n"
    << "set xlabel 'spindle speed (rev/min)'\nset ylabel 'depth limit (mm)'\n"
    << "set xrange [" << g(equal.front().spindle_rpm) << ":" << g(equal.back().spindle_rpm) << "]\n"
    << "set yrange [0:" << g(y_max, 6) << "]\n"
    << "set key bottom right box opaque noenhanced\n"
    << "c_equal = '#606060'; c_designed = '#d95f02'\n";
  if (std::isfinite(w_equal))
    s << "set arrow 1 from graph 0, first " << g(w_equal * 1e3) << " to graph 1, first " << g(w_equal * 1e3)
      << " nohead dt (6,4) lw 1.5 lc rgb c_equal\n"
      << "set label 1 sprintf('worst, equal: %.3g mm', " << g(w_equal * 1e3) << ") at graph 0.01, first "
      << g(w_equal * 1e3) << " offset 0, 0.6 tc rgb c_equal\n";
  if (std::isfinite(w_designed))
    s << "set arrow 2 from graph 0, first " << g(w_designed * 1e3) << " to graph 1, first " << g(w_designed * 1e3)
      << " nohead dt (6,4) lw 1.5 lc rgb c_designed\n"
      << "set label 2 sprintf('worst, designed: %.3g mm', " << g(w_designed * 1e3) << ") at graph 0.01, first "
      << g(w_designed * 1e3) << " offset 0, 0.6 tc rgb c_designed\n";
  s << "plot data using 1:2 with linespoints lw 2 pt 7 ps 0.5 lc rgb c_equal title 'equal pitch', \\\n"
    << "     data using 1:3 with linespoints lw 2.5 pt 7 ps 0.5 lc rgb c_designed title "
    << gnuplot_quote("designed: " + designed_label) << "\n";
  return plot_detail::render(f, d.str(), s.str());
}

}  // namespace chatter
