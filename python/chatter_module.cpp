// The Python module `chatter` (pybind11): the library's lobes, point, check
// and simulate for post-processors, notebooks and scripts, with the same
// numbers as the `chatter` CLI for the same inputs (each call follows the
// CLI command of the same name in src/cli/, through the library; nothing is
// printed). API reference: docs/python.md.
//
// Errors: chatter::InputError -> chatter.InputError (a ValueError) with the
// library's message ("<file>: <key> = <value>: <rule>"); the module's own
// argument checks name the keyword ("rpm = -1: must be > 0 rev/min").
// chatter::NumericalError -> chatter.NumericalError (a RuntimeError); any
// other failure -> RuntimeError. Every solve runs with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/forced_records.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"
#include "chatter/operations.hpp"
#include "chatter/solvers.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/uncertainty.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;
using chatter::InputError;

namespace {

// The CLI's defaults (src/cli/cli_common.hpp), kept equal so that the same
// call gives the same table.
constexpr double kDefaultDepthMaxMm = 50.0;
constexpr int kDefaultRpmPoints = 400;
constexpr long long kMaxRpmPoints = 1'000'000;
constexpr long long kMaxSurfacePoints = 4'000'000;  // positions x speeds, as the CLI's surface
constexpr int kDefaultPositionPoints = 21;           // as the CLI's surface
constexpr long long kMaxMonteCarloSolves = 25'000'000;  // samples x speeds, as the CLI's lobes --samples
constexpr int kDefaultDepthPoints = 101;                // as the CLI's --depth-points
constexpr double kDefaultFeedMm = 0.1;         // chatter simulate's feed default
constexpr double kDefaultSimRtol = 1e-7;       // chatter simulate --rtol default
constexpr double kDefaultSpeedTolPct = 2.0;    // chatter check --speed-tolerance-pct default
constexpr const char* kJobOrigin = "<chatter.Job>";

// A number for messages, as the CLI prints it (6 significant digits).
std::string fmt(double x) {
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}

// ------------------------------------------------------------------ the job

/// A loaded or built config: model, process, sweep defaults. Immutable, so
/// one Job may be used from several Python threads at once.
struct Built;
/// The solvers built for a job, by (method, depth searched, options): the
/// analytic solver's construction (its lobe geometry) costs about 30 times a
/// limit_at, so repeated point() calls reuse it. Solvers are immutable, so
/// the result is bitwise the same as building a new one. At most
/// kMaxCachedSolvers entries (then the cache starts again: no growth).
struct SolverCache {
  std::mutex mutex;
  std::map<std::string, std::shared_ptr<const Built>> solvers;
};
constexpr std::size_t kMaxCachedSolvers = 16;

struct Job {
  std::shared_ptr<const chatter::Config> cfg;
  std::shared_ptr<SolverCache> cache = std::make_shared<SolverCache>();
};

Job job_from(chatter::Config c, bool strict) {
  if (strict && !c.warnings.empty()) {
    std::string message;
    for (const std::string& w : c.warnings) message += (message.empty() ? "" : "\n") + w + " (strict)";
    throw InputError(message);
  }
  return Job{std::make_shared<const chatter::Config>(std::move(c))};
}

/// The job at a tool position (docs/position.md), through the io layer as
/// the CLI's --position-mm: messages name `position_mm`. No position: the job.
Job at_position(const Job& job, const std::optional<double>& position_mm) {
  if (!position_mm) return job;
  return Job{std::make_shared<const chatter::Config>(chatter::config_at_position(*job.cfg, *position_mm, "position_mm"))};
}

// --- Python values -> TOML text (inline tables), for Job built in code. The
// text then goes through the config loader, so a Job built in code gets the
// loader's full validation and its messages ("<chatter.Job>: key = v: rule").

std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char ch : s) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += static_cast<char>(ch);
    } else if (ch < 0x20 || ch == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", ch);
      out += buf;
    } else {
      out += static_cast<char>(ch);
    }
  }
  return out + "\"";
}

std::string toml_double(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);  // round-trips exactly
  std::string s = buf;
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

std::string toml_value(const py::handle& v, const std::string& key) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) return toml_double(v.cast<double>());
  if (py::isinstance<py::str>(v)) return toml_string(v.cast<std::string>());
  if (py::hasattr(v, "tolist") && !py::isinstance<py::dict>(v))  // NumPy arrays and scalars
    return toml_value(v.attr("tolist")(), key);
  if (py::isinstance<py::dict>(v)) {
    std::string out = "{";
    bool first = true;
    for (auto item : v.cast<py::dict>()) {
      if (!py::isinstance<py::str>(item.first))
        throw InputError(std::string(kJobOrigin) + ": " + key + ": keys must be strings");
      const std::string k = item.first.cast<std::string>();
      if (item.second.is_none()) continue;  // None = key absent
      out += (first ? " " : ", ") + toml_string(k) + " = " + toml_value(item.second, key.empty() ? k : key + "." + k);
      first = false;
    }
    return out + " }";
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string out = "[";
    std::size_t i = 0;
    for (auto item : v) {
      out += (i ? ", " : "") + toml_value(item, key + "[" + std::to_string(i) + "]");
      ++i;
    }
    return out + "]";
  }
  throw InputError(std::string(kJobOrigin) + ": " + key + " = " + py::repr(v).cast<std::string>() +
                   ": must be a number, string, bool, list or dict");
}

Job make_job(const std::optional<py::dict>& config, const std::optional<std::string>& name,
             const std::optional<py::dict>& process, const std::optional<py::list>& tool_modes,
             const std::optional<py::list>& workpiece_modes, const std::optional<py::dict>& sweep, bool strict) {
  py::dict d;
  if (config) d = py::dict(py::module_::import("copy").attr("deepcopy")(*config));
  if (name) d["name"] = *name;
  if (process) d["process"] = *process;
  if (sweep) d["sweep"] = *sweep;
  const auto put_modes = [&](const char* body, const py::list& modes) {
    py::dict b = d.contains(body) ? py::dict(d[body]) : py::dict();
    b["modes"] = modes;
    d[body] = b;
  };
  if (tool_modes) put_modes("tool", *tool_modes);
  if (workpiece_modes) put_modes("workpiece", *workpiece_modes);
  std::string text;
  for (auto item : d) {
    if (!py::isinstance<py::str>(item.first)) throw InputError(std::string(kJobOrigin) + ": keys must be strings");
    if (item.second.is_none()) continue;
    const std::string k = item.first.cast<std::string>();
    text += toml_string(k) + " = " + toml_value(item.second, k) + "\n";
  }
  return job_from(chatter::parse_config(text, kJobOrigin), strict);
}

