// The milling implementation of the cutting law (include/chatter/cutting_law.hpp):
// the closed-form means over a revolution (flat cutter; a profile slice by
// slice), and a sampled revolution for the peak force and for the means
// with runout (whose chip is floored at zero); and the regenerative side
// (chatter/regenerative_cut.hpp): the cut as teeth and slices.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "cutting_internal.hpp"
#include "chatter/kinematics.hpp"

namespace chatter::cutting_detail {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Samples of one revolution per tooth: the force of a straight tooth jumps at
// the entry and exit; 360 per tooth puts the largest value within 1° of tool
// rotation of the true peak (a relative error below 1e-4 of a smooth peak).
constexpr int kSamplesPerTooth = 360;
// Slices of a helical tooth: the force over the depth is a sum over slices
// (midpoint rule); 16 keep the peak within ~0.5 % of its converged value on
// the shipped 30° helix cutter.
constexpr int kHelixSlices = 16;

// One revolution sampled: the largest |F|, and the means of F, of the summed
// tangential force and of the torque.
struct Sampled {
  double peak_n = 0.0;
  Eigen::Vector2d mean_force_n{0.0, 0.0};
  double mean_tangential_n = 0.0;
  double mean_torque_n_m = 0.0;
};

class MillingLaw final : public CuttingLaw {
 public:
  MillingLaw(const Process& process, const EdgeCoefficients& edge) : process_(process), edge_(edge) {}

  MeanCut mean(const CutPoint& p) const override {
    check_point(p);
    const MillingParameters& mp = process_.milling_parameters();
    const int nt = mp.teeth;
    const double kt = mp.tangential_coefficient_n_per_m2;
    const double omega = angular_speed_rad_per_s(p.spindle_rpm);
    MeanCut m;
    m.cutting_speed_m_per_s = cutting_speed_m_per_s(p.diameter_m, p.spindle_rpm);
    // Table feed f N_t N/60 (m/s) times the cross-section cut.
    const double table_speed = table_speed_m_per_s(p.feed_m * nt, p.spindle_rpm);
    if (process_.has_profile()) {
      // Slice by slice: its arc, its radius (the torque arm and the width
      // across the feed R_s P_s) and its radial coefficient; the chip
      // f sin φ sin κ over the width dz / sin κ.
      double torque = 0.0, section = 0.0;
      if (p.depth_m > 0.0)
        for (const AxialSlice& c : process_.axial_slices(p.depth_m)) {
          if (!c.engaged) continue;
          const ArcIntegrals I = arc_integrals(c.entry_rad, c.exit_rad);
          m.force_n += milling_mean_force_n(nt, I, p.feed_m, c.height_m(), kt, c.radial_coefficient_n_per_m2);
          const double ft = milling_mean_tangential_force_n(nt, I, p.feed_m, c.height_m(), kt);
          m.tangential_force_n += ft;
          torque += ft * c.radius_m;
          section += c.height_m() * c.radius_m * I.sin;
        }
      m.torque_n_m = torque;
      m.removal_rate_m3_per_s = section * table_speed;
    } else {
      const ArcIntegrals I = arc_integrals(process_.engaged_arcs());
      m.force_n = milling_mean_force_n(nt, I, p.feed_m, p.depth_m, kt, mp.radial_coefficient_n_per_m2, edge_);
      m.tangential_force_n = milling_mean_tangential_force_n(nt, I, p.feed_m, p.depth_m, kt, edge_.tangential_n_per_m);
      m.torque_n_m = m.tangential_force_n * p.diameter_m / 2.0;
      // a × a_e × the table feed.
      m.removal_rate_m3_per_s = p.depth_m * (mp.radial_immersion * p.diameter_m) * table_speed;
    }
    if (process_.has_runout()) {
      // The chip is floored at zero and moves between the teeth: the forces
      // from a sampled revolution (the volume removed is the same).
      const Sampled s = sample(p);
      m.force_n = s.mean_force_n;
      m.tangential_force_n = s.mean_tangential_n;
      m.torque_n_m = s.mean_torque_n_m;
    }
    m.power_w = m.torque_n_m * omega;
    return m;
  }

