// `chatter program`'s record, CSV and annotated program
// (chatter/records/program.hpp; every key: docs/program.md "The record").
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/io/table_writer.hpp"
#include "chatter/records.hpp"
#include "chatter/records/program.hpp"

namespace chatter {
namespace {

using json = nlohmann::json;

// The columns in record order: name, and the row's value (NaN = null / empty).
struct Column {
  const char* name;
  double (*get)(const ProgramRow&);
  bool milling, turning;
};
const Column kColumns[] = {
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

bool shown(const Column& c, bool turning) { return turning ? c.turning : c.milling; }

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
    for (const Column& c : kColumns)
      if (shown(c, rep.turning)) j[c.name] = finite_or_null(c.get(r));
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
    b.t0_s = t;
    if (!r.air) t += r.time_s;
    b.t1_s = t;
    b.margin = r.margin;
    b.power_kw = r.power_kw;
    b.depth_limit_mm = r.depth_limit_mm;
    b.depth_mm = r.depth_mm;
    b.part_error_um = r.part_error_um;
    b.position_mm = r.position_mm;
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
  for (const Column& c : kColumns)
    if (shown(c, rep.turning)) os << "," << c.name;
  os << ",stable,overloaded\n";
  for (const ProgramRow& r : rep.rows) {
    os << r.line << "," << r.tool << "," << (r.air ? "true" : "false");
    for (const Column& c : kColumns)
      if (shown(c, rep.turning)) os << "," << cell(c.get(r));
    os << "," << (r.air ? "" : r.stable ? "true" : "false") << "," << (r.overloaded ? "true" : "false") << "\n";
  }
  return os.str();
}

std::string annotate_program(const std::string& text, const ProgramReport& rep) {
  // What to say and change per source line (several moves may share one).
  struct LineEdit {
    std::vector<std::string> comments;
    std::optional<double> rpm, feed;
    double old_rpm = 0.0, old_feed = 0.0;
  };
  std::map<int, LineEdit> edits;
  for (const ProgramRow& r : rep.rows) {
    if (r.air || r.line <= 0 || (r.stable && !r.overloaded)) continue;
    LineEdit& e = edits[r.line];
    std::string c = "chatter:";
    if (!r.stable)
      c += " unstable, margin " + g(r.margin, "%.2f") + ", limit " + g(r.depth_limit_mm, "%.3g") + " mm at S" +
           g(r.spindle_rpm, "%.0f") + (std::isfinite(r.chatter_frequency_hz) ? ", " + g(r.chatter_frequency_hz, "%.0f") + " Hz" : "");
    if (r.overloaded) c += std::string(r.stable ? "" : ";") + " overloaded, " + g(r.power_kw, "%.3g") + " kW " + g(r.torque_nm, "%.3g") + " Nm";
    if (r.fixed_rpm) c += "; speed set to S" + g(*r.fixed_rpm, "%.0f");
    if (r.fixed_feed) c += "; feed set to F" + g(*r.fixed_feed, "%.6g");
    if (!r.fix_note.empty()) c += "; " + r.fix_note;
    for (char& ch : c)
      if (ch == '(' || ch == ')') ch = ' ';  // a comment cannot hold parentheses
    if (std::find(e.comments.begin(), e.comments.end(), c) == e.comments.end()) e.comments.push_back(c);
    if (r.fixed_rpm && !e.rpm) {
      e.rpm = r.fixed_rpm;
      e.old_rpm = r.spindle_rpm;
    }
    if (r.fixed_feed && !e.feed) {
      e.feed = r.fixed_feed;
      e.old_feed = r.original_feed;
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
    if (it == edits.end()) {
      out << line << "\n";
      continue;
    }
    const LineEdit& e = it->second;
    out << line;
    if (e.rpm) out << " S" << g(*e.rpm, "%.0f");
    if (e.feed) out << " F" << g(*e.feed, "%.6g");
    for (const std::string& c : e.comments) out << " (" << c << ")";
    out << "\n";
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
