// End-to-end tests of `chatter fit` (src/cli/cmd_fit.cpp), run as a separate
// process: FRFs synthesised here from known modes, written with the library's
// writers (CSV, tab, UFF 58), fitted by the binary; the TOML it writes is
// loaded with chatter::load_config and the modes compared with the ones the
// FRF was made from (issue 7: frequency within 0.5 %, damping within 10 %,
// stiffness within 5 %, with 2 % noise). Bad input must exit 2 and write
// nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/io/config.hpp"
#include "chatter/io/frf.hpp"

#include "cli_harness.hpp"

namespace fs = std::filesystem;

namespace {

using chatter::test::CliFixture;
using chatter::test::contains;
using chatter::test::RunResult;
using chatter::test::shell_quote;
using chatter::test::slurp;

// Issue 7 bounds (relative).
constexpr double kFrequencyTol = 0.005;
constexpr double kDampingTol = 0.10;
constexpr double kStiffnessTol = 0.05;

struct TrueMode {
  double f_hz, zeta, k;
};
// The two-mode FRF of docs/frf.md.
const std::vector<TrueMode> kXModes = {{650.0, 0.03, 2e7}, {1100.0, 0.02, 5e7}};
// A different pair for the yy term.
const std::vector<TrueMode> kYModes = {{480.0, 0.025, 3e7}, {1400.0, 0.035, 8e7}};

std::complex<double> receptance(const std::vector<TrueMode>& modes, double f) {
  std::complex<double> g = 0.0;
  for (const auto& m : modes) {
    const double r = f / m.f_hz;
    g += 1.0 / (m.k * std::complex<double>(1.0 - r * r, 2.0 * m.zeta * r));
  }
  return g;
}

// 0-2000 Hz every 2.5 Hz; `noise` = RMS of the complex relative noise ε in G(1 + ε).
chatter::FrfTable synth(const std::vector<TrueMode>& modes, double noise = 0.0, unsigned seed = 7,
                        double f_first = 0.0) {
  chatter::FrfTable t;
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise / std::sqrt(2.0));
  for (int i = 0; i <= 800; ++i) {
    const double f = f_first + 2.5 * i;
    std::complex<double> g = receptance(modes, f);
    if (noise > 0) g *= std::complex<double>(1.0 + n(rng), n(rng));
    t.frequency_hz.push_back(f);
    t.value.push_back(g);
  }
  t.source = "synthetic";
  return t;
}

class CliFit : public CliFixture {
 protected:
  // `chatter fit ARGS...`.
  RunResult run(const std::vector<std::string>& args) {
    std::vector<std::string> all{"fit"};
    all.insert(all.end(), args.begin(), args.end());
    return CliFixture::run(all);
  }

  // The written fragment behind a minimal [process] table, through the loader.
  chatter::Config load_fragment(const fs::path& toml) {
    const fs::path cfg = path("config.toml");
    std::ofstream(cfg) << "name = \"fitted\"\n[process]\noperation = \"turning\"\n"
                          "feed_force_coefficient_n_per_m2 = 1e9\n\n"
                       << slurp(toml);
    chatter::Config c = chatter::load_config(cfg);
    EXPECT_TRUE(c.warnings.empty()) << c.warnings.front();  // fitted modes are plausible ones
    return c;
  }

  fs::path dir_;
};

void expect_modes(const std::vector<chatter::Mode>& got, const std::vector<TrueMode>& want, double ux, double uy) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE("mode " + std::to_string(i + 1));
    EXPECT_NEAR(got[i].natural_frequency_hz, want[i].f_hz, kFrequencyTol * want[i].f_hz);
    EXPECT_NEAR(got[i].damping_ratio, want[i].zeta, kDampingTol * want[i].zeta);
    EXPECT_NEAR(got[i].stiffness_n_per_m, want[i].k, kStiffnessTol * want[i].k);
    EXPECT_NEAR(got[i].direction.x(), ux, 1e-12);
    EXPECT_NEAR(got[i].direction.y(), uy, 1e-12);
  }
}

// ------------------------------------------------------------------ success

