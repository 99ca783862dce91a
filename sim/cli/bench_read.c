/* bench_read.c — what one run left in DIR/runs/ID: summary.json (status, counters, wall and CPU
 * time), its logs at the common sample times (tension.csv, energy.csv, tendons.csv) and
 * positions.bin, and what its process did (DIR/logs/ID.exit).  Nothing here trusts the files: a
 * run without a final summary is "crashed"; a run whose summary says ok but whose data are damaged
 * (a log line cut short or with a field that is not a number, a value the bench uses that is not
 * finite, a positions.bin that is not whole records of finite numbers, a log above BENCH_LOG_MAX
 * bytes, positions above BENCH_POS_BUDGET bytes) is "damaged", with the file and line in its
 * message, and none of its numbers is used. */
#include "bench.h"

#include <math.h>
#include <stdarg.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <fcntl.h>
#include <unistd.h>

/* ------------------------------------------------------------ sample times */

static int last_regular(const bench_cfg *c) { return (int)floor(c->duration / c->sample + 1e-9); }

int bench_nsample(const bench_cfg *c) {
  int k = last_regular(c);
  return k + 1 + (c->duration - k * c->sample > 1e-9 * c->sample);
}

double bench_sample_time(const bench_cfg *c, int k) {
  return k <= last_regular(c) ? k * c->sample : c->duration;
}

/* The sample a logged time is, or -1. */
static int sample_of(const bench_cfg *c, double t) {
  double q = t / c->sample;
  if (!(fabs(q) < 1e9)) return -1;
  long k = lround(q);
  if (fabs(q - (double)k) < 1e-6 && k >= 0 && k <= last_regular(c)) return (int)k;
  int ns = bench_nsample(c);
  if (ns > last_regular(c) + 1 && fabs(t - c->duration) < 1e-9 * fmax(c->duration, c->sample))
    return ns - 1;
  return -1;
}

#define BENCH_LOG_MAX (1L << 30)    /* bytes of one log read by --merge */
#define BENCH_POS_BUDGET (1L << 30) /* bytes of positions held for one run */

/* ------------------------------------------------------------ damage */

/* Mark an ok run damaged: "runs/ID/FILE:LINE: why" (line 0: no line) in its message. */
static void damaged(bench_result *r, const bench_job *j, const char *file, long line,
                    const char *fmt, ...) __attribute__((format(printf, 5, 6)));
static void damaged(bench_result *r, const bench_job *j, const char *file, long line,
                    const char *fmt, ...) {
  if (!strcmp(r->status, "damaged")) return; /* the first damage found is reported */
  char why[256];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(why, sizeof why, fmt, ap);
  va_end(ap);
  snprintf(r->status, sizeof r->status, "damaged");
  snprintf(r->how, sizeof r->how, "damaged data");
  if (line > 0)
    snprintf(r->message, sizeof r->message, "runs/%s/%s:%ld: %s", j->id, file, line, why);
  else snprintf(r->message, sizeof r->message, "runs/%s/%s: %s", j->id, file, why);
}

/* ------------------------------------------------------------ whole files */

/* path opened for reading only if it is a regular file (not a FIFO, which would block the
 * merge forever, a device or a symbolic link); NULL otherwise. */
static FILE *open_regular(const char *path) {
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_NOCTTY | O_CLOEXEC);
  struct stat st;
  if (fd < 0) return NULL;
  if (fstat(fd, &st) || !S_ISREG(st.st_mode) || fcntl(fd, F_SETFL, 0)) return close(fd), NULL;
  FILE *f = fdopen(fd, "rb");
  if (!f) close(fd);
  return f;
}

static char *slurp(const char *path, size_t max) {
  FILE *f = open_regular(path);
  if (!f) return NULL;
  size_t cap = 4096, n = 0;
  char *buf = malloc(cap);
  while (buf) {
    if (n + 1 >= cap) {
      char *nb = cap < max ? realloc(buf, cap * 2) : NULL;
      if (!nb) { free(buf), buf = NULL; break; }
      buf = nb, cap *= 2;
    }
    size_t got = fread(buf + n, 1, cap - 1 - n, f);
    if (got == 0) break;
    n += got;
  }
  fclose(f);
  if (buf) buf[n] = '\0';
  return buf;
}

