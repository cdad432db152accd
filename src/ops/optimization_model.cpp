// The forward models of the optimisation (include/chatter/optimization.hpp):
// one set-point's indices, loss, constraints and stability margin.
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "chatter/cutting_force.hpp"
#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"
#include "chatter/optimization.hpp"
#include "chatter/solvers.hpp"
#include "chatter/number_text.hpp"

namespace chatter {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// The lobe solvers search to this many times the deepest cut the bounds
// allow, times the stability margin: a limit above it is reported +inf and
// satisfies the constraint anyway.
constexpr double kDepthSearchFactor = 2.0;

std::string number(double x) { return number_text(x, 6); }

// The positions evaluated over a part: a cantilever's clamp is rigid (the
// workpiece does not move there), so position_points from L/n to L; stations
// from the first to the last.
std::vector<double> part_positions(const PositionDependence& dep, int points) {
  const auto [lo, hi] = dep.range_m();
  std::vector<double> x;
  if (!dep.cantilever.empty()) {
    for (int i = 1; i <= points; ++i) x.push_back(i == points ? hi : lo + (hi - lo) * i / points);
    return x;
  }
  return evenly_spaced_positions(lo, hi, points);
}

}  // namespace

Corrections no_corrections() {
  Corrections c;
  c.fill(1.0);
  return c;
}

OptimizationModel::OptimizationModel(const StructuralModel& base, const PositionDependence& dependence,
                                     const Process& process, OptimizationSpec spec, ModelOptions options)
    : spec_(std::move(spec)), process_(process), threads_(options.threads) {
  if (const std::string why = spec_.validate(process_); !why.empty()) throw InputError("optimization: " + why);
  if (options.position_m) {
    models_.push_back(dependence.empty() ? base : model_at_position(base, dependence, *options.position_m));
    if (!dependence.empty()) positions_m_.push_back(*options.position_m);
    position_given_ = true;
  } else if (!dependence.empty()) {
    positions_m_ = part_positions(dependence, spec_.position_points);
    for (const double x : positions_m_) models_.push_back(model_at_position(base, dependence, x));
  } else {
    models_.push_back(base);
  }
  alpha_ = loss_alpha(spec_.loss);
  depth_search_m_ = kDepthSearchFactor * spec_.depth_m.hi * spec_.constraints.stability_margin;
  if (spec_.constraints.stability) {
    std::string warning;
    method_ = resolve_lobe_method(options.method, models_.front(), process_, &warning);
    if (!warning.empty()) notes_.push_back(warning);
    for (const std::string& n : ignored_feature_notes(find_lobe_method(method_), process_)) notes_.push_back(n);
    (void)solvers_at(0.0);  // the method's refusals now, not at the first set-point
  }
  if (milling()) {
    ForcedOptions fo;
    fo.sdm.depth_max_m = depth_search_m_;
    for (const StructuralModel& m : models_) forced_.push_back(std::make_unique<ForcedResponseSolver>(m, process_, fo));
  }
}

double OptimizationModel::cutting_speed_m_per_min(double rpm) const {
  return chatter::cutting_speed_m_per_min(spec_.diameter_m, rpm);
}

const std::vector<std::unique_ptr<LobeSolver>>& OptimizationModel::solvers_at(double feed_m) const {
  const double key = feed_key(feed_m);
  const std::lock_guard lock(cache_mutex_);
  auto it = solvers_.find(key);
  if (it == solvers_.end()) {
    std::vector<std::unique_ptr<LobeSolver>> built;
    const Process process = key > 0.0 ? process_.at_feed(key) : process_;
    for (const StructuralModel& m : models_) built.push_back(make_lobe_solver(method_, m, process, depth_search_m_));
    it = solvers_.emplace(key, std::move(built)).first;
  }
  return it->second;  // a map's nodes stay where they are
}

