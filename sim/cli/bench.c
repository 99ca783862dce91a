/* bench.c — `sinew bench`: the command line and the plan (docs/benchmarks.md).
 *
 * A plan is the list of `sinew run` processes one mode needs:
 *   work precision  a reference (CVODE at rtol 1e-10, or a fixed-step method at a fine dt), a
 *                   second method confirming it, then every method x setting (dt for
 *                   fixed-step methods, rtol for adaptive ones) x repeat
 *   stability       per stiffness scale: a reference, then every fixed-step method x dt
 *   scaling         every method x grid size, a few steps each
 * It is written to DIR/plan_MODE.csv and DIR/bench_MODE.cfg before anything runs, so that the
 * runs can go to another engine (--emit-jobs) and `sinew bench --merge DIR` can read them. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "bench.h"
#include "cli.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const role_names[] = {"reference", "confirm", "run"};

/* ------------------------------------------------------------------ options */

typedef struct bench_cli {
  const char *scene, *out, *merge, *emit;
  char methods[BENCH_MAXLIST][SW_NAMESZ];
  int nmethod;
  double dts[BENCH_MAXLIST], rtols[BENCH_MAXLIST], scales[BENCH_MAXLIST], sizes[BENCH_MAXLIST];
  int ndt, nrtol, nscale, nsize;
  int orders[5], norder;       /* --max-orders: each adaptive method at each of these */
  double duration, sample_every;
  double scene_dt;             /* s: the scene's integrator.dt */
  int time;                    /* --time: 1 cpu, 0 wall, -1 not given */
} bench_cli;

static void bench_usage(FILE *fp) {
  fprintf(fp,
      "usage: sinew bench SCENE [--out DIR] [--methods M,...] [--dts DT,...] [--rtols R,...]\n"
      "                   [--max-orders Q,...] [--repeat N] [--duration T] [--sample-every S]\n"
      "                   [--reference M] [--reference-rtol R] [--reference-dt DT]\n"
      "                   [--confirm M] [--confirm-dt DT] [--confirm-tol E]\n"
      "                   [--reference-newton-tol V] [--newton-tol V]\n"
      "                   [--stability [--scales S,...] [--overdamped F]]\n"
      "                   [--scaling [--sizes N,...] [--steps N]]\n"
      "                   [--jobs N | --emit-jobs FILE] [--timeout S] [--diverged F]\n"
      "                   [--tension-diverged F]\n"
      "                   [--max-halvings N] [--time cpu|wall] [--no-charts]\n"
      "       sinew bench --merge DIR [--time cpu|wall] [--no-charts]\n"
      "\n"
      "  Runs SCENE under each method and setting, each in its own `sinew run` process, and\n"
      "  writes CSV files and PNG charts into DIR (default out/bench/<scene stem>).\n"
      "  Default mode: work precision.  A reference (--reference cvode:q5 at --reference-rtol\n"
      "  1e-10) confirmed by a second method (--confirm ida:q5, same rtol) agreeing to\n"
      "  --confirm-tol (1e-6 of the cloth's size).  A fixed-step reference or confirm (bdf2,\n"
      "  backward-euler: where CVODE and IDA fail, e.g. at contact) runs at --reference-dt\n"
      "  (default: the finest dt of the sweep / 8) or --confirm-dt (default: half the\n"
      "  reference's), each dividing the finest dt, with Newton's tolerance at\n"
      "  --reference-newton-tol (1e-5 m/s; 0: the scene's), and may halve a failed step up\n"
      "  to 4 times (or --max-halvings when larger).  Then every method x setting: fixed-step\n"
      "  methods at --dts (default: the scene's dt x 1, 1/2, 1/4, 1/8), adaptive ones at\n"
      "  --rtols (default 1e-3 .. 1e-6).  Errors at the common sample times (every\n"
      "  --sample-every s, a multiple of every dt; default ~duration/40) against the reference:\n"
      "  RMS position error / cloth size, tension XY max and mean series (L2, max), tendon\n"
      "  tension, final time; costs: CPU time (user + system) and wall time, each the\n"
      "  median of --repeat N, default 3; counts.\n"
      "  Observed order per method: the least-squares slope of log(position error) over\n"
      "  log(dt or rtol) on its converged range (orders.csv), with a warning where the\n"
      "  error does not fall with dt.  The sweep's fixed-step runs stop Newton at the\n"
      "  scene's tolerance, or at --newton-tol V (m/s; for order studies, 1e-6).\n"
      "  An adaptive method may carry its largest BDF order, NAME:qN (N = 1..5, e.g.\n"
      "  cvode:q2; --methods, --reference, --confirm); --max-orders 2,5 runs each adaptive\n"
      "  method of --methods given without one at each order, as separate lines\n"
      "  (cvode:q2, cvode:q5).\n"
      "  --stability  fixed-step methods x --dts (default dt x 8 .. 1/4) x --scales (stiffness\n"
      "               scale, default 1,10,100): stable, over-damped (lost more than\n"
      "               --overdamped 0.1 of the energy scale beyond the reference), failed,\n"
      "               or short (fewer than 10 steps: too few to tell); the largest stable\n"
      "               dt per method and scale\n"
      "  --scaling    per-step time, factorisation share and peak memory of --methods (default\n"
      "               backward-euler,bdf2,implicit-midpoint) on the scene's grid at --sizes\n"
      "               (vertices per side, default 32,64,128,256,512), --steps (3) steps each\n"
      "  --jobs N     N runs at a time on this machine (timings share its cores; default 1)\n"
      "  --emit-jobs FILE  write the runs as a job list (one shell command per line, for GNU\n"
      "               parallel or a Slurm array; DIR/slurm.sh) and stop; then\n"
      "               `sinew bench --merge DIR` reads their folders\n"
      "  --timeout S  kill a run after S s of wall time (recorded as failed: timed out)\n"
      "  --diverged F a finished run whose position error exceeds F x the cloth's size\n"
      "               (default 1) is recorded as failed (diverged)\n"
      "  --tension-diverged F  ... or whose tension error (tension XY max or mean, L2 over\n"
      "               the samples; tendons, largest) exceeds F x the reference's largest\n"
      "               tension (default 1)\n"
      "  --max-halvings N  a failed step of a run is retried with half the step at most N\n"
      "               times (default 0: dt means dt, a failed step fails the run);\n"
      "               work_precision.csv counts the retries\n"
      "  --time cpu|wall  the time of the printed table and the charts (default cpu: CPU\n"
      "               time moves less than wall time when other programs share the machine;\n"
      "               the CSV files have both)\n"
      "  --no-charts  CSV only (charts: /usr/bin/python3 tools/bench_charts.py DIR)\n");
}

