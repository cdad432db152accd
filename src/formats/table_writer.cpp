#include "chatter/io/table_writer.hpp"
#include "chatter/io/columns.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "chatter/error.hpp"

namespace chatter {
namespace {

// printf's "%.10g" (the standard defines to_chars with a precision as that
// conversion in the C locale), without printf's cost: a simulated series
// prints millions of numbers.
std::string num(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, 10).ptr;
  return std::string(buf, end);
}

}  // namespace

std::string version() { return CHATTER_VERSION; }

std::string table_number(double x) { return num(x); }

void write_lobe_csv(std::ostream& os, const std::vector<StabilityLimit>& rows, const std::vector<ExtraColumn>& extra) {
  os << "spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe";
  for (const ExtraColumn& c : extra) os << ',' << c.name;
  os << '\n';
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const StabilityLimit& r = rows[i];
    os << num(r.spindle_rpm) << ',' << num(r.depth_limit_m * 1e3) << ',';
    if (r.bounded()) os << num(r.chatter_frequency_hz) << ',' << r.lobe;
    else os << ',';
    for (const ExtraColumn& c : extra) os << ',' << c.values.at(i);
    os << '\n';
  }
}

void write_text_files(const std::vector<std::pair<std::filesystem::path, std::string>>& files) {
  std::vector<std::filesystem::path> temps;
  auto discard = [&] {
    std::error_code ec;
    for (const auto& t : temps)
      if (!t.empty()) std::filesystem::remove(t, ec);
  };
  // Special files (/dev/stdout, a pipe) are written in place, after every
  // regular file has been prepared: they cannot be replaced by a rename.
  // A symbolic link is written through, never replaced.
  auto special = [](const std::filesystem::path& p) {
    std::error_code ec;
    const auto st = std::filesystem::symlink_status(p, ec);
    return p == "/dev/stdout" || (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st));
  };
  for (const auto& [path, text] : files) {
    if (special(path)) {
      temps.emplace_back();
      continue;
    }
    std::filesystem::path tmp = path;
    tmp += ".partial";
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) {
      discard();
      throw InputError(path.string() + ": cannot open for writing (does the directory exist?)");
    }
    temps.push_back(tmp);
    f << text;
    f.close();
    if (!f) {
      discard();
      throw InputError(path.string() + ": write failed (disk full?)");
    }
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (temps[i].empty()) {
      if (files[i].first == "/dev/stdout") {  // share std::cout's buffer and file offset
        std::cout << files[i].second << std::flush;
        continue;
      }
      std::error_code ec;
      const bool regular_target = std::filesystem::is_regular_file(files[i].first, ec);
      std::ofstream f(files[i].first, std::ios::binary | (regular_target ? std::ios::trunc : std::ios::app));
      f << files[i].second;
      f.close();
      if (!f) {
        discard();
        throw InputError(files[i].first.string() + ": write failed");
      }
      continue;
    }
    std::error_code ec;
    std::filesystem::rename(temps[i], files[i].first, ec);
    if (ec) {
      discard();
      throw InputError(files[i].first.string() + ": cannot replace (" + ec.message() + ")");
    }
  }
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  write_text_files({{path, text}});
}

std::size_t Column::size() const {
  return std::visit([](const auto& v) { return v.size(); }, values);
}

std::string columns_csv(const std::vector<Column>& columns) {
  std::ostringstream o;
  for (std::size_t c = 0; c < columns.size(); ++c) o << (c ? "," : "") << columns[c].name;
  o << '\n';
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  for (const Column& c : columns)
    if (c.cols != 0 || c.size() != rows || std::holds_alternative<std::vector<std::complex<double>>>(c.values))
      throw std::logic_error("columns_csv: column " + c.name + " is a grid, complex or of another length");
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c) o << ',';
      std::visit(
          [&](const auto& v) {
            using T = typename std::decay_t<decltype(v)>::value_type;
            if constexpr (std::is_same_v<T, double>) {
              if (!std::isnan(v[r])) o << table_number(v[r]);
            } else if constexpr (std::is_same_v<T, bool>) {
              o << (v[r] ? '1' : '0');
            } else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, std::string>) {
              o << v[r];
            }
          },
          columns[c].values);
    }
    o << '\n';
  }
  return o.str();
}

}  // namespace chatter
