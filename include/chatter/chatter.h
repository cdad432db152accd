/* chatter C API: stability lobes for post-processors written in C, C#,
 * Python (ctypes) or anything else with a C FFI.
 *
 * Handles are opaque. Every function returns a chatter_status; on anything
 * other than CHATTER_OK, chatter_last_error() returns a message naming the
 * file, key or argument and the rule that was broken. The message is kept
 * per thread (thread-local), so two threads never see each other's errors.
 *
 * Units: spindle speed rev/min, depth mm, frequency Hz (shop units).
 *
 * Thread safety: a chatter_model and a chatter_solver are immutable once
 * created; any number of threads may call chatter_limit_at /
 * chatter_lobe_table / chatter_find_robust_speed on the same solver at once. Creating and freeing are
 * not synchronised: do not free a handle another thread is using.
 */
#ifndef CHATTER_CHATTER_H
#define CHATTER_CHATTER_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum chatter_status {
  CHATTER_OK = 0,
  CHATTER_INTERNAL_ERROR = 1, /* a numerical or system failure: report it */
  CHATTER_INPUT_ERROR = 2,    /* bad config, option or argument: see chatter_last_error() */
  CHATTER_NULL_ARGUMENT = 3   /* a required pointer argument was NULL */
} chatter_status;

typedef struct chatter_model chatter_model;   /* structure + process, from a TOML config */
typedef struct chatter_solver chatter_solver; /* a lobe solver built on a model */

/* The stability limit at one spindle speed. */
typedef struct chatter_limit {
  double spindle_rpm;          /* rev/min */
  double depth_limit_mm;       /* largest stable depth, mm; HUGE_VAL (+inf) when bounded == 0 */
  double chatter_frequency_hz; /* Hz; 0 when bounded == 0 */
  int lobe;                    /* lobe number k >= 0; -1 when bounded == 0 */
  int bounded;                 /* 1: a limit exists below the searched depth; 0: stable up to it */
} chatter_limit;

/* Library version, "MAJOR.MINOR.PATCH". Never NULL. */
const char* chatter_version(void);

/* Message of the last failed call on this thread ("" if none). Valid until
 * the next chatter_* call on the same thread. Never NULL. */
const char* chatter_last_error(void);

/* Plausibility warnings of the last call on this thread about its numeric
 * arguments: a value that is accepted but lies outside what machining
 * usually sees (docs/results.md, rule 2), e.g. a depth typed in metres:
 * "depth_mm = 0.0015: outside the 0.01 to 100 mm of a depth of cut; is it in
 * m (depth_mm = 1.5)?". The same bands and
 * text as the CLI's flags and Python's keywords (arguments named as the CLI
 * flags: rpm, depth_mm, feed_per_tooth_mm, ...). Every chatter_* call clears
 * them; a call that fails has none. How many, and the i-th (valid until the
 * next chatter_* call on the thread; NULL when i >= the count). The JSON
 * records (chatter_point_json, chatter_performance_json) also carry them in
 * their "warnings". */
size_t chatter_last_warning_count(void);
const char* chatter_last_warning(size_t i);

/* Reads and validates a TOML config (docs/config.md). *out is set only on
 * success; free it with chatter_model_free. */
chatter_status chatter_model_load(const char* config_path, chatter_model** out);
/* Same from TOML text; `origin` names it in messages (may be NULL). */
chatter_status chatter_model_parse(const char* toml_text, const char* origin, chatter_model** out);
void chatter_model_free(chatter_model* model);
/* Plausibility warnings of the model's config (values that load but lie
 * outside what machining usually sees, docs/config.md): how many, and the
 * i-th as "<file>: <key path> = <value>: <what is odd; did you mean ...?>",
 * valid while the model lives (NULL when model is NULL or i >= the count). */
size_t chatter_model_warning_count(const chatter_model* model);
const char* chatter_model_warning(const chatter_model* model, size_t i);

/* The methods this build provides (the solver registry), in a fixed order:
 * how many, and the i-th name (static storage; NULL when i >= the count). */