static int run_file(char *out, size_t sz, const bench_cfg *c, const bench_job *j,
                    const char *name) {
  int n = snprintf(out, sz, "%s/runs/%s/%s", c->dir, j->id, name);
  return n < 0 || (size_t)n >= sz ? -1 : 0;
}

/* ---------------------------------------------------------- summary.json */

static const char *json_at(const char *js, const char *key) {
  char pat[64];
  snprintf(pat, sizeof pat, "\"%s\": ", key);
  const char *p = strstr(js, pat);
  return p ? p + strlen(pat) : NULL;
}

static double json_num(const char *js, const char *key) {
  const char *p = json_at(js, key);
  if (!p) return NAN;
  char *end;
  double v = strtod(p, &end);
  return end == p ? NAN : v;
}

static long json_long(const char *js, const char *key) {
  double v = json_num(js, key);
  return fabs(v) < 1e18 ? (long)v : 0; /* NaN and out of range: 0 */
}

/* A JSON string value (escapes reduced: \uXXXX becomes '?'). */
static void json_str(const char *js, const char *key, char *out, size_t sz) {
  const char *p = json_at(js, key);
  size_t n = 0;
  if (p && *p == '"')
    for (p++; *p && *p != '"' && n + 1 < sz; p++) {
      if (*p == '\\' && p[1]) {
        p++;
        out[n++] = *p == 'n' ? ' ' : *p == 'u' ? '?' : *p;
        if (*p == 'u') for (int k = 0; k < 4 && p[1]; k++) p++;
      } else out[n++] = *p;
    }
  out[n] = '\0';
}

/* A short name for why a run failed, from its message. */
static void failure_kind(const char *msg, char *how, size_t sz) {
  static const struct { const char *has, *how; } kinds[] = {
      {"energy blow-up", "blew up (energy)"}, {"not finite", "blew up (not finite)"},
      {"Newton did not converge", "Newton did not converge"},
      {"Newton step is not finite", "blew up (not finite)"},
      {"too much work", "too much work"}, {"error test", "error test failures"},
      {"convergence test", "convergence failures"}, {"cannot start", "cannot start"}};
  for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++)
    if (strstr(msg, kinds[k].has)) {
      snprintf(how, sz, "%s", kinds[k].how);
      return;
    }
  snprintf(how, sz, "failed");
}

static void read_summary(const char *js, bench_result *r) {
  json_str(js, "status", r->status, sizeof r->status);
  json_str(js, "message", r->message, sizeof r->message);
  r->wall = json_num(js, "wall_time_s");
  r->cpu = json_num(js, "cpu_time_s"); /* NaN: a run of a sinew before it */
  r->time_step = json_num(js, "time_step_s");
  r->time_assemble = json_num(js, "time_assemble_s");
  r->time_factor = json_num(js, "time_factor_s");
  r->time_solve = json_num(js, "time_solve_s");
  r->max_rss_mb = json_num(js, "max_rss_mb");
  r->steps = json_long(js, "steps");
  r->newton = json_long(js, "newton_iterations");
  r->factor = json_long(js, "factorizations");
  r->assemble = json_long(js, "assemblies");
  r->force = json_long(js, "force_evaluations");
  r->retries = json_long(js, "retries");
  r->dofs = json_long(js, "free_dofs");
  r->nv = json_long(js, "vertices");
}

/* The line of js that p points into (1-based), for "summary.json:LINE". */
static long line_of(const char *js, const char *p) {
  long n = 1;
  for (const char *q = js; q < p; q++) n += *q == '\n';
  return n;
}

/* The time the run was planned to reach (s): the bench's duration, or a scaling run's steps. */
static double planned_end(const bench_cfg *c, const bench_job *j) {
  return c->mode == BM_SCALING ? c->steps * j->dt : c->duration;
}

static int same_value(double a, double b) { return fabs(a - b) <= 1e-9 * fmax(fabs(a), fabs(b)); }

/* Costs and counters of an ok summary: each one present is a finite number >= 0, and the wall
 * time is present (a summary saying `"wall_time_s": -1e308` is damaged, not a fast run). */
