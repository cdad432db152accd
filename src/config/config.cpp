// TOML configuration reader. The key reference (units, defaults, rules) is
// docs/config.md; keep the two in step.
//
// Every bad input becomes a chatter::InputError whose message names the
// origin, the full key path (0-based array indices) and the rule:
//   <origin>: <key.path> = <value as written>: <rule>
//   <origin>: <key.path>: missing (required, <unit>, <rule>)
//   <origin>: <key.path>: unknown key (did you mean <key>?)
//   <origin>:<line>:<col>: <TOML syntax error>
//   <path>: cannot read file (<reason>)
// No toml++ exception escapes the reader; an InputError of the model
// constructors is given the file and table (model_checked).
// The reading primitives (Document, Table, Range, Quantity, Band, ...) are
// in config_read.hpp; each table has its section reader (config_sections.hpp):
// config_process.cpp, config_structure.cpp ([tool], [workpiece]),
// config_positions.cpp, config_sweep.cpp, config_uncertainty.cpp,
// config_optimization.cpp, config_grinding.cpp; `include` is merged first by
// config_include.cpp. This file is the top level: read_config (a cutting
// process) and read_grinding_config (a [grinding] config) call them in order,
// parse_config / load_config and parse_grinding_config / load_grinding_config
// wrap them with the same parsing.
#include "chatter/io/config.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/io/job.hpp"

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#include "config_sections.hpp"

