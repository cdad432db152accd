// Least-squares fits of the grinding models (include/chatter/grinding_data.hpp).
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding_data.hpp"
#include "grinding_internal.hpp"
#include "grinding_text.hpp"

namespace chatter::grinding {

namespace {

// A regressor column whose scaled norm falls below this fraction of the
// largest singular value makes the design singular (1e-10: far above double
// rounding, far below any real spread of test conditions).
constexpr double kRankTolerance = 1e-10;
// Below this R^2 a fit explains too little of its data to be trusted as is.
constexpr double kPoorRSquared = 0.9;

double t975(int dof) { return detail::student_t975(dof); }

// Ordinary least squares y ~ X b. Columns are scaled to unit norm for the
// solve (the regressors span many decades: V_c^3 against P_u, ...).
struct Ols {
  Eigen::VectorXd b, se;
  int dof = 0;
  FitUncertainty uncertainty;  // s^2 (X'X)^-1 of b, s^2, dof
};
Ols ols(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const std::vector<std::string>& names) {
  const Eigen::Index m = X.rows(), p = X.cols();
  Eigen::VectorXd scale(p);
  for (Eigen::Index j = 0; j < p; ++j) {
    const double n = X.col(j).norm();
    scale(j) = n > 0.0 ? n : 1.0;
  }
  const Eigen::MatrixXd Xs = X * scale.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Xs, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  if (sv.size() < p || !(sv(p - 1) > kRankTolerance * sv(0))) {
    // Name the column that is (nearly) a combination of the others.
    const Eigen::VectorXd v = svd.matrixV().col(p - 1);
    Eigen::Index worst = 0;
    v.cwiseAbs().maxCoeff(&worst);
    throw InputError("the tests do not separate the coefficient " + names[static_cast<std::size_t>(worst)] +
                     " from the others (singular design): vary the test conditions more");
  }
  Ols r;
  const Eigen::VectorXd bs = svd.solve(y);
  r.b = bs.cwiseQuotient(scale);
  r.dof = static_cast<int>(m - p);
  const Eigen::VectorXd res = y - X * r.b;
  const double s2 = r.dof > 0 ? res.squaredNorm() / r.dof : 0.0;
  // (Xs'Xs)^-1 = V S^-2 V'; back to the unscaled coefficients.
  const Eigen::MatrixXd V = svd.matrixV();
  const Eigen::VectorXd inv2 = sv.array().square().inverse();
  const Eigen::MatrixXd cov =
      s2 * scale.cwiseInverse().asDiagonal() * V * inv2.asDiagonal() * V.transpose() * scale.cwiseInverse().asDiagonal();
  r.se.resize(p);
  for (Eigen::Index j = 0; j < p; ++j) r.se(j) = std::sqrt(std::max(cov(j, j), 0.0));
  r.uncertainty.residual_variance = s2;
  r.uncertainty.degrees_of_freedom = r.dof;
  r.uncertainty.covariance.resize(static_cast<std::size_t>(p * p));
  for (Eigen::Index i = 0; i < p; ++i)
    for (Eigen::Index j = 0; j < p; ++j)  // symmetric to the last bit
      r.uncertainty.covariance[static_cast<std::size_t>(i * p + j)] = i <= j ? cov(i, j) : cov(j, i);
  return r;
}

// R^2, RMSE, MAE, MAPE of fitted against measured.
void quality(FitStatistics& f, const std::vector<double>& measured) {
  const std::size_t m = measured.size();
  double mean = 0.0;
  for (double v : measured) mean += v;
  mean /= static_cast<double>(m);
  double rss = 0.0, tss = 0.0, abs_sum = 0.0, ape = 0.0;
  int ape_n = 0;
  f.residuals.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double r = measured[i] - f.fitted[i];
    f.residuals[i] = r;
    rss += r * r;
    tss += (measured[i] - mean) * (measured[i] - mean);
    abs_sum += std::abs(r);
    if (measured[i] != 0.0) {
      ape += std::abs(r / measured[i]);
      ++ape_n;
    }
  }
  f.tests = static_cast<int>(m);
  f.r_squared = tss > 0.0 ? 1.0 - rss / tss : (rss == 0.0 ? 1.0 : 0.0);
  f.rmse = std::sqrt(rss / static_cast<double>(m));
  f.mae = abs_sum / static_cast<double>(m);
  f.mape_percent = ape_n > 0 ? 100.0 * ape / ape_n : 0.0;
  if (f.r_squared < kPoorRSquared)
    f.warnings.push_back("R^2 = " + detail::num(f.r_squared) + " < " + detail::num(kPoorRSquared) +
                         ": the model explains little of the tests (check them, or try another form)");
  if (f.degrees_of_freedom == 0)
    f.warnings.emplace_back("no degree of freedom left (as many tests as coefficients): no standard errors");
}

void intervals(FitStatistics& f) {
  const double t = t975(f.degrees_of_freedom);
  const std::size_t p = f.coefficients.size();
  f.confidence_95.assign(p, 0.0);
  f.lower_95.assign(p, 0.0);
  f.upper_95.assign(p, 0.0);
  for (std::size_t j = 0; j < p; ++j) {
    f.confidence_95[j] = t * f.standard_error[j];
    f.lower_95[j] = f.coefficients[j] - f.confidence_95[j];
    f.upper_95[j] = f.coefficients[j] + f.confidence_95[j];
  }
}

// The polynomial terms of poly11/22/33 at (x, y), MATLAB's order.
void poly_terms(EmpiricalForm form, double x, double y, double* t) {
  t[0] = 1.0;
  t[1] = x;
  t[2] = y;
  if (form == EmpiricalForm::kPoly11) return;
  t[3] = x * x;
  t[4] = x * y;
  t[5] = y * y;
  if (form == EmpiricalForm::kPoly22) return;
  t[6] = x * x * x;
  t[7] = x * x * y;
  t[8] = x * y * y;
  t[9] = y * y * y;
}

}  // namespace

