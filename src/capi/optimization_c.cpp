// The C API of the optimisation (chatter.h: chatter_optimizer_*, chatter_performance_json,
// chatter_optimize_json, chatter_adapt_start, chatter_adapt_step), over the same
// library calls and records as `chatter performance|optimize|adapt`.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "capi_internal.hpp"
#include "chatter/optimization.hpp"

struct chatter_optimizer {
  std::unique_ptr<chatter::OptimizationModel> model;
  chatter::RecordSource source;
};

namespace {

using chatter::capi::fail;
using chatter::capi::guarded;

void copy_out(const std::string& text, char* buffer, std::size_t size, std::size_t* length) {
  if (length) *length = text.size();
  if (buffer && size > 0) {
    const std::size_t n = std::min(size - 1, text.size());
    std::memcpy(buffer, text.data(), n);
    buffer[n] = '\0';
  }
}

std::string number(double x) {
  std::string s = std::to_string(x);
  return s;
}

double positive(double x, const char* where, const char* name) {
  if (!(std::isfinite(x) && x > 0.0)) throw chatter::InputError(std::string(where) + name + " = " + number(x) + ": must be > 0");
  return x;
}

// The speed argument in rev/min: cutting speed (m/min) in turning.
// The set point's plausibility, named as the CLI's flags of the operation
// (NaN: not given, the bounds' middle).
void warn_set_point(const chatter::OptimizationModel& m, double speed, double feed_mm, double depth_mm) {
  std::vector<std::pair<std::string, double>> given;
  if (!std::isnan(speed)) given.emplace_back(m.milling() ? "rpm" : "cutting_speed_m_per_min", speed);
  if (!std::isnan(feed_mm)) given.emplace_back(m.milling() ? "feed_per_tooth_mm" : "feed_mm_per_rev", feed_mm);
  if (!std::isnan(depth_mm)) given.emplace_back("depth_mm", depth_mm);
  chatter::capi::warn_unusual(given);
}

double rpm_of(const chatter::OptimizationModel& m, double speed) {
  return m.milling() ? speed : chatter::spindle_rpm_of(m.spec().diameter_m, speed);
}
double speed_of(const chatter::OptimizationModel& m, double rpm) {
  return m.milling() ? rpm : m.cutting_speed_m_per_min(rpm);
}

chatter::IndexValues values_of(const double* v) {
  chatter::IndexValues out = chatter::unknown_indices();
  if (v) std::copy(v, v + chatter::kIndexCount, out.begin());
  return out;
}

chatter::AdaptState state_of(const chatter::OptimizationModel& m, const chatter_adapt_state& s) {
  const char* where = "chatter_adapt_step: state.";
  chatter::AdaptState a;
  a.point = {rpm_of(m, positive(s.speed, where, "speed")), positive(s.feed_mm, where, "feed_mm") * 1e-3,
             positive(s.depth_mm, where, "depth_mm") * 1e-3};
  for (std::size_t i = 0; i < chatter::kIndexCount; ++i)
    a.correction[i] = positive(s.correction[i], where, "correction");
  a.iteration = s.iteration;
  a.loss = s.loss;
  a.converged = s.converged != 0;
  return a;
}

chatter_adapt_state c_state(const chatter::OptimizationModel& m, const chatter::AdaptState& a) {
  chatter_adapt_state s{};
  s.speed = speed_of(m, a.point.spindle_rpm);
  s.feed_mm = a.point.feed_m * 1e3;
  s.depth_mm = a.point.depth_m * 1e3;
  std::copy(a.correction.begin(), a.correction.end(), s.correction);
  s.iteration = a.iteration;
  s.loss = a.loss;
  s.converged = a.converged ? 1 : 0;
  return s;
}

}  // namespace

