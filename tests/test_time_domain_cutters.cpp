// The `time-domain` solver with real cutters (docs/physics.md §8,
// docs/time_domain.md "Real cutters"): runout and variable-pitch chips
// against the §8 formula worked by hand, the once-per-revolution force line
// of runout, helix slice convergence, β → 0 and the helix-independent mean
// force, variable pitch against the uniform path, and process damping in
// turning against the exact boundary of its delay equation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/time_domain.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// ---- tolerances ----
// Chips on a stiff tool (3 kHz, 1e9 N/m, depth 10 µm): the force is ~1 N,
// its deflection ~1e-9 m, so the regenerative part is below 1e-8 m, 0.01 %
// of the 0.1 mm feed.
constexpr double kChipTolerance = 1e-8;
// Runout line: with runout the once-per-revolution force line is at least
// this fraction of the tooth-passing line (hand estimate: the runout 20–150
// µm against a 100 µm feed gives lines of the same order) …
constexpr double kRunoutLineMin = 0.1;
// … and without runout the force repeats every tooth period, so the line is
// only integration noise (rtol 1e-7) relative to the tooth-passing line.
constexpr double kNoRunoutLineMax = 1e-4;
// Growth per period with 20 vs 80 axial slices: the slices ramp in and out
// of the arc and carry the chip at their midpoint, a midpoint rule in z
// (error O(N_z⁻²)): measured 1.4e-5 relative near the limit. The ratio of
// successive changes (20→40 over 40→80) is ≈ 4 for second order (measured
// 3.6); accepted between 2.5 and 6.5.
constexpr double kSliceConvergence = 1e-4;
constexpr double kOrderRatioMin = 2.5, kOrderRatioMax = 6.5;
// A helix of 1e-6 rad on 20 slices vs the straight uniform path: the same
// equation up to the helix lag (1e-7 rad over the cut) and the integration
// tolerance (rtol 1e-7): measured 1.2e-6.
constexpr double kStraightLimit = 1e-5;
// Exact edge vs slices (ExactEdge* tests): growth of the edge vs 40 slices
// (relative; measured 4.4e-6); the ratio of successive slice errors
// (second order: 4; measured 3.6 and 3.9); the nonlinear series vs 640
// slices (relative to its peak; measured 4.7e-6) and the share of the arc
// in air (absolute; measured 9e-5); with process damping, the edge vs 40
// slices (relative; the slices' own error at 40).
constexpr double kEdgeLimit = 1e-5;
constexpr double kEdgeOrderMin = 3.0, kEdgeOrderMax = 5.5;
constexpr double kEdgeSeries = 2e-5;
constexpr double kEdgeAir = 5e-4;
// Linear series on the edge vs 640 slices: the largest |chip| relative to
// its peak. The slices read the chip at their midpoints, half a slice
// (1/1280 of the edge) inside the edge's ends, where the largest |h| often
// sits: a first-order difference, measured 1.2e-3.
constexpr double kEdgeChip = 3e-3;
// Mean force over whole revolutions vs the closed form −a H₀ (f_z, 0) and
// between helix and straight: the sample mean of a force that jumps at the
// tooth entry has an O(1/M) quadrature error (M = 512 samples per period).
// Measured 9e-4 (straight) and 5e-5 (helix: its force is continuous).
constexpr double kMeanForce = 5e-3;
// Variable pitch path with equal pitch given explicitly vs the uniform path:
// same equation, different stop grid: integration tolerance.
// Measured 1.2e-12 (equal pitch), 2.2e-5 (near-equal pitch, per
// revolution), 1.1e-7 (near-equal helix, per revolution).
constexpr double kSamePath = 1e-4;
// Process damping boundary: the exact (a, ω) of the delay equation is
// bracketed by ±5 % in depth; at high speed the damped and undamped exact
// limits differ by less than this (relative).
// (Measured |mu| per revolution: 0.960 and 1.038 at 300 rev/min; 0.974 and
// 1.022 at 20 000 rev/min, where the two exact limits differ by 0.38 %.)
constexpr double kBoundaryBand = 0.05;
constexpr double kHighSpeedLimit = 0.01;
// Two lobe searches whose brackets are 1 % wide (depth_tolerance) around the
// same boundary.
constexpr double kBisection = 0.01;
// Milling process damping: decay rate per tooth period vs the averaged
// closed form (measured 7.5e-4 relative): the averaging error is small in
// the damping over the vibration frequency.
constexpr double kPdDecayRate = 1e-2;

// ---- helpers ----
StructuralModel stiff_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(3000.0, 0.05, 1e9, {1.0, 0.0}));
  return m;
}