/* A comma-separated list of positive numbers. */
static int parse_list(const char *opt, const char *s, double *out, int *n) {
  *n = 0;
  const char *p = s;
  while (*p) {
    char *end;
    errno = 0;
    double v = strtod(p, &end);
    if (errno || end == p || !isfinite(v) || v <= 0 || (*end && *end != ',') ||
        *n == BENCH_MAXLIST)
      return fprintf(stderr, "sinew: %s expects up to %d positive numbers separated by ',', "
                     "got '%s'\n", opt, BENCH_MAXLIST, s), -1;
    out[(*n)++] = v;
    p = *end ? end + 1 : end;
  }
  if (*n == 0) return fprintf(stderr, "sinew: %s expects a list of numbers\n", opt), -1;
  return 0;
}

/* A method of --methods, --reference or --confirm: a method's name, or an adaptive method's
 * NAME:qN; 1 if it is adaptive, 0 if not, -1 if neither. */
static int check_spec(const char *spec) {
  char name[SW_NAMESZ];
  int q;
  if (bench_method_split(spec, name, sizeof name, &q) || !cli_known_method(name)) return -1;
  int ad = sw_method_adaptive(name) == 1;
  return q && !ad ? -1 : ad;
}

/* "1,2,5": distinct orders 1..5. */
static int parse_orders(const char *opt, const char *s, bench_cli *c) {
  double v[BENCH_MAXLIST];
  int n;
  if (parse_list(opt, s, v, &n)) return -1;
  c->norder = 0;
  for (int k = 0; k < n; k++) {
    int dup = 0;
    for (int i = 0; i < c->norder; i++) dup |= c->orders[i] == (int)v[k];
    if (v[k] != floor(v[k]) || v[k] < 1 || v[k] > 5 || dup)
      return fprintf(stderr, "sinew: %s expects distinct integers 1..5, got '%s'\n", opt, s), -1;
    c->orders[c->norder++] = (int)v[k];
  }
  return 0;
}

static int parse_methods(const char *s, bench_cli *c) {
  c->nmethod = 0;
  const char *p = s;
  while (*p) {
    size_t len = strcspn(p, ",");
    if (len == 0 || len >= SW_NAMESZ || c->nmethod == BENCH_MAXLIST)
      return fprintf(stderr, "sinew: --methods expects method names separated by ','\n"), -1;
    char *name = c->methods[c->nmethod++];
    memcpy(name, p, len);
    name[len] = '\0';
    if (check_spec(name) < 0 || !strcmp(name, "static"))
      return fprintf(stderr, "sinew: --methods: unknown or static method '%s' (see sinew "
                     "--help; an adaptive one may be NAME:qN, N = 1..5)\n", name), -1;
    p += len + (p[len] == ',');
  }
  return 0;
}

/* One option with a value; returns 1 if consumed, 0 if not ours, -1 on a bad value. */
static int parse_valued(const char *a, const char *v, bench_cli *c, bench_cfg *g) {
  if (!strcmp(a, "--out")) return c->out = v, 1;
  if (!strcmp(a, "--merge")) return c->merge = v, 1;
  if (!strcmp(a, "--emit-jobs")) return c->emit = v, 1;
  if (!strcmp(a, "--methods")) return parse_methods(v, c) ? -1 : 1;
  if (!strcmp(a, "--dts")) return parse_list(a, v, c->dts, &c->ndt) ? -1 : 1;
  if (!strcmp(a, "--rtols")) return parse_list(a, v, c->rtols, &c->nrtol) ? -1 : 1;
  if (!strcmp(a, "--max-orders")) return parse_orders(a, v, c) ? -1 : 1;
  if (!strcmp(a, "--scales")) return parse_list(a, v, c->scales, &c->nscale) ? -1 : 1;
  if (!strcmp(a, "--sizes")) return parse_list(a, v, c->sizes, &c->nsize) ? -1 : 1;
  if (!strcmp(a, "--duration")) return cli_number(a, v, 0, &c->duration) ? -1 : 1;
  if (!strcmp(a, "--sample-every")) return cli_number(a, v, 0, &c->sample_every) ? -1 : 1;
  if (!strcmp(a, "--reference-rtol")) return cli_number(a, v, 0, &g->ref_rtol) ? -1 : 1;
  if (!strcmp(a, "--confirm-tol")) return cli_number(a, v, 0, &g->confirm_tol) ? -1 : 1;
  if (!strcmp(a, "--overdamped")) return cli_number(a, v, 0, &g->overdamped) ? -1 : 1;
  if (!strcmp(a, "--diverged")) return cli_number(a, v, 0, &g->diverged) ? -1 : 1;
  if (!strcmp(a, "--tension-diverged"))
    return cli_number(a, v, 0, &g->tension_diverged) ? -1 : 1;
  if (!strcmp(a, "--timeout")) return cli_number(a, v, 1, &g->timeout) ? -1 : 1;
  if (!strcmp(a, "--repeat")) return cli_int(a, v, 1, 100, &g->repeat) ? -1 : 1;
  if (!strcmp(a, "--jobs")) return cli_int(a, v, 1, 256, &g->jobs) ? -1 : 1;
  if (!strcmp(a, "--steps")) return cli_int(a, v, 1, 100000, &g->steps) ? -1 : 1;
  if (!strcmp(a, "--max-halvings")) return cli_int(a, v, 0, 60, &g->max_halvings) ? -1 : 1;
  if (!strcmp(a, "--reference-dt")) return cli_number(a, v, 0, &g->ref_dt) ? -1 : 1;
  if (!strcmp(a, "--confirm-dt")) return cli_number(a, v, 0, &g->confirm_dt) ? -1 : 1;
  if (!strcmp(a, "--reference-newton-tol"))
    return cli_number(a, v, 1, &g->ref_newton_tol) ? -1 : 1;
  if (!strcmp(a, "--newton-tol")) return cli_number(a, v, 1, &g->newton_tol) ? -1 : 1;
  if (!strcmp(a, "--time")) {
    if (strcmp(v, "cpu") && strcmp(v, "wall"))
      return fprintf(stderr, "sinew: --time expects cpu or wall, got '%s'\n", v), -1;
    return c->time = g->time_cpu = !strcmp(v, "cpu"), 1;
  }
  if (!strcmp(a, "--reference") || !strcmp(a, "--confirm")) {
    char *dst = a[2] == 'r' ? g->ref_method : g->confirm_method;
    if (check_spec(v) < 0 || !strcmp(v, "static") || strlen(v) >= SW_NAMESZ)
      return fprintf(stderr, "sinew: %s expects an adaptive method (cvode, ida, or with its "
                     "largest order: cvode:q5) or a fixed-step one (bdf2, backward-euler, ...: "
                     "at --reference-dt), got '%s'\n", a, v), -1;
    snprintf(dst, SW_NAMESZ, "%s", v);
    return 1;
  }
  return 0;
}

