// Uncertain lobes (docs/uncertainty.md): counter-based draws, samples, the
// Monte Carlo over a range of samples and the reduction to probabilities and
// quantile lobes.
//
// Independent answers: a zero spread must give the nominal table bit for bit
// (probabilities exactly 0 / 1 on either side of today's limit); a 1-mode
// turning case with a frequency spread against a Monte Carlo written here
// (its own generator: std::mt19937_64, Box–Muller, truncation by rejection;
// its own closed-form limit: b = −1/(2 K_f Re G) on the phase condition
// ωτ = 3π + 2∠G + 2πk, solved here by bisection), within a statistical
// tolerance from the sample counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/solvers.hpp"
#include "chatter/uncertainty.hpp"

namespace chatter {
namespace {

using C = std::complex<double>;
constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Case A (configs/seed_turning_1dof.toml): 94.22 Hz, ζ 0.033, 45e6 N/m, K_f 2.4e9 N/m².
constexpr double kF0 = 94.22, kZeta = 0.033, kK = 45e6, kKf = 2.4e9;
constexpr double kDepthMax = 0.02;  // m

StructuralModel one_mode(double f = kF0) {
  StructuralModel m;
  m.workpiece.modes.push_back(Mode::from_stiffness(f, kZeta, kK, {1, 0}));
  return m;
}
Process turning() {
  TurningParameters p;
  p.feed_force_coefficient_n_per_m2 = kKf;
  return Process::turning(p);
}
SampleSolverFactory factory(const std::string& method, double depth_max = kDepthMax) {
  return [method, depth_max](const StructuralModel& m, const Process& p) {
    return make_lobe_solver(method, m, p, depth_max);
  };
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_rows(const std::vector<std::vector<StabilityLimit>>& a, const std::vector<std::vector<StabilityLimit>>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].size() != b[i].size()) return false;
    for (std::size_t s = 0; s < a[i].size(); ++s)
      if (!same_bits(a[i][s].depth_limit_m, b[i][s].depth_limit_m) ||
          !same_bits(a[i][s].chatter_frequency_hz, b[i][s].chatter_frequency_hz) || a[i][s].lobe != b[i][s].lobe)
        return false;
  }
  return true;
}

// ------------------------------------------------------------------ draws

TEST(UncertaintyDraws, PureBoundedAndStandardised) {
  // Same arguments, same bits; any argument changed, another number.
  EXPECT_TRUE(same_bits(uncertainty_normal(1, 7, 3), uncertainty_normal(1, 7, 3)));
  EXPECT_NE(uncertainty_normal(1, 7, 3), uncertainty_normal(2, 7, 3));
  EXPECT_NE(uncertainty_normal(1, 7, 3), uncertainty_normal(1, 8, 3));
  EXPECT_NE(uncertainty_normal(1, 7, 3), uncertainty_normal(1, 7, 4));
  // Moments over many samples against the normal truncated at 3 sigma:
  // mean 0, variance 1 − 2·3·φ(3)/(Φ(3) − Φ(−3)).
  constexpr int kN = 200000;
  const double phi3 = std::exp(-4.5) / std::sqrt(2 * kPi), mass = std::erf(3.0 / std::sqrt(2.0));
  const double var_exact = 1.0 - 6.0 * phi3 / mass;
  double sum = 0.0, sum2 = 0.0, sum4 = 0.0;
  for (int i = 0; i < kN; ++i) {
    const double z = uncertainty_normal(42, static_cast<std::uint64_t>(i), 5);
    ASSERT_LE(std::abs(z), kUncertaintyTruncationSigma) << "draw " << i;
    sum += z;
    sum2 += z * z;
    sum4 += z * z * z * z;
  }
  const double mean = sum / kN, var = sum2 / kN - mean * mean;
  // 5 standard errors: sd(mean) = sqrt(var / N); sd(var) = sqrt((E z⁴ − var²) / N).
  const double mean_tol = 5.0 * std::sqrt(var_exact / kN);
  const double var_tol = 5.0 * std::sqrt((sum4 / kN - var_exact * var_exact) / kN);
  EXPECT_NEAR(mean, 0.0, mean_tol);
  EXPECT_NEAR(var, var_exact, var_tol);
}

