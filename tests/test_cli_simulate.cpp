// End-to-end tests of the time-domain solver through the binary:
// `chatter simulate` (JSON keys, verdicts either side of the sdm limit, the
// CSV files, linear growth vs sdm), `point` and `lobes` with
// --method time-domain, and bad input (exit 2, a message naming the option,
// nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/io/config.hpp"
#include "chatter/semi_discretization.hpp"

#include "cli_harness.hpp"

namespace fs = std::filesystem;

namespace {

using chatter::test::CliFixture;
using chatter::test::contains;
using chatter::test::RunResult;
using chatter::test::shell_quote;
using chatter::test::slurp;

const std::string kCaseC = std::string(CHATTER_SOURCE_DIR) + "/configs/milling_benchmark_ae005_down.toml";
const std::string kCaseA = std::string(CHATTER_SOURCE_DIR) + "/configs/seed_turning_1dof.toml";

class CliSimulate : public CliFixture {};

double sdm_limit_mm(const std::string& config, double rpm) {
  const chatter::Config cfg = chatter::load_config(config);
  return chatter::SemiDiscretizationSolver(cfg.model, cfg.process).limit_at(chatter::SpindleSpeed(rpm)).depth_limit_m * 1e3;
}

TEST_F(CliSimulate, VerdictsEitherSideOfTheSdmLimitWithTheDocumentedKeys) {
  const double lim = sdm_limit_mm(kCaseC, 20000);
  for (double factor : {0.9, 1.1}) {
    const RunResult r = run({"simulate", kCaseC, "--rpm", "20000", "--depth-mm", std::to_string(factor * lim)});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"verdict", "stable", "verdict_measure", "growth_per_period", "chatter_frequency_hz",
                            "max_amplitude_mm", "out_of_cut_fraction", "harmonics", "integrator", "periods"})
      EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["verdict"], factor < 1 ? "stable" : "chatter") << j["verdict_measure"];
    EXPECT_EQ(j["periods"], 200);
    if (factor > 1) {
      EXPECT_NEAR(j["chatter_frequency_hz"].get<double>(), 901.6, 15.0);
    } else {
      EXPECT_TRUE(j["chatter_frequency_hz"].is_null());
    }
    EXPECT_GT(j["max_amplitude_mm"].get<double>(), 0.0);
  }
}

