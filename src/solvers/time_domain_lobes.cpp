// Lobes by simulation (TimeDomainSolver): per speed, the depth where the
// simulated cut starts to chatter, by the depth search shared with sdm
// (depth_search.hpp), each verdict one run of TimeDomainSimulator.
#include "chatter/report.hpp"
#include "chatter/time_domain.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/transfer_function.hpp"
#include "depth_search.hpp"
#include "time_domain_model.hpp"
#include "time_domain_model.hpp"

namespace chatter {

using td_detail::simulation_period;

namespace {

// A helical cutter's lobe search (issue 27: 1.75 s per speed on the
// issue's 4-flute variable-pitch helix cutter, now ~0.3 s):
//  - the starting guess is sdm's limit (the linear limit itself: sdm sees
//    the helix, which the zeroth-order analytic method averages away), so
//    the search brackets it with a first ratio of kFloquetBracket (growing
//    by squaring while the verdict does not change) instead of scanning up
//    from guess / 16 by factors of 2;
//  - with axial_slices automatic, its runs take the exact edge of a
//    uniform helix, as simulate does (time_domain_edge.cpp: exact, and
//    2.2x faster than 12 slices on the cutter), and cut the other
//    helical cutters in kSearchHelixSlices slices instead of simulate's 20.
//    Near the limit the growth per period is flat in depth (|μ| moves 1e-3
//    over 1.5 % of depth on the cutter), so the slices' small error
//    on |μ| moves the limit: 8 slices moved it 1.2 % at 14 000 rev/min, 12
//    slices 0.8 % (inside the 1 % bracket; 10 000 and 12 000 rev/min within
//    0.3 %); the exact edge has no such error.
// The verdict of a nonlinear run need not be monotone in depth near the
// limit (a thin chatter band, then a stable window): a bracket of 10 %,
// like the wide scan's bisection before it, returns a crossing, not always
// the first (docs/performance.md).
// Straight cutters keep the analytic guess, the wide scan and their slices
// (their tables are the golden ones).
constexpr double kFloquetBracket = 1.1;
constexpr int kSearchHelixSlices = 12;
constexpr int kMaxBracketSteps = 30;

/// The depth search's starting guess: sdm for a helical cutter (above), else
/// the zeroth-order analytic solver; null when the method does not apply to
/// this model and process (its constructor's rules, e.g. a model with both
/// bodies rigid).
std::shared_ptr<const LobeSolver> default_starting_guess(const TimeDomainSimulator& sim) {
  // Speed variation: sdm solves the same modulated equation (the averaged
  // methods refuse it); not with process damping, which sdm refuses there.
  const bool ssv_guess = sim.process().has_speed_variation() && !sim.process().has_process_damping();
  if ((sim.process().has_helix() || sim.process().has_profile() || ssv_guess) && !sim.model().has_measured() &&
      sim.model().mode_count() > 0) {
    SemiDiscretizationOptions so;
    so.depth_max_m = sim.options().depth_max_m;
    try {
      return std::make_shared<const SemiDiscretizationSolver>(sim.model(), sim.process(), so);
    } catch (const InputError&) {
      // fall back on the analytic guess
    }
  }
  TransferFunctionOptions to;
  to.depth_max_m = sim.options().depth_max_m;
  if (!to.validate().empty() || sim.model().rigid()) return nullptr;
  try {
    return std::make_shared<const AnalyticSolver>(sim.model(), sim.process(), to);
  } catch (const InputError&) {
    return nullptr;  // e.g. a cutter feature the analytic method refuses: no guess
  }
}

}  // namespace

TimeDomainSolver::TimeDomainSolver(StructuralModel model, Process process, TimeDomainOptions options,
                                   std::shared_ptr<const LobeSolver> starting_guess)
    : simulator_(std::move(model), std::move(process), options), starting_guess_(std::move(starting_guess)) {
  if (!starting_guess_) {
    starting_guess_ = default_starting_guess(simulator_);
    floquet_guess_ = dynamic_cast<const SemiDiscretizationSolver*>(starting_guess_.get()) != nullptr;
  }
  const TimeDomainOptions& to = simulator_.options();
  if (floquet_guess_ && simulator_.process().has_helix() && to.axial_slices == 0 &&
      !td_detail::exact_edge_applies(simulator_.process(), to, to.linear, to.multiple_regeneration)) {
    TimeDomainOptions o = simulator_.options();
    o.axial_slices = kSearchHelixSlices;
    search_simulator_ = std::make_shared<const TimeDomainSimulator>(simulator_.model(), simulator_.process(), o);
  }
}

SimulationResult TimeDomainSolver::verdict_run(double rpm, double depth_m) const {
  SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_m;
  st.feed_m = simulator_.options().feed_m;
  st.linear = simulator_.options().linear;
  // options.periods counts tooth periods (header): the same simulated time
  // when the run's period is a revolution.
  const double tooth_periods_per_period = simulation_period(simulator_.process(), st) / simulator_.process().delay_s(rpm);
  st.periods = tooth_periods_per_period > 1.5
                   ? std::max(20, static_cast<int>(std::ceil(simulator_.options().periods / tooth_periods_per_period)))
                   : simulator_.options().periods;
  st.multiple_regeneration = simulator_.options().multiple_regeneration;
  st.record_series = false;
  st.stop_when_periodic = true;  // a run that settles says "stable" at once
  return (search_simulator_ ? *search_simulator_ : simulator_).simulate(st);
}

StabilityLimit TimeDomainSolver::limit_at(SpindleSpeed speed) const {
  const double rpm = speed.rpm();
  if (!(rpm > 0.0 && std::isfinite(rpm))) throw InputError("spindle speed must be > 0 rev/min");
  const TimeDomainOptions& o = simulator_.options();
  StabilityLimit out;
  out.spindle_rpm = rpm;
  // Starting guess (header): only places the scan, never the answer.
  double guess = o.depth_max_m / 4.0;
  bool guess_bounded = false;
  if (starting_guess_) {
    std::optional<StabilityLimit> g;
    try {
      g = starting_guess_->limit_at(SpindleSpeed(speed));
    } catch (const InputError&) {
      // The guess refuses this speed (documented in the header): no guess.
    }
    if (g && g->bounded() && g->depth_limit_m > 0.0) {
      guess = std::min(g->depth_limit_m, o.depth_max_m);
      guess_bounded = true;
    }
  }
  // Scan by factors of 2 from guess / 16 (down if already chatter), then
  // bisection to depth_tolerance (depth_search.hpp, shared with sdm).
  auto probe = [&](double depth) { return verdict_run(rpm, depth); };
  auto chatter = [](const SimulationResult& r) { return r.verdict == SimulationVerdict::kChatter; };
  if (floquet_guess_ && guess_bounded) {
    // The linear limit as the first probe; bracket outwards by a ratio that
    // starts at kFloquetBracket and squares at every step (a nonlinear limit
    // far from the linear one is still reached in a few probes).
    detail::DepthBracket<SimulationResult> b;
    SimulationResult first = probe(guess);
    const bool up = !chatter(first);
    double at = guess, ratio = kFloquetBracket;
    (up ? b.lo : b.hi) = at;
    (up ? b.at_lo : b.at_hi) = std::move(first);
    for (int step = 0; step < kMaxBracketSteps && !b.found; ++step, ratio *= ratio) {
      const double next = up ? std::min(at * ratio, o.depth_max_m) : at / ratio;
      SimulationResult v = probe(next);
      if (chatter(v) == up) {
        (up ? b.hi : b.lo) = next;
        (up ? b.at_hi : b.at_lo) = std::move(v);
        b.found = true;
        break;
      }
      (up ? b.lo : b.hi) = next;
      (up ? b.at_lo : b.at_hi) = std::move(v);
      at = next;
      if (up && next >= o.depth_max_m) return out;  // stable up to the searched depth
    }
    if (!b.found) {
      if (!up) out.depth_limit_m = 0.0;
      return out;
    }
    detail::bisect_bracket(b, o.depth_tolerance, probe, chatter);
    out.depth_limit_m = 0.5 * (b.lo + b.hi);
    out.chatter_frequency_hz = b.at_hi.chatter_frequency_hz;
    if (std::isnan(out.chatter_frequency_hz)) out.chatter_frequency_hz = b.at_hi.dominant_nonharmonic_hz;
    out.lobe = lobe_number(out.chatter_frequency_hz, b.at_hi.tooth_passing_hz);
    return out;
  }
  constexpr double kScanRatio = 2.0;
  constexpr int kMaxHalvings = 30;
  const double a = guess / 16.0;
  SimulationResult first = probe(a);
  detail::DepthBracket<SimulationResult> b;
  if (chatter(first)) {
    b = detail::descend_to_stable(a, std::move(first), kScanRatio, kMaxHalvings, probe, chatter);
    if (!b.found) {
      out.depth_limit_m = 0.0;
      return out;
    }
  } else {
    b = detail::climb_to_unstable(a, std::move(first), kScanRatio, o.depth_max_m, probe, chatter);
    if (!b.found) return out;  // stable up to the searched depth
  }
  detail::bisect_bracket(b, o.depth_tolerance, probe, chatter);
  const double lo = b.lo, hi = b.hi;
  const SimulationResult& at_hi = b.at_hi;
  out.depth_limit_m = 0.5 * (lo + hi);
  out.chatter_frequency_hz = at_hi.chatter_frequency_hz;
  if (std::isnan(out.chatter_frequency_hz)) out.chatter_frequency_hz = at_hi.dominant_nonharmonic_hz;
  out.lobe = lobe_number(out.chatter_frequency_hz, at_hi.tooth_passing_hz);
  return out;
}

}  // namespace chatter
