// The interpreter's canonical machining calls to feed moves
// (chatter/io/nc_program.hpp parse_canon_log). Each log line reads
//   "   18 N6     STRAIGHT_FEED(-10.0000, 0.0000, -2.0000, 0.0000, 0.0000, 0.0000)"
// (call number, the block's N word or "N.....", the call). The state the
// calls set (units, plane, tool, spindle, feed) is carried to every move.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/nc_program.hpp"

namespace chatter {
namespace {

struct CanonCall {
  int block_line = 0;          // the N word (our line number), 0 = none
  std::string name;
  std::string raw_args;        // as printed, for the CANON_* words
  std::vector<double> args;    // the numeric arguments
};

// The largest N word taken as the program's line number.
constexpr long kMaxBlockLine = 1'000'000'000;

// One log line; false when it is not a call (the interpreter's banner).
bool parse_call(const std::string& l, CanonCall& c) {
  std::istringstream is(l);
  std::string count, nword;
  if (!(is >> count >> nword)) return false;
  if (count.empty() || !std::isdigit(static_cast<unsigned char>(count[0])) || nword.empty() || nword[0] != 'N')
    return false;
  // The N word's number: 0 when absent or beyond any program's length
  // (strtol saturates where atoi overflowed: a negative line, found by fuzzing).
  const long n = std::isdigit(static_cast<unsigned char>(nword.size() > 1 ? nword[1] : '.'))
                     ? std::strtol(nword.c_str() + 1, nullptr, 10)
                     : 0;
  c.block_line = n >= 0 && n <= kMaxBlockLine ? static_cast<int>(n) : 0;
  std::string rest;
  std::getline(is, rest);
  const auto b = rest.find_first_not_of(' ');
  const auto open = rest.find('(');
  if (b == std::string::npos || open == std::string::npos) return false;
  c.name = rest.substr(b, open - b);
  const auto close = rest.rfind(')');
  c.raw_args = rest.substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1);
  c.args.clear();
  std::string tok;
  for (char& ch : c.raw_args)
    if (ch == ',') ch = ' ';
  std::istringstream as(c.raw_args);
  while (as >> tok) {
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (end && *end == '\0') c.args.push_back(v);
  }
  return true;
}

// The largest number a canonical call may carry: the interpreter's own
// "no cap" sentinel is 1e30 (SET_SPINDLE_MODE without D); beyond it the log
// is not the interpreter's.
constexpr double kMaxCanonNumber = 1e31;
// The largest tool number or count of arc turns.
constexpr double kMaxCanonCount = 1e9;

}  // namespace

