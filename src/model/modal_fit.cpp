// Modal fit: peak picking, then Levenberg–Marquardt on the complex
// residual. See include/chatter/modal_fit.hpp for the method.
#include "chatter/modal_fit.hpp"
#include "chatter/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <unsupported/Eigen/NonLinearOptimization>

#include "chatter/error.hpp"

namespace chatter {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kHalfPower = 0.70710678118654752440;  // 1/√2
constexpr double kMaxDamping = 0.9;                    // ζ kept below this during the fit
// A residual that cannot be evaluated (overflow) counts as this large, so the
// step that led there is rejected.
constexpr double kHugeResidual = 1e100;
// Levenberg–Marquardt (MINPACK): stop once a step changes θ (log f, log ζ,
// log k) by less than this relative amount: 1e-10, far below the 1e-6 a
// printed mode shows.
constexpr double kStepTolerance = 1e-10;
// Initial trust-region radius as a multiple of the scaled ‖θ‖ (MINPACK's
// `factor`; 100 by default, 0.1 to 100 recommended): peak picking starts near
// the answer, so the first steps stay local (another peak is not reached).
constexpr double kInitialStepBound = 1.0;

void check_options(const FrfTable& t, const ModalFitOptions& o) {
  const std::string p = t.source + ": modal fit: ";
  if (o.modes < 0) throw InputError(p + "modes = " + std::to_string(o.modes) + ": must be >= 0 (0 = auto)");
  if (!std::isfinite(o.f_min_hz) || o.f_min_hz < 0.0)
    throw InputError(p + "band minimum " + number_text(o.f_min_hz, 10) + " Hz: must be finite and >= 0");
  if (std::isnan(o.f_max_hz) || o.f_max_hz <= o.f_min_hz)
    throw InputError(p + "band maximum " + number_text(o.f_max_hz, 10) + " Hz: must be > band minimum " + number_text(o.f_min_hz, 10) + " Hz");
  if (!(o.peak_threshold >= 0.0 && o.peak_threshold < 1.0))
    throw InputError(p + "peak_threshold = " + number_text(o.peak_threshold, 10) + ": must be in [0, 1)");
  if (!o.direction.allFinite() || o.direction.norm() == 0.0)
    throw InputError(p + "direction must be a finite, non-zero vector");
  if (o.max_iterations < 1) throw InputError(p + "max_iterations = " + std::to_string(o.max_iterations) + ": must be >= 1");
  if (!(o.tolerance >= 0.0)) throw InputError(p + "tolerance = " + number_text(o.tolerance, 10) + ": must be >= 0");
}

/// Indices of the lines in the band.
std::vector<std::size_t> band_lines(const FrfTable& t, const ModalFitOptions& o, bool skip_zero) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double f = t.frequency_hz[i];
    if (f >= o.f_min_hz && f <= o.f_max_hz && !(skip_zero && f <= 0.0)) idx.push_back(i);
  }
  return idx;
}

struct Peak {
  double f = 0.0, zeta = 0.0, k = 0.0, height = 0.0;
};

/// Frequency where |G| crosses `level` between lines a and b (linear).
double crossing(const FrfTable& t, std::size_t a, std::size_t b, double level) {
  const double ma = std::abs(t.value[a]), mb = std::abs(t.value[b]);
  const double s = (ma == mb) ? 0.5 : (level - ma) / (mb - ma);
  return t.frequency_hz[a] + s * (t.frequency_hz[b] - t.frequency_hz[a]);
}

