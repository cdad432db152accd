#include "chatter/process.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "chatter/cutting_law.hpp"
#include "chatter/error.hpp"
#include "chatter/kinematics.hpp"
#include "windowed_integral.hpp"

namespace chatter {
using namespace process_detail;
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError(what);
}

std::string deg_text(double rad) {
  std::ostringstream os;
  os.precision(10);
  os << rad * 180.0 / std::numbers::pi << " deg";
  return os.str();
}

// Pitch angles must sum to 2π to this (rad): 1e-6 rad is 6e-5 deg, far
// below any drawing tolerance, far above the round-off of degrees → rad.
constexpr double kPitchSumTolerance = 1e-6;
// Helix angles below 90° by at least this (rad): tan β stays finite.
constexpr double kHelixMax = 0.5 * std::numbers::pi - 1e-6;

// With Kienzle's law, K_f and K_r are its tangents at the mean chip
// h₀ = f sin κ (kienzle.hpp): what the regenerative side reads.
void linearise_kienzle(TurningParameters& p) {
  if (!p.kienzle) return;
  const std::string why = p.kienzle->validate();
  require(why.empty(), why);
  const double h0 = p.kienzle->feed_m * std::sin(p.lead_angle_rad);
  p.feed_force_coefficient_n_per_m2 = p.kienzle->feed.tangent_n_per_m2(h0);
  p.radial_force_coefficient_n_per_m2 = p.kienzle->has_radial() ? p.kienzle->radial.tangent_n_per_m2(h0) : 0.0;
}

}  // namespace

InsertChord insert_chord(double kappa_r, double r, double a) {
  InsertChord c;
  if (!(a > 0.0)) {  // nothing engaged: the limit a → 0 of the direction
    c.lead_angle_rad = r > 0.0 ? 0.0 : kappa_r;
    c.nose_only = r > 0.0;
    return c;
  }
  const double s = lead_sin(kappa_r), co = lead_cos(kappa_r);
  if (r == 0.0) {
    c.width_m = a / s;
    c.lead_angle_rad = kappa_r;
    return c;
  }
  const double nose_height = r * (1.0 - co);  // where the arc meets the straight edge
  if (a <= nose_height) {
    // The arc from the tip (0, 0) to (r sin θ, r(1 − cos θ)), r(1 − cos θ) = a:
    // the chord is at θ/2 to X, of length 2 r sin(θ/2), sin(θ/2) = sqrt(a/2r).
    const double sh = std::sqrt(a / (2.0 * r));
    c.width_m = std::sqrt(2.0 * r * a);
    c.lead_angle_rad = std::asin(std::min(1.0, sh));
    c.nose_only = true;
    return c;
  }
  const double x_end = r * s + (a - nose_height) * co / s;
  c.width_m = std::hypot(x_end, a);
  c.lead_angle_rad = std::atan2(a, x_end);
  return c;
}

Process Process::turning(TurningParameters p) {
  require(std::isfinite(p.lead_angle_rad) && p.lead_angle_rad > 0.0 && p.lead_angle_rad <= kHalfPi,
          "lead angle " + deg_text(p.lead_angle_rad) + ": must be in (0, 90] deg");
  linearise_kienzle(p);
  require(std::isfinite(p.feed_force_coefficient_n_per_m2) && p.feed_force_coefficient_n_per_m2 > 0.0,
          "feed force coefficient K_f must be > 0 N/m^2");
  require(std::isfinite(p.radial_force_coefficient_n_per_m2) && p.radial_force_coefficient_n_per_m2 >= 0.0,
          "radial force coefficient K_r must be >= 0 N/m^2");
  require(std::isfinite(p.nose_radius_m) && p.nose_radius_m >= 0.0 && p.nose_radius_m <= kMaxNoseRadiusM,
          "nose radius must be in [0, 25] mm (round inserts reach 16 mm)");
  require(std::isfinite(p.process_damping_coefficient_n_per_m) && p.process_damping_coefficient_n_per_m >= 0.0,
          "process damping coefficient C_pd must be >= 0 N/m");
  require(std::isfinite(p.workpiece_diameter_m) && p.workpiece_diameter_m >= 0.0,
          "workpiece diameter must be >= 0 m (0 = not given)");
  require(p.process_damping_coefficient_n_per_m == 0.0 || p.workpiece_diameter_m > 0.0,
          "process damping needs the workpiece diameter (> 0 m) for the cutting speed V = pi D N / 60");
  Process pr;
  pr.operation_ = Operation::kTurning;
  pr.turning_ = p;
  return pr;
}

