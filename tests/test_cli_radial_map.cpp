// `chatter map --axes radial-axial` (issue 31 item 4), end to end: the
// map's boundary (one sdm limit search per radial immersion) against
// independent answers — `chatter point` at the config's own immersion, and
// `chatter lobes --method sdm` of configs rewritten with other immersions —
// the grid against its boundary, the table's columns, the plot, and bad input
// (exit 2, a message naming the flag and its rule, nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace fs = std::filesystem;
using chatter::test::CliFixture;
using chatter::test::contains;
using chatter::test::RunResult;
using chatter::test::slurp;
using nlohmann::json;

namespace {

// The sdm limit search stops when the bracket is below depth_tolerance
// (relative, 1e-4 by default): two searches of the same problem agree to it.
constexpr double kDepthTolerance = 1e-4;

const fs::path kCaseC = fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_benchmark_ae005_down.toml";

// The config's text with `radial_immersion = ...` replaced (and, if given,
// a tool diameter added to [process]).
std::string with_immersion(const std::string& text, double immersion, double diameter_mm = 0.0) {
  char value[64];
  std::snprintf(value, sizeof value, "%.17g", immersion);
  std::string out = std::regex_replace(text, std::regex(R"(radial_immersion\s*=\s*[0-9.eE+-]+)"),
                                       std::string("radial_immersion = ") + value);
  if (diameter_mm > 0.0)
    out = std::regex_replace(out, std::regex(R"(\[process\]\n)"),
                             "[process]\ntool_diameter_mm = " + std::to_string(diameter_mm) + "\n");
  return out;
}

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) v.push_back(l);
  return v;
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> v;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, ',');) v.push_back(f);
  return v;
}

class RadialMap : public CliFixture {
 protected:
  void expect_rejected(const std::vector<std::string>& args, const std::vector<std::string>& words) {
    const fs::path out = path("m.csv"), js = path("m.json");
    std::vector<std::string> all{"map"};
    all.insert(all.end(), args.begin(), args.end());
    all.insert(all.end(), {"--out", out.string(), "--json", js.string()});
    const RunResult r = run(all);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    for (const auto& w : words) EXPECT_TRUE(contains(r.err, w)) << "missing '" << w << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(js));
  }
};

