/* intersect.c — exact segment-triangle and triangle-triangle intersection tests, and the count
 * of a mesh's intersecting faces: the solver-independent check of "no crossing".
 *
 * The orientation determinants are computed exactly with floating-point expansions (Shewchuk,
 * "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997):
 * a floating-point value with Shewchuk's error bound first, and when that cannot decide the
 * sign, the whole determinant as an expansion (two-sum, two-product; not adaptive).  Touching
 * counts as intersecting, and every degenerate case (coplanar, collinear, a segment through a
 * vertex, degenerate triangles) is decided by signs alone. */
#include <math.h>

#include "cancel.h"
#include "contact_geom.h"
#include "sinew.h"

/* ------------------------------------------------------------------- expansion arithmetic */

static const double EPS = 0x1p-53;        /* half an ulp of 1 */
static const double SPLITTER = 134217729; /* 2^27 + 1 */

static void two_sum(double a, double b, double *x, double *y) {
  double s = a + b, bv = s - a, av = s - bv;
  *x = s, *y = (a - av) + (b - bv);
}

static void two_diff(double a, double b, double *x, double *y) {
  double s = a - b, bv = a - s, av = s + bv;
  *x = s, *y = (a - av) + (bv - b);
}

static void split(double a, double *hi, double *lo) {
  double c = SPLITTER * a, big = c - a;
  *hi = c - big, *lo = a - *hi;
}

static void two_product(double a, double b, double *x, double *y) {
  double p = a * b, ah, al, bh, bl;
  split(a, &ah, &al), split(b, &bh, &bl);
  double e1 = p - ah * bh, e2 = e1 - al * bh, e3 = e2 - ah * bl;
  *x = p, *y = al * bl - e3;
}

/* h = e + b (e nonoverlapping, increasing magnitude; zeros dropped); its length. */
static int grow(int n, const double *e, double b, double *h) {
  int k = 0;
  double q = b;
  for (int i = 0; i < n; i++) {
    double hh;
    two_sum(q, e[i], &q, &hh);
    if (hh != 0.0) h[k++] = hh;
  }
  if (q != 0.0 || k == 0) h[k++] = q;
  return k;
}

/* h = e + f (h may not alias e or f; at most n + m components). */
static int exp_sum(int n, const double *e, int m, const double *f, double *h) {
  double t[256];
  int k = n;
  for (int i = 0; i < n; i++) h[i] = e[i];
  for (int j = 0; j < m; j++) {
    k = grow(k, h, f[j], t);
    for (int i = 0; i < k; i++) h[i] = t[i];
  }
  return k;
}

/* h = e * b (Shewchuk's scale-expansion, zeros dropped). */
static int scale(int n, const double *e, double b, double *h) {
  double q, hh, p1, p0, s;
  int k = 0;
  two_product(e[0], b, &q, &hh);
  if (hh != 0.0) h[k++] = hh;
  for (int i = 1; i < n; i++) {
    two_product(e[i], b, &p1, &p0);
    two_sum(q, p0, &s, &hh);
    if (hh != 0.0) h[k++] = hh;
    two_sum(p1, s, &q, &hh);
    if (hh != 0.0) h[k++] = hh;
  }
  if (q != 0.0 || k == 0) h[k++] = q;
  return k;
}

/* h = e * f. */
static int exp_mul(int n, const double *e, int m, const double *f, double *h) {
  double part[128], acc[256];
  int k = 0;
  for (int j = 0; j < m; j++) {
    int np = scale(n, e, f[j], part);
    k = exp_sum(k, h, np, part, acc);
    for (int i = 0; i < k; i++) h[i] = acc[i];
  }
  return k;
}

static int exp_neg(int n, double *e) {
  for (int i = 0; i < n; i++) e[i] = -e[i];
  return n;
}

static int sign_of(int n, const double *e) { return e[n - 1] > 0.0 ? 1 : e[n - 1] < 0.0 ? -1 : 0; }

/* a - b exactly as a two-component expansion. */
static void diff2(double a, double b, double *e) { two_diff(a, b, &e[1], &e[0]); }

/* The exact value of u v - w z (each a two-component expansion) in h; its length. */
static int cross_term(const double *u, const double *v, const double *w, const double *z,
                      double *h) {
  double p[8], q[8];
  int np = exp_mul(2, u, 2, v, p), nq = exp_neg(exp_mul(2, w, 2, z, q), q);
  return exp_sum(np, p, nq, q, h);
}

/* ---------------------------------------------------------------------------- orientation */

/* Sign of det[b - a; c - a] of the points projected along axis k (coordinates k+1, k+2). */
static int orient2(const double *a, const double *b, const double *c, int k) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  /* a zero column or row (x - y == 0 exactly iff x == y): zero exactly, with no expansion
   * (a flat cloth's faces in an axis plane, its edges along the axes) */
  if ((a[i] == c[i] && b[i] == c[i]) || (a[j] == c[j] && b[j] == c[j]) ||
      (a[i] == c[i] && a[j] == c[j]) || (b[i] == c[i] && b[j] == c[j]))
    return 0;
  double l = (a[i] - c[i]) * (b[j] - c[j]), r = (a[j] - c[j]) * (b[i] - c[i]), det = l - r;
  double bound = (3.0 + 16.0 * EPS) * EPS * (fabs(l) + fabs(r));
  if (det > bound || -det > bound) return det > 0.0 ? 1 : -1;
  double acx[2], bcy[2], acy[2], bcx[2], h[16];
  diff2(a[i], c[i], acx), diff2(b[j], c[j], bcy), diff2(a[j], c[j], acy), diff2(b[i], c[i], bcx);
  return sign_of(cross_term(acx, bcy, acy, bcx, h), h);
}

