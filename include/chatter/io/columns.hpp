// A table as named columns: one definition of a table's column names,
// units (in each name) and values, from which its CSV is written
// (columns_csv) and which Python hands over as NumPy arrays (a
// ColumnRecord's columns, chatter/records/columns.hpp). NaN is an empty cell
// (no value in this row); +inf is written "inf" (no limit below the searched
// depth), as every table of the CLI.
#pragma once

#include <complex>
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

namespace chatter {

/// One named column: one value per row, or a rows × `cols` grid stored row
/// by row (`cols` > 0; e.g. the spectral radius over speed × depth).
struct Column {
  using Values = std::variant<std::vector<double>, std::vector<int>, std::vector<bool>, std::vector<std::string>,
                              std::vector<std::complex<double>>>;
  std::string name;
  Values values;
  std::size_t cols = 0;

  Column(std::string n, Values v, std::size_t grid_cols = 0)
      : name(std::move(n)), values(std::move(v)), cols(grid_cols) {}
  /// Its number of values (rows × cols for a grid).
  std::size_t size() const;
};

/// `v` times `factor`, element by element: a column in the unit its name
/// says (m to mm: 1e3, m to um: 1e6).
inline std::vector<double> scaled(const std::vector<double>& v, double factor) {
  std::vector<double> out;
  out.reserve(v.size());
  for (const double x : v) out.push_back(x * factor);
  return out;
}

/// The columns (one-value-per-row, all the same length) as CSV: a header of
/// the names, then one line per row; numbers as table_number (10
/// significant digits), NaN empty, booleans 1 or 0, text as is.
/// @pre no grid and no complex column; every column of the same size.
std::string columns_csv(const std::vector<Column>& columns);

}  // namespace chatter
