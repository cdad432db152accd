// Internal (not installed): the passes of `chatter program`
// (chatter/records/program.hpp): the stock simulation that gives each sample
// its cut (program_engagement.cpp), the solves and the rows
// (program_check.cpp), the record and the annotated program
// (program_records.cpp).
#pragma once

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/records/program.hpp"
#include "chatter/stock.hpp"

namespace chatter::program_detail {

/// What the stock needs of a tool, and what its cut is made of.
struct ToolSetup {
  const JobTool* tool = nullptr;
  bool turning = false;
  bool flat = true;      ///< milling: a flat end mill (arcs as given; else widened to a wall)
  int teeth = 1;
  MillShape shape;       ///< milling
};
/// `turning`: the job's stock is a bar (load_job matched every tool to it).
/// @throws InputError for a milling tool without a diameter or with a general profile.
ToolSetup tool_setup(const JobTool& tool, bool turning);

/// The tool config's turning K_c ([optimization] cutting_coefficient), when given.
std::optional<double> cutting_coefficient(const Config& config);

/// One point of a feed move that cuts.
struct Sample {
  std::size_t row = 0;        ///< index of its move
  double rpm = 0.0;           ///< rev/min, as solved and reported
  double depth_mm = 0.0;      ///< depth of cut (turning) or axial depth (milling)
  /// Milling: the engaged arcs on the kArcStepDeg grid (sorted, disjoint;
  /// one unless the stock gave material on both sides of a gap).
  std::vector<std::pair<int, int>> arcs;
  int arc_en() const { return arcs.front().first; }  ///< the hull's entry (grid index)
  int arc_ex() const { return arcs.back().second; }  ///< the hull's exit (grid index)
  bool split = false, plunge = false, widened = false;  ///< milling notes
  double position_mm = 0.0;   ///< turning: on the bar's cells
  double diameter_mm = 0.0;   ///< turning: the bar where it cuts
  bool facing = false;        ///< turning
};

/// The stock's pass over the program.
struct Engaged {
  std::vector<ProgramRow> rows;   ///< one per move: line, tool, geometry (the rest filled later)
  std::vector<Sample> samples;    ///< the cutting samples, in program order
  double removed_mm3 = 0.0;       ///< the stock's volume before minus after
};
Engaged simulate_stock(const Job& job, const Toolpath& path, const std::map<int, ToolSetup>& tools);

/// The spindle speed at fraction s of a move as the program check uses it:
/// G97's S, or G96's at the radius capped by D and the machine's rpm_max and
/// rounded to 1 rev/min; the job's default_spindle_rpm when S is 0.
double block_rpm(const ToolpathMove& m, double s, const Job& job);

/// One solved cut: its config (the tool's, with the arc or the position),
/// the solver `auto` built for it, and the limit at the sample's speed.
struct Solved {
  Config config;
  std::unique_ptr<LobeSolver> solver;
  std::string method;
  double limit_m = std::numeric_limits<double>::infinity();
};

/// --fix-speed on an unstable row: the robust stable speed (robust_speed
/// over the machine's range at the row's depth), or a note why none.
void fix_speed(ProgramRow& row, const ToolpathMove& m, const Solved& cut, const Job& job);
/// --fix-feed on an overloaded row: the F word scaled so the peak power and
/// torque (at the fixed speed when there is one) are 98 % of the machine's.
void fix_feed(ProgramRow& row, const ToolpathMove& m, const Solved& cut, const Job& job, int teeth, double diameter_mm,
              std::vector<std::string>& warnings);

/// The solve cache's key: tool, speed, arc grid indices (milling), position (turning).
std::string cut_key(int tool, double rpm, const std::vector<std::pair<int, int>>& arcs, double position_mm);

}  // namespace chatter::program_detail
