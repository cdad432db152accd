// The records of `chatter coefficients` and `chatter detect`
// (chatter/records/shop.hpp): cutting coefficients from test cuts, chatter
// in a recording of the cut (issue 18), built once for the CLI and Python.
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/io/modes_toml.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/shop.hpp"
#include "chatter/report.hpp"
#include "chatter/solvers.hpp"
#include "chatter/kinematics.hpp"

namespace chatter {

using nlohmann::json;

namespace {

json num_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

std::string route_name(CoefficientRoute r) {
  switch (r) {
    case CoefficientRoute::kForces: return "average forces";
    case CoefficientRoute::kSeries: return "force series averaged over whole revolutions";
    case CoefficientRoute::kPower: return "net spindle power";
  }
  return "?";
}

const char* direction_word(MillingDirection d) { return d == MillingDirection::kDown ? "down" : "up"; }

// The detect check searches depths up to this multiple of depth_mm: a margin
// above it is reported as "at least" this much.
constexpr double kCheckDepthFactor = 4.0;

}  // namespace

// ------------------------------------------------------------------ coefficients

MillingEngagement coefficient_engagement(const CoefficientArgs& a, ArgStyle style) {
  MillingEngagement e;
  e.teeth = a.teeth;
  if (a.teeth < 1 || a.teeth > 1000)
    throw InputError(arg_name(style, "teeth") + " = " + std::to_string(a.teeth) + ": must be in [1, 1000]");
  if (!(a.radial_immersion > 0.0 && a.radial_immersion <= 1.0))
    throw InputError(arg_name(style, "radial_immersion") + " = " + number_text(a.radial_immersion) +
                     ": must be in (0, 1] (width of cut / diameter)");
  e.radial_immersion = a.radial_immersion;
  if (a.milling_direction == "down" || a.milling_direction == "climb") e.direction = MillingDirection::kDown;
  else if (a.milling_direction == "up" || a.milling_direction == "conventional") e.direction = MillingDirection::kUp;
  else throw InputError(arg_name(style, "milling_direction") + " '" + a.milling_direction + "': use down or up");
  if (a.diameter_mm && !(std::isfinite(*a.diameter_mm) && *a.diameter_mm > 0.0))
    throw InputError(arg_name(style, "diameter_mm") + " = " + number_text(*a.diameter_mm) + ": must be > 0 mm");
  return e;
}

CoefficientResult fit_cutting_coefficients(const CoefficientArgs& a, ArgStyle style) {
  CoefficientResult r;
  r.engagement = coefficient_engagement(a, style);
  r.radial_immersion = a.radial_immersion;
  r.diameter_mm = a.diameter_mm.value_or(0.0);
  r.tests_path = a.tests;
  r.tests = read_coefficient_tests(a.tests);
  if (r.power() && !a.diameter_mm)
    throw InputError(a.tests.string() + ": power tests need the tool diameter: give " + arg_name(style, "diameter_mm"));
  try {
    r.fit = r.power() ? fit_coefficients_from_power(r.tests.power, r.engagement, r.diameter_mm * 1e-3)
                      : fit_coefficients_from_forces(r.tests.forces, r.engagement);
  } catch (const InputError& err) {
    throw InputError(a.tests.string() + ": " + err.what());
  }
  return r;
}

std::string coefficients_report(const CoefficientResult& r) {
  const CoefficientFit& fit = r.fit;
  const bool power = r.power();
  std::ostringstream rep;
  const char* names[4] = {"tangential_coefficient", "radial_coefficient", "tangential_edge_coefficient",
                          "radial_edge_coefficient"};
  const double vals[4] = {fit.tangential_coefficient_n_per_m2, fit.radial_coefficient_n_per_m2,
                          fit.tangential_edge_coefficient_n_per_m, fit.radial_edge_coefficient_n_per_m};
  const double to_shop[4] = {1e-6, 1e-6, 1e-3, 1e-3};  // N/m^2 -> N/mm^2, N/m -> N/mm
  const char* shop_unit[4] = {"N/mm^2", "N/mm^2", "N/mm", "N/mm"};
  rep << r.tests_path.string() << ": " << r.tests.line.size() << " tests (" << route_name(r.tests.route) << "), "
      << r.engagement.teeth << " teeth, radial immersion " << number_text(r.radial_immersion) << ", "
      << direction_word(r.engagement.direction) << "-milling\n";
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(vals[i])) continue;
    char line[200];
    std::snprintf(line, sizeof line, "  %-28s %12.5g %-7s +- %.3g (95 %%)\n", names[i], vals[i] * to_shop[i],
                  shop_unit[i], fit.confidence_95[static_cast<std::size_t>(i)] * to_shop[i]);
    rep << line;
  }
  rep << "  R^2 = " << number_text(fit.r_squared, 6);
  if (!power) rep << " (fx " << number_text(fit.r_squared_x, 6) << ", fy " << number_text(fit.r_squared_y, 6) << ")";
  rep << ", " << fit.degrees_of_freedom << " degrees of freedom\n  residuals (measured - fitted) per test:\n";
  for (std::size_t i = 0; i < r.tests.line.size(); ++i) {
    rep << "    line " << r.tests.line[i] << ": ";
    if (power) rep << number_text(fit.residual_x_n[i], 4) << " W\n";
    else rep << "fx " << number_text(fit.residual_x_n[i], 4) << " N, fy " << number_text(fit.residual_y_n[i], 4) << " N\n";
  }
  return rep.str();
}