static int check_costs(const char *js, const bench_job *j, bench_result *r) {
  static const char *const keys[] = {"wall_time_s", "cpu_time_s", "time_step_s", "time_assemble_s",
      "time_factor_s", "time_solve_s", "max_rss_mb", "steps", "newton_iterations",
      "factorizations", "assemblies", "force_evaluations", "retries", "free_dofs", "vertices"};
  for (size_t k = 0; k < sizeof keys / sizeof *keys; k++) {
    const char *p = json_at(js, keys[k]);
    if (!p && k == 0) return damaged(r, j, "summary.json", 0, "no wall_time_s; expected the "
                                     "run's wall time"), -1;
    double v = json_num(js, keys[k]);
    int len = p ? (int)strcspn(p, ",\n}") : 0;
    if (p && !(v >= 0 && v < 1e18))
      return damaged(r, j, "summary.json", line_of(js, p), "%s is %.*s; expected a number >= 0",
                     keys[k], len < 40 ? len : 40, p), -1;
  }
  return 0;
}

/* An ok summary against its plan entry: the method (and BDF order), dt, rtol, stiffness scale,
 * scene file and duration of the run the plan asked for, so that a folder holding another run's
 * numbers is not read as this one. */
static void check_summary(const bench_cfg *c, const bench_job *j, const char *js,
                          bench_result *r) {
  char name[SW_NAMESZ], got[SW_PATHSZ];
  int order = 0;
  if (bench_method_split(j->method, name, sizeof name, &order)) name[0] = '\0';
  const struct { const char *key, *want; } str[] = {{"method", name}, {"scene_file", c->scene}};
  for (size_t k = 0; k < sizeof str / sizeof *str; k++) {
    json_str(js, str[k].key, got, sizeof got);
    const char *p = json_at(js, str[k].key);
    if (strcmp(got, str[k].want))
      return damaged(r, j, "summary.json", p ? line_of(js, p) : 0, "%s is '%.80s'; the plan "
                     "says '%.80s' for this run", str[k].key, got, str[k].want);
  }
  const struct { const char *key; double want; int used; } num[] = {
      {"dt", j->dt, 1}, {"rtol", j->rtol, j->adaptive}, {"stiffness_scale", j->scale, 1},
      {"duration", planned_end(c, j), 1}, {"max_order", order, order > 0},
      {"vertices", (double)j->grid * j->grid, j->grid > 0}};
  for (size_t k = 0; k < sizeof num / sizeof *num; k++) {
    const char *p = json_at(js, num[k].key);
    double v = json_num(js, num[k].key);
    if (num[k].used && !same_value(v, num[k].want))
      return damaged(r, j, "summary.json", p ? line_of(js, p) : 0, "%s is %.17g; the plan "
                     "says %.17g for this run", num[k].key, v, num[k].want);
  }
  check_costs(js, j, r);
}

/* The status from the process's exit (DIR/logs/ID.exit) and the summary. */
static void classify(const bench_cfg *c, const bench_job *j, bench_result *r) {
  char path[SW_PATHSZ + BENCH_IDSZ + 16], line[64] = "";
  snprintf(path, sizeof path, "%s/logs/%s.exit", c->dir, j->id);
  FILE *f = open_regular(path);
  if (f) {
    if (!fgets(line, sizeof line, f)) line[0] = '\0';
    fclose(f);
  }
  int code = -1, sig = 0;
  if (!strncmp(line, "exit ", 5)) code = bench_atoi(line + 5);
  if (!strncmp(line, "signal ", 7)) sig = bench_atoi(line + 7);
  if (code > 128) sig = code - 128; /* sh: 128 + the signal */
  int timed_out = !strncmp(line, "timeout", 7) || (code == 124 && c->timeout > 0);
  if (timed_out) {
    snprintf(r->status, sizeof r->status, "failed");
    snprintf(r->how, sizeof r->how, "timed out (%g s)", c->timeout);
  } else if (sig > 0) {
    snprintf(r->status, sizeof r->status, "crashed");
    snprintf(r->how, sizeof r->how, "signal %d (%s)", sig, strsignal(sig));
  } else if (!r->present || !strcmp(r->status, "running")) {
    snprintf(r->status, sizeof r->status, "crashed");
    snprintf(r->how, sizeof r->how, "%s", line[0] ? "no final summary" : "did not run");
  } else if (!strcmp(r->status, "failed")) {
    failure_kind(r->message, r->how, sizeof r->how);
  } else if (strcmp(r->status, "ok")) {
    snprintf(r->how, sizeof r->how, "unknown status '%.20s'", r->status);
    snprintf(r->status, sizeof r->status, "crashed");
  }
}

