// Direct tests of the internal numerics the solvers share (src/solvers/):
// Brent's root finder of roots.hpp, the phase search of phase_search.hpp and
// the Hessenberg eigenvalues of hessenberg_eigen.hpp. Answers are closed
// forms (roots of elementary functions, the 1-DOF delay equation and its
// minimum 2kζ(1+ζ)/K_f, roots of unity), residuals or an independent
// eigen-solver (Eigen's, a different algorithm path: reduction + Schur).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>
#include <random>

#include "chatter/error.hpp"
#include "solvers/hessenberg_eigen.hpp"
#include "solvers/phase_search.hpp"
#include "solvers/roots.hpp"

namespace chatter {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// --------------------------------------------------------------- roots

// A root asked to round-off (xtol = 1e-15·|root|) must come back within this
// relative error: the tolerance plus a few ulps of the root.
constexpr double kRoundOffRelative = 1e-14;
// Brent converges superlinearly: a smooth root to round-off from a unit
// bracket takes far fewer evaluations than this (bisection would need ~50).
constexpr int kMaxSmoothEvaluations = 40;

// A fifth-order root: f vanishes to round-off only where |x − 1|⁵ underflows,
// but its sign is exact, so the bracket still shrinks; asked less of it.
constexpr double kFlatRootAbsolute = 1e-6;

struct Case {
  const char* name;
  double (*f)(double);
  double a, b, root;
  bool smooth = true;  // a simple root: superlinear convergence, round-off accuracy
  bool flat = false;   // a multiple root: only kFlatRootAbsolute
};

const std::vector<Case>& cases() {
  static const std::vector<Case> c = {
      {"cos on [0, 2]", [](double x) { return std::cos(x); }, 0.0, 2.0, kPi / 2},
      {"x^3 - 2 on [0, 3]", [](double x) { return x * x * x - 2.0; }, 0.0, 3.0, std::cbrt(2.0)},
      {"exp(x) - 10 on [-1, 5]", [](double x) { return std::exp(x) - 10.0; }, -1.0, 5.0, std::log(10.0)},
      {"decreasing 1/x - 4 on [0.1, 2]", [](double x) { return 1.0 / x - 4.0; }, 0.1, 2.0, 0.25},
      {"flat (x-1)^5 on [0, 3]", [](double x) { return std::pow(x - 1.0, 5); }, 0.0, 3.0, 1.0, false, true},
      {"kink |x-0.3|(x-0.3) on [-1, 1]", [](double x) { return std::abs(x - 0.3) * (x - 0.3); }, -1.0, 1.0, 0.3,
       false, false},
  };
  return c;
}

template <class Finder>
void check_known_roots(Finder find, const char* finder) {
  for (const Case& c : cases()) {
    int evaluations = 0;
    auto f = [&](double x) {
      ++evaluations;
      return c.f(x);
    };
    const double xtol = 1e-15 * std::abs(c.root);
    const double x = find(f, c.a, c.b, c.f(c.a), c.f(c.b), xtol);
    const double allowed = c.flat ? kFlatRootAbsolute : kRoundOffRelative * std::abs(c.root);
    EXPECT_LE(std::abs(x - c.root), allowed) << finder << ", " << c.name << ": got " << x << ", exact " << c.root;
    if (c.smooth) {
      EXPECT_LE(evaluations, kMaxSmoothEvaluations) << finder << ", " << c.name;
    }
  }
}

template <class Finder>
void check_tolerance_honoured(Finder find, const char* finder) {
  // A coarse tolerance stops early but still returns a point within xtol of
  // the root (plus ulps), whatever the bracket.
  for (const double xtol : {1e-2, 1e-4, 1e-8}) {
    for (const Case& c : cases()) {
      if (c.flat) continue;  // a multiple root: covered above
      const double x = find(c.f, c.a, c.b, c.f(c.a), c.f(c.b), xtol);
      EXPECT_LE(std::abs(x - c.root), xtol + 8 * kEps * std::abs(c.root))
          << finder << ", " << c.name << ", xtol " << xtol << ": got " << x << ", exact " << c.root;
    }
  }
}

template <class Finder>
void check_bracket_rules(Finder find, const char* finder) {
  auto f = [](double x) { return x * x - 2.0; };
  // Same sign at both ends: no bracket.
  EXPECT_THROW(find(f, 2.0, 3.0, f(2.0), f(3.0), 1e-12), NumericalError) << finder;
  EXPECT_THROW(find(f, -1.0, 1.0, f(-1.0), f(1.0), 1e-12), NumericalError) << finder;
  // A zero at an end is returned as is, without evaluating inside.
  int evaluations = 0;
  auto g = [&](double x) {
    ++evaluations;
    return x - 1.0;
  };
  EXPECT_EQ(find(g, 1.0, 4.0, 0.0, 3.0, 1e-12), 1.0) << finder;
  EXPECT_EQ(find(g, -2.0, 1.0, -3.0, 0.0, 1e-12), 1.0) << finder;
  EXPECT_EQ(evaluations, 0) << finder;
}

auto brent = [](auto&& f, double a, double b, double fa, double fb, double xtol) {
  return detail::brent_root(f, a, b, fa, fb, xtol);
};

TEST(Roots, BrentFindsKnownRootsToRoundOff) { check_known_roots(brent, "brent_root"); }
TEST(Roots, BrentHonoursItsTolerance) { check_tolerance_honoured(brent, "brent_root"); }
TEST(Roots, BrentRefusesAnUnbracketedRoot) { check_bracket_rules(brent, "brent_root"); }

// --------------------------------------------------------- phase search
//
// One mode along X under turning: H₀G = K_f g(ω) with g = 1/(k(1 − r² + 2jζr)),
// so the single branch λ = K_f g gives the 1-DOF delay equation
//   1 + a (1 − e^{−jωτ}) K_f g(ω) = 0,
// whose depth on the boundary is a(ω) = −1/(2 K_f Re g(ω)) and whose lowest
// value over ω is 2kζ(1+ζ)/K_f (Tobias; Altintas, Manufacturing Automation §3).

struct OneDof {
  double fn_hz = 94.22, zeta = 0.033, k = 45e6, kf = 2.4e9;
  double wn() const { return kTwoPi * fn_hz; }
  Complex g(double w) const {
    const double r = w / wn();
    return 1.0 / (k * Complex(1.0 - r * r, 2.0 * zeta * r));
  }
  double boundary_depth(double w) const { return -1.0 / (2.0 * kf * g(w).real()); }
  // |1 + a(1 − e^{−jωτ}) K_f g(ω)|: zero on the stability boundary.
  double residual(double a, double w, double tau) const {
    return std::abs(1.0 + a * (1.0 - std::exp(Complex(0.0, -w * tau))) * kf * g(w));
  }
};

double wrap_2pi(double x) {
  x = std::fmod(x, kTwoPi);
  return x < 0.0 ? x + kTwoPi : x;
}

detail::BranchValue branch_of(Complex lambda) {
  return {lambda, -2.0 * lambda.real(), wrap_2pi(3.0 * kPi + 2.0 * std::arg(lambda))};
}

detail::PhaseSearch one_dof_search(const OneDof& m, double depth_max_m) {
  return detail::PhaseSearch([m](double w, std::array<detail::BranchValue, 2>& out) { out[0] = branch_of(m.kf * m.g(w)); },
                             1, 0.2 * m.wn(), 5.0 * m.wn(), depth_max_m);
}

// The characteristic equation at a reported root: |1 + a(1 − e^{−jωτ})K_f g|
// is a sum of O(1) terms, so round-off leaves ~1e-15; the refinement's own
// tolerance (1e-15 ω) adds at most ~1e-12 through dε/dω·τ.
constexpr double kResidual = 1e-9;
// The minimum by golden-section search is exact to round-off in ω; the depth
// is flat there, so its relative error is ~ (δω/ω)² — far below this.
constexpr double kMinimumRelative = 1e-10;

TEST(PhaseSearch, LowestRootSolvesTheDelayEquation) {
  const OneDof m;
  const double depth_max = 0.05;
  const detail::PhaseSearch ps = one_dof_search(m, depth_max);
  int bounded = 0;
  for (double rpm = 300.0; rpm <= 6000.0; rpm *= 1.37) {
    const double tau = 60.0 / rpm;
    const detail::PhaseRoot r = ps.lowest_root(tau);
    if (!std::isfinite(r.depth_m)) continue;
    ++bounded;
    EXPECT_LT(m.residual(r.depth_m, r.omega, tau), kResidual)
        << "rpm " << rpm << ": a = " << r.depth_m << " m at " << r.omega / kTwoPi << " Hz";
    EXPECT_NEAR(r.depth_m / m.boundary_depth(r.omega), 1.0, kResidual) << "rpm " << rpm;
    EXPECT_LE(r.depth_m, depth_max);
    EXPECT_GE(r.lobe, 0);
    EXPECT_EQ(r.branch, 0);
    // Chatter above the natural frequency, on the side where Re g < 0.
    EXPECT_GT(r.omega, m.wn()) << "rpm " << rpm;
  }
  EXPECT_GT(bounded, 5) << "too few bounded speeds to test anything";
}

TEST(PhaseSearch, LowestRootIsTheLowestOfADenseScanOfBoundaryPoints) {
  // Independent answer: at delay τ the boundary points are the ω where
  // ωτ − ε(ω) crosses 2πk; scan ω densely (10⁵ log-spaced points) and take
  // the lowest depth among the crossings. The search must match it to the
  // scan's resolution in depth (flat near a lobe bottom, steep on the flanks).
  constexpr double kScanRelative = 1e-3;
  const OneDof m;
  const detail::PhaseSearch ps = one_dof_search(m, 0.05);
  const int n = 100000;
  for (double rpm : {500.0, 1130.0, 2400.0, 4700.0}) {
    const double tau = 60.0 / rpm;
    double best = std::numeric_limits<double>::infinity();
    const double w0 = 0.2 * m.wn();
    double prev_t = 0.0, prev_s = 0.0, unwrapped = 0.0, last_phase = 0.0;
    for (int i = 0; i < n; ++i) {
      const double w = w0 * std::pow(25.0, static_cast<double>(i) / (n - 1));
      const detail::BranchValue v = branch_of(m.kf * m.g(w));
      if (i == 0) unwrapped = v.phase;
      else unwrapped += std::remainder(v.phase - last_phase, kTwoPi);
      last_phase = v.phase;
      const double t = (w * tau - unwrapped) / kTwoPi;  // lobe count: crossing an integer = a boundary point
      if (i > 0 && std::floor(t) != std::floor(prev_t)) {
        const double k = std::max(std::floor(t), std::floor(prev_t));
        const double s = prev_s + (k - prev_t) / (t - prev_t) * (v.s - prev_s);  // linear in between
        if (s > 0.0) best = std::min(best, 1.0 / s);
      }
      prev_t = t;
      prev_s = v.s;
    }
    const detail::PhaseRoot r = ps.lowest_root(tau);
    if (!(best <= 0.05)) {
      EXPECT_FALSE(std::isfinite(r.depth_m)) << "rpm " << rpm << ": scan finds none, search " << r.depth_m;
      continue;
    }
    EXPECT_NEAR(r.depth_m / best, 1.0, kScanRelative) << "rpm " << rpm << ": search " << r.depth_m << ", scan " << best;
  }
}

TEST(PhaseSearch, MinimumDepthIsTheClosedForm) {
  const OneDof m;
  const detail::PhaseSearch ps = one_dof_search(m, 0.05);
  const detail::PhaseRoot r = ps.minimum_depth();
  const double exact = 2.0 * m.k * m.zeta * (1.0 + m.zeta) / m.kf;
  EXPECT_NEAR(r.depth_m / exact, 1.0, kMinimumRelative) << "search " << r.depth_m << ", closed form " << exact;
  // The minimum sits exactly at r² = 1 + 2ζ; the depth is flat there, so ω is
  // located only to ~√ε of the golden-section search: allowed 1e-6.
  constexpr double kMinimumOmegaRelative = 1e-6;
  EXPECT_NEAR(r.omega / (m.wn() * std::sqrt(1.0 + 2.0 * m.zeta)), 1.0, kMinimumOmegaRelative) << r.omega;
}

TEST(PhaseSearch, CurvePointsLieOnTheBoundary) {
  const OneDof m;
  const double tau_min = 60.0 / 3000.0, tau_max = 60.0 / 600.0;
  const detail::PhaseSearch ps = one_dof_search(m, 0.05);
  const auto curves = ps.curves(tau_min, tau_max);
  ASSERT_FALSE(curves.empty());
  std::size_t points = 0;
  for (const auto& c : curves) {
    for (const auto& p : c.points) {
      ++points;
      EXPECT_GE(p.tau_s, tau_min);
      EXPECT_LE(p.tau_s, tau_max);
      EXPECT_LE(p.depth_m, 0.05);
      EXPECT_NEAR(p.depth_m / m.boundary_depth(p.omega), 1.0, kResidual);
      EXPECT_LT(m.residual(p.depth_m, p.omega, p.tau_s), kResidual)
          << "lobe " << c.lobe << " at " << p.omega / kTwoPi << " Hz";
    }
  }
  EXPECT_GT(points, 50u);
}

TEST(PhaseSearch, TwoBranchesGiveTheLowerOfTheirSingleBranchRoots) {
  // Diagonal H₀ on modes along X and Y: the branches decouple, so the lowest
  // root is the lower of the two 1-DOF searches.
  const OneDof x, y{150.0, 0.02, 30e6, 1.6e9};
  const double lo = 0.1 * x.wn(), hi = 10.0 * y.wn();
  const detail::PhaseSearch both(
      [&](double w, std::array<detail::BranchValue, 2>& out) {
        out[0] = branch_of(x.kf * x.g(w));
        out[1] = branch_of(y.kf * y.g(w));
      },
      2, lo, hi, 0.05);
  auto single = [&](const OneDof& m) {
    return detail::PhaseSearch([m](double w, std::array<detail::BranchValue, 2>& out) { out[0] = branch_of(m.kf * m.g(w)); },
                               1, lo, hi, 0.05);
  };
  const detail::PhaseSearch sx = single(x), sy = single(y);
  for (double rpm : {700.0, 1500.0, 3100.0, 5200.0}) {
    const double tau = 60.0 / rpm;
    const detail::PhaseRoot r = both.lowest_root(tau), rx = sx.lowest_root(tau), ry = sy.lowest_root(tau);
    const double expect = std::min(rx.depth_m, ry.depth_m);
    if (!std::isfinite(expect)) {
      EXPECT_FALSE(std::isfinite(r.depth_m)) << rpm;
      continue;
    }
    EXPECT_NEAR(r.depth_m / expect, 1.0, kResidual) << "rpm " << rpm << ": " << r.depth_m << " vs " << expect;
    const OneDof& m = rx.depth_m <= ry.depth_m ? x : y;
    EXPECT_LT(m.residual(r.depth_m, r.omega, tau), kResidual) << rpm;
  }
}

TEST(PhaseSearch, NothingToSearchAndBadArguments) {
  const OneDof m;
  // No branch: nothing can be unstable.
  const detail::PhaseSearch none([](double, std::array<detail::BranchValue, 2>&) {}, 0, 1.0, 10.0, 0.05);
  EXPECT_FALSE(std::isfinite(none.lowest_root(0.01).depth_m));
  EXPECT_FALSE(std::isfinite(none.minimum_depth().depth_m));
  // A depth cap below the closed-form minimum: no root at any delay.
  const double below = 0.5 * 2.0 * m.k * m.zeta * (1.0 + m.zeta) / m.kf;
  const detail::PhaseSearch capped = one_dof_search(m, below);
  for (double rpm : {500.0, 2000.0, 5000.0}) EXPECT_FALSE(std::isfinite(capped.lowest_root(60.0 / rpm).depth_m)) << rpm;
  auto eval = [m](double w, std::array<detail::BranchValue, 2>& out) { out[0] = branch_of(m.kf * m.g(w)); };
  EXPECT_THROW(detail::PhaseSearch(eval, 3, 1.0, 10.0, 0.05), NumericalError);
  EXPECT_THROW(detail::PhaseSearch(eval, 1, 10.0, 1.0, 0.05), NumericalError);
  EXPECT_THROW(detail::PhaseSearch(eval, 1, 1.0, 10.0, 0.0), NumericalError);
}

// --------------------------------------------------------------- Hessenberg eigenvalues

// Largest distance from each eigenvalue of `want` to its own match in `got`
// (greedy nearest unused), over ‖H‖_F.
double eigenvalue_mismatch(const Eigen::VectorXcd& got, const Eigen::VectorXcd& want, double scale) {
  std::vector<bool> used(static_cast<std::size_t>(got.size()), false);
  double worst = 0.0;
  for (Eigen::Index i = 0; i < want.size(); ++i) {
    Eigen::Index best = -1;
    double d = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < got.size(); ++j)
      if (!used[static_cast<std::size_t>(j)] && std::abs(got(j) - want(i)) < d) {
        d = std::abs(got(j) - want(i));
        best = j;
      }
    if (best < 0) return std::numeric_limits<double>::infinity();
    used[static_cast<std::size_t>(best)] = true;
    worst = std::max(worst, d / scale);
  }
  return worst;
}

