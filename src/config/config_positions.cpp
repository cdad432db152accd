// [[positions]] of the TOML config (docs/config.md, "Positions";
// docs/position.md), and the position-dependent views of a loaded Config:
// model_at_position, position_range_text, position_m, config_at_position,
// surface_positions (include/chatter/io/config.hpp).
#include "config_sections.hpp"

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace chatter::config_detail {
namespace {

constexpr UnitKey kPositionKeys[] = {{"position_m", 1.0, "m"}, {"position_mm", 1e-3, "mm"}};
const Quantity kPosition{kPositionKeys};

}  // namespace

/// `[[positions]]`: mode sets along the path (docs/config.md "Positions").
/// A body given in one entry is given in every entry and not at the top
/// level; a body given in none is the top-level one at every position.
std::vector<PositionStation> read_positions(const Table& root, const StructuralModel& top) {
  const Document& doc = root.doc();
  const toml::node* n = root.find("positions");
  if (!n) return {};
  const Path path = "positions";
  const toml::array* entries = n->as_array();
  if (!entries || !entries->is_array_of_tables())
    doc.fail(path, *n, "must be an array of tables ([[positions]])");
  if (entries->size() < 2)
    doc.fail(path, *n, "give at least 2 [[positions]] (mode sets at two or more positions along the path)");
  constexpr std::string_view kStationKeys[] = {"position_m", "position_mm", "tool", "workpiece"};
  bool varies[2] = {false, false};
  for (std::size_t i = 0; i < entries->size(); ++i)
    for (int b = 0; b < 2; ++b)
      if (entries->get(i)->as_table()->get(b == 0 ? "tool" : "workpiece")) varies[b] = true;
  if (!varies[0] && !varies[1])
    doc.fail_key(path, "no entry gives tool or workpiece modes: give the modes at each position");
  for (int b = 0; b < 2; ++b) {
    const char* name = b == 0 ? "tool" : "workpiece";
    if (varies[b] && root.has(name))
      doc.error_key(name, std::string("not with [[positions]] giving ") + name +
                              " modes (the body that varies is given at every position, and only there)");
  }
  std::vector<PositionStation> stations;
  std::vector<std::pair<Path, const toml::node*>> gaps;  // where each kept station's position is written
  for (std::size_t i = 0; i < entries->size(); ++i) {
    const Table t(doc, *entries->get(i)->as_table(), element(path, i));
    const std::size_t mark = doc.error_count();
    t.reject_unknown(kStationKeys);
    const Given x = t.required_quantity(kPosition, kNonNegative);
    PositionStation st;
    st.model = top;
    for (int b = 0; b < 2; ++b) {
      const char* name = b == 0 ? "tool" : "workpiece";
      if (!varies[b]) continue;
      if (!t.has(name)) {
        doc.error_key(t.path_of(name), std::string("missing (") + name +
                                           " modes are given at another position: give them at every position)");
        continue;
      }
      if (const auto body = t.table(name); body && body->has("frf"))
        doc.error_key(body->path_of("frf"),
                      "not in [[positions]]: measured FRFs are not interpolated between positions (fit modes to "
                      "them with `chatter fit` and give the modes here)");
      if (auto body = attempt([&] { return read_body(t, name); })) (b == 0 ? st.model.tool : st.model.workpiece) = *body;
    }
    if (doc.error_count() > mark || !x.si) continue;
    st.position_m = *x.si;
    const std::string at = element(path, i);
    if (st.model.rigid()) {
      doc.error_key(at, "both bodies are rigid at this position: give at least one mode");
      continue;
    }
    if (!stations.empty()) {
      const PositionStation& prev = stations.back();
      const Path prev_at = element(path, i - 1);
      if (!(st.position_m > prev.position_m))
        doc.error(t.path_of(x.unit->key), *t.find(x.unit->key),
                  "must be > the position of " + prev_at + " (" + number_text(prev.position_m * 1e3) +
                      " mm): positions sorted along the path, none twice");
      for (int b = 0; b < 2; ++b) {
        const char* name = b == 0 ? "tool" : "workpiece";
        const Body& pb = b == 0 ? prev.model.tool : prev.model.workpiece;
        const Body& cb = b == 0 ? st.model.tool : st.model.workpiece;
        if (pb.modes.size() != cb.modes.size()) {
          doc.error_key(child(at, name) + ".modes",
                        std::to_string(cb.modes.size()) + " modes, " + prev_at + " has " +
                            std::to_string(pb.modes.size()) +
                            ": neighbouring positions must have the same modes (count and directions) to "
                            "interpolate between them");
          continue;
        }
        for (std::size_t m = 0; m < cb.modes.size(); ++m)
          if ((pb.modes[m].direction - cb.modes[m].direction).norm() > 1e-9)
            doc.error_key(element(child(at, name) + ".modes", m) + ".direction",
                          "differs from " + prev_at + ": a mode keeps its direction along the path");
      }
    }
    if (st.position_m > 20.0)
      doc.warn(t.path_of(x.unit->key), *t.find(x.unit->key),
               "beyond the 20 m of a machine's travel; is it in um?");
    stations.push_back(std::move(st));
    gaps.push_back({t.path_of(x.unit->key), t.find(x.unit->key)});
  }
  // One station a unit slip moved: its gap to the previous one over 500
  // times smaller than the widest gap of the path.
  double widest = 0.0;
  for (std::size_t i = 1; i < stations.size(); ++i)
    widest = std::max(widest, stations[i].position_m - stations[i - 1].position_m);
  for (std::size_t i = 1; i < stations.size(); ++i)
    if (const double gap = stations[i].position_m - stations[i - 1].position_m; gap * 500.0 < widest)
      doc.warn(gaps[i].first, *gaps[i].second,
               number_text(gap * 1e3) + " mm from the previous position against " + number_text(widest * 1e3) +
                   " mm between others: a value in m or um among mm?");
  return stations;
}

}  // namespace chatter::config_detail

