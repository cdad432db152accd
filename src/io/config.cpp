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
// No toml++ exception and no std::invalid_argument from the model
// constructors escapes this file.
#include "chatter/io/config.hpp"
#include "chatter/io/frf.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

// toml++ 3.3 asserts (debug builds) that a table-header key starts with a key
// character before checking it, so inputs such as "[`x]" abort instead of
// reporting an error (found by fuzzing; fuzz/corpus/config/crash_*). With the
// assertion compiled out the parser reports the error as it should.
#ifndef TOML_ASSERT
#define TOML_ASSERT(expr) static_cast<void>(0)
#endif
#include <toml++/toml.h>

#include "chatter/error.hpp"

namespace chatter {
namespace {

using Path = std::string;

// ---------------------------------------------------------------- key paths

bool is_bare_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

std::string quote_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default: out += c;
    }
  }
  return out + "\"";
}

std::string key_text(std::string_view key) { return is_bare_key(key) ? std::string(key) : quote_string(key); }

Path child(const Path& parent, std::string_view key) {
  return parent.empty() ? key_text(key) : parent + "." + key_text(key);
}

Path element(const Path& parent, std::size_t index) { return parent + "[" + std::to_string(index) + "]"; }

// ------------------------------------------------------ unknown-key advice

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// "did you mean" for a near miss (a typo, or a key written without its unit
// suffix such as `stiffness` for `stiffness_n_per_m`), else the allowed list.
std::string unknown_key_rule(std::string_view key, std::span<const std::string_view> allowed) {
  std::string_view best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string_view candidate : allowed) {
    const bool unit_missing = candidate.size() > key.size() && candidate.starts_with(key) &&
                              candidate[key.size()] == '_' && !key.empty();
    const std::size_t d = unit_missing ? 1 : edit_distance(key, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  const std::size_t tolerance = std::max<std::size_t>(2, key.size() / 4);
  if (!best.empty() && best_distance <= tolerance) return "unknown key (did you mean " + std::string(best) + "?)";
  std::string list;
  for (const std::string_view candidate : allowed) {
    if (!list.empty()) list += ", ";
    list += candidate;
  }
  return "unknown key (expected one of: " + list + ")";
}

// ------------------------------------------------------------ value ranges

/// An interval a number must lie in, with the words used in messages.
struct Range {
  std::string_view text;  ///< "> 0", "in (0, 1)", ...
  double lo = -std::numeric_limits<double>::infinity();
  bool lo_open = true;
  double hi = std::numeric_limits<double>::infinity();
  bool hi_open = true;

  bool contains(double v) const {
    const bool above = lo_open ? v > lo : v >= lo;
    const bool below = hi_open ? v < hi : v <= hi;
    return above && below;
  }
};

constexpr double kInf = std::numeric_limits<double>::infinity();
const Range kPositive{"> 0", 0.0, true, kInf, true};
const Range kNonNegative{">= 0", 0.0, false, kInf, true};
const Range kOpenUnit{"in (0, 1)", 0.0, true, 1.0, true};
const Range kUnitInterval{"in (0, 1]", 0.0, true, 1.0, false};
// Plausibility bounds, checked after the basic rule: beyond them a value is
// not machining dynamics, and the solvers could not resolve it to their
// stated accuracy (docs/config.md).
struct Plausible {
  double lo, hi;
  const char* rule;
};
constexpr Plausible kFrequencyBound{0.1, 1e6, "must be in [0.1, 1e6] Hz (outside it is not machining dynamics)"};
constexpr Plausible kStiffnessBound{1.0, 1e15, "must be in [1, 1e15] N/m"};
constexpr Plausible kMassBound{1e-6, 1e6, "must be in [1e-6, 1e6] kg"};
constexpr Plausible kDampingBound{1e-6, 1.0, "must be >= 1e-6 (lighter damping is not physical and cannot be resolved)"};
constexpr Plausible kCoefficientBound{0.0, 1e13, "must be <= 1e13 N/m^2 (steel cuts at about 2e9)"};

// ----------------------------------------------------------------- document

/// The TOML text and its origin: turns nodes back into the text the user
/// wrote and builds the messages.
class Document {
 public:
  Document(std::string_view text, std::string origin) : text_(text), origin_(std::move(origin)) {
    line_starts_.push_back(0);
    for (std::size_t i = 0; i < text_.size(); ++i)
      if (text_[i] == '\n') line_starts_.push_back(i + 1);
  }

  const std::string& origin() const { return origin_; }

  /// "<origin>: <path> = <value>: <rule>"
  [[noreturn]] void fail(const Path& path, const toml::node& value, std::string_view rule) const {
    throw InputError(origin_ + ": " + path + " = " + as_written(value) + ": " + std::string(rule));
  }
  /// "<origin>: <path>: <rule>" (missing or unknown keys, whole-model rules).
  [[noreturn]] void fail_key(const Path& path, std::string_view rule) const {
    throw InputError(origin_ + ": " + path + ": " + std::string(rule));
  }

  /// The value as it appears in the text when it sits on one line (so
  /// `45e6` stays `45e6`), else a compact rendering.
  std::string as_written(const toml::node& n) const {
    constexpr std::size_t kMaxLength = 80;
    std::string s = written_text(n).value_or(render(n));
    if (s.size() > kMaxLength) s = s.substr(0, kMaxLength - 3) + "...";
    return s;
  }

 private:
  // Byte offset of a toml++ position (1-based line, 1-based column counted in
  // code points).
  std::optional<std::size_t> offset(const toml::source_position& p) const {
    if (p.line < 1 || p.line > line_starts_.size() || p.column < 1) return std::nullopt;
    std::size_t i = line_starts_[p.line - 1];
    for (toml::source_index col = 1; col < p.column; ++col) {
      if (i >= text_.size() || text_[i] == '\n') return std::nullopt;
      ++i;
      while (i < text_.size() && (static_cast<unsigned char>(text_[i]) & 0xC0u) == 0x80u) ++i;
    }
    return i;
  }

  std::optional<std::string> written_text(const toml::node& n) const {
    if (const toml::table* t = n.as_table(); t && !t->is_inline()) return std::nullopt;  // [header]
    if (const toml::array* a = n.as_array(); a && a->is_array_of_tables()) return std::nullopt;
    const toml::source_region& r = n.source();
    if (r.begin.line != r.end.line) return std::nullopt;
    const auto b = offset(r.begin);
    const auto e = offset(r.end);
    if (!b || !e || *e <= *b || *e > text_.size()) return std::nullopt;
    std::string s(text_.substr(*b, *e - *b));
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.pop_back();
    if (s.empty()) return std::nullopt;
    return s;
  }

  static std::string render(const toml::node& n) {
    if (const toml::array* a = n.as_array()) {
      std::string s = "[";
      for (std::size_t i = 0; i < a->size(); ++i) s += (i ? ", " : "") + render(*a->get(i));
      return s + "]";
    }
    if (const toml::table* t = n.as_table()) {
      std::string s = "{";
      bool first = true;
      for (auto&& [k, v] : *t) {
        s += (first ? " " : ", ") + key_text(k.str()) + " = " + render(v);
        first = false;
      }
      return s + (first ? "}" : " }");
    }
    if (const auto* str = n.as_string()) return quote_string(str->get());
    std::ostringstream os;
    n.visit([&os](auto&& v) {
      if constexpr (toml::is_value<std::remove_cvref_t<decltype(v)>>) os << v;
    });
    return os.str();
  }

  std::string_view text_;
  std::string origin_;
  std::vector<std::size_t> line_starts_;
};

// -------------------------------------------------------------------- table

/// A TOML table at a known key path, with typed, validated getters.
class Table {
 public:
  Table(const Document& doc, const toml::table& table, Path path)
      : doc_(doc), table_(table), path_(std::move(path)) {}

  const Path& path() const { return path_; }
  Path path_of(std::string_view key) const { return child(path_, key); }
  const toml::node* find(std::string_view key) const { return table_.get(key); }
  bool has(std::string_view key) const { return find(key) != nullptr; }

  /// Rejects any key not in `allowed` (checked first, in key order).
  void reject_unknown(std::span<const std::string_view> allowed) const {
    for (auto&& [key, value] : table_) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end())
        doc_.fail_key(path_of(key.str()), unknown_key_rule(key.str(), allowed));
    }
  }

  /// A number (float, or integer converted) in `range`; nullopt if absent.
  std::optional<double> number(std::string_view key, const Range& range) const {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    double v = 0.0;
    if (const auto* i = n->as_integer())
      v = static_cast<double>(i->get());
    else if (const auto* f = n->as_floating_point())
      v = f->get();
    else
      doc_.fail(path_of(key), *n, "must be a number");
    if (!std::isfinite(v)) doc_.fail(path_of(key), *n, "must be a finite number");
    if (!range.contains(v)) doc_.fail(path_of(key), *n, "must be " + std::string(range.text));
    return v;
  }

  /// A required number; `unit` ("Hz", "" for a ratio) goes into the
  /// missing-key message.
  double required_number(std::string_view key, const Range& range, std::string_view unit) const {
    if (const auto v = number(key, range)) return *v;
    doc_.fail_key(path_of(key), "missing (required, " + (unit.empty() ? std::string() : std::string(unit) + ", ") +
                                    std::string(range.text) + ")");
  }

  /// An integer >= `min` that fits an int; nullopt if absent. Floats are
  /// rejected, even 2.0.
  std::optional<int> integer(std::string_view key, int min) const {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    const auto* i = n->as_integer();
    if (!i) doc_.fail(path_of(key), *n, "must be an integer");
    const std::int64_t v = i->get();
    if (v < min) doc_.fail(path_of(key), *n, "must be an integer >= " + std::to_string(min));
    if (v > std::numeric_limits<int>::max())
      doc_.fail(path_of(key), *n, "must be an integer <= " + std::to_string(std::numeric_limits<int>::max()));
    return static_cast<int>(v);
  }

  std::optional<std::string> string(std::string_view key, std::string_view rule = "must be a string") const {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    const auto* s = n->as_string();
    if (!s) doc_.fail(path_of(key), *n, rule);
    return s->get();
  }

  /// A sub-table (a [header] or an inline table); nullopt if absent.
  std::optional<Table> table(std::string_view key) const {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    const toml::table* t = n->as_table();
    if (!t) doc_.fail(path_of(key), *n, "must be a table");
    return Table(doc_, *t, path_of(key));
  }

  const Document& doc() const { return doc_; }

  /// Fails naming `key` when `value` lies outside the plausible bound.
  void plausible(std::string_view key, double value, const Plausible& b) const {
    if (value < b.lo || value > b.hi) doc_.fail(path_of(key), *find(key), b.rule);
  }

 private:
  const Document& doc_;
  const toml::table& table_;
  Path path_;
};

