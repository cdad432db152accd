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
#include "../io/text.hpp"
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

struct FitArgs {
  std::string file, format, quantity, body = "tool", direction, out, plot, term;
  double scale = 1.0;
  std::optional<int> record, modes;
  bool auto_modes = false, residuals = false;
  std::optional<std::pair<double, double>> band;
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string format_from_extension(const fs::path& file) {
  const std::string ext = lower(file.extension().string());
  if (ext == ".csv") return "csv";
  if (ext == ".frf" || ext == ".tab" || ext == ".txt") return "tab";
  if (ext == ".uff" || ext == ".unv" || ext == ".58") return "uff";
  throw InputError(file.string() + ": cannot tell the format from the extension '" + file.extension().string() +
                   "': give --format csv, tab or uff");
}

// "x", "y", "[ux, uy]" or "ux,uy" -> unit vector.
Eigen::Vector2d parse_direction(const std::string& text) {
  const std::string t = lower(text);
  if (t == "x" || t == "+x") return {1.0, 0.0};
  if (t == "y" || t == "+y") return {0.0, 1.0};
  std::string s;
  for (char c : t)
    if (c != '[' && c != ']' && !std::isspace(static_cast<unsigned char>(c))) s += c;
  const std::size_t comma = s.find(',');
  auto number = [](const std::string& p, double& v) {
    const std::optional<double> x = detail::text::parse_double(p);
    if (!x || !std::isfinite(*x)) return false;
    v = *x;
    return true;
  };
  double ux = 0.0, uy = 0.0;
  if (comma == std::string::npos || !number(s.substr(0, comma), ux) || !number(s.substr(comma + 1), uy))
    throw InputError("--direction '" + text + "': use x, y or [ux,uy] (a vector in the X-Y plane)");
  const double n = std::hypot(ux, uy);
  if (!(n > 0.0) || !std::isfinite(n)) throw InputError("--direction '" + text + "': the vector must not be zero");
  return {ux / n, uy / n};
}

std::string direction_text(const Eigen::Vector2d& u) {
  if (u.x() == 1.0 && u.y() == 0.0) return "x";
  if (u.x() == 0.0 && u.y() == 1.0) return "y";
  std::string s = "[";  // appended piecewise: `"literal" + std::string` trips a GCC 12 -Wrestrict false positive
  s.append(fmt(u.x(), 6)).append(", ").append(fmt(u.y(), 6)).append("]");
  return s;
}

// UFF record 6 direction code as text: 1 +X, -2 -Y, ...
std::string uff_direction_text(int d) {
  static const char* const axes[] = {"?", "X", "Y", "Z", "RX", "RY", "RZ"};
  const int a = std::abs(d);
  if (a < 1 || a > 6) return std::to_string(d);
  return std::string(d < 0 ? "-" : "+") + axes[a];
}

// One table to fit, with what the output says about it.
struct Job {
  FrfTable table;
  std::string label;                  // "tap.csv" or "tap.uff record 2 (response 1 +X, reference 1 +X)"
  std::string name;                   // in the plot key: "" or "record 2"
  Eigen::Vector2d direction{1.0, 0.0};
};

// The header of the table `chatter frf --out` writes: frequency_hz, then
// <body>_<term>_real_m_per_n, <body>_<term>_imag_m_per_n for body tool,
// workpiece, relative and term xx, xy, yy.
constexpr std::string_view kFrfTableHeader = "frequency_hz,tool_xx_real_m_per_n,tool_xx_imag_m_per_n";

// True if `file` starts (after comment lines) with the header of `chatter frf`.
bool is_chatter_frf_table(const fs::path& file) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    const std::string_view t = detail::text::trim(line);
    if (t.empty() || t.front() == '#') continue;
    return t.substr(0, kFrfTableHeader.size()) == kFrfTableHeader;
  }
  return false;
}