size_t chatter_method_count(void);
const char* chatter_method_name(size_t i);

/* Builds a solver. method: "auto" (or NULL: the default of every interface:
 * turning "analytic", milling "sdm", or "analytic" when sdm does not handle
 * the model, e.g. measured FRFs; chatter_solver_method says which) or one of
 * chatter_method_name(), e.g. "analytic", "coupled", "sdm"
 * (semi-discretisation: Floquet, flip lobes; ~2 ms per speed) or
 * "time-domain" (simulation; ~0.3 s per speed). A method that does not
 * handle the model fails with CHATTER_INPUT_ERROR naming the method and what
 * it lacks. depth_max_mm: deepest cut searched (> 0); limits above it are
 * unbounded. */
chatter_status chatter_solver_create(const chatter_model* model, const char* method, double depth_max_mm,
                                     chatter_solver** out);
/* As chatter_solver_create, with the method's tuning options (the CLI's
 * --NAME flags, Python's options=) as "name=value" items separated by commas,
 * e.g. "collocation=3" (sdm: Gauss collocation, docs/sdm.md) or "steps=128";
 * a flag as its name alone; NULL or "" for none. An option the method does
 * not have, a value of the wrong kind or out of its range fails with
 * CHATTER_INPUT_ERROR naming the option and the rule. */
chatter_status chatter_solver_create_with_options(const chatter_model* model, const char* method,
                                                  double depth_max_mm, const char* options, chatter_solver** out);
void chatter_solver_free(chatter_solver* solver);
/* The method the solver uses ("auto" resolved), valid while the solver
 * lives; NULL when solver is NULL. */
const char* chatter_solver_method(const chatter_solver* solver);

/* `chatter point` (docs/results.md): the limit at one speed (the lobe-table
 * row) and the method's own analysis at the asked depth, each in its own
 * fields. Strings are static; NAN where the method gives no value. */
typedef struct chatter_point_result {
  chatter_limit limit;              /* the lobe-table row at the speed: depth limit, chatter frequency, lobe */
  const char* multiplier_type;      /* at the limit: "hopf", "flip", "fold" (sdm); "" when the method gives none */
  double depth_mm;                  /* as asked */
  int stable;                       /* 1: stable at depth_mm (the method's own verdict, else depth < limit) */
  double margin;                    /* depth_limit_mm / depth_mm; HUGE_VAL when limit.bounded == 0 */
  double tooth_passing_hz;          /* N * N_t / 60, whatever the pitch */
  double tooth_period_s;            /* 1 / tooth_passing_hz */
  double floquet_period_s;          /* the period multipliers refer to; 0 when the method has none */
  double spectral_radius;           /* at depth_mm (sdm): max |mu|, < 1 stable */
  double growth_per_period;         /* at depth_mm (time-domain): measured |mu| */
  double dominant_multiplier_re;    /* the dominant multiplier mu at depth_mm */
  double dominant_multiplier_im;
  double dominant_frequency_hz;     /* the frequency of its vibration at depth_mm */
  const char* dominant_multiplier_type;  /* at depth_mm: "hopf", "flip", "fold"; "" when none */
} chatter_point_result;

/* One operating point (spindle_rpm in (0, 500000], depth_mm in (0, 1000]):
 * the numbers of `chatter point` with the solver's method. */
chatter_status chatter_point(const chatter_solver* solver, double spindle_rpm, double depth_mm,
                             chatter_point_result* out);
/* The same as `chatter point`'s JSON record, text valid until the next
 * chatter_point_json call on this thread. */
chatter_status chatter_point_json(const chatter_solver* solver, double spindle_rpm, double depth_mm,
                                  const char** json);

/* Stability limit at one spindle speed (rev/min > 0). */
chatter_status chatter_limit_at(const chatter_solver* solver, double spindle_rpm, chatter_limit* out);

/* Limits at `points` speeds evenly spaced from rpm_min to rpm_max, both
 * included (points >= 2, 0 < rpm_min < rpm_max). `rows` must hold `points`
 * entries. */
chatter_status chatter_lobe_table(const chatter_solver* solver, double rpm_min, double rpm_max, int points,
                                  chatter_limit* rows);

