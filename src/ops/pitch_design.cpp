// Variable-pitch design (include/chatter/pitch_design.hpp, docs/design_pitch.md):
// Budak's rule for the start, a scan of the family's range, then Brent's
// maximiser (src/solvers/extremum.hpp) of the worst limit over the band.
#include "chatter/pitch_design.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/solvers.hpp"
#include "chatter/kinematics.hpp"
#include "../solvers/extremum.hpp"
#include "ops_internal.hpp"

namespace chatter {

namespace {

using detail::ops::kInf;
using detail::ops::num;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * kPi;

// Brent's polish stops once ΔP is located to this fraction of step_max (at
// 12 points over a 4-tooth range of ~30°: 0.03°, below what a cutter grinder
// holds) or after kPolishEvaluations band tables.
constexpr double kPolishWidthFraction = 1e-3;
constexpr std::uintmax_t kPolishEvaluations = 20;
// Largest scan (each point is a band table).
constexpr int kMaxScanPoints = 200;
constexpr int kMaxBandPoints = 100000;
// min_pitch_ratio range: below 0.1 a gap is a tenth of the equal one (no
// room for a chip); 1 leaves no freedom.
constexpr double kMinPitchRatioLow = 0.1;

}  // namespace

std::string to_string(PitchFamily f) { return f == PitchFamily::kLinear ? "linear" : "alternating"; }

std::optional<PitchFamily> pitch_family_from_string(std::string_view name) {
  if (name == "linear") return PitchFamily::kLinear;
  if (name == "alternating") return PitchFamily::kAlternating;
  return std::nullopt;
}

std::vector<double> family_pitch_angles(PitchFamily family, int teeth, double step_rad) {
  const double mean = kTwoPi / teeth;
  std::vector<double> th(static_cast<std::size_t>(teeth));
  for (int j = 0; j < teeth; ++j)
    th[static_cast<std::size_t>(j)] = family == PitchFamily::kLinear
                                          ? mean + (j - 0.5 * (teeth - 1)) * step_rad
                                          : mean + ((j % 2 == 0) ? 0.5 : -0.5) * step_rad;
  return th;
}

double max_pitch_step_rad(PitchFamily family, int teeth, double min_pitch_ratio) {
  const double room = 4.0 * kPi * (1.0 - min_pitch_ratio);
  return family == PitchFamily::kLinear ? room / (teeth * (teeth - 1.0)) : room / teeth;
}

double budak_pitch_step_rad(PitchFamily family, int teeth, double spindle_rpm, double chatter_frequency_hz) {
  const double ratio = angular_speed_rad_per_s(spindle_rpm) / (kTwoPi * chatter_frequency_hz);  // Ω / ω_c
  return family == PitchFamily::kLinear ? kTwoPi * ratio / teeth : kPi * ratio;
}

std::string PitchDesignOptions::validate() const {
  if (!(std::isfinite(rpm_min) && rpm_min > 0.0))
    return "rpm_min = " + num(rpm_min) + ": must be > 0 rev/min";
  if (!(std::isfinite(rpm_max) && rpm_max > rpm_min))
    return "rpm_max = " + num(rpm_max) + ": must be > rpm_min = " + num(rpm_min) + " rev/min (a band of speeds)";
  if (rpm_points < 2 || rpm_points > kMaxBandPoints)
    return "rpm_points = " + std::to_string(rpm_points) + ": must be in [2, " + std::to_string(kMaxBandPoints) + "]";
  if (!(std::isfinite(depth_max_m) && depth_max_m > 0.0))
    return "depth_max_m = " + num(depth_max_m) + ": must be > 0";
  if (!(min_pitch_ratio >= kMinPitchRatioLow && min_pitch_ratio < 1.0))
    return "min_pitch_ratio = " + num(min_pitch_ratio) + ": must be in [0.1, 1) (each angle >= ratio x 360/N_t)";
  if (scan_points < 0 || scan_points > kMaxScanPoints)
    return "scan_points = " + std::to_string(scan_points) + ": must be in [0, " + std::to_string(kMaxScanPoints) + "]";
  return {};
}

namespace {

// Refuses a process the design cannot start from (turning, one tooth, an odd
// count for the alternating family, a cutter already pitched or with unequal
// helices, a varying spindle speed), naming the key.
void check_designable(const Process& process, const PitchDesignOptions& options) {
  if (!process.rotating_edges())
    throw InputError("the process is turning: pitch design needs a milling cutter (process.operation = \"milling\")");
  const int teeth = process.teeth();
  if (teeth < 2)
    throw InputError("teeth = " + std::to_string(teeth) + ": a pitch needs >= 2 teeth");
  if (options.family == PitchFamily::kAlternating && teeth % 2 != 0)
    throw InputError("family alternating: needs an even number of teeth (teeth = " + std::to_string(teeth) +
                     "); use linear");
  if (process.has_variable_pitch())
    throw InputError("the config's cutter already has unequal pitch angles (process.pitch_angles_deg): the design "
                     "starts from the equal-pitch cutter it compares with; remove pitch_angles_deg");
  if (process.has_variable_helix())
    throw InputError("the config's cutter has unequal helix angles (process.helix_angles_deg): the design needs one "
                     "helix angle for every tooth");
  if (process.has_speed_variation())
    throw InputError("the config has a spindle speed variation (process.speed_variation): the design assumes a "
                     "constant spindle speed");
}

// The candidate's worst limit over the band (kInf when no row has a limit at
// or below depth_max_m) and its speed (first_rpm when none has).
void set_worst(PitchCandidate& c, double depth_max_m, double first_rpm) {
  c.worst_limit_m = kInf;
  c.worst_rpm = first_rpm;
  for (const StabilityLimit& l : c.limits) {
    const double a = l.bounded() && l.depth_limit_m <= depth_max_m ? l.depth_limit_m : kInf;
    if (a < c.worst_limit_m) {
      c.worst_limit_m = a;
      c.worst_rpm = l.spindle_rpm;
    }
  }
}

// The objective: an unbounded worst limit counts as the searched depth.
double design_merit(const PitchCandidate& c, double depth_max_m) { return std::min(c.worst_limit_m, depth_max_m); }

// The index of the best candidate by merit; ties go to the smaller ΔP,
// nearer equal pitch.
std::size_t best_candidate(const std::vector<PitchCandidate>& cs, double depth_max_m) {
  std::size_t b = 0;
  for (std::size_t i = 1; i < cs.size(); ++i) {
    const double mi = design_merit(cs[i], depth_max_m), mb = design_merit(cs[b], depth_max_m);
    if (mi > mb || (mi == mb && cs[i].step_rad < cs[b].step_rad)) b = i;
  }
  return b;
}

}  // namespace

PitchDesign design_pitch(const StructuralModel& model, const Process& process, const PitchDesignOptions& options) {
  if (const std::string why = options.validate(); !why.empty()) throw InputError(why);
  check_designable(process, options);
  const int teeth = process.teeth();

  PitchDesign d;
  d.family = options.family;
  d.depth_max_m = options.depth_max_m;
  d.step_max_rad = max_pitch_step_rad(options.family, teeth, options.min_pitch_ratio);
  d.speeds_rpm = evenly_spaced_speeds(options.rpm_min, options.rpm_max, options.rpm_points);

  // The method must see the designed cutters: probe with one of them.
  const auto cutter = [&](double step) {
    MillingParameters mp = process.milling_parameters();
    mp.pitch_angles_rad = step == 0.0 ? std::vector<double>{} : family_pitch_angles(options.family, teeth, step);
    Process p = Process::milling(mp);
    p.set_speed_variation(process.speed_variation());
    return p;
  };
  const Process probe = cutter(0.5 * d.step_max_rad);
  d.method = resolve_lobe_method(options.method, model, probe);
  const SolverDescriptor& desc = find_lobe_method(d.method);
  if (desc.kind == SolverKind::kSimulation)
    throw InputError("method \"" + d.method + "\": a simulation's limit is a depth bracket, too coarse and slow "
                     "for a search; use sdm or analytic");
  check_accepts(desc, model, probe);

  const std::size_t budget = 2 + static_cast<std::size_t>(options.scan_points) + kPolishEvaluations;
  std::size_t done = 0;
  const auto evaluate = [&](double step) {
    PitchCandidate c;
    c.step_rad = step;
    const Process p = cutter(step);
    for (int j = 0; j < teeth; ++j) c.angles_rad.push_back(p.pitch_angle_rad(j));
    const auto solver = make_lobe_solver(d.method, model, p, options.depth_max_m, options.solver_options);
    c.limits = lobe_envelope(*solver, d.speeds_rpm, options.threads);
    set_worst(c, options.depth_max_m, d.speeds_rpm.front());
    d.evaluated.emplace_back(step, c.worst_limit_m);
    if (options.progress) options.progress(std::min(0.99, static_cast<double>(++done) / static_cast<double>(budget)));
    return c;
  };
  const auto merit = [&](const PitchCandidate& c) { return design_merit(c, options.depth_max_m); };

  d.equal = evaluate(0.0);
  d.evaluated.clear();  // the list holds the pitched cutters; equal pitch is d.equal
  if (!std::isfinite(d.equal.worst_limit_m))
    throw InputError("depth_max_m = " + num(options.depth_max_m) +
                     ": the equal-pitch cutter has no limit below it anywhere in [" + num(options.rpm_min) + ", " +
                     num(options.rpm_max) + "] rev/min: nothing to improve (search deeper)");
  // The worst row's chatter frequency and speed: Budak's rule.
  for (const StabilityLimit& l : d.equal.limits)
    if (l.spindle_rpm == d.equal.worst_rpm) d.rule_chatter_frequency_hz = l.chatter_frequency_hz;
  d.rule_rpm = d.equal.worst_rpm;
  d.rule_step_rad = budak_pitch_step_rad(options.family, teeth, d.rule_rpm, d.rule_chatter_frequency_hz);
  d.rule_clipped = !(d.rule_step_rad <= d.step_max_rad);
  const double start_step = d.rule_clipped ? d.step_max_rad : d.rule_step_rad;
  d.start = evaluate(start_step);

  // Candidates so far: equal (0), the rule, the scan. The best by merit
  // (ties: the smaller ΔP, nearer equal pitch) brackets the polish.
  std::vector<PitchCandidate> tried{d.equal, d.start};
  for (int i = 1; i <= options.scan_points; ++i) tried.push_back(evaluate(d.step_max_rad * i / options.scan_points));
  std::vector<double> steps;
  for (const auto& c : tried) steps.push_back(c.step_rad);
  std::sort(steps.begin(), steps.end());
  steps.erase(std::unique(steps.begin(), steps.end()), steps.end());
  const auto best_of = [&](const std::vector<PitchCandidate>& cs) { return best_candidate(cs, options.depth_max_m); };
  const PitchCandidate best_start = tried[best_of(tried)];
  const auto at = std::lower_bound(steps.begin(), steps.end(), best_start.step_rad);
  const double lo = at == steps.begin() ? steps.front() : *(at - 1);
  const double hi = (at + 1) == steps.end() ? steps.back() : *(at + 1);
  if (hi > lo) {
    PitchCandidate polished;
    double polished_merit = -kInf;
    detail::maximize_on(
        [&](double step) {
          PitchCandidate c = evaluate(step);
          const double m = merit(c);
          if (m > polished_merit) {
            polished_merit = m;
            polished = std::move(c);
          }
          return m;
        },
        lo, hi, kPolishWidthFraction * d.step_max_rad, kPolishEvaluations);
    if (!polished.limits.empty()) tried.push_back(std::move(polished));
  }
  d.designed = tried[best_of(tried)];
  if (std::isfinite(d.designed.worst_limit_m)) {
    d.gain = d.designed.worst_limit_m / d.equal.worst_limit_m;
  } else {
    d.gain = options.depth_max_m / d.equal.worst_limit_m;
    d.gain_is_lower_bound = true;
  }
  if (options.progress) options.progress(1.0);
  return d;
}

}  // namespace chatter
