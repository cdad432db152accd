// One time-domain run on SUNDIALS CVODE (time_domain_run.hpp): set-up of
// the sampling, initial state, history, stop points and the integrator;
// stepping over the uniform grid with its stop points, roots and restarts.
// The outputs are in time_domain_analysis.cpp. Design: docs/time_domain.md.
#include "chatter/time_domain.hpp"
#include "time_domain_run.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "chatter/error.hpp"

namespace chatter::td_detail {

// A relative displacement beyond these stops a run with a static chip: 1 m
// (no machine structure moves that far), or 10 mm when the integrator gave
// up on it (CV_TOO_MUCH_WORK on a runaway) — both far beyond any chatter.
// Found by the extremes test: a mode of 1 N/m (30 m of static deflection)
// ran 88 s and ended in an internal error.
constexpr double kRunawayDisplacementM = 1.0;
constexpr double kFailedRunawayDisplacementM = 1e-2;
namespace {

using detail::HistoryEntry;

// stop_when_periodic: at least this many periods before a run may stop, and
// this many quiet increments in a row (SimulationSettings::stop_when_periodic).
constexpr int kMinPeriodsBeforeStop = 20;
constexpr int kQuietPeriods = 3;
// Delay-propagated images of the start discontinuity that are stop points:
// the k-th image is a jump in the k-th derivative, beyond Adams order 5 after 6.
constexpr int kStartImages = 6;
constexpr int kMaxAdamsOrder = 5;

int cvode_rhs(double t, N_Vector y, N_Vector ydot, void* user) {
  static_cast<const Model*>(user)->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), nullptr);
  return 0;
}
int cvode_roots(double t, N_Vector y, double* g, void* user) {
  static_cast<const Model*>(user)->chips(t, N_VGetArrayPointer(y), g);
  return 0;
}

}  // namespace

SimulationRun::SimulationRun(const StructuralModel& model, const Process& process, const TimeDomainOptions& options,
                             const SimulationSettings& s)
    : process_(process),
      options_(options),
      s_(s),
      tau_(simulation_period(process, s)),
      m_(model, process, s, tau_, options),
      n_(m_.n()),
      teeth_(m_.teeth()) {
  if (!s.initial_state.empty() && static_cast<int>(s.initial_state.size()) != 2 * n_)
    throw InputError("initial state has " + std::to_string(s.initial_state.size()) + " values: needs 2 x " +
                     std::to_string(n_) + " modes");
  choose_sampling();
  set_initial_state();
  init_history();
  init_stops();
  init_integrator();
}

void SimulationRun::choose_sampling() {
  for (int i = 0; i < n_; ++i) f_max_ = std::max(f_max_, m_.modal().omega(i) / (2.0 * kPi));
  const double need = std::ceil(options_.samples_per_vibration_cycle * tau_ * f_max_);
  if (need > options_.max_samples_per_period)
    throw InputError("time-domain: " + std::to_string(s_.spindle_rpm) + " rev/min needs " +
                     std::to_string(static_cast<long>(need)) + " history samples per delay (limit " +
                     std::to_string(options_.max_samples_per_period) + "): raise the speed");
  M_ = std::max(options_.samples_per_period, static_cast<int>(need));
  if (m_.general() || m_.ssv()) {
    // samples_per_period per tooth period; at least 2 samples per shortest
    // delay (with speed variation the period holds q Floquet periods).
    const int tooth_periods = static_cast<int>(std::lround(tau_ / process_.delay_s(s_.spindle_rpm)));
    M_ = std::max({M_, options_.samples_per_period * tooth_periods,
                   static_cast<int>(std::ceil(2.0 * tau_ / m_.min_delay()))});
    if (M_ > options_.max_samples_per_period)
      throw InputError("time-domain: " + std::to_string(s_.spindle_rpm) + " rev/min needs " + std::to_string(M_) +
                       " history samples per period (limit " + std::to_string(options_.max_samples_per_period) + ")");
  }
  dt_ = tau_ / M_;
}

