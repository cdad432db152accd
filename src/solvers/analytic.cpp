// Transfer-function lobes from the eigenvalues of H₀G(jω) (docs/physics.md §4),
// and the behaviour shared with the coupled solver.
#include <cmath>
#include <numbers>
#include <sstream>

#include <Eigen/LU>

#include "chatter/error.hpp"
#include "chatter/transfer_function.hpp"
#include "chatter/solvers.hpp"
#include "multi_delay.hpp"
#include "phase_search.hpp"
#include "roots.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

double wrap_2pi(double x) {  // into [0, 2π)
  x = std::fmod(x, kTwoPi);
  return x < 0.0 ? x + kTwoPi : x;
}

// Nose radius (chord_limit_at): the depth iteration starts this far
// (relative to depth_max) above 0, stops when F(a) = a to this relative
// tolerance, after at most so many frozen solvers.
constexpr double kChordStartDepth = 1e-9;
constexpr double kChordDepthTolerance = 1e-12;
constexpr int kMaxChordIterations = 200;

detail::BranchValue from_eigenvalue(Complex lambda) {
  // 1 + a(1 − e^{−jωτ})λ = 0 with a real: a = −1/(2 Re λ), ωτ = 3π + 2ψ + 2πk.
  return {lambda, -2.0 * lambda.real(), wrap_2pi(3.0 * kPi + 2.0 * std::arg(lambda))};
}

}  // namespace

std::string TransferFunctionOptions::validate() const {
  std::ostringstream os;
  if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    os << "depth_max_m = " << depth_max_m << ": must be > 0 and finite";
  else if (!(std::isfinite(max_phase_step_rad) && max_phase_step_rad > 0.0 && max_phase_step_rad <= 0.5))
    os << "max_phase_step_rad = " << max_phase_step_rad << ": must be in (0, 0.5]";
  return os.str();
}

TransferFunctionSolver::TransferFunctionSolver(StructuralModel model, Process process,
                                               TransferFunctionOptions options)
    : model_(std::move(model)), process_(std::move(process)), options_(options) {
  if (const std::string e = options_.validate(); !e.empty())
    throw InputError("transfer-function options: " + e);
  if (model_.rigid())
    throw InputError("structural model: both bodies are rigid: give at least one mode or measured FRF");
  // A nose radius: H depends on the depth; H₀ here is H at depth_max, whose
  // a·H bounds a·H(a) for every a <= depth_max (the chord grows with a). A
  // cutter profile (docs/cutter_geometry.md): H₀(a) at depth_max likewise;
  // the limit comes from the same iteration over frozen depths.
  H0_ = process_.has_nose_radius()          ? process_.turning_matrix(options_.depth_max_m)
        : process_.depth_dependent_force() ? process_.average_directional_matrix_at(options_.depth_max_m)
                                            : process_.average_directional_matrix();
  chord_iteration_ = process_.depth_dependent_force();
  if (chord_iteration_ && process_.has_profile() && process_.has_variable_helix())
    throw InputError("the averaged methods do not handle a variable helix on a ball-end, bull-nose or general "
                     "cutter (the delays vary along the curved edge): use sdm or time-domain");
}

TransferFunctionSolver::~TransferFunctionSolver() = default;

void TransferFunctionSolver::build_search(int branches) {
  const auto [lo, hi] = detail::search_band(model_, H0_, options_.depth_max_m);
  detail::PhaseSearchOptions po;
  po.max_phase_step_rad = options_.max_phase_step_rad;
  search_ = std::make_unique<detail::PhaseSearch>(
      [this](double w, std::array<detail::BranchValue, 2>& out) { evaluate(w, out); }, branches, lo, hi,
      options_.depth_max_m, po);
}

void TransferFunctionSolver::build_general_search() {
  general_ = std::make_unique<detail::MultiDelaySearch>(
      model_, process_, detail::MultiDelayOptions{options_.depth_max_m, options_.max_phase_step_rad});
}

