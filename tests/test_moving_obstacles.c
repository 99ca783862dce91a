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
 *    intersects it at any step; a Newton failure at the box (8 iterations, 2 halvings) names it,
 *    a vertex over it and the time; and a mesh box turning 90 degrees about z under a cloth lying
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

/* Run m step by step; after each step call check(d, x_n, t_n, x_{n+1}, t_{n+1}), or (a step
 * the solver halved: the path between is not one straight motion) check(d, x_{n+1}, t_{n+1},
 * x_{n+1}, t_{n+1}).  The last state into xe (nv x 3), its time into *te.  Returns 0 when the
 * run ends ok, else 1 with err holding the failure; *whole counts the steps taken whole. */
typedef void (*step_check)(const sw_model *m, const sw_data *d, const double *x0, double t0,
                           const double *x1, double t1, void *arg);
static int run_checked(sw_model *m, double duration, step_check check, void *arg, char *err,
                       double *xe, double *te, int *whole) {
  sw_sim *s = sw_sim_new(m, 0, err, SW_ERRSZ);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  size_t nd = (size_t)m->nv * 3;
  double *x0 = malloc(nd * sizeof(double));
  int rc = 0;
  *whole = 0;
  while (d->t < duration - 1e-9) {
    memcpy(x0, d->x, nd * sizeof(double));
    double t0 = d->t;
    long n0 = d->nstep;
    if ((rc = sw_sim_step(s, err, SW_ERRSZ)) != 0) break;
    if (d->nstep == n0 + 1) ++*whole, check(m, d, x0, t0, d->x, d->t, arg);
    else check(m, d, d->x, d->t, d->x, d->t, arg); /* halved: its end state only */
  }
  if (xe) memcpy(xe, d->x, nd * sizeof(double));
  if (te) *te = d->t;
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

static void sphere_check(const sw_model *m, const sw_data *d, const double *x0, double t0,
                         const double *x1, double t1, void *arg) {
  sphere_arg *a = arg;
  (void)d;
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
      double x[75], t;
      int whole, failed = run_checked(m, 0.12, sphere_check, &a, err, x, &t, &whole);
      if (failed) { /* the alternative to carrying it: a failed run (never ok), its last state
                     * outside the sphere */
        print_message("dt %g %s: failed: %s\n", dts[k], smooth ? "smooth" : "linear", err);
        assert_non_null(strstr(err, "obstacles[0]")); /* names the obstacle and the time */
        sphere_check(m, NULL, x, t, x, t, &a);
      } else {
        /* carried: the middle vertex above the sphere's top, none below its bottom */
        int above = 0;
        double cz = sphere_z(&a, t);
        for (int i = 0; i < m->nv; i++) above += x[3 * i + 2] > cz - 0.2;
        print_message("dt %g %s: ok, the middle vertex %.3g m above the sphere's top, %d of 25 "
                      "above its bottom, %d whole steps checked along the path, deepest sample "
                      "%.3g m\n", dts[k], smooth ? "smooth" : "linear",
                      x[3 * 12 + 2] - cz - 0.2, above, whole, a.worst);
        assert_true(x[3 * 12 + 2] > cz + 0.2);
        assert_int_equal(above, 25);
      }
      sw_model_free(m);
    }
}

/* ---------------------------------------------------------------------- turning capsule */

/* The capsule arm from (0.5, -0.25, 0.3) to (0.5 + 0.45 cos a, -0.25 + 0.45 sin a, 0.3), r
 * 0.03, a = pi blend(t / 0.1): the scene's rotation about z through (0.5, -0.25, 0.3). */
static double arm_angle(double t) { return M_PI * blend(t / 0.1); }

static void arm_check(const sw_model *m, const sw_data *d, const double *x0, double t0,
                      const double *x1, double t1, void *arg) {
  double *worst = arg;
  (void)d;
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
    int whole, failed = run_checked(m, 0.12, arm_check, &worst, err, NULL, NULL, &whole);
    print_message("arm dt %g: %s (deepest sample %.3g m)\n", dts[k], failed ? err : "ok", worst);
    if (failed) assert_non_null(strstr(err, "obstacles[0]"));
    sw_model_free(m);
  }
}

/* ------------------------------------------------------------------------ mesh obstacles */