/* A robust spindle speed: the one in [rpm_min, rpm_max] whose worst limit
 * over spindle_rpm * (1 +/- speed_tolerance_pct/100) is largest (a spindle
 * never runs exactly at its set speed), and the stable pocket around it at
 * depth_mm. */
typedef struct chatter_robust_speed {
  chatter_limit limit;          /* exact at the chosen speed (limit.spindle_rpm) */
  double speed_tolerance_pct;   /* as asked */
  double worst_limit_mm;        /* smallest limit over the band; HUGE_VAL: none below the searched depth */
  double worst_margin;          /* worst_limit_mm / depth_mm (> 1) */
  double pocket_min_rpm;        /* the connected interval around the speed where limit > depth, */
  double pocket_max_rpm;        /* searched inside [rpm_min, rpm_max] (an end: the pocket goes on) */
  int found;                    /* 1: set; 0: no speed in range is stable over the whole band */
} chatter_robust_speed;

/* The robust speed for a cut depth_mm deep (> 0), 0 <= speed_tolerance_pct
 * < 50 (0: the highest cusp, held exactly). A few tens of solves plus about
 * 8 per lobe in the range. out->found = 0 (and CHATTER_OK) when no speed is
 * stable over the whole band at that depth. */
chatter_status chatter_find_robust_speed(const chatter_solver* solver, double rpm_min, double rpm_max,
                                         double depth_mm, double speed_tolerance_pct,
                                         chatter_robust_speed* out);

/* --- Tool position (docs/position.md) ---------------------------------
 * A structure that changes along the part (a `cantilever` workpiece mode:
 * a bar clamped at one end; or `[[positions]]`: mode sets along the path).
 * Positions in mm: from the clamp of the cantilever, or along the path of
 * [[positions]]. A config without either fails with CHATTER_INPUT_ERROR. */

/* The position range of the model's part, mm (clamp to free end, or first
 * to last [[positions]]). Both outputs are set only on success. */
chatter_status chatter_model_position_range(const chatter_model* model, double* min_mm, double* max_mm);

/* A new model: `model` with the structure the tool sees at position_mm (the
 * process and everything else as in `model`). Solvers built on it give the
 * numbers of the CLI's `--position-mm` (its `chatter lobes`, `point`,
 * `check`). An end typed in mm snaps to the end of the part. Fails with
 * CHATTER_INPUT_ERROR and the CLI's message naming `position_mm` when the
 * position is outside the part ("position_mm = 600: outside the part
 * [0, 500] mm (clamp to free end of workpiece.modes[0].cantilever)") or the
 * config has no position-dependent structure. *out is set only on success;
 * free it with chatter_model_free. Cost: a copy of the model, O(modes). */
chatter_status chatter_model_at_position(const chatter_model* model, double position_mm, chatter_model** out);

/* One row of a lobe surface: the limit at one (position, speed). */
typedef struct chatter_surface_row {
  double position_mm;   /* mm; the `position_mm` column of `chatter surface` */
  chatter_limit limit;  /* as chatter_limit_at on chatter_model_at_position(position_mm) */
} chatter_surface_row;

/* The lobe surface of `chatter surface`: position_points (>= 2) positions
 * evenly spaced from position_min_mm to position_max_mm (both included,
 * inside the part, max > min) times rpm_points (>= 2) speeds evenly spaced
 * from rpm_min to rpm_max (both included, 0 < rpm_min < rpm_max).
 * rows[p * rpm_points + s] is position p, speed s: `rows` must hold
 * position_points * rpm_points entries, in the CSV's order. method and
 * depth_max_mm as chatter_solver_create (the method's default options).
 * threads: positions shared among this many threads (0 = every core; the
 * numbers do not depend on it). Every position is checked before any solve;
 * on an error `rows` may be partly written. Cost: per position one solver
 * build plus rpm_points limits (analytic: a 50 x 200 surface of a 2-mode
 * turning case takes ~0.1 s on one core; sdm: ~2 ms a limit). */
