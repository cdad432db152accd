// The simulated stock of `chatter program` (chatter/stock.hpp) against
// closed forms and an independent construction: the slot's and the side
// pass's arcs (docs/physics.md §3), the removed volumes D a_p L, a_e a_p L
// and π/4 (D₀² − D₁²) L, and the arc at a slot's corner from the tool's rim
// intersected with the remaining material, built here point by point.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "chatter/stock.hpp"
#include "chatter/toolpath.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// Runs a straight move through the Z-map at one-cell steps; returns the
// engagement at the sample nearest `at` (fraction of the move).
MillingEngagement run_line(ZMapStock& s, Eigen::Vector3d a, Eigen::Vector3d b, const MillShape& tool, double at,
                           double* removed = nullptr) {
  const double len = (b - a).norm();
  const int n = static_cast<int>(std::ceil(len / s.resolution_mm()));
  const Eigen::Vector2d f = Eigen::Vector2d(b.x() - a.x(), b.y() - a.y()).normalized();
  MillingEngagement keep;
  double total = 0.0;
  for (int k = 1; k <= n; ++k) {
    const double u = static_cast<double>(k) / n;
    const MillingEngagement e = s.cut(a + u * (b - a), f, tool);
    total += e.removed_mm3;
    if (k == static_cast<int>(std::lround(at * n))) keep = e;
  }
  if (removed) *removed = total;
  return keep;
}

// The independent construction of an engaged arc: the span [lo, hi] of the
// angles φ (0.01° apart, clockwise from n̂) at which a point just inside the
// rim of a tool of radius R at c (the Z-map sees cells whose centres are in
// the disk) lies in `material`; f̂ the feed, n̂ 90° left of it.
template <class Material>
std::pair<double, double> rim_span(const Eigen::Vector2d& c, double R, double h, const Eigen::Vector2d& f,
                                   const Material& material) {
  const Eigen::Vector2d n(-f.y(), f.x());
  double lo = kPi, hi = 0.0;
  for (int k = 1; k < 18000; ++k) {
    const double phi = k * 0.01 * kDeg;
    if (material(Eigen::Vector2d(c + (R - 0.5 * h) * (std::cos(phi) * n + std::sin(phi) * f)))) {
      lo = std::min(lo, phi);
      hi = std::max(hi, phi);
    }
  }
  return {lo, hi};
}

TEST(ZMapStock, SlotIsHalfACircleAndRemovesDApL) {
  const double h = 0.05, D = 10.0, ap = 3.0, L = 100.0;
  ZMapStock s({0, 0, 0}, {L, 50, 20}, h);
  const double v0 = s.volume_mm3();
  MillShape tool{0.5 * D, 0.0, 0.0};
  double removed = 0.0;
  const MillingEngagement e = run_line(s, {-10, 25, 20 - ap}, {L + 10, 25, 20 - ap}, tool, 0.5, &removed);
  EXPECT_TRUE(e.contact);
  EXPECT_DOUBLE_EQ(e.entry_rad, 0.0);
  EXPECT_DOUBLE_EQ(e.exit_rad, kPi);
  EXPECT_NEAR(e.axial_depth_mm, ap, 1e-5);
  EXPECT_NEAR(e.radial_depth_mm, D, 1e-12);
  // D a_p L, to the cells on the slot's two walls (one cell each, at most).
  const double exact = D * ap * L, err = 2.0 * h * ap * L;
  EXPECT_NEAR(v0 - s.volume_mm3(), exact, err) << "removed " << v0 - s.volume_mm3();
  EXPECT_NEAR(removed, v0 - s.volume_mm3(), 1e-6 * exact);
}

