/* Drives the C API from C: success paths against the C++ results' known
 * values (docs/physics.md case A), the tool position against the CLI's
 * `--position-mm` and `chatter surface` output, and every error path.
 * Prints "N passed, M failed". */
#define _POSIX_C_SOURCE 200809L /* popen */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "chatter/chatter.h"

#include "capi_check.h"


/* A limit as the CLI's CSV prints it (%.10g, "inf", empty cells when
 * unbounded): "spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe". */
static void csv_cells(const chatter_limit* l, char* out, size_t size) {
  if (l->bounded)
    snprintf(out, size, "%.10g,%.10g,%.10g,%d", l->spindle_rpm, l->depth_limit_mm, l->chatter_frequency_hz, l->lobe);
  else
    snprintf(out, size, "%.10g,inf,,", l->spindle_rpm);
}

/* The number after "\"key\": " in a JSON text (NaN if absent). */
static double json_number(const char* text, const char* key) {
  char pattern[128];
  const char* at;
  snprintf(pattern, sizeof pattern, "\"%s\": ", key);
  at = text ? strstr(text, pattern) : NULL;
  return at ? strtod(at + strlen(pattern), NULL) : NAN;
}

/* Positions of case B (the 0.5 m cantilever shaft): the model at a position
 * gives the CLI's `--position-mm` numbers, the surface gives `chatter
 * surface`'s table, and bad positions fail with the CLI's message. */
/* chatter_forced_response: the numbers of `chatter forced --json`
 * (docs/forced.md), an unstable cut, and bad arguments. */
static void check_forced(void) {
  chatter_model* model = NULL;
  chatter_forced_result r;
  const char* config = CHATTER_SOURCE_DIR "/configs/milling_variable_pitch_helix.toml";
  CHECK(chatter_model_load(config, &model) == CHATTER_OK);
  CHECK(chatter_forced_response(model, 9000.0, 1.5, 0.05, &r) == CHATTER_OK);
  CHECK(r.stable == 1 && r.spectral_radius < 1.0);
  char* out = run_cli("forced " CHATTER_SOURCE_DIR "/configs/milling_variable_pitch_helix.toml --rpm 9000 "
                      "--depth-mm 1.5 --feed-per-tooth-mm 0.05 --json -");
  CHECK(out != NULL);
  CHECK(out != NULL && json_number(out, "surface_location_error_um") == r.surface_location_error_um);
  CHECK(out != NULL && json_number(out, "spectral_radius") == r.spectral_radius);
  CHECK(out != NULL && json_number(out, "depth_limit_mm") == r.depth_limit_mm);
  CHECK(out != NULL && json_number(out, "min_chip_thickness_um") == r.min_chip_thickness_um);
  CHECK(out != NULL && json_number(out, "negative_chip_arc_deg") == r.negative_chip_arc_deg);
  CHECK(isnan(r.diametral_error_um));
  free(out);
  /* Unstable: CHATTER_OK, stable = 0, no response. */
  CHECK(chatter_forced_response(model, 9000.0, 19.0, 0.05, &r) == CHATTER_OK);
  CHECK(r.stable == 0 && r.spectral_radius >= 1.0 && isnan(r.surface_location_error_um));
  CHECK(r.depth_limit_mm < 19.0);
  CHECK(chatter_forced_response(model, 9000.0, 1.0, -0.05, &r) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "feed_mm") != NULL);
  CHECK(chatter_forced_response(model, 9000.0, 1.0, 0.05, NULL) == CHATTER_NULL_ARGUMENT);
  chatter_model_free(model);
  /* Turning: the diametral error 2 delta. */
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml", &model) == CHATTER_OK);
  CHECK(chatter_forced_response(model, 1000.0, 0.5, 0.1, &r) == CHATTER_OK && r.stable == 1);
  CHECK(fabs(r.diametral_error_um - 2.0 * r.surface_location_error_um) <= 1e-12 * r.diametral_error_um);
  chatter_model_free(model);
}

/* chatter_cutting_load: the cutting law's closed forms (docs/cutting_law.md)
 * on the variable-pitch helix cutter (K_t 600 N/mm^2, a_e 6 mm of a 12 mm
 * tool, 4 teeth): MRR = a a_e f N_t N / 60, power = K_t x MRR, torque =
 * power / Omega; turning case A with K_f as the cutting pressure (check's
 * rule) and with K_c; bad arguments. */
