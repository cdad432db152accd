#include <cmath>
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

std::vector<StabilityLimit> lobe_envelope(const LobeSolver& solver, const std::vector<double>& speeds_rpm) {
  std::vector<StabilityLimit> rows;
  rows.reserve(speeds_rpm.size());
  for (double rpm : speeds_rpm) rows.push_back(solver.limit_at(rpm));
  return rows;
}

}  // namespace chatter