json coefficients_record(const CoefficientResult& r) {
  const CoefficientFit& fit = r.fit;
  const CoefficientTests& tests = r.tests;
  const bool power = r.power();
  json j;
  j["tests_file"] = r.tests_path.string();
  j["route"] = power ? "power" : tests.route == CoefficientRoute::kSeries ? "series" : "forces";
  j["teeth"] = r.engagement.teeth;
  j["radial_immersion"] = r.radial_immersion;
  j["milling_direction"] = direction_word(r.engagement.direction);
  j["tangential_coefficient_n_per_m2"] = fit.tangential_coefficient_n_per_m2;
  j["radial_coefficient_n_per_m2"] = num_or_null(fit.radial_coefficient_n_per_m2);
  j["tangential_edge_coefficient_n_per_m"] = fit.tangential_edge_coefficient_n_per_m;
  j["radial_edge_coefficient_n_per_m"] = num_or_null(fit.radial_edge_coefficient_n_per_m);
  const char* keys[4] = {"tangential_coefficient_n_per_m2", "radial_coefficient_n_per_m2",
                         "tangential_edge_coefficient_n_per_m", "radial_edge_coefficient_n_per_m"};
  for (std::size_t i = 0; i < 4; ++i) {
    j["standard_error"][keys[i]] = num_or_null(fit.standard_error[i]);
    j["confidence_95"][keys[i]] = num_or_null(fit.confidence_95[i]);
  }
  j["degrees_of_freedom"] = fit.degrees_of_freedom;
  j["r_squared"] = fit.r_squared;
  j["r_squared_fx"] = num_or_null(fit.r_squared_x);
  j["r_squared_fy"] = num_or_null(fit.r_squared_y);
  json res = json::array();
  for (std::size_t i = 0; i < tests.line.size(); ++i) {
    json t;
    t["line"] = tests.line[i];
    if (power) {
      t["feed_per_tooth_mm"] = tests.power[i].feed_per_tooth_m * 1e3;
      t["depth_mm"] = tests.power[i].depth_m * 1e3;
      t["power_w"] = tests.power[i].power_w;
      t["residual_power_w"] = fit.residual_x_n[i];
    } else {
      t["feed_per_tooth_mm"] = tests.forces[i].feed_per_tooth_m * 1e3;
      t["depth_mm"] = tests.forces[i].depth_m * 1e3;
      t["fx_mean_n"] = tests.forces[i].fx_mean_n;
      t["fy_mean_n"] = tests.forces[i].fy_mean_n;
      t["residual_fx_n"] = fit.residual_x_n[i];
      t["residual_fy_n"] = fit.residual_y_n[i];
      if (tests.route == CoefficientRoute::kSeries) {
        t["series"] = tests.series_file[i];
        t["revolutions_averaged"] = tests.series_average[i].revolutions;
      }
    }
    res.push_back(t);
  }
  j["tests"] = res;
  j["warnings"] = fit.warnings;
  return j;
}