static int parse_bench_args(int argc, char **argv, bench_cli *c, bench_cfg *g) {
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) return bench_usage(stdout), 1;
    if (!strcmp(a, "--stability")) g->mode = BM_STABILITY;
    else if (!strcmp(a, "--scaling")) g->mode = BM_SCALING;
    else if (!strcmp(a, "--no-charts")) g->charts = 0;
    else if (a[0] == '-' && a[1]) {
      int rc = i + 1 < argc ? parse_valued(a, argv[i + 1], c, g) : 0;
      if (rc < 0) return -1;
      if (rc == 0)
        return fprintf(stderr, "sinew: bench: unknown option or missing value: %s (see sinew "
                       "bench --help)\n", a), -1;
      i++;
    } else if (!c->scene) c->scene = a;
    else return fprintf(stderr, "sinew: bench: more than one scene given: %s\n", a), -1;
  }
  if (!c->scene && !c->merge)
    return fprintf(stderr, "sinew: bench: no scene file given (see sinew bench --help)\n"), -1;
  if (c->scene && c->merge)
    return fprintf(stderr, "sinew: bench: give a scene or --merge DIR, not both\n"), -1;
  if (c->emit && g->jobs > 1)
    return fprintf(stderr, "sinew: bench: --emit-jobs and --jobs exclude each other\n"), -1;
  return 0;
}

/* ------------------------------------------------------------------- plan */

static void job_id(bench_job *j, int mode, const char *what) {
  char v[32];
  bench_fmt(v, sizeof v, j->adaptive ? j->rtol : j->dt);
  const char *pre = mode == BM_WORK ? "wp" : mode == BM_STABILITY ? "st" : "sc";
  char sc[40] = "";
  if (mode == BM_STABILITY) {
    char s[24];
    bench_fmt(s, sizeof s, j->scale);
    snprintf(sc, sizeof sc, "_s%s", s);
  }
  if (what) snprintf(j->id, sizeof j->id, "%s%s_%s", pre, sc, what);
  else if (mode == BM_SCALING)
    snprintf(j->id, sizeof j->id, "%s_%s_n%d_r%d", pre, j->method, j->grid, j->rep);
  else
    snprintf(j->id, sizeof j->id, "%s%s_%s_%s%s_r%d", pre, sc, j->method,
             j->adaptive ? "rtol" : "dt", v, j->rep);
  for (char *q = j->id; *q; q++)
    if (*q == ':') *q = '_'; /* cvode:q2 -> cvode_q2 */
}

static bench_job *add_job(bench_plan *p, int cap) {
  if (p->njob >= cap) return NULL;
  bench_job *j = &p->job[p->njob++];
  memset(j, 0, sizeof *j);
  j->scale = 1.0;
  j->rep = 1;
  return j;
}

/* atol for an rtol: 1 % of the cloth's size times rtol (m; the same number in m/s). */
static double atol_for(const bench_cfg *g, double rtol) { return 1e-2 * g->size * rtol; }

/* The reference or confirm run: an adaptive method at --reference-rtol, logged every log_dt
 * (s); a fixed-step one at its own step, --reference-dt or --confirm-dt. */
static void add_reference(bench_plan *p, int cap, int role, const char *method, double scale,
                          double log_dt) {
  const bench_cfg *g = &p->cfg;
  bench_job *j = add_job(p, cap);
  if (!j) return;
  j->role = role;
  snprintf(j->method, sizeof j->method, "%s", method);
  j->adaptive = check_spec(method) == 1;
  j->dt = j->adaptive ? log_dt : role == BR_REFERENCE ? g->ref_dt : g->confirm_dt;
  j->rtol = j->adaptive ? g->ref_rtol : 0.0;
  j->atol = j->adaptive ? atol_for(g, g->ref_rtol) : 0.0;
  j->scale = scale;
  job_id(j, g->mode, role == BR_REFERENCE ? "reference" : "confirm");
}

