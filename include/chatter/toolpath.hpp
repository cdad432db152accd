// A part program as the cut sees it: the feed moves of an NC program, in
// program order, each with the source line it came from, the tool in the
// spindle, the spindle speed (or constant surface speed) and the feed. What
// `chatter program` checks block by block (docs/program.md).
//
// The moves are read by LinuxCNC's RS274/NGC interpreter
// (chatter/io/nc_program.hpp); this header is plain data and geometry (core
// layer), so a CAM integrator with its own toolpath can fill it directly.
//
// Units: millimetres, mm/min or mm/rev, rev/min, m/min (surface speed),
// whatever the program's G20/G21 (converted on reading). Positions are the
// controlled point: the tool tip on a mill (flat end at its bottom, a ball's
// lowest point), the insert's nose on a lathe, where X is a radius (the
// interpreter reports radii in G7 diameter mode too).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace chatter {

/// The plane of an arc (G17, G18, G19).
enum class ArcPlane { kXY, kXZ, kYZ };

/// One feed move (G1, G2/G3 and the moves the interpreter expands canned
/// cycles and cutter compensation into).
struct ToolpathMove {
  int line = 0;                      ///< 1-based line of the program the move came from (0 = not known)
  int tool = 0;                      ///< tool number in the spindle (0 = none)
  Eigen::Vector3d start{0, 0, 0};    ///< mm
  Eigen::Vector3d end{0, 0, 0};      ///< mm
  bool arc = false;                  ///< G2/G3
  ArcPlane plane = ArcPlane::kXY;    ///< the arc's plane
  Eigen::Vector3d centre{0, 0, 0};   ///< the arc's centre, mm (the axis coordinate unused)
  /// Turns of the arc: > 0 counter-clockwise, < 0 clockwise, seen from the
  /// positive end of the plane's normal in the interpreter's (first, second)
  /// axes: XY (X, Y), XZ (Z, X), YZ (Y, Z). |turns| = 1 for a partial arc.
  int turns = 0;
  double spindle_rpm = 0.0;          ///< G97 speed, rev/min (0: stopped or not set)
  /// G96: constant surface speed, m/min (0 = G97), capped at css_max_rpm.
  double surface_speed_m_per_min = 0.0;
  double css_max_rpm = 0.0;          ///< G96's D word, rev/min (0 = none)
  bool spindle_on = false;           ///< M3/M4 given and not stopped (M5)
  bool spindle_clockwise = true;     ///< M3 (clockwise seen from +Z); false = M4
  double feed = 0.0;                 ///< F, mm/min (G94) or mm/rev (G95)
  bool feed_per_rev = false;         ///< G95
  double unit_mm = 1.0;              ///< the program's length unit here, mm (25.4 with G20): for writing F back
};

/// The moves of one program, and where they came from.
struct Toolpath {
  std::string source;                ///< the program's path as given
  std::vector<ToolpathMove> moves;   ///< feed moves, in program order
  bool lathe_plane = false;          ///< the program selected G18 (XZ) before its first feed move
};

/// Length of a move's path, mm (an arc's helix included). Cost O(1).
double move_length_mm(const ToolpathMove& m);
/// The point at fraction s in [0, 1] of the path, mm. Cost O(1).
Eigen::Vector3d move_point(const ToolpathMove& m, double s);
/// The unit direction of travel in the XY plane at fraction s (the tangent
/// projected on XY, normalised); zero when the move is along Z there.
Eigen::Vector2d move_direction_xy(const ToolpathMove& m, double s);
/// Spindle speed at fraction s, rev/min: the G97 speed, or with G96 the
/// surface speed over the circumference at radius |x| (a lathe), capped at
/// css_max_rpm (at x = 0 the cap, or 0 when no cap is given).
double move_spindle_rpm(const ToolpathMove& m, double s);

}  // namespace chatter
