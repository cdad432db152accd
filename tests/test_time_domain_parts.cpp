// The parts of the time-domain solver tested on their own, each against an
// answer built into the input (src/solvers/time_domain_parts.hpp,
// src/solvers/depth_search.hpp):
//  - history interpolation: quintic Hermite on r, ṙ, r̈ is exact for
//    polynomials of degree <= 5 (also across a jump of r̈ at an entry), and its
//    error on a smooth signal falls with the 6th power of the spacing;
//  - growth per period (exact DMD): snapshots built from known multipliers
//    give the dominant one back, through the linear-mode rescaling and the
//    nonlinear-mode increments;
//  - spectrum: a sum of known sinusoids gives their frequencies within a bin
//    and amplitudes within the Hann window's scalloping loss, with the
//    tooth-passing harmonics marked and the chatter frequency off them;
//  - verdict: constructed growing, decaying and bounded series;
//  - depth search: bracketing and refinement of a known threshold.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "depth_search.hpp"
#include "time_domain_parts.hpp"

namespace chatter::detail {
namespace {

constexpr double kPi = std::numbers::pi;

// Tolerances (relative unless said).
// Polynomial reproduction: the Hermite weights sum the data exactly, so only
// rounding of O(10) terms of size |p| is left.
constexpr double kPolynomialExact = 1e-12;
// Observed convergence order of the quintic Hermite interpolant (6 in
// theory, the local error being O(h⁶)); ±0.3 covers the pre-asymptotic drift
// at 16..64 points per period of the test signal.
constexpr double kHermiteOrder = 6.0;
constexpr double kOrderSlack = 0.3;
// DMD of noise-free snapshots: the eigenvalues of the projected map are exact
// up to the conditioning of the SVD and the eigensolver.
constexpr double kDmdExact = 1e-8;
// Spectrum: a sinusoid on a bin reads its amplitude up to the leakage of the
// symmetric (n − 1) Hann window and of the other components, < 1 % here.
constexpr double kOnBinAmplitude = 0.01;
// Worst-case Hann scalloping loss, half a bin off: 0.8488 (−1.42 dB).
constexpr double kHannScallop = 0.8488;
// Hann sidelobes stay below −31.5 dB of the tone (0.0266); 0.03 with margin.
constexpr double kHannSidelobe = 0.03;

// ---------------------------------------------------------------------------
// History.

// p(t) = Σ c_k t^k and its first two derivatives.
struct Poly {
  std::vector<double> c;
  double operator()(double t) const {
    double s = 0.0;
    for (std::size_t k = c.size(); k-- > 0;) s = s * t + c[k];
    return s;
  }
  Poly derivative() const {
    Poly d;
    for (std::size_t k = 1; k < c.size(); ++k) d.c.push_back(static_cast<double>(k) * c[k]);
    if (d.c.empty()) d.c.push_back(0.0);
    return d;
  }
};

HistoryEntry entry(double t, const Poly& px, const Poly& py) {
  HistoryEntry e;
  e.t = t;
  const Poly vx = px.derivative(), vy = py.derivative(), ax = vx.derivative(), ay = vy.derivative();
  e.r[0] = px(t);
  e.r[1] = py(t);
  e.v[0] = vx(t);
  e.v[1] = vy(t);
  e.a_left[0] = e.a_right[0] = ax(t);
  e.a_left[1] = e.a_right[1] = ay(t);
  return e;
}

TEST(History, ExactForQuinticPolynomialsOnAnUnevenGrid) {
  const Poly px{{0.3, -1.2, 0.7, 2.0, -0.9, 0.4}};  // degree 5
  const Poly py{{-0.5, 0.1, -0.3, 0.0, 1.1, -0.6}};
  const std::vector<double> times = {0.0, 0.13, 0.2, 0.47, 0.5, 0.81, 1.0};
  const double gaps[1] = {0.0};
  History h(4, 1);  // grows on push
  for (double t : times) h.push(entry(t, px, py), gaps);
  double worst = 0.0;
  for (int i = 0; i <= 1000; ++i) {
    const double t = i / 1000.0;
    double r[2];
    h.displacement(t, r);
    worst = std::max({worst, std::abs(r[0] - px(t)), std::abs(r[1] - py(t))});
  }
  EXPECT_LT(worst, kPolynomialExact) << "largest error " << worst;
  EXPECT_EQ(h.extrapolations(), 0);
}

TEST(History, SixthDegreeIsNotReproduced) {
  // The same check fails one degree up: the test above can fail.
  const Poly px{{0, 0, 0, 0, 0, 0, 1.0}}, py{{0.0}};
  const double gaps[1] = {0.0};
  History h(4, 1);
  h.push(entry(0.0, px, py), gaps);
  h.push(entry(1.0, px, py), gaps);
  double r[2];
  h.displacement(0.5, r);
  // Error of the Hermite interpolant of t⁶ at s = 1/2: (s(1 − s))³ = 1/64.
  EXPECT_NEAR(std::abs(r[0] - px(0.5)), 1.0 / 64.0, kPolynomialExact);
}

TEST(History, OneSidedAccelerationsKeepAJumpOfTheForce) {
  // r is C¹ at t = 1 with a jump of r̈ (a tooth enters the cut): each side is
  // its own quintic, and a_right / a_left keep both sides exact.
  const Poly left{{0.0, 1.0, 0.5, -0.2, 0.1, 0.03}};
  // right(t) = left(t) + 0.8 (t − 1)² : same value and slope at 1, r̈ + 1.6.
  Poly right = left;
  right.c[0] += 0.8;
  right.c[1] += -1.6;
  right.c[2] += 0.8;
  const Poly zero{{0.0}};
  const double gaps[1] = {0.0};
  History h(8, 1);
  h.push(entry(0.0, left, zero), gaps);
  h.push(entry(0.6, left, zero), gaps);
  HistoryEntry at_jump = entry(1.0, left, zero);
  at_jump.a_right[0] = entry(1.0, right, zero).a_left[0];
  h.push(at_jump, gaps);
  h.push(entry(1.4, right, zero), gaps);
  h.push(entry(2.0, right, zero), gaps);
  double worst = 0.0;
  for (int i = 0; i <= 400; ++i) {
    const double t = 2.0 * i / 400.0;
    double r[2];
    h.displacement(t, r);
    worst = std::max(worst, std::abs(r[0] - (t <= 1.0 ? left(t) : right(t))));
  }
  EXPECT_LT(worst, kPolynomialExact) << "largest error " << worst;
}

// Largest error interpolating r = (sin ωt, cos 1.7ωt) sampled every h.
double smooth_signal_error(double h) {
  const double w = 2 * kPi;
  const double gaps[1] = {0.0};
  History hist(8, 1);
  for (double t = 0.0; t <= 2.0 + 1e-12; t += h) {
    HistoryEntry e;
    e.t = t;
    e.r[0] = std::sin(w * t);
    e.v[0] = w * std::cos(w * t);
    e.a_left[0] = e.a_right[0] = -w * w * std::sin(w * t);
    e.r[1] = std::cos(1.7 * w * t);
    e.v[1] = -1.7 * w * std::sin(1.7 * w * t);
    e.a_left[1] = e.a_right[1] = -1.7 * 1.7 * w * w * std::cos(1.7 * w * t);
    hist.push(e, gaps);
  }
  double worst = 0.0;
  for (int i = 0; i < 5000; ++i) {
    const double t = 1.9 * i / 5000.0 + 0.01;
    double r[2];
    hist.displacement(t, r);
    worst = std::max({worst, std::abs(r[0] - std::sin(w * t)), std::abs(r[1] - std::cos(1.7 * w * t))});
  }
  return worst;
}

TEST(History, ErrorFallsWithTheSixthPowerOfTheSpacing) {
  const double e1 = smooth_signal_error(1.0 / 16), e2 = smooth_signal_error(1.0 / 32), e3 = smooth_signal_error(1.0 / 64);
  const double order12 = std::log2(e1 / e2), order23 = std::log2(e2 / e3);
  EXPECT_NEAR(order12, kHermiteOrder, kOrderSlack) << "errors " << e1 << ", " << e2;
  EXPECT_NEAR(order23, kHermiteOrder, kOrderSlack) << "errors " << e2 << ", " << e3;
}

TEST(History, RingBufferDropsOldEntriesAndCountsLookupsOutsideIt) {
  const Poly px{{1.0, 2.0, -1.0}}, py{{0.0, 1.0}};
  const double gaps[1] = {0.0};
  History h(16, 1);
  for (int i = 0; i < 1000; ++i) {
    h.push(entry(0.01 * i, px, py), gaps);
    h.drop_before(0.01 * i - 0.05);  // keeps about 6 entries
  }
  EXPECT_EQ(h.capacity(), 16u) << "the buffer grew although entries were dropped";
  EXPECT_LE(h.max_count(), 8u);
  double r[2];
  h.displacement(9.97, r);
  EXPECT_NEAR(r[0], px(9.97), kPolynomialExact * std::abs(px(9.97)));
  EXPECT_EQ(h.extrapolations(), 0);
  h.displacement(1.0, r);  // long dropped
  EXPECT_EQ(h.extrapolations(), 1);
}

// ---------------------------------------------------------------------------
// Growth per period (DMD).

// Snapshots z_k = Σ_j Re(c_j μ_j^k v_j), k = 0..K−1, in dimension d.
struct KnownMode {
  std::complex<double> mu;
  double amplitude;
};
std::vector<Eigen::VectorXd> snapshots(const std::vector<KnownMode>& modes, int K, int d, const Eigen::VectorXd& offset) {
  std::vector<Eigen::VectorXcd> shapes;
  for (std::size_t j = 0; j < modes.size(); ++j) {
    Eigen::VectorXcd v(d);
    for (int i = 0; i < d; ++i)
      v(i) = {std::cos(0.7 * i * static_cast<double>(j + 1) + 0.3), std::sin(1.3 * i + 0.5 * static_cast<double>(j))};
    shapes.push_back(v);
  }
  std::vector<Eigen::VectorXd> out;
  for (int k = 0; k < K; ++k) {
    Eigen::VectorXd z = offset;
    for (std::size_t j = 0; j < modes.size(); ++j)
      z += (modes[j].amplitude * std::pow(modes[j].mu, k) * shapes[j]).real();
    out.push_back(z);
  }
  return out;
}

TEST(GrowthPerPeriod, DominantMultiplierOfKnownModes) {
  const std::complex<double> hopf = std::polar(0.97, 0.8);
  const int d = 12;
  PeriodSnapshots s;
  s.states = snapshots({{hopf, 1.0}, {0.6, 2.0}, {-0.9, 0.5}}, 30, d, Eigen::VectorXd::Zero(d));
  s.log_scale.assign(s.states.size(), 0.0);
  const GrowthEstimate g = growth_per_period(s, 0, /*linear=*/true, 1e-10);
  EXPECT_NEAR(g.multiplier.real(), hopf.real(), kDmdExact) << g.multiplier;
  EXPECT_NEAR(g.multiplier.imag(), hopf.imag(), kDmdExact) << g.multiplier;  // Im >= 0 of the pair
}

TEST(GrowthPerPeriod, LinearRescalingIsUndone) {
  // A growing mode stored as in a linear run: rescaled by 1e-3 every 10
  // periods, with the log of the factor kept beside each snapshot.
  const int d = 8;
  PeriodSnapshots s;
  s.states = snapshots({{std::polar(1.08, 2.1), 1.0}, {0.5, 1.0}}, 40, d, Eigen::VectorXd::Zero(d));
  for (std::size_t k = 0; k < s.states.size(); ++k) {
    const double log_scale = std::log(1e3) * static_cast<double>(k / 10);
    s.states[k] *= std::exp(-log_scale);
    s.log_scale.push_back(log_scale);
  }
  const GrowthEstimate g = growth_per_period(s, 10, true, 1e-10);
  EXPECT_NEAR(std::abs(g.multiplier), 1.08, kDmdExact) << g.multiplier;
  EXPECT_NEAR(std::arg(g.multiplier), 2.1, kDmdExact) << g.multiplier;
}

TEST(GrowthPerPeriod, NonlinearModeUsesIncrementsAboutTheForcedResponse) {
  // A large periodic (forced) part plus a decaying flip transient: the
  // increments between periods carry only the transient.
  const int d = 10;
  Eigen::VectorXd forced(d);
  for (int i = 0; i < d; ++i) forced(i) = 1.0 + 0.1 * i;
  PeriodSnapshots s;
  s.states = snapshots({{-0.93, 1e-3}, {std::polar(0.7, 1.0), 1e-3}}, 40, d, forced);
  s.log_scale.assign(s.states.size(), 0.0);
  const GrowthEstimate g = growth_per_period(s, 0, /*linear=*/false, 1e-10);
  EXPECT_FALSE(g.converged);
  EXPECT_NEAR(g.multiplier.real(), -0.93, kDmdExact) << g.multiplier;
  EXPECT_NEAR(g.multiplier.imag(), 0.0, kDmdExact) << g.multiplier;
}

TEST(GrowthPerPeriod, ModesAbsentFromTheLastSnapshotAreIgnored) {
  // A slower-decaying mode excited at 1e-9 of the dominant one carries less
  // than 1e-3 of the last snapshot: it is not the "dominant" multiplier.
  const int d = 10;
  PeriodSnapshots s;
  s.states = snapshots({{0.95, 1.0}, {0.99, 1e-9}}, 20, d, Eigen::VectorXd::Zero(d));
  s.log_scale.assign(s.states.size(), 0.0);
  const GrowthEstimate g = growth_per_period(s, 0, true, 1e-10);
  EXPECT_NEAR(g.multiplier.real(), 0.95, kDmdExact) << g.multiplier;
}

TEST(GrowthPerPeriod, ConvergedWhenIncrementsFallToTheNoise) {
  const int d = 6;
  PeriodSnapshots s;
  s.states = snapshots({{0.3, 1e-2}}, 40, d, Eigen::VectorXd::Constant(d, 1.0));
  s.log_scale.assign(s.states.size(), 0.0);
  const GrowthEstimate g = growth_per_period(s, 20, false, 1e-7);
  EXPECT_TRUE(g.converged);
  EXPECT_TRUE(std::isnan(g.multiplier.real())) << "fewer than 4 usable pairs must give no estimate";
}

// ---------------------------------------------------------------------------
// Spectrum.

struct Tone {
  double f_hz, amp, phase;
};
// Samples of x = Σ tones_x, y = Σ tones_y at spacing dt.
void sample(const std::vector<Tone>& tx, const std::vector<Tone>& ty, std::size_t n, double dt, std::vector<double>& x,
            std::vector<double>& y) {
  x.assign(n, 0.5);  // an offset: the mean is removed
  y.assign(n, -0.2);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt;
    for (const Tone& s : tx) x[i] += s.amp * std::sin(2 * kPi * s.f_hz * t + s.phase);
    for (const Tone& s : ty) y[i] += s.amp * std::sin(2 * kPi * s.f_hz * t + s.phase);
  }
}
double peak_near(const Spectrum& sp, double f) {
  double a = 0.0;
  for (std::size_t k = 0; k < sp.f.size(); ++k)
    if (std::abs(sp.f[k] - f) <= sp.f[1]) a = std::max(a, sp.amp[k]);
  return a;
}

TEST(Spectrum, TonesOnBinsReadTheirAmplitudes) {
  const std::size_t n = 4096;  // a power of two: no zero padding
  const double dt = 1e-4, df = 1.0 / (n * dt);
  std::vector<double> x, y;
  sample({{100 * df, 2e-6, 0.3}, {371 * df, 5e-7, 1.0}}, {{900 * df, 1e-6, -0.4}}, n, dt, x, y);
  const Spectrum sp = amplitude_spectrum(x, y, dt);
  ASSERT_EQ(sp.f.size(), n / 2 + 1);
  EXPECT_NEAR(sp.resolution_hz, df, 1e-12 * df);
  for (auto [f, a] : {std::pair{100 * df, 2e-6}, std::pair{371 * df, 5e-7}, std::pair{900 * df, 1e-6}})
    EXPECT_NEAR(peak_near(sp, f), a, kOnBinAmplitude * a) << "tone at " << f << " Hz";
  EXPECT_LT(sp.amp[0], kOnBinAmplitude * 5e-7) << "the mean was not removed";
}

TEST(Spectrum, OffBinToneWithinTheScallopingLossAndFoundWithinABin) {
  const std::size_t n = 3000;  // zero-padded to 4096
  const double dt = 2e-4;
  const double f = 613.37;
  std::vector<double> x, y;
  sample({{f, 3e-6, 0.0}}, {{f, 1e-6, kPi / 2}}, n, dt, x, y);
  const Spectrum sp = amplitude_spectrum(x, y, dt);
  const double combined = std::hypot(3e-6, 1e-6);  // |X| combined over x and y
  const double read = peak_near(sp, f);
  EXPECT_GE(read, kHannScallop * combined * (1 - kOnBinAmplitude)) << read << " vs " << combined;
  EXPECT_LE(read, combined * (1 + kOnBinAmplitude)) << read << " vs " << combined;
  // Tooth passing at 97 Hz: f lies 31 Hz above the 6th harmonic.
  const double found = dominant_nonharmonic_hz(sp, 97.0);
  EXPECT_NEAR(found, f, sp.resolution_hz) << "resolution " << sp.resolution_hz;
}

TEST(Spectrum, ToothPassingHarmonicsAreMarkedAndSkippedForTheChatterPeak) {
  const std::size_t n = 8192;
  const double dt = 5e-5;
  const double ftp = 283.0;  // tooth passing, Hz
  const double fc = 1234.5;  // chatter, between the 4th and 5th harmonics
  std::vector<double> x, y;
  // Harmonics larger than the chatter: the largest peak is a harmonic.
  sample({{ftp, 4e-6, 0.1}, {2 * ftp, 2e-6, 0.2}, {3 * ftp, 1e-6, 0.0}, {fc, 5e-7, 0.7}}, {}, n, dt, x, y);
  const Spectrum sp = amplitude_spectrum(x, y, dt);
  EXPECT_EQ(harmonic_index(2 * ftp + 0.5 * sp.resolution_hz, ftp, sp.resolution_hz), 2);
  EXPECT_EQ(harmonic_index(fc, ftp, sp.resolution_hz), -1);
  EXPECT_NEAR(dominant_nonharmonic_hz(sp, ftp), fc, sp.resolution_hz);
  const std::vector<SpectralPeak> h = tooth_passing_harmonics(sp, ftp, 1500.0);
  ASSERT_EQ(h.size(), 5u) << "harmonics up to 1500 Hz: 283 .. 1415";
  const double amps[3] = {4e-6, 2e-6, 1e-6};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(h[k].harmonic, k + 1);
    EXPECT_DOUBLE_EQ(h[k].frequency_hz, (k + 1) * ftp);
    EXPECT_GE(h[k].amplitude_m, kHannScallop * amps[k]) << "harmonic " << k + 1;
    EXPECT_LE(h[k].amplitude_m, (1 + kOnBinAmplitude) * amps[k]) << "harmonic " << k + 1;
  }
  EXPECT_LT(h[4].amplitude_m, 0.1 * 5e-7) << "no tone at the 5th harmonic";
}

