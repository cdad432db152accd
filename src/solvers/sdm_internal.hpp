// Internal parts of the `sdm` solver (not part of the public API): the data
// of one step grid and one period map, and the functions that build and
// read them. The solver is one concept per file:
//   sdm_grid.cpp         the step grid of one period (steps on the tooth
//                        entries and exits, the real-cutter grid with its
//                        exact force integrals) and the modal state space;
//   sdm_map.cpp          the step maps of one period at one depth (augmented
//                        exponentials, sdm_step_exp.hpp) and Φ y, the
//                        monodromy applied as the sequence of step maps
//                        (never formed);
//   sdm_cutter_map.cpp   the same on the real-cutter grid (first order);
//   sdm_collocation.cpp, sdm_cutter_collocation.cpp  Gauss collocation on
//                        the straight-teeth and on the real-cutter grid;
//   sdm_multipliers.cpp  the dominant multiplier: dense eigen-decomposition,
//                        restarted Arnoldi;
//   sdm_branches.cpp     the branch roots of turning (first order, collocation);
//   sdm_floquet.cpp      the Floquet analysis at a point: multiplier type
//                        and the chatter-frequency rule;
//   sdm_search.cpp       the depth search (limit_at);
//   sdm_ssv.cpp          spindle speed variation: the grid of the principal
//                        period with the time-varying delay (docs/ssv.md);
// and the forced response (forced_periodic.cpp) solves for the periodic
// response on the same grid and step maps with the static chip force.
//   semi_discretization.cpp  the solver class: options, construction,
//                        analyse, spectral_radius_map.
// Method and references: include/chatter/semi_discretization.hpp, docs/sdm.md.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "chatter/process.hpp"
#include "chatter/regenerative_cut.hpp"
#include "chatter/results.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/structural_model.hpp"

namespace chatter::sdm_detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Cplx = std::complex<double>;

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kInf = std::numeric_limits<double>::infinity();
// Augmented step systems up to this size use stack-allocated matrices.
inline constexpr int kSmallAugmented = 12;
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kSmallAugmented, kSmallAugmented>;
// A step whose force integral is below this times (K_t + K_r) a h is free
// flight: the windowed integral of a free span is 0 up to round-off.
inline constexpr double kFreeForce = 1e-12;
// Branch roots of turning (SdmKernel::branches): used when τ min ζω is at
// least kBranchMinDecay (contraction factor about 1/kBranchMinDecay) and the
// map is larger than dense_max_dimension.
inline constexpr double kBranchMinDecay = 4.0;
// While bracketing, Arnoldi stops once | |θ| − 1 | exceeds this many residuals.
inline constexpr double kDecideFactor = 20.0;

// The modal state space of the solver, x = [q; q̇/ω] (the scaled state keeps
// the exponentials well balanced): ẋ = A x + B F, and the reduced delayed
// quantity z = Wx x (n_r × 2n) with H(t) S q = Ĥ(t) U W q (Ĥ = H U for
// milling and for turning with a nose radius; for other turning H = ĥ nᵀ,
// Ĥ = ĥ = (b/a) d, and U W = nᵀ S: [K_f; 0] and e_xᵀ S for the orthogonal
// cut). Sv: ṙ = Sv x.
struct SdmStateSpace {
  MatrixXd A;   // 2n × 2n free dynamics
  MatrixXd B;   // 2n × 2 force input
  MatrixXd Wx;  // n_r × 2n, z = Wx x
  MatrixXd U;   // n_L × n_r
  MatrixXd Sv;  // 2 × 2n: relative velocity ṙ = Sv x (process damping)
  MatrixXd Sr;  // 2 × 2n: relative displacement r = Sr x (the forced response)
  double f_max_hz = 0.0;
  double slowest_decay_per_s = 0.0;  // min −Re λ_i (= min ζ_i ω_i)
  std::vector<Cplx> free_poles;      // λ_i = −ζω + jω√(1−ζ²) (1/s), or real pairs
};
/// @pre model has modes only (no measured FRF), at least one.
SdmStateSpace state_space(const StructuralModel& model, const Process& process, bool general_path = false);

