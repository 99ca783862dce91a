/* test_sim.c — the stepping API (sim/sim.c): N steps are sw_run's run, a rest length changed
 * between steps is the scene with that rest length from then on (every integrator, CVODE and
 * IDA through their restart), a moved pin reaches CVODE's forces, the static solve after a
 * change has the analytic equilibrium, bad changes are errors; state copies and resets repeat
 * steps to the bit, dt changes the grid, bad times and closed sims are errors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "util.h"

/* A 6 x 6 cloth hung from its top edge, a spring tendon through its bottom row whose rest
 * length is REST (printed into the text), membrane stiffness k (N/m; the tendon k/6, shear
 * k/30), light Rayleigh damping; in 3D (plane xz, gravity -z)
 * or in 2D (plane xy, gravity -y: no buckling out of the plane, so no sensitivity to
 * round-off). */
static sw_model *cloth_dim(int dim, double k, double rest, const char *method) {
  char text[2048];
  snprintf(text, sizeof text,
           "dimension: %d\n"
           "mesh: {grid: {size: [1.0, 1.0], vertices: [6, 6], plane: %s}}\n"
           "material: {density: 0.1, membrane: {model: bw98, k_u: %g, k_v: %g, k_shear: %g}}\n"
           "gravity: %s\n"
           "pins: [{select: {box: %s}}]\n"
           "damping: {mass: 0.2}\n"
           "tendons: [{name: hem, waypoints: [0, 1, 2, 3, 4, 5], law: spring, stiffness: %g,\n"
           "           rest_length: %.17g}]\n"
           "integrator: {method: %s, dt: 0.01}\n"
           "duration: 0.2\n"
           "output: {dir: out/test_sim, frames_every: 0}\n",
           dim, dim == 3 ? "xz" : "xy", k, k, k / 30.0, dim == 3 ? "[0, 0, -9.81]" : "[0, -9.81]",
           dim == 3 ? "[[-0.01, -1, 0.999], [1.01, 1, 1.01]]" : "[[-0.01, 0.999], [1.01, 1.01]]",
           k / 6.0, rest, method);
  return th_scene("sim.yaml", text);
}

static sw_model *cloth(double rest, const char *method) { return cloth_dim(3, 300.0, rest, method); }

static sw_sim *start(sw_model *m, int flags) {
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, flags, err, sizeof err);
  if (!s) print_error("sw_sim_new: %s\n", err);
  return s;
}

static void steps(sw_sim *s, int n) {
  char err[SW_ERRSZ];
  for (int k = 0; k < n; k++) {
    int rc = sw_sim_step(s, err, sizeof err);
    if (rc) print_error("step %d: %s\n", k, err);
    assert_int_equal(rc, 0);
  }
}

/* energy.csv without its wall-time column (the 3rd from last field of each line, or the last
 * without damping columns: here the scene is damped, so counted from the end). */
static char *energy_without_wall(const char *dir) {
  char *s = th_slurp_in(dir, "energy.csv");
  assert_non_null(s);
  char *out = malloc(strlen(s) + 1), *o = out;
  for (char *line = strtok(s, "\n"); line; line = strtok(NULL, "\n")) {
    char *f[64];
    int n = 0;
    for (char *p = line; p && n < 64; p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL) f[n++] = p;
    for (int k = 0; k < n; k++) {
      if (k == n - 3) continue; /* step_wall_s, damping_power, dissipated */
      size_t len = (k + 1 < n) ? (size_t)(f[k + 1] - f[k]) : strlen(f[k]);
      memcpy(o, f[k], len);
      o += len;
    }
    *o++ = '\n';
  }
  *o = '\0';
  free(s);
  return out;
}

/* N steps of sw_sim_step with a run folder write what sw_run writes (tension.csv, tendons.csv
 * and energy.csv but its wall times), and end in the same state as sw_sim_run without one. */