namespace chatter::config_detail {
namespace {

// A table as written: numbers exactly as parsed (integers as int when they
// fit), arrays of numbers as lists, strings and booleans as they are, any
// other value as its TOML text.
std::vector<std::pair<std::string, SolverValue>> as_given(const toml::table& t) {
  std::vector<std::pair<std::string, SolverValue>> out;
  for (const auto& [key, node] : t) {
    SolverValue v;
    if (const auto* i = node.as_integer()) {
      const std::int64_t x = i->get();
      if (x >= std::numeric_limits<int>::min() && x <= std::numeric_limits<int>::max()) v = static_cast<int>(x);
      else v = static_cast<double>(x);
    } else if (const auto* f = node.as_floating_point()) {
      v = f->get();
    } else if (const auto* s = node.as_string()) {
      v = s->get();
    } else if (const auto* b = node.as_boolean()) {
      v = b->get();
    } else if (const auto* a = node.as_array();
               a && !a->empty() && std::all_of(a->begin(), a->end(), [](const toml::node& e) { return e.is_number(); })) {
      std::vector<double> xs;
      for (const toml::node& e : *a) xs.push_back(e.value<double>().value_or(0.0));
      v = xs;
    } else {
      std::ostringstream os;
      os << toml::toml_formatter{node};
      v = os.str();
    }
    out.emplace_back(std::string(key.str()), std::move(v));
  }
  return out;
}

std::string config_name(const Table& root, const Document& doc) {
  const auto name = root.string("name");
  if (name && name->empty()) doc.error("name", *root.find("name"), "must not be empty");
  if (name) return *name;
  const std::string stem = std::filesystem::path(doc.origin()).stem().string();
  return stem.empty() ? doc.origin() : stem;
}

Config read_config(const toml::table& root_table, const Document& doc) {
  const Table root(doc, root_table, "");
  // A grinding config has no cutting process: one message, nothing else.
  if (root.has("grinding"))
    doc.fail_key("grinding", "a grinding config ([grinding]) has no turning or milling [process], so no stability "
                             "lobes: read it with the grinding commands (chatter grind ..., load_grinding_config)");
  // (`include` was merged and removed before; listed so a near miss is named.)
  constexpr std::string_view kTopKeys[] = {"name",      "process",     "tool",        "workpiece",    "sweep",
                                           "positions", "uncertainty", "optimization", "include"};
  root.reject_unknown(kTopKeys);

  Config config;
  config.name = config_name(root, doc);
  attempt_void([&] { config.process = read_process(root, &config.feed_mm, &config.flute_length_m); });
  if (const toml::table* p = root_table["process"].as_table()) config.process_given = as_given(*p);
  const std::size_t before_bodies = doc.error_count();
  attempt_void([&] { config.model.tool = read_body(root, "tool"); });
  attempt_void([&] { config.model.workpiece = read_body(root, "workpiece"); });
  const bool has_positions = root.has("positions");
  if (has_positions)
    attempt_void([&] { config.position.stations = read_positions(root, config.model); });
  // A body whose modes all had errors looks rigid: say so only without them.
  if (doc.error_count() == before_bodies && !has_positions && config.model.rigid())
    doc.error_key("tool.modes, workpiece.modes", "both bodies are rigid: give at least one mode (or a measured frf)");
  attempt_void([&] { config.sweep = read_sweep(root); });
  if (doc.error_count() == before_bodies) {
    config.position.cantilever = cantilever_refs(root_table);
    if (has_positions && !config.position.cantilever.empty()) {
      doc.error_key("positions", "not with a cantilever workpiece mode (workpiece.modes[" +
                                     std::to_string(config.position.cantilever.front().workpiece_mode) +
                                     "].cantilever already makes the model depend on the position): give one of them");
      config.position.cantilever.clear();
    }
    if (!config.position.stations.empty()) config.model = config.position.stations.front().model;
  }
  // Checked against the model and process read above, so only when they are sound.
  if (doc.error_count() == 0)
    attempt_void([&] { config.uncertainty = read_uncertainty(root, config.model, config.process); });
  if (doc.error_count() == 0)
    attempt_void([&] { config.optimization = read_optimization(root, config.process); });
  doc.throw_if_errors();
  // (Cantilever lengths are checked when a position is asked for, so a config
  // with two bars of different lengths still loads for the other commands.)
  if (!config.position.stations.empty())
    if (const std::string why = config.position.validate(); !why.empty())
      throw InputError(doc.origin() + ": " + why);  // a rule above is missing: still name the file
  warn_frequency_vs_speeds(root_table, doc, config);
  config.warnings = doc.take_warnings();
  return config;
}

GrindingConfig read_grinding_config(const toml::table& root_table, const Document& doc) {
  const Table root(doc, root_table, "");
  constexpr std::string_view kTopKeys[] = {"name", "grinding", "tool", "workpiece"};
  for (auto&& [key, value] : root_table) {
    const std::string_view k = key.str();
    if (k == "process" || k == "sweep" || k == "positions" || k == "uncertainty" || k == "optimization")
      doc.error_key(std::string(k), "not in a grinding config (a config is a cutting process with [process], or "
                                    "grinding with [grinding]; its robot's modes go in [[tool.modes]])");
    else if (std::find(std::begin(kTopKeys), std::end(kTopKeys), k) == std::end(kTopKeys))
      doc.error_key(key_text(k), unknown_key_rule(k, kTopKeys));
  }
  GrindingConfig config;
  config.name = config_name(root, doc);
  attempt_void([&] { config.process = read_grinding(root); });
  attempt_void([&] { config.robot.tool = read_body(root, "tool"); });
  attempt_void([&] { config.robot.workpiece = read_body(root, "workpiece"); });
  if (config.robot.has_measured())
    doc.error_key(config.robot.tool.measured.empty() ? "workpiece.frf" : "tool.frf",
                  "not in a grinding config: `chatter grind simulate` integrates modes ([[tool.modes]]; fit them "
                  "from the measurement with `chatter fit`)");
  doc.throw_if_errors();
  config.warnings = doc.take_warnings();
  return config;
}

// TOML allows non-ASCII characters only inside strings and comments. toml++
// 3.3 reaches __builtin_unreachable (undefined behaviour) when it tests some
// non-ASCII code points for whitespace (is_non_ascii_horizontal_whitespace,
// e.g. U+00B0 or U+0490; found by fuzzing, fuzz/corpus/config/crash_*), in
// values, strings and keys alike. So the parser is only ever handed ASCII:
// in the copy it gets, non-ASCII bytes of comments become spaces (byte for
// byte, positions kept) and every other non-ASCII code point becomes a
// \uXXXX escape, which a basic string decodes back to the same character and
// which anywhere else is the same syntax error the character would be.
// Invalid UTF-8 is refused with its line number.
std::string sanitize_for_parser(const std::string& t, const std::string& origin) {
  std::string out;
  out.reserve(t.size());
  bool comment = false, basic = false, literal = false;
  std::size_t line = 1;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const auto c = static_cast<unsigned char>(t[i]);
    if (c < 0x80) {
      if (c == '\n') {
        ++line;
        comment = false;
      } else if (!basic && !literal && c == '#') {
        comment = true;
      } else if (!comment && !literal && c == '"') {
        basic = !basic;
      } else if (!comment && !basic && c == '\'') {
        literal = !literal;
      } else if (basic && c == '\\' && i + 1 < t.size() && t[i + 1] != '\n') {
        out += t[i++];  // the escaped character cannot end the string
      }
      out += t[i];
      continue;
    }
    // Decode one UTF-8 sequence.
    const int n = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 0;
    char32_t cp = n == 4 ? (c & 0x07u) : n == 3 ? (c & 0x0Fu) : (c & 0x1Fu);
    bool ok = n > 0 && c < 0xF5 && i + static_cast<std::size_t>(n) <= t.size();
    for (int k = 1; ok && k < n; ++k) {
      const auto cc = static_cast<unsigned char>(t[i + static_cast<std::size_t>(k)]);
      ok = (cc & 0xC0u) == 0x80u;
      cp = (cp << 6) | (cc & 0x3Fu);
    }
    if (!ok || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF) || (n == 2 && cp < 0x80) ||
        (n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000))
      throw InputError(origin + ":" + std::to_string(line) + ": not valid UTF-8 text");
    if (comment) {
      out.append(static_cast<std::size_t>(n), ' ');
    } else {
      char buf[16];
      std::snprintf(buf, sizeof buf, cp > 0xFFFF ? "\\U%08X" : "\\u%04X", static_cast<unsigned>(cp));
      out += buf;
    }
    i += static_cast<std::size_t>(n) - 1;
  }
  return out;
}

}  // namespace
}  // namespace chatter::config_detail

