/* test_mesh_friction.c — friction of mesh obstacles and self-contact (models/mesh_friction.c,
 * docs/contact.md "Friction"):
 *   - one lagged pair's friction (a point and a triangle, two edges): gradient and Hessian
 *     against central differences at slips below and above the smoothing scale eps_v h, and
 *     the Hessian positive semi-definite;
 *   - the term mesh_contact with friction: its gradient against central differences of its
 *     energy after a step's lag;
 *   - a cloth on an inclined mesh plane (two triangles) sticks below tan(theta) = mu and
 *     slides above with the acceleration g (sin theta - mu cos theta);
 *   - energy balance on that slide: K + U + dissipated stays at its start;
 *   - a cloth on a tilted mesh sphere stays with mu = 0.5 and slides off with mu = 0. */
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

static sw_model *scene(const char *text) {
  char name[128];
  snprintf(name, sizeof name, "%s/scene.yaml", dir);
  return th_scene(name, text);
}

/* The smallest eigenvalue of a symmetric 12 x 12 matrix (Jacobi sweeps). */
static double min_eig12(const double *A0) {
  double A[144];
  memcpy(A, A0, sizeof A);
  for (int sweep = 0; sweep < 60; sweep++)
    for (int p = 0; p < 12; p++)
      for (int q = p + 1; q < 12; q++) {
        if (fabs(A[p * 12 + q]) < 1e-300) continue;
        double th = 0.5 * atan2(2 * A[p * 12 + q], A[q * 12 + q] - A[p * 12 + p]);
        double c = cos(th), s = sin(th);
        for (int k = 0; k < 12; k++) {
          double akp = A[k * 12 + p], akq = A[k * 12 + q];
          A[k * 12 + p] = c * akp - s * akq, A[k * 12 + q] = s * akp + c * akq;
        }
        for (int k = 0; k < 12; k++) {
          double apk = A[p * 12 + k], aqk = A[q * 12 + k];
          A[p * 12 + k] = c * apk - s * aqk, A[q * 12 + k] = s * apk + c * aqk;
        }
      }
  double e = INFINITY;
  for (int k = 0; k < 12; k++) e = fmin(e, A[k * 12 + k]);
  return e;
}

/* One pair lagged at p0 (xi = 0, shat for dhat = 1e-3 m, h = 0.01 s, eps_v = 1e-3 m/s: eps =
 * 1e-5 m), evaluated at p0 slid by `slip` (m) along a tangent direction plus a normal part. */
static void pair_case(int kind, const double *p0, double slip) {
  const double dhat = 1e-3, mu = 0.4, eps_v = 1e-3, w = 1e5;
  const int v[4] = {0, 1, 2, 3};
  sw_mfriction *f = sw_mfriction_new();
  assert_non_null(f);
  sw_mfriction_begin(f, 0.01);
  assert_int_equal(sw_mfriction_lag_pair(f, kind, v, p0, 0.0, dhat * dhat, w, mu), 0);
  assert_int_equal(sw_mfriction_count(f), 1);
  double x[12], g[12], H[144];
  const double dir[12] = {0.8, -0.6, 0.3, -0.2, 0.1, 0.0, 0.05, 0.3, -0.1, -0.4, 0.2, 0.1};
  for (int i = 0; i < 12; i++) x[i] = p0[i] + slip * dir[i];
  double e = sw_mfriction_pair(f, eps_v, 0, x, g, H, 0);
  assert_true(e > 0.0);
  const double h = 1e-3 * fmin(slip, 1e-5); /* m */
  double gmax = 0.0, hmax = 0.0;
  for (int i = 0; i < 12; i++) gmax = fmax(gmax, fabs(g[i]));
  for (int i = 0; i < 144; i++) hmax = fmax(hmax, fabs(H[i]));
  for (int c = 0; c < 12; c++) {
    double xp[12], gp[12], gm[12];
    memcpy(xp, x, sizeof xp);
    xp[c] += h;
    double ep = sw_mfriction_pair(f, eps_v, 0, xp, gp, NULL, 0);
    xp[c] -= 2 * h;
    double em = sw_mfriction_pair(f, eps_v, 0, xp, gm, NULL, 0);
    double fd = (ep - em) / (2 * h);
    if (fabs(fd - g[c]) > 1e-6 * gmax) print_error("g[%d]: %g fd %g\n", c, g[c], fd);
    assert_true(fabs(fd - g[c]) <= 1e-6 * gmax);
    for (int r = 0; r < 12; r++) {
      double fh = (gp[r] - gm[r]) / (2 * h);
      if (fabs(fh - H[r * 12 + c]) > 1e-5 * hmax)
        print_error("H[%d][%d]: %g fd %g\n", r, c, H[r * 12 + c], fh);
      assert_true(fabs(fh - H[r * 12 + c]) <= 1e-5 * hmax);
    }
  }
  assert_true(min_eig12(H) >= -1e-12 * hmax);
  /* the bound Newton's matrix may take instead (sw_eval.bound): the same energy and
   * gradient, positive semi-definite, above the exact Hessian, and the Hessian of a quadratic
   * above the energy along the slip (f0 majorised: checked at slips 0.5, 2 and 4 times) */
  double gb[12], Hb[144], D[144];
  assert_true(sw_mfriction_pair(f, eps_v, 0, x, gb, Hb, 1) == e);
  assert_memory_equal(g, gb, sizeof g);
  for (int i = 0; i < 144; i++) D[i] = Hb[i] - H[i];
  assert_true(min_eig12(Hb) >= -1e-12 * hmax);
  assert_true(min_eig12(D) >= -1e-12 * hmax);
  for (int s = 0; s < 3; s++) {
    double t = s == 0 ? -0.5 : s == 1 ? 1.0 : 3.0, xq[12], q = e; /* x + t (x - p0) */
    for (int i = 0; i < 12; i++) xq[i] = x[i] + t * (x[i] - p0[i]);
    for (int i = 0; i < 12; i++) q += gb[i] * t * (x[i] - p0[i]);
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) q += 0.5 * t * t * (x[i] - p0[i]) * Hb[i * 12 + j] * (x[j] - p0[j]);
    double eq = sw_mfriction_pair(f, eps_v, 0, xq, NULL, NULL, 0);
    assert_true(eq <= q * (1.0 + 1e-9) + 1e-18);
  }
  sw_mfriction_free(f);
}