Process Process::milling(MillingParameters p) {
  require(p.teeth >= 1, "number of teeth must be >= 1");
  require(p.teeth <= kMaxTeeth, "number of teeth must be <= " + std::to_string(kMaxTeeth));
  require(std::isfinite(p.tangential_coefficient_n_per_m2) && p.tangential_coefficient_n_per_m2 > 0.0,
          "tangential coefficient K_t must be > 0 N/m^2");
  require(std::isfinite(p.radial_coefficient_n_per_m2) && p.radial_coefficient_n_per_m2 >= 0.0,
          "radial coefficient K_r must be >= 0 N/m^2");
  if (!p.engaged_arcs_rad.empty()) {
    double width = 0.0, last_exit = -1.0;
    for (const auto& [en, ex] : p.engaged_arcs_rad) {
      require(std::isfinite(en) && std::isfinite(ex) && en >= 0.0 && en < ex && ex <= std::numbers::pi,
              "engaged arc: must be 0 <= entry < exit <= 180 deg");
      require(en > last_exit, "engaged arcs: must be sorted and must not touch or overlap (merge them into one)");
      last_exit = ex;
      width += 0.5 * (std::cos(en) - std::cos(ex));
    }
    require(p.cutter.geometry == CutterGeometry::kFlat,
            "engaged arc: only for a flat cutter (a profile's slices take their arcs from a straight wall: give "
            "radial_immersion and direction)");
    p.radial_immersion = width;
  }
  require(std::isfinite(p.radial_immersion) && p.radial_immersion > 0.0 && p.radial_immersion <= 1.0,
          "radial immersion a_e/D must be in (0, 1]");
  require(std::isfinite(p.tool_diameter_m) && p.tool_diameter_m >= 0.0, "tool diameter must be >= 0 m (0 = not given)");
  const auto nt = static_cast<std::size_t>(p.teeth);
  const double radius = 0.5 * p.tool_diameter_m;
  Process pr;
  pr.operation_ = Operation::kMilling;
  pr.pitch_.assign(nt, kTwoPi / p.teeth);
  if (!p.pitch_angles_rad.empty()) {
    require(p.pitch_angles_rad.size() == nt, "pitch angles: " + std::to_string(p.pitch_angles_rad.size()) +
                                                 " given, need one per tooth (" + std::to_string(nt) + ")");
    double sum = 0.0;
    for (std::size_t j = 0; j < nt; ++j) {
      const double th = p.pitch_angles_rad[j];
      require(std::isfinite(th) && th > 0.0, "pitch angle of tooth " + std::to_string(j + 1) + " = " + deg_text(th) +
                                                 ": must be > 0");
      sum += th;
    }
    require(std::abs(sum - kTwoPi) <= kPitchSumTolerance,
            "pitch angles sum to " + deg_text(sum) + ": must sum to 360 deg (one revolution)");
    pr.pitch_ = p.pitch_angles_rad;
  }
  std::vector<double> helix(nt, 0.0);
  if (!p.helix_angles_rad.empty()) {
    require(p.helix_angles_rad.size() == 1 || p.helix_angles_rad.size() == nt,
            "helix angles: " + std::to_string(p.helix_angles_rad.size()) + " given, need 1 (every tooth) or one per tooth (" +
                std::to_string(nt) + ")");
    for (std::size_t j = 0; j < nt; ++j) {
      const double b = p.helix_angles_rad.size() == 1 ? p.helix_angles_rad[0] : p.helix_angles_rad[j];
      require(std::isfinite(b) && b >= 0.0 && b < kHelixMax,
              "helix angle " + deg_text(b) + ": must be in [0, 90) deg");
      helix[j] = b;
    }
  }
  const bool any_helix = std::any_of(helix.begin(), helix.end(), [](double b) { return b > 0.0; });
  require(!any_helix || radius > 0.0, "a helix needs the tool diameter (> 0 m)");
  require(std::isfinite(p.process_damping_coefficient_n_per_m) && p.process_damping_coefficient_n_per_m >= 0.0,
          "process damping coefficient C_pd must be >= 0 N/m");
  require(p.process_damping_coefficient_n_per_m == 0.0 || radius > 0.0,
          "process damping needs the tool diameter (> 0 m) for the cutting speed V = pi D N / 60");
  pr.runout_.assign(nt, 0.0);
  if (!p.runout_m.empty()) {
    require(p.runout_m.size() == nt, "runout: " + std::to_string(p.runout_m.size()) + " offsets given, need one per tooth (" +
                                         std::to_string(nt) + ")");
    for (std::size_t j = 0; j < nt; ++j) {
      const double r = p.runout_m[j];
      require(std::isfinite(r) && (radius == 0.0 || std::abs(r) < radius),
              "runout of tooth " + std::to_string(j + 1) + ": must be finite and smaller than the tool radius");
    }
    pr.runout_ = p.runout_m;
  }
  pr.offset_.assign(nt, 0.0);
  for (std::size_t j = 1; j < nt; ++j) pr.offset_[j] = pr.offset_[j - 1] + pr.pitch_[j];
  pr.lag_.assign(nt, 0.0);
  for (std::size_t j = 0; j < nt; ++j) pr.lag_[j] = helix[j] > 0.0 ? std::tan(helix[j]) / radius : 0.0;
  require(std::isfinite(p.axial_coefficient_n_per_m2) && p.axial_coefficient_n_per_m2 >= 0.0,
          "axial force coefficient K_a must be >= 0 N/m^2");
  pr.profile_ = CutterProfile::make(p.cutter, radius);
  if (!pr.profile_.flat()) {
    const std::string what = std::string("cutter_geometry = ") + to_string(p.cutter.geometry);
    require(p.process_damping_coefficient_n_per_m == 0.0,
            "process damping with " + what + " is not modelled (the flank contact of a curved edge): use a flat cutter "
            "or no process damping");
    require(!any_helix || pr.profile_.finite_lag(),
            "a helix on a general profile needs every radius > 0 (the lag tan(beta) / R(z) grows without bound at R = 0)");
    pr.tan_helix_.assign(nt, 0.0);
    for (std::size_t j = 0; j < nt; ++j) pr.tan_helix_[j] = helix[j] > 0.0 ? std::tan(helix[j]) : 0.0;
  }
  p.helix_angles_rad = helix;
  if (!any_helix) p.helix_angles_rad.clear();
  pr.milling_ = p;
  if (!p.engaged_arcs_rad.empty())
    pr.arcs_ = p.engaged_arcs_rad;
  else
    pr.arcs_ = {milling_arc_rad(p.radial_immersion, p.direction)};
  return pr;
}

