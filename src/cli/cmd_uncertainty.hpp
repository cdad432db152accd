// `chatter lobes --samples N`: the Monte Carlo over the [uncertainty] spreads
// of the config (docs/uncertainty.md). plan_lobes (cmd_lobes.hpp) adds these
// options and checks them before computing; the samples are solved by
// sample_limits (in one process, or by ranges across MPI ranks in
// chatter-mpi), and reduce_uncertainty gives the quantile columns, the
// probability table and the summary; this file also adds the JSON record.
#pragma once

#include <cstdint>
#include <functional>
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

/// Refuses a config without an [uncertainty] table or with spreads its
/// model and process cannot take, before any solve. @throws InputError.
void check_uncertainty_config(const Config& cfg);

/// The limits of samples [begin, end) at `speeds` with the command's method
/// and options (monte_carlo_limits: rows[i - begin][s], bitwise independent of
/// the range split and of `threads`). `per_sample` as monte_carlo_limits.
/// @throws InputError (bad spreads, solver refusal), naming --samples.
std::vector<std::vector<StabilityLimit>> sample_limits(const UncertaintyRequest& request, const Config& cfg,
                                                       const std::string& method, double depth_max_mm,
                                                       const po::variables_map& vm, const std::vector<double>& speeds,
                                                       std::uint64_t begin, std::uint64_t end, unsigned threads,
                                                       const std::function<void(std::size_t)>& per_sample = {});

/// Reduces the rows of all the samples (rows[i][s], in sample order, as
/// sample_limits over [0, samples)) to the outputs. Pure; O(N S (log N + D)).
UncertaintyOutputs reduce_uncertainty(const UncertaintyRequest& request, double depth_max_mm,
                                      const po::variables_map& vm, const std::vector<double>& speeds,
                                      const std::vector<StabilityLimit>& nominal,
                                      const std::vector<std::vector<StabilityLimit>>& rows);

}  // namespace chatter::cli
