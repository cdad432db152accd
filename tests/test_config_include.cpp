// `include = [...]` in a config (src/config/config_include.cpp, docs/config.md
// "Several files"): the merged config equals the one-file config, messages
// name the file a key is in, and cycles, clashes and unreadable files are
// refused with the files named.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;

const std::string kModes = R"(# as `chatter fit --out` writes it
[[tool.modes]]
frequency_hz = 800
damping_ratio = 0.02
stiffness_n_per_um = 8
direction = "x"
)";
const std::string kCoefficients = R"([process]
tangential_coefficient_n_per_mm2 = 600
radial_coefficient_ratio = 0.3
)";
const std::string kProcess = R"([process]
operation = "milling"
teeth = 2
tool_diameter_mm = 12
radial_depth_mm = 1.2
milling_direction = "climb"
)";

class ConfigInclude : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("chatter_include_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "parts");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }
  std::string message(const fs::path& file) const {
    try {
      (void)load_config(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(ConfigInclude, MergedConfigEqualsTheOneFileConfig) {
  write("parts/modes.toml", kModes);
  write("parts/coefficients.toml", kCoefficients);
  const fs::path main = write("main.toml", std::string("name = \"c\"\ninclude = [\"parts/modes.toml\", "
                                                       "\"parts/coefficients.toml\"]\n") + kProcess);
  const fs::path flat = write("flat.toml", std::string("name = \"c\"\n") + kProcess +
                                               "tangential_coefficient_n_per_mm2 = 600\nradial_coefficient_ratio = 0.3\n" +
                                               kModes);
  const Config a = load_config(main);
  const Config b = load_config(flat);
  ASSERT_EQ(a.model.tool.modes.size(), 1u);
  EXPECT_EQ(a.model.tool.modes[0].natural_frequency_hz, b.model.tool.modes[0].natural_frequency_hz);
  EXPECT_EQ(a.model.tool.modes[0].stiffness_n_per_m, b.model.tool.modes[0].stiffness_n_per_m);
  const MillingParameters& ma = a.process.milling_parameters();
  const MillingParameters& mb = b.process.milling_parameters();
  EXPECT_EQ(ma.tangential_coefficient_n_per_m2, mb.tangential_coefficient_n_per_m2);
  EXPECT_EQ(ma.radial_coefficient_n_per_m2, mb.radial_coefficient_n_per_m2);
  EXPECT_EQ(ma.radial_immersion, mb.radial_immersion);
  EXPECT_EQ(a.process.teeth(), b.process.teeth());
  EXPECT_EQ(a.name, "c");
}

TEST_F(ConfigInclude, NestedIncludesAreRelativeToTheirOwnFile) {
  write("parts/modes.toml", kModes);
  write("parts/both.toml", std::string("include = [\"modes.toml\"]\n") + kCoefficients);
  const fs::path main = write("main.toml", std::string("include = [\"parts/both.toml\"]\n") + kProcess);
  const Config c = load_config(main);
  EXPECT_EQ(c.model.tool.modes.size(), 1u);
  EXPECT_EQ(c.name, "main");
}

TEST_F(ConfigInclude, AnErrorNamesTheFileTheKeyIsIn) {
  const std::size_t at = kModes.find("0.02");
  ASSERT_NE(at, std::string::npos);
  const std::string bad = kModes.substr(0, at) + "2" + kModes.substr(at + 4);
  const fs::path modes = write("parts/modes.toml", bad);
  write("parts/coefficients.toml", kCoefficients);
  const fs::path main =
      write("main.toml", std::string("include = [\"parts/modes.toml\", \"parts/coefficients.toml\"]\n") + kProcess);
  const std::string m = message(main);
  EXPECT_NE(m.find(modes.string() + ": tool.modes[0].damping_ratio = 2: must be in (0, 1)"), std::string::npos) << m;
  // A key of the including file is still reported against it.
  const fs::path main2 =
      write("main2.toml", std::string("include = [\"parts/coefficients.toml\"]\n") + kProcess + "teeth_typo = 3\n" + kModes);
  const std::string m2 = message(main2);
  EXPECT_NE(m2.find(main2.string() + ": process.teeth_typo: unknown key"), std::string::npos) << m2;
}

TEST_F(ConfigInclude, AKeyInTwoFilesIsRefusedWithBothNamed) {
  const fs::path coefficients = write("coefficients.toml", std::string(kCoefficients) + "teeth = 3\n");
  write("modes.toml", kModes);
  const fs::path main = write("main.toml", std::string("include = [\"modes.toml\", \"coefficients.toml\"]\n") +
                                                kProcess + kModes);
  const std::string m = message(main);
  EXPECT_NE(m.find(coefficients.string() + ": process.teeth: also given in " + main.string()), std::string::npos) << m;
  EXPECT_EQ(m.find("tool.modes: also given"), std::string::npos) << "mode lists append: " << m;
}

// Two tap tests, each fitted to its own fragment, make one tool (issue 44:
// include = ["modes_x.toml", "modes_y.toml"] was refused); each mode's
// messages name its own file.
TEST_F(ConfigInclude, ModeListsAppendAcrossFiles) {
  std::string y = kModes;
  y.replace(y.find("800"), 3, "820");
  y.replace(y.find("\"x\""), 3, "\"y\"");
  write("modes_x.toml", kModes);
  const fs::path my = write("modes_y.toml", y);
  write("coefficients.toml", kCoefficients);
  const fs::path main = write(
      "main.toml", std::string("include = [\"modes_x.toml\", \"modes_y.toml\", \"coefficients.toml\"]\n") + kProcess);
  const fs::path flat = write("flat.toml", std::string("include = [\"coefficients.toml\"]\n") + kProcess + kModes + y);
  const Config a = load_config(main), b = load_config(flat);
  ASSERT_EQ(a.model.tool.modes.size(), 2u);
  ASSERT_EQ(b.model.tool.modes.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(a.model.tool.modes[i].natural_frequency_hz, b.model.tool.modes[i].natural_frequency_hz);
    EXPECT_EQ(a.model.tool.modes[i].direction, b.model.tool.modes[i].direction);
  }
  EXPECT_EQ(a.model.tool.modes[1].direction, Eigen::Vector2d(0.0, 1.0));
  // The including file's own modes and an included file's append too.
  const fs::path mixed = write("mixed.toml", std::string("include = [\"modes_y.toml\", \"coefficients.toml\"]\n") +
                                                 kProcess + kModes);
  EXPECT_EQ(load_config(mixed).model.tool.modes.size(), 2u);
  // A bad value in the appended mode names the file it is in.
  std::string bad = y;
  bad.replace(bad.find("0.02"), 4, "2");
  const fs::path by = write("modes_y.toml", bad);
  ASSERT_EQ(by, my);
  const std::string m = message(main);
  EXPECT_NE(m.find(my.string() + ": tool.modes[1].damping_ratio = 2: must be in (0, 1)"), std::string::npos) << m;
}

TEST_F(ConfigInclude, CyclesBadValuesAndMissingFilesAreRefused) {
  write("a.toml", "include = [\"b.toml\"]\n");
  write("b.toml", "include = [\"a.toml\"]\n");
  const fs::path main = write("main.toml", std::string("include = [\"a.toml\"]\n") + kProcess + kModes);
  EXPECT_NE(message(main).find("includes a file being included (a cycle:"), std::string::npos) << message(main);
  const fs::path self = write("self.toml", std::string("include = [\"self.toml\"]\n") + kProcess + kModes);
  EXPECT_NE(message(self).find("a cycle"), std::string::npos) << message(self);

  const fs::path missing = write("missing.toml", std::string("include = [\"nothere.toml\"]\n") + kProcess + kModes);
  EXPECT_NE(message(missing).find(missing.string() + ": include[0] = \"nothere.toml\": "), std::string::npos);
  EXPECT_NE(message(missing).find("cannot read file (no such file)"), std::string::npos) << message(missing);

  const fs::path scalar = write("scalar.toml", std::string("include = \"modes.toml\"\n") + kProcess + kModes);
  EXPECT_NE(message(scalar).find(scalar.string() + ": include: must be an array of file names"), std::string::npos);
  const fs::path number = write("number.toml", std::string("include = [3]\n") + kProcess + kModes);
  EXPECT_NE(message(number).find(number.string() + ": include[0]: must be a file name"), std::string::npos);
  const fs::path directory = write("directory.toml", std::string("include = [\"parts\"]\n") + kProcess + kModes);
  EXPECT_NE(message(directory).find("not a regular file"), std::string::npos) << message(directory);

  // A syntax error in an included file names it, its line and the include.
  const fs::path broken = write("broken.toml", "[process\n");
  const fs::path uses = write("uses.toml", std::string("include = [\"broken.toml\"]\n") + kProcess + kModes);
  const std::string m = message(uses);
  EXPECT_NE(m.find(uses.string() + ": include[0] = \"broken.toml\": " + broken.string() + ":1:"), std::string::npos)
      << m;
}

}  // namespace
}  // namespace chatter