void SimulationRun::set_initial_state() {
  y0_.assign(2 * n_, 0.0);
  if (!s_.initial_state.empty()) {
    y0_ = s_.initial_state;
  } else if (homogeneous(s_) || s_.feed_m == 0.0) {
    for (int i = 0; i < n_; ++i) {
      y0_[i] = 1e-6;
      y0_[n_ + i] = 0.5e-6 * m_.modal().omega(i);
    }
  }
  double scale = 0.0;
  for (int i = 0; i < n_; ++i) scale = std::max(scale, std::abs(y0_[i]));
  if (!homogeneous(s_) && s_.feed_m > 0.0) {
    double kmin = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n_; ++i)
      kmin = std::min(kmin, m_.modal().mass_kg(i) * m_.modal().omega(i) * m_.modal().omega(i));
    const double coeff = m_.milling() ? process_.milling_parameters().tangential_coefficient_n_per_m2
                                      : process_.turning_parameters().feed_force_coefficient_n_per_m2;
    scale = std::max(scale, s_.depth_m * coeff * s_.feed_m / kmin);
  }
  if (!(scale > 0.0)) scale = 1e-9;
  scale_ = scale;
  m_.set_air_margin(1e-6 * std::max(scale_, s_.feed_m));
}

void SimulationRun::init_history() {
  // History: constant at the initial displacement before t = 0.
  // Entries held: about 1.5 delays of grid samples, the arc events and start
  // images in that span, at most root_cap + 1 root stops per period and as
  // many stops at each of their root_images delay images.
  root_cap_ = 8 * teeth_ + 8;
  // Speed variation: the period holds q Floquet periods of the mean speed.
  if (m_.ssv())
    root_cap_ *= static_cast<int>(std::max(1L, std::lround(tau_ / process_.floquet_period_s(s_.spindle_rpm))));
  root_images_ = s_.linear ? 0 : (s_.multiple_regeneration ? kRootImagesMultiple : kRootImagesSingle);
  // Real cutters hold the largest delay read (up to one revolution), and so
  // does a modulated speed (the delay at the lowest speed).
  const bool long_hold = m_.general() || m_.ssv();
  hold_ = long_hold ? std::max(1.5 * tau_, m_.max_delay() + 0.5 * tau_) : 1.5 * tau_;
  const std::size_t held = long_hold ? static_cast<std::size_t>(std::ceil(hold_ / dt_))
                                         : static_cast<std::size_t>(M_ + M_ / 2);
  const std::size_t capacity =
      held + static_cast<std::size_t>(2 * (root_cap_ + 1) * (1 + root_images_) + 4 * teeth_ + 16);
  history_.emplace(capacity, m_.general() ? 1 : teeth_);
  m_.attach(&*history_);
  std::vector<double> zero_gaps(teeth_, 0.0);
  HistoryEntry e;
  m_.relative(y0_.data(), e.r);
  e.t = -(long_hold ? m_.max_delay() : tau_) - 2.0 * dt_;
  history_->push(e, zero_gaps.data());
  e.t = 0.0;
  history_->push(e, zero_gaps.data());
}

