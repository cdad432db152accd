// The forced response of a cutter whose motion repeats only once per
// revolution (variable pitch or helix, runout, process damping): one linear
// periodic solve on the sdm grid (docs/physics.md §11, docs/forced.md).
//
// The real-cutter map of sdm over one revolution (the general path: step
// boundaries on every engagement event, exact step averages of H, delayed
// values interpolated in the stored samples) advances the state y = [x(0);
// z_{−1} … z_{−L}] by y ↦ Φ y. With the static chip the step equation gains
// a force F̄_i held at its exact step average,
//   F̄_i = −(1/h) Σ_j ∫∫ [H₁(φ_j) (f_j, 0)ᵀ + (ρ_j − ρ_{j−1}) v(φ_j)] dz dt
// (Process::tooth_force_integral, tooth_force_direction_integral), entering
// as x_{i+1} += G_i F̄_i with G_i = ∫₀ʰ e^{Ã s} ds B: the map becomes y ↦
// Φ y + r, and the periodic response solves (I − Φ) y = r (dense LU; Φ
// formed column by column from the step maps). Error O(h²), as sdm's.
#include "forced_internal.hpp"
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <unsupported/Eigen/MatrixFunctions>

#include "chatter/error.hpp"

namespace chatter::forced_detail {

using namespace sdm_detail;

SampledPath::SampledPath(std::vector<double> t, std::vector<Eigen::Vector2d> r, std::vector<Eigen::Vector2d> v)
    : t_(std::move(t)), r_(std::move(r)), v_(std::move(v)) {
  period_ = t_.back();
}

Eigen::Vector2d SampledPath::at(double t) const {
  double s = std::fmod(t, period_);
  if (s < 0.0) s += period_;
  std::size_t k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), s) - t_.begin());
  k = std::clamp<std::size_t>(k, 1, t_.size() - 1) - 1;
  const double h = t_[k + 1] - t_[k];
  const double u = (s - t_[k]) / h, u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  return h00 * r_[k] + h10 * h * v_[k] + h01 * r_[k + 1] + h11 * h * v_[k + 1];
}

Eigen::Vector2d SampledPath::mean() const {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k + 1 < t_.size(); ++k) {
    const double h = t_[k + 1] - t_[k];
    sum += 0.5 * h * (r_[k] + r_[k + 1]) + h * h / 12.0 * (v_[k] - v_[k + 1]);
  }
  return sum / period_;
}

PathSource periodic_response(const StructuralModel& model, const Process& process,
                             const SemiDiscretizationOptions& options, double rpm, double depth_m, double feed_m,
                             double* residual) {
  const SdmStateSpace ss = state_space(model, process);
  SemiDiscretizationOptions o = options;
  o.general_cutter_path = true;  // one revolution, one delay per tooth, whatever the cutter
  const Grid g = make_grid(process, o, ss.f_max_hz, rpm, turning_hhat_of(process), ss.A, ss.B, ss.U, ss.Sv);
  const SdmKernel kernel(ss.A, ss.B, ss.Wx, ss.U, o, &process, &ss.Sv);
  PeriodMap pm;
  pm.cm.forcing = true;
  kernel.build_map(g, depth_m, pm);
  const int n2 = pm.n2, nt = process.teeth();
  // The static chip force of each cutting step, held at its step average.
  std::vector<double> feed(static_cast<std::size_t>(nt)), offset(static_cast<std::size_t>(nt));
  for (int j = 0; j < nt; ++j) {
    feed[static_cast<std::size_t>(j)] = process.feed_of_tooth_m(j, feed_m);
    offset[static_cast<std::size_t>(j)] = process.runout_m(j) - process.runout_m((j + nt - 1) % nt);
  }
  PathSource out;
  Eigen::Vector2d impulse = Eigen::Vector2d::Zero();  // ∫ F dt over the period
  CutterMap& cm = pm.cm;
  for (std::size_t i = 0; i < cm.steps.size(); ++i) {
    CutterStep& st = cm.steps[i];
    if (st.free || st.G.size() == 0) continue;
    Eigen::Vector2d F = Eigen::Vector2d::Zero();
    for (int j = 0; j < nt; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      F -= process.tooth_force_integral(j, cm.t[i], cm.t[i + 1], depth_m, rpm) * Eigen::Vector2d(feed[ju], 0.0);
      if (offset[ju] != 0.0)
        F -= offset[ju] * process.tooth_force_direction_integral(j, cm.t[i], cm.t[i + 1], depth_m, rpm);
    }
    impulse += F;
    st.gF = st.G * (F / st.h);
  }
  out.mean_force_n = impulse / g.tau;
  // (I − Φ) y = r.
  const int d = pm.dim;
  MatrixXd Phi(d, d);
  VectorXd e = VectorXd::Zero(d), r(d), y(d), again(d);
  for (int j = 0; j < d; ++j) {
    e.setZero();
    e(j) = 1.0;
    SdmKernel::apply_cutter(pm, ss.Wx, e.data(), Phi.col(j).data(), nullptr, false);
  }
  e.setZero();
  SdmKernel::apply_cutter(pm, ss.Wx, e.data(), r.data(), nullptr, true);
  const MatrixXd I_minus_Phi = MatrixXd::Identity(d, d) - Phi;
  y = I_minus_Phi.partialPivLu().solve(r);
  std::vector<double> rec;
  SdmKernel::apply_cutter(pm, ss.Wx, y.data(), again.data(), &rec, true);
  if (residual) *residual = (again - y).norm() / std::max(y.norm(), 1e-300);
  // Knots: every step boundary; a free step (exact free vibration) is
  // split into pieces no longer than the cutting steps.
  std::vector<double> t;
  std::vector<Eigen::Vector2d> rr, vv;
  auto push = [&](double time, const VectorXd& x) {
    t.push_back(time);
    rr.push_back(ss.Sr * x);
    vv.push_back(ss.Sv * x);
  };
  for (std::size_t i = 0; i < cm.steps.size(); ++i) {
    const VectorXd x = Eigen::Map<const VectorXd>(rec.data() + i * static_cast<std::size_t>(n2), n2);
    const CutterStep& st = cm.steps[i];
    const int pieces = st.free ? std::max(1, static_cast<int>(std::ceil(st.h / g.h_target - 1e-9))) : 1;
    if (pieces == 1) {
      push(cm.t[i], x);
      continue;
    }
    const MatrixXd E = (ss.A * (st.h / pieces)).exp();
    VectorXd xs = x;
    for (int p = 0; p < pieces; ++p) {
      push(cm.t[i] + st.h * p / pieces, xs);
      xs = E * xs;
    }
  }
  push(g.tau, Eigen::Map<const VectorXd>(rec.data() + cm.steps.size() * static_cast<std::size_t>(n2), n2));
  out.path = std::make_unique<SampledPath>(std::move(t), std::move(rr), std::move(vv));
  return out;
}

}  // namespace chatter::forced_detail
