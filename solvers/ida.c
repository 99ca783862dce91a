/* ida.c — SUNDIALS IDA ("ida"): variable-order, variable-step BDF on the implicit form
 *   F(t, y, y') = [x' - v; M v' - f(x, t)] = 0,   y = [x; v] on the free DOFs, f = -dU/dx
 * (no damping yet: D = 0; with it the second row is M v' - f + D v).  The initial y' is
 * consistent by construction, y'(0) = [v0; M^-1 f(x0, t0)], so IDACalcIC is not needed.
 * Tolerances, largest step and counters as for CVODE (cvode.c), the largest order
 * sw_sun_max_order (m->opt.max_order, or automatic: 5); nforce (counted by
 * sw_eval_terms) = IDAGetNumResEvals + 1 per (re)start, the one for y'(0).
 *
 * The linear solve (sundials_ls.h).  IDA's matrix dF/dy + cj dF/dy' is
 *   [[cj I, -I], [H, cj M + D]]     (H = d2U/dx2 = d(-f)/dx).
 * For rhs [r1; r2]: row 1 gives dv = cj dx - r1; row 2 then gives
 *   (cj^2 M + cj D + H) dx = r2 + (cj M + D) r1,
 * solved by CHOLMOD, then dv = cj dx - r1.  cj is frozen at the last setup (jac call): IDA scales
 * the solution by 2 / (1 + cj / cj_setup) itself (its solution scaling is left on).  IDA asks for
 * a new matrix only when cj has moved too far or Newton struggles, and H is re-evaluated then. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <nvector/nvector_serial.h>

#include "sundials_ls.h"
#include "util.h"

typedef struct ida_state {
  sw_sunls sys;
  void *mem;
  N_Vector y, yp;
  double *ylast;  /* (2n) the state handed out by the last step */
  double *ytmp;   /* (2n) */
  double tlast;   /* s */
  int stale;      /* IDA must be restarted from d before the next step */
  sw_sun_counts cnt; /* IDA's counters at the last step */
} ida_state;

/* F = [x' - v; M v' - f(x, t)] */
static int ida_res(sw_real t, N_Vector y, N_Vector yp, N_Vector res, void *user_data) {
  ida_state *s = user_data;
  const int n = s->sys.n;
  const double *yv = N_VGetArrayPointer(y), *ypv = N_VGetArrayPointer(yp);
  double *r = N_VGetArrayPointer(res);
  int rc = sw_sunls_force(&s->sys, yv, t, r + n);
  if (rc) return sw_sun_rc(rc);
  for (int c = 0; c < n; c++) {
    r[c] = ypv[c] - yv[n + c];
    r[n + c] = s->sys.mdiag[c] * ypv[n + c] - r[n + c]; /* f includes - D v */
  }
  return 0;
}

/* The matrix for this cj: H at y (IDA calls this only when it wants a new matrix). */
static int ida_jac(sw_real t, sw_real cj, N_Vector y, N_Vector yp, N_Vector r, SUNMatrix J,
                   void *user_data, N_Vector tmp1, N_Vector tmp2, N_Vector tmp3) {
  (void)yp, (void)r, (void)J, (void)tmp1, (void)tmp2, (void)tmp3;
  ida_state *s = user_data;
  int rc = sw_sunls_hessian(&s->sys, N_VGetArrayPointer(y), t);
  if (rc) return sw_sun_rc(rc);
  s->sys.cm = cj * cj;
  s->sys.cd = cj;
  s->sys.ch = 1.0;
  s->sys.coef_next = cj;
  return 0;
}

/* (cj^2 M + cj D + H) dx = r2 + (cj M + D) r1,  dv = cj dx - r1. */
int sw_ida_reduce(sw_sunls *sys, const double *b, double *x) {
  const int n = sys->n;
  const double cj = sys->coef, *r1 = b, *r2 = b + n;
  for (int c = 0; c < n; c++) sys->w1[c] = r2[c] + cj * sys->mdiag[c] * r1[c];
  sw_sunls_dmul_add(sys, r1, sys->w1);
  int rc = sw_chol_solve(&sys->chol, sys->w1, sys->w1, sys->d->err, sizeof sys->d->err);
  if (rc) return rc;
  for (int c = 0; c < n; c++) {
    double r1c = r1[c]; /* x may alias b */
    x[n + c] = cj * sys->w1[c] - r1c;
    x[c] = sys->w1[c];
  }
  return SW_OK;
}

