/* run.c — the run loop: state -> integrator step -> diagnostics -> logs (DESIGN.md data flow).
 * A failed step is retried with half the step up to opt.max_halvings times; a run that cannot
 * go on stops with a message naming the time, the method and the reason, keeps its logs, writes
 * the last good state as a frame and a summary.json with status "failed".  Frames (every
 * opt.frames_every s, and the first and last; none when it is < 0) and records of positions.bin
 * (every opt.positions_every s > 0, and the first and last) are taken at logged states. */
#define _GNU_SOURCE /* dlsym(RTLD_DEFAULT) */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "output.h"
#include "solver.h"
#include "util.h"

typedef struct run_ctx {
  const sw_model *m;
  sw_data *d;
  sw_output *out;
  double next_frame;   /* s */
  double next_positions; /* s: when the next record of positions.bin is due */
  double wall0, last_progress;
  int progress;
  double t_logged;     /* s: time of the previous log line (damping's trapezoid) */
  int logged;          /* a line was logged already */
} run_ctx;

/* The power damping dissipates at the current state (d->grad as scratch for D v) and its
 * integral by the trapezoid rule between log lines. */
static int damping_power(run_ctx *r) {
  const sw_model *m = r->m;
  sw_data *d = r->d;
  double p;
  int rc = sw_damping_force(m, d, d->x, d->t, d->v, d->grad, &p);
  if (rc) return rc;
  if (r->logged) d->dissipated += 0.5 * (d->damp_power + p) * (d->t - r->t_logged); /* J */
  d->damp_power = p; /* W */
  return SW_OK;
}

/* Prefix err (an output failure) with the time it happened at; returns SW_FATAL. */
static int output_failed(const sw_data *d, char *err, size_t errsz) {
  if (err && errsz) {
    char why[SW_ERRSZ];
    snprintf(why, sizeof why, "%s", err);
    sw_errf(err, errsz, "t = %.9g s: %s", d->t, why);
  }
  return SW_FATAL;
}

/* A sample taken every `every` s (> 0) is due at t when t reached next (up to round-off). */
static int is_due(double every, double next, double t) {
  return every > 0.0 && t >= next - 1e-9 * fmax(every, 1.0);
}

/* After a sample at t: the next one is the first multiple of every past t, k every with the
 * index k = floor(t / every) + 1 computed at once (adding every to next until it passes t
 * spins forever once every is below half an ulp of t).  An interval below the step makes every
 * step a sample; one so small that t / every overflows gives next = t (the next step is due). */
static void advance(double every, double *next, double t) {
  if (!(every > 0.0)) return;
  double k = floor((t + 1e-9 * fmax(every, 1.0)) / every) + 1.0;
  *next = isfinite(k) ? k * every : t;
}

/* Diagnostics of the current state, one log line, a record of positions.bin and a frame when
 * they are due (force: the first and last state, due anyway when they are on). */
static int record(run_ctx *r, int force, char *err, size_t errsz) {
  const sw_model *m = r->m;
  sw_data *d = r->d;
  double u;
  int rc = sw_damped(m) ? damping_power(r) : SW_OK;
  if (!rc) rc = sw_eval_terms(m, d, d->x, d->t, 0, 0, 0, &u);
  if (rc) /* e.g. a step accepted a state whose energy is not finite */
    return sw_errf(err, errsz, "t = %.9g s: %s: cannot evaluate the state to log it: %s", d->t,
                   m->opt.method, d->err),
           SW_FATAL;
  sw_tension_xy(m, d);
  sw_tendon_state(m, d);
  double pe = m->opt.positions_every, fe = m->opt.frames_every; /* s */
  int pos = pe > 0.0 && (force || is_due(pe, r->next_positions, d->t));
  if (sw_output_record(r->out, m, d, pos, err, errsz)) return output_failed(d, err, errsz);
  if (pos) advance(pe, &r->next_positions, d->t);
  r->t_logged = d->t;
  r->logged = 1;
  if (fe >= 0.0 && (force || is_due(fe, r->next_frame, d->t))) {
    if (sw_output_frame(r->out, m, d, err, errsz)) return output_failed(d, err, errsz);
    advance(fe, &r->next_frame, d->t);
  }
  return SW_OK;
}

static void show_progress(run_ctx *r, int final) {
  if (!r->progress) return;
  double now = sw_now();
  if (!final && now - r->last_progress < 0.25) return;
  r->last_progress = now;
  const sw_data *d = r->d;
  fprintf(stderr, "\r  t = %9.4f / %g s  steps %ld  newton %ld  factorizations %ld  %6.1f s%s",
          d->t, r->m->opt.duration, d->nstep, d->nnewton, d->nfactor, now - r->wall0,
          final ? "\n" : "");
  fflush(stderr);
}

/* One step from d->t to end, halving it on recoverable failures.  Returns the last error code. */
static int step_with_retries(const sw_integrator_ops *ops, void *st, run_ctx *r, double end,
                             char *err, size_t errsz) {
  const sw_model *m = r->m;
  sw_data *d = r->d;
  const double dt = end - d->t;
  double h = dt;
  int k = 0, rc = SW_OK;
  for (; k <= m->opt.max_halvings; k++, h *= 0.5) {
    double t0 = sw_now();
    rc = ops->step(st, m, d, fmin(h, end - d->t));
    d->time_step += sw_now() - t0;
    /* After a success with a reduced step, finish [t, t + dt] with it, logging each one. */
    while (rc == SW_OK && d->t < end - 1e-12 * dt) {
      if (record(r, 0, err, errsz)) return SW_FATAL;
      t0 = sw_now();
      rc = ops->step(st, m, d, fmin(h, end - d->t));
      d->time_step += sw_now() - t0;
    }
    if (rc == SW_OK) {
      d->t = end; /* no drift from summing steps */
      return SW_OK;
    }
    if (rc < 0) break;
    d->nretry++;
  }
  sw_errf(err, errsz, "t = %.9g s: %s: %s (step %g s, halved %d times)", d->t, m->opt.method,
          d->err, dt, SW_MIN(k, m->opt.max_halvings));
  return SW_FATAL;
}

