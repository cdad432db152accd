// The shape of a milling cutter along its axis (docs/cutter_geometry.md):
// flat end mill (the cylinder of docs/physics.md §8), ball end, bull nose
// (torus corner) or a general tabulated profile. Geometry only: the local
// radius R(z), the axial immersion (lead) angle κ(z) between the tool axis
// and the surface normal, the helix lag integral Λ(z) and the engagement of
// a slice in the cut. The force law per slice lives in Process
// (process.hpp: Process::axial_slices), which every solver reads.
//
// Heights z are measured from the tool tip upwards (m); radii in m; angles
// in rad. The model follows Lee & Altintas (1996), "Prediction of ball-end
// milling forces from orthogonal cutting data", Int. J. Mach. Tools Manuf.
// 36(9): a slice of height dz at height z has chip thickness
// h = f_t sin φ sin κ (plus the regenerative part, projected the same way),
// chip width db = dz / sin κ, and tangential, radial (along the surface
// normal) and axial forces K_t h db, K_r h db, K_a h db.
#pragma once

#include <vector>

namespace chatter {

enum class CutterGeometry { kFlat, kBall, kBullNose, kGeneral };

/// Name as written in the config ("flat", "ball", "bull_nose", "general").
const char* to_string(CutterGeometry g);

/// One row of a general profile: at height z above the tip the cutting edge
/// is at radius R and its surface normal makes the lead angle κ with the
/// tool axis (90° on a cylinder, 0 at the tip of a ball).
struct ProfilePoint {
  double height_m = 0.0;        ///< z >= 0, m; rows strictly increasing, the first at 0
  double radius_m = 0.0;        ///< R in [0, D/2], m
  double lead_angle_rad = 0.0;  ///< κ in [0, π/2], rad
};

/// The cutter's shape, as given (MillingParameters::cutter).
struct CutterProfileParameters {
  CutterGeometry geometry = CutterGeometry::kFlat;
  /// r_c, m: corner radius of a bull nose, in (0, D/2] (D/2 = a ball).
  double corner_radius_m = 0.0;
  /// Rows of a general profile (>= 2), linearly interpolated in z; above
  /// the last row the last radius and lead angle hold (a cylinder).
  std::vector<ProfilePoint> profile{};
  /// Axial slices over the depth of cut a (every method uses the same
  /// slices); 0 = kDefaultProfileSlices. In [0, kMaxProfileSlices].
  int slices = 0;
};

/// Default axial slices of a non-flat cutter: on the ball-end example
/// (configs/milling_ball_end.toml) 32 slices put the sdm limit within
/// 0.012 % of 256 slices (order ~1.3: κ ~ sqrt(z) at a ball's tip;
/// tests/test_cutter_profile_solvers.cpp).
inline constexpr int kDefaultProfileSlices = 32;
inline constexpr int kMaxProfileSlices = 2000;

/// Where one slice of a down- or up-milling cut engages: the workpiece is the
/// band between two planes parallel to the feed and to the tool axis, set
/// by a_e on the full diameter D (down: −R₀ <= y <= −R₀ + a_e; up:
/// R₀ − a_e <= y <= R₀; y = R cos φ). A slice of radius r cuts where its
/// circle lies in the band: down [arccos((2a_e/D − 1) R₀/r), π], up
/// [0, arccos((1 − 2a_e/D) R₀/r)], the cosine clamped to [−1, 1]; no cut
/// when the circle misses the band. r = R₀ gives §3's angles bit for bit;
/// slotting (a_e = D) and half immersion give them at every radius.
struct SliceEngagement {
  double entry_rad = 0.0;
  double exit_rad = 0.0;
  bool engaged = false;
};
/// @pre r >= 0, R₀ > 0, immersion a_e/D in (0, 1].
SliceEngagement slice_engagement(double radius_m, double tool_radius_m, double radial_immersion, bool down_milling);

/// The validated shape. Cost of every query O(1) (general: O(log rows)).
class CutterProfile {
 public:
  CutterProfile() = default;
  /// @throws InputError naming the rule: a non-flat geometry without a tool
  ///         radius R₀ > 0, a corner radius outside (0, R₀], a general
  ///         profile with fewer than 2 rows, a first height != 0, heights
  ///         not strictly increasing, a radius outside [0, R₀] or a lead
  ///         angle outside [0, 90°], slices outside [0, kMaxProfileSlices].
  static CutterProfile make(const CutterProfileParameters& p, double tool_radius_m);

  CutterGeometry geometry() const { return p_.geometry; }
  const CutterProfileParameters& parameters() const { return p_; }
  /// True for the flat end mill (the cylinder; Process keeps its closed forms).
  bool flat() const { return p_.geometry == CutterGeometry::kFlat; }
  int slices() const { return p_.slices > 0 ? p_.slices : kDefaultProfileSlices; }
  double tool_radius_m() const { return r0_; }

  /// R(z), m. @pre z >= 0.
  double radius_m(double z_m) const;
  /// κ(z) in [0, π/2], rad (exactly π/2 on a cylinder part).
  double lead_angle_rad(double z_m) const;
  /// Λ(z) = ∫₀ᶻ dz'/R(z'), rad per unit tan β: a helical edge of helix
  /// angle β lags its tip by tan β · Λ(z) (the lag taken on the local
  /// radius). Ball: Λ = κ(z) below the equator; cylinder: z / R₀. +inf
  /// past a general row of radius 0.
  double lag_integral(double z_m) const;
  /// True when no radius is 0 (a helix needs it: Λ is finite).
  bool finite_lag() const;

 private:
  CutterProfileParameters p_;
  double r0_ = 0.0;
  std::vector<double> lag_at_row_;  // general: Λ at each row
};

}  // namespace chatter
