/* One-file C consumer of the chatter C API, compiled with pkg-config flags:
 *   cc c_consumer.c $(pkg-config --cflags --libs chatter) -o c_consumer
 * Usage: c_consumer CONFIG */
#include <stdio.h>

#include "chatter/chatter.h"

int main(int argc, char** argv) {
  chatter_model* model = NULL;
  chatter_solver* solver = NULL;
  chatter_limit lim;
  if (argc != 2) {
    fprintf(stderr, "usage: c_consumer CONFIG\n");
    return 2;
  }
  if (chatter_model_load(argv[1], &model) != CHATTER_OK ||
      chatter_solver_create(model, "analytic", 20.0, &solver) != CHATTER_OK ||
      chatter_limit_at(solver, 1800.0, &lim) != CHATTER_OK) {
    fprintf(stderr, "chatter: %s\n", chatter_last_error());
    chatter_solver_free(solver);
    chatter_model_free(model);
    return 2;
  }
  printf("chatter %s: at %.0f rev/min the depth limit is %.4f mm (chatter at %.2f Hz, lobe %d)\n", chatter_version(),
         lim.spindle_rpm, lim.depth_limit_mm, lim.chatter_frequency_hz, lim.lobe);
  chatter_solver_free(solver);
  chatter_model_free(model);
  return 0;
}
