// Internal (not installed): the reading primitives of the TOML config reader,
// shared by its section readers (src/config/config_*.cpp; the top level,
// read_config, is src/config/config.cpp). Key reference: docs/config.md.
//
// How a section reader works
// --------------------------
// A reader gets the parent Table (the root for a top-level table) and reads
// its keys through Table's getters. A bad value is recorded on the Document
// (the message "<origin>: <key.path> = <value as written>: <rule>") and read
// as absent (nullopt), so reading goes on and one run reports every error of
// a file. When a value or table cannot be read any further, Document::fail
// records the error and throws Skip; attempt() / attempt_void() catch it
// where reading resumes (read_config runs each section in attempt_void).
// Document::throw_if_errors turns the recorded errors into one InputError at
// the end. Values that load but are unusual (a stiffness of 20 N/m) are
// warnings (warn_band, Document::warn), never errors. So, per key: the basic
// rule (Range) is an error, the hard bound (Plausible) is an error, the usual
// band (Band) is a warning naming the unit that was probably meant.
//
// Example: a `[grinding]` table with one required key.
//   constexpr UnitKey kWheelKeys[] = {{"wheel_speed_m_per_s", 1.0, "m/s"}};
//   constexpr Plausible kWheelBound{0.1, 500.0, "must be in [0.1, 500] m/s"};
//   const Band kWheelBand{10.0, 150.0, "v_s", "m/s", "the 10 to 150 m/s of grinding wheels"};
//   std::optional<Grinding> read_grinding(const Table& root) {
//     const auto t = root.table("grinding");       // absent: nullopt; not a table: error, Skip
//     if (!t) return std::nullopt;
//     const std::size_t mark = t->doc().error_count();
//     constexpr std::string_view kKeys[] = {"wheel_speed_m_per_s"};
//     t->reject_unknown(kKeys);                     // "unknown key (did you mean ...?)"
//     auto v = t->required_number("wheel_speed_m_per_s", kPositive, "m/s");  // missing / bad: error
//     if (v && !t->plausible("wheel_speed_m_per_s", *v, kWheelBound)) v.reset();  // hard bound: error
//     stop_if_errors_since(t->doc(), mark);         // this table had errors: Skip
//     if (!v) throw Skip{};                         // (defensive: each nullopt above was recorded)
//     warn_band(*t, given(kWheelKeys[0], v), Quantity{kWheelKeys}, kWheelBand);  // unusual: warning
//     return model_checked(*t, [&] { return Grinding(*v); });  // constructor's InputError named
//   }
// Then: declare it in config_sections.hpp, add the key to read_config's
// allowed top-level keys and call it there (src/config/config.cpp), list the
// file in CMakeLists.txt (CHATTER_IO_SOURCES) and scripts/fuzz.sh (config),
// and document the keys in docs/config.md.
//
// Nothing here throws a toml++ exception; Skip never leaves the reader
// (parse_config catches it).
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
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
#include "chatter/usual_bands.hpp"

namespace chatter::config_detail {

/// A key path as messages show it: `tool.modes[0].frequency_hz` (0-based
/// indices, keys quoted when not bare).
using Path = std::string;

// ---------------------------------------------------------------- key paths

/// `key` as TOML writes it: bare when it may be, else a quoted string.
std::string key_text(std::string_view key);
/// `s` as a TOML basic string, quotes and escapes included.
std::string quote_string(std::string_view s);
/// `parent.key` (`key` alone at the root).
Path child(const Path& parent, std::string_view key);
/// `parent[index]`.
Path element(const Path& parent, std::size_t index);
/// True when `path` is `prefix` or lies under it (`tool.modes[0].mass_kg`
/// under `tool.modes`, not under `tool.mode`).
bool path_under(const Path& path, const Path& prefix);

/// The rule for an unknown key: "unknown key (did you mean <key>?)" for a
/// near miss, else "unknown key (expected one of: <allowed>)".
std::string unknown_key_rule(std::string_view key, std::span<const std::string_view> allowed);

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

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr Range kPositive{"> 0", 0.0, true, kInf, true};
inline constexpr Range kNonNegative{">= 0", 0.0, false, kInf, true};
inline constexpr Range kOpenUnit{"in (0, 1)", 0.0, true, 1.0, true};
inline constexpr Range kUnitInterval{"in (0, 1]", 0.0, true, 1.0, false};
inline constexpr Range kAnyNumber{"a finite number", -kInf, true, kInf, true};

/// Plausibility bounds, checked after the basic rule: beyond them a value is
/// not machining dynamics, and the solvers could not resolve it to their
/// stated accuracy (docs/config.md). Breaking one is an error (Table::plausible).
struct Plausible {
  double lo, hi;
  const char* rule;
};

// ----------------------------------------------------------------- document

/// At most this many errors are listed; the rest are counted.
inline constexpr std::size_t kMaxErrors = 20;

/// Thrown after an error is recorded: abandons the value or table being read
/// (reading resumes at the next one; see attempt()). Never leaves the config
/// reader (parse_config).
struct Skip {};

/// The TOML text and its origin: turns nodes back into the text the user
/// wrote and builds the messages.
class Document {
 public:
  Document(std::string_view text, std::string origin);

