// The table and the heat map of the spindle-speed-variation map
// (include/chatter/io/plot_ssv.hpp, docs/ssv.md).
#include "chatter/io/plot_ssv.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/io/table_writer.hpp"
#include "plot_files.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;

// Colours clip at ρ = 10 per revolution (and 1/10).
constexpr double kClipLogRho = 2.302585092994046;

std::string g(double x, int digits = 8) { return gnuplot_number(x, digits); }

}  // namespace

std::string ssv_map_csv(const SsvMapGrid& grid) {
  std::ostringstream os;
  os << "amplitude_ratio,frequency_ratio,frequency_ratio_used,exact_period,spectral_radius_per_revolution\n";
  const std::size_t nf = grid.frequency_ratios.size();
  for (std::size_t i = 0; i < grid.amplitude_ratios.size(); ++i)
    for (std::size_t j = 0; j < nf; ++j) {
      const std::size_t k = i * nf + j;
      os << table_number(grid.amplitude_ratios[i]) << ',' << table_number(grid.frequency_ratios[j]) << ','
         << table_number(grid.frequency_ratio_used[k]) << ',' << (grid.exact[k] ? "true" : "false") << ','
         << table_number(grid.rho_per_revolution[k]) << '\n';
    }
  return os.str();
}

PlotFiles plot_ssv_map(const fs::path& image, const std::string& title, const SsvMapGrid& grid) {
  const plot_detail::Files f = plot_detail::files_for(image);
  const std::size_t nf = grid.frequency_ratios.size();
  std::ostringstream d;
  d << "# chatter map --ssv-map at " << g(grid.spindle_rpm, 6) << " rev/min, " << g(grid.depth_m * 1e3, 6)
    << " mm\n# frequency_ratio amplitude_ratio ln_rho_per_revolution (clipped)\n";
  for (std::size_t i = 0; i < grid.amplitude_ratios.size(); ++i) {
    for (std::size_t j = 0; j < nf; ++j) {
      const double r = grid.rho_per_revolution[i * nf + j];
      const double l = std::isfinite(r) && r > 0.0 ? std::clamp(std::log(r), -kClipLogRho, kClipLogRho) : kClipLogRho;
      d << g(grid.frequency_ratios[j]) << ' ' << g(grid.amplitude_ratios[i]) << ' ' << g(l) << '\n';
    }
    d << '\n';
  }
  // The image's cells are centred on the grid points: half a step beyond each end.
  const auto& fr = grid.frequency_ratios;
  const auto& ar = grid.amplitude_ratios;
  const double hx = fr.size() > 1 ? 0.5 * (fr.back() - fr.front()) / static_cast<double>(fr.size() - 1) : 0.05 * fr.front();
  const double hy = ar.size() > 1 ? 0.5 * (ar.back() - ar.front()) / static_cast<double>(ar.size() - 1) : 0.05;
  const double x_lo = fr.front() - hx, x_hi = fr.back() + hx, y_lo = ar.front() - hy, y_hi = ar.back() + hy;
  std::ostringstream s;
  s << plot_detail::terminal(f, "Spindle speed variation map") << "set title " << gnuplot_quote(title)
    << " noenhanced\n"
    << "set xlabel 'frequency ratio R_VF (modulation / spindle frequency)' noenhanced\n"
    << "set ylabel 'amplitude ratio R_VA' noenhanced\n"
    << "set cblabel 'ln of the spectral radius per revolution (< 0 stable)'\n"
    << "set cbrange [" << g(-kClipLogRho) << ":" << g(kClipLogRho) << "]\n"
    << "set palette defined (-1 '#2166ac', -0.5 '#92c5de', 0 '#f7f7f7', 0.5 '#f4a582', 1 '#b2182b')\n"
    << "set view map\nset key off\nset grid front\n"
    << "set xrange [" << g(x_lo) << ":" << g(x_hi) << "]\nset yrange [" << g(y_lo) << ":" << g(y_hi) << "]\n"
    // The ρ = 1 contour from the same data.
    << "set contour base\nunset surface\nset cntrparam levels discrete 0\nset table $boundary\n"
    << "splot data using 1:2:3\nunset table\nset surface\nunset contour\n";
  if (nf > 1 && grid.amplitude_ratios.size() > 1)
    s << "plot data using 1:2:3 with image, $boundary using 1:2 with lines lw 2.5 lc rgb '#000000'\n";
  else
    s << "plot data using 1:2:3 with points pt 5 ps 3 palette\n";
  return plot_detail::render(f, d.str(), s.str());
}

}  // namespace chatter
