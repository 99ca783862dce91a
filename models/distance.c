/* distance.c — squared distances between points, edges and triangles with exact gradients
 * and Hessians, the closest-feature classifiers, IPC's barrier and edge-edge mollifier
 * (Li et al., "Incremental Potential Contact", SIGGRAPH 2020, sec. 4 and its supplement).
 *
 * Every distance here is one form: r(s) = sum_i c_i(s) x_i, with coefficients c affine in
 * k <= 2 parameters s (a point on an edge or a triangle, or one on each of two lines), and
 * d2(x) = min_s |r(s)|^2.  At the minimiser f_s = 0, so (envelope theorem) grad d2 = f_x and,
 * differentiating f_s(x, s(x)) = 0, Hess d2 = f_xx - f_xs f_ss^-1 f_sx: one routine gives the
 * exact derivatives of point-point, point-line, point-plane and line-line distances. */
#include <math.h>
#include <string.h>

#include "contact_geom.h"

/* r = sum_{i<n} c_i x_i, s(s) at the minimiser: the form of one distance over n <= 4 vertices. */
typedef struct form {
  int n, k;
  double c0[4], dc[2][4]; /* c(s) = c0 + s_0 dc[0] + s_1 dc[1] */
} form;

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double sq(double a) { return a * a; }

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

static void combine(const double *c, const double *const *x, int n, double *r) {
  r[0] = r[1] = r[2] = 0.0;
  for (int i = 0; i < n; i++)
    for (int a = 0; a < 3; a++) r[a] += c[i] * x[i][a];
}

/* Below this sin^2 of the angle between the two directions of a 2-parameter form, its
 * parameters are recomputed in long double from the vertices themselves: in double, the
 * directions' own rounding (relative 1e-16) turns into an error of 1e-16 / sin^2 in the
 * parameters. */
static const double NEAR_SIN2 = 1e-8;

/* The minimiser of |r + s0 R0 + s1 R1|^2 by Gram-Schmidt: s1 along R1's part q orthogonal to
 * R0, then s0 exactly for that s1.  The error of nearly dependent directions then stays in the
 * soft direction (s0 R0 + s1 R1 nearly constant), where it changes the distance only to second
 * order in sin; Cramer's rule spreads it over both and costs digits of the distance itself.
 * Returns 0, or -1 when the directions are dependent.  T is double or long double. */
#define GRAM_SCHMIDT_2(T, r, R, s)                                                        \
  do {                                                                                    \
    T uu = 0, ur = 0, c, q[3], qq = 0, qr = 0, s1;                                        \
    for (int a_ = 0; a_ < 3; a_++) uu += R[0][a_] * R[0][a_], ur += R[0][a_] * R[1][a_];  \
    if (!(uu > 0)) return -1;                                                             \
    c = ur / uu;                                                                          \
    for (int a_ = 0; a_ < 3; a_++) q[a_] = R[1][a_] - c * R[0][a_];                       \
    for (int a_ = 0; a_ < 3; a_++) qq += q[a_] * q[a_], qr += q[a_] * r[a_];              \
    if (!(qq > 0)) return -1;                                                             \
    s1 = -qr / qq;                                                                        \
    T p0 = 0;                                                                             \
    for (int a_ = 0; a_ < 3; a_++) p0 += (r[a_] + s1 * R[1][a_]) * R[0][a_];              \
    s[0] = (double)(-p0 / uu), s[1] = (double)s1;                                         \
  } while (0)

/* The parameters s of form L at the vertices x in long double (x87's 64-bit mantissa on x86-64,
 * binary128 on arm64): r and R from the coordinates, Ginv = (R^T R)^-1.  -1 when dependent. */
static int solve_params_ld(const form *L, const double *const *x, double *s, double Ginv[2][2]) {
  long double r[3] = {0, 0, 0}, R[2][3] = {{0, 0, 0}, {0, 0, 0}};
  for (int i = 0; i < L->n; i++)
    for (int a = 0; a < 3; a++) {
      r[a] += (long double)L->c0[i] * x[i][a];
      for (int j = 0; j < 2; j++) R[j][a] += (long double)L->dc[j][i] * x[i][a];
    }
  long double G00 = 0, G11 = 0, G01 = 0, w[3];
  for (int a = 0; a < 3; a++)
    G00 += R[0][a] * R[0][a], G11 += R[1][a] * R[1][a], G01 += R[0][a] * R[1][a];
  w[0] = R[0][1] * R[1][2] - R[0][2] * R[1][1];
  w[1] = R[0][2] * R[1][0] - R[0][0] * R[1][2];
  w[2] = R[0][0] * R[1][1] - R[0][1] * R[1][0];
  long double det = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  if (!(det > 0)) return -1;
  GRAM_SCHMIDT_2(long double, r, R, s);
  Ginv[0][0] = (double)(G11 / det), Ginv[1][1] = (double)(G00 / det);
  Ginv[0][1] = Ginv[1][0] = (double)(-G01 / det);
  return 0;
}