TEST(ZMapStock, SidePassIsTheDownMillingArcAndRemovesAeApL) {
  const double h = 0.05, D = 10.0, R = 5.0, ap = 4.0, L = 80.0;
  for (const double ae : {1.0, 2.5, 5.0, 8.0}) {
    ZMapStock s({0, 0, 0}, {L, 40, 10}, h);
    const double v0 = s.volume_mm3();
    // Feed +x with the material on the right (y below the tool): down milling.
    const double y = 40.0 + R - ae;
    MillShape tool{R, 0.0, 0.0};
    const MillingEngagement e = run_line(s, {-10, y, 10 - ap}, {L + 10, y, 10 - ap}, tool, 0.5);
    const double entry = std::acos(2.0 * ae / D - 1.0);
    // A wall known to a cell: the angle to h / (R sin φ) (and 1.5 cells of snap).
    const double tol = 1.5 * h / (R * std::max(0.2, std::sin(entry)));
    EXPECT_NEAR(e.entry_rad, entry, tol) << "a_e " << ae;
    EXPECT_DOUBLE_EQ(e.exit_rad, kPi);
    EXPECT_NEAR(e.radial_depth_mm, ae, 2.0 * h) << "a_e " << ae;
    EXPECT_NEAR(v0 - s.volume_mm3(), ae * ap * L, 2.0 * h * ap * L) << "a_e " << ae;
  }
}

TEST(ZMapStock, UpMillingMirrorsTheArc) {
  const double h = 0.05, R = 5.0, ae = 2.0;
  ZMapStock s({0, 0, 0}, {60, 40, 10}, h);
  // Feed −x along the same wall: the material is now on the left (up milling).
  const double y = 40.0 + R - ae;
  const MillingEngagement e = run_line(s, {70, y, 8}, {-10, y, 8}, MillShape{R, 0.0, 0.0}, 0.5);
  EXPECT_DOUBLE_EQ(e.entry_rad, 0.0);
  EXPECT_NEAR(e.exit_rad, std::acos(1.0 - 2.0 * ae / (2 * R)), 1.5 * h / (R * 0.8));
}

// The corner where a slot turns 90°: the arc by an independent construction
// (rim points at 0.01° tested against the remaining material, the box minus
// the first leg's swept strip and end disk), against the Z-map's.
TEST(ZMapStock, SlotCornerArcMatchesTheRimAgainstTheRemainingMaterial) {
  const double h = 0.04, R = 5.0, z = 7.0;
  ZMapStock s({0, 0, 0}, {100, 100, 10}, h);
  const MillShape tool{R, 0.0, 0.0};
  run_line(s, {40, -10, z}, {40, 60, z}, tool, 1.0);  // first leg along +y
  const Eigen::Vector2d f(1, 0);
  auto material = [&](const Eigen::Vector2d& q) {
    if (q.x() < 0 || q.x() > 100 || q.y() < 0 || q.y() > 100) return false;
    const bool strip = std::abs(q.x() - 40.0) <= R && q.y() <= 60.0;
    const bool disk = (q - Eigen::Vector2d(40, 60)).norm() <= R;
    return !(strip || disk);
  };
  for (const double dx : {0.5, 2.0, 4.0}) {
    const Eigen::Vector2d c(40 + dx, 60);
    const auto [lo, hi] = rim_span(c, R, h, f, material);
    ZMapStock copy = s;
    const MillingEngagement e = copy.cut({c.x(), c.y(), z}, f, tool);
    const double tol = 3.0 * h / R + 0.5 * kDeg;
    EXPECT_NEAR(e.entry_rad, lo, tol) << "dx " << dx;
    EXPECT_NEAR(e.exit_rad, hi, tol) << "dx " << dx;
  }
}

