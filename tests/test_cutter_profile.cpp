// The cutter's shape along its axis (include/chatter/cutter_profile.hpp,
// docs/cutter_geometry.md): the geometry of ball and bull-nose corners, the
// averaged directional matrix H₀(a) of a ball end mill against a quadrature
// of the Lee & Altintas (1996) projection written here, the flat cutter
// through the general-profile path against the flat cutter, and the rules
// Process::milling enforces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "chatter/cutter_profile.hpp"
#include "chatter/error.hpp"
#include "chatter/process.hpp"

namespace chatter {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- tolerances (relative unless said otherwise) ----
// Closed forms against each other (R, κ, Λ): round-off only.
constexpr double kClosedForm = 1e-12;
// The flat cutter through the general path: the same integrals summed over
// slices instead of taken at once; round-off of a few dozen terms.
constexpr double kFlatThroughGeneral = 1e-12;
// H₀(a) on 2000 slices against the Gauss quadrature below: the slices' mid
// point rule converges as S^-1.5 at the ball's tip (κ ~ sqrt(z)); measured
// 4.4e-6 at 2000 slices (a_e/D = 0.2), the bound leaves a factor ~20.
constexpr double kH0Quadrature = 1e-4;
// Λ of a bull nose against a Simpson quadrature of 1/R(z) (20 000 panels).
constexpr double kLagQuadrature = 1e-9;

::testing::AssertionResult RelNear(double actual, double expected, double tol) {
  const double err = std::abs(actual - expected) / std::max(std::abs(expected), 1e-300);
  if (err <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "actual " << actual << ", expected " << expected << ", relative error " << err
                                       << " > " << tol;
}

// Relative to the larger norm, or to `floor` when that is larger (an
// integral over a span out of the cut is 0 up to the round-off of its
// closed form: compared with the size the integral has in the cut).
::testing::AssertionResult MatrixNear(const Eigen::Matrix2d& actual, const Eigen::Matrix2d& expected, double tol,
                                      double floor = 0.0) {
  const double scale = std::max({actual.norm(), expected.norm(), floor});
  const double err = scale == 0.0 ? 0.0 : (actual - expected).norm() / scale;
  if (err <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "actual\n" << actual << "\nexpected\n" << expected << "\nrelative error " << err
                                       << " > " << tol;
}

constexpr double kR0 = 5e-3;  // 10 mm cutter

MillingParameters ball_cutter(double immersion, MillingDirection dir = MillingDirection::kDown) {
  MillingParameters p;
  p.teeth = 2;
  p.tangential_coefficient_n_per_m2 = 1.8e9;
  p.radial_coefficient_n_per_m2 = 0.63e9;
  p.axial_coefficient_n_per_m2 = 0.4e9;
  p.radial_immersion = immersion;
  p.direction = dir;
  p.tool_diameter_m = 2 * kR0;
  p.helix_angles_rad = {30.0 * kPi / 180.0};
  p.cutter.geometry = CutterGeometry::kBall;
  return p;
}

// Gauss–Legendre nodes and weights on [-1, 1] (Newton on P_n).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double t = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (t * p1 - p0) / (t * t - 1.0);
      const double dt = p1 / dp;
      t -= dt;
      if (std::abs(dt) < 1e-15) break;
    }
    x[static_cast<std::size_t>(i)] = t;
    w[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - t * t) * dp * dp);
  }
}

// ∫_lo^hi f by composite Gauss–Legendre (panels × 20 points).
template <class F>
Eigen::Matrix2d integrate(F f, double lo, double hi, int panels = 8) {
  static std::vector<double> x, w;
  if (x.empty()) gauss_legendre(20, x, w);
  Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
  const double h = (hi - lo) / panels;
  for (int p = 0; p < panels; ++p)
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double u = lo + h * (p + 0.5 * (x[i] + 1.0));
      s += 0.5 * h * w[i] * f(u);
    }
  return s;
}

