// The mechanistic grinding model and the predictions at a power, a depth or a
// removal (include/chatter/grinding.hpp; seed 001 ch. 2 and 4).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "grinding_internal.hpp"
#include "grinding_text.hpp"

namespace chatter::grinding {

namespace {

constexpr double kPi = std::numbers::pi;
// Newton on u = Z^(1/3) stops when the step is below this fraction of u:
// a few ulps, the power balance is then exact to rounding.
constexpr double kRootRelTol = 4.0 * std::numeric_limits<double>::epsilon();
constexpr int kMaxRootIterations = 200;

double impacts_at(const Process& p, double power_w) { return p.mechanistic->impacts.at(power_w); }

// The unique u >= 0 with b u^3 + a u = P (a >= 0, b > 0, P > 0): a
// safeguarded Newton iteration inside a bracket that always holds the root.
double cubic_root(double a, double b, double power) {
  double lo = 0.0;
  double hi = std::cbrt(power / b);
  if (a > 0.0) hi = std::min(hi, power / a);
  auto g = [&](double u) { return (b * u * u + a) * u - power; };
  double u = hi;  // g(hi) >= 0; Newton from above is monotone for this convex g
  for (int i = 0; i < kMaxRootIterations; ++i) {
    const double gu = g(u);
    if (gu > 0.0) hi = u;
    else lo = u;
    const double dg = 3.0 * b * u * u + a;
    double next = dg > 0.0 ? u - gu / dg : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool done = std::abs(next - u) <= kRootRelTol * std::max(u, std::numeric_limits<double>::min());
    u = next;
    if (done || hi - lo <= kRootRelTol * hi) break;
  }
  return u;
}

// The powers P with P = c n_c(P) + d, n_c piecewise linear in P (held at the
// ends): one linear equation per piece, in increasing order of P.
std::vector<double> power_roots(const ImpactsPerTurn& nc, double c, double d) {
  const auto& pw = nc.power_w();
  const auto& n = nc.impacts();
  std::vector<double> roots;
  auto keep = [&](double P, double lo, double hi) {
    if (std::isfinite(P) && P > 0.0 && P >= lo && P <= hi &&
        (roots.empty() || P > roots.back() * (1.0 + 1e-12)))
      roots.push_back(P);
  };
  // Below the first row: n_c = n[0].
  keep(c * n.front() + d, 0.0, pw.front());
  for (std::size_t i = 0; i + 1 < pw.size(); ++i) {
    const double s = (n[i + 1] - n[i]) / (pw[i + 1] - pw[i]);
    const double den = 1.0 - c * s;
    if (std::abs(den) < 1e-15) continue;  // P - c n_c(P) - d constant on this piece (no isolated root)
    keep((c * (n[i] - s * pw[i]) + d) / den, pw[i], pw[i + 1]);
  }
  keep(c * n.back() + d, pw.back(), std::numeric_limits<double>::infinity());
  return roots;
}

void check_positive(double v, const char* name, const char* unit) {
  if (!(std::isfinite(v) && v > 0.0))
    throw InputError(std::string(name) + " = " + detail::num(v) + ": must be > 0 " + unit);
}

// Fills everything that follows from (P, Z_w).
Prediction complete(const Process& p, double power_w, double removal, const char* mode) {
  Prediction r;
  r.mode = mode;
  r.removal_source = p.mechanistic ? "mechanistic" : "empirical";
  const double R = p.wheel.radius_m(), N = p.wheel.speed_rev_per_s;
  r.power_w = power_w;
  r.removal_rate_m3_per_s = removal;
  if (p.density_kg_per_m3) r.removal_rate_kg_per_h = removal * *p.density_kg_per_m3 * 3600.0;
  r.max_depth_m = depth_from_removal_m(removal, p.feed_m_per_s, R);
  r.groove_width_m = groove_width_m(r.max_depth_m, R);
  r.depth_per_pass_m = removal / (p.feed_m_per_s * p.wheel.width_m);
  r.cutting_speed_m_per_s = p.wheel.cutting_speed_m_per_s();
  r.tangential_force_n = power_w / r.cutting_speed_m_per_s;
  r.normal_force_n = r.tangential_force_n / p.force_ratio;
  r.specific_energy_j_per_m3 = power_w / removal;
  r.contact_half_angle_rad = contact_half_angle_rad(r.max_depth_m, R);
  r.contact_duration_s = 2.0 * r.contact_half_angle_rad / (2.0 * kPi * N);
  if (r.max_depth_m >= R)
    r.warnings.push_back("the groove depth " + detail::num(r.max_depth_m * 1e3) + " mm reaches the wheel radius " +
                         detail::num(R * 1e3) + " mm: the small-depth geometry no longer holds");
  if (p.mechanistic) {
    const double nc = impacts_at(p, power_w);
    r.impacts_per_turn = nc;
    const PowerSplit s = power_split(p, removal, nc);
    r.friction_power_w = s.friction_w;
    r.chip_power_w = s.chip_w;
    const ImpactsPerTurn& t = p.mechanistic->impacts;
    if (t.is_table() && (power_w < t.power_w().front() || power_w > t.power_w().back()))
      r.warnings.push_back("power " + detail::num(power_w) + " W is outside the impacts_per_turn table (" +
                           detail::num(t.power_w().front()) + " to " + detail::num(t.power_w().back()) +
                           " W): n_c held at " + detail::num(nc));
  }
  if (p.partition) r.energy_partition = detail::energy_partition(p, r, r.warnings);
  if (p.no_load_loss) {
    r.no_load_loss_w = p.no_load_loss->loss_w(p.wheel);
    r.motor_power_w = power_w + *r.no_load_loss_w;
  }
  if (!p.empirical.empty()) r.empirical = predict_empirical(p, power_w, r.warnings);
  return r;
}

void require_mechanistic(const Process& p, const char* what) {
  if (!p.mechanistic)
    throw InputError(std::string(what) +
                     " needs the mechanistic model (grinding.edge_coefficient_n_per_mm, "
                     "cutting_coefficient_n_per_mm2, impacts_per_turn); the empirical models are read at a power only");
}

// The power of the groove (h0, Z_w): P = c n_c(P) + d.
Prediction inverse(const Process& p, double h0, double removal, const char* mode) {
  const MechanisticModel& m = *p.mechanistic;
  const double w = groove_width_m(h0, p.wheel.radius_m());
  const double c = m.edge_coefficient_n_per_m * p.wheel.speed_rev_per_s * 0.75 * p.wheel.width_m * w;
  const double d = m.cutting_coefficient_n_per_m2 * removal;
  const std::vector<double> roots = power_roots(m.impacts, c, d);
  if (roots.empty()) throw NumericalError("grinding: no power found for the target (internal: the balance has a root)");
  Prediction r = complete(p, roots.front(), removal, mode);
  r.max_depth_m = h0;  // exact, not through the round trip
  r.groove_width_m = w;
  if (roots.size() > 1) {
    std::string list;
    for (double P : roots) list += (list.empty() ? "" : ", ") + detail::num(P) + " W";
    r.warnings.push_back("several powers give this target with the impacts_per_turn table (" + list +
                         "): the lowest is reported");
  }
  return r;
}

}  // namespace

// ---------------------------------------------------------------- ImpactsPerTurn

ImpactsPerTurn::ImpactsPerTurn(double impacts) {
  if (!(std::isfinite(impacts) && impacts > 0.0))
    throw InputError("impacts_per_turn = " + detail::num(impacts) + ": must be > 0");
  impacts_ = {impacts};
}

ImpactsPerTurn::ImpactsPerTurn(std::vector<double> power_w, std::vector<double> impacts)
    : power_w_(std::move(power_w)), impacts_(std::move(impacts)) {
  if (power_w_.empty() || power_w_.size() != impacts_.size())
    throw InputError("impacts table: needs one impacts_per_turn per power_w (at least one row)");
  for (std::size_t i = 0; i < power_w_.size(); ++i) {
    if (!(std::isfinite(power_w_[i]) && power_w_[i] > 0.0))
      throw InputError("impacts[" + std::to_string(i) + "].power_w = " + detail::num(power_w_[i]) + ": must be > 0 W");
    if (!(std::isfinite(impacts_[i]) && impacts_[i] > 0.0))
      throw InputError("impacts[" + std::to_string(i) + "].impacts_per_turn = " + detail::num(impacts_[i]) +
                       ": must be > 0");
    if (i > 0 && !(power_w_[i] > power_w_[i - 1]))
      throw InputError("impacts[" + std::to_string(i) + "].power_w = " + detail::num(power_w_[i]) +
                       ": the powers must increase (previous row " + detail::num(power_w_[i - 1]) + " W)");
  }
}

double ImpactsPerTurn::at(double power_w) const {
  if (impacts_.size() == 1 || power_w <= power_w_.front()) return impacts_.front();
  if (power_w >= power_w_.back()) return impacts_.back();
  const auto it = std::upper_bound(power_w_.begin(), power_w_.end(), power_w);
  const std::size_t i = static_cast<std::size_t>(it - power_w_.begin()) - 1;
  const double t = (power_w - power_w_[i]) / (power_w_[i + 1] - power_w_[i]);
  return impacts_[i] + t * (impacts_[i + 1] - impacts_[i]);
}

// ------------------------------------------------------------------- Process

double Wheel::cutting_speed_m_per_s() const { return kPi * diameter_m * speed_rev_per_s; }

double NoLoadLoss::loss_w(const Wheel& wheel) const {
  return c0 * std::pow(2.0 * kPi * wheel.speed_rev_per_s, speed_exponent) *
         std::pow(wheel.diameter_m * 1e3, diameter_exponent);
}

std::string Process::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(wheel.diameter_m)) return "wheel diameter = " + detail::num(wheel.diameter_m) + " m: must be > 0";
  if (!positive(wheel.width_m)) return "wheel width = " + detail::num(wheel.width_m) + " m: must be > 0";
  if (!positive(wheel.speed_rev_per_s))
    return "wheel speed = " + detail::num(wheel.speed_rev_per_s) + " rev/s: must be > 0";
  if (!positive(feed_m_per_s)) return "feed = " + detail::num(feed_m_per_s) + " m/s: must be > 0";
  if (!(positive(force_ratio) && force_ratio <= 10.0))
    return "force ratio = " + detail::num(force_ratio) + ": must be in (0, 10]";
  if (density_kg_per_m3 && !positive(*density_kg_per_m3)) return "density: must be > 0 kg/m^3";
  if (mechanistic) {
    if (!(std::isfinite(mechanistic->edge_coefficient_n_per_m) && mechanistic->edge_coefficient_n_per_m >= 0.0))
      return "edge coefficient k_e = " + detail::num(mechanistic->edge_coefficient_n_per_m) + " N/m: must be >= 0";
    if (!positive(mechanistic->cutting_coefficient_n_per_m2))
      return "cutting coefficient k_c = " + detail::num(mechanistic->cutting_coefficient_n_per_m2) +
             " N/m^2: must be > 0";
  }
  if (!mechanistic && !empirical.removal)
    return "no removal model: give the mechanistic coefficients or an empirical removal model";
  if (!(std::isfinite(transmission_ratio) && transmission_ratio > 0.0)) return "transmission ratio: must be > 0";
  if (motor)
    if (const std::string e = motor->validate(); !e.empty()) return "motor map: " + e;
  if (partition) {
    if (partition->model == PartitionModel::kPower && !mechanistic)
      return "energy partition model \"power\" needs the mechanistic model (friction and chip power)";
    if (partition->model != PartitionModel::kPower && !positive(partition->chip_energy_j_per_m3))
      return "energy partition u_ch: must be > 0";
    if (!(partition->alpha >= 0.0 && partition->alpha <= 1.0 && partition->beta >= 0.0 && partition->beta <= 1.0))
      return "energy partition alpha and beta: must be in [0, 1]";
  }
  if (no_load_loss && !(std::isfinite(no_load_loss->c0) && no_load_loss->c0 >= 0.0 &&
                        std::isfinite(no_load_loss->speed_exponent) && std::isfinite(no_load_loss->diameter_exponent)))
    return "no-load loss: c0 must be >= 0 and the exponents finite";
  for (const auto* m : {&empirical.removal, &empirical.wear, &empirical.normal_force})
    if (*m)
      if (std::string why = (*m)->validate(); !why.empty()) return why;
  if (empirical.normal_force && empirical.normal_force->variable == EmpiricalVariable::kNormalForce)
    return "the normal-force model cannot read the normal force: its variable must be the useful power";
  if (min_wheel_diameter_m && !(positive(*min_wheel_diameter_m) && *min_wheel_diameter_m < wheel.diameter_m))
    return "used-up wheel diameter: must be > 0 and below the wheel diameter";
  return "";
}

