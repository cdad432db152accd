// Plots of `chatter grind sweep|fit|impacts|simulate`
// (include/chatter/io/plot_grinding.hpp): data, script and image side by side.
#include "chatter/io/plot_grinding.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/io/table_writer.hpp"
#include "chatter/kinematics.hpp"
#include "plot_files.hpp"

namespace chatter {
namespace {

using plot_detail::Files;
using plot_detail::files_for;
using plot_detail::render;
using plot_detail::terminal;

namespace fs = std::filesystem;

std::string g(double x, int digits = 8) { return std::isfinite(x) ? gnuplot_number(x, digits) : "?"; }

const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"};
const char* colour(std::size_t i) { return kColours[i % (sizeof kColours / sizeof kColours[0])]; }

}  // namespace

PlotFiles plot_grinding_sweep(const fs::path& image, const std::string& title,
                              const std::vector<grinding::SweepCurve>& curves, const grinding::Envelope& env) {
  const Files f = files_for(image);
  if (curves.empty() || curves.front().points.empty()) throw InputError(image.string() + ": nothing to plot");
  const bool emp = curves.front().points.front().empirical.has_value();
  std::ostringstream d;
  d << "# chatter grind sweep: one block per feed (gnuplot index)\n";
  double pmin = curves.front().points.front().power_w, pmax = curves.front().points.back().power_w;
  for (const auto& c : curves) {
    d << "# feed " << g(c.feed_m_per_s * 1e3, 6) << " mm/s\n"
      << "# power_w removal_rate_mm3_per_s max_depth_mm normal_force_n empirical_removal_mm3_per_s "
         "empirical_normal_force_n\n";
    for (const grinding::Prediction& p : c.points) {
      d << g(p.power_w) << ' ' << g(p.removal_rate_m3_per_s * 1e9) << ' ' << g(p.max_depth_m * 1e3) << ' '
        << g(p.normal_force_n) << ' '
        << (p.empirical && p.empirical->removal_rate_m3_per_s ? g(*p.empirical->removal_rate_m3_per_s * 1e9) : "?")
        << ' ' << (p.empirical && p.empirical->normal_force_n ? g(*p.empirical->normal_force_n) : "?") << '\n';
    }
    d << "\n\n";
  }
  std::ostringstream s;
  s << terminal(f, "Grinding: removal, depth and force against power") << "set multiplot layout 3,1 title "
    << gnuplot_quote(title) << " noenhanced\nset xrange [" << g(pmin) << ":" << g(pmax) << "]\n"
    << "set key top left\nset lmargin 12\n";
  // The envelope: shaded power ranges the models were measured over.
  int obj = 1;
  auto shade = [&](const std::optional<grinding::Interval>& i, const char* rgb) {
    if (!i) return;
    s << "set object " << obj++ << " rect from " << g(std::max(i->lo, pmin)) << ", graph 0 to "
      << g(std::min(i->hi, pmax)) << ", graph 1 back fc rgb '" << rgb << "' fs solid 0.25 noborder\n";
  };
  shade(env.impacts_table_w, "#9ecae1");
  shade(env.tested_power_w, "#fdd0a2");
  std::string note;
  if (env.impacts_table_w) note += "blue: powers of the impacts table";
  if (env.tested_power_w) note += std::string(note.empty() ? "" : "; ") + "orange: powers the empirical models were tested at";
  auto panel = [&](const char* ylabel, int col, int emp_col, bool last) {
    s << "set ylabel " << gnuplot_quote(ylabel) << "\n";
    if (last) s << "set xlabel " << gnuplot_quote("useful grinding power (W)" + (note.empty() ? "" : "   [" + note + "]")) << "\n";
    else s << "unset xlabel\n";
    s << "plot ";
    for (std::size_t i = 0; i < curves.size(); ++i) {
      s << (i ? ", \\\n  " : "") << "data index " << i << " using 1:" << col << " with lines lw 2 lc rgb '"
        << colour(i) << "' title " << gnuplot_quote(g(curves[i].feed_m_per_s * 1e3, 6) + " mm/s");
      if (emp && emp_col > 0)
        s << ", \\\n  data index " << i << " using 1:" << emp_col << " with lines lw 2 dt 2 lc rgb '" << colour(i)
          << "' title " << gnuplot_quote("empirical, " + g(curves[i].feed_m_per_s * 1e3, 6) + " mm/s");
    }
    s << "\n";
  };
  panel("removal rate (mm^3/s)", 2, 5, false);
  panel("maximum depth h_0 (mm)", 3, 0, false);
  panel("normal force (N)", 4, 6, true);
  s << "unset multiplot\n";
  return render(f, d.str(), s.str());
}

PlotFiles plot_grinding_fit(const fs::path& image, const std::string& title, const GrindingFitReport& r) {
  const Files f = files_for(image);
  if (r.targets.empty()) throw InputError(image.string() + ": nothing to plot");
  std::ostringstream d;
  d << "# chatter grind fit: measured and fitted value per test, one block per target\n";
  for (const auto& t : r.targets) {
    d << "# " << t.name << ": measured fitted line\n";
    for (std::size_t i = 0; i < t.rows.size(); ++i)
      d << g(t.fit.fitted[i] + t.fit.residuals[i]) << ' ' << g(t.fit.fitted[i]) << ' ' << r.tests[t.rows[i]].line << '\n';
    d << "\n\n";
  }
  std::ostringstream s;
  s << terminal(f, "Grinding fit: measured against fitted") << "set multiplot layout 1," << r.targets.size()
    << " title " << gnuplot_quote(title) << " noenhanced\nset key top left\nset size ratio -1\n";
  for (std::size_t k = 0; k < r.targets.size(); ++k) {
    const auto& t = r.targets[k];
    const char* unit = r.model == "mechanistic" ? "W" : t.name == "normal_force" ? "N" : "mm^3/s";
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = 0; i < t.rows.size(); ++i)
      for (double v : {t.fit.fitted[i], t.fit.fitted[i] + t.fit.residuals[i]}) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    const double pad = 0.05 * std::max(hi - lo, 1e-12);
    s << "set title " << gnuplot_quote(t.name + ": R^2 = " + g(t.fit.r_squared, 4)) << " noenhanced\n"
      << "set xlabel " << gnuplot_quote(std::string("measured (") + unit + ")") << "\nset ylabel "
      << gnuplot_quote(std::string("fitted (") + unit + ")") << "\nset xrange [" << g(lo - pad) << ":" << g(hi + pad)
      << "]\nset yrange [" << g(lo - pad) << ":" << g(hi + pad) << "]\n"
      << "plot x with lines dt 2 lc rgb '#808080' title 'measured = fitted', \\\n  data index " << k
      << " using 1:2 with points pt 7 ps 1.3 lc rgb '" << colour(k) << "' title 'tests'\n";
  }
  s << "unset multiplot\n";
  return render(f, d.str(), s.str());
}

