// `chatter surface` in its steps, shared by the `chatter` CLI and the MPI
// runner `chatter-mpi` (src/mpi/, docs/scaling.md):
//   plan_surface   parse the command line, load and check the config, check
//                  the outputs: everything that can fail on bad input, before
//                  any solve;
//   the solves     surface_rows (threads, one process), or the MPI runner
//                  over work items (surface_solver + limit_at per speed);
//   write_surface  the table, the summary and the plot, from the rows.
// Both executables run the same plan and write code, so their outputs are the
// same bytes when the rows are the same bits.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "chatter/io/plot.hpp"
#include "chatter/lobes.hpp"
#include "chatter/solvers.hpp"
#include "cli_common.hpp"

namespace chatter::cli {

/// What `chatter surface` computes and where it writes it.
struct SurfacePlan {
  Common common;
  po::variables_map vm;
  Config cfg;
  std::string table_path;   ///< "" = no table file
  std::string plot_path;    ///< "" = no plot
  bool table_to_stdout = false;
  std::vector<double> contours_mm;  ///< --plot-contours-mm (empty: automatic)
  ShowRequest show;                 ///< --show (a live window; chatter-mpi refuses it)
  Sweep sweep;
  double min_mm = 0.0, max_mm = 0.0;  ///< the position range as typed, mm
  std::vector<double> positions_mm;   ///< the table's position column
  std::vector<double> positions_m;    ///< the same positions for the model, m
  std::vector<double> speeds_rpm;
  std::string method;                 ///< the solver's method() name, for the summary and plot title
  SolverRecipe recipe;                ///< --method ("auto" resolved) and its checked options
  double depth_max_m = 0.0;
  unsigned threads = 0;               ///< --threads (0 = every core)
};

/// Parses `args` (after "surface") and plans the surface. Returns nullopt
/// when --help was printed. With `check_output_files` false the outputs are
/// not probed (a process that will not write them: the MPI workers).
/// @throws InputError / po::error on bad input (nothing written).
std::optional<SurfacePlan> plan_surface(const std::vector<std::string>& args, bool check_output_files = true);

/// The solver of the plan's method, options and depth for one structure
/// (the model at a position). Thread-safe. @throws InputError.
std::unique_ptr<LobeSolver> surface_solver(const SurfacePlan& plan, const StructuralModel& model);

/// rows[p][s] for every position and speed of the plan in this process
/// (lobe_surface on plan.threads threads, with the progress bar).
std::vector<std::vector<StabilityLimit>> surface_rows(const SurfacePlan& plan);

/// Writes the table (file or standard output), the summary and the plot of
/// `rows` (rows[p][s], as surface_rows), and draws it in `window` when given
/// (--show). Returns the exit status (0).
/// @throws InputError if an output cannot be written.
int write_surface(const SurfacePlan& plan, const std::vector<std::vector<StabilityLimit>>& rows,
                  PlotWindow* window = nullptr);

}  // namespace chatter::cli
