// chatter-mpi: `chatter surface` and `chatter lobes --samples N` across MPI
// ranks (docs/scaling.md).
//   mpirun -n K chatter-mpi surface CONFIG [the options of chatter surface]
//   mpirun -n K chatter-mpi lobes CONFIG --samples N [the options of chatter lobes]
// Rank 0 parses and checks everything first (bad input: its message and exit
// 2, once); then every rank plans the same surface (the config is read on
// every rank: a shared file system on a cluster), the items (one position x a
// block of speeds; for lobes a block of samples) are shared by the dynamic
// runner (sweep_runner.hpp), and rank 0 writes the outputs with the code of
// `chatter surface` / `chatter lobes`, so they are the same bytes.
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <cstdlib>
#include <functional>
#include <optional>
#include <iostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <thread>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/position.hpp"
#include "cli_common.hpp"
#include "cmd_lobes.hpp"
#include "cmd_surface.hpp"
#include "sweep_runner.hpp"

namespace {

using chatter::InputError;
namespace cli = chatter::cli;
namespace po = boost::program_options;

constexpr const char* kHelp =
    "chatter-mpi: the sweeps of chatter across MPI processes and nodes (docs/scaling.md)\n\n"
    "Usage: mpirun -n K chatter-mpi surface CONFIG [the options of chatter surface]\n"
    "       mpirun -n K chatter-mpi lobes CONFIG --samples N [the options of chatter lobes]\n\n"
    "Every output is the same bytes as `chatter surface` / `chatter lobes` with the same options.\n"
    "lobes runs the Monte Carlo over the config's [uncertainty] spreads (--samples N, required: the\n"
    "nominal table alone is one process's work, run `chatter lobes`). --threads is per process\n"
    "(0, the default: the cores of the node shared among its processes).\n";

// Work items per rank the split aims at: with dynamic hand-out the last item
// to finish leaves the others idle for at most one item, <= 1/8 of a rank's
// share; more items cost one solver build and two messages each.
constexpr std::size_t kItemsPerRank = 8;

// Status rank 0 broadcasts after checking the command line.
constexpr int kPlanned = 0, kHelpShown = -1;

struct NullBuffer : std::streambuf {
  int overflow(int c) override { return c; }
};

// Exit status and message of an exception escaping the command (as `chatter`).
int report(const std::exception_ptr& e, const std::string& command) {
  try {
    std::rethrow_exception(e);
  } catch (const po::error& x) {
    const char* hint = dynamic_cast<const po::invalid_option_value*>(&x)
                           ? ": expected a number (a whole number for counts such as --revolutions, --periods, "
                             "--rpm-points)"
                           : "";
    std::cerr << "chatter-mpi: " << x.what() << hint << " (see chatter " << command << " --help)\n";
    return 2;
  } catch (const InputError& x) {
    std::istringstream lines(x.what());
    for (std::string line; std::getline(lines, line);) std::cerr << "chatter-mpi: " << line << "\n";
    return 2;
  } catch (const std::exception& x) {
    std::cerr << "chatter-mpi: internal error: " << x.what() << "\n";
    return 1;
  }
}

long env_count(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::strtol(v, nullptr, 10) : -1;
}

// One item: position p, speeds [first, first + count).
struct Item {
  std::size_t position = 0, first = 0, count = 0;
};

std::vector<Item> surface_items(std::size_t positions, std::size_t speeds, int ranks) {
  const std::size_t want = kItemsPerRank * static_cast<std::size_t>(ranks);
  const std::size_t blocks = std::min(speeds, std::max<std::size_t>(1, (want + positions - 1) / positions));
  const std::size_t per = (speeds + blocks - 1) / blocks;
  std::vector<Item> items;
  for (std::size_t p = 0; p < positions; ++p)
    for (std::size_t first = 0; first < speeds; first += per)
      items.push_back({p, first, std::min(per, speeds - first)});
  return items;
}

// Threads per rank: --threads, or the node's cores shared by its ranks.
unsigned rank_threads(MPI_Comm comm, int rank, unsigned asked) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
  int on_node = 1;
  MPI_Comm_size(node, &on_node);
  MPI_Comm_free(&node);
  if (asked != 0) return asked;
  return std::max(1u, std::max(1u, std::thread::hardware_concurrency()) / static_cast<unsigned>(on_node));
}