void SimulationRun::init_stops() {
  t_end_ = s_.periods * tau_;
  std::vector<std::pair<double, char>> stops;
  const char soft = m_.continuous_arc_events() ? 1 : 0;
  for (const double t : m_.arc_events(t_end_)) stops.emplace_back(t, soft);
  if (!m_.general() && !m_.ssv()) {
    for (int k = 1; k <= kStartImages && k <= s_.periods; ++k) stops.emplace_back(k * tau_, 0);
  } else {
    // Speed variation: the images of the start at the mean-speed delays'
    // multiples, at the real times the spindle turns that far.
    for (const double d : m_.start_image_delays())
      for (int k = 1; k <= kStartImages && m_.real_time(k * d) < t_end_; ++k)
        stops.emplace_back(m_.real_time(k * d), 0);
  }
  std::sort(stops.begin(), stops.end());
  std::vector<double> merged;
  std::vector<char> merged_soft;
  for (const auto& [t, sf] : stops) {
    if (t <= 1e-9 * tau_ || t >= t_end_ - 1e-9 * tau_) continue;
    if (merged.empty() || t - merged.back() > 1e-9 * tau_) {
      merged.push_back(t);
      merged_soft.push_back(sf);
    } else {
      merged_soft.back() = static_cast<char>(merged_soft.back() && sf);  // one hard stop makes it hard
    }
  }
  merged.push_back(t_end_);  // always the last stop, exactly
  merged_soft.push_back(0);
  stops_.swap(merged);
  soft_.swap(merged_soft);
}

bool SimulationRun::soft_event(double tt) const {
  if (!(next_stop_ < stops_.size() && std::abs(stops_[next_stop_] - tt) <= 1e-9 * tau_ && soft_[next_stop_]))
    return false;
  return images_.empty() || images_.front() - tt > 1e-9 * tau_;
}

void SimulationRun::init_integrator() {
  y_.emplace(2 * n_, ctx_);
  atol_.emplace(2 * n_, ctx_);
  std::copy(y0_.begin(), y0_.end(), y_->data());
  const double rtol = options_.relative_tolerance;
  for (int i = 0; i < n_; ++i) {
    const double sc = std::max(1e-300, scale_);
    atol_->data()[i] = rtol * sc;
    atol_->data()[n_ + i] = rtol * sc * m_.modal().omega(i);
  }
  cv_.emplace(CV_ADAMS, ctx_);
  mem_ = cv_->get();
  cv_->check(CVodeInit(mem_, cvode_rhs, 0.0, *y_), "CVodeInit");
  cv_->check(CVodeSVtolerances(mem_, rtol, *atol_), "CVodeSVtolerances");
  nls_.emplace(*y_, 0, ctx_);
  cv_->check(CVodeSetNonlinearSolver(mem_, *nls_), "CVodeSetNonlinearSolver");
  cv_->check(CVodeSetUserData(mem_, &m_), "CVodeSetUserData");
  cv_->check(CVodeSetMaxOrd(mem_, kMaxAdamsOrder), "CVodeSetMaxOrd");
  cv_->check(CVodeSetMaxStep(mem_, 0.5 * (m_.general() || m_.ssv() ? std::min(tau_, m_.min_delay()) : tau_)),
             "CVodeSetMaxStep");
  cv_->check(CVodeSetMaxNumSteps(mem_, options_.max_steps), "CVodeSetMaxNumSteps");
  root_count_ = m_.root_count();
  use_roots_ = !s_.linear && root_count_ > 0;
  if (use_roots_) {
    cv_->check(CVodeRootInit(mem_, root_count_, cvode_roots), "CVodeRootInit");
    cv_->check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
  }
  roots_on_ = use_roots_;

  res_.floquet_period_s = tau_;
  res_.tooth_passing_hz = process_.tooth_passing_hz(s_.spindle_rpm);
  res_.periods = s_.periods;
  res_.samples_per_period = M_;
  first_analysed_ = std::clamp(static_cast<int>(std::floor(s_.periods * (1.0 - s_.analysed_fraction))), 0,
                               s_.periods - 2);
  res_.analysed_from_period = first_analysed_;
  zdim_ = 2 * M_ + 2 * n_;
  period_r_.resize(2 * M_);
  ydot_.assign(2 * n_, 0.0);
  tooth_arc_.assign(static_cast<std::size_t>(teeth_), 0.0);
  tooth_air_.assign(static_cast<std::size_t>(teeth_), 0.0);
}

