// The turning implementation of the cutting law (include/chatter/cutting_law.hpp;
// the insert's chord, docs/turning_inserts.md).
#include <cmath>
#include <limits>
#include <numbers>

#include "chatter/error.hpp"
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
    m.power_w = fc * std::numbers::pi * p.diameter_m * p.spindle_rpm / 60.0;
    m.cutting_speed_m_per_s = std::numbers::pi * p.diameter_m * p.spindle_rpm / 60.0;
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

}  // namespace

std::unique_ptr<const CuttingLaw> turning_law(const Process& process, double kc) {
  return std::make_unique<TurningLaw>(process, kc);
}

}  // namespace chatter::cutting_detail