std::string coefficients_fragment(const CoefficientResult& r, ArgStyle style) {
  const CoefficientFit& fit = r.fit;
  const std::string out = arg_name(style, "out");
  if (r.power())
    throw InputError(out + ": " + r.tests_path.string() +
                     " holds power tests, which give the tangential coefficients only; a [process] table needs the "
                     "radial coefficient too: measure forces, or write the table by hand");
  if (!(fit.tangential_coefficient_n_per_m2 > 0.0) || fit.radial_coefficient_n_per_m2 < 0.0)
    throw InputError(out + ": the fitted coefficients (K_tc = " + number_text(fit.tangential_coefficient_n_per_m2) +
                     ", K_rc = " + number_text(fit.radial_coefficient_n_per_m2) +
                     " N/m^2) are not a valid [process] table (K_tc > 0, K_rc >= 0): check the tests");
  std::ostringstream t;
  t << "# Cutting coefficients fitted by `chatter coefficients` (chatter " << version() << ") from "
    << r.tests_path.string() << ":\n# " << r.tests.line.size() << " tests, R^2 = " << number_text(fit.r_squared, 6)
    << ". Append modes ([[tool.modes]], e.g. from `chatter fit`) to make a config.\n"
    << "# Edge (rubbing) coefficients, not used by the stability model:\n"
    << "#   tangential_edge_coefficient_n_per_m = " << table_number(fit.tangential_edge_coefficient_n_per_m)
    << "\n#   radial_edge_coefficient_n_per_m = " << table_number(fit.radial_edge_coefficient_n_per_m) << "\n"
    << "[process]\noperation = \"milling\"\nteeth = " << r.engagement.teeth << "\n"
    << "tangential_coefficient_n_per_m2 = " << table_number(fit.tangential_coefficient_n_per_m2) << "   # +- "
    << table_number(fit.confidence_95[0]) << " (95 %)\n"
    << "radial_coefficient_n_per_m2 = " << table_number(fit.radial_coefficient_n_per_m2) << "   # +- "
    << table_number(fit.confidence_95[1]) << " (95 %)\n"
    << "radial_immersion = " << table_number(r.radial_immersion) << "\n"
    << "milling_direction = \"" << direction_word(r.engagement.direction) << "\"\n";
  // [uncertainty], commented out: 100 x standard error / coefficient
  // (docs/shop_data.md, "Spreads for [uncertainty]").
  const double se_t = 100.0 * fit.standard_error[0] / fit.tangential_coefficient_n_per_m2;
  const double se_r = fit.radial_coefficient_n_per_m2 > 0.0
                          ? 100.0 * fit.standard_error[1] / fit.radial_coefficient_n_per_m2
                          : std::numeric_limits<double>::quiet_NaN();
  t << "\n";
  if (!(std::isfinite(se_t) && std::isfinite(se_r))) {
    t << "# [uncertainty]: no spreads: the standard errors are not defined (no degree of freedom left, or K_rc = 0).\n";
    return t.str();
  }
  std::string notes;
  const UncertaintyKey keys[2] = {{"tangential_coefficient_percent", {allowed_spread_percent(se_t)}, false},
                                  {"radial_coefficient_percent", {allowed_spread_percent(se_r)}, false}};
  for (const auto& [k, raw] : {std::pair{&keys[0], se_t}, std::pair{&keys[1], se_r}})
    if (k->percent[0] < raw)
      notes += "\n" + k->key + ": the standard error is " + number_text(raw, 4) + " %, capped to " + number_text(k->percent[0], 4) +
               " % (the most [uncertainty] accepts)";
  t << commented_uncertainty_toml(
      {keys[0], keys[1]},
      "[uncertainty]: 1-sigma spreads of K_tc and K_rc from the fit's standard errors (percent = 100 x standard\n"
      "error / coefficient; docs/shop_data.md). To sample them with `chatter lobes --samples N`, remove the '#'\n"
      "in front of [uncertainty] and of each key below (the edge coefficients have no spread: not used)." +
          notes);
  return t.str();
}

// ------------------------------------------------------------------ detect

