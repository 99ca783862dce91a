/* test_contact.c — contact with obstacles (models/obstacle.c, models/contact.c,
 * docs/contact.md):
 *   - the barrier's derivatives, and the contact term's gradient and Hessian against central
 *     differences for every shape (2D and 3D), near faces, edges, corners and end caps;
 *   - friction's gradient and Hessian at slips below and above the smoothing scale;
 *   - conservative advancement never lets a point get closer than it allows;
 *   - a cloth dropped on a sphere never enters it (every vertex at every step, measured by the
 *     test's own distance) and comes to rest with the total force of the sphere on it equal
 *     to its weight to 1e-6;
 *   - a cloth on an inclined plane sticks for tan(theta) < mu and slides with acceleration
 *     g (sin theta - mu cos theta) for tan(theta) > mu;
 *   - a scene without obstacles builds no contact term; scene errors name the place;
 *   - the drape on a mesh sphere and a floor takes few line-search halvings a step. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "contact.h"
#include "harness.h"
#include "scene.h"
#include "solver.h"

static sw_model *parse(const char *text) {
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_parse("contact.yaml", text, strlen(text), err, sizeof err);
  if (!m) print_error("%s\n", err);
  assert_non_null(m);
  return m;
}

/* The barrier's first and second derivatives against central differences. */
static void barrier_derivatives(void **st) {
  (void)st;
  const double dhat = 1e-3;
  for (double d = 0.01 * dhat; d < dhat; d += 0.07 * dhat) {
    double db, d2b, dbp, dbm, d2;
    double h = 1e-6 * d;
    double bp = sw_contact_barrier(d + h, dhat, &dbp, &d2);
    double bm = sw_contact_barrier(d - h, dhat, &dbm, &d2);
    assert_true(sw_contact_barrier(d, dhat, &db, &d2b) > 0.0);
    assert_true(db < 0.0 && d2b > 0.0); /* repulsive and convex */
    assert_true(fabs((bp - bm) / (2 * h) - db) < 1e-6 * fabs(db));
    assert_true(fabs((dbp - dbm) / (2 * h) - d2b) < 1e-5 * d2b);
  }
  double db, d2b;
  assert_true(sw_contact_barrier(dhat, dhat, &db, &d2b) == 0.0 && db == 0.0 && d2b == 0.0);
  assert_true(isinf(sw_contact_barrier(0.0, dhat, &db, &d2b)));
}

/* A points scene: one obstacle, nine points of 0.1 kg each at the given positions. */
static sw_model *points_scene(int dim, const char *obstacle, const double *p, int n) {
  char text[4096], pts[2048] = "";
  size_t len = 0;
  for (int i = 0; i < n; i++)
    len += (size_t)snprintf(pts + len, sizeof pts - len, dim == 3 ? "%s[%.17g, %.17g, %.17g]"
                            : "%s[%.17g, %.17g]", i ? ", " : "", p[i * dim], p[i * dim + 1],
                            dim == 3 ? p[i * dim + 2] : 0.0);
  snprintf(text, sizeof text,
           "dimension: %d\nmesh: {points: [%s]}\n"
           "masses: [{select: {box: %s}, mass: 0.1}]\n"
           "obstacles: [%s]\ncontact: {distance: 1e-3, friction: 0.4}\n",
           dim, pts, dim == 3 ? "[[-9, -9, -9], [9, 9, 9]]" : "[[-9, -9], [9, 9]]", obstacle);
  return parse(text);
}

/* Points within the barrier's range of each shape (faces, edges, corners, end caps): the
 * term's gradient and Hessian against central differences, symmetric, filtered PSD. */
