// Grinding configs and files (include/chatter/io/grinding_config.hpp,
// grinding_io.hpp): [grinding] read by the loader with its rules (file, key,
// rule; every error at once; plausibility warnings with the likely unit), the
// shipped configs, the lobe loader refusing a grinding config, the fit's
// [grinding] fragment loading back, and bad tests tables and records.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/io/grinding_io.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = CHATTER_SOURCE_DIR;

// The minimal grinding config, with extra lines.
std::string minimal(const std::string& extra = "") {
  return "[grinding]\nwheel_diameter_mm = 230\nwheel_width_mm = 6.8\nwheel_rpm = 6000\nfeed_mm_per_s = 80\n"
         "force_ratio = 0.26\nedge_coefficient_n_per_mm = 75\ncutting_coefficient_n_per_mm2 = 10020\n"
         "impacts_per_turn = 1.29\n" +
         extra;
}

std::string error_of(const std::string& text) {
  try {
    parse_grinding_config(text, "g.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& hay, const std::string& needle) { return hay.find(needle) != std::string::npos; }

TEST(GrindingConfig, ShippedConfigsLoadWithoutWarnings) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(kSource / "configs")) {
    if (!e.path().filename().string().starts_with("grinding_")) continue;
    ++n;
    const GrindingConfig c = load_grinding_config(e.path());
    EXPECT_TRUE(c.warnings.empty()) << e.path() << ": " << (c.warnings.empty() ? "" : c.warnings.front());
    EXPECT_EQ(c.process.validate(), "");
  }
  EXPECT_GE(n, 2);
  // Seed 001 ch. 4: the impacts table, the partition, the robot mode.
  const GrindingConfig s = load_grinding_config(kSource / "configs/grinding_scompi_ch4.toml");
  ASSERT_TRUE(s.process.mechanistic);
  EXPECT_DOUBLE_EQ(s.process.mechanistic->edge_coefficient_n_per_m, 75e3);
  EXPECT_DOUBLE_EQ(s.process.mechanistic->cutting_coefficient_n_per_m2, 10020e6);
  EXPECT_EQ(s.process.mechanistic->impacts.power_w().size(), 4u);
  EXPECT_DOUBLE_EQ(s.process.mechanistic->impacts.at(1000), 1.29);
  EXPECT_EQ(s.robot.tool.modes.size(), 1u);
  // Seed 000: the wheel speed from the motor and the transmission.
  const GrindingConfig u = load_grinding_config(kSource / "configs/grinding_underwater_seed000.toml");
  EXPECT_DOUBLE_EQ(u.process.wheel.speed_rev_per_s * 60.0, 2250.0);
  EXPECT_FALSE(u.process.mechanistic.has_value());
  ASSERT_TRUE(u.process.empirical.wear);
  EXPECT_EQ(u.process.empirical.wear->form, grinding::EmpiricalForm::kPoly33);
  ASSERT_TRUE(u.process.no_load_loss);
  // Its illustrative motor map through annex VI's screen point.
  ASSERT_TRUE(u.process.motor);
  EXPECT_DOUBLE_EQ(u.process.transmission_ratio, 1.125);
  EXPECT_NEAR(u.process.motor->power_w(19.0, 2000.0, nullptr), 2491.4, 1e-6);
  EXPECT_EQ(*u.process.motor->max_current_a, 19.0);
  const std::string bad = error_of(minimal("[grinding.motor]\nform = \"power_law\"\ncoefficients = [1, 2, 3]\n"));
  EXPECT_TRUE(has(bad, "grinding.motor.form = \"power_law\": must be \"poly11\", \"poly22\" or \"poly33\"")) << bad;
  const std::string count = error_of(minimal("[grinding.motor]\nform = \"poly22\"\ncoefficients = [1, 2, 3]\n"));
  EXPECT_TRUE(has(count, "grinding.motor.coefficients = [1, 2, 3]: must hold 6 numbers")) << count;
}

// Seed 000's use of its empirical models: the power for a target removal
// (issue 44: refused without a mechanistic model). The inversion is the
// forward model read back: Z(P) at 1 500 W, then the power for that Z.
TEST(GrindingConfig, EmpiricalRemovalInvertedInItsTestedPowerRange) {
  const GrindingConfig u = load_grinding_config(kSource / "configs/grinding_underwater_seed000.toml");
  const grinding::Prediction forward = grinding::predict_at_power(u.process, 1500.0);
  const grinding::Prediction back = grinding::predict_for_removal(u.process, forward.removal_rate_m3_per_s);
  EXPECT_NEAR(back.power_w, 1500.0, 1e-8 * 1500.0);
  EXPECT_NEAR(back.removal_rate_m3_per_s, forward.removal_rate_m3_per_s, 1e-9 * forward.removal_rate_m3_per_s);
  EXPECT_EQ(back.mode, "target_removal");
  EXPECT_EQ(back.removal_source, "empirical");
  try {
    grinding::predict_for_removal(u.process, 5000e-9);
    FAIL() << "5000 mm^3/s accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("over its tested power range 1106 to 2751 W"), std::string::npos) << e.what();
  }
}

TEST(GrindingConfig, LobeLoaderRefusesAGrindingConfig) {
  try {
    load_config(kSource / "configs/grinding_scompi_ch4.toml");
    FAIL() << "a grinding config loaded as a lobe config";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), "grinding_scompi_ch4.toml: grinding: a grinding config")) << e.what();
    EXPECT_TRUE(has(e.what(), "chatter grind")) << e.what();
  }
  // And the grinding loader refuses a lobe config's tables.
  const std::string err = error_of(minimal("[process]\noperation = \"turning\"\n"));
  EXPECT_TRUE(has(err, "g.toml: process: not in a grinding config")) << err;
  EXPECT_TRUE(has(error_of("name = \"x\"\n"), "g.toml: grinding: missing")) << error_of("name = \"x\"\n");
}

