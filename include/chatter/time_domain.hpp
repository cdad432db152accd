// Time-domain simulation of the regenerative delay equation with the real,
// nonlinear chip: the `time-domain` solver (docs/physics.md §2, §3, §6).
//
// Equations (modal coordinates, docs/physics.md §2–3):
//   q̈_i + 2 ζ_i ω_i q̇_i + ω_i² q_i = (1/m_i) S_iᵀ F(t),   r = S q (relative, m)
// Force on the tool, N (the workpiece gets −F):
//   turning: h = f + r_x(t) − r_x(t − τ),                    F = (−a K_f max(0, h), 0)
//   milling: h_j = f_z sin φ_j + n_j·(r(t) − r(t − τ)),  n_j = (sin φ_j, cos φ_j),
//            F = Σ_{j cutting} −a max(0, h_j) (K_t cos φ_j + K_r sin φ_j, −(K_t sin φ_j − K_r cos φ_j))
// f is the feed per revolution (turning) or per tooth (milling); a the depth.
// With multiple regeneration the chip is measured against the surface left by
// every earlier pass, not only the last one:
//   h(t) = h_single(t) − max(0, −h(t − τ))   (the gap the last pass left in air).
// Linear mode drops the static chip and the max(0, ·): F = −a H(t)(r − r(t − τ)),
// the equation whose Floquet multipliers `sdm` computes.
// Real cutters (docs/physics.md §8, docs/time_domain.md "Real cutters"):
// each tooth is N_z axial slices (TimeDomainOptions::axial_slices; with one
// helix angle, automatically, the closed-form integral along the edge), each a
// straight tooth at φ_j(t, z) with its own delay τ_j(z) and the static chip
// of Process::static_chip_m (pitch, runout), ramping in and out of the arc;
// plus the process damping −(C_pd/V) dz (n·ṙ) n of each cutting slice
// (turning: −(C_pd/V) a ṙ_x). With a variable pitch or helix, or runout in
// nonlinear mode, the period is one revolution.
// Spindle speed variation (docs/ssv.md "In the time domain"; Insperger &
// Stépán 2004, Seguy et al. 2010): Ω(t) = Ω₀ (1 + R_VA sin(R_VF Ω₀ t)); the
// tooth angles follow θ(t) = ∫Ω, each delay τ(t) solves θ(t) − θ(t − τ) =
// the constant-speed delay angle, V in C_pd/V follows Ω(t), and the period
// is sdm's principal period p T_m = q T_F (speed_variation_period).
//
// Integrator: SUNDIALS CVODE, variable-order Adams–Moulton (order <= 5) with
// fixed-point iteration — the structural modes are lightly damped and not
// stiff, so no Jacobian or linear solve is needed, and CVODE's root finding
// stops the integration exactly where a tooth leaves or re-enters the cut
// (docs/time_domain.md says why CVODE rather than ARKODE). SUNDIALS has no
// delays: the delayed relative displacement comes from a history ring buffer
// holding about one delay of samples (r, ṙ, r̈ at a uniform grid plus every
// event), interpolated by quintic Hermite polynomials (order 6 >= the
// integrator's order 5). Memory does not grow with simulated time.
// Discontinuities are stop points, never stepped across: tooth entry and exit
// (milling), the start of the cut and its delay-propagated images t = kτ
// (k <= 6, after which the jump is in a derivative above the method's order),
// and — nonlinear mode — the instants t_r a chip thickness crosses zero and
// their delay images t_r + kτ (k <= 2; k <= 3 with multiple regeneration,
// where the surface keeps the kink). The integrator restarts at each of them.
//
// Thread safety: the simulator and the lobe solver are immutable after
// construction; simulate() allocates its own SUNDIALS context, so several
// threads may call it at once.
#pragma once

#include <complex>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <functional>
#include <vector>

#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/results.hpp"  // SimulationResult
#include "chatter/structural_model.hpp"

