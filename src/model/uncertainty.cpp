// Uncertain inputs: spreads, counter-based draws, samples, quantiles and the
// reduction to probabilities (include/chatter/uncertainty.hpp,
// docs/uncertainty.md).
#include "chatter/uncertainty.hpp"

#include <algorithm>
#include <boost/math/special_functions/erf.hpp>
#include <cmath>
#include <string>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"

namespace chatter {
namespace {

// The SplitMix64 step: add the golden-ratio increment, then the finaliser
// (Steele, Lea & Flood 2014). A bijection of 64-bit words with full
// avalanche: neighbouring counters give unrelated outputs.
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// Parameter numbers of the stream (the header's table).
constexpr std::uint64_t kParamTangential = 0, kParamRadial = 1, kParamFirstMode = 2;

std::string number(double x) { return number_text(x, 10); }

double of(const std::vector<double>& list, std::size_t m) {
  if (list.empty()) return 0.0;
  return list.size() == 1 ? list.front() : list[m];
}

// Each mode, tool modes first, then workpiece modes.
std::vector<const Mode*> modes_of(const StructuralModel& m) {
  std::vector<const Mode*> out;
  for (const Mode& md : m.tool.modes) out.push_back(&md);
  for (const Mode& md : m.workpiece.modes) out.push_back(&md);
  return out;
}

}  // namespace

double UncertaintySpreads::frequency_of(std::size_t m) const { return of(frequency, m); }
double UncertaintySpreads::damping_of(std::size_t m) const { return of(damping, m); }
double UncertaintySpreads::stiffness_of(std::size_t m) const { return of(stiffness, m); }

bool UncertaintySpreads::zero() const {
  auto all_zero = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double s) { return s == 0.0; });
  };
  return all_zero(frequency) && all_zero(damping) && all_zero(stiffness) && tangential == 0.0 && radial == 0.0;
}

std::string UncertaintySpreads::validate(const StructuralModel& model, const Process& process) const {
  const double limit = 1.0 / kUncertaintyTruncationSigma;
  auto one = [&](const std::string& name, double s) -> std::string {
    if (!std::isfinite(s) || s < 0.0) return name + " = " + number(s) + ": must be a finite spread >= 0";
    if (!(s < limit))
      return name + " = " + number(s) + ": must be < 1/3 (a 3-sigma draw p (1 - 3 s) would reach <= 0)";
    return "";
  };
  const std::vector<const Mode*> modes = modes_of(model);
  const struct {
    const char* name;
    const std::vector<double>* list;
  } lists[] = {{"frequency", &frequency}, {"damping", &damping}, {"stiffness", &stiffness}};
  for (const auto& l : lists) {
    if (l.list->size() > 1 && l.list->size() != modes.size())
      return std::string(l.name) + ": " + std::to_string(l.list->size()) +
             " values: give one for every mode or one per mode (" + std::to_string(modes.size()) +
             ": tool modes, then workpiece modes)";
    for (std::size_t i = 0; i < l.list->size(); ++i) {
      const std::string name = l.list->size() == 1 ? std::string(l.name) : std::string(l.name) + "[" + std::to_string(i) + "]";
      if (std::string why = one(name, (*l.list)[i]); !why.empty()) return why;
    }
  }
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const double s = damping_of(m), zeta = modes[m]->damping_ratio;
    if (zeta * (1.0 + kUncertaintyTruncationSigma * s) >= 1.0) {
      const std::string name = damping.size() == 1 ? "damping" : "damping[" + std::to_string(m) + "]";
      return name + " = " + number(s) + ": with damping_ratio " + number(zeta) + " (mode " + std::to_string(m) +
             ") a 3-sigma draw reaches " + number(zeta * (1.0 + kUncertaintyTruncationSigma * s)) +
             ": must be < " + number((1.0 / zeta - 1.0) / kUncertaintyTruncationSigma) +
             " (a damping ratio stays < 1)";
    }
  }
  if (std::string why = one("tangential", tangential); !why.empty()) return why;
  if (std::string why = one("radial", radial); !why.empty()) return why;
  if (radial > 0.0 && process.operation() != Operation::kMilling)
    return "radial = " + number(radial) + ": only for milling (turning has one coefficient, K_f: use tangential)";
  return "";
}

