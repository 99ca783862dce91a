/* sim.c — the stepping API (sinew.h, "stepping"): state -> integrator step -> diagnostics ->
 * logs, one step at a time.  sw_run (run.c) is sw_sim_run to the scene's duration.
 * A failed step is retried with half the step up to opt.max_halvings times; a step that cannot
 * be made fails with a message naming the time, the method and the reason and leaves the last
 * good state.  With a run folder: frames (every opt.frames_every s, the first state and the
 * end of each sw_sim_run; none when it is < 0) and records of positions.bin (every
 * opt.positions_every s > 0, and the same first and last) are taken at logged states, and
 * sw_sim_close writes the last good state as a frame and a summary.json "failed" when the last
 * step failed. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <math.h>
#include <stddef.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "output.h"
#include "cancel.h"
#include "solver.h"
#include "terms.h"
#include "util.h"

struct sw_sim {
  sw_model *m;
  sw_data *d;
  sw_output *out;              /* the run folder, or NULL */
  const sw_integrator_ops *ops; /* NULL: the static solve */
  void *st;                    /* the integrator's state */
  double t0;                   /* s: the origin of the step grid t0 + n dt */
  long n;                      /* grid steps taken since t0 */
  double next_frame;           /* s */
  double next_positions;       /* s: when the next record of positions.bin is due */
  double wall0, last_progress;
  double t_begin;              /* s: the simulated time this process started from */
  int progress;
  double t_logged;             /* s: time of the previous log line (damping's trapezoid) */
  int logged;                  /* a line was logged since the start or the last set_state */
  int changed;                 /* SW_CHANGED_* since the last step */
  int failed;                  /* the last step failed, with msg */
  int stopped;                 /* sw_sim_run stopped at sw_interrupt's request, with msg */
  char msg[SW_ERRSZ];
  int finished;                /* the run folder was closed (finish ran) */
  int started;                 /* the integrator is going (a restart file can be written) */
  int fitting;                 /* the fit stage is going: ops and st are its backward Euler */
  double fit_wall0;            /* s: wall clock the fit stage's time counts from */
  double kept_damp, kept_tol, kept_ramp; /* the model's own, while the fit holds its own */
  double fit_t_min;            /* s: the fit's ramps are over (gravity in full) from here */
  double last_restart;         /* s: wall clock of the last restart.bin written */
  int closed;                  /* sw_sim_close was called: no more steps or changes */
};

#define FIT_EASY 6  /* Newton iterations: the optimisation fit's step grows after at most */
#define FIT_HARD 16 /* ... and is halved after more */

static int write_restart(sw_sim *s, char *err, size_t errsz);
static void fit_restore(sw_sim *s);

/* The power damping dissipates at the current state and its integral by the trapezoid rule
 * between log lines.  After a step of a method that froze D for it (the Newton methods), v.D v
 * with that D: the power of the damping force the step applied, at the velocity it accepted,
 * and no Hessian to evaluate; else D at the state (d->grad as scratch for D v). */
static int damping_power(sw_sim *s) {
  sw_data *d = s->d;
  double p = 0.0;
  int rc = SW_OK;
  if (sw_damped(s->m) &&
      !(s->ops && s->ops->damping_power && s->ops->damping_power(s->st, s->m, d, &p) == SW_OK))
    rc = sw_damping_force(s->m, d, d->x, d->t, d->v, d->grad, &p);
  if (rc) return rc;
  p += d->friction_power; /* W: contact friction (the terms' state, sw_terms_state) */
  if (s->logged) d->dissipated += 0.5 * (d->damp_power + p) * (d->t - s->t_logged); /* J */
  d->damp_power = p; /* W */
  return SW_OK;
}

/* The power the forcing puts in at the current state and its integral, the work in, by the
 * trapezoid rule between log lines (as damping_power). */
