// [process] of the TOML config (docs/config.md, "Process"): turning, and
// milling with the real-cutter keys (helix, pitch, runout, process damping).
#include "config_sections.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>

namespace chatter::config_detail {
namespace {

// ------------------------------------------------------ plausibility bounds

constexpr Plausible kCoefficientBound{0.0, 1e13, "must be <= 1e13 N/m^2 (steel cuts at about 2e9)"};
/// A feed below this (mm per tooth or revolution) is thinner than any chip.
constexpr double kThinFeedMm = 1e-3;
/// The usual lengths of the process (docs/config.md, "Plausibility warnings"),
/// in mm as written; metres typed as mm fall below, micrometres above.
constexpr const Usual& kToolDiameterUsual = usual::kToolDiameterMm;
constexpr const Usual& kWorkpieceDiameterUsual = usual::kWorkpieceDiameterMm;
constexpr const Usual& kFluteLengthUsual = usual::kFluteLengthMm;
constexpr const Usual& kImmersionUsual = usual::kRadialImmersion;
constexpr const Usual& kProcessDampingUsual = usual::kProcessDampingNPerM;
/// A nose radius below this (mm, but > 0: 0 is a sharp corner) is metres typed as mm.
constexpr double kTinyNoseRadiusMm = 0.01;
/// A radial depth thinner than this (mm) is a cut below a sharp edge's radius:
/// warned as metres typed as mm (docs/config.md).
constexpr double kPlausibleRadialDepthMm = 0.01;

// ------------------------------------------------------------ the quantities

// Every quantity has its SI key first, then at most a couple of shop-unit
// keys whose suffix names the unit (docs/config.md, "Units").
constexpr UnitKey kFeedForceKeys[] = {{"feed_force_coefficient_n_per_m2", 1.0, "N/m^2"},
                                      {"feed_force_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
constexpr UnitKey kRadialForceKeys[] = {{"radial_force_coefficient_n_per_m2", 1.0, "N/m^2"},
                                       {"radial_force_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
constexpr UnitKey kTangentialKeys[] = {{"tangential_coefficient_n_per_m2", 1.0, "N/m^2"},
                                       {"tangential_coefficient_n_per_mm2", 1e6, "N/mm^2"}};
constexpr UnitKey kRadialKeys[] = {{"radial_coefficient_n_per_m2", 1.0, "N/m^2"},
                                   {"radial_coefficient_n_per_mm2", 1e6, "N/mm^2"}};

const Quantity kFeedForce{kFeedForceKeys};
const Quantity kRadialForce{kRadialForceKeys};
const Quantity kTangential{kTangentialKeys};
const Quantity kRadial{kRadialKeys};

// ------------------------------------------------------ plausibility warnings

const Band kCoefficientBand{1e8, 1e10, "K", "N/m^2",
                            "the 1e8 to 1e10 N/m^2 of metal cutting (aluminium about 5e8, steel about 2e9, hardened "
                            "steel and titanium about 3e9)"};
const Band kRadialBand{5e6, 1.5e10, "K_r", "N/m^2", "the 5e6 to 1.5e10 N/m^2 of metal cutting"};
// K_r/K_t: usually 0.1 to 1; warned outside this slightly wider band.
constexpr double kRatioLo = 0.05, kRatioHi = 1.5;

// ------------------------------------------------------------------ keys

constexpr std::string_view kTurningKeys[] = {"feed_force_coefficient_n_per_m2",
                                             "feed_force_coefficient_n_per_mm2",
                                             "radial_force_coefficient_n_per_m2",
                                             "radial_force_coefficient_n_per_mm2",
                                             "lead_angle_deg",
                                             "nose_radius_mm",
                                             "feed_per_rev_mm",
                                             "workpiece_diameter_mm",
                                             "force_law",
                                             "specific_force_n_per_mm2",
                                             "exponent"};
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
                                             "engaged_arc_deg",
                                             "helix_angle_deg",
                                             "pitch_angles_deg",
                                             "runout_um",
                                             "radial_coefficient_ratio",
                                             "cutter_geometry",
                                             "corner_radius_mm",
                                             "profile",
                                             "profile_slices",
                                             "axial_force_coefficient_n_per_m2",
                                             "axial_force_coefficient_n_per_mm2"};
// The static chip of the time-domain simulation (feed per revolution in
// turning, per tooth in milling), mm.
const Range kFeedMm{"in (0, 10] (mm)", 0.0, true, kMaxFeedMm, false};
static_assert(kMaxFeedMm == 10.0, "kFeedMm's text names the bound");
// The keys of either operation, and every key of [process]: the lists above
// joined (what reject_unknown accepts and names, in this order).
constexpr std::string_view kOperationKey[] = {"operation"};
constexpr std::string_view kSharedKeys[] = {"process_damping_coefficient_n_per_m", "speed_variation"};
template <std::size_t... N>
constexpr auto join_keys(const std::string_view (&... lists)[N]) {
  std::array<std::string_view, (N + ...)> out{};
  std::size_t at = 0;
  ((std::copy(std::begin(lists), std::end(lists), out.begin() + static_cast<std::ptrdiff_t>(at)), at += N), ...);
  return out;
}
constexpr auto kProcessKeys = join_keys(kOperationKey, kTurningKeys, kMillingKeys, kSharedKeys);
// Pitch angles as written must sum to 360° to this (deg); they are then
// scaled to sum to exactly one revolution.
constexpr double kPitchSumToleranceDeg = 1e-3;
const Range kHelixDeg{"in [0, 90) (deg)", 0.0, false, 90.0, true};
// Plausibility of the cutter (warnings; --strict refuses them): a helix at or
// above 60 deg, a helix below 1.6 deg (radians typed as degrees), a feed
// above 1 mm per tooth or per revolution (um typed as mm is refused by the
// range, 1 to 10 mm is possible but rare).
constexpr double kSteepHelixDeg = 60.0;
constexpr double kRadianLikeHelixDeg = 1.6;
constexpr double kPlausibleFeedMm = 1.0;
// The turning insert (docs/turning_inserts.md): lead angle in (0, 90] deg
// (above 90 the chord model does not apply), nose radius in [0, 25] mm
// (round inserts reach 16 mm). Warned: a lead angle below 1.6 deg (radians
// typed as degrees), a nose radius above 2.4 mm (the largest of ISO
// turning inserts but round ones: a diameter, or um typed as mm?).
const Range kLeadAngleDeg{"in (0, 90] (deg)", 0.0, true, 90.0, false};
const Range kNoseRadiusMm{"in [0, 25] (mm)", 0.0, false, 25.0, false};
constexpr double kRadianLikeLeadDeg = 1.6;
constexpr double kLargeNoseRadiusMm = 2.4;

void warn_feed(const Table& process, std::string_view key, const std::optional<double>& feed, const char* per) {
  if (feed && *feed > kPlausibleFeedMm)
    process.doc().warn(process.path_of(key), *process.find(key),
                       "a feed of " + number_text(*feed) + " mm " + per + " is above the 0.01 to 1 mm of cutting; "
                       "a feed per revolution given per tooth, or in the wrong unit?");
  if (feed && *feed < kThinFeedMm)  // metres typed as mm (0.00005 for 0.05)
    process.doc().warn(process.path_of(key), *process.find(key),
                       "a feed of " + number_text(*feed) + " mm " + per + " is below " + number_text(kThinFeedMm) +
                           " mm, thinner than any chip; is it in m (" + std::string(key) + " = " +
                           number_text(*feed * 1e3) + ")?");
}

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

// engaged_arc_deg: one arc [entry, exit] or a list of them [[en, ex], ...]
// (degrees, clockwise from the normal left of the feed): each 0 <= en < ex
// <= 180, sorted and not touching. Empty when bad (every error recorded).
std::vector<std::pair<double, double>> read_engaged_arcs(const Document& doc, const Table& process) {
  const std::string_view key = "engaged_arc_deg";
  const toml::node* node = process.find(key);
  const toml::array* list = node->as_array();
  if (!list || list->empty()) {
    doc.error(process.path_of(key), *node, "must be [entry, exit] or a list of them [[entry, exit], ...] (degrees)");
    return {};
  }
  std::vector<std::pair<const toml::node*, Path>> arcs;  // each [entry, exit] node and its path
  if (list->front().is_array()) {
    for (std::size_t i = 0; i < list->size(); ++i) arcs.emplace_back(list->get(i), element(process.path_of(key), i));
  } else {
    arcs.emplace_back(node, process.path_of(key));
  }
  std::vector<std::pair<double, double>> out;
  for (const auto& [arc, path] : arcs) {
    const toml::array* a = arc->as_array();
    std::optional<double> en, ex;
    if (a && a->size() == 2) {
      en = (*a)[0].value<double>();
      ex = (*a)[1].value<double>();
    }
    if (!(en && ex && std::isfinite(*en) && std::isfinite(*ex) && *en >= 0.0 && *en < *ex && *ex <= 180.0)) {
      doc.error(path, *arc, "must be [entry, exit] with 0 <= entry < exit <= 180 (degrees)");
      return {};
    }
    if (!out.empty() && !(*en > out.back().second)) {
      doc.error(path, *arc, "arcs must be sorted and must not touch or overlap (merge them into one)");
      return {};
    }
    out.emplace_back(*en, *ex);
  }
  return out;
}

Process with_speed_variation(Process p, const std::optional<SpeedVariation>& ssv) {
  if (ssv) p.set_speed_variation(*ssv);
  return p;
}

// [process] of a turning operation: K_f, the insert (K_r, lead angle, nose
// radius), the workpiece diameter and process damping.
Process read_turning(const Table& t, std::size_t mark, std::optional<double>* feed_mm,
                     const std::optional<SpeedVariation>& ssv) {
  const Table* process = &t;
  const Document& doc = t.doc();
  reject_keys_of(*process, kMillingKeys, "milling");
  *feed_mm = process->number("feed_per_rev_mm", kFeedMm);
  warn_feed(*process, "feed_per_rev_mm", *feed_mm, "per revolution");
  // Kienzle's law gives K_f and K_r (config_kienzle.cpp); else K_f is required.
  const toml::node* law = process->find("force_law");
  const bool kienzle = law && law->value<std::string>() == "kienzle";
  const std::optional<KienzleLaw> size_effect =
      attempt([&] { return read_kienzle(*process, *feed_mm); }).value_or(std::nullopt);
  const Given kf = kienzle ? Given{} : read_coefficient(*process, kFeedForce, kPositive);
  const auto cpd = process->number("process_damping_coefficient_n_per_m", kNonNegative);
  const auto dw = process->number("workpiece_diameter_mm", kPositive);
  double kr = 0.0;  // K_r of the insert, N/m² (absent: 0)
  if (const Given g = process->quantity(kRadialForce, kNonNegative);
      g.si && process->plausible(g.unit->key, *g.si, kCoefficientBound, g.unit)) {
    kr = *g.si;
    if (kr > 0.0) warn_band(*process, g, kRadialForce, kRadialBand);  // 0: an insert without radial force
  }
  const auto lead = process->number("lead_angle_deg", kLeadAngleDeg);
  const auto nose = process->number("nose_radius_mm", kNoseRadiusMm);
  if (lead && *lead < kRadianLikeLeadDeg)
    doc.warn(process->path_of("lead_angle_deg"), *process->find("lead_angle_deg"),
             "a lead angle of " + number_text(*lead) + " deg: a value in radians (" + number_text(*lead) +
                 " rad = " + number_text(*lead * 180.0 / kPi) + " deg)? the key is in degrees, 90 = edge "
                 "perpendicular to the feed");
  if (nose && *nose > 0.0 && *nose < kTinyNoseRadiusMm)
    doc.warn(process->path_of("nose_radius_mm"), *process->find("nose_radius_mm"),
             "a nose radius of " + number_text(*nose) + " mm is below the 0.1 to 2.4 mm of turning inserts (0 is a "
             "sharp corner); is it in m (nose_radius_mm = " + number_text(*nose * 1e3) + ")?");
  warn_usual(*process, "workpiece_diameter_mm", dw, kWorkpieceDiameterUsual);
  if (cpd && *cpd > 0.0) warn_usual(*process, "process_damping_coefficient_n_per_m", cpd, kProcessDampingUsual);
  if (nose && *nose > kLargeNoseRadiusMm)
    doc.warn(process->path_of("nose_radius_mm"), *process->find("nose_radius_mm"),
             "a nose radius of " + number_text(*nose) + " mm is above the 0.1 to 2.4 mm of turning inserts (round "
             "inserts excepted): the diameter, or another unit?");
  if (cpd && *cpd > 0.0 && !process->has("workpiece_diameter_mm"))
    doc.error(process->path_of("process_damping_coefficient_n_per_m"), *process->find("process_damping_coefficient_n_per_m"),
              "needs process.workpiece_diameter_mm (the cutting speed V = pi D N / 60 sets the damping C a / V)");
  stop_if_errors_since(doc, mark);
  if (!kf.si && !size_effect) throw Skip{};
  TurningParameters p;
  p.feed_force_coefficient_n_per_m2 = kf.si.value_or(0.0);  // with Kienzle's law: derived by Process::turning
  p.kienzle = size_effect;
  p.process_damping_coefficient_n_per_m = cpd.value_or(0.0);
  p.workpiece_diameter_m = dw.value_or(0.0) * 1e-3;
  p.radial_force_coefficient_n_per_m2 = kr;
  if (lead) p.lead_angle_rad = *lead / 180.0 * kPi;  // 90 → π/2 exactly
  if (nose) p.nose_radius_m = *nose * 1e-3;
  Band band = kCoefficientBand;
  band.symbol = "K_f";
  if (kf.si) warn_band(*process, kf, kFeedForce, band);
  return model_checked(*process, [&] { return with_speed_variation(Process::turning(p), ssv); });
}

// K_r in N/m² (or N/mm²), or as the ratio K_r/K_t (`*ratio_given`): exactly one.
Given read_radial_coefficient(const Table& t, const Given& kt, std::optional<double>* ratio_given) {
  const Table* process = &t;
  const Document& doc = t.doc();
  *ratio_given = process->number("radial_coefficient_ratio", kNonNegative);
  Given kr;
  if (process->has("radial_coefficient_ratio")) {
    kr = process->quantity(kRadial, kNonNegative);
    if (kr.present()) {
      doc.error(process->path_of(kr.unit->key), *process->find(kr.unit->key),
                "not with radial_coefficient_ratio (give K_r once: " + std::string(kr.unit->key) +
                    " or radial_coefficient_ratio = K_r/K_t)");
      kr.si.reset();
    } else if (*ratio_given && kt.si) {
      kr.si = **ratio_given * *kt.si;
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
  return kr;
}

// The radial engagement: a_e/D, a_e in mm with D, or engaged arcs (what
// `chatter program` reads off a stock, into `*arcs_deg`). Empty on an error.
std::optional<double> read_engagement(const Table& t, std::optional<double> diameter_mm,
                                      std::vector<std::pair<double, double>>* arcs_deg) {
  const Table* process = &t;
  const Document& doc = t.doc();
  std::optional<double> immersion;
  const bool has_ae = process->has("radial_depth_mm"), has_ratio = process->has("radial_immersion");
  // Engaged arcs instead of a wall (what `chatter program` reads off a stock).
  if (process->has("engaged_arc_deg")) {
    const auto* node = process->find("engaged_arc_deg");
    if (has_ae || has_ratio || process->has("milling_direction"))
      doc.error(process->path_of("engaged_arc_deg"), *node,
                "not with radial_immersion, radial_depth_mm or milling_direction (the arc says both)");
    else
      *arcs_deg = read_engaged_arcs(doc, *process);
    if (!arcs_deg->empty()) {
      immersion = 0.0;
      for (const auto& [en, ex] : *arcs_deg) *immersion += 0.5 * (std::cos(en * kPi / 180.0) - std::cos(ex * kPi / 180.0));
    }
  } else if (has_ae && has_ratio) {
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
    if (ae && *ae < kPlausibleRadialDepthMm)  // metres typed as mm (0.004 for 4 mm)
      doc.warn(process->path_of("radial_depth_mm"), *process->find("radial_depth_mm"),
               "below " + number_text(kPlausibleRadialDepthMm) + " mm, a cut thinner than the edge's radius: a radial depth in m? (" +
                   number_text(*ae) + " m is " + number_text(*ae * 1e3) + " mm)");
    else if (immersion && *immersion < kImmersionUsual.lo)  // a slot's 16 mm typed as 0.016
      doc.warn(process->path_of("radial_depth_mm"), *process->find("radial_depth_mm"),
               "gives a_e/D = " + number_text(*immersion) + ", below the " + number_text(kImmersionUsual.lo) +
                   " of milling engagements: a radial depth in m? (" + number_text(*ae) + " m is " +
                   number_text(*ae * 1e3) + " mm)");
  } else {
    const toml::node* n = process->find("radial_immersion");
    const double v = !n ? 0.0 : n->is_integer() ? static_cast<double>(n->as_integer()->get())
                              : n->is_floating_point() ? n->as_floating_point()->get() : 0.0;
    if (!n && !process->meant("radial_immersion"))
      doc.error_key(process->path_of("radial_immersion"),
                    "missing (required, a_e/D, in (0, 1]); or give radial_depth_mm with tool_diameter_mm");
    else if (v > 1.0 && v <= 100.0)  // a percentage typed as the ratio (25 for 25 %)
      doc.error(process->path_of("radial_immersion"), *n,
                "must be in (0, 1] (a_e/D, a ratio, not a percentage: " + doc.as_written(*n) + " % is " +
                    number_text(v / 100.0) + ")");
    else {
      immersion = process->number("radial_immersion", kUnitInterval);
      warn_usual(*process, "radial_immersion", immersion, kImmersionUsual);
    }
  }
  return immersion;
}

// A helix beyond end mills (the lead angle given?) or one in radians.
void warn_helix(const Table& t, const std::vector<double>& helix) {
  const Table* process = &t;
  const Document& doc = t.doc();
  // End mills have 0 to ~50 deg; a few rad look like degrees below 1.6.
  const double top = *std::max_element(helix.begin(), helix.end());
  double low = kInf;
  for (const double b : helix)
    if (b > 0.0) low = std::min(low, b);
  const toml::node& node = *process->find("helix_angle_deg");
  if (top >= kSteepHelixDeg)
    doc.warn(process->path_of("helix_angle_deg"), node,
             "a helix of " + number_text(top) + " deg (" + number_text(kSteepHelixDeg) +
                 " or more) is beyond end mills (0 to about 50 deg); is it the helix angle, not the lead angle "
                 "(90 - helix)?");
  else if (low < kRadianLikeHelixDeg)
    doc.warn(process->path_of("helix_angle_deg"), node,
             "a helix of " + number_text(low) + " deg is hardly a helix: a value in radians (" + number_text(low) +
                 " rad = " + number_text(low * 180.0 / kPi) + " deg)? the key is in degrees");
}

// One helix angle (or one per tooth), one pitch angle per tooth summing to
// 360 deg, one runout per tooth smaller than the radius.
void check_tooth_lists(const Table& t, std::size_t nt, const std::optional<std::vector<double>>& helix,
                       const std::optional<std::vector<double>>& pitch, const std::optional<std::vector<double>>& runout,
                       std::optional<double> diameter_mm) {
  const Table* process = &t;
  const Document& doc = t.doc();
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

// K_t and K_r against metal cutting's bands, and their ratio.
void warn_milling_coefficients(const Table& t, const Given& kt, const Given& kr, std::optional<double> ratio_given) {
  const Table* process = &t;
  const Document& doc = t.doc();
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
}

// [process] of a milling operation: teeth, K_t and K_r, the engagement, the
// direction, the feed, the cutter (helix, pitch, runout, shape) and process
// damping.
Process read_milling(const Table& t, std::size_t mark, std::optional<double>* feed_mm,
                     std::optional<double>* flute_length_m, const std::optional<SpeedVariation>& ssv) {
  const Table* process = &t;
  const Document& doc = t.doc();
  reject_keys_of(*process, kTurningKeys, "turning");
  MillingParameters p;
  const auto teeth = process->integer("teeth", 1, kMaxTeeth);
  if (!process->has("teeth") && !process->meant("teeth")) doc.error_key(process->path_of("teeth"), "missing (required, integer >= 1)");
  const Given kt = read_coefficient(*process, kTangential, kPositive);
  std::optional<double> ratio_given;
  const Given kr = read_radial_coefficient(*process, kt, &ratio_given);
  // Tool diameter and radial engagement: a_e/D, or a_e in mm with D.
  const auto diameter_mm = process->number("tool_diameter_mm", kPositive);
  warn_usual(*process, "tool_diameter_mm", diameter_mm, kToolDiameterUsual);
  std::vector<std::pair<double, double>> arcs_deg;
  const std::optional<double> immersion = read_engagement(*process, diameter_mm, &arcs_deg);
  constexpr std::string_view kDirectionRuleMilling = R"(must be "down" (= "climb") or "up" (= "conventional"))";
  const std::string direction = process->string("milling_direction", kDirectionRuleMilling).value_or("down");
  if (direction == "down" || direction == "climb")
    p.direction = MillingDirection::kDown;
  else if (direction == "up" || direction == "conventional")
    p.direction = MillingDirection::kUp;
  else
    doc.error(process->path_of("milling_direction"), *process->find("milling_direction"), kDirectionRuleMilling);
  *feed_mm = process->number("feed_per_tooth_mm", kFeedMm);
  warn_feed(*process, "feed_per_tooth_mm", *feed_mm, "per tooth");
  if (const auto flute = process->number("flute_length_mm", kPositive)) {
    *flute_length_m = *flute * 1e-3;
    warn_usual(*process, "flute_length_mm", flute, kFluteLengthUsual);
  }
  // The cutter (docs/config.md, "Real cutters").
  const auto helix = process->number_list("helix_angle_deg", kHelixDeg);
  const auto pitch = process->number_list("pitch_angles_deg", kPositive);
  const auto runout = process->number_list("runout_um", kAnyNumber);
  const auto cpd = process->number("process_damping_coefficient_n_per_m", kNonNegative);
  if (cpd && *cpd > 0.0) warn_usual(*process, "process_damping_coefficient_n_per_m", cpd, kProcessDampingUsual);
  auto need_diameter = [&](std::string_view key, std::string_view why) {
    if (process->has(key) && !process->has("tool_diameter_mm"))
      doc.error(process->path_of(key), *process->find(key), "needs process.tool_diameter_mm (" + std::string(why) + ")");
  };
  if (helix && std::any_of(helix->begin(), helix->end(), [](double b) { return b > 0.0; }))
    need_diameter("helix_angle_deg", "the helix lag of a slice at height z is z tan(beta) / R");
  if (helix) warn_helix(*process, *helix);
  read_cutter(*process, diameter_mm, &p);  // the shape along the axis (config_cutter.cpp)
  if (cpd && *cpd > 0.0)
    need_diameter("process_damping_coefficient_n_per_m", "the cutting speed V = pi D N / 60 sets the damping C a / V");
  if (teeth) check_tooth_lists(*process, static_cast<std::size_t>(*teeth), helix, pitch, runout, diameter_mm);
  stop_if_errors_since(doc, mark);
  if (!(teeth && kt.si && kr.si && immersion)) throw Skip{};
  p.teeth = *teeth;
  p.tangential_coefficient_n_per_m2 = *kt.si;
  p.radial_coefficient_n_per_m2 = *kr.si;
  p.radial_immersion = *immersion;
  for (const auto& [en, ex] : arcs_deg) p.engaged_arcs_rad.emplace_back(en * kPi / 180.0, ex * kPi / 180.0);
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
  warn_milling_coefficients(*process, kt, kr, ratio_given);
  return model_checked(*process, [&] { return with_speed_variation(Process::milling(p), ssv); });
}

}  // namespace

Process read_process(const Table& root, std::optional<double>* feed_mm, std::optional<double>* flute_length_m) {
  const auto process = root.table("process");
  const Document& doc = root.doc();
  if (!process) {
    // A near miss ([proces]) was reported as unknown with "did you mean
    // process?": not missing as well.
    if (root.meant("process")) throw Skip{};
    doc.fail_key("process", "missing (required table: [process] with operation = \"turning\" or \"milling\")");
  }
  process->reject_unknown(kProcessKeys);

  constexpr std::string_view kOperationRule = R"(must be "turning" or "milling")";
  if (!process->has("operation"))
    doc.fail_key(process->path_of("operation"), R"(missing (required, "turning" or "milling"))");
  const auto operation = process->string("operation", kOperationRule);
  if (!operation) throw Skip{};
  const std::size_t mark = doc.error_count();
  // Spindle speed variation, for either operation (docs/ssv.md).
  const std::optional<SpeedVariation> ssv = attempt([&] { return read_speed_variation(*process); }).value_or(std::nullopt);
  if (*operation == "turning") return read_turning(*process, mark, feed_mm, ssv);
  if (*operation == "milling") return read_milling(*process, mark, feed_mm, flute_length_m, ssv);
  doc.fail(process->path_of("operation"), *process->find("operation"), kOperationRule);
}

}  // namespace chatter::config_detail
