/* backward_euler.c — backward Euler as minimisation of the incremental potential
 *   x_{n+1} = argmin 1/(2h^2) (x - xhat)^T M (x - xhat) + U(x, t_{n+1}),  xhat = x_n + h v_n,
 *   v_{n+1} = (x_{n+1} - x_n) / h,
 * solved by Newton with a line search to the scene's tolerance ("backward-euler"), and the
 * classic Baraff–Witkin variant ("baraff-witkin"): one Newton step from x_n without line search.
 * That single step is exactly Baraff and Witkin's (M + h^2 H) dv = h (f_n - h H v_n) with
 * x_{n+1} = x_n + h (v_n + dv), since grad Phi(x_n) = -(M v_n / h + f_n). */
#include <string.h>

#include "solver.h"
#include "util.h"

typedef struct be_state {
  sw_newton nw;
  double *xhat, *xnew; /* (nv x dim) */
  int one_step;        /* 1: Baraff–Witkin */
} be_state;

static void be_free(void *p) {
  be_state *s = p;
  if (!s) return;
  sw_newton_free(&s->nw);
  sw_free(s->xhat);
  sw_free(s->xnew);
  sw_free(s);
}

static int init_common(void **state, const sw_model *m, int one_step, char *err, size_t errsz) {
  be_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory for the step's state"), SW_FATAL;
  s->one_step = one_step;
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  s->xhat = sw_calloc(nd, sizeof(double));
  s->xnew = sw_calloc(nd, sizeof(double));
  int rc = (!s->xhat || !s->xnew) ? (sw_errf(err, errsz, "out of memory for the step's state"), SW_FATAL)
                                  : sw_newton_init(&s->nw, m, err, errsz);
  if (rc) {
    be_free(s);
    return rc;
  }
  *state = s;
  return SW_OK;
}

static int be_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  return init_common(state, m, 0, err, errsz);
}

static int bw_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  return init_common(state, m, 1, err, errsz);
}

static int be_step(void *p, const sw_model *m, sw_data *d, double h) {
  be_state *s = p;
  const int nd = m->nv * m->dim;
  for (int i = 0; i < nd; i++) s->xhat[i] = d->x[i] + h * d->v[i];
  memcpy(s->xnew, s->one_step ? d->x : s->xhat, (size_t)nd * sizeof(double));
  sw_newton_opts o = {
      .a = 1.0 / (h * h),
      .t = d->t + h,
      .max_iter = s->one_step ? 1 : m->opt.newton_max,
      .tol_dx = m->opt.newton_tol * h,
      .line_search = !s->one_step,
      .must_converge = !s->one_step,
      .hessian = m->opt.hessian,
      .cd = 1.0 / h, /* damping: v_{n+1} = (x - x_n) / h */
      .xd = d->x,
  };
  int rc = sw_newton_damping(&s->nw, m, d, s->xhat, d->t + h);
  if (rc) return rc;
  rc = sw_newton_solve(&s->nw, m, d, s->xnew, s->xhat, &o);
  if (rc) return rc;
  for (int i = 0; i < nd; i++) {
    d->v[i] = m->dof[i] < 0 ? 0.0 : (s->xnew[i] - d->x[i]) / h;
    d->x[i] = s->xnew[i];
  }
  d->t += h;
  d->last_dt = h;
  d->nstep++;
  return SW_OK;
}

const sw_integrator_ops sw_backward_euler_ops = {
    .name = "backward-euler",
    .summary = "backward Euler, Newton with line search to tolerance (order 1, L-stable, damps)",
    .init = be_init,
    .step = be_step,
    .free = be_free,
};

const sw_integrator_ops sw_baraff_witkin_ops = {
    .name = "baraff-witkin",
    .summary = "Baraff-Witkin: backward Euler linearised, one Newton step per time step",
    .init = bw_init,
    .step = be_step,
    .free = be_free,
};
