// The MPI sweep runner (sweep_runner.hpp).
#include "sweep_runner.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <exception>
#include <iostream>
#include <mutex>
#include <optional>
#include <thread>

namespace chatter::mpi {
namespace {

// Message tags. Worker -> rank 0: kReady (no payload: the first request),
// kResult (item index, then the row: also the next request), kError (the
// message text). Rank 0 -> worker: kWork (item index), kStop (no payload).
constexpr int kReady = 1, kResult = 2, kError = 3, kWork = 4, kStop = 5;
// How long rank 0's serving loop sleeps when no message and no local result
// is waiting: short against an item (>= milliseconds), long enough that the
// serving thread takes no measurable CPU from the computing ones.
constexpr auto kServePoll = std::chrono::microseconds(200);
constexpr std::size_t kNone = static_cast<std::size_t>(-1);

std::string what_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::exception& x) {
    return x.what();
  } catch (...) {
    return "unknown exception";
  }
}

void send_index(MPI_Comm comm, int dest, int tag, std::uint64_t i) {
  MPI_Send(&i, 8, MPI_BYTE, dest, tag, comm);
}

// --- rank 0 ---
std::vector<Bytes> serve(MPI_Comm comm, int size, std::size_t items, const std::function<Bytes(std::size_t)>& compute,
                         const SweepHooks& hooks) {
  std::vector<Bytes> rows(items);
  std::mutex m;
  std::size_t next = 0;       // the next item to hand out
  std::size_t gathered = 0;   // rows in
  std::vector<std::size_t> local_done;  // items rank 0 computed, not yet counted
  bool stopping = false;      // a failure: hand out no more work
  std::optional<RankFailed> failure;
  auto take = [&]() -> std::size_t {
    std::lock_guard<std::mutex> lock(m);
    if (stopping || next >= items) return kNone;
    return next++;
  };
  auto fail = [&](int rank, const std::string& what) {
    std::lock_guard<std::mutex> lock(m);
    if (!failure) failure.emplace(rank, what);
    stopping = true;
  };
  bool local_finished = false;
  auto local = [&] {
    for (std::size_t i = take(); i != kNone; i = take()) {
      try {
        Bytes row = compute(i);
        std::lock_guard<std::mutex> lock(m);
        rows[i] = std::move(row);
        local_done.push_back(i);
      } catch (...) {
        fail(0, what_of(std::current_exception()));
        break;
      }
    }
    std::lock_guard<std::mutex> lock(m);
    local_finished = true;
  };
  if (size == 1) {  // nothing to serve: compute here
    local();
    if (failure) throw *failure;
    if (hooks.progress) hooks.progress(items);
    return rows;
  }

  std::thread worker(local);
  int serving = size - 1;  // workers not yet told to stop
  auto dispatch = [&](int dest) {
    const std::size_t i = take();
    if (i == kNone) {
      MPI_Send(nullptr, 0, MPI_BYTE, dest, kStop, comm);
      --serving;
    } else {
      send_index(comm, dest, kWork, i);
    }
  };
  Bytes buffer;
  for (;;) {
    bool idle = true;
    {
      std::lock_guard<std::mutex> lock(m);
      gathered += local_done.size();
      if (!local_done.empty() && hooks.progress) hooks.progress(gathered);
      idle = local_done.empty();
      local_done.clear();
      if (serving == 0 && local_finished) break;
    }
    int flag = 0;
    MPI_Status st;
    if (serving > 0) MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm, &flag, &st);
    if (!flag) {
      if (idle) std::this_thread::sleep_for(kServePoll);
      continue;
    }
    int count = 0;
    MPI_Get_count(&st, MPI_BYTE, &count);
    buffer.resize(static_cast<std::size_t>(count));
    MPI_Recv(buffer.data(), count, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, comm, MPI_STATUS_IGNORE);
    if (st.MPI_TAG == kResult) {
      std::uint64_t i = 0;
      if (count < 8) {
        fail(st.MPI_SOURCE, "malformed result message");
      } else {
        std::memcpy(&i, buffer.data(), 8);
        if (i >= items) {
          fail(st.MPI_SOURCE, "result for item " + std::to_string(i) + " of " + std::to_string(items));
        } else {
          std::lock_guard<std::mutex> lock(m);
          rows[i].assign(buffer.begin() + 8, buffer.end());
          ++gathered;
          if (hooks.progress) hooks.progress(gathered);
        }
      }
    } else if (st.MPI_TAG == kError) {
      fail(st.MPI_SOURCE, std::string(buffer.begin(), buffer.end()));
    } else if (st.MPI_TAG != kReady) {
      fail(st.MPI_SOURCE, "unexpected message tag " + std::to_string(st.MPI_TAG));
    }
    dispatch(st.MPI_SOURCE);  // the next item, or stop (after a failure: stop)
  }
  worker.join();
  if (failure) throw *failure;
  if (gathered != items)  // every worker is stopped only in answer to its last message: cannot happen
    throw RankFailed(0, "gathered " + std::to_string(gathered) + " of " + std::to_string(items) + " items");
  return rows;
}

