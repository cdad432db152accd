// Plots of `chatter coefficients` and `chatter detect`
// (include/chatter/io/plot_shop.hpp): data, script and image side by side.
#include "chatter/io/plot_shop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "chatter/io/table_writer.hpp"
#include "plot_files.hpp"

namespace chatter {
namespace {

using plot_detail::Files;
using plot_detail::files_for;
using plot_detail::render;
using plot_detail::terminal;

namespace fs = std::filesystem;

std::string g(double x, int digits = 8) { return gnuplot_number(x, digits); }

}  // namespace

PlotFiles plot_coefficient_fit(const fs::path& image, const std::string& title, const CoefficientTests& tests,
                               const CoefficientFit& fit, const MillingEngagement& e, double tool_diameter_m) {
  const Files f = files_for(image);
  const bool power = tests.route == CoefficientRoute::kPower;
  std::ostringstream d;
  d << "# chatter coefficients: measured averages per unit depth and the fitted lines\n";
  double fmax = 0;
  const std::array<double, 4> k{fit.tangential_coefficient_n_per_m2, fit.radial_coefficient_n_per_m2,
                                fit.tangential_edge_coefficient_n_per_m, fit.radial_edge_coefficient_n_per_m};
  if (!power) {
    d << "# feed_per_tooth_mm fx_per_depth_n_per_mm fy_per_depth_n_per_mm\n";
    for (const auto& t : tests.forces) {
      d << g(t.feed_per_tooth_m * 1e3) << ' ' << g(t.fx_mean_n / (t.depth_m * 1e3)) << ' '
        << g(t.fy_mean_n / (t.depth_m * 1e3)) << '\n';
      fmax = std::max(fmax, t.feed_per_tooth_m);
    }
  } else {
    d << "# feed_per_tooth_mm tangential_force_per_depth_n_per_mm (P / (Omega R a))\n";
    for (const auto& t : tests.power) {
      const double omega_r = t.spindle_rpm * std::numbers::pi / 30.0 * 0.5 * tool_diameter_m;
      d << g(t.feed_per_tooth_m * 1e3) << ' ' << g(t.power_w / (omega_r * t.depth_m * 1e3)) << '\n';
      fmax = std::max(fmax, t.feed_per_tooth_m);
    }
  }
  d << "\n\n# fitted: feed_per_tooth_mm fx fy (or tangential) per depth, N/mm\n";
  for (int i = 0; i <= 50; ++i) {
    const double fz = 1.2 * fmax * i / 50.0;
    if (!power) {
      const auto m = mean_forces(e, fz, 1e-3, k);
      d << g(fz * 1e3) << ' ' << g(m[0]) << ' ' << g(m[1]) << '\n';
    } else {
      const double p = mean_power(e, fz, 1e-3, 60.0, tool_diameter_m, k[0], k[2]);
      const double omega_r = 2 * std::numbers::pi * 0.5 * tool_diameter_m;
      d << g(fz * 1e3) << ' ' << g(p / omega_r) << '\n';
    }
  }
  std::ostringstream s;
  s << terminal(f, "Cutting-coefficient fit") << "set title " << gnuplot_quote(title) << " noenhanced\n"
    << "set xlabel 'feed per tooth (mm)'\nset ylabel 'average force per unit depth (N/mm)'\n"
    << "set key top left\nset xrange [0:" << g(1.2 * fmax * 1e3) << "]\nset xzeroaxis lt -1\n";
  if (!power)
    s << "plot data index 0 using 1:2 with points pt 7 ps 1.3 lc rgb '#1f77b4' title 'F_x measured', \\\n"
      << "  data index 1 using 1:2 with lines lw 2 lc rgb '#1f77b4' title 'F_x fit', \\\n"
      << "  data index 0 using 1:3 with points pt 5 ps 1.3 lc rgb '#d62728' title 'F_y measured', \\\n"
      << "  data index 1 using 1:3 with lines lw 2 lc rgb '#d62728' title 'F_y fit'\n";
  else
    s << "plot data index 0 using 1:2 with points pt 7 ps 1.3 lc rgb '#1f77b4' title 'tangential (from power) "
         "measured', \\\n  data index 1 using 1:2 with lines lw 2 lc rgb '#1f77b4' title 'fit'\n";
  return render(f, d.str(), s.str());
}

PlotFiles plot_detection(const fs::path& image, const std::string& title, const ChatterDetection& det) {
  const Files f = files_for(image);
  if (det.spectrum_amplitude.empty()) throw InputError(image.string() + ": no spectrum to plot");
  const double top = det.spectrum_frequency_hz.back();
  double fmax = 3.0 * std::max(det.tooth_passing_hz, std::isfinite(det.candidate_frequency_hz) ? det.candidate_frequency_hz : 0.0);
  fmax = std::min(std::max(fmax, 5 * det.tooth_passing_hz), top);
  // At most ~4000 points: the largest amplitude of each bucket (peaks survive).
  std::size_t n = 0;
  while (n < det.spectrum_frequency_hz.size() && det.spectrum_frequency_hz[n] <= fmax) ++n;
  const std::size_t step = std::max<std::size_t>(1, n / 4000);
  std::ostringstream d;
  d << "# chatter detect: amplitude spectrum (Hann window), single-sided, in the recording's unit\n"
    << "# frequency_hz amplitude\n";
  for (std::size_t i = 1; i < n; i += step) {
    std::size_t best = i;
    for (std::size_t j = i; j < std::min(n, i + step); ++j)
      if (det.spectrum_amplitude[j] > det.spectrum_amplitude[best]) best = j;
    if (det.spectrum_amplitude[best] > 0)
      d << g(det.spectrum_frequency_hz[best]) << ' ' << g(det.spectrum_amplitude[best]) << '\n';
  }
  std::ostringstream s;
  s << terminal(f, "Spectrum of a recording") << "set title " << gnuplot_quote(title) << " noenhanced\n"
    << "set xlabel 'frequency (Hz)'\nset ylabel 'amplitude'\nset logscale y\nset format y '10^{%L}'\n"
    << "set xrange [0:" << g(fmax) << "]\nset key top right\n";
  // Spindle harmonics dotted, tooth-passing harmonics dashed.
  int obj = 1;
  for (int h = 1; h * det.spindle_hz <= fmax && h < 400; ++h) {
    const bool tp = det.tooth_passing_hz > 0 && std::abs(std::remainder(h * det.spindle_hz, det.tooth_passing_hz)) < 1e-6 * det.tooth_passing_hz;
    s << "set arrow " << obj++ << " from " << g(h * det.spindle_hz) << ", graph 0 to " << g(h * det.spindle_hz)
      << ", graph 1 nohead back " << (tp ? "dt 2 lw 1.5 lc rgb '#2ca02c'" : "dt 3 lw 1 lc rgb '#b0b0b0'") << "\n";
  }
  s << "set label 1 " << gnuplot_quote("tooth passing " + g(det.tooth_passing_hz, 6) + " Hz") << " at "
    << g(det.tooth_passing_hz) << ", graph 0.97 left offset 0.5,0 tc rgb '#2ca02c' font ','.(fs-2)\n";
  if (det.chatter)
    s << "set arrow " << obj++ << " from " << g(det.chatter_frequency_hz) << ", graph 0 to "
      << g(det.chatter_frequency_hz) << ", graph 1 nohead front lw 2 lc rgb '#d62728'\n"
      << "set label 2 " << gnuplot_quote("chatter " + g(det.chatter_frequency_hz, 6) + " Hz") << " at "
      << g(det.chatter_frequency_hz) << ", graph 0.9 left offset 0.5,0 tc rgb '#d62728' font ','.(fs+1)\n";
  s << "plot data using 1:2 with lines lw 1 lc rgb '#1f77b4' title "
    << gnuplot_quote(det.chatter ? "spectrum: CHATTER" : "spectrum: no chatter") << "\n";
  return render(f, d.str(), s.str());
}

}  // namespace chatter