namespace chatter {

StructuralModel model_at_position(const Config& config, double position_m) {
  using config_detail::number_text;
  const std::string origin = config.source.empty() ? config.name : config.source.string();
  if (config.position.empty())
    throw InputError(origin + ": position " + number_text(position_m * 1e3) +
                     " mm: the structure does not depend on the position (give a cantilever workpiece mode or "
                     "[[positions]]; docs/position.md)");
  const auto& bars = config.position.cantilever;
  for (std::size_t i = 1; i < bars.size(); ++i)
    if (bars[i].length_m != bars[0].length_m)
      throw InputError(origin + ": workpiece.modes[" + std::to_string(bars[i].workpiece_mode) +
                       "].cantilever: length " + number_text(bars[i].length_m) + " m differs from workpiece.modes[" +
                       std::to_string(bars[0].workpiece_mode) + "].cantilever (" + number_text(bars[0].length_m) +
                       " m): position-dependent lobes need one part, one length");
  try {
    return model_at_position(config.model, config.position, position_m);
  } catch (const InputError& e) {
    throw InputError(origin + ": " + e.what());
  }
}

namespace {
std::string origin_of(const Config& config) {
  return config.source.empty() ? config.name : config.source.string();
}
/// 6 significant digits, as the CLI prints numbers in messages.
std::string short_number(double x) {
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}
}  // namespace

std::string position_range_text(const Config& config) {
  const auto [lo, hi] = config.position.range_m();
  std::string where = config.position.stations.empty()
                          ? "clamp to free end of workpiece.modes[" +
                                std::to_string(config.position.cantilever.front().workpiece_mode) + "].cantilever"
                          : "first to last [[positions]]";
  // Appended piecewise: `"literal" + std::string` trips a GCC 12 -Wrestrict false positive.
  std::string out("[");
  out.append(short_number(lo * 1e3)).append(", ").append(short_number(hi * 1e3)).append("] mm (");
  out.append(where).append(")");
  return out;
}

double position_m(const Config& config, double position_mm, const std::string& name) {
  if (config.position.empty())
    throw InputError(name + ": " + origin_of(config) +
                     ": the structure does not depend on the position: give a cantilever workpiece mode or "
                     "[[positions]] (docs/position.md)");
  const auto [lo, hi] = config.position.range_m();
  double x = position_mm / 1e3;
  // mm typed for an end given in m (or the reverse) differs from it by rounding only.
  constexpr double kEndRelTol = 1e-12;
  if (std::abs(x - hi) <= kEndRelTol * hi) x = hi;
  if (std::abs(x - lo) <= kEndRelTol * hi) x = lo;
  if (!(std::isfinite(position_mm) && x >= lo && x <= hi))
    throw InputError(name + " = " + short_number(position_mm) + ": outside the part " + position_range_text(config));
  return x;
}

Config config_at_position(const Config& config, double position_mm, const std::string& name) {
  const double x = position_m(config, position_mm, name);
  Config out = config;
  try {
    out.model = model_at_position(config, x);
  } catch (const InputError& e) {
    throw InputError(name + ": " + e.what());
  }
  return out;
}

SurfacePositions surface_positions(const Config& config, std::optional<double> min_mm, std::optional<double> max_mm,
                                   int points, const SurfacePositionNames& names) {
  if (config.position.empty())
    throw InputError(origin_of(config) +
                     ": surface: the structure does not depend on the position: give a cantilever workpiece mode "
                     "or [[positions]] (docs/position.md)");
  const auto [part_lo_m, part_hi_m] = config.position.range_m();
  const double lo_mm = min_mm.value_or(part_lo_m * 1e3);
  const double hi_mm = max_mm.value_or(part_hi_m * 1e3);
  const double lo_m = min_mm ? position_m(config, *min_mm, names.min) : part_lo_m;
  const double hi_m = max_mm ? position_m(config, *max_mm, names.max) : part_hi_m;
  if (!(hi_m > lo_m))
    throw InputError(names.max + " = " + short_number(hi_mm) + ": must be > " + names.min + " (" +
                     short_number(lo_mm) + ")");
  if (points < 2) throw InputError(names.points + " = " + std::to_string(points) + ": must be >= 2 (both ends)");
  SurfacePositions out;
  out.mm.resize(static_cast<std::size_t>(points));
  out.m.resize(out.mm.size());
  for (int i = 0; i < points; ++i) {
    const auto k = static_cast<std::size_t>(i);
    out.mm[k] = lo_mm + (hi_mm - lo_mm) * static_cast<double>(i) / (points - 1);
    out.m[k] = out.mm[k] / 1e3;
  }
  out.mm.back() = hi_mm;
  out.m.front() = lo_m;
  out.m.back() = hi_m;
  return out;
}

}  // namespace chatter
