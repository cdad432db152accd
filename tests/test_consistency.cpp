// One meaning per number (docs/results.md): for every shipped config and
// every method that applies, the same quantity is the same number in every
// command and interface.
//  - a lobe-table row (lobes --json) equals the limit part of `point` at that
//    speed (depth limit, chatter frequency, lobe, multiplier type), bitwise,
//    whatever the asked depth, and equals the C API's chatter_point;
//  - tooth_passing_hz is N·N_t/60 and the lobe is ⌊f_c / f_tp⌋, both
//    recomputed here from the config's numbers;
//  - `check` on the same job reports the same limit (to the method's depth
//    tolerance: it searches a different depth range) and the same lobe;
//  - `simulate` reports N·N_t/60 and the Floquet period of sdm;
//  - the default method is the registry's auto rule, named in the output.
// This is the test that would have caught a point whose frequency was taken
// at the asked depth, a simulation that called the spindle frequency the
// tooth passing, and lobe numbers per different periods.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/chatter.h"
#include "chatter/io/config.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/solvers.hpp"
#include "cli_harness.hpp"

namespace chatter::test {
namespace {

using nlohmann::json;

// check searches max(4 x depth, 20 mm) instead of the table's depth: the
// limit is the same root to the method's depth tolerance (sdm: 1e-4
// relative, the bracketing ends differ); the transfer-function roots are
// independent of the range to round-off.
constexpr double kCheckVsTableRel = 2e-4;

std::vector<std::string> shipped_configs() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(fs::path(CHATTER_SOURCE_DIR) / "configs"))
    if (e.path().extension() == ".toml" && !contains(slurp(e.path()), "[grinding]"))  // lobe configs only
      out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// The methods of the registry that accept the config, but the simulation
// (tested on its own below: seconds per speed).
std::vector<std::string> methods_for(const Config& cfg) {
  std::vector<std::string> out;
  const FeatureSet needed = needed_features(cfg.model, cfg.process);
  for (const auto& d : solver_registry())
    if (d.kind != SolverKind::kSimulation && d.accepts.missing(needed).empty()) out.push_back(d.name);
  return out;
}

int teeth_of(const Config& cfg) {
  return cfg.process.operation() == Operation::kMilling ? cfg.process.milling_parameters().teeth : 1;
}

// A number as the lobe table prints it (10 significant digits, CSV and JSON
// alike): the table row is this rounding of the same double.
json printed(const json& x) {
  if (!x.is_number()) return x;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", x.get<double>());
  return std::stod(buf);
}

std::string number(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

class Consistency : public CliFixture, public ::testing::WithParamInterface<std::string> {
 protected:
  json run_json(const std::vector<std::string>& args) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0 ? json::parse(r.out) : json();
  }
};

TEST_P(Consistency, TableRowEqualsPointEqualsCApiEqualsCheck) {
  const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / GetParam()).string();
  const Config cfg = load_config(file);
  ASSERT_TRUE(cfg.sweep.rpm_min && cfg.sweep.rpm_max);
  const double dmax = cfg.sweep.depth_max_mm.value_or(50.0);
  const int nt = teeth_of(cfg);
  chatter_model* cm = nullptr;
  ASSERT_EQ(chatter_model_load(file.c_str(), &cm), CHATTER_OK) << chatter_last_error();
  int rows_compared = 0;
  for (const std::string& method : methods_for(cfg)) {
    SCOPED_TRACE(GetParam() + " " + method);
    const fs::path table = path("t.json");
    const RunResult lr = run({"lobes", file, "--method", method, "--rpm-min", number(*cfg.sweep.rpm_min), "--rpm-max",
                              number(*cfg.sweep.rpm_max), "--rpm-points", "3", "--json", table.string(), "--quiet"});
    ASSERT_EQ(lr.exit_code, 0) << lr.err;
    const json t = json::parse(slurp(table));
    EXPECT_EQ(t["method"], method);
    chatter_solver* cs = nullptr;
    ASSERT_EQ(chatter_solver_create(cm, method.c_str(), dmax, &cs), CHATTER_OK) << chatter_last_error();
    EXPECT_STREQ(chatter_solver_method(cs), method.c_str());
    std::string ops = "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\n";
    std::vector<json> rows;
    for (const json& row : t["rows"]) {
      const double rpm = row["spindle_rpm"].get<double>();
      if (rpm < 1000.0) continue;  // check's search depth per row: keep it to bounded, moderate speeds
      rows.push_back(row);
      const bool bounded = !row["depth_limit_mm"].is_null();
      const double lim = bounded ? row["depth_limit_mm"].get<double>() : dmax;
      const double ftp = rpm * nt / 60.0;
      if (bounded) {
        // The lobe from its definition, computed here.
        const double ratio = row["chatter_frequency_hz"].get<double>() / ftp;
        const double k = std::round(ratio);
        const int lobe = std::abs(ratio - k) <= 1e-9 * std::max(1.0, ratio) ? static_cast<int>(k)
                                                                               : static_cast<int>(std::floor(ratio));
        EXPECT_EQ(row["lobe"].get<int>(), lobe) << rpm;
      }
      json first;
      for (const double depth : {0.4 * lim, 0.9 * std::min(2.0 * lim, dmax)}) {
        const json p = run_json({"point", file, "--method", method, "--rpm", number(rpm), "--depth-mm", number(depth),
                                 "--depth-max-mm", number(dmax)});
        ASSERT_FALSE(p.is_null());
        EXPECT_EQ(p["method"], method);
        EXPECT_EQ(printed(p["depth_limit_mm"]), row["depth_limit_mm"]) << rpm << " rev/min, asked " << depth << " mm";
        EXPECT_EQ(printed(p["chatter_frequency_hz"]), row["chatter_frequency_hz"]) << rpm << " rev/min, asked " << depth;
        if (!first.is_null()) {  // bitwise the same limit whatever the depth
          EXPECT_EQ(p["depth_limit_mm"], first["depth_limit_mm"]);
          EXPECT_EQ(p["chatter_frequency_hz"], first["chatter_frequency_hz"]);
        }
        EXPECT_EQ(p["lobe"], row["lobe"]) << rpm;
        if (row.contains("multiplier_type")) {
          EXPECT_EQ(p["multiplier_type"], row["multiplier_type"]) << rpm;
        }
        EXPECT_EQ(p["tooth_passing_hz"].get<double>(), ftp);
        EXPECT_DOUBLE_EQ(p["tooth_period_s"].get<double>(), 1.0 / ftp);
        EXPECT_EQ(p["depth_mm"].get<double>(), depth);  // echoed as given
        if (first.is_null()) first = p;
        ++rows_compared;
      }
      // The C API: the same limit row.
      chatter_point_result c{};
      ASSERT_EQ(chatter_point(cs, rpm, 0.4 * lim, &c), CHATTER_OK) << chatter_last_error();
      EXPECT_EQ(c.limit.bounded, bounded ? 1 : 0);
      if (bounded) {
        EXPECT_EQ(c.limit.depth_limit_mm, first["depth_limit_mm"].get<double>());
        EXPECT_EQ(c.limit.chatter_frequency_hz, first["chatter_frequency_hz"].get<double>());
        EXPECT_EQ(c.limit.lobe, row["lobe"].get<int>());
      }
      if (row.contains("multiplier_type") && bounded) {
        EXPECT_EQ(std::string(c.multiplier_type), row["multiplier_type"]);
      }
      EXPECT_EQ(c.tooth_passing_hz, ftp);
      const char* text = nullptr;
      ASSERT_EQ(chatter_point_json(cs, rpm, 0.4 * lim, &text), CHATTER_OK) << chatter_last_error();
      json cj = json::parse(text), fj = first;
      cj.erase("depth_max_mm");  // the solver's search depth vs point's --depth-max-mm: the same value
      fj.erase("depth_max_mm");
      EXPECT_EQ(cj, fj) << "C API record vs chatter point at " << rpm;
      ops += "r" + std::to_string(rows.size()) + "," + number(rpm) + "," + number(0.4 * lim) + ",,\n";
    }
    chatter_solver_free(cs);
    // check on the same job: the same limit (to the depth tolerance) and lobe.
    const fs::path opsf = path("ops.csv"), cj = path("check.json");
    {
      std::ofstream(opsf) << ops;
    }
    // The machine range from the lowest row up: the suggestions' scan of low
    // speeds is not what is compared here (and costs seconds with sdm).
    const RunResult cr = run({"check", file, "--operations", opsf.string(), "--method", method, "--json", cj.string(),
                              "--speed-tolerance-pct", "0", "--rpm-min", number(rows.front()["spindle_rpm"].get<double>()),
                              "--rpm-max", number(*cfg.sweep.rpm_max)});
    ASSERT_TRUE(cr.exit_code == 0 || cr.exit_code == 3) << cr.err;
    const json c = json::parse(slurp(cj));
    ASSERT_EQ(c["operations"].size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const json& o = c["operations"][i];
      EXPECT_EQ(o["method"], method);
      if (rows[i]["depth_limit_mm"].is_null() || o["depth_limit_mm"].is_null()) continue;
      const double a = rows[i]["depth_limit_mm"].get<double>(), b = o["depth_limit_mm"].get<double>();
      EXPECT_NEAR(b / a, 1.0, kCheckVsTableRel) << "check " << b << " mm vs table " << a << " mm";
      EXPECT_EQ(o["lobe"], rows[i]["lobe"]);
    }
  }
  chatter_model_free(cm);
  EXPECT_GT(rows_compared, 0);
}

