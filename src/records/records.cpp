// The records of point and simulate (chatter/records.hpp), and what every
// record shares. Keys and their meaning: docs/results.md.
#include "chatter/records.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "chatter/io/table_writer.hpp"  // table_number
#include "chatter/kinematics.hpp"

namespace chatter {

using nlohmann::json;

std::string arg_name(ArgStyle style, const std::string& key) {
  if (style == ArgStyle::kKeyword) return key;
  std::string flag = "--" + key;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

std::vector<std::string> method_notes(const std::string& requested, const SolverDescriptor& descriptor,
                                      const Process& process, const SolverValues& options,
                                      const std::string& averaged_milling, ArgStyle style) {
  std::vector<std::string> notes = ignored_feature_notes(descriptor, process);
  // "auto" fell back to an averaged method for milling (measured FRFs).
  if (requested == kAutoMethod && !averaged_milling.empty())
    notes.insert(notes.begin(), "method auto chose \"" + descriptor.name +
                                    "\" (no Floquet method handles this input): " + averaged_milling);
  // A method that sees runout only through its nonlinear static chip does
  // not see it in its linear mode.
  if (const auto it = options.find("linear"); it != options.end() && std::get_if<bool>(&it->second) &&
      std::get<bool>(it->second) && process.has_runout() && descriptor.accepts.contains(SolverFeature::kRunout))
    notes.push_back("runout (process.runout_um) is ignored with " +
                    std::string(style == ArgStyle::kFlag ? "--linear" : "linear = True") +
                    ": the linear delay equation has no static chip, which is all runout changes");
  return notes;
}

SolverValues with_config_defaults(const SolverDescriptor& descriptor, const Config& config, SolverValues given) {
  for (const SolverOption& o : descriptor.options)
    if (o.name == "feed_per_tooth_mm" && config.feed_mm && !given.count(o.name)) given[o.name] = *config.feed_mm;
  return given;
}

std::unique_ptr<LobeSolver> SolverRecipe::build(const StructuralModel& model, const Process& process,
                                                double depth_max_m) const {
  return make_lobe_solver(method, model, process, depth_max_m, values);
}

ConfiguredSolver configure_solver(const std::string& requested, const Config& config, double depth_max_m,
                                  SolverValues given, ArgStyle style) {
  ConfiguredSolver c;
  std::string averaged_milling;
  c.method = resolve_lobe_method(requested, config.model, config.process, &averaged_milling);
  c.descriptor = &find_lobe_method(c.method);
  c.values = with_config_defaults(*c.descriptor, config, std::move(given));
  c.solver = c.recipe().build(config.model, config.process, depth_max_m);
  c.notes = method_notes(requested, *c.descriptor, config.process, c.values, averaged_milling, style);
  return c;
}

RecordSource record_source(const Config& config, std::optional<double> position_mm) {
  RecordSource s;
  s.config_name = config.name;
  s.config_path = config.source.string();
  s.warnings = config.warnings;
  s.position_mm = position_mm;
  return s;
}

json finite_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json value_json(const SolverValue& v) {
  return std::visit(
      [](const auto& x) -> json {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>) return nullptr;
        else if constexpr (std::is_same_v<T, double>) return finite_or_null(x);
        else return json(x);
      },
      v);
}

std::string value_text(const SolverValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  if (const auto* x = std::get_if<double>(&v)) return table_number(*x);
  if (const auto* i = std::get_if<int>(&v)) return std::to_string(*i);
  if (const auto* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  return "";
}

namespace {

json multiplier_json(const std::complex<double>& mu) { return json::array({mu.real(), mu.imag()}); }

}  // namespace

json point_record(const PointReport& r, const RecordSource& source) {
  const StabilityLimit& lim = r.limit.limit;
  json j;
  j["method"] = r.method;
  j["warnings"] = source.warnings;
  json notes = source.notes;
  for (const std::string& n : r.notes) notes.push_back(n);
  j["notes"] = notes;
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  j["spindle_rpm"] = r.spindle_rpm;
  j["depth_mm"] = r.depth_mm;  // as given
  j["depth_max_mm"] = r.depth_max_m * 1e3;
  j["stable"] = r.stable;
  j["margin"] = finite_or_null(r.margin);
  // The limit: the lobe-table row at this speed.
  j["depth_limit_mm"] = lim.bounded() ? json(lim.depth_limit_m * 1e3) : json(nullptr);
  j["chatter_frequency_hz"] = lim.bounded() ? finite_or_null(lim.chatter_frequency_hz) : json(nullptr);
  j["lobe"] = lim.bounded() && lim.lobe >= 0 ? json(lim.lobe) : json(nullptr);
  for (std::size_t c = 0; c < r.columns.size(); ++c)
    j[r.columns[c].name] = c < r.limit.values.size() ? value_json(r.limit.values[c]) : json(nullptr);
  j["tooth_passing_hz"] = r.tooth_passing_hz;
  j["tooth_period_s"] = r.tooth_period_s;
  // The method's own analysis at the asked depth.
  const PointAnalysis& a = r.at_depth;
  if (a.floquet_period_s) j["floquet_period_s"] = *a.floquet_period_s;
  if (a.spectral_radius) j["spectral_radius"] = finite_or_null(*a.spectral_radius);
  if (a.growth_per_period) j["growth_per_period"] = finite_or_null(*a.growth_per_period);
  if (a.dominant_multiplier) j["dominant_multiplier"] = multiplier_json(*a.dominant_multiplier);
  if (a.dominant_frequency_hz) j["dominant_frequency_hz"] = finite_or_null(*a.dominant_frequency_hz);
  if (a.dominant_multiplier_type) j["dominant_multiplier_type"] = to_string(*a.dominant_multiplier_type);
  for (const auto& [key, value] : a.extra) j[key] = value_json(value);
  // Spindle speed variation (docs/ssv.md): the modulation, the period it was
  // solved over, and the gain over constant speed.
  if (r.speed_variation) {
    const SpeedVariationGain& g = *r.speed_variation;
    j["speed_variation"] = {{"amplitude_ratio", g.asked.amplitude_ratio},
                            {"frequency_ratio", g.asked.frequency_ratio},
                            {"frequency_ratio_used", g.period.frequency_ratio_used},
                            {"exact_period", g.period.exact},
                            {"period_s", g.period.period_s},
                            {"modulation_periods", g.period.modulation_periods},
                            {"floquet_periods", g.period.floquet_periods},
                            {"constant_speed_depth_limit_mm", finite_or_null(g.constant_speed_limit_m * 1e3)},
                            {"gain", finite_or_null(g.gain)}};
  }
  return j;
}

std::vector<int> spectrum_harmonics(const SimulationResult& r) {
  if (r.spectrum_harmonic.size() == r.spectrum_hz.size()) return r.spectrum_harmonic;
  return std::vector<int>(r.spectrum_hz.size(), 0);
}

SimulationRequest simulation_request(const SimulationSettings& settings, const Process& process,
                                     double relative_tolerance, double depth_mm, double feed_mm) {
  SimulationRequest q;
  q.settings = settings;
  q.relative_tolerance = relative_tolerance;
  q.periods_per_revolution = simulation_periods_per_revolution(process, settings.spindle_rpm, settings.linear);
  q.tooth_period_s = process.delay_s(settings.spindle_rpm);
  q.depth_mm = depth_mm;
  q.feed_mm = feed_mm;
  if (process.has_speed_variation()) {
    q.speed_variation = process.speed_variation();
    q.speed_variation_period = speed_variation_period(process, settings.spindle_rpm);
  }
  return q;
}

json simulation_record(const SimulationResult& r, const SimulationRequest& q, const RecordSource& source) {
  const SimulationSettings& st = q.settings;
  json j;
  j["method"] = "time-domain";
  j["config"] = source.config_name;
  j["warnings"] = source.warnings;
  j["notes"] = source.notes;
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  j["spindle_rpm"] = st.spindle_rpm;
  j["depth_mm"] = q.depth_mm;  // as given
  j["feed_per_tooth_mm"] = st.linear ? json(nullptr) : json(q.feed_mm);
  j["linear"] = st.linear;
  j["multiple_regeneration"] = st.multiple_regeneration;
  j["verdict"] = to_string(r.verdict);
  j["stable"] = r.verdict == SimulationVerdict::kStable;
  j["verdict_measure"] = r.verdict_measure;
  j["growth_per_period"] = finite_or_null(r.growth_per_period);
  j["dominant_multiplier"] = std::isfinite(r.growth_per_period) ? multiplier_json(r.dominant_multiplier) : json(nullptr);
  j["chatter_frequency_hz"] = finite_or_null(r.chatter_frequency_hz);
  j["dominant_frequency_hz"] = finite_or_null(r.dominant_nonharmonic_hz);
  j["max_amplitude_mm"] = r.max_amplitude_m * 1e3;
  j["out_of_cut_fraction"] = r.out_of_cut_fraction;
  j["floquet_period_s"] = r.floquet_period_s;  // growth_per_period and the harmonics refer to it
  j["tooth_passing_hz"] = r.tooth_passing_hz;
  j["tooth_period_s"] = q.tooth_period_s;
  j["periods"] = r.periods;
  // (Speed variation: a period of several revolutions, periods_per_revolution 0.)
  j["revolutions"] = q.periods_per_revolution > 0 ? static_cast<double>(r.periods) / q.periods_per_revolution
                                                  : revolutions_in(r.periods * r.floquet_period_s, st.spindle_rpm);
  j["analysed_from_period"] = r.analysed_from_period;
  json harmonics = json::array();
  for (std::size_t k = 0; k < r.harmonics.size() && k < 10; ++k)
    harmonics.push_back({{"harmonic", r.harmonics[k].harmonic},
                         {"frequency_hz", r.harmonics[k].frequency_hz},
                         {"amplitude_um", r.harmonics[k].amplitude_m * 1e6}});
  j["harmonics"] = harmonics;
  if (q.speed_variation) {  // the modulation the run integrated and its principal period (docs/ssv.md)
    const SpeedVariationPeriod& p = q.speed_variation_period;
    j["speed_variation"] = {{"amplitude_ratio", q.speed_variation->amplitude_ratio},
                            {"frequency_ratio", q.speed_variation->frequency_ratio},
                            {"frequency_ratio_used", p.frequency_ratio_used},
                            {"exact_period", p.exact},
                            {"period_s", p.period_s},
                            {"modulation_periods", p.modulation_periods},
                            {"floquet_periods", p.floquet_periods}};
  }
  // What the run measured of the forced vibration, the teeth out of the cut
  // and the linear limit's validity (docs/forced.md).
  if (st.linear_static_chip) j["feed_per_tooth_mm"] = q.feed_mm;
  j["linear_static_chip"] = st.linear_static_chip;
  j["out_of_cut_fraction_per_tooth"] = r.out_of_cut_fraction_per_tooth;
  j["teeth_leave_cut"] = r.teeth_leave_cut;
  j["forced"] = {{"steady", r.forced_steady},
                 {"peak_to_peak_um", {{"x", r.forced_peak_to_peak_x_m * 1e6}, {"y", r.forced_peak_to_peak_y_m * 1e6}}},
                 {"static_deflection_um", {{"x", r.forced_static_x_m * 1e6}, {"y", r.forced_static_y_m * 1e6}}},
                 {"surface_location_error_um", finite_or_null(r.forced_surface_location_error_m * 1e6)}};
  j["linear_limit_warning"] = r.linear_limit_warning.empty() ? json(nullptr) : json(r.linear_limit_warning);
  j["integrator"] = {{"name", "SUNDIALS CVODE, Adams-Moulton order <= 5, fixed-point iteration"},
                     {"relative_tolerance", q.relative_tolerance},
                     {"steps", r.steps},
                     {"rhs_evaluations", r.rhs_evaluations},
                     {"restarts", r.restarts},
                     {"root_stops", r.root_stops},
                     {"samples_per_period", r.samples_per_period},
                     {"history_capacity", r.history_capacity},
                     {"axial_slices", r.axial_slices},
                     {"axial_model", r.axial_slices == 0   ? "exact integral along the helical edge"
                                     : r.axial_slices == 1 ? "one element per tooth"
                                                           : "axial slices"}};
  return j;
}

namespace {

// A series in simulate --out's columns and units.
std::vector<Column> series_columns(const std::vector<SeriesSample>& rows) {
  std::vector<double> t, tx, ty, wx, wy, rx, ry, fx, fy, chip;
  std::vector<bool> in_cut;
  for (const SeriesSample& r : rows) {
    t.push_back(r.t_s);
    tx.push_back(r.tool_x_m * 1e6);
    ty.push_back(r.tool_y_m * 1e6);
    wx.push_back(r.workpiece_x_m * 1e6);
    wy.push_back(r.workpiece_y_m * 1e6);
    rx.push_back(r.rel_x_m * 1e6);
    ry.push_back(r.rel_y_m * 1e6);
    fx.push_back(r.force_x_n);
    fy.push_back(r.force_y_n);
    chip.push_back(r.chip_m * 1e6);
    in_cut.push_back(r.in_cut);
  }
  return {{"time_s", std::move(t)},          {"tool_x_um", std::move(tx)}, {"tool_y_um", std::move(ty)},
          {"workpiece_x_um", std::move(wx)}, {"workpiece_y_um", std::move(wy)}, {"rel_x_um", std::move(rx)},
          {"rel_y_um", std::move(ry)},       {"force_x_n", std::move(fx)}, {"force_y_n", std::move(fy)},
          {"chip_um", std::move(chip)},      {"in_cut", std::move(in_cut)}};
}

}  // namespace

ColumnRecord simulation_columns(const SimulationResult& result, const SimulationRequest& request,
                                const RecordSource& source) {
  ColumnRecord out;
  out.fields = simulation_record(result, request, source);
  out.groups = {{"/series", series_columns(result.series)},
                {"/periodic", series_columns(result.once_per_period)},
                {"/spectrum",
                 {{"frequency_hz", result.spectrum_hz},
                  {"amplitude_um", scaled(result.spectrum_amplitude_m, 1e6)},
                  {"harmonic", spectrum_harmonics(result)}}}};
  return out;
}

}  // namespace chatter
