/* newton.c — Newton's method with a backtracking line search on an incremental potential
 *   Phi(x) = a/2 (x - xhat)^T M (x - xhat) + U(x, t)
 * over the free DOFs.  Each iteration assembles S = a M + H (H the PSD-projected Hessian, so S
 * is positive definite whenever a > 0), refactorises it on the fixed pattern and solves
 * S dx = -grad Phi.  Backward Euler is the minimiser with a = 1/h^2 (DESIGN.md). */
#include <math.h>
#include <string.h>

#include "solver.h"
#include "util.h"

int sw_newton_init(sw_newton *nw, const sw_model *m, char *err, size_t errsz) {
  memset(nw, 0, sizeof *nw);
  nw->n = m->ndof;
  nw->nterm = m->nterm;
  int rc = sw_pattern_build(&nw->pat, m, err, errsz);
  if (rc) return rc;
  if (nw->n > 0 && (rc = sw_chol_init(&nw->chol, &nw->pat, err, errsz))) return rc;
  nw->g = sw_calloc((size_t)nw->n, sizeof(double));
  nw->dx = sw_calloc((size_t)nw->n, sizeof(double));
  nw->xtry = sw_calloc((size_t)m->nv * (size_t)m->dim, sizeof(double));
  int damped = sw_damped(m);
  if (damped) {
    nw->dval = sw_calloc((size_t)nw->pat.nnz + 1, sizeof(double));
    nw->r = sw_calloc((size_t)nw->n + 1, sizeof(double));
    nw->dr = sw_calloc((size_t)nw->n + 1, sizeof(double));
  }
  if (!nw->g || !nw->dx || !nw->xtry || (damped && (!nw->dval || !nw->r || !nw->dr))) {
    sw_errf(err, errsz, "out of memory for Newton's workspaces (%d DOFs)", nw->n);
    return SW_FATAL;
  }
  return SW_OK;
}

void sw_newton_free(sw_newton *nw) {
  sw_chol_free(&nw->chol);
  sw_pattern_free(&nw->pat, nw->nterm);
  sw_free(nw->g);
  sw_free(nw->dx);
  sw_free(nw->xtry);
  sw_free(nw->dval);
  sw_free(nw->r);
  sw_free(nw->dr);
  memset(nw, 0, sizeof *nw);
}

int sw_newton_damping(sw_newton *nw, const sw_model *m, sw_data *d, const double *x, double t) {
  if (!nw->dval) return SW_OK;
  double u, beta = m->damp_stiffness, t0 = sw_now();
  int rc = beta > 0.0 ? sw_eval_terms(m, d, x, t, 0, 1, 1, &u) : SW_OK;
  if (rc) return rc;
  if (beta > 0.0) {
    sw_pattern_fill(&nw->pat, m, d, m->damp_mass, beta, nw->dval);
  } else { /* alpha M alone: no Hessian needed */
    memset(nw->dval, 0, (size_t)nw->pat.nnz * sizeof(double));
    for (int i = 0; i < m->nv * m->dim; i++)
      if (m->dof[i] >= 0) nw->dval[nw->pat.diag[m->dof[i]]] = m->damp_mass * m->mass[i / m->dim];
  }
  sw_damping_tendons_fill(&nw->pat, m, x, nw->dval);
  d->time_assemble += sw_now() - t0;
  return SW_OK;
}

/* cd/2 r.D r with r = x - xd on the free DOFs; its gradient cd D r into nw->dr. */
static double damping_phi(sw_newton *nw, const sw_model *m, const double *x) {
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) nw->r[m->dof[i]] = x[i] - nw->xd[i];
  sw_pattern_symv(&nw->pat, nw->dval, nw->r, nw->dr);
  double e = 0.0;
  for (int c = 0; c < nw->n; c++) {
    nw->dr[c] *= nw->cd;
    e += 0.5 * nw->r[c] * nw->dr[c];
  }
  return e;
}

int sw_newton_phi(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                  const double *xhat, double a, double t, int want_grad, int want_hess,
                  int project, double *phi) {
  double u;
  int rc = sw_eval_terms(m, d, x, t, want_grad, want_hess, project, &u);
  if (rc) return rc;
  double inertia = 0.0;
  const int dim = m->dim;
  for (int i = 0; i < m->nv; i++)
    for (int al = 0; al < dim; al++) {
      int c = m->dof[i * dim + al];
      if (c < 0) continue;
      double r = x[i * dim + al] - xhat[i * dim + al];
      inertia += 0.5 * a * m->mass[i] * r * r;
      if (want_grad) nw->g[c] = a * m->mass[i] * r + d->grad[i * dim + al];
    }
  *phi = inertia + u;
  if (nw->cd > 0.0 && nw->dval) {
    *phi += damping_phi(nw, m, x);
    if (want_grad)
      for (int c = 0; c < nw->n; c++) nw->g[c] += nw->dr[c];
  }
  if (!isfinite(*phi)) {
    sw_errf(d->err, sizeof d->err, "the energy is not finite (NaN or Inf) at t = %g s", t);
    return SW_RECOVER;
  }
  return SW_OK;
}