/* ------------------------------------------------------------------ logs */

/* The column of name in a CSV header line, or -1. */
static int column(const char *header, const char *name) {
  int col = 0;
  size_t n = strlen(name);
  for (const char *p = header; *p; col++) {
    size_t len = strcspn(p, ",\n");
    if (len == n && !strncmp(p, name, n)) return col;
    p += len;
    if (*p != ',') break;
    p++;
  }
  return -1;
}

/* Field col of a CSV line as a number (NaN if absent). */
static double field(const char *line, int col) {
  const char *p = line;
  for (int k = 0; k < col && p; k++) {
    p = strpbrk(p, ",\n");
    if (p && *p == ',') p++;
    else p = NULL;
  }
  if (!p) return NAN;
  char *end;
  double v = strtod(p, &end);
  return end == p ? NAN : v;
}

/* Fields of a CSV line (up to its newline). */
static int nfields(const char *line) {
  int n = 1;
  for (const char *p = line; *p && *p != '\n'; p++) n += *p == ',';
  return n;
}

/* Field col of a line is a whole number (strtod: "nan" and "inf" too), finite when `finite`. */
static int field_ok(const char *line, int col, int finite) {
  const char *p = line;
  for (int k = 0; k < col; k++) p = strchr(p, ',') + 1; /* col < nfields(line) */
  char *end;
  double v = strtod(p, &end);
  return end != p && (*end == ',' || *end == '\n') && (!finite || isfinite(v));
}

/* What the times of a log must be: increasing (strictly, or not for logs of several lines per
 * time), up to and ending at the planned end (s). */
typedef struct log_times {
  int strict;
  double end;
} log_times;

/* The time t (s) of a log line after one at *prev: in order and not after the planned end. */
static int check_time(bench_result *r, const bench_job *j, const char *file, long line, double t,
                      double *prev, const log_times *lt) {
  if (lt->strict ? !(t > *prev) : !(t >= *prev))
    return damaged(r, j, file, line, "t = %g s after t = %g s on the line before; expected "
                   "increasing times", t, *prev), -1;
  if (t > lt->end && !same_value(t, lt->end))
    return damaged(r, j, file, line, "t = %g s is after the planned end %g s", t, lt->end), -1;
  *prev = t;
  return 0;
}

/* The start of the last line of text (whose last character is its newline). */
static const char *last_line(const char *text) {
  const char *e = text + strlen(text) - 1, *s = e;
  while (s > text && s[-1] != '\n') s--;
  return s;
}

/* A log of a run that says ok: every line whole (a newline at its end, the header's number of
 * fields), every field a number but column `text_col` (-1: none), and the columns in used[]
 * (nused of them, -1 entries skipped) finite.  0, or -1 with the run marked damaged. */
static int check_log(bench_result *r, const bench_job *j, const char *file, const char *text,
                     int text_col, const int *used, int nused, const log_times *lt) {
  const char *p = strchr(text, '\n');
  if (!p) return damaged(r, j, file, 1, "no whole header line"), -1;
  int nh = nfields(text);
  long line = 2;
  for (double prev = -INFINITY; p[1]; line++) {
    const char *s = p + 1;
    p = strchr(s, '\n');
    if (!p) return damaged(r, j, file, line, "the line is cut short (no end of line)"), -1;
    int nf = nfields(s);
    if (nf != nh)
      return damaged(r, j, file, line, "%d fields; expected %d (the header's)", nf, nh), -1;
    for (int c = 0; c < nf; c++)
      if (c != text_col && !field_ok(s, c, 0))
        return damaged(r, j, file, line, "field %d is not a number", c + 1), -1;
    for (int u = 0; u < nused; u++)
      if (used[u] >= 0 && !field_ok(s, used[u], 1))
        return damaged(r, j, file, line, "field %d is not finite", used[u] + 1), -1;
    if (check_time(r, j, file, line, field(s, 0), &prev, lt)) return -1;
  }
  if (line == 2) return damaged(r, j, file, 1, "no line after the header"), -1;
  double last = field(last_line(text), 0);
  if (!same_value(last, lt->end))
    return damaged(r, j, file, line - 1, "the log ends at t = %g s; expected the planned end "
                   "%g s", last, lt->end), -1;
  return 0;
}

