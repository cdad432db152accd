// The `time-domain` solver (SUNDIALS CVODE, docs/physics.md §6) against closed
// forms (free vibration), against Floquet theory (`sdm`: growth factor per
// period vs spectral radius, verdicts either side of the sdm limit, in a
// Hopf and in a flip lobe, chatter frequency), for bounded nonlinear
// chatter, for a history buffer that does not grow with simulated time, and
// for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/time_domain.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;

// Tolerances.
// Growth factor per period (exact DMD of the simulated once-per-period map)
// vs sdm's spectral radius at 64 steps: measured agreement 1e-4…3e-4; the
// issue asks for about 1 %.
constexpr double kGrowthVsSdm = 5e-3;
// Chatter frequency of a saturated (nonlinear) chatter vs sdm at the limit:
// the amplitude-dependent nonlinear vibration drifts from the linear one by
// up to 1.6 % in the runs of docs/time_domain.md.
constexpr double kChatterFrequency = 0.03;
// Free vibration over 0.8 s (75 tool and 250 workpiece cycles): the global
// error stays within this multiple of CVODE's relative tolerance, and falls
// by at least kTighterFactor when the tolerance is tightened 100 times.
constexpr double kGlobalErrorPerRtol = 300.0;
constexpr double kTighterFactor = 10.0;
// Period doubling: chatter at an odd multiple of half the tooth-passing
// frequency, to the parabolic peak refinement (measured < 1e-4 half orders).
constexpr double kHalfOrder = 1e-3;
// Saturated chatter at 1.5 x the sdm limit: the tool is in air for more than
// this fraction of the arc time (measured 20–45 %) …
constexpr double kSaturatedAirFraction = 0.05;
// … and the amplitude of a run five times longer drifts by less than this
// (relative): the vibration is bounded, not growing (an unbounded growth
// at |mu| >= 1.01 per period would be 1.01^800 = 3e3 times larger).
constexpr double kSaturatedAmplitudeDrift = 0.1;
// Time-domain lobe search vs sdm: bracket width 1 %, sdm within 0.5 % of exact.
constexpr double kBisectionVsSdm = 0.02;
// Random models: the nonlinear verdict equals sdm's where rho is more than
// this away from 1 (closer, 150 periods may not show the trend; measured
// agreement on all 11 checked trials, the closest at rho = 1.014) …
constexpr double kVerdictMargin = 0.01;
// … and saturated chatter has increments at |mu| = 1 within the verdict's
// own margin (measured 1.000001–1.009 for rho = 1.014–1.22).
constexpr double kSaturatedGrowth = 0.02;

Config config(const std::string& name) { return load_config(std::string(CHATTER_SOURCE_DIR) + "/configs/" + name); }

// Exact free vibration of one mode from (q0, v0).
double free_vibration(double t, double f_hz, double zeta, double q0, double v0) {
  const double w = 2 * kPi * f_hz, wd = w * std::sqrt(1 - zeta * zeta);
  return std::exp(-zeta * w * t) * (q0 * std::cos(wd * t) + (v0 + zeta * w * q0) / wd * std::sin(wd * t));
}

// Largest error of the simulated displacement against the exact free
// vibration of a tool mode along X and a workpiece mode at 30°, depth 0.
double free_vibration_error(double rtol) {
  StructuralModel model;
  model.tool.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1, 0}));
  model.workpiece.modes.push_back(Mode::from_stiffness(310.0, 0.02, 8e6, {std::cos(kPi / 6), std::sin(kPi / 6)}));
  TimeDomainOptions o;
  o.relative_tolerance = rtol;
  TimeDomainSimulator sim(model, Process::turning({2.4e9}), o);
  SimulationSettings s;
  s.spindle_rpm = 3000;
  s.depth_m = 0.0;
  s.periods = 40;  // 0.8 s: 75 tool and 250 workpiece cycles
  s.linear = true;
  s.initial_state = {2e-6, -1e-6, 1e-3, 4e-3};  // q_tool, q_work, q̇_tool, q̇_work
  const SimulationResult r = sim.simulate(s);
  EXPECT_EQ(r.series.size(), static_cast<std::size_t>(40 * r.samples_per_period + 1));
  double err = 0.0, peak = 0.0;
  for (const SeriesSample& x : r.series) {
    const double qt = free_vibration(x.t_s, 94.22, 0.033, 2e-6, 1e-3);
    const double qw = free_vibration(x.t_s, 310.0, 0.02, -1e-6, 4e-3);
    err = std::max({err, std::abs(x.tool_x_m - qt), std::abs(x.tool_y_m),
                    std::abs(x.workpiece_x_m - qw * std::cos(kPi / 6)),
                    std::abs(x.workpiece_y_m - qw * std::sin(kPi / 6)),
                    std::abs(x.rel_x_m - (qt - qw * std::cos(kPi / 6)))});
    peak = std::max(peak, std::abs(qt));
  }
  EXPECT_GT(peak, 1e-6);
  return err / peak;
}

