// Plots through gnuplot (include/chatter/io/plot.hpp): real images, scripts
// that reproduce them, clean data files, and the error paths.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/plot.hpp"
#include "chatter/io/plot_surface.hpp"
#include "chatter/io/plot_uncertainty.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/transfer_function.hpp"

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

bool gnuplot_available() { return std::system("gnuplot --version > /dev/null 2>&1") == 0; }

std::string quote_shell(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Re-runs the emitted script the way a user would: cd DIR && gnuplot STEM.gp.
int rerun(const fs::path& script) {
  const std::string cmd = "cd " + quote_shell(script.parent_path().string()) + " && gnuplot " +
                          quote_shell(script.filename().string()) + " > /dev/null 2>&1";
  return std::system(cmd.c_str());
}

// PNG width and height from the IHDR chunk (the first chunk, right after the
// 8-byte signature: length(4) "IHDR"(4) width(4) height(4), big-endian).
std::pair<unsigned, unsigned> png_size(const std::string& bytes) {
  auto be32 = [&](std::size_t at) {
    return (unsigned(static_cast<unsigned char>(bytes[at])) << 24) |
           (unsigned(static_cast<unsigned char>(bytes[at + 1])) << 16) |
           (unsigned(static_cast<unsigned char>(bytes[at + 2])) << 8) |
           unsigned(static_cast<unsigned char>(bytes[at + 3]));
  };
  return {be32(16), be32(20)};
}

bool is_png(const std::string& bytes) {
  return bytes.size() > 24 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0 && bytes.compare(12, 4, "IHDR") == 0;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A cheap well-formedness check of an SVG: it starts as XML and every element
// opened is closed (tags balance).
void expect_well_formed_svg(const std::string& svg) {
  ASSERT_FALSE(svg.empty());
  EXPECT_TRUE(svg.rfind("<?xml", 0) == 0 || svg.rfind("<svg", 0) == 0);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  std::size_t open = 0, close = 0, self = 0;
  for (std::size_t i = svg.find('<'); i != std::string::npos; i = svg.find('<', i + 1)) {
    if (svg.compare(i, 2, "<?") == 0 || svg.compare(i, 2, "<!") == 0) continue;
    const std::size_t end = svg.find('>', i);
    ASSERT_NE(end, std::string::npos);
    if (svg[i + 1] == '/') ++close;
    else if (svg[end - 1] == '/') ++self;
    else ++open;
  }
  EXPECT_EQ(open, close);
  EXPECT_GT(self + open, 10u);
}

// The rows of data set `index` (0-based, separated by two blank lines) of a
// .dat file, each split into fields; comment and blank lines skipped.
std::vector<std::vector<std::string>> dat_rows(const std::string& dat, int index) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(dat);
  std::string line;
  int current = 0, blanks = 0;
  while (std::getline(in, line)) {
    if (line.empty()) {
      if (++blanks == 2) ++current;
      continue;
    }
    blanks = 0;
    if (line[0] == '#') continue;
    if (current != index) continue;
    std::istringstream fields(line);
    rows.emplace_back(std::istream_iterator<std::string>(fields), std::istream_iterator<std::string>());
  }
  return rows;
}

// Case C on a coarse grid (12 speeds x 10 depths over its sweep): the map
// chatter map computes, with the multiplier type at the unstable points.
chatter::StabilityMapGrid case_c_map(int rpm_points = 12, int depth_points = 10) {
  const auto cfg = chatter::load_config(fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_benchmark_ae005_down.toml");
  const chatter::SemiDiscretizationSolver sdm(cfg.model, cfg.process);
  chatter::StabilityMapGrid g;
  g.spindle_rpm = chatter::evenly_spaced_speeds(cfg.sweep.rpm_min.value(), cfg.sweep.rpm_max.value(), rpm_points);
  for (int k = 0; k < depth_points; ++k)
    g.depth_m.push_back(cfg.sweep.depth_max_mm.value() * 1e-3 * k / (depth_points - 1));
  g.spectral_radius = sdm.spectral_radius_map(g.spindle_rpm, g.depth_m);
  g.multiplier_type.assign(g.spectral_radius.size(), chatter::MultiplierType::kHopf);
  for (std::size_t i = 0; i < g.spindle_rpm.size(); ++i)
    for (std::size_t j = 0; j < g.depth_m.size(); ++j)
      if (g.spectral_radius[i * g.depth_m.size() + j] >= 1.0)
        g.multiplier_type[i * g.depth_m.size() + j] = sdm.analyse(g.spindle_rpm[i], g.depth_m[j]).type;
  return g;
}

// The seed case A: model, envelope, lobes and absolute limit.
struct LobeData {
  chatter::Config cfg;
  std::vector<chatter::StabilityLimit> envelope;
  std::vector<chatter::LobeCurve> curves;
  chatter::AbsoluteLimit absolute;
  double depth_max_m = 0.0;
};

LobeData seed_lobes(double depth_max_mm, int rpm_points = 200) {
  LobeData d;
  d.cfg = chatter::load_config(fs::path(CHATTER_SOURCE_DIR) / "configs" / "seed_turning_1dof.toml");
  chatter::TransferFunctionOptions opt;
  opt.depth_max_m = depth_max_mm * 1e-3;
  const chatter::AnalyticSolver solver(d.cfg.model, d.cfg.process, opt);
  const double lo = d.cfg.sweep.rpm_min.value(), hi = d.cfg.sweep.rpm_max.value();
  d.envelope = chatter::lobe_envelope(solver, chatter::evenly_spaced_speeds(lo, hi, rpm_points));
  d.curves = solver.lobe_curves(chatter::SpindleSpeed(lo), chatter::SpindleSpeed(hi));
  d.absolute = solver.absolute_limit();
  d.depth_max_m = solver.depth_max_m();
  return d;
}

class PlotTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("chatter_test_plot_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

}  // namespace

TEST(PlotPath, FormatFromExtension) {
  EXPECT_EQ(chatter::check_plot_path("a/lobes.png"), chatter::ImageFormat::png);
  EXPECT_EQ(chatter::check_plot_path("lobes.SVG"), chatter::ImageFormat::svg);
  EXPECT_EQ(chatter::check_plot_path("lobes.pdf"), chatter::ImageFormat::pdf);
  try {
    chatter::check_plot_path("plot.xyz");
    FAIL() << "no exception";
  } catch (const chatter::InputError& e) {
    EXPECT_STREQ(e.what(), "plot.xyz: unknown image type '.xyz' (use .png, .svg or .pdf)");
  }
  EXPECT_THROW(chatter::check_plot_path("plot"), chatter::InputError);
}

TEST_F(PlotTest, UnknownExtensionThrowsAndWritesNothing) {
  const LobeData d = seed_lobes(20.0, 50);
  EXPECT_THROW(chatter::plot_lobes(dir_ / "plot.xyz", "x", d.envelope, d.curves, d.absolute, d.depth_max_m),
               chatter::InputError);
  EXPECT_THROW(chatter::plot_frf(dir_ / "frf.jpg", "x", d.cfg.model, 10, 200, 100, false), chatter::InputError);
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(PlotTest, LobesPngHasRequestedSizeAndScriptReproducesIt) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const LobeData d = seed_lobes(20.0);
  chatter::PlotOptions opt;
  opt.width_px = 1000;
  opt.height_px = 700;
  const auto files = chatter::plot_lobes(dir_ / "lobes.png", d.cfg.name, d.envelope, d.curves, d.absolute,
                                         d.depth_max_m, opt);
  EXPECT_EQ(files.image, dir_ / "lobes.png");
  EXPECT_EQ(files.script, dir_ / "lobes.gp");
  EXPECT_EQ(files.data, dir_ / "lobes.dat");
  const std::string png = read_file(files.image);
  ASSERT_TRUE(is_png(png));
  EXPECT_EQ(png_size(png), std::make_pair(1000u, 700u));

  // The script names its files relatively and renders the same image again.
  const std::string gp = read_file(files.script);
  EXPECT_NE(gp.find("set output 'lobes.png'"), std::string::npos);
  EXPECT_NE(gp.find("data = 'lobes.dat'"), std::string::npos);
  EXPECT_EQ(gp.find(dir_.string()), std::string::npos) << "script must not hold absolute paths";
  fs::remove(files.image);
  ASSERT_EQ(rerun(files.script), 0);
  const std::string again = read_file(files.image);
  ASSERT_TRUE(is_png(again));
  EXPECT_EQ(png_size(again), png_size(png));
  EXPECT_EQ(again, png) << "re-running the script should give the same bytes";
}

TEST_F(PlotTest, LobesSvgIsXmlWithPathsAndReproducible) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const LobeData d = seed_lobes(20.0);
  const auto files =
      chatter::plot_lobes(dir_ / "lobes.svg", d.cfg.name, d.envelope, d.curves, d.absolute, d.depth_max_m);
  const std::string svg = read_file(files.image);
  ASSERT_FALSE(svg.empty());
  EXPECT_TRUE(svg.rfind("<?xml", 0) == 0 || svg.rfind("<svg", 0) == 0);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("<path"), std::string::npos);
  EXPECT_NE(svg.find("width=\"1200\""), std::string::npos);
  EXPECT_NE(svg.find("height=\"800\""), std::string::npos);
  // The title and the axis labels are in the image.
  EXPECT_NE(svg.find("Seed 1-DOF turning"), std::string::npos);
  EXPECT_NE(svg.find("spindle speed (rev/min)"), std::string::npos);
  EXPECT_NE(svg.find("depth of cut (mm)"), std::string::npos);

  // Tags balance (a cheap well-formedness check): every element opened is closed.
  std::size_t open = 0, close = 0, self = 0;
  for (std::size_t i = svg.find('<'); i != std::string::npos; i = svg.find('<', i + 1)) {
    if (svg.compare(i, 2, "<?") == 0 || svg.compare(i, 2, "<!") == 0) continue;
    const std::size_t end = svg.find('>', i);
    ASSERT_NE(end, std::string::npos);
    if (svg[i + 1] == '/') ++close;
    else if (svg[end - 1] == '/') ++self;
    else ++open;
  }
  EXPECT_EQ(open, close);
  EXPECT_GT(self + open, 10u);

  fs::remove(files.image);
  ASSERT_EQ(rerun(files.script), 0);
  EXPECT_EQ(read_file(files.image), svg);
}