// One step of the delay period, independent of the depth.
struct Step {
  double h = 0.0;     // s
  MatrixXd BHU;       // B Ĥ U with Ĥ the step average of Ĥ(t): 2n × n_r (per unit depth)
  double t0 = 0.0;    // start, s after the tooth entry (milling)
  // Gauss collocation with s nodes c_j (sdm_collocation.cpp; empty at s = 0),
  // per unit depth: WxEc = [Wx e^{A c_j h}]_j (s n_r × 2n), WxK = [Wx W_jk B
  // H(c_k) U]_jk (s n_r × s n_r), VB = [V_k B H(c_k) U]_k (2n × s n_r), Eh =
  // e^{A h}; W_jk, V_k: the weights of the cutting term's Lagrange basis in
  // the variation-of-constants integral up to c_j h and up to h.
  MatrixXd WxEc, WxK, VB, Eh;
};

// Real-cutter grid of one period (cutter_grid): boundaries, and per step the
// exact integrals ∫∫ H₁ per delay group and Σ_j ∫∫ n nᵀ at depth `depth`.
struct CutterGrid {
  double depth = 0.0;              // m
  // The cut it was built from (cutter_grid; collocation samples its H at the
  // nodes, with speed variation at their mean-speed times); null for turning
  // with speed variation (H constant).
  std::shared_ptr<const RegenerativeCut> cut;
  std::vector<double> t;           // t_0 = 0 … t_M = T
  std::vector<double> h;           // step lengths, s
  std::vector<char> free;          // 1: free flight (exact step)
  std::vector<Eigen::Matrix2d> F;  // M × groups, row-major
  std::vector<Eigen::Matrix2d> D;  // M
  std::vector<double> gtau;        // delay of each group, s (at the mean speed with SSV)
  std::vector<int> edge_group;     // the delay group of each edge of the cut (RegenerativeCut order)
  // Per step: the span between two engagement events it lies in (steps of
  // one span share a smooth H), −1 for free flight; empty with SSV.
  std::vector<int> segment;
  double force_scale_n_per_m2 = 0.0;  // RegenerativeCut::force_scale_n_per_m2 (the free-flight test)
  // Spindle speed variation: the delay of group k at boundary t_i is
  // tau_at[i · groups + k] (M + 1 rows); empty: the constant gtau.
  std::vector<double> tau_at;
};

// The four ways the one-period map is built and applied, chosen once per
// speed by period_grid (docs/sdm.md): on the tooth-period grid (straight
// teeth and turning; turning's constant step and its branch roots are
// within kToothSteps and kToothCollocation, a nose radius within
// kToothSteps) or on the real-cutter grid (a helix, variable
// pitch or helix, a profile, two arcs, process damping in milling, speed
// variation), each with first-order steps or Gauss collocation. Every
// dispatch (SdmKernel::build_map, apply, the chatter-frequency samples)
// switches on it.
enum class MapPath {
  kToothSteps,         // Grid::steps -> PeriodMap::steps (first-order step maps)
  kToothCollocation,   // Grid::steps and their node weights -> PeriodMap::steps
  kCutterSteps,        // a CutterGrid per depth -> PeriodMap::cm (CutterMap)
  kCutterCollocation,  // a CutterGrid per depth -> PeriodMap::cc (CollocationCutterMap)
};
inline bool on_cutter_grid(MapPath p) { return p == MapPath::kCutterSteps || p == MapPath::kCutterCollocation; }

