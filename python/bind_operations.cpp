// chatter.check and chatter.recommend: chatter check --json's and chatter
// recommend --json's records (chatter/records.hpp) as dicts (docs/python.md).
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/operations.hpp"
#include "chatter/records.hpp"
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
               std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  chatter::CheckOptions opt;
  const auto pick = [&](const std::optional<double>& given, const std::optional<double>& from_cfg, const char* arg,
                        const char* key) {
    if (given) return *given;
    if (from_cfg) return *from_cfg;
    throw InputError(cfg.source.string() + ": missing " + arg + " (or " + key +
                     " in the config): the machine's spindle speed range");
  };
  opt.machine.rpm_min = pick(rpm_min, cfg.sweep.rpm_min, "rpm_min", "sweep.rpm_min");
  opt.machine.rpm_max = pick(rpm_max, cfg.sweep.rpm_max, "rpm_max", "sweep.rpm_max");
  if (!(std::isfinite(opt.machine.rpm_min) && opt.machine.rpm_min > 0.0))
    throw InputError("rpm_min = " + fmt(opt.machine.rpm_min) + ": must be > 0 rev/min");
  if (!(std::isfinite(opt.machine.rpm_max) && opt.machine.rpm_max > opt.machine.rpm_min))
    throw InputError("rpm_max = " + fmt(opt.machine.rpm_max) + ": must be > rpm_min (" + fmt(opt.machine.rpm_min) + ")");
  opt.method = method;
  opt.threads = thread_count(threads);
  if (const std::string e = chatter::validate_speed_tolerance(speed_tolerance_pct / 100.0, "speed_tolerance_pct");
      !e.empty())
    throw InputError(e);
  opt.speed_tolerance = speed_tolerance_pct / 100.0;
  opt.flute_length_m = cfg.flute_length_m;
  try {
    chatter::resolve_lobe_method(method, cfg.model, cfg.process);
  } catch (const InputError& e) {
    throw InputError(std::string("method: ") + e.what());
  }
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

}  // namespace

void bind_operations(py::module_& m) {
  m.def("check", &check, "job"_a, "operations"_a, py::kw_only(), "method"_a = "auto", "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "speed_tolerance_pct"_a = kDefaultSpeedTolPct, "threads"_a = 0,
        "position_mm"_a = py::none(), "Checks operations (list of dicts or a CSV path) as chatter check --json.");
}

}  // namespace chatter_py
