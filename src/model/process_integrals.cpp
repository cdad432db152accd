// The exact integrals of a tooth's force and damping directions over time
// and height (the flat cutter; a profile sums its slices' integrals,
// process_profile.cpp): what sdm's steps, the forced response and the
// collocation nodes read (include/chatter/process.hpp).
#include <vector>

#include "chatter/kinematics.hpp"
#include "chatter/process.hpp"
#include "windowed_integral.hpp"

namespace chatter {
using namespace process_detail;
namespace {

// f(the windowed integrand of every engaged arc), summed (the arcs are
// disjoint: their integrals add; one arc: exactly f's).
template <class T, class F>
auto over_arcs(const T& trig, const std::vector<std::pair<double, double>>& arcs, F&& f) {
  auto sum = f(Windowed(trig, arcs[0].first, arcs[0].second));
  for (std::size_t k = 1; k < arcs.size(); ++k) sum += f(Windowed(trig, arcs[k].first, arcs[k].second));
  return sum;
}

}  // namespace

Eigen::Matrix2d Process::tooth_force_integral(int j, double t_a, double t_b, double a_m, double rpm) const {
  if (has_profile()) {
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
    if (a_m > 0.0)
      for (const AxialSlice& s : axial_slices(a_m)) sum += slice_force_integral(j, s, t_a, t_b, rpm);
    return sum;
  }
  return over_arcs(force_trig(milling_.tangential_coefficient_n_per_m2, milling_.radial_coefficient_n_per_m2), arcs_,
                   [&](const auto& w) { return time_height_integral(w, angular_speed_rad_per_s(rpm), tooth_offset_rad(j),
                                                                    helix_lag_rad_per_m(j), t_a, t_b, a_m); });
}

Eigen::Matrix2d Process::tooth_force_rate(int j, double t, double a_m, double rpm) const {
  if (has_profile()) {
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
    if (a_m > 0.0)
      for (const AxialSlice& s : axial_slices(a_m)) sum += slice_force_rate(j, s, t, rpm);
    return sum;
  }
  return over_arcs(force_trig(milling_.tangential_coefficient_n_per_m2, milling_.radial_coefficient_n_per_m2), arcs_,
                   [&](const auto& w) {
                     return height_integral(w, angular_speed_rad_per_s(rpm), tooth_offset_rad(j), helix_lag_rad_per_m(j),
                                            t, a_m);
                   });
}

Eigen::Vector2d Process::tooth_force_direction_integral(int j, double t_a, double t_b, double a_m,
                                                       double rpm) const {
  if (has_profile()) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    if (a_m > 0.0)
      for (const AxialSlice& s : axial_slices(a_m)) sum += slice_force_direction_integral(j, s, t_a, t_b, rpm);
    return sum;
  }
  return over_arcs(force_direction_trig(milling_.tangential_coefficient_n_per_m2, milling_.radial_coefficient_n_per_m2),
                   arcs_, [&](const auto& w) {
                     return time_height_integral(w, angular_speed_rad_per_s(rpm), tooth_offset_rad(j),
                                                 helix_lag_rad_per_m(j), t_a, t_b, a_m);
                   });
}

Eigen::Matrix2d Process::tooth_damping_integral(int j, double t_a, double t_b, double a_m, double rpm) const {
  return over_arcs(damping_trig(), arcs_, [&](const auto& w) {
    return time_height_integral(w, angular_speed_rad_per_s(rpm), tooth_offset_rad(j), helix_lag_rad_per_m(j), t_a, t_b,
                                a_m);
  });
}

Eigen::Matrix2d Process::tooth_damping_rate(int j, double t, double a_m, double rpm) const {
  return over_arcs(damping_trig(), arcs_, [&](const auto& w) {
    return height_integral(w, angular_speed_rad_per_s(rpm), tooth_offset_rad(j), helix_lag_rad_per_m(j), t, a_m);
  });
}

}  // namespace chatter
