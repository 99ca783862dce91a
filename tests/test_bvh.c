/* test_bvh.c — the bounding-volume hierarchy of models/bvh.c against brute force: on random
 * triangle soups (1 to 3000 triangles of sizes spread over four decades, some degenerate,
 * some coincident) and random query boxes (points, slabs, boxes of every size, boxes far
 * outside), a query reports exactly the triangles whose box overlaps the query's (closed
 * boxes, touching counts), each once; after the triangles move (a random rigid motion plus a
 * jitter) and the tree is refitted, again exactly (the primitives' boxes kept in the tree,
 * sw_bvh_keep_boxes, and refreshed by the refit); without the per-primitive test, a superset
 * with every leaf's box containing its primitives'; and a nonzero return of the visitor stops
 * the query and is returned.
 * And in the term mesh_contact (models/mesh_contact.c): a 5 x 5 cloth held 1.5 to 2.5 mm above
 * the mean plane of a wavy mesh obstacle of 100352 triangles (and of 8192, whose triangles'
 * boxes the term keeps beside the tree), so that it is near some of them: the
 * active pairs of an evaluation are exactly those within d-hat found by brute force over every
 * cloth point against every obstacle triangle, every obstacle point against every cloth
 * triangle and every cloth edge against every obstacle edge (each pair once: the obstacle's
 * vertices and edges come from the tree's triangles, through each cloth face's list of the
 * obstacle triangles near it); the term's memory (its tree, 12 bytes a triangle, 48 more for the
 * kept boxes, and the cloth's edges: no copy of the obstacle); then three steps of a run, with no
 * cloth triangle crossing the obstacle's at the end (exact count). */
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

typedef struct soup {
  int n;
  double *x; /* (n x 9) the triangles' corners, m */
} soup;

static void soup_box(const void *ctx, int i, double *b) {
  const soup *s = ctx;
  const double *p = s->x + 9 * (size_t)i;
  for (int a = 0; a < 3; a++) {
    b[a] = fmin(p[a], fmin(p[3 + a], p[6 + a]));
    b[3 + a] = fmax(p[a], fmax(p[3 + a], p[6 + a]));
  }
}

static double urand(unsigned long *rs) { return 0.5 * (th_rand(rs) + 1.0); } /* [0, 1) */

static void random_soup(soup *s, int n, unsigned long *rs) {
  s->n = n;
  s->x = calloc(9 * (size_t)n + 1, sizeof(double));
  for (int i = 0; i < n; i++) {
    double *p = s->x + 9 * (size_t)i, size = pow(10.0, -4.0 + 4.0 * urand(rs));
    for (int a = 0; a < 3; a++) p[a] = 2.0 * urand(rs) - 1.0;
    for (int k = 3; k < 9; k++) p[k] = p[k % 3] + size * th_rand(rs);
    if (i % 17 == 3) /* a point */
      memcpy(p + 3, p, 3 * sizeof(double)), memcpy(p + 6, p, 3 * sizeof(double));
    if (i % 29 == 5 && i > 0) memcpy(p, p - 9, 9 * sizeof(double)); /* the previous one again */
  }
}

/* A random query box: a point, a slab, a box of any size, or one far away. */
static void random_box(double *b, unsigned long *rs, const soup *s) {
  int kind = (int)(5 * urand(rs));
  double c[3], h[3];
  for (int a = 0; a < 3; a++) c[a] = 2.4 * urand(rs) - 1.2, h[a] = pow(10.0, -4.0 + 4.0 * urand(rs));
  if (kind == 0) h[0] = h[1] = h[2] = 0.0;
  if (kind == 1) h[(int)(3 * urand(rs))] = 10.0;
  if (kind == 2) c[2] += 100.0;
  if (kind == 3 && s->n > 0) { /* exactly touching a triangle's box */
    double tb[6];
    soup_box(s, (int)(s->n * urand(rs)), tb);
    for (int a = 0; a < 3; a++) c[a] = tb[3 + a] + h[a];
  }
  for (int a = 0; a < 3; a++) b[a] = c[a] - h[a], b[3 + a] = c[a] + h[a];
}

typedef struct hits {
  int *count, total, stop_at;
} hits;

static int on_hit(void *arg, int i) {
  hits *h = arg;
  h->count[i]++;
  h->total++;
  return h->stop_at > 0 && h->total == h->stop_at ? 7 : 0;
}

static int meet(const double *p, const double *q) {
  for (int a = 0; a < 3; a++)
    if (p[a] > q[3 + a] || q[a] > p[3 + a]) return 0;
  return 1;
}