// Backward-stable QR on a Hessenberg matrix: eigenvalues within a modest
// multiple of ε‖H‖ of the exact ones for well-conditioned cases; random
// matrices have some ill-conditioned eigenvalues, hence the margin
// (measured worst over these 3 000: 8e-14).
constexpr double kEigenAgree = 1e-10;

TEST(HessenbergEigenvalues, AgreeWithEigenOnRandomMatricesOfEverySize) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = 1 + trial % 30;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
    const double scale = trial % 7 == 0 ? 1e3 : trial % 7 == 1 ? 1e-3 : 1.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i <= std::min(j + 1, n - 1); ++i) h(i, j) = scale * normal(rng);
    if (trial % 5 == 0 && n > 3) h(n / 2, n / 2 - 1) = 0.0;  // already split
    Eigen::VectorXcd got;
    detail::hessenberg_eigenvalues(h, got);
    ASSERT_EQ(got.size(), n);
    const Eigen::EigenSolver<Eigen::MatrixXd> ref(h, false);
    EXPECT_LT(eigenvalue_mismatch(got, ref.eigenvalues(), h.norm()), kEigenAgree) << "trial " << trial << ", n " << n;
    for (Eigen::Index i = 0; i < n; ++i)  // complex values come in conjugate pairs
      if (got(i).imag() != 0.0) {
        bool paired = false;
        for (Eigen::Index j = 0; j < n; ++j) paired = paired || (j != i && got(j) == std::conj(got(i)));
        EXPECT_TRUE(paired) << got(i);
      }
  }
}