  double peak_force_n(const CutPoint& p) const override {
    check_point(p);
    return sample(p).peak_n;
  }

 private:
  // The teeth's forces over one revolution, kSamplesPerTooth N_t samples;
  // straight or helical teeth by kHelixSlices slices, a profile by its own.
  Sampled sample(const CutPoint& p) const {
    const MillingParameters& mp = process_.milling_parameters();
    const double kt = mp.tangential_coefficient_n_per_m2;
    const double kte = edge_.tangential_n_per_m, kre = edge_.radial_n_per_m;
    const bool edge = kte > 0.0 || kre > 0.0;
    const int nt = process_.teeth();
    const int slices = process_.has_helix() ? kHelixSlices : 1;
    const int samples = kSamplesPerTooth * nt;
    const double rpm = p.spindle_rpm, period = revolution_s(rpm), dz = p.depth_m / slices;
    const std::vector<AxialSlice> cut = process_.has_profile() && p.depth_m > 0.0 ? process_.axial_slices(p.depth_m)
                                                                                : std::vector<AxialSlice>{};
    Sampled out;
    double tangential_sum = 0.0, torque_sum = 0.0;
    Eigen::Vector2d force_sum(0.0, 0.0);
    for (int s = 0; s < samples; ++s) {
      const double t = period * s / samples;
      double fx = 0.0, fy = 0.0, tangential = 0.0, torque = 0.0;
      for (int j = 0; j < nt; ++j)
        for (const AxialSlice& c : cut) {
          if (!c.engaged) continue;
          double phi = std::fmod(process_.tooth_angle_rad(j, t, c.z_m, rpm), kTwoPi);
          if (phi < 0.0) phi += kTwoPi;
          if (phi < c.entry_rad || phi > c.exit_rad) continue;
          const double h = process_.static_chip_m(j, phi, p.feed_m) * c.height_m();
          const auto v = milling_force_direction(kt, c.radial_coefficient_n_per_m2, std::sin(phi), std::cos(phi));
          fx += h * v.x();
          fy += h * v.y();
          tangential += kt * h;
          torque += kt * h * c.radius_m;
        }
      for (int j = 0; j < nt && cut.empty(); ++j)
        for (int k = 0; k < slices; ++k) {
          const double phi = process_.tooth_angle_rad(j, t, (k + 0.5) * dz, rpm);
          if (!process_.in_cut(phi)) continue;
          const double chip = process_.static_chip_m(j, phi, p.feed_m);
          const double h = chip * dz;
          const auto v = process_.force_direction(phi);
          fx += h * v.x();
          fy += h * v.y();
          tangential += kt * h;
          if (edge && chip > 0.0) {  // the edge rubs only where the tooth cuts
            const auto ve = milling_force_direction(kte, kre, std::sin(phi), std::cos(phi));
            fx += dz * ve.x();
            fy += dz * ve.y();
            tangential += kte * dz;
          }
        }
      if (cut.empty()) torque = tangential * p.diameter_m / 2.0;
      out.peak_n = std::max(out.peak_n, std::hypot(fx, fy));
      // The force on the tool is −F (Process::force_direction: F = −h v).
      force_sum -= Eigen::Vector2d(fx, fy);
      tangential_sum += tangential;
      torque_sum += torque;
    }
    out.mean_force_n = force_sum / samples;
    out.mean_tangential_n = tangential_sum / samples;
    out.mean_torque_n_m = torque_sum / samples;
    return out;
  }

