/* test_forcing.c — forcing a user states in a scene (models/forcing.c, docs/scenes.md
 * "Forcing"):
 *   - the smooth keyframe blend is C^2 and stays within its keyframes; its rate is the
 *     derivative of its value (central differences);
 *   - a stiff tendon whose rest length follows keyframes: backward Euler's error against a
 *     tight CVODE reference falls at first order with dt under smooth keyframes and stays on a
 *     plateau (the free oscillation a slope jump starts) under linear ones;
 *   - gravity and point loads ramp smoothly from 0;
 *   - a point mass (`masses`) on a spring hangs m g / K below its rest position;
 *   - a flat drawstring cloth stays flat; `perturb` makes it buckle, reproducibly;
 *   - the power the forcing puts in is dU/dt at fixed x, and energy.csv's work_in closes the
 *     energy balance of an actuated, damped run under CVODE. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "harness.h"
#include "scene.h"
#include "solver.h"

static sw_model *parse(const char *text) {
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_parse("forcing.yaml", text, strlen(text), err, sizeof err);
  if (!m) print_error("%s\n", err);
  assert_non_null(m);
  return m;
}

/* ------------------------------------------------------------------ the blend */

/* Keyframes (0, 1), (1, 0.6), (3, 0.8): smooth is continuous with its first two derivatives
 * at and between the keyframes (one-sided differences agree), monotone between them, and its
 * rate is the derivative of its value. */
static void smooth_blend(void **st) {
  (void)st;
  const double kt[3] = {0.0, 1.0, 3.0}, kv[3] = {1.0, 0.6, 0.8};
  const double h = 1e-4;
  for (double t = -0.5; t <= 3.5; t += 0.0625) {
    double v = sw_keyframe_value(kt, kv, 3, SW_INTERP_SMOOTH, t);
    assert_true(v >= 0.6 - 1e-15 && v <= 1.0 + 1e-15);
    double vp = sw_keyframe_value(kt, kv, 3, SW_INTERP_SMOOTH, t + h);
    double vm = sw_keyframe_value(kt, kv, 3, SW_INTERP_SMOOTH, t - h);
    double r = sw_keyframe_rate(kt, kv, 3, SW_INTERP_SMOOTH, t);
    assert_true(fabs((vp - vm) / (2 * h) - r) < 1e-6); /* m/s */
    /* C^2: the second difference stays bounded (a slope jump would make it ~ jump / h) */
    assert_true(fabs(vp - 2 * v + vm) / (h * h) < 3.0);
  }
  const double knots[3] = {0.0, 1.0, 3.0};
  for (int k = 0; k < 3; k++) { /* at a keyframe: its value, zero rate */
    assert_float_equal(sw_keyframe_value(kt, kv, 3, SW_INTERP_SMOOTH, knots[k]), kv[k], 1e-15);
    assert_float_equal(sw_keyframe_rate(kt, kv, 3, SW_INTERP_SMOOTH, knots[k]), 0.0, 1e-15);
  }
  /* linear: the slope jumps from -0.4 to 0.1 m/s at t = 1 */
  assert_float_equal(sw_keyframe_rate(kt, kv, 3, SW_INTERP_LINEAR, 0.999), -0.4, 1e-15);
  assert_float_equal(sw_keyframe_rate(kt, kv, 3, SW_INTERP_LINEAR, 1.001), 0.1, 1e-15);
  assert_float_equal(sw_ramp(-1.0, 0.5), 0.0, 0.0);
  assert_float_equal(sw_ramp(0.25, 0.5), 0.5, 1e-15);
  assert_float_equal(sw_ramp(0.7, 0.5), 1.0, 0.0);
  assert_float_equal(sw_ramp(0.0, 0.0), 1.0, 0.0);
  assert_float_equal(sw_ramp_rate(0.25, 0.5), 30.0 / 16.0 / 0.5, 1e-14); /* 1/s */
}

/* ------------------------------------------------------------------ keyframe orders */

