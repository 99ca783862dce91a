/* test_sundials.c — CVODE and IDA (solvers/cvode.c, ida.c) through their integrator ops:
 *   - the Schur-complement solves satisfy the full 2n x 2n Newton systems (dense check);
 *   - free fall under gravity alone matches x0 + v0 t + g t^2 / 2;
 *   - on a small swinging cloth the error against a tight reference falls with rtol, and CVODE
 *     and IDA agree with each other;
 *   - counters are consistent; a caller who changes the state makes the integrator restart;
 *   - max_order bounds the BDF order of every step (steps counted per order); setup_every
 *     bounds the steps between CVODE's linear-solver setups;
 *   - a force that turns NaN fails the step fast, naming SUNDIALS' flag and the cause;
 *   - bad options fail at init with SUNDIALS' flag name. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <nvector/nvector_serial.h>

#include "harness.h"
#include "solver.h"
#include "sundials_ls.h"
#include "terms.h"
#include "util.h"

static const double G[3] = {0.0, 0.0, -9.81};

/* 4 x 3 vertices, 0.3 x 0.2 m, top row pinned, gravity out of plane: the cloth swings down and
 * stretches (nonlinear), 24 free DOFs. */
static sw_model *swing_model(void) {
  return th_grid_model(3, 4, 3, 0.3, 0.2, 0.1, 50.0, 5.0, G, 1);
}

typedef struct run_out {
  double *x, *v;
  long nstep, nnewton, nfactor, nforce, nsetup, nerrfail, nassemble;
  long nstep_order[5];
  double last_dt;
} run_out;

/* From the model's initial state to T in nout output intervals of ops. */
static run_out run(const sw_integrator_ops *ops, sw_model *m, double rtol, double atol, double T,
                   int nout) {
  m->opt.rtol = rtol;
  m->opt.atol = atol;
  void *s;
  sw_data *d = th_start(ops, m, &s);
  assert_non_null(d);
  int rc;
  for (int k = 1; k <= nout; k++) {
    rc = ops->step(s, m, d, T * k / nout - d->t);
    if (rc) print_error("%s: interval %d: %s\n", ops->name, k, d->err);
    assert_int_equal(rc, 0);
    d->t = T * k / nout; /* as the run loop does */
  }
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  run_out o = {.x = malloc(nd * sizeof(double)), .v = malloc(nd * sizeof(double)),
               .nstep = d->nstep, .nnewton = d->nnewton, .nfactor = d->nfactor,
               .nforce = d->nforce, .nsetup = d->nsetup, .nerrfail = d->nerrfail,
               .nassemble = d->nassemble, .last_dt = d->last_dt};
  memcpy(o.nstep_order, d->nstep_order, sizeof o.nstep_order);
  memcpy(o.x, d->x, nd * sizeof(double));
  memcpy(o.v, d->v, nd * sizeof(double));
  ops->free(s);
  sw_data_free(d);
  return o;
}

static void run_free(run_out *o) {
  free(o->x);
  free(o->v);
}

/* ------------------------------------------------------------- reductions */

/* Solve each method's 2n system through the custom SUNLinearSolver and check the residual of
 * the unreduced system with dense H:  CVODE  [dx - g dv;  dv + g M^-1 H dx] = [r1; r2],
 * IDA  [cj dx - dv;  H dx + cj M dv] = [r1; r2]. */