/* 200 random boxes: exactly the brute-force set with the per-primitive test, a superset
 * without. */
static void check_queries(const sw_bvh *t, const soup *s, unsigned long *rs) {
  int *count = calloc((size_t)s->n + 1, sizeof(int));
  for (int q = 0; q < 200; q++) {
    double b[6], tb[6];
    random_box(b, rs, s);
    for (int exact = 0; exact < 2; exact++) {
      memset(count, 0, ((size_t)s->n + 1) * sizeof(int));
      hits h = {count, 0, 0};
      assert_int_equal(sw_bvh_query(t, b, exact ? soup_box : NULL, s, on_hit, &h), 0);
      for (int i = 0; i < s->n; i++) {
        soup_box(s, i, tb);
        assert_true(count[i] <= 1);
        if (meet(tb, b)) assert_int_equal(count[i], 1);
        else if (exact) assert_int_equal(count[i], 0);
      }
    }
  }
  free(count);
}

/* Every leaf's box holds its primitives' boxes, every node's its children's. */
static void check_boxes(const sw_bvh *t, const soup *s) {
  for (int k = 0; k < t->nnode; k++) {
    const float *f = t->box + 6 * (size_t)k;
    int first = t->node[2 * k], count = t->node[2 * k + 1];
    for (int i = first; count > 0 && i < first + count; i++) {
      double b[6];
      soup_box(s, t->prim[i], b);
      for (int a = 0; a < 3; a++) assert_true(f[a] <= b[a] && b[3 + a] <= f[3 + a]);
    }
    for (int c = first; count == 0 && c < first + 2; c++)
      for (int a = 0; a < 3; a++)
        assert_true(f[a] <= t->box[6 * c + a] && t->box[6 * c + 3 + a] <= f[3 + a]);
  }
}

/* Rotate about z by angle w, translate, jitter each corner by up to 1e-3. */
static void move_soup(soup *s, unsigned long *rs) {
  double w = 6.0 * urand(rs), cw = cos(w), sw = sin(w), d[3];
  for (int a = 0; a < 3; a++) d[a] = th_rand(rs);
  for (int k = 0; k < 3 * s->n; k++) {
    double *p = s->x + 3 * (size_t)k, x = p[0], y = p[1];
    p[0] = cw * x - sw * y + d[0], p[1] = sw * x + cw * y + d[1], p[2] += d[2];
    for (int a = 0; a < 3; a++) p[a] += 1e-3 * th_rand(rs);
  }
}

static void bvh_equals_brute_force(void **state) {
  (void)state;
  unsigned long rs = 20261126;
  const int sizes[] = {1, 2, 3, 4, 5, 7, 8, 9, 16, 17, 100, 1000, 3000};
  for (size_t c = 0; c < sizeof sizes / sizeof *sizes; c++) {
    soup s;
    random_soup(&s, sizes[c], &rs);
    sw_bvh t;
    assert_int_equal(sw_bvh_build(&t, s.n, soup_box, &s), 0);
    assert_int_equal(t.n, s.n);
    assert_true(t.nnode <= 2 * ((s.n + 7) / 8)); /* ceil(n / 8) leaves */
    check_boxes(&t, &s);
    check_queries(&t, &s, &rs);
    assert_int_equal(sw_bvh_keep_boxes(&t, soup_box, &s), 0); /* queries read them now */
    assert_true(s.n == 0 || t.pbox);
    check_queries(&t, &s, &rs);
    move_soup(&s, &rs); /* the kept boxes are refreshed by the refit */
    sw_bvh_refit(&t, soup_box, &s);
    check_boxes(&t, &s);
    check_queries(&t, &s, &rs);
    sw_bvh_free(&t);
    free(s.x);
  }
}

static void bvh_stops(void **state) {
  (void)state;
  unsigned long rs = 7;
  soup s;
  random_soup(&s, 500, &rs);
  sw_bvh t;
  assert_int_equal(sw_bvh_build(&t, s.n, soup_box, &s), 0);
  int *count = calloc((size_t)s.n, sizeof(int));
  double all[6] = {-10, -10, -10, 10, 10, 10};
  hits h = {count, 0, 3};
  assert_int_equal(sw_bvh_query(&t, all, soup_box, &s, on_hit, &h), 7);
  assert_int_equal(h.total, 3);
  sw_bvh empty;
  assert_int_equal(sw_bvh_build(&empty, 0, soup_box, &s), 0);
  assert_int_equal(sw_bvh_query(&empty, all, soup_box, &s, on_hit, &h), 0);
  sw_bvh_free(&empty);
  sw_bvh_free(&t);
  free(count);
  free(s.x);
}