// At a_e equal to the config's immersion the boundary is `chatter point`'s
// limit at that speed (same solver, same depth searched); at other
// immersions it is `chatter lobes --method sdm` of the config rewritten with
// that immersion.
TEST_F(RadialMap, BoundaryIsTheSdmLimitOfEachImmersion) {
  const std::string base = slurp(kCaseC);
  for (const char* rpm : {"10000", "16000"}) {
    SCOPED_TRACE(std::string("rpm ") + rpm);
    const RunResult r = run({"map", kCaseC.string(), "--axes", "radial-axial", "--rpm", rpm, "--immersion-min", "0.05",
                             "--immersion-max", "0.5", "--immersion-points", "10", "--depth-points", "21", "--json",
                             path("map.json").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(slurp(path("map.json")));
    EXPECT_EQ(j.at("axes"), "radial-axial");
    const json& b = j.at("boundary");
    ASSERT_EQ(b.size(), 10u);
    EXPECT_EQ(b[0].at("radial_immersion").get<double>(), 0.05);  // the config's own immersion

    const RunResult p = run({"point", kCaseC.string(), "--method", "sdm", "--rpm", rpm, "--depth-mm", "1"});
    ASSERT_EQ(p.exit_code, 0) << p.err;
    const double point_limit = json::parse(p.out).at("depth_limit_mm").get<double>();
    const double map_limit = b[0].at("depth_limit_mm").get<double>();
    EXPECT_NEAR(map_limit, point_limit, kDepthTolerance * point_limit)
        << "map boundary " << map_limit << " mm, point " << point_limit << " mm";
    std::printf("[ radial  ] %s rev/min, a_e/D = 0.05: map boundary %.9g mm, chatter point %.9g mm\n", rpm, map_limit,
                point_limit);

    for (const std::size_t i : {2u, 5u, 9u}) {
      const double e = b[i].at("radial_immersion").get<double>();
      const fs::path cfg = path("ae" + std::to_string(i) + ".toml");
      std::ofstream(cfg) << with_immersion(base, e);
      const fs::path table = path("lobes" + std::to_string(i) + ".csv");
      const RunResult l = run({"lobes", cfg.string(), "--method", "sdm", "--rpm-min", rpm, "--rpm-max",
                               std::to_string(std::stod(rpm) + 1.0), "--rpm-points", "2", "--table", table.string(),
                               "--quiet"});
      ASSERT_EQ(l.exit_code, 0) << l.err;
      const double lobes_limit = std::stod(fields(lines_of(slurp(table)).at(1)).at(1));
      const double got = b[i].at("depth_limit_mm").get<double>();
      EXPECT_NEAR(got, lobes_limit, kDepthTolerance * lobes_limit) << "a_e/D = " << e;
      std::printf("[ radial  ] %s rev/min, a_e/D = %.3g: map boundary %.9g mm, lobes of that config %.9g mm\n", rpm, e,
                  got, lobes_limit);
    }
  }
}

// The grid agrees with its boundary: at every immersion the depths below the
// searched limit are stable (rho < 1) and the first unstable depth is not
// below it. Depth 0 is stable everywhere.
TEST_F(RadialMap, GridAgreesWithItsBoundaryAndTheTableHasUnits) {
  std::ofstream(path("d10.toml")) << with_immersion(slurp(kCaseC), 0.05, 10.0);
  const RunResult r = run({"map", path("d10.toml").string(), "--axes", "radial-axial", "--rpm", "12000",
                           "--immersion-points", "8", "--depth-points", "26", "--out", path("map.csv").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lines = lines_of(slurp(path("map.csv")));
  ASSERT_EQ(lines.size(), 1u + 8u * 26u);
  EXPECT_EQ(lines[0], "radial_immersion,radial_depth_mm,depth_mm,spectral_radius,depth_limit_mm");
  for (std::size_t i = 0; i < 8; ++i) {
    bool seen_unstable = false;
    for (std::size_t k = 0; k < 26; ++k) {
      const auto f = fields(lines[1 + i * 26 + k]);
      ASSERT_EQ(f.size(), 5u);
      const double e = std::stod(f[0]), ae = std::stod(f[1]), depth = std::stod(f[2]), rho = std::stod(f[3]);
      const double limit = f[4] == "inf" ? std::numeric_limits<double>::infinity() : std::stod(f[4]);
      EXPECT_NEAR(ae, 10.0 * e, 1e-9 * ae);  // a_e = immersion x D
      if (k == 0) EXPECT_LT(rho, 1.0) << "no cut, no chatter";
      if (depth < limit * (1 - kDepthTolerance)) EXPECT_LT(rho, 1.0) << "a_e/D " << e << ", depth " << depth;
      if (rho >= 1.0 && !seen_unstable) {
        seen_unstable = true;
        EXPECT_GE(depth, limit * (1 - kDepthTolerance)) << "a_e/D " << e;
      }
    }
  }
}

TEST_F(RadialMap, PlotHasUnitsOnItsAxesAndTheSearchedLimits) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  std::ofstream(path("d10.toml")) << with_immersion(slurp(kCaseC), 0.05, 10.0);
  const RunResult r = run({"map", path("d10.toml").string(), "--axes", "radial-axial", "--rpm", "10000",
                           "--immersion-points", "6", "--depth-points", "12", "--plot", path("m.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(fs::file_size(path("m.png")), 1000u);
  const std::string gp = slurp(path("m.gp")), dat = slurp(path("m.dat"));
  EXPECT_TRUE(contains(gp, "radial depth of cut a_e (mm)")) << gp;
  EXPECT_TRUE(contains(gp, "axial depth of cut a_p (mm)")) << gp;
  EXPECT_TRUE(contains(gp, "10000 rev/min")) << gp;
  EXPECT_TRUE(contains(dat, "# radial_depth_mm depth_limit_mm")) << dat;
  EXPECT_FALSE(contains(r.out, "radial_immersion,")) << "the table goes to stdout only when nothing else is asked";
}

TEST_F(RadialMap, BadInputNamesTheFlagAndTheRule) {
  const std::string c = kCaseC.string();
  expect_rejected({c, "--axes", "speed-radial"}, {"--axes 'speed-radial'", "speed-axial", "radial-axial"});
  expect_rejected({c, "--axes", "radial-axial"}, {"--rpm: required with --axes radial-axial"});
  expect_rejected({c, "--axes", "radial-axial", "--rpm", "10000", "--immersion-min", "0"},
                  {"--immersion-min = 0: must be in (0, 1]"});
  expect_rejected({c, "--axes", "radial-axial", "--rpm", "10000", "--immersion-max", "1.5"},
                  {"--immersion-max = 1.5: must be in (0, 1]"});
  expect_rejected({c, "--axes", "radial-axial", "--rpm", "10000", "--immersion-min", "0.5", "--immersion-max", "0.2"},
                  {"--immersion-max = 0.2: must be > --immersion-min"});
  expect_rejected({c, "--axes", "radial-axial", "--rpm", "10000", "--immersion-points", "1"},
                  {"--immersion-points = 1: must be >= 2"});
  expect_rejected({c, "--axes", "radial-axial", "--rpm", "-5"}, {"--rpm"});
  expect_rejected({c, "--axes", "radial-axial", "--rpm", "10000", "--rpm-points", "5"},
                  {"--rpm-points: only with --axes speed-axial"});
  expect_rejected({c, "--rpm", "10000"}, {"--rpm: only with --axes radial-axial"});
  expect_rejected({c, "--immersion-min", "0.1"}, {"--immersion-min: only with --axes radial-axial"});
  const fs::path turning = fs::path(CHATTER_SOURCE_DIR) / "configs" / "seed_turning_1dof.toml";
  expect_rejected({turning.string(), "--axes", "radial-axial", "--rpm", "1000"}, {"turning", "radial immersion"});
}

}  // namespace
