/* bench_read.c — what one run left in DIR/runs/ID: summary.json (status, counters, wall time),
 * its logs at the common sample times (tension.csv, energy.csv, tendons.csv) and positions.bin,
 * and what its process did (DIR/logs/ID.exit).  Anything missing or malformed makes the run
 * "crashed" or leaves a value NaN; nothing here trusts the files. */
#include "bench.h"

#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

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

/* ------------------------------------------------------------ whole files */

static char *slurp(const char *path, size_t max) {
  FILE *f = fopen(path, "rb");
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

/* The status from the process's exit (DIR/logs/ID.exit) and the summary. */
static void classify(const bench_cfg *c, const bench_job *j, bench_result *r) {
  char path[SW_PATHSZ + BENCH_IDSZ + 16], line[64] = "";
  snprintf(path, sizeof path, "%s/logs/%s.exit", c->dir, j->id);
  FILE *f = fopen(path, "r");
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

static void read_logs(const bench_cfg *c, const bench_job *j, bench_result *r) {
  char path[SW_PATHSZ + BENCH_IDSZ + 32];
  size_t n = (size_t)r->ns;
  r->t = nan_array(n), r->txy_max = nan_array(n), r->txy_mean = nan_array(n);
  r->energy = nan_array(n), r->kinetic = nan_array(n);
  if (!r->t || !r->txy_max || !r->txy_mean || !r->energy || !r->kinetic) return;
  for (int k = 0; k < r->ns; k++) r->t[k] = bench_sample_time(c, k);
  char *text = run_file(path, sizeof path, c, j, "tension.csv") ? NULL : slurp(path, 1ul << 31);
  if (text) read_pair(c, text, "txy_max", "txy_mean", r->txy_max, r->txy_mean);
  free(text);
  text = run_file(path, sizeof path, c, j, "energy.csv") ? NULL : slurp(path, 1ul << 31);
  if (text) {
    read_pair(c, text, "total", "kinetic", r->energy, r->kinetic);
    r->step_median = step_median(text);
  }
  free(text);
  text = run_file(path, sizeof path, c, j, "tendons.csv") ? NULL : slurp(path, 1ul << 31);
  if (text) read_tendons(c, text, r);
  free(text);
}

/* ------------------------------------------------------------ positions.bin */

static void read_positions(const bench_cfg *c, const bench_job *j, bench_result *r) {
  char path[SW_PATHSZ + BENCH_IDSZ + 32], magic[8];
  int32_t head[2];
  if (run_file(path, sizeof path, c, j, "positions.bin")) return;
  FILE *f = fopen(path, "rb");
  if (!f) return;
  if (fread(magic, 1, 8, f) != 8 || memcmp(magic, "SWPOS001", 8) || fread(head, 4, 2, f) != 2 ||
      head[0] < 1 || head[1] < 2 || head[1] > 3 || head[0] > (1 << 26)) {
    fclose(f);
    return;
  }
  r->pnv = head[0], r->dim = head[1];
  size_t rec = (size_t)r->pnv * (size_t)r->dim;
  struct stat st; /* a header that promises more than the file holds is not believed */
  if (fstat(fileno(f), &st) || (size_t)st.st_size < 16 + (rec + 1) * sizeof(double)) {
    r->pnv = r->dim = 0;
    fclose(f);
    return;
  }
  r->pos = nan_array((size_t)r->ns * rec);
  double t;
  while (r->pos && fread(&t, sizeof t, 1, f) == 1) {
    int k = sample_of(c, t);
    double *dst = k >= 0 ? r->pos + (size_t)k * rec : NULL;
    if (dst ? fread(dst, sizeof *dst, rec, f) != rec : fseek(f, (long)(rec * sizeof t), SEEK_CUR))
      break;
    r->npos += dst != NULL;
  }
  fclose(f);
}

/* ------------------------------------------------------------------ entry */

int bench_read(const bench_cfg *c, const bench_job *j, int want_positions, bench_result *r) {
  memset(r, 0, sizeof *r);
  r->wall = r->time_step = r->max_rss_mb = r->step_median = NAN;
  char path[SW_PATHSZ + BENCH_IDSZ + 32];
  char *js = run_file(path, sizeof path, c, j, "summary.json") ? NULL : slurp(path, 1 << 20);
  if (js) {
    r->present = 1;
    read_summary(js, r);
    free(js);
  }
  classify(c, j, r);
  r->ns = bench_nsample(c);
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
