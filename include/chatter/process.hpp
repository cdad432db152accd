// The cutting process: turning or straight-tooth milling (docs/physics.md §3).
//
// Every operation reduces to the regenerative force on the tool
//   F(t) = −a · H(t) · (r(t) − r(t − τ)),
// with a the depth of cut (m), H(t) the 2×2 directional cutting-coefficient
// matrix (N/m²), r the relative tool − workpiece displacement (m) and τ the
// delay (s). Units are SI; spindle speeds in rev/min only where a name says so.
#pragma once

#include <Eigen/Core>

namespace chatter {

enum class Operation { kTurning, kMilling };
enum class MillingDirection { kDown, kUp };

struct TurningParameters {
  /// K_f: feed-direction specific cutting force, N/m² (> 0). Chip thickness and
  /// feed force both along X, H = [[K_f, 0], [0, 0]].
  double feed_force_coefficient_n_per_m2 = 0.0;
};

struct MillingParameters {
  int teeth = 0;                                     ///< N_t >= 1, equally spaced straight teeth.
  double tangential_coefficient_n_per_m2 = 0.0;      ///< K_t > 0, N/m².
  double radial_coefficient_n_per_m2 = 0.0;          ///< K_r >= 0, N/m².
  double radial_immersion = 1.0;                     ///< a_e / D in (0, 1].
  MillingDirection direction = MillingDirection::kDown;
};

/// The process description. Build with Process::turning / Process::milling,
/// which validate their arguments.
class Process {
 public:
  /// @throws InputError if K_f <= 0 or not finite.
  static Process turning(TurningParameters p);
  /// @throws InputError if teeth < 1, K_t <= 0, K_r < 0,
  ///         radial immersion outside (0, 1].
  static Process milling(MillingParameters p);

  Operation operation() const { return operation_; }
  const TurningParameters& turning_parameters() const { return turning_; }
  const MillingParameters& milling_parameters() const { return milling_; }

  /// Delay τ (s) at spindle speed `rpm` (rev/min): one revolution for turning,
  /// one tooth period 60/(N·N_t) for milling. @pre rpm > 0.
  double delay_s(double rpm) const;
  /// Inverse of delay_s: the spindle speed (rev/min) whose delay is `tau_s`.
  double rpm_from_delay(double tau_s) const;
  /// Number of delay periods per spindle revolution: 1 (turning) or N_t.
  int delays_per_revolution() const;

  /// Entry and exit angles φ_en, φ_ex (rad, clockwise from +Y) of a milling
  /// tooth: down-milling [arccos(2a_e/D − 1), π], up-milling [0, arccos(1 − 2a_e/D)].
  /// @pre operation() == kMilling.
  double entry_angle() const;
  double exit_angle() const;

  /// Directional matrix of one milling tooth at angle φ (rad) while it cuts,
  /// N/m²: [[(K_t cosφ + K_r sinφ) sinφ, (K_t cosφ + K_r sinφ) cosφ],
  ///        [−(K_t sinφ − K_r cosφ) sinφ, −(K_t sinφ − K_r cosφ) cosφ]].
  Eigen::Matrix2d tooth_matrix(double phi) const;

  /// An antiderivative in φ of tooth_matrix (closed form), N/m²·rad:
  /// ∫_{φa}^{φb} tooth_matrix(φ) dφ = F(φb) − F(φa). Used for H₀ and for the
  /// step averages of the semi-discretisation. Cost O(1). @pre operation() == kMilling.
  Eigen::Matrix2d tooth_matrix_antiderivative(double phi) const;

  /// Directional matrix H(t) at time t (s) after tooth 0 passes φ = 0, for
  /// spindle speed `rpm`, N/m²: Σ_j g_j(φ_j) tooth_matrix(φ_j) with
  /// φ_j = Ωt + 2πj/N_t. Turning: the constant [[K_f, 0], [0, 0]].
  Eigen::Matrix2d directional_matrix(double t_s, double rpm) const;

  /// Average of H over one delay, H₀ (N/m²): turning H itself; milling
  /// (N_t/2π) ∫_{φ_en}^{φ_ex} tooth_matrix(φ) dφ, integrated in closed form
  /// (zeroth-order approximation, Altintas & Budak 1995).
  Eigen::Matrix2d average_directional_matrix() const;

 private:
  Operation operation_ = Operation::kTurning;
  TurningParameters turning_;
  MillingParameters milling_;
};

}  // namespace chatter
