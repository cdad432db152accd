// First-order semi-discretisation (Insperger & Stépán 2004) of the periodic
// delay equation of docs/physics.md §3, the `sdm` solver: options, the
// solver class, the Floquet analysis at a point and the spectral-radius map.
// See include/chatter/semi_discretization.hpp for the method, docs/sdm.md
// for the convergence study, and sdm_internal.hpp for where each part lives
// (grid, maps, multipliers, Floquet analysis, depth search).
#include "chatter/semi_discretization.hpp"

#include "sdm_internal.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include "chatter/error.hpp"

namespace chatter {
using namespace sdm_detail;

std::string to_string(MultiplierType t) {
  switch (t) {
    case MultiplierType::kHopf: return "hopf";
    case MultiplierType::kFlip: return "flip";
    case MultiplierType::kFold: return "fold";
  }
  return "hopf";
}

std::string SemiDiscretizationOptions::validate() const {
  std::ostringstream os;
  if (steps_per_period < 1)
    os << "steps_per_period = " << steps_per_period << ": must be >= 1";
  else if (steps_per_vibration_cycle < 1)
    os << "steps_per_vibration_cycle = " << steps_per_vibration_cycle << ": must be >= 1";
  else if (max_steps_per_period < 1)
    os << "max_steps_per_period = " << max_steps_per_period << ": must be >= 1";
  else if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    os << "depth_max_m = " << depth_max_m << ": must be > 0 and finite";
  else if (!(depth_tolerance > 0.0 && depth_tolerance < 0.1))
    os << "depth_tolerance = " << depth_tolerance << ": must be in (0, 0.1)";
  else if (!(bracket_ratio > 1.0 && bracket_ratio <= 10.0))
    os << "bracket_ratio = " << bracket_ratio << ": must be in (1, 10]";
  else if (!(bracket_min_ratio > 1.0 && bracket_min_ratio <= bracket_ratio))
    os << "bracket_min_ratio = " << bracket_min_ratio << ": must be in (1, bracket_ratio]";
  else if (bracket_steps < 1)
    os << "bracket_steps = " << bracket_steps << ": must be >= 1";
  else if (dense_max_dimension < 1)
    os << "dense_max_dimension = " << dense_max_dimension << ": must be >= 1";
  else if (krylov_dimension < 4 || krylov_dimension > 400)
    os << "krylov_dimension = " << krylov_dimension << ": must be in [4, 400]";
  else if (axial_slices < 1)
    os << "axial_slices = " << axial_slices << ": must be >= 1";
  else if ((collocation_nodes < 0 && collocation_nodes != kAutoCollocation) || collocation_nodes > kMaxCollocationNodes)
    os << "collocation_nodes = " << collocation_nodes << ": must be in [0, " << kMaxCollocationNodes
       << "] or kAutoCollocation (" << kAutoCollocation << ")";
  return os.str();
}

SemiDiscretizationSolver::SemiDiscretizationSolver(StructuralModel model, Process process,
                                                   SemiDiscretizationOptions options)
    : model_(std::move(model)), process_(std::move(process)), options_(options) {
  if (const std::string e = options_.validate(); !e.empty()) throw InputError("sdm options: " + e);
  options_ = resolved_collocation(options_, process_);
  if (const std::string e = collocation_refusal(process_, options_); !e.empty()) throw InputError(e);
  if (model_.mode_count() == 0)
    throw InputError("structural model: both bodies are rigid: give at least one mode");
  if (model_.has_measured())
    throw InputError("sdm needs modes, not measured FRFs: fit modes to the measurement first (chatter fit) "
                     "or use the analytic method");
  SdmStateSpace ss = state_space(model_, process_, options_.general_cutter_path);
  A_ = std::move(ss.A);
  B_ = std::move(ss.B);
  Wx_ = std::move(ss.Wx);
  U_ = std::move(ss.U);
  Sv_ = std::move(ss.Sv);
  f_max_hz_ = ss.f_max_hz;
  slowest_decay_per_s_ = ss.slowest_decay_per_s;
  free_poles_ = std::move(ss.free_poles);
}

FloquetResult SemiDiscretizationSolver::analyse(double rpm, double depth_m) const {
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  const Grid g = period_grid(process_, options_, f_max_hz_, slowest_decay_per_s_, rpm, A_, B_, Wx_, U_, Sv_);
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  PeriodMap pm;
  kernel.build_map(g, depth_m, pm);
  return floquet_of(kernel, g, pm, rpm, depth_m, A_, Wx_, f_max_hz_);
}

std::optional<bool> SemiDiscretizationSolver::stable_at(SpindleSpeed speed, double depth_m) const {
  const double rpm = speed.rpm();
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  if (Wx_.rows() == 0) return true;  // the process cannot see any mode
  const Grid g = period_grid(process_, options_, f_max_hz_, slowest_decay_per_s_, rpm, A_, B_, Wx_, U_, Sv_);
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  PeriodMap pm;
  kernel.build_map(g, depth_m, pm);
  // The converged dominant multiplier, not the early-stopped verdict of the
  // depth climb: with many vibration cycles per period the map is far from
  // normal, and a Ritz value with a small residual can lie outside the unit
  // circle while every multiplier lies inside (case C at 100 rev/min).
  return std::abs(kernel.dominant(pm, false).mu) < 1.0;
}

std::vector<double> SemiDiscretizationSolver::spectral_radius_map(const std::vector<double>& rpms,
                                                                  const std::vector<double>& depths_m) const {
  for (double d : depths_m)
    if (!(std::isfinite(d) && d >= 0.0)) throw InputError("stability map: depths must be >= 0 and finite");
  std::vector<double> out;
  out.reserve(rpms.size() * depths_m.size());
  const SdmKernel kernel(A_, B_, Wx_, U_, options_, &process_, &Sv_);
  PeriodMap pm;
  for (double rpm : rpms) {
    if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(bad_speed(rpm));
    const Grid g = period_grid(process_, options_, f_max_hz_, slowest_decay_per_s_, rpm, A_, B_, Wx_, U_, Sv_);
    for (double d : depths_m) {
      kernel.build_map(g, d, pm);
      out.push_back(std::abs(kernel.dominant(pm, false).mu));
    }
  }
  return out;
}

}  // namespace chatter