// The step grid of one delay period at one spindle speed.
struct Grid {
  double tau = 0.0;
  std::vector<Step> steps;     // cutting steps, in time order from a tooth entry
  bool constant = false;       // turning: every step identical (steps.size() == 1, count m)
  int m = 0;                   // number of cutting steps
  double free_time = 0.0;      // free-flight duration (s), 0 if a tooth always cuts
  MatrixXd E_free;             // exp(A t_free), depth-independent: built once per speed
  bool branch_roots = false;   // see SdmKernel::branches
  // Turning with process damping: c̄ B D Sv (2n × 2n, per unit depth), D =
  // (b/a) n nᵀ (e_x e_xᵀ for the orthogonal cut); empty without it.
  MatrixXd damping;
  // Turning with a nose radius (docs/turning_inserts.md): H depends on the
  // depth, so build_steps forms a B H(a) U (and a c̄ B D(a) Sv) per depth
  // from this process (the caller's, which outlives the grid); Wx is then
  // the whole S. nullptr otherwise.
  const Process* nose = nullptr;
  double nose_cbar = 0.0;  // C_pd / V, N·s/m²
  MatrixXd nose_Sv;        // 2 × 2n, with process damping only
  // The path (MapPath). On the real-cutter grid (milling with helix, variable
  // pitch or helix, or process damping) the steps are built per depth by
  // SdmKernel::build_cutter; tau is then the period of H (tooth period, or
  // one revolution).
  MapPath path = MapPath::kToothSteps;
  double rpm = 0.0;
  double h_target = 0.0;       // longest cutting step, s
  std::shared_ptr<const CutterGrid> cutter_grid;  // straight teeth: built once per speed at 1 m
  // Spindle speed variation (sdm_ssv.cpp): the real-cutter path over the
  // principal period (tau), with the time-varying delays of CutterGrid::tau_at.
  bool ssv = false;
  SpeedVariationPeriod ssv_period;
  // Gauss collocation nodes per cutting step (0 unless the path collocates).
  int nodes = 0;
};

// Real-cutter step: x_{i+1} = P x_i + Σ C z_g over stored samples z_g.
struct CutterStep {
  double h = 0.0;
  bool free = false;                             // no slice cuts: P = exp(A h)
  MatrixXd P;
  // (sample index g, 2n × n_r): the first n_terms are the step's terms (the
  // rest is storage kept from an earlier depth, reused without reallocation).
  std::vector<std::pair<int, MatrixXd>> terms;
  int n_terms = 0;
  // The forced response only (CutterMap::forcing): G = ∫₀ʰ e^{Ã s} ds B
  // (2n × 2), the state at the step's end driven by a force held constant
  // over the step (Ã: the step's present-state matrix), and gF = G F̄ for
  // the step's static chip force F̄ (set by forced_periodic.cpp). Empty
  // otherwise and for free steps.
  MatrixXd G;
  VectorXd gF;
};

// Where each delayed sample of a step falls on the stored samples: for the
// start and end of the step, z(t − τ) ≈ (1 − w) z_g + w z_{g+1}.
struct Located {
  int g0 = 0, g1 = 0;
  double w0 = 0.0, w1 = 0.0;
};

// Depth-independent work of a real-cutter map whose grid is shared by every
// depth of one speed (straight teeth): the free-flight exponentials and the
// located delayed samples per step and delay group, filled on first use.
struct CutterCache {
  std::shared_ptr<const CutterGrid> grid;  // the grid they belong to (kept alive: a unique key)
  std::vector<MatrixXd> free_P;            // per step: exp(A h) of a free step
  std::vector<char> located;               // per step × group: 1 once `where` is set
  std::vector<Located> where;              // per step × group
};

// One period of the real-cutter map. Sample g is z at t_g = t[g mod M] +
// floor(g/M) T; the state is [x(0); z_{−1}; …; z_{−L}].
struct CutterMap {
  std::vector<double> t;  // step boundaries t_0 = 0 … t_M = T
  std::vector<CutterStep> steps;
  int L = 0;
  // Set before build_map to also build each cutting step's forcing gain G
  // (the forced response, forced_periodic.cpp); false for the stability solver.
  bool forcing = false;
  CutterCache cache;
  mutable std::vector<double> buf, x, xn;  // apply() workspace
  // cutter_map() workspace (kept to avoid reallocating at every depth).
  std::vector<MatrixXd> Bt, R0, R1, HU;
  std::vector<int> gid;
  MatrixXd At, aug, E, Q0, Q1, Xh, Yh, G1, G2;
};

