// `chatter grind fit` and `chatter grind impacts`: grinding models from test
// logs and impacts per turn from a force record (docs/grinding.md). The fits
// and the count are library functions (chatter/grinding_data.hpp); the files
// and records are the io layer's (chatter/io/grinding_io.hpp).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding_data.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/records/grinding.hpp"
#include "chatter/io/plot_grinding.hpp"
#include "chatter/io/table_writer.hpp"
#include "cmd_grind.hpp"

namespace chatter::cli {

namespace {

namespace fs = std::filesystem;

const char* const kFitUsage = R"(Usage: chatter grind fit TESTS.csv --model MODEL [options]

Coefficients of a grinding model from logged tests, by least squares, with
standard errors, 95 % intervals, R^2, RMSE, MAE, MAPE and each test's
residual (measured - fitted).

TESTS.csv: a header naming the columns (units in the names, any order), one
test per line:
  power_w                    useful grinding power at the wheel
  removal_mm3_per_s          (or removed_volume_mm3 and grinding_time_s)
  wear_mm3_per_s             (or wheel_diameter_before_mm, wheel_diameter_after_mm,
                              grinding_time_s and the width)
  normal_force_n, impacts_per_turn
  wheel_diameter_mm, wheel_width_mm, wheel_rpm, feed_mm_per_s
                             (columns, or the options below for every test)
  cutting_speed_m_per_s      (computed from the diameter and rpm when absent)
  test                       a label, not read
Derived per test (in --json's "tests"): mu = P / (V_c F_N), G-ratio = removal /
wear, depth per pass = removal / (feed x width), specific energy = P / removal
(J/mm^3).

MODEL:
  mechanistic   P = k_e [n_c N (3/4) E w] + k_c Z_w (seed 001): needs power_w,
                removal, impacts_per_turn and the wheel
  poly11, poly22, poly33, power_law, hahn_lindsay (seed 000): each of removal,
                wear and normal force whose column is in the table, against the
                cutting speed and --variable (docs/grinding.md gives the term order)

Examples:
  chatter grind fit examples/grinding/scompi_tests_synthetic.csv --model mechanistic --out fitted.toml
  chatter grind fit examples/grinding/underwater_tests_seed000.csv --model poly11 --json - --plot fit.png
)";

const char* const kImpactsUsage = R"(Usage: chatter grind impacts FORCE.csv --wheel-rpm N [options]

Impacts per wheel turn in a record (seed 001 §4.7): the peaks of the normal
force per revolution (or the dips of the wheel speed), their histogram, the
weighted mean (the n_c of the mechanistic model) and the turns without
contact. FORCE.csv: time_s and normal_force_n (N), or time_s and wheel_rpm.
The record is cut into turns of 60 / N s from its first sample. An impact
starts above the threshold and ends below the median plus half of (threshold
- median); it counts in the turn holding its maximum.

Example:
  chatter grind impacts force_log.csv --wheel-rpm 6000 --plot impacts.png   (your logged time_s, normal_force_n)
)";

std::string f4(double x) { return fmt(x, 4); }

void print_stats(std::ostream& os, const std::string& title, const grinding::FitStatistics& f,
                 const std::vector<std::string>& names, const std::vector<double>& scale, const char* unit,
                 const std::vector<GrindingTest>& tests, const std::vector<std::size_t>& rows) {
  os << "  " << title << " (" << f.tests << " tests, " << f.degrees_of_freedom << " degrees of freedom)\n";
  for (std::size_t i = 0; i < f.coefficients.size(); ++i) {
    const double s = scale.empty() ? 1.0 : scale[i];
    char line[256];
    // Both spreads, each labelled (issue 44: "+-" was the 95 % half-width
    // where docs/grinding.md names the standard error).
    std::snprintf(line, sizeof line, "    %-30s %13.6g  standard error %-11.4g 95 %% interval %.6g to %.6g\n",
                  names[i].c_str(), f.coefficients[i] * s, f.standard_error[i] * s, f.lower_95[i] * s,
                  f.upper_95[i] * s);
    os << line;
  }
  os << "    R^2 = " << f4(f.r_squared) << ", RMSE = " << f4(f.rmse) << " " << unit << ", MAE = " << f4(f.mae) << " "
     << unit << ", MAPE = " << f4(f.mape_percent) << " %\n    residuals (measured - fitted, " << unit << "):";
  for (std::size_t i = 0; i < rows.size(); ++i)
    os << (i % 6 == 0 ? "\n      " : "  ") << "line " << tests[rows[i]].line << ": " << f4(f.residuals[i]);
  os << "\n";
}

// Per test, what its columns give (docs/grinding.md "grind fit"; the JSON
// record's `tests`): specific energy P/Z (seed 000's tables list it), G-ratio,
// friction coefficient, depth per pass; "-" where a column is missing.
void print_derived(std::ostream& os, const std::vector<GrindingTest>& tests) {
  auto cell = [](const std::optional<double>& v) { return v ? f4(*v) : std::string("-"); };
  os << "  per test: line  specific energy J/mm^3  G-ratio  friction mu  depth per pass mm\n";
  for (const GrindingTest& t : tests) {
    char line[160];
    std::snprintf(line, sizeof line, "            %4d  %22s  %7s  %11s  %17s\n", t.line,
                  cell(t.specific_energy_j_per_mm3).c_str(), cell(t.g_ratio).c_str(),
                  cell(t.friction_coefficient).c_str(), cell(t.depth_per_pass_mm).c_str());
    os << line;
  }
}

}  // namespace