TEST_F(CliSimulate, WritesSeriesPeriodicSamplesAndSpectrum) {
  const RunResult r = run({"simulate", kCaseA, "--rpm", "3000", "--depth-mm", "1", "--revolutions", "30", "--out",
                           path("series.csv").string(), "--periodic", path("periodic.csv").string(), "--spectrum",
                           path("spectrum.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["periods"], 30);
  EXPECT_EQ(j["verdict"], "stable");
  std::istringstream series(slurp(path("series.csv")));
  std::string line;
  std::getline(series, line);
  EXPECT_EQ(line, "time_s,tool_x_um,tool_y_um,workpiece_x_um,workpiece_y_um,rel_x_um,rel_y_um,force_x_n,force_y_n,"
                  "chip_um,in_cut");
  int rows = 0;
  double last_t = -1;
  while (std::getline(series, line)) {
    ++rows;
    const double t = std::stod(line.substr(0, line.find(',')));
    EXPECT_GT(t, last_t);
    last_t = t;
    EXPECT_FALSE(contains(line, "nan"));
  }
  EXPECT_EQ(rows, 30 * j["integrator"]["samples_per_period"].get<int>() + 1);
  EXPECT_NEAR(last_t, 30 * 60.0 / 3000, 1e-9);
  // Once per revolution: 31 samples (t = 0 … 30 τ).
  std::istringstream periodic(slurp(path("periodic.csv")));
  rows = -1;
  while (std::getline(periodic, line)) ++rows;
  EXPECT_EQ(rows, 31);
  EXPECT_TRUE(contains(slurp(path("spectrum.csv")), "frequency_hz,amplitude_um,harmonic\n"));
}

TEST_F(CliSimulate, PlotWritesImageScriptAndData) {
  if (std::system("gnuplot --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  const RunResult r = run({"simulate", kCaseC, "--rpm", "17000", "--depth-mm", "3.6", "--periods", "40", "--plot",
                           path("sim.svg").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["plot"], path("sim.svg").string());
  const std::string svg = slurp(path("sim.svg"));
  EXPECT_TRUE(contains(svg, "<svg")) << svg.substr(0, 200);
  EXPECT_TRUE(contains(svg, "17000 rev/min"));
  EXPECT_TRUE(fs::exists(path("sim.gp")));
  EXPECT_TRUE(fs::exists(path("sim.dat")));
}

TEST_F(CliSimulate, LinearGrowthMatchesSdm) {
  const RunResult r = run({"simulate", kCaseC, "--rpm", "17000", "--depth-mm", "3.6", "--linear", "--periods", "120"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const chatter::Config cfg = chatter::load_config(kCaseC);
  const double rho = chatter::SemiDiscretizationSolver(cfg.model, cfg.process).analyse(17000, 3.6e-3).spectral_radius;
  EXPECT_NEAR(j["growth_per_period"].get<double>() / rho, 1.0, 5e-3);
  EXPECT_EQ(j["verdict"], "chatter");
  EXPECT_TRUE(j["feed_per_tooth_mm"].is_null());
}

TEST_F(CliSimulate, PointAndLobesWithTimeDomain) {
  RunResult r = run({"point", kCaseC, "--method", "time-domain", "--rpm", "20000", "--depth-mm", "2.5"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "time-domain");
  EXPECT_EQ(j["stable"], false);
  EXPECT_NEAR(j["depth_limit_mm"].get<double>(), 2.2987, 0.05);
  EXPECT_TRUE(j.contains("verdict_measure"));

  r = run({"lobes", kCaseA, "--method", "time-domain", "--rpm-min", "2500", "--rpm-max", "3000", "--rpm-points", "2",
           "--table", path("lobes.csv").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream t(slurp(path("lobes.csv")));
  std::string line;
  std::getline(t, line);
  EXPECT_TRUE(contains(line, "spindle_rpm,depth_limit_mm"));
  int rows = 0;
  while (std::getline(t, line)) {
    ++rows;
    const std::string depth = line.substr(line.find(',') + 1);
    EXPECT_GT(std::stod(depth), 1.0) << line;  // case A: above the 1.28 mm absolute limit
  }
  EXPECT_EQ(rows, 2);
}

TEST_F(CliSimulate, BadInputExitsTwoNamingTheOption) {
  struct Bad {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Bad> cases = {
      {{"simulate", kCaseC, "--rpm", "0", "--depth-mm", "1"}, "--rpm"},
      {{"simulate", kCaseC, "--rpm", "10000", "--depth-mm", "-1"}, "--depth-mm"},
      {{"simulate", kCaseC, "--rpm", "10000", "--depth-mm", "1", "--revolutions", "5", "--periods", "10"},
       "--revolutions"},
      {{"simulate", kCaseC, "--rpm", "10000", "--depth-mm", "1", "--periods", "2"}, "--periods"},
      {{"simulate", kCaseC, "--rpm", "10000", "--depth-mm", "1", "--rtol", "1"}, "--rtol"},
      {{"simulate", kCaseC, "--rpm", "10000", "--depth-mm", "1", "--feed-per-tooth-mm", "-0.1"},
       "--feed-per-tooth-mm"},
      {{"simulate", kCaseC, "--rpm", "10000", "--depth-mm", "1", "--plot", "x.bmp"}, "x.bmp"},
      {{"simulate", "/nonexistent/case.toml", "--rpm", "10000", "--depth-mm", "1"}, "/nonexistent/case.toml"},
      {{"simulate", kCaseC, "--depth-mm", "1"}, "rpm"},
      {{"lobes", kCaseC, "--method", "analytic", "--periods", "50"}, "--periods"},
      {{"simulate", kCaseC, "--rpm", "0.001", "--depth-mm", "1"}, "samples per delay"},
  };
  for (const Bad& b : cases) {
    const RunResult r = run(b.args);
    EXPECT_EQ(r.exit_code, 2) << b.says << ": " << r.err;
    EXPECT_TRUE(contains(r.err, b.says)) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_FALSE(fs::exists("x.bmp"));
}

// [process] feed_per_tooth_mm in the config is the static chip of every
// time-domain run (simulate, and lobes/point through build_solver) unless
// --feed-per-tooth-mm overrides it; the JSON outputs record which one was used.
TEST_F(CliSimulate, FeedFromTheConfigUnlessTheFlagOverridesIt) {
  std::string text = slurp(kCaseC);
  const std::string op = "operation = \"milling\"\n";
  ASSERT_NE(text.find(op), std::string::npos);
  text.insert(text.find(op) + op.size(), "feed_per_tooth_mm = 0.05\n");
  const fs::path cfg = path("feed.toml");
  std::ofstream(cfg) << text;

  RunResult r = run({"simulate", cfg.string(), "--rpm", "20000", "--depth-mm", "0.5", "--revolutions", "40"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(r.out)["feed_per_tooth_mm"].get<double>(), 0.05);
  r = run({"simulate", cfg.string(), "--rpm", "20000", "--depth-mm", "0.5", "--revolutions", "40",
           "--feed-per-tooth-mm", "0.2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(r.out)["feed_per_tooth_mm"].get<double>(), 0.2);

  for (const auto& [extra, feed_m] : std::vector<std::pair<std::vector<std::string>, double>>{
           {{}, 5e-5}, {{"--feed-per-tooth-mm", "0.2"}, 2e-4}}) {
    std::vector<std::string> args = {"lobes", cfg.string(), "--method", "time-domain", "--rpm-min", "20000",
                                     "--rpm-max", "20100", "--rpm-points", "2", "--periods", "40", "-q",
                                     "--json", path("lobes.json").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    r = run(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string json = slurp(path("lobes.json"));
    ASSERT_TRUE(contains(json, "\"feed_m\"")) << json.substr(0, 400);
    const auto pos = json.find("\"feed_m\"");
    EXPECT_DOUBLE_EQ(std::stod(json.substr(json.find(':', pos) + 1)), feed_m);
  }
}

}  // namespace

namespace {

// The "no cut" rule (docs/results.md) at the command line: a cut with no
// chip is refused with the reason, never judged.
class CliNoCut : public CliFixture {
 protected:
  // A 16 mm, 3-flute bull nose (2 mm corner) on 0.5 mm of radial depth: at
  // 0.5 mm deep the corner reaches 7.32 mm from the axis, the band starts at
  // 7.5 mm (tests/test_cutter_profile.cpp, NoChipWhereTheCornerMissesTheBand).
  std::string bull_nose() {
    const fs::path p = path("bull.toml");
    std::ofstream(p) << "name = \"bull nose\"\n[process]\noperation = \"milling\"\nteeth = 3\n"
                        "tangential_coefficient_n_per_mm2 = 700\nradial_coefficient_ratio = 0.3\n"
                        "cutter_geometry = \"bull_nose\"\ncorner_radius_mm = 2\ntool_diameter_mm = 16\n"
                        "radial_depth_mm = 0.5\nmilling_direction = \"climb\"\n"
                        "[[tool.modes]]\nfrequency_hz = 600\ndamping_ratio = 0.03\nstiffness_n_per_um = 8\n"
                        "direction = \"x\"\n[[tool.modes]]\nfrequency_hz = 620\ndamping_ratio = 0.03\n"
                        "stiffness_n_per_um = 8\ndirection = \"y\"\n";
    return p.string();
  }
};

TEST_F(CliNoCut, NonlinearSimulationAtFeedZeroIsRefused) {
  // Before: exit 0, verdict "chatter" (growth 1.096) at feed 0, "stable" at 1e-9 mm.
  const RunResult r = run({"simulate", kCaseC, "--rpm", "18000", "--depth-mm", "1.5", "--feed-per-tooth-mm", "0"});
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.err, "no static chip")) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  // The linear question needs no feed.
  EXPECT_EQ(run({"simulate", kCaseC, "--rpm", "18000", "--depth-mm", "0.2", "--feed-per-tooth-mm", "0", "--linear"})
                .exit_code,
            0);
  // point by simulation at feed 0: refused (before: depth_limit_mm 0.0).
  const RunResult p = run({"point", kCaseC, "--rpm", "18000", "--depth-mm", "1.5", "--method", "time-domain",
                           "--feed-per-tooth-mm", "0"});
  EXPECT_NE(p.exit_code, 0) << p.out;
  EXPECT_TRUE(contains(p.err, "no static chip")) << p.err;
}

TEST_F(CliNoCut, BullNoseThatMissesTheBandIsNotJudged) {
  const std::string cfg = bull_nose();
  // Before: point said stable, margin 22.3.
  for (const char* method : {"sdm", "analytic"}) {
    const RunResult r = run({"point", cfg, "--rpm", "12000", "--depth-mm", "0.5", "--method", method});
    EXPECT_NE(r.exit_code, 0) << method << ": " << r.out;
    EXPECT_TRUE(contains(r.err, "no edge engages")) << r.err;
    EXPECT_TRUE(contains(r.err, "7.5 mm")) << r.err;
  }
  const RunResult sim = run({"simulate", cfg, "--rpm", "12000", "--depth-mm", "0.5", "--feed-per-tooth-mm", "0.05"});
  EXPECT_NE(sim.exit_code, 0) << sim.out;
  EXPECT_TRUE(contains(sim.err, "no edge engages")) << sim.err;
  // 1 mm deep the corner reaches the band: judged.
  EXPECT_EQ(run({"point", cfg, "--rpm", "12000", "--depth-mm", "1", "--method", "sdm"}).exit_code, 0);
  // check: the shallow row is not judged, with the reason; the deep one is.
  const fs::path ops = path("ops.csv");
  std::ofstream(ops) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\nshallow,12000,0.5,,0.05\ndeep,12000,1,,0.05\n";
  const RunResult c = run({"check", cfg, "--operations", ops.string(), "--json", "-", "--rpm-min", "5000", "--rpm-max", "20000"});
  const auto j = nlohmann::json::parse(c.out);
  ASSERT_EQ(j["not_judged"].size(), 1u) << c.out;
  EXPECT_EQ(j["not_judged"][0]["id"], "shallow");
  EXPECT_TRUE(contains(j["not_judged"][0]["reason"].get<std::string>(), "no edge engages")) << c.out;
}

TEST_F(CliNoCut, ImplausibleDepthsNameTheUnitSlip) {
  // Before: 0.0015 mm gave margin 1286 with no word; 150 mm passed silently.
  for (const auto& [depth, slip] : {std::pair{"0.0015", "a depth in m?"}, std::pair{"150", "a depth in um?"}}) {
    const RunResult r = run({"point", kCaseC, "--rpm", "18000", "--depth-mm", depth, "--method", "analytic"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(contains(j["notes"].dump(), slip)) << depth << ": " << j["notes"];
  }
  const RunResult ok = run({"point", kCaseC, "--rpm", "18000", "--depth-mm", "1.5", "--method", "analytic"});
  EXPECT_FALSE(contains(nlohmann::json::parse(ok.out)["notes"].dump(), "a depth in")) << ok.out;
  EXPECT_FALSE(contains(ok.err, "outside the config's speed range")) << ok.err;
  // A speed outside the config's range (the machine's, for check) is said.
  const chatter::Config cfg = chatter::load_config(kCaseC);
  ASSERT_TRUE(cfg.sweep.rpm_min.has_value());
  const std::string slow = std::to_string(static_cast<int>(*cfg.sweep.rpm_min / 2));
  const RunResult low = run({"point", kCaseC, "--rpm", slow, "--depth-mm", "0.5", "--method", "analytic"});
  ASSERT_EQ(low.exit_code, 0) << low.err;
  EXPECT_TRUE(contains(low.err, "note: --rpm " + slow + ": outside the config's speed range")) << low.err;
  EXPECT_TRUE(contains(nlohmann::json::parse(low.out)["notes"].dump(), "outside the config's speed range")) << low.out;
  const fs::path ops = path("ops.csv");
  std::ofstream(ops) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\nthin,18000,0.0015,,0.05\n";
  const RunResult c = run({"check", kCaseC, "--operations", ops.string(), "--json", "-", "--method", "analytic"});
  EXPECT_TRUE(contains(nlohmann::json::parse(c.out)["warnings"].dump(), "operation 'thin' (line 2): depth 0.0015 mm"))
      << c.out;
}

}  // namespace
