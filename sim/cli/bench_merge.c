/* bench_merge.c — from the run folders of a plan to its CSV files and charts
 * (docs/benchmarks.md has every column):
 *   work precision  reference.csv (the reference and how well the second method agrees with
 *                   it) and work_precision.csv (errors and costs per method x setting)
 *   stability       stability.csv (class of every run) and stability_limits.csv
 *   scaling         scaling.csv (per-step time, shares, memory per method x size)
 * Errors are measured at the common sample times against the reference:
 *   position   e(t) = sqrt(mean_i |x_i - x_ref,i|^2) / L, L = the initial bounding-box diagonal;
 *              pos_err_max = max over samples, pos_err_final = at the final time
 *   series     L2 = sqrt(mean_k (s_k - r_k)^2) / max_k |r_k|, max = max_k |s_k - r_k| / max_k |r_k|
 *              (absolute when the reference series is zero) for tension XY max and mean, and
 *              the max form over every tendon's tension. */
#include "bench.h"
#include "cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* ------------------------------------------------------------------ errors */

static double pos_err_at(const bench_result *a, const bench_result *ref, int k, double size) {
  if (!a->pos || !ref->pos || a->pnv != ref->pnv || a->dim != ref->dim) return NAN;
  size_t rec = (size_t)a->pnv * (size_t)a->dim;
  const double *x = a->pos + (size_t)k * rec, *y = ref->pos + (size_t)k * rec;
  double s = 0.0;
  for (size_t i = 0; i < rec; i++) s += (x[i] - y[i]) * (x[i] - y[i]);
  return sqrt(s / a->pnv) / size; /* NaN if either sample is missing */
}

static double pos_err_max(const bench_result *a, const bench_result *ref, double size) {
  double m = NAN;
  for (int k = 0; k < a->ns; k++) {
    double e = pos_err_at(a, ref, k, size);
    if (isfinite(e)) m = isfinite(m) ? fmax(m, e) : e;
  }
  return m;
}

/* L2 (which = 0) or max (which = 1) error of series s against r, stride between values. */
static double series_err(const double *s, const double *r, int n, int stride, int which) {
  double sum = 0.0, big = 0.0, scale = 0.0;
  int used = 0;
  for (int k = 0; k < n * stride; k++) {
    if (!isfinite(r[k])) continue;
    scale = fmax(scale, fabs(r[k]));
    if (!isfinite(s[k])) continue;
    double e = s[k] - r[k];
    sum += e * e, big = fmax(big, fabs(e)), used++;
  }
  if (!used) return NAN;
  double v = which ? big : sqrt(sum / used);
  return scale > 0 ? v / scale : v;
}

typedef struct errors {
  double pos_max, pos_final, txy_max_l2, txy_max_linf, txy_mean_l2, txy_mean_linf, tendon;
} errors;

static void measure(const bench_result *a, const bench_result *ref, double size, errors *e) {
  e->pos_max = pos_err_max(a, ref, size);
  e->pos_final = pos_err_at(a, ref, a->ns - 1, size);
  e->txy_max_l2 = series_err(a->txy_max, ref->txy_max, a->ns, 1, 0);
  e->txy_max_linf = series_err(a->txy_max, ref->txy_max, a->ns, 1, 1);
  e->txy_mean_l2 = series_err(a->txy_mean, ref->txy_mean, a->ns, 1, 0);
  e->txy_mean_linf = series_err(a->txy_mean, ref->txy_mean, a->ns, 1, 1);
  e->tendon = a->ntendon && a->ntendon == ref->ntendon && a->tendon && ref->tendon
                  ? series_err(a->tendon, ref->tendon, a->ns, a->ntendon, 1) : NAN;
}

/* ------------------------------------------------------------------ CSV */

static void put_num(FILE *f, double v) {
  if (v == 0.0) v = 0.0; /* no "-0" */
  if (isfinite(v)) fprintf(f, ",%.6g", v);
  else fputs(",", f);
}

