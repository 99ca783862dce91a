/* test_damping.c — Rayleigh damping D = alpha M + beta K (solvers/damping.c) in every method:
 *   - free fall with mass damping against the analytic answer x(t) = x0 + g/a t - g/a^2
 *     (1 - e^{-a t}): each fixed-step method converges at its order, CVODE and IDA to rtol;
 *   - a small hanging cloth with mass and stiffness damping: every method converges to the
 *     same solution as CVODE at a tight tolerance (which uses D at the current state, the ODE
 *     itself), at its order, so the per-step frozen D of the Newton methods is consistent;
 *     with Newton-Krylov (newton_reuse on) too;
 *   - the damping force dissipates (v.D v >= 0) and energy + dissipated work is conserved by
 *     the implicit midpoint rule to its order;
 *   - a mass on a tendon with mass, stiffness and tendon damping: the damped oscillator;
 *   - the damping power a Newton method reports after a step is v.D v with the D it froze at
 *     its predictor, none before a step or after a reset; the sim logs it. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "scene.h"
#include "solver.h"

/* Integrate to T with n equal steps (adaptive methods: one interval per step); x, v out.
 * With work != NULL: the work damping did, by the trapezoid rule on v.D v at the steps (J). */
static void integrate(const sw_integrator_ops *ops, const sw_model *m, double T, int n, double *x,
                      double *v, double *work) {
  void *s;
  sw_data *d = th_start(ops, m, &s);
  assert_non_null(d);
  int rc;
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  double *scratch = calloc(nd, sizeof(double)), p0 = 0.0, p1;
  if (work) {
    *work = 0.0;
    assert_int_equal(sw_damping_force(m, d, d->x, d->t, d->v, scratch, &p0), 0);
  }
  for (int k = 1; k <= n; k++) {
    double end = k == n ? T : T * k / n;
    rc = ops->step(s, m, d, end - d->t);
    if (rc) print_error("%s: step %d: %s\n", ops->name, k, d->err);
    assert_int_equal(rc, 0);
    d->t = end;
    if (!work) continue;
    assert_int_equal(sw_damping_force(m, d, d->x, d->t, d->v, scratch, &p1), 0);
    assert_true(p1 >= 0.0);
    *work += 0.5 * (p0 + p1) * (T / n);
    p0 = p1;
  }
  memcpy(x, d->x, nd * sizeof(double));
  memcpy(v, d->v, nd * sizeof(double));
  free(scratch);
  ops->free(s);
  sw_data_free(d);
}

typedef struct method_order {
  const sw_integrator_ops *ops;
  double order;
} method_order;

static const method_order fixed[] = {
    {&sw_backward_euler_ops, 1.0}, {&sw_bdf2_ops, 2.0}, {&sw_implicit_midpoint_ops, 2.0},
    {&sw_newmark_ops, 2.0},        {&sw_symplectic_euler_ops, 1.0},
};
enum { NFIXED = 5 };

/* Fitted order of ops against the reference xref over n = n0, 2 n0, 4 n0 steps. */
static double fitted_order(const sw_integrator_ops *ops, const sw_model *m, double T, int n0,
                           const double *xref) {
  int nd = m->nv * m->dim;
  double *x = calloc((size_t)nd, sizeof(double)), *v = calloc((size_t)nd, sizeof(double));
  double h[3], e[3];
  for (int k = 0; k < 3; k++) {
    int n = n0 << k;
    integrate(ops, m, T, n, x, v, NULL);
    h[k] = T / n;
    e[k] = th_max_diff(x, xref, nd);
  }
  free(x), free(v);
  double p = th_slope(h, e, 3);
  print_message("%-18s errors %.3g %.3g %.3g, order %.2f\n", ops->name, e[0], e[1], e[2], p);
  return p;
}

static void free_fall_mass_damping(void **st) {
  (void)st;
  const double g[3] = {0.0, 0.0, -9.81}, a = 2.0, T = 1.0; /* m/s^2, 1/s, s */
  sw_model *m = th_grid_model(3, 3, 3, 0.2, 0.2, 0.1, 0.0, 0.0, g, 0);
  assert_non_null(m);
  m->damp_mass = a;
  int nd = m->nv * 3;
  double *xref = calloc((size_t)nd, sizeof(double));
  double dz = g[2] / a * T - g[2] / (a * a) * (1.0 - exp(-a * T)); /* m */
  for (int i = 0; i < nd; i++) xref[i] = m->x0[i] + (i % 3 == 2 ? dz : 0.0);
  for (int k = 0; k < NFIXED; k++)
    assert_true(fabs(fitted_order(fixed[k].ops, m, T, 20, xref) - fixed[k].order) < 0.15);
  /* adaptive methods: error bounded by the tolerance's scale */
  double *x = calloc((size_t)nd, sizeof(double)), *v = calloc((size_t)nd, sizeof(double));
  m->opt.rtol = 1e-9;
  m->opt.atol = 1e-11;
  const sw_integrator_ops *ad[2] = {&sw_cvode_ops, &sw_ida_ops};
  for (int k = 0; k < 2; k++) {
    integrate(ad[k], m, T, 4, x, v, NULL);
    double e = th_max_diff(x, xref, nd);
    print_message("%-18s error %.3g\n", ad[k]->name, e);
    assert_true(e < 1e-6);
  }
  free(x), free(v), free(xref);
  sw_model_free(m);
}

