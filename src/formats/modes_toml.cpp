// TOML fragment writer for fitted modes (the io side of `chatter fit`).
#include "chatter/io/modes_toml.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"

namespace chatter {

std::string modes_to_toml(const std::vector<Mode>& modes, const std::string& body, const std::string& comment) {
  if (body != "tool" && body != "workpiece")
    throw InputError("modes_to_toml: body = \"" + body + "\": must be \"tool\" or \"workpiece\"");
  std::string s;
  std::istringstream lines(comment);
  for (std::string l; std::getline(lines, l);) s += "# " + l + "\n";
  char buf[64];
  auto g10 = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.10g", v);
    std::string x = buf;
    if (x.find_first_of(".eEn") == std::string::npos) x += ".0";  // keep TOML floats floats
    return x;
  };
  for (const Mode& md : modes) {
    if (!s.empty()) s += "\n";
    s += "[[" + body + ".modes]]\n";
    s += "frequency_hz = " + g10(md.natural_frequency_hz) + "\n";
    s += "damping_ratio = " + g10(md.damping_ratio) + "\n";
    s += "stiffness_n_per_m = " + g10(md.stiffness_n_per_m) + "\n";
    const Eigen::Vector2d& u = md.direction;
    if (u.x() == 1.0 && u.y() == 0.0)
      s += "direction = \"x\"\n";
    else if (u.x() == 0.0 && u.y() == 1.0)
      s += "direction = \"y\"\n";
    else
      s += "direction = [" + g10(u.x()) + ", " + g10(u.y()) + "]\n";
  }
  return s;
}

std::string commented_uncertainty_toml(const std::vector<UncertaintyKey>& keys, const std::string& comment) {
  std::string s;
  std::istringstream lines(comment);
  for (std::string l; std::getline(lines, l);) s += "# " + l + "\n";
  s += "#[uncertainty]\n";
  char buf[64];
  for (const UncertaintyKey& k : keys) {
    s += "#" + k.key + " = ";
    const bool list = k.list || k.percent.size() != 1;
    if (list) s += "[";
    for (std::size_t i = 0; i < k.percent.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.4g", k.percent[i]);
      std::string x = buf;
      if (x.find_first_of(".eEn") == std::string::npos) x += ".0";  // keep TOML floats floats
      s += (i ? ", " : "") + x;
    }
    s += list ? "]\n" : "\n";
  }
  return s;
}

double allowed_spread_percent(double percent, double damping_ratio) {
  // Just inside [uncertainty]'s rules (config_uncertainty.cpp): 3 s < 1, ζ (1 + 3 s) < 1,
  // with room for the 4 significant digits the table is written with.
  double cap = 33.3;
  if (damping_ratio > 0.0) cap = std::min(cap, 0.999 * 100.0 * (1.0 / damping_ratio - 1.0) / 3.0);
  return std::min(percent, cap);
}

}  // namespace chatter
