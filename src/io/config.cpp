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
// No toml++ exception escapes this file; an InputError of the model
// constructors is given the file and table (model_checked). The reading
// primitives (Document, Table, Range, Quantity, Band, ...) are in
// config_read.hpp.
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

#include "config_read.hpp"  // the reading primitives: Document, Table, Range, Quantity, Band, ...

namespace chatter::config_detail {
namespace {

// ------------------------------------------------------ plausibility bounds

constexpr Plausible kFrequencyBound{0.1, 1e6, "must be in [0.1, 1e6] Hz (outside it is not machining dynamics)"};
constexpr Plausible kStiffnessBound{1.0, 1e15, "must be in [1, 1e15] N/m"};
constexpr Plausible kMassBound{1e-6, 1e6, "must be in [1e-6, 1e6] kg"};
constexpr Plausible kDampingBound{1e-6, 1.0, "must be >= 1e-6 (lighter damping is not physical and cannot be resolved)"};
constexpr Plausible kCoefficientBound{0.0, 1e13, "must be <= 1e13 N/m^2 (steel cuts at about 2e9)"};

// ------------------------------------------------------------ the quantities

// Every quantity has its SI key first, then at most a couple of shop-unit
// keys whose suffix names the unit (docs/config.md, "Units").
constexpr UnitKey kFeedForceKeys[] = {{"feed_force_coefficient_n_per_m2", 1.0, "N/m^2"},
                                      {"feed_force_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
constexpr UnitKey kTangentialKeys[] = {{"tangential_coefficient_n_per_m2", 1.0, "N/m^2"},
                                       {"tangential_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
constexpr UnitKey kRadialKeys[] = {{"radial_coefficient_n_per_m2", 1.0, "N/m^2"},
                                   {"radial_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
constexpr UnitKey kStiffnessKeys[] = {{"stiffness_n_per_m", 1.0, "N/m"}, {"stiffness_n_per_um", 1e6, "N/um"}};
constexpr UnitKey kMassKeys[] = {{"mass_kg", 1.0, "kg"}, {"mass_g", 1e-3, "g"}};
constexpr UnitKey kYoungsKeys[] = {{"youngs_modulus_pa", 1.0, "Pa"}, {"youngs_modulus_gpa", 1e9, "GPa"}};
constexpr UnitKey kDensityKeys[] = {{"density_kg_per_m3", 1.0, "kg/m^3"}, {"density_g_per_cm3", 1e3, "g/cm^3"}};
constexpr UnitKey kLengthKeys[] = {{"length_m", 1.0, "m"}, {"length_mm", 1e-3, "mm"}};
constexpr UnitKey kDiameterKeys[] = {{"diameter_m", 1.0, "m"}, {"diameter_mm", 1e-3, "mm"}};

const Quantity kFeedForce{kFeedForceKeys};
const Quantity kTangential{kTangentialKeys};
const Quantity kRadial{kRadialKeys};
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

const Band kCoefficientBand{1e8, 1e10, "K", "N/m^2",
                            "the 1e8 to 1e10 N/m^2 of metal cutting (aluminium about 5e8, steel about 2e9, hardened "
                            "steel and titanium about 3e9)"};
const Band kRadialBand{5e6, 1.5e10, "K_r", "N/m^2", "the 5e6 to 1.5e10 N/m^2 of metal cutting"};
const Band kStiffnessBand{1e5, 1e10, "k", "N/m", "the 1e5 to 1e10 N/m of machine-tool, tool and workpiece modes",
                          kStiffnessMixups};
const Band kFrequencyBand{10.0, 2e4, "f", "Hz", "the 10 Hz to 20 kHz of machining structures", kFrequencyMixups};
const Band kDampingBand{1e-3, 0.2, "zeta", "", "the 0.001 to 0.2 of machine structures (0.01 to 0.05 is common)",
                        kDampingMixups};
const Band kYoungsBand{1e9, 1.2e12, "E", "Pa", "the 1e9 to 1.2e12 Pa of engineering materials (steel 2.1e11)"};
const Band kDensityBand{500.0, 2.5e4, "rho", "kg/m^3", "the 500 to 25 000 kg/m^3 of solids (steel 7850)"};
const Band kLengthBand{1e-3, 20.0, "L", "m", "1 mm to 20 m"};
const Band kDiameterBand{1e-4, 5.0, "D", "m", "0.1 mm to 5 m"};
// K_r/K_t: usually 0.1 to 1; warned outside this slightly wider band.
constexpr double kRatioLo = 0.05, kRatioHi = 1.5;
// A natural frequency above this many tooth-passing frequencies at the
// fastest speed (lobe numbers above 200 everywhere: lobes narrower than a
// 400-point sweep resolves), or below the slowest tooth-passing frequency
// divided by kToothPassingOverModeMax, is out of reach of the sweep.
constexpr double kLobeNumberMax = 200.0;
constexpr double kToothPassingOverModeMax = 20.0;

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
  if (path.is_relative()) path = std::filesystem::path(doc.origin()).parent_path() / path;
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
          doc.add_error(doc.origin() + ": " + element(fpath, i) + ": " + e.what());
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

// ------------------------------------------------------------------ process

constexpr std::string_view kTurningKeys[] = {"feed_force_coefficient_n_per_m2", "feed_force_coefficient_n_per_mm2",
                                             "feed_per_rev_mm", "workpiece_diameter_mm"};
constexpr std::string_view kMillingKeys[] = {"teeth",
                                             "tangential_coefficient_n_per_m2",
                                             "tangential_coefficient_n_per_mm2",
                                             "radial_coefficient_n_per_m2",
                                             "radial_coefficient_n_per_mm2",
                                             "radial_immersion",
                                             "milling_direction",
                                             "feed_per_tooth_mm",
                                             "flute_length_mm",
                                             "tool_diameter_mm",
                                             "radial_depth_mm",
                                             "helix_angle_deg",
                                             "pitch_angles_deg",
                                             "runout_um",
                                             "radial_coefficient_ratio"};
// The static chip of the time-domain simulation (feed per revolution in
// turning, per tooth in milling), mm.
const Range kFeedMm{"in (0, 10] (mm)", 0.0, true, 10.0, false};
constexpr std::string_view kProcessKeys[] = {"operation",
                                             "feed_force_coefficient_n_per_m2",
                                             "feed_force_coefficient_n_per_mm2",
                                             "feed_per_rev_mm",
                                             "feed_per_tooth_mm",
                                             "teeth",
                                             "tangential_coefficient_n_per_m2",
                                             "tangential_coefficient_n_per_mm2",
                                             "radial_coefficient_n_per_m2",
                                             "radial_coefficient_n_per_mm2",
                                             "radial_immersion",
                                             "milling_direction",
                                             "flute_length_mm",
                                             "tool_diameter_mm",
                                             "radial_depth_mm",
                                             "helix_angle_deg",
                                             "pitch_angles_deg",
                                             "runout_um",
                                             "radial_coefficient_ratio",
                                             "process_damping_coefficient_n_per_m",
                                             "workpiece_diameter_mm"};
// Pitch angles as written must sum to 360° to this (deg); they are then
// scaled to sum to exactly one revolution.
constexpr double kPitchSumToleranceDeg = 1e-3;
const Range kHelixDeg{"in [0, 90) (deg)", 0.0, false, 90.0, true};

void reject_keys_of(const Table& process, std::span<const std::string_view> keys, std::string_view operation) {
  for (const std::string_view key : keys) {
    if (const toml::node* n = process.find(key))
      process.doc().error(process.path_of(key), *n, "only for operation = \"" + std::string(operation) + "\"");
  }
}

/// A cutting coefficient, with the hard bound.
Given read_coefficient(const Table& process, const Quantity& q, const Range& range) {
  Given g = process.required_quantity(q, range);
  if (g.si && !process.plausible(g.unit->key, *g.si, kCoefficientBound, g.unit)) g.si.reset();
  return g;
}

Process read_process(const Table& root, std::optional<double>* feed_mm, std::optional<double>* flute_length_m) {
  const auto process = root.table("process");
  const Document& doc = root.doc();
  if (!process) doc.fail_key("process", "missing (required table: [process] with operation = \"turning\" or \"milling\")");
  process->reject_unknown(kProcessKeys);

  constexpr std::string_view kOperationRule = R"(must be "turning" or "milling")";
  if (!process->has("operation"))
    doc.fail_key(process->path_of("operation"), R"(missing (required, "turning" or "milling"))");
  const auto operation = process->string("operation", kOperationRule);
  if (!operation) throw Skip{};
  const std::size_t mark = doc.error_count();

  if (*operation == "turning") {
    reject_keys_of(*process, kMillingKeys, "milling");
    const Given kf = read_coefficient(*process, kFeedForce, kPositive);
    *feed_mm = process->number("feed_per_rev_mm", kFeedMm);
    const auto cpd = process->number("process_damping_coefficient_n_per_m", kNonNegative);
    const auto dw = process->number("workpiece_diameter_mm", kPositive);
    if (cpd && *cpd > 0.0 && !process->has("workpiece_diameter_mm"))
      doc.error(process->path_of("process_damping_coefficient_n_per_m"), *process->find("process_damping_coefficient_n_per_m"),
                "needs process.workpiece_diameter_mm (the cutting speed V = pi D N / 60 sets the damping C a / V)");
    stop_if_errors_since(doc, mark);
    if (!kf.si) throw Skip{};
    TurningParameters p;
    p.feed_force_coefficient_n_per_m2 = *kf.si;
    p.process_damping_coefficient_n_per_m = cpd.value_or(0.0);
    p.workpiece_diameter_m = dw.value_or(0.0) * 1e-3;
    Band band = kCoefficientBand;
    band.symbol = "K_f";
    warn_band(*process, kf, kFeedForce, band);
    return model_checked(*process, [&] { return Process::turning(p); });
  }
  if (*operation == "milling") {
    reject_keys_of(*process, kTurningKeys, "turning");
    MillingParameters p;
    const auto teeth = process->integer("teeth", 1, kMaxTeeth);
    if (!process->has("teeth") && !process->meant("teeth")) doc.error_key(process->path_of("teeth"), "missing (required, integer >= 1)");
    const Given kt = read_coefficient(*process, kTangential, kPositive);
    // K_r: in N/m² (or N/mm²), or as the ratio K_r/K_t; exactly one.
    const auto ratio_given = process->number("radial_coefficient_ratio", kNonNegative);
    Given kr;
    if (process->has("radial_coefficient_ratio")) {
      kr = process->quantity(kRadial, kNonNegative);
      if (kr.present()) {
        doc.error(process->path_of(kr.unit->key), *process->find(kr.unit->key),
                  "not with radial_coefficient_ratio (give K_r once: " + std::string(kr.unit->key) +
                      " or radial_coefficient_ratio = K_r/K_t)");
        kr.si.reset();
      } else if (ratio_given && kt.si) {
        kr.si = *ratio_given * *kt.si;
        kr.unit = &kRadialKeys[0];
      }
    } else {
      kr = process->quantity(kRadial, kNonNegative);
      if (!kr.present() && !process->meant("radial_coefficient_n_per_m2"))
        doc.error_key(process->path_of("radial_coefficient_n_per_m2"),
                      "missing (required, N/m^2, >= 0); or give radial_coefficient_n_per_mm2 (N/mm^2) or "
                      "radial_coefficient_ratio (K_r/K_t)");
      if (kr.si && !process->plausible(kr.unit->key, *kr.si, kCoefficientBound, kr.unit)) kr.si.reset();
    }
    // Tool diameter and radial engagement: a_e/D, or a_e in mm with D.
    const auto diameter_mm = process->number("tool_diameter_mm", kPositive);
    std::optional<double> immersion;
    const bool has_ae = process->has("radial_depth_mm"), has_ratio = process->has("radial_immersion");
    if (has_ae && has_ratio) {
      doc.error(process->path_of("radial_depth_mm"), *process->find("radial_depth_mm"),
                "not with radial_immersion (give the radial engagement once: radial_immersion = a_e/D, or "
                "radial_depth_mm with tool_diameter_mm)");
    } else if (has_ae) {
      const auto ae = process->number("radial_depth_mm", kPositive);
      if (!process->has("tool_diameter_mm"))
        doc.error(process->path_of("radial_depth_mm"), *process->find("radial_depth_mm"),
                  "needs process.tool_diameter_mm (a_e/D = radial_depth_mm / tool_diameter_mm)");
      else if (ae && diameter_mm && *ae > *diameter_mm)
        doc.error(process->path_of("radial_depth_mm"), *process->find("radial_depth_mm"),
                  "must be <= tool_diameter_mm (" + number_text(*diameter_mm) + " mm): the cutter cannot engage more than its diameter");
      else if (ae && diameter_mm)
        immersion = *ae / *diameter_mm;
    } else {
      if (!process->has("radial_immersion") && !process->meant("radial_immersion"))
        doc.error_key(process->path_of("radial_immersion"),
                      "missing (required, a_e/D, in (0, 1]); or give radial_depth_mm with tool_diameter_mm");
      else
        immersion = process->number("radial_immersion", kUnitInterval);
    }
    constexpr std::string_view kDirectionRuleMilling = R"(must be "down" (= "climb") or "up" (= "conventional"))";
    const std::string direction = process->string("milling_direction", kDirectionRuleMilling).value_or("down");
    if (direction == "down" || direction == "climb")
      p.direction = MillingDirection::kDown;
    else if (direction == "up" || direction == "conventional")
      p.direction = MillingDirection::kUp;
    else
      doc.error(process->path_of("milling_direction"), *process->find("milling_direction"), kDirectionRuleMilling);
    *feed_mm = process->number("feed_per_tooth_mm", kFeedMm);
    if (const auto flute = process->number("flute_length_mm", kPositive)) *flute_length_m = *flute * 1e-3;
    // The cutter (docs/config.md, "Real cutters").
    const auto helix = process->number_list("helix_angle_deg", kHelixDeg);
    const auto pitch = process->number_list("pitch_angles_deg", kPositive);
    const auto runout = process->number_list("runout_um", kAnyNumber);
    const auto cpd = process->number("process_damping_coefficient_n_per_m", kNonNegative);
    auto need_diameter = [&](std::string_view key, std::string_view why) {
      if (process->has(key) && !process->has("tool_diameter_mm"))
        doc.error(process->path_of(key), *process->find(key), "needs process.tool_diameter_mm (" + std::string(why) + ")");
    };
    if (helix && std::any_of(helix->begin(), helix->end(), [](double b) { return b > 0.0; }))
      need_diameter("helix_angle_deg", "the helix lag of a slice at height z is z tan(beta) / R");
    if (cpd && *cpd > 0.0)
      need_diameter("process_damping_coefficient_n_per_m", "the cutting speed V = pi D N / 60 sets the damping C a / V");
    if (teeth) {
      const auto nt = static_cast<std::size_t>(*teeth);
      if (helix && helix->size() != 1 && helix->size() != nt)
        doc.error(process->path_of("helix_angle_deg"), *process->find("helix_angle_deg"),
                  "has " + std::to_string(helix->size()) + " values: give one number (every tooth) or one per tooth (teeth = " +
                      std::to_string(nt) + ")");
      if (pitch) {
        double sum = 0.0;
        for (const double th : *pitch) sum += th;
        if (pitch->size() != nt)
          doc.error(process->path_of("pitch_angles_deg"), *process->find("pitch_angles_deg"),
                    "has " + std::to_string(pitch->size()) + " values: need one per tooth (teeth = " + std::to_string(nt) +
                        "), the angle from the previous tooth to this one");
        else if (std::abs(sum - 360.0) > kPitchSumToleranceDeg)
          doc.error(process->path_of("pitch_angles_deg"), *process->find("pitch_angles_deg"),
                    "sums to " + number_text(sum) + " deg: the pitch angles must sum to 360 deg (one revolution)");
      }
      if (runout) {
        if (runout->size() != nt)
          doc.error(process->path_of("runout_um"), *process->find("runout_um"),
                    "has " + std::to_string(runout->size()) + " values: need one radial offset per tooth (teeth = " +
                        std::to_string(nt) + "), in um");
        else if (diameter_mm)
          for (std::size_t j = 0; j < nt; ++j)
            if (std::abs((*runout)[j]) * 1e-3 >= 0.5 * *diameter_mm) {
              // `runout_um = 1e5` with one tooth is a list of one: no element to point at.
              const auto [where, node] = process->list_item("runout_um", j);
              doc.error(where, *node,
                        "must be smaller than the tool radius (" + number_text(0.5 * *diameter_mm * 1e3) + " um)");
            }
      }
    }
    stop_if_errors_since(doc, mark);
    if (!(teeth && kt.si && kr.si && immersion)) throw Skip{};
    p.teeth = *teeth;
    p.tangential_coefficient_n_per_m2 = *kt.si;
    p.radial_coefficient_n_per_m2 = *kr.si;
    p.radial_immersion = *immersion;
    p.tool_diameter_m = diameter_mm.value_or(0.0) * 1e-3;
    constexpr double kDegToRad = kPi / 180.0;
    if (helix) {
      for (const double b : *helix) p.helix_angles_rad.push_back(b * kDegToRad);
      if (std::all_of(helix->begin(), helix->end(), [](double b) { return b == 0.0; })) p.helix_angles_rad.clear();
    }
    if (pitch) {
      double sum = 0.0;
      for (const double th : *pitch) sum += th;
      for (const double th : *pitch) p.pitch_angles_rad.push_back(th / sum * 2.0 * kPi);  // exactly one revolution
    }
    if (runout)
      for (const double r : *runout) p.runout_m.push_back(r * 1e-6);
    p.process_damping_coefficient_n_per_m = cpd.value_or(0.0);
    Band band = kCoefficientBand;
    band.symbol = "K_t";
    warn_band(*process, kt, kTangential, band);
    if (*kr.si > 0.0 && !process->has("radial_coefficient_ratio")) {  // K_r = 0 is a deliberate idealisation: no radial force
      warn_band(*process, kr, kRadial, kRadialBand);
      const double ratio = *kr.si / *kt.si;
      if (ratio < kRatioLo || ratio > kRatioHi)
        doc.warn(process->path_of(kr.unit->key), *process->find(kr.unit->key),
                 "K_r/K_t = " + number_text(ratio) +
                     ", outside the 0.05 to 1.5 of metal cutting (usually 0.1 to 1: aluminium about 0.3, steel and "
                     "titanium 0.3 to 0.8); are " +
                     std::string(kt.unit->key) + " and " + std::string(kr.unit->key) + " both right?");
    } else if (ratio_given && *ratio_given > 0.0 && (*ratio_given < kRatioLo || *ratio_given > kRatioHi)) {
      doc.warn(process->path_of("radial_coefficient_ratio"), *process->find("radial_coefficient_ratio"),
               "K_r/K_t = " + number_text(*ratio_given) +
                   ", outside the 0.05 to 1.5 of metal cutting (usually 0.1 to 1: aluminium about 0.3, steel and "
                   "titanium 0.3 to 0.8)");
    }
    return model_checked(*process, [&] { return Process::milling(p); });
  }
  doc.fail(process->path_of("operation"), *process->find("operation"), kOperationRule);
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
    sweep->doc().error(sweep->path_of("rpm_max"), *sweep->find("rpm_max"),
                       "must be > rpm_min (" + sweep->doc().as_written(*sweep->find("rpm_min")) + ")");
  s.rpm_points = sweep->integer("rpm_points", 2);
  s.depth_max_mm = sweep->number("depth_max_mm", kPositive);
  return s;
}

// -------------------------------------------------------------- uncertainty

/// `[uncertainty]`: 1σ spreads in percent (docs/config.md, docs/uncertainty.md).
/// Mode keys: one number for every mode, or an array with one value per mode
/// (tool modes, then workpiece modes). Every rule of
/// UncertaintySpreads::validate is checked here with the key and the value
/// as written.
std::optional<UncertaintySpreads> read_uncertainty(const Table& root, const StructuralModel& model,
                                                   const Process& process) {
  const auto t = root.table("uncertainty");
  if (!t) return std::nullopt;
  const Document& doc = root.doc();
  constexpr std::string_view kUncertaintyKeys[] = {"frequency_percent",
                                                   "damping_percent",
                                                   "stiffness_percent",
                                                   "tangential_coefficient_percent",
                                                   "radial_coefficient_percent",
                                                   "feed_force_coefficient_percent"};
  t->reject_unknown(kUncertaintyKeys);
  const std::size_t mark = doc.error_count();
  // 3 s < 1: a 3-sigma draw p (1 - 3 s) stays > 0.
  const Range kSpreadPercent{"in [0, 33.33) % (a 3-sigma draw p (1 - 3 s / 100) must stay > 0)", 0.0, false,
                             100.0 / kUncertaintyTruncationSigma, true};
  const std::size_t n_modes = model.tool.modes.size() + model.workpiece.modes.size();
  UncertaintySpreads s;
  auto mode_list = [&](std::string_view key, std::vector<double>* out) {
    const auto v = t->number_list(key, kSpreadPercent);
    if (!v) return;
    const toml::node& n = *t->find(key);
    if (n.as_array() && v->size() != n_modes) {
      doc.error(t->path_of(key), n,
                "must have one value per mode: " + std::to_string(n_modes) +
                    " (tool modes, then workpiece modes), or be one number for every mode");
      return;
    }
    for (const double p : *v) out->push_back(p / 100.0);
  };
  mode_list("frequency_percent", &s.frequency);
  mode_list("damping_percent", &s.damping);
  mode_list("stiffness_percent", &s.stiffness);
  std::vector<const Mode*> modes;
  for (const Mode& md : model.tool.modes) modes.push_back(&md);
  for (const Mode& md : model.workpiece.modes) modes.push_back(&md);
  for (std::size_t m = 0; m < modes.size() && !s.damping.empty(); ++m) {
    const double sd = s.damping_of(m), zeta = modes[m]->damping_ratio;
    if (zeta * (1.0 + kUncertaintyTruncationSigma * sd) < 1.0) continue;
    const bool one = s.damping.size() == 1;
    const Path where = one ? t->path_of("damping_percent") : element(t->path_of("damping_percent"), m);
    const toml::node& n = one ? *t->find("damping_percent") : *t->find("damping_percent")->as_array()->get(m);
    std::ostringstream rule;
    rule << "with damping ratio " << zeta << " (" << (m < model.tool.modes.size() ? "tool" : "workpiece")
         << " mode " << (m < model.tool.modes.size() ? m : m - model.tool.modes.size())
         << ") a 3-sigma draw reaches " << zeta * (1.0 + kUncertaintyTruncationSigma * sd)
         << ": must be < " << 100.0 * (1.0 / zeta - 1.0) / kUncertaintyTruncationSigma
         << " (a damping ratio stays < 1)";
    doc.error(where, n, rule.str());
    break;
  }
  const bool milling = process.operation() == Operation::kMilling;
  const auto kt = t->number("tangential_coefficient_percent", kSpreadPercent);
  const auto kr = t->number("radial_coefficient_percent", kSpreadPercent);
  const auto kf = t->number("feed_force_coefficient_percent", kSpreadPercent);
  for (const std::string_view key : {"tangential_coefficient_percent", "radial_coefficient_percent"})
    if (!milling && t->has(key))
      doc.error(t->path_of(key), *t->find(key), "only for milling (turning: feed_force_coefficient_percent)");
  if (milling && t->has("feed_force_coefficient_percent"))
    doc.error(t->path_of("feed_force_coefficient_percent"), *t->find("feed_force_coefficient_percent"),
              "only for turning (milling: tangential_coefficient_percent, radial_coefficient_percent)");
  if (milling) {
    s.tangential = kt.value_or(0.0) / 100.0;
    s.radial = kr.value_or(0.0) / 100.0;
  } else {
    s.tangential = kf.value_or(0.0) / 100.0;
  }
  stop_if_errors_since(doc, mark);
  if (const std::string why = s.validate(model, process); !why.empty())
    doc.fail_key("uncertainty", why);  // a rule above is missing: still name the table
  return s;
}

// --------------------------------------------------------------------- root

/// Each mode's natural frequency against the tooth-passing frequencies of the
/// [sweep] speeds: a mode the sweep cannot excite in a usual lobe.
void warn_frequency_vs_speeds(const toml::table& root_table, const Document& doc, const Config& config) {
  if (!config.sweep.rpm_min || !config.sweep.rpm_max) return;
  const double z = config.process.delays_per_revolution();
  const double ftp_min = *config.sweep.rpm_min * z / 60.0, ftp_max = *config.sweep.rpm_max * z / 60.0;
  for (const std::string_view name : {"tool", "workpiece"}) {
    const Body& body = name == "tool" ? config.model.tool : config.model.workpiece;
    const toml::array* modes = root_table.at_path(std::string(name) + ".modes").as_array();
    if (!modes) continue;
    for (std::size_t i = 0; i < body.modes.size() && i < modes->size(); ++i) {
      const toml::table* t = modes->get(i)->as_table();
      if (!t) continue;
      const double f = body.modes[i].natural_frequency_hz;
      std::string what;
      if (f > kLobeNumberMax * ftp_max)
        what = "f is over " + number_text(kLobeNumberMax) + " times the tooth-passing frequency at sweep.rpm_max (" +
               number_text(ftp_max) + " Hz): lobe numbers above " + number_text(kLobeNumberMax) +
               " at every speed of the sweep, lobes narrower than its speed step; is the speed in rev/min (not "
               "rev/s) and the frequency in Hz (not rad/s)?";
      else if (f * kToothPassingOverModeMax < ftp_min)
        what = "f is under 1/" + number_text(kToothPassingOverModeMax) +
               " of the tooth-passing frequency at sweep.rpm_min (" + number_text(ftp_min) +
               " Hz): every speed of the sweep is far past the last lobe; is the frequency in Hz (not kHz) and "
               "the speed in rev/min?";
      if (what.empty()) continue;
      const Path path = element(child(Path(name), "modes"), i);
      if (const toml::node* n = t->get("frequency_hz"))
        doc.warn(child(path, "frequency_hz"), *n, what);
      else
        doc.warn_key(child(path, "cantilever"), "gives f = " + number_text(f) + " Hz: " + what);
    }
  }
}

// ---------------------------------------------------------------- positions

constexpr UnitKey kPositionKeys[] = {{"position_m", 1.0, "m"}, {"position_mm", 1e-3, "mm"}};
const Quantity kPosition{kPositionKeys};

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
    stations.push_back(std::move(st));
  }
  return stations;
}

Config read_config(const toml::table& root_table, const Document& doc) {
  const Table root(doc, root_table, "");
  constexpr std::string_view kTopKeys[] = {"name", "process", "tool", "workpiece", "sweep", "positions", "uncertainty"};
  root.reject_unknown(kTopKeys);

  Config config;
  const auto name = root.string("name");
  if (name && name->empty()) doc.error("name", *root.find("name"), "must not be empty");
  if (name) {
    config.name = *name;
  } else {
    const std::string stem = std::filesystem::path(doc.origin()).stem().string();
    config.name = stem.empty() ? doc.origin() : stem;
  }
  attempt_void([&] { config.process = read_process(root, &config.feed_mm, &config.flute_length_m); });
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

}  // namespace
}  // namespace chatter::config_detail

namespace chatter {

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
  const config_detail::Document doc(toml_text, origin);
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
    return config_detail::read_config(root, doc);
  } catch (const InputError&) {
    throw;
  } catch (const config_detail::Skip&) {
    // Every Skip is caught where reading resumes; should one get here, its
    // error is recorded: report it.
    doc.throw_if_errors();
    throw InputError(origin + ": invalid config");
#if TOML_EXCEPTIONS
  } catch (const toml::parse_error& e) {
    throw InputError(origin + ":" + std::to_string(e.source().begin.line) + ":" +
                     std::to_string(e.source().begin.column) + ": " + std::string(e.description()));
#endif
  }
}

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