/* The minimising parameters s (k of them) of |r0 + sum s_j R_j|^2; Ginv = (R^T R)^-1.  Nearly
 * dependent directions (sin^2 < NEAR_SIN2) take the long double path when the form L and its
 * vertices x are given.  Returns 0, or -1 when the directions are (numerically) dependent. */
static int solve_params(int k, const double *r0, double R[2][3], double *s, double Ginv[2][2],
                        const form *L, const double *const *x) {
  if (k == 0) return 0;
  double G00 = dot3(R[0], R[0]), b0 = -dot3(R[0], r0);
  if (k == 1) {
    if (!(G00 > 0.0)) return -1;
    Ginv[0][0] = 1.0 / G00, s[0] = b0 / G00;
    return 0;
  }
  double G11 = dot3(R[1], R[1]), G01 = dot3(R[0], R[1]), w[3];
  cross3(R[0], R[1], w);
  double det = dot3(w, w); /* = G00 G11 - G01^2 without its cancellation */
  if (L && det < NEAR_SIN2 * G00 * G11) return solve_params_ld(L, x, s, Ginv);
  if (!(det > 0.0)) return -1;
  Ginv[0][0] = G11 / det, Ginv[1][1] = G00 / det, Ginv[0][1] = Ginv[1][0] = -G01 / det;
  GRAM_SCHMIDT_2(double, r0, R, s);
  return 0;
}

/* The Hessian f_xx - f_xs f_ss^-1 f_sx with f_xx = 2 c c^T (x) I, f_ss = 2 G and
 * f_{x_ia, s_j} = 2 (dc_ji r_a + c_i R_ja). */
static void form_hessian(const form *L, const double *c, const double *r, double R[2][3],
                         double Ginv[2][2], double *H) {
  int m = 3 * L->n;
  double F[12][2];
  for (int i = 0; i < L->n; i++)
    for (int a = 0; a < 3; a++)
      for (int j = 0; j < L->k; j++) F[3 * i + a][j] = 2.0 * (L->dc[j][i] * r[a] + c[i] * R[j][a]);
  for (int p = 0; p < m; p++)
    for (int q = p; q < m; q++) {
      double v = p % 3 == q % 3 ? 2.0 * c[p / 3] * c[q / 3] : 0.0;
      for (int j = 0; j < L->k; j++)
        for (int l = 0; l < L->k; l++) v -= 0.5 * F[p][j] * Ginv[j][l] * F[q][l];
      H[p * m + q] = H[q * m + p] = v;
    }
}

/* d2 of the form L at the vertices x, its gradient (3n) and Hessian (3n x 3n).  A form whose
 * directions are dependent (a degenerate edge or triangle, parallel lines) is evaluated at
 * s = 0: its callers classify such cases away. */
static double form_eval(const form *L, const double *const *x, double *g, double *H) {
  double r[3], R[2][3], s[2] = {0.0, 0.0}, Ginv[2][2] = {{0.0, 0.0}, {0.0, 0.0}}, c[4];
  combine(L->c0, x, L->n, r);
  for (int j = 0; j < L->k; j++) combine(L->dc[j], x, L->n, R[j]);
  int k = solve_params(L->k, r, R, s, Ginv, L, x) ? 0 : L->k;
  form M = *L;
  M.k = k;
  for (int i = 0; i < L->n; i++) c[i] = L->c0[i] + s[0] * L->dc[0][i] + s[1] * L->dc[1][i];
  for (int j = 0; j < k; j++)
    for (int a = 0; a < 3; a++) r[a] += s[j] * R[j][a];
  if (g)
    for (int i = 0; i < L->n; i++)
      for (int a = 0; a < 3; a++) g[3 * i + a] = 2.0 * c[i] * r[a];
  if (H) form_hessian(&M, c, r, R, Ginv, H);
  return dot3(r, r);
}

/* ------------------------------------------------------------------ the four distances */

