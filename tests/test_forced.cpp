// The forced response (include/chatter/forced.hpp, docs/forced.md) against
// answers built in the test:
//  - equal pitch: the FRF, written here from docs/physics.md §2, times the
//    Fourier series of the static force, written here from §3's force law
//    and integrated numerically (Gauss–Legendre over the arc and the height);
//  - any cutter: the time-domain steady state with the same linear chip
//    (SimulationSettings::linear_static_chip) within 1 %;
//  - depth → 0: the response per unit depth tends to the static-force
//    response (no regeneration left);
//  - turning: δ = F_r Σ (u·n)²/k exactly, and along a cantilever shaft the
//    deflection scales with the mode shape φ(x/L)² (k(x) = k_tip / φ²);
//  - the two paths (Fourier, periodic solve) agree on an equal-pitch cutter;
//  - teeth leaving the cut: the forced response and the nonlinear simulation
//    agree on where the linear model stops holding.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/forced.hpp"
#include "chatter/time_domain.hpp"

namespace {

using chatter::ForcedOptions;
using chatter::ForcedResponse;
using chatter::ForcedResponseSolver;
using chatter::ForcedSettings;
using chatter::MillingDirection;
using chatter::MillingParameters;
using chatter::Mode;
using chatter::Process;
using chatter::StructuralModel;
using Cplx = std::complex<double>;

constexpr double kPi = std::numbers::pi;

// Tolerances (relative to the largest |r| over the period unless said).
// Fourier path with the same harmonics as the reference: only the
// quadrature of the reference (64 Gauss points per arc, smooth integrand)
// and round-off differ.
constexpr double kSameSeries = 1e-9;
// Fourier path with its automatic harmonic count against a 4 000-harmonic
// reference: the truncation (f_max / f_top)² ≈ 4e-4 of the static part.
constexpr double kAutoTruncation = 2e-3;
// The periodic solve (sdm steps, O(h²)) against an exact answer: 64 steps
// per tooth period and per vibration cycle keep it near 1e-3.
constexpr double kPeriodicSolve = 5e-3;
// The issue's acceptance: time-domain steady state and forced within 1 %.
constexpr double kTimeDomain = 0.01;

// Gauss–Legendre nodes and weights on [−1, 1] (Golub–Welsch-free: Newton
// on the Legendre polynomial), n points.
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p1 = 1.0, p2 = 0.0;
      for (int k = 1; k <= n; ++k) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * k - 1.0) * z * p2 - (k - 1.0) * p3) / k;
      }
      pp = n * (z * p1 - p2) / (z * z - 1.0);
      const double dz = p1 / pp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[static_cast<std::size_t>(i)] = z;
    w[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - z * z) * pp * pp);
  }
}

// §2: G(ω) = Σ u uᵀ / (k (1 − r² + 2jζr)), tool and workpiece modes.
Eigen::Matrix<Cplx, 2, 2> receptance(const std::vector<Mode>& modes, double omega) {
  Eigen::Matrix<Cplx, 2, 2> g = Eigen::Matrix<Cplx, 2, 2>::Zero();
  for (const Mode& m : modes) {
    const double r = omega / (2.0 * kPi * m.natural_frequency_hz);
    const Cplx den = m.stiffness_n_per_m * Cplx(1.0 - r * r, 2.0 * m.damping_ratio * r);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) g(a, b) += m.direction(a) * m.direction(b) / den;
  }
  return g;
}

// §3: the force on the tool of one tooth at angle φ with chip h, per unit
// depth: F_x = −F_t cos φ − F_r sin φ, F_y = F_t sin φ − F_r cos φ,
// F_t = K_t h, F_r = K_r h.
Eigen::Vector2d tooth_force(double kt, double kr, double phi, double h) {
  const double ft = kt * h, fr = kr * h;
  return {-ft * std::cos(phi) - fr * std::sin(phi), ft * std::sin(phi) - fr * std::cos(phi)};
}

// The reference response of an equal-pitch cutter (feed f per tooth, depth
// a, helix lag κ rad/m): r(t) = Σ_k G(k ω_T) F_k e^{j k ω_T t}, F_k the
// Fourier coefficients of the static force over one tooth period, by
// Gauss–Legendre over each arc (in φ) and over the height (in z).
struct Reference {
  double omega_t = 0.0;
  std::vector<Eigen::Matrix<Cplx, 2, 1>> c;  // c[k] = G(kω_T) F_k, k = 0 … K
  Eigen::Vector2d at(double t) const {
    Eigen::Vector2d r = c[0].real();
    for (std::size_t k = 1; k < c.size(); ++k) {
      const Cplx e = std::polar(1.0, omega_t * static_cast<double>(k) * t);
      r += 2.0 * (c[k] * e).real();
    }
    return r;
  }
};

