// A generic sweep over MPI ranks (docs/scaling.md): W independent work items,
// each computed by one rank into a row (bytes, or a vector of
// StabilityLimit), gathered on rank 0 in item order. Used by `chatter-mpi
// surface` (an item = one position x a block of speeds) and `chatter-mpi
// lobes --samples` (an item = a block of Monte Carlo samples x every speed);
// any sweep whose items are independent fits the same runner.
//
// Work split: dynamic, master-worker. Rank 0's main thread serves: it answers
// each worker's request with the next item index (or "stop"), receives the
// results and never blocks (MPI_Iprobe, then a 0.2 ms sleep when nothing has
// arrived). A second thread on rank 0 computes items from the same counter,
// so with K ranks K processes compute. A worker asks for an item, computes
// it, sends the row back (which asks for the next) until told to stop.
// MPI threading: MPI_THREAD_FUNNELED (only rank 0's main thread calls MPI).
//
// Identity: rows travel as raw bytes (MPI_BYTE, the doubles bit for bit) and
// each item's row depends only on its index, so the gathered rows are the
// same bits whatever the rank count, the item order and who computed what.
// Homogeneous clusters only (same byte order and double format).
//
// Failure: an exception on any rank (rank 0's own items included) stops
// handing out work; the ranks busy finish their current item, and rank 0
// throws RankFailed naming the rank and its message. A rank that dies (signal,
// exit) makes mpirun end the whole job (Open MPI's default), before rank 0
// has written anything.
//
// Cost per item: two messages (16 bytes out, 8 + row bytes back) and at most
// ~0.2 ms of serving latency.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "chatter/lobes.hpp"

namespace chatter::mpi {

using Bytes = std::vector<unsigned char>;

/// A rank failed: what() = "rank R: <its message>".
class RankFailed : public std::runtime_error {
 public:
  RankFailed(int rank, const std::string& what) : std::runtime_error("rank " + std::to_string(rank) + ": " + what), rank_(rank) {}
  int rank() const { return rank_; }

 private:
  int rank_;
};

struct SweepHooks {
  /// On rank 0 (from its serving thread), after each item gathered: the
  /// number gathered so far.
  std::function<void(std::size_t done)> progress;
  /// Test hook (docs/scaling.md): a worker (rank >= 1) whose rank equals
  /// fail_rank exits with _exit(3) after sending `exit_after_items` results
  /// (< 0: never), or throws after computing `throw_after_items` (< 0: never).
  int fail_rank = 1;
  long exit_after_items = -1;
  long throw_after_items = -1;
};

/// Runs compute(i) for i in [0, items) across the ranks of `comm` (every rank
/// calls this with the same `items`). Returns, on rank 0, the rows in item
/// order; on the other ranks an empty vector.
/// @throws RankFailed on rank 0 if any rank's compute threw (the other ranks
///         return normally: the failure is reported once, by rank 0).
std::vector<Bytes> run_sweep_bytes(MPI_Comm comm, std::size_t items, const std::function<Bytes(std::size_t)>& compute,
                                   const SweepHooks& hooks = {});

/// Rows of stability limits, bit for bit (3 doubles + 2 ints per limit).
Bytes encode_limits(const std::vector<StabilityLimit>& row);
/// @throws std::runtime_error if `bytes` is not a whole number of limits.
std::vector<StabilityLimit> decode_limits(const Bytes& bytes);

/// run_sweep_bytes with StabilityLimit rows.
std::vector<std::vector<StabilityLimit>> run_sweep(MPI_Comm comm, std::size_t items,
                                                   const std::function<std::vector<StabilityLimit>(std::size_t)>& compute,
                                                   const SweepHooks& hooks = {});

}  // namespace chatter::mpi
