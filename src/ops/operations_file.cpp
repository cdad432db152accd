// The operations file: MachineLimits, parse_operations(), read_operations()
// and process_for() (include/chatter/operations.hpp, docs/operations.md
// "The operations file"). Plain text, no solver.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/operations.hpp"
#include "chatter/report.hpp"
#include "../formats/text.hpp"
#include "ops_internal.hpp"

namespace chatter {

using namespace detail::ops;

// ================================================================ machine

std::string MachineLimits::validate() const {
  std::ostringstream os;
  if (!(std::isfinite(rpm_min) && rpm_min > 0.0))
    os << "MachineLimits::rpm_min = " << rpm_min << ": must be > 0 rev/min";
  else if (!(std::isfinite(rpm_max) && rpm_max > rpm_min))
    os << "MachineLimits::rpm_max = " << rpm_max << ": must be > rpm_min (" << rpm_min << ")";
  else if (!(max_power_w > 0.0))
    os << "MachineLimits::max_power_w = " << max_power_w << ": must be > 0 W (+inf = no limit)";
  else if (!(max_torque_n_m > 0.0))
    os << "MachineLimits::max_torque_n_m = " << max_torque_n_m << ": must be > 0 N·m (+inf = no limit)";
  return os.str();
}

// ===================================================== operations file

namespace {

const std::vector<std::string> kRequiredColumns = {"id", "spindle_rpm", "depth_mm", "radial_immersion",
                                                   "feed_per_tooth_mm"};
const std::vector<std::string> kOptionalColumns = {"teeth", "milling_direction", "max_sle_um", "tolerance_um"};

using detail::text::trim;

// Splits one CSV line; fields may be double-quoted with "" for a quote.
// Returns false (and sets *error) on an unterminated quote.
bool split_csv(std::string_view line, std::vector<std::string>& out, std::string* error) {
  if (detail::text::split_delimited(line, ',', /*quotes=*/true, out)) return true;
  *error = "unterminated quote";
  return false;
}

// Parses a finite number; "" if fine, else the reason.
std::string parse_number(std::string_view s, double& x) {
  const std::optional<double> v = detail::text::parse_double(s);
  if (!v) return "not a number";
  x = *v;
  if (!std::isfinite(x)) return "must be a finite number";
  return "";
}

std::string parse_integer(std::string_view s, int& x) {
  const std::optional<int> v = detail::text::parse_integer<int>(s);
  if (!v) return "not an integer";
  x = *v;
  return "";
}

}  // namespace

namespace {

// The header line: each column known (a ';'-separated export and a near miss
// named), none twice, every required one present. @throws InputError.
std::map<std::string, std::size_t> read_header(std::string_view line, const std::string& where,
                                               std::vector<std::string>& header) {
  std::map<std::string, std::size_t> column;  // name -> index
  std::string err;
  if (!split_csv(line, header, &err)) throw InputError(where + "header: " + err);
  for (std::size_t i = 0; i < header.size(); ++i) {
    const std::string& h = header[i];
    const bool known = std::find(kRequiredColumns.begin(), kRequiredColumns.end(), h) != kRequiredColumns.end() ||
                       std::find(kOptionalColumns.begin(), kOptionalColumns.end(), h) != kOptionalColumns.end();
    if (!known) {
      // A spreadsheet exported with ';' (a decimal-comma locale): one
      // unknown column holding the separators.
      if (h.find(';') != std::string::npos)
        throw InputError(where + "header " + in_quotes(trim(line)) +
                         ": the file seems to use ';' as separator; chatter reads ',' (export as CSV with "
                         "commas)");
      std::string names;
      std::vector<std::string_view> known_names;
      for (const auto* list : {&kRequiredColumns, &kOptionalColumns})
        for (const auto& c : *list) {
          names += (names.empty() ? "" : ",") + c;
          known_names.emplace_back(c);
        }
      const std::string_view meant = detail::text::near_miss(h, known_names);
      throw InputError(where + "header column " + in_quotes(h) + ": unknown column (" +
                       (meant.empty() ? "" : "did you mean " + std::string(meant) + "? ") + "known: " + names +
                       "; a header line is required)");
    }
    if (column.count(h)) throw InputError(where + "header column " + in_quotes(h) + ": given twice");
    column[h] = i;
  }
  for (const auto& c : kRequiredColumns)
    if (!column.count(c)) {
      std::string req;
      for (const auto& r : kRequiredColumns) req += (req.empty() ? "" : ",") + r;
      throw InputError(where + "header lacks column " + in_quotes(c) + " (required: " + req + ")");
    }
  return column;
}

// One row's fields: what a field holds, read into `row`; each problem a
// reason (the row is rejected with all of them).
struct RowFields {
  const std::map<std::string, std::size_t>& column;
  const std::vector<std::string>& f;
  std::vector<std::string>& reasons;
  std::string_view field(const std::string& name) const {
    const auto it = column.find(name);
    return it == column.end() ? std::string_view{} : std::string_view(f[it->second]);
  }
  bool number(const std::string& name, double& x) const {
    const std::string_view s = field(name);
    if (s.empty()) {  // only the required columns are read without a value
      reasons.push_back(name + ": missing (required)");
      return false;
    }
    if (const std::string e = parse_number(s, x); !e.empty()) {
      reasons.push_back(name + " = " + in_quotes(s) + ": " + e);
      return false;
    }
    return true;
  }
};

void read_values(const RowFields& rf, bool milling, const MachineLimits& machine, OperationRow& row) {
  std::vector<std::string>& reasons = rf.reasons;
  auto field = [&](const std::string& name) { return rf.field(name); };
  auto number = [&](const std::string& name, double& x) { return rf.number(name, x); };
  double rpm = 0.0, depth_mm = 0.0;
  if (number("spindle_rpm", rpm)) {
    if (!(rpm > 0.0))
      reasons.push_back("spindle_rpm = " + num(rpm) + ": must be > 0 rev/min");
    else if (rpm < machine.rpm_min || rpm > machine.rpm_max)
      reasons.push_back("spindle_rpm = " + num(rpm) + ": outside the machine range [" + num(machine.rpm_min) +
                        ", " + num(machine.rpm_max) + "] rev/min");
  }
  if (number("depth_mm", depth_mm)) {
    if (!(depth_mm > 0.0)) reasons.push_back("depth_mm = " + num(depth_mm) + ": must be > 0 mm");
    else if (depth_mm > kMaxDepthMm)
      reasons.push_back("depth_mm = " + num(depth_mm) + ": at most " + num(kMaxDepthMm) +
                        " mm (no cut is a metre deep); a depth in um?");
  }
  row.spindle_rpm = rpm;
  row.depth_m = depth_mm * 1e-3;
  row.depth_mm = depth_mm;

  if (const std::string_view s = field("radial_immersion"); !s.empty()) {
    double ae = 0.0;
    if (!milling)
      reasons.push_back("radial_immersion = " + in_quotes(s) + ": only for milling (leave empty for turning)");
    else if (number("radial_immersion", ae)) {
      if (!(ae > 0.0 && ae <= 1.0)) reasons.push_back("radial_immersion = " + num(ae) + ": must be in (0, 1] (a_e/D)");
      else row.radial_immersion = ae;
    }
  }
  if (const std::string_view s = field("feed_per_tooth_mm"); !s.empty()) {
    double fz = 0.0;
    if (number("feed_per_tooth_mm", fz)) {
      if (!(fz > 0.0)) reasons.push_back("feed_per_tooth_mm = " + num(fz) + ": must be > 0 mm");
      else {
        row.feed_per_tooth_m = fz * 1e-3;
        row.feed_per_tooth_mm = fz;
      }
    }
  }
  if (const std::string_view s = field("teeth"); !s.empty()) {
    int nt = 0;
    if (!milling) reasons.push_back("teeth = " + in_quotes(s) + ": only for milling (leave empty for turning)");
    else if (const std::string e = parse_integer(s, nt); !e.empty())
      reasons.push_back("teeth = " + in_quotes(s) + ": " + e);
    else if (nt < 1) reasons.push_back("teeth = " + std::to_string(nt) + ": must be >= 1");
    else if (nt > kMaxTeeth) reasons.push_back("teeth = " + std::to_string(nt) + ": must be <= " + std::to_string(kMaxTeeth));
    else row.teeth = nt;
  }
  // Issue 27: the part's tolerance on the surface location error (milling)
  // or the diametral error (turning), µm; either name.
  for (const char* name : {"max_sle_um", "tolerance_um"})
    if (const std::string_view s = field(name); !s.empty()) {
      double tol = 0.0;
      if (number(name, tol)) {
        if (!(tol > 0.0)) reasons.push_back(std::string(name) + " = " + num(tol) + ": must be > 0 um");
        else if (row.max_error_m) reasons.push_back(std::string(name) + ": max_sle_um and tolerance_um both given");
        else row.max_error_m = tol * 1e-6;
      }
    }
  if (const std::string_view s = field("milling_direction"); !s.empty()) {
    if (!milling)
      reasons.push_back("milling_direction = " + in_quotes(s) + ": only for milling (leave empty for turning)");
    else if (s == "down") row.direction = MillingDirection::kDown;
    else if (s == "up") row.direction = MillingDirection::kUp;
    else reasons.push_back("milling_direction = " + in_quotes(s) + ": must be \"down\" or \"up\"");
  }
}

}  // namespace

OperationsFile parse_operations(std::string_view text, const std::string& origin, Operation operation,
                                const MachineLimits& machine) {
  if (const std::string e = machine.validate(); !e.empty()) throw InputError(origin + ": " + e);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte-order mark
  const bool milling = rotating_edges(operation);

  OperationsFile out;
  std::map<std::string, std::size_t> column;  // name -> index
  std::size_t n_columns = 0;
  std::vector<std::string> header;
  std::map<std::string, int> first_line_of_id;
  std::vector<std::string> f;
  int line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view t = trim(line);
    if (t.empty() || t.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    std::string err;
    const std::string where = origin + ":" + std::to_string(line_no) + ": ";
    if (header.empty()) {  // ---- header
      column = read_header(line, where, header);
      n_columns = header.size();
      if (end == text.size()) break;
      continue;
    }

    // ---- one operation
    RejectedRow bad{line_no, "", ""};
    std::vector<std::string> reasons;
    if (!split_csv(line, f, &err)) {
      out.rejected.push_back({line_no, "", err});
      if (end == text.size()) break;
      continue;
    }
    if (f.size() < n_columns) {
      std::string missing;
      for (std::size_t i = f.size(); i < n_columns; ++i) missing += (missing.empty() ? "" : ", ") + header[i];
      if (column.count("id") && column["id"] < f.size()) bad.id = f[column["id"]];
      bad.reason = "has " + std::to_string(f.size()) + " fields, the header has " + std::to_string(n_columns) +
                   " (missing column" + (n_columns - f.size() > 1 ? "s " : " ") + missing + ")";
      out.rejected.push_back(bad);
      if (end == text.size()) break;
      continue;
    }
    if (f.size() > n_columns) {
      bad.id = f[column["id"]];
      bad.reason = "has " + std::to_string(f.size()) + " fields, the header has " + std::to_string(n_columns) +
                   " (an unquoted comma?)";
      out.rejected.push_back(bad);
      if (end == text.size()) break;
      continue;
    }
    const RowFields rf{column, f, reasons};

    OperationRow row;
    row.line = line_no;
    row.id = std::string(rf.field("id"));
    bad.id = row.id;
    if (row.id.empty()) reasons.push_back("id: missing (required)");

    read_values(rf, milling, machine, row);
    if (!row.id.empty()) {
      const auto [it, inserted] = first_line_of_id.emplace(row.id, line_no);
      if (!inserted)
        reasons.push_back("duplicate id (first on line " + std::to_string(it->second) + ")");
    }
    if (reasons.empty()) {
      out.rows.push_back(std::move(row));
    } else {
      for (const auto& r : reasons) bad.reason += (bad.reason.empty() ? "" : "; ") + r;
      out.rejected.push_back(std::move(bad));
    }
    if (end == text.size()) break;
  }
  if (header.empty()) {
    std::string req;
    for (const auto& r : kRequiredColumns) req += (req.empty() ? "" : ",") + r;
    throw InputError(origin + ": no header line (expected the columns " + req + ")");
  }
  // A file that lists nothing must not read as "all stable" to a
  // post-processor: nothing checked is an error.
  if (out.rows.empty() && out.rejected.empty())
    throw InputError(origin + ": no operations (a header and no rows): nothing to check");
  return out;
}

OperationsFile read_operations(const std::filesystem::path& file, Operation operation, const MachineLimits& machine) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(file.string() + ": cannot read file (" + (err ? std::strerror(err) : "unknown reason") + ")");
  }
  std::ostringstream os;
  os << in.rdbuf();
  return parse_operations(os.str(), file.string(), operation, machine);
}

Process process_for(const Process& base, const OperationRow& row) {
  if (!base.rotating_edges()) {
    if (row.radial_immersion || row.teeth || row.direction)
      throw InputError("operation " + in_quotes(row.id) + ": immersion, teeth and direction are for milling only");
    // Kienzle's law: the regenerative coefficient at the row's own chip.
    return row.feed_per_tooth_m ? base.at_feed(*row.feed_per_tooth_m) : base;
  }
  MillingParameters p = base.milling_parameters();
  if (row.radial_immersion) p.radial_immersion = *row.radial_immersion;
  if (row.teeth) p.teeth = *row.teeth;
  if (row.direction) p.direction = *row.direction;
  try {
    Process out = Process::milling(p);
    out.set_speed_variation(base.speed_variation());
    return out;
  } catch (const InputError& e) {
    throw InputError("operation " + in_quotes(row.id) + ": " + e.what());
  }
}

}  // namespace chatter