// ------------------------------------------------------------------ geometry

double groove_area_m2(double h0, double R) { return 4.0 / 3.0 * std::sqrt(2.0 * R) * std::pow(h0, 1.5); }
double groove_width_m(double h0, double R) { return 2.0 * std::sqrt(2.0 * R * h0); }
double depth_from_removal_m(double Z, double vf, double R) {
  return std::pow(3.0 * Z / (4.0 * vf * std::sqrt(2.0 * R)), 2.0 / 3.0);
}
double contact_half_angle_rad(double h0, double R) { return std::sqrt(2.0 * h0 / R); }

PowerSplit power_split(const Process& p, double removal, double nc) {
  const MechanisticModel& m = *p.mechanistic;
  const double R = p.wheel.radius_m();
  const double w = std::cbrt(12.0 * R * removal / p.feed_m_per_s);
  PowerSplit s;
  s.friction_w = m.edge_coefficient_n_per_m * nc * p.wheel.speed_rev_per_s * 0.75 * p.wheel.width_m * w;
  s.chip_w = m.cutting_coefficient_n_per_m2 * removal;
  return s;
}

double impact_tangential_force_n(const Process& p, double h0, double nc, double phi) {
  const MechanisticModel& m = *p.mechanistic;
  const double R = p.wheel.radius_m();
  const double phi0 = contact_half_angle_rad(h0, R);
  if (!(std::abs(phi) < phi0)) return 0.0;
  const double x = std::abs(phi) / phi0;
  return m.edge_coefficient_n_per_m * p.wheel.width_m * (1.0 - x * x * x) +
         m.cutting_coefficient_n_per_m2 * p.feed_m_per_s / (nc * p.wheel.speed_rev_per_s) * (h0 - 0.5 * R * phi * phi);
}

