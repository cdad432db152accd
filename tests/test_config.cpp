// Tests for the TOML config reader (src/config/config.cpp, docs/config.md):
// every shipped config loads with the values of docs/physics.md §7, and every
// bad-input rule throws chatter::InputError whose message names the origin,
// the exact key path and the rule.
#include "chatter/io/config.hpp"
#include "chatter/io/grinding_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chatter/error.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;

const fs::path kConfigDir = fs::path(CHATTER_SOURCE_DIR) / "configs";
const std::string kOrigin = "mem/case.toml";  // origin used for parse_config

// Input values are copied, not computed: exact up to the last bit.
constexpr double kExact = 1e-12;
// Table IV.1 prints the derived cantilever values to 5 significant digits.
constexpr double kStiffnessRelTol = 1e-4;  // 0.01 %
constexpr double kFrequencyRelTol = 5e-4;  // 0.05 %

::testing::AssertionResult RelNear(double actual, double expected, double rel_tol) {
  const double err = std::abs(actual - expected) / std::abs(expected);
  if (err <= rel_tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "actual " << actual << ", expected " << expected << ", relative error "
                                       << err << " > " << rel_tol;
}

/// Parses `text`; succeeds when an InputError is thrown whose message
/// contains every one of `parts`.
::testing::AssertionResult ThrowsInputError(const std::string& text, std::initializer_list<std::string> parts) {
  try {
    (void)parse_config(text, kOrigin);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts) {
      if (msg.find(p) == std::string::npos)
        return ::testing::AssertionFailure() << "message \"" << msg << "\" lacks \"" << p << "\"";
    }
    return ::testing::AssertionSuccess() << msg;
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "threw a non-InputError: " << e.what();
  }
  return ::testing::AssertionFailure() << "no exception";
}

/// The InputError message for `text` ("" if none is thrown).
std::string MessageOf(const std::string& text) {
  try {
    (void)parse_config(text, kOrigin);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A valid turning process and mode to build cases from.
const std::string kTurning = R"(
[process]
operation = "turning"
feed_force_coefficient_n_per_m2 = 2.4e9
)";
const std::string kMillingHead = R"(
[process]
operation = "milling"
)";
const std::string kMillingKeys = R"(teeth = 2
tangential_coefficient_n_per_m2 = 6e8
radial_coefficient_n_per_m2 = 2e8
radial_immersion = 0.05
)";
const std::string kGoodMode = R"(frequency_hz = 100.0
damping_ratio = 0.03
stiffness_n_per_m = 1e7
)";
const std::string kOneToolMode = "[[tool.modes]]\n" + kGoodMode;

std::string Turning(const std::string& rest) { return kTurning + rest; }
std::string TurningWithToolMode(const std::string& rest) { return kTurning + kOneToolMode + rest; }
std::string Milling(const std::string& process_keys) { return kMillingHead + process_keys + kOneToolMode; }

// ============================================================ shipped configs

TEST(ShippedConfig, SeedTurning1Dof) {
  const fs::path file = kConfigDir / "seed_turning_1dof.toml";
  const Config c = load_config(file);
  EXPECT_EQ(c.name, "Seed 1-DOF turning, flexible workpiece (case A)");
  EXPECT_EQ(c.source, file);
  ASSERT_EQ(c.process.operation(), Operation::kTurning);
  EXPECT_NEAR(c.process.turning_parameters().feed_force_coefficient_n_per_m2, 2.4e9, 2.4e9 * kExact);
  EXPECT_TRUE(c.model.tool.rigid());
  ASSERT_EQ(c.model.workpiece.modes.size(), 1u);
  const Mode& m = c.model.workpiece.modes[0];
  EXPECT_NEAR(m.natural_frequency_hz, 94.22, 94.22 * kExact);
  EXPECT_NEAR(m.damping_ratio, 0.033, kExact);
  EXPECT_NEAR(m.stiffness_n_per_m, 45e6, 45e6 * kExact);
  EXPECT_EQ(m.direction, Eigen::Vector2d(1.0, 0.0));
  EXPECT_EQ(c.sweep.rpm_min, 50.0);
  EXPECT_EQ(c.sweep.rpm_max, 2000.0);
  EXPECT_EQ(c.sweep.rpm_points, 400);
  EXPECT_EQ(c.sweep.depth_max_mm, 20.0);
}

TEST(ShippedConfig, CoupledTool1Workpiece1) {
  const Config c = load_config(kConfigDir / "coupled_tool1_workpiece1.toml");
  ASSERT_EQ(c.process.operation(), Operation::kTurning);
  EXPECT_NEAR(c.process.turning_parameters().feed_force_coefficient_n_per_m2, 684e6, 684e6 * kExact);
  ASSERT_EQ(c.model.tool.modes.size(), 1u);
  const Mode& t = c.model.tool.modes[0];
  EXPECT_NEAR(t.stiffness_n_per_m, 20e6, 20e6 * kExact);
  EXPECT_NEAR(t.natural_frequency_hz, 100.66, 100.66 * kExact);
  EXPECT_NEAR(t.damping_ratio, 0.032, kExact);
  EXPECT_EQ(t.direction, Eigen::Vector2d(1.0, 0.0));
  ASSERT_EQ(c.model.workpiece.modes.size(), 1u);
  const Mode& w = c.model.workpiece.modes[0];
  EXPECT_TRUE(RelNear(w.stiffness_n_per_m, 43.972e6, kStiffnessRelTol));
  EXPECT_TRUE(RelNear(w.natural_frequency_hz, 326.71, kFrequencyRelTol));
  EXPECT_NEAR(w.damping_ratio, 0.025, kExact);
  EXPECT_EQ(w.direction, Eigen::Vector2d(1.0, 0.0));
  ASSERT_TRUE(c.sweep.rpm_min && c.sweep.rpm_max && c.sweep.rpm_points && c.sweep.depth_max_mm);
  EXPECT_LT(*c.sweep.rpm_min, 60.0 * t.natural_frequency_hz);  // the tool's lobe k = 0 edge is in range
  EXPECT_GT(*c.sweep.rpm_max, 60.0 * t.natural_frequency_hz);
}

TEST(ShippedConfig, CoupledTool2Workpiece2) {
  const Config c = load_config(kConfigDir / "coupled_tool2_workpiece2.toml");
  ASSERT_EQ(c.model.tool.modes.size(), 1u);
  const Mode& t = c.model.tool.modes[0];
  EXPECT_NEAR(t.stiffness_n_per_m, 7.465e6, 7.465e6 * kExact);
  EXPECT_NEAR(t.natural_frequency_hz, 185.0, 185.0 * kExact);
  EXPECT_NEAR(t.damping_ratio, 0.032, kExact);
  ASSERT_EQ(c.model.workpiece.modes.size(), 1u);
  const Mode& w = c.model.workpiece.modes[0];
  EXPECT_TRUE(RelNear(w.stiffness_n_per_m, 5.092e6, kStiffnessRelTol));
  EXPECT_TRUE(RelNear(w.natural_frequency_hz, 190.58, kFrequencyRelTol));
  EXPECT_NEAR(w.damping_ratio, 0.025, kExact);
  ASSERT_TRUE(c.sweep.rpm_min && c.sweep.rpm_max);
  EXPECT_LT(*c.sweep.rpm_min, 60.0 * t.natural_frequency_hz);
  EXPECT_GT(*c.sweep.rpm_max, 60.0 * t.natural_frequency_hz);
}

TEST(ShippedConfig, MillingBenchmark) {
  const Config c = load_config(kConfigDir / "milling_benchmark_ae005_down.toml");
  ASSERT_EQ(c.process.operation(), Operation::kMilling);
  const MillingParameters& p = c.process.milling_parameters();
  EXPECT_EQ(p.teeth, 2);
  EXPECT_NEAR(p.tangential_coefficient_n_per_m2, 6e8, 6e8 * kExact);
  EXPECT_NEAR(p.radial_coefficient_n_per_m2, 2e8, 2e8 * kExact);
  EXPECT_NEAR(p.radial_immersion, 0.05, kExact);
  EXPECT_EQ(p.direction, MillingDirection::kDown);
  EXPECT_TRUE(c.model.workpiece.rigid());
  ASSERT_EQ(c.model.tool.modes.size(), 1u);
  const Mode& m = c.model.tool.modes[0];
  EXPECT_NEAR(m.natural_frequency_hz, 922.0, 922.0 * kExact);
  EXPECT_NEAR(m.damping_ratio, 0.011, kExact);
  EXPECT_TRUE(RelNear(m.mass_kg(), 0.03993, 1e-12));
  EXPECT_EQ(c.sweep.rpm_min, 5000.0);
  EXPECT_EQ(c.sweep.rpm_max, 25000.0);
  EXPECT_EQ(c.sweep.rpm_points, 400);
  EXPECT_EQ(c.sweep.depth_max_mm, 10.0);
}

