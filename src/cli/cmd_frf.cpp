// `chatter frf`: the receptance of the tool, the workpiece and the relative
// motion on a frequency grid, as a table and a plot (docs/frf.md).
#include <boost/program_options.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include <numbers>

#include "chatter/io/config.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"

namespace po = boost::program_options;

namespace chatter::cli {

int cmd_frf(const std::vector<std::string>& args) {
  Common common;
  std::string out_path, plot_path;
  int points = 1000;
  po::options_description d("Options");
  d.add_options()
      ("fmin", po::value<double>(), "lowest frequency, Hz (default: half the lowest natural frequency)")
      ("fmax", po::value<double>(), "highest frequency, Hz (default: twice the highest natural frequency)")
      ("points", po::value<int>(&points)->default_value(1000), "number of frequencies (>= 2)")
      ("log", "space the frequencies logarithmically (default: evenly)")
      ("out", po::value<std::string>(&out_path), "write the CSV here ('-': standard output; by default standard "
                                                 "output only when --plot is not given)")
      ("plot", po::value<std::string>(&plot_path), "draw magnitude and phase to this .png, .svg or .pdf (script and data beside it)")
      ("re-im", "with --plot: draw real and imaginary parts instead of magnitude and phase");
  po::variables_map vm;
  if (!parse(args, "Usage: chatter frf CONFIG [options]\n\n"
                   "Tabulates the receptance (m/N) of the tool, the workpiece and the relative motion\n"
                   "tool - workpiece (their sum): real and imaginary parts of the xx, xy and yy terms.\n"
                   "The lobes come from the relative receptance: compare it with a tap test.\n",
             d, common, vm))
    return 0;
  const bool table_to_stdout = out_path == "-" || (out_path.empty() && plot_path.empty());
  if (out_path == "-") out_path.clear();
  check_outputs({{"--out", out_path}, {"--plot", plot_path, true}});  // before computing
  const chatter::Config cfg = load_checked(common);
  const double f_lo_default = 0.5 * cfg.model.min_omega() / (2 * std::numbers::pi);
  const double f_hi_default = 2.0 * cfg.model.max_omega() / (2 * std::numbers::pi);
  const double fmin = vm.count("fmin") ? vm["fmin"].as<double>() : f_lo_default;
  const double fmax = vm.count("fmax") ? vm["fmax"].as<double>() : f_hi_default;
  const bool log_spacing = vm.count("log") > 0;
  if (!(std::isfinite(fmin) && (log_spacing ? fmin > 0.0 : fmin >= 0.0)))
    throw InputError("--fmin = " + fmt(fmin) + (log_spacing ? ": must be > 0 Hz with --log" : ": must be >= 0 Hz"));
  if (!(std::isfinite(fmax) && fmax > fmin))
    throw InputError("--fmax = " + fmt(fmax) + ": must be > --fmin (" + fmt(fmin) + ")");
  if (points < 2) throw InputError("--points = " + std::to_string(points) + ": must be >= 2");

  std::ostringstream os;
  os << "frequency_hz";
  for (const char* body : {"tool", "workpiece", "relative"})
    for (const char* term : {"xx", "xy", "yy"})
      os << ',' << body << '_' << term << "_real_m_per_n," << body << '_' << term << "_imag_m_per_n";
  os << '\n';
  char buf[40];
  auto put = [&](double x) {
    std::snprintf(buf, sizeof buf, ",%.10g", x);
    os << buf;
  };
  for (int i = 0; i < points; ++i) {
    const double t = static_cast<double>(i) / (points - 1);
    const double f = log_spacing ? fmin * std::pow(fmax / fmin, t) : fmin + (fmax - fmin) * t;
    const double w = 2 * std::numbers::pi * f;
    std::snprintf(buf, sizeof buf, "%.10g", f);
    os << buf;
    const chatter::Matrix2c gt = cfg.model.tool.receptance(w), gw = cfg.model.workpiece.receptance(w);
    const chatter::Matrix2c gr = gt + gw;
    for (const chatter::Matrix2c* g : {&gt, &gw, &gr})
      for (auto [r, c] : {std::pair{0, 0}, std::pair{0, 1}, std::pair{1, 1}}) {
        put((*g)(r, c).real());
        put((*g)(r, c).imag());
      }
    os << '\n';
  }
  if (table_to_stdout) std::cout << os.str();
  if (!out_path.empty()) {
    chatter::write_text_file(out_path, os.str());
    std::cout << "wrote receptance table (" << points << " frequencies, " << fmt(fmin) << "-" << fmt(fmax)
              << " Hz): " << out_path << "\n";
  }
  if (!plot_path.empty()) {
    chatter::PlotOptions po_;
    if (vm.count("re-im")) po_.frf_parts = chatter::FrfParts::real_imaginary;
    const auto files = chatter::plot_frf(plot_path, cfg.name, cfg.model, fmin, fmax, points, log_spacing, po_);
    (table_to_stdout ? std::cerr : std::cout) << "wrote plot: " << files.image.string() << " (gnuplot script "
                                               << files.script.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
