// The milled stock as a height field (chatter/stock.hpp, docs/program.md
// "Milling: the Z-map").
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "chatter/error.hpp"
#include "chatter/number_text.hpp"
#include "chatter/stock.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMaxCells = 4e8;
// Heights within this of the envelope are not contact (float storage).
constexpr double kContactEpsMm = 1e-6;
// The leading half's angles are binned per degree to see a gap between two
// arcs (ZMapStock::cut's `split`).
constexpr int kArcBins = 180;

// Per 1° bin of the leading half: the smallest and largest angle of
// material met there (contact cells and the rim band), NaN = none.
struct ArcBins {
  std::array<float, kArcBins> lo, hi;
  ArcBins() {
    lo.fill(std::numeric_limits<float>::quiet_NaN());
    hi.fill(std::numeric_limits<float>::quiet_NaN());
  }
  void mark(double phi) {
    const auto b = static_cast<std::size_t>(std::clamp(static_cast<int>(phi / kPi * kArcBins), 0, kArcBins - 1));
    const auto f = static_cast<float>(phi);
    if (std::isnan(lo[b]) || f < lo[b]) lo[b] = f;
    if (std::isnan(hi[b]) || f > hi[b]) hi[b] = f;
  }
  // The arcs from `entry` to `exit` (rad): a gap of more than `allowed`
  // empty bins (the cells' angular spacing at the rim) splits them, one arc
  // per run of material.
  std::vector<std::pair<double, double>> arcs(double entry, double exit, int allowed) const {
    std::vector<std::pair<double, double>> out;
    const int first = std::max(static_cast<int>(entry / kPi * kArcBins), 0);
    const int last = std::min(static_cast<int>(exit / kPi * kArcBins), kArcBins - 1);
    int run = 0;
    double start = entry, end = entry;  // the current arc's start, its last material
    for (int b = first; b <= last; ++b) {
      const auto k = static_cast<std::size_t>(b);
      if (std::isnan(lo[k])) {
        ++run;
        continue;
      }
      if (run > allowed) {  // a gap behind: close the arc before it
        out.emplace_back(start, end);
        start = lo[k];
      }
      run = 0;
      end = hi[k];
    }
    out.emplace_back(start, exit);
    return out;
  }
};

}  // namespace

double MillShape::envelope_mm(double rho) const {
  const double rc = corner_radius_mm;
  if (rc <= 0.0) return 0.0;
  const double flat = radius_mm - rc;  // radius of the flat bottom
  if (rho <= flat) return 0.0;
  const double u = std::min(rho - flat, rc);
  return rc - std::sqrt(std::max(0.0, rc * rc - u * u));
}

ZMapStock::ZMapStock(const Eigen::Vector3d& min_mm, const Eigen::Vector3d& max_mm, double resolution_mm)
    : min_(min_mm), max_(max_mm), h_(resolution_mm) {
  for (int k = 0; k < 3; ++k)
    if (!(std::isfinite(min_mm[k]) && std::isfinite(max_mm[k]) && max_mm[k] > min_mm[k]))
      throw InputError("stock: max_mm[" + std::to_string(k) + "] = " + number_text(max_mm[k]) + ": must be > min_mm[" +
                       std::to_string(k) + "] (" + number_text(min_mm[k]) + ")");
  if (!(std::isfinite(resolution_mm) && resolution_mm > 0.0))
    throw InputError("stock.resolution_mm = " + number_text(resolution_mm) + ": must be > 0");
  const double cx = std::ceil((max_mm.x() - min_mm.x()) / h_ - 1e-9), cy = std::ceil((max_mm.y() - min_mm.y()) / h_ - 1e-9);
  if (cx * cy > kMaxCells)
    throw InputError("stock.resolution_mm = " + number_text(resolution_mm) + ": " + number_text(cx * cy) +
                     " cells, more than 4e8: use a coarser resolution");
  nx_ = static_cast<int>(std::max(1.0, cx));
  ny_ = static_cast<int>(std::max(1.0, cy));
  top_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), static_cast<float>(max_mm.z()));
}

double ZMapStock::height_at(double x, double y) const {
  const double u = (x - min_.x()) / h_, v = (y - min_.y()) / h_;
  if (u < 0 || v < 0 || u >= nx_ || v >= ny_) return min_.z();
  return top_[static_cast<std::size_t>(static_cast<int>(v)) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(static_cast<int>(u))];
}

double ZMapStock::volume_mm3() const {
  double v = 0.0;
  for (const float t : top_) v += std::max(0.0, static_cast<double>(t) - min_.z());
  return v * h_ * h_;  // the cells cover the box rounded up to whole cells
}

