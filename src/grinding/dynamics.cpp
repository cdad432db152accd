// The robot-wheel-part dynamics along the normal on SUNDIALS CVODE
// (include/chatter/grinding_dynamics.hpp for the model).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "../solvers/sundials_raii.hpp"
#include "chatter/error.hpp"
#include "chatter/grinding_dynamics.hpp"
#include "chatter/kinematics.hpp"
#include "grinding_text.hpp"

namespace chatter::grinding {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxAdamsOrder = 5;
// CVODE steps allowed between two grid points (a grid interval is a few
// hundred microseconds: a step budget this large means a failure, not work).
constexpr long kMaxStepsPerInterval = 100000;

struct Model {
  // Modes acting along the normal (S_i != 0).
  int n = 0;
  std::vector<double> S, omega, zeta, mass;
  std::vector<char> tool;
  double x0 = 0.0;
  // Process.
  double R = 0.0, E = 0.0, N = 0.0, vf = 0.0, mu = 0.0, Vs = 0.0, ke = 0.0, kc = 0.0, nc = 0.0, r = 1.0;
  double target = 0.0, tau = 1.0;
  // The memory over the current grid interval: s from s_a at t_a to s_b at t_b.
  double t_a = 0.0, t_b = 1.0, s_a = 0.0, s_b = 0.0;
  bool contact = false;

  double depth(const double* y) const {
    double x = x0;
    for (int i = 0; i < n; ++i) x += S[static_cast<std::size_t>(i)] * y[i];
    return x;
  }
  double surface(double t) const {
    const double u = std::clamp((t - t_a) / (t_b - t_a), 0.0, 1.0);
    return s_a + u * (s_b - s_a);
  }
  double width(double x) const { return 2.0 * std::sqrt(2.0 * R * std::max(x, 0.0)); }
  double chip_rate(double x, double p, bool in) const { return in ? 2.0 / 3.0 * width(x) * p * vf / r : 0.0; }
  double force(double x, double p, bool in) const {
    if (!in) return 0.0;
    return (ke * nc * N * 0.75 * E * width(x) + kc * chip_rate(x, p, in)) / (mu * Vs);
  }
  void rhs(double t, const double* y, double* yd) const {
    const double x = depth(y);
    const double fc = force(x, x - surface(t), contact);
    const double fp = y[2 * n];
    for (int i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      const double q = y[i], v = y[n + i];
      yd[i] = v;
      yd[n + i] = S[k] * ((tool[k] ? fp : 0.0) - fc) / mass[k] - 2.0 * zeta[k] * omega[k] * v - omega[k] * omega[k] * q;
    }
    yd[2 * n] = (target - fc) / tau;
  }
};

int rhs_cb(double t, N_Vector y, N_Vector yd, void* user) {
  static_cast<const Model*>(user)->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yd));
  return 0;
}
int root_cb(double t, N_Vector y, double* g, void* user) {
  const Model* m = static_cast<const Model*>(user);
  g[0] = m->depth(N_VGetArrayPointer(y)) - m->surface(t);
  return 0;
}

void check_options(const DynamicsOptions& o) {
  auto bad = [](const std::string& what) { throw InputError(what); };
  if (o.turns < 20 || o.turns > 100000) bad("turns = " + std::to_string(o.turns) + ": must be in [20, 100000]");
  if (!(o.analysed_fraction > 0.0 && o.analysed_fraction <= 1.0))
    bad("analysed_fraction = " + detail::num(o.analysed_fraction) + ": must be in (0, 1]");
  if (o.points_per_turn < 50 || o.points_per_turn > 20000)
    bad("points_per_turn = " + std::to_string(o.points_per_turn) + ": must be in [50, 20000]");
  if (!(std::isfinite(o.power_loop_turns) && o.power_loop_turns > 0.0))
    bad("power_loop_turns = " + detail::num(o.power_loop_turns) + ": must be > 0");
  if (!(o.initial_lift >= 0.0 && o.initial_lift <= 10.0))
    bad("initial_lift = " + detail::num(o.initial_lift) + ": must be in [0, 10]");
  if (!(o.relative_tolerance >= 1e-12 && o.relative_tolerance <= 1e-3))
    bad("relative_tolerance = " + detail::num(o.relative_tolerance) + ": must be in [1e-12, 1e-3]");
  if (o.series_turns < 0 || o.series_turns > o.turns)
    bad("series_turns = " + std::to_string(o.series_turns) + ": must be in [0, turns]");
}

}  // namespace