  /// The file read (the one that includes the others).
  const std::string& origin() const { return origin_; }
  /// A file merged in by `include` (config_include.cpp): its text (kept
  /// alive by the caller) for as_written, and the key paths it gave
  /// (`tool.modes`, `process.tangential_coefficient_n_per_mm2`), so that a
  /// message about a key names the file the key is in.
  void add_source(std::string origin, std::string_view text, std::vector<Path> paths);
  /// The file that gave `path` (or the key path it lies under): an included
  /// file's name, else origin().
  const std::string& origin_of(const Path& path) const;

  /// Records "<origin>: <path> = <value>: <rule>" and goes on reading.
  void error(const Path& path, const toml::node& value, std::string_view rule) const {
    add_error(origin_of(path) + ": " + path + " = " + as_written(value) + ": " + std::string(rule));
  }
  /// Records "<origin>: <path>: <rule>" (missing or unknown keys, whole-model rules).
  void error_key(const Path& path, std::string_view rule) const {
    add_error(origin_of(path) + ": " + path + ": " + std::string(rule));
  }
  /// Records a whole message (e.g. from an FRF reader).
  void add_error(std::string message) const {
    ++error_total_;
    if (errors_.size() < kMaxErrors) errors_.push_back(std::move(message));
  }
  /// Records the error and abandons the value or table being read (Skip).
  [[noreturn]] void fail(const Path& path, const toml::node& value, std::string_view rule) const {
    error(path, value, rule);
    throw Skip{};
  }
  [[noreturn]] void fail_key(const Path& path, std::string_view rule) const {
    error_key(path, rule);
    throw Skip{};
  }
  std::size_t error_count() const { return error_total_; }

  /// Throws one InputError listing the recorded errors, one per line (the
  /// first kMaxErrors, then how many more); nothing if there are none.
  void throw_if_errors() const;

  /// Records "<origin>: <path> = <value>: <what>" as a plausibility warning.
  void warn(const Path& path, const toml::node& value, std::string_view what) const {
    warnings_.push_back(origin_of(path) + ": " + path + " = " + as_written(value) + ": " + std::string(what));
  }
  /// Records "<origin>: <path>: <what>" (a value derived from several keys).
  void warn_key(const Path& path, std::string_view what) const {
    warnings_.push_back(origin_of(path) + ": " + path + ": " + std::string(what));
  }
  std::size_t warning_count() const { return warnings_.size(); }
  std::vector<std::string> take_warnings() const { return std::move(warnings_); }

  /// The value as it appears in the text when it sits on one line (so
  /// `45e6` stays `45e6`), else a compact rendering.
  std::string as_written(const toml::node& n) const;

 private:
  // One file's text and where its lines start.
  struct Source {
    std::string origin;
    std::string_view text;
    std::vector<std::size_t> line_starts;
    std::vector<Path> paths;  // the key paths it gave (empty for the file read)
  };
  static Source make_source(std::string origin, std::string_view text, std::vector<Path> paths);
  // The file a node was parsed from (toml++ keeps its origin), else the first.
  const Source& source_of(const toml::node& n) const;
  // Byte offset of a toml++ position (1-based line, 1-based column counted in
  // code points) in `src`'s text.
  static std::optional<std::size_t> offset(const Source& src, const toml::source_position& p);
  std::optional<std::string> written_text(const toml::node& n) const;
  static std::string render(const toml::node& n);

