// JOB.toml of `chatter program` (chatter/io/job.hpp; docs/program.md "The
// job"): the tables, then the tool configs each [[tools]] entry names.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/job.hpp"
#include "config_sections.hpp"

namespace chatter::config_detail {
namespace {

std::optional<Eigen::Vector3d> point3(const Table& t, std::string_view key) {
  const auto v = t.number_list(key, kAnyNumber);
  if (!v) {
    if (!t.has(key)) t.doc().error_key(t.path_of(key), "missing (required for shape = \"box\": [x, y, z] in mm)");
    return std::nullopt;
  }
  if (v->size() != 3) {
    t.doc().error(t.path_of(key), *t.find(key), "must be [x, y, z] (three numbers, mm)");
    return std::nullopt;
  }
  return Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]);
}

JobStock read_stock(const Table& root) {
  const auto t = root.table("stock");
  if (!t) root.doc().fail_key("stock", "missing: give [stock] with shape = \"bar\" (turning) or \"box\" (milling)");
  constexpr std::string_view kKeys[] = {"shape", "diameter_mm", "length_mm", "face_z_mm", "min_mm", "max_mm",
                                        "resolution_mm"};
  t->reject_unknown(kKeys);
  JobStock s;
  constexpr std::string_view kShapeRule = R"(must be "bar" (turning) or "box" (milling))";
  const auto shape = t->string("shape", kShapeRule);
  if (!shape) {
    if (!t->has("shape")) t->doc().error_key(t->path_of("shape"), std::string("missing: ") + std::string(kShapeRule));
    throw Skip{};
  }
  if (*shape == "bar") {
    s.shape = JobStock::Shape::kBar;
    s.diameter_mm = t->required_number("diameter_mm", kPositive, "mm").value_or(0.0);
    s.length_mm = t->required_number("length_mm", kPositive, "mm").value_or(0.0);
    s.face_z_mm = t->number("face_z_mm", kAnyNumber).value_or(0.0);
    for (const char* k : {"min_mm", "max_mm"})
      if (t->has(k)) t->doc().error(t->path_of(k), *t->find(k), "only for shape = \"box\"");
  } else if (*shape == "box") {
    s.shape = JobStock::Shape::kBox;
    const auto lo = point3(*t, "min_mm"), hi = point3(*t, "max_mm");
    if (lo && hi) {
      s.min_mm = *lo;
      s.max_mm = *hi;
      for (int k = 0; k < 3; ++k)
        if (!(s.max_mm[k] > s.min_mm[k]))
          t->doc().error(t->path_of("max_mm"), *t->find("max_mm"),
                         "must exceed min_mm in x, y and z (the box is empty)");
    }
    for (const char* k : {"diameter_mm", "length_mm", "face_z_mm"})
      if (t->has(k)) t->doc().error(t->path_of(k), *t->find(k), "only for shape = \"bar\"");
  } else {
    t->doc().error(t->path_of("shape"), *t->find("shape"), kShapeRule);
  }
  s.resolution_mm = t->number("resolution_mm", kPositive);
  return s;
}

JobMachine read_machine(const Table& root) {
  JobMachine m;
  const auto t = root.table("machine");
  if (!t) return m;
  constexpr std::string_view kKeys[] = {"rpm_min", "rpm_max", "max_power_kw", "max_torque_nm"};
  t->reject_unknown(kKeys);
  m.rpm_min = t->number("rpm_min", kPositive);
  m.rpm_max = t->number("rpm_max", kPositive);
  m.max_power_kw = t->number("max_power_kw", kPositive);
  m.max_torque_nm = t->number("max_torque_nm", kPositive);
  if (m.rpm_min && m.rpm_max && !(*m.rpm_max > *m.rpm_min))
    t->doc().error(t->path_of("rpm_max"), *t->find("rpm_max"), "must be > rpm_min");
  return m;
}

}  // namespace

JobText read_job(const toml::table& root_table, const Document& doc) {
  const Table root(doc, root_table, "");
  constexpr std::string_view kTopKeys[] = {"name", "stock", "tools", "workpiece", "machine", "program", "include"};
  root.reject_unknown(kTopKeys);
  JobText job;
  attempt_void([&] { job.stock = read_stock(root); });
  attempt_void([&] { job.machine = read_machine(root); });
  if (const auto p = root.table("program")) {
    constexpr std::string_view kKeys[] = {"speed_tolerance_pct", "cache", "default_spindle_rpm"};
    p->reject_unknown(kKeys);
    static constexpr Range kPct{"in [0, 50) (percent)", 0.0, false, 50.0, true};
    if (const auto tol = p->number("speed_tolerance_pct", kPct)) job.speed_tolerance = *tol / 100.0;
    if (const toml::node* c = p->find("cache")) {
      if (const auto b = c->value<bool>()) job.cache = *b;
      else doc.error(p->path_of("cache"), *c, "must be true or false");
    }
    job.default_spindle_rpm = p->number("default_spindle_rpm", kPositive);
  }
  if (root.has("workpiece")) {
    attempt_void([&] { job.workpiece = read_body(root, "workpiece"); });
    job.has_workpiece = true;
  }
  const toml::node* n = root.find("tools");
  if (!n) doc.fail_key("tools", "missing: give one [[tools]] entry per tool the program uses (number, config)");
  const toml::array* entries = n->as_array();
  if (!entries || !entries->is_array_of_tables() || entries->empty())
    doc.fail("tools", *n, "must be an array of tables ([[tools]] with number and config)");
  std::set<int> numbers;
  for (std::size_t i = 0; i < entries->size(); ++i) {
    const Table t(doc, *entries->get(i)->as_table(), element("tools", i));
    constexpr std::string_view kKeys[] = {"number", "config"};
    t.reject_unknown(kKeys);
    JobText::Tool tool;
    const auto number = t.integer("number", 1, 99999);
    if (!number && !t.has("number")) doc.error_key(t.path_of("number"), "missing (the T word's number, >= 1)");
    const auto config = t.string("config", "must be a file name (the tool's chatter config)");
    if (!config && !t.has("config")) doc.error_key(t.path_of("config"), "missing (the tool's chatter config file)");
    if (number && !numbers.insert(*number).second)
      doc.error(t.path_of("number"), *t.find("number"), "given twice: each tool number once");
    if (number && config) job.tools.push_back({*number, *config, t.path_of("config")});
  }
  doc.throw_if_errors();
  if (job.has_workpiece) job.cantilever = cantilever_refs(root_table);
  return job;
}

}  // namespace chatter::config_detail