static void obstacle_conformance(void **st) {
  (void)st;
  const char *shapes[2][4] = {
      {"{shape: plane, point: [0, 0], normal: [0.3, 1.0]}",
       "{shape: sphere, center: [0, -0.5], radius: 0.5}",
       "{shape: capsule, ends: [[-0.2, -0.3], [0.2, -0.3]], radius: 0.3}",
       "{shape: box, center: [0, -0.25], size: [0.4, 0.5]}"},
      {"{shape: plane, point: [0, 0, 0], normal: [0.3, 0.4, 1.0]}",
       "{shape: sphere, center: [0, 0, -0.5], radius: 0.5}",
       "{shape: capsule, ends: [[-0.2, 0, -0.3], [0.2, 0, -0.3]], radius: 0.3}",
       "{shape: box, center: [0, 0, -0.25], size: [0.4, 0.4, 0.5]}"}};
  /* above the middle of each, and off toward an edge, corner or end cap; then moved along
   * the normal to the distance off[i][2] */
  const double off[][3] = {{0.0, 0.0, 3e-4}, {0.15, 0.0, 5e-4}, {0.2003, 0.0, 2e-4},
                           {0.2004, 0.2002, 3e-4}, {-0.2001, 0.1, 6e-4}};
  for (int dim = 2; dim <= 3; dim++)
    for (int s = 0; s < 4; s++) {
      const char *shape = shapes[dim - 2][s];
      double p[5 * 3];
      sw_model *m0 = points_scene(dim, shape, (double[]){0, 0.5, 0.5}, 1);
      for (int i = 0; i < 5; i++) {
        double q[3] = {off[i][0], dim == 3 ? off[i][1] : 0.5, 0.5}, n[3];
        for (int it = 0; it < 50; it++) {
          double dd = sw_obstacle_sdf(&m0->obstacle[0], dim, 0.0, q, n, NULL);
          for (int a = 0; a < dim; a++) q[a] += (off[i][2] - dd) * n[a];
        }
        assert_true(fabs(sw_obstacle_sdf(&m0->obstacle[0], dim, 0.0, q, n, NULL) - off[i][2]) <
                    1e-12);
        memcpy(p + i * dim, q, (size_t)dim * sizeof(double));
      }
      sw_model_free(m0);
      sw_model *m = points_scene(dim, shape, p, 5);
      th_conformance_at(m, "contact", 0, 1e-3, m->x0);
      sw_model_free(m);
    }
}

/* Friction's gradient and Hessian (its energy for a step lagged at x0) against central
 * differences, with slips below and above eps_v h. */
static void friction_derivatives(void **st) {
  (void)st;
  const double p[6] = {0.0, 0.0, 4e-4, 0.3, 0.1, 6e-4};
  sw_model *m = points_scene(3, "{shape: sphere, center: [0, 0, -1], radius: 1}", p, 2);
  sw_data *d = sw_data_new(m);
  double y[6];
  memcpy(y, d->x, sizeof y);
  assert_int_equal(sw_contact_begin(m, d, 0.01, 0.01, y), SW_OK); /* eps = 1e-5 m */
  const double slip[2] = {3e-6, 4e-5};
  for (int k = 0; k < 2; k++) {
    double x[6];
    for (int i = 0; i < 6; i++) x[i] = p[i] + slip[k] * (i % 3 == 0 ? 0.8 : i % 3 == 1 ? -0.6 : 0.1);
    const sw_term *t = &m->term[m->nterm - 1];
    double g[6] = {0}, H[18] = {0}, e, gp[6], gm[6];
    sw_eval ev = {.t = 0.01, .x = x, .grad = g, .hess = H, .lag = d->lag};
    assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
    const double h = 1e-8; /* m: d changes by only n_x h, near the round-off of d itself */
    for (int c = 0; c < 6; c++) {
      double xp[6], ep, em;
      memcpy(xp, x, sizeof xp);
      memset(gp, 0, sizeof gp), memset(gm, 0, sizeof gm);
      xp[c] += h;
      sw_eval e1 = {.t = 0.01, .x = xp, .grad = gp, .lag = d->lag};
      t->ops->eval(t, m, &e1, &ep);
      xp[c] -= 2 * h;
      sw_eval e2 = {.t = 0.01, .x = xp, .grad = gm, .lag = d->lag};
      t->ops->eval(t, m, &e2, &em);
      assert_true(fabs((ep - em) / (2 * h) - g[c]) < 1e-5 * (fabs(g[c]) + 1e-3));
      int v = c / 3, a = c % 3; /* column c of the vertex's 3x3 block */
      for (int b = 0; b < 3; b++) {
        double fd = (gp[v * 3 + b] - gm[v * 3 + b]) / (2 * h), ex = sw_hess_get(H + v * 6, b, a, 3);
        assert_true(fabs(fd - ex) < 1e-4 * (fabs(ex) + 1.0));
      }
    }
  }
  sw_data_free(d);
  sw_model_free(m);
}

