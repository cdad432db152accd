// Reading shop data (issue 18): cutting-test tables, dynamometer force
// series and recordings (audio through libsndfile, or CSV). Every error is an
// InputError naming the file and, for text files, the line. User guide:
// docs/shop_data.md. The numerics are in include/chatter/shop.hpp.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "chatter/shop.hpp"

namespace chatter {

/// How a tests table gives the cuts.
enum class CoefficientRoute {
  kForces,  ///< columns feed_per_tooth_mm, depth_mm, fx_mean_n, fy_mean_n [, fz_mean_n]
  kSeries,  ///< columns feed_per_tooth_mm, depth_mm, spindle_rpm, series (a force-series CSV per row)
  kPower,   ///< columns feed_per_tooth_mm, depth_mm, spindle_rpm, power_w
};

/// A tests table, in SI, with the line of each test for messages.
struct CoefficientTests {
  CoefficientRoute route = CoefficientRoute::kForces;
  std::vector<ForceTest> forces;  ///< forces and series routes (series: the revolution averages)
  std::vector<PowerTest> power;   ///< power route
  std::vector<int> line;          ///< 1-based line in the file, per test
  std::vector<double> spindle_rpm;       ///< series route, per test
  std::vector<std::string> series_file;  ///< series route: path as resolved (relative to the table's folder)
  std::vector<RevolutionAverage> series_average;  ///< series route
  std::vector<double> fz_mean_n;  ///< when the column is present (reported, not fitted)
};

/// Reads TESTS.csv: a header line naming the columns (any order, extra
/// columns ignored), then one test per line; blank lines and lines starting
/// with '#' are skipped. The route follows the columns: fx_mean_n/fy_mean_n,
/// else series, else power_w. Series files are read and averaged over whole
/// revolutions here. Feeds and depths must be > 0, speeds > 0, power >= 0.
/// @throws InputError "<file>: line <n>: <column> = '<text>': <rule>", or
///   "<file>: line 1: missing column <name>", or on an unreadable file.
CoefficientTests read_coefficient_tests(const std::filesystem::path& csv);

/// True when TESTS.csv's header names feed_mm_per_rev: turning tests for
/// Kienzle's law (read_turning_tests), not a milling table.
/// @throws InputError on an unreadable or empty file.
bool is_turning_tests_table(const std::filesystem::path& csv);

/// Turning tests: columns feed_mm_per_rev, depth_mm, tangential_force_n,
/// feed_force_n [, radial_force_n] (any order, extra columns ignored), each
/// force > 0 and within 1e6 N, feed in (0, 100) mm, depth in (0, 1000) mm.
struct TurningTests {
  std::vector<TurningForceTest> tests;
  std::vector<int> line;  ///< 1-based line in the file, per test
};
/// @throws InputError "<file>: line <n>: <column> = <value>: <rule>".
TurningTests read_turning_tests(const std::filesystem::path& csv);

/// A dynamometer series: columns time_s, fx_n, fy_n [, fz_n] (header line
/// required), time strictly increasing. @throws InputError naming file and line.
struct ForceSeries {
  std::vector<double> time_s, fx_n, fy_n, fz_n;
};
ForceSeries read_force_series(const std::filesystem::path& csv);

/// One channel of a recording.
struct Recording {
  double sample_rate_hz = 0.0;
  std::vector<double> samples;  ///< as stored (audio: full scale ±1)
  int channels = 1;             ///< channels in the file
  int channel = 1;              ///< the one read, 1-based
  std::string format;           ///< "WAV (16-bit PCM)", "CSV", ...
};

/// Reads a recording: `.csv` as `time_s,value` (header optional; time
/// strictly increasing and uniformly spaced within 1 %), anything else
/// through libsndfile (WAV, FLAC, AIFF, ...; any sample rate). `channel` is
/// 1-based (CSV: must be 1).
/// @throws InputError on an unreadable, empty or malformed file, or a
///   channel the file does not have. Cost O(samples).
Recording read_recording(const std::filesystem::path& file, int channel = 1);

}  // namespace chatter
