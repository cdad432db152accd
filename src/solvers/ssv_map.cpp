// The spectral radius over (R_VA, R_VF) at one speed and depth
// (chatter/ssv_map.hpp, docs/ssv.md).
#include "chatter/ssv_map.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <string>
#include <thread>

#include "chatter/error.hpp"
#include "chatter/report.hpp"
#include "chatter/kinematics.hpp"

namespace chatter {

SsvMapGrid ssv_stability_map(const StructuralModel& model, const Process& process, double rpm, double depth_m,
                             const std::vector<double>& amplitudes, const std::vector<double>& frequencies,
                             const SemiDiscretizationOptions& options, unsigned threads,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
  check_spindle_rpm(rpm, "spindle speed");
  if (!(std::isfinite(depth_m) && depth_m > 0.0)) throw InputError("depth of cut: must be > 0 m");
  if (amplitudes.empty() || frequencies.empty())
    throw InputError("speed variation map: needs at least one amplitude ratio and one frequency ratio");
  for (double a : amplitudes)
    for (double f : frequencies)
      if (const std::string e = SpeedVariation{a, f}.validate(); !e.empty()) throw InputError("speed variation map: " + e);
  SsvMapGrid g;
  g.spindle_rpm = rpm;
  g.depth_m = depth_m;
  g.amplitude_ratios = amplitudes;
  g.frequency_ratios = frequencies;
  const std::size_t n = amplitudes.size() * frequencies.size();
  g.rho_per_revolution.assign(n, 0.0);
  g.frequency_ratio_used.assign(n, 0.0);
  g.exact.assign(n, 1);
  const double rev = revolution_s(rpm);
  const Process steady = process.at_constant_speed();
  auto point = [&](std::size_t k) {
    const double a = amplitudes[k / frequencies.size()], f = frequencies[k % frequencies.size()];
    Process p = steady;
    p.set_speed_variation({a, f});
    const SemiDiscretizationSolver sdm(model, p, options);
    const FloquetResult r = sdm.analyse(rpm, depth_m);
    g.rho_per_revolution[k] = std::pow(r.spectral_radius, rev / r.period_s);
    if (p.has_speed_variation()) {
      const SpeedVariationPeriod per = speed_variation_period(p, rpm);
      g.frequency_ratio_used[k] = per.frequency_ratio_used;
      g.exact[k] = per.exact ? 1 : 0;
    } else {
      g.frequency_ratio_used[k] = f;
    }
  };
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, n));
  std::atomic<std::size_t> next{0}, done{0};
  std::exception_ptr failure;
  std::mutex m;
  auto work = [&] {
    for (std::size_t k; (k = next++) < n;) {
      try {
        point(k);
      } catch (...) {
        std::lock_guard<std::mutex> lock(m);
        if (!failure) failure = std::current_exception();
        next = n;
      }
      const std::size_t d = ++done;
      if (progress && d % frequencies.size() == 0) {
        std::lock_guard<std::mutex> lock(m);
        progress(d, n);
      }
    }
  };
  if (threads <= 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);
    for (auto& t : pool) t.join();
  }
  if (failure) std::rethrow_exception(failure);
  return g;
}

}  // namespace chatter