// One term (--term, e.g. relative_xx) of a `chatter frf` table, scaled by
// opt.scale and converted from opt.quantity like the other readers.
// @throws InputError naming the file, line or --term.
FrfTable read_chatter_frf_term(const fs::path& file, const std::string& term, const FrfReadOptions& opt) {
  std::ifstream in(file);
  std::vector<std::string> header, f;
  std::size_t re = 0, im = 0;
  FrfTable t;
  t.source = file.string() + " (" + term + ")";
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string_view tl = detail::text::trim(line);
    if (tl.empty() || tl.front() == '#') continue;
    if (header.empty()) {
      detail::text::split_delimited(tl, ',', false, header);
      const auto at = [&](const std::string& name) {
        return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
      };
      re = at(term + "_real_m_per_n");
      im = at(term + "_imag_m_per_n");
      if (re >= header.size() || im >= header.size())
        throw InputError("--term '" + term + "': not a term of " + file.string() +
                         " (a chatter frf table: tool_xx, tool_yy, workpiece_xx, workpiece_yy, relative_xx, "
                         "relative_yy)");
      continue;
    }
    detail::text::split_delimited(tl, ',', false, f);
    const auto fr = f.empty() ? std::nullopt : detail::text::parse_double(f[0]);
    const auto vr = re < f.size() ? detail::text::parse_double(f[re]) : std::nullopt;
    const auto vi = im < f.size() ? detail::text::parse_double(f[im]) : std::nullopt;
    if (!fr || !vr || !vi)
      throw InputError(file.string() + ": line " + std::to_string(line_no) + ": expected " +
                       std::to_string(header.size()) + " numbers (a chatter frf table)");
    if (*fr == 0.0 && opt.drop_zero_hz && opt.quantity && *opt.quantity != FrfQuantity::kReceptance) continue;
    t.frequency_hz.push_back(*fr);
    t.value.emplace_back(*vr * opt.scale, *vi * opt.scale);
  }
  validate(t);
  return opt.quantity ? to_receptance(std::move(t), *opt.quantity) : t;
}

