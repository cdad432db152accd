// Measured FRFs in the structural model: interpolation that keeps resonances,
// lobes from measured data against the modal lobes, config entries and the
// solvers that need modes refusing measured bodies.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <unistd.h>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/frf.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
// A single mode's dynamic stiffness is quadratic in ω, so the cubic
// interpolation of 1/G is exact to round-off.
constexpr double kSingleModeExact = 1e-9;
// Two modes in one measured term at 1 Hz lines: the cubic in 1/G is no longer
// exact, but the error stays below 1e-6 on case B (measured 2026-11-22).
constexpr double kTwoModeInterpolation = 1e-5;

MeasuredTerm sample(const std::vector<Mode>& modes, double f0, double f1, double df) {
  MeasuredTerm t;
  for (double f = f0; f <= f1 + 1e-9; f += df) {
    Complex g(0.0);
    for (const Mode& m : modes) g += m.receptance(kTwoPi * f);
    t.frequency_hz.push_back(f);
    t.receptance.push_back(g);
  }
  t.source = "synthetic";
  return t;
}

TEST(MeasuredTerm, InterpolationIsExactForOneMode) {
  const Mode m = Mode::from_stiffness(94.22, 0.033, 45e6, {1, 0});
  const MeasuredTerm t = sample({m}, 20, 300, 2.0);
  for (double f : {21.3, 90.0, 93.7, 94.22, 95.05, 97.9, 150.5, 299.0}) {
    const Complex exact = m.receptance(kTwoPi * f);
    EXPECT_LT(std::abs(t.at(kTwoPi * f) - exact), kSingleModeExact * std::abs(exact)) << f << " Hz";
  }
  EXPECT_EQ(t.at(kTwoPi * 10.0), Complex(0.0)) << "outside the measured range";
}

TEST(MeasuredTerm, LinearInterpolationOfGWouldFlattenTheResonance) {
  // The reason for interpolating 1/G: at 2 Hz lines, a straight line between
  // the lines around the peak misses the peak by a few per cent.
  const Mode m = Mode::from_stiffness(94.22, 0.01, 45e6, {1, 0});
  const MeasuredTerm t = sample({m}, 20, 300, 2.0);
  const double f = 94.22;
  const Complex exact = m.receptance(kTwoPi * f);
  const Complex lin = 0.5 * (m.receptance(kTwoPi * 94.0) + m.receptance(kTwoPi * 96.0));
  EXPECT_GT(std::abs(lin - exact) / std::abs(exact), 0.01);
  EXPECT_LT(std::abs(t.at(kTwoPi * f) - exact) / std::abs(exact), kSingleModeExact);
}

TEST(MeasuredLobes, SingleModeEqualsModalLobes) {
  StructuralModel modal;
  modal.workpiece.modes.push_back(Mode::from_stiffness(94.22, 0.033, 45e6, {1, 0}));
  StructuralModel measured;
  measured.workpiece.measured.push_back(sample(modal.workpiece.modes, 10, 400, 2.0));
  TransferFunctionOptions o;
  o.depth_max_m = 0.02;
  const AnalyticSolver a(modal, Process::turning({2.4e9}), o), b(measured, Process::turning({2.4e9}), o);
  for (double rpm : {100.0, 500.0, 1234.0, 2000.0, 5000.0}) {
    const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lb = b.limit_at(SpindleSpeed(rpm));
    ASSERT_TRUE(la.bounded() && lb.bounded()) << rpm;
    EXPECT_NEAR(lb.depth_limit_m / la.depth_limit_m, 1.0, kSingleModeExact * 100) << rpm;
    EXPECT_EQ(lb.lobe, la.lobe);
  }
  EXPECT_NEAR(b.absolute_limit().depth_m / a.absolute_limit().depth_m, 1.0, 1e-7);
  EXPECT_DOUBLE_EQ(measured.frequency_resolution_hz(), 2.0);
}

