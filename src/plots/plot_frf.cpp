// Plots through gnuplot: the receptance (FRF) of the structural model.
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
// Receptance (FRF)

namespace {

// A term of the receptance matrix: its name and diagonal index.
struct Term {
  const char* name;
  int index;
};

// The .dat file: per frequency, each body's and the relative receptance of
// each term (magnitude, phase, real, imaginary; '?' for a rigid body).
std::string frf_data(const std::string& title, const StructuralModel& model, double f_min_hz, double f_max_hz,
                     int points, bool log_frequency, const std::vector<Term>& terms) {
  const char* bodies[] = {"tool", "workpiece", "relative"};
  const bool tool_flex = !model.tool.rigid(), work_flex = !model.workpiece.rigid();
  std::ostringstream dat;
  dat << "# " << one_line(title) << ": receptance (chatter " << version() << ")\n"
      << "# Relative receptance = tool + workpiece (docs/physics.md section 2). '?' = rigid body (no value).\n"
      << "# Per body and term: magnitude (m/N), phase (deg), real and imaginary parts (m/N).\n"
      << "# frequency_hz";
  for (const auto& term : terms)
    for (const char* body : bodies)
      dat << ' ' << body << '_' << term.name << "_abs_m_per_n " << body << '_' << term.name << "_phase_deg "
          << body << '_' << term.name << "_real_m_per_n " << body << '_' << term.name << "_imag_m_per_n";
  dat << '\n';
  for (int i = 0; i < points; ++i) {
    const double s = static_cast<double>(i) / (points - 1);
    const double f = log_frequency ? f_min_hz * std::pow(f_max_hz / f_min_hz, s) : f_min_hz + (f_max_hz - f_min_hz) * s;
    const double w = 2 * std::numbers::pi * f;
    const Matrix2c gt = model.tool.receptance(w), gw = model.workpiece.receptance(w);
    const Matrix2c gr = gt + gw;
    dat << num(f);
    for (const auto& term : terms) {
      const Matrix2c* g[] = {&gt, &gw, &gr};
      const bool flex[] = {tool_flex, work_flex, true};
      for (int b = 0; b < 3; ++b) {
        const Complex z = (*g[b])(term.index, term.index);
        if (!flex[b] || std::abs(z) == 0.0) {
          dat << " ? ? ? ?";
          continue;
        }
        dat << ' ' << num(std::abs(z)) << ' ' << num(std::arg(z) * 180.0 / std::numbers::pi) << ' ' << num(z.real())
            << ' ' << num(z.imag());
      }
    }
    dat << '\n';
  }
  return dat.str();
}

// The frequency axis's scale and tics (Hz): on a log axis spanning less than
// two decades, labels at 1-2-3-5 steps, not just the decades.
std::string frequency_axis(double f_min_hz, double f_max_hz, bool log_frequency) {
  std::ostringstream os;
  if (log_frequency) {
    os << "set logscale x\nset mxtics 10\n";
    if (f_max_hz / f_min_hz < 100.0) {
      std::string tics;
      for (double p = std::pow(10.0, std::floor(std::log10(f_min_hz))); p <= f_max_hz; p *= 10.0)
        for (double m : {1.0, 2.0, 3.0, 5.0})
          if (m * p >= f_min_hz * (1 - 1e-9) && m * p <= f_max_hz * (1 + 1e-9))
            tics += (tics.empty() ? "" : ", ") + short_num(m * p, 6);
      if (!tics.empty()) os << "set xtics (" << tics << ")\n";
    }
  }
  else
    os << "set mxtics 2\n";
  return os.str();
}

// One plot command over the bodies and terms for part p (0 magnitude,
// 1 phase, 2 real, 3 imaginary).
std::string frf_plot_command(const std::vector<Term>& terms, int p, bool has_y, bool tool_flex, bool work_flex) {
  PlotCommand pl;
  auto add = [&](const std::string& clause) { pl.add(clause); };
  for (std::size_t ti = 0; ti < terms.size(); ++ti) {
    const std::string tn = terms[ti].name;
    const std::string dash = ti == 0 ? "" : " dt (6,4)";
    const std::string suffix = has_y ? " " + tn : "";
    const int bs[] = {2, 1, 0};  // relative first (underneath), bodies on top
    for (int b : bs) {
      if ((b == 0 && !tool_flex) || (b == 1 && !work_flex)) continue;
      const char* colour = b == 0 ? "c_tool" : b == 1 ? "c_workpiece" : "c_relative";
      const std::string lw = b == 2 ? "3.2" : "1.6";
      const std::string name = b == 0 ? "tool" : b == 1 ? "workpiece" : "relative = tool + workpiece";
      const std::string column =
          "col(" + std::to_string(b) + "," + std::to_string(ti) + "," + std::to_string(p) + ")";
      add("data using 1:" + (p >= 2 ? "(column(" + column + ") * 1e6)" : column) + " with lines lw " + lw +
          dash + " lc rgb " + colour + " title " + quote(name + suffix));
    }
  }
  if (!tool_flex) add("keyentry with lines lt nodraw title 'tool: rigid'");
  if (!work_flex) add("keyentry with lines lt nodraw title 'workpiece: rigid'");
  return pl.str() + "\n";
}

}  // namespace

