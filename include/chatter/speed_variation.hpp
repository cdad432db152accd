// Spindle speed variation (SSV): a sinusoidally modulated spindle speed and
// the time-varying delay it makes (docs/ssv.md).
//
//   Ω(t) = Ω₀ (1 + R_VA sin(R_VF Ω₀ t)),
//
// Ω₀ = 2π N / 60 the mean speed (rad/s), R_VA the amplitude ratio, R_VF the
// frequency ratio (modulation frequency over spindle frequency). The spindle
// angle is the integral of Ω,
//
//   θ(t) = ∫₀ᵗ Ω ds = Ω₀ t + (R_VA / R_VF) (1 − cos(R_VF Ω₀ t))   (rad),
//
// and a tooth that follows the one before it by the angle θ_p (2π/N_t for
// equal pitch, 2π in turning) cuts the surface it left τ(t) earlier, where
// τ(t) solves θ(t) − θ(t − τ) = θ_p. The delay equation then has the
// modulation period T_m = 2π / (R_VF Ω₀) in its delay; in milling the
// cutting coefficients repeat with the tooth angle, so the equation is
// periodic over p T_m = q T_F (T_F the Floquet period of the cutter at Ω₀)
// when R_VF T_F Ω₀ / 2π = p/q is rational; speed_variation_period picks p/q
// (exactly, or the nearest fraction with a bounded p).
// Method: T. Insperger, G. Stépán, "Stability analysis of turning with
// periodic spindle speed modulation via semi-discretization", J. Vib.
// Control 10 (2004) 1835–1855; S. Seguy, T. Insperger, L. Arnaud, G. Dessein,
// G. Peigné, "On the stability of high-speed milling with spindle speed
// variation", Int. J. Adv. Manuf. Technol. 48 (2010) 883–895.
// Units: SI (s, rad, rad/s); spindle speeds in rev/min where a name says so.
#pragma once

#include <string>

namespace chatter {

/// The modulation of the spindle speed (both ratios dimensionless).
struct SpeedVariation {
  /// R_VA in [0, 1): the speed swings between (1 ∓ R_VA) Ω₀. 0 = constant speed.
  double amplitude_ratio = 0.0;
  /// R_VF > 0: modulation frequency / spindle frequency (Ω₀ / 2π).
  double frequency_ratio = 0.0;
  /// True when the speed varies (R_VA > 0).
  bool active() const { return amplitude_ratio > 0.0; }
  /// Empty when valid (0 <= R_VA < 1 and R_VF > 0, both finite), else the rule broken.
  std::string validate() const;
};

/// Amplitude ratios above this are accepted with a warning (config reader,
/// CLI): spindle drives rarely follow a swing of more than ±30 %.
inline constexpr double kLargeSpeedVariation = 0.3;

/// The modulated speed at one mean speed: Ω(t), θ(t), their inverse and the
/// time-varying delay. Cheap to copy; all members are pure.
class ModulatedSpeed {
 public:
  /// @pre mean_rpm > 0; v valid (SpeedVariation::validate), or inactive.
  ModulatedSpeed(double mean_rpm, SpeedVariation v);

  double mean_rad_s() const { return omega0_; }
  const SpeedVariation& variation() const { return v_; }
  /// Ω(t), rad/s.
  double omega(double t_s) const;
  /// θ(t) = ∫₀ᵗ Ω ds, rad (θ(0) = 0; increasing since R_VA < 1).
  double angle(double t_s) const;
  /// The time t with θ(t) = angle_rad (Newton on the monotone θ, to round-off), s.
  double time_at_angle(double angle_rad) const;
  /// τ(t) > 0 with θ(t) − θ(t − τ) = angle_rad (the delay of a tooth that
  /// follows the one before by that angle), s. @pre angle_rad > 0.
  double delay(double t_s, double angle_rad) const;
  /// T_m = 2π / (R_VF Ω₀), s; +inf at constant speed.
  double modulation_period_s() const;

 private:
  double omega0_ = 0.0;
  SpeedVariation v_;
  double nu_ = 0.0;  // R_VF Ω₀, rad/s
};

class Process;

/// The principal period of the delay equation with speed variation at mean
/// speed `rpm` (docs/ssv.md, "The period"): p T_m = q T_F with T_m the
/// modulation period and T_F = Process::floquet_period_s(rpm) (one
/// revolution in turning, one tooth period for a uniform milling cutter).
/// The ratio r = T_F / T_m = R_VF Ω₀ T_F / 2π must be p/q: the smallest p <=
/// max_modulation_periods for which p / round(p / r) matches r to 1e-9
/// (exact), else to kSpeedVariationRatioTolerance, else the best p in that
/// range. Off the exact ratio, the modulation is solved with the frequency
/// ratio the fraction gives, R_VF' = (p/q) 2π / (Ω₀ T_F)
/// (frequency_ratio_used), and `exact` is false. A whole number q of Floquet
/// periods keeps the constant-speed grid: at R_VA -> 0 the limit is the
/// constant-speed one. @pre rpm > 0 and process.has_speed_variation().
struct SpeedVariationPeriod {
  double period_s = 0.0;             ///< the principal period, s
  int modulation_periods = 1;        ///< p
  double floquet_periods = 0.0;      ///< q = period_s / T_F (revolutions in turning), a whole number
  double frequency_ratio_used = 0.0; ///< R_VF the period is exact for
  bool exact = true;                 ///< R_VF used equals R_VF asked to 1e-9 (relative)
};
/// Relative change of R_VF accepted from the smallest p before a larger p is tried.
inline constexpr double kSpeedVariationRatioTolerance = 1e-3;
/// Largest number of modulation periods p in one principal period (milling).
inline constexpr int kMaxModulationPeriods = 8;
SpeedVariationPeriod speed_variation_period(const Process& process, double rpm,
                                            int max_modulation_periods = kMaxModulationPeriods);

}  // namespace chatter