TEST(Spectrum, TooShortOrPurelyHarmonicGivesNoChatterPeak) {
  EXPECT_TRUE(amplitude_spectrum(std::vector<double>(7, 1.0), std::vector<double>(7, 0.0), 1e-3).f.empty());
  const double ftp = 250.0;
  std::vector<double> x, y;
  sample({{ftp, 1e-6, 0.0}, {2 * ftp, 1e-6, 0.0}}, {}, 4000, 1e-4, x, y);
  const Spectrum sp = amplitude_spectrum(x, y, 1e-4);
  // Only the window's sidelobes are left off the harmonics.
  const double f = dominant_nonharmonic_hz(sp, ftp);
  if (!std::isnan(f)) {
    EXPECT_LT(peak_near(sp, f), kHannSidelobe * 1e-6) << "spurious peak at " << f << " Hz";
  }
}

// ---------------------------------------------------------------------------
// Verdict: from constructed series through the growth estimate.

VerdictOutcome verdict_of(const std::vector<Eigen::VectorXd>& states, bool linear, const AirCounts& air) {
  PeriodSnapshots s;
  s.states = states;
  s.log_scale.assign(states.size(), 0.0);
  VerdictInput in;
  in.linear = linear;
  in.growth = growth_per_period(s, 0, linear, 1e-7);
  in.air = air;
  in.analysed_periods = static_cast<int>(states.size());
  in.relative_tolerance = 1e-7;
  return decide_verdict(in);
}