PlotFiles plot_grinding_impacts(const fs::path& image, const std::string& title, const ImpactRecord& rec,
                                const grinding::ImpactCount& c, double wheel_rpm) {
  const Files f = files_for(image);
  const double turn = revolution_s(wheel_rpm), t0 = rec.time_s.front();
  const double t_end = t0 + std::min(c.turns, 20) * turn;
  const bool force = rec.kind == grinding::ImpactSignal::kNormalForce;
  // The signal as counted: the force, or the speed's drop below its median.
  std::vector<double> sorted(rec.signal);
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::ostringstream d;
  d << "# chatter grind impacts: the record (first turns), the peaks, the histogram\n# time_s "
    << (force ? "normal_force_n" : "speed_drop_rpm") << "\n";
  const std::size_t n = rec.time_s.size();
  std::size_t shown = 0;
  for (std::size_t i = 0; i < n && rec.time_s[i] <= t_end; ++i) ++shown;
  const std::size_t step = std::max<std::size_t>(1, shown / 20000);
  for (std::size_t i = 0; i < shown; i += step)
    d << g(rec.time_s[i]) << ' ' << g(force ? rec.signal[i] : median - rec.signal[i]) << '\n';
  d << "\n\n# peaks: time_s value\n";
  for (std::size_t i = 0; i < c.peak_time_s.size() && c.peak_time_s[i] <= t_end; ++i)
    d << g(c.peak_time_s[i]) << ' ' << g(c.peak_value[i]) << '\n';
  d << "\n\n# histogram: impacts_per_turn turns\n";
  for (std::size_t k = 0; k < c.histogram.size(); ++k) d << k << ' ' << c.histogram[k] << '\n';
  std::ostringstream s;
  s << terminal(f, "Grinding impacts per turn") << "set multiplot layout 2,1 title " << gnuplot_quote(title)
    << " noenhanced\nset key top right\n"
    << "set xlabel 'time (s)'\nset ylabel " << gnuplot_quote(force ? "normal force (N)" : "speed drop (rev/min)")
    << "\nset xrange [" << g(t0) << ":" << g(t_end) << "]\n";
  for (int k = 1; k < std::min(c.turns, 20); ++k)
    s << "set arrow " << k << " from " << g(t0 + k * turn) << ", graph 0 to " << g(t0 + k * turn)
      << ", graph 1 nohead back dt 3 lc rgb '#b0b0b0'\n";
  s << "plot data index 0 using 1:2 with lines lw 1 lc rgb '#1f77b4' title 'record (dotted: wheel turns)', \\\n"
    << "  data index 1 using 1:2 with points pt 7 ps 1.2 lc rgb '#d62728' title 'impacts', \\\n  " << g(c.threshold)
    << " with lines dt 2 lc rgb '#2ca02c' title " << gnuplot_quote("threshold " + g(c.threshold, 4)) << "\n"
    << "unset arrow\nset xrange [-0.5:" << static_cast<double>(c.histogram.size()) - 0.5 << "]\nset xtics 1\nset yrange [0:*]\n"
    << "set xlabel 'impacts in a turn'\nset ylabel 'turns'\nset style fill solid 0.6\nset boxwidth 0.7\nset key top left\n"
    << "plot data index 2 using 1:2 with boxes lc rgb '#1f77b4' title "
    << gnuplot_quote("mean " + g(c.mean_per_turn, 4) + " impacts per turn over " + std::to_string(c.turns) + " turns")
    << "\nunset multiplot\n";
  return render(f, d.str(), s.str());
}