INSTANTIATE_TEST_SUITE_P(ShippedConfigs, Consistency, ::testing::ValuesIn(shipped_configs()),
                         [](const auto& test_info) {
                           std::string n = test_info.param.substr(0, test_info.param.size() - 5);
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

class ConsistencyCli : public CliFixture {};

// The default method is auto: analytic for turning, sdm for milling, and the
// output names it (lobes JSON, point, check).
TEST_F(ConsistencyCli, DefaultMethodIsAutoAndNamed) {
  const std::map<std::string, std::string> expect = {{"seed_turning_1dof.toml", "analytic"},
                                                     {"milling_benchmark_ae005_down.toml", "sdm"}};
  for (const auto& [cfg, method] : expect) {
    const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / cfg).string();
    const RunResult p = run({"point", file, "--rpm", "3000", "--depth-mm", "0.5"});
    ASSERT_EQ(p.exit_code, 0) << p.err;
    EXPECT_EQ(json::parse(p.out)["method"], method) << cfg;
    const fs::path t = path("t.json");
    const RunResult l = run({"lobes", file, "--rpm-points", "3", "--json", t.string(), "--quiet"});
    ASSERT_EQ(l.exit_code, 0) << l.err;
    EXPECT_EQ(json::parse(slurp(t))["method"], method) << cfg;
    EXPECT_TRUE(contains(l.out, "(" + method + ")")) << l.out;
  }
}

// The cut's mean power, torque and removal rate are the cutting law's
// (docs/cutting_law.md) in every command: `recommend`'s at its point equal
// `performance`'s at the same point and the closed forms (turning: K_c a f V,
// K_c a f D/2, a f V; milling without edge forces power = K_t × removal rate).
TEST_F(ConsistencyCli, MeanPowerTorqueAndRemovalAreTheCuttingLaws) {
  const std::string turning = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "turning_seed003_shaft.toml").string();
  // K_c = the config's [optimization] cutting_coefficient_n_per_mm2 = 1400.
  const RunResult r = run({"recommend", turning, "--feed-per-tooth-mm", "0.35", "--tangential-coefficient-n-per-m2",
                           "1.4e9", "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json rec = json::parse(r.out);
  const double rpm = rec["spindle_rpm"].get<double>(), depth_mm = rec["depth_mm"].get<double>();
  std::ostringstream rpm_s, depth_s;
  rpm_s.precision(17);
  depth_s.precision(17);
  rpm_s << rpm;
  depth_s << depth_mm;
  const RunResult p = run({"performance", turning, "--rpm", rpm_s.str(), "--feed-mm-per-rev", "0.35", "--depth-mm",
                           depth_s.str(), "--json", "-"});
  ASSERT_TRUE(p.exit_code == 0 || p.exit_code == 3) << p.err;
  const json perf = json::parse(p.out);
  const double v = std::numbers::pi * 0.025 * rpm / 60.0, a = depth_mm * 1e-3, f = 0.35e-3;
  EXPECT_NEAR(rec["power_kw"].get<double>(), 1.4e9 * a * f * v * 1e-3, 1e-12 * rec["power_kw"].get<double>());
  EXPECT_NEAR(perf["power_kw"].get<double>(), rec["power_kw"].get<double>(), 1e-12 * rec["power_kw"].get<double>());
  EXPECT_NEAR(rec["torque_nm"].get<double>(), 1.4e9 * a * f * 0.0125, 1e-12 * rec["torque_nm"].get<double>());
  EXPECT_NEAR(perf["torque_nm"].get<double>(), rec["torque_nm"].get<double>(), 1e-12 * rec["torque_nm"].get<double>());
  const double mrr_mm3_s = a * f * v * 1e9;
  EXPECT_NEAR(rec["mrr_cm3_per_min"].get<double>(), mrr_mm3_s * 0.06, 1e-12 * mrr_mm3_s);
  EXPECT_NEAR(perf["removal_rate_mm3_per_s"].get<double>(), mrr_mm3_s, 1e-12 * mrr_mm3_s);

  // Milling, the variable-pitch helix cutter (K_t = 600 N/mm², a_e = 6 mm,
  // 4 teeth): MRR = a a_e f N_t N, power = K_t × MRR, torque = power / Ω.
  const std::string milling = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_variable_pitch_helix.toml").string();
  const RunResult m = run({"recommend", milling, "--feed-per-tooth-mm", "0.05", "--max-power-kw", "5", "--json", "-"});
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const json mr = json::parse(m.out);
  const double n = mr["spindle_rpm"].get<double>(), d = mr["depth_mm"].get<double>();
  const double mrr = d * 6.0 * 0.05 * 4 * n / 60.0;  // mm³/s
  EXPECT_NEAR(mr["mrr_cm3_per_min"].get<double>(), mrr * 0.06, 1e-12 * mrr);
  EXPECT_NEAR(mr["power_kw"].get<double>(), 600.0 * mrr * 1e-6, 1e-12 * mrr);
  EXPECT_NEAR(mr["torque_nm"].get<double>(), mr["power_kw"].get<double>() * 1e3 / (2 * std::numbers::pi * n / 60.0),
              1e-12 * mr["torque_nm"].get<double>());
  // Part quality beside the suggestion (issue 44), without a tolerance: the
  // recommended point's |SLE| and peak-to-peak are `forced`'s there.
  std::ostringstream rpm_text, depth_text;
  rpm_text.precision(17);
  depth_text.precision(17);
  rpm_text << n;
  depth_text << d;
  const RunResult fo = run({"forced", milling, "--rpm", rpm_text.str(), "--depth-mm", depth_text.str(),
                           "--feed-per-tooth-mm", "0.05", "--json", "-"});
  ASSERT_EQ(fo.exit_code, 0) << fo.err;
  const json fr = json::parse(fo.out);
  ASSERT_TRUE(fr["stable"].get<bool>());
  const double sle = std::abs(fr["surface_location_error_um"].get<double>());
  const double pp = std::max(fr["peak_to_peak_um"]["x"].get<double>(), fr["peak_to_peak_um"]["y"].get<double>());
  EXPECT_NEAR(mr["part_error_um"].get<double>(), sle, 1e-9 * sle) << m.out;
  EXPECT_NEAR(mr["peak_to_peak_um"].get<double>(), pp, 1e-9 * pp) << m.out;
}

// A ball end's power, torque and removal rate are the cutting law's at the
// depth itself (its section, not the cylinder's a·a_e): `recommend` at its
// point equals `check` on that point and the closed form of the section —
// half immersion on a ball of radius R cut to depth a < R removes
// ½ [R² acos((R − a)/R) − (R − a) √(2Ra − a²)] per unit feed, and power =
// K_t × removal rate for any shape without edge forces; and a binding power
// cap is met at the recommended depth, not undercut by the cylinder's power.
TEST_F(ConsistencyCli, BallEndPowerAndRemovalAreTheSectionsNotTheCylinders) {
  const std::string ball = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_ball_end.toml").string();
  const RunResult r = run({"recommend", ball, "--feed-per-tooth-mm", "0.08", "--tool-diameter-mm", "10", "--json", "-"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json rec = json::parse(r.out);
  const double n = rec["spindle_rpm"].get<double>(), a_mm = rec["depth_mm"].get<double>();
  ASSERT_LT(a_mm, 5.0);  // inside the ball
  const double R = 5.0;  // mm
  const double section = 0.5 * (R * R * std::acos((R - a_mm) / R) - (R - a_mm) * std::sqrt(2 * R * a_mm - a_mm * a_mm));
  const double mrr = section * 0.08 * 2 * n / 60.0;  // mm³/s
  // 32 slices (the default), each at its mid-height radius: measured 5.0e-4
  // above the closed form (the ball's tip, where R(z) ~ √z, converges slowest).
  EXPECT_NEAR(rec["mrr_cm3_per_min"].get<double>() / (mrr * 0.06), 1.0, 1e-3);
  // The cylinder's a·a_e, what recommend reported before, is 2× off here.
  EXPECT_LT(rec["mrr_cm3_per_min"].get<double>(), 0.6 * a_mm * 5.0 * 0.08 * 2 * n / 60.0 * 0.06);
  EXPECT_NEAR(rec["power_kw"].get<double>(), 1800.0 * rec["mrr_cm3_per_min"].get<double>() / 0.06 * 1e-6,
              1e-12 * rec["power_kw"].get<double>());
  // `check` on the recommended point: the same law, the same numbers.
  std::ostringstream row;
  row.precision(17);
  row << "id,spindle_rpm,depth_mm,radial_immersion,feed_per_tooth_mm\nrec," << n << "," << a_mm << ",,0.08\n";
  const fs::path ops = path("ball_ops.csv");
  std::ofstream(ops) << row.str();
  const RunResult c = run({"check", ball, "--operations", ops.string(), "--tool-diameter-mm", "10", "--json", "-"});
  ASSERT_TRUE(c.exit_code == 0 || c.exit_code == 3) << c.err;
  const json load = json::parse(c.out)["operations"][0]["load"];
  for (const char* key : {"power_kw", "torque_nm", "mrr_cm3_per_min"})
    EXPECT_NEAR(load[key].get<double>(), rec[key].get<double>(), 1e-9 * rec[key].get<double>()) << key;
  // A power cap below that power binds and is met (within the root's 1e-10
  // of the searched depth), where the cylinder's power per depth stopped short.
  const RunResult capped = run({"recommend", ball, "--feed-per-tooth-mm", "0.08", "--tool-diameter-mm", "10",
                                "--max-power-kw", "0.2", "--json", "-"});
  ASSERT_EQ(capped.exit_code, 0) << capped.err;
  const json cj = json::parse(capped.out);
  EXPECT_NE(std::find(cj["binding"].begin(), cj["binding"].end(), "power"), cj["binding"].end()) << cj["binding"];
  EXPECT_NEAR(cj["power_kw"].get<double>(), 0.2, 1e-6);
}

// The limit's frequency and lobe do not move with the asked depth; what
// belongs to the depth has its own keys (the variable-pitch helix cutter, at
// the speed where the first report saw 1 148 / 1 210 / 1 253 Hz).
TEST_F(ConsistencyCli, PointLimitDoesNotDependOnTheAskedDepth) {
  const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_variable_pitch_helix.toml").string();
  json first;
  std::vector<double> dominant;
  for (const char* depth : {"1", "3", "10"}) {
    const RunResult p = run({"point", file, "--method", "sdm", "--rpm", "12000", "--depth-mm", depth});
    ASSERT_EQ(p.exit_code, 0) << p.err;
    const json j = json::parse(p.out);
    if (first.is_null()) first = j;
    for (const char* key : {"depth_limit_mm", "chatter_frequency_hz", "lobe", "multiplier_type"})
      EXPECT_EQ(j[key], first[key]) << key << " at " << depth << " mm";
    dominant.push_back(j["dominant_frequency_hz"].get<double>());
    EXPECT_TRUE(j.contains("spectral_radius") && j.contains("dominant_multiplier_type")) << p.out;
    EXPECT_EQ(j["tooth_passing_hz"].get<double>(), 800.0);
    // 80/100/80/100: the pattern repeats after two teeth.
    EXPECT_DOUBLE_EQ(j["floquet_period_s"].get<double>(), 2.0 / 800.0);
  }
  // The dominant vibration at the depth does move (that is why it has its own key).
  EXPECT_NE(dominant.front(), dominant.back());
}

// sdm with Gauss collocation (--collocation): a table row is `point`'s limit
// bitwise, the table and point say which scheme and steps ran, and a cut
// it does not model is refused naming the option, with no table written.
TEST_F(ConsistencyCli, CollocationRowEqualsPointAndNamesItsScheme) {
  const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_benchmark_ae005_down.toml").string();
  const fs::path table = path("c.json");
  const RunResult lr = run({"lobes", file, "--method", "sdm", "--collocation", "3", "--rpm-min", "5000", "--rpm-max",
                            "16000", "--rpm-points", "3", "--json", table.string(), "--quiet"});
  ASSERT_EQ(lr.exit_code, 0) << lr.err;
  const json t = json::parse(slurp(table));
  EXPECT_EQ(t["options"]["collocation_nodes"], 3) << t["options"];
  EXPECT_EQ(t["options"]["steps_per_period"], kCollocationSteps);
  std::set<std::string> types;
  for (const json& row : t["rows"]) {
    ASSERT_FALSE(row["depth_limit_mm"].is_null());
    const double rpm = row["spindle_rpm"].get<double>();
    const json p = json::parse(run({"point", file, "--method", "sdm", "--collocation", "3", "--rpm", number(rpm),
                                    "--depth-mm", "1"}).out);
    EXPECT_EQ(printed(p["depth_limit_mm"]), row["depth_limit_mm"]) << rpm;
    EXPECT_EQ(printed(p["chatter_frequency_hz"]), row["chatter_frequency_hz"]) << rpm;
    EXPECT_EQ(p["lobe"], row["lobe"]) << rpm;
    EXPECT_EQ(p["multiplier_type"], row["multiplier_type"]) << rpm;
    types.insert(row["multiplier_type"].get<std::string>());
  }
  EXPECT_EQ(types, (std::set<std::string>{"hopf", "flip"}));  // 5 000: hopf; 10 500, 16 000: flip
  const std::string nose = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "turning_insert_lead_angle.toml").string();
  const fs::path none = path("none.csv");
  const RunResult bad = run({"lobes", nose, "--method", "sdm", "--collocation", "3", "--table", none.string(),
                             "--quiet"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_TRUE(contains(bad.err, "--collocation") && contains(bad.err, "is turning with a nose radius")) << bad.err;
  EXPECT_FALSE(fs::exists(none));
}

// simulate: tooth passing N N_t / 60 and the Floquet period of sdm.
TEST_F(ConsistencyCli, SimulateReportsToothPassingAndFloquetPeriod) {
  const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_variable_pitch_helix.toml").string();
  const RunResult s = run({"simulate", file, "--rpm", "12000", "--depth-mm", "1", "--revolutions", "20"});
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const json j = json::parse(s.out);
  EXPECT_EQ(j["tooth_passing_hz"].get<double>(), 12000.0 * 4 / 60);
  EXPECT_DOUBLE_EQ(j["floquet_period_s"].get<double>(), 2.0 * 60.0 / (12000.0 * 4));
  EXPECT_DOUBLE_EQ(j["revolutions"].get<double>(), 20.0);
  const RunResult p = run({"point", file, "--method", "sdm", "--rpm", "12000", "--depth-mm", "1"});
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_EQ(json::parse(p.out)["floquet_period_s"], j["floquet_period_s"]);
}

// The simulated limit's lobe uses the same definition (time-domain is slow:
// one speed of case A).
TEST_F(ConsistencyCli, TimeDomainLobeHasTheSameDefinition) {
  const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "seed_turning_1dof.toml").string();
  const fs::path t = path("t.json");
  const RunResult l = run({"lobes", file, "--method", "time-domain", "--rpm-min", "1500", "--rpm-max", "1600",
                           "--rpm-points", "2", "--periods", "60", "--json", t.string(), "--quiet"});
  ASSERT_EQ(l.exit_code, 0) << l.err;
  const json table = json::parse(slurp(t));
  for (const json& row : table["rows"]) {
    if (row["depth_limit_mm"].is_null()) continue;
    const double ratio = row["chatter_frequency_hz"].get<double>() / (row["spindle_rpm"].get<double>() / 60.0);
    EXPECT_EQ(row["lobe"].get<int>(), static_cast<int>(std::floor(ratio))) << row;
  }
}

// Inputs come back as given: the config's cutter keys, the asked depth.
TEST_F(ConsistencyCli, GivenNumbersAreEchoedExactly) {
  const fs::path cfg = path("vp.toml");
  std::string text = slurp(fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_variable_pitch_helix.toml");
  const auto at = text.find("pitch_angles_deg = [80, 100, 80, 100]");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("pitch_angles_deg = [80, 100, 80, 100]").size(), "pitch_angles_deg = [85, 95, 85, 95]");
  std::ofstream(cfg) << text;
  const fs::path t = path("t.json");
  const RunResult l = run({"lobes", cfg.string(), "--rpm-points", "2", "--json", t.string(), "--quiet"});
  ASSERT_EQ(l.exit_code, 0) << l.err;
  const json p = json::parse(slurp(t))["config"]["process"];
  EXPECT_EQ(p["helix_angle_deg"].dump(), "30");
  EXPECT_EQ(p["pitch_angles_deg"], json::parse("[85.0, 95.0, 85.0, 95.0]"));
  EXPECT_EQ(p["flute_length_mm"].dump(), "26");
  EXPECT_EQ(p["radial_depth_mm"].dump(), "6");
  const RunResult q = run({"point", cfg.string(), "--rpm", "9000", "--depth-mm", "0.123"});
  ASSERT_EQ(q.exit_code, 0) << q.err;
  EXPECT_EQ(json::parse(q.out)["depth_mm"].dump(), "0.123");
}

// Along an adaptive sdm table the lobe number never flickers (k, k+1, k
// between neighbouring rows), fold rows included: a fold chatters on a
// harmonic, f_c = k f_tp exactly, and round-off must not make it k-1 on one
// row and k on the next (the variable-pitch config has 20-odd fold rows).
TEST_F(ConsistencyCli, LobeNumbersDoNotFlickerAlongAnAdaptiveTable) {
  const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "milling_variable_pitch_helix.toml").string();
  const fs::path t = path("t.json");
  const RunResult l = run({"lobes", file, "--method", "sdm", "--rpm-spacing", "adaptive", "--rpm-points", "400",
                           "--json", t.string(), "--quiet"});
  ASSERT_EQ(l.exit_code, 0) << l.err;
  const json rows = json::parse(slurp(t))["rows"];
  int folds = 0;
  for (std::size_t i = 1; i + 1 < rows.size(); ++i) {
    if (rows[i - 1]["lobe"].is_null() || rows[i]["lobe"].is_null() || rows[i + 1]["lobe"].is_null()) continue;
    const int a = rows[i - 1]["lobe"].get<int>(), b = rows[i]["lobe"].get<int>(), c = rows[i + 1]["lobe"].get<int>();
    EXPECT_FALSE(a == c && b != a) << "lobe " << a << ", " << b << ", " << c << " at " << rows[i]["spindle_rpm"];
    if (rows[i]["multiplier_type"] == "fold") {
      ++folds;
      const double ratio = rows[i]["chatter_frequency_hz"].get<double>() / (rows[i]["spindle_rpm"].get<double>() * 4 / 60);
      EXPECT_EQ(b, static_cast<int>(std::floor(ratio + 1e-6))) << rows[i];
    }
  }
  EXPECT_GT(folds, 0) << "the table has no fold row: the test checks no fold";
}

// A speed or depth beyond anything physical is a unit mistake: refused with
// the rule, by every command that takes one.
TEST_F(ConsistencyCli, PointsBeyondThePhysicalRangeAreRefused) {
  const std::string file = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "seed_turning_1dof.toml").string();
  const RunResult fast = run({"point", file, "--rpm", "1e7", "--depth-mm", "1"});
  EXPECT_EQ(fast.exit_code, 2);
  EXPECT_TRUE(contains(fast.err, "--rpm = 1e+07: at most 500000 rev/min")) << fast.err;
  const RunResult deep = run({"point", file, "--rpm", "1000", "--depth-mm", "1e6"});
  EXPECT_EQ(deep.exit_code, 2);
  EXPECT_TRUE(contains(deep.err, "--depth-mm = 1e+06: at most 1000 mm (no cut is a metre deep)")) << deep.err;
  const RunResult sim = run({"simulate", file, "--rpm", "1000", "--depth-mm", "5000"});
  EXPECT_EQ(sim.exit_code, 2);
  EXPECT_TRUE(contains(sim.err, "--depth-mm = 5000: at most 1000 mm")) << sim.err;
  const RunResult sweep = run({"lobes", file, "--rpm-min", "100", "--rpm-max", "6e6"});
  EXPECT_EQ(sweep.exit_code, 2);
  EXPECT_TRUE(contains(sweep.err, "--rpm-max = 6e+06: at most 500000 rev/min")) << sweep.err;
}

// `--json -` means standard output in every command that writes a JSON file
// (lobes and compare once wrote a file named "-"), the summary then on
// standard error; with the table on standard output too it is refused.
TEST_F(ConsistencyCli, JsonDashIsStandardOutputEverywhere) {
  const std::string a = (fs::path(CHATTER_SOURCE_DIR) / "configs" / "seed_turning_1dof.toml").string();
  const std::vector<std::vector<std::string>> commands = {
      {"lobes", a, "--rpm-points", "3"},
      {"compare", a, "--rpm-points", "3"},
      {"map", a, "--rpm-points", "3", "--depth-points", "3"},
  };
  for (std::vector<std::string> args : commands) {
    args.insert(args.end(), {"--json", "-"});
    const RunResult r = run(args);
    ASSERT_EQ(r.exit_code, 0) << args[0] << ": " << r.err;
    EXPECT_TRUE(json::accept(r.out)) << args[0] << " did not write its JSON alone to standard output";
    EXPECT_FALSE(fs::exists("-")) << args[0] << " wrote a file named '-'";
  }
  for (const std::string cmd : {"lobes", "compare"}) {
    const RunResult r = run({cmd, a, "--rpm-points", "3", "--json", "-", "--table", "-"});
    EXPECT_EQ(r.exit_code, 2) << cmd;
    EXPECT_NE(r.err.find("only one of them can go to standard output"), std::string::npos) << r.err;
  }
}


}  // namespace
}  // namespace chatter::test