static char dir[64]; /* the mesh tests' folder: scene.yaml's OBJ paths are relative to it */

/* An axis-aligned box lo..hi as 12 triangles wound outwards, into dir/name. */
static void write_box(const char *name, const double lo[3], const double hi[3]) {
  char path[128];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  for (int k = 0; k < 8; k++)
    fprintf(f, "v %.17g %.17g %.17g\n", k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1],
            k & 4 ? hi[2] : lo[2]);
  static const int fc[12][3] = {{1, 3, 4}, {1, 4, 2}, {5, 6, 8}, {5, 8, 7}, {1, 2, 6}, {1, 6, 5},
                                {3, 7, 8}, {3, 8, 4}, {1, 5, 7}, {1, 7, 3}, {2, 4, 8}, {2, 8, 6}};
  for (int k = 0; k < 12; k++) fprintf(f, "f %d %d %d\n", fc[k][0], fc[k][1], fc[k][2]);
  fclose(f);
}

static sw_model *scene_in_dir(const char *text) {
  char name[128];
  snprintf(name, sizeof name, "%s/scene.yaml", dir);
  return th_scene(name, text);
}

/* After each step: no cloth triangle intersects the box (exact), and (whole steps, the box
 * translating linearly) no vertex's straight path relative to the box crosses one of its
 * triangles (exact segment-triangle test at the box's stated place). */
static void mesh_check(const sw_model *m, const sw_data *d, const double *x0, double t0,
                       const double *x1, double t1, void *arg) {
  (void)arg;
  assert_int_equal(sw_mcontact_obstacle_intersections(m, d->mc, d->x, d->t, NULL), 0);
  if (x0 == x1) return;
  const sw_obstacle *o = &m->mesh_obstacle[0];
  double d0[3], d1[3];
  sw_obstacle_disp(o, t0, d0);
  sw_obstacle_disp(o, t1, d1);
  for (int i = 0; i < m->nv; i++) {
    double p[3], q[3];
    for (int c = 0; c < 3; c++) p[c] = x0[3 * i + c] - d0[c], q[c] = x1[3 * i + c] - d1[c];
    for (int f = 0; f < o->mesh_nf; f++) {
      const int *v = o->mesh_face + 3 * f;
      assert_false(sw_segment_triangle_intersect(p, q, o->mesh_x + 3 * v[0], o->mesh_x + 3 * v[1],
                                                 o->mesh_x + 3 * v[2]));
    }
  }
}

/* A mesh box (0.3 m) rising 1 m in 0.05 s through a 0.6 m cloth, linear keyframes; the third
 * run (8 Newton iterations, 2 halvings) fails in Newton, its message naming the box. */
static void rising_mesh_box(void **st) {
  (void)st;
  const double lo[3] = {0.15, 0.15, -0.4}, hi[3] = {0.45, 0.45, -0.1}, dts[] = {0.05, 0.02, 0.05};
  const int halvings[] = {8, 8, 2}, iters[] = {50, 50, 8};
  write_box("box.obj", lo, hi);
  for (int k = 0; k < 3; k++) {
    char text[1024], err[SW_ERRSZ];
    snprintf(text, sizeof text,
             "dimension: 3\nmesh: {grid: {size: [0.6, 0.6], vertices: [7, 7], plane: xy}}\n"
             "material: {density: 0.1, membrane: {model: bw98, k_u: 2000, k_v: 2000, "
             "k_shear: 50}}\ngravity: [0, 0, -9.81]\n"
             "obstacles: [{mesh: box.obj, motion: {keyframes: [[0, 0, 0, 0], [0.05, 0, 0, 1]], "
             "interpolation: linear}}]\n"
             "integrator: {method: backward-euler, dt: %g, max_halvings: %d, newton: {max_iterations: "
             "%d}}\nduration: 0.06\n",
             dts[k], halvings[k], iters[k]);
    sw_model *m = scene_in_dir(text);
    assert_non_null(m);
    double *x = malloc((size_t)m->nv * 3 * sizeof(double));
    int whole, failed = run_checked(m, 0.06, mesh_check, NULL, err, x, NULL, &whole);
    double top = 1.0 - 0.1, zmid = x[3 * 24 + 2]; /* the box's top at the end */
    print_message("mesh box dt %g: %s (%d whole steps checked), middle vertex at z = %.3g (box "
                  "top %.3g)\n", dts[k], failed ? err : "ok", whole, zmid, top);
    if (failed) assert_non_null(strstr(err, "obstacles[0]") ? err : strstr(err, "Newton"));
    else assert_true(zmid > top);
    if (k == 2) { /* Newton stopped by the box: the message names it, the vertex and the time */
      const char *h = strstr(err, "obstacles[0] held vertex ");
      int iv = -1;
      double t = -1.0;
      assert_true(failed && strstr(err, "Newton did not converge") && h);
      assert_int_equal(sscanf(h, "obstacles[0] held vertex %d to %*g of an update at t = %lg",
                              &iv, &t), 2);
      assert_true(iv >= 0 && iv < m->nv && t > 0.0 && t < 0.05);
      for (int a = 0; a < 2; a++) /* a vertex over the box (the grid's spacing 0.1 m) */
        assert_true(m->x0[3 * iv + a] > lo[a] - 0.1 && m->x0[3 * iv + a] < hi[a] + 0.1);
    }
    free(x);
    sw_model_free(m);
  }
}