AirCounts air_counts(std::size_t early_in_air, std::size_t late_in_air) {
  AirCounts a;  // 1000 arc samples in each half
  for (std::size_t i = 0; i < 1000; ++i) a.add(i < early_in_air, false);
  for (std::size_t i = 0; i < 1000; ++i) a.add(i < late_in_air, true);
  return a;
}

// Nonlinear runs: a forced (periodic) part plus the vibration; linear runs:
// the vibration alone (a constant part would be a multiplier 1).
const Eigen::VectorXd kForced = Eigen::VectorXd::Constant(6, 1e-5);
const Eigen::VectorXd kNone = Eigen::VectorXd::Zero(6);

TEST(Verdict, GrowingSeriesIsChatter) {
  const KnownMode growing{std::polar(1.03, 1.2), 1e-6};
  const VerdictOutcome v = verdict_of(snapshots({growing}, 30, 6, kForced), false, AirCounts{});
  EXPECT_EQ(v.verdict, SimulationVerdict::kChatter) << v.measure;
  const VerdictOutcome lin = verdict_of(snapshots({growing}, 30, 6, kNone), true, AirCounts{});
  EXPECT_EQ(lin.verdict, SimulationVerdict::kChatter) << lin.measure;
}

TEST(Verdict, DecayingSeriesIsStable) {
  const KnownMode decaying{std::polar(0.95, 1.2), 1e-6};
  const VerdictOutcome v = verdict_of(snapshots({decaying}, 30, 6, kForced), false, AirCounts{});
  EXPECT_EQ(v.verdict, SimulationVerdict::kStable) << v.measure;
  EXPECT_NE(v.measure.find("stayed in the cut"), std::string::npos) << v.measure;
  const VerdictOutcome lin = verdict_of(snapshots({decaying}, 30, 6, kNone), true, AirCounts{});
  EXPECT_EQ(lin.verdict, SimulationVerdict::kStable) << lin.measure;
}