TEST(GrindingConfig, EveryErrorAtOnceWithFileKeyAndRule) {
  const std::string err = error_of(
      "[grinding]\nwheel_diameter_mm = -230\nwheel_width_mm = 6.8\nwheel_rpm = 6000\nfeed_mm_per_s = 0\n"
      "force_ratio = 0.26\nedge_coefficient_n_per_mm = 75\ncutting_coefficient_n_per_mm2 = 10020\n"
      "impacts_per_turn = 1.29\nwheel_widht_mm = 3\n");
  EXPECT_TRUE(has(err, "g.toml: grinding.wheel_diameter_mm = -230: must be > 0")) << err;
  EXPECT_TRUE(has(err, "g.toml: grinding.feed_mm_per_s = 0: must be > 0")) << err;
  EXPECT_TRUE(has(err, "g.toml: grinding.wheel_widht_mm: unknown key (did you mean wheel_width_mm?)")) << err;
  // Missing keys name their unit.
  const std::string missing = error_of("[grinding]\nwheel_width_mm = 6.8\nwheel_rpm = 6000\nforce_ratio = 0.3\n"
                                       "[grinding.models.removal]\nform = \"poly11\"\ncoefficients = [1, 2, 3]\n");
  EXPECT_TRUE(has(missing, "grinding.wheel_diameter_mm: missing (required, mm, > 0)")) << missing;
  EXPECT_TRUE(has(missing, "grinding.feed_mm_per_s: missing (required, mm/s, > 0)")) << missing;
}

TEST(GrindingConfig, ImpactsTableMustIncreaseInPower) {
  const std::string err = error_of(
      "[grinding]\nwheel_diameter_mm = 230\nwheel_width_mm = 6.8\nwheel_rpm = 6000\nfeed_mm_per_s = 80\n"
      "force_ratio = 0.26\nedge_coefficient_n_per_mm = 75\ncutting_coefficient_n_per_mm2 = 10020\n"
      "[[grinding.impacts]]\npower_w = 1000\nimpacts_per_turn = 1.29\n"
      "[[grinding.impacts]]\npower_w = 500\nimpacts_per_turn = 0.75\n");
  EXPECT_TRUE(has(err, "g.toml: grinding.impacts[1].power_w = 500: must increase from row to row (the previous row "
                       "has 1000 W)"))
      << err;
  EXPECT_TRUE(has(error_of(minimal("[[grinding.impacts]]\npower_w = 500\nimpacts_per_turn = 1\n")),
                  "not with impacts_per_turn"));
  // The mechanistic model is all or nothing.
  EXPECT_TRUE(has(error_of("[grinding]\nwheel_diameter_mm = 230\nwheel_width_mm = 6.8\nwheel_rpm = 6000\n"
                           "feed_mm_per_s = 80\nforce_ratio = 0.26\nedge_coefficient_n_per_mm = 75\n"),
                  "grinding.cutting_coefficient_n_per_mm2: missing"));
}

