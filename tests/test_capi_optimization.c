/* Drives the optimisation part of the C API from C (include/chatter/chatter.h,
 * "Process optimisation"; docs/c_api.md, docs/optimization.md): the index
 * names, the source study's removal rate and its table 14 loss from measured
 * indices, the optimum, the adaptive loop stepped by hand as a machine
 * controller would (converging within 30 steps), and the error paths.
 * Prints "N passed, M failed". */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "chatter/chatter.h"

#include "capi_check.h"

/* The number of "key" at `indent` spaces in a JSON text written with an
 * indent of 2 (top level: 2; in an object of the top level: 4), or NAN. */
static double json_number_at(const char* json, const char* key, int indent) {
  char pattern[128];
  const char* at;
  snprintf(pattern, sizeof pattern, "\n%*s\"%s\": ", indent, "", key);
  at = strstr(json, pattern);
  if (!at) return NAN;
  return strtod(at + strlen(pattern), NULL);
}
static double json_number(const char* json, const char* key) { return json_number_at(json, key, 2); }

static char* record(chatter_status (*call)(const chatter_optimizer*, char*, size_t, size_t*),
                    const chatter_optimizer* o) {
  size_t length = 0;
  char* text;
  if (call(o, NULL, 0, &length) != CHATTER_OK) return NULL;
  text = (char*)malloc(length + 1);
  if (text && call(o, text, length + 1, &length) != CHATTER_OK) {
    free(text);
    return NULL;
  }
  return text;
}