TEST_F(PlotTest, DataFileHasHeaderAndNoNanOrInf) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  // A 3 mm search depth leaves speeds with no limit (inf rows in the envelope).
  const LobeData d = seed_lobes(3.0);
  std::size_t unbounded = 0;
  for (const auto& r : d.envelope) unbounded += r.bounded() ? 0 : 1;
  ASSERT_GT(unbounded, 0u) << "the test needs rows with no limit";
  const auto files =
      chatter::plot_lobes(dir_ / "lobes.png", d.cfg.name, d.envelope, d.curves, d.absolute, d.depth_max_m);
  const std::string dat = read_file(files.data);
  const std::string l = lower(dat);
  EXPECT_EQ(l.find("nan"), std::string::npos);
  EXPECT_EQ(l.find("inf"), std::string::npos);
  EXPECT_NE(dat.find("# spindle_rpm depth_limit_mm depth_filled_mm chatter_frequency_hz lobe bounded"),
            std::string::npos);
  EXPECT_NE(dat.find("# spindle_rpm depth_mm chatter_frequency_hz lobe branch"), std::string::npos);
  EXPECT_NE(dat.find(" ? "), std::string::npos) << "unbounded rows use the '?' missing marker";
  EXPECT_NE(read_file(files.script).find("set datafile missing '?'"), std::string::npos);
  // Every data row of the envelope block has 6 fields.
  std::istringstream in(dat);
  std::string line;
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    if (line.find("# index 1") == 0) break;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> f{std::istream_iterator<std::string>(fields), std::istream_iterator<std::string>()};
    EXPECT_EQ(f.size(), 6u) << line;
    ++rows;
  }
  EXPECT_EQ(rows, d.envelope.size());
  EXPECT_TRUE(is_png(read_file(files.image)));
}