double Process::compensation_diameter_m() const {
  return operation_ == Operation::kMilling ? milling_.tool_diameter_m : 2.0 * turning_.nose_radius_m;
}

bool Process::orthogonal_turning() const {
  return operation_ == Operation::kTurning && turning_.lead_angle_rad == kHalfPi && turning_.nose_radius_m == 0.0 &&
         turning_.radial_force_coefficient_n_per_m2 == 0.0;
}

bool Process::has_nose_radius() const { return operation_ == Operation::kTurning && turning_.nose_radius_m > 0.0; }

InsertChord Process::chord(double depth_m) const {
  return insert_chord(turning_.lead_angle_rad, turning_.nose_radius_m, depth_m);
}

Eigen::Vector2d Process::chip_direction(double depth_m) const {
  const double k = chord(depth_m).lead_angle_rad;
  return {lead_sin(k), lead_cos(k)};
}

namespace {
// K_f n + K_r e at the chord's lead angle κ, e = (−cos κ, sin κ).
Eigen::Vector2d edge_force_of(double k, double kf, double kr) {
  const double s = lead_sin(k), c = lead_cos(k);
  if (kr == 0.0) return {kf * s, kf * c};
  return {kf * s - kr * c, kf * c + kr * s};
}
}  // namespace

Eigen::Vector2d Process::edge_force(double depth_m) const {
  const double k = chord(depth_m).lead_angle_rad;
  const std::optional<KienzleLaw>& law = turning_.kienzle;
  const double h0 = law ? chip_thickness_m(depth_m, law->feed_m) : 0.0;
  // Sharp: the fields hold the tangents at f sin κ_r = f sin κ_eq. On the
  // nose at a → 0 (κ_eq → 0, no chip) they keep b d finite (→ 0).
  if (!law || !has_nose_radius() || !(h0 > 0.0))
    return edge_force_of(k, turning_.feed_force_coefficient_n_per_m2, turning_.radial_force_coefficient_n_per_m2);
  return edge_force_of(k, law->feed.tangent_n_per_m2(h0), law->has_radial() ? law->radial.tangent_n_per_m2(h0) : 0.0);
}

