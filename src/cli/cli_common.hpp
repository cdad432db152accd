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
  bool strict = false;  ///< --strict: the config's plausibility warnings are errors
};

/// Adds --method to `d`.
void add_common(po::options_description& d, Common& c);

/// Parses a subcommand's arguments (positional CONFIG, --strict); returns
/// false if --help was printed. @throws po::error on a usage error.
bool parse(const std::vector<std::string>& args, const std::string& usage, po::options_description& visible,
           Common& common, po::variables_map& vm);

/// Loads CONFIG and prints each plausibility warning on stderr as
/// "warning: <file>: <key> = <value>: <what>". With --strict the warnings are
/// errors: @throws InputError listing them (before anything is written).
Config load_checked(const Common& common);

/// Speeds and depth from --rpm-min/--rpm-max/--rpm-points/--depth-max-mm,
/// falling back on the config's [sweep]. @throws InputError.
struct Sweep {
  double rpm_min = 0.0, rpm_max = 0.0, depth_max_mm = kDefaultDepthMaxMm;
  int rpm_points = kDefaultRpmPoints;
};
Sweep resolve_sweep(const po::variables_map& vm, const Config& cfg);

}  // namespace chatter::cli

#include <chrono>
#include <memory>
#include <mutex>

#include "chatter/lobes.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/time_domain.hpp"
#include "chatter/transfer_function.hpp"

namespace chatter::cli {

/// Adds the solver-tuning options: --threads, --quiet and, for sdm, --steps.
void add_solver_options(po::options_description& d);

/// The solver chosen by --method, built with the sweep depth; exactly one of
/// `tf` / `sdm` points into `solver`.
struct BuiltSolver {
  std::unique_ptr<LobeSolver> solver;
  const TransferFunctionSolver* tf = nullptr;
  const SemiDiscretizationSolver* sdm = nullptr;
  const TimeDomainSolver* td = nullptr;
  std::string options_json;  ///< the solver's options, for the JSON provenance
};
/// Refuses a solver option that none of `methods` uses: --steps (sdm);
/// --periods, --feed-per-tooth-mm, --multiple-regeneration, --linear
/// (time-domain). `chooser` is the option that picked the methods ("--method"
/// or "--methods"), for the message. @throws InputError.
void check_solver_options(const std::vector<std::string>& methods, const po::variables_map& vm,
                          const std::string& chooser);

/// @throws InputError on an unknown method or bad option. Unless
/// `check_options` is false (the caller already ran check_solver_options over
/// all the methods it builds, as `compare` does), first refuses the options
/// `method` does not use.
BuiltSolver build_solver(const std::string& method, const Config& cfg, double depth_max_m,
                         const po::variables_map& vm, bool check_options = true);

/// Threads from --threads (0 = every core).
unsigned thread_count(const po::variables_map& vm);

/// A progress bar with the time left, on stderr, only when stderr is a
/// terminal and --quiet is not given, and only once `show_after_s` seconds
/// have passed (short runs stay silent). Safe to tick from worker threads.
class Progress {
 public:
  Progress(const po::variables_map& vm, std::size_t total, std::string label, double show_after_s = 0.0);
  ~Progress();
  void tick(std::size_t done);

 private:
  bool enabled_;
  std::size_t total_;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_;
  std::chrono::duration<double> show_after_;
  bool shown_ = false;
};

}  // namespace chatter::cli