void check_detect_args(const DetectArgs& a, ArgStyle style) {
  const auto name = [&](const char* key) { return arg_name(style, key); };
  check_spindle_rpm(a.rpm, name("rpm"));
  if (a.teeth < 1 || a.teeth > 1000)
    throw InputError(name("teeth") + " = " + std::to_string(a.teeth) + ": must be in [1, 1000]");
  if (a.rpm_min && !(std::isfinite(*a.rpm_min) && *a.rpm_min > 0.0))
    throw InputError(name("rpm_min") + " = " + number_text(*a.rpm_min) + ": must be > 0 rev/min");
  if (!(std::isfinite(a.peak_ratio) && a.peak_ratio > 0.0))
    throw InputError(name("peak_ratio") + " = " + number_text(a.peak_ratio) + ": must be > 0");
  if ((a.config != nullptr) != a.depth_mm.has_value())
    throw InputError(a.config ? name("config") + ": give " + name("depth_mm") + " too (the depth to check the speeds at)"
                              : name("depth_mm") + ": give " + name("config") +
                                    " too (the model to check the speeds against)");
  if (a.depth_mm && !(std::isfinite(*a.depth_mm) && *a.depth_mm > 0.0 && *a.depth_mm <= 1000.0))
    throw InputError(name("depth_mm") + " = " + number_text(*a.depth_mm) + ": must be in (0, 1000] mm");
}

DetectResult detect_recording(const DetectArgs& a, ArgStyle style) {
  const auto name = [&](const char* key) { return arg_name(style, key); };
  check_detect_args(a, style);
  const Config* cfg = a.config;
  if (cfg && cfg->process.delays_per_revolution() != a.teeth)
    throw InputError(cfg->source.string() + ": the process has " + std::to_string(cfg->process.delays_per_revolution()) +
                     " delay period(s) per revolution (teeth; 1 for turning) but " + name("teeth") + " = " +
                     std::to_string(a.teeth));
  DetectResult r;
  r.recording_path = a.recording;
  r.rpm = a.rpm;
  r.teeth = a.teeth;
  r.peak_ratio = a.peak_ratio;
  // The speeds to suggest: the arguments, else the config's [sweep] (the
  // machine this config describes), else 0.5x to 1.5x the current speed.
  r.rpm_min = a.rpm_min ? *a.rpm_min : cfg && cfg->sweep.rpm_min ? *cfg->sweep.rpm_min : 0.5 * a.rpm;
  r.rpm_max = a.rpm_max ? *a.rpm_max : cfg && cfg->sweep.rpm_max ? *cfg->sweep.rpm_max : 1.5 * a.rpm;
  if (!(std::isfinite(r.rpm_max) && r.rpm_max > r.rpm_min))
    throw InputError(name("rpm_max") + " = " + number_text(r.rpm_max) + ": must be > " + name("rpm_min") + " (" +
                     number_text(r.rpm_min) + ")");

  r.recording = read_recording(a.recording, a.channel);
  DetectOptions o;
  o.spindle_rpm = a.rpm;
  o.teeth = a.teeth;
  o.rpm_min = r.rpm_min;
  o.rpm_max = r.rpm_max;
  o.peak_ratio_threshold = a.peak_ratio;
  r.prominence_threshold = o.prominence_threshold;
  ChatterDetection& det = r.detection;
  try {
    det = detect_chatter(r.recording.samples, r.recording.sample_rate_hz, o);
  } catch (const InputError& e) {
    throw InputError(a.recording.string() + ": " + e.what());
  }
  // A recording without the tooth-passing line of the given speed is the
  // wrong speed (or teeth): refuse to judge it rather than cry wolf.
  if (!det.tooth_passing_found && !a.force) {
    std::string implied;
    for (std::size_t k = 0; k < det.implied_rpm.size(); ++k)
      implied += (k == 0 ? "the tooth passing at " : k == 1 ? ", its 2nd harmonic at " : ", its 3rd at ") +
                 number_text(std::round(det.implied_rpm[k])) + " rev/min";
    throw InputError(a.recording.string() + ": no line stands within +/-2 % of the tooth-passing frequency " +
                     number_text(tooth_passing_hz(a.rpm, a.teeth)) + " Hz (" + name("rpm") + " " + number_text(a.rpm) + " x " + name("teeth") +
                     " " + std::to_string(a.teeth) + " / 60) or its second harmonic: is " + name("rpm") + " (or " +
                     name("teeth") + ") right? The strongest line, " + number_text(det.strongest_line_hz) + " Hz, would be " +
                     implied + ". " + (style == ArgStyle::kFlag ? "--force" : "force=True") +
                     " analyses the recording anyway.");
  }
  if (!det.tooth_passing_found)
    det.warnings.push_back("no line stands at the tooth-passing frequency of " + name("rpm") + " and " + name("teeth") +
                           " (analysed anyway: " + (style == ArgStyle::kFlag ? "--force" : "force=True") +
                           "); the verdict assumes a speed the recording does not show");

  // The model's view of each suggestion.
  if (cfg) {
    r.config_name = cfg->name;
    r.depth_mm = *a.depth_mm;
    r.check_depth_max_mm = kCheckDepthFactor * r.depth_mm;
    // The default method, as every command builds it (sdm where it applies;
    // an averaged method for a measured FRF in milling, with its note).
    ConfiguredSolver c = configure_solver(kAutoMethod, *cfg, r.check_depth_max_mm * 1e-3, {}, style);
    r.check_method = c.method;
    for (const std::string& n : c.notes) det.warnings.push_back(n);
    for (const SpeedSuggestion& s : det.suggestions) {
      const StabilityLimit l = c.solver->limit_at(SpindleSpeed(s.spindle_rpm));
      r.checks.push_back({l.bounded(), l.depth_limit_m * 1e3, l.depth_limit_m * 1e3 / r.depth_mm});
    }
  }
  return r;
}

