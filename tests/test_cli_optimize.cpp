// End-to-end tests of `chatter performance`, `optimize` and `adapt` (issue
// 29, docs/optimization.md) through the binary: the JSON keys of the issue,
// table 14 of the source study reproduced from --index, the exit statuses,
// the adapt rows and plot files, and bad input (exit 2, a message naming the
// file, the key or flag, and the rule).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_harness.hpp"

namespace fs = std::filesystem;

namespace {

using chatter::test::CliFixture;
using chatter::test::contains;
using chatter::test::RunResult;
using chatter::test::slurp;

const std::string kSeed = std::string(CHATTER_SOURCE_DIR) + "/configs/turning_seed003_shaft.toml";
const std::string kPlain = std::string(CHATTER_SOURCE_DIR) + "/configs/seed_turning_1dof.toml";

const std::vector<std::string> kIndexNames = {"diametral_error_um", "surface_roughness_um", "removal_rate_mm3_per_s",
                                              "cost", "production_rate_per_h"};

class CliOptimize : public CliFixture {
 protected:
  // The seed's config with `from` replaced by `to` (one occurrence, which must exist).
  std::string edited(const std::string& from, const std::string& to, const std::string& name = "edited.toml") {
    std::string text = slurp(kSeed);
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    std::ofstream(path(name)) << text;
    return path(name).string();
  }
};

TEST_F(CliOptimize, PerformancePrintsTheIssuesJsonKeys) {
  const RunResult r = run({"performance", kSeed, "--cutting-speed-m-per-min", "200", "--feed-mm-per-rev", "0.35",
                           "--depth-mm", "1.5", "--json", "-"});
  EXPECT_EQ(r.exit_code, 3) << r.err;  // diametral error and roughness fail
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"removal_rate_mm3_per_s", "diametral_error_um", "surface_roughness_um", "cost",
                          "production_rate_per_h", "loss", "loss_terms", "alpha", "constraints", "stability_margin"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const std::string& name : kIndexNames) {
    EXPECT_TRUE(j["loss_terms"].contains(name)) << name;
    EXPECT_TRUE(j["alpha"].contains(name)) << name;
  }
  EXPECT_NEAR(j["removal_rate_mm3_per_s"].get<double>(), 1750.0, 1e-9);
  EXPECT_NEAR(j["alpha"]["removal_rate_mm3_per_s"].get<double>(), 1236.0, 1e-9);
  for (const auto& c : j["constraints"]) {
    for (const char* key : {"name", "value", "limit", "ok"}) EXPECT_TRUE(c.contains(key)) << key;
    const std::string name = c["name"];
    EXPECT_EQ(c["ok"].get<bool>(), name != "max_diametral_error_um" && name != "max_roughness_um") << name;
  }
  EXPECT_GT(j["stability_margin"].get<double>(), 1.25);
  EXPECT_TRUE(contains(r.err, "FAILS max_roughness_um")) << r.err;
  EXPECT_FALSE(contains(r.err, "outside the [optimization] bounds")) << r.err;
}

TEST_F(CliOptimize, PerformanceOutsideTheBoundsSaysSo) {
  // Issue 44: --feed-mm-per-rev 35 against bounds 0.05-0.5 gave no warning.
  const RunResult r = run({"performance", kSeed, "--cutting-speed-m-per-min", "200", "--feed-mm-per-rev", "35",
                           "--depth-mm", "1.5", "--json", "-"});
  const std::string w = "feed 35 mm/rev is outside the [optimization] bounds 0.05-0.5 mm/rev: a unit slip?";
  EXPECT_TRUE(contains(r.err, "warning: " + w)) << r.err;
  EXPECT_TRUE(contains(nlohmann::json::parse(r.out)["warnings"].dump(), w)) << r.out;
  const RunResult near = run({"performance", kSeed, "--cutting-speed-m-per-min", "200", "--feed-mm-per-rev", "0.6",
                              "--depth-mm", "1.5"});
  EXPECT_TRUE(contains(near.err, "feed 0.6 mm/rev is outside the [optimization] bounds 0.05-0.5 mm/rev: the models "
                                 "extrapolate")) << near.err;
}

