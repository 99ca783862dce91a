/* test_contact_cost.c — what makes contact cheap, checked against what it replaces:
 *  - the closed-form barrier blocks (models/barrier_block.c): the distance form gives the
 *    distance and gradient of models/distance.c bit for bit and its exact Hessian to round-off,
 *    on random pairs of every closest-feature type; the block is positive semi-definite (LAPACK
 *    eigenvalues) and equals LAPACK's clamped eigen-decomposition of the exact 12 x 12 barrier
 *    Hessian to 1e-10 of its largest entry, and so does its closed form (no eigen-decomposition)
 *    on the 99 % or more of the pairs with sliding closest points that it takes; the block of an
 *    edge-edge pair the mollifier scales
 *    (nearly parallel edges), clamped on the 9 dimensions a translation leaves out, equals the
 *    12 x 12 clamp likewise;
 *  - the exact intersection tests on coplanar triangles (the flat cloth's case, decided by zero
 *    determinants): small-integer triangles in a plane, against an integer separating-axis test,
 *    in the axis planes and in tilted planes (an integer linear map of the plane: exact). */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "contact_geom.h"
#include "harness.h"
#include "terms.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

/* The smallest and largest eigenvalues of the symmetric 12 x 12 H. */
static void eig_range(const double *H, double *lo, double *hi) {
  double A[144], w[12], work[12 * 64];
  int n = 12, lwork = 12 * 64, info;
  memcpy(A, H, sizeof A);
  dsyev_("N", "U", &n, A, &n, w, work, &lwork, &info);
  assert_int_equal(info, 0);
  *lo = w[0], *hi = w[11];
}

/* The reference clamp, independent of sinew's eigensolver: H's nearest PSD matrix by LAPACK's
 * dsyev, sum over positive eigenvalues of l v v^T. */
static void lapack_clamp(double *H) {
  double A[144], w[12], work[12 * 64];
  int n = 12, lwork = 12 * 64, info;
  memcpy(A, H, sizeof A);
  dsyev_("V", "U", &n, A, &n, w, work, &lwork, &info);
  assert_int_equal(info, 0);
  memset(H, 0, 144 * sizeof(double));
  for (int k = 0; k < 12; k++)
    if (w[k] > 0.0)
      for (int i = 0; i < 12; i++)
        for (int j = 0; j < 12; j++) H[i * 12 + j] += w[k] * A[k * 12 + i] * A[k * 12 + j];
}

static double max_abs(const double *a, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s = fmax(s, fabs(a[i]));
  return s;
}

/* A random pair near contact: kind 0 point-triangle, 1 edge-edge; every few draws places the
 * point near a triangle's vertex or edge, or the edges end to end, so every type occurs. */
static void random_pair(unsigned long *rs, int kind, int rep, double *x) {
  for (int i = 0; i < 12; i++) x[i] = 0.3 * th_rand(rs);
  int near = rep % 4, j = 1 + rep % 3;
  if (near == 1) /* the point (or a0) just beside a vertex of the other */
    for (int a = 0; a < 3; a++) x[a] = x[3 * (kind ? 2 : j) + a] + 0.02 * th_rand(rs);
  if (near == 2) /* beside an edge's midpoint */
    for (int a = 0; a < 3; a++)
      x[a] = 0.5 * (x[3 * j + a] + x[3 * (j % 3 + 1) + a]) + 0.02 * th_rand(rs);
}

/* The form gives distance.c's d2 and gradient exactly and its Hessian to round-off. */
static void form_matches_distance(void **st) {
  (void)st;
  unsigned long rs = 5;
  int types[2][9] = {{0}};
  for (int rep = 0; rep < 4000; rep++) {
    int kind = rep % 2;
    double x[12], g[12], H[144], K[144];
    random_pair(&rs, kind, rep / 2, x);
    double d2 = kind ? sw_d2_edge_edge(x, x + 3, x + 6, x + 9, g, H)
                     : sw_d2_point_triangle(x, x + 3, x + 6, x + 9, g, H);
    types[kind][kind ? (int)sw_edge_edge_type(x, x + 3, x + 6, x + 9)
                     : (int)sw_point_triangle_type(x, x + 3, x + 6, x + 9)]++;
    sw_pair_form pf;
    assert_true(sw_pair_d2_form(kind, x, &pf) == d2);
    for (int i = 0; i < 12; i++) assert_true(pf.g[i] == g[i]); /* -0 == 0 */
    /* within reach the near form is the whole form, bit for bit; beyond it the distance */
    sw_pair_form pn, pb;
    memset(&pb, 0xff, sizeof pb);
    assert_true(sw_pair_d2_form_near(kind, x, nextafter(d2, INFINITY), &pn) == d2);
    assert_memory_equal(&pn, &pf, sizeof pf);
    assert_true(sw_pair_d2_form_near(kind, x, d2, &pb) == d2 && pb.d2 == d2);
    sw_pair_hess_d2(&pf, K);
    double err = 0.0;
    for (int i = 0; i < 144; i++) err = fmax(err, fabs(K[i] - H[i]));
    if (!(err <= 1e-9 * fmax(max_abs(H, 144), 1.0)))
      print_error("kind %d rep %d: Hessian error %g of %g\n", kind, rep, err, max_abs(H, 144));
    assert_true(err <= 1e-9 * fmax(max_abs(H, 144), 1.0));
  }
  for (int t = 0; t < 7; t++) assert_true(types[0][t] > 0);
  for (int t = 0; t < 9; t++) assert_true(types[1][t] > 0);
}

