// Readers of the grinding commands' CSV files (include/chatter/io/grinding_io.hpp):
// the tests table of `grind fit` and the record of `grind impacts`.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <optional>
#include <map>
#include <numbers>
#include <span>
#include <string>
#include <system_error>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/grinding_data.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/kinematics.hpp"
#include "text.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;
namespace text = detail::text;

// A CSV as (line number, cells) rows after the header.
struct Csv {
  std::string file;
  std::map<std::string, std::size_t> col;
  std::vector<std::pair<int, std::vector<std::string>>> rows;
  bool has(const std::string& c) const { return col.count(c) > 0; }
};

Csv read_csv(const fs::path& path, const char* what, std::span<const std::string_view> known) {
  Csv c;
  c.file = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(c.file + ": no such file (" + what + ")");
  if (fs::is_directory(path, ec)) throw InputError(c.file + ": is a directory, not " + std::string(what));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(c.file + ": cannot be read (" + what + ")");
  std::string line;
  bool header = true;
  std::vector<std::string> cells;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string_view t = text::trim(line);
    if (t.empty() || t.front() == '#') continue;
    if (!text::split_delimited(line, ',', true, cells))
      throw InputError(c.file + ": line " + std::to_string(n) + ": unterminated quote");
    if (header) {
      for (std::size_t i = 0; i < cells.size(); ++i) {
        std::string name(text::trim(cells[i]));
        for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        if (name.empty()) throw InputError(c.file + ": line " + std::to_string(n) + ": column " + std::to_string(i + 1) + " has no name");
        if (std::find(known.begin(), known.end(), name) == known.end()) {
          const std::string_view meant = text::near_miss(name, known);
          std::string list;
          for (const std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
          throw InputError(c.file + ": line " + std::to_string(n) + ": unknown column '" + name + "' (" +
                           (meant.empty() ? "known: " + list : "did you mean " + std::string(meant) + "?") + ")");
        }
        if (!c.col.emplace(name, i).second)
          throw InputError(c.file + ": line " + std::to_string(n) + ": column " + name + " appears twice");
      }
      header = false;
      continue;
    }
    if (cells.size() > c.col.size())
      throw InputError(c.file + ": line " + std::to_string(n) + ": " + std::to_string(cells.size()) +
                       " values for " + std::to_string(c.col.size()) + " columns");
    c.rows.emplace_back(n, cells);
  }
  if (header) throw InputError(c.file + ": empty: no header and no data (" + what + ")");
  if (c.rows.empty()) throw InputError(c.file + ": no data rows after the header (" + what + ")");
  return c;
}

enum class Rule { kPositive, kNonNegative, kAny };

// The cell of column `name` on a row: nullopt when the column is absent or
// the cell empty; otherwise a number obeying `rule`.
std::optional<double> cell(const Csv& c, const std::pair<int, std::vector<std::string>>& row, const std::string& name,
                           Rule rule = Rule::kPositive) {
  const auto it = c.col.find(name);
  if (it == c.col.end() || it->second >= row.second.size()) return std::nullopt;
  const std::string& s = row.second[it->second];
  if (text::trim(s).empty()) return std::nullopt;
  const auto v = text::parse_double(text::trim(s));
  const std::string where = c.file + ": line " + std::to_string(row.first) + ": " + name + " = '" + s + "'";
  if (!v || !std::isfinite(*v)) throw InputError(where + ": must be a finite number");
  if (rule == Rule::kPositive && !(*v > 0.0)) throw InputError(where + ": must be > 0");
  if (rule == Rule::kNonNegative && !(*v >= 0.0)) throw InputError(where + ": must be >= 0");
  return v;
}

constexpr std::string_view kTestColumns[] = {
    "power_w",           "removal_mm3_per_s", "removed_volume_mm3", "grinding_time_s",
    "wear_mm3_per_s",    "wheel_diameter_before_mm", "wheel_diameter_after_mm", "normal_force_n",
    "impacts_per_turn",  "wheel_diameter_mm", "wheel_width_mm",     "wheel_rpm",
    "feed_mm_per_s",     "cutting_speed_m_per_s", "test"};

}  // namespace

