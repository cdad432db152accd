// The cutter's shape along its axis (include/chatter/cutter_profile.hpp,
// docs/cutter_geometry.md): radius, lead angle and helix lag integral of a
// ball end, a bull nose or a tabulated profile, and a slice's engagement.
#include "chatter/cutter_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "chatter/error.hpp"

namespace chatter {
namespace {

constexpr double kHalfPi = 0.5 * std::numbers::pi;

std::string mm(double m) {
  std::ostringstream os;
  os.precision(10);
  os << m * 1e3 << " mm";
  return os.str();
}

// Corner of a bull nose (torus) of corner radius r and R₀ = c + r: with κ
// the lead angle, z = r (1 − cos κ), R = c + r sin κ, dz = r sin κ dκ, so
//   Λ(κ) = ∫₀^κ r sin k / (c + r sin k) dk = κ − c I(κ),
//   I(κ) = ∫₀^κ dk / (c + r sin k),
// in closed form with t = tan(k/2): I = ∫ 2 dt / (c t² + 2 r t + c).
double corner_lag(double kappa, double c, double r) {
  if (c == 0.0) return kappa;  // a ball: Λ = κ
  const double t = std::tan(0.5 * kappa);
  double I = 0.0;
  if (r > c) {  // real roots t± = (−r ± s)/c, both < 0
    const double s = std::sqrt((r - c) * (r + c));
    const double tp = (-r + s) / c, tm = (-r - s) / c;
    I = std::log((t - tp) * tm / ((t - tm) * tp)) / s;
  } else if (r < c) {
    const double s = std::sqrt((c - r) * (c + r));
    I = 2.0 / s * (std::atan((c * t + r) / s) - std::atan(r / s));
  } else {
    I = 2.0 / c * t / (1.0 + t);
  }
  return kappa - c * I;
}

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError(what);
}

}  // namespace

const char* to_string(CutterGeometry g) {
  switch (g) {
    case CutterGeometry::kFlat: return "flat";
    case CutterGeometry::kBall: return "ball";
    case CutterGeometry::kBullNose: return "bull_nose";
    case CutterGeometry::kGeneral: return "general";
  }
  return "?";
}

SliceEngagement slice_engagement(double r, double r0, double immersion, bool down) {
  SliceEngagement e;
  if (!(r > 0.0)) return e;
  // The band's inner edge as a cosine on this slice's circle.
  const double c = (down ? 2.0 * immersion - 1.0 : 1.0 - 2.0 * immersion) * (r0 / r);
  if (down) {  // cuts where cos φ <= c
    if (c <= -1.0) return e;  // the circle does not reach the band
    e.entry_rad = c >= 1.0 ? 0.0 : std::acos(c);
    e.exit_rad = std::numbers::pi;
  } else {  // cuts where cos φ >= c
    if (c >= 1.0) return e;
    e.entry_rad = 0.0;
    e.exit_rad = c <= -1.0 ? std::numbers::pi : std::acos(c);
  }
  e.engaged = true;
  return e;
}

CutterProfile CutterProfile::make(const CutterProfileParameters& p, double r0) {
  CutterProfile cp;
  cp.p_ = p;
  cp.r0_ = r0;
  require(p.slices >= 0 && p.slices <= kMaxProfileSlices,
          "profile slices = " + std::to_string(p.slices) + ": must be in [0, " + std::to_string(kMaxProfileSlices) +
              "] (0 = " + std::to_string(kDefaultProfileSlices) + ")");
  if (p.geometry == CutterGeometry::kFlat) return cp;
  require(std::isfinite(r0) && r0 > 0.0,
          std::string("cutter_geometry = ") + to_string(p.geometry) + " needs the tool diameter (> 0 m)");
  if (p.geometry == CutterGeometry::kBall) {
    cp.p_.corner_radius_m = r0;
    return cp;
  }
  if (p.geometry == CutterGeometry::kBullNose) {
    require(std::isfinite(p.corner_radius_m) && p.corner_radius_m > 0.0 && p.corner_radius_m <= r0,
            "corner radius " + mm(p.corner_radius_m) + ": must be in (0, D/2 = " + mm(r0) + "] (D/2 = a ball)");
    return cp;
  }
  const auto& rows = p.profile;
  require(rows.size() >= 2, "profile: " + std::to_string(rows.size()) + " rows given, need at least 2");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ProfilePoint& q = rows[i];
    const std::string at = "profile row " + std::to_string(i) + ": ";
    require(std::isfinite(q.height_m) && (i > 0 || q.height_m == 0.0), at + "the first height must be 0 (the tip)");
    require(i == 0 || q.height_m > rows[i - 1].height_m,
            at + "height " + mm(q.height_m) + ": heights must increase from the tip");
    require(std::isfinite(q.radius_m) && q.radius_m >= 0.0 && q.radius_m <= r0 * (1.0 + 1e-12),
            at + "radius " + mm(q.radius_m) + ": must be in [0, D/2 = " + mm(r0) + "]");
    require(std::isfinite(q.lead_angle_rad) && q.lead_angle_rad >= 0.0 && q.lead_angle_rad <= kHalfPi,
            at + "lead angle must be in [0, 90] deg");
  }
  cp.lag_at_row_.assign(rows.size(), 0.0);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double r1 = rows[i - 1].radius_m, r2 = rows[i].radius_m, dz = rows[i].height_m - rows[i - 1].height_m;
    double d = 0.0;  // ∫ dz / R over the segment, R linear
    if (r1 == 0.0 || r2 == 0.0) d = std::numeric_limits<double>::infinity();
    else if (r1 == r2) d = dz / r1;
    else d = dz * std::log(r2 / r1) / (r2 - r1);
    cp.lag_at_row_[i] = cp.lag_at_row_[i - 1] + d;
  }
  return cp;
}