static void steps_are_run(const char *method) {
  sw_model *m = cloth(0.9, method);
  assert_non_null(m);
  char err[SW_ERRSZ];
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "out/test_sim_run");
  th_remove_tree(m->opt.out_dir);
  assert_int_equal(sw_run(m, 0, err, sizeof err), 0);
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "out/test_sim_steps");
  th_remove_tree(m->opt.out_dir);
  sw_sim *s = start(m, SW_SIM_OUTPUT);
  assert_non_null(s);
  steps(s, 20);
  assert_true(fabs(sw_sim_data(s)->t - 0.2) < 1e-15);
  assert_int_equal(sw_sim_close(s, err, sizeof err), 0);
  sw_model *m2 = cloth(0.9, method);
  sw_sim *r = start(m2, 0);
  assert_int_equal(sw_sim_run(r, 0.2, err, sizeof err), 0);
  const int nd = m->nv * m->dim;
  assert_memory_equal(sw_sim_data(s)->x, sw_sim_data(r)->x, nd * sizeof(double));
  assert_memory_equal(sw_sim_data(s)->v, sw_sim_data(r)->v, nd * sizeof(double));
  sw_sim_free(s);
  sw_sim_free(r);
  const char *same[] = {"tension.csv", "tendons.csv"};
  for (int k = 0; k < 2; k++) {
    char *a = th_slurp_in("out/test_sim_run", same[k]), *b = th_slurp_in("out/test_sim_steps",
                                                                          same[k]);
    assert_non_null(a);
    assert_non_null(b);
    assert_string_equal(a, b);
    free(a);
    free(b);
  }
  char *a = energy_without_wall("out/test_sim_run"), *b = energy_without_wall("out/test_sim_steps");
  assert_string_equal(a, b);
  free(a);
  free(b);
  th_remove_tree("out/test_sim_run");
  th_remove_tree("out/test_sim_steps");
  sw_model_free(m);
  sw_model_free(m2);
}

static void steps_are_run_be(void **state) { (void)state, steps_are_run("backward-euler"); }
static void steps_are_run_cvode(void **state) { (void)state, steps_are_run("cvode"); }

/* Rest 0.9 to t = 0.1, then 0.7 to 0.2, equals the scene with rest 0.7 started at the state of
 * t = 0.1: to the last bit for the methods that restart there alike (backward Euler, Newmark,
 * CVODE, IDA: both sims restart them at the same state), and the tendon feels it. */
static void rest_change_is_new_scene(const char *method) {
  char err[SW_ERRSZ];
  sw_model *ma = cloth(0.9, method), *mb = cloth(0.7, method);
  sw_sim *a = start(ma, 0), *b = start(mb, 0);
  assert_non_null(a);
  assert_non_null(b);
  steps(a, 10);
  const sw_data *da = sw_sim_data(a), *db = sw_sim_data(b);
  assert_int_equal(sw_sim_set_rest(a, 0, 0.7, err, sizeof err), 0);
  assert_true(sw_sim_rest(a, 0) == 0.7);
  /* the diagnostics follow at once: tension K (l - 0.7) */
  assert_true(fabs(da->tendon_tension[0] - 50.0 * (da->tendon_length[0] - 0.7)) < 1e-12);
  assert_int_equal(sw_sim_set_state(b, da->t, da->x, da->v, err, sizeof err), 0);
  steps(a, 10);
  steps(b, 10);
  const int nd = ma->nv * ma->dim;
  print_message("%s: t = %.17g, %.17g; max |xa - xb| = %.3g m\n", method, da->t, db->t,
                th_max_diff(da->x, db->x, nd));
  assert_true(da->t == db->t);
  assert_memory_equal(da->x, db->x, nd * sizeof(double));
  assert_memory_equal(da->v, db->v, nd * sizeof(double));
  sw_sim_free(a);
  sw_sim_free(b);
  sw_model_free(ma);
  sw_model_free(mb);
}

static void rest_change_be(void **state) { (void)state, rest_change_is_new_scene("backward-euler"); }
static void rest_change_newmark(void **state) { (void)state, rest_change_is_new_scene("newmark"); }
static void rest_change_cvode(void **state) { (void)state, rest_change_is_new_scene("cvode"); }
static void rest_change_ida(void **state) { (void)state, rest_change_is_new_scene("ida"); }

/* The state (2D) at t = 0.2 after rest 0.9 to t = 0.1 and 0.6 after, by method with step dt (and
 * CVODE's tolerances), into x. */
static void after_change(const char *method, double dt, double *x) {
  char err[SW_ERRSZ];
  sw_model *m = cloth_dim(2, 30.0, 0.9, method);
  m->opt.dt = dt;
  m->opt.rtol = 1e-9;
  m->opt.atol = 1e-11;
  sw_sim *s = start(m, 0);
  assert_non_null(s);
  assert_int_equal(sw_sim_run(s, 0.1, err, sizeof err), 0);
  assert_int_equal(sw_sim_set_rest(s, 0, 0.6, err, sizeof err), 0);
  assert_int_equal(sw_sim_run(s, 0.2, err, sizeof err), 0);
  memcpy(x, sw_sim_data(s)->x, m->nv * m->dim * sizeof(double));
  sw_sim_free(s);
  sw_model_free(m);
}