StabilityLimit TransferFunctionSolver::limit_at(SpindleSpeed speed) const {
  const double rpm = speed.rpm();
  if (!(std::isfinite(rpm) && rpm > 0.0)) {
    std::ostringstream os;
    os << "spindle speed " << rpm << " rev/min: must be > 0";
    throw InputError(os.str());
  }
  if (chord_iteration_) return chord_limit_at(rpm);
  if (general_) {
    try {
      return general_->limit_at(rpm);
    } catch (const InputError& e) {
      std::ostringstream os;
      os << "spindle speed " << rpm << " rev/min: " << e.what();
      throw InputError(os.str());
    }
  }
  detail::PhaseRoot r;
  try {
    r = search_->lowest_root(process_.delay_s(rpm));
  } catch (const InputError& e) {
    std::ostringstream os;
    os << "spindle speed " << rpm << " rev/min: " << e.what();
    throw InputError(os.str());
  }
  StabilityLimit lim;
  lim.spindle_rpm = rpm;
  if (std::isfinite(r.depth_m)) {
    lim.depth_limit_m = r.depth_m;
    lim.chatter_frequency_hz = r.omega / kTwoPi;
    lim.lobe = r.lobe;
    lim.branch = r.branch;
  }
  return lim;
}

// Turning with a nose radius (docs/turning_inserts.md), or a milling cutter
// profile (docs/cutter_geometry.md, H₀(a) averaged over the slices of depth
// a): the cut at depth a is the frozen process at_depth(a), so the boundary is the
// smallest a with F(a) <= a, F(a) the limit of this method for the frozen
// chord. h(a) = F(a) − a > 0 near a = 0 (F ~ sqrt(a) there: the chord turns
// towards the feed as sin κ_eq = sqrt(a/2r_ε)). March up with the fixed-point
// step a → F(a), never shorter than the step before, until h <= 0 brackets
// the root; then Brent's method on h (the variable helix's iteration,
// multi_delay.cpp). A root where h jumps between lobes is the jump depth.
StabilityLimit TransferFunctionSolver::chord_limit_at(double rpm) const {
  const double depth_max = options_.depth_max_m;
  auto limit_with = [&](double a) { return with_process(process_.at_depth(a))->limit_at(SpindleSpeed(rpm)); };
  auto h_of = [&](const StabilityLimit& l, double a) {
    return (l.bounded() ? l.depth_limit_m : depth_max + 1.0) - a;  // finite, > 0 when unbounded
  };
  double lo = 0.0, h_lo = 0.0, hi = 0.0, h_hi = 0.0, stride = 0.0;
  double a = kChordStartDepth * depth_max;
  bool bracketed = false;
  for (int it = 0; it < kMaxChordIterations && !bracketed; ++it) {
    const StabilityLimit l = limit_with(a);
    const double h = h_of(l, a);
    if (l.bounded() && std::abs(h) <= kChordDepthTolerance * l.depth_limit_m) return l;
    if (h <= 0.0) {
      hi = a;
      h_hi = h;
      bracketed = true;
      break;
    }
    if (a >= depth_max) return StabilityLimit{rpm};  // no self-consistent limit below depth_max
    lo = a;
    h_lo = h;
    stride = std::max(stride, std::min(h, depth_max - a));
    a = std::min(depth_max, a + stride);
  }
  if (!bracketed)
    throw NumericalError((process_.has_profile() ? "cutter profile at " : "nose radius at ") + std::to_string(rpm) +
                         " rev/min: the depth iteration over the frozen depths did not converge");
  if (lo == 0.0) return limit_with(hi);  // unstable at the smallest depth tried
  const double root =
      detail::brent_root([&](double x) { return h_of(limit_with(x), x); }, lo, hi, h_lo, h_hi, kChordDepthTolerance * hi);
  StabilityLimit l = limit_with(root);
  if (!l.bounded() || l.depth_limit_m > root) l = limit_with(std::min(hi, root * (1.0 + 4.0 * kChordDepthTolerance)));
  if (l.bounded()) l.depth_limit_m = std::min(l.depth_limit_m, root);
  return l;
}

std::vector<LobeCurve> TransferFunctionSolver::lobe_curves(SpindleSpeed from, SpindleSpeed to) const {
  const double rpm_min = from.rpm(), rpm_max = to.rpm();
  if (!(rpm_min > 0.0 && rpm_max >= rpm_min)) throw InputError("lobe curves: need 0 < rpm_min <= rpm_max");
  std::vector<LobeCurve> out;
  if (general_ || chord_iteration_) return out;
  for (const auto& c : search_->curves(process_.delay_s(rpm_max), process_.delay_s(rpm_min))) {
    LobeCurve lc{c.lobe, c.branch, {}};
    lc.points.reserve(c.points.size());
    for (const auto& p : c.points) lc.points.push_back({process_.rpm_from_delay(p.tau_s), p.depth_m, p.omega / kTwoPi});
    out.push_back(std::move(lc));
  }
  return out;
}