/* A text field: commas, quotes and line breaks would break the CSV, so they become blanks. */
static void put_text(FILE *f, const char *s) {
  fputc(',', f);
  for (; *s; s++) fputc(*s == ',' || *s == '"' || *s == '\n' || *s == '\r' ? ' ' : *s, f);
}

/* DIR/NAME.tmp with its header line; close_csv renames it to DIR/NAME. */
static FILE *open_csv(const bench_cfg *c, const char *name, const char *header, char *tmp,
                      size_t sz) {
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/%s", c->dir, name);
  FILE *f = bench_create(path, tmp, sz);
  if (f) fprintf(f, "%s\n", header);
  return f;
}

static int close_csv(FILE *f, const char *tmp) { return bench_commit(f, tmp); }

/* --------------------------------------------------------- runs of a plan */

/* Same method and setting (and scale, grid) as job a: b is a repeat of a. */
static int same_setting(const bench_job *a, const bench_job *b) {
  return a->role == b->role && !strcmp(a->method, b->method) && a->dt == b->dt &&
         a->rtol == b->rtol && a->scale == b->scale && a->grid == b->grid;
}

/* Median, min and max of what(r) over the repeats of job k that finished ok; how many. */
typedef struct spread {
  double median, lo, hi;
  int n;
} spread;

static spread repeat_spread(const bench_plan *p, int k, double (*what)(const bench_result *)) {
  double v[128];
  int n = 0;
  for (int i = 0; i < p->njob && n < 128; i++) {
    if (!same_setting(&p->job[k], &p->job[i])) continue;
    bench_result r;
    bench_read(&p->cfg, &p->job[i], 0, &r);
    if (!strcmp(r.status, "ok") && isfinite(what(&r))) v[n++] = what(&r);
    bench_result_free(&r);
  }
  double med = bench_median(v, n); /* sorts v */
  return (spread){med, n ? v[0] : NAN, n ? v[n - 1] : NAN, n};
}

/* The other repeats of job k that are damaged, each named on stderr: they are left out of the
 * medians, and the table shows only the first repeat's status. */
static void warn_damaged_repeats(const bench_plan *p, int k) {
  for (int i = 0; i < p->njob; i++) {
    if (i == k || !same_setting(&p->job[k], &p->job[i])) continue;
    bench_result r;
    bench_read(&p->cfg, &p->job[i], 0, &r);
    if (!strcmp(r.status, "damaged"))
      fprintf(stderr, "sinew: bench: repeat %d of %s damaged, left out of the medians: %s\n",
              p->job[i].rep, p->job[k].id, r.message);
    bench_result_free(&r);
  }
}

static double wall_of(const bench_result *r) { return r->wall; }
static double cpu_of(const bench_result *r) { return r->cpu; }
static double step_of(const bench_result *r) { return r->step_median; }
static double rss_of(const bench_result *r) { return r->max_rss_mb; }

static int find_role(const bench_plan *p, int role, double scale) {
  for (int k = 0; k < p->njob; k++)
    if (p->job[k].role == role && p->job[k].scale == scale) return k;
  return -1;
}

/* Read the reference of a scale; 0 when it finished ok. */
static int read_reference(const bench_plan *p, double scale, bench_result *ref) {
  int k = find_role(p, BR_REFERENCE, scale);
  if (k < 0) return memset(ref, 0, sizeof *ref), -1;
  bench_read(&p->cfg, &p->job[k], 1, ref);
  if (!strcmp(ref->status, "ok") && ref->pos) return 0;
  fprintf(stderr, "sinew: bench: the reference run %s %s%s%s%s: no errors can be measured "
          "(logs/%s.log%s%s)\n", p->job[k].id, ref->status, ref->how[0] ? " (" : "", ref->how,
          ref->how[0] ? ")" : "", p->job[k].id, ref->message[0] ? "; " : "", ref->message);
  return -1;
}

/* A finished run farther from the reference than cfg.diverged x size has failed. */
static void check_diverged(const bench_cfg *c, bench_result *r, double pos_max) {
  if (strcmp(r->status, "ok") || !(pos_max > c->diverged)) return;
  snprintf(r->status, sizeof r->status, "failed");
  snprintf(r->how, sizeof r->how, "diverged (error %.3g x size)", pos_max);
}

