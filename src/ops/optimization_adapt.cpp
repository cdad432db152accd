// The adaptive loop of seed 003 (include/chatter/optimization.hpp, docs/optimization.md):
// adapt_step corrects the models from one measurement and moves the
// set-point toward the corrected optimum; adapt runs it against a plant.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "chatter/error.hpp"
#include "chatter/optimization.hpp"

namespace chatter {

namespace {

// Points tried along the way to the corrected optimum: within the step limit
// (the move lands within 1/32 of the step of where the target is reached),
// and beyond it (to find the far side of an infeasible band).
constexpr int kPointsWithinStep = 32;
constexpr int kPointsBeyondStep = 64;

double range(const Bounds& b) { return b.hi - b.lo; }

// The distance between two set-points in bound ranges (fixed variables do
// not count).
double distance(const OptimizationSpec& s, const SetPoint& a, const SetPoint& b) {
  double d2 = 0.0;
  if (!s.speed_rpm.fixed()) d2 += std::pow((a.spindle_rpm - b.spindle_rpm) / range(s.speed_rpm), 2);
  if (!s.feed_m.fixed()) d2 += std::pow((a.feed_m - b.feed_m) / range(s.feed_m), 2);
  if (!s.depth_m.fixed()) d2 += std::pow((a.depth_m - b.depth_m) / range(s.depth_m), 2);
  return std::sqrt(d2);
}

SetPoint along(const SetPoint& a, const SetPoint& b, double s) {
  if (s >= 1.0) return b;
  return {a.spindle_rpm + s * (b.spindle_rpm - a.spindle_rpm), a.feed_m + s * (b.feed_m - a.feed_m),
          a.depth_m + s * (b.depth_m - a.depth_m)};
}

bool inside(const Bounds& b, double x) { return x >= b.lo && x <= b.hi; }

}  // namespace

AdaptStepResult adapt_step(const OptimizationModel& model, const AdaptState& state, const IndexValues& measurement,
                           const AdaptSettings& settings, const OptimizeOptions& options) {
  if (!(settings.gamma > 0.0 && settings.gamma <= 1.0)) throw InputError("AdaptSettings::gamma: must be in (0, 1]");
  if (!(settings.max_step > 0.0 && settings.max_step <= 1.0))
    throw InputError("AdaptSettings::max_step: must be in (0, 1]");
  const OptimizationSpec& spec = model.spec();
  AdaptStepResult out;
  // 1. Correct each measured index's model: measured / predicted here.
  const Performance uncorrected = model.evaluate(state.point);
  Corrections correction = state.correction;
  for (std::size_t i = 0; i < kIndexCount; ++i)
    if (std::isfinite(measurement[i]) && std::isfinite(uncorrected.model[i]) && uncorrected.model[i] != 0.0)
      correction[i] = measurement[i] / uncorrected.model[i];
  out.measured = model.evaluate(state.point, correction, measurement);

  // 2. The corrected optimum and the relaxed target.
  const Optimum optimum = optimize(model, correction, options);
  out.corrected_optimum = optimum.best;
  out.optimum_found = optimum.found;
  const double here = out.measured.objective;
  out.target = spec.objective == Objective::kLoss && std::isfinite(here)
                   ? std::max(settings.gamma * here, optimum.best.objective)
                   : optimum.best.objective;

  // 3. The move, along the segment to the optimum.
  const SetPoint from = state.point, to = optimum.best.point;
  const double dist = distance(spec, from, to);
  double s_best = 0.0;
  if (optimum.found && dist > 0.0) {
    const double s_max = std::min(1.0, settings.max_step / dist);
    std::vector<double> s;
    for (int k = 1; k <= kPointsWithinStep; ++k) s.push_back(s_max * k / kPointsWithinStep);
    if (s_max < 1.0)
      for (int k = 1; k <= kPointsBeyondStep; ++k) s.push_back(s_max + (1.0 - s_max) * k / kPointsBeyondStep);
    const IndexValues none = unknown_indices();
    std::vector<Performance> tried;
    for (const double sk : s) tried.push_back(model.evaluate(along(from, to, sk), correction, none));
    const std::size_t within = kPointsWithinStep;
    auto pick = [&](auto&& accept, std::size_t lo, std::size_t hi) -> std::optional<std::size_t> {
      for (std::size_t k = lo; k < std::min(hi, s.size()); ++k)
        if (tried[k].feasible && accept(tried[k])) return k;
      return std::nullopt;
    };
    std::optional<std::size_t> k;
    if (!out.measured.feasible) {
      // Leave an infeasible set-point at once, for the first feasible point.
      k = pick([](const Performance&) { return true; }, 0, s.size());
    } else {
      k = pick([&](const Performance& r) { return r.objective <= out.target; }, 0, within);
      if (!k) {
        // Not reachable within the step: the best improvement within it.
        for (std::size_t j = 0; j < within; ++j)
          if (tried[j].feasible && tried[j].objective < here && (!k || tried[j].objective < tried[*k].objective)) k = j;
      }
      // Nothing within the step improves: an infeasible band on the way;
      // jump to its far side.
      if (!k) k = pick([&](const Performance& r) { return r.objective < here; }, within, s.size());
    }
    if (k) s_best = s[*k];
  }
  out.next.point = s_best > 0.0 ? along(from, to, s_best) : from;
  out.step = distance(spec, from, out.next.point);
  out.next.correction = correction;
  out.next.iteration = state.iteration + 1;
  out.next.loss = out.measured.loss;
  out.next.converged = out.step < kAdaptConvergedStep;
  return out;
}

PlantBias parse_plant_bias(const std::string& s, Operation op) {
  const auto eq = s.find('='), at = s.find('@');
  const std::string rule = s + ": must be INDEX=PERCENT@ITERATION (INDEX: all or one of " + index_names(op) +
                           "; e.g. all=5@15)";
  if (eq == std::string::npos || at == std::string::npos || at < eq) throw InputError(rule);
  PlantBias b;
  const std::string name = s.substr(0, eq);
  if (name != "all") {
    b.index = index_from_name(name, op);
    if (!b.index) throw InputError(rule);
  }
  const std::string pct = s.substr(eq + 1, at - eq - 1), it = s.substr(at + 1);
  std::size_t u1 = 0, u2 = 0;
  try {
    b.fraction = std::stod(pct, &u1) / 100.0;
    b.from_iteration = std::stoi(it, &u2);
  } catch (const std::logic_error&) {
    throw InputError(rule);
  }
  if (u1 != pct.size() || u2 != it.size()) throw InputError(rule);
  if (!(std::isfinite(b.fraction) && b.fraction > -1.0) || b.from_iteration < 1)
    throw InputError(s + ": the percent must be > -100 and the iteration >= 1");
  return b;
}

AdaptRun adapt(const OptimizationModel& model, const AdaptPlan& plan, const AdaptSettings& settings,
               const OptimizeOptions& options) {
  const OptimizationSpec& spec = model.spec();
  if (plan.iterations < 1) throw InputError("AdaptPlan::iterations = " + std::to_string(plan.iterations) + ": must be >= 1");
  if (!plan.biases.empty() && !plan.measurements.empty())
    throw InputError("AdaptPlan: biases are for the simulated plant, not with measurements");
  for (const PlantBias& b : plan.biases)
    if (!(std::isfinite(b.fraction) && b.fraction > -1.0) || b.from_iteration < 1)
      throw InputError("AdaptPlan: a bias must be > -100 % from an iteration >= 1");
  AdaptState state;
  if (plan.start) {
    const SetPoint& p = *plan.start;
    if (!inside(spec.speed_rpm, p.spindle_rpm) || !inside(spec.feed_m, p.feed_m) || !inside(spec.depth_m, p.depth_m))
      throw InputError("AdaptPlan::start: outside the optimisation bounds");
    state.point = p;
  } else {
    state.point = {(spec.speed_rpm.lo + spec.speed_rpm.hi) / 2.0, (spec.feed_m.lo + spec.feed_m.hi) / 2.0,
                   (spec.depth_m.lo + spec.depth_m.hi) / 2.0};
  }
  AdaptRun run;
  run.reference = optimize(model, no_corrections(), options);
  for (int it = 1; it <= plan.iterations; ++it) {
    IndexValues measured = unknown_indices();
    if (!plan.measurements.empty()) {
      if (static_cast<std::size_t>(it) > plan.measurements.size()) break;
      measured = plan.measurements[static_cast<std::size_t>(it - 1)];
    } else {
      const Performance truth = model.evaluate(state.point);
      for (std::size_t i = 0; i < kIndexCount; ++i) {
        double factor = 1.0;
        for (const PlantBias& b : plan.biases)
          if (it >= b.from_iteration && (!b.index || static_cast<std::size_t>(*b.index) == i)) factor *= 1.0 + b.fraction;
        measured[i] = truth.model[i] * factor;
      }
    }
    const AdaptStepResult step = adapt_step(model, state, measured, settings, options);
    run.rows.push_back({it, step.measured, step.target, step.step});
    state = step.next;
  }
  run.final_state = state;
  return run;
}

}  // namespace chatter