/* The block: the exact barrier Hessian clamped (a 12 x 12 eigen-decomposition by LAPACK), to
 * round-off, so positive semi-definite. */
static void block_is_clamp(void **st) {
  (void)st;
  unsigned long rs = 11;
  int n = 0, indefinite = 0, rank[6] = {0}, sliding = 0, closed = 0;
  for (int rep = 0; rep < 40000 && n < 2000; rep++) {
    int kind = rep % 2;
    double x[12], g2[12], H2[144], B[144], E[144];
    random_pair(&rs, kind, rep / 2, x);
    sw_pair_form pf;
    double d2 = sw_pair_d2_form(kind, x, &pf), xi = rep % 3 ? 0.0 : 0.3 * sqrt(d2);
    double dhat = 0.2 * th_rand(&rs) + 0.25, s = d2 - xi * xi;
    double shat = (xi + dhat) * (xi + dhat) - xi * xi;
    if (!(s > 1e-4 * shat && s < shat)) continue;
    n++;
    kind ? sw_d2_edge_edge(x, x + 3, x + 6, x + 9, g2, H2)
         : sw_d2_point_triangle(x, x + 3, x + 6, x + 9, g2, H2);
    double db, d2b, w = 0.5 + th_rand(&rs) * 0.4;
    sw_barrier(s, shat, &db, &d2b);
    sw_barrier_of(12, s, g2, H2, shat, NULL, E); /* the exact barrier Hessian */
    for (int i = 0; i < 144; i++) E[i] *= w;
    double elo, ehi, lo, hi;
    eig_range(E, &elo, &ehi);
    indefinite += elo < -1e-8 * ehi;
    assert_int_equal(sw_pair_barrier_block(&pf, db, d2b, w, B), 0);
    lapack_clamp(E);
    double err = 0.0;
    for (int i = 0; i < 144; i++) err = fmax(err, fabs(B[i] - E[i]));
    if (!(err <= 1e-10 * max_abs(E, 144)))
      print_error("kind %d rep %d: block error %g of %g\n", kind, rep, err, max_abs(E, 144));
    assert_true(err <= 1e-10 * max_abs(E, 144));
    eig_range(B, &lo, &hi);
    assert_true(lo >= -1e-13 * hi);
    rank[3 + pf.k]++;
    if (pf.k >= 1) { /* the closed form alone (no eigen-decomposition), where it applies */
      sliding++;
      if (!sw_pair_clamp_closed(&pf, db, d2b, w, B)) continue;
      closed++;
      err = 0.0;
      for (int i = 0; i < 144; i++) err = fmax(err, fabs(B[i] - E[i]));
      if (!(err <= 1e-10 * max_abs(E, 144)))
        print_error("kind %d rep %d: closed form error %g of %g\n", kind, rep, err, max_abs(E, 144));
      assert_true(err <= 1e-10 * max_abs(E, 144));
    }
  }
  assert_int_equal(n, 2000);
  assert_true(indefinite > 1000); /* the exact blocks are indefinite: the clamp has work */
  for (int r = 3; r <= 5; r++) assert_true(rank[r] > 50); /* every form's span */
  assert_true(closed >= sliding - sliding / 100); /* the closed form gives 99 % of them */
}


/* The mollified edge-edge block (nearly parallel edges: the product of the mollifier and the
 * barrier, as models/mesh_contact.c forms it) clamped on its 9 translation-free dimensions is
 * the 12 x 12 clamp, to round-off. */