static void actuation_power(sw_sim *s) {
  sw_data *d = s->d;
  double p = sw_actuation_power(s->m, d->x, d->t); /* W */
  if (s->logged) d->work_in += 0.5 * (d->actuation_power + p) * (d->t - s->t_logged); /* J */
  d->actuation_power = p;
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

/* After a sample at t: the next one is next + k every, the first past t, with the count k of
 * intervals computed at once (adding every until next passes t spins forever once every is
 * below half an ulp of next).  An interval below the step makes every step a sample; when
 * next + k every overflows or does not move, next = t (the next step is due). */
static void advance(double every, double *next, double t) {
  double tol = 1e-9 * fmax(every, 1.0);
  if (!(every > 0.0) || *next > t + tol) return;
  double k = floor((t + tol - *next) / every) + 1.0, n = *next + k * every;
  *next = isfinite(n) && n > *next ? n : t;
}

/* The diagnostics of the current state: term energies (into *u, J), tension XY, tendons. */
static int diagnose(sw_sim *s, double *u) {
  int rc = sw_eval_terms(s->m, s->d, s->d->x, s->d->t, 0, 0, 0, u);
  if (rc) return rc;
  sw_tension_xy(s->m, s->d);
  sw_tendon_state(s->m, s->d);
  sw_seam_state(s->m, s->d);
  double *e = s->d->energy; /* J */
  sw_sim_energy(s, &e[0], &e[1], &e[3]);
  e[2] = e[0] + e[1];
  return SW_OK;
}

/* The diagnostics of an accepted state: the terms' (contact forces and pressure), the
 * dissipated and put-in power, the energies, tension XY, tendons, seams. */
static int observe(sw_sim *s) {
  const sw_model *m = s->m;
  double u;
  sw_terms_state(m, s->d);
  int rc = sw_damped(m) || sw_terms_dissipate(m) || m->fit.on ? damping_power(s) : SW_OK;
  if (sw_actuated(m)) actuation_power(s);
  if (!rc) rc = diagnose(s, &u);
  return rc;
}

/* With a run folder, one log line of the current state, a record of positions.bin and a frame
 * when they are due (force: the first and last state, due anyway when they are on). */
static int record(sw_sim *s, int force, char *err, size_t errsz) {
  const sw_model *m = s->m;
  sw_data *d = s->d;
  s->t_logged = d->t;
  s->logged = 1;
  if (!s->out) return SW_OK;
  double pe = m->opt.positions_every, fe = m->opt.frames_every; /* s */
  int pos = pe > 0.0 && (force || is_due(pe, s->next_positions, d->t));
  if (sw_output_record(s->out, m, d, pos, err, errsz)) return output_failed(d, err, errsz);
  if (pos) advance(pe, &s->next_positions, d->t);
  if (fe >= 0.0 && (force || is_due(fe, s->next_frame, d->t))) {
    if (sw_output_frame(s->out, m, d, err, errsz)) return output_failed(d, err, errsz);
    advance(fe, &s->next_frame, d->t);
    if (write_restart(s, err, errsz)) return output_failed(d, err, errsz);
  } else if (m->opt.restart_every > 0.0 && sw_now() - s->last_restart >= m->opt.restart_every) {
    if (write_restart(s, err, errsz)) return output_failed(d, err, errsz);
  }
  return SW_OK;
}

/* A state accepted (the first state, then each step's): its diagnostics, then each term's
 * commit (its lagged state advanced for the steps from here on: the adaptive contact
 * stiffness; after the diagnostics, which belong to the state as the steps reached it, and
 * before the logs, whose restart file holds the committed state), then its logs. */
static int accepted(sw_sim *s, int force, char *err, size_t errsz) {
  sw_data *d = s->d;
  int rc = observe(s);
  sw_terms_commit(s->m, d);
  if (rc) /* e.g. a step accepted a state whose energy is not finite */
    return sw_errf(err, errsz, "t = %.9g s: %s: cannot evaluate the state to log it: %s", d->t,
                   s->m->opt.method, d->err),
           SW_FATAL;
  return record(s, force, err, errsz);
}

static void show_progress(sw_sim *s, int final) {
  if (!s->progress) return;
  double now = sw_now();
  if (!final && now - s->last_progress < 0.25) return;
  s->last_progress = now;
  const sw_data *d = s->d;
  /* the share of the simulated time reached; the rest at this process's rate so far (a
   * resumed run: since the resume) */
  const double T = s->m->opt.duration, wall = now - s->wall0, ran = d->t - s->t_begin;
  double pct = T > 0 ? 100.0 * fmin(fmax(d->t / T, 0.0), 1.0) : 100.0;
  double left = ran > 0 ? wall * (T - d->t) / ran : NAN;
  char eta[32] = "";
  if (!final && ran > 0.005 * (T - s->t_begin) && isfinite(left))
    snprintf(eta, sizeof eta, "  ~%.0f s left", fmax(left, 0.0));
  fprintf(stderr, "\r  t = %9.4f / %g s (%5.1f%%)  steps %ld  newton %ld  factorizations %ld  "
          "%6.1f s%s%s", d->t, T, pct, d->nstep, d->nnewton, d->nfactor, wall, eta,
          final ? "\n" : "         ");
  fflush(stderr);
}

/* One attempt of the integrator's step of size h (timed). */
static int try_step(sw_sim *s, double h) {
  double t0 = sw_now();
  int rc = s->ops->step(s->st, s->m, s->d, h);
  s->d->time_step += sw_now() - t0;
  return rc;
}

/* One step from d->t to end, halving it on recoverable failures.  Returns the last error code. */
static int step_with_retries(sw_sim *s, double end, char *err, size_t errsz) {
  const sw_model *m = s->m;
  sw_data *d = s->d;
  const double dt = end - d->t;
  double h = dt;
  int k = 0, rc = SW_OK;
  for (; k <= m->opt.max_halvings; k++, h *= 0.5) {
    rc = try_step(s, fmin(h, end - d->t));
    /* After a success with a reduced step, finish [t, t + dt] with it, logging each one. */
    while (rc == SW_OK && d->t < end - 1e-12 * dt) {
      if (accepted(s, 0, err, errsz)) return SW_FATAL;
      rc = try_step(s, fmin(h, end - d->t));
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

/* The result of a step: remembered for sw_sim_close (msg: the failure). */
static int outcome(sw_sim *s, int rc, const char *err) {
  s->failed = rc != SW_OK;
  s->stopped = 0;
  snprintf(s->msg, sizeof s->msg, "%s", rc && err ? err : "");
  show_progress(s, 0);
  return rc;
}

static int static_step(sw_sim *s, char *err, size_t errsz) {
  double reaction[3];
  int rc = sw_static_solve(s->m, s->d, reaction, err, errsz);
  if (rc) return outcome(s, rc, err);
  s->d->nstep++;
  if (s->progress)
    fprintf(stderr, "static equilibrium: pin reactions sum to (%.9g, %.9g, %.9g) N\n",
            reaction[0], reaction[1], reaction[2]);
  return outcome(s, accepted(s, 1, err, errsz), err);
}

/* The step to end (a point of the grid, or the end of a sw_sim_run), logged; force: a frame
 * and a positions record however due.  The integrator first forgets what a change made
 * stale. */
static int step_to(sw_sim *s, double end, int force, char *err, size_t errsz) {
  if (s->changed && s->ops->reset) s->ops->reset(s->st, s->m, s->d, s->changed);
  s->changed = 0;
  int rc = step_with_retries(s, end, err, errsz);
  if (rc == SW_OK) rc = accepted(s, force, err, errsz);
  return outcome(s, rc, err);
}

/* The next point of the step grid, s. */
static double grid_next(const sw_sim *s) {
  const double dt = s->m->opt.dt;
  return s->t0 + tidy_time((double)(s->n + 1) * dt, dt);
}

/* SW_FATAL with err "what: the simulation is closed" after sw_sim_close, else SW_OK. */
static int check_open(const sw_sim *s, const char *what, char *err, size_t errsz) {
  if (!s->closed) return SW_OK;
  return sw_errf(err, errsz, "%s: the simulation is closed (its run folder finished); expected "
                 "a simulation that is still open", what),
         SW_FATAL;
}

int sw_sim_step(sw_sim *s, char *err, size_t errsz) {
  if (check_open(s, "step", err, errsz)) return SW_FATAL;
  if (!s->ops) return static_step(s, err, errsz);
  int rc = step_to(s, grid_next(s), 0, err, errsz);
  if (rc == SW_OK) s->n++;
  return rc;
}

/* The request is models' flag (models/cancel.h), which their long loops poll. */
void sw_interrupt(int sig) { sw_stop_request = sig; }
int sw_interrupted(void) { return sw_stop_request; }

/* Stop at sw_interrupt's request: the state is that of the last step, whole. */
static int stop(sw_sim *s, char *err, size_t errsz) {
  int sig = sw_stop_request;
  s->stopped = 1;
  snprintf(s->msg, sizeof s->msg, "interrupted by signal %d (%s) at t = %.9g s", sig,
           sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal", s->d->t);
  sw_errf(err, errsz, "%s", s->msg);
  return SW_INTERRUPTED;
}

int sw_sim_run(sw_sim *s, double until, char *err, size_t errsz) {
  return sw_sim_run_steps(s, until, -1, err, errsz);
}

int sw_sim_run_steps(sw_sim *s, double until, long max_steps, char *err, size_t errsz) {
  if (check_open(s, "run", err, errsz)) return SW_FATAL;
  if (!isfinite(until) || until < s->d->t)
    return sw_errf(err, errsz, "run: until = %g s; expected a finite time >= the current time "
                   "%.9g s", until, s->d->t),
           SW_FATAL;
  if (!s->ops) return static_step(s, err, errsz);
  const double dt = s->m->opt.dt;
  int rc = SW_OK;
  for (long k = 0; rc == SW_OK && s->d->t < until && (max_steps < 0 || k < max_steps); k++) {
    if (sw_stop_request) return stop(s, err, errsz);
    /* a step ends on the grid (not a running sum), and a last sliver below dt/1e6 is merged */
    double grid = grid_next(s), end = fmin(grid, until);
    if (until - end < 1e-6 * dt) end = until;
    rc = step_to(s, end, end == until, err, errsz);
    if (rc == SW_OK && grid <= until + 1e-6 * dt) s->n++;
  }
  return rc;
}

/* Write the folder's end: the last good state as a frame after a failure, the summary. */
static int finish(sw_sim *s, char *err, size_t errsz) {
  if (s->finished) return SW_OK;
  s->finished = 1;
  show_progress(s, 1);
  if (!s->out) return SW_OK;
  if (s->failed || s->stopped) {
    char ferr[SW_ERRSZ]; /* the last good state, as a frame */
    sw_tension_xy(s->m, s->d);
    if (!sw_output_frame(s->out, s->m, s->d, ferr, sizeof ferr))
      write_restart(s, ferr, sizeof ferr); /* to resume from */
  }
  const char *status = s->failed ? "failed" : s->stopped ? "interrupted" : "ok";
  int rc = sw_output_close(s->out, s->m, s->d, status, s->msg, sw_now() - s->wall0, err, errsz);
  s->out = NULL;
  return rc;
}

int sw_sim_close(sw_sim *s, char *err, size_t errsz) {
  if (!s) return 0;
  s->closed = 1;
  return finish(s, err, errsz);
}

void sw_sim_free(sw_sim *s) {
  if (!s) return;
  char err[SW_ERRSZ];
  finish(s, err, sizeof err);
  if (s->ops && s->st) s->ops->free(s->st);
  if (s->fitting) fit_restore(s); /* interrupted in the fit: the model as it was */
  sw_data_free(s->d);
  sw_free(s);
}

/* The RMS speed of the free vertices, mass-weighted, m/s. */
static double rms_speed(const sw_model *m, const sw_data *d) {
  double k = 2.0 * sw_kinetic(m, d->v), mass = 0.0; /* kg m^2/s^2, kg */
  for (int i = 0; i < m->nv; i++) mass += m->pinned[i] ? 0.0 : m->mass[i];
  return mass > 0.0 ? sqrt(k / mass) : 0.0;
}

/* One step of the fit to end, logged; the sim's integrator is the fit's meanwhile. */
static int fit_step(sw_sim *s, double end, char *err, size_t errsz) {
  int rc = step_with_retries(s, end, err, errsz);
  s->d->fit_steps++; /* counted before the log: a restart file written there holds it */
  if (!rc) rc = accepted(s, 0, err, errsz);
  return rc;
}

/* The model's damping, Newton tolerance and gravity ramp back as they were before the fit. */
static void fit_restore(sw_sim *s) {
  sw_model *m = s->m;
  m->damp_mass = s->kept_damp, m->opt.newton_tol = s->kept_tol;
  m->gravity_delay = 0.0, m->gravity_ramp = s->kept_ramp;
}

/* The fit's model and its backward Euler integrator started at d (the fit's start, or the
 * state a resumed run loaded).  Its mass damping is added, gravity is held over the seams'
 * ramp time and then grows over as long, the Newton tolerance is the fit's. */
static int fit_enter(sw_sim *s, char *err, size_t errsz) {
  sw_model *m = s->m;
  const sw_fit *f = &m->fit;
  s->kept_damp = m->damp_mass, s->kept_tol = m->opt.newton_tol, s->kept_ramp = m->gravity_ramp;
  m->damp_mass += f->damping;
  m->gravity_delay = m->seam_ramp;
  m->gravity_ramp = fmax(s->kept_ramp, m->seam_ramp);
  m->opt.newton_tol = fmin(s->kept_tol, f->newton_tol);
  s->fit_t_min = m->gravity_delay + m->gravity_ramp;
  s->fitting = 1;
  s->fit_wall0 = sw_now() - s->d->fit_wall; /* a resumed fit: its time so far */
  s->ops = f->mode == SW_FIT_DYNAMIC ? sw_integrator_find("backward-euler") : &sw_proximal_ops;
  int rc = s->ops ? s->ops->init(&s->st, m, s->d, err, errsz) : SW_FATAL;
  if (rc) s->st = NULL;
  s->started = !rc; /* restart files from here on */
  return rc;
}

/* The dynamic fit's Newton tolerance once it may end, as a fraction of fit.speed (m/s per
 * m/s): Newton's stop leaves an error in a step's velocity of up to about its tolerance (more
 * with an approximate matrix, integrator.bending_matrix compact, whose convergence is linear),
 * and the end test reads that error as speed.  0.3 rather than 1: the grid skirt's fit ends at
 * 3.23 s instead of 3.82 s for 0.89 times the CPU, the other garments within 5 %; 0.1 ends it at
 * 2.91 s for 1.00 times (docs/garments.md, "fit"). */
#define FIT_TOL_SPEED 0.3

/* The end of the fit's next step, s.  Dynamic: the grid of fit.dt.  Optimisation: a step
 * chosen from the last one by its Newton iterations (grown by opt_growth after at most
 * FIT_EASY, halved after more than FIT_HARD; a step halved on failure goes on from its halved
 * size), at least fit.dt, at most opt_dt until the ramps are over (gravity in full, at twice the
 * seams' ramp time, where a step ends), unbounded after; its Newton tolerance the dynamic
 * fit's in metres, newton_tol x dt, whatever the step. */
static double fit_next(sw_sim *s) {
  sw_model *m = s->m;
  const sw_data *d = s->d;
  const sw_fit *f = &m->fit;
  double h = f->opt_dt, t_min = s->fit_t_min; /* s */
  int ramps = d->t < t_min - 1e-9 * f->dt;
  if (f->mode == SW_FIT_DYNAMIC || (f->mode == SW_FIT_SETTLE && ramps)) {
    double tol = fmin(s->kept_tol, f->newton_tol); /* m/s */
    m->opt.newton_tol = ramps ? tol : fmin(tol, FIT_TOL_SPEED * f->speed);
    return tidy_time((double)(d->fit_steps + 1) * f->dt, f->dt);
  }
  if (d->fit_steps > 0) {
    h = d->last_dt;
    if (d->last_newton <= FIT_EASY) h *= f->opt_growth;
    else if (d->last_newton > FIT_HARD) h *= 0.5;
  }
  h = fmax(h, f->dt);
  double end = d->t + h;
  if (ramps) end = fmin(d->t + fmin(h, f->opt_dt), t_min);
  m->opt.newton_tol = fmin(s->kept_tol, f->newton_tol) * f->dt / (end - d->t);
  return end;
}

/* 1 when the fit is over after its last step: the seams closed to fit.gap and the RMS speed
 * below fit.speed once gravity is on in full (*rc SW_OK), or fit.max_time reached (*rc
 * SW_FATAL, with err).  Checked before each step, so that a resumed fit ends where a straight
 * one does. */
static int fit_over(sw_sim *s, int *rc, char *err, size_t errsz) {
  const sw_model *m = s->m;
  const sw_data *d = s->d;
  const sw_fit *f = &m->fit;
  if (d->fit_steps == 0) return 0; /* one step at least */
  const double t_min = m->gravity_delay + m->gravity_ramp, eps = 1e-9 * f->dt; /* s */
  double v = rms_speed(m, d);
  if (d->t >= t_min - eps && d->seam_gap_max <= f->gap && v <= f->speed) return 1;
  if (d->t < f->max_time - eps) return 0;
  sw_errf(err, errsz, "t = %.9g s: the garment did not fit within fit max_time = %g s: "
          "largest seam gap %.3g m (fit gap %g m), RMS speed %.3g m/s (fit speed %g m/s)",
          d->t, f->max_time, d->seam_gap_max, f->gap, v, f->speed);
  *rc = SW_FATAL;
  return 1;
}

/* The fit stage (sinew.h, sw_fit; docs/garments.md): backward Euler steps of fit.dt with the
 * fit's mass damping added (fit.mode optimize and settle: proximal steps, fit_next), from the arrangement until the seams are closed to fit.gap and the
 * RMS speed is below fit.speed (after the seams' ramp), logged as the run's first steps; the
 * scene's own method then starts from there, its step grid and duration counted from the
 * fit's end, which is written as a frame.  Gravity grows over the seams' ramp time once they
 * are sewn (the fit ends no earlier than twice the ramp time).  The model's damping, Newton
 * tolerance and gravity ramp are the fit's only while it lasts.  Restart files are written
 * during the fit as during the method's steps (record); an interrupted fit stays entered, to
 * be written so and resumed (sw_sim_resume goes on here). */
static int fit_stage(sw_sim *s, char *err, size_t errsz) {
  sw_model *m = s->m;
  sw_data *d = s->d;
  const sw_fit *f = &m->fit;
  if (!f->on) return SW_OK;
  int rc = s->fitting ? SW_OK : fit_enter(s, err, errsz);
  while (rc == SW_OK && !fit_over(s, &rc, err, errsz)) {
    if (sw_stop_request) return stop(s, err, errsz);
    rc = fit_step(s, fit_next(s), err, errsz);
  }
  if (!rc && f->mode != SW_FIT_DYNAMIC) /* a rest state: dx/h was no speed */
    memset(d->v, 0, (size_t)m->nv * (size_t)m->dim * sizeof *d->v);
  if (rc && err && strncmp(err, "fit: ", 5)) {
    char why[SW_ERRSZ];
    snprintf(why, sizeof why, "%s", err);
    sw_errf(err, errsz, "fit: %s", why);
  }
  if (s->st) s->ops->free(s->st);
  s->ops = NULL, s->st = NULL, s->started = 0, s->fitting = 0;
  fit_restore(s);
  if (!rc && s->out && m->opt.frames_every >= 0.0 && sw_output_frame(s->out, m, d, err, errsz))
    rc = output_failed(d, err, errsz); /* the fitted garment */
  d->fit_end = d->t, d->fit_wall = sw_now() - s->fit_wall0;
  s->t0 = d->t, s->n = 0;
  return rc;
}

/* The integrator (none for static) and its state, started at d; "METHOD: cannot start: why". */
static int start_method(sw_sim *s, char *err, size_t errsz) {
  const sw_model *m = s->m;
  if (!strcmp(m->opt.method, "static")) return SW_OK;
  s->ops = sw_integrator_find(m->opt.method);
  if (!s->ops) return sw_errf(err, errsz, "unknown method '%s'", m->opt.method), SW_FATAL;
  int rc = s->ops->init(&s->st, m, s->d, err, errsz);
  if (rc) { /* name the method that could not start */
    char why[SW_ERRSZ];
    snprintf(why, sizeof why, "%s", err ? err : "");
    sw_errf(err, errsz, "%s: cannot start: %s", m->opt.method, why);
    s->st = NULL;
  }
  return rc;
}

sw_sim *sw_sim_new(sw_model *m, int flags, char *err, size_t errsz) {
  return sw_sim_start(m, flags, NULL, err, errsz);
}

/* A sim of m and its state at t = 0, no folder, no integrator; NULL when out of memory. */
static sw_sim *sim_alloc(sw_model *m, int flags, char *err, size_t errsz) {
  sw_set_threads(m->opt.blas_threads);
  sw_sim *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory"), NULL;
  s->m = m;
  s->wall0 = sw_now();
  s->progress = (flags & SW_SIM_PROGRESS) && isatty(2);
  s->d = sw_data_new(m);
  if (!s->d)
    return sw_errf(err, errsz, "out of memory allocating the state (%d vertices, %d faces)",
                   m->nv, m->nf),
           sw_free(s), NULL;
  return s;
}

/* The sim's start after the first state was logged (begin) or a fit was resumed: the fit stage
 * (the rest of it), the method started, the restart file of the start. */
static int fit_then_start(sw_sim *s, char *err, size_t errsz) {
  int rc = fit_stage(s, err, errsz);
  if (!rc) rc = start_method(s, err, errsz);
  s->started = !rc;
  if (!rc && write_restart(s, err, errsz)) rc = output_failed(s->d, err, errsz); /* the start */
  return rc;
}

/* A sim that could not start (rc: why; SW_INTERRUPTED: a fit stopped by a signal, which
 * stop() recorded) closed and freed; its status in *status. */
static sw_sim *start_failed(sw_sim *s, int rc, int *status, char *err) {
  if (rc != SW_INTERRUPTED) outcome(s, rc, err);
  if (status) *status = rc == SW_INTERRUPTED ? rc : SW_FATAL;
  char cerr[SW_ERRSZ];
  finish(s, cerr, sizeof cerr); /* an interrupted fit: its state, to resume from */
  sw_sim_free(s);
  return NULL;
}

/* The start of a run from s->d (the initial state): the sampling, the energy bound, the first
 * state logged (the static solve logs only its answer), the fit stage, the method started. */
static int begin(sw_sim *s, char *err, size_t errsz) {
  const sw_model *m = s->m;
  s->t0 = 0.0, s->n = 0;
  s->next_frame = m->opt.frames_every;
  s->next_positions = 0.0; /* a record at t = 0 */
  s->d->energy_bound = m->opt.energy_bound > 0.0 ? m->opt.energy_bound : sw_energy_bound(m, s->d);
  /* a failure of any is the run's: the folder says so */
  int is_static = !strcmp(m->opt.method, "static");
  int rc = is_static && !m->fit.on ? SW_OK : accepted(s, 1, err, errsz);
  return rc ? rc : fit_then_start(s, err, errsz);
}

sw_sim *sw_sim_start(sw_model *m, int flags, int *status, char *err, size_t errsz) {
  if (status) *status = SW_FATAL;
  sw_sim *s = sim_alloc(m, flags, err, errsz);
  if (!s) return NULL;
  if (flags & SW_SIM_OUTPUT) {
    s->out = sw_output_open(m, err, errsz);
    if (!s->out) { /* nothing to close */
      if (status) *status = SW_NOSTART;
      return s->finished = 1, sw_sim_free(s), NULL;
    }
  }
  int rc = begin(s, err, errsz);
  return rc ? start_failed(s, rc, status, err) : s;
}

/* ------------------------------------------------------------------ restart */

/* restart.bin (sim/output/restart.c) begins with what the run was, checked on loading: the
 * scene, the overrides it was loaded with and the options are what `sinew run --resume` runs
 * again (sw_restart_options); the files the scene read (m->input) follow the header. */
typedef struct restart_head {
  char magic[8];         /* SW_RESTART_MAGIC */
  char scene[SW_PATHSZ]; /* the scene file, absolute */
  sw_options opt;        /* the run's options, the command line's included */
  int nv, dim, nf;
  int grid[2];           /* sw_scene_overrides */
  double stiffness_scale;
  int fitting;           /* written during the fit stage: its backward Euler's history follows */
  int ninput;            /* sw_input records after the header */
} restart_head;

static void head_of(const sw_model *m, restart_head *h) {
  memset(h, 0, sizeof *h);
  memcpy(h->magic, SW_RESTART_MAGIC, 8);
  if (!realpath(m->path, h->scene)) snprintf(h->scene, sizeof h->scene, "%s", m->path);
  h->opt = m->opt;
  h->nv = m->nv, h->dim = m->dim, h->nf = m->nf;
  memcpy(h->grid, m->grid_override, sizeof h->grid);
  h->stiffness_scale = m->stiffness_scale;
  h->ninput = m->ninput;
}

#define IO(field) sw_io_bytes(io, &(field), sizeof(field))

/* The run loop's state after a logged step: time, step grid, sampling, the integrals and
 * counters of the logs, positions and velocities, then the integrator's history. */
static void sim_io(sw_sim *s, sw_io *io) {
  sw_data *d = s->d;
  const size_t nd = (size_t)s->m->nv * (size_t)s->m->dim;
  IO(d->t), IO(s->t0), IO(s->n), IO(s->next_frame), IO(s->next_positions);
  IO(s->t_logged), IO(s->logged);
  IO(d->damp_power), IO(d->dissipated), IO(d->actuation_power), IO(d->work_in);
  IO(d->nstep), IO(d->nnewton), IO(d->nfactor), IO(d->nassemble), IO(d->nforce);
  IO(d->nretry), IO(d->nlinesearch), IO(d->nerrfail), IO(d->nsetup), IO(d->nstep_order);
  IO(d->ncg), IO(d->nbound);
  IO(d->energy_bound), IO(d->last_newton), IO(d->last_dt);
  IO(d->fit_end), IO(d->fit_steps);
  if (s->fitting && !io->load) d->fit_wall = sw_now() - s->fit_wall0; /* s: the fit's so far */
  IO(d->fit_wall);
  if (s->fitting) { /* the fit's model: its damping, gravity held and ramped, Newton tolerance */
    sw_model *m = s->m;
    IO(m->damp_mass), IO(m->gravity_delay), IO(m->gravity_ramp), IO(m->opt.newton_tol);
  }
  int nio = 0; /* the terms' run state (the adapted contact stiffness's factor) */
  for (int k = 0; k < s->m->nterm; k++) {
    const sw_term *t = &s->m->term[k];
    if (t->ops->io) t->ops->io(t, s->m, d->tdata[k], io), nio++;
  }
  double one = 1.0; /* without any: the one double the format keeps there */
  if (!nio) IO(one);
  IO(d->time_assemble), IO(d->time_factor), IO(d->time_solve), IO(d->time_step);
  double wall = d->wall_before + (sw_now() - s->wall0); /* s: every part's, to this state */
  IO(wall);
  if (io->load) d->wall_before = wall;
  sw_io_bytes(io, d->x, nd * sizeof(double));
  sw_io_bytes(io, d->v, nd * sizeof(double));
  if (s->ops->history) s->ops->history(s->st, s->m, io);
}

uint64_t sw_sim_restart_shape(sw_sim *s) {
  sw_io io = {0};
  restart_head h;
  head_of(s->m, &h);
  sw_io_bytes(&io, &h, sizeof h);
  sw_io_bytes(&io, s->m->input, (size_t)s->m->ninput * sizeof *s->m->input);
  sim_io(s, &io);
  uint64_t shape = io.shape;
  sw_io_free(&io);
  return shape;
}

/* restart.bin of the current state (with a frame, and when the run stops). */
static int write_restart(sw_sim *s, char *err, size_t errsz) {
  if (!s->started || !s->out || !s->ops) return SW_OK; /* a static solve: nothing to resume */
  sw_io io = {0};
  restart_head h;
  head_of(s->m, &h);
  h.fitting = s->fitting;
  sw_io_bytes(&io, &h, sizeof h);
  sw_io_bytes(&io, s->m->input, (size_t)s->m->ninput * sizeof *s->m->input);
  sim_io(s, &io);
  int rc = sw_output_restart(s->out, &io, err, errsz);
  sw_io_free(&io);
  s->last_restart = sw_now();
  return rc ? SW_FATAL : SW_OK;
}

/* An option that a resumed run must keep: its name and where it is in sw_options. */
typedef struct kept_option {
  const char *name;
  size_t at, size;
} kept_option;
#define KEPT(f) {#f, offsetof(sw_options, f), sizeof(((sw_options *)0)->f)}
static const kept_option kept_options[] = {
    KEPT(method), KEPT(dt), KEPT(newton_max), KEPT(newton_tol), KEPT(newton_norm),
    KEPT(max_halvings), KEPT(hessian), KEPT(newton_reuse), KEPT(factorization), KEPT(ordering),
    KEPT(bending_matrix),
    KEPT(rtol), KEPT(atol), KEPT(max_order), KEPT(max_step), KEPT(setup_every), KEPT(energy_bound),
    KEPT(frames_every), KEPT(positions_every), KEPT(frames_format), KEPT(tx_clip),
    KEPT(tx_reference_uv), KEPT(tx_k_u), KEPT(tx_k_v), KEPT(tendon_dense_max)};

/* What differs between the run that wrote the restart (h and its inputs in) and m: a message
 * naming it, or 0 when nothing that defines the model does. */
static int model_changed(const restart_head *h, const sw_input *in, const sw_model *m,
                         char *why, size_t whysz) {
  for (size_t k = 0; k < sizeof kept_options / sizeof *kept_options; k++) {
    const kept_option *o = &kept_options[k];
    if (memcmp((const char *)&h->opt + o->at, (const char *)&m->opt + o->at, o->size))
      return snprintf(why, whysz, "the option %s differs from the run's", o->name), 1;
  }
  if (memcmp(h->grid, m->grid_override, sizeof h->grid))
    return snprintf(why, whysz, "--grid %dx%d, the run's %dx%d (0: the scene's)",
                    m->grid_override[0], m->grid_override[1], h->grid[0], h->grid[1]), 1;
  if (h->stiffness_scale != m->stiffness_scale)
    return snprintf(why, whysz, "the stiffness scale is %.17g, the run's %.17g",
                    m->stiffness_scale, h->stiffness_scale), 1;
  for (int k = 0; k < h->ninput || k < m->ninput; k++) {
    if (k >= m->ninput || k >= h->ninput || strcmp(in[k].path, m->input[k].path))
      return snprintf(why, whysz, "the scene reads other files: '%.400s' where the run read '%.400s'",
                      k < m->ninput ? m->input[k].path : "(none)",
                      k < h->ninput ? in[k].path : "(none)"), 1;
    if (in[k].bytes != m->input[k].bytes || in[k].hash != m->input[k].hash)
      return snprintf(why, whysz, "%s '%.400s' changed since the run (%lld bytes, checksum %016llx; "
                      "the run's %lld bytes, %016llx)", k ? "the file" : "the scene file",
                      in[k].path, m->input[k].bytes, m->input[k].hash, in[k].bytes,
                      in[k].hash), 1;
  }
  return 0;
}

/* The header of io and the inputs after it, checked against m (loading); force: a changed
 * scene, files or option is taken (sinew run --resume --force); *fitting: written in the fit. */
static int check_head(sw_io *io, const sw_model *m, int force, int *fitting, const char *dir,
                      char *err, size_t errsz) {
  restart_head h;
  sw_io_bytes(io, &h, sizeof h);
  if (io->bad || memcmp(h.magic, SW_RESTART_MAGIC, 8) || h.ninput < 0 ||
      (size_t)h.ninput > (io->len - io->pos) / sizeof(sw_input))
    return sw_errf(err, errsz, "%s/restart.bin: not a restart file of this sinew", dir), -1;
  if (h.nv != m->nv || h.dim != m->dim || h.nf != m->nf || strcmp(h.opt.method, m->opt.method))
    return sw_errf(err, errsz, "%s/restart.bin: a run of %d vertices, %d faces in %dD with %s; "
                   "expected this scene's %d, %d, %dD, %s", dir, h.nv, h.nf, h.dim,
                   h.opt.method, m->nv, m->nf, m->dim, m->opt.method),
           -1;
  if (h.fitting && !m->fit.on)
    return sw_errf(err, errsz, "%s/restart.bin: written during a fit stage; expected a scene "
                   "with seams to fit", dir),
           -1;
  *fitting = h.fitting;
  sw_input *copy = sw_calloc((size_t)h.ninput + 1, sizeof *copy);
  if (!copy) return sw_errf(err, errsz, "%s/restart.bin: out of memory", dir), -1;
  sw_io_bytes(io, copy, (size_t)h.ninput * sizeof *copy);
  char why[SW_ERRSZ];
  int bad = model_changed(&h, copy, m, why, sizeof why);
  sw_free(copy);
  if (bad && !force)
    return sw_errf(err, errsz, "%s/restart.bin: the model changed: %s; expected the run's own "
                   "scene, files and options (--force goes on anyway, for a change that leaves "
                   "the model as it was)", dir, why),
           -1;
  return 0;
}

int sw_restart_options(const char *dir, char *scene, size_t scenesz, sw_options *opt,
                       char *err, size_t errsz) {
  sw_scene_overrides ov;
  double t;
  return sw_restart_options_ex(dir, scene, scenesz, opt, &ov, &t, err, errsz);
}

int sw_restart_options_ex(const char *dir, char *scene, size_t scenesz, sw_options *opt,
                          sw_scene_overrides *ov, double *t, char *err, size_t errsz) {
  sw_io io;
  if (sw_io_read(&io, dir, err, errsz)) return SW_FATAL;
  restart_head h;
  sw_io_bytes(&io, &h, sizeof h);
  int bad = io.bad || memcmp(h.magic, SW_RESTART_MAGIC, 8) || h.ninput < 0 ||
            (size_t)h.ninput > (io.len - io.pos) / sizeof(sw_input);
  if (!bad) io.pos += (size_t)h.ninput * sizeof(sw_input);
  sw_io_bytes(&io, t, sizeof *t); /* the first of sim_io */
  bad = bad || io.bad;
  sw_io_free(&io);
  if (bad) return sw_errf(err, errsz, "%s/restart.bin: not a restart file of this sinew", dir), SW_FATAL;
  snprintf(scene, scenesz, "%s", h.scene);
  *opt = h.opt;
  memset(ov, 0, sizeof *ov);
  memcpy(ov->grid, h.grid, sizeof ov->grid);
  ov->stiffness_scale = h.stiffness_scale;
  ov->bending_matrix = h.opt.bending_matrix + 1; /* the terms are built with it */
  return SW_OK;
}

/* The state, the integrator's history and the folder of the run in m->opt.out_dir, from its
 * restart.bin. */
static int resume_from(sw_sim *s, int flags, char *err, size_t errsz) {
  const char *dir = s->m->opt.out_dir;
  sw_io io;
  if (sw_io_read(&io, dir, err, errsz)) return SW_NOSTART;
  int fitting = 0; /* the fit's integrator, or the method's */
  int rc = check_head(&io, s->m, flags & SW_SIM_FORCE, &fitting, dir, err, errsz) ||
                   (fitting ? fit_enter(s, err, errsz) : start_method(s, err, errsz))
               ? SW_NOSTART
               : SW_OK;
  if (!rc) {
    sim_io(s, &io);
    if (io.bad) rc = SW_NOSTART, sw_errf(err, errsz, "%s/restart.bin: cut short", dir);
    s->t_begin = s->d->t;
    if (fitting) s->fit_wall0 = sw_now() - s->d->fit_wall; /* its time so far, loaded */
    /* written by the step that reached grid point n + 1, before the loop counted it (the fit
     * counts its steps in d->fit_steps) */
    else if (!rc && grid_next(s) <= s->d->t + 1e-9 * s->m->opt.dt) s->n++;
  }
  if (!rc && !s->ops->history && s->ops->reset) s->ops->reset(s->st, s->m, s->d, SW_CHANGED_STATE);
  if (!rc && (flags & SW_SIM_OUTPUT) && !(s->out = sw_output_resume(s->m, s->d, &io, err, errsz)))
    rc = SW_NOSTART;
  sw_io_free(&io);
  s->started = !rc;
  return rc;
}

sw_sim *sw_sim_resume(sw_model *m, int flags, int *status, char *err, size_t errsz) {
  *status = SW_FATAL;
  sw_sim *s = sim_alloc(m, flags, err, errsz);
  if (!s) return NULL;
  s->finished = 1; /* nothing to close until the folder is open */
  if (!strcmp(m->opt.method, "static"))
    return sw_errf(err, errsz, "a static solve is not resumed; expected a run of a method"),
           sw_sim_free(s), NULL;
  int rc = resume_from(s, flags, err, errsz);
  if (rc) return *status = rc, sw_sim_free(s), NULL;
  s->finished = 0;
  double u; /* the diagnostics of the state, as after the step that reached it */
  if (diagnose(s, &u)) {
    sw_errf(err, errsz, "t = %.9g s: cannot evaluate the resumed state: %s", s->d->t, s->d->err);
    outcome(s, SW_FATAL, err);
    return sw_sim_free(s), NULL;
  }
  if (s->fitting && (rc = fit_then_start(s, err, errsz))) /* the rest of the fit, as begin */
    return start_failed(s, rc, status, err);
  *status = SW_OK;
  return s;
}

/* ------------------------------------------------------ changes between steps */

/* K + U at the current state (U from the last evaluation), J. */
static double total_energy(const sw_sim *s) {
  double k, u, dis;
  sw_sim_energy(s, &k, &u, &dis);
  return k + u;
}

/* After a change (SW_CHANGED_*) that moved the total energy from e_before: the diagnostics of
 * the new state, and an automatic energy bound raised to admit it (1e3 x the energy the change
 * put in above the new total, as sw_energy_bound allows at the start). */
static int changed(sw_sim *s, int what, double e_before, char *err, size_t errsz) {
  s->changed |= what;
  double u;
  if (diagnose(s, &u))
    return sw_errf(err, errsz, "t = %.9g s: cannot evaluate the changed state: %s", s->d->t,
                   s->d->err),
           SW_FATAL;
  double e = total_energy(s);
  if (s->m->opt.energy_bound <= 0.0 && s->d->energy_bound > 0.0)
    s->d->energy_bound = fmax(s->d->energy_bound, e + 1e3 * fabs(e - e_before));
  return SW_OK;
}

static int all_finite(const double *a, long n) {
  for (long i = 0; i < n; i++)
    if (!isfinite(a[i])) return 0;
  return 1;
}

/* The step grid after the state was set at t: n dt from 0 when t is on it (to 1e-9 dt), else
 * a new grid from t. */
static void set_grid(sw_sim *s, double t) {
  const double dt = s->m->opt.dt, k = dt > 0.0 ? round(t / dt) : 0.0;
  int on = dt > 0.0 && fabs(k) < 1e15 && fabs(tidy_time(k * dt, dt) - t) <= 1e-9 * dt;
  s->t0 = on ? 0.0 : t;
  s->n = on ? (long)k : 0;
}

int sw_sim_set_state(sw_sim *s, double t, const double *x, const double *v, char *err,
                     size_t errsz) {
  if (check_open(s, "set_state", err, errsz)) return SW_FATAL;
  const sw_model *m = s->m;
  sw_data *d = s->d;
  const long nd = (long)m->nv * m->dim;
  if (!isfinite(t) || (x && !all_finite(x, nd)) || (v && !all_finite(v, nd)))
    return sw_errf(err, errsz, "set_state: a value is not finite"), SW_FATAL;
  double e0 = total_energy(s);
  d->t = t;
  if (x) memcpy(d->x, x, (size_t)nd * sizeof(double));
  for (long i = 0; v && i < nd; i++) d->v[i] = m->pinned[i / m->dim] ? 0.0 : v[i];
  set_grid(s, t);
  s->logged = 0; /* no damping trapezoid across the jump */
  s->next_frame = m->opt.frames_every > 0 ? t + m->opt.frames_every : m->opt.frames_every;
  s->next_positions = m->opt.positions_every > 0 ? t + m->opt.positions_every : 0.0;
  return changed(s, SW_CHANGED_STATE, e0, err, errsz);
}

/* Tendon k exists and rest (m) is a length; else err. */
static int check_rest(const sw_sim *s, int k, double rest, char *err, size_t errsz) {
  if (k < 0 || k >= s->m->ntendon)
    return sw_errf(err, errsz, "set_rest: no tendon %d (the scene has %d)", k, s->m->ntendon),
           SW_FATAL;
  if (!isfinite(rest) || rest < 0.0)
    return sw_errf(err, errsz, "set_rest: tendon '%s': rest length %g m; expected a finite "
                   "value >= 0", s->m->tendon[k].name, rest),
           SW_FATAL;
  return SW_OK;
}

static void put_rest(sw_tendon *td, double rest) {
  td->nkey = 1; /* constant from now on */
  td->key_t[0] = 0.0;
  td->key_rest[0] = rest;
}

/* The arrays sw_sim_array hands out of sw_data: their addresses outlive sw_sim_reset. */
static double **data_array(sw_data *d, int k, size_t *n, const sw_model *m) {
  const size_t nd = (size_t)m->nv * (size_t)m->dim, nf = (size_t)m->nf;
  const size_t nt = (size_t)m->ntendon + 1, ne = (size_t)m->nterm;
  double **f[] = {&d->x, &d->v, &d->txy, &d->stretch_u, &d->stretch_v, &d->shear,
                  &d->tendon_length, &d->tendon_tension, &d->tendon_delta, &d->term_energy,
                  &d->contact_pressure, NULL};
  const size_t len[] = {nd, nd, nf, nf, nf, nf, nt, nt, nt, ne, nf + 1, 0};
  *n = len[k];
  return f[k];
}

/* d becomes fresh (a new sw_data of m, freed here) but keeps the addresses of its arrays
 * that bindings hold (data_array): their contents are fresh's. */
static void renew_data(sw_data *d, sw_data *fresh, const sw_model *m) {
  size_t n;
  for (int k = 0; data_array(d, k, &n, m); k++) {
    double **a = data_array(d, k, &n, m), **b = data_array(fresh, k, &n, m);
    if (!*a) continue;
    memcpy(*a, *b, n * sizeof(double));
    double *t = *a;
    *a = *b, *b = t; /* fresh holds d's array, with fresh's values */
  }
  sw_data tmp = *d;
  *d = *fresh, *fresh = tmp;
  sw_data_free(fresh);
}

int sw_sim_set_rest(sw_sim *s, int k, double rest, char *err, size_t errsz) {
  if (check_open(s, "set_rest", err, errsz)) return SW_FATAL;
  if (check_rest(s, k, rest, err, errsz)) return SW_FATAL;
  double e0 = total_energy(s);
  put_rest(&s->m->tendon[k], rest);
  return changed(s, SW_CHANGED_MODEL, e0, err, errsz);
}

int sw_sim_set_rests(sw_sim *s, const double *rest, char *err, size_t errsz) {
  if (check_open(s, "set_rests", err, errsz)) return SW_FATAL;
  for (int k = 0; k < s->m->ntendon; k++)
    if (check_rest(s, k, rest[k], err, errsz)) return SW_FATAL;
  double e0 = total_energy(s);
  for (int k = 0; k < s->m->ntendon; k++) put_rest(&s->m->tendon[k], rest[k]);
  return changed(s, SW_CHANGED_MODEL, e0, err, errsz);
}

void sw_sim_rests(const sw_sim *s, double *rest) {
  for (int k = 0; k < s->m->ntendon; k++) rest[k] = sw_tendon_rest(&s->m->tendon[k], s->d->t);
}

int sw_sim_set_dt(sw_sim *s, double dt, char *err, size_t errsz) {
  if (check_open(s, "set_dt", err, errsz)) return SW_FATAL;
  if (!s->ops)
    return sw_errf(err, errsz, "set_dt: the static method takes no time step"), SW_FATAL;
  if (!isfinite(dt) || dt <= 0.0)
    return sw_errf(err, errsz, "set_dt: dt = %g s; expected a finite value > 0", dt), SW_FATAL;
  s->m->opt.dt = dt;
  s->t0 = s->d->t, s->n = 0; /* a new grid from here */
  s->changed |= SW_CHANGED_STATE; /* a history of the old step is not this one's */
  return SW_OK;
}

int sw_sim_reset(sw_sim *s, char *err, size_t errsz) {
  if (check_open(s, "reset", err, errsz)) return SW_FATAL;
  if (s->out)
    return sw_errf(err, errsz, "reset: the simulation writes a run folder (one trajectory); "
                   "expected one without"),
           SW_FATAL;
  sw_data *fresh = sw_data_new(s->m);
  if (!fresh) return sw_errf(err, errsz, "reset: out of memory"), SW_FATAL;
  renew_data(s->d, fresh, s->m);
  if (s->ops && s->st) s->ops->free(s->st);
  s->ops = NULL, s->st = NULL;
  s->logged = s->changed = s->failed = s->stopped = 0;
  s->msg[0] = 0;
  int rc = begin(s, err, errsz);
  if (rc) outcome(s, rc, err);
  return rc;
}

/* Vertex i in range, and the dim values at p finite; else err naming what (set_pin ...). */
static int check_vertex(const sw_sim *s, const char *what, int i, const double *p, char *err,
                        size_t errsz) {
  if (i < 0 || i >= s->m->nv)
    return sw_errf(err, errsz, "%s: no vertex %d (the model has %d)", what, i, s->m->nv),
           SW_FATAL;
  if (!all_finite(p, s->m->dim))
    return sw_errf(err, errsz, "%s: vertex %d: a value is not finite", what, i), SW_FATAL;
  return SW_OK;
}

int sw_sim_set_pin(sw_sim *s, int i, const double *x, char *err, size_t errsz) {
  if (check_open(s, "set_pin", err, errsz)) return SW_FATAL;
  const sw_model *m = s->m;
  if (check_vertex(s, "set_pin", i, x, err, errsz)) return SW_FATAL;
  if (!m->pinned[i])
    return sw_errf(err, errsz, "set_pin: vertex %d is not pinned", i), SW_FATAL;
  double e0 = total_energy(s);
  for (int a = 0; a < m->dim; a++)
    if (m->dof[i * m->dim + a] < 0) s->d->x[i * m->dim + a] = x[a];
  return changed(s, SW_CHANGED_MODEL, e0, err, errsz);
}

int sw_sim_set_load(sw_sim *s, int i, const double *f, char *err, size_t errsz) {
  if (check_open(s, "set_load", err, errsz)) return SW_FATAL;
  sw_model *m = s->m;
  if (check_vertex(s, "set_load", i, f, err, errsz)) return SW_FATAL;
  if (!m->load)
    return sw_errf(err, errsz, "set_load: the scene has no `loads` (give one, a zero force is "
                   "fine, to change loads between steps)"), SW_FATAL;
  double e0 = total_energy(s);
  memcpy(m->load + (size_t)i * m->dim, f, (size_t)m->dim * sizeof(double));
  return changed(s, SW_CHANGED_MODEL, e0, err, errsz);
}

/* ------------------------------------------------------------------ state copies */

/* What a state copy begins with: the sizes and the method of the sim it came from. */
#define STATE_MAGIC "SWSTATE1"
typedef struct state_head {
  char magic[8];
  int nv, dim, nf, ndof;
  char method[64];
} state_head;

static void state_head_of(const sw_model *m, state_head *h) {
  memset(h, 0, sizeof *h);
  memcpy(h->magic, STATE_MAGIC, 8);
  h->nv = m->nv, h->dim = m->dim, h->nf = m->nf, h->ndof = m->ndof;
  snprintf(h->method, sizeof h->method, "%s", m->opt.method);
}

/* sim_io for the static method too (no integrator, no history). */
static void state_io(sw_sim *s, sw_io *io) {
  state_head h;
  state_head_of(s->m, &h);
  sw_io_bytes(io, &h, sizeof h);
  if (s->ops) {
    sim_io(s, io);
    return;
  }
  const size_t nd = (size_t)s->m->nv * (size_t)s->m->dim;
  IO(s->d->t), IO(s->d->nstep), IO(s->d->nnewton), IO(s->d->nfactor);
  sw_io_bytes(io, s->d->x, nd * sizeof(double));
  sw_io_bytes(io, s->d->v, nd * sizeof(double));
}

size_t sw_sim_get_state(sw_sim *s, void *buf, size_t size) {
  sw_io io = {0};
  state_io(s, &io);
  size_t n = io.bad ? 0 : io.len;
  if (buf && n && size >= n) memcpy(buf, io.buf, n);
  sw_io_free(&io);
  return n;
}

int sw_sim_put_state(sw_sim *s, const void *buf, size_t size, char *err, size_t errsz) {
  if (check_open(s, "put_state", err, errsz)) return SW_FATAL;
  state_head h, mine;
  state_head_of(s->m, &mine);
  if (size < sizeof h)
    return sw_errf(err, errsz, "put_state: %zu bytes; expected a state copy", size), SW_FATAL;
  memcpy(&h, buf, sizeof h);
  if (memcmp(&h, &mine, sizeof h))
    return sw_errf(err, errsz, "put_state: a state of %d vertices, %d faces in %dD with %.64s; "
                   "expected this simulation's %d, %d, %dD, %s", h.nv, h.nf, h.dim, h.method,
                   mine.nv, mine.nf, mine.dim, mine.method),
           SW_FATAL;
  sw_io io = {.load = 1, .buf = (unsigned char *)buf, .len = size};
  state_io(s, &io);
  if (io.bad || io.pos != size)
    return sw_errf(err, errsz, "put_state: the copy is cut short or too long (%zu bytes)", size),
           SW_FATAL;
  s->failed = s->stopped = 0;
  /* the history is the state's (a pending change of the model still counts); an integrator
   * without one (CVODE, IDA) restarts at the state */
  s->changed &= ~SW_CHANGED_STATE;
  if (s->ops && !s->ops->history && s->ops->reset) s->ops->reset(s->st, s->m, s->d, SW_CHANGED_STATE);
  double u;
  if (diagnose(s, &u))
    return sw_errf(err, errsz, "t = %.9g s: cannot evaluate the state: %s", s->d->t, s->d->err),
           SW_FATAL;
  return SW_OK;
}

/* ------------------------------------------------------------------ reading */

const sw_data *sw_sim_data(const sw_sim *s) { return s->d; }
const sw_model *sw_sim_model(const sw_sim *s) { return s->m; }

void sw_sim_energy(const sw_sim *s, double *kinetic, double *potential, double *dissipated) {
  double u = 0.0;
  for (int k = 0; k < s->m->nterm; k++) u += s->d->term_energy[k];
  *kinetic = sw_kinetic(s->m, s->d->v);
  *potential = u;
  *dissipated = s->d->dissipated;
}

double sw_sim_time(const sw_sim *s) { return s->d->t; }
double sw_sim_dt(const sw_sim *s) { return s->m->opt.dt; }

double sw_sim_rest(const sw_sim *s, int k) {
  return k >= 0 && k < s->m->ntendon ? sw_tendon_rest(&s->m->tendon[k], s->d->t) : NAN;
}

const int *sw_sim_waypoints(const sw_sim *s, int k, int *n) {
  if (k < 0 || k >= s->m->ntendon) return *n = 0, NULL;
  *n = s->m->tendon[k].nway;
  return s->m->tendon[k].way;
}