/* ------------------------------------------------------- a large obstacle in mesh_contact */

static int GRID = 224; /* squares per side: 2 GRID^2 = 100352 triangles; 64: 8192, whose boxes
                          the term keeps beside its tree (SW_MC_KEEP_BOXES) */
#define PI 3.14159265358979323846
#define WAVE 1e-3    /* m: the obstacle's height is WAVE sin(2 pi x / 0.1 m) sin(2 pi y / 0.1 m) */

static double grid_z(double x, double y) {
  return WAVE * sin(2.0 * PI * x / 0.1) * sin(2.0 * PI * y / 0.1);
}

/* The obstacle: a 0.4 m square about (0.1, 0.1), GRID x GRID squares split as
 * tools/make_big_obstacle.py does; its vertex (i, j) is i + (GRID + 1) j. */
static void write_grid(const char *path) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  for (int j = 0; j <= GRID; j++)
    for (int i = 0; i <= GRID; i++) {
      double x = -0.1 + 0.4 * i / GRID, y = -0.1 + 0.4 * j / GRID;
      fprintf(f, "v %.17g %.17g %.17g\n", x, y, grid_z(x, y));
    }
  for (int j = 0; j < GRID; j++)
    for (int i = 0; i < GRID; i++) {
      int a = 1 + i + (GRID + 1) * j, b = a + 1, c = a + GRID + 2, d = a + GRID + 1;
      fprintf(f, "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d);
    }
  fclose(f);
}

/* Whether pair (kind, v) is among the n active pairs. */
static int listed(const sw_mc_pair *pr, int n, int kind, const int *v) {
  for (int k = 0; k < n; k++)
    if (pr[k].kind == kind && !memcmp(pr[k].v, v, sizeof pr[k].v)) return 1;
  return 0;
}

/* Pair (kind, v) at x: whether it is within dhat; counted, and checked listed when it is. */
static int brute_pair(const double *x, int kind, const int *v, double dhat, const sw_mc_pair *pr,
                      int n) {
  const double *p[4];
  for (int k = 0; k < 4; k++) p[k] = x + 3 * (size_t)v[k];
  double d2 = kind == SW_MC_PT ? sw_d2_point_triangle(p[0], p[1], p[2], p[3], NULL, NULL)
                               : sw_d2_edge_edge(p[0], p[1], p[2], p[3], NULL, NULL);
  if (!(sqrt(d2) < dhat)) return 0;
  assert_true(listed(pr, n, kind, v));
  return 1;
}