  Process process_;
  EdgeCoefficients edge_;
};

// The regenerative side (chatter/regenerative_cut.hpp): an edge is a tooth,
// or a slice of it when its delay varies along it (variable helix: equal
// slices of the depth) or the cutter has a profile (its own slices). Edges
// in tooth-major order, e = j · slices + s.
class MillingCut final : public RegenerativeCut {
 public:
  MillingCut(const Process& process, double rpm, double depth_m, int helix_slices)
      : process_(process), rpm_(rpm), depth_m_(depth_m), teeth_(process.teeth()) {
    if (process_.has_profile() && depth_m_ > 0.0) cut_ = process_.axial_slices(depth_m_);
    slices_ = !cut_.empty() ? static_cast<int>(cut_.size())
              : (process_.has_variable_helix() && depth_m_ > 0.0) ? helix_slices
                                                                  : 1;
    delays_.reserve(static_cast<std::size_t>(teeth_ * slices_));
    for (int j = 0; j < teeth_; ++j)
      for (int s = 0; s < slices_; ++s)
        delays_.push_back(process_.tooth_delay_s(
            j, !cut_.empty() ? cut_[static_cast<std::size_t>(s)].z_m : depth_m_ * (s + 0.5) / slices_, rpm_));
    const MillingParameters& mp = process_.milling_parameters();
    scale_ = mp.tangential_coefficient_n_per_m2 + mp.radial_coefficient_n_per_m2;
  }

  double pattern_period_s() const override { return process_.period_s(rpm_); }
  std::vector<double> engagement_events_s() const override { return process_.engagement_events_s(rpm_, depth_m_); }
  const std::vector<double>& edge_delays_s() const override { return delays_; }
  // Each slice's own events when a tooth's slices have different delays (a
  // variable helix: they sit in different delay groups, whose shares have
  // kinks the tooth's sum does not) or different arcs, coefficients or lag
  // rates (a ball or bull nose: each slice's entry and exit is a kink of the
  // sum too): a flat cutter's
  // slice tops, a profile's slice bottoms and tops entering and leaving
  // their arcs. A cylinder's slices (one arc, one delay) need none.
  std::vector<double> edge_events_s() const override {
    bool varies = false;
    for (int j = 0; j < teeth_ && !varies; ++j)
      for (int s = 1; s < slices_ && !varies; ++s)
        varies = delays_[static_cast<std::size_t>(j * slices_ + s)] != delays_[static_cast<std::size_t>(j * slices_)];
    auto slope = [](const AxialSlice& c) { return (c.lag_hi - c.lag_lo) / c.height_m(); };
    for (std::size_t s = 1; s < cut_.size() && !varies; ++s)
      varies = cut_[s].engaged != cut_[0].engaged || cut_[s].entry_rad != cut_[0].entry_rad ||
               cut_[s].exit_rad != cut_[0].exit_rad ||
               cut_[s].radial_coefficient_n_per_m2 != cut_[0].radial_coefficient_n_per_m2 ||
               std::abs(slope(cut_[s]) - slope(cut_[0])) > 1e-12 * std::abs(slope(cut_[0]));
    if (!varies) return engagement_events_s();
    std::vector<double> all = engagement_events_s();
    if (cut_.empty()) {
      for (int s = 1; s < slices_; ++s) {
        const std::vector<double> at = process_.engagement_events_s(rpm_, depth_m_ * s / slices_);
        all.insert(all.end(), at.begin(), at.end());
      }
    } else {
      const double omega = angular_speed_rad_per_s(rpm_), period = pattern_period_s();
      for (int j = 0; j < teeth_; ++j)
        for (const AxialSlice& c : cut_)
          if (c.engaged)
            for (const double edge : {c.entry_rad, c.exit_rad})
              for (const double z : {c.z_lo_m, c.z_hi_m}) {
                const double t = (edge + process_.tooth_offset_rad(j) + process_.helix_lag_rad(j, z)) / omega;
                all.push_back(t - period * std::floor(t / period));
              }
    }
    std::sort(all.begin(), all.end());
    const double merge = 1e-12 * pattern_period_s();
    std::vector<double> out;
    for (const double t : all)
      if (out.empty() || t - out.back() > merge) out.push_back(t);
    return out;
  }

