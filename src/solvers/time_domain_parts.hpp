// Internal parts of the time-domain solver (not part of the public API):
// the history of the delayed displacement, and the analysers that turn a
// simulated run into its results — growth per period (exact DMD), amplitude
// spectrum with the tooth-passing harmonics and the chatter frequency, and
// the stable / chatter verdict. Each is a function or a small class with no
// SUNDIALS in it, tested on its own in tests/test_time_domain_parts.cpp.
// The run itself (set-up, stepping, stop points, events) is in
// time_domain_run.cpp. Header-only so that the tests need no exported symbols.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <unsupported/Eigen/FFT>
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
inline std::complex<double> dominant_multiplier(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y,
                                                const Eigen::VectorXd& last, double rank_tolerance) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (X.cols() < 2) return {kNaN, 0.0};
  Eigen::BDCSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  if (sv.size() == 0 || !(sv(0) > 0.0)) return {kNaN, 0.0};
  Eigen::Index r = 0;
  while (r < sv.size() && sv(r) > rank_tolerance * sv(0)) ++r;
  const Eigen::MatrixXd Ur = svd.matrixU().leftCols(r);
  const Eigen::MatrixXd Vr = svd.matrixV().leftCols(r);
  const Eigen::MatrixXd At = Ur.transpose() * Y * Vr * sv.head(r).cwiseInverse().asDiagonal();
  Eigen::EigenSolver<Eigen::MatrixXd> es(At);
  if (es.info() != Eigen::Success) return {kNaN, 0.0};
  const Eigen::VectorXcd lambda = es.eigenvalues();
  // Amplitudes of the last snapshot on the (projected) eigenvectors.
  const Eigen::VectorXcd coord = Ur.transpose() * last;
  const Eigen::VectorXcd b = es.eigenvectors().colPivHouseholderQr().solve(coord);
  const double bmax = b.cwiseAbs().maxCoeff();
  std::complex<double> best{kNaN, 0.0};
  double best_abs = -1.0;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) {
    if (std::abs(b(i)) < 1e-3 * bmax) continue;
    if (std::abs(lambda(i)) > best_abs) {
      best_abs = std::abs(lambda(i));
      best = lambda(i);
    }
  }
  if (best.imag() < 0) best = std::conj(best);
  return best;
}

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
inline GrowthEstimate growth_per_period(const PeriodSnapshots& snap, int first_analysed, bool linear, double rtol) {
  GrowthEstimate out;
  const std::vector<Eigen::VectorXd>& snapshots = snap.states;
  const int K = static_cast<int>(snapshots.size());  // snapshot k at t = (k+1)τ
  const int k0 = std::max(0, first_analysed - 1);
  std::vector<Eigen::VectorXd> seq;  // states (linear) or increments (nonlinear), true scale relative
  std::vector<double> seq_log;
  if (linear) {
    for (int k = k0; k < K; ++k) {
      seq.push_back(snapshots[k]);
      seq_log.push_back(snap.log_scale[k]);
    }
  } else {
    for (int k = k0; k + 1 < K; ++k) {
      seq.push_back(snapshots[k + 1] - snapshots[k]);
      seq_log.push_back(0.0);
    }
  }
  double amp_ref = 0.0;
  if (!snapshots.empty()) amp_ref = snapshots.back().norm();
  const double floor = 1e4 * rtol * std::max(amp_ref, 1e-300);
  std::vector<int> usable;
  for (std::size_t k = 0; k + 1 < seq.size(); ++k) {
    const double a0 = seq[k].norm(), a1 = seq[k + 1].norm() * std::exp(seq_log[k + 1] - seq_log[k]);
    if (linear || (a0 > floor && a1 > floor)) usable.push_back(static_cast<int>(k));
  }
  if (!linear && !seq.empty() && seq.back().norm() <= floor) out.converged = true;
  if (usable.size() >= 4) {
    const Eigen::Index zdim = seq.front().size();
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(zdim, static_cast<Eigen::Index>(usable.size()));
    Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(zdim, static_cast<Eigen::Index>(usable.size()));
    for (std::size_t c = 0; c < usable.size(); ++c) {
      const int k = usable[c];
      const double nk = seq[k].norm();
      if (!(nk > 0.0)) continue;
      X.col(static_cast<Eigen::Index>(c)) = seq[k] / nk;
      Y.col(static_cast<Eigen::Index>(c)) = seq[k + 1] * (std::exp(seq_log[k + 1] - seq_log[k]) / nk);
    }
    const int last = usable.back() + 1;
    // Singular values below the integration noise (≈ rtol × |z| on every
    // snapshot, relative to the smallest fitted one) are not dynamics.
    double smallest = std::numeric_limits<double>::infinity();
    for (int k : usable) smallest = std::min(smallest, seq[k].norm());
    const double noise = linear ? 30.0 * rtol : 30.0 * rtol * amp_ref / std::max(smallest, 1e-300);
    out.multiplier =
        dominant_multiplier(X, Y, seq[last] / std::max(seq[last].norm(), 1e-300), std::clamp(noise, 1e-9, 0.05));
  }
  return out;
}

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
inline Spectrum amplitude_spectrum(const std::vector<double>& x, const std::vector<double>& y, double dt) {
  constexpr double kPi = std::numbers::pi;
  Spectrum s;
  const std::size_t n = x.size();
  if (n < 8) return s;
  std::size_t nfft = 1;
  while (nfft < n) nfft *= 2;
  std::vector<double> w(n);
  double wsum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(n - 1));
    wsum += w[i];
  }
  Eigen::FFT<double> fft;
  std::vector<double> mag2(nfft / 2 + 1, 0.0);
  for (const std::vector<double>* comp : {&x, &y}) {
    double mean = 0.0;
    for (double v : *comp) mean += v;
    mean /= static_cast<double>(n);
    std::vector<double> in(nfft, 0.0);
    for (std::size_t i = 0; i < n; ++i) in[i] = ((*comp)[i] - mean) * w[i];
    std::vector<std::complex<double>> out;
    fft.fwd(out, in);
    for (std::size_t k = 0; k <= nfft / 2; ++k) mag2[k] += std::norm(out[k]);
  }
  s.f.resize(nfft / 2 + 1);
  s.amp.resize(nfft / 2 + 1);
  for (std::size_t k = 0; k <= nfft / 2; ++k) {
    s.f[k] = static_cast<double>(k) / (static_cast<double>(nfft) * dt);
    s.amp[k] = 2.0 * std::sqrt(mag2[k]) / wsum;
  }
  s.resolution_hz = 1.0 / (static_cast<double>(n) * dt);
  return s;
}

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
inline double dominant_nonharmonic_hz(const Spectrum& sp, double tooth_passing_hz) {
  double best_amp = 0.0, best_f = std::numeric_limits<double>::quiet_NaN(), amp_all = 0.0;
  std::size_t best_k = 0;
  for (std::size_t k = 1; k + 1 < sp.f.size(); ++k) {
    amp_all = std::max(amp_all, sp.amp[k]);
    if (harmonic_index(sp.f[k], tooth_passing_hz, sp.resolution_hz) >= 0) continue;
    if (sp.amp[k] > best_amp && sp.amp[k] >= sp.amp[k - 1] && sp.amp[k] >= sp.amp[k + 1]) {
      best_amp = sp.amp[k];
      best_k = k;
    }
  }
  if (best_k > 0 && best_amp > 1e-9 * amp_all) {
    // Parabolic refinement on the log amplitude.
    const double l0 = std::log(std::max(sp.amp[best_k - 1], 1e-300)), l1 = std::log(sp.amp[best_k]),
                 l2 = std::log(std::max(sp.amp[best_k + 1], 1e-300));
    const double den = l0 - 2 * l1 + l2;
    const double shift = den < 0 ? std::clamp(0.5 * (l0 - l2) / den, -0.5, 0.5) : 0.0;
    best_f = sp.f[best_k] + shift * (sp.f[1] - sp.f[0]);
  }
  return best_f;
}

