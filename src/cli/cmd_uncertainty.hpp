// `chatter lobes --samples N`: the Monte Carlo over the [uncertainty] spreads
// of the config (docs/uncertainty.md). cmd_lobes (main.cpp) adds these
// options, checks them before computing, runs the samples after the nominal
// table and lets this file add the quantile columns, the JSON record, the
// probability table, the summary and the plot.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "chatter/io/table_writer.hpp"
#include "chatter/uncertainty.hpp"
#include "cli_common.hpp"

namespace chatter::cli {

/// --samples, --seed, --depth-points, --probability-table.
void add_uncertainty_options(po::options_description& d);

/// What the command line asked for (checked: samples > 0, --seed only with
/// --samples, even spacing, the rows fit in memory).
struct UncertaintyRequest {
  std::uint64_t samples = 0;
  std::uint64_t seed = 1;
  int depth_points = 100;
  std::string probability_table;  ///< --probability-table path ("" = not asked)
};
/// nullopt without --samples (and then none of its options may be given).
/// `rpm_points` is the table's speed count. @throws InputError naming the flag.
std::optional<UncertaintyRequest> uncertainty_request(const po::variables_map& vm, bool adaptive, int rpm_points);

/// The Monte Carlo's results as the outputs want them.
struct UncertaintyOutputs {
  UncertainLobes lobes;
  std::vector<ExtraColumn> columns;  ///< depth_limit_p05_mm, _p50_mm, _p95_mm
  std::string probability_csv;       ///< spindle_rpm,depth_mm,probability_stable
  std::string summary;               ///< one line for the machinist
  double depth_grid_top_mm = 0.0;    ///< the top of the probability grid
};

/// Solves every sample at `speeds` with the command's method and options
/// and reduces them. @throws InputError (no [uncertainty] table, bad
/// spreads, solver refusal).
UncertaintyOutputs run_uncertainty(const UncertaintyRequest& request, const Config& cfg, const std::string& method,
                                   double depth_max_mm, const po::variables_map& vm, const std::vector<double>& speeds,
                                   const std::vector<StabilityLimit>& nominal, unsigned threads);

/// The lobe JSON with an "uncertainty" record added (samples, seed, spreads in
/// percent, distribution, quantile definition).
std::string add_uncertainty_json(const std::string& lobe_json, const UncertaintyRequest& request,
                                 const Config& cfg, const UncertaintyOutputs& out);

}  // namespace chatter::cli