std::vector<GrindingTest> read_grinding_tests(const fs::path& path, const GrindingTestDefaults& d) {
  const Csv c = read_csv(path, "a grinding tests table", kTestColumns);
  std::vector<GrindingTest> out;
  for (const auto& row : c.rows) {
    GrindingTest t;
    t.line = row.first;
    const std::string at = c.file + ": line " + std::to_string(row.first) + ": ";
    t.power_w = cell(c, row, "power_w");
    t.normal_force_n = cell(c, row, "normal_force_n");
    t.impacts_per_turn = cell(c, row, "impacts_per_turn");
    if (!t.impacts_per_turn) t.impacts_per_turn = d.impacts_per_turn;
    t.wheel_diameter_mm = cell(c, row, "wheel_diameter_mm");
    if (!t.wheel_diameter_mm) t.wheel_diameter_mm = d.wheel_diameter_mm;
    t.wheel_width_mm = cell(c, row, "wheel_width_mm");
    if (!t.wheel_width_mm) t.wheel_width_mm = d.wheel_width_mm;
    t.wheel_rpm = cell(c, row, "wheel_rpm");
    if (!t.wheel_rpm) t.wheel_rpm = d.wheel_rpm;
    t.feed_mm_per_s = cell(c, row, "feed_mm_per_s");
    if (!t.feed_mm_per_s) t.feed_mm_per_s = d.feed_mm_per_s;
    t.cutting_speed_m_per_s = cell(c, row, "cutting_speed_m_per_s");
    if (!t.cutting_speed_m_per_s && t.wheel_diameter_mm && t.wheel_rpm)
      t.cutting_speed_m_per_s = cutting_speed_m_per_s(*t.wheel_diameter_mm * 1e-3, *t.wheel_rpm);
    const auto time = cell(c, row, "grinding_time_s");
    // Removal: given, or volume / time.
    t.removal_mm3_per_s = cell(c, row, "removal_mm3_per_s");
    const auto volume = cell(c, row, "removed_volume_mm3");
    if (t.removal_mm3_per_s && volume)
      throw InputError(at + "removal_mm3_per_s and removed_volume_mm3 both given: give one");
    if (volume) {
      if (!time) throw InputError(at + "removed_volume_mm3 needs grinding_time_s (the removal is volume / time)");
      t.removal_mm3_per_s = *volume / *time;
    }
    // Wear: given, or the wheel volume between the diameters before and after over the time.
    t.wear_mm3_per_s = cell(c, row, "wear_mm3_per_s", Rule::kNonNegative);
    const auto before = cell(c, row, "wheel_diameter_before_mm"), after = cell(c, row, "wheel_diameter_after_mm");
    if ((before || after) && t.wear_mm3_per_s)
      throw InputError(at + "wear_mm3_per_s and the wheel diameters before/after both given: give one");
    if (before || after) {
      if (!(before && after && time && t.wheel_width_mm))
        throw InputError(at + "the wear from the diameters needs wheel_diameter_before_mm, wheel_diameter_after_mm, "
                              "grinding_time_s and the wheel width");
      if (*after > *before)
        throw InputError(at + "wheel_diameter_after_mm = " + number_text(*after) + ": larger than before (" + number_text(*before) +
                         " mm): the wheel cannot grow");
      t.wear_mm3_per_s = std::numbers::pi * *t.wheel_width_mm * (*before * *before - *after * *after) / 4.0 / *time;
    }
    if (t.power_w && t.cutting_speed_m_per_s && t.normal_force_n)
      t.friction_coefficient = *t.power_w / (*t.cutting_speed_m_per_s * *t.normal_force_n);
    if (t.removal_mm3_per_s && t.wear_mm3_per_s && *t.wear_mm3_per_s > 0.0)
      t.g_ratio = *t.removal_mm3_per_s / *t.wear_mm3_per_s;
    if (t.removal_mm3_per_s && t.feed_mm_per_s && t.wheel_width_mm)
      t.depth_per_pass_mm = *t.removal_mm3_per_s / (*t.feed_mm_per_s * *t.wheel_width_mm);
    if (t.power_w && t.removal_mm3_per_s && *t.removal_mm3_per_s > 0.0)
      t.specific_energy_j_per_mm3 = *t.power_w / *t.removal_mm3_per_s;
    out.push_back(t);
  }
  return out;
}

