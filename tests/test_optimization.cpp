// The process optimisation of issue 29 (include/chatter/optimization.hpp,
// docs/optimization.md) against known answers: the source study's (seed 003)
// loss coefficients and losses from its tables' indices, the exact removal
// rate, its table 14's initial point failing on diametral error and roughness
// and its optimum passing, the optimum against a brute-force grid written
// here, the stability constraint binding on the shaft when the depth is free,
// and the adaptive loop: converged within 30 iterations from three starts to
// within 5 % of the optimum, and again after a 5 % bias injected mid-run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/optimization.hpp"

namespace chatter {
namespace {

const std::string kSeed = std::string(CHATTER_SOURCE_DIR) + "/configs/turning_seed003_shaft.toml";

constexpr std::size_t kDd = 0, kRa = 1, kMrr = 2, kCost = 3, kProd = 4;

// The source study's loss: P_c = 12.36, all weights 20 %, critical values
// D_d 40 µm, Ra 3.6 µm, MRR 500 mm³/s, cost 1.5, production rate 60 /h.
LossSpec seed_loss() {
  LossSpec s;
  s.critical_loss = 12.36;
  s.weight = {0.2, 0.2, 0.2, 0.2, 0.2};
  s.critical = {40.0, 3.6, 500.0, 1.5, 60.0};
  return s;
}

double loss_of(const std::array<double, kLossIndexCount>& alpha, const std::array<double, 5>& x) {
  double p = 0.0;
  for (std::size_t i = 0; i < kLossIndexCount; ++i) p += loss_term(static_cast<PerformanceIndex>(i), alpha[i], x[i]);
  return p;
}

OptimizationModel seed_model(const Config& c, const std::function<void(OptimizationSpec&)>& edit = {}) {
  OptimizationSpec spec = *c.optimization;
  if (edit) edit(spec);
  return OptimizationModel(c.model, c.position, c.process, spec);
}

SetPoint turning_point(const OptimizationModel& m, double v_m_per_min, double f_mm, double d_mm) {
  return {spindle_rpm_of(m.spec().diameter_m, v_m_per_min), f_mm * 1e-3, d_mm * 1e-3};
}

IndexValues measured(double dd, double ra, double mrr, double cost, double prod) {
  IndexValues v = unknown_indices();
  v[kDd] = dd, v[kRa] = ra, v[kMrr] = mrr, v[kCost] = cost, v[kProd] = prod;
  return v;
}

std::vector<std::string> failing(const Performance& p) {
  std::vector<std::string> out;
  for (const ConstraintCheck& c : p.constraints)
    if (!c.ok) out.push_back(c.name);
  return out;
}

// ================================================================ the seed

TEST(SeedNumbers, AlphaCoefficients) {
  const auto a = loss_alpha(seed_loss());
  EXPECT_NEAR(a[kDd], 0.001545, 1e-9);
  EXPECT_NEAR(a[kRa], 0.19074, 1e-5);
  EXPECT_NEAR(a[kMrr], 1236.0, 1e-9);
  EXPECT_NEAR(a[kCost], 1.0987, 1e-4);
  EXPECT_NEAR(a[kProd], 148.32, 1e-9);
}

// The seed's tables print two decimals of indices it rounded itself: its
// losses agree with the formula to 0.02.
TEST(SeedNumbers, LossesOfTheTablesIndices) {
  const auto a = loss_alpha(seed_loss());
  EXPECT_NEAR(loss_of(a, {55.83, 6.40, 1750, 0.80, 75.68}), 16.01, 0.02);  // table 14, initial
  EXPECT_NEAR(loss_of(a, {22.12, 2.37, 641, 0.98, 63.90}), 7.13, 0.01);    // table 14, optimum
  EXPECT_NEAR(loss_of(a, {15.91, 2.35, 625, 0.99, 62.84}), 6.86, 0.01);    // table 15, test cut
}

TEST(SeedNumbers, ConfigGivesTheSeedsLossAndAlphas) {
  const Config c = load_config(kSeed);
  ASSERT_TRUE(c.optimization);
  EXPECT_NEAR(c.optimization->loss.critical_loss, 12.36, 1e-12);  // 7.5 + 3.94 + 0.92
  const OptimizationModel m = seed_model(c);
  const auto expect = loss_alpha(seed_loss());
  for (std::size_t i = 0; i < kLossIndexCount; ++i) EXPECT_NEAR(m.alpha()[i], expect[i], 1e-9 * expect[i]) << i;
}

TEST(SeedNumbers, RemovalRateAt200MPerMin) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  const Performance p = m.evaluate(turning_point(m, 200.0, 0.35, 1.5));
  EXPECT_NEAR(p.value[kMrr], 1750.0, 1e-9);
  EXPECT_NEAR(p.cutting_speed_m_per_min, 200.0, 1e-9);
}

// Table 14 reproduced from its indices (as `chatter performance --index`):
// the initial point fails on diametral error and roughness only, its optimum
// meets every constraint, stability included.
TEST(SeedNumbers, Table14InitialFailsOptimumPasses) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  const Performance initial =
      m.evaluate(turning_point(m, 200.0, 0.35, 1.5), no_corrections(), measured(55.83, 6.40, 1750, 0.80, 75.68));
  EXPECT_NEAR(initial.loss, 16.01, 0.02);
  EXPECT_FALSE(initial.feasible);
  EXPECT_EQ(failing(initial), (std::vector<std::string>{"max_diametral_error_um", "max_roughness_um"}));
  const Performance optimum =
      m.evaluate(turning_point(m, 287.0, 0.089, 1.5), no_corrections(), measured(22.12, 2.37, 641, 0.98, 63.90));
  EXPECT_NEAR(optimum.loss, 7.13, 0.01);
  EXPECT_TRUE(optimum.feasible) << (failing(optimum).empty() ? "" : failing(optimum).front());
  // This engine's own models agree on the verdict at the initial point.
  const Performance model_initial = m.evaluate(turning_point(m, 200.0, 0.35, 1.5));
  EXPECT_EQ(failing(model_initial), (std::vector<std::string>{"max_diametral_error_um", "max_roughness_um"}));
}

