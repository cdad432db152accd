// The C API (include/chatter/chatter.h): a thin, exception-safe layer over the
// C++ library. Every entry point catches everything; nothing propagates into C.
#include "chatter/chatter.h"
#include "chatter/solvers.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <variant>
#include <exception>
#include <memory>
#include <new>
#include <string>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/operations.hpp"
#include "chatter/position.hpp"
#include "chatter/records.hpp"
#include "chatter/report.hpp"
#include "chatter/transfer_function.hpp"
#include "chatter/usual_bands.hpp"
#include "capi_internal.hpp"

#include <nlohmann/json.hpp>

namespace {

using chatter::capi::fail;
using chatter::capi::guarded;
using chatter::capi::warn_unusual;

// Static storage for a multiplier type's name ("" if unknown).
const char* type_name(const std::string& t) {
  if (t == "hopf") return "hopf";
  if (t == "flip") return "flip";
  if (t == "fold") return "fold";
  return "";
}

chatter_limit to_c(const chatter::StabilityLimit& l) {
  chatter_limit c;
  c.spindle_rpm = l.spindle_rpm;
  c.bounded = l.bounded() ? 1 : 0;
  c.depth_limit_mm = l.bounded() ? l.depth_limit_m * 1e3 : HUGE_VAL;
  c.chatter_frequency_hz = l.bounded() ? l.chatter_frequency_hz : 0.0;
  c.lobe = l.bounded() ? l.lobe : -1;
  return c;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// "name=value,name=value" (a flag: its name alone) as the method's values,
// typed by its options. A name the method does not have goes through as a
// flag, so that make_lobe_solver refuses it with the message every front end
// gives ("unknown option ... (it takes: ...)").
chatter::SolverValues parse_options(const char* text, const chatter::SolverDescriptor& d) {
  chatter::SolverValues values;
  const std::string s = text ? text : "";
  std::size_t pos = 0;
  while (pos < s.size()) {
    std::size_t end = s.find(',', pos);
    if (end == std::string::npos) end = s.size();
    const std::string item = trimmed(s.substr(pos, end - pos));
    pos = end + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    const std::string name = trimmed(item.substr(0, eq));
    const std::string value = eq == std::string::npos ? "" : trimmed(item.substr(eq + 1));
    const chatter::SolverOption* opt = nullptr;
    for (const auto& o : d.options)
      if (o.name == name) opt = &o;
    const std::string where = "chatter_solver_create_with_options: option \"" + name + "\" = \"" + value + "\": ";
    if (!opt) {
      values[name] = true;
      continue;
    }
    char* stop = nullptr;
    switch (opt->kind) {
      case chatter::SolverOption::Kind::kInt: {
        const long v = std::strtol(value.c_str(), &stop, 10);
        if (value.empty() || *stop != '\0' || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
          throw chatter::InputError(where + "must be an integer");
        values[name] = static_cast<int>(v);
        break;
      }
      case chatter::SolverOption::Kind::kReal: {
        const double v = std::strtod(value.c_str(), &stop);
        if (value.empty() || *stop != '\0') throw chatter::InputError(where + "must be a number");
        values[name] = v;
        break;
      }
      case chatter::SolverOption::Kind::kFlag:
        if (!value.empty()) throw chatter::InputError(where + "a flag takes no value: give its name alone");
        values[name] = true;
        break;
    }
  }
  return values;
}

}  // namespace

std::string& chatter::capi::last_error() {
  thread_local std::string message;
  return message;
}

std::vector<std::string>& chatter::capi::last_warnings() {
  thread_local std::vector<std::string> warnings;
  return warnings;
}

void chatter::capi::warn_unusual(const std::vector<std::pair<std::string, double>>& arguments) {
  for (std::string& w : chatter::unusual_arguments(arguments)) last_warnings().push_back(std::move(w));
}

extern "C" {

const char* chatter_version(void) {
  static const std::string v = chatter::version();
  return v.c_str();
}

const char* chatter_last_error(void) { return chatter::capi::last_error().c_str(); }

size_t chatter_last_warning_count(void) { return chatter::capi::last_warnings().size(); }

const char* chatter_last_warning(size_t i) {
  const auto& w = chatter::capi::last_warnings();
  return i < w.size() ? w[i].c_str() : nullptr;
}

chatter_status chatter_model_load(const char* config_path, chatter_model** out) {
  if (!config_path || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_model_load: config_path and out must not be NULL");
  return guarded([&] { *out = new chatter_model{chatter::load_config(config_path)}; });
}

chatter_status chatter_model_parse(const char* toml_text, const char* origin, chatter_model** out) {
  if (!toml_text || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_model_parse: toml_text and out must not be NULL");
  return guarded([&] { *out = new chatter_model{chatter::parse_config(toml_text, origin ? origin : "<text>")}; });
}

void chatter_model_free(chatter_model* model) { delete model; }

size_t chatter_model_warning_count(const chatter_model* model) { return model ? model->config.warnings.size() : 0; }

const char* chatter_model_warning(const chatter_model* model, size_t i) {
  if (!model || i >= model->config.warnings.size()) return nullptr;
  return model->config.warnings[i].c_str();
}

size_t chatter_method_count(void) { return chatter::solver_registry().size(); }

const char* chatter_method_name(size_t i) {
  const auto& r = chatter::solver_registry();
  return i < r.size() ? r[i].name.c_str() : nullptr;
}

chatter_status chatter_solver_create(const chatter_model* model, const char* method, double depth_max_mm,
                                     chatter_solver** out) {
  if (!model || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_solver_create: model and out must not be NULL");
  return guarded([&] {
    if (!(std::isfinite(depth_max_mm) && depth_max_mm > 0.0))
      throw chatter::InputError("chatter_solver_create: depth_max_mm = " + std::to_string(depth_max_mm) +
                                ": must be > 0");
    warn_unusual({{"depth_max_mm", depth_max_mm}});
    const chatter::Config& cfg = model->config;
    // Built as the CLI and Python build it (the config's defaults, e.g. the
    // time-domain chip's feed, and the notes).
    chatter::ConfiguredSolver c = chatter::configure_solver(method ? method : chatter::kAutoMethod, cfg,
                                                            depth_max_mm * 1e-3, {}, chatter::ArgStyle::kKeyword);
    chatter::RecordSource source = chatter::record_source(cfg);
    source.notes = std::move(c.notes);
    *out = new chatter_solver{std::move(c.solver), c.method, cfg.process, std::move(source)};
  });
}

chatter_status chatter_solver_create_with_options(const chatter_model* model, const char* method,
                                                  double depth_max_mm, const char* options, chatter_solver** out) {
  if (!model || !out)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_solver_create_with_options: model and out must not be NULL");
  return guarded([&] {
    if (!(std::isfinite(depth_max_mm) && depth_max_mm > 0.0))
      throw chatter::InputError("chatter_solver_create_with_options: depth_max_mm = " + std::to_string(depth_max_mm) +
                                ": must be > 0");
    warn_unusual({{"depth_max_mm", depth_max_mm}});
    const chatter::Config& cfg = model->config;
    const std::string requested = method ? method : chatter::kAutoMethod;
    const std::string resolved = chatter::resolve_lobe_method(requested, cfg.model, cfg.process);
    chatter::SolverValues given = parse_options(options, chatter::find_lobe_method(resolved));
    chatter::ConfiguredSolver c =
        chatter::configure_solver(requested, cfg, depth_max_mm * 1e-3, std::move(given), chatter::ArgStyle::kKeyword);
    chatter::RecordSource source = chatter::record_source(cfg);
    source.notes = std::move(c.notes);
    *out = new chatter_solver{std::move(c.solver), c.method, cfg.process, std::move(source)};
  });
}

void chatter_solver_free(chatter_solver* solver) { delete solver; }

const char* chatter_solver_method(const chatter_solver* solver) { return solver ? solver->method.c_str() : nullptr; }

chatter_status chatter_point(const chatter_solver* solver, double spindle_rpm, double depth_mm,
                             chatter_point_result* out) {
  if (!solver || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_point: solver and out must not be NULL");
  return guarded([&] {
    chatter::check_spindle_rpm(spindle_rpm, "chatter_point: spindle_rpm");
    chatter::check_depth_mm(depth_mm, "chatter_point: depth_mm");
    warn_unusual({{"rpm", spindle_rpm}, {"depth_mm", depth_mm}});
    const chatter::PointReport r = chatter::report_point(*solver->solver, solver->process, spindle_rpm, depth_mm);
    chatter_point_result c{};
    c.limit = to_c(r.limit.limit);
    c.multiplier_type = "";
    for (std::size_t i = 0; i < r.columns.size() && i < r.limit.values.size(); ++i)
      if (r.columns[i].name == "multiplier_type")
        if (const auto* t = std::get_if<std::string>(&r.limit.values[i])) c.multiplier_type = type_name(*t);
    c.depth_mm = depth_mm;
    c.stable = r.stable ? 1 : 0;
    c.margin = std::isfinite(r.margin) ? r.margin : HUGE_VAL;
    c.tooth_passing_hz = r.tooth_passing_hz;
    c.tooth_period_s = r.tooth_period_s;
    const chatter::PointAnalysis& a = r.at_depth;
    c.floquet_period_s = a.floquet_period_s.value_or(0.0);
    c.spectral_radius = a.spectral_radius.value_or(NAN);
    c.growth_per_period = a.growth_per_period.value_or(NAN);
    c.dominant_multiplier_re = a.dominant_multiplier ? a.dominant_multiplier->real() : NAN;
    c.dominant_multiplier_im = a.dominant_multiplier ? a.dominant_multiplier->imag() : NAN;
    c.dominant_frequency_hz = a.dominant_frequency_hz.value_or(NAN);
    c.dominant_multiplier_type = a.dominant_multiplier_type ? type_name(chatter::to_string(*a.dominant_multiplier_type)) : "";
    *out = c;
  });
}

chatter_status chatter_point_json(const chatter_solver* solver, double spindle_rpm, double depth_mm,
                                  const char** json) {
  if (!solver || !json) return fail(CHATTER_NULL_ARGUMENT, "chatter_point_json: solver and json must not be NULL");
  thread_local std::string text;
  return guarded([&] {
    chatter::check_spindle_rpm(spindle_rpm, "chatter_point_json: spindle_rpm");
    chatter::check_depth_mm(depth_mm, "chatter_point_json: depth_mm");
    warn_unusual({{"rpm", spindle_rpm}, {"depth_mm", depth_mm}});
    const chatter::PointReport r = chatter::report_point(*solver->solver, solver->process, spindle_rpm, depth_mm);
    text = chatter::point_record(r, chatter::capi::with_argument_warnings(solver->source)).dump(2);
    *json = text.c_str();
  });
}

chatter_status chatter_limit_at(const chatter_solver* solver, double spindle_rpm, chatter_limit* out) {
  if (!solver || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_limit_at: solver and out must not be NULL");
  return guarded([&] {
    warn_unusual({{"rpm", spindle_rpm}});
    *out = to_c(solver->solver->limit_at(chatter::SpindleSpeed(spindle_rpm)));
  });
}

chatter_status chatter_lobe_table(const chatter_solver* solver, double rpm_min, double rpm_max, int points,
                                  chatter_limit* rows) {
  if (!solver || !rows) return fail(CHATTER_NULL_ARGUMENT, "chatter_lobe_table: solver and rows must not be NULL");
  return guarded([&] {
    if (points < 2) throw chatter::InputError("chatter_lobe_table: points = " + std::to_string(points) + ": must be >= 2");
    if (!(rpm_max > rpm_min)) throw chatter::InputError("chatter_lobe_table: rpm_max must be > rpm_min");
    warn_unusual({{"rpm_min", rpm_min}, {"rpm_max", rpm_max}, {"rpm_points", points}});
    const auto speeds = chatter::evenly_spaced_speeds(rpm_min, rpm_max, points);
    for (std::size_t i = 0; i < speeds.size(); ++i) rows[i] = to_c(solver->solver->limit_at(chatter::SpindleSpeed(speeds[i])));
  });
}

chatter_status chatter_find_robust_speed(const chatter_solver* solver, double rpm_min, double rpm_max,
                                         double depth_mm, double speed_tolerance_pct,
                                         chatter_robust_speed* out) {
  if (!solver || !out)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_find_robust_speed: solver and out must not be NULL");
  return guarded([&] {
    if (const std::string e = chatter::validate_speed_tolerance(speed_tolerance_pct / 100.0,
                                                                "chatter_find_robust_speed: speed_tolerance_pct");
        !e.empty())
      throw chatter::InputError(e);
    warn_unusual({{"rpm_min", rpm_min}, {"rpm_max", rpm_max}, {"depth_mm", depth_mm},
                  {"speed_tolerance_pct", speed_tolerance_pct}});
    const auto p = chatter::robust_speed(*solver->solver, rpm_min, rpm_max, depth_mm * 1e-3,
                                         speed_tolerance_pct / 100.0);
    chatter_robust_speed r{};
    r.speed_tolerance_pct = speed_tolerance_pct;
    r.found = p ? 1 : 0;
    if (p) {
      r.limit = to_c(p->limit);
      r.worst_limit_mm = std::isfinite(p->worst_limit_m) ? p->worst_limit_m * 1e3 : HUGE_VAL;
      r.worst_margin = std::isfinite(p->worst_margin) ? p->worst_margin : HUGE_VAL;
      r.pocket_min_rpm = p->pocket_min_rpm;
      r.pocket_max_rpm = p->pocket_max_rpm;
    }
    *out = r;
  });
}

chatter_status chatter_model_position_range(const chatter_model* model, double* min_mm, double* max_mm) {
  if (!model || !min_mm || !max_mm)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_model_position_range: model, min_mm and max_mm must not be NULL");
  return guarded([&] {
    // The io layer's message for a config without a position model.
    if (model->config.position.empty()) (void)chatter::position_m(model->config, 0.0, "position_mm");
    const auto [lo, hi] = model->config.position.range_m();
    *min_mm = lo * 1e3;
    *max_mm = hi * 1e3;
  });
}

chatter_status chatter_model_at_position(const chatter_model* model, double position_mm, chatter_model** out) {
  if (!model || !out)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_model_at_position: model and out must not be NULL");
  return guarded([&] {
    *out = new chatter_model{chatter::config_at_position(model->config, position_mm, "position_mm")};
  });
}

chatter_status chatter_lobe_surface(const chatter_model* model, const char* method, double depth_max_mm,
                                    double position_min_mm, double position_max_mm, int position_points,
                                    double rpm_min, double rpm_max, int rpm_points, int threads,
                                    chatter_surface_row* rows) {
  if (!model || !rows) return fail(CHATTER_NULL_ARGUMENT, "chatter_lobe_surface: model and rows must not be NULL");
  return guarded([&] {
    const chatter::Config& cfg = model->config;
    if (!(std::isfinite(depth_max_mm) && depth_max_mm > 0.0))
      throw chatter::InputError("chatter_lobe_surface: depth_max_mm = " + std::to_string(depth_max_mm) +
                                ": must be > 0");
    if (rpm_points < 2)
      throw chatter::InputError("chatter_lobe_surface: rpm_points = " + std::to_string(rpm_points) + ": must be >= 2");
    if (!(std::isfinite(rpm_min) && rpm_min > 0.0 && std::isfinite(rpm_max) && rpm_max > rpm_min))
      throw chatter::InputError("chatter_lobe_surface: rpm_min, rpm_max: must be 0 < rpm_min < rpm_max");
    if (threads < 0 || threads > 1024)
      throw chatter::InputError("chatter_lobe_surface: threads = " + std::to_string(threads) +
                                ": must be in [0, 1024] (0 = every core)");
    // The positions exactly as `chatter surface` places them (io layer).
    const chatter::SurfacePositions pos = chatter::surface_positions(cfg, position_min_mm, position_max_mm,
                                                                     position_points);
    const auto speeds = chatter::evenly_spaced_speeds(rpm_min, rpm_max, rpm_points);
    const std::string m = chatter::resolve_lobe_method(method ? method : chatter::kAutoMethod, cfg.model, cfg.process);
    const chatter::SolverRecipe recipe{m, chatter::with_config_defaults(chatter::find_lobe_method(m), cfg, {})};
    const double depth_max_m = depth_max_mm * 1e-3;
    // The method checked on the first position before the sweep (as the CLI).
    (void)recipe.build(chatter::model_at_position(cfg, pos.m.front()), cfg.process, depth_max_m);
    const chatter::SolverFactory factory = [&](const chatter::StructuralModel& s) {
      return recipe.build(s, cfg.process, depth_max_m);
    };
    const auto surface = chatter::lobe_surface(cfg.model, cfg.position, pos.m, speeds, factory,
                                               static_cast<unsigned>(threads));
    for (std::size_t p = 0; p < surface.size(); ++p)
      for (std::size_t s = 0; s < surface[p].size(); ++s) {
        chatter_surface_row& r = rows[p * speeds.size() + s];
        r.position_mm = pos.mm[p];
        r.limit = to_c(surface[p][s]);
      }
  });
}

}  // extern "C"
