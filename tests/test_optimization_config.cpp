// `[optimization]` of the config (src/config/config_optimization.cpp,
// docs/config.md "[optimization]"): read into SI with its defaults, and every
// bad value refused with a message naming the file, the key and the rule;
// then milling: the spindle speed, the feed per tooth and the stability limit
// from sdm through the same optimiser (a small scan: sdm costs ~0.1 s a speed).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/optimization.hpp"

namespace chatter {
namespace {

const std::string kTurning = R"(
[process]
operation = "turning"
feed_force_coefficient_n_per_m2 = 954e6
workpiece_diameter_mm = 25
[[workpiece.modes]]
frequency_hz = 2790
damping_ratio = 0.04
stiffness_n_per_m = 23e6
direction = "x"
)";

const std::string kLoss = R"(
[optimization.loss]
critical_loss = 12.36
weights_percent = { diametral_error_um = 50, removal_rate_mm3_per_s = 50 }
critical = { diametral_error_um = 40, removal_rate_mm3_per_s = 500 }
)";

std::string optimization(const std::string& head, const std::string& rest = kLoss) {
  return kTurning + "[optimization]\n" + head + rest;
}
const std::string kBounds = "cutting_speed_m_per_min = [50, 350]\nfeed_mm_per_rev = [0.05, 0.5]\ndepth_mm = 1.5\n";