std::optional<AbsoluteLimit> TransferFunctionSolver::known_absolute_limit() const {
  if (general_ || chord_iteration_) return std::nullopt;
  return absolute_limit();
}

AbsoluteLimit TransferFunctionSolver::absolute_limit() const {
  if (chord_iteration_)
    throw InputError(process_.has_profile()
                         ? "absolute limit: not defined for a ball-end, bull-nose or general cutter (the averaged "
                           "force changes with the depth); use limit_at"
                         : "absolute limit: not defined for a turning insert with a nose radius (the direction of the "
                           "cut changes with the depth); use limit_at");
  if (general_)
    throw InputError("absolute limit: not defined with variable pitch or helix or process damping (the limit "
                     "depends on the speed beyond the lobe phase); use limit_at");
  const detail::PhaseRoot r = search_->minimum_depth();
  AbsoluteLimit a;
  if (std::isfinite(r.depth_m)) {
    a.depth_m = r.depth_m;
    a.chatter_frequency_hz = r.omega / kTwoPi;
    a.branch = r.branch;
  }
  return a;
}

SearchBand TransferFunctionSolver::band() const {
  if (chord_iteration_) return with_process(process_.at_depth(options_.depth_max_m))->band();
  if (general_) return {general_->omega_lo(), general_->omega_hi(), general_->grid_size()};
  return {search_->omega_lo(), search_->omega_hi(), search_->grid_size()};
}

std::unique_ptr<TransferFunctionSolver> AnalyticSolver::with_process(Process process) const {
  return std::make_unique<AnalyticSolver>(model_, std::move(process), options_);
}

AnalyticSolver::AnalyticSolver(StructuralModel model, Process process, TransferFunctionOptions options)
    : TransferFunctionSolver(std::move(model), std::move(process), options) {
  if (chord_iteration_) return;  // per speed over frozen chords (chord_limit_at)
  // Variable pitch or helix, or process damping: the general per-speed search
  // (the uniform cutter keeps the phase search below, unchanged).
  if (process_.has_variable_pitch() || process_.has_variable_helix() || process_.has_process_damping()) {
    build_general_search();
    return;
  }
  // H₀G has rank one when H₀ does (turning) or when every mode acts along one
  // line; then its only non-zero eigenvalue is its trace.
  const double h2 = H0_.squaredNorm();
  bool parallel = true;
  Eigen::Vector2d u0 = Eigen::Vector2d::Zero();
  for (const Body* b : {&model_.tool, &model_.workpiece})
    for (const Mode& m : b->modes) {
      if (u0.isZero()) u0 = m.direction;
      if (std::abs(u0.x() * m.direction.y() - u0.y() * m.direction.x()) > 1e-12) parallel = false;
    }
  if (model_.has_measured()) parallel = false;  // measured terms may couple x and y
  rank_one_ = std::abs(H0_.determinant()) <= 1e-12 * h2 || parallel;
  build_search(rank_one_ ? 1 : 2);
}

std::array<Complex, 2> AnalyticSolver::eigenvalues(double omega) const {
  return detail::eigenvalues_2x2(H0_.cast<Complex>() * model_.receptance(omega));
}

void AnalyticSolver::evaluate(double omega, std::array<detail::BranchValue, 2>& out) const {
  if (rank_one_) {
    const Matrix2c M = H0_.cast<Complex>() * model_.receptance(omega);
    out[0] = from_eigenvalue(M.trace());
    return;
  }
  const auto l = eigenvalues(omega);
  out[0] = from_eigenvalue(l[0]);
  out[1] = from_eigenvalue(l[1]);
}

std::unique_ptr<TransferFunctionSolver> make_transfer_function_solver(const std::string& method,
                                                                      const StructuralModel& model,
                                                                      const Process& process,
                                                                      const TransferFunctionOptions& options) {
  // Through the registry: the method must be one of its transfer-function
  // (averaged) methods, which all take max_phase_step_rad.
  const SolverDescriptor& d = find_lobe_method(method);
  if (d.kind != SolverKind::kAveraged)
    throw InputError("method \"" + method + "\": not a transfer-function method");
  auto s = make_lobe_solver(method, model, process, options.depth_max_m,
                            {{"max_phase_step_rad", options.max_phase_step_rad}});
  return std::unique_ptr<TransferFunctionSolver>(static_cast<TransferFunctionSolver*>(s.release()));
}

}  // namespace chatter