// -------------------------------------------------------------------- modes

constexpr std::string_view kModeKeys[] = {"frequency_hz", "damping_ratio", "stiffness_n_per_m",
                                          "mass_kg",      "direction",     "cantilever"};
constexpr std::string_view kCantileverKeys[] = {"youngs_modulus_pa", "density_kg_per_m3", "length_m",
                                                "diameter_m"};

constexpr std::string_view kDirectionRule = R"(must be "x", "y" or two numbers [x, y])";

Eigen::Vector2d read_direction(const Table& mode) {
  const toml::node* n = mode.find("direction");
  if (!n) return {1.0, 0.0};
  const Document& doc = mode.doc();
  const Path path = mode.path_of("direction");
  if (const auto* s = n->as_string()) {
    if (s->get() == "x") return {1.0, 0.0};
    if (s->get() == "y") return {0.0, 1.0};
    doc.fail(path, *n, kDirectionRule);
  }
  const toml::array* a = n->as_array();
  if (!a || a->size() != 2) doc.fail(path, *n, kDirectionRule);
  Eigen::Vector2d d;
  for (std::size_t i = 0; i < 2; ++i) {
    const toml::node& c = *a->get(i);
    if (const auto* iv = c.as_integer())
      d[static_cast<Eigen::Index>(i)] = static_cast<double>(iv->get());
    else if (const auto* fv = c.as_floating_point())
      d[static_cast<Eigen::Index>(i)] = fv->get();
    else
      doc.fail(element(path, i), c, "must be a number");
    if (!std::isfinite(d[static_cast<Eigen::Index>(i)])) doc.fail(element(path, i), c, "must be a finite number");
  }
  if (d.isZero(0.0)) doc.fail(path, *n, "must not be the zero vector (not both components zero)");
  return d;
}

