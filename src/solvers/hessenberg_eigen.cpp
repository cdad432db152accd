// Francis double-shift QR for the eigenvalues of a small Hessenberg matrix
// (hessenberg_eigen.hpp).
#include "hessenberg_eigen.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "chatter/error.hpp"

namespace chatter::detail {
namespace {

using Cplx = std::complex<double>;

// Most QR steps per eigenvalue before giving up (LAPACK's dlahqr: 30).
constexpr int kStepsPerEigenvalue = 30;
// Exceptional shifts after this many steps without a deflation, and every
// this many after (Golub & Van Loan §7.5.6; EISPACK hqr: 10 and 20).
constexpr int kExceptionalEvery = 10;
// The exceptional shift pair of dlahqr: roots of x² − 2 (h + 0.75 w) x +
// (h + 0.75 w)² + 0.4375 w², w = |h_{i,i−1}| + |h_{i−1,i−2}|.
constexpr double kExceptionalShift = 0.75, kExceptionalSpread = 0.4375;

// The eigenvalues of [[a, b], [c, d]], scaled against overflow; a complex
// pair as (re + j im, re − j im) with im > 0.
void two_by_two(double a, double b, double c, double d, Cplx& l1, Cplx& l2) {
  const double p = 0.5 * (a - d);
  const double mx = std::max({std::abs(p), std::abs(b), std::abs(c)});
  if (mx == 0.0) {
    l1 = l2 = d;
    return;
  }
  const double ps = p / mx, q = ps * ps + (b / mx) * (c / mx);  // (p² + bc) / mx²
  if (q >= 0.0) {
    const double z = p + std::copysign(mx * std::sqrt(q), p);  // no cancellation
    l1 = d + z;
    l2 = z != 0.0 ? d - (b / z) * c : d;
  } else {
    const double im = mx * std::sqrt(-q);
    l1 = Cplx(d + p, im);
    l2 = Cplx(d + p, -im);
  }
}

// Householder reflector I − τ v vᵀ, v = [1; v1; v2], taking [x; y; z] to
// [β; 0; 0] (τ = 0 when y = z = 0).
struct Reflector {
  double v1 = 0.0, v2 = 0.0, tau = 0.0, beta = 0.0;
};
Reflector reflector(double x, double y, double z) {
  Reflector r;
  // Norms scaled by the largest entry (no overflow, no std::hypot: the
  // correctly rounded one costs as much as the rest of the step here).
  const double m = std::max({std::abs(x), std::abs(y), std::abs(z)});
  if (m == 0.0 || (y == 0.0 && z == 0.0)) {
    r.beta = x;
    return r;
  }
  const double xs = x / m, ys = y / m, zs = z / m;
  r.beta = -std::copysign(m * std::sqrt(xs * xs + ys * ys + zs * zs), x);
  const double v0 = x - r.beta;
  r.v1 = y / v0;
  r.v2 = z / v0;
  r.tau = -v0 / r.beta;
  return r;
}

}  // namespace

void hessenberg_eigenvalues(const Eigen::MatrixXd& h, Eigen::VectorXcd& eigenvalues) {
  const int n = static_cast<int>(h.rows());
  eigenvalues.resize(n);
  if (n == 0) return;
  Eigen::MatrixXd H = h;
  double norm = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i <= std::min(j + 1, n - 1); ++i) norm += std::abs(H(i, j));
  if (!std::isfinite(norm)) throw NumericalError("hessenberg_eigenvalues: the matrix holds a non-finite value");
  const double eps = std::numeric_limits<double>::epsilon();
  int hi = n - 1, since_deflation = 0, steps = 0;
  while (hi >= 0) {
    // The unreduced block [lo, hi]: the first negligible subdiagonal above hi.
    int lo = hi;
    for (; lo > 0; --lo) {
      double s = std::abs(H(lo - 1, lo - 1)) + std::abs(H(lo, lo));
      if (s == 0.0) s = norm;
      if (std::abs(H(lo, lo - 1)) <= eps * s) {
        H(lo, lo - 1) = 0.0;
        break;
      }
    }
    if (lo == hi) {
      eigenvalues(hi) = H(hi, hi);
      --hi;
      since_deflation = 0;
      continue;
    }
    if (lo == hi - 1) {
      Cplx l1, l2;
      two_by_two(H(hi - 1, hi - 1), H(hi - 1, hi), H(hi, hi - 1), H(hi, hi), l1, l2);
      eigenvalues(hi - 1) = l1;
      eigenvalues(hi) = l2;
      hi -= 2;
      since_deflation = 0;
      continue;
    }
    if (++steps > kStepsPerEigenvalue * n)
      throw NumericalError("hessenberg_eigenvalues: the QR iteration did not converge");
    ++since_deflation;
    // The shifts' sum s and product t: the trailing 2 × 2 block, or an
    // exceptional pair when no deflation came for a while.
    double s, t;
    if (since_deflation % kExceptionalEvery == 0) {
      const double w = std::abs(H(hi, hi - 1)) + std::abs(H(hi - 1, hi - 2));
      const double c = H(hi, hi) + kExceptionalShift * w;
      s = 2.0 * c;
      t = c * c + kExceptionalSpread * w * w;
    } else {
      s = H(hi - 1, hi - 1) + H(hi, hi);
      t = H(hi - 1, hi - 1) * H(hi, hi) - H(hi - 1, hi) * H(hi, hi - 1);
    }
    // First column of (H − σ₁)(H − σ₂) on the block, then chase the bulge.
    double x = H(lo, lo) * H(lo, lo) + H(lo, lo + 1) * H(lo + 1, lo) - s * H(lo, lo) + t;
    double y = H(lo + 1, lo) * (H(lo, lo) + H(lo + 1, lo + 1) - s);
    double z = H(lo + 1, lo) * H(lo + 2, lo + 1);
    for (int k = lo; k <= hi - 1; ++k) {
      const bool three = k <= hi - 2;  // the last reflector has two rows
      const Reflector r = reflector(x, y, three ? z : 0.0);
      if (k > lo) {  // column k − 1 becomes [β; 0; 0]
        H(k, k - 1) = r.beta;
        H(k + 1, k - 1) = 0.0;
        if (three) H(k + 2, k - 1) = 0.0;
      }
      if (r.tau != 0.0) {
        for (int j = k; j <= hi; ++j) {  // rows k … k + 2 (left)
          double p = H(k, j) + r.v1 * H(k + 1, j);
          if (three) p += r.v2 * H(k + 2, j);
          p *= r.tau;
          H(k, j) -= p;
          H(k + 1, j) -= p * r.v1;
          if (three) H(k + 2, j) -= p * r.v2;
        }
        const int last = std::min(k + 3, hi);
        for (int i = lo; i <= last; ++i) {  // columns k … k + 2 (right)
          double p = H(i, k) + r.v1 * H(i, k + 1);
          if (three) p += r.v2 * H(i, k + 2);
          p *= r.tau;
          H(i, k) -= p;
          H(i, k + 1) -= p * r.v1;
          if (three) H(i, k + 2) -= p * r.v2;
        }
      }
      if (k + 1 <= hi - 1) {
        x = H(k + 1, k);
        y = H(k + 2, k);
        if (k + 3 <= hi) z = H(k + 3, k);
      }
    }
  }
}

}  // namespace chatter::detail