  std::string origin_;
  std::vector<Source> sources_;  // [0]: the file read; then the included ones
  // Reading goes on after an error so that one run reports them all.
  mutable std::vector<std::string> errors_;
  mutable std::size_t error_total_ = 0;
  mutable std::vector<std::string> warnings_;
};

/// Runs `read`; a Skip (the error is recorded) gives nullopt, so reading goes
/// on with the next key or table.
template <class F>
auto attempt(F&& read) -> std::optional<decltype(read())> {
  try {
    return read();
  } catch (const Skip&) {
    return std::nullopt;
  }
}
template <class F>
void attempt_void(F&& read) {
  try {
    read();
  } catch (const Skip&) {
  }
}

/// Throws Skip when errors were recorded since `mark` (a doc.error_count()).
void stop_if_errors_since(const Document& doc, std::size_t mark);

// ------------------------------------------------------------------- units

/// One key of a quantity: its name (the suffix names the unit) and the
/// factor to SI.
struct UnitKey {
  std::string_view key;
  double to_si;
  std::string_view unit;  ///< for messages: "N/m^2", "N/um", ...
};

/// A physical quantity that a config may give in one of several units: the
/// SI key first, then the shop-unit alternatives (at most a couple, whose
/// suffix names the unit: docs/config.md, "Units"). Giving two is an error.
struct Quantity {
  std::span<const UnitKey> keys;
  const UnitKey& si() const { return keys.front(); }
};

/// What a table holds for a Quantity.
struct Given {
  const UnitKey* unit = nullptr;  ///< the key present; nullptr: none
  std::optional<double> si;       ///< the value in SI; nullopt if absent or bad (the error is recorded)
  double written = 0.0;           ///< the value in the unit of its key
  bool present() const { return unit != nullptr; }
};

/// A single-key number as a Given (frequency_hz, damping_ratio).
Given given(const UnitKey& key, std::optional<double> v);

// -------------------------------------------------------------------- table

/// A TOML table at a known key path, with typed, validated getters. A bad
/// value is recorded as an error (Document::error) and read as absent
/// (nullopt), so reading goes on and every error of a file is reported.
class Table {
 public:
  Table(const Document& doc, const toml::table& table, Path path)
      : doc_(doc), table_(table), path_(std::move(path)) {}

  const Path& path() const { return path_; }
  Path path_of(std::string_view key) const { return child(path_, key); }
  const toml::node* find(std::string_view key) const { return table_.get(key); }
  bool has(std::string_view key) const { return find(key) != nullptr; }

  /// Records every key not in `allowed`, in key order. A key a near miss
  /// was meant to be is not reported missing as well.
  void reject_unknown(std::span<const std::string_view> allowed) const;
  /// True if an unknown key of this table was a near miss of `key`.
  bool meant(std::string_view key) const { return std::find(meant_.begin(), meant_.end(), key) != meant_.end(); }

  /// A number (float, or integer converted) in `range`; nullopt if absent or
  /// bad (recorded).
  std::optional<double> number(std::string_view key, const Range& range) const;

  /// Item `index` of a number_list key: the array's element and its path, or
  /// the key's own node and path when it holds one number (a list of one).
  /// @pre find(key) is present and number_list(key, ...) read `index`.
  std::pair<Path, const toml::node*> list_item(std::string_view key, std::size_t index) const {
    const toml::node* n = find(key);
    if (const toml::array* a = n->as_array()) return {element(path_of(key), index), a->get(index)};
    return {path_of(key), n};
  }

  /// One number or an array of numbers, each in `range`; nullopt if absent
  /// or bad (every bad element recorded with its index).
  std::optional<std::vector<double>> number_list(std::string_view key, const Range& range) const;

  /// A required number; `unit` ("Hz", "" for a ratio) goes into the
  /// missing-key message. nullopt (recorded) if absent or bad.
  std::optional<double> required_number(std::string_view key, const Range& range, std::string_view unit) const;

  /// The quantity `q` in whichever of its keys is present, converted to SI.
  /// Two keys of one quantity are an error naming both.
  Given quantity(const Quantity& q, const Range& range) const;

  /// A required quantity: absent is an error naming its keys and units.
  Given required_quantity(const Quantity& q, const Range& range) const;

  /// An integer >= `min` that fits an int; nullopt if absent or bad
  /// (recorded). Floats are rejected, even 2.0.
  std::optional<int> integer(std::string_view key, int min, int max = std::numeric_limits<int>::max()) const;

  /// A string; nullopt if absent or not a string (recorded with `rule`).
  std::optional<std::string> string(std::string_view key, std::string_view rule = "must be a string") const;

