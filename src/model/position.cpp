// Position-dependent structure: cantilever mode shape, interpolation between
// stations (include/chatter/position.hpp, docs/position.md).
#include "chatter/position.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"

namespace chatter {
namespace {

// Un-normalised shape. cosh x − cos x = 2 (sinh²(x/2) + sin²(x/2)) avoids the
// cancellation of the difference near the clamp; sinh x − sin x ≈ x³/3 there
// and is smaller by a factor x, so its cancellation (absolute error ~1e-16)
// stays below the first term's rounding for every x the range allows.
double raw_shape(double xi) {
  const double x = kCantileverBeta * xi;
  const double sh = std::sinh(0.5 * x), s = std::sin(0.5 * x);
  const double cosh_minus_cos = 2.0 * (sh * sh + s * s);
  return cosh_minus_cos - kCantileverSigma * (std::sinh(x) - std::sin(x));
}

// Directions of the same mode at two stations are the same when their unit
// vectors differ by less than this (the config normalises them; two spellings
// of one direction, "x" and [1, 0], agree to rounding).
constexpr double kDirectionTol = 1e-9;

std::string number(double x) { return number_text(x, 10); }

// Fritsch–Carlson monotone cubic Hermite slopes (harmonic-mean interior
// slopes after Fritsch & Butland; the one-sided three-point end slopes,
// limited to keep monotonicity).
std::vector<double> pchip_slopes(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  std::vector<double> h(n - 1), d(n - 1), m(n, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    h[k] = x[k + 1] - x[k];
    d[k] = (y[k + 1] - y[k]) / h[k];
  }
  if (n == 2) {
    m[0] = m[1] = d[0];
    return m;
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    if (d[k - 1] * d[k] <= 0.0) continue;  // a local extremum: flat
    const double w1 = 2.0 * h[k] + h[k - 1], w2 = h[k] + 2.0 * h[k - 1];
    m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k]);
  }
  auto end_slope = [](double h0, double h1, double d0, double d1) {
    double s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
    if (s * d0 <= 0.0) return 0.0;
    if (d0 * d1 <= 0.0 && std::abs(s) > 3.0 * std::abs(d0)) s = 3.0 * d0;
    return s;
  };
  m[0] = end_slope(h[0], h[1], d[0], d[1]);
  m[n - 1] = end_slope(h[n - 2], h[n - 3], d[n - 2], d[n - 3]);
  return m;
}

// The Hermite cubic on [x[k], x[k+1]] at `at`.
double pchip_eval(const std::vector<double>& x, const std::vector<double>& y, std::size_t k, double at) {
  const std::vector<double> m = pchip_slopes(x, y);
  const double h = x[k + 1] - x[k], t = (at - x[k]) / h;
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  return h00 * y[k] + h10 * h * m[k] + h01 * y[k + 1] + h11 * h * m[k + 1];
}

// One parameter of one mode over the stations, interpolated at `at` in
// interval k (log: in its logarithm). Equal at every station: copied.
double interpolate(const std::vector<double>& x, std::vector<double> y, std::size_t k, double at, bool log) {
  if (std::all_of(y.begin(), y.end(), [&](double v) { return v == y.front(); })) return y.front();
  if (log)
    for (double& v : y) v = std::log(v);
  const double v = pchip_eval(x, y, k, at);
  return log ? std::exp(v) : v;
}

Body interpolate_body(const std::vector<PositionStation>& st, bool tool, std::size_t k, double at) {
  const Body& left = tool ? st[k].model.tool : st[k].model.workpiece;
  Body out;
  std::vector<double> x;
  for (const auto& s : st) x.push_back(s.position_m);
  for (std::size_t i = 0; i < left.modes.size(); ++i) {
    std::vector<double> f, z, kk;
    for (const auto& s : st) {
      const Mode& md = (tool ? s.model.tool : s.model.workpiece).modes[i];
      f.push_back(md.natural_frequency_hz);
      z.push_back(md.damping_ratio);
      kk.push_back(md.stiffness_n_per_m);
    }
    Mode md = left.modes[i];
    md.natural_frequency_hz = interpolate(x, f, k, at, true);
    md.damping_ratio = interpolate(x, z, k, at, false);
    md.stiffness_n_per_m = interpolate(x, kk, k, at, true);
    out.modes.push_back(md);
  }
  return out;
}

}  // namespace

double cantilever_mode_shape(double xi) {
  if (!(std::isfinite(xi) && xi >= 0.0 && xi <= 1.0))
    throw InputError("cantilever mode shape: xi = x / L = " + number(xi) + ": must be in [0, 1] (clamp to free end)");
  if (xi == 1.0) return 1.0;
  return raw_shape(xi) / raw_shape(1.0);
}

std::pair<double, double> PositionDependence::range_m() const {
  if (!stations.empty()) return {stations.front().position_m, stations.back().position_m};
  double length = cantilever.empty() ? 0.0 : cantilever.front().length_m;
  return {0.0, length};
}

