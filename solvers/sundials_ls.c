/* sundials_ls.c — see sundials_ls.h: the Schur-complement linear solver of CVODE and IDA. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sundials_ls.h"
#include "util.h"

/* ------------------------------------------------------------ state and forces */

void sw_sunls_pins(sw_sunls *sys, const double *x) {
  const sw_model *m = sys->m;
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] < 0) sys->xfull[i] = x[i];
}

void sw_sunls_gather(const sw_sunls *sys, const double *x, const double *v, double *y) {
  const sw_model *m = sys->m;
  for (int i = 0; i < m->nv * m->dim; i++) {
    int c = m->dof[i];
    if (c < 0) continue;
    y[c] = x[i];
    y[sys->n + c] = v[i];
  }
}

void sw_sunls_scatter(const sw_sunls *sys, const double *y, double *x, double *v) {
  const sw_model *m = sys->m;
  for (int i = 0; i < m->nv * m->dim; i++) {
    int c = m->dof[i];
    if (c < 0) {
      v[i] = 0.0;
      continue;
    }
    x[i] = y[c];
    v[i] = y[sys->n + c];
  }
}

static void set_free(const sw_sunls *sys, const double *xf, double *x) {
  const sw_model *m = sys->m;
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) x[i] = xf[m->dof[i]];
}

/* D(x) v at the state y into sys->dvfull (the Hessian is evaluated there). */
static int damping_force(sw_sunls *sys, const double *y, double t) {
  const sw_model *m = sys->m;
  for (int i = 0; i < m->nv * m->dim; i++)
    sys->vfull[i] = m->dof[i] < 0 ? 0.0 : y[sys->n + m->dof[i]];
  return sw_damping_force(m, sys->d, sys->xfull, t, sys->vfull, sys->dvfull, NULL);
}

int sw_sunls_force(sw_sunls *sys, const double *y, double t, double *f) {
  const sw_model *m = sys->m;
  sw_data *d = sys->d;
  double t0 = sw_now(), u;
  set_free(sys, y, sys->xfull);
  int rc = sys->dvfull ? damping_force(sys, y, t) : SW_OK;
  if (!rc) rc = sw_eval_terms(m, d, sys->xfull, t, 1, 0, 0, &u);
  d->time_assemble += sw_now() - t0;
  if (rc) return rc;
  for (int i = 0; i < m->nv * m->dim; i++) {
    int c = m->dof[i];
    if (c < 0) continue;
    f[c] = -d->grad[i] - (sys->dvfull ? sys->dvfull[i] : 0.0);
    if (!isfinite(f[c])) {
      sw_errf(d->err, sizeof d->err, "the force is not finite (NaN or Inf) at t = %g s", t);
      return SW_RECOVER;
    }
  }
  return SW_OK;
}

/* ------------------------------------------------------------------- Hessian */

static int all_finite(const double *v, long n) {
  for (long k = 0; k < n; k++)
    if (!isfinite(v[k])) return 0;
  return 1;
}

/* hval and hlr <- the Hessian at sys->xlin, sys->tlin; projected or exact. */
static int eval_hessian(sw_sunls *sys, int project) {
  const sw_model *m = sys->m;
  sw_data *d = sys->d;
  double t0 = sw_now(), u;
  memset(sys->hval, 0, (size_t)sys->pat.nnz * sizeof(double)); /* the blocks straight in */
  int rc = sw_eval_terms_into(m, d, sys->xlin, sys->tlin, 0, project, sys->hval,
                              &sys->pat.slots, &u);
  if (rc == SW_OK) {
    sw_pattern_finish(&sys->pat, m, 0.0, 1.0, sys->hval);
    sw_pattern_fill_lowrank(&sys->pat, d, sys->hlr);
    if (!all_finite(sys->hval, sys->pat.nnz) ||
        !all_finite(sys->hlr, sys->pat.lrptr[sys->pat.nlr])) {
      sw_errf(d->err, sizeof d->err, "the Hessian is not finite (NaN or Inf) at t = %g s",
              sys->tlin);
      rc = SW_RECOVER;
    }
  }
  sys->h_projected = project;
  d->time_assemble += sw_now() - t0;
  return rc;
}