Mode read_cantilever_mode(const Table& mode, const Table& bar_table) {
  for (const std::string_view key : {"frequency_hz", "stiffness_n_per_m", "mass_kg"}) {
    if (const toml::node* n = mode.find(key))
      mode.doc().fail(mode.path_of(key), *n, "not with cantilever (the bar gives frequency and stiffness)");
  }
  bar_table.reject_unknown(kCantileverKeys);
  CantileverBar bar;
  bar.youngs_modulus_pa = bar_table.required_number("youngs_modulus_pa", kPositive, "Pa");
  bar.density_kg_per_m3 = bar_table.required_number("density_kg_per_m3", kPositive, "kg/m^3");
  bar.length_m = bar_table.required_number("length_m", kPositive, "m");
  bar.diameter_m = bar_table.required_number("diameter_m", kPositive, "m");
  const double zeta = mode.required_number("damping_ratio", kOpenUnit, "");
  mode.plausible("damping_ratio", zeta, kDampingBound);
  return first_bending_mode(bar, zeta, read_direction(mode));
}

Mode read_mode(const Table& mode) {
  mode.reject_unknown(kModeKeys);
  if (const auto bar = mode.table("cantilever")) return read_cantilever_mode(mode, *bar);

  const double f = mode.required_number("frequency_hz", kPositive, "Hz");
  const double zeta = mode.required_number("damping_ratio", kOpenUnit, "");
  const auto k = mode.number("stiffness_n_per_m", kPositive);
  const auto m = mode.number("mass_kg", kPositive);
  mode.plausible("frequency_hz", f, kFrequencyBound);
  mode.plausible("damping_ratio", zeta, kDampingBound);
  if (k) mode.plausible("stiffness_n_per_m", *k, kStiffnessBound);
  if (m) mode.plausible("mass_kg", *m, kMassBound);
  if (k && m)
    mode.doc().fail(mode.path_of("mass_kg"), *mode.find("mass_kg"),
                    "not with stiffness_n_per_m (give exactly one of stiffness_n_per_m, mass_kg)");
  if (!k && !m)
    mode.doc().fail_key(mode.path_of("stiffness_n_per_m"),
                        "missing (give exactly one of stiffness_n_per_m (N/m, > 0) or mass_kg (kg, > 0))");
  const Eigen::Vector2d u = read_direction(mode);
  const Mode md = k ? Mode::from_stiffness(f, zeta, *k, u) : Mode::from_mass(f, zeta, *m, u);
  if (m && md.stiffness_n_per_m < kStiffnessBound.lo) {
    std::ostringstream rule;
    rule << "gives a modal stiffness m(2 pi f)^2 = " << md.stiffness_n_per_m << " N/m: must be >= 1 N/m";
    mode.doc().fail(mode.path_of("mass_kg"), *mode.find("mass_kg"), rule.str());
  }
  return md;
}

