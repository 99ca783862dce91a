/* test_physics.c — end-to-end physics: lumped masses, a free corner falling no faster than
 * free fall, static equilibrium whose pin reactions carry the total weight, and backward
 * Euler's total energy never increasing on an undamped scene. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "solver.h"

/* Masses sum to density x rest area. */
static void masses_sum(void **st) {
  (void)st;
  sw_model *m = th_grid_model(3, 10, 7, 0.9, 0.6, 0.25, 100.0, 10.0, NULL, 0);
  double s = 0.0;
  for (int i = 0; i < m->nv; i++) s += m->mass[i];
  assert_float_equal(s, 0.25 * 0.9 * 0.6, 1e-14);
  assert_float_equal(m->total_mass, 0.25 * 0.9 * 0.6, 1e-14);
  sw_model_free(m);
}

/* A cloth hanging from its top row under in-plane gravity: the pin reactions sum to the total
 * weight, up, with relative error below 1e-6. */
static void static_reactions(int dim) {
  const double g[3] = {0.0, -9.81, 0.0};
  sw_model *m = th_grid_model(dim, 9, 9, 0.5, 0.5, 0.1, 2000.0, 50.0, g, 1);
  sw_data *d = sw_data_new(m);
  double r[3];
  assert_int_equal(th_static(m, d, r), 0);
  double W = m->total_mass * 9.81; /* N */
  print_message("dim %d: reactions (%.12g, %.12g, %.12g) N, weight %.12g N\n", dim, r[0], r[1],
                r[2], W);
  assert_true(fabs(r[1] - W) < 1e-6 * W);
  assert_true(fabs(r[0]) < 1e-6 * W && fabs(r[2]) < 1e-6 * W);
  /* it did stretch: the bottom row hangs below its rest position */
  assert_true(d->x[0 * dim + 1] < m->x0[0 * dim + 1] - 1e-5);
  sw_data_free(d);
  sw_model_free(m);
}

static void static_reactions_3d(void **st) { (void)st, static_reactions(3); }
static void static_reactions_2d(void **st) { (void)st, static_reactions(2); }

/* The shipped default scene: its free corner (vertex 0) drops, no faster than backward Euler's
 * own free fall, x_N = g h^2 N (N + 1) / 2 (the continuous 1/2 g t^2 times 1 + h/t). */
static void default_scene_corner_drops(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = th_scene_file("scenes/hanging_cloth.yaml");
  assert_non_null(m);
  sw_data *d = sw_data_new(m);
  const sw_integrator_ops *ops = sw_integrator_find(m->opt.method);
  assert_non_null(ops);
  void *s = NULL;
  assert_int_equal(ops->init(&s, m, d, err, sizeof err), 0);
  double z0 = d->x[2], T = 0.1;
  while (d->t < T - 1e-12) assert_int_equal(ops->step(s, m, d, fmin(m->opt.dt, T - d->t)), 0);
  double N = round(T / m->opt.dt), h = m->opt.dt;
  double drop = z0 - d->x[2], free_fall = 0.5 * 9.81 * h * h * N * (N + 1);
  print_message("corner drop %.6g m after %g s (free fall %.6g m)\n", drop, T, free_fall);
  assert_true(drop > 0.5 * free_fall);
  assert_true(drop <= free_fall * (1 + 1e-9));
  ops->free(s);
  sw_data_free(d);
  sw_model_free(m);
}

/* Undamped cloth swinging down from horizontal: backward Euler's K + U never increases. */
static void backward_euler_dissipates(void **st) {
  (void)st;
  const double g[3] = {0.0, 0.0, -9.81};
  sw_model *m = th_grid_model(3, 12, 12, 0.5, 0.5, 0.1, 1000.0, 20.0, g, 1);
  sw_data *d = sw_data_new(m);
  char err[SW_ERRSZ];
  void *s = NULL;
  assert_int_equal(sw_backward_euler_ops.init(&s, m, d, err, sizeof err), 0);
  double u, e0;
  assert_int_equal(sw_eval_terms(m, d, d->x, 0.0, 0, 0, 0, &u), 0);
  double prev = e0 = u + sw_kinetic(m, d->v);
  for (int n = 0; n < 150; n++) {
    assert_int_equal(sw_backward_euler_ops.step(s, m, d, 0.01), 0);
    assert_int_equal(sw_eval_terms(m, d, d->x, d->t, 0, 0, 0, &u), 0);
    double e = u + sw_kinetic(m, d->v);
    if (e > prev + 1e-10 * fabs(e0)) print_error("step %d: energy %.15g after %.15g\n", n, e, prev);
    assert_true(e <= prev + 1e-10 * fabs(e0));
    prev = e;
  }
  assert_true(prev < e0); /* and it did dissipate */
  sw_backward_euler_ops.free(s);
  sw_data_free(d);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(masses_sum),
      cmocka_unit_test(static_reactions_3d),
      cmocka_unit_test(static_reactions_2d),
      cmocka_unit_test(default_scene_corner_drops),
      cmocka_unit_test(backward_euler_dissipates),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
