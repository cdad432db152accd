// `chatter fit`: modal identification from a measured FRF file (issue 7).
// Reads a CSV, tab `.frf` or UFF 58/58b file (include/chatter/io/frf.hpp),
// fits modes to each direct term (include/chatter/modal_fit.hpp), prints
// them with the fit error and writes a config fragment ([[tool.modes]] ...)
// the config loader accepts; optionally plots measured against fitted FRF.
// Reference: docs/frf.md.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/frf.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/io/modes_toml.hpp"
#include "chatter/modal_fit.hpp"
#include "chatter/records/shop.hpp"
#include "cli_common.hpp"
#include "commands.hpp"

namespace chatter::cli {
namespace {

namespace fs = std::filesystem;

const char* const kFitUsage = R"(Usage: chatter fit FRF-FILE [options] --out modes.toml

Identifies modes (natural frequency, damping ratio, stiffness) from a measured
frequency response function (a tap test) and writes them as a config fragment
that lobes, point, check, sdm and time-domain runs can use.

FRF-FILE holds one direct term (xx or yy) of a receptance, or several records
(UFF):
  .csv                 frequency_hz, real, imag per line (one header line allowed),
                       or the table of chatter frf --out (pick the term with
                       --term; default relative_xx)
  .frf, .tab, .txt     tab-separated frequency, real, imaginary after any header
  .uff, .unv, .58      Universal File dataset 58 / 58b: every FRF record is
                       fitted, one fit per record (or pick one with --record);
                       cross terms (response X, reference Y) are skipped
Values are receptance in m/N unless --quantity and --scale say otherwise
(UFF: as the record says). A 0 Hz line of mobility or accelerance is dropped.

Peak picking gives starting values; Levenberg-Marquardt then fits the complex
FRF over the band. For each record it prints the modes, the fit error
(relative RMS of G_fit - G_measured over the band: 0.02 means 2 %, about the
noise of a good tap test; above ~0.1 the modes do not describe the data: adjust
--band or --modes) and the iterations used.

The output file holds [[tool.modes]] (or [[workpiece.modes]]) blocks: paste
them into a config, or append a config's [process] table to the file.
The stiffness is along the measured direction: fit the xx term with
--direction x, the yy term with --direction y.

Examples:
  chatter fit tap_xx.csv --out tool_modes.toml
  chatter fit tap.uff --band 400 1500 --modes 2 --out tool_modes.toml --plot fit.png
  chatter fit tap_yy.frf --scale 1e-6 --direction y --body workpiece --out wp.toml
)";

std::string g(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

// Phase in degrees, wrapped to (-270, 90] so a receptance (0 .. -180) does
// not jump at -180.
double phase_deg(Complex z) {
  double p = std::arg(z) * 180.0 / std::numbers::pi;
  if (p > 90.0) p -= 360.0;
  return p;
}

std::string gp_quote(const std::string& s) { return gnuplot_quote(s); }

// The plot's data and script (measured points and fitted curve of every
// record: magnitude over phase), named after the image like plot.hpp does.
std::pair<std::string, std::string> plot_files(const fs::path& image, const std::string& file,
                                               const std::vector<FittedRecord>& jobs) {
  const ImageFormat format = check_plot_path(image);
  fs::path dat = image, gp = image;
  dat.replace_extension(".dat");
  gp.replace_extension(".gp");
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& j : jobs) {
    lo = std::min(lo, j.fit.f_min_hz);
    hi = std::max(hi, j.fit.f_max_hz);
  }
  const double pad = 0.03 * (hi - lo);
  lo = std::max(0.0, lo - pad);
  hi += pad;

  std::ostringstream d;
  d << "# chatter fit (chatter " << version() << "): measured and fitted receptance\n"
    << "# Two data sets per record (gnuplot index 2r: measured lines, 2r+1: fitted model over the band).\n";
  for (std::size_t r = 0; r < jobs.size(); ++r) {
    if (r) d << "\n\n";
    d << "# " << jobs[r].label << ": measured\n# frequency_hz abs_m_per_n phase_deg real_m_per_n imag_m_per_n\n";
    const FrfTable& t = jobs[r].table;
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (t.frequency_hz[i] < lo || t.frequency_hz[i] > hi) continue;
      const Complex z = t.value[i];
      d << g(t.frequency_hz[i], 10) << ' ' << g(std::abs(z), 10) << ' ' << (std::abs(z) > 0 ? g(phase_deg(z), 8) : "?")
        << ' ' << g(z.real(), 10) << ' ' << g(z.imag(), 10) << '\n';
    }
    d << "\n\n# " << jobs[r].label << ": fitted\n# frequency_hz abs_m_per_n phase_deg real_m_per_n imag_m_per_n\n";
    const int n = 2000;
    for (int i = 0; i <= n; ++i) {
      const double f = jobs[r].fit.f_min_hz + (jobs[r].fit.f_max_hz - jobs[r].fit.f_min_hz) * i / n;
      const Complex z = jobs[r].fit.receptance(f);
      if (!std::isfinite(std::abs(z))) continue;
      d << g(f, 10) << ' ' << g(std::abs(z), 10) << ' ' << (std::abs(z) > 0 ? g(phase_deg(z), 8) : "?") << ' '
        << g(z.real(), 10) << ' ' << g(z.imag(), 10) << '\n';
    }
  }