/* Conservative advancement: along random straight motions toward a capsule, the distance at
 * every sampled point of the allowed fraction stays at least keep x the start distance. */
static void advancement_is_conservative(void **st) {
  (void)st;
  sw_model *m = points_scene(3, "{shape: capsule, ends: [[-0.2, 0, 0], [0.2, 0, 0]], "
                             "radius: 0.3}", (double[]){0, 0, 0.5}, 1);
  unsigned long rs = 7;
  int hits = 0;
  for (int k = 0; k < 200; k++) {
    double p0[3], p1[3];
    for (int a = 0; a < 3; a++) {
      p0[a] = 1.2 * (th_rand(&rs) - 0.5);
      p1[a] = 1.2 * (th_rand(&rs) - 0.5);
    }
    double d0 = sw_obstacle_sdf(&m->obstacle[0], 3, 0.0, p0, NULL, NULL);
    if (d0 <= 0.0) continue;
    double s = sw_obstacle_toi(&m->obstacle[0], 3, 0.0, p0, p1, SW_CONTACT_KEEP);
    hits += s < 1.0;
    for (int j = 0; j <= 100; j++) {
      double q[3];
      for (int a = 0; a < 3; a++) q[a] = p0[a] + s * j / 100.0 * (p1[a] - p0[a]);
      assert_true(sw_obstacle_sdf(&m->obstacle[0], 3, 0.0, q, NULL, NULL) >=
                  SW_CONTACT_KEEP * d0 * (1 - 1e-9));
    }
  }
  assert_true(hits > 20); /* the test did meet the capsule */
  sw_model_free(m);
}

static const char drape[] =
    "dimension: 3\n"
    "mesh: {grid: {size: [0.6, 0.6], vertices: [21, 21], plane: xy}}\n"
    "material: {density: 0.1, membrane: {model: bw98, k_u: 5000, k_v: 5000, k_shear: 100},\n"
    "           bending: {model: quadratic, stiffness: 1e-5}}\n"
    "gravity: [0, 0, -9.81]\n"
    "obstacles: [{shape: sphere, center: [0.3, 0.3, -0.26], radius: 0.25}]\n"
    "contact: {distance: 2e-3, friction: 0.3}\n"
    "damping: {mass: 2.0}\n"
    "integrator: {method: backward-euler, dt: 0.01}\n"
    "duration: 6.0\n";

/* Dropped on a sphere: no vertex ever inside (by the test's own |x - c| - R), and at rest the
 * sphere carries the cloth's weight (barrier plus friction) to 1e-6. */
static void drop_on_sphere(void **st) {
  (void)st;
  sw_model *m = parse(drape);
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  const double c[3] = {0.3, 0.3, -0.26}, R = 0.25;
  double closest = INFINITY;
  while (d->t < m->opt.duration - 1e-9) {
    assert_int_equal(sw_sim_step(s, err, sizeof err), 0);
    for (int i = 0; i < m->nv; i++) {
      double r = 0.0;
      for (int a = 0; a < 3; a++) r += (d->x[3 * i + a] - c[a]) * (d->x[3 * i + a] - c[a]);
      closest = fmin(closest, sqrt(r) - R);
    }
  }
  assert_true(closest > 0.0);
  assert_true(closest < m->contact.dhat); /* it did touch */
  double weight = m->total_mass * 9.81, fz = d->contact_force[2] + d->friction_force[2];
  print_message("drop on sphere: closest %.3g m, contacts %d, support %.9g N, weight %.9g N\n",
                closest, d->contact_count, fz, weight);
  assert_true(fabs(fz - weight) < 1e-6 * weight);
  assert_true(fabs(d->contact_force[0] + d->friction_force[0]) < 1e-6 * weight);
  sw_sim_free(s);
  sw_model_free(m);
}