/* CVODE restarted after a rest change is the solution the implicit midpoint rule converges to
 * at order 2 through the same change (a jump of the right-hand side CVODE would otherwise step
 * over with its old history).  A soft cloth: the asymptotic range starts at dt ~ 2e-3 s. */
static void cvode_rest_change_is_the_limit(void **state) {
  (void)state;
  enum { ND = 72, NH = 3 };
  double xc[ND], xe[ND], h[NH] = {2e-3, 1e-3, 5e-4}, e[NH];
  after_change("cvode", 0.01, xc);
  for (int k = 0; k < NH; k++) {
    after_change("implicit-midpoint", h[k], xe);
    e[k] = th_max_diff(xc, xe, ND);
    print_message("implicit midpoint dt %g: max |x - x_cvode| = %.3g m\n", h[k], e[k]);
  }
  double order = th_slope(h, e, NH);
  print_message("observed order %.3f\n", order);
  assert_true(order > 1.8 && order < 2.4);
}

/* A pin moved between steps reaches CVODE's forces (its positions of the pinned vertices are
 * refreshed): the same as a sim whose state was set with the pin there. */
static void cvode_pin_move(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *ma = cloth(0.9, "cvode"), *mb = cloth(0.9, "cvode");
  sw_sim *a = start(ma, 0), *b = start(mb, 0);
  steps(a, 5);
  const sw_data *da = sw_sim_data(a), *db = sw_sim_data(b);
  const int corner = 35, nd = ma->nv * ma->dim; /* (1, 0, 1): pinned */
  double p[3] = {1.1, 0.05, 1.0};
  double *x = malloc(nd * sizeof(double));
  memcpy(x, da->x, nd * sizeof(double));
  memcpy(x + 3 * corner, p, sizeof p);
  assert_int_equal(sw_sim_set_pin(a, corner, p, err, sizeof err), 0);
  assert_int_equal(sw_sim_set_state(b, da->t, x, da->v, err, sizeof err), 0);
  steps(a, 5);
  steps(b, 5);
  assert_memory_equal(da->x, db->x, nd * sizeof(double));
  assert_true(da->x[3 * corner] == 1.1);
  /* the neighbour of the moved corner was pulled towards +x */
  sw_model *mc = cloth(0.9, "cvode");
  sw_sim *c = start(mc, 0);
  steps(c, 10);
  assert_true(da->x[3 * 29] > sw_sim_data(c)->x[3 * 29] + 1e-4);
  free(x);
  sw_sim_free(a);
  sw_sim_free(b);
  sw_sim_free(c);
  sw_model_free(ma);
  sw_model_free(mb);
  sw_model_free(mc);
}

/* Two masses hanging from pins on spring tendons (2D, no membrane): the static solve after each
 * rest change gives length = rest + m g / K and tension = m g (each bottom vertex's lumped
 * mass). */
static void static_after_rest_change(void **state) {
  (void)state;
  const double g[2] = {0.0, -9.81}, K = 200.0; /* m/s^2, N/m */
  sw_model *m = th_grid_start(2, 2, 2, 1.0, 1.0, 0.3, 0.0, 0.0, g, 1);
  assert_non_null(m);
  const int w0[2] = {2, 0}, w1[2] = {3, 1};
  th_add_tendon(m, w0, 2, SW_LAW_SPRING, K, 1.0, 0.0);
  th_add_tendon(m, w1, 2, SW_LAW_SPRING, K, 1.0, 0.0);
  m = th_finish(m);
  assert_non_null(m);
  snprintf(m->opt.method, sizeof m->opt.method, "static");
  sw_sim *s = start(m, 0);
  assert_non_null(s);
  char err[SW_ERRSZ];
  const double rests[3] = {1.0, 0.8, 1.3};
  for (int k = 0; k < 3; k++) {
    for (int t = 0; t < 2; t++) assert_int_equal(sw_sim_set_rest(s, t, rests[k], err, sizeof err), 0);
    assert_int_equal(sw_sim_step(s, err, sizeof err), 0);
    const sw_data *d = sw_sim_data(s);
    for (int t = 0; t < 2; t++) {
      double w = m->mass[m->tendon[t].way[1]] * 9.81; /* N */
      assert_true(fabs(d->tendon_length[t] - (rests[k] + w / K)) < 1e-9);
      assert_true(fabs(d->tendon_tension[t] - w) < 1e-7);
    }
  }
  sw_sim_free(s);
  sw_model_free(m);
}