SeriesSample SimulationRun::make_sample(double t, const double* yy, const Diagnostics& d) const {
  SeriesSample smp;
  smp.t_s = t;
  const auto& mm = m_.modal();
  const double ex = std::exp(log_scale_);
  for (int i = 0; i < n_; ++i) {
    // S column = ±u_i; the body's own displacement is u_i q_i.
    const double sign = i < m_.tool_modes() ? 1.0 : -1.0;
    const double dx = sign * mm.S(0, i) * yy[i] * ex, dy = sign * mm.S(1, i) * yy[i] * ex;
    if (i < m_.tool_modes()) {
      smp.tool_x_m += dx;
      smp.tool_y_m += dy;
    } else {
      smp.workpiece_x_m += dx;
      smp.workpiece_y_m += dy;
    }
  }
  smp.rel_x_m = smp.tool_x_m - smp.workpiece_x_m;
  smp.rel_y_m = smp.tool_y_m - smp.workpiece_y_m;
  smp.force_x_n = d.force[0] * ex;
  smp.force_y_n = d.force[1] * ex;
  smp.chip_m = d.chip_max * (s_.linear ? ex : 1.0);
  smp.in_cut = d.in_cut;
  return smp;
}

// Stores a history entry at the current (t, y): a_left from the segment
// that ends here, a_right from the one that starts (same when no event).
// Returns the diagnostics of the segment that ends here.
Diagnostics SimulationRun::store(double t, bool segment_changes, double t_next_mid) {
  double* y = y_->data();
  HistoryEntry e;
  e.t = t;
  m_.relative(y, e.r);
  m_.rhs(t, y, ydot_.data(), &dg_);
  // ṙ and r̈ from q̇ and q̈.
  double v[2] = {0, 0}, a[2] = {0, 0};
  for (int i = 0; i < n_; ++i) {
    v[0] += m_.modal().S(0, i) * ydot_[i];
    v[1] += m_.modal().S(1, i) * ydot_[i];
    a[0] += m_.modal().S(0, i) * ydot_[n_ + i];
    a[1] += m_.modal().S(1, i) * ydot_[n_ + i];
  }
  e.v[0] = v[0];
  e.v[1] = v[1];
  e.a_left[0] = e.a_right[0] = a[0];
  e.a_left[1] = e.a_right[1] = a[1];
  Diagnostics left = dg_;
  if (segment_changes) {
    m_.set_segment(t_next_mid);
    m_.rhs(t, y, ydot_.data(), &dg_);
    double ar[2] = {0, 0};
    for (int i = 0; i < n_; ++i) {
      ar[0] += m_.modal().S(0, i) * ydot_[n_ + i];
      ar[1] += m_.modal().S(1, i) * ydot_[n_ + i];
    }
    e.a_right[0] = ar[0];
    e.a_right[1] = ar[1];
  }
  // Gaps in air (multiple regeneration), from the chips after the event.
  std::vector<double> gaps(teeth_, 0.0);
  if (s_.multiple_regeneration && !s_.linear && !m_.general()) {
    std::vector<double> h(teeth_);
    m_.chips(t, y, h.data());
    for (int j = 0; j < teeth_; ++j) gaps[j] = m_.in_arc()[j] ? std::max(0.0, -h[j]) : 0.0;
  }
  history_->push(e, gaps.data());
  history_->drop_before(t - hold_);
  return left;
}

// The next stop (skip = 0) or the one after it (skip = 1): the earlier of
// the fixed list and the pending images; two within 1e-9 τ are one.
double SimulationRun::next_event(int skip) const {
  double a[2] = {t_end_, t_end_};
  std::size_t i = next_stop_, j = 0;
  for (int k = 0; k < 2; ++k) {
    const double si = i < stops_.size() ? stops_[i] : t_end_, ij = j < images_.size() ? images_[j] : t_end_;
    a[k] = std::min(si, ij);
    while (i < stops_.size() && stops_[i] - a[k] <= 1e-9 * tau_) ++i;
    while (j < images_.size() && images_[j] - a[k] <= 1e-9 * tau_) ++j;
  }
  return a[skip];
}