static const form PP = {2, 0, {1, -1}, {{0}}};
static const form PL = {3, 1, {1, -1, 0}, {{0, 1, -1}}};
static const form PPLANE = {4, 2, {1, -1, 0, 0}, {{0, 1, -1, 0}, {0, 1, 0, -1}}};
static const form LL = {4, 2, {1, 0, -1, 0}, {{-1, 1, 0, 0}, {0, 0, 1, -1}}};

double sw_d2_point_point(const double p[3], const double q[3], double *g, double *H) {
  const double *x[2] = {p, q};
  return form_eval(&PP, x, g, H);
}

double sw_d2_point_line(const double p[3], const double e0[3], const double e1[3], double *g,
                        double *H) {
  const double *x[3] = {p, e0, e1};
  return form_eval(&PL, x, g, H);
}

double sw_d2_point_plane(const double p[3], const double t0[3], const double t1[3],
                         const double t2[3], double *g, double *H) {
  const double *x[4] = {p, t0, t1, t2};
  return form_eval(&PPLANE, x, g, H);
}

double sw_d2_line_line(const double a0[3], const double a1[3], const double b0[3],
                       const double b1[3], double *g, double *H) {
  const double *x[4] = {a0, a1, b0, b1};
  return form_eval(&LL, x, g, H);
}

/* --------------------------------------------------------------------------- classifiers */

/* The parameter of the point of segment e0e1 closest to p, clamped to [0, 1] (0 when the
 * segment is a point), and the squared distance to it. */
static double segment_param(const double *p, const double *e0, const double *e1, double *d2) {
  double e[3] = {e1[0] - e0[0], e1[1] - e0[1], e1[2] - e0[2]};
  double w[3] = {p[0] - e0[0], p[1] - e0[1], p[2] - e0[2]}, ee = dot3(e, e);
  double s = ee > 0.0 ? dot3(w, e) / ee : 0.0;
  s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
  double r[3] = {w[0] - s * e[0], w[1] - s * e[1], w[2] - s * e[2]};
  *d2 = dot3(r, r);
  return s;
}

sw_pe_type sw_point_edge_type(const double p[3], const double e0[3], const double e1[3]) {
  double d2, s = segment_param(p, e0, e1, &d2);
  return s <= 0.0 ? SW_PE_E0 : s >= 1.0 ? SW_PE_E1 : SW_PE_LINE;
}

/* The barycentric (u, v) of p's projection on the plane of t0 t1 t2 (u along t1 - t0, v along
 * t2 - t0); -1 when the triangle is degenerate. */
static int plane_param(const double *p, const double *t0, const double *t1, const double *t2,
                       double *u, double *v) {
  const double *x[4] = {p, t0, t1, t2};
  double r[3], R[2][3], s[2], Ginv[2][2];
  combine(PPLANE.c0, x, 4, r);
  for (int j = 0; j < 2; j++) combine(PPLANE.dc[j], x, 4, R[j]);
  if (solve_params(2, r, R, s, Ginv, &PPLANE, x)) return -1;
  *u = s[0], *v = s[1];
  return 0;
}

sw_pt_type sw_point_triangle_type(const double p[3], const double t0[3], const double t1[3],
                                  const double t2[3]) {
  double u, v;
  if (!plane_param(p, t0, t1, t2, &u, &v) && u >= 0.0 && v >= 0.0 && u + v <= 1.0)
    return SW_PT_PLANE;
  /* outside (or degenerate): the closest point is on the boundary, on the nearest edge */
  const double *t[3] = {t0, t1, t2};
  double best = INFINITY;
  sw_pt_type type = SW_PT_T0;
  for (int e = 0; e < 3; e++) {
    double d2, s = segment_param(p, t[e], t[(e + 1) % 3], &d2);
    if (!(d2 < best)) continue;
    best = d2;
    type = s <= 0.0 ? (sw_pt_type)e : s >= 1.0 ? (sw_pt_type)((e + 1) % 3) : (sw_pt_type)(SW_PT_E01 + e);
  }
  return type;
}

/* Relative sin^2 of the angle below which two edges count as parallel: their distance is then
 * the smallest of the four end-point-to-segment distances.  Above it the line-line parameters
 * (long double below NEAR_SIN2) are accurate to 5e-20 / sin^2 = 5e-6; below it the end points
 * overestimate the squared distance by at most 2 sin^2 min(|ea|, |eb|)^2 (the quadratic over the
 * parameter square rises by at most its smallest curvature times the square's diameter^2), and
 * IPC's mollifier (2e3 sin^2 or less there) makes the switch invisible to the barrier. */
