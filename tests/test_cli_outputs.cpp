// What the CLI writes, through the binary (issue 17 item 4): the lobe and
// comparison plots' depth axis shows every finite limit, the table reaches
// the terminal only when asked, output paths are checked before computing,
// and bad input gets a hint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_harness.hpp"

namespace {

using chatter::test::contains;
using chatter::test::slurp;

const std::string kSource = CHATTER_SOURCE_DIR;
const std::string kCaseC = kSource + "/configs/milling_benchmark_ae005_down.toml";
const std::string kTurning = kSource + "/configs/seed_turning_1dof.toml";
const std::string kHalfImmersion = kSource + "/configs/milling_up_ae05_2dof.toml";

class OutputsCli : public chatter::test::CliFixture {
 protected:
  // The value of `y_max = ...` in a plot script (NaN if absent).
  static double script_y_max(const std::string& gp) {
    const std::size_t at = gp.find("\ny_max = ");
    if (at == std::string::npos) return NAN;
    return std::stod(gp.substr(at + 9));
  }
  // The lines of a text, the empty last one dropped.
  static std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
  }
  // The largest finite value of column `col` of a CSV with a header.
  static double largest_finite(const std::string& csv, std::size_t col) {
    double best = -1.0;
    const auto rows = lines(csv);
    for (std::size_t i = 1; i < rows.size(); ++i) {
      std::istringstream cells(rows[i]);
      std::string cell;
      for (std::size_t c = 0; c <= col && std::getline(cells, cell, ','); ++c) {}
      if (cell.empty() || cell == "inf") continue;
      best = std::max(best, std::stod(cell));
    }
    return best;
  }
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    for (const auto& e : chatter::test::fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    return out;
  }
};

// ---------------------------------------------------------------------------
// 1. The depth axis of a lobe plot shows the deepest stable pocket.