static void pair_derivatives(void **st) {
  (void)st;
  const double pt[12] = {0.02, 0.03, 4e-4, 0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.1, 0.0};
  const double ee[12] = {0.0, 0.05, 5e-4, 0.1, 0.05, 5e-4, 0.05, 0.0, 0.0, 0.05, 0.1, 0.0};
  const double slip[3] = {2e-6, 4e-5, 3e-3}; /* m: below, above eps = 1e-5 m, far above */
  for (int k = 0; k < 3; k++) {
    pair_case(SW_MC_PT, pt, slip[k]);
    pair_case(SW_MC_EE, ee, slip[k]);
  }
}

/* A 3 x 3 cloth just above a two-triangle mesh plane, with friction: after a step's lag, the
 * term's gradient against central differences of its energy at a slid position. */
static void term_gradient(void **st) {
  (void)st;
  write_file("plane.obj", "v -1 -1 -1e-3\nv 1 -1 -1e-3\nv 1 1 -1e-3\nv -1 1 -1e-3\n"
                          "f 1 2 3\nf 1 3 4\n");
  sw_model *m = scene("dimension: 3\n"
                      "mesh: {grid: {size: [0.1, 0.1], vertices: [3, 3], plane: xy}}\n"
                      "material: {density: 0.1, membrane: {model: bw98, k_u: 100, k_v: 100, "
                      "k_shear: 10}}\n"
                      "gravity: [0, 0, -9.81]\n"
                      "obstacles: [{mesh: plane.obj}]\n"
                      "contact: {distance: 2e-3, friction: 0.5}\n");
  assert_non_null(m);
  sw_data *d = sw_data_new(m);
  assert_non_null(d);
  assert_int_equal(sw_mcontact_lag(m, d, 0.01), SW_OK);
  const int n = m->nv * 3, k = sw_term_find(m, "mesh_contact");
  assert_true(k >= 0);
  double *x = malloc(n * sizeof *x), *g = calloc(n, sizeof *g);
  unsigned long seed = 3;
  for (int i = 0; i < n; i++) /* slips of 0 to 30 um: both sides of eps = 1e-5 m */
    x[i] = m->x0[i] + (i % 3 == 2 ? 1e-5 : 3e-5) * (th_rand(&seed) - 0.5);
  sw_eval ev = {.t = 0.01, .x = x, .grad = g, .mc = d->mc};
  double e, ep, em;
  assert_int_equal(m->term[k].ops->eval(&m->term[k], m, &ev, &e), SW_OK);
  /* the friction alone, to know the test measures it: the gradient with mu = 0 differs */
  double *g0 = calloc(n, sizeof *g0), e0, fric = 0.0, gmax = 0.0;
  sw_model *mm = (sw_model *)m;
  mm->contact.friction = 0.0; /* lagged again without friction */
  assert_int_equal(sw_mcontact_lag(m, d, 0.01), SW_OK);
  sw_eval ev0 = {.t = 0.01, .x = x, .grad = g0, .mc = d->mc};
  assert_int_equal(m->term[k].ops->eval(&m->term[k], m, &ev0, &e0), SW_OK);
  mm->contact.friction = 0.5;
  assert_int_equal(sw_mcontact_lag(m, d, 0.01), SW_OK);
  for (int i = 0; i < n; i++) fric = fmax(fric, fabs(g[i] - g0[i])), gmax = fmax(gmax, fabs(g[i]));
  assert_true(fric > 1e-3 * gmax);
  for (int i = 0; i < n; i++) {
    const double h = 1e-8;
    double keep = x[i];
    sw_eval e1 = {.t = 0.01, .x = x, .mc = d->mc};
    x[i] = keep + h;
    m->term[k].ops->eval(&m->term[k], m, &e1, &ep);
    x[i] = keep - h;
    m->term[k].ops->eval(&m->term[k], m, &e1, &em);
    x[i] = keep;
    double fd = (ep - em) / (2 * h);
    if (fabs(fd - g[i]) > 1e-5 * gmax) print_error("g[%d] %g fd %g\n", i, g[i], fd);
    assert_true(fabs(fd - g[i]) <= 1e-5 * gmax);
  }
  free(x), free(g), free(g0);
  sw_data_free(d);
  sw_model_free(m);
}