// Composite Gauss–Legendre nodes and weights on [lo, hi]: `pieces` equal
// parts, 8 points each (exact to degree 15 on each part).
void composite(double lo, double hi, int pieces, std::vector<double>& x, std::vector<double>& w) {
  std::vector<double> gx, gw;
  gauss_legendre(8, gx, gw);
  x.clear();
  w.clear();
  const double h = (hi - lo) / pieces;
  for (int p = 0; p < pieces; ++p)
    for (std::size_t i = 0; i < gx.size(); ++i) {
      x.push_back(lo + h * (p + 0.5 * (gx[i] + 1.0)));
      w.push_back(0.5 * h * gw[i]);
    }
}

Reference reference(const std::vector<Mode>& modes, int teeth, double kt, double kr, double en, double ex, double rpm,
                    double a, double f, double kappa, int harmonics) {
  // Each part of the arc and of the height spans at most half a wave of
  // the highest harmonic e^{−j m φ}, m = K N_t.
  const double m_max = static_cast<double>(harmonics) * teeth;
  std::vector<double> px, pw, zx, zw;
  composite(en, ex, 1 + static_cast<int>(std::ceil(m_max * (ex - en) / kPi)), px, pw);
  if (kappa > 0.0) {
    composite(0.0, a, 1 + static_cast<int>(std::ceil(m_max * kappa * a / kPi)), zx, zw);
  } else {
    zx = {0.0};
    zw = {a};
  }
  const double omega = 2.0 * kPi * rpm / 60.0;
  Reference ref;
  ref.omega_t = teeth * omega;
  // Over one revolution every tooth sweeps its arc once; by the change of
  // variable φ = Ωt − Θ_j − κz the coefficient of e^{jmΩt} is
  //   (1/2π) Σ_j ∫₀ᵃ ∫_arc F1(φ) e^{−jm(φ + Θ_j + κz)} dφ dz,
  // nonzero for m = k N_t only (N_t equally spaced teeth).
  std::vector<Eigen::Matrix<Cplx, 2, 1>> F(static_cast<std::size_t>(harmonics) + 1,
                                           Eigen::Matrix<Cplx, 2, 1>::Zero());
  for (std::size_t iz = 0; iz < zx.size(); ++iz)
    for (std::size_t i = 0; i < px.size(); ++i) {
      const double w = zw[iz] * pw[i];
      const Eigen::Vector2d F1 = tooth_force(kt, kr, px[i], f * std::sin(px[i]));
      const Cplx step = std::polar(1.0, -teeth * (px[i] + kappa * zx[iz]));
      Cplx e(1.0, 0.0);
      for (int k = 0; k <= harmonics; ++k) {
        F[static_cast<std::size_t>(k)](0) += w * F1.x() * e;
        F[static_cast<std::size_t>(k)](1) += w * F1.y() * e;
        e *= step;
      }
    }
  for (int k = 0; k <= harmonics; ++k) {
    Cplx teeth_sum(0.0, 0.0);
    for (int j = 0; j < teeth; ++j) teeth_sum += std::polar(1.0, -k * teeth * 2.0 * kPi * j / teeth);
    ref.c.push_back(receptance(modes, k * ref.omega_t) * (F[static_cast<std::size_t>(k)] * teeth_sum / (2.0 * kPi)));
  }
  return ref;
}

double max_abs(const ForcedResponse& r) {
  double m = 0.0;
  for (std::size_t i = 0; i < r.t_s.size(); ++i) m = std::max(m, std::hypot(r.rel_x_m[i], r.rel_y_m[i]));
  return m;
}

// A 2-DOF tool (x and y modes apart) with a 3-tooth equal-pitch cutter.
StructuralModel two_mode_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(700.0, 0.02, 6e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(820.0, 0.03, 9e6, {0.2, 1.0}));
  return m;
}

