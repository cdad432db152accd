/* Drives the grinding part of the C API from C (include/chatter/chatter.h,
 * "grinding"; docs/c_api.md): seed 001's numbers at 1000 W, the inverse
 * mode, the JSON record against the CLI's, the fit of the synthetic tests,
 * and the error paths. Prints "N passed, M failed". */
#define _POSIX_C_SOURCE 200809L /* popen */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "chatter/chatter.h"

#include "capi_check.h"

/* The seeds print 3 significant digits: half a unit of the last one. */
#define NEAR(a, b, tol) (fabs((a) - (b)) <= (tol))


int main(void) {
  const char* scompi = CHATTER_SOURCE_DIR "/configs/grinding_scompi_ch4.toml";
  const char* tests = CHATTER_SOURCE_DIR "/examples/grinding/scompi_tests_synthetic.csv";
  const char* printed = CHATTER_SOURCE_DIR "/examples/grinding/underwater_tests_seed000.csv";
  chatter_grinding_prediction p;
  chatter_grinding_fit_result f;
  size_t length = 0;
  char* json;
  char* cli;
  char args[1024];

  /* Seed 001 ch. 4 at 1000 W: 52.2 mm^3/s, 0.101 mm, 477 / 523 W. */
  CHECK(chatter_grinding_predict(scompi, CHATTER_GRINDING_POWER_W, 1000.0, &p) == CHATTER_OK);
  CHECK(NEAR(p.removal_rate_mm3_per_s, 52.2, 0.05));
  CHECK(NEAR(p.max_depth_mm, 0.101, 0.0005));
  CHECK(p.has_mechanistic == 1);
  CHECK(NEAR(p.friction_power_w, 477.0, 0.5));
  CHECK(NEAR(p.chip_power_w, 523.0, 0.5));
  CHECK(NEAR(p.friction_power_w + p.chip_power_w, 1000.0, 1e-9));
  CHECK(p.has_energy_partition == 1 && p.energy_partition > 0.0 && p.energy_partition < 1.0);
  CHECK(p.has_empirical_removal == 0);
  /* Inverse: the power of that depth. */
  {
    chatter_grinding_prediction q;
    CHECK(chatter_grinding_predict(scompi, CHATTER_GRINDING_DEPTH_MM, p.max_depth_mm, &q) == CHATTER_OK);
    CHECK(NEAR(q.power_w, 1000.0, 1e-6));
  }
  /* The JSON record is the CLI's, byte for byte. */
  CHECK(chatter_grinding_predict_json(scompi, CHATTER_GRINDING_POWER_W, 1000.0, NULL, 0, &length) == CHATTER_OK);
  json = (char*)malloc(length + 1);
  CHECK(chatter_grinding_predict_json(scompi, CHATTER_GRINDING_POWER_W, 1000.0, json, length + 1, NULL) == CHATTER_OK);
  snprintf(args, sizeof args, "grind predict '%s' --power-w 1000 --json -", scompi);
  cli = run_cli(args);
  CHECK(cli != NULL && strcmp(json, cli) == 0);
  free(cli);
  free(json);
  /* Truncation keeps a NUL. */
  {
    char small[8];
    CHECK(chatter_grinding_predict_json(scompi, CHATTER_GRINDING_POWER_W, 1000.0, small, sizeof small, &length) ==
          CHATTER_OK);
    CHECK(strlen(small) == 7 && length > 7);
  }

  /* The fit of tests generated from k_e = 75 N/mm, k_c = 10 020 N/mm^2. */
  CHECK(chatter_grinding_fit(tests, "mechanistic", NULL, NULL, &f) == CHATTER_OK);
  CHECK(f.count == 2 && f.tests == 21 && f.degrees_of_freedom == 19);
  CHECK(f.lower_95[0] <= 75.0 && f.upper_95[0] >= 75.0);
  CHECK(f.lower_95[1] <= 10020.0 && f.upper_95[1] >= 10020.0);
  CHECK(f.r_squared > 0.99);
  CHECK(chatter_grinding_fit_json(tests, "mechanistic", NULL, NULL, 0, &length) == CHATTER_OK && length > 100);

  /* Errors: status, and a message naming the value and the rule. */
  CHECK(chatter_grinding_predict(scompi, CHATTER_GRINDING_POWER_W, 0.0, &p) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "power_w = 0: must be > 0 W") != NULL);
  CHECK(chatter_grinding_predict(scompi, CHATTER_GRINDING_DEPTH_MM, 500.0, &p) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "below the wheel radius") != NULL);
  CHECK(chatter_grinding_predict(scompi, (chatter_grinding_target)7, 1.0, &p) == CHATTER_INPUT_ERROR);
  CHECK(chatter_grinding_predict(NULL, CHATTER_GRINDING_POWER_W, 1.0, &p) == CHATTER_NULL_ARGUMENT);
  CHECK(chatter_grinding_predict("/nonexistent.toml", CHATTER_GRINDING_POWER_W, 1.0, &p) == CHATTER_INPUT_ERROR);
  /* One wheel at one speed: the cutting speed cannot be told from the constant. */
  CHECK(chatter_grinding_fit(tests, "poly11", NULL, NULL, &f) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "singular design") != NULL);
  /* Seed 000's printed tests: removal, wear and normal force; no power fit. */
  CHECK(chatter_grinding_fit(printed, "poly11", NULL, "wear", &f) == CHATTER_OK && f.count == 3 && f.tests == 12);
  CHECK(chatter_grinding_fit(printed, "poly11", NULL, "power_w", &f) == CHATTER_INPUT_ERROR);
  CHECK(strstr(chatter_last_error(), "not fitted (fitted: removal, wear, normal_force)") != NULL);
  CHECK(chatter_grinding_fit(tests, "nonsense", NULL, NULL, &f) == CHATTER_INPUT_ERROR);
  CHECK(chatter_grinding_predict_json(scompi, CHATTER_GRINDING_POWER_W, 1000.0, NULL, 5, &length) ==
        CHATTER_NULL_ARGUMENT);
  /* The lobe side refuses a grinding config. */
  {
    chatter_model* m = NULL;
    CHECK(chatter_model_load(scompi, &m) == CHATTER_INPUT_ERROR && m == NULL);
    CHECK(strstr(chatter_last_error(), "a grinding config") != NULL);
  }

  printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
