// unusual(): the one text of a value outside its usual band
// (chatter/usual_bands.hpp).
#include "chatter/usual_bands.hpp"

#include <cmath>
#include <sstream>
#include <utility>

namespace chatter {

namespace {
std::string number_text(double x) {
  std::ostringstream os;
  os.precision(4);
  os << x;
  return os.str();
}
}  // namespace

std::string unusual(std::string_view name, double v, const Usual& u) {
  if (u.contains(v) || !std::isfinite(v)) return "";
  std::string what = std::string("outside ") + u.what;
  for (const auto& [factor, unit] : {std::pair{u.mixup_factor, u.mixup_unit}, std::pair{u.other_factor, u.other_unit}}) {
    const double meant = v * factor;
    if (factor > 0.0 && u.contains(meant)) {
      what += "; is it in " + std::string(unit) + " (" + std::string(name) + " = " + number_text(meant) + ")?";
      break;
    }
  }
  return what;
}

}  // namespace chatter