// Gauss collocation on the real-cutter grid (sdm_cutter_collocation.cpp,
// docs/sdm.md "Collocation on real cutters"). A cutting step with s nodes:
//   d = Σ C z_l over its terms (the delayed force per unit displacement
//       at each node, 2 values per node: d_k = Σ_g H_g U z(t_k − τ_g)),
//   Z = Qx x_i + Qd d (its node samples, s n_r values),
//   x_{i+1} = P x_i + Rd d.
// Sample l is z at node l mod N of period floor(l / N) (N nodes per period,
// period 0 the one being mapped); the state is [x(0); z_{−L}; …; z_{−1}].
struct CollocationStep {
  double h = 0.0;
  bool free = false;        // no edge cuts: P = e^{A h}, no nodes
  MatrixXd P, Qx, Qd, Rd;   // n2 × n2, s n_r × n2, s n_r × 2s, n2 × 2s
  int first_node = 0;       // index in the period of its first node
  int first_term = 0, n_terms = 0;
};
struct NodeTerm {
  int node = 0;    // 0 … s − 1 within the step
  int sample = 0;  // global sample index l
};
// The depth-independent weights of one step length as a collocation step
// reads them (node_weights; both collocation grids): WxEc = [Wx e^{A c_j h}]_j (s n_r
// × 2n), G = [Wx W_jk B]_jk (s n_r × 2s), VB = [V_k B]_k (2n × 2s), Eh = e^{A h};
// with process damping also SvEc and Gv, the same two for ṙ = Sv x (empty
// otherwise).
struct NodeWeights {
  MatrixXd Eh, WxEc, G, VB;
  MatrixXd SvEc, Gv;
};
struct CollocationCutterMap {
  std::vector<double> t;  // step boundaries t_0 = 0 … t_M = T
  std::vector<CollocationStep> steps;
  int N = 0, L = 0, s = 0;
  std::vector<NodeTerm> terms;
  std::vector<double> term_c;  // 2 n_r per term (C, column-major): d_node += C z_sample
  mutable std::vector<double> buf, d, x, xn;  // apply workspace
  // NodeWeights by step length, kept between depths (for the A of
  // weights_for and weights_nodes nodes).
  std::map<double, NodeWeights> weights;
  const double* weights_for = nullptr;
  int weights_nodes = 0;
};

// Step maps x_{i+1} = P x_i + R0 z_{i−m} + R1 z_{i−m+1} at one depth.
// Collocation (PeriodMap::nodes = s > 0): x_{i+1} = P x_i + Rc ζ_i and the
// step's node samples ζ_i⁺ = Qc [x_i; ζ_i], ζ_i the same nodes one period
// back (s n_r values).
struct StepMap {
  MatrixXd P, R0, R1;
  MatrixXd Rc, Qc;
};

struct PeriodMap {
  std::vector<StepMap> steps;  // one when constant
  bool constant = false;
  int m = 0;
  bool free_flight = false;
  const MatrixXd* E = nullptr;  // exp(A t_free), owned by the Grid
  int n2 = 0, nr = 0, nz = 0, dim = 0;
  double tau = 0.0;             // s
  bool branch_roots = false;    // turning with many steps: multipliers from ν^m = g(ν)
  MapPath path = MapPath::kToothSteps;  // the grid's: `steps`, or on the real-cutter grid `cm` / `cc`
  CutterMap cm;
  CollocationCutterMap cc;
  int nodes = 0;                // Gauss collocation nodes per step (0 unless the path collocates)
  // Turning with collocation: the grid's constant step (its depth-independent
  // node weights, owned by the Grid) and the depth, for the branch roots.
  const Step* node_step = nullptr;
  double depth = 0.0;           // m
};

// Dominant eigenpair of the one-period map.
struct Dominant {
  Cplx mu{0.0, 0.0};
  // Largest |μ| among the multipliers (Ritz values for Arnoldi) in the left
  // (Re μ < 0: where flip bands come from) and the right half-plane.
  double rho_left = 0.0, rho_right = 0.0;
  Cplx mu_left{0.0, 0.0}, mu_right{0.0, 0.0};  // those multipliers, Im >= 0
  // Exponent s of the dominant multiplier μ = e^{sτ} when it came from the
  // branch roots of turning (Im s: chatter frequency, rad/s); else 0.
  Cplx branch_s{0.0, 0.0};
  bool converged = true;
  Eigen::VectorXcd vec;  // empty unless requested
};

