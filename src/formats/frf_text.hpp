// Internal to src/formats: the text helpers the FRF readers share (CSV and
// tab in frf_reader.cpp, Universal File 58 in frf_uff.cpp; docs/frf.md).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/io/frf.hpp"
#include "text.hpp"

namespace chatter::frf_detail {

using detail::text::is_blank;
using detail::text::trim;

/// The whole file. @throws InputError "<file>: cannot read file (...)".
std::string read_bytes(const std::filesystem::path& file);
std::string_view trim_right(std::string_view s);
/// A field as shown in a message: printable ASCII only, at most 40 characters.
std::string shown(std::string_view s);
/// Parses a whole field as a number: C / Fortran forms, `D` exponents and the
/// Fortran form without exponent letter for 3-digit exponents
/// (`1.23456-100`). Leading '+' allowed. Nullopt unless the whole field is a
/// number.
std::optional<double> parse_number(std::string_view field);
std::optional<long long> parse_integer(std::string_view field);
/// The fields of a line separated by blanks (spaces, tabs).
std::vector<std::string_view> split_blanks(std::string_view s);

/// Lines of a text with their 1-based numbers; a final line without newline
/// counts; `\r\n` and a lone `\r` at the end of a line are removed.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {
    if (text_.starts_with("\xEF\xBB\xBF")) pos_ = 3;  // UTF-8 byte-order mark
  }
  bool at_end() const { return pos_ >= text_.size(); }
  /// Number of the line the next call to next() returns.
  int line() const { return line_; }
  std::size_t position() const { return pos_; }
  std::string_view next() {
    const std::size_t e = text_.find('\n', pos_);
    std::string_view l = text_.substr(pos_, e == std::string_view::npos ? std::string_view::npos : e - pos_);
    pos_ = e == std::string_view::npos ? text_.size() : e + 1;
    ++line_;
    while (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    return l;
  }
  /// Skips `n` raw bytes (binary data), counting the newlines in them.
  void skip_bytes(std::size_t n) {
    const std::size_t e = std::min(text_.size(), pos_ + n);
    line_ += static_cast<int>(std::count(text_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                         text_.begin() + static_cast<std::ptrdiff_t>(e), '\n'));
    pos_ = e;
  }
  std::size_t remaining() const { return text_.size() - std::min(pos_, text_.size()); }
  std::string_view rest() const { return text_.substr(pos_); }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

/// @throws InputError "<whole>: scale = ...: must be a finite, non-zero factor".
void check_scale(const std::string& whole, double scale);
/// Scale, drop 0 Hz if asked, convert to receptance.
FrfTable finish(FrfTable t, FrfQuantity q, const FrfReadOptions& options, double extra_scale);

}  // namespace chatter::frf_detail