// Any config added to configs/ later is at least valid (configs/grinding_*.toml
// are grinding configs: load_grinding_config, tests/test_grinding_config.cpp).
TEST(ShippedConfig, EveryFileInConfigsLoads) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kConfigDir)) {
    if (entry.path().extension() != ".toml") continue;
    ++count;
    try {
      if (entry.path().filename().string().starts_with("grinding_")) {
        const GrindingConfig g = load_grinding_config(entry.path());
        EXPECT_TRUE(g.warnings.empty()) << entry.path() << ": " << (g.warnings.empty() ? "" : g.warnings.front());
        continue;
      }
      const Config c = load_config(entry.path());
      // A shipped config is the example users copy: it raises no warning.
      EXPECT_TRUE(c.warnings.empty()) << entry.path() << ": " << (c.warnings.empty() ? "" : c.warnings.front());
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_GE(count, 4);
}

// ============================================================ valid features

TEST(ConfigValid, IntegersAcceptedWhereFloatsExpected) {
  const Config c = parse_config(Turning(R"(
[[tool.modes]]
frequency_hz = 100
damping_ratio = 0.03
stiffness_n_per_m = 10000000
[sweep]
rpm_min = 50
rpm_max = 2000
depth_max_mm = 5
)"),
                                kOrigin);
  EXPECT_EQ(c.model.tool.modes[0].natural_frequency_hz, 100.0);
  EXPECT_EQ(c.model.tool.modes[0].stiffness_n_per_m, 1e7);
  EXPECT_EQ(c.sweep.rpm_min, 50.0);
  EXPECT_EQ(c.sweep.depth_max_mm, 5.0);
  EXPECT_FALSE(c.sweep.rpm_points.has_value());
}

TEST(ConfigValid, DefaultsNameFromOriginStemAndLeavesSourceEmpty) {
  const Config c = parse_config(TurningWithToolMode(""), kOrigin);
  EXPECT_EQ(c.name, "case");
  EXPECT_TRUE(c.source.empty());
  EXPECT_TRUE(c.model.workpiece.rigid());
  EXPECT_FALSE(c.sweep.rpm_min || c.sweep.rpm_max || c.sweep.rpm_points || c.sweep.depth_max_mm);
}

TEST(ConfigValid, FeedForTheTimeDomainSimulation) {
  // Turning: per revolution; milling: per tooth; absent: no value.
  const std::string turning_head = R"(
[process]
operation = "turning"
feed_force_coefficient_n_per_m2 = 2.4e9
feed_per_rev_mm = 0.25
)";
  EXPECT_EQ(parse_config(turning_head + R"(
[[tool.modes]]
frequency_hz = 100
damping_ratio = 0.03
stiffness_n_per_m = 1e7
)",
                         kOrigin)
                .feed_mm,
            0.25);
  EXPECT_EQ(parse_config(Milling(kMillingKeys + "feed_per_tooth_mm = 0.05\n"), kOrigin).feed_mm, 0.05);
  EXPECT_FALSE(parse_config(Milling(kMillingKeys), kOrigin).feed_mm.has_value());
  EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "feed_per_tooth_mm = 0\n"),
                               {kOrigin, "process.feed_per_tooth_mm", "in (0, 10] (mm)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "feed_per_tooth_mm = 12\n"),
                               {"process.feed_per_tooth_mm", "in (0, 10] (mm)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "feed_per_rev_mm = 0.1\n"),
                               {"process.feed_per_rev_mm", "only for operation = \"turning\""}));
  EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "feed_per_tooth_mm = \"fast\"\n"),
                               {"process.feed_per_tooth_mm", "must be a number"}));
}

TEST(ConfigValid, FluteLengthIsMillingOnlyPositiveAndInMetres) {
  EXPECT_EQ(parse_config(Milling(kMillingKeys + "flute_length_mm = 16\n"), kOrigin).flute_length_m, 16e-3);
  EXPECT_FALSE(parse_config(Milling(kMillingKeys), kOrigin).flute_length_m.has_value());
  for (const char* bad : {"0", "-16"})
    EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "flute_length_mm = " + bad + "\n"),
                                 {kOrigin, "process.flute_length_mm", "> 0"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "flute_length_mm = \"long\"\n"),
                               {"process.flute_length_mm", "must be a number"}));
}

TEST(ConfigValid, ExplicitName) {
  EXPECT_EQ(parse_config("name = \"lathe 3\"\n" + TurningWithToolMode(""), kOrigin).name, "lathe 3");
}

TEST(ConfigValid, DirectionDefaultsToXAndAcceptsYAndVectors) {
  const Config c = parse_config(Turning(R"(
[[tool.modes]]
frequency_hz = 100.0
damping_ratio = 0.03
stiffness_n_per_m = 1e7
[[tool.modes]]
frequency_hz = 200.0
damping_ratio = 0.03
stiffness_n_per_m = 1e7
direction = "y"
[[workpiece.modes]]
frequency_hz = 300.0
damping_ratio = 0.03
mass_kg = 2
direction = [3, -4.0]
)"),
                                kOrigin);
  ASSERT_EQ(c.model.tool.modes.size(), 2u);
  EXPECT_EQ(c.model.tool.modes[0].direction, Eigen::Vector2d(1.0, 0.0));
  EXPECT_EQ(c.model.tool.modes[1].direction, Eigen::Vector2d(0.0, 1.0));
  ASSERT_EQ(c.model.workpiece.modes.size(), 1u);
  EXPECT_NEAR(c.model.workpiece.modes[0].direction.x(), 0.6, kExact);
  EXPECT_NEAR(c.model.workpiece.modes[0].direction.y(), -0.8, kExact);
  EXPECT_TRUE(RelNear(c.model.workpiece.modes[0].mass_kg(), 2.0, kExact));
}

TEST(ConfigValid, CantileverAsSubTable) {
  const Config c = parse_config(Turning(R"(
[[workpiece.modes]]
damping_ratio = 0.025
[workpiece.modes.cantilever]
youngs_modulus_pa = 180e9
density_kg_per_m3 = 7600
length_m = 0.5
diameter_m = 0.12
)"),
                                kOrigin);
  ASSERT_EQ(c.model.workpiece.modes.size(), 1u);
  EXPECT_TRUE(RelNear(c.model.workpiece.modes[0].stiffness_n_per_m, 43.972e6, kStiffnessRelTol));
}

TEST(ConfigValid, MillingDirectionDefaultsToDownAndAcceptsUp) {
  EXPECT_EQ(parse_config(Milling(kMillingKeys), kOrigin).process.milling_parameters().direction,
            MillingDirection::kDown);
  EXPECT_EQ(parse_config(Milling(kMillingKeys + "milling_direction = \"up\"\n"), kOrigin)
                .process.milling_parameters()
                .direction,
            MillingDirection::kUp);
}

TEST(ConfigValid, FullImmersionAndZeroRadialCoefficientAccepted) {
  const Config c = parse_config(Milling(R"(teeth = 4
tangential_coefficient_n_per_m2 = 6e8
radial_coefficient_n_per_m2 = 0
radial_immersion = 1
)"),
                                kOrigin);
  EXPECT_EQ(c.process.milling_parameters().radial_immersion, 1.0);
  EXPECT_EQ(c.process.milling_parameters().radial_coefficient_n_per_m2, 0.0);
}

TEST(ConfigValid, EmptyModesArrayIsRigid) {
  const Config c = parse_config(TurningWithToolMode("[workpiece]\nmodes = []\n"), kOrigin);
  EXPECT_TRUE(c.model.workpiece.rigid());
}

// ============================================================ message format

