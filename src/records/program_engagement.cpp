// `chatter program`, first pass (docs/program.md "Engagement from the
// stock"): the stock simulated along the toolpath, each feed move sampled
// (at most one cell apart, at least kMinSamples per move), every sample's
// cut (tool, speed, engagement, position, depth, feed) recorded with the key
// its limit is solved and cached under. Sequential: the stock's state is the
// program's history.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "chatter/error.hpp"
#include "program_internal.hpp"

namespace chatter::program_detail {
namespace {

constexpr int kMinSamples = 4;
constexpr double kPi = std::numbers::pi;
// A sample cuts when its depth exceeds this, mm (a cell's float rounding).
constexpr double kMinDepthMm = 1e-4;

std::string line_text(int line) { return line > 0 ? "line " + std::to_string(line) : "a block"; }

std::string exact(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// The arc on the kArcStepDeg grid, widened outward (never narrower than the
// stock's). Returns the grid indices.
std::pair<int, int> quantised_arc(double entry_rad, double exit_rad) {
  const double step = kArcStepDeg * kPi / 180.0;
  const int top = static_cast<int>(std::lround(180.0 / kArcStepDeg));
  int en = static_cast<int>(std::floor(entry_rad / step + 1e-9));
  int ex = static_cast<int>(std::ceil(exit_rad / step - 1e-9));
  en = std::clamp(en, 0, top - 1);
  ex = std::clamp(ex, en + 1, top);
  return {en, ex};
}

// Every arc on the grid, widened outward; arcs that then touch are merged.
std::vector<std::pair<int, int>> quantised_arcs(const std::vector<std::pair<double, double>>& arcs_rad) {
  std::vector<std::pair<int, int>> out;
  for (const auto& [en, ex] : arcs_rad) {
    const std::pair<int, int> q = quantised_arc(en, ex);
    if (!out.empty() && q.first <= out.back().second)
      out.back().second = std::max(out.back().second, q.second);
    else
      out.push_back(q);
  }
  return out;
}

}  // namespace

double block_rpm(const ToolpathMove& m, double s, const Job& job) {
  double n = move_spindle_rpm(m, s);
  if (m.surface_speed_m_per_min > 0.0) {
    if (job.machine.rpm_max) n = std::min(n, *job.machine.rpm_max);
    n = std::round(n);  // a G96 speed is reported (and solved) to 1 rev/min
  }
  if (n <= 0.0 && job.default_spindle_rpm) n = *job.default_spindle_rpm;
  return n;
}

std::optional<double> cutting_coefficient(const Config& config) {
  if (config.optimization && config.optimization->cutting_coefficient_n_per_m2 > 0.0)
    return config.optimization->cutting_coefficient_n_per_m2;
  return std::nullopt;
}

ToolSetup tool_setup(const JobTool& tool, bool turning) {
  ToolSetup t;
  t.tool = &tool;
  const Process& p = tool.config.process;
  t.turning = turning;
  if (t.turning) {
    t.teeth = 1;
  } else {
    const MillingParameters& mp = p.milling_parameters();
    t.teeth = mp.teeth;
    if (!(mp.tool_diameter_m > 0.0))
      throw InputError(tool.config_path.string() + ": process.tool_diameter_mm: missing (the program's stock is "
                       "cut by the tool's diameter)");
    t.shape.radius_mm = 0.5 * mp.tool_diameter_m * 1e3;
    if (mp.cutter.geometry == CutterGeometry::kBall) t.shape.corner_radius_mm = t.shape.radius_mm;
    else if (mp.cutter.geometry == CutterGeometry::kBullNose) t.shape.corner_radius_mm = mp.cutter.corner_radius_m * 1e3;
    else if (mp.cutter.geometry == CutterGeometry::kGeneral)
      throw InputError(tool.config_path.string() + ": cutter_geometry = \"general\": the program's stock takes flat, "
                       "ball and bull-nose cutters");
    t.flat = mp.cutter.geometry == CutterGeometry::kFlat;
    if (tool.config.flute_length_m) t.shape.flute_length_mm = *tool.config.flute_length_m * 1e3;
  }
  return t;
}

std::string cut_key(int tool, double rpm, const std::vector<std::pair<int, int>>& arcs, double position_mm) {
  std::string k = std::to_string(tool) + "|" + exact(rpm) + "|";
  for (const auto& [en, ex] : arcs) k += std::to_string(en) + "-" + std::to_string(ex) + ",";
  return k + "|" + exact(position_mm);
}

Engaged simulate_stock(const Job& job, const Toolpath& path, const std::map<int, ToolSetup>& tools) {
  Engaged out;
  const bool turning = job.turning();
  std::optional<BarStock> bar;
  std::optional<ZMapStock> box;
  if (turning) {
    bar.emplace(job.stock.diameter_mm, job.stock.length_mm, job.stock.face_z_mm, job.stock.resolution_mm.value_or(0.1));
  } else {
    double smallest = std::numeric_limits<double>::infinity();
    for (const auto& [n, t] : tools) smallest = std::min(smallest, 2.0 * t.shape.radius_mm);
    box.emplace(job.stock.min_mm, job.stock.max_mm, job.stock.resolution_mm.value_or(smallest / 40.0));
  }
  const double res = turning ? bar->resolution_mm() : box->resolution_mm();
  const double start_volume = turning ? bar->volume_mm3() : box->volume_mm3();
  for (const ToolpathMove& m : path.moves) {
    ProgramRow row;
    row.line = m.line;
    row.tool = m.tool;
    row.start = m.start;
    row.end = m.end;
    row.length_mm = move_length_mm(m);
    // A program that never selects a tool runs with the job's only one.
    const int tool_number = m.tool == 0 && tools.size() == 1 ? tools.begin()->first : m.tool;
    row.tool = tool_number;
    const auto it = tools.find(tool_number);
    const int n = std::max(kMinSamples, static_cast<int>(std::ceil(row.length_mm / res)));
    std::vector<Eigen::Vector2d> polyline{{m.start.z(), m.start.x()}};
    const std::size_t row_index = out.rows.size();
    double rpm0 = 0.0;
    for (int k = 1; k <= n; ++k) {
      const double s = static_cast<double>(k) / n;
      const Eigen::Vector3d p = move_point(m, s);
      Sample smp;
      smp.row = row_index;
      if (turning) {
        polyline.emplace_back(p.z(), p.x());
        const Eigen::Vector3d d = move_point(m, std::min(1.0, s + 1e-6)) - move_point(m, std::max(0.0, s - 1e-6));
        const TurningEngagement e = bar->engagement(p.z(), p.x(), d.z(), d.x());
        smp.depth_mm = e.depth_mm;
        smp.diameter_mm = e.diameter_mm;
        smp.facing = e.facing;
        // The position along the bar, on the bar's cells (docs/program.md).
        const double cellpos = std::floor((p.z() - bar->chuck_z_mm()) / res);
        smp.position_mm = std::clamp((cellpos + 0.5) * res, 0.5 * res, job.stock.length_mm - 0.5 * res);
      } else {
        const Eigen::Vector2d f = move_direction_xy(m, s);
        const MillShape shape = it != tools.end() ? it->second.shape : MillShape{};
        const MillingEngagement e = box->cut(p, f, shape, m.spindle_clockwise);
        if (e.contact) {
          smp.depth_mm = e.axial_depth_mm;
          if (it != tools.end() && !it->second.flat && (e.split || (e.entry_rad > 0.0 && e.exit_rad < kPi))) {
            // A profile's slices take their arcs from a straight wall: the
            // hull widened to the nearer end (conservative), said in a note.
            double en = e.entry_rad, ex = e.exit_rad;
            if (en > 0.0 && ex < kPi) {
              if (en < kPi - ex)
                en = 0.0;
              else
                ex = kPi;
            }
            smp.arcs = {quantised_arc(en, ex)};
            smp.widened = true;
          } else {
            smp.arcs = quantised_arcs(e.arcs_rad);
            smp.split = smp.arcs.size() > 1;
          }
          smp.plunge = e.plunge;
        }
      }
      smp.rpm = block_rpm(m, s, job);
      if (k == 1) rpm0 = smp.rpm;
      if (smp.depth_mm > kMinDepthMm) out.samples.push_back(smp);
    }
    if (turning) bar->sweep(polyline);
    const bool cuts = !out.samples.empty() && out.samples.back().row == row_index;
    if (cuts) {
      if (it == tools.end())
        throw InputError(path.source + ":" + std::to_string(m.line) + ": " + line_text(m.line) +
                         " cuts the stock with " + (m.tool > 0 ? "tool " + std::to_string(m.tool) + ", which is not in the job's [[tools]]"
                                                                : std::string("no tool in the spindle (no T and M6 before it)")));
      if (!(rpm0 > 0.0) || (!m.spindle_on && !job.default_spindle_rpm))
        throw InputError(path.source + ":" + std::to_string(m.line) + ": " + line_text(m.line) +
                         " cuts the stock with the spindle " + (m.spindle_on ? "speed 0 (no S word)" : "stopped (no M3/M4)") +
                         ": give S and M3 before it" + (m.spindle_on ? ", or [program] default_spindle_rpm in the job" : ""));
      if (!(m.feed > 0.0))
        throw InputError(path.source + ":" + std::to_string(m.line) + ": " + line_text(m.line) +
                         " cuts the stock with feed 0 (no F word)");
    }
    out.rows.push_back(row);
  }
  const double end_volume = turning ? bar->volume_mm3() : box->volume_mm3();
  out.removed_mm3 = start_volume - end_volume;
  return out;
}

}  // namespace chatter::program_detail