static void check_cutting_load(void) {
  chatter_model* model = NULL;
  chatter_cutting_load_result r;
  const double pi = 3.14159265358979323846;
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/milling_variable_pitch_helix.toml", &model) == CHATTER_OK);
  CHECK(chatter_cutting_load(model, 9000.0, 2.0, 0.05, NAN, NAN, &r) == CHATTER_OK);
  const double mrr = 2.0 * 6.0 * 0.05 * 4 * 9000.0 / 60.0; /* 360 mm^3/s */
  CHECK(fabs(r.removal_rate_mm3_per_s - mrr) <= 1e-12 * mrr);
  CHECK(fabs(r.power_kw - 600.0 * mrr * 1e-6) <= 1e-12 * r.power_kw);
  CHECK(fabs(r.torque_nm - r.power_kw * 1e3 / (2 * pi * 9000.0 / 60.0)) <= 1e-12 * r.torque_nm);
  CHECK(r.peak_force_n > hypot(r.mean_force_x_n, r.mean_force_y_n));
  /* A given diameter scales the width cut (a_e = 0.5 D): 24 mm doubles it. */
  chatter_cutting_load_result w;
  CHECK(chatter_cutting_load(model, 9000.0, 2.0, 0.05, 24.0, NAN, &w) == CHATTER_OK);
  CHECK(fabs(w.removal_rate_mm3_per_s - 2.0 * mrr) <= 1e-12 * mrr);
  CHECK(chatter_cutting_load(model, 9000.0, 2.0, 0.05, NAN, 2e9, &r) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "only for turning") != NULL);
  CHECK(chatter_cutting_load(model, 9000.0, -2.0, 0.05, NAN, NAN, &r) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "depth_mm") != NULL);
  CHECK(chatter_cutting_load(model, 9000.0, 2.0, 0.05, 0.0, NAN, &r) == CHATTER_INPUT_ERROR);
  CHECK(chatter_cutting_load(model, 9000.0, 2.0, 0.05, NAN, NAN, NULL) == CHATTER_NULL_ARGUMENT);
  chatter_model_free(model);
  /* Turning case A (K_f = 2.4e9 N/m^2, no workpiece diameter in the config:
   * torque, power and removal need one). */
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml", &model) == CHATTER_OK);
  CHECK(chatter_cutting_load(model, 1800.0, 2.0, 0.2, NAN, NAN, &r) == CHATTER_OK);
  CHECK(isnan(r.power_kw) && isnan(r.torque_nm) && isnan(r.removal_rate_mm3_per_s));
  const double kf = 2.4e9;
  CHECK(fabs(r.mean_force_x_n + 2e-3 * kf * 0.2e-3) <= 1e-12 * 2e-3 * kf * 0.2e-3); /* the in-plane -a K_f f */
  CHECK(r.mean_force_y_n == 0.0);
  CHECK(chatter_cutting_load(model, 1800.0, 2.0, 0.2, 50.0, NAN, &r) == CHATTER_OK);
  const double v = pi * 0.05 * 1800.0 / 60.0;
  CHECK(fabs(r.power_kw - kf * 2e-3 * 0.2e-3 * v * 1e-3) <= 1e-12 * r.power_kw);
  CHECK(chatter_cutting_load(model, 1800.0, 2.0, 0.2, 50.0, 2e9, &r) == CHATTER_OK);
  CHECK(fabs(r.power_kw - 2e9 * 2e-3 * 0.2e-3 * v * 1e-3) <= 1e-12 * r.power_kw);
  CHECK(fabs(r.torque_nm - 2e9 * 2e-3 * 0.2e-3 * 0.025) <= 1e-12 * r.torque_nm);
  CHECK(fabs(r.removal_rate_mm3_per_s - 2.0 * 0.2 * v * 1e3) <= 1e-12 * r.removal_rate_mm3_per_s);
  chatter_model_free(model);
}