StructuralModel case_c() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  return m;
}

MillingParameters four_teeth_quarter() {
  MillingParameters p;
  p.teeth = 4;
  p.tangential_coefficient_n_per_m2 = 6e8;
  p.radial_coefficient_n_per_m2 = 2e8;
  p.radial_immersion = 0.25;  // down milling: arc [120°, 180°], narrower than any pitch below
  p.direction = MillingDirection::kDown;
  p.tool_diameter_m = 0.01;
  return p;
}

// Simulated chip of each tooth when it passes φ = 150° (only that tooth is
// in the 60° arc then) in the last of 6 revolutions at 3000 rev/min, on the
// stiff tool at 10 µm depth; 720 samples per revolution put every 10° on the
// grid.
std::vector<double> chips_at_150(const Process& p, bool multiple) {
  TimeDomainOptions o;
  // The run's period is the Floquet period: repeat_teeth tooth periods.
  const int repeat = p.repeat_teeth(p.has_runout());
  o.samples_per_period = 180;  // per tooth period: 720 per revolution
  o.samples_per_vibration_cycle = 8;  // 8 × 60 cycles = 480 < 720
  o.axial_slices = 1;
  TimeDomainSimulator sim(stiff_tool(), p, o);
  SimulationSettings s;
  s.spindle_rpm = 3000.0;
  s.depth_m = 1e-5;
  s.periods = 6 * 4 / repeat;  // 6 revolutions
  s.feed_m = 1e-4;
  s.multiple_regeneration = multiple;
  const SimulationResult r = sim.simulate(s);
  EXPECT_EQ(r.samples_per_period, 180 * repeat);
  const long per_rev = 720;
  std::vector<double> out;
  for (int j = 0; j < 4; ++j) {
    const double phase_deg = 150.0 + p.tooth_offset_rad(j) / kDeg;  // φ_j = Ωt − Θ_j = 150°
    const long i = 4 * per_rev + std::lround(phase_deg / 360.0 * per_rev);
    EXPECT_NEAR(r.series.at(static_cast<std::size_t>(i)).t_s, (4.0 + phase_deg / 360.0) * 0.02, 1e-12);
    out.push_back(r.series.at(static_cast<std::size_t>(i)).chip_m);
  }
  return out;
}

TEST(TimeDomainCutters, RunoutChipIsTheHandWorkedFormula) {
  MillingParameters mp = four_teeth_quarter();
  mp.runout_m = {0.0, 20e-6, -150e-6, 30e-6};
  const Process p = Process::milling(mp);
  // §8 by hand at φ = 150° (sin φ = 0.5), f_z = 100 µm, equal pitch: the
  // chip of tooth j is min_k (k · 50 µm + ρ_j − ρ_{j−k}), floored at 0:
  //   tooth 0: min(50 − 30, 100 + 150, 150 − 20, 200) = 20 µm
  //   tooth 1: min(50 + 20, 100 + 20 − 30, 150 + 20 + 150, 200) = 70 µm
  //   tooth 2: 50 − 150 − 20 = −120 µm < 0: cuts nothing
  //   tooth 3: min(50 + 30 + 150, 100 + 30 − 20, 150 + 30, 200) = 110 µm
  const std::vector<double> expected = {20e-6, 70e-6, 0.0, 110e-6};
  for (const bool multiple : {false, true}) {
    const std::vector<double> got = chips_at_150(p, multiple);
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(got[j], expected[j], kChipTolerance)
          << "tooth " << j << (multiple ? " (multiple regeneration)" : "") << ": simulated " << got[j]
          << " m, hand-worked " << expected[j] << " m";
  }
}

TEST(TimeDomainCutters, VariablePitchChipIsProportionalToThePitch) {
  MillingParameters mp = four_teeth_quarter();
  mp.pitch_angles_rad = {80 * kDeg, 100 * kDeg, 80 * kDeg, 100 * kDeg};
  const Process p = Process::milling(mp);
  const std::vector<double> got = chips_at_150(p, false);
  for (int j = 0; j < 4; ++j) {
    // N_t f_z θ_j / 2π sin φ
    const double expected = 4 * 1e-4 * p.pitch_angle_rad(j) / (2 * kPi) * 0.5;
    EXPECT_NEAR(got[j], expected, kChipTolerance) << "tooth " << j << ": simulated " << got[j] << " m, expected "
                                                  << expected << " m";
  }
}