std::pair<double, std::size_t> OptimizationModel::depth_limit_m(double rpm, double feed_m) const {
  if (!spec_.constraints.stability) return {kNaN, 0};
  // The orthogonal cut without process damping: the characteristic equation
  // holds a and K_f only as their product (1 + a K_f (1 − e^{−iωτ}) G_xx = 0,
  // every method), so the limit at another feed's tangent K_f is the
  // process's limit scaled by their ratio, at the same frequency: one solve
  // per speed, not per (speed, feed) (tests/test_kienzle.cpp checks the
  // ratio on analytic and sdm solves).
  if (feed_key(feed_m) > 0.0 && process_.orthogonal_turning() && !process_.has_process_damping() &&
      !process_.has_speed_variation()) {
    const auto [base, where] = depth_limit_m(rpm, process_.turning_parameters().kienzle->feed_m);
    const double ratio = process_.turning_parameters().feed_force_coefficient_n_per_m2 /
                         process_.at_feed(feed_m).turning_parameters().feed_force_coefficient_n_per_m2;
    // None below the searched depth says nothing below it × ratio < 1: solve then.
    if (std::isfinite(base) || ratio >= 1.0) return {base * ratio, where};
  }
  const auto key = std::pair{feed_key(feed_m), rpm};
  {
    const std::lock_guard lock(cache_mutex_);
    if (const auto it = limit_cache_.find(key); it != limit_cache_.end()) return it->second;
  }
  const auto& solvers = solvers_at(feed_m);
  double best = kInf;
  std::size_t where = 0;
  for (std::size_t i = 0; i < solvers.size(); ++i) {
    const StabilityLimit l = solvers[i]->limit_at(SpindleSpeed(rpm));
    const double d = l.bounded() ? l.depth_limit_m : kInf;
    if (d < best) best = d, where = i;
  }
  const std::lock_guard lock(cache_mutex_);
  limit_cache_.emplace(key, std::pair{best, where});
  return {best, where};
}

double OptimizationModel::sle_um(std::size_t position, const SetPoint& p) const {
  const ForcedResponseSolver& solver = *forced_[position];
  auto response_at = [&](double feed_m) {
    ForcedSettings st;
    st.spindle_rpm = p.spindle_rpm;
    st.depth_m = p.depth_m;
    st.feed_m = feed_m;
    st.record_path = false;
    const ForcedResponse r = solver.response(st);
    return r.stable ? r.surface_location_error_m : kNaN;
  };
  // With runout the wall offset between teeth adds a feed-free term: solve at
  // the feed itself. Without, the response is the static force's, linear in
  // the feed: one solve per (position, speed, depth) at a reference feed.
  if (process_.has_runout()) return std::abs(response_at(p.feed_m)) * 1e6;
  const auto key = std::tuple{position, p.spindle_rpm, p.depth_m};
  double per_feed = kNaN;
  bool cached = false;
  {
    const std::lock_guard lock(cache_mutex_);
    if (const auto it = sle_cache_.find(key); it != sle_cache_.end()) per_feed = it->second, cached = true;
  }
  if (!cached) {
    const double reference = spec_.feed_m.hi;
    per_feed = response_at(reference) / reference;
    const std::lock_guard lock(cache_mutex_);
    sle_cache_.emplace(key, per_feed);
  }
  return std::abs(per_feed * p.feed_m) * 1e6;
}

double OptimizationModel::dimensional_error_um(const SetPoint& p, double* worst_position_m) const {
  double worst = -1.0;
  std::size_t where = 0;
  for (std::size_t i = 0; i < models_.size(); ++i) {
    const double e = milling() ? sle_um(i, p)
                               : static_deflection_turning(models_[i], process_, p.depth_m, p.feed_m).diametral_error_m *
                                     1e6;
    if (std::isnan(e)) {
      *worst_position_m = positions_m_.empty() ? kNaN : positions_m_[i];
      return kNaN;  // an unstable milling cut: no forced response
    }
    if (e > worst) worst = e, where = i;
  }
  *worst_position_m = positions_m_.empty() ? kNaN : positions_m_[where];
  return worst;
}