// xn = E x, E the n2 × n2 free-flight exponential (column-major): the last
// step of Φ y on the tooth-period grid (first-order and collocation maps).
inline void free_flight_step(const MatrixXd& E, int n2, const double* x, double* xn) {
  const double* e = E.data();
  for (int r = 0; r < n2; ++r) {
    double acc = 0.0;
    for (int c = 0; c < n2; ++c) acc += e[r + c * n2] * x[c];
    xn[r] = acc;
  }
}

// "spindle speed N rev/min: must be > 0 and finite".
std::string bad_speed(double rpm);

// Where a time s on the global axis (s < 0: earlier periods) falls on a
// period's step grid with boundaries t (t[0] = 0 … t[M] = T): s = period T +
// loc, step k with t[k] <= loc < t[k + 1] (clamped to 0 … M − 1 against
// round-off at the ends). Both real-cutter maps read their delayed samples
// through it (sdm_cutter_map.cpp, sdm_cutter_collocation.cpp).
struct GridTime {
  int k = 0, period = 0;
  double loc = 0.0;
};
inline GridTime grid_time(const std::vector<double>& t, double T, double s) {
  GridTime g;
  const double per = std::floor(s / T);
  g.loc = s - per * T;
  g.k = static_cast<int>(std::upper_bound(t.begin(), t.end(), g.loc) - t.begin()) - 1;
  g.k = std::clamp(g.k, 0, static_cast<int>(t.size()) - 2);
  g.period = static_cast<int>(per);
  return g;
}

// ---------------------------------------------------------------- grid
// (sdm_grid.cpp)

// The real-cutter path (a helix, variable pitch, process damping or a
// profile in milling, or general_cutter_path) rather than the tooth-period
// grid of straight teeth or the constant turning step.
bool real_cutter_grid(const Process& p, const SemiDiscretizationOptions& o);
// The options with kAutoCollocation replaced by the choice for this cut
// (kRealCutterNodes and kRealCutterSteps on the real-cutter path, else 0).
SemiDiscretizationOptions resolved_collocation(SemiDiscretizationOptions o, const Process& p);
// Why collocation_nodes > 0 cannot run on this cut (speed variation,
// turning with a nose radius or process damping), as an InputError message;
// "" when it can.
std::string collocation_refusal(const Process& p, const SemiDiscretizationOptions& o);

// First pass of the real-cutter map at depth a: step boundaries 0, T and
// every engagement event in [0, T); the exact integrals per step.
// collocation: the grid collocation samples H on: also at every edge's own
// events (RegenerativeCut::edge_events_s), and without the step integrals
// F and D (left zero: the nodes sample H instead).
CutterGrid cutter_grid(const Process& p, const Grid& g, int axial_slices, double a, bool collocation = false);
// Step grid of one delay period at `rpm`, from a tooth entry (milling).
Grid make_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double rpm,
               const MatrixXd& turning_hhat, const MatrixXd& A, const MatrixXd& B, const MatrixXd& U,
               const MatrixXd& Sv);
// Spindle speed variation (sdm_ssv.cpp): the grid of the principal period
// (SpeedVariationPeriod) at mean speed `rpm`; the steps are built per depth
// from ssv_cutter_grid (once per speed for straight teeth).
// @throws InputError with process damping, or beyond max_steps_per_period.
Grid make_ssv_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double rpm);
// The steps of one principal period at depth a: turning in equal steps;
// milling on the constant-speed grid in the mean-speed time θ(t)/Ω₀, mapped
// to real time, its integrals scaled by dt/dt'. tau_at: the delays τ(t_i).
// collocation: milling's boundaries also at every edge's own events, and
// without the step integrals (as cutter_grid).
CutterGrid ssv_cutter_grid(const Process& p, const Grid& g, int axial_slices, double a, bool collocation = false);