TEST(ConfigError, FormatIsOriginKeyPathValueRule) {
  const std::string msg = MessageOf(Turning(R"(
[[tool.modes]]
frequency_hz = 100.0
damping_ratio = 0.03
stiffness_n_per_m = 1e7
[[tool.modes]]
frequency_hz = 200.0
damping_ratio = -0.01
stiffness_n_per_m = 1e7
)"));
  EXPECT_EQ(msg, "mem/case.toml: tool.modes[1].damping_ratio = -0.01: must be in (0, 1)");
}

TEST(ConfigError, ValueIsQuotedAsWritten) {
  EXPECT_EQ(MessageOf(Turning("[[tool.modes]]\nfrequency_hz = 1e2\ndamping_ratio = 0.03\nstiffness_n_per_m = -45e6  "
                              "# comment\n")),
            "mem/case.toml: tool.modes[0].stiffness_n_per_m = -45e6: must be > 0");
}

// ============================================================ unknown keys

TEST(ConfigError, UnknownTopLevelKey) {
  EXPECT_EQ(MessageOf("nmae = \"x\"\n" + TurningWithToolMode("")),
            "mem/case.toml: nmae: unknown key (did you mean name?)");
}

TEST(ConfigError, UnknownTopLevelTable) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[machine]\nx = 1\n"),
                               {"mem/case.toml: machine: unknown key", "process", "sweep"}));
}

TEST(ConfigError, UnknownProcessKey) {
  EXPECT_EQ(MessageOf(R"(
[process]
operation = "turning"
feed_forse_coefficient_n_per_m2 = 2.4e9
)" + kOneToolMode),
            "mem/case.toml: process.feed_forse_coefficient_n_per_m2: unknown key "
            "(did you mean feed_force_coefficient_n_per_m2?)");
}

TEST(ConfigError, UnknownModeKeySuggestsUnitSuffix) {
  EXPECT_TRUE(ThrowsInputError(
      TurningWithToolMode("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0.03\nstiffness = 1e7\n"),
      {"mem/case.toml: tool.modes[1].stiffness: unknown key", "did you mean stiffness_n_per_m?"}));
}

TEST(ConfigError, UnknownBodyKey) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[workpiece]\nmode = []\n"),
                               {"mem/case.toml: workpiece.mode: unknown key", "did you mean modes?"}));
}

TEST(ConfigError, UnknownCantileverKey) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[workpiece.modes]]\ndamping_ratio = 0.02\ncantilever = { youngs_modulus_pa = 1e11, "
              "density_kg_per_m3 = 7600, length_m = 0.5, diameter_m = 0.1, poisson = 0.3 }\n"),
      {"mem/case.toml: workpiece.modes[0].cantilever.poisson: unknown key"}));
}

TEST(ConfigError, UnknownSweepKey) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\ndepth_max = 5\n"),
                               {"mem/case.toml: sweep.depth_max: unknown key", "did you mean depth_max_mm?"}));
}

// ============================================================ missing keys

TEST(ConfigError, MissingModeFrequency) {
  EXPECT_EQ(MessageOf(Turning("[[workpiece.modes]]\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n")),
            "mem/case.toml: workpiece.modes[0].frequency_hz: missing (required, Hz, > 0)");
}

TEST(ConfigError, MissingDampingRatio) {
  EXPECT_TRUE(ThrowsInputError(Turning("[[tool.modes]]\nfrequency_hz = 100.0\nstiffness_n_per_m = 1e7\n"),
                               {"mem/case.toml: tool.modes[0].damping_ratio: missing (required", "in (0, 1)"}));
}

TEST(ConfigError, MissingProcessTable) {
  EXPECT_TRUE(ThrowsInputError(kOneToolMode, {"mem/case.toml: process: missing"}));
}

TEST(ConfigError, MissingOperation) {
  EXPECT_TRUE(ThrowsInputError("[process]\nfeed_force_coefficient_n_per_m2 = 1e9\n" + kOneToolMode,
                               {"mem/case.toml: process.operation: missing (required", "turning", "milling"}));
}

TEST(ConfigError, MissingFeedForceCoefficient) {
  EXPECT_TRUE(ThrowsInputError("[process]\noperation = \"turning\"\n" + kOneToolMode,
                               {"mem/case.toml: process.feed_force_coefficient_n_per_m2: missing (required",
                                "N/m^2", "> 0"}));
}

TEST(ConfigError, MissingMillingTeeth) {
  EXPECT_TRUE(ThrowsInputError(Milling("tangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_n_per_m2 = 2e8\n"
                                       "radial_immersion = 0.5\n"),
                               {"mem/case.toml: process.teeth: missing (required", "integer >= 1"}));
}

TEST(ConfigError, MissingCantileverKey) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[workpiece.modes]]\ndamping_ratio = 0.02\ncantilever = { youngs_modulus_pa = 1e11, "
              "density_kg_per_m3 = 7600, length_m = 0.5 }\n"),
      {"mem/case.toml: workpiece.modes[0].cantilever.diameter_m: missing (required, m, > 0)"}));
}

// ============================================================ wrong types

TEST(ConfigError, WrongTypeTeethString) {
  // Every error of the process at once: the bad teeth and the three keys missing.
  EXPECT_EQ(MessageOf(Milling("teeth = \"two\"\n")),
            "mem/case.toml: process.teeth = \"two\": must be an integer\n"
            "mem/case.toml: process.tangential_coefficient_n_per_m2: missing (required, N/m^2, > 0); or give "
            "tangential_coefficient_n_per_mm2 (N/mm^2)\n"
            "mem/case.toml: process.radial_coefficient_n_per_m2: missing (required, N/m^2, >= 0); or give "
            "radial_coefficient_n_per_mm2 (N/mm^2) or radial_coefficient_ratio (K_r/K_t)\n"
            "mem/case.toml: process.radial_immersion: missing (required, a_e/D, in (0, 1]); or give radial_depth_mm "
            "with tool_diameter_mm");
}

TEST(ConfigError, WrongTypeNumberAsString) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = \"100\"\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].frequency_hz = \"100\": must be a number"}));
}

TEST(ConfigError, WrongTypeProcessNotTable) {
  EXPECT_TRUE(ThrowsInputError("process = \"turning\"\n" + kOneToolMode,
                               {"mem/case.toml: process = \"turning\": must be a table"}));
}

TEST(ConfigError, WrongTypeModesNotArray) {
  EXPECT_TRUE(ThrowsInputError(Turning("[tool.modes]\nfrequency_hz = 100.0\n"),
                               {"mem/case.toml: tool.modes = ", "must be an array of tables ([[tool.modes]])"}));
}

TEST(ConfigError, WrongTypeName) {
  EXPECT_TRUE(ThrowsInputError("name = 3\n" + TurningWithToolMode(""), {"mem/case.toml: name = 3: must be a string"}));
}

TEST(ConfigError, EmptyName) {
  EXPECT_TRUE(ThrowsInputError("name = \"\"\n" + TurningWithToolMode(""),
                               {"mem/case.toml: name = \"\": must not be empty"}));
}

// ============================================================ mode values

TEST(ConfigError, NonPositiveFrequency) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 0\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].frequency_hz = 0: must be > 0"}));
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = -5.0\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].frequency_hz = -5.0: must be > 0"}));
}

TEST(ConfigError, ImplausibleValuesAreRefused) {
  // Beyond these bounds a value is not machining dynamics and the solvers
  // could not resolve it (found by fuzzing: a 1e300 Hz mode hung the search).
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 2e5\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].frequency_hz = 2e5: must be in [0.1, 1e5] Hz"}));
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 1e-9\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].damping_ratio = 1e-9: must be >= 1e-6"}));
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e20\n"),
      {"tool.modes[0].stiffness_n_per_m = 1e20: must be in [1, 1e15] N/m"}));
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nmass_kg = 1e9\n"),
      {"tool.modes[0].mass_kg = 1e9: must be in [1e-6, 1e6] kg"}));
  // Found by fuzzing: a 1e-23 kg mode overflowed the receptance.
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nmass_kg = 1e-23\n"),
      {"tool.modes[0].mass_kg = 1e-23: must be in [1e-6, 1e6] kg"}));
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 0.2\ndamping_ratio = 0.03\nmass_kg = 1e-3\n"),
      {"tool.modes[0].mass_kg = 1e-3: gives a modal stiffness", "must be >= 1 N/m"}));
}

TEST(ConfigError, NonPositiveStiffness) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0.03\nstiffness_n_per_m = 0.0\n"),
      {"mem/case.toml: tool.modes[0].stiffness_n_per_m = 0.0: must be > 0"}));
}