ImpactRecord read_impact_record(const fs::path& path) {
  constexpr std::string_view kColumns[] = {"time_s", "normal_force_n", "wheel_rpm"};
  const Csv c = read_csv(path, "a force or wheel-speed record", kColumns);
  ImpactRecord r;
  if (!c.has("time_s")) throw InputError(c.file + ": missing column time_s");
  if (c.has("normal_force_n") == c.has("wheel_rpm"))
    throw InputError(c.file + ": give one signal column: normal_force_n (impacts are peaks) or wheel_rpm (dips)");
  r.column = c.has("normal_force_n") ? "normal_force_n" : "wheel_rpm";
  r.kind = c.has("normal_force_n") ? grinding::ImpactSignal::kNormalForce : grinding::ImpactSignal::kWheelSpeed;
  for (const auto& row : c.rows) {
    const auto t = cell(c, row, "time_s", Rule::kAny);
    const auto v = cell(c, row, r.column, Rule::kAny);
    const std::string at = c.file + ": line " + std::to_string(row.first) + ": ";
    if (!t || !v) throw InputError(at + "time_s and " + r.column + " must both be numbers");
    if (!r.time_s.empty() && !(*t > r.time_s.back()))
      throw InputError(at + "time_s = " + number_text(*t) + ": must increase (previous " + number_text(r.time_s.back()) + " s)");
    r.time_s.push_back(*t);
    r.signal.push_back(*v);
  }
  if (r.time_s.size() < 3) throw InputError(c.file + ": fewer than 3 samples");
  return r;
}


namespace {

using grinding::EmpiricalForm;
using grinding::EmpiricalVariable;

std::optional<EmpiricalForm> form_named(const std::string& m) {
  for (EmpiricalForm f : {EmpiricalForm::kPoly11, EmpiricalForm::kPoly22, EmpiricalForm::kPoly33,
                          EmpiricalForm::kPowerLaw, EmpiricalForm::kHahnLindsay})
    if (m == grinding::empirical_form_name(f)) return f;
  return std::nullopt;
}

// The missing piece of a test for a model, or "".
std::string missing(const GrindingTest& t, bool mechanistic, bool power_law, bool force) {
  std::string m;
  auto need = [&](bool ok, const char* what) {
    if (!ok) m += (m.empty() ? "" : ", ") + std::string(what);
  };
  if (mechanistic) {
    need(t.power_w.has_value(), "power_w");
    need(t.removal_mm3_per_s.has_value(), "removal_mm3_per_s");
    need(t.impacts_per_turn.has_value(), "impacts_per_turn (column or --impacts-per-turn)");
    need(t.wheel_diameter_mm.has_value(), "wheel_diameter_mm");
    need(t.wheel_width_mm.has_value(), "wheel_width_mm");
    need(t.wheel_rpm.has_value(), "wheel_rpm");
    need(t.feed_mm_per_s.has_value(), "feed_mm_per_s");
    return m;
  }
  need(t.cutting_speed_m_per_s.has_value(), "cutting_speed_m_per_s (or wheel_diameter_mm and wheel_rpm)");
  need(force ? t.normal_force_n.has_value() : t.power_w.has_value(), force ? "normal_force_n" : "power_w");
  if (power_law) {
    need(t.wheel_rpm.has_value(), "wheel_rpm");
    need(t.wheel_diameter_mm.has_value(), "wheel_diameter_mm");
  }
  return m;
}

}  // namespace