// Rank 0 plans (make(true)); the other ranks wait for its verdict, so bad
// input gives one message. Then the others plan quietly (make(false)); a worker that cannot
// plan reports it on its first item (plan_error). Returns -1 to go on, else
// the exit status every rank returns.
template <class Plan>
int plan_on_every_rank(MPI_Comm comm, int rank, const std::string& command,
                       const std::function<std::optional<Plan>(bool)>& make, std::optional<Plan>& plan,
                       std::string& plan_error) {
  int status = kPlanned;
  if (rank == 0) {
    try {
      plan = make(true);
      if (!plan) status = kHelpShown;
    } catch (...) {
      status = report(std::current_exception(), command);
    }
  }
  MPI_Bcast(&status, 1, MPI_INT, 0, comm);
  if (status == kHelpShown) return 0;
  if (status != kPlanned) return status;
  if (rank != 0) {
    NullBuffer null;  // the config's warnings and solver notes: rank 0 printed them
    std::streambuf* old = std::cerr.rdbuf(&null);
    try {
      plan = make(false);
    } catch (const std::exception& e) {
      plan_error = e.what();
    }
    std::cerr.rdbuf(old);
    if (!plan && plan_error.empty()) plan_error = "the command line planned nothing on this rank";
  }
  return -1;
}

chatter::mpi::SweepHooks test_hooks() {
  chatter::mpi::SweepHooks hooks;
  hooks.exit_after_items = env_count("CHATTER_MPI_FAIL_AFTER_ITEMS");
  hooks.throw_after_items = env_count("CHATTER_MPI_THROW_AFTER_ITEMS");
  return hooks;
}

// The item count: rank 0's, broadcast (the others check theirs against it).
std::size_t broadcast_count(MPI_Comm comm, std::size_t on_rank0) {
  unsigned long long n = on_rank0;
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
  return static_cast<std::size_t>(n);
}

/// Runs the sweep with the test hooks and, on rank 0, a progress line; the
/// rows on rank 0 (empty elsewhere), or nullopt after reporting a failed rank.
std::optional<std::vector<std::vector<chatter::StabilityLimit>>> gather(
    MPI_Comm comm, int rank, const po::variables_map& vm, std::size_t n, const std::string& label,
    const std::function<std::vector<chatter::StabilityLimit>(std::size_t)>& compute) {
  chatter::mpi::SweepHooks hooks = test_hooks();
  std::optional<cli::Progress> progress;
  if (rank == 0) {
    progress.emplace(vm, n, label);
    hooks.progress = [&](std::size_t done) { progress->tick(done); };
  }
  try {
    return chatter::mpi::run_sweep(comm, n, compute, hooks);
  } catch (const chatter::mpi::RankFailed& e) {
    progress.reset();
    std::cerr << "chatter-mpi: " << e.what() << " (the run failed: nothing written)\n";
    return std::nullopt;
  }
}

// --show opens a gnuplot window from one process: the `chatter` executable's.
constexpr const char* kNoShow =
    "--show: chatter-mpi draws no live plot (its ranks may run on other machines): write an image with --plot "
    "FILE, or run chatter with --show";

