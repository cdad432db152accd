// Closed-form windowed integrals of the milling force law over time and
// height (internal to src/model: Process and its axial slices). Both H₁ (§3)
// and n nᵀ are trigonometric polynomials of degree 2 in φ, the force
// direction v of degree 1; a tooth cuts in the window [φ_en, φ_ex] (mod 2π).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <Eigen/Core>

namespace chatter::process_detail {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kHalfPi = 0.5 * std::numbers::pi;

// sin and cos of a lead angle, exactly (1, 0) at 90° (cos(π/2) is 6e-17 in
// double): the orthogonal cut must give H = [[K_f, 0], [0, 0]] exactly, and
// a cylinder slice of a cutter profile the flat cutter's K_r.
inline double lead_sin(double kappa) { return kappa == kHalfPi ? 1.0 : std::sin(kappa); }
inline double lead_cos(double kappa) { return kappa == kHalfPi ? 0.0 : std::cos(kappa); }

// Below this lag κa (rad) across the cut, the helix integral uses the
// midpoint slice (error (κa)²/24 relative, < 1e-9) instead of the exact
// four-term difference, which cancels there.
inline constexpr double kSmallHelixLag = 1e-4;

// A 2×2 matrix-valued trigonometric polynomial of degree 2,
//   f(φ) = A0 + A1 sin 2φ + A2 cos 2φ,
// with its first and second antiderivatives. Both H₁ (§3) and n nᵀ are of
// this form, so one closed form serves the force and the damping integrals.
struct Trig2 {
  Eigen::Matrix2d a0, a1, a2;
  Eigen::Matrix2d f0(double phi) const { return a0 + a1 * std::sin(2.0 * phi) + a2 * std::cos(2.0 * phi); }
  Eigen::Matrix2d f1(double phi) const {
    return a0 * phi - a1 * (0.5 * std::cos(2.0 * phi)) + a2 * (0.5 * std::sin(2.0 * phi));
  }
  Eigen::Matrix2d f2(double phi) const {
    return a0 * (0.5 * phi * phi) - a1 * (0.25 * std::sin(2.0 * phi)) - a2 * (0.25 * std::cos(2.0 * phi));
  }
};

inline Trig2 force_trig(double kt, double kr) {
  Trig2 t;
  t.a0 << 0.5 * kr, 0.5 * kt, -0.5 * kt, 0.5 * kr;
  t.a1 << 0.5 * kt, 0.5 * kr, 0.5 * kr, -0.5 * kt;
  t.a2 << -0.5 * kr, 0.5 * kt, 0.5 * kt, 0.5 * kr;
  return t;
}

inline Trig2 damping_trig() {
  Trig2 t;
  t.a0 << 0.5, 0.0, 0.0, 0.5;
  t.a1 << 0.0, 0.5, 0.5, 0.0;
  t.a2 << -0.5, 0.0, 0.0, 0.5;
  return t;
}

// The force direction of a tooth per unit chip thickness (§3), v(φ) =
// (K_t cos φ + K_r sin φ, −(K_t sin φ − K_r cos φ)) = c1 cos φ + s1 sin φ
// (vector-valued, degree 1), with its first and second antiderivatives.
struct Trig1 {
  Eigen::Vector2d c1, s1;
  Eigen::Vector2d f0(double phi) const { return c1 * std::cos(phi) + s1 * std::sin(phi); }
  Eigen::Vector2d f1(double phi) const { return c1 * std::sin(phi) - s1 * std::cos(phi); }
  Eigen::Vector2d f2(double phi) const { return -c1 * std::cos(phi) - s1 * std::sin(phi); }
};

inline Trig1 force_direction_trig(double kt, double kr) {
  Trig1 t;
  t.c1 << kt, kr;
  t.s1 << kr, -kt;
  return t;
}

// The windowed, 2π-periodic integrand w(φ) = f(φ) g(φ) (g = 1 on [en, ex]
// + 2πn) and its antiderivatives W1, W2 with W1(0) = W2(0) = 0:
//   W1(2πn + ψ) = n I + w1(ψ),  w1(ψ) = F1(clamp(ψ)) − F1(en),  I = w1(2π);
//   W2(2πn + ψ) = π I n(n − 1) + n J + n I ψ + w2(ψ),  J = w2(2π),
// with w2(ψ) = 0 before en, F2(ψ) − F2(en) − F1(en)(ψ − en) in the arc and
// w2(ex) + I (ψ − ex) after it. (W2' = W1 and continuity at every 2πn.)
// T: Trig2 (matrix-valued: H₁, n nᵀ) or Trig1 (vector-valued: v).
template <class T>
class Windowed {
 public:
  using Value = decltype(std::declval<T>().f1(0.0));
  Windowed(const T& f, double en, double ex) : f_(f), en_(en), ex_(ex) {
    f1en_ = f.f1(en);
    f2en_ = f.f2(en);
    I_ = f.f1(ex) - f1en_;
    w2ex_ = f.f2(ex) - f2en_ - f1en_ * (ex - en);
    J_ = w2ex_ + I_ * (kTwoPi - ex);
  }
  // w itself: f(φ) inside the window, 0 outside.
  Value w0(double phi) const {
    const double psi = phi - kTwoPi * std::floor(phi / kTwoPi);
    if (psi >= en_ && psi <= ex_) return f_.f0(psi);
    Value zero = f_.f0(psi);
    zero.setZero();
    return zero;
  }
  Value w1(double phi) const {
    const double n = std::floor(phi / kTwoPi);
    const double psi = phi - kTwoPi * n;
    return I_ * n + (f_.f1(std::clamp(psi, en_, ex_)) - f1en_);
  }
  Value w2(double phi) const {
    const double n = std::floor(phi / kTwoPi);
    const double psi = phi - kTwoPi * n;
    Value local;
    if (psi <= en_) local.setZero();
    else if (psi <= ex_) local = f_.f2(psi) - f2en_ - f1en_ * (psi - en_);
    else local = w2ex_ + I_ * (psi - ex_);
    return I_ * (std::numbers::pi * n * (n - 1.0)) + J_ * n + I_ * (n * psi) + local;
  }

 private:
  T f_;
  double en_, ex_;
  Value f1en_, f2en_, I_, w2ex_, J_;
};

// ∫_{ta}^{tb} ∫_0^a w(Ω t − Θ − κ z) dz dt for the windowed integrand.
template <class T>
typename Windowed<T>::Value time_height_integral(const Windowed<T>& w, double omega, double theta, double kappa,
                                                 double ta, double tb, double a) {
  const double pa = omega * ta - theta, pb = omega * tb - theta;
  const double lag = kappa * a;
  if (lag < kSmallHelixLag) {  // straight (or nearly): a times the time integral at the mid slice
    const double mid = 0.5 * lag;
    return (w.w1(pb - mid) - w.w1(pa - mid)) * (a / omega);
  }
  return (w.w2(pb) - w.w2(pb - lag) - w.w2(pa) + w.w2(pa - lag)) / (omega * kappa);
}

// ∫_0^a w(Ω t − Θ − κ z) dz at one instant t: the edge's directional matrix
// integrated over the height (the t-derivative of time_height_integral).
template <class T>
typename Windowed<T>::Value height_integral(const Windowed<T>& w, double omega, double theta, double kappa, double t,
                                            double a) {
  const double p = omega * t - theta, lag = kappa * a;
  if (lag < kSmallHelixLag) return w.w0(p - 0.5 * lag) * a;  // the midpoint slice, as time_height_integral
  return (w.w1(p) - w.w1(p - lag)) / kappa;
}

}  // namespace chatter::process_detail