GrindingFitReport fit_grinding_tests(const std::vector<GrindingTest>& tests, const std::string& model,
                                     const std::string& variable_in, const std::string& tests_file) {
  const bool mech = model == "mechanistic";
  const std::optional<EmpiricalForm> form = form_named(model);
  if (!mech && !form)
    throw InputError("model \"" + model + "\": unknown (use mechanistic, poly11, poly22, poly33, power_law or hahn_lindsay)");
  std::string variable = variable_in;
  if (variable.empty()) variable = form == EmpiricalForm::kHahnLindsay ? "normal_force_n" : "useful_power_w";
  if (!mech && variable != "useful_power_w" && variable != "normal_force_n")
    throw InputError("variable \"" + variable + "\": use useful_power_w or normal_force_n");
  if (form == EmpiricalForm::kHahnLindsay && variable != "normal_force_n")
    throw InputError("variable \"useful_power_w\": hahn_lindsay reads the normal force (K_p (F_N - F_th) V_c)");
  GrindingFitReport report;
  report.model = model;
  report.tests_file = tests_file;
  report.tests = tests;
  if (mech) {
    std::vector<grinding::MechanisticTest> mt;
    GrindingFitReport::Target t;
    t.name = "power_w";
    for (std::size_t i = 0; i < tests.size(); ++i) {
      const GrindingTest& x = tests[i];
      if (const std::string m = missing(x, true, false, false); !m.empty())
        throw InputError(tests_file + ": line " + std::to_string(x.line) + ": the mechanistic fit needs " + m);
      grinding::MechanisticTest m;
      m.power_w = *x.power_w;
      m.removal_m3_per_s = *x.removal_mm3_per_s * 1e-9;
      m.impacts_per_turn = *x.impacts_per_turn;
      m.wheel = {*x.wheel_diameter_mm * 1e-3, *x.wheel_width_mm * 1e-3, revolutions_per_s(*x.wheel_rpm)};
      m.feed_m_per_s = *x.feed_mm_per_s * 1e-3;
      mt.push_back(m);
      t.rows.push_back(i);
    }
    try {
      t.fit = grinding::fit_mechanistic(mt);
    } catch (const InputError& e) {
      throw InputError(tests_file + ": " + e.what());
    }
    report.targets.push_back(t);
    return report;
  }
  report.variable = variable;
  const bool force = variable == "normal_force_n";
  const bool power_law = form == EmpiricalForm::kPowerLaw;
  struct Wanted {
    const char* name;
    std::optional<double> GrindingTest::*value;
  };
  std::vector<Wanted> wanted = {{"removal", &GrindingTest::removal_mm3_per_s}, {"wear", &GrindingTest::wear_mm3_per_s}};
  if (!force) wanted.push_back({"normal_force", &GrindingTest::normal_force_n});
  for (const Wanted& w : wanted) {
    GrindingFitReport::Target t;
    t.name = w.name;
    std::vector<grinding::EmpiricalSample> samples;
    std::string left_out;  // tests with an empty cell for this target: said, not dropped silently
    for (std::size_t i = 0; i < tests.size(); ++i) {
      const GrindingTest& x = tests[i];
      if (!(x.*(w.value))) {
        left_out += (left_out.empty() ? "" : ", ") + std::to_string(x.line);
        continue;
      }
      if (const std::string m = missing(x, false, power_law, force); !m.empty())
        throw InputError(tests_file + ": line " + std::to_string(x.line) + ": the " + w.name + " model needs " + m);
      grinding::EmpiricalSample smp;
      smp.inputs.cutting_speed_m_per_s = *x.cutting_speed_m_per_s;
      smp.inputs.useful_power_w = x.power_w.value_or(0.0);
      smp.inputs.normal_force_n = x.normal_force_n.value_or(0.0);
      smp.inputs.wheel_rpm = x.wheel_rpm.value_or(0.0);
      smp.inputs.wheel_diameter_mm = x.wheel_diameter_mm.value_or(0.0);
      smp.value = *(x.*(w.value));
      samples.push_back(smp);
      t.rows.push_back(i);
    }
    if (samples.empty()) continue;
    try {
      t.fit = grinding::fit_empirical(*form, force ? EmpiricalVariable::kNormalForce : EmpiricalVariable::kUsefulPower,
                                      samples);
    } catch (const InputError& e) {
      throw InputError(tests_file + ": " + w.name + " model: " + e.what());
    }
    if (!left_out.empty())
      t.fit.warnings.push_back("line(s) " + left_out + " have no value: left out of this fit (" +
                               std::to_string(samples.size()) + " of " + std::to_string(tests.size()) + " tests)");
    report.targets.push_back(t);
  }
  if (report.targets.empty())
    throw InputError(tests_file + ": nothing to fit: the table has no removal_mm3_per_s (or removed_volume_mm3), "
                                  "wear_mm3_per_s (or the wheel diameters) or normal_force_n column with values");
  return report;
}

}  // namespace chatter
