// The static cutting load (include/chatter/cutting_force.hpp): the cutting
// law's peak force and mean torque and power (include/chatter/cutting_law.hpp).
#include "chatter/cutting_force.hpp"

#include <cmath>
#include <string>

#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"

namespace chatter {

CuttingLoad cutting_load(const Process& process, double rpm, double depth_m, double feed_m, double diameter_m,
                         double kc) {
  const std::string where = "cutting_load: ";
  if (!(std::isfinite(diameter_m) && diameter_m > 0.0)) throw InputError(where + "diameter must be > 0");
  if (process.operation() == Operation::kTurning && !process.has_size_effect() && !(std::isfinite(kc) && kc > 0.0))
    throw InputError(where + "turning needs the tangential coefficient K_c > 0");
  CuttingLawOptions o;  // K_c beside Kienzle's law: refused by CuttingLaw::of
  if (process.operation() == Operation::kTurning && kc > 0.0) o.turning_tangential_coefficient_n_per_m2 = kc;
  const auto law = CuttingLaw::of(process, o);
  const CutPoint p{rpm, depth_m, feed_m, diameter_m};
  const MeanCut mean = law->mean(p);
  return {law->peak_force_n(p), mean.torque_n_m, mean.power_w};
}

}  // namespace chatter