/* A finished run also fails when a tension error exceeds cfg.tension_diverged (a fraction of
 * the reference's largest value): tension XY max and mean (L2 over the samples), the tendons'
 * (largest over the samples and tendons).  Positions alone miss a run whose shape is right and
 * whose tensions are not. */
static void check_tension(const bench_cfg *c, bench_result *r, const errors *e) {
  const struct { const char *what; double v; } m[] = {{"tension XY max", e->txy_max_l2},
      {"tension XY mean", e->txy_mean_l2}, {"tendon tension", e->tendon}};
  for (size_t k = 0; k < sizeof m / sizeof *m && !strcmp(r->status, "ok"); k++)
    if (m[k].v > c->tension_diverged) {
      snprintf(r->status, sizeof r->status, "failed");
      snprintf(r->how, sizeof r->how, "diverged (%s error %.3g)", m[k].what, m[k].v);
    }
}

/* -------------------------------------------------------- work precision */

static const char *const wp_header =
    "method,kind,setting,value,status,how,message,repeats,wall_s,wall_min_s,wall_max_s,cpu_s,"
    "cpu_min_s,cpu_max_s,steps,newton_iterations,force_evaluations,assemblies,factorizations,"
    "retries,pos_err_max,pos_err_final,"
    "txy_max_l2,txy_max_linf,txy_mean_l2,txy_mean_linf,tendon_err,run_dir";

/* One line of work_precision.csv and of the table; the run's point for its order into pt. */
static void wp_row(FILE *f, const bench_plan *p, int k, const bench_result *ref,
                   bench_point *pt) {
  const bench_job *j = &p->job[k];
  bench_result r;
  bench_read(&p->cfg, j, 1, &r);
  errors e = {NAN, NAN, NAN, NAN, NAN, NAN, NAN};
  if (!strcmp(r.status, "ok") && ref) measure(&r, ref, p->cfg.size, &e);
  check_diverged(&p->cfg, &r, e.pos_max);
  check_tension(&p->cfg, &r, &e);
  int ok = !strcmp(r.status, "ok");
  *pt = (bench_point){j->method, j->adaptive, ok, j->adaptive ? j->rtol : j->dt, e.pos_max};
  spread w = repeat_spread(p, k, wall_of), u = repeat_spread(p, k, cpu_of);
  warn_damaged_repeats(p, k);
  fprintf(f, "%s,%s,%s,%.6g,%s", j->method, j->adaptive ? "adaptive" : "fixed",
          j->adaptive ? "rtol" : "dt", j->adaptive ? j->rtol : j->dt, r.status);
  put_text(f, r.how), put_text(f, r.message);
  fprintf(f, ",%d", w.n);
  /* a failed run's times are its time to failure (first repeat) */
  double wall = ok ? w.median : strcmp(r.status, "damaged") ? r.wall : NAN; /* damaged: none */
  double cpu = ok ? u.median : strcmp(r.status, "damaged") ? r.cpu : NAN;
  put_num(f, wall), put_num(f, w.lo), put_num(f, w.hi);
  put_num(f, cpu), put_num(f, u.lo), put_num(f, u.hi);
  if (!strcmp(r.status, "damaged")) fputs(",,,,,,", f); /* its counters are not its own */
  else fprintf(f, ",%ld,%ld,%ld,%ld,%ld,%ld", r.steps, r.newton, r.force, r.assemble, r.factor,
               r.retries);
  if (!ok) e = (errors){NAN, NAN, NAN, NAN, NAN, NAN, NAN}; /* a failed run has no errors */
  put_num(f, e.pos_max), put_num(f, e.pos_final), put_num(f, e.txy_max_l2);
  put_num(f, e.txy_max_linf), put_num(f, e.txy_mean_l2), put_num(f, e.txy_mean_linf);
  put_num(f, e.tendon);
  fprintf(f, ",runs/%s\n", j->id);
  printf("  %-18s %-4s %-8.3g %-8s %10.3g %10.3g %9.3g s %9.3g s  %s\n", j->method,
         j->adaptive ? "rtol" : "dt", j->adaptive ? j->rtol : j->dt, r.status, e.pos_max,
         e.txy_max_l2, p->cfg.time_cpu ? cpu : wall, p->cfg.time_cpu ? wall : cpu, r.how);
  bench_result_free(&r);
}