// The grid of one period at `rpm` as the solver uses it: make_grid, the
// branch-root choice of turning and, with collocation_nodes > 0, the
// collocation weights (add_collocation). Every caller of the stability
// solver takes its grid from here.
Grid period_grid(const Process& p, const SemiDiscretizationOptions& o, double f_max_hz, double slowest_decay,
                 double rpm, const MatrixXd& A, const MatrixXd& B, const MatrixXd& Wx, const MatrixXd& U,
                 const MatrixXd& Sv);
// Gauss–Legendre nodes c_1 … c_s on [0, 1] (1 <= s <= kMaxCollocationNodes).
std::vector<double> gauss_nodes(int s);
// e^{aT} and G_q(T) = ∫₀^T e^{a(T−σ)} (σ/T)^q dσ (q < s, into G[0 … s−1])
// of one 2 × 2 mode block a of the solver's A (sdm_collocation.cpp): in
// closed form for an underdamped block, else from an augmented exponential.
void mode_integrals(const Eigen::Matrix2d& a, double T, int s, Eigen::Matrix2d& E, Eigen::Matrix2d* G);
// The collocation weights of step length h (NodeWeights above), mode by
// mode (sdm_collocation.cpp), with W_jk = ∫₀^{c_j h} e^{A(c_j h − σ)}
// ℓ_k(σ/h) dσ and V_k = ∫₀^h e^{A(h − σ)} ℓ_k(σ/h) dσ, ℓ_k the Lagrange
// basis of the nodes c. @pre A couples only q_i and q̇_i/ω_i of each mode (state_space
// builds it so); B has 2 columns (the force).
NodeWeights node_weights(const MatrixXd& A, const MatrixXd& B, const MatrixXd& Wx, double h,
                         const std::vector<double>& c);
// Gauss collocation (sdm_collocation.cpp): the depth-independent weights of
// every cutting step of a straight-teeth milling grid, or of the constant
// step of turning with a sharp edge and no process damping (Step::WxEc … Eh).
// @pre collocation_refusal(p, o) is empty (the solver checks it at construction).
void add_collocation(Grid& g, const Process& p, int nodes, const MatrixXd& A, const MatrixXd& B,
                     const MatrixXd& Wx, const MatrixXd& U);

// ĥ of turning, H = ĥ nᵀ: (b/a) d ([K_f; 0] for the orthogonal cut); empty
// for milling and for a nose radius (H per depth).
MatrixXd turning_hhat_of(const Process& p);
// Turning with a map larger than dense_max_dimension and τ min ζω >=
// kBranchMinDecay: multipliers from the branch roots (SdmKernel::branches).
Grid with_branch_choice(Grid g, double slowest_decay, const SemiDiscretizationOptions& o, Index n2, Index nr);

// ---------------------------------------------------------------- kernel
// Everything that depends on the speed and depth, created per call. The
// maps are in sdm_map.cpp, the multipliers in sdm_multipliers.cpp.
class SdmKernel {
 public:
  SdmKernel(const MatrixXd& A, const MatrixXd& B, const MatrixXd& Wx, const MatrixXd& U,
            const SemiDiscretizationOptions& o, const Process* p = nullptr, const MatrixXd* Sv = nullptr)
      : A_(A), B_(B), Wx_(Wx), U_(U), o_(o), p_(p), Sv_(Sv) {}

  void build_map(const Grid& g, double depth, PeriodMap& pm) const;
  // out = Φ y (both of length pm.dim, distinct). work: >= 2 n2 + nr doubles.
  // Dispatches to fixed-size loops for the common small models.
  static void apply(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work);
  // out = Φ y on the real-cutter map; `record` (if given) receives x at t_0 … t_M.
  // `forcing`: out = Φ y + r, each step also adding its gF (forced response).
  static void apply_cutter(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out,
                           std::vector<double>* record, bool forcing = false);
  // out = Φ y on the real-cutter collocation map; `record` as apply_cutter.
  static void apply_cutter_collocation(const PeriodMap& pm, const double* y, double* out,
                                       std::vector<double>* record);
  // `decide`: only the verdict ρ < 1 or ρ >= 1 matters (bracketing); the
  // Arnoldi iteration can then stop after a few steps, even for small maps.
  Dominant dominant(const PeriodMap& pm, bool want_vector, bool decide = false) const;
  // Turning: the multipliers from the branch roots of the constant step map
  // (first-order steps or collocation, sdm_multipliers.cpp).
  bool branches(const PeriodMap& pm, Dominant& out) const;
  // The largest of `eigs` in the left (Re μ < 0) and right half-planes into
  // out's rho_left/mu_left and rho_right/mu_right, each μ the member of its
  // conjugate pair with Im μ >= 0 (the depth climb follows them).
  static void half_plane_radii(const Eigen::VectorXcd& eigs, Dominant& out);

