/* test_bvh.c — the bounding-volume hierarchy of models/bvh.c against brute force: on random
 * triangle soups (1 to 3000 triangles of sizes spread over four decades, some degenerate,
 * some coincident) and random query boxes (points, slabs, boxes of every size, boxes far
 * outside), a query reports exactly the triangles whose box overlaps the query's (closed
 * boxes, touching counts), each once; after the triangles move (a random rigid motion plus a
 * jitter) and the tree is refitted, again exactly; without the per-primitive test, a superset
 * with every leaf's box containing its primitives'; and a nonzero return of the visitor stops
 * the query and is returned. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "contact_geom.h"
#include "harness.h"

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
    if (i % 17 == 3) memcpy(p + 3, p, 6 * sizeof(double)); /* a point */
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
    assert_true(t.nnode <= 2 * ((s.n + 3) / 4)); /* ceil(n / 4) leaves */
    check_boxes(&t, &s);
    check_queries(&t, &s, &rs);
    move_soup(&s, &rs);
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

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(bvh_equals_brute_force),
      cmocka_unit_test(bvh_stops),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