static const double PARALLEL_SIN2 = 1e-14;

/* The end-point-to-segment type of two edges closest to each other, and its squared distance. */
static sw_ee_type edge_edge_ends(const double *const *x, double *best) {
  static const sw_ee_type END[4][3] = {{SW_EE_A0B0, SW_EE_A0B1, SW_EE_A0_B},
                                       {SW_EE_A1B0, SW_EE_A1B1, SW_EE_A1_B},
                                       {SW_EE_A0B0, SW_EE_A1B0, SW_EE_A_B0},
                                       {SW_EE_A0B1, SW_EE_A1B1, SW_EE_A_B1}};
  sw_ee_type type = SW_EE_A0B0;
  *best = INFINITY;
  for (int q = 0; q < 4; q++) {
    const double *p = x[q], *e0 = x[q < 2 ? 2 : 0], *e1 = x[q < 2 ? 3 : 1];
    double d2, t = segment_param(p, e0, e1, &d2);
    if (!(d2 < *best)) continue;
    *best = d2;
    type = END[q][t <= 0.0 ? 0 : t >= 1.0 ? 1 : 2];
  }
  return type;
}

/* sin^2 of the angle between the edges (0 for a degenerate edge) and their smaller squared
 * length. */
static double edge_sin2(const double *const *x, double *lmin2) {
  double ea[3], eb[3], w[3];
  for (int a = 0; a < 3; a++) ea[a] = x[1][a] - x[0][a], eb[a] = x[3][a] - x[2][a];
  cross3(ea, eb, w);
  double aa = dot3(ea, ea), bb = dot3(eb, eb);
  *lmin2 = fmin(aa, bb);
  return aa > 0.0 && bb > 0.0 ? dot3(w, w) / (aa * bb) : 0.0;
}

/* The closest features: both interiors when the line-line minimiser lies in the parameter
 * square (edges not parallel) and, for nearly parallel edges (sin^2 < NEAR_SIN2), is no
 * farther than the best end point; else that end point.  There the smallest candidate is
 * taken, so round-off in the parameters can only choose between distances that are all real
 * distances between points of the edges. */
sw_ee_type sw_edge_edge_type(const double a0[3], const double a1[3], const double b0[3],
                             const double b1[3]) {
  const double *x[4] = {a0, a1, b0, b1};
  double best, lmin2, r[3], R[2][3], s[2], Ginv[2][2], sin2 = edge_sin2(x, &lmin2);
  if (sin2 >= PARALLEL_SIN2) {
    combine(LL.c0, x, 4, r);
    for (int j = 0; j < 2; j++) combine(LL.dc[j], x, 4, R[j]);
    if (!solve_params(2, r, R, s, Ginv, &LL, x) && s[0] >= 0.0 && s[0] <= 1.0 && s[1] >= 0.0 &&
        s[1] <= 1.0) {
      if (sin2 >= NEAR_SIN2) return SW_EE_LINES; /* parameters to 1e-16 / sin^2 <= 1e-8 */
      for (int a = 0; a < 3; a++) r[a] += s[0] * R[0][a] + s[1] * R[1][a];
      sw_ee_type type = edge_edge_ends(x, &best);
      return dot3(r, r) <= best ? SW_EE_LINES : type;
    }
  }
  return edge_edge_ends(x, &best);
}

double sw_d2_edge_edge_lower(const double a0[3], const double a1[3], const double b0[3],
                             const double b1[3]) {
  const double *x[4] = {a0, a1, b0, b1};
  double lmin2, sin2 = edge_sin2(x, &lmin2), la2 = 0.0, lb2 = 0.0;
  double d2 = sw_d2_edge_edge(a0, a1, b0, b1, NULL, NULL);
  if (sin2 < PARALLEL_SIN2) d2 -= 2.0 * sin2 * lmin2; /* the end points' overestimate */
  for (int a = 0; a < 3; a++) la2 += sq(a1[a] - a0[a]), lb2 += sq(b1[a] - b0[a]);
  /* round-off: 5e-20 L / sin (>= 1e-7) in long double, 1e-16 L / sin (>= 1e-4) in double */
  double d = sqrt(fmax(d2, 0.0)), margin = 1e-11 * (sqrt(fmax(la2, lb2)) + d);
  return d > margin ? sq(d - margin) : 0.0;
}

