// A result whose numbers are tables: named columns (chatter/io/columns.hpp:
// the CSV's columns, the unit in each name) beside a JSON record of what the
// columns do not hold.
// Built in the records layer, like every record; Python turns one into a
// dict of NumPy arrays by its one converter (python/module_common.cpp,
// to_python), so no binding writes a result key of its own. JSON text has
// no NaN and no infinity; a column keeps them (NaN: no value in this row,
// +inf: no limit below the searched depth, as the CSV's "inf").
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/io/columns.hpp"  // Column

namespace chatter {

/// Columns that belong together inside the result (a tool path, a
/// spectrum, the measured lines of one FRF record): `at` is a JSON pointer
/// into the fields ("/path", "/records/0") to the object the columns join;
/// a missing last key is created as an empty object.
struct ColumnGroup {
  std::string at;
  std::vector<Column> columns;
};

/// A table result: the record's fields (JSON: names, warnings, notes, the
/// inputs echoed), its top-level columns and its groups of columns, in the
/// order a reader meets them. A key appears in exactly one of the three.
struct ColumnRecord {
  nlohmann::json fields = nlohmann::json::object();
  std::vector<Column> columns;
  std::vector<ColumnGroup> groups;
};

}  // namespace chatter