MillingParameters three_teeth(MillingDirection dir, double immersion) {
  MillingParameters mp;
  mp.teeth = 3;
  mp.tangential_coefficient_n_per_m2 = 7e8;
  mp.radial_coefficient_n_per_m2 = 2.1e8;
  mp.radial_immersion = immersion;
  mp.direction = dir;
  mp.tool_diameter_m = 0.016;
  return mp;
}

// The issue's cutter: 4 flutes, 85/95° pitch, 30° helix, 12 mm, half
// immersion climb; modes 1 150 / 1 230 Hz, 12 / 14 N/µm (ζ = 0.02).
StructuralModel issue_tool() {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(1150.0, 0.02, 12e6, {1.0, 0.0}));
  m.tool.modes.push_back(Mode::from_stiffness(1230.0, 0.02, 14e6, {0.0, 1.0}));
  return m;
}

MillingParameters issue_cutter() {
  MillingParameters mp;
  mp.teeth = 4;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 1.8e8;
  mp.radial_immersion = 0.5;
  mp.direction = MillingDirection::kDown;
  mp.tool_diameter_m = 0.012;
  mp.helix_angles_rad = {30.0 * kPi / 180.0};
  for (const double d : {85.0, 95.0, 85.0, 95.0}) mp.pitch_angles_rad.push_back(d * kPi / 180.0);
  return mp;
}

void expect_path_near(const ForcedResponse& r, const Reference& ref, double tol, const char* what) {
  const double scale = max_abs(r);
  ASSERT_GT(scale, 0.0);
  double worst = 0.0;
  for (std::size_t i = 0; i < r.t_s.size(); ++i) {
    const Eigen::Vector2d e = ref.at(r.t_s[i]);
    worst = std::max(worst, std::hypot(r.rel_x_m[i] - e.x(), r.rel_y_m[i] - e.y()));
  }
  EXPECT_LT(worst / scale, tol) << what << ": worst difference " << worst << " m of " << scale << " m";
}

TEST(Forced, EqualPitchIsTheFrfTimesTheFourierSeriesOfTheStaticForce) {
  const StructuralModel model = two_mode_tool();
  std::vector<Mode> modes = model.tool.modes;
  constexpr int kHarmonics = 200;
  for (const MillingDirection dir : {MillingDirection::kDown, MillingDirection::kUp}) {
    const MillingParameters mp = three_teeth(dir, 0.3);
    const Process p = Process::milling(mp);
    const double rpm = 9000.0, a = 0.4e-3, f = 0.08e-3;
    ForcedOptions o;
    o.harmonics = kHarmonics;
    const ForcedResponse r = ForcedResponseSolver(model, p, o).response({rpm, a, f, true});
    ASSERT_TRUE(r.stable) << r.spectral_radius;
    EXPECT_EQ(r.method, "fourier");
    const Reference ref = reference(modes, mp.teeth, mp.tangential_coefficient_n_per_m2,
                                    mp.radial_coefficient_n_per_m2, p.entry_angle(), p.exit_angle(), rpm, a, f, 0.0,
                                    kHarmonics);
    expect_path_near(r, ref, kSameSeries, "same harmonics");
    // The mean is G(0) F_0 (Kline & DeVor's static deflection).
    EXPECT_NEAR(r.static_x_m, ref.c[0].real().x(), kSameSeries * max_abs(r));
    EXPECT_NEAR(r.static_y_m, ref.c[0].real().y(), kSameSeries * max_abs(r));
    // SLE: −n_w·r when a tooth is at the wall, n_w = (sin φ_w, cos φ_w):
    // φ_w = π (down, n_w = (0, −1): SLE = r_y) or 0 (up: SLE = −r_y).
    const double omega = 2.0 * kPi * rpm / 60.0;
    const double phi_w = dir == MillingDirection::kDown ? kPi : 0.0;
    const double sle = (dir == MillingDirection::kDown ? 1.0 : -1.0) * ref.at(phi_w / omega).y();
    EXPECT_NEAR(r.surface_location_error_m, sle, kSameSeries * max_abs(r));
    // Equal pitch: the chip is the static chip, the teeth never leave the cut.
    EXPECT_FALSE(r.teeth_leave_cut);
    EXPECT_TRUE(r.linear_limit_holds);
    EXPECT_GE(r.min_chip_m, 0.0);
    // Automatic harmonics against the long series.
    const ForcedResponse r_auto = ForcedResponseSolver(model, p).response({rpm, a, f, true});
    expect_path_near(r_auto, ref, kAutoTruncation, "automatic harmonics");
  }
}

