/* newmark.c — Newmark's method with beta = 1/4, gamma = 1/2, the average-acceleration
 * (trapezoidal) rule ("newmark"), on x' = v, M v' = f(x):
 *   x_{n+1} = x_n + h v_n + h^2 ((1/2 - beta) a_n + beta a_{n+1}),
 *   v_{n+1} = v_n + h ((1 - gamma) a_n + gamma a_{n+1}),  a_k = M^-1 f(x_k, t_k).
 * With xhat = x_n + h v_n + h^2 (1/2 - beta) a_n the first line reads
 * 1/(beta h^2) M (x_{n+1} - xhat) = f(x_{n+1}): the stationarity condition of
 *   Phi(x) = a/2 (x - xhat)^T M (x - xhat) + U(x, t_{n+1}),  a = 1/(beta h^2) = 4/h^2,
 * minimised by one Newton solve (line search, to the scene's tolerance); then
 * a_{n+1} = (x_{n+1} - xhat) / (beta h^2) (= M^-1 f(x_{n+1}) at the converged minimiser, so no
 * extra force evaluation) and the velocity from the second line.  a_0 is evaluated at init.
 * Order 2, A-stable with no numerical damping (|R| = 1 on the imaginary axis); for a linear
 * problem it conserves the energy like the implicit midpoint rule, to which it is then
 * equivalent; for a nonlinear one it is not symplectic, and on stiff nonlinear cloth at
 * h w_max >> 1 its energy can grow until it blows up, like the midpoint rule's
 * (docs/integrators.md).  One-step: any step size, no restart. */
#include <math.h>
#include <string.h>

#include "solver.h"
#include "util.h"

#define BETA 0.25
#define GAMMA 0.5

typedef struct nm_state {
  sw_ipstep ip;
  double *acc, *anew; /* (nv x dim) a_n and a_{n+1} */
  double tacc;        /* time of the state acc belongs to */
  int stale;          /* acc must be re-evaluated (a change between steps) */
} nm_state;

static void nm_free(void *p) {
  nm_state *s = p;
  if (!s) return;
  sw_ipstep_free(&s->ip);
  sw_free(s->acc);
  sw_free(s->anew);
  sw_free(s);
}

/* acc = M^-1 f(d->x, d->t) on the free components, 0 on the pinned ones. */
static int eval_acc(nm_state *s, const sw_model *m, sw_data *d) {
  double u;
  int rc = sw_eval_terms(m, d, d->x, d->t, 1, 0, 0, &u);
  if (rc) return rc;
  for (int i = 0; i < m->nv; i++)
    for (int al = 0; al < m->dim; al++) {
      int k = i * m->dim + al;
      s->acc[k] = m->dof[k] < 0 ? 0.0 : -d->grad[k] / m->mass[i];
    }
  if (sw_damped(m)) { /* a_n = M^-1 (f - D v_n); anew as scratch for D v_n */
    if ((rc = sw_damping_force(m, d, d->x, d->t, d->v, s->anew, NULL))) return rc;
    for (int k = 0; k < m->nv * m->dim; k++) s->acc[k] -= s->anew[k] / m->mass[k / m->dim];
  }
  s->tacc = d->t;
  return SW_OK;
}

static int nm_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  nm_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  s->acc = sw_calloc(nd, sizeof(double));
  s->anew = sw_calloc(nd, sizeof(double));
  int rc = (!s->acc || !s->anew) ? (sw_errf(err, errsz, "out of memory"), SW_FATAL)
                                 : sw_ipstep_init(&s->ip, m, err, errsz);
  if (!rc && (rc = eval_acc(s, m, d))) sw_errf(err, errsz, "%s", d->err);
  if (rc) {
    nm_free(s);
    return rc;
  }
  *state = s;
  return SW_OK;
}

/* a_n = M^-1 f(x_n, t_n) no longer holds after any change: evaluated again at the next step. */
static void nm_reset(void *p, const sw_model *m, sw_data *d, int what) {
  (void)m, (void)d, (void)what;
  nm_state *s = p;
  sw_ipstep_reset(&s->ip);
  s->stale = 1;
}

static int nm_step(void *p, const sw_model *m, sw_data *d, double h) {
  nm_state *s = p;
  sw_ipstep *ip = &s->ip;
  const int nd = m->nv * m->dim;
  /* a_n belongs to the state it was computed at; the run loop resets d->t to the interval end
   * (round-off), anything more means the state was changed from outside. */
  if (s->stale || fabs(d->t - s->tacc) > 1e-9 * h) {
    int rc = eval_acc(s, m, d);
    if (rc) return rc;
    s->stale = 0;
  }
  const double bh2 = BETA * h * h;
  /* damping: v_{n+1} = v_n + h/2 (a_n + a_{n+1}) = (2/h) (x - xd) with
   * xd = xhat - h/2 (v_n + h/2 a_n); a_{n+1} = M^-1 (f - D v_{n+1}) keeps its formula.
   * D at xhat, a predictor of x_{n+1} to O(h^2): that keeps order 2. */
  for (int i = 0; i < nd; i++) {
    ip->xhat[i] = d->x[i] + h * d->v[i] + h * h * (0.5 - BETA) * s->acc[i];
    ip->xd[i] = ip->xhat[i] - 0.5 * h * (d->v[i] + 0.5 * h * s->acc[i]);
  }
  sw_newton_opts o = sw_ipstep_opts(m, ip, 1.0 / bh2, d->t + h, 2.0 / h, h, 1.0);
  int rc = sw_ipstep_solve(ip, m, d, &o, NULL);
  if (rc) return rc;
  for (int i = 0; i < nd; i++) {
    if (m->dof[i] < 0) {
      s->anew[i] = ip->vnew[i] = 0.0;
    } else {
      s->anew[i] = (ip->xnew[i] - ip->xhat[i]) / bh2;
      ip->vnew[i] = d->v[i] + h * ((1.0 - GAMMA) * s->acc[i] + GAMMA * s->anew[i]);
    }
  }
  if ((rc = sw_ipstep_commit(ip, m, d, h, 1))) return rc;
  memcpy(s->acc, s->anew, (size_t)nd * sizeof(double));
  s->tacc = d->t;
  return SW_OK;
}

/* The acceleration of the current state, as the last step left it. */
static void nm_history(void *p, const sw_model *m, sw_io *io) {
  nm_state *s = p;
  sw_io_bytes(io, &s->tacc, sizeof s->tacc);
  sw_io_bytes(io, &s->stale, sizeof s->stale);
  sw_io_bytes(io, s->acc, (size_t)m->nv * (size_t)m->dim * sizeof(double));
  sw_ipstep_history(&s->ip, io);
}

/* The power of the damping the last step applied, at the state it accepted. */
static int nm_damping_power(void *p, const sw_model *m, const sw_data *d, double *power) {
  return sw_ipstep_damping_power(&((nm_state *)p)->ip, m, d, power);
}

const sw_integrator_ops sw_newmark_ops = {
    .history = nm_history,
    .name = "newmark",
    .summary = "Newmark beta 1/4, gamma 1/2, Newton (order 2, no damping)",
    .init = nm_init,
    .step = nm_step,
    .free = nm_free,
    .reset = nm_reset,
    .damping_power = nm_damping_power,
};