  std::ostringstream s;
  s << "# Measured vs fitted FRF, written by chatter " << version() << " (chatter fit).\n"
    << "# Reproduce or restyle: cd into this directory, edit, then run\n"
    << "#   gnuplot " << gp.filename().string() << "\n"
    << "# It reads " << dat.filename().string() << " and writes " << image.filename().string()
    << " (both by relative name).\n\n"
    << "fs = " << (format == ImageFormat::pdf ? 10 : 14) << "\n";
  s << fixed_size_terminal(format);
  s << "set output " << gp_quote(image.filename().string()) << "\n"
    << "set encoding utf8\nset datafile missing '?'\n"
    << "data = " << gp_quote(dat.filename().string()) << "\n"
    << "# Record r: measured points in a light shade, the fitted model in the full colour\n"
    << "colours = \"#1f77b4 #d62728 #2ca02c #9467bd #ff7f0e #8c564b\"\n"
    << "lights = \"#8fbbd9 #eb9394 #96d096 #c9b3de #ffbf87 #c5aba5\"\n"
    << "colour(r) = word(colours, (r % 6) + 1)\n"
    << "light(r) = word(lights, (r % 6) + 1)\n\n"
    << "set multiplot title " << gp_quote("Modal fit: " + fs::path(file).filename().string())
    << " noenhanced font ','.(fs+3)\n"
    << "set lmargin at screen 0.11; set rmargin at screen 0.975\n"
    << "set border lw 1 lc rgb '#404040'\n"
    << "set grid xtics ytics mxtics mytics back lw 1 lc rgb '#c8c8c8', lw 0.5 lc rgb '#e4e4e4'\n"
    << "set xrange [" << g(lo, 10) << ":" << g(hi, 10) << "]\nset mxtics 2\n"
    << "set key at screen 0.54, screen 0.9 center center horizontal samplen 2 font ','.(fs-1) noenhanced\n";
  auto plot = [&](int column) {
    std::ostringstream p;
    p << "plot";
    for (std::size_t r = 0; r < jobs.size(); ++r) {
      const std::string who = jobs.size() > 1 ? jobs[r].name + " " : "";
      const std::string c = "lc rgb colour(" + std::to_string(r) + ")";
      p << (r ? ", \\\n  " : " \\\n  ") << "data index " << 2 * r << " using 1:" << column
        << " with points pt 7 ps 0.6 lc rgb light(" << r << ") title " << gp_quote(who + "measured")
        << ", \\\n  data index " << 2 * r + 1 << " using 1:" << column
        << " with lines lw 2.5 " << c << " title "
        << gp_quote(who + "fit, " + std::to_string(jobs[r].fit.modes.size()) + " mode(s), error " +
                    g(100 * jobs[r].fit.fit_error, 3) + " %");
    }
    return p.str() + "\n";
  };
  s << "\n# Upper panel: magnitude\n"
    << "set tmargin at screen 0.86; set bmargin at screen 0.515\n"
    << "set format x ''; unset xlabel\n"
    << "set logscale y\nset format y '10^{%L}'\nset mytics 10\nset ylabel 'magnitude |G| (m/N)'\n"
    << plot(2)
    << "\n# Lower panel: phase\nunset key\n"
    << "set tmargin at screen 0.465; set bmargin at screen 0.10\n"
    << "set format x '%g'\nset xlabel 'frequency (Hz)'\n"
    << "unset logscale y\nset format y '%g'\nset ytics 45\nset mytics 3\nset ylabel 'phase (deg)'\n"
    << plot(3) << "unset multiplot\n";
  return {d.str(), s.str()};
}

}  // namespace