/* Fill S = a M + H (H from the last evaluation: blocks and low-rank vectors) and factorise it. */
static int fill_factor(sw_newton *nw, const sw_model *m, sw_data *d, double a) {
  double t0 = sw_now();
  double *val = sw_chol_values(&nw->chol);
  sw_pattern_fill(&nw->pat, m, d, a, 1.0, val);
  sw_pattern_fill_lowrank(&nw->pat, d, sw_chol_lowrank(&nw->chol, 1.0));
  if (nw->cd > 0.0 && nw->dval)
    for (long q = 0; q < nw->pat.nnz; q++) val[q] += nw->cd * nw->dval[q];
  double t1 = sw_now();
  d->time_assemble += t1 - t0;
  int rc = sw_chol_factor(&nw->chol, d->err, sizeof d->err);
  d->time_factor += sw_now() - t1;
  d->nfactor++;
  d->factor_nnz = sw_chol_nnz(&nw->chol);
  return rc;
}

static void add_step(const sw_model *m, const double *x, const double *dx, double alpha,
                     double *out) {
  const int dim = m->dim;
  for (int i = 0; i < m->nv * dim; i++) {
    int c = m->dof[i];
    out[i] = c < 0 ? x[i] : x[i] + alpha * dx[c];
  }
}

int sw_newton_line_search(sw_newton *nw, const sw_model *m, sw_data *d, double *x,
                          const double *xhat, const sw_newton_opts *o, double phi0, double slope) {
  /* Differences below this are round-off in Phi itself. */
  double noise = 1e-13 * (fabs(phi0) + 1e-300);
  double alpha = 1.0;
  for (int k = 0; k < 40; k++, alpha *= 0.5) {
    add_step(m, x, nw->dx, alpha, nw->xtry);
    double phi;
    int rc = sw_newton_phi(nw, m, d, nw->xtry, xhat, o->a, o->t, 0, 0, 0, &phi);
    if (rc < 0) return rc;
    if (rc == SW_OK && phi <= phi0 + 1e-4 * alpha * slope + noise) {
      memcpy(x, nw->xtry, (size_t)m->nv * (size_t)m->dim * sizeof(double));
      return SW_OK;
    }
    d->nlinesearch++;
  }
  sw_errf(d->err, sizeof d->err, "line search found no decrease at t = %g s", o->t);
  return SW_RECOVER;
}

/* max |v_i|, or NaN when any v_i is NaN (fmax would drop it, and a NaN step would "converge"). */
static double max_abs(const double *v, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) {
    if (isnan(v[i])) return NAN;
    s = fmax(s, fabs(v[i]));
  }
  return s;
}

/* Evaluate Phi, its gradient and the Hessian at x, and factorise S = a M + H with the Hessian
 * the options ask for (auto: exact, projected when that S is not positive definite). */
static int linearise(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                     const double *xhat, const sw_newton_opts *o, double *phi) {
  int mode = o->hessian;
  double t0 = sw_now();
  int rc = sw_newton_phi(nw, m, d, x, xhat, o->a, o->t, 1, 1, mode == SW_HESSIAN_PROJECTED,
                         phi);
  d->time_assemble += sw_now() - t0;
  if (!rc) rc = fill_factor(nw, m, d, o->a);
  if (rc == SW_RECOVER && mode == SW_HESSIAN_AUTO) {
    double u;
    t0 = sw_now();
    rc = sw_eval_terms(m, d, x, o->t, 0, 1, 1, &u);
    d->time_assemble += sw_now() - t0;
    if (!rc) rc = fill_factor(nw, m, d, o->a);
  }
  return rc;
}

int sw_newton_solve(sw_newton *nw, const sw_model *m, sw_data *d, double *x, const double *xhat,
                    const sw_newton_opts *o) {
  d->last_newton = 0;
  if (nw->n == 0) return SW_OK;
  nw->cd = o->xd ? o->cd : 0.0;
  nw->xd = o->xd;
  for (int it = 0; it < o->max_iter; it++) {
    double phi;
    int rc = linearise(nw, m, d, x, xhat, o, &phi);
    if (rc) return rc;
    for (int c = 0; c < nw->n; c++) nw->g[c] = -nw->g[c];
    double t0 = sw_now();
    rc = sw_chol_solve(&nw->chol, nw->g, nw->dx, d->err, sizeof d->err);
    d->time_solve += sw_now() - t0;
    if (rc) return rc;
    d->nnewton++;
    d->last_newton++;
    double slope = 0.0; /* grad Phi . dx, negative for a descent direction */
    for (int c = 0; c < nw->n; c++) slope -= nw->g[c] * nw->dx[c];
    double step = max_abs(nw->dx, nw->n);
    if (!isfinite(step)) {
      sw_errf(d->err, sizeof d->err, "Newton step is not finite at t = %g s", o->t);
      return SW_RECOVER;
    }
    if (o->line_search && step > o->tol_dx) {
      rc = sw_newton_line_search(nw, m, d, x, xhat, o, phi, slope);
      if (rc) return rc;
    } else {
      add_step(m, x, nw->dx, 1.0, x);
    }
    if (step <= o->tol_dx) return SW_OK;
  }
  if (!o->must_converge) return SW_OK;
  sw_errf(d->err, sizeof d->err, "Newton did not converge in %d iterations at t = %g s",
          o->max_iter, o->t);
  return SW_RECOVER;
}
