// End-to-end tests of `chatter forced` and `chatter sle` (issue 27,
// docs/forced.md) through the binary: the JSON keys, the exit status of an
// unstable cut (3, naming the limit), the SLE table's columns, the plot
// files, turning along a shaft, and bad input (exit 2, a message naming
// the file, the flag and the rule). Also the simulate keys and warning.
#include <gtest/gtest.h>

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

const std::string kCaseC = std::string(CHATTER_SOURCE_DIR) + "/configs/milling_benchmark_ae005_down.toml";
const std::string kCaseB = std::string(CHATTER_SOURCE_DIR) + "/configs/coupled_tool1_workpiece1.toml";
const std::string kVariable = std::string(CHATTER_SOURCE_DIR) + "/configs/milling_variable_pitch_helix.toml";

class CliForced : public CliFixture {};

TEST_F(CliForced, StableMillingCutPrintsTheDocumentedJsonKeys) {
  const RunResult r = run({"forced", kCaseC, "--rpm", "14000", "--depth-mm", "2", "--feed-per-tooth-mm", "0.05",
                           "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"surface_location_error_um", "peak_to_peak_um", "static_deflection_um",
                          "min_chip_thickness_um", "teeth_leave_cut", "linear_limit_holds", "spectral_radius",
                          "stable", "depth_limit_mm", "negative_chip_arc_deg", "wall_profile", "method"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["stable"].get<bool>());
  EXPECT_LT(j["spectral_radius"].get<double>(), 1.0);
  EXPECT_TRUE(j["peak_to_peak_um"].contains("x") && j["peak_to_peak_um"].contains("y"));
  // Case C's only mode is along the feed: nothing moves the wall (normal y).
  EXPECT_EQ(j["surface_location_error_um"].get<double>(), 0.0);
  EXPECT_GT(j["peak_to_peak_um"]["x"].get<double>(), 1.0);
  EXPECT_FALSE(j.contains("diametral_error_um"));
  EXPECT_TRUE(contains(r.err, "surface location error")) << "the summary goes to stderr with --json -";
}

TEST_F(CliForced, UnstableCutExits3NamingTheLimit) {
  const RunResult r = run({"forced", kCaseC, "--rpm", "20000", "--depth-mm", "3", "--feed-per-tooth-mm", "0.05",
                           "--json", path("f.json").string(), "--plot", path("f.png").string()});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(contains(r.err, "unstable at 20000 rev/min")) << r.err;
  EXPECT_TRUE(contains(r.err, "depth limit at this speed 2.29")) << r.err;
  const auto j = nlohmann::json::parse(slurp(path("f.json")));
  EXPECT_FALSE(j["stable"].get<bool>());
  EXPECT_TRUE(j["surface_location_error_um"].is_null());
  EXPECT_FALSE(fs::exists(path("f.png")));
}

TEST_F(CliForced, PlotAndPathFilesAreWritten) {
  const RunResult r = run({"forced", kVariable, "--rpm", "9000", "--depth-mm", "1", "--plot",
                           path("wall.svg").string(), "--out", path("path.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("wall.gp")));
  EXPECT_TRUE(fs::exists(path("wall.dat")));
  EXPECT_TRUE(fs::exists(path("wall.svg")) || contains(r.err, "gnuplot"));
  std::istringstream csv(slurp(path("path.csv")));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "time_s,rel_x_um,rel_y_um,wall_normal_um");
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_GE(rows, 720);
}

TEST_F(CliForced, SleTableHasTheIssuesColumns) {
  const RunResult r = run({"sle", kCaseC, "--rpm-min", "10000", "--rpm-max", "20000", "--rpm-points", "11",
                           "--depth-mm", "2", "--feed-per-tooth-mm", "0.05", "--threads", "2", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream csv(r.out);
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "spindle_rpm,surface_location_error_um,peak_to_peak_x_um,peak_to_peak_y_um,min_chip_thickness_um,stable");
  int rows = 0, stable = 0, unstable = 0;
  while (std::getline(csv, line)) {
    ++rows;
    if (line.back() == '1') ++stable;
    if (line.back() == '0') {
      ++unstable;
      EXPECT_TRUE(contains(line, ",,,,0")) << line;
    }
  }
  EXPECT_EQ(rows, 11);
  EXPECT_GT(stable, 0);
  EXPECT_GT(unstable, 0) << "2 mm crosses the lobes of case C between 10 000 and 20 000 rev/min";
  // The speeds agree with forced at one of them.
  const RunResult one = run({"forced", kCaseC, "--rpm", "14000", "--depth-mm", "2", "--feed-per-tooth-mm", "0.05",
                             "--json", "-"});
  ASSERT_EQ(one.exit_code, 0);
  const double ppx = nlohmann::json::parse(one.out)["peak_to_peak_um"]["x"].get<double>();
  EXPECT_TRUE(contains(r.out, "14000,0,")) << r.out;
  std::ostringstream want;
  want.precision(10);
  want << ppx;
  EXPECT_TRUE(contains(r.out, "14000,0," + want.str().substr(0, 6))) << r.out << " vs " << ppx;
}

TEST_F(CliForced, TurningAlongTheShaftAndAtAPosition) {
  RunResult r = run({"forced", kCaseB, "--along-shaft", "--depth-mm", "1", "--feed-mm-per-rev", "0.2",
                     "--position-points", "3", "--table", path("shaft.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string table = slurp(path("shaft.csv"));
  EXPECT_TRUE(contains(table, "position_mm,force_n,deflection_x_um,deflection_y_um,diametral_error_um\n")) << table;
  EXPECT_TRUE(contains(table, "\n0,136.8,-6.84,0,13.68\n")) << table;  // at the clamp: the tool alone, 136.8 N / 20 N/um
  r = run({"forced", kCaseB, "--rpm", "1000", "--depth-mm", "1", "--feed-mm-per-rev", "0.2", "--position-mm", "0",
           "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["diametral_error_um"].get<double>(), 13.68, 1e-9);
  EXPECT_EQ(j["operation"], "turning");
  EXPECT_DOUBLE_EQ(j["feed_mm_per_rev"].get<double>(), 0.2);
}

TEST_F(CliForced, BadInputExits2NamingFileFlagAndRule) {
  struct Bad {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Bad> cases = {
      {{"forced", kCaseC, "--rpm", "14000", "--feed-per-tooth-mm", "0.05"}, "depth-mm"},
      {{"forced", kCaseC, "--rpm", "-1", "--depth-mm", "1", "--feed-per-tooth-mm", "0.05"}, "--rpm = -1: must be > 0"},
      {{"forced", kCaseC, "--rpm", "14000", "--depth-mm", "1", "--feed-mm-per-rev", "0.05"},
       "--feed-mm-per-rev: " + kCaseC + " is milling"},
      {{"forced", kCaseC, "--rpm", "14000", "--depth-mm", "1"}, "missing --feed-per-tooth-mm"},
      {{"forced", kCaseC, "--rpm", "14000", "--depth-mm", "1", "--feed-per-tooth-mm", "0"},
       "--feed-per-tooth-mm = 0: must be in (0, 100] mm"},
      {{"forced", kCaseC, "--rpm", "14000", "--depth-mm", "1", "--feed-per-tooth-mm", "0.05", "--radial-immersion",
        "1.5"},
       "--radial-immersion = 1.5: radial immersion a_e/D must be in (0, 1]"},
      {{"forced", kCaseC, "--along-shaft", "--depth-mm", "1", "--feed-per-tooth-mm", "0.05"}, "is milling (turning only)"},
      {{"forced", kCaseB, "--rpm", "1000", "--depth-mm", "1", "--feed-mm-per-rev", "0.2", "--plot", "x.png"},
       "--plot: turning has a constant deflection"},
      {{"forced", kCaseC, "--rpm", "14000", "--depth-mm", "1", "--feed-per-tooth-mm", "0.05", "--plot", "x.txt"},
       "unknown image type"},
      {{"forced", kCaseB, "--along-shaft", "--depth-mm", "1", "--feed-mm-per-rev", "0.2", "--position-max-mm", "900"},
       "--position-max-mm = 900: outside the part"},
      {{"sle", kCaseC, "--rpm-min", "10000", "--rpm-max", "9000", "--depth-mm", "1", "--feed-per-tooth-mm", "0.05"},
       "--rpm-max = 9000: must be > --rpm-min (10000)"},
      {{"forced", "no_such.toml", "--rpm", "1", "--depth-mm", "1"}, "no_such.toml"},
  };
  for (const Bad& b : cases) {
    const RunResult r = run(b.args);
    EXPECT_EQ(r.exit_code, 2) << b.args[0] << " " << b.args.back() << ": " << r.err;
    EXPECT_TRUE(contains(r.err, b.says)) << "want '" << b.says << "' in: " << r.err;
  }
  // A config with a broken key: the file, the key and the rule.
  std::string text = slurp(kCaseC);
  text.replace(text.find("damping_ratio = 0.011"), 21, "damping_ratio = -0.011");
  std::ofstream(path("bad.toml")) << text;
  const RunResult r = run({"forced", path("bad.toml").string(), "--rpm", "14000", "--depth-mm", "1",
                           "--feed-per-tooth-mm", "0.05"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "bad.toml") && contains(r.err, "damping_ratio")) << r.err;
}

TEST_F(CliForced, CheckReportsTheSleAndTheToleranceVerdict) {
  // examples/forced/case_c_xy.toml at 2 mm, 0.05 mm/tooth: SLE 23.95 um at
  // 14 000 rev/min, 75.05 um at 13 800 (docs/forced.md). A 30 um tolerance
  // passes the first, fails the second: exit 3 although every row is stable.
  const std::string cfg = std::string(CHATTER_SOURCE_DIR) + "/examples/forced/case_c_xy.toml";
  std::ofstream(path("ops.csv")) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm,max_sle_um\n"
                                    "fin1,14000,2,,0.05,30\nfin2,13800,2,,0.05,30\nnofeed,14000,1,,,\n"
                                    "badtol,14000,1,,0.05,-3\n";
  const RunResult r = run({"check", cfg, "--operations", path("ops.csv").string(), "--quiet", "--json",
                           path("c.json").string()});
  EXPECT_EQ(r.exit_code, 2) << "a rejected row wins: " << r.out << r.err;
  EXPECT_TRUE(contains(r.out, "max_sle_um = -3: must be > 0 um")) << r.out;
  std::ofstream(path("ops2.csv")) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm,tolerance_um\n"
                                     "fin1,14000,2,,0.05,30\nfin2,13800,2,,0.05,30\nnofeed,14000,1,,,\n";
  const RunResult r2 = run({"check", cfg, "--operations", path("ops2.csv").string(), "--quiet", "--json",
                            path("c2.json").string()});
  EXPECT_EQ(r2.exit_code, 3) << r2.out << r2.err;
  EXPECT_TRUE(contains(r2.out, "sle_um") && contains(r2.out, "leaves_cut") && contains(r2.out, "OUT")) << r2.out;
  EXPECT_TRUE(contains(r2.out, "3 stable, 0 unstable, 0 rejected, 0 not judged, 1 out of tolerance")) << r2.out;
  const auto j = nlohmann::json::parse(slurp(path("c2.json")));
  const auto& ops = j["operations"];
  ASSERT_EQ(ops.size(), 3u);
  EXPECT_NEAR(ops[0]["forced"]["surface_location_error_um"].get<double>(), 23.951, 1e-3);
  EXPECT_TRUE(ops[0]["forced"]["within_tolerance"].get<bool>());
  EXPECT_NEAR(ops[1]["forced"]["surface_location_error_um"].get<double>(), 75.05, 1e-2);
  EXPECT_FALSE(ops[1]["forced"]["within_tolerance"].get<bool>());
  EXPECT_TRUE(ops[2]["forced"].is_null());
  EXPECT_EQ(j["summary"]["out_of_tolerance"], 1);
}

// Case C at 18 250 rev/min: the first limit is 1.15 mm, yet sdm's map is
// stable again at 4.4 mm (spectral radius 0.951; `chatter map`). forced
// reports the SLE there and says the cut sits in an island above the first
// limit (issue 44: it said nothing).
TEST_F(CliForced, AStableIslandAboveTheFirstLimitIsSaid) {
  const RunResult island = run({"forced", kCaseC, "--rpm", "18250", "--depth-mm", "4.4", "--feed-per-tooth-mm", "0.05"});
  ASSERT_EQ(island.exit_code, 0) << island.err;
  EXPECT_TRUE(contains(island.out, "above the first limit: stable only in an island")) << island.out;
  const RunResult below = run({"forced", kCaseC, "--rpm", "18250", "--depth-mm", "1", "--feed-per-tooth-mm", "0.05"});
  ASSERT_EQ(below.exit_code, 0) << below.err;
  EXPECT_FALSE(contains(below.out, "island")) << below.out;
}

TEST_F(CliForced, AnUnstableRowIsUnstableNotOutOfTolerance) {
  // Before: an unstable row with a tolerance was marked "OUT" and counted
  // "out of tolerance"; it has no steady part error to hold (docs/operations.md).
  const std::string cfg = std::string(CHATTER_SOURCE_DIR) + "/examples/forced/case_c_xy.toml";
  std::ofstream(path("ops.csv")) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm,max_sle_um\n"
                                    "fin1,14000,2,,0.05,30\ndeep,14000,20,,0.05,30\n";
  const RunResult r = run({"check", cfg, "--operations", path("ops.csv").string(), "--quiet", "--json",
                           path("c.json").string()});
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_TRUE(contains(r.out, "1 stable, 1 unstable, 0 rejected, 0 not judged, 0 out of tolerance")) << r.out;
  const auto j = nlohmann::json::parse(slurp(path("c.json")));
  const auto& ops = j["operations"];
  ASSERT_EQ(ops.size(), 2u);
  EXPECT_FALSE(ops[1]["stable"].get<bool>());
  EXPECT_TRUE(ops[1]["forced"]["within_tolerance"].is_null()) << ops[1]["forced"];
  EXPECT_TRUE(ops[1]["forced"]["surface_location_error_um"].is_null()) << ops[1]["forced"];
  EXPECT_TRUE(ops[0]["forced"]["within_tolerance"].get<bool>());
  EXPECT_EQ(j["summary"]["out_of_tolerance"], 0);
  // Part quality beside the suggestion: the row's depth and feed at the
  // suggested speed, as `forced` gives them there.
  const auto& s = ops[0]["suggestion"];
  ASSERT_TRUE(s.is_object()) << ops[0];
  std::ostringstream rpm;
  rpm.precision(17);
  rpm << s["spindle_rpm"].get<double>();
  const RunResult f = run({"forced", cfg, "--rpm", rpm.str(), "--depth-mm", "2", "--feed-per-tooth-mm", "0.05",
                           "--json", "-"});
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const auto fj = nlohmann::json::parse(f.out);
  ASSERT_TRUE(fj["stable"].get<bool>());
  const double sle = std::abs(fj["surface_location_error_um"].get<double>());
  EXPECT_NEAR(s["part_error_um"].get<double>(), sle, 1e-9 * sle) << s;
  EXPECT_EQ(s["within_tolerance"].get<bool>(), sle <= 30.0) << s;
  EXPECT_TRUE(contains(r.out, "sugg_sle_um")) << r.out;
}

// Issue 44: a suggested speed never breaks the row's tolerance silently.
// Case C's finishing row: the best-margin speed (25 000 rev/min) leaves
// |SLE| 8.9 um; with a 5 um tolerance the suggestion moves to a stable speed
// whose SLE holds it, checked here by `forced` at both speeds; with 0.01 um
// no speed holds it and the note says so.
TEST_F(CliForced, CheckSuggestionHoldsTheRowsTolerance) {
  const std::string cfg = std::string(CHATTER_SOURCE_DIR) + "/examples/forced/case_c_xy.toml";
  auto check = [&](const std::string& tol) {
    std::ofstream(path("ops.csv")) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm,max_sle_um\n"
                                      "fin1,14000,2,,0.05," << tol << "\n";
    const RunResult r = run({"check", cfg, "--operations", path("ops.csv").string(), "--json", path("c.json").string()});
    EXPECT_NE(r.exit_code, 2) << r.err;
    return std::pair{r.out, nlohmann::json::parse(slurp(path("c.json")))["operations"][0]};
  };
  auto sle_at = [&](double rpm) {
    std::ostringstream n;
    n.precision(17);
    n << rpm;
    const RunResult f = run({"forced", cfg, "--rpm", n.str(), "--depth-mm", "2", "--feed-per-tooth-mm", "0.05",
                             "--json", "-"});
    EXPECT_EQ(f.exit_code, 0) << f.err;
    return std::abs(nlohmann::json::parse(f.out)["surface_location_error_um"].get<double>());
  };
  const auto [loose_out, loose] = check("30");
  const double best = loose["suggestion"]["spindle_rpm"].get<double>();
  EXPECT_TRUE(loose["suggestion"]["note"].is_null());
  const double best_sle = sle_at(best);
  ASSERT_GT(best_sle, 5.0) << "the case no longer tests a broken tolerance";
  const auto [out, op] = check("5");
  const auto& s = op["suggestion"];
  ASSERT_TRUE(s.is_object()) << op;
  const double moved = s["spindle_rpm"].get<double>();
  EXPECT_NE(moved, best);
  EXPECT_TRUE(s["within_tolerance"].get<bool>()) << s;
  EXPECT_GT(s["worst_margin"].is_null() ? 2.0 : s["worst_margin"].get<double>(), 1.0) << s;
  const double sle = sle_at(moved);
  EXPECT_LE(sle, 5.0);
  EXPECT_NEAR(s["part_error_um"].get<double>(), sle, 1e-9 * sle);
  EXPECT_NE(s["note"].get<std::string>().find("moved from " + std::to_string(static_cast<int>(std::round(best))) +
                                              " rev/min (part error"),
            std::string::npos)
      << s["note"];
  EXPECT_TRUE(contains(out, "suggestion for 'fin1': moved from")) << out;
  const auto [tight_out, tight] = check("0.01");
  EXPECT_FALSE(tight["suggestion"]["within_tolerance"].get<bool>());
  EXPECT_NE(tight["suggestion"]["note"].get<std::string>().find("no other stable scanned speed holds it"),
            std::string::npos)
      << tight["suggestion"]["note"];
}

TEST_F(CliForced, SimulateReportsTheForcedVibrationAndWarnsWhenTeethLeaveTheCut) {
  // A variable-pitch helix cutter in a resonant forced vibration below its
  // linear limit (docs/forced.md): the simulation is stable, the teeth leave
  // the cut, simulate says so on stderr and in its JSON.
  const std::string cfg = path("vp.toml").string();
  std::ofstream(cfg) << "[process]\noperation = \"milling\"\nteeth = 4\ntangential_coefficient_n_per_mm2 = 600\n"
                        "radial_coefficient_ratio = 0.3\ntool_diameter_mm = 12\nradial_depth_mm = 6\n"
                        "milling_direction = \"climb\"\nhelix_angle_deg = 30\npitch_angles_deg = [85, 95, 85, 95]\n"
                        "feed_per_tooth_mm = 0.05\n"
                        "[[tool.modes]]\nfrequency_hz = 1150\ndamping_ratio = 0.02\nstiffness_n_per_um = 12\n"
                        "direction = \"x\"\n"
                        "[[tool.modes]]\nfrequency_hz = 1230\ndamping_ratio = 0.02\nstiffness_n_per_um = 14\n"
                        "direction = \"y\"\n";
  const RunResult r = run({"simulate", cfg, "--rpm", "12000", "--depth-mm", "4.2", "--revolutions", "60"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["verdict"], "stable");
  EXPECT_TRUE(j["teeth_leave_cut"].get<bool>());
  EXPECT_EQ(j["out_of_cut_fraction_per_tooth"].size(), 4u);
  EXPECT_GT(j["out_of_cut_fraction"].get<double>(), 0.05) << "slices leave the cut although the tool never does";
  EXPECT_TRUE(j["forced"]["steady"].get<bool>());
  EXPECT_GT(j["forced"]["peak_to_peak_um"]["y"].get<double>(), 20.0);
  EXPECT_TRUE(j["linear_limit_warning"].is_string());
  EXPECT_TRUE(contains(r.err, "warning: the linear stability limit does not hold: forced vibration")) << r.err;
  // compare names the cause of the simulation's deeper limit.
  const RunResult c = run({"compare", cfg, "--methods", "sdm,time-domain", "--rpm-min", "12000", "--rpm-max", "12100",
                           "--rpm-points", "2", "--quiet", "--table", path("c.csv").string()});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_TRUE(contains(c.out, "time-domain is ") && contains(c.out, "% deeper than sdm at 12")) << c.out;
  EXPECT_TRUE(contains(c.out, "the teeth leave the cut (linear chip negative over")) << c.out;
  // forced agrees that the linear model does not hold there.
  const RunResult f = run({"forced", cfg, "--rpm", "12000", "--depth-mm", "4.2", "--json", "-"});
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const auto fj = nlohmann::json::parse(f.out);
  EXPECT_TRUE(fj["teeth_leave_cut"].get<bool>());
  EXPECT_FALSE(fj["linear_limit_holds"].get<bool>());
}

}  // namespace