/* y' = [v; M^-1 f(x, t)] for y = [x; v]: the consistent derivative. */
static int ida_consistent_yp(ida_state *s, double t) {
  const int n = s->sys.n;
  const double *yv = N_VGetArrayPointer(s->y);
  double *ypv = N_VGetArrayPointer(s->yp);
  int rc = sw_sunls_force(&s->sys, yv, t, ypv + n);
  if (rc) return rc;
  for (int c = 0; c < n; c++) {
    ypv[c] = yv[n + c];
    ypv[n + c] /= s->sys.mdiag[c];
  }
  return SW_OK;
}

static void ida_free(void *p) {
  ida_state *s = p;
  if (!s) return;
  if (s->y) N_VDestroy(s->y);
  if (s->yp) N_VDestroy(s->yp);
  if (s->mem) IDAFree(&s->mem);
  sw_sunls_free(&s->sys);
  sw_free(s->ylast);
  sw_free(s->ytmp);
  sw_free(s);
}

/* d->err <- the failed call, its flag, SUNDIALS' message and our callbacks' last reason. */
static int ida_fail(ida_state *s, sw_data *d, const char *what, int flag, const char *cause) {
  return sw_sun_fail(d->err, sizeof d->err, "IDA", what, IDAGetReturnFlagName(flag), s->sys.msg,
                     cause);
}

static int ida_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  ida_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  *state = s;
  s->sys.n = m->ndof;
  if (m->ndof == 0) return SW_OK; /* nothing moves: step only advances t */
  const int n = m->ndof;
  int rc = sw_sunls_init(&s->sys, m, d, sw_ida_reduce, err, errsz);
  if (!rc) {
    s->ylast = sw_calloc(2 * (size_t)n, sizeof(double));
    s->ytmp = sw_calloc(2 * (size_t)n, sizeof(double));
    s->y = N_VNew_Serial(2 * (sunindextype)n, s->sys.ctx);
    s->yp = N_VNew_Serial(2 * (sunindextype)n, s->sys.ctx);
    s->mem = IDACreate(s->sys.ctx);
    if (!s->ylast || !s->ytmp || !s->y || !s->yp || !s->mem)
      rc = (sw_errf(err, errsz, "out of memory creating IDA"), SW_FATAL);
  }
  if (!rc) {
    sw_sunls_gather(&s->sys, d->x, d->v, N_VGetArrayPointer(s->y));
    if ((rc = ida_consistent_yp(s, d->t)))
      sw_errf(err, errsz, "IDA: initial state: %s", d->err);
  }
  if (rc) {
    ida_free(s);
    *state = NULL;
    return rc < 0 ? rc : SW_FATAL;
  }
  const sw_options *o = &m->opt;
  const char *what = "";
  int flag;
  (void)SW_SUN_ROUTE_ERRORS(IDASetErrHandlerFn, s->mem, s->sys.ctx, s->sys.msg);
  if ((flag = IDAInit(s->mem, ida_res, d->t, s->y, s->yp))) what = "IDAInit";
  else if ((flag = IDASetUserData(s->mem, s))) what = "IDASetUserData";
  else if ((flag = IDASStolerances(s->mem, o->rtol, o->atol))) what = "IDASStolerances";
  else if ((flag = IDASetMaxOrd(s->mem, sw_sun_max_order(o, 0)))) what = "IDASetMaxOrd";
  else if (o->max_step > 0 && (flag = IDASetMaxStep(s->mem, o->max_step))) what = "IDASetMaxStep";
  else if ((flag = IDASetLinearSolver(s->mem, s->sys.LS, s->sys.A))) what = "IDASetLinearSolver";
  else if ((flag = IDASetJacFn(s->mem, ida_jac))) what = "IDASetJacFn";
  if (flag) {
    sw_sun_fail(err, errsz, "IDA", what, IDAGetReturnFlagName(flag), s->sys.msg, "");
    ida_free(s);
    *state = NULL;
    return SW_FATAL;
  }
  memcpy(s->ylast, N_VGetArrayPointer(s->y), 2 * (size_t)n * sizeof(double));
  s->tlast = d->t;
  return SW_OK;
}

/* IDA's counters since the last step, into d. */
static void ida_counters(ida_state *s, sw_data *d) {
  long nst = 0, nni = 0, nsetup = 0, netf = 0;
  IDAGetNumSteps(s->mem, &nst);
  IDAGetNumNonlinSolvIters(s->mem, &nni);
  IDAGetNumLinSolvSetups(s->mem, &nsetup);
  IDAGetNumErrTestFails(s->mem, &netf);
  sw_sun_counts_add(&s->cnt, d, nst, nni, nsetup, netf);
}

