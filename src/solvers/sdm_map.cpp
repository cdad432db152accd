// The step maps of one period of the semi-discretised delay equation at one
// depth, and Φ y: the monodromy applied as the sequence of step maps, never
// formed (docs/sdm.md). Part of the `sdm` solver (sdm_internal.hpp).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>

#include "sdm_step_exp.hpp"

namespace chatter::sdm_detail {

using namespace step_exp;

namespace {

// One straight-teeth step map from X = (A − Bt Wx) h and Y = Bt h: P =
// e^X, R1 = ∫₀¹ e^{X(1−u)} Y u du, R0 = ∫₀¹ e^{X(1−u)} Y du − R1 (the blocks
// of the exponential of [[X, Y, 0], [0, 0, I], [0, 0, 0]]); false for the
// sizes augmented_exp_fixed does not have.
template <class XM, class YM>
bool step_exp_by_blocks(const XM& X, const YM& Y, StepMap& sm) {
  return augmented_exp_fixed(X, Y, 1.0, [&](const auto& p, const auto& g1, const auto& g2) {
    sm.P = p;
    sm.R1 = g2;
    sm.R0 = g1 - g2;
  });
}

}  // namespace

void SdmKernel::build_map(const Grid& g, double depth, PeriodMap& pm) const {
  if (on_cutter_grid(g.path)) return build_cutter(g, depth, pm);
  const int n2 = static_cast<int>(A_.rows());
  const int nr = static_cast<int>(Wx_.rows());
  pm.n2 = n2;
  pm.nr = nr;
  pm.m = g.m;
  pm.path = g.path;
  pm.nodes = g.nodes;
  pm.constant = g.constant;
  pm.free_flight = g.free_time > 0.0;
  // Stored samples: s per cutting step with collocation (none for free
  // flight); else one per step start, and one at the free flight's start.
  const bool collocating = g.path == MapPath::kToothCollocation;
  pm.nz = collocating ? g.m * g.nodes : pm.free_flight ? g.m + 1 : g.m;
  pm.dim = n2 + pm.nz * nr;
  pm.E = pm.free_flight ? &g.E_free : nullptr;
  pm.tau = g.tau;
  pm.branch_roots = g.branch_roots && nr == 1;
  pm.steps.resize(g.steps.size());
  pm.node_step = collocating && g.constant ? &g.steps[0] : nullptr;
  pm.depth = depth;
  if (collocating) return build_collocation(g, depth, pm);
  if (n2 + 2 * nr <= kSmallAugmented)
    build_steps<SmallMatrix>(g, depth, pm);  // no heap traffic: most models
  else
    build_steps<MatrixXd>(g, depth, pm);
}

// The step map of one step is read off the exponential of the augmented
// matrix [[(A − Bt Wx) h, Bt h, 0], [0, 0, I], [0, 0, 0]], Bt = a B Ĥ U
// (the first-order interpolation of the delayed term). M is the matrix
// type of the augmented system: a stack-allocated one for small models.
template <class M>
void SdmKernel::build_steps(const Grid& g, double depth, PeriodMap& pm) const {
  const int n2 = pm.n2, nr = pm.nr, na = n2 + 2 * nr;
  M aug = M::Zero(na, na);
  M Bt(n2, nr);
  for (std::size_t i = 0; i < g.steps.size(); ++i) {
    const Step& s = g.steps[i];
    if (g.nose) {  // a nose radius: a H(a) = b d nᵀ and b n nᵀ at this depth
      Bt.noalias() = B_ * g.nose->turning_force_matrix(depth) * U_;
      if (g.nose_Sv.size() > 0)
        aug.topLeftCorner(n2, n2).noalias() =
            (A_ - Bt * Wx_ - g.nose_cbar * B_ * g.nose->turning_damping_matrix(depth) * g.nose_Sv) * s.h;
      else
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_) * s.h;
    } else {
      Bt.noalias() = (depth * s.BHU);  // 2n × n_r
      if (g.damping.size() > 0)  // process damping (turning): − a c̄ B D Sv
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_ - depth * g.damping) * s.h;
      else
        aug.topLeftCorner(n2, n2).noalias() = (A_ - Bt * Wx_) * s.h;
    }
    StepMap& sm = pm.steps[i];
    // The common sizes (up to four modes in the plane, two on a line):
    // the exponential by blocks (augmented_exp: Padé on the block structure,
    // no (2n + 2 n_r)² work on the zero blocks); else the dense one.
    if (step_exp_by_blocks(aug.topLeftCorner(n2, n2), Bt * s.h, sm)) continue;
    aug.block(0, n2, n2, nr) = Bt * s.h;
    aug.block(n2, n2 + nr, nr, nr).setIdentity();
    const M E = aug.exp();
    sm.P = E.topLeftCorner(n2, n2);
    sm.R1 = E.block(0, n2 + nr, n2, nr);
    sm.R0 = E.block(0, n2, n2, nr) - sm.R1;
  }
}

