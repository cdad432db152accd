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

// The interpreter's modal state while its log is read, and the checks of a
// call's numbers (each refusal names the source and the log line).
class CanonReader {
 public:
  explicit CanonReader(const std::string& source) { path_.source = source; }

  // One call of the log, at log line `log_line`.
  void apply(const CanonCall& c, int log_line) {
    line_ = log_line;
    const std::string& n = c.name;
    if (n == "USE_LENGTH_UNITS") {
      scale_ = c.raw_args.find("INCHES") != std::string::npos ? 25.4 : c.raw_args.find("CM") != std::string::npos ? 10.0 : 1.0;
      state_.unit_mm = scale_;
    } else if (n == "SELECT_PLANE") {
      plane_ = c.raw_args.find("XZ") != std::string::npos   ? ArcPlane::kXZ
               : c.raw_args.find("YZ") != std::string::npos ? ArcPlane::kYZ
                                                            : ArcPlane::kXY;
      if (path_.moves.empty()) path_.lathe_plane = plane_ == ArcPlane::kXZ;
    } else if (n == "SELECT_TOOL") {
      need(c, 1);
      selected_tool_ = count(c, 0);
    } else if (n == "CHANGE_TOOL") {
      state_.tool = selected_tool_;  // CHANGE_TOOL's argument is the table's index, not the number
    } else if (n == "SET_SPINDLE_MODE" || n == "SET_SPINDLE_SPEED") {
      spindle(c);
    } else if (n == "START_SPINDLE_CLOCKWISE" || n == "START_SPINDLE_COUNTERCLOCKWISE") {
      state_.spindle_on = true;
      state_.spindle_clockwise = n == "START_SPINDLE_CLOCKWISE";
    } else if (n == "STOP_SPINDLE_TURNING") {
      state_.spindle_on = false;
    } else if (n == "SET_FEED_MODE") {
      need(c, 2);
      state_.feed_per_rev = c.args[1] != 0.0;
    } else if (n == "SET_FEED_RATE") {
      need(c, 1);
      nonnegative(c, 0);
      state_.feed = c.args[0] * scale_;
    } else if (n == "STRAIGHT_TRAVERSE" || n == "STRAIGHT_PROBE") {
      need(c, 3);
      pos_ = Eigen::Vector3d(c.args[0], c.args[1], c.args[2]) * scale_;
    } else if (n == "STRAIGHT_FEED" || n == "ARC_FEED") {
      feed_move(c);
    }
  }

  Toolpath take() { return std::move(path_); }

 private:
  // SET_SPINDLE_MODE (G96/G97) and SET_SPINDLE_SPEED (S).
  void spindle(const CanonCall& c) {
    need(c, 2);
    if (c.name == "SET_SPINDLE_MODE") {
      // G96 D (the cap) arrives as the mode's number: > 0 is constant
      // surface speed, and the next speed is a surface speed.
      css_ = c.args[1] > 0.0;
      // Without D the interpreter sends 1e30: no cap of the program's own
      // (the machine's rpm_max caps it, docs/program.md).
      state_.css_max_rpm = css_ && c.args[1] < 1e20 ? c.args[1] : 0.0;
      if (!css_) state_.surface_speed_m_per_min = 0.0;
      return;
    }
    nonnegative(c, 1);
    if (css_) {
      // G96 S: m/min with G21, ft/min with G20.
      state_.surface_speed_m_per_min = c.args[1] * (scale_ == 25.4 ? 0.3048 : 1.0);
      state_.spindle_rpm = 0.0;
    } else {
      state_.spindle_rpm = c.args[1];
      state_.surface_speed_m_per_min = 0.0;
    }
  }

  // STRAIGHT_FEED and ARC_FEED: a move of the path (of non-zero length).
  void feed_move(const CanonCall& c) {
    ToolpathMove m = state_;
    m.line = c.block_line;
    m.start = pos_;
    if (c.name == "STRAIGHT_FEED") {
      need(c, 3);
      m.end = Eigen::Vector3d(c.args[0], c.args[1], c.args[2]) * scale_;
    } else {
      // ARC_FEED(first_end, second_end, first_centre, second_centre, rotation, axis_end, ...)
      need(c, 6);
      m.arc = true;
      m.plane = plane_;
      m.turns = count(c, 4);
      const int first = plane_ == ArcPlane::kXY ? 0 : plane_ == ArcPlane::kXZ ? 2 : 1;
      const int second = plane_ == ArcPlane::kXY ? 1 : plane_ == ArcPlane::kXZ ? 0 : 2;
      const int axis = 3 - first - second;
      m.end[first] = c.args[0] * scale_;
      m.end[second] = c.args[1] * scale_;
      m.end[axis] = c.args[5] * scale_;
      m.centre = m.end;
      m.centre[first] = c.args[2] * scale_;
      m.centre[second] = c.args[3] * scale_;
    }
    pos_ = m.end;
    if (move_length_mm(m) > 0.0) path_.moves.push_back(m);
  }

  std::string where(const CanonCall& c) const {
    return path_.source + ": interpreter log line " + std::to_string(line_) + ": " + c.name;
  }
  void need(const CanonCall& c, std::size_t n) const {
    if (c.args.size() < n)
      throw InputError(where(c) + " with " + std::to_string(c.args.size()) + " numbers, expected " +
                       std::to_string(n));
    // The interpreter writes finite numbers; "nan" or "1e400" (strtod reads
    // both) is not a coordinate, a feed or a speed (found by fuzzing).
    for (std::size_t i = 0; i < n; ++i)
      if (!(std::isfinite(c.args[i]) && std::abs(c.args[i]) <= kMaxCanonNumber))
        throw InputError(where(c) + " argument " + std::to_string(i + 1) + " is not a finite number (" +
                         c.raw_args + ")");
  }
  // A feed or speed: the interpreter writes magnitudes (the spindle's sense
  // comes from START_SPINDLE_*).
  void nonnegative(const CanonCall& c, std::size_t i) const {
    if (!(c.args[i] >= 0.0))
      throw InputError(where(c) + " argument " + std::to_string(i + 1) + " is negative (" + c.raw_args + ")");
  }
  // A count the log gives as a number (a tool number, an arc's turns): an int.
  int count(const CanonCall& c, std::size_t i) const {
    if (!(std::abs(c.args[i]) < kMaxCanonCount))
      throw InputError(where(c) + " argument " + std::to_string(i + 1) + " is not a count below 1e9 (" +
                       c.raw_args + ")");
    return static_cast<int>(c.args[i]);
  }

  Toolpath path_;
  double scale_ = 1.0;  // program units -> mm
  ArcPlane plane_ = ArcPlane::kXY;
  ToolpathMove state_;  // the modal state every move copies
  int selected_tool_ = 0;
  bool css_ = false;
  Eigen::Vector3d pos_ = Eigen::Vector3d::Zero();
  int line_ = 0;
};

}  // namespace

Toolpath parse_canon_log(const std::string& log, const std::string& source) {
  CanonReader reader(source);
  std::istringstream in(log);
  std::string l;
  int log_line = 0;
  CanonCall c;
  while (std::getline(in, l)) {
    ++log_line;
    if (parse_call(l, c)) reader.apply(c, log_line);
  }
  return reader.take();
}

}  // namespace chatter
