// Gauss collocation of the `sdm` solver (SemiDiscretizationOptions::
// collocation_nodes, docs/sdm.md "Collocation") against the first-order
// semi-discretisation extrapolated to zero step (an independent
// discretisation), its own order of convergence (2s at s nodes), the
// multiplier type and chatter frequency the first order reports (flip and
// Hopf lobes), ρ = 1 at the reported limit, and the cuts it refuses (real
// cutters: tests/test_sdm_cutter_collocation.cpp; turning:
// tests/test_sdm_turning_collocation.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "chatter/error.hpp"
#include "chatter/semi_discretization.hpp"

namespace chatter {
namespace {

// The peers' benchmark of issue 32 (bench/bench_peers.cpp): case C's mode
// in X and in Y, 2 teeth, a_e/D = 0.05, up-milling.
StructuralModel peers_model() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {0.0, 1.0}));
  return m;
}
Process peers_process() { return Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kUp}); }

// Tolerances (relative).
// Three nodes at the default 8 steps against the zero-step limit: measured
// 2.8e-6, 3.1e-5 and 1.2e-4 at 5 000, 8 800 and 18 400 rev/min (the worst
// of the 101 speeds of the benchmark: 1.4e-4, docs/sdm.md).
constexpr double kDefaultStepsAgree = 2e-4;
// The reference: first-order steps at 256 and 512 per period and per
// vibration cycle, Richardson-extrapolated for their h² error; its own
// error is below 1e-6 (the extrapolation of 512 and 1 024 differs by less).
constexpr int kReferenceSteps = 256;
// Order 2s: halving the step divides the error by 2^(2s) = 16 (s = 2) and
// 64 (s = 3). Measured at 5 000 rev/min: 15.9 (s = 2, 16 → 32 steps) and
// 39 (s = 3, 8 → 16 steps; 63 from 16 → 32); accepted from 12 and 32.
constexpr double kOrderFourRatioMin = 12.0, kOrderSixRatioMin = 32.0;
// The depth search's tolerance for the order and reference runs (the
// errors measured go down to 1e-8).
constexpr double kTightDepth = 1e-10;
// ρ at the reported limit (the default depth tolerance is 1e-4 in depth).
constexpr double kUnitCircle = 1e-3;

SemiDiscretizationOptions options(int nodes, int steps, double depth_tolerance = 1e-4) {
  SemiDiscretizationOptions o;
  o.depth_max_m = 0.01;
  o.collocation_nodes = nodes;
  o.steps_per_period = o.steps_per_vibration_cycle = steps;
  o.depth_tolerance = depth_tolerance;
  return o;
}

double limit(const SemiDiscretizationOptions& o, double rpm) {
  const SemiDiscretizationSolver s(peers_model(), peers_process(), o);
  const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
  EXPECT_TRUE(l.bounded()) << rpm;
  return l.depth_limit_m;
}

double zero_step_limit(double rpm) {
  const double a = limit(options(0, kReferenceSteps, kTightDepth), rpm);
  const double b = limit(options(0, 2 * kReferenceSteps, kTightDepth), rpm);
  return b + (b - a) / 3.0;
}

TEST(SdmCollocation, ThreeNodesAtEightStepsMatchTheZeroStepFirstOrderLimit) {
  for (double rpm : {5000.0, 8800.0, 18400.0}) {
    const double ref = zero_step_limit(rpm);
    const double c = limit(options(3, kCollocationSteps), rpm);
    EXPECT_NEAR(c / ref, 1.0, kDefaultStepsAgree) << rpm << " rev/min: collocation " << c << " m vs " << ref;
    // The first order at its default steps is 10-100 times further off
    // (1.2 % at 18 400 rev/min): the reason collocation exists.
    const double first = limit(options(0, 64), rpm);
    EXPECT_GT(std::abs(first / ref - 1.0), 3.0 * std::abs(c / ref - 1.0)) << rpm;
  }
}

