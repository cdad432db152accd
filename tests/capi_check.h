/* Shared by the C API's test programs (tests/test_capi*.c): the CHECK
 * counter and the CLI's output for the cross-checks. Each test program is
 * one translation unit, so the statics here are its own. */
#ifndef CHATTER_TESTS_CAPI_CHECK_H
#define CHATTER_TESTS_CAPI_CHECK_H

#include <stdio.h>
#include <stdlib.h>

static int passed = 0, failed = 0;
#define CHECK(cond)                                                            \
  do {                                                                         \
    if (cond) {                                                                \
      ++passed;                                                                \
    } else {                                                                   \
      ++failed;                                                                \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                          \
  } while (0)

#ifdef CHATTER_CLI
/* The whole standard output of `chatter ARGS` (NULL when it cannot run or
 * exits non-zero); free() it. Needs _POSIX_C_SOURCE >= 2 for popen. */
static char* run_cli(const char* args) {
  char cmd[2048];
  FILE* p;
  char* buf = NULL;
  size_t len = 0, cap = 0, n;
  snprintf(cmd, sizeof cmd, "'%s' %s 2>/dev/null", CHATTER_CLI, args);
  p = popen(cmd, "r");
  if (!p) return NULL;
  for (;;) {
    if (cap - len < 4096) {
      char* grown = (char*)realloc(buf, cap + 65536);
      if (!grown) break;
      buf = grown;
      cap += 65536;
    }
    n = fread(buf + len, 1, cap - len - 1, p);
    if (n == 0) break;
    len += n;
  }
  if (pclose(p) != 0 || !buf) {
    free(buf);
    return NULL;
  }
  buf[len] = 0;
  return buf;
}
#endif

#endif
