// Cutting-coefficient identification from average forces or spindle power
// (include/chatter/shop.hpp; docs/shop_data.md). Least squares through a QR
// factorisation of the design matrix; standard errors from (AᵀA)⁻¹ s².
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>

#include "chatter/cutting_law.hpp"
#include "chatter/number_text.hpp"
#include "chatter/error.hpp"
#include "chatter/shop.hpp"
#include "chatter/kinematics.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;

// The fit is "poor" below this R²: a mechanistic model of clean tests
// explains well over 90 % of the variation of the averages.
constexpr double kMinGoodRSquared = 0.9;

// Relative spread below which two feeds count as equal.
constexpr double kSameFeedRel = 1e-9;

// Two-sided 95 % Student t quantile t(0.975, dof).
double student_t95(int dof) {
  static const double table[] = {12.706, 4.303, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201,
                                 2.179,  2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080,
                                 2.074,  2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042, 2.042};
  if (dof < 1) return std::numeric_limits<double>::quiet_NaN();
  if (dof <= 30) return table[dof - 1];
  return 1.959964 + 2.37 / dof;  // asymptotic expansion, error < 0.002 above 30
}

// The arc integrals of the cutting law (chatter/cutting_law.hpp): the same
// ones the law's mean force is made of, here as the fit's regressors.
ArcIntegrals integrals(const MillingEngagement& e) {
  double a = 0, b = 0;
  engagement_angles(e, a, b);
  return arc_integrals(a, b);
}

void check_engagement(const MillingEngagement& e) {
  if (e.teeth < 1) throw InputError("teeth = " + std::to_string(e.teeth) + ": must be >= 1");
  if (!(e.radial_immersion > 0.0 && e.radial_immersion <= 1.0))
    throw InputError("radial immersion = " + number_text(e.radial_immersion) + ": must be in (0, 1]");
}

void check_feeds(const std::vector<double>& feeds, std::size_t needed, const char* route) {
  if (feeds.size() < needed)
    throw InputError(std::string(route) + ": " + std::to_string(feeds.size()) + " test(s), at least " +
                     std::to_string(needed) + " are needed (more tests than unknowns, so the error can be estimated)");
  const auto [lo, hi] = std::minmax_element(feeds.begin(), feeds.end());
  if (!(*hi - *lo > kSameFeedRel * *hi))
    throw InputError(std::string(route) + ": every test has the same feed per tooth (" + number_text(*lo * 1e3) +
                     " mm): cutting and edge coefficients cannot be told apart; cut at two or more feeds");
}

// Solves A θ ≈ b, fills standard errors / intervals for the columns `cols`.
Eigen::VectorXd solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& se, int& dof) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < A.cols())
    throw InputError("the tests do not determine the coefficients (singular design): vary the feed per tooth");
  const Eigen::VectorXd theta = qr.solve(b);
  dof = static_cast<int>(A.rows() - A.cols());
  const double rss = (A * theta - b).squaredNorm();
  const Eigen::MatrixXd cov = (A.transpose() * A).inverse();
  se.resize(A.cols());
  for (Eigen::Index i = 0; i < A.cols(); ++i)
    se[i] = dof > 0 ? std::sqrt(rss / dof * cov(i, i)) : std::numeric_limits<double>::quiet_NaN();
  return theta;
}

double r_squared(const std::vector<double>& measured, const std::vector<double>& residual) {
  double mean = 0;
  for (double v : measured) mean += v;
  mean /= static_cast<double>(measured.size());
  double tss = 0, rss = 0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    tss += (measured[i] - mean) * (measured[i] - mean);
    rss += residual[i] * residual[i];
  }
  return tss > 0 ? 1.0 - rss / tss : (rss == 0 ? 1.0 : 0.0);
}

void plausibility(CoefficientFit& f) {
  auto neg = [&](const char* key, double v, const char* unit) {
    if (std::isfinite(v) && v < 0)
      f.warnings.push_back(std::string(key) + " = " + number_text(v) + " " + unit +
                           " is negative: check the force signs and axes (X along the feed, Y normal to it), "
                           "the milling direction and the radial immersion");
  };
  neg("tangential_coefficient_n_per_m2", f.tangential_coefficient_n_per_m2, "N/m^2");
  neg("radial_coefficient_n_per_m2", f.radial_coefficient_n_per_m2, "N/m^2");
  neg("tangential_edge_coefficient_n_per_m", f.tangential_edge_coefficient_n_per_m, "N/m");
  neg("radial_edge_coefficient_n_per_m", f.radial_edge_coefficient_n_per_m, "N/m");
  auto low = [&](const char* what, double r2) {
    if (std::isfinite(r2) && r2 < kMinGoodRSquared)
      f.warnings.push_back(std::string(what) + " = " + number_text(r2) + " < " + number_text(kMinGoodRSquared) +
                           ": the straight-line model explains the averages poorly (scatter, wear, a bad test?); "
                           "look at the residuals");
  };
  low("R^2", f.r_squared);
  low("R^2 of fx_mean_n", f.r_squared_x);
  low("R^2 of fy_mean_n", f.r_squared_y);
}

}  // namespace