int cmd_grind_fit(const std::vector<std::string>& args) {
  std::string tests_path, model, variable, json_path, out_path, plot_path;
  po::options_description d("Options");
  d.add_options()("model", po::value<std::string>(&model)->required(),
                  "mechanistic, poly11, poly22, poly33, power_law or hahn_lindsay (required)")
      ("variable", po::value<std::string>(&variable), "empirical models: useful_power_w (default) or normal_force_n "
                                                      "(hahn_lindsay: normal_force_n)")
      ("json", po::value<std::string>(&json_path), "write the JSON record here ('-': standard output)")
      ("out", po::value<std::string>(&out_path), "write a [grinding] table the config loader accepts (TOML)")
      ("plot", po::value<std::string>(&plot_path), "draw measured against fitted (.png, .svg or .pdf)")
      ("force-ratio", po::value<double>(), "F_T/F_N for --out when the tests have no normal_force_n column")
      ("wheel-diameter-mm", po::value<double>(), "wheel diameter, mm, for tests without the column")
      ("wheel-width-mm", po::value<double>(), "wheel width, mm, for tests without the column")
      ("wheel-rpm", po::value<double>(), "wheel speed, rev/min, for tests without the column")
      ("feed-mm-per-s", po::value<double>(), "feed, mm/s, for tests without the column")
      ("impacts-per-turn", po::value<double>(), "n_c for tests without the column (mechanistic)");
  po::variables_map vm;
  if (!parse_grind(args, kFitUsage, d, "TESTS.csv", vm, tests_path, false)) return 0;
  GrindingTestDefaults defaults;
  auto opt = [&](const char* flag, const char* unit, std::optional<double>& into) {
    require_positive(vm, flag, unit);
    if (vm.count(flag)) into = vm[flag].as<double>();
  };
  opt("wheel-diameter-mm", "mm", defaults.wheel_diameter_mm);
  opt("wheel-width-mm", "mm", defaults.wheel_width_mm);
  opt("wheel-rpm", "rev/min", defaults.wheel_rpm);
  opt("feed-mm-per-s", "mm/s", defaults.feed_mm_per_s);
  opt("impacts-per-turn", "", defaults.impacts_per_turn);
  std::optional<double> force_ratio;
  if (vm.count("force-ratio")) {
    force_ratio = vm["force-ratio"].as<double>();
    if (!(*force_ratio > 0.0 && *force_ratio <= 10.0))
      throw InputError("--force-ratio = " + fmt(*force_ratio) + ": must be in (0, 10]");
  }
  const bool mech = model == "mechanistic";
  if (mech && vm.count("variable")) throw InputError("--variable: only for the empirical models");
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--out", out_path}, {"--plot", plot_path, true}});

  GrindingFitReport report = fit_grinding_tests(read_grinding_tests(tests_path, defaults), model,
                                                vm.count("variable") ? variable : "", tests_path);
  const std::vector<GrindingTest>& tests = report.tests;
  // ---- records, then the report ----
  // The [grinding] table the fit makes: required with --out (its refusal is
  // the error), else in the record when the fit makes one (null otherwise).
  std::optional<std::string> fragment;
  if (!out_path.empty()) fragment = grinding_fit_fragment(report, force_ratio);
  else
    try {
      fragment = grinding_fit_fragment(report, force_ratio);
    } catch (const InputError&) {
    }
  const std::string json = grinding_fit_record(report, fragment).dump(2) + "\n";
  std::vector<std::pair<fs::path, std::string>> files;
  if (!json_path.empty() && json_path != "-") files.emplace_back(json_path, json);
  if (!out_path.empty()) files.emplace_back(out_path, *fragment);
  write_text_files(files);
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << tests_path << ": " << tests.size() << " tests, model " << model << (mech ? "" : " on " + report.variable) << "\n";
  print_derived(os, tests);
  for (const auto& t : report.targets) {
    if (mech)
      print_stats(os, "power = friction + chip", t.fit, {"edge_coefficient_n_per_mm", "cutting_coefficient_n_per_mm2"},
                  {1e-3, 1e-6}, "W", tests, t.rows);
    else
      print_stats(os, t.name + " (" + (t.name == "normal_force" ? "N" : "mm^3/s") + ")", t.fit, t.fit.names, {},
                  t.name == "normal_force" ? "N" : "mm^3/s", tests, t.rows);
    for (const std::string& w : t.fit.warnings) std::cerr << "warning: " << t.name << ": " << w << "\n";
  }
  if (json_path == "-") std::cout << json;
  if (!out_path.empty()) os << "wrote [grinding] table: " << out_path << "\n";
  if (!plot_path.empty())
    print_plot(os, plot_grinding_fit(plot_path, "Grinding fit (" + model + "): " + fs::path(tests_path).filename().string(),
                                     report));
  return 0;
}