// ============================================================ the models

TEST(Models, RoughnessFitAndGeometric) {
  RoughnessModel fit;
  fit.kind = RoughnessModel::Kind::kFit;
  fit.c0 = 3.133, fit.cv = -0.0082, fit.cf = 12.54, fit.cd = 0.195;
  EXPECT_NEAR(fit.roughness_um(200.0, 0.35e-3, 1.5e-3), 3.133 - 1.64 + 4.389 + 0.2925, 1e-12);
  RoughnessModel geo;
  geo.nose_radius_m = 0.8e-3;
  EXPECT_NEAR(geo.roughness_um(200.0, 0.2e-3, 1e-3), 0.2 * 0.2 / (32 * 0.8) * 1e3, 1e-9);  // 1.5625 µm
}

TEST(Models, TaylorToolLifeCostAndProductionRate) {
  Economics e;
  e.taylor_c_m_per_min = 500, e.taylor_n = 0.25, e.cut_length_mm = 85, e.setup_time_min = 0.25;
  e.index_time_min = 0.1, e.approach_time_min = 0.35, e.tool_change_time_min = 1.0, e.machine_rate_per_h = 87;
  e.tool_cost = 12, e.tool_uses = 4;
  const double rpm = spindle_rpm_of(0.025, 200.0);
  const OperationEconomics o = operation_economics(e, 200.0, 0.35e-3, rpm);
  EXPECT_NEAR(o.tool_life_min, std::pow(2.5, 4.0), 1e-12);  // V T^n = C
  const double tc = 85.0 / (0.35 * rpm);
  EXPECT_NEAR(o.cutting_time_min, tc, 1e-12);
  const double top = 0.1 + 0.35 + tc + tc / o.tool_life_min * 1.0;
  EXPECT_NEAR(o.operation_time_min, top, 1e-12);
  EXPECT_NEAR(o.cost, 87.0 / 60.0 * top + tc / o.tool_life_min * 3.0, 1e-12);
  EXPECT_NEAR(o.production_rate_per_h, 60.0 / (0.25 + top), 1e-12);
  EXPECT_NEAR(o.cost, 0.80, 0.005);  // the config's rates make the seed's initial cost
}

TEST(Models, DiametralErrorIsTwiceTheStaticDeflectionAtTheFreeEnd) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  const Performance p = m.evaluate(turning_point(m, 200.0, 0.35, 1.5));
  // F_r = K_f b f; the shaft's tip stiffness 3EI/L³; 2δ at the free end.
  const double pi = 3.14159265358979323846;
  const double k_tip = 3.0 * 205e9 * pi * std::pow(0.025, 4) / 64.0 / std::pow(0.080, 3);
  const double fr = 954e6 * 1.5e-3 * 0.35e-3;
  EXPECT_NEAR(p.value[kDd], 2.0 * fr / k_tip * 1e6, 0.01 * p.value[kDd]);
  EXPECT_NEAR(p.worst_error_position_m, 0.080, 1e-12);
  // A tool position nearer the chuck: a smaller error.
  ModelOptions at;
  at.position_m = 0.040;
  const OptimizationModel mid(c.model, c.position, c.process, *c.optimization, at);
  EXPECT_LT(mid.evaluate(turning_point(mid, 200.0, 0.35, 1.5)).value[kDd], 0.5 * p.value[kDd]);
}

