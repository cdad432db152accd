// FRF file readers: CSV and tab `.frf` (the Universal File 58 / 58b reader:
// frf_uff.cpp; the text helpers they share: frf_text.hpp).
// Format notes and tolerated quirks: docs/frf.md.
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

namespace frf_detail {

// ------------------------------------------------------------------ text

std::string read_bytes(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw InputError(file.string() + ": cannot read file (is a directory)");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot read file (" + std::strerror(errno) + ")");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(file.string() + ": cannot read file (read error)");
  return bytes;
}

std::string_view trim_right(std::string_view s) {
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string shown(std::string_view s) {
  std::string out;
  for (const char c : s.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    out += (u >= 0x20 && u < 0x7f) ? c : '?';
  }
  if (s.size() > 40) out += "...";
  return out;
}

std::optional<double> parse_number(std::string_view field) {
  field = trim(field);
  if (field.empty() || field.size() > 64) return std::nullopt;
  std::array<char, 80> buf{};
  std::size_t n = 0;
  for (char c : field) {
    if (c == 'D' || c == 'd') c = 'E';
    buf[n++] = c;
  }
  auto attempt = [](const char* b, const char* e) {
    return detail::text::parse_double(std::string_view(b, static_cast<std::size_t>(e - b)));
  };
  if (auto v = attempt(buf.data(), buf.data() + n)) return v;
  // Fortran: mantissa followed directly by a signed exponent (no letter).
  for (std::size_t i = n; i-- > 1;) {
    if ((buf[i] == '+' || buf[i] == '-') && (std::isdigit(static_cast<unsigned char>(buf[i - 1])) || buf[i - 1] == '.')) {
      std::array<char, 82> alt{};
      std::copy(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(i), alt.begin());
      alt[i] = 'E';
      std::copy(buf.begin() + static_cast<std::ptrdiff_t>(i), buf.begin() + static_cast<std::ptrdiff_t>(n),
                alt.begin() + static_cast<std::ptrdiff_t>(i) + 1);
      return attempt(alt.data(), alt.data() + n + 1);
    }
  }
  return std::nullopt;
}

std::optional<long long> parse_integer(std::string_view field) {
  return detail::text::parse_integer<long long>(trim(field));
}

std::vector<std::string_view> split_blanks(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_blank(s[i])) ++i;
    const std::size_t b = i;
    while (i < s.size() && !is_blank(s[i])) ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

// ------------------------------------------------------------ validation


void check_scale(const std::string& whole, double scale) {
  if (!std::isfinite(scale) || scale == 0.0)
    throw InputError(whole + ": scale = " + number_text(scale, 10) + ": must be a finite, non-zero factor");
}

FrfTable finish(FrfTable t, FrfQuantity q, const FrfReadOptions& options, double extra_scale) {
  const double s = options.scale * extra_scale;
  for (Complex& v : t.value) v *= s;
  if (options.drop_zero_hz && q != FrfQuantity::kReceptance && !t.frequency_hz.empty() && t.frequency_hz[0] == 0.0) {
    t.frequency_hz.erase(t.frequency_hz.begin());
    t.value.erase(t.value.begin());
    if (t.frequency_hz.size() < 2)
      throw InputError(t.source + ": fewer than 2 frequency lines once the 0 Hz line is dropped");
  }
  return to_receptance(std::move(t), q);
}

}  // namespace frf_detail

namespace {

using namespace frf_detail;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// ---------------------------------------------------------- CSV and tab

bool is_comment(std::string_view l) {
  return l.starts_with('#') || l.starts_with('%') || l.starts_with('!') || l.starts_with("//");
}

/// Splits a delimited line: ';' (decimal comma allowed), ',', else tabs and blanks.
std::vector<std::string> split_fields(std::string_view l) {
  std::vector<std::string> out;
  auto split_on = [&](char sep, bool decimal_comma) {
    detail::text::split_delimited(l, sep, /*quotes=*/false, out);
    if (decimal_comma)
      for (std::string& f : out) std::replace(f.begin(), f.end(), ',', '.');
  };
  if (l.find(';') != std::string_view::npos) {
    split_on(';', true);
  } else if (l.find(',') != std::string_view::npos) {
    split_on(',', false);
  } else {
    for (const auto f : split_blanks(l)) out.emplace_back(f);
  }
  // A trailing separator ("1,2,3,") leaves one empty last field: tolerated.
  if (out.size() > 3 && out.back().empty()) out.pop_back();
  return out;
}

enum class HeaderPolicy { kFirstLineOnly, kAnyLeadingLines };

FrfTable parse_delimited(std::string_view bytes, const std::string& name, const FrfReadOptions& options,
                         HeaderPolicy policy) {
  check_scale(name, options.scale);
  LineReader lines(bytes);
  FrfTable t;
  t.source = name;
  std::vector<int> line_of;
  bool data_started = false;
  int content_lines = 0;
  while (!lines.at_end()) {
    const int ln = lines.line();
    const std::string_view l = trim(lines.next());
    if (l.empty() || is_comment(l)) continue;
    ++content_lines;
    const std::vector<std::string> fields = split_fields(l);
    if (!data_started && !parse_number(fields[0])) {
      const bool header_allowed = policy == HeaderPolicy::kAnyLeadingLines || content_lines == 1;
      if (header_allowed) continue;  // header line
    }
    data_started = true;
    if (fields.size() != 3)
      throw InputError(name + ": line " + std::to_string(ln) + ": expected 3 columns (frequency_hz, real, imag), got " +
                       std::to_string(fields.size()));
    double v[3];
    for (std::size_t c = 0; c < 3; ++c) {
      const auto x = parse_number(fields[c]);
      if (!x)
        throw InputError(name + ": line " + std::to_string(ln) + ": non-numeric field '" + shown(fields[c]) +
                         "' in column " + std::to_string(c + 1) + " (expected frequency_hz, real, imag)");
      v[c] = *x;
    }
    t.frequency_hz.push_back(v[0]);
    t.value.emplace_back(v[1], v[2]);
    line_of.push_back(ln);
  }
  if (bytes.empty() || trim(bytes).empty()) throw InputError(name + ": empty file (no FRF lines)");
  if (t.frequency_hz.empty()) throw InputError(name + ": no numeric line (expected frequency_hz, real, imag)");
  validate(t, name, [&](std::size_t i) { return name + ": line " + std::to_string(line_of[i]); });
  return finish(std::move(t), options.quantity.value_or(FrfQuantity::kReceptance), options, 1.0);
}

}  // namespace

// --------------------------------------------------------------- public

const char* to_string(FrfQuantity q) {
  switch (q) {
    case FrfQuantity::kReceptance: return "receptance";
    case FrfQuantity::kMobility: return "mobility";
    case FrfQuantity::kAccelerance: return "accelerance";
  }
  return "?";
}

std::optional<FrfQuantity> parse_frf_quantity(const std::string& name) {
  std::string s;
  for (const char c : name) s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (s == "receptance" || s == "compliance") return FrfQuantity::kReceptance;
  if (s == "mobility") return FrfQuantity::kMobility;
  if (s == "accelerance" || s == "inertance") return FrfQuantity::kAccelerance;
  return std::nullopt;
}

FrfTable to_receptance(FrfTable t, FrfQuantity q) {
  if (q == FrfQuantity::kReceptance) return t;
  for (std::size_t i = 0; i < t.frequency_hz.size() && i < t.value.size(); ++i) {
    const double w = kTwoPi * t.frequency_hz[i];
    if (w == 0.0)
      throw InputError(t.source + ": frequency line " + std::to_string(i + 1) + " is at 0 Hz: " + to_string(q) +
                       " cannot be converted to receptance there (division by " +
                       (q == FrfQuantity::kMobility ? "jω" : "−ω²") + " = 0); drop that line");
    if (q == FrfQuantity::kMobility)
      t.value[i] /= Complex(0.0, w);
    else
      t.value[i] /= -(w * w);
  }
  return t;
}

FrfTable parse_frf_csv(std::string_view text, const std::string& origin, const FrfReadOptions& options) {
  return parse_delimited(text, origin, options, HeaderPolicy::kFirstLineOnly);
}
FrfTable parse_frf_tab(std::string_view text, const std::string& origin, const FrfReadOptions& options) {
  return parse_delimited(text, origin, options, HeaderPolicy::kAnyLeadingLines);
}

FrfTable read_frf_csv(const std::filesystem::path& file, const FrfReadOptions& options) {
  check_scale(file.string(), options.scale);
  return parse_frf_csv(read_bytes(file), file.string(), options);
}
FrfTable read_frf_csv(const std::filesystem::path& file, FrfQuantity quantity, double scale) {
  FrfReadOptions o;
  o.quantity = quantity;
  o.scale = scale;
  return read_frf_csv(file, o);
}
FrfTable read_frf_tab(const std::filesystem::path& file, const FrfReadOptions& options) {
  check_scale(file.string(), options.scale);
  return parse_frf_tab(read_bytes(file), file.string(), options);
}
FrfTable read_frf_tab(const std::filesystem::path& file, FrfQuantity quantity, double scale) {
  FrfReadOptions o;
  o.quantity = quantity;
  o.scale = scale;
  return read_frf_tab(file, o);
}

}  // namespace chatter
