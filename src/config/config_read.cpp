// The reading primitives of the TOML config reader (config_read.hpp): key
// paths, the Document (messages, errors, warnings) and Table (typed,
// validated getters), and the plausibility-warning helpers.
#include "chatter/number_text.hpp"
#include "config_read.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <type_traits>
#include <utility>

#include "../formats/text.hpp"

namespace chatter::config_detail {

// ---------------------------------------------------------------- key paths

namespace {

bool is_bare_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

}  // namespace

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

// edit_distance and near_miss: src/formats/text.hpp (shared with the CLI's
// option hints and the operations reader's header hints).
using detail::text::near_miss;

// "did you mean" for a near miss, else the allowed list.
bool path_under(const Path& path, const Path& prefix) {
  return path.compare(0, prefix.size(), prefix) == 0 &&
         (path.size() == prefix.size() || path[prefix.size()] == '.' || path[prefix.size()] == '[');
}

std::string unknown_key_rule(std::string_view key, std::span<const std::string_view> allowed) {
  if (const std::string_view best = near_miss(key, allowed); !best.empty())
    return "unknown key (did you mean " + std::string(best) + "?)";
  std::string list;
  for (const std::string_view candidate : allowed) {
    if (!list.empty()) list += ", ";
    list += candidate;
  }
  return "unknown key (expected one of: " + list + ")";
}

// ----------------------------------------------------------------- document

Document::Source Document::make_source(std::string origin, std::string_view text, std::vector<Path> paths) {
  Source src{std::move(origin), text, {0}, std::move(paths)};
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') src.line_starts.push_back(i + 1);
  return src;
}

Document::Document(std::string_view text, std::string origin) : origin_(std::move(origin)) {
  sources_.push_back(make_source(origin_, text, {}));
}

void Document::add_source(std::string origin, std::string_view text, std::vector<Path> paths) {
  sources_.push_back(make_source(std::move(origin), text, std::move(paths)));
}

const std::string& Document::origin_of(const Path& path) const {
  // The longest matching path: a mode appended to tool.modes by a second
  // file ("tool.modes[2]") is that file's, not the first one's.
  const std::string* best = &origin_;
  std::size_t best_size = 0;
  for (std::size_t s = 1; s < sources_.size(); ++s)
    for (const Path& p : sources_[s].paths)
      if (path_under(path, p) && (best == &origin_ || p.size() > best_size)) {
        best = &sources_[s].origin;
        best_size = p.size();
      }
  return *best;
}

const Document::Source& Document::source_of(const toml::node& n) const {
  if (const auto& file = n.source().path)
    for (const Source& src : sources_)
      if (src.origin == *file) return src;
  return sources_.front();
}

void Document::throw_if_errors() const {
  if (errors_.empty()) return;
  std::string message;
  for (const std::string& e : errors_) message += (message.empty() ? "" : "\n") + e;
  if (error_total_ > errors_.size())
    message += "\n" + origin_ + ": " + std::to_string(error_total_ - errors_.size()) + " more error" +
               (error_total_ - errors_.size() == 1 ? "" : "s") + " not listed (the first " +
               std::to_string(kMaxErrors) + " are)";
  throw InputError(message);
}

std::string Document::as_written(const toml::node& n) const {
  constexpr std::size_t kMaxLength = 80;
  std::string s = written_text(n).value_or(render(n));
  if (s.size() > kMaxLength) s = s.substr(0, kMaxLength - 3) + "...";
  return s;
}

std::optional<std::size_t> Document::offset(const Source& src, const toml::source_position& p) {
  if (p.line < 1 || p.line > src.line_starts.size() || p.column < 1) return std::nullopt;
  std::size_t i = src.line_starts[p.line - 1];
  for (toml::source_index col = 1; col < p.column; ++col) {
    if (i >= src.text.size() || src.text[i] == '\n') return std::nullopt;
    ++i;
    while (i < src.text.size() && (static_cast<unsigned char>(src.text[i]) & 0xC0u) == 0x80u) ++i;
  }
  return i;
}

std::optional<std::string> Document::written_text(const toml::node& n) const {
  if (const toml::table* t = n.as_table(); t && !t->is_inline()) return std::nullopt;  // [header]
  if (const toml::array* a = n.as_array(); a && a->is_array_of_tables()) return std::nullopt;
  const toml::source_region& r = n.source();
  if (r.begin.line != r.end.line) return std::nullopt;
  const Source& src = source_of(n);
  const auto b = offset(src, r.begin);
  const auto e = offset(src, r.end);
  if (!b || !e || *e <= *b || *e > src.text.size()) return std::nullopt;
  std::string s(src.text.substr(*b, *e - *b));
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.pop_back();
  if (s.empty()) return std::nullopt;
  return s;
}

std::string Document::render(const toml::node& n) {
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

void stop_if_errors_since(const Document& doc, std::size_t mark) {
  if (doc.error_count() > mark) throw Skip{};
}

// ------------------------------------------------------------------- units

Given given(const UnitKey& key, std::optional<double> v) {
  Given g;
  if (v) {
    g.unit = &key;
    g.si = *v;
    g.written = *v;
  }
  return g;
}

// -------------------------------------------------------------------- table

void Table::reject_unknown(std::span<const std::string_view> allowed) const {
  for (auto&& [key, value] : table_) {
    if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
    doc_.error_key(path_of(key.str()), unknown_key_rule(key.str(), allowed));
    if (const std::string_view meant = near_miss(key.str(), allowed); !meant.empty()) meant_.push_back(meant);
  }
}

std::optional<double> Table::number(std::string_view key, const Range& range) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  double v = 0.0;
  if (const auto* i = n->as_integer()) {
    v = static_cast<double>(i->get());
  } else if (const auto* f = n->as_floating_point()) {
    v = f->get();
  } else {
    doc_.error(path_of(key), *n, "must be a number");
    return std::nullopt;
  }
  if (!std::isfinite(v)) {
    doc_.error(path_of(key), *n, "must be a finite number");
    return std::nullopt;
  }
  if (!range.contains(v)) {
    doc_.error(path_of(key), *n, "must be " + std::string(range.text));
    return std::nullopt;
  }
  return v;
}

std::optional<std::vector<double>> Table::number_list(std::string_view key, const Range& range) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  auto one = [&](const toml::node& c, const Path& where) -> std::optional<double> {
    double v = 0.0;
    if (const auto* i = c.as_integer()) v = static_cast<double>(i->get());
    else if (const auto* f = c.as_floating_point()) v = f->get();
    else {
      doc_.error(where, c, "must be a number");
      return std::nullopt;
    }
    if (!std::isfinite(v) || !range.contains(v)) {
      doc_.error(where, c, "must be " + std::string(range.text));
      return std::nullopt;
    }
    return v;
  };
  std::vector<double> out;
  if (const toml::array* a = n->as_array()) {
    if (a->empty()) {
      doc_.error(path_of(key), *n, "must not be empty");
      return std::nullopt;
    }
    bool ok = true;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const auto v = one(*a->get(i), element(path_of(key), i));
      if (v) out.push_back(*v);
      else ok = false;
    }
    if (!ok) return std::nullopt;
    return out;
  }
  const auto v = one(*n, path_of(key));
  if (!v) return std::nullopt;
  return std::vector<double>{*v};
}