static void reduction_solves_full_system(void **st) {
  (void)st;
  sw_model *m = swing_model();
  m->opt.hessian = SW_HESSIAN_PROJECTED;
  sw_data *d = sw_data_new(m);
  unsigned long rs = 11;
  const int nd = m->nv * m->dim;
  for (int i = 0; i < nd; i++)
    if (m->dof[i] >= 0) d->x[i] += 0.02 * th_rand(&rs);
  char err[SW_ERRSZ];
  for (int method = 0; method < 2; method++) {
    sw_sunls sys;
    int rc = sw_sunls_init(&sys, m, d, method ? sw_ida_reduce : sw_cvode_reduce, err, sizeof err);
    if (rc) print_error("%s\n", err);
    assert_int_equal(rc, 0);
    const int n = sys.n;
    double *y2 = calloc(2 * (size_t)n, sizeof(double));
    sw_sunls_gather(&sys, d->x, d->v, y2);
    assert_int_equal(sw_sunls_hessian(&sys, y2, 0.0), 0);
    /* dense H on all DOFs, summed over the terms: their blocks at the same state and filter
     * (sw_sunls_hessian adds them straight into its system) */
    double u;
    assert_int_equal(
        sw_eval_terms(m, d, sys.xlin, 0.0, 0, 1, sw_hessian_filter(m->opt.hessian), &u), 0);
    double *H = calloc((size_t)nd * nd, sizeof(double));
    double *Hk = calloc((size_t)nd * nd, sizeof(double));
    for (int k = 0; k < m->nterm; k++) {
      th_dense_hessian(m, k, d->hess + d->hoff[k], Hk);
      for (long q = 0; q < (long)nd * nd; q++) H[q] += Hk[q];
    }
    double coef = method ? 150.0 : 0.004; /* cj (1/s) or gamma (s) */
    sys.cm = method ? coef * coef : 1.0;
    sys.ch = method ? 1.0 : coef * coef;
    sys.cd = coef;
    sys.coef_next = coef;
    assert_int_equal(SUNLinSolSetup(sys.LS, sys.A), 0);
    N_Vector b = N_VNew_Serial(2 * n, sys.ctx), x = N_VNew_Serial(2 * n, sys.ctx);
    double *bv = N_VGetArrayPointer(b), *xv = N_VGetArrayPointer(x);
    for (int c = 0; c < 2 * n; c++) bv[c] = th_rand(&rs);
    assert_int_equal(SUNLinSolSolve(sys.LS, sys.A, x, b, 0.0), 0);
    /* H dx with the dense matrix on the free DOFs */
    double *Hdx = calloc((size_t)n, sizeof(double)), *Hdx2 = calloc((size_t)n, sizeof(double));
    for (int i = 0; i < nd; i++)
      for (int j = 0; j < nd; j++)
        if (m->dof[i] >= 0 && m->dof[j] >= 0) Hdx[m->dof[i]] += H[(long)i * nd + j] * xv[m->dof[j]];
    sw_sunls_hmul(&sys, xv, Hdx2); /* and the symmetric CSC product agrees */
    double res = 0.0, scale = 0.0;
    for (int c = 0; c < n; c++) {
      assert_float_equal(Hdx2[c], Hdx[c], 1e-10 * (fabs(Hdx[c]) + 1.0));
      double dx = xv[c], dv = xv[n + c], mc = sys.mdiag[c], e1, e2;
      if (method == 0) {
        e1 = dx - coef * dv - bv[c];
        e2 = dv + coef * Hdx[c] / mc - bv[n + c];
      } else {
        e1 = coef * dx - dv - bv[c];
        e2 = (Hdx[c] + coef * mc * dv - bv[n + c]) / (coef * mc); /* per unit of v */
      }
      res = fmax(res, fmax(fabs(e1), fabs(e2)));
      scale = fmax(scale, fmax(fabs(bv[c]), fabs(bv[n + c])));
    }
    print_message("%s reduction: max residual %.3g (rhs %.3g)\n", method ? "IDA" : "CVODE", res,
                  scale);
    assert_true(res < 1e-10 * scale);
    /* the solve may be asked in place, b == x */
    N_Vector c = N_VClone(b);
    memcpy(N_VGetArrayPointer(c), bv, 2 * (size_t)n * sizeof(double));
    assert_int_equal(SUNLinSolSolve(sys.LS, sys.A, c, c, 0.0), 0);
    assert_true(th_max_diff(N_VGetArrayPointer(c), xv, 2 * n) == 0.0);
    N_VDestroy(c);
    free(Hdx);
    free(Hdx2);
    free(H);
    free(Hk);
    free(y2);
    N_VDestroy(b);
    N_VDestroy(x);
    sw_sunls_free(&sys);
  }
  sw_data_free(d);
  sw_model_free(m);
}