namespace chatter {

/// The range of TimeDomainOptions::periods (the lobe search's periods per
/// verdict): fewer than 20 leave too little to analyse, more than 1e5 is an
/// hour per speed. One range for the option, the CLI and Python.
inline constexpr int kMinVerdictPeriods = 20;
inline constexpr int kMaxVerdictPeriods = 100000;

/// The feed's part of the "no cut" rule (docs/results.md): a nonlinear run
/// (the chip clipped at zero) at feed 0 has no static chip; its growth
/// measures the clipping of a perturbation, not the cut. Refused by
/// SimulationSettings and TimeDomainOptions validation.
inline constexpr std::string_view kNoChipFeed =
    "feed 0: no static chip, so no cut to judge (a nonlinear simulation needs a feed > 0; "
    "the linear mode asks the stability question without one)";

struct TimeDomainOptions {
  /// CVODE relative tolerance (in [1e-12, 1e-2]). The absolute tolerance is
  /// relative_tolerance × a displacement scale (the static deflection of the
  /// static chip force, or the initial perturbation in linear mode), and that
  /// scale × ω_i for the modal velocities.
  double relative_tolerance = 1e-7;
  /// History samples per delay period (>= 8) ...
  int samples_per_period = 64;
  /// ... and per period of the highest natural frequency (>= 8): the sample
  /// spacing is τ / M with M the smallest integer meeting both.
  int samples_per_vibration_cycle = 32;
  /// Largest number of history samples per delay (guards memory at very low
  /// speed; a run needing more is refused with an InputError).
  int max_samples_per_period = 200000;
  /// Largest number of integrator steps in one simulation.
  long max_steps = 20000000;

  // --- lobes by simulation (TimeDomainSolver) ---
  /// Delay periods simulated per verdict, in [kMinVerdictPeriods,
  /// kMaxVerdictPeriods] (the registry's `periods` option takes the same
  /// range). The last half is analysed.
  /// Counted in tooth periods: a run whose period is one revolution (variable
  /// pitch or helix, runout) simulates max(20, ⌈periods / N_t⌉) revolutions.
  int periods = 200;
  /// Deepest cut searched, m (> 0). Limits above it are reported as +inf.
  double depth_max_m = 0.05;
  /// Relative width of the final depth bracket (in (0, 0.5)).
  double depth_tolerance = 0.01;
  /// Feed per tooth (milling) or per revolution (turning), m (>= 0), used by
  /// the lobe search; only sets the amplitude at which the tool leaves the cut.
  double feed_m = 1e-4;
  /// Multiple regeneration in the lobe search.
  bool multiple_regeneration = false;
  /// Lobe search in linear mode (verdict from the growth factor).
  bool linear = false;

  // --- real cutters (last, so that positional initialisers keep working) ---
  /// Axial slices N_z of the cut (real cutters, docs/time_domain.md "Real
  /// cutters"): each tooth is N_z straight slices of height a/N_z at the
  /// midpoints z = (s + ½) a/N_z, each at its own angle φ_j(t, z) and delay
  /// τ_j(z). 0 = automatic: with one helix angle (no profile, runout or
  /// multiple regeneration) the exact, closed-form integral along each
  /// tooth's edge (docs/time_domain.md "The exact edge"; the slices' limit),
  /// 20 slices for the other helical cutters, 1 otherwise. An explicit value
  /// (1 … 1000) also sends a straight, equally spaced cutter through the
  /// per-tooth path (its tables then differ from the uniform path's by the
  /// integration tolerance only). Cost: the right-hand side grows as N_t N_z.
  int axial_slices = 0;

