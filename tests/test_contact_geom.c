/* test_contact_geom.c — the geometry of contact (models/contact_geom.h):
 *  - every distance type (point-point ... line-line, each closest-feature case of point-triangle
 *    and edge-edge) against central finite differences of its value and gradient, at random
 *    states and near-degenerate ones (nearly parallel edges, a point near a triangle's edge, a
 *    point exactly above a vertex), and its value against a dense sampling of the primitives;
 *  - the cheap separation test of two primitives never calls a pair farther apart than it is;
 *  - IPC's mollifier, the mollified edge-edge distance and the barrier likewise, and their
 *    12 x 12 Hessian blocks made PSD by sw_psd_project (LAPACK eigenvalues);
 *  - additive CCD: a trajectory through a triangle or across an edge is always caught (toi
 *    before the crossing, found by the roots of the coplanarity cubic), the separation at toi
 *    and at every earlier sample is above the minimum, and the gap at toi keeps the scaling;
 *  - the broad phase finds exactly the pairs an O(n^2) box check finds, each once, and a second
 *    query of the same size allocates nothing;
 *  - the intersection predicates: constructed touching and degenerate cases, agreement with an
 *    independent rational test on small-integer coordinates, orient3d exact where floating
 *    point fails, and the mesh count against all pairs. */
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

/* ------------------------------------------------------------------ finite differences */

typedef double (*packed_fn)(const double *x, double *g, double *H);
typedef int (*type_fn)(const double *x);

static double eps_x_now; /* the mollifier threshold of the wrappers below, m^4 */

static double f_pp(const double *x, double *g, double *H) { return sw_d2_point_point(x, x + 3, g, H); }
static double f_pl(const double *x, double *g, double *H) {
  return sw_d2_point_line(x, x + 3, x + 6, g, H);
}
static double f_pe(const double *x, double *g, double *H) {
  return sw_d2_point_edge(x, x + 3, x + 6, g, H);
}
static double f_pt(const double *x, double *g, double *H) {
  return sw_d2_point_triangle(x, x + 3, x + 6, x + 9, g, H);
}
static double f_ee(const double *x, double *g, double *H) {
  return sw_d2_edge_edge(x, x + 3, x + 6, x + 9, g, H);
}
static double f_moll(const double *x, double *g, double *H) {
  return sw_ee_mollifier(x, x + 3, x + 6, x + 9, eps_x_now, g, H);
}
static double f_ee_moll(const double *x, double *g, double *H) {
  return sw_d2_edge_edge_mollified(x, x + 3, x + 6, x + 9, eps_x_now, g, H);
}
static int ty_pe(const double *x) { return (int)sw_point_edge_type(x, x + 3, x + 6); }
static int ty_pt(const double *x) { return (int)sw_point_triangle_type(x, x + 3, x + 6, x + 9); }
static int ty_ee(const double *x) { return (int)sw_edge_edge_type(x, x + 3, x + 6, x + 9); }

/* Relative errors of the gradient (against differences of f) and the Hessian (against
 * differences of the gradient) with step h; 1 when the closest-feature type changes within the
 * step (the Hessian jumps there): the sample is skipped. */
static int fd_errors(packed_fn f, type_fn ty, int n, const double *x, double h, double *eg,
                     double *eH) {
  double g[12], H[144], gp[12], gm[12], y[12], gmax = 1e-300, Hmax = 1e-300;
  f(x, g, H);
  *eg = *eH = 0.0;
  for (int i = 0; i < n; i++) gmax = fmax(gmax, fabs(g[i]));
  for (int i = 0; i < n * n; i++) Hmax = fmax(Hmax, fabs(H[i]));
  for (int i = 0; i < n; i++) {
    memcpy(y, x, sizeof(double) * (size_t)n);
    y[i] = x[i] + h;
    if (ty && ty(y) != ty(x)) return 1;
    double fp = f(y, gp, NULL);
    y[i] = x[i] - h;
    if (ty && ty(y) != ty(x)) return 1;
    double fm = f(y, gm, NULL);
    *eg = fmax(*eg, fabs((fp - fm) / (2 * h) - g[i]) / gmax);
    for (int j = 0; j < n; j++) *eH = fmax(*eH, fabs((gp[j] - gm[j]) / (2 * h) - H[i * n + j]) / Hmax);
  }
  return 0;
}

static void assert_fd(packed_fn f, type_fn ty, int n, const double *x, double h, double tol) {
  double eg, eH;
  if (fd_errors(f, ty, n, x, h, &eg, &eH)) return;
  if (!(eg < tol && eH < tol)) print_error("gradient error %.3g, Hessian error %.3g\n", eg, eH);
  assert_true(eg < tol);
  assert_true(eH < tol);
}

static void rand_pts(unsigned long *rs, double *x, int n, double scale) {
  for (int i = 0; i < n; i++) x[i] = scale * th_rand(rs);
}

/* ----------------------------------------------------------------------- sampled distances */

static double sq(double a) { return a * a; }
static double d2pts(const double *a, const double *b) { return sq(a[0] - b[0]) + sq(a[1] - b[1]) + sq(a[2] - b[2]); }
static double len(const double *a, const double *b) { return sqrt(d2pts(a, b)); }

/* min over a K x K grid of points of the triangle (or pairs of points of two edges). */
enum { K = 200 };
static double sampled_pt(const double *x) {
  double best = INFINITY, q[3];
  for (int i = 0; i <= K; i++)
    for (int j = 0; i + j <= K; j++) {
      double u = (double)i / K, v = (double)j / K;
      for (int a = 0; a < 3; a++) q[a] = (1 - u - v) * x[3 + a] + u * x[6 + a] + v * x[9 + a];
      best = fmin(best, d2pts(x, q));
    }
  return best;
}

static double sampled_ee(const double *x) {
  double best = INFINITY, p[3], q[3];
  for (int i = 0; i <= K; i++)
    for (int j = 0; j <= K; j++) {
      double s = (double)i / K, t = (double)j / K;
      for (int a = 0; a < 3; a++)
        p[a] = (1 - s) * x[a] + s * x[3 + a], q[a] = (1 - t) * x[6 + a] + t * x[9 + a];
      best = fmin(best, d2pts(p, q));
    }
  return best;
}

/* d2 is the minimum: no sample is closer, and the nearest sample is within a grid spacing. */
static void assert_is_min(double d2, double sampled, double spacing) {
  assert_true(d2 <= sampled * (1 + 1e-12) + 1e-15);
  assert_true(sqrt(sampled) - sqrt(d2) <= spacing);
}

