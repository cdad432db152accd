// The simulated stock of `chatter program` (docs/program.md): what a feed
// move engages, and what it leaves for the next one.
//
//  - BarStock (turning): the radius profile r(z) of a bar held in a chuck,
//    on cells of `resolution` along z. The tool is a right-hand turning
//    insert: its nose at (z, x) and its body in the quadrant z' >= z,
//    x' >= x, so a move leaves r(z') = min(r(z'), x_p) for every path point
//    p with z_p <= z' (a longitudinal pass turns the diameter down behind
//    the nose, a facing pass removes what lies beyond it toward the face).
//    A point's depth of cut: radial, r(z) − x, on a longitudinal move; axial,
//    the length of material beyond z at radius x, on a facing move (more X
//    than Z travel).
//  - ZMapStock (3-axis milling): a height field z_top(i, j) on square cells
//    of `resolution`, swept by the tool's lower envelope (flat: its tip
//    plane; ball z_tip + R − √(R² − ρ²); bull nose the torus). At a tool
//    position, a cell inside the tool's disk is in contact where the
//    envelope is below z_top; the engaged arc is the hull of the contact
//    cells' angles on the leading half of the cutter (§3's φ, clockwise from
//    the normal left of the feed, M3), the axial depth max(z_top) − z_tip
//    over the contact; then the envelope lowers the cells.
//
// Both are exact for the volumes they remove to the cell size: a straight
// slot removes D a_p L, a side pass a_e a_p L, a turned cylinder
// π/4 (D₀² − D₁²) L (tests/test_stock.cpp). Units: mm; angles in rad.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace chatter {

// ============================================================== turning

/// What a lathe's tool nose meets at one point of a move.
struct TurningEngagement {
  double depth_mm = 0.0;     ///< depth of cut (radial on a longitudinal move, axial facing), mm; 0 = air
  double diameter_mm = 0.0;  ///< the stock's diameter where the nose cuts (before the cut), mm
  bool facing = false;       ///< the move runs more along X than along Z
};

class BarStock {
 public:
  /// A bar of `diameter_mm` from the chuck at face_z_mm − length_mm to its
  /// face at face_z_mm, on cells of `resolution_mm` along z.
  /// @throws InputError if a length is not finite and > 0, or the cells
  ///         would number more than 10⁷.
  BarStock(double diameter_mm, double length_mm, double face_z_mm, double resolution_mm);

  /// The engagement of the nose at (z, x) moving along (dz, dx) (any scale).
  TurningEngagement engagement(double z_mm, double x_mm, double dz, double dx) const;
  /// Removes what the tool's quadrant sweeps along the polyline `points`
  /// (z, x) in order; returns the volume removed, mm³.
  double sweep(const std::vector<Eigen::Vector2d>& points);

  double radius_at(double z_mm) const;  ///< r(z), mm (0 outside the bar)
  double volume_mm3() const;            ///< π Σ r² dz
  double chuck_z_mm() const { return z0_; }
  double face_z_mm() const { return z0_ + length_; }
  double length_mm() const { return length_; }
  double resolution_mm() const { return dz_; }

 private:
  long cell(double z_mm) const;  // index of the cell holding z, −1 below, n above
  double z0_, length_, dz_;
  std::vector<double> r_;        // radius of each cell, mm
};

// ============================================================== milling

/// The cutter's lower envelope (from a tool config's process).
struct MillShape {
  double radius_mm = 0.0;         ///< R = D/2
  double corner_radius_mm = 0.0;  ///< 0 flat, R a ball, in between a bull nose
  double flute_length_mm = 0.0;   ///< caps the axial depth (0 = not known: no cap)
  /// Height of the envelope above the tip at radial distance rho <= R, mm.
  double envelope_mm(double rho_mm) const;
};

/// What the cutter engages at one position.
struct MillingEngagement {
  bool contact = false;          ///< some cell in the disk is above the envelope
  double axial_depth_mm = 0.0;   ///< max(z_top) − z_tip over the contact (capped by the flute length)
  /// The engaged arc on the leading half, rad, clockwise from the normal
  /// left of the feed: [entry, exit] ⊂ [0, π]; the ends snap to 0 and π
  /// within one cell of the cutter's rim. Valid when contact and not plunge.
  double entry_rad = 0.0, exit_rad = 0.0;
  /// The arcs' width across the feed: R Σ (cos entry − cos exit), mm.
  double radial_depth_mm = 0.0;
  /// The engaged arcs themselves, sorted, [entry, exit] ⊂ [0, π]: one
  /// (= [entry_rad, exit_rad]) unless material lies on both sides of a gap
  /// on the leading half (a pass across an earlier slot), then one per run
  /// of material, the first starting at entry_rad and the last ending at
  /// exit_rad. The inner ends are on the contact cells' angles, to about a
  /// cell over R (the gap test's resolution, 1°).
  std::vector<std::pair<double, double>> arcs_rad;
  bool split = false;            ///< more than one arc
  bool plunge = false;           ///< moving along Z (no XY direction): reported as a slot
  double removed_mm3 = 0.0;      ///< the volume the envelope took at this position
};

class ZMapStock {
 public:
  /// A box [min, max] (mm) on square cells of `resolution_mm`.
  /// @throws InputError if the box is empty, a value not finite, the
  ///         resolution <= 0 or the cells would number more than 4·10⁸.
  ZMapStock(const Eigen::Vector3d& min_mm, const Eigen::Vector3d& max_mm, double resolution_mm);

  /// At tool tip `tip` moving along `feed_xy` (unit, or zero for a plunge)
  /// with a cutter turning clockwise seen from +Z (M3; `clockwise` false
  /// mirrors the angles): the engagement, then the cut (z_top lowered to
  /// the envelope inside the disk). Cost O((R / resolution)²).
  MillingEngagement cut(const Eigen::Vector3d& tip, const Eigen::Vector2d& feed_xy, const MillShape& tool,
                        bool clockwise = true);

  double volume_mm3() const;             ///< Σ (z_top − z_min) cell area
  double height_at(double x_mm, double y_mm) const;  ///< z_top of the cell holding (x, y); z_min outside
  double resolution_mm() const { return h_; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }

 private:
  Eigen::Vector3d min_, max_;
  double h_;
  int nx_, ny_;
  std::vector<float> top_;  // z_top, mm, row-major (j * nx + i)
};

}  // namespace chatter