/* "cvode:q5 rtol 1e-10" or "bdf2 dt 0.0003125 s" (a fixed-step job: its step). */
static void describe(char *out, size_t sz, const bench_job *j, const char *method) {
  char v[32];
  bench_fmt(v, sizeof v, j && !j->adaptive ? j->dt : j ? j->rtol : NAN);
  snprintf(out, sz, "%s %s %s%s", method, j && !j->adaptive ? "dt" : "rtol", v,
           j && !j->adaptive ? " s" : "");
}

/* The rtol and dt columns of a reference or confirm job (the one that does not apply: empty). */
static void put_setting(FILE *f, const bench_job *j) {
  put_num(f, j && j->adaptive ? j->rtol : NAN);
  put_num(f, j && !j->adaptive ? j->dt : NAN);
}

/* How a reference or confirm run ended, in a word or two: ok, damaged, timed out (S s), ... */
static const char *ended(int ok, const bench_result *r) {
  return ok ? "ok" : !strcmp(r->status, "damaged") ? "damaged" : r->how[0] ? r->how : "missing";
}

static const char *const ref_header =
    "method,rtol,dt,confirm_method,confirm_rtol,confirm_dt,pos_err,txy_err,tendon_err,bound,"
    "confirmed,wall_s,cpu_s,retries,confirm_retries,run_dir,confirm_dir";

/* reference.csv: the reference run and its agreement with the second method. */
static int wp_reference(const bench_plan *p, const bench_result *ref, int have_ref,
                        double *agreement) {
  const bench_cfg *c = &p->cfg;
  int kc = find_role(p, BR_CONFIRM, 1.0), kr = find_role(p, BR_REFERENCE, 1.0);
  const bench_job *jr = kr >= 0 ? &p->job[kr] : NULL, *jc = kc >= 0 ? &p->job[kc] : NULL;
  bench_result cr;
  errors e = {NAN, NAN, NAN, NAN, NAN, NAN, NAN};
  if (jc) bench_read(c, jc, 1, &cr);
  else memset(&cr, 0, sizeof cr);
  if (have_ref && jc && !strcmp(cr.status, "ok")) measure(&cr, ref, c->size, &e);
  int confirmed = isfinite(e.pos_max) && e.pos_max <= c->confirm_tol;
  *agreement = e.pos_max;
  char path[SW_PATHSZ + 64], rd[SW_NAMESZ + 48], cd[SW_NAMESZ + 48];
  FILE *f = open_csv(c, "reference.csv", ref_header, path, sizeof path);
  if (!f) return bench_result_free(&cr), -1;
  fprintf(f, "%s", c->ref_method), put_setting(f, jr);
  fprintf(f, ",%s", c->confirm_method), put_setting(f, jc);
  put_num(f, e.pos_max), put_num(f, e.txy_max_l2), put_num(f, e.tendon);
  put_num(f, c->confirm_tol);
  fprintf(f, ",%s", confirmed ? "yes" : "no");
  put_num(f, have_ref ? ref->wall : NAN), put_num(f, have_ref ? ref->cpu : NAN);
  fprintf(f, ",%ld,%ld", have_ref ? ref->retries : 0L, cr.retries);
  fprintf(f, ",runs/%s,runs/%s\n", jr ? jr->id : "", jc ? jc->id : "");
  describe(rd, sizeof rd, jr, c->ref_method), describe(cd, sizeof cd, jc, c->confirm_method);
  if (!have_ref || !jc || strcmp(cr.status, "ok")) /* a run that did not finish: how it ended */
    printf("reference: %s %s; %s %s: NOT CONFIRMED, nothing measured\n", rd,
           ended(have_ref, ref), cd, jc ? ended(!strcmp(cr.status, "ok"), &cr) : "missing");
  else
    printf("reference: %s; %s agrees to %.3g of the size (positions), %.3g (tension XY max): "
           "%s (bound %g)\n", rd, cd, e.pos_max, e.txy_max_l2,
           confirmed ? "confirmed" : "NOT CONFIRMED", c->confirm_tol);
  if (have_ref && (ref->retries || cr.retries))
    printf("reference: halved steps: %ld (reference), %ld (confirm)\n", ref->retries,
           cr.retries);
  bench_result_free(&cr);
  return close_csv(f, path) ? -1 : confirmed ? 0 : 1;
}