// ---------------------------------------------------------- measured FRFs

constexpr std::string_view kFrfKeys[] = {"file", "direction", "format", "quantity", "scale", "record"};

/// One `[[tool.frf]]` / `[[workpiece.frf]]` entry: a measured receptance
/// term read from a file (path relative to the config's folder).
MeasuredTerm read_frf_term(const Table& t) {
  t.reject_unknown(kFrfKeys);
  const Document& doc = t.doc();
  const auto file = t.string("file");
  if (!file) doc.fail_key(t.path_of("file"), "missing (required: the measurement file, relative to the config)");
  MeasuredTerm term;
  const std::string dir = t.string("direction").value_or("xx");
  if (dir == "xx") {
    term.row = term.col = 0;
  } else if (dir == "yy") {
    term.row = term.col = 1;
  } else if (dir == "xy" || dir == "yx") {
    term.row = 0;
    term.col = 1;
  } else {
    doc.fail(t.path_of("direction"), *t.find("direction"), R"(must be "xx", "xy" or "yy")");
  }
  FrfReadOptions opt;
  if (const auto q = t.string("quantity")) {
    opt.quantity = parse_frf_quantity(*q);
    if (!opt.quantity)
      doc.fail(t.path_of("quantity"), *t.find("quantity"), R"(must be "receptance", "mobility" or "accelerance")");
  }
  if (const auto sc = t.number("scale", kPositive)) opt.scale = *sc;
  std::filesystem::path path(*file);
  if (path.is_relative()) path = std::filesystem::path(doc.origin()).parent_path() / path;
  std::string format = t.string("format").value_or("");
  if (format.empty()) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    format = ext == ".csv" ? "csv" : (ext == ".frf" || ext == ".tab" || ext == ".txt") ? "tab"
             : (ext == ".uff" || ext == ".unv" || ext == ".58") ? "uff" : "";
    if (format.empty())
      doc.fail(t.path_of("file"), *t.find("file"),
               R"(cannot tell the format from the extension: add format = "csv", "tab" or "uff")");
  }
  const auto record = t.integer("record", 1);
  FrfTable table;
  if (format == "csv") {
    table = read_frf_csv(path, opt);
  } else if (format == "tab") {
    table = read_frf_tab(path, opt);
  } else if (format == "uff") {
    const auto tables = read_uff58(path, opt);
    const int r = record.value_or(1);
    if (static_cast<std::size_t>(r) > tables.size())
      doc.fail(t.path_of("record"), *t.find("record"),
               "must be <= " + std::to_string(tables.size()) + " (the FRF records in " + path.string() + ")");
    table = tables[static_cast<std::size_t>(r - 1)];
  } else {
    doc.fail(t.path_of("format"), *t.find("format"), R"(must be "csv", "tab" or "uff")");
  }
  if (record && format != "uff") doc.fail(t.path_of("record"), *t.find("record"), "only for format = \"uff\"");
  term.frequency_hz = std::move(table.frequency_hz);
  term.receptance = std::move(table.value);
  term.source = table.source;
  return term;
}