TEST(TimeDomainFreeVibration, MatchesExactSolutionAndErrorFallsWithTolerance) {
  const double e6 = free_vibration_error(1e-6);
  const double e8 = free_vibration_error(1e-8);
  const double e10 = free_vibration_error(1e-10);
  // Global error within a small multiple of the tolerance …
  EXPECT_LT(e6, kGlobalErrorPerRtol * 1e-6) << e6;
  EXPECT_LT(e8, kGlobalErrorPerRtol * 1e-8) << e8;
  // … and falling when it is tightened.
  EXPECT_LT(e8, e6 / kTighterFactor) << e6 << " " << e8;
  EXPECT_LT(e10, e8 / kTighterFactor) << e8 << " " << e10;
}

struct GrowthCase {
  const char* config;
  double rpm, depth_mm;
};

TEST(TimeDomainLinear, GrowthPerPeriodMatchesSdmSpectralRadius) {
  const std::vector<GrowthCase> cases = {
      {"milling_benchmark_ae005_down.toml", 8000, 1.9},   // Hopf, stable
      {"milling_benchmark_ae005_down.toml", 12000, 2.0},  // Hopf, unstable
      {"milling_benchmark_ae005_down.toml", 17000, 3.6},  // flip lobe, unstable
      {"milling_benchmark_ae005_down.toml", 20000, 1.0},  // stable
      {"seed_turning_1dof.toml", 1000, 1.5},              // turning, unstable
      {"seed_turning_1dof.toml", 3000, 2.1},              // turning, stable
  };
  for (const GrowthCase& c : cases) {
    const Config cfg = config(c.config);
    SemiDiscretizationSolver sdm(cfg.model, cfg.process);
    const FloquetResult f = sdm.analyse(c.rpm, c.depth_mm * 1e-3);
    TimeDomainSimulator sim(cfg.model, cfg.process);
    SimulationSettings s;
    s.spindle_rpm = c.rpm;
    s.depth_m = c.depth_mm * 1e-3;
    s.periods = 120;
    s.linear = true;
    s.record_series = false;
    const SimulationResult r = sim.simulate(s);
    SCOPED_TRACE(std::string(c.config) + " at " + std::to_string(c.rpm) + " rev/min, " + std::to_string(c.depth_mm) +
                 " mm");
    EXPECT_NEAR(r.growth_per_period / f.spectral_radius, 1.0, kGrowthVsSdm)
        << "td " << r.growth_per_period << " sdm " << f.spectral_radius;
    // The dominant multipliers themselves agree (same type, same argument).
    EXPECT_LT(std::abs(r.dominant_multiplier - f.dominant_multiplier), 2 * kGrowthVsSdm * f.spectral_radius)
        << r.dominant_multiplier << " vs " << f.dominant_multiplier;
    EXPECT_EQ(r.verdict == SimulationVerdict::kStable, f.stable());
  }
}

