// JOB.toml: what `chatter program` needs beside the NC program
// (docs/program.md "The job"): the stock, the tools (each an ordinary
// chatter config), the workpiece's structure and the machine.
//
//   [stock]     shape = "bar": diameter_mm, length_mm, face_z_mm (default 0),
//                              resolution_mm (default 0.1)
//               shape = "box": min_mm = [x, y, z], max_mm = [x, y, z],
//                              resolution_mm (default: smallest tool diameter / 40)
//   [[tools]]   number = N, config = "FILE.toml" (relative to JOB.toml)
//   [workpiece] modes as in any config (a cantilever follows the bar along
//               z); absent: each tool config's own workpiece
//   [machine]   rpm_min, rpm_max, max_power_kw, max_torque_nm
//   [program]   speed_tolerance_pct (default 2), cache (default true),
//               default_spindle_rpm (for a program with no S word)
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "chatter/io/config.hpp"

namespace chatter {

struct JobStock {
  enum class Shape { kBar, kBox };
  Shape shape = Shape::kBar;
  double diameter_mm = 0.0, length_mm = 0.0, face_z_mm = 0.0;  ///< bar
  Eigen::Vector3d min_mm{0, 0, 0}, max_mm{0, 0, 0};            ///< box
  std::optional<double> resolution_mm;                         ///< absent: the default of the shape
};

struct JobTool {
  int number = 0;
  std::filesystem::path config_path;  ///< as resolved (relative to JOB.toml)
  /// The tool's config, with JOB.toml's [workpiece] in place of its own
  /// when JOB.toml has one.
  Config config;
};

struct JobMachine {
  std::optional<double> rpm_min, rpm_max;          ///< rev/min
  std::optional<double> max_power_kw, max_torque_nm;
};

struct Job {
  std::filesystem::path source;
  JobStock stock;
  std::vector<JobTool> tools;   ///< in the file's order, numbers distinct
  JobMachine machine;
  double speed_tolerance = 0.02;       ///< [program] speed_tolerance_pct / 100
  bool cache = true;                   ///< [program] cache
  std::optional<double> default_spindle_rpm;  ///< [program] default_spindle_rpm
  std::vector<std::string> warnings;   ///< the tool configs' plausibility warnings, each naming its file

  const JobTool* tool(int number) const;
  bool turning() const { return stock.shape == JobStock::Shape::kBar; }
};

/// Reads JOB.toml and every tool config it names. @throws InputError naming
/// the file and key: a missing [stock] or [[tools]], an unknown key, a bad
/// value, a tool config that does not load (its own message), a turning
/// tool on a box or a milling tool on a bar, two tools with one number.
Job load_job(const std::filesystem::path& file);

}  // namespace chatter
