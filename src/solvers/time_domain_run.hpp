// Internal: one run of TimeDomainSimulator::simulate on SUNDIALS CVODE
// (not part of the public API). The stepping is in time_domain_run.cpp, the
// outputs (finish) in time_domain_analysis.cpp; the right-hand side it
// integrates is Model (time_domain_model.hpp).
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "chatter/results.hpp"
#include "chatter/time_domain.hpp"
#include "sundials_raii.hpp"
#include "time_domain_model.hpp"
#include "time_domain_parts.hpp"

namespace chatter::td_detail {

using detail::AirCounts;
using detail::PeriodSnapshots;

// Settings checks that need neither the model nor the speed's sampling.
void validate_settings(const SimulationSettings& s);

// Speed variation, nonlinear mode (time_domain_ssv.cpp): a run that settled
// into an orbit periodic over the principal period while the tool left the
// cut is either the forced response (then the linear equation is stable
// too) or a chatter orbit locked to the modulation (a flip or fold of the
// principal-period map: q tooth periods hold it). One linear run at the
// same point tells which; `r` becomes chatter in the second case.
void check_locked_orbit(const TimeDomainSimulator& sim, const SimulationSettings& s, SimulationResult& r);

// ---------------------------------------------------------------------------
// One run of TimeDomainSimulator::simulate.
//   set-up (constructor): sampling, initial state and tolerance scale,
//     history, stop points, CVODE;
//   stepping (run): the uniform grid of M samples per delay; between grid
//     points the fixed stop points (arc events, start images), the chip zero
//     crossings (CVODE roots) and their delay images, each stored in the
//     history and followed by a restart;
//   outputs (finish): counters, then the analysers of time_domain_parts.hpp
//     (growth per period, spectrum, verdict).
// Lives on the stack of simulate(); not copyable (CVODE holds its address).
class SimulationRun {
 public:
  SimulationRun(const StructuralModel& model, const Process& process, const TimeDomainOptions& options,
                const SimulationSettings& s);
  SimulationRun(const SimulationRun&) = delete;
  SimulationRun& operator=(const SimulationRun&) = delete;

  SimulationResult run();

 private:
  // --- set-up ---
  void choose_sampling();
  void set_initial_state();
  void init_history();
  void init_stops();
  void init_integrator();
  // --- stepping ---
  void start();
  void step_to_grid_point(long i);
  void end_of_period(bool at_stop, bool& root_at_grid);
  double next_event(int skip) const;
  void pass_event(double tt);
  void on_root(double tr);
  double segment_mid(double tt, double t_next) const;
  void restart(double tt);
  // |r| of the current state (relative displacement, m).
  double displacement_now() const;
  // The integrator's flag, with a runaway (a displacement no machine shows)
  // turned into InputError naming the likely unit mistake.
  void check_step(int flag);
  Diagnostics store(double t, bool segment_changes, double t_next_mid);
  SeriesSample make_sample(double t, const double* yy, const Diagnostics& d) const;
  // --- outputs ---
  SimulationResult finish();
  // The forced vibration of the last period and the teeth out of the cut
  // (issue 27), into res_.
  void measure_forced(bool converged);

  const Process& process_;
  const TimeDomainOptions& options_;
  const SimulationSettings& s_;
  const double tau_;
  Model m_;
  const int n_, teeth_;

  // Sampling: M grid samples per delay, spacing dt; highest natural frequency.
  double f_max_ = 0.0, dt_ = 0.0;
  int M_ = 0;
  // Initial state [q; q̇] and the displacement scale of the tolerances.
  std::vector<double> y0_;
  double scale_ = 0.0;
  int root_cap_ = 0, root_images_ = 0, root_count_ = 0;
  double hold_ = 0.0;  // history kept behind the newest entry, s
  std::optional<History> history_;
  double t_end_ = 0.0;
  std::vector<double> stops_;  // fixed stop points, sorted, t_end last
  // Per stop: 1 when the force is continuous there (an end of a helical
  // edge entering or leaving the arc): the integrator stops on it but keeps
  // its history instead of restarting (Model::continuous_arc_events).
  std::vector<char> soft_;

  sundials::Context ctx_;
  std::optional<sundials::SerialVector> y_, atol_;
  std::optional<sundials::Cvode> cv_;
  std::optional<sundials::FixedPointSolver> nls_;
  void* mem_ = nullptr;
  bool use_roots_ = false, roots_on_ = false;

  SimulationResult res_;
  int first_analysed_ = 0;
  // Per-period observables for the DMD: r at the M grid points of the period
  // just ended, plus the modal state at its end (velocities / ω).
  int zdim_ = 0;
  PeriodSnapshots snapshots_;
  Eigen::VectorXd period_r_;
  double log_scale_ = 0.0;  // linear mode: true state = stored × exp(log_scale)
  std::vector<double> win_x_, win_y_;  // uniform samples of r over the analysed window
  AirCounts air_;
  // Per tooth: the arc share sampled in the analysed window and its part
  // out of the cut (Model::tally_air), for out_of_cut_fraction.
  std::vector<double> tooth_arc_, tooth_air_;
  double max_amp_ = 0.0;

  std::vector<double> ydot_;
  Diagnostics dg_;
  // Pending images of the chip zero crossings, sorted; they lie within
  // root_images delays ahead, so at most about (root_cap + 1) x root_images
  // are held, whatever the simulated time.
  std::deque<double> images_;
  std::size_t next_stop_ = 0;
  // True when the next event, at tt, is a soft stop and no image (root or
  // start) coincides with it.
  bool soft_event(double tt) const;
  long restarts_ = 0, root_stops_ = 0;
  double t_ = 0.0;
  int roots_this_period_ = 0;
  long steps_done_ = 0, rhs_done_ = 0;  // CVodeReInit resets CVODE's counters
  bool settled_ = false;  // stop_when_periodic: the run has settled (end_of_period)
};

}  // namespace chatter::td_detail
