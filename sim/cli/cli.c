/* cli.c — argument checks shared by the subcommands of the sinew executable, and where the
 * installed Python package is (cli.h). */
#include "cli.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

#ifndef SW_PYVER
#define SW_PYVER "3" /* meson.build gives the Python's X.Y */
#endif

/* The folder holding the installed package sinew/ beside this program, found as its rpath is
 * (meson.build): lib/pythonX.Y/site- or dist-packages of a venv, --user or --prefix install, or
 * the --target folder itself; 0 and dir set, or -1 when none holds sinew/__init__.py. */
int cli_package_dir(char *dir, size_t size) {
  char exe[4096];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return -1;
  exe[n] = '\0';
  char *slash = strrchr(exe, '/');
  if (!slash) return -1;
  *slash = '\0'; /* the program's folder (bin/) */
  const char *under[] = {"/../lib/python" SW_PYVER "/site-packages",
                         "/../lib/python" SW_PYVER "/dist-packages", "/.."};
  for (size_t k = 0; k < sizeof under / sizeof *under; k++) {
    char init[4200];
    snprintf(dir, size, "%s%s", exe, under[k]);
    snprintf(init, sizeof init, "%s/sinew/__init__.py", dir);
    if (strlen(dir) + 1 < size && !access(init, R_OK)) return 0;
  }
  return -1;
}