/// The tooth-passing harmonics k × tooth_passing_hz, k = 1..60, up to
/// min(Nyquist, max_frequency_hz), each with the largest amplitude within
/// ±3 bins of its frequency.
inline std::vector<SpectralPeak> tooth_passing_harmonics(const Spectrum& sp, double tooth_passing_hz,
                                                         double max_frequency_hz) {
  std::vector<SpectralPeak> out;
  const double ftp = tooth_passing_hz;
  for (int k = 1; sp.f.size() > 1 && k * ftp <= std::min(sp.f.back(), max_frequency_hz) && k <= 60; ++k) {
    SpectralPeak pk;
    pk.frequency_hz = k * ftp;
    pk.harmonic = k;
    const auto c = static_cast<std::size_t>(std::llround(k * ftp / (sp.f[1] - sp.f[0])));
    for (std::size_t j = c >= 3 ? c - 3 : 0; j <= c + 3 && j < sp.f.size(); ++j)
      pk.amplitude_m = std::max(pk.amplitude_m, sp.amp[j]);
    out.push_back(pk);
  }
  return out;
}

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
inline VerdictOutcome decide_verdict(const VerdictInput& in) {
  VerdictOutcome out;
  std::ostringstream why;
  why.precision(4);
  const double growth = std::abs(in.growth.multiplier);
  const double air_fraction = in.air.fraction();
  const int analysed = in.analysed_periods;
  if (in.linear) {
    if (std::isnan(growth)) {
      out.verdict = SimulationVerdict::kStable;
      why << "no motion to analyse";
    } else {
      out.verdict = growth < 1.0 ? SimulationVerdict::kStable : SimulationVerdict::kChatter;
      why << "linear mode: growth per period |mu| = " << growth << " over the last " << analysed << " periods ("
          << (growth < 1.0 ? "< 1: decays" : ">= 1: grows") << ")";
    }
  } else if (in.growth.converged) {
    out.verdict = SimulationVerdict::kStable;
    why << "periodic: the once-per-period increments fell below " << 1e4 * in.relative_tolerance
        << " of the amplitude (forced vibration only)";
  } else if (std::isnan(growth)) {
    out.verdict = air_fraction > kAirFraction ? SimulationVerdict::kChatter : SimulationVerdict::kStable;
    why << "the tool was in air during " << 100.0 * air_fraction << " % of the cutting-arc time in the last "
        << analysed << " periods";
  } else {
    const bool air = air_fraction > kAirFraction;
    const double early = in.air.early_fraction();
    const double late = in.air.late_fraction();
    // Persisting contact loss: at least half as often in the second half of
    // the window as in the first (a decaying transient loses contact less
    // and less; a saturated chatter vibration keeps doing it).
    const bool persisting = air && late > kAirFraction && late >= 0.5 * early;
    const double threshold = persisting ? 1.0 - kSaturatedMargin : 1.0;
    out.verdict = growth < threshold ? SimulationVerdict::kStable : SimulationVerdict::kChatter;
    why << "once-per-period increments " << (growth < 1.0 ? "decay" : "grow") << " by |mu| = " << growth
        << " per period over the last " << analysed << " periods";
    if (air)
      why << "; the tool was in air during " << 100.0 * air_fraction << " % of the cutting-arc time ("
          << 100.0 * early << " % then " << 100.0 * late << " % in the two halves"
          << (persisting ? ": persisting, saturated chatter has |mu| = 1" : ": dying out") << ")";
    else
      why << "; the tool stayed in the cut";
  }
  out.measure = why.str();
  return out;
}

}  // namespace chatter::detail
