// The measurements file of `chatter adapt` (include/chatter/io/optimization_files.hpp).
#include "chatter/io/optimization_files.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include "chatter/error.hpp"
#include "text.hpp"

namespace chatter {

std::vector<IndexValues> parse_measurements(std::string_view text, const std::string& origin, Operation operation) {
  namespace t = detail::text;
  std::vector<IndexValues> rows;
  std::vector<int> column;  // index of each column, -1 for `iteration`
  std::vector<std::string> fields;
  std::size_t line_no = 0, start = 0;
  bool header = false;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = t::trim(text.substr(start, end - start));
    ++line_no;
    start = end + 1;
    const std::string where = origin + ":" + std::to_string(line_no) + ": ";
    if (line.empty() || line.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    t::split_delimited(line, ',', false, fields);
    if (!header) {
      header = true;
      for (const std::string& name : fields) {
        int c = -2;
        if (name == "iteration") c = -1;
        else if (const auto i = index_from_name(name, operation)) c = static_cast<int>(*i);
        if (c == -2)
          throw InputError(where + "unknown column \"" + name + "\" (expected iteration or an index: " +
                           index_names(operation) + ")");
        if (std::find(column.begin(), column.end(), c) != column.end())
          throw InputError(where + "column \"" + name + "\" appears twice");
        column.push_back(c);
      }
      if (end == text.size()) break;
      continue;
    }
    if (fields.size() != column.size())
      throw InputError(where + std::to_string(fields.size()) + " fields: the header has " +
                       std::to_string(column.size()));
    IndexValues v = unknown_indices();
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (fields[k].empty()) continue;
      const auto x = t::parse_double(fields[k]);
      if (column[k] == -1) {
        if (!x || *x != static_cast<double>(rows.size() + 1))
          throw InputError(where + "iteration = " + fields[k] + ": must be " + std::to_string(rows.size() + 1) +
                           " (rows in order, one per iteration)");
        continue;
      }
      if (!x || !std::isfinite(*x) || !(*x > 0.0))
        throw InputError(where + std::string(index_name(static_cast<PerformanceIndex>(column[k]), operation)) +
                         " = " + fields[k] + ": must be a number > 0 (empty: not measured)");
      v[static_cast<std::size_t>(column[k])] = *x;
    }
    rows.push_back(v);
    if (end == text.size()) break;
  }
  if (!header) throw InputError(origin + ": no header (a line naming the columns: iteration, " +
                                index_names(operation) + ")");
  if (rows.empty()) throw InputError(origin + ": no measurement rows");
  return rows;
}

std::vector<IndexValues> read_measurements(const std::filesystem::path& file, Operation operation) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot read file");
  std::ostringstream s;
  s << in.rdbuf();
  return parse_measurements(s.str(), file.string(), operation);
}

}  // namespace chatter