TEST(GrindingConfig, WheelSpeedOneWay) {
  const GrindingConfig c = parse_grinding_config(
      "[grinding]\nwheel_diameter_mm = 155\nwheel_width_mm = 25\nmotor_rpm = 2000\ntransmission_ratio = 1.125\n"
      "feed_mm_per_s = 50\nforce_ratio = 0.5\n[grinding.models.removal]\nform = \"poly11\"\n"
      "coefficients = [63.1, -5.05, 0.0439]\n",
      "g.toml");
  EXPECT_DOUBLE_EQ(c.process.wheel.speed_rev_per_s, 2250.0 / 60.0);
  EXPECT_TRUE(has(error_of(minimal("motor_rpm = 2000\ntransmission_ratio = 1.1\n")), "not with wheel_rpm"));
}

TEST(GrindingConfig, PlausibilityWarningsNameTheLikelyUnit) {
  // An edge coefficient written in N/m under the N/mm key, a feed in m/s.
  const GrindingConfig c = parse_grinding_config(
      "[grinding]\nwheel_diameter_mm = 230\nwheel_width_mm = 6.8\nwheel_rpm = 6000\nfeed_mm_per_s = 0.08\n"
      "force_ratio = 0.26\nedge_coefficient_n_per_mm = 75000\ncutting_coefficient_n_per_mm2 = 10020\n"
      "impacts_per_turn = 1.29\n",
      "g.toml");
  ASSERT_EQ(c.warnings.size(), 2u);
  EXPECT_TRUE(has(c.warnings[0], "g.toml: grinding.feed_mm_per_s = 0.08: outside the 1 to 500 mm/s")) << c.warnings[0];
  EXPECT_TRUE(has(c.warnings[0], "is it in m/s (feed_mm_per_s = 80)?")) << c.warnings[0];
  EXPECT_TRUE(has(c.warnings[1], "grinding.edge_coefficient_n_per_mm = 75000: outside")) << c.warnings[1];
  EXPECT_TRUE(has(c.warnings[1], "is it in N/m (edge_coefficient_n_per_mm = 75)?")) << c.warnings[1];
  // Far beyond: an error, with the likely unit.
  EXPECT_TRUE(has(error_of(minimal("").replace(minimal("").find("10020"), 5, "1.002e10")),
                  "cutting_coefficient_n_per_mm2 = 1.002e10: must be <= 1e9 N/mm^2 (a value in N/m^2? divide it by 1e6)"));
}

TEST(GrindingConfig, EmpiricalModelRules) {
  const std::string base = "[grinding]\nwheel_diameter_mm = 155\nwheel_width_mm = 25\nwheel_rpm = 2250\n"
                           "feed_mm_per_s = 50\nforce_ratio = 0.5\n";
  EXPECT_TRUE(has(error_of(base + "[grinding.models.removal]\nform = \"poly22\"\ncoefficients = [1, 2, 3]\n"),
                  "grinding.models.removal.coefficients = [1, 2, 3]: must hold 6 numbers for form = \"poly22\""));
  EXPECT_TRUE(has(error_of(base + "[grinding.models.removal]\nform = \"poly4\"\ncoefficients = [1]\n"),
                  "grinding.models.removal.form = \"poly4\": must be \"poly11\""));
  EXPECT_TRUE(has(error_of(base + "[grinding.models.removal]\nform = \"hahn_lindsay\"\ncoefficients = [1, 2]\n"
                                  "variables = [\"cutting_speed_m_per_s\", \"useful_power_w\"]\n"),
                  "hahn_lindsay reads the normal force"));
  EXPECT_TRUE(has(error_of(base + "[grinding.models.removal]\nform = \"poly11\"\ncoefficients = [1, 2, 3]\n"
                                  "[grinding.models.removal.domain]\nuseful_power_w = [2000, 1000]\n"),
                  "grinding.models.removal.domain.useful_power_w = [2000, 1000]: must be [low, high] with low < high"));
  EXPECT_TRUE(has(error_of(base + "[grinding.energy_partition]\nmodel = \"power\"\nalpha = 0.76\nbeta = 0.27\n"
                                  "[grinding.models.removal]\nform = \"poly11\"\ncoefficients = [1, 2, 3]\n"),
                  "it needs the mechanistic model"));
}

