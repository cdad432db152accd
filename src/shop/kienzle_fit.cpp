// Kienzle's law from turning force tests (include/chatter/shop.hpp,
// docs/shop_data.md "Kienzle's law"): a straight line in log-log per force
// direction, its standard errors from the residual variance.
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <string>

#include <boost/math/distributions/students_t.hpp>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/shop.hpp"

namespace chatter {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// y = c + s x by least squares; the fit's direction.
KienzleDirectionFit fit_line(const std::vector<double>& x, const std::vector<double>& y,
                             const std::vector<double>& width_mm, const std::vector<double>& chip_mm,
                             const std::vector<double>& force_n) {
  const double n = static_cast<double>(x.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  const double slope = sxy / sxx, intercept = my - slope * mx;
  KienzleDirectionFit f;
  f.term = {std::exp(intercept) * 1e6, 1.0 - slope};
  double rss = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double e = y[i] - (intercept + slope * x[i]);
    rss += e * e;
    f.residual_n.push_back(force_n[i] - std::exp(intercept) * width_mm[i] * std::pow(chip_mm[i], slope));
  }
  const int dof = static_cast<int>(x.size()) - 2;
  if (dof < 1) return f;
  const double s2 = rss / dof;
  const double se_slope = std::sqrt(s2 / sxx), se_intercept = std::sqrt(s2 * (1.0 / n + mx * mx / sxx));
  const double t95 = boost::math::quantile(boost::math::complement(boost::math::students_t(dof), 0.025));
  f.m_standard_error = se_slope;
  f.k_standard_error_n_per_m2 = f.term.specific_force_n_per_m2 * se_intercept;  // the delta method on exp
  f.m_confidence_95 = t95 * se_slope;
  f.k_confidence_95_n_per_m2 = t95 * f.k_standard_error_n_per_m2;
  f.r_squared = syy > 0.0 ? 1.0 - rss / syy : kNaN;
  return f;
}

}  // namespace

KienzleFit fit_kienzle(const std::vector<TurningForceTest>& tests, double lead_angle_rad) {
  if (!(lead_angle_rad > 0.0 && lead_angle_rad <= std::numbers::pi / 2.0))
    throw InputError("lead angle must be in (0, 90] deg");
  if (tests.size() < 2)
    throw InputError("Kienzle's law needs tests at two feeds at least (it has two constants per direction); got " +
                     std::to_string(tests.size()));
  const double s = std::sin(lead_angle_rad);
  std::vector<double> x, width, chip;
  std::set<double> chips;
  bool radial = true;
  for (const TurningForceTest& t : tests) {
    chip.push_back(t.feed_per_rev_m * 1e3 * s);
    width.push_back(t.depth_m * 1e3 / s);
    x.push_back(std::log(chip.back()));
    chips.insert(chip.back());
    for (const double f : {t.tangential_n, t.feed_n})
      if (!(std::isfinite(f) && f > 0.0)) throw InputError("forces must be > 0 N (got " + number_text(f, 4) + ")");
    if (!(t.radial_n > 0.0)) radial = false;
  }
  if (chips.size() < 2)
    throw InputError("every test has the same chip thickness: Kienzle's exponent needs two feeds at least");
  KienzleFit out;
  out.lead_angle_rad = lead_angle_rad;
  out.degrees_of_freedom = static_cast<int>(tests.size()) - 2;
  auto direction = [&](double TurningForceTest::*force, const char* name) {
    std::vector<double> y, f;
    for (std::size_t i = 0; i < tests.size(); ++i) {
      f.push_back(tests[i].*force);
      y.push_back(std::log(f.back() / width[i]));
    }
    KienzleDirectionFit d = fit_line(x, y, width, chip, f);
    if (!(d.term.exponent >= 0.0 && d.term.exponent < 1.0))
      out.warnings.push_back(std::string(name) + " exponent m = " + number_text(d.term.exponent, 4) +
                             ": outside [0, 1) (the force should grow with the chip, less than in proportion); "
                             "check the feeds and the force columns");
    if (d.r_squared < 0.9)
      out.warnings.push_back(std::string(name) + ": R^2 = " + number_text(d.r_squared, 4) +
                             " < 0.9 in log-log: the tests do not follow one power law (a built-up edge, a "
                             "changed insert?)");
    return d;
  };
  out.tangential = direction(&TurningForceTest::tangential_n, "tangential");
  out.feed = direction(&TurningForceTest::feed_n, "feed");
  if (radial) out.radial = direction(&TurningForceTest::radial_n, "radial");
  // (a named string: GCC 12 warns falsely on push_back of this literal inlined)
  static const std::string kTwoTests =
      "two tests: the law passes through both exactly, with no error estimate; a third feed gives standard errors "
      "and R^2";
  if (out.degrees_of_freedom == 0) out.warnings.push_back(kTwoTests);
  return out;
}

}  // namespace chatter
