// The Universal File reader: datasets 58 (ASCII) and 58b (binary), units from
// dataset 164 (the CSV and tab readers: frf_reader.cpp). Format notes and
// tolerated quirks: docs/frf.md.
//
// Every bad input becomes a chatter::InputError:
//   <file>: line <l>: <what>                 (CSV, tab)
//   <file>: record <r>, line <l>: <what>     (UFF; r counts every dataset, 1-based)
//   <file>: <what>                           (whole file)
// Nothing is allocated from a count read in a header before the data that
// backs it has been seen, so a corrupt header cannot exhaust memory.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/io/frf.hpp"
#include "frf_text.hpp"
#include "text.hpp"
namespace chatter {
namespace {

using namespace frf_detail;

// ------------------------------------------------------------------- UFF

struct UffContext {
  std::string name;
  int record = 0;
  std::string at(int line) const {
    return name + ": record " + std::to_string(record) + ", line " + std::to_string(line);
  }
  [[noreturn]] void fail(int line, const std::string& what) const { throw InputError(at(line) + ": " + what); }
};

// A header type code read as a number: blank = 0; anything but an integer of
// modest size (inf, NaN, 1e300, 8.5) = -1, an unknown type (never cast out of
// range: that is undefined behaviour).
long long type_code(const std::optional<double>& v) {
  if (!v) return 0;
  return (*v == std::floor(*v) && std::abs(*v) < 1e9) ? static_cast<long long>(*v) : -1;
}

/// Fixed-width integer fields with a whitespace fallback.
std::vector<std::optional<double>> header_fields(std::string_view l, std::initializer_list<int> widths) {
  std::vector<std::optional<double>> fixed;
  std::size_t p = 0;
  bool ok = true;
  for (const int w : widths) {
    const std::string_view f = p < l.size() ? l.substr(p, static_cast<std::size_t>(w)) : std::string_view();
    p += static_cast<std::size_t>(w);
    if (trim(f).empty()) {
      fixed.emplace_back(std::nullopt);
      continue;
    }
    const auto v = parse_number(f);
    if (!v) ok = false;
    fixed.push_back(v);
  }
  if (ok && p >= trim_right(l).size()) return fixed;
  // Fields not at their columns: take blank-separated tokens in order.
  std::vector<std::optional<double>> tokens;
  for (const auto tok : split_blanks(l)) tokens.push_back(parse_number(tok));
  tokens.resize(widths.size());
  return tokens;
}

const char* spec_type_name(long long t) {
  switch (t) {
    case 0: return "unknown";
    case 1: return "general";
    case 2: return "stress";
    case 3: return "strain";
    case 5: return "temperature";
    case 6: return "heat flux";
    case 8: return "displacement";
    case 9: return "reaction force";
    case 11: return "velocity";
    case 12: return "acceleration";
    case 13: return "excitation force";
    case 15: return "pressure";
    case 16: return "mass";
    case 17: return "time";
    case 18: return "frequency";
    case 19: return "rpm";
    default: return "other";
  }
}

const char* function_type_name(long long t) {
  switch (t) {
    case 0: return "general";
    case 1: return "time response";
    case 2: return "auto spectrum";
    case 3: return "cross spectrum";
    case 4: return "frequency response function";
    case 5: return "transmissibility";
    case 6: return "coherence";
    case 7: return "auto correlation";
    case 8: return "cross correlation";
    case 9: return "power spectral density";
    case 10: return "energy spectral density";
    case 12: return "spectrum";
    default: return "other";
  }
}

struct DatasetHeader {
  long long number = 0;
  bool binary = false;
  int byte_order = 1;          // 1 little, 2 big
  int fp_format = 2;           // 2 IEEE 754
  long long ascii_lines = 11;
  long long bytes = 0;
};

DatasetHeader parse_dataset_header(const UffContext& ctx, std::string_view l, int ln) {
  DatasetHeader h;
  const std::string_view t = trim(l);
  // Number, optionally followed by 'b' (58b), in the first 6 columns.
  std::size_t i = 0;
  while (i < t.size() && (std::isdigit(static_cast<unsigned char>(t[i])) || (i == 0 && t[i] == '-'))) ++i;
  const auto n = parse_integer(t.substr(0, i));
  if (!n) ctx.fail(ln, "expected a dataset number after '-1', found '" + shown(t) + "'");
  h.number = *n;
  std::string_view rest = t.substr(i);
  if (!rest.empty() && (rest[0] == 'b' || rest[0] == 'B')) {
    h.binary = true;
    const auto tok = split_blanks(rest.substr(1));
    if (tok.size() < 4)
      ctx.fail(ln, "binary dataset header needs byte ordering, floating-point format, ASCII line count and byte count, found '" +
                       shown(t) + "'");
    const auto bo = parse_integer(tok[0]), fp = parse_integer(tok[1]), al = parse_integer(tok[2]),
               nb = parse_integer(tok[3]);
    if (!bo || !fp || !al || !nb) ctx.fail(ln, "non-numeric field in binary dataset header '" + shown(t) + "'");
    if (*bo != 1 && *bo != 2) ctx.fail(ln, "byte ordering " + std::to_string(*bo) + " (must be 1 little-endian or 2 big-endian)");
    if (*al < 0 || *nb < 0) ctx.fail(ln, "negative line or byte count in binary dataset header");
    h.byte_order = static_cast<int>(*bo);
    h.fp_format = static_cast<int>(*fp);
    h.ascii_lines = *al;
    h.bytes = *nb;
  } else if (!trim(rest).empty()) {
    ctx.fail(ln, "expected a dataset number after '-1', found '" + shown(t) + "'");
  }
  return h;
}

bool is_delimiter(std::string_view l) { return trim(l) == "-1"; }

/// Skips to the closing `-1` of a dataset (or the end of the file).
void skip_to_delimiter(LineReader& lines) {
  while (!lines.at_end())
    if (is_delimiter(lines.next())) return;
}

/// After binary data: blank bytes / lines, then `-1` (or end of file).
void expect_delimiter_after_binary(const UffContext& ctx, LineReader& lines, long long bytes) {
  while (!lines.at_end()) {
    const int ln = lines.line();
    const std::string_view l = lines.next();
    if (trim(l).empty()) continue;
    if (is_delimiter(l)) return;
    ctx.fail(ln, "expected '-1' after the " + std::to_string(bytes) +
                     " bytes of binary data, found '" + shown(trim(l)) +
                     "' (byte count in the header does not match the data?)");
  }
}

/// Column layout of the ASCII data lines of dataset 58.
std::vector<int> column_pattern(int ordinate_type, bool even) {
  const bool single = ordinate_type == 2 || ordinate_type == 5;
  if (single) return {13};
  if (even) return {20};
  if (ordinate_type == 4) return {13, 20};  // 2(E13.5, E20.12)
  return {13, 20, 20};                      // E13.5, 2E20.12
}

struct Values {
  std::vector<double> v;
  std::vector<int> line;  // line of each value
};

/// Parses one ASCII data line into `out`; blank-separated first, fixed
/// columns when fields run together.
void parse_data_line(const UffContext& ctx, std::string_view l, int ln, const std::vector<int>& pattern, Values& out) {
  const auto tokens = split_blanks(l);
  std::vector<double> parsed;
  parsed.reserve(tokens.size());
  std::optional<std::size_t> bad_token;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const auto v = parse_number(tokens[i]);
    if (!v) {
      bad_token = i;
      break;
    }
    parsed.push_back(*v);
  }
  if (!bad_token) {
    for (const double v : parsed) {
      out.v.push_back(v);
      out.line.push_back(ln);
    }
    return;
  }
  // Fields running together: cut by column width, the pattern continuing
  // from the values already read.
  std::vector<double> fixed;
  std::size_t k = out.v.size() % pattern.size();
  const std::string_view r = trim_right(l);
  std::size_t p = 0;
  bool ok = true;
  while (p < r.size()) {
    const auto w = static_cast<std::size_t>(pattern[k]);
    const std::string_view f = r.substr(p, w);
    const auto v = parse_number(f);
    if (!v) {
      ok = false;
      break;
    }
    fixed.push_back(*v);
    p += w;
    k = (k + 1) % pattern.size();
  }
  if (!ok)
    ctx.fail(ln, "non-numeric field '" + shown(tokens[*bad_token]) + "' at column " + std::to_string(*bad_token + 1));
  for (const double v : fixed) {
    out.v.push_back(v);
    out.line.push_back(ln);
  }
}

double load_float(const char* p, int byte_order, bool dbl) {
  const bool swap = (byte_order == 1) != (std::endian::native == std::endian::little);
  if (dbl) {
    std::array<unsigned char, 8> b;
    std::memcpy(b.data(), p, 8);
    if (swap) std::reverse(b.begin(), b.end());
    return std::bit_cast<double>(b);
  }
  std::array<unsigned char, 4> b;
  std::memcpy(b.data(), p, 4);
  if (swap) std::reverse(b.begin(), b.end());
  return static_cast<double>(std::bit_cast<float>(b));
}

struct UffState {
  double units_scale = 1.0;  // SI per file unit for an FRF ordinate (force factor / length factor)
  std::vector<std::string> skipped;
};

/// Dataset 164 (units): record 2 holds length, force, temperature factors
/// (SI = file value / factor).
void read_units(const UffContext& ctx, LineReader& lines, UffState& st) {
  std::vector<std::pair<int, std::string_view>> recs;
  while (!lines.at_end()) {
    const int ln = lines.line();
    const std::string_view l = lines.next();
    if (is_delimiter(l)) break;
    recs.emplace_back(ln, l);
  }
  if (recs.size() < 2) ctx.fail(recs.empty() ? lines.line() : recs.back().first, "units dataset 164 truncated (needs 2 records)");
  const auto f = header_fields(recs[1].second, {25, 25, 25});
  if (!f[0] || !f[1]) ctx.fail(recs[1].first, "units dataset 164: non-numeric length or force factor");
  const double length = *f[0], force = *f[1];
  if (!std::isfinite(length) || length <= 0.0 || !std::isfinite(force) || force <= 0.0)
    ctx.fail(recs[1].first, "units dataset 164: length and force factors must be finite and > 0");
  st.units_scale = force / length;
}

using Header = std::vector<std::pair<int, std::string_view>>;

// The 11 header records of a dataset 58 (line number, text).
Header header_records(const UffContext& ctx, LineReader& lines, const DatasetHeader& h, int start_line) {
  const long long header_count = h.binary ? h.ascii_lines : 11;
  if (h.binary && h.ascii_lines < 11)
    ctx.fail(start_line + 1, "binary dataset header gives " + std::to_string(h.ascii_lines) +
                                 " ASCII lines, dataset 58 has 11");
  Header hdr;
  for (long long i = 0; i < header_count; ++i) {
    if (lines.at_end()) ctx.fail(lines.line(), "truncated header: expected 11 header records, got " + std::to_string(hdr.size()));
    const int ln = lines.line();
    const std::string_view l = lines.next();
    if (is_delimiter(l)) ctx.fail(ln, "truncated header: expected 11 header records, got " + std::to_string(hdr.size()));
    hdr.emplace_back(ln, l);
  }
  return hdr;
}

// Record 6: the function type (false, the dataset skipped and noted, when it
// is not an FRF) and the response and reference DOF.
bool read_record6(const UffContext& ctx, LineReader& lines, const DatasetHeader& h,
                  const std::pair<int, std::string_view>& record, UffState& st, UffFrfRecord& rec) {
  const auto& [ln, l] = record;
  const std::string_view t = trim(l);
  const auto toks = split_blanks(t);
  std::optional<long long> ft = parse_integer(l.substr(0, std::min<std::size_t>(5, l.size())));
  if (!ft && !toks.empty()) ft = parse_integer(toks[0]);
  if (!ft) ctx.fail(ln, "header record 6: non-numeric function type '" + shown(toks.empty() ? t : toks[0]) + "'");
  if (*ft != 4) {
    st.skipped.push_back("record " + std::to_string(ctx.record) + ": dataset 58 function type " + std::to_string(*ft) +
                         " (" + function_type_name(*ft) + ") is not an FRF");
    if (h.binary) {
      lines.skip_bytes(static_cast<std::size_t>(std::min<long long>(h.bytes, static_cast<long long>(lines.remaining()))));
      expect_delimiter_after_binary(ctx, lines, h.bytes);
    } else {
      skip_to_delimiter(lines);
    }
    return false;
  }
  auto field = [l = l](std::size_t b, std::size_t w) -> int {  // by value: clang < 16 cannot capture a structured binding
    if (b >= l.size()) return 0;
    const auto v = parse_integer(l.substr(b, w));
    return v ? static_cast<int>(*v) : 0;
  };
  rec.response_node = field(41, 10);
  rec.response_direction = field(51, 4);
  rec.reference_node = field(66, 10);
  rec.reference_direction = field(76, 4);
  return true;
}

// Record 7: the data form (ordinate type, points, abscissa spacing).
struct DataForm {
  std::size_t n_points = 0, per_point = 0, expected = 0;  // values per point; values in all
  double x_min = 0.0, x_inc = 0.0;                       // Hz, even abscissa
  bool complex_data = false, dbl = false;
};

DataForm read_record7(const UffContext& ctx, const std::pair<int, std::string_view>& record, UffFrfRecord& rec) {
  DataForm d;
  const auto& [ln7, l7] = record;
  const auto r7 = header_fields(l7, {10, 10, 10, 13, 13, 13});
  if (!r7[0] || !r7[1] || !r7[2]) ctx.fail(ln7, "header record 7: expected ordinate data type, number of points and abscissa spacing, found '" + shown(trim(l7)) + "'");
  const double ot = *r7[0], np = *r7[1], sp = *r7[2];
  if (ot != 2 && ot != 4 && ot != 5 && ot != 6)
    ctx.fail(ln7, "header record 7: ordinate data type " + number_text(ot, 10) +
                      " is not supported (2 real single, 4 real double, 5 complex single, 6 complex double)");
  if (np != std::floor(np) || np < 1 || np > 1e9) ctx.fail(ln7, "header record 7: number of points " + number_text(np, 10) + " must be an integer >= 1");
  if (sp != 0 && sp != 1) ctx.fail(ln7, "header record 7: abscissa spacing " + number_text(sp, 10) + " must be 1 (even) or 0 (uneven)");
  rec.ordinate_data_type = static_cast<int>(ot);
  rec.even_abscissa = sp == 1;
  d.n_points = static_cast<std::size_t>(np);
  if (rec.even_abscissa) {
    if (!r7[3] || !r7[4]) ctx.fail(ln7, "header record 7: even abscissa needs its minimum and increment");
    d.x_min = *r7[3];
    d.x_inc = *r7[4];
    if (!std::isfinite(d.x_inc) || d.x_inc <= 0.0) ctx.fail(ln7, "header record 7: abscissa increment " + number_text(d.x_inc, 10) + " Hz must be > 0");
    if (!std::isfinite(d.x_min) || d.x_min < 0.0) ctx.fail(ln7, "header record 7: abscissa minimum " + number_text(d.x_min, 10) + " Hz must be >= 0");
  }
  d.complex_data = ot == 5 || ot == 6;
  d.dbl = ot == 4 || ot == 6;
  d.per_point = (d.complex_data ? 2u : 1u) + (rec.even_abscissa ? 0u : 1u);
  d.expected = d.n_points * d.per_point;
  return d;
}

// Records 9 and 10: the ordinate's numerator and denominator (the FRF's
// quantity; options.quantity overrides).
void read_quantity(const UffContext& ctx, const std::pair<int, std::string_view>& record9,
                   const std::pair<int, std::string_view>& record10, const FrfReadOptions& options,
                   UffFrfRecord& rec) {
  const auto& [ln9, l9] = record9;
  const auto r9 = header_fields(l9, {10});
  const long long num = type_code(r9[0]);
  std::optional<FrfQuantity> q;
  if (num == 8) q = FrfQuantity::kReceptance;
  else if (num == 11) q = FrfQuantity::kMobility;
  else if (num == 12) q = FrfQuantity::kAccelerance;
  if (options.quantity) {
    rec.quantity = *options.quantity;
  } else if (q) {
    rec.quantity = *q;
  } else if (num == 0 || num == 1) {
    rec.quantity = FrfQuantity::kReceptance;
  } else {
    ctx.fail(ln9, "header record 9: ordinate is " + std::string(spec_type_name(num)) + " (data type " + std::to_string(num) +
                      "), not displacement (8), velocity (11) or acceleration (12); give the quantity explicitly");
  }
  const auto& [ln10, l10] = record10;
  const auto r10 = header_fields(l10, {10});
  const long long den = type_code(r10[0]);
  if (!options.quantity && den != 0 && den != 1 && den != 9 && den != 13)
    ctx.fail(ln10, "header record 10: ordinate denominator is " + std::string(spec_type_name(den)) + " (data type " +
                       std::to_string(den) + "), not force (13)");
}

// The data of a binary dataset: the values header record 7 announces.
Values binary_values(const UffContext& ctx, LineReader& lines, const DatasetHeader& h, int start_line,
                     const DataForm& form) {
  Values vals;
  if (h.fp_format != 2 && h.fp_format != 0)
    ctx.fail(start_line + 1, "binary floating-point format " + std::to_string(h.fp_format) + " is not supported (2 = IEEE 754)");
  const std::size_t size = form.dbl ? 8 : 4;
  const long long need = static_cast<long long>(form.expected * size);
  if (h.bytes != need)
    ctx.fail(start_line + 1, "binary record holds " + std::to_string(h.bytes) + " bytes, header record 7 needs " +
                                 std::to_string(need) + " (" + std::to_string(form.n_points) + " points x " +
                                 std::to_string(form.per_point) + " values x " + std::to_string(size) + " bytes)");
  if (static_cast<long long>(lines.remaining()) < need)
    ctx.fail(lines.line(), "truncated: expected " + std::to_string(need) + " bytes of binary data, the file has " +
                               std::to_string(lines.remaining()) + " left");
  const std::string_view data = lines.rest();
  const int data_line = lines.line();
  vals.v.reserve(form.expected);
  for (std::size_t i = 0; i < form.expected; ++i) {
    vals.v.push_back(load_float(data.data() + i * size, h.byte_order, form.dbl));
    vals.line.push_back(data_line);
  }
  lines.skip_bytes(static_cast<std::size_t>(need));
  expect_delimiter_after_binary(ctx, lines, h.bytes);
  return vals;
}

// The data of an ASCII dataset up to its closing delimiter: exactly the
// values header record 7 announces.
Values ascii_values(const UffContext& ctx, LineReader& lines, const UffFrfRecord& rec, const DataForm& form) {
  Values vals;
  int end_line = lines.line();
  const std::vector<int> pattern = column_pattern(rec.ordinate_data_type, rec.even_abscissa);
  bool closed = false;
  while (!lines.at_end()) {
    const int ln = lines.line();
    const std::string_view l = lines.next();
    end_line = ln;
    if (is_delimiter(l)) {
      closed = true;
      break;
    }
    if (trim(l).empty()) continue;
    if (vals.v.size() >= form.expected)
      ctx.fail(ln, "extra data after the " + std::to_string(form.expected) + " values header record 7 announces ('" + shown(trim(l)) + "')");
    parse_data_line(ctx, l, ln, pattern, vals);
  }
  if (vals.v.size() < form.expected)
    ctx.fail(end_line, "truncated: expected " + std::to_string(form.expected) + " values (" + std::to_string(form.n_points) +
                           " points), got " + std::to_string(vals.v.size()) +
                           (closed ? "" : " before the end of the file"));
  if (vals.v.size() > form.expected)
    ctx.fail(vals.line[form.expected], "extra data: " + std::to_string(vals.v.size()) + " values, header record 7 announces " +
                                      std::to_string(form.expected));
  return vals;
}

// The record's table from the values (frequency, complex value), and the
// file line of each point.
std::vector<int> fill_table(const UffContext& ctx, const Values& vals, const DataForm& form, UffFrfRecord& rec) {
  FrfTable& t = rec.table;
  t.source = ctx.name + " (record " + std::to_string(ctx.record) + ")";
  t.frequency_hz.reserve(form.n_points);
  t.value.reserve(form.n_points);
  std::vector<int> line_of;
  line_of.reserve(form.n_points);
  for (std::size_t i = 0; i < form.n_points; ++i) {
    const double* p = vals.v.data() + i * form.per_point;
    std::size_t c = 0;
    const double f = rec.even_abscissa ? form.x_min + static_cast<double>(i) * form.x_inc : p[c++];
    const double re = p[c++];
    const double im = form.complex_data ? p[c] : 0.0;
    t.frequency_hz.push_back(f);
    t.value.emplace_back(re, im);
    line_of.push_back(vals.line[i * form.per_point]);
  }
  return line_of;
}

std::optional<UffFrfRecord> read_dataset58(const UffContext& ctx, LineReader& lines, const DatasetHeader& h,
                                           int start_line, UffState& st, const FrfReadOptions& options) {
  const Header hdr = header_records(ctx, lines, h, start_line);
  UffFrfRecord rec;
  rec.record = ctx.record;
  rec.line = start_line;
  rec.binary = h.binary;
  rec.id1 = std::string(trim(hdr[0].second));

  if (!read_record6(ctx, lines, h, hdr[5], st, rec)) return std::nullopt;
  const DataForm form = read_record7(ctx, hdr[6], rec);
  read_quantity(ctx, hdr[8], hdr[9], options, rec);
  const Values vals = h.binary ? binary_values(ctx, lines, h, start_line, form)
                               : ascii_values(ctx, lines, rec, form);

  const std::vector<int> line_of = fill_table(ctx, vals, form, rec);
  const std::string binary_note = h.binary ? " (binary data)" : "";
  validate(rec.table, ctx.name + ": record " + std::to_string(ctx.record), [&](std::size_t i) {
    return ctx.at(line_of[i]) + binary_note + ", point " + std::to_string(i + 1);
  });
  rec.table = finish(std::move(rec.table), rec.quantity, options, st.units_scale);
  return rec;
}

}  // namespace

