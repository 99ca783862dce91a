/* implicit_midpoint.c — the implicit midpoint rule ("implicit-midpoint") on x' = v, M v' = f(x):
 *   x_{n+1} = x_n + h (v_n + v_{n+1}) / 2,
 *   v_{n+1} = v_n + h M^-1 f((x_n + x_{n+1}) / 2, t_n + h/2).
 * With the midpoint y = (x_n + x_{n+1}) / 2, the first line gives v_{n+1} = 4 (y - x_n)/h - v_n;
 * put into the second, 4/h^2 M (y - xhat) = f(y) with xhat = x_n + (h/2) v_n: the stationarity
 * condition of
 *   Phi(y) = a/2 (y - xhat)^T M (y - xhat) + U(y, t_n + h/2),  a = 4/h^2,
 * minimised by one Newton solve (line search, to the scene's tolerance); then
 *   x_{n+1} = 2 y - x_n,  v_{n+1} = 2 (x_{n+1} - x_n)/h - v_n.
 * Order 2, A-stable with |R| = 1 on the imaginary axis: no numerical damping.  Symplectic and
 * symmetric; it conserves quadratic invariants (linear and angular momentum, and the energy of
 * a linear problem up to the Newton tolerance), and for nonlinear problems at steps that
 * resolve the motion its energy error stays bounded (no drift).  Undamped stiff modes keep
 * ringing, and on stiff nonlinear cloth at h w_max >> 1 the energy can grow until it blows up
 * (measured on the shipped scene even at dt = 2.5 ms, docs/integrators.md): A-stability is a
 * linear property. */
#include "solver.h"
#include "util.h"

typedef struct mid_state {
  sw_ipstep ip;
} mid_state;

static void mid_free(void *p) {
  mid_state *s = p;
  if (!s) return;
  sw_ipstep_free(&s->ip);
  sw_free(s);
}

static int mid_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  mid_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  int rc = sw_ipstep_init(&s->ip, m, err, errsz);
  if (rc) {
    mid_free(s);
    return rc;
  }
  *state = s;
  return SW_OK;
}

/* The kept factorisation: a resumed run goes on with the same Newton iterations. */
static void mid_history(void *p, const sw_model *m, sw_io *io) {
  (void)m;
  sw_ipstep_history(&((mid_state *)p)->ip, io);
}

static void mid_reset(void *p, const sw_model *m, sw_data *d, int what) {
  (void)m, (void)d, (void)what;
  sw_ipstep_reset(&((mid_state *)p)->ip);
}

static int mid_step(void *p, const sw_model *m, sw_data *d, double h) {
  sw_ipstep *ip = &((mid_state *)p)->ip;
  const int nd = m->nv * m->dim;
  for (int i = 0; i < nd; i++) {
    ip->xhat[i] = d->x[i] + 0.5 * h * d->v[i];
    ip->xd[i] = d->x[i];
  }
  /* damping: v_mid = (x_{n+1} - x_n)/h = 2 (y - x_n)/h, D at xhat = x_n + h/2 v_n, a predictor
   * of the midpoint to O(h^2): that keeps order 2.  The Newton variable is the midpoint: an
   * error e in y is 2e in x_{n+1}, hence half the tolerance. */
  sw_newton_opts o = sw_ipstep_opts(m, ip, 4.0 / (h * h), d->t + 0.5 * h, 2.0 / h, h, 0.5);
  int rc = sw_ipstep_solve(ip, m, d, &o, NULL);
  if (rc) return rc;
  for (int i = 0; i < nd; i++) {
    if (m->dof[i] < 0) {
      ip->xnew[i] = d->x[i];
      ip->vnew[i] = 0.0;
    } else {
      ip->xnew[i] = 2.0 * ip->xnew[i] - d->x[i]; /* now x_{n+1} */
      ip->vnew[i] = 2.0 * (ip->xnew[i] - d->x[i]) / h - d->v[i];
    }
  }
  return sw_ipstep_commit(ip, m, d, h, 1);
}

/* The power of the damping the last step applied, at the state it accepted. */
static int mid_damping_power(void *p, const sw_model *m, const sw_data *d, double *power) {
  return sw_ipstep_damping_power(&((mid_state *)p)->ip, m, d, power);
}

const sw_integrator_ops sw_implicit_midpoint_ops = {
    .name = "implicit-midpoint",
    .summary = "implicit midpoint, Newton (order 2, symplectic, no damping)",
    .init = mid_init,
    .step = mid_step,
    .free = mid_free,
    .reset = mid_reset,
    .history = mid_history,
    .damping_power = mid_damping_power,
};
