// The [process] keys of the cutter's shape (docs/config.md "Cutter geometry",
// docs/cutter_geometry.md): the shipped ball-end example loads, a general
// profile reads row by row, and every bad value is an InputError naming the
// file, the key path and the rule.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <numbers>
#include <string>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"

namespace chatter {
namespace {

const std::string kOrigin = "mem/ball.toml";

const std::string kHead = R"(
[process]
operation = "milling"
teeth = 2
tangential_coefficient_n_per_mm2 = 1800
radial_coefficient_ratio = 0.35
radial_immersion = 0.5
)";
const std::string kMode = R"(
[[tool.modes]]
frequency_hz = 1350
damping_ratio = 0.025
stiffness_n_per_um = 4
)";

std::string cfg(const std::string& process_keys, const std::string& tables = "") {
  return kHead + process_keys + tables + kMode;
}

::testing::AssertionResult ThrowsInputError(const std::string& text, std::initializer_list<std::string> parts) {
  try {
    (void)parse_config(text, kOrigin);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts)
      if (msg.find(p) == std::string::npos)
        return ::testing::AssertionFailure() << "message \"" << msg << "\" lacks \"" << p << "\"";
    return ::testing::AssertionSuccess() << msg;
  }
  return ::testing::AssertionFailure() << "no exception";
}

TEST(CutterProfileConfig, ShippedBallEndExample) {
  const Config c = load_config(std::filesystem::path(CHATTER_SOURCE_DIR) / "configs" / "milling_ball_end.toml");
  ASSERT_TRUE(c.process.has_profile());
  const MillingParameters& p = c.process.milling_parameters();
  EXPECT_EQ(p.cutter.geometry, CutterGeometry::kBall);
  EXPECT_EQ(p.axial_coefficient_n_per_m2, 400e6);
  EXPECT_EQ(p.tool_diameter_m, 10e-3);
  EXPECT_EQ(c.process.cutter_profile().slices(), kDefaultProfileSlices);
}

TEST(CutterProfileConfig, FlatIsTheDefaultAndGeneralRowsAreRead) {
  EXPECT_FALSE(parse_config(cfg(""), kOrigin).process.has_profile());
  EXPECT_FALSE(parse_config(cfg("cutter_geometry = \"flat\"\n"), kOrigin).process.has_profile());
  const Config g = parse_config(cfg("cutter_geometry = \"general\"\ntool_diameter_mm = 10\nprofile_slices = 48\n",
                                    "[[process.profile]]\nheight_mm = 0\nradius_mm = 2\nlead_angle_deg = 20\n"
                                    "[[process.profile]]\nheight_mm = 3\nradius_mm = 5\nlead_angle_deg = 90\n"),
                                kOrigin);
  const auto& rows = g.process.milling_parameters().cutter.profile;
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].height_m, 3e-3);
  EXPECT_EQ(rows[1].radius_m, 5e-3);
  EXPECT_EQ(rows[1].lead_angle_rad, 0.5 * std::numbers::pi);  // exactly 90°
  EXPECT_EQ(g.process.cutter_profile().slices(), 48);
  const Config b = parse_config(cfg("cutter_geometry = \"bull_nose\"\ntool_diameter_mm = 10\ncorner_radius_mm = 1.5\n"),
                                kOrigin);
  EXPECT_EQ(b.process.milling_parameters().cutter.corner_radius_m, 1.5e-3);
}

