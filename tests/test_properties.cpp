// Property tests over randomly drawn valid models (fixed seeds, a fresh draw
// per trial): depth limits are positive, finite or exactly +inf, never NaN;
// the two transfer-function solvers agree; invariances that follow from the
// equations hold for randomly drawn scale factors; one-mode models meet their
// closed forms; a limit does not depend on what else the solver was asked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

constexpr double kInvariance = 1e-9;     // exact invariances: round-off only
constexpr double kMethodsAgree = 1e-7;   // analytic vs coupled on random models
// The envelope may not dip below the absolute limit by more than the
// round-off of the two searches (both exact to ~1e-15): allowed 1e-9.
constexpr double kBelowAbsolute = 1e-9;
// |1 + a(1 − e^{−jωτ}) K_f g(ω)| at a reported 1-DOF root: O(1) terms, the
// root exact to round-off in ω.
constexpr double kResidual = 1e-9;
// The absolute limit against 2kζ(1+ζ)/K_f: the minimum is flat, its value
// exact to round-off.
constexpr double kClosedForm = 1e-9;

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
      const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lc = c.limit_at(SpindleSpeed(rpm));
      ++total;
      ASSERT_FALSE(std::isnan(la.depth_limit_m)) << "trial " << trial << " rpm " << rpm;
      ASSERT_GT(la.depth_limit_m, 0.0);
      ASSERT_EQ(la.bounded(), lc.bounded()) << "trial " << trial << " rpm " << rpm;
      if (!la.bounded()) {  // no limit: exactly +inf, not a huge finite number
        EXPECT_EQ(la.depth_limit_m, std::numeric_limits<double>::infinity()) << "trial " << trial << " rpm " << rpm;
        continue;
      }
      ++bounded;
      EXPECT_TRUE(std::isfinite(la.chatter_frequency_hz) && la.chatter_frequency_hz > 0.0);
      EXPECT_GE(la.lobe, 0);
      EXPECT_LE(la.depth_limit_m, 0.05);
      EXPECT_GE(la.depth_limit_m, abs_lim.depth_m * (1 - kBelowAbsolute))
          << "envelope below the absolute limit " << abs_lim.depth_m;
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
    const double s = log_uniform(g, 1e-3, 1e3);  // a different factor per model
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
      const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lb = b.limit_at(SpindleSpeed(rpm));
      ASSERT_EQ(la.bounded(), lb.bounded());
      if (!la.bounded()) continue;
      EXPECT_NEAR(lb.depth_limit_m / la.depth_limit_m, 1.0, kInvariance) << "trial " << trial << ", factor " << s;
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
      const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lb = b.limit_at(SpindleSpeed(rpm));
      ASSERT_EQ(la.bounded(), lb.bounded());
      if (la.bounded()) {
        EXPECT_NEAR(lb.depth_limit_m / la.depth_limit_m, 1.0, kMethodsAgree);
      }
    }
  }
}

TEST(Properties, ScalingTheCuttingCoefficientsAloneScalesTheDepthInversely) {
  // Only the product a·H₀ enters the equation: K → cK gives a → a/c at the
  // same chatter frequency and lobe (depth_max scaled alike).
  std::mt19937_64 g(13);
  for (int trial = 0; trial < 10; ++trial) {
    const Drawn d = draw(g);
    const double c = log_uniform(g, 0.05, 20.0);
    Process scaled = d.process;
    if (d.process.operation() == Operation::kTurning) {
      scaled = Process::turning({d.process.turning_parameters().feed_force_coefficient_n_per_m2 * c});
    } else {
      MillingParameters p = d.process.milling_parameters();
      p.tangential_coefficient_n_per_m2 *= c;
      p.radial_coefficient_n_per_m2 *= c;
      scaled = Process::milling(p);
    }
    const AnalyticSolver a(d.model, d.process, depth_max(0.05));
    const AnalyticSolver b(d.model, scaled, depth_max(0.05 / c));
    for (double rpm : evenly_spaced_speeds(800, 24000, 15)) {
      const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lb = b.limit_at(SpindleSpeed(rpm));
      ASSERT_EQ(la.bounded(), lb.bounded()) << "trial " << trial << " rpm " << rpm;
      if (!la.bounded()) continue;
      EXPECT_NEAR(lb.depth_limit_m * c / la.depth_limit_m, 1.0, kInvariance)
          << "trial " << trial << ", factor " << c << ": " << lb.depth_limit_m << " vs " << la.depth_limit_m;
      EXPECT_NEAR(lb.chatter_frequency_hz / la.chatter_frequency_hz, 1.0, kInvariance);
      EXPECT_EQ(lb.lobe, la.lobe);
    }
  }
}