TEST(Verdict, BoundedPeriodicSeriesIsStable) {
  // Forced vibration only: the increments are zero.
  const std::vector<Eigen::VectorXd> z(30, kForced);
  const VerdictOutcome v = verdict_of(z, false, AirCounts{});
  EXPECT_EQ(v.verdict, SimulationVerdict::kStable);
  EXPECT_NE(v.measure.find("periodic"), std::string::npos) << v.measure;
}

TEST(Verdict, BoundedChatterWithPersistingContactLossIsChatter) {
  // A saturated flip vibration fitted at |mu| = 0.99 (between 1 − margin and
  // 1): chatter when the tool keeps leaving the cut, stable when the contact
  // loss dies out (a decaying transient).
  const auto z = snapshots({{-0.99, 1e-6}}, 30, 6, kForced);
  const VerdictOutcome persisting = verdict_of(z, false, air_counts(300, 280));
  EXPECT_EQ(persisting.verdict, SimulationVerdict::kChatter) << persisting.measure;
  const VerdictOutcome dying = verdict_of(z, false, air_counts(300, 2));
  EXPECT_EQ(dying.verdict, SimulationVerdict::kStable) << dying.measure;
  EXPECT_NEAR(air_counts(300, 280).fraction(), 0.29, 1e-15);
}

