// chatter.Job, chatter.load, chatter.methods: a config loaded from a file,
// TOML text or Python dicts, through the config loader (docs/python.md).
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bindings.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

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
  if (py::isinstance<py::float_>(v)) {
    // An integral float (4.0, often from NumPy) is written as an integer, so
    // it is accepted where the loader wants one (teeth); number keys take
    // integers too.
    const double x = v.cast<double>();
    if (std::isfinite(x) && x == std::trunc(x) && std::abs(x) < 9007199254740992.0)
      return std::to_string(static_cast<long long>(x));
    return toml_double(x);
  }
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

}  // namespace

void bind_job(py::module_& m) {
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
                               return std::string(j.cfg->process.operation_name());
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
               std::string(j.cfg->process.operation_name()) + ")>";
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
  m.def(
      "_plot_styles",
      [] {
        // Each method's line in the compare plots (the registry's PlotStyle):
        // colour, gnuplot width, dash lengths, gnuplot point type (0: a line).
        py::dict out;
        for (const auto& d : chatter::solver_registry()) {
          std::vector<double> dash;
          for (const char* c = d.plot.dash; *c;) {
            char* end = nullptr;
            const double x = std::strtod(c, &end);
            if (end != c) {
              dash.push_back(x);
              c = end;
            } else {
              ++c;
            }
          }
          out[py::str(d.name)] = py::make_tuple(d.plot.colour, d.plot.width, dash, d.plot.point_type);
        }
        return out;
      },
      "The compare plot's style of each method (registry): (colour, width, dashes, point type).");
}

}  // namespace chatter_py