/// `[tool]` / `[workpiece]`: absent, or without `modes`, means rigid.
Body read_body(const Table& root, std::string_view name) {
  Body body;
  const auto table = root.table(name);
  if (!table) return body;
  constexpr std::string_view kBodyKeys[] = {"modes", "frf"};
  table->reject_unknown(kBodyKeys);
  if (const toml::node* f = table->find("frf")) {
    const Path fpath = table->path_of("frf");
    const toml::array* terms = f->as_array();
    if (!terms) root.doc().fail(fpath, *f, "must be an array of tables ([[" + fpath + "]])");
    for (std::size_t i = 0; i < terms->size(); ++i) {
      const toml::node& m = *terms->get(i);
      const toml::table* t = m.as_table();
      if (!t) root.doc().fail(element(fpath, i), m, "must be a table");
      try {
        body.measured.push_back(read_frf_term(Table(root.doc(), *t, element(fpath, i))));
      } catch (const InputError& e) {
        const std::string msg = e.what();
        if (msg.rfind(root.doc().origin() + ": " + element(fpath, i), 0) == 0) throw;
        // A reader error names the measurement file; say which entry read it.
        throw InputError(root.doc().origin() + ": " + element(fpath, i) + ": " + msg);
      }
    }
  }
  const toml::node* n = table->find("modes");
  if (!n) return body;
  const Path path = table->path_of("modes");
  const toml::array* modes = n->as_array();
  if (!modes) root.doc().fail(path, *n, "must be an array of tables ([[" + path + "]])");
  for (std::size_t i = 0; i < modes->size(); ++i) {
    const toml::node& m = *modes->get(i);
    const toml::table* t = m.as_table();
    if (!t) root.doc().fail(element(path, i), m, "must be a table");
    body.modes.push_back(read_mode(Table(root.doc(), *t, element(path, i))));
  }
  return body;
}

