// Internal to the ops layer: the robust speed search behind robust_speed(),
// check_operations() and recommend() (docs/operations.md, "Search"). Exact
// solves of one solver, cached by speed; the scan evenly spaced in 1/rpm;
// the worst limit over a speed band; the robust optimum; pocket edges; and,
// at low speed, where lobes crowd, the rules that keep all that affordable
// (the dense region, see SpeedSearch::scan()).
#pragma once

#include <cstddef>
#include <functional>
#include <initializer_list>
#include <map>
#include <utility>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/operations.hpp"
#include "../solvers/extremum.hpp"
#include "ops_internal.hpp"

namespace chatter::detail::ops {

// Scan: kScanStart solves evenly spaced in 1/rpm, then each interval is
// divided so that every lobe gets about kScanPointsPerLobe points (the lobe
// count from the spread of lobe numbers of the first scan), at most
// kScanMaxPoints in all. 8 points per lobe locate every cusp and lobe bottom
// to 1/16 of a lobe; the refinements below work from there.
inline constexpr int kScanStart = 24;
inline constexpr double kScanPointsPerLobe = 8.0;
inline constexpr int kScanMaxPoints = 2000;
// Refined candidates: every local maximum of the scanned objective within
// kCandidateSpread (relative) of the best, at most kMaxCandidates (two
// pockets of nearly equal height are both refined).
inline constexpr double kCandidateSpread = 0.1;
inline constexpr std::size_t kMaxCandidates = 3;
// Maximiser resolution for a robust optimum: 1e-4 of the speed (1 rev/min
// at 10 000), far below a spindle's speed error; at tolerance 0 the optimum
// is a cusp and the old kGoldenRelativeWidth (1e-8) applies.
inline constexpr double kRobustRelativeWidth = 1e-4;
// Lobe bottoms inside a band: 1e-5 of the speed; a bottom is smooth
// (quadratic), so its value is then exact to ~1e-10 relative. Pocket edges:
// 1e-4 of the speed (1 rev/min at 10 000; they are printed in whole rev/min).
inline constexpr double kBottomRelativeWidth = 1e-5;
inline constexpr double kEdgeRelativeWidth = 1e-4;
// The band's two ends are balanced when their limits agree to this (relative).
inline constexpr double kBalanceRelative = 1e-6;
inline constexpr int kEdgeMaxIterations = 60;

// The dense region (check and robust_speed with a speed tolerance; see
// SpeedSearch::scan()). The first kScanStart solves cover at most the top
// kProbeSpeedRatio of the range (speeds >= rpm_max / 10): the lobe count
// there sizes the rest. The scan stops where a band N(1 ± tol) holds
// kDenseBandLobes lobes; below, a band holds at least half a lobe.
inline constexpr double kProbeSpeedRatio = 10.0;
inline constexpr double kDenseBandLobes = 0.25;
// Where the dense region may hold a better speed, the scan is extended down
// past the highest band in doubt, at least by this speed ratio at a time.
inline constexpr double kExtendRatio = 1.5;
// The worst limit over a band outside the scan: a band whose ends' lobe
// numbers differ by kManyLobes or more is sampled at kManyLobesSamples speeds
// evenly spaced in 1/rpm (ends included) and at its own centre, and the
// kManyLobesRefined lowest sampled local minima are refined by one exact
// solve at the vertex of the parabola (in 1/rpm) through the minimum and
// its two neighbours. Fewer lobes: kScanPointsPerLobe samples per lobe and
// every sampled local minimum refined by Brent, as in the scan.
inline constexpr int kManyLobes = 2;
inline constexpr int kManyLobesSamples = 9;
// A refinement with a floor (SpeedSearch::refinement_floor) is solved from
// the top down this many speeds at a time, the floor raised between chunks.
inline constexpr std::size_t kRefineChunk = 16;
inline constexpr std::size_t kManyLobesRefined = 2;

// Exact solves of one solver, cached by speed, with the scan and the band
// and pocket searches built on them. Not thread-safe itself; the scan, the
// band samples and the dense-region verdicts are solved in parallel.
class SpeedSearch {
 public:
  SpeedSearch(const LobeSolver& solver, double rpm_min, double rpm_max, double tol, unsigned threads);

  double tolerance() const { return tol_; }
  double rpm_min() const { return lo_; }
  double rpm_max() const { return hi_; }
  /// Exact solves (limit_at) so far.
  std::size_t solves() const { return solves_; }

  /// The exact limit at `rpm`, solved once.
  const StabilityLimit& at(double rpm);
  /// Called after every exact solve or question (from worker threads while
  /// several run in parallel).
  std::function<void()> on_solve;
  double g(double rpm) { return at(rpm).depth_limit_m; }
  /// Solves the speeds not cached yet, in parallel when threads allow.
  void prefetch(std::initializer_list<double> rpms) { prefetch(std::vector<double>(rpms)); }
  void prefetch(const std::vector<double>& rpms);