static void add_run(bench_plan *p, int cap, const char *method, double setting, double sample,
                    double scale, int rep) {
  const bench_cfg *g = &p->cfg;
  bench_job *j = add_job(p, cap);
  if (!j) return;
  j->role = BR_RUN;
  snprintf(j->method, sizeof j->method, "%s", method);
  j->adaptive = check_spec(method) == 1;
  j->dt = j->adaptive ? sample : setting;
  j->rtol = j->adaptive ? setting : 0.0;
  j->atol = j->adaptive ? atol_for(g, setting) : 0.0;
  j->scale = scale;
  j->rep = rep;
  job_id(j, g->mode, NULL);
}

/* The smallest dt: the log interval of adaptive references (CVODE and IDA interpolate to it,
 * their steps are not limited by it); a fixed-step reference's step divides it. */
static double finest(const bench_cli *c) {
  double h = INFINITY;
  for (int k = 0; k < c->ndt; k++) h = fmin(h, c->dts[k]);
  return h;
}

static void plan_work(bench_plan *p, const bench_cli *c, int cap) {
  const bench_cfg *g = &p->cfg;
  add_reference(p, cap, BR_REFERENCE, g->ref_method, 1.0, finest(c));
  add_reference(p, cap, BR_CONFIRM, g->confirm_method, 1.0, finest(c));
  for (int m = 0; m < c->nmethod; m++) {
    int ad = check_spec(c->methods[m]) == 1;
    int n = ad ? c->nrtol : c->ndt;
    for (int k = 0; k < n; k++)
      for (int r = 1; r <= g->repeat; r++)
        add_run(p, cap, c->methods[m], ad ? c->rtols[k] : c->dts[k], g->sample, 1.0, r);
  }
}

static void plan_stability(bench_plan *p, const bench_cli *c, int cap) {
  const bench_cfg *g = &p->cfg;
  for (int s = 0; s < c->nscale; s++) {
    add_reference(p, cap, BR_REFERENCE, g->ref_method, c->scales[s], finest(c));
    for (int m = 0; m < c->nmethod; m++)
      for (int k = 0; k < c->ndt; k++)
        add_run(p, cap, c->methods[m], c->dts[k], g->sample, c->scales[s], 1);
  }
}

static void plan_scaling(bench_plan *p, const bench_cli *c, int cap) {
  const bench_cfg *g = &p->cfg;
  for (int m = 0; m < c->nmethod; m++)
    for (int k = 0; k < c->nsize; k++)
      for (int r = 1; r <= g->repeat; r++) {
        bench_job *j = add_job(p, cap);
        if (!j) return;
        j->role = BR_RUN;
        snprintf(j->method, sizeof j->method, "%s", c->methods[m]);
        j->dt = c->scene_dt;
        j->grid = (int)c->sizes[k];
        j->rep = r;
        job_id(j, BM_SCALING, NULL);
      }
}

/* ------------------------------------------------------------- defaults */

static void default_methods(bench_cli *c, int mode) {
  static const char *const scaling[] = {"backward-euler", "bdf2", "implicit-midpoint"};
  c->nmethod = 0;
  if (mode == BM_SCALING) {
    for (int k = 0; k < 3; k++) snprintf(c->methods[c->nmethod++], SW_NAMESZ, "%s", scaling[k]);
    return;
  }
  for (const char *const *n = sw_method_names(); *n; n++)
    if (strcmp(*n, "static") && (mode == BM_WORK || sw_method_adaptive(*n) == 0))
      snprintf(c->methods[c->nmethod++], SW_NAMESZ, "%s", *n);
}

/* --max-orders: every adaptive method named without an order becomes one method per order. */
static int expand_orders(bench_cli *c) {
  if (!c->norder) return 0;
  char in[BENCH_MAXLIST][SW_NAMESZ];
  int n = c->nmethod;
  memcpy(in, c->methods, sizeof in);
  c->nmethod = 0;
  for (int m = 0; m < n; m++) {
    int plain = check_spec(in[m]) == 1 && !strchr(in[m], ':');
    for (int k = 0; k < (plain ? c->norder : 1); k++) {
      if (c->nmethod == BENCH_MAXLIST)
        return fprintf(stderr, "sinew: bench: more than %d methods\n", BENCH_MAXLIST), -1;
      char *dst = c->methods[c->nmethod++];
      if (plain) snprintf(dst, SW_NAMESZ, "%.*s:q%d", SW_NAMESZ - 5, in[m], c->orders[k]);
      else memcpy(dst, in[m], SW_NAMESZ);
    }
  }
  return 0;
}

static void defaults(bench_cli *c, bench_cfg *g, const sw_model *m) {
  static const double work_dt[] = {1, 0.5, 0.25, 0.125}, stab_dt[] = {8, 4, 2, 1, 0.5, 0.25};
  static const double rtols[] = {1e-3, 1e-4, 1e-5, 1e-6}, scales[] = {1, 10, 100};
  static const double sizes[] = {32, 64, 128, 256, 512};
  c->scene_dt = m->opt.dt;
  if (!c->nmethod) default_methods(c, g->mode);
  if (!c->ndt) {
    const double *f = g->mode == BM_STABILITY ? stab_dt : work_dt;
    c->ndt = g->mode == BM_STABILITY ? 6 : 4;
    for (int k = 0; k < c->ndt; k++) c->dts[k] = m->opt.dt * f[k];
  }
  if (!c->nrtol) c->nrtol = 4, memcpy(c->rtols, rtols, sizeof rtols);
  if (!c->nscale) c->nscale = 3, memcpy(c->scales, scales, sizeof scales);
  if (!c->nsize) c->nsize = 5, memcpy(c->sizes, sizes, sizeof sizes);
  g->duration = c->duration > 0 ? c->duration : m->opt.duration;
  if (g->mode == BM_SCALING) g->duration = g->steps * m->opt.dt;
  if (g->ref_rtol <= 0) g->ref_rtol = g->mode == BM_STABILITY ? 1e-8 : 1e-10;
  if (g->max_halvings < 0) g->max_halvings = 0; /* dt means dt (--max-halvings to change) */
}

/* Whether q = a / b is a whole number >= 1 (to 1e-6 of it). */
static int whole_ratio(double a, double b) {
  double q = a / b;
  return q >= 1.0 - 1e-6 && fabs(q - floor(q + 0.5)) <= 1e-6 * q;
}