TEST_F(PlotTest, LobesWithFrequencyPanelAndPdf) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const LobeData d = seed_lobes(20.0, 100);
  chatter::PlotOptions opt;
  opt.chatter_frequency_panel = true;
  auto files = chatter::plot_lobes(dir_ / "lobes_f.png", "panel", d.envelope, d.curves, d.absolute, d.depth_max_m, opt);
  EXPECT_EQ(png_size(read_file(files.image)), std::make_pair(1200u, 800u));
  files = chatter::plot_lobes(dir_ / "lobes.pdf", "pdf", d.envelope, d.curves, d.absolute, d.depth_max_m);
  EXPECT_EQ(read_file(files.image).rfind("%PDF", 0), 0u);
}

TEST_F(PlotTest, FrfPngHasRequestedSize) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const auto cfg = chatter::load_config(fs::path(CHATTER_SOURCE_DIR) / "configs" / "coupled_tool1_workpiece1.toml");
  chatter::PlotOptions opt;
  opt.width_px = 900;
  opt.height_px = 650;
  const auto files = chatter::plot_frf(dir_ / "frf.png", cfg.name, cfg.model, 20.0, 1000.0, 400, true, opt);
  const std::string png = read_file(files.image);
  ASSERT_TRUE(is_png(png));
  EXPECT_EQ(png_size(png), std::make_pair(900u, 650u));
  const std::string dat = read_file(files.data);
  EXPECT_NE(dat.find("frequency_hz tool_xx_abs_m_per_n tool_xx_phase_deg"), std::string::npos);
  EXPECT_EQ(dat.find("yy"), std::string::npos) << "all modes along X: no yy columns";
  EXPECT_EQ(lower(dat).find("nan"), std::string::npos);
  fs::remove(files.image);
  ASSERT_EQ(rerun(files.script), 0);
  EXPECT_EQ(read_file(files.image), png);
}

TEST_F(PlotTest, FrfWithRigidToolAndYModeRealImaginarySvg) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  chatter::StructuralModel model;  // rigid tool, a workpiece mode at 45 degrees
  model.workpiece.modes.push_back(chatter::Mode::from_stiffness(200.0, 0.03, 2e7, {1.0, 1.0}));
  chatter::PlotOptions opt;
  opt.frf_parts = chatter::FrfParts::real_imaginary;
  const auto files = chatter::plot_frf(dir_ / "frf.svg", "rigid tool", model, 0.0, 400.0, 300, false, opt);
  const std::string svg = read_file(files.image);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("<path"), std::string::npos);
  EXPECT_NE(svg.find("tool: rigid"), std::string::npos);
  const std::string dat = read_file(files.data);
  EXPECT_NE(dat.find("relative_yy_imag_m_per_n"), std::string::npos);
  EXPECT_EQ(lower(dat).find("nan"), std::string::npos);
  EXPECT_EQ(lower(dat).find("inf"), std::string::npos);
}

TEST_F(PlotTest, FrfRejectsBadRanges) {
  const auto cfg = chatter::load_config(fs::path(CHATTER_SOURCE_DIR) / "configs" / "seed_turning_1dof.toml");
  EXPECT_THROW(chatter::plot_frf(dir_ / "f.png", "t", cfg.model, 0.0, 100.0, 100, true), chatter::InputError);
  EXPECT_THROW(chatter::plot_frf(dir_ / "f.png", "t", cfg.model, 100.0, 50.0, 100, false), chatter::InputError);
  EXPECT_THROW(chatter::plot_frf(dir_ / "f.png", "t", cfg.model, 10.0, 50.0, 1, false), chatter::InputError);
  EXPECT_THROW(chatter::plot_frf(dir_ / "f.png", "t", chatter::StructuralModel{}, 10.0, 50.0, 10, false),
               chatter::InputError);
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(PlotTest, MissingGnuplotWritesDataAndScriptThenSaysHowToInstall) {
  const LobeData d = seed_lobes(20.0, 50);
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  const fs::path empty_bin = dir_ / "empty_bin";
  fs::create_directories(empty_bin);
  ::setenv("PATH", empty_bin.c_str(), 1);
  bool thrown = false;
  try {
    chatter::plot_lobes(dir_ / "lobes.png", "x", d.envelope, d.curves, d.absolute, d.depth_max_m);
  } catch (const chatter::GnuplotNotFound& e) {
    thrown = true;
    const chatter::InputError& as_input = e;  // exit status 2 in the CLI
    EXPECT_NE(std::string(as_input.what()).find("apt-get install gnuplot-nox"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gnuplot lobes.gp"), std::string::npos) << e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_TRUE(thrown);
  EXPECT_TRUE(fs::exists(dir_ / "lobes.dat"));
  EXPECT_TRUE(fs::exists(dir_ / "lobes.gp"));
  EXPECT_FALSE(fs::exists(dir_ / "lobes.png"));
}

TEST_F(PlotTest, UnwritableDirectoryIsInputError) {
  const LobeData d = seed_lobes(20.0, 50);
  EXPECT_THROW(chatter::plot_lobes(dir_ / "no_such_dir" / "lobes.png", "x", d.envelope, d.curves, d.absolute,
                                   d.depth_max_m),
               chatter::InputError);
}

TEST_F(PlotTest, QuotesAndSpacesInTitleAndPathPassThrough) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const LobeData d = seed_lobes(20.0, 50);
  const fs::path sub = dir_ / "it's a dir";
  fs::create_directories(sub);
  const std::string title = "Bob's \"case\" a_e^2 {x} @ 50%\\n";
  const auto files = chatter::plot_lobes(sub / "my lobes.svg", title, d.envelope, d.curves, d.absolute, d.depth_max_m);
  const std::string svg = read_file(files.image);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("Bob's \"case\" a_e^2 {x} @ 50%\\n"), std::string::npos) << "title not shown verbatim";
  EXPECT_EQ(rerun(files.script), 0);
  EXPECT_EQ(read_file(files.image), svg);
}

TEST_F(PlotTest, GnuplotFailureIsPlotErrorWithItsMessage) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  std::ofstream(dir_ / "bad.gp") << "set terminal svg\nset output 'bad.svg'\nplot 'no_such_file.dat'\n";
  try {
    chatter::run_gnuplot(dir_ / "bad.gp");
    FAIL() << "no exception";
  } catch (const chatter::PlotError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_file.dat"), std::string::npos) << e.what();
  }
}

TEST_F(PlotTest, NoInstabilityBelowSearchedDepthStillPlots) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const LobeData d = seed_lobes(0.5, 50);  // case A's absolute limit is 1.28 mm
  for (const auto& r : d.envelope) ASSERT_FALSE(r.bounded());
  ASSERT_FALSE(std::isfinite(d.absolute.depth_m));
  const auto files = chatter::plot_lobes(dir_ / "none.png", "stable everywhere", d.envelope, d.curves, d.absolute,
                                         d.depth_max_m);
  EXPECT_TRUE(is_png(read_file(files.image)));
  EXPECT_EQ(lower(read_file(files.data)).find("inf"), std::string::npos);
  // And with no lobe curves at all, plus the frequency panel.
  chatter::PlotOptions opt;
  opt.chatter_frequency_panel = true;
  const auto f2 = chatter::plot_lobes(dir_ / "none2.svg", "t", d.envelope, {}, d.absolute, d.depth_max_m, opt);
  EXPECT_NE(read_file(f2.image).find("</svg>"), std::string::npos);
}

