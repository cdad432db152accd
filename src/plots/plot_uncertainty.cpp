// The uncertain-lobes plot (include/chatter/io/plot_uncertainty.hpp).
#include "chatter/io/plot_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/io/table_writer.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;

std::string g(double x, int digits = 8) { return gnuplot_number(x, digits); }

// The line colours of the quantile lobes, lowest level first.
constexpr const char* kQuantileColours[] = {"#6a00a8", "#e6a800", "#00796b", "#b35806", "#4d4d4d"};

}  // namespace

namespace {

// The plot to image files, or (window) to a live window.
PlotFiles draw_uncertain_lobes(PlotWindow* window, const fs::path& image, const std::string& title,
                               const UncertainLobes& lobes, const std::vector<StabilityLimit>& nominal,
                               double depth_max_mm, double depth_axis_mm) {
  const ImageFormat format = window ? ImageFormat::png : check_plot_path(image);
  const std::string where = (window ? std::string("live plot") : image.string()) + ": uncertain lobes: ";
  if (!window && (image.filename().empty() || image.stem().empty()))
    throw InputError(image.string() + ": not an image file name");
  const std::size_t ns = lobes.speeds_rpm.size(), nd = lobes.depths_m.size();
  if (ns < 2 || nd < 2 || lobes.probability_stable.size() != ns || nominal.size() != ns)
    throw InputError(where + "needs >= 2 speeds and depths, a probability row and a nominal limit per speed");
  for (std::size_t s = 0; s < ns; ++s)
    if (lobes.probability_stable[s].size() != nd || nominal[s].spindle_rpm != lobes.speeds_rpm[s])
      throw InputError(where + "the nominal lobe and the probabilities must share the speeds and depths");
  for (const auto& q : lobes.quantile_depth_m)
    if (q.size() != ns) throw InputError(where + "every quantile lobe needs one depth per speed");
  if (!(std::isfinite(depth_max_mm) && depth_max_mm > 0.0 && std::isfinite(depth_axis_mm) && depth_axis_mm > 0.0))
    throw InputError(where + "depth_max_mm and the depth axis must be > 0");
  fs::path data = image, script = image;
  data.replace_extension(".dat");
  script.replace_extension(".gp");
  auto shown_mm = [&](double depth_m) { return std::min(depth_m * 1e3, depth_max_mm); };  // +inf at the top

  std::string one_line_title = title;
  std::replace(one_line_title.begin(), one_line_title.end(), '\n', ' ');
  std::ostringstream dat;
  dat << "# " << one_line_title << ": uncertain lobes (chatter " << version() << ")\n"
      << "# " << ns << " spindle speeds x " << nd << " depths.\n\n"
      << "# index 0: probability of stability, one block per speed (blocks separated by one blank line).\n"
      << "# spindle_rpm depth_mm probability_stable\n";
  for (std::size_t s = 0; s < ns; ++s) {
    if (s > 0) dat << '\n';
    for (std::size_t d = 0; d < nd; ++d)
      dat << g(lobes.speeds_rpm[s], 10) << ' ' << g(lobes.depths_m[d] * 1e3, 10) << ' '
          << g(lobes.probability_stable[s][d], 10) << '\n';
  }
  dat << "\n\n# index 1: the lobes, depth limits in mm (" << g(depth_max_mm)
      << " = no chatter below the searched depth)\n# spindle_rpm nominal_mm";
  for (const double q : lobes.levels) dat << " p" << g(100.0 * q) << "_mm";
  dat << '\n';
  for (std::size_t s = 0; s < ns; ++s) {
    dat << g(lobes.speeds_rpm[s], 10) << ' ' << g(shown_mm(nominal[s].depth_limit_m), 7);
    for (const auto& q : lobes.quantile_depth_m) dat << ' ' << g(shown_mm(q[s]), 7);
    dat << '\n';
  }

  std::ostringstream gp;
  if (window)
    gp << live_script_head("Uncertain lobes: probability of stability over spindle speed and depth");
  else
    gp << "# Uncertain lobes: probability of stability over spindle speed and depth, with quantile lobes,\n"
       << "# written by chatter " << version() << ".\n# Reproduce or restyle: cd into this directory, edit, then run\n"
       << "#   gnuplot " << script.filename().string() << "\n# It reads " << data.filename().string()
       << " and writes " << image.filename().string() << ".\n\n"
       << "fs = " << (format == ImageFormat::pdf ? 10 : 14) << "\n"
       << fixed_size_terminal(format) << "set output " << gnuplot_quote(image.filename().string()) << "\n"
       << "set encoding utf8\ndata = " << gnuplot_quote(data.filename().string()) << "\n";
  gp << "set title " << gnuplot_quote(one_line_title) << " noenhanced font ','.(fs+2)\n"
     << "set xlabel 'spindle speed (rev/min)'\nset ylabel 'depth of cut (mm)'\n"
     << "set cblabel 'probability of stability'\n"
     << "set xrange [" << g(lobes.speeds_rpm.front(), 10) << ":" << g(lobes.speeds_rpm.back(), 10) << "]\n"
     << "set yrange [0:" << g(depth_axis_mm) << "]\nset cbrange [0:1]\n"
     << "set palette defined (0 '#b2182b', 0.5 '#fddbc7', 0.5 '#d1e5f0', 1 '#2166ac')\n"
     << "set key top right opaque box font ','.(fs-2)\nset tics front\nset border front\n"
     << "plot data index 0 using 1:2:3 with image notitle";
  for (std::size_t l = 0; l < lobes.levels.size(); ++l) {
    const double q = lobes.levels[l];
    gp << ", \\\n  data index 1 using 1:" << 3 + l << " with lines lw 2 dt " << (l % 2 == 0 ? 2 : 1) << " lc rgb '"
       << kQuantileColours[l % std::size(kQuantileColours)] << "' title '" << g(100.0 * (1.0 - q))
       << " % of samples stable below'";
  }
  gp << ", \\\n  data index 1 using 1:2 with lines lw 2.5 lc rgb '#000000' title 'nominal lobe'\n";

  if (window) {
    window->draw(dat.str(), gp.str());
    return {};
  }
  write_text_files({{data, dat.str()}, {script, gp.str()}});
  render_gnuplot_image(script, image);
  return {image, script, data};
}

}  // namespace

PlotFiles plot_uncertain_lobes(const fs::path& image, const std::string& title, const UncertainLobes& lobes,
                               const std::vector<StabilityLimit>& nominal, double depth_max_mm, double depth_axis_mm) {
  return draw_uncertain_lobes(nullptr, image, title, lobes, nominal, depth_max_mm, depth_axis_mm);
}

void plot_uncertain_lobes(PlotWindow& window, const std::string& title, const UncertainLobes& lobes,
                          const std::vector<StabilityLimit>& nominal, double depth_max_mm, double depth_axis_mm) {
  draw_uncertain_lobes(&window, {}, title, lobes, nominal, depth_max_mm, depth_axis_mm);
}

}  // namespace chatter