std::vector<Peak> find_peaks(const FrfTable& t, const std::vector<std::size_t>& band) {
  std::vector<Peak> peaks;
  const std::size_t n = band.size();
  auto mag = [&](std::size_t j) { return std::abs(t.value[band[j]]); };
  for (std::size_t j = 1; j + 1 < n; ++j) {
    const double m = mag(j);
    if (!(m >= mag(j - 1) && m > mag(j + 1)) || m <= 0.0) continue;
    const double level = m * kHalfPower;
    // Left: every line stays below m until |G| < level.
    std::size_t l = j;
    bool ok = false;
    while (l > 0) {
      --l;
      if (mag(l) > m) break;
      if (mag(l) < level) {
        ok = true;
        break;
      }
    }
    if (!ok) continue;
    std::size_t r = j;
    ok = false;
    while (r + 1 < n) {
      ++r;
      if (mag(r) > m) break;
      if (mag(r) < level) {
        ok = true;
        break;
      }
    }
    if (!ok) continue;
    // Peak frequency and height: parabola through the three top lines.
    const double x0 = t.frequency_hz[band[j - 1]], x1 = t.frequency_hz[band[j]], x2 = t.frequency_hz[band[j + 1]];
    const double y0 = mag(j - 1), y1 = m, y2 = mag(j + 1);
    const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
    const double a = (d12 - d01) / (x2 - x0);
    double f = x1, h = y1;
    if (a < 0.0) {
      const double b = d01 - a * (x0 + x1);
      const double xv = -b / (2.0 * a);
      if (xv > x0 && xv < x2) {
        f = xv;
        h = y1 + d01 * (xv - x1) + a * (xv - x0) * (xv - x1);
        h = std::max(h, y1);
      }
    }
    const double f1 = crossing(t, band[l], band[l + 1], level);
    const double f2 = crossing(t, band[r - 1], band[r], level);
    double zeta = (f2 - f1) / (2.0 * f);
    zeta = std::clamp(zeta, 1e-4, 0.5);
    peaks.push_back({f, zeta, 1.0 / (2.0 * zeta * h), h});
  }
  return peaks;
}

std::vector<Peak> select_peaks(const FrfTable& t, const ModalFitOptions& o, const std::vector<std::size_t>& band) {
  if (band.size() < 3)
    throw InputError(t.source + ": modal fit: band [" + number_text(o.f_min_hz, 10) + ", " + number_text(o.f_max_hz, 10) + "] Hz holds " +
                     std::to_string(band.size()) + " line(s), need at least 3");
  std::vector<Peak> peaks = find_peaks(t, band);
  std::sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.height > b.height; });
  const std::string band_text = "band " + number_text(t.frequency_hz[band.front()], 10) + "–" + number_text(t.frequency_hz[band.back()], 10) + " Hz";
  if (o.modes == 0) {
    if (peaks.empty())
      throw InputError(t.source + ": modal fit: no resonance peak in " + band_text +
                       " (a maximum whose |G| falls below 1/√2 of it on both sides inside the band)");
    const double cut = o.peak_threshold * peaks.front().height;
    peaks.erase(std::remove_if(peaks.begin(), peaks.end(), [&](const Peak& p) { return p.height < cut; }), peaks.end());
  } else {
    if (peaks.size() < static_cast<std::size_t>(o.modes))
      throw InputError(t.source + ": modal fit: " + std::to_string(o.modes) + " mode(s) asked, " + band_text + " holds " +
                       std::to_string(peaks.size()) +
                       " resonance peak(s) (a maximum whose |G| falls below 1/√2 of it on both sides inside the band)");
    // The N highest must be resonances, not ripple: each at least
    // peak_threshold of the highest, the rule `modes = 0` counts by (issue
    // 44: 5 modes on 2 peaks "fitted" ζ = 0.9 and k = 4e11 N/m to noise).
    const double cut = o.peak_threshold * peaks.front().height;
    const auto significant = static_cast<std::size_t>(
        std::count_if(peaks.begin(), peaks.end(), [&](const Peak& p) { return p.height >= cut; }));
    if (significant < static_cast<std::size_t>(o.modes))
      throw InputError(t.source + ": modal fit: " + std::to_string(o.modes) + " mode(s) asked, " + band_text + " holds " +
                       std::to_string(significant) + " resonance peak(s) at least " + number_text(100.0 * o.peak_threshold, 10) +
                       " % of the highest (and " + std::to_string(peaks.size() - significant) +
                       " smaller maxima: noise or modes too weak to fit): ask for " + std::to_string(significant));
    peaks.resize(static_cast<std::size_t>(o.modes));
  }
  std::sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.f < b.f; });
  return peaks;
}