TEST(ConfigError, NonPositiveMass) {
  EXPECT_TRUE(ThrowsInputError(Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0.03\nmass_kg = -1\n"),
                               {"mem/case.toml: tool.modes[0].mass_kg = -1: must be > 0"}));
}

TEST(ConfigError, DampingZero) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].damping_ratio = 0: must be in (0, 1)"}));
}

TEST(ConfigError, DampingOne) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 1.0\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].damping_ratio = 1.0: must be in (0, 1)"}));
}

TEST(ConfigError, DampingAsPercentageSaysSo) {
  EXPECT_EQ(MessageOf(Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 3\nstiffness_n_per_m = 1e7\n")),
            "mem/case.toml: tool.modes[0].damping_ratio = 3: must be in (0, 1) (a ratio, not a percentage: 3 % is "
            "0.03)");
}

TEST(ConfigError, DampingNegative) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[workpiece.modes]]\nfrequency_hz = 100.0\ndamping_ratio = -0.02\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: workpiece.modes[0].damping_ratio = -0.02: must be in (0, 1)"}));
}

TEST(ConfigError, BothStiffnessAndMass) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\nmass_kg = 2.0\n"),
      {"mem/case.toml: tool.modes[0].mass_kg = 2.0: not with stiffness_n_per_m", "exactly one"}));
}

TEST(ConfigError, NeitherStiffnessNorMass) {
  EXPECT_TRUE(ThrowsInputError(Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0.03\n"),
                               {"mem/case.toml: tool.modes[0].stiffness_n_per_m: missing", "exactly one",
                                "mass_kg"}));
}

TEST(ConfigError, ZeroDirection) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("direction = [0, 0.0]\n"),
                               {"mem/case.toml: tool.modes[0].direction = [0, 0.0]: must not be the zero vector"}));
}

TEST(ConfigError, BadDirectionString) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("direction = \"z\"\n"),
                               {"mem/case.toml: tool.modes[0].direction = \"z\": must be \"x\", \"y\" or two "
                                "numbers [x, y]"}));
}

TEST(ConfigError, DirectionWrongLength) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("direction = [1, 0, 0]\n"),
                               {"mem/case.toml: tool.modes[0].direction = [1, 0, 0]: must be \"x\", \"y\" or two "
                                "numbers [x, y]"}));
}

TEST(ConfigError, DirectionComponentNotNumber) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("direction = [1, \"a\"]\n"),
                               {"mem/case.toml: tool.modes[0].direction[1] = \"a\": must be a number"}));
}

TEST(ConfigError, NotANumber) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = nan\ndamping_ratio = 0.03\nstiffness_n_per_m = 1e7\n"),
      {"mem/case.toml: tool.modes[0].frequency_hz = nan: must be a finite number"}));
}

TEST(ConfigError, Infinity) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0.03\nstiffness_n_per_m = +inf\n"),
      {"mem/case.toml: tool.modes[0].stiffness_n_per_m = +inf: must be a finite number"}));
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("direction = [inf, 0]\n"),
                               {"mem/case.toml: tool.modes[0].direction[0] = inf: must be a finite number"}));
}

TEST(ConfigError, BothBodiesRigid) {
  EXPECT_EQ(MessageOf(kTurning), "mem/case.toml: tool.modes, workpiece.modes: both bodies are rigid: give at least "
                                 "one mode (or a measured frf)");
  EXPECT_TRUE(ThrowsInputError(Turning("[tool]\nmodes = []\n[workpiece]\n"),
                               {"mem/case.toml: tool.modes, workpiece.modes: both bodies are rigid"}));
}

// ============================================================ cantilever

TEST(ConfigError, FrequencyWithCantilever) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[workpiece.modes]]\ndamping_ratio = 0.02\nfrequency_hz = 300.0\ncantilever = { youngs_modulus_pa = "
              "1e11, density_kg_per_m3 = 7600, length_m = 0.5, diameter_m = 0.1 }\n"),
      {"mem/case.toml: workpiece.modes[0].frequency_hz = 300.0: not with cantilever"}));
}

TEST(ConfigError, StiffnessWithCantilever) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[workpiece.modes]]\ndamping_ratio = 0.02\nstiffness_n_per_m = 1e7\ncantilever = { youngs_modulus_pa "
              "= 1e11, density_kg_per_m3 = 7600, length_m = 0.5, diameter_m = 0.1 }\n"),
      {"mem/case.toml: workpiece.modes[0].stiffness_n_per_m = 1e7: not with cantilever"}));
}

TEST(ConfigError, NonPositiveCantileverLength) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[workpiece.modes]]\ndamping_ratio = 0.02\ncantilever = { youngs_modulus_pa = 1e11, "
              "density_kg_per_m3 = 7600, length_m = -0.5, diameter_m = 0.1 }\n"),
      {"mem/case.toml: workpiece.modes[0].cantilever.length_m = -0.5: must be > 0"}));
}

TEST(ConfigError, CantileverNotTable) {
  EXPECT_TRUE(ThrowsInputError(Turning("[[workpiece.modes]]\ndamping_ratio = 0.02\ncantilever = 0.5\n"),
                               {"mem/case.toml: workpiece.modes[0].cantilever = 0.5: must be a table"}));
}

// ============================================================ process values

TEST(ConfigError, UnknownOperation) {
  EXPECT_TRUE(ThrowsInputError("[process]\noperation = \"drilling\"\n" + kOneToolMode,
                               {"mem/case.toml: process.operation = \"drilling\": must be \"turning\" or "
                                "\"milling\""}));
}

TEST(ConfigError, TurningKeyInMilling) {
  EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "feed_force_coefficient_n_per_m2 = 1e9\n"),
                               {"mem/case.toml: process.feed_force_coefficient_n_per_m2 = 1e9: only for "
                                "operation = \"turning\""}));
}

TEST(ConfigError, MillingKeyInTurning) {
  EXPECT_TRUE(ThrowsInputError("[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = 1e9\n"
                               "teeth = 2\n" +
                                   kOneToolMode,
                               {"mem/case.toml: process.teeth = 2: only for operation = \"milling\""}));
}

TEST(ConfigError, NonPositiveFeedForceCoefficient) {
  EXPECT_TRUE(ThrowsInputError(
      "[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = -2.4e9\n" + kOneToolMode,
      {"mem/case.toml: process.feed_force_coefficient_n_per_m2 = -2.4e9: must be > 0"}));
}

TEST(ConfigError, ImmersionZero) {
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\n"
                                       "radial_coefficient_n_per_m2 = 2e8\nradial_immersion = 0\n"),
                               {"mem/case.toml: process.radial_immersion = 0: must be in (0, 1]"}));
}

TEST(ConfigError, ImmersionAboveOne) {
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\n"
                                       "radial_coefficient_n_per_m2 = 2e8\nradial_immersion = 1.5\n"),
                               {"mem/case.toml: process.radial_immersion = 1.5: must be in (0, 1]"}));
}

TEST(ConfigError, TeethZero) {
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 0\n"), {"mem/case.toml: process.teeth = 0: must be an integer >= 1"}));
}

// Fuzzing (operations target) found 57 483 648 teeth allocating gigabytes of
// per-tooth tables; the same cap holds in the config.
TEST(ConfigError, TeethAboveTheCap) {
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 57483648\n"),
                               {"mem/case.toml: process.teeth = 57483648: must be an integer <= 1000"}));
}

TEST(ConfigError, TeethNotInteger) {
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 2.5\n"), {"mem/case.toml: process.teeth = 2.5: must be an integer"}));
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 2.0\n"), {"mem/case.toml: process.teeth = 2.0: must be an integer"}));
}

TEST(ConfigError, NegativeRadialCoefficient) {
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\n"
                                       "radial_coefficient_n_per_m2 = -1\nradial_immersion = 0.5\n"),
                               {"mem/case.toml: process.radial_coefficient_n_per_m2 = -1: must be >= 0"}));
}

TEST(ConfigError, BadMillingDirection) {
  EXPECT_TRUE(ThrowsInputError(Milling(kMillingKeys + "milling_direction = \"sideways\"\n"),
                               {"mem/case.toml: process.milling_direction = \"sideways\": must be \"down\" (= \"climb\") "
                                "or \"up\" (= \"conventional\")"}));
}

// ============================================================ sweep values

TEST(ConfigError, RpmMinNegative) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\nrpm_min = -50\n"),
                               {"mem/case.toml: sweep.rpm_min = -50: must be > 0"}));
}