// ---------------------------------------------------------------- stability map

TEST_F(PlotTest, MapPngFromCaseCHasSizeAndScriptReproducesIt) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const auto map = case_c_map();
  std::size_t flips = 0;
  for (std::size_t p = 0; p < map.spectral_radius.size(); ++p)
    flips += map.spectral_radius[p] >= 1.0 && map.multiplier_type[p] == chatter::MultiplierType::kFlip;
  ASSERT_GT(flips, 0u) << "case C's grid should hold flip points";
  chatter::PlotOptions opt;
  opt.width_px = 1000;
  opt.height_px = 700;
  const auto files = chatter::plot_stability_map(dir_ / "map.png", "case C map", map, opt);
  EXPECT_EQ(files.script, dir_ / "map.gp");
  EXPECT_EQ(files.data, dir_ / "map.dat");
  const std::string png = read_file(files.image);
  ASSERT_TRUE(is_png(png));
  EXPECT_EQ(png_size(png), std::make_pair(1000u, 700u));

  const std::string gp = read_file(files.script);
  EXPECT_NE(gp.find("set output 'map.png'"), std::string::npos);
  EXPECT_NE(gp.find("data = 'map.dat'"), std::string::npos);
  EXPECT_NE(gp.find("set cblabel 'spectral radius ρ'"), std::string::npos);
  EXPECT_NE(gp.find("ρ = 1, Hopf"), std::string::npos) << "the legend names the Hopf boundary";
  EXPECT_NE(gp.find("ρ = 1, flip"), std::string::npos) << "the legend names the flip boundary";
  EXPECT_NE(gp.find("flip dominates"), std::string::npos) << "the flip points are marked";
  EXPECT_EQ(gp.find(dir_.string()), std::string::npos) << "script must not hold absolute paths";

  // The data: the whole grid, no nan/inf, the contour with both types.
  const std::string dat = read_file(files.data);
  for (int set = 0; set < 3; ++set)
    for (const auto& row : dat_rows(dat, set))
      for (const auto& field : row) EXPECT_TRUE(lower(field).find("nan") == std::string::npos &&
                                                lower(field).find("inf") == std::string::npos) << field;
  EXPECT_NE(dat.find("# spindle_rpm depth_mm spectral_radius multiplier_type"), std::string::npos);
  const auto grid = dat_rows(dat, 0);
  ASSERT_EQ(grid.size(), map.spectral_radius.size());
  for (std::size_t p = 0; p < grid.size(); ++p) {
    ASSERT_EQ(grid[p].size(), 4u);
    EXPECT_NEAR(std::stod(grid[p][2]), map.spectral_radius[p], 1e-6 * map.spectral_radius[p]);
    EXPECT_EQ(grid[p][3] == "?", map.spectral_radius[p] < 1.0) << p;
  }
  const auto contour = dat_rows(dat, 1);
  ASSERT_FALSE(contour.empty());
  bool hopf = false, flip = false;
  for (const auto& r : contour) {
    ASSERT_EQ(r.size(), 3u);
    hopf = hopf || r[2] == "hopf";
    flip = flip || r[2] == "flip";
  }
  EXPECT_TRUE(hopf && flip);
  EXPECT_FALSE(dat_rows(dat, 2).empty()) << "flip marks";

  fs::remove(files.image);
  ASSERT_EQ(rerun(files.script), 0);
  EXPECT_EQ(read_file(files.image), png) << "re-running the script should give the same bytes";
}