Mode make_mode(double f, double zeta, double k, const Eigen::Vector2d& u, const std::string& source) {
  try {
    return Mode::from_stiffness(f, zeta, k, u);
  } catch (const InputError& e) {
    throw NumericalError(source + ": modal fit left the physical range (f = " + number_text(f, 10) + " Hz, zeta = " + number_text(zeta, 10) +
                         ", k = " + number_text(k, 10) + " N/m): " + e.what());
  }
}

/// The model over the band: G(θ) and its Jacobian, both divided by `scale`.
struct Model {
  std::size_t n_modes = 0;
  bool residuals = false;
  double scale = 1.0;     // m/N, max |G| in the band
  double omega_c = 1.0;   // rad/s
  std::vector<double> omega;
  std::vector<Complex> measured;

  Eigen::Index parameters() const { return static_cast<Eigen::Index>(3 * n_modes + (residuals ? 2 : 0)); }
  Eigen::Index rows() const { return static_cast<Eigen::Index>(2 * omega.size()); }

  Complex value(const Eigen::VectorXd& th, double w) const {
    Complex g = 0.0;
    for (std::size_t i = 0; i < n_modes; ++i) {
      const auto b = static_cast<Eigen::Index>(3 * i);
      const double wn = kTwoPi * std::exp(th[b]), zeta = std::exp(th[b + 1]), k = std::exp(th[b + 2]);
      const double r = w / wn;
      g += 1.0 / (k * Complex(1.0 - r * r, 2.0 * zeta * r));
    }
    g /= scale;
    if (residuals) {
      const auto b = static_cast<Eigen::Index>(3 * n_modes);
      const double q = omega_c / w;
      g += th[b] - th[b + 1] * q * q;
    }
    return g;
  }

  /// Residual r (2L) and Jacobian J (2L × P) at θ.
  void evaluate(const Eigen::VectorXd& th, Eigen::VectorXd& r, Eigen::MatrixXd* J) const {
    r.resize(rows());
    if (J) J->setZero(rows(), parameters());
    for (std::size_t j = 0; j < omega.size(); ++j) {
      const double w = omega[j];
      const auto row = static_cast<Eigen::Index>(2 * j);
      Complex g = 0.0;
      for (std::size_t i = 0; i < n_modes; ++i) {
        const auto b = static_cast<Eigen::Index>(3 * i);
        const double wn = kTwoPi * std::exp(th[b]), zeta = std::exp(th[b + 1]), k = std::exp(th[b + 2]);
        const double rr = w / wn;
        const Complex D(1.0 - rr * rr, 2.0 * zeta * rr);
        const Complex gi = 1.0 / (k * D) / scale;
        g += gi;
        if (J) {
          const Complex d_f = -gi * Complex(2.0 * rr * rr, -2.0 * zeta * rr) / D;
          const Complex d_z = -gi * Complex(0.0, 2.0 * zeta * rr) / D;
          const Complex d_k = -gi;
          (*J)(row, b) = d_f.real();
          (*J)(row + 1, b) = d_f.imag();
          (*J)(row, b + 1) = d_z.real();
          (*J)(row + 1, b + 1) = d_z.imag();
          (*J)(row, b + 2) = d_k.real();
          (*J)(row + 1, b + 2) = d_k.imag();
        }
      }
      if (residuals) {
        const auto b = static_cast<Eigen::Index>(3 * n_modes);
        const double q = omega_c / w;
        g += th[b] - th[b + 1] * q * q;
        if (J) {
          (*J)(row, b) = 1.0;
          (*J)(row, b + 1) = -q * q;
        }
      }
      const Complex e = g - measured[j] / scale;
      r[row] = e.real();
      r[row + 1] = e.imag();
    }
  }

  double relative_error(const Eigen::VectorXd& th) const {
    double num_sq = 0.0, den_sq = 0.0;
    for (std::size_t j = 0; j < omega.size(); ++j) {
      num_sq += std::norm(value(th, omega[j]) - measured[j] / scale);
      den_sq += std::norm(measured[j] / scale);
    }
    return den_sq > 0.0 ? std::sqrt(num_sq / den_sq) : 0.0;
  }
};

