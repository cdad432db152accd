// The records of performance, optimize and adapt (chatter/records.hpp): the
// same JSON for `chatter performance|optimize|adapt --json`, Python's
// chatter.performance / optimize / adapt / adapt_step and the C API. Keys and
// their meaning: docs/results.md, "Optimisation".
#include <cmath>

#include <nlohmann/json.hpp>

#include "chatter/io/table_writer.hpp"  // version()
#include "chatter/records.hpp"

namespace chatter {

using nlohmann::json;

namespace {

std::string index_key(const OptimizationModel& m, std::size_t i) {
  return std::string(index_name(static_cast<PerformanceIndex>(i), m.operation()));
}

std::string feed_key(const OptimizationModel& m) { return std::string(m.process().feed_record_key()); }

json mm_or_null(double m) { return finite_or_null(m * 1e3); }

json set_point_json(const SetPoint& p, const OptimizationModel& m) {
  return {{"spindle_rpm", p.spindle_rpm},
          {"cutting_speed_m_per_min", m.cutting_speed_m_per_min(p.spindle_rpm)},
          {feed_key(m), p.feed_m * 1e3},
          {"depth_mm", p.depth_m * 1e3}};
}

json bounds_json(const Bounds& b, double scale) {
  return b.fixed() ? json(b.lo * scale) : json::array({b.lo * scale, b.hi * scale});
}

// What every optimisation record says about its inputs.
void head(json& j, const char* format, const OptimizationModel& m, const RecordSource& source) {
  j["format"] = format;
  j["version"] = version();
  j["config"] = source.config_path;
  if (source.position_mm) j["position_mm"] = *source.position_mm;
  json positions = json::array();
  for (const double x : m.positions_m()) positions.push_back(x * 1e3);
  j["positions_evaluated_mm"] = positions;
  j["operation"] = m.process().operation_name();
  j["objective"] = std::string(objective_name(m.spec().objective));
  j["method"] = m.method().empty() ? json(nullptr) : json(m.method());
  j["warnings"] = source.warnings;
  json notes = source.notes;
  for (const std::string& n : m.notes()) notes.push_back(n);
  j["notes"] = notes;
}

}  // namespace

json performance_json(const Performance& p, const OptimizationModel& m) {
  json j = set_point_json(p.point, m);
  json measured = json::array(), predicted, alpha, terms, critical, sense;
  for (std::size_t i = 0; i < kIndexCount; ++i) {
    const std::string key = index_key(m, i);
    j[key] = finite_or_null(p.value[i]);
    predicted[key] = finite_or_null(p.model[i]);
    if (p.measured[i]) measured.push_back(key);
  }
  const LossSpec& loss = m.spec().loss;
  for (std::size_t i = 0; i < kLossIndexCount; ++i) {
    const std::string key = index_key(m, i);
    alpha[key] = m.alpha()[i];
    terms[key] = finite_or_null(p.loss_terms[i]);
    critical[key] = finite_or_null(loss.critical[i]);
    sense[key] = std::string(sense_name(index_sense(static_cast<PerformanceIndex>(i))));
  }
  j["measured"] = measured;
  j["predicted"] = predicted;
  j["alpha"] = alpha;
  j["critical"] = critical;
  j["sense"] = sense;
  j["critical_loss"] = loss.critical_loss;
  j["loss_terms"] = terms;
  j["loss"] = finite_or_null(p.loss);
  json constraints = json::array();
  for (const ConstraintCheck& c : p.constraints)
    constraints.push_back({{"name", c.name}, {"value", finite_or_null(c.value)}, {"limit", c.limit}, {"ok", c.ok}});
  j["constraints"] = constraints;
  j["feasible"] = p.feasible;
  // Stability: null when not evaluated (stability = false); the margin is
  // null (unbounded) when no limit lies below the searched depth.
  const bool stability = m.spec().constraints.stability;
  j["stability_margin"] = stability ? finite_or_null(p.stability_margin) : json(nullptr);
  j["depth_limit_mm"] = stability ? mm_or_null(p.depth_limit_m) : json(nullptr);
  j["depth_searched_mm"] = stability ? json(m.depth_search_m() * 1e3) : json(nullptr);
  j["weakest_position_mm"] = mm_or_null(p.weakest_position_m);
  j["worst_error_position_mm"] = mm_or_null(p.worst_error_position_m);
  j["power_kw"] = finite_or_null(p.power_w * 1e-3);
  j["torque_nm"] = finite_or_null(p.torque_n_m);
  j["tool_life_min"] = p.economics ? finite_or_null(p.economics->tool_life_min) : json(nullptr);
  j["cutting_time_min"] = p.economics ? finite_or_null(p.economics->cutting_time_min) : json(nullptr);
  return j;
}

json performance_record(const Performance& p, const OptimizationModel& m, const RecordSource& source) {
  json j;
  head(j, "chatter-performance", m, source);
  j.update(performance_json(p, m));
  return j;
}

json optimize_record(const Optimum& o, const OptimizationModel& m, const RecordSource& source) {
  json j;
  head(j, "chatter-optimize", m, source);
  const OptimizationSpec& s = m.spec();
  j["bounds"] = {{"spindle_rpm", bounds_json(s.speed_rpm, 1.0)},
                 {"cutting_speed_m_per_min", bounds_json(Bounds{m.cutting_speed_m_per_min(s.speed_rpm.lo),
                                                                m.cutting_speed_m_per_min(s.speed_rpm.hi)},
                                                         1.0)},
                 {feed_key(m), bounds_json(s.feed_m, 1e3)},
                 {"depth_mm", bounds_json(s.depth_m, 1e3)}};
  j["stability"] = s.constraints.stability;
  j["stability_margin_required"] = s.constraints.stability ? json(s.constraints.stability_margin) : json(nullptr);
  j["found"] = o.found;
  j["binding"] = o.binding;
  j["evaluations"] = o.evaluations;
  j["candidates_polished"] = o.candidates_polished;
  j["optimum"] = performance_json(o.best, m);
  return j;
}

json adapt_state_json(const AdaptState& s, const OptimizationModel& m) {
  json j = set_point_json(s.point, m);
  json corr;
  for (std::size_t i = 0; i < kIndexCount; ++i) corr[index_key(m, i)] = s.correction[i];
  j["correction"] = corr;
  j["iteration"] = s.iteration;
  j["loss"] = finite_or_null(s.loss);
  j["converged"] = s.converged;
  return j;
}

json adapt_step_record(const AdaptStepResult& r, const OptimizationModel& m) {
  json j;
  j["format"] = "chatter-adapt-step";
  j["version"] = version();
  j["state"] = adapt_state_json(r.next, m);
  j["next"] = set_point_json(r.next.point, m);
  j["measured"] = performance_json(r.measured, m);
  j["optimum_found"] = r.optimum_found;
  j["corrected_optimum"] = performance_json(r.corrected_optimum, m);
  j["target"] = finite_or_null(r.target);
  j["step"] = r.step;
  return j;
}

json adapt_record(const AdaptRun& run, const OptimizationModel& m, const AdaptRecordInputs& in,
                  const RecordSource& source) {
  json j;
  head(j, "chatter-adapt", m, source);
  j["gamma"] = in.settings->gamma;
  j["max_step_percent"] = in.settings->max_step * 100.0;
  j["measurements_file"] = in.measurements_origin.empty() ? json(nullptr) : json(in.measurements_origin);
  json biases = json::array();
  for (const PlantBias& b : in.plan->biases)
    biases.push_back({{"index", b.index ? json(index_key(m, static_cast<std::size_t>(*b.index))) : json("all")},
                      {"percent", b.fraction * 100.0},
                      {"from_iteration", b.from_iteration}});
  j["biases"] = biases;
  json rows = json::array();
  for (const AdaptRow& r : run.rows) {
    json row = {{"iteration", r.iteration}};
    row.update(set_point_json(r.measured.point, m));
    row["loss"] = finite_or_null(r.measured.loss);
    for (std::size_t i = 0; i < kIndexCount; ++i) row[index_key(m, i)] = finite_or_null(r.measured.value[i]);
    row["stability_margin"] = m.spec().constraints.stability ? finite_or_null(r.measured.stability_margin) : json(nullptr);
    row["feasible"] = r.measured.feasible;
    row["target"] = finite_or_null(r.target);
    row["step"] = r.step;
    rows.push_back(row);
  }
  j["rows"] = rows;
  j["final_state"] = adapt_state_json(run.final_state, m);
  j["reference_found"] = run.reference.found;
  j["reference_optimum"] = performance_json(run.reference.best, m);
  return j;
}

std::string adapt_table_csv(const json& record) {
  const Operation op = operation_named(record.at("operation").get<std::string>());
  std::vector<std::string> columns = {"iteration", "cutting_speed_m_per_min", "spindle_rpm",
                                      std::string(feed_record_key(op)),
                                      "depth_mm", "loss"};
  for (std::size_t i = 0; i < kIndexCount; ++i) columns.emplace_back(index_name(static_cast<PerformanceIndex>(i), op));
  for (const char* c : {"stability_margin", "feasible", "target", "step"}) columns.emplace_back(c);
  std::string out;
  for (std::size_t c = 0; c < columns.size(); ++c) out += (c ? "," : "") + columns[c];
  out += '\n';
  for (const json& row : record.at("rows")) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c) out += ',';
      const json& v = row.at(columns[c]);
      if (!v.is_null()) out += v.dump();
    }
    out += '\n';
  }
  return out;
}

}  // namespace chatter
