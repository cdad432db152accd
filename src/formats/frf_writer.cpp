// FRF file writers: CSV, tab `.frf`, Universal File dataset 58 / 58b.
// They write what the readers in frf_reader.cpp read; docs/frf.md.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/frf.hpp"

namespace chatter {
namespace {

void check_writable(const FrfTable& t) {
  try {
    validate(t);
  } catch (const InputError& e) {
    throw std::invalid_argument(std::string("cannot write FRF: ") + e.what());
  }
}

std::string format(const char* fmt, auto... args) {
  std::array<char, 256> buf{};
  const int n = std::snprintf(buf.data(), buf.size(), fmt, args...);
  if (n < 0 || static_cast<std::size_t>(n) >= buf.size()) throw std::logic_error("FRF writer: line too long");
  return std::string(buf.data(), static_cast<std::size_t>(n));
}

void write_file(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(file.string() + ": cannot open for writing (does the directory exist?)");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.flush();
  if (!out) throw InputError(file.string() + ": write failed (disk full?)");
}

int ordinate_spec_type(FrfQuantity q) {
  switch (q) {
    case FrfQuantity::kReceptance: return 8;
    case FrfQuantity::kMobility: return 11;
    case FrfQuantity::kAccelerance: return 12;
  }
  return 0;
}

const char* ordinate_label(FrfQuantity q) {
  switch (q) {
    case FrfQuantity::kReceptance: return "Displacement";
    case FrfQuantity::kMobility: return "Velocity";
    case FrfQuantity::kAccelerance: return "Acceleration";
  }
  return "NONE";
}

const char* ordinate_unit(FrfQuantity q) {
  switch (q) {
    case FrfQuantity::kReceptance: return "m";
    case FrfQuantity::kMobility: return "m/s";
    case FrfQuantity::kAccelerance: return "m/s^2";
  }
  return "NONE";
}

template <class T>
void append_binary(std::string& out, T v) {
  static_assert(sizeof(T) == 4 || sizeof(T) == 8);
  auto b = std::bit_cast<std::array<char, sizeof(T)>>(v);
  if constexpr (std::endian::native == std::endian::big) std::reverse(b.begin(), b.end());
  out.append(b.data(), b.size());
}

std::string ascii_line_80(std::string s) {
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = ' ';
  return s.substr(0, 80);
}

std::string dataset58(const FrfTable& t, const UffWriteOptions& o) {
  check_writable(t);
  const std::size_t n = t.size();
  double x_min = 0.0, x_inc = 0.0;
  if (o.even_abscissa) {
    x_min = t.frequency_hz.front();
    x_inc = (t.frequency_hz.back() - x_min) / static_cast<double>(n - 1);
    const double span = t.frequency_hz.back() - x_min;
    for (std::size_t i = 0; i < n; ++i)
      if (std::abs(x_min + static_cast<double>(i) * x_inc - t.frequency_hz[i]) > 1e-9 * span)
        throw std::invalid_argument("cannot write FRF " + t.source + " with even abscissa: line " + std::to_string(i + 1) +
                                    " is off the even grid (write it with even_abscissa = false)");
  }
  const int ord_type = o.complex_data ? (o.double_precision ? 6 : 5) : (o.double_precision ? 4 : 2);
  // Values in file order.
  std::vector<double> data;
  std::vector<bool> is_abscissa;
  for (std::size_t i = 0; i < n; ++i) {
    if (!o.even_abscissa) {
      data.push_back(t.frequency_hz[i]);
      is_abscissa.push_back(true);
    }
    data.push_back(t.value[i].real());
    is_abscissa.push_back(false);
    if (o.complex_data) {
      data.push_back(t.value[i].imag());
      is_abscissa.push_back(false);
    }
  }
  const std::size_t size = o.double_precision ? 8 : 4;
  std::string s = format("%6d\n", -1);
  if (o.binary)
    s += format("%6db%6d%6d%12d%12lld%6d%6d%12d%12d\n", 58, 1, 2, 11, static_cast<long long>(data.size() * size), 0, 0, 0, 0);
  else
    s += format("%6d\n", 58);
  s += ascii_line_80(o.id1) + "\n";
  s += ascii_line_80(t.source) + "\n";
  s += "NONE\nNONE\nNONE\n";
  s += format("%5d%10d%5d%10d %-10s%10d%4d %-10s%10d%4d\n", 4, 1, 0, 0, "NONE", o.response_node, o.response_direction,
              "NONE", o.reference_node, o.reference_direction);
  s += format("%10d%10zu%10d%13.5E%13.5E%13.5E\n", ord_type, n, o.even_abscissa ? 1 : 0, x_min, x_inc, 0.0);
  s += format("%10d%5d%5d%5d %-20s %-20s\n", 18, 0, 0, 0, "Frequency", "Hz");
  s += format("%10d%5d%5d%5d %-20s %-20s\n", ordinate_spec_type(o.quantity), 1, 0, 0, ordinate_label(o.quantity),
              ordinate_unit(o.quantity));
  s += format("%10d%5d%5d%5d %-20s %-20s\n", 13, 0, 1, 0, "Force", "N");
  s += format("%10d%5d%5d%5d %-20s %-20s\n", 0, 0, 0, 0, "NONE", "NONE");
  if (o.binary) {
    for (const double v : data) {
      if (o.double_precision)
        append_binary(s, v);
      else
        append_binary(s, static_cast<float>(v));
    }
    s += "\n";
  } else {
    // Dataset 58 columns: single 6E13.5; double even 4E20.12; double uneven
    // real 2(E13.5,E20.12); double uneven complex E13.5,2E20.12. Abscissa
    // always E13.5.
    const std::size_t per_line = !o.double_precision ? 6 : (o.even_abscissa ? 4 : (o.complex_data ? 3 : 4));
    std::string line;
    for (std::size_t i = 0; i < data.size(); ++i) {
      line += (is_abscissa[i] || !o.double_precision) ? format("%13.5E", data[i]) : format("%20.12E", data[i]);
      if ((i + 1) % per_line == 0 || i + 1 == data.size()) {
        s += line + "\n";
        line.clear();
      }
    }
  }
  s += format("%6d\n", -1);
  return s;
}

}  // namespace

void write_frf_csv(const std::filesystem::path& file, const FrfTable& t, bool header) {
  check_writable(t);
  std::string s = header ? "frequency_hz,real,imag\n" : "";
  for (std::size_t i = 0; i < t.size(); ++i)
    s += format("%.17g,%.17g,%.17g\n", t.frequency_hz[i], t.value[i].real(), t.value[i].imag());
  write_file(file, s);
}

void write_frf_tab(const std::filesystem::path& file, const FrfTable& t) {
  check_writable(t);
  std::string s = "# frequency (Hz)\treal (m/N)\timaginary (m/N)\n";
  for (std::size_t i = 0; i < t.size(); ++i)
    s += format("%.17g\t%.17g\t%.17g\n", t.frequency_hz[i], t.value[i].real(), t.value[i].imag());
  write_file(file, s);
}

void write_uff58(const std::filesystem::path& file, const std::vector<FrfTable>& tables, const UffWriteOptions& options) {
  if (tables.empty()) throw std::invalid_argument("write_uff58: no table to write");
  std::string s;
  for (const FrfTable& t : tables) s += dataset58(t, options);
  write_file(file, s);
}

}  // namespace chatter
