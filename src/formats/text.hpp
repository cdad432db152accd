// Internal: the one set of text helpers the file readers share (FRF tables,
// operations lists): trimming, splitting a delimited line, parsing a whole
// field as a number, and the "did you mean" of an unknown name (config keys,
// CSV headers, command-line options). Not part of the public API. Header-only, no allocation
// beyond the output fields; cost linear in the line length.
#pragma once

#include <algorithm>
#include <charconv>
#include <limits>
#include <span>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace chatter::detail::text {

/// Space, tab, CR, LF, form feed, vertical tab.
inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

/// `s` without leading and trailing blanks (is_blank).
inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

/// Splits `line` on `sep` into trimmed fields ("a, b," gives "a", "b", "").
/// With `quotes`, a field may be double-quoted (opening quote after optional
/// blanks), `""` inside standing for one quote; a quoted field keeps its
/// blanks. Returns false on an unterminated quote (with quotes only).
inline bool split_delimited(std::string_view line, char sep, bool quotes, std::vector<std::string>& out) {
  out.clear();
  std::string cur;
  bool quoted = false, was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"') {
        cur += c;
      } else if (i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else {
        quoted = false;
      }
    } else if (quotes && c == '"' && trim(cur).empty()) {
      cur.clear();
      quoted = was_quoted = true;
    } else if (c == sep) {
      out.emplace_back(was_quoted ? cur : std::string(trim(cur)));
      cur.clear();
      was_quoted = false;
    } else {
      cur += c;
    }
  }
  if (quoted) return false;
  out.emplace_back(was_quoted ? cur : std::string(trim(cur)));
  return true;
}

/// Whole-field decimal number as std::from_chars reads it, a leading '+'
/// allowed, no blanks. Out of range: strtod's ±HUGE_VAL or underflowed value
/// (the caller checks finiteness). Nullopt unless the whole field is a number.
inline std::optional<double> parse_double(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return std::nullopt;
  double v = 0.0;
  const char* e = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), e, v);
  if (ptr != e) return std::nullopt;
  if (ec == std::errc::result_out_of_range) return std::strtod(std::string(field).c_str(), nullptr);
  if (ec != std::errc()) return std::nullopt;
  return v;
}

/// Whole-field decimal integer, a leading '+' allowed, no blanks.
template <class Int = long long>
std::optional<Int> parse_integer(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return std::nullopt;
  Int v = 0;
  const char* e = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), e, v);
  if (ec != std::errc() || ptr != e) return std::nullopt;
  return v;
}

/// Levenshtein distance (insertions, deletions, substitutions of bytes).
/// Cost O(|a| |b|) time, O(|b|) memory.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The allowed name a near miss was meant to be (a typo, or a name written
/// without its unit suffix such as `stiffness` for `stiffness_n_per_m`);
/// empty if none is within max(2, |key| / 4) edits.
inline std::string_view near_miss(std::string_view key, std::span<const std::string_view> allowed) {
  std::string_view best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string_view candidate : allowed) {
    const bool unit_missing = candidate.size() > key.size() && candidate.starts_with(key) &&
                              candidate[key.size()] == '_' && !key.empty();
    const std::size_t d = unit_missing ? 1 : edit_distance(key, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  const std::size_t tolerance = std::max<std::size_t>(2, key.size() / 4);
  return best_distance <= tolerance ? best : std::string_view();
}

}  // namespace chatter::detail::text