chatter_status chatter_lobe_surface(const chatter_model* model, const char* method, double depth_max_mm,
                                    double position_min_mm, double position_max_mm, int position_points,
                                    double rpm_min, double rpm_max, int rpm_points, int threads,
                                    chatter_surface_row* rows);


/* ================================================================ uncertainty
 * Monte Carlo over the config's [uncertainty] spreads (docs/uncertainty.md),
 * the numbers of `chatter lobes --samples N --seed S`: N models drawn from
 * the spreads (truncated normal, |z| <= 3), each solved at every speed with
 * the same method and options. Same seed, same numbers, whatever `threads`
 * (and the same as the CLI's JSON to its 10 digits; bitwise the same doubles
 * as Python's chatter.uncertain_lobes). */

/* One speed of the Monte Carlo lobes. Depths in mm; HUGE_VAL where no
 * chatter below depth_max_mm (the nominal limit) or where that many samples
 * find none (a quantile). */
typedef struct chatter_uncertain_row {
  double spindle_rpm;
  double depth_limit_mm;      /* the nominal model's limit (as chatter_lobe_table) */
  double depth_limit_p05_mm;  /* 5 % of the samples chatter below it: 95 % stable below */
  double depth_limit_p50_mm;  /* the median limit */
  double depth_limit_p95_mm;  /* 95 % of the samples chatter below it */
} chatter_uncertain_row;

/* The quantile lobes at rpm_points (>= 2) speeds evenly spaced from rpm_min
 * to rpm_max (both included, 0 < rpm_min < rpm_max); `rows` must hold
 * rpm_points entries. method ("auto" or NULL: the CLI's default) and
 * depth_max_mm as chatter_solver_create (the method's default options);
 * samples in [1, 1e6] with samples x rpm_points <= 25e6; seed any value;
 * threads: samples shared among this many threads (0 = every core). Fails
 * with CHATTER_INPUT_ERROR when the config has no [uncertainty] table or its
 * spreads do not suit the model. Cost: samples x (one solver build +
 * rpm_points limits). */
chatter_status chatter_uncertain_lobes(const chatter_model* model, const char* method, double depth_max_mm,
                                       double rpm_min, double rpm_max, int rpm_points, int samples,
                                       unsigned long long seed, int threads, chatter_uncertain_row* rows);

/* The probability that one operation is stable: the fraction of `samples`
 * models (drawn as above) whose limit at spindle_rpm lies above depth_mm
 * (rev/min in (0, 500000], mm in (0, 1000]), in [0, 1] and a multiple of
 * 1/samples; the value `chatter lobes --samples` plots at that point. */
chatter_status chatter_probability_stable(const chatter_model* model, const char* method, double depth_max_mm,
                                          double spindle_rpm, double depth_mm, int samples, unsigned long long seed,
                                          int threads, double* probability);

/* ====================================================================== grinding
 * Robotic grinding at controlled power (docs/grinding.md; docs/c_api.md,
 * "Grinding"): a config with a [grinding] table (configs/grinding_*.toml),
 * read on each call (no handle). The lobe functions above refuse such a
 * config. Units: W, mm, mm^3/s, N, J/mm^3, s, m/s. Same status codes and
 * chatter_last_error() as above; thread-safe (each call reads its own files).
 */

typedef enum chatter_grinding_target {
  CHATTER_GRINDING_POWER_W = 0,          /* value: useful grinding power, W */
  CHATTER_GRINDING_DEPTH_MM = 1,         /* value: target maximum depth of the groove, mm */
  CHATTER_GRINDING_REMOVAL_MM3_PER_S = 2, /* value: target removal rate, mm^3/s */
  /* Not a target: makes the enum int-sized so any int a caller passes is a
   * representable value (it is refused with CHATTER_INPUT_ERROR). */
  CHATTER_GRINDING_TARGET_FORCE_INT = 0x7fffffff
} chatter_grinding_target;

/* What a power set-point gives (or the power of a target), as `chatter grind
 * predict`. The has_* flags say which optional groups are set (0: those
 * fields are 0). */
