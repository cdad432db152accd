// Files of the grinding commands (docs/grinding.md): the tests table of
// `grind fit`, the force (or wheel-speed) record of `grind impacts`, the
// CSV tables every front end writes (a unit in every column name) and the
// [grinding] fragment a fit writes. The JSON records of predict, fit,
// impacts, simulate and plan: chatter/records/grinding.hpp. The numerics are in
// chatter/grinding.hpp, grinding_data.hpp and grinding_dynamics.hpp.
//
// CSV files: a header line naming the columns (any order; a name not known
// is an error naming the closest known one), then one row per line; blank
// lines and lines starting with '#' are skipped. Every error is an
// InputError "<file>: line <n>: <column> = '<text>': <rule>".
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "chatter/io/columns.hpp"
#include "chatter/grinding.hpp"
#include "chatter/grinding_data.hpp"
#include "chatter/io/grinding_config.hpp"

namespace chatter {

// ------------------------------------------------------------- tests table

/// One logged grinding test, in the table's shop units. A value is absent
/// when its column is (or its cell is empty).
struct GrindingTest {
  int line = 0;  ///< 1-based line in the file
  std::optional<double> power_w;              ///< useful power at the wheel, W
  std::optional<double> removal_mm3_per_s;    ///< given, or removed_volume_mm3 / grinding_time_s
  std::optional<double> wear_mm3_per_s;       ///< given, or from the diameters before and after
  std::optional<double> normal_force_n;
  std::optional<double> impacts_per_turn;
  std::optional<double> wheel_diameter_mm, wheel_width_mm, wheel_rpm, feed_mm_per_s;
  std::optional<double> cutting_speed_m_per_s;  ///< given, or pi D n / 60
  // Derived (docs/grinding.md, "grind fit"):
  std::optional<double> friction_coefficient;  ///< mu = P / (V_c F_N)
  std::optional<double> g_ratio;               ///< removal / wear
  std::optional<double> depth_per_pass_mm;     ///< removal / (feed x width)
  std::optional<double> specific_energy_j_per_mm3;  ///< power / removal (seed 000's tables list it)
};

/// The wheel and feed of tests whose table lacks the columns (the CLI's
/// --wheel-diameter-mm, ...); a column wins over a default.
struct GrindingTestDefaults {
  std::optional<double> wheel_diameter_mm, wheel_width_mm, wheel_rpm, feed_mm_per_s, impacts_per_turn;
};

/// Reads TESTS.csv. Columns (units in the names): power_w, removal_mm3_per_s
/// (or removed_volume_mm3 with grinding_time_s), wear_mm3_per_s (or
/// wheel_diameter_before_mm and wheel_diameter_after_mm with grinding_time_s
/// and the width), normal_force_n, impacts_per_turn, wheel_diameter_mm,
/// wheel_width_mm, wheel_rpm, feed_mm_per_s, cutting_speed_m_per_s. Every
/// number must be finite; powers, removals, diameters, widths, speeds, feeds,
/// forces, impacts and times > 0, wear >= 0.
/// @throws InputError naming file, line and column; on an empty table, an
///         unknown column, or a row with more cells than the header.
std::vector<GrindingTest> read_grinding_tests(const std::filesystem::path& csv, const GrindingTestDefaults& defaults);

// ------------------------------------------------------------ force record

/// A record for `grind impacts`: time_s and normal_force_n, or time_s and
/// wheel_rpm (the wheel's measured speed; impacts are its dips).
struct ImpactRecord {
  std::vector<double> time_s, signal;
  grinding::ImpactSignal kind = grinding::ImpactSignal::kNormalForce;
  std::string column;  ///< "normal_force_n" or "wheel_rpm"
};
/// @throws InputError naming file and line: time not strictly increasing, a
///         cell that is not a number, fewer than 3 rows, neither column.
ImpactRecord read_impact_record(const std::filesystem::path& csv);

// ------------------------------------------------------- fits and tables

/// A fit of a tests table (fit_grinding_tests): per target its statistics
/// and the tests it used. Its JSON record: chatter/records/grinding.hpp.
struct GrindingFitReport {
  std::string model;                 ///< "mechanistic", "poly11", ...
  std::string variable;              ///< "useful_power_w" or "normal_force_n" (empirical)
  std::string tests_file;
  /// Per fitted target ("power_w" for mechanistic; "removal", "wear",
  /// "normal_force" for empirical) its statistics, and the tests it used.
  struct Target {
    std::string name;
    grinding::FitStatistics fit;
    std::vector<std::size_t> rows;  ///< indices into tests
  };
  std::vector<Target> targets;
  std::vector<GrindingTest> tests;
};

/// Fits `model` ("mechanistic", "poly11", "poly22", "poly33", "power_law",
/// "hahn_lindsay") to the tests read from `tests_file`: the mechanistic model
/// to the power of every test (each needs power_w, the removal,
/// impacts_per_turn, the wheel and feed); an empirical form to each of
/// removal, wear and normal force (the last only on the power) with values
/// in the table, on `variable` ("useful_power_w" or "normal_force_n"; empty:
/// useful_power_w, hahn_lindsay normal_force_n). The one fit of a tests table
/// the CLI, Python and the C API share.
/// @throws InputError "<tests_file>: line <n>: the <target> model needs <columns>",
///         on a bad model or variable, or a fit's own refusal (prefixed by the file).
GrindingFitReport fit_grinding_tests(const std::vector<GrindingTest>& tests, const std::string& model,
                                     const std::string& variable, const std::string& tests_file);

/// A [grinding] table that load_grinding_config accepts as it stands: the
/// tests' wheel and feed (the first test's), the force ratio (the tests'
/// mean mu, or `force_ratio`), and the fitted model: the mechanistic
/// coefficients with impacts_per_turn (one value, or a [[grinding.impacts]]
/// table of the mean n_c per power), or the empirical models with their
/// tested domain. @throws InputError when the force ratio is not known or a
/// fitted coefficient cannot be a config value (k_c <= 0, k_e < 0, a
/// power law's C <= 0).
std::string grinding_fit_fragment(const GrindingFitReport& r, std::optional<double> force_ratio);


/// The sweep table: one row per (feed, power), the prediction's quantities
/// with their units in the column names (feed_mm_per_s, power_w,
/// removal_rate_mm3_per_s, max_depth_mm, groove_width_mm, depth_per_pass_mm,
/// tangential_force_n, normal_force_n, specific_energy_j_per_mm3; the
/// mechanistic model's friction_power_w, chip_power_w, impacts_per_turn;
/// energy_partition, heat_into_part_w; empirical columns when the config has
/// those models). NaN where a value is absent or not finite (an empty cell).
std::vector<Column> grinding_sweep_table(const std::vector<grinding::SweepCurve>& curves);
/// The simulated series: time_s, depth_mm, surface_mm, contact_force_n, push_n.
std::vector<Column> grinding_series_table(const grinding::DynamicsResult& r);
/// The impacts per turn: turn, impacts, first_peak_time_s and the largest
/// peak (largest_peak_n or largest_peak_rpm_drop, by the record's signal).
std::vector<Column> grinding_impacts_table(const grinding::ImpactCount& c, const ImpactRecord& record);
/// A wheel's life: wheel_diameter_mm, removal_rate_mm3_per_s,
/// wear_rate_mm3_per_s, g_ratio, removed_mm3, time_s, wheel_rpm,
/// cutting_speed_m_per_s, power_w.
std::vector<Column> grinding_plan_table(const grinding::Plan& p);
/// Each table as CSV (columns_csv).
std::string grinding_sweep_csv(const std::vector<grinding::SweepCurve>& curves);
std::string grinding_series_csv(const grinding::DynamicsResult& r);
std::string grinding_impacts_csv(const grinding::ImpactCount& c, const ImpactRecord& record);
std::string grinding_plan_csv(const grinding::Plan& p);

}  // namespace chatter