static void check_position(void) {
  const char* config = CHATTER_SOURCE_DIR "/configs/coupled_tool1_workpiece1.toml";
  chatter_model *model = NULL, *at = NULL, *plain = NULL;
  chatter_solver* solver = NULL;
  chatter_limit rows[7], lim;
  chatter_surface_row surface[3 * 7];
  char args[1024], cells[256], *out, *line;
  double lo = -1, hi = -1;
  int i;

  CHECK(chatter_model_load(config, &model) == CHATTER_OK);
  CHECK(chatter_model_position_range(model, &lo, &hi) == CHATTER_OK);
  CHECK(lo == 0.0 && hi == 500.0);

  /* lobes --position-mm 250: each row equal to the CLI's CSV cell for cell. */
  CHECK(chatter_model_at_position(model, 250.0, &at) == CHATTER_OK && at != NULL);
  CHECK(chatter_solver_create(at, "analytic", 20.0, &solver) == CHATTER_OK);
  CHECK(chatter_lobe_table(solver, 500.0, 10000.0, 7, rows) == CHATTER_OK);
  snprintf(args, sizeof args,
           "lobes '%s' --position-mm 250 --rpm-min 500 --rpm-max 10000 --rpm-points 7 --depth-max-mm 20 --table -",
           config);
  out = run_cli(args);
  CHECK(out != NULL);
  if (out) {
    line = strtok(out, "\n"); /* header */
    for (i = 0; i < 7; ++i) {
      line = strtok(NULL, "\n");
      csv_cells(&rows[i], cells, sizeof cells);
      CHECK(line != NULL && strcmp(line, cells) == 0);
      if (line && strcmp(line, cells) != 0) fprintf(stderr, "  CLI: %s\n  API: %s\n", line, cells);
    }
    free(out);
  }
  /* point --position-mm 250 writes full doubles: bitwise equal. */
  CHECK(chatter_limit_at(solver, 3000.0, &lim) == CHATTER_OK && lim.bounded);
  snprintf(args, sizeof args, "point '%s' --position-mm 250 --rpm 3000 --depth-mm 1 --depth-max-mm 20", config);
  out = run_cli(args);
  CHECK(out != NULL && json_number(out, "depth_limit_mm") == lim.depth_limit_mm);
  CHECK(out != NULL && json_number(out, "chatter_frequency_hz") == lim.chatter_frequency_hz);
  CHECK(out != NULL && json_number(out, "position_mm") == 250.0);
  if (out && json_number(out, "depth_limit_mm") != lim.depth_limit_mm)
    fprintf(stderr, "  CLI depth %.17g, API %.17g\n", json_number(out, "depth_limit_mm"), lim.depth_limit_mm);
  free(out);
  chatter_solver_free(solver);
  /* At 250 mm the shaft is stiffer than at its free end (stiffness / phi^2,
   * phi < 1): the limit there is at least the free end's. */
  CHECK(chatter_solver_create(model, "analytic", 20.0, &solver) == CHATTER_OK);
  {
    chatter_limit free_end;
    CHECK(chatter_limit_at(solver, 3000.0, &free_end) == CHATTER_OK);
    CHECK(lim.depth_limit_mm >= free_end.depth_limit_mm);
  }
  chatter_solver_free(solver);
  chatter_model_free(at);

  /* The surface: 3 positions x 7 speeds, equal to `chatter surface`'s CSV
   * (position_mm first, then the lobes cells), for 1 and 2 threads. */
  CHECK(chatter_lobe_surface(model, "analytic", 20.0, 100.0, 500.0, 3, 500.0, 10000.0, 7, 2, surface) == CHATTER_OK);
  snprintf(args, sizeof args,
           "surface '%s' --position-min-mm 100 --position-max-mm 500 --position-points 3 --rpm-min 500 "
           "--rpm-max 10000 --rpm-points 7 --depth-max-mm 20 --table - -q",
           config);
  out = run_cli(args);
  CHECK(out != NULL);
  if (out) {
    char expected[300];
    line = strtok(out, "\n");
    CHECK(line && strcmp(line, "position_mm,spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe") == 0);
    for (i = 0; i < 3 * 7; ++i) {
      line = strtok(NULL, "\n");
      csv_cells(&surface[i].limit, cells, sizeof cells);
      snprintf(expected, sizeof expected, "%.10g,%s", surface[i].position_mm, cells);
      CHECK(line != NULL && strcmp(line, expected) == 0);
      if (line && strcmp(line, expected) != 0) fprintf(stderr, "  CLI: %s\n  API: %s\n", line, expected);
    }
    CHECK(strtok(NULL, "\n") == NULL);
    free(out);
  }
  {
    /* Each surface block is the lobe table of the model at that position. */
    chatter_surface_row one[3 * 7];
    CHECK(chatter_lobe_surface(model, NULL, 20.0, 100.0, 500.0, 3, 500.0, 10000.0, 7, 1, one) == CHATTER_OK);
    CHECK(memcmp(one, surface, sizeof one) == 0);
    CHECK(chatter_model_at_position(model, 300.0, &at) == CHATTER_OK);
    CHECK(chatter_solver_create(at, NULL, 20.0, &solver) == CHATTER_OK);
    CHECK(chatter_lobe_table(solver, 500.0, 10000.0, 7, rows) == CHATTER_OK);
    for (i = 0; i < 7; ++i)
      CHECK(one[7 + i].position_mm == 300.0 && memcmp(&one[7 + i].limit, &rows[i], sizeof rows[i]) == 0);
    chatter_solver_free(solver);
    chatter_model_free(at);
  }

  /* Bad positions: the CLI's message (naming the argument, not the flag). */
  at = NULL;
  CHECK(chatter_model_at_position(model, 600.0, &at) == CHATTER_INPUT_ERROR && at == NULL);
  CHECK(strcmp(chatter_last_error(),
               "position_mm = 600: outside the part [0, 500] mm (clamp to free end of workpiece.modes[0].cantilever)") ==
        0);
  CHECK(chatter_model_at_position(model, NAN, &at) == CHATTER_INPUT_ERROR && at == NULL);
  CHECK(chatter_model_at_position(model, -1.0, &at) == CHATTER_INPUT_ERROR);
  CHECK(chatter_model_at_position(NULL, 1.0, &at) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_lobe_surface(model, NULL, 20.0, 100.0, 700.0, 3, 500.0, 10000.0, 7, 1, surface) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "position_max_mm = 700: outside the part [0, 500] mm") != NULL);
  CHECK(chatter_lobe_surface(model, NULL, 20.0, 300.0, 100.0, 3, 500.0, 10000.0, 7, 1, surface) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "position_max_mm = 100: must be > position_min_mm (300)") != NULL);
  CHECK(chatter_lobe_surface(model, NULL, 20.0, 100.0, 500.0, 1, 500.0, 10000.0, 7, 1, surface) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "position_points = 1: must be >= 2") != NULL);
  CHECK(chatter_lobe_surface(model, NULL, 20.0, 100.0, 500.0, 3, 500.0, 10000.0, 1, 1, surface) == CHATTER_INPUT_ERROR);
  CHECK(chatter_lobe_surface(model, NULL, 20.0, 100.0, 500.0, 3, 500.0, 10000.0, 7, -1, surface) == CHATTER_INPUT_ERROR);
  CHECK(chatter_lobe_surface(model, "nonsense", 20.0, 100.0, 500.0, 3, 500.0, 10000.0, 7, 1, surface) ==
        CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "nonsense") != NULL);
  CHECK(chatter_lobe_surface(model, NULL, 20.0, 100.0, 500.0, 3, 500.0, 10000.0, 7, 1, NULL) == CHATTER_NULL_ARGUMENT);
  /* The same message as the CLI gives for --position-mm 600 (after its flag). */
  snprintf(args, sizeof args, "'%s' lobes '%s' --position-mm 600 --table - 2>&1 >/dev/null", CHATTER_CLI, config);
  {
    FILE* p = popen(args, "r");
    char err[512] = {0};
    CHECK(p != NULL);
    if (p) {
      CHECK(fgets(err, sizeof err, p) != NULL);
      CHECK(pclose(p) != 0);
      CHECK(strstr(err, "--position-mm = 600: outside the part [0, 500] mm (clamp to free end of "
                        "workpiece.modes[0].cantilever)") != NULL);
    }
  }
  chatter_model_free(model);

  /* A config without a position-dependent structure. */
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml", &plain) == CHATTER_OK);
  CHECK(chatter_model_at_position(plain, 10.0, &at) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "position_mm: ") == chatter_last_error() &&
        strstr(chatter_last_error(), "seed_turning_1dof.toml: the structure does not depend on the position") != NULL);
  CHECK(chatter_model_position_range(plain, &lo, &hi) == CHATTER_INPUT_ERROR);
  CHECK(chatter_lobe_surface(plain, NULL, 20.0, 0.0, 1.0, 3, 500.0, 10000.0, 7, 1, surface) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "does not depend on the position") != NULL);
  chatter_model_free(plain);
}

