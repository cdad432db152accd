// Internal parts of the forced response (include/chatter/forced.hpp; not
// part of the public API): a periodic relative displacement r(t) as a
// function one can evaluate anywhere, from one of two sources:
//   forced_fourier.cpp   the static force's Fourier series times the
//                        receptance (equal pitch, one helix, no runout;
//                        turning), and the turning deflection;
//   forced_periodic.cpp  one linear periodic solve on the sdm grid
//                        (variable pitch or helix, runout, process damping);
// forced.cpp reads the path: mean, peak to peak, the wall (SLE) and the
// chip of every tooth.
#pragma once

#include <complex>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "chatter/process.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/structural_model.hpp"

namespace chatter::forced_detail {

using Vector2cd = Eigen::Matrix<std::complex<double>, 2, 1>;

/// A periodic relative displacement r(t) = r(t + period), m.
class PeriodicPath {
 public:
  virtual ~PeriodicPath() = default;
  double period() const { return period_; }
  /// r(t), m, for any t (wrapped into one period).
  virtual Eigen::Vector2d at(double t) const = 0;
  /// The mean of r over one period, m.
  virtual Eigen::Vector2d mean() const = 0;

 protected:
  double period_ = 0.0;
};

/// r(t) = c_0 + 2 Re Σ_{k=1}^{K} c_k e^{j k ω t}, ω = 2π / period.
class FourierPath final : public PeriodicPath {
 public:
  FourierPath(double period, const Eigen::Vector2d& c0, std::vector<Vector2cd> ck);
  Eigen::Vector2d at(double t) const override;
  Eigen::Vector2d mean() const override { return c0_; }
  int harmonics() const { return static_cast<int>(ck_.size()); }

 private:
  Eigen::Vector2d c0_;
  std::vector<Vector2cd> ck_;
};

/// The cubic Hermite interpolant through knots (t_i, r_i, ṙ_i), t_0 = 0 …
/// t_N = period (r_N = r_0 for a periodic path): error O(h⁴) in the knot
/// spacing h.
class SampledPath final : public PeriodicPath {
 public:
  SampledPath(std::vector<double> t, std::vector<Eigen::Vector2d> r, std::vector<Eigen::Vector2d> v);
  Eigen::Vector2d at(double t) const override;
  /// Exact integral of the interpolant over the period, over the period.
  Eigen::Vector2d mean() const override;

 private:
  std::vector<double> t_;
  std::vector<Eigen::Vector2d> r_, v_;
};

/// What a source returns: the path and the mean cutting force on the tool.
struct PathSource {
  std::unique_ptr<PeriodicPath> path;
  Eigen::Vector2d mean_force_n = Eigen::Vector2d::Zero();
  int harmonics = 0;
};

/// Fourier path (forced_fourier.cpp). Milling: equal pitch, one helix angle,
/// no runout (the caller checks); turning: the constant force alone.
/// `harmonics` 0 = automatic (ForcedOptions::harmonics).
PathSource fourier_response(const StructuralModel& model, const Process& process, double rpm, double depth_m,
                            double feed_m, int harmonics, int max_harmonics);

/// Periodic solve over one revolution on the sdm grid (forced_periodic.cpp),
/// milling. `residual`: |Φ y + r − y| / |y| of the solved periodic state.
PathSource periodic_response(const StructuralModel& model, const Process& process,
                             const SemiDiscretizationOptions& options, double rpm, double depth_m, double feed_m,
                             double* residual = nullptr);

}  // namespace chatter::forced_detail