/* scenes/drape_mesh.yaml's first 0.3 s, where the cloth lands on the sphere's facets and its
 * corners reach the floor (a plane, whose bound cuts Newton's updates per vertex): no step
 * takes more than 20 line-search halvings (12 at most here).  The per-vertex clip of an update
 * cut short by the plane is kept only when it promises a part of the cut update's first-order
 * decrease (solvers/newton.c, clip_step); when every clipped update that still descended was
 * kept, one step (t = 0.23 s) took 151 halvings in 27 iterations, most for no progress. */
static void drape_line_search(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = th_scene_file("scenes/drape_mesh.yaml");
  assert_non_null(m);
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  long worst = 0, last = 0;
  double at = 0.0;
  while (d->t < 0.3 - 1e-9) {
    int rc = sw_sim_step(s, err, sizeof err);
    if (rc) print_error("%s\n", err);
    assert_int_equal(rc, 0);
    if (d->nlinesearch - last > worst) worst = d->nlinesearch - last, at = d->t;
    last = d->nlinesearch;
  }
  print_message("drape on a mesh sphere, 0.3 s: %ld Newton iterations, %ld halvings, at most "
                "%ld in one step (t = %g s)\n", d->nnewton, d->nlinesearch, worst, at);
  assert_true(worst <= 20);
  sw_sim_free(s);
  sw_model_free(m);
}

/* A 10 cm cloth on the plane z = 0 under gravity tilted by theta (the plane inclined by theta):
 * the mean velocity along the slope at 0.25 s and at 0.5 s in v[0], v[1] (m/s). */
static void slide_velocity(double theta, double mu, double v[2]) {
  char text[2048];
  const double g = 9.81;
  snprintf(text, sizeof text,
           "dimension: 3\n"
           "mesh: {grid: {size: [0.1, 0.1], vertices: [5, 5], plane: xy}}\n"
           "material: {density: 0.2, membrane: {model: bw98, k_u: 1000, k_v: 1000, k_shear: 50}}\n"
           "gravity: [%.17g, 0, %.17g]\n"
           "obstacles: [{shape: plane, point: [0, 0, -1e-3], normal: [0, 0, 1]}]\n"
           "contact: {distance: 2e-3, friction: %g}\n"
           "integrator: {method: backward-euler, dt: 0.005}\nduration: 0.5\n",
           g * sin(theta), -g * cos(theta), mu);
  sw_model *m = parse(text);
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  for (int k = 0; k < 2; k++) {
    assert_int_equal(sw_sim_run(s, 0.25 * (k + 1), err, sizeof err), 0);
    v[k] = 0.0;
    for (int i = 0; i < m->nv; i++) v[k] += d->v[3 * i] / m->nv;
  }
  sw_sim_free(s);
  sw_model_free(m);
}

static void inclined_plane(void **st) {
  (void)st;
  const double mu = 0.5, g = 9.81;
  double stick[2], slide[2], th = atan(1.2 * mu);
  slide_velocity(atan(0.8 * mu), mu, stick); /* tan = 0.4 < mu */
  slide_velocity(th, mu, slide);
  /* the acceleration once the first steps' settling on the barrier is over (m/s^2) */
  double a = (slide[1] - slide[0]) / 0.25, expect = g * (sin(th) - mu * cos(th));
  print_message("inclined plane: stick %.3g m/s, slide %.6g m/s^2 (expected %.6g)\n",
                stick[1], a, expect);
  assert_true(fabs(stick[1]) < SW_CONTACT_EPS_V); /* creeps below the stick-slip velocity */
  assert_true(fabs(a - expect) < 0.01 * expect);
}