// Passes the event at tt (the fixed stop and / or the images there).
void SimulationRun::pass_event(double tt) {
  if (next_stop_ < stops_.size() && stops_[next_stop_] - tt <= 1e-9 * tau_) ++next_stop_;
  while (!images_.empty() && images_.front() - tt <= 1e-9 * tau_) images_.pop_front();
}

// A chip zero crossing at tr: count it and queue its delay images.
void SimulationRun::on_root(double tr) {
  ++root_stops_;
  // Uniform path: images at tr + kτ. Real cutter: at the times the next
  // teeth pass over the surface the root's element left.
  std::vector<int> which{0};
  if (m_.general()) {
    std::vector<int> found(static_cast<std::size_t>(root_count_), 0);
    cv_->check(CVodeGetRootInfo(mem_, found.data()), "CVodeGetRootInfo");
    which.clear();
    for (int i = 0; i < root_count_; ++i)
      if (found[static_cast<std::size_t>(i)] != 0) which.push_back(i);
  }
  for (const int i : which) {
    for (int k = 1; k <= root_images_; ++k) {
      const double ti = m_.root_image_time(tr, i, k);
      if (ti >= t_end_ - 1e-9 * tau_) break;
      const auto at = std::lower_bound(images_.begin(), images_.end(), ti - 1e-9 * tau_);
      if (at != images_.end() && *at - ti <= 1e-9 * tau_) continue;  // already there (e.g. roots at tooth exit)
      images_.insert(at, ti);
    }
  }
}

// A time inside the segment that starts at tt and ends at the next event
// t_next (the arc test at an event itself would be ambiguous).
double SimulationRun::segment_mid(double tt, double t_next) const {
  return 0.5 * (tt + (t_next > tt + 1e-9 * tau_ ? std::min(t_next, tt + dt_) : tt + dt_));
}

double SimulationRun::displacement_now() const {
  const double* y = y_->data();
  double r[2] = {0.0, 0.0};
  for (int i = 0; i < n_; ++i) {
    r[0] += m_.modal().S(0, i) * y[i];
    r[1] += m_.modal().S(1, i) * y[i];
  }
  return std::hypot(r[0], r[1]);
}

void SimulationRun::check_step(int flag) {
  // A linear run rescales its state every period (end_of_period); only a run
  // with a static chip (nonlinear, or linear with the feed) can run away.
  if (!homogeneous(s_)) {
    const double r = displacement_now();
    if (r > kRunawayDisplacementM || (flag < 0 && r > kFailedRunawayDisplacementM)) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "the simulated displacement reached %.3g mm at t = %.3g s (%.3g periods)",
                    r * 1e3, t_, t_ / tau_);
      throw InputError("time-domain: " + std::string(buf) +
                       ": no machine structure moves that far; the cut runs away, which with an accepted config "
                       "means a stiffness or a cutting coefficient in the wrong unit (N/m for N/um, N/m^2 for "
                       "N/mm^2)?");
    }
  }
  cv_->check(flag, "CVode");
}

void SimulationRun::restart(double tt) {
  long ns = 0, nf = 0;
  CVodeGetNumSteps(mem_, &ns);
  CVodeGetNumRhsEvals(mem_, &nf);
  steps_done_ += ns;
  rhs_done_ += nf;
  cv_->check(CVodeReInit(mem_, tt, *y_), "CVodeReInit");
  cv_->check(CVodeSetStopTime(mem_, next_event(0)), "CVodeSetStopTime");
  ++restarts_;
}