std::optional<double> Table::required_number(std::string_view key, const Range& range, std::string_view unit) const {
  if (!has(key)) {
    if (!meant(key))
      doc_.error_key(path_of(key), "missing (required, " + (unit.empty() ? std::string() : std::string(unit) + ", ") +
                                       std::string(range.text) + ")");
    return std::nullopt;
  }
  return number(key, range);
}

Given Table::quantity(const Quantity& q, const Range& range) const {
  Given g;
  for (const UnitKey& u : q.keys) {
    if (!has(u.key)) continue;
    if (g.unit) {
      doc_.error(path_of(u.key), *find(u.key),
                 "not with " + std::string(g.unit->key) + " (one quantity, one key: give " +
                     std::string(g.unit->key) + " or " + std::string(u.key) + ")");
      g.si.reset();
      return g;
    }
    g.unit = &u;
    if (const auto v = number(u.key, range)) {
      g.written = *v;
      g.si = *v * u.to_si;
    }
  }
  return g;
}

Given Table::required_quantity(const Quantity& q, const Range& range) const {
  Given g = quantity(q, range);
  const bool near_miss_reported =
      std::any_of(q.keys.begin(), q.keys.end(), [this](const UnitKey& u) { return meant(u.key); });
  if (!g.present() && !near_miss_reported) {
    std::string rule = "missing (required, " + std::string(q.si().unit) + ", " + std::string(range.text) + ")";
    for (std::size_t i = 1; i < q.keys.size(); ++i)
      rule += (i == 1 ? "; or give " : " or ") + std::string(q.keys[i].key) + " (" + std::string(q.keys[i].unit) + ")";
    doc_.error_key(path_of(q.si().key), rule);
  }
  return g;
}