TEST_F(PlotTest, MapSvgIsXmlWithTheContourPathAndPdfRenders) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const auto map = case_c_map();
  const auto files = chatter::plot_stability_map(dir_ / "map.svg", "Case C, 12 x 10", map);
  const std::string svg = read_file(files.image);
  expect_well_formed_svg(svg);
  EXPECT_NE(svg.find("width=\"1200\""), std::string::npos);
  EXPECT_NE(svg.find("Case C, 12 x 10"), std::string::npos);
  EXPECT_NE(svg.find("spindle speed (rev/min)"), std::string::npos);
  EXPECT_NE(svg.find("depth of cut (mm)"), std::string::npos);
  EXPECT_NE(svg.find("spectral radius ρ"), std::string::npos);
  EXPECT_NE(svg.find("<image"), std::string::npos) << "the heat map";
  // The flip part of the contour is a dashed path in its own colour
  // (#7b1fa2 = rgb(123, 31, 162)), the Hopf part a path in near-black.
  const std::size_t flip_path = svg.find("<path stroke='rgb(123,  31, 162)' stroke-dasharray");
  ASSERT_NE(flip_path, std::string::npos);
  EXPECT_NE(svg.find(" L", flip_path), std::string::npos);
  EXPECT_NE(svg.find("<path stroke='rgb( 16,  16,  16)'"), std::string::npos);
  fs::remove(files.image);
  ASSERT_EQ(rerun(files.script), 0);
  EXPECT_EQ(read_file(files.image), svg);

  const auto pdf = chatter::plot_stability_map(dir_ / "map.pdf", "pdf", map);
  EXPECT_EQ(read_file(pdf.image).rfind("%PDF", 0), 0u);
}

TEST_F(PlotTest, MapContourFollowsRhoEqualOneBetweenGridPoints) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  // ln ρ = 3 (x - 1100)/100 along the speed: ρ = 1 at 1100 rev/min exactly
  // (linear interpolation of ln ρ is exact here); flip where ρ >= 1 above 2 mm.
  chatter::StabilityMapGrid g;
  g.spindle_rpm = {1000, 1050, 1200, 1300};
  g.depth_m = {0.0, 1e-3, 2e-3, 3e-3, 4e-3};
  for (double rpm : g.spindle_rpm)
    for (double d : g.depth_m) {
      g.spectral_radius.push_back(std::exp(3.0 * (rpm - 1100.0) / 100.0));
      g.multiplier_type.push_back(d > 2.5e-3 ? chatter::MultiplierType::kFlip : chatter::MultiplierType::kHopf);
    }
  const auto files = chatter::plot_stability_map(dir_ / "m.png", "synthetic", g);
  const auto contour = dat_rows(read_file(files.data), 1);
  ASSERT_GE(contour.size(), 5u);
  bool hopf = false, flip = false;
  for (const auto& r : contour) {
    EXPECT_NEAR(std::stod(r[0]), 1100.0, 1e-3) << "the contour is the line rho = 1";
    const double d = std::stod(r[1]);
    EXPECT_TRUE(d >= 0.0 && d <= 4.0) << d;
    if (r[2] == "hopf") {
      hopf = true;
      EXPECT_LE(d, 3.0);
    }
    if (r[2] == "flip") {
      flip = true;
      EXPECT_GE(d, 2.0);
    }
  }
  EXPECT_TRUE(hopf && flip);
  EXPECT_TRUE(is_png(read_file(files.image)));

  // Without types: one kind of contour, no marks; all stable: no contour.
  g.multiplier_type.clear();
  auto f2 = chatter::plot_stability_map(dir_ / "m2.svg", "untyped", g);
  EXPECT_NE(read_file(f2.script).find("ρ = 1 (stability boundary)"), std::string::npos);
  EXPECT_TRUE(dat_rows(read_file(f2.data), 2).empty());
  for (double& r : g.spectral_radius) r = 0.5;
  f2 = chatter::plot_stability_map(dir_ / "m3.svg", "stable", g);
  EXPECT_TRUE(dat_rows(read_file(f2.data), 1).empty());
  EXPECT_NE(read_file(f2.image).find("stable everywhere"), std::string::npos);
}