// H₀(a) of a ball end mill (down milling) from the Lee–Altintas projection:
// for a unit regenerative displacement Δr the chip is h = sin κ (sin φ Δx +
// cos φ Δy), the width db = dz / sin κ, dF_t,r,a = K_t,r,a h db and
//   dF_x = −dF_r sin κ sin φ − dF_t cos φ − dF_a cos κ sin φ,
//   dF_y = −dF_r sin κ cos φ + dF_t sin φ − dF_a cos κ cos φ;
// F = −a H₀ Δr averaged over a revolution (N_t/2π) and over the depth (1/a).
// The ball is integrated in κ (z = R₀(1 − cos κ), dz = R₀ sin κ dκ), split
// where the slice circle first meets the band −R₀ <= y <= −R₀ + a_e.
Eigen::Matrix2d ball_h0_quadrature(const MillingParameters& p, double a) {
  const double kt = p.tangential_coefficient_n_per_m2, kr = p.radial_coefficient_n_per_m2,
               ka = p.axial_coefficient_n_per_m2, r0 = 0.5 * p.tool_diameter_m, ae = p.radial_immersion * 2 * r0;
  auto slice = [&](double kappa, double radius) {  // ∫ over the arc of ∂(−dF/dz)/∂Δr
    const double c = (ae - r0) / radius;              // cos φ_en: the band's inner edge on this circle
    if (c <= -1.0) return Eigen::Matrix2d::Zero().eval();  // the circle does not reach the band
    const double en = c >= 1.0 ? 0.0 : std::acos(c);
    const double sk = std::sin(kappa), ck = std::cos(kappa);
    return integrate(
        [&](double phi) {
          const double s = std::sin(phi), co = std::cos(phi);
          // per unit dz and unit (sin φ Δx + cos φ Δy): h db = 1
          const double fx = -kr * sk * s - kt * co - ka * ck * s;
          const double fy = -kr * sk * co + kt * s - ka * ck * co;
          Eigen::Matrix2d m;
          m << -fx * s, -fx * co, -fy * s, -fy * co;
          return m;
        },
        en, kPi, 4);
  };
  const double kappa_top = a >= r0 ? 0.5 * kPi : std::acos(1.0 - a / r0);
  const double kappa_band = ae >= r0 ? 0.0 : std::asin((r0 - ae) / r0);  // R₀ sin κ = R₀ − a_e
  auto ball = [&](double kappa) { return (slice(kappa, r0 * std::sin(kappa)) * (r0 * std::sin(kappa))).eval(); };
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  if (kappa_band < kappa_top) sum += integrate(ball, kappa_band, kappa_top, 16);
  if (a > r0) sum += slice(0.5 * kPi, r0) * (a - r0);  // the cylinder above the equator
  return p.teeth / (2 * kPi * a) * sum;
}

TEST(CutterProfile, BallAndBullNoseGeometry) {
  CutterProfileParameters ball;
  ball.geometry = CutterGeometry::kBall;
  const CutterProfile b = CutterProfile::make(ball, kR0);
  for (const double z : {0.2e-3, 1e-3, 2.5e-3, 4.9e-3}) {
    const double kappa = std::acos(1.0 - z / kR0);
    EXPECT_TRUE(RelNear(b.radius_m(z), kR0 * std::sin(kappa), kClosedForm)) << "R at z = " << z;
    EXPECT_TRUE(RelNear(b.lead_angle_rad(z), kappa, kClosedForm)) << "kappa at z = " << z;
    EXPECT_TRUE(RelNear(b.lag_integral(z), kappa, kClosedForm)) << "ball: Lambda = kappa at z = " << z;
  }
  EXPECT_EQ(b.lead_angle_rad(6e-3), 0.5 * kPi);  // exactly 90° on the shank
  EXPECT_EQ(b.radius_m(6e-3), kR0);
  EXPECT_TRUE(RelNear(b.lag_integral(6e-3), 0.5 * kPi + 1e-3 / kR0, kClosedForm));

  // Bull nose: Λ(z) against Simpson's rule on 1/R(z) (the corner's closed
  // form has three branches: r_c above, below and at R₀ − r_c).
  for (const double rc : {1e-3, 2.5e-3, 4e-3}) {
    CutterProfileParameters bn;
    bn.geometry = CutterGeometry::kBullNose;
    bn.corner_radius_m = rc;
    const CutterProfile c = CutterProfile::make(bn, kR0);
    const double z_end = 0.8 * rc;
    // Simpson in κ (z = r_c(1 − cos κ)): dz / R = r_c sin κ dκ / (R₀ − r_c + r_c sin κ).
    const double k_end = std::acos(1.0 - z_end / rc);
    const int n = 20000;
    double s = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double k = k_end * i / n;
      const double f = rc * std::sin(k) / (kR0 - rc + rc * std::sin(k));
      s += f * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    s *= k_end / (3.0 * n);
    EXPECT_TRUE(RelNear(c.lag_integral(z_end), s, kLagQuadrature)) << "bull nose r_c = " << rc;
    EXPECT_TRUE(RelNear(c.radius_m(rc), kR0, kClosedForm));
    EXPECT_TRUE(RelNear(c.radius_m(0.0), kR0 - rc, kClosedForm));
  }
}