namespace {

// Reads and checks every option (nothing is read or written before this
// returns). Returns false when --help was asked (the usage is printed).
bool parse_fit_args(const std::vector<std::string>& args, FitArgs& a, std::string& out, std::string& plot,
                    std::string& json_path) {
  std::string file;
  po::options_description d("Options");
  d.add_options()
      ("format", po::value<std::string>(&a.format),
       "csv, tab or uff (default: from the extension: .csv; .frf, .tab, .txt; .uff, .unv, .58)")
      ("quantity", po::value<std::string>(&a.quantity),
       "what the file's values are: receptance (m/N), mobility ((m/s)/N) or accelerance ((m/s^2)/N) "
       "(default: receptance; UFF: as each record says)")
      ("scale", po::value<double>(&a.scale)->default_value(1.0),
       "factor from the file's unit to SI: 1e-6 for um/N, 1e-3 for mm/N or (mm/s^2)/N")
      ("term", po::value<std::string>(&a.term),
       "a table written by chatter frf --out: the term to fit, tool_xx, tool_yy, workpiece_xx, workpiece_yy, "
       "relative_xx or relative_yy (default: relative_xx, what the lobes use)")
      ("record", po::value<int>(),
       "UFF: fit only this FRF record (1-based, counting FRF records only; default: every record, one fit each)")
      ("modes", po::value<int>(), "number of modes to fit (>= 1) in the band: the N highest resonance peaks")
      ("auto", "fit every resonance peak at least 5 % of the highest (the default)")
      ("band", po::value<std::vector<double>>()->multitoken(),
       "FMIN FMAX: fit only the lines in [FMIN, FMAX] Hz (default: every line); put it after FRF-FILE")
      ("residuals", "also fit residual terms for modes outside the band (use when --band cuts next to other modes)")
      ("body", po::value<std::string>(&a.body)->default_value("tool"),
       "which body the modes belong to in the output: tool or workpiece")
      ("direction", po::value<std::string>(&a.direction),
       "direction of the measured term: x (xx term), y (yy term) or \"[ux,uy]\" (default: x; UFF: the record's "
       "response direction, +Y -> y)")
      ("out", po::value<std::string>(&out)->required(), "write the modes as a config fragment (TOML) here (required)")
      ("json", po::value<std::string>(&json_path),
       "also write the fit's record (modes, fit errors, warnings, the fragment) as JSON ('-': standard output, the "
       "report then goes to standard error)")
      ("plot", po::value<std::string>(&plot),
       "draw measured vs fitted magnitude and phase to this .png, .svg or .pdf (script and data beside it)");
  po::options_description hidden;
  hidden.add_options()("frf-file", po::value<std::string>(&file), "FRF file");
  po::options_description all;
  all.add(d).add(hidden);
  all.add_options()("help,h", "show this help");
  po::positional_options_description pos;
  pos.add("frf-file", 1);
  po::variables_map vm;
  store_command_line(args, all, pos, vm);
  if (vm.count("help")) {
    std::cout << kFitUsage << "\n" << d << "  -h [ --help ]            show this help\n";
    return false;
  }
  if (!vm.count("frf-file")) throw po::error("missing FRF-FILE (a .csv, .frf or .uff file of a tap test)");
  po::notify(vm);
  a.file = file;
  a.fragment_name = out;
  if (vm.count("record")) a.record = vm["record"].as<int>();
  if (vm.count("modes")) a.modes = vm["modes"].as<int>();
  if (vm.count("auto") && a.modes) throw InputError("--modes and --auto: give one of them");
  a.residuals = vm.count("residuals") > 0;
  if (vm.count("band")) {
    const auto& b = vm["band"].as<std::vector<double>>();
    if (b.size() != 2)
      throw InputError("--band: give two frequencies FMIN FMAX in Hz, got " + std::to_string(b.size()) + " value(s)");
    a.band = std::pair{b[0], b[1]};
  }
  check_fit_args(a, ArgStyle::kFlag);
  check_outputs({{"--out", out}, {"--json", json_path == "-" ? "" : json_path}, {"--plot", plot, true}});  // before reading or fitting
  return true;
}

// Never overwrite the measurement, nor one output with another.
// @throws InputError naming both uses of a path.
void refuse_colliding_paths(const std::vector<std::pair<fs::path, std::string>>& uses) {
  std::vector<fs::path> canon;
  for (const auto& u : uses) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(u.first, ec);
    canon.push_back(ec ? fs::absolute(u.first).lexically_normal() : c);
  }
  for (std::size_t i = 1; i < canon.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (canon[i] == canon[k])
        throw InputError(uses[i].first.string() + ": would be both " + uses[k].second + " and " + uses[i].second +
                         "; choose another name for --out or --plot");
}

}  // namespace

