// Variable-pitch design (include/chatter/pitch_design.hpp, docs/design_pitch.md)
// against an answer built here: on symmetric 2-DOF slotting the averaged
// equation has closed-form eigenvalues, so the lowest point of the equal-pitch
// lobes (its speed and chatter frequency) and from it Budak's step are
// computed independently of the library; the design's start must match it,
// its sdm worst limit must beat equal pitch, and its band table must be what
// a separately built sdm solver gives for the reported angles, bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/pitch_design.hpp"
#include "chatter/solvers.hpp"

namespace chatter {
namespace {

using C = std::complex<double>;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * kPi;

// docs/physics.md case C's mode in X and in Y (G = g I), slotting, 4 teeth.
constexpr double kF = 922.0, kZeta = 0.011, kMass = 0.03993, kKt = 6e8, kKr = 2e8;
constexpr int kTeeth = 4;
constexpr int kLobe = 2;  // the band sits on the bottom of lobe k = 2 (about 5000 rev/min)

// Tolerances.
// The rule's step from the design against the closed form: the design takes
// f_c and n from the sdm equal-pitch row with the lowest limit; sdm is not
// the averaged equation (its limit differs by its discretisation and by the
// intermittent force: a few tenths of a percent in frequency here) and the
// row is on a grid of 0.5 % speed steps, within a quarter step of the bottom.
// Measured 2026-11-26: 7e-7 (the worst row falls on the closed-form bottom);
// held to 1.5 %.
constexpr double kRuleTolerance = 0.015;
// The polished step against the rule's roots: the geometric sum vanishes at
// ψ = 2πk/N_t, k = 1 … N_t − 1, i.e. at k times the rule's step; the search
// finds the best over the family's whole range, which on this case is near
// the k = 3 root (26.4°) and stops at the bound 30° (measured 2026-11-26: the
// scan point 11.25° near the k = 1 root gives a worst limit of 0.058 mm, the
// bound 0.0655 mm). Asked: within 15 % of a root (the bound is 13.5 % away).
constexpr double kPolishFromRoot = 0.15;
// Gain of the designed cutter's worst sdm limit over equal pitch's on this
// case: measured 2.73 (the rule's start alone 1.97); asked a clear rise.
constexpr double kMinimumGain = 2.0;

StructuralModel symmetric() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(kF, kZeta, kMass, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_mass(kF, kZeta, kMass, {0.0, 1.0}));
  return m;
}

Process slotting(std::vector<double> pitch = {}) {
  MillingParameters p;
  p.teeth = kTeeth;
  p.tangential_coefficient_n_per_m2 = kKt;
  p.radial_coefficient_n_per_m2 = kKr;
  p.radial_immersion = 1.0;
  p.direction = MillingDirection::kDown;
  p.pitch_angles_rad = std::move(pitch);
  return Process::milling(p);
}

// The closed form. With H₀ = (N/4)[[K_r, K_t], [−K_t, K_r]] and G = g I, the
// averaged equation splits into 1 + a z±(ω)(1 − e^{−iωτ}) = 0, z± = (N/4)(K_r ±
// i K_t) g(ω). Writing 1 − e^{−iθ} = 2 cos β e^{iβ}, β = (π − θ)/2, a real
// a > 0 needs arg z + β = π, hence a(ω) = −1 / (2 Re z(ω)) (Re z < 0) and θ =
// 2 arg z − π (mod 2π): the lobes' lowest point is the minimum of Re z over ω,
// at the speed with ωτ = θ + 2πk, τ = 60 / (N n).
struct Bottom {
  double omega = 0.0;  // rad/s
  double depth_m = 0.0;
  double rpm = 0.0;    // lobe kLobe
};

Bottom closed_form_bottom() {
  const double wn = kTwoPi * kF, k = kMass * wn * wn;
  const auto z = [&](double w, double sign) {
    const double r = w / wn;
    const C g = 1.0 / (k * C(1.0 - r * r, 2.0 * kZeta * r));
    return kTeeth / 4.0 * C(kKr, sign * kKt) * g;
  };
  Bottom best;
  double best_re = 0.0, best_sign = 1.0;
  for (double sign : {1.0, -1.0})
    for (double w = 0.8 * wn; w < 1.2 * wn; w += 1e-5 * wn)
      if (z(w, sign).real() < best_re) {
        best_re = z(w, sign).real();
        best.omega = w;
        best_sign = sign;
      }
  // Golden-section refinement on [w − h, w + h].
  double lo = best.omega - 2e-5 * wn, hi = best.omega + 2e-5 * wn;
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 200; ++it) {
    const double a = hi - gr * (hi - lo), b = lo + gr * (hi - lo);
    if (z(a, best_sign).real() < z(b, best_sign).real()) hi = b;
    else lo = a;
  }
  best.omega = 0.5 * (lo + hi);
  const C zb = z(best.omega, best_sign);
  best.depth_m = -1.0 / (2.0 * zb.real());
  double theta = std::fmod(2.0 * std::arg(zb) - kPi, kTwoPi);
  if (theta <= 0.0) theta += kTwoPi;
  const double tau = (theta + kTwoPi * kLobe) / best.omega;
  best.rpm = 60.0 / (kTeeth * tau);
  return best;
}