FitStatistics fit_mechanistic(const std::vector<MechanisticTest>& tests) {
  const std::size_t m = tests.size();
  if (m < 3)
    throw InputError("the mechanistic fit needs at least 3 tests (2 coefficients and 1 degree of freedom), got " +
                     std::to_string(m));
  Eigen::MatrixXd X(static_cast<Eigen::Index>(m), 2);
  Eigen::VectorXd y(static_cast<Eigen::Index>(m));
  std::vector<double> measured(m);
  for (std::size_t i = 0; i < m; ++i) {
    const MechanisticTest& t = tests[i];
    const Eigen::Index r = static_cast<Eigen::Index>(i);
    const double w = std::cbrt(12.0 * t.wheel.radius_m() * t.removal_m3_per_s / t.feed_m_per_s);
    X(r, 0) = t.impacts_per_turn * t.wheel.speed_rev_per_s * 0.75 * t.wheel.width_m * w;
    X(r, 1) = t.removal_m3_per_s;
    y(r) = t.power_w;
    measured[i] = t.power_w;
  }
  FitStatistics f;
  f.names = {"edge_coefficient_n_per_m", "cutting_coefficient_n_per_m2"};
  const Ols o = ols(X, y, f.names);
  f.coefficients = {o.b(0), o.b(1)};
  f.standard_error = {o.se(0), o.se(1)};
  f.uncertainty = o.uncertainty;
  f.degrees_of_freedom = o.dof;
  intervals(f);
  const Eigen::VectorXd fit = X * o.b;
  f.fitted.assign(fit.data(), fit.data() + fit.size());
  quality(f, measured);
  if (f.coefficients[0] < 0.0)
    f.warnings.push_back("edge_coefficient = " + detail::num(f.coefficients[0] * 1e-3) +
                         " N/mm is negative: friction cannot feed power in (check n_c and the removal)");
  if (f.coefficients[1] <= 0.0)
    f.warnings.push_back("cutting_coefficient = " + detail::num(f.coefficients[1] * 1e-6) +
                         " N/mm^2 is not positive: chip formation must cost power (check the removal)");
  return f;
}