std::vector<UffFrfRecord> parse_uff58_records(std::string_view bytes, const std::string& name,
                                              const FrfReadOptions& options) {
  check_scale(name, options.scale);
  LineReader lines(bytes);
  UffContext ctx{name, 0};
  UffState st;
  std::vector<UffFrfRecord> out;
  while (true) {
    // Blank lines and doubled '-1' between datasets are tolerated.
    int start_line = 0;
    std::string_view head;
    bool found = false;
    while (!lines.at_end()) {
      const int ln = lines.line();
      const std::string_view l = lines.next();
      if (trim(l).empty()) continue;
      if (is_delimiter(l)) {
        start_line = ln;
        found = true;
        continue;
      }
      if (!found)
        throw InputError(name + ": line " + std::to_string(ln) + ": expected '-1' (start of a dataset), found '" +
                         shown(trim(l)) + "'" + (ctx.record == 0 ? " (is this a Universal File?)" : ""));
      head = l;
      break;
    }
    if (head.empty()) {  // end of file: a trailing '-1' alone is fine after a dataset
      if (found && ctx.record == 0)
        throw InputError(name + ": line " + std::to_string(start_line) + ": '-1' is not followed by a dataset number");
      break;
    }
    ++ctx.record;
    const DatasetHeader h = parse_dataset_header(ctx, head, start_line + 1);
    if (h.number == 58) {
      if (auto rec = read_dataset58(ctx, lines, h, start_line, st, options)) out.push_back(std::move(*rec));
    } else if (h.number == 164 && !h.binary) {
      read_units(ctx, lines, st);
    } else {
      st.skipped.push_back("record " + std::to_string(ctx.record) + ": dataset " + std::to_string(h.number) +
                           " is not an FRF");
      if (h.binary) {
        for (long long i = 0; i < h.ascii_lines && !lines.at_end(); ++i) lines.next();
        lines.skip_bytes(static_cast<std::size_t>(std::min<long long>(h.bytes, static_cast<long long>(lines.remaining()))));
        expect_delimiter_after_binary(ctx, lines, h.bytes);
      } else {
        skip_to_delimiter(lines);
      }
    }
  }
  if (ctx.record == 0) throw InputError(name + ": empty file (no dataset)");
  if (out.empty()) {
    std::string why;
    for (const auto& s : st.skipped) why += (why.empty() ? "" : "; ") + s;
    throw InputError(name + ": no FRF record (dataset 58 with function type 4): " + why);
  }
  return out;
}

std::vector<UffFrfRecord> read_uff58_records(const std::filesystem::path& file, const FrfReadOptions& options) {
  check_scale(file.string(), options.scale);
  return parse_uff58_records(read_bytes(file), file.string(), options);
}

std::vector<FrfTable> read_uff58(const std::filesystem::path& file, const FrfReadOptions& options) {
  std::vector<FrfTable> out;
  for (auto& r : read_uff58_records(file, options)) out.push_back(std::move(r.table));
  return out;
}

}  // namespace chatter