/* ---------------------------------------------------------------------- distance tests */

static void distances_simple(void **st) {
  (void)st;
  unsigned long rs = 11;
  double x[12];
  for (int rep = 0; rep < 200; rep++) {
    rand_pts(&rs, x, 12, 1.0);
    assert_fd(f_pp, NULL, 6, x, 1e-6, 1e-7);
    assert_fd(f_pl, NULL, 9, x, 1e-6, 1e-6);
    assert_fd(f_pe, ty_pe, 9, x, 1e-6, 1e-6);
  }
  /* values: a point above the middle of an edge, a point beyond its end */
  double p[3] = {0.5, 2.0, 0.0}, e0[3] = {0, 0, 0}, e1[3] = {1, 0, 0}, q[3] = {3, 0, 4};
  assert_true(fabs(sw_d2_point_edge(p, e0, e1, NULL, NULL) - 4.0) < 1e-15);
  assert_true(fabs(sw_d2_point_edge(q, e0, e1, NULL, NULL) - 20.0) < 1e-14);
  assert_int_equal(sw_point_edge_type(q, e0, e1), SW_PE_E1);
}

/* Random states until every closest-feature type of point-triangle has been checked 20 times. */
static void distances_point_triangle(void **st) {
  (void)st;
  unsigned long rs = 12;
  int seen[7] = {0};
  double x[12];
  for (int rep = 0; rep < 200000; rep++) {
    rand_pts(&rs, x, 3, 1.6);
    rand_pts(&rs, x + 3, 9, 1.0);
    int t = ty_pt(x);
    if (seen[t] >= 20) continue;
    assert_fd(f_pt, ty_pt, 12, x, 1e-6, 2e-6);
    if (seen[t] < 3) {
      double L = fmax(len(x + 3, x + 6), fmax(len(x + 6, x + 9), len(x + 9, x + 3)));
      assert_is_min(f_pt(x, NULL, NULL), sampled_pt(x), 2.0 * L / K);
    }
    seen[t]++;
  }
  for (int t = 0; t < 7; t++) assert_int_equal(seen[t], 20);
}

static void distances_edge_edge(void **st) {
  (void)st;
  unsigned long rs = 13;
  int seen[9] = {0};
  double x[12];
  for (int rep = 0; rep < 400000; rep++) {
    rand_pts(&rs, x, 12, 1.0);
    if (rep % 3 == 0) /* short second edges make the end-point cases common */
      for (int a = 0; a < 3; a++) x[9 + a] = x[6 + a] + 0.2 * th_rand(&rs);
    int t = ty_ee(x);
    if (seen[t] >= 20) continue;
    assert_fd(f_ee, ty_ee, 12, x, 1e-6, 2e-6);
    if (seen[t] < 3) {
      double L = fmax(len(x, x + 3), len(x + 6, x + 9));
      assert_is_min(f_ee(x, NULL, NULL), sampled_ee(x), 2.0 * L / K);
    }
    seen[t]++;
  }
  for (int t = 0; t < 9; t++) assert_int_equal(seen[t], 20);
}

/* sw_pair_apart never calls a pair farther apart than r when its distance is not: random
 * pairs at random separations, r just below and above their distance, and it does call some
 * apart (it is not vacuous). */
static void pair_apart(void **st) {
  (void)st;
  unsigned long rs = 17;
  int called[2] = {0, 0};
  for (int rep = 0; rep < 200000; rep++) {
    int ee = rep % 2;
    double x[12];
    rand_pts(&rs, x, 12, 0.02); /* primitives of about 2 cm */
    double shift = 0.05 * th_rand(&rs);
    for (int k = ee ? 2 : 1; k < 4; k++) x[3 * k] += shift; /* the second primitive moved off */
    double d = sqrt(ee ? sw_d2_edge_edge(x, x + 3, x + 6, x + 9, NULL, NULL)
                       : sw_d2_point_triangle(x, x + 3, x + 6, x + 9, NULL, NULL));
    assert_false(sw_pair_apart(ee, x, d * (1.0 + 1e-12) + 1e-15));
    double r = d * (0.5 + 0.5 * (th_rand(&rs) + 1.0) / 2.0);
    if (sw_pair_apart(ee, x, r)) called[ee]++, assert_true(d > r);
  }
  print_message("pair_apart: point-triangle %d, edge-edge %d of 100000 called apart\n", called[0],
                called[1]);
  assert_true(called[0] > 10000 && called[1] > 10000);
}

/* Near-degenerate states: nearly parallel edges (line-line and end-point cases), a point near
 * an edge of the triangle just inside and just outside, a point exactly above a vertex. */
