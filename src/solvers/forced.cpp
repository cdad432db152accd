// The forced response of a stable cut (include/chatter/forced.hpp,
// docs/forced.md): the stability verdict (sdm), the choice of the path
// (Fourier series or periodic solve), and what the path says about the
// part: mean and peak-to-peak vibration, the surface location error of the
// machined wall, and the chip of every tooth (where the linear model stops
// holding).
#include "chatter/forced.hpp"
#include "forced_internal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/lobes.hpp"
#include "chatter/kinematics.hpp"
#include "chatter/number_text.hpp"

namespace chatter {
namespace {

using forced_detail::PathSource;
using forced_detail::PeriodicPath;

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The recorded path has at least this many samples per period of the
// highest natural frequency (peak to peak read off them is then within
// 1 − cos(π/32) = 0.5 % of the true one, usually far closer).
constexpr int kSamplesPerVibrationCycle = 32;

std::string number(double x) { return number_text(x, 6); }

// True when the motion repeats every tooth period and the regenerative term
// vanishes in steady state (the Fourier path applies).
bool tooth_periodic(const Process& p) {
  if (!p.rotating_edges()) return true;
  return p.uniform_cutter() && !p.has_runout() && !p.has_process_damping();
}

// sin φ, exactly 0 at φ = π (the exit of down milling, the end of a full
// slot): the static chip there is 0, not 6e-17 f.
double exact_sin(double phi) { return phi == kPi ? 0.0 : std::sin(phi); }

// The part of one pass's arc (rad) where the sampled chip h(φ_i) (evenly
// spaced by dphi) is negative, zero crossings by linear interpolation.
double negative_arc(const std::vector<double>& h, double dphi) {
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < h.size(); ++i) {
    const double a = h[i], b = h[i + 1];
    if (a < 0.0 && b < 0.0) total += dphi;
    else if (a < 0.0 && b >= 0.0) total += dphi * a / (a - b);
    else if (a >= 0.0 && b < 0.0) total += dphi * b / (b - a);
  }
  return total;
}

// The path over one period at `samples` + 1 instants: peak to peak, and the
// record when asked (the displacement into the wall n_w beside it).
void sample_path(const PeriodicPath& path, int samples, const Eigen::Vector2d& n_w, bool record,
                 ForcedResponse& out) {
  const double T = path.period();
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int k = 0; k <= samples; ++k) {
    const double t = T * k / samples;
    const Eigen::Vector2d r = path.at(t);
    lo = lo.cwiseMin(r);
    hi = hi.cwiseMax(r);
    if (record) {
      out.t_s.push_back(t);
      out.rel_x_m.push_back(r.x());
      out.rel_y_m.push_back(r.y());
      out.wall_normal_m.push_back(-n_w.dot(r) + 0.0);
    }
  }
  out.peak_to_peak_x_m = hi.x() - lo.x();
  out.peak_to_peak_y_m = hi.y() - lo.y();
}

// The wall: tooth j's slice at height z passes φ_w at t = (φ_w + Θ_j +
// κ_j z)/Ω (omega in rad/s); it leaves the wall at −n_w·r − ρ_j; the wall at
// z is the deepest pass. Heights z_i = a i / heights, i = 0 … heights (one,
// z = 0, when heights is 0).
void wall_sle(const Process& p, const PeriodicPath& path, double a, double omega, double phi_w,
              const Eigen::Vector2d& n_w, int heights, ForcedResponse& out) {
  const int nt = p.teeth();
  const double T = path.period();
  out.wall_z_m.resize(static_cast<std::size_t>(heights + 1));
  out.wall_sle_m.assign(static_cast<std::size_t>(heights + 1), std::numeric_limits<double>::infinity());
  out.tooth_wall_sle_m.resize(static_cast<std::size_t>(nt * (heights + 1)));
  for (int j = 0; j < nt; ++j) {
    const double t0 = std::fmod((phi_w + p.tooth_offset_rad(j)) / omega, T);
    out.tooth_wall_t_s.push_back(t0 < 0.0 ? t0 + T : t0);
  }
  for (int i = 0; i <= heights; ++i) {
    const double z = heights > 0 ? a * i / heights : 0.0;
    out.wall_z_m[static_cast<std::size_t>(i)] = z;
    for (int j = 0; j < nt; ++j) {
      const double t = (phi_w + p.tooth_offset_rad(j) + p.helix_lag_rad_per_m(j) * z) / omega;
      const double sle = -n_w.dot(path.at(t)) - p.runout_m(j) + 0.0;  // + 0: no −0 when the wall does not move
      out.tooth_wall_sle_m[static_cast<std::size_t>(j * (heights + 1) + i)] = sle;
      double& wall = out.wall_sle_m[static_cast<std::size_t>(i)];
      wall = std::min(wall, sle);
    }
  }
  out.sle_min_m = *std::min_element(out.wall_sle_m.begin(), out.wall_sle_m.end());
  out.sle_max_m = *std::max_element(out.wall_sle_m.begin(), out.wall_sle_m.end());
  out.surface_location_error_m = std::abs(out.sle_max_m) > std::abs(out.sle_min_m) ? out.sle_max_m : out.sle_min_m;
}