/* The Monte Carlo of case A with spreads (configs/seed_turning_1dof_uncertain.toml):
 * the quantile lobes equal `chatter lobes --samples 20 --seed 3`'s table
 * cell for cell, the probability of stability its probability table at
 * every grid point, for 1 and 2 threads; the errors name the rule. */
static void check_uncertainty(void) {
  const char* config = CHATTER_SOURCE_DIR "/configs/seed_turning_1dof_uncertain.toml";
  const char* table = "/tmp/chatter_test_capi_probability.csv";
  chatter_model* model = NULL;
  chatter_model* plain = NULL;
  chatter_uncertain_row rows[3];
  char args[1024], expected[256], got[256];
  char *out, *line, *save = NULL;
  int threads, i, compared = 0;
  double p;
  FILE* f;
  CHECK(chatter_model_load(config, &model) == CHATTER_OK);
  snprintf(args, sizeof args,
           "lobes '%s' --samples 20 --seed 3 --rpm-min 500 --rpm-max 1500 --rpm-points 3 --depth-max-mm 20 "
           "--table - --probability-table %s --depth-points 5",
           config, table);
  out = run_cli(args);
  CHECK(out != NULL);
  for (threads = 1; threads <= 2 && out; ++threads) {
    CHECK(chatter_uncertain_lobes(model, NULL, 20.0, 500.0, 1500.0, 3, 20, 3, threads, rows) == CHATTER_OK);
    line = strtok_r(out, "\n", &save); /* the header */
    for (i = 0; i < 3; ++i) {
      line = strtok_r(NULL, "\n", &save);
      /* spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe,p05,p50,p95 */
      snprintf(got, sizeof got, "%.10g,%.10g", rows[i].spindle_rpm, rows[i].depth_limit_mm);
      CHECK(line && strncmp(line, got, strlen(got)) == 0);
      snprintf(got, sizeof got, ",%.10g,%.10g,%.10g", rows[i].depth_limit_p05_mm, rows[i].depth_limit_p50_mm,
               rows[i].depth_limit_p95_mm);
      CHECK(line && strlen(line) > strlen(got) && strcmp(line + strlen(line) - strlen(got), got) == 0);
    }
    free(out);
    out = threads == 1 ? run_cli(args) : NULL;
  }
  /* The probability table: spindle_rpm,depth_mm,probability_stable. */
  f = fopen(table, "r");
  CHECK(f != NULL);
  if (f) {
    double rpm, depth, prob;
    CHECK(fgets(expected, sizeof expected, f) != NULL); /* the header */
    while (fscanf(f, "%lf,%lf,%lf", &rpm, &depth, &prob) == 3) {
      if (depth <= 0.0) continue; /* the C API asks a depth > 0 */
      CHECK(chatter_probability_stable(model, "analytic", 20.0, rpm, depth, 20, 3, 0, &p) == CHATTER_OK);
      CHECK(p == prob);
      ++compared;
    }
    fclose(f);
    remove(table);
  }
  CHECK(compared == 12);
  /* Errors: no [uncertainty] table, bad samples, bad speeds. */
  CHECK(chatter_uncertain_lobes(model, NULL, 20.0, 500.0, 1500.0, 3, 0, 3, 1, rows) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "samples = 0: must be in [1, 1000000]") != NULL);
  CHECK(chatter_probability_stable(model, NULL, 20.0, 1000.0, -1.0, 20, 3, 1, &p) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "depth_mm") != NULL);
  CHECK(chatter_uncertain_lobes(model, NULL, 20.0, 1500.0, 500.0, 3, 20, 3, 1, rows) == CHATTER_INPUT_ERROR);
  CHECK(chatter_uncertain_lobes(model, NULL, 20.0, 500.0, 1500.0, 3, 20, 3, 1, NULL) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml", &plain) == CHATTER_OK);
  CHECK(chatter_probability_stable(plain, NULL, 20.0, 1000.0, 1.0, 20, 3, 1, &p) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "no [uncertainty] table") != NULL);
  chatter_model_free(plain);
  chatter_model_free(model);
  (void)expected;
}

