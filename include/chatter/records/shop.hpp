// The records of the commands that read shop measurements: `chatter
// coefficients` (cutting tests), `chatter detect` (a recording of the cut)
// and `chatter fit` (a tap test). Each function does the command's work from
// its arguments to its result, and the record and report are built from
// that result once, for the CLI (src/cli/cmd_coefficients.cpp,
// cmd_detect.cpp, cmd_fit.cpp) and Python (python/bind_shop.cpp). Messages
// name arguments as the caller does (ArgStyle). Keys: docs/shop_data.md,
// docs/frf.md.
//
// Layer: records (core + io + ops, nlohmann-json); see chatter/records.hpp.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "chatter/records/columns.hpp"
#include "chatter/frf_data.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/shop_io.hpp"
#include "chatter/modal_fit.hpp"
#include "chatter/records.hpp"
#include "chatter/shop.hpp"

namespace chatter {

// ------------------------------------------------------------------ coefficients

/// `chatter coefficients` on turning tests (a table with feed_mm_per_rev):
/// Kienzle's law per direction (fit_kienzle, docs/shop_data.md "Kienzle's law").
struct KienzleResult {
  std::filesystem::path tests_path;
  TurningTests tests;
  KienzleFit fit;
};
/// Reads the table and fits the law at lead angle κ_r (deg, in (0, 90]).
/// @throws InputError naming the file (and the flag for a bad lead angle).
KienzleResult fit_kienzle_tests(const std::filesystem::path& tests, double lead_angle_deg, ArgStyle style);
/// The record: per direction k_1.1 (N/mm²) and m with standard errors and 95 %
/// half-widths, R², and every test with its residuals.
nlohmann::json kienzle_record(const KienzleResult& r);
/// The report the CLI prints.
std::string kienzle_report(const KienzleResult& r);
/// The [process] keys of the law (TOML: force_law, specific_force_n_per_mm2,
/// exponent, lead_angle_deg) for a turning config.
/// @throws InputError naming `out` when an exponent lies outside [0, 1).
std::string kienzle_fragment(const KienzleResult& r, ArgStyle style);

/// The arguments of `chatter coefficients`.
struct CoefficientArgs {
  std::filesystem::path tests;  ///< TESTS.csv
  int teeth = 0;
  double radial_immersion = 0.0;
  std::string milling_direction;           ///< down (climb) or up (conventional)
  std::optional<double> diameter_mm;       ///< needed for power tests
};

/// The tests read and fitted.
struct CoefficientResult {
  std::filesystem::path tests_path;
  CoefficientTests tests;
  CoefficientFit fit;
  MillingEngagement engagement;
  double radial_immersion = 0.0;
  double diameter_mm = 0.0;  ///< 0 when not given
  bool power() const { return tests.route == CoefficientRoute::kPower; }
};

/// Checks the arguments (before anything is read), reads the tests and fits
/// the coefficients. @throws InputError naming the argument, the file and line.
CoefficientResult fit_cutting_coefficients(const CoefficientArgs& args, ArgStyle style);
/// Only the argument checks (the CLI runs them before checking its outputs).
MillingEngagement coefficient_engagement(const CoefficientArgs& args, ArgStyle style);
/// The record (`chatter coefficients --json`): the coefficients in SI, their
/// standard errors and 95 % intervals, R², every test with its residuals.
nlohmann::json coefficients_record(const CoefficientResult& r);
/// The report the CLI prints (coefficients in shop units, R², residuals).
std::string coefficients_report(const CoefficientResult& r);
/// The [process] table of `--out` (TOML). @throws InputError naming `out`
/// for power tests (no radial coefficient) or coefficients that are no valid
/// [process] table (K_tc <= 0 or K_rc < 0).
std::string coefficients_fragment(const CoefficientResult& r, ArgStyle style);
/// The record with its fragment beside it (Python's chatter.coefficients,
/// whose result holds what the CLI writes to --out): "fragment" the
/// [process] text, or null when the tests give none (power tests;
/// coefficients or exponents that make no valid table: see warnings).
nlohmann::json coefficients_record_with_fragment(const CoefficientResult& r, ArgStyle style);
/// The same for Kienzle's law (kienzle_fragment).
nlohmann::json kienzle_record_with_fragment(const KienzleResult& r, ArgStyle style);

// ------------------------------------------------------------------ detect

/// The arguments of `chatter detect`.
struct DetectArgs {
  std::filesystem::path recording;
  double rpm = 0.0;
  int teeth = 0;
  std::optional<double> rpm_min, rpm_max;  ///< default: the config's [sweep], else 0.5 and 1.5 x rpm
  int channel = 1;
  double peak_ratio = 0.25;
  const Config* config = nullptr;          ///< with depth_mm: check each suggested speed (sdm)
  std::optional<double> depth_mm;
  bool force = false;                      ///< judge a recording without the tooth-passing line of rpm and teeth
};

/// The model's view of one suggested speed.
struct SuggestionCheck {
  bool bounded = false;
  double depth_limit_mm = 0.0, margin = 0.0;
};

struct DetectResult {
  std::filesystem::path recording_path;
  Recording recording;
  ChatterDetection detection;
  double rpm = 0.0, rpm_min = 0.0, rpm_max = 0.0, peak_ratio = 0.0, prominence_threshold = 0.0;
  int teeth = 0;
  std::string config_name;             ///< "" without a config
  double depth_mm = 0.0;               ///< with a config
  double check_depth_max_mm = 0.0;     ///< the depth searched for the checks (4 x depth_mm)
  std::string check_method;            ///< the method of the checks: "auto" as every command resolves it
  std::vector<SuggestionCheck> checks;  ///< per suggestion, with a config
};

/// Checks the arguments (before reading), reads the recording, detects
/// chatter and checks each suggested speed against the config (the default
/// method, "auto" as every command resolves it: sdm where it applies; depths
/// up to 4 x depth_mm). A recording without the tooth-passing line of rpm
/// and teeth is refused unless `force` (then a warning says so).
/// @throws InputError naming the argument or the file.
DetectResult detect_recording(const DetectArgs& args, ArgStyle style);
/// Only the checks of the arguments that need no file.
void check_detect_args(const DetectArgs& args, ArgStyle style);
/// The record (`chatter detect --json`).
nlohmann::json detect_record(const DetectResult& r);
/// chatter.detect's result: detect_record's fields and the group "spectrum"
/// (frequency_hz, amplitude: the spectrum the detection read).
ColumnRecord detect_columns(const DetectResult& r);
/// The report the CLI prints (verdict, evidence, speeds to try).
std::string detect_report(const DetectResult& r);

// ------------------------------------------------------------------ fit

/// The arguments of `chatter fit`.
struct FitArgs {
  std::filesystem::path file;
  std::string format;    ///< csv, tab or uff ("" = from the extension)
  std::string quantity;  ///< receptance, mobility or accelerance ("" = receptance; UFF: the record's)
  double scale = 1.0;
  std::string term;      ///< a `chatter frf` table: the term (default relative_xx)
  std::optional<int> record;  ///< UFF: one FRF record (1-based)
  std::optional<int> modes;   ///< the N highest peaks; none = every peak >= 5 % of the highest
  bool residuals = false;
  std::optional<std::pair<double, double>> band;  ///< Hz
  std::string body = "tool";
  std::string direction;  ///< x, y or "[ux, uy]" ("" = x; UFF: the record's)
  /// What the fragment is called in a warning ("modes.toml" for --out, or
  /// "the fragment").
  std::string fragment_name = "the fragment";
};

/// One FRF record fitted.
struct FittedRecord {
  FrfTable table;
  std::string label;  ///< "tap.csv", "tap.uff FRF record 2 (...)"
  std::string name;   ///< "" or "record 2" (plot key)
  Eigen::Vector2d direction{1.0, 0.0};
  ModalFitResult fit;
};

struct FitReport {
  std::filesystem::path file;
  std::string body;
  std::vector<FittedRecord> records;
  std::vector<std::string> warnings;
  std::string fragment;  ///< the [[<body>.modes]] blocks (TOML)
  std::string report;    ///< the text the CLI prints (modes, fit errors)
};

/// Checks the arguments that need no file (the CLI runs this before its outputs).
void check_fit_args(const FitArgs& args, ArgStyle style);
/// Reads the FRF file (CSV, tab, UFF 58/58b, or a `chatter frf` table) and
/// fits every direct term. @throws InputError naming the argument or file.
FitReport fit_frf_file(const FitArgs& args, ArgStyle style);
/// The record: file, body, per record its label, direction, band, modes
/// (frequency_hz, damping_ratio, stiffness_n_per_m) and beside them
/// relative_standard_errors (per mode: frequency, damping_ratio, stiffness as
/// fractions, null if not defined), fit error, iterations,
/// residual terms; warnings; the fragment.
nlohmann::json fit_record(const FitReport& r);
/// chatter.fit's result: fit_record's fields and, in each of its records,
/// measured_frequency_hz and measured_receptance_m_per_n (complex, m/N: the
/// file's lines) and fitted_frequency_hz and fitted_receptance_m_per_n (the
/// fitted model on kFittedPoints evenly spaced over the band, as the fit
/// plot draws it).
ColumnRecord fit_columns(const FitReport& r);
/// Points of the fitted curve over the band.
inline constexpr int kFittedPoints = 2001;
/// "x", "y" or "[ux, uy]".
std::string direction_text(const Eigen::Vector2d& u);

}  // namespace chatter
