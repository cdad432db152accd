// The one definition of the reported quantities (chatter/report.hpp).
#include "chatter/report.hpp"

#include <cmath>

namespace chatter {

int lobe_number(double chatter_frequency_hz, double tooth_passing_hz) {
  if (!(std::isfinite(chatter_frequency_hz) && chatter_frequency_hz >= 0.0 && tooth_passing_hz > 0.0)) return -1;
  const double x = chatter_frequency_hz / tooth_passing_hz;
  if (!(x < 1e9)) return -1;
  const double k = std::round(x);
  if (std::abs(x - k) <= 1e-9 * std::max(1.0, x)) return static_cast<int>(k);
  return static_cast<int>(std::floor(x));
}

}  // namespace chatter