  /// Empty string when valid, else the violated rule (Ceres-style).
  std::string validate() const;
};

/// One simulation run.
struct SimulationSettings {
  double spindle_rpm = 0.0;   ///< > 0.
  double depth_m = 0.0;       ///< >= 0 (axial depth for milling, width of cut for turning).
  /// Periods to simulate (>= 4): tooth periods, or revolutions with a
  /// variable pitch or helix or (nonlinear mode) runout.
  int periods = 200;
  /// Feed per tooth (milling) or per revolution (turning), m (>= 0).
  /// Ignored in linear mode.
  double feed_m = 1e-4;
  bool linear = false;
  /// Linear mode only: keep the static chip (f_j sin φ + ρ_j − ρ_{j−1},
  /// never clipped), so that the run converges to the linear forced
  /// response of chatter/forced.hpp instead of measuring the growth of a
  /// perturbation. The run then starts at rest (unless the feed is 0), is
  /// not rescaled, and its growth and verdict come from the once-per-period
  /// increments, as in nonlinear mode.
  bool linear_static_chip = false;
  bool multiple_regeneration = false;
  /// Initial condition. Default: at rest (nonlinear mode; the static chip
  /// starts the motion) or, in linear mode, every modal displacement set so
  /// that the relative displacement is 1 µm along each direction the cut
  /// sees. When `initial_state` is non-empty it is [q; q̇] (2n, modal
  /// coordinates in the order of modal_matrices(): tool modes first) and the
  /// history before t = 0 is held at the initial displacement.
  std::vector<double> initial_state;
  /// Record the time series (every history sample). Lobe searches turn it off.
  bool record_series = true;
  /// Analyse the last `analysed_fraction` of the periods (in (0, 1]).
  double analysed_fraction = 0.5;
  /// Called at the end of every period with the run so far: `series` (with
  /// record_series) and `once_per_period` up to now, `periods` the total
  /// asked; no spectrum, verdict or growth yet (a live plot: the CLI's
  /// simulate --show). Empty: not called. Cost: the call itself; a caller
  /// that redraws should throttle by time.
  std::function<void(const SimulationResult& so_far)> on_period;
  /// Stop as soon as the run has settled into its periodic forced response
  /// (nonlinear mode, or linear with the static chip): the once-per-period
  /// increments below the verdict's floor (1e4 × relative_tolerance of the
  /// state) for kQuietPeriods periods in a row, after at least
  /// kMinPeriodsBeforeStop periods. The verdict is then "stable (periodic)",
  /// the one the whole run would reach (a periodic attractor stays), and
  /// `periods` counts the periods simulated. The lobe search sets it: most
  /// of its runs below the limit settle in a fraction of their periods.
  bool stop_when_periodic = false;
};

// What a run returns (SimulationResult, SeriesSample, SpectralPeak,
// SimulationVerdict) is plain data in chatter/results.hpp, so that the io
// layer can write and draw it without this header.

/// The period of a simulation (s) at `rpm` (rev/min): one tooth period for
/// a uniform cutter (and turning: one revolution); one revolution with
/// variable pitch or helix, or with runout in nonlinear mode (`linear` false),
/// since the chips then repeat once per revolution only. With spindle speed
/// variation (process.speed_variation, docs/ssv.md) the principal period of
/// the modulated equation, p T_m = q T_F (speed_variation_period: sdm's),
/// usually several revolutions. Periods, the once-per-period samples and
/// growth_per_period of a run are per this.
double simulation_period_s(const Process& process, double rpm, bool linear);

/// Periods of that length in one revolution: N_t for a uniform milling
/// cutter, 1 when the period is a revolution (and in turning). What
/// `--revolutions` is multiplied by. 0 with speed variation (a period of
/// several revolutions): see simulation_periods_in_revolutions.
int simulation_periods_per_revolution(const Process& process, double rpm, bool linear);

/// The periods of a run of `revolutions` (>= 1) revolutions: revolutions ×
/// simulation_periods_per_revolution; with speed variation the fewest whole
/// principal periods that hold them (at least 4, the fewest a run takes).
int simulation_periods_in_revolutions(const Process& process, double rpm, bool linear, int revolutions);

/// The periods a run takes by default: 200 (tooth periods, or revolutions
/// for a cutter whose period is one); with speed variation as many whole
/// principal periods as hold 200 tooth periods, at least 20 (the lobe
/// search's rule, TimeDomainOptions::periods).
int default_simulation_periods(const Process& process, double rpm, bool linear);

class TimeDomainSimulator {
 public:
  /// @throws InputError if the options are invalid or both bodies are rigid.
  TimeDomainSimulator(StructuralModel model, Process process, TimeDomainOptions options = {});