TEST(MeasuredLobes, TwoModeTapTestEqualsModalLobes) {
  // Case B, tool 1 x workpiece 1, measured as one relative xx term at 1 Hz.
  StructuralModel modal;
  modal.tool.modes.push_back(Mode::from_stiffness(100.66, 0.032, 20e6, {1, 0}));
  modal.workpiece.modes.push_back(Mode::from_stiffness(326.71, 0.025, 43.972e6, {1, 0}));
  StructuralModel measured;
  measured.workpiece.measured.push_back(
      sample({modal.tool.modes[0], modal.workpiece.modes[0]}, 20, 1200, 1.0));
  TransferFunctionOptions o;
  o.depth_max_m = 0.02;
  const AnalyticSolver a(modal, Process::turning({684e6}), o), b(measured, Process::turning({684e6}), o);
  double worst = 0;
  for (double rpm = 600; rpm <= 12000; rpm += 300) {
    const StabilityLimit la = a.limit_at(SpindleSpeed(rpm)), lb = b.limit_at(SpindleSpeed(rpm));
    ASSERT_EQ(la.bounded(), lb.bounded()) << rpm;
    if (la.bounded()) worst = std::max(worst, std::abs(lb.depth_limit_m / la.depth_limit_m - 1));
  }
  EXPECT_LT(worst, kTwoModeInterpolation);
  RecordProperty("worst_relative_error", std::to_string(worst * 1e6) + "e-6");
}

std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("chatter_measured_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

const char* const kTurning = "[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = 2.4e9\n";

TEST(MeasuredConfig, FrfEntryReadsFileRelativeToConfig) {
  const auto d = temp_dir("cfg");
  const Mode m = Mode::from_stiffness(94.22, 0.033, 45e6, {1, 0});
  MeasuredTerm t = sample({m}, 10, 400, 2.0);
  FrfTable table;
  table.frequency_hz = t.frequency_hz;
  table.value = t.receptance;
  write_frf_csv(d / "tap_xx.csv", table);
  std::ofstream(d / "case.toml") << kTurning << "[[workpiece.frf]]\nfile = \"tap_xx.csv\"\ndirection = \"xx\"\n";
  const Config c = load_config(d / "case.toml");
  ASSERT_EQ(c.model.workpiece.measured.size(), 1u);
  EXPECT_EQ(c.model.workpiece.measured[0].frequency_hz.size(), t.frequency_hz.size());
  TransferFunctionOptions o;
  o.depth_max_m = 0.02;
  const AnalyticSolver s(c.model, c.process, o);
  EXPECT_NEAR(s.absolute_limit().depth_m / (2 * 45e6 * 0.033 * 1.033 / 2.4e9), 1.0, 1e-7);
  // Solvers that need modes refuse a measured body with a way out.
  try {
    CoupledSolver bad(c.model, c.process, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("chatter fit"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SemiDiscretizationSolver(c.model, c.process), InputError);
  std::filesystem::remove_all(d);
}

TEST(MeasuredConfig, BadEntriesNameTheKey) {
  const auto d = temp_dir("bad");
  auto expect_error = [&](const std::string& body, const std::string& needle) {
    std::ofstream(d / "case.toml") << kTurning << body;
    try {
      load_config(d / "case.toml");
      ADD_FAILURE() << "expected InputError for: " << body;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error("[[workpiece.frf]]\nfile = \"missing.csv\"\n", "workpiece.frf[0]");
  expect_error("[[workpiece.frf]]\nfile = \"missing.csv\"\n", "missing.csv");
  expect_error("[[workpiece.frf]]\ndirection = \"xx\"\n", "workpiece.frf[0].file: missing");
  expect_error("[[workpiece.frf]]\nfile = \"a.csv\"\ndirection = \"xz\"\n", "workpiece.frf[0].direction");
  expect_error("[[workpiece.frf]]\nfile = \"a.dat\"\n", "format");
  expect_error("[[workpiece.frf]]\nfile = \"a.csv\"\nquantity = \"force\"\n", "workpiece.frf[0].quantity");
  expect_error("[[workpiece.frf]]\nfile = \"a.csv\"\nfrobnicate = 1\n", "frobnicate");
  std::ofstream(d / "broken.csv") << "frequency_hz,real,imag\n100,1e-7,-1e-8\n90,1e-7,-1e-8\n";
  expect_error("[[workpiece.frf]]\nfile = \"broken.csv\"\n", "broken.csv");
  std::filesystem::remove_all(d);
}

}  // namespace
}  // namespace chatter
