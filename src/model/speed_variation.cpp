// The modulated spindle speed, its angle, the time-varying delay and the
// principal period of the delay equation (chatter/speed_variation.hpp,
// docs/ssv.md).
#include "chatter/speed_variation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "chatter/error.hpp"
#include "chatter/process.hpp"
#include "chatter/kinematics.hpp"
#include "chatter/number_text.hpp"

namespace chatter {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Newton on the monotone angle stops at this relative change (round-off).
constexpr double kNewtonTolerance = 1e-15;
constexpr int kNewtonIterations = 60;
// A fraction p/q within this (relative) of the asked ratio is the ratio.
constexpr double kExactRatio = 1e-9;

std::string number(double x) { return number_text(x, 6); }

// Solves g(x) = target for an increasing g with derivative dg >= gmin > 0 on
// [lo, hi] (g(lo) <= target <= g(hi)): Newton, kept inside the bracket
// (bisection when a step leaves it).
template <class G, class D>
double solve_increasing(G g, D dg, double target, double lo, double hi, double x) {
  for (int it = 0; it < kNewtonIterations; ++it) {
    const double f = g(x) - target;
    if (f > 0.0) hi = std::min(hi, x);
    else lo = std::max(lo, x);
    double next = x - f / dg(x);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double change = std::abs(next - x);
    x = next;
    if (change <= kNewtonTolerance * std::abs(x)) break;
  }
  return x;
}

}  // namespace

std::string SpeedVariation::validate() const {
  if (!(std::isfinite(amplitude_ratio) && amplitude_ratio >= 0.0 && amplitude_ratio < 1.0))
    return "amplitude_ratio = " + number(amplitude_ratio) +
           ": must be in [0, 1) (the speed swings between (1 - R_VA) and (1 + R_VA) times the mean)";
  if (!(std::isfinite(frequency_ratio) && frequency_ratio > 0.0))
    return "frequency_ratio = " + number(frequency_ratio) +
           ": must be > 0 (modulation frequency / spindle frequency)";
  return "";
}

ModulatedSpeed::ModulatedSpeed(double mean_rpm, SpeedVariation v)
    : omega0_(angular_speed_rad_per_s(mean_rpm)), v_(v), nu_(v.frequency_ratio * angular_speed_rad_per_s(mean_rpm)) {
  if (!v_.active()) v_ = {};
}

double ModulatedSpeed::omega(double t) const {
  if (!v_.active()) return omega0_;
  return omega0_ * (1.0 + v_.amplitude_ratio * std::sin(nu_ * t));
}

double ModulatedSpeed::angle(double t) const {
  if (!v_.active()) return omega0_ * t;
  return omega0_ * t + (v_.amplitude_ratio / v_.frequency_ratio) * (1.0 - std::cos(nu_ * t));
}

double ModulatedSpeed::time_at_angle(double phi) const {
  if (!v_.active()) return phi / omega0_;
  const double a = v_.amplitude_ratio;
  // |θ(t) − Ω₀ t| <= 2 R_VA / R_VF: the root lies within that of φ / Ω₀.
  const double spread = 2.0 * a / v_.frequency_ratio / omega0_;
  const double x0 = phi / omega0_;
  return solve_increasing([&](double t) { return angle(t); }, [&](double t) { return omega(t); }, phi,
                          x0 - spread, x0 + spread, x0);
}

double ModulatedSpeed::delay(double t, double phi) const {
  if (!v_.active()) return phi / omega0_;
  const double a = v_.amplitude_ratio;
  // Ω between (1 − R_VA) Ω₀ and (1 + R_VA) Ω₀: τ between φ/Ω_max and φ/Ω_min.
  const double lo = phi / (omega0_ * (1.0 + a)), hi = phi / (omega0_ * (1.0 - a));
  const double at = angle(t);
  return solve_increasing([&](double tau) { return at - angle(t - tau); }, [&](double tau) { return omega(t - tau); },
                          phi, lo, hi, std::clamp(phi / omega0_, lo, hi));
}

double ModulatedSpeed::modulation_period_s() const {
  if (!v_.active()) return std::numeric_limits<double>::infinity();
  return kTwoPi / nu_;
}

void Process::set_speed_variation(SpeedVariation v) {
  if (v.amplitude_ratio == 0.0) {  // off: the frequency does not matter (the default {0, 0} included)
    speed_variation_ = {};
    return;
  }
  if (const std::string e = v.validate(); !e.empty()) throw InputError("process.speed_variation." + e);
  speed_variation_ = v.active() ? v : SpeedVariation{};
}

SpeedVariationPeriod speed_variation_period(const Process& process, double rpm, int max_modulation_periods) {
  const SpeedVariation& v = process.speed_variation();
  const double omega0 = angular_speed_rad_per_s(rpm);
  SpeedVariationPeriod out;
  out.frequency_ratio_used = v.frequency_ratio;
  const double tf = process.floquet_period_s(rpm);
  const double r = v.frequency_ratio * omega0 * tf / kTwoPi;  // = T_F / T_m = p / q
  const int pmax = std::max(1, max_modulation_periods);
  auto q_of = [&](int p) { return std::max(1.0, std::round(p / r)); };
  auto err_of = [&](int p) { return std::abs(p / q_of(p) - r) / r; };
  // The smallest p exact to round-off, else within the tolerance, else the best.
  int best_p = 0;
  for (const double tol : {kExactRatio, kSpeedVariationRatioTolerance}) {
    for (int p = 1; p <= pmax && best_p == 0; ++p)
      if (err_of(p) <= tol) best_p = p;
    if (best_p != 0) break;
  }
  if (best_p == 0) {
    best_p = 1;
    for (int p = 2; p <= pmax; ++p)
      if (err_of(p) < err_of(best_p)) best_p = p;
  }
  const double best_q = q_of(best_p), best_err = err_of(best_p);
  out.modulation_periods = best_p;
  out.floquet_periods = best_q;
  out.period_s = best_q * tf;
  out.exact = best_err <= kExactRatio;
  // The ratio the fraction gives: p T_m' = q T_F.
  out.frequency_ratio_used = out.exact ? v.frequency_ratio : (best_p / best_q) * kTwoPi / (omega0 * tf);
  return out;
}

}  // namespace chatter