MillingEngagement ZMapStock::cut(const Eigen::Vector3d& tip, const Eigen::Vector2d& feed_xy, const MillShape& tool,
                                 bool clockwise) {
  MillingEngagement e;
  const double R = tool.radius_mm;
  e.plunge = !(feed_xy.squaredNorm() > 0.0);
  const Eigen::Vector2d f = e.plunge ? Eigen::Vector2d(1.0, 0.0) : feed_xy;
  // n̂ = ẑ × f̂, 90° left of the feed; φ clockwise from it (M3), mirrored for M4.
  const Eigen::Vector2d n(-f.y(), f.x());
  const double side = clockwise ? 1.0 : -1.0;
  // The disk, and a rim band 1.5 cells wide outside it: material there on
  // the leading half is what the cutting edge meets at its rim (a step of one
  // cell cuts only a thin crescent inside the disk, none near 0° and 180°).
  const double band = R + 1.5 * h_;
  const int i0 = std::max(0, static_cast<int>(std::floor((tip.x() - band - min_.x()) / h_)));
  const int i1 = std::min(nx_ - 1, static_cast<int>(std::floor((tip.x() + band - min_.x()) / h_)));
  const int j0 = std::max(0, static_cast<int>(std::floor((tip.y() - band - min_.y()) / h_)));
  const int j1 = std::min(ny_ - 1, static_cast<int>(std::floor((tip.y() + band - min_.y()) / h_)));
  const double rim_z = std::max(min_.z(), tip.z() + tool.envelope_mm(R)), band2 = band * band;
  const double floor_z = min_.z(), area = h_ * h_;
  double top_max = -std::numeric_limits<double>::infinity();
  double phi_min = kPi, phi_max = 0.0;
  bool leading = false;
  double rim_lo = kPi, rim_hi = 0.0;  // the rim band's material on the leading half
  ArcBins bins;
  const double r2 = R * R;
  // Every envelope and the rim lie at or above z_low: a cell at or below it
  // (most of the disk once the first pass has been) is skipped on one compare.
  const double z_low = std::max(floor_z, tip.z()) + kContactEpsMm;
  for (int j = j0; j <= j1; ++j) {
    const double dy = min_.y() + (j + 0.5) * h_ - tip.y();
    if (dy * dy > band2) continue;
    // The band's chord on this row, one cell wider each side for rounding.
    const double half = std::sqrt(band2 - dy * dy);
    const int a = std::max(i0, static_cast<int>(std::floor((tip.x() - half - min_.x()) / h_)) - 1);
    const int b = std::min(i1, static_cast<int>(std::floor((tip.x() + half - min_.x()) / h_)) + 1);
    float* row = top_.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_);
    for (int i = a; i <= b; ++i) {
      if (!(row[i] > z_low)) continue;
      const double dx = min_.x() + (i + 0.5) * h_ - tip.x();
      const double rho2 = dx * dx + dy * dy;
      if (rho2 > band2) continue;
      if (rho2 > r2) {
        const double along = dx * f.x() + dy * f.y();
        if (along > 0.0 && row[i] > rim_z + kContactEpsMm) {
          const double phi = std::atan2(along, side * (dx * n.x() + dy * n.y()));
          rim_lo = std::min(rim_lo, phi);
          rim_hi = std::max(rim_hi, phi);
          bins.mark(phi);
        }
        continue;
      }
      const double env = std::max(floor_z, tip.z() + tool.envelope_mm(std::sqrt(rho2)));
      const double top = row[i];
      if (!(top > env + kContactEpsMm)) continue;
      e.contact = true;
      top_max = std::max(top_max, top);
      const double along = dx * f.x() + dy * f.y();
      if (along > 0.0) {
        const double across = side * (dx * n.x() + dy * n.y());
        const double phi = std::atan2(along, across);  // in (0, π)
        leading = true;
        phi_min = std::min(phi_min, phi);
        phi_max = std::max(phi_max, phi);
        bins.mark(phi);
      }
      e.removed_mm3 += (top - env) * area;
      row[i] = static_cast<float>(env);
    }
  }
  if (!e.contact) return e;
  e.axial_depth_mm = top_max - tip.z();
  if (tool.flute_length_mm > 0.0) e.axial_depth_mm = std::min(e.axial_depth_mm, tool.flute_length_mm);
  if (leading && rim_hi >= rim_lo) {
    phi_min = std::min(phi_min, rim_lo);
    phi_max = std::max(phi_max, rim_hi);
  }
  if (e.plunge || !leading) {
    // A plunge (or contact only behind the axis): the whole leading half.
    e.entry_rad = 0.0;
    e.exit_rad = kPi;
  } else {
    // Snap the ends to the rim's angles: a cell centre inside the disk is at
    // most ~one cell from the wall, i.e. an angle of ~h/R from 0 or π.
    const double snap = 1.5 * h_ / std::max(R, h_);
    e.entry_rad = phi_min <= snap ? 0.0 : phi_min;
    e.exit_rad = phi_max >= kPi - snap ? kPi : phi_max;
    // A gap of more bins than the cells' angular spacing at the rim splits the arc.
    const int allowed = 2 + static_cast<int>(std::ceil(h_ / std::max(R, h_) / kPi * kArcBins));
    e.arcs_rad = bins.arcs(e.entry_rad, e.exit_rad, allowed);
    e.split = e.arcs_rad.size() > 1;
  }
  if (e.arcs_rad.empty()) e.arcs_rad.emplace_back(e.entry_rad, e.exit_rad);
  for (const auto& [en, ex] : e.arcs_rad) e.radial_depth_mm += R * (std::cos(en) - std::cos(ex));
  return e;
}

}  // namespace chatter
