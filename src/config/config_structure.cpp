// [tool] and [workpiece] of the TOML config (docs/config.md, "Structure"):
// modes given by frequency, damping and stiffness or mass, cantilever modes
// from a bar, and measured FRF terms read from files.
#include "config_sections.hpp"

#include <cctype>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>

#include "chatter/io/frf.hpp"

namespace chatter::config_detail {
namespace {

// ------------------------------------------------------ plausibility bounds

constexpr Plausible kFrequencyBound{0.1, 1e5, "must be in [0.1, 1e5] Hz (outside it is not machining dynamics)"};
constexpr Plausible kStiffnessBound{1.0, 1e15, "must be in [1, 1e15] N/m"};
constexpr Plausible kMassBound{1e-6, 1e6, "must be in [1e-6, 1e6] kg"};
constexpr Plausible kDampingBound{1e-6, 1.0, "must be >= 1e-6 (lighter damping is not physical and cannot be resolved)"};

// ------------------------------------------------------------ the quantities

// Every quantity has its SI key first, then at most a couple of shop-unit
// keys whose suffix names the unit (docs/config.md, "Units").
constexpr UnitKey kStiffnessKeys[] = {{"stiffness_n_per_m", 1.0, "N/m"}, {"stiffness_n_per_um", 1e6, "N/um"}};
constexpr UnitKey kMassKeys[] = {{"mass_kg", 1.0, "kg"}, {"mass_g", 1e-3, "g"}};
constexpr UnitKey kYoungsKeys[] = {{"youngs_modulus_pa", 1.0, "Pa"}, {"youngs_modulus_gpa", 1e9, "GPa"}};
constexpr UnitKey kDensityKeys[] = {{"density_kg_per_m3", 1.0, "kg/m^3"}, {"density_g_per_cm3", 1e3, "g/cm^3"}};
constexpr UnitKey kLengthKeys[] = {{"length_m", 1.0, "m"}, {"length_mm", 1e-3, "mm"}};
constexpr UnitKey kDiameterKeys[] = {{"diameter_m", 1.0, "m"}, {"diameter_mm", 1e-3, "mm"}};

const Quantity kStiffness{kStiffnessKeys};
const Quantity kMass{kMassKeys};
const Quantity kYoungs{kYoungsKeys};
const Quantity kDensity{kDensityKeys};
const Quantity kLength{kLengthKeys};
const Quantity kDiameter{kDiameterKeys};

// ------------------------------------------------------ plausibility warnings

constexpr UnitKey kStiffnessMixups[] = {{"", 1e3, "N/mm"}};
constexpr UnitKey kFrequencyMixups[] = {{"", 1.0 / (2 * kPi), "rad/s"}, {"", 1e3, "kHz"}};
constexpr UnitKey kDampingMixups[] = {{"", 1e-2, "percent"}};

const Band kStiffnessBand{1e5, 5e8, "k", "N/m", "the 1e5 to 5e8 N/m (0.1 to 500 N/um) of machine-tool, tool and workpiece modes",
                          kStiffnessMixups};
const Band kFrequencyBand{10.0, 2e4, "f", "Hz", "the 10 Hz to 20 kHz of machining structures", kFrequencyMixups};
const Band kDampingBand{1e-3, 0.2, "zeta", "", "the 0.001 to 0.2 of machine structures (0.01 to 0.05 is common)",
                        kDampingMixups};
const Band kYoungsBand{1e9, 1.2e12, "E", "Pa", "the 1e9 to 1.2e12 Pa of engineering materials (steel 2.1e11)"};
const Band kDensityBand{500.0, 2.5e4, "rho", "kg/m^3", "the 500 to 25 000 kg/m^3 of solids (steel 7850)"};
const Band kLengthBand{1e-3, 20.0, "L", "m", "1 mm to 20 m"};
const Band kDiameterBand{1e-4, 5.0, "D", "m", "0.1 mm to 5 m"};

// -------------------------------------------------------------------- modes

constexpr std::string_view kModeKeys[] = {"frequency_hz",      "damping_ratio", "stiffness_n_per_m",
                                          "stiffness_n_per_um", "mass_kg",       "mass_g",
                                          "direction",          "cantilever"};
constexpr std::string_view kCantileverKeys[] = {"youngs_modulus_pa", "youngs_modulus_gpa", "density_kg_per_m3",
                                                "density_g_per_cm3", "length_m",           "length_mm",
                                                "diameter_m",        "diameter_mm"};
constexpr UnitKey kFrequencyKeys[] = {{"frequency_hz", 1.0, "Hz"}};
constexpr UnitKey kDampingKeys[] = {{"damping_ratio", 1.0, ""}};
const Quantity kFrequency{kFrequencyKeys};
const Quantity kDamping{kDampingKeys};

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

/// The damping ratio, checked, and its warning.
std::optional<double> read_damping(const Table& mode) {
  // A percentage typed as a ratio (3 for 3 %): say so in the error.
  if (const toml::node* n = mode.find("damping_ratio")) {
    const double v = n->is_integer() ? static_cast<double>(n->as_integer()->get())
                     : n->is_floating_point() ? n->as_floating_point()->get()
                                              : 0.0;
    if (v >= 1.0 && v < 100.0) {
      mode.doc().error(mode.path_of("damping_ratio"), *n,
                       "must be in (0, 1) (a ratio, not a percentage: " + mode.doc().as_written(*n) + " % is " +
                           number_text(v / 100.0) + ")");
      return std::nullopt;
    }
  }
  const auto zeta = mode.required_number("damping_ratio", kOpenUnit, "");
  if (zeta && !mode.plausible("damping_ratio", *zeta, kDampingBound)) return std::nullopt;
  return zeta;
}

/// Warns on a mode's stiffness and frequency derived from a cantilever bar.
void warn_derived_mode(const Table& mode, const Mode& md) {
  const Path path = mode.path_of("cantilever");
  if (!kStiffnessBand.contains(md.stiffness_n_per_m))
    mode.doc().warn_key(path, "gives k = 3EI/L^3 = " + number_text(md.stiffness_n_per_m) + " N/m, which is " +
                                  how_far(md.stiffness_n_per_m, kStiffnessBand) + std::string(kStiffnessBand.usual) +
                                  "; check the units of the bar");
  if (!kFrequencyBand.contains(md.natural_frequency_hz))
    mode.doc().warn_key(path, "gives f = " + number_text(md.natural_frequency_hz) + " Hz, which is " +
                                  how_far(md.natural_frequency_hz, kFrequencyBand) +
                                  std::string(kFrequencyBand.usual) + "; check the units of the bar");
}

Mode read_cantilever_mode(const Table& mode, const Table& bar_table) {
  const Document& doc = mode.doc();
  const std::size_t mark = doc.error_count();
  for (const std::string_view key : {"frequency_hz", "stiffness_n_per_m", "stiffness_n_per_um", "mass_kg", "mass_g"}) {
    if (const toml::node* n = mode.find(key))
      doc.error(mode.path_of(key), *n, "not with cantilever (the bar gives frequency and stiffness)");
  }
  bar_table.reject_unknown(kCantileverKeys);
  const Given e = bar_table.required_quantity(kYoungs, kPositive);
  const Given rho = bar_table.required_quantity(kDensity, kPositive);
  const Given len = bar_table.required_quantity(kLength, kPositive);
  const Given dia = bar_table.required_quantity(kDiameter, kPositive);
  const auto zeta = read_damping(mode);
  const auto dir = attempt([&] { return read_direction(mode); });
  stop_if_errors_since(doc, mark);
  if (!(e.si && rho.si && len.si && dia.si && zeta && dir)) throw Skip{};
  CantileverBar bar;
  bar.youngs_modulus_pa = *e.si;
  bar.density_kg_per_m3 = *rho.si;
  bar.length_m = *len.si;
  bar.diameter_m = *dia.si;
  const Mode md = model_checked(bar_table, [&] { return first_bending_mode(bar, *zeta, *dir); });
  const std::size_t warnings_before = doc.warning_count();
  warn_band(bar_table, e, kYoungs, kYoungsBand);
  warn_band(bar_table, rho, kDensity, kDensityBand);
  warn_band(bar_table, len, kLength, kLengthBand);
  warn_band(bar_table, dia, kDiameter, kDiameterBand);
  if (doc.warning_count() == warnings_before) warn_derived_mode(mode, md);
  warn_band(mode, given(kDampingKeys[0], zeta), kDamping, kDampingBand);
  return md;
}

Mode read_mode(const Table& mode) {
  const Document& doc = mode.doc();
  const std::size_t mark = doc.error_count();
  mode.reject_unknown(kModeKeys);
  if (const auto bar = mode.table("cantilever")) {
    const Mode md = read_cantilever_mode(mode, *bar);
    stop_if_errors_since(doc, mark);
    return md;
  }

  auto f = mode.required_number("frequency_hz", kPositive, "Hz");
  if (f && !mode.plausible("frequency_hz", *f, kFrequencyBound)) f.reset();
  const auto zeta = read_damping(mode);
  Given k = mode.quantity(kStiffness, kPositive);
  Given m = mode.quantity(kMass, kPositive);
  if (k.si && !mode.plausible(k.unit->key, *k.si, kStiffnessBound, k.unit)) k.si.reset();
  if (m.si && !mode.plausible(m.unit->key, *m.si, kMassBound, m.unit)) m.si.reset();
  if (k.present() && m.present())
    doc.error(mode.path_of(m.unit->key), *mode.find(m.unit->key),
              "not with " + std::string(k.unit->key) + " (give exactly one of stiffness_n_per_m, mass_kg)");
  const bool near_miss = mode.meant("stiffness_n_per_m") || mode.meant("stiffness_n_per_um") ||
                         mode.meant("mass_kg") || mode.meant("mass_g");
  if (!k.present() && !m.present() && !near_miss)
    doc.error_key(mode.path_of("stiffness_n_per_m"),
                  "missing (give exactly one of stiffness_n_per_m (N/m, > 0) or mass_kg (kg, > 0); or in shop "
                  "units stiffness_n_per_um (N/um) or mass_g (g))");
  const auto dir = attempt([&] { return read_direction(mode); });
  stop_if_errors_since(doc, mark);
  if (!(f && zeta && dir && (k.si || m.si))) throw Skip{};
  const double f_hz = *f, zeta_value = *zeta;
  const auto u = *dir;
  const Mode md = model_checked(mode, [&] {
    return k.si ? Mode::from_stiffness(f_hz, zeta_value, *k.si, u) : Mode::from_mass(f_hz, zeta_value, *m.si, u);
  });
  if (m.si && md.stiffness_n_per_m < kStiffnessBound.lo) {
    std::ostringstream rule;
    rule << "gives a modal stiffness m(2 pi f)^2 = " << md.stiffness_n_per_m << " N/m: must be >= 1 N/m";
    doc.fail(mode.path_of(m.unit->key), *mode.find(m.unit->key), rule.str());
  }
  warn_band(mode, given(kFrequencyKeys[0], f), kFrequency, kFrequencyBand);
  warn_band(mode, given(kDampingKeys[0], zeta), kDamping, kDampingBand);
  if (k.si) {
    warn_band(mode, k, kStiffness, kStiffnessBand);
  } else {
    const double w2 = std::pow(2 * kPi * f_hz, 2);
    warn_band(mode, m, kMass, kStiffnessBand, [w2](double mass) { return mass * w2; }, "gives k = m (2 pi f)^2 = ");
  }
  return md;
}

// ---------------------------------------------------------- measured FRFs

constexpr std::string_view kFrfKeys[] = {"file", "direction", "format", "quantity", "scale", "record"};

/// One `[[tool.frf]]` / `[[workpiece.frf]]` entry: a measured receptance
/// term read from a file (path relative to the config's folder).
MeasuredTerm read_frf_term(const Table& t) {
  const Document& doc = t.doc();
  const std::size_t mark = doc.error_count();
  t.reject_unknown(kFrfKeys);
  if (!t.has("file")) doc.fail_key(t.path_of("file"), "missing (required: the measurement file, relative to the config)");
  const auto file = t.string("file");
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
    doc.error(t.path_of("direction"), *t.find("direction"), R"(must be "xx", "xy" or "yy")");
  }
  FrfReadOptions opt;
  if (const auto q = t.string("quantity")) {
    opt.quantity = parse_frf_quantity(*q);
    if (!opt.quantity)
      doc.error(t.path_of("quantity"), *t.find("quantity"), R"(must be "receptance", "mobility" or "accelerance")");
  }
  if (const auto sc = t.number("scale", kPositive)) opt.scale = *sc;
  const auto record = t.integer("record", 1);
  const auto format_key = t.string("format");
  stop_if_errors_since(doc, mark);  // read no file for a bad entry
  if (!file) throw Skip{};
  std::filesystem::path path(*file);
  if (path.is_relative()) path = std::filesystem::path(doc.origin_of(t.path())).parent_path() / path;
  std::string format = format_key.value_or("");
  if (format.empty()) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    format = ext == ".csv" ? "csv" : (ext == ".frf" || ext == ".tab" || ext == ".txt") ? "tab"
             : (ext == ".uff" || ext == ".unv" || ext == ".58") ? "uff" : "";
    if (format.empty())
      doc.fail(t.path_of("file"), *t.find("file"),
               R"(cannot tell the format from the extension: add format = "csv", "tab" or "uff")");
  }
  if (format != "csv" && format != "tab" && format != "uff")
    doc.fail(t.path_of("format"), *t.find("format"), R"(must be "csv", "tab" or "uff")");
  if (record && format != "uff") doc.fail(t.path_of("record"), *t.find("record"), "only for format = \"uff\"");
  FrfTable table;
  if (format == "csv") {
    table = read_frf_csv(path, opt);
  } else if (format == "tab") {
    table = read_frf_tab(path, opt);
  } else {
    const auto tables = read_uff58(path, opt);
    const int r = record.value_or(1);
    if (static_cast<std::size_t>(r) > tables.size())
      doc.fail(t.path_of("record"), *t.find("record"),
               "must be <= " + std::to_string(tables.size()) + " (the FRF records in " + path.string() + ")");
    table = tables[static_cast<std::size_t>(r - 1)];
  }
  term.frequency_hz = std::move(table.frequency_hz);
  term.receptance = std::move(table.value);
  term.source = table.source;
  return term;
}

}  // namespace

