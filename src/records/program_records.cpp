// `chatter program`'s record, CSV and annotated program
// (chatter/records/program.hpp; every key: docs/program.md "The record").
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/io/table_writer.hpp"
#include "chatter/records.hpp"
#include "chatter/records/program.hpp"

namespace chatter {
namespace {

using json = nlohmann::json;

// The columns in record order: name, and the row's value (NaN = null / empty).
struct ProgramColumn {
  const char* name;
  double (*get)(const ProgramRow&);
  bool milling, turning;
};
const ProgramColumn kColumns[] = {
    {"spindle_rpm", [](const ProgramRow& r) { return r.spindle_rpm; }, true, true},
    {"feed_per_tooth_mm", [](const ProgramRow& r) { return r.air ? NAN : r.feed; }, true, false},
    {"feed_per_rev_mm", [](const ProgramRow& r) { return r.air ? NAN : r.feed; }, false, true},
    {"axial_depth_mm", [](const ProgramRow& r) { return r.air ? NAN : r.axial_depth_mm; }, true, false},
    {"radial_depth_mm", [](const ProgramRow& r) { return r.air ? NAN : r.radial_depth_mm; }, true, false},
    {"entry_angle_deg", [](const ProgramRow& r) { return r.air ? NAN : r.entry_angle_deg; }, true, false},
    {"exit_angle_deg", [](const ProgramRow& r) { return r.air ? NAN : r.exit_angle_deg; }, true, false},
    {"depth_mm", [](const ProgramRow& r) { return r.air ? NAN : r.depth_mm; }, true, true},
    {"position_mm", [](const ProgramRow& r) { return r.air ? NAN : r.position_mm; }, false, true},
    {"diameter_mm", [](const ProgramRow& r) { return r.air ? NAN : r.diameter_mm; }, false, true},
    {"removal_rate_mm3_per_s", [](const ProgramRow& r) { return r.removal_rate_mm3_per_s; }, true, true},
    {"power_kw", [](const ProgramRow& r) { return r.power_kw; }, true, true},
    {"torque_nm", [](const ProgramRow& r) { return r.torque_nm; }, true, true},
    {"force_n", [](const ProgramRow& r) { return r.force_n; }, true, true},
    {"depth_limit_mm", [](const ProgramRow& r) { return r.depth_limit_mm; }, true, true},
    {"margin", [](const ProgramRow& r) { return r.margin; }, true, true},
    {"chatter_frequency_hz", [](const ProgramRow& r) { return r.chatter_frequency_hz; }, true, true},
    {"surface_location_error_um", [](const ProgramRow& r) { return r.part_error_um; }, true, false},
    {"diametral_error_um", [](const ProgramRow& r) { return r.part_error_um; }, false, true},
    {"length_mm", [](const ProgramRow& r) { return r.length_mm; }, true, true},
    {"time_s", [](const ProgramRow& r) { return r.time_s; }, true, true},
};

bool shown(const ProgramColumn& c, bool turning) { return turning ? c.turning : c.milling; }

std::string cell(double x) { return std::isfinite(x) ? table_number(x) : (std::isinf(x) ? "inf" : ""); }

std::string g(double x, const char* f = "%.4g") {
  char b[48];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

}  // namespace

json program_record(const ProgramReport& rep) {
  json rows = json::array();
  for (const ProgramRow& r : rep.rows) {
    json j;
    j["line"] = r.line;
    j["tool"] = r.tool;
    j["air"] = r.air;
    for (const ProgramColumn& c : kColumns)
      if (shown(c, rep.turning)) j[c.name] = finite_or_null(c.get(r));
    if (!rep.turning) {  // every engaged arc (one unless the stock gave two): [[entry, exit], ...], degrees
      json arcs = json::array();
      for (const auto& [en, ex] : r.arcs_deg) arcs.push_back({en, ex});
      j["engaged_arcs_deg"] = r.air ? json(nullptr) : arcs;
    }
    j["stable"] = r.air ? json(nullptr) : json(r.stable);
    j["overloaded"] = r.overloaded;
    j["notes"] = r.notes;
    if (r.fixed_rpm) j["fixed_spindle_rpm"] = *r.fixed_rpm;
    if (r.fixed_feed) j["fixed_feed"] = *r.fixed_feed;
    if (!r.fix_note.empty()) j["fix_note"] = r.fix_note;
    rows.push_back(std::move(j));
  }
  const ProgramSummary& s = rep.summary;
  json summary = {{"blocks", s.blocks},
                  {"cutting_blocks", s.cutting_blocks},
                  {"air_blocks", s.air_blocks},
                  {"unstable_blocks", s.unstable_blocks},
                  {"overloaded_blocks", s.overloaded_blocks},
                  {"worst_margin", finite_or_null(s.worst_margin)},
                  {"worst_line", s.worst_line},
                  {"removed_volume_mm3", s.removed_volume_mm3},
                  {"cutting_time_s", s.cutting_time_s},
                  {"solves", s.solves},
                  {"cache_hits", s.cache_hits}};
  json tools = json::array();
  std::map<int, std::string> methods(rep.methods.begin(), rep.methods.end());
  for (const auto& [tool, d] : rep.depth_max_mm)
    tools.push_back({{"tool", tool}, {"method", methods.count(tool) ? methods[tool] : ""}, {"depth_max_mm", d}});
  return {{"program", rep.program},
          {"job", rep.job},
          {"process", rep.turning ? "turning" : "milling"},
          {"tools", tools},
          {"summary", summary},
          {"rows", rows},
          {"warnings", rep.warnings},
          {"status", rep.ok() ? 0 : 3}};
}

ProgramPlotData program_plot_data(const ProgramReport& rep, double max_power_kw) {
  ProgramPlotData d;
  d.title = std::filesystem::path(rep.program).filename().string() + ": " + std::to_string(rep.summary.cutting_blocks) +
            " cutting blocks, " + std::to_string(rep.summary.unstable_blocks) + " unstable, " +
            std::to_string(rep.summary.overloaded_blocks) + " overloaded";
  d.turning = rep.turning;
  d.max_power_kw = max_power_kw;
  double t = 0.0;
  for (const ProgramRow& r : rep.rows) {
    ProgramPlotData::Block b;
    b.line = r.line;
    b.air = r.air;
    b.overloaded = r.overloaded;
    b.t0_s = t;
    if (!r.air) t += r.time_s;
    b.t1_s = t;
    b.margin = r.margin;
    b.power_kw = r.power_kw;
    b.depth_limit_mm = r.depth_limit_mm;
    b.depth_mm = r.depth_mm;
    b.part_error_um = r.part_error_um;
    b.position_mm = r.position_mm;
    for (const ProgramRow::AlongBar& a : r.along_bar) b.along_bar.push_back({a.position_mm, a.margin, a.part_error_um});
    b.x0 = r.start.x();
    b.y0 = r.start.y();
    b.z0 = r.start.z();
    b.x1 = r.end.x();
    b.y1 = r.end.y();
    b.z1 = r.end.z();
    d.blocks.push_back(b);
  }
  return d;
}

std::string program_csv(const ProgramReport& rep) {
  std::ostringstream os;
  os << "line,tool,air";
  for (const ProgramColumn& c : kColumns)
    if (shown(c, rep.turning)) os << "," << c.name;
  if (!rep.turning) os << ",engaged_arcs_deg";
  os << ",stable,overloaded\n";
  for (const ProgramRow& r : rep.rows) {
    os << r.line << "," << r.tool << "," << (r.air ? "true" : "false");
    for (const ProgramColumn& c : kColumns)
      if (shown(c, rep.turning)) os << "," << cell(c.get(r));
    if (!rep.turning) {  // "entry-exit" per arc, ';' between arcs
      os << ",";
      for (std::size_t k = 0; !r.air && k < r.arcs_deg.size(); ++k)
        os << (k ? ";" : "") << cell(r.arcs_deg[k].first) << "-" << cell(r.arcs_deg[k].second);
    }
    os << "," << (r.air ? "" : r.stable ? "true" : "false") << "," << (r.overloaded ? "true" : "false") << "\n";
  }
  return os.str();
}

namespace {

// The start and end of the first `letter` word on a G-code line outside its
// comments: the letter, then a number, a parameter (#5, #<name>) or a
// bracketed expression. A lexical scan of one line for --out, so that a
// changed S or F replaces the line's own word (two F words on one line is an
// interpreter error); the program itself is read only by LinuxCNC's.
std::optional<std::pair<std::size_t, std::size_t>> find_word(const std::string& line, char letter) {
  const char lower = static_cast<char>(letter - 'A' + 'a');
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == ';') return std::nullopt;
    if (c == '(') {
      const std::size_t close = line.find(')', i);
      if (close == std::string::npos) return std::nullopt;
      i = close;
      continue;
    }
    if (c == '[') {  // an expression (o-word conditions, axis words): skip it whole
      int depth = 0;
      for (; i < line.size(); ++i) {
        depth += line[i] == '[' ? 1 : line[i] == ']' ? -1 : 0;
        if (depth == 0) break;
      }
      continue;
    }
    if (c != letter && c != lower) continue;
    std::size_t j = i + 1;
    while (j < line.size() && line[j] == ' ') ++j;
    if (j < line.size() && line[j] == '[') {
      int depth = 0;
      for (; j < line.size(); ++j) {
        depth += line[j] == '[' ? 1 : line[j] == ']' ? -1 : 0;
        if (depth == 0) break;
      }
      return std::make_pair(i, std::min(j + 1, line.size()));
    }
    if (j < line.size() && line[j] == '#') {
      ++j;
      if (j < line.size() && line[j] == '<') {
        const std::size_t close = line.find('>', j);
        j = close == std::string::npos ? line.size() : close + 1;
      } else {
        while (j < line.size() && std::isdigit(static_cast<unsigned char>(line[j]))) ++j;
      }
      return std::make_pair(i, j);
    }
    while (j < line.size() && (std::isdigit(static_cast<unsigned char>(line[j])) || line[j] == '.' || line[j] == '+' ||
                               line[j] == '-' || line[j] == ' '))
      ++j;
    return std::make_pair(i, j);
  }
  return std::nullopt;
}

// `line` with its own `letter` word (if any) given `value`, else the word appended.
std::string set_word(const std::string& line, char letter, const std::string& value) {
  const auto w = find_word(line, letter);
  std::ostringstream out;  // (not operator+ on strings: g++ 12 warns of a false overflow there)
  if (!w)
    out << line << ' ' << letter << value;
  else
    out << std::string_view(line).substr(0, w->first) << letter << value << ' ' << std::string_view(line).substr(w->second);
  return out.str();
}

// The comment for one source line from every execution of it (a line in a
// loop or a subroutine runs several times, each with its own cut).
std::string line_comment(const std::vector<const ProgramRow*>& rows, std::size_t runs) {
  const ProgramRow* worst = nullptr;    // the smallest margin among the unstable
  const ProgramRow* heaviest = nullptr; // the largest power among the overloaded
  for (const ProgramRow* r : rows) {
    if (!r->stable && (!worst || r->margin < worst->margin)) worst = r;
    if (r->overloaded && (!heaviest || r->power_kw > heaviest->power_kw)) heaviest = r;
  }
  std::string c = "chatter:";
  if (worst)
    c += " unstable, margin " + g(worst->margin, "%.2f") + ", limit " + g(worst->depth_limit_mm, "%.3g") + " mm at S" +
         g(worst->spindle_rpm, "%.0f") +
         (std::isfinite(worst->chatter_frequency_hz) ? ", " + g(worst->chatter_frequency_hz, "%.0f") + " Hz" : "");
  if (heaviest)
    c += std::string(worst ? ";" : "") + " overloaded, " + g(heaviest->power_kw, "%.3g") + " kW " +
         g(heaviest->torque_nm, "%.3g") + " Nm";
  if (runs > 1) c += ", at worst, in " + std::to_string(rows.size()) + " of the line's " + std::to_string(runs) + " runs";
  const ProgramRow* fixed = worst ? worst : heaviest;
  if (fixed->fixed_rpm) c += "; speed set to S" + g(*fixed->fixed_rpm, "%.0f");
  double feed = NAN;
  for (const ProgramRow* r : rows)
    if (r->fixed_feed) feed = std::isnan(feed) ? *r->fixed_feed : std::min(feed, *r->fixed_feed);
  if (!std::isnan(feed)) c += "; feed set to F" + g(feed, "%.6g");
  for (const ProgramRow* r : rows)
    if (!r->fix_note.empty() && c.find(r->fix_note) == std::string::npos) c += "; " + r->fix_note;
  for (char& ch : c)
    if (ch == '(' || ch == ')') ch = ' ';  // a comment cannot hold parentheses
  return c;
}

}  // namespace

