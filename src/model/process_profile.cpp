// The cut of a cutter with a profile along its axis (ball, bull nose,
// general; docs/cutter_geometry.md): its axial slices and their exact
// time integrals. The one implementation sdm, the time domain, the averaged
// methods and the shop numerics read (include/chatter/process.hpp).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "chatter/process.hpp"
#include "chatter/kinematics.hpp"
#include "windowed_integral.hpp"

namespace chatter {
using namespace process_detail;

double Process::helix_lag_rad(int j, double z_m) const {
  if (!has_profile()) return z_m * helix_lag_rad_per_m(j);
  const double tb = tan_helix_[static_cast<std::size_t>(j)];
  return tb == 0.0 ? 0.0 : tb * profile_.lag_integral(z_m);  // Λ may be +inf where tan β = 0
}

std::vector<AxialSlice> Process::axial_slices(double depth_m) const {
  if (!has_profile()) throw std::logic_error("axial_slices: only for a cutter with a profile");
  const int n = profile_.slices();
  const MillingParameters& mp = milling_;
  const double r0 = profile_.tool_radius_m();
  const bool down = mp.direction == MillingDirection::kDown;
  std::vector<AxialSlice> out(static_cast<std::size_t>(n));
  double lag_below = profile_.lag_integral(0.0);
  for (int k = 0; k < n; ++k) {
    AxialSlice& s = out[static_cast<std::size_t>(k)];
    s.z_lo_m = depth_m * k / n;
    s.z_hi_m = k + 1 == n ? depth_m : depth_m * (k + 1) / n;
    s.z_m = 0.5 * (s.z_lo_m + s.z_hi_m);
    s.radius_m = profile_.radius_m(s.z_m);
    s.lead_angle_rad = profile_.lead_angle_rad(s.z_m);
    s.lag_lo = lag_below;
    s.lag_hi = profile_.lag_integral(s.z_hi_m);
    lag_below = s.lag_hi;
    const SliceEngagement e = slice_engagement(s.radius_m, r0, mp.radial_immersion, down);
    s.entry_rad = e.entry_rad;
    s.exit_rad = e.exit_rad;
    s.engaged = e.engaged;
    const double kr = mp.radial_coefficient_n_per_m2, ka = mp.axial_coefficient_n_per_m2;
    // K_r sin κ + K_a cos κ; exactly K_r on a cylinder slice (κ = 90°).
    s.radial_coefficient_n_per_m2 =
        ka == 0.0 ? kr * lead_sin(s.lead_angle_rad) : kr * lead_sin(s.lead_angle_rad) + ka * lead_cos(s.lead_angle_rad);
  }
  return out;
}

std::string Process::no_chip_reason(double depth_m) const {
  if (!(depth_m > 0.0)) return "no cut: a depth of 0 leaves no chip";
  if (!has_profile()) return "";
  for (const AxialSlice& s : axial_slices(depth_m))
    if (s.engaged) return "";
  const double r0 = profile_.tool_radius_m();
  std::ostringstream os;
  os.precision(4);
  os << "no cut: " << depth_m * 1e3 << " mm deep, the " << to_string(profile_.parameters().geometry)
     << " cutter's edge reaches " << profile_.radius_m(depth_m) * 1e3 << " mm from its axis, and the radial depth ("
     << milling_.radial_immersion * 2.0 * r0 * 1e3 << " mm) starts "
     << r0 * std::abs(1.0 - 2.0 * milling_.radial_immersion) * 1e3
     << " mm from it: no edge engages, so there is no chip to judge (cut deeper or wider)";
  return os.str();
}

namespace {

// A windowed integrand over one slice of tooth j: the edge at height
// z_lo + ζ (0 <= ζ <= dz) is at φ = Ω t − Θ − κ ζ, Θ = Θ_j + tan β_j Λ_lo,
// κ = tan β_j ΔΛ/dz. `integral(w, Ω, Θ, κ, dz)`: time_height_integral over a
// step or height_integral at an instant.
template <class T, class I>
typename Windowed<T>::Value over_slice(const T& f, const AxialSlice& s, double offset, double tan_helix, double rpm,
                                       I&& integral) {
  const double dz = s.height_m();
  const double theta = offset + (tan_helix == 0.0 ? 0.0 : tan_helix * s.lag_lo);
  const double rate = (tan_helix == 0.0 || !(dz > 0.0)) ? 0.0 : tan_helix * (s.lag_hi - s.lag_lo) / dz;
  return integral(Windowed(f, s.entry_rad, s.exit_rad), angular_speed_rad_per_s(rpm), theta, rate, dz);
}

// ∫∫ over the slice's height and [t_a, t_b].
template <class T>
typename Windowed<T>::Value slice_integral(const T& f, const AxialSlice& s, double offset, double tan_helix,
                                           double t_a, double t_b, double rpm) {
  return over_slice(f, s, offset, tan_helix, rpm, [&](const auto& w, double om, double th, double k, double dz) {
    return time_height_integral(w, om, th, k, t_a, t_b, dz);
  });
}

// ∫ over the slice's height at one instant t.
template <class T>
typename Windowed<T>::Value slice_height_integral(const T& f, const AxialSlice& s, double offset, double tan_helix,
                                                  double t, double rpm) {
  return over_slice(f, s, offset, tan_helix, rpm, [&](const auto& w, double om, double th, double k, double dz) {
    return height_integral(w, om, th, k, t, dz);
  });
}

}  // namespace

Eigen::Matrix2d Process::slice_force_rate(int j, const AxialSlice& s, double t, double rpm) const {
  if (!s.engaged) return Eigen::Matrix2d::Zero();
  return slice_height_integral(force_trig(milling_.tangential_coefficient_n_per_m2, s.radial_coefficient_n_per_m2), s,
                               tooth_offset_rad(j), tan_helix_[static_cast<std::size_t>(j)], t, rpm);
}

Eigen::Matrix2d Process::slice_force_integral(int j, const AxialSlice& s, double t_a, double t_b, double rpm) const {
  if (!s.engaged) return Eigen::Matrix2d::Zero();
  return slice_integral(force_trig(milling_.tangential_coefficient_n_per_m2, s.radial_coefficient_n_per_m2), s,
                        tooth_offset_rad(j), tan_helix_[static_cast<std::size_t>(j)], t_a, t_b, rpm);
}

Eigen::Vector2d Process::slice_force_direction_integral(int j, const AxialSlice& s, double t_a, double t_b,
                                                        double rpm) const {
  if (!s.engaged) return Eigen::Vector2d::Zero();
  return slice_integral(force_direction_trig(milling_.tangential_coefficient_n_per_m2, s.radial_coefficient_n_per_m2),
                        s, tooth_offset_rad(j), tan_helix_[static_cast<std::size_t>(j)], t_a, t_b, rpm);
}

bool Process::depth_dependent_force() const {
  return has_nose_radius() || (has_profile() && !(frozen_depth_m_ > 0.0));
}

Process Process::at_depth(double depth_m) const {
  if (has_nose_radius()) return with_chord_at(depth_m);
  Process p = *this;
  if (has_profile()) {
    if (!(depth_m > 0.0)) throw std::logic_error("at_depth: needs depth > 0");
    p.frozen_depth_m_ = depth_m;
  }
  return p;
}

Eigen::Matrix2d Process::average_directional_matrix_at(double depth_m) const {
  if (!has_profile()) return average_directional_matrix();
  if (!(depth_m > 0.0)) throw std::logic_error("average_directional_matrix_at: needs depth > 0");
  // (N_t / 2π a) Σ_slices dz ∫_{φ_en}^{φ_ex} H₁,κ dφ.
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  for (const AxialSlice& s : axial_slices(depth_m)) {
    if (!s.engaged) continue;
    const Trig2 f = force_trig(milling_.tangential_coefficient_n_per_m2, s.radial_coefficient_n_per_m2);
    sum += s.height_m() * (f.f1(s.exit_rad) - f.f1(s.entry_rad));
  }
  return milling_.teeth / (kTwoPi * depth_m) * sum;
}

std::vector<double> Process::profile_events_s(double rpm, double depth_m) const {
  // Straight teeth: every slice's entry and exit is a jump of its force (one
  // time per slice arc). A helix smears them into ramps: the entry and exit
  // of the lowest engaged edge point and of the top of the cut (for a
  // cylinder z = 0 and z = a, the flat cutter's events exactly).
  std::vector<double> out;
  const double omega = angular_speed_rad_per_s(rpm);
  const std::vector<AxialSlice> slices = axial_slices(depth_m);
  for (int j = 0; j < milling_.teeth; ++j) {
    const double tb = tan_helix_[static_cast<std::size_t>(j)];
    auto push = [&](double edge, double lag) { out.push_back((edge + tooth_offset_rad(j) + lag) / omega); };
    if (tb == 0.0) {
      for (const AxialSlice& s : slices)
        if (s.engaged) {
          push(s.entry_rad, 0.0);
          push(s.exit_rad, 0.0);
        }
      continue;
    }
    const auto first = std::find_if(slices.begin(), slices.end(), [](const AxialSlice& s) { return s.engaged; });
    if (first == slices.end()) continue;
    const AxialSlice& top = slices.back();
    for (const double edge : {first->entry_rad, first->exit_rad}) push(edge, tb * first->lag_lo);
    if (top.engaged)
      for (const double edge : {top.entry_rad, top.exit_rad}) push(edge, tb * top.lag_hi);
  }
  return out;
}

}  // namespace chatter