static void turn_check(const sw_model *m, const sw_data *d, const double *x0, double t0,
                       const double *x1, double t1, void *arg) {
  (void)x0, (void)t0, (void)x1, (void)t1;
  assert_int_equal(sw_mcontact_obstacle_intersections(m, d->mc, d->x, d->t, NULL), 0);
  long *a = arg; /* steps, tries (halvings too), refits of the obstacle's tree */
  a[0] = d->nstep, a[1] = d->nstep + d->nretry, a[2] = sw_mcontact_refits(d->mc);
}

/* A cloth lying on a mesh box that turns 90 degrees about z in 0.2 s (smooth): no cloth
 * triangle ever intersects the box, and the cloth stays on its top. */
static void turning_mesh_box(void **st) {
  (void)st;
  const double lo[3] = {-0.15, -0.15, -0.3}, hi[3] = {0.45, 0.45, -0.0015};
  write_box("turn.obj", lo, hi);
  char err[SW_ERRSZ];
  sw_model *m = scene_in_dir(
      "dimension: 3\nmesh: {grid: {size: [0.3, 0.3], vertices: [7, 7], plane: xy}}\n"
      "material: {density: 0.1, membrane: {model: bw98, k_u: 2000, k_v: 2000, k_shear: 50}}\n"
      "gravity: [0, 0, -9.81]\n"
      "obstacles: [{mesh: turn.obj, motion: {rotation: {axis: [0, 0, 1], center: [0.15, 0.15, 0],"
      " keyframes: [[0, 0], [0.2, 90]]}}}]\n"
      "integrator: {method: backward-euler, dt: 0.01}\nduration: 0.25\n");
  assert_non_null(m);
  double x[147];
  long count[3] = {0, 0, 0};
  int whole, rc = run_checked(m, 0.25, turn_check, count, err, x, NULL, &whole);
  if (rc) print_error("%s\n", err);
  assert_int_equal(rc, 0);
  print_message("turning mesh box: %ld steps, %ld refits of its tree\n", count[0], count[2]);
  assert_true(count[2] > 0 && count[2] <= count[1]); /* once a step, not per evaluation */
  double zmin = INFINITY;
  for (int i = 0; i < m->nv; i++) zmin = fmin(zmin, x[3 * i + 2]);
  print_message("turning mesh box: ok, lowest vertex z = %.3g m (top at -0.0015)\n", zmin);
  assert_true(zmin > -0.0015);
  sw_model_free(m);
}

static int setup(void **st) {
  (void)st;
  snprintf(dir, sizeof dir, "/tmp/sinew_moving_XXXXXX");
  return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **st) {
  (void)st;
  th_remove_tree(dir);
  return 0;
}

/* ------------------------------------------------------------------ rotation keys */

/* A box turned 90 degrees about z through (1, 0, 0) and moved up 1: its distance, normal and
 * the carry of a point against the test's own rotation; and the keys' errors with their place. */
