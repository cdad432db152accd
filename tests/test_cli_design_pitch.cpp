// `chatter design-pitch` through the binary (docs/design_pitch.md): the
// shipped example's record, table, fragment and plot agree with each other
// (the worst limits are the minima of the table, the gain their ratio), the
// fragment makes a config whose sdm lobes are the table's designed column,
// and bad input exits 2 with a message naming the flag and the rule, writing
// nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/pitch_design.hpp"
#include "chatter/records/pitch.hpp"
#include "cli_harness.hpp"

namespace fs = std::filesystem;

namespace {

using chatter::test::CliFixture;
using chatter::test::contains;
using chatter::test::RunResult;
using chatter::test::slurp;

const std::string kConfigs = std::string(CHATTER_SOURCE_DIR) + "/configs/";
const std::string kExample = kConfigs + "milling_pitch_design_4flute.toml";

// The fragment's angles are printed in degrees (12 digits) and read back by
// the config (degrees -> rad, scaled to sum to exactly 360°): a few ulps of
// the angle, which moves the sdm limit by far less than this.
constexpr double kFragmentRoundTrip = 1e-7;

struct Row {
  double rpm, equal, designed;
};

std::vector<Row> read_table(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "spindle_rpm,depth_limit_equal_mm,depth_limit_designed_mm");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    Row r{};
    char c1 = 0, c2 = 0;
    std::istringstream ls(line);
    ls >> r.rpm >> c1 >> r.equal >> c2 >> r.designed;
    EXPECT_TRUE(ls && c1 == ',' && c2 == ',') << line;
    rows.push_back(r);
  }
  return rows;
}

using CliDesignPitch = CliFixture;