int sw_sunls_hessian(sw_sunls *sys, const double *xf, double t) {
  set_free(sys, xf, sys->xlin);
  sys->tlin = t;
  return eval_hessian(sys, sw_hessian_filter(sys->m->opt.hessian));
}

void sw_sunls_hmul(const sw_sunls *sys, const double *x, double *y) {
  const sw_pattern *p = &sys->pat;
  sw_pattern_symv(p, sys->hval, x, y);
  for (int v = 0; v < p->nlr; v++) { /* + v_r (v_r . x) */
    double s = 0.0;
    for (long q = p->lrptr[v]; q < p->lrptr[v + 1]; q++) s += sys->hlr[q] * x[p->lrrow[q]];
    for (long q = p->lrptr[v]; q < p->lrptr[v + 1]; q++) y[p->lrrow[q]] += sys->hlr[q] * s;
  }
}

void sw_sunls_dmul_add(const sw_sunls *sys, const double *r, double *y) {
  const sw_model *m = sys->m;
  if (!sw_damped(m)) return;
  if (m->damp_stiffness > 0.0) {
    sw_sunls_hmul(sys, r, sys->w2);
    for (int c = 0; c < sys->n; c++) y[c] += m->damp_stiffness * sys->w2[c];
  }
  for (int c = 0; c < sys->n; c++) y[c] += m->damp_mass * sys->mdiag[c] * r[c];
}

/* S = cm M + cd D + ch H on the pattern, D = alpha M + beta H, factorised. */
static int fill_factor(sw_sunls *sys) {
  sw_data *d = sys->d;
  const sw_model *m = sys->m;
  double t0 = sw_now();
  double *val = sw_chol_values(&sys->chol);
  double chh = sys->ch + sys->cd * m->damp_stiffness, cmm = sys->cm + sys->cd * m->damp_mass;
  for (long k = 0; k < sys->pat.nnz; k++) val[k] = chh * sys->hval[k];
  if (sys->pat.nlr) /* the low-rank part of H, scaled like hval */
    memcpy(sw_chol_lowrank(&sys->chol, chh), sys->hlr,
           (size_t)sys->pat.lrptr[sys->pat.nlr] * sizeof(double));
  for (int c = 0; c < sys->n; c++) val[sys->pat.diag[c]] += cmm * sys->mdiag[c];
  double t1 = sw_now();
  d->time_assemble += t1 - t0;
  int rc = sw_chol_factor(&sys->chol, d->err, sizeof d->err);
  d->time_factor += sw_now() - t1;
  d->nfactor++;
  d->factor_nnz = sw_chol_nnz(&sys->chol);
  d->factor_super = sw_chol_super(&sys->chol);
  d->factor_ordering = sw_chol_ordering(&sys->chol);
  return rc;
}

/* -------------------------------------------------- the custom SUNLinearSolver */

