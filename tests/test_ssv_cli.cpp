// Spindle speed variation through the binary (docs/ssv.md): the config key
// and the flags are validated with file, key (or flag) and rule and exit 2;
// methods that cannot do it refuse, naming those that can; `point` reports
// the gain over constant speed, the ratio of its own limit to the limit
// the same command finds at constant speed.
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace {

using chatter::test::contains;
using nlohmann::json;

// Two limits searched to the sdm depth tolerance (1e-4 relative) each.
constexpr double kGainRatio = 1e-12;  // the gain is the quotient of the two printed limits

const std::string kExample = std::string(CHATTER_SOURCE_DIR) + "/configs/ssv_turning_case_a.toml";
const std::string kCaseA = std::string(CHATTER_SOURCE_DIR) + "/configs/seed_turning_1dof.toml";

class CliSsv : public chatter::test::CliFixture {
 protected:
  std::string write_config(const std::string& ssv_line) {
    const auto p = path("ssv.toml");
    std::ofstream(p) << "[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = 2.4e9\n" << ssv_line
                     << "\n[[workpiece.modes]]\nfrequency_hz = 94.22\ndamping_ratio = 0.033\n"
                        "stiffness_n_per_m = 45e6\ndirection = \"x\"\n";
    return p.string();
  }
  json point(const std::vector<std::string>& extra) {
    std::vector<std::string> args{"point"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0 ? json::parse(r.out) : json();
  }
};

TEST_F(CliSsv, BadSpeedVariationNamesFileKeyAndRule) {
  struct Case {
    std::string line, message;
  };
  for (const Case& c :
       {Case{"speed_variation = { amplitude_ratio = 1.2, frequency_ratio = 0.1 }",
             "ssv.toml: process.speed_variation.amplitude_ratio = 1.2: must be in [0, 1)"},
        Case{"speed_variation = { amplitude_ratio = 0.1 }",
             "ssv.toml: process.speed_variation.frequency_ratio: missing: speed_variation needs both"},
        Case{"speed_variation = { amplitude_ratio = 0.1, frequency_ratio = 0 }",
             "ssv.toml: process.speed_variation.frequency_ratio = 0: must be > 0"},
        Case{"speed_variation = { amplitude_ratio = 0.1, frequency_ratio = 0.1, phase = 1 }",
             "ssv.toml: process.speed_variation.phase: unknown key"},
        Case{"speed_variation = 0.1", "ssv.toml: process.speed_variation = 0.1: must be a table"}}) {
    const auto r = run({"point", write_config(c.line), "--rpm", "300", "--depth-mm", "1"});
    EXPECT_EQ(r.exit_code, 2) << c.line;
    EXPECT_TRUE(contains(r.err, c.message)) << c.line << "\n" << r.err;
  }
  // Above 30 %: accepted with a warning, refused with --strict.
  const std::string wide = write_config("speed_variation = { amplitude_ratio = 0.4, frequency_ratio = 0.1 }");
  const auto w = run({"point", wide, "--rpm", "300", "--depth-mm", "1"});
  EXPECT_EQ(w.exit_code, 0) << w.err;
  EXPECT_TRUE(contains(w.err, "warning: ") && contains(w.err, "amplitude_ratio = 0.4")) << w.err;
  EXPECT_EQ(run({"point", wide, "--rpm", "300", "--depth-mm", "1", "--strict"}).exit_code, 2);
}

TEST_F(CliSsv, FlagsAreCheckedAndNeedEachOther) {
  auto r = run({"point", kCaseA, "--rpm", "300", "--depth-mm", "1", "--ssv-amplitude", "0.1"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--ssv-amplitude: needs --ssv-frequency too")) << r.err;
  r = run({"point", kCaseA, "--rpm", "300", "--depth-mm", "1", "--ssv-amplitude", "1", "--ssv-frequency", "0.1"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--ssv-amplitude = 1: must be in [0, 1)")) << r.err;
  r = run({"lobes", kCaseA, "--ssv-amplitude", "0.1", "--ssv-frequency", "-2", "--rpm-points", "2"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--ssv-frequency = -2: must be > 0")) << r.err;
}

TEST_F(CliSsv, MethodsThatCannotRefuseNamingSdm) {
  for (const std::string method : {"analytic", "coupled"}) {
    const auto r = run({"point", kExample, "--rpm", "300", "--depth-mm", "1", "--method", method});
    EXPECT_EQ(r.exit_code, 2) << method;
    EXPECT_TRUE(contains(r.err, "method \"" + method + "\" does not handle spindle speed variation")) << r.err;
    EXPECT_TRUE(contains(r.err, "sdm")) << r.err;
    EXPECT_TRUE(contains(r.err, "time-domain")) << r.err;  // it solves SSV too
  }
}

TEST_F(CliSsv, SimulateRunsTheModulatedSpeedOverThePrincipalPeriod) {
  // Case A, R_VA 0.1, R_VF 0.1 at 300 rev/min: the period is ten
  // revolutions (2 s, sdm's); 2 mm is stable with SSV (sdm: 2.65 mm) although
  // constant speed chatters there (1.35 mm).
  auto r = run({"simulate", kExample, "--rpm", "300", "--depth-mm", "2", "--linear"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["verdict"], "stable") << j["verdict_measure"];
  EXPECT_NEAR(j["floquet_period_s"].get<double>(), 2.0, 1e-12);
  EXPECT_EQ(j["periods"], 20);  // 200 revolutions by default
  EXPECT_NEAR(j["revolutions"].get<double>(), 200.0, 1e-9);
  ASSERT_TRUE(j.contains("speed_variation"));
  EXPECT_EQ(j["speed_variation"]["frequency_ratio_used"], 0.1);
  EXPECT_EQ(j["speed_variation"]["exact_period"], true);
  EXPECT_DOUBLE_EQ(j["speed_variation"]["floquet_periods"].get<double>(), 10.0);
  // The same modulation from the flags on the constant-speed config: the same run.
  r = run({"simulate", kCaseA, "--rpm", "300", "--depth-mm", "2", "--linear", "--ssv-amplitude", "0.1",
           "--ssv-frequency", "0.1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json f = json::parse(r.out);
  EXPECT_EQ(f["growth_per_period"], j["growth_per_period"]);
  // --ssv-amplitude 0: constant speed, the constant-speed config's run bit for bit.
  r = run({"simulate", kExample, "--rpm", "300", "--depth-mm", "2", "--linear", "--ssv-amplitude", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json z = json::parse(r.out);
  r = run({"simulate", kCaseA, "--rpm", "300", "--depth-mm", "2", "--linear"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json c = json::parse(r.out);
  EXPECT_FALSE(z.contains("speed_variation"));
  EXPECT_EQ(z["growth_per_period"], c["growth_per_period"]);
  EXPECT_EQ(z["integrator"]["steps"], c["integrator"]["steps"]);
  EXPECT_EQ(z["integrator"]["rhs_evaluations"], c["integrator"]["rhs_evaluations"]);
  EXPECT_EQ(c["verdict"], "chatter");
  // --revolutions: the whole principal periods that hold them.
  r = run({"simulate", kExample, "--rpm", "300", "--depth-mm", "2", "--linear", "--revolutions", "45"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["periods"], 5);
}

TEST_F(CliSsv, TimeDomainPointAndLobesTakeSpeedVariation) {
  // 1 200 rev/min: sdm's SSV limit; the simulation's within its depth
  // tolerance (1 %) and the verdict's margin (docs/ssv.md).
  const json sdm = point({kExample, "--rpm", "1200", "--depth-mm", "2", "--method", "sdm"});
  const json td = point({kExample, "--rpm", "1200", "--depth-mm", "2", "--method", "time-domain"});
  ASSERT_TRUE(td.contains("speed_variation")) << td.dump();
  EXPECT_NEAR(td["floquet_period_s"].get<double>(), sdm["floquet_period_s"].get<double>(), 1e-12);
  const double a_sdm = sdm["depth_limit_mm"].get<double>(), a_td = td["depth_limit_mm"].get<double>();
  EXPECT_NEAR(a_td / a_sdm, 1.0, 0.03) << "sdm " << a_sdm << " mm, time-domain " << a_td << " mm";
  EXPECT_GT(td["speed_variation"]["gain"].get<double>(), 1.0);
  // lobes at the mean speed: the row at 1 200 rev/min is point's limit.
  const auto r = run({"lobes", kExample, "--method", "time-domain", "--rpm-min", "1200", "--rpm-max", "1300",
                      "--rpm-points", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream rows(r.out);
  std::string header, first;
  std::getline(rows, header);
  std::getline(rows, first);
  EXPECT_EQ(header, "spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe") << r.out;
  const double row_limit = std::stod(first.substr(first.find(',') + 1));
  EXPECT_NEAR(row_limit / a_td, 1.0, 1e-8) << first << " vs point " << a_td;
}

TEST_F(CliSsv, PointReportsTheGainOverConstantSpeed) {
  const json j = point({kExample, "--rpm", "300", "--depth-mm", "2"});
  ASSERT_TRUE(j.contains("speed_variation"));
  EXPECT_EQ(j["method"], "sdm");  // auto: the averaged methods cannot do it
  const json& sv = j["speed_variation"];
  EXPECT_EQ(sv["amplitude_ratio"], 0.1);
  EXPECT_EQ(sv["frequency_ratio"], 0.1);
  EXPECT_EQ(sv["exact_period"], true);
  EXPECT_EQ(sv["modulation_periods"], 1);
  EXPECT_DOUBLE_EQ(sv["floquet_periods"].get<double>(), 10.0);  // ten revolutions
  EXPECT_NEAR(sv["period_s"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(j["floquet_period_s"].get<double>(), 2.0, 1e-12);
  // The constant-speed limit is the one `point` finds without the modulation.
  const json c = point({kExample, "--rpm", "300", "--depth-mm", "2", "--ssv-amplitude", "0", "--method", "sdm"});
  EXPECT_FALSE(c.contains("speed_variation"));
  const double constant = c["depth_limit_mm"].get<double>(), with = j["depth_limit_mm"].get<double>();
  EXPECT_DOUBLE_EQ(sv["constant_speed_depth_limit_mm"].get<double>(), constant);
  EXPECT_NEAR(sv["gain"].get<double>() / (with / constant), 1.0, kGainRatio);
  EXPECT_GT(sv["gain"].get<double>(), 1.5);  // test_ssv checks the value against an independent scheme
}

}  // namespace

namespace {

// The map's CSV as (R_VA, R_VF) -> ρ per revolution.
std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream l(line);
    std::string c;
    while (std::getline(l, c, ',')) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST_F(CliSsv, SsvMapIsThePointsSpectralRadiusPerRevolution) {
  const auto r = run({"map", kCaseA, "--ssv-map", "--rpm", "300", "--depth-mm", "2", "--ssv-amplitude-max", "0.2",
                      "--ssv-amplitude-points", "2", "--ssv-frequency-min", "0.1", "--ssv-frequency-max", "0.25",
                      "--ssv-frequency-points", "2", "--out", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "amplitude_ratio,frequency_ratio,frequency_ratio_used,exact_period,"
                              "spectral_radius_per_revolution\n"))
      << r.out;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 5u);
    const std::string a = row[0], f = row[1];
    const json p = point({kCaseA, "--rpm", "300", "--depth-mm", "2", "--method", "sdm", "--ssv-amplitude", a,
                          "--ssv-frequency", f});
    // Per revolution: ρ over the principal period of q revolutions, to the 1/q.
    const double q = p.contains("speed_variation") ? p["speed_variation"]["floquet_periods"].get<double>() : 1.0;
    const double expected = std::pow(p["spectral_radius"].get<double>(), 1.0 / q);
    EXPECT_NEAR(std::stod(row[4]) / expected, 1.0, 1e-9) << "R_VA " << a << ", R_VF " << f;
    EXPECT_EQ(row[3], "true");
  }
  // R_VA = 0 is constant speed: unstable at 2 mm (limit 1.35 mm); R_VA = 0.2 stable (docs/ssv.md).
  EXPECT_GT(std::stod(rows[0][4]), 1.0);
  EXPECT_LT(std::stod(rows[2][4]), 1.0);
}

TEST_F(CliSsv, SsvMapOptionsAreChecked) {
  auto r = run({"map", kCaseA, "--ssv-map", "--rpm", "300"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--ssv-map: needs --rpm and --depth-mm")) << r.err;
  r = run({"map", kCaseA, "--rpm", "300"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--rpm: only with --axes radial-axial or --ssv-map")) << r.err;
  r = run({"map", kCaseA, "--depth-mm", "1"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--depth-mm: only with --ssv-map")) << r.err;
  r = run({"map", kCaseA, "--ssv-map", "--rpm", "300", "--depth-mm", "1", "--ssv-amplitude-max", "1"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--ssv-amplitude-max = 1: must be in (0, 1)")) << r.err;
  r = run({"map", kCaseA, "--ssv-map", "--rpm", "300", "--depth-mm", "1", "--rpm-min", "100"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--rpm-min: not with --ssv-map")) << r.err;
}

}  // namespace