/* A swinging cloth strip with alpha and beta: every method converges to CVODE's answer. */
static void cloth_stiffness_damping(void **st) {
  (void)st;
  const double g[3] = {0.0, -9.81, -3.0}, T = 0.2; /* s */
  sw_model *m = th_grid_model(3, 4, 3, 0.3, 0.2, 0.2, 60.0, 5.0, g, 1);
  assert_non_null(m);
  m->damp_mass = 0.5;      /* 1/s */
  m->damp_stiffness = 0.01; /* s */
  int nd = m->nv * 3;
  double *xref = calloc((size_t)nd, sizeof(double)), *v = calloc((size_t)nd, sizeof(double));
  m->opt.rtol = 1e-11;
  m->opt.atol = 1e-13;
  integrate(&sw_cvode_ops, m, T, 4, xref, v, NULL);
  for (int k = 0; k < NFIXED - 1; k++) /* symplectic Euler: unstable at these steps */
    assert_true(fabs(fitted_order(fixed[k].ops, m, T, 40, xref) - fixed[k].order) < 0.25);
  /* the same orders with Newton-Krylov at Newton's default tolerance: CG's error in the last
   * direction is corrected (without that correction BDF2 measured order 0.92 here) */
  m->opt.newton_reuse = SW_REUSE_ON;
  for (int k = 0; k < NFIXED - 1; k++)
    assert_true(fabs(fitted_order(fixed[k].ops, m, T, 40, xref) - fixed[k].order) < 0.25);
  free(xref), free(v);
  sw_model_free(m);
}

/* Midpoint: K + U + the dissipated work stays at its initial value to O(h^2). */
static void energy_balance(void **st) {
  (void)st;
  const double g[3] = {0.0, -9.81, -3.0}, T = 0.2;
  sw_model *m = th_grid_model(3, 4, 3, 0.3, 0.2, 0.2, 60.0, 5.0, g, 1);
  assert_non_null(m);
  m->damp_mass = 1.0;
  m->damp_stiffness = 0.02;
  int nd = m->nv * 3;
  double *x = calloc((size_t)nd, sizeof(double)), *v = calloc((size_t)nd, sizeof(double));
  sw_data *d = sw_data_new(m);
  double u0, u1, work[2], gap[2];
  assert_int_equal(sw_eval_terms(m, d, m->x0, 0.0, 0, 0, 0, &u0), 0);
  for (int k = 0; k < 2; k++) {
    integrate(&sw_implicit_midpoint_ops, m, T, 100 << k, x, v, &work[k]);
    assert_int_equal(sw_eval_terms(m, d, x, T, 0, 0, 0, &u1), 0);
    gap[k] = fabs(sw_kinetic(m, v) + u1 + work[k] - u0);
    print_message("midpoint n=%d: dissipated %.6g J, balance gap %.3g J\n", 100 << k, work[k],
                  gap[k]);
    assert_true(work[k] > 0.0);
  }
  assert_true(gap[1] < 0.35 * gap[0]); /* second order: 1/4 */
  assert_true(gap[1] < 1e-3 * work[1]);
  sw_data_free(d);
  free(x), free(v);
  sw_model_free(m);
}

/* A mass on a two-waypoint spring tendon (one end pinned), all three kinds of damping along
 * it: m x'' + (alpha m + beta K + c) x' + K (x - L) = 0, the damped oscillator.  Every method
 * converges to the analytic answer at its order. */
static void tendon_oscillator(void **st) {
  (void)st;
  const char *scene = "dimension: 2\n"
                      "mesh: {points: [[0, 0], [1.2, 0]]}\n"
                      "pins: [{select: {vertices: [0]}}]\n"
                      "damping: {mass: 1.0, stiffness: 0.005}\n"
                      "tendons: [{waypoints: [0, 1], law: spring, stiffness: 100,\n"
                      "           rest_length: 1.0, density: 1.0, damping: 0.5}]\n";
  sw_model *m = th_scene("oscillator.yaml", scene);
  assert_non_null(m);
  const double mass = 0.6, K = 100.0, L = 1.0, A = 0.2, T = 0.5; /* kg, N/m, m, m, s */
  double b = 1.0 * mass + 0.005 * K + 0.5, gam = b / (2 * mass);   /* N s/m, 1/s */
  double wd = sqrt(K / mass - gam * gam);                            /* rad/s */
  double xT = L + A * exp(-gam * T) * (cos(wd * T) + gam / wd * sin(wd * T));
  double xref[4] = {0.0, 0.0, xT, 0.0};
  for (int k = 0; k < NFIXED - 1; k++)
    assert_true(fitted_order(fixed[k].ops, m, T, 100, xref) > fixed[k].order - 0.15);
  double x[4], v[4];
  m->opt.rtol = 1e-10;
  m->opt.atol = 1e-12;
  integrate(&sw_cvode_ops, m, T, 5, x, v, NULL);
  print_message("cvode error %.3g\n", th_max_diff(x, xref, 4));
  assert_true(th_max_diff(x, xref, 4) < 1e-7);
  sw_model_free(m);
}

