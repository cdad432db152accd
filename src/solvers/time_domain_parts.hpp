// Internal parts of the time-domain solver (not part of the public API):
// the history of the delayed displacement, and the analysers that turn a
// simulated run into its results — growth per period (exact DMD), amplitude
// spectrum with the tooth-passing harmonics and the chatter frequency, and
// the stable / chatter verdict. Each is a function or a small class with no
// SUNDIALS in it, tested on its own in tests/test_time_domain_parts.cpp.
// The run itself (set-up, stepping, stop points, events) is in
// time_domain_run.cpp. The analysers are defined in time_domain_parts.cpp
// (their Eigen decompositions and FFT compiled once, not in every
// time-domain source).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/time_domain.hpp"

namespace chatter::detail {

// ---------------------------------------------------------------------------
// History of the relative displacement (the delay).
//
// A ring buffer of entries, one per stored instant (the uniform grid and every
// event), sorted by time. Between two neighbours r(t) is the quintic Hermite
// polynomial through r, ṙ and r̈ at both ends (r̈ one-sided: `a_right` of the
// older entry, `a_left` of the newer one, so a jump of the force at an event
// is not smeared): exact for polynomials of degree <= 5, local error O(h⁶)
// on a smooth signal (h the entry spacing), one order above CVODE's Adams
// order 5. Units: t in s, r in m, v in m/s, a in m/s².
// Preconditions: entries are pushed in non-decreasing t, at least two are
// held before a query. Cost: O(1) per query near the previous one (a hint),
// O(log n) otherwise; push is amortised O(1) (the buffer doubles when full).
struct HistoryEntry {
  double t = 0.0;
  double r[2] = {0, 0}, v[2] = {0, 0};
  double a_left[2] = {0, 0}, a_right[2] = {0, 0};
};

class History {
 public:
  /// Lookup slots that remember their last interval (displacement's
  /// `slot`; larger slots share them by modulo), and the one the run's
  /// analysis reads through (away from the delays' slots 0, 1, ...).
  static constexpr std::size_t kHintSlots = 16;
  static constexpr std::size_t kAnalysisSlot = kHintSlots - 1;
  History(std::size_t capacity, int teeth) : teeth_(teeth) { reserve(capacity); }

  void push(const HistoryEntry& e, const double* gaps) {
    if (count_ == buf_.size()) reserve(2 * buf_.size());
    const std::size_t i = (head_ + count_) % buf_.size();
    buf_[i] = e;
    std::copy(gaps, gaps + teeth_, gap_.begin() + static_cast<std::ptrdiff_t>(i * teeth_));
    ++count_;
    max_count_ = std::max(max_count_, count_);
  }
  /// Drops entries while the second oldest is still at or before `t`.
  void drop_before(double t) {
    while (count_ > 2 && at(1).t <= t) {
      head_ = (head_ + 1) % buf_.size();
      --count_;
      // The intervals remembered move down with the oldest entry.
      for (std::size_t& h : hints_) h = h > 0 ? h - 1 : 0;
    }
  }
  std::size_t capacity() const { return buf_.size(); }
  std::size_t max_count() const { return max_count_; }
  const HistoryEntry& newest() const { return at(count_ - 1); }
  HistoryEntry& newest_mutable() { return buf_[(head_ + count_ - 1) % buf_.size()]; }
  double* newest_gaps() { return &gap_[((head_ + count_ - 1) % buf_.size()) * teeth_]; }

  /// r(t) (m). Outside the stored range the nearest interval's polynomial
  /// is used (counted in extrapolations()). `slot`: which of the caller's
  /// lookups this is (e.g. the delay's index): each slot remembers its last
  /// interval, so several delays read in turn each find theirs in O(1).
  void displacement(double t, double out[2], std::size_t slot = 0) const {
    const std::size_t k = interval(t, slot);
    const HistoryEntry& e0 = at(k);
    const HistoryEntry& e1 = at(k + 1);
    const double h = e1.t - e0.t;
    if (!(h > 0.0)) {
      out[0] = e1.r[0];
      out[1] = e1.r[1];
      return;
    }
    const double s = (t - e0.t) / h, s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s;
    const double h0 = 1 - 10 * s3 + 15 * s4 - 6 * s5;
    const double h1 = s - 6 * s3 + 8 * s4 - 3 * s5;
    const double h2 = 0.5 * (s2 - 3 * s3 + 3 * s4 - s5);
    const double h3 = 10 * s3 - 15 * s4 + 6 * s5;
    const double h4 = -4 * s3 + 7 * s4 - 3 * s5;
    const double h5 = 0.5 * (s3 - 2 * s4 + s5);
    for (int c = 0; c < 2; ++c)
      out[c] = e0.r[c] * h0 + e0.v[c] * h * h1 + e0.a_right[c] * h * h * h2 + e1.r[c] * h3 + e1.v[c] * h * h4 +
               e1.a_left[c] * h * h * h5;
  }
  /// Gap (m) left in air by tooth `tooth` at time t, linear interpolation.
  double gap(double t, int tooth) const {
    const std::size_t k = interval(t, 0);
    const std::size_t i0 = (head_ + k) % buf_.size(), i1 = (head_ + k + 1) % buf_.size();
    const double t0 = buf_[i0].t, t1 = buf_[i1].t;
    const double g0 = gap_[i0 * teeth_ + tooth], g1 = gap_[i1 * teeth_ + tooth];
    if (!(t1 > t0)) return g1;
    const double s = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    return g0 + s * (g1 - g0);
  }
  void scale(double factor) {
    for (std::size_t k = 0; k < count_; ++k) {
      HistoryEntry& e = buf_[(head_ + k) % buf_.size()];
      for (int c = 0; c < 2; ++c) {
        e.r[c] *= factor;
        e.v[c] *= factor;
        e.a_left[c] *= factor;
        e.a_right[c] *= factor;
      }
    }
  }
  long extrapolations() const { return extrapolations_; }