py::object optional_number(const std::optional<double>& x) { return x ? py::cast(*x) : py::none(); }
py::object optional_int(const std::optional<int>& x) { return x ? py::cast(*x) : py::none(); }

// ------------------------------------------------------------------ values

py::object to_py(const chatter::SolverValue& v) {
  return std::visit(
      [](const auto& x) -> py::object {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, std::monostate>) return py::none();
        else return py::cast(x);
      },
      v);
}

chatter::SolverValue to_solver_value(const chatter::SolverOption& o, const py::handle& v) {
  const std::string given = py::repr(v).cast<std::string>();
  switch (o.kind) {
    case chatter::SolverOption::Kind::kFlag:
      if (!py::isinstance<py::bool_>(v)) throw InputError(o.name + " = " + given + ": must be True or False");
      return v.cast<bool>();
    case chatter::SolverOption::Kind::kInt:
      if (py::isinstance<py::bool_>(v) || !py::hasattr(v, "__index__"))
        throw InputError(o.name + " = " + given + ": must be a whole number");
      return v.cast<int>();
    case chatter::SolverOption::Kind::kReal:
      if (py::isinstance<py::bool_>(v) || !(py::isinstance<py::float_>(v) || py::hasattr(v, "__index__")))
        throw InputError(o.name + " = " + given + ": must be a number");
      return v.cast<double>();
  }
  return {};
}

/// What the CLI's build_solver does, with options from a dict (names as in
/// the registry: "steps", "feed_per_tooth_mm", ...).
struct Built {
  const chatter::SolverDescriptor* descriptor = nullptr;
  std::unique_ptr<chatter::LobeSolver> solver;
  std::vector<std::string> notes;
  chatter::SolverValues values;  ///< the method's options it was built with (checked)
};

std::string value_key(const chatter::SolverValue& v) {
  if (const auto* b = std::get_if<bool>(&v)) return *b ? "T" : "F";
  if (const auto* i = std::get_if<int>(&v)) return "i" + std::to_string(*i);
  if (const auto* x = std::get_if<double>(&v)) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "d%.17g", *x);
    return buf;
  }
  return "?";
}

/// The method's options from the dict, checked, with the CLI's defaults.
chatter::SolverValues solver_values(const chatter::Config& cfg, const chatter::SolverDescriptor& descriptor,
                                    const std::string& method, const std::optional<py::dict>& options) {
  chatter::SolverValues values;
  if (options) {
    for (auto item : *options) {
      const std::string name = py::str(item.first).cast<std::string>();
      const chatter::SolverOption* opt = nullptr;
      for (const auto& o : descriptor.options)
        if (o.name == name) opt = &o;
      if (!opt) {
        std::string known;
        for (const auto& o : descriptor.options) known += (known.empty() ? "" : ", ") + o.name;
        throw InputError("options: '" + name + "': not an option of method " + method +
                         (known.empty() ? " (it has none)" : " (it has: " + known + ")"));
      }
      const chatter::SolverValue v = to_solver_value(*opt, item.second);
      if (const std::string why = chatter::option_violation(*opt, v); !why.empty())
        throw InputError(name + " = " + py::repr(item.second).cast<std::string>() + ": " + why);
      values[name] = v;
    }
  }
  // As the CLI: the time-domain feed defaults to the config's feed.
  for (const auto& o : descriptor.options)
    if (o.name == "feed_per_tooth_mm" && cfg.feed_mm && !values.count(o.name)) values[o.name] = *cfg.feed_mm;
  return values;
}

std::shared_ptr<const Built> build_solver(const Job& job, const std::string& method, double depth_max_m,
                                          const std::optional<py::dict>& options) {
  const chatter::Config& cfg = *job.cfg;
  const chatter::SolverDescriptor& descriptor = chatter::find_lobe_method(method);
  const chatter::SolverValues values = solver_values(cfg, descriptor, method, options);
  std::string key = method + "|" + value_key(depth_max_m);
  for (const auto& [k, v] : values) key += "|" + k + "=" + value_key(v);
  {
    std::lock_guard<std::mutex> lock(job.cache->mutex);
    if (const auto it = job.cache->solvers.find(key); it != job.cache->solvers.end()) return it->second;
  }
  auto b = std::make_shared<Built>();
  b->descriptor = &descriptor;
  {
    py::gil_scoped_release release;
    b->solver = chatter::make_lobe_solver(method, cfg.model, cfg.process, depth_max_m, values);
  }
  b->notes = chatter::ignored_feature_notes(descriptor, cfg.process);
  b->values = values;
  std::lock_guard<std::mutex> lock(job.cache->mutex);
  if (job.cache->solvers.size() >= kMaxCachedSolvers) job.cache->solvers.clear();
  job.cache->solvers.emplace(key, b);
  return b;
}

unsigned thread_count(int t) {
  if (t < 0 || t > 1024) throw InputError("threads = " + std::to_string(t) + ": must be in [0, 1024] (0 = every core)");
  return static_cast<unsigned>(t);
}

// ------------------------------------------------------------------ lobes

/// Evenly spaced speeds as the CLI's resolve_sweep: arguments, then the
/// config's [sweep].
std::vector<double> even_speeds(const chatter::Config& cfg, std::optional<double> rpm_min,
                                std::optional<double> rpm_max, std::optional<int> rpm_points) {
  const auto pick = [&](const std::optional<double>& given, const std::optional<double>& from_cfg,
                        const char* arg, const char* key) {
    if (given) return *given;
    if (from_cfg) return *from_cfg;
    throw InputError(cfg.source.string() + ": missing " + arg + " (or " + key + " in the config)");
  };
  const double lo = pick(rpm_min, cfg.sweep.rpm_min, "rpm_min", "sweep.rpm_min");
  const double hi = pick(rpm_max, cfg.sweep.rpm_max, "rpm_max", "sweep.rpm_max");
  const int n = rpm_points.value_or(cfg.sweep.rpm_points.value_or(kDefaultRpmPoints));
  if (!(std::isfinite(lo) && lo > 0.0)) throw InputError("rpm_min = " + fmt(lo) + ": must be > 0 rev/min");
  if (!(std::isfinite(hi) && hi > lo))
    throw InputError("rpm_max = " + fmt(hi) + ": must be > rpm_min (" + fmt(lo) + ")");
  if (n < 2) throw InputError("rpm_points = " + std::to_string(n) + ": must be >= 2");
  if (n > kMaxRpmPoints)
    throw InputError("rpm_points = " + std::to_string(n) + ": at most " + std::to_string(kMaxRpmPoints) + " speeds");
  return chatter::evenly_spaced_speeds(lo, hi, n);
}