// Amplitude of the force line at f (Hz) over the last `revs` revolutions:
// a DFT at one frequency over whole periods (exact for a periodic force).
double force_line(const SimulationResult& r, double f_hz, double rev_s, int revs) {
  const double t_end = r.series.back().t_s, t0 = t_end - revs * rev_s;
  std::complex<double> sx = 0, sy = 0;
  long n = 0;
  for (const SeriesSample& smp : r.series) {
    if (smp.t_s <= t0 + 1e-12) continue;
    const std::complex<double> e = std::polar(1.0, -2 * kPi * f_hz * smp.t_s);
    sx += smp.force_x_n * e;
    sy += smp.force_y_n * e;
    ++n;
  }
  return 2.0 * std::sqrt(std::norm(sx) + std::norm(sy)) / static_cast<double>(n);
}

TEST(TimeDomainCutters, RunoutShowsTheSpindleLine) {
  constexpr double kRpm = 3000.0, kRev = 60.0 / kRpm;
  auto run = [&](bool runout) {
    MillingParameters mp = four_teeth_quarter();
    if (runout) mp.runout_m = {0.0, 20e-6, -150e-6, 30e-6};
    TimeDomainOptions o;
    o.samples_per_vibration_cycle = 8;
    TimeDomainSimulator sim(stiff_tool(), Process::milling(mp), o);
    SimulationSettings s;
    s.spindle_rpm = kRpm;
    s.depth_m = 1e-3;
    s.periods = runout ? 12 : 48;  // revolutions with runout, tooth periods without: 12 revolutions
    const SimulationResult r = sim.simulate(s);
    EXPECT_EQ(r.verdict, SimulationVerdict::kStable) << r.verdict_measure;
    return std::pair{force_line(r, kRpm / 60.0, kRev, 8), force_line(r, 4 * kRpm / 60.0, kRev, 8)};
  };
  const auto [spindle_ro, tooth_ro] = run(true);
  const auto [spindle_0, tooth_0] = run(false);
  EXPECT_GE(spindle_ro, kRunoutLineMin * tooth_ro)
      << "runout: spindle line " << spindle_ro << " N, tooth-passing line " << tooth_ro << " N";
  EXPECT_LE(spindle_0, kNoRunoutLineMax * tooth_0)
      << "no runout: spindle line " << spindle_0 << " N, tooth-passing line " << tooth_0 << " N";
}

// A run on case C (2 teeth, a_e/D = 0.05 down, 922 Hz, 10 mm cutter) at
// 10 000 rev/min: `slices` axial slices (0: automatic), nonlinear with
// `feed_m` or linear, its series recorded or not.
SimulationResult case_c_run(const MillingParameters& mp, int slices, double depth_m, int periods, bool linear,
                            double feed_m, double rtol, bool record_series) {
  TimeDomainOptions o;
  o.axial_slices = slices;
  o.relative_tolerance = rtol;
  TimeDomainSimulator sim(case_c(), Process::milling(mp), o);
  SimulationSettings s;
  s.spindle_rpm = 10000.0;
  s.depth_m = depth_m;
  s.periods = periods;
  s.linear = linear;
  s.feed_m = feed_m;
  s.record_series = record_series;
  return sim.simulate(s);
}

// Linear mode: growth per tooth period.
double case_c_growth(const MillingParameters& mp, int slices, double depth_m, int periods = 60, double rtol = 1e-7) {
  return case_c_run(mp, slices, depth_m, periods, true, 0.0, rtol, false).growth_per_period;
}

// The recorded series at rtol 1e-9 (edge-vs-slices comparisons).
SimulationResult case_c_series(const MillingParameters& mp, int slices, double depth_m, int periods, bool linear,
                               double feed_m) {
  return case_c_run(mp, slices, depth_m, periods, linear, feed_m, 1e-9, true);
}

MillingParameters case_c_cutter() {
  MillingParameters p;
  p.teeth = 2;
  p.tangential_coefficient_n_per_m2 = 6e8;
  p.radial_coefficient_n_per_m2 = 2e8;
  p.radial_immersion = 0.05;
  p.direction = MillingDirection::kDown;
  p.tool_diameter_m = 0.01;
  return p;
}