/* The step (s) of a fixed-step reference (what: "--reference-dt") or confirm run: given, or
 * def; it must divide the finest dt of the sweep, so that the run is at least as fine as every
 * run and logs at every sample time.  An adaptive one takes no step (given must be 0). */
static int ref_step(const char *what, const char *method, double given, double def,
                    double fine, double *dt) {
  if (check_spec(method) == 1) {
    if (given > 0)
      return fprintf(stderr, "sinew: bench: %s is for a fixed-step method; %s is adaptive (its "
                     "accuracy is --reference-rtol)\n", what, method), -1;
    return *dt = 0.0, 0;
  }
  *dt = given > 0 ? given : def;
  if (whole_ratio(fine, *dt)) return 0;
  char a[32], b[32];
  bench_fmt(a, sizeof a, *dt), bench_fmt(b, sizeof b, fine);
  return fprintf(stderr, "sinew: bench: %s %s s does not divide the finest dt of the sweep (%s "
                 "s): the %s run must log at every sample time; choose %s / N\n", what, a, b,
                 method, b), -1;
}

/* The steps of fixed-step references: --reference-dt (default the finest dt / 8) and
 * --confirm-dt (default half the reference's: a confirm by the same method then measures the
 * reference's own error). */
static int reference_steps(const bench_cli *c, bench_cfg *g) {
  double fine = finest(c), rdt = 0.0;
  if (ref_step("--reference-dt", g->ref_method, g->ref_dt, fine / 8.0, fine, &rdt)) return -1;
  double cdef = 0.5 * (rdt > 0 ? rdt : fine / 8.0);
  if (ref_step("--confirm-dt", g->confirm_method, g->confirm_dt, cdef, fine, &g->confirm_dt))
    return -1;
  g->ref_dt = rdt;
  return 0;
}

/* The common sample interval: a multiple of every dt (checked), ~duration/40 by default. */
static int sample_interval(const bench_cli *c, bench_cfg *g) {
  double big = 0.0;
  for (int k = 0; k < c->ndt; k++) big = fmax(big, c->dts[k]);
  g->sample = c->sample_every;
  if (g->sample <= 0) g->sample = big * fmax(1.0, floor(g->duration / 40.0 / big + 0.5));
  for (int k = 0; k < c->ndt; k++) {
    double q = g->sample / c->dts[k];
    if (fabs(q - floor(q + 0.5)) > 1e-6 * q || q < 0.5) {
      char a[32], b[32];
      bench_fmt(a, sizeof a, c->dts[k]);
      bench_fmt(b, sizeof b, g->sample);
      return fprintf(stderr, "sinew: bench: dt %s does not divide the sample interval %s s; "
                     "choose --dts that divide it or set --sample-every\n", a, b), -1;
    }
  }
  return 0;
}

static double diagonal(const sw_model *m) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, s = 0;
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < m->dim; a++)
      lo[a] = fmin(lo[a], m->x0[i * m->dim + a]), hi[a] = fmax(hi[a], m->x0[i * m->dim + a]);
  for (int a = 0; a < m->dim; a++) s += (hi[a] - lo[a]) * (hi[a] - lo[a]);
  return sqrt(s);
}

/* Load the scene (and, for scaling, at the first size) so that bad input stops here. */
static int check_scene(bench_cli *c, bench_cfg *g) {
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_load(c->scene, err, sizeof err);
  if (!m) return fprintf(stderr, "sinew: %s\n", err), -1;
  defaults(c, g, m);
  g->size = diagonal(m);
  sw_model_free(m);
  if (expand_orders(c)) return -1;
  if (g->mode == BM_SCALING) {
    for (int k = 0; k < c->nsize; k++)
      if (c->sizes[k] != floor(c->sizes[k]) || c->sizes[k] < 2 || c->sizes[k] > 4096)
        return fprintf(stderr, "sinew: --sizes expects integers 2..4096 (vertices per side)\n"),
               -1;
    sw_scene_overrides ov = {.grid = {(int)c->sizes[0], (int)c->sizes[0]}};
    m = sw_scene_load_ex(c->scene, &ov, err, sizeof err);
    if (!m) return fprintf(stderr, "sinew: bench --scaling: %s\n", err), -1;
    sw_model_free(m);
    g->sample = g->duration; /* no samples: counters and timings only */
    return 0;
  }
  if (!(g->size > 0)) return fprintf(stderr, "sinew: bench: %s has zero size\n", c->scene), -1;
  return sample_interval(c, g) || reference_steps(c, g) ? -1 : 0;
}

/* ------------------------------------------------------------ plan files */

static int mkdirs(const char *path) {
  char buf[SW_PATHSZ];
  snprintf(buf, sizeof buf, "%s", path);
  for (char *p = buf + 1; *p; p++)
    if (*p == '/') {
      *p = '\0';
      if (mkdir(buf, 0777) && errno != EEXIST) return -1;
      *p = '/';
    }
  return mkdir(buf, 0777) && errno != EEXIST ? -1 : 0;
}

static void num(FILE *f, const char *key, double v) {
  char b[32];
  bench_fmt(b, sizeof b, v);
  fprintf(f, "%s = %s\n", key, b);
}

/* The machine's CPU for the charts' footnotes: /proc/cpuinfo's first "model name". */
static const char *cpu_model(char *out, size_t sz) {
  char line[256];
  snprintf(out, sz, "unknown CPU");
  FILE *f = fopen("/proc/cpuinfo", "r");
  if (!f) return out;
  while (fgets(line, sizeof line, f)) {
    char *colon = strchr(line, ':');
    if (strncmp(line, "model name", 10) || !colon) continue;
    colon += 1 + (colon[1] == ' ');
    snprintf(out, sz, "%.*s", (int)strcspn(colon, "\n"), colon);
    break;
  }
  fclose(f);
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  size_t len = strlen(out);
  if (n > 0 && len + 24 < sz) snprintf(out + len, sz - len, ", %ld cores", n);
  return out;
}

