// The turning implementation of the cutting law (include/chatter/cutting_law.hpp;
// the insert's chord, docs/turning_inserts.md): the static side and the
// regenerative side (chatter/regenerative_cut.hpp).
#include <cmath>
#include <limits>
#include <numbers>

#include "chatter/error.hpp"
#include "chatter/kinematics.hpp"
#include "cutting_internal.hpp"

namespace chatter::cutting_detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class TurningLaw final : public CuttingLaw {
 public:
  TurningLaw(const Process& process, double kc) : process_(process), kc_(kc) {}

  MeanCut mean(const CutPoint& p) const override {
    check_point(p);
    MeanCut m;
    // In the plane: −b h d with b h = a f whatever the insert (the chord's
    // width b times its chip f sin κ_eq); the orthogonal cut: −a K_f f along X.
    // With Kienzle's law the secants at the chip h = f sin κ_eq (kienzle.hpp).
    const double h = process_.chip_thickness_m(p.depth_m, p.feed_m);
    m.force_n = process_.orthogonal_turning() && !law()
                    ? Eigen::Vector2d(-p.depth_m * process_.turning_parameters().feed_force_coefficient_n_per_m2 * p.feed_m, 0.0)
                    : Eigen::Vector2d(-p.depth_m * p.feed_m * static_edge_force(p.depth_m, h));
    const double fc = tangential_force_n(p, h);
    m.tangential_force_n = fc;
    m.torque_n_m = fc * p.diameter_m / 2.0;
    m.cutting_speed_m_per_s = cutting_speed_m_per_s(p.diameter_m, p.spindle_rpm);
    m.power_w = fc * m.cutting_speed_m_per_s;
    m.removal_rate_m3_per_s = p.depth_m * p.feed_m * m.cutting_speed_m_per_s;
    return m;
  }

  double peak_force_n(const CutPoint& p) const override {
    check_point(p);
    if (!(kc_ > 0.0) && !law()) throw InputError("cutting law: turning needs the tangential coefficient K_c > 0");
    const double h = process_.chip_thickness_m(p.depth_m, p.feed_m);
    const double fc = tangential_force_n(p, h);
    // |d| = |(K_f, K_r)| (n and e are orthonormal).
    const double ff = static_edge_force(p.depth_m, h).norm() * p.depth_m * p.feed_m;
    return std::hypot(fc, ff);
  }

 private:
  // d of the static force at chip h; no chip, no force (Kienzle's k(h) grows without bound as h → 0).
  Eigen::Vector2d static_edge_force(double depth_m, double chip_m) const {
    if (law() && !(chip_m > 0.0)) return Eigen::Vector2d::Zero();
    return process_.secant_edge_force(depth_m, chip_m);
  }
  // F_c = k_c(h) a f: K_c, or Kienzle's tangential secant at h; NaN without either.
  double tangential_force_n(const CutPoint& p, double chip_m) const {
    if (law()) return chip_m > 0.0 ? law()->tangential.secant_n_per_m2(chip_m) * p.depth_m * p.feed_m : 0.0;
    return kc_ > 0.0 ? kc_ * p.depth_m * p.feed_m : kNaN;
  }

  const std::optional<KienzleLaw>& law() const { return process_.turning_parameters().kienzle; }

  Process process_;
  double kc_;
};

// The regenerative side (chatter/regenerative_cut.hpp): one edge, the insert,
// one revolution back; a H(a) = b d nᵀ and b n nᵀ constant in time.
class TurningCut final : public RegenerativeCut {
 public:
  TurningCut(const Process& process, double rpm, double depth_m)
      : force_(process.turning_force_matrix(depth_m)),
        damping_(process.has_process_damping() ? process.turning_damping_matrix(depth_m)
                                               : Eigen::Matrix2d::Zero()),
        delays_{process.delay_s(rpm)},
        scale_(process.turning_parameters().feed_force_coefficient_n_per_m2 +
               process.turning_parameters().radial_force_coefficient_n_per_m2) {}

  double pattern_period_s() const override { return delays_.front(); }
  std::vector<double> engagement_events_s() const override { return {}; }
  const std::vector<double>& edge_delays_s() const override { return delays_; }
  void force_integrals(double t_a, double t_b, std::vector<Eigen::Matrix2d>& per_edge) const override {
    per_edge.assign(1, force_ * (t_b - t_a));
  }
  void force_rates(double /*t*/, std::vector<Eigen::Matrix2d>& per_edge) const override { per_edge.assign(1, force_); }
  Eigen::Matrix2d total_force_integral(double t_a, double t_b) const override { return force_ * (t_b - t_a); }
  Eigen::Matrix2d damping_integral(double t_a, double t_b) const override { return damping_ * (t_b - t_a); }
  Eigen::Matrix2d damping_rate(double /*t*/) const override { return damping_; }
  double force_scale_n_per_m2() const override { return scale_; }

 private:
  Eigen::Matrix2d force_, damping_;
  std::vector<double> delays_;
  double scale_;
};

}  // namespace

std::unique_ptr<const CuttingLaw> turning_law(const Process& process, double kc) {
  return std::make_unique<TurningLaw>(process, kc);
}

std::unique_ptr<const RegenerativeCut> turning_cut(const Process& process, double rpm, double depth_m) {
  return std::make_unique<TurningCut>(process, rpm, depth_m);
}

}  // namespace chatter::cutting_detail
