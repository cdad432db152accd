// Kienzle's size effect in turning (Kienzle 1952; Kienzle & Victor 1957;
// docs/cutting_law.md "Kienzle's law"): the specific force rises as the chip
// thins. Per force direction (tangential = cutting force F_c, feed = the
// in-plane force normal to the edge, radial = along the edge)
//   F = k_1.1 · b · h^(1 − m)      (b, h in mm; k_1.1 in N/mm²)
// with the chip width b and thickness h (for a straight edge at lead angle
// κ_r: h = f sin κ_r, b = a / sin κ_r, so b·h = a·f), k_1.1 the specific
// force of a 1 mm × 1 mm chip and m the exponent (0 = the linear law). The
// specific force at h is then
//   k(h) = F / (b h) = k_1.1 · h^(−m)                    (the secant)
// and the force's derivative with respect to the chip thickness, what the
// regenerative (dynamic) side of the cut sees when the chip varies about its
// mean h₀, is
//   dF/dh / b = (1 − m) · k_1.1 · h₀^(−m) = (1 − m) · k(h₀)   (the tangent).
// The static side (mean forces, torque, power, the static deflection and
// diametral error) reads the secant at the point's own feed; every linear
// stability method reads the tangent at the process's feed
// (TurningParameters::kienzle, Process::at_feed); the time-domain simulation
// integrates the nonlinear force itself (its linearisation is the tangent).
//
// Units: SI inside (N/m², m); the config's k_1.1 is in N/mm² at h = 1 mm.
#pragma once

#include <optional>
#include <string>

namespace chatter {

/// One direction of Kienzle's law.
struct KienzleTerm {
  /// k_1.1 > 0, N/m²: the specific force of a chip 1 mm thick and 1 mm wide
  /// (the config's `specific_force_n_per_mm2` × 1e6).
  double specific_force_n_per_m2 = 0.0;
  /// m in [0, 1): the exponent of the size effect (k(h) = k_1.1 h^(−m)); 0
  /// is the linear law.
  double exponent = 0.0;

  /// The secant specific force k(h) = k_1.1 (h / 1 mm)^(−m), N/m², at chip
  /// thickness h > 0 (m). @pre h > 0.
  double secant_n_per_m2(double chip_m) const;
  /// The tangent (1 − m) k(h), N/m²: dF/dh per unit chip width at h > 0.
  double tangent_n_per_m2(double chip_m) const;
  /// The force per unit chip width, secant(h)·h = k_1.1 · 1 mm · (h / 1 mm)^(1−m),
  /// N/m, for h >= 0 (0 at h = 0: no chip, no force).
  double force_per_width_n_per_m(double chip_m) const;
};

/// Kienzle's law of a turning process: the tangential direction (required:
/// the k_c1.1, m_c shops publish; torque and power), the feed direction
/// (required: what the structure in the X-Y plane feels) and the radial
/// direction when known (specific force 0 = not given).
struct KienzleLaw {
  KienzleTerm tangential;  ///< F_c, out of the model's plane: torque and power
  KienzleTerm feed;        ///< normal to the engaged edge, in the plane (K_f's direction); required
  KienzleTerm radial;      ///< along the engaged edge (K_r's direction); 0 = not given
  /// The feed per revolution (m, > 0) whose mean chip the regenerative side
  /// is linearised at: the config's `feed_per_rev_mm`, or a row's, a block's
  /// or a set-point's feed (Process::at_feed).
  double feed_m = 0.0;

  bool has_radial() const { return radial.specific_force_n_per_m2 > 0.0; }
  /// Empty when valid, else the rule broken ("kienzle: feed exponent m =
  /// 1.2: must be in [0, 1)").
  std::string validate() const;
};

}  // namespace chatter