// ---------------------------------------------------------------- prediction

namespace {

// predict_at_power without its refusal of a groove as deep as the wheel's
// radius: the sweep keeps such points, each with its warning (a curve).
Prediction at_power(const Process& p, double power_w) {
  check_positive(power_w, "power_w", "W");
  double removal = 0.0;
  if (p.mechanistic) {
    const MechanisticModel& m = *p.mechanistic;
    const double nc = impacts_at(p, power_w);
    const double a = m.edge_coefficient_n_per_m * nc * p.wheel.speed_rev_per_s * 0.75 * p.wheel.width_m *
                     std::cbrt(12.0 * p.wheel.radius_m() / p.feed_m_per_s);
    const double u = cubic_root(a, m.cutting_coefficient_n_per_m2, power_w);
    removal = u * u * u;
  } else if (p.empirical.removal) {
    std::vector<std::string> ignored;
    const EmpiricalPrediction e = predict_empirical(p, power_w, ignored);
    removal = e.removal_rate_m3_per_s.value_or(0.0);
    if (!(std::isfinite(removal) && removal > 0.0))
      throw InputError("power_w = " + detail::num(power_w) + ": the empirical removal model gives " +
                       detail::num(removal * 1e9) + " mm^3/s there (not > 0): outside where it holds");
  } else {
    throw InputError("grinding: no removal model (mechanistic coefficients or [grinding.models.removal])");
  }
  if (!(removal > 0.0)) throw NumericalError("grinding: the power balance gave no removal at " + detail::num(power_w) + " W");
  return complete(p, power_w, removal, "power");
}

}  // namespace