/// The fit as Eigen's MINPACK-style Levenberg–Marquardt (unsupported module
/// NonLinearOptimization, Moré 1978: trust region on the scaled step, QR of
/// the Jacobian) sees it: residual and Jacobian of the log parameters, with ζ
/// held at or below kMaxDamping (evaluated at min(ζ, kMaxDamping), no slope
/// beyond) and a non-finite residual reported as a huge one, so such a step is
/// rejected and the trust region shrinks.
struct LmFunctor {
  const Model& m;
  mutable Eigen::VectorXd clamped;
  int values() const { return static_cast<int>(m.rows()); }
  int inputs() const { return static_cast<int>(m.parameters()); }
  const Eigen::VectorXd& clamp(const Eigen::VectorXd& th) const {
    clamped = th;
    for (std::size_t i = 0; i < m.n_modes; ++i) {
      const auto b = static_cast<Eigen::Index>(3 * i) + 1;
      clamped[b] = std::min(clamped[b], std::log(kMaxDamping));
    }
    return clamped;
  }
  int operator()(const Eigen::VectorXd& th, Eigen::VectorXd& r) const {
    m.evaluate(clamp(th), r, nullptr);
    if (!r.allFinite()) r.setConstant(kHugeResidual);
    return 0;
  }
  int df(const Eigen::VectorXd& th, Eigen::MatrixXd& J) const {
    Eigen::VectorXd r;
    m.evaluate(clamp(th), r, &J);
    for (std::size_t i = 0; i < m.n_modes; ++i) {
      const auto b = static_cast<Eigen::Index>(3 * i) + 1;
      if (th[b] > std::log(kMaxDamping)) J.col(b).setZero();
    }
    if (!J.allFinite()) J = J.unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; });
    return 0;
  }
};

}  // namespace

Complex ModalFitResult::receptance(double frequency_hz) const {
  const double w = kTwoPi * frequency_hz;
  Complex g = 0.0;
  for (const Mode& m : modes) g += m.receptance(w);
  if (residual_upper != 0.0 || residual_lower != 0.0) {
    const double q = residual_omega / w;
    g += residual_upper - residual_lower * q * q;
  }
  return g;
}

std::vector<Mode> pick_peaks(const FrfTable& receptance, const ModalFitOptions& options) {
  check_options(receptance, options);
  const auto band = band_lines(receptance, options, false);
  std::vector<Mode> out;
  for (const Peak& p : select_peaks(receptance, options, band))
    out.push_back(make_mode(p.f, p.zeta, p.k, options.direction, receptance.source));
  return out;
}