double Process::chip_thickness_m(double depth_m, double feed_per_rev_m) const {
  return feed_per_rev_m * lead_sin(chord(depth_m).lead_angle_rad);
}

Eigen::Vector2d Process::secant_edge_force(double depth_m, double chip_m) const {
  const double k = chord(depth_m).lead_angle_rad;
  const std::optional<KienzleLaw>& law = turning_.kienzle;
  if (!law)
    return edge_force_of(k, turning_.feed_force_coefficient_n_per_m2, turning_.radial_force_coefficient_n_per_m2);
  return edge_force_of(k, law->feed.secant_n_per_m2(chip_m),
                       law->has_radial() ? law->radial.secant_n_per_m2(chip_m) : 0.0);
}

bool Process::has_size_effect() const { return operation_ == Operation::kTurning && turning_.kienzle.has_value(); }

Process Process::at_feed(double feed_per_rev_m) const {
  if (!has_size_effect() || feed_per_rev_m == turning_.kienzle->feed_m) return *this;
  TurningParameters p = turning_;
  p.kienzle->feed_m = feed_per_rev_m;
  Process out = Process::turning(p);
  out.set_speed_variation(speed_variation());
  return out;
}

Eigen::Matrix2d Process::turning_matrix(double depth_m) const {
  if (orthogonal_turning()) {
    Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
    h(0, 0) = turning_.feed_force_coefficient_n_per_m2;
    return h;
  }
  if (has_nose_radius() && !(depth_m > 0.0))
    throw std::logic_error("turning_matrix: with a nose radius H depends on the depth; needs depth > 0");
  const double s = lead_sin(chord(depth_m).lead_angle_rad);
  return edge_force(depth_m) * chip_direction(depth_m).transpose() / s;
}

Eigen::Matrix2d Process::turning_force_matrix(double depth_m) const {
  if (!has_nose_radius()) return depth_m * turning_matrix(depth_m);
  return chord(depth_m).width_m * edge_force(depth_m) * chip_direction(depth_m).transpose();
}

Eigen::Matrix2d Process::turning_damping_matrix(double depth_m) const {
  const Eigen::Vector2d n = chip_direction(depth_m);
  return chord(depth_m).width_m * n * n.transpose();
}

Process Process::with_chord_at(double depth_m) const {
  if (!has_nose_radius()) return *this;
  if (!(depth_m > 0.0)) throw std::logic_error("with_chord_at: needs depth > 0");
  Process p = *this;
  p.turning_.lead_angle_rad = chord(depth_m).lead_angle_rad;
  p.turning_.nose_radius_m = 0.0;
  linearise_kienzle(p.turning_);  // the tangents at f sin κ_eq, as edge_force(a) takes them
  return p;
}

int Process::teeth() const { return operation_ == Operation::kTurning ? 1 : milling_.teeth; }

bool Process::has_helix() const {
  return std::any_of(lag_.begin(), lag_.end(), [](double k) { return k > 0.0; });
}

bool Process::has_variable_pitch() const {
  return std::any_of(pitch_.begin(), pitch_.end(), [&](double th) { return th != pitch_.front(); });
}

bool Process::has_variable_helix() const {
  return std::any_of(lag_.begin(), lag_.end(), [&](double k) { return k != lag_.front(); });
}

bool Process::has_runout() const {
  return std::any_of(runout_.begin(), runout_.end(), [](double r) { return r != 0.0; });
}

bool Process::has_process_damping() const {
  return (operation_ == Operation::kTurning ? turning_.process_damping_coefficient_n_per_m
                                            : milling_.process_damping_coefficient_n_per_m) > 0.0;
}

bool Process::uniform_cutter() const {
  return operation_ == Operation::kTurning || (!has_variable_pitch() && !has_variable_helix());
}

double Process::period_s(double rpm) const { return uniform_cutter() ? delay_s(rpm) : revolution_s(rpm); }

double Process::tooth_passing_hz(double rpm) const { return chatter::tooth_passing_hz(rpm, delays_per_revolution()); }

int Process::repeat_teeth(bool with_runout) const {
  if (operation_ == Operation::kTurning) return 1;
  const int nt = milling_.teeth;
  for (int r = 1; r < nt; ++r) {
    if (nt % r != 0) continue;
    bool repeats = true;
    for (int j = 0; j < nt && repeats; ++j) {
      const int k = (j + r) % nt;
      repeats = pitch_angle_rad(j) == pitch_angle_rad(k) && helix_lag_rad_per_m(j) == helix_lag_rad_per_m(k) &&
                (!with_runout || runout_m(j) == runout_m(k));
    }
    if (repeats) return r;
  }
  return nt;
}