/* The time-domain solver takes the chip's feed from the config's
 * [process] feed_per_tooth_mm as the CLI does (the C API used to build it
 * with the solver's own default): above the limit the saturated vibration
 * scales with the feed, so max_amplitude_mm of chatter_point_json equals
 * `chatter point --method time-domain` bitwise, and a CLI feed 10x smaller
 * gives a 10x smaller amplitude (so the check can tell them apart). */
static void check_time_domain_feed(void) {
  const char* config = CHATTER_SOURCE_DIR "/tests/data/capi/time_domain_feed.toml";
  chatter_model* model = NULL;
  chatter_solver* solver = NULL;
  const char* json = NULL;
  char args[1024];
  char* out;
  double api, cli, small;
  CHECK(chatter_model_load(config, &model) == CHATTER_OK);
  CHECK(chatter_solver_create(model, "time-domain", 50.0, &solver) == CHATTER_OK);
  CHECK(chatter_point_json(solver, 9000.0, 14.0, &json) == CHATTER_OK);
  api = json_number(json, "max_amplitude_mm");
  snprintf(args, sizeof args, "point '%s' --method time-domain --rpm 9000 --depth-mm 14", config);
  out = run_cli(args);
  cli = json_number(out, "max_amplitude_mm");
  free(out);
  snprintf(args, sizeof args, "point '%s' --method time-domain --rpm 9000 --depth-mm 14 --feed-per-tooth-mm 0.02",
           config);
  out = run_cli(args);
  small = json_number(out, "max_amplitude_mm");
  free(out);
  CHECK(api > 0.0 && api == cli);
  if (api != cli) fprintf(stderr, "  time-domain max_amplitude_mm: API %.17g, CLI %.17g\n", api, cli);
  CHECK(fabs(small / cli - 0.1) < 1e-3);
  chatter_solver_free(solver);
  chatter_model_free(model);
}