static int merge_work(const bench_plan *p) {
  bench_result ref;
  int have_ref = read_reference(p, 1.0, &ref) == 0;
  double agreement = NAN;
  int rc = wp_reference(p, &ref, have_ref, &agreement);
  char path[SW_PATHSZ + 64];
  FILE *f = open_csv(&p->cfg, "work_precision.csv", wp_header, path, sizeof path);
  bench_point *pt = calloc((size_t)p->njob + 1, sizeof *pt);
  if (!f || !pt) return bench_result_free(&ref), free(pt), f ? fclose(f) : 0, 2;
  printf("a run fails when its position error exceeds %g x the cloth's size or a tension "
         "error (XY max, XY mean, tendons) exceeds %g x the reference's largest\n",
         p->cfg.diverged, p->cfg.tension_diverged);
  printf("  %-18s %-4s %-8s %-8s %10s %10s %11s %11s\n", "method", "", "setting", "status",
         "pos err", "txy err", p->cfg.time_cpu ? "CPU" : "wall", p->cfg.time_cpu ? "wall" : "CPU");
  int npt = 0;
  for (int k = 0; k < p->njob; k++)
    if (p->job[k].role == BR_RUN && p->job[k].rep == 1)
      wp_row(f, p, k, have_ref ? &ref : NULL, &pt[npt++]);
  bench_result_free(&ref);
  int bad = close_csv(f, path) || (have_ref && bench_orders(&p->cfg, pt, npt, agreement));
  free(pt);
  if (bad) return 2;
  return !have_ref || rc ? 1 : 0;
}

/* ------------------------------------------------------------- stability */

/* The energy that moves in the reference: its largest kinetic energy plus the range of its
 * total (J); the yardstick of energy lost or gained. */
static double energy_scale(const bench_result *ref) {
  double kmax = 0.0, lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < ref->ns; k++) {
    if (isfinite(ref->kinetic[k])) kmax = fmax(kmax, ref->kinetic[k]);
    if (isfinite(ref->energy[k])) lo = fmin(lo, ref->energy[k]), hi = fmax(hi, ref->energy[k]);
  }
  return fmax(kmax + (hi > lo ? hi - lo : 0.0), 1e-12);
}

/* Largest energy lost (sign +1) or gained (-1) against the reference, / scale. */
static double energy_dev(const bench_result *r, const bench_result *ref, double sign) {
  double m = NAN, scale = energy_scale(ref);
  for (int k = 0; k < r->ns; k++) {
    double d = sign * (ref->energy[k] - r->energy[k]) / scale;
    if (isfinite(d)) m = isfinite(m) ? fmax(m, d) : d;
  }
  return m;
}

static const char *const st_header =
    "method,stiffness_scale,dt,status,how,energy_loss,energy_gain,pos_err_max,message,run_dir";

/* Stable, over-damped or failed (how); a gain of more than the energy scale is a blow-up. */
static void st_classify(const bench_cfg *c, bench_result *r, const bench_result *ref,
                        double *loss, double *gain, double *pos) {
  *loss = *gain = *pos = NAN;
  if (strcmp(r->status, "ok")) return;
  if (ref) {
    *loss = energy_dev(r, ref, 1.0), *gain = energy_dev(r, ref, -1.0);
    *pos = pos_err_max(r, ref, c->size);
  }
  check_diverged(c, r, *pos);
  if (strcmp(r->status, "ok")) return;
  if (*gain > 1.0) {
    snprintf(r->status, sizeof r->status, "failed");
    snprintf(r->how, sizeof r->how, "energy grew (%.3g x scale)", *gain);
  } else if (r->steps < BENCH_MIN_STABLE_STEPS) { /* too few steps to tell */
    snprintf(r->status, sizeof r->status, "short");
    snprintf(r->how, sizeof r->how, "%ld steps < %d", r->steps, BENCH_MIN_STABLE_STEPS);
  } else snprintf(r->status, sizeof r->status, *loss > c->overdamped ? "over-damped" : "stable");
}

