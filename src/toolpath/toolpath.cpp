// Geometry of a feed move (chatter/toolpath.hpp): straight lines and the
// interpreter's arcs (helical, several turns, a radius that may change
// slightly from start to end: interpolated linearly, as the controller does).
#include "chatter/toolpath.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace chatter {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The plane's (first, second, axis) coordinate indices in (x, y, z).
struct PlaneAxes {
  int first, second, axis;
};
PlaneAxes axes(ArcPlane p) {
  switch (p) {
    case ArcPlane::kXY: return {0, 1, 2};
    case ArcPlane::kXZ: return {2, 0, 1};
    case ArcPlane::kYZ: return {1, 2, 0};
  }
  return {0, 1, 2};
}

struct ArcShape {
  PlaneAxes ax;
  double r0, r1;       // radius at the start and the end, mm
  double theta0;       // start angle in the (first, second) plane, rad
  double sweep;        // signed angle swept (> 0 counter-clockwise), rad
};

ArcShape arc_shape(const ToolpathMove& m) {
  ArcShape a{axes(m.plane), 0, 0, 0, 0};
  const double s1 = m.start[a.ax.first] - m.centre[a.ax.first], s2 = m.start[a.ax.second] - m.centre[a.ax.second];
  const double e1 = m.end[a.ax.first] - m.centre[a.ax.first], e2 = m.end[a.ax.second] - m.centre[a.ax.second];
  a.r0 = std::hypot(s1, s2);
  a.r1 = std::hypot(e1, e2);
  a.theta0 = std::atan2(s2, s1);
  const double theta1 = std::atan2(e2, e1);
  const int extra = std::max(std::abs(m.turns), 1) - 1;
  if (m.turns >= 0) {
    double d = theta1 - a.theta0;
    while (d <= 0.0) d += kTwoPi;  // a full circle when start = end
    a.sweep = d + extra * kTwoPi;
  } else {
    double d = theta1 - a.theta0;
    while (d >= 0.0) d -= kTwoPi;
    a.sweep = d - extra * kTwoPi;
  }
  return a;
}

}  // namespace

double move_length_mm(const ToolpathMove& m) {
  if (!m.arc) return (m.end - m.start).norm();
  const ArcShape a = arc_shape(m);
  const double planar = std::abs(a.sweep) * 0.5 * (a.r0 + a.r1);
  const double along = m.end[a.ax.axis] - m.start[a.ax.axis];
  return std::hypot(planar, along);
}

Eigen::Vector3d move_point(const ToolpathMove& m, double s) {
  s = std::clamp(s, 0.0, 1.0);
  if (!m.arc) return m.start + s * (m.end - m.start);
  if (s == 1.0) return m.end;
  const ArcShape a = arc_shape(m);
  const double r = a.r0 + s * (a.r1 - a.r0), th = a.theta0 + s * a.sweep;
  Eigen::Vector3d p;
  p[a.ax.first] = m.centre[a.ax.first] + r * std::cos(th);
  p[a.ax.second] = m.centre[a.ax.second] + r * std::sin(th);
  p[a.ax.axis] = m.start[a.ax.axis] + s * (m.end[a.ax.axis] - m.start[a.ax.axis]);
  return p;
}

Eigen::Vector2d move_direction_xy(const ToolpathMove& m, double s) {
  Eigen::Vector3d t;
  if (!m.arc) {
    t = m.end - m.start;
  } else {
    const ArcShape a = arc_shape(m);
    const double r = a.r0 + s * (a.r1 - a.r0), th = a.theta0 + s * a.sweep;
    t.setZero();
    t[a.ax.first] = -r * std::sin(th) * a.sweep + (a.r1 - a.r0) * std::cos(th);
    t[a.ax.second] = r * std::cos(th) * a.sweep + (a.r1 - a.r0) * std::sin(th);
    t[a.ax.axis] = m.end[a.ax.axis] - m.start[a.ax.axis];
  }
  const Eigen::Vector2d xy(t[0], t[1]);
  const double n = xy.norm();
  // Along Z (a plunge) when the XY travel is a vanishing part of the move.
  if (!(n > 1e-9 * std::max(1.0, t.norm()))) return Eigen::Vector2d::Zero();
  return xy / n;
}

double move_spindle_rpm(const ToolpathMove& m, double s) {
  if (m.surface_speed_m_per_min <= 0.0) return m.spindle_rpm;
  const double radius_mm = std::abs(move_point(m, s)[0]);
  // N = 1000 V / (π D), D = 2 |x| in mm.
  const double n = radius_mm > 0.0 ? 1000.0 * m.surface_speed_m_per_min / (std::numbers::pi * 2.0 * radius_mm)
                                   : std::numeric_limits<double>::infinity();
  if (m.css_max_rpm > 0.0) return std::min(n, m.css_max_rpm);
  return std::isfinite(n) ? n : 0.0;
}

}  // namespace chatter