TEST(Models, MeasuredIndexReplacesThePrediction) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  IndexValues v = unknown_indices();
  v[kRa] = 1.0;
  const Performance p = m.evaluate(turning_point(m, 200.0, 0.35, 1.5), no_corrections(), v);
  EXPECT_TRUE(p.measured[kRa]);
  EXPECT_FALSE(p.measured[kDd]);
  EXPECT_EQ(p.value[kRa], 1.0);
  EXPECT_NEAR(p.model[kRa], 6.1745, 1e-9);
  EXPECT_NEAR(p.loss_terms[kRa], m.alpha()[kRa], 1e-12);
}

// ============================================================== optimize

// The optimum against a brute-force grid of the same models (depth fixed at
// the seed's 1.5 mm): no grid point that meets every constraint has a lower
// loss, and the grid's best is within 0.5 % of it.
TEST(Optimize, BeatsABruteForceGrid) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  const Optimum o = optimize(m);
  ASSERT_TRUE(o.found);
  EXPECT_TRUE(o.best.feasible);
  const OptimizationSpec& s = m.spec();
  constexpr int kSpeeds = 241, kFeeds = 361;
  double grid_best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kSpeeds; ++i)
    for (int j = 0; j < kFeeds; ++j) {
      const SetPoint p{s.speed_rpm.lo + (s.speed_rpm.hi - s.speed_rpm.lo) * i / (kSpeeds - 1),
                       s.feed_m.lo + (s.feed_m.hi - s.feed_m.lo) * j / (kFeeds - 1), s.depth_m.lo};
      const Performance r = m.evaluate(p);
      if (r.feasible && r.loss < grid_best) grid_best = r.loss;
    }
  EXPECT_LE(o.best.loss, grid_best * (1.0 + 1e-9));
  EXPECT_GE(o.best.loss, grid_best * (1.0 - 5e-3));
}

// With the depth free and the removal rate maximised, the shaft's lobes bind:
// the optimum sits at depth limit / margin; without the stability constraint
// (as the source study) the optimum cuts deeper than the limit allows.
TEST(Optimize, StabilityBindsOnTheShaftWhenTheDepthIsFree) {
  const Config c = load_config(kSeed);
  auto free_depth = [](OptimizationSpec& s) {
    s.objective = Objective::kRemovalRate;
    s.depth_m = {0.5e-3, 5e-3};
  };
  const OptimizationModel m = seed_model(c, free_depth);
  const Optimum o = optimize(m);
  ASSERT_TRUE(o.found);
  EXPECT_NEAR(o.best.stability_margin, 1.25, 1.25 * kBindingTolerance);
  EXPECT_NE(std::find(o.binding.begin(), o.binding.end(), "stability_margin"), o.binding.end());
  const OptimizationModel blind = seed_model(c, [&](OptimizationSpec& s) {
    free_depth(s);
    s.constraints.stability = false;
  });
  const Optimum ob = optimize(blind);
  ASSERT_TRUE(ob.found);
  EXPECT_GT(ob.best.value[kMrr], o.best.value[kMrr] * 1.05);
  const Performance judged = m.evaluate(ob.best.point);
  EXPECT_FALSE(judged.feasible);
  EXPECT_EQ(failing(judged), std::vector<std::string>{"stability_margin"});
}

TEST(Optimize, NoFeasiblePointIsReportedNotFound) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c, [](OptimizationSpec& s) { s.constraints.max_force_n = 1.0; });
  const Optimum o = optimize(m);
  EXPECT_FALSE(o.found);
  EXPECT_FALSE(o.best.feasible);
  EXPECT_TRUE(o.binding.empty());
}

// ================================================================= adapt

double final_loss(const AdaptRun& run) { return run.rows.back().measured.loss; }