TEST(Forced, EqualPitchHelixSpreadsTheForceOverTheHeight) {
  const StructuralModel model = two_mode_tool();
  MillingParameters mp = three_teeth(MillingDirection::kDown, 0.5);
  mp.helix_angles_rad = {35.0 * kPi / 180.0};
  const Process p = Process::milling(mp);
  const double rpm = 7000.0, a = 1.5e-3, f = 0.06e-3;
  ForcedOptions o;
  o.harmonics = 80;
  const ForcedResponse r = ForcedResponseSolver(model, p, o).response({rpm, a, f, true});
  ASSERT_TRUE(r.stable);
  EXPECT_EQ(r.method, "fourier");
  const Reference ref = reference(model.tool.modes, mp.teeth, mp.tangential_coefficient_n_per_m2,
                                  mp.radial_coefficient_n_per_m2, p.entry_angle(), p.exit_angle(), rpm, a, f,
                                  p.helix_lag_rad_per_m(0), 80);
  expect_path_near(r, ref, kSameSeries, "helix");
  // The wall at height z is made when the slice at z passes φ_w.
  ASSERT_EQ(r.wall_z_m.size(), static_cast<std::size_t>(o.axial_points + 1));
  const double omega = 2.0 * kPi * rpm / 60.0;
  for (std::size_t i = 0; i < r.wall_z_m.size(); ++i) {
    const double t = (kPi + p.helix_lag_rad_per_m(0) * r.wall_z_m[i]) / omega;
    EXPECT_NEAR(r.wall_sle_m[i], ref.at(t).y(), kSameSeries * max_abs(r)) << "z = " << r.wall_z_m[i];
  }
}

TEST(Forced, PeriodicSolveAgreesWithTheFourierSeriesOnAnEqualPitchCutter) {
  const StructuralModel model = two_mode_tool();
  const Process p = Process::milling(three_teeth(MillingDirection::kUp, 0.4));
  ForcedOptions fo;
  fo.harmonics = 200;
  ForcedOptions po;
  po.periodic_solve_always = true;
  for (const double rpm : {6000.0, 11000.0, 17000.0}) {
    const ForcedSettings st{rpm, 0.3e-3, 0.1e-3, true};
    const ForcedResponse a = ForcedResponseSolver(model, p, fo).response(st);
    const ForcedResponse b = ForcedResponseSolver(model, p, po).response(st);
    ASSERT_TRUE(a.stable && b.stable) << rpm;
    EXPECT_EQ(b.method, "periodic-solve");
    const double scale = max_abs(a);
    EXPECT_NEAR(a.peak_to_peak_x_m, b.peak_to_peak_x_m, kPeriodicSolve * scale) << rpm;
    EXPECT_NEAR(a.peak_to_peak_y_m, b.peak_to_peak_y_m, kPeriodicSolve * scale) << rpm;
    EXPECT_NEAR(a.static_x_m, b.static_x_m, kPeriodicSolve * scale) << rpm;
    EXPECT_NEAR(a.surface_location_error_m, b.surface_location_error_m, kPeriodicSolve * scale) << rpm;
    EXPECT_NEAR(a.mean_force_x_n, b.mean_force_x_n, 1e-9 * std::abs(a.mean_force_x_n)) << "exact integrals";
    EXPECT_NEAR(a.mean_force_y_n, b.mean_force_y_n, 1e-9 * std::abs(a.mean_force_y_n) + 1e-12) << "exact integrals";
  }
}

// The time-domain steady state with the same linear chip (static chip,
// never clipped) over enough revolutions for the transient to die.
chatter::SimulationResult linear_forced_run(const StructuralModel& m, const Process& p, double rpm, double a,
                                            double f, int periods) {
  chatter::SimulationSettings st;
  st.spindle_rpm = rpm;
  st.depth_m = a;
  st.feed_m = f;
  st.periods = periods;
  st.linear = true;
  st.linear_static_chip = true;
  st.record_series = false;
  return chatter::TimeDomainSimulator(m, p).simulate(st);
}