static void obstacle_pairs(int grid) {
  GRID = grid;
  char dir[] = "/tmp/sinew_bvh_XXXXXX", path[64], err[SW_ERRSZ];
  assert_non_null(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/big.obj", dir);
  write_grid(path);
  snprintf(path, sizeof path, "%s/scene.yaml", dir);
  sw_model *m = th_scene(path, "dimension: 3\n"
                         "mesh: {grid: {size: [0.2, 0.2], vertices: [5, 5], plane: xy}}\n"
                         "material: {density: 0.1, membrane: {model: bw98, k_u: 1000, k_v: 1000, "
                         "k_shear: 50}}\n"
                         "gravity: [0, 0, -9.81]\n"
                         "integrator: {method: backward-euler, dt: 0.01}\n"
                         "obstacles: [{mesh: big.obj, translate: [0, 0, -2.5e-3]}]\n"
                         "contact: {distance: 2e-3}\nduration: 0.03\n");
  assert_non_null(m);
  const int nv = m->nv, no = (GRID + 1) * (GRID + 1);
  assert_int_equal(m->mesh_obstacle[0].mesh_nf, 2 * GRID * GRID);
  /* the term keeps no copy of the obstacle: its tree, 12 bytes a triangle, and the cloth's */
  size_t bytes = sw_mesh_contact_bytes(m), mesh = 24 * (size_t)no + 12 * 2 * GRID * GRID;
  print_message("mesh_contact term: %zu bytes for an obstacle of %zu bytes\n", bytes, mesh);
  size_t kept = 2 * GRID * GRID <= 65536 ? 48 * (size_t)(2 * GRID * GRID) : 0; /* the boxes */
  assert_true(bytes <= 12 * (size_t)(2 * GRID * GRID) + kept + 64 * (size_t)(nv + m->nf) + 1024);
  sw_data *d = sw_data_new(m);
  assert_non_null(d);
  /* the cloth's vertices at random heights over the obstacle (at its places, 2.5 mm lower) */
  double *x = calloc(3 * (size_t)(nv + no), sizeof(double));
  unsigned long rs = 11;
  memcpy(x, m->x0, 3 * (size_t)nv * sizeof(double));
  for (int i = 0; i < nv; i++)
    x[3 * i + 2] = -1e-3 + 1e-3 * urand(&rs); /* 1.5 to 2.5 mm above the mean plane */
  for (int j = 0; j < no; j++)
    for (int a = 0; a < 3; a++)
      x[3 * (size_t)(nv + j) + a] = m->mesh_obstacle[0].mesh_x[3 * j + a]; /* translated */
  int k = sw_term_find(m, "mesh_contact");
  assert_true(k >= 0);
  sw_eval ev = {.t = 0.0, .x = x, .mc = d->mc};
  double e;
  assert_int_equal(m->term[k].ops->eval(&m->term[k], m, &ev, &e), SW_OK);
  const sw_mc_pair *pr;
  int n = sw_mcontact_pairs(d->mc, &pr, NULL), found = 0, kinds[3] = {0, 0, 0};
  const double dhat = m->contact.dhat;
  for (int k2 = 0; k2 < n; k2++) kinds[pr[k2].kind == SW_MC_EE ? 2 : pr[k2].v[0] < nv ? 0 : 1]++;
  for (int i = 0; i < nv; i++) /* cloth points, obstacle triangles */
    for (int f = 0; f < 2 * GRID * GRID; f++) {
      const int *g = m->mesh_obstacle[0].mesh_face + 3 * f, v[4] = {i, nv + g[0], nv + g[1], nv + g[2]};
      found += brute_pair(x, SW_MC_PT, v, dhat, pr, n);
    }
  for (int j = 0; j < no; j++) /* obstacle points, cloth triangles */
    for (int f = 0; f < m->nf; f++) {
      const int v[4] = {nv + j, m->face[3 * f], m->face[3 * f + 1], m->face[3 * f + 2]};
      found += brute_pair(x, SW_MC_PT, v, dhat, pr, n);
    }
  sw_topology tp;
  assert_int_equal(sw_topology_build(&tp, m, err, sizeof err), 0);
  for (int c = 0; c < tp.ne; c++) /* cloth edges, obstacle edges (right, up, diagonal) */
    for (int j = 0; j < no; j++) {
      int i0 = j % (GRID + 1), j0 = j / (GRID + 1), to[3] = {j + 1, j + GRID + 1, j + GRID + 2};
      int ok[3] = {i0 < GRID, j0 < GRID, i0 < GRID && j0 < GRID};
      for (int q = 0; q < 3; q++) {
        if (!ok[q]) continue;
        int a = nv + j, b = nv + to[q], v[4] = {tp.ev[2 * c], tp.ev[2 * c + 1], a, b};
        found += brute_pair(x, SW_MC_EE, v, dhat, pr, n);
      }
    }
  sw_topology_free(&tp);
  print_message("mesh_contact on %d obstacle triangles: %d active pairs (%d cloth point, %d "
                "obstacle point, %d edge-edge), %d by brute force\n", 2 * GRID * GRID, n, kinds[0],
                kinds[1], kinds[2], found);
  assert_true(kinds[0] > 0 && kinds[1] > 0 && kinds[2] > 0);
  assert_int_equal(found, n);
  free(x);
  sw_data_free(d);
  /* three steps of a run: no crossing at the end */
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *sd = sw_sim_data(s);
  while (sd->t < m->opt.duration - 1e-9) assert_int_equal(sw_sim_step(s, err, sizeof err), 0);
  assert_int_equal(sw_mcontact_obstacle_intersections(m, sd->mc, sd->x, sd->t, NULL), 0);
  assert_true(sd->contact_count > 0);
  sw_sim_free(s);
  sw_model_free(m);
  th_remove_tree(dir);
}

static void large_obstacle(void **state) {
  (void)state;
  obstacle_pairs(224);
}

static void small_obstacle(void **state) {
  (void)state;
  obstacle_pairs(64);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(bvh_equals_brute_force),
      cmocka_unit_test(bvh_stops),
      cmocka_unit_test(large_obstacle),
      cmocka_unit_test(small_obstacle),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