static int write_cfg(const bench_cfg *g) {
  char path[SW_PATHSZ + 64], tmp[SW_PATHSZ + 96];
  snprintf(path, sizeof path, "%s/bench_%s.cfg", g->dir, bench_mode_name(g->mode));
  FILE *f = bench_create(path, tmp, sizeof tmp);
  if (!f) return -1;
  fprintf(f, "# sinew bench settings (read by sinew bench --merge)\nmode = %s\nscene = %s\n"
          "exe = %s\nreference = %s\nconfirm = %s\n", bench_mode_name(g->mode), g->scene, g->exe,
          g->ref_method, g->confirm_method);
  num(f, "duration", g->duration), num(f, "sample", g->sample), num(f, "size", g->size);
  num(f, "reference_rtol", g->ref_rtol), num(f, "confirm_tol", g->confirm_tol);
  num(f, "reference_dt", g->ref_dt), num(f, "confirm_dt", g->confirm_dt);
  num(f, "reference_newton_tol", g->ref_newton_tol), num(f, "newton_tol", g->newton_tol);
  num(f, "overdamped", g->overdamped), num(f, "diverged", g->diverged);
  num(f, "tension_diverged", g->tension_diverged);
  num(f, "timeout", g->timeout);
  fprintf(f, "repeat = %d\nsteps = %d\nmax_halvings = %d\ntime = %s\n", g->repeat, g->steps,
          g->max_halvings, g->time_cpu ? "cpu" : "wall");
  char cpu[160];
  fprintf(f, "version = %s\ncpu = %s\n", SW_VERSION, cpu_model(cpu, sizeof cpu));
  return bench_commit(f, tmp);
}

static int write_plan(const bench_plan *p) {
  char path[SW_PATHSZ + 64], tmp[SW_PATHSZ + 96];
  if (write_cfg(&p->cfg)) return -1;
  snprintf(path, sizeof path, "%s/plan_%s.csv", p->cfg.dir, bench_mode_name(p->cfg.mode));
  FILE *f = bench_create(path, tmp, sizeof tmp);
  if (!f) return -1;
  fprintf(f, "id,role,method,adaptive,dt,rtol,atol,scale,grid,rep\n");
  for (int k = 0; k < p->njob; k++) {
    const bench_job *j = &p->job[k];
    char dt[32], rt[32], at[32], sc[32];
    bench_fmt(dt, sizeof dt, j->dt), bench_fmt(rt, sizeof rt, j->rtol);
    bench_fmt(at, sizeof at, j->atol), bench_fmt(sc, sizeof sc, j->scale);
    fprintf(f, "%s,%s,%s,%d,%s,%s,%s,%s,%d,%d\n", j->id, role_names[j->role], j->method,
            j->adaptive, dt, rt, at, sc, j->grid, j->rep);
  }
  return bench_commit(f, tmp);
}

/* -------------------------------------------------------- reading a plan */

/* The plan's files are read as data, not trusted: every value a whole number in its range, or
 * "FILE:LINE: KEY = VALUE; expected ..." (a plan edited by hand says where). */

/* A whole finite number at least lo (above lo when strict); 0, or -1. */
static int plan_num(const char *s, double lo, int strict, double *v) {
  char *end;
  *v = strtod(s, &end);
  return end == s || *end || !isfinite(*v) || *v < lo || (strict && *v == lo) ? -1 : 0;
}

/* A whole integer in [lo, hi]; 0, or -1. */
static int plan_int(const char *s, long lo, long hi, int *v) {
  char *end;
  errno = 0;
  long x = strtol(s, &end, 10);
  if (end == s || *end || errno || x < lo || x > hi) return -1;
  return *v = (int)x, 0;
}

static int cfg_line(bench_cfg *g, const char *key, const char *val, char *why, size_t sz) {
  if (!strcmp(key, "mode")) {
    for (int k = 0; k < BM_NMODE; k++)
      if (!strcmp(val, bench_mode_name(k))) return g->mode = k, 0;
    return snprintf(why, sz, "expected work_precision, stability or scaling"), -1;
  }
  if (!strcmp(key, "time")) {
    if (strcmp(val, "cpu") && strcmp(val, "wall"))
      return snprintf(why, sz, "expected cpu or wall"), -1;
    return g->time_cpu = !strcmp(val, "cpu"), 0;
  }
  struct { const char *k; char *s; size_t sz; } str[] = {{"scene", g->scene, SW_PATHSZ},
      {"exe", g->exe, SW_PATHSZ}, {"reference", g->ref_method, SW_NAMESZ},
      {"confirm", g->confirm_method, SW_NAMESZ}};
  for (size_t k = 0; k < sizeof str / sizeof *str; k++)
    if (!strcmp(key, str[k].k)) return snprintf(str[k].s, str[k].sz, "%s", val), 0;
  /* lo: the least value; strict: above it */
  struct { const char *k; double *v; double lo; int strict; } nums[] = {
      {"duration", &g->duration, 0, 0}, {"sample", &g->sample, 0, 1}, {"size", &g->size, 0, 1},
      {"reference_rtol", &g->ref_rtol, 0, 0}, {"confirm_tol", &g->confirm_tol, 0, 0},
      {"reference_dt", &g->ref_dt, 0, 0}, {"confirm_dt", &g->confirm_dt, 0, 0},
      {"reference_newton_tol", &g->ref_newton_tol, 0, 0}, {"newton_tol", &g->newton_tol, 0, 0},
      {"overdamped", &g->overdamped, 0, 0},
      {"diverged", &g->diverged, 0, 1}, {"tension_diverged", &g->tension_diverged, 0, 1},
      {"timeout", &g->timeout, 0, 0}};
  for (size_t k = 0; k < sizeof nums / sizeof *nums; k++)
    if (!strcmp(key, nums[k].k))
      return plan_num(val, nums[k].lo, nums[k].strict, nums[k].v)
                 ? snprintf(why, sz, "expected a number %s 0", nums[k].strict ? ">" : ">="), -1
                 : 0;
  struct { const char *k; int *v; long lo; } ints[] = {{"repeat", &g->repeat, 1},
      {"steps", &g->steps, 1}, {"max_halvings", &g->max_halvings, -1}};
  for (size_t k = 0; k < sizeof ints / sizeof *ints; k++)
    if (!strcmp(key, ints[k].k))
      return plan_int(val, ints[k].lo, 1000000000L, ints[k].v)
                 ? snprintf(why, sz, "expected an integer >= %ld", ints[k].lo), -1 : 0;
  return 0; /* unknown keys: from a newer sinew; ignored */
}

