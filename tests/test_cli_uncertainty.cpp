// `chatter lobes --samples` through the binary (docs/uncertainty.md): the
// quantile columns beside the unchanged nominal ones, zero spread = the
// nominal table, the probability table, reproducibility for a seed whatever
// the thread count, JSON record, plot files, and every bad input refused with
// exit 2 and nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace chatter {
namespace {

using test::CliFixture;
using test::contains;
using test::slurp;
namespace fs = std::filesystem;

const std::string kCaseA = std::string(CHATTER_SOURCE_DIR) + "/configs/seed_turning_1dof.toml";

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

class LobesSamples : public CliFixture {
 protected:
  // Case A with an [uncertainty] table appended.
  std::string config(const std::string& uncertainty, const std::string& name = "u.toml") {
    const fs::path p = path(name);
    std::ofstream(p) << slurp(kCaseA) << "\n[uncertainty]\n" << uncertainty << "\n";
    return p.string();
  }
  void expect_refused(const std::vector<std::string>& args, const std::string& message) {
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, message)) << "expected '" << message << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(path("t.csv"))) << "a table was written on bad input";
    EXPECT_FALSE(fs::exists(path("p.csv"))) << "a probability table was written on bad input";
  }
};

TEST_F(LobesSamples, ZeroSpreadQuantilesAreTheNominalColumns) {
  const std::string cfg = config("frequency_percent = 0\ndamping_percent = 0\nfeed_force_coefficient_percent = 0");
  const auto nominal = run({"lobes", cfg, "--rpm-points", "50", "--table", path("n.csv").string()});
  ASSERT_EQ(nominal.exit_code, 0) << nominal.err;
  const auto r = run({"lobes", cfg, "--rpm-points", "50", "--samples", "4", "--table", path("t.csv").string(),
                      "--probability-table", path("p.csv").string(), "--depth-points", "11"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto n = csv_rows(slurp(path("n.csv"))), t = csv_rows(slurp(path("t.csv")));
  ASSERT_EQ(n.size(), t.size());
  ASSERT_EQ(t[0], (std::vector<std::string>{"spindle_rpm", "depth_limit_mm", "chatter_frequency_hz", "lobe",
                                            "depth_limit_p05_mm", "depth_limit_p50_mm", "depth_limit_p95_mm"}));
  for (std::size_t i = 1; i < t.size(); ++i) {
    ASSERT_EQ(t[i].size(), 7u);
    for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(t[i][c], n[i][c]) << "row " << i << ": nominal column changed";
    for (std::size_t c = 4; c < 7; ++c) EXPECT_EQ(t[i][c], n[i][1]) << "row " << i << ": quantile vs nominal";
  }
  // Probabilities exactly 1 below the nominal limit, 0 at or above it.
  const auto p = csv_rows(slurp(path("p.csv")));
  ASSERT_EQ(p[0], (std::vector<std::string>{"spindle_rpm", "depth_mm", "probability_stable"}));
  ASSERT_EQ(p.size(), 1 + 50u * 11u);
  std::size_t ones = 0, zeros = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    const std::size_t row = 1 + (i - 1) / 11;  // the lobe-table row of that speed
    ASSERT_EQ(p[i][0], n[row][0]);
    const double depth = std::stod(p[i][1]), limit = std::stod(n[row][1]);
    const std::string expected = depth < limit ? "1" : "0";
    EXPECT_EQ(p[i][2], expected) << p[i][0] << " rev/min, " << depth << " mm, limit " << limit;
    (expected == "1" ? ones : zeros)++;
  }
  EXPECT_GT(ones, 0u);
  EXPECT_GT(zeros, 0u);
}

TEST_F(LobesSamples, SameSeedSameTableWhateverThreadsOtherSeedDiffers) {
  const std::string cfg =
      config("frequency_percent = 3\ndamping_percent = [20]\nstiffness_percent = 5\nfeed_force_coefficient_percent = 4");
  auto table = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args{"lobes", cfg, "--rpm-points", "60", "--samples", "40", "--table", "-"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.out;
  };
  const std::string one = table({"--threads", "1"}), two = table({"--threads", "2"});
  const std::string seed1 = table({"--threads", "2", "--seed", "1"}), seed2 = table({"--threads", "2", "--seed", "2"});
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, seed1) << "--seed defaults to 1";
  EXPECT_NE(seed1, seed2);
  // The spread moves the quantiles apart at some speed.
  bool apart = false;
  for (const auto& row : csv_rows(one))
    if (row.size() == 7 && row[0] != "spindle_rpm" && row[4] != row[6]) apart = true;
  EXPECT_TRUE(apart);
}