/* ------------------------------------------------------------- free fall */

/* No membrane, gravity only, nothing pinned, a non-zero initial velocity: every vertex follows
 * x0 + v0 t + g t^2 / 2.  BDF of order >= 2 is exact on it; the first order-1 steps commit
 * errors the tolerance bounds, so at rtol 1e-10 the state is right to 1e-8. */
static void free_fall(void **st) {
  (void)st;
  const sw_integrator_ops *ops[2] = {&sw_cvode_ops, &sw_ida_ops};
  for (int k = 0; k < 2; k++) {
    sw_model *m = th_grid_model(3, 3, 3, 0.2, 0.2, 0.1, 0.0, 0.0, G, 0);
    assert_non_null(m);
    for (int i = 0; i < m->nv; i++)
      for (int a = 0; a < 3; a++) m->v0[i * 3 + a] = 0.3 * (a + 1) - 0.1 * i;
    const double T = 0.5;
    run_out o = run(ops[k], m, 1e-10, 1e-12, T, 5);
    double ex = 0.0, ev = 0.0;
    for (int i = 0; i < m->nv * 3; i++) {
      int a = i % 3;
      ex = fmax(ex, fabs(o.x[i] - (m->x0[i] + m->v0[i] * T + 0.5 * G[a] * T * T)));
      ev = fmax(ev, fabs(o.v[i] - (m->v0[i] + G[a] * T)));
    }
    print_message("%s free fall: position error %.3g m, velocity error %.3g m/s, %ld steps\n",
                  ops[k]->name, ex, ev, o.nstep);
    assert_true(ex < 1e-8);
    assert_true(ev < 1e-8);
    run_free(&o);
    sw_model_free(m);
  }
}

/* ------------------------------------------------- tolerance convergence */

/* Errors at t = 0.2 s against CVODE at rtol 1e-10, atol 1e-12 (m, m/s), position max-norm. */
static void error_falls_with_rtol(void **st) {
  (void)st;
  sw_model *m = swing_model();
  assert_non_null(m);
  const int nd = m->nv * m->dim;
  const double T = 0.2;
  run_out ref = run(&sw_cvode_ops, m, 1e-10, 1e-12, T, 10);
  double drop = m->x0[2] - ref.x[2]; /* the free corner fell: a real, nonlinear motion */
  print_message("reference: %ld steps, corner drop %.4g m\n", ref.nstep, drop);
  assert_true(drop > 0.05);
  const double rtol[3] = {1e-4, 1e-6, 1e-8};
  const sw_integrator_ops *ops[2] = {&sw_cvode_ops, &sw_ida_ops};
  double *x8[2];
  for (int k = 0; k < 2; k++) {
    double err[3];
    for (int j = 0; j < 3; j++) {
      run_out o = run(ops[k], m, rtol[j], rtol[j] * 1e-2, T, 10);
      err[j] = th_max_diff(o.x, ref.x, nd);
      print_message("%-5s rtol %.0e: error %.3e m  steps %5ld  newton %5ld  setups %4ld  "
                    "factorizations %4ld  forces %5ld  error-test failures %ld\n",
                    ops[k]->name, rtol[j], err[j], o.nstep, o.nnewton, o.nsetup, o.nfactor,
                    o.nforce, o.nerrfail);
      /* counters: positive; one factorisation per setup (two at most with hessian: auto's
       * fall-back); one force evaluation per Newton iteration plus a few for the start (the
       * initial step estimate, IDA's y'(0)): nothing counted twice */
      assert_true(o.nstep > 0 && o.nnewton >= o.nstep && o.nsetup > 0 && o.nforce > 0);
      assert_true(o.nfactor >= o.nsetup && o.nfactor <= 2 * o.nsetup);
      assert_true(o.nforce >= o.nnewton && o.nforce <= o.nnewton + 10);
      assert_true(o.nsetup < o.nnewton); /* the matrix is reused across iterations and steps */
      assert_true(o.last_dt > 0.0);
      if (j == 2) x8[k] = o.x, free(o.v);
      else run_free(&o);
    }
    assert_true(err[0] > err[1] && err[1] > err[2]);
    assert_true(err[2] < 1e-1 * err[0]);
    assert_true(err[2] < 1e-5); /* m, on a 0.3 m cloth that fell ~0.1 m */
  }
  /* CVODE and IDA at rtol 1e-8 (atol 1e-10) each sit within ~1e-7 m of the reference here; their
   * difference is bounded by the sum: require 1e-6 relative to the motion (drop). */
  double dci = th_max_diff(x8[0], x8[1], nd);
  print_message("CVODE vs IDA at rtol 1e-8: %.3e m (%.3e of the drop)\n", dci, dci / drop);
  assert_true(dci < 1e-6 * drop);
  free(x8[0]);
  free(x8[1]);
  run_free(&ref);
  sw_model_free(m);
}