std::string detect_report(const DetectResult& r) {
  const ChatterDetection& det = r.detection;
  std::ostringstream rep;
  rep << r.recording_path.string() << ": " << r.recording.format << ", " << number_text(r.recording.sample_rate_hz) << " Hz, "
      << number_text(det.duration_s) << " s, channel " << r.recording.channel << " of " << r.recording.channels << "\n"
      << "  tooth passing " << number_text(det.tooth_passing_hz) << " Hz (spindle " << number_text(det.spindle_hz)
      << " Hz), resolution " << number_text(det.frequency_resolution_hz, 3) << " Hz\n";
  if (std::isfinite(det.candidate_frequency_hz))
    rep << "  strongest other line " << number_text(det.candidate_frequency_hz) << " Hz: " << number_text(det.peak_ratio, 3)
        << " x the strongest forced line (chatter from " << number_text(r.peak_ratio, 3) << "), " << number_text(det.prominence, 3)
        << " x the noise floor (from 20), grew " << number_text(det.growth_ratio, 3) << " x over the recording\n";
  if (det.chatter) {
    rep << "CHATTER at " << number_text(det.chatter_frequency_hz) << " Hz";
    if (std::isfinite(det.onset_s)) rep << ", from about " << number_text(det.onset_s, 3) << " s";
    rep << "\n";
    if (det.suggestions.empty())
      rep << "  no speed N_k = 60 f_c / (teeth k) lies in " << number_text(r.rpm_min) << "-" << number_text(r.rpm_max) << " rev/min\n";
    else
      rep << "  try (nearest first), rev/min:\n";
    for (std::size_t i = 0; i < det.suggestions.size(); ++i) {
      rep << "    " << number_text(std::round(det.suggestions[i].spindle_rpm)) << "  (k = " << det.suggestions[i].k << ")";
      if (i < r.checks.size()) {
        const SuggestionCheck& c = r.checks[i];
        if (c.bounded)
          rep << "  model: depth limit " << number_text(c.depth_limit_mm, 4) << " mm, margin " << number_text(c.margin, 3)
              << (c.margin > 1 ? "" : "  (chatters in the model at this depth)");
        else
          rep << "  model: stable to " << number_text(r.check_depth_max_mm, 4) << " mm, margin > " << number_text(kCheckDepthFactor, 3);
      }
      rep << "\n";
    }
  } else {
    rep << "no chatter\n";
  }
  return rep.str();
}