Performance OptimizationModel::evaluate(const SetPoint& p, const Corrections& correction,
                                        const IndexValues& measured) const {
  for (const auto& [x, name] : {std::pair{p.spindle_rpm, "spindle_rpm"}, {p.feed_m, "feed"}, {p.depth_m, "depth"}})
    if (!(std::isfinite(x) && x > 0.0)) throw InputError(std::string("set-point: ") + name + " = " + number(x) + ": must be > 0");
  const bool mill = milling();
  Performance r;
  r.point = p;
  const double v = cutting_speed_m_per_min(p.spindle_rpm);
  r.cutting_speed_m_per_min = v;
  IndexValues& m = r.model;
  m = unknown_indices();
  // The removal rate of the cutting law (chatter/cutting_law.hpp), mm³/s.
  m[2] = CuttingLaw::of(process_)->mean(CutPoint{p.spindle_rpm, p.depth_m, p.feed_m, spec_.diameter_m})
             .removal_rate_m3_per_s * 1e9;
  m[0] = dimensional_error_um(p, &r.worst_error_position_m);
  if (spec_.roughness) m[1] = spec_.roughness->roughness_um(v, p.feed_m, p.depth_m);
  const double feed_per_rev_m = mill ? p.feed_m * process_.teeth() : p.feed_m;
  if (spec_.economics) {
    r.economics = operation_economics(*spec_.economics, v, feed_per_rev_m, p.spindle_rpm);
    m[3] = r.economics->cost;
    m[4] = r.economics->production_rate_per_h;
  }
  r.power_w = r.torque_n_m = kNaN;
  if (mill || spec_.cutting_coefficient_n_per_m2 > 0.0 || process_.has_size_effect()) {
    const CuttingLoad load = cutting_load(process_, p.spindle_rpm, p.depth_m, p.feed_m, spec_.diameter_m,
                                          spec_.cutting_coefficient_n_per_m2);
    m[5] = load.force_n;
    // The force's correction applies to power and torque: the same
    // cutting coefficients give all three.
    r.power_w = load.power_w * correction[5];
    r.torque_n_m = load.torque_n_m * correction[5];
  }
  for (std::size_t i = 0; i < kIndexCount; ++i) {
    m[i] *= correction[i];
    r.measured[i] = std::isfinite(measured[i]);
    r.value[i] = r.measured[i] ? measured[i] : m[i];
  }

  r.depth_limit_m = r.weakest_position_m = r.stability_margin = kNaN;
  if (spec_.constraints.stability) {
    std::size_t where = 0;
    std::tie(r.depth_limit_m, where) = depth_limit_m(p.spindle_rpm, p.feed_m);
    if (!positions_m_.empty()) r.weakest_position_m = positions_m_[where];
    r.stability_margin = r.depth_limit_m / p.depth_m;
    // No limit below the searched depth proves the margin only up to it: a
    // depth beyond the search over the margin is not judged (NaN: fails).
    if (std::isinf(r.depth_limit_m) && p.depth_m * spec_.constraints.stability_margin > depth_search_m_)
      r.stability_margin = kNaN;
  }

  r.loss = 0.0;
  for (std::size_t i = 0; i < kLossIndexCount; ++i) {
    r.loss_terms[i] = loss_term(static_cast<PerformanceIndex>(i), alpha_[i], r.value[i]);
    r.loss += r.loss_terms[i];
  }
  switch (spec_.objective) {
    case Objective::kLoss: r.objective = r.loss; break;
    case Objective::kRemovalRate: r.objective = -r.value[2]; break;
    case Objective::kCost: r.objective = r.value[3]; break;
    case Objective::kProductionRate: r.objective = -r.value[4]; break;
  }

  const ConstraintLimits& c = spec_.constraints;
  const std::string dim = mill ? "max_surface_location_error_um" : "max_diametral_error_um";
  auto at_most = [&](const std::optional<double>& limit, const std::string& name, double value, double scale) {
    if (limit) r.constraints.push_back({name, value, *limit * scale, value <= *limit * scale});
  };
  auto at_least = [&](const std::optional<double>& limit, const std::string& name, double value) {
    if (limit) r.constraints.push_back({name, value, *limit, value >= *limit});
  };
  at_most(c.max_force_n, "max_force_n", r.value[5], 1.0);
  at_most(c.max_power_w, "max_power_kw", r.power_w * 1e-3, 1e-3);
  at_most(c.max_torque_n_m, "max_torque_nm", r.torque_n_m, 1.0);
  at_most(c.max_dimensional_error_um, dim, r.value[0], 1.0);
  at_most(c.max_roughness_um, "max_roughness_um", r.value[1], 1.0);
  at_least(c.min_removal_rate_mm3_per_s, "min_removal_rate_mm3_per_s", r.value[2]);
  at_most(c.max_cost, "max_cost", r.value[3], 1.0);
  at_least(c.min_production_rate_per_h, "min_production_rate_per_h", r.value[4]);
  if (c.stability)
    r.constraints.push_back({"stability_margin", r.stability_margin, c.stability_margin,
                             r.stability_margin >= c.stability_margin});
  r.feasible = std::isfinite(r.objective) &&
               std::all_of(r.constraints.begin(), r.constraints.end(), [](const ConstraintCheck& k) { return k.ok; });
  return r;
}

}  // namespace chatter
