// Impacts per wheel turn counted in a normal-force or wheel-speed record
// (include/chatter/grinding_data.hpp; seed 001 §4.7, figures 4-6 and 4-7).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding_data.hpp"
#include "chatter/kinematics.hpp"
#include "grinding_text.hpp"

namespace chatter::grinding {

namespace {

// The automatic threshold: this fraction of the way from the median (the
// no-contact baseline when contact takes less than half of the time) to the
// highest peak. A quarter keeps impacts down to a quarter of the largest and
// stays clear of a noise floor a few percent of it.
constexpr double kAutoFraction = 0.25;

double percentile(std::vector<double> v, double q) {
  const std::size_t k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

ImpactCount count_impacts(const std::vector<double>& time_s, const std::vector<double>& signal, ImpactSignal kind,
                          const ImpactCountOptions& o) {
  if (!(std::isfinite(o.wheel_rpm) && o.wheel_rpm > 0.0))
    throw InputError("wheel_rpm = " + detail::num(o.wheel_rpm) + ": must be > 0 rev/min");
  if (!(std::isfinite(o.threshold) && o.threshold >= 0.0))
    throw InputError("threshold = " + detail::num(o.threshold) + ": must be >= 0 (0: automatic)");
  if (!(o.release_fraction >= 0.0 && o.release_fraction < 1.0))
    throw InputError("release_fraction = " + detail::num(o.release_fraction) + ": must be in [0, 1)");
  const std::size_t n = time_s.size();
  if (n < 3 || signal.size() != n) throw InputError("the record needs at least 3 samples");
  const double turn = revolution_s(o.wheel_rpm);
  const double t0 = time_s.front();
  ImpactCount c;
  c.turns = static_cast<int>(std::floor((time_s.back() - t0) / turn + 1e-9));
  if (c.turns < 2)
    throw InputError("the record spans " + detail::num(time_s.back() - t0) + " s, less than two wheel turns (" +
                     detail::num(2 * turn) + " s at " + detail::num(o.wheel_rpm) + " rev/min)");

  // The signal as "how much impact": the force itself, or the speed's drop
  // below its median (an impact brakes the wheel).
  std::vector<double> s(signal);
  const double med_raw = percentile(signal, 0.5);
  if (kind == ImpactSignal::kWheelSpeed)
    for (double& v : s) v = med_raw - v;
  const double med = percentile(s, 0.5), top = *std::max_element(s.begin(), s.end());
  // A given threshold is in the signal's units: N of force, or rev/min of
  // speed drop below the median.
  c.threshold = o.threshold > 0.0 ? o.threshold : med + kAutoFraction * (top - med);
  if (!(c.threshold > med))
    throw InputError("the signal has no impacts to count: the threshold " + detail::num(c.threshold) +
                     " is not above its median " + detail::num(med) +
                     (o.threshold > 0.0 ? "" : " (a flat record, or contact more than half of the time: give a threshold)"));
  const double release = med + o.release_fraction * (c.threshold - med);

  c.per_turn.assign(static_cast<std::size_t>(c.turns), 0);
  const double t_end = t0 + c.turns * turn;
  bool in = false;
  double peak = 0.0, peak_t = 0.0;
  auto close = [&]() {
    if (peak_t < t_end) {
      const std::size_t k = std::min(static_cast<std::size_t>((peak_t - t0) / turn), c.per_turn.size() - 1);
      ++c.per_turn[k];
      c.peak_value.push_back(peak);
      c.peak_time_s.push_back(peak_t);
    }
    in = false;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const double v = s[i];
    if (!in) {
      if (v > c.threshold) {
        in = true;
        peak = v;
        peak_t = time_s[i];
      }
    } else {
      if (v > peak) {
        peak = v;
        peak_t = time_s[i];
      }
      if (v < release) close();
    }
  }
  if (in) close();
  int most = 0;
  for (int k : c.per_turn) most = std::max(most, k);
  c.histogram.assign(static_cast<std::size_t>(most) + 1, 0);
  long total = 0;
  for (int k : c.per_turn) {
    ++c.histogram[static_cast<std::size_t>(k)];
    total += k;
  }
  c.mean_per_turn = static_cast<double>(total) / c.turns;
  c.turns_without_contact = static_cast<double>(c.histogram[0]) / c.turns;
  return c;
}

}  // namespace chatter::grinding