typedef struct chatter_grinding_prediction {
  double power_w;                   /* the power (given, or found for the target) */
  double removal_rate_mm3_per_s;
  double max_depth_mm;              /* h0, the groove's maximum depth */
  double groove_width_mm;
  double depth_per_pass_mm;         /* removal / (feed x wheel width) */
  double tangential_force_n;        /* P / V_c */
  double normal_force_n;            /* F_T / force_ratio */
  double specific_energy_j_per_mm3; /* P / removal */
  double contact_duration_s;        /* one impact */
  double cutting_speed_m_per_s;
  int has_mechanistic;              /* seed 001's model: the next three */
  double friction_power_w, chip_power_w, impacts_per_turn;
  int has_energy_partition;         /* [grinding.energy_partition]: the next two */
  double energy_partition, heat_into_part_w;
  int has_empirical_removal, has_empirical_normal_force, has_empirical_wear;
  double empirical_removal_rate_mm3_per_s, empirical_normal_force_n, empirical_wear_rate_mm3_per_s;
  size_t warning_count;             /* the config's and the prediction's warnings (their text: the JSON) */
} chatter_grinding_prediction;

/* Predicts at a power (target CHATTER_GRINDING_POWER_W), or finds the power
 * of a target depth or removal (those need the mechanistic model).
 * CHATTER_INPUT_ERROR on a bad config or value (power <= 0, a depth beyond
 * the wheel radius, ...). */
chatter_status chatter_grinding_predict(const char* config_path, chatter_grinding_target target, double value,
                                        chatter_grinding_prediction* out);

/* The same as the JSON record of `chatter grind predict --json`, written into
 * buffer (at most size bytes, NUL-terminated, truncated when too short);
 * *length (may be NULL) receives the record's full length in bytes, without
 * the NUL. buffer may be NULL with size 0 to ask the length. */
chatter_status chatter_grinding_predict_json(const char* config_path, chatter_grinding_target target, double value,
                                             char* buffer, size_t size, size_t* length);

#define CHATTER_GRINDING_MAX_COEFFICIENTS 10

/* One fitted target of `chatter grind fit`: coefficients in the config's
 * units and order (mechanistic: edge_coefficient_n_per_mm,
 * cutting_coefficient_n_per_mm2; empirical: docs/grinding.md's term order;
 * power_law: C, b1, b2, b3, with C's standard error that of ln C). */
typedef struct chatter_grinding_fit_result {
  size_t count;                     /* coefficients set below */
  double coefficients[CHATTER_GRINDING_MAX_COEFFICIENTS];
  double standard_error[CHATTER_GRINDING_MAX_COEFFICIENTS];
  double lower_95[CHATTER_GRINDING_MAX_COEFFICIENTS], upper_95[CHATTER_GRINDING_MAX_COEFFICIENTS];
  int tests, degrees_of_freedom;
  double r_squared, rmse, mae, mape_percent;  /* rmse, mae in the target's unit: W, mm^3/s or N */
} chatter_grinding_fit_result;

/* Fits model ("mechanistic", "poly11", "poly22", "poly33", "power_law",
 * "hahn_lindsay") to a tests table (docs/grinding.md, "grind fit").
 * variable: NULL or "" (the default), "useful_power_w" or "normal_force_n".
 * target: which fit to return: "power_w" (mechanistic), "removal", "wear",
 * "normal_force"; NULL: the first fitted. CHATTER_INPUT_ERROR when the table
 * does not give that target. */
chatter_status chatter_grinding_fit(const char* tests_csv, const char* model, const char* variable, const char* target,
                                    chatter_grinding_fit_result* out);

/* Every fitted target as the JSON record of `chatter grind fit --json`
 * (buffer, size, length as chatter_grinding_predict_json). */
chatter_status chatter_grinding_fit_json(const char* tests_csv, const char* model, const char* variable, char* buffer,
                                         size_t size, size_t* length);
/* --- Forced vibration of a stable cut (docs/forced.md) ---------------
 * Below the stability limit the cutting force still drives the structure:
 * the surface location error (milling), the diametral error (turning), the
 * vibration, and whether a tooth leaves the cut (then the linear limit of
 * the lobes does not hold). The numbers of `chatter forced --json`. */

