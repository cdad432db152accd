// Property tests over randomly drawn valid models (fixed seed): depth limits
// are positive, finite or +inf, never NaN; the two transfer-function solvers
// agree; invariances that follow from the equations hold.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

constexpr double kInvariance = 1e-9;     // exact invariances: round-off only
constexpr double kMethodsAgree = 1e-7;   // analytic vs coupled on random models

struct Drawn {
  StructuralModel model;
  Process process = Process::turning({1e9});
};

// Log-uniform draw in [lo, hi].
double log_uniform(std::mt19937_64& g, double lo, double hi) {
  std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
  return std::exp(u(g));
}

Drawn draw(std::mt19937_64& g) {
  Drawn d;
  std::uniform_int_distribution<int> modes(1, 4), coin(0, 1), teeth(1, 6);
  std::uniform_real_distribution<double> angle(0.0, std::numbers::pi), unit(0.0, 1.0);
  const int n = modes(g);
  for (int i = 0; i < n; ++i) {
    const double a = angle(g);
    const Mode m = Mode::from_stiffness(log_uniform(g, 50, 3000), log_uniform(g, 0.005, 0.2), log_uniform(g, 1e6, 1e9),
                                        {std::cos(a), std::sin(a)});
    (coin(g) ? d.model.tool : d.model.workpiece).modes.push_back(m);
  }
  if (coin(g)) {
    d.process = Process::turning({log_uniform(g, 1e8, 5e9)});
  } else {
    const double kt = log_uniform(g, 1e8, 2e9);
    d.process = Process::milling({teeth(g), kt, kt * unit(g) * 0.6, std::max(0.02, unit(g)),
                                  coin(g) ? MillingDirection::kDown : MillingDirection::kUp});
  }
  return d;
}

TransferFunctionOptions depth_max(double d) {
  TransferFunctionOptions o;
  o.depth_max_m = d;
  return o;
}

TEST(Properties, RandomModelsGiveValidLimitsAndBothSolversAgree) {
  std::mt19937_64 g(20261122);
  int bounded = 0, total = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Drawn d = draw(g);
    const AnalyticSolver a(d.model, d.process, depth_max(0.05));
    const CoupledSolver c(d.model, d.process, depth_max(0.05));
    const AbsoluteLimit abs_lim = a.absolute_limit();
    for (double rpm : evenly_spaced_speeds(500, 30000, 25)) {
      const StabilityLimit la = a.limit_at(rpm), lc = c.limit_at(rpm);
      ++total;
      ASSERT_FALSE(std::isnan(la.depth_limit_m)) << "trial " << trial << " rpm " << rpm;
      ASSERT_GT(la.depth_limit_m, 0.0);
      ASSERT_EQ(la.bounded(), lc.bounded()) << "trial " << trial << " rpm " << rpm;
      if (!la.bounded()) continue;
      ++bounded;
      EXPECT_TRUE(std::isfinite(la.chatter_frequency_hz) && la.chatter_frequency_hz > 0.0);
      EXPECT_GE(la.lobe, 0);
      EXPECT_LE(la.depth_limit_m, 0.05);
      EXPECT_GE(la.depth_limit_m, abs_lim.depth_m * (1 - 1e-9)) << "envelope below the absolute limit";
      EXPECT_NEAR(lc.depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree) << "trial " << trial << " rpm " << rpm;
    }
  }
  EXPECT_GT(bounded, total / 4) << "draws too stable to test anything";
}

TEST(Properties, ScalingStiffnessesAndCuttingCoefficientsLeavesLobesUnchanged) {
  // a·H₀·G is unchanged when every k and every cutting coefficient scale alike.
  std::mt19937_64 g(7);
  for (int trial = 0; trial < 10; ++trial) {
    const Drawn d = draw(g);
    const double s = 37.5;
    Drawn scaled = d;
    for (Body* b : {&scaled.model.tool, &scaled.model.workpiece})
      for (Mode& m : b->modes) m.stiffness_n_per_m *= s;
    if (d.process.operation() == Operation::kTurning) {
      scaled.process = Process::turning({d.process.turning_parameters().feed_force_coefficient_n_per_m2 * s});
    } else {
      MillingParameters p = d.process.milling_parameters();
      p.tangential_coefficient_n_per_m2 *= s;
      p.radial_coefficient_n_per_m2 *= s;
      scaled.process = Process::milling(p);
    }
    const AnalyticSolver a(d.model, d.process, depth_max(0.05));
    const AnalyticSolver b(scaled.model, scaled.process, depth_max(0.05));
    for (double rpm : evenly_spaced_speeds(1000, 20000, 20)) {
      const StabilityLimit la = a.limit_at(rpm), lb = b.limit_at(rpm);
      ASSERT_EQ(la.bounded(), lb.bounded());
      if (!la.bounded()) continue;
      EXPECT_NEAR(lb.depth_limit_m / la.depth_limit_m, 1.0, kInvariance) << "trial " << trial;
      EXPECT_NEAR(lb.chatter_frequency_hz / la.chatter_frequency_hz, 1.0, kInvariance);
    }
  }
}

TEST(Properties, SwappingBodiesLeavesLobesUnchanged) {
  // G = G_tool + G_workpiece: which body holds a mode does not matter.
  std::mt19937_64 g(11);
  for (int trial = 0; trial < 10; ++trial) {
    const Drawn d = draw(g);
    StructuralModel swapped;
    swapped.tool = d.model.workpiece;
    swapped.workpiece = d.model.tool;
    const AnalyticSolver a(d.model, d.process, depth_max(0.05));
    const CoupledSolver b(swapped, d.process, depth_max(0.05));
    for (double rpm : evenly_spaced_speeds(1000, 20000, 20)) {
      const StabilityLimit la = a.limit_at(rpm), lb = b.limit_at(rpm);
      ASSERT_EQ(la.bounded(), lb.bounded());
      if (la.bounded()) {
        EXPECT_NEAR(lb.depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree);
      }
    }
  }
}

TEST(Properties, DeterministicAcrossRuns) {
  std::mt19937_64 g(3);
  const Drawn d = draw(g);
  const auto speeds = evenly_spaced_speeds(1000, 20000, 50);
  const auto first = lobe_envelope(AnalyticSolver(d.model, d.process, depth_max(0.05)), speeds);
  const auto second = lobe_envelope(AnalyticSolver(d.model, d.process, depth_max(0.05)), speeds);
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    EXPECT_EQ(first[i].depth_limit_m, second[i].depth_limit_m);  // bitwise
    EXPECT_EQ(first[i].lobe, second[i].lobe);
  }
}

}  // namespace
}  // namespace chatter