PlotFiles plot_grinding_simulation(const fs::path& image, const std::string& title, const grinding::DynamicsResult& r) {
  const Files f = files_for(image);
  if (r.series.empty()) throw InputError(image.string() + ": the simulation kept no series (series turns 0)");
  std::ostringstream d;
  d << "# chatter grind simulate: the last turns\n# time_s depth_mm surface_mm contact_force_n push_n\n";
  for (const auto& x : r.series)
    d << g(x.time_s) << ' ' << g(x.depth_m * 1e3) << ' ' << g(x.surface_m * 1e3) << ' ' << g(x.contact_force_n)
      << ' ' << g(x.push_n) << '\n';
  const double turn = revolution_s(r.wheel_rpm);
  const double t0 = r.series.front().time_s, t1 = r.series.back().time_s;
  std::ostringstream s;
  s << terminal(f, "Grinding simulation") << "set multiplot layout 2,1 title " << gnuplot_quote(title)
    << " noenhanced\nset key top right\nset xrange [" << g(t0) << ":" << g(t1) << "]\n";
  int k = 1;
  for (double t = std::ceil(t0 / turn - 1e-9) * turn; t <= t1; t += turn)
    s << "set arrow " << k++ << " from " << g(t) << ", graph 0 to " << g(t) << ", graph 1 nohead back dt 3 lc rgb '#b0b0b0'\n";
  s << "unset xlabel\nset ylabel 'depth below the uncut surface (mm)'\n"
    << "plot data using 1:2 with lines lw 2 lc rgb '#1f77b4' title 'wheel', \\\n"
    << "  data using 1:3 with lines lw 1.5 dt 2 lc rgb '#d62728' title 'surface the previous turn left'\n"
    << "set xlabel 'time (s); dotted: wheel turns'\nset ylabel 'normal force (N)'\n"
    << "plot data using 1:4 with lines lw 1.5 lc rgb '#1f77b4' title "
    << gnuplot_quote("contact force (" + g(r.impacts_per_turn, 3) + " impacts per turn)") << "\nunset multiplot\n";
  return render(f, d.str(), s.str());
}

}  // namespace chatter