std::string PositionDependence::validate() const {
  std::ostringstream os;
  if (!cantilever.empty() && !stations.empty())
    return "cantilever modes and stations: give one position-dependent model, not both";
  for (std::size_t i = 0; i < cantilever.size(); ++i) {
    const double len = cantilever[i].length_m;
    if (!(std::isfinite(len) && len > 0.0)) {
      os << "cantilever[" << i << "].length_m = " << len << ": must be > 0";
      return os.str();
    }
    if (len != cantilever.front().length_m) {
      os << "cantilever[" << i << "].length_m = " << len << ": must equal cantilever[0].length_m ("
         << cantilever.front().length_m << "): one part, one length along which the tool moves";
      return os.str();
    }
  }
  if (stations.empty()) return "";
  if (stations.size() < 2) return "stations: give at least 2 (one set does not vary along the path)";
  for (std::size_t s = 0; s < stations.size(); ++s) {
    const PositionStation& st = stations[s];
    if (!(std::isfinite(st.position_m) && st.position_m >= 0.0)) {
      os << "stations[" << s << "].position_m = " << st.position_m << ": must be >= 0";
      return os.str();
    }
    if (st.model.has_measured()) {
      os << "stations[" << s << "]: measured FRF terms are not interpolated; fit modes to them";
      return os.str();
    }
    if (st.model.rigid()) {
      os << "stations[" << s << "]: both bodies are rigid: give at least one mode";
      return os.str();
    }
    if (s == 0) continue;
    const PositionStation& prev = stations[s - 1];
    if (!(st.position_m > prev.position_m)) {
      os << "stations[" << s << "].position_m = " << st.position_m << ": must be > stations[" << s - 1
         << "].position_m (" << prev.position_m << "): sorted along the path, no position twice";
      return os.str();
    }
    for (const bool tool : {true, false}) {
      const Body& a = tool ? prev.model.tool : prev.model.workpiece;
      const Body& b = tool ? st.model.tool : st.model.workpiece;
      const char* name = tool ? "tool" : "workpiece";
      if (a.modes.size() != b.modes.size()) {
        os << "stations[" << s << "]." << name << ".modes: " << b.modes.size() << " modes, stations[" << s - 1
           << "] has " << a.modes.size() << ": neighbouring stations must have the same modes to interpolate";
        return os.str();
      }
      for (std::size_t i = 0; i < a.modes.size(); ++i)
        if ((a.modes[i].direction - b.modes[i].direction).norm() > kDirectionTol) {
          os << "stations[" << s << "]." << name << ".modes[" << i << "].direction: differs from stations[" << s - 1
             << "]: a mode keeps its direction along the path";
          return os.str();
        }
    }
  }
  return "";
}

StructuralModel model_at_position(const StructuralModel& base, const PositionDependence& dep, double position_m) {
  if (const std::string why = dep.validate(); !why.empty()) throw InputError(why);
  if (dep.empty()) return base;
  const auto [lo, hi] = dep.range_m();
  if (!(std::isfinite(position_m) && position_m >= lo && position_m <= hi))
    throw InputError("position_m = " + number(position_m) + ": outside the part [" + number(lo) + ", " + number(hi) +
                     "] m" + (dep.stations.empty() ? " (clamp to free end)" : " (first to last station)"));
  if (!dep.cantilever.empty()) {
    StructuralModel m = base;
    std::vector<bool> drop(m.workpiece.modes.size(), false);
    for (const CantileverModeRef& c : dep.cantilever) {
      if (c.workpiece_mode >= m.workpiece.modes.size())
        throw InputError("cantilever: workpiece mode " + std::to_string(c.workpiece_mode) + " does not exist");
      const double phi = cantilever_mode_shape(position_m == c.length_m ? 1.0 : position_m / c.length_m);
      const double k = m.workpiece.modes[c.workpiece_mode].stiffness_n_per_m / (phi * phi);
      if (!(std::isfinite(k))) drop[c.workpiece_mode] = true;  // at the clamp: rigid
      else m.workpiece.modes[c.workpiece_mode].stiffness_n_per_m = k;
    }
    std::vector<Mode> kept;
    for (std::size_t i = 0; i < m.workpiece.modes.size(); ++i)
      if (!drop[i]) kept.push_back(m.workpiece.modes[i]);
    m.workpiece.modes = std::move(kept);
    if (m.rigid())
      throw InputError("position_m = " + number(position_m) +
                       ": at the clamp the workpiece does not move and the tool has no modes: nothing can chatter");
    return m;
  }
  const auto& st = dep.stations;
  // The interval [k, k+1] holding the position; a station's own set exactly.
  const auto it = std::lower_bound(st.begin(), st.end(), position_m,
                                   [](const PositionStation& s, double x) { return s.position_m < x; });
  if (it != st.end() && it->position_m == position_m) return it->model;
  const std::size_t k = static_cast<std::size_t>(it - st.begin()) - 1;
  StructuralModel m;
  m.tool = interpolate_body(st, true, k, position_m);
  m.workpiece = interpolate_body(st, false, k, position_m);
  return m;
}

std::vector<double> evenly_spaced_positions(double lo_m, double hi_m, int count) {
  std::ostringstream os;
  if (!(std::isfinite(lo_m) && std::isfinite(hi_m) && hi_m > lo_m))
    os << "position range [" << lo_m << ", " << hi_m << "] m: must be finite with max > min";
  else if (count < 2)
    os << "position points = " << count << ": must be >= 2 (both ends of the range)";
  if (!os.str().empty()) throw InputError(os.str());
  std::vector<double> v(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
    v[static_cast<std::size_t>(i)] = lo_m + (hi_m - lo_m) * static_cast<double>(i) / (count - 1);
  v.back() = hi_m;  // exactly, whatever the rounding
  return v;
}

}  // namespace chatter