TEST(ConfigError, RpmMaxNotAboveRpmMin) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\nrpm_min = 500\nrpm_max = 400\n"),
                               {"mem/case.toml: sweep.rpm_max = 400: must be > rpm_min (500)"}));
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\nrpm_min = 500\nrpm_max = 500.0\n"),
                               {"mem/case.toml: sweep.rpm_max = 500.0: must be > rpm_min (500)"}));
}

TEST(ConfigError, RpmPointsBelowTwo) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\nrpm_points = 1\n"),
                               {"mem/case.toml: sweep.rpm_points = 1: must be an integer >= 2"}));
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\nrpm_points = 400.0\n"),
                               {"mem/case.toml: sweep.rpm_points = 400.0: must be an integer"}));
}

TEST(ConfigError, DepthMaxNotPositive) {
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\ndepth_max_mm = 0\n"),
                               {"mem/case.toml: sweep.depth_max_mm = 0: must be > 0"}));
  EXPECT_TRUE(ThrowsInputError(TurningWithToolMode("[sweep]\ndepth_max_mm = -3.5\n"),
                               {"mem/case.toml: sweep.depth_max_mm = -3.5: must be > 0"}));
}

// ============================================================ TOML and files

TEST(ConfigError, TomlSyntaxErrorHasLineAndColumn) {
  const std::string msg = MessageOf("[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = = 2\n");
  EXPECT_EQ(msg.rfind("mem/case.toml:3:", 0), 0u) << msg;
}

TEST(ConfigError, TomlDuplicateKeyIsSyntaxError) {
  const std::string msg = MessageOf(TurningWithToolMode("frequency_hz = 120.0\n"));
  EXPECT_EQ(msg.rfind("mem/case.toml:", 0), 0u) << msg;
  EXPECT_NE(msg.find("frequency_hz"), std::string::npos) << msg;
}

TEST(ConfigError, UnreadableFile) {
  const fs::path missing = fs::path(::testing::TempDir()) / "chatter_no_such_config.toml";
  fs::remove(missing);
  try {
    (void)load_config(missing);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), missing.string() + ": cannot read file (No such file or directory)");
  }
}

TEST(ConfigError, DirectoryIsUnreadable) {
  try {
    (void)load_config(kConfigDir);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), kConfigDir.string() + ": cannot read file (is a directory)");
  }
}

TEST(ConfigError, LoadConfigNamesThePathAndStem) {
  const fs::path file = fs::path(::testing::TempDir()) / "chatter_bad_config.toml";
  {
    std::ofstream out(file);
    out << Turning("[[tool.modes]]\nfrequency_hz = 100.0\ndamping_ratio = 0.03\nmass_kg = 0\n");
  }
  try {
    (void)load_config(file);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() + ": tool.modes[0].mass_kg = 0: must be > 0");
  }
  {
    std::ofstream out(file);
    out << TurningWithToolMode("");
  }
  const Config c = load_config(file);
  EXPECT_EQ(c.name, "chatter_bad_config");
  EXPECT_EQ(c.source, file);
  fs::remove(file);
}

// ============================================================ shop units

// The value as it would be in SI, times the unit's factor: exact up to the
// one rounding of the multiplication.
constexpr double kUnitRelTol = 1e-15;

TEST(ConfigUnits, ShopUnitKeysGiveTheSameModelAsSi) {
  const Config si = parse_config(R"(
[process]
operation = "milling"
teeth = 2
tangential_coefficient_n_per_m2 = 6e8
radial_coefficient_n_per_m2 = 2e8
radial_immersion = 0.05
[[tool.modes]]
frequency_hz = 922
damping_ratio = 0.011
mass_kg = 0.03993
[[tool.modes]]
frequency_hz = 1500
damping_ratio = 0.02
stiffness_n_per_m = 2e7
[[workpiece.modes]]
damping_ratio = 0.025
cantilever = { youngs_modulus_pa = 180e9, density_kg_per_m3 = 7600, length_m = 0.5, diameter_m = 0.12 }
)",
                                 kOrigin);
  const Config shop = parse_config(R"(
[process]
operation = "milling"
teeth = 2
tangential_coefficient_n_per_mm2 = 600
radial_coefficient_n_per_mm2 = 200
radial_immersion = 0.05
[[tool.modes]]
frequency_hz = 922
damping_ratio = 0.011
mass_g = 39.93
[[tool.modes]]
frequency_hz = 1500
damping_ratio = 0.02
stiffness_n_per_um = 20
[[workpiece.modes]]
damping_ratio = 0.025
cantilever = { youngs_modulus_gpa = 180, density_g_per_cm3 = 7.6, length_mm = 500, diameter_mm = 120 }
)",
                                   kOrigin);
  const MillingParameters& a = si.process.milling_parameters();
  const MillingParameters& b = shop.process.milling_parameters();
  EXPECT_TRUE(RelNear(b.tangential_coefficient_n_per_m2, a.tangential_coefficient_n_per_m2, kUnitRelTol));
  EXPECT_TRUE(RelNear(b.radial_coefficient_n_per_m2, a.radial_coefficient_n_per_m2, kUnitRelTol));
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_TRUE(RelNear(shop.model.tool.modes[i].stiffness_n_per_m, si.model.tool.modes[i].stiffness_n_per_m,
                        4 * kUnitRelTol));
  EXPECT_TRUE(RelNear(shop.model.workpiece.modes[0].stiffness_n_per_m, si.model.workpiece.modes[0].stiffness_n_per_m,
                      16 * kUnitRelTol));
  EXPECT_TRUE(RelNear(shop.model.workpiece.modes[0].natural_frequency_hz,
                      si.model.workpiece.modes[0].natural_frequency_hz, 16 * kUnitRelTol));
  EXPECT_TRUE(si.warnings.empty()) << si.warnings.front();
  EXPECT_TRUE(shop.warnings.empty()) << shop.warnings.front();
  const Config turning = parse_config(
      "[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_mm2 = 2400\n" + kOneToolMode, kOrigin);
  EXPECT_TRUE(RelNear(turning.process.turning_parameters().feed_force_coefficient_n_per_m2, 2.4e9, kUnitRelTol));
}

TEST(ConfigUnits, OneQuantityTwoKeysIsAnErrorNamingBoth) {
  EXPECT_TRUE(ThrowsInputError(
      Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nstiffness_n_per_m = 2e7\n"
              "stiffness_n_per_um = 20\n"),
      {"mem/case.toml: tool.modes[0].stiffness_n_per_um = 20: not with stiffness_n_per_m", "one quantity, one key"}));
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\n"
                                       "tangential_coefficient_n_per_mm2 = 600\nradial_coefficient_n_per_m2 = 2e8\n"
                                       "radial_immersion = 0.5\n"),
                               {"process.tangential_coefficient_n_per_mm2 = 600: not with "
                                "tangential_coefficient_n_per_m2"}));
  EXPECT_TRUE(ThrowsInputError(Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nmass_g = 40\n"
                                       "mass_kg = 0.04\n"),
                               {"tool.modes[0].mass_g = 40: not with mass_kg"}));
}

// ============================================================ warnings

/// The warnings of a config that loads.
std::vector<std::string> WarningsOf(const std::string& text) { return parse_config(text, kOrigin).warnings; }

/// Succeeds when exactly one warning is raised and it holds every part.
::testing::AssertionResult WarnsOnce(const std::string& text, std::initializer_list<std::string> parts) {
  std::vector<std::string> w;
  try {
    w = WarningsOf(text);
  } catch (const InputError& e) {
    return ::testing::AssertionFailure() << "refused: " << e.what();
  }
  if (w.size() != 1) {
    auto f = ::testing::AssertionFailure() << w.size() << " warnings:";
    for (const auto& x : w) f << "\n  " << x;
    return f;
  }
  for (const std::string& p : parts)
    if (w[0].find(p) == std::string::npos) return ::testing::AssertionFailure() << "\"" << w[0] << "\" lacks \"" << p << "\"";
  return ::testing::AssertionSuccess() << w[0];
}