int sw_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]) {
  /* = Shewchuk's orient3d(b, c, d, a) = det[b - a; c - a; d - a] */
  const double *P[3] = {b, c, d};
  double m[3][3], pr[6];
  int zrow[3] = {1, 1, 1}, zcol[3] = {1, 1, 1};
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++) {
      m[r][k] = P[r][k] - a[k];
      zrow[r] &= m[r][k] == 0.0, zcol[k] &= m[r][k] == 0.0;
    }
  /* a zero row or column (x - y == 0 exactly iff x == y): zero exactly, with no expansion
   * (four points of a flat cloth in an axis plane, or a repeated point) */
  if (zrow[0] || zrow[1] || zrow[2] || zcol[0] || zcol[1] || zcol[2]) return 0;
  for (int r = 0; r < 3; r++) {
    int s = (r + 1) % 3, t = (r + 2) % 3;
    pr[2 * r] = m[s][0] * m[t][1], pr[2 * r + 1] = m[t][0] * m[s][1];
  }
  double det = 0.0, perm = 0.0;
  for (int r = 0; r < 3; r++) {
    det += m[r][2] * (pr[2 * r] - pr[2 * r + 1]);
    perm += (fabs(pr[2 * r]) + fabs(pr[2 * r + 1])) * fabs(m[r][2]);
  }
  double bound = (7.0 + 56.0 * EPS) * EPS * perm;
  if (det > bound || -det > bound) return det > 0.0 ? 1 : -1;
  double e[3][3][2], total[256] = {0.0}, acc[256];
  int n = 1;
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++) diff2(P[r][k], a[k], e[r][k]);
  for (int r = 0; r < 3; r++) {
    int s = (r + 1) % 3, t = (r + 2) % 3;
    double minor[16], term[64];
    int nm = cross_term(e[s][0], e[t][1], e[t][0], e[s][1], minor);
    int nt = exp_mul(nm, minor, 2, e[r][2], term);
    n = exp_sum(n, total, nt, term, acc);
    for (int i = 0; i < n; i++) total[i] = acc[i];
  }
  return sign_of(n, total);
}

/* ------------------------------------------------------------------------- 2D predicates */

/* c on the closed segment ab, all three collinear in projection k. */
static int on_segment2(const double *a, const double *b, const double *c, int k) {
  for (int q = 1; q <= 2; q++) {
    int i = (k + q) % 3;
    if (c[i] < fmin(a[i], b[i]) || c[i] > fmax(a[i], b[i])) return 0;
  }
  return 1;
}

/* The closed segments pq and rs meet in projection k (Cormen, Leiserson, Rivest, Stein,
 * "Introduction to Algorithms", sec. 33.1; points and collinear overlaps included). */
static int segments_meet2(const double *p, const double *q, const double *r, const double *s,
                          int k) {
  int d1 = orient2(r, s, p, k), d2 = orient2(r, s, q, k);
  int d3 = orient2(p, q, r, k), d4 = orient2(p, q, s, k);
  if (d1 * d2 < 0 && d3 * d4 < 0) return 1;
  return (d1 == 0 && on_segment2(r, s, p, k)) || (d2 == 0 && on_segment2(r, s, q, k)) ||
         (d3 == 0 && on_segment2(p, q, r, k)) || (d4 == 0 && on_segment2(p, q, s, k));
}

/* p in the closed triangle t in projection k (a degenerate triangle is its edges). */
static int in_triangle2(const double *p, const double *const *t, int k) {
  int o = orient2(t[0], t[1], t[2], k), pos = 0, neg = 0;
  if (o == 0) {
    for (int e = 0; e < 3; e++)
      if (segments_meet2(p, p, t[e], t[(e + 1) % 3], k)) return 1;
    return 0;
  }
  for (int e = 0; e < 3; e++) {
    int s = orient2(t[e], t[(e + 1) % 3], p, k);
    pos |= s > 0, neg |= s < 0;
  }
  return !(pos && neg);
}

static int segment_triangle2(const double *a, const double *b, const double *const *t, int k) {
  if (in_triangle2(a, t, k) || in_triangle2(b, t, k)) return 1;
  for (int e = 0; e < 3; e++)
    if (segments_meet2(a, b, t[e], t[(e + 1) % 3], k)) return 1;
  return 0;
}

/* ------------------------------------------------------------------------- 3D predicates */

static int segments_meet3(const double *p, const double *q, const double *r, const double *s) {
  if (sw_orient3d(p, q, r, s) != 0) return 0;
  for (int k = 0; k < 3; k++)
    if (!segments_meet2(p, q, r, s, k)) return 0;
  return 1;
}

