// Shared pieces of the Python module (python/module.hpp).
#include "bindings.hpp"
#include "module.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include <nlohmann/json.hpp>

#include "chatter/operations.hpp"
#include "chatter/records.hpp"
#include "chatter/report.hpp"
#include "chatter/number_text.hpp"

namespace chatter_py {

std::string fmt(double x) { return chatter::number_text(x); }

Job job_from(chatter::Config c, bool strict) {
  if (strict && !c.warnings.empty()) {
    std::string message;
    for (const std::string& w : c.warnings) message += (message.empty() ? "" : "\n") + w + " (strict)";
    throw InputError(message);
  }
  return Job{std::make_shared<const chatter::Config>(std::move(c))};
}

Job at_position(const Job& job, const std::optional<double>& position_mm) {
  if (!position_mm) return job;
  return Job{std::make_shared<const chatter::Config>(chatter::config_at_position(*job.cfg, *position_mm, "position_mm"))};
}

py::object optional_number(const std::optional<double>& x) { return x ? py::cast(*x) : py::none(); }
py::object optional_int(const std::optional<int>& x) { return x ? py::cast(*x) : py::none(); }

py::object finite_or_none(double x) { return std::isfinite(x) ? py::object(py::float_(x)) : py::none(); }

namespace {

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

}  // namespace

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
  // As every front end: the config's defaults for the options not given.
  return chatter::with_config_defaults(descriptor, cfg, std::move(values));
}

std::shared_ptr<const Built> build_solver(const Job& job, const std::string& requested, double depth_max_m,
                                          const std::optional<py::dict>& options) {
  const chatter::Config& cfg = *job.cfg;
  const std::string method = chatter::resolve_lobe_method(requested, cfg.model, cfg.process);
  const chatter::SolverDescriptor& descriptor = chatter::find_lobe_method(method);
  const chatter::SolverValues values = solver_values(cfg, descriptor, method, options);
  std::string key = requested + "|" + method + "|" + value_key(depth_max_m);
  for (const auto& [k, v] : values) key += "|" + k + "=" + value_key(v);
  {
    std::lock_guard<std::mutex> lock(job.cache->mutex);
    if (const auto it = job.cache->solvers.find(key); it != job.cache->solvers.end()) return it->second;
  }
  auto b = std::make_shared<Built>();
  chatter::ConfiguredSolver c;
  {
    py::gil_scoped_release release;
    c = chatter::configure_solver(requested, cfg, depth_max_m, values, chatter::ArgStyle::kKeyword);
  }
  b->recipe = c.recipe();
  b->descriptor = c.descriptor;
  b->solver = std::move(c.solver);
  b->notes = std::move(c.notes);
  b->values = std::move(c.values);
  std::lock_guard<std::mutex> lock(job.cache->mutex);
  if (job.cache->solvers.size() >= kMaxCachedSolvers) job.cache->solvers.clear();
  job.cache->solvers.emplace(key, b);
  return b;
}

unsigned thread_count(int t) {
  if (t < 0 || t > 1024) throw InputError("threads = " + std::to_string(t) + ": must be in [0, 1024] (0 = every core)");
  return static_cast<unsigned>(t);
}

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
  chatter::check_spindle_rpm(lo, "rpm_min");
  chatter::check_spindle_rpm(hi, "rpm_max");
  if (!(std::isfinite(hi) && hi > lo))
    throw InputError("rpm_max = " + fmt(hi) + ": must be > rpm_min (" + fmt(lo) + ")");
  if (n < 2) throw InputError("rpm_points = " + std::to_string(n) + ": must be >= 2");
  if (n > kMaxRpmPoints)
    throw InputError("rpm_points = " + std::to_string(n) + ": at most " + std::to_string(kMaxRpmPoints) + " speeds");
  return chatter::evenly_spaced_speeds(lo, hi, n);
}

py::array_t<double> array_of(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

namespace {

// One column as a NumPy array of its own dtype; a grid column reshaped.
py::object column_array(const chatter::Column& c) {
  py::object a = std::visit(
      [](const auto& v) -> py::object {
        using T = typename std::decay_t<decltype(v)>::value_type;
        const auto n = static_cast<py::ssize_t>(v.size());
        if constexpr (std::is_same_v<T, std::string>) {
          py::list cells;
          for (const std::string& t : v) cells.append(t);
          return py::module_::import("numpy").attr("array")(cells, py::arg("dtype") = "str");
        } else if constexpr (std::is_same_v<T, bool>) {
          py::array_t<bool> out(n);
          for (py::ssize_t i = 0; i < n; ++i) out.mutable_data()[i] = v[static_cast<std::size_t>(i)];
          return out;
        } else {
          py::array_t<T> out(n);
          std::copy(v.begin(), v.end(), out.mutable_data());
          return out;
        }
      },
      c.values);
  if (c.cols > 0) {
    const auto cols = static_cast<py::ssize_t>(c.cols);
    a = a.attr("reshape")(py::len(a) / cols, cols);
  }
  return a;
}

py::dict columns_dict(const std::vector<chatter::Column>& columns) {
  py::dict out;
  for (const chatter::Column& c : columns) out[py::str(c.name)] = column_array(c);
  return out;
}

// The dict a group's JSON pointer names ("/path", "/records/0"): dict keys
// and list indices followed from `root`; a missing last key becomes {}.
py::dict dict_at(py::dict root, const std::string& pointer) {
  py::object node = root;
  std::size_t start = 1;
  while (start <= pointer.size()) {
    const std::size_t slash = pointer.find('/', start);
    const std::string token = pointer.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    const bool last = slash == std::string::npos;
    if (py::isinstance<py::list>(node)) {
      node = node.cast<py::list>()[std::stoul(token)];
    } else {
      py::dict d = node.cast<py::dict>();
      if (!d.contains(token.c_str())) {
        if (!last) throw std::logic_error("column group " + pointer + ": no key " + token);
        d[py::str(token)] = py::dict();
      }
      node = d[py::str(token)];
    }
    if (last) break;
    start = slash + 1;
  }
  return node.cast<py::dict>();
}

}  // namespace

py::dict to_python(const chatter::ColumnRecord& r) {
  py::dict out = to_python(r.fields).cast<py::dict>();
  for (const chatter::Column& c : r.columns) out[py::str(c.name)] = column_array(c);
  for (const chatter::ColumnGroup& g : r.groups) {
    py::dict d = dict_at(out, g.at);
    for (const chatter::Column& c : g.columns) d[py::str(c.name)] = column_array(c);
  }
  return out;
}

py::tuple to_python_table(const chatter::ColumnRecord& r) {
  return py::make_tuple(columns_dict(r.columns), to_python(r.fields));
}

}  // namespace chatter_py

std::shared_ptr<const chatter::Config> job_config(const pybind11::handle& job) {
  return job.cast<const chatter_py::Job&>().cfg;
}

namespace chatter_py {

py::object to_python(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list out;
      for (const auto& e : j) out.append(to_python(e));
      return out;
    }
    case nlohmann::json::value_t::object: {
      py::dict out;
      for (const auto& [k, v] : j.items()) out[py::str(k)] = to_python(v);
      return out;
    }
    default: return py::none();  // binary and discarded values never occur in a record
  }
}

}  // namespace chatter_py
