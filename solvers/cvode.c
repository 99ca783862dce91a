/* cvode.c — SUNDIALS CVODE ("cvode"): variable-order, variable-step BDF with Newton on the first
 * order system y = [x; v] over the free DOFs,
 *   y' = [v; M^-1 f(x, v, t)],   f = -dU/dx - D(x) v  (D: Rayleigh damping, damping.c).
 * Tolerances: scalar rtol and atol (m->opt), the same atol for positions (m) and velocities
 * (m/s).  Largest order sw_sun_max_order (m->opt.max_order, or automatic: 2 at rtol > 1e-4,
 * else 5), largest step m->opt.max_step when > 0.  A new Newton
 * matrix (a linear-solver setup: one CHOLMOD factorisation) at least every m->opt.setup_every
 * steps (SUNDIALS' default is 20), and whenever CVODE asks for one: gamma moved by more than 30 %
 * since the last, or Newton failed to converge.
 *
 * The linear solve (sundials_ls.h).  CVODE's Newton matrix is I - gamma J with
 *   J = [[0, I], [-M^-1 H, -M^-1 D]]   (H = d2U/dx2 = -df/dx, the K of df/dx = -H).
 * For rhs [r1; r2]: row 1 gives dx = r1 + gamma dv; row 2 times M gives
 *   gamma H dx + (M + gamma D) dv = M r2, so  (M + gamma D + gamma^2 H) dv = M r2 - gamma H r1,
 * then dx = r1 + gamma dv (no division by gamma).  linsys re-evaluates H only when CVODE says
 * its Jacobian is stale (!jok) and reports it through *jcur; with jok it only re-scales S.
 *
 * The run loop asks for d->t + h with h the output interval: CVODE steps on its own past it and
 * the state is interpolated back to that time (cv_advance), so h does not limit its steps.  A caller who
 * changes d between steps (t, x or v) makes it restart there (CVodeReInit).  An interval CVODE
 * cannot finish after its own step cuts returns SW_FATAL (a smaller h would not help) with the
 * flag, SUNDIALS' message and the last reason our callbacks gave; steps stay >= sw_sun_hmin.
 *
 * Counters: nstep, nnewton (nonlinear iterations), nsetup (linear solver setups) and nerrfail
 * (error-test failures) are CVODE's own, added as increments per call; nstep_order counts the
 * steps by the BDF order they were taken at (CVodeGetLastOrder); nfactor counts CHOLMOD
 * factorisations (one per setup, two when hessian: auto falls back to the projected Hessian);
 * nforce is counted by sw_eval_terms, once per right-hand side (= CVodeGetNumRhsEvals: no
 * difference-quotient Jacobian is ever used), so it is not taken from CVODE as well. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>

#include "sundials_ls.h"
#include "util.h"

typedef struct cv_state {
  sw_sunls sys;
  void *mem;
  N_Vector y;
  double *ylast;  /* (2n) the state handed out by the last step */
  double *ytmp;   /* (2n) */
  double tlast;   /* s */
  int stale;      /* CVODE must be restarted from d before the next step */
  sw_sun_counts cnt; /* CVODE's counters at the last step */
} cv_state;

/* y' = [v; M^-1 f(x, t)] */
static int cv_rhs(sw_real t, N_Vector y, N_Vector ydot, void *user_data) {
  cv_state *s = user_data;
  const int n = s->sys.n;
  const double *yv = N_VGetArrayPointer(y);
  double *yd = N_VGetArrayPointer(ydot);
  int rc = sw_sunls_force(&s->sys, yv, t, yd + n);
  if (rc) return sw_sun_rc(rc);
  for (int c = 0; c < n; c++) {
    yd[c] = yv[n + c];
    yd[n + c] /= s->sys.mdiag[c]; /* f includes - D v */
  }
  return 0;
}

/* The Newton matrix for this gamma: H at y when CVODE's Jacobian is stale, S's coefficients. */
static int cv_linsys(sw_real t, N_Vector y, N_Vector fy, SUNMatrix A, sw_bool jok, sw_bool *jcur,
                     sw_real gamma, void *user_data, N_Vector tmp1, N_Vector tmp2,
                     N_Vector tmp3) {
  (void)fy, (void)A, (void)tmp1, (void)tmp2, (void)tmp3;
  cv_state *s = user_data;
  *jcur = SUNFALSE;
  if (!jok) {
    int rc = sw_sunls_hessian(&s->sys, N_VGetArrayPointer(y), t);
    if (rc) return sw_sun_rc(rc);
    *jcur = SUNTRUE;
  }
  s->sys.cm = 1.0;
  s->sys.cd = gamma;
  s->sys.ch = gamma * gamma;
  s->sys.coef_next = gamma;
  return 0;
}

