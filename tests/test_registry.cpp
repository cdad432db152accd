// The solver registry (solvers.hpp): complete, unique descriptors; every
// method builds on a shipped config it accepts and agrees with what it
// reports; refusals name the method and the feature.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/solvers.hpp"

namespace {

namespace fs = std::filesystem;
using namespace chatter;

// The registry's diagnostics must be the limit_at() answer bitwise: the same
// search, only more reported.
constexpr double kSameLimit = 0.0;

fs::path source(const std::string& rel) { return fs::path(CHATTER_SOURCE_DIR) / rel; }

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(Registry, DescriptorsCompleteAndUnique) {
  std::set<std::string> names;
  ASSERT_FALSE(solver_registry().empty());
  for (const auto& d : solver_registry()) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_TRUE(names.insert(d.name).second) << d.name << " registered twice";
    EXPECT_FALSE(d.summary.empty()) << d.name;
    EXPECT_TRUE(static_cast<bool>(d.make)) << d.name;
    EXPECT_TRUE(static_cast<bool>(d.effective_options)) << d.name;
    EXPECT_TRUE(d.accepts.contains(SolverFeature::kModalModel) || d.accepts.contains(SolverFeature::kMeasuredFrf))
        << d.name << " accepts no structural model";
    EXPECT_TRUE(d.accepts.contains(SolverFeature::kMilling) || d.accepts.contains(SolverFeature::kTurning)) << d.name;
    ASSERT_NE(d.plot.colour, nullptr);
    EXPECT_EQ(std::string(d.plot.colour).size(), 7u) << d.name << ": " << d.plot.colour;
    for (const auto& c : d.compare_columns) {
      bool declared = false;
      for (const auto& col : d.columns) declared = declared || col.name == c;
      EXPECT_TRUE(declared) << d.name << ": compare column " << c << " is not a diagnostic column";
    }
    std::set<std::string> options;
    for (const auto& o : d.options) {
      EXPECT_TRUE(options.insert(o.name).second) << d.name << ": option " << o.name << " twice";
      EXPECT_FALSE(o.help.empty()) << d.name << ": " << o.name;
    }
    EXPECT_TRUE(has_lobe_method(d.name));
    EXPECT_EQ(&find_lobe_method(d.name), &d);
  }
  EXPECT_EQ(lobe_methods().size(), solver_registry().size());
}

TEST(Registry, EveryMethodBuildsOnAShippedConfigItAccepts) {
  constexpr double kDepthMaxM = 0.01;
  constexpr double kRpm = 3000.0;
  for (const auto& d : solver_registry()) {
    int built = 0;
    for (const auto& entry : fs::directory_iterator(source("configs"))) {
      if (entry.path().filename().string().starts_with("grinding_")) continue;  // grinding configs: no lobes
      const Config cfg = load_config(entry.path());
      if (!d.accepts.missing(needed_features(cfg.model, cfg.process)).empty()) continue;
      const auto s = make_lobe_solver(d.name, cfg.model, cfg.process, kDepthMaxM);
      ++built;
      EXPECT_EQ(s->method(), d.name);
      EXPECT_EQ(s->depth_max_m(), kDepthMaxM) << d.name;
      EXPECT_EQ(s->diagnostic_columns(), d.columns) << d.name;
      const SolverValues eff = d.effective_options(*s);
      ASSERT_TRUE(eff.count("depth_max_m")) << d.name;
      EXPECT_EQ(std::get<double>(eff.at("depth_max_m")), kDepthMaxM) << d.name;
      if (d.kind == SolverKind::kSimulation) break;  // slow: one config is enough
      const StabilityLimit plain = s->limit_at(SpindleSpeed(kRpm));
      const DiagnosedLimit diag = s->limit_with_diagnostics(SpindleSpeed(kRpm));
      EXPECT_EQ(diag.values.size(), d.columns.size()) << d.name;
      if (plain.bounded())
        EXPECT_LE(std::abs(diag.limit.depth_limit_m - plain.depth_limit_m), kSameLimit)
            << d.name << " " << entry.path() << ": " << diag.limit.depth_limit_m << " vs " << plain.depth_limit_m;
      else
        EXPECT_FALSE(diag.limit.bounded()) << d.name;
      break;  // one config per method keeps the test quick
    }
    EXPECT_GE(built, 1) << d.name << " builds on no shipped config";
  }
}

TEST(Registry, RefusesWhatItDoesNotAccept) {
  // A measured-FRF model: the methods that need modes refuse it by name.
  const fs::path dir = fs::temp_directory_path() / "chatter_test_registry";
  fs::create_directories(dir);
  fs::copy_file(source("tests/corpus/frf/good_receptance.csv"), dir / "tap.csv", fs::copy_options::overwrite_existing);
  const fs::path toml = dir / "measured.toml";
  std::ofstream(toml) << "name = \"measured\"\n[process]\noperation = \"turning\"\n"
                         "feed_force_coefficient_n_per_m2 = 2.4e9\n"
                         "[[workpiece.frf]]\nfile = \"tap.csv\"\ndirection = \"xx\"\n";
  const Config cfg = load_config(toml);
  int refused = 0, accepted = 0;
  for (const auto& d : solver_registry()) {
    if (d.accepts.contains(SolverFeature::kMeasuredFrf)) {
      EXPECT_NO_THROW(make_lobe_solver(d.name, cfg.model, cfg.process, 0.01)) << d.name;
      ++accepted;
      continue;
    }
    try {
      make_lobe_solver(d.name, cfg.model, cfg.process, 0.01);
      ADD_FAILURE() << d.name << " built on measured FRFs";
    } catch (const InputError& e) {
      ++refused;
      EXPECT_TRUE(contains(e.what(), "method \"" + d.name + "\"")) << e.what();
      EXPECT_TRUE(contains(e.what(), "measured FRFs")) << e.what();
    }
  }
  EXPECT_GE(accepted, 1);
  EXPECT_GE(refused, 1);
  fs::remove_all(dir);
}