double Process::floquet_period_s(double rpm, bool with_runout) const {
  const int r = repeat_teeth(with_runout);
  return r == teeth() && r > 1 ? revolution_s(rpm) : delay_s(rpm) * r;
}

double Process::pitch_angle_rad(int j) const { return pitch_[static_cast<std::size_t>(j)]; }
double Process::tooth_offset_rad(int j) const { return offset_[static_cast<std::size_t>(j)]; }
double Process::helix_angle_rad(int j) const {
  const auto& h = milling_.helix_angles_rad;
  return h.empty() ? 0.0 : h[static_cast<std::size_t>(j)];
}
double Process::runout_m(int j) const { return runout_[static_cast<std::size_t>(j)]; }
double Process::helix_lag_rad_per_m(int j) const { return lag_[static_cast<std::size_t>(j)]; }

double Process::tooth_angle_rad(int j, double t_s, double z_m, double rpm) const {
  if (has_profile()) return angular_speed_rad_per_s(rpm) * t_s - tooth_offset_rad(j) - helix_lag_rad(j, z_m);
  return angular_speed_rad_per_s(rpm) * t_s - tooth_offset_rad(j) - z_m * helix_lag_rad_per_m(j);
}

double Process::tooth_delay_s(int j, double z_m, double rpm) const {
  const int prev = (j + milling_.teeth - 1) % milling_.teeth;
  if (has_profile())
    return (pitch_angle_rad(j) + helix_lag_rad(j, z_m) - helix_lag_rad(prev, z_m)) / (angular_speed_rad_per_s(rpm));
  return (pitch_angle_rad(j) + z_m * (helix_lag_rad_per_m(j) - helix_lag_rad_per_m(prev))) / (angular_speed_rad_per_s(rpm));
}

std::vector<double> Process::arc_edges_rad() const {
  std::vector<double> edges;
  for (const auto& [en, ex] : arcs_) edges.insert(edges.end(), {en, ex});
  return edges;
}

bool Process::in_cut(double phi) const {
  phi = std::fmod(phi, kTwoPi);
  if (phi < 0.0) phi += kTwoPi;
  for (const auto& [en, ex] : arcs_)
    if (phi >= en && phi <= ex) return true;
  return false;
}

Eigen::Matrix2d Process::damping_direction(double phi) {
  const double s = std::sin(phi), c = std::cos(phi);
  Eigen::Matrix2d m;
  m << s * s, s * c, s * c, c * c;
  return m;
}

double Process::process_damping_per_depth(double rpm) const {
  const bool turning = operation_ == Operation::kTurning;
  const double c = turning ? turning_.process_damping_coefficient_n_per_m : milling_.process_damping_coefficient_n_per_m;
  if (c == 0.0) return 0.0;
  const double d = turning ? turning_.workpiece_diameter_m : milling_.tool_diameter_m;
  return c / cutting_speed_m_per_s(d, rpm);
}

Eigen::Matrix2d Process::average_damping_direction() const {
  if (operation_ == Operation::kTurning) {
    if (orthogonal_turning()) {
      Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
      m(0, 0) = 1.0;
      return m;
    }
    if (has_nose_radius())
      throw std::logic_error("average_damping_direction: with a nose radius it depends on the depth");
    return turning_damping_matrix(1.0);  // b n nᵀ at a = 1 m: (b/a) n nᵀ
  }
  const Trig2 t = damping_trig();
  Eigen::Matrix2d integral = t.f1(arcs_[0].second) - t.f1(arcs_[0].first);
  for (std::size_t k = 1; k < arcs_.size(); ++k) integral += t.f1(arcs_[k].second) - t.f1(arcs_[k].first);
  return milling_.teeth / kTwoPi * integral;
}

