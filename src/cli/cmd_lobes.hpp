// `chatter lobes` in its steps, shared by the `chatter` CLI and the MPI
// runner `chatter-mpi lobes --samples N` (src/mpi/, docs/scaling.md):
//   plan_lobes     parse the command line, load and check the config, the
//                  Monte Carlo request and the outputs: everything that can
//                  fail on bad input, before any solve;
//   lobes_nominal  the nominal table (even or adaptive speeds, with the
//                  solver's diagnostic columns);
//   lobes_samples  the Monte Carlo limits of samples [begin, end) (one
//                  process: [0, N) on threads; chatter-mpi: blocks of samples
//                  across ranks, gathered in sample order);
//   write_lobes    the reduction, table, JSON, probability table, summary and
//                  plot, from the nominal table and the sample rows.
// Both executables run the same plan and write code, so their outputs are the
// same bytes when the rows are the same bits.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"
#include "cli_common.hpp"
#include "cmd_uncertainty.hpp"

namespace chatter::cli {

/// What `chatter lobes` computes and where it writes it.
struct LobesPlan {
  Common common;
  po::variables_map vm;
  Config cfg;
  Sweep sweep;
  std::string table_path;  ///< "" = no table file
  std::string json_path;   ///< "" = no JSON
  std::string plot_path;   ///< "" = no plot
  std::string spacing = "even";
  bool adaptive = false;
  bool table_to_stdout = false;
  bool json_to_stdout = false;  ///< --json - : the JSON on standard output, the summary on standard error
  double plot_depth_axis_mm = 0.0;                 ///< plot_depth_max_mm
  ShowRequest show;                                ///< --show (a live window; chatter-mpi refuses it)
  std::optional<UncertaintyRequest> uncertainty;   ///< --samples (checked, config included)
  std::optional<double> planned_mm;                ///< --depth-mm
  unsigned threads = 0;                            ///< --threads (0 = every core)
  BuiltSolver built;                               ///< the nominal solver (its notes printed once)
  std::vector<double> speeds_rpm;                  ///< even spacing: the table's speeds (adaptive: empty)
};

/// The nominal lobe table.
struct NominalTable {
  std::vector<StabilityLimit> rows;
  std::vector<ExtraColumn> extra;  ///< the solver's diagnostic columns (e.g. sdm's multiplier_type)
  bool tolerance_met = false;      ///< adaptive spacing: the 0.5 % midpoint tolerance met everywhere
};

/// Parses `args` (after "lobes") and plans the table. Returns nullopt when
/// --help was printed. With `check_output_files` false the outputs are not
/// probed (a process that will not write them: the MPI workers). With
/// --samples the config's [uncertainty] table is checked here too.
/// @throws InputError / po::error on bad input (nothing written).
std::optional<LobesPlan> plan_lobes(const std::vector<std::string>& args, bool check_output_files = true);

/// The nominal table on `threads` threads, with the progress bar unless
/// `progress` is false (chatter-mpi solves it beside the Monte Carlo, whose
/// bar it shows). Thread-safe. Cost: one limit_at per speed (adaptive: up to
/// --rpm-points).
NominalTable lobes_nominal(const LobesPlan& plan, unsigned threads, bool progress = true);

/// The Monte Carlo limits of samples [begin, end) at plan.speeds_rpm
/// (precondition: plan.uncertainty): rows[i - begin][s], bitwise the same
/// whatever the split of [0, N) and `threads`. Cost: (end - begin) x (one
/// solver build + speeds x limit_at). @throws InputError (solver refusal).
std::vector<std::vector<StabilityLimit>> lobes_samples(const LobesPlan& plan, std::uint64_t begin, std::uint64_t end,
                                                       unsigned threads,
                                                       const std::function<void(std::size_t)>& per_sample = {});

/// Writes the outputs of the plan from the nominal table and (with
/// --samples) the rows of all N samples in sample order, and draws the plot
/// in `window` when given (--show). Returns the exit status (0, or
/// kExitChatter with --fail-on-chatter). Extra solves only for a plot
/// without --samples (the refined envelope, once for the image and the
/// window). @throws InputError if an output cannot be written.
int write_lobes(const LobesPlan& plan, const NominalTable& nominal,
                const std::vector<std::vector<StabilityLimit>>& samples, PlotWindow* window = nullptr);

}  // namespace chatter::cli