py::dict lobes(const Job& job_in, const std::string& method, std::optional<double> rpm_min,
               std::optional<double> rpm_max, std::optional<int> rpm_points, std::optional<double> depth_max_mm,
               const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& rpm, int threads,
               const std::optional<py::dict>& options, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  std::vector<double> speeds;
  if (rpm) {
    if (rpm_min || rpm_max || rpm_points) throw InputError("rpm: give either rpm or rpm_min/rpm_max/rpm_points");
    if (rpm->ndim() != 1) throw InputError("rpm: must be a one-dimensional array of speeds, rev/min");
    speeds.assign(rpm->data(), rpm->data() + rpm->size());
    if (speeds.empty()) throw InputError("rpm: empty (give at least one speed)");
    for (std::size_t i = 0; i < speeds.size(); ++i)
      if (!(std::isfinite(speeds[i]) && speeds[i] > 0.0))
        throw InputError("rpm[" + std::to_string(i) + "] = " + fmt(speeds[i]) + ": must be > 0 rev/min");
  } else {
    speeds = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  }
  const double dmax = depth_max_mm.value_or(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm));
  if (!(std::isfinite(dmax) && dmax > 0.0)) throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > 0 mm");
  const unsigned nthreads = thread_count(threads);
  const std::shared_ptr<const Built> built = build_solver(job, method, dmax * 1e-3, options);
  const chatter::LobeSolver& solver = *built->solver;
  const std::vector<chatter::DiagnosticColumn> columns = solver.diagnostic_columns();

  std::vector<chatter::StabilityLimit> rows(speeds.size());
  std::vector<std::vector<chatter::SolverValue>> values;
  {
    py::gil_scoped_release release;
    if (!columns.empty()) {
      values.resize(speeds.size());
      chatter::parallel_for(speeds.size(), nthreads, [&](std::size_t i) {
        chatter::DiagnosedLimit r = solver.limit_with_diagnostics(speeds[i]);
        rows[i] = r.limit;
        values[i] = std::move(r.values);
      });
    } else {
      rows = chatter::lobe_envelope(solver, speeds, nthreads);
    }
  }

  const auto n = static_cast<py::ssize_t>(rows.size());
  py::array_t<double> s(n), d(n), f(n);
  py::array_t<int> k(n);
  auto sp = s.mutable_unchecked<1>();
  auto dp = d.mutable_unchecked<1>();
  auto fp = f.mutable_unchecked<1>();
  auto kp = k.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const chatter::StabilityLimit& r = rows[static_cast<std::size_t>(i)];
    sp(i) = r.spindle_rpm;
    dp(i) = r.depth_limit_m * 1e3;  // +inf where unbounded, as the CSV
    fp(i) = r.bounded() ? r.chatter_frequency_hz : std::nan("");
    kp(i) = r.bounded() ? r.lobe : -1;
  }
  py::dict out;
  out["spindle_rpm"] = s;
  out["depth_limit_mm"] = d;
  out["chatter_frequency_hz"] = f;
  out["lobe"] = k;
  const py::object np_array = py::module_::import("numpy").attr("array");
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].numeric) {
      py::array_t<double> col(n);
      auto cp = col.mutable_unchecked<1>();
      for (py::ssize_t i = 0; i < n; ++i) {
        const auto& row = values[static_cast<std::size_t>(i)];
        const chatter::SolverValue v = c < row.size() ? row[c] : chatter::SolverValue{};
        if (const auto* x = std::get_if<double>(&v)) cp(i) = *x;
        else if (const auto* j = std::get_if<int>(&v)) cp(i) = *j;
        else cp(i) = std::nan("");
      }
      out[py::str(columns[c].name)] = col;
    } else {
      py::list col;
      for (const auto& row : values) {
        const chatter::SolverValue v = c < row.size() ? row[c] : chatter::SolverValue{};
        if (const auto* t = std::get_if<std::string>(&v)) col.append(*t);
        else if (const auto* b = std::get_if<bool>(&v)) col.append(*b ? "true" : "false");
        else col.append("");
      }
      out[py::str(columns[c].name)] = np_array(col, "dtype"_a = "str");
    }
  }
  return out;
}

// ------------------------------------------------------------------ point

py::dict point(const Job& job_in, double rpm, double depth_mm, const std::string& method,
               std::optional<double> depth_max_mm, const std::optional<py::dict>& options,
               std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError("rpm = " + fmt(rpm) + ": must be > 0 rev/min");
  if (!(std::isfinite(depth_mm) && depth_mm > 0.0))
    throw InputError("depth_mm = " + fmt(depth_mm) + ": must be > 0 mm (a cut of no depth cannot chatter)");
  double dmax = std::max(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm), 2.0 * depth_mm);
  if (depth_max_mm) {
    dmax = *depth_max_mm;
    if (!(std::isfinite(dmax) && dmax > depth_mm))
      throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > depth_mm (" + fmt(depth_mm) + ")");
  }
  const std::shared_ptr<const Built> built = build_solver(job, method, dmax * 1e-3, options);
  const double depth_m = depth_mm * 1e-3;
  chatter::StabilityLimit lim;
  chatter::SolverValues diag;
  {
    py::gil_scoped_release release;
    lim = built->solver->limit_at(rpm);
    diag = built->solver->point_diagnostics(rpm, depth_m);
  }
  py::dict j;
  j["method"] = built->solver->method();
  j["warnings"] = cfg.warnings;
  j["notes"] = built->notes;
  if (position_mm) j["position_mm"] = *position_mm;
  j["spindle_rpm"] = rpm;
  j["depth_mm"] = depth_mm;
  j["stable"] = depth_m < lim.depth_limit_m;
  j["depth_limit_mm"] = lim.bounded() ? py::object(py::float_(lim.depth_limit_m * 1e3)) : py::none();
  j["chatter_frequency_hz"] = lim.bounded() ? py::object(py::float_(lim.chatter_frequency_hz)) : py::none();
  j["lobe"] = lim.bounded() ? py::object(py::int_(lim.lobe)) : py::none();
  j["margin"] = (lim.bounded() && depth_m > 0.0) ? py::object(py::float_(lim.depth_limit_m / depth_m)) : py::none();
  j["depth_max_mm"] = dmax;
  for (const auto& [key, value] : diag) j[py::str(key)] = to_py(value);
  return j;
}