TEST(SdmCollocation, SeveralTeethInTheCutSlottingAndOneToothAgree) {
  // Grids with segments of one and two teeth cutting (4 teeth, a_e/D = 0.5
  // up), no free flight at all (slotting: the map holds the whole period),
  // 3 teeth at 0.3 down and one tooth (a long free flight), on two modes of
  // different frequencies in X and Y; against the zero-step first order.
  // Measured over 21 speeds 3 000–25 000 rev/min: worst 2.0e-5, 2.2e-5,
  // 2.4e-5, 3.5e-5, and the same multiplier type everywhere.
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(1150.0, 0.02, 0.05, {0.0, 1.0}));
  struct Cut {
    int teeth;
    double immersion;
    MillingDirection direction;
  };
  for (const Cut c : {Cut{4, 0.5, MillingDirection::kUp}, Cut{4, 1.0, MillingDirection::kDown},
                      Cut{3, 0.3, MillingDirection::kDown}, Cut{1, 0.2, MillingDirection::kUp}}) {
    const Process p = Process::milling({c.teeth, 6e8, 2e8, c.immersion, c.direction});
    for (double rpm : {4100.0, 9600.0, 15100.0, 20600.0}) {
      SCOPED_TRACE(std::to_string(c.teeth) + " teeth, a_e/D " + std::to_string(c.immersion) + ", " +
                   std::to_string(rpm) + " rev/min");
      SemiDiscretizationOptions fine = options(0, kReferenceSteps, kTightDepth), finer = fine;
      finer.steps_per_period = finer.steps_per_vibration_cycle = 2 * kReferenceSteps;
      fine.depth_max_m = finer.depth_max_m = 0.02;
      SemiDiscretizationOptions coll = options(3, kCollocationSteps);
      coll.depth_max_m = 0.02;
      FloquetResult ff, fc;
      const StabilityLimit a = SemiDiscretizationSolver(m, p, fine).limit_at(SpindleSpeed(rpm), &ff);
      const StabilityLimit b = SemiDiscretizationSolver(m, p, finer).limit_at(SpindleSpeed(rpm));
      const StabilityLimit k = SemiDiscretizationSolver(m, p, coll).limit_at(SpindleSpeed(rpm), &fc);
      ASSERT_TRUE(a.bounded() && b.bounded() && k.bounded());
      const double ref = b.depth_limit_m + (b.depth_limit_m - a.depth_limit_m) / 3.0;
      EXPECT_NEAR(k.depth_limit_m / ref, 1.0, kDefaultStepsAgree);
      EXPECT_EQ(fc.type, ff.type);
      EXPECT_NEAR(k.chatter_frequency_hz, a.chatter_frequency_hz, 0.5);  // Hz
    }
  }
}

TEST(SdmCollocation, HalvingTheStepDividesTheErrorByTwoToTheTwoS) {
  const double rpm = 5000.0;
  const double ref = limit(options(3, 64, kTightDepth), rpm);  // error ~1e-11 by the order below
  auto err = [&](int nodes, int steps) { return std::abs(limit(options(nodes, steps, kTightDepth), rpm) / ref - 1.0); };
  const double e2a = err(2, 16), e2b = err(2, 32);
  EXPECT_GT(e2a / e2b, kOrderFourRatioMin) << "s = 2: " << e2a << " → " << e2b;
  const double e3a = err(3, 8), e3b = err(3, 16);
  EXPECT_GT(e3a / e3b, kOrderSixRatioMin) << "s = 3: " << e3a << " → " << e3b;
}

