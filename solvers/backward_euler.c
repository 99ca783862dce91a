/* backward_euler.c — backward Euler as minimisation of the incremental potential
 *   x_{n+1} = argmin 1/(2h^2) (x - xhat)^T M (x - xhat) + U(x, t_{n+1}),  xhat = x_n + h v_n,
 *   v_{n+1} = (x_{n+1} - x_n) / h,
 * solved by Newton with a line search to the scene's tolerance ("backward-euler"), and the
 * classic Baraff–Witkin variant ("baraff-witkin"): one Newton step from x_n without line search.
 * That single step is exactly Baraff and Witkin's (M + h^2 H) dv = h (f_n - h H v_n) with
 * x_{n+1} = x_n + h (v_n + dv), since grad Phi(x_n) = -(M v_n / h + f_n).
 * The proximal step of the optimisation fit (sim.c, fit_stage) is the same minimisation with
 * xhat = x_n: the proximal point method on U (Rockafellar, "Monotone operators and the proximal
 * point algorithm", 1976) with weight M / h^2, an incremental potential that keeps no momentum;
 * v_{n+1} = (x_{n+1} - x_n) / h is still recorded (the fit's stopping test reads it). */
#include "solver.h"
#include "util.h"

typedef struct be_state {
  sw_ipstep ip;
  int one_step; /* 1: Baraff–Witkin */
  int proximal; /* 1: the optimisation fit's proximal step, xhat = x_n (no momentum kept) */
} be_state;

static void be_free(void *p) {
  be_state *s = p;
  if (!s) return;
  sw_ipstep_free(&s->ip);
  sw_free(s);
}

static int init_common(void **state, const sw_model *m, int one_step, int proximal, char *err,
                       size_t errsz) {
  be_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory for the step's state"), SW_FATAL;
  s->one_step = one_step;
  s->proximal = proximal;
  int rc = sw_ipstep_init(&s->ip, m, err, errsz);
  if (rc) {
    be_free(s);
    return rc;
  }
  *state = s;
  return SW_OK;
}

static int be_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  return init_common(state, m, 0, 0, err, errsz);
}

static int bw_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  return init_common(state, m, 1, 0, err, errsz);
}

static int px_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  return init_common(state, m, 0, 1, err, errsz);
}

/* The kept factorisation: a resumed run goes on with the same Newton iterations. */
static void be_history(void *p, const sw_model *m, sw_io *io) {
  (void)m;
  sw_ipstep_history(&((be_state *)p)->ip, io);
}

static void be_reset(void *p, const sw_model *m, sw_data *d, int what) {
  (void)m, (void)d, (void)what;
  sw_ipstep_reset(&((be_state *)p)->ip);
}

static int be_step(void *p, const sw_model *m, sw_data *d, double h) {
  be_state *s = p;
  sw_ipstep *ip = &s->ip;
  const int nd = m->nv * m->dim;
  /* fit.mode settle: backward Euler itself while the fit's ramps run (to gravity in full) */
  int proximal = s->proximal && !(m->fit.mode == SW_FIT_SETTLE &&
                                   d->t < m->gravity_delay + m->gravity_ramp - 1e-9 * h);
  for (int i = 0; i < nd; i++) {
    ip->xhat[i] = d->x[i] + (proximal ? 0.0 : h * d->v[i]);
    ip->xd[i] = d->x[i]; /* damping: v_{n+1} = (x - x_n) / h */
  }
  sw_newton_opts o = sw_ipstep_opts(m, ip, 1.0 / (h * h), d->t + h, 1.0 / h, h, 1.0);
  if (s->one_step) { /* one full Newton step from x_n, with its own fresh matrix */
    o.max_iter = 1;
    o.line_search = 0;
    o.must_converge = 0;
    o.reuse = 0;
  }
  /* the proximal step starts Newton from the motion's extrapolation, its centre kept at x_n */
  if (proximal)
    for (int i = 0; i < nd; i++) ip->xnew[i] = d->x[i] + h * d->v[i];
  int rc = sw_ipstep_solve(ip, m, d, &o, s->one_step ? d->x : proximal ? ip->xnew : NULL);
  if (rc) return rc;
  for (int i = 0; i < nd; i++) ip->vnew[i] = m->dof[i] < 0 ? 0.0 : (ip->xnew[i] - d->x[i]) / h;
  return sw_ipstep_commit(ip, m, d, h, 0);
}

/* The power of the damping the last step applied, at the state it accepted. */
static int be_damping_power(void *p, const sw_model *m, const sw_data *d, double *power) {
  return sw_ipstep_damping_power(&((be_state *)p)->ip, m, d, power);
}

const sw_integrator_ops sw_backward_euler_ops = {
    .name = "backward-euler",
    .summary = "backward Euler, Newton with line search to tolerance (order 1, L-stable, damps)",
    .init = be_init,
    .step = be_step,
    .free = be_free,
    .reset = be_reset,
    .history = be_history,
    .damping_power = be_damping_power,
};

const sw_integrator_ops sw_baraff_witkin_ops = {
    .name = "baraff-witkin",
    .summary = "Baraff-Witkin: backward Euler linearised, one Newton step per time step",
    .init = bw_init,
    .step = be_step,
    .free = be_free,
    .reset = be_reset,
    .history = be_history,
    .damping_power = be_damping_power,
};

/* Not a scene method: the optimisation fit's step (docs/garments.md, `fit.mode: optimize`). */
const sw_integrator_ops sw_proximal_ops = {
    .name = "proximal",
    .summary = "the proximal step of the optimisation fit: backward Euler with no momentum",
    .init = px_init,
    .step = be_step,
    .free = be_free,
    .reset = be_reset,
    .history = be_history,
    .damping_power = be_damping_power,
};