TEST_F(PlotTest, MapRejectsBadGridsAndExtensionsAndWritesNothing) {
  chatter::StabilityMapGrid g;
  g.spindle_rpm = {1000, 2000};
  g.depth_m = {0.0, 1e-3, 2e-3};
  g.spectral_radius = {0.5, 0.9, 1.2, 0.6, 1.1, 1.5};
  EXPECT_THROW(chatter::plot_stability_map(dir_ / "map.jpg", "t", g), chatter::InputError);
  EXPECT_THROW(chatter::plot_stability_map(dir_ / "map.xyz", "t", chatter::StabilityMapGrid{}), chatter::InputError);
  auto bad = g;
  bad.spectral_radius.pop_back();
  EXPECT_THROW(chatter::plot_stability_map(dir_ / "map.png", "t", bad), chatter::InputError);
  bad = g;
  bad.depth_m = {0.0, 2e-3, 1e-3};
  EXPECT_THROW(chatter::plot_stability_map(dir_ / "map.png", "t", bad), chatter::InputError);
  bad = g;
  bad.spectral_radius[2] = std::nan("");
  EXPECT_THROW(chatter::plot_stability_map(dir_ / "map.png", "t", bad), chatter::InputError);
  bad = g;
  bad.multiplier_type = {chatter::MultiplierType::kFlip};
  EXPECT_THROW(chatter::plot_stability_map(dir_ / "map.png", "t", bad), chatter::InputError);
  bad = g;
  bad.spindle_rpm = {1000};
  bad.spectral_radius.resize(3);
  EXPECT_THROW(chatter::plot_stability_map(dir_ / "map.png", "t", bad), chatter::InputError);
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(PlotTest, MapWithoutGnuplotWritesDataAndScriptThenSaysHowToInstall) {
  chatter::StabilityMapGrid g;
  g.spindle_rpm = {1000, 2000};
  g.depth_m = {0.0, 1e-3};
  g.spectral_radius = {0.5, 1.2, 0.6, 1.1};
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  const fs::path empty_bin = dir_ / "empty_bin";
  fs::create_directories(empty_bin);
  ::setenv("PATH", empty_bin.c_str(), 1);
  std::string message;
  try {
    chatter::plot_stability_map(dir_ / "map.png", "t", g);
  } catch (const chatter::GnuplotNotFound& e) {
    message = e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_NE(message.find("apt-get install gnuplot-nox"), std::string::npos) << message;
  EXPECT_NE(message.find("gnuplot map.gp"), std::string::npos) << message;
  EXPECT_TRUE(fs::exists(dir_ / "map.dat"));
  EXPECT_TRUE(fs::exists(dir_ / "map.gp"));
  EXPECT_FALSE(fs::exists(dir_ / "map.png"));
}

// ---------------------------------------------------------------- comparison

namespace {

// Case C between 14 000 and 19 000 rev/min (the flip lobe): analytic and sdm
// at the same speeds, sdm with its multiplier types.
std::vector<chatter::MethodLimits> case_c_methods(int points) {
  const auto cfg = chatter::load_config(fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_benchmark_ae005_down.toml");
  const auto speeds = chatter::evenly_spaced_speeds(14000.0, 19000.0, points);
  chatter::TransferFunctionOptions tf;
  tf.depth_max_m = 10e-3;
  const chatter::AnalyticSolver analytic(cfg.model, cfg.process, tf);
  chatter::SemiDiscretizationOptions so;
  so.depth_max_m = 10e-3;
  const chatter::SemiDiscretizationSolver sdm(cfg.model, cfg.process, so);
  std::vector<chatter::MethodLimits> m(2);
  m[0].method = "analytic";
  m[0].limits = chatter::lobe_envelope(analytic, speeds);
  m[1].method = "sdm";
  for (double rpm : speeds) {
    chatter::FloquetResult f;
    m[1].limits.push_back(sdm.limit_at(chatter::SpindleSpeed(rpm), &f));
    m[1].multiplier_type.push_back(f.type);
  }
  return m;
}

}  // namespace

TEST_F(PlotTest, ComparePngAndSvgOverlayTheMethods) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const auto methods = case_c_methods(30);
  chatter::PlotOptions opt;
  opt.width_px = 900;
  opt.height_px = 600;
  const auto files = chatter::plot_compare(dir_ / "cmp.png", "case C compare", methods, 10e-3, opt);
  const std::string png = read_file(files.image);
  ASSERT_TRUE(is_png(png));
  EXPECT_EQ(png_size(png), std::make_pair(900u, 600u));
  const std::string gp = read_file(files.script);
  EXPECT_NE(gp.find("title 'analytic'"), std::string::npos);
  EXPECT_NE(gp.find("title 'sdm'"), std::string::npos);
  EXPECT_NE(gp.find("sdm: flip (period doubling)"), std::string::npos);
  EXPECT_NE(gp.find("set ylabel 'depth limit (mm)'"), std::string::npos);
  const std::string dat = read_file(files.data);
  EXPECT_NE(dat.find("# spindle_rpm depth_limit_mm_analytic bounded_analytic depth_limit_mm_sdm bounded_sdm"),
            std::string::npos);
  EXPECT_EQ(lower(dat).find("nan"), std::string::npos);
  EXPECT_EQ(lower(dat).find("inf"), std::string::npos);
  const auto rows = dat_rows(dat, 0);
  ASSERT_EQ(rows.size(), 30u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 5u);
    const auto& sdm = methods[1].limits[i];
    EXPECT_EQ(rows[i][4], sdm.bounded() ? "1" : "0");
    if (sdm.bounded()) {
      EXPECT_NEAR(std::stod(rows[i][3]), sdm.depth_limit_m * 1e3, 1e-8);
    }
  }
  EXPECT_FALSE(dat_rows(dat, 1).empty()) << "sdm's flip-limited speeds";
  fs::remove(files.image);
  ASSERT_EQ(rerun(files.script), 0);
  EXPECT_EQ(read_file(files.image), png);

  const auto svg_files = chatter::plot_compare(dir_ / "cmp.svg", "case C compare", methods, 10e-3);
  const std::string svg = read_file(svg_files.image);
  expect_well_formed_svg(svg);
  EXPECT_NE(svg.find("case C compare"), std::string::npos);
  EXPECT_NE(svg.find("spindle speed (rev/min)"), std::string::npos);
  EXPECT_NE(svg.find("depth limit (mm)"), std::string::npos);
  // Each method's line is a path in its colour, the same on every chart:
  // analytic #8fbce6, sdm #d95f02.
  EXPECT_NE(svg.find("<path stroke='rgb(143, 188, 230)'"), std::string::npos);
  EXPECT_NE(svg.find("<path stroke='rgb(217,  95,   2)'"), std::string::npos);
  fs::remove(svg_files.image);
  ASSERT_EQ(rerun(svg_files.script), 0);
  EXPECT_EQ(read_file(svg_files.image), svg);
}

// time-domain is drawn as open circles on top of the lines and flip marks
// (it lies on sdm's line where the two agree), thinned to about 100 points.
TEST_F(PlotTest, CompareDrawsTimeDomainAsPointsOnTop) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  auto methods = case_c_methods(250);
  chatter::MethodLimits td = methods[1];
  td.method = "time-domain";
  td.multiplier_type.clear();
  methods.push_back(td);
  const auto files = chatter::plot_compare(dir_ / "cmp_td.png", "case C compare", methods, 10e-3);
  ASSERT_TRUE(is_png(read_file(files.image)));
  const std::string gp = read_file(files.script);
  const auto td_points = gp.find("data index 0 every 3 using 1:(limit(2)) with points pt 6");
  const auto flip_marks = gp.find("sdm: flip (period doubling)");
  const auto sdm_line = gp.find("using 1:(limit(1)) with lines");
  ASSERT_NE(td_points, std::string::npos) << gp;
  ASSERT_NE(flip_marks, std::string::npos);
  ASSERT_NE(sdm_line, std::string::npos);
  EXPECT_LT(sdm_line, td_points);
  EXPECT_LT(flip_marks, td_points) << "the circles are drawn over the flip marks";
  EXPECT_NE(gp.find("keyentry with points pt 6"), std::string::npos);
  EXPECT_NE(gp.find("title 'time-domain'"), std::string::npos);
  // The data still holds every speed of every method.
  EXPECT_EQ(dat_rows(read_file(files.data), 0).size(), 250u);
}