TEST(Verdict, WithoutAnEstimateContactLossDecides) {
  VerdictInput in;
  in.linear = false;  // growth NaN by default
  in.air = air_counts(0, 0);
  EXPECT_EQ(decide_verdict(in).verdict, SimulationVerdict::kStable);
  in.air = air_counts(100, 100);
  EXPECT_EQ(decide_verdict(in).verdict, SimulationVerdict::kChatter);
  in.linear = true;
  EXPECT_EQ(decide_verdict(in).verdict, SimulationVerdict::kStable) << "linear, no motion";
}

// ---------------------------------------------------------------------------
// Depth search on a verdict with a known threshold.

constexpr double kThreshold = 3.7e-3;  // m

TEST(DepthSearch, ClimbThenBisectBracketsTheThresholdToTheTolerance) {
  int probes = 0;
  auto probe = [&](double a) {
    ++probes;
    return a;
  };
  auto unstable = [](double a) { return a >= kThreshold; };
  DepthBracket<double> b = climb_to_unstable(1e-4, 1e-4, 2.0, 0.05, probe, unstable);
  ASSERT_TRUE(b.found);
  EXPECT_LT(b.lo, kThreshold);
  EXPECT_GE(b.hi, kThreshold);
  EXPECT_DOUBLE_EQ(b.hi, 2.0 * b.lo);
  bisect_bracket(b, 0.01, probe, unstable);
  EXPECT_LE(b.hi - b.lo, 0.01 * b.hi);
  EXPECT_LT(b.lo, kThreshold);
  EXPECT_GE(b.hi, kThreshold);
  EXPECT_EQ(b.at_hi, b.hi) << "each end keeps its probe value";
  EXPECT_LE(probes, 6 + 7);  // 1e-4 -> 6.4e-3 in 6 doublings, 2^-7 < 1 %
}