static double *nan_array(size_t n) {
  double *a = malloc((n ? n : 1) * sizeof *a);
  for (size_t k = 0; a && k < n; k++) a[k] = NAN;
  return a;
}

/* Visit each line after the header: fn(ctx, line, sample index) for the sampled ones. */
typedef void (*line_fn)(void *ctx, const char *line, int k);

static void each_sample(const bench_cfg *c, const char *text, line_fn fn, void *ctx) {
  const char *p = strchr(text, '\n');
  while (p && p[1]) {
    p++;
    int k = sample_of(c, field(p, 0));
    if (k >= 0) fn(ctx, p, k);
    p = strchr(p, '\n');
  }
}

typedef struct cols {
  int a, b;                    /* columns */
  double *x, *y;
} cols;

static void take_two(void *ctx, const char *line, int k) {
  cols *q = ctx;
  q->x[k] = field(line, q->a);
  q->y[k] = field(line, q->b);
}

static void read_pair(const bench_cfg *c, const char *text, const char *ca, const char *cb,
                      double *x, double *y) {
  cols q = {.a = column(text, ca), .b = column(text, cb), .x = x, .y = y};
  if (q.a >= 0 && q.b >= 0) each_sample(c, text, take_two, &q);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

double bench_median(double *v, int n) {
  if (n <= 0) return NAN;
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Median of step_wall_s over the logged steps after the first (the first one analyses the
 * sparsity pattern); every step when there is only one. */
static double step_median(const char *text) {
  int col = column(text, "step_wall_s"), n = 0, cap = 0;
  double *v = NULL;
  const char *p = strchr(text, '\n');
  for (int line = 0; col >= 0 && p && p[1]; line++) {
    p++;
    double s = field(p, col);
    if (line > 0 && isfinite(s)) {
      if (n == cap) {
        double *nv = realloc(v, (size_t)(cap = cap ? 2 * cap : 64) * sizeof *v);
        if (!nv) break;
        v = nv;
      }
      v[n++] = s;
    }
    p = strchr(p, '\n');
  }
  int skip = n > 1;
  double med = n > skip ? bench_median(v + skip, n - skip) : NAN;
  free(v);
  return med;
}

typedef struct tendon_ctx {
  bench_result *r;
  char (*name)[SW_NAMESZ];
  int cap;
} tendon_ctx;

static int tendon_index(tendon_ctx *q, const char *line) {
  const char *p = strchr(line, ',');
  if (!p) return -1;
  p++;
  size_t len = strcspn(p, ",\n");
  if (len >= SW_NAMESZ) return -1;
  for (int t = 0; t < q->r->ntendon; t++)
    if (strlen(q->name[t]) == len && !strncmp(q->name[t], p, len)) return t;
  return -1;
}

static void take_tendon(void *ctx, const char *line, int k) {
  tendon_ctx *q = ctx;
  int t = tendon_index(q, line);
  if (t >= 0) q->r->tendon[k * q->r->ntendon + t] = field(line, 4);
}

/* tendons.csv: the tendons are the names of the first logged time. */
static void read_tendons(const bench_cfg *c, const char *text, bench_result *r) {
  char name[64][SW_NAMESZ];
  tendon_ctx q = {.r = r, .name = name, .cap = 64};
  const char *p = strchr(text, '\n');
  double t0 = p ? field(p + 1, 0) : NAN;
  r->ntendon = 0;
  while (p && p[1] && field(p + 1, 0) == t0 && r->ntendon < q.cap) {
    const char *s = strchr(p + 1, ',');
    size_t len = s ? strcspn(s + 1, ",\n") : SW_NAMESZ;
    if (len >= SW_NAMESZ) break;
    memcpy(name[r->ntendon], s + 1, len);
    name[r->ntendon++][len] = '\0';
    p = strchr(p + 1, '\n');
  }
  r->tendon = nan_array((size_t)r->ns * (size_t)r->ntendon);
  if (r->tendon && r->ntendon) each_sample(c, text, take_tendon, &q);
}

/* A log of the run, checked (check_log with the columns named in used[], NULL-terminated);
 * NULL when it is damaged, or absent and optional. */
static char *read_log(const bench_cfg *c, const bench_job *j, bench_result *r, const char *file,
                      int optional, int text_col, const char *const *used) {
  char path[SW_PATHSZ + BENCH_IDSZ + 32];
  struct stat st;
  if (run_file(path, sizeof path, c, j, file) || lstat(path, &st))
    return optional ? NULL : (damaged(r, j, file, 0, "missing"), NULL);
  if (!S_ISREG(st.st_mode))
    return damaged(r, j, file, 0, "not a regular file (a FIFO, device, folder or symbolic "
                   "link); expected the log the run wrote"), NULL;
  if (st.st_size > BENCH_LOG_MAX)
    return damaged(r, j, file, 0, "%lld bytes; expected at most %ld", (long long)st.st_size,
                   BENCH_LOG_MAX), NULL;
  char *text = slurp(path, (size_t)BENCH_LOG_MAX + 1);
  if (!text) return damaged(r, j, file, 0, "cannot be read"), NULL;
  int cols[8], n = 0;
  for (; used[n] && n < 8; n++) cols[n] = column(text, used[n]);
  log_times lt = {.strict = text_col < 0, .end = planned_end(c, j)};
  if (check_log(r, j, file, text, text_col, cols, n, &lt)) return free(text), NULL;
  return text;
}

/* Every common sample time has its line in a log (values v at the samples, NaN where none):
 * a deleted line leaves a sample unmeasured.  Scaling runs take no samples. */
static void check_samples(const bench_cfg *c, const bench_job *j, bench_result *r,
                          const char *file, const double *v) {
  for (int k = 0; k < r->ns && c->mode != BM_SCALING; k++)
    if (isnan(v[k]))
      return damaged(r, j, file, 0, "no line at the sample time t = %g s; expected one at every "
                     "%g s and at the end", bench_sample_time(c, k), c->sample);
}

static void read_logs(const bench_cfg *c, const bench_job *j, bench_result *r) {
  static const char *const t_used[] = {"time", "txy_max", "txy_mean", NULL};
  static const char *const e_used[] = {"time", "total", "kinetic", "step_wall_s", NULL};
  static const char *const d_used[] = {"time", "tension", NULL};
  size_t n = (size_t)r->ns;
  r->t = nan_array(n), r->txy_max = nan_array(n), r->txy_mean = nan_array(n);
  r->energy = nan_array(n), r->kinetic = nan_array(n);
  if (!r->t || !r->txy_max || !r->txy_mean || !r->energy || !r->kinetic) return;
  for (int k = 0; k < r->ns; k++) r->t[k] = bench_sample_time(c, k);
  char *text = read_log(c, j, r, "tension.csv", 0, -1, t_used);
  if (text) read_pair(c, text, "txy_max", "txy_mean", r->txy_max, r->txy_mean);
  if (text) check_samples(c, j, r, "tension.csv", r->txy_max);
  free(text);
  text = read_log(c, j, r, "energy.csv", 0, -1, e_used);
  if (text) {
    read_pair(c, text, "total", "kinetic", r->energy, r->kinetic);
    check_samples(c, j, r, "energy.csv", r->energy);
    r->step_median = step_median(text);
  }
  free(text);
  text = read_log(c, j, r, "tendons.csv", 1, 1, d_used);
  if (text) read_tendons(c, text, r);
  free(text);
}

/* ------------------------------------------------------------ positions.bin */

/* The header of positions.bin: the record size in values (1 + nv dim), or 0 with the run
 * marked damaged (a bad header, a size that is not whole records, more than the budget). */
static size_t positions_header(const bench_job *j, bench_result *r, FILE *f) {
  const char *file = "positions.bin";
  char magic[8];
  int32_t head[2];
  struct stat st;
  if (fread(magic, 1, 8, f) != 8 || memcmp(magic, "SWPOS001", 8) || fread(head, 4, 2, f) != 2 ||
      head[0] < 1 || head[1] < 2 || head[1] > 3 || head[0] > (1 << 26))
    return damaged(r, j, file, 0, "not a positions file (header SWPOS001, nv, dim 2 or 3)"), 0;
  if (r->nv > 0 && head[0] != r->nv)
    return damaged(r, j, file, 0, "%d vertices; the summary says %ld", head[0], r->nv), 0;
  size_t rec = 1 + (size_t)head[0] * (size_t)head[1], bytes = rec * sizeof(double);
  if (fstat(fileno(f), &st) || st.st_size < 16 || ((size_t)st.st_size - 16) % bytes ||
      (size_t)st.st_size == 16)
    return damaged(r, j, file, 0, "%lld bytes: not whole records of %zu bytes after the "
                   "16-byte header", (long long)st.st_size, bytes), 0;
  if ((double)r->ns * (double)(rec - 1) * sizeof(double) > (double)BENCH_POS_BUDGET)
    return damaged(r, j, file, 0, "%d samples of %zu values need more than the %ld-byte memory "
                   "budget of --merge", r->ns, rec - 1, BENCH_POS_BUDGET), 0;
  r->pnv = head[0], r->dim = head[1];
  return rec;
}

/* positions.bin: the records at sample times, every number finite (record N: line N of the
 * message's "file:N"). */
static void read_positions(const bench_cfg *c, const bench_job *j, bench_result *r) {
  char path[SW_PATHSZ + BENCH_IDSZ + 32];
  if (run_file(path, sizeof path, c, j, "positions.bin")) return;
  FILE *f = open_regular(path);
  if (!f) {
    damaged(r, j, "positions.bin", 0, "missing");
    return;
  }
  size_t rec = positions_header(j, r, f);
  double *buf = rec ? malloc(rec * sizeof *buf) : NULL;
  r->pos = buf ? nan_array((size_t)r->ns * (rec - 1)) : NULL;
  for (long n = 1; r->pos && fread(buf, sizeof *buf, rec, f) == rec; n++) {
    for (size_t i = 0; i < rec; i++)
      if (!isfinite(buf[i])) {
        damaged(r, j, "positions.bin", n, "record %ld (t = %g s): %s is not finite", n, buf[0],
                i ? "a position" : "the time");
        free(buf), fclose(f);
        free(r->pos), r->pos = NULL, r->npos = 0;
        return;
      }
    int k = sample_of(c, buf[0]);
    if (k >= 0) memcpy(r->pos + (size_t)k * (rec - 1), buf + 1, (rec - 1) * sizeof *buf);
    r->npos += k >= 0;
  }
  free(buf);
  fclose(f);
  for (int k = 0; r->pos && k < r->ns; k++)
    if (isnan(r->pos[(size_t)k * (rec - 1)]))
      return damaged(r, j, "positions.bin", 0, "no record at the sample time t = %g s; expected "
                     "one at every %g s and at the end", bench_sample_time(c, k), c->sample);
}

/* ------------------------------------------------------------------ entry */

int bench_read(const bench_cfg *c, const bench_job *j, int want_positions, bench_result *r) {
  memset(r, 0, sizeof *r);
  r->wall = r->cpu = r->time_step = r->max_rss_mb = r->step_median = NAN;
  char path[SW_PATHSZ + BENCH_IDSZ + 32];
  struct stat st;
  int n = snprintf(path, sizeof path, "%s/runs/%s", c->dir, j->id);
  if (n > 0 && (size_t)n < sizeof path && !lstat(path, &st) && !S_ISDIR(st.st_mode)) {
    classify(c, j, r); /* the process's exit, then the folder refused */
    snprintf(r->status, sizeof r->status, "damaged");
    snprintf(r->how, sizeof r->how, "damaged data");
    snprintf(r->message, sizeof r->message, "runs/%s: %s; expected the run's own folder", j->id,
             S_ISLNK(st.st_mode) ? "a symbolic link" : "not a folder");
    r->ns = bench_nsample(c);
    return 0;
  }
  char *js = run_file(path, sizeof path, c, j, "summary.json") ? NULL : slurp(path, 1 << 20);
  if (js) {
    r->present = 1;
    read_summary(js, r);
  }
  classify(c, j, r);
  r->ns = bench_nsample(c);
  if (!strcmp(r->status, "ok")) check_summary(c, j, js, r);
  free(js);
  if (strcmp(r->status, "ok")) return 0;
  read_logs(c, j, r);
  if (want_positions) read_positions(c, j, r);
  return 0;
}

void bench_result_free(bench_result *r) {
  free(r->t), free(r->txy_max), free(r->txy_mean), free(r->energy), free(r->kinetic);
  free(r->tendon), free(r->pos);
  memset(r, 0, sizeof *r);
}