TEST_F(PlotTest, CompareRejectsBadInputAndWritesNothing) {
  auto methods = case_c_methods(4);
  EXPECT_THROW(chatter::plot_compare(dir_ / "cmp.bmp", "t", methods, 10e-3), chatter::InputError);
  EXPECT_THROW(chatter::plot_compare(dir_ / "cmp.png", "t", {}, 10e-3), chatter::InputError);
  EXPECT_THROW(chatter::plot_compare(dir_ / "cmp.png", "t", methods, 0.0), chatter::InputError);
  auto bad = methods;
  bad[1].method = "analytic";
  EXPECT_THROW(chatter::plot_compare(dir_ / "cmp.png", "t", bad, 10e-3), chatter::InputError);
  bad = methods;
  bad[1].limits.pop_back();
  EXPECT_THROW(chatter::plot_compare(dir_ / "cmp.png", "t", bad, 10e-3), chatter::InputError);
  bad = methods;
  bad[1].limits[2].spindle_rpm += 1.0;
  EXPECT_THROW(chatter::plot_compare(dir_ / "cmp.png", "t", bad, 10e-3), chatter::InputError);
  bad = methods;
  bad[1].multiplier_type.pop_back();
  EXPECT_THROW(chatter::plot_compare(dir_ / "cmp.png", "t", bad, 10e-3), chatter::InputError);
  EXPECT_TRUE(fs::is_empty(dir_));
}

namespace {

chatter::SimulationResult case_c_simulation(double rpm, double depth_m, int periods) {
  const chatter::Config cfg =
      chatter::load_config(std::string(CHATTER_SOURCE_DIR) + "/configs/milling_benchmark_ae005_down.toml");
  chatter::TimeDomainSimulator sim(cfg.model, cfg.process);
  chatter::SimulationSettings s;
  s.spindle_rpm = rpm;
  s.depth_m = depth_m;
  s.periods = periods;
  s.multiple_regeneration = true;
  return sim.simulate(s);
}

}  // namespace

TEST_F(PlotTest, SimulationPngAndSvgShowSeriesSamplesAndSpectrum) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  // Flip chatter in case C's flip lobe: 850 Hz = 1.5 x tooth passing.
  const chatter::SimulationResult r = case_c_simulation(17000, 3.6e-3, 60);
  ASSERT_EQ(r.verdict, chatter::SimulationVerdict::kChatter);
  chatter::PlotOptions opt;
  opt.width_px = 1000;
  opt.height_px = 800;
  const auto files = chatter::plot_simulation(dir_ / "sim.png", "case C simulate", r, 922.0, opt);
  const std::string png = read_file(files.image);
  ASSERT_TRUE(is_png(png));
  EXPECT_EQ(png_size(png), std::make_pair(1000u, 800u));
  const std::string gp = read_file(files.script);
  EXPECT_NE(gp.find("set ylabel 'relative displacement ({/Symbol m}m)'"), std::string::npos);
  EXPECT_NE(gp.find("set ylabel 'force on the tool (N)'"), std::string::npos);
  EXPECT_NE(gp.find("set xlabel 'frequency (Hz)'"), std::string::npos);
  EXPECT_NE(gp.find("chatter 850 Hz"), std::string::npos) << "the chatter frequency is labelled";
  EXPECT_NE(gp.find("set arrow from 566.66667, graph 0"), std::string::npos) << "first tooth-passing harmonic marked";
  const std::string dat = read_file(files.data);
  EXPECT_EQ(lower(dat).find("nan"), std::string::npos);
  EXPECT_EQ(lower(dat).find("inf"), std::string::npos);
  EXPECT_EQ(dat_rows(dat, 0).size(), r.series.size());
  EXPECT_EQ(dat_rows(dat, 1).size(), r.once_per_period.size());
  EXPECT_FALSE(dat_rows(dat, 2).empty());
  EXPECT_FALSE(dat_rows(dat, 3).empty());
  fs::remove(files.image);
  ASSERT_EQ(rerun(files.script), 0);
  EXPECT_EQ(read_file(files.image), png);

  const auto svg_files = chatter::plot_simulation(dir_ / "sim.svg", "case C simulate", r, 922.0);
  const std::string svg = read_file(svg_files.image);
  expect_well_formed_svg(svg);
  EXPECT_NE(svg.find("case C simulate"), std::string::npos);
  EXPECT_NE(svg.find("<path stroke='rgb( 31, 119, 180)'"), std::string::npos) << "the x displacement line";
}

TEST_F(PlotTest, SimulationWithoutSeriesIsRefusedBeforeWriting) {
  chatter::SimulationResult r;
  EXPECT_THROW(chatter::plot_simulation(dir_ / "sim.png", "x", r, 922.0), chatter::InputError);
  EXPECT_THROW(chatter::plot_simulation(dir_ / "sim.bmp", "x", r, 922.0), chatter::InputError);
  EXPECT_TRUE(fs::is_empty(dir_));
}

// ---------------------------------------------------------------------------
// Live plots (--show): the same data and script as the image, without the
// terminal and output lines, the data in a datablock (io/plot.hpp's
// PlotWindow). The window here records what it is handed.