/* One 1 g mass on a 1e5 N/m tendon (omega = 1e4 rad/s: stiff at every dt tried, omega dt >= 12)
 * whose rest length goes 1 -> 0.99 -> 0.995 m at t = 0, 0.1, 0.2 s; no damping, no gravity. */
static sw_model *stiff_tendon(const char *interp, const char *method, double dt) {
  char text[1024];
  snprintf(text, sizeof text,
           "dimension: 2\n"
           "mesh: {points: [[0, 0], [1, 0]]}\n"
           "pins: [{select: {vertices: [0]}}]\n"
           "tendons: [{waypoints: [0, 1], law: spring, stiffness: 1e5, density: 2e-3,\n"
           "           rest_length: {keyframes: [[0, 1], [0.1, 0.99], [0.2, 0.995]],\n"
           "                         interpolation: %s}}]\n"
           "integrator: {method: %s, dt: %g, rtol: 1e-11, atol: 1e-13,\n"
           "             newton: {tol: 1e-12, max_iterations: 100}}\n"
           "duration: 0.3\n",
           interp, method, dt);
  return parse(text);
}

#define NSAMPLE 30 /* every 10 ms to 0.3 s */

/* x and v of the free vertex at the samples (every 10 ms), integrating with steps of dt. */
static void trajectory(sw_model *m, double dt, double *x, double *v) {
  const sw_integrator_ops *ops = sw_integrator_find(m->opt.method);
  assert_non_null(ops);
  sw_data *d = sw_data_new(m);
  char err[SW_ERRSZ];
  void *s = NULL;
  assert_int_equal(ops->init(&s, m, d, err, sizeof err), 0);
  int per = (int)lround(0.01 / dt);
  for (int k = 1; k <= NSAMPLE; k++) {
    for (int j = 1; j <= per; j++) {
      double end = 0.01 * (k - 1) + j * dt;
      int rc = ops->step(s, m, d, end - d->t);
      if (rc) print_error("%s: %s\n", ops->name, d->err);
      assert_int_equal(rc, 0);
      d->t = end;
    }
    x[k - 1] = d->x[2];
    v[k - 1] = d->v[2];
  }
  ops->free(s);
  sw_data_free(d);
}

/* Backward Euler at dt = 10, 5, 2.5, 1.25 ms against CVODE at rtol 1e-11: the largest position
 * error (m) and velocity error (m/s) over the samples. */
static void keyframe_errors(const char *interp, double ex[4], double ev[4]) {
  double xr[NSAMPLE], vr[NSAMPLE], x[NSAMPLE], v[NSAMPLE];
  sw_model *m = stiff_tendon(interp, "cvode", 0.01);
  m->opt.max_order = 5;
  trajectory(m, 0.01, xr, vr);
  sw_model_free(m);
  for (int k = 0; k < 4; k++) {
    double dt = 0.01 / (1 << k);
    m = stiff_tendon(interp, "backward-euler", dt);
    trajectory(m, dt, x, v);
    ex[k] = th_max_diff(x, xr, NSAMPLE);
    ev[k] = th_max_diff(v, vr, NSAMPLE);
    printf("  %-6s dt %.5f s: position error %.3e m, velocity error %.3e m/s\n", interp, dt,
           ex[k], ev[k]);
    sw_model_free(m);
  }
}

/* Measured: smooth 4.0e-8 .. 6.7e-9 m (order 0.86), 2.8e-2 .. 3.6e-3 m/s (order 0.99); linear
 * 1.222e-5 m and 0.1216 m/s at every dt: the free oscillations, of amplitude |the jump of the
 * rest length's slope| / omega at each keyframe (0.1, 0.15 and 0.05 m/s over 1e4 rad/s), that
 * the reference keeps and backward Euler damps out at omega dt >= 12. */
