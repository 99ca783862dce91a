/* test_mesh_obstacle.c — mesh obstacles (obstacles: - {mesh: file.obj}; models/mesh_contact.c,
 * docs/contact.md "Mesh obstacles"):
 *   - the term mesh_contact's gradient against central differences with a cloth near a mesh
 *     obstacle, in each kind of pair: a cloth point against an obstacle triangle, a cloth edge
 *     against an obstacle edge, an obstacle point against a cloth triangle (and that kind is
 *     among the active pairs);
 *   - a cloth dropped on a mesh box never has a vertex inside it nor an edge crossing one of
 *     its triangles (a brute-force exact check after every step), and comes to rest with the
 *     vertical contact force equal to its weight to 1e-3;
 *   - the same with steps of 0.1 s and a Newton tolerance loose enough to accept the first
 *     update from rest, which would carry the cloth through the box: it lands on the top;
 *   - a mesh box rising under a cloth carries it up (the start of each step moves the cloth
 *     with it), still with no crossing;
 *   - a mesh box coming down onto a cloth lying on another fails the step, naming both;
 *   - scene errors name the place (file:line:column). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "contact.h"
#include "contact_geom.h"
#include "harness.h"
#include "scene.h"
#include "terms.h"

static char dir[64]; /* the tests' folder: scene.yaml's OBJ paths are relative to it */