int sw_segment_triangle_intersect(const double a[3], const double b[3], const double t0[3],
                                  const double t1[3], const double t2[3]) {
  const double *t[3] = {t0, t1, t2};
  int flat = 1, kp = 0; /* kp: an axis along which t projects to a triangle */
  for (int k = 0; k < 3 && flat; k++)
    if (orient2(t0, t1, t2, k) != 0) flat = 0, kp = k;
  if (flat) { /* collinear corners: the triangle is its edges */
    for (int e = 0; e < 3; e++)
      if (segments_meet3(a, b, t[e], t[(e + 1) % 3])) return 1;
    return 0;
  }
  int oa = sw_orient3d(t0, t1, t2, a), ob = sw_orient3d(t0, t1, t2, b);
  if (oa * ob > 0) return 0;
  /* both in t's plane: sets in a plane meet iff their projections along an axis that is
   * one-to-one on that plane meet (kp keeps t a triangle, so it is) */
  if (oa == 0 && ob == 0) return segment_triangle2(a, b, t, kp);
  /* ab meets the plane at one point: inside iff the line passes on one side of every edge */
  int pos = 0, neg = 0;
  for (int e = 0; e < 3; e++) {
    int s = sw_orient3d(a, b, t[e], t[(e + 1) % 3]);
    pos |= s > 0, neg |= s < 0;
  }
  return !(pos && neg);
}

/* Whether the corners of q lie strictly on one side of p's plane (exact: orient3d's signs);
 * *flat = 1 when all three lie in it. */
static int off_plane(const double *const *p, const double *const *q, int *flat) {
  int s[3];
  for (int j = 0; j < 3; j++) s[j] = sw_orient3d(p[0], p[1], p[2], q[j]);
  *flat = !s[0] && !s[1] && !s[2];
  return s[0] && s[0] == s[1] && s[1] == s[2];
}

/* Whether the line of an edge of p has all of q strictly on the side away from p in the
 * projection along an axis that keeps p a triangle (a separating axis, exact: orient2's signs;
 * sets whose projections are apart are apart). */
static int edge_separates(const double *const *p, const double *const *q) {
  int k = 0, o = 0;
  while (k < 3 && (o = orient2(p[0], p[1], p[2], k)) == 0) k++;
  if (o == 0) return 0; /* p is a segment or a point */
  for (int e = 0; e < 3; e++) {
    const double *a = p[e], *b = p[(e + 1) % 3];
    int away = 1;
    for (int j = 0; j < 3 && away; j++) away = orient2(a, b, q[j], k) == -o;
    if (away) return 1;
  }
  return 0;
}

/* A quick exact rejection of most pairs of a broad phase's candidates: one triangle strictly
 * on one side of the other's plane, or (coplanar: a flat cloth's neighbours, which the segment
 * tests below decide slowly through zero determinants) an edge of one separating them in its
 * plane. */
static int clearly_apart(const double *const *p, const double *const *q) {
  int flat, unused;
  if (off_plane(p, q, &flat) || off_plane(q, p, &unused)) return 1;
  return flat && (edge_separates(p, q) || edge_separates(q, p));
}

int sw_triangles_intersect(const double p0[3], const double p1[3], const double p2[3],
                           const double q0[3], const double q1[3], const double q2[3]) {
  const double *p[3] = {p0, p1, p2}, *q[3] = {q0, q1, q2};
  if (clearly_apart(p, q)) return 0;
  for (int e = 0; e < 3; e++)
    if (sw_segment_triangle_intersect(p[e], p[(e + 1) % 3], q0, q1, q2) ||
        sw_segment_triangle_intersect(q[e], q[(e + 1) % 3], p0, p1, p2))
      return 1;
  return 0;
}

long sw_mesh_self_intersections(int nv, const double *x, int nf, const int *faces) {
  return sw_mesh_self_intersections_sewn(nv, x, nf, faces, NULL, NULL);
}

long sw_mesh_self_intersections_sewn(int nv, const double *x, int nf, const int *faces,
                                     const int *sewn_ptr, const int *sewn_idx) {
  sw_broadphase bp;
  sw_broadphase_init(&bp);
  sw_bp_input in = {.nv = nv, .x0 = x, .x1 = x, .nf = nf, .face = faces, .nsewn = nv,
                    .sewn_ptr = sewn_ptr, .sewn_idx = sewn_idx};
  long count = -1;
  if (!sw_broadphase_query(&bp, &in, SW_BP_FF)) {
    count = 0;
    for (int k = 0; k < bp.nff; k++) {
      if ((k & 0xffff) == 0xffff && sw_cancelled()) { /* a stop request */
        count = -2;
        break;
      }
      const int *f = faces + 3 * bp.ff[2 * k], *g = faces + 3 * bp.ff[2 * k + 1];
      count += sw_triangles_intersect(x + 3 * f[0], x + 3 * f[1], x + 3 * f[2], x + 3 * g[0],
                                      x + 3 * g[1], x + 3 * g[2]);
    }
  }
  sw_broadphase_free(&bp);
  return count;
}
