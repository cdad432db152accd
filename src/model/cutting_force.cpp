// The static cutting load (include/chatter/cutting_force.hpp).
#include "chatter/cutting_force.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "chatter/error.hpp"

namespace chatter {

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

}  // namespace

CuttingLoad cutting_load(const Process& process, double rpm, double depth_m, double feed_m, double diameter_m,
                         double kc) {
  const std::string where = "cutting_load: ";
  if (!(std::isfinite(rpm) && rpm > 0.0)) throw InputError(where + "spindle_rpm must be > 0");
  if (!(std::isfinite(depth_m) && depth_m >= 0.0)) throw InputError(where + "depth must be >= 0");
  if (!(std::isfinite(feed_m) && feed_m >= 0.0)) throw InputError(where + "feed must be >= 0");
  if (!(std::isfinite(diameter_m) && diameter_m > 0.0)) throw InputError(where + "diameter must be > 0");
  CuttingLoad load;
  if (process.operation() == Operation::kTurning) {
    if (!(std::isfinite(kc) && kc > 0.0)) throw InputError(where + "turning needs the tangential coefficient K_c > 0");
    const double fc = kc * depth_m * feed_m;
    // In the plane: −b h d with b h = a f whatever the insert (the chord's
    // width b times its chip f sin κ_eq), |d| = |(K_f, K_r)|.
    const TurningParameters& tp = process.turning_parameters();
    const double ff = (tp.radial_force_coefficient_n_per_m2 == 0.0
                           ? tp.feed_force_coefficient_n_per_m2
                           : std::hypot(tp.feed_force_coefficient_n_per_m2, tp.radial_force_coefficient_n_per_m2)) *
                      depth_m * feed_m;
    load.force_n = std::hypot(fc, ff);
    load.torque_n_m = fc * diameter_m / 2.0;
    load.power_w = fc * std::numbers::pi * diameter_m * rpm / 60.0;
    return load;
  }
  const MillingParameters& mp = process.milling_parameters();
  const int nt = process.teeth();
  const int slices = process.has_helix() ? kHelixSlices : 1;
  const int samples = kSamplesPerTooth * nt;
  const double period = 60.0 / rpm, dz = depth_m / slices;
  // A cutter profile: its own slices, each with its arc and radial
  // coefficient (the chip f sin φ sin κ times the width dz / sin κ: f sin φ dz).
  const std::vector<AxialSlice> cut =
      process.has_profile() && depth_m > 0.0 ? process.axial_slices(depth_m) : std::vector<AxialSlice>{};
  double torque_sum = 0.0;
  for (int s = 0; s < samples; ++s) {
    const double t = period * s / samples;
    double fx = 0.0, fy = 0.0, tangential = 0.0;
    for (int j = 0; j < nt; ++j)
      for (const AxialSlice& c : cut) {
        if (!c.engaged) continue;
        double phi = std::fmod(process.tooth_angle_rad(j, t, c.z_m, rpm), kTwoPi);
        if (phi < 0.0) phi += kTwoPi;
        if (phi < c.entry_rad || phi > c.exit_rad) continue;
        const double h = process.static_chip_m(j, phi, feed_m) * c.height_m();
        const auto v = milling_force_direction(mp.tangential_coefficient_n_per_m2, c.radial_coefficient_n_per_m2,
                                               std::sin(phi), std::cos(phi));
        fx += h * v.x();
        fy += h * v.y();
        // The torque arm is the slice's radius (the sum below takes D/2).
        tangential += mp.tangential_coefficient_n_per_m2 * h * c.radius_m / (0.5 * diameter_m);
      }
    for (int j = 0; j < nt && cut.empty(); ++j)
      for (int k = 0; k < slices; ++k) {
        const double phi = process.tooth_angle_rad(j, t, (k + 0.5) * dz, rpm);
        if (!process.in_cut(phi)) continue;
        const double h = process.static_chip_m(j, phi, feed_m) * dz;
        const auto v = process.force_direction(phi);
        fx += h * v.x();
        fy += h * v.y();
        tangential += mp.tangential_coefficient_n_per_m2 * h;
      }
    load.force_n = std::max(load.force_n, std::hypot(fx, fy));
    torque_sum += tangential * diameter_m / 2.0;
  }
  load.torque_n_m = torque_sum / samples;
  load.power_w = load.torque_n_m * kTwoPi * rpm / 60.0;
  return load;
}

}  // namespace chatter