int cmd_fit(const std::vector<std::string>& args) {
  FitArgs a;
  std::string out, plot, json_path;
  if (!parse_fit_args(args, a, out, plot, json_path)) return 0;
  const FitReport r = fit_frf_file(a, ArgStyle::kFlag);

  // ---- write (all or nothing), then render ----
  std::vector<std::pair<fs::path, std::string>> files{{out, r.fragment}};
  std::vector<std::pair<fs::path, std::string>> uses{{a.file, "the FRF file being fitted"}, {out, "--out"}};
  if (!json_path.empty() && json_path != "-") {
    files.emplace_back(json_path, fit_record(r).dump(2) + "\n");
    uses.emplace_back(json_path, "--json");
  }
  fs::path image, script, data;
  if (!plot.empty()) {
    image = plot;
    script = image;
    script.replace_extension(".gp");
    data = image;
    data.replace_extension(".dat");
    auto [dat_text, gp_text] = plot_files(image, a.file.string(), r.records);
    files.emplace_back(data, std::move(dat_text));
    files.emplace_back(script, std::move(gp_text));
    uses.emplace_back(data, "the --plot data file");
    uses.emplace_back(script, "the --plot gnuplot script");
    uses.emplace_back(image, "the --plot image");
  }
  refuse_colliding_paths(uses);
  write_text_files(files);
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << r.report;
  for (const auto& w : r.warnings) os << "warning: " << w << "\n";
  os << "wrote modes: " << out << " ([[" << r.body << ".modes]])\n";
  if (json_path == "-") std::cout << fit_record(r).dump(2) << "\n";
  if (!plot.empty()) {
    render_gnuplot_image(script, image);
    os << "wrote plot: " << image.string() << " (gnuplot script " << script.string() << ", data "
       << data.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