// ------------------------------------------------------------------ process

constexpr std::string_view kTurningKeys[] = {"feed_force_coefficient_n_per_m2", "feed_per_rev_mm"};
constexpr std::string_view kMillingKeys[] = {"teeth", "tangential_coefficient_n_per_m2",
                                             "radial_coefficient_n_per_m2", "radial_immersion",
                                             "milling_direction", "feed_per_tooth_mm", "flute_length_mm"};
// The static chip of the time-domain simulation (feed per revolution in
// turning, per tooth in milling), mm.
const Range kFeedMm{"in (0, 10] (mm)", 0.0, true, 10.0, false};
constexpr std::string_view kProcessKeys[] = {"operation",
                                             "feed_force_coefficient_n_per_m2",
                                             "feed_per_rev_mm",
                                             "feed_per_tooth_mm",
                                             "teeth",
                                             "tangential_coefficient_n_per_m2",
                                             "radial_coefficient_n_per_m2",
                                             "radial_immersion",
                                             "milling_direction",
                                             "flute_length_mm"};

void reject_keys_of(const Table& process, std::span<const std::string_view> keys, std::string_view operation) {
  for (const std::string_view key : keys) {
    if (const toml::node* n = process.find(key))
      process.doc().fail(process.path_of(key), *n, "only for operation = \"" + std::string(operation) + "\"");
  }
}

Process read_process(const Table& root, std::optional<double>* feed_mm, std::optional<double>* flute_length_m) {
  const auto process = root.table("process");
  if (!process) root.doc().fail_key("process", "missing (required table: [process] with operation = \"turning\" or \"milling\")");
  process->reject_unknown(kProcessKeys);

  constexpr std::string_view kOperationRule = R"(must be "turning" or "milling")";
  const auto operation = process->string("operation", kOperationRule);
  if (!operation) process->doc().fail_key(process->path_of("operation"), R"(missing (required, "turning" or "milling"))");

  if (*operation == "turning") {
    reject_keys_of(*process, kMillingKeys, "milling");
    TurningParameters p;
    p.feed_force_coefficient_n_per_m2 = process->required_number("feed_force_coefficient_n_per_m2", kPositive, "N/m^2");
    process->plausible("feed_force_coefficient_n_per_m2", p.feed_force_coefficient_n_per_m2, kCoefficientBound);
    *feed_mm = process->number("feed_per_rev_mm", kFeedMm);
    return Process::turning(p);
  }
  if (*operation == "milling") {
    reject_keys_of(*process, kTurningKeys, "turning");
    MillingParameters p;
    const auto teeth = process->integer("teeth", 1);
    if (!teeth) process->doc().fail_key(process->path_of("teeth"), "missing (required, integer >= 1)");
    p.teeth = *teeth;
    p.tangential_coefficient_n_per_m2 = process->required_number("tangential_coefficient_n_per_m2", kPositive, "N/m^2");
    p.radial_coefficient_n_per_m2 = process->required_number("radial_coefficient_n_per_m2", kNonNegative, "N/m^2");
    process->plausible("tangential_coefficient_n_per_m2", p.tangential_coefficient_n_per_m2, kCoefficientBound);
    process->plausible("radial_coefficient_n_per_m2", p.radial_coefficient_n_per_m2, kCoefficientBound);
    p.radial_immersion = process->required_number("radial_immersion", kUnitInterval, "a_e/D");
    constexpr std::string_view kDirectionRuleMilling = R"(must be "down" or "up")";
    const std::string direction = process->string("milling_direction", kDirectionRuleMilling).value_or("down");
    if (direction == "down")
      p.direction = MillingDirection::kDown;
    else if (direction == "up")
      p.direction = MillingDirection::kUp;
    else
      process->doc().fail(process->path_of("milling_direction"), *process->find("milling_direction"),
                          kDirectionRuleMilling);
    *feed_mm = process->number("feed_per_tooth_mm", kFeedMm);
    if (const auto flute = process->number("flute_length_mm", kPositive)) *flute_length_m = *flute * 1e-3;
    return Process::milling(p);
  }
  process->doc().fail(process->path_of("operation"), *process->find("operation"), kOperationRule);
}