/* A 10 cm cloth on a two-triangle mesh plane z = -1 mm under gravity tilted by theta (the
 * plane inclined by theta), from t = 0 to 0.5 s: the mean velocity along the slope at 0.25 s
 * and 0.5 s (m/s), and the energy balance's drift (K + U + dissipated at the end minus at the
 * start, J) and the dissipated energy (J). */
typedef struct slide_out {
  double v[2], drift, dissipated;
} slide_out;

static slide_out slide(double theta, double mu) {
  char text[2048];
  const double g = 9.81;
  write_file("plane.obj", "v -1 -1 -1e-3\nv 1 -1 -1e-3\nv 1 1 -1e-3\nv -1 1 -1e-3\n"
                          "f 1 2 4\nf 2 3 4\n");
  snprintf(text, sizeof text,
           "dimension: 3\n"
           "mesh: {grid: {size: [0.1, 0.1], vertices: [5, 5], plane: xy}}\n"
           "material: {density: 0.2, membrane: {model: bw98, k_u: 1000, k_v: 1000, k_shear: 50}}\n"
           "gravity: [%.17g, 0, %.17g]\n"
           "obstacles: [{mesh: plane.obj}]\n"
           "contact: {distance: 2e-3, friction: %g}\n"
           "integrator: {method: backward-euler, dt: 0.005}\nduration: 0.5\n",
           g * sin(theta), -g * cos(theta), mu);
  sw_model *m = scene(text);
  assert_non_null(m);
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  if (!s) print_error("%s\n", err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  slide_out o;
  double k0, u0, w0, k1, u1, w1;
  sw_sim_energy(s, &k0, &u0, &w0);
  for (int k = 0; k < 2; k++) {
    int rc = sw_sim_run(s, 0.25 * (k + 1), err, sizeof err);
    if (rc) print_error("%s\n", err);
    assert_int_equal(rc, 0);
    o.v[k] = 0.0;
    for (int i = 0; i < m->nv; i++) o.v[k] += d->v[3 * i] / m->nv;
  }
  sw_sim_energy(s, &k1, &u1, &w1);
  o.drift = (k1 + u1 + w1) - (k0 + u0 + w0);
  o.dissipated = w1 - w0;
  sw_sim_free(s);
  sw_model_free(m);
  return o;
}

static void inclined_plane(void **st) {
  (void)st;
  const double mu = 0.5, g = 9.81, th = atan(1.2 * mu);
  slide_out stick = slide(atan(0.8 * mu), mu), go = slide(th, mu);
  /* the acceleration once the first steps' settling on the barrier is over (m/s^2) */
  double a = (go.v[1] - go.v[0]) / 0.25, expect = g * (sin(th) - mu * cos(th));
  print_message("mesh plane: stick %.3g m/s, slide %.6g m/s^2 (expected %.6g, %.2f %%)\n",
                stick.v[1], a, expect, 100 * (a / expect - 1));
  print_message("mesh plane: dissipated %.6g J, K + U + dissipated drifts %.3g J\n",
                go.dissipated, go.drift);
  assert_true(fabs(stick.v[1]) < SW_CONTACT_EPS_V); /* creeps below the stick-slip velocity */
  assert_true(fabs(a - expect) < 0.02 * expect);
  assert_true(go.dissipated > 0.0);
  assert_true(fabs(go.drift) < 0.02 * go.dissipated);
}

/* A UV sphere of radius r about the origin, `rings` rings of latitude and `seg` segments of
 * longitude, wound outwards, into name. */
static void write_sphere(const char *name, double r, int rings, int seg) {
  size_t cap = (size_t)(rings * seg + 2) * 64 + (size_t)(2 * rings * seg) * 40, n = 0;
  char *text = malloc(cap);
  assert_non_null(text);
  const double pi = acos(-1.0);
  n += (size_t)snprintf(text + n, cap - n, "v 0 0 %.17g\n", r); /* 1: the top */
  for (int i = 1; i < rings; i++)
    for (int j = 0; j < seg; j++) {
      double th = pi * i / rings, ph = 2 * pi * j / seg;
      n += (size_t)snprintf(text + n, cap - n, "v %.17g %.17g %.17g\n", r * sin(th) * cos(ph),
                            r * sin(th) * sin(ph), r * cos(th));
    }
  int bottom = 2 + (rings - 1) * seg;
  n += (size_t)snprintf(text + n, cap - n, "v 0 0 %.17g\n", -r);
  for (int j = 0; j < seg; j++) { /* ring i, segment j is vertex 2 + (i - 1) seg + j */
    int a = 2 + j, b = 2 + (j + 1) % seg;
    n += (size_t)snprintf(text + n, cap - n, "f 1 %d %d\n", a, b);
    for (int i = 1; i < rings - 1; i++) {
      int p = 2 + (i - 1) * seg + j, q = 2 + (i - 1) * seg + (j + 1) % seg;
      n += (size_t)snprintf(text + n, cap - n, "f %d %d %d\nf %d %d %d\n", p, p + seg, q + seg, p,
                            q + seg, q);
    }
    a = 2 + (rings - 2) * seg + j, b = 2 + (rings - 2) * seg + (j + 1) % seg;
    n += (size_t)snprintf(text + n, cap - n, "f %d %d %d\n", a, bottom, b);
  }
  write_file(name, text);
  free(text);
}

/* A 5 cm cloth laid on the top of a mesh sphere (R = 0.2 m) under gravity tilted by 15 degrees
 * (tan = 0.27), for 1 s: how far its centre moves sideways (m). */
static double sphere_slide(double mu) {
  char text[2048];
  const double g = 9.81, th = 15.0 * acos(-1.0) / 180.0;
  write_sphere("sphere.obj", 0.2, 24, 48);
  snprintf(text, sizeof text,
           "dimension: 3\n"
           "mesh: {grid: {size: [0.05, 0.05], vertices: [5, 5], plane: xy}}\n"
           "material: {density: 0.2, membrane: {model: bw98, k_u: 1000, k_v: 1000, k_shear: 50}}\n"
           "gravity: [%.17g, 0, %.17g]\n"
           "obstacles: [{mesh: sphere.obj, translate: [0.025, 0.025, -0.2015]}]\n"
           "contact: {distance: 2e-3, friction: %g}\n"
           "integrator: {method: backward-euler, dt: 0.01}\nduration: 1\n",
           g * sin(th), -g * cos(th), mu);
  sw_model *m = scene(text);
  assert_non_null(m);
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  if (!s) print_error("%s\n", err);
  assert_non_null(s);
  int rc = sw_sim_run(s, 1.0, err, sizeof err);
  if (rc) print_error("%s\n", err);
  assert_int_equal(rc, 0);
  const sw_data *d = sw_sim_data(s);
  double move = 0.0;
  for (int i = 0; i < m->nv; i++) move += (d->x[3 * i] - m->x0[3 * i]) / m->nv;
  sw_sim_free(s);
  sw_model_free(m);
  return move;
}

static void mesh_sphere(void **st) {
  (void)st;
  double stays = sphere_slide(0.5), slides = sphere_slide(0.0);
  print_message("mesh sphere: the cloth's centre moves %.3g m with mu = 0.5, %.3g m with mu = 0 "
                "in 1 s\n", stays, slides);
  assert_true(fabs(stays) < SW_CONTACT_EPS_V * 1.0); /* creeps below eps_v over 1 s */
  assert_true(slides > 0.05);
}

/* An nx x ny grid of squares (two triangles each) spanning [x0, x0 + sx] x [y0, y0 + sy] at
 * height z, its vertices numbered from base (OBJ's 1-based), appended to text at *n. */
static void grid_obj(char *text, size_t cap, size_t *n, int base, int nx, int ny, double x0,
                     double y0, double sx, double sy, double z) {
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++)
      *n += (size_t)snprintf(text + *n, cap - *n, "v %.17g %.17g %.17g\nvt %.17g %.17g\n",
                             x0 + sx * i / (nx - 1), y0 + sy * j / (ny - 1), z,
                             x0 + sx * i / (nx - 1), y0 + sy * j / (ny - 1));
  for (int j = 0; j + 1 < ny; j++)
    for (int i = 0; i + 1 < nx; i++) {
      int a = base + j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      *n += (size_t)snprintf(text + *n, cap - *n, "f %d/%d %d/%d %d/%d\nf %d/%d %d/%d %d/%d\n",
                             a, a, b, b, d, d, a, a, d, d, c, c);
    }
}