  /// One run. @throws InputError on rpm <= 0, depth < 0, periods < 4, a
  /// negative feed, a wrong-sized initial state, a speed needing more than
  /// max_samples_per_period samples, or runout with speed variation outside
  /// the homogeneous linear mode; NumericalError if CVODE fails.
  /// With speed variation a nonlinear run that settles while the tool
  /// leaves the cut costs one more (linear) run (docs/ssv.md).
  SimulationResult simulate(const SimulationSettings& settings) const;
  /// A front end's check before it reports one run as a verdict on the cut
  /// (`chatter simulate`, Python's simulate): @throws InputError with the
  /// process's no_chip_reason (no edge engaged at the depth, a depth of 0)
  /// or kNoChipFeed. The lobe search does not call it: a depth at which no
  /// edge engages is a stable point of its search.
  void require_chip(const SimulationSettings& settings) const;

  const StructuralModel& model() const { return model_; }
  const Process& process() const { return process_; }
  const TimeDomainOptions& options() const { return options_; }

 private:
  StructuralModel model_;
  Process process_;
  TimeDomainOptions options_;
};

/// Lobes by simulation: per speed, the depth where the verdict changes from
/// stable to chatter (scan upward by factors of 2 from 1/16 of the
/// zeroth-order estimate, then bisection to depth_tolerance). Cost: about
/// 10–14 simulations of options.periods periods per speed.
class TimeDomainSolver final : public LobeSolver {
 public:
  /// `starting_guess`: a cheaper solver whose limit at each speed places the
  /// first depth of the search (only where the scan starts, not the answer).
  /// Null: built here, once, on the same model and process (depth_max_m of
  /// these options): sdm for a helical cutter (it sees the helix; its limit
  /// is the linear limit, so the search brackets it by 10 %, growing, and
  /// its runs use 12 axial slices when axial_slices is automatic: about 3×
  /// faster on the issue-27 cutter, docs/performance.md), else the
  /// zeroth-order analytic solver (the wide scan below); when the analytic
  /// method does not apply to the model (or refuses the process), the search
  /// has no guess.
  TimeDomainSolver(StructuralModel model, Process process, TimeDomainOptions options = {},
                   std::shared_ptr<const LobeSolver> starting_guess = nullptr);
  std::string method() const override { return "time-domain"; }
  /// verdict_run() at the point: stable, growth_per_period and the dominant
  /// multiplier (if measured), the dominant frequency (if found),
  /// floquet_period_s; extra: verdict, verdict_measure, max_amplitude_mm,
  /// out_of_cut_fraction, periods. Defined with the registry entry (factory.cpp).
  PointAnalysis analyse_point(SpindleSpeed speed, double depth_m) const override;
  /// The midpoint of the final bracket; `lobe` = floor(f_c τ), branch −1.
  /// With sdm's guess (a helical cutter) the search starts at the guess and
  /// brackets by 1.1, 1.21, 1.46, ... up or down. Otherwise it
  /// starts at 1/16 of the guess's bounded limit (capped at
  /// depth_max_m), or of depth_max_m/4 without a guess, where the guess finds
  /// no limit, or where it refuses the speed (its InputError, e.g. too many
  /// lobes in one delay for the analytic phase search at very low speed).
  StabilityLimit limit_at(SpindleSpeed speed) const override;
  /// The guess solver in use, null if none.
  const LobeSolver* starting_guess() const { return starting_guess_.get(); }
  double depth_max_m() const override { return simulator_.options().depth_max_m; }
  const TimeDomainSimulator& simulator() const { return simulator_; }
  /// The verdict run used for one (speed, depth) point of the search.
  SimulationResult verdict_run(double spindle_rpm, double depth_m) const;

 private:
  TimeDomainSimulator simulator_;
  std::shared_ptr<const LobeSolver> starting_guess_;
  /// The default guess is sdm's (a helical cutter): bracket it narrowly.
  bool floquet_guess_ = false;
  /// The search's runs with fewer slices (a helical cutter, axial_slices
  /// automatic); null: simulator_.
  std::shared_ptr<const TimeDomainSimulator> search_simulator_;
};

}  // namespace chatter