// ------------------------------------------------------------------ check

py::object finite_or_none(double x) { return std::isfinite(x) ? py::object(py::float_(x)) : py::none(); }

py::dict limit_dict(const chatter::StabilityLimit& l) {
  py::dict d;
  d["spindle_rpm"] = l.spindle_rpm;
  d["depth_limit_mm"] = l.bounded() ? py::object(py::float_(l.depth_limit_m * 1e3)) : py::none();
  d["chatter_frequency_hz"] = l.bounded() ? py::object(py::float_(l.chatter_frequency_hz)) : py::none();
  d["lobe"] = l.bounded() ? py::object(py::int_(l.lobe)) : py::none();
  return d;
}

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
    chatter::resolve_lobe_method(cfg.process, method, nullptr);
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
  // ---- issue 27: the forced vibration of every row with a feed and the
  // part's tolerance (chatter check's block in src/cli/cmd_operations.cpp).
  std::vector<std::optional<chatter::OperationForced>> forced(report.checks.size());
  std::size_t out_of_tolerance = 0;
  {
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < report.checks.size(); ++i) {
      forced[i] = chatter::forced_check(cfg.model, cfg.process, report.checks[i].op);
      if (forced[i] && report.checks[i].op.max_error_m && !forced[i]->within_tolerance) ++out_of_tolerance;
    }
  }
  const py::object json_loads = py::module_::import("json").attr("loads");
  // ---- end of the issue 27 block
  // The JSON of chatter check --json, key for key.
  const bool milling = cfg.process.operation() == chatter::Operation::kMilling;
  const int status = !file.rejected.empty() ? 2 : report.unstable() > 0 || out_of_tolerance > 0 ? 3 : 0;
  py::dict j;
  j["format"] = "chatter-operation-check";
  j["version"] = chatter::version();
  j["config"] = cfg.source.string();
  if (position_mm) j["position_mm"] = *position_mm;
  j["operations_file"] = origin;
  py::dict machine;
  machine["rpm_min"] = opt.machine.rpm_min;
  machine["rpm_max"] = opt.machine.rpm_max;
  j["machine"] = machine;
  j["method_requested"] = method;
  py::list warnings;
  for (const auto& w : cfg.warnings) warnings.append(w);
  for (const auto& w : report.warnings) warnings.append(w);
  j["warnings"] = warnings;
  j["search_depth_rule"] = "max(4 x depth_mm, 20 mm)";
  j["speed_tolerance_pct"] = opt.speed_tolerance * 100.0;
  j["flute_length_mm"] = opt.flute_length_m ? py::object(py::float_(*opt.flute_length_m * 1e3)) : py::none();
  py::list ops;
  for (const auto& c : report.checks) {
    py::dict o;
    o["id"] = c.op.id;
    o["line"] = c.op.line;
    o["spindle_rpm"] = c.op.spindle_rpm;
    o["depth_mm"] = c.op.depth_m * 1e3;
    o["feed_per_tooth_mm"] = c.op.feed_per_tooth_m ? py::object(py::float_(*c.op.feed_per_tooth_m * 1e3)) : py::none();
    o["method"] = c.method;
    o["stable"] = c.stable;
    o["depth_limit_mm"] = c.limit.bounded() ? py::object(py::float_(c.limit.depth_limit_m * 1e3)) : py::none();
    o["searched_depth_mm"] = c.search_depth_m * 1e3;
    o["margin"] = finite_or_none(c.margin);
    o["worst_margin"] = finite_or_none(c.worst_margin);
    o["chatter_frequency_hz"] = c.limit.bounded() ? py::object(py::float_(c.limit.chatter_frequency_hz)) : py::none();
    o["lobe"] = c.limit.bounded() ? py::object(py::int_(c.limit.lobe)) : py::none();
    if (milling) {
      const auto& mp = cfg.process.milling_parameters();
      o["radial_immersion"] = c.op.radial_immersion.value_or(mp.radial_immersion);
      o["teeth"] = c.op.teeth.value_or(mp.teeth);
      o["milling_direction"] = c.op.direction.value_or(mp.direction) == chatter::MillingDirection::kDown ? "down" : "up";
    }
    if (const auto& f = forced[static_cast<std::size_t>(&c - report.checks.data())])  // issue 27
      o["forced"] = json_loads(chatter::forced_check_json(f->response, c.op.max_error_m, f->within_tolerance));
    else
      o["forced"] = py::none();
    if (c.suggestion) {
      py::dict s = limit_dict(*c.suggestion);
      s["margin"] = finite_or_none(c.suggestion_margin);
      const chatter::SpeedPocket& p = *c.suggestion_pocket;
      s["speed_tolerance_pct"] = p.speed_tolerance * 100.0;
      s["worst_limit_mm"] = finite_or_none(p.worst_limit_m * 1e3);
      s["worst_margin"] = finite_or_none(p.worst_margin);
      s["pocket_min_rpm"] = p.pocket_min_rpm;
      s["pocket_max_rpm"] = p.pocket_max_rpm;
      o["suggestion"] = s;
    } else {
      o["suggestion"] = py::none();
    }
    ops.append(o);
  }
  j["operations"] = ops;
  py::list rej;
  for (const auto& b : file.rejected) {
    py::dict r;
    r["line"] = b.line;
    r["id"] = b.id;
    r["reason"] = b.reason;
    rej.append(r);
  }
  j["rejected"] = rej;
  py::dict summary;
  summary["checked"] = report.checks.size();
  summary["stable"] = report.checks.size() - report.unstable();
  summary["unstable"] = report.unstable();
  summary["rejected"] = file.rejected.size();
  summary["out_of_tolerance"] = out_of_tolerance;  // issue 27
  j["summary"] = summary;
  j["exit_status"] = status;
  return j;
}

// ------------------------------------------------------------------ simulate