TEST(Forced, AnyCutterMatchesTheTimeDomainSteadyStateWithin1Percent) {
  struct Case {
    const char* name;
    StructuralModel model;
    MillingParameters mp;
    double rpm, depth_m, feed_m;
    int periods;
  };
  std::vector<Case> cases;
  cases.push_back({"variable pitch and helix (the issue's cutter)", issue_tool(), issue_cutter(), 12000.0, 1.0e-3,
                   0.05e-3, 80});
  MillingParameters runout = three_teeth(MillingDirection::kDown, 0.5);
  runout.runout_m = {4e-6, -2e-6, 0.0};
  cases.push_back({"equal pitch with runout", two_mode_tool(), runout, 8000.0, 0.3e-3, 0.08e-3, 60});
  MillingParameters equal = three_teeth(MillingDirection::kUp, 0.3);
  cases.push_back({"equal pitch (Fourier path)", two_mode_tool(), equal, 9000.0, 0.4e-3, 0.08e-3, 300});
  for (const Case& c : cases) {
    const Process p = Process::milling(c.mp);
    const ForcedResponse r = ForcedResponseSolver(c.model, p).response({c.rpm, c.depth_m, c.feed_m, true});
    ASSERT_TRUE(r.stable) << c.name;
    const chatter::SimulationResult s = linear_forced_run(c.model, p, c.rpm, c.depth_m, c.feed_m, c.periods);
    ASSERT_TRUE(s.forced_steady) << c.name << ": " << s.verdict_measure;
    const double scale = max_abs(r);
    EXPECT_NEAR(s.forced_peak_to_peak_x_m, r.peak_to_peak_x_m, kTimeDomain * scale) << c.name;
    EXPECT_NEAR(s.forced_peak_to_peak_y_m, r.peak_to_peak_y_m, kTimeDomain * scale) << c.name;
    EXPECT_NEAR(s.forced_static_x_m, r.static_x_m, kTimeDomain * scale) << c.name;
    EXPECT_NEAR(s.forced_static_y_m, r.static_y_m, kTimeDomain * scale) << c.name;
    EXPECT_NEAR(s.forced_surface_location_error_m, r.surface_location_error_m, kTimeDomain * scale) << c.name;
  }
}

TEST(Forced, AtVanishingDepthTheResponseIsTheStaticForceResponse) {
  // Variable pitch: at depth a the regeneration is O(a²) against the O(a)
  // static-force response, so r/a tends to the static-force response per
  // unit depth: here from the periodic solve at 1 µm against an equal-pitch
  // reference (the static force of unequal pitch differs; an equal-pitch
  // cutter through the periodic solve makes the reference exact).
  const StructuralModel model = two_mode_tool();
  const MillingParameters mp = three_teeth(MillingDirection::kDown, 0.4);
  const Process p = Process::milling(mp);
  ForcedOptions o;
  o.periodic_solve_always = true;
  const double rpm = 10000.0, f = 0.1e-3;
  const Reference ref = reference(model.tool.modes, mp.teeth, mp.tangential_coefficient_n_per_m2,
                                  mp.radial_coefficient_n_per_m2, p.entry_angle(), p.exit_angle(), rpm, 1.0, f, 0.0, 200);
  for (const double a : {1e-3, 1e-4, 1e-6}) {
    const ForcedResponse r = ForcedResponseSolver(model, p, o).response({rpm, a, f, true});
    ASSERT_TRUE(r.stable);
    double worst = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < r.t_s.size(); ++i) {
      const Eigen::Vector2d e = ref.at(r.t_s[i]);
      scale = std::max(scale, e.norm());
      worst = std::max(worst, std::hypot(r.rel_x_m[i] / a - e.x(), r.rel_y_m[i] / a - e.y()));
    }
    // Equal pitch: exactly the static-force response at any depth (up to
    // the periodic solve's discretisation).
    EXPECT_LT(worst / scale, kPeriodicSolve) << "a = " << a;
  }
  // Variable pitch: the difference from the zero-depth limit shrinks with a.
  const Process vp = Process::milling(issue_cutter());
  const StructuralModel it = issue_tool();
  const ForcedResponse small = ForcedResponseSolver(it, vp).response({12000.0, 1e-6, 0.05e-3, true});
  const ForcedResponse smaller = ForcedResponseSolver(it, vp).response({12000.0, 1e-7, 0.05e-3, true});
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < small.t_s.size(); ++i) {
    scale = std::max(scale, std::hypot(smaller.rel_x_m[i], smaller.rel_y_m[i]) / 1e-7);
    worst = std::max(worst, std::hypot(small.rel_x_m[i] / 1e-6 - smaller.rel_x_m[i] / 1e-7,
                                       small.rel_y_m[i] / 1e-6 - smaller.rel_y_m[i] / 1e-7));
  }
  // r/a = r₀ + O(a): between 1 µm and 0.1 µm the change is ~1e-3 of the
  // value here (the depth limit is ~4.7 mm).
  EXPECT_LT(worst / scale, 1e-3);
}

