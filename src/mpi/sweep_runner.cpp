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
// Rank 0's side of the sweep: the rows, the next item to hand out, and the
// first failure; shared by the local worker thread and the serving loop.
class Served {
 public:
  Served(std::size_t items, const SweepHooks& hooks) : rows_(items), items_(items), hooks_(hooks) {}

  std::size_t take() {
    std::lock_guard<std::mutex> lock(m_);
    if (stopping_ || next_ >= items_) return kNone;
    return next_++;
  }
  void fail(int rank, const std::string& what) {
    std::lock_guard<std::mutex> lock(m_);
    if (!failure_) failure_.emplace(rank, what);
    stopping_ = true;
  }
  // Rank 0's own share: items until none is left or one fails.
  void local(const std::function<Bytes(std::size_t)>& compute) {
    for (std::size_t i = take(); i != kNone; i = take()) {
      try {
        Bytes row = compute(i);
        std::lock_guard<std::mutex> lock(m_);
        rows_[i] = std::move(row);
        local_done_.push_back(i);
      } catch (...) {
        fail(0, what_of(std::current_exception()));
        break;
      }
    }
    std::lock_guard<std::mutex> lock(m_);
    local_finished_ = true;
  }
  // Counts the rows rank 0 computed since the last call; `idle` when none.
  // True when nothing is left to wait for (no worker served, rank 0 done).
  bool tally_local(int serving, bool& idle) {
    std::lock_guard<std::mutex> lock(m_);
    gathered_ += local_done_.size();
    if (!local_done_.empty() && hooks_.progress) hooks_.progress(gathered_);
    idle = local_done_.empty();
    local_done_.clear();
    return serving == 0 && local_finished_;
  }
  // A message from a worker: a result (item index, then the row), an error,
  // or "ready".
  void receive(int source, int tag, const Bytes& buffer) {
    if (tag == kResult) {
      std::uint64_t i = 0;
      if (buffer.size() < 8) return fail(source, "malformed result message");
      std::memcpy(&i, buffer.data(), 8);
      if (i >= items_) return fail(source, "result for item " + std::to_string(i) + " of " + std::to_string(items_));
      std::lock_guard<std::mutex> lock(m_);
      rows_[i].assign(buffer.begin() + 8, buffer.end());
      ++gathered_;
      if (hooks_.progress) hooks_.progress(gathered_);
    } else if (tag == kError) {
      fail(source, std::string(buffer.begin(), buffer.end()));
    } else if (tag != kReady) {
      fail(source, "unexpected message tag " + std::to_string(tag));
    }
  }
  void throw_if_failed() const {
    if (failure_) throw *failure_;
  }
  // The rows, or the first failure thrown.
  std::vector<Bytes> finish() {
    throw_if_failed();
    if (gathered_ != items_)  // every worker is stopped only in answer to its last message: cannot happen
      throw RankFailed(0, "gathered " + std::to_string(gathered_) + " of " + std::to_string(items_) + " items");
    return std::move(rows_);
  }

 private:
  std::vector<Bytes> rows_;
  std::size_t items_;
  const SweepHooks& hooks_;
  std::mutex m_;
  std::size_t next_ = 0;                 // the next item to hand out
  std::size_t gathered_ = 0;             // rows in
  std::vector<std::size_t> local_done_;  // items rank 0 computed, not yet counted
  bool stopping_ = false;                // a failure: hand out no more work
  bool local_finished_ = false;
  std::optional<RankFailed> failure_;
};

std::vector<Bytes> serve(MPI_Comm comm, int size, std::size_t items, const std::function<Bytes(std::size_t)>& compute,
                         const SweepHooks& hooks) {
  Served served(items, hooks);
  if (size == 1) {  // nothing to serve: compute here
    served.local(compute);
    served.throw_if_failed();
    bool idle = true;
    served.tally_local(0, idle);
    return served.finish();
  }

  std::thread worker([&] { served.local(compute); });
  int serving = size - 1;  // workers not yet told to stop
  auto dispatch = [&](int dest) {
    const std::size_t i = served.take();
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
    if (served.tally_local(serving, idle)) break;
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
    served.receive(st.MPI_SOURCE, st.MPI_TAG, buffer);
    dispatch(st.MPI_SOURCE);  // the next item, or stop (after a failure: stop)
  }
  worker.join();
  return served.finish();
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