std::vector<double> Process::engagement_events_s(double rpm, double depth_m) const {
  std::vector<double> out;
  if (operation_ == Operation::kTurning) return out;
  const double omega = angular_speed_rad_per_s(rpm), period = period_s(rpm);
  if (has_profile()) {
    out = profile_events_s(rpm, depth_m);
    for (double& t : out) {
      t = std::fmod(t, period);
      if (t < 0.0) t += period;
      if (period - t <= 1e-12 * period) t = 0.0;
    }
  }
  for (int j = 0; j < milling_.teeth && !has_profile(); ++j) {
    for (const double edge : arc_edges_rad()) {
      for (const double z : {0.0, depth_m}) {
        // φ_j(t, z) = edge (mod 2π) → t = (edge + Θ_j + κ z) / Ω (mod period)
        double t = std::fmod((edge + tooth_offset_rad(j) + z * helix_lag_rad_per_m(j)) / omega, period);
        if (t < 0.0) t += period;
        if (period - t <= 1e-12 * period) t = 0.0;  // = the next period's start
        out.push_back(t);
        if (helix_lag_rad_per_m(j) == 0.0) break;
      }
    }
  }
  std::sort(out.begin(), out.end());
  std::vector<double> merged;
  for (const double t : out)
    if (merged.empty() || t - merged.back() > 1e-12 * period) merged.push_back(t);
  return merged;
}

Eigen::Vector2d Process::force_direction(double phi) const {
  const double kt = milling_.tangential_coefficient_n_per_m2;
  const double kr = milling_.radial_coefficient_n_per_m2;
  return milling_force_direction(kt, kr, std::sin(phi), std::cos(phi));
}

double Process::feed_of_tooth_m(int j, double feed_per_tooth_m) const {
  if (operation_ == Operation::kTurning) return feed_per_tooth_m;
  return milling_.teeth * feed_per_tooth_m * pitch_angle_rad(j) / kTwoPi;
}

double Process::static_chip_m(int j, double phi, double feed_per_tooth_m) const {
  const int nt = teeth();
  if (operation_ == Operation::kTurning) return std::max(0.0, feed_per_tooth_m);
  const double s = std::sin(phi);
  double best = std::numeric_limits<double>::infinity();
  double swept = 0.0;  // θ_j + … + θ_{j−k+1}
  for (int k = 1; k <= nt; ++k) {
    const int cur = ((j - k + 1) % nt + nt) % nt, prev = ((j - k) % nt + nt) % nt;
    swept += pitch_angle_rad(cur);
    const double advance = nt * feed_per_tooth_m * swept / kTwoPi;
    best = std::min(best, advance * s + runout_m(j) - runout_m(prev));
  }
  return std::max(0.0, best);
}

int Process::delays_per_revolution() const {
  return operation_ == Operation::kTurning ? 1 : milling_.teeth;
}

double Process::delay_s(double rpm) const { return tooth_period_s(rpm, delays_per_revolution()); }

double Process::rpm_from_delay(double tau_s) const { return rpm_from_tooth_period(tau_s, delays_per_revolution()); }


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
    if (has_nose_radius())
      throw std::logic_error("directional_matrix: with a nose radius H depends on the depth (turning_matrix)");
    return turning_matrix(1.0);
  }
  const double omega = angular_speed_rad_per_s(rpm);
  Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
  for (int j = 0; j < milling_.teeth; ++j) {
    double phi = std::fmod(omega * t_s + kTwoPi * j / milling_.teeth, kTwoPi);
    if (phi < 0.0) phi += kTwoPi;
    for (const auto& [en, ex] : arcs_)
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
  if (has_profile()) {
    if (!(frozen_depth_m_ > 0.0))
      throw std::logic_error("average_directional_matrix: with a cutter profile H0 depends on the depth "
                             "(average_directional_matrix_at, or at_depth)");
    return average_directional_matrix_at(frozen_depth_m_);
  }
  Eigen::Matrix2d integral = tooth_matrix_antiderivative(arcs_[0].second) - tooth_matrix_antiderivative(arcs_[0].first);
  for (std::size_t k = 1; k < arcs_.size(); ++k)
    integral += tooth_matrix_antiderivative(arcs_[k].second) - tooth_matrix_antiderivative(arcs_[k].first);
  return milling_.teeth / kTwoPi * integral;
}

std::string_view operation_name(Operation op) { return op == Operation::kMilling ? "milling" : "turning"; }

Operation operation_named(std::string_view name) {
  if (name == "milling") return Operation::kMilling;
  if (name == "turning") return Operation::kTurning;
  throw InputError("operation \"" + std::string(name) + "\": must be \"turning\" or \"milling\"");
}

bool rotating_edges(Operation op) { return op == Operation::kMilling; }

std::string_view feed_record_key(Operation op) {
  return op == Operation::kMilling ? "feed_per_tooth_mm" : "feed_mm_per_rev";
}

std::string_view feed_basis(Operation op) { return op == Operation::kMilling ? "tooth" : "revolution"; }

}  // namespace chatter