TEST(Forced, TurningStaticDeflectionIsTheForceTimesTheStaticCompliance) {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_stiffness(300.0, 0.03, 2e7, {std::cos(0.3), std::sin(0.3)}));
  m.tool.modes.push_back(Mode::from_stiffness(500.0, 0.05, 5e7, {0.0, 1.0}));
  m.workpiece.modes.push_back(Mode::from_stiffness(150.0, 0.02, 4.5e7, {1.0, 0.0}));
  chatter::TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = 2.4e9;
  const Process p = Process::turning(tp);
  const double b = 0.3e-3, f = 0.2e-3;  // below the limit (~0.7 mm)
  const chatter::TurningDeflection d = chatter::static_deflection_turning(m, p, b, f);
  // δ = F_r Σ (u·n)²/k, n = x, F_r = K_f b f.
  const double F = 2.4e9 * b * f;
  const double delta = F * (std::cos(0.3) * std::cos(0.3) / 2e7 + 0.0 / 5e7 + 1.0 / 4.5e7);
  EXPECT_NEAR(d.force_n, F, 1e-15 * F);
  EXPECT_NEAR(d.deflection_m, delta, 1e-15 * delta);
  EXPECT_NEAR(d.diametral_error_m, 2.0 * delta, 2e-15 * delta);
  EXPECT_NEAR(d.deflection_y_m, -F * std::cos(0.3) * std::sin(0.3) / 2e7, 1e-15 * delta);
  // The forced response of turning is that deflection (its one definition).
  const ForcedResponse r = ForcedResponseSolver(m, p).response({1000.0, b, f, false});
  ASSERT_TRUE(r.stable);
  EXPECT_EQ(r.surface_location_error_m, d.deflection_m);
  EXPECT_EQ(r.diametral_error_m, d.diametral_error_m);
  EXPECT_EQ(r.peak_to_peak_x_m, 0.0);
  EXPECT_EQ(r.min_chip_m, f);
}

TEST(Forced, ShaftDiametralErrorFollowsTheModeShape) {
  // A cantilever shaft (rigid tool): k(x) = k_tip / φ(x/L)², so the
  // diametral error at x is φ(x/L)² times the one at the free end (the
  // compliance 1/k(x)), φ written here from §10.
  StructuralModel m;
  const double k_tip = 4.0e7, L = 0.4;
  m.workpiece.modes.push_back(Mode::from_stiffness(200.0, 0.02, k_tip, {1.0, 0.0}));
  chatter::PositionDependence dep;
  dep.cantilever.push_back({0, L});
  chatter::TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = 1.8e9;
  const Process p = Process::turning(tp);
  auto phi = [](double xi) {
    const double beta = 1.8751, sigma = 0.7341;
    auto shape = [&](double s) {
      return std::cosh(beta * s) - std::cos(beta * s) - sigma * (std::sinh(beta * s) - std::sin(beta * s));
    };
    return shape(xi) / shape(1.0);
  };
  const std::vector<double> xs = {0.1, 0.2, 0.3, 0.35, 0.4};
  const auto rows = chatter::diametral_error_along(m, dep, p, xs, 2e-3, 0.1e-3);
  ASSERT_EQ(rows.size(), xs.size());
  const double tip = rows.back().deflection.diametral_error_m;
  EXPECT_NEAR(tip, 2.0 * 1.8e9 * 2e-3 * 0.1e-3 / k_tip, 1e-12 * tip);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double expect = tip * std::pow(phi(xs[i] / L), 2);
    // The engine's mode shape uses the same β and σ: round-off only.
    EXPECT_NEAR(rows[i].deflection.diametral_error_m, expect, 1e-12 * tip) << "x = " << xs[i];
  }
}