TEST(TimeDomainCutters, HelixSliceConvergence) {
  MillingParameters mp = case_c_cutter();
  mp.helix_angles_rad = {30 * kDeg};  // lag over 6 mm: 0.69 rad, wider than the 0.45 rad arc
  // Near the limit (|mu| = 1.047 per tooth period): the growth that decides.
  constexpr double kDepth = 6e-3;
  const double g20 = case_c_growth(mp, 20, kDepth), g40 = case_c_growth(mp, 40, kDepth),
               g80 = case_c_growth(mp, 80, kDepth);
  EXPECT_NEAR(g20, g80, kSliceConvergence * g80) << "20 slices " << g20 << ", 80 slices " << g80;
  // Second order in 1/N_z (midpoint rule): halving the slice height divides
  // the change by about 4.
  const double ratio = (g20 - g40) / (g40 - g80);
  EXPECT_GT(ratio, kOrderRatioMin) << "20: " << g20 << ", 40: " << g40 << ", 80: " << g80;
  EXPECT_LT(ratio, kOrderRatioMax) << "20: " << g20 << ", 40: " << g40 << ", 80: " << g80;
  // The helix changes the answer (else this test could not fail).
  const double straight = case_c_growth(case_c_cutter(), 0, kDepth);
  EXPECT_GT(std::abs(g80 - straight), 10 * kSliceConvergence * g80) << "helix " << g80 << ", straight " << straight;
}

// The exact edge (automatic slices, one helix angle) is the limit of the
// slices: the midpoint slices' error falls as 1/N_z², so the change from N
// to 2N slices is 3/4 of the N-slice error. Measured at rtol 1e-9 on the
// 30° helix near the limit (growth ~1.05): the edge and 80 slices within
// kEdgeLimit, and the slices' error N = 20 -> 40 down by 4 (second order
// towards the edge, not towards another value).
TEST(TimeDomainCutters, ExactEdgeIsTheLimitOfTheSlices) {
  MillingParameters mp = case_c_cutter();
  mp.helix_angles_rad = {30 * kDeg};
  constexpr double kDepth = 6e-3, kRtol = 1e-9;
  const double edge = case_c_growth(mp, 0, kDepth, 60, kRtol);
  const double g10 = case_c_growth(mp, 10, kDepth, 60, kRtol), g20 = case_c_growth(mp, 20, kDepth, 60, kRtol),
               g40 = case_c_growth(mp, 40, kDepth, 60, kRtol);
  EXPECT_NEAR(g40, edge, kEdgeLimit * edge) << "40 slices " << g40 << ", exact edge " << edge;
  const double r1 = (g10 - edge) / (g20 - edge), r2 = (g20 - edge) / (g40 - edge);
  EXPECT_GT(r1, kEdgeOrderMin) << "10: " << g10 << ", 20: " << g20 << ", edge: " << edge;
  EXPECT_LT(r1, kEdgeOrderMax) << "10: " << g10 << ", 20: " << g20 << ", edge: " << edge;
  EXPECT_GT(r2, kEdgeOrderMin) << "20: " << g20 << ", 40: " << g40 << ", edge: " << edge;
  EXPECT_LT(r2, kEdgeOrderMax) << "20: " << g20 << ", 40: " << g40 << ", edge: " << edge;
}

// The nonlinear cut on the exact edge against many slices: a chattering
// run on the 30° helix (teeth leave the cut), 20 tooth periods from rest
// with the feed: the relative displacement at every sample and the share
// of the arc in air.
TEST(TimeDomainCutters, ExactEdgeNonlinearMatchesFineSlices) {
  MillingParameters mp = case_c_cutter();
  mp.helix_angles_rad = {30 * kDeg};
  auto run = [&](int slices) { return case_c_series(mp, slices, 8e-3, 20, false, 5e-5); };
  const SimulationResult edge = run(0), fine = run(640);
  EXPECT_EQ(edge.axial_slices, 0);
  EXPECT_EQ(fine.axial_slices, 640);
  ASSERT_EQ(edge.series.size(), fine.series.size());
  double worst = 0.0, peak = 0.0;
  for (std::size_t i = 0; i < edge.series.size(); ++i) {
    worst = std::max(worst, std::hypot(edge.series[i].rel_x_m - fine.series[i].rel_x_m,
                                       edge.series[i].rel_y_m - fine.series[i].rel_y_m));
    peak = std::max(peak, std::hypot(fine.series[i].rel_x_m, fine.series[i].rel_y_m));
  }
  EXPECT_LT(worst, kEdgeSeries * peak) << "edge vs 640 slices, peak " << peak;
  ASSERT_TRUE(fine.teeth_leave_cut);  // the clipped chip is exercised
  EXPECT_NEAR(edge.out_of_cut_fraction, fine.out_of_cut_fraction, kEdgeAir);
}