Prediction predict_at_power(const Process& p, double power_w) {
  Prediction r = at_power(p, power_w);
  // The same rule as a target depth (predict_for_depth): a groove reaching
  // the wheel's radius is outside the model, refused rather than warned
  // (issue 44: 1 561 mm deep at 1e9 W; a 0.23 mm wheel, i.e. metres as mm).
  const double R = p.wheel.radius_m();
  if (!(r.max_depth_m < R))
    throw InputError("power_w = " + detail::num(power_w) + ": its groove would be " + detail::num(r.max_depth_m * 1e3) +
                     " mm deep, beyond the wheel radius " + detail::num(R * 1e3) +
                     " mm, where the contact geometry no longer holds (a power in mW, or a wheel diameter in m?)");
  return r;
}

Prediction predict_for_depth(const Process& p, double h0) {
  const double R = p.wheel.radius_m();
  if (!(std::isfinite(h0) && h0 > 0.0))
    throw InputError("target_depth_mm = " + detail::num(h0 * 1e3) + ": must be > 0 mm");
  if (!(h0 < R))
    throw InputError("target_depth_mm = " + detail::num(h0 * 1e3) + ": must be below the wheel radius " +
                     detail::num(R * 1e3) + " mm");
  if (!p.mechanistic && p.empirical.removal) {
    // The groove of depth h0 removes A(h0) v_f: the empirical removal model
    // inverted for that (seed 000's predictor's own use).
    Prediction r = predict_for_removal(p, groove_area_m2(h0, R) * p.feed_m_per_s);
    r.mode = "target_depth";
    return r;
  }
  require_mechanistic(p, "target_depth_mm");
  return inverse(p, h0, groove_area_m2(h0, R) * p.feed_m_per_s, "target_depth");
}

