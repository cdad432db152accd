// `chatter program --fix-speed / --fix-feed` (docs/program.md "Fixing a
// program"): a robust stable speed for an unstable block, as `check`
// suggests one (robust_speed over the machine's range, ± the job's speed
// tolerance); a feed that brings an overloaded block to the machine's power
// and torque.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "chatter/cutting_law.hpp"
#include "chatter/operations.hpp"
#include "program_internal.hpp"

namespace chatter::program_detail {
namespace {

// Power and torque stay this far under the machine's after a feed fix.
constexpr double kFeedFixShare = 0.98;

std::string mm(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

}  // namespace

void fix_speed(ProgramRow& row, const ToolpathMove& m, const Solved& cut, const Job& job) {
  if (m.surface_speed_m_per_min > 0.0) {
    row.fix_note = "constant surface speed (G96): not changed; give this block a G97 speed";
    return;
  }
  if (!job.machine.rpm_min || !job.machine.rpm_max) {
    row.fix_note = "no speed range: give [machine] rpm_min and rpm_max in the job";
    return;
  }
  const double depth_m = row.depth_mm * 1e-3;
  const auto pocket = robust_speed(*cut.solver, *job.machine.rpm_min, *job.machine.rpm_max, depth_m,
                                   job.speed_tolerance, 1);
  if (pocket) {
    row.fixed_rpm = std::round(pocket->limit.spindle_rpm);
    return;
  }
  // No speed holds this depth: the deepest cut some speed holds over its band.
  const auto best = robust_speed(*cut.solver, *job.machine.rpm_min, *job.machine.rpm_max, 1e-6 * depth_m,
                                 job.speed_tolerance, 1);
  row.fix_note = "no speed in the machine's range is stable at " + mm(row.depth_mm) + " mm";
  if (best && std::isfinite(best->worst_limit_m))
    row.fix_note += "; " + mm(best->worst_limit_m * 1e3) + " mm holds at S" +
                    std::to_string(static_cast<long>(std::lround(best->limit.spindle_rpm))) + ": take this block in passes";
}

void fix_feed(ProgramRow& row, const ToolpathMove& m, const Solved& cut, const Job& job, int teeth, double diameter_mm,
              std::vector<std::string>& warnings) {
  const double n = row.fixed_rpm.value_or(row.spindle_rpm);
  const auto law =
      CuttingLaw::of(cut.config.process, cutting_law_options(cut.config.process, cutting_coefficient(cut.config), warnings));
  auto load = [&](double f_word_mm) {
    const double per_tooth_mm = m.feed_per_rev ? f_word_mm / teeth : f_word_mm / (n * teeth);
    return law->mean({n, row.depth_mm * 1e-3, per_tooth_mm * 1e-3, diameter_mm * 1e-3});
  };
  auto over = [&](const MeanCut& c) {
    return (job.machine.max_power_kw && c.power_w * 1e-3 > kFeedFixShare * *job.machine.max_power_kw) ||
           (job.machine.max_torque_nm && c.torque_n_m > kFeedFixShare * *job.machine.max_torque_nm);
  };
  double f = m.feed;
  MeanCut c = load(f);
  if (!over(c)) return;  // the speed's fix alone relieved it, or it is over the speed range only
  // Power and torque are linear in the feed (plus a constant edge force), or
  // with Kienzle's law go as f^(1 − m_c): the ratio first, then 1 % steps
  // until both are under.
  double ratio = 1.0;
  if (job.machine.max_power_kw) ratio = std::min(ratio, kFeedFixShare * *job.machine.max_power_kw / (c.power_w * 1e-3));
  if (job.machine.max_torque_nm) ratio = std::min(ratio, kFeedFixShare * *job.machine.max_torque_nm / c.torque_n_m);
  if (const auto& k = cut.config.process.turning_parameters().kienzle; cut.config.process.has_size_effect())
    ratio = std::pow(ratio, 1.0 / (1.0 - k->tangential.exponent));
  f *= ratio * (1.0 - 1e-9);  // just under: the share itself compares as over
  for (int i = 0; i < 100 && over(load(f)); ++i) f *= 0.99;
  if (over(load(f))) {
    row.fix_note += std::string(row.fix_note.empty() ? "" : "; ") + "no feed brings this block under the machine's power";
    return;
  }
  row.fixed_feed = f / m.unit_mm;
  row.original_feed = m.feed / m.unit_mm;  // the F word, in the program's units
}

}  // namespace chatter::program_detail
