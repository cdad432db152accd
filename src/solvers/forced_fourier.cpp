// The forced response of a cutter whose motion repeats every tooth (equal
// pitch, one helix angle, no runout, no process damping) and of turning:
// r(t) = Σ_k G(k ω_T) F_k e^{j k ω_T t}, the receptance times the Fourier
// series of the static chip force (docs/physics.md §11; Schmitz & Mann 2006).
// Also the turning deflection δ = F Σ (u·n)²/k and its diametral error.
#include "chatter/forced.hpp"
#include "forced_internal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"

namespace chatter {
namespace forced_detail {
namespace {

using Cplx = std::complex<double>;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The in-plane force of turning does not need the workpiece diameter.
constexpr double kNaNDiameter = std::numeric_limits<double>::quiet_NaN();
// Automatic harmonic count: every tooth-passing harmonic up to this many
// times the highest natural frequency (ForcedOptions::harmonics), at least
// kMinHarmonics.
constexpr double kAutoHarmonicFactor = 50.0;
constexpr int kMinHarmonics = 64;
// Below this |n (φ_ex − φ_en)| (and |m κ a|) the closed forms of E(n) and
// Z(m) use their Taylor series (the closed form cancels; the first omitted
// term is below 1e-13 relative).
constexpr double kSeriesBelow = 1e-4;

// E(n) = ∫_{en}^{ex} e^{−j n φ} dφ.
Cplx arc_exponential(int n, double en, double ex) {
  const double w = ex - en;
  const double u = n * w;
  if (std::abs(u) < kSeriesBelow)
    return std::polar(1.0, -n * 0.5 * (en + ex)) * w * (1.0 - u * u / 24.0);
  return (std::polar(1.0, -n * ex) - std::polar(1.0, -n * en)) / Cplx(0.0, -static_cast<double>(n));
}

// Z(m) = ∫₀ᵃ e^{−j m κ z} dz: the helix spreads a harmonic over the height.
Cplx helix_factor(double m_kappa, double a) {
  const double u = m_kappa * a;
  if (std::abs(u) < kSeriesBelow) return std::polar(1.0, -0.5 * u) * a * (1.0 - u * u / 24.0);
  return (1.0 - std::polar(1.0, -u)) / Cplx(0.0, m_kappa);
}

}  // namespace

FourierPath::FourierPath(double period, const Eigen::Vector2d& c0, std::vector<Vector2cd> ck)
    : c0_(c0), ck_(std::move(ck)) {
  period_ = period;
}

Eigen::Vector2d FourierPath::at(double t) const {
  const double omega = kTwoPi / period_;
  const Cplx step = std::polar(1.0, omega * std::fmod(t, period_));
  Cplx e = step;
  Cplx sx(0.0, 0.0), sy(0.0, 0.0);
  for (const Vector2cd& c : ck_) {
    sx += c(0) * e;
    sy += c(1) * e;
    e *= step;
  }
  return c0_ + 2.0 * Eigen::Vector2d(sx.real(), sy.real());
}

PathSource fourier_response(const StructuralModel& model, const Process& process, double rpm, double depth_m,
                            double feed_m, int harmonics, int max_harmonics) {
  PathSource out;
  const double tau = process.delay_s(rpm);  // the tooth period (one revolution in turning)
  if (!process.rotating_edges()) {
    // The cutting law's constant force (−a f d, docs/turning_inserts.md), so r = G(0) F.
    const Eigen::Vector2d F = CuttingLaw::of(process)->mean(CutPoint{rpm, depth_m, feed_m, kNaNDiameter}).force_n;
    const Matrix2c G0 = model.receptance(0.0);
    out.mean_force_n = F;
    out.path = std::make_unique<FourierPath>(tau, G0.real() * F, std::vector<Vector2cd>{});
    return out;
  }
  const int nt = process.teeth();
  const MillingParameters& mp = process.milling_parameters();
  const double kt = mp.tangential_coefficient_n_per_m2, kr = mp.radial_coefficient_n_per_m2;
  const double en = process.entry_angle(), ex = process.exit_angle();
  const double kappa = process.helix_lag_rad_per_m(0);
  const double omega_t = kTwoPi / tau;
  if (harmonics <= 0) {
    const double f_max = model.max_omega() / kTwoPi;
    const double want = std::ceil(kAutoHarmonicFactor * f_max * tau);
    harmonics = static_cast<int>(std::clamp(want, static_cast<double>(kMinHarmonics), static_cast<double>(max_harmonics)));
  }
  // One tooth's static force per unit depth: F1(φ) = −f sin φ v(φ), with
  // sin φ v(φ) = A0 + A1 sin 2φ + A2 cos 2φ (§3):
  //   x: (K_r/2, K_t/2, −K_r/2),  y: (−K_t/2, K_r/2, K_t/2).
  const Eigen::Vector2d A0(0.5 * kr, -0.5 * kt), A1(0.5 * kt, 0.5 * kr), A2(-0.5 * kr, 0.5 * kt);
  // a_m = (1/2π) ∫_{en}^{ex} F1(φ) e^{−jmφ} dφ; the N_t equally spaced
  // teeth keep m = k N_t (N_t a_m), the height gives Z(m).
  auto coefficient = [&](int k) {
    const int m = k * nt;
    const Cplx e0 = arc_exponential(m, en, ex), ep = arc_exponential(m - 2, en, ex),
               em = arc_exponential(m + 2, en, ex);
    const Cplx s2 = (ep - em) / Cplx(0.0, 2.0);  // ∫ sin 2φ e^{−jmφ}
    const Cplx c2 = 0.5 * (ep + em);             // ∫ cos 2φ e^{−jmφ}
    Vector2cd a;
    for (int c = 0; c < 2; ++c) a(c) = -feed_m * (A0(c) * e0 + A1(c) * s2 + A2(c) * c2) / kTwoPi;
    return Vector2cd(static_cast<double>(nt) * helix_factor(m * kappa, depth_m) * a);
  };
  const Vector2cd F0 = coefficient(0);
  out.mean_force_n = F0.real();
  const Eigen::Vector2d c0 = model.receptance(0.0).real() * out.mean_force_n;
  std::vector<Vector2cd> ck(static_cast<std::size_t>(harmonics));
  for (int k = 1; k <= harmonics; ++k) ck[static_cast<std::size_t>(k - 1)] = model.receptance(k * omega_t) * coefficient(k);
  out.harmonics = harmonics;
  out.path = std::make_unique<FourierPath>(tau, c0, std::move(ck));
  return out;
}

}  // namespace forced_detail

TurningDeflection static_deflection_turning(const StructuralModel& model, const Process& process, double depth_m,
                                            double feed_per_rev_m) {
  if (process.rotating_edges())
    throw InputError("static deflection of turning: the process is milling (use the forced response)");
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) {
    std::ostringstream os;
    os << "depth " << depth_m << " m: must be >= 0 and finite";
    throw InputError(os.str());
  }
  if (!(std::isfinite(feed_per_rev_m) && feed_per_rev_m >= 0.0)) {
    std::ostringstream os;
    os << "feed " << feed_per_rev_m << " m per revolution: must be >= 0 and finite";
    throw InputError(os.str());
  }
  if (model.has_measured())
    throw InputError("static deflection: needs modes, not measured FRFs (their static compliance is not measured)");
  if (!process.orthogonal_turning())
    throw InputError("static deflection and diametral error of turning: modelled for the orthogonal cut only "
                     "(lead_angle_deg = 90, nose_radius_mm = 0, no radial_force_coefficient); with an insert the "
                     "finished diameter is left by the nose, which this model does not follow "
                     "(docs/turning_inserts.md)");
  TurningDeflection d;
  // The cutting law's force along the chip direction x (−a K_f f on the
  // tool); it does not depend on the speed (1 rev/min stands for any).
  d.force_n = -CuttingLaw::of(process)->mean(CutPoint{1.0, depth_m, feed_per_rev_m, forced_detail::kNaNDiameter}).force_n.x();
  // G(0) = Σ u uᵀ / k over the tool and workpiece modes; the force on the
  // tool is −F along the chip direction n = x.
  Eigen::Matrix2d G0 = Eigen::Matrix2d::Zero();
  for (const Body* b : {&model.tool, &model.workpiece})
    for (const Mode& m : b->modes) {
      G0 += m.direction * m.direction.transpose() / m.stiffness_n_per_m;
    }
  const Eigen::Vector2d r = G0 * Eigen::Vector2d(-d.force_n, 0.0);
  d.deflection_x_m = r.x();
  d.deflection_y_m = r.y();
  d.deflection_m = -r.x();  // −n·r: material left on the radius
  d.diametral_error_m = 2.0 * d.deflection_m;
  return d;
}

std::vector<ShaftDeflection> diametral_error_along(const StructuralModel& base, const PositionDependence& dependence,
                                                   const Process& process, const std::vector<double>& positions_m,
                                                   double depth_m, double feed_per_rev_m) {
  std::vector<ShaftDeflection> out;
  out.reserve(positions_m.size());
  for (const double x : positions_m)
    out.push_back({x, static_deflection_turning(model_at_position(base, dependence, x), process, depth_m,
                                                feed_per_rev_m)});
  return out;
}

}  // namespace chatter