// The chip of every tooth (slice) over its engaged arc: h = f_j sin φ +
// ρ_j − ρ_{j−1} + n·(r(t) − r(t − τ_j(z))); its smallest value and the
// longest arc where it is negative (the teeth leave the cut).
void chip_over_arcs(const Process& p, const PeriodicPath& path, bool fourier, double rpm, double a, double feed_m,
                    const ForcedOptions& o, ForcedResponse& out) {
  const int nt = p.teeth();
  const double omega = angular_speed_rad_per_s(rpm);
  const double en = p.entry_angle(), ex = p.exit_angle(), arc = ex - en;
  const int na = o.arc_points;
  const double dphi = arc / na;
  double min_chip = std::numeric_limits<double>::infinity(), worst_arc = 0.0;
  if (fourier) {
    // Tooth-periodic: r(t) = r(t − τ), the chip is the static chip f sin φ
    // (≥ 0 on the arc): its smallest value is at an end of the arc.
    min_chip = feed_m * std::min(exact_sin(en), exact_sin(ex));
  } else {
    const int slices = p.has_helix() ? o.axial_points : 1;
    std::vector<double> h(static_cast<std::size_t>(na + 1));
    for (int j = 0; j < nt; ++j) {
      const double f = p.feed_of_tooth_m(j, feed_m);
      const double offset = p.runout_m(j) - p.runout_m((j + nt - 1) % nt);
      for (int sl = 0; sl < slices; ++sl) {
        const double z = p.has_helix() ? a * (sl + 0.5) / slices : 0.0;
        const double tau = p.tooth_delay_s(j, z, rpm);
        for (int k = 0; k <= na; ++k) {
          const double phi = en + dphi * k;
          const double t = (phi + p.tooth_offset_rad(j) + p.helix_lag_rad_per_m(j) * z) / omega;
          const Eigen::Vector2d n(std::sin(phi), std::cos(phi));
          const double hk = f * exact_sin(phi) + offset + n.dot(path.at(t) - path.at(t - tau));
          h[static_cast<std::size_t>(k)] = hk;
          min_chip = std::min(min_chip, hk);
        }
        worst_arc = std::max(worst_arc, negative_arc(h, dphi));
      }
    }
  }
  out.min_chip_m = min_chip;
  out.negative_chip_arc_deg = worst_arc * 180.0 / kPi;
  out.negative_chip_fraction = arc > 0.0 ? worst_arc / arc : 0.0;
  out.teeth_leave_cut = out.negative_chip_fraction > kLeaveCutArcFraction;
}

}  // namespace

std::string ForcedOptions::validate() const {
  std::ostringstream os;
  if (const std::string e = sdm.validate(); !e.empty())
    os << "sdm." << e;
  else if (harmonics < 0)
    os << "harmonics = " << harmonics << ": must be >= 0 (0 = automatic)";
  else if (max_harmonics < 1)
    os << "max_harmonics = " << max_harmonics << ": must be >= 1";
  else if (samples_per_period < 16)
    os << "samples_per_period = " << samples_per_period << ": must be >= 16";
  else if (axial_points < 1)
    os << "axial_points = " << axial_points << ": must be >= 1";
  else if (arc_points < 16)
    os << "arc_points = " << arc_points << ": must be >= 16";
  return os.str();
}

ForcedResponseSolver::ForcedResponseSolver(StructuralModel model, Process process, ForcedOptions options)
    : model_(std::move(model)), process_(std::move(process)), options_(std::move(options)),
      sdm_([&] {
        if (const std::string e = options_.validate(); !e.empty()) throw InputError("forced options: " + e);
        if (model_.has_measured())
          throw InputError("forced response needs modes, not measured FRFs: fit modes to the measurement first "
                           "(chatter fit)");
        if (process_.split_engagement())  // (turning has one window: never split)
          throw InputError("the forced response (surface location error) with two engaged arcs is not modelled (which "
                           "wall the SLE is at is not defined): give one arc");
        if (process_.has_speed_variation())
          throw InputError("the forced response (surface location error) is computed at constant spindle speed: "
                           "remove process.speed_variation (docs/ssv.md)");
        if (process_.has_profile())
          throw InputError(std::string("the forced response (surface location error) is not modelled for "
                                       "process.cutter_geometry = \"") +
                           to_string(process_.cutter_profile().geometry()) +
                           "\" (the wall a curved edge leaves is not followed): use a flat cutter "
                           "(docs/cutter_geometry.md)");
        return SemiDiscretizationSolver(model_, process_, options_.sdm);
      }()) {}

