#include "chatter/structural_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include "chatter/error.hpp"
#include <string>

namespace chatter {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError(what);
}

Eigen::Vector2d unit_direction(const Eigen::Vector2d& d) {
  const double n = d.norm();
  require(std::isfinite(n) && n > 0.0, "mode direction must be a non-zero vector");
  return d / n;
}

void check_common(double frequency_hz, double damping_ratio) {
  require(std::isfinite(frequency_hz) && frequency_hz > 0.0, "natural frequency must be > 0 Hz");
  require(std::isfinite(damping_ratio) && damping_ratio > 0.0 && damping_ratio < 1.0,
          "damping ratio must be in (0, 1)");
}

}  // namespace

Mode Mode::from_stiffness(double frequency_hz, double damping_ratio, double stiffness_n_per_m,
                          Eigen::Vector2d direction) {
  check_common(frequency_hz, damping_ratio);
  require(std::isfinite(stiffness_n_per_m) && stiffness_n_per_m > 0.0, "stiffness must be > 0 N/m");
  Mode m;
  m.natural_frequency_hz = frequency_hz;
  m.damping_ratio = damping_ratio;
  m.stiffness_n_per_m = stiffness_n_per_m;
  m.direction = unit_direction(direction);
  return m;
}

Mode Mode::from_mass(double frequency_hz, double damping_ratio, double mass_kg,
                     Eigen::Vector2d direction) {
  check_common(frequency_hz, damping_ratio);
  require(std::isfinite(mass_kg) && mass_kg > 0.0, "modal mass must be > 0 kg");
  const double w = kTwoPi * frequency_hz;
  return from_stiffness(frequency_hz, damping_ratio, mass_kg * w * w, direction);
}

double Mode::omega() const { return kTwoPi * natural_frequency_hz; }

double Mode::mass_kg() const {
  const double w = omega();
  return stiffness_n_per_m / (w * w);
}

Complex Mode::receptance(double omega_rad_s) const {
  const double r = omega_rad_s / omega();
  return 1.0 / (stiffness_n_per_m * Complex(1.0 - r * r, 2.0 * damping_ratio * r));
}

Mode first_bending_mode(const CantileverBar& bar, double damping_ratio, Eigen::Vector2d direction) {
  require(std::isfinite(bar.youngs_modulus_pa) && bar.youngs_modulus_pa > 0.0,
          "Young's modulus must be > 0 Pa");
  require(std::isfinite(bar.density_kg_per_m3) && bar.density_kg_per_m3 > 0.0,
          "density must be > 0 kg/m^3");
  require(std::isfinite(bar.length_m) && bar.length_m > 0.0, "bar length must be > 0 m");
  require(std::isfinite(bar.diameter_m) && bar.diameter_m > 0.0, "bar diameter must be > 0 m");
  // β₁L = 1.8751040687 is the first root of cos(βL)cosh(βL) = −1.
  constexpr double kBeta1L = 1.8751040687119611;
  const double pi = std::numbers::pi;
  const double d = bar.diameter_m;
  const double L = bar.length_m;
  const double I = pi * d * d * d * d / 64.0;
  const double A = pi * d * d / 4.0;
  const double EI = bar.youngs_modulus_pa * I;
  const double k = 3.0 * EI / (L * L * L);
  const double omega = kBeta1L * kBeta1L / (L * L) * std::sqrt(EI / (bar.density_kg_per_m3 * A));
  return Mode::from_stiffness(omega / kTwoPi, damping_ratio, k, direction);
}

Complex MeasuredTerm::at(double omega_rad_s) const {
  const double f = omega_rad_s / kTwoPi;
  const std::size_t n = frequency_hz.size();
  if (n < 2 || f < frequency_hz.front() || f > frequency_hz.back()) return Complex(0.0);
  // The four lines around f (fewer at the ends of the table).
  const auto it = std::upper_bound(frequency_hz.begin(), frequency_hz.end(), f);
  std::size_t hi = static_cast<std::size_t>(it - frequency_hz.begin());
  hi = std::min(std::max<std::size_t>(hi, 1), n - 1);  // interval [hi-1, hi]
  const std::size_t first = hi >= 2 ? hi - 2 : 0;
  const std::size_t last = std::min(first + 3, n - 1);
  // Lagrange interpolation of the dynamic stiffness 1/G; of G itself where a
  // line is exactly zero (a term that vanishes there has no stiffness).
  bool inverse = true;
  for (std::size_t i = first; i <= last; ++i)
    if (receptance[i] == Complex(0.0)) inverse = false;
  Complex sum(0.0);
  for (std::size_t i = first; i <= last; ++i) {
    double w = 1.0;
    for (std::size_t j = first; j <= last; ++j)
      if (j != i) w *= (f - frequency_hz[j]) / (frequency_hz[i] - frequency_hz[j]);
    sum += w * (inverse ? 1.0 / receptance[i] : receptance[i]);
  }
  return inverse ? 1.0 / sum : sum;
}