TEST(UncertaintyDraws, QuantileType7) {
  EXPECT_DOUBLE_EQ(quantile_type7({4, 1, 3, 2}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(quantile_type7({4, 1, 3, 2}, 0.05), 1.15);  // h = 0.15
  EXPECT_DOUBLE_EQ(quantile_type7({4, 1, 3, 2}, 1.0), 4.0);
  EXPECT_EQ(quantile_type7({1.0, kInf}, 0.5), kInf);  // touches +inf
  EXPECT_EQ(quantile_type7({1.0, kInf}, 0.0), 1.0);
  EXPECT_EQ(quantile_type7({kInf, kInf, kInf}, 0.5), kInf);
  EXPECT_THROW(quantile_type7({}, 0.5), InputError);
  EXPECT_THROW(quantile_type7({1.0}, 1.5), InputError);
}

TEST(UncertaintyDraws, ReduceCountsInfAsStableAndAboveEveryLimit) {
  // Four samples at one speed: limits 1, 2, 3 mm and +inf (no chatter below
  // the searched depth).
  std::vector<std::vector<StabilityLimit>> rows;
  for (const double a : {0.002, kInf, 0.001, 0.003}) {
    StabilityLimit r;
    r.spindle_rpm = 1000.0;
    r.depth_limit_m = a;
    rows.push_back({r});
  }
  const UncertainLobes u = reduce_monte_carlo(rows, {0.0, 0.001, 0.0025, 0.05}, {0.0, 0.5, 0.75, 1.0});
  // depth < limit: 4, 3 (1 mm is the boundary), 2, 1 (only the inf sample) of 4.
  EXPECT_EQ(u.probability_stable[0], (std::vector<double>{1.0, 0.75, 0.5, 0.25}));
  EXPECT_EQ(u.quantile_depth_m[0][0], 0.001);
  EXPECT_DOUBLE_EQ(u.quantile_depth_m[1][0], 0.0025);  // h = 1.5 between 2 and 3 mm
  EXPECT_EQ(u.quantile_depth_m[2][0], kInf);           // h = 2.25: between 3 mm and inf
  EXPECT_EQ(u.quantile_depth_m[3][0], kInf);
}

// --------------------------------------------------------------- spreads

TEST(UncertaintySpreads, RefusesNonPhysicalSpreads) {
  const StructuralModel m = one_mode();
  const Process p = turning();
  auto why = [&](UncertaintySpreads s) { return s.validate(m, p); };
  EXPECT_EQ(why({{0.05}, {0.1}, {0.05}, 0.05, 0.0}), "");
  EXPECT_NE(why({{-0.01}, {}, {}, 0, 0}).find("frequency = -0.01: must be a finite spread >= 0"), std::string::npos);
  EXPECT_NE(why({{}, {}, {std::nan("")}, 0, 0}).find("stiffness"), std::string::npos);
  EXPECT_NE(why({{0.34}, {}, {}, 0, 0}).find("must be < 1/3"), std::string::npos);
  EXPECT_NE(why({{0.01, 0.02}, {}, {}, 0, 0}).find("frequency: 2 values"), std::string::npos);
  EXPECT_NE(why({{}, {}, {}, 0.0, 0.05}).find("radial = 0.05: only for milling"), std::string::npos);
  StructuralModel heavy = m;
  heavy.workpiece.modes[0].damping_ratio = 0.8;  // 0.8 (1 + 3 s) < 1 needs s < 1/12
  const UncertaintySpreads damp{{}, {0.1}, {}, 0, 0};
  EXPECT_NE(damp.validate(heavy, p).find("must be < 0.0833"), std::string::npos);
  EXPECT_THROW(sample_inputs(m, p, UncertaintySpreads{{-0.1}, {}, {}, 0, 0}, 1, 0), InputError);
}

TEST(UncertaintySpreads, SampleScalesEachParameterByItsOwnDraw) {
  StructuralModel m = one_mode();
  m.tool.modes.push_back(Mode::from_stiffness(300.0, 0.05, 8e7, {0, 1}));
  const UncertaintySpreads s{{0.02, 0.04}, {0.1}, {0.05}, 0.07, 0.0};
  const UncertainSample x = sample_inputs(m, turning(), s, 9, 11);
  // Parameter numbers: 0 K_f, then 2 + 3 m + {0 f, 1 ζ, 2 k}; tool mode first.
  const Mode& tool = x.model.tool.modes[0];
  const Mode& wp = x.model.workpiece.modes[0];
  EXPECT_EQ(tool.natural_frequency_hz, 300.0 * (1.0 + 0.02 * uncertainty_normal(9, 11, 2)));
  EXPECT_EQ(tool.damping_ratio, 0.05 * (1.0 + 0.1 * uncertainty_normal(9, 11, 3)));
  EXPECT_EQ(tool.stiffness_n_per_m, 8e7 * (1.0 + 0.05 * uncertainty_normal(9, 11, 4)));
  EXPECT_EQ(wp.natural_frequency_hz, kF0 * (1.0 + 0.04 * uncertainty_normal(9, 11, 5)));
  EXPECT_EQ(x.process.turning_parameters().feed_force_coefficient_n_per_m2,
            kKf * (1.0 + 0.07 * uncertainty_normal(9, 11, 0)));
  EXPECT_TRUE(tool.direction == m.tool.modes[0].direction);
}

// ------------------------------------------------------------ zero spread

TEST(UncertainLobes, ZeroSpreadGivesTheNominalTable) {
  const StructuralModel m = one_mode();
  const Process p = turning();
  const std::vector<double> speeds = evenly_spaced_speeds(300.0, 2000.0, 60);
  const auto nominal_solver = make_lobe_solver("analytic", m, p, kDepthMax);
  const std::vector<StabilityLimit> nominal = lobe_envelope(*nominal_solver, speeds, 1);
  const UncertaintySpreads zero{{0.0}, {0.0}, {0.0}, 0.0, 0.0};
  constexpr std::uint64_t kSamples = 5;
  const auto rows = monte_carlo_limits(m, p, zero, 3, 0, kSamples, speeds, factory("analytic"), 2);
  ASSERT_EQ(rows.size(), kSamples);
  for (const auto& row : rows) EXPECT_TRUE(same_rows({row}, {nominal}));
  // Depths at every nominal limit, just below it and 0: probability exactly
  // 0 at and above the limit (the limit is the boundary), 1 below.
  std::vector<double> depths{0.0};
  for (const auto& r : nominal)
    if (r.bounded()) {
      depths.push_back(r.depth_limit_m);
      depths.push_back(std::nextafter(r.depth_limit_m, 0.0));
    }
  const UncertainLobes u = reduce_monte_carlo(rows, depths, {0.05, 0.5, 0.95});
  for (std::size_t s = 0; s < speeds.size(); ++s) {
    for (std::size_t d = 0; d < depths.size(); ++d)
      EXPECT_EQ(u.probability_stable[s][d], depths[d] < nominal[s].depth_limit_m ? 1.0 : 0.0)
          << speeds[s] << " rev/min, depth " << depths[d];
    for (std::size_t l = 0; l < 3; ++l)
      EXPECT_TRUE(same_bits(u.quantile_depth_m[l][s], nominal[s].depth_limit_m))
          << "level " << u.levels[l] << " at " << speeds[s] << ": " << u.quantile_depth_m[l][s] << " vs nominal "
          << nominal[s].depth_limit_m;
  }
}

TEST(UncertainLobes, SdmRunsAndZeroSpreadIsItsNominal) {
  MillingParameters mp;
  mp.teeth = 2;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 2e8;
  mp.radial_immersion = 0.5;
  const Process p = Process::milling(mp);
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(922.0, 0.011, 1.4e6, {1, 0}));
  m.tool.modes.push_back(Mode::from_stiffness(922.0, 0.011, 1.4e6, {0, 1}));
  const std::vector<double> speeds{9000.0, 12000.0, 15000.0};
  const auto nominal = lobe_envelope(*make_lobe_solver("sdm", m, p, 0.01), speeds, 1);
  const auto zero = monte_carlo_limits(m, p, UncertaintySpreads{}, 1, 0, 2, speeds, factory("sdm", 0.01), 2);
  for (const auto& row : zero) EXPECT_TRUE(same_rows({row}, {nominal}));
  // With spreads: every limit positive, and the samples differ.
  const UncertaintySpreads s{{0.03}, {0.1}, {0.05}, 0.05, 0.05};
  const auto rows = monte_carlo_limits(m, p, s, 1, 0, 3, speeds, factory("sdm", 0.01), 2);
  for (const auto& row : rows)
    for (const auto& r : row) EXPECT_GT(r.depth_limit_m, 0.0);
  EXPECT_FALSE(same_rows({rows[0]}, {rows[1]}));
}

// --------------------------------------------------------- reproducibility

TEST(UncertainLobes, SameSeedSameBitsWhateverThreadsAndRanges) {
  StructuralModel m = one_mode();
  m.tool.modes.push_back(Mode::from_stiffness(180.0, 0.04, 9e7, {1, 0}));
  const Process p = turning();
  const UncertaintySpreads s{{0.03, 0.05}, {0.2}, {0.1}, 0.08, 0.0};
  const std::vector<double> speeds = evenly_spaced_speeds(400.0, 2000.0, 40);
  constexpr std::uint64_t kN = 37, kSplit = 16;
  const auto one = monte_carlo_limits(m, p, s, 5, 0, kN, speeds, factory("analytic"), 1);
  const auto two = monte_carlo_limits(m, p, s, 5, 0, kN, speeds, factory("analytic"), 2);
  auto first = monte_carlo_limits(m, p, s, 5, 0, kSplit, speeds, factory("analytic"), 2);
  const auto second = monte_carlo_limits(m, p, s, 5, kSplit, kN, speeds, factory("analytic"), 1);
  first.insert(first.end(), second.begin(), second.end());
  EXPECT_TRUE(same_rows(one, two)) << "1 thread vs 2 threads";
  EXPECT_TRUE(same_rows(one, first)) << "[0, N) vs [0, k) + [k, N)";
  const auto other = monte_carlo_limits(m, p, s, 6, 0, kN, speeds, factory("analytic"), 2);
  EXPECT_FALSE(same_rows(one, other)) << "seed 5 vs seed 6";
  // The reduction does not depend on the order of the samples.
  auto reversed = one;
  std::reverse(reversed.begin(), reversed.end());
  const std::vector<double> depths{0.001, 0.002, 0.004};
  const UncertainLobes a = reduce_monte_carlo(one, depths, {0.05, 0.5}), b = reduce_monte_carlo(reversed, depths, {0.05, 0.5});
  EXPECT_EQ(a.probability_stable, b.probability_stable);
  EXPECT_EQ(a.quantile_depth_m, b.quantile_depth_m);
  EXPECT_THROW(monte_carlo_limits(m, p, s, 5, 3, 2, speeds, factory("analytic")), InputError);
  EXPECT_THROW(reduce_monte_carlo({}, depths, {0.5}), InputError);
}

// ------------------------------------------------ independent Monte Carlo

// The exact 1-DOF turning limit at `rpm` for natural frequency f (Hz), by
// hand: G = 1/(k (1 − r² + 2jζr)); for ω above ω_n (Re G < 0) the phase
// F(ω) = ωτ − 3π − 2∠G(ω) increases monotonically (∠G falls from −π/2 to
// −π), so lobe k has one root of F = 2πk, bisected; b = −1/(2 K_f Re G),
// the smallest over the lobes; +inf above depth_max.
double limit_by_hand(double f, double rpm) {
  const double wn = 2 * kPi * f, tau = 60.0 / rpm;
  auto G = [&](double w) {
    const double r = w / wn;
    return 1.0 / (kK * C(1.0 - r * r, 2.0 * kZeta * r));
  };
  auto F = [&](double w) { return w * tau - 3 * kPi - 2 * std::arg(G(w)); };
  // b >= k (r² − 1) / (2 K_f): beyond r_max every root is deeper than depth_max.
  const double w_lo = wn * (1.0 + 1e-12), w_hi = wn * std::sqrt(1.0 + 2.0 * kKf * kDepthMax / kK) * 1.01;
  double best = kInf;
  const int k_lo = static_cast<int>(std::ceil(F(w_lo) / (2 * kPi))), k_hi = static_cast<int>(std::floor(F(w_hi) / (2 * kPi)));
  for (int k = std::max(k_lo, 0); k <= k_hi; ++k) {
    double a = w_lo, b = w_hi;
    for (int it = 0; it < 200 && b - a > 1e-14 * b; ++it) {
      const double c = 0.5 * (a + b);
      (F(c) < 2 * kPi * k ? a : b) = c;
    }
    best = std::min(best, -1.0 / (2 * kKf * G(0.5 * (a + b)).real()));
  }
  return best <= kDepthMax ? best : kInf;
}

// Own normal truncated at 3 by rejection: Box–Muller on std::mt19937_64
// (exactly specified), not std::normal_distribution.
class OwnNormal {
 public:
  explicit OwnNormal(std::uint64_t seed) : gen_(seed) {}
  double operator()() {
    for (;;) {
      const double u1 = (static_cast<double>(gen_() >> 11) + 0.5) * 0x1.0p-53;
      const double u2 = (static_cast<double>(gen_() >> 11) + 0.5) * 0x1.0p-53;
      const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * kPi * u2);
      if (std::abs(z) <= 3.0) return z;
    }
  }

 private:
  std::mt19937_64 gen_;
};

