// The cutting law's shared part (include/chatter/cutting_law.hpp): the arc
// of a milling tooth, the integrals over it, the closed-form mean milling
// force, and the choice of implementation (turning_law.cpp, milling_law.cpp)
// for the static side (CuttingLaw) and the regenerative side (RegenerativeCut).
#include "chatter/cutting_law.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "chatter/error.hpp"
#include "cutting_internal.hpp"

namespace chatter {

std::pair<double, double> milling_arc_rad(double radial_immersion, MillingDirection direction) {
  if (direction == MillingDirection::kDown)
    return {std::acos(std::clamp(2.0 * radial_immersion - 1.0, -1.0, 1.0)), std::numbers::pi};
  return {0.0, std::acos(std::clamp(1.0 - 2.0 * radial_immersion, -1.0, 1.0))};
}

ArcIntegrals arc_integrals(double a, double b) {
  ArcIntegrals I;
  I.sin_cos = 0.5 * (std::sin(b) * std::sin(b) - std::sin(a) * std::sin(a));
  I.sin_sq = 0.5 * (b - a) - 0.25 * (std::sin(2 * b) - std::sin(2 * a));
  I.cos = std::sin(b) - std::sin(a);
  I.sin = std::cos(a) - std::cos(b);
  I.width_rad = b - a;
  return I;
}

ArcIntegrals arc_integrals(const std::vector<std::pair<double, double>>& arcs) {
  ArcIntegrals sum = arc_integrals(arcs.front().first, arcs.front().second);
  for (std::size_t k = 1; k < arcs.size(); ++k) {
    const ArcIntegrals I = arc_integrals(arcs[k].first, arcs[k].second);
    sum.sin_cos += I.sin_cos;
    sum.sin_sq += I.sin_sq;
    sum.cos += I.cos;
    sum.sin += I.sin;
    sum.width_rad += I.width_rad;
  }
  return sum;
}

Eigen::Vector2d milling_mean_force_n(int teeth, const ArcIntegrals& I, double f, double a, double kt, double kr,
                                     const EdgeCoefficients& edge) {
  const double c = teeth * a / (2 * std::numbers::pi);
  const double kte = edge.tangential_n_per_m, kre = edge.radial_n_per_m;
  return {c * (-f * (kt * I.sin_cos + kr * I.sin_sq) - (kte * I.cos + kre * I.sin)),
          c * (f * (kt * I.sin_sq - kr * I.sin_cos) + (kte * I.sin - kre * I.cos))};
}

double milling_mean_tangential_force_n(int teeth, const ArcIntegrals& I, double f, double a, double kt,
                                       double kte) {
  const double c = teeth * a / (2 * std::numbers::pi);
  return c * (kt * f * I.sin + kte * I.width_rad);
}

namespace cutting_detail {

void check_point(const CutPoint& p) {
  const std::string where = "cutting law: ";
  if (!(std::isfinite(p.spindle_rpm) && p.spindle_rpm > 0.0)) throw InputError(where + "spindle_rpm must be > 0");
  if (!(std::isfinite(p.depth_m) && p.depth_m >= 0.0)) throw InputError(where + "depth must be >= 0");
  if (!(std::isfinite(p.feed_m) && p.feed_m >= 0.0)) throw InputError(where + "feed must be >= 0");
  if (!std::isnan(p.diameter_m) && !(std::isfinite(p.diameter_m) && p.diameter_m > 0.0))
    throw InputError(where + "diameter must be > 0 (or unknown)");
}

}  // namespace cutting_detail

std::unique_ptr<const CuttingLaw> CuttingLaw::of(const Process& process, const CuttingLawOptions& o) {
  const std::string where = "cutting law: ";
  const double kc = o.turning_tangential_coefficient_n_per_m2;
  if (!(std::isfinite(kc) && kc >= 0.0))
    throw InputError(where + "the turning tangential coefficient K_c must be >= 0 (0 = not given)");
  for (const double k : {o.edge.tangential_n_per_m, o.edge.radial_n_per_m})
    if (!(std::isfinite(k) && k >= 0.0)) throw InputError(where + "edge coefficients must be >= 0 and finite");
  const bool edge = o.edge.tangential_n_per_m > 0.0 || o.edge.radial_n_per_m > 0.0;
  if (process.operation() == Operation::kTurning) {
    if (edge) throw InputError(where + "edge coefficients are a milling law's (turning takes K_c only)");
    if (kc > 0.0 && process.has_size_effect())
      throw InputError(where + std::string(kKienzleTakesTheTangential));
    return cutting_detail::turning_law(process, kc);
  }
  if (edge && process.has_profile())
    throw InputError(where + "edge coefficients with a ball-end, bull-nose or general cutter are not modelled "
                             "(docs/cutter_geometry.md)");
  return cutting_detail::milling_law(process, o.edge);
}

std::unique_ptr<const RegenerativeCut> RegenerativeCut::of(const Process& process, double rpm, double depth_m,
                                                           int helix_slices) {
  const std::string where = "regenerative cut: ";
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(where + "spindle_rpm must be > 0");
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) throw InputError(where + "depth must be >= 0");
  if (helix_slices < 1) throw InputError(where + "helix_slices must be >= 1");
  if (process.operation() == Operation::kTurning) return cutting_detail::turning_cut(process, rpm, depth_m);
  return cutting_detail::milling_cut(process, rpm, depth_m, helix_slices);
}

}  // namespace chatter