namespace {

// The robot's modes along the normal (+y into the part), the wheel and the
// mechanistic force at the quasi-static point `qs`. Sets the robot's and the
// contact's stiffness in `res`; `*tool_compliance` is the tool modes' share.
Model make_model(const Process& p, const StructuralModel& robot, const Prediction& qs, const DynamicsOptions& o,
                 double* tool_compliance, DynamicsResult& res) {
  Model m;
  const ModalMatrices mm = modal_matrices(robot);
  const std::size_t tool_modes = robot.tool.modes.size();
  double compliance = 0.0;
  *tool_compliance = 0.0;
  for (Eigen::Index i = 0; i < mm.S.cols(); ++i) {
    const double s = mm.S(1, i);
    if (s == 0.0) continue;
    const double k = mm.mass_kg(i) * mm.omega(i) * mm.omega(i);
    m.S.push_back(s);
    m.omega.push_back(mm.omega(i));
    m.zeta.push_back(mm.damping_ratio(i));
    m.mass.push_back(mm.mass_kg(i));
    m.tool.push_back(static_cast<std::size_t>(i) < tool_modes ? 1 : 0);
    compliance += s * s / k;
    if (static_cast<std::size_t>(i) < tool_modes) *tool_compliance += s * s / k;
  }
  m.n = static_cast<int>(m.S.size());
  if (*tool_compliance == 0.0)
    throw InputError("simulate needs the robot's compliance along the normal: [[tool.modes]] with a direction "
                     "that has a y component (+y points into the part)");
  res.robot_stiffness_n_per_m = 1.0 / compliance;
  m.R = p.wheel.radius_m();
  m.E = p.wheel.width_m;
  m.N = p.wheel.speed_rev_per_s;
  m.vf = p.feed_m_per_s;
  m.mu = p.force_ratio;
  m.Vs = p.wheel.cutting_speed_m_per_s();
  m.ke = p.mechanistic->edge_coefficient_n_per_m;
  m.kc = p.mechanistic->cutting_coefficient_n_per_m2;
  m.nc = *qs.impacts_per_turn;
  m.r = std::min(1.0, m.vf / (m.N * m.E));
  m.target = qs.normal_force_n;
  const double T = 1.0 / m.N;
  m.tau = o.power_loop_turns * T;
  res.contact_stiffness_n_per_m = m.kc * 2.0 / 3.0 * m.width(qs.max_depth_m) * m.vf / m.r / (m.mu * m.Vs);
  return m;
}

// Static equilibrium (push = contact force = target): tool modes at rest,
// workpiece modes pushed away; m.x0 puts the wheel at h0 there. Then the
// lift, shared by the tool modes in proportion to their compliance.
std::vector<double> initial_state(Model& m, double h0, double tool_compliance, const DynamicsOptions& o) {
  const int n = m.n;
  std::vector<double> y0(static_cast<std::size_t>(2 * n + 1), 0.0);
  double z_eq = 0.0;
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const double stiff = m.mass[k] * m.omega[k] * m.omega[k];
    if (!m.tool[k]) y0[k] = -m.S[k] * m.target / stiff;
    z_eq += m.S[k] * y0[k];
  }
  m.x0 = h0 - z_eq;
  const double lift = o.initial_lift * m.r * h0;
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (m.tool[k]) y0[k] += -lift * (m.S[k] / (m.mass[k] * m.omega[k] * m.omega[k])) / tool_compliance;
  }
  y0[static_cast<std::size_t>(2 * n)] = m.target;
  return y0;
}