TEST(DepthSearch, ClimbStopsAtTheSearchedDepth) {
  auto unstable = [](double a) { return a >= 1.0; };
  const DepthBracket<double> b = climb_to_unstable(1e-3, 1e-3, 2.0, 0.05, [](double a) { return a; }, unstable);
  EXPECT_FALSE(b.found);
  EXPECT_EQ(b.lo, 0.05);
}

TEST(DepthSearch, DescendFindsAStableDepthOrReportsNone) {
  auto unstable = [](double a) { return a >= kThreshold; };
  const DepthBracket<double> b = descend_to_stable(0.04, 0.04, 2.0, 30, [](double a) { return a; }, unstable);
  ASSERT_TRUE(b.found);
  EXPECT_LT(b.lo, kThreshold);
  EXPECT_GE(b.hi, kThreshold);
  EXPECT_DOUBLE_EQ(b.hi, 2.0 * b.lo);
  const DepthBracket<double> none = descend_to_stable(0.04, 0.04, 2.0, 3, [](double a) { return a; }, unstable);
  EXPECT_FALSE(none.found);
  EXPECT_EQ(none.lo, none.hi);
  EXPECT_DOUBLE_EQ(none.hi, 0.005);
}

TEST(DepthSearch, RefineRootOfAMargin) {
  // ln ρ-like margin with its root at the threshold.
  auto margin = [](double a) { return std::log(a / kThreshold); };
  const DepthBracket<double> b{1e-3, 1e-2, margin(1e-3), margin(1e-2), true};
  const double xtol = 1e-9;
  EXPECT_NEAR(refine_root(b, margin, xtol), kThreshold, xtol);
}

}  // namespace
}  // namespace chatter::detail