TEST_F(CliFit, CsvWithTwoPercentNoiseGivesTheModes) {
  chatter::write_frf_csv(path("tap_xx.csv"), synth(kXModes, 0.02));
  const RunResult r = run({path("tap_xx.csv").string(), "--out", path("modes.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "fit error")) << r.out;
  EXPECT_TRUE(contains(r.out, "iterations")) << r.out;
  EXPECT_TRUE(contains(r.out, "frequency_hz")) << r.out;
  EXPECT_TRUE(contains(r.out, "wrote modes")) << r.out;
  const std::string toml = slurp(path("modes.toml"));
  EXPECT_TRUE(contains(toml, "[[tool.modes]]")) << toml;
  const chatter::Config cfg = load_fragment(path("modes.toml"));
  expect_modes(cfg.model.tool.modes, kXModes, 1.0, 0.0);
  EXPECT_TRUE(cfg.model.workpiece.modes.empty());
}

// Issue 31 item 6: the fragment carries the [uncertainty] spreads from the
// standard errors, commented out; uncommented, the loader reads them as
// 100 x the standard error of ln p (4 significant digits), one per mode.
TEST_F(CliFit, FragmentCarriesTheSpreadsCommentedOut) {
  chatter::write_frf_csv(path("tap_xx.csv"), synth(kXModes, 0.02));
  const RunResult r = run({path("tap_xx.csv").string(), "--out", path("modes.toml").string(), "--json",
                           path("fit.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "standard errors")) << r.out;
  const std::string toml = slurp(path("modes.toml"));
  EXPECT_TRUE(contains(toml, "#[uncertainty]\n#frequency_percent = [")) << toml;
  // As written: no [uncertainty] active.
  EXPECT_FALSE(load_fragment(path("modes.toml")).uncertainty.has_value());
  // Opted in: the spreads are the fit's standard errors.
  std::ofstream(path("opted.toml")) << chatter::test::uncomment_uncertainty(toml);
  const chatter::Config cfg = load_fragment(path("opted.toml"));
  ASSERT_TRUE(cfg.uncertainty.has_value()) << slurp(path("opted.toml"));
  const auto j = nlohmann::json::parse(slurp(path("fit.json")));
  const auto& errors = j.at("records").at(0).at("relative_standard_errors");
  ASSERT_EQ(errors.size(), 2u);
  ASSERT_EQ(cfg.uncertainty->frequency.size(), 2u);
  constexpr double kWritten = 5e-4;  // 4 significant digits in the TOML
  for (std::size_t m = 0; m < 2; ++m) {
    SCOPED_TRACE("mode " + std::to_string(m + 1));
    const auto& se = errors[m];
    const double want[3] = {se.at("frequency").get<double>(), se.at("damping_ratio").get<double>(),
                            se.at("stiffness").get<double>()};
    const double got[3] = {cfg.uncertainty->frequency[m], cfg.uncertainty->damping[m], cfg.uncertainty->stiffness[m]};
    for (int p = 0; p < 3; ++p) {
      EXPECT_GT(want[p], 0.0);
      EXPECT_NEAR(got[p], want[p], kWritten * want[p]) << "parameter " << p << ": loaded " << got[p] << ", fit " << want[p];
    }
  }
  EXPECT_EQ(cfg.uncertainty->tangential, 0.0);  // the fit says nothing of the cutting coefficients
}

TEST_F(CliFit, CleanCsvIsExact) {
  chatter::write_frf_csv(path("tap.csv"), synth(kXModes));
  const RunResult r = run({path("tap.csv").string(), "--modes", "2", "--out", path("modes.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const chatter::Config cfg = load_fragment(path("modes.toml"));
  ASSERT_EQ(cfg.model.tool.modes.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    // 10 significant digits in the TOML.
    EXPECT_NEAR(cfg.model.tool.modes[i].natural_frequency_hz, kXModes[i].f_hz, 1e-8 * kXModes[i].f_hz);
    EXPECT_NEAR(cfg.model.tool.modes[i].damping_ratio, kXModes[i].zeta, 1e-7 * kXModes[i].zeta);
    EXPECT_NEAR(cfg.model.tool.modes[i].stiffness_n_per_m, kXModes[i].k, 1e-7 * kXModes[i].k);
  }
}

TEST_F(CliFit, UffFitsEveryRecordAlongItsResponseDirection) {
  // Single-record files concatenated: record 1 xx (+X), record 2 the cross
  // term xy (skipped: nothing to fit alone), record 3 yy (+Y).
  chatter::UffWriteOptions ox, oxy, oy;
  oxy.reference_direction = 2;
  oy.response_direction = 2;
  oy.reference_direction = 2;
  chatter::write_uff58(path("xx.uff"), {synth(kXModes, 0.02, 11)}, ox);
  chatter::write_uff58(path("xy.uff"), {synth(kYModes, 0.02, 13)}, oxy);
  chatter::write_uff58(path("yy.uff"), {synth(kYModes, 0.02, 12)}, oy);
  std::ofstream(path("tap.uff"), std::ios::binary) << slurp(path("xx.uff")) << slurp(path("xy.uff"))
                                                   << slurp(path("yy.uff"));

  RunResult r = run({path("tap.uff").string(), "--out", path("modes.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "FRF record 1")) << r.out;
  EXPECT_TRUE(contains(r.out, "skipped cross term: " + path("tap.uff").string() + " FRF record 2")) << r.out;
  EXPECT_TRUE(contains(r.out, "FRF record 3")) << r.out;
  chatter::Config cfg = load_fragment(path("modes.toml"));
  ASSERT_EQ(cfg.model.tool.modes.size(), 4u);
  expect_modes({cfg.model.tool.modes.begin(), cfg.model.tool.modes.begin() + 2}, kXModes, 1.0, 0.0);
  expect_modes({cfg.model.tool.modes.begin() + 2, cfg.model.tool.modes.end()}, kYModes, 0.0, 1.0);

  // --record 3: only the yy term.
  r = run({path("tap.uff").string(), "--record", "3", "--out", path("yy.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(contains(r.out, "FRF record 1 ")) << r.out;
  cfg = load_fragment(path("yy.toml"));
  expect_modes(cfg.model.tool.modes, kYModes, 0.0, 1.0);

  // --record 2 alone is a cross term: refused unless a direction is given.
  r = run({path("tap.uff").string(), "--record", "2", "--out", path("xy.toml").string()});
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_TRUE(contains(r.err, "cross term")) << r.err;
  EXPECT_FALSE(fs::exists(path("xy.toml")));
}

TEST_F(CliFit, UffBinaryAccelerance) {
  // Accelerance A = −ω² G, typed as such in record 9: converted by the reader.
  chatter::FrfTable t = synth(kXModes, 0.0, 1, 2.5);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double w = 2 * std::numbers::pi * t.frequency_hz[i];
    t.value[i] *= -w * w;
  }
  chatter::UffWriteOptions o;
  o.binary = true;
  o.quantity = chatter::FrfQuantity::kAccelerance;
  chatter::write_uff58(path("acc.unv"), {t}, o);
  const RunResult r = run({path("acc.unv").string(), "--out", path("modes.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_modes(load_fragment(path("modes.toml")).model.tool.modes, kXModes, 1.0, 0.0);
}

TEST_F(CliFit, TabInMicrometresPerNewtonBandOneModeWorkpieceY) {
  chatter::FrfTable t = synth(kXModes);
  for (auto& v : t.value) v *= 1e6;  // µm/N
  chatter::write_frf_tab(path("tap_yy.frf"), t);
  const RunResult r = run({path("tap_yy.frf").string(), "--scale", "1e-6", "--band", "560", "740", "--modes", "1",
                           "--residuals", "--body", "workpiece", "--direction", "y", "--out",
                           path("wp.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "residual terms")) << r.out;
  const chatter::Config cfg = load_fragment(path("wp.toml"));
  EXPECT_TRUE(cfg.model.tool.modes.empty());
  expect_modes(cfg.model.workpiece.modes, {kXModes[0]}, 0.0, 1.0);
}

TEST_F(CliFit, MobilityCsvWithObliqueDirection) {
  chatter::FrfTable t = synth(kXModes, 0.0, 1, 2.5);
  for (std::size_t i = 0; i < t.size(); ++i)
    t.value[i] *= std::complex<double>(0.0, 2 * std::numbers::pi * t.frequency_hz[i]);  // Y = jω G
  chatter::write_frf_csv(path("mob.csv"), t);
  const RunResult r = run({path("mob.csv").string(), "--quantity", "mobility", "--direction", "[1,1]", "--out",
                           path("modes.toml").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_modes(load_fragment(path("modes.toml")).model.tool.modes, kXModes, std::sqrt(0.5), std::sqrt(0.5));
}

TEST_F(CliFit, PlotDrawsMeasuredAndFitted) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  chatter::write_frf_csv(path("tap.csv"), synth(kXModes, 0.02));
  const RunResult r =
      run({path("tap.csv").string(), "--out", path("modes.toml").string(), "--plot", path("fit.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "wrote plot")) << r.out;
  ASSERT_TRUE(fs::exists(path("fit.png")));
  EXPECT_GT(fs::file_size(path("fit.png")), 1000u);
  const std::string png = slurp(path("fit.png"));
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_TRUE(fs::exists(path("fit.gp")));
  const std::string dat = slurp(path("fit.dat"));
  EXPECT_TRUE(contains(dat, "measured")) << dat.substr(0, 400);
  EXPECT_TRUE(contains(dat, "fitted")) << dat.substr(0, 400);
}

TEST_F(CliFit, HelpExplainsUse) {
  const RunResult r = run({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(contains(r.out, "Usage: chatter fit FRF-FILE")) << r.out;
  EXPECT_TRUE(contains(r.out, "--band")) << r.out;
  EXPECT_TRUE(contains(r.out, "fit error")) << r.out;
}

// ------------------------------------------------------------------ bad input

TEST_F(CliFit, BadInputExitsTwoAndWritesNothing) {
  chatter::write_frf_csv(path("tap.csv"), synth(kXModes));
  const std::string csv = path("tap.csv").string(), out = path("modes.toml").string();
  chatter::write_uff58(path("one.uff"), {synth(kXModes)});
  fs::copy_file(path("tap.csv"), path("tap.xyz"));
  const std::string bad_csv = std::string(CHATTER_SOURCE_DIR) + "/tests/corpus/frf/bad_decreasing_frequency.csv";
  const std::string bad_uff = std::string(CHATTER_SOURCE_DIR) + "/tests/corpus/frf/bad_uff58_truncated_data.uff";
  struct Case {
    std::vector<std::string> args;
    std::string message;  // part of the error message
  };
  const std::vector<Case> cases = {
      {{path("missing.csv").string(), "--out", out}, "no such file"},
      {{path("tap.xyz").string(), "--out", out}, "--format"},
      {{csv, "--format", "xml", "--out", out}, "--format"},
      {{bad_csv, "--out", out}, "decreasing frequency"},
      {{bad_uff, "--out", out}, "truncated"},
      {{csv, "--band", "3000", "4000", "--out", out}, "outside the measured lines"},
      {{csv, "--band", "900", "500", "--out", out}, "FMAX"},
      {{csv, "--band", "500", "--out", out}, "--band"},
      {{csv, "--band", "600", "601", "--out", out}, "line"},
      {{csv, "--modes", "0", "--out", out}, "--modes = 0"},
      {{csv, "--modes", "-1", "--out", out}, "--modes"},
      {{csv, "--modes", "5", "--out", out}, "5 mode(s) asked"},
      {{csv, "--modes", "2", "--auto", "--out", out}, "--auto"},
      {{csv, "--quantity", "stress", "--out", out}, "--quantity"},
      {{csv, "--scale", "0", "--out", out}, "--scale"},
      {{csv, "--scale", "abc", "--out", out}, "scale"},
      {{csv, "--record", "1", "--out", out}, "--record"},
      {{path("one.uff").string(), "--record", "2", "--out", out}, "holds 1 FRF record"},
      {{path("one.uff").string(), "--record", "0", "--out", out}, "--record = 0"},
      {{csv, "--body", "spindle", "--out", out}, "--body"},
      {{csv, "--direction", "z", "--out", out}, "--direction"},
      {{csv, "--direction", "[0,0]", "--out", out}, "--direction"},
      {{csv, "--plot", path("fit.bmp").string(), "--out", out}, "unknown image type"},
      {{csv, "--no-such-option", "--out", out}, "no-such-option"},
      {{csv}, "out"},
      {{"--out", out}, "FRF-FILE"},
      {{csv, "--out", path("no_dir/modes.toml").string()}, "no_dir"},
      {{csv, "--out", csv}, "FRF file being fitted"},
      {{csv, "--out", path("fit.dat").string(), "--plot", path("fit.png").string()}, "--plot data file"},
  };
  const std::string csv_text = slurp(path("tap.csv"));
  for (const Case& c : cases) {
    std::string joined;
    for (const auto& a : c.args) joined += a + " ";
    SCOPED_TRACE(joined);
    const RunResult r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_TRUE(contains(r.err, c.message)) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(path("fit.bmp")));
    EXPECT_FALSE(fs::exists(path("fit.png")));
    EXPECT_FALSE(fs::exists(path("fit.dat")));
    EXPECT_EQ(slurp(path("tap.csv")), csv_text);
  }
}

}  // namespace