// CVODE (Adams, fixed point) on the model, absolute tolerances scaled to the
// depth h0, at most one grid step dt per step, the contact switch as root.
void configure_integrator(sundials::Cvode& cv, sundials::FixedPointSolver& nls, Model& m, sundials::SerialVector& y,
                          sundials::SerialVector& atol, double h0, double dt, const DynamicsOptions& o) {
  const int n = m.n;
  double smax = 0.0;
  for (double s : m.S) smax = std::max(smax, std::abs(s));
  const double qscale = std::max(h0, 1e-9) / smax;
  for (int i = 0; i < n; ++i) {
    atol.data()[i] = o.relative_tolerance * qscale;
    atol.data()[n + i] = o.relative_tolerance * qscale * m.omega[static_cast<std::size_t>(i)];
  }
  atol.data()[2 * n] = o.relative_tolerance * m.target;
  void* mem = cv.get();
  cv.check(CVodeInit(mem, rhs_cb, 0.0, y), "CVodeInit");
  cv.check(CVodeSVtolerances(mem, o.relative_tolerance, atol), "CVodeSVtolerances");
  cv.check(CVodeSetNonlinearSolver(mem, nls), "CVodeSetNonlinearSolver");
  cv.check(CVodeSetUserData(mem, &m), "CVodeSetUserData");
  cv.check(CVodeSetMaxOrd(mem, kMaxAdamsOrder), "CVodeSetMaxOrd");
  cv.check(CVodeSetMaxStep(mem, dt), "CVodeSetMaxStep");
  cv.check(CVodeSetMaxNumSteps(mem, kMaxStepsPerInterval), "CVodeSetMaxNumSteps");
  cv.check(CVodeRootInit(mem, 1, root_cb), "CVodeRootInit");
  cv.check(CVodeSetNoInactiveRootWarn(mem), "CVodeSetNoInactiveRootWarn");
}

// What the run adds up: the contacts per turn (a contact counts once, in
// the turn of its largest force, as a force peak per turn would; one lasting
// a turn or more counts in every turn it spans: continuous contact, one per
// turn), and over the analysed window the force and chip integrals, the
// contact time, the peaks.
struct Tally {
  double T = 0.0, t_analysed = 0.0;
  std::vector<int> per_turn;
  double force_integral = 0.0, chip_integral = 0.0, contact_time = 0.0;
  double peak = 0.0, contact_peak = 0.0, peak_sum = 0.0;
  double contact_start = 0.0, contact_peak_t = 0.0;
  long peak_count = 0, switches_in_window = 0;

  void count_contact(double t_end) {
    const auto turn_of = [&](double tt) {
      return std::min(static_cast<std::size_t>(std::max(tt, 0.0) / T), per_turn.size() - 1);
    };
    if (t_end - contact_start >= T)
      for (std::size_t k = turn_of(contact_start); k <= turn_of(t_end - 1e-12 * T); ++k) ++per_turn[k];
    else
      ++per_turn[turn_of(contact_peak_t)];
  }
  // The piece [t0, t1] had one contact state, forces f0, f1 and chip rates z0, z1.
  void piece(double t0, double t1, double f0, double f1, double z0, double z1, bool contact) {
    if (0.5 * (t0 + t1) >= t_analysed) {
      force_integral += 0.5 * (f0 + f1) * (t1 - t0);
      chip_integral += 0.5 * (z0 + z1) * (t1 - t0);
      if (contact) contact_time += t1 - t0;
      peak = std::max(peak, f1);
    }
    if (contact && f1 > contact_peak) {
      contact_peak = f1;
      contact_peak_t = t1;
    }
  }
  // The contact switched at t (it was `was`).
  void switched(double t, bool was) {
    if (t >= t_analysed) ++switches_in_window;
    if (!was) {  // a contact starts
      contact_peak = 0.0;
      contact_start = contact_peak_t = t;
    } else {  // a contact ends
      count_contact(t);
      if (t >= t_analysed) {
        peak_sum += contact_peak;
        ++peak_count;
      }
    }
  }
  // A contact still going at the end.
  void finish(double t, bool contact) {
    if (!contact) return;
    count_contact(t);
    if (contact_peak > 0.0) {
      peak_sum += contact_peak;
      ++peak_count;
    }
  }
};