TEST(Registry, UnknownMethodAndOptionNameNoFlag) {
  const Config cfg = load_config(source("configs/seed_turning_1dof.toml"));
  try {
    make_lobe_solver("bogus", cfg.model, cfg.process, 0.01);
    ADD_FAILURE() << "bogus built";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "method \"bogus\": unknown (this build has: ")) << m;
    for (const auto& n : lobe_methods()) EXPECT_TRUE(contains(m, n)) << m;
    EXPECT_FALSE(contains(m, "--")) << m;
  }
  for (const auto& d : solver_registry()) {
    EXPECT_THROW(make_lobe_solver(d.name, cfg.model, cfg.process, 0.01, {{"no_such_option", 1}}), InputError);
    EXPECT_THROW(make_lobe_solver(d.name, cfg.model, cfg.process, -1.0), InputError);
    for (const auto& o : d.options) {
      if (o.kind != SolverOption::Kind::kInt || !std::isfinite(o.min)) continue;
      const int below = static_cast<int>(o.min) - 1;
      try {
        make_lobe_solver(d.name, cfg.model, cfg.process, 0.01, {{o.name, below}});
        ADD_FAILURE() << d.name << ": " << o.name << " = " << below << " accepted";
      } catch (const InputError& e) {
        EXPECT_TRUE(contains(e.what(), o.name + " = " + std::to_string(below))) << e.what();
        EXPECT_EQ(option_violation(o, SolverValue(below)).empty(), false);
      }
    }
  }
}

TEST(Registry, DiagnosticsAgreeWithTheLimit) {
  // Milling at low immersion (flip lobes): the Floquet method's diagnostics
  // at the limit, and its point verdict on either side of it.
  const Config cfg = load_config(source("configs/milling_benchmark_ae005_down.toml"));
  // At the reported limit the spectral radius is 1 to within what the depth
  // tolerance (1e-4 relative) allows; ρ changes by well under 1 % per 1 %
  // of depth near the limit here, so 1e-2 is a loose, safe bound.
  constexpr double kRhoAtLimit = 1e-2;
  // Points at half and 1.5 × the limit are far from it: the verdict must be clear.
  constexpr double kBelow = 0.5, kAbove = 1.5;
  int rho_checked = 0, verdicts_checked = 0;
  for (const auto& d : solver_registry()) {
    if (d.kind == SolverKind::kSimulation) continue;  // slow; covered by test_time_domain
    const auto s = make_lobe_solver(d.name, cfg.model, cfg.process, 0.02);
    EXPECT_EQ(s->known_absolute_limit().has_value(), d.kind == SolverKind::kAveraged) << d.name;
    for (double rpm : {6000.0, 9000.0, 12000.0}) {
      const DiagnosedLimit r = s->limit_with_diagnostics(SpindleSpeed(rpm));
      ASSERT_EQ(r.values.size(), d.columns.size()) << d.name;
      for (std::size_t c = 0; c < d.columns.size(); ++c) {
        const SolverValue& v = r.values[c];
        if (!r.limit.bounded()) {
          EXPECT_TRUE(std::holds_alternative<std::monostate>(v)) << d.name << " " << d.columns[c].name;
          continue;
        }
        EXPECT_EQ(std::holds_alternative<double>(v), d.columns[c].numeric) << d.name << " " << d.columns[c].name;
        if (d.columns[c].name == "spectral_radius_check" && ++rho_checked > 0) {
          EXPECT_NEAR(std::get<double>(v), 1.0, kRhoAtLimit) << d.name << " at " << rpm;
        }
      }
      if (!r.limit.bounded()) continue;
      const PointAnalysis below = s->analyse_point(SpindleSpeed(rpm), kBelow * r.limit.depth_limit_m);
      const PointAnalysis above = s->analyse_point(SpindleSpeed(rpm), kAbove * r.limit.depth_limit_m);
      if (!below.stable) continue;  // the method judges from limit_at alone
      ASSERT_TRUE(above.stable.has_value()) << d.name;
      ++verdicts_checked;
      EXPECT_TRUE(*below.stable) << d.name << " at " << rpm << " rev/min, " << kBelow * r.limit.depth_limit_m << " m";
      EXPECT_FALSE(*above.stable) << d.name << " at " << rpm << " rev/min, " << kAbove * r.limit.depth_limit_m << " m";
    }
  }
  EXPECT_GE(rho_checked, 1) << "no bounded Floquet limit: the test checked nothing";
  EXPECT_GE(verdicts_checked, 1) << "no point verdict checked";
}

}  // namespace