Toolpath parse_canon_log(const std::string& log, const std::string& source) {
  Toolpath path;
  path.source = source;
  double scale = 1.0;  // program units -> mm
  ArcPlane plane = ArcPlane::kXY;
  ToolpathMove state;  // the modal state every move copies
  int selected_tool = 0;
  bool css = false;
  Eigen::Vector3d pos(0, 0, 0);
  std::istringstream in(log);
  std::string l;
  int log_line = 0;
  auto need = [&](const CanonCall& c, std::size_t n) {
    if (c.args.size() < n)
      throw InputError(source + ": interpreter log line " + std::to_string(log_line) + ": " + c.name + " with " +
                       std::to_string(c.args.size()) + " numbers, expected " + std::to_string(n));
    // The interpreter writes finite numbers; "nan" or "1e400" (strtod reads
    // both) is not a coordinate, a feed or a speed (found by fuzzing).
    for (std::size_t i = 0; i < n; ++i)
      if (!(std::isfinite(c.args[i]) && std::abs(c.args[i]) <= kMaxCanonNumber))
        throw InputError(source + ": interpreter log line " + std::to_string(log_line) + ": " + c.name +
                         " argument " + std::to_string(i + 1) + " is not a finite number (" + c.raw_args + ")");
  };
  // A feed or speed: the interpreter writes magnitudes (the spindle's sense
  // comes from START_SPINDLE_*).
  auto nonnegative = [&](const CanonCall& c, std::size_t i) {
    if (!(c.args[i] >= 0.0))
      throw InputError(source + ": interpreter log line " + std::to_string(log_line) + ": " + c.name +
                       " argument " + std::to_string(i + 1) + " is negative (" + c.raw_args + ")");
  };
  // A count the log gives as a number (a tool number, an arc's turns): an int.
  auto count = [&](const CanonCall& c, std::size_t i) {
    if (!(std::abs(c.args[i]) < kMaxCanonCount))
      throw InputError(source + ": interpreter log line " + std::to_string(log_line) + ": " + c.name +
                       " argument " + std::to_string(i + 1) + " is not a count below 1e9 (" + c.raw_args + ")");
    return static_cast<int>(c.args[i]);
  };
  CanonCall c;
  while (std::getline(in, l)) {
    ++log_line;
    if (!parse_call(l, c)) continue;
    const std::string& n = c.name;
    if (n == "USE_LENGTH_UNITS") {
      scale = c.raw_args.find("INCHES") != std::string::npos ? 25.4 : c.raw_args.find("CM") != std::string::npos ? 10.0 : 1.0;
      state.unit_mm = scale;
    } else if (n == "SELECT_PLANE") {
      plane = c.raw_args.find("XZ") != std::string::npos   ? ArcPlane::kXZ
              : c.raw_args.find("YZ") != std::string::npos ? ArcPlane::kYZ
                                                           : ArcPlane::kXY;
      if (path.moves.empty()) path.lathe_plane = plane == ArcPlane::kXZ;
    } else if (n == "SELECT_TOOL") {
      need(c, 1);
      selected_tool = count(c, 0);
    } else if (n == "CHANGE_TOOL") {
      state.tool = selected_tool;  // CHANGE_TOOL's argument is the table's index, not the number
    } else if (n == "SET_SPINDLE_MODE") {
      need(c, 2);
      // G96 D (the cap) arrives as the mode's number: > 0 is constant
      // surface speed, and the next speed is a surface speed.
      css = c.args[1] > 0.0;
      // Without D the interpreter sends 1e30: no cap of the program's own
      // (the machine's rpm_max caps it, docs/program.md).
      state.css_max_rpm = css && c.args[1] < 1e20 ? c.args[1] : 0.0;
      if (!css) state.surface_speed_m_per_min = 0.0;
    } else if (n == "SET_SPINDLE_SPEED") {
      need(c, 2);
      nonnegative(c, 1);
      if (css) {
        // G96 S: m/min with G21, ft/min with G20.
        state.surface_speed_m_per_min = c.args[1] * (scale == 25.4 ? 0.3048 : 1.0);
        state.spindle_rpm = 0.0;
      } else {
        state.spindle_rpm = c.args[1];
        state.surface_speed_m_per_min = 0.0;
      }
    } else if (n == "START_SPINDLE_CLOCKWISE" || n == "START_SPINDLE_COUNTERCLOCKWISE") {
      state.spindle_on = true;
      state.spindle_clockwise = n == "START_SPINDLE_CLOCKWISE";
    } else if (n == "STOP_SPINDLE_TURNING") {
      state.spindle_on = false;
    } else if (n == "SET_FEED_MODE") {
      need(c, 2);
      state.feed_per_rev = c.args[1] != 0.0;
    } else if (n == "SET_FEED_RATE") {
      need(c, 1);
      nonnegative(c, 0);
      state.feed = c.args[0] * scale;
    } else if (n == "STRAIGHT_TRAVERSE" || n == "STRAIGHT_PROBE") {
      need(c, 3);
      pos = Eigen::Vector3d(c.args[0], c.args[1], c.args[2]) * scale;
    } else if (n == "STRAIGHT_FEED" || n == "ARC_FEED") {
      ToolpathMove m = state;
      m.line = c.block_line;
      m.start = pos;
      if (n == "STRAIGHT_FEED") {
        need(c, 3);
        m.end = Eigen::Vector3d(c.args[0], c.args[1], c.args[2]) * scale;
      } else {
        // ARC_FEED(first_end, second_end, first_centre, second_centre, rotation, axis_end, ...)
        need(c, 6);
        m.arc = true;
        m.plane = plane;
        m.turns = count(c, 4);
        const int first = plane == ArcPlane::kXY ? 0 : plane == ArcPlane::kXZ ? 2 : 1;
        const int second = plane == ArcPlane::kXY ? 1 : plane == ArcPlane::kXZ ? 0 : 2;
        const int axis = 3 - first - second;
        m.end[first] = c.args[0] * scale;
        m.end[second] = c.args[1] * scale;
        m.end[axis] = c.args[5] * scale;
        m.centre = m.end;
        m.centre[first] = c.args[2] * scale;
        m.centre[second] = c.args[3] * scale;
      }
      pos = m.end;
      if (move_length_mm(m) > 0.0) path.moves.push_back(m);
    }
  }
  return path;
}

}  // namespace chatter
