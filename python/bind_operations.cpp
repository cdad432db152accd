// chatter.check and chatter.recommend: chatter check --json's and chatter
// recommend --json's records (chatter/records.hpp) as dicts (docs/python.md),
// with the CLI's checks and defaults (chatter::check_options,
// chatter::recommend_plan) naming the keywords.
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/operations.hpp"
#include "chatter/records.hpp"
#include "chatter/usual_bands.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

// The operations as the CSV text parse_operations reads, so a list of dicts
// gets the file's validation row by row (line = list index + 2).
std::string operations_csv(const py::list& ops) {
  static const char* const kColumns[] = {"id", "spindle_rpm", "depth_mm", "radial_immersion", "feed_per_tooth_mm",
                                         "teeth", "milling_direction"};
  std::vector<bool> used(std::size(kColumns), false);
  used[0] = used[1] = used[2] = used[3] = used[4] = true;  // the required header columns
  std::size_t index = 0;
  for (auto item : ops) {
    if (!py::isinstance<py::dict>(item))
      throw InputError("operations[" + std::to_string(index) + "]: must be a dict (keys: id, spindle_rpm, depth_mm, "
                       "radial_immersion, feed_per_tooth_mm, teeth, milling_direction)");
    for (auto kv : item.cast<py::dict>()) {
      const std::string key = py::str(kv.first).cast<std::string>();
      bool known = false;
      for (std::size_t c = 0; c < std::size(kColumns); ++c)
        if (key == kColumns[c]) used[c] = known = true;
      if (!known)
        throw InputError("operations[" + std::to_string(index) + "]: '" + key +
                         "': unknown key (keys: id, spindle_rpm, depth_mm, radial_immersion, feed_per_tooth_mm, "
                         "teeth, milling_direction)");
    }
    ++index;
  }
  std::string text;
  for (std::size_t c = 0; c < std::size(kColumns); ++c)
    if (used[c]) text += std::string(text.empty() ? "" : ",") + kColumns[c];
  text += '\n';
  for (auto item : ops) {
    const py::dict row = item.cast<py::dict>();
    bool first = true;
    for (std::size_t c = 0; c < std::size(kColumns); ++c) {
      if (!used[c]) continue;
      if (!first) text += ',';
      first = false;
      if (!row.contains(kColumns[c])) continue;
      const py::object v = row[kColumns[c]];
      if (v.is_none()) continue;
      std::string cell;
      if (py::isinstance<py::float_>(v)) {
        const double x = v.cast<double>();
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", x);  // exact round trip
        cell = buf;
      } else {
        cell = py::str(v).cast<std::string>();
      }
      std::string quoted = "\"";
      for (char ch : cell) {
        if (ch == '"') quoted += '"';
        quoted += ch;
      }
      text += quoted + "\"";
    }
    text += '\n';
  }
  return text;
}

py::dict check(const Job& job_in, const py::object& operations, const std::string& method,
               std::optional<double> rpm_min, std::optional<double> rpm_max, double speed_tolerance_pct, int threads,
               std::optional<double> position_mm, std::optional<double> max_power_kw,
               std::optional<double> max_torque_nm, std::optional<double> tool_diameter_mm,
               std::optional<double> workpiece_diameter_mm, std::optional<double> tangential_coefficient_n_per_m2) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  // The CLI's options and checks (chatter::check_options), named as keywords.
  chatter::CheckOptions opt = chatter::check_options(
      cfg, rpm_min, rpm_max, method, speed_tolerance_pct, thread_count(threads), chatter::ArgStyle::kKeyword,
      {max_power_kw, max_torque_nm, tool_diameter_mm, workpiece_diameter_mm, tangential_coefficient_n_per_m2});
  chatter::OperationsFile file;
  std::string origin;
  if (py::isinstance<py::str>(operations) || py::hasattr(operations, "__fspath__")) {
    origin = py::str(py::module_::import("os").attr("fspath")(operations)).cast<std::string>();
    file = chatter::read_operations(origin, cfg.process.operation(), opt.machine);
  } else if (py::isinstance<py::list>(operations) || py::isinstance<py::tuple>(operations)) {
    origin = "<operations>";
    file = chatter::parse_operations(operations_csv(py::list(operations)), origin, cfg.process.operation(),
                                     opt.machine);
  } else {
    throw InputError("operations: must be a list of dicts or the path of an operations CSV file");
  }
  chatter::CheckReport report;
  {
    py::gil_scoped_release release;
    report = chatter::check_operations(cfg.model, cfg.process, file.rows, opt);
  }
  chatter::CheckRecordInputs in;
  in.operations_origin = origin;
  in.method_requested = method;
  in.options = &opt;
  in.process = &cfg.process;
  return chatter_py::to_python(chatter::check_record(report, file, in, chatter::record_source(cfg, position_mm)));
}