// The inside corner of a pocket: a region cleared by four raster passes
// (y = 10 … 34, x up to 60), then a side pass along its wall at y = 40
// (a_e = 6 mm on the left) that runs into the wall ahead (the end caps of
// the earlier passes). The remaining material is built here from the passes
// as capsules (a point is cut when it lies within R of a pass's segment);
// the arc is the rim's span over that material. Far from the corner it is
// the side pass's arc, and it rises as the tool meets the wall ahead.
TEST(ZMapStock, PocketInsideCornerArcRisesAsThePolygonGives) {
  const double h = 0.05, R = 5.0, z = 7.0;
  ZMapStock s({0, 0, 0}, {100, 100, 10}, h);
  const MillShape tool{R, 0.0, 0.0};
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> passes;
  for (const double y : {10.0, 18.0, 26.0, 34.0}) {
    run_line(s, {-10, y, z}, {60, y, z}, tool, 1.0);
    passes.push_back({{-10, y}, {60, y}});
  }
  auto within = [&](const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (q - (a + t * ab)).norm() <= R;
  };
  const Eigen::Vector2d f(1, 0);
  double first_width = 0.0;
  for (const double x : {40.0, 58.0, 60.0, 62.0}) {
    ZMapStock copy = s;
    run_line(copy, {-10, 40, z}, {x - h, 40, z}, tool, 1.0);
    auto material = [&](const Eigen::Vector2d& q) {
      if (q.x() < 0 || q.x() > 100 || q.y() < 0 || q.y() > 100) return false;
      // The pass's own trail lies behind the tool (x' ≤ x): the leading half
      // meets only what the earlier passes left.
      for (const auto& [a, b] : passes)
        if (within(q, a, b)) return false;
      return true;
    };
    const Eigen::Vector2d c(x, 40);
    const auto [lo, hi] = rim_span(c, R, h, f, material);
    const MillingEngagement e = copy.cut({c.x(), c.y(), z}, f, tool);
    const double tol = 3.0 * h / R + 0.5 * kDeg;
    EXPECT_NEAR(e.entry_rad, lo, tol) << "x " << x;
    EXPECT_NEAR(e.exit_rad, hi, tol) << "x " << x;
    if (x == 40.0) {
      // Away from the corner: the side pass at a_e = 6 on the left: 0 … acos(1 − a_e/R) from n̂.
      EXPECT_NEAR(e.entry_rad, 0.0, tol);
      EXPECT_NEAR(e.exit_rad, std::acos(1.0 - 6.0 / R), tol);
      first_width = e.exit_rad - e.entry_rad;
    } else {
      // Nearer the wall ahead, a wider arc than the last position's.
      EXPECT_GT(e.exit_rad - e.entry_rad, first_width + 5 * kDeg) << "x " << x;
      first_width = e.exit_rad - e.entry_rad;
    }
  }
}

// A pass that widens an earlier slot: a 10 mm slot along X, then a 16 mm
// cutter down its middle. The material is on both sides of the slot, so the
// leading half meets two arcs with the slot between them: on the rim
// y = 40 + R cos φ, material where |R cos φ| > 5, i.e. [0, acos(5/R)] and
// [π − acos(5/R), π]; their width across the feed R Σ (cos en − cos ex) is
// the 2 × 3 mm the pass adds.
TEST(ZMapStock, WideningASlotGivesTwoArcs) {
  const double h = 0.05, z = 7.0, R = 8.0;
  ZMapStock s({0, 0, 0}, {100, 100, 10}, h);
  run_line(s, {-10, 40, z}, {110, 40, z}, MillShape{5.0, 0.0, 0.0}, 1.0);
  const MillingEngagement e = run_line(s, {-10, 40, z}, {60, 40, z}, MillShape{R, 0.0, 0.0}, 1.0);
  ASSERT_TRUE(e.split);
  ASSERT_EQ(e.arcs_rad.size(), 2u);
  const double inner = std::acos(5.0 / R), tol = 3.0 * h / R + 0.5 * kDeg;
  EXPECT_NEAR(e.arcs_rad[0].first, 0.0, tol);
  EXPECT_NEAR(e.arcs_rad[0].second, inner, tol);
  EXPECT_NEAR(e.arcs_rad[1].first, kPi - inner, tol);
  EXPECT_NEAR(e.arcs_rad[1].second, kPi, tol);
  EXPECT_DOUBLE_EQ(e.entry_rad, e.arcs_rad[0].first);  // the hull
  EXPECT_DOUBLE_EQ(e.exit_rad, e.arcs_rad[1].second);
  EXPECT_NEAR(e.radial_depth_mm, 6.0, 2.0 * h);
}

TEST(ZMapStock, BallEnvelopeAndFlatCap) {
  MillShape ball{5.0, 5.0, 0.0};
  EXPECT_DOUBLE_EQ(ball.envelope_mm(0.0), 0.0);
  EXPECT_NEAR(ball.envelope_mm(3.0), 5.0 - 4.0, 1e-12);
  MillShape bull{5.0, 2.0, 0.0};
  EXPECT_DOUBLE_EQ(bull.envelope_mm(2.9), 0.0);
  EXPECT_NEAR(bull.envelope_mm(5.0), 2.0, 1e-12);
  // A ball slot 2 mm deep cuts a circular segment: area R² acos((R−d)/R) − (R−d)√(2Rd − d²).
  const double h = 0.04, R = 5.0, d = 2.0, L = 40.0;
  ZMapStock s({0, 0, 0}, {L, 20, 10}, h);
  const double v0 = s.volume_mm3();
  run_line(s, {-6, 10, 10 - d}, {L + 6, 10, 10 - d}, ball, 0.5);
  const double seg = R * R * std::acos((R - d) / R) - (R - d) * std::sqrt(2 * R * d - d * d);
  EXPECT_NEAR(v0 - s.volume_mm3(), seg * L, 0.01 * seg * L);
}