// --- ranks >= 1 ---
void work(MPI_Comm comm, int rank, const std::function<Bytes(std::size_t)>& compute, const SweepHooks& hooks) {
  MPI_Send(nullptr, 0, MPI_BYTE, 0, kReady, comm);
  long done = 0;
  bool failed = false;
  for (;;) {
    MPI_Status st;
    std::uint64_t i = 0;
    MPI_Recv(&i, 8, MPI_BYTE, 0, MPI_ANY_TAG, comm, &st);
    if (st.MPI_TAG == kStop) break;
    if (failed) continue;  // (not reached: rank 0 answers an error with stop)
    Bytes message(8);
    std::memcpy(message.data(), &i, 8);
    try {
      if (rank == hooks.fail_rank && hooks.throw_after_items >= 0 && done >= hooks.throw_after_items)
        throw std::runtime_error("CHATTER_MPI_THROW_AFTER_ITEMS=" + std::to_string(hooks.throw_after_items) +
                                 ": test hook: throwing at item " + std::to_string(i));
      const Bytes row = compute(static_cast<std::size_t>(i));
      message.insert(message.end(), row.begin(), row.end());
    } catch (...) {
      const std::string what = what_of(std::current_exception());
      MPI_Send(what.data(), static_cast<int>(what.size()), MPI_BYTE, 0, kError, comm);
      failed = true;
      continue;
    }
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, kResult, comm);
    ++done;
    if (rank == hooks.fail_rank && hooks.exit_after_items >= 0 && done >= hooks.exit_after_items) {
      std::cerr << "chatter-mpi: rank " << rank << ": CHATTER_MPI_FAIL_AFTER_ITEMS=" << hooks.exit_after_items
                << ": test hook: exiting with status 3 after " << done << " item(s)" << std::endl;
      _exit(3);
    }
  }
}

}  // namespace

std::vector<Bytes> run_sweep_bytes(MPI_Comm comm, std::size_t items, const std::function<Bytes(std::size_t)>& compute,
                                   const SweepHooks& hooks) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (rank == 0) return serve(comm, size, items, compute, hooks);
  work(comm, rank, compute, hooks);
  return {};
}

namespace {
constexpr std::size_t kLimitBytes = 3 * sizeof(double) + 2 * sizeof(std::int32_t);
}

Bytes encode_limits(const std::vector<StabilityLimit>& row) {
  Bytes out(row.size() * kLimitBytes);
  unsigned char* p = out.data();
  for (const StabilityLimit& l : row) {
    const double d[3] = {l.spindle_rpm, l.depth_limit_m, l.chatter_frequency_hz};
    const std::int32_t n[2] = {l.lobe, l.branch};
    std::memcpy(p, d, sizeof d);
    std::memcpy(p + sizeof d, n, sizeof n);
    p += kLimitBytes;
  }
  return out;
}

std::vector<StabilityLimit> decode_limits(const Bytes& bytes) {
  if (bytes.size() % kLimitBytes != 0)
    throw std::runtime_error("a row of " + std::to_string(bytes.size()) + " bytes is not whole stability limits");
  std::vector<StabilityLimit> row(bytes.size() / kLimitBytes);
  const unsigned char* p = bytes.data();
  for (StabilityLimit& l : row) {
    double d[3];
    std::int32_t n[2];
    std::memcpy(d, p, sizeof d);
    std::memcpy(n, p + sizeof d, sizeof n);
    l.spindle_rpm = d[0];
    l.depth_limit_m = d[1];
    l.chatter_frequency_hz = d[2];
    l.lobe = n[0];
    l.branch = n[1];
    p += kLimitBytes;
  }
  return row;
}

std::vector<std::vector<StabilityLimit>> run_sweep(MPI_Comm comm, std::size_t items,
                                                   const std::function<std::vector<StabilityLimit>(std::size_t)>& compute,
                                                   const SweepHooks& hooks) {
  const std::vector<Bytes> bytes =
      run_sweep_bytes(comm, items, [&](std::size_t i) { return encode_limits(compute(i)); }, hooks);
  std::vector<std::vector<StabilityLimit>> rows;
  rows.reserve(bytes.size());
  for (const Bytes& b : bytes) rows.push_back(decode_limits(b));
  return rows;
}

}  // namespace chatter::mpi