bool CutterProfile::finite_lag() const {
  if (p_.geometry != CutterGeometry::kGeneral) return true;
  return std::all_of(p_.profile.begin(), p_.profile.end(), [](const ProfilePoint& q) { return q.radius_m > 0.0; });
}

namespace {
// Index i of the segment [row i, row i+1] holding z (general profile), or the
// last row when z is above it.
std::size_t segment_of(const std::vector<ProfilePoint>& rows, double z) {
  const auto it = std::upper_bound(rows.begin(), rows.end(), z,
                                   [](double v, const ProfilePoint& q) { return v < q.height_m; });
  return static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - rows.begin()) - 1));
}
}  // namespace

double CutterProfile::radius_m(double z) const {
  switch (p_.geometry) {
    case CutterGeometry::kFlat: return r0_;
    case CutterGeometry::kBall:
    case CutterGeometry::kBullNose: {
      const double rc = p_.corner_radius_m;
      if (z >= rc) return r0_;
      const double u = rc - z;  // R = R₀ − r_c + sqrt(r_c² − (r_c − z)²)
      return r0_ - rc + std::sqrt(std::max(0.0, (rc - u) * (rc + u)));
    }
    case CutterGeometry::kGeneral: {
      const auto& rows = p_.profile;
      const std::size_t i = segment_of(rows, z);
      if (i + 1 >= rows.size()) return rows.back().radius_m;
      const double s = (z - rows[i].height_m) / (rows[i + 1].height_m - rows[i].height_m);
      return rows[i].radius_m + s * (rows[i + 1].radius_m - rows[i].radius_m);
    }
  }
  return r0_;
}

double CutterProfile::lead_angle_rad(double z) const {
  switch (p_.geometry) {
    case CutterGeometry::kFlat: return kHalfPi;
    case CutterGeometry::kBall:
    case CutterGeometry::kBullNose: {
      const double rc = p_.corner_radius_m;
      if (z >= rc) return kHalfPi;
      return std::acos(std::clamp(1.0 - z / rc, 0.0, 1.0));  // z = r_c (1 − cos κ)
    }
    case CutterGeometry::kGeneral: {
      const auto& rows = p_.profile;
      const std::size_t i = segment_of(rows, z);
      if (i + 1 >= rows.size()) return rows.back().lead_angle_rad;
      if (rows[i].lead_angle_rad == rows[i + 1].lead_angle_rad) return rows[i].lead_angle_rad;  // 90 stays exact
      const double s = (z - rows[i].height_m) / (rows[i + 1].height_m - rows[i].height_m);
      return rows[i].lead_angle_rad + s * (rows[i + 1].lead_angle_rad - rows[i].lead_angle_rad);
    }
  }
  return kHalfPi;
}

double CutterProfile::lag_integral(double z) const {
  switch (p_.geometry) {
    case CutterGeometry::kFlat: return z / r0_;
    case CutterGeometry::kBall:
    case CutterGeometry::kBullNose: {
      const double rc = p_.corner_radius_m, c = r0_ - rc;
      if (z >= rc) return corner_lag(kHalfPi, c, rc) + (z - rc) / r0_;
      return corner_lag(lead_angle_rad(z), c, rc);
    }
    case CutterGeometry::kGeneral: {
      const auto& rows = p_.profile;
      const std::size_t i = segment_of(rows, z);
      const double z0 = rows[i].height_m, r1 = rows[i].radius_m;
      if (i + 1 >= rows.size()) return lag_at_row_[i] + (z - z0) / r1;
      if (z == z0) return lag_at_row_[i];
      const double r2 = radius_m(z);
      if (r1 == 0.0 || r2 == 0.0) return std::numeric_limits<double>::infinity();
      if (r1 == r2) return lag_at_row_[i] + (z - z0) / r1;
      return lag_at_row_[i] + (z - z0) * std::log(r2 / r1) / (r2 - r1);
    }
  }
  return z / r0_;
}

}  // namespace chatter