TEST(BarStock, TurnedCylinderRemovesItsAnnulusAtEveryPosition) {
  const double D0 = 40.0, L = 100.0, h = 0.05;
  BarStock bar(D0, L, 0.0, h);
  const double v0 = bar.volume_mm3();
  EXPECT_NEAR(v0, kPi / 4 * D0 * D0 * L, 1e-9 * v0);
  // A longitudinal pass at radius 18 from z = 2 to z = −60: depth 2 everywhere.
  for (const double z : {-1.0, -30.0, -59.0}) {
    const TurningEngagement e = bar.engagement(z, 18.0, -1.0, 0.0);
    EXPECT_DOUBLE_EQ(e.depth_mm, 2.0);
    EXPECT_DOUBLE_EQ(e.diameter_mm, D0);
    EXPECT_FALSE(e.facing);
  }
  bar.sweep({{2.0, 18.0}, {-60.0, 18.0}});
  EXPECT_NEAR(v0 - bar.volume_mm3(), kPi / 4 * (D0 * D0 - 36.0 * 36.0) * 60.0, kPi / 4 * (D0 * D0 - 36.0 * 36.0) * h);
  EXPECT_DOUBLE_EQ(bar.radius_at(-30.0), 18.0);
  EXPECT_DOUBLE_EQ(bar.radius_at(-70.0), 20.0);
  // The next pass meets the new profile: (36 − 32)/2 = 2 mm at every position.
  EXPECT_DOUBLE_EQ(bar.engagement(-10.0, 16.0, -1.0, 0.0).depth_mm, 2.0);
  // Facing 1 mm off the end: the axial depth, and π r² × 1 mm removed.
  const double before = bar.volume_mm3();
  const TurningEngagement f = bar.engagement(-1.0, 10.0, 0.0, -1.0);
  EXPECT_TRUE(f.facing);
  EXPECT_NEAR(f.depth_mm, 1.0, h);
  bar.sweep({{-1.0, 22.0}, {-1.0, -0.5}});
  EXPECT_NEAR(before - bar.volume_mm3(), kPi * 18.0 * 18.0 * 1.0, kPi * 18.0 * 18.0 * h);
}

TEST(Toolpath, ArcLengthPointsAndCss) {
  ToolpathMove m;
  m.arc = true;
  m.plane = ArcPlane::kXY;
  m.start = {10, 0, 0};
  m.end = {0, 10, -2};
  m.centre = {0, 0, 0};
  m.turns = 1;  // counter-clockwise quarter
  EXPECT_NEAR(move_length_mm(m), std::hypot(10 * kPi / 2, 2.0), 1e-12);
  const Eigen::Vector3d p = move_point(m, 0.5);
  EXPECT_NEAR(p.x(), 10 * std::cos(kPi / 4), 1e-12);
  EXPECT_NEAR(p.y(), 10 * std::sin(kPi / 4), 1e-12);
  EXPECT_NEAR(p.z(), -1.0, 1e-12);
  const Eigen::Vector2d t = move_direction_xy(m, 0.0);
  EXPECT_NEAR(t.x(), 0.0, 1e-12);
  EXPECT_NEAR(t.y(), 1.0, 1e-12);
  m.turns = -1;  // clockwise: three quarters
  EXPECT_NEAR(move_length_mm(m), std::hypot(10 * 3 * kPi / 2, 2.0), 1e-12);
  ToolpathMove css;
  css.start = {12.5, 0, 0};
  css.end = {12.5, 0, -10};
  css.surface_speed_m_per_min = 200.0;
  css.css_max_rpm = 3000.0;
  EXPECT_NEAR(move_spindle_rpm(css, 0.5), 1000.0 * 200.0 / (kPi * 25.0), 1e-9);
  css.start.x() = css.end.x() = 1.0;
  EXPECT_DOUBLE_EQ(move_spindle_rpm(css, 0.5), 3000.0);
}

}  // namespace
}  // namespace chatter