Matrix2c Body::receptance(double omega_rad_s) const {
  Matrix2c G = Matrix2c::Zero();
  for (const Mode& m : modes) {
    const Eigen::Matrix2d uu = m.direction * m.direction.transpose();
    G += m.receptance(omega_rad_s) * uu.cast<Complex>();
  }
  for (const MeasuredTerm& t : measured) {
    const Complex g = t.at(omega_rad_s);
    G(t.row, t.col) += g;
    if (t.row != t.col) G(t.col, t.row) += g;  // reciprocity
  }
  return G;
}

std::pair<double, double> StructuralModel::measured_band() const {
  double lo = 0.0, hi = std::numeric_limits<double>::infinity();
  for (const Body* b : {&tool, &workpiece})
    for (const MeasuredTerm& t : b->measured) {
      lo = std::max(lo, kTwoPi * t.frequency_hz.front());
      hi = std::min(hi, kTwoPi * t.frequency_hz.back());
    }
  return {lo, hi};
}

double StructuralModel::frequency_resolution_hz() const {
  double res = 0.0;
  for (const Body* b : {&tool, &workpiece})
    for (const MeasuredTerm& t : b->measured)
      for (std::size_t i = 1; i < t.frequency_hz.size(); ++i)
        res = std::max(res, t.frequency_hz[i] - t.frequency_hz[i - 1]);
  return res;
}

Matrix2c StructuralModel::receptance(double omega_rad_s) const {
  return tool.receptance(omega_rad_s) + workpiece.receptance(omega_rad_s);
}

double StructuralModel::min_omega() const {
  double w = std::numeric_limits<double>::infinity();
  for (const Body* b : {&tool, &workpiece})
    for (const Mode& m : b->modes) w = std::min(w, m.omega());
  if (has_measured()) w = std::min(w, std::max(measured_band().first, 1e-3));
  return w;
}

double StructuralModel::max_omega() const {
  double w = 0.0;
  for (const Body* b : {&tool, &workpiece})
    for (const Mode& m : b->modes) w = std::max(w, m.omega());
  if (has_measured()) w = std::max(w, measured_band().second);
  return w;
}

ModalMatrices modal_matrices(const StructuralModel& model) {
  const Eigen::Index n = static_cast<Eigen::Index>(model.mode_count());
  ModalMatrices mm;
  mm.omega.resize(n);
  mm.damping_ratio.resize(n);
  mm.mass_kg.resize(n);
  mm.S.resize(2, n);
  Eigen::Index i = 0;
  for (const auto& [body, sign] : {std::pair{&model.tool, 1.0}, std::pair{&model.workpiece, -1.0}}) {
    for (const Mode& m : body->modes) {
      mm.omega(i) = m.omega();
      mm.damping_ratio(i) = m.damping_ratio;
      mm.mass_kg(i) = m.mass_kg();
      mm.S.col(i) = sign * m.direction;
      ++i;
    }
  }
  return mm;
}

StateSpace state_space(const StructuralModel& model) {
  const ModalMatrices mm = modal_matrices(model);
  const Eigen::Index n = mm.omega.size();
  StateSpace ss;
  ss.A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  ss.B = Eigen::MatrixXd::Zero(2 * n, 2);
  ss.C = Eigen::MatrixXd::Zero(2, 2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double w = mm.omega(i);
    ss.A(i, n + i) = 1.0;
    ss.A(n + i, i) = -w * w;
    ss.A(n + i, n + i) = -2.0 * mm.damping_ratio(i) * w;
    // q̈_i = ... + (1/m_i) s_i u_iᵀ F, and column i of S is s_i u_i.
    ss.B.row(n + i) = mm.S.col(i).transpose() / mm.mass_kg(i);
  }
  ss.C.leftCols(n) = mm.S;
  return ss;
}

}  // namespace chatter
