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
#include "chatter/io/grinding_io.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/kinematics.hpp"

namespace chatter {
namespace {

namespace g = grinding;

std::string cell(double x) { return std::isfinite(x) ? table_number(x) : std::string(); }
std::string cell(const std::optional<double>& x, double scale = 1.0) { return x ? cell(*x * scale) : std::string(); }

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




std::string grinding_sweep_csv(const std::vector<g::SweepCurve>& curves) {
  std::ostringstream o;
  const bool mech = !curves.empty() && !curves.front().points.empty() && curves.front().points.front().friction_power_w;
  const bool emp = !curves.empty() && !curves.front().points.empty() && curves.front().points.front().empirical;
  o << "feed_mm_per_s,power_w,removal_rate_mm3_per_s,max_depth_mm,groove_width_mm,depth_per_pass_mm,"
       "tangential_force_n,normal_force_n,specific_energy_j_per_mm3";
  if (mech) o << ",friction_power_w,chip_power_w,impacts_per_turn";
  o << ",energy_partition,heat_into_part_w";
  if (emp) o << ",empirical_removal_rate_mm3_per_s,empirical_normal_force_n,empirical_wear_rate_mm3_per_s";
  o << "\n";
  for (const auto& c : curves)
    for (const g::Prediction& p : c.points) {
      o << cell(c.feed_m_per_s * 1e3) << ',' << cell(p.power_w) << ',' << cell(p.removal_rate_m3_per_s * 1e9) << ','
        << cell(p.max_depth_m * 1e3) << ',' << cell(p.groove_width_m * 1e3) << ',' << cell(p.depth_per_pass_m * 1e3)
        << ',' << cell(p.tangential_force_n) << ',' << cell(p.normal_force_n) << ','
        << cell(p.specific_energy_j_per_m3 * 1e-9);
      if (mech) o << ',' << cell(p.friction_power_w) << ',' << cell(p.chip_power_w) << ',' << cell(p.impacts_per_turn);
      o << ',' << (p.energy_partition ? cell(p.energy_partition->fraction) : "") << ','
        << (p.energy_partition ? cell(p.energy_partition->heat_into_part_w) : "");
      if (emp)
        o << ',' << cell(p.empirical->removal_rate_m3_per_s, 1e9) << ',' << cell(p.empirical->normal_force_n) << ','
          << cell(p.empirical->wear_rate_m3_per_s, 1e9);
      o << "\n";
    }
  return o.str();
}

std::string grinding_series_csv(const g::DynamicsResult& r) {
  std::ostringstream o;
  o << "time_s,depth_mm,surface_mm,contact_force_n,push_n\n";
  for (const auto& s : r.series)
    o << cell(s.time_s) << ',' << cell(s.depth_m * 1e3) << ',' << cell(s.surface_m * 1e3) << ','
      << cell(s.contact_force_n) << ',' << cell(s.push_n) << "\n";
  return o.str();
}

std::string grinding_impacts_csv(const g::ImpactCount& c, const ImpactRecord& record) {
  std::ostringstream o;
  o << "turn,impacts,first_peak_time_s,largest_peak_" << (record.kind == g::ImpactSignal::kNormalForce ? "n" : "rpm_drop")
    << "\n";
  std::size_t k = 0;  // peaks are in time order, as the turns
  for (std::size_t i = 0; i < c.per_turn.size(); ++i) {
    double first = NAN, largest = NAN;
    for (int n = 0; n < c.per_turn[i] && k < c.peak_value.size(); ++n, ++k) {
      if (n == 0) first = c.peak_time_s[k];
      largest = std::isnan(largest) ? c.peak_value[k] : std::max(largest, c.peak_value[k]);
    }
    o << i << ',' << c.per_turn[i] << ',' << cell(first) << ',' << cell(largest) << "\n";
  }
  return o.str();
}

std::string grinding_plan_csv(const g::Plan& p) {
  std::ostringstream o;
  o << "wheel_diameter_mm,removal_rate_mm3_per_s,wear_rate_mm3_per_s,g_ratio,removed_mm3,time_s,wheel_rpm,"
       "cutting_speed_m_per_s,power_w\n";
  for (const auto& s : p.life)
    o << cell(s.diameter_m * 1e3) << ',' << cell(s.removal_rate_m3_per_s * 1e9) << ','
      << cell(s.wear_rate_m3_per_s * 1e9) << ',' << cell(s.removal_rate_m3_per_s / s.wear_rate_m3_per_s) << ','
      << cell(s.removed_m3 * 1e9) << ',' << cell(s.time_s) << ',' << cell(s.wheel_rpm) << ','
      << cell(s.cutting_speed_m_per_s) << ',' << cell(s.power_w) << "\n";
  return o.str();
}

}  // namespace chatter