// The record of the analysed turns from the tally.
void summarise(const Tally& tl, const Model& m, const DynamicsOptions& o, DynamicsResult& res) {
  const double window = (o.turns - res.analysed_from_turn) * tl.T;
  res.per_turn.assign(tl.per_turn.begin() + res.analysed_from_turn, tl.per_turn.end());
  int most = 0;
  long sum = 0;
  for (int k : res.per_turn) {
    most = std::max(most, k);
    sum += k;
  }
  res.histogram.assign(static_cast<std::size_t>(most) + 1, 0);
  for (int k : res.per_turn) ++res.histogram[static_cast<std::size_t>(k)];
  const double turns_analysed = static_cast<double>(res.per_turn.size());
  res.impacts_per_turn = static_cast<double>(sum) / turns_analysed;
  res.turns_without_contact = res.histogram[0] / turns_analysed;
  res.contact_fraction = std::min(1.0, tl.contact_time / window);
  res.continuous = tl.switches_in_window == 0 && m.contact;
  res.mean_normal_force_n = tl.force_integral / window;
  res.peak_normal_force_n = tl.peak;
  res.mean_contact_peak_n = tl.peak_count > 0 ? tl.peak_sum / static_cast<double>(tl.peak_count) : tl.peak;
  res.removal_rate_m3_per_s = tl.chip_integral / window;
  res.mean_power_w = m.mu * m.Vs * res.mean_normal_force_n;
}

// Adds the integrator's steps and right-hand-side evaluations since its last
// (re)initialisation to the result's counts.
void add_counts(void* mem, DynamicsResult& res) {
  long ns = 0, nf = 0;
  CVodeGetNumSteps(mem, &ns);
  CVodeGetNumRhsEvals(mem, &nf);
  res.steps += ns;
  res.rhs_evaluations += nf;
}

// The quasi-static removal rate (m³/s) at the power with the impacts per turn
// the simulation counted in place of the model's.
double removal_at_impacts(const Process& p, double power_w, double impacts_per_turn) {
  Process q = p;
  q.mechanistic->impacts = ImpactsPerTurn(impacts_per_turn);
  q.empirical = {};
  return predict_at_power(q, power_w).removal_rate_m3_per_s;
}

}  // namespace