/* chatter_solver_create_with_options: sdm's collocation gives the CLI's
 * `point --collocation 3` limit bitwise, no options is chatter_solver_create,
 * and every bad option fails naming it. */
static void check_options(void) {
  const char* config = CHATTER_SOURCE_DIR "/configs/milling_benchmark_ae005_down.toml";
  chatter_model* model = NULL;
  chatter_model* turning = NULL;
  chatter_solver* solver = NULL;
  chatter_limit coll, plain, none;
  char args[1024];
  char* out;
  CHECK(chatter_model_load(config, &model) == CHATTER_OK);
  CHECK(chatter_solver_create_with_options(model, "sdm", 10.0, " collocation = 3 ", &solver) == CHATTER_OK);
  CHECK(chatter_limit_at(solver, 16000.0, &coll) == CHATTER_OK);
  chatter_solver_free(solver);
  snprintf(args, sizeof args, "point '%s' --method sdm --collocation 3 --rpm 16000 --depth-mm 1 --depth-max-mm 10",
           config);
  out = run_cli(args);
  CHECK(out != NULL && json_number(out, "depth_limit_mm") == coll.depth_limit_mm);
  CHECK(out != NULL && json_number(out, "chatter_frequency_hz") == coll.chatter_frequency_hz);
  free(out);
  CHECK(chatter_solver_create(model, "sdm", 10.0, &solver) == CHATTER_OK);
  CHECK(chatter_limit_at(solver, 16000.0, &plain) == CHATTER_OK);
  chatter_solver_free(solver);
  CHECK(chatter_solver_create_with_options(model, "sdm", 10.0, NULL, &solver) == CHATTER_OK);
  CHECK(chatter_limit_at(solver, 16000.0, &none) == CHATTER_OK);
  chatter_solver_free(solver);
  CHECK(none.depth_limit_mm == plain.depth_limit_mm);
  CHECK(coll.depth_limit_mm != plain.depth_limit_mm && fabs(coll.depth_limit_mm / plain.depth_limit_mm - 1.0) < 2e-3);
  solver = NULL;
  CHECK(chatter_solver_create_with_options(model, "sdm", 10.0, "collocation=9", &solver) == CHATTER_INPUT_ERROR);
  CHECK(solver == NULL && strstr(chatter_last_error(), "collocation") && strstr(chatter_last_error(), "[0, 3]"));
  CHECK(chatter_solver_create_with_options(model, "sdm", 10.0, "colocation=3", &solver) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "unknown option \"colocation\"") != NULL);
  CHECK(chatter_solver_create_with_options(model, "sdm", 10.0, "collocation=three", &solver) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "must be an integer") != NULL);
  CHECK(chatter_solver_create_with_options(model, "sdm", 0.0, "collocation=3", &solver) == CHATTER_INPUT_ERROR);
  CHECK(chatter_solver_create_with_options(NULL, "sdm", 10.0, "collocation=3", &solver) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/turning_insert_lead_angle.toml", &turning) == CHATTER_OK);
  CHECK(chatter_solver_create_with_options(turning, "sdm", 10.0, "collocation=3", &solver) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "is turning with a nose radius") != NULL);
  chatter_model_free(turning);
  chatter_model_free(model);
}

/* Numeric arguments outside their usual band are named as the CLI's flags
 * and Python's keywords name them (one check, unusual_arguments): a depth
 * typed in metres warns with the unit it meant, in chatter_last_warning and
 * in the JSON record's warnings, with the band's text the CLI prints; every
 * call clears them, a usual call has none, a failed call none. */