 private:
  const HistoryEntry& at(std::size_t k) const { return buf_[(head_ + k) % buf_.size()]; }
  // Index k with at(k).t <= t <= at(k+1).t (clamped to the stored range).
  std::size_t interval(double t, std::size_t slot) const {
    if (t < at(0).t || t > at(count_ - 1).t) ++extrapolations_;
    std::size_t& hint_ = hints_[slot % kHintSlots];
    if (hint_ + 1 < count_ && at(hint_).t <= t && t <= at(hint_ + 1).t) return hint_;
    if (hint_ + 2 < count_ && at(hint_ + 1).t <= t && t <= at(hint_ + 2).t) return ++hint_;
    std::size_t lo = 0, hi = count_ - 1;  // invariant: answer in [lo, hi)
    while (hi - lo > 1) {
      const std::size_t mid = (lo + hi) / 2;
      if (at(mid).t <= t) lo = mid;
      else hi = mid;
    }
    hint_ = lo;
    return lo;
  }
  void reserve(std::size_t cap) {
    cap = std::max<std::size_t>(cap, 4);
    std::vector<HistoryEntry> nb(cap);
    std::vector<double> ng(cap * teeth_, 0.0);
    for (std::size_t k = 0; k < count_; ++k) {
      const std::size_t i = (head_ + k) % buf_.size();
      nb[k] = buf_[i];
      std::copy(gap_.begin() + static_cast<std::ptrdiff_t>(i * teeth_),
                gap_.begin() + static_cast<std::ptrdiff_t>((i + 1) * teeth_), ng.begin() + static_cast<std::ptrdiff_t>(k * teeth_));
    }
    buf_.swap(nb);
    gap_.swap(ng);
    head_ = 0;
    hints_.fill(0);
  }