TEST(CutterProfileConfig, BadValuesNameFileKeyAndRule) {
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"sphere\"\ntool_diameter_mm = 10\n"),
                               {kOrigin, "process.cutter_geometry", R"(must be "flat", "ball", "bull_nose" or "general")"}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"ball\"\n"),
                               {kOrigin, "process.cutter_geometry", "needs process.tool_diameter_mm"}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"bull_nose\"\ntool_diameter_mm = 10\n"),
                               {kOrigin, "process.corner_radius_mm", "missing (required with cutter_geometry = \"bull_nose\""}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"bull_nose\"\ntool_diameter_mm = 10\ncorner_radius_mm = 6\n"),
                               {kOrigin, "process.corner_radius_mm", "must be <= tool_diameter_mm / 2 = 5 mm"}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"ball\"\ntool_diameter_mm = 10\ncorner_radius_mm = 2\n"),
                               {kOrigin, "process.corner_radius_mm", "only with cutter_geometry = \"bull_nose\""}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"ball\"\ntool_diameter_mm = 10\n",
                                   "[[process.profile]]\nheight_mm = 0\nradius_mm = 2\nlead_angle_deg = 20\n"),
                               {kOrigin, "process.profile", "only with cutter_geometry = \"general\""}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"general\"\ntool_diameter_mm = 10\n"),
                               {kOrigin, "process.profile", "missing (required with cutter_geometry = \"general\""}));
  EXPECT_TRUE(ThrowsInputError(
      cfg("cutter_geometry = \"general\"\ntool_diameter_mm = 10\n",
          "[[process.profile]]\nheight_mm = 0\nradius_mm = 2\nlead_angle_deg = 20\n"
          "[[process.profile]]\nheight_mm = 0\nradius_mm = 3\nlead_angle_deg = 95\n"),
      {kOrigin, "process.profile[1].lead_angle_deg", "in [0, 90] (deg)"}));
  EXPECT_TRUE(ThrowsInputError(
      cfg("cutter_geometry = \"general\"\ntool_diameter_mm = 10\n",
          "[[process.profile]]\nheight_mm = 0\nradius_mm = 2\nlead_angle_deg = 20\n"
          "[[process.profile]]\nheight_mm = 0\nradius_mm = 3\nlead_angle_deg = 45\n"),
      {kOrigin, "process.profile[1].height_mm", "must be above the row before (0 mm)"}));
  EXPECT_TRUE(ThrowsInputError(
      cfg("cutter_geometry = \"general\"\ntool_diameter_mm = 10\n",
          "[[process.profile]]\nheight_mm = 1\nradius_mm = 2\nlead_angle_deg = 20\n"
          "[[process.profile]]\nheight_mm = 2\nradius_mm = 7\nlead_angle_deg = 45\n"),
      {kOrigin, "process.profile[0].height_mm", "must be 0 in the first row (the tip)", "process.profile[1].radius_mm",
       "must be <= tool_diameter_mm / 2 = 5 mm"}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"general\"\ntool_diameter_mm = 10\n",
                                   "[[process.profile]]\nheight_mm = 0\nradius_mm = 2\nlead_angle_deg = 20\n"),
                               {kOrigin, "process.profile", "needs at least 2 rows"}));
  EXPECT_TRUE(ThrowsInputError(cfg("profile_slices = 16\n"),
                               {kOrigin, "process.profile_slices", "only with cutter_geometry"}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"ball\"\ntool_diameter_mm = 10\nprofile_slices = 0\n"),
                               {kOrigin, "process.profile_slices", "must be an integer >= 1"}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"ball\"\ntool_diameter_mm = 10\naxial_force_coefficient_n_per_m2 = -1\n"),
                               {kOrigin, "process.axial_force_coefficient_n_per_m2", ">= 0"}));
  EXPECT_TRUE(ThrowsInputError(cfg("cutter_geometry = \"ball\"\ntool_diameter_mm = 10\n"
                                   "process_damping_coefficient_n_per_m = 1e4\n"),
                               {kOrigin, "process damping with cutter_geometry = ball is not modelled"}));
}

TEST(CutterProfileConfig, AxialCoefficientOnAFlatCutterIsAWarning) {
  const Config c = parse_config(cfg("axial_force_coefficient_n_per_mm2 = 300\n"), kOrigin);
  bool warned = false;
  for (const std::string& w : c.warnings) warned |= w.find("has no effect on a flat cutter") != std::string::npos;
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace chatter
