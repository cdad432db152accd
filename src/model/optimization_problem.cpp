// The optimisation problem's closed forms (include/chatter/optimization_problem.hpp):
// index names, the loss and its coefficients, roughness, tool life, cost and
// production rate (docs/optimization.md; seed 003 eq. 0.2–0.9 and 1.13–1.18).
#include "chatter/optimization_problem.hpp"

#include "chatter/cutting_law.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace chatter {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string_view name_of(PerformanceIndex i, bool milling) {
  switch (i) {
    case PerformanceIndex::kDimensionalError: return milling ? "surface_location_error_um" : "diametral_error_um";
    case PerformanceIndex::kRoughness: return "surface_roughness_um";
    case PerformanceIndex::kRemovalRate: return "removal_rate_mm3_per_s";
    case PerformanceIndex::kCost: return "cost";
    case PerformanceIndex::kProductionRate: return "production_rate_per_h";
    case PerformanceIndex::kForce: return "force_n";
  }
  return "?";
}

}  // namespace

IndexValues unknown_indices() {
  IndexValues v;
  v.fill(kNaN);
  return v;
}

std::string_view index_name(PerformanceIndex index, Operation operation) {
  return name_of(index, operation == Operation::kMilling);
}

std::optional<PerformanceIndex> index_from_name(std::string_view name, Operation operation) {
  for (std::size_t i = 0; i < kIndexCount; ++i) {
    const auto index = static_cast<PerformanceIndex>(i);
    if (index_name(index, operation) == name) return index;
  }
  return std::nullopt;
}

std::string index_names(Operation operation) {
  std::string out;
  for (std::size_t i = 0; i < kIndexCount; ++i)
    out += (i ? ", " : "") + std::string(index_name(static_cast<PerformanceIndex>(i), operation));
  return out;
}

Sense index_sense(PerformanceIndex index) {
  return index == PerformanceIndex::kRemovalRate || index == PerformanceIndex::kProductionRate
             ? Sense::kLargerIsBetter
             : Sense::kSmallerIsBetter;
}

std::string_view sense_name(Sense sense) { return sense == Sense::kSmallerIsBetter ? "max" : "min"; }

std::string_view objective_name(Objective objective) {
  switch (objective) {
    case Objective::kLoss: return "loss";
    case Objective::kRemovalRate: return "removal_rate";
    case Objective::kCost: return "cost";
    case Objective::kProductionRate: return "production_rate";
  }
  return "?";
}

std::array<double, kLossIndexCount> loss_alpha(const LossSpec& spec) {
  std::array<double, kLossIndexCount> alpha{};
  for (std::size_t i = 0; i < kLossIndexCount; ++i) {
    const double beta = spec.weight[i];
    if (!(beta > 0.0)) continue;
    const double xc = spec.critical[i];
    alpha[i] = index_sense(static_cast<PerformanceIndex>(i)) == Sense::kSmallerIsBetter
                   ? beta * spec.critical_loss / (xc * xc)
                   : beta * spec.critical_loss * xc;
  }
  return alpha;
}

double loss_term(PerformanceIndex index, double alpha, double value) {
  if (alpha == 0.0) return 0.0;
  if (std::isnan(value)) return kNaN;
  if (index_sense(index) == Sense::kSmallerIsBetter) return alpha * value * value;
  return value > 0.0 ? alpha / value : std::numeric_limits<double>::infinity();
}

double RoughnessModel::roughness_um(double v, double feed_m, double depth_m) const {
  const double f = feed_m * 1e3, d = depth_m * 1e3;  // mm
  if (kind == Kind::kGeometric) return f * f / (32.0 * nose_radius_m * 1e3) * 1e3;  // mm -> µm
  const double ra = c0 + cv * v + cf * f + cd * d + cvv * v * v + cff * f * f + cdd * d * d + cvf * v * f +
                    cvd * v * d + cfd * f * d;
  return std::max(ra, 0.0);
}

OperationEconomics operation_economics(const Economics& e, double v, double feed_per_rev_m, double rpm) {
  OperationEconomics o;
  o.tool_life_min = std::pow(e.taylor_c_m_per_min / v, 1.0 / e.taylor_n);
  o.cutting_time_min = e.cut_length_mm / (feed_per_rev_m * 1e3 * rpm);
  const double wear = o.cutting_time_min / o.tool_life_min;  // tools worn per part
  o.operation_time_min = e.index_time_min + e.approach_time_min + o.cutting_time_min + wear * e.tool_change_time_min;
  const double per_tool = e.tool_cost / e.tool_uses +
                          e.tooling_rate_per_h / 60.0 * (e.sharpening_time_min + e.preset_time_min);
  o.cost = e.machine_rate_per_h / 60.0 * o.operation_time_min + wear * per_tool;
  o.production_rate_per_h = 60.0 / (e.setup_time_min + o.operation_time_min);
  return o;
}