// Seed 001 table 2.2 as a config reads it, and its rules.
TEST(GrindingConfig, BetaTableByPowerAndFeed) {
  const GrindingConfig c = load_grinding_config(kSource / "configs/grinding_scompi_power_partition.toml");
  ASSERT_TRUE(c.process.partition && c.process.partition->beta_table);
  const auto& rows = c.process.partition->beta_table->rows();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_DOUBLE_EQ(rows[0].feed_m_per_s, 0.040);
  EXPECT_EQ(rows[2].beta, (std::vector<double>{0.27, 0.17, 0.09, 0.05, 0.03}));
  EXPECT_EQ(c.process.partition->beta_at(1500, 0.060, nullptr), 0.13);
  const std::string power = "[grinding.energy_partition]\nmodel = \"power\"\nalpha = 0.76\n";
  const std::string row = "[[grinding.energy_partition.beta_table]]\nfeed_mm_per_s = 80\n";
  EXPECT_TRUE(has(error_of(minimal(power + "beta = 0.2\n" + row + "power_w = [1000]\nbeta = [0.2]\n")),
                  "grinding.energy_partition.beta_table"))
      << error_of(minimal(power + "beta = 0.2\n" + row + "power_w = [1000]\nbeta = [0.2]\n"));
  const std::string short_row = error_of(minimal(power + row + "power_w = [1000, 1500]\nbeta = [0.2]\n"));
  EXPECT_TRUE(has(short_row, "grinding.energy_partition.beta_table[0].beta = [0.2]: must hold one beta per power"))
      << short_row;
  const std::string down = error_of(minimal(power + row + "power_w = [1500, 1000]\nbeta = [0.2, 0.1]\n"));
  EXPECT_TRUE(has(down, "grinding.energy_partition.beta_table[0].power_w[1] = 1000: the powers must increase")) << down;
  const std::string feeds =
      error_of(minimal(power + row + "power_w = [1000]\nbeta = [0.2]\n" + row + "power_w = [1000]\nbeta = [0.2]\n"));
  EXPECT_TRUE(has(feeds, "beta_table[1].feed_mm_per_s = 80: must increase from row to row")) << feeds;
  EXPECT_TRUE(has(error_of(minimal(power + row + "power_w = [1000]\nbeta = [1.5]\n")), "in [0, 1]"));
  EXPECT_TRUE(has(error_of(minimal(power)), "grinding.energy_partition.beta: missing"));
}

// ------------------------------------------------------------- tests tables

