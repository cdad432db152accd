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

}  // namespace