/* (M + gamma D + gamma^2 H) dv = M r2 - gamma H r1,  dx = r1 + gamma dv. */
int sw_cvode_reduce(sw_sunls *sys, const double *b, double *x) {
  const int n = sys->n;
  const double g = sys->coef, *r1 = b, *r2 = b + n;
  sw_sunls_hmul(sys, r1, sys->w1);
  for (int c = 0; c < n; c++) sys->w2[c] = sys->mdiag[c] * r2[c] - g * sys->w1[c];
  int rc = sw_chol_solve(&sys->chol, sys->w2, sys->w2, sys->d->err, sizeof sys->d->err);
  if (rc) return rc;
  for (int c = 0; c < n; c++) {
    x[c] = r1[c] + g * sys->w2[c];
    x[n + c] = sys->w2[c];
  }
  return SW_OK;
}

static void cv_free(void *p) {
  cv_state *s = p;
  if (!s) return;
  if (s->y) N_VDestroy(s->y);
  if (s->mem) CVodeFree(&s->mem);
  sw_sunls_free(&s->sys);
  sw_free(s->ylast);
  sw_free(s->ytmp);
  sw_free(s);
}

/* d->err <- the failed call, its flag, SUNDIALS' message and our callbacks' last reason. */
static int cv_fail(cv_state *s, sw_data *d, const char *what, int flag, const char *cause) {
  return sw_sun_fail(d->err, sizeof d->err, "CVODE", what, CVodeGetReturnFlagName(flag),
                     s->sys.msg, cause);
}

static int cv_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  cv_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  *state = s;
  s->sys.n = m->ndof;
  if (m->ndof == 0) return SW_OK; /* nothing moves: step only advances t */
  const int n = m->ndof;
  int rc = sw_sunls_init(&s->sys, m, d, sw_cvode_reduce, err, errsz);
  if (!rc) {
    s->ylast = sw_calloc(2 * (size_t)n, sizeof(double));
    s->ytmp = sw_calloc(2 * (size_t)n, sizeof(double));
    s->y = N_VNew_Serial(2 * (sunindextype)n, s->sys.ctx);
    s->mem = CVodeCreate(CV_BDF, s->sys.ctx);
    if (!s->ylast || !s->ytmp || !s->y || !s->mem)
      rc = (sw_errf(err, errsz, "out of memory creating CVODE"), SW_FATAL);
  }
  if (rc) {
    cv_free(s);
    *state = NULL;
    return rc;
  }
  sw_sunls_gather(&s->sys, d->x, d->v, N_VGetArrayPointer(s->y));
  const sw_options *o = &m->opt;
  const char *what = "";
  int flag;
  (void)SW_SUN_ROUTE_ERRORS(CVodeSetErrHandlerFn, s->mem, s->sys.ctx, s->sys.msg);
  if ((flag = CVodeInit(s->mem, cv_rhs, d->t, s->y))) what = "CVodeInit";
  else if ((flag = CVodeSetUserData(s->mem, s))) what = "CVodeSetUserData";
  else if ((flag = CVodeSStolerances(s->mem, o->rtol, o->atol))) what = "CVodeSStolerances";
  else if ((flag = CVodeSetMaxOrd(s->mem, sw_sun_max_order(o, 1)))) what = "CVodeSetMaxOrd";
  else if (o->max_step > 0 && (flag = CVodeSetMaxStep(s->mem, o->max_step)))
    what = "CVodeSetMaxStep";
  else if ((flag = CVodeSetLinearSolver(s->mem, s->sys.LS, s->sys.A)))
    what = "CVodeSetLinearSolver";
  else if ((flag = CVodeSetLinSysFn(s->mem, cv_linsys))) what = "CVodeSetLinSysFn";
  else if ((flag = CVodeSetLSetupFrequency(s->mem, o->setup_every)))
    what = "CVodeSetLSetupFrequency";
  if (flag) {
    sw_sun_fail(err, errsz, "CVODE", what, CVodeGetReturnFlagName(flag), s->sys.msg, "");
    cv_free(s);
    *state = NULL;
    return SW_FATAL;
  }
  memcpy(s->ylast, N_VGetArrayPointer(s->y), 2 * (size_t)n * sizeof(double));
  s->tlast = d->t;
  return SW_OK;
}