TEST(CutterProfile, SliceEngagementIsTheNominalArcAtFullRadiusSlotAndHalf) {
  for (const double ae : {0.1, 0.37, 0.5, 0.8, 1.0})
    for (const bool down : {true, false}) {
      const SliceEngagement e = slice_engagement(kR0, kR0, ae, down);
      MillingParameters p = ball_cutter(ae, down ? MillingDirection::kDown : MillingDirection::kUp);
      p.cutter = {};
      const Process flat = Process::milling(p);
      EXPECT_EQ(e.entry_rad, flat.entry_angle()) << "a_e/D = " << ae;  // bit for bit
      EXPECT_EQ(e.exit_rad, flat.exit_angle()) << "a_e/D = " << ae;
      if (ae == 0.5 || ae == 1.0)
        for (const double r : {0.3e-3, 2e-3, 4.5e-3}) {
          const SliceEngagement s = slice_engagement(r, kR0, ae, down);
          EXPECT_EQ(s.entry_rad, e.entry_rad) << "a_e/D = " << ae << ", r = " << r;
          EXPECT_EQ(s.exit_rad, e.exit_rad) << "a_e/D = " << ae << ", r = " << r;
        }
    }
  // A small circle misses a narrow band; a larger one meets it.
  EXPECT_FALSE(slice_engagement(3e-3, kR0, 0.1, true).engaged);  // band −5 … −4 mm, circle of 3 mm
  EXPECT_TRUE(slice_engagement(4.5e-3, kR0, 0.1, true).engaged);
  EXPECT_NEAR(slice_engagement(4.5e-3, kR0, 0.1, true).entry_rad, std::acos(-4.0 / 4.5), 1e-15);
}

TEST(CutterProfile, BallAveragedDirectionalMatrixMatchesLeeAltintasQuadrature) {
  for (const double ae : {0.5, 0.2, 1.0})
    for (const double a : {1e-3, 3e-3, 7e-3}) {
      MillingParameters p = ball_cutter(ae);
      p.cutter.slices = 2000;
      const Process pr = Process::milling(p);
      const Eigen::Matrix2d expected = ball_h0_quadrature(p, a);
      EXPECT_TRUE(MatrixNear(pr.average_directional_matrix_at(a), expected, kH0Quadrature))
          << "a_e/D = " << ae << ", a = " << a * 1e3 << " mm";
      // The frozen process gives the same H₀ to the averaged methods.
      EXPECT_EQ(pr.at_depth(a).average_directional_matrix(), pr.average_directional_matrix_at(a));
    }
}

TEST(CutterProfile, AveragedMatrixConvergesWithSlices) {
  const MillingParameters base = ball_cutter(0.5);
  const double a = 2e-3;
  const Eigen::Matrix2d expected = ball_h0_quadrature(base, a);
  double previous = 1.0;
  for (const int s : {8, 16, 32, 64, 128}) {
    MillingParameters p = base;
    p.cutter.slices = s;
    const double err = (Process::milling(p).average_directional_matrix_at(a) - expected).norm() / expected.norm();
    EXPECT_LT(err, previous) << s << " slices: error " << err << " not below " << previous;
    previous = err;
  }
  // Measured 7.2e-4, 2.6e-4, 9.5e-5, 3.4e-5, 1.2e-5 (order 1.5).
  EXPECT_LT(previous, 3e-5) << "128 slices";
}