namespace {

// Points of the scan that brackets the empirical removal's crossing.
constexpr int kInverseScanPoints = 400;

// The empirical removal model inverted in its tested power range (seed 000's
// own use: the power for a target removal). The first crossing of the
// removal Z(P) with the target in the range, bracketed by a scan and closed
// by bisection; outside the range it is refused with the range's removals.
Prediction empirical_for_removal(const Process& p, double removal) {
  const EmpiricalModel& m = *p.empirical.removal;
  if (!m.domain.useful_power_w)
    throw InputError("target_removal_mm3_per_s: the empirical removal model has no tested power range "
                     "([grinding.models.removal] domain useful_power_w) to invert it in");
  const double lo = m.domain.useful_power_w->lo, hi = m.domain.useful_power_w->hi;
  auto z = [&](double power) {
    std::vector<std::string> ignored;
    return predict_empirical(p, power, ignored).removal_rate_m3_per_s.value_or(std::numeric_limits<double>::quiet_NaN());
  };
  double a = lo, za = z(lo), z_min = za, z_max = za;
  for (int i = 1; i <= kInverseScanPoints; ++i) {
    double b = lo + (hi - lo) * i / kInverseScanPoints;
    const double zb = z(b);
    z_min = std::min(z_min, zb);
    z_max = std::max(z_max, zb);
    if (std::isfinite(za) && std::isfinite(zb) && (za - removal) * (zb - removal) <= 0.0) {
      for (int k = 0; k < 200 && b - a > 1e-12 * b; ++k) {
        const double mid = 0.5 * (a + b), zm = z(mid);
        if ((za - removal) * (zm - removal) <= 0.0) b = mid;
        else a = mid, za = zm;
      }
      Prediction r = predict_at_power(p, 0.5 * (a + b));
      r.mode = "target_removal";
      return r;
    }
    a = b, za = zb;
  }
  throw InputError("target_removal_mm3_per_s = " + detail::num(removal * 1e9) +
                   ": the empirical removal model gives " + detail::num(z_min * 1e9) + " to " +
                   detail::num(z_max * 1e9) + " mm^3/s over its tested power range " + detail::num(lo) + " to " +
                   detail::num(hi) + " W: outside it the model is not read");
}

}  // namespace