TEST(TimeDomainNonlinear, VerdictChangesAcrossTheSdmLimitInHopfAndFlipLobes) {
  const Config cfg = config("milling_benchmark_ae005_down.toml");
  SemiDiscretizationSolver sdm(cfg.model, cfg.process);
  TimeDomainSimulator sim(cfg.model, cfg.process);
  bool saw_flip = false;
  for (double rpm : {8000.0, 12000.0, 17000.0, 20000.0}) {
    FloquetResult at_limit;
    const StabilityLimit lim = sdm.limit_at(SpindleSpeed(rpm), &at_limit);
    ASSERT_TRUE(lim.bounded());
    for (double factor : {0.9, 1.1}) {
      SimulationSettings s;
      s.spindle_rpm = rpm;
      s.depth_m = factor * lim.depth_limit_m;
      s.periods = 200;
      s.feed_m = 1e-4;
      s.record_series = false;
      const SimulationResult r = sim.simulate(s);
      SCOPED_TRACE(std::to_string(rpm) + " rev/min, " + std::to_string(factor) + " x sdm limit: " + r.verdict_measure);
      EXPECT_EQ(r.verdict, factor < 1 ? SimulationVerdict::kStable : SimulationVerdict::kChatter);
      if (at_limit.type == MultiplierType::kFlip && factor > 1) {
        saw_flip = true;
        // Period doubling: the chatter sits at an odd multiple of half the
        // tooth-passing frequency.
        const double half_orders = r.chatter_frequency_hz / (0.5 * r.tooth_passing_hz);
        EXPECT_NEAR(half_orders, std::round(half_orders), kHalfOrder);
        EXPECT_EQ(static_cast<long>(std::round(half_orders)) % 2, 1);
      }
    }
  }
  EXPECT_TRUE(saw_flip) << "17 000 rev/min should be in case C's flip lobe";
}

TEST(TimeDomainNonlinear, UnstableRunStaysBoundedAndChattersNearSdmFrequency) {
  const Config cfg = config("milling_benchmark_ae005_down.toml");
  SemiDiscretizationSolver sdm(cfg.model, cfg.process);
  TimeDomainSimulator sim(cfg.model, cfg.process);
  for (double rpm : {12000.0, 20000.0}) {
    FloquetResult at_limit;
    const StabilityLimit lim = sdm.limit_at(SpindleSpeed(rpm), &at_limit);
    SimulationSettings s;
    s.spindle_rpm = rpm;
    s.depth_m = 1.5 * lim.depth_limit_m;
    s.multiple_regeneration = true;
    s.record_series = false;
    s.periods = 200;
    const SimulationResult a = sim.simulate(s);
    s.periods = 1000;
    const SimulationResult b = sim.simulate(s);
    SCOPED_TRACE(std::to_string(rpm) + " rev/min: " + b.verdict_measure);
    EXPECT_EQ(a.verdict, SimulationVerdict::kChatter);
    EXPECT_EQ(b.verdict, SimulationVerdict::kChatter);
    EXPECT_GT(b.out_of_cut_fraction, kSaturatedAirFraction);  // the tool leaves the cut …
    // … which bounds the vibration: five times longer, same amplitude.
    EXPECT_GT(a.max_amplitude_m, 0.0);
    EXPECT_NEAR(b.max_amplitude_m / a.max_amplitude_m, 1.0, kSaturatedAmplitudeDrift)
        << b.max_amplitude_m << " vs " << a.max_amplitude_m;
    EXPECT_NEAR(b.chatter_frequency_hz / at_limit.chatter_frequency_hz, 1.0, kChatterFrequency)
        << b.chatter_frequency_hz << " vs sdm " << at_limit.chatter_frequency_hz;
  }
}

TEST(TimeDomainHistory, BufferDoesNotGrowWithSimulatedTime) {
  const Config cfg = config("milling_benchmark_ae005_down.toml");
  TimeDomainSimulator sim(cfg.model, cfg.process);
  for (bool multiple : {false, true}) {
    SCOPED_TRACE(multiple ? "multiple regeneration" : "single regeneration");
    SimulationSettings s;
    s.spindle_rpm = 17000;
    s.depth_m = 3.6e-3;  // chatter with contact loss: root stops and their images add entries
    s.multiple_regeneration = multiple;
    s.record_series = false;
    s.periods = 100;
    const SimulationResult a = sim.simulate(s);
    s.periods = 1000;
    const SimulationResult b = sim.simulate(s);
    EXPECT_GT(b.root_stops, 5 * a.root_stops / 2);
    EXPECT_GT(b.restarts, 5 * a.restarts);
    EXPECT_EQ(a.history_capacity, b.history_capacity);
    EXPECT_LE(b.history_max_entries, b.history_capacity);
    // About 1.5 delays of samples plus the event entries, whatever the length of the run.
    EXPECT_LT(b.history_capacity, static_cast<std::size_t>(6 * b.samples_per_period));
  }
}