static void keyframe_orders(void **st) {
  (void)st;
  double xs[4], vs[4], xl[4], vl[4];
  const double h[4] = {0.01, 0.005, 0.0025, 0.00125};
  keyframe_errors("smooth", xs, vs);
  keyframe_errors("linear", xl, vl);
  assert_true(th_slope(h, xs, 4) > 0.75);
  assert_true(th_slope(h, vs, 4) > 0.9);
  assert_true(xs[0] >= 4.0 * xs[3] && vs[0] >= 4.0 * vs[3]);
  for (int k = 0; k < 4; k++) { /* the plateau */
    assert_true(fabs(xl[k] / xl[0] - 1.0) < 0.05 && fabs(vl[k] / vl[0] - 1.0) < 0.05);
    assert_true(xl[k] > 100.0 * xs[k]);
  }
}

/* ------------------------------------------------------------------ ramps */

/* gravity {vector, ramp} and a load's ramp scale their energy by the blend of t / T; a tendon's
 * keyframes are smooth unless told linear; bad keys are refused where they stand. */
static void ramps_and_keys(void **st) {
  (void)st;
  sw_model *m = parse("dimension: 2\n"
                      "mesh: {points: [[0, 0], [1, 0], [2, 0]]}\n"
                      "pins: [{select: {vertices: [0]}}]\n"
                      "gravity: {vector: [0, -10], ramp: 0.5}\n"
                      "tendons: [{waypoints: [0, 1, 2], stiffness: 0, density: 1,\n"
                      "           rest_length: {keyframes: [[0, 2], [1, 1]]}}]\n"
                      "loads: [{select: {vertices: [2]}, force: [4, 0], ramp: 2}]\n");
  assert_int_equal(m->tendon[0].interp, SW_INTERP_SMOOTH);
  assert_float_equal(m->gravity_ramp, 0.5, 0.0);
  sw_data *d = sw_data_new(m);
  double x[6] = {0, 0, 1, 1, 2, 1}, u;
  const double t[3] = {0.0, 0.25, 1.0};
  for (int k = 0; k < 3; k++) {
    assert_int_equal(sw_eval_terms(m, d, x, t[k], 0, 0, 0, &u), 0);
    /* gravity: -r(t) g.x summed (masses 0.5, 1, 0.5 kg at y = 0, 1, 1); the load on x = 2 */
    double want = sw_ramp(t[k], 0.5) * 10.0 * 1.5 - sw_ramp(t[k], 2.0) * 4.0 * 2.0;
    assert_float_equal(u, want, 1e-12);
  }
  assert_float_equal(sw_ramp(0.25, 0.5), 0.5, 1e-15);
  sw_data_free(d);
  sw_model_free(m);
  static const struct { const char *text; int line, col; const char *what; } bad[] = {
      {"dimension: 2\nmesh: {points: [[0, 0], [1, 0]]}\n"
       "tendons: [{waypoints: [0, 1], stiffness: 1, density: 1,\n"
       "           rest_length: {relative: 1, interpolation: smooth}}]\n", 4, 54, "without"},
      {"dimension: 2\nmesh: {points: [[0, 0], [1, 0]]}\n"
       "tendons: [{waypoints: [0, 1], stiffness: 1, density: 1,\n"
       "           rest_length: {keyframes: [[0, 1]], interpolation: cubic}}]\n", 4, 62,
       "linear"},
      {"dimension: 2\nmesh: {points: [[0, 0], [1, 0]]}\ngravity: {vector: [0, -1], ramp: -1}\n",
       3, 34, "ramp"},
      {"dimension: 2\nmesh: {points: [[0, 0], [1, 0]]}\ngravity: {ramp: 1}\n", 3, 10,
       "vector"},
      {"dimension: 2\nmesh: {points: [[0, 0], [1, 0]]}\n"
       "loads: [{select: {vertices: [1]}, force: [1, 0], ramp: 1},\n"
       "        {select: {vertices: [1]}, force: [1, 0], ramp: 2}]\n", 4, 56, "one ramp time"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    char err[SW_ERRSZ], want[64];
    sw_model *b = sw_scene_parse("bad.yaml", bad[k].text, strlen(bad[k].text), err, sizeof err);
    if (b || !strstr(err, bad[k].what)) print_error("case %zu: %s\n", k, b ? "loaded" : err);
    assert_null(b);
    snprintf(want, sizeof want, "bad.yaml:%d:%d: ", bad[k].line, bad[k].col);
    if (strncmp(err, want, strlen(want))) print_error("case %zu: %s\n", k, err);
    assert_true(!strncmp(err, want, strlen(want)));
  }
}

/* ------------------------------------------------------------------ point masses */

/* A 0.25 kg point mass on a massless 100 N/m spring (a tendon) under g = 9.81 m/s^2 hangs
 * m g / K = 24.525 mm below the spring's rest position; two items on one vertex add up. */
static void point_mass_hangs(void **st) {
  (void)st;
  sw_model *m = parse("dimension: 2\n"
                      "mesh: {points: [[0, 0], [0, -0.5]]}\n"
                      "pins: [{select: {vertices: [0]}}]\n"
                      "gravity: [0, -9.81]\n"
                      "tendons: [{waypoints: [0, 1], law: spring, stiffness: 100}]\n"
                      "masses: [{select: {vertices: [1]}, mass: 0.125},\n"
                      "         {select: {box: [[-1, -1], [1, -0.4]]}, mass: 0.125}]\n"
                      "integrator: {method: static}\n");
  assert_float_equal(m->mass[1], 0.25, 1e-15);
  assert_float_equal(m->total_mass, 0.25, 1e-15);
  sw_data *d = sw_data_new(m);
  double reaction[3];
  char err[SW_ERRSZ];
  int rc = sw_static_solve(m, d, reaction, err, sizeof err);
  if (rc) print_error("%s\n", err);
  assert_int_equal(rc, 0);
  assert_float_equal(d->x[3], -0.5 - 0.024525, 1e-12); /* m */
  assert_float_equal(d->x[2], 0.0, 1e-15);
  sw_data_free(d);
  sw_model_free(m);
  const char *bad = "dimension: 2\nmesh: {points: [[0, 0]]}\nmasses: [{select: {vertices: [0]}, "
                    "mass: -1}]\n";
  char e[SW_ERRSZ];
  assert_null(sw_scene_parse("bad.yaml", bad, strlen(bad), e, sizeof e));
  assert_non_null(strstr(e, "bad.yaml:3:42: masses[0] mass is -1"));
}

/* ------------------------------------------------------------------ perturbation */

/* scenes/cloth_drawstring.yaml for 0.5 s with backward Euler at its 10 ms; the largest |y| (m)
 * over the vertices at the end, and x (nv x 3) into xout. */
static double drawstring_y(double amplitude, unsigned long seed, double *xout) {
  char err[SW_ERRSZ];
  sw_model *m = th_scene_file("scenes/cloth_drawstring.yaml");
  assert_non_null(m);
  if (amplitude != m->perturb_amplitude || seed != m->perturb_seed) { /* again, perturbed anew */
    sw_model_free(m);
    char text[8192];
    FILE *f = fopen("scenes/cloth_drawstring.yaml", "rb");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    const char *shipped = "perturb: {amplitude: 0.001, seed: 1}";
    char *p = strstr(text, shipped), repl[64];
    assert_non_null(p);
    int k = snprintf(repl, sizeof repl, "perturb: {amplitude: %.17g, seed: %lu}", amplitude,
                     seed);
    size_t was = strlen(shipped);
    memmove(p + k, p + was, strlen(p + was) + 1);
    memcpy(p, repl, (size_t)k);
    if (amplitude == 0.0) memcpy(p, "#", 1); /* no perturbation at all */
    m = sw_scene_parse("drawstring.yaml", text, strlen(text), err, sizeof err);
    if (!m) print_error("%s\n", err);
    assert_non_null(m);
  }
  const sw_integrator_ops *ops = sw_integrator_find(m->opt.method);
  sw_data *d = sw_data_new(m);
  void *s = NULL;
  assert_int_equal(ops->init(&s, m, d, err, sizeof err), 0);
  for (int k = 1; k <= 50; k++) {
    int rc = ops->step(s, m, d, 0.01 * k - d->t);
    if (rc) print_error("step %d: %s\n", k, d->err);
    assert_int_equal(rc, 0);
    d->t = 0.01 * k;
  }
  double ymax = 0.0;
  for (int i = 0; i < m->nv; i++) ymax = fmax(ymax, fabs(d->x[3 * i + 1]));
  memcpy(xout, d->x, (size_t)m->nv * 3 * sizeof(double));
  ops->free(s);
  sw_data_free(d);
  sw_model_free(m);
  return ymax;
}

/* The flat drawstring cloth (plane xz) never leaves its plane: y stays exactly 0.  With the
 * shipped 1 mm perturbation it buckles: |y| grows to ~6 cm in 0.5 s (measured 0.058 m), the
 * same bit for bit with the same seed, differently with another. */
static void perturbation_buckles(void **st) {
  (void)st;
  enum { NV = 441 };
  static double x0[NV * 3], x1[NV * 3], x2[NV * 3], x3[NV * 3];
  assert_true(drawstring_y(0.0, 0, x0) == 0.0);
  double y1 = drawstring_y(0.001, 1, x1), y2 = drawstring_y(0.001, 1, x2);
  printf("  max |y| at 0.5 s: %.4g m (flat: 0)\n", y1);
  assert_true(y1 > 0.01); /* 10x the amplitude: out of the plane, not just the noise */
  assert_memory_equal(x1, x2, sizeof x1);
  assert_true(y2 == y1);
  drawstring_y(0.001, 2, x3);
  assert_true(th_max_diff(x1, x3, NV * 3) > 1e-4);
  const char *bad = "dimension: 2\nmesh: {points: [[0, 0]]}\nperturb: {amplitude: 0.1}\n";
  char e[SW_ERRSZ];
  assert_null(sw_scene_parse("bad.yaml", bad, strlen(bad), e, sizeof e));
  assert_non_null(strstr(e, "bad.yaml:3:10: perturb is given in a 2D scene"));
}

/* ------------------------------------------------------------------ actuation work */

/* A 2D 5 x 5 membrane hung by its top row, with a tendon (keyframed, smooth) through its
 * middle column, gravity ramped over 0.3 s, a load ramped over 0.5 s, mass damping. */
static const char *actuated_scene =
    "dimension: 2\n"
    "mesh: {grid: {size: [0.4, 0.4], vertices: [5, 5]}}\n"
    "material: {density: 0.2, membrane: {model: bw98, k_u: 200, k_v: 200, k_shear: 20}}\n"
    "pins: [{select: {box: [[-1, 0.39], [1, 1]]}}]\n"
    "gravity: {vector: [0, -9.81], ramp: 0.3}\n"
    "loads: [{select: {box: [[0.39, -1], [1, 0.01]]}, force: [0.05, 0], ramp: 0.5}]\n"
    "damping: {mass: 0.5}\n"
    "tendons: [{waypoints: {box: [[0.19, -1], [0.21, 1]]}, law: spring, stiffness: 100,\n"
    "           rest_length: {keyframes: [[0, 1], [0.4, 0.8], [0.7, 0.9]], relative: true}}]\n"
    "integrator: {method: cvode, dt: 0.001, rtol: 1e-10, atol: 1e-12}\n"
    "duration: 1.0\n";

/* sw_actuation_power is dU/dt at fixed x: central differences of the energy in t. */
static void actuation_power_is_dudt(void **st) {
  (void)st;
  sw_model *m = parse(actuated_scene);
  assert_true(sw_actuated(m));
  sw_data *d = sw_data_new(m);
  unsigned long seed = 5;
  double *x = calloc((size_t)m->nv * 2, sizeof(double));
  for (int i = 0; i < m->nv * 2; i++) x[i] = m->x0[i] + 0.01 * th_rand(&seed);
  const double ts[4] = {0.1, 0.25, 0.45, 0.6}, h = 1e-6;
  for (int k = 0; k < 4; k++) {
    double up, um;
    assert_int_equal(sw_eval_terms(m, d, x, ts[k] + h, 0, 0, 0, &up), 0);
    assert_int_equal(sw_eval_terms(m, d, x, ts[k] - h, 0, 0, 0, &um), 0);
    double p = sw_actuation_power(m, x, ts[k]), fd = (up - um) / (2 * h); /* W */
    assert_true(fabs(p - fd) < 1e-6 * (fabs(p) + 1e-3));
  }
  assert_float_equal(sw_actuation_power(m, x, 2.0), 0.0, 0.0); /* all forcing done */
  free(x);
  sw_data_free(d);
  sw_model_free(m);
}

/* Column `name` of every line of energy.csv into col (at most max); the number of lines. */
static int energy_column(const char *dir, const char *name, double *col, int max) {
  char path[512], line[8192];
  snprintf(path, sizeof path, "%s/energy.csv", dir);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  assert_non_null(fgets(line, sizeof line, f));
  int at = -1, c = 0;
  for (char *tok = strtok(line, ",\n"); tok; tok = strtok(NULL, ",\n"), c++)
    if (!strcmp(tok, name)) at = c;
  if (at < 0) print_error("energy.csv has no column %s\n", name);
  assert_true(at >= 0);
  int n = 0;
  while (n < max && fgets(line, sizeof line, f)) {
    char *p = line;
    for (int k = 0; k < at; k++) p = strchr(p, ',') + 1;
    col[n++] = strtod(p, NULL);
  }
  fclose(f);
  return n;
}

/* With CVODE at rtol 1e-10, kinetic + potential + dissipated - work_in stays at its initial
 * value to the trapezoid rule's accuracy on the 1 ms logs, while the work in is ~0.1 J. */
static void energy_balance_with_actuation(void **st) {
  (void)st;
  sw_model *m = parse(actuated_scene);
  char err[SW_ERRSZ];
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "/tmp/sinew_test_forcing_%d", (int)getpid());
  int rc = sw_run(m, 0, err, sizeof err);
  if (rc) print_error("%s\n", err);
  assert_int_equal(rc, 0);
  enum { N = 1001 };
  static double total[N + 1], diss[N + 1], work[N + 1];
  const char *dir = m->opt.out_dir;
  int n = energy_column(dir, "total", total, N + 1);
  assert_int_equal(n, N);
  assert_int_equal(energy_column(dir, "dissipated", diss, N + 1), N);
  assert_int_equal(energy_column(dir, "work_in", work, N + 1), N);
  double drift = 0.0, wmax = 0.0, emax = 0.0;
  for (int k = 0; k < N; k++) {
    drift = fmax(drift, fabs(total[k] + diss[k] - work[k] - total[0])); /* J */
    wmax = fmax(wmax, fabs(work[k]));
    emax = fmax(emax, fabs(total[k] + diss[k] - total[0]));
  }
  printf("  work in up to %.4g J; K + U + dissipated moves %.4g J; minus the work: %.3g J\n",
         wmax, emax, drift);
  assert_true(wmax > 1e-2);
  assert_true(drift < 2e-5 * wmax); /* measured 3.7e-6: the trapezoid rule on 1 ms logs */
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(smooth_blend),
      cmocka_unit_test(keyframe_orders),
      cmocka_unit_test(ramps_and_keys),
      cmocka_unit_test(point_mass_hangs),
      cmocka_unit_test(perturbation_buckles),
      cmocka_unit_test(actuation_power_is_dudt),
      cmocka_unit_test(energy_balance_with_actuation),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