TEST(ConfigWarning, EveryValidModelOfTheseTestsRaisesNone) {
  for (const std::string& text :
       {TurningWithToolMode(""), Milling(kMillingKeys), Milling(kMillingKeys + "milling_direction = \"up\"\n"),
        Turning("[[workpiece.modes]]\ndamping_ratio = 0.025\n[workpiece.modes.cantilever]\nyoungs_modulus_pa = "
                "180e9\ndensity_kg_per_m3 = 7600\nlength_m = 0.5\ndiameter_m = 0.12\n"),
        Turning("[[tool.modes]]\nfrequency_hz = 300.0\ndamping_ratio = 0.03\nmass_kg = 2\ndirection = [3, -4.0]\n"),
        Milling("teeth = 4\ntangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_n_per_m2 = 0\n"
                "radial_immersion = 1\n"),
        TurningWithToolMode("[sweep]\nrpm_min = 50\nrpm_max = 2000\n")}) {
    const auto w = WarningsOf(text);
    EXPECT_TRUE(w.empty()) << text << "\n" << (w.empty() ? "" : w.front());
  }
}

TEST(ConfigWarning, CoefficientInNPerMm2TypedIntoNPerM2Key) {
  // The issue's case: K_t = 700 and K_r = 210, meant as N/mm^2.
  const auto w = WarningsOf(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 700\n"
                                    "radial_coefficient_n_per_m2 = 210\nradial_immersion = 0.5\n"));
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0],
            "mem/case.toml: process.tangential_coefficient_n_per_m2 = 700: K_t = 700 N/m^2 is over 1e5 times below "
            "the 1e8 to 1e10 N/m^2 of metal cutting (aluminium about 5e8, steel about 2e9, hardened steel and "
            "titanium about 3e9); did you mean N/mm^2 (tangential_coefficient_n_per_mm2 = 700)?");
  EXPECT_NE(w[1].find("process.radial_coefficient_n_per_m2 = 210: K_r = 210 N/m^2"), std::string::npos) << w[1];
  EXPECT_NE(w[1].find("did you mean N/mm^2 (radial_coefficient_n_per_mm2 = 210)?"), std::string::npos) << w[1];
  EXPECT_TRUE(WarnsOnce("[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = 2400\n" + kOneToolMode,
                        {"process.feed_force_coefficient_n_per_m2 = 2400: K_f = 2400 N/m^2",
                         "did you mean N/mm^2 (feed_force_coefficient_n_per_mm2 = 2400)?"}));
}

TEST(ConfigWarning, RadialOverTangentialRatio) {
  // K_t = 700 (N/mm^2 meant) with K_r = 2.1e8: the ratio is 3e5.
  const auto w = WarningsOf(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 700\n"
                                    "radial_coefficient_n_per_m2 = 2.1e8\nradial_immersion = 0.5\n"));
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0].find("did you mean N/mm^2"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("process.radial_coefficient_n_per_m2 = 2.1e8: K_r/K_t = 3e+05"), std::string::npos) << w[1];
  EXPECT_TRUE(WarnsOnce(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\n"
                                "radial_coefficient_n_per_m2 = 1.2e9\nradial_immersion = 0.5\n"),
                        {"K_r/K_t = 2,", "0.1 to 1"}));
}

TEST(ConfigWarning, StiffnessInNPerUmTypedIntoNPerMKey) {
  EXPECT_TRUE(WarnsOnce(Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nstiffness_n_per_m = 20\n"),
                        {"mem/case.toml: tool.modes[0].stiffness_n_per_m = 20: k = 20 N/m is over 1e3 times below",
                         "did you mean N/um (stiffness_n_per_um = 20)?"}));
  EXPECT_TRUE(WarnsOnce(
      Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nstiffness_n_per_m = 20000\n"),
      {"is it in N/mm (stiffness_n_per_m = 2e+07)?"}));
  // A mass in grams typed into mass_kg: k = m (2 pi f)^2 far above machine
  // modes (a 40 kg column mode at 200 Hz: 6.3e7 N/m, usual).
  EXPECT_TRUE(WarnsOnce(Turning("[[tool.modes]]\nfrequency_hz = 200\ndamping_ratio = 0.03\nmass_kg = 39930\n"),
                        {"tool.modes[0].mass_kg = 39930: gives k = m (2 pi f)^2 = ", "did you mean g (mass_g = 39930)?"}));
}

TEST(ConfigWarning, DampingAndFrequency) {
  EXPECT_TRUE(WarnsOnce(Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.5\nstiffness_n_per_m = 2e7\n"),
                        {"tool.modes[0].damping_ratio = 0.5: zeta = 0.5 is above", "is it in percent"}));
  EXPECT_TRUE(WarnsOnce(Turning("[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 2e-4\nstiffness_n_per_m = 2e7\n"),
                        {"tool.modes[0].damping_ratio = 2e-4: zeta = 0.0002 is below"}));
  EXPECT_TRUE(WarnsOnce(Turning("[[tool.modes]]\nfrequency_hz = 6e4\ndamping_ratio = 0.03\nstiffness_n_per_m = 2e7\n"),
                        {"tool.modes[0].frequency_hz = 6e4: f = 6e+04 Hz is above", "is it in rad/s (frequency_hz = 9549)?"}));
  EXPECT_TRUE(WarnsOnce(Turning("[[tool.modes]]\nfrequency_hz = 0.9\ndamping_ratio = 0.03\nstiffness_n_per_m = 2e7\n"),
                        {"tool.modes[0].frequency_hz = 0.9: f = 0.9 Hz is over 1e1 times below", "is it in kHz (frequency_hz = 900)?"}));
}

TEST(ConfigWarning, FrequencyOutOfReachOfTheSpeedRange) {
  // A 100 Hz mode, 2 teeth, rpm_max = 12: tooth passing at 0.4 Hz, lobe 250
  // (at or above the 10 rev/min a spindle turns: no warning on the speeds).
  EXPECT_TRUE(WarnsOnce(Milling(kMillingKeys) + "[sweep]\nrpm_min = 10\nrpm_max = 12\n",
                        {"tool.modes[0].frequency_hz = 100.0: f is over 200 times the tooth-passing frequency",
                         "rev/min"}));
  // A 100 Hz mode against 2 teeth at 120 000 rev/min or more: tooth passing 40 times f.
  EXPECT_TRUE(WarnsOnce(Milling(kMillingKeys) + "[sweep]\nrpm_min = 120000\nrpm_max = 200000\n",
                        {"tool.modes[0].frequency_hz = 100.0: f is under 1/20 of the tooth-passing frequency"}));
}

// Every length, speed and coefficient of [process] and [sweep] has a usual
// band; a value 1000 times off names the unit slip (issue 44: these loaded
// silently). Each case: the key, the value, and a piece of the warning.
TEST(ConfigWarning, LengthsSpeedsAndCoefficientsOutsideTheirBandNameTheUnit) {
  const std::string head = "teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_n_per_m2 = 2e8\n";
  const std::string ratio = head + "radial_immersion = 0.5\n";
  EXPECT_TRUE(WarnsOnce(Milling(ratio + "tool_diameter_mm = 0.016\n"),
                        {"process.tool_diameter_mm = 0.016: outside the 0.1 to 500 mm of milling cutters",
                         "is it in m (tool_diameter_mm = 16)?"}));
  EXPECT_TRUE(WarnsOnce(Milling(ratio + "tool_diameter_mm = 16000\n"),
                        {"tool_diameter_mm = 16000", "is it in um (tool_diameter_mm = 16)?"}));
  EXPECT_TRUE(WarnsOnce(Milling(ratio + "flute_length_mm = 30000\n"), {"process.flute_length_mm = 30000"}));
  EXPECT_TRUE(WarnsOnce(Milling(head + "radial_immersion = 0.0005\n"),
                        {"process.radial_immersion = 0.0005: outside the 0.002 to 1 of milling"}));
  EXPECT_TRUE(WarnsOnce(Milling(ratio + "feed_per_tooth_mm = 0.00005\n"),
                        {"process.feed_per_tooth_mm = 0.00005", "is it in m (feed_per_tooth_mm = 0.05)?"}));
  const std::vector<std::string> ka = WarningsOf(Milling(ratio + "axial_force_coefficient_n_per_m2 = 4e11\n"));
  EXPECT_TRUE(std::any_of(ka.begin(), ka.end(), [](const std::string& w) {
    return w.find("process.axial_force_coefficient_n_per_m2 = 4e11: K_a = 4e+11 N/m^2 is over") != std::string::npos;
  })) << ka.size();
  EXPECT_TRUE(WarnsOnce(Milling(kMillingKeys) + "[sweep]\nrpm_min = 5\nrpm_max = 400\n",
                        {"sweep.rpm_min = 5: outside the 10 to 200 000 rev/min", "is it in rev/s (rpm_min = 300)?"}));
  EXPECT_TRUE(WarnsOnce(Milling(kMillingKeys) + "[sweep]\ndepth_max_mm = 8000\n",
                        {"sweep.depth_max_mm = 8000", "is it in um (depth_max_mm = 8)?"}));
  // Inside the bands: silent.
  EXPECT_TRUE(parse_config(Milling(ratio + "tool_diameter_mm = 16\nflute_length_mm = 30\nfeed_per_tooth_mm = 0.05\n"),
                           kOrigin).warnings.empty());
}