extern "C" {

chatter_status chatter_optimizer_create(const chatter_model* model, const char* method, double position_mm,
                                        chatter_optimizer** out) {
  if (!model || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_optimizer_create: model and out must not be NULL");
  return guarded([&] {
    const chatter::Config& cfg = model->config;
    if (!cfg.optimization)
      throw chatter::InputError(cfg.source.string() + ": no [optimization] table (docs/config.md, \"Optimization\")");
    chatter::ModelOptions o;
    o.method = method ? method : "auto";
    std::optional<double> at_mm;
    if (!std::isnan(position_mm)) {
      o.position_m = chatter::position_m(cfg, position_mm, "position_mm");
      at_mm = position_mm;
    }
    auto h = std::make_unique<chatter_optimizer>();
    h->model = std::make_unique<chatter::OptimizationModel>(cfg.model, cfg.position, cfg.process, *cfg.optimization, o);
    h->source = chatter::record_source(cfg, at_mm);
    *out = h.release();
  });
}

void chatter_optimizer_free(chatter_optimizer* optimizer) { delete optimizer; }

const char* chatter_optimizer_index_name(const chatter_optimizer* optimizer, size_t i) {
  if (!optimizer || i >= chatter::kIndexCount) return nullptr;
  return chatter::index_name(static_cast<chatter::PerformanceIndex>(i), optimizer->model->operation()).data();
}

chatter_status chatter_performance_json(const chatter_optimizer* optimizer, double speed, double feed_mm,
                                        double depth_mm, const double* measured, char* buffer, size_t size,
                                        size_t* length) {
  if (!optimizer) return fail(CHATTER_NULL_ARGUMENT, "chatter_performance_json: optimizer must not be NULL");
  if (!buffer && size > 0) return fail(CHATTER_NULL_ARGUMENT, "chatter_performance_json: buffer is NULL but size is not 0");
  return guarded([&] {
    const char* where = "chatter_performance_json: ";
    const chatter::OptimizationModel& m = *optimizer->model;
    const chatter::SetPoint p{rpm_of(m, positive(speed, where, "speed")), positive(feed_mm, where, "feed_mm") * 1e-3,
                              positive(depth_mm, where, "depth_mm") * 1e-3};
    warn_set_point(m, speed, feed_mm, depth_mm);
    const chatter::Performance r = m.evaluate(p, chatter::no_corrections(), values_of(measured));
    copy_out(chatter::performance_record(r, m, chatter::capi::with_argument_warnings(optimizer->source)).dump(2), buffer,
             size, length);
  });
}

chatter_status chatter_optimize_json(const chatter_optimizer* optimizer, char* buffer, size_t size, size_t* length) {
  if (!optimizer) return fail(CHATTER_NULL_ARGUMENT, "chatter_optimize_json: optimizer must not be NULL");
  if (!buffer && size > 0) return fail(CHATTER_NULL_ARGUMENT, "chatter_optimize_json: buffer is NULL but size is not 0");
  return guarded([&] {
    const chatter::OptimizationModel& m = *optimizer->model;
    copy_out(chatter::optimize_record(chatter::optimize(m), m, optimizer->source).dump(2), buffer, size, length);
  });
}

chatter_status chatter_adapt_start(const chatter_optimizer* optimizer, double speed, double feed_mm, double depth_mm,
                                   chatter_adapt_state* out) {
  if (!optimizer || !out) return fail(CHATTER_NULL_ARGUMENT, "chatter_adapt_start: optimizer and out must not be NULL");
  return guarded([&] {
    const char* where = "chatter_adapt_start: ";
    const chatter::OptimizationModel& m = *optimizer->model;
    const chatter::OptimizationSpec& s = m.spec();
    chatter::AdaptState a;
    a.point = {std::isnan(speed) ? (s.speed_rpm.lo + s.speed_rpm.hi) / 2.0 : rpm_of(m, positive(speed, where, "speed")),
               std::isnan(feed_mm) ? (s.feed_m.lo + s.feed_m.hi) / 2.0 : positive(feed_mm, where, "feed_mm") * 1e-3,
               std::isnan(depth_mm) ? (s.depth_m.lo + s.depth_m.hi) / 2.0 : positive(depth_mm, where, "depth_mm") * 1e-3};
    warn_set_point(m, speed, feed_mm, depth_mm);
    *out = c_state(m, a);
  });
}

chatter_status chatter_adapt_step(const chatter_optimizer* optimizer, const chatter_adapt_state* state,
                                  const double* measurement, double gamma, double max_step_pct,
                                  chatter_adapt_state* next) {
  if (!optimizer || !state || !measurement || !next)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_adapt_step: optimizer, state, measurement and next must not be NULL");
  return guarded([&] {
    const chatter::OptimizationModel& m = *optimizer->model;
    chatter::AdaptSettings settings = m.spec().adapt;
    if (!std::isnan(gamma)) settings.gamma = gamma;
    if (!std::isnan(max_step_pct)) settings.max_step = max_step_pct / 100.0;
    if (!(settings.gamma > 0.0 && settings.gamma <= 1.0))
      throw chatter::InputError("chatter_adapt_step: gamma = " + number(gamma) + ": must be in (0, 1]");
    if (!(settings.max_step > 0.0 && settings.max_step <= 1.0))
      throw chatter::InputError("chatter_adapt_step: max_step_pct = " + number(max_step_pct) + ": must be in (0, 100]");
    const chatter::AdaptStepResult r = chatter::adapt_step(m, state_of(m, *state), values_of(measurement), settings);
    *next = c_state(m, r.next);
  });
}

}  // extern "C"