py::dict series_dict(const std::vector<chatter::SeriesSample>& rows) {
  const auto n = static_cast<py::ssize_t>(rows.size());
  const char* const names[] = {"time_s",        "tool_x_um", "tool_y_um", "workpiece_x_um", "workpiece_y_um",
                               "rel_x_um",      "rel_y_um",  "force_x_n", "force_y_n",      "chip_um"};
  std::vector<py::array_t<double>> cols;
  for (std::size_t c = 0; c < std::size(names); ++c) cols.emplace_back(n);
  py::array_t<bool> in_cut(n);
  std::vector<double*> p;
  for (auto& c : cols) p.push_back(c.mutable_data());
  bool* q = in_cut.mutable_data();
  for (py::ssize_t i = 0; i < n; ++i) {
    const chatter::SeriesSample& r = rows[static_cast<std::size_t>(i)];
    // The units of chatter simulate --out's columns.
    const double v[] = {r.t_s,           r.tool_x_m * 1e6, r.tool_y_m * 1e6, r.workpiece_x_m * 1e6,
                        r.workpiece_y_m * 1e6, r.rel_x_m * 1e6,  r.rel_y_m * 1e6,  r.force_x_n,
                        r.force_y_n,     r.chip_m * 1e6};
    for (std::size_t c = 0; c < std::size(names); ++c) p[c][i] = v[c];
    q[i] = r.in_cut;
  }
  py::dict d;
  for (std::size_t c = 0; c < std::size(names); ++c) d[names[c]] = cols[c];
  d["in_cut"] = in_cut;
  return d;
}

py::dict simulate(const Job& job_in, double rpm, double depth_mm, std::optional<double> feed_per_tooth_mm,
                  std::optional<int> revolutions, std::optional<int> periods, bool linear, bool multiple_regeneration,
                  double rtol, bool record_series, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  const double feed_mm = feed_per_tooth_mm.value_or(cfg.feed_mm.value_or(kDefaultFeedMm));
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError("rpm = " + fmt(rpm) + ": must be > 0 rev/min");
  if (!(std::isfinite(depth_mm) && depth_mm >= 0.0 && depth_mm <= 1000.0))
    throw InputError("depth_mm = " + fmt(depth_mm) + ": must be in [0, 1000] mm");
  if (!(std::isfinite(feed_mm) && feed_mm >= 0.0 && feed_mm <= 100.0))
    throw InputError("feed_per_tooth_mm = " + fmt(feed_mm) + ": must be in [0, 100] mm");
  if (revolutions && periods) throw InputError("revolutions and periods: give one of them");
  const int per_rev = chatter::simulation_periods_per_revolution(cfg.process, rpm, linear);
  int n_periods = 200;
  if (revolutions) {
    if (*revolutions < 1 || *revolutions > 1000000)
      throw InputError("revolutions = " + std::to_string(*revolutions) + ": must be in [1, 1000000]");
    n_periods = *revolutions * per_rev;
  } else if (periods) {
    n_periods = *periods;
  }
  if (n_periods < 4 || n_periods > 10000000)
    throw InputError("periods = " + std::to_string(n_periods) + ": must be in [4, 10000000]");
  if (!(rtol >= 1e-12 && rtol <= 1e-2)) throw InputError("rtol = " + fmt(rtol) + ": must be in [1e-12, 1e-2]");
  chatter::TimeDomainOptions o;
  o.relative_tolerance = rtol;
  chatter::SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_mm * 1e-3;
  st.periods = n_periods;
  st.feed_m = feed_mm * 1e-3;
  st.linear = linear;
  st.multiple_regeneration = multiple_regeneration;
  st.record_series = record_series;
  chatter::SimulationResult r;
  {
    py::gil_scoped_release release;
    const chatter::TimeDomainSimulator sim(cfg.model, cfg.process, o);
    r = sim.simulate(st);
  }
  // The JSON of chatter simulate, key for key, then the arrays.
  py::dict j;
  j["method"] = "time-domain";
  j["config"] = cfg.name;
  j["warnings"] = cfg.warnings;
  if (position_mm) j["position_mm"] = *position_mm;
  j["spindle_rpm"] = rpm;
  j["depth_mm"] = depth_mm;
  j["feed_per_tooth_mm"] = linear ? py::none() : py::object(py::float_(feed_mm));
  j["linear"] = linear;
  j["multiple_regeneration"] = multiple_regeneration;
  j["verdict"] = chatter::to_string(r.verdict);
  j["stable"] = r.verdict == chatter::SimulationVerdict::kStable;
  j["verdict_measure"] = r.verdict_measure;
  j["growth_per_period"] = finite_or_none(r.growth_per_period);
  if (std::isfinite(r.growth_per_period)) {
    py::list m;
    m.append(r.dominant_multiplier.real());
    m.append(r.dominant_multiplier.imag());
    j["dominant_multiplier"] = m;
  } else {
    j["dominant_multiplier"] = py::none();
  }
  j["chatter_frequency_hz"] = finite_or_none(r.chatter_frequency_hz);
  j["dominant_nonharmonic_hz"] = finite_or_none(r.dominant_nonharmonic_hz);
  j["max_amplitude_mm"] = r.max_amplitude_m * 1e3;
  j["out_of_cut_fraction"] = r.out_of_cut_fraction;
  j["floquet_period_s"] = r.floquet_period_s;
  j["tooth_passing_hz"] = r.tooth_passing_hz;
  j["tooth_period_s"] = cfg.process.delay_s(rpm);
  j["periods"] = r.periods;
  j["revolutions"] = static_cast<double>(r.periods) / per_rev;
  j["analysed_from_period"] = r.analysed_from_period;
  py::list harmonics;
  for (std::size_t k = 0; k < r.harmonics.size() && k < 10; ++k) {
    py::dict h;
    h["harmonic"] = r.harmonics[k].harmonic;
    h["frequency_hz"] = r.harmonics[k].frequency_hz;
    h["amplitude_um"] = r.harmonics[k].amplitude_m * 1e6;
    harmonics.append(h);
  }
  j["harmonics"] = harmonics;
  py::dict integ;
  integ["name"] = "SUNDIALS CVODE, Adams-Moulton order <= 5, fixed-point iteration";
  integ["relative_tolerance"] = rtol;
  integ["steps"] = r.steps;
  integ["rhs_evaluations"] = r.rhs_evaluations;
  integ["restarts"] = r.restarts;
  integ["root_stops"] = r.root_stops;
  integ["samples_per_period"] = r.samples_per_period;
  integ["history_capacity"] = r.history_capacity;
  j["integrator"] = integ;
  // ---- issue 27 (the forced vibration the run measured, the teeth out of
  // the cut, the linear-limit warning): one block, the keys of chatter
  // simulate's (src/cli/cmd_simulate.cpp), for the shared records function.
  {
    j["linear_static_chip"] = st.linear_static_chip;
    j["out_of_cut_fraction_per_tooth"] = r.out_of_cut_fraction_per_tooth;
    j["teeth_leave_cut"] = r.teeth_leave_cut;
    py::dict forced, pp, sd;
    pp["x"] = r.forced_peak_to_peak_x_m * 1e6;
    pp["y"] = r.forced_peak_to_peak_y_m * 1e6;
    sd["x"] = r.forced_static_x_m * 1e6;
    sd["y"] = r.forced_static_y_m * 1e6;
    forced["steady"] = r.forced_steady;
    forced["peak_to_peak_um"] = pp;
    forced["static_deflection_um"] = sd;
    forced["surface_location_error_um"] = finite_or_none(r.forced_surface_location_error_m * 1e6);
    j["forced"] = forced;
    j["linear_limit_warning"] =
        r.linear_limit_warning.empty() ? py::object(py::none()) : py::object(py::str(r.linear_limit_warning));
  }
  // ---- end of the issue 27 block
  j["series"] = series_dict(r.series);
  j["periodic"] = series_dict(r.once_per_period);
  // The spectrum of chatter simulate --spectrum (harmonic: 0 where not one).
  const auto ns = static_cast<py::ssize_t>(r.spectrum_hz.size());
  py::array_t<double> fr(ns), amp(ns);
  py::array_t<int> harm(ns);
  const double res = r.spectrum_hz.size() > 1 ? r.spectrum_hz[1] - r.spectrum_hz[0] : 0.0;
  for (py::ssize_t k = 0; k < ns; ++k) {
    const double fk = r.spectrum_hz[static_cast<std::size_t>(k)];
    const long hk = std::lround(fk * r.floquet_period_s);
    const bool is_harmonic = hk >= 1 && std::abs(fk - static_cast<double>(hk) / r.floquet_period_s) <= 0.5 * res;
    fr.mutable_data()[k] = fk;
    amp.mutable_data()[k] = r.spectrum_amplitude_m[static_cast<std::size_t>(k)] * 1e6;
    harm.mutable_data()[k] = is_harmonic ? static_cast<int>(hk) : 0;
  }
  py::dict spec;
  spec["frequency_hz"] = fr;
  spec["amplitude_um"] = amp;
  spec["harmonic"] = harm;
  j["spectrum"] = spec;
  return j;
}