std::string error_of(const std::string& text) {
  try {
    parse_config(text, "o.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(OptimizationConfig, ReadsBoundsInSiAndDefaults) {
  const Config c = parse_config(optimization(kBounds), "o.toml");
  ASSERT_TRUE(c.optimization);
  const OptimizationSpec& s = *c.optimization;
  EXPECT_EQ(s.objective, Objective::kLoss);
  EXPECT_NEAR(s.speed_rpm.lo, 50.0 / (3.14159265358979323846 * 0.025), 1e-9);
  EXPECT_TRUE(s.speed_as_cutting_speed);
  EXPECT_DOUBLE_EQ(s.feed_m.hi, 0.5e-3);
  EXPECT_TRUE(s.depth_m.fixed());
  EXPECT_DOUBLE_EQ(s.loss.weight[0], 0.5);
  EXPECT_TRUE(s.constraints.stability);
  EXPECT_EQ(s.constraints.stability_margin, 1.0);
  EXPECT_EQ(s.adapt.gamma, 0.95);
  EXPECT_EQ(s.adapt.max_step, 0.1);
  EXPECT_FALSE(s.roughness);
  EXPECT_FALSE(s.economics);
  EXPECT_FALSE(parse_config(kTurning, "o.toml").optimization);
  // The indices left out of weights_percent weigh 0, and the config says so
  // (issue 44: silently).
  const std::vector<std::string>& w = c.warnings;
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("o.toml: optimization.loss.weights_percent: surface_roughness_um, cost, production_rate_per_h "
                      "not given: each weighs 0 %"),
            std::string::npos)
      << w[0];
}

TEST(OptimizationConfig, CriticalLossFromItsParts) {
  const Config c = parse_config(optimization(kBounds, R"(
[optimization.loss]
part_value = 7.5
previous_operations_cost = 3.94
operation_cost = 0.92
weights_percent = { removal_rate_mm3_per_s = 100 }
critical = { removal_rate_mm3_per_s = 500 }
)"),
                                "o.toml");
  EXPECT_NEAR(c.optimization->loss.critical_loss, 12.36, 1e-12);
}

TEST(OptimizationConfig, BadValuesNameFileKeyAndRule) {
  struct Case {
    std::string text;
    std::vector<std::string> said;
  };
  const std::vector<Case> cases = {
      {optimization("feed_mm_per_rev = [0.05, 0.5]\ndepth_mm = 1.5\n"),
       {"o.toml", "optimization.cutting_speed_m_per_min", "missing"}},
      {optimization(kBounds + "spindle_rpm = [1000, 2000]\n"), {"cutting_speed_m_per_min or spindle_rpm, not both"}},
      {optimization("cutting_speed_m_per_min = [50, 350]\nfeed_mm_per_rev = [0.5, 0.05]\ndepth_mm = 1.5\n"),
       {"optimization.feed_mm_per_rev", "lower <= upper"}},
      {optimization("cutting_speed_m_per_min = [50, 350]\nfeed_mm_per_rev = [0.05, 0.5]\ndepth_mm = 1.5\n"
                    "objective = \"speed\"\n"),
       {"optimization.objective", "\"loss\""}},
      {optimization(kBounds, ""), {"optimization.loss", "missing"}},
      {optimization(kBounds, R"(
[optimization.loss]
critical_loss = 10
weights_percent = { diametral_error_um = 50, surface_roughness_um = 50 }
critical = { diametral_error_um = 40, surface_roughness_um = 3 }
)"),
       {"optimization.roughness", "missing"}},
      {optimization(kBounds, R"(
[optimization.loss]
critical_loss = 10
weights_percent = { cost = 100 }
critical = { cost = 1 }
)"),
       {"optimization.economics", "missing"}},
      {optimization(kBounds, R"(
[optimization.loss]
critical_loss = 10
weights_percent = { diametral_error_um = 100 }
)"),
       {"optimization.loss.critical.diametral_error_um", "missing"}},
      {optimization(kBounds + "[optimization.constraints]\nmax_force_n = 100\n"),
       {"optimization.cutting_coefficient_n_per_mm2", "missing"}},
      {optimization(kBounds + "[optimization.constraints]\nstability = false\nstability_margin = 1.2\n"),
       {"optimization.constraints.stability_margin", "stability = false"}},
      {optimization(kBounds + "[optimization.constraints]\nstability_margin = 0.8\n"),
       {"optimization.constraints.stability_margin", ">= 1"}},
      {optimization(kBounds + "[optimization.constraints]\nmax_speed = 3\n"),
       {"optimization.constraints.max_speed", "unknown key"}},
      {optimization(kBounds + "[optimization.adapt]\nmax_step_percent = 0\n"),
       {"optimization.adapt.max_step_percent", "(0, 100]"}},
      {optimization(kBounds + "[optimization.roughness]\nmodel = \"geometric\"\n"),
       {"optimization.roughness.nose_radius_mm", "missing"}},
      {optimization(kBounds + "[optimization.economics]\ntaylor_c_m_per_min = 500\ntaylor_n = 0.25\n"),
       {"optimization.economics.cut_length_mm", "missing"}},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_FALSE(e.empty()) << c.text;
    for (const std::string& s : c.said) EXPECT_NE(e.find(s), std::string::npos) << s << " in: " << e;
  }
}

// Milling: the speed in rev/min, the feed per tooth, the surface location
// error and the stability limit from sdm. The benchmark's tool (case C,
// 922 Hz) at half immersion; the removal rate maximised over a small scan:
// the optimum is stable with the margin and binds on it or on a bound.
TEST(OptimizationMilling, RemovalRateUnderTheSdmLimit) {
  const Config c = parse_config(R"(
[process]
operation = "milling"
teeth = 2
tangential_coefficient_n_per_m2 = 6e8
radial_coefficient_n_per_m2 = 2e8
radial_immersion = 0.5
tool_diameter_mm = 12
milling_direction = "down"
[[tool.modes]]
frequency_hz = 922
damping_ratio = 0.011
mass_kg = 0.03993
direction = "x"
[optimization]
objective = "removal_rate"
spindle_rpm = [5000, 9000]
feed_per_tooth_mm = 0.05
depth_mm = [0.05, 3]
[optimization.constraints]
stability_margin = 1.2
)",
                                "m.toml");
  ASSERT_TRUE(c.optimization);
  const OptimizationModel m(c.model, c.position, c.process, *c.optimization);
  EXPECT_EQ(m.method(), "sdm");
  OptimizeOptions o;
  o.speed_points = 9;
  o.depth_points = 5;
  o.candidates = 1;
  const Optimum best = optimize(m, no_corrections(), o);
  ASSERT_TRUE(best.found);
  EXPECT_TRUE(best.best.feasible);
  EXPECT_GE(best.best.stability_margin, 1.2 * (1.0 - 1e-9));
  EXPECT_NEAR(best.best.stability_margin, 1.2, 1.2 * kBindingTolerance);
  // Removal a_p a_e f_z N_t N / 60.
  const SetPoint& p = best.best.point;
  EXPECT_NEAR(best.best.value[2], p.depth_m * 1e3 * 6.0 * 0.05 * 2 * p.spindle_rpm / 60.0, 1e-9);
  EXPECT_TRUE(std::isfinite(best.best.value[0]));  // the SLE of a stable cut exists
}

}  // namespace
}  // namespace chatter