/* v_{n+1}.D v_{n+1} with D at the step's predictor xhat (a fresh evaluation, sw_damping_force). */
static double frozen_power(const sw_model *m, const double *xhat, double t, const double *v) {
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  sw_data *d = sw_data_new(m);
  double *out = calloc(nd, sizeof(double)), p = -1.0;
  assert_int_equal(sw_damping_force(m, d, xhat, t, v, out, &p), 0);
  free(out);
  sw_data_free(d);
  return p;
}

/* After each of three steps of backward Euler, BDF2's start and the implicit midpoint rule on
 * a swinging cloth with mass and stiffness damping: ops->damping_power is v.D v at the
 * accepted velocity with D at the step's predictor (x_n + h v_n; midpoint x_n + h/2 v_n), to
 * round-off, and differs from D at the new state; none before a step and after a reset. */
static void frozen_damping_power(void **st) {
  (void)st;
  const double g[3] = {0.0, -9.81, -3.0}, h = 0.02; /* m/s^2, s */
  sw_model *m = th_grid_model(3, 4, 3, 0.3, 0.2, 0.2, 60.0, 5.0, g, 1);
  assert_non_null(m);
  m->damp_mass = 0.5;       /* 1/s */
  m->damp_stiffness = 0.01; /* s */
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  double *xhat = calloc(nd, sizeof(double));
  const sw_integrator_ops *ops[3] = {&sw_backward_euler_ops, &sw_bdf2_ops,
                                     &sw_implicit_midpoint_ops};
  const double frac[3] = {1.0, 1.0, 0.5}; /* predictor x_n + frac h v_n */
  for (int k = 0; k < 3; k++) {
    void *s;
    sw_data *d = th_start(ops[k], m, &s);
    assert_non_null(d);
    double p;
    assert_int_not_equal(ops[k]->damping_power(s, m, d, &p), 0); /* no step yet */
    for (int n = 0; n < 3; n++) {
      for (size_t i = 0; i < nd; i++) xhat[i] = d->x[i] + frac[k] * h * d->v[i];
      double tstage = d->t + frac[k] * h;
      assert_int_equal(ops[k]->step(s, m, d, h), 0);
      if (ops[k] == &sw_bdf2_ops && n > 0) break; /* BDF2 proper: another predictor */
      assert_int_equal(ops[k]->damping_power(s, m, d, &p), 0);
      double ref = frozen_power(m, xhat, tstage, d->v), now = frozen_power(m, d->x, d->t, d->v);
      print_message("%-18s step %d: v.D v %.12g W, D at the predictor %.12g, at x_{n+1} %.12g\n",
                    ops[k]->name, n + 1, p, ref, now);
      assert_true(ref > 0.0);
      assert_true(fabs(p - ref) < 1e-12 * ref);
      assert_true(fabs(now - ref) > 1e-9 * ref); /* the check can tell the two apart */
    }
    ops[k]->reset(s, m, d, SW_CHANGED_MODEL);
    assert_int_not_equal(ops[k]->damping_power(s, m, d, &p), 0);
    ops[k]->free(s);
    sw_data_free(d);
  }
  /* the sim logs it: D at the state for the first state, the step's frozen D after a step */
  snprintf(m->opt.method, sizeof m->opt.method, "backward-euler");
  m->opt.dt = h;
  for (size_t i = 0; i < nd; i++) m->v0[i] = 0.1 * sin((double)i); /* m/s: p0 > 0 */
  char err[SW_ERRSZ];
  sw_sim *sim = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(sim);
  const sw_data *d = sw_sim_data(sim);
  double p0 = frozen_power(m, d->x, d->t, d->v);
  assert_true(p0 > 0.0);
  assert_true(fabs(d->damp_power - p0) < 1e-12 * p0);
  for (size_t i = 0; i < nd; i++) xhat[i] = d->x[i] + h * d->v[i];
  assert_int_equal(sw_sim_step(sim, err, sizeof err), 0);
  double p1 = frozen_power(m, xhat, d->t, d->v);
  assert_true(fabs(d->damp_power - p1) < 1e-12 * p1);
  assert_true(fabs(d->dissipated - 0.5 * (p0 + p1) * h) < 1e-12 * p1 * h); /* trapezoid, J */
  sw_sim_free(sim);
  free(xhat);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(free_fall_mass_damping),
      cmocka_unit_test(cloth_stiffness_damping),
      cmocka_unit_test(energy_balance),
      cmocka_unit_test(tendon_oscillator),
      cmocka_unit_test(frozen_damping_power),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