int run_surface(const std::vector<std::string>& args, MPI_Comm comm, int rank, int size) {
  std::optional<cli::SurfacePlan> plan;
  std::string plan_error;
  const int planned = plan_on_every_rank<cli::SurfacePlan>(
      comm, rank, "surface",
      [&](bool rank0) {
        std::optional<cli::SurfacePlan> p = cli::plan_surface(args, rank0);
        if (p && p->show.requested) throw InputError(kNoShow);
        return p;
      },
      plan, plan_error);
  const unsigned threads = rank_threads(comm, rank, plan ? plan->threads : 1);
  if (planned >= 0) return planned;

  const std::size_t positions = plan ? plan->positions_m.size() : 0, speeds = plan ? plan->speeds_rpm.size() : 0;
  const std::size_t n = broadcast_count(comm, rank == 0 ? surface_items(positions, speeds, size).size() : 0);
  const std::vector<Item> items = plan ? surface_items(positions, speeds, size) : std::vector<Item>{};
  auto compute = [&](std::size_t i) -> std::vector<chatter::StabilityLimit> {
    if (!plan) throw std::runtime_error(plan_error);
    if (items.size() != n) throw std::runtime_error("planned a different surface than rank 0");
    const Item& it = items[i];
    const chatter::StructuralModel model =
        chatter::model_at_position(plan->cfg.model, plan->cfg.position, plan->positions_m[it.position]);
    const auto solver = cli::surface_solver(*plan, model);
    std::vector<chatter::StabilityLimit> row(it.count);
    chatter::parallel_for(it.count, threads,
                          [&](std::size_t k) { row[k] = solver->limit_at(chatter::SpindleSpeed(plan->speeds_rpm[it.first + k])); });
    return row;
  };

  auto gathered = gather(comm, rank, plan->vm, n,
                         "surface (" + plan->method + ", " + std::to_string(size) + " processes)", compute);
  if (!gathered) return 1;
  if (rank != 0) return 0;
  const auto& parts = *gathered;

  // Assemble rows[position][speed] in item order, then write as `chatter surface`.
  std::vector<std::vector<chatter::StabilityLimit>> rows(positions);
  for (std::size_t i = 0; i < items.size(); ++i) {
    auto& row = rows[items[i].position];
    row.insert(row.end(), parts[i].begin(), parts[i].end());
  }
  try {
    return cli::write_surface(*plan, rows);
  } catch (...) {
    return report(std::current_exception(), "surface");
  }
}

// Blocks [begin, end) of the samples [0, N): about kItemsPerRank per rank.
std::vector<std::pair<std::uint64_t, std::uint64_t>> sample_blocks(std::uint64_t samples, int ranks) {
  const std::uint64_t want = kItemsPerRank * static_cast<std::uint64_t>(ranks);
  const std::uint64_t blocks = std::max<std::uint64_t>(1, std::min(samples, want));
  const std::uint64_t per = (samples + blocks - 1) / blocks;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> out;
  for (std::uint64_t b = 0; b < samples; b += per) out.emplace_back(b, std::min(samples, b + per));
  return out;
}