/* ------------------------------------------------------------- distances of closed primitives */

static const form PE_FORMS[3] = {
    {3, 0, {1, -1, 0}, {{0}}}, {3, 0, {1, 0, -1}, {{0}}}, {3, 1, {1, -1, 0}, {{0, 1, -1}}}};

static const form PT_FORMS[7] = {
    {4, 0, {1, -1, 0, 0}, {{0}}},            {4, 0, {1, 0, -1, 0}, {{0}}},
    {4, 0, {1, 0, 0, -1}, {{0}}},            {4, 1, {1, -1, 0, 0}, {{0, 1, -1, 0}}},
    {4, 1, {1, 0, -1, 0}, {{0, 0, 1, -1}}},  {4, 1, {1, 0, 0, -1}, {{0, -1, 0, 1}}},
    {4, 2, {1, -1, 0, 0}, {{0, 1, -1, 0}, {0, 1, 0, -1}}}};

static const form EE_FORMS[9] = {
    {4, 0, {1, 0, -1, 0}, {{0}}},           {4, 0, {1, 0, 0, -1}, {{0}}},
    {4, 0, {0, 1, -1, 0}, {{0}}},           {4, 0, {0, 1, 0, -1}, {{0}}},
    {4, 1, {1, 0, -1, 0}, {{0, 0, 1, -1}}}, {4, 1, {0, 1, -1, 0}, {{0, 0, 1, -1}}},
    {4, 1, {1, 0, -1, 0}, {{-1, 1, 0, 0}}}, {4, 1, {1, 0, 0, -1}, {{-1, 1, 0, 0}}},
    {4, 2, {1, 0, -1, 0}, {{-1, 1, 0, 0}, {0, 0, 1, -1}}}};

double sw_d2_point_edge(const double p[3], const double e0[3], const double e1[3], double *g,
                        double *H) {
  const double *x[3] = {p, e0, e1};
  return form_eval(&PE_FORMS[sw_point_edge_type(p, e0, e1)], x, g, H);
}

double sw_d2_point_triangle(const double p[3], const double t0[3], const double t1[3],
                            const double t2[3], double *g, double *H) {
  const double *x[4] = {p, t0, t1, t2};
  return form_eval(&PT_FORMS[sw_point_triangle_type(p, t0, t1, t2)], x, g, H);
}

double sw_d2_edge_edge(const double a0[3], const double a1[3], const double b0[3],
                       const double b1[3], double *g, double *H) {
  const double *x[4] = {a0, a1, b0, b1};
  return form_eval(&EE_FORMS[sw_edge_edge_type(a0, a1, b0, b1)], x, g, H);
}

/* ------------------------------------------------------------------------------ mollifier */

double sw_ee_mollifier_eps(const double a0[3], const double a1[3], const double b0[3],
                           const double b1[3]) {
  double ea[3] = {a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
  double eb[3] = {b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]};
  return 1e-3 * dot3(ea, ea) * dot3(eb, eb);
}

/* c = |ea x eb|^2 = |ea|^2 |eb|^2 - (ea.eb)^2 with its gradient and Hessian over the edge
 * vectors y = (ea, eb) (6 and 36). */
static double cross2_derivs(const double *ea, const double *eb, double *gy, double *Hy) {
  double aa = dot3(ea, ea), bb = dot3(eb, eb), ab = dot3(ea, eb), w[3];
  cross3(ea, eb, w);
  for (int i = 0; i < 3; i++) {
    gy[i] = 2.0 * (bb * ea[i] - ab * eb[i]);
    gy[3 + i] = 2.0 * (aa * eb[i] - ab * ea[i]);
    for (int j = 0; j < 3; j++) {
      double I = i == j;
      Hy[i * 6 + j] = 2.0 * (bb * I - eb[i] * eb[j]);
      Hy[(3 + i) * 6 + 3 + j] = 2.0 * (aa * I - ea[i] * ea[j]);
      Hy[i * 6 + 3 + j] = Hy[(3 + j) * 6 + i] = 4.0 * ea[i] * eb[j] - 2.0 * eb[i] * ea[j] - 2.0 * ab * I;
    }
  }
  return dot3(w, w);
}

