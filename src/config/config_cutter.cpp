// [process] keys of a milling cutter's shape along its axis (docs/config.md
// "Cutter geometry", docs/cutter_geometry.md): cutter_geometry,
// corner_radius_mm, [[process.profile]], profile_slices and the axial force
// coefficient K_a.
#include "config_sections.hpp"

#include <cmath>
#include <string>

namespace chatter::config_detail {
namespace {

constexpr UnitKey kAxialKeys[] = {{"axial_force_coefficient_n_per_m2", 1.0, "N/m^2"},
                                  {"axial_force_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
const Quantity kAxial{kAxialKeys};
constexpr Plausible kAxialBound{0.0, 1e13, "must be <= 1e13 N/m^2 (steel cuts at about 2e9)"};
const Band kAxialBand{5e6, 1.5e10, "K_a", "N/m^2", "the 5e6 to 1.5e10 N/m^2 of metal cutting"};
constexpr std::string_view kRowKeys[] = {"height_mm", "radius_mm", "lead_angle_deg"};
constexpr std::string_view kGeometryRule = R"(must be "flat", "ball", "bull_nose" or "general")";
const Range kLeadDeg{"in [0, 90] (deg)", 0.0, false, 90.0, false};

std::optional<ProfilePoint> read_row(const Table& row) {
  row.reject_unknown(kRowKeys);
  const auto z = row.required_number("height_mm", kNonNegative, "mm");
  const auto r = row.required_number("radius_mm", kNonNegative, "mm");
  const auto k = row.required_number("lead_angle_deg", kLeadDeg, "deg");
  if (!(z && r && k)) return std::nullopt;
  return ProfilePoint{*z * 1e-3, *r * 1e-3, *k == 90.0 ? 0.5 * kPi : *k / 180.0 * kPi};
}

}  // namespace

void read_cutter(const Table& process, std::optional<double> diameter_mm, MillingParameters* p) {
  const Document& doc = process.doc();
  if (const Given ka = process.quantity(kAxial, kNonNegative);
      ka.si && process.plausible(ka.unit->key, *ka.si, kAxialBound, ka.unit)) {
    p->axial_coefficient_n_per_m2 = *ka.si;
    if (*ka.si > 0.0) warn_band(process, ka, kAxial, kAxialBand);  // 0: no axial force
  }
  const std::string name = process.string("cutter_geometry", kGeometryRule).value_or("flat");
  CutterProfileParameters& c = p->cutter;
  if (name == "flat") c.geometry = CutterGeometry::kFlat;
  else if (name == "ball") c.geometry = CutterGeometry::kBall;
  else if (name == "bull_nose") c.geometry = CutterGeometry::kBullNose;
  else if (name == "general") c.geometry = CutterGeometry::kGeneral;
  else {
    doc.error(process.path_of("cutter_geometry"), *process.find("cutter_geometry"), kGeometryRule);
    return;
  }
  const bool flat = c.geometry == CutterGeometry::kFlat;
  auto only_with = [&](std::string_view key, bool ok, std::string_view what) {
    if (process.has(key) && !ok) doc.error(process.path_of(key), *process.find(key), "only with " + std::string(what));
    return process.has(key) && ok;
  };
  if (!flat && !process.has("tool_diameter_mm"))
    doc.error(process.path_of("cutter_geometry"), *process.find("cutter_geometry"),
              "needs process.tool_diameter_mm (the radius R(z) of the slices is measured against D/2)");
  if (flat && p->axial_coefficient_n_per_m2 > 0.0) {
    const std::string key = process.has(kAxialKeys[0].key) ? std::string(kAxialKeys[0].key) : std::string(kAxialKeys[1].key);
    doc.warn(process.path_of(key), *process.find(key),
             "has no effect on a flat cutter (lead angle 90 deg: the axial force has no x-y part); set "
             "cutter_geometry = \"ball\", \"bull_nose\" or \"general\"");
  }
  if (only_with("profile_slices", !flat, R"(cutter_geometry = "ball", "bull_nose" or "general")"))
    if (const auto n = process.integer("profile_slices", 1, kMaxProfileSlices)) c.slices = *n;
  if (only_with("corner_radius_mm", c.geometry == CutterGeometry::kBullNose, R"(cutter_geometry = "bull_nose")")) {
    if (const auto rc = process.number("corner_radius_mm", kPositive)) {
      if (diameter_mm && *rc > 0.5 * *diameter_mm)
        doc.error(process.path_of("corner_radius_mm"), *process.find("corner_radius_mm"),
                  "must be <= tool_diameter_mm / 2 = " + number_text(0.5 * *diameter_mm) +
                      " mm (= D/2: a ball; give cutter_geometry = \"ball\")");
      else
        c.corner_radius_m = *rc * 1e-3;
    }
  } else if (c.geometry == CutterGeometry::kBullNose && !process.has("corner_radius_mm")) {
    doc.error_key(process.path_of("corner_radius_mm"),
                  "missing (required with cutter_geometry = \"bull_nose\": the corner radius, mm, in (0, D/2])");
  }
  if (only_with("profile", c.geometry == CutterGeometry::kGeneral, R"(cutter_geometry = "general")")) {
    const Path path = process.path_of("profile");
    const toml::node& n = *process.find("profile");
    const toml::array* rows = n.as_array();
    if (!rows) {
      doc.error(path, n, "must be an array of tables ([[" + path + "]]) with height_mm, radius_mm, lead_angle_deg");
      return;
    }
    for (std::size_t i = 0; i < rows->size(); ++i) {
      const toml::node& m = *rows->get(i);
      const toml::table* t = m.as_table();
      if (!t) {
        doc.error(element(path, i), m, "must be a table with height_mm, radius_mm, lead_angle_deg");
        continue;
      }
      const Table row(doc, *t, element(path, i));
      const auto q = read_row(row);
      if (!q) continue;
      if (i == 0 && q->height_m != 0.0)
        doc.error(row.path_of("height_mm"), *t->get("height_mm"), "must be 0 in the first row (the tip)");
      else if (i > 0 && !c.profile.empty() && q->height_m <= c.profile.back().height_m)
        doc.error(row.path_of("height_mm"), *t->get("height_mm"),
                  "must be above the row before (" + number_text(c.profile.back().height_m * 1e3) +
                      " mm): heights increase from the tip");
      else if (diameter_mm && q->radius_m * 1e3 > 0.5 * *diameter_mm * (1.0 + 1e-12))
        doc.error(row.path_of("radius_mm"), *t->get("radius_mm"),
                  "must be <= tool_diameter_mm / 2 = " + number_text(0.5 * *diameter_mm) + " mm");
      c.profile.push_back(*q);
    }
    if (rows->size() < 2) doc.error(path, n, "needs at least 2 rows (height_mm, radius_mm, lead_angle_deg)");
  } else if (c.geometry == CutterGeometry::kGeneral && !process.has("profile")) {
    doc.error_key(process.path_of("profile"),
                  "missing (required with cutter_geometry = \"general\": [[process.profile]] rows of height_mm, "
                  "radius_mm, lead_angle_deg from the tip)");
  }
}

}  // namespace chatter::config_detail