class GrindingFiles : public ::testing::Test {
 protected:
  fs::path dir_;
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("chatter_grinding_files_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  std::string error_reading(const std::string& text) {
    try {
      read_grinding_tests(write("t.csv", text), {});
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(GrindingFiles, MalformedTestsTables) {
  EXPECT_TRUE(has(error_reading(""), "t.csv: empty"));
  EXPECT_TRUE(has(error_reading("power_w,removal_mm3_per_s\n"), "no data rows"));
  EXPECT_TRUE(has(error_reading("power_w,removel_mm3_per_s\n1,2\n"),
                  "t.csv: line 1: unknown column 'removel_mm3_per_s' (did you mean removal_mm3_per_s?)"));
  EXPECT_TRUE(has(error_reading("power_w,removal_mm3_per_s\n1000,abc\n"),
                  "t.csv: line 2: removal_mm3_per_s = 'abc': must be a finite number"));
  EXPECT_TRUE(has(error_reading("power_w,removal_mm3_per_s\n-5,3\n"), "t.csv: line 2: power_w = '-5': must be > 0"));
  EXPECT_TRUE(has(error_reading("power_w,removal_mm3_per_s\n1,2,3\n"), "t.csv: line 2: 3 values for 2 columns"));
  EXPECT_TRUE(has(error_reading("power_w,removed_volume_mm3\n1000,50\n"), "needs grinding_time_s"));
  EXPECT_TRUE(has(error_reading("power_w,power_w\n1,1\n"), "column power_w appears twice"));
  EXPECT_TRUE(has(error_reading("wheel_diameter_before_mm,wheel_diameter_after_mm,grinding_time_s,wheel_width_mm\n"
                                "150,151,10,25\n"),
                  "the wheel cannot grow"));
}

TEST_F(GrindingFiles, DerivedColumns) {
  const auto t = read_grinding_tests(
      write("t.csv", "# a comment\npower_w,removed_volume_mm3,grinding_time_s,wheel_diameter_before_mm,"
                     "wheel_diameter_after_mm,normal_force_n,wheel_diameter_mm,wheel_rpm,wheel_width_mm,feed_mm_per_s\n"
                     "2093,941.6,17.7,163.8,163.4,219,163.4,2244,25,50\n"),
      {});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_NEAR(*t[0].removal_mm3_per_s, 941.6 / 17.7, 1e-12);
  const double wear = 3.14159265358979 * 25 * (163.8 * 163.8 - 163.4 * 163.4) / 4 / 17.7;
  EXPECT_NEAR(*t[0].wear_mm3_per_s, wear, 1e-9 * wear);
  const double vc = 3.14159265358979 * 0.1634 * 2244 / 60;
  EXPECT_NEAR(*t[0].cutting_speed_m_per_s, vc, 1e-12);
  EXPECT_NEAR(*t[0].friction_coefficient, 2093 / (vc * 219), 1e-12);  // seed 000 table 6.2: about 0.5
  EXPECT_NEAR(*t[0].g_ratio, *t[0].removal_mm3_per_s / wear, 1e-12);
  EXPECT_NEAR(*t[0].depth_per_pass_mm, *t[0].removal_mm3_per_s / (50 * 25), 1e-12);
  // Specific energy P / Z_w: 2093 W over 941.6 / 17.7 mm^3/s = 39.34 J/mm^3.
  EXPECT_NEAR(*t[0].specific_energy_j_per_mm3, 2093.0 * 17.7 / 941.6, 1e-12);
}

// A test with an empty cell for one target leaves that fit, and the fit
// says so (issue 44: it was dropped silently).
TEST_F(GrindingFiles, AnEmptyCellIsLeftOutOfThatFitAndSaid) {
  const fs::path tests = kSource / "examples/grinding/underwater_tests_seed000.csv";
  const GrindingFitReport all = fit_grinding_tests(read_grinding_tests(tests, {}), "poly11", "", tests.string());
  for (const auto& t : all.targets)
    for (const std::string& w : t.fit.warnings) EXPECT_EQ(w.find("left out"), std::string::npos) << w;
  // The same table with the first test's removal blanked.
  std::ifstream in(tests);
  std::string header, first, text;
  std::getline(in, header);
  while (header.rfind('#', 0) == 0) std::getline(in, header);
  std::getline(in, first);
  std::vector<std::string> names, cells;
  for (std::istringstream h(header); std::getline(h, text, ',');) names.push_back(text);
  for (std::istringstream c(first); std::getline(c, text, ',');) cells.push_back(text);
  const auto col = std::find(names.begin(), names.end(), "removal_mm3_per_s") - names.begin();
  ASSERT_LT(static_cast<std::size_t>(col), cells.size()) << header;
  cells[static_cast<std::size_t>(col)].clear();
  std::ostringstream blank;
  blank << header << "\n";
  for (std::size_t i = 0; i < cells.size(); ++i) blank << (i ? "," : "") << cells[i];
  blank << "\n" << std::string(std::istreambuf_iterator<char>(in), {});
  const GrindingFitReport r =
      fit_grinding_tests(read_grinding_tests(write("blank.csv", blank.str()), {}), "poly11", "", "blank.csv");
  ASSERT_EQ(r.targets[0].name, "removal");
  EXPECT_EQ(r.targets[0].rows.size(), all.targets[0].rows.size() - 1);
  const auto& w = r.targets[0].fit.warnings;
  EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](const std::string& s) {
    return s.find("have no value: left out of this fit (11 of 12 tests)") != std::string::npos;
  })) << (w.empty() ? "" : w.front());
}