/// chatter recommend --json's record: the CLI's checks and defaults
/// (chatter::recommend_plan), the library's recommendation, the record.
py::dict recommend(const Job& job_in, double feed_per_tooth_mm, std::optional<double> rpm_min,
                   std::optional<double> rpm_max, std::optional<double> max_power_kw,
                   std::optional<double> max_torque_nm, double safety, std::optional<double> depth_max_mm,
                   double speed_tolerance_pct, std::optional<double> tool_diameter_mm,
                   std::optional<double> workpiece_diameter_mm,
                   std::optional<double> tangential_coefficient_n_per_m2, std::optional<double> radial_immersion,
                   std::optional<int> teeth, std::optional<std::string> milling_direction, const std::string& method,
                   int threads, std::optional<double> position_mm, std::optional<double> max_sle_um) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  chatter::RecommendArgs a;
  a.max_sle_um = max_sle_um;
  a.feed_per_tooth_mm = feed_per_tooth_mm;
  a.rpm_min = rpm_min;
  a.rpm_max = rpm_max;
  a.max_power_kw = max_power_kw;
  a.max_torque_nm = max_torque_nm;
  a.safety = safety;
  a.depth_max_mm = depth_max_mm;
  a.speed_tolerance_pct = speed_tolerance_pct;
  a.tool_diameter_mm = tool_diameter_mm;
  a.workpiece_diameter_mm = workpiece_diameter_mm;
  a.tangential_coefficient_n_per_m2 = tangential_coefficient_n_per_m2;
  a.radial_immersion = radial_immersion;
  a.teeth = teeth;
  a.milling_direction = milling_direction;
  a.method = method;
  a.threads = thread_count(threads);
  const chatter::RecommendPlan plan = chatter::recommend_plan(cfg, a, chatter::ArgStyle::kKeyword);
  chatter::Recommendation r;
  {
    py::gil_scoped_release release;
    r = chatter::recommend(cfg.model, plan.process, plan.options);
  }
  chatter::RecordSource source = chatter::record_source(cfg, position_mm);
  std::vector<std::pair<std::string, double>> given{{"feed_per_tooth_mm", feed_per_tooth_mm}, {"safety", safety},
                                                    {"speed_tolerance_pct", speed_tolerance_pct}};
  for (const auto& [k, v] : {std::pair{"rpm_min", rpm_min}, {"rpm_max", rpm_max}, {"max_power_kw", max_power_kw},
                             {"max_torque_nm", max_torque_nm}, {"depth_max_mm", depth_max_mm},
                             {"tool_diameter_mm", tool_diameter_mm}, {"workpiece_diameter_mm", workpiece_diameter_mm},
                             {"tangential_coefficient_n_per_m2", tangential_coefficient_n_per_m2},
                             {"radial_immersion", radial_immersion}, {"max_sle_um", max_sle_um}})
    if (v) given.emplace_back(k, *v);
  for (std::string& w : chatter::unusual_arguments(given)) source.warnings.push_back(std::move(w));
  return to_python(chatter::recommend_record(r, plan.options, plan.process, source));
}

}  // namespace

void bind_operations(py::module_& m) {
  m.def("check", &check, "job"_a, "operations"_a, py::kw_only(), "method"_a = "auto", "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "speed_tolerance_pct"_a = kDefaultSpeedTolPct, "threads"_a = 0,
        "position_mm"_a = py::none(), "max_power_kw"_a = py::none(), "max_torque_nm"_a = py::none(),
        "tool_diameter_mm"_a = py::none(), "workpiece_diameter_mm"_a = py::none(),
        "tangential_coefficient_n_per_m2"_a = py::none(),
        "Checks operations (list of dicts or a CSV path) as chatter check --json: stability, forced vibration and "
        "the mean cutting load against the spindle's power and torque.");
  m.def("recommend", &recommend, "job"_a, py::kw_only(), "feed_per_tooth_mm"_a, "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "max_power_kw"_a = py::none(), "max_torque_nm"_a = py::none(), "safety"_a = 0.8,
        "depth_max_mm"_a = py::none(), "speed_tolerance_pct"_a = kDefaultSpeedTolPct,
        "tool_diameter_mm"_a = py::none(), "workpiece_diameter_mm"_a = py::none(),
        "tangential_coefficient_n_per_m2"_a = py::none(), "radial_immersion"_a = py::none(), "teeth"_a = py::none(),
        "milling_direction"_a = py::none(), "method"_a = "auto", "threads"_a = 0, "position_mm"_a = py::none(),
        "max_sle_um"_a = py::none(),
        "The speed and depth that remove the most material, stable and within power and torque: the record of "
        "chatter recommend --json.");
}

}  // namespace chatter_py