// Process damping on the exact edge: −(C_pd/V) ∫ (n·ṙ) n dz in closed form,
// against the slices' sum at 20 and 40 slices (second order towards it).
TEST(TimeDomainCutters, ExactEdgeProcessDampingIsTheLimitOfTheSlices) {
  MillingParameters mp = case_c_cutter();
  mp.helix_angles_rad = {30 * kDeg};
  mp.process_damping_coefficient_n_per_m = 2e4;
  constexpr double kDepth = 6e-3, kRtol = 1e-9;
  const double edge = case_c_growth(mp, 0, kDepth, 60, kRtol), g20 = case_c_growth(mp, 20, kDepth, 60, kRtol),
               g40 = case_c_growth(mp, 40, kDepth, 60, kRtol);
  MillingParameters no_damping = mp;
  no_damping.process_damping_coefficient_n_per_m = 0.0;
  const double undamped = case_c_growth(no_damping, 0, kDepth, 60, kRtol);
  ASSERT_GT(std::abs(edge - undamped), 100 * kEdgeLimit);  // the damping matters here
  const double ratio = (g20 - edge) / (g40 - edge);
  EXPECT_GT(ratio, kEdgeOrderMin) << "20: " << g20 << ", 40: " << g40 << ", edge: " << edge;
  EXPECT_LT(ratio, kEdgeOrderMax) << "20: " << g20 << ", 40: " << g40 << ", edge: " << edge;
}

// Linear mode on the exact edge reports the same series as fine slices:
// displacement and the unclipped chip at every sample, and the in-cut flag
// (some of an edge inside the arc with h > 0) wherever the edge sets it.
// The slices' flag may also be set where the edge's chip is <= 0 all
// through the arc but 0 at its end (sin π = 0 at a down-milling exit): a
// slice half out of the arc sees its chip at a midpoint beyond the end.
TEST(TimeDomainCutters, ExactEdgeLinearSeriesMatchesFineSlices) {
  MillingParameters mp = case_c_cutter();
  mp.helix_angles_rad = {30 * kDeg};
  auto run = [&](int slices) { return case_c_series(mp, slices, 6e-3, 10, true, 0.0); };
  const SimulationResult edge = run(0), fine = run(640);
  ASSERT_EQ(edge.series.size(), fine.series.size());
  double peak = 0.0, chip_peak = 0.0, worst = 0.0, chip_worst = 0.0;
  std::size_t edge_cut = 0, both_cut = 0;
  for (std::size_t i = 0; i < edge.series.size(); ++i) {
    const SeriesSample &e = edge.series[i], &f = fine.series[i];
    peak = std::max(peak, std::hypot(f.rel_x_m, f.rel_y_m));
    worst = std::max(worst, std::hypot(e.rel_x_m - f.rel_x_m, e.rel_y_m - f.rel_y_m));
    chip_peak = std::max(chip_peak, f.chip_m);
    chip_worst = std::max(chip_worst, std::abs(e.chip_m - f.chip_m));
    edge_cut += e.in_cut ? 1 : 0;
    both_cut += e.in_cut && f.in_cut ? 1 : 0;
  }
  EXPECT_LT(worst, kEdgeSeries * peak);
  EXPECT_LT(chip_worst, kEdgeChip * chip_peak);
  ASSERT_GT(edge_cut, edge.series.size() / 10);  // the flag is exercised
  EXPECT_EQ(both_cut, edge_cut);
}

// At zero depth the edge has no length: no force, no air time (0, not 0/0).
TEST(TimeDomainCutters, ExactEdgeAtZeroDepthCutsNothing) {
  MillingParameters mp = case_c_cutter();
  mp.helix_angles_rad = {30 * kDeg};
  TimeDomainSimulator sim(case_c(), Process::milling(mp));
  SimulationSettings s;
  s.spindle_rpm = 10000.0;
  s.depth_m = 0.0;
  s.periods = 20;
  s.feed_m = 5e-5;
  const SimulationResult r = sim.simulate(s);
  EXPECT_EQ(r.axial_slices, 0);
  EXPECT_EQ(r.out_of_cut_fraction, 0.0);
  for (const double f : r.out_of_cut_fraction_per_tooth) EXPECT_EQ(f, 0.0);
  EXPECT_TRUE(std::isfinite(r.max_amplitude_m));
  EXPECT_EQ(r.verdict, SimulationVerdict::kStable);
}

TEST(TimeDomainCutters, VanishingHelixIsTheStraightCutter) {
  MillingParameters mp = case_c_cutter();
  mp.helix_angles_rad = {1e-6};
  const double helix = case_c_growth(mp, 20, 3e-3), straight = case_c_growth(case_c_cutter(), 0, 3e-3);
  EXPECT_NEAR(helix, straight, kStraightLimit * straight) << "beta = 1e-6 rad: " << helix << ", straight " << straight;
}