  void force_integrals(double t_a, double t_b, std::vector<Eigen::Matrix2d>& per_edge) const override {
    per_edge.assign(delays_.size(), Eigen::Matrix2d::Zero());
    for (int j = 0; j < teeth_; ++j) {
      const auto first = static_cast<std::size_t>(j * slices_);
      if (!cut_.empty()) {
        for (std::size_t s = 0; s < cut_.size(); ++s)
          per_edge[first + s] = process_.slice_force_integral(j, cut_[s], t_a, t_b, rpm_);
        continue;
      }
      // Slices as differences of the integral up to their tops (exact for
      // any helix: the closed form integrates over the height).
      Eigen::Matrix2d below = Eigen::Matrix2d::Zero();
      for (int s = 0; s < slices_; ++s) {
        const Eigen::Matrix2d upto = process_.tooth_force_integral(j, t_a, t_b, depth_m_ * (s + 1) / slices_, rpm_);
        per_edge[first + static_cast<std::size_t>(s)] = upto - below;
        below = upto;
      }
    }
  }

  // The same slices at one instant (force_integrals' integrand in t_b).
  void force_rates(double t, std::vector<Eigen::Matrix2d>& per_edge) const override {
    per_edge.assign(delays_.size(), Eigen::Matrix2d::Zero());
    for (int j = 0; j < teeth_; ++j) {
      const auto first = static_cast<std::size_t>(j * slices_);
      if (!cut_.empty()) {
        for (std::size_t s = 0; s < cut_.size(); ++s) per_edge[first + s] = process_.slice_force_rate(j, cut_[s], t, rpm_);
        continue;
      }
      Eigen::Matrix2d below = Eigen::Matrix2d::Zero();
      for (int s = 0; s < slices_; ++s) {
        const Eigen::Matrix2d upto = process_.tooth_force_rate(j, t, depth_m_ * (s + 1) / slices_, rpm_);
        per_edge[first + static_cast<std::size_t>(s)] = upto - below;
        below = upto;
      }
    }
  }

  Eigen::Matrix2d total_force_integral(double t_a, double t_b) const override {
    Eigen::Matrix2d tot = Eigen::Matrix2d::Zero();
    if (!cut_.empty()) {
      for (int j = 0; j < teeth_; ++j)
        for (const AxialSlice& c : cut_) tot += process_.slice_force_integral(j, c, t_a, t_b, rpm_);
    } else {
      for (int j = 0; j < teeth_; ++j) tot += process_.tooth_force_integral(j, t_a, t_b, depth_m_, rpm_);
    }
    return tot;
  }

  Eigen::Matrix2d damping_integral(double t_a, double t_b) const override {
    Eigen::Matrix2d d = Eigen::Matrix2d::Zero();
    if (!process_.has_process_damping()) return d;  // (a profile refuses process damping: Process::milling)
    for (int j = 0; j < teeth_; ++j) d += process_.tooth_damping_integral(j, t_a, t_b, depth_m_, rpm_);
    return d;
  }

  Eigen::Matrix2d damping_rate(double t) const override {
    Eigen::Matrix2d d = Eigen::Matrix2d::Zero();
    if (!process_.has_process_damping()) return d;
    for (int j = 0; j < teeth_; ++j) d += process_.tooth_damping_rate(j, t, depth_m_, rpm_);
    return d;
  }

  double force_scale_n_per_m2() const override { return scale_; }

 private:
  Process process_;
  double rpm_, depth_m_;
  int teeth_, slices_ = 1;
  std::vector<AxialSlice> cut_;
  std::vector<double> delays_;
  double scale_ = 0.0;
};

}  // namespace

std::unique_ptr<const CuttingLaw> milling_law(const Process& process, const EdgeCoefficients& edge) {
  return std::make_unique<MillingLaw>(process, edge);
}

std::unique_ptr<const RegenerativeCut> milling_cut(const Process& process, double rpm, double depth_m,
                                                   int helix_slices) {
  return std::make_unique<MillingCut>(process, rpm, depth_m, helix_slices);
}

}  // namespace chatter::cutting_detail