static void check_argument_warnings(void) {
  chatter_model* model = NULL;
  chatter_solver* solver = NULL;
  chatter_point_result pr;
  chatter_limit lim;
  chatter_cutting_load_result load;
  const char* json = NULL;
  char args[1024];
  char* out;
  size_t i;
  int kf = 0;
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml", &model) == CHATTER_OK);
  CHECK(chatter_solver_create(model, "analytic", 20.0, &solver) == CHATTER_OK);
  CHECK(chatter_last_warning_count() == 0);
  CHECK(chatter_point(solver, 1800.0, 0.0015, &pr) == CHATTER_OK);
  CHECK(chatter_last_warning_count() == 1);
  CHECK(chatter_last_warning(0) != NULL &&
        strcmp(chatter_last_warning(0),
               "depth_mm = 0.0015: outside the 0.01 to 100 mm of a depth of cut; is it in m (depth_mm = 1.5)?") == 0);
  CHECK(chatter_last_warning(1) == NULL);
  CHECK(chatter_point_json(solver, 1800.0, 0.0015, &json) == CHATTER_OK);
  CHECK(strstr(json, "\"depth_mm = 0.0015: outside the 0.01 to 100 mm of a depth of cut") != NULL);
  snprintf(args, sizeof args, "point '%s' --rpm 1800 --depth-mm 0.0015", CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml");
  out = run_cli(args);
  CHECK(out != NULL && strstr(out, "0.0015: outside the 0.01 to 100 mm of a depth of cut; is it in m") != NULL);
  free(out);
  CHECK(chatter_limit_at(solver, 1800.0, &lim) == CHATTER_OK && chatter_last_warning_count() == 0);
  CHECK(chatter_limit_at(solver, 300000.0, &lim) == CHATTER_OK && chatter_last_warning_count() == 1);
  CHECK(strstr(chatter_last_warning(0), "rpm = 300000: outside the 10 to 200 000 rev/min") != NULL);
  CHECK(chatter_point(solver, -5.0, 1.0, &pr) == CHATTER_INPUT_ERROR && chatter_last_warning_count() == 0);
  /* cutting load: a feed typed in um, and the law's own warning (K_f as the
     cutting pressure when turning gets no tangential coefficient) */
  CHECK(chatter_cutting_load(model, 1800.0, 1.0, 200.0, NAN, NAN, &load) == CHATTER_OK);
  CHECK(chatter_last_warning_count() == 2);
  for (i = 0; i < chatter_last_warning_count(); ++i)
    if (strstr(chatter_last_warning(i), "feed-force coefficient K_f")) ++kf;
  CHECK(kf == 1);
  CHECK(strstr(chatter_last_warning(0), "feed_mm_per_rev = 200: outside the 0.001 to 1 mm") != NULL);
  chatter_solver_free(solver);
  chatter_model_free(model);
}

int main(void) {
  chatter_model* model = NULL;
  chatter_solver* solver = NULL;
  chatter_limit lim, rows[5];
  const double closed = 2 * 45e6 * 0.033 * 1.033 / 2.4e9 * 1e3; /* mm, case A absolute limit */
  int i;

  CHECK(strlen(chatter_version()) > 0);
  check_time_domain_feed();
  check_options();
  check_argument_warnings();
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml", &model) == CHATTER_OK);
  CHECK(chatter_solver_create(model, "analytic", 20.0, &solver) == CHATTER_OK);
  CHECK(chatter_limit_at(solver, 1800.0, &lim) == CHATTER_OK);
  CHECK(lim.bounded == 1 && fabs(lim.depth_limit_mm - 2.974523725) < 1e-6 && lim.lobe == 3);
  CHECK(chatter_lobe_table(solver, 50.0, 2000.0, 5, rows) == CHATTER_OK);
  for (i = 0; i < 5; ++i) CHECK(rows[i].bounded && rows[i].depth_limit_mm >= closed * (1 - 1e-9));
  CHECK(rows[0].spindle_rpm == 50.0 && rows[4].spindle_rpm == 2000.0);
  {
    /* Robust speed, case A at 2 mm, +/-2 %: every speed of the band (sampled
       every 0.01 %) is stable and the pocket holds the band. */
    chatter_robust_speed rs;
    chatter_limit band;
    double n, worst = HUGE_VAL;
    int k;
    CHECK(chatter_find_robust_speed(solver, 50.0, 2000.0, 2.0, 2.0, &rs) == CHATTER_OK);
    CHECK(rs.found == 1 && rs.worst_margin > 1.0 && rs.speed_tolerance_pct == 2.0);
    n = rs.limit.spindle_rpm;
    CHECK(n >= 50.0 && n <= 2000.0 && fabs(n - 1922.2) > 19.0); /* not the cusp */
    CHECK(rs.pocket_min_rpm <= n * 0.98 * (1 + 2e-4) && rs.pocket_max_rpm >= n * 1.02 * (1 - 2e-4));
    for (k = 0; k <= 400; ++k) {
      CHECK(chatter_limit_at(solver, n * (0.98 + 0.04 * k / 400.0), &band) == CHATTER_OK);
      if (band.depth_limit_mm < worst) worst = band.depth_limit_mm;
    }
    CHECK(worst > 2.0 && rs.worst_limit_mm <= worst * (1 + 1e-9) && rs.worst_limit_mm >= worst * 0.99);
    CHECK(chatter_find_robust_speed(solver, 50.0, 2000.0, 10.0, 2.0, &rs) == CHATTER_OK && rs.found == 0);
    CHECK(chatter_find_robust_speed(solver, 50.0, 2000.0, 2.0, -1.0, &rs) == CHATTER_INPUT_ERROR);
    CHECK(strstr(chatter_last_error(), "speed_tolerance_pct") != NULL);
    CHECK(chatter_find_robust_speed(solver, 50.0, 2000.0, 2.0, 2.0, NULL) == CHATTER_NULL_ARGUMENT);
  }
  chatter_solver_free(solver);

  /* Shallow search: unbounded everywhere. */
  CHECK(chatter_solver_create(model, "coupled", 0.5, &solver) == CHATTER_OK);
  CHECK(chatter_limit_at(solver, 1000.0, &lim) == CHATTER_OK);
  CHECK(lim.bounded == 0 && isinf(lim.depth_limit_mm) && lim.lobe == -1);
  chatter_solver_free(solver);

  /* The Floquet solver through the same handle: case A's limit at 3000 rev/min
   * is 2.2048 mm (sdm, within 0.5 % of the exact transfer-function value). */
  CHECK(chatter_solver_create(model, "sdm", 20.0, &solver) == CHATTER_OK);
  CHECK(chatter_limit_at(solver, 3000.0, &lim) == CHATTER_OK);
  CHECK(lim.bounded && fabs(lim.depth_limit_mm - 2.2048) < 0.01);
  chatter_solver_free(solver);

  /* Error paths: status, message, no crash. */
  CHECK(chatter_solver_create(model, "nonsense", 20.0, &solver) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "nonsense") != NULL);
  CHECK(strstr(chatter_last_error(), "--") == NULL); /* library messages name no CLI flag */
  /* The registry's methods: each builds on case A (turning, modes). */
  CHECK(chatter_method_count() >= 4);
  CHECK(chatter_method_name(chatter_method_count()) == NULL);
  for (i = 0; i < (int)chatter_method_count(); ++i) {
    CHECK(chatter_method_name((size_t)i) != NULL);
    CHECK(chatter_solver_create(model, chatter_method_name((size_t)i), 20.0, &solver) == CHATTER_OK);
    chatter_solver_free(solver);
  }
  CHECK(chatter_solver_create(model, NULL, -1.0, &solver) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "depth_max_mm") != NULL);
  CHECK(chatter_solver_create(NULL, NULL, 1.0, &solver) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_solver_create(model, NULL, 20.0, &solver) == CHATTER_OK);
  CHECK(chatter_limit_at(solver, -5.0, &lim) == CHATTER_INPUT_ERROR);
  CHECK(chatter_lobe_table(solver, 100.0, 50.0, 5, rows) == CHATTER_INPUT_ERROR);
  CHECK(chatter_lobe_table(solver, 50.0, 100.0, 1, rows) == CHATTER_INPUT_ERROR);
  CHECK(chatter_limit_at(solver, 1000.0, NULL) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_limit_at(solver, 1000.0, &lim) == CHATTER_OK && strlen(chatter_last_error()) == 0);
  chatter_solver_free(solver);
  chatter_model_free(model);

  model = NULL;
  CHECK(chatter_model_load("/nonexistent/config.toml", &model) == CHATTER_INPUT_ERROR && model == NULL);
  CHECK(strstr(chatter_last_error(), "/nonexistent/config.toml") != NULL);
  CHECK(chatter_model_parse("[process]\noperation = \"turning\"\n", "inline.toml", &model) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "inline.toml") != NULL);
  CHECK(chatter_model_load(NULL, &model) == CHATTER_NULL_ARGUMENT);

  /* Plausibility warnings: none for a shipped config, one naming the unit
   * mistake for a stiffness of 20 N/m (20 N/um meant). */
  CHECK(chatter_model_load(CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml", &model) == CHATTER_OK);
  CHECK(chatter_model_warning_count(model) == 0 && chatter_model_warning(model, 0) == NULL);
  chatter_model_free(model);
  CHECK(chatter_model_parse("[process]\noperation = \"turning\"\nfeed_force_coefficient_n_per_m2 = 2.4e9\n"
                            "[[tool.modes]]\nfrequency_hz = 100\ndamping_ratio = 0.03\nstiffness_n_per_m = 20\n",
                            "k20.toml", &model) == CHATTER_OK);
  CHECK(chatter_model_warning_count(model) == 1);
  CHECK(chatter_model_warning(model, 0) != NULL &&
        strstr(chatter_model_warning(model, 0), "k20.toml: tool.modes[0].stiffness_n_per_m = 20: ") != NULL &&
        strstr(chatter_model_warning(model, 0), "did you mean N/um (stiffness_n_per_um = 20)?") != NULL);
  CHECK(chatter_model_warning(model, 1) == NULL && chatter_model_warning(NULL, 0) == NULL);
  CHECK(chatter_model_warning_count(NULL) == 0);
  chatter_model_free(model);

  check_position();
  check_forced();
  check_cutting_load();
  check_uncertainty();

  printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