// From three starts (the seed's initial point, a slow light cut, a fast heavy
// one) the loop ends within 5 % of the optimum's loss within 30 iterations,
// on feasible set-points once it has left an infeasible start.
TEST(Adapt, ConvergesFromThreeStartsWithin30Iterations) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  const Optimum best = optimize(m);
  ASSERT_TRUE(best.found);
  for (const auto& [v, f] : {std::pair{200.0, 0.35}, {60.0, 0.08}, {330.0, 0.45}}) {
    AdaptPlan plan;
    plan.iterations = 30;
    plan.start = turning_point(m, v, f, 1.5);
    const AdaptRun run = adapt(m, plan, m.spec().adapt);
    ASSERT_EQ(run.rows.size(), 30u);
    EXPECT_LE(std::abs(final_loss(run) - best.best.loss), 0.05 * best.best.loss) << v << " m/min, " << f << " mm";
    EXPECT_TRUE(run.final_state.converged) << v;
    int first_converged = 0;
    for (const AdaptRow& r : run.rows)
      if (!first_converged && r.step < kAdaptConvergedStep) first_converged = r.iteration;
    EXPECT_GT(first_converged, 0);
    EXPECT_LE(first_converged, 30);
    for (std::size_t k = 1; k < run.rows.size(); ++k) EXPECT_TRUE(run.rows[k].measured.feasible) << v << " " << k;
  }
}

// A 5 % bias of every index from iteration 15: the corrections take it in,
// the loop settles again by iteration 30 within 5 % of the corrected models'
// optimum, and the loss moves by under 3 %.
TEST(Adapt, ReconvergesAfterA5PercentBiasMidRun) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  AdaptPlan plan;
  plan.iterations = 30;
  plan.start = turning_point(m, 200.0, 0.35, 1.5);
  plan.biases.push_back(parse_plant_bias("all=5@15", Operation::kTurning));
  const AdaptRun run = adapt(m, plan, m.spec().adapt);
  ASSERT_EQ(run.rows.size(), 30u);
  const double before = run.rows[13].measured.loss;  // iteration 14, settled and unbiased
  for (std::size_t i = 0; i < kIndexCount; ++i) EXPECT_NEAR(run.final_state.correction[i], 1.05, 1e-9) << i;
  const Optimum corrected = optimize(m, run.final_state.correction);
  ASSERT_TRUE(corrected.found);
  EXPECT_LE(std::abs(final_loss(run) - corrected.best.loss), 0.05 * corrected.best.loss);
  EXPECT_TRUE(run.final_state.converged);
  const double change = (final_loss(run) - before) / before;
  EXPECT_GT(change, 0.0);
  EXPECT_LT(change, 0.03);  // 1.7 % here; the source study reports about 1.3 %
}

TEST(Adapt, StepNeverMovesToAFailingPointAndKeepsUnmeasuredCorrections) {
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  AdaptState s;
  s.point = turning_point(m, 300.0, 0.2, 1.5);
  s.correction[kRa] = 1.2;
  IndexValues meas = unknown_indices();
  meas[kDd] = 30.0;
  const AdaptStepResult r = adapt_step(m, s, meas, m.spec().adapt);
  EXPECT_EQ(r.next.iteration, 1);
  EXPECT_EQ(r.next.correction[kRa], 1.2);
  EXPECT_NEAR(r.next.correction[kDd], 30.0 / m.evaluate(s.point).model[kDd], 1e-12);
  EXPECT_TRUE(m.evaluate(r.next.point, r.next.correction, unknown_indices()).feasible);
  EXPECT_LE(r.step, m.spec().adapt.max_step + 1e-12);
}

TEST(Adapt, BadBiasAndPlanNameTheRule) {
  for (const char* bad : {"all=5", "speed=5@3", "all=x@3", "all=5@0", "all=-100@2"})
    EXPECT_THROW(parse_plant_bias(bad, Operation::kTurning), InputError) << bad;
  const PlantBias b = parse_plant_bias("surface_roughness_um=-3@7", Operation::kTurning);
  EXPECT_EQ(*b.index, PerformanceIndex::kRoughness);
  EXPECT_DOUBLE_EQ(b.fraction, -0.03);
  EXPECT_EQ(b.from_iteration, 7);
  const Config c = load_config(kSeed);
  const OptimizationModel m = seed_model(c);
  AdaptPlan plan;
  plan.iterations = 0;
  EXPECT_THROW(adapt(m, plan, m.spec().adapt), InputError);
  plan.iterations = 3;
  plan.start = turning_point(m, 400.0, 0.2, 1.5);  // above the 350 m/min bound
  EXPECT_THROW(adapt(m, plan, m.spec().adapt), InputError);
}

}  // namespace
}  // namespace chatter