TEST(HessenbergEigenvalues, CyclicShiftHasTheRootsOfUnity) {
  // The cyclic shift: every eigenvalue on the unit circle, equal moduli (the
  // standard shifts stall here; the exceptional ones must break the tie).
  for (int n : {3, 4, 8, 13, 30}) {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i + 1 < n; ++i) h(i + 1, i) = 1.0;
    h(0, n - 1) = 1.0;
    Eigen::VectorXcd got;
    detail::hessenberg_eigenvalues(h, got);
    Eigen::VectorXcd roots(n);
    for (int k = 0; k < n; ++k) roots(k) = std::polar(1.0, kTwoPi * k / n);
    EXPECT_LT(eigenvalue_mismatch(got, roots, 1.0), 1e-12) << n;
  }
}

TEST(HessenbergEigenvalues, TriangularAndTwoByTwoClosedForms) {
  Eigen::MatrixXd t(3, 3);
  t << 2.0, 5.0, -1.0, 0.0, -3.0, 4.0, 0.0, 0.0, 0.5;  // triangular: the diagonal
  Eigen::VectorXcd got;
  detail::hessenberg_eigenvalues(t, got);
  EXPECT_LT(eigenvalue_mismatch(got, Eigen::Vector3cd(2.0, -3.0, 0.5), 1.0), 1e-15);
  Eigen::MatrixXd r(2, 2);
  r << 0.0, -4.0, 1.0, 0.0;  // λ² + 4 = 0: ±2j
  detail::hessenberg_eigenvalues(r, got);
  EXPECT_LT(eigenvalue_mismatch(got, Eigen::Vector2cd(Complex(0.0, 2.0), Complex(0.0, -2.0)), 1.0), 1e-15);
  r << 1e-20, 1.0, 1e-20, 1e-20;  // tiny entries: λ = 1e-20 ± 1e-10
  detail::hessenberg_eigenvalues(r, got);
  EXPECT_LT(eigenvalue_mismatch(got, Eigen::Vector2cd(1e-20 + 1e-10, 1e-20 - 1e-10), 1e-10), 1e-9);
}

TEST(HessenbergEigenvalues, RefusesNonFiniteEntries) {
  Eigen::MatrixXd h = Eigen::MatrixXd::Identity(4, 4);
  h(1, 2) = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXcd got;
  EXPECT_THROW(detail::hessenberg_eigenvalues(h, got), NumericalError);
}

}  // namespace
}  // namespace chatter