  /// A sub-table (a [header] or an inline table); nullopt if absent; not a
  /// table: recorded, and Skip.
  std::optional<Table> table(std::string_view key) const;

  const Document& doc() const { return doc_; }

  /// Records an error naming `key` when `si_value` lies outside the hard
  /// bound; false then. `unit` is the key's unit, to show the SI value when
  /// the key is in another unit.
  bool plausible(std::string_view key, double si_value, const Plausible& b, const UnitKey* unit = nullptr) const;

 private:
  const Document& doc_;
  const toml::table& table_;
  Path path_;
  mutable std::vector<std::string_view> meant_;  // keys that unknown near misses were meant to be
};

/// Builds a model object (Mode, Process) from values validated above. The
/// model constructors re-check them and throw InputError without a file name;
/// should one fire, a rule above is missing: the user still gets the file and
/// the table.
template <class Make>
auto model_checked(const Table& where, Make&& make) {
  try {
    return make();
  } catch (const InputError& e) {
    throw InputError(where.doc().origin() + ": " + where.path() + ": " + e.what());
  }
}

// ------------------------------------------------------ plausibility warnings

/// The values usual in machining (docs/config.md, "Plausibility warnings").
/// Outside the band a value is accepted but warned about; the warning names
/// a unit in which the number as written would be inside the band.
struct Band {
  double lo, hi;               ///< SI
  std::string_view symbol;     ///< "K_t"
  std::string_view unit;       ///< SI unit for the message
  std::string_view usual;      ///< "the 1e8 to 1e10 N/m^2 of metal cutting (...)"
  std::span<const UnitKey> other_units = {};  ///< likely mix-ups that are not keys (rad/s, N/mm, ...)
  bool contains(double v) const { return v >= lo && v <= hi; }
};

/// `x` with 4 significant digits, as messages show numbers.
std::string number_text(double x);

/// "over 1e5 times below" / "below".
std::string how_far(double v, const Band& b);

/// Warns when the quantity given in `g` (or what `derive` makes of its SI
/// value) lies outside `b`; `derived` describes the derived value ("gives
/// k = m (2 pi f)^2 = "), empty when the band is on the value itself.
// (noinline: inlined, GCC 12 reports a false -Wmaybe-uninitialized on Given::si.)
template <class Derive>
[[gnu::noinline]] void warn_band(const Table& t, const Given& g, const Quantity& q, const Band& b, Derive derive,
               std::string_view derived = "") {
  if (!g.present() || !g.si.has_value()) return;
  const double v = derive(g.si.value());
  if (b.contains(v)) return;
  std::string what;
  if (derived.empty())
    what = std::string(b.symbol) + " = " + number_text(v) + (b.unit.empty() ? "" : " ") + std::string(b.unit);
  else
    what = std::string(derived) + number_text(v) + " " + std::string(b.unit) + ", which";
  what += " is " + how_far(v, b) + std::string(b.usual);
  // A unit in which the number as written would be usual.
  const std::string written = t.doc().as_written(*t.find(g.unit->key));
  std::string hint;
  for (const UnitKey& u : q.keys) {
    if (&u == g.unit || !b.contains(derive(g.written * u.to_si))) continue;
    hint = "did you mean " + std::string(u.unit) + " (" + std::string(u.key) + " = " + written + ")?";
    break;
  }
  for (const UnitKey& u : b.other_units) {
    if (!hint.empty() || !b.contains(derive(g.written * g.unit->to_si * u.to_si))) continue;
    hint = "is it in " + std::string(u.unit) + " (" + std::string(q.si().key) + " = " +
           number_text(g.written * g.unit->to_si * u.to_si) + ")?";
  }
  if (!hint.empty()) what += "; " + hint;
  t.doc().warn(t.path_of(g.unit->key), *t.find(g.unit->key), what);
}

/// warn_band on the value itself.
void warn_band(const Table& t, const Given& g, const Quantity& q, const Band& b);

/// A usual band in a key's own unit: chatter/usual_bands.hpp (shared with
/// the command line's flags).
using chatter::Usual;
/// Warns "<key> = v: outside <what>; is it in <unit> (<key> = meant)?" when
/// v (the key's value as written) lies outside u. Nothing when v is empty.
void warn_usual(const Table& t, std::string_view key, std::optional<double> v, const Usual& u);

}  // namespace chatter::config_detail