TEST(SdmCollocation, TypeFrequencyAndRadiusAreTheFirstOrdersFlipAndHopf) {
  // Case C's mode in X only, down-milling at a_e/D = 0.05 (tests/test_sdm.cpp
  // LowImmersionFlipLobeThatTheTransferFunctionMisses): flip lobes at 16 000
  // and 18 000 rev/min, Hopf lobes at 5 000 and 12 000.
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  const Process p = Process::milling({2, 6e8, 2e8, 0.05, MillingDirection::kDown});
  SemiDiscretizationOptions fine = options(0, 256);
  const SemiDiscretizationSolver first(m, p, fine);
  const SemiDiscretizationSolver coll(m, p, options(3, kCollocationSteps));
  for (double rpm : {5000.0, 12000.0, 16000.0, 18000.0}) {
    FloquetResult ff, fc;
    const StabilityLimit a = first.limit_at(SpindleSpeed(rpm), &ff);
    const StabilityLimit b = coll.limit_at(SpindleSpeed(rpm), &fc);
    ASSERT_TRUE(a.bounded() && b.bounded()) << rpm;
    EXPECT_EQ(fc.type, ff.type) << rpm;
    EXPECT_NEAR(b.depth_limit_m / a.depth_limit_m, 1.0, 1e-3) << rpm;
    EXPECT_NEAR(b.chatter_frequency_hz, a.chatter_frequency_hz, 0.5) << rpm;  // Hz
    EXPECT_EQ(b.lobe, a.lobe) << rpm;
    EXPECT_NEAR(fc.spectral_radius, 1.0, kUnitCircle) << rpm;
    if (fc.type == MultiplierType::kFlip) {  // f = (k + 1/2) × tooth passing, exactly
      const double tooth_hz = 2.0 * rpm / 60.0;
      EXPECT_NEAR(std::abs(std::remainder(b.chatter_frequency_hz / tooth_hz, 1.0)), 0.5, 1e-9) << rpm;
    }
  }
  FloquetResult f16;
  coll.limit_at(SpindleSpeed(16000.0), &f16);
  EXPECT_EQ(f16.type, MultiplierType::kFlip);
  FloquetResult f5;
  coll.limit_at(SpindleSpeed(5000.0), &f5);
  EXPECT_EQ(f5.type, MultiplierType::kHopf);
  // The map holds 3 samples per cutting step (n_r = 1: one direction), none
  // for free flight.
  EXPECT_EQ(f5.map_dimension, 2 + 3 * (f5.steps - 1));
}

TEST(SdmCollocation, AnalyseAgreesWithTheSearchAtTheLimit) {
  const SemiDiscretizationSolver s(peers_model(), peers_process(), options(3, kCollocationSteps));
  FloquetResult at;
  const StabilityLimit l = s.limit_at(SpindleSpeed(7000.0), &at);
  ASSERT_TRUE(l.bounded());
  const FloquetResult again = s.analyse(7000.0, l.depth_limit_m);
  EXPECT_EQ(again.spectral_radius, at.spectral_radius);
  EXPECT_EQ(again.chatter_frequency_hz, at.chatter_frequency_hz);
  EXPECT_LT(s.analyse(7000.0, 0.99 * l.depth_limit_m).spectral_radius, 1.0);
  EXPECT_GT(s.analyse(7000.0, 1.01 * l.depth_limit_m).spectral_radius, 1.0);
}

void expect_refused(const StructuralModel& m, const Process& p, const SemiDiscretizationOptions& o,
                    const std::string& words) {
  try {
    const SemiDiscretizationSolver s(m, p, o);
    s.limit_at(SpindleSpeed(5000.0));
    ADD_FAILURE() << "no InputError; expected: " << words;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(SdmCollocation, RefusesWhatItDoesNotModelNamingTheOption) {
  // The cuts it does not model: tests/test_sdm_turning_collocation.cpp.
  SemiDiscretizationOptions o = options(3, 8);
  o.collocation_nodes = 4;
  expect_refused(peers_model(), peers_process(), o, "collocation_nodes = 4: must be in [0, 3]");
  o.collocation_nodes = -2;
  expect_refused(peers_model(), peers_process(), o, "collocation_nodes = -2");
}

}  // namespace
}  // namespace chatter