json detect_record(const DetectResult& r) {
  const ChatterDetection& det = r.detection;
  json j;
  j["recording"] = r.recording_path.string();
  j["format"] = r.recording.format;
  j["sample_rate_hz"] = r.recording.sample_rate_hz;
  j["duration_s"] = det.duration_s;
  j["channel"] = r.recording.channel;
  j["channels"] = r.recording.channels;
  j["spindle_rpm"] = r.rpm;
  j["teeth"] = r.teeth;
  j["chatter"] = det.chatter;
  j["chatter_frequency_hz"] = num_or_null(det.chatter_frequency_hz);
  j["tooth_passing_hz"] = det.tooth_passing_hz;
  j["spindle_hz"] = det.spindle_hz;
  j["tooth_passing_found"] = det.tooth_passing_found;
  j["strongest_line_hz"] = num_or_null(det.strongest_line_hz);
  j["implied_rpm"] = det.implied_rpm;
  json sug = json::array(), full = json::array();
  const bool checked = !r.config_name.empty();
  for (std::size_t i = 0; i < det.suggestions.size(); ++i) {
    sug.push_back(det.suggestions[i].spindle_rpm);
    json s{{"rpm", det.suggestions[i].spindle_rpm}, {"k", det.suggestions[i].k}};
    if (checked) {
      const SuggestionCheck& c = r.checks[i];
      s["depth_limit_mm"] = c.bounded ? json(c.depth_limit_mm) : json(nullptr);
      s["margin"] = c.bounded ? json(c.margin) : json(nullptr);
      if (!c.bounded) s["margin_at_least"] = kCheckDepthFactor;
      s["stable_in_model"] = !c.bounded || c.margin > 1.0;
    }
    full.push_back(s);
  }
  j["suggested_rpm"] = sug;
  j["suggestions"] = full;
  j["rpm_min"] = r.rpm_min;
  j["rpm_max"] = r.rpm_max;
  if (checked) {
    j["config"] = r.config_name;
    j["depth_mm"] = r.depth_mm;
    j["check_method"] = r.check_method;
  }
  j["evidence"] = {{"measure", "chatter when the strongest line that is no spindle or tooth-passing harmonic has "
                               "peak_ratio >= peak_ratio_threshold and prominence >= prominence_threshold"},
                   {"candidate_frequency_hz", num_or_null(det.candidate_frequency_hz)},
                   {"peak_ratio", num_or_null(det.peak_ratio)},
                   {"peak_ratio_threshold", r.peak_ratio},
                   {"prominence", num_or_null(det.prominence)},
                   {"prominence_threshold", r.prominence_threshold},
                   {"growth_ratio", num_or_null(det.growth_ratio)},
                   {"onset_s", num_or_null(det.onset_s)},
                   {"frequency_resolution_hz", det.frequency_resolution_hz}};
  json peaks = json::array();
  for (const auto& p : det.peaks)
    peaks.push_back({{"frequency_hz", p.frequency_hz}, {"amplitude", p.amplitude}, {"kind", p.kind}, {"harmonic", p.harmonic}});
  j["peaks"] = peaks;
  j["warnings"] = det.warnings;
  return j;
}

ColumnRecord detect_columns(const DetectResult& r) {
  ColumnRecord out;
  out.fields = detect_record(r);
  out.groups.push_back({"/spectrum",
                        {{"frequency_hz", r.detection.spectrum_frequency_hz},
                         {"amplitude", r.detection.spectrum_amplitude}}});
  return out;
}

namespace {

// `record` with "fragment": the text `fragment` returns, or null when it
// refuses (InputError: no table to write).
template <class Fragment>
json with_fragment(json record, Fragment&& fragment) {
  try {
    record["fragment"] = fragment();
  } catch (const InputError&) {
    record["fragment"] = nullptr;
  }
  return record;
}

}  // namespace

json coefficients_record_with_fragment(const CoefficientResult& r, ArgStyle style) {
  return with_fragment(coefficients_record(r), [&] { return coefficients_fragment(r, style); });
}

json kienzle_record_with_fragment(const KienzleResult& r, ArgStyle style) {
  return with_fragment(kienzle_record(r), [&] { return kienzle_fragment(r, style); });
}

}  // namespace chatter
