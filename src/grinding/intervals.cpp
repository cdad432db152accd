// Intervals on the empirical models' predictions from their fit's statistics
// (include/chatter/grinding.hpp: FitUncertainty, PredictionInterval; the
// fit: src/grinding/fit.cpp). Ordinary least squares: the fitted mean at x
// has variance g(x) C g(x)' (C = s^2 (X'X)^-1), one new test s^2 more.
#include <boost/math/distributions/students_t.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "chatter/grinding.hpp"
#include "grinding_internal.hpp"

namespace chatter::grinding {

namespace detail {

double student_t975(int dof) {
  if (dof <= 0) return 0.0;
  const boost::math::students_t t(static_cast<double>(dof));
  return boost::math::quantile(t, 0.975);
}

std::string validate_uncertainty(const FitUncertainty& u, std::size_t p) {
  if (u.covariance.size() != p * p)
    return "the fit's covariance must be " + std::to_string(p) + " x " + std::to_string(p) + " (one row per coefficient)";
  for (std::size_t i = 0; i < p; ++i) {
    if (!(std::isfinite(u.covariance[i * p + i]) && u.covariance[i * p + i] >= 0.0))
      return "the fit's covariance: its diagonal (variances) must be >= 0";
    for (std::size_t j = 0; j < i; ++j) {
      const double a = u.covariance[i * p + j], b = u.covariance[j * p + i];
      if (!(std::isfinite(a) && std::isfinite(b)) || std::abs(a - b) > 1e-6 * (std::abs(a) + std::abs(b)))
        return "the fit's covariance must be symmetric (row " + std::to_string(i + 1) + ", column " +
               std::to_string(j + 1) + ")";
    }
  }
  if (!(std::isfinite(u.residual_variance) && u.residual_variance >= 0.0))
    return "the fit's residual variance must be >= 0";
  if (u.degrees_of_freedom < 1) return "the fit's degrees of freedom must be >= 1";
  return "";
}

}  // namespace detail

PredictionInterval PredictionInterval::scaled(double f) const {
  PredictionInterval r = *this;
  r.value *= f;
  r.mean_95 = {mean_95.lo * f, mean_95.hi * f};
  r.test_95 = {test_95.lo * f, test_95.hi * f};
  // On ln y (power_law) a factor shifts ln y and leaves its error: the
  // standard errors are scaled only when they are in the value's units.
  if (!log_scale) {
    r.standard_error_mean *= f;
    r.standard_error_test *= f;
  }
  return r;
}

std::vector<double> EmpiricalModel::design_row(const EmpiricalInputs& in) const {
  const double x = in.cutting_speed_m_per_s;
  const double y = variable == EmpiricalVariable::kUsefulPower ? in.useful_power_w : in.normal_force_n;
  switch (form) {
    case EmpiricalForm::kPoly11: return {1.0, x, y};
    case EmpiricalForm::kPoly22: return {1.0, x, y, x * x, x * y, y * y};
    case EmpiricalForm::kPoly33:
      return {1.0, x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y};
    case EmpiricalForm::kPowerLaw:
      return {1.0, std::log(in.wheel_rpm), std::log(y), std::log(in.wheel_diameter_mm)};
    case EmpiricalForm::kHahnLindsay: return {in.normal_force_n * x, x};
  }
  return {};
}

std::optional<PredictionInterval> EmpiricalModel::interval(const EmpiricalInputs& in) const {
  if (!uncertainty) return std::nullopt;
  const FitUncertainty& u = *uncertainty;
  const std::vector<double> g = design_row(in);
  const std::size_t p = g.size();
  double var_mean = 0.0;
  for (std::size_t i = 0; i < p; ++i)
    for (std::size_t j = 0; j < p; ++j) var_mean += g[i] * u.covariance[i * p + j] * g[j];
  var_mean = std::max(var_mean, 0.0);
  PredictionInterval r;
  r.value = evaluate(in);
  r.degrees_of_freedom = u.degrees_of_freedom;
  r.standard_error_mean = std::sqrt(var_mean);
  r.standard_error_test = std::sqrt(var_mean + u.residual_variance);
  const double t = detail::student_t975(u.degrees_of_freedom);
  r.log_scale = form == EmpiricalForm::kPowerLaw;
  if (r.log_scale) {
    const double ln = std::log(r.value);
    r.mean_95 = {std::exp(ln - t * r.standard_error_mean), std::exp(ln + t * r.standard_error_mean)};
    r.test_95 = {std::exp(ln - t * r.standard_error_test), std::exp(ln + t * r.standard_error_test)};
  } else {
    r.mean_95 = {r.value - t * r.standard_error_mean, r.value + t * r.standard_error_mean};
    r.test_95 = {r.value - t * r.standard_error_test, r.value + t * r.standard_error_test};
  }
  return r;
}

}  // namespace chatter::grinding
