// The real-cutter keys through the binary: an impossible cutter is refused
// with file, key and rule, exit 2 and nothing written; what a method does
// not see of the cutter is said on stderr and recorded in the JSON.
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace {

using chatter::test::contains;
using chatter::test::slurp;

class CliCutter : public chatter::test::CliFixture {
 protected:
  std::string write_config(const std::string& cutter_keys) {
    const auto p = path("cutter.toml");
    std::ofstream(p) << "name = \"4 flutes\"\n[process]\noperation = \"milling\"\nteeth = 4\n"
                        "tangential_coefficient_n_per_mm2 = 600\nradial_coefficient_ratio = 0.3\n"
                        "tool_diameter_mm = 12\nradial_depth_mm = 6\n"
                     << cutter_keys
                     << "[[tool.modes]]\nfrequency_hz = 900\ndamping_ratio = 0.02\nstiffness_n_per_m = 2e7\n"
                        "direction = \"x\"\n[[tool.modes]]\nfrequency_hz = 900\ndamping_ratio = 0.02\n"
                        "stiffness_n_per_m = 2e7\ndirection = \"y\"\n";
    return p.string();
  }
};

TEST_F(CliCutter, ImpossibleCutterIsRefusedAndNothingIsWritten) {
  const std::string cfg = write_config("pitch_angles_deg = [90, 90, 90, 80]\n");
  const auto out = path("lobes.csv");
  const auto r = run({"lobes", cfg, "--rpm-min", "5000", "--rpm-max", "6000", "--rpm-points", "3", "--table", out.string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "cutter.toml: process.pitch_angles_deg = [90, 90, 90, 80]: sums to 350 deg")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  const std::string cfg2 = write_config("helix_angle_deg = 95\n");
  const auto r2 = run({"point", cfg2, "--rpm", "5000", "--depth-mm", "1"});
  EXPECT_EQ(r2.exit_code, 2);
  EXPECT_TRUE(contains(r2.err, "process.helix_angle_deg = 95: must be in [0, 90) (deg)")) << r2.err;
  EXPECT_TRUE(r2.out.empty()) << r2.out;
}

TEST_F(CliCutter, RunoutIgnoredByALinearMethodIsSaidAndRecorded) {
  const std::string cfg = write_config("runout_um = [8, 0, -4, 0]\n");
  const auto json = path("lobes.json");
  const auto r = run({"lobes", cfg, "--method", "analytic", "--rpm-min", "5000", "--rpm-max", "6000", "--rpm-points", "3",
                      "--table", path("lobes.csv").string(), "--json", json.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "note: runout (process.runout_um) is ignored by method \"analytic\"")) << r.err;
  const auto j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["notes"].size(), 1u) << j["notes"];
  EXPECT_TRUE(contains(j["notes"][0].get<std::string>(), "runout")) << j["notes"];
  // The cutter as given, in the units of the keys.
  const auto& p = j["config"]["process"];
  EXPECT_DOUBLE_EQ(p["tool_diameter_mm"].get<double>(), 12.0);
  EXPECT_DOUBLE_EQ(p["radial_immersion"].get<double>(), 0.5);
  EXPECT_NEAR(p["runout_um"][0].get<double>(), 8.0, 1e-9);
  EXPECT_NEAR(p["runout_um"][2].get<double>(), -4.0, 1e-9);
  EXPECT_NEAR(p["radial_coefficient_n_per_m2"].get<double>(), 1.8e8, 1e-3);
}

}  // namespace

namespace {

TEST_F(CliCutter, LinearSimulationSaysItIgnoresRunout) {
  const std::string cfg = write_config("runout_um = [8, 0, -4, 0]\n");
  const auto r = run({"point", cfg, "--rpm", "6000", "--depth-mm", "0.5", "--method", "time-domain", "--linear", "--periods", "40"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "note: runout (process.runout_um) is ignored with --linear")) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["notes"].size(), 1u) << j["notes"];
  // Without --linear the simulation sees the runout: no note.
  const auto n = run({"point", cfg, "--rpm", "6000", "--depth-mm", "0.5", "--method", "time-domain", "--periods", "40"});
  ASSERT_EQ(n.exit_code, 0) << n.err;
  EXPECT_FALSE(contains(n.err, "note:")) << n.err;
}

TEST_F(CliCutter, SimulateCountsRevolutionsForAVariablePitchCutter) {
  // The run's period is the Floquet period, the shortest repeat of the
  // cutter (80/100/80/100: two teeth, half a revolution, as sdm's):
  // --revolutions 12 is 24 periods, growth_per_period is per half revolution;
  // the tooth passing is N N_t / 60 whatever the pitch.
  const std::string cfg = write_config("pitch_angles_deg = [80, 100, 80, 100]\n");
  const auto r = run({"simulate", cfg, "--rpm", "6000", "--depth-mm", "0.5", "--revolutions", "12"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["periods"].get<int>(), 24);
  EXPECT_DOUBLE_EQ(j["floquet_period_s"].get<double>(), 0.005);
  EXPECT_DOUBLE_EQ(j["tooth_passing_hz"].get<double>(), 400.0);
  EXPECT_DOUBLE_EQ(j["revolutions"].get<double>(), 12.0);
}

}  // namespace