// Table 14 of the source study from its printed indices (docs/optimization.md).
TEST_F(CliOptimize, Table14FromIndexValues) {
  const RunResult initial = run({"performance", kSeed, "--cutting-speed-m-per-min", "200", "--feed-mm-per-rev",
                                 "0.35", "--depth-mm", "1.5", "--index", "diametral_error_um=55.83", "--index",
                                 "surface_roughness_um=6.40", "--index", "removal_rate_mm3_per_s=1750", "--index",
                                 "cost=0.80", "--index", "production_rate_per_h=75.68", "--json", "-"});
  EXPECT_EQ(initial.exit_code, 3) << initial.err;
  const auto a = nlohmann::json::parse(initial.out);
  EXPECT_NEAR(a["loss"].get<double>(), 16.01, 0.02);
  EXPECT_EQ(a["measured"].size(), 5u);
  const RunResult optimum = run({"performance", kSeed, "--cutting-speed-m-per-min", "287", "--feed-mm-per-rev",
                                 "0.089", "--depth-mm", "1.5", "--index", "diametral_error_um=22.12", "--index",
                                 "surface_roughness_um=2.37", "--index", "removal_rate_mm3_per_s=641", "--index",
                                 "cost=0.98", "--index", "production_rate_per_h=63.90", "--json", "-"});
  EXPECT_EQ(optimum.exit_code, 0) << optimum.err;
  const auto b = nlohmann::json::parse(optimum.out);
  EXPECT_NEAR(b["loss"].get<double>(), 7.13, 0.01);
  EXPECT_TRUE(b["feasible"].get<bool>());
}

