// The plot of `chatter program` (include/chatter/io/plot_program.hpp).
#include "chatter/io/plot_program.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;

std::string g(double x, int digits = 8) { return gnuplot_number(x, digits); }

// Margins above this are drawn at it (an unbounded limit, or a deep reserve).
constexpr double kMarginTop = 4.0;

double shown_margin(double m) { return std::isfinite(m) ? std::min(m, kMarginTop) : kMarginTop; }

PlotFiles draw_program(PlotWindow* window, const fs::path& image, const ProgramPlotData& d) {
  const ImageFormat format = window ? ImageFormat::png : check_plot_path(image);
  const std::string where = (window ? std::string("live plot") : image.string()) + ": program: ";
  if (!window && (image.filename().empty() || image.stem().empty()))
    throw InputError(image.string() + ": not an image file name");
  if (std::none_of(d.blocks.begin(), d.blocks.end(), [](const auto& b) { return !b.air; }))
    throw InputError(where + "no cutting block to plot");
  fs::path data = image, script = image;
  data.replace_extension(".dat");
  script.replace_extension(".gp");
  std::ostringstream dat;
  dat << "# " << d.title << ": program check (chatter " << version() << ")\n"
      << "# index 0: cutting blocks, two points each (start and end of the block in cutting time)\n"
      << "# t_s margin_shown power_kw depth_limit_mm depth_mm line\n";
  for (const auto& b : d.blocks) {
    if (b.air) continue;
    for (const double t : {b.t0_s, b.t1_s})
      dat << g(t) << ' ' << g(shown_margin(b.margin)) << ' ' << g(b.power_kw) << ' ' << g(b.depth_limit_mm) << ' '
          << g(b.depth_mm) << ' ' << b.line << '\n';
    dat << '\n';
  }
  dat << "\n\n# index 1: " << (d.turning ? "along the bar: position_mm margin_shown diametral_error_um line (every sample, one run per block)"
                                         : "toolpath from above: x_mm y_mm margin_shown line (one segment per block)")
      << "\n";
  for (const auto& b : d.blocks) {
    if (d.turning) {
      if (b.air) continue;
      for (const auto& [pos, margin, err] : b.along_bar)
        dat << g(pos) << ' ' << g(shown_margin(margin)) << ' ' << (std::isfinite(err) ? g(err) : "?") << ' ' << b.line << '\n';
      dat << '\n';
    } else {
      const double m = b.air ? kMarginTop : shown_margin(b.margin);
      dat << g(b.x0) << ' ' << g(b.y0) << ' ' << g(m) << ' ' << b.line << '\n'
          << g(b.x1) << ' ' << g(b.y1) << ' ' << g(m) << ' ' << b.line << "\n\n";
    }
  }
  bool overloaded = false;
  if (!d.turning) {
    dat << "\n\n# index 2: overloaded blocks from above: x_mm y_mm line\n";
    for (const auto& b : d.blocks)
      if (b.overloaded && !b.air) {
        overloaded = true;
        dat << g(b.x0) << ' ' << g(b.y0) << ' ' << b.line << '\n' << g(b.x1) << ' ' << g(b.y1) << ' ' << b.line << "\n\n";
      }
    if (!overloaded) dat << "? ? 0\n";  // an empty index would stop gnuplot
  }
  std::ostringstream gp;
  if (window)
    gp << live_script_head("Program check");
  else
    gp << "# Program check, written by chatter " << version() << ".\n# Reproduce or restyle: cd here and run gnuplot "
       << script.filename().string() << "\n\nfs = " << (format == ImageFormat::pdf ? 10 : 14) << "\n"
       << fixed_size_terminal(format) << "set output " << gnuplot_quote(image.filename().string()) << "\n"
       << "set encoding utf8\nset datafile missing '?'\ndata = " << gnuplot_quote(data.filename().string()) << "\n";
  gp << "set multiplot layout 2,1 title " << gnuplot_quote(d.title) << " noenhanced font ','.(fs+2)\n"
     << "set grid lc rgb '#c8c8c8'\nset key top right opaque box font ','.(fs-3)\n"
     << "set xlabel 'cutting time (s)'\nset ylabel 'margin = limit / depth'\nset yrange [0:" << g(kMarginTop * 1.05) << "]\n"
     << "set y2label 'spindle power (kW)'\nset y2tics\nset ytics nomirror\n"
     << "set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead lw 2 lc rgb '#c0392b' dt 2\n"
     << "plot data index 0 using 1:2 with lines lw 2.5 lc rgb '#1a4d80' title 'margin (limit / depth; 1 = chatter)', \\\n"
     << "  data index 0 using 1:3 axes x1y2 with lines lw 1.5 lc rgb '#e07b00' title 'power (kW)'";
  if (d.max_power_kw > 0.0) gp << ", \\\n  " << g(d.max_power_kw) << " axes x1y2 with lines dt 3 lc rgb '#e07b00' title 'machine power'";
  gp << "\nunset arrow 1\nunset y2tics\nunset y2label\nset ytics mirror\n";
  if (d.turning) {
    gp << "set xlabel 'position along the bar from the chuck (mm)'\nset ylabel 'margin'\nset y2label 'diametral error (um)'\n"
       << "set y2tics\nset ytics nomirror\n"
       << "set autoscale y\nset yrange [0:" << g(kMarginTop + 0.2) << "]\nset autoscale y2\n"
       << "plot data index 1 using 1:2 with linespoints pt 7 ps 0.4 lw 2 lc rgb '#1a4d80' title 'margin (each pass)', \\\n"
       << "  data index 1 using 1:3 axes x1y2 with linespoints pt 6 ps 0.4 lw 1.5 dt 2 lc rgb '#e07b00' title 'diametral error (um)', \\\n"
       << "  1 with lines dt 2 lw 2 lc rgb '#c0392b' title 'chatter'\n";
  } else {
    gp << "set autoscale xy\nset xlabel 'x (mm)'\nset ylabel 'y (mm)'\nset size ratio -1\nset cblabel 'margin'\nset cbrange [0:"
       << g(kMarginTop) << "]\n"
       << "set palette defined (0 '#7a0c0c', 0.9 '#d7301f', 1.0 '#fc8d59', 1.5 '#fee090', 2.5 '#91bfdb', 4 '#2c5aa0')\n"
       << "set key below\nplot "
       << (overloaded ? "data index 2 using 1:2 with lines lw 7 lc rgb '#90000000' title 'overloaded (power, torque or speed)', " : "")
       << "data index 1 using 1:2:3 with lines lw 2 lc palette title 'toolpath by margin (air = top colour)'\n";
  }
  gp << "unset multiplot\n";
  if (window) {
    window->draw(dat.str(), gp.str());
    return {};
  }
  write_text_files({{data, dat.str()}, {script, gp.str()}});
  render_gnuplot_image(script, image);
  return {image, script, data};
}

}  // namespace

PlotFiles plot_program(const ProgramPlotData& data, const fs::path& image) { return draw_program(nullptr, image, data); }

void plot_program(const ProgramPlotData& data, PlotWindow& window) { draw_program(&window, {}, data); }

}  // namespace chatter