int main(void) {
  const char* seed = CHATTER_SOURCE_DIR "/configs/turning_seed003_shaft.toml";
  const char* lobes_only = CHATTER_SOURCE_DIR "/configs/seed_turning_1dof.toml";
  chatter_model* model = NULL;
  chatter_model* plain = NULL;
  chatter_optimizer* opt = NULL;
  chatter_optimizer* none = NULL;
  chatter_adapt_state state, next;
  double measured[CHATTER_INDEX_COUNT];
  double optimum_loss, last_loss = NAN;
  size_t length = 0, i;
  char* json;
  char buffer[16384];
  int k, converged_at = 0;

  CHECK(chatter_model_load(seed, &model) == CHATTER_OK);
  CHECK(chatter_optimizer_create(model, NULL, NAN, &opt) == CHATTER_OK);
  if (!opt) {
    fprintf(stderr, "no optimizer: %s\n", chatter_last_error());
    return 1;
  }
  CHECK(strcmp(chatter_optimizer_index_name(opt, 0), "diametral_error_um") == 0);
  CHECK(strcmp(chatter_optimizer_index_name(opt, 2), "removal_rate_mm3_per_s") == 0);
  CHECK(strcmp(chatter_optimizer_index_name(opt, 5), "force_n") == 0);
  CHECK(chatter_optimizer_index_name(opt, CHATTER_INDEX_COUNT) == NULL);

  /* Removal 1750 mm^3/s at 200 m/min, 0.35 mm/rev, 1.5 mm; table 14's loss. */
  CHECK(chatter_performance_json(opt, 200.0, 0.35, 1.5, NULL, buffer, sizeof buffer, &length) == CHATTER_OK);
  CHECK(length < sizeof buffer);
  CHECK(fabs(json_number(buffer, "removal_rate_mm3_per_s") - 1750.0) < 1e-6);
  for (i = 0; i < CHATTER_INDEX_COUNT; ++i) measured[i] = NAN;
  measured[0] = 55.83, measured[1] = 6.40, measured[2] = 1750, measured[3] = 0.80, measured[4] = 75.68;
  CHECK(chatter_performance_json(opt, 200.0, 0.35, 1.5, measured, buffer, sizeof buffer, &length) == CHATTER_OK);
  CHECK(fabs(json_number(buffer, "loss") - 16.01) < 0.02);
  CHECK(strstr(buffer, "\"feasible\": false") != NULL);
  CHECK(chatter_last_warning_count() == 0);
  /* A cutting speed typed in m/s warns under the CLI's flag name, in
     chatter_last_warning and in the record (chatter.h). */
  CHECK(chatter_performance_json(opt, 3.3, 0.35, 1.5, NULL, buffer, sizeof buffer, &length) == CHATTER_OK);
  CHECK(chatter_last_warning_count() == 1 &&
        strstr(chatter_last_warning(0), "cutting_speed_m_per_min = 3.3: outside the 5 to 3 000 m/min") != NULL);
  CHECK(strstr(buffer, "cutting_speed_m_per_min = 3.3: outside") != NULL);

  /* The optimum. */
  json = record(chatter_optimize_json, opt);
  CHECK(json != NULL);
  if (json) {
    CHECK(strstr(json, "\"found\": true") != NULL);
    CHECK(strstr(json, "\"format\": \"chatter-optimize\"") != NULL);
    optimum_loss = json_number_at(json, "loss", 4); /* the optimum's (the one nested record) */
    CHECK(optimum_loss > 5.0 && optimum_loss < 7.13);
    free(json);
  } else {
    optimum_loss = NAN;
  }

  /* The controller's loop: the plant is the model itself (measured = the
   * performance record's indices at the set-point). */
  CHECK(chatter_adapt_start(opt, 200.0, 0.35, NAN, &state) == CHATTER_OK);
  CHECK(fabs(state.depth_mm - 1.5) < 1e-12);
  CHECK(state.iteration == 0 && state.correction[0] == 1.0);
  for (k = 1; k <= 30; ++k) {
    CHECK(chatter_performance_json(opt, state.speed, state.feed_mm, state.depth_mm, NULL, buffer, sizeof buffer,
                                   &length) == CHATTER_OK);
    for (i = 0; i < CHATTER_INDEX_COUNT; ++i) measured[i] = json_number(buffer, chatter_optimizer_index_name(opt, i));
    if (chatter_adapt_step(opt, &state, measured, NAN, NAN, &next) != CHATTER_OK) {
      fprintf(stderr, "step %d: %s\n", k, chatter_last_error());
      ++failed;
      break;
    }
    last_loss = next.loss;
    state = next; /* next may also be &state */
    if (state.converged && !converged_at) converged_at = k;
  }
  CHECK(state.iteration == 30);
  CHECK(converged_at > 0 && converged_at <= 30);
  CHECK(fabs(last_loss - optimum_loss) <= 0.05 * optimum_loss);
  CHECK(chatter_adapt_step(opt, &state, measured, 0.95, 10.0, &state) == CHATTER_OK);
  CHECK(state.iteration == 31);

  /* Errors: a message naming the argument and the rule. */
  CHECK(chatter_performance_json(opt, -1.0, 0.35, 1.5, NULL, buffer, sizeof buffer, &length) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "speed") != NULL);
  CHECK(chatter_adapt_step(opt, &state, measured, 1.5, NAN, &next) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "gamma") != NULL);
  CHECK(chatter_adapt_step(opt, NULL, measured, NAN, NAN, &next) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_optimizer_create(NULL, NULL, NAN, &none) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_optimizer_create(model, "no-such-method", NAN, &none) == CHATTER_INPUT_ERROR);
  CHECK(chatter_optimizer_create(model, NULL, 500.0, &none) == CHATTER_INPUT_ERROR); /* beyond the 80 mm shaft */
  CHECK(chatter_model_load(lobes_only, &plain) == CHATTER_OK);
  CHECK(chatter_optimizer_create(plain, NULL, NAN, &none) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "[optimization]") != NULL);
  CHECK(none == NULL);

  chatter_optimizer_free(opt);
  chatter_optimizer_free(NULL);
  chatter_model_free(model);
  chatter_model_free(plain);
  printf("%d passed, %d failed\n", passed, failed);
  return failed ? 1 : 0;
}
