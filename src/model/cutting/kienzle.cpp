// Kienzle's law (include/chatter/kienzle.hpp): the secant and tangent specific
// forces of one direction and the law's rules.
#include "chatter/kienzle.hpp"
#include "chatter/number_text.hpp"

#include <cmath>

namespace chatter {

namespace {
constexpr double kReferenceChipM = 1e-3;  // k_1.1 is the specific force at h = 1 mm

}  // namespace

double KienzleTerm::secant_n_per_m2(double chip_m) const {
  return specific_force_n_per_m2 * std::pow(chip_m / kReferenceChipM, -exponent);
}

double KienzleTerm::tangent_n_per_m2(double chip_m) const { return (1.0 - exponent) * secant_n_per_m2(chip_m); }

double KienzleTerm::force_per_width_n_per_m(double chip_m) const {
  if (!(chip_m > 0.0)) return 0.0;
  return specific_force_n_per_m2 * kReferenceChipM * std::pow(chip_m / kReferenceChipM, 1.0 - exponent);
}

std::string KienzleLaw::validate() const {
  const std::pair<const KienzleTerm*, const char*> terms[] = {{&tangential, "tangential"}, {&feed, "feed"},
                                                             {&radial, "radial"}};
  for (const auto& [t, name] : terms) {
    const double k = t->specific_force_n_per_m2, m = t->exponent;
    if (!(std::isfinite(k) && k >= 0.0))
      return std::string("kienzle: ") + name + " k_1.1 = " + number_text(k * 1e-6) + " N/mm^2: must be >= 0 (0 = not given)";
    if (!(std::isfinite(m) && m >= 0.0 && m < 1.0))
      return std::string("kienzle: ") + name + " exponent m = " + number_text(m) +
             ": must be in [0, 1) (0 = the linear law; at 1 the force would not grow with the chip)";
  }
  if (!(tangential.specific_force_n_per_m2 > 0.0))
    return "kienzle: the tangential k_c1.1 must be > 0 (the cutting force: torque, power and the chip's own law)";
  if (!(feed.specific_force_n_per_m2 > 0.0))
    return "kienzle: the feed direction's k_1.1 must be > 0 (it is the force the structure in the X-Y plane feels)";
  if (!(std::isfinite(feed_m) && feed_m > 0.0))
    return "kienzle: the feed per revolution (" + number_text(feed_m * 1e3) +
           " mm) must be > 0: the regenerative side is linearised at its mean chip";
  return "";
}

}  // namespace chatter