// Budak's rule for the linear family, written here: ψ = ω_c ΔP / Ω = 2π/N.
double rule_step(double rpm, double omega_c) { return kTwoPi * (kTwoPi * rpm / 60.0) / (kTeeth * omega_c); }

PitchDesignOptions band_options(const Bottom& b) {
  PitchDesignOptions o;
  o.rpm_min = 0.95 * b.rpm;
  o.rpm_max = 1.05 * b.rpm;
  o.rpm_points = 21;
  o.depth_max_m = 0.02;
  o.scan_points = 8;
  o.threads = 0;
  return o;
}

// One design shared by the tests below (about 30 bands of 21 sdm limits).
const PitchDesign& the_design() {
  static const PitchDesign d = design_pitch(symmetric(), slotting(), band_options(closed_form_bottom()));
  return d;
}

TEST(PitchFamilies, AnglesSumToOneTurnAndRespectTheBound) {
  for (PitchFamily f : {PitchFamily::kLinear, PitchFamily::kAlternating})
    for (int n : {2, 4, 6}) {
      const double step = max_pitch_step_rad(f, n, 0.5);
      const std::vector<double> th = family_pitch_angles(f, n, step);
      double sum = 0.0;
      for (double t : th) sum += t;
      EXPECT_NEAR(sum, kTwoPi, 1e-12) << to_string(f) << " " << n;
      // At the largest step the smallest angle is exactly half the equal one.
      EXPECT_NEAR(*std::min_element(th.begin(), th.end()), 0.5 * kTwoPi / n, 1e-12) << to_string(f) << " " << n;
    }
  // Linear: neighbours differ by the step; alternating: the two angles by it.
  const std::vector<double> lin = family_pitch_angles(PitchFamily::kLinear, 4, 0.1);
  EXPECT_NEAR(lin[1] - lin[0], 0.1, 1e-15);
  EXPECT_NEAR(lin[3] - lin[2], 0.1, 1e-15);
  const std::vector<double> alt = family_pitch_angles(PitchFamily::kAlternating, 4, 0.1);
  EXPECT_NEAR(alt[0] - alt[1], 0.1, 1e-15);
  EXPECT_EQ(alt[0], alt[2]);
}

TEST(PitchFamilies, RuleCancelsTheRegenerativeSum) {
  // At the rule's step Σ_j e^{−iω_c θ_j/Ω} = 0 (linear: ψ = 2π/N; alternating:
  // ψ = π), summed here directly.
  const double rpm = 6000.0, f_c = 900.0;
  const double omega_spindle = kTwoPi * rpm / 60.0, w = kTwoPi * f_c;
  for (PitchFamily f : {PitchFamily::kLinear, PitchFamily::kAlternating}) {
    const double step = budak_pitch_step_rad(f, 4, rpm, f_c);
    C s(0.0);
    for (double th : family_pitch_angles(f, 4, step)) s += std::polar(1.0, -w * th / omega_spindle);
    EXPECT_LT(std::abs(s), 1e-12) << to_string(f) << ": |sum| = " << std::abs(s);
  }
  EXPECT_NEAR(budak_pitch_step_rad(PitchFamily::kLinear, 4, rpm, f_c), rule_step(rpm, w), 1e-15);
}

TEST(PitchDesign, RuleStartMatchesClosedForm) {
  const Bottom b = closed_form_bottom();
  const PitchDesign& d = the_design();
  const double expected = rule_step(b.rpm, b.omega);
  EXPECT_FALSE(d.rule_clipped);
  EXPECT_NEAR(d.rule_step_rad / expected, 1.0, kRuleTolerance)
      << "rule step " << d.rule_step_rad * 180 / kPi << " deg (at " << d.rule_rpm << " rev/min, "
      << d.rule_chatter_frequency_hz << " Hz) vs closed form " << expected * 180 / kPi << " deg (at " << b.rpm
      << " rev/min, " << b.omega / kTwoPi << " Hz)";
  // The equal-pitch worst limit is the lobes' lowest point (sdm vs the
  // averaged closed form: 10 % allowed for the intermittent force).
  EXPECT_NEAR(d.equal.worst_limit_m / b.depth_m, 1.0, 0.1)
      << d.equal.worst_limit_m << " m vs closed form " << b.depth_m << " m";
}