/// `[tool]` / `[workpiece]`: absent, or without `modes`, means rigid. A bad
/// entry is recorded and left out; the others are still read.
Body read_body(const Table& root, std::string_view name) {
  Body body;
  const auto table = root.table(name);
  if (!table) return body;
  constexpr std::string_view kBodyKeys[] = {"modes", "frf"};
  table->reject_unknown(kBodyKeys);
  const Document& doc = root.doc();
  if (const toml::node* f = table->find("frf")) {
    const Path fpath = table->path_of("frf");
    if (const toml::array* terms = f->as_array()) {
      for (std::size_t i = 0; i < terms->size(); ++i) {
        const toml::node& m = *terms->get(i);
        const toml::table* t = m.as_table();
        if (!t) {
          doc.error(element(fpath, i), m, "must be a table");
          continue;
        }
        try {
          if (auto term = attempt([&] { return read_frf_term(Table(doc, *t, element(fpath, i))); }))
            body.measured.push_back(std::move(*term));
        } catch (const InputError& e) {
          // A reader error names the measurement file; say which entry read it.
          doc.add_error(doc.origin_of(fpath) + ": " + element(fpath, i) + ": " + e.what());
        }
      }
    } else {
      doc.error(fpath, *f, "must be an array of tables ([[" + fpath + "]])");
    }
  }
  const toml::node* n = table->find("modes");
  if (!n) return body;
  const Path path = table->path_of("modes");
  const toml::array* modes = n->as_array();
  if (!modes) doc.fail(path, *n, "must be an array of tables ([[" + path + "]])");
  for (std::size_t i = 0; i < modes->size(); ++i) {
    const toml::node& m = *modes->get(i);
    const toml::table* t = m.as_table();
    if (!t) {
      doc.error(element(path, i), m, "must be a table");
      continue;
    }
    if (auto mode = attempt([&] { return read_mode(Table(doc, *t, element(path, i))); }))
      body.modes.push_back(*mode);
  }
  return body;
}

/// The cantilever workpiece modes of a config read without errors: their
/// index in model.workpiece.modes and their bar length (m).
std::vector<CantileverModeRef> cantilever_refs(const toml::table& root_table) {
  std::vector<CantileverModeRef> refs;
  const toml::array* modes = root_table.at_path("workpiece.modes").as_array();
  if (!modes) return refs;
  for (std::size_t i = 0; i < modes->size(); ++i) {
    const toml::table* t = modes->get(i)->as_table();
    const toml::table* bar = t ? t->get_as<toml::table>("cantilever") : nullptr;
    if (!bar) continue;
    for (const UnitKey& u : kLengthKeys)
      if (const toml::node* n = bar->get(u.key)) {
        const double v = n->is_integer() ? static_cast<double>(n->as_integer()->get()) : n->value_or(0.0);
        refs.push_back({i, v * u.to_si});
      }
  }
  return refs;
}

}  // namespace chatter::config_detail