double uncertainty_normal(std::uint64_t seed, std::uint64_t sample, std::uint64_t parameter) {
  const std::uint64_t h = splitmix64(splitmix64(splitmix64(seed) ^ sample) ^ parameter);
  // The top 53 bits, centred in their cell: u in (0, 1), never 0 or 1.
  const double u = (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
  // Φ(±3) and the inverse of Φ through erf: Φ(x) = (1 + erf(x/√2)) / 2.
  const double c = kUncertaintyTruncationSigma / std::sqrt(2.0);
  const double lo = 0.5 * boost::math::erfc(c), width = boost::math::erf(c);  // Φ(−3), Φ(3) − Φ(−3)
  const double p = lo + u * width;
  const double z = std::sqrt(2.0) * boost::math::erf_inv(2.0 * p - 1.0);
  return std::clamp(z, -kUncertaintyTruncationSigma, kUncertaintyTruncationSigma);
}

UncertainSample sample_inputs(const StructuralModel& model, const Process& process, const UncertaintySpreads& spreads,
                              std::uint64_t seed, std::uint64_t sample) {
  if (const std::string why = spreads.validate(model, process); !why.empty())
    throw InputError("uncertainty spreads: " + why);
  auto scale = [&](double value, double s, std::uint64_t parameter) {
    if (s == 0.0) return value;  // the nominal bit for bit
    return value * (1.0 + s * uncertainty_normal(seed, sample, parameter));
  };
  UncertainSample out{model, process};
  std::size_t m = 0;
  for (Body* body : {&out.model.tool, &out.model.workpiece})
    for (Mode& md : body->modes) {
      const std::uint64_t base = kParamFirstMode + 3 * m;
      md.natural_frequency_hz = scale(md.natural_frequency_hz, spreads.frequency_of(m), base);
      md.damping_ratio = scale(md.damping_ratio, spreads.damping_of(m), base + 1);
      md.stiffness_n_per_m = scale(md.stiffness_n_per_m, spreads.stiffness_of(m), base + 2);
      ++m;
    }
  if (spreads.tangential == 0.0 && spreads.radial == 0.0) return out;
  if (process.operation() == Operation::kMilling) {
    MillingParameters p = process.milling_parameters();
    p.tangential_coefficient_n_per_m2 = scale(p.tangential_coefficient_n_per_m2, spreads.tangential, kParamTangential);
    p.radial_coefficient_n_per_m2 = scale(p.radial_coefficient_n_per_m2, spreads.radial, kParamRadial);
    out.process = Process::milling(p);
    out.process.set_speed_variation(process.speed_variation());
  } else {
    TurningParameters p = process.turning_parameters();
    p.feed_force_coefficient_n_per_m2 = scale(p.feed_force_coefficient_n_per_m2, spreads.tangential, kParamTangential);
    out.process = Process::turning(p);
    out.process.set_speed_variation(process.speed_variation());
  }
  return out;
}

double quantile_type7(std::vector<double> values, double q) {
  if (values.empty()) throw InputError("quantile: no values");
  if (!(q >= 0.0 && q <= 1.0)) throw InputError("quantile level = " + number(q) + ": must be in [0, 1]");
  std::sort(values.begin(), values.end());  // +inf last
  const double h = static_cast<double>(values.size() - 1) * q;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const double frac = h - static_cast<double>(lo);
  if (frac == 0.0 || lo + 1 >= values.size()) return values[lo];
  const double a = values[lo], b = values[lo + 1];
  if (a == b) return a;
  if (std::isinf(b)) return b;  // a finite, b = +inf: the interpolation is +inf
  return a + frac * (b - a);
}

UncertainLobes reduce_monte_carlo(const std::vector<std::vector<StabilityLimit>>& rows,
                                  const std::vector<double>& depths_m, const std::vector<double>& levels) {
  if (rows.empty()) throw InputError("Monte Carlo reduction: no samples");
  const std::size_t n_speeds = rows.front().size();
  for (std::size_t i = 1; i < rows.size(); ++i)
    if (rows[i].size() != n_speeds)
      throw InputError("Monte Carlo reduction: sample " + std::to_string(i) + " has " +
                       std::to_string(rows[i].size()) + " speeds, sample 0 has " + std::to_string(n_speeds));
  for (const double q : levels)
    if (!(q >= 0.0 && q <= 1.0)) throw InputError("quantile level = " + number(q) + ": must be in [0, 1]");
  UncertainLobes r;
  r.depths_m = depths_m;
  r.levels = levels;
  const double n = static_cast<double>(rows.size());
  r.quantile_depth_m.assign(levels.size(), std::vector<double>(n_speeds));
  std::vector<double> limits(rows.size());
  for (std::size_t s = 0; s < n_speeds; ++s) {
    r.speeds_rpm.push_back(rows.front()[s].spindle_rpm);
    for (std::size_t i = 0; i < rows.size(); ++i) limits[i] = rows[i][s].depth_limit_m;
    std::sort(limits.begin(), limits.end());
    std::vector<double> p(depths_m.size());
    for (std::size_t d = 0; d < depths_m.size(); ++d) {
      // Stable: depth < limit (the limit itself is the boundary).
      const auto first_above = std::upper_bound(limits.begin(), limits.end(), depths_m[d]);
      p[d] = static_cast<double>(limits.end() - first_above) / n;
    }
    r.probability_stable.push_back(std::move(p));
    for (std::size_t l = 0; l < levels.size(); ++l) r.quantile_depth_m[l][s] = quantile_type7(limits, levels[l]);
  }
  return r;
}

std::string quantile_column_name(double level) {
  const int pct = static_cast<int>(std::lround(100.0 * level));
  return std::string("depth_limit_p") + (pct < 10 ? "0" : "") + std::to_string(pct) + "_mm";
}

ProbabilityDepthGrid probability_depth_grid(const std::vector<std::vector<StabilityLimit>>& rows, double depth_max_mm,
                                            int points, std::optional<double> top_mm) {
  // Without a given top the grid ends at this factor times the deepest finite
  // limit, so that it resolves the lobes rather than the searched depth.
  constexpr double kGridTopFactor = 1.2;
  if (points < 2) throw InputError("probability grid: " + std::to_string(points) + " depths: must be >= 2");
  ProbabilityDepthGrid g;
  if (top_mm) {
    g.top_mm = *top_mm;
  } else {
    double deepest = 0.0;
    for (const auto& row : rows)
      for (const auto& r : row)
        if (r.bounded()) deepest = std::max(deepest, r.depth_limit_m * 1e3);
    if (deepest > 0.0) {
      // Rounded up to two significant digits, so the depths are round numbers.
      const double unit = std::pow(10.0, std::floor(std::log10(kGridTopFactor * deepest)) - 1.0);
      g.top_mm = std::min(depth_max_mm, std::ceil(kGridTopFactor * deepest / unit) * unit);
    } else {
      g.top_mm = depth_max_mm;
    }
  }
  if (!(std::isfinite(g.top_mm) && g.top_mm > 0.0))
    throw InputError("probability grid: top depth = " + number(g.top_mm) + " mm: must be finite and > 0");
  g.depths_m.resize(static_cast<std::size_t>(points));
  for (int d = 0; d < points; ++d) g.depths_m[static_cast<std::size_t>(d)] = g.top_mm * 1e-3 * d / (points - 1);
  g.depths_m.back() = g.top_mm * 1e-3;
  return g;
}

}  // namespace chatter