TEST(PitchDesign, DesignedStepNearARootOfTheRuleAndGainAboveOne) {
  const Bottom b = closed_form_bottom();
  const PitchDesign& d = the_design();
  const double expected = rule_step(b.rpm, b.omega);
  double nearest = 1e300;
  int root = 0;
  for (int k = 1; k < kTeeth; ++k)
    if (std::abs(d.designed.step_rad / (k * expected) - 1.0) < nearest) {
      nearest = std::abs(d.designed.step_rad / (k * expected) - 1.0);
      root = k;
    }
  EXPECT_LT(nearest, kPolishFromRoot) << "designed step " << d.designed.step_rad * 180 / kPi
                                      << " deg vs closed-form rule root k = " << root << ": "
                                      << root * expected * 180 / kPi << " deg";
  EXPECT_GT(d.gain, kMinimumGain) << "designed worst " << d.designed.worst_limit_m << " m vs equal "
                                  << d.equal.worst_limit_m << " m";
  EXPECT_FALSE(d.gain_is_lower_bound);
  EXPECT_EQ(d.gain, d.designed.worst_limit_m / d.equal.worst_limit_m);
}

TEST(PitchDesign, PolishNeverWorseThanStartOrEqual) {
  const PitchDesign& d = the_design();
  EXPECT_GE(d.designed.worst_limit_m, d.start.worst_limit_m);
  EXPECT_GE(d.designed.worst_limit_m, d.equal.worst_limit_m);
  for (const auto& [step, worst] : d.evaluated) {
    EXPECT_LE(worst, d.designed.worst_limit_m) << "step " << step;
    EXPECT_GE(step, 0.0);
    EXPECT_LE(step, d.step_max_rad);
  }
}

TEST(PitchDesign, WorstIsTheMinimumOfTheTable) {
  const PitchDesign& d = the_design();
  for (const PitchCandidate* c : {&d.equal, &d.start, &d.designed}) {
    ASSERT_EQ(c->limits.size(), d.speeds_rpm.size());
    double lowest = std::numeric_limits<double>::infinity(), at = 0.0;
    for (const StabilityLimit& l : c->limits)
      if (l.depth_limit_m < lowest) {
        lowest = l.depth_limit_m;
        at = l.spindle_rpm;
      }
    EXPECT_EQ(c->worst_limit_m, lowest);
    EXPECT_EQ(c->worst_rpm, at);
  }
}

TEST(PitchDesign, TableEqualsASeparatelyBuiltSdmSolverBitwise) {
  const PitchDesign& d = the_design();
  ASSERT_EQ(d.method, "sdm");
  const Process designed = slotting(d.designed.angles_rad);
  ASSERT_TRUE(designed.has_variable_pitch());
  const auto solver = make_lobe_solver("sdm", symmetric(), designed, 0.02);
  const auto equal_solver = make_lobe_solver("sdm", symmetric(), slotting(), 0.02);
  for (std::size_t i : {std::size_t{0}, std::size_t{7}, std::size_t{13}, d.speeds_rpm.size() - 1}) {
    const StabilityLimit l = solver->limit_at(SpindleSpeed(d.speeds_rpm[i]));
    EXPECT_EQ(l.depth_limit_m, d.designed.limits[i].depth_limit_m) << d.speeds_rpm[i] << " rev/min";
    EXPECT_EQ(l.chatter_frequency_hz, d.designed.limits[i].chatter_frequency_hz) << d.speeds_rpm[i];
    EXPECT_EQ(equal_solver->limit_at(SpindleSpeed(d.speeds_rpm[i])).depth_limit_m, d.equal.limits[i].depth_limit_m)
        << d.speeds_rpm[i];
  }
}

TEST(PitchDesign, RefusesWhatItCannotDesign) {
  const Bottom b = closed_form_bottom();
  PitchDesignOptions o = band_options(b);
  const auto message = [&](const Process& p, const PitchDesignOptions& opt) {
    try {
      design_pitch(symmetric(), p, opt);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message(slotting({1.4, 1.74159265358979, 1.4, 1.74159265358979}), o).find("unequal pitch"),
            std::string::npos);
  EXPECT_NE(message(Process::turning({2e9}), o).find("turning"), std::string::npos);
  PitchDesignOptions inverted = o;
  inverted.rpm_max = o.rpm_min;
  EXPECT_NE(message(slotting(), inverted).find("rpm_max"), std::string::npos);
  PitchDesignOptions shallow = o;
  shallow.depth_max_m = 1e-6;  // far below the lowest limit: nothing to design
  shallow.rpm_points = 2;
  EXPECT_NE(message(slotting(), shallow).find("depth_max_m"), std::string::npos);
  PitchDesignOptions tdomain = o;
  tdomain.method = "time-domain";
  EXPECT_NE(message(slotting(), tdomain).find("simulation"), std::string::npos);
  MillingParameters three;
  three.teeth = 3;
  three.tangential_coefficient_n_per_m2 = kKt;
  PitchDesignOptions alt = o;
  alt.family = PitchFamily::kAlternating;
  EXPECT_NE(message(Process::milling(three), alt).find("even number"), std::string::npos);
}

}  // namespace
}  // namespace chatter