TEST(Properties, OneModeTurningMeetsTheClosedForms) {
  // A single mode along X under turning: the limit solves
  // 1 + a(1 − e^{−jωτ}) K_f g(ω) = 0 and the absolute limit is 2kζ(1+ζ)/K_f.
  std::mt19937_64 g(17);
  for (int trial = 0; trial < 15; ++trial) {
    const double f = log_uniform(g, 50, 3000), zeta = log_uniform(g, 0.005, 0.2), k = log_uniform(g, 1e6, 1e9);
    const double kf = log_uniform(g, 1e8, 5e9);
    StructuralModel m;
    m.workpiece.modes.push_back(Mode::from_stiffness(f, zeta, k, {1.0, 0.0}));
    const double closed = 2.0 * k * zeta * (1.0 + zeta) / kf;
    const AnalyticSolver s(m, Process::turning({kf}), depth_max(4.0 * closed));
    EXPECT_NEAR(s.absolute_limit().depth_m / closed, 1.0, kClosedForm) << "trial " << trial;
    int bounded = 0;
    for (double rpm : evenly_spaced_speeds(0.02 * 60 * f, 2.0 * 60 * f, 12)) {  // 0.02 … 2 revolutions per vibration
      const StabilityLimit l = s.limit_at(SpindleSpeed(rpm));
      if (!l.bounded()) continue;
      ++bounded;
      const double w = 2.0 * std::numbers::pi * l.chatter_frequency_hz, tau = 60.0 / rpm;
      const double residual =
          std::abs(1.0 + l.depth_limit_m * (1.0 - std::exp(std::complex<double>(0.0, -w * tau))) * kf *
                             m.workpiece.modes[0].receptance(w));
      EXPECT_LT(residual, kResidual) << "trial " << trial << " rpm " << rpm << ": a = " << l.depth_limit_m;
      EXPECT_GE(l.depth_limit_m, closed * (1.0 - kClosedForm)) << "trial " << trial << " rpm " << rpm;
    }
    EXPECT_GT(bounded, 0) << "trial " << trial << ": depth_max 4× the minimum, yet nothing bounded";
  }
}

TEST(Properties, ALimitDoesNotDependOnTheOtherQueries) {
  // A solver keeps no state between speeds: each speed asked alone of a fresh
  // solver gives the same bits as within a sweep, and the sweep order does
  // not matter (a fresh draw per trial).
  std::mt19937_64 g(3);
  for (int trial = 0; trial < 5; ++trial) {
    const Drawn d = draw(g);
    std::vector<double> speeds = evenly_spaced_speeds(1000, 20000, 30);
    const AnalyticSolver sweep(d.model, d.process, depth_max(0.05));
    const auto rows = lobe_envelope(sweep, speeds);
    std::vector<std::size_t> order(speeds.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), g);
    const AnalyticSolver shuffled(d.model, d.process, depth_max(0.05));
    for (std::size_t i : order) {
      const StabilityLimit l = shuffled.limit_at(SpindleSpeed(speeds[i]));
      EXPECT_EQ(l.depth_limit_m, rows[i].depth_limit_m) << "trial " << trial << " rpm " << speeds[i];  // bitwise
      EXPECT_EQ(l.lobe, rows[i].lobe);
    }
    const std::size_t one = order.front();
    const StabilityLimit alone = AnalyticSolver(d.model, d.process, depth_max(0.05)).limit_at(SpindleSpeed(speeds[one]));
    EXPECT_EQ(alone.depth_limit_m, rows[one].depth_limit_m) << "trial " << trial;
  }
}

}  // namespace
}  // namespace chatter
