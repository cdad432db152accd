// No internal error on accepted input (issue 26, item 4): every command runs
// on configs at the extremes the config validation accepts (a mode of 1 N/m
// or 1e15 N/m, 0.1 Hz or 1e6 Hz, damping 1e-6 or 0.99, K_t = 1e13 N/m², a
// radial immersion of 1e-6, a thousand teeth, a helix of 89.9°). Each run
// must end with a verdict (0 or 3) or refuse the input with the rule (2):
// never an internal error (1), a crash, or a NaN / inf in its JSON.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace chatter::test {
namespace {

using nlohmann::json;

struct Extreme {
  std::string name;
  std::string toml;
  double rpm;
};

const std::string kMilling = R"([process]
operation = "milling"
teeth = TEETH
tangential_coefficient_n_per_m2 = KT
radial_coefficient_n_per_m2 = 2e8
radial_immersion = AE
tool_diameter_mm = 12
HELIX
[[tool.modes]]
frequency_hz = FREQ
damping_ratio = ZETA
stiffness_n_per_m = K
direction = "x"
)";

std::string milling(const std::string& teeth = "2", const std::string& kt = "6e8", const std::string& ae = "0.05",
                    const std::string& helix = "", const std::string& f = "922", const std::string& zeta = "0.011",
                    const std::string& k = "1.34e6") {
  std::string s = kMilling;
  auto put = [&](const std::string& key, const std::string& v) { s.replace(s.find(key), key.size(), v); };
  put("TEETH", teeth);
  put("KT", kt);
  put("AE", ae);
  put("HELIX", helix);
  put("FREQ", f);
  put("ZETA", zeta);
  put("K", k);
  return s;
}

std::string turning(const std::string& f, const std::string& zeta, const std::string& k) {
  return "[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = 2.4e9\n[[workpiece.modes]]\n"
         "frequency_hz = " + f + "\ndamping_ratio = " + zeta + "\nstiffness_n_per_m = " + k + "\ndirection = \"x\"\n";
}

std::vector<Extreme> extremes() {
  return {
      {"soft_mode", milling("2", "6e8", "0.05", "", "922", "0.011", "1"), 12000},
      {"stiff_mode", milling("2", "6e8", "0.05", "", "922", "0.011", "1e15"), 12000},
      {"slow_mode", turning("0.1", "0.03", "4.5e7"), 1000},
      {"fast_mode", milling("2", "6e8", "0.05", "", "1e5", "0.011", "1e8"), 20000},
      {"undamped", milling("2", "6e8", "0.05", "", "922", "1e-6", "1.34e6"), 12000},
      {"overdamped", turning("94.22", "0.99", "4.5e7"), 1000},
      {"huge_coefficient", milling("2", "1e13", "0.05"), 12000},
      {"sliver_immersion", milling("2", "6e8", "1e-6"), 12000},
      {"thousand_teeth", milling("1000", "6e8", "1"), 100},
      {"steep_helix", milling("4", "6e8", "0.5", "helix_angle_deg = 89.9"), 12000},
  };
}

// Every number of a JSON value is finite (null stands for "none").
bool all_finite(const json& j, std::string& where) {
  if (j.is_number_float()) return std::isfinite(j.get<double>());
  if (j.is_array() || j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!all_finite(*it, where)) {
        where = (j.is_object() ? it.key() : std::string("[]")) + "." + where;
        return false;
      }
  }
  return true;
}

class Extremes : public CliFixture, public ::testing::WithParamInterface<Extreme> {
 protected:
  // Runs the command; it must end with 0, 2 or 3 (never 1 or a crash), and
  // its JSON (stdout, when asked) must hold finite numbers only.
  void expect_handled(const std::vector<std::string>& args, bool json_on_stdout) {
    const RunResult r = run(args);
    std::string cmd;
    for (const auto& a : args) cmd += a + " ";
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 2 || r.exit_code == 3) << cmd << "\nexit " << r.exit_code << "\n"
                                                                           << r.err;
    EXPECT_FALSE(contains(r.err, "internal error")) << cmd << "\n" << r.err;
    if (r.exit_code == 2) {
      EXPECT_TRUE(contains(r.err, "chatter: ")) << cmd << ": refused without a message\n" << r.err;
      return;
    }
    if (!json_on_stdout || r.exit_code == 1) return;
    const json j = json::parse(r.out, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << cmd << ": not JSON:\n" << r.out;
    std::string where;
    EXPECT_TRUE(all_finite(j, where)) << cmd << ": a non-finite number at " << where;
  }
};

TEST_P(Extremes, EveryCommandEndsWithAVerdictOrARule) {
  const Extreme& e = GetParam();
  const fs::path cfg = path(e.name + ".toml");
  std::ofstream(cfg) << e.toml;
  const std::string c = cfg.string();
  const std::string rpm = std::to_string(e.rpm), lo = std::to_string(0.8 * e.rpm), hi = std::to_string(1.2 * e.rpm);
  for (const char* method : {"auto", "analytic"})
    expect_handled({"point", c, "--method", method, "--rpm", rpm, "--depth-mm", "0.5"}, true);
  const fs::path table = path("t.json");
  expect_handled({"lobes", c, "--rpm-min", lo, "--rpm-max", hi, "--rpm-points", "3", "--json", table.string(),
                  "--quiet"},
                 false);
  if (fs::exists(table)) {
    const json t = json::parse(std::ifstream(table), nullptr, false);
    std::string where;
    EXPECT_TRUE(!t.is_discarded() && all_finite(t, where)) << "lobes JSON: " << where;
  }
  const fs::path ops = path("ops.csv");
  std::ofstream(ops) << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\nr," << rpm << ",0.5,,\n";
  expect_handled({"check", c, "--operations", ops.string(), "--rpm-min", lo, "--rpm-max", hi, "--json", "-",
                  "--quiet"},
                 true);
  expect_handled({"simulate", c, "--rpm", rpm, "--depth-mm", "0.5", "--periods", "20"}, true);
  if (e.name == "soft_mode") {  // 30 m of static deflection: a runaway, refused with the likely cause
    const RunResult s = run({"simulate", c, "--rpm", rpm, "--depth-mm", "0.5", "--periods", "20"});
    EXPECT_EQ(s.exit_code, 2);
    EXPECT_TRUE(contains(s.err, "no machine structure moves that far") && contains(s.err, "wrong unit")) << s.err;
  }
}

INSTANTIATE_TEST_SUITE_P(AcceptedExtremes, Extremes, ::testing::ValuesIn(extremes()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace chatter::test