std::optional<int> Table::integer(std::string_view key, int min, int max) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const auto* i = n->as_integer();
  if (!i) {
    doc_.error(path_of(key), *n, "must be an integer");
    return std::nullopt;
  }
  const std::int64_t v = i->get();
  if (v < min) {
    doc_.error(path_of(key), *n, "must be an integer >= " + std::to_string(min));
    return std::nullopt;
  }
  if (v > max) {
    doc_.error(path_of(key), *n, "must be an integer <= " + std::to_string(max));
    return std::nullopt;
  }
  return static_cast<int>(v);
}

std::optional<std::string> Table::string(std::string_view key, std::string_view rule) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const auto* s = n->as_string();
  if (!s) {
    doc_.error(path_of(key), *n, rule);
    return std::nullopt;
  }
  return s->get();
}

std::optional<Table> Table::table(std::string_view key) const {
  const toml::node* n = find(key);
  if (!n) return std::nullopt;
  const toml::table* t = n->as_table();
  if (!t) doc_.fail(path_of(key), *n, "must be a table");
  return Table(doc_, *t, path_of(key));
}

bool Table::plausible(std::string_view key, double si_value, const Plausible& b, const UnitKey* unit) const {
  if (si_value >= b.lo && si_value <= b.hi) return true;
  std::string rule = b.rule;
  if (unit && unit->to_si != 1.0) {
    std::ostringstream os;
    os << rule << " (this is " << si_value << " in SI)";
    rule = os.str();
  }
  doc_.error(path_of(key), *find(key), rule);
  return false;
}

// ------------------------------------------------------ plausibility warnings

std::string number_text(double x) {
  return chatter::number_text(x, 4);
}

std::string how_far(double v, const Band& b) {
  const bool below = v < b.lo;
  const double ratio = below ? b.lo / v : v / b.hi;
  const std::string side = below ? "below " : "above ";
  if (!(ratio >= 10.0) || !std::isfinite(ratio)) return side;
  return "over 1e" + std::to_string(static_cast<int>(std::floor(std::log10(ratio)))) + " times " + side;
}

void warn_band(const Table& t, const Given& g, const Quantity& q, const Band& b) {
  warn_band(t, g, q, b, [](double v) { return v; });
}

void warn_usual(const Table& t, std::string_view key, std::optional<double> v, const Usual& u) {
  if (!v) return;
  if (const std::string what = unusual(key, *v, u); !what.empty()) t.doc().warn(t.path_of(key), *t.find(key), what);
}

}  // namespace chatter::config_detail