  int teeth_;
  std::vector<HistoryEntry> buf_;
  std::vector<double> gap_;
  std::size_t head_ = 0, count_ = 0, max_count_ = 0;
  mutable std::array<std::size_t, kHintSlots> hints_{};
  mutable long extrapolations_ = 0;
};

// ---------------------------------------------------------------------------
// Growth per period: exact dynamic mode decomposition (Tu et al., "On dynamic
// mode decomposition: theory and applications", J. Comput. Dyn. 2014).

/// Dominant eigenvalue of the linear map that sends the columns of X to those
/// of Y (snapshot pairs x_k -> y_k, equal sizes): the SVD of X truncated at
/// singular values <= rank_tolerance × the largest, the projected map
/// Ãᵀ = Uᵣᵀ Y Vᵣ Σᵣ⁻¹, and among its eigenvalues the one of largest modulus
/// among the modes that carry at least 1e-3 of `last` (the final snapshot,
/// projected on the eigenvectors). Returned with Im >= 0.
/// Returns NaN when X has fewer than 2 columns or is zero.
/// Cost: O(d c²) for d rows and c columns.
std::complex<double> dominant_multiplier(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y,
                                         const Eigen::VectorXd& last, double rank_tolerance);

/// Once-per-period snapshots of a run: snapshot k is the observable at
/// t = (k+1)τ (r at the M grid points of the period just ended, then the
/// modal state [q; q̇/ω]), each stored × exp(−log_scale[k]) (linear mode
/// rescales the state to keep it near its initial size; 0 otherwise).
struct PeriodSnapshots {
  std::vector<Eigen::VectorXd> states;
  std::vector<double> log_scale;
};

struct GrowthEstimate {
  /// Dominant multiplier per period (Im >= 0); NaN when too few usable pairs.
  std::complex<double> multiplier{std::numeric_limits<double>::quiet_NaN(), 0.0};
  /// Nonlinear mode: the last increment fell below the noise floor (periodic).
  bool converged = false;
};

/// Growth per period from the snapshots from period `first_analysed` on.
/// Linear mode: DMD of the states; nonlinear mode: of the increments between
/// consecutive periods (they obey the linear map while the tool cuts), using
/// only pairs above the floor 1e4 × rtol × |last snapshot| (below it they are
/// integration noise; if the last increment is below it the run `converged`).
/// Needs at least 4 usable pairs, else the multiplier is NaN. The DMD rank is
/// cut at the integration noise, 30 × rtol relative to the smallest fitted
/// snapshot (clamped to [1e-9, 0.05]). `rtol` is CVODE's relative tolerance.
GrowthEstimate growth_per_period(const PeriodSnapshots& snap, int first_analysed, bool linear, double rtol);

// ---------------------------------------------------------------------------
// Spectrum.

struct Spectrum {
  std::vector<double> f, amp;  ///< Hz, m; bins 0 .. nfft/2.
  double resolution_hz = 0.0;  ///< 1 / (n dt): the window's length, not the zero-padded bin spacing.
};

/// One-sided amplitude spectrum of the planar signal (x, y) sampled every dt
/// seconds (n >= 8 samples, else empty): mean removed, Hann window, zero-padded
/// to the next power of two nfft, |X| combined over the components
/// (sqrt(|X_x|² + |X_y|²)), scaled by 2 / Σw so that a sinusoid of amplitude
/// A whose frequency falls on a bin reads A (to O(1/n)). Between bins it
/// reads less, at worst 0.849 A (the Hann window's scalloping loss, −1.42 dB,
/// half a bin off; zero padding makes the bins finer than 1/(n dt), so the
/// loss is usually smaller); its sidelobes fall below −31 dB.
/// Cost: O(nfft log nfft).
Spectrum amplitude_spectrum(const std::vector<double>& x, const std::vector<double>& y, double dt);

/// k when f (Hz) lies within 2.5 resolutions of k × tooth_passing_hz (k >= 0),
/// else −1.
inline int harmonic_index(double f_hz, double tooth_passing_hz, double resolution_hz) {
  const double k = std::round(f_hz / tooth_passing_hz);
  return std::abs(f_hz - k * tooth_passing_hz) <= 2.5 * resolution_hz ? static_cast<int>(k) : -1;
}

/// Frequency (Hz) of the largest local maximum of the spectrum that is not a
/// tooth-passing harmonic (harmonic_index < 0), refined by a parabola through
/// the log amplitudes of the peak bin and its neighbours (shift <= half a
/// bin); NaN when there is none or it is below 1e-9 of the largest bin.
double dominant_nonharmonic_hz(const Spectrum& sp, double tooth_passing_hz);

/// The tooth-passing harmonics k × tooth_passing_hz, k = 1..60, up to
/// min(Nyquist, max_frequency_hz), each with the largest amplitude within
/// ±3 bins of its frequency.
std::vector<SpectralPeak> tooth_passing_harmonics(const Spectrum& sp, double tooth_passing_hz,
                                                  double max_frequency_hz);

// ---------------------------------------------------------------------------
// Verdict.

/// Nonlinear verdict: fraction of the cutting-arc time in air that counts as
/// leaving the cut, and the margin below |mu| = 1 that then counts as chatter.
constexpr double kAirFraction = 0.005;
constexpr double kSaturatedMargin = 0.02;

/// Samples of the analysed window during which some tooth was inside the
/// cutting arc (`arc`) and, of those, every such tooth in air (`air`), in
/// the whole window and in its first and second halves.
struct AirCounts {
  std::size_t arc = 0, air = 0, arc_early = 0, air_early = 0, arc_late = 0, air_late = 0;
  /// Counts one sample; `late` when it lies in the second half of the window.
  void add(bool in_air, bool late) {
    ++arc;
    if (in_air) ++air;
    (late ? arc_late : arc_early) += 1;
    if (in_air) (late ? air_late : air_early) += 1;
  }
  double fraction() const { return arc ? static_cast<double>(air) / static_cast<double>(arc) : 0.0; }
  double early_fraction() const { return arc_early ? static_cast<double>(air_early) / static_cast<double>(arc_early) : 0.0; }
  double late_fraction() const { return arc_late ? static_cast<double>(air_late) / static_cast<double>(arc_late) : 0.0; }
};

struct VerdictInput {
  bool linear = false;
  GrowthEstimate growth;
  AirCounts air;
  int analysed_periods = 0;   ///< only quoted in the measure
  double relative_tolerance = 0.0;  ///< only quoted in the measure
};

struct VerdictOutcome {
  SimulationVerdict verdict = SimulationVerdict::kStable;
  std::string measure;  ///< the measure the verdict rests on, with its numbers
};

/// Stable or chatter from the growth per period |mu| and the contact losses:
///  - linear mode: chatter iff |mu| >= 1 (stable when there was no motion, NaN);
///  - nonlinear, converged increments: stable (forced vibration only);
///  - nonlinear, no estimate (NaN): chatter iff the tool was in air during
///    more than kAirFraction of the cutting-arc time;
///  - otherwise chatter iff |mu| >= 1, or >= 1 − kSaturatedMargin when the
///    contact loss persists (> kAirFraction overall and in the second half,
///    and at least half as frequent there as in the first half): saturated
///    chatter is a limit cycle of the increments, |mu| = 1 up to the fit.
VerdictOutcome decide_verdict(const VerdictInput& in);

}  // namespace chatter::detail
