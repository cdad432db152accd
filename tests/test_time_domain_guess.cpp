// TimeDomainSolver's starting guess: built once, replaceable by the caller,
// and only the start of the depth search — never the answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "chatter/error.hpp"
#include "chatter/process.hpp"
#include "chatter/structural_model.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

// Case A (1-DOF turning, flexible workpiece), 3000 rev/min: a bounded limit
// near the closed-form minimum, quick to simulate.
constexpr double kStiffness = 45e6, kDamping = 0.033, kFeedForce = 2.4e9;
constexpr double kRpm = 3000.0;
// Each search ends with a bracket of relative width <= depth_tolerance around
// its midpoint (width <= depth_tolerance × its upper end = midpoint ×
// (1 + depth_tolerance / 2) at most); both brackets hold the same verdict
// boundary, so two midpoints differ by at most one bracket width.
constexpr double kDepthTolerance = 0.01;

StructuralModel case_a() {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(94.22, kDamping, kStiffness, {1.0, 0.0}));
  return m;
}

TimeDomainOptions options() {
  TimeDomainOptions o;
  o.periods = 100;
  o.depth_max_m = 0.02;
  o.depth_tolerance = kDepthTolerance;
  return o;
}

/// A guess that refuses every speed, as the analytic phase search does at
/// very low speed (too many lobes in one delay).
class RefusingSolver final : public LobeSolver {
 public:
  std::string method() const override { return "refusing"; }
  StabilityLimit limit_at(SpindleSpeed) const override { throw InputError("refused"); }
  double depth_max_m() const override { return 0.02; }
};

TEST(TimeDomainGuess, DefaultIsTheAnalyticSolverBuiltOnce) {
  const TimeDomainSolver td(case_a(), Process::turning({kFeedForce}), options());
  ASSERT_NE(td.starting_guess(), nullptr);
  EXPECT_EQ(td.starting_guess()->method(), "analytic");
  EXPECT_EQ(td.starting_guess()->depth_max_m(), options().depth_max_m);
}

TEST(TimeDomainGuess, CallerGuessIsUsedAndGivesTheSameSearch) {
  const Process process = Process::turning({kFeedForce});
  TransferFunctionOptions to;
  to.depth_max_m = options().depth_max_m;
  const auto guess = std::make_shared<const AnalyticSolver>(case_a(), process, to);
  const TimeDomainSolver with(case_a(), process, options(), guess);
  const TimeDomainSolver without(case_a(), process, options());
  EXPECT_EQ(with.starting_guess(), guess.get());
  const StabilityLimit a = with.limit_at(SpindleSpeed(kRpm)), b = without.limit_at(SpindleSpeed(kRpm));
  ASSERT_TRUE(a.bounded());
  // The same guess: the same verdict runs, the same bits.
  EXPECT_EQ(a.depth_limit_m, b.depth_limit_m) << a.depth_limit_m << " vs " << b.depth_limit_m;
}

TEST(TimeDomainGuess, RefusedGuessOnlyMovesTheStartOfTheSearch) {
  const Process process = Process::turning({kFeedForce});
  const TimeDomainSolver refused(case_a(), process, options(), std::make_shared<const RefusingSolver>());
  const TimeDomainSolver analytic(case_a(), process, options());
  const StabilityLimit a = refused.limit_at(SpindleSpeed(kRpm)), b = analytic.limit_at(SpindleSpeed(kRpm));
  ASSERT_TRUE(a.bounded());
  ASSERT_TRUE(b.bounded());
  const double width = kDepthTolerance * (1.0 + kDepthTolerance) * std::max(a.depth_limit_m, b.depth_limit_m);
  EXPECT_LE(std::abs(a.depth_limit_m - b.depth_limit_m), width)
      << a.depth_limit_m << " vs " << b.depth_limit_m;
}

}  // namespace
}  // namespace chatter