  /// The scan over [rpm_min, rpm_max], evenly spaced in 1/rpm: kScanStart
  /// solves, then ≈ kScanPointsPerLobe per lobe (at most kScanMaxPoints).
  /// With `split_dense` and a speed tolerance the first kScanStart solves
  /// cover only speeds >= rpm_max / kProbeSpeedRatio, and the scan stops
  /// where a band N(1 ± tol) holds kDenseBandLobes lobes: the speeds below
  /// dense_below() form the dense region, which best() shows cannot hold the
  /// optimum (or scans after all). Without: the whole range.
  void scan(bool split_dense = false);
  const std::vector<double>& scan_speeds() const { return scan_; }
  /// Optional, for a whole-range scan: its refinement is then solved from
  /// the top down, kRefineChunk speeds at a time, and before each chunk this
  /// is asked, with the speeds solved so far, for a floor; the speeds below
  /// it are not solved but kept in skipped() — the caller shows afterwards
  /// that none can hold its optimum, or calls fill_skipped() (recommend: no
  /// speed there removes more, whatever its limit, than the optimum found).
  std::function<double(const std::vector<double>& solved)> refinement_floor;
  const std::vector<double>& skipped() const { return skipped_; }
  /// Solves the skipped speeds and adds them to the scan (the memoised band
  /// minima are forgotten: they were found on the thinner scan).
  void fill_skipped();
  /// Speeds below this form the dense region, not scanned (rpm_min: none).
  double dense_below() const { return dense_below_; }
  /// How often best() extended the scan into the dense region (where it
  /// could not show that the region holds nothing better).
  int extensions() const { return extensions_; }

  /// Linear interpolation of min(limit, cap) in 1/rpm between scanned speeds
  /// (clamped to the scan's ends): the cheap estimate used for ranking.
  double g_scan(double rpm, double cap);
  /// Scan estimate of the worst limit over the band of `rpm` (no solves).
  double band_min_scan(double rpm, double cap);
  /// The worst limit over [rpm(1 − tol), rpm(1 + tol)] from exact solves
  /// (docs/operations.md "Search"): inside the scan the band's ends, the
  /// scanned speeds inside and the Brent-refined bottom of every scanned
  /// local minimum; outside it (the dense region) the band sampled on its
  /// own (kManyLobes rule). Memoised by speed.
  double band_min(double rpm);

  /// Maximisation of f on [a, b] down to `rel` of the speed (Brent's
  /// minimiser, golden section with parabolic steps); returns the best
  /// evaluated point.
  template <class F>
  double maximize(F&& f, double a, double b, double rel) {
    return maximize_on(f, a, b, rel * b, kGoldenMaxIterations).x;
  }

  /// Edges of the connected interval around `rpm` (where limit > threshold is
  /// known) in which the limit stays above `threshold`, inside the range.
  std::pair<double, double> pocket(double rpm, double threshold) {
    return {edge(rpm, threshold, -1), edge(rpm, threshold, +1)};
  }

  /// The robust optimum: the speed in range maximising band_min (capped at
  /// `cap`: above it every speed is as good, then the one nearest `near`).
  /// Ranked on the scan; with a dense region, the optimum found is kept
  /// only if every band of the dense region holds a speed unstable at its
  /// worst limit (dense_cannot_beat), else the dense region is scanned too.
  double best(double cap, double near);

  /// The band straddling a cusp is best placed where its two ends see the same
  /// limit: d(N) = g(N(1 − tol)) − g(N(1 + tol)) = 0, d < 0 left of it. Found
  /// by regula falsi (Illinois) in [a, b] when d changes sign there and the
  /// band's worst limit at the root is at its ends (no lobe bottom inside);
  /// else 0 (the caller falls back on golden-section search). ≈ 2 solves per
  /// step, superlinear on the smooth lobe flanks.
  double balance(double a, double b, double rel);

 private:
  void solve_all(const std::vector<double>& rpms);
  // Minimum of the limit on [a, b] by Brent's minimiser (memoised per bracket).
  std::pair<double, double> bottom(double a, double b);
  // The pocket edge on side `dir` (−1 lower, +1 upper) of `rpm`.
  double edge(double rpm, double threshold, int dir);
  // The ranking of best() on the scan alone.
  double best_scanned(double cap, double near);
  // The exact worst limit over [a, b] from the scan (a >= the scan's start).
  double band_min_scanned(double a, double b);
  // The worst limit over a band outside the scan (kManyLobes rule).
  double band_min_sampled(double rpm, double a, double b);
  // limit(rpm) > depth, from the cache or the solver's limit_above (memoised).
  bool above(double rpm, double depth);
  // 0 if every band N(1 ± tol), N in [rpm_min, dense_below), holds a speed
  // whose limit is at most `depth` (the solver's stability verdict at that
  // depth, or an exact limit): no speed there has a worst limit above it.
  // Else the speed down to which the scan must reach to cover the highest
  // band where that could not be shown (that band's lower end).
  double dense_cannot_beat(double depth);
  // Extends the scan down to `down_to` (>= rpm_min) at its spacing.
  void extend_scan(double down_to);

  const LobeSolver& solver_;
  double lo_, hi_, tol_, dmax_;
  unsigned threads_;
  std::map<double, StabilityLimit> cache_;
  std::map<std::pair<double, double>, std::pair<double, double>> bottoms_;
  std::map<double, double> bands_;                    // band_min by speed
  std::map<std::pair<double, double>, bool> above_;   // limit_above by (speed, depth)
  std::map<double, double> unstable_at_;              // smallest depth found unstable, by speed
  std::vector<double> skipped_;                       // refinement speeds below refinement_floor()
  std::vector<double> scan_;
  double dense_below_ = 0.0;     // the dense region is [lo_, dense_below_)
  int extensions_ = 0;
  double lobes_per_u_ = 0.0;     // lobes per unit of 1/rpm (from the first scan)
  double scan_step_u_ = 0.0;     // the scan's spacing in 1/rpm
  double cleared_depth_ = kInf;  // dense_cannot_beat(d) holds for every d >= this
  std::size_t solves_ = 0;
};

/// The pocket of `rpm`: its exact limit, the worst limit over its band
/// (worst_margin against `depth_m`) and the edges where the limit falls to
/// `threshold_m`.
SpeedPocket make_pocket(SpeedSearch& s, double rpm, double depth_m, double threshold_m);

}  // namespace chatter::detail::ops