/* CVODE's counters since the last step, into d. */
static void cv_counters(cv_state *s, sw_data *d) {
  long nst = 0, nni = 0, nsetup = 0, netf = 0;
  CVodeGetNumSteps(s->mem, &nst);
  CVodeGetNumNonlinSolvIters(s->mem, &nni);
  CVodeGetNumLinSolvSetups(s->mem, &nsetup);
  CVodeGetNumErrTestFails(s->mem, &netf);
  sw_sun_counts_add(&s->cnt, d, nst, nni, nsetup, netf);
}

/* CVODE's steps until its internal time passes tout, one at a time (CV_ONE_STEP) so that the
 * order of each is counted, then y at tout interpolated (CVodeGetDky): the same steps and the
 * same numbers as CV_NORMAL, which does exactly this inside.  At most SW_SUN_MXSTEP steps. */
static int cv_advance(cv_state *s, sw_data *d, double tout, sw_real *tret) {
  sw_real tn = 0.0;
  CVodeGetCurrentTime(s->mem, &tn);
  const double out = tout - tn; /* s: the output interval */
  long tiny = 0;
  for (long k = 0; tn < tout; k++) {
    if (k == SW_SUN_MXSTEP) return CV_TOO_MUCH_WORK;
    int flag = CVode(s->mem, tout, s->y, tret, CV_ONE_STEP);
    if (flag < 0) return flag;
    int q = 0;
    CVodeGetLastOrder(s->mem, &q);
    if (q >= 1 && q <= 5) d->nstep_order[q - 1]++;
    CVodeGetCurrentTime(s->mem, &tn);
    sw_real h = 0.0;
    CVodeGetLastStep(s->mem, &h);
    if (sw_sun_tiny(&tiny, h, out, &s->sys.m->opt, d->err, sizeof d->err)) {
      *tret = tn;
      return CV_TOO_MUCH_WORK;
    }
  }
  *tret = tout;
  return CVodeGetDky(s->mem, tout, 0, s->y);
}

/* Any change between steps: restart from d (pinned positions too) at the next step. */
static void cv_reset(void *p, const sw_model *m, sw_data *d, int what) {
  (void)m, (void)what;
  cv_state *s = p;
  if (s->sys.n == 0) return;
  sw_sunls_pins(&s->sys, d->x);
  s->stale = 1;
}

static int cv_step(void *p, const sw_model *m, sw_data *d, double h) {
  cv_state *s = p;
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
    s->sys.msg[0] = '\0';
    int flag = CVodeReInit(s->mem, d->t, s->y);
    if (flag) return cv_fail(s, d, "CVodeReInit", flag, "");
    s->cnt = (sw_sun_counts){0};
    s->stale = 0;
  }
  const double tout = d->t + h;
  sw_real tret = d->t;
  s->sys.msg[0] = d->err[0] = '\0'; /* d->err: what our callbacks last failed on, if anything */
  int flag = CVodeSetMinStep(s->mem, sw_sun_hmin(tout));
  if (flag) return cv_fail(s, d, "CVodeSetMinStep", flag, "");
  flag = cv_advance(s, d, tout, &tret);
  cv_counters(s, d);
  if (flag < 0) {
    char what[64];
    snprintf(what, sizeof what, "failed at t = %.9g s", (double)tret);
    s->stale = 1; /* CVODE's own state went on; d keeps the last good one */
    return cv_fail(s, d, what, flag, d->err);
  }
  sw_sunls_scatter(&s->sys, yv, d->x, d->v);
  d->t = tout;
  sw_real hlast = 0.0;
  CVodeGetLastStep(s->mem, &hlast);
  d->last_dt = hlast;
  memcpy(s->ylast, yv, 2 * (size_t)s->sys.n * sizeof(double));
  s->tlast = d->t;
  return SW_OK;
}

const sw_integrator_ops sw_cvode_ops = {
    .name = "cvode",
    .adaptive = 1,
    .summary = "SUNDIALS CVODE: adaptive BDF (orders 1-5) to rtol/atol, Newton with CHOLMOD",
    .init = cv_init,
    .step = cv_step,
    .free = cv_free,
    .reset = cv_reset,
};