namespace chatter {

namespace {

// The text of a config file. @throws InputError "<file>: cannot read file (...)".
std::string read_text(const std::filesystem::path& file) {
  const std::string origin = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw InputError(origin + ": cannot read file (is a directory)");
  errno = 0;
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(origin + ": cannot read file (" +
                     (err != 0 ? std::generic_category().message(err) : std::string("cannot open")) + ")");
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(origin + ": cannot read file (read error)");
  return buffer.str();
}


// The TOML table of a text (sanitized, NUL refused; `toml_text` set to the
// text parsed). @throws InputError "<origin>:<line>:<col>: <syntax error>".
toml::table parse_toml(const std::string& original_text, const std::string& origin, std::string* toml_text) {
  *toml_text = config_detail::sanitize_for_parser(original_text, origin);
  // A NUL byte is never valid TOML; toml++ 3.3 asserts on some (found by
  // fuzzing, fuzz/corpus/config/crash_nul_in_key.toml), so refuse it first.
  if (const auto nul = toml_text->find('\0'); nul != std::string::npos) {
    const auto line = 1 + std::count(toml_text->begin(), toml_text->begin() + static_cast<std::ptrdiff_t>(nul), '\n');
    throw InputError(origin + ":" + std::to_string(line) + ": contains a NUL byte: a config must be UTF-8 text");
  }
#if TOML_EXCEPTIONS
  try {
    return toml::parse(std::string_view(*toml_text), std::string_view(origin));
  } catch (const toml::parse_error& e) {
    throw InputError(origin + ":" + std::to_string(e.source().begin.line) + ":" +
                     std::to_string(e.source().begin.column) + ": " + std::string(e.description()));
  }
#else
  toml::parse_result result = toml::parse(std::string_view(*toml_text), std::string_view(origin));
  if (!result) {
    const toml::parse_error& e = result.error();
    throw InputError(origin + ":" + std::to_string(e.source().begin.line) + ":" +
                     std::to_string(e.source().begin.column) + ": " + std::string(e.description()));
  }
  return std::move(result).table();
#endif
}

// Parses TOML text, merges the files it includes (config_include.cpp) and
// runs `read` on the result with a Document for its messages: the one
// parsing of every kind of config.
template <class Read>
auto parse_with(const std::string& original_text, const std::string& origin, Read&& read) {
  std::string toml_text;
  toml::table root = parse_toml(original_text, origin, &toml_text);
  const std::vector<config_detail::IncludedFile> included = config_detail::merge_includes(
      root, origin, [](const std::filesystem::path& file, std::string* text) {
        return parse_toml(read_text(file), file.string(), text);
      });
  config_detail::Document doc(toml_text, origin);
  for (const config_detail::IncludedFile& f : included) doc.add_source(f.origin, f.text, f.paths);
  try {
    return read(root, static_cast<const config_detail::Document&>(doc));
  } catch (const InputError&) {
    throw;
  } catch (const config_detail::Skip&) {
    // Every Skip is caught where reading resumes; should one get here, its
    // error is recorded: report it.
    doc.throw_if_errors();
    throw InputError(origin + ": invalid config");
  }
}

}  // namespace

Config parse_config(const std::string& original_text, const std::string& origin) {
  return parse_with(original_text, origin, config_detail::read_config);
}

GrindingConfig parse_grinding_config(const std::string& original_text, const std::string& origin) {
  return parse_with(original_text, origin, config_detail::read_grinding_config);
}

GrindingConfig load_grinding_config(const std::filesystem::path& file) {
  GrindingConfig config = parse_grinding_config(read_text(file), file.string());
  config.source = file;
  return config;
}

Config load_config(const std::filesystem::path& file) {
  Config config = parse_config(read_text(file), file.string());
  config.source = file;
  return config;
}

const JobTool* Job::tool(int number) const {
  for (const JobTool& t : tools)
    if (t.number == number) return &t;
  return nullptr;
}

Job load_job(const std::filesystem::path& file) {
  const config_detail::JobText text = parse_with(read_text(file), file.string(), config_detail::read_job);
  Job job;
  job.source = file;
  job.stock = text.stock;
  job.machine = text.machine;
  job.speed_tolerance = text.speed_tolerance;
  job.cache = text.cache;
  job.default_spindle_rpm = text.default_spindle_rpm;
  const bool bar = job.stock.shape == JobStock::Shape::kBar;
  for (const config_detail::JobText::Tool& t : text.tools) {
    JobTool tool;
    tool.number = t.number;
    const std::filesystem::path p(t.config);
    tool.config_path = p.is_absolute() ? p : file.parent_path() / p;
    const std::string where = file.string() + ": " + t.path + " = \"" + t.config + "\"";
    if (!std::filesystem::exists(tool.config_path))
      throw InputError(where + ": no such file (" + tool.config_path.string() + ")");
    tool.config = load_config(tool.config_path);  // its own messages name its file
    const bool turning = !tool.config.process.rotating_edges();
    if (turning != bar)
      throw InputError(where + ": a " + (turning ? "turning" : "milling") + " tool on a stock of shape = \"" +
                       (bar ? "bar" : "box") + "\" (a bar is turned, a box is milled)");
    if (text.has_workpiece) {
      if (!tool.config.position.stations.empty())
        throw InputError(where + ": its [[positions]] and the job's [workpiece] both give the workpiece: keep one");
      tool.config.model.workpiece = text.workpiece;
      tool.config.position.cantilever = text.cantilever;
    }
    for (const std::string& w : tool.config.warnings) job.warnings.push_back(w);
    job.tools.push_back(std::move(tool));
  }
  return job;
}

}  // namespace chatter
