// The kinematics of a turning spindle, defined once: spindle speed N in
// rev/min against angular speed Ω (rad/s), one revolution, a tooth period,
// the tooth-passing frequency, a cutting (surface) speed and the table feed.
// Every `/ 60` that turns a spindle speed into seconds is here; the rest of
// the code calls these (ctest `kinematics` greps for a stray one).
//
//   Ω = 2π N / 60          one revolution T_rev = 60 / N
//   tooth period τ = 60 / (N n)   for n equally spaced teeth (n = 1: turning)
//   tooth passing f_tp = N n / 60 Hz
//   cutting speed V = π D N / 60  (D the tool's or workpiece's diameter)
//   table speed v_f = f_rev N / 60  (f_rev the feed per revolution)
//
// SpindleSpeed is the type a spindle speed crosses an interface in (the
// lobe solvers' methods, chatter/lobes.hpp): built from rev/min or rad/s by
// name, never converted from a bare number by accident, and it answers the
// same kinematic questions through the functions below.
//
// Units: rev/min for N, s, rad/s, Hz, m and m/s. Header-only, constexpr;
// each formula keeps the order of its operations (the numbers every caller
// had before it moved here, to the last bit).
#pragma once

#include <compare>
#include <numbers>

namespace chatter {

/// Ω (rad/s) of N rev/min: 2π N / 60.
constexpr double angular_speed_rad_per_s(double rpm) { return 2.0 * std::numbers::pi * rpm / 60.0; }
/// N (rev/min) of Ω rad/s.
constexpr double rpm_from_angular_speed(double omega_rad_per_s) { return omega_rad_per_s * 60.0 / (2.0 * std::numbers::pi); }
/// One revolution at N rev/min, s: 60 / N.
constexpr double revolution_s(double rpm) { return 60.0 / rpm; }
/// Revolutions per second at N rev/min (the spindle frequency, Hz): N / 60.
constexpr double revolutions_per_s(double rpm) { return rpm / 60.0; }
/// N (rev/min) of a rotation at `rev_per_s` revolutions per second.
constexpr double rpm_from_revolutions_per_s(double rev_per_s) { return rev_per_s * 60.0; }
/// The revolutions in `t_s` seconds at N rev/min: t N / 60.
constexpr double revolutions_in(double t_s, double rpm) { return t_s * rpm / 60.0; }
/// τ (s) between `n` equally spaced edges at N rev/min: 60 / (N n).
constexpr double tooth_period_s(double rpm, int n) { return 60.0 / (rpm * n); }
/// N (rev/min) whose tooth period with `n` edges is τ: 60 / (τ n).
constexpr double rpm_from_tooth_period(double tau_s, int n) { return 60.0 / (tau_s * n); }
/// The tooth-passing frequency (Hz) of `n` edges at N rev/min: N n / 60.
constexpr double tooth_passing_hz(double rpm, int n) { return rpm * n / 60.0; }
/// N (rev/min) whose `n` edges pass at f_tp Hz: 60 f_tp / n (the inverse of tooth_passing_hz).
constexpr double rpm_from_tooth_passing_hz(double f_hz, int n) { return 60.0 * f_hz / n; }
/// V (m/s) of a diameter D (m) turning at N rev/min: π D N / 60.
constexpr double cutting_speed_m_per_s(double diameter_m, double rpm) {
  return std::numbers::pi * diameter_m * rpm / 60.0;
}
/// v_f (m/s) of a feed per revolution f (m) at N rev/min: f N / 60.
constexpr double table_speed_m_per_s(double feed_per_rev_m, double rpm) { return feed_per_rev_m * rpm / 60.0; }

/// A spindle speed N (rev/min). Explicit: `SpindleSpeed(12000.0)` is 12 000
/// rev/min, `SpindleSpeed::from_rad_per_s(w)` an angular speed; a bare
/// double never becomes one silently. No validity check here (a speed is
/// checked where it enters: check_spindle_rpm, the config readers); the
/// solvers' preconditions say > 0.
class SpindleSpeed {
 public:
  constexpr explicit SpindleSpeed(double rpm) : rpm_(rpm) {}
  static constexpr SpindleSpeed from_rad_per_s(double omega) { return SpindleSpeed(rpm_from_angular_speed(omega)); }

  /// N, rev/min.
  constexpr double rpm() const { return rpm_; }
  /// Ω = 2π N / 60, rad/s.
  constexpr double rad_per_s() const { return angular_speed_rad_per_s(rpm_); }
  /// One revolution, s.
  constexpr double revolution_s() const { return chatter::revolution_s(rpm_); }
  /// The period between `n` equally spaced edges, s.
  constexpr double tooth_period_s(int n) const { return chatter::tooth_period_s(rpm_, n); }
  /// The passing frequency of `n` equally spaced edges, Hz.
  constexpr double tooth_passing_hz(int n) const { return chatter::tooth_passing_hz(rpm_, n); }

  constexpr auto operator<=>(const SpindleSpeed&) const = default;

 private:
  double rpm_;
};

}  // namespace chatter
