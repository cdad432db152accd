#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>
#include <sstream>

#include "chatter/error.hpp"
#include "chatter/lobes.hpp"

namespace chatter {

std::vector<double> evenly_spaced_speeds(double rpm_min, double rpm_max, int count) {
  std::ostringstream os;
  if (!(std::isfinite(rpm_min) && rpm_min > 0.0))
    os << "rpm_min = " << rpm_min << ": must be > 0 rev/min";
  else if (!(std::isfinite(rpm_max) && rpm_max >= rpm_min))
    os << "rpm_max = " << rpm_max << ": must be >= rpm_min (" << rpm_min << ")";
  else if (count < 1)
    os << "rpm_points = " << count << ": must be >= 1";
  else if (count == 1 && rpm_max != rpm_min)
    os << "rpm_points = 1: needs rpm_min == rpm_max";
  else if (count > 1 && rpm_max == rpm_min)
    os << "rpm_max = rpm_min = " << rpm_min << ": empty range for " << count << " points";
  if (!os.str().empty()) throw InputError(os.str());
  std::vector<double> v(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
    v[static_cast<std::size_t>(i)] =
        count == 1 ? rpm_min : rpm_min + (rpm_max - rpm_min) * static_cast<double>(i) / (count - 1);
  if (count > 1) v.back() = rpm_max;  // exactly, whatever the rounding
  return v;
}

void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& f,
                  const std::function<void(std::size_t done)>& per_item) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(n, 1)));
  std::atomic<std::size_t> next{0}, done{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        f(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;  // stop handing out work
        return;
      }
      const std::size_t d = ++done;
      if (per_item) per_item(d);
    }
  };
  if (threads <= 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads);
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
  }
  if (error) std::rethrow_exception(error);
}

std::vector<StabilityLimit> lobe_envelope(const LobeSolver& solver, const std::vector<double>& speeds_rpm,
                                          unsigned threads, const std::function<void(std::size_t done)>& per_speed) {
  std::vector<StabilityLimit> rows(speeds_rpm.size());
  parallel_for(
      speeds_rpm.size(), threads, [&](std::size_t i) { rows[i] = solver.limit_at(speeds_rpm[i]); }, per_speed);
  return rows;
}

}  // namespace chatter
