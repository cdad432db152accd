// The grinding commands' tables and the [grinding] fragment of a fit
// (include/chatter/io/grinding_io.hpp): file formats, CSV and TOML. Their
// JSON records are the records layer's (chatter/records/grinding.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/columns.hpp"
#include "chatter/io/grinding_io.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/kinematics.hpp"

namespace chatter {
namespace {

namespace g = grinding;

// [grinding.models.<name>.fit]: what grind predict needs for intervals
// (docs/grinding.md, "Intervals"); nothing without a degree of freedom.
void write_fit_statistics(std::ostream& o, const std::string& name, const std::string& model,
                          const g::FitUncertainty& u) {
  const auto p = static_cast<std::size_t>(std::lround(std::sqrt(static_cast<double>(u.covariance.size()))));
  if (u.degrees_of_freedom < 1 || p == 0) return;
  const char* params = model == "power_law"      ? "ln C, b1, b2, b3"
                       : model == "hahn_lindsay" ? "K_p, -K_p F_th"
                                                 : "the coefficients";
  o << "[grinding.models." << name << ".fit]   # for intervals: covariance of (" << params
    << "), residual variance" << (model == "power_law" ? " of ln y" : "") << "\nresidual_variance = "
    << table_number(u.residual_variance) << "\ndegrees_of_freedom = " << u.degrees_of_freedom << "\ncovariance = [";
  for (std::size_t i = 0; i < p; ++i) {
    o << (i ? ",\n  [" : "\n  [");
    for (std::size_t j = 0; j < p; ++j) o << (j ? ", " : "") << table_number(u.covariance[i * p + j]);
    o << "]";
  }
  o << "\n]\n";
}

}  // namespace

std::string grinding_fit_fragment(const GrindingFitReport& r, std::optional<double> force_ratio) {
  if (r.tests.empty() || r.targets.empty()) throw InputError("--out: nothing was fitted");
  const GrindingTest& t0 = r.tests.front();
  if (!(t0.wheel_diameter_mm && t0.wheel_width_mm && t0.wheel_rpm && t0.feed_mm_per_s))
    throw InputError("--out: a [grinding] table needs the wheel and feed: give the columns wheel_diameter_mm, "
                     "wheel_width_mm, wheel_rpm, feed_mm_per_s (or the options)");
  if (!force_ratio) {
    double sum = 0.0;
    int n = 0;
    for (const GrindingTest& t : r.tests)
      if (t.friction_coefficient) {
        sum += *t.friction_coefficient;
        ++n;
      }
    if (n > 0) force_ratio = sum / n;
  }
  if (!force_ratio)
    throw InputError("--out: the force ratio F_T/F_N is not in the tests (no normal_force_n column): give --force-ratio");
  std::ostringstream o;
  o << "# Fitted by `chatter grind fit --model " << r.model << "` (chatter " << version() << ") from "
    << r.tests_file << ".\n# The wheel and feed are the first test's; force_ratio "
    << (t0.friction_coefficient ? "is the tests' mean P / (V_c F_N)" : "as given") << ".\n"
    << "[grinding]\nwheel_diameter_mm = " << table_number(*t0.wheel_diameter_mm)
    << "\nwheel_width_mm = " << table_number(*t0.wheel_width_mm) << "\nwheel_rpm = " << table_number(*t0.wheel_rpm)
    << "\nfeed_mm_per_s = " << table_number(*t0.feed_mm_per_s) << "\nforce_ratio = " << table_number(*force_ratio)
    << "\n";
  if (r.model == "mechanistic") {
    const g::FitStatistics& f = r.targets.front().fit;
    if (!(f.coefficients[1] > 0.0) || f.coefficients[0] < 0.0)
      throw InputError("--out: the fitted coefficients (k_e = " + table_number(f.coefficients[0] * 1e-3) +
                       " N/mm, k_c = " + table_number(f.coefficients[1] * 1e-6) +
                       " N/mm^2) are not a valid [grinding] model (k_e >= 0, k_c > 0): check the tests");
    o << "edge_coefficient_n_per_mm = " << table_number(f.coefficients[0] * 1e-3) << "   # +- "
      << table_number(f.confidence_95[0] * 1e-3) << " (95 %)\n"
      << "cutting_coefficient_n_per_mm2 = " << table_number(f.coefficients[1] * 1e-6) << "   # +- "
      << table_number(f.confidence_95[1] * 1e-6) << " (95 %)\n";
    // n_c: one value, or the mean per power as a table.
    std::map<double, std::pair<double, int>> by_power;
    for (std::size_t i : r.targets.front().rows) {
      const GrindingTest& t = r.tests[i];
      auto& e = by_power[*t.power_w];
      e.first += *t.impacts_per_turn;
      ++e.second;
    }
    double first = by_power.begin()->second.first / by_power.begin()->second.second;
    bool constant = true;
    for (const auto& [p, e] : by_power) constant = constant && std::abs(e.first / e.second - first) <= 1e-12 * first;
    if (constant) {
      o << "impacts_per_turn = " << table_number(first) << "\n";
    } else {
      for (const auto& [p, e] : by_power)
        o << "\n[[grinding.impacts]]\npower_w = " << table_number(p)
          << "\nimpacts_per_turn = " << table_number(e.first / e.second) << "\n";
    }
    return o.str();
  }
  for (const auto& t : r.targets) {
    const g::FitStatistics& f = t.fit;
    if (r.model == "power_law" && !(f.coefficients[0] > 0.0))
      throw InputError("--out: the power law's constant C = " + table_number(f.coefficients[0]) + " is not > 0");
    o << "\n[grinding.models." << t.name << "]   # R^2 = " << table_number(f.r_squared) << ", RMSE = "
      << table_number(f.rmse) << (t.name == "normal_force" ? " N" : " mm^3/s") << "\nform = \"" << r.model
      << "\"\ncoefficients = [";
    for (std::size_t i = 0; i < f.coefficients.size(); ++i) o << (i ? ", " : "") << table_number(f.coefficients[i]);
    o << "]   # " << (f.names.empty() ? "" : f.names.front());
    for (std::size_t i = 1; i < f.names.size(); ++i) o << ", " << f.names[i];
    const bool force = r.variable == "normal_force_n";
    o << "\nvariables = [\"cutting_speed_m_per_s\", \"" << (force ? "normal_force_n" : "useful_power_w") << "\"]\n";
    // The tested domain: the tests' range of each variable.
    auto range = [&](auto get) {
      double lo = INFINITY, hi = -INFINITY;
      for (std::size_t i : t.rows)
        if (const auto v = get(r.tests[i])) {
          lo = std::min(lo, *v);
          hi = std::max(hi, *v);
        }
      return std::pair<double, double>{lo, hi};
    };
    o << "[grinding.models." << t.name << ".domain]   # the tests' range\n";
    auto line = [&](const char* key, std::pair<double, double> lh) {
      if (lh.first < lh.second) o << key << " = [" << table_number(lh.first) << ", " << table_number(lh.second) << "]\n";
    };
    line("cutting_speed_m_per_s", range([](const GrindingTest& x) { return x.cutting_speed_m_per_s; }));
    if (force) line("normal_force_n", range([](const GrindingTest& x) { return x.normal_force_n; }));
    else line("useful_power_w", range([](const GrindingTest& x) { return x.power_w; }));
    line("wheel_diameter_mm", range([](const GrindingTest& x) { return x.wheel_diameter_mm; }));
    write_fit_statistics(o, t.name, r.model, f.uncertainty);
  }
  return o.str();
}




namespace {

// A table's number: NaN where the CSV cell is empty (not finite, or absent).
double num_or_nan(double x) { return std::isfinite(x) ? x : std::nan(""); }
double num_or_nan(const std::optional<double>& x, double scale = 1.0) {
  return x ? num_or_nan(*x * scale) : std::nan("");
}

}  // namespace

std::vector<Column> grinding_sweep_table(const std::vector<g::SweepCurve>& curves) {
  const bool mech = !curves.empty() && !curves.front().points.empty() && curves.front().points.front().friction_power_w;
  const bool emp = !curves.empty() && !curves.front().points.empty() && curves.front().points.front().empirical;
  std::vector<double> feed, power, removal, depth, width, pass, ft, fn, energy, friction, chip, impacts, partition,
      heat, e_removal, e_normal, e_wear;
  for (const auto& c : curves)
    for (const g::Prediction& p : c.points) {
      feed.push_back(num_or_nan(c.feed_m_per_s * 1e3));
      power.push_back(num_or_nan(p.power_w));
      removal.push_back(num_or_nan(p.removal_rate_m3_per_s * 1e9));
      depth.push_back(num_or_nan(p.max_depth_m * 1e3));
      width.push_back(num_or_nan(p.groove_width_m * 1e3));
      pass.push_back(num_or_nan(p.depth_per_pass_m * 1e3));
      ft.push_back(num_or_nan(p.tangential_force_n));
      fn.push_back(num_or_nan(p.normal_force_n));
      energy.push_back(num_or_nan(p.specific_energy_j_per_m3 * 1e-9));
      friction.push_back(num_or_nan(p.friction_power_w));
      chip.push_back(num_or_nan(p.chip_power_w));
      impacts.push_back(num_or_nan(p.impacts_per_turn));
      partition.push_back(p.energy_partition ? num_or_nan(p.energy_partition->fraction) : std::nan(""));
      heat.push_back(p.energy_partition ? num_or_nan(p.energy_partition->heat_into_part_w) : std::nan(""));
      if (emp) {
        e_removal.push_back(num_or_nan(p.empirical->removal_rate_m3_per_s, 1e9));
        e_normal.push_back(num_or_nan(p.empirical->normal_force_n));
        e_wear.push_back(num_or_nan(p.empirical->wear_rate_m3_per_s, 1e9));
      }
    }
  std::vector<Column> t = {{"feed_mm_per_s", std::move(feed)},         {"power_w", std::move(power)},
                           {"removal_rate_mm3_per_s", std::move(removal)}, {"max_depth_mm", std::move(depth)},
                           {"groove_width_mm", std::move(width)},     {"depth_per_pass_mm", std::move(pass)},
                           {"tangential_force_n", std::move(ft)},     {"normal_force_n", std::move(fn)},
                           {"specific_energy_j_per_mm3", std::move(energy)}};
  if (mech) {
    t.emplace_back("friction_power_w", std::move(friction));
    t.emplace_back("chip_power_w", std::move(chip));
    t.emplace_back("impacts_per_turn", std::move(impacts));
  }
  t.emplace_back("energy_partition", std::move(partition));
  t.emplace_back("heat_into_part_w", std::move(heat));
  if (emp) {
    t.emplace_back("empirical_removal_rate_mm3_per_s", std::move(e_removal));
    t.emplace_back("empirical_normal_force_n", std::move(e_normal));
    t.emplace_back("empirical_wear_rate_mm3_per_s", std::move(e_wear));
  }
  return t;
}

std::string grinding_sweep_csv(const std::vector<g::SweepCurve>& curves) {
  return columns_csv(grinding_sweep_table(curves));
}

std::vector<Column> grinding_series_table(const g::DynamicsResult& r) {
  std::vector<double> t, depth, surface, force, push;
  for (const auto& s : r.series) {
    t.push_back(num_or_nan(s.time_s));
    depth.push_back(num_or_nan(s.depth_m * 1e3));
    surface.push_back(num_or_nan(s.surface_m * 1e3));
    force.push_back(num_or_nan(s.contact_force_n));
    push.push_back(num_or_nan(s.push_n));
  }
  return {{"time_s", std::move(t)},
          {"depth_mm", std::move(depth)},
          {"surface_mm", std::move(surface)},
          {"contact_force_n", std::move(force)},
          {"push_n", std::move(push)}};
}

std::string grinding_series_csv(const g::DynamicsResult& r) { return columns_csv(grinding_series_table(r)); }

std::vector<Column> grinding_impacts_table(const g::ImpactCount& c, const ImpactRecord& record) {
  std::vector<int> turn, impacts;
  std::vector<double> first_peak, largest_peak;
  std::size_t k = 0;  // peaks are in time order, as the turns
  for (std::size_t i = 0; i < c.per_turn.size(); ++i) {
    double first = NAN, largest = NAN;
    for (int n = 0; n < c.per_turn[i] && k < c.peak_value.size(); ++n, ++k) {
      if (n == 0) first = c.peak_time_s[k];
      largest = std::isnan(largest) ? c.peak_value[k] : std::max(largest, c.peak_value[k]);
    }
    turn.push_back(static_cast<int>(i));
    impacts.push_back(c.per_turn[i]);
    first_peak.push_back(num_or_nan(first));
    largest_peak.push_back(num_or_nan(largest));
  }
  return {{"turn", std::move(turn)},
          {"impacts", std::move(impacts)},
          {"first_peak_time_s", std::move(first_peak)},
          {record.kind == g::ImpactSignal::kNormalForce ? "largest_peak_n" : "largest_peak_rpm_drop",
           std::move(largest_peak)}};
}

std::string grinding_impacts_csv(const g::ImpactCount& c, const ImpactRecord& record) {
  return columns_csv(grinding_impacts_table(c, record));
}

std::vector<Column> grinding_plan_table(const g::Plan& p) {
  std::vector<double> diameter, removal, wear, ratio, removed, time, rpm, speed, power;
  for (const auto& s : p.life) {
    diameter.push_back(num_or_nan(s.diameter_m * 1e3));
    removal.push_back(num_or_nan(s.removal_rate_m3_per_s * 1e9));
    wear.push_back(num_or_nan(s.wear_rate_m3_per_s * 1e9));
    ratio.push_back(num_or_nan(s.removal_rate_m3_per_s / s.wear_rate_m3_per_s));
    removed.push_back(num_or_nan(s.removed_m3 * 1e9));
    time.push_back(num_or_nan(s.time_s));
    rpm.push_back(num_or_nan(s.wheel_rpm));
    speed.push_back(num_or_nan(s.cutting_speed_m_per_s));
    power.push_back(num_or_nan(s.power_w));
  }
  return {{"wheel_diameter_mm", std::move(diameter)}, {"removal_rate_mm3_per_s", std::move(removal)},
          {"wear_rate_mm3_per_s", std::move(wear)},    {"g_ratio", std::move(ratio)},
          {"removed_mm3", std::move(removed)},         {"time_s", std::move(time)},
          {"wheel_rpm", std::move(rpm)},               {"cutting_speed_m_per_s", std::move(speed)},
          {"power_w", std::move(power)}};
}

std::string grinding_plan_csv(const g::Plan& p) { return columns_csv(grinding_plan_table(p)); }

}  // namespace chatter