std::vector<Job> read_jobs(const FitArgs& a) {
  const fs::path file = a.file;
  {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw InputError(a.file + ": no such file");
    if (fs::is_directory(file, ec)) throw InputError(a.file + ": is a directory, not an FRF file");
  }
  const std::string format = a.format.empty() ? format_from_extension(file) : lower(a.format);
  if (format != "csv" && format != "tab" && format != "uff")
    throw InputError("--format '" + a.format + "': use csv, tab or uff");
  FrfReadOptions opt;
  if (!a.quantity.empty()) {
    opt.quantity = parse_frf_quantity(a.quantity);
    if (!opt.quantity)
      throw InputError("--quantity '" + a.quantity +
                       "': use receptance (m/N), mobility ((m/s)/N) or accelerance ((m/s^2)/N)");
  }
  if (!(std::isfinite(a.scale) && a.scale > 0.0))
    throw InputError("--scale = " + fmt(a.scale) + ": must be > 0 (the factor to SI: 1e-6 for um/N, 1e-3 for mm/N)");
  opt.scale = a.scale;
  opt.drop_zero_hz = true;
  const bool given = !a.direction.empty();
  const Eigen::Vector2d given_direction = given ? parse_direction(a.direction) : Eigen::Vector2d(1.0, 0.0);

  std::vector<Job> jobs;
  const bool frf_table = format == "csv" && is_chatter_frf_table(file);
  if (!a.term.empty() && !frf_table)
    throw InputError("--term: only for a table written by chatter frf --out (" + a.file + " is not one)");
  if (frf_table) {
    // `chatter frf --out` holds 9 receptance terms: fit one (default relative_xx,
    // what the lobes are computed from); its direction follows the term.
    if (a.record) throw InputError("--record: only for UFF files (use --term for a chatter frf table)");
    const std::string term = a.term.empty() ? "relative_xx" : a.term;
    if (term.size() < 3 || term.substr(term.size() - 3) == "_xy")
      throw InputError("--term '" + term + "': a cross term (xy) has no modes of its own; fit an xx or yy term");
    Job j;
    j.table = read_chatter_frf_term(file, term, opt);
    j.label = a.file + " (" + term + ")";
    j.direction = given ? given_direction
                        : term.substr(term.size() - 3) == "_yy" ? Eigen::Vector2d(0.0, 1.0) : Eigen::Vector2d(1.0, 0.0);
    jobs.push_back(std::move(j));
    return jobs;
  }
  if (format != "uff") {
    if (a.record) throw InputError("--record: only for UFF files (a " + format + " file holds one FRF)");
    Job j;
    j.table = format == "csv" ? read_frf_csv(file, opt) : read_frf_tab(file, opt);
    j.label = a.file;
    j.direction = given_direction;
    jobs.push_back(std::move(j));
    return jobs;
  }
  if (a.record && *a.record < 1) throw InputError("--record = " + std::to_string(*a.record) + ": must be >= 1");
  std::vector<UffFrfRecord> recs = read_uff58_records(file, opt);
  if (a.record && static_cast<std::size_t>(*a.record) > recs.size())
    throw InputError("--record = " + std::to_string(*a.record) + ": " + a.file + " holds " +
                     std::to_string(recs.size()) + " FRF record(s)");
  std::vector<std::string> cross;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    if (a.record && static_cast<std::size_t>(*a.record) != i + 1) continue;
    UffFrfRecord& r = recs[i];
    const int rd = std::abs(r.response_direction), fd = std::abs(r.reference_direction);
    Job j;
    j.name = "record " + std::to_string(i + 1);
    j.label = a.file + " FRF record " + std::to_string(i + 1) + " (dataset " + std::to_string(r.record) +
              " at line " + std::to_string(r.line) + ", response " + std::to_string(r.response_node) + " " +
              uff_direction_text(r.response_direction) + ", reference " + std::to_string(r.reference_node) + " " +
              uff_direction_text(r.reference_direction) + ")";
    // A cross term (response X, reference Y) has no modes of its own to fit.
    if ((rd == 1 || rd == 2) && (fd == 1 || fd == 2) && rd != fd && !given) {
      cross.push_back(j.label);
      continue;
    }
    j.direction = given ? given_direction : rd == 2 ? Eigen::Vector2d(0.0, 1.0) : Eigen::Vector2d(1.0, 0.0);
    j.table = std::move(r.table);
    jobs.push_back(std::move(j));
  }
  if (jobs.empty()) {
    std::string list;
    for (const auto& c : cross) list += "\n  " + c;
    throw InputError(a.file + ": only cross terms (response and reference in different directions), which cannot "
                              "be fitted on their own; fit the direct terms (xx, yy), or give --direction to fit "
                              "one anyway:" + list);
  }
  for (const auto& c : cross) std::cout << "skipped cross term: " << c << "\n";
  return jobs;
}

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
                                               const std::vector<Job>& jobs, const std::vector<ModalFitResult>& fits) {
  const ImageFormat format = check_plot_path(image);
  fs::path dat = image, gp = image;
  dat.replace_extension(".dat");
  gp.replace_extension(".gp");
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& r : fits) {
    lo = std::min(lo, r.f_min_hz);
    hi = std::max(hi, r.f_max_hz);
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
      const double f = fits[r].f_min_hz + (fits[r].f_max_hz - fits[r].f_min_hz) * i / n;
      const Complex z = fits[r].receptance(f);
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
        << gp_quote(who + "fit, " + std::to_string(fits[r].modes.size()) + " mode(s), error " +
                    g(100 * fits[r].fit_error, 3) + " %");
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
bool parse_fit_args(const std::vector<std::string>& args, FitArgs& a) {
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
      ("out", po::value<std::string>(&a.out)->required(), "write the modes as a config fragment (TOML) here (required)")
      ("plot", po::value<std::string>(&a.plot),
       "draw measured vs fitted magnitude and phase to this .png, .svg or .pdf (script and data beside it)");
  po::options_description hidden;
  hidden.add_options()("frf-file", po::value<std::string>(&a.file), "FRF file");
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

  if (vm.count("record")) a.record = vm["record"].as<int>();
  if (vm.count("modes")) {
    a.modes = vm["modes"].as<int>();
    if (*a.modes < 1) throw InputError("--modes = " + std::to_string(*a.modes) + ": must be >= 1 (or --auto)");
  }
  a.auto_modes = vm.count("auto") > 0;
  if (a.auto_modes && a.modes) throw InputError("--modes and --auto: give one of them");
  a.residuals = vm.count("residuals") > 0;
  if (vm.count("band")) {
    const auto& b = vm["band"].as<std::vector<double>>();
    if (b.size() != 2)
      throw InputError("--band: give two frequencies FMIN FMAX in Hz, got " + std::to_string(b.size()) + " value(s)");
    if (!(std::isfinite(b[0]) && b[0] >= 0.0)) throw InputError("--band: FMIN = " + fmt(b[0]) + " Hz: must be >= 0");
    if (!(std::isfinite(b[1]) && b[1] > b[0]))
      throw InputError("--band: FMAX = " + fmt(b[1]) + " Hz: must be > FMIN (" + fmt(b[0]) + " Hz)");
    a.band = std::pair{b[0], b[1]};
  }
  a.body = lower(a.body);
  if (a.body != "tool" && a.body != "workpiece") throw InputError("--body '" + a.body + "': use tool or workpiece");
  check_outputs({{"--out", a.out}, {"--plot", a.plot, true}});  // before reading or fitting
  if (!a.direction.empty()) parse_direction(a.direction);
  return true;
}

// Fits one FRF record; appends its lines to the report, its modes to the TOML
// fragment and any warning. @throws InputError when the data cannot be fitted.
ModalFitResult fit_job(const Job& j, const FitArgs& a, std::ostringstream& report, std::ostringstream& toml,
                       std::vector<std::string>& warnings) {
  const FrfTable& t = j.table;
  ModalFitOptions o;
  o.modes = a.modes.value_or(0);
  o.residuals = a.residuals;
  o.direction = j.direction;
  if (a.band) {
    o.f_min_hz = a.band->first;
    o.f_max_hz = a.band->second;
    const double lo = t.frequency_hz.front(), hi = t.frequency_hz.back();
    if (o.f_max_hz < lo || o.f_min_hz > hi)
      throw InputError(j.label + ": --band " + fmt(o.f_min_hz) + " " + fmt(o.f_max_hz) +
                       " Hz lies outside the measured lines (" + fmt(lo) + "-" + fmt(hi) + " Hz)");
  }
  ModalFitResult res;
  try {
    res = fit_modes(t, o);
  } catch (const NumericalError& e) {
    throw InputError(std::string(e.what()) +
                     "; the data do not look like lightly damped modes in this band: narrow --band around the "
                     "resonances, give --modes, or check --quantity");
  }
  report << j.label << ": " << t.size() << " lines " << fmt(t.frequency_hz.front()) << "-"
         << fmt(t.frequency_hz.back()) << " Hz; fitted " << res.lines << " lines " << fmt(res.f_min_hz) << "-"
         << fmt(res.f_max_hz) << " Hz, direction " << direction_text(j.direction) << "\n";
  report << "  mode  frequency_hz  damping_ratio  stiffness_n_per_m\n";
  for (std::size_t m = 0; m < res.modes.size(); ++m) {
    const Mode& md = res.modes[m];
    char line[160];
    std::snprintf(line, sizeof line, "  %4zu  %12.6g  %13.5g  %17.6g\n", m + 1, md.natural_frequency_hz,
                  md.damping_ratio, md.stiffness_n_per_m);
    report << line;
  }
  if (a.residuals)
    report << "  residual terms: upper " << g(res.residual_upper, 4) << " m/N, lower " << g(res.residual_lower, 4)
           << " m/N at " << g(res.residual_omega / (2 * std::numbers::pi), 6)
           << " Hz (not written: they stand for modes outside the band)\n";
  report << "  fit error " << g(res.fit_error, 3) << " (relative RMS over the band; peak picking alone: "
         << g(res.initial_error, 3) << "), " << res.iterations << " iterations"
         << (res.converged ? "" : ", NOT converged") << "\n";
  if (!res.converged)
    warnings.push_back(j.label + ": the fit did not converge within " + std::to_string(o.max_iterations) +
                       " iterations; the modes are the best found");
  if (res.fit_error > 0.1)
    warnings.push_back(j.label + ": fit error " + g(100 * res.fit_error, 3) +
                       " %: the modes do not describe this FRF well; try --band around the resonances, --modes, "
                       "or --residuals");
  std::ostringstream comment;
  comment << j.label << ": " << res.modes.size() << " mode(s), band " << fmt(res.f_min_hz) << "-"
          << fmt(res.f_max_hz) << " Hz (" << res.lines << " lines), fit error " << g(res.fit_error, 3)
          << " (relative RMS), " << res.iterations << " iterations" << (res.converged ? "" : ", not converged");
  toml << "\n" << modes_to_toml(res.modes, a.body, comment.str());
  return res;
}

// Two records along the same direction would put the same modes in twice.
void warn_same_directions(const std::vector<Job>& jobs, const FitArgs& a, std::vector<std::string>& warnings) {
  for (std::size_t r = 1; r < jobs.size(); ++r)
    for (std::size_t q = 0; q < r; ++q)
      if ((jobs[r].direction - jobs[q].direction).norm() < 1e-12) {
        warnings.push_back("FRF records " + std::to_string(q + 1) + " and " + std::to_string(r + 1) +
                           " are both along " + direction_text(jobs[r].direction) + ": " + a.out +
                           " holds the modes of both; keep one set (or pick a record with --record)");
        q = r;
      }
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
  if (!parse_fit_args(args, a)) return 0;

  // ---- read and fit ----
  std::vector<Job> jobs = read_jobs(a);
  std::vector<ModalFitResult> fits;
  std::ostringstream report, toml;
  toml << "# Modes fitted by `chatter fit` (chatter " << version() << ") from " << a.file << ".\n"
       << "# Paste the blocks below into a config (docs/config.md), or append a [process] table.\n";
  std::vector<std::string> warnings;
  for (const Job& j : jobs) fits.push_back(fit_job(j, a, report, toml, warnings));
  warn_same_directions(jobs, a, warnings);

  // ---- write (all or nothing), then render ----
  std::vector<std::pair<fs::path, std::string>> files{{a.out, toml.str()}};
  std::vector<std::pair<fs::path, std::string>> uses{{a.file, "the FRF file being fitted"}, {a.out, "--out"}};
  fs::path image, script, data;
  if (!a.plot.empty()) {
    image = a.plot;
    script = image;
    script.replace_extension(".gp");
    data = image;
    data.replace_extension(".dat");
    auto [dat_text, gp_text] = plot_files(image, a.file, jobs, fits);
    files.emplace_back(data, std::move(dat_text));
    files.emplace_back(script, std::move(gp_text));
    uses.emplace_back(data, "the --plot data file");
    uses.emplace_back(script, "the --plot gnuplot script");
    uses.emplace_back(image, "the --plot image");
  }
  refuse_colliding_paths(uses);
  write_text_files(files);
  std::cout << report.str();
  for (const auto& w : warnings) std::cout << "warning: " << w << "\n";
  std::cout << "wrote modes: " << a.out << " ([[" << a.body << ".modes]])\n";
  if (!a.plot.empty()) {
    render_gnuplot_image(script, image);
    std::cout << "wrote plot: " << image.string() << " (gnuplot script " << script.string() << ", data "
              << data.string() << ")\n";
  }
  return 0;
}

}  // namespace chatter::cli