void engagement_angles(const MillingEngagement& e, double& phi_entry_rad, double& phi_exit_rad) {
  std::tie(phi_entry_rad, phi_exit_rad) = milling_arc_rad(e.radial_immersion, e.direction);
}

std::array<double, 2> mean_forces(const MillingEngagement& e, double f, double a, const std::array<double, 4>& k) {
  const Eigen::Vector2d m = milling_mean_force_n(e.teeth, integrals(e), f, a, k[0], k[1], {k[2], k[3]});
  return {m.x(), m.y()};
}

double mean_power(const MillingEngagement& e, double f, double a, double rpm, double diameter_m, double ktc,
                  double kte) {
  return angular_speed_rad_per_s(rpm) * 0.5 * diameter_m * milling_mean_tangential_force_n(e.teeth, integrals(e), f, a, ktc, kte);
}

CoefficientFit fit_coefficients_from_forces(const std::vector<ForceTest>& tests, const MillingEngagement& e) {
  check_engagement(e);
  std::vector<double> feeds;
  for (const auto& t : tests) feeds.push_back(t.feed_per_tooth_m);
  check_feeds(feeds, 3, "force tests");
  const ArcIntegrals I = integrals(e);
  const Eigen::Index n = static_cast<Eigen::Index>(tests.size());
  // Rows scaled so each unknown's column is O(1): θ = (K_tc/1e9, K_rc/1e9, K_te/1e4, K_re/1e4).
  const double sc = 1e9, se_ = 1e4;
  Eigen::MatrixXd A(2 * n, 4);
  Eigen::VectorXd b(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const ForceTest& t = tests[i];
    const double c = e.teeth * t.depth_m / (2 * kPi), f = t.feed_per_tooth_m;
    A.row(2 * i) << -c * f * I.sin_cos * sc, -c * f * I.sin_sq * sc, -c * I.cos * se_, -c * I.sin * se_;
    A.row(2 * i + 1) << c * f * I.sin_sq * sc, -c * f * I.sin_cos * sc, c * I.sin * se_, -c * I.cos * se_;
    b[2 * i] = t.fx_mean_n;
    b[2 * i + 1] = t.fy_mean_n;
  }
  Eigen::VectorXd se;
  CoefficientFit r;
  const Eigen::VectorXd th = solve(A, b, se, r.degrees_of_freedom);
  const double scale[4] = {sc, sc, se_, se_};
  r.tangential_coefficient_n_per_m2 = th[0] * sc;
  r.radial_coefficient_n_per_m2 = th[1] * sc;
  r.tangential_edge_coefficient_n_per_m = th[2] * se_;
  r.radial_edge_coefficient_n_per_m = th[3] * se_;
  const double t95 = student_t95(r.degrees_of_freedom);
  for (int i = 0; i < 4; ++i) {
    r.standard_error[i] = se[i] * scale[i];
    r.confidence_95[i] = t95 * r.standard_error[i];
  }
  const Eigen::VectorXd res = b - A * th;
  std::vector<double> mx, my;
  for (Eigen::Index i = 0; i < n; ++i) {
    r.residual_x_n.push_back(res[2 * i]);
    r.residual_y_n.push_back(res[2 * i + 1]);
    mx.push_back(tests[i].fx_mean_n);
    my.push_back(tests[i].fy_mean_n);
  }
  r.r_squared_x = r_squared(mx, r.residual_x_n);
  r.r_squared_y = r_squared(my, r.residual_y_n);
  // Overall: 1 − (RSS_x + RSS_y) / (TSS_x + TSS_y).
  {
    auto tss = [](const std::vector<double>& v) {
      double m = 0, s = 0;
      for (double x : v) m += x;
      m /= static_cast<double>(v.size());
      for (double x : v) s += (x - m) * (x - m);
      return s;
    };
    const double t = tss(mx) + tss(my);
    r.r_squared = t > 0 ? 1.0 - res.squaredNorm() / t : 1.0;
  }
  plausibility(r);
  return r;
}