ModalFitResult fit_modes(const FrfTable& receptance, const ModalFitOptions& options) {
  check_options(receptance, options);
  validate(receptance);
  const FrfTable& t = receptance;
  const auto band = band_lines(t, options, options.residuals);
  const std::vector<Peak> peaks = select_peaks(t, options, band);

  Model m;
  m.n_modes = peaks.size();
  m.residuals = options.residuals;
  double largest = 0.0;
  for (const std::size_t i : band) {
    m.omega.push_back(kTwoPi * t.frequency_hz[i]);
    m.measured.push_back(t.value[i]);
    largest = std::max(largest, std::abs(t.value[i]));
  }
  m.scale = largest > 0.0 ? largest : 1.0;
  m.omega_c = 0.5 * (m.omega.front() + m.omega.back());
  if (m.rows() < m.parameters() + 1)
    throw InputError(t.source + ": modal fit: " + std::to_string(band.size()) + " lines in the band cannot determine " +
                     std::to_string(m.parameters()) + " parameters");

  Eigen::VectorXd th(m.parameters());
  th.setZero();
  for (std::size_t i = 0; i < peaks.size(); ++i) {
    const auto b = static_cast<Eigen::Index>(3 * i);
    th[b] = std::log(peaks[i].f);
    th[b + 1] = std::log(peaks[i].zeta);
    th[b + 2] = std::log(peaks[i].k);
  }

  ModalFitResult res;
  res.lines = band.size();
  res.f_min_hz = t.frequency_hz[band.front()];
  res.f_max_hz = t.frequency_hz[band.back()];
  for (const Peak& p : peaks) res.initial_modes.push_back(make_mode(p.f, p.zeta, p.k, options.direction, t.source));
  res.initial_error = m.relative_error(th);

  // Levenberg–Marquardt: Eigen's port of MINPACK lmder. Stops when a step
  // lowers the cost by less than `tolerance` (relative: ftol), the step is
  // below round-off of θ, or after max_iterations evaluations of the residual.
  LmFunctor functor{m, {}};
  Eigen::LevenbergMarquardt<LmFunctor> lm(functor);
  lm.parameters.maxfev = options.max_iterations;
  lm.parameters.ftol = options.tolerance;
  lm.parameters.xtol = kStepTolerance;
  lm.parameters.factor = kInitialStepBound;
  const auto status = lm.minimize(th);
  th = functor.clamp(th);
  res.iterations = static_cast<int>(lm.nfev);
  using LmStatus = Eigen::LevenbergMarquardtSpace::Status;
  res.converged = status == LmStatus::RelativeReductionTooSmall || status == LmStatus::RelativeErrorTooSmall ||
                  status == LmStatus::RelativeErrorAndReductionTooSmall || status == LmStatus::CosinusTooSmall ||
                  status == LmStatus::FtolTooSmall || status == LmStatus::XtolTooSmall ||
                  status == LmStatus::GtolTooSmall;

  // Linearised covariance of θ at the solution (the sandwich estimator below).
  Eigen::VectorXd se = Eigen::VectorXd::Constant(m.parameters(), std::numeric_limits<double>::quiet_NaN());
  {
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    m.evaluate(th, r, &J);
    const double rows = static_cast<double>(m.rows()), dof = rows - static_cast<double>(m.parameters());
    const Eigen::MatrixXd normal = J.transpose() * J;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(normal);
    if (r.allFinite() && J.allFinite() && lu.isInvertible()) {
      // Heteroscedasticity-consistent ("sandwich", HC1: White 1980,
      // MacKinnon & White 1985): (JᵀJ)⁻¹ Jᵀ diag(r²) J (JᵀJ)⁻¹ · n/(n − p).
      // A tap test's noise grows with |G| (it is about relative), which the
      // plain s² (JᵀJ)⁻¹ would underestimate by 2-4x at the peaks.
      const Eigen::MatrixXd inv = lu.inverse();
      const Eigen::MatrixXd meat = J.transpose() * r.cwiseAbs2().asDiagonal() * J;
      const Eigen::MatrixXd cov = (rows / dof) * inv * meat * inv;
      for (Eigen::Index p = 0; p < m.parameters(); ++p)
        if (cov(p, p) >= 0.0) se[p] = std::sqrt(cov(p, p));
    }
    for (std::size_t i = 0; i < m.n_modes; ++i)  // ζ at its bound: not identified
      if (th[static_cast<Eigen::Index>(3 * i) + 1] >= std::log(kMaxDamping)) se[static_cast<Eigen::Index>(3 * i) + 1] = std::numeric_limits<double>::quiet_NaN();
  }

  std::vector<std::size_t> order(peaks.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return th[static_cast<Eigen::Index>(3 * a)] < th[static_cast<Eigen::Index>(3 * b)]; });
  for (const std::size_t i : order) {
    const auto b = static_cast<Eigen::Index>(3 * i);
    res.modes.push_back(make_mode(std::exp(th[b]), std::exp(th[b + 1]), std::exp(th[b + 2]), options.direction, t.source));
    res.standard_errors.push_back({se[b], se[b + 1], se[b + 2]});
  }
  if (m.residuals) {
    const auto b = static_cast<Eigen::Index>(3 * m.n_modes);
    res.residual_upper = th[b] * m.scale;
    res.residual_lower = th[b + 1] * m.scale;
    res.residual_omega = m.omega_c;
  }
  res.fit_error = m.relative_error(th);
  return res;
}

}  // namespace chatter