static void distances_degenerate(void **st) {
  (void)st;
  for (int k = 2; k <= 5; k++) { /* angle 10^-k rad, overlapping and offset */
    double th = pow(10.0, -k);
    double c = 0.5 * cos(th), sn = 0.5 * sin(th); /* b crosses 1e-3 above a's middle */
    double x[12] = {0, 0, 0, 1, 0, 0, 0.5 - c, -sn, 0.001, 0.5 + c, sn, 0.001};
    double h = 1e-4 * th; /* the Hessian varies on the scale of the angle */
    assert_int_equal(ty_ee(x), SW_EE_LINES);
    assert_fd(f_ee, ty_ee, 12, x, h, 1e-5);
    x[6] += 1.5, x[9] += 1.5; /* no overlap: an end point is closest */
    assert_true(ty_ee(x) != SW_EE_LINES);
    assert_fd(f_ee, ty_ee, 12, x, 1e-6, 1e-6);
  }
  double t[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (int s = -1; s <= 1; s += 2) { /* 1e-9 inside and outside edge t0t1 */
    double x[12] = {0.4, s * 1e-9, 1e-3};
    memcpy(x + 3, t, sizeof t);
    assert_int_equal(ty_pt(x), s > 0 ? SW_PT_PLANE : SW_PT_E01);
    assert_fd(f_pt, ty_pt, 12, x, 1e-12, 1e-4);
    assert_true(fabs(f_pt(x, NULL, NULL) - (1e-6 + (s < 0 ? 1e-18 : 0.0))) < 1e-20);
  }
  /* exactly above t0: the plane, edge and vertex forms agree in value and gradient */
  double x[12] = {0, 0, 0.3}, g[12], gv[12];
  memcpy(x + 3, t, sizeof t);
  assert_true(fabs(f_pt(x, g, NULL) - 0.09) < 1e-16);
  sw_d2_point_point(x, x + 3, gv, NULL);
  for (int a = 0; a < 6; a++) assert_true(fabs(g[a] - gv[a]) < 1e-15);
  for (int a = 6; a < 12; a++) assert_true(fabs(g[a]) < 1e-15);
  double eg, eH;
  fd_errors(f_pt, NULL, 12, x, 1e-7, &eg, &eH); /* C1 across the type boundaries */
  assert_true(eg < 1e-6);
}

/* ------------------------------------------------------------------ mollifier and barrier */

static void mollifier(void **st) {
  (void)st;
  unsigned long rs = 21;
  int active = 0;
  for (int rep = 0; rep < 400; rep++) {
    double x[12], th = pow(10.0, -1.0 - 3.0 * (rep % 40) / 40.0); /* 0.1 ... 1e-4 rad */
    rand_pts(&rs, x, 6, 1.0);
    double d[3] = {x[3] - x[0], x[4] - x[1], x[5] - x[2]}, w[3] = {th_rand(&rs), th_rand(&rs), th_rand(&rs)};
    for (int a = 0; a < 3; a++) x[6 + a] = x[a] + 0.3 * th_rand(&rs) + 0.2;
    for (int a = 0; a < 3; a++) x[9 + a] = x[6 + a] + d[a] + th * len(x, x + 3) * w[a];
    eps_x_now = sw_ee_mollifier_eps(x, x + 3, x + 6, x + 9) * (1.0 + th_rand(&rs) * 0.5);
    double m = f_moll(x, NULL, NULL);
    active += m < 1.0;
    assert_true(m >= 0.0 && m <= 1.0);
    double h = 1e-5 * th * len(x, x + 3);
    assert_fd(f_moll, NULL, 12, x, h, 1e-5);
    assert_fd(f_ee_moll, ty_ee, 12, x, h, 1e-5);
  }
  assert_true(active > 100);
  /* c = 0 (parallel): m = 0 with zero gradient; c >= eps_x: m = 1 */
  double par[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 1, 0}, g[12];
  assert_true(sw_ee_mollifier(par, par + 3, par + 6, par + 9, 1e-3, g, NULL) == 0.0);
  for (int i = 0; i < 12; i++) assert_true(g[i] == 0.0);
  par[10] = 2.0;
  assert_true(sw_ee_mollifier(par, par + 3, par + 6, par + 9, 1e-3, g, NULL) == 1.0);
}

static void barrier(void **st) {
  (void)st;
  const double dhat2 = 1e-4;
  for (int i = 1; i < 200; i++) {
    double d2 = dhat2 * i / 200.0, h = 1e-6 * d2, b1, b2, p1, m1;
    double b = sw_barrier(d2, dhat2, &b1, &b2);
    double bp = sw_barrier(d2 + h, dhat2, &p1, NULL), bm = sw_barrier(d2 - h, dhat2, &m1, NULL);
    assert_true(b > 0.0 && b1 < 0.0 && b2 > 0.0); /* decreasing and convex */
    assert_true(fabs((bp - bm) / (2 * h) - b1) <= 1e-7 * fabs(b1) + 1e-16);
    assert_true(fabs((p1 - m1) / (2 * h) - b2) <= 1e-6 * fabs(b2) + 1e-12);
  }
  double b1, b2; /* C2 at dhat2, infinite at contact */
  assert_true(sw_barrier(dhat2 * (1 - 1e-6), dhat2, &b1, &b2) < 1e-20);
  assert_true(fabs(b1) < 1e-14 && fabs(b2) < 1e-5);
  assert_true(sw_barrier(dhat2, dhat2, &b1, &b2) == 0.0 && b1 == 0.0 && b2 == 0.0);
  assert_true(isinf(sw_barrier(0.0, dhat2, NULL, NULL)) && isinf(sw_barrier(-1.0, dhat2, NULL, NULL)));
}

/* The barrier of a point-triangle or edge-edge distance (mollified) as the contact term will
 * use it: gradient and Hessian by differences, and its Hessian made PSD by sw_psd_project
 * (12 x 12) has no eigenvalue below -1e-10 times the largest. */
static double dhat2_now = 0.04;
static double f_bpt(const double *x, double *g, double *H) {
  double g2[12], H2[144], d2 = f_pt(x, g2, H ? H2 : NULL);
  return sw_barrier_of(12, d2, g2, H2, dhat2_now, g, H);
}
static double f_bee(const double *x, double *g, double *H) {
  double g2[12], H2[144], gb[12], Hb[144], gm[12], Hm[144];
  double b = sw_barrier_of(12, f_ee(x, g2, H ? H2 : NULL), g2, H2, dhat2_now, gb, H ? Hb : NULL);
  double m = f_moll(x, gm, H ? Hm : NULL);
  return sw_product_derivs(12, m, gm, Hm, b, gb, Hb, g, H);
}

static double min_eig_ratio(const double *H, int n) {
  double A[144], w[12], work[64];
  int lwork = 64, info;
  memcpy(A, H, sizeof(double) * (size_t)(n * n));
  dsyev_("N", "U", &n, A, &n, w, work, &lwork, &info);
  assert_int_equal(info, 0);
  return w[0] / fmax(fabs(w[0]), fabs(w[n - 1]));
}

static void barrier_blocks(void **st) {
  (void)st;
  unsigned long rs = 31;
  int indefinite = 0, n = 0;
  for (int rep = 0; rep < 20000 && n < 200; rep++) {
    double x[12], H[144];
    rand_pts(&rs, x, 12, 0.3);
    eps_x_now = sw_ee_mollifier_eps(x, x + 3, x + 6, x + 9);
    packed_fn f = rep % 2 ? f_bpt : f_bee;
    type_fn ty = rep % 2 ? ty_pt : ty_ee;
    double d2 = rep % 2 ? f_pt(x, NULL, NULL) : f_ee(x, NULL, NULL);
    if (!(d2 < dhat2_now && d2 > 1e-4 * dhat2_now)) continue;
    n++;
    assert_fd(f, ty, 12, x, 1e-7, 1e-5);
    f(x, NULL, H);
    indefinite += min_eig_ratio(H, 12) < -1e-8;
    for (int mode = SW_FILTER_CLAMP; mode <= SW_FILTER_ABS; mode++) {
      double P[144];
      memcpy(P, H, sizeof P);
      assert_int_equal(sw_psd_project(P, 12, mode), 0);
      assert_true(min_eig_ratio(P, 12) > -1e-10);
    }
  }
  assert_int_equal(n, 200);
  assert_true(indefinite > 20); /* the filter had work to do */
}

/* ------------------------------------------------------------------------------------ CCD */

typedef double (*ccd_fn)(const double *, const double *, double, double);

static void lerp(int n, const double *x0, const double *x1, double t, double *x) {
  for (int i = 0; i < n; i++) x[i] = x0[i] + t * (x1[i] - x0[i]);
}

static double dist_at(packed_fn d2, int n, const double *x0, const double *x1, double t) {
  double x[12];
  lerp(n, x0, x1, t, x);
  return sqrt(d2(x, NULL, NULL));
}

/* Coplanarity volume of the four moving vertices: ((x1 - x0) x (x2 - x0)) . (x3 - x0) for a
 * point-triangle (p, t0..t2 -> t0, t1, t2, p) or edge-edge pair; the roots of this cubic in t
 * are the only times the primitives can meet. */
static double volume_at(int pt, const double *x0, const double *x1, double t) {
  double x[12], u[3], v[3], w[3];
  lerp(12, x0, x1, t, x);
  const double *o = pt ? x + 3 : x, *A = pt ? x + 6 : x + 3, *B = pt ? x + 9 : x + 6,
               *C = pt ? x : x + 9;
  for (int a = 0; a < 3; a++) u[a] = A[a] - o[a], v[a] = B[a] - o[a], w[a] = C[a] - o[a];
  return (u[1] * v[2] - u[2] * v[1]) * w[0] + (u[2] * v[0] - u[0] * v[2]) * w[1] +
         (u[0] * v[1] - u[1] * v[0]) * w[2];
}

/* The first time in [0, 1] the primitives meet: a sign change of the volume, bisected, where
 * the distance is zero to rounding; 2 when there is none. */
static double first_crossing(int pt, const double *x0, const double *x1) {
  packed_fn d2 = pt ? f_pt : f_ee;
  const int N = 4000;
  double va = volume_at(pt, x0, x1, 0.0);
  for (int i = 1; i <= N; i++) {
    double ta = (double)(i - 1) / N, tb = (double)i / N, vb = volume_at(pt, x0, x1, tb);
    if (va * vb <= 0.0) {
      for (int it = 0; it < 60; it++) {
        double tm = 0.5 * (ta + tb), vm = volume_at(pt, x0, x1, tm);
        if ((vm <= 0.0) == (va <= 0.0)) ta = tm, va = vm;
        else tb = tm;
      }
      if (dist_at(d2, 12, x0, x1, tb) < 1e-9) return tb;
      va = volume_at(pt, x0, x1, (double)i / N);
    } else va = vb;
  }
  return 2.0;
}

/* toi is safe (or 0 for a start within dmin): the separation is above dmin at toi and at 1000 samples before it, and the gap
 * at toi keeps SW_CCD_SCALE of the starting gap. */
static void assert_safe(packed_fn d2, int n, const double *x0, const double *x1, double dmin,
                        double toi) {
  double g0 = dist_at(d2, n, x0, x1, 0.0) - dmin, gt = dist_at(d2, n, x0, x1, toi) - dmin;
  assert_true(toi >= 0.0 && toi <= 1.0);
  if (g0 <= 0.0) { /* starts within dmin: no step is safe */
    assert_true(toi == 0.0);
    return;
  }
  assert_true(gt > 0.0);
  assert_true(gt >= SW_CCD_SCALE * g0 * (1 - 1e-9));
  for (int i = 0; i < 1000; i++) assert_true(dist_at(d2, n, x0, x1, toi * i / 1000.0) > dmin);
}

/* Trajectories built to cross: the point meets the triangle's interior (or the edges meet
 * inside both) at a chosen time tc; CCD stops before tc. */
static void ccd_crossing(void **st) {
  (void)st;
  unsigned long rs = 41;
  for (int rep = 0; rep < 400; rep++) {
    int pt = rep % 2;
    double x0[12], x1[12], xc[12], tc = 0.05 + 0.9 * (th_rand(&rs) + 1) / 2;
    rand_pts(&rs, x0 + 3 * pt, 12 - 3 * pt, 1.0); /* the other primitive's start */
    rand_pts(&rs, x1 + 3 * pt, 12 - 3 * pt, 1.0);
    for (int i = 3 * pt; i < 12; i++) x1[i] = x0[i] + 0.8 * x1[i];
    lerp(12, x0, x1, tc, xc);
    double u = 0.1 + 0.35 * (th_rand(&rs) + 1) / 2, v = 0.1 + 0.35 * (th_rand(&rs) + 1) / 2, m[3];
    const double *o = pt ? xc + 3 : xc + 6; /* meeting point on the triangle or edge b */
    for (int a = 0; a < 3; a++)
      m[a] = pt ? (1 - u - v) * o[a] + u * xc[6 + a] + v * xc[9 + a] : (1 - u) * o[a] + u * xc[9 + a];
    double dir[3];
    rand_pts(&rs, dir, 3, 1.0);
    if (pt) /* the point: through m at tc */
      for (int a = 0; a < 3; a++) x0[a] = m[a] - tc * dir[a], x1[a] = m[a] + (1 - tc) * dir[a];
    else { /* edge a: a0 moved so that its point at parameter v is m at tc */
      double r[3];
      for (int a = 0; a < 3; a++) r[a] = xc[3 + a] - m[a]; /* a1 - m at tc */
      for (int a = 0; a < 3; a++) {
        double a0c = m[a] - v / (1 - v) * r[a];
        x0[a] = a0c - tc * dir[a], x1[a] = a0c + (1 - tc) * dir[a];
      }
    }
    packed_fn d2 = pt ? f_pt : f_ee;
    assert_true(dist_at(d2, 12, x0, x1, tc) < 1e-12);
    for (int k = 0; k < 2; k++) {
      double dmin = k ? 1e-3 : 0.0;
      double toi = (pt ? sw_ccd_point_triangle : sw_ccd_edge_edge)(x0, x1, dmin, 1.0);
      assert_true(toi < tc);
      assert_safe(d2, 12, x0, x1, dmin, toi);
    }
  }
}

/* Random trajectories: never toi = 1 when the primitives meet within the step. */
static void ccd_random(void **st) {
  (void)st;
  unsigned long rs = 42;
  int crossings = 0;
  for (int rep = 0; rep < 600; rep++) {
    int pt = rep % 2;
    double x0[12], x1[12];
    rand_pts(&rs, x0, 12, 1.0);
    rand_pts(&rs, x1, 12, 1.5);
    for (int i = 0; i < 12; i++) x1[i] += x0[i];
    double tc = first_crossing(pt, x0, x1);
    double toi = (pt ? sw_ccd_point_triangle : sw_ccd_edge_edge)(x0, x1, 0.0, 1.0);
    if (tc <= 1.0) crossings++, assert_true(toi < tc);
    assert_safe(pt ? f_pt : f_ee, 12, x0, x1, 0.0, toi);
  }
  assert_true(crossings > 50);
}

/* Point-point and point-edge, no motion, tmax, and a start within dmin. */
static void ccd_small(void **st) {
  (void)st;
  unsigned long rs = 43;
  for (int rep = 0; rep < 400; rep++) {
    int pe = rep % 2, n = pe ? 9 : 6;
    double x0[9], x1[9];
    rand_pts(&rs, x0, n, 1.0);
    rand_pts(&rs, x1, n, 1.0);
    for (int i = 0; i < n; i++) x1[i] = x0[i] + 2.0 * x1[i];
    double toi = (pe ? sw_ccd_point_edge : sw_ccd_point_point)(x0, x1, 0.05, 1.0);
    assert_safe(pe ? f_pe : f_pp, n, x0, x1, 0.05, toi);
  }
  double a[6] = {0, 0, 0, 1, 0, 0}, b[6] = {0, 0, 0, 1, 0, 0}, c[6] = {1, 0, 0, 0, 0, 0};
  assert_true(sw_ccd_point_point(a, b, 0.0, 1.0) == 1.0);   /* no motion */
  assert_true(sw_ccd_point_point(a, b, 0.0, 0.25) == 0.25); /* tmax */
  assert_true(sw_ccd_point_point(a, b, 1.0, 1.0) == 0.0);   /* within dmin at the start */
  double toi = sw_ccd_point_point(a, c, 0.0, 1.0);         /* head-on: meet at 0.5 */
  assert_true(toi < 0.5 && 1.0 - 2.0 * toi >= SW_CCD_SCALE * (1 - 1e-12));
  double fly[6] = {5, 5, 5, 6, 5, 5}; /* a rigid translation changes no distance */
  assert_true(sw_ccd_point_point(a, fly, 0.0, 1.0) == 1.0);
}

/* ---------------------------------------------------------------------------- broad phase */

typedef struct mesh {
  int nv, ne, nf, *edge, *face;
  double *x0, *x1;
  unsigned char *fixed;
} mesh;

/* Two crumpled grids (nx x nx vertices each) in one vertex array, the second fixed
 * (an obstacle), moving randomly by up to `motion`. */
static mesh random_mesh(unsigned long *rs, int nx, double motion) {
  mesh M = {0};
  int per = nx * nx, fper = 2 * (nx - 1) * (nx - 1);
  M.nv = 2 * per, M.nf = 2 * fper;
  M.x0 = malloc(sizeof(double) * 3 * (size_t)M.nv), M.x1 = malloc(sizeof(double) * 3 * (size_t)M.nv);
  M.fixed = calloc((size_t)M.nv, 1);
  M.face = malloc(sizeof(int) * 3 * (size_t)M.nf);
  M.edge = malloc(sizeof(int) * 6 * (size_t)M.nf);
  for (int s = 0; s < 2; s++)
    for (int j = 0; j < nx; j++)
      for (int i = 0; i < nx; i++) {
        int v = s * per + j * nx + i;
        double *p = M.x0 + 3 * v;
        p[0] = (double)i / (nx - 1) + 0.3 * th_rand(rs) / nx;
        p[1] = (double)j / (nx - 1) + 0.3 * th_rand(rs) / nx;
        p[2] = 0.15 * th_rand(rs) + 0.1 * s;
        for (int a = 0; a < 3; a++) M.x1[3 * v + a] = p[a] + motion * th_rand(rs);
        M.fixed[v] = (unsigned char)s;
      }
  int f = 0;
  for (int s = 0; s < 2; s++)
    for (int j = 0; j + 1 < nx; j++)
      for (int i = 0; i + 1 < nx; i++) {
        int v = s * per + j * nx + i, q[4] = {v, v + 1, v + nx + 1, v + nx};
        int t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(M.face + 3 * f, t, sizeof t);
        f += 2;
      }
  for (int k = 0; k < M.nf; k++) /* edges: each face's, kept once (from the lower-index face) */
    for (int e = 0; e < 3; e++) {
      int a = M.face[3 * k + e], b = M.face[3 * k + (e + 1) % 3], dup = 0;
      for (int i = 0; i < M.ne && !dup; i++)
        dup = (M.edge[2 * i] == a && M.edge[2 * i + 1] == b) || (M.edge[2 * i] == b && M.edge[2 * i + 1] == a);
      if (!dup) M.edge[2 * M.ne] = a, M.edge[2 * M.ne + 1] = b, M.ne++;
    }
  return M;
}

static void free_mesh(mesh *M) { free(M->x0), free(M->x1), free(M->fixed), free(M->face), free(M->edge); }

static void prim_box(const mesh *M, const int *v, int n, double r, double *b) {
  for (int a = 0; a < 3; a++) b[a] = INFINITY, b[3 + a] = -INFINITY;
  for (int k = 0; k < n; k++)
    for (int a = 0; a < 3; a++) {
      double p = M->x0[3 * v[k] + a], q = M->x1[3 * v[k] + a];
      b[a] = fmin(b[a], fmin(p, q) - r), b[3 + a] = fmax(b[3 + a], fmax(p, q) + r);
    }
}

static int boxes_meet(const double *p, const double *q) {
  for (int a = 0; a < 3; a++)
    if (p[a] > q[3 + a] || q[a] > p[3 + a]) return 0;
  return 1;
}

/* The pair is a candidate by brute force: boxes meet, no shared vertex, not all fixed. */
static int brute_pair(const mesh *M, const int *u, int nu, const int *w, int nw, double r) {
  double bu[6], bw[6];
  int fixed = 1;
  for (int i = 0; i < nu; i++)
    for (int j = 0; j < nw; j++)
      if (u[i] == w[j]) return 0;
  for (int i = 0; i < nu; i++) fixed &= M->fixed[u[i]];
  for (int j = 0; j < nw; j++) fixed &= M->fixed[w[j]];
  if (fixed) return 0;
  prim_box(M, u, nu, r, bu), prim_box(M, w, nw, r, bw);
  return boxes_meet(bu, bw);
}

/* Each reported pair is a brute-force candidate, reported once, and their numbers agree. */
static void check_pairs(const mesh *M, const int *pairs, int n, int ka, int kb, double r) {
  char *seen = calloc((size_t)(ka == 0 ? M->nv : ka == 1 ? M->ne : M->nf) *
                          (size_t)(kb == 1 ? M->ne : M->nf), 1);
  int nb = kb == 1 ? M->ne : M->nf, expect = 0;
  const int *A = ka == 1 ? M->edge : M->face, *B = kb == 1 ? M->edge : M->face;
  int na_v = ka == 0 ? 1 : ka + 1, nb_v = kb + 1, nA = ka == 0 ? M->nv : ka == 1 ? M->ne : M->nf;
  for (int k = 0; k < n; k++) {
    int a = pairs[2 * k], b = pairs[2 * k + 1], va[3] = {a};
    if (ka != 0) memcpy(va, A + na_v * a, sizeof(int) * (size_t)na_v);
    assert_true(ka == 0 || ka != kb || a < b);
    assert_true(brute_pair(M, va, na_v, B + nb_v * b, nb_v, r));
    assert_int_equal(seen[(size_t)a * (size_t)nb + (size_t)b]++, 0);
  }
  for (int a = 0; a < nA; a++)
    for (int b = ka == kb ? a + 1 : 0; b < nb; b++) {
      int va[3] = {a};
      if (ka != 0) memcpy(va, A + na_v * a, sizeof(int) * (size_t)na_v);
      expect += brute_pair(M, va, na_v, B + nb_v * b, nb_v, r);
    }
  assert_int_equal(n, expect);
  free(seen);
}

static void broadphase_brute(void **st) {
  (void)st;
  unsigned long rs = 51;
  sw_broadphase bp;
  sw_broadphase_init(&bp);
  for (int rep = 0; rep < 6; rep++) {
    mesh M = random_mesh(&rs, 6 + 2 * rep, rep % 3 == 0 ? 0.0 : 0.05);
    double r = rep % 2 ? 0.02 : 0.0;
    sw_bp_input in = {M.nv, M.x0, M.x1, M.ne, M.edge, M.nf, M.face, M.fixed, r, 0, NULL, NULL};
    assert_int_equal(sw_broadphase_query(&bp, &in, SW_BP_PT | SW_BP_EE | SW_BP_FF), 0);
    assert_true(bp.npt > 0 && bp.nee > 0 && bp.nff > 0);
    check_pairs(&M, bp.pt, bp.npt, 0, 2, r);
    check_pairs(&M, bp.ee, bp.nee, 1, 1, r);
    check_pairs(&M, bp.ff, bp.nff, 2, 2, r);
    /* the same query again: same pairs, no buffer grown */
    int *pt = bp.pt, *ee = bp.ee, npt = bp.npt, nee = bp.nee;
    size_t cap = bp.cap_ent;
    assert_int_equal(sw_broadphase_query(&bp, &in, SW_BP_PT | SW_BP_EE), 0);
    assert_true(bp.pt == pt && bp.ee == ee && bp.cap_ent == cap);
    assert_int_equal(bp.npt, npt);
    assert_int_equal(bp.nee, nee);
    assert_int_equal(bp.nff, 0);
    free_mesh(&M);
  }
  double bad[3] = {NAN, 0, 0};
  int f[3] = {0, 0, 0};
  sw_bp_input in = {1, bad, bad, 0, NULL, 1, f, NULL, 0.0, 0, NULL, NULL};
  assert_int_equal(sw_broadphase_query(&bp, &in, SW_BP_PT), -1);
  sw_broadphase_free(&bp);
}

/* The pairs (n, as a, b) with a vertex marked: a is a vertex (kind 0) or an edge, b a face or
 * an edge; as sorted keys into k, their number. */
static int marked_keys(const mesh *M, const int *q, int n, int kind, const unsigned char *mark,
                       long long *k) {
  int m = 0;
  for (int i = 0; i < n; i++) {
    int a = q[2 * i], b = q[2 * i + 1], hit = kind == 0 ? mark[a] : 0;
    for (int j = 0; kind == 1 && j < 2; j++) hit |= mark[M->edge[2 * a + j]] | mark[M->edge[2 * b + j]];
    for (int j = 0; kind == 0 && j < 3; j++) hit |= mark[M->face[3 * b + j]];
    if (hit) k[m++] = (long long)a * 1000003 + b;
  }
  for (int i = 1; i < m; i++) /* insertion sort: small lists */
    for (int j = i; j > 0 && k[j - 1] > k[j]; j--) { long long t = k[j]; k[j] = k[j - 1], k[j - 1] = t; }
  return m;
}

/* The marked query lists exactly the full query's pairs that have a marked vertex, once each,
 * with the lower edge first: marks of none, a few, half and all of the free vertices. */
static void broadphase_marked(void **st) {
  (void)st;
  unsigned long rs = 77;
  sw_broadphase bp, bq;
  sw_broadphase_init(&bp), sw_broadphase_init(&bq);
  for (int rep = 0; rep < 8; rep++) {
    mesh M = random_mesh(&rs, 6 + rep, 0.05);
    sw_bp_input in = {M.nv, M.x0, M.x1, M.ne, M.edge, M.nf, M.face, M.fixed, 0.02, 0, NULL, NULL};
    unsigned char *mark = calloc((size_t)M.nv, 1);
    int every = rep % 4 == 0 ? 0 : rep % 4 == 1 ? 17 : rep % 4 == 2 ? 2 : 1;
    for (int v = 0; every && v < M.nv / 2; v++) mark[v] = v % every == 0; /* the free grid's */
    assert_int_equal(sw_broadphase_query(&bp, &in, SW_BP_PT | SW_BP_EE), 0);
    assert_int_equal(sw_broadphase_query_marked(&bq, &in, SW_BP_PT | SW_BP_EE, mark), 0);
    for (int kind = 0; kind < 2; kind++) {
      int n = kind ? bp.nee : bp.npt, nq = kind ? bq.nee : bq.npt;
      const int *p = kind ? bp.ee : bp.pt, *q = kind ? bq.ee : bq.pt;
      long long *kp = malloc(sizeof *kp * (size_t)(n + 1)), *kq = malloc(sizeof *kq * (size_t)(nq + 1));
      int mp = marked_keys(&M, p, n, kind, mark, kp), mq = marked_keys(&M, q, nq, kind, mark, kq);
      assert_int_equal(mq, nq); /* every pair listed has a marked vertex */
      assert_int_equal(mp, mq);
      for (int i = 0; i < mp; i++) assert_true(kp[i] == kq[i]);
      for (int i = 0; kind && i < nq; i++) assert_true(q[2 * i] < q[2 * i + 1]);
      if (every == 1) assert_true(mq > 0);
      free(kp), free(kq);
    }
    free(mark);
    free_mesh(&M);
  }
  double bad[3] = {NAN, 0, 0};
  int f[3] = {0, 0, 0};
  unsigned char one = 1;
  sw_bp_input in = {1, bad, bad, 0, NULL, 1, f, NULL, 0.0, 0, NULL, NULL};
  assert_int_equal(sw_broadphase_query_marked(&bq, &in, SW_BP_PT, &one), -1);
  sw_broadphase_free(&bp), sw_broadphase_free(&bq);
}

/* -------------------------------------------------------------------- exact predicates */

static int seg_tri(const double *x) { return sw_segment_triangle_intersect(x, x + 3, x + 6, x + 9, x + 12); }

static void predicates_constructed(void **st) {
  (void)st;
  /* triangle (0,0,0) (2,0,0) (0,2,0); each case: a, b, t0, t1, t2 and the answer */
  static const struct { double x[15]; int hit; } C[] = {
      {{0.5, 0.5, -1, 0.5, 0.5, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},   /* through the interior */
      {{0, 0, -1, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},           /* through a vertex */
      {{1, 0, -1, 1, 0, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},           /* through an edge */
      {{1, 1, -1, 1, 1, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},           /* through the hypotenuse */
      {{1.0000001, 1, -1, 1, 1.0000001, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 0}, /* just outside it */
      {{0.5, 0.5, 0, 0.5, 0.5, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},    /* ends on the face */
      {{0.5, 0.5, 0x1p-60, 0.5, 0.5, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 0}, /* ends 2^-60 above */
      {{2, 0, 0, 3, 0, 5, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},            /* starts at a vertex */
      {{-1, 1, 0, 3, 1, 0, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},           /* coplanar, across */
      {{-1, 3, 0, 3, -1, 0, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},          /* coplanar, along the hypotenuse */
      {{-1, 3.5, 0, 3.5, -1, 0, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 0},      /* coplanar, outside */
      {{-2, 2, 0, 2, -2, 0, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},          /* coplanar, through t0 only */
      {{0.2, 0.2, 0, 0.3, 0.3, 0, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},    /* coplanar, inside */
      {{-1, -1, 1, 3, 3, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 0},          /* parallel above */
      {{0.5, 0.5, 0, 0.5, 0.5, 0, 0, 0, 0, 2, 0, 0, 0, 2, 0}, 1},    /* a point on the face */
      {{1, 0, -1, 1, 0, 1, 0, 0, 0, 1, 0, 0, 2, 0, 0}, 1},           /* degenerate triangle, crossed */
      {{1, 1, -1, 1, 1, 1, 0, 0, 0, 1, 0, 0, 2, 0, 0}, 0},           /* degenerate triangle, missed */
      {{3, 0, 0, 4, 0, 0, 0, 0, 0, 1, 0, 0, 2, 0, 0}, 0},            /* collinear, disjoint */
      {{2, 0, 0, 4, 0, 0, 0, 0, 0, 1, 0, 0, 2, 0, 0}, 1},            /* collinear, touching */
  };
  for (size_t i = 0; i < sizeof C / sizeof C[0]; i++) {
    if (seg_tri(C[i].x) != C[i].hit) print_error("case %zu\n", i);
    assert_int_equal(seg_tri(C[i].x), C[i].hit);
  }
  /* triangles: crossing, touching at a vertex, stacked */
  double T[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0}, U[9] = {0.5, 0.5, -1, 0.5, 0.5, 1, 3, 3, 0};
  assert_int_equal(sw_triangles_intersect(T, T + 3, T + 6, U, U + 3, U + 6), 1);
  double V[9] = {2, 0, 0, 3, 0, 1, 3, 1, 0}, W[9] = {0, 0, 1e-9, 2, 0, 1e-9, 0, 2, 1e-9};
  assert_int_equal(sw_triangles_intersect(T, T + 3, T + 6, V, V + 3, V + 6), 1);
  assert_int_equal(sw_triangles_intersect(T, T + 3, T + 6, W, W + 3, W + 6), 0);
}

/* An independent rational test on integer coordinates: the segment a + l (b - a), l in [0, 1],
 * clipped against the triangle's three inner half-planes n . ((tj - ti) x (x - ti)) >= 0
 * (Liang-Barsky) in its plane; -1 for a degenerate triangle (not compared). */
typedef long long ll;
static void icross(const ll *u, const ll *v, ll *w) {
  w[0] = u[1] * v[2] - u[2] * v[1], w[1] = u[2] * v[0] - u[0] * v[2], w[2] = u[0] * v[1] - u[1] * v[0];
}
static ll idot(const ll *u, const ll *v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

static int ref_seg_tri(const ll *a, const ll *b, const ll *t0, const ll *t1, const ll *t2) {
  const ll *t[3] = {t0, t1, t2};
  ll e1[3], e2[3], n[3], ab[3], pa[3], pb[3];
  for (int k = 0; k < 3; k++)
    e1[k] = t1[k] - t0[k], e2[k] = t2[k] - t0[k], ab[k] = b[k] - a[k], pa[k] = a[k] - t0[k], pb[k] = b[k] - t0[k];
  icross(e1, e2, n);
  if (!n[0] && !n[1] && !n[2]) return -1;
  ll da = idot(n, pa), db = idot(n, pb);
  if ((da > 0 && db > 0) || (da < 0 && db < 0)) return 0;
  /* lambda in [lo_n/lo_d, hi_n/hi_d], denominators positive */
  ll lo_n = 0, lo_d = 1, hi_n = 1, hi_d = 1;
  if (da != 0 || db != 0) lo_n = hi_n = da, lo_d = hi_d = da - db; /* the plane crossing */
  if (lo_d < 0) lo_n = -lo_n, lo_d = -lo_d, hi_n = -hi_n, hi_d = -hi_d;
  for (int e = 0; e < 3; e++) {
    ll te[3], w[3], cw[3], cab[3];
    for (int k = 0; k < 3; k++) te[k] = t[(e + 1) % 3][k] - t[e][k], w[k] = a[k] - t[e][k];
    icross(te, w, cw), icross(te, ab, cab);
    ll al = idot(n, cw), be = idot(n, cab); /* al + lambda be >= 0 */
    if (be == 0) {
      if (al < 0) return 0;
    } else if (be > 0) { /* lambda >= -al/be */
      if (-al * lo_d > lo_n * be) lo_n = -al, lo_d = be;
    } else if (al * hi_d < hi_n * -be) hi_n = al, hi_d = -be; /* lambda <= al/-be */
  }
  return lo_n * hi_d <= hi_n * lo_d;
}

static void predicates_random(void **st) {
  (void)st;
  unsigned long rs = 61;
  int hits = 0, compared = 0, coplanar = 0;
  for (int rep = 0; rep < 200000; rep++) {
    ll xi[15];
    double x[15];
    for (int i = 0; i < 15; i++) xi[i] = (ll)floor(2.5 * th_rand(&rs)), x[i] = (double)xi[i];
    int ref = ref_seg_tri(xi, xi + 3, xi + 6, xi + 9, xi + 12);
    if (ref < 0) continue;
    compared++, hits += ref;
    coplanar += sw_orient3d(x + 6, x + 9, x + 12, x) == 0 && sw_orient3d(x + 6, x + 9, x + 12, x + 3) == 0;
    if (seg_tri(x) != ref) print_error("case %d: ref %d\n", rep, ref);
    assert_int_equal(seg_tri(x), ref);
  }
  assert_true(compared > 100000 && hits > 10000 && coplanar > 1000);
}

/* orient3d on coplanar and nearly coplanar integer points of magnitude 2^30 (the fourth a
 * small integer combination of the others, moved by -1, 0 or 1 along one axis), against
 * exact 128-bit integers: it agrees every time, where the plain floating-point determinant
 * often does not. */
static void orient3d_exact(void **st) {
  (void)st;
  unsigned long rs = 71;
  int naive_wrong = 0;
  for (int rep = 0; rep < 20000; rep++) {
    double p[4][3];
    for (int k = 0; k < 3; k++)
      for (int a = 0; a < 3; a++) p[k][a] = floor(0x1p30 * th_rand(&rs));
    double u = floor(2.5 * th_rand(&rs)), v = floor(2.5 * th_rand(&rs));
    for (int a = 0; a < 3; a++) p[3][a] = p[0][a] + u * (p[1][a] - p[0][a]) + v * (p[2][a] - p[0][a]);
    p[3][rep % 3] += rep % 5 == 0 ? 1.0 : rep % 5 == 1 ? -1.0 : 0.0;
    __int128 m[3][3];
    double md[3][3];
    for (int r = 0; r < 3; r++)
      for (int a = 0; a < 3; a++) m[r][a] = (__int128)(p[r + 1][a] - p[0][a]), md[r][a] = p[r + 1][a] - p[0][a];
    __int128 det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                   m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double dd = md[0][0] * (md[1][1] * md[2][2] - md[1][2] * md[2][1]) -
                md[0][1] * (md[1][0] * md[2][2] - md[1][2] * md[2][0]) +
                md[0][2] * (md[1][0] * md[2][1] - md[1][1] * md[2][0]);
    int s = det > 0 ? 1 : det < 0 ? -1 : 0;
    naive_wrong += (dd > 0 ? 1 : dd < 0 ? -1 : 0) != s;
    assert_int_equal(sw_orient3d(p[0], p[1], p[2], p[3]), s);
  }
  assert_true(naive_wrong > 2000); /* of 20000 */
}

/* Two grids crossing each other (and one touching), counted against every pair of faces. */
static void mesh_intersections(void **st) {
  (void)st;
  unsigned long rs = 81;
  for (int rep = 0; rep < 4; rep++) {
    mesh M = random_mesh(&rs, 6 + rep, 0.0);
    int per = M.nv / 2;
    for (int v = per; v < M.nv; v++) { /* the second grid stood up: plane x = 0.45 (or 0) */
      double *p = M.x0 + 3 * v, y = p[0];
      p[0] = rep == 3 ? 0.0 : 0.45 + 0.02 * th_rand(&rs), p[2] = y - 0.5;
    }
    if (rep == 3) /* the first grid flat at z in [0, 0.5]: the second touches its edge */
      for (int v = 0; v < per; v++) M.x0[3 * v] = fmax(M.x0[3 * v], 0.0);
    long brute = 0;
    for (int f = 0; f < M.nf; f++)
      for (int g = f + 1; g < M.nf; g++) {
        const int *a = M.face + 3 * f, *b = M.face + 3 * g;
        int shared = 0;
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) shared |= a[i] == b[j];
        if (!shared)
          brute += sw_triangles_intersect(M.x0 + 3 * a[0], M.x0 + 3 * a[1], M.x0 + 3 * a[2],
                                          M.x0 + 3 * b[0], M.x0 + 3 * b[1], M.x0 + 3 * b[2]);
      }
    long n = sw_mesh_self_intersections(M.nv, M.x0, M.nf, M.face);
    assert_true(brute > 0);
    assert_int_equal(n, brute);
    free_mesh(&M);
  }
  mesh M = random_mesh(&rs, 8, 0.0); /* one flat grid alone: none */
  for (int v = 0; v < M.nv; v++) M.x0[3 * v + 2] = 0.0;
  assert_int_equal(sw_mesh_self_intersections(M.nv / 2, M.x0, M.nf / 2, M.face), 0);
  free_mesh(&M);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(distances_simple),     cmocka_unit_test(distances_point_triangle),
      cmocka_unit_test(distances_edge_edge),  cmocka_unit_test(distances_degenerate),
      cmocka_unit_test(mollifier),            cmocka_unit_test(barrier),
      cmocka_unit_test(barrier_blocks),       cmocka_unit_test(ccd_crossing),
      cmocka_unit_test(ccd_random),           cmocka_unit_test(ccd_small),
      cmocka_unit_test(broadphase_brute),     cmocka_unit_test(broadphase_marked),     cmocka_unit_test(predicates_constructed),
      cmocka_unit_test(predicates_random),    cmocka_unit_test(orient3d_exact),
      cmocka_unit_test(mesh_intersections),   cmocka_unit_test(pair_apart),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