// For bench/bench_python.py: seconds of the bare C++ work of lobes() on a
// built solver (lobe_envelope or the diagnosed loop; a repeated lobes() call
// finds its solver in the job's cache), no Python objects, so the module's
// overhead can be measured against it.
double time_lobes_cpp(const Job& job, const std::string& method,
                      const py::array_t<double, py::array::c_style | py::array::forcecast>& rpm, double depth_max_mm,
                      int threads) {
  const std::vector<double> speeds(rpm.data(), rpm.data() + rpm.size());
  const unsigned n = thread_count(threads);
  py::gil_scoped_release release;
  const auto solver = chatter::make_lobe_solver(method, job.cfg->model, job.cfg->process, depth_max_mm * 1e-3);
  const auto t0 = std::chrono::steady_clock::now();
  if (solver->diagnostic_columns().empty()) {
    const auto rows = chatter::lobe_envelope(*solver, speeds, n);
  } else {
    std::vector<chatter::DiagnosedLimit> rows(speeds.size());
    chatter::parallel_for(speeds.size(), n, [&](std::size_t i) { rows[i] = solver->limit_with_diagnostics(speeds[i]); });
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// ------------------------------------------------------------------ surface

/// `chatter surface`'s table as arrays: positions placed by the io layer
/// (chatter::surface_positions, the CLI's), the sweep by lobe_surface.
py::dict surface(const Job& job, const std::string& method, std::optional<double> position_min_mm,
                 std::optional<double> position_max_mm, int position_points, std::optional<double> rpm_min,
                 std::optional<double> rpm_max, std::optional<int> rpm_points, std::optional<double> depth_max_mm,
                 int threads, const std::optional<py::dict>& options) {
  const chatter::Config& cfg = *job.cfg;
  const chatter::SurfacePositions pos = chatter::surface_positions(cfg, position_min_mm, position_max_mm, position_points);
  const std::vector<double> speeds = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  if (static_cast<long long>(pos.m.size()) * static_cast<long long>(speeds.size()) > kMaxSurfacePoints)
    throw InputError("position_points x rpm_points = " + std::to_string(pos.m.size()) + " x " +
                     std::to_string(speeds.size()) + ": at most " + std::to_string(kMaxSurfacePoints) +
                     " solves (a surface that size would not finish)");
  const double dmax = depth_max_mm.value_or(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm));
  if (!(std::isfinite(dmax) && dmax > 0.0)) throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > 0 mm");
  const unsigned nthreads = thread_count(threads);
  const chatter::SolverDescriptor& descriptor = chatter::find_lobe_method(method);
  const chatter::SolverValues values = solver_values(cfg, descriptor, method, options);
  const double depth_max_m = dmax * 1e-3;
  std::vector<std::vector<chatter::StabilityLimit>> rows;
  {
    py::gil_scoped_release release;
    // The method checked at the first position before the sweep (as the CLI).
    (void)chatter::make_lobe_solver(method, chatter::model_at_position(cfg, pos.m.front()), cfg.process, depth_max_m,
                                    values);
    const chatter::SolverFactory factory = [&](const chatter::StructuralModel& model) {
      return chatter::make_lobe_solver(method, model, cfg.process, depth_max_m, values);
    };
    rows = chatter::lobe_surface(cfg.model, cfg.position, pos.m, speeds, factory, nthreads);
  }
  const auto n = static_cast<py::ssize_t>(pos.m.size() * speeds.size());
  py::array_t<double> x(n), s(n), d(n), f(n);
  py::array_t<int> k(n);
  auto xp = x.mutable_unchecked<1>();
  auto sp = s.mutable_unchecked<1>();
  auto dp = d.mutable_unchecked<1>();
  auto fp = f.mutable_unchecked<1>();
  auto kp = k.mutable_unchecked<1>();
  py::ssize_t i = 0;
  for (std::size_t p = 0; p < rows.size(); ++p)
    for (const chatter::StabilityLimit& r : rows[p]) {
      xp(i) = pos.mm[p];
      sp(i) = r.spindle_rpm;
      dp(i) = r.depth_limit_m * 1e3;  // +inf where unbounded, as the CSV
      fp(i) = r.bounded() ? r.chatter_frequency_hz : std::nan("");
      kp(i) = r.bounded() ? r.lobe : -1;
      ++i;
    }
  py::dict out;
  out["position_mm"] = x;
  out["spindle_rpm"] = s;
  out["depth_limit_mm"] = d;
  out["chatter_frequency_hz"] = f;
  out["lobe"] = k;
  return out;
}

// ------------------------------------------------------------------ Monte Carlo

/// `chatter lobes --samples N`'s numbers as arrays (docs/uncertainty.md): the
/// nominal lobes, the 5/50/95 % quantile lobes of N models drawn from the
/// config's [uncertainty] spreads, and the probability of stability over a
/// (speed, depth) grid chosen as the CLI's (chatter::probability_depth_grid).
/// Same seed, same numbers as the CLI, whatever `threads`.
py::dict uncertain_lobes(const Job& job_in, const std::string& method, long long samples, long long seed,
                         std::optional<double> rpm_min, std::optional<double> rpm_max, std::optional<int> rpm_points,
                         std::optional<double> depth_max_mm, int depth_points,
                         std::optional<double> probability_depth_max_mm, int threads,
                         const std::optional<py::dict>& options, std::optional<double> position_mm) {
  const Job job = at_position(job_in, position_mm);
  const chatter::Config& cfg = *job.cfg;
  if (!cfg.uncertainty)
    throw InputError(cfg.source.string() +
                     ": no [uncertainty] table (give the 1-sigma spreads in percent; docs/config.md)");
  if (const std::string why = cfg.uncertainty->validate(cfg.model, cfg.process); !why.empty())
    throw InputError(cfg.source.string() + ": uncertainty: " + why);
  const std::vector<double> speeds = even_speeds(cfg, rpm_min, rpm_max, rpm_points);
  if (samples < 1) throw InputError("samples = " + std::to_string(samples) + ": must be >= 1");
  if (samples > kMaxMonteCarloSolves / static_cast<long long>(speeds.size()))
    throw InputError("samples x rpm_points = " + std::to_string(samples) + " x " + std::to_string(speeds.size()) +
                     ": at most " + std::to_string(kMaxMonteCarloSolves) +
                     " limits are held in memory (32 bytes each); use fewer samples or speeds");
  if (seed < 0) throw InputError("seed = " + std::to_string(seed) + ": must be an integer >= 0");
  if (depth_points < 2 || depth_points > 10000)
    throw InputError("depth_points = " + std::to_string(depth_points) + ": must be in [2, 10000]");
  const double dmax = depth_max_mm.value_or(cfg.sweep.depth_max_mm.value_or(kDefaultDepthMaxMm));
  if (!(std::isfinite(dmax) && dmax > 0.0)) throw InputError("depth_max_mm = " + fmt(dmax) + ": must be > 0 mm");
  if (probability_depth_max_mm && !(std::isfinite(*probability_depth_max_mm) && *probability_depth_max_mm > 0.0))
    throw InputError("probability_depth_max_mm = " + fmt(*probability_depth_max_mm) + ": must be > 0 mm");
  const unsigned nthreads = thread_count(threads);
  const std::shared_ptr<const Built> built = build_solver(job, method, dmax * 1e-3, options);
  const chatter::SolverValues& values = built->values;
  const double depth_max_m = dmax * 1e-3;
  std::vector<chatter::StabilityLimit> nominal;
  chatter::UncertainLobes mc;
  chatter::ProbabilityDepthGrid grid;
  {
    py::gil_scoped_release release;
    nominal = chatter::lobe_envelope(*built->solver, speeds, nthreads);
    const chatter::SampleSolverFactory factory = [&](const chatter::StructuralModel& model,
                                                     const chatter::Process& process) {
      return chatter::make_lobe_solver(method, model, process, depth_max_m, values);
    };
    const auto rows = chatter::monte_carlo_limits(cfg.model, cfg.process, *cfg.uncertainty,
                                                  static_cast<std::uint64_t>(seed), 0,
                                                  static_cast<std::uint64_t>(samples), speeds, factory, nthreads);
    grid = chatter::probability_depth_grid(rows, dmax, depth_points, probability_depth_max_mm);
    mc = chatter::reduce_monte_carlo(
        rows, grid.depths_m,
        std::vector<double>(std::begin(chatter::kUncertaintyLevels), std::end(chatter::kUncertaintyLevels)));
  }
  const auto n = static_cast<py::ssize_t>(speeds.size());
  const auto nd = static_cast<py::ssize_t>(grid.depths_m.size());
  py::array_t<double> s(n), d(n), depths(nd);
  py::array_t<double> prob({n, nd});
  auto sp = s.mutable_unchecked<1>();
  auto dp = d.mutable_unchecked<1>();
  auto gp = depths.mutable_unchecked<1>();
  auto pp = prob.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    sp(i) = speeds[static_cast<std::size_t>(i)];
    dp(i) = nominal[static_cast<std::size_t>(i)].depth_limit_m * 1e3;  // +inf where unbounded, as lobes()
    for (py::ssize_t j = 0; j < nd; ++j)
      pp(i, j) = mc.probability_stable[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  }
  for (py::ssize_t j = 0; j < nd; ++j) gp(j) = grid.depths_m[static_cast<std::size_t>(j)] * 1e3;
  py::dict out;
  out["method"] = built->solver->method();
  out["warnings"] = cfg.warnings;
  out["notes"] = built->notes;
  out["samples"] = samples;
  out["seed"] = seed;
  out["spindle_rpm"] = s;
  out["depth_limit_mm"] = d;
  for (std::size_t l = 0; l < mc.levels.size(); ++l) {
    py::array_t<double> q(n);
    auto qp = q.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) qp(i) = mc.quantile_depth_m[l][static_cast<std::size_t>(i)] * 1e3;
    out[py::str(chatter::quantile_column_name(mc.levels[l]))] = q;
  }
  out["depth_mm"] = depths;
  out["probability_stable"] = prob;
  if (position_mm) out["position_mm"] = *position_mm;
  return out;
}