TEST(CutterProfile, BullNoseOfFullRadiusIsTheBallAndATabulatedBallConverges) {
  const double a = 3e-3;
  const MillingParameters ball = ball_cutter(0.3);
  MillingParameters bull = ball;
  bull.cutter.geometry = CutterGeometry::kBullNose;
  bull.cutter.corner_radius_m = kR0;
  const Process pb = Process::milling(ball), pn = Process::milling(bull);
  EXPECT_TRUE(MatrixNear(pn.average_directional_matrix_at(a), pb.average_directional_matrix_at(a), kClosedForm));
  EXPECT_TRUE(RelNear(pn.tooth_angle_rad(1, 1e-4, 2e-3, 9000.0), pb.tooth_angle_rad(1, 1e-4, 2e-3, 9000.0), kClosedForm));
  // The ball tabulated as a general profile (straight teeth: a radius 0 at
  // the tip is allowed): linear between rows, so the error falls with the
  // row spacing (second order away from the tip).
  double previous = 1.0;
  for (const int rows : {10, 40, 160}) {
    MillingParameters g = ball;
    g.helix_angles_rad.clear();
    g.cutter.geometry = CutterGeometry::kGeneral;
    g.cutter.slices = 400;
    for (int i = 0; i <= rows; ++i) {
      const double z = kR0 * i / rows, kappa = std::acos(1.0 - z / kR0);
      g.cutter.profile.push_back({z, kR0 * std::sin(kappa), kappa});
    }
    MillingParameters b = ball;
    b.cutter.slices = 400;
    const Eigen::Matrix2d ref = Process::milling(b).average_directional_matrix_at(a);
    const double err = (Process::milling(g).average_directional_matrix_at(a) - ref).norm() / ref.norm();
    EXPECT_LT(err, previous) << rows << " rows: error " << err << " not below " << previous;
    previous = err;
  }
  EXPECT_LT(previous, 1e-3) << "160 rows";
}

MillingParameters flat_as_general(double helix_deg) {
  MillingParameters p = ball_cutter(0.3);
  p.axial_coefficient_n_per_m2 = 0.4e9;  // no effect at κ = 90°
  p.helix_angles_rad = {helix_deg * kPi / 180.0};
  p.cutter.geometry = CutterGeometry::kGeneral;
  p.cutter.profile = {{0.0, kR0, 0.5 * kPi}, {20e-3, kR0, 0.5 * kPi}};
  p.cutter.slices = 20;
  return p;
}

TEST(CutterProfile, FlatThroughGeneralPathIsTheFlatCutter) {
  for (const double helix : {0.0, 30.0}) {
    const MillingParameters g = flat_as_general(helix);
    MillingParameters f = g;
    f.cutter = {};
    const Process general = Process::milling(g), flat = Process::milling(f);
    ASSERT_TRUE(general.has_profile());
    ASSERT_FALSE(flat.has_profile());
    const double a = 3e-3, rpm = 12000.0, tooth = 60.0 / rpm / 2;
    EXPECT_TRUE(MatrixNear(general.average_directional_matrix_at(a), flat.average_directional_matrix(), kFlatThroughGeneral));
    for (int j = 0; j < 2; ++j)
      for (const double t0 : {0.0, 0.13, 0.41, 0.77}) {
        const double ta = t0 * tooth, tb = ta + 0.05 * tooth;
        const double in_cut = (1.8e9 + 0.63e9) * a * (tb - ta);  // (K_t + K_r) a Δt
        EXPECT_TRUE(MatrixNear(general.tooth_force_integral(j, ta, tb, a, rpm), flat.tooth_force_integral(j, ta, tb, a, rpm),
                               kFlatThroughGeneral, in_cut))
            << "helix " << helix << ", tooth " << j << ", t = " << ta;
        EXPECT_TRUE(RelNear(general.tooth_angle_rad(j, ta, 2e-3, rpm), flat.tooth_angle_rad(j, ta, 2e-3, rpm),
                            kFlatThroughGeneral));
      }
    EXPECT_TRUE(RelNear(general.tooth_delay_s(1, 2e-3, rpm), flat.tooth_delay_s(1, 2e-3, rpm), kFlatThroughGeneral));
  }
}

TEST(CutterProfile, FlatDefaultIsUntouched) {
  MillingParameters p = ball_cutter(0.3);
  p.cutter = {};
  const Process flat = Process::milling(p);
  EXPECT_FALSE(flat.has_profile());
  EXPECT_FALSE(flat.depth_dependent_force());
  EXPECT_EQ(flat.at_depth(1e-3).average_directional_matrix(), flat.average_directional_matrix());
}