CoefficientFit fit_coefficients_from_power(const std::vector<PowerTest>& tests, const MillingEngagement& e,
                                           double tool_diameter_m) {
  check_engagement(e);
  if (!(tool_diameter_m > 0.0 && std::isfinite(tool_diameter_m)))
    throw InputError("tool diameter = " + number_text(tool_diameter_m) + " m: must be > 0");
  std::vector<double> feeds;
  for (const auto& t : tests) feeds.push_back(t.feed_per_tooth_m);
  check_feeds(feeds, 3, "power tests");
  const ArcIntegrals I = integrals(e);
  const Eigen::Index n = static_cast<Eigen::Index>(tests.size());
  const double sc = 1e9, se_ = 1e4;
  Eigen::MatrixXd A(n, 2);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const PowerTest& t = tests[i];
    const double g = angular_speed_rad_per_s(t.spindle_rpm) * 0.5 * tool_diameter_m * e.teeth * t.depth_m / (2 * kPi);
    A.row(i) << g * t.feed_per_tooth_m * I.sin * sc, g * I.width_rad * se_;
    b[i] = t.power_w;
  }
  Eigen::VectorXd se;
  CoefficientFit r;
  const Eigen::VectorXd th = solve(A, b, se, r.degrees_of_freedom);
  r.tangential_coefficient_n_per_m2 = th[0] * sc;
  r.tangential_edge_coefficient_n_per_m = th[1] * se_;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double t95 = student_t95(r.degrees_of_freedom);
  r.standard_error = {se[0] * sc, nan, se[1] * se_, nan};
  r.confidence_95 = {t95 * r.standard_error[0], nan, t95 * r.standard_error[2], nan};
  const Eigen::VectorXd res = b - A * th;
  std::vector<double> m;
  for (Eigen::Index i = 0; i < n; ++i) {
    r.residual_x_n.push_back(res[i]);
    m.push_back(tests[i].power_w);
  }
  r.r_squared = r_squared(m, r.residual_x_n);
  plausibility(r);
  return r;
}

RevolutionAverage average_whole_revolutions(const std::vector<double>& t, const std::vector<double>& fx,
                                            const std::vector<double>& fy, double rpm) {
  if (!(rpm > 0.0 && std::isfinite(rpm))) throw InputError("spindle_rpm = " + number_text(rpm) + ": must be > 0");
  if (t.size() < 2 || fx.size() != t.size() || fy.size() != t.size())
    throw InputError("a force series needs at least 2 samples of time, fx and fy");
  const double period = revolution_s(rpm);
  const double span = t.back() - t.front();
  const double whole = std::floor(span / period * (1 + 1e-12));
  // More revolutions than this (8 h at 20 000 rev/min) is a time column in the
  // wrong unit, and would not fit the int count (found by fuzzing).
  constexpr double kMaxRevolutions = 1e7;
  if (!(whole <= kMaxRevolutions))
    throw InputError("the series spans " + number_text(span) + " s = " + number_text(span / period) + " revolutions at " + number_text(rpm) +
                     " rev/min, more than 1e7: time_s must be in seconds");
  const int revs = static_cast<int>(whole);
  if (revs < 1)
    throw InputError("the series spans " + number_text(span) + " s, shorter than one revolution (" + number_text(period) +
                     " s at " + number_text(rpm) + " rev/min): record at least one whole revolution, better several");
  const double t_end = t.front() + revs * period;
  double sx = 0, sy = 0;
  for (std::size_t i = 0; i + 1 < t.size() && t[i] < t_end; ++i) {
    double t1 = t[i + 1], x1 = fx[i + 1], y1 = fy[i + 1];
    if (t1 > t_end) {  // last interval: interpolate to the end of the last whole revolution
      const double w = (t_end - t[i]) / (t[i + 1] - t[i]);
      x1 = fx[i] + w * (fx[i + 1] - fx[i]);
      y1 = fy[i] + w * (fy[i + 1] - fy[i]);
      t1 = t_end;
    }
    sx += 0.5 * (fx[i] + x1) * (t1 - t[i]);
    sy += 0.5 * (fy[i] + y1) * (t1 - t[i]);
  }
  RevolutionAverage r;
  r.revolutions = revs;
  r.duration_s = revs * period;
  r.fx_mean_n = sx / r.duration_s;
  r.fy_mean_n = sy / r.duration_s;
  return r;
}

}  // namespace chatter