 private:
  template <class M>
  void build_steps(const Grid& g, double depth, PeriodMap& pm) const;
  template <int N2, int NR>
  static void apply_n(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out, double* work);
  // Collocation (sdm_collocation.cpp): the step maps at one depth, and Φ y.
  void build_collocation(const Grid& g, double depth, PeriodMap& pm) const;
  static void apply_collocation(const PeriodMap& pm, const double* y, double* out, double* work);
  void build_cutter(const Grid& g, double a, PeriodMap& pm) const;
  // Collocation on the real-cutter grid (sdm_cutter_collocation.cpp).
  void build_cutter_collocation(const Grid& g, double a, PeriodMap& pm) const;
  void cutter_map(const Grid& g, const CutterGrid& cg, double a, double scale, PeriodMap& pm,
                  const std::shared_ptr<const CutterGrid>* shared) const;
  template <int N2, int NR>
  static void apply_cutter_n(const PeriodMap& pm, const MatrixXd& Wx, const double* y, double* out,
                             std::vector<double>* record, bool forcing);
  static bool better(const Cplx& a, const Cplx& b);
  Dominant dense(const PeriodMap& pm, bool want_vector) const;
  static void hessenberg_dominant(const MatrixXd& Hk, Cplx& theta, Eigen::VectorXcd& y,
                                  std::vector<std::pair<double, Index>>* order, Eigen::VectorXcd* eigs);
  Dominant arnoldi(const PeriodMap& pm, bool want_vector, bool decide) const;

  const MatrixXd& A_;
  const MatrixXd& B_;
  const MatrixXd& Wx_;
  const MatrixXd& U_;
  const SemiDiscretizationOptions& o_;
  const Process* p_;    // real-cutter path only
  const MatrixXd* Sv_;  // 2 × 2n, ṙ = Sv x
  // Arnoldi's Krylov basis, Hessenberg matrix and vectors, kept between the
  // calls of one kernel (a depth search evaluates ~10 maps of one size): a
  // kernel serves one thread.
  struct ArnoldiWorkspace {
    MatrixXd V, H;
    VectorXd v, w, h, h2;
    std::vector<double> work;
    // Map dimension d, Krylov dimension k, apply()'s workspace in doubles.
    void size_for(int d, int k, std::size_t work_doubles) {
      V.resize(d, k + 1);
      H.resize(k + 1, k);
      v.resize(d);
      w.resize(d);
      h.resize(k + 1);
      h2.resize(k + 1);
      work.resize(work_doubles);
    }
  };
  mutable ArnoldiWorkspace arnoldi_work_;
};

// ---------------------------------------------------------------- Floquet
// (sdm_floquet.cpp)

// hopf, flip or fold from the angle of μ.
MultiplierType classify(const Cplx& mu);
// Chatter frequency (Hz) of the dominant multiplier μ with eigenvector `vec`
// (rule in docs/sdm.md).
double chatter_frequency(const Cplx& mu, const Eigen::VectorXcd& vec, const PeriodMap& pm, const Grid& g,
                         const MatrixXd& A, const MatrixXd& Wx, double f_max_hz);
// The Floquet analysis of the map `pm`, built at `depth_m` on grid `g`.
// `known`: kernel.dominant(pm, true) when the caller has it already.
FloquetResult floquet_of(const SdmKernel& kernel, const Grid& g, const PeriodMap& pm, double rpm, double depth_m,
                         const MatrixXd& A, const MatrixXd& Wx, double f_max_hz, const Dominant* known = nullptr);

}  // namespace chatter::sdm_detail
