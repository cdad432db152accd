/* Drives the C API from C: success paths against the C++ results' known
 * values (docs/physics.md case A) and every error path. Prints "N passed, M failed". */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "chatter/chatter.h"

static int passed = 0, failed = 0;
#define CHECK(cond)                                                   \
  do {                                                                \
    if (cond) {                                                       \
      ++passed;                                                       \
    } else {                                                          \
      ++failed;                                                       \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                 \
  } while (0)

int main(void) {
  chatter_model* model = NULL;
  chatter_solver* solver = NULL;
  chatter_limit lim, rows[5];
  const double closed = 2 * 45e6 * 0.033 * 1.033 / 2.4e9 * 1e3; /* mm, case A absolute limit */
  int i;

  CHECK(strlen(chatter_version()) > 0);
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

  printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
