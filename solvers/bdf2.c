/* bdf2.c — the two-step backward differentiation formula ("bdf2") on x' = v, M v' = f(x):
 *   x_{n+1} - 4/3 x_n + 1/3 x_{n-1} = 2/3 h v_{n+1},
 *   v_{n+1} - 4/3 v_n + 1/3 v_{n-1} = 2/3 h M^-1 f(x_{n+1}, t_{n+1}).
 * With xb = 4/3 x_n - 1/3 x_{n-1} and vb = 4/3 v_n - 1/3 v_{n-1}, the first line gives
 * v_{n+1} = 3/(2h) (x_{n+1} - xb); put into the second, 9/(4h^2) M (x_{n+1} - xhat) = f(x_{n+1})
 * with xhat = xb + (2h/3) vb: the stationarity condition of
 *   Phi(x) = a/2 (x - xhat)^T M (x - xhat) + U(x, t_{n+1}),  a = 9/(4h^2),
 * which one Newton solve (line search, to the scene's tolerance) minimises.
 * Order 2, A-stable (and L-stable: it damps the stiffest modes, far less than backward Euler
 * damps the resolved ones).
 *
 * Start and step changes: BDF2 needs (x_{n-1}, v_{n-1}) a step h behind.  The first step, and
 * any step whose h differs from the previous one (a retry with h/2 after a failure, the last
 * shorter step of a run, or a state changed behind the integrator's back), is a backward Euler
 * step; the next step of the same size is BDF2 again.  That restart is exact and keeps
 * L-stability, but each restart step has a local error O(h^2) instead of O(h^3): it lowers
 * the order locally (a bounded number of restarts keeps the global order 2).  The
 * variable-step BDF2 formula was not used: it is zero-stable only for step ratios below
 * 1 + sqrt(2), and the run loop goes from h/4 back to h after two halvings. */
#include <math.h>
#include <string.h>

#include "solver.h"
#include "util.h"

typedef struct bdf2_state {
  sw_ipstep ip;
  double *xprev, *vprev; /* (nv x dim) */
  int have_prev;       /* xprev, vprev hold the state at tcur - hprev */
  double hprev, tcur;  /* size and end time of the last accepted step */
} bdf2_state;

static void bdf2_free(void *p) {
  bdf2_state *s = p;
  if (!s) return;
  sw_ipstep_free(&s->ip);
  sw_free(s->xprev);
  sw_free(s->vprev);
  sw_free(s);
}

static int bdf2_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  bdf2_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  s->xprev = sw_calloc(nd, sizeof(double));
  s->vprev = sw_calloc(nd, sizeof(double));
  int rc = (!s->xprev || !s->vprev) ? (sw_errf(err, errsz, "out of memory"), SW_FATAL)
                                    : sw_ipstep_init(&s->ip, m, err, errsz);
  if (rc) {
    bdf2_free(s);
    return rc;
  }
  *state = s;
  return SW_OK;
}

/* A changed state has no past a step behind: the next step is a backward Euler start.  A
 * changed model keeps the history (it is still the solution's, as at a keyframe). */
static void bdf2_reset(void *p, const sw_model *m, sw_data *d, int what) {
  (void)m, (void)d;
  bdf2_state *s = p;
  sw_ipstep_reset(&s->ip);
  if (what & SW_CHANGED_STATE) s->have_prev = 0;
}

static int bdf2_step(void *p, const sw_model *m, sw_data *d, double h) {
  bdf2_state *s = p;
  sw_ipstep *ip = &s->ip;
  const int nd = m->nv * m->dim;
  /* Same step as the last one, from where it ended (the run loop resets d->t to the interval
   * end, so times match to round-off only). */
  int bdf = s->have_prev && fabs(h - s->hprev) <= 1e-9 * h && fabs(d->t - s->tcur) <= 1e-9 * h;
  double a, c = 1.0 / h; /* c: v_{n+1} = c (x_{n+1} - xb), xb in xd (BE start: xb = x_n) */
  if (bdf) {
    a = 9.0 / (4.0 * h * h);
    c = 3.0 / (2.0 * h);
    for (int i = 0; i < nd; i++) {
      double xb = (4.0 * d->x[i] - s->xprev[i]) / 3.0, vb = (4.0 * d->v[i] - s->vprev[i]) / 3.0;
      ip->xhat[i] = xb + (2.0 * h / 3.0) * vb;
      ip->xd[i] = xb;
    }
  } else {
    a = 1.0 / (h * h);
    for (int i = 0; i < nd; i++) {
      ip->xhat[i] = d->x[i] + h * d->v[i];
      ip->xd[i] = d->x[i];
    }
  }
  /* damping: D v_{n+1} = c D (x - xb); D at xhat, a predictor of x_{n+1} to O(h^2): that
   * keeps order 2 */
  sw_newton_opts o = sw_ipstep_opts(m, ip, a, d->t + h, c, h, 1.0);
  int rc = sw_ipstep_solve(ip, m, d, &o, NULL);
  if (rc) return rc;
  for (int i = 0; i < nd; i++) ip->vnew[i] = m->dof[i] < 0 ? 0.0 : c * (ip->xnew[i] - ip->xd[i]);
  if ((rc = sw_energy_check(m, d, ip->xnew, ip->vnew, d->t + h))) return rc;
  memcpy(s->xprev, d->x, (size_t)nd * sizeof(double));
  memcpy(s->vprev, d->v, (size_t)nd * sizeof(double));
  sw_ipstep_commit(ip, m, d, h, 0);
  s->have_prev = 1;
  s->hprev = h;
  s->tcur = d->t;
  return SW_OK;
}

/* The previous state, its step and time: a resumed run goes on with the BDF2 formula. */
static void bdf2_history(void *p, const sw_model *m, sw_io *io) {
  bdf2_state *s = p;
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  sw_io_bytes(io, &s->have_prev, sizeof s->have_prev);
  sw_io_bytes(io, &s->hprev, sizeof s->hprev);
  sw_io_bytes(io, &s->tcur, sizeof s->tcur);
  sw_io_bytes(io, s->xprev, nd * sizeof(double));
  sw_io_bytes(io, s->vprev, nd * sizeof(double));
  sw_ipstep_history(&s->ip, io);
}

/* The power of the damping the last step applied, at the state it accepted. */
static int bdf2_damping_power(void *p, const sw_model *m, const sw_data *d, double *power) {
  return sw_ipstep_damping_power(&((bdf2_state *)p)->ip, m, d, power);
}

const sw_integrator_ops sw_bdf2_ops = {
    .history = bdf2_history,
    .name = "bdf2",
    .summary = "BDF2, Newton; restarts on a step change (order 2, L-stable)",
    .init = bdf2_init,
    .step = bdf2_step,
    .free = bdf2_free,
    .reset = bdf2_reset,
    .damping_power = bdf2_damping_power,
};
