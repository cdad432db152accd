// The cutting law's static side: what a cut does on average and at its
// peak — mean force on the tool, mean tangential force, torque, power,
// material removal rate, cutting speed, largest resultant force — behind
// one interface with an implementation for turning and one for milling
// (src/model/cutting/; docs/cutting_law.md). Every command that reports one
// of these numbers (`check`, `recommend`, `optimize`/`performance`,
// `coefficients`' prediction, the forced response's turning force,
// chatter_cutting_load, Python through the records) reads it here, so a new
// process or cutter geometry is one more implementation. (The forced
// response's milling mean force is its Fourier series' zeroth term: tested
// equal to this law's.)
//
// The dynamic side — the directional matrix H(t) of the regenerative force
// and its exact integrals over a step — is Process's (chatter/process.hpp);
// both read the same force formula: milling_force_direction (per tooth and
// unit chip) and Process::edge_force (a turning insert).
//
// Mean milling forces (Altintas 2012, Manufacturing Automation, 2nd ed.,
// §2.6; Budak, Altintas & Armarego 1996): with N_t teeth, axial depth a,
// feed per tooth f, cutting coefficients K_t, K_r (N/m²) and edge
// coefficients K_te, K_re (N/m), the force on the tool averaged over a
// revolution is
//   F̄x = (N_t a / 2π) [ −f (K_t S + K_r Q) − (K_te C + K_re P) ],
//   F̄y = (N_t a / 2π) [  f (K_t Q − K_r S) + (K_te P − K_re C) ],
// and the teeth's tangential forces sum on average to
//   F̄t = (N_t a / 2π) (K_t f P + K_te W),
// with the integrals over the cutting arc [φ_en, φ_ex] (arc_integrals):
// S = ∫ sin φ cos φ, Q = ∫ sin² φ, C = ∫ cos φ, P = ∫ sin φ, W = φ_ex − φ_en.
// Torque F̄t D/2, power torque × 2πN/60 (= K_t × removal rate without edge
// forces). Neither helix nor pitch changes these means (each tooth's chip
// over a revolution is the same; the feeds of a variable pitch sum to N_t f);
// runout does (the chip is floored at zero), so with runout the means come
// from a sampled revolution. A ball-end, bull-nose or general profile is
// summed over its axial slices, each with its own arc, radius and radial
// coefficient (Process::axial_slices).
//
// Turning (docs/turning_inserts.md): the in-plane force on the tool is
// −b h d = −a f d (b h = a f for any insert), the tangential (cutting)
// force F_c = K_c a f, torque F_c D_w/2, power F_c V, V = π D_w N / 60,
// removal rate a f V. With Kienzle's size effect (chatter/kienzle.hpp) each
// coefficient is its secant k(h) = k_1.1 h^(−m) at the point's chip
// h = f sin κ_eq.
//
// Units: SI (N, N·m, W, m³/s, m/s); spindle speeds in rev/min.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "chatter/process.hpp"