std::shared_ptr<const chatter::Config> job_config(const py::handle& job) { return job.cast<const Job&>().cfg; }

PYBIND11_MODULE(chatter, m) {
  m.doc() = "chatter: regenerative chatter prediction and stability lobes (docs/python.md)";
  m.attr("__version__") = chatter::version();
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<chatter::NumericalError> numerical_error(m, "NumericalError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      input_error(e.what());
    } catch (const chatter::NumericalError& e) {
      numerical_error(e.what());
    }
  });

  py::class_<Job>(m, "Job",
                  "A structural model, a cutting process and sweep defaults: chatter.load(path) or "
                  "chatter.Job(process=..., tool_modes=..., workpiece_modes=...). Immutable.")
      .def(py::init(&make_job), "config"_a = py::none(), py::kw_only(), "name"_a = py::none(),
           "process"_a = py::none(), "tool_modes"_a = py::none(), "workpiece_modes"_a = py::none(),
           "sweep"_a = py::none(), "strict"_a = false,
           "A job from config keys (the TOML config's tables as dicts, docs/config.md), validated by the loader.")
      .def_static(
          "from_toml", [](const std::string& text, const std::string& origin,
                          bool strict) { return job_from(chatter::parse_config(text, origin), strict); },
          "text"_a, "origin"_a = "<string>", "strict"_a = false, "A job from TOML text (origin names it in messages).")
      .def_property_readonly("name", [](const Job& j) { return j.cfg->name; })
      .def_property_readonly("source", [](const Job& j) { return j.cfg->source.string(); })
      .def_property_readonly("operation",
                             [](const Job& j) {
                               return j.cfg->process.operation() == chatter::Operation::kMilling ? "milling"
                                                                                                  : "turning";
                             })
      .def_property_readonly("warnings", [](const Job& j) { return j.cfg->warnings; })
      .def_property_readonly("feed_mm", [](const Job& j) { return optional_number(j.cfg->feed_mm); })
      .def_property_readonly("sweep",
                             [](const Job& j) {
                               py::dict d;
                               d["rpm_min"] = optional_number(j.cfg->sweep.rpm_min);
                               d["rpm_max"] = optional_number(j.cfg->sweep.rpm_max);
                               d["rpm_points"] = optional_int(j.cfg->sweep.rpm_points);
                               d["depth_max_mm"] = optional_number(j.cfg->sweep.depth_max_mm);
                               return d;
                             })
      .def(
          "at_position", [](const Job& j, double position_mm) { return at_position(j, position_mm); },
          "position_mm"_a,
          "The job with the structure at a tool position, mm (docs/position.md); keeps its own solvers.")
      .def_property_readonly("position_range_mm",
                             [](const Job& j) -> py::object {
                               if (j.cfg->position.empty()) return py::none();
                               const auto [lo, hi] = j.cfg->position.range_m();
                               return py::make_tuple(lo * 1e3, hi * 1e3);
                             })
      .def("__repr__", [](const Job& j) {
        return "<chatter.Job '" + j.cfg->name + "' (" +
               (j.cfg->process.operation() == chatter::Operation::kMilling ? "milling" : "turning") + ")>";
      });

  m.def(
      "load",
      [](const py::object& path, bool strict) {
        const std::string p = py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
        chatter::Config c;
        {
          py::gil_scoped_release release;
          c = chatter::load_config(p);
        }
        return job_from(std::move(c), strict);
      },
      "path"_a, "strict"_a = false, "Reads and validates a TOML config (as the CLI does).");
  m.def("methods", &chatter::lobe_methods, "The lobe methods of this build, in registry order.");
  m.def("lobes", &lobes, "job"_a, "method"_a = "analytic", py::kw_only(), "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "rpm_points"_a = py::none(), "depth_max_mm"_a = py::none(), "rpm"_a = py::none(),
        "threads"_a = 0, "options"_a = py::none(), "position_mm"_a = py::none(),
        "The stability-lobe table as NumPy arrays (chatter lobes).");
  m.def("point", &point, "job"_a, py::kw_only(), "rpm"_a, "depth_mm"_a, "method"_a = "analytic",
        "depth_max_mm"_a = py::none(), "options"_a = py::none(), "position_mm"_a = py::none(),
        "One operating point (chatter point's JSON).");
  m.def("check", &check, "job"_a, "operations"_a, py::kw_only(), "method"_a = "auto", "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "speed_tolerance_pct"_a = kDefaultSpeedTolPct, "threads"_a = 0,
        "position_mm"_a = py::none(), "Checks operations (list of dicts or a CSV path) as chatter check --json.");
  m.def("surface", &surface, "job"_a, "method"_a = "analytic", py::kw_only(), "position_min_mm"_a = py::none(),
        "position_max_mm"_a = py::none(), "position_points"_a = kDefaultPositionPoints, "rpm_min"_a = py::none(),
        "rpm_max"_a = py::none(), "rpm_points"_a = py::none(), "depth_max_mm"_a = py::none(), "threads"_a = 0,
        "options"_a = py::none(), "The lobe surface over (position, speed) as NumPy arrays (chatter surface).");
  m.def("uncertain_lobes", &uncertain_lobes, "job"_a, "method"_a = "analytic", py::kw_only(), "samples"_a,
        "seed"_a = 1, "rpm_min"_a = py::none(), "rpm_max"_a = py::none(), "rpm_points"_a = py::none(),
        "depth_max_mm"_a = py::none(), "depth_points"_a = kDefaultDepthPoints,
        "probability_depth_max_mm"_a = py::none(), "threads"_a = 0, "options"_a = py::none(),
        "position_mm"_a = py::none(),
        "Monte Carlo lobes over the config's [uncertainty] spreads as NumPy arrays (chatter lobes --samples).");
  m.def("simulate", &simulate, "job"_a, py::kw_only(), "rpm"_a, "depth_mm"_a, "feed_per_tooth_mm"_a = py::none(),
        "revolutions"_a = py::none(), "periods"_a = py::none(), "linear"_a = false,
        "multiple_regeneration"_a = false, "rtol"_a = kDefaultSimRtol, "record_series"_a = true,
        "position_mm"_a = py::none(),
        "One time-domain simulation (chatter simulate's JSON plus the series arrays).");
  m.def("_time_lobes_cpp", &time_lobes_cpp, "job"_a, "method"_a, "rpm"_a, "depth_max_mm"_a, "threads"_a = 1,
        "Benchmark hook: seconds of the C++ work of lobes() alone.");
  bind_forced(m);
}
