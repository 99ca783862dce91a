/* cli.c — argument checks shared by the subcommands of the sinew executable (cli.h). */
#include "cli.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sinew.h"

int cli_number(const char *opt, const char *s, int allow_zero, double *out) {
  char *end;
  errno = 0;
  double v = strtod(s, &end);
  if (errno == ERANGE && end != s && !*end && fabs(v) < DBL_MIN) { /* as the scene loader */
    fprintf(stderr, "sinew: %s is %s, too small to compute with (below %g); expected a %s "
            "number\n", opt, s, DBL_MIN, allow_zero ? "non-negative" : "positive");
    return -1;
  }
  if (errno || end == s || *end || !isfinite(v) || v < 0 || (!allow_zero && v == 0)) {
    fprintf(stderr, "sinew: %s expects a %s number, got '%s'\n", opt,
            allow_zero ? "non-negative" : "positive", s);
    return -1;
  }
  *out = v;
  return 0;
}

int cli_int(const char *opt, const char *s, int lo, int hi, int *out) {
  char *end;
  errno = 0;
  long v = strtol(s, &end, 10);
  if (errno || end == s || *end || v < lo || v > hi) {
    fprintf(stderr, "sinew: %s expects an integer %d..%d, got '%s'\n", opt, lo, hi, s);
    return -1;
  }
  *out = (int)v;
  return 0;
}

int cli_known_method(const char *name) {
  for (const char *const *n = sw_method_names(); *n; n++)
    if (!strcmp(*n, name)) return 1;
  return 0;
}