/* Self-contact: a 10 cm cloth lying 1 mm above a pinned 40 cm one (one mesh, two layers)
 * under gravity tilted by theta: the top layer's mean velocity along the slope at 0.25 s and
 * 0.5 s (m/s).  friction is 0.9 (no obstacle: it acts on nothing), self_friction mu. */
static void layer_slide(double theta, double mu, double v[2]) {
  char obj[32768], text[2048];
  size_t n = 0;
  const double g = 9.81;
  grid_obj(obj, sizeof obj, &n, 1, 9, 5, -0.05, -0.05, 0.4, 0.2, 0.0);
  grid_obj(obj, sizeof obj, &n, 46, 5, 5, 0.0, 0.013, 0.1, 0.1, 1e-3);
  write_file("layers.obj", obj);
  snprintf(text, sizeof text,
           "dimension: 3\n"
           "mesh: {obj: layers.obj}\n"
           "material: {density: 0.2, membrane: {model: bw98, k_u: 1000, k_v: 1000, k_shear: 50}}\n"
           "pins: [{select: {box: [[-1, -1, -1e-4], [1, 1, 1e-4]]}}]\n"
           "gravity: [%.17g, 0, %.17g]\n"
           "contact: {self: true, distance: 2e-3, friction: 0.9, self_friction: %g}\n"
           "integrator: {method: backward-euler, dt: 0.005}\nduration: 0.5\n",
           g * sin(theta), -g * cos(theta), mu);
  sw_model *m = scene(text);
  assert_non_null(m);
  assert_true(m->contact.self_friction == mu && m->contact.friction == 0.9);
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  if (!s) print_error("%s\n", err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  for (int k = 0; k < 2; k++) {
    int rc = sw_sim_run(s, 0.25 * (k + 1), err, sizeof err);
    if (rc) print_error("%s\n", err);
    assert_int_equal(rc, 0);
    v[k] = 0.0;
    for (int i = 45; i < m->nv; i++) v[k] += d->v[3 * i] / (m->nv - 45);
  }
  sw_sim_free(s);
  sw_model_free(m);
}

static void self_contact_slide(void **st) {
  (void)st;
  const double mu = 0.5, g = 9.81, th = atan(1.2 * mu);
  double stick[2], go[2];
  layer_slide(atan(0.8 * mu), mu, stick);
  layer_slide(th, mu, go);
  double a = (go[1] - go[0]) / 0.25, expect = g * (sin(th) - mu * cos(th));
  print_message("cloth on cloth: stick %.3g m/s, slide %.6g m/s^2 (expected %.6g, %.2f %%)\n",
                stick[1], a, expect, 100 * (a / expect - 1));
  assert_true(fabs(stick[1]) < SW_CONTACT_EPS_V);
  assert_true(fabs(a - expect) < 0.03 * expect);
}

static int setup(void **st) {
  (void)st;
  snprintf(dir, sizeof dir, "/tmp/sinew_meshfric_XXXXXX");
  return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **st) {
  (void)st;
  th_remove_tree(dir);
  return 0;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(pair_derivatives),
      cmocka_unit_test(term_gradient),
      cmocka_unit_test(inclined_plane),
      cmocka_unit_test(mesh_sphere),
      cmocka_unit_test(self_contact_slide),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