TEST(UncertainLobes, FrequencySpreadAgainstAnIndependentMonteCarlo) {
  constexpr double kSpread = 0.05;  // 1σ of the natural frequency
  constexpr std::uint64_t kN = 2000;  // library samples; as many independent ones
  const std::vector<double> speeds{600.0, 1000.0, 1500.0, 1900.0};
  const auto rows = monte_carlo_limits(one_mode(), turning(), UncertaintySpreads{{kSpread}, {}, {}, 0, 0}, 1, 0, kN,
                                       speeds, factory("analytic"), 2);
  std::vector<double> depths;
  for (int d = 1; d <= 40; ++d) depths.push_back(0.0005 * d);  // 0.5 to 20 mm
  const std::vector<double> levels{0.05, 0.5, 0.95};
  const UncertainLobes lib = reduce_monte_carlo(rows, depths, levels);

  OwnNormal z(20240601);
  std::vector<std::vector<double>> own(speeds.size());
  for (std::uint64_t i = 0; i < kN; ++i) {
    const double f = kF0 * (1.0 + kSpread * z());
    for (std::size_t s = 0; s < speeds.size(); ++s) own[s].push_back(limit_by_hand(f, speeds[s]));
  }
  // Two independent estimates of one probability p: the difference has
  // sd = sqrt(p (1 − p) (1/N + 1/N)) <= 0.5 sqrt(2/N) = 0.0158; 5 sd over
  // the 160 grid points keeps a false alarm below 1e-4.
  const double kProbabilityTol = 5.0 * 0.5 * std::sqrt(2.0 / kN);
  double largest_gap = 0.0;
  for (std::size_t s = 0; s < speeds.size(); ++s) {
    std::vector<double> sorted = own[s];
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t d = 0; d < depths.size(); ++d) {
      const double p_own =
          static_cast<double>(sorted.end() - std::upper_bound(sorted.begin(), sorted.end(), depths[d])) / kN;
      const double gap = std::abs(lib.probability_stable[s][d] - p_own);
      largest_gap = std::max(largest_gap, gap);
      EXPECT_LE(gap, kProbabilityTol) << speeds[s] << " rev/min, " << depths[d] * 1e3
                                      << " mm: library " << lib.probability_stable[s][d] << ", independent " << p_own;
    }
    // A quantile q of the library's samples lies between the independent
    // sample's quantiles at q ± 5 sd of the difference of two empirical
    // CDFs at that point (sqrt(q (1 − q) 2 / N)): distribution-free.
    for (std::size_t l = 0; l < levels.size(); ++l) {
      const double q = levels[l], band = 5.0 * std::sqrt(q * (1.0 - q) * 2.0 / kN);
      const double lo = quantile_type7(own[s], std::max(0.0, q - band));
      const double hi = quantile_type7(own[s], std::min(1.0, q + band));
      const double v = lib.quantile_depth_m[l][s];
      EXPECT_TRUE(v >= lo && v <= hi) << speeds[s] << " rev/min, level " << q << ": library " << v
                                      << " m, independent band [" << lo << ", " << hi << "]";
    }
  }
  // The spread matters here: the probabilities are not all 0 / 1.
  std::size_t fractional = 0;
  for (const auto& row : lib.probability_stable)
    for (const double pr : row) fractional += pr > 0.05 && pr < 0.95;
  EXPECT_GT(fractional, 10u) << "largest gap " << largest_gap;
}

