// `chatter frf`: the receptance of the tool, the workpiece and the relative
// motion on a frequency grid, as a table and a plot (docs/frf.md). The grid
// and the table: frf_grid, receptance_table (chatter/records/lobes.hpp),
// shared with Python's chatter.frf.
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
#include "chatter/records/lobes.hpp"

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
  const std::optional<double> fmin = vm.count("fmin") ? std::optional<double>(vm["fmin"].as<double>()) : std::nullopt;
  const std::optional<double> fmax = vm.count("fmax") ? std::optional<double>(vm["fmax"].as<double>()) : std::nullopt;
  const chatter::FrfGrid grid = chatter::frf_grid(cfg.model, fmin, fmax, points, vm.count("log") > 0, chatter::ArgStyle::kFlag);
  const double fmin_hz = grid.fmin_hz, fmax_hz = grid.fmax_hz;
  const bool log_spacing = grid.log;
  std::ostringstream os;
  os << chatter::named_columns_csv(chatter::receptance_table(cfg.model, grid));
  if (table_to_stdout) std::cout << os.str();
  if (!out_path.empty()) {
    chatter::write_text_file(out_path, os.str());
    std::cout << "wrote receptance table (" << points << " frequencies, " << fmt(fmin_hz) << "-" << fmt(fmax_hz)
              << " Hz): " << out_path << "\n";
  }
  if (!plot_path.empty()) {
    chatter::PlotOptions po_;
    if (vm.count("re-im")) po_.frf_parts = chatter::FrfParts::real_imaginary;
    const auto files = chatter::plot_frf(plot_path, cfg.name, cfg.model, fmin_hz, fmax_hz, points, log_spacing, po_);
    (table_to_stdout ? std::cerr : std::cout) << "wrote plot: " << files.image.string() << " (gnuplot script "
                                               << files.script.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