/* IDA's steps until its internal time passes tout, one at a time (IDA_ONE_STEP) so that the
 * order of each is counted, then y and y' at tout interpolated (IDAGetDky): the same steps as
 * IDA_NORMAL, which does this inside with its own copy of the interpolation (the outputs agree
 * to round-off, ~1e-24 m on the default scene).  At most SW_SUN_MXSTEP steps. */
static int ida_advance(ida_state *s, sw_data *d, double tout, sw_real *tret) {
  sw_real tn = 0.0;
  IDAGetCurrentTime(s->mem, &tn);
  const double out = tout - tn; /* s: the output interval */
  long tiny = 0;
  for (long k = 0; tn < tout; k++) {
    if (k == SW_SUN_MXSTEP) return IDA_TOO_MUCH_WORK;
    int flag = IDASolve(s->mem, tout, tret, s->y, s->yp, IDA_ONE_STEP);
    if (flag < 0) return flag;
    int q = 0;
    IDAGetLastOrder(s->mem, &q);
    if (q >= 1 && q <= 5) d->nstep_order[q - 1]++;
    IDAGetCurrentTime(s->mem, &tn);
    sw_real h = 0.0;
    IDAGetLastStep(s->mem, &h);
    if (sw_sun_tiny(&tiny, h, out, &s->sys.m->opt, d->err, sizeof d->err)) {
      *tret = tn;
      return IDA_TOO_MUCH_WORK;
    }
  }
  *tret = tout;
  int flag = IDAGetDky(s->mem, tout, 0, s->y);
  return flag ? flag : IDAGetDky(s->mem, tout, 1, s->yp);
}

/* Any change between steps: restart from d (pinned positions too) at the next step. */
static void ida_reset(void *p, const sw_model *m, sw_data *d, int what) {
  (void)m, (void)what;
  ida_state *s = p;
  if (s->sys.n == 0) return;
  sw_sunls_pins(&s->sys, d->x);
  s->stale = 1;
}

static int ida_step(void *p, const sw_model *m, sw_data *d, double h) {
  ida_state *s = p;
  if (s->sys.n == 0) {
    d->t += h;
    d->last_dt = h;
    d->nstep++;
    return SW_OK;
  }
  (void)m;
  s->sys.d = d;
  double *yv = N_VGetArrayPointer(s->y);
  if (s->stale || sw_sunls_changed(&s->sys, d, h, s->tlast, s->ylast, s->ytmp)) {
    sw_sunls_gather(&s->sys, d->x, d->v, yv);
    int rc = ida_consistent_yp(s, d->t);
    if (rc) return rc;
    s->sys.msg[0] = '\0';
    int flag = IDAReInit(s->mem, d->t, s->y, s->yp);
    if (flag) return ida_fail(s, d, "IDAReInit", flag, "");
    s->cnt = (sw_sun_counts){0};
    s->stale = 0;
  }
  const double tout = d->t + h;
  sw_real tret = d->t;
  s->sys.msg[0] = d->err[0] = '\0'; /* d->err: what our callbacks last failed on, if anything */
  int flag = IDASetMinStep(s->mem, sw_sun_hmin(tout));
  if (flag) return ida_fail(s, d, "IDASetMinStep", flag, "");
  flag = ida_advance(s, d, tout, &tret);
  ida_counters(s, d);
  if (flag < 0) {
    char what[64];
    snprintf(what, sizeof what, "failed at t = %.9g s", (double)tret);
    s->stale = 1; /* IDA's own state went on; d keeps the last good one */
    return ida_fail(s, d, what, flag, d->err);
  }
  sw_sunls_scatter(&s->sys, yv, d->x, d->v);
  d->t = tout;
  sw_real hlast = 0.0;
  IDAGetLastStep(s->mem, &hlast);
  d->last_dt = hlast;
  memcpy(s->ylast, yv, 2 * (size_t)s->sys.n * sizeof(double));
  s->tlast = d->t;
  return SW_OK;
}

const sw_integrator_ops sw_ida_ops = {
    .name = "ida",
    .adaptive = 1,
    .summary = "SUNDIALS IDA: adaptive BDF on the implicit form [x' - v; M v' - f], CHOLMOD",
    .init = ida_init,
    .step = ida_step,
    .free = ida_free,
    .reset = ida_reset,
};