TEST_F(LobesSamples, JsonRecordAndPlot) {
  const std::string cfg = config("frequency_percent = 2\nstiffness_percent = 4");
  const auto r = run({"lobes", cfg, "--rpm-points", "40", "--samples", "30", "--seed", "7", "--json",
                      path("t.json").string(), "--plot", path("u.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "95 % of samples stable below")) << r.out;
  const auto j = nlohmann::json::parse(slurp(path("t.json")));
  EXPECT_EQ(j["uncertainty"]["samples"], 30);
  EXPECT_EQ(j["uncertainty"]["seed"], 7);
  EXPECT_EQ(j["uncertainty"]["spreads"]["frequency_percent"][0], 2.0);
  EXPECT_EQ(j["uncertainty"]["spreads"]["stiffness_percent"][0], 4.0);
  EXPECT_TRUE(j["rows"][0].contains("depth_limit_p95_mm"));
  EXPECT_TRUE(fs::exists(path("u.png")));
  EXPECT_TRUE(contains(slurp(path("u.gp")), "probability of stability"));
  EXPECT_TRUE(contains(slurp(path("u.gp")), "nominal lobe"));
}

TEST_F(LobesSamples, BadInputExitsTwoAndWritesNothing) {
  const std::string good = config("frequency_percent = 3");
  const std::string t = path("t.csv").string(), pt = path("p.csv").string();
  expect_refused({"lobes", good, "--samples", "0", "--table", t}, "--samples = 0: must be >= 1");
  expect_refused({"lobes", good, "--seed", "3", "--table", t}, "--seed: only with --samples");
  expect_refused({"lobes", good, "--probability-table", pt, "--table", t}, "--probability-table: only with --samples");
  expect_refused({"lobes", good, "--samples", "100000000", "--table", t}, "held in memory");
  expect_refused({"lobes", good, "--samples", "5", "--seed=-1", "--table", t}, "--seed = -1");
  expect_refused({"lobes", good, "--samples", "5", "--rpm-spacing", "adaptive", "--table", t},
                 "only with --rpm-spacing even");
  expect_refused({"lobes", kCaseA, "--samples", "5", "--table", t}, "no [uncertainty] table");
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"frequency_percent = -1", "uncertainty.frequency_percent = -1: must be in [0, 33.33)"},
      {"stiffness_percent = 40", "uncertainty.stiffness_percent = 40: must be in [0, 33.33)"},
      {"damping_percent = nan", "uncertainty.damping_percent = nan"},
      {"frequency_percent = [1, 2]", "uncertainty.frequency_percent = [1, 2]: must have one value per mode: 1"},
      {"tangential_coefficient_percent = 5", "uncertainty.tangential_coefficient_percent = 5: only for milling"},
      {"frequncy_percent = 3", "uncertainty.frequncy_percent: unknown key (did you mean frequency_percent?)"},
  };
  {
    // A lightly damped mode made heavy: ζ = 0.5 allows s < (1/ζ − 1)/3 = 33.3 %, ζ = 0.8 only 8.3 %.
    std::string text = slurp(kCaseA);
    text.replace(text.find("damping_ratio = 0.033"), 21, "damping_ratio = 0.8");
    std::ofstream(path("heavy.toml")) << text << "\n[uncertainty]\ndamping_percent = 10\n";
    expect_refused({"lobes", path("heavy.toml").string(), "--samples", "5", "--table", t},
                   "heavy.toml: uncertainty.damping_percent = 10: with damping ratio 0.8 (workpiece mode 0) a 3-sigma "
                   "draw reaches 1.04: must be < 8.33333");
  }
  for (const auto& [text, message] : bad) {
    const std::string cfg = config(text, "bad.toml");
    expect_refused({"lobes", cfg, "--samples", "5", "--table", t, "--probability-table", pt}, "bad.toml: " + message);
  }
}

TEST_F(LobesSamples, WithoutSamplesTheTableIsUnchanged) {
  // An [uncertainty] table alone changes nothing: byte for byte the table of
  // the config without it.
  const auto with = run({"lobes", config("frequency_percent = 5"), "--rpm-points", "30"});
  const auto without = run({"lobes", kCaseA, "--rpm-points", "30"});
  ASSERT_EQ(with.exit_code, 0) << with.err;
  EXPECT_EQ(with.out, without.out);
}

}  // namespace
}  // namespace chatter