TEST_F(OutputsCli, LobePlotDepthAxisShowsTheDeepestFiniteLimit) {
  // Case C with sdm searched to 30 mm: flip/Hopf pockets reach ~15 mm, far
  // above the median limit the old axis followed.
  const auto r = run({"lobes", kCaseC, "--method", "sdm", "--depth-max-mm", "30", "--quiet", "--table",
                      path("c.csv").string(), "--plot", path("c.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double deepest = largest_finite(slurp(path("c.csv")), 1);
  ASSERT_GT(deepest, 0.0);
  const double y_max = script_y_max(slurp(path("c.gp")));
  EXPECT_GE(y_max, deepest) << "deepest finite limit " << deepest << " mm above the axis top " << y_max << " mm";
  EXPECT_LE(y_max, 30.0) << "axis top " << y_max << " mm above --depth-max-mm 30";
}

TEST_F(OutputsCli, PlotDepthMaxSetsTheAxisAndIsChecked) {
  const auto r = run({"lobes", kTurning, "--rpm-points", "50", "--quiet", "--table", path("t.csv").string(),
                      "--plot", path("t.png").string(), "--plot-depth-max-mm", "3.5"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(script_y_max(slurp(path("t.gp"))), 3.5);

  for (const char* bad : {"0", "-2", "nan"}) {
    const auto b = run({"lobes", kTurning, "--rpm-points", "50", "--table", path("b.csv").string(), "--plot",
                        path("b.png").string(), "--plot-depth-max-mm", bad});
    EXPECT_EQ(b.exit_code, 2) << bad << ": " << b.err;
    EXPECT_TRUE(contains(b.err, "--plot-depth-max-mm")) << b.err;
    EXPECT_FALSE(chatter::test::fs::exists(path("b.csv")));
    EXPECT_FALSE(chatter::test::fs::exists(path("b.gp")));
  }
  const auto no_plot = run({"lobes", kTurning, "--rpm-points", "50", "--plot-depth-max-mm", "3"});
  EXPECT_EQ(no_plot.exit_code, 2);
  EXPECT_TRUE(contains(no_plot.err, "only with --plot")) << no_plot.err;
}

TEST_F(OutputsCli, ComparePlotDepthAxis) {
  const auto r = run({"compare", kCaseC, "--depth-max-mm", "30", "--rpm-points", "60", "--quiet", "--table",
                      path("c.csv").string(), "--plot", path("c.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = slurp(path("c.csv"));
  double deepest = 0.0;
  for (std::size_t col = 1; col <= 3; ++col) deepest = std::max(deepest, largest_finite(csv, col));
  const double y_max = script_y_max(slurp(path("c.gp")));
  EXPECT_GE(y_max, deepest) << "deepest finite limit " << deepest << " mm above the axis top " << y_max << " mm";
  EXPECT_LE(y_max, 30.0);

  const auto f = run({"compare", kCaseC, "--rpm-points", "20", "--quiet", "--table", path("f.csv").string(),
                      "--plot", path("f.png").string(), "--plot-depth-max-mm", "7"});
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_EQ(script_y_max(slurp(path("f.gp"))), 7.0);
}

// ---------------------------------------------------------------------------
// 2. The table reaches the terminal only when it is the only output, or with '-'.

TEST_F(OutputsCli, LobesPlotAloneDoesNotPrintTheTable) {
  const auto r = run({"lobes", kTurning, "--rpm-points", "200", "--quiet", "--plot", path("l.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(contains(r.out, "spindle_rpm,")) << r.out.substr(0, 200);
  EXPECT_LT(lines(r.out).size(), 5u) << "stdout has " << lines(r.out).size() << " lines";
  EXPECT_TRUE(contains(r.out, "wrote plot")) << r.out;

  const auto json_only = run({"lobes", kTurning, "--rpm-points", "200", "--json", path("l.json").string()});
  ASSERT_EQ(json_only.exit_code, 0) << json_only.err;
  EXPECT_FALSE(contains(json_only.out, "spindle_rpm,"));

  // Nothing else asked: the table is the output (unchanged behaviour).
  const auto plain = run({"lobes", kTurning, "--rpm-points", "200"});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(lines(plain.out).size(), 201u);  // header + 200 rows

  // '-' asks for it beside the plot.
  const auto dash = run({"lobes", kTurning, "--rpm-points", "200", "--quiet", "--table", "-", "--plot",
                         path("d.png").string()});
  ASSERT_EQ(dash.exit_code, 0) << dash.err;
  EXPECT_EQ(lines(dash.out).size(), 201u);
  EXPECT_TRUE(contains(dash.err, "wrote plot")) << dash.err;
  EXPECT_FALSE(chatter::test::fs::exists(path("-")));
}

TEST_F(OutputsCli, MapFrfComparePlotAloneDoNotPrintTheTable) {
  const auto map = run({"map", kCaseC, "--rpm-points", "20", "--depth-points", "10", "--quiet", "--plot",
                        path("m.png").string()});
  ASSERT_EQ(map.exit_code, 0) << map.err;
  EXPECT_FALSE(contains(map.out, "spindle_rpm,"));
  EXPECT_LT(lines(map.out).size(), 5u);
  const auto map_plain = run({"map", kCaseC, "--rpm-points", "20", "--depth-points", "10", "--quiet"});
  ASSERT_EQ(map_plain.exit_code, 0) << map_plain.err;
  EXPECT_EQ(lines(map_plain.out).size(), 201u);  // header + 20 x 10

  const auto frf = run({"frf", kTurning, "--points", "300", "--plot", path("f.png").string()});
  ASSERT_EQ(frf.exit_code, 0) << frf.err;
  EXPECT_FALSE(contains(frf.out, "frequency_hz,"));
  const auto frf_dash = run({"frf", kTurning, "--points", "300", "--out", "-", "--plot", path("g.png").string()});
  ASSERT_EQ(frf_dash.exit_code, 0) << frf_dash.err;
  EXPECT_EQ(lines(frf_dash.out).size(), 301u);

  const auto cmp = run({"compare", kTurning, "--rpm-points", "30", "--quiet", "--plot", path("c.png").string()});
  ASSERT_EQ(cmp.exit_code, 0) << cmp.err;
  EXPECT_FALSE(contains(cmp.out, "spindle_rpm,"));
}

// ---------------------------------------------------------------------------
// 3. Every output path checked before computing: exit 2, flag and path named,
// nothing written.

TEST_F(OutputsCli, BadOutputPathsFailBeforeAnythingIsWritten) {
  const std::string missing = path("no_such_dir/x").string();
  struct Case {
    std::vector<std::string> args;
    std::string flag;
  };
  const std::string ok_csv = path("ok.csv").string(), ok_png = path("ok.png").string();
  const std::vector<Case> cases = {
      {{"lobes", kTurning, "--table", ok_csv, "--plot", missing + ".png"}, "--plot"},
      {{"lobes", kTurning, "--table", missing + ".csv", "--plot", ok_png}, "--table"},
      {{"lobes", kTurning, "--table", ok_csv, "--json", missing + ".json"}, "--json"},
      {{"map", kCaseC, "--rpm-points", "5", "--depth-points", "3", "--out", ok_csv, "--plot", missing + ".png"},
       "--plot"},
      {{"compare", kTurning, "--table", ok_csv, "--json", missing + ".json"}, "--json"},
      {{"frf", kTurning, "--out", missing + ".csv", "--plot", ok_png}, "--out"},
      {{"simulate", kTurning, "--rpm", "1000", "--depth-mm", "1", "--out", ok_csv, "--spectrum", missing + ".csv"},
       "--spectrum"},
      {{"simulate", kTurning, "--rpm", "1000", "--depth-mm", "1", "--periodic", "/proc/chatter_cannot.csv"},
       "--periodic"},
      {{"lobes", kTurning, "--table", dir_.string()}, "--table"},                  // a directory
      {{"lobes", kTurning, "--table", ok_csv, "--json", ok_csv}, "--json"},          // the same file twice
      {{"lobes", kTurning, "--table", path("ok.dat").string(), "--plot", ok_png}, "--plot"},  // the plot's data
  };
  for (const Case& c : cases) {
    const auto r = run(c.args);
    std::string cmd;
    for (const auto& a : c.args) cmd += a + " ";
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.flag + " ")) << cmd << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, "nothing written")) << cmd << "\n" << r.err;
    EXPECT_EQ(r.out, "") << cmd;
    const auto left = files();
    EXPECT_TRUE(left.empty()) << cmd << ": left " << left.front();
  }
}

// ---------------------------------------------------------------------------
// 4. lobes --fail-on-chatter --depth-mm D: exit 3 when D chatters at a speed of
// the table, the count checked against the table itself.

TEST_F(OutputsCli, LobesFailOnChatterJudgesTheDepthAtEverySpeed) {
  // Case A: absolute limit 1.278 mm (closed form 2k zeta (1 + zeta) / K_f), so
  // 0.5 mm is stable everywhere and 3 mm chatters at most speeds.
  const auto stable = run({"lobes", kTurning, "--rpm-points", "100", "--depth-mm", "0.5", "--fail-on-chatter",
                           "--table", path("s.csv").string()});
  EXPECT_EQ(stable.exit_code, 0) << stable.err;
  EXPECT_TRUE(contains(stable.err, "stable at all 100 speeds")) << stable.err;

  const auto deep = run({"lobes", kTurning, "--rpm-points", "100", "--depth-mm", "3", "--fail-on-chatter",
                         "--table", path("d.csv").string()});
  EXPECT_EQ(deep.exit_code, 3) << deep.err;
  // The speeds of the table whose limit is not above 3 mm.
  std::size_t expected = 0;
  std::string first;
  const auto rows = lines(slurp(path("d.csv")));
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const std::size_t c1 = rows[i].find(','), c2 = rows[i].find(',', c1 + 1);
    const std::string limit = rows[i].substr(c1 + 1, c2 - c1 - 1);
    if (limit != "inf" && std::stod(limit) <= 3.0) {
      if (expected++ == 0) first = rows[i].substr(0, c1);
    }
  }
  ASSERT_GT(expected, 0u);
  EXPECT_TRUE(contains(deep.err, "chatter at " + std::to_string(expected) + " of 100 speeds")) << deep.err;
  EXPECT_TRUE(contains(deep.err, "(" + first)) << "first chatter speed " << first << ": " << deep.err;

  // Without --fail-on-chatter the same line, exit 0.
  const auto told = run({"lobes", kTurning, "--rpm-points", "100", "--depth-mm", "3", "--table",
                         path("t.csv").string()});
  EXPECT_EQ(told.exit_code, 0) << told.err;
  EXPECT_TRUE(contains(told.err, "chatter at " + std::to_string(expected) + " of 100")) << told.err;
}

TEST_F(OutputsCli, LobesFailOnChatterNeedsAValidDepth) {
  const auto none = run({"lobes", kTurning, "--fail-on-chatter", "--table", path("n.csv").string()});
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_TRUE(contains(none.err, "--fail-on-chatter: give --depth-mm")) << none.err;
  for (const char* bad : {"0", "-1", "60"}) {  // 60 > the default --depth-max-mm 50
    const auto r = run({"lobes", kTurning, "--fail-on-chatter", "--depth-mm", bad, "--table", path("b.csv").string()});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(contains(r.err, "--depth-mm = ")) << r.err;
  }
  EXPECT_TRUE(files().empty());
}

// ---------------------------------------------------------------------------
// 5. compare's explanations only where their condition holds.

TEST_F(OutputsCli, CompareSaysLowImmersionOnlyWhenItIsLow) {
  // Case C, a_e/D = 0.05: sdm finds flip-limited speeds well below analytic.
  const auto low = run({"compare", kCaseC, "--rpm-points", "100", "--quiet", "--table", path("c.csv").string()});
  ASSERT_EQ(low.exit_code, 0) << low.err;
  EXPECT_TRUE(contains(low.out, "cannot see flip lobes (low radial immersion, a_e/D = 0.05)")) << low.out;
  EXPECT_FALSE(contains(low.out, "turning has constant coefficients")) << low.out;

  // a_e/D = 0.5 (up-milling, 2-DOF tool): whatever sdm finds, immersion is
  // not the reason given.
  const auto half = run({"compare", kHalfImmersion, "--rpm-points", "100", "--quiet", "--table",
                         path("h.csv").string()});
  ASSERT_EQ(half.exit_code, 0) << half.err;
  EXPECT_FALSE(contains(half.out, "low radial immersion")) << half.out;
  EXPECT_FALSE(contains(half.out, "turning has constant coefficients")) << half.out;

  // Turning: no flip talk at all, the constant-coefficient explanation instead.
  const auto turning = run({"compare", kTurning, "--rpm-points", "100", "--quiet", "--table",
                            path("t.csv").string()});
  ASSERT_EQ(turning.exit_code, 0) << turning.err;
  EXPECT_FALSE(contains(turning.out, "flip")) << turning.out;
  EXPECT_TRUE(contains(turning.out, "turning has constant coefficients")) << turning.out;
}

TEST_F(OutputsCli, CompareFlipExplanationFollowsTheFlipRows) {
  // Case C (a_e/D = 0.05) over two speed ranges: 19000-24000 rev/min where
  // sdm's limits are Hopf-type, 15000-18000 where they are flip-type. The
  // flip sentence appears exactly when sdm's table has flip rows, with their
  // count, however low the immersion.
  for (const auto& [lo, hi] : {std::pair{"19000", "24000"}, std::pair{"15000", "18000"}}) {
    const auto r = run({"compare", kCaseC, "--methods", "analytic,sdm", "--rpm-min", lo, "--rpm-max", hi,
                        "--rpm-points", "20", "--quiet", "--table", path("c.csv").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto rows = lines(slurp(path("c.csv")));
    std::size_t flips = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) flips += contains(rows[i], ",flip");
    SCOPED_TRACE(std::string(lo) + "-" + hi + " rev/min: " + std::to_string(flips) + " flip rows\n" + r.out);
    if (std::string(lo) == "19000") EXPECT_EQ(flips, 0u);
    else EXPECT_GT(flips, 0u);
    if (flips == 0) EXPECT_FALSE(contains(r.out, "flip"));
    else EXPECT_TRUE(contains(r.out, "(flip) chatter at " + std::to_string(flips) + " speed"));
  }
}

// ---------------------------------------------------------------------------
// 6. simulate --out-every N and the size warning.

TEST_F(OutputsCli, SimulateOutEveryThinsTheSeries) {
  const std::vector<std::string> base = {"simulate", kTurning, "--rpm", "1000", "--depth-mm", "1"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = base;
    a.insert(a.end(), extra.begin(), extra.end());
    return run(a);
  };
  const auto all = with({"--out", path("all.csv").string()});
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_FALSE(contains(all.err, "warning")) << all.err;  // ~2.7 MB: under the 50 MB default
  const auto tenth = with({"--out", path("tenth.csv").string(), "--out-every", "10"});
  ASSERT_EQ(tenth.exit_code, 0) << tenth.err;
  const auto full = lines(slurp(path("all.csv"))), thin = lines(slurp(path("tenth.csv")));
  ASSERT_GT(full.size(), 1000u);
  // Samples 0, 10, 20, ...: ceil(n / 10) data rows, each a row of the full series.
  const std::size_t n = full.size() - 1;
  EXPECT_EQ(thin.size() - 1, (n + 9) / 10) << n << " samples";
  EXPECT_EQ(thin[0], full[0]);
  EXPECT_EQ(thin[1], full[1]);
  EXPECT_EQ(thin[2], full[11]);
  EXPECT_EQ(thin.back(), full[1 + 10 * (thin.size() - 2)]);

  // The warning, with the size and the advice, once the file passes the limit.
  const auto big = with({"--out", path("big.csv").string(), "--warn-size-mb", "0.5"});
  ASSERT_EQ(big.exit_code, 0) << big.err;
  const double mb = static_cast<double>(chatter::test::fs::file_size(path("big.csv"))) / 1e6;
  ASSERT_GT(mb, 0.5);
  EXPECT_TRUE(contains(big.err, "warning: --out")) << big.err;
  EXPECT_TRUE(contains(big.err, "--out-every")) << big.err;
  std::ostringstream size;
  size.precision(3);
  size << mb << " MB";
  EXPECT_TRUE(contains(big.err, size.str())) << "file " << mb << " MB: " << big.err;

  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--out", path("x.csv").string(), "--out-every", "0"},
        std::vector<std::string>{"--out-every", "5"},  // nothing to thin
        std::vector<std::string>{"--out", path("x.csv").string(), "--warn-size-mb", "0"}}) {
    const auto r = with(bad);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, bad[bad.size() - 2])) << r.err;
    EXPECT_FALSE(chatter::test::fs::exists(path("x.csv")));
  }
}

// ---------------------------------------------------------------------------
// 7. Hints: ';' separators, a near-miss CSV header, a near-miss option.

TEST_F(OutputsCli, OperationsFileHints) {
  const std::string json = path("out.json").string();
  {
    std::ofstream(path("semi.csv")) << "id;spindle_rpm;depth_mm;radial_immersion;feed_per_tooth_mm\n"
                                       "a;1000;1;;0,1\n";
  }
  const auto semi = run({"check", kTurning, "--operations", path("semi.csv").string(), "--json", json});
  EXPECT_EQ(semi.exit_code, 2) << semi.err;
  EXPECT_TRUE(contains(semi.err, "semi.csv:1:")) << semi.err;
  EXPECT_TRUE(contains(semi.err, "the file seems to use ';' as separator; chatter reads ','")) << semi.err;
  EXPECT_FALSE(chatter::test::fs::exists(json));

  {
    std::ofstream(path("typo.csv")) << "id,spindle_rpm,depth,radial_immersion,feed_per_tooth_mm\n"
                                       "a,1000,1,,0.1\n";
  }
  const auto typo = run({"check", kTurning, "--operations", path("typo.csv").string(), "--json", json});
  EXPECT_EQ(typo.exit_code, 2) << typo.err;
  EXPECT_TRUE(contains(typo.err, "header column 'depth': unknown column (did you mean depth_mm?")) << typo.err;
  EXPECT_FALSE(chatter::test::fs::exists(json));

  // Nothing close: the list of known columns, no guess.
  { std::ofstream(path("far.csv")) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm,xyzzy\n"; }
  const auto far = run({"check", kTurning, "--operations", path("far.csv").string()});
  EXPECT_EQ(far.exit_code, 2) << far.err;
  EXPECT_TRUE(contains(far.err, "'xyzzy': unknown column (known:")) << far.err;
  EXPECT_FALSE(contains(far.err, "did you mean")) << far.err;
}

TEST_F(OutputsCli, UnknownOptionGetsTheNearestOfItsCommand) {
  struct Case {
    std::vector<std::string> args;
    std::string hint;  // "" = no close option
  };
  const std::vector<Case> cases = {
      {{"lobes", kTurning, "--rpm-pionts", "30"}, "did you mean --rpm-points?"},
      {{"lobes", kTurning, "--deph-max-mm", "3"}, "did you mean --depth-max-mm?"},
      {{"simulate", kTurning, "--rpm", "1000", "--depth-mm", "1", "--out-evry", "3"}, "did you mean --out-every?"},
      {{"map", kCaseC, "--depth-pionts", "3"}, "did you mean --depth-points?"},
      {{"fit", "x.csv", "--modez", "2"}, "did you mean --modes?"},
      {{"point", kTurning, "--rpm", "1000", "--depth-mm", "1", "--fail-on-chater"}, "did you mean --fail-on-chatter?"},
      {{"lobes", kTurning, "--zzzzzz"}, ""},
  };
  for (const Case& c : cases) {
    const auto r = run(c.args);
    std::string cmd;
    for (const auto& a : c.args) cmd += a + " ";
    EXPECT_EQ(r.exit_code, 2) << cmd << r.err;
    EXPECT_TRUE(contains(r.err, "unrecognised option")) << cmd << r.err;
    if (c.hint.empty()) EXPECT_FALSE(contains(r.err, "did you mean")) << cmd << r.err;
    else EXPECT_TRUE(contains(r.err, c.hint)) << cmd << r.err;
  }
}

// ---------------------------------------------------------------------------
// 8. frf -> fit round trip.

// A fitted mode frequency within 1 % of the config's (the tolerance;
// the table is exact to 10 digits, so the fit is far inside it).
constexpr double kRoundTripFrequencyRelTol = 0.01;

// Every `frequency_hz = X` of a fitted TOML fragment.
std::vector<double> fitted_frequencies(const std::string& toml) {
  std::vector<double> out;
  for (const std::string& l : [&] {
         std::vector<std::string> v;
         std::istringstream in(toml);
         for (std::string x; std::getline(in, x);) v.push_back(x);
         return v;
       }())
    if (l.rfind("frequency_hz = ", 0) == 0) out.push_back(std::stod(l.substr(15)));
  return out;
}

TEST_F(OutputsCli, FrfTableFitsBackToTheModes) {
  const std::string csv = path("frf.csv").string(), toml = path("modes.toml").string();
  ASSERT_EQ(run({"frf", kTurning, "--out", csv}).exit_code, 0);
  const auto fit = run({"fit", csv, "--out", toml});
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  const auto f = fitted_frequencies(slurp(toml));
  ASSERT_EQ(f.size(), 1u) << slurp(toml);
  constexpr double kCaseAHz = 94.22;  // configs/seed_turning_1dof.toml, workpiece mode
  EXPECT_NEAR(f[0], kCaseAHz, kRoundTripFrequencyRelTol * kCaseAHz) << "fitted " << f[0] << " Hz";

  // Case B's tool term alone: its one mode (100.66 Hz in the config).
  const std::string csv_b = path("frf_b.csv").string(), toml_b = path("tool.toml").string();
  ASSERT_EQ(run({"frf", kSource + "/configs/coupled_tool1_workpiece1.toml", "--out", csv_b}).exit_code, 0);
  const auto tool = run({"fit", csv_b, "--term", "tool_xx", "--out", toml_b});
  ASSERT_EQ(tool.exit_code, 0) << tool.err;
  const auto fb = fitted_frequencies(slurp(toml_b));
  ASSERT_EQ(fb.size(), 1u) << slurp(toml_b);
  constexpr double kCaseBToolHz = 100.66;
  EXPECT_NEAR(fb[0], kCaseBToolHz, kRoundTripFrequencyRelTol * kCaseBToolHz) << "fitted " << fb[0] << " Hz";

  // A cross term or an unknown one: exit 2, nothing written.
  for (const char* term : {"relative_xy", "spindle_xx"}) {
    const auto bad = run({"fit", csv_b, "--term", term, "--out", path("bad.toml").string()});
    EXPECT_EQ(bad.exit_code, 2) << term;
    EXPECT_TRUE(contains(bad.err, "--term '")) << bad.err;
    EXPECT_FALSE(chatter::test::fs::exists(path("bad.toml")));
  }
}

}  // namespace