static void write_file(const char *name, const char *text) {
  char path[128];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

/* An axis-aligned box lo..hi as 12 triangles wound outwards. */
static void write_box(const char *name, const double lo[3], const double hi[3]) {
  char text[2048];
  size_t n = 0;
  for (int k = 0; k < 8; k++)
    n += (size_t)snprintf(text + n, sizeof text - n, "v %.17g %.17g %.17g\n",
                          k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
  static const int f[12][3] = {{1, 3, 4}, {1, 4, 2}, {5, 6, 8}, {5, 8, 7}, {1, 2, 6}, {1, 6, 5},
                               {3, 7, 8}, {3, 8, 4}, {1, 5, 7}, {1, 7, 3}, {2, 4, 8}, {2, 8, 6}};
  for (int k = 0; k < 12; k++)
    n += (size_t)snprintf(text + n, sizeof text - n, "f %d %d %d\n", f[k][0], f[k][1], f[k][2]);
  write_file(name, text);
}

static sw_model *scene(const char *text) {
  char name[128];
  snprintf(name, sizeof name, "%s/scene.yaml", dir);
  return th_scene(name, text);
}

/* The term mesh_contact alone at x (t = 0): energy (J) and gradient (nv x 3, N). */
static double term_energy(const sw_model *m, sw_data *d, const double *x, double *grad) {
  int k = sw_term_find(m, "mesh_contact");
  assert_true(k >= 0);
  sw_eval ev = {.t = 0.0, .x = x, .grad = grad, .mc = d->mc};
  double e;
  if (grad) memset(grad, 0, (size_t)m->nv * 3 * sizeof(double));
  assert_int_equal(m->term[k].ops->eval(&m->term[k], m, &ev, &e), SW_OK);
  return e;
}

/* A 3 x 3 cloth (10 cm) at z = 0 above the obstacle `obj`, raised by up to 0.2 mm at random
 * per vertex: the gradient against central differences, and a pair of kind `kind` whose
 * vertex `at` is the obstacle's (>= nv) among the active pairs. */
static void fd_case(const char *obj, int kind, int at, const char *what) {
  write_file("o.obj", obj);
  sw_model *m = scene("dimension: 3\n"
                      "mesh: {grid: {size: [0.1, 0.1], vertices: [3, 3], plane: xy}}\n"
                      "material: {density: 0.1, membrane: {model: bw98, k_u: 100, k_v: 100, "
                      "k_shear: 10}}\n"
                      "obstacles: [{mesh: o.obj}]\n"
                      "contact: {distance: 2e-3}\n");
  assert_non_null(m);
  sw_data *d = sw_data_new(m);
  assert_non_null(d);
  const int n = m->nv * 3;
  double *x = malloc(n * sizeof *x), *g = malloc(n * sizeof *g), *scratch = malloc(n * sizeof *g);
  unsigned long seed = 7;
  memcpy(x, m->x0, n * sizeof *x);
  for (int i = 0; i < m->nv; i++) x[3 * i + 2] += 1e-4 * (1.0 + th_rand(&seed));
  double e = term_energy(m, d, x, g), gmax = 0.0, err = 0.0, h = 1e-7;
  const sw_mc_pair *pr;
  int np = sw_mcontact_pairs(d->mc, &pr, NULL), found = 0;
  for (int k = 0; k < np; k++) found |= pr[k].kind == kind && pr[k].v[at] >= m->nv;
  for (int c = 0; c < n; c++) {
    double keep = x[c];
    x[c] = keep + h;
    double ep = term_energy(m, d, x, scratch);
    x[c] = keep - h;
    double em = term_energy(m, d, x, scratch);
    x[c] = keep;
    gmax = fmax(gmax, fabs(g[c]));
    err = fmax(err, fabs((ep - em) / (2.0 * h) - g[c]));
  }
  print_message("mesh obstacle gradient, %s: %d pairs, energy %.3g J, max |g| %.3g N, "
                "FD error %.2g\n", what, np, e, gmax, err / gmax);
  assert_true(e > 0.0 && found);
  assert_true(err < 1e-6 * gmax);
  free(x), free(g), free(scratch);
  sw_data_free(d);
  sw_model_free(m);
}

static void gradient(void **st) {
  (void)st;
  /* a large triangle 0.5 mm under the cloth: each cloth point against its plane */
  fd_case("v -1 -1 -5e-4\nv 2 -1 -5e-4\nv -1 2 -5e-4\nf 1 2 3\n", SW_MC_PT, 1, "point-triangle");
  /* an upright triangle whose top edge (along y at x = 0.025) passes 0.5 mm under the cloth's
   * edges along x: edge-edge pairs only (the cloth's vertices are 2.5 cm away) */
  fd_case("v 0.025 -1 -5e-4\nv 0.025 1 -5e-4\nv 0.025 0 -1\nf 1 2 3\n", SW_MC_EE, 2, "edge-edge");
  /* a tetrahedron's apex 0.5 mm under the interior of a cloth triangle */
  fd_case("v 0.03 0.02 -5e-4\nv -0.5 -0.5 -1\nv 0.5 -0.5 -1\nv 0 0.5 -1\n"
          "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n", SW_MC_PT, 0, "obstacle point-triangle");
}

/* Every cloth edge against every obstacle triangle (exact), and every cloth vertex against
 * the box lo..hi (strictly inside): the number of crossings and of vertices inside. */
static int crossings(const sw_model *m, const double *x, double t, const double *lo,
                     const double *hi) {
  const sw_obstacle *o = &m->mesh_obstacle[0];
  double disp[3], q[3][3];
  sw_obstacle_disp(o, t, disp);
  int bad = 0;
  for (int i = 0; i < m->nv; i++) {
    int in = 1;
    for (int a = 0; a < 3; a++)
      in &= x[3 * i + a] > lo[a] + disp[a] && x[3 * i + a] < hi[a] + disp[a];
    bad += in;
  }
  for (int f = 0; f < o->mesh_nf; f++) {
    for (int c = 0; c < 3; c++)
      for (int a = 0; a < 3; a++) q[c][a] = o->mesh_x[3 * o->mesh_face[3 * f + c] + a] + disp[a];
    for (int g = 0; g < m->nf; g++)
      for (int e = 0; e < 3; e++) {
        const double *p0 = x + 3 * m->face[3 * g + e], *p1 = x + 3 * m->face[3 * g + (e + 1) % 3];
        bad += sw_segment_triangle_intersect(p0, p1, q[0], q[1], q[2]);
      }
  }
  return bad;
}

static int renew_listings = 1; /* sw_mcontact_set_renew for run_with's simulations */

/* A cloth of n x n vertices (20 cm) at z = 0 over the mesh box lo..hi (`more`: its motion and
 * the scene's other keys; `integrator`: the integrator key's value), run to its duration: the
 * crossings summed over every step; the simulation in *out. */
static int run_with(const double *lo, const double *hi, int n, const char *integrator,
                    const char *more, sw_sim **out) {
  char text[1024], err[SW_ERRSZ];
  write_box("box.obj", lo, hi);
  snprintf(text, sizeof text,
           "dimension: 3\n"
           "mesh: {grid: {size: [0.2, 0.2], vertices: [%d, %d], plane: xy}}\n"
           "material: {density: 0.1, membrane: {model: bw98, k_u: 1000, k_v: 1000, k_shear: 50}}\n"
           "gravity: [0, 0, -9.81]\n"
           "integrator: %s\n"
           "obstacles: [{mesh: box.obj%s\n", n, n, integrator, more);
  sw_model *m = scene(text);
  assert_non_null(m);
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  sw_mcontact_set_renew(d->mc, renew_listings);
  int bad = 0;
  while (d->t < m->opt.duration - 1e-9) {
    assert_int_equal(sw_sim_step(s, err, sizeof err), 0);
    bad += crossings(m, d->x, d->t, lo, hi);
  }
  *out = s;
  return bad;
}

/* The height of the cloth's lowest vertex, m. */
static double lowest(const sw_model *m, const sw_data *d) {
  double z = INFINITY;
  for (int i = 0; i < m->nv; i++) z = fmin(z, d->x[3 * i + 2]);
  return z;
}

static int run_on_box(const double *lo, const double *hi, int n, const char *more, sw_sim **out) {
  return run_with(lo, hi, n, "{method: backward-euler, dt: 0.01}", more, out);
}

/* A 20 cm cloth dropped from 1 cm onto a 40 cm mesh box (frictionless: it stays on the top,
 * which is wider than it). */
static void drop_on_box(void **st) {
  (void)st;
  const double lo[3] = {-0.1, -0.1, -0.41}, hi[3] = {0.3, 0.3, -0.01};
  sw_sim *s;
  int bad = run_on_box(lo, hi, 11, "}]\ncontact: {distance: 2e-3}\ndamping: {mass: 5.0}\n"
                       "duration: 2.0", &s);
  const sw_model *m = sw_sim_model(s);
  const sw_data *d = sw_sim_data(s);
  double weight = m->total_mass * 9.81, fz = d->contact_force[2];
  print_message("drop on a mesh box: contacts %d, closest %.3g m, support %.9g N, weight %.9g N,"
                " crossings %d, sideways %.3g %.3g N\n", d->contact_count, d->contact_min, fz,
                weight, bad, d->contact_force[0], d->contact_force[1]);
  assert_int_equal(bad, 0);
  assert_true(d->contact_count > 0 && d->contact_min > 0.0 && d->contact_min < m->contact.dhat);
  assert_true(fabs(fz - weight) < 1e-3 * weight);
  /* sideways: the barrier of the top's diagonal edge (inside the flat face) pushes the cloth's
   * vertices near it a little apart from it, and the frictionless cloth drifts (measured:
   * 1.7e-3 of the weight) */
  assert_true(hypot(d->contact_force[0], d->contact_force[1]) < 5e-3 * weight);
  sw_sim_free(s);
  sw_model_free((sw_model *)m);
}

/* The same drop with steps of 0.1 s and a Newton tolerance of 1 m/s: the first step's Newton
 * update from rest is h^2 g = 9.8 cm, ten times the drop, and within that tolerance, while the
 * box is beyond the barrier's reach (d-hat 2 mm) where it starts.  The update is taken whole
 * only if the collision detection lets it through, so the cloth lands on the top and stays
 * there (it used to go through: converged, with no pair near, nothing checked the update). */
static void loose_tolerance(void **st) {
  (void)st;
  const double lo[3] = {-0.1, -0.1, -0.41}, hi[3] = {0.3, 0.3, -0.01};
  sw_sim *s;
  int bad = run_with(lo, hi, 6, "{method: backward-euler, dt: 0.1, newton: {tol: 1.0}}",
                     "}]\ncontact: {distance: 2e-3}\ndamping: {mass: 5.0}\nduration: 0.5", &s);
  const sw_model *m = sw_sim_model(s);
  const sw_data *d = sw_sim_data(s);
  double zmin = lowest(m, d);
  print_message("loose tolerance: lowest vertex %.6g m (box top %.6g m), crossings %d\n", zmin,
                hi[2], bad);
  assert_int_equal(bad, 0);
  assert_true(zmin > hi[2] && zmin < hi[2] + 2e-3);
  sw_sim_free(s);
  sw_model_free((sw_model *)m);
}

/* A cloth dropped half over the edge of a mesh box, so that it folds down the side, with
 * the candidate listings renewed for the vertices that left their boxes (the default) and
 * every listing made anew: the same positions to round-off, no crossing, renewals taken. */
static void renewed_listings(void **st) {
  (void)st;
  const double lo[3] = {0.06, -0.1, -0.41}, hi[3] = {0.14, 0.3, -0.01};
  sw_sim *s[2];
  long made[2], renewed[2];
  int bad[2];
  for (int k = 0; k < 2; k++) {
    renew_listings = k == 0;
    bad[k] = run_on_box(lo, hi, 11, "}]\ncontact: {distance: 2e-3}\ndamping: {mass: 2.0}\n"
                        "duration: 1.0", &s[k]);
    sw_mcontact_listings(sw_sim_data(s[k])->mc, &made[k], &renewed[k]);
  }
  renew_listings = 1;
  const sw_model *m = sw_sim_model(s[0]);
  const double *x0 = sw_sim_data(s[0])->x, *x1 = sw_sim_data(s[1])->x;
  double dx = 0.0;
  for (int i = 0; i < 3 * m->nv; i++) dx = fmax(dx, fabs(x0[i] - x1[i]));
  print_message("over the edge of a mesh box: listings %ld made, %ld renewed; made anew %ld; "
                "largest difference of the positions %.3g m, lowest vertex %.4g m, crossings "
                "%d %d\n", made[0], renewed[0], made[1], dx, lowest(m, sw_sim_data(s[0])),
                bad[0], bad[1]);
  assert_true(renewed[0] > 0 && renewed[1] == 0);
  assert_true(dx < 1e-9); /* m */
  assert_true(lowest(m, sw_sim_data(s[0])) < hi[2] - 0.05); /* it did fold down the side */
  assert_int_equal(bad[0], 0);
  for (int k = 0; k < 2; k++) {
    const sw_model *mk = sw_sim_model(s[k]);
    sw_sim_free(s[k]);
    sw_model_free((sw_model *)mk);
  }
}

/* A mesh box rising 5 cm in 0.5 s under a cloth lying on it lifts the cloth. */
static void rising_box(void **st) {
  (void)st;
  const double lo[3] = {-0.1, -0.1, -0.2015}, hi[3] = {0.3, 0.3, -0.0015};
  sw_sim *s;
  int bad = run_on_box(lo, hi, 9, ",\n  motion: {keyframes: [[0, 0, 0, 0], [0.5, 0, 0, 0.05]]}}]\n"
                       "duration: 0.6", &s);
  const sw_model *m = sw_sim_model(s);
  const sw_data *d = sw_sim_data(s);
  double zmin = lowest(m, d);
  print_message("rising mesh box: lowest vertex %.6g m (box top %.6g m), crossings %d\n", zmin,
                hi[2] + 0.05, bad);
  assert_int_equal(bad, 0);
  assert_true(zmin > hi[2] + 0.05 && zmin < hi[2] + 0.05 + 2e-3); /* on the top, 5 cm up */
  sw_sim_free(s);
  sw_model_free((sw_model *)m);
}

/* A mesh box coming down onto a cloth lying on another: the cloth cannot get out of the way,
 * and the step fails with the obstacle and vertex named (after every halving), not through. */
static void squeeze(void **st) {
  (void)st;
  const double lo[3] = {-0.1, -0.1, -0.2015}, hi[3] = {0.3, 0.3, -0.0015};
  const double lo2[3] = {-0.1, -0.1, 0.0015}, hi2[3] = {0.3, 0.3, 0.2015};
  write_box("floor.obj", lo, hi);
  write_box("press.obj", lo2, hi2);
  sw_model *m = scene("dimension: 3\n"
                      "mesh: {grid: {size: [0.2, 0.2], vertices: [5, 5], plane: xy}}\n"
                      "material: {density: 0.1, membrane: {model: bw98, k_u: 1000, k_v: 1000, "
                      "k_shear: 50}}\n"
                      "integrator: {method: backward-euler, dt: 0.01}\nduration: 0.5\n"
                      "obstacles: [{mesh: floor.obj},\n"
                      "  {mesh: press.obj, motion: {keyframes: [[0, 0, 0, 0], [0.5, 0, 0, -0.05]],"
                      " interpolation: linear}}]\n");
  assert_non_null(m);
  char err[SW_ERRSZ] = "";
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  int rc = 0;
  while (rc == 0 && d->t < m->opt.duration - 1e-9) rc = sw_sim_step(s, err, sizeof err);
  print_message("squeezed: stopped at t = %.4g s: %s\n", d->t, err);
  assert_true(rc != 0 && d->t < 0.05); /* the 3 mm between the boxes close at 0.1 m/s */
  assert_non_null(strstr(err, "obstacles[1] moves vertex "));
  assert_non_null(strstr(err, " into obstacles[0] between"));
  sw_sim_free(s);
  sw_model_free(m);
}

static void scene_errors(void **st) {
  (void)st;
  const double lo[3] = {-0.1, -0.1, -0.5}, hi[3] = {0.3, 0.3, -0.001};
  write_box("box.obj", lo, hi);
  write_file("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 x\nf 1 2 3\n");
  static const char head[] = "dimension: 3\n"
                             "mesh: {grid: {size: [0.2, 0.2], vertices: [3, 3], plane: xy}}\n"
                             "material: {density: 0.1}\n";
  const struct { const char *text, *want; } bad[] = {
      {"obstacles: [{mesh: bad.obj}]\n", "scene.yaml:4:20: in obstacles[0] mesh: "},
      {"obstacles: [{mesh: none.obj}]\n", "scene.yaml:4:20: obstacles[0] mesh '"},
      {"obstacles: [{mesh: box.obj, radius: 1}]\n",
       "scene.yaml:4:37: obstacles[0] (a mesh) does not take 'radius'"},
      {"obstacles: [{shape: sphere, center: [0, 0, -1], radius: 0.1, scale: 2}]\n",
       "obstacles[0] (a shape) does not take 'scale'"},
      {"obstacles: [{mesh: box.obj, offset: 2e-3}]\n",
       "scene.yaml:4:12: obstacles: vertex 0 starts 0.001 m from obstacles[0], within its offset"},
      {"obstacles: [{mesh: box.obj, translate: [0.15, 0, 0.1]}]\n",
       "scene.yaml:4:12: obstacles: face 0 of the cloth (vertices 0 1 4) intersects obstacles[0]"},
      {"obstacles: [{shape: plane, point: [0, 0, -1], normal: [0, 0, 1]},\n"
       "            {mesh: box.obj, scale: 0}]\n", "scene.yaml:5:36: obstacles[1] scale"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    char text[1024], err[SW_ERRSZ], name[128];
    snprintf(text, sizeof text, "%s%s", head, bad[k].text);
    snprintf(name, sizeof name, "%s/scene.yaml", dir);
    sw_model *m = sw_scene_parse(name, text, strlen(text), err, sizeof err);
    if (m || !strstr(err, bad[k].want)) print_error("case %zu: %s\n", k, err);
    assert_null(m);
    assert_non_null(strstr(err, bad[k].want));
  }
  /* 2D: no mesh obstacles */
  char err[SW_ERRSZ], name[128];
  const char *two = "dimension: 2\nmesh: {points: [[0, 1]]}\nobstacles: [{mesh: box.obj}]\n";
  snprintf(name, sizeof name, "%s/scene.yaml", dir);
  assert_null(sw_scene_parse(name, two, strlen(two), err, sizeof err));
  assert_non_null(strstr(err, "scene.yaml:3:20: obstacles[0] mesh is given in a 2D scene"));
  /* self_stiffness sets the mesh obstacles' stiffness without self-contact */
  sw_model *m = scene("dimension: 3\n"
                      "mesh: {grid: {size: [0.2, 0.2], vertices: [3, 3], plane: xy}}\n"
                      "material: {density: 0.1}\n"
                      "obstacles: [{mesh: box.obj}]\ncontact: {self_stiffness: 1e7}\n");
  assert_non_null(m);
  assert_true(m->contact.kappa_mesh == 1e7 && !m->contact.kappa_mesh_auto && !m->contact.self);
  sw_model_free(m);
}

static int setup(void **st) {
  (void)st;
  snprintf(dir, sizeof dir, "/tmp/sinew_meshobst_XXXXXX");
  return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **st) {
  (void)st;
  th_remove_tree(dir);
  return 0;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(gradient),   cmocka_unit_test(drop_on_box),
      cmocka_unit_test(loose_tolerance),
      cmocka_unit_test(renewed_listings),
      cmocka_unit_test(rising_box), cmocka_unit_test(squeeze),
      cmocka_unit_test(scene_errors),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