/* ------------------------------------------------------------- max_order */

/* Every step is counted at its order, none above max_order; order 1 takes the most steps, and
 * with 5 allowed the smooth swing uses orders above 2. */
static void max_order_is_honoured(void **st) {
  (void)st;
  const sw_integrator_ops *ops[2] = {&sw_cvode_ops, &sw_ida_ops};
  const int order[3] = {1, 2, 5};
  for (int k = 0; k < 2; k++) {
    long nstep[3];
    for (int j = 0; j < 3; j++) {
      sw_model *m = swing_model();
      m->opt.max_order = order[j];
      run_out o = run(ops[k], m, 1e-6, 1e-8, 0.2, 4);
      long sum = 0, high = 0;
      for (int q = 1; q <= 5; q++) {
        sum += o.nstep_order[q - 1];
        if (q > order[j]) assert_int_equal(o.nstep_order[q - 1], 0);
        if (q > 2) high += o.nstep_order[q - 1];
      }
      print_message("%-5s max_order %d: %5ld steps, by order %ld %ld %ld %ld %ld\n",
                    ops[k]->name, order[j], o.nstep, o.nstep_order[0], o.nstep_order[1],
                    o.nstep_order[2], o.nstep_order[3], o.nstep_order[4]);
      assert_int_equal(sum, o.nstep);
      if (order[j] == 5) assert_true(high > o.nstep / 2);
      nstep[j] = o.nstep;
      run_free(&o);
      sw_model_free(m);
    }
    assert_true(nstep[0] > 2 * nstep[1] && nstep[1] > nstep[2]);
  }
  /* automatic (0): CVODE at order 2 at most above rtol 1e-4, up to 5 below; IDA up to 5 */
  const double rtol[2] = {1e-3, 1e-6};
  for (int k = 0; k < 2; k++)
    for (int j = 0; j < 2; j++) {
      sw_model *m = swing_model();
      m->opt.max_order = 0;
      run_out o = run(ops[k], m, rtol[j], rtol[j] * 1e-2, 0.2, 4);
      long high = o.nstep_order[2] + o.nstep_order[3] + o.nstep_order[4];
      print_message("%-5s max_order auto, rtol %g: by order %ld %ld %ld %ld %ld\n", ops[k]->name,
                    rtol[j], o.nstep_order[0], o.nstep_order[1], o.nstep_order[2],
                    o.nstep_order[3], o.nstep_order[4]);
      if (k == 0 && j == 0) assert_int_equal(high, 0);
      else assert_true(high > 0);
      run_free(&o);
      sw_model_free(m);
    }
}

