// [sweep] of the TOML config (docs/config.md, "Sweep"), and the warnings on
// modes its speeds cannot excite in a usual lobe.
#include "config_sections.hpp"

#include <cstddef>
#include <string>
#include "chatter/kinematics.hpp"

namespace chatter::config_detail {
namespace {

// A natural frequency above this many tooth-passing frequencies at the
// fastest speed (lobe numbers above 200 everywhere: lobes narrower than a
// 400-point sweep resolves), or below the slowest tooth-passing frequency
// divided by kToothPassingOverModeMax, is out of reach of the sweep.
constexpr double kLobeNumberMax = 200.0;
constexpr double kToothPassingOverModeMax = 20.0;
// A sweep whose highest tooth-passing frequency is below 1/10 of the lowest
// natural frequency: lobe numbers above 10 everywhere.
constexpr double kSweepBelowLowestModeFactor = 10.0;

}  // namespace

SweepDefaults read_sweep(const Table& root) {
  SweepDefaults s;
  const auto sweep = root.table("sweep");
  if (!sweep) return s;
  constexpr std::string_view kSweepKeys[] = {"rpm_min", "rpm_max", "rpm_points", "depth_max_mm"};
  sweep->reject_unknown(kSweepKeys);
  s.rpm_min = sweep->number("rpm_min", kPositive);
  s.rpm_max = sweep->number("rpm_max", kPositive);
  if (s.rpm_min && s.rpm_max && !(*s.rpm_max > *s.rpm_min))
    sweep->doc().error(sweep->path_of("rpm_max"), *sweep->find("rpm_max"),
                       "must be > rpm_min (" + sweep->doc().as_written(*sweep->find("rpm_min")) + ")");
  s.rpm_points = sweep->integer("rpm_points", 2);
  s.depth_max_mm = sweep->number("depth_max_mm", kPositive);
  // Speeds and the searched depth a machine can have (docs/config.md,
  // "Plausibility warnings"): rev/s typed as rev/min falls below.
  warn_usual(*sweep, "rpm_min", s.rpm_min, usual::kSpindleSpeedRpm);
  warn_usual(*sweep, "rpm_max", s.rpm_max, usual::kSpindleSpeedRpm);
  warn_usual(*sweep, "depth_max_mm", s.depth_max_mm, usual::kSearchedDepthMm);
  if (s.rpm_points)
    warn_usual(*sweep, "rpm_points", static_cast<double>(*s.rpm_points), usual::kSweepPoints);
  return s;
}

/// Each mode's natural frequency against the tooth-passing frequencies of the
/// [sweep] speeds: a mode the sweep cannot excite in a usual lobe.
void warn_frequency_vs_speeds(const toml::table& root_table, const Document& doc, const Config& config) {
  if (!config.sweep.rpm_min || !config.sweep.rpm_max) return;
  const int z = config.process.delays_per_revolution();
  const double ftp_min = tooth_passing_hz(*config.sweep.rpm_min, z), ftp_max = tooth_passing_hz(*config.sweep.rpm_max, z);
  bool mode_warned = false;
  for (const std::string_view name : {"tool", "workpiece"}) {
    const Body& body = name == "tool" ? config.model.tool : config.model.workpiece;
    const toml::array* modes = root_table.at_path(std::string(name) + ".modes").as_array();
    if (!modes) continue;
    for (std::size_t i = 0; i < body.modes.size() && i < modes->size(); ++i) {
      const toml::table* t = modes->get(i)->as_table();
      if (!t) continue;
      const double f = body.modes[i].natural_frequency_hz;
      std::string what;
      if (f > kLobeNumberMax * ftp_max)
        what = "f is over " + number_text(kLobeNumberMax) + " times the tooth-passing frequency at sweep.rpm_max (" +
               number_text(ftp_max) + " Hz): lobe numbers above " + number_text(kLobeNumberMax) +
               " at every speed of the sweep, lobes narrower than its speed step; is the speed in rev/min (not "
               "rev/s) and the frequency in Hz (not rad/s)?";
      else if (f * kToothPassingOverModeMax < ftp_min)
        what = "f is under 1/" + number_text(kToothPassingOverModeMax) +
               " of the tooth-passing frequency at sweep.rpm_min (" + number_text(ftp_min) +
               " Hz): every speed of the sweep is far past the last lobe; is the frequency in Hz (not kHz) and "
               "the speed in rev/min?";
      if (what.empty()) continue;
      mode_warned = true;
      const Path path = element(child(Path(name), "modes"), i);
      if (const toml::node* n = t->get("frequency_hz"))
        doc.warn(child(path, "frequency_hz"), *n, what);
      else
        doc.warn_key(child(path, "cantilever"), "gives f = " + number_text(f) + " Hz: " + what);
    }
  }
  // The whole sweep far below the lowest mode (no mode said so already):
  // lobe numbers above 10 everywhere, speeds typed in rev/s?
  const double f_low = config.model.min_omega() / (2.0 * kPi);
  if (!mode_warned && f_low > 0.0 && ftp_max * kSweepBelowLowestModeFactor < f_low)
    if (const toml::node* n = root_table.at_path("sweep.rpm_max").node())
      doc.warn("sweep.rpm_max", *n,
               "the highest tooth-passing frequency of the sweep (" + number_text(ftp_max) + " Hz) is below 1/" +
                   number_text(kSweepBelowLowestModeFactor) + " of the lowest natural frequency (" +
                   number_text(f_low) + " Hz): every speed lies in the dense low-speed lobes; speeds in rev/s "
                   "instead of rev/min (x 60)?");
}

}  // namespace chatter::config_detail
