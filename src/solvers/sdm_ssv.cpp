// Spindle speed variation in the `sdm` solver (docs/ssv.md): the step grid
// of the principal period with the time-varying delay. Part of the `sdm`
// solver (sdm_internal.hpp).
//
// Method: first-order semi-discretisation with a time-varying delay
// (Insperger & Stépán 2004, turning; Seguy et al. 2010, milling). The
// period is the principal period of speed_variation_period, p T_m = q T_F
// (T_F: one revolution in turning, the Floquet period of the cutter in
// milling). On each step the present
// state is solved exactly and the delayed value z(t − τ(t)) is the straight
// line between its values at the step's ends, t_i − τ(t_i) and t_{i+1} −
// τ(t_{i+1}), each interpolated linearly between the stored samples — the
// same first-order rule as the constant-delay real-cutter path, which builds
// and applies the maps (SdmKernel::cutter_map, apply_cutter).
//
// Turning: equal steps, a whole number per revolution, all with the same map
// (built once per depth); at R_VA = 0 the samples and delays are exactly
// those of the constant-speed solver, so its limit comes back.
// Collocation (sdm_cutter_collocation.cpp; the default for turning with a
// sharp edge and for real cutters, as at constant speed): H at each node
// from the cut at the node's mean-speed time θ(t_k)/Ω₀, the delayed node
// values τ_g(t_k) back read by Lagrange interpolation of degree 2s − 1.
// Milling: the cutting coefficients follow the tooth angle θ(t), so the
// grid is the constant-speed one in the mean-speed time t' = θ(t)/Ω₀ (tooth
// entries and exits land on step boundaries, free flight is one exact
// step), mapped to real time t = θ⁻¹(Ω₀ t'); the exact integral of H over a
// step in t' is scaled by Δt/Δt' (exact when Ω is constant over the step;
// the error is of the order of the step's change of Ω, O(h) relative, far
// below the O(h²) of the semi-discretisation at the default steps since the
// speed changes over a modulation period of many steps).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "chatter/error.hpp"

namespace chatter::sdm_detail {
namespace {

// Most steps in one principal period: each step keeps its map and its
// delayed-sample terms (about 0.5 kB with one mode), so this bounds the
// memory of one map near 0.5 GB. Case A at 100 rev/min with R_VF = 0.01
// (100 revolutions) needs 362 000 (51 s).
constexpr double kMaxPeriodSteps = 1e6;
// With collocation, most node samples (steps × nodes) in one period: the
// same case needs 34 000 (11 300 steps of 3 nodes; 4.5 s), 200 revolutions
// 68 000 (20 s); the cost grows faster than the count (docs/ssv.md).
constexpr double kMaxPeriodNodeSamples = 1.5e5;

}  // namespace

Grid make_ssv_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double rpm) {
  if (p.has_process_damping())
    throw InputError(
        "sdm with spindle speed variation does not model process damping (its C a / V follows the varying cutting "
        "speed): remove process.process_damping_coefficient_n_per_m or process.speed_variation");
  Grid g;
  g.path = MapPath::kCutterSteps;
  g.ssv = true;
  g.rpm = rpm;
  g.ssv_period = speed_variation_period(p, rpm);
  g.tau = g.ssv_period.period_s;
  const double tooth = p.delay_s(rpm);
  g.h_target = std::min(tooth / o.steps_per_period, 1.0 / (o.steps_per_vibration_cycle * f_max_hz));
  const double per_tooth = std::ceil(tooth / g.h_target - 1e-9);
  const double needed = std::ceil(g.tau / g.h_target - 1e-9);
  const int nodes = std::max(0, o.collocation_nodes);
  const double samples = needed * std::max(1, nodes), budget = nodes > 0 ? kMaxPeriodNodeSamples : kMaxPeriodSteps;
  if (per_tooth > o.max_steps_per_period || samples > budget) {
    std::ostringstream os;
    os.precision(6);
    os << "sdm with speed variation at " << rpm << " rev/min needs about " << needed << " steps";
    if (nodes > 0) os << " (" << samples << " node samples at collocation_nodes = " << nodes << ")";
    os << " over its period of " << g.tau << " s (" << g.ssv_period.modulation_periods << " modulation periods, "
       << per_tooth << " steps per tooth period), more than ";
    if (per_tooth > o.max_steps_per_period)
      os << "max_steps_per_period = " << o.max_steps_per_period << " per tooth period";
    else
      os << static_cast<long long>(budget) << (nodes > 0 ? " node samples per period" : " steps per period");
    os << ": raise the speed or the frequency ratio (a shorter modulation period), or lower "
          "steps_per_vibration_cycle";
    throw InputError(os.str());
  }
  if (!p.has_helix() && !p.has_nose_radius())  // linear in a: once per speed at 1 m
    g.cutter_grid =
        std::make_shared<const CutterGrid>(ssv_cutter_grid(p, g, o.axial_slices, 1.0, o.collocation_nodes > 0));
  return g;
}