namespace chatter {

/// φ_en, φ_ex (rad, clockwise from +Y) of a milling tooth for radial
/// immersion a_e/D in (0, 1] and direction (§3): down [arccos(2a_e/D − 1),
/// π], up [0, arccos(1 − 2a_e/D)]. The one definition (Process::entry_angle,
/// the shop fit's engagement). @pre radial_immersion in (0, 1].
std::pair<double, double> milling_arc_rad(double radial_immersion, MillingDirection direction);

/// The integrals over a cutting arc [φ_en, φ_ex] (rad) the mean milling
/// force is made of: also the regressors of the coefficient fit
/// (chatter/shop.hpp), so fit and prediction cannot disagree.
struct ArcIntegrals {
  double sin_cos = 0.0;   ///< S = ∫ sin φ cos φ dφ
  double sin_sq = 0.0;    ///< Q = ∫ sin² φ dφ
  double cos = 0.0;       ///< C = ∫ cos φ dφ
  double sin = 0.0;       ///< P = ∫ sin φ dφ = cos φ_en − cos φ_ex
  double width_rad = 0.0; ///< W = φ_ex − φ_en
};
ArcIntegrals arc_integrals(double entry_rad, double exit_rad);
/// The same summed over several arcs (Process::engaged_arcs): the integrals
/// are additive. One arc: exactly arc_integrals(entry, exit). @pre non-empty.
ArcIntegrals arc_integrals(const std::vector<std::pair<double, double>>& arcs);

/// Edge (ploughing) coefficients of the milling law, N/m (force per unit
/// edge length, independent of the chip); 0 = none. Only the flat cutter
/// takes them (a profile's edge force is not modelled: refused).
struct EdgeCoefficients {
  double tangential_n_per_m = 0.0;  ///< K_te >= 0
  double radial_n_per_m = 0.0;      ///< K_re >= 0
};

/// F̄ = (F̄x, F̄y), N: the mean force on the tool of N_t straight teeth over
/// the arc with integrals `I`, feed per tooth f (m), depth a (m), K_t, K_r
/// (N/m²) and edge coefficients (N/m). The formula of the header. Cost O(1).
Eigen::Vector2d milling_mean_force_n(int teeth, const ArcIntegrals& I, double feed_m, double depth_m, double kt,
                                     double kr, const EdgeCoefficients& edge = {});
/// F̄t, N: the teeth's tangential forces summed and averaged over a
/// revolution (the torque is F̄t D/2). Cost O(1).
double milling_mean_tangential_force_n(int teeth, const ArcIntegrals& I, double feed_m, double depth_m, double kt,
                                       double kte = 0.0);

/// Where a cut is evaluated.
struct CutPoint {
  double spindle_rpm = 0.0;  ///< N > 0, rev/min
  double depth_m = 0.0;      ///< a >= 0, m (axial depth in milling, depth of cut in turning)
  double feed_m = 0.0;       ///< f >= 0, m per tooth (milling) or per revolution (turning)
  /// D > 0, m: the tool's (milling) or the workpiece's (turning) diameter;
  /// NaN = unknown (every number that needs it is then NaN).
  double diameter_m = 0.0;
};

/// The cut's means over a revolution. A number the law cannot give from
/// what it was told (no diameter, no turning K_c) is NaN.
struct MeanCut {
  Eigen::Vector2d force_n{0.0, 0.0};     ///< mean in-plane force on the tool (model X, Y), N
  double tangential_force_n = 0.0;       ///< mean tangential (cutting) force, teeth summed, N
  double torque_n_m = 0.0;               ///< mean spindle torque, N·m
  double power_w = 0.0;                  ///< mean cutting power, W
  double removal_rate_m3_per_s = 0.0;    ///< material removal rate, m³/s
  double cutting_speed_m_per_s = 0.0;    ///< V = π D N / 60, m/s
};

/// Why a tangential coefficient K_c beside Kienzle's law is refused (the
/// law's tangential term is the cutting force; two would disagree).
inline constexpr const char* kKienzleTakesTheTangential =
    "a tangential coefficient K_c is given, but the process follows Kienzle's law ([process] force_law = "
    "\"kienzle\"), whose tangential term k_c1.1, m_c gives the cutting force: give one of them";

/// What the law needs beyond the Process.
struct CuttingLawOptions {
  /// K_c, N/m² (> 0): turning's tangential (cutting) coefficient, out of
  /// the model's plane; 0 = not given (tangential force, torque and power
  /// are NaN and peak_force_n refuses). Must be 0 when the process follows
  /// Kienzle's law (its tangential term gives the force). Milling ignores
  /// it (K_t is the process's).
  double turning_tangential_coefficient_n_per_m2 = 0.0;
  /// Milling edge coefficients (flat cutter only).
  EdgeCoefficients edge{};
};

/// The static cutting law of one process (turning or milling).
class CuttingLaw {
 public:
  virtual ~CuttingLaw() = default;
  /// The law of `process`. @throws InputError for a negative or non-finite
  /// K_c or edge coefficient, edge coefficients on turning or on a milling
  /// cutter with a profile.
  static std::unique_ptr<const CuttingLaw> of(const Process& process, const CuttingLawOptions& options = {});

  /// The means at `p`. @throws InputError if N <= 0, a < 0, f < 0 (or not
  /// finite) or D <= 0 (NaN is allowed: unknown). Cost O(1) (O(slices) with
  /// a profile; a sampled revolution, ~0.1 ms, with runout).
  virtual MeanCut mean(const CutPoint& p) const = 0;
  /// The largest resultant force on the tool over a revolution, N: turning
  /// |(F_c, |F̄|)|; milling the largest |F(t)| of the teeth's in-plane forces
  /// (helix by slices, runout included), 360 samples per tooth. @throws
  /// InputError as mean(), and for turning without K_c.
  virtual double peak_force_n(const CutPoint& p) const = 0;
};

}  // namespace chatter