/* DIR/bench_MODE.cfg: 1 when absent (this mode was not run here), -1 with err when a value is
 * not what `sinew bench` writes. */
static int read_cfg(const char *dir, int mode, bench_cfg *g, char *err, size_t errsz) {
  char path[SW_PATHSZ + 64], line[SW_PATHSZ + 64], why[128];
  snprintf(path, sizeof path, "%s/bench_%s.cfg", dir, bench_mode_name(mode));
  FILE *f = fopen(path, "r");
  if (!f) return 1;
  int rc = 0;
  for (int n = 1; !rc && fgets(line, sizeof line, f); n++) {
    line[strcspn(line, "\n")] = '\0';
    char *eq = strstr(line, " = ");
    if (line[0] == '#' || !eq) continue;
    *eq = '\0';
    if ((rc = cfg_line(g, line, eq + 3, why, sizeof why)))
      snprintf(err, errsz, "%s:%d: %s = %.60s; %s", path, n, line, eq + 3, why);
  }
  fclose(f);
  if (rc) return -1;
  if (g->mode != mode)
    return snprintf(err, errsz, "%s: mode = %s; expected %s (the file's name)", path,
                    bench_mode_name(g->mode), bench_mode_name(mode)), -1;
  /* at most 1e7 sample times: the readers allocate per sample */
  if (!(g->sample > 0 && g->size > 0 && g->duration / g->sample <= 1e7))
    return snprintf(err, errsz, "%s: duration %g s, sample %g s, size %g m; expected a sample "
                    "> 0 (at most 1e7 of them) and a size > 0", path, g->duration, g->sample,
                    g->size), -1;
  return 0;
}

/* One line of plan_MODE.csv: id,role,method,adaptive,dt,rtol,atol,scale,grid,rep; 0, or -1
 * with why (the field and what was expected). */
static int parse_job(char *line, bench_job *j, char *why, size_t sz) {
  static const char *const names[] = {"id", "role", "method", "adaptive", "dt", "rtol", "atol",
                                      "scale", "grid", "rep"};
  char *f[10], name[SW_NAMESZ];
  int n = 0, order, bad = -1;
  for (char *s = line; n < 10; n++) {
    f[n] = s;
    s = strchr(s, ',');
    if (!s) { n++; break; }
    *s++ = '\0';
  }
  if (n != 10) return snprintf(why, sz, "%d fields; expected 10 (%s)", n,
                               "id,role,method,adaptive,dt,rtol,atol,scale,grid,rep"), -1;
  memset(j, 0, sizeof *j);
  j->role = !strcmp(f[1], "reference") ? BR_REFERENCE : !strcmp(f[1], "confirm") ? BR_CONFIRM
            : !strcmp(f[1], "run") ? BR_RUN : -1;
  if (!*f[0] || strlen(f[0]) >= sizeof j->id || strchr(f[0], '/') || !strcmp(f[0], "..")) bad = 0;
  else if (j->role < 0) bad = 1;
  else if (bench_method_split(f[2], name, sizeof name, &order) || strlen(f[2]) >= sizeof j->method) bad = 2;
  else if (plan_int(f[3], 0, 1, &j->adaptive)) bad = 3;
  else if (plan_num(f[4], 0, 1, &j->dt)) bad = 4;
  else if (plan_num(f[5], 0, 0, &j->rtol)) bad = 5;
  else if (plan_num(f[6], 0, 0, &j->atol)) bad = 6;
  else if (plan_num(f[7], 0, 1, &j->scale)) bad = 7;
  else if (plan_int(f[8], 0, 100000, &j->grid)) bad = 8;
  else if (plan_int(f[9], 1, 1000000, &j->rep)) bad = 9;
  static const char *const want[] = {"a run folder's name", "reference, confirm or run",
      "a method name (NAME or NAME:qN)", "0 or 1", "a number > 0 (s)", "a number >= 0",
      "a number >= 0", "a number > 0", "an integer >= 0", "an integer >= 1"};
  if (bad >= 0)
    return snprintf(why, sz, "%s = '%.60s'; expected %s", names[bad], f[bad], want[bad]), -1;
  snprintf(j->id, sizeof j->id, "%s", f[0]);
  snprintf(j->method, sizeof j->method, "%s", f[2]);
  return 0;
}