TEST_F(CliDesignPitch, ExampleRecordTableFragmentAndPlotAgree) {
  const RunResult r = run({"design-pitch", kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--teeth", "4",
                           "--rpm-points", "15", "--scan-points", "6", "--table", path("band.csv").string(), "--json",
                           path("d.json").string(), "--out", path("pitch.toml").string(), "--plot",
                           path("pitch.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "designed pitch (linear, sdm)")) << r.out;
  EXPECT_TRUE(contains(r.out, "gain: ")) << r.out;
  const std::string csv = slurp(path("band.csv"));
  EXPECT_FALSE(contains(csv, "nan")) << csv;
  const std::vector<Row> rows = read_table(csv);
  ASSERT_EQ(rows.size(), 15u);
  const auto j = nlohmann::json::parse(slurp(path("d.json")));
  EXPECT_EQ(j["format"], "chatter-pitch-design");
  EXPECT_EQ(j["method"], "sdm");
  double lowest_equal = std::numeric_limits<double>::infinity(), lowest_designed = lowest_equal;
  for (const Row& row : rows) {
    lowest_equal = std::min(lowest_equal, row.equal);
    lowest_designed = std::min(lowest_designed, row.designed);
  }
  // The table prints 10 digits; the record keeps the double.
  const double equal_worst = j["equal"]["worst_limit_mm"].get<double>();
  const double designed_worst = j["designed"]["worst_limit_mm"].get<double>();
  EXPECT_NEAR(equal_worst / lowest_equal, 1.0, 1e-9);
  EXPECT_NEAR(designed_worst / lowest_designed, 1.0, 1e-9);
  // The gain is the ratio of the limits in m; the record gives them in mm
  // (each × 1e3, rounded): the ratio of those agrees to a few ulp.
  EXPECT_DOUBLE_EQ(j["gain"].get<double>(), designed_worst / equal_worst);
  EXPECT_GT(j["gain"].get<double>(), 1.0);
  EXPECT_GE(designed_worst, j["start"]["worst_limit_mm"].get<double>());
  double sum = 0.0;
  for (const auto& a : j["pitch_angles_deg"]) {
    EXPECT_GE(a.get<double>(), 0.5 * 90.0 - 1e-9);
    sum += a.get<double>();
  }
  EXPECT_NEAR(sum, 360.0, 1e-9);
  EXPECT_EQ(j["band"].size(), 15u);
  EXPECT_TRUE(fs::exists(path("pitch.png")) && fs::exists(path("pitch.gp")) && fs::exists(path("pitch.dat")));

  // The fragment in the config: sdm's lobes at the band's speeds are the
  // designed column.
  const std::string fragment = slurp(path("pitch.toml"));
  ASSERT_TRUE(contains(fragment, "pitch_angles_deg = [")) << fragment;
  std::string config = slurp(kExample);
  std::string line;
  std::istringstream fl(fragment);
  while (std::getline(fl, line))
    if (line.rfind("pitch_angles_deg", 0) == 0) break;
  const auto at = config.find("[process]\n");
  ASSERT_NE(at, std::string::npos);
  config.insert(at + 10, line + "\n");
  std::ofstream(path("designed.toml")) << config;
  const RunResult lobes = run({"lobes", path("designed.toml").string(), "--method", "sdm", "--rpm-min", "6600",
                               "--rpm-max", "8000", "--rpm-points", "15", "--table", "-"});
  ASSERT_EQ(lobes.exit_code, 0) << lobes.err;
  std::istringstream lt(lobes.out);
  std::getline(lt, line);  // header
  for (const Row& row : rows) {
    ASSERT_TRUE(std::getline(lt, line));
    std::istringstream ls(line);
    double rpm = 0.0, depth = 0.0;
    char c = 0;
    ls >> rpm >> c >> depth;
    EXPECT_NEAR(rpm, row.rpm, 1e-6 * row.rpm);
    EXPECT_NEAR(depth / row.designed, 1.0, kFragmentRoundTrip) << rpm << " rev/min: lobes " << depth
                                                                << " mm vs design-pitch " << row.designed << " mm";
  }
}

TEST_F(CliDesignPitch, JsonToStandardOutput) {
  const RunResult r = run({"design-pitch", kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--rpm-points", "5",
                           "--scan-points", "2", "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["inputs"]["teeth"], 4);
  EXPECT_TRUE(contains(r.err, "designed pitch")) << r.err;
  // The chip loads and the bound, from the record's own angles and steps.
  double lo = 1e9, hi = 0.0;
  for (const auto& a : j["pitch_angles_deg"]) {
    lo = std::min(lo, a.get<double>());
    hi = std::max(hi, a.get<double>());
  }
  EXPECT_NEAR(j["chip_load_ratio"].get<double>(), hi / lo, 1e-12);
  EXPECT_EQ(j["on_min_pitch_bound"].get<bool>(),
            j["designed"]["step_deg"].get<double>() >= j["step_max_deg"].get<double>() * (1.0 - 1e-9));
  EXPECT_TRUE(contains(r.err, "chip loads: the largest")) << r.err;
}

TEST(PitchRecord, BoundAndChipLoadsOfThreeTeethOnTheBound) {
  // design-pitch --teeth 3 at the 0.5 x bound (issue 44): 60/120/180 deg,
  // the smallest pitch half the equal 120 deg, chip loads 3:1; the fragment
  // prints 60, not 59.999999999999993.
  chatter::PitchDesign d;
  const double deg = std::numbers::pi / 180.0;
  d.designed.angles_rad = {(180.0 / 3.0) * deg * (1.0 - 1e-16), 120.0 * deg, 180.0 * deg};
  d.step_max_rad = 60.0 * deg;
  d.designed.step_rad = 60.0 * deg;
  d.speeds_rpm = {1000.0, 2000.0};
  EXPECT_TRUE(chatter::on_min_pitch_bound(d));
  EXPECT_NEAR(chatter::chip_load_ratio(d), 3.0, 1e-12);
  const std::string summary = chatter::pitch_design_summary(d);
  EXPECT_TRUE(contains(summary, "on the bound: the smallest pitch is 60 deg")) << summary;
  EXPECT_TRUE(contains(summary, "chip loads: the largest 3 x the smallest")) << summary;
  const std::string fragment = chatter::pitch_design_fragment(d, "x");
  EXPECT_TRUE(contains(fragment, "pitch_angles_deg = [60, 120, 180]")) << fragment;
  d.designed.step_rad = 30.0 * deg;
  EXPECT_FALSE(chatter::on_min_pitch_bound(d));
}

struct BadCase {
  std::vector<std::string> args;
  std::string message;  // a piece of the message on stderr
};

TEST_F(CliDesignPitch, BadInputExitsTwoNamingTheFlagAndWritesNothing) {
  const std::string table = path("t.csv").string();
  const std::vector<BadCase> cases = {
      {{kExample, "--rpm-min", "8000", "--rpm-max", "6600"}, "--rpm-max = 6600: must be > --rpm-min = 8000"},
      {{kExample, "--rpm-min", "7000", "--rpm-max", "7000"}, "the band is empty or inverted"},
      {{kExample, "--rpm-max", "7000"}, "--rpm-min: required"},
      {{kExample, "--rpm-min", "-5", "--rpm-max", "7000"}, "--rpm-min = -5: must be > 0"},
      {{kExample, "--rpm-min", "6000", "--rpm-max", "9e6"}, "--rpm-max = 9e+06"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--teeth", "1"}, "--teeth = 1: must be >= 2"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--teeth", "3"}, "--teeth = 3: the config's cutter has 4"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--depth-max-mm", "0"}, "--depth-max-mm = 0"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--depth-max-mm", "0.01"},
       "--depth-max-mm = 0.01 mm: the equal-pitch cutter has no limit below it"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--family", "spiral"}, "--family = 'spiral'"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--min-pitch-ratio", "1"}, "--min-pitch-ratio = 1"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--rpm-points", "1"}, "--rpm-points = 1"},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--method", "time-domain"}, "--method: method \"time-domain\""},
      {{kExample, "--rpm-min", "6600", "--rpm-max", "8000", "--method", "coupled"}, "does not handle variable pitch"},
      {{kConfigs + "seed_turning_1dof.toml", "--rpm-min", "600", "--rpm-max", "800"}, "process.operation = \"turning\""},
      {{kConfigs + "milling_variable_pitch_helix.toml", "--rpm-min", "6600", "--rpm-max", "8000"},
       "process.pitch_angles_deg: the cutter already has unequal pitch"},
  };
  for (const BadCase& c : cases) {
    std::vector<std::string> args = {"design-pitch"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"--table", table});
    const RunResult r = run(args);
    std::string shown;
    for (const auto& a : c.args) shown += a + " ";
    EXPECT_EQ(r.exit_code, 2) << shown << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.message)) << shown << "\nexpected: " << c.message << "\ngot: " << r.err;
    EXPECT_FALSE(contains(r.err, "nan")) << r.err;
    EXPECT_FALSE(fs::exists(table)) << shown;
  }
}

}  // namespace