DynamicsResult simulate_grinding(const Process& p, const StructuralModel& robot, double power_w,
                                 const DynamicsOptions& o) {
  check_options(o);
  if (!p.mechanistic)
    throw InputError("simulate needs the mechanistic model (grinding.edge_coefficient_n_per_mm, "
                     "cutting_coefficient_n_per_mm2, impacts_per_turn): the contact force is built on it");
  DynamicsResult res;
  res.quasi_static = predict_at_power(p, power_w);  // checks the power
  const Prediction& qs = res.quasi_static;
  res.power_w = power_w;
  res.wheel_rpm = rpm_from_revolutions_per_s(p.wheel.speed_rev_per_s);
  double tool_compliance = 0.0;
  Model m = make_model(p, robot, qs, o, &tool_compliance, res);
  const double T = 1.0 / m.N, h0 = qs.max_depth_m;
  const std::vector<double> y0 = initial_state(m, h0, tool_compliance, o);
  const int n = m.n, M = o.points_per_turn;
  const double dt = T / M;

  sundials::Context ctx;
  sundials::SerialVector y(2 * n + 1, ctx), atol(2 * n + 1, ctx);
  std::copy(y0.begin(), y0.end(), y.data());
  sundials::Cvode cv(CV_ADAMS, ctx, "grinding simulate");
  sundials::FixedPointSolver nls(y, 0, ctx);
  configure_integrator(cv, nls, m, y, atol, h0, dt, o);
  void* mem = cv.get();

  // The groove memory: d at grid indices i - M .. i + 1 in a ring of M + 1.
  std::vector<double> ring(static_cast<std::size_t>(M) + 1, h0);
  const long size = M + 1;
  auto slot = [&](long j) { return static_cast<std::size_t>(((j % size) + size) % size); };
  const long total = static_cast<long>(o.turns) * M;
  res.turns = o.turns;
  res.analysed_from_turn = std::min(o.turns - 1, static_cast<int>(std::floor(o.turns * (1.0 - o.analysed_fraction))));
  Tally tl{T, res.analysed_from_turn * T, std::vector<int>(static_cast<std::size_t>(o.turns), 0)};
  const double t_series = (o.turns - o.series_turns) * T;

  double t = 0.0;
  m.t_a = 0.0;
  m.t_b = dt;
  m.s_a = (1.0 - m.r) * ring[slot(-M)];
  m.s_b = (1.0 - m.r) * ring[slot(1 - M)];
  m.contact = m.depth(y.data()) - m.surface(0.0) > 0.0;
  auto state_force = [&](double tt) {
    const double x = m.depth(y.data());
    return std::pair<double, double>{m.force(x, x - m.surface(tt), m.contact),
                                     m.chip_rate(x, x - m.surface(tt), m.contact)};
  };
  auto [f_start, z_start] = state_force(0.0);
  double t_start = 0.0;
  auto record = [&](double tt) {
    if (o.series_turns == 0 || tt < t_series - 1e-12 * T) return;
    const double x = m.depth(y.data());
    res.series.push_back({tt, x, m.surface(tt), m.force(x, x - m.surface(tt), m.contact), y.data()[2 * n]});
  };
  record(0.0);

  for (long i = 0; i < total; ++i) {
    const double t_next = static_cast<double>(i + 1) * dt;
    m.t_a = static_cast<double>(i) * dt;
    m.t_b = t_next;
    m.s_a = (1.0 - m.r) * ring[slot(i - M)];
    m.s_b = (1.0 - m.r) * ring[slot(i + 1 - M)];
    cv.check(CVodeSetStopTime(mem, t_next), "CVodeSetStopTime");
    for (;;) {
      const int flag = CVode(mem, t_next, y, &t, CV_NORMAL);
      cv.check(flag, "CVode");
      const auto [f_end, z_end] = state_force(t);
      tl.piece(t_start, t, f_start, f_end, z_start, z_end, m.contact);
      const bool at_grid = t >= t_next - 1e-9 * dt;
      if (flag == CV_ROOT_RETURN) {
        record(t);
        tl.switched(t, m.contact);
        m.contact = !m.contact;
        add_counts(mem, res);
        cv.check(CVodeReInit(mem, t, y), "CVodeReInit");
        cv.check(CVodeSetStopTime(mem, t_next), "CVodeSetStopTime");
        ++res.restarts;
        std::tie(f_start, z_start) = state_force(t);
        t_start = t;
        record(t);
        if (at_grid) break;
        continue;
      }
      f_start = f_end;
      z_start = z_end;
      t_start = t;
      if (at_grid) break;
    }
    // Grid point i + 1: the surface the wheel leaves at this angle.
    const double x = m.depth(y.data());
    ring[slot(i + 1)] = m.contact ? x : m.s_b;
    record(t_next);
  }
  add_counts(mem, res);
  tl.finish(t, m.contact);
  summarise(tl, m, o, res);
  if (res.impacts_per_turn > 0.0)
    res.removal_at_simulated_impacts_m3_per_s = removal_at_impacts(p, power_w, res.impacts_per_turn);
  return res;
}

}  // namespace chatter::grinding