// t = 0: the segment, the right-limit acceleration of the newest (t = 0)
// history entry, the first samples and the first stop time.
void SimulationRun::start() {
  m_.set_segment(stops_.empty() ? 0.5 * dt_ : 0.5 * std::min(stops_.front(), dt_));
  m_.rhs(0.0, y_->data(), ydot_.data(), &dg_);
  HistoryEntry& e0 = history_->newest_mutable();
  double a[2] = {0, 0};
  for (int i = 0; i < n_; ++i) {
    a[0] += m_.modal().S(0, i) * ydot_[n_ + i];
    a[1] += m_.modal().S(1, i) * ydot_[n_ + i];
  }
  e0.a_right[0] = a[0];
  e0.a_right[1] = a[1];
  if (s_.record_series) res_.series.push_back(make_sample(0.0, y_->data(), dg_));
  res_.once_per_period.push_back(make_sample(0.0, y_->data(), dg_));
  cv_->check(CVodeSetStopTime(mem_, stops_[0]), "CVodeSetStopTime");
}

// Integrates to grid point i (t = i τ / M), stopping at every event and root
// on the way, and records the grid point.
void SimulationRun::step_to_grid_point(long i) {
  const double target = static_cast<double>(i) * tau_ / M_;
  bool root_at_grid = false;
  while (true) {
    const int flag = CVode(mem_, target, *y_, &t_, CV_NORMAL);
    check_step(flag);
    if (t_ >= target - 1e-12 * tau_) {  // at the grid point (possibly also a stop or a root)
      if (flag == CV_ROOT_RETURN) {
        on_root(t_);
        root_at_grid = true;
      }
      break;
    }
    if (next_event(0) - t_ <= 1e-9 * tau_) {
      // An event before the grid point (reached as a stop, or a root that
      // fell on it): step onto it and change segment.
      const double t_next = next_event(1);
      const bool soft = flag != CV_ROOT_RETURN && soft_event(t_);
      store(t_, true, segment_mid(t_, t_next));
      pass_event(t_);
      if (flag == CV_ROOT_RETURN) on_root(t_);
      if (soft)  // the force is continuous here: keep the integrator's history
        cv_->check(CVodeSetStopTime(mem_, next_event(0)), "CVodeSetStopTime");
      else
        restart(t_);
      continue;
    }
    if (flag == CV_ROOT_RETURN) {
      on_root(t_);
      store(t_, false, 0.0);
      if (++roots_this_period_ > root_cap_ && roots_on_) {
        cv_->check(CVodeRootInit(mem_, 0, nullptr), "CVodeRootInit");
        roots_on_ = false;
      }
      restart(t_);
      continue;
    }
    throw NumericalError("time-domain: internal error: CVODE stopped at t = " + std::to_string(t_) +
                         " s, neither a grid point, a stop nor a root");
  }
  t_ = target;
  const bool at_stop = std::abs(next_event(0) - target) <= 1e-9 * tau_;
  const bool soft = at_stop && !root_at_grid && soft_event(target);
  const double t_next = at_stop ? next_event(1) : t_end_;
  const Diagnostics left = store(target, at_stop, segment_mid(target, t_next));
  if (at_stop) pass_event(target);
  const long period = (i - 1) / M_;  // 0-based period this sample ends or lies in
  const long in_period = (i - 1) % M_;
  period_r_(2 * in_period) = history_->newest().r[0];
  period_r_(2 * in_period + 1) = history_->newest().r[1];
  const SeriesSample smp = make_sample(target, y_->data(), left);
  if (s_.record_series) res_.series.push_back(smp);
  if (period >= first_analysed_) {
    win_x_.push_back(smp.rel_x_m);
    win_y_.push_back(smp.rel_y_m);
    max_amp_ = std::max(max_amp_, std::hypot(smp.rel_x_m, smp.rel_y_m));
    if (left.any_in_arc) air_.add(left.in_air, 2 * (period - first_analysed_) >= (s_.periods - first_analysed_));
    if (!s_.linear) m_.tally_air(tooth_arc_, tooth_air_);
  }
  if ((i % M_) == 0) {
    res_.once_per_period.push_back(smp);
    end_of_period(at_stop && !soft, root_at_grid);
    if (s_.on_period) s_.on_period(res_);
  }
  if ((at_stop && !soft) || root_at_grid)
    restart(target);
  else if (at_stop)  // a soft stop: on to the next one with the integrator's history
    cv_->check(CVodeSetStopTime(mem_, next_event(0)), "CVodeSetStopTime");
}