TEST(ConfigWarning, CantileverInMillimetresTypedIntoMetreKeys) {
  EXPECT_TRUE(WarnsOnce(Turning("[[workpiece.modes]]\ndamping_ratio = 0.025\ncantilever = { youngs_modulus_pa = "
                                "180e9, density_kg_per_m3 = 7600, length_m = 500, diameter_m = 0.12 }\n"),
                        {"workpiece.modes[0].cantilever.length_m = 500: L = 500 m is over 1e1 times above",
                         "did you mean mm (length_mm = 500)?"}));
}

// ============================================================ every error at once

TEST(ConfigErrors, EveryErrorOfTheFileIsListed) {
  const std::string msg = MessageOf(R"(
nmae = "x"
[process]
operation = "turning"
feed_force_coefficient_n_per_m2 = -1
colour = "red"
[[tool.modes]]
frequency_hz = 100
damping_ratio = 1.5
stiffness = 2e7
[[tool.modes]]
frequency_hz = 200
damping_ratio = 0.03
stiffness_n_per_m = 2e7
direction = "z"
[sweep]
rpm_min = 500
rpm_max = 100
)");
  EXPECT_EQ(msg,
            "mem/case.toml: nmae: unknown key (did you mean name?)\n"
            "mem/case.toml: process.colour: unknown key (expected one of: operation, feed_force_coefficient_n_per_m2, "
            "feed_force_coefficient_n_per_mm2, radial_force_coefficient_n_per_m2, radial_force_coefficient_n_per_mm2, "
            "lead_angle_deg, nose_radius_mm, feed_per_rev_mm, workpiece_diameter_mm, force_law, specific_force_n_per_mm2, exponent, teeth, "
            "tangential_coefficient_n_per_m2, tangential_coefficient_n_per_mm2, radial_coefficient_n_per_m2, "
            "radial_coefficient_n_per_mm2, radial_immersion, milling_direction, feed_per_tooth_mm, flute_length_mm, "
            "tool_diameter_mm, radial_depth_mm, engaged_arc_deg, helix_angle_deg, pitch_angles_deg, runout_um, radial_coefficient_ratio, "
            "cutter_geometry, corner_radius_mm, profile, profile_slices, axial_force_coefficient_n_per_m2, "
            "axial_force_coefficient_n_per_mm2, process_damping_coefficient_n_per_m, speed_variation)\n"
            "mem/case.toml: process.feed_force_coefficient_n_per_m2 = -1: must be > 0\n"
            "mem/case.toml: tool.modes[0].stiffness: unknown key (did you mean stiffness_n_per_m?)\n"
            "mem/case.toml: tool.modes[0].damping_ratio = 1.5: must be in (0, 1) (a ratio, not a percentage: 1.5 % is "
            "0.015)\n"
            "mem/case.toml: tool.modes[1].direction = \"z\": must be \"x\", \"y\" or two numbers [x, y]\n"
            "mem/case.toml: sweep.rpm_max = 100: must be > rpm_min (500)");
}

TEST(ConfigErrors, ListIsCappedAtTwentyWithACount) {
  std::string text = TurningWithToolMode("");
  for (int i = 0; i < 25; ++i) text += "[[workpiece.modes]]\nfrequency_hz = -" + std::to_string(i + 1) + "\n";
  const std::string msg = MessageOf(text);
  // 25 modes, each with three errors (frequency, damping, stiffness): 75.
  std::size_t lines = 1;
  for (char c : msg) lines += c == '\n';
  EXPECT_EQ(lines, 21u) << msg;
  EXPECT_NE(msg.find("mem/case.toml: 55 more errors not listed (the first 20 are)"), std::string::npos) << msg;
}

}  // namespace
}  // namespace chatter

// ============================================================ real cutters

namespace chatter {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

const std::string kCutterHead = R"(teeth = 4
tangential_coefficient_n_per_mm2 = 600
tool_diameter_mm = 12
)";

TEST(ConfigCutter, ShopTermsAreReadInSi) {
  const Config c = parse_config(Milling(kCutterHead + R"(radial_coefficient_ratio = 0.3
radial_depth_mm = 3
milling_direction = "conventional"
helix_angle_deg = 30
pitch_angles_deg = [80, 100, 80, 100]
runout_um = [5, 0, -3, 0]
process_damping_coefficient_n_per_m = 2e5
)"),
                                    "mem/case.toml");
  const MillingParameters& m = c.process.milling_parameters();
  EXPECT_NEAR(m.radial_coefficient_n_per_m2, 0.3 * 6e8, 1e-6);
  EXPECT_NEAR(m.radial_immersion, 0.25, 1e-15);
  EXPECT_EQ(m.direction, MillingDirection::kUp);
  EXPECT_NEAR(m.tool_diameter_m, 0.012, 1e-15);
  EXPECT_NEAR(c.process.helix_angle_rad(3), 30 * kDegToRad, 1e-15);
  EXPECT_NEAR(c.process.pitch_angle_rad(1), 100 * kDegToRad, 1e-15);
  EXPECT_NEAR(c.process.tooth_offset_rad(3), 280 * kDegToRad, 1e-12);  // θ_1 + θ_2 + θ_3 = 100 + 80 + 100
  EXPECT_NEAR(c.process.runout_m(2), -3e-6, 1e-18);
  EXPECT_NEAR(m.process_damping_coefficient_n_per_m, 2e5, 1e-9);
  EXPECT_TRUE(c.process.has_variable_pitch());
  EXPECT_FALSE(c.process.has_variable_helix());
  // "climb" is down-milling; one helix per tooth.
  const Config d = parse_config(Milling(kCutterHead + R"(radial_coefficient_n_per_m2 = 2e8
radial_immersion = 0.5
milling_direction = "climb"
helix_angle_deg = [30, 35, 30, 35]
)"),
                                    "mem/case.toml");
  EXPECT_EQ(d.process.milling_parameters().direction, MillingDirection::kDown);
  EXPECT_TRUE(d.process.has_variable_helix());
  EXPECT_NEAR(d.process.helix_angle_rad(1), 35 * kDegToRad, 1e-15);
}

TEST(ConfigCutter, PitchAnglesAreScaledToOneRevolution) {
  // 90.0002 × 4 = 360.0008: within the 1e-3 deg written tolerance; scaled.
  const Config c = parse_config(Milling(kCutterHead + R"(radial_coefficient_ratio = 0.3
radial_immersion = 1
pitch_angles_deg = [90.0002, 90.0002, 90.0002, 90.0002]
)"),
                                    "mem/case.toml");
  double sum = 0.0;
  for (int j = 0; j < 4; ++j) sum += c.process.pitch_angle_rad(j);
  EXPECT_NEAR(sum, 2.0 * 3.14159265358979323846, 1e-14);
}