TEST(TimeDomainCutters, MeanForceDoesNotDependOnTheHelix) {
  constexpr double kRpm = 3000.0, kDepth = 2e-3, kFeed = 1e-4;
  auto mean_force = [&](const MillingParameters& mp) {
    TimeDomainOptions o;
    o.samples_per_period = 512;
    o.samples_per_vibration_cycle = 8;
    TimeDomainSimulator sim(stiff_tool(), Process::milling(mp), o);
    SimulationSettings s;
    s.spindle_rpm = kRpm;
    s.depth_m = kDepth;
    s.periods = 40;  // tooth periods: 10 revolutions
    s.feed_m = kFeed;
    const SimulationResult r = sim.simulate(s);
    // Mean over the last 5 revolutions (20 tooth periods), trapezoid rule.
    const std::size_t n = r.series.size(), m = 20 * static_cast<std::size_t>(r.samples_per_period);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (std::size_t i = n - 1 - m; i + 1 < n; ++i)
      sum += 0.5 * Eigen::Vector2d(r.series[i].force_x_n + r.series[i + 1].force_x_n,
                                   r.series[i].force_y_n + r.series[i + 1].force_y_n);
    return Eigen::Vector2d(sum / static_cast<double>(m));
  };
  MillingParameters straight = four_teeth_quarter();
  MillingParameters helix = straight;
  helix.helix_angles_rad = {45 * kDeg};  // lag 0.8 rad over 2 mm: longer than the 60° arc
  const Process p = Process::milling(straight);
  const Eigen::Vector2d exact = -kDepth * p.average_directional_matrix() * Eigen::Vector2d(kFeed, 0.0);
  const Eigen::Vector2d fs = mean_force(straight), fh = mean_force(helix);
  const double scale = exact.norm();
  EXPECT_LE((fs - exact).norm(), kMeanForce * scale) << "straight " << fs.transpose() << " vs " << exact.transpose();
  EXPECT_LE((fh - exact).norm(), kMeanForce * scale) << "helix " << fh.transpose() << " vs " << exact.transpose();
  EXPECT_LE((fh - fs).norm(), kMeanForce * scale) << "helix " << fh.transpose() << " vs straight " << fs.transpose();
}

TEST(TimeDomainCutters, EqualPitchGivenExplicitlyIsTheUniformCutter) {
  const double uniform = case_c_growth(case_c_cutter(), 0, 3.7e-3);
  // Equal pitch angles, per-tooth path (axial_slices = 1): tooth period.
  MillingParameters equal = case_c_cutter();
  equal.pitch_angles_rad = {kPi, kPi};
  const double explicit_equal = case_c_growth(equal, 1, 3.7e-3);
  EXPECT_NEAR(explicit_equal, uniform, kSamePath * uniform) << explicit_equal << " vs " << uniform;
  // Pitch 1e-7 rad off equal: a variable-pitch cutter, simulated per
  // revolution (two tooth periods): |mu_rev| = |mu_tooth|².
  MillingParameters almost = case_c_cutter();
  almost.pitch_angles_rad = {kPi + 1e-7, kPi - 1e-7};
  ASSERT_TRUE(Process::milling(almost).has_variable_pitch());
  const double per_rev = case_c_growth(almost, 0, 3.7e-3, 30);
  EXPECT_NEAR(per_rev, uniform * uniform, 2 * kSamePath * uniform * uniform)
      << "per revolution " << per_rev << " vs uniform per tooth squared " << uniform * uniform;
}

TEST(TimeDomainCutters, NearlyEqualHelixAnglesAreTheUniformHelix) {
  // A variable helix 1e-7 rad off a uniform 30° helix: per-slice delays,
  // simulated per revolution; |mu_rev| = |mu_tooth|² of the uniform helix.
  MillingParameters uniform = case_c_cutter();
  uniform.helix_angles_rad = {30 * kDeg};
  MillingParameters variable = case_c_cutter();
  variable.helix_angles_rad = {30 * kDeg, 30 * kDeg + 1e-7};
  ASSERT_TRUE(Process::milling(variable).has_variable_helix());
  const double per_tooth = case_c_growth(uniform, 20, 6e-3), per_rev = case_c_growth(variable, 20, 6e-3, 30);
  EXPECT_NEAR(per_rev, per_tooth * per_tooth, 2 * kSamePath * per_tooth * per_tooth)
      << "variable helix per revolution " << per_rev << " vs uniform helix per tooth squared " << per_tooth * per_tooth;
}