double sw_ee_mollifier(const double a0[3], const double a1[3], const double b0[3],
                       const double b1[3], double eps_x, double *g, double *H) {
  double ea[3] = {a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
  double eb[3] = {b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]}, gy[6], Hy[36], w[3];
  cross3(ea, eb, w);
  if (g) memset(g, 0, 12 * sizeof(double));
  if (H) memset(H, 0, 144 * sizeof(double));
  if (!(dot3(w, w) < eps_x)) return 1.0; /* as cross2_derivs's c, without its derivatives */
  double c = cross2_derivs(ea, eb, gy, Hy);
  double q = c / eps_x, m1 = 2.0 * (1.0 - q) / eps_x, m2 = -2.0 / (eps_x * eps_x);
  /* vertex v moves edge v/2 with sign -1 (first end) or +1 (second end) */
  for (int v = 0; v < 4; v++)
    for (int a = 0; a < 3; a++) {
      int p = 3 * (v / 2) + a;
      double sp = v % 2 ? 1.0 : -1.0;
      if (g) g[3 * v + a] = m1 * sp * gy[p];
      if (H)
        for (int u = 0; u < 4; u++)
          for (int b = 0; b < 3; b++) {
            int q2 = 3 * (u / 2) + b;
            double sq = u % 2 ? 1.0 : -1.0;
            H[(3 * v + a) * 12 + 3 * u + b] = sp * sq * (m2 * gy[p] * gy[q2] + m1 * Hy[p * 6 + q2]);
          }
    }
  return (2.0 - q) * q;
}

double sw_product_derivs(int n, double f, const double *fg, const double *fH, double h,
                         const double *hg, const double *hH, double *g, double *H) {
  if (g)
    for (int i = 0; i < n; i++) g[i] = f * hg[i] + h * fg[i];
  if (H)
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++)
        H[i * n + j] = f * hH[i * n + j] + h * fH[i * n + j] + fg[i] * hg[j] + hg[i] * fg[j];
  return f * h;
}

double sw_d2_edge_edge_mollified(const double a0[3], const double a1[3], const double b0[3],
                                 const double b1[3], double eps_x, double *g, double *H) {
  double mg[12], mH[144], dg[12], dH[144];
  double m = sw_ee_mollifier(a0, a1, b0, b1, eps_x, mg, H ? mH : NULL);
  double d2 = sw_d2_edge_edge(a0, a1, b0, b1, dg, H ? dH : NULL);
  return sw_product_derivs(12, m, mg, mH, d2, dg, dH, g, H);
}

/* -------------------------------------------------------------------------------- barrier */

double sw_barrier(double d2, double dhat2, double *db, double *d2b) {
  if (db) *db = 0.0;
  if (d2b) *d2b = 0.0;
  if (!(d2 > 0.0)) return INFINITY;
  if (d2 >= dhat2) return 0.0;
  double t = d2 - dhat2, L = log(d2 / dhat2);
  if (db) *db = -t * (2.0 * L + t / d2);
  if (d2b) *d2b = -2.0 * L - 4.0 * t / d2 + t * t / (d2 * d2);
  return -t * t * L;
}

double sw_barrier_of(int n, double d2, const double *g2, const double *H2, double dhat2,
                     double *g, double *H) {
  double b1, b2, b = sw_barrier(d2, dhat2, &b1, &b2);
  if (g)
    for (int i = 0; i < n; i++) g[i] = b1 * g2[i];
  if (H)
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) H[i * n + j] = b1 * H2[i * n + j] + b2 * g2[i] * g2[j];
  return b;
}

/* ------------------------------------------------------------------ separation */

/* The separation of the two primitives along the line between their centroids (a direction
 * separates two convex hulls by no more than their distance), compared without a square root
 * or a division: sep > r |n| as sep^2 > r^2 |n|^2 with sep > 0. */
int sw_pair_apart(int edge_edge, const double *p, double r) {
  const int na = edge_edge ? 2 : 1;
  double n[3];
  for (int a = 0; a < 3; a++)
    n[a] = na == 1 ? (p[3 + a] + p[6 + a] + p[9 + a]) - 3.0 * p[a]
                   : (p[6 + a] + p[9 + a]) - (p[a] + p[3 + a]);
  double t[4];
  for (int k = 0; k < 4; k++) t[k] = p[3 * k] * n[0] + p[3 * k + 1] * n[1] + p[3 * k + 2] * n[2];
  double amax = na == 1 ? t[0] : fmax(t[0], t[1]);
  double bmin = na == 1 ? fmin(t[1], fmin(t[2], t[3])) : fmin(t[2], t[3]);
  double sep = bmin - amax, nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  return sep > 0.0 && sep * sep > r * r * nn;
}
