// The C API's Monte Carlo (include/chatter/chatter.h, "uncertainty"): the
// quantile lobes and the probability of stability of one operation, from the
// same library calls as `chatter lobes --samples` and Python's
// chatter.uncertain_lobes (monte_carlo_limits, reduce_monte_carlo).
#include <cmath>
#include <cstdint>
#include <iterator>
#include <string>
#include <vector>

#include "capi_internal.hpp"
#include "chatter/lobes.hpp"
#include "chatter/report.hpp"
#include "chatter/solvers.hpp"
#include "chatter/uncertainty.hpp"

using chatter::capi::fail;
using chatter::capi::guarded;

namespace {

// The same bound as the CLI's --samples: the limits held in memory.
constexpr long long kMaxSolves = 25'000'000;
constexpr int kMaxSamples = 1'000'000;

double mm_or_inf(double m) { return std::isfinite(m) ? m * 1e3 : HUGE_VAL; }

// The checks every Monte Carlo call shares; returns the resolved method.
std::string checked_method(const chatter::Config& cfg, const char* method, double depth_max_mm, int samples,
                           long long speeds, int threads, const std::string& fn) {
  if (!cfg.uncertainty)
    throw chatter::InputError(fn + ": " + cfg.source.string() +
                              ": no [uncertainty] table (give the 1-sigma spreads in percent; docs/config.md)");
  if (const std::string why = cfg.uncertainty->validate(cfg.model, cfg.process); !why.empty())
    throw chatter::InputError(fn + ": " + cfg.source.string() + ": uncertainty: " + why);
  if (!(std::isfinite(depth_max_mm) && depth_max_mm > 0.0))
    throw chatter::InputError(fn + ": depth_max_mm = " + std::to_string(depth_max_mm) + ": must be > 0");
  if (samples < 1 || samples > kMaxSamples)
    throw chatter::InputError(fn + ": samples = " + std::to_string(samples) + ": must be in [1, " +
                              std::to_string(kMaxSamples) + "]");
  if (static_cast<long long>(samples) * speeds > kMaxSolves)
    throw chatter::InputError(fn + ": samples x speeds = " + std::to_string(samples) + " x " + std::to_string(speeds) +
                              ": at most " + std::to_string(kMaxSolves) + " limits are held in memory");
  if (threads < 0 || threads > 1024)
    throw chatter::InputError(fn + ": threads = " + std::to_string(threads) + ": must be in [0, 1024] (0 = every core)");
  return chatter::resolve_lobe_method(method ? method : chatter::kAutoMethod, cfg.model, cfg.process);
}

// The N samples' limits at `speeds` (rows[sample][speed]), each sample's
// solver built as the nominal one (`recipe`: the config's
// defaults applied once, by the caller).
std::vector<std::vector<chatter::StabilityLimit>> sample_rows(const chatter::Config& cfg,
                                                              const chatter::SolverRecipe& recipe, double depth_max_mm,
                                                              const std::vector<double>& speeds, int samples,
                                                              unsigned long long seed, int threads) {
  const double depth_max_m = depth_max_mm * 1e-3;
  const chatter::SampleSolverFactory factory = [&](const chatter::StructuralModel& model,
                                                   const chatter::Process& process) {
    return recipe.build(model, process, depth_max_m);
  };
  return chatter::monte_carlo_limits(cfg.model, cfg.process, *cfg.uncertainty, static_cast<std::uint64_t>(seed), 0,
                                     static_cast<std::uint64_t>(samples), speeds, factory,
                                     static_cast<unsigned>(threads));
}

}  // namespace

extern "C" {

chatter_status chatter_uncertain_lobes(const chatter_model* model, const char* method, double depth_max_mm,
                                       double rpm_min, double rpm_max, int rpm_points, int samples,
                                       unsigned long long seed, int threads, chatter_uncertain_row* rows) {
  if (!model || !rows) return fail(CHATTER_NULL_ARGUMENT, "chatter_uncertain_lobes: model and rows must not be NULL");
  return guarded([&] {
    const chatter::Config& cfg = model->config;
    const std::string fn = "chatter_uncertain_lobes";
    if (rpm_points < 2) throw chatter::InputError(fn + ": rpm_points = " + std::to_string(rpm_points) + ": must be >= 2");
    if (!(std::isfinite(rpm_min) && rpm_min > 0.0 && std::isfinite(rpm_max) && rpm_max > rpm_min))
      throw chatter::InputError(fn + ": rpm_min, rpm_max: must be 0 < rpm_min < rpm_max");
    const std::string m = checked_method(cfg, method, depth_max_mm, samples, rpm_points, threads, fn);
    const auto speeds = chatter::evenly_spaced_speeds(rpm_min, rpm_max, rpm_points);
    // The config's defaults once, for the nominal solver (built first: the
    // method is checked before any sampling) and every sample's.
    const chatter::SolverRecipe recipe{m, chatter::with_config_defaults(chatter::find_lobe_method(m), cfg, {})};
    const auto nominal_solver = recipe.build(cfg.model, cfg.process, depth_max_mm * 1e-3);
    const auto nominal = chatter::lobe_envelope(*nominal_solver, speeds, static_cast<unsigned>(threads));
    const auto sampled = sample_rows(cfg, recipe, depth_max_mm, speeds, samples, seed, threads);
    // No probability grid is asked: one depth (the reduction needs one).
    const chatter::UncertainLobes mc = chatter::reduce_monte_carlo(
        sampled, {0.0}, std::vector<double>(std::begin(chatter::kUncertaintyLevels), std::end(chatter::kUncertaintyLevels)));
    for (std::size_t s = 0; s < speeds.size(); ++s) {
      chatter_uncertain_row& r = rows[s];
      r.spindle_rpm = speeds[s];
      r.depth_limit_mm = nominal[s].bounded() ? nominal[s].depth_limit_m * 1e3 : HUGE_VAL;
      r.depth_limit_p05_mm = mm_or_inf(mc.quantile_depth_m[0][s]);
      r.depth_limit_p50_mm = mm_or_inf(mc.quantile_depth_m[1][s]);
      r.depth_limit_p95_mm = mm_or_inf(mc.quantile_depth_m[2][s]);
    }
  });
}

chatter_status chatter_probability_stable(const chatter_model* model, const char* method, double depth_max_mm,
                                          double spindle_rpm, double depth_mm, int samples, unsigned long long seed,
                                          int threads, double* probability) {
  if (!model || !probability)
    return fail(CHATTER_NULL_ARGUMENT, "chatter_probability_stable: model and probability must not be NULL");
  return guarded([&] {
    const chatter::Config& cfg = model->config;
    const std::string fn = "chatter_probability_stable";
    chatter::check_spindle_rpm(spindle_rpm, fn + ": spindle_rpm");
    chatter::check_depth_mm(depth_mm, fn + ": depth_mm");
    const std::string m = checked_method(cfg, method, depth_max_mm, samples, 1, threads, fn);
    const chatter::SolverRecipe recipe{m, chatter::with_config_defaults(chatter::find_lobe_method(m), cfg, {})};
    // The method checked on the nominal model before any sampling.
    (void)recipe.build(cfg.model, cfg.process, depth_max_mm * 1e-3);
    const auto sampled = sample_rows(cfg, recipe, depth_max_mm, {spindle_rpm}, samples, seed, threads);
    const chatter::UncertainLobes mc = chatter::reduce_monte_carlo(sampled, {depth_mm * 1e-3}, {0.5});
    *probability = mc.probability_stable[0][0];
  });
}

}  // extern "C"