/* n dt, snapped to the nearest 12-digit decimal when that is within 1e-9 dt of it, so that step
 * times read 0.57 rather than 0.5700000000000001 (57 * 0.01) in the logs. */
static double tidy_time(double t, double dt) {
  char buf[32];
  snprintf(buf, sizeof buf, "%.12g", t);
  double v = strtod(buf, NULL);
  return fabs(v - t) <= 1e-9 * dt ? v : t;
}

static int integrate(run_ctx *r, char *err, size_t errsz) {
  const sw_model *m = r->m;
  sw_data *d = r->d;
  const sw_integrator_ops *ops = sw_integrator_find(m->opt.method);
  if (!ops) return sw_errf(err, errsz, "unknown method '%s'", m->opt.method), SW_FATAL;
  void *st = NULL;
  int rc = ops->init(&st, m, d, err, errsz);
  if (rc) { /* name the method that could not start */
    char why[SW_ERRSZ];
    snprintf(why, sizeof why, "%s", err ? err : "");
    sw_errf(err, errsz, "%s: cannot start: %s", m->opt.method, why);
    return rc;
  }
  const double T = m->opt.duration, dt = m->opt.dt;
  for (long n = 1; rc == SW_OK && d->t < T; n++) {
    /* step n ends at n dt (not a running sum), and a last sliver below dt/1e6 is merged */
    double end = fmin(tidy_time((double)n * dt, dt), T);
    if (T - end < 1e-6 * dt) end = T;
    rc = step_with_retries(ops, st, r, end, err, errsz);
    if (rc == SW_OK) rc = record(r, d->t >= T, err, errsz);
    show_progress(r, 0);
  }
  ops->free(st);
  return rc;
}

static int static_run(run_ctx *r, char *err, size_t errsz) {
  double reaction[3];
  int rc = sw_static_solve(r->m, r->d, reaction, err, errsz);
  if (rc) return rc;
  r->d->nstep = 1;
  if (r->progress)
    fprintf(stderr, "static equilibrium: pin reactions sum to (%.9g, %.9g, %.9g) N\n",
            reaction[0], reaction[1], reaction[2]);
  return record(r, 1, err, errsz);
}

void openblas_set_num_threads(int num_threads); /* OpenBLAS' cblas.h */

/* Threads (docs/performance.md).  Debian's CHOLMOD runs small loops of its factorisation on 4
 * OpenMP threads, compiled in; on 2 cores they fight and a step got 2.3x slower, so nested
 * OpenMP parallelism is switched off unless the user sets OMP_MAX_ACTIVE_LEVELS or
 * OMP_THREAD_LIMIT (looked up at run time: no dependency on libgomp, nothing if it is absent).
 * Then one BLAS thread unless asked: with the OpenMP fix two threads gave no gain per
 * factorisation at 77k DOFs for twice the CPU, and were slower on small systems. */
void sw_set_threads(int blas_threads) {
  if (!getenv("OMP_MAX_ACTIVE_LEVELS") && !getenv("OMP_THREAD_LIMIT")) {
    void (*set_levels)(int);
    *(void **)&set_levels = dlsym(RTLD_DEFAULT, "omp_set_max_active_levels");
    if (set_levels) set_levels(0);
  }
  if (blas_threads > 0) openblas_set_num_threads(blas_threads);
  else if (!getenv("OPENBLAS_NUM_THREADS")) openblas_set_num_threads(1);
}

int sw_run(const sw_model *m, int progress, char *err, size_t errsz) {
  sw_set_threads(m->opt.blas_threads);
  run_ctx r = {.m = m, .wall0 = sw_now(), .progress = progress && isatty(2)};
  r.d = sw_data_new(m);
  if (!r.d)
    return sw_errf(err, errsz, "out of memory allocating the state (%d vertices, %d faces)",
                   m->nv, m->nf),
           SW_FATAL;
  r.out = sw_output_open(m, err, errsz);
  if (!r.out) return sw_data_free(r.d), SW_FATAL;
  r.next_frame = m->opt.frames_every;
  r.next_positions = 0.0; /* a record at t = 0 */
  r.d->energy_bound = m->opt.energy_bound > 0.0 ? m->opt.energy_bound : sw_energy_bound(m, r.d);
  int is_static = !strcmp(m->opt.method, "static");
  int rc = is_static ? SW_OK : record(&r, 1, err, errsz);
  if (rc == SW_OK) rc = is_static ? static_run(&r, err, errsz) : integrate(&r, err, errsz);
  show_progress(&r, 1);
  char msg[SW_ERRSZ];
  snprintf(msg, sizeof msg, "%s", rc ? err : "");
  if (rc) {
    char ferr[SW_ERRSZ]; /* the last good state, as a frame */
    sw_tension_xy(m, r.d);
    sw_output_frame(r.out, m, r.d, ferr, sizeof ferr);
  }
  char cerr[SW_ERRSZ];
  int crc = sw_output_close(r.out, m, r.d, rc ? "failed" : "ok", msg, sw_now() - r.wall0, cerr,
                            sizeof cerr);
  if (!rc && crc) sw_errf(err, errsz, "%s", cerr), rc = SW_FATAL;
  sw_data_free(r.d);
  return rc;
}