// At t = kτ: the DMD snapshot, roots back on, and (linear mode) the exact
// rescaling that keeps the state near its initial size.
void SimulationRun::end_of_period(bool at_stop, bool& root_at_grid) {
  double* y = y_->data();
  Eigen::VectorXd z(zdim_);
  z.head(2 * M_) = period_r_;
  for (int k = 0; k < n_; ++k) {
    z(2 * M_ + k) = y[k];
    z(2 * M_ + n_ + k) = y[n_ + k] / m_.modal().omega(k);
  }
  snapshots_.states.push_back(z);
  snapshots_.log_scale.push_back(log_scale_);
  if (s_.stop_when_periodic && !homogeneous(s_)) {
    // Settled: the last kQuietPeriods increments below the verdict's floor
    // (growth_per_period's 1e4 × rtol × |snapshot|).
    const auto& st = snapshots_.states;
    const std::size_t K = st.size();
    if (K >= static_cast<std::size_t>(std::max(kMinPeriodsBeforeStop, kQuietPeriods + 1))) {
      const double floor = 1e4 * options_.relative_tolerance * std::max(st.back().norm(), 1e-300);
      bool quiet = true;
      for (std::size_t k = K - kQuietPeriods; k < K && quiet; ++k) quiet = (st[k] - st[k - 1]).norm() <= floor;
      settled_ = quiet;
    }
  }
  roots_this_period_ = 0;
  bool need_restart = at_stop;
  if (use_roots_ && !roots_on_) {
    cv_->check(CVodeRootInit(mem_, root_count_, cvode_roots), "CVodeRootInit");
    roots_on_ = true;
    need_restart = true;
  }
  if (homogeneous(s_)) {
    // Keep the state near the initial scale (linear: exact rescaling).
    double norm = 0.0;
    for (int k = 0; k < n_; ++k) norm = std::max(norm, std::abs(y[k]));
    // With speed variation a period is many vibration cycles and the state
    // may shrink by orders of magnitude in one: rescaled every period, so
    // that the absolute tolerance stays rtol of it (else, at 1e-3 of the
    // scale, the snapshots carry errors up to 1e3 rtol relative, which the
    // DMD fitted as spurious multipliers: 1.75 for sdm's 0.610 on case A
    // at 1 200 rev/min, 2.088 mm).
    const bool rescale = m_.ssv() ? norm != scale_ : (norm > 1e3 * scale_ || norm < 1e-3 * scale_);
    if (norm > 0.0 && rescale) {
      const double f = scale_ / norm;
      for (int k = 0; k < 2 * n_; ++k) y[k] *= f;
      history_->scale(f);
      log_scale_ -= std::log(f);
      need_restart = true;
    }
  }
  if (need_restart) root_at_grid = true;
}

SimulationResult SimulationRun::run() {
  start();
  const long total = static_cast<long>(s_.periods) * M_;
  for (long i = 1; i <= total; ++i) {
    step_to_grid_point(i);
    if (settled_ && i % M_ == 0 && i < total) {
      // Settled (stop_when_periodic): the run is its first i / M periods,
      // analysed over their last analysed_fraction.
      const int done = static_cast<int>(i / M_);
      res_.periods = done;
      first_analysed_ = std::clamp(static_cast<int>(std::floor(done * (1.0 - s_.analysed_fraction))), 0, done - 2);
      res_.analysed_from_period = first_analysed_;
      t_end_ = static_cast<double>(i) * tau_ / M_;  // the last grid point, as stored
      break;
    }
  }
  return finish();
}

}  // namespace chatter::td_detail
