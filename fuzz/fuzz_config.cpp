// libFuzzer target: the TOML config loader, and the analytic solver on every
// config the loader accepts. Allowed outcomes: a Config, or InputError (bad
// input, with a message). Anything else (a crash, another exception, a NaN
// depth, an accepted config with a non-physical value, a cutter breaking the
// rules of Process::milling: pitch angles summing to 2π, helix in [0, π/2),
// runout below the radius, ...) aborts. Where the config has a position
// dependence ([[positions]] or cantilever modes, docs/position.md), the model
// at both ends and the middle of its range must be physical too (or refused
// with an InputError when only rigid modes are left); where it has an
// [uncertainty] table (docs/uncertainty.md), the spreads must pass their own
// rules and a 3-sigma-bounded sample must still be a physical model and
// process. A grinding config ([grinding], docs/grinding.md) goes to
// parse_grinding_config: accepted, its process must validate, its modes be
// physical and its prediction at a few powers finite (or refused with an
// InputError, an empirical model negative there).
//
// Build and run: see docs/reliability.md (scripts/fuzz.sh). The same entry
// point runs over fuzz/corpus/config/ in the test suite (test_fuzz_corpus).
#include <cmath>
#include <cstddef>
#include <numbers>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/position.hpp"
#include "chatter/uncertainty.hpp"
#include "chatter/transfer_function.hpp"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_config: invariant violated: %s\n", what);
  std::abort();
}

void check_body(const chatter::Body& b) {
  for (const chatter::Mode& m : b.modes) {
    if (!(std::isfinite(m.natural_frequency_hz) && m.natural_frequency_hz > 0)) fail("frequency");
    if (!(m.damping_ratio > 0 && m.damping_ratio < 1)) fail("damping");
    if (!(std::isfinite(m.stiffness_n_per_m) && m.stiffness_n_per_m > 0)) fail("stiffness");
    if (!(std::abs(m.direction.norm() - 1.0) < 1e-12)) fail("direction not unit");
  }
}

// The real cutter (process.hpp, Process::milling): pitch angles empty or N_t
// values > 0 summing to 2π; helix angles empty, one or N_t values in
// [0, π/2); runout empty or N_t finite values below the radius; a helix or
// process damping only with a diameter; C_pd finite and >= 0.
constexpr double kPitchSumTolerance = 1e-6;  // rad, the rule of Process::milling

void check_process(const chatter::Process& p) {
  if (p.operation() == chatter::Operation::kTurning) {
    const chatter::TurningParameters& t = p.turning_parameters();
    if (!(std::isfinite(t.feed_force_coefficient_n_per_m2) && t.feed_force_coefficient_n_per_m2 > 0)) fail("K_f");
    if (!(std::isfinite(t.process_damping_coefficient_n_per_m) && t.process_damping_coefficient_n_per_m >= 0))
      fail("turning C_pd");
    if (t.process_damping_coefficient_n_per_m > 0 && !(t.workpiece_diameter_m > 0)) fail("C_pd without D_w");
    return;
  }
  const chatter::MillingParameters& m = p.milling_parameters();
  const auto n = static_cast<std::size_t>(m.teeth);
  if (m.teeth < 1) fail("teeth");
  if (!(std::isfinite(m.tangential_coefficient_n_per_m2) && m.tangential_coefficient_n_per_m2 > 0)) fail("K_t");
  if (!(std::isfinite(m.radial_coefficient_n_per_m2) && m.radial_coefficient_n_per_m2 >= 0)) fail("K_r");
  if (!(m.radial_immersion > 0 && m.radial_immersion <= 1)) fail("radial immersion");
  if (!(std::isfinite(m.tool_diameter_m) && m.tool_diameter_m >= 0)) fail("tool diameter");
  if (!m.pitch_angles_rad.empty()) {
    if (m.pitch_angles_rad.size() != n) fail("pitch angles: not one per tooth");
    double sum = 0;
    for (double a : m.pitch_angles_rad) {
      if (!(std::isfinite(a) && a > 0)) fail("pitch angle not > 0");
      sum += a;
    }
    if (!(std::abs(sum - 2 * std::numbers::pi) <= kPitchSumTolerance)) fail("pitch angles do not sum to 2 pi");
  }
  if (!(m.helix_angles_rad.empty() || m.helix_angles_rad.size() == 1 || m.helix_angles_rad.size() == n))
    fail("helix angles: not 0, 1 or N_t values");
  bool helix = false;
  for (double b : m.helix_angles_rad) {
    if (!(b >= 0 && b < std::numbers::pi / 2)) fail("helix angle outside [0, pi/2)");
    helix = helix || b > 0;
  }
  if (!m.runout_m.empty()) {
    if (m.runout_m.size() != n) fail("runout: not one per tooth");
    for (double r : m.runout_m) {
      if (!std::isfinite(r)) fail("runout not finite");
      if (m.tool_diameter_m > 0 && !(std::abs(r) < m.tool_diameter_m / 2)) fail("runout not below the radius");
    }
  }
  if (!(std::isfinite(m.process_damping_coefficient_n_per_m) && m.process_damping_coefficient_n_per_m >= 0))
    fail("milling C_pd");
  if ((helix || m.process_damping_coefficient_n_per_m > 0) && !(m.tool_diameter_m > 0))
    fail("helix or process damping without a diameter");
  if (p.teeth() != m.teeth) fail("Process::teeth");
}

