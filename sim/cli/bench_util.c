/* bench_util.c — the small helpers every part of `sinew bench` shares (bench.h): mode names,
 * paths, files written whole or not at all, number formatting, NAME:qN method specs.  It sits
 * below bench.c, bench_exec.c, bench_read.c and bench_merge.c and calls none of them. */
#include "bench.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const mode_names[BM_NMODE] = {"work_precision", "stability", "scaling"};

const char *bench_mode_name(int mode) { return mode_names[mode]; }

int bench_path(char *out, size_t sz, const char *dir, const char *a, const char *b) {
  int n = snprintf(out, sz, "%s/%s%s%s", dir, a, b ? "/" : "", b ? b : "");
  return n < 0 || (size_t)n >= sz ? -1 : 0;
}

FILE *bench_create(const char *path, char *tmp, size_t sz) {
  int n = snprintf(tmp, sz, "%s.tmp", path);
  FILE *f = n < 0 || (size_t)n >= sz ? NULL : fopen(tmp, "w");
  if (!f) fprintf(stderr, "sinew: bench: cannot write %s: %s\n", path, strerror(errno));
  return f;
}

int bench_commit(FILE *f, const char *tmp) {
  char final[SW_PATHSZ + 256];
  snprintf(final, sizeof final, "%.*s", (int)(strlen(tmp) - 4), tmp);
  int bad = ferror(f);
  if (fclose(f) || bad || rename(tmp, final)) {
    unlink(tmp);
    return fprintf(stderr, "sinew: bench: cannot write %s\n", final), -1;
  }
  return 0;
}

int bench_atoi(const char *s) {
  long v = strtol(s, NULL, 10); /* saturates, unlike atoi */
  return v > 1000000000L ? 1000000000 : v < -1000000000L ? -1000000000 : (int)v;
}

void bench_fmt(char *buf, size_t sz, double v) {
  for (int p = 1; p <= 17; p++) {
    snprintf(buf, sz, "%.*g", p, v);
    if (strtod(buf, NULL) == v) return;
  }
}

int bench_method_split(const char *spec, char *name, size_t namesz, int *order) {
  const char *colon = strchr(spec, ':');
  size_t len = colon ? (size_t)(colon - spec) : strlen(spec);
  *order = 0;
  if (len == 0 || len >= namesz) return -1;
  memcpy(name, spec, len);
  name[len] = '\0';
  if (!colon) return 0;
  if (colon[1] != 'q' || colon[2] < '1' || colon[2] > '5' || colon[3]) return -1;
  *order = colon[2] - '0';
  return 0;
}
