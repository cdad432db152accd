// Plots through gnuplot: a time-domain simulation (displacement, once per period, spectrum).
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

namespace {

// The .dat file: the time series (index 0), the once-per-period samples (1),
// the spectrum up to f_hi (2, floored at amp_floor for the log axis) and the
// tooth-passing harmonics (3).
std::string simulation_data(const std::string& title, const SimulationResult& r, double f_hi, double amp_floor) {
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": time-domain simulation (chatter " << version() << ")\n"
      << "# verdict: " << to_string(r.verdict) << " (" << one_line(r.verdict_measure) << ")\n"
      << "# Floquet period = " << num(r.floquet_period_s) << " s, tooth passing = " << num(r.tooth_passing_hz) << " Hz, periods = "
      << r.periods << ", analysed from period " << r.analysed_from_period << "\n"
      << "# Missing values are '?'.\n\n"
      << "# index 0: time series\n"
      << "# time_ms rel_x_um rel_y_um force_x_n force_y_n chip_um in_cut\n";
  for (const SeriesSample& s : r.series)
    dat << num(s.t_s * 1e3) << ' ' << num(s.rel_x_m * 1e6) << ' ' << num(s.rel_y_m * 1e6) << ' ' << num(s.force_x_n)
        << ' ' << num(s.force_y_n) << ' ' << num(s.chip_m * 1e6) << ' ' << (s.in_cut ? 1 : 0) << '\n';
  dat << "\n\n# index 1: once-per-period samples (t = k tau)\n# time_ms rel_x_um rel_y_um\n";
  for (const SeriesSample& s : r.once_per_period)
    dat << num(s.t_s * 1e3) << ' ' << num(s.rel_x_m * 1e6) << ' ' << num(s.rel_y_m * 1e6) << '\n';
  dat << "\n\n# index 2: amplitude spectrum of the relative displacement over the analysed window\n"
      << "# frequency_hz amplitude_um (floored at 1e-7 of the peak for the log axis)\n";
  for (std::size_t k = 0; k < r.spectrum_hz.size() && r.spectrum_hz[k] <= f_hi; ++k)
    dat << num(r.spectrum_hz[k]) << ' ' << num(std::max(r.spectrum_amplitude_m[k], amp_floor) * 1e6) << '\n';
  if (r.spectrum_hz.empty()) dat << "? ?\n";
  dat << "\n\n# index 3: tooth-passing harmonics\n# frequency_hz amplitude_um harmonic\n";
  int harmonics = 0;
  for (const SpectralPeak& h : r.harmonics)
    if (h.frequency_hz <= f_hi) {
      dat << num(h.frequency_hz) << ' ' << num(std::max(h.amplitude_m, amp_floor) * 1e6) << ' ' << h.harmonic << '\n';
      ++harmonics;
    }
  if (harmonics == 0) dat << "? ? ?\n";
  return dat.str();
}

// The third panel: the amplitude spectrum of the analysed window, the
// tooth-passing harmonics marked, the dominant non-harmonic labelled.
std::string spectrum_panel(const SimulationResult& r, double f_hi, double amp_floor, double amp_max) {
  const bool chatter = r.verdict == SimulationVerdict::kChatter;
  std::ostringstream os;
  os << "set offsets 0, 0, 0, 0\n"
     << "set xlabel 'frequency (Hz)' offset 0,0.4\n"
     << "set ylabel 'amplitude ({/Symbol m}m)'\n"
     << "set logscale y\nset format y '10^{%L}'\n"
     << "set key top right vertical\n"
     << "set xrange [0:" << short_num(f_hi, 6) << "]\n"
     << "set yrange [" << short_num(amp_floor * 1e6 * 10, 4) << ":" << short_num(std::max(amp_max, 1e-300) * 1e6 * 300, 4)
     << "]   # headroom for the key\n";
  int arrows = 0;
  for (const SpectralPeak& h : r.harmonics)
    if (h.frequency_hz <= f_hi && arrows < 40) {
      os << "set arrow from " << short_num(h.frequency_hz, 8) << ", graph 0 to " << short_num(h.frequency_hz, 8)
         << ", graph 1 nohead dt 3 lw 0.8 lc rgb c_grid\n";
      ++arrows;
    }
  if (std::isfinite(r.dominant_nonharmonic_hz) && r.dominant_nonharmonic_hz <= f_hi) {
    const std::string what = chatter ? "chatter " : "least damped ";
    os << "set label " << quote(what + short_num(r.dominant_nonharmonic_hz, 4) + " Hz") << " at "
       << short_num(r.dominant_nonharmonic_hz, 8) << ", graph 0.62 left offset 0.6,0 tc rgb c_sample font ','.(fs-1)\n"
       << "set arrow from " << short_num(r.dominant_nonharmonic_hz, 8) << ", graph 0 to "
       << short_num(r.dominant_nonharmonic_hz, 8) << ", graph 1 nohead lw 1.2 lc rgb c_sample\n";
  }
  const int analysed = r.periods - r.analysed_from_period;
  os << "plot data index 2 using 1:2 with lines lc rgb c_spec lw 1 title "
     << quote("relative displacement, last " + std::to_string(analysed) + " periods") << ", \\\n"
     << "     data index 3 using 1:2 with points pt 6 ps 1.1 lw 1.2 lc rgb c_x title "
     << quote("harmonics of 1/{/Symbol t} = " + short_num(1.0 / r.floquet_period_s, 5) + " Hz (" + (std::abs(r.floquet_period_s * r.tooth_passing_hz - 1.0) < 1e-9 ? "tooth passing" : "Floquet period") + ")") << "\n"
     << "unset multiplot\n";
  return os.str();
}

void draw_simulation(const Target& t, const std::string& title, const SimulationResult& r, double f_max_hz,
                     const PlotOptions& options, bool running) {
  const std::string where = t.label + ": simulation: ";
  if (r.series.size() < 2)
    throw InputError(where + "no time series to draw (simulate with record_series)");
  if (!(std::isfinite(f_max_hz) && f_max_hz > 0.0))
    throw InputError(where + "highest natural frequency " + short_num(f_max_hz) + " Hz: must be > 0");

  bool moves_y = false;
  double peak_x = 0.0, peak_y = 0.0;
  for (const SeriesSample& s : r.series) {
    peak_x = std::max(peak_x, std::abs(s.rel_x_m));
    peak_y = std::max(peak_y, std::abs(s.rel_y_m));
  }
  moves_y = peak_y > 1e-3 * peak_x && peak_y > 0.0;
  bool force_y = false;
  {
    double fx = 0.0, fy = 0.0;
    for (const SeriesSample& s : r.series) {
      fx = std::max(fx, std::abs(s.force_x_n));
      fy = std::max(fy, std::abs(s.force_y_n));
    }
    force_y = fy > 1e-3 * fx && fy > 0.0;
  }
  const double f_hi = std::min(r.spectrum_hz.empty() ? 2.5 * f_max_hz : r.spectrum_hz.back(), 2.5 * f_max_hz);
  double amp_max = 0.0;
  for (std::size_t k = 1; k < r.spectrum_hz.size() && r.spectrum_hz[k] <= f_hi; ++k)
    amp_max = std::max(amp_max, r.spectrum_amplitude_m[k]);
  const double amp_floor = amp_max > 0.0 ? amp_max * 1e-7 : 1e-12;

  const std::string dat = simulation_data(title, r, f_hi, amp_floor);

  // --- script ---
  std::ostringstream gp;
  gp << script_preamble(t, options, "Time-domain simulation");
  const bool chatter = r.verdict == SimulationVerdict::kChatter;
  std::string head = title + ": " + to_string(r.verdict);
  if (chatter && std::isfinite(r.chatter_frequency_hz)) head += " at " + short_num(r.chatter_frequency_hz, 4) + " Hz";
  if (std::isfinite(r.growth_per_period)) head += ", |{/Symbol m}| = " + short_num(r.growth_per_period, 4);
  // A run still integrating has no verdict yet: its periods so far.
  if (running)
    head = title + ": integrating, " + std::to_string(r.once_per_period.size() - 1) + " of " +
           std::to_string(r.periods) + " periods";
  gp << "c_x = '" << kTool << "'\nc_y = '" << kWorkpiece << "'\nc_sample = '" << kAbsolute << "'\nc_spec = '"
     << kRelative << "'\nc_grid = '" << kGrid << "'\nc_label = '" << kLabel << "'\n"
     << "set grid lc rgb c_grid lw 0.6\n"
     << "set border lw 0.8\n"
     << "set key top left horizontal opaque box lc rgb c_grid font ','.(fs-2)\n"
     << "set multiplot layout " << (running ? 2 : 3) << ",1 title " << quote(head)
     << " font ','.(fs+2) margins 0.09,0.97,0.07,0.91 spacing 0,0.09\n"
     << "set offsets 0, 0, graph 0.28, graph 0.04   # room for the key above the curves\n"
     // A run still integrating is drawn on the time axis of the whole run: it grows across the window.
     << "set xrange [0:"
     << short_num((running ? r.periods * r.floquet_period_s : r.series.back().t_s) * 1e3, 8) << "]\n"
     << "set xlabel 'time (ms)' offset 0,0.4\n"
     << "set ylabel 'relative displacement ({/Symbol m}m)'\n"
     << "plot data index 0 using 1:2 with lines lc rgb c_x lw 1 title 'x (feed direction)'";
  if (moves_y) gp << ", \\\n     data index 0 using 1:3 with lines lc rgb c_y lw 1 title 'y'";
  gp << ", \\\n     data index 1 using 1:2 with points pt 7 ps 0.45 lc rgb c_sample title 'x once per "
     << (r.tooth_passing_hz > 0 && r.periods > 0 ? "period" : "period") << "'\n"
     << "set ylabel 'force on the tool (N)'\n"
     << "plot ";
  if (force_y) gp << "data index 0 using 1:5 with lines lc rgb c_y lw 1 title 'F_y', \\\n     ";
  gp << "data index 0 using 1:4 with lines lc rgb c_x lw 1 title 'F_x'\n";
  if (running) {  // no spectrum before the run ends
    gp << "unset multiplot\n";
    write_and_render(t, dat, gp.str());
    return;
  }
  gp << spectrum_panel(r, f_hi, amp_floor, amp_max);
  write_and_render(t, dat, gp.str());
}

}  // namespace

PlotFiles plot_simulation(const fs::path& image, const std::string& title, const SimulationResult& result,
                          double f_max_hz, const PlotOptions& options) {
  const Target t = make_target(image, options);
  draw_simulation(t, title, result, f_max_hz, options, false);
  return {t.image, t.script, t.data};
}

void plot_simulation(PlotWindow& window, const std::string& title, const SimulationResult& result, double f_max_hz,
                     bool running, const PlotOptions& options) {
  draw_simulation(live_target(window, options), title, result, f_max_hz, options, running);
}

}  // namespace chatter