static SUNLinearSolver_Type ls_gettype(SUNLinearSolver LS) {
  (void)LS;
  return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID ls_getid(SUNLinearSolver LS) {
  (void)LS;
  return SUNLINEARSOLVER_CUSTOM;
}

/* Factorise S for the coefficients the method's callback just set; with hessian: auto or
 * progressive, an S that is not positive definite is rebuilt from the clamped Hessian at the
 * same point. */
static int ls_setup(SUNLinearSolver LS, SUNMatrix A) {
  (void)A;
  sw_sunls *sys = LS->content;
  sys->coef = sys->coef_next;
  int rc = fill_factor(sys);
  int mode = sys->m->opt.hessian;
  if (rc == SW_RECOVER && (mode == SW_HESSIAN_AUTO || mode == SW_HESSIAN_PROGRESSIVE) &&
      !sys->h_projected) {
    rc = eval_hessian(sys, SW_FILTER_CLAMP);
    if (rc == SW_OK) rc = fill_factor(sys);
  }
  return rc == SW_OK ? SUNLS_SUCCESS : rc > 0 ? SUNLS_LUFACT_FAIL : SUNLS_PACKAGE_FAIL_UNREC;
}

static int ls_solve(SUNLinearSolver LS, SUNMatrix A, N_Vector x, N_Vector b, sw_real tol) {
  (void)A, (void)tol; /* direct: tol is not used */
  sw_sunls *sys = LS->content;
  double t0 = sw_now();
  int rc = sys->reduce(sys, N_VGetArrayPointer(b), N_VGetArrayPointer(x));
  sys->d->time_solve += sw_now() - t0;
  return rc == SW_OK ? SUNLS_SUCCESS : SUNLS_PACKAGE_FAIL_UNREC;
}

/* The content is the sw_sunls, owned by the method: free only the shell. */
static int ls_free(SUNLinearSolver LS) {
  SUNLinSolFreeEmpty(LS);
  return SUNLS_SUCCESS;
}

static SUNMatrix_ID tok_getid(SUNMatrix A) {
  (void)A;
  return SUNMATRIX_CUSTOM;
}

static int tok_zero(SUNMatrix A) { /* IDA calls it before every jac: S is refilled anyway */
  (void)A;
  return SUNMAT_SUCCESS;
}

static void tok_destroy(SUNMatrix A) { SUNMatFreeEmpty(A); }

/* ------------------------------------------------------------------ lifetime */

int sw_sun_fail(char *err, size_t errsz, const char *solver, const char *what, char *flag_name,
                const char *msg, const char *cause) {
  char why[SW_ERRSZ];
  snprintf(why, sizeof why, "%s", cause ? cause : "");
  sw_errf(err, errsz, "%s %s: %s%s%s%s%s%s", solver, what, flag_name ? flag_name : "?",
          *msg ? " (" : "", msg, *msg ? ")" : "", *why ? ": " : "", why);
  free(flag_name);
  return SW_FATAL;
}

int sw_sunls_init(sw_sunls *sys, const sw_model *m, sw_data *d, sw_sunls_reduce_fn reduce,
                  char *err, size_t errsz) {
  memset(sys, 0, sizeof *sys);
  sys->m = m;
  sys->d = d;
  sys->n = m->ndof;
  sys->reduce = reduce;
  sys->cm = 1.0;
  int rc = sw_pattern_build(&sys->pat, m, err, errsz);
  if (rc) return rc;
  if ((rc = sw_chol_init(&sys->chol, &sys->pat,
                         SW_CHOL_MODE(m->opt.factorization, m->opt.ordering), err, errsz))) return rc;
  size_t n = (size_t)sys->n, nd = (size_t)m->nv * (size_t)m->dim;
  sys->mdiag = sw_calloc(n, sizeof(double));
  sys->hval = sw_calloc((size_t)sys->pat.nnz, sizeof(double));
  sys->hlr = sw_calloc((size_t)sys->pat.lrptr[sys->pat.nlr] + 1, sizeof(double));
  sys->xfull = sw_calloc(nd, sizeof(double));
  sys->xlin = sw_calloc(nd, sizeof(double));
  sys->w1 = sw_calloc(n, sizeof(double));
  sys->w2 = sw_calloc(n, sizeof(double));
  int damped = sw_damped(m);
  if (damped) {
    sys->vfull = sw_calloc(nd, sizeof(double));
    sys->dvfull = sw_calloc(nd, sizeof(double));
  }
  if ((damped && (!sys->vfull || !sys->dvfull)) || !sys->mdiag || !sys->hval || !sys->hlr ||
      !sys->xfull || !sys->xlin || !sys->w1 || !sys->w2)
    return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  memcpy(sys->xfull, d->x, nd * sizeof(double));
  memcpy(sys->xlin, d->x, nd * sizeof(double));
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < m->dim; a++)
      if (m->dof[i * m->dim + a] >= 0) sys->mdiag[m->dof[i * m->dim + a]] = m->mass[i];
  if (sw_sun_context(&sys->ctx))
    return sw_errf(err, errsz, "SUNDIALS: cannot create a context"), SW_FATAL;
  sys->LS = SUNLinSolNewEmpty(sys->ctx);
  sys->A = SUNMatNewEmpty(sys->ctx);
  if (!sys->LS || !sys->A)
    return sw_errf(err, errsz, "SUNDIALS: out of memory creating the linear solver"), SW_FATAL;
  sys->LS->content = sys;
  sys->LS->ops->gettype = ls_gettype;
  sys->LS->ops->getid = ls_getid;
  sys->LS->ops->setup = ls_setup;
  sys->LS->ops->solve = ls_solve;
  sys->LS->ops->free = ls_free;
  sys->A->content = sys;
  sys->A->ops->getid = tok_getid;
  sys->A->ops->zero = tok_zero;
  sys->A->ops->destroy = tok_destroy;
  return SW_OK;
}