// With multiple regeneration the surface keeps a kink where the tool left the
// cut; it reaches the chip one delay later. Those delay images of the chip's
// zero crossings are stop points, so the error keeps falling with the
// tolerance. Stepping across them instead left an error floor of about
// 5e-4 of the amplitude (measured, 200 periods), whatever the tolerance.
TEST(TimeDomainNonlinear, MultipleRegenerationConvergesWithTolerance) {
  const Config cfg = config("milling_benchmark_ae005_down.toml");
  auto run = [&](double rtol) {
    TimeDomainOptions o;
    o.relative_tolerance = rtol;
    TimeDomainSimulator sim(cfg.model, cfg.process, o);
    SimulationSettings s;
    s.spindle_rpm = 17000;
    s.depth_m = 3.6e-3;  // flip chatter, the tool leaves the cut
    s.multiple_regeneration = true;
    s.periods = 100;
    return sim.simulate(s);
  };
  const SimulationResult ref = run(1e-12);
  ASSERT_GT(ref.out_of_cut_fraction, 0.05);
  ASSERT_GT(ref.root_stops, 20);
  double peak = 0.0;
  for (const SeriesSample& x : ref.series) peak = std::max(peak, std::abs(x.rel_x_m));
  auto error = [&](const SimulationResult& r) {
    EXPECT_EQ(r.series.size(), ref.series.size());
    double e = 0.0;
    for (std::size_t i = 0; i < std::min(r.series.size(), ref.series.size()); ++i)
      e = std::max(e, std::abs(r.series[i].rel_x_m - ref.series[i].rel_x_m));
    return e / peak;
  };
  const double e7 = error(run(1e-7)), e9 = error(run(1e-9));
  EXPECT_LT(e7, 1e-3) << e7;
  EXPECT_LT(e9, 2e-5) << e9;
  EXPECT_LT(e9, e7 / 10) << e7 << " " << e9;
}

TEST(TimeDomainLobes, LimitByBisectionMatchesSdm) {
  for (const auto& [name, rpm] : {std::pair{"milling_benchmark_ae005_down.toml", 20000.0},
                                  std::pair{"seed_turning_1dof.toml", 3000.0}}) {
    const Config cfg = config(name);
    SemiDiscretizationSolver sdm(cfg.model, cfg.process);
    TimeDomainOptions o;
    o.periods = 200;
    TimeDomainSolver td(cfg.model, cfg.process, o);
    const StabilityLimit a = td.limit_at(SpindleSpeed(rpm));
    const StabilityLimit b = sdm.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(a.bounded());
    // Bracket width 1 %, sdm within 0.5 % of exact.
    EXPECT_NEAR(a.depth_limit_m / b.depth_limit_m, 1.0, kBisectionVsSdm)
        << name << ": " << a.depth_limit_m << " vs sdm " << b.depth_limit_m;
    EXPECT_NEAR(a.chatter_frequency_hz / b.chatter_frequency_hz, 1.0, kChatterFrequency) << name;
  }
}