PlotFiles plot_frf(const fs::path& image, const std::string& title, const StructuralModel& model, double f_min_hz,
                   double f_max_hz, int points, bool log_frequency, const PlotOptions& options) {
  const Target t = make_target(image, options);
  if (!(std::isfinite(f_min_hz) && (log_frequency ? f_min_hz > 0.0 : f_min_hz >= 0.0)))
    throw InputError(image.string() + ": f_min = " + short_num(f_min_hz) + " Hz: must be " +
                     (log_frequency ? "> 0 with a log frequency axis" : ">= 0"));
  if (!(std::isfinite(f_max_hz) && f_max_hz > f_min_hz))
    throw InputError(image.string() + ": f_max = " + short_num(f_max_hz) + " Hz: must be > f_min (" +
                     short_num(f_min_hz) + " Hz)");
  if (points < 2) throw InputError(image.string() + ": points = " + std::to_string(points) + ": must be >= 2");
  if (model.rigid()) throw InputError(image.string() + ": the model has no mode (both bodies rigid)");

  bool has_y = false;
  for (const Body* b : {&model.tool, &model.workpiece})
    for (const Mode& m : b->modes)
      if (std::abs(m.direction.y()) > 1e-12) has_y = true;
  const bool tool_flex = !model.tool.rigid(), work_flex = !model.workpiece.rigid();

  std::vector<Term> terms = {{"xx", 0}};
  if (has_y) terms.push_back({"yy", 1});

  const std::string dat = frf_data(title, model, f_min_hz, f_max_hz, points, log_frequency, terms);

  // --- script ---
  const bool mag_phase = options.frf_parts == FrfParts::magnitude_phase;
  std::ostringstream gp;
  gp << script_preamble(t, options, "Receptance (FRF) chart") << "# Colours\n"
     << "c_tool = " << quote(kTool) << "; c_workpiece = " << quote(kWorkpiece) << "; c_relative = "
     << quote(kRelative) << "\n"
     << "# Column of body b (0 tool, 1 workpiece, 2 relative), term t (0 xx, 1 yy), part p\n"
     << "# (0 magnitude, 1 phase, 2 real, 3 imaginary)\n"
     << "col(b, t, p) = 2 + 12*t + 4*b + p\n\n"
     << "set multiplot title " << quote(title) << " noenhanced font ','.(fs+3)\n"
     << "set lmargin at screen 0.11; set rmargin at screen 0.975\n"
     << "set border lw 1 lc rgb '#404040'\n"
     << "set grid xtics ytics mxtics mytics back lw 1 lc rgb " << quote(kGrid) << ", lw 0.5 lc rgb '#e4e4e4'\n"
     << "set xrange [" << short_num(f_min_hz, 10) << ":" << short_num(f_max_hz, 10) << "]\n";
  gp << frequency_axis(f_min_hz, f_max_hz, log_frequency);
  gp << "set key at screen 0.54, screen 0.9 center center horizontal reverse Left samplen 2 width -1 font ','.(fs-1)\n";

  const auto plot_part = [&](int p) { return frf_plot_command(terms, p, has_y, tool_flex, work_flex); };

  gp << "\n# Upper panel\n"
     << "set tmargin at screen 0.86; set bmargin at screen 0.515\n"
     << "set format x ''; unset xlabel\n";
  if (mag_phase)
    gp << "set logscale y\nset format y '10^{%L}'\nset mytics 10\nset ylabel 'magnitude |G| (m/N)'\n" << plot_part(0);
  else
    gp << "set format y '%g'\nset mytics 2\nset ylabel 'real part Re G (µm/N)'\n" << plot_part(2);
  gp << "\n# Lower panel\n"
     << "unset key\n"
     << "set tmargin at screen 0.465; set bmargin at screen 0.10\n"
     << "set format x '%g'\nset xlabel 'frequency (Hz)'\n";
  if (mag_phase)
    gp << "unset logscale y\nset format y '%g'\nset yrange [-180:0]\nset ytics 45\nset mytics 3\n"
       << "set ylabel 'phase (deg)'\n"
       << plot_part(1);
  else
    gp << "set format y '%g'\nset ylabel 'imaginary part Im G (µm/N)'\n" << plot_part(3);
  gp << "unset multiplot\n";
  write_and_render(t, dat, gp.str());
  return {t.image, t.script, t.data};
}

}  // namespace chatter