// The probability grid's depths: 1.2 x the deepest finite limit of any sample
// rounded up to two significant digits (3.7 mm -> 4.44 -> 4.5 mm), capped at
// the searched depth; the searched depth when every limit is +inf; a given
// top as given; both ends included.
TEST(ProbabilityDepthGrid, TopFromTheDeepestLimitRoundedUp) {
  const auto limit = [](double depth_m) {
    StabilityLimit l;
    l.spindle_rpm = 1000.0;
    l.depth_limit_m = depth_m;
    return l;
  };
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<StabilityLimit>> rows = {{limit(2e-3), limit(inf)}, {limit(3.7e-3), limit(1e-3)}};
  const ProbabilityDepthGrid g = probability_depth_grid(rows, 50.0, 10);
  EXPECT_DOUBLE_EQ(g.top_mm, 4.5);
  ASSERT_EQ(g.depths_m.size(), 10u);
  EXPECT_EQ(g.depths_m.front(), 0.0);
  EXPECT_DOUBLE_EQ(g.depths_m.back(), 4.5e-3);
  EXPECT_NEAR(g.depths_m[1], 0.5e-3, 1e-18);
  // 1.2 x 0.0912 = 0.10944 -> 0.11 mm (two digits of the first decade below).
  EXPECT_DOUBLE_EQ(probability_depth_grid({{limit(0.0912e-3)}}, 50.0, 2).top_mm, 0.11);
  EXPECT_EQ(probability_depth_grid(rows, 4.0, 5).top_mm, 4.0);                // capped at the searched depth
  EXPECT_EQ(probability_depth_grid({{limit(inf)}}, 20.0, 5).top_mm, 20.0);    // no chatter anywhere
  EXPECT_DOUBLE_EQ(probability_depth_grid(rows, 50.0, 3, 7.25).depths_m[1], 7.25e-3 / 2);  // given top
  EXPECT_THROW(probability_depth_grid(rows, 50.0, 1), InputError);
  EXPECT_THROW(probability_depth_grid(rows, 50.0, 5, 0.0), InputError);
}

}  // namespace
}  // namespace chatter