static void rotation_keys(void **st) {
  (void)st;
  sw_model *m = th_scene("rot.yaml",
      "dimension: 3\nmesh: {points: [[0, 0, 5]]}\npins: [{select: {vertices: [0]}}]\n"
      "obstacles: [{shape: box, center: [2, 0, 0], size: [2, 0.5, 0.5], motion: {keyframes: "
      "[[0, 0, 0, 0], [1, 0, 0, 1]], rotation: {axis: [0, 0, 2], center: [1, 0, 0], keyframes: "
      "[[0, 0], [1, 90]]}, interpolation: linear}}]\n");
  assert_non_null(m);
  const sw_obstacle *o = &m->obstacle[0];
  /* at t = 1 the box's long side lies along y from (1, 0, 1) to (1, 2, 1): a point at
   * (1.6, 1, 1) is 0.6 from the axis, 0.35 beyond the face x = 1.25 */
  double p[3] = {1.6, 1.0, 1.0}, n[3], H[9];
  double phi = sw_obstacle_sdf(o, 3, 1.0, p, n, H);
  assert_true(fabs(phi - 0.35) < 1e-12);
  assert_true(fabs(n[0] - 1.0) < 1e-12 && fabs(n[1]) < 1e-12 && fabs(n[2]) < 1e-12);
  /* halfway (45 degrees, up 0.5): the body point (3, 0, 0) (the far end of the axis) */
  double q[3] = {3.0, 0.0, 0.0}, w[3], c = sqrt(0.5);
  sw_obstacle_place(o, 0.5, q, w);
  assert_true(fabs(w[0] - (1 + 2 * c)) < 1e-12 && fabs(w[1] - 2 * c) < 1e-12 &&
              fabs(w[2] - 0.5) < 1e-12);
  double back[3];
  sw_obstacle_carry(o, 0.5, 0.0, w, back); /* carried back to the start */
  for (int a = 0; a < 3; a++) assert_true(fabs(back[a] - q[a]) < 1e-12);
  sw_model_free(m);
  const struct { const char *text, *want; } bad[] = {
      {"dimension: 3\nmesh: {points: [[0, 0, 5]]}\npins: [{select: {vertices: [0]}}]\nobstacles: [{shape: sphere, center: [0, 0, 0], "
       "radius: 1, motion: {rotation: {center: [0, 0, 0], keyframes: [[0, 0]]}}}]\n",
       "rot.yaml:4:78: obstacles[0] motion rotation has no 'axis'"},
      {"dimension: 3\nmesh: {points: [[0, 0, 5]]}\npins: [{select: {vertices: [0]}}]\nobstacles: [{shape: sphere, center: [0, 0, 0], "
       "radius: 1, motion: {rotation: {axis: [0, 0, 0], center: [0, 0, 0], keyframes: [[0, 0]]}}}]\n",
       "axis is zero"},
      {"dimension: 3\nmesh: {points: [[0, 0, 5]]}\npins: [{select: {vertices: [0]}}]\nobstacles: [{shape: sphere, center: [0, 0, 0], "
       "radius: 1, motion: {rotation: {axis: [0, 0, 1], center: [0, 0, 0], keyframes: [[1, 0], "
       "[0, 5]]}}}]\n", "expected increasing times"},
      {"dimension: 3\nmesh: {points: [[0, 0, 5]]}\npins: [{select: {vertices: [0]}}]\nobstacles: [{shape: sphere, center: [0, 0, 0], "
       "radius: 1, motion: {interpolation: linear}}]\n", "has neither keyframes nor rotation"},
      {"dimension: 2\nmesh: {points: [[0, 5]]}\npins: [{select: {vertices: [0]}}]\nobstacles: [{shape: sphere, center: [0, 0], "
       "radius: 1, motion: {rotation: {axis: [0, 0, 1], center: [0, 0], keyframes: [[0, 0]]}}}]\n",
       "axis is given in a 2D scene"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    char err[SW_ERRSZ];
    sw_model *b = sw_scene_parse("rot.yaml", bad[k].text, strlen(bad[k].text), err, sizeof err);
    if (b || !strstr(err, bad[k].want)) print_error("case %zu: %s\n", k, err);
    assert_null(b);
    assert_non_null(strstr(err, bad[k].want));
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(rotation_keys),
      cmocka_unit_test(rising_sphere),
      cmocka_unit_test(turning_capsule),
      cmocka_unit_test(rising_mesh_box),
      cmocka_unit_test(turning_mesh_box),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