typedef struct chatter_forced_result {
  int stable;                       /* 1: stable (sdm spectral radius < 1); 0: unstable, no forced response:
                                       every field below but spectral_radius and depth_limit_mm is NaN */
  double spectral_radius;           /* sdm, per Floquet period */
  double depth_limit_mm;            /* sdm depth limit at the speed; HUGE_VAL: none below the searched depth */
  double surface_location_error_um; /* milling: the machined wall's offset, + = material left (the value of
                                       largest magnitude over the wall height); turning: the deflection
                                       along the radius */
  double sle_min_um, sle_max_um;    /* over the wall height (milling); = the SLE in turning */
  double peak_to_peak_x_um, peak_to_peak_y_um;       /* relative vibration over one period */
  double static_deflection_x_um, static_deflection_y_um; /* mean relative displacement */
  double min_chip_thickness_um;     /* smallest linear chip over the teeth and the period */
  double negative_chip_arc_deg;     /* longest arc of one tooth with a negative chip */
  int teeth_leave_cut;              /* 1: that arc exceeds 5 % of the engaged arc */
  int linear_limit_holds;           /* 1: stable and no tooth leaves the cut */
  double diametral_error_um;        /* turning: 2 x the deflection; NaN in milling */
} chatter_forced_result;

/* The forced response at spindle_rpm (> 0) and depth_mm (> 0) with the
 * feed feed_mm (> 0): per tooth in milling, per revolution in turning.
 * CHATTER_OK for an unstable cut too (out->stable = 0). Cost: one sdm
 * analysis and depth-limit search at the speed plus the response (a few
 * ms to a few tens of ms). Thread-safe on the same model. */
chatter_status chatter_forced_response(const chatter_model* model, double spindle_rpm, double depth_mm, double feed_mm,
                                       chatter_forced_result* out);


/* --- The cutting load (docs/cutting_law.md) ------------------------------
 * What one operation asks of the spindle: the numbers `chatter check`
 * reports per row (and `recommend` and `performance` use), from the one
 * cutting law of the engine. */

typedef struct chatter_cutting_load_result {
  double mean_force_n;           /* mean tangential (cutting) force, the teeth's summed, N */
  double torque_nm;              /* mean spindle torque, N m; NaN without a diameter */
  double power_kw;               /* mean cutting power, kW; NaN without a diameter */
  double removal_rate_mm3_per_s; /* material removal rate, mm^3/s; NaN without a diameter */
  double mean_force_x_n, mean_force_y_n; /* mean in-plane force on the tool (model X, Y), N */
  double peak_force_n;           /* largest resultant force over a revolution, N */
} chatter_cutting_load_result;

/* The mean cutting load at spindle_rpm (> 0), depth_mm (> 0) and feed_mm
 * (> 0; per tooth in milling, per revolution in turning) on the model's
 * process. diameter_mm: the tool's (milling) or the workpiece's at the cut
 * (turning), > 0, or NAN for the config's process.tool_diameter_mm /
 * workpiece_diameter_mm (torque, power and removal rate NaN when neither is
 * known). tangential_coefficient_n_per_m2: turning's K_c (> 0), or NAN for
 * the feed-force coefficient K_f as check and recommend use it (an
 * underestimate); must be NAN in milling. Cost: O(1), ~0.1 ms with runout
 * (a sampled revolution) and for the peak force in milling. Thread-safe. */
chatter_status chatter_cutting_load(const chatter_model* model, double spindle_rpm, double depth_mm, double feed_mm,
                                    double diameter_mm, double tangential_coefficient_n_per_m2,
                                    chatter_cutting_load_result* out);

