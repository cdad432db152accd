// The turned bar's radius profile (chatter/stock.hpp, docs/program.md
// "Turning: the bar").
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/stock.hpp"

namespace chatter {
namespace {

constexpr double kMaxCells = 1e7;

}  // namespace

BarStock::BarStock(double diameter_mm, double length_mm, double face_z_mm, double resolution_mm) {
  if (!(std::isfinite(diameter_mm) && diameter_mm > 0.0))
    throw InputError("stock.diameter_mm = " + number_text(diameter_mm) + ": must be > 0");
  if (!(std::isfinite(length_mm) && length_mm > 0.0))
    throw InputError("stock.length_mm = " + number_text(length_mm) + ": must be > 0");
  if (!std::isfinite(face_z_mm)) throw InputError("stock.face_z_mm: must be finite");
  if (!(std::isfinite(resolution_mm) && resolution_mm > 0.0))
    throw InputError("stock.resolution_mm = " + number_text(resolution_mm) + ": must be > 0");
  const double cells = std::ceil(length_mm / resolution_mm - 1e-9);
  if (cells > kMaxCells)
    throw InputError("stock.resolution_mm = " + number_text(resolution_mm) + ": " + number_text(cells) +
                     " cells along the bar, more than 10^7: use a coarser resolution");
  const auto n = static_cast<std::size_t>(std::max(1.0, cells));
  z0_ = face_z_mm - length_mm;
  length_ = length_mm;
  dz_ = length_mm / static_cast<double>(n);  // the cells tile the bar exactly
  r_.assign(n, 0.5 * diameter_mm);
}

long BarStock::cell(double z_mm) const {
  const double u = (z_mm - z0_) / dz_;
  if (u < 0.0) return -1;
  if (u >= static_cast<double>(r_.size())) return static_cast<long>(r_.size());
  return static_cast<long>(u);
}

double BarStock::radius_at(double z_mm) const {
  const long i = cell(z_mm);
  if (i < 0 || i >= static_cast<long>(r_.size())) return 0.0;
  return r_[static_cast<std::size_t>(i)];
}

TurningEngagement BarStock::engagement(double z_mm, double x_mm, double dz, double dx) const {
  TurningEngagement e;
  e.facing = std::abs(dx) > std::abs(dz);
  const long n = static_cast<long>(r_.size());
  if (!e.facing) {
    const double r = radius_at(z_mm);
    e.diameter_mm = 2.0 * r;
    e.depth_mm = std::max(0.0, r - x_mm);
    return e;
  }
  // Facing: the material at radius x beyond the nose toward the face.
  long i = std::max(0L, cell(z_mm));
  if (i >= n) return e;
  const double first_r = r_[static_cast<std::size_t>(i)];
  if (!(first_r > std::max(x_mm, 0.0))) return e;
  e.diameter_mm = 2.0 * first_r;
  const double from = std::max(z_mm, z0_);
  long j = i;
  while (j < n && r_[static_cast<std::size_t>(j)] > std::max(x_mm, 0.0)) ++j;
  e.depth_mm = std::max(0.0, z0_ + static_cast<double>(j) * dz_ - from);
  return e;
}

double BarStock::sweep(const std::vector<Eigen::Vector2d>& points) {
  const std::size_t n = r_.size();
  std::vector<double> cap(n, std::numeric_limits<double>::infinity());
  // r(z') <- min(r(z'), x_p) for every path point p with z_p <= z' (the
  // tool's quadrant): per segment the smallest x over its part at or below
  // the cell's centre, which is at an end of that part (x is linear in z).
  for (std::size_t s = 0; s < points.size(); ++s) {
    const Eigen::Vector2d a = points[s];
    const Eigen::Vector2d b = s + 1 < points.size() ? points[s + 1] : points[s];
    const double zlo = std::min(a.x(), b.x());
    const long first = std::max(0L, cell(zlo));
    for (long i = first; i < static_cast<long>(n); ++i) {
      const double zc = z0_ + (static_cast<double>(i) + 0.5) * dz_;
      if (zc < zlo) continue;
      double m = std::numeric_limits<double>::infinity();
      if (a.x() <= zc) m = std::min(m, a.y());
      if (b.x() <= zc) m = std::min(m, b.y());
      if ((a.x() - zc) * (b.x() - zc) < 0.0) {  // the segment crosses the centre's z
        const double t = (zc - a.x()) / (b.x() - a.x());
        m = std::min(m, a.y() + t * (b.y() - a.y()));
      }
      cap[static_cast<std::size_t>(i)] = std::min(cap[static_cast<std::size_t>(i)], m);
    }
  }
  double removed = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r_new = std::max(0.0, std::min(r_[i], cap[i]));
    removed += std::numbers::pi * (r_[i] * r_[i] - r_new * r_new) * dz_;
    r_[i] = r_new;
  }
  return removed;
}

double BarStock::volume_mm3() const {
  double v = 0.0;
  for (const double r : r_) v += std::numbers::pi * r * r * dz_;
  return v;
}

}  // namespace chatter