namespace {

struct RecordingWindow : chatter::PlotWindow {
  std::vector<std::pair<std::string, std::string>> draws;  // (data, script)
  void draw(const std::string& data, const std::string& script) override { draws.emplace_back(data, script); }
};

// The script after its head: everything after the line `data = ...` (the
// head names the terminal, the output and where the data are; the body is
// the plot's styles and clauses).
std::string script_body(const std::string& script) {
  const std::size_t at = script.find("\ndata = ");
  if (at == std::string::npos) return "<no data line>";
  std::size_t from = script.find('\n', at + 1);
  while (from < script.size() && script[from] == '\n') ++from;
  return script.substr(from);
}

// The live draw has the image's data byte for byte and the image's script
// body; its head has no terminal or output and reads the datablock.
void expect_live_equals_image(const RecordingWindow& w, const chatter::PlotFiles& files) {
  ASSERT_EQ(w.draws.size(), 1u);
  const auto& [data, script] = w.draws.front();
  EXPECT_EQ(data, read_file(files.data));
  EXPECT_EQ(script_body(script), script_body(read_file(files.script)));
  EXPECT_EQ(script.find("set terminal"), std::string::npos);
  EXPECT_EQ(script.find("set output"), std::string::npos);
  EXPECT_NE(script.find("data = '$data'"), std::string::npos) << script.substr(0, 400);
}

}  // namespace

TEST_F(PlotTest, LiveLobesMapCompareAreTheImagesScripts) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  chatter::PlotOptions opt;
  opt.chatter_frequency_panel = true;
  const LobeData d = seed_lobes(20.0, 120);
  {
    RecordingWindow w;
    chatter::plot_lobes(w, "case A", d.envelope, d.curves, d.absolute, d.depth_max_m, opt);
    expect_live_equals_image(w, chatter::plot_lobes(dir_ / "lobes.png", "case A", d.envelope, d.curves, d.absolute,
                                                    d.depth_max_m, opt));
  }
  {
    const chatter::StabilityMapGrid g = case_c_map();
    RecordingWindow w;
    chatter::plot_stability_map(w, "case C", g);
    expect_live_equals_image(w, chatter::plot_stability_map(dir_ / "map.png", "case C", g));
  }
  {
    const auto methods = case_c_methods(30);
    RecordingWindow w;
    chatter::plot_compare(w, "case C compare", methods, 10e-3);
    expect_live_equals_image(w, chatter::plot_compare(dir_ / "cmp.png", "case C compare", methods, 10e-3));
  }
}

TEST_F(PlotTest, LiveSimulationIsTheImageAndARunningRunDrawsTwoPanels) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  const chatter::SimulationResult r = case_c_simulation(17000, 3.6e-3, 20);
  RecordingWindow w;
  chatter::plot_simulation(w, "case C simulate", r, 922.0, /*running=*/false);
  expect_live_equals_image(w, chatter::plot_simulation(dir_ / "sim.png", "case C simulate", r, 922.0));
  // While integrating: displacement and force on the whole run's time axis,
  // no spectrum panel, the title counting the periods done.
  chatter::SimulationResult so_far = r;
  so_far.once_per_period.resize(6);  // 5 periods done
  so_far.series.resize(so_far.series.size() / 4);
  so_far.spectrum_hz.clear();
  so_far.spectrum_amplitude_m.clear();
  RecordingWindow running;
  chatter::plot_simulation(running, "case C simulate", so_far, 922.0, /*running=*/true);
  ASSERT_EQ(running.draws.size(), 1u);
  const std::string& gp = running.draws.front().second;
  EXPECT_NE(gp.find("set multiplot layout 2,1 title 'case C simulate: integrating, 5 of 20 periods'"),
            std::string::npos)
      << gp;
  EXPECT_EQ(gp.find("frequency (Hz)"), std::string::npos);
  EXPECT_NE(gp.find("set xrange [0:" + chatter::gnuplot_number(20 * r.floquet_period_s * 1e3, 8) + "]"),
            std::string::npos)
      << gp;
}

TEST_F(PlotTest, LiveSurfaceAndUncertainLobesAreTheImagesScripts) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  chatter::LobeSurfaceData s;
  s.positions_mm = {0.0, 50.0, 100.0};
  s.depth_max_mm = 10.0;
  for (std::size_t p = 0; p < 3; ++p) {
    std::vector<chatter::StabilityLimit> row;
    for (int k = 0; k < 5; ++k) {
      chatter::StabilityLimit l;
      l.spindle_rpm = 1000.0 + 500.0 * k;
      l.depth_limit_m = 1e-3 * (1.0 + static_cast<double>(p) + 0.5 * k);
      l.chatter_frequency_hz = 500.0;
      l.lobe = 1;
      row.push_back(l);
    }
    s.limits.push_back(row);
  }
  {
    RecordingWindow w;
    chatter::plot_surface(w, "surface", s, {2.0, 4.0});
    expect_live_equals_image(w, chatter::plot_surface(dir_ / "surface.png", "surface", s, {2.0, 4.0}));
  }
  chatter::UncertainLobes u;
  u.speeds_rpm = {1000.0, 1500.0, 2000.0};
  u.depths_m = {0.0, 1e-3, 2e-3};
  u.probability_stable = {{1.0, 0.5, 0.0}, {1.0, 1.0, 0.5}, {1.0, 0.5, 0.0}};
  u.levels = {0.05, 0.5, 0.95};
  u.quantile_depth_m = {{0.8e-3, 1.5e-3, 0.8e-3}, {1e-3, 2e-3, 1e-3}, {1.2e-3, 2.5e-3, 1.2e-3}};
  std::vector<chatter::StabilityLimit> nominal(3);
  for (std::size_t i = 0; i < 3; ++i) {
    nominal[i].spindle_rpm = u.speeds_rpm[i];
    nominal[i].depth_limit_m = u.quantile_depth_m[1][i];
  }
  RecordingWindow w;
  chatter::plot_uncertain_lobes(w, "uncertain", u, nominal, 10.0, 3.0);
  expect_live_equals_image(w, chatter::plot_uncertain_lobes(dir_ / "unc.png", "uncertain", u, nominal, 10.0, 3.0));
}