// Random models (1–3 modes on either body at any angle, turning or milling
// with 1–4 teeth, up or down, any immersion): the linear growth factor equals
// sdm's spectral radius, and the nonlinear verdict is sdm's away from rho = 1,
// with bounded (saturated) chatter where rho > 1.
TEST(TimeDomainProperties, RandomModelsAgreeWithSdm) {
  std::mt19937_64 g(20261122);
  auto log_uniform = [&](double lo, double hi) {
    return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(g));
  };
  std::uniform_int_distribution<int> modes(1, 3), coin(0, 1), teeth(1, 4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0, stable_compared = 0, unstable_compared = 0;
  for (int trial = 0; trial < 12; ++trial) {
    StructuralModel model;
    const int n = modes(g);
    for (int i = 0; i < n; ++i) {
      const double a = kPi * unit(g);
      (coin(g) ? model.tool : model.workpiece)
          .modes.push_back(Mode::from_stiffness(log_uniform(200, 2000), log_uniform(0.01, 0.08), log_uniform(1e6, 1e8),
                                                {std::cos(a), std::sin(a)}));
    }
    const bool turning = coin(g);
    const double kt = log_uniform(2e8, 2e9);
    const Process process =
        turning ? Process::turning({kt})
                : Process::milling({teeth(g), kt, 0.3 * kt, std::max(0.05, unit(g)),
                                    coin(g) ? MillingDirection::kDown : MillingDirection::kUp});
    const double rpm = turning ? log_uniform(1500, 6000) : log_uniform(4000, 20000);
    SemiDiscretizationSolver sdm(model, process);
    const StabilityLimit lim = sdm.limit_at(SpindleSpeed(rpm));
    if (!lim.bounded()) continue;
    const double depth = lim.depth_limit_m * (0.7 + 0.6 * unit(g));
    const FloquetResult f = sdm.analyse(rpm, depth);
    TimeDomainSimulator sim(model, process);
    SimulationSettings s;
    s.spindle_rpm = rpm;
    s.depth_m = depth;
    s.periods = 150;
    s.linear = true;
    s.record_series = false;
    const SimulationResult r = sim.simulate(s);
    SCOPED_TRACE("trial " + std::to_string(trial) + ": " + std::to_string(n) + " modes, " +
                 (turning ? "turning" : "milling") + " at " + std::to_string(rpm) + " rev/min, " +
                 std::to_string(depth * 1e3) + " mm");
    EXPECT_NEAR(r.growth_per_period / f.spectral_radius, 1.0, 2 * kGrowthVsSdm)
        << r.growth_per_period << " vs " << f.spectral_radius;
    s.linear = false;
    s.multiple_regeneration = coin(g);
    const SimulationResult nl = sim.simulate(s);
    // The static chip moves the tool; the contact-loss fraction is a fraction.
    EXPECT_GT(nl.max_amplitude_m, 0.0);
    EXPECT_GE(nl.out_of_cut_fraction, 0.0);
    EXPECT_LE(nl.out_of_cut_fraction, 1.0);
    if (f.spectral_radius < 1.0 - kVerdictMargin) {
      // Stable by Floquet theory: the nonlinear run is stable too (the
      // start-up transient about the forced vibration of the static chip
      // decays; it may leave the cut briefly, less and less).
      EXPECT_EQ(nl.verdict, SimulationVerdict::kStable) << nl.verdict_measure;
      ++stable_compared;
    } else if (f.spectral_radius > 1.0 + kVerdictMargin) {
      // Unstable: the vibration grows until the tool leaves the cut, which
      // bounds it — saturated chatter, increments at |mu| = 1 to within the
      // verdict's margin, while the linear run keeps growing by rho.
      EXPECT_EQ(nl.verdict, SimulationVerdict::kChatter) << nl.verdict_measure;
      EXPECT_GT(nl.out_of_cut_fraction, 0.0) << nl.verdict_measure;
      EXPECT_NEAR(nl.growth_per_period, 1.0, kSaturatedGrowth) << nl.verdict_measure;
      ++unstable_compared;
    }
    ++checked;
  }
  EXPECT_GE(checked, 8);
  // Both branches ran (measured: 4 stable, 7 unstable of 11 checked).
  EXPECT_GE(stable_compared, 2);
  EXPECT_GE(unstable_compared, 2);
}