TEST(Forced, TeethLeaveTheCutWhereTheNonlinearSimulationLeavesItToo) {
  // The issue's cutter at 12 000 rev/min (sdm limit ≈ 4.7 mm): at 1 mm the
  // negative chip is the harmless edge effect (< 5 % of the arc) and the
  // simulation keeps every tooth in the cut over 95 % of its arc time; at
  // 4.2 mm (0.9 × the limit) the forced vibration exceeds the chip: both
  // say the teeth leave the cut, and the simulation warns.
  const StructuralModel m = issue_tool();
  const Process p = Process::milling(issue_cutter());
  for (const double depth : {1.0e-3, 4.2e-3}) {
    const ForcedResponse r = ForcedResponseSolver(m, p).response({12000.0, depth, 0.05e-3, false});
    ASSERT_TRUE(r.stable);
    chatter::SimulationSettings st;
    st.spindle_rpm = 12000.0;
    st.depth_m = depth;
    st.feed_m = 0.05e-3;
    st.periods = 60;
    st.record_series = false;
    const chatter::SimulationResult s = chatter::TimeDomainSimulator(m, p).simulate(st);
    const bool deep = depth > 2e-3;
    EXPECT_EQ(r.teeth_leave_cut, deep) << r.negative_chip_fraction;
    EXPECT_EQ(r.linear_limit_holds, !deep);
    EXPECT_GT(r.negative_chip_arc_deg, 0.0) << "variable pitch: the edge effect is there at every depth";
    EXPECT_EQ(s.teeth_leave_cut, deep) << s.out_of_cut_fraction;
    EXPECT_EQ(s.verdict, chatter::SimulationVerdict::kStable) << s.verdict_measure;
    EXPECT_EQ(s.linear_limit_warning.empty(), !deep) << s.linear_limit_warning;
    ASSERT_EQ(s.out_of_cut_fraction_per_tooth.size(), 4u);
    if (deep) {
      EXPECT_GT(s.out_of_cut_fraction, 0.0);
      // One definition per reported fraction: the warning quotes
      // out_of_cut_fraction itself (3 significant digits).
      std::ostringstream pct;
      pct.precision(3);
      pct << "teeth out of the cut " << 100.0 * s.out_of_cut_fraction << " % of their arc time";
      EXPECT_NE(s.linear_limit_warning.find(pct.str()), std::string::npos) << pct.str() << " | " << s.linear_limit_warning;
    }
  }
}

TEST(Forced, UnstableCutHasNoForcedResponse) {
  StructuralModel m;
  m.tool.modes.push_back(Mode::from_mass(922.0, 0.011, 0.03993, {1.0, 0.0}));
  MillingParameters mp;
  mp.teeth = 2;
  mp.tangential_coefficient_n_per_m2 = 6e8;
  mp.radial_coefficient_n_per_m2 = 2e8;
  mp.radial_immersion = 0.05;
  const ForcedResponseSolver s(m, Process::milling(mp));
  const ForcedResponse r = s.response({20000.0, 3e-3, 0.05e-3, true});
  EXPECT_FALSE(r.stable);
  EXPECT_GE(r.spectral_radius, 1.0);
  EXPECT_FALSE(r.linear_limit_holds);
  EXPECT_TRUE(std::isnan(r.surface_location_error_m));
  EXPECT_TRUE(r.t_s.empty());
  EXPECT_LT(s.stability().limit_at(chatter::SpindleSpeed(20000.0)).depth_limit_m, 3e-3);
}

TEST(Forced, BadInputNamesTheRule) {
  const ForcedResponseSolver s(two_mode_tool(), Process::milling(three_teeth(MillingDirection::kDown, 0.5)));
  EXPECT_THROW(s.response({-1.0, 1e-3, 1e-4, false}), chatter::InputError);
  EXPECT_THROW(s.response({1000.0, -1e-3, 1e-4, false}), chatter::InputError);
  EXPECT_THROW(s.response({1000.0, 1e-3, std::nan(""), false}), chatter::InputError);
  ForcedOptions o;
  o.axial_points = 0;
  try {
    ForcedResponseSolver(two_mode_tool(), Process::milling(three_teeth(MillingDirection::kDown, 0.5)), o);
    FAIL() << "no throw";
  } catch (const chatter::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("axial_points = 0: must be >= 1"), std::string::npos) << e.what();
  }
  chatter::TurningParameters tp;
  tp.feed_force_coefficient_n_per_m2 = 1e9;
  EXPECT_THROW(chatter::static_deflection_turning(two_mode_tool(), Process::milling(three_teeth(MillingDirection::kDown, 0.5)), 1e-3, 1e-4),
               chatter::InputError);
  EXPECT_THROW(chatter::static_deflection_turning(two_mode_tool(), Process::turning(tp), 1e-3, -1.0), chatter::InputError);
}

}  // namespace