std::string OptimizationSpec::validate(const Process& process) const {
  const Operation operation = process.operation();
  const std::string w = "OptimizationSpec::";
  auto bounds = [&](const Bounds& b, const char* name) -> std::string {
    if (!(std::isfinite(b.lo) && std::isfinite(b.hi) && b.lo > 0.0))
      return w + name + ": lo = " + std::to_string(b.lo) + ": must be finite and > 0";
    if (!(b.hi >= b.lo)) return w + name + ": hi = " + std::to_string(b.hi) + ": must be >= lo";
    return {};
  };
  for (const auto& [b, name] : {std::pair{&speed_rpm, "speed_rpm"}, {&feed_m, "feed_m"}, {&depth_m, "depth_m"}})
    if (std::string e = bounds(*b, name); !e.empty()) return e;
  if (!(std::isfinite(diameter_m) && diameter_m > 0.0)) return w + "diameter_m: must be > 0";
  if (!(position_points >= 2)) return w + "position_points: must be >= 2";
  if (!(adapt.gamma > 0.0 && adapt.gamma <= 1.0)) return w + "adapt.gamma: must be in (0, 1]";
  if (!(adapt.max_step > 0.0 && adapt.max_step <= 1.0)) return w + "adapt.max_step: must be in (0, 1]";
  if (!(constraints.stability_margin >= 1.0)) return w + "constraints.stability_margin: must be >= 1";
  double sum = 0.0;
  for (std::size_t i = 0; i < kLossIndexCount; ++i) {
    const std::string name(index_name(static_cast<PerformanceIndex>(i), operation));
    if (!(loss.weight[i] >= 0.0 && loss.weight[i] <= 1.0)) return w + "loss.weight[" + name + "]: must be in [0, 1]";
    if (loss.weight[i] > 0.0 && !(std::isfinite(loss.critical[i]) && loss.critical[i] > 0.0))
      return w + "loss.critical[" + name + "]: must be > 0 (its weight is > 0)";
    sum += loss.weight[i];
  }
  if (objective == Objective::kLoss) {
    if (!(std::abs(sum - 1.0) <= 1e-9)) return w + "loss.weight: must sum to 1";
    if (!(std::isfinite(loss.critical_loss) && loss.critical_loss > 0.0)) return w + "loss.critical_loss: must be > 0";
  }
  const auto weighted = [&](PerformanceIndex i) { return loss.weight[static_cast<std::size_t>(i)] > 0.0; };
  if (!roughness && (weighted(PerformanceIndex::kRoughness) || constraints.max_roughness_um))
    return w + "roughness: needed by the roughness weight or limit";
  if (roughness && roughness->kind == RoughnessModel::Kind::kGeometric && !(roughness->nose_radius_m > 0.0))
    return w + "roughness.nose_radius_m: must be > 0";
  const bool money = weighted(PerformanceIndex::kCost) || weighted(PerformanceIndex::kProductionRate) ||
                     constraints.max_cost || constraints.min_production_rate_per_h || objective == Objective::kCost ||
                     objective == Objective::kProductionRate;
  if (money && !economics) return w + "economics: needed by the cost or production rate (weight, limit or objective)";
  if (economics) {
    const Economics& e = *economics;
    if (!(e.taylor_c_m_per_min > 0.0)) return w + "economics.taylor_c_m_per_min: must be > 0";
    if (!(e.taylor_n > 0.0 && e.taylor_n < 1.0)) return w + "economics.taylor_n: must be in (0, 1)";
    if (!(e.cut_length_mm > 0.0)) return w + "economics.cut_length_mm: must be > 0";
    if (!(e.tool_uses >= 1.0)) return w + "economics.tool_uses: must be >= 1";
    for (const double x : {e.setup_time_min, e.index_time_min, e.approach_time_min, e.tool_change_time_min,
                           e.machine_rate_per_h, e.tool_cost, e.tooling_rate_per_h, e.sharpening_time_min,
                           e.preset_time_min})
      if (!(std::isfinite(x) && x >= 0.0)) return w + "economics: times, rates and costs must be >= 0";
  }
  const bool load_limit = constraints.max_force_n || constraints.max_power_w || constraints.max_torque_n_m;
  if (operation == Operation::kTurning && process.has_size_effect() && cutting_coefficient_n_per_m2 > 0.0)
    return w + "cutting_coefficient_n_per_m2: " + kKienzleTakesTheTangential;
  if (operation == Operation::kTurning && !process.has_size_effect() && load_limit && !(cutting_coefficient_n_per_m2 > 0.0))
    return w + "cutting_coefficient_n_per_m2: needed by a force, power or torque limit (turning)";
  return {};
}

double cutting_speed_m_per_min(double diameter_m, double spindle_rpm) {
  return std::numbers::pi * diameter_m * spindle_rpm;
}

double spindle_rpm_of(double diameter_m, double cutting_speed) {
  return cutting_speed / (std::numbers::pi * diameter_m);
}

}  // namespace chatter
