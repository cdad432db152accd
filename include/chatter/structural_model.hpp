// The one structural-mode description shared by every solver
// (docs/physics.md §2).
//
// Two bodies, the tool and the workpiece, each with zero or more modes. A body
// with no modes is rigid. Everything here is in SI units (Hz only where a name
// says so). The model is a plain value: build it once, pass it by const&; no
// member function modifies it, so any number of threads may read one model.
#pragma once

#include <complex>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace chatter {

using Complex = std::complex<double>;
using Matrix2c = Eigen::Matrix<Complex, 2, 2>;

/// One vibration mode acting along a unit direction in the machine X-Y plane
/// (X = feed direction, Y = its normal in the cutting plane).
struct Mode {
  double natural_frequency_hz = 0.0;  ///< f_i > 0, Hz.
  double damping_ratio = 0.0;         ///< ζ_i, in (0, 1).
  double stiffness_n_per_m = 0.0;     ///< modal stiffness k_i > 0, N/m.
  Eigen::Vector2d direction{1.0, 0.0};  ///< unit vector u_i (normalised by from_stiffness / from_mass).

  /// Builds a mode from stiffness, normalising `direction`.
  /// @throws InputError if a value is non-physical (f, k <= 0,
  ///         ζ outside (0,1), zero direction).
  static Mode from_stiffness(double frequency_hz, double damping_ratio, double stiffness_n_per_m,
                             Eigen::Vector2d direction);
  /// Builds a mode from modal mass m (kg): k = m ω².
  static Mode from_mass(double frequency_hz, double damping_ratio, double mass_kg,
                        Eigen::Vector2d direction);

  double omega() const;      ///< ω_i = 2π f_i, rad/s.
  double mass_kg() const;    ///< modal mass m_i = k_i / ω_i², kg.

  /// Scalar receptance of the mode along its own direction, m/N:
  /// 1 / (k (1 − r² + 2jζr)), r = ω/ω_i.
  Complex receptance(double omega_rad_s) const;
};

/// First bending mode of a cantilever bar of circular section (clamped at one
/// end, force at the free end): k = 3EI/L³, ω = (1.8751²/L²)·√(EI/(ρA)),
/// I = πD⁴/64, A = πD²/4. Modal mass k/ω² (not the bar's mass ρAL). This is
/// how the seed thesis (table IV.1, docs/physics.md case B) derives its workpiece modes.
struct CantileverBar {
  double youngs_modulus_pa = 0.0;   ///< E > 0, Pa.
  double density_kg_per_m3 = 0.0;   ///< ρ > 0, kg/m³.
  double length_m = 0.0;            ///< L > 0, m.
  double diameter_m = 0.0;          ///< D > 0, m.
};
/// @throws InputError on a non-positive field or ζ outside (0,1).
Mode first_bending_mode(const CantileverBar& bar, double damping_ratio, Eigen::Vector2d direction);

/// One measured receptance term of a body (e.g. a tap test), m/N, tabulated
/// at frequency lines (Hz, strictly increasing). Between lines the dynamic
/// stiffness 1/G is interpolated by a cubic through the four nearest lines:
/// exact for a single mode (1/G = k(1 − r² + 2jζr) is quadratic in ω), so
/// resonances are kept rather than flattened as a linear interpolation of G
/// would. Outside the measured range the term is unknown: solvers restrict
/// their search to the range (see StructuralModel::measured_band).
struct MeasuredTerm {
  int row = 0;  ///< 0 = x, 1 = y (response direction)
  int col = 0;  ///< 0 = x, 1 = y (force direction); xy also stands for yx (reciprocity)
  std::vector<double> frequency_hz;
  std::vector<Complex> receptance;  ///< m/N, one per line
  std::string source;               ///< file (and record) it came from, for messages
  /// Interpolated value at ω (rad/s); 0 outside the measured range.
  Complex at(double omega_rad_s) const;
};

/// A body: modes and/or measured receptance terms (none of either = rigid).
struct Body {
  std::vector<Mode> modes;
  std::vector<MeasuredTerm> measured;
  bool rigid() const { return modes.empty() && measured.empty(); }
  /// 2×2 receptance Σ u uᵀ / (k (1 − r² + 2jζr)) plus the measured terms, m/N.
  Matrix2c receptance(double omega_rad_s) const;
};

/// The two-body structure seen by the cutting process.
struct StructuralModel {
  Body tool;
  Body workpiece;

  /// Relative receptance G = G_tool + G_workpiece (m/N): the chip depends on
  /// tool − workpiece displacement and the force acts equal and opposite.
  Matrix2c receptance(double omega_rad_s) const;

  std::size_t mode_count() const { return tool.modes.size() + workpiece.modes.size(); }
  /// True when either body holds measured terms (then only the
  /// transfer-function solver `analytic` applies; fit modes for the others).
  bool has_measured() const { return !tool.measured.empty() || !workpiece.measured.empty(); }
  /// True when both bodies are rigid.
  bool rigid() const { return tool.rigid() && workpiece.rigid(); }
  /// Frequency range (rad/s) covered by every measured term (their
  /// intersection); {0, +inf} without measured terms.
  std::pair<double, double> measured_band() const;
  /// Coarsest line spacing (Hz) among the measured terms; 0 without.
  double frequency_resolution_hz() const;
  /// Lowest and highest natural frequency over both bodies, rad/s (the
  /// measured range when there are measured terms). @pre !rigid().
  double min_omega() const;
  double max_omega() const;
};

/// Modal view of the model (docs/physics.md §2): n modal coordinates q, tool modes
/// first then workpiece modes, each mass-normalised so that
///   q̈_i + 2ζ_i ω_i q̇_i + ω_i² q_i = (1/m_i) s_i u_iᵀ F(t),
/// and relative displacement r = S q with column i of S equal to s_i u_i
/// (s_i = +1 tool, −1 workpiece).
struct ModalMatrices {
  Eigen::VectorXd omega;         ///< ω_i, rad/s.
  Eigen::VectorXd damping_ratio; ///< ζ_i.
  Eigen::VectorXd mass_kg;       ///< m_i, kg.
  Eigen::Matrix<double, 2, Eigen::Dynamic> S;  ///< 2×n, r = S q (m per unit q).
};
ModalMatrices modal_matrices(const StructuralModel& model);

/// First-order state-space form, state x = [q; q̇] (2n):
///   ẋ = A x + B F,   r = C x,
/// with F the force on the tool (N, 2-vector) and r the relative displacement
/// (m). C (jωI − A)⁻¹ B equals StructuralModel::receptance(ω).
struct StateSpace {
  Eigen::MatrixXd A;  ///< 2n × 2n.
  Eigen::MatrixXd B;  ///< 2n × 2.
  Eigen::MatrixXd C;  ///< 2 × 2n.
};
StateSpace state_space(const StructuralModel& model);

}  // namespace chatter