TEST_F(CliOptimize, OptimizeNamesTheBindingConstraintsAndDrawsTheMap) {
  const RunResult r = run({"optimize", kSeed, "--json", path("o.json").string(), "--plot", path("map.svg").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(path("o.json")));
  EXPECT_TRUE(j["found"].get<bool>());
  EXPECT_EQ(j["format"], "chatter-optimize");
  EXPECT_TRUE(j["optimum"]["feasible"].get<bool>());
  EXPECT_LT(j["optimum"]["loss"].get<double>(), 7.13);  // below the source study's optimum
  EXPECT_TRUE(j["binding"].is_array());
  EXPECT_TRUE(contains(r.out, "binding:")) << r.out;
  EXPECT_TRUE(fs::exists(path("map.gp")));
  EXPECT_TRUE(fs::exists(path("map.svg")) || contains(r.err, "gnuplot"));
  // The depth free and the removal rate maximised: the lobes bind.
  const RunResult s = run({"optimize", edited("objective = \"loss\"", "objective = \"removal_rate\""), "--depth-mm",
                           "0.5,5", "--json", "-"});
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto k = nlohmann::json::parse(s.out);
  const auto& binding = k["binding"];
  EXPECT_NE(std::find(binding.begin(), binding.end(), "stability_margin"), binding.end()) << binding.dump();
  EXPECT_NEAR(k["optimum"]["stability_margin"].get<double>(), 1.25, 2e-3);
}

TEST_F(CliOptimize, NoFeasiblePointExits3) {
  const RunResult r = run({"optimize", edited("max_force_n = 4000", "max_force_n = 1")});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(contains(r.out, "no set-point meets every constraint")) << r.out;
}

TEST_F(CliOptimize, AdaptWritesOneRowPerIterationAndConverges) {
  const RunResult r = run({"adapt", kSeed, "--iterations", "20", "--start", "200,0.35", "--bias", "all=5@12",
                           "--table", path("loop.csv").string(), "--json", path("loop.json").string(), "--plot",
                           path("loop.svg").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream csv(slurp(path("loop.csv")));
  std::string header;
  std::getline(csv, header);
  for (const char* col : {"iteration", "cutting_speed_m_per_min", "feed_mm_per_rev", "loss", "diametral_error_um",
                          "surface_roughness_um", "removal_rate_mm3_per_s", "cost", "production_rate_per_h",
                          "feasible"})
    EXPECT_TRUE(contains(header, col)) << col;
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 20);
  const auto j = nlohmann::json::parse(slurp(path("loop.json")));
  EXPECT_EQ(j["rows"].size(), 20u);
  EXPECT_EQ(j["biases"][0]["from_iteration"], 12);
  EXPECT_TRUE(j["final_state"]["converged"].get<bool>());
  EXPECT_NEAR(j["final_state"]["correction"]["cost"].get<double>(), 1.05, 1e-9);
  EXPECT_TRUE(fs::exists(path("loop.gp")));
  EXPECT_TRUE(contains(r.out, "converged")) << r.out;
}

TEST_F(CliOptimize, AdaptFromAMeasurementsFile) {
  std::ofstream(path("m.csv")) << "iteration,diametral_error_um,surface_roughness_um\n1,50,6.0\n2,,3.0\n";
  const RunResult r = run({"adapt", kSeed, "--iterations", "5", "--measurements", path("m.csv").string(), "--json",
                           "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["rows"].size(), 2u);  // the rows run out
  EXPECT_NEAR(j["rows"][0]["diametral_error_um"].get<double>(), 50.0, 1e-12);
}

// Bad input: exit 2, the file, the key or flag, and the rule.
TEST_F(CliOptimize, BadInputNamesFileKeyAndRule) {
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> said;
  };
  const std::string weights = edited("production_rate_per_h = 20 }", "production_rate_per_h = 25 }", "w.toml");
  const std::string sense = edited("max_roughness_um = 3.6", "max_roughness_um = -3.6", "r.toml");
  const std::string feed = edited("feed_mm_per_rev = [0.05, 0.5]", "feed_per_tooth_mm = [0.05, 0.5]", "f.toml");
  const std::string gamma = edited("gamma = 0.95", "gamma = 1.5", "g.toml");
  const std::string taylor = edited("taylor_n = 0.25", "taylor_n = 1.25", "t.toml");
  const std::string bounds = edited("cutting_speed_m_per_min = [50, 350]", "cutting_speed_m_per_min = [350, 50]",
                                    "b.toml");
  const std::vector<Case> cases = {
      {{"optimize", weights}, {"w.toml", "optimization.loss.weights_percent", "must sum to 100"}},
      {{"optimize", sense}, {"r.toml", "optimization.constraints.max_roughness_um", "> 0"}},
      {{"optimize", feed}, {"f.toml", "feed_per_tooth_mm", "feed_mm_per_rev"}},
      {{"adapt", gamma, "--iterations", "3"}, {"g.toml", "optimization.adapt.gamma"}},
      {{"optimize", taylor}, {"t.toml", "optimization.economics.taylor_n"}},
      {{"optimize", bounds}, {"b.toml", "optimization.cutting_speed_m_per_min", "lower <= upper"}},
      {{"optimize", kPlain}, {"seed_turning_1dof.toml", "no [optimization]"}},
      {{"performance", kSeed, "--cutting-speed-m-per-min", "200", "--feed-mm-per-rev", "0.35", "--depth-mm", "1.5",
        "--index", "speed=3"},
       {"--index speed=3", "diametral_error_um"}},
      {{"performance", kSeed, "--cutting-speed-m-per-min", "200", "--feed-per-tooth-mm", "0.35", "--depth-mm", "1.5"},
       {"--feed-per-tooth-mm", "turning", "--feed-mm-per-rev"}},
      {{"adapt", kSeed, "--iterations", "3", "--bias", "all=5"}, {"--bias", "INDEX=PERCENT@ITERATION"}},
      {{"adapt", kSeed, "--iterations", "0"}, {"--iterations", "must be in [1"}},
      {{"adapt", kSeed, "--iterations", "3", "--start", "500,0.2"}, {"--start", "outside the optimisation bounds"}},
      {{"optimize", kSeed, "--depth-mm", "3,1"}, {"--depth-mm", "LO <= HI"}},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args[1] << " " << r.err;
    for (const std::string& s : c.said) EXPECT_TRUE(contains(r.err, s)) << s << " in: " << r.err;
  }
}

}  // namespace