TEST(TimeDomainCutters, MillingProcessDampingAveragesToItsClosedForm) {
  // Full slot, 2 teeth, negligible cutting (K_t = 1e-3 N/m²): the free
  // vibration of the 922 Hz mode decays under c + C_pd (a/V) sin² φ(t),
  // whose mean is c + C_pd (a/V) N_t/4 ((N_t/2π) ∫_0^π sin² φ dφ, one tooth
  // always in the slot); with 9 vibration cycles per tooth period and a
  // damping that varies only at the tooth frequency (far from 2ω), the
  // decay per tooth period is exp(−(c + C_pd a N_t/(4V)) τ / 2m).
  constexpr double kRpm = 3000.0, kDepth = 1e-3, kCpd = 15000.0, kD = 0.01;
  const double m = 0.03993, w = 2 * kPi * 922.0, c = 2 * 0.011 * m * w;
  MillingParameters mp;
  mp.teeth = 2;
  mp.tangential_coefficient_n_per_m2 = 1e-3;
  mp.radial_coefficient_n_per_m2 = 0.0;
  mp.radial_immersion = 1.0;
  mp.tool_diameter_m = kD;
  mp.process_damping_coefficient_n_per_m = kCpd;
  TimeDomainSimulator sim(case_c(), Process::milling(mp));
  SimulationSettings s;
  s.spindle_rpm = kRpm;
  s.depth_m = kDepth;
  s.periods = 40;
  s.linear = true;
  s.record_series = false;
  const double growth = sim.simulate(s).growth_per_period;
  const double tau = 60.0 / (kRpm * 2), v = kPi * kD * kRpm / 60.0;
  const double expected = std::exp(-(c + kCpd * kDepth / v * 2.0 / 4.0) * tau / (2 * m));
  const double undamped = std::exp(-c * tau / (2 * m));
  ASSERT_LT(expected, 0.7 * undamped);  // the process damping is a large part of the decay
  EXPECT_NEAR(std::log(growth), std::log(expected), kPdDecayRate * std::abs(std::log(expected)))
      << "growth per tooth period " << growth << ", averaged closed form " << expected;
}

TEST(TimeDomainCutters, LobeSearchWithVariablePitchCountsToothPeriods) {
  // The lobe search on a pitch 1e-7 rad off equal (runs of 100 revolutions
  // = 200 tooth periods) finds the uniform cutter's limit: both brackets
  // are 1 % wide around the same boundary.
  TimeDomainOptions o;
  o.depth_max_m = 0.01;
  o.linear = true;
  MillingParameters almost = case_c_cutter();
  almost.pitch_angles_rad = {kPi + 1e-7, kPi - 1e-7};
  const TimeDomainSolver uniform(case_c(), Process::milling(case_c_cutter()), o);
  const TimeDomainSolver variable(case_c(), Process::milling(almost), o);
  EXPECT_EQ(variable.verdict_run(20000, 1e-3).periods, 100);
  const double a_u = uniform.limit_at(SpindleSpeed(20000)).depth_limit_m, a_v = variable.limit_at(SpindleSpeed(20000)).depth_limit_m;
  ASSERT_TRUE(std::isfinite(a_u)) << "no limit below 10 mm";
  EXPECT_NEAR(a_v, a_u, kBisection * a_u) << "variable pitch " << a_v << " m, uniform " << a_u << " m";
}

// ---- process damping, 1-DOF turning (case A) ----
struct Turning1Dof {
  double m, c, k, kf, cpd, diameter;
};

// Exact boundary of m ẍ + (c + C_pd a/V) ẋ + k x = −K_f a (x − x_τ) at
// `rpm`: with s = jω, the real part gives a(ω) = (mω² − k) / (K_f (1 − cos ωτ))
// and the imaginary part g(ω) = ω (c + C_pd a(ω)/V) + K_f a(ω) sin ωτ = 0;
// the smallest a > 0 over the roots of g on ω in (ω_n, 4 ω_n).
double exact_limit(const Turning1Dof& s, double rpm) {
  const double tau = 60.0 / rpm, v = kPi * s.diameter * rpm / 60.0, wn = std::sqrt(s.k / s.m);
  auto depth = [&](double w) { return (s.m * w * w - s.k) / (s.kf * (1.0 - std::cos(w * tau))); };
  auto g = [&](double w) {
    const double a = depth(w);
    return w * (s.c + s.cpd * a / v) + s.kf * a * std::sin(w * tau);
  };
  double best = std::numeric_limits<double>::infinity();
  const int n = 400000;
  double w0 = wn * (1.0 + 1e-9), g0 = g(w0);
  for (int i = 1; i <= n; ++i) {
    const double w1 = wn * (1.0 + 3.0 * i / n), g1 = g(w1);
    if (std::isfinite(g0) && std::isfinite(g1) && (g0 < 0) != (g1 < 0)) {
      double lo = w0, hi = w1, glo = g0;
      for (int it = 0; it < 100; ++it) {
        const double mid = 0.5 * (lo + hi), gm = g(mid);
        if ((gm < 0) == (glo < 0)) {
          lo = mid;
          glo = gm;
        } else {
          hi = mid;
        }
      }
      const double w = 0.5 * (lo + hi), a = depth(w);
      // A true root, not the jump at a pole of a(ω) (cos ωτ = 1).
      if (a > 0.0 && std::abs(g(w)) < 1e-6 * w * s.c) best = std::min(best, a);
    }
    w0 = w1;
    g0 = g1;
  }
  return best;
}