/* CVODE sets its Newton matrix up at least every setup_every steps: at every step with 1, at
 * least every 20th with 20, and less often with 1000 (gamma's drift and failures still ask for
 * setups), on the same path to the tolerance. */
static void setup_every_is_honoured(void **st) {
  (void)st;
  const int every[3] = {1, 20, 1000};
  long nsetup[3];
  double *x0 = NULL;
  for (int j = 0; j < 3; j++) {
    sw_model *m = swing_model();
    m->opt.setup_every = every[j];
    run_out o = run(&sw_cvode_ops, m, 1e-6, 1e-8, 0.2, 4);
    double dd = x0 ? th_max_diff(o.x, x0, m->nv * m->dim) : 0.0;
    print_message("cvode setup_every %4d: %ld steps, %ld setups, %ld factorisations, %.2g m from "
                  "the first\n", every[j], o.nstep, o.nsetup, o.nfactor, dd);
    assert_true(o.nsetup >= o.nstep / every[j]);
    assert_true(dd < 1e-6);
    nsetup[j] = o.nsetup;
    if (!x0) x0 = o.x, free(o.v);
    else run_free(&o);
    sw_model_free(m);
  }
  assert_true(nsetup[2] < nsetup[1]);
  free(x0);
}

/* ------------------------------------------------------ restart, hessian */

/* Output intervals do not change the integration (interpolated output); a caller who changes
 * d between steps gets a restart from the new state, the same as a fresh integrator. */
static void intervals_and_restart(void **st) {
  (void)st;
  const sw_integrator_ops *ops[2] = {&sw_cvode_ops, &sw_ida_ops};
  for (int k = 0; k < 2; k++) {
    sw_model *m = swing_model();
    const int nd = m->nv * m->dim;
    run_out one = run(ops[k], m, 1e-6, 1e-8, 0.1, 1), many = run(ops[k], m, 1e-6, 1e-8, 0.1, 7);
    /* CVODE's and IDA's first step guess depends on the first output time, so the two runs
     * differ within the tolerance (the error at rtol 1e-6 is ~1e-7 m here); the integrator is
     * not restarted per interval (that would cost ~10 steps at order 1 each time). */
    double dd = th_max_diff(one.x, many.x, nd);
    print_message("%s: 1 vs 7 output intervals: %.3g m, steps %ld vs %ld\n", ops[k]->name, dd,
                  one.nstep, many.nstep);
    assert_true(dd < 1e-6);
    assert_true(labs(many.nstep - one.nstep) <= 10);
    /* restart: continue from one.x with zero velocity, two ways */
    char err[SW_ERRSZ];
    sw_data *d1 = sw_data_new(m), *d2 = sw_data_new(m);
    void *s1 = NULL, *s2 = NULL;
    assert_int_equal(ops[k]->init(&s1, m, d1, err, sizeof err), 0);
    assert_int_equal(ops[k]->step(s1, m, d1, 0.05), 0);
    memcpy(d1->x, one.x, (size_t)nd * sizeof(double));
    memset(d1->v, 0, (size_t)nd * sizeof(double));
    d1->t = 0.1;
    memcpy(d2->x, one.x, (size_t)nd * sizeof(double));
    memset(d2->v, 0, (size_t)nd * sizeof(double));
    d2->t = 0.1;
    assert_int_equal(ops[k]->init(&s2, m, d2, err, sizeof err), 0);
    assert_int_equal(ops[k]->step(s1, m, d1, 0.05), 0);
    assert_int_equal(ops[k]->step(s2, m, d2, 0.05), 0);
    dd = th_max_diff(d1->x, d2->x, nd);
    print_message("%s: restarted vs fresh: %.3g m\n", ops[k]->name, dd);
    assert_true(dd < 1e-12);
    ops[k]->free(s1);
    ops[k]->free(s2);
    sw_data_free(d1);
    sw_data_free(d2);
    run_free(&one);
    run_free(&many);
    sw_model_free(m);
  }
}