// Extremes of the edge-case list (docs/reliability.md): every run ends with
// finite numbers or a clear InputError, never NaN, a hang or a crash.
// A bound that only catches a blown-up fit: a growth of 10 per period.
constexpr double kEdgeGrowthBound = 10.0;
TEST(TimeDomainEdgeCases, ExtremeModelsAndSpeedsGiveFiniteResultsOrInputError) {
  struct Case {
    const char* what;
    StructuralModel model;
    double rpm;
    bool expect_input_error;
  };
  auto one = [](double f, double zeta, double k) {
    StructuralModel m;
    m.tool.modes.push_back(Mode::from_stiffness(f, zeta, k, {1, 0}));
    return m;
  };
  StructuralModel stiff_and_soft = one(100.0, 0.03, 1e4);
  stiff_and_soft.workpiece.modes.push_back(Mode::from_stiffness(5e4, 0.03, 1e12, {0, 1}));
  const std::vector<Case> cases = {
      {"damping 0.99", one(922.0, 0.99, 1.34e6), 10000, false},
      {"damping 1e-6", one(922.0, 1e-6, 1.34e6), 10000, false},
      {"1e6 rev/min", one(922.0, 0.011, 1.34e6), 1e6, false},
      {"1e4 beside 1e12 N/m at 20 000 rev/min", stiff_and_soft, 20000, false},
      {"1e4 beside 1e12 N/m at 10 rev/min (too many samples)", stiff_and_soft, 10, true},
  };
  const Process milling = Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kDown});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    TimeDomainSimulator sim(c.model, milling);
    for (bool linear : {false, true}) {
      SimulationSettings s;
      s.spindle_rpm = c.rpm;
      s.depth_m = 1e-3;
      s.periods = 30;
      s.linear = linear;
      s.record_series = false;
      if (c.expect_input_error) {
        EXPECT_THROW(sim.simulate(s), InputError);
        continue;
      }
      const SimulationResult r = sim.simulate(s);
      SCOPED_TRACE(linear ? "linear" : "nonlinear");
      // Something moves (initial perturbation or static chip), by a finite
      // amount (no physical bound: the 1e4 N/m mode deflects 6 mm statically).
      EXPECT_GT(r.max_amplitude_m, 0.0);
      EXPECT_TRUE(std::isfinite(r.max_amplitude_m));
      if (linear) {
        // The rescaled linear run always has periods to fit.
        EXPECT_GT(r.growth_per_period, 0.0) << r.verdict_measure;
        EXPECT_LT(r.growth_per_period, kEdgeGrowthBound) << r.verdict_measure;
        EXPECT_EQ(r.verdict == SimulationVerdict::kChatter, r.growth_per_period >= 1.0) << r.verdict_measure;
      } else if (std::isnan(r.growth_per_period)) {
        // No estimate only when the increments fell to the noise (periodic)
        // or the decision rests on the contact loss alone.
        EXPECT_TRUE(r.verdict_measure.find("periodic") != std::string::npos ||
                    r.verdict_measure.find("in air") != std::string::npos)
            << r.verdict_measure;
      } else {
        EXPECT_GT(r.growth_per_period, 0.0) << r.verdict_measure;
      }
      EXPECT_FALSE(r.verdict_measure.empty());
      ASSERT_FALSE(r.spectrum_amplitude_m.empty());
      for (double a : r.spectrum_amplitude_m) ASSERT_TRUE(std::isfinite(a));
    }
  }
}

TEST(TimeDomain, ReproducibleBitForBit) {
  const Config cfg = config("milling_benchmark_ae005_down.toml");
  TimeDomainSimulator sim(cfg.model, cfg.process);
  SimulationSettings s;
  s.spindle_rpm = 15000;
  s.depth_m = 2e-3;
  s.periods = 40;
  const SimulationResult a = sim.simulate(s), b = sim.simulate(s);
  ASSERT_EQ(a.series.size(), b.series.size());
  for (std::size_t i = 0; i < a.series.size(); ++i) ASSERT_EQ(a.series[i].rel_x_m, b.series[i].rel_x_m);
  EXPECT_EQ(a.steps, b.steps);
}

TEST(TimeDomain, RefusesBadInput) {
  const Config cfg = config("milling_benchmark_ae005_down.toml");
  TimeDomainSimulator sim(cfg.model, cfg.process);
  SimulationSettings s;
  s.spindle_rpm = 10000;
  s.depth_m = 1e-3;
  s.periods = 20;
  auto bad = [&](auto mutate) {
    SimulationSettings x = s;
    mutate(x);
    EXPECT_THROW(sim.simulate(x), InputError);
  };
  bad([](SimulationSettings& x) { x.spindle_rpm = 0; });
  bad([](SimulationSettings& x) { x.spindle_rpm = std::nan(""); });
  bad([](SimulationSettings& x) { x.depth_m = -1e-3; });
  bad([](SimulationSettings& x) { x.periods = 3; });
  bad([](SimulationSettings& x) { x.feed_m = -1e-4; });
  bad([](SimulationSettings& x) { x.initial_state = {1.0}; });
  bad([](SimulationSettings& x) { x.spindle_rpm = 1e-3; });  // needs too many samples per delay
  TimeDomainOptions o;
  o.relative_tolerance = 0.5;
  EXPECT_THROW(TimeDomainSimulator(cfg.model, cfg.process, o), InputError);
  EXPECT_THROW(TimeDomainSimulator(StructuralModel{}, cfg.process), InputError);
}