CutterGrid ssv_cutter_grid(const Process& p, const Grid& g, int axial_slices, double a, bool collocation) {
  const SpeedVariation asked = p.speed_variation();
  const ModulatedSpeed speed(g.rpm, {asked.amplitude_ratio, g.ssv_period.frequency_ratio_used});
  const double T = g.tau, omega0 = speed.mean_rad_s();
  CutterGrid cg;
  cg.depth = a;
  if (!p.rotating_edges()) {
    // Constant coefficients: equal steps, a whole number m of them per
    // revolution at the mean speed (so that at R_VA = 0 the grid and the
    // delayed samples are those of the constant-speed solver), q m in the
    // period; H = [[K_f, 0], [0, 0]] (an insert: H(a)); one delay, one
    // revolution back.
    const double rev = p.delay_s(g.rpm);
    const int per_rev = std::max(1, static_cast<int>(std::ceil(rev / g.h_target - 1e-9)));
    const auto m = static_cast<std::size_t>(std::llround(g.ssv_period.floquet_periods)) * static_cast<std::size_t>(per_rev);
    const double kf = p.turning_parameters().feed_force_coefficient_n_per_m2;
    cg.gtau = {rev};
    cg.t.resize(m + 1);
    for (std::size_t i = 0; i <= m; ++i) cg.t[i] = (i == m) ? T : T * static_cast<double>(i) / static_cast<double>(m);
    Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
    if (p.orthogonal_turning())
      F(0, 0) = kf * a * (T / static_cast<double>(m));
    else  // an insert: a H(a) = b d nᵀ (docs/turning_inserts.md)
      F = p.turning_force_matrix(a) * (T / static_cast<double>(m));
    cg.h.assign(m, T / static_cast<double>(m));
    cg.free.assign(m, 0);
    cg.F.assign(m, F);
    cg.D.assign(m, Eigen::Matrix2d::Zero());
    cg.force_scale_n_per_m2 = kf + p.turning_parameters().radial_force_coefficient_n_per_m2;
  } else {
    // The constant-speed grid in t' = θ(t)/Ω₀ over the same length (θ(T) =
    // Ω₀ T: a whole number of modulation periods), with steps short enough
    // that their real length stays below h_target (dt <= dt' / (1 − R_VA)).
    Grid gm = g;
    gm.h_target = g.h_target * (1.0 - asked.amplitude_ratio);
    cg = cutter_grid(p, gm, axial_slices, a, collocation);
    const std::size_t ng = cg.gtau.size();
    std::vector<double> t(cg.t.size());
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = speed.time_at_angle(omega0 * cg.t[i]);
    t.front() = 0.0;
    t.back() = T;
    for (std::size_t i = 0; i + 1 < t.size(); ++i) {
      const double h = t[i + 1] - t[i], ratio = h / cg.h[i];
      cg.h[i] = h;
      for (std::size_t k = 0; k < ng; ++k) cg.F[i * ng + k] *= ratio;
      cg.D[i] *= ratio;
    }
    cg.t = std::move(t);
  }
  // τ_k(t_i): the time over which the spindle turns the group's delay angle
  // Ω₀ τ_k (a tooth pitch, or one revolution in turning).
  const std::size_t ng = cg.gtau.size();
  cg.tau_at.resize(cg.t.size() * ng);
  for (std::size_t i = 0; i < cg.t.size(); ++i)
    for (std::size_t k = 0; k < ng; ++k) cg.tau_at[i * ng + k] = speed.delay(cg.t[i], omega0 * cg.gtau[k]);
  return cg;
}

}  // namespace chatter::sdm_detail