typedef struct limit {
  char method[SW_NAMESZ];
  double scale, stable, failed;
  int tried;
} limit;

static void track_limit(limit *lim, int *nlim, const bench_job *j, const char *status) {
  int k = 0;
  while (k < *nlim && (strcmp(lim[k].method, j->method) || lim[k].scale != j->scale)) k++;
  if (k == *nlim) {
    lim[k] = (limit){.scale = j->scale, .stable = NAN, .failed = NAN};
    snprintf(lim[k].method, sizeof lim[k].method, "%s", j->method);
    ++*nlim;
  }
  lim[k].tried++;
  if (!strcmp(status, "stable") && !(lim[k].stable >= j->dt)) lim[k].stable = j->dt;
  if ((!strcmp(status, "failed") || !strcmp(status, "crashed")) && !(lim[k].failed <= j->dt))
    lim[k].failed = j->dt;
}

static int write_limits(const bench_cfg *c, const limit *lim, int n) {
  char path[SW_PATHSZ + 64];
  FILE *f = open_csv(c, "stability_limits.csv",
                     "method,stiffness_scale,largest_stable_dt,smallest_failed_dt,tried", path,
                     sizeof path);
  if (!f) return -1;
  printf("largest stable dt (s) per method and stiffness scale (stable: at least %d steps, "
         "energy not grown):\n", BENCH_MIN_STABLE_STEPS);
  for (int k = 0; k < n; k++) {
    fprintf(f, "%s,%g", lim[k].method, lim[k].scale);
    put_num(f, lim[k].stable), put_num(f, lim[k].failed);
    fprintf(f, ",%d\n", lim[k].tried);
    char stable[32] = "none stable", failed[48] = "none failed";
    if (isfinite(lim[k].stable)) snprintf(stable, sizeof stable, "%.4g", lim[k].stable);
    if (isfinite(lim[k].failed))
      snprintf(failed, sizeof failed, "smallest failed %.4g", lim[k].failed);
    printf("  %-18s x%-6g %11s   (%s)\n", lim[k].method, lim[k].scale, stable, failed);
  }
  return close_csv(f, path);
}

static int merge_stability(const bench_plan *p) {
  char path[SW_PATHSZ + 64];
  FILE *f = open_csv(&p->cfg, "stability.csv", st_header, path, sizeof path);
  limit *lim = calloc((size_t)p->njob + 1, sizeof *lim);
  if (!f || !lim) return free(lim), f ? fclose(f) : 0, 2;
  int nlim = 0, rc = 0;
  for (int k = 0; k < p->njob; k++) {
    const bench_job *j = &p->job[k];
    if (j->role != BR_RUN) continue;
    bench_result ref, r;
    int have_ref = read_reference(p, j->scale, &ref) == 0;
    rc |= !have_ref;
    bench_read(&p->cfg, j, 1, &r);
    double loss, gain, pos;
    st_classify(&p->cfg, &r, have_ref ? &ref : NULL, &loss, &gain, &pos);
    fprintf(f, "%s,%g,%g,%s", j->method, j->scale, j->dt, r.status);
    put_text(f, r.how), put_num(f, loss), put_num(f, gain), put_num(f, pos);
    put_text(f, r.message);
    fprintf(f, ",runs/%s\n", j->id);
    track_limit(lim, &nlim, j, r.status);
    bench_result_free(&r), bench_result_free(&ref);
  }
  if (close_csv(f, path) || write_limits(&p->cfg, lim, nlim)) rc = 2;
  free(lim);
  return rc;
}

/* --------------------------------------------------------------- scaling */

