/* ipstep.c — the step shared by the Newton time integrators (backward_euler.c, bdf2.c,
 * implicit_midpoint.c, newmark.c).  Each of them is one minimisation per step of
 *   Phi(y) = a/2 (y - xhat)^T M (y - xhat) + U(y, t*)  (+ cd/2 (y - xd)^T D (y - xd))
 * with its own a, xhat, stage time t* and, with damping, the stage velocity v = cd (y - xd);
 * only those coefficients and the map from y to (x_{n+1}, v_{n+1}) differ.  This file holds
 * what they have in common: the state, the Newton options, the solve from the predictor, and
 * the commit of the new state. */
#include <string.h>

#include "solver.h"
#include "util.h"

int sw_ipstep_init(sw_ipstep *s, const sw_model *m, char *err, size_t errsz) {
  memset(s, 0, sizeof *s);
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  s->xhat = sw_calloc(nd, sizeof(double));
  s->xd = sw_calloc(nd, sizeof(double));
  s->xnew = sw_calloc(nd, sizeof(double));
  s->vnew = sw_calloc(nd, sizeof(double));
  if (!s->xhat || !s->xd || !s->xnew || !s->vnew) {
    sw_errf(err, errsz, "out of memory for the step's state (%zu coordinates)", nd);
    return SW_FATAL;
  }
  return sw_newton_init(&s->nw, m, err, errsz);
}

void sw_ipstep_free(sw_ipstep *s) {
  sw_newton_free(&s->nw);
  sw_free(s->xhat);
  sw_free(s->xd);
  sw_free(s->xnew);
  sw_free(s->vnew);
  memset(s, 0, sizeof *s);
}

void sw_ipstep_reset(sw_ipstep *s) {
  sw_newton_forget(&s->nw);
  s->committed = 0;
}

void sw_ipstep_history(sw_ipstep *s, sw_io *io) { sw_newton_history(&s->nw, io); }

sw_newton_opts sw_ipstep_opts(const sw_model *m, const sw_ipstep *s, double a, double t,
                              double cd, double h, double tol_scale) {
  sw_newton_opts o = {
      .a = a,
      .t = t,
      .max_iter = m->opt.newton_max,
      .tol_dx = tol_scale * m->opt.newton_tol * h, /* newton_tol is a velocity, m/s */
      .norm = m->opt.newton_norm,
      .line_search = 1,
      .must_converge = 1,
      .hessian = m->opt.hessian,
      .reuse = m->opt.newton_reuse,
      .cd = cd,
      .xd = s->xd,
      .h = h,
  };
  return o;
}

int sw_ipstep_solve(sw_ipstep *s, const sw_model *m, sw_data *d, const sw_newton_opts *o,
                    const double *y0) {
  const int nd = m->nv * m->dim;
  s->committed = 0; /* nw.dval is about to be this step's */
  if (!y0) y0 = s->xhat;
  for (int i = 0; i < nd; i++) s->xnew[i] = m->dof[i] < 0 ? d->x[i] : y0[i];
  /* each term's start of the step (contact: friction lagged at d->x, the guess made
   * admissible), in term order */
  int rc = SW_OK, begun = 0;
  for (int k = 0; !rc && k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    if (!t->ops->begin) continue;
    rc = t->ops->begin(t, m, d, d->tdata[k], o->h, o->t, s->xnew);
    begun = 1;
  }
  if (rc) return rc;
  /* D at the predictor; with a term that moved the guess at the start guess instead, which
   * it made admissible (the predictor may be inside an obstacle or through the cloth itself,
   * where the barriers have no Hessian) */
  rc = sw_newton_damping(&s->nw, m, d, begun ? s->xnew : s->xhat, o->t);
  if (!rc) rc = sw_newton_solve(&s->nw, m, d, s->xnew, s->xhat, o);
  /* the solve keeps the obstacles at the stage time: a moving one must not have passed
   * through the cloth on the way there (recoverable: the step is retried smaller) */
  for (int k = 0; !rc && k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    if (t->ops->swept) rc = t->ops->swept(t, m, d, d->tdata[k], s->xnew, o->t);
  }
  return rc;
}

int sw_ipstep_commit(sw_ipstep *s, const sw_model *m, sw_data *d, double h, int check_energy) {
  if (check_energy) {
    int rc = sw_energy_check(m, d, s->xnew, s->vnew, d->t + h);
    if (rc) return rc;
  }
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  memcpy(d->x, s->xnew, nd * sizeof(double));
  memcpy(d->v, s->vnew, nd * sizeof(double));
  d->t += h;
  d->last_dt = h;
  d->nstep++;
  s->committed = 1;
  return SW_OK;
}

int sw_ipstep_damping_power(sw_ipstep *s, const sw_model *m, const sw_data *d, double *power) {
  sw_newton *nw = &s->nw;
  if (!s->committed || !nw->dval) return -1;
  for (int i = 0; i < m->nv * m->dim; i++) /* nw->r, nw->dr: the damping's scratch */
    if (m->dof[i] >= 0) nw->r[m->dof[i]] = d->v[i];
  sw_pattern_symv(&nw->pat, nw->dval, nw->r, nw->dr);
  double p = 0.0;
  for (int c = 0; c < nw->n; c++) p += nw->r[c] * nw->dr[c];
  *power = p; /* W */
  return SW_OK;
}