std::string milling_error(const MillingParameters& p) {
  try {
    (void)Process::milling(p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CutterProfile, BadInputNamesTheRule) {
  MillingParameters p = ball_cutter(0.5);
  p.tool_diameter_m = 0.0;
  p.helix_angles_rad.clear();
  EXPECT_NE(milling_error(p).find("cutter_geometry = ball needs the tool diameter"), std::string::npos)
      << milling_error(p);
  p = ball_cutter(0.5);
  p.cutter.geometry = CutterGeometry::kBullNose;
  p.cutter.corner_radius_m = 6e-3;
  EXPECT_NE(milling_error(p).find("corner radius 6 mm: must be in (0, D/2 = 5 mm]"), std::string::npos)
      << milling_error(p);
  p = ball_cutter(0.5);
  p.cutter.geometry = CutterGeometry::kGeneral;
  p.cutter.profile = {{0.0, 1e-3, 0.2}, {1e-3, 2e-3, 0.6}, {1e-3, 3e-3, 0.9}};
  EXPECT_NE(milling_error(p).find("profile row 2: height 1 mm: heights must increase from the tip"), std::string::npos)
      << milling_error(p);
  p.cutter.profile = {{0.0, 0.0, 0.0}, {2e-3, 4e-3, 1.2}};
  EXPECT_NE(milling_error(p).find("a helix on a general profile needs every radius > 0"), std::string::npos)
      << milling_error(p);
  p.cutter.profile = {{0.0, 1e-3, 0.2}, {2e-3, 6e-3, 1.2}};
  EXPECT_NE(milling_error(p).find("profile row 1: radius 6 mm: must be in [0, D/2 = 5 mm]"), std::string::npos)
      << milling_error(p);
  p = ball_cutter(0.5);
  p.process_damping_coefficient_n_per_m = 1e4;
  EXPECT_NE(milling_error(p).find("process damping with cutter_geometry = ball is not modelled"), std::string::npos)
      << milling_error(p);
  p = ball_cutter(0.5);
  p.axial_coefficient_n_per_m2 = -1.0;
  EXPECT_NE(milling_error(p).find("axial force coefficient K_a must be >= 0"), std::string::npos) << milling_error(p);
  p = ball_cutter(0.5);
  p.cutter.slices = -3;
  EXPECT_NE(milling_error(p).find("profile slices = -3: must be in [0, 2000]"), std::string::npos) << milling_error(p);
}

// The "no cut" rule (docs/results.md): a 16 mm bull nose with a 2 mm corner
// on a 0.5 mm radial depth. The band starts R(1 − 2 a_e/D) = 7.5 mm from the
// axis; the corner reaches R − r_c + √(r_c² − (r_c − z)²) at height z: 7.32 mm
// at the top of a 0.5 mm cut (no slice engages), 7.73 mm at 1 mm (the upper
// slices do).
TEST(CutterProfile, NoChipWhereTheCornerMissesTheBand) {
  MillingParameters p;
  p.teeth = 3;
  p.tangential_coefficient_n_per_m2 = 700e6;
  p.radial_coefficient_n_per_m2 = 210e6;
  p.tool_diameter_m = 16e-3;
  p.radial_immersion = 0.5 / 16.0;
  p.cutter.geometry = CutterGeometry::kBullNose;
  p.cutter.corner_radius_m = 2e-3;
  const Process bull = Process::milling(p);
  auto reach_mm = [](double z_mm) { return 8.0 - 2.0 + std::sqrt(4.0 - (2.0 - z_mm) * (2.0 - z_mm)); };
  ASSERT_LT(reach_mm(0.5), 7.5);
  ASSERT_GT(reach_mm(1.0), 7.5);
  const std::string why = bull.no_chip_reason(0.5e-3);
  EXPECT_NE(why.find("no cut"), std::string::npos) << why;
  EXPECT_NE(why.find("reaches 7.323 mm"), std::string::npos) << why;  // reach_mm(0.5) = 7.3229
  EXPECT_NE(why.find("starts 7.5 mm"), std::string::npos) << why;
  EXPECT_EQ(bull.no_chip_reason(1.0e-3), "");
  EXPECT_NE(bull.no_chip_reason(0.0), "");
  // A flat cutter always has a chip at a depth > 0; a wide cut engages the corner at once.
  MillingParameters flat = p;
  flat.cutter = {};
  EXPECT_EQ(Process::milling(flat).no_chip_reason(0.1e-3), "");
  MillingParameters wide = p;
  wide.radial_immersion = 0.5;
  EXPECT_EQ(Process::milling(wide).no_chip_reason(0.05e-3), "");
}

}  // namespace
}  // namespace chatter