/* A cloth (density 1 kg/m^2) that starts compressed to 70 %: the exact Hessian is indefinite. */
static sw_model *compressed_model(void) {
  sw_model *m = th_grid_model(3, 4, 3, 0.3, 0.2, 1.0, 50.0, 5.0, G, 1);
  for (int i = 0; i < m->nv * m->dim; i++) m->x0[i] *= 0.7;
  return m;
}

/* The linear solver's setup with a large gamma on the compressed cloth: exact fails as
 * recoverable (SUNDIALS then cuts the step), auto falls back to the projected Hessian (two
 * factorisations), projected factorises once. */
static void hessian_fallback_in_setup(void **st) {
  (void)st;
  sw_model *m = compressed_model();
  sw_data *d = sw_data_new(m);
  char err[SW_ERRSZ];
  const int mode[3] = {SW_HESSIAN_EXACT, SW_HESSIAN_AUTO, SW_HESSIAN_PROJECTED};
  const int want_rc[3] = {1, 0, 0}, want_nfactor[3] = {1, 2, 1}, want_projected[3] = {0, 1, 1};
  for (int j = 0; j < 3; j++) {
    m->opt.hessian = mode[j];
    sw_sunls sys;
    assert_int_equal(sw_sunls_init(&sys, m, d, sw_cvode_reduce, err, sizeof err), 0);
    double *y = calloc(2 * (size_t)sys.n, sizeof(double));
    sw_sunls_gather(&sys, d->x, d->v, y);
    assert_int_equal(sw_sunls_hessian(&sys, y, 0.0), 0);
    const double gamma = 1.0; /* s: gamma^2 |H| far above M */
    sys.cm = 1.0, sys.cd = gamma, sys.ch = gamma * gamma, sys.coef_next = gamma;
    long nf0 = d->nfactor;
    int rc = SUNLinSolSetup(sys.LS, sys.A);
    print_message("hessian mode %d: setup returns %d after %ld factorisations\n", mode[j], rc,
                  d->nfactor - nf0);
    assert_int_equal(rc > 0, want_rc[j]);
    assert_true(rc >= 0);
    assert_int_equal(d->nfactor - nf0, want_nfactor[j]);
    assert_int_equal(sys.h_projected, want_projected[j]);
    free(y);
    sw_sunls_free(&sys);
  }
  sw_data_free(d);
  sw_model_free(m);
}

/* The three Hessian choices reach the same state (to the tolerance) on the compressed cloth;
 * exact and projected have exactly one factorisation per setup. */
static void hessian_choices(void **st) {
  (void)st;
  sw_model *m = compressed_model();
  const int nd = m->nv * m->dim;
  const int mode[3] = {SW_HESSIAN_AUTO, SW_HESSIAN_EXACT, SW_HESSIAN_PROJECTED};
  const char *name[3] = {"auto", "exact", "projected"};
  double *x0 = NULL;
  for (int k = 0; k < 2; k++)
    for (int j = 0; j < 3; j++) {
      const sw_integrator_ops *ops = k ? &sw_ida_ops : &sw_cvode_ops;
      m->opt.hessian = mode[j];
      run_out o = run(ops, m, 1e-8, 1e-10, 0.2, 4);
      double dd = x0 ? th_max_diff(o.x, x0, nd) : 0.0;
      print_message("%-5s hessian %-9s: steps %ld newton %ld setups %ld factorizations %ld, "
                    "%.2g m from the first\n",
                    ops->name, name[j], o.nstep, o.nnewton, o.nsetup, o.nfactor, dd);
      if (mode[j] != SW_HESSIAN_AUTO) assert_int_equal(o.nfactor, o.nsetup);
      if (!x0) {
        x0 = o.x;
        free(o.v);
        continue;
      }
      assert_true(dd < 1e-6);
      run_free(&o);
    }
  free(x0);
  sw_model_free(m);
}

