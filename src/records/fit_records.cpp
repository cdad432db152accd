// The record of `chatter fit` (chatter/records/shop.hpp): modes fitted to a
// measured FRF (a tap test) from a CSV, tab `.frf` or UFF 58/58b file or a
// `chatter frf` table, one fit per direct term, with the config fragment
// ([[tool.modes]] ...) the config loader accepts. Built once for the CLI and
// Python. Reference: docs/frf.md.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "../formats/text.hpp"
#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/io/frf.hpp"
#include "chatter/io/modes_toml.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/shop.hpp"
#include "chatter/records.hpp"

namespace chatter {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string g(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string format_from_extension(const fs::path& file, ArgStyle style) {
  const std::string ext = lower(file.extension().string());
  if (ext == ".csv") return "csv";
  if (ext == ".frf" || ext == ".tab" || ext == ".txt") return "tab";
  if (ext == ".uff" || ext == ".unv" || ext == ".58") return "uff";
  throw InputError(file.string() + ": cannot tell the format from the extension '" + file.extension().string() +
                   "': give " + arg_name(style, "format") + " csv, tab or uff");
}

// "x", "y", "[ux, uy]" or "ux,uy" -> unit vector.
Eigen::Vector2d parse_direction(const std::string& text, ArgStyle style) {
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
    throw InputError(arg_name(style, "direction") + " '" + text + "': use x, y or [ux,uy] (a vector in the X-Y plane)");
  const double n = std::hypot(ux, uy);
  if (!(n > 0.0) || !std::isfinite(n)) throw InputError(arg_name(style, "direction") + " '" + text + "': the vector must not be zero");
  return {ux / n, uy / n};
}

// UFF record 6 direction code as text: 1 +X, -2 -Y, ...
std::string uff_direction_text(int d) {
  static const char* const axes[] = {"?", "X", "Y", "Z", "RX", "RY", "RZ"};
  const int a = std::abs(d);
  if (a < 1 || a > 6) return std::to_string(d);
  return std::string(d < 0 ? "-" : "+") + axes[a];
}

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
FrfTable read_chatter_frf_term(const fs::path& file, const std::string& term, const FrfReadOptions& opt,
                               ArgStyle style) {
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
        throw InputError(arg_name(style, "term") + " '" + term + "': not a term of " + file.string() +
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

std::vector<FittedRecord> read_records(const FitArgs& a, ArgStyle style, std::vector<std::string>& skipped) {
  const auto name = [&](const char* key) { return arg_name(style, key); };
  const std::string file_name = a.file.string();
  const fs::path file = a.file;
  {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw InputError(file_name + ": no such file");
    if (fs::is_directory(file, ec)) throw InputError(file_name + ": is a directory, not an FRF file");
  }
  const std::string format = a.format.empty() ? format_from_extension(file, style) : lower(a.format);
  if (format != "csv" && format != "tab" && format != "uff")
    throw InputError(name("format") + " '" + a.format + "': use csv, tab or uff");
  FrfReadOptions opt;
  if (!a.quantity.empty()) {
    opt.quantity = parse_frf_quantity(a.quantity);
    if (!opt.quantity)
      throw InputError(name("quantity") + " '" + a.quantity +
                       "': use receptance (m/N), mobility ((m/s)/N) or accelerance ((m/s^2)/N)");
  }
  if (!(std::isfinite(a.scale) && a.scale > 0.0))
    throw InputError(name("scale") + " = " + number_text(a.scale) + ": must be > 0 (the factor to SI: 1e-6 for um/N, 1e-3 for mm/N)");
  opt.scale = a.scale;
  opt.drop_zero_hz = true;
  const bool given = !a.direction.empty();
  const Eigen::Vector2d given_direction = given ? parse_direction(a.direction, style) : Eigen::Vector2d(1.0, 0.0);

  std::vector<FittedRecord> jobs;
  const bool frf_table = format == "csv" && is_chatter_frf_table(file);
  if (!a.term.empty() && !frf_table)
    throw InputError(name("term") + ": only for a table written by chatter frf --out (" + file_name + " is not one)");
  if (frf_table) {
    // `chatter frf --out` holds 9 receptance terms: fit one (default relative_xx,
    // what the lobes are computed from); its direction follows the term.
    if (a.record) throw InputError(name("record") + ": only for UFF files (use " + name("term") + " for a chatter frf table)");
    const std::string term = a.term.empty() ? "relative_xx" : a.term;
    if (term.size() < 3 || term.substr(term.size() - 3) == "_xy")
      throw InputError(name("term") + " '" + term + "': a cross term (xy) has no modes of its own; fit an xx or yy term");
    FittedRecord j;
    j.table = read_chatter_frf_term(file, term, opt, style);
    j.label = file_name + " (" + term + ")";
    j.direction = given ? given_direction
                        : term.substr(term.size() - 3) == "_yy" ? Eigen::Vector2d(0.0, 1.0) : Eigen::Vector2d(1.0, 0.0);
    jobs.push_back(std::move(j));
    return jobs;
  }
  if (format != "uff") {
    if (a.record) throw InputError(name("record") + ": only for UFF files (a " + format + " file holds one FRF)");
    FittedRecord j;
    j.table = format == "csv" ? read_frf_csv(file, opt) : read_frf_tab(file, opt);
    j.label = a.file;
    j.direction = given_direction;
    jobs.push_back(std::move(j));
    return jobs;
  }
  if (a.record && *a.record < 1) throw InputError(name("record") + " = " + std::to_string(*a.record) + ": must be >= 1");
  std::vector<UffFrfRecord> recs = read_uff58_records(file, opt);
  if (a.record && static_cast<std::size_t>(*a.record) > recs.size())
    throw InputError(name("record") + " = " + std::to_string(*a.record) + ": " + file_name + " holds " +
                     std::to_string(recs.size()) + " FRF record(s)");
  std::vector<std::string> cross;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    if (a.record && static_cast<std::size_t>(*a.record) != i + 1) continue;
    UffFrfRecord& r = recs[i];
    const int rd = std::abs(r.response_direction), fd = std::abs(r.reference_direction);
    FittedRecord j;
    j.name = "record " + std::to_string(i + 1);
    j.label = file_name + " FRF record " + std::to_string(i + 1) + " (dataset " + std::to_string(r.record) +
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
    throw InputError(file_name + ": only cross terms (response and reference in different directions), which cannot "
                              "be fitted on their own; fit the direct terms (xx, yy), or give " + name("direction") +
                              " to fit one anyway:" + list);
  }
  skipped = cross;
  return jobs;
}

// Fits one FRF record; appends its lines to the report, its modes to the TOML
// fragment and any warning. @throws InputError when the data cannot be fitted.
ModalFitResult fit_record_of(const FittedRecord& j, const FitArgs& a, ArgStyle style, std::ostringstream& report,
                             std::ostringstream& toml, std::vector<std::string>& warnings) {
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
      throw InputError(j.label + ": " + arg_name(style, "band") + " " + number_text(o.f_min_hz) + " " + number_text(o.f_max_hz) +
                       " Hz lies outside the measured lines (" + number_text(lo) + "-" + number_text(hi) + " Hz)");
  }
  ModalFitResult res;
  try {
    res = fit_modes(t, o);
  } catch (const NumericalError& e) {
    throw InputError(std::string(e.what()) +
                     "; the data do not look like lightly damped modes in this band: narrow " + arg_name(style, "band") +
                     " around the resonances, give " + arg_name(style, "modes") + ", or check " + arg_name(style, "quantity"));
  }
  report << j.label << ": " << t.size() << " lines " << number_text(t.frequency_hz.front()) << "-"
         << number_text(t.frequency_hz.back()) << " Hz; fitted " << res.lines << " lines " << number_text(res.f_min_hz) << "-"
         << number_text(res.f_max_hz) << " Hz, direction " << direction_text(j.direction) << "\n";
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
  report << "  1-sigma standard errors, % of the value (frequency, damping ratio, stiffness):";
  for (std::size_t m = 0; m < res.standard_errors.size(); ++m) {
    const auto& e = res.standard_errors[m];
    report << (m ? ";" : "") << " mode " << m + 1 << ": " << g(100 * e.frequency, 3) << ", " << g(100 * e.damping, 3)
           << ", " << g(100 * e.stiffness, 3);
  }
  report << "\n";
  report << "  fit error " << g(res.fit_error, 3) << " (relative RMS over the band; peak picking alone: "
         << g(res.initial_error, 3) << "), " << res.iterations << " iterations"
         << (res.converged ? "" : ", NOT converged") << "\n";
  if (!res.converged)
    warnings.push_back(j.label + ": the fit did not converge within " + std::to_string(o.max_iterations) +
                       " iterations; the modes are the best found");
  if (res.fit_error > 0.1)
    warnings.push_back(j.label + ": fit error " + g(100 * res.fit_error, 3) +
                       " %: the modes do not describe this FRF well; try " + arg_name(style, "band") + " around the resonances, " +
                       arg_name(style, "modes") + ", or " + arg_name(style, "residuals"));
  std::ostringstream comment;
  comment << j.label << ": " << res.modes.size() << " mode(s), band " << number_text(res.f_min_hz) << "-"
          << number_text(res.f_max_hz) << " Hz (" << res.lines << " lines), fit error " << g(res.fit_error, 3)
          << " (relative RMS), " << res.iterations << " iterations" << (res.converged ? "" : ", not converged");
  toml << "\n" << modes_to_toml(res.modes, a.body, comment.str());
  return res;
}

// The spreads of [uncertainty] from the fit's standard errors, commented out
// (docs/frf.md, "Standard errors and [uncertainty]"): 100 × the standard
// error of ln p for each mode's frequency, damping ratio and stiffness, one
// value per mode in the order of the fragment; capped to what [uncertainty]
// accepts, with a note.
std::string fit_uncertainty_toml(const std::vector<FittedRecord>& records) {
  UncertaintyKey f{"frequency_percent", {}, true}, z{"damping_percent", {}, true}, k{"stiffness_percent", {}, true};
  std::ostringstream notes;
  std::size_t mode = 0;
  for (const FittedRecord& j : records)
    for (std::size_t m = 0; m < j.fit.modes.size(); ++m, ++mode) {
      const auto& e = j.fit.standard_errors[m];
      if (!(std::isfinite(e.frequency) && std::isfinite(e.damping) && std::isfinite(e.stiffness)))
        return "# [uncertainty]: no spreads: the standard errors of mode " + std::to_string(mode + 1) +
               " are not defined (a parameter is not identified by the data).\n";
      const double zeta = j.fit.modes[m].damping_ratio;
      const std::pair<UncertaintyKey*, std::pair<double, double>> parts[3] = {
          {&f, {100 * e.frequency, 0.0}}, {&z, {100 * e.damping, zeta}}, {&k, {100 * e.stiffness, 0.0}}};
      for (const auto& [key, p] : parts) {
        const double allowed = allowed_spread_percent(p.first, p.second);
        if (allowed < p.first)
          notes << "\n" << key->key << " of mode " << mode + 1 << ": the standard error is " << g(p.first, 4)
                << " %, capped to " << g(allowed, 4) << " % (the most [uncertainty] accepts)";
        key->percent.push_back(allowed);
      }
    }
  if (mode == 0) return "";
  return commented_uncertainty_toml(
      {f, z, k},
      "[uncertainty]: 1-sigma spreads of the modes above, from the fit's standard errors (percent = 100 x the\n"
      "standard error of ln p; docs/frf.md). To sample them with `chatter lobes --samples N`, remove the '#'\n"
      "in front of [uncertainty] and of each key below. One value per mode in the order above: with other\n"
      "modes in the config, give theirs too (tool modes first, then workpiece modes)." + notes.str());
}

// Two records along the same direction would put the same modes in twice.
void warn_same_directions(const std::vector<FittedRecord>& jobs, const FitArgs& a, ArgStyle style,
                          std::vector<std::string>& warnings) {
  for (std::size_t r = 1; r < jobs.size(); ++r)
    for (std::size_t q = 0; q < r; ++q)
      if ((jobs[r].direction - jobs[q].direction).norm() < 1e-12) {
        warnings.push_back("FRF records " + std::to_string(q + 1) + " and " + std::to_string(r + 1) +
                           " are both along " + direction_text(jobs[r].direction) + ": " + a.fragment_name +
                           " holds the modes of both; keep one set (or pick a record with " + arg_name(style, "record") + ")");
        q = r;
      }
}

}  // namespace

std::string direction_text(const Eigen::Vector2d& u) {
  if (u.x() == 1.0 && u.y() == 0.0) return "x";
  if (u.x() == 0.0 && u.y() == 1.0) return "y";
  std::string s = "[";  // appended piecewise: `"literal" + std::string` trips a GCC 12 -Wrestrict false positive
  s.append(number_text(u.x(), 6)).append(", ").append(number_text(u.y(), 6)).append("]");
  return s;
}

void check_fit_args(const FitArgs& a, ArgStyle style) {
  const auto name = [&](const char* key) { return arg_name(style, key); };
  if (a.modes && *a.modes < 1)
    throw InputError(name("modes") + " = " + std::to_string(*a.modes) + ": must be >= 1" +
                     (style == ArgStyle::kFlag ? " (or --auto)" : " (or None: every peak)"));
  if (a.band) {
    const auto [lo, hi] = *a.band;
    if (!(std::isfinite(lo) && lo >= 0.0)) throw InputError(name("band") + ": FMIN = " + number_text(lo) + " Hz: must be >= 0");
    if (!(std::isfinite(hi) && hi > lo))
      throw InputError(name("band") + ": FMAX = " + number_text(hi) + " Hz: must be > FMIN (" + number_text(lo) + " Hz)");
  }
  const std::string body = lower(a.body);
  if (body != "tool" && body != "workpiece") throw InputError(name("body") + " '" + a.body + "': use tool or workpiece");
  if (!a.direction.empty()) parse_direction(a.direction, style);
}

FitReport fit_frf_file(const FitArgs& args, ArgStyle style) {
  check_fit_args(args, style);
  FitArgs a = args;
  a.body = lower(a.body);
  FitReport r;
  r.file = a.file;
  r.body = a.body;
  std::vector<std::string> skipped;
  r.records = read_records(a, style, skipped);
  std::ostringstream report, toml;
  for (const std::string& c : skipped) report << "skipped cross term: " << c << "\n";
  toml << "# Modes fitted by `chatter fit` (chatter " << version() << ") from " << a.file.string() << ".\n"
       << "# Paste the blocks below into a config (docs/config.md), or append a [process] table.\n";
  for (FittedRecord& j : r.records) j.fit = fit_record_of(j, a, style, report, toml, r.warnings);
  warn_same_directions(r.records, a, style, r.warnings);
  toml << "\n" << fit_uncertainty_toml(r.records);
  r.fragment = toml.str();
  r.report = report.str();
  return r;
}

json fit_record(const FitReport& r) {
  json records = json::array();
  for (const FittedRecord& f : r.records) {
    const ModalFitResult& m = f.fit;
    // modes: keys a Job takes as they are; their errors in a list beside.
    json modes = json::array(), errors = json::array();
    for (std::size_t i = 0; i < m.modes.size(); ++i) {
      const Mode& md = m.modes[i];
      const auto& e = m.standard_errors[i];
      modes.push_back({{"frequency_hz", md.natural_frequency_hz},
                       {"damping_ratio", md.damping_ratio},
                       {"stiffness_n_per_m", md.stiffness_n_per_m}});
      errors.push_back({{"frequency", finite_or_null(e.frequency)},
                        {"damping_ratio", finite_or_null(e.damping)},
                        {"stiffness", finite_or_null(e.stiffness)}});
    }
    json one = {{"label", f.label},
                {"direction", direction_text(f.direction)},
                {"measured_lines", f.table.size()},
                {"measured_min_hz", f.table.frequency_hz.front()},
                {"measured_max_hz", f.table.frequency_hz.back()},
                {"band_min_hz", m.f_min_hz},
                {"band_max_hz", m.f_max_hz},
                {"fitted_lines", m.lines},
                {"modes", modes},
                {"relative_standard_errors", errors},
                {"fit_error", m.fit_error},
                {"initial_error", m.initial_error},
                {"iterations", m.iterations},
                {"converged", m.converged}};
    if (!f.name.empty()) one["record"] = f.name;
    records.push_back(one);
  }
  return {{"file", r.file.string()},
          {"body", r.body},
          {"records", records},
          {"warnings", r.warnings},
          {"fragment", r.fragment}};
}

ColumnRecord fit_columns(const FitReport& r) {
  ColumnRecord out;
  out.fields = fit_record(r);
  for (std::size_t i = 0; i < r.records.size(); ++i) {
    const FittedRecord& f = r.records[i];
    std::vector<double> hz(kFittedPoints);
    std::vector<std::complex<double>> g(kFittedPoints);
    for (std::size_t k = 0; k < hz.size(); ++k) {
      hz[k] = f.fit.f_min_hz + (f.fit.f_max_hz - f.fit.f_min_hz) * static_cast<double>(k) / (kFittedPoints - 1);
      g[k] = f.fit.receptance(hz[k]);
    }
    out.groups.push_back({"/records/" + std::to_string(i),
                          {{"measured_frequency_hz", f.table.frequency_hz},
                           {"measured_receptance_m_per_n", f.table.value},
                           {"fitted_frequency_hz", std::move(hz)},
                           {"fitted_receptance_m_per_n", std::move(g)}}});
  }
  return out;
}

}  // namespace chatter