TEST_F(GrindingFiles, FitFragmentLoadsBack) {
  // Seed 000's printed tests: poly11 on the power; the fragment is a config.
  const fs::path tests = kSource / "examples/grinding/underwater_tests_seed000.csv";
  const GrindingFitReport r = fit_grinding_tests(read_grinding_tests(tests, {}), "poly11", "", tests.string());
  ASSERT_EQ(r.targets.size(), 3u);  // removal, wear, normal force
  const GrindingConfig c = parse_grinding_config(grinding_fit_fragment(r, std::nullopt), "fragment.toml");
  ASSERT_TRUE(c.process.empirical.removal);
  // The fragment prints 10 significant digits.
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_NEAR(c.process.empirical.removal->coefficients[i], r.targets[0].fit.coefficients[i],
                1e-9 * std::abs(r.targets[0].fit.coefficients[i]));
  EXPECT_TRUE(c.process.empirical.removal->domain.useful_power_w.has_value());
  // The fit's statistics travel with the model: the intervals of a
  // prediction from the loaded config are the fit's own.
  ASSERT_TRUE(c.process.empirical.removal->uncertainty);
  const grinding::FitUncertainty& u = *c.process.empirical.removal->uncertainty;
  EXPECT_EQ(u.degrees_of_freedom, 9);
  EXPECT_NEAR(u.residual_variance, r.targets[0].fit.uncertainty.residual_variance,
              1e-9 * r.targets[0].fit.uncertainty.residual_variance);
  for (std::size_t i = 0; i < 9; ++i)
    EXPECT_NEAR(u.covariance[i], r.targets[0].fit.uncertainty.covariance[i],
                1e-9 * std::abs(r.targets[0].fit.uncertainty.covariance[i]));
  // Seed 000's printed tests at the annex VI point (155.33 mm, 2250 rev/min,
  // 2021 W): the confidence of the mean, by hand from the covariance.
  {
    grinding::Process q = c.process;
    q.wheel.diameter_m = 0.15533;
    q.wheel.speed_rev_per_s = 2250.0 / 60.0;
    const grinding::Prediction pr = grinding::predict_at_power(q, 2021.0);
    ASSERT_TRUE(pr.empirical && pr.empirical->removal_interval);
    const double g[3] = {1.0, pr.cutting_speed_m_per_s, 2021.0};
    double var = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) var += g[i] * u.covariance[static_cast<std::size_t>(3 * i + j)] * g[j];
    EXPECT_NEAR(pr.empirical->removal_interval->standard_error_mean, std::sqrt(var), 1e-9 * std::sqrt(var));
  }
  // A covariance of the wrong shape is refused with its key.
  const std::string bad = error_of(minimal("[grinding.models.removal]\nform = \"poly11\"\ncoefficients = [1, 2, 3]\n"
                                           "[grinding.models.removal.fit]\nresidual_variance = 1\n"
                                           "degrees_of_freedom = 5\ncovariance = [[1, 0], [0, 1]]\n"));
  EXPECT_TRUE(has(bad, "grinding.models.removal.fit.covariance = [[1, 0], [0, 1]]: must be 3 rows of 3 numbers")) << bad;
  // The annex IV removal model (fitted to all 82 tests) lies inside the 95 %
  // intervals of the fit to the 12 tests the thesis prints.
  const double annex[] = {63.1, -5.05, 0.0439};
  for (int i = 0; i < 3; ++i) {
    EXPECT_GE(annex[i], r.targets[0].fit.lower_95[static_cast<std::size_t>(i)]) << i;
    EXPECT_LE(annex[i], r.targets[0].fit.upper_95[static_cast<std::size_t>(i)]) << i;
  }
  // Mechanistic: the synthetic tests of seed 001's model give a loadable table too.
  const fs::path mt = kSource / "examples/grinding/scompi_tests_synthetic.csv";
  const GrindingFitReport m = fit_grinding_tests(read_grinding_tests(mt, {}), "mechanistic", "", mt.string());
  const GrindingConfig mc = parse_grinding_config(grinding_fit_fragment(m, std::nullopt), "fragment.toml");
  ASSERT_TRUE(mc.process.mechanistic);
  EXPECT_TRUE(mc.process.mechanistic->impacts.is_table());
  // The fit needs the columns of its model, named with the line.
  try {
    fit_grinding_tests(read_grinding_tests(write("m.csv", "power_w,removal_mm3_per_s\n1000,52\n"), {}), "mechanistic",
                       "", "m.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), "m.csv: line 2: the mechanistic fit needs impacts_per_turn")) << e.what();
  }
}

TEST_F(GrindingFiles, ImpactRecords) {
  EXPECT_THROW(read_impact_record(write("r.csv", "time_s,normal_force_n\n0,1\n0.1,2\n0.05,3\n")), InputError);
  EXPECT_THROW(read_impact_record(write("r.csv", "time_s\n0\n1\n2\n")), InputError);
  EXPECT_THROW(read_impact_record(write("r.csv", "time_s,normal_force_n,wheel_rpm\n0,1,2\n1,1,2\n2,1,2\n")), InputError);
  const ImpactRecord r = read_impact_record(write("r.csv", "time_s,wheel_rpm\n0,6000\n1e-3,5990\n2e-3,6000\n"));
  EXPECT_EQ(r.kind, grinding::ImpactSignal::kWheelSpeed);
  EXPECT_EQ(r.time_s.size(), 3u);
}

}  // namespace
}  // namespace chatter
