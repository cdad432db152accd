// Shared pieces of the `chatter` subcommands: option parsing with a
// positional CONFIG, the --method option, sweep resolution from flags and the
// config's [sweep] table. Only the CLI includes Boost.Program_options.
#pragma once

#include <boost/program_options.hpp>

#include <string>
#include <vector>

#include "chatter/io/config.hpp"

namespace chatter::cli {

namespace po = boost::program_options;

inline constexpr double kDefaultDepthMaxMm = 50.0;
inline constexpr int kDefaultRpmPoints = 400;

/// A number for messages and summaries.
std::string fmt(double x, int digits = 6);

struct Common {
  std::string config_path;
  std::string method = "analytic";
};

/// Adds --method to `d`.
void add_common(po::options_description& d, Common& c);

/// Parses a subcommand's arguments (positional CONFIG); returns false if
/// --help was printed. @throws po::error on a usage error.
bool parse(const std::vector<std::string>& args, const std::string& usage, po::options_description& visible,
           Common& common, po::variables_map& vm);

/// Speeds and depth from --rpm-min/--rpm-max/--rpm-points/--depth-max-mm,
/// falling back on the config's [sweep]. @throws InputError.
struct Sweep {
  double rpm_min = 0.0, rpm_max = 0.0, depth_max_mm = kDefaultDepthMaxMm;
  int rpm_points = kDefaultRpmPoints;
};
Sweep resolve_sweep(const po::variables_map& vm, const Config& cfg);

}  // namespace chatter::cli