static void scene_errors(void **st) {
  (void)st;
  const struct { const char *text, *want; } bad[] = {
      {"mesh: {points: [[0, 0, 0]]}\ncontact: {distance: 1e-3}\n", "contact.yaml:2:10: contact is "
       "given but the scene has no obstacles"},
      {"mesh: {points: [[0, 0, 0]]}\nmasses: [{select: {vertices: [0]}, mass: 1}]\n"
       "obstacles: [{shape: sphere, center: [0, 0, 0], radius: 1}]\n",
       "contact.yaml:3:12: obstacles: vertex 0 is not outside obstacles[0]"},
      {"mesh: {points: [[0, 0, 2]]}\nobstacles: [{shape: sphere, center: [0, 0, 0], normal: [0, 0, 1]}]\n",
       "obstacles[0] (a sphere) does not take 'normal'"},
      {"mesh: {points: [[0, 0, 2]]}\nobstacles: [{shape: cone}]\n", "contact.yaml:2:21: obstacles[0] shape is 'cone'; expected one of: plane"},
      {"mesh: {points: [[0, 0, 2]]}\nobstacles: [{shape: plane, point: [0, 0, 0], normal: [0, 0, 0]}]\n",
       "normal is zero"},
      {"mesh: {points: [[0, 0, 2]]}\nobstacles: [{shape: box, center: [0, 0, 0], size: [1, 1, 1], "
       "motion: {keyframes: [[1, 0, 0, 0], [0.5, 1, 0, 0]]}}]\n", "expected increasing times"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    char err[SW_ERRSZ];
    sw_model *m = sw_scene_parse("contact.yaml", bad[k].text, strlen(bad[k].text), err,
                                 sizeof err);
    if (m || !strstr(err, bad[k].want)) print_error("case %zu: %s\n", k, err);
    assert_null(m);
    assert_non_null(strstr(err, bad[k].want));
  }
  /* no obstacles: no contact term, no contact arrays */
  sw_model *m = parse("mesh: {points: [[0, 0, 0]]}\npins: [{select: {vertices: [0]}}]\n");
  assert_int_equal(sw_term_find(m, "contact"), -1);
  sw_data *d = sw_data_new(m);
  assert_null(d->lag);
  assert_null(d->contact_pressure);
  sw_data_free(d);
  sw_model_free(m);
}

/* An obstacle moving into a resting cloth pushes it along: a box rising 5 cm under a cloth
 * lying on it lifts it, and no vertex is ever inside. */
static void moving_obstacle(void **st) {
  (void)st;
  sw_model *m = parse(
      "dimension: 3\n"
      "mesh: {grid: {size: [0.2, 0.2], vertices: [9, 9], plane: xy}}\n"
      "material: {density: 0.1, membrane: {model: bw98, k_u: 1000, k_v: 1000, k_shear: 50}}\n"
      "gravity: [0, 0, -9.81]\n"
      "obstacles: [{shape: box, center: [0.1, 0.1, -0.1015], size: [0.4, 0.4, 0.2],\n"
      "             motion: {keyframes: [[0, 0, 0, 0], [0.5, 0, 0, 0.05]]}}]\n"
      "integrator: {method: backward-euler, dt: 0.01}\nduration: 0.6\n");
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  while (d->t < 0.6 - 1e-9) {
    assert_int_equal(sw_sim_step(s, err, sizeof err), 0);
    assert_int_equal(sw_contact_outside(m, d->x, d->t, err, sizeof err), 0);
  }
  double zmin = INFINITY;
  for (int i = 0; i < m->nv; i++) zmin = fmin(zmin, d->x[3 * i + 2]);
  assert_true(zmin > 0.05 - 1.5e-3 && zmin < 0.05 + 2e-3); /* on the box's top, 5 cm up */
  sw_sim_free(s);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(barrier_derivatives),  cmocka_unit_test(obstacle_conformance),
      cmocka_unit_test(friction_derivatives), cmocka_unit_test(advancement_is_conservative),
      cmocka_unit_test(drop_on_sphere),       cmocka_unit_test(inclined_plane),
      cmocka_unit_test(moving_obstacle),      cmocka_unit_test(scene_errors),
      cmocka_unit_test(drape_line_search),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