TEST(ConfigCutter, ImpossibleCuttersAreRefusedWithKeyAndRule) {
  const std::string ok = "radial_coefficient_ratio = 0.3\n";
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_immersion = 1\npitch_angles_deg = [90, 90, 90, 80]\n"),
                               {"mem/case.toml: process.pitch_angles_deg = [90, 90, 90, 80]: sums to 350 deg: the pitch "
                                "angles must sum to 360 deg (one revolution)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_immersion = 1\npitch_angles_deg = [120, 120, 120]\n"),
                               {"process.pitch_angles_deg = [120, 120, 120]: has 3 values: need one per tooth (teeth = 4)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_immersion = 1\npitch_angles_deg = [0, 180, 90, 90]\n"),
                               {"process.pitch_angles_deg[0] = 0: must be > 0"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_immersion = 1\nhelix_angle_deg = 90\n"),
                               {"process.helix_angle_deg = 90: must be in [0, 90) (deg)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_immersion = 1\nhelix_angle_deg = -5\n"),
                               {"process.helix_angle_deg = -5: must be in [0, 90) (deg)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_depth_mm = 13\n"),
                               {"process.radial_depth_mm = 13: must be <= tool_diameter_mm (12 mm)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_depth_mm = 3\nradial_immersion = 0.25\n"),
                               {"process.radial_depth_mm = 3: not with radial_immersion"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_immersion = 1\nrunout_um = [10, 0]\n"),
                               {"process.runout_um = [10, 0]: has 2 values: need one radial offset per tooth (teeth = 4)"}));
  // Runout beyond the radius: the element named; with one tooth a single
  // number is the list (found by fuzzing: it dereferenced a missing array).
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + ok + "radial_immersion = 1\nrunout_um = [10, 0, 6000, 0]\n"),
                               {"process.runout_um[2] = 6000: must be smaller than the tool radius (6000 um)"}));
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 1\ntangential_coefficient_n_per_mm2 = 600\ntool_diameter_mm = 10\n" + ok +
                                       "radial_immersion = 0.3\nrunout_um = 1e5\n"),
                               {"process.runout_um = 1e5: must be smaller than the tool radius (5000 um)"}));
  EXPECT_TRUE(ThrowsInputError(Milling(kCutterHead + "radial_coefficient_ratio = 0.3\nradial_coefficient_n_per_m2 = 2e8\n"
                                                     "radial_immersion = 1\n"),
                               {"process.radial_coefficient_n_per_m2 = 2e8: not with radial_coefficient_ratio"}));
  // A helix or process damping without the diameter; radial depth without it.
  EXPECT_TRUE(ThrowsInputError(Milling("teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_ratio = 0.3\n"
                                       "radial_depth_mm = 3\nhelix_angle_deg = 30\n"),
                               {"process.radial_depth_mm = 3: needs process.tool_diameter_mm",
                                "process.helix_angle_deg = 30: needs process.tool_diameter_mm"}));
  EXPECT_TRUE(ThrowsInputError(Turning("process_damping_coefficient_n_per_m = 1e5\n" + kOneToolMode),
                               {"process.process_damping_coefficient_n_per_m = 1e5: needs process.workpiece_diameter_mm"}));
  EXPECT_TRUE(ThrowsInputError(Turning("helix_angle_deg = 30\n" + kOneToolMode),
                               {"process.helix_angle_deg = 30: only for operation = \"milling\""}));
}

// Plausibility of the cutter and the sweep (issue 26): a steep helix, a helix
// in radians, a feed that is no feed, a sweep typed in rev/s.
TEST(ConfigWarning, CutterAndSweepPlausibility) {
  const std::string cutter = kMillingKeys + "tool_diameter_mm = 12\n";
  EXPECT_TRUE(WarnsOnce(Milling(cutter + "helix_angle_deg = 89\n"),
                        {"process.helix_angle_deg = 89: a helix of 89 deg (60 or more) is beyond end mills"}));
  EXPECT_TRUE(WarnsOnce(Milling(cutter + "helix_angle_deg = 0.52\n"),
                        {"process.helix_angle_deg = 0.52: a helix of 0.52 deg is hardly a helix: a value in radians",
                         "29.79 deg"}));
  EXPECT_TRUE(WarnsOnce(Milling(cutter + "helix_angle_deg = [30, 0.5]\n"), {"a helix of 0.5 deg"}));
  EXPECT_TRUE(WarningsOf(Milling(cutter + "helix_angle_deg = 30\n")).empty());
  EXPECT_TRUE(WarningsOf(Milling(cutter + "helix_angle_deg = 0\n")).empty());  // straight teeth
  EXPECT_TRUE(WarnsOnce(Milling(kMillingKeys + "feed_per_tooth_mm = 8\n"),
                        {"process.feed_per_tooth_mm = 8: a feed of 8 mm per tooth is above"}));
  EXPECT_TRUE(WarnsOnce(Turning("feed_per_rev_mm = 3\n" + kOneToolMode),
                        {"process.feed_per_rev_mm = 3: a feed of 3 mm per revolution"}));
  // 50-250 rev/min for a 100 Hz mode and 2 teeth: the highest tooth passing
  // (8.33 Hz) is below 1/10 of the mode; 500-20000 is not warned.
  EXPECT_TRUE(WarnsOnce(Milling(kMillingKeys) + "[sweep]\nrpm_min = 50\nrpm_max = 250\n",
                        {"sweep.rpm_max = 250: the highest tooth-passing frequency of the sweep (8.333 Hz) is below "
                         "1/10 of the lowest natural frequency (100 Hz)",
                         "rev/s"}));
  EXPECT_TRUE(WarningsOf(Milling(kMillingKeys) + "[sweep]\nrpm_min = 500\nrpm_max = 20000\n").empty());
}

}  // namespace
}  // namespace chatter

namespace chatter {
namespace {

// engaged_arc_deg: one arc or a list of arcs; each is checked, named by its
// index, and the arcs must be sorted and apart.
TEST(ConfigEngagedArcs, OneArcOrAListOfArcs) {
  const std::string head = "teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_n_per_m2 = 2e8\n";
  const Config one = parse_config(Milling(head + "engaged_arc_deg = [0, 180]\n"), kOrigin);
  ASSERT_EQ(one.process.engaged_arcs().size(), 1u);
  EXPECT_DOUBLE_EQ(one.process.milling_parameters().radial_immersion, 1.0);
  const Config two = parse_config(Milling(head + "engaged_arc_deg = [[0, 60], [120, 180]]\n"), kOrigin);
  ASSERT_EQ(two.process.engaged_arcs().size(), 2u);
  EXPECT_NEAR(two.process.engaged_arcs()[1].first, 120.0 * std::numbers::pi / 180.0, 1e-15);
  // Σ (cos en − cos ex)/2 = (1 − 0.5)/2 + (−0.5 + 1)/2 = 0.5
  EXPECT_NEAR(two.process.milling_parameters().radial_immersion, 0.5, 1e-12);
  EXPECT_TRUE(ThrowsInputError(Milling(head + "engaged_arc_deg = [[0, 60], [50, 180]]\n"),
                               {"process.engaged_arc_deg[1]", "must not touch or overlap"}));
  EXPECT_TRUE(ThrowsInputError(Milling(head + "engaged_arc_deg = [[0, 60], [90, 200]]\n"),
                               {"process.engaged_arc_deg[1]", "0 <= entry < exit <= 180"}));
  EXPECT_TRUE(ThrowsInputError(Milling(head + "engaged_arc_deg = 90\n"), {"process.engaged_arc_deg", "[entry, exit]"}));
  EXPECT_TRUE(ThrowsInputError(Milling(head + "engaged_arc_deg = [0, 90]\nradial_immersion = 0.5\n"),
                               {"process.engaged_arc_deg", "not with radial_immersion"}));
}


// Unit slips on the radial engagement (issue 44): a percentage typed as the
// ratio is refused with the ratio it meant; a radial depth in metres loads
// with a warning that says so.
TEST(Config, RadialEngagementUnitSlipsNameTheUnit) {
  const std::string head = "teeth = 2\ntangential_coefficient_n_per_m2 = 6e8\nradial_coefficient_n_per_m2 = 2e8\n";
  EXPECT_TRUE(ThrowsInputError(Milling(head + "radial_immersion = 25\n"),
                               {"process.radial_immersion = 25", "not a percentage: 25 % is 0.25"}));
  EXPECT_TRUE(ThrowsInputError(Milling(head + "radial_immersion = 1.5\n"),
                               {"process.radial_immersion = 1.5", "not a percentage: 1.5 % is 0.015"}));
  EXPECT_TRUE(ThrowsInputError(Milling(head + "radial_immersion = 250\n"), {"process.radial_immersion = 250", "in (0, 1]"}));
  const Config metres = parse_config(Milling(head + "tool_diameter_mm = 16\nradial_depth_mm = 0.004\n"), kOrigin);
  ASSERT_EQ(metres.warnings.size(), 1u);
  EXPECT_NE(metres.warnings[0].find("process.radial_depth_mm = 0.004"), std::string::npos) << metres.warnings[0];
  EXPECT_NE(metres.warnings[0].find("a radial depth in m? (0.004 m is 4 mm)"), std::string::npos) << metres.warnings[0];
  EXPECT_TRUE(parse_config(Milling(head + "tool_diameter_mm = 16\nradial_depth_mm = 0.5\n"), kOrigin).warnings.empty());
}

}  // namespace
}  // namespace chatter
