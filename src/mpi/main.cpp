// chatter-mpi: `chatter surface` across MPI ranks (docs/scaling.md).
//   mpirun -n K chatter-mpi surface CONFIG [the options of chatter surface]
// Rank 0 parses and checks everything first (bad input: its message and exit
// 2, once); then every rank plans the same surface (the config is read on
// every rank: a shared file system on a cluster), the items (one position x a
// block of speeds) are shared by the dynamic runner (sweep_runner.hpp), and
// rank 0 writes the outputs with the code of `chatter surface`, so they are
// the same bytes.
#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <thread>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/position.hpp"
#include "cli_common.hpp"
#include "cmd_surface.hpp"
#include "sweep_runner.hpp"

namespace {

using chatter::InputError;
namespace cli = chatter::cli;
namespace po = boost::program_options;

constexpr const char* kHelp =
    "chatter-mpi: the sweeps of chatter across MPI processes and nodes (docs/scaling.md)\n\n"
    "Usage: mpirun -n K chatter-mpi surface CONFIG [the options of chatter surface]\n\n"
    "Every output is the same bytes as `chatter surface` with the same options. --threads is per\n"
    "process (0, the default: the cores of the node shared among its processes).\n";

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

int run(const std::vector<std::string>& argv, MPI_Comm comm, int rank, int size) {
  if (argv.empty() || argv.front() == "--help" || argv.front() == "-h" || argv.front() == "help") {
    if (rank == 0) (argv.empty() ? std::cerr : std::cout) << kHelp;
    return argv.empty() ? 2 : 0;
  }
  if (argv.front() != "surface") {
    if (rank == 0) std::cerr << "chatter-mpi: unknown command '" << argv.front() << "' (commands: surface)\n";
    return 2;
  }
  const std::vector<std::string> args(argv.begin() + 1, argv.end());

  // Rank 0 checks the command line, the config and the outputs; the others
  // wait for its verdict, so bad input gives one message.
  std::optional<cli::SurfacePlan> plan;
  int status = kPlanned;
  if (rank == 0) {
    try {
      plan = cli::plan_surface(args);
      if (!plan) status = kHelpShown;
    } catch (...) {
      status = report(std::current_exception(), "surface");
    }
  }
  MPI_Bcast(&status, 1, MPI_INT, 0, comm);
  if (status == kHelpShown) return 0;
  if (status != kPlanned) return status;
  std::string plan_error;  // a worker that cannot plan reports it on its first item
  if (rank != 0) {
    NullBuffer null;  // the config's warnings and solver notes: rank 0 printed them
    std::streambuf* old = std::cerr.rdbuf(&null);
    try {
      plan = cli::plan_surface(args, false);
    } catch (const std::exception& e) {
      plan_error = e.what();
    }
    std::cerr.rdbuf(old);
    if (!plan && plan_error.empty()) plan_error = "the command line planned nothing on this rank";
  }

  // Threads per rank: --threads, or the node's cores shared by its ranks.
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
  int on_node = 1;
  MPI_Comm_size(node, &on_node);
  MPI_Comm_free(&node);
  unsigned threads = plan ? plan->threads : 1;
  if (threads == 0) threads = std::max(1u, std::max(1u, std::thread::hardware_concurrency()) / static_cast<unsigned>(on_node));

  const std::size_t positions = plan ? plan->positions_m.size() : 0, speeds = plan ? plan->speeds_rpm.size() : 0;
  std::size_t count = rank == 0 ? surface_items(positions, speeds, size).size() : 0;
  unsigned long long n = count;
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
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
                          [&](std::size_t k) { row[k] = solver->limit_at(plan->speeds_rpm[it.first + k]); });
    return row;
  };

  chatter::mpi::SweepHooks hooks;
  hooks.exit_after_items = env_count("CHATTER_MPI_FAIL_AFTER_ITEMS");
  hooks.throw_after_items = env_count("CHATTER_MPI_THROW_AFTER_ITEMS");
  std::optional<cli::Progress> progress;
  if (rank == 0) {
    progress.emplace(plan->vm, static_cast<std::size_t>(n), "surface (" + plan->method + ", " + std::to_string(size) + " processes)");
    hooks.progress = [&](std::size_t done) { progress->tick(done); };
  }
  std::vector<std::vector<chatter::StabilityLimit>> parts;
  try {
    parts = chatter::mpi::run_sweep(comm, static_cast<std::size_t>(n), compute, hooks);
  } catch (const chatter::mpi::RankFailed& e) {
    progress.reset();
    std::cerr << "chatter-mpi: " << e.what() << " (the run failed: nothing written)\n";
    return 1;
  }
  if (rank != 0) return 0;
  progress.reset();

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