int cmd_grind_impacts(const std::vector<std::string>& args) {
  std::string record_path, json_path, plot_path, table_path;
  grinding::ImpactCountOptions o;
  po::options_description d("Options");
  d.add_options()("wheel-rpm", po::value<double>(&o.wheel_rpm)->required(), "the wheel's nominal speed, rev/min (required)")
      ("threshold-n", po::value<double>(), "force record: an impact starts above this force, N (default: a quarter of "
                                           "the way from the median to the largest peak)")
      ("threshold-rpm", po::value<double>(), "speed record: an impact starts when the speed drops this far below "
                                             "its median, rev/min (default: as --threshold-n)")
      ("json", po::value<std::string>(&json_path), "write the JSON record here ('-': standard output)")
      ("table", po::value<std::string>(&table_path), "write impacts per turn as CSV (turn, impacts, first peak, largest)")
      ("plot", po::value<std::string>(&plot_path), "draw the record with its impacts and the histogram (.png, .svg or .pdf)");
  po::variables_map vm;
  if (!parse_grind(args, kImpactsUsage, d, "FORCE.csv", vm, record_path, false)) return 0;
  require_positive(vm, "wheel-rpm", "rev/min");
  require_positive(vm, "threshold-n", "N");
  require_positive(vm, "threshold-rpm", "rev/min");
  check_outputs({{"--json", json_path == "-" ? "" : json_path}, {"--table", table_path}, {"--plot", plot_path, true}});
  const ImpactRecord rec = read_impact_record(record_path);
  const bool force = rec.kind == grinding::ImpactSignal::kNormalForce;
  if (vm.count(force ? "threshold-rpm" : "threshold-n"))
    throw InputError(std::string(force ? "--threshold-rpm" : "--threshold-n") + ": " + record_path + " is a " +
                     (force ? "force" : "wheel-speed") + " record: use " + (force ? "--threshold-n" : "--threshold-rpm"));
  if (vm.count(force ? "threshold-n" : "threshold-rpm")) o.threshold = vm[force ? "threshold-n" : "threshold-rpm"].as<double>();
  grinding::ImpactCount c;
  try {
    c = grinding::count_impacts(rec.time_s, rec.signal, rec.kind, o);
  } catch (const InputError& e) {
    throw InputError(record_path + ": " + e.what());
  }
  const std::string json = grinding_impacts_record(c, rec, record_path, o.wheel_rpm).dump(2) + "\n";
  std::vector<std::pair<fs::path, std::string>> files;
  if (!json_path.empty() && json_path != "-") files.emplace_back(json_path, json);
  if (!table_path.empty()) files.emplace_back(table_path, grinding_impacts_csv(c, rec));
  write_text_files(files);
  std::ostream& os = json_path == "-" ? std::cerr : std::cout;
  os << record_path << ": " << c.turns << " turns at " << f4(o.wheel_rpm) << " rev/min, threshold " << f4(c.threshold)
     << (force ? " N" : " rev/min below the median") << "\n  impacts per turn      " << f4(c.mean_per_turn)
     << "\n  turns without contact " << f4(100 * c.turns_without_contact) << " %\n  histogram             ";
  for (std::size_t k = 0; k < c.histogram.size(); ++k) os << (k ? ", " : "") << k << ": " << c.histogram[k];
  os << " (impacts in a turn: turns)\n";
  if (json_path == "-") std::cout << json;
  if (!table_path.empty()) os << "wrote table: " << table_path << "\n";
  if (!plot_path.empty())
    print_plot(os, plot_grinding_impacts(plot_path, "Impacts per turn: " + fs::path(record_path).filename().string(),
                                         rec, c, o.wheel_rpm));
  return 0;
}

}  // namespace chatter::cli