// out = Φ y (both of length pm.dim, distinct). work: >= 2 n2 + nr doubles.
// Dispatches to fixed-size loops for the common small models.
void SdmKernel::apply(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work) {
  switch (pm.path) {
    case MapPath::kCutterCollocation:
      return apply_cutter_collocation(pm, y, out, nullptr);
    case MapPath::kCutterSteps:
      return apply_cutter(pm, Wx, y, out, nullptr);
    case MapPath::kToothCollocation:
      return apply_collocation(pm, y, out, work);
    case MapPath::kToothSteps:
      break;
  }
  if (pm.n2 == 2 && pm.nr == 1) return apply_n<2, 1>(pm, Wx, y, out, work);
  if (pm.n2 == 4 && pm.nr == 1) return apply_n<4, 1>(pm, Wx, y, out, work);
  if (pm.n2 == 4 && pm.nr == 2) return apply_n<4, 2>(pm, Wx, y, out, work);
  return apply_n<0, 0>(pm, Wx, y, out, work);
}

// N2, NR: compile-time sizes, or 0 for run-time ones.
template <int N2, int NR>
void SdmKernel::apply_n(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work) {
  const int n2 = N2 > 0 ? N2 : pm.n2;
  const int nr = NR > 0 ? NR : pm.nr;
  double* x = work;
  double* xn = work + n2;
  double* zw = work + 2 * n2;
  const double* W = Wx.data();
  auto project = [&](const double* xv, double* z) {  // z = Wx x
    for (int r = 0; r < nr; ++r) {
      double acc = 0.0;
      for (int c = 0; c < n2; ++c) acc += W[r + c * nr] * xv[c];
      z[r] = acc;
    }
  };
  std::copy(y, y + n2, x);
  project(x, zw);
  for (int i = 0; i < pm.m; ++i) {
    const StepMap& s = pm.constant ? pm.steps[0] : pm.steps[static_cast<std::size_t>(i)];
    project(x, out + n2 + i * nr);
    const double* z0 = y + n2 + i * nr;
    const double* z1 = (i + 1 < pm.nz) ? y + n2 + (i + 1) * nr : zw;
    const double* P = s.P.data();
    const double* R0 = s.R0.data();
    const double* R1 = s.R1.data();
    for (int row = 0; row < n2; ++row) {
      double acc = 0.0;
      for (int c = 0; c < n2; ++c) acc += P[row + c * n2] * x[c];
      for (int r = 0; r < nr; ++r) acc += R0[row + r * n2] * z0[r] + R1[row + r * n2] * z1[r];
      xn[row] = acc;
    }
    std::swap(x, xn);
  }
  if (pm.free_flight) {
    project(x, out + n2 + pm.m * nr);
    free_flight_step(*pm.E, n2, x, xn);
    std::swap(x, xn);
  }
  std::copy(x, x + n2, out);
}

}  // namespace chatter::sdm_detail
