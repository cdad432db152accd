// The step grid of one period of the `sdm` solver at one spindle speed
// (steps on the tooth entries and exits, free flight as one exact step; the
// real-cutter grid with the exact force integrals of Process), and the
// modal state space the step maps are built on. Part of the `sdm` solver
// (sdm_internal.hpp).
#include "sdm_internal.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/SVD>
#include <unsupported/Eigen/MatrixFunctions>

#include "chatter/error.hpp"
#include "chatter/regenerative_cut.hpp"
#include "chatter/kinematics.hpp"

namespace chatter::sdm_detail {
namespace {

// Relative rank threshold for the delayed quantity (entries of S are O(1)).
constexpr double kRankTol = 1e-10;
// Real cutter: events closer than this fraction of the period are one event
// (Process merges at 1e-12 too); delays equal to it are one delay group.
constexpr double kEventMerge = 1e-12;

Step step_of(double h, MatrixXd BHU, double t0 = 0.0) {
  Step s;
  s.h = h;
  s.BHU = std::move(BHU);
  s.t0 = t0;
  return s;
}

}  // namespace

std::string bad_speed(double rpm) {
  std::ostringstream os;
  os << "spindle speed " << rpm << " rev/min: must be > 0 and finite";
  return os.str();
}

SdmStateSpace state_space(const StructuralModel& model, const Process& process, bool general_path) {
  SdmStateSpace ss;
  const ModalMatrices mm = modal_matrices(model);
  const Index n = mm.omega.size();
  // Scaled state x = [q; q̇/ω] keeps the exponentials well balanced.
  ss.A = MatrixXd::Zero(2 * n, 2 * n);
  ss.B = MatrixXd::Zero(2 * n, 2);
  ss.Sv = MatrixXd::Zero(2, 2 * n);
  ss.Sr = MatrixXd::Zero(2, 2 * n);
  for (Index i = 0; i < n; ++i) {
    const double w = mm.omega(i);
    ss.A(i, n + i) = w;
    ss.A(n + i, i) = -w;
    ss.A(n + i, n + i) = -2.0 * mm.damping_ratio(i) * w;
    ss.B.row(n + i) = mm.S.col(i).transpose() / (mm.mass_kg(i) * w);
    ss.Sv.col(n + i) = mm.S.col(i) * w;  // ṙ = S q̇ = S diag(ω) (q̇/ω)
    ss.Sr.col(i) = mm.S.col(i);          // r = S q
    const double z = mm.damping_ratio(i);
    if (z < 1.0) {
      ss.free_poles.emplace_back(-z * w, w * std::sqrt(1.0 - z * z));
    } else {  // overdamped: two real poles
      ss.free_poles.emplace_back(-w * (z - std::sqrt(z * z - 1.0)), 0.0);
      ss.free_poles.emplace_back(-w * (z + std::sqrt(z * z - 1.0)), 0.0);
    }
  }
  // The slowest free decay, from the same poles (so the two cannot disagree).
  ss.slowest_decay_per_s = kInf;
  for (const Cplx& l : ss.free_poles) ss.slowest_decay_per_s = std::min(ss.slowest_decay_per_s, -l.real());
  ss.f_max_hz = model.max_omega() / kTwoPi;
  // H(t) = Ĥ(t) L: L = nᵀ for turning (e_xᵀ for the orthogonal cut), I for
  // milling, for turning with a nose radius (n varies with the depth) and on
  // the general path (any cut). L S = U W by SVD.
  MatrixXd LS;
  if (general_path || process.rotating_edges() || process.has_nose_radius())
    LS = mm.S;
  else if (process.orthogonal_turning())
    LS = mm.S.topRows(1);
  else
    LS = process.chip_direction(0.0).transpose() * mm.S;
  Eigen::JacobiSVD<MatrixXd> svd(LS, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const auto& sv = svd.singularValues();
  Index nr = 0;
  for (Index i = 0; i < sv.size(); ++i)
    if (sv(i) > kRankTol * std::max(sv(0), 1e-300)) ++nr;
  ss.U = svd.matrixU().leftCols(nr);
  const MatrixXd W = sv.head(nr).asDiagonal() * svd.matrixV().leftCols(nr).transpose();  // n_r × n
  ss.Wx = MatrixXd::Zero(nr, 2 * n);
  ss.Wx.leftCols(n) = W;
  return ss;
}

// First pass of the real-cutter map (SdmKernel::build_cutter) at depth a:
// step boundaries 0, T and every engagement event in [0, T); between two
// events the cut is free (one exact step) or cut in ceil(d / h_target) equal
// steps, each with the exact integrals of its share of H per delay group
// (distinct delays τ_k: a tooth, or a slice of a tooth with a variable
// helix) and of the damping direction. Straight teeth: every integral is
// proportional to a, so the grid is built once per speed (a = 1 m) and
// scaled.
CutterGrid cutter_grid(const Process& p, const Grid& g, int axial_slices, double a, bool collocation) {
  CutterGrid cg;
  cg.depth = a;
  const double T = g.tau, rpm = g.rpm;
  // The cut through the cutting law's regenerative side only: its edges,
  // their delays and exact integrals, its events (any operation).
  cg.cut = RegenerativeCut::of(p, rpm, a, axial_slices);
  const RegenerativeCut* cut = cg.cut.get();
  const double ph = cut->pattern_period_s();
  // Whole repeats of the events (T is a whole number of periods; with speed
  // variation a whole number of Floquet periods, which may be half a revolution).
  const int reps = std::max(1, static_cast<int>(std::ceil(T / ph - 1e-9)));
  std::vector<double> bnd{0.0, T};
  const std::vector<double> ev = collocation ? cut->edge_events_s() : cut->engagement_events_s();
  for (int r = 0; r < reps; ++r)
    for (const double e : ev)
      if (r * ph + e > 0.0 && r * ph + e < T) bnd.push_back(r * ph + e);
  std::sort(bnd.begin(), bnd.end());
  std::vector<double> b;
  for (const double t : bnd)
    if (b.empty() || t - b.back() > kEventMerge * T) b.push_back(t);
  b.back() = T;
  // Edges with equal delays (within kEventMerge T) form one delay group.
  const std::vector<double>& delays = cut->edge_delays_s();
  std::vector<int>& group = cg.edge_group;
  group.assign(delays.size(), 0);
  for (std::size_t e = 0; e < delays.size(); ++e) {
    std::size_t k = 0;
    while (k < cg.gtau.size() && std::abs(cg.gtau[k] - delays[e]) > kEventMerge * T) ++k;
    if (k == cg.gtau.size()) cg.gtau.push_back(delays[e]);
    group[e] = static_cast<int>(k);
  }
  const std::size_t ng = cg.gtau.size();
  const double h_target = std::min(g.h_target, *std::min_element(cg.gtau.begin(), cg.gtau.end()));
  const double kscale = cut->force_scale_n_per_m2();
  cg.force_scale_n_per_m2 = kscale;
  std::vector<Eigen::Matrix2d> per_edge;
  cg.t.assign(1, 0.0);
  for (std::size_t s = 0; s + 1 < b.size(); ++s) {
    const double ta = b[s], tb = b[s + 1], d = tb - ta;
    if (cut->total_force_integral(ta, tb).norm() <= kFreeForce * kscale * a * d) {  // free flight: one step with any free neighbour
      if (!cg.free.empty() && cg.free.back()) {
        cg.h.back() += d;
        cg.t.back() = tb;
      } else {
        cg.h.push_back(d);
        cg.free.push_back(1);
        cg.segment.push_back(-1);
        cg.t.push_back(tb);
        cg.F.resize(cg.F.size() + ng, Eigen::Matrix2d::Zero());
        cg.D.push_back(Eigen::Matrix2d::Zero());
      }
      continue;
    }
    const int ns = std::max(1, static_cast<int>(std::ceil(d / h_target - 1e-9)));
    for (int i = 0; i < ns; ++i) {
      const double sa = ta + d * i / ns, sb = (i + 1 == ns) ? tb : ta + d * (i + 1) / ns;
      const std::size_t first = cg.F.size();
      cg.F.resize(first + ng, Eigen::Matrix2d::Zero());
      if (collocation) {  // H is sampled at the nodes instead (sdm_cutter_collocation.cpp)
        cg.D.push_back(Eigen::Matrix2d::Zero());
      } else {
        cut->force_integrals(sa, sb, per_edge);
        for (std::size_t e = 0; e < per_edge.size(); ++e) cg.F[first + static_cast<std::size_t>(group[e])] += per_edge[e];
        cg.D.push_back(cut->damping_integral(sa, sb));
      }
      cg.h.push_back(sb - sa);
      cg.free.push_back(0);
      cg.segment.push_back(static_cast<int>(s));
      cg.t.push_back(sb);
    }
  }
  return cg;
}

bool real_cutter_grid(const Process& p, const SemiDiscretizationOptions& o) {
  return o.general_cutter_path ||
         (p.rotating_edges() &&
          (p.has_helix() || !p.uniform_cutter() || p.has_process_damping() || p.has_profile() ||
           p.split_engagement()));
}

SemiDiscretizationOptions resolved_collocation(SemiDiscretizationOptions o, const Process& p) {
  if (o.collocation_nodes != kAutoCollocation) return o;
  const SemiDiscretizationOptions defaults;
  // Process damping keeps the first order unless collocation is asked for:
  // Gauss collocation is not L-stable, and where C̄ a is far above the modes'
  // own damping its stiff, damped motion gets multipliers near −1 per step
  // (docs/sdm.md "Collocation with process damping").
  const bool real = real_cutter_grid(p, o) && !o.general_cutter_path && p.rotating_edges() &&
                    !p.has_process_damping();
  // Turning with a sharp edge: the constant step collocates too (its branch
  // roots: sdm_branches.cpp); a nose radius's H depends on the depth.
  const bool turning = !p.rotating_edges() && !o.general_cutter_path && !p.has_process_damping() &&
                       !p.has_nose_radius();
  const bool collocate = real || turning;
  o.collocation_nodes = collocate ? kRealCutterNodes : 0;
  if (collocate && o.steps_per_period == defaults.steps_per_period &&
      o.steps_per_vibration_cycle == defaults.steps_per_vibration_cycle)
    o.steps_per_period = o.steps_per_vibration_cycle = kRealCutterSteps;
  return o;
}

std::string collocation_refusal(const Process& p, const SemiDiscretizationOptions& o) {
  if (o.collocation_nodes <= 0) return "";
  const bool turning = !p.rotating_edges();
  const char* what = turning && p.has_nose_radius()        ? "is turning with a nose radius"
                     : turning && p.has_process_damping()  ? "is turning with process damping"
                                                           : nullptr;
  if (!what) return "";
  std::ostringstream os;
  os << "sdm: collocation_nodes = " << o.collocation_nodes << " (--collocation): Gauss collocation is for milling "
     << "and for turning with a sharp edge and no process damping; this cut " << what
     << ": use collocation 0 (the first-order steps)";
  return os.str();
}

namespace {

// The real-cutter grid's period and step bound at `rpm` (the steps
// themselves per depth: cutter_grid, SdmKernel::build_cutter).
Grid real_cutter_period(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double rpm) {
  Grid g;
  // Real cutter, or any cut on the general path: the steps from the
  // cutting law's regenerative side (cutter_grid; SdmKernel::build_cutter).
  // The straight uniform milling cutter and turning below are its fast
  // paths (tested equal to it: tests/test_regenerative_cut.cpp).
  g.path = MapPath::kCutterSteps;
  g.rpm = rpm;
  // Period: the shortest shift of teeth after which the pitch and helix
  // pattern repeats (Process::floquet_period_s): one tooth period for a
  // uniform cutter, half a revolution for 70/110/70/110°, one revolution
  // for an irregular cutter (and always with general_cutter_path).
  g.tau = o.general_cutter_path ? revolution_s(rpm) : p.floquet_period_s(rpm);
  const double tooth = p.delay_s(rpm);
  g.h_target = std::min(tooth / o.steps_per_period, 1.0 / (o.steps_per_vibration_cycle * f_max_hz));
  const double needed = std::ceil(tooth / g.h_target - 1e-9);
  if (needed > o.max_steps_per_period) {
    std::ostringstream os;
    os << "sdm at " << rpm << " rev/min needs about " << needed << " steps per tooth period, more than "
       << "max_steps_per_period = " << o.max_steps_per_period
       << ": raise the speed or max_steps_per_period, or lower steps_per_vibration_cycle";
    throw InputError(os.str());
  }
  if (!p.has_helix() && !p.has_profile() && !p.has_nose_radius())  // linear in a: once per speed at 1 m
    g.cutter_grid = std::make_shared<const CutterGrid>(cutter_grid(p, g, o.axial_slices, 1.0));
  return g;
}

}  // namespace

// Step grid of one delay period at `rpm`, from a tooth entry (milling).
// A, B, U: the solver's free dynamics, force input and delayed-quantity basis.
// Sv: ṙ = Sv x (process damping).
Grid make_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double rpm,
               const MatrixXd& turning_hhat, const MatrixXd& A, const MatrixXd& B, const MatrixXd& U,
               const MatrixXd& Sv) {
  if (p.has_speed_variation()) {
    if (p.has_profile())
      throw InputError("sdm: spindle speed variation with a ball-end, bull-nose or general cutter is not modelled "
                       "(docs/cutter_geometry.md): remove process.speed_variation or use a flat cutter");
    return make_ssv_grid(p, o, f_max_hz, rpm);
  }
  if (real_cutter_grid(p, o)) return real_cutter_period(p, o, f_max_hz, rpm);
  Grid g;
  g.tau = p.delay_s(rpm);
  const double h_target = std::min(g.tau / o.steps_per_period, 1.0 / (o.steps_per_vibration_cycle * f_max_hz));
  const double needed = std::ceil(g.tau / h_target - 1e-9);
  if (needed > o.max_steps_per_period) {
    std::ostringstream os;
    os << "sdm at " << rpm << " rev/min needs about " << needed << " steps per delay period, more than "
       << "max_steps_per_period = " << o.max_steps_per_period
       << ": raise the speed or max_steps_per_period, or lower steps_per_vibration_cycle";
    throw InputError(os.str());
  }
  auto count = [&](double duration) {
    return std::max(1, static_cast<int>(std::ceil(duration / h_target - 1e-9)));
  };
  if (!p.rotating_edges()) {
    g.constant = true;
    g.m = count(g.tau);
    if (p.has_nose_radius()) {  // B H(a) U per depth (SdmKernel::build_steps)
      g.steps.push_back(step_of(g.tau / g.m, MatrixXd()));
      g.nose = &p;
      g.nose_cbar = p.process_damping_per_depth(rpm);
      if (p.has_process_damping()) g.nose_Sv = Sv;
      return g;
    }
    g.steps.push_back(step_of(g.tau / g.m, B * turning_hhat * U));
    if (p.has_process_damping()) {  // − a (C_pd/V) B (b/a) n nᵀ ṙ
      MatrixXd D = MatrixXd::Zero(2, 2);
      if (p.orthogonal_turning())
        D(0, 0) = p.process_damping_per_depth(rpm);
      else
        D = p.process_damping_per_depth(rpm) * p.average_damping_direction();
      g.damping = B * D * Sv;
    }
    return g;
  }
  const MillingParameters& mp = p.milling_parameters();
  g.rpm = rpm;
  const double omega = angular_speed_rad_per_s(rpm);  // rad/s
  const double theta_p = kTwoPi / mp.teeth;           // tooth pitch, rad
  const double en = p.entry_angle();
  const double delta = p.exit_angle() - en;            // cutting arc of one tooth
  int K = static_cast<int>(std::floor(delta / theta_p + 1e-12));
  double r = delta - K * theta_p;
  if (r < 1e-12 * theta_p) r = 0.0;
  // Segments [θa, θb] (rad after tooth 0 enters) with `teeth` teeth cutting.
  struct Seg { double a, b; int teeth; };
  std::vector<Seg> segs;
  if (r > 0.0) {
    segs.push_back({0.0, r, K + 1});
    segs.push_back({r, theta_p, K});
  } else {
    segs.push_back({0.0, theta_p, K});
  }
  for (const Seg& s : segs) {
    const double duration = (s.b - s.a) / omega;
    if (s.teeth == 0) {
      g.free_time += duration;
      continue;
    }
    const int ns = count(duration);
    for (int i = 0; i < ns; ++i) {
      const double ta = s.a + (s.b - s.a) * i / ns, tb = s.a + (s.b - s.a) * (i + 1) / ns;
      Eigen::Matrix2d integral = Eigen::Matrix2d::Zero();
      for (int j = 0; j < s.teeth; ++j)
        integral += p.tooth_matrix_antiderivative(en + tb + j * theta_p) -
                    p.tooth_matrix_antiderivative(en + ta + j * theta_p);
      g.steps.push_back(step_of(duration / ns, B * (integral / (tb - ta)) * U, ta / omega));
    }
  }
  g.m = static_cast<int>(g.steps.size());
  if (g.free_time > 0.0) g.E_free = (A * g.free_time).exp();
  return g;
}

Grid period_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double slowest_decay,
                 double rpm, const MatrixXd& A, const MatrixXd& B, const MatrixXd& Wx, const MatrixXd& U,
                 const MatrixXd& Sv) {
  Grid g = make_grid(p, o, f_max_hz, rpm, turning_hhat_of(p), A, B, U, Sv);
  if (o.collocation_nodes > 0) {
    if (on_cutter_grid(g.path)) {  // the step maps per depth (sdm_cutter_collocation.cpp)
      g.path = MapPath::kCutterCollocation;
      g.nodes = o.collocation_nodes;
    } else {
      add_collocation(g, p, o.collocation_nodes, A, B, Wx, U);
    }
  }
  return with_branch_choice(std::move(g), slowest_decay, o, A.rows(), Wx.rows());
}

// ĥ of turning: H = ĥ nᵀ, ĥ = H n since |n| = 1 ([K_f; 0] for the orthogonal
// cut; unused for milling and for a nose radius).
MatrixXd turning_hhat_of(const Process& p) {
  MatrixXd h = MatrixXd::Zero(2, 1);
  if (p.rotating_edges() || p.has_nose_radius()) return h;
  if (p.orthogonal_turning())
    h(0, 0) = p.turning_parameters().feed_force_coefficient_n_per_m2;
  else
    h = p.turning_matrix(1.0) * p.chip_direction(1.0);
  return h;
}

// Turning with a map larger than dense_max_dimension and τ min ζω >=
// kBranchMinDecay: multipliers from the branch roots (SdmKernel::branches).
Grid with_branch_choice(Grid g, double slowest_decay, const SemiDiscretizationOptions& o, Index n2, Index nr) {
  g.branch_roots = o.turning_branch_roots && g.constant && nr == 1 &&
                   n2 + g.m * std::max(1, g.nodes) * nr > o.dense_max_dimension &&
                   g.tau * slowest_decay >= kBranchMinDecay;
  return g;
}

}  // namespace chatter::sdm_detail