int bench_plan_read(const char *dir, int mode, bench_plan *p, char *err, size_t errsz) {
  memset(p, 0, sizeof *p);
  p->cfg.tension_diverged = BENCH_TENSION_DIVERGED; /* a folder of an older sinew has none */
  p->cfg.time_cpu = BENCH_TIME_CPU;
  int rc = read_cfg(dir, mode, &p->cfg, err, errsz);
  if (rc) return rc;
  snprintf(p->cfg.dir, sizeof p->cfg.dir, "%s", dir);
  char path[SW_PATHSZ + 64], line[512], why[160];
  snprintf(path, sizeof path, "%s/plan_%s.csv", dir, bench_mode_name(mode));
  FILE *f = fopen(path, "r");
  if (!f) return snprintf(err, errsz, "%s: %s", path, strerror(errno)), -1;
  int cap = 0, lineno = 0;
  while (fgets(line, sizeof line, f)) {
    line[strcspn(line, "\r\n")] = '\0';
    if (lineno++ == 0) continue;
    if (p->njob == BENCH_MAX_JOBS) { /* a memory budget: each job takes 320 bytes */
      snprintf(err, errsz, "%s:%d: more than %d runs in the plan; expected fewer", path, lineno,
               BENCH_MAX_JOBS);
      return fclose(f), -1;
    }
    if (p->njob == cap) {
      cap = cap ? 2 * cap : 64;
      bench_job *nj = realloc(p->job, (size_t)cap * sizeof *nj);
      if (!nj) {
        snprintf(err, errsz, "%s:%d: out of memory for %d runs", path, lineno, cap);
        return fclose(f), -1;
      }
      p->job = nj;
    }
    if (parse_job(line, &p->job[p->njob], why, sizeof why)) {
      snprintf(err, errsz, "%s:%d: %s", path, lineno, why);
      fclose(f);
      return -1;
    }
    p->njob++;
  }
  fclose(f);
  return 0;
}

/* ------------------------------------------------------------------ main */

static int self_exe(char *out, size_t sz) {
  ssize_t n = readlink("/proc/self/exe", out, sz - 1);
  if (n <= 0 || (size_t)n >= sz - 1) return -1;
  out[n] = '\0';
  return 0;
}

/* The folder (created) and the absolute paths the runs will use. */
static int locate(const bench_cli *c, bench_cfg *g) {
  char stem[SW_NAMESZ], dir[SW_PATHSZ];
  const char *base = strrchr(c->scene, '/');
  base = base ? base + 1 : c->scene;
  snprintf(stem, sizeof stem, "%.*s", (int)strcspn(base, "."), base);
  if (c->out) snprintf(dir, sizeof dir, "%s", c->out);
  else snprintf(dir, sizeof dir, "out/bench/%s", stem);
  if (mkdirs(dir) || !realpath(dir, g->dir))
    return fprintf(stderr, "sinew: bench: cannot create the folder %s: %s\n", dir,
                   strerror(errno)), -1;
  if (!realpath(c->scene, g->scene))
    return fprintf(stderr, "sinew: bench: %s: %s\n", c->scene, strerror(errno)), -1;
  if (self_exe(g->exe, sizeof g->exe))
    return fprintf(stderr, "sinew: bench: cannot find the sinew executable\n"), -1;
  char sub[SW_PATHSZ + 16];
  snprintf(sub, sizeof sub, "%s/runs", g->dir);
  if (mkdirs(sub)) return fprintf(stderr, "sinew: bench: cannot create %s\n", sub), -1;
  snprintf(sub, sizeof sub, "%s/logs", g->dir);
  if (mkdirs(sub)) return fprintf(stderr, "sinew: bench: cannot create %s\n", sub), -1;
  return 0;
}

static int make_plan(const bench_cli *c, bench_plan *p) {
  const bench_cfg *g = &p->cfg;
  int cap = 2 + c->nscale + c->nmethod * BENCH_MAXLIST * (g->mode == BM_STABILITY ? c->nscale : 1)
                * g->repeat;
  p->job = calloc((size_t)cap, sizeof *p->job);
  if (!p->job) return fprintf(stderr, "sinew: bench: out of memory\n"), -1;
  if (g->mode == BM_WORK) plan_work(p, c, cap);
  else if (g->mode == BM_STABILITY) plan_stability(p, c, cap);
  else plan_scaling(p, c, cap);
  return 0;
}

/* time: --time (1 cpu, 0 wall), or -1: the folder's */
static int merge_all(const char *dir, int charts, int time) {
  int rc = 0, found = 0;
  for (int mode = 0; mode < BM_NMODE; mode++) {
    bench_plan p;
    char err[SW_ERRSZ] = "";
    int r = bench_plan_read(dir, mode, &p, err, sizeof err);
    if (r < 0) fprintf(stderr, "sinew: bench --merge: %s\n", err), rc = 2;
    if (r) { free(p.job); continue; }
    found = 1;
    p.cfg.charts = charts;
    if (time >= 0) p.cfg.time_cpu = time;
    int m = bench_merge(&p);
    rc = rc ? rc : m;
    free(p.job);
  }
  if (!found && !rc)
    return fprintf(stderr, "sinew: bench --merge: %s has no bench_*.cfg (not a bench folder)\n",
                   dir), 2;
  return rc;
}

int sw_bench_main(int argc, char **argv) {
  bench_cli c = {.time = -1};
  bench_plan p = {.cfg = {.mode = BM_WORK, .confirm_tol = 1e-6, .overdamped = 0.1,
                          .diverged = 1.0, .tension_diverged = BENCH_TENSION_DIVERGED,
                          .repeat = BENCH_REPEAT, .jobs = 1, .steps = 3, .charts = 1,
                          .max_halvings = -1, .ref_newton_tol = BENCH_REF_NEWTON_TOL,
                          .newton_tol = BENCH_NEWTON_TOL, .time_cpu = BENCH_TIME_CPU,
                          .ref_method = "cvode:q5", .confirm_method = "ida:q5"}};
  int rc = parse_bench_args(argc, argv, &c, &p.cfg);
  if (rc) return rc < 0 ? 2 : 0;
  if (c.merge) return merge_all(c.merge, p.cfg.charts, c.time);
  if (check_scene(&c, &p.cfg) || locate(&c, &p.cfg)) return 2;
  if (make_plan(&c, &p)) return 2;
  if (write_plan(&p)) return free(p.job), 2;
  if (c.emit) {
    char err[SW_ERRSZ];
    rc = bench_emit(&p, c.emit, err, sizeof err);
    if (rc) fprintf(stderr, "sinew: bench: %s\n", err);
    free(p.job);
    return rc ? 2 : 0;
  }
  rc = bench_execute(&p);
  if (!rc) rc = bench_merge(&p);
  free(p.job);
  return rc;
}