// The model at `x` (m) is physical; only at the start of the range (the clamp
// of a cantilever, where its modes are rigid) may it be refused.
void check_position(const chatter::Config& cfg, double x, bool range_start) {
  try {
    const chatter::StructuralModel at = chatter::model_at_position(cfg, x);
    if (at.mode_count() == 0) fail("rigid model at a position");
    check_body(at.tool);
    check_body(at.workpiece);
  } catch (const chatter::InputError&) {
    if (!range_start) fail("position inside the range refused");
  }
}

}  // namespace

void check_grinding(const std::string& text) {
  chatter::GrindingConfig g;
  try {
    g = chatter::parse_grinding_config(text, "fuzz.toml");
  } catch (const chatter::InputError&) {
    return;  // refused with a message: fine
  }
  if (!g.process.validate().empty()) fail("accepted an invalid grinding process");
  check_body(g.robot.tool);
  check_body(g.robot.workpiece);
  for (double power : {1.0, 1000.0, 1e5}) {
    try {
      const chatter::grinding::Prediction r = chatter::grinding::predict_at_power(g.process, power);
      if (!(std::isfinite(r.removal_rate_m3_per_s) && r.removal_rate_m3_per_s > 0 && std::isfinite(r.max_depth_m) &&
            std::isfinite(r.normal_force_n) && std::isfinite(r.specific_energy_j_per_m3)))
        fail("grinding prediction not finite");
    } catch (const chatter::InputError&) {
    }
  }
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  check_grinding(text);
  chatter::Config cfg;
  try {
    cfg = chatter::parse_config(text, "fuzz.toml");
  } catch (const chatter::InputError&) {
    return 0;  // refused with a message: fine
  }
  if (cfg.model.mode_count() == 0) fail("accepted a rigid model");
  check_body(cfg.model.tool);
  check_body(cfg.model.workpiece);
  check_process(cfg.process);
  if (!cfg.position.empty()) {
    const auto [lo, hi] = cfg.position.range_m();
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo >= 0 && hi > lo)) fail("position range");
    if (!cfg.position.validate().empty()) {
      // By design (docs/position.md) cantilever bars of different lengths
      // load (each mode at its bar's free end, which is what the commands
      // without a position use); every position-dependent use must then be
      // refused with a message naming both bars.
      if (cfg.position.cantilever.size() < 2) fail("accepted an invalid position dependence");
      for (double x : {lo, 0.5 * (lo + hi), hi}) {
        try {
          (void)chatter::model_at_position(cfg, x);
          fail("a position model from cantilevers of different lengths");
        } catch (const chatter::InputError&) {
        }
      }
    } else {
      for (double x : {lo, 0.5 * (lo + hi), hi}) check_position(cfg, x, x == lo);
    }
  }
  if (cfg.uncertainty) {
    if (!cfg.uncertainty->validate(cfg.model, cfg.process).empty()) fail("accepted invalid uncertainty spreads");
    for (std::uint64_t sample : {0u, 1u, 7u}) {
      const chatter::UncertainSample s = chatter::sample_inputs(cfg.model, cfg.process, *cfg.uncertainty, 1, sample);
      if (s.model.mode_count() != cfg.model.mode_count()) fail("sample changed the mode count");
      check_body(s.model.tool);
      check_body(s.model.workpiece);
      check_process(s.process);
    }
  }
  try {
    chatter::TransferFunctionOptions opt;
    opt.depth_max_m = 0.05;
    const chatter::AnalyticSolver solver(cfg.model, cfg.process, opt);
    // Three speeds, the lowest 1 000 rev/min: the search's cost grows as the
    // number of lobes below the speed (~ 1/speed). At 100 rev/min a
    // variable-helix cutter took 0.6 s per input, and such inputs, which the
    // fuzzer keeps because they reach the multi-delay search, held the run at
    // ~200 executions per second (docs/reliability.md); low speeds are in the
    // solver tests.
    for (double rpm : {1000.0, 3000.0, 20000.0}) {
      const chatter::StabilityLimit l = solver.limit_at(chatter::SpindleSpeed(rpm));
      if (std::isnan(l.depth_limit_m) || !(l.depth_limit_m > 0)) fail("depth limit NaN or non-positive");
      if (l.bounded() && !std::isfinite(l.chatter_frequency_hz)) fail("bounded limit without a frequency");
    }
  } catch (const chatter::InputError&) {
    return 0;  // e.g. values the solver refuses with a message
  }
  return 0;
}