// -------------------------------------------------------------------- sweep

SweepDefaults read_sweep(const Table& root) {
  SweepDefaults s;
  const auto sweep = root.table("sweep");
  if (!sweep) return s;
  constexpr std::string_view kSweepKeys[] = {"rpm_min", "rpm_max", "rpm_points", "depth_max_mm"};
  sweep->reject_unknown(kSweepKeys);
  s.rpm_min = sweep->number("rpm_min", kPositive);
  s.rpm_max = sweep->number("rpm_max", kPositive);
  if (s.rpm_min && s.rpm_max && !(*s.rpm_max > *s.rpm_min))
    sweep->doc().fail(sweep->path_of("rpm_max"), *sweep->find("rpm_max"),
                      "must be > rpm_min (" + sweep->doc().as_written(*sweep->find("rpm_min")) + ")");
  s.rpm_points = sweep->integer("rpm_points", 2);
  s.depth_max_mm = sweep->number("depth_max_mm", kPositive);
  return s;
}

// --------------------------------------------------------------------- root

Config read_config(const toml::table& root_table, const Document& doc) {
  const Table root(doc, root_table, "");
  constexpr std::string_view kTopKeys[] = {"name", "process", "tool", "workpiece", "sweep"};
  root.reject_unknown(kTopKeys);

  Config config;
  if (const auto name = root.string("name")) {
    if (name->empty()) doc.fail("name", *root.find("name"), "must not be empty");
    config.name = *name;
  } else {
    const std::string stem = std::filesystem::path(doc.origin()).stem().string();
    config.name = stem.empty() ? doc.origin() : stem;
  }
  config.process = read_process(root, &config.feed_mm, &config.flute_length_m);
  config.model.tool = read_body(root, "tool");
  config.model.workpiece = read_body(root, "workpiece");
  if (config.model.rigid())
    doc.fail_key("tool.modes, workpiece.modes", "both bodies are rigid: give at least one mode (or a measured frf)");
  config.sweep = read_sweep(root);
  return config;
}

}  // namespace

namespace {

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

Config parse_config(const std::string& original_text, const std::string& origin) {
  const std::string toml_text = sanitize_for_parser(original_text, origin);
  // A NUL byte is never valid TOML; toml++ 3.3 asserts on some (found by
  // fuzzing, fuzz/corpus/config/crash_nul_in_key.toml), so refuse it first.
  if (const auto nul = toml_text.find('\0'); nul != std::string::npos) {
    const auto line = 1 + std::count(toml_text.begin(), toml_text.begin() + static_cast<std::ptrdiff_t>(nul), '\n');
    throw InputError(origin + ":" + std::to_string(line) + ": contains a NUL byte: a config must be UTF-8 text");
  }
  const Document doc(toml_text, origin);
  try {
#if TOML_EXCEPTIONS
    const toml::table root = toml::parse(std::string_view(toml_text), std::string_view(origin));
#else
    toml::parse_result result = toml::parse(std::string_view(toml_text), std::string_view(origin));
    if (!result) {
      const toml::parse_error& e = result.error();
      throw InputError(origin + ":" + std::to_string(e.source().begin.line) + ":" +
                       std::to_string(e.source().begin.column) + ": " + std::string(e.description()));
    }
    const toml::table root = std::move(result).table();
#endif
    return read_config(root, doc);
  } catch (const InputError&) {
    throw;
#if TOML_EXCEPTIONS
  } catch (const toml::parse_error& e) {
    throw InputError(origin + ":" + std::to_string(e.source().begin.line) + ":" +
                     std::to_string(e.source().begin.column) + ": " + std::string(e.description()));
#endif
  } catch (const std::invalid_argument& e) {
    // The model constructors re-check what was validated above; reaching
    // here means a rule above is missing, but the user still gets an
    // InputError naming the file.
    throw InputError(origin + ": " + e.what());
  }
}

Config load_config(const std::filesystem::path& file) {
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
  Config config = parse_config(buffer.str(), origin);
  config.source = file;
  return config;
}

}  // namespace chatter
