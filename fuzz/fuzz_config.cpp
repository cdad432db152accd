// libFuzzer target: the TOML config loader, and the analytic solver on every
// config the loader accepts. Allowed outcomes: a Config, or InputError (bad
// input, with a message). Anything else (a crash, another exception, a NaN
// depth, an accepted config with a non-physical value) aborts.
//
// Build and run: see docs/reliability.md (scripts/fuzz.sh). The same entry
// point runs over fuzz/corpus/config/ in the test suite (test_fuzz_corpus).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  chatter::Config cfg;
  try {
    cfg = chatter::parse_config(text, "fuzz.toml");
  } catch (const chatter::InputError&) {
    return 0;  // refused with a message: fine
  }
  if (cfg.model.mode_count() == 0) fail("accepted a rigid model");
  check_body(cfg.model.tool);
  check_body(cfg.model.workpiece);
  try {
    chatter::TransferFunctionOptions opt;
    opt.depth_max_m = 0.05;
    const chatter::AnalyticSolver solver(cfg.model, cfg.process, opt);
    for (double rpm : {100.0, 3000.0, 20000.0}) {
      const chatter::StabilityLimit l = solver.limit_at(rpm);
      if (std::isnan(l.depth_limit_m) || !(l.depth_limit_m > 0)) fail("depth limit NaN or non-positive");
      if (l.bounded() && !std::isfinite(l.chatter_frequency_hz)) fail("bounded limit without a frequency");
    }
  } catch (const chatter::InputError&) {
    return 0;  // e.g. values the solver refuses with a message
  }
  return 0;
}