static void clamp_free_is_clamp(void **st) {
  (void)st;
  unsigned long rs = 5;
  int n = 0;
  for (int rep = 0; rep < 4000 && n < 500; rep++) {
    double x[12], r[12], g2[12], H2[144], mg[12], mH[144], bg[12], bH[144], g[12], H[144];
    for (int i = 0; i < 6; i++) x[i] = 0.3 * th_rand(&rs);
    double off[3] = {0.05 * th_rand(&rs), 0.05 * th_rand(&rs), 0.05 * th_rand(&rs)};
    for (int i = 0; i < 6; i++) /* b: a moved, and turned by up to about 1e-2 rad */
      x[6 + i] = x[i] + off[i % 3] + 0.004 * th_rand(&rs) * (i < 3 ? 1.0 : -1.0);
    memcpy(r, x, sizeof r);
    double d2 = sw_d2_edge_edge(x, x + 3, x + 6, x + 9, g2, H2), shat = 4.0 * d2, db, d2b;
    double eps = sw_ee_mollifier_eps(r, r + 3, r + 6, r + 9) * 400.0;
    double mo = sw_ee_mollifier(x, x + 3, x + 6, x + 9, eps, mg, mH);
    if (!(mo < 1.0) || !(d2 > 0.0)) continue;
    double b = sw_barrier(d2, shat, &db, &d2b);
    sw_barrier_of(12, d2, g2, H2, shat, bg, bH);
    sw_product_derivs(12, mo, mg, mH, b, bg, bH, g, H);
    double E[144], lo, hi, err = 0.0;
    memcpy(E, H, sizeof E);
    assert_int_equal(sw_pair_clamp_free(H), 0);
    lapack_clamp(E);
    for (int i = 0; i < 144; i++) err = fmax(err, fabs(H[i] - E[i]));
    assert_true(err <= 1e-10 * max_abs(E, 144));
    eig_range(H, &lo, &hi);
    assert_true(lo >= -1e-12 * hi);
    n++;
  }
  assert_int_equal(n, 500);
}

/* ---------------------------------------------------------------- coplanar intersections */

typedef long long ll;

/* Whether the closed 2D triangles p and q (integer coordinates) meet: no edge normal of either
 * separates them strictly (the separating axis theorem for convex polygons). */
static int sat_meet(const ll p[3][2], const ll q[3][2]) {
  const ll(*t[2])[2] = {p, q};
  for (int s = 0; s < 2; s++)
    for (int e = 0; e < 3; e++) {
      const ll *a = t[s][e], *b = t[s][(e + 1) % 3];
      ll nx = b[1] - a[1], ny = a[0] - b[0];
      if (nx == 0 && ny == 0) continue;
      ll lo[2] = {LLONG_MAX, LLONG_MAX}, hi[2] = {LLONG_MIN, LLONG_MIN};
      for (int u = 0; u < 2; u++)
        for (int i = 0; i < 3; i++) {
          ll d = nx * t[u][i][0] + ny * t[u][i][1];
          lo[u] = d < lo[u] ? d : lo[u], hi[u] = d > hi[u] ? d : hi[u];
        }
      if (hi[0] < lo[1] || hi[1] < lo[0]) return 0;
    }
  return 1;
}

/* 2D point (u, v) into 3D: plane 0, 1, 2 the axis planes z = 0, x = 0, y = 0; plane 3 the
 * tilted z = u + 2 v (x = u, y = v: exact in doubles). */
static void embed(int plane, const ll *p, double *x) {
  double u = (double)p[0], v = (double)p[1];
  if (plane == 0) x[0] = u, x[1] = v, x[2] = 0.0;
  if (plane == 1) x[0] = 0.0, x[1] = u, x[2] = v;
  if (plane == 2) x[0] = v, x[1] = 0.0, x[2] = u;
  if (plane == 3) x[0] = u, x[1] = v, x[2] = u + 2.0 * v;
}

static void coplanar_triangles(void **st) {
  (void)st;
  unsigned long rs = 3;
  int meet = 0, apart = 0;
  for (int rep = 0; rep < 40000; rep++) {
    ll p[3][2], q[3][2];
    for (int i = 0; i < 3; i++)
      for (int a = 0; a < 2; a++) {
        p[i][a] = (ll)floor(2.5 * (th_rand(&rs) + 1.0));
        q[i][a] = (ll)floor(2.5 * (th_rand(&rs) + 1.0));
      }
    ll ap = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    ll aq = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
    if (ap == 0 || aq == 0) continue; /* the separating-axis test wants proper triangles */
    int want = sat_meet(p, q);
    for (int plane = 0; plane < 4; plane++) {
      double x[6][3];
      for (int i = 0; i < 3; i++) embed(plane, p[i], x[i]), embed(plane, q[i], x[3 + i]);
      int got = sw_triangles_intersect(x[0], x[1], x[2], x[3], x[4], x[5]);
      if (got != want) print_error("rep %d plane %d: %d, want %d\n", rep, plane, got, want);
      assert_int_equal(got, want);
    }
    meet += want, apart += !want;
  }
  assert_true(meet > 1000 && apart > 1000);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(form_matches_distance),
      cmocka_unit_test(block_is_clamp),
      cmocka_unit_test(clamp_free_is_clamp),
      cmocka_unit_test(coplanar_triangles),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