std::string annotate_program(const std::string& text, const ProgramReport& rep) {
  // What to say and change per source line (several moves may share one: a
  // loop's body runs once per pass). One speed per line: the unstable run
  // with the smallest margin's; one feed: the smallest any run needs.
  struct LineEdit {
    std::vector<const ProgramRow*> flagged;
    std::size_t runs = 0;
    std::optional<double> rpm, feed;
    double old_rpm = 0.0, old_feed = 0.0;
  };
  std::map<int, LineEdit> edits;
  for (const ProgramRow& r : rep.rows)
    if (r.line > 0) ++edits[r.line].runs;
  for (const ProgramRow& r : rep.rows) {
    if (r.air || r.line <= 0 || (r.stable && !r.overloaded)) continue;
    edits[r.line].flagged.push_back(&r);
  }
  for (auto& [line, e] : edits) {
    const ProgramRow* worst = nullptr;
    for (const ProgramRow* r : e.flagged) {
      if (r->fixed_rpm && (!worst || r->margin < worst->margin)) worst = r;
      if (r->fixed_feed && (!e.feed || *r->fixed_feed < *e.feed)) {
        e.feed = r->fixed_feed;
        e.old_feed = r->original_feed;
      }
    }
    if (worst) {
      e.rpm = worst->fixed_rpm;
      e.old_rpm = worst->spindle_rpm;
    }
  }
  std::ostringstream out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto it = edits.find(number);
    if (it == edits.end() || it->second.flagged.empty()) {
      out << line << "\n";
      continue;
    }
    const LineEdit& e = it->second;
    if (e.rpm) line = set_word(line, 'S', g(*e.rpm, "%.0f"));
    if (e.feed) line = set_word(line, 'F', g(*e.feed, "%.6g"));
    out << line << " (" << line_comment(e.flagged, e.runs) << ")\n";
    // S and F are modal: the next blocks get the program's own values back.
    if (e.rpm || e.feed) {
      if (e.rpm) out << "S" << g(e.old_rpm, "%.10g");
      if (e.feed) out << (e.rpm ? " " : "") << "F" << g(e.old_feed, "%.10g");
      out << " (chatter: restores the program's values)\n";
    }
  }
  return out.str();
}

}  // namespace chatter
