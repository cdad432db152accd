// --show (docs/plots.md): a live gnuplot window through gnuplot-iostream, or
// with GNUPLOT_TERM=dumb a text plot on standard output (what these tests
// read); without a display and without GNUPLOT_TERM the command says so and
// exits 2 before computing anything.
#include <cstdlib>
#include <string>
#include <vector>

#include "cli_harness.hpp"

namespace {

using chatter::test::CliFixture;
using chatter::test::contains;

const std::string kConfigs = std::string(CHATTER_SOURCE_DIR) + "/configs/";
const std::string kTurning = kConfigs + "seed_turning_1dof.toml";
const std::string kCaseC = kConfigs + "milling_benchmark_ae005_down.toml";
const std::string kPositions = kConfigs + "milling_case_c_positions.toml";

bool gnuplot_available() { return std::system("gnuplot --version > /dev/null 2>&1") == 0; }

std::size_t count(const std::string& hay, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t at = hay.find(needle); at != std::string::npos; at = hay.find(needle, at + 1)) ++n;
  return n;
}

// Every test starts without a display or a terminal choice.
class ShowTest : public CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    ::unsetenv("DISPLAY");
    ::unsetenv("WAYLAND_DISPLAY");
    ::unsetenv("GNUPLOT_TERM");
  }
  void text_terminal() { ::setenv("GNUPLOT_TERM", "dumb size 100,32", 1); }
};

TEST_F(ShowTest, WithoutADisplayItSaysSoAndExitsTwoBeforeComputing) {
  for (const std::vector<std::string>& cmd :
       {std::vector<std::string>{"lobes", kTurning}, {"map", kCaseC}, {"compare", kTurning}, {"surface", kPositions},
        {"simulate", kTurning, "--rpm", "1200", "--depth-mm", "1"}}) {
    std::vector<std::string> args = cmd;
    args.push_back("--show");
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 2) << cmd[0] << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "chatter: --show: no display (DISPLAY is not set)")) << r.err;
    EXPECT_TRUE(contains(r.err, "GNUPLOT_TERM=dumb")) << r.err;
    EXPECT_TRUE(r.out.empty()) << cmd[0] << " printed before refusing: " << r.out;
  }
}

TEST_F(ShowTest, AnUnknownGnuplotTermIsRefusedAndNoGnuplotIsSaid) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  ::setenv("GNUPLOT_TERM", "no_such_terminal", 1);
  auto r = run({"lobes", kTurning, "--show"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--show: GNUPLOT_TERM=no_such_terminal: not a terminal of")) << r.err;
  const std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", "/nonexistent", 1);
  r = run({"lobes", kTurning, "--show"});
  ::setenv("PATH", path.c_str(), 1);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--show: gnuplot not found on PATH")) << r.err;
}

TEST_F(ShowTest, LobesDrawTheDiagramOnATextTerminalAndNoTable) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  text_terminal();
  const auto r = run({"lobes", kCaseC, "--rpm-points", "60", "--show"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The image's labels and key, drawn as text; the table does not go to
  // standard output with --show (as with --plot).
  EXPECT_TRUE(contains(r.out, "spindle speed (rev/min)")) << r.out;
  EXPECT_TRUE(contains(r.out, "stability limit")) << r.out;
  EXPECT_TRUE(contains(r.out, "+------")) << r.out;
  EXPECT_FALSE(contains(r.out, "spindle_rpm,depth_limit_mm")) << r.out;
  EXPECT_TRUE(contains(r.out, "(sdm): 60 speeds")) << "the summary follows the plot";
  EXPECT_FALSE(contains(r.err, "warning")) << r.err;
}

TEST_F(ShowTest, MapCompareAndSurfaceDrawTheirPlots) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  text_terminal();
  auto r = run({"map", kCaseC, "--rpm-points", "12", "--depth-points", "8", "--show"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // (A text terminal draws no rotated y labels: the x label and the key tell the plots apart.)
  EXPECT_TRUE(contains(r.out, "stable (ρ < 1)")) << r.out;
  EXPECT_TRUE(contains(r.out, "spindle speed (rev/min)")) << r.out;
  EXPECT_FALSE(contains(r.out, "spindle_rpm,depth_mm,spectral_radius")) << "no table on standard output";
  r = run({"compare", kCaseC, "--rpm-points", "20", "--show", "--plot-depth-max-mm", "8"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "analytic")) << r.out;
  EXPECT_TRUE(contains(r.out, "sdm: flip (period doubling)")) << r.out;
  r = run({"surface", kPositions, "--rpm-points", "12", "--position-points", "3", "--show", "--plot-contours-mm",
           "2,4"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "best speed at each position")) << r.out;
  EXPECT_TRUE(contains(r.out, "depth contours (2, 4 mm)")) << r.out;
  EXPECT_FALSE(contains(r.out, "position_mm,spindle_rpm")) << "no table on standard output";
}

TEST_F(ShowTest, SimulateRedrawsWhileItIntegratesThenDrawsTheSpectrum) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  text_terminal();
  // 40 periods: a frame after every 4th period but the last (9 frames of two
  // panels, displacement and force), then the final three panels.
  const auto r = run({"simulate", kTurning, "--rpm", "1200", "--depth-mm", "1.5", "--periods", "40", "--show"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // (A text terminal draws no rotated y labels: the keys and x labels count the panels.)
  EXPECT_EQ(count(r.out, "x (feed direction)"), 10u) << r.out;
  EXPECT_EQ(count(r.out, "F_x"), 10u);
  EXPECT_EQ(count(r.out, "time (ms)"), 20u);
  EXPECT_EQ(count(r.out, "frequency (Hz)"), 1u) << "the spectrum once the run is done";
  EXPECT_TRUE(contains(r.out, "\"verdict\": \"chatter\"")) << "the record still printed";
  EXPECT_FALSE(contains(r.err, "warning")) << r.err;
}

TEST_F(ShowTest, ShowAndPlotTogetherWriteTheImageToo) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  text_terminal();
  const auto r = run({"lobes", kTurning, "--rpm-points", "50", "--show", "--plot", path("l.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(chatter::test::fs::exists(path("l.png")));
  EXPECT_TRUE(contains(r.out, "wrote plot: ")) << r.out;
  EXPECT_TRUE(contains(r.out, "spindle speed (rev/min)")) << r.out;
}

}  // namespace