/* Bad changes are errors with a message; the sim goes on. */
static void bad_changes(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *m = cloth(0.9, "backward-euler");
  sw_sim *s = start(m, 0);
  double p[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 0};
  assert_int_not_equal(sw_sim_set_rest(s, 1, 0.5, err, sizeof err), 0);
  assert_non_null(strstr(err, "no tendon 1"));
  assert_int_not_equal(sw_sim_set_rest(s, 0, -1.0, err, sizeof err), 0);
  assert_non_null(strstr(err, "hem"));
  assert_int_not_equal(sw_sim_set_pin(s, 0, p, err, sizeof err), 0);
  assert_non_null(strstr(err, "not pinned"));
  assert_int_not_equal(sw_sim_set_pin(s, 35, nan3, err, sizeof err), 0);
  assert_non_null(strstr(err, "not finite"));
  assert_int_not_equal(sw_sim_set_load(s, 3, p, err, sizeof err), 0);
  assert_non_null(strstr(err, "no `loads`"));
  assert_int_equal(sw_tendon_find(m, "hem"), 0);
  assert_int_equal(sw_tendon_find(m, "nope"), -1);
  assert_int_not_equal(sw_model_set_option(m, "dt", "-1", err, sizeof err), 0);
  assert_int_not_equal(sw_model_set_option(m, "method", "euler", err, sizeof err), 0);
  assert_int_not_equal(sw_model_set_option(m, "nope", "1", err, sizeof err), 0);
  steps(s, 2);
  sw_sim_free(s);
  sw_model_free(m);
}

/* n steps from s, their positions after each into xs (n x nd). */
static void record_steps(sw_sim *s, int n, double *xs, long nd) {
  for (int k = 0; k < n; k++) {
    steps(s, 1);
    memcpy(xs + k * nd, sw_sim_data(s)->x, (size_t)nd * sizeof(double));
  }
}

/* A state copy put back (into the same sim and into another) repeats the steps after it to the
 * bit; a reset repeats a fresh sim's steps to the bit and keeps the arrays' addresses. */
static void state_copy_and_reset(const char *method) {
  char err[SW_ERRSZ];
  sw_model *m = cloth(0.9, method);
  sw_sim *s = start(m, 0), *o = start(m, 0);
  const long nd = (long)m->nv * m->dim, n = 5;
  double *a = calloc((size_t)(n * nd), sizeof(double)), *b = calloc((size_t)(n * nd), sizeof(double));
  record_steps(o, (int)n, a, nd); /* a fresh sim's first steps */
  const double *x = sw_sim_array(s, "x", NULL, NULL);
  steps(s, 7);
  assert_int_equal(sw_sim_reset(s, err, sizeof err), 0);
  assert_ptr_equal(sw_sim_array(s, "x", NULL, NULL), x);
  assert_true(sw_sim_time(s) == 0.0 && sw_sim_counter(s, "nstep") == 0);
  record_steps(s, (int)n, b, nd);
  assert_memory_equal(a, b, (size_t)(n * nd) * sizeof(double));

  size_t size = sw_sim_get_state(s, NULL, 0);
  unsigned char *copy = malloc(size);
  assert_true(size > 0 && sw_sim_get_state(s, copy, size) == size);
  record_steps(s, (int)n, a, nd);
  assert_int_equal(sw_sim_put_state(s, copy, size, err, sizeof err), 0);
  record_steps(s, (int)n, b, nd);
  assert_memory_equal(a, b, (size_t)(n * nd) * sizeof(double));
  assert_int_equal(sw_sim_put_state(o, copy, size, err, sizeof err), 0);
  record_steps(o, (int)n, b, nd);
  assert_memory_equal(a, b, (size_t)(n * nd) * sizeof(double));
  assert_int_not_equal(sw_sim_put_state(o, copy, size - 1, err, sizeof err), 0);
  assert_non_null(strstr(err, "cut short"));
  free(copy), free(a), free(b);
  sw_sim_free(s), sw_sim_free(o);
  sw_model_free(m);
}

static void state_copy_and_reset_be(void **st) { (void)st, state_copy_and_reset("backward-euler"); }
static void state_copy_and_reset_bdf2(void **st) { (void)st, state_copy_and_reset("bdf2"); }

/* dt changes the grid from the current time; bad times, closed sims and all rest lengths at
 * once. */
