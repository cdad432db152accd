#include "chatter/process.hpp"

#include <cmath>
#include <numbers>
#include "chatter/error.hpp"

namespace chatter {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void require(bool ok, const char* what) {
  if (!ok) throw InputError(what);
}

}  // namespace

Process Process::turning(TurningParameters p) {
  require(std::isfinite(p.feed_force_coefficient_n_per_m2) && p.feed_force_coefficient_n_per_m2 > 0.0,
          "feed force coefficient K_f must be > 0 N/m^2");
  Process pr;
  pr.operation_ = Operation::kTurning;
  pr.turning_ = p;
  return pr;
}

Process Process::milling(MillingParameters p) {
  require(p.teeth >= 1, "number of teeth must be >= 1");
  require(std::isfinite(p.tangential_coefficient_n_per_m2) && p.tangential_coefficient_n_per_m2 > 0.0,
          "tangential coefficient K_t must be > 0 N/m^2");
  require(std::isfinite(p.radial_coefficient_n_per_m2) && p.radial_coefficient_n_per_m2 >= 0.0,
          "radial coefficient K_r must be >= 0 N/m^2");
  require(std::isfinite(p.radial_immersion) && p.radial_immersion > 0.0 && p.radial_immersion <= 1.0,
          "radial immersion a_e/D must be in (0, 1]");
  Process pr;
  pr.operation_ = Operation::kMilling;
  pr.milling_ = p;
  return pr;
}

int Process::delays_per_revolution() const {
  return operation_ == Operation::kTurning ? 1 : milling_.teeth;
}

double Process::delay_s(double rpm) const { return 60.0 / (rpm * delays_per_revolution()); }

double Process::rpm_from_delay(double tau_s) const { return 60.0 / (tau_s * delays_per_revolution()); }

double Process::entry_angle() const {
  return milling_.direction == MillingDirection::kDown
             ? std::acos(2.0 * milling_.radial_immersion - 1.0)
             : 0.0;
}

double Process::exit_angle() const {
  return milling_.direction == MillingDirection::kDown
             ? std::numbers::pi
             : std::acos(1.0 - 2.0 * milling_.radial_immersion);
}

Eigen::Matrix2d Process::tooth_matrix(double phi) const {
  const double kt = milling_.tangential_coefficient_n_per_m2;
  const double kr = milling_.radial_coefficient_n_per_m2;
  const double s = std::sin(phi), c = std::cos(phi);
  const double a = kt * c + kr * s;
  const double b = kt * s - kr * c;
  Eigen::Matrix2d m;
  m << a * s, a * c, -b * s, -b * c;
  return m;
}

Eigen::Matrix2d Process::directional_matrix(double t_s, double rpm) const {
  if (operation_ == Operation::kTurning) {
    Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
    h(0, 0) = turning_.feed_force_coefficient_n_per_m2;
    return h;
  }
  const double omega = kTwoPi * rpm / 60.0;
  const double en = entry_angle(), ex = exit_angle();
  Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
  for (int j = 0; j < milling_.teeth; ++j) {
    double phi = std::fmod(omega * t_s + kTwoPi * j / milling_.teeth, kTwoPi);
    if (phi < 0.0) phi += kTwoPi;
    if (phi >= en && phi <= ex) h += tooth_matrix(phi);
  }
  return h;
}

Eigen::Matrix2d Process::tooth_matrix_antiderivative(double phi) const {
  const double kt = milling_.tangential_coefficient_n_per_m2;
  const double kr = milling_.radial_coefficient_n_per_m2;
  const double s2 = 0.5 * std::sin(phi) * std::sin(phi);  // ∫ sinφ cosφ
  const double c = 0.25 * std::sin(2.0 * phi);
  const double ss = 0.5 * phi - c;                         // ∫ sin²φ
  const double cc = 0.5 * phi + c;                         // ∫ cos²φ
  Eigen::Matrix2d m;
  m << kt * s2 + kr * ss, kt * cc + kr * s2,
       -kt * ss + kr * s2, -kt * s2 + kr * cc;
  return m;
}

Eigen::Matrix2d Process::average_directional_matrix() const {
  if (operation_ == Operation::kTurning) return directional_matrix(0.0, 1.0);
  const Eigen::Matrix2d integral = tooth_matrix_antiderivative(exit_angle()) -
                                   tooth_matrix_antiderivative(entry_angle());
  return milling_.teeth / kTwoPi * integral;
}

}  // namespace chatter