/* --- Process optimisation and adaptive control (docs/optimization.md) -----
 * A config's [optimization] table: the performance indices of a cut (removal
 * rate, diametral error or surface location error, roughness, cost,
 * production rate, force), their weighted loss, the constraints (stability
 * among them), the constrained optimum, and the step of the adaptive loop a
 * machine controller calls after each measurement. Indices are numbered
 * 0..CHATTER_INDEX_COUNT-1 in the order of chatter_optimizer_index_name:
 * 0 diametral_error_um (milling: surface_location_error_um), 1
 * surface_roughness_um, 2 removal_rate_mm3_per_s, 3 cost, 4
 * production_rate_per_h, 5 force_n. Records are the JSON of the CLI's
 * `performance --json` and `optimize --json` (buffer, size, length as
 * chatter_grinding_predict_json). An optimizer is immutable once created
 * but for its caches of solved limits, which are guarded: any number of
 * threads may use one at once. */

#define CHATTER_INDEX_COUNT 6

typedef struct chatter_optimizer chatter_optimizer;

/* The optimisation problem of `model`'s [optimization] (CHATTER_INPUT_ERROR
 * without one). method: NULL or "auto" (analytic for turning, sdm for
 * milling) or a method name. position_mm: the tool position along a
 * position-dependent part, or NAN for the worst over the part. Free it with
 * chatter_optimizer_free. Cost: one lobe solver per position evaluated. */
chatter_status chatter_optimizer_create(const chatter_model* model, const char* method, double position_mm,
                                        chatter_optimizer** out);
void chatter_optimizer_free(chatter_optimizer* optimizer);
/* The name of index i (static storage while the optimizer lives; NULL when
 * i >= CHATTER_INDEX_COUNT or optimizer is NULL). */
const char* chatter_optimizer_index_name(const chatter_optimizer* optimizer, size_t i);

/* Every index, loss term and constraint at (speed, feed_mm, depth_mm): speed
 * is the cutting speed in m/min for turning, the spindle speed in rev/min for
 * milling; feed per revolution (turning) or per tooth (milling). measured:
 * NULL, or CHATTER_INDEX_COUNT values, NAN where not measured (a measured
 * value replaces the model's). */
chatter_status chatter_performance_json(const chatter_optimizer* optimizer, double speed, double feed_mm,
                                        double depth_mm, const double* measured, char* buffer, size_t size,
                                        size_t* length);

/* The constrained optimum of the objective over the bounds (the record of
 * `chatter optimize --json`). Cost: turning ~0.1 s; milling seconds. */
chatter_status chatter_optimize_json(const chatter_optimizer* optimizer, char* buffer, size_t size, size_t* length);

/* The controller's state between two measurements: the set-point to cut
 * (speed as in chatter_performance_json), the model corrections (measured /
 * predicted, 1 = none) and the loss of the last measurement. */
typedef struct chatter_adapt_state {
  double speed;         /* m/min (turning) or rev/min (milling) */
  double feed_mm;       /* per revolution (turning) or per tooth (milling) */
  double depth_mm;
  double correction[CHATTER_INDEX_COUNT];
  int iteration;        /* measurements taken */
  double loss;          /* the last measurement's loss (NAN before the first) */
  int converged;        /* 1: the last step moved less than 0.1 % of the bounds */
} chatter_adapt_state;

/* The first state: the set-point (speed, feed_mm, depth_mm), or the centre
 * of the bounds for any of them given as NAN; no corrections. */
chatter_status chatter_adapt_start(const chatter_optimizer* optimizer, double speed, double feed_mm, double depth_mm,
                                   chatter_adapt_state* out);

/* One step of the loop (docs/optimization.md): measurement holds the
 * CHATTER_INDEX_COUNT indices measured at state's set-point (NAN: not
 * measured); gamma in (0, 1] and max_step_pct in (0, 100] (NAN: the config's
 * [optimization.adapt], else 0.95 and 10). *next receives the corrected
 * models and the set-point to cut next (never one that fails a constraint).
 * next may be state. Cost: one optimisation of the corrected models. */
chatter_status chatter_adapt_step(const chatter_optimizer* optimizer, const chatter_adapt_state* state,
                                  const double* measurement, double gamma, double max_step_pct,
                                  chatter_adapt_state* next);

#ifdef __cplusplus
}
#endif

#endif /* CHATTER_CHATTER_H */