// `chatter lobes --samples N`: rank 0 plans, then solves the nominal table
// (one sample's work) in a thread beside the sweep; the items are blocks of
// samples, each
// solved by monte_carlo_limits over its range (bitwise the rows of the whole
// run), gathered in sample order; rank 0 reduces and writes as `chatter lobes`.
int run_lobes(const std::vector<std::string>& args, MPI_Comm comm, int rank, int size) {
  std::optional<cli::LobesPlan> plan;
  std::string plan_error;
  cli::NominalTable nominal;
  unsigned threads = 1;
  const auto make = [&](bool rank0) {
    std::optional<cli::LobesPlan> p = cli::plan_lobes(args, rank0);
    if (p && p->show.requested) throw InputError(kNoShow);
    if (p && !p->uncertainty)
      throw InputError("lobes: chatter-mpi runs the Monte Carlo of the lobes only: give --samples N (and an "
                       "[uncertainty] table in the config); for the nominal table alone run chatter lobes");
    return p;
  };
  const int planned = plan_on_every_rank<cli::LobesPlan>(comm, rank, "lobes", make, plan, plan_error);
  threads = rank_threads(comm, rank, plan ? plan->threads : 1);
  if (planned >= 0) return planned;
  // Rank 0 solves the nominal table in a thread of its own while the sweep
  // runs, so no rank waits for it (its error, if any, is reported after).
  std::exception_ptr nominal_error;
  std::jthread nominal_thread;
  if (rank == 0)
    nominal_thread = std::jthread([&] {
      try {
        nominal = cli::lobes_nominal(*plan, threads, false);
      } catch (...) {
        nominal_error = std::current_exception();
      }
    });

  const std::uint64_t samples = plan ? plan->uncertainty->samples : 0;
  const std::size_t speeds = plan ? plan->speeds_rpm.size() : 0;
  const std::size_t n = broadcast_count(comm, rank == 0 ? sample_blocks(samples, size).size() : 0);
  const auto blocks = plan ? sample_blocks(samples, size) : std::vector<std::pair<std::uint64_t, std::uint64_t>>{};
  auto compute = [&](std::size_t i) -> std::vector<chatter::StabilityLimit> {
    if (!plan) throw std::runtime_error(plan_error);
    if (blocks.size() != n) throw std::runtime_error("planned a different Monte Carlo than rank 0");
    std::vector<chatter::StabilityLimit> flat;
    for (auto& row : cli::lobes_samples(*plan, blocks[i].first, blocks[i].second, threads))
      flat.insert(flat.end(), row.begin(), row.end());
    return flat;
  };

  auto gathered = gather(comm, rank, plan->vm, n,
                         "Monte Carlo (" + plan->common.method + ", " + std::to_string(size) + " processes)", compute);
  if (!gathered) return 1;
  if (rank != 0) return 0;
  const auto& parts = *gathered;
  nominal_thread.join();
  if (nominal_error) return report(nominal_error, "lobes");

  // rows[sample][speed] in sample order, then reduce and write as `chatter lobes`.
  std::vector<std::vector<chatter::StabilityLimit>> rows;
  rows.reserve(static_cast<std::size_t>(samples));
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const std::size_t count = static_cast<std::size_t>(blocks[i].second - blocks[i].first);
    if (parts[i].size() != count * speeds) {
      std::cerr << "chatter-mpi: internal error: block " << i << " came back with " << parts[i].size()
                << " limits, expected " << count * speeds << " (nothing written)\n";
      return 1;
    }
    for (std::size_t k = 0; k < count; ++k)
      rows.emplace_back(parts[i].begin() + static_cast<std::ptrdiff_t>(k * speeds),
                        parts[i].begin() + static_cast<std::ptrdiff_t>((k + 1) * speeds));
  }
  try {
    return cli::write_lobes(*plan, nominal, rows);
  } catch (...) {
    return report(std::current_exception(), "lobes");
  }
}

int run(const std::vector<std::string>& argv, MPI_Comm comm, int rank, int size) {
  if (argv.empty() || argv.front() == "--help" || argv.front() == "-h" || argv.front() == "help") {
    if (rank == 0) (argv.empty() ? std::cerr : std::cout) << kHelp;
    return argv.empty() ? 2 : 0;
  }
  const std::vector<std::string> args(argv.begin() + 1, argv.end());
  if (argv.front() == "surface") return run_surface(args, comm, rank, size);
  if (argv.front() == "lobes") return run_lobes(args, comm, rank, size);
  if (rank == 0) std::cerr << "chatter-mpi: unknown command '" << argv.front() << "' (commands: surface, lobes)\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int status = 0;
  if (provided < MPI_THREAD_FUNNELED) {
    if (rank == 0) std::cerr << "chatter-mpi: the MPI library gives no MPI_THREAD_FUNNELED (rank 0 serves and computes)\n";
    status = 1;
  } else {
    try {
      status = run(std::vector<std::string>(argv + 1, argv + argc), MPI_COMM_WORLD, rank, size);
    } catch (const std::exception& e) {
      std::cerr << "chatter-mpi: rank " << rank << ": internal error: " << e.what() << "\n";
      status = 1;
    }
  }
  MPI_Finalize();
  return status;
}