double turning_growth(const Turning1Dof& s, double rpm, double depth_m, int periods) {
  StructuralModel model;
  model.tool.modes.push_back(Mode::from_stiffness(std::sqrt(s.k / s.m) / (2 * kPi), s.c / (2 * std::sqrt(s.k * s.m)),
                                                  s.k, {1.0, 0.0}));
  TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = s.kf;
  tp.process_damping_coefficient_n_per_m = s.cpd;
  tp.workpiece_diameter_m = s.diameter;
  TimeDomainSimulator sim(model, Process::turning(tp));
  SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = depth_m;
  st.periods = periods;
  st.linear = true;
  st.record_series = false;
  return sim.simulate(st).growth_per_period;
}

Turning1Dof case_a(double cpd) {
  const double k = 45e6, wn = 592.0, zeta = 0.033, m = k / (wn * wn);
  return {m, 2 * zeta * std::sqrt(k * m), k, 2.4e9, cpd, 0.1};
}

TEST(TimeDomainCutters, ProcessDampingTurningBoundaryAtLowSpeed) {
  constexpr double kRpm = 300.0;  // V = 1.57 m/s
  const Turning1Dof pd = case_a(1e6), none = case_a(0.0);
  const double a_pd = exact_limit(pd, kRpm), a_0 = exact_limit(none, kRpm);
  ASSERT_TRUE(std::isfinite(a_pd));
  // Process damping matters at this speed (else the test could not fail).
  ASSERT_GT(a_pd, 1.1 * a_0) << "damped " << a_pd << " m, undamped " << a_0 << " m";
  const double below = turning_growth(pd, kRpm, (1 - kBoundaryBand) * a_pd, 30);
  const double above = turning_growth(pd, kRpm, (1 + kBoundaryBand) * a_pd, 30);
  EXPECT_LT(below, 1.0) << "at 0.95 x the exact limit " << a_pd << " m";
  EXPECT_GT(above, 1.0) << "at 1.05 x the exact limit " << a_pd << " m";
}

TEST(TimeDomainCutters, ProcessDampingVanishesAtHighSpeed) {
  constexpr double kRpm = 20000.0;  // V = 105 m/s
  const Turning1Dof pd = case_a(1e6), none = case_a(0.0);
  const double a_pd = exact_limit(pd, kRpm), a_0 = exact_limit(none, kRpm);
  ASSERT_TRUE(std::isfinite(a_0));
  EXPECT_NEAR(a_pd, a_0, kHighSpeedLimit * a_0) << "damped " << a_pd << " m, undamped " << a_0 << " m";
  EXPECT_LT(turning_growth(pd, kRpm, (1 - kBoundaryBand) * a_0, 200), 1.0) << "0.95 x undamped limit " << a_0;
  EXPECT_GT(turning_growth(pd, kRpm, (1 + kBoundaryBand) * a_0, 200), 1.0) << "1.05 x undamped limit " << a_0;
}

TEST(TimeDomainCutters, RefusesTeethThatOvertakeTheirPredecessor) {
  MillingParameters mp = case_c_cutter();
  mp.pitch_angles_rad = {170 * kDeg, 190 * kDeg};
  mp.helix_angles_rad = {10 * kDeg, 80 * kDeg};  // lag difference 1.1 rad/mm eats the 170° pitch at 2.7 mm
  TimeDomainSimulator sim(case_c(), Process::milling(mp));
  SimulationSettings s;
  s.spindle_rpm = 10000.0;
  s.depth_m = 5e-3;
  s.periods = 4;
  EXPECT_THROW(sim.simulate(s), InputError);
}

}  // namespace
}  // namespace chatter