void sw_sunls_free(sw_sunls *sys) {
  if (sys->LS) SUNLinSolFree(sys->LS);
  if (sys->A) SUNMatDestroy(sys->A);
  if (sys->ctx) SUNContext_Free(&sys->ctx);
  sw_chol_free(&sys->chol);
  sw_pattern_free(&sys->pat);
  sw_free(sys->mdiag);
  sw_free(sys->hval);
  sw_free(sys->hlr);
  sw_free(sys->xfull);
  sw_free(sys->vfull);
  sw_free(sys->dvfull);
  sw_free(sys->xlin);
  sw_free(sys->w1);
  sw_free(sys->w2);
  memset(sys, 0, sizeof *sys);
}

/* Automatic: CVODE's order selection, free to use orders 3-5, gets stuck at order 3 on
 * undamped cloth at loose tolerances (BDF3 is unstable on the imaginary axis for 0 < h w <
 * 1.94) and takes tiny steps there; at tight tolerances high orders pay.  IDA, at the same
 * orders, climbs to 5 (stable for h w < 0.71) and does not get stuck.  docs/integrators.md. */
int sw_sun_max_order(const sw_options *o, int cvode) {
  if (o->max_order > 0) return o->max_order;
  return cvode && o->rtol > SW_AUTO_ORDER_RTOL ? 2 : 5;
}

int sw_max_order(const sw_model *m) {
  return m ? sw_sun_max_order(&m->opt, !strcmp(m->opt.method, "cvode")) : 5;
}

static long delta(long now, long *last) {
  long dlt = now - *last;
  *last = now;
  return dlt;
}

void sw_sun_counts_add(sw_sun_counts *last, sw_data *d, long nst, long nni, long nsetup,
                       long netf) {
  d->nstep += delta(nst, &last->nst);
  d->last_newton = (int)delta(nni, &last->nni);
  d->nnewton += d->last_newton;
  d->nsetup += delta(nsetup, &last->nsetup);
  d->nerrfail += delta(netf, &last->netf);
}

int sw_sunls_changed(const sw_sunls *sys, const sw_data *d, double h, double tlast,
                     const double *ylast, double *ytmp) {
  if (fabs(d->t - tlast) > 1e-12 * (fabs(d->t) + fabs(h))) return 1;
  sw_sunls_gather(sys, d->x, d->v, ytmp);
  return memcmp(ytmp, ylast, 2 * (size_t)sys->n * sizeof(double)) != 0;
}

int sw_sun_tiny(long *tiny, double h, double out, const sw_options *o, char *err, size_t errsz) {
  *tiny = h < SW_SUN_TINY * out ? *tiny + 1 : 0;
  if (*tiny < SW_SUN_TINY_STEPS) return 0;
  sw_errf(err, errsz, "%ld internal steps in a row below %g x the output interval (the last "
          "%.3g s, the interval %g s): the problem looks unresolvable at this tolerance (rtol "
          "%g, atol %g); expected a larger rtol or atol, a fixed-step method, or a model whose "
          "fastest motion is slower (heavier or softer)", *tiny, SW_SUN_TINY, h, out, o->rtol,
          o->atol);
  return 1;
}