FitStatistics fit_empirical(EmpiricalForm form, EmpiricalVariable variable, const std::vector<EmpiricalSample>& s) {
  const std::size_t p = coefficient_count(form), m = s.size();
  if (form == EmpiricalForm::kHahnLindsay && variable != EmpiricalVariable::kNormalForce)
    throw InputError("hahn_lindsay reads the normal force: fit it on normal_force_n, not on the power");
  if (m < p + 1)
    throw InputError(std::string(empirical_form_name(form)) + " has " + std::to_string(p) +
                     " coefficients: it needs at least " + std::to_string(p + 1) + " tests, got " + std::to_string(m));
  auto second = [&](const EmpiricalInputs& in) {
    return variable == EmpiricalVariable::kUsefulPower ? in.useful_power_w : in.normal_force_n;
  };
  FitStatistics f;
  f.names = coefficient_names(form);
  const Eigen::Index rows = static_cast<Eigen::Index>(m);
  std::vector<double> measured(m);
  for (std::size_t i = 0; i < m; ++i) measured[i] = s[i].value;
  EmpiricalModel model;
  model.form = form;
  model.variable = variable;

  if (form == EmpiricalForm::kPowerLaw) {
    Eigen::MatrixXd X(rows, 4);
    Eigen::VectorXd y(rows);
    for (std::size_t i = 0; i < m; ++i) {
      const EmpiricalInputs& in = s[i].inputs;
      if (!(s[i].value > 0.0 && in.wheel_rpm > 0.0 && second(in) > 0.0 && in.wheel_diameter_mm > 0.0))
        throw InputError("test " + std::to_string(i + 1) +
                         ": power_law is fitted on logarithms: the value, wheel speed, variable and diameter must "
                         "be > 0");
      const Eigen::Index r = static_cast<Eigen::Index>(i);
      X(r, 0) = 1.0;
      X(r, 1) = std::log(in.wheel_rpm);
      X(r, 2) = std::log(second(in));
      X(r, 3) = std::log(in.wheel_diameter_mm);
      y(r) = std::log(s[i].value);
    }
    const Ols o = ols(X, y, {"ln C", "b1", "b2", "b3"});
    f.degrees_of_freedom = o.dof;
    f.coefficients = {std::exp(o.b(0)), o.b(1), o.b(2), o.b(3)};
    f.uncertainty = o.uncertainty;
    f.standard_error = {o.se(0), o.se(1), o.se(2), o.se(3)};
    intervals(f);
    // C's interval is the exponential of ln C's; its "standard error" is ln C's.
    const double t = t975(o.dof);
    f.lower_95[0] = std::exp(o.b(0) - t * o.se(0));
    f.upper_95[0] = std::exp(o.b(0) + t * o.se(0));
    f.confidence_95[0] = 0.5 * (f.upper_95[0] - f.lower_95[0]);
  } else if (form == EmpiricalForm::kHahnLindsay) {
    Eigen::MatrixXd X(rows, 2);
    Eigen::VectorXd y(rows);
    for (std::size_t i = 0; i < m; ++i) {
      const Eigen::Index r = static_cast<Eigen::Index>(i);
      X(r, 0) = s[i].inputs.normal_force_n * s[i].inputs.cutting_speed_m_per_s;
      X(r, 1) = s[i].inputs.cutting_speed_m_per_s;
      y(r) = s[i].value;
    }
    const Ols o = ols(X, y, {"K_p", "F_th"});
    f.degrees_of_freedom = o.dof;
    const double a = o.b(0), b = o.b(1);
    if (a == 0.0) throw InputError("hahn_lindsay: the fitted K_p is 0: the removal does not follow F_N V_c");
    f.coefficients = {a, -b / a};
    f.uncertainty = o.uncertainty;
    // Delta method for F_th = -b/a, with the covariance of (a, b).
    const Eigen::MatrixXd XtX = X.transpose() * X;
    const Eigen::VectorXd res = y - X * o.b;
    const double s2 = o.dof > 0 ? res.squaredNorm() / o.dof : 0.0;
    const Eigen::Matrix2d cov = s2 * XtX.inverse();
    const Eigen::Vector2d grad(b / (a * a), -1.0 / a);
    f.standard_error = {o.se(0), std::sqrt(std::max(0.0, grad.dot(cov * grad)))};
    intervals(f);
  } else {
    Eigen::MatrixXd X(rows, static_cast<Eigen::Index>(p));
    Eigen::VectorXd y(rows);
    double t[10];
    for (std::size_t i = 0; i < m; ++i) {
      poly_terms(form, s[i].inputs.cutting_speed_m_per_s, second(s[i].inputs), t);
      for (std::size_t j = 0; j < p; ++j) X(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = t[j];
      y(static_cast<Eigen::Index>(i)) = s[i].value;
    }
    const Ols o = ols(X, y, f.names);
    f.degrees_of_freedom = o.dof;
    f.coefficients.assign(o.b.data(), o.b.data() + o.b.size());
    f.uncertainty = o.uncertainty;
    f.standard_error.assign(o.se.data(), o.se.data() + o.se.size());
    intervals(f);
  }
  model.coefficients = f.coefficients;
  for (const EmpiricalSample& x : s) f.fitted.push_back(model.evaluate(x.inputs));
  quality(f, measured);
  return f;
}

}  // namespace chatter::grinding