/* A term whose gradient is NaN after t = 0.045 s. */
static int nan_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  (void)t;
  *energy = 0.0;
  if (ev->t > 0.045 && ev->grad)
    for (int k = 0; k < m->nv * m->dim; k++) ev->grad[k] += NAN;
  return SW_OK;
}

static const sw_term_ops nan_ops = {.kind = "nan", .eval = nan_eval};

/* The output interval (0.04, 0.05] fails (SW_FATAL: SUNDIALS did its own retries) with the flag
 * and the reason, quickly (the minimum step stops the creep towards 0.045 s), and leaves d at
 * the last good state.  (SUNDIALS steps past an output time and interpolates back, so a NaN just
 * after an output time can fail the interval before it.) */
static void nan_force_fails_fast(void **st) {
  (void)st;
  const sw_integrator_ops *ops[2] = {&sw_cvode_ops, &sw_ida_ops};
  const char *flag[2] = {"CV_REPTD_RHSFUNC_ERR", "IDA_REP_RES_ERR"};
  for (int k = 0; k < 2; k++) {
    sw_model *m = swing_model();
    sw_term *t = realloc(m->term, (size_t)(m->nterm + 1) * sizeof *t);
    assert_non_null(t);
    m->term = t;
    memset(&t[m->nterm], 0, sizeof *t);
    t[m->nterm].ops = &nan_ops;
    snprintf(t[m->nterm].name, sizeof t[m->nterm].name, "nan");
    assert_int_equal(sw_term_alloc_stencils(&t[m->nterm], 0, 1, m->dim), 0);
    m->nterm++;
    sw_data *d = sw_data_new(m);
    char err[SW_ERRSZ];
    void *s = NULL;
    assert_int_equal(ops[k]->init(&s, m, d, err, sizeof err), 0);
    int rc = SW_OK, n = 0;
    double x2 = 0.0, wall = sw_now();
    for (; n < 10 && rc == SW_OK; n++) {
      x2 = d->x[2];
      rc = ops[k]->step(s, m, d, 0.01);
    }
    wall = sw_now() - wall;
    print_message("%s: interval %d: %s (%.3f s)\n", ops[k]->name, n, d->err, wall);
    assert_int_equal(rc, SW_FATAL);
    assert_int_equal(n, 5); /* (0.04, 0.05] */
    assert_true(fabs(d->t - 0.04) < 1e-12 && d->x[2] == x2);
    assert_non_null(strstr(d->err, flag[k]));
    assert_non_null(strstr(d->err, "not finite"));
    assert_true(wall < 2.0);
    ops[k]->free(s);
    sw_data_free(d);
    sw_model_free(m);
  }
}

/* Options SUNDIALS rejects fail at init, naming the call and the flag. */
static void bad_options_fail_at_init(void **st) {
  (void)st;
  sw_model *m = swing_model();
  m->opt.rtol = -1.0;
  const sw_integrator_ops *ops[2] = {&sw_cvode_ops, &sw_ida_ops};
  for (int k = 0; k < 2; k++) {
    sw_data *d = sw_data_new(m);
    char err[SW_ERRSZ] = "";
    void *s = NULL;
    assert_int_equal(ops[k]->init(&s, m, d, err, sizeof err), SW_FATAL);
    print_message("%s: %s\n", ops[k]->name, err);
    assert_non_null(strstr(err, "SStolerances"));
    assert_non_null(strstr(err, "ILL_INPUT"));
    assert_null(s);
    sw_data_free(d);
  }
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(reduction_solves_full_system),
      cmocka_unit_test(free_fall),
      cmocka_unit_test(error_falls_with_rtol),
      cmocka_unit_test(max_order_is_honoured),
      cmocka_unit_test(setup_every_is_honoured),
      cmocka_unit_test(intervals_and_restart),
      cmocka_unit_test(hessian_fallback_in_setup),
      cmocka_unit_test(hessian_choices),
      cmocka_unit_test(nan_force_fails_fast),
      cmocka_unit_test(bad_options_fail_at_init),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