static int merge_scaling(const bench_plan *p) {
  char path[SW_PATHSZ + 64];
  FILE *f = open_csv(&p->cfg, "scaling.csv", "method,grid,vertices,dofs,steps,step_s,"
                     "assemble_s,factor_s,solve_s,factor_share,max_rss_mb,wall_s,cpu_s,status,"
                     "run_dir",
                     path, sizeof path);
  if (!f) return 2;
  printf("  %-18s %8s %9s %10s %8s %9s\n", "method", "vertices", "DOFs", "step (s)", "factor",
         "RSS (MB)");
  for (int k = 0; k < p->njob; k++) {
    const bench_job *j = &p->job[k];
    if (j->rep != 1) continue;
    bench_result r;
    bench_read(&p->cfg, j, 0, &r);
    int ok = !strcmp(r.status, "ok");
    warn_damaged_repeats(p, k);
    double step = ok ? repeat_spread(p, k, step_of).median : NAN;
    double ts = r.time_step > 0 ? r.time_step : NAN;
    fprintf(f, "%s,%d,%ld,%ld,%ld", j->method, j->grid, r.nv, r.dofs, r.steps);
    put_num(f, step), put_num(f, step * r.time_assemble / ts);
    put_num(f, step * r.time_factor / ts), put_num(f, step * r.time_solve / ts);
    put_num(f, r.time_factor / ts), put_num(f, ok ? repeat_spread(p, k, rss_of).median : NAN);
    put_num(f, ok ? repeat_spread(p, k, wall_of).median : NAN); /* s: the whole run */
    put_num(f, ok ? repeat_spread(p, k, cpu_of).median : NAN);
    fprintf(f, ",%s,runs/%s\n", r.status, j->id);
    printf("  %-18s %8ld %9ld %10.4g %7.0f%% %9.1f  %s\n", j->method, r.nv, r.dofs, step,
           100.0 * r.time_factor / ts, r.max_rss_mb, ok ? "" : r.how);
    bench_result_free(&r);
  }
  return close_csv(f, path) ? 2 : 0;
}

/* ----------------------------------------------------------------- charts */

#ifndef SW_CHARTS_SCRIPT
#define SW_CHARTS_SCRIPT "tools/bench_charts.py"
#endif

/* tools/bench_charts.py DIR through /usr/bin/python3 (Debian's matplotlib); $SINEW_CHARTS
 * names another script.  A missing Python or matplotlib is a warning: the CSV files stand. */
static void charts(const bench_cfg *c) {
  const char *script = getenv("SINEW_CHARTS");
  char installed[4200];
  if (!script || !*script) script = SW_CHARTS_SCRIPT;
  if (access(script, R_OK) && !getenv("SINEW_CHARTS") && !cli_package_dir(installed, 4096)) {
    strcat(installed, "/sinew/bench_charts.py"); /* a pip install: the copy in the package */
    script = installed;
  }
  if (access(script, R_OK) || access("/usr/bin/python3", X_OK)) {
    fprintf(stderr, "sinew: bench: no charts: %s or /usr/bin/python3 not found (the CSV files "
            "are complete; set SINEW_CHARTS to the script)\n", script);
    return;
  }
  fflush(NULL);
  pid_t pid = fork();
  if (pid == 0) {
    execl("/usr/bin/python3", "python3", script, c->dir, "--time", c->time_cpu ? "cpu" : "wall",
          (char *)NULL);
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status))
    fprintf(stderr, "sinew: bench: the chart script failed (%s %s); the CSV files are "
            "complete\n", script, c->dir);
}

int bench_merge(const bench_plan *p) {
  printf("%s of %s (%d runs) in %s\n", bench_mode_name(p->cfg.mode), p->cfg.scene, p->njob,
         p->cfg.dir);
  int rc = p->cfg.mode == BM_WORK ? merge_work(p)
           : p->cfg.mode == BM_STABILITY ? merge_stability(p) : merge_scaling(p);
  fflush(stdout);
  if (p->cfg.charts && rc != 2) charts(&p->cfg);
  return rc;
}