Prediction predict_for_removal(const Process& p, double removal) {
  if (!(std::isfinite(removal) && removal > 0.0))
    throw InputError("target_removal_mm3_per_s = " + detail::num(removal * 1e9) + ": must be > 0 mm^3/s");
  if (!p.mechanistic && p.empirical.removal) return empirical_for_removal(p, removal);
  require_mechanistic(p, "target_removal_mm3_per_s");
  const double R = p.wheel.radius_m();
  const double h0 = depth_from_removal_m(removal, p.feed_m_per_s, R);
  if (!(h0 < R))
    throw InputError("target_removal_mm3_per_s = " + detail::num(removal * 1e9) + ": its groove would be " +
                     detail::num(h0 * 1e3) + " mm deep, beyond the wheel radius " + detail::num(R * 1e3) + " mm");
  Prediction r = inverse(p, h0, removal, "target_removal");
  r.removal_rate_m3_per_s = removal;
  return r;
}

// --------------------------------------------------------------------- sweep

std::vector<SweepCurve> sweep_power(const Process& p, double lo, double hi, int points, const std::vector<double>& feeds) {
  if (!(std::isfinite(lo) && lo > 0.0)) throw InputError("power_w_min = " + detail::num(lo) + ": must be > 0 W");
  if (!(std::isfinite(hi) && hi > lo))
    throw InputError("power_w_max = " + detail::num(hi) + ": must be > power_w_min (" + detail::num(lo) + " W)");
  if (points < 2 || points > 100000)
    throw InputError("points = " + std::to_string(points) + ": must be in [2, 100000]");
  if (feeds.size() > 50) throw InputError("feed list: at most 50 feeds (" + std::to_string(feeds.size()) + " given)");
  std::vector<double> fs = feeds.empty() ? std::vector<double>{p.feed_m_per_s} : feeds;
  std::vector<SweepCurve> out;
  for (double f : fs) {
    if (!(std::isfinite(f) && f > 0.0))
      throw InputError("feed_mm_per_s = " + detail::num(f * 1e3) + ": must be > 0 mm/s");
    Process q = p;
    q.feed_m_per_s = f;
    SweepCurve c;
    c.feed_m_per_s = f;
    for (int i = 0; i < points; ++i) {
      const double P = i + 1 == points ? hi : lo + (hi - lo) * i / (points - 1);
      c.points.push_back(at_power(q, P));  // a point beyond the radius stays, with its warning
    }
    out.push_back(std::move(c));
  }
  return out;
}

Envelope operating_envelope(const Process& p) {
  Envelope e;
  if (p.mechanistic && p.mechanistic->impacts.is_table())
    e.impacts_table_w = Interval{p.mechanistic->impacts.power_w().front(), p.mechanistic->impacts.power_w().back()};
  for (const auto* m : {&p.empirical.removal, &p.empirical.wear, &p.empirical.normal_force}) {
    if (!*m || !(*m)->domain.useful_power_w) continue;
    const Interval d = *(*m)->domain.useful_power_w;
    if (!e.tested_power_w) e.tested_power_w = d;
    else e.tested_power_w = Interval{std::max(e.tested_power_w->lo, d.lo), std::min(e.tested_power_w->hi, d.hi)};
  }
  if (e.tested_power_w && !(e.tested_power_w->lo < e.tested_power_w->hi)) e.tested_power_w.reset();
  return e;
}

}  // namespace chatter::grinding
