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
    m.force_n = process_.orthogonal_turning()
                    ? Eigen::Vector2d(-p.depth_m * process_.turning_parameters().feed_force_coefficient_n_per_m2 * p.feed_m, 0.0)
                    : Eigen::Vector2d(-p.depth_m * p.feed_m * process_.edge_force(p.depth_m));
    const double fc = kc_ > 0.0 ? kc_ * p.depth_m * p.feed_m : kNaN;
    m.tangential_force_n = fc;
    m.torque_n_m = fc * p.diameter_m / 2.0;
    m.cutting_speed_m_per_s = cutting_speed_m_per_s(p.diameter_m, p.spindle_rpm);
    m.power_w = fc * m.cutting_speed_m_per_s;
    m.removal_rate_m3_per_s = p.depth_m * p.feed_m * m.cutting_speed_m_per_s;
    return m;
  }

  double peak_force_n(const CutPoint& p) const override {
    check_point(p);
    if (!(kc_ > 0.0)) throw InputError("cutting law: turning needs the tangential coefficient K_c > 0");
    const double fc = kc_ * p.depth_m * p.feed_m;
    // |d| = |(K_f, K_r)| (n and e are orthonormal).
    const TurningParameters& tp = process_.turning_parameters();
    const double ff = (tp.radial_force_coefficient_n_per_m2 == 0.0
                           ? tp.feed_force_coefficient_n_per_m2
                           : std::hypot(tp.feed_force_coefficient_n_per_m2, tp.radial_force_coefficient_n_per_m2)) *
                      p.depth_m * p.feed_m;
    return std::hypot(fc, ff);
  }

 private:
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
  Eigen::Matrix2d total_force_integral(double t_a, double t_b) const override { return force_ * (t_b - t_a); }
  Eigen::Matrix2d damping_integral(double t_a, double t_b) const override { return damping_ * (t_b - t_a); }
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