static void dt_times_close(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *m = cloth(0.9, "backward-euler");
  sw_sim *s = start(m, 0);
  steps(s, 2);
  assert_int_equal(sw_sim_set_dt(s, 0.004, err, sizeof err), 0);
  assert_true(sw_sim_dt(s) == 0.004);
  steps(s, 3);
  assert_true(fabs(sw_sim_time(s) - 0.032) < 1e-15);
  assert_int_not_equal(sw_sim_set_dt(s, -1.0, err, sizeof err), 0);
  assert_int_not_equal(sw_sim_set_dt(s, NAN, err, sizeof err), 0);
  assert_int_not_equal(sw_sim_run(s, NAN, err, sizeof err), 0);
  assert_int_not_equal(sw_sim_run(s, INFINITY, err, sizeof err), 0);
  assert_int_not_equal(sw_sim_run(s, 0.01, err, sizeof err), 0);
  assert_non_null(strstr(err, "until"));
  assert_int_equal(sw_sim_run_steps(s, 1.0, 2, err, sizeof err), 0); /* two steps only */
  assert_true(fabs(sw_sim_time(s) - 0.04) < 1e-15);
  double rest[1] = {0.7}, got[1];
  assert_int_equal(sw_sim_set_rests(s, rest, err, sizeof err), 0);
  sw_sim_rests(s, got);
  assert_true(got[0] == 0.7 && sw_sim_rest(s, 0) == 0.7);
  rest[0] = -1.0;
  assert_int_not_equal(sw_sim_set_rests(s, rest, err, sizeof err), 0);
  long c[16];
  assert_int_equal(sw_sim_counters(s, c, 16), 11);
  assert_int_equal(c[0], sw_sim_counter(s, "nstep"));
  assert_int_equal(sw_sim_close(s, err, sizeof err), 0);
  assert_int_not_equal(sw_sim_step(s, err, sizeof err), 0);
  assert_non_null(strstr(err, "closed"));
  assert_int_not_equal(sw_sim_reset(s, err, sizeof err), 0);
  sw_sim_free(s);
  sw_model_free(m);
}

/* The layout of restart.bin's header and run loop part (sim.c sim_io: every field's size, in
 * order) for a cloth with self-contact over a sphere, a tendon, backward Euler: a resumed run
 * reads the bytes of its own format's layout, so a change of it (a counter, an option, a
 * term's state) must come with a new format version, which refuses the older files
 * ("format 05; expected format 06") instead of reading them shifted.  When this fails: bump
 * SW_RESTART_MAGIC's version and set SW_RESTART_SHAPE (sim/util.h) to the shape printed.  On
 * LP64 only (the sizes of the structs are the platform's). */
static void restart_layout(void **state) {
  (void)state;
  if (sizeof(void *) != 8 || sizeof(long) != 8) skip();
  sw_model *m = th_scene("layout.yaml",
      "dimension: 3\n"
      "mesh: {grid: {size: [0.5, 0.5], vertices: [6, 6], plane: xy}}\n"
      "material: {density: 0.1, membrane: {model: bw98, k_u: 500, k_v: 500, k_shear: 20}}\n"
      "gravity: [0, 0, -9.81]\n"
      "obstacles: [{shape: sphere, center: [0.25, 0.25, -0.21], radius: 0.2}]\n"
      "contact: {self: true, thickness: 1e-3, friction: 0.3}\n"
      "tendons: [{name: hem, waypoints: [0, 1, 2, 3, 4, 5], law: spring, stiffness: 50}]\n"
      "integrator: {method: backward-euler, dt: 0.01}\n"
      "duration: 0.05\n");
  assert_non_null(m);
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  assert_int_equal(sw_sim_step(s, err, sizeof err), 0);
  uint64_t shape = sw_sim_restart_shape(s);
  print_message("restart format %s, layout 0x%016llx (recorded: 0x%016llx)\n",
                SW_RESTART_MAGIC + 6, (unsigned long long)shape,
                (unsigned long long)SW_RESTART_SHAPE);
  assert_true(shape == SW_RESTART_SHAPE);
  sw_sim_free(s);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(state_copy_and_reset_be),
      cmocka_unit_test(state_copy_and_reset_bdf2),
      cmocka_unit_test(dt_times_close),
      cmocka_unit_test(steps_are_run_be),
      cmocka_unit_test(steps_are_run_cvode),
      cmocka_unit_test(rest_change_be),
      cmocka_unit_test(rest_change_newmark),
      cmocka_unit_test(rest_change_cvode),
      cmocka_unit_test(rest_change_ida),
      cmocka_unit_test(cvode_rest_change_is_the_limit),
      cmocka_unit_test(cvode_pin_move),
      cmocka_unit_test(static_after_rest_change),
      cmocka_unit_test(bad_changes),
      cmocka_unit_test(restart_layout),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