TEST(TimeDomain, NoCutNoMotion) {
  // Nonlinear mode at rest with depth 0: nothing moves, stable, no NaN.
  const Config cfg = config("seed_turning_1dof.toml");
  TimeDomainSimulator sim(cfg.model, cfg.process);
  SimulationSettings s;
  s.spindle_rpm = 2000;
  s.depth_m = 0.0;
  s.periods = 20;
  const SimulationResult r = sim.simulate(s);
  EXPECT_EQ(r.verdict, SimulationVerdict::kStable);
  EXPECT_EQ(r.max_amplitude_m, 0.0);
  EXPECT_TRUE(std::isnan(r.chatter_frequency_hz));
}

}  // namespace
}  // namespace chatter

namespace chatter {
namespace {

// One definition of "a harmonic" (SimulationResult::spectrum_harmonic): the
// lines marked k lie within 2.5 frequency resolutions of k / floquet_period_s,
// no line nearer than that to a multiple is unmarked, and the chatter
// frequency is never on a marked line (the spectrum CSV's `harmonic` column
// prints this field: records' spectrum_harmonics). Milling case C in its flip
// lobe (17 000 rev/min, 3.6 mm: chatter at ~ (k + 1/2) f_tp) and turning.
TEST(TimeDomainSpectrum, HarmonicLinesHaveOneDefinition) {
  struct Case {
    const char* config;
    double rpm, depth_mm;
  };
  for (const Case& c : {Case{"milling_benchmark_ae005_down.toml", 17000, 3.6}, Case{"seed_turning_1dof.toml", 1000, 1.5}}) {
    SCOPED_TRACE(c.config);
    const Config cfg = config(c.config);
    TimeDomainSimulator sim(cfg.model, cfg.process);
    SimulationSettings s;
    s.spindle_rpm = c.rpm;
    s.depth_m = c.depth_mm * 1e-3;
    s.periods = 120;
    s.record_series = false;
    const SimulationResult r = sim.simulate(s);
    ASSERT_EQ(r.spectrum_harmonic.size(), r.spectrum_hz.size());
    ASSERT_GT(r.spectrum_hz.size(), 10u);
    // The resolution of the analysed window (its second half): 1 / its length.
    const double window_s = (r.periods - r.analysed_from_period) * r.floquet_period_s;
    const double res = 1.0 / window_s;
    const double f1 = 1.0 / r.floquet_period_s;
    int marked = 0;
    for (std::size_t k = 0; k < r.spectrum_hz.size(); ++k) {
      const double f = r.spectrum_hz[k];
      const long h = std::lround(f / f1);
      const double off = std::abs(f - static_cast<double>(h) * f1);
      if (r.spectrum_harmonic[k] > 0) {
        ++marked;
        EXPECT_EQ(r.spectrum_harmonic[k], h) << f;
        EXPECT_LE(off, 2.5 * res * (1 + 0.02)) << f;
      } else if (h >= 1) {
        EXPECT_GE(off, 2.5 * res * (1 - 0.02)) << f;
      }
    }
    EXPECT_GT(marked, 0);
    ASSERT_EQ(r.verdict, SimulationVerdict::kChatter);
    ASSERT_TRUE(std::isfinite(r.chatter_frequency_hz));
    // The chatter line is not a harmonic line.
    std::size_t nearest = 0;
    for (std::size_t k = 1; k < r.spectrum_hz.size(); ++k)
      if (std::abs(r.spectrum_hz[k] - r.chatter_frequency_hz) < std::abs(r.spectrum_hz[nearest] - r.chatter_frequency_hz))
        nearest = k;
    EXPECT_EQ(r.spectrum_harmonic[nearest], 0) << r.chatter_frequency_hz << " Hz";
  }
}

}  // namespace
}  // namespace chatter
