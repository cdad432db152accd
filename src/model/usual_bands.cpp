// unusual(): the one text of a value outside its usual band
// (chatter/usual_bands.hpp).
#include "chatter/usual_bands.hpp"
#include "chatter/number_text.hpp"

#include <cmath>
#include <utility>

namespace chatter {

namespace {
}  // namespace

std::string unusual(std::string_view name, double v, const Usual& u) {
  if (u.contains(v) || !std::isfinite(v)) return "";
  std::string what = std::string("outside ") + u.what;
  for (const auto& [factor, unit] : {std::pair{u.mixup_factor, u.mixup_unit}, std::pair{u.other_factor, u.other_unit}}) {
    const double meant = v * factor;
    if (factor > 0.0 && u.contains(meant)) {
      what += "; is it in " + std::string(unit) + " (" + std::string(name) + " = " + number_text(meant, 4) + ")?";
      break;
    }
  }
  return what;
}

std::vector<std::string> unusual_arguments(const std::vector<std::pair<std::string, double>>& arguments) {
  std::vector<std::string> out;
  for (const auto& [name, value] : arguments) {
    std::string flag = name.substr(name.find_first_not_of('-'));
    for (char& c : flag)
      if (c == '_') c = '-';
    for (const FlagBand& f : kFlagBands) {
      if (flag != f.flag || value == 0.0) continue;
      if (const std::string what = unusual(name, value, *f.band); !what.empty())
        out.push_back(name + " = " + number_text(value, 10) + ": " + what);  // the value as typed
    }
  }
  return out;
}

}  // namespace chatter