ForcedResponse ForcedResponseSolver::response(const ForcedSettings& s) const {
  if (!(std::isfinite(s.spindle_rpm) && s.spindle_rpm > 0.0))
    throw InputError("spindle speed " + number(s.spindle_rpm) + " rev/min: must be > 0 and finite");
  if (!(std::isfinite(s.depth_m) && s.depth_m >= 0.0))
    throw InputError("depth " + number(s.depth_m) + " m: must be >= 0 and finite");
  if (!(std::isfinite(s.feed_m) && s.feed_m >= 0.0))
    throw InputError("feed " + number(s.feed_m) + " m: must be >= 0 and finite");
  const Process& p = process_;
  const bool milling = p.rotating_edges();
  const double rpm = s.spindle_rpm, a = s.depth_m;
  ForcedResponse out;
  out.spindle_rpm = rpm;
  out.depth_m = a;
  out.feed_m = s.feed_m;
  out.milling = milling;
  const bool fourier = tooth_periodic(p) && !(milling && options_.periodic_solve_always);
  out.method = fourier ? "fourier" : "periodic-solve";
  // Kienzle's law: the regenerative coefficient at this response's own chip
  // (Process::at_feed); the solver's process otherwise.
  const FloquetResult fr = p.has_size_effect() && s.feed_m > 0.0
                               ? SemiDiscretizationSolver(model_, p.at_feed(s.feed_m), options_.sdm).analyse(rpm, a)
                               : sdm_.analyse(rpm, a);
  out.spectral_radius = fr.spectral_radius;
  out.stable = fr.stable();
  if (!out.stable) return out;  // no forced response: the vibration grows

  PathSource src = fourier ? forced_detail::fourier_response(model_, p, rpm, a, s.feed_m, options_.harmonics,
                                                             options_.max_harmonics)
                           : forced_detail::periodic_response(model_, p, options_.sdm, rpm, a, s.feed_m);
  const PeriodicPath& path = *src.path;
  out.harmonics = src.harmonics;
  out.period_s = path.period();
  out.mean_force_x_n = src.mean_force_n.x();
  out.mean_force_y_n = src.mean_force_n.y();
  const Eigen::Vector2d mean = path.mean();
  out.static_x_m = mean.x();
  out.static_y_m = mean.y();
  // The direction into the machined wall: n_w = (sin φ_w, cos φ_w) at the
  // wall (φ_w = π down, 0 up); turning: the chip direction x.
  // (0, −1) at π and (0, 1) at 0 exactly: sin π = 1.2e-16 would leak the
  // feed-direction motion into the SLE.
  const bool down = milling && p.milling_parameters().direction == MillingDirection::kDown;
  const double phi_w = down ? kPi : 0.0;
  const Eigen::Vector2d n_w = milling ? Eigen::Vector2d(0.0, down ? -1.0 : 1.0) : Eigen::Vector2d(1.0, 0.0);

  sample_path(path, std::max(options_.samples_per_period,
                              static_cast<int>(std::ceil(kSamplesPerVibrationCycle * model_.max_omega() / kTwoPi *
                                                         path.period()))),
              n_w, s.record_path, out);

  if (!milling) {
    // Turning: the constant deflection (static_deflection_turning, the one
    // definition; the path above is the same constant); the chip is the feed.
    const TurningDeflection d = static_deflection_turning(model_, p, a, s.feed_m);
    out.static_x_m = d.deflection_x_m;
    out.static_y_m = d.deflection_y_m;
    out.surface_location_error_m = out.sle_min_m = out.sle_max_m = d.deflection_m;
    out.diametral_error_m = d.diametral_error_m;
    out.min_chip_m = s.feed_m;
    out.linear_limit_holds = true;
    return out;
  }

  wall_sle(p, path, a, angular_speed_rad_per_s(rpm), phi_w, n_w, p.has_helix() ? options_.axial_points : 0, out);

  chip_over_arcs(p, path, fourier, rpm, a, s.feed_m, options_, out);
  out.linear_limit_holds = !out.teeth_leave_cut;
  return out;
}

std::vector<ForcedResponse> sle_sweep(const ForcedResponseSolver& solver, const std::vector<double>& speeds_rpm,
                                      double depth_m, double feed_m, unsigned threads,
                                      const std::function<void(std::size_t done)>& per_speed) {
  for (const double rpm : speeds_rpm)
    if (!(std::isfinite(rpm) && rpm > 0.0))
      throw InputError("spindle speed " + number(rpm) + " rev/min: must be > 0 and finite");
  std::vector<ForcedResponse> rows(speeds_rpm.size());
  parallel_for(
      speeds_rpm.size(), threads,
      [&](std::size_t i) {
        ForcedSettings st;
        st.spindle_rpm = speeds_rpm[i];
        st.depth_m = depth_m;
        st.feed_m = feed_m;
        st.record_path = false;
        rows[i] = solver.response(st);
      },
      per_speed);
  return rows;
}

}  // namespace chatter
