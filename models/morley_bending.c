/* morley_bending.c — bending that converges on unstructured triangulations: Morley's
 * constant-curvature triangle (L. S. D. Morley 1968, "The constant-moment plate-bending
 * element") with its mid-edge normal slopes taken from a quadratic fitted around each edge
 * instead of kept as unknowns; 2D and 3D.  docs/models.md "morley".
 *
 * Morley's triangle T (rest area A, edges k of length l_k with outward unit normals n_k in T's
 * (u,v)) carries the constant curvature of its quadratic deflection w,
 *   A II_T = integral over T of grad grad w = sum_k l_k (s_k - grad L_T . n_k) n_k n_k^T,
 * s_k the slope dw/dn_k at the midpoint of edge k and L_T the linear interpolant of w at T's
 * corners (the tangential parts of the boundary integral cancel).  Two properties make the
 * energy converge on any mesh: (i) s_k is the one slope of the edge, shared by its two
 * triangles, so the sum over triangles of A II_T is sum_e l_e theta_e n_e n_e^T, the exact
 * integral of the distributional Hessian of the piecewise-linear w (the constant-moment patch
 * test); (ii) s_k is exact for every quadratic w, so II_T is.  The bending of slopes
 * interpolated between centroids (models/bending.c) has (i) but (ii) only where the two
 * triangles across an edge form a parallelogram; the quadratic through a triangle's six-vertex
 * patch has (ii) but not (i).  Here s_e is the slope at the midpoint of the least-squares
 * quadratic through the edge's patch (the two triangles' four vertices and the far vertex
 * across each of their other four edges, unfolded flat about the edges in their own (u,v)):
 * both hold.  Where that patch has fewer than six vertices or lies nearly on a conic, the edge
 * takes the centroid slope (property (i) kept, (ii) lost on that edge).
 *
 * Positions enter linearly, as in Bergou et al.'s quadratic model: II_T = sum_v L_v x_v is a
 * 2 x 2 of d-vectors (the second derivatives of the deformed surface over the rest layout,
 * along the normal and of length the curvature for an isometric bending), and
 *   E_T = (A/2) II_T : D : II_T,   D = diag(D_u, D_v, 2G) on (uu, vv, sqrt(2) uv)   (J)
 * (isotropic: D_u = D_v = 2G = k_b; models/bending.c has the orthotropic rigidities).  A free
 * edge has no slope: its curvature n_k n_k^T is left free and eliminated (the Schur complement
 * of D on it: zero moment across a free edge, as in models/bending.c).  So E_T is a quadratic
 * form Q (x) I in the stencil's positions (T's corners, the far vertices across its edges and
 * across its neighbours' other edges: at most 12), positive semi-definite, annihilating every
 * affine map of the rest layout; the eigenvalue filters leave it unchanged.  Rest state: the
 * flat (u,v) layout. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

#define NV 12      /* stencil vertices at most */
#define FIT_COND 1e-8 /* smallest pivot of the fit's normal equations relative to the largest */
#define PARA_TOL 1e-9 /* a parallelogram: diagonals' midpoints this close, relative to the edge */

typedef struct morley_param {
  int n;     /* triangles (stencils) */
  double *L; /* (n x 3 x NV) II_T = sum_v L_v x_v in (uu, vv, sqrt(2) uv), 1/m^2 */
  double *D; /* (n x 9) A times the condensed rigidity, N m^3 */
  double *Q; /* (n x NV x NV) Q = L^T D L of each stencil, nv x nv used, N/m */
  sw_compact cm; /* the compact Newton matrix (cm.C != NULL): the stencils are there */
} morley_param;

static void morley_free(void *p) {
  morley_param *mp = p;
  if (!mp) return;
  sw_free(mp->L);
  sw_free(mp->D);
  sw_free(mp->Q);
  sw_compact_free(&mp->cm);
  sw_free(mp);
}

/* ------------------------------------------------------------------ geometry at rest */

/* A point of a triangle's layout with the vertex it is. */
typedef struct pt {
  int v;
  double p[2]; /* m */
} pt;

static double cross2(const double *a, const double *b) { return a[0] * b[1] - a[1] * b[0]; }

static const double *corner_uv(const sw_model *m, int f, int v) {
  return m->uv + 6 * f + 2 * sw_face_corner(m, f, v);
}

/* Point P of face g's layout placed in a frame where g's edge (va, vb) lies at a, b and g is on
 * the side away from `inside`: the distance along the edge and the signed distance from it
 * (positive towards g's third corner) carried over. */
static void unfold(const sw_model *m, int g, int va, int vb, const double *P, const double *a,
                   const double *b, const double *inside, double out[2]) {
  const double *ga = corner_uv(m, g, va), *gb = corner_uv(m, g, vb);
  const double *gc = m->uv + 6 * g + 2 * (3 - sw_face_corner(m, g, va) - sw_face_corner(m, g, vb));
  double e[2] = {gb[0] - ga[0], gb[1] - ga[1]}, w[2] = {P[0] - ga[0], P[1] - ga[1]};
  double c[2] = {gc[0] - ga[0], gc[1] - ga[1]}, l2 = e[0] * e[0] + e[1] * e[1];
  double along = (e[0] * w[0] + e[1] * w[1]) / l2, across = cross2(e, w) / sqrt(l2);
  if (cross2(e, c) < 0.0) across = -across;
  double t[2] = {b[0] - a[0], b[1] - a[1]}, lt = hypot(t[0], t[1]);
  double o[2] = {t[1] / lt, -t[0] / lt};
  if (o[0] * (inside[0] - a[0]) + o[1] * (inside[1] - a[1]) > 0.0) o[0] = -o[0], o[1] = -o[1];
  out[0] = a[0] + along * t[0] + across * o[0], out[1] = a[1] + along * t[1] + across * o[1];
}

/* The face across the edge of face f opposite its corner k (-1: none), and its far vertex. */
static int across(const sw_topology *tp, const int *fe, int f, int k, int *far) {
  int e = fe[3 * f + k];
  if (e < 0 || tp->ef[2 * e + 1] < 0) return -1;
  int side = tp->ef[2 * e] == f ? 1 : 0;
  *far = tp->efar[2 * e + side];
  return tp->ef[2 * e + side];
}

/* The patch of face f's edge k in f's layout: f's corners, the far vertex across each edge of
 * f and across the other two edges of the face g across edge k.  Returns its size (0: edge k
 * is a boundary edge); pts[3] is g's far vertex. */
static int edge_patch(const sw_model *m, const sw_topology *tp, const int *fe, int f, int k,
                      pt pts[8]) {
  const double *p = m->uv + 6 * f;
  int n = 0, far;
  for (int i = 0; i < 3; i++)
    pts[n].v = m->face[3 * f + i], memcpy(pts[n++].p, p + 2 * i, sizeof pts->p);
  int g = across(tp, fe, f, k, &far);
  if (g < 0) return 0;
  const int va = m->face[3 * f + (k + 1) % 3], vb = m->face[3 * f + (k + 2) % 3];
  const double *a = p + 2 * ((k + 1) % 3), *b = p + 2 * ((k + 2) % 3);
  pts[n].v = far, unfold(m, g, va, vb, corner_uv(m, g, far), a, b, p + 2 * k, pts[n++].p);
  for (int j = 1; j < 3; j++) { /* across f's other edges */
    int kj = (k + j) % 3, h = across(tp, fe, f, kj, &pts[n].v);
    if (h < 0) continue;
    unfold(m, h, m->face[3 * f + (kj + 1) % 3], m->face[3 * f + (kj + 2) % 3],
           corner_uv(m, h, pts[n].v), p + 2 * ((kj + 1) % 3), p + 2 * ((kj + 2) % 3), p + 2 * kj,
           pts[n].p);
    n++;
  }
  for (int j = 0; j < 3; j++) { /* across g's other edges, unfolded in g's layout first */
    if (m->face[3 * g + j] == far) continue; /* the edge opposite far is edge k itself */
    int h = across(tp, fe, g, j, &pts[n].v);
    if (h < 0) continue;
    const double *gp = m->uv + 6 * g, *ga = gp + 2 * ((j + 1) % 3), *gb = gp + 2 * ((j + 2) % 3);
    double in_g[2];
    unfold(m, h, m->face[3 * g + (j + 1) % 3], m->face[3 * g + (j + 2) % 3],
           corner_uv(m, h, pts[n].v), ga, gb, gp + 2 * j, in_g);
    unfold(m, g, va, vb, in_g, a, b, p + 2 * k, pts[n].p);
    n++;
  }
  return n;
}

/* Coefficients c (per patch point) of the slope along the unit direction nrm at point mid of
 * the least-squares quadratic through the n points: slope = sum_i c_i w_i.  0 if the fit is
 * ill-posed (fewer than 6 points, or nearly on a conic). */
static int fit_slope(const pt *pts, int n, const double mid[2], const double nrm[2], double l,
                     double *c) {
  if (n < 6) return 0;
  double V[8][6], N[6][7] = {{0}};
  for (int i = 0; i < n; i++) { /* monomials in (along, across)/l about mid */
    double dx = pts[i].p[0] - mid[0], dy = pts[i].p[1] - mid[1];
    double s = (dx * -nrm[1] + dy * nrm[0]) / l, t = (dx * nrm[0] + dy * nrm[1]) / l;
    const double row[6] = {1.0, s, t, s * s, s * t, t * t};
    memcpy(V[i], row, sizeof row);
  }
  for (int r = 0; r < 6; r++) {
    for (int q = 0; q < 6; q++)
      for (int i = 0; i < n; i++) N[r][q] += V[i][r] * V[i][q];
    N[r][6] = r == 2; /* solve N y = e_t: the slope's row of (V^T V)^-1 V^T is V y */
  }
  double top = 0.0;
  for (int r = 0; r < 6; r++) top = fmax(top, N[r][r]);
  for (int col = 0; col < 6; col++) { /* Cholesky-free elimination, SPD so no pivoting */
    if (!(N[col][col] > FIT_COND * top)) return 0;
    for (int r = col + 1; r < 6; r++) {
      double f = N[r][col] / N[col][col];
      for (int q = col; q < 7; q++) N[r][q] -= f * N[col][q];
    }
  }
  double y[6];
  for (int r = 5; r >= 0; r--) {
    y[r] = N[r][6];
    for (int q = r + 1; q < 6; q++) y[r] -= N[r][q] * y[q];
    y[r] /= N[r][r];
  }
  for (int i = 0; i < n; i++) {
    c[i] = 0.0;
    for (int r = 0; r < 6; r++) c[i] += V[i][r] * y[r];
    c[i] /= l; /* 1/m */
  }
  return 1;
}

/* Coefficients of grad L . nrm for the linear interpolant through three points (1/m). */
static void lin_slope(const double *p0, const double *p1, const double *p2, const double nrm[2],
                      double c[3]) {
  const double *p[3] = {p0, p1, p2};
  double det = cross2((double[2]){p1[0] - p0[0], p1[1] - p0[1]},
                      (double[2]){p2[0] - p0[0], p2[1] - p0[1]});
  for (int i = 0; i < 3; i++) { /* grad lambda_i = perp(p_{i+2} - p_{i+1}) / det */
    const double *a = p[(i + 1) % 3], *b = p[(i + 2) % 3];
    c[i] = (-(b[1] - a[1]) * nrm[0] + (b[0] - a[0]) * nrm[1]) / det;
  }
}

/* The slope of edge k at its midpoint as coefficients on the patch points: the slopes of f
 * and of the face across interpolated between their centroids, at distances h/3 and h'/3 from
 * the edge, where the two faces form a parallelogram (the interpolation is then exact for
 * quadratics, and needs no more vertices); else the fitted quadratic's, or the centroids' if
 * the fit is ill-posed. */
static void edge_slope(const pt *pts, int n, int k, const double nrm[2], double *c) {
  const double *a = pts[(k + 1) % 3].p, *b = pts[(k + 2) % 3].p;
  const double mid[2] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
  double l = hypot(b[0] - a[0], b[1] - a[1]);
  const double *pk = pts[k].p, *q = pts[3].p; /* a parallelogram: pk + q = a + b */
  int para = hypot(pk[0] + q[0] - a[0] - b[0], pk[1] + q[1] - a[1] - b[1]) < PARA_TOL * l;
  memset(c, 0, 8 * sizeof(double));
  if (!para && fit_slope(pts, n, mid, nrm, l, c)) return;
  double cf[3], cg[3];
  double h = fabs(cross2((double[2]){b[0] - a[0], b[1] - a[1]},
                         (double[2]){pts[k].p[0] - a[0], pts[k].p[1] - a[1]})) / l;
  double hg = fabs(cross2((double[2]){b[0] - a[0], b[1] - a[1]},
                          (double[2]){pts[3].p[0] - a[0], pts[3].p[1] - a[1]})) / l;
  lin_slope(pts[0].p, pts[1].p, pts[2].p, nrm, cf);
  lin_slope(a, b, pts[3].p, nrm, cg);
  for (int i = 0; i < 3; i++) c[i] += hg / (h + hg) * cf[i];
  c[(k + 1) % 3] += h / (h + hg) * cg[0];
  c[(k + 2) % 3] += h / (h + hg) * cg[1];
  c[3] += h / (h + hg) * cg[2];
}

/* Stencil-local index of vertex v, appended if new. */
static int local(int *sv, int *nv, int v) {
  for (int i = 0; i < *nv; i++)
    if (sv[i] == v) return i;
  sv[*nv] = v;
  return (*nv)++;
}

/* Schur complement of the 3 x 3 D (diagonal (D_u, D_v, 2G) in (uu, vv, sqrt(2) uv)) on the
 * complement of the free edges' curvatures nn_b: Dc = D - D N (N^T D N)^-1 N^T D. */
static void condense_free(const double D[3], const double nn[3][3], const int *bnd, int nb,
                          double Dc[3][3]) {
  double DN[3][2] = {{0}}, S[2][2] = {{0}}, Si[2][2] = {{0}};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) Dc[i][j] = i == j ? D[i] : 0.0;
  if (nb == 0) return;
  for (int i = 0; i < 3; i++)
    for (int p = 0; p < nb; p++) DN[i][p] = D[i] * nn[bnd[p]][i];
  for (int p = 0; p < nb; p++)
    for (int q = 0; q < nb; q++)
      for (int i = 0; i < 3; i++) S[p][q] += nn[bnd[p]][i] * DN[i][q];
  double det = nb == 1 ? S[0][0] : S[0][0] * S[1][1] - S[0][1] * S[1][0];
  if (!(fabs(det) > 0.0)) return;
  if (nb == 1) Si[0][0] = 1.0 / det;
  else Si[0][0] = S[1][1] / det, Si[1][1] = S[0][0] / det, Si[0][1] = -S[0][1] / det,
       Si[1][0] = -S[1][0] / det;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      for (int p = 0; p < nb; p++)
        for (int q = 0; q < nb; q++) Dc[i][j] -= DN[i][p] * Si[p][q] * DN[j][q];
}

/* Remove from each row of L (on nv stencil points at positions P, in T's layout) its part on
 * the affine functions 1, u, v, which it annihilates up to the fit's round-off: so that II_T
 * is exactly zero (to round-off of x) under rigid motions and uniform stretch. */
static void annihilate_affine(double L[3][NV], const double P[NV][2], int nv) {
  double B[3][NV]; /* an orthonormal basis of the affine functions on the points */
  for (int i = 0; i < nv; i++)
    B[0][i] = 1.0, B[1][i] = P[i][0] - P[0][0], B[2][i] = P[i][1] - P[0][1];
  for (int a = 0; a < 3; a++) {
    for (int b = 0; b < a; b++) {
      double d = 0.0;
      for (int i = 0; i < nv; i++) d += B[a][i] * B[b][i];
      for (int i = 0; i < nv; i++) B[a][i] -= d * B[b][i];
    }
    double n2 = 0.0;
    for (int i = 0; i < nv; i++) n2 += B[a][i] * B[a][i];
    for (int i = 0; i < nv; i++) B[a][i] /= sqrt(n2);
  }
  for (int r = 0; r < 3; r++)
    for (int a = 0; a < 3; a++) {
      double d = 0.0;
      for (int i = 0; i < nv; i++) d += L[r][i] * B[a][i];
      for (int i = 0; i < nv; i++) L[r][i] -= d * B[a][i];
    }
}

/* Face f's stencil sv (returns its size, 0: no interior edge), L (3 x NV), A Dc (3 x 3) and Q
 * (NV x NV, N/m). */
static int tri_setup(const sw_model *m, const sw_topology *tp, const int *fe, int f, int *sv,
                     double *Lout, double *Dout, double *Q) {
  const double *p = m->uv + 6 * f, A = m->area[f]; /* m^2 */
  double L[3][NV] = {{0}}, P[NV][2], nn[3][3], D[3], Dc[3][3];
  int nv = 3, bnd[3], nb = 0;
  for (int i = 0; i < 3; i++)
    sv[i] = m->face[3 * f + i], P[i][0] = p[2 * i], P[i][1] = p[2 * i + 1];
  sw_plate_rigidity(&m->mat[m->face_mat[f]], D);
  for (int k = 0; k < 3; k++) {
    const double *a = p + 2 * ((k + 1) % 3), *b = p + 2 * ((k + 2) % 3);
    double l = hypot(b[0] - a[0], b[1] - a[1]), nrm[2] = {(b[1] - a[1]) / l, (a[0] - b[0]) / l};
    if (nrm[0] * (p[2 * k] - a[0]) + nrm[1] * (p[2 * k + 1] - a[1]) > 0.0)
      nrm[0] = -nrm[0], nrm[1] = -nrm[1]; /* outward */
    nn[k][0] = nrm[0] * nrm[0], nn[k][1] = nrm[1] * nrm[1], nn[k][2] = sqrt(2.0) * nrm[0] * nrm[1];
    pt pts[8];
    int n = edge_patch(m, tp, fe, f, k, pts);
    if (n == 0) {
      bnd[nb++] = k;
      continue;
    }
    double c[8], cl[3];
    edge_slope(pts, n, k, nrm, c);
    lin_slope(p, p + 2, p + 4, nrm, cl);
    for (int i = 0; i < 3; i++) c[i] -= cl[i]; /* s_k - grad L_T . n_k */
    for (int i = 0; i < n; i++) {
      if (c[i] == 0.0) continue; /* a centroid slope uses 4 of the points */
      int v = local(sv, &nv, pts[i].v);
      P[v][0] = pts[i].p[0], P[v][1] = pts[i].p[1];
      for (int r = 0; r < 3; r++) L[r][v] += l / A * c[i] * nn[k][r]; /* 1/m^2 */
    }
  }
  if (nb == 3) return 0;
  annihilate_affine(L, P, nv);
  condense_free(D, nn, bnd, nb, Dc);
  memset(Q, 0, NV * NV * sizeof(double));
  for (int i = 0; i < nv; i++)
    for (int j = 0; j < nv; j++)
      for (int r = 0; r < 3; r++)
        for (int s = 0; s < 3; s++) Q[NV * i + j] += A * L[r][i] * Dc[r][s] * L[s][j];
  for (int r = 0; r < 3; r++) {
    memcpy(Lout + NV * r, L[r], NV * sizeof(double));
    for (int s = 0; s < 3; s++) Dout[3 * r + s] = A * Dc[r][s];
  }
  return nv;
}

/* ------------------------------------------------------------------ the term */

static int morley_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const morley_param *mp = t->param;
  const int d = m->dim, compact = mp->cm.C != NULL;
  const int *sptr = compact ? mp->cm.sptr : t->sptr, *sidx = compact ? mp->cm.sidx : t->sidx;
  double total = 0.0;
  if (ev->hess && compact) sw_compact_hess(t, m, &mp->cm, ev);
  for (int s = 0; s < mp->n; s++) {
    const int *v = sidx + sptr[s], nv = sptr[s + 1] - sptr[s], bw = nv * d;
    const double *Q = mp->Q + NV * NV * s, *L = mp->L + 3 * NV * s, *D = mp->D + 9 * s;
    double II[3][3] = {{0}}, mu[3][3] = {{0}}; /* II_T (1/m), A D : II_T (N m^2) */
    for (int r = 0; r < 3; r++)
      for (int i = 0; i < nv; i++)
        for (int c = 0; c < d; c++) II[r][c] += L[NV * r + i] * ev->x[(size_t)v[i] * d + c];
    for (int r = 0; r < 3; r++)
      for (int q = 0; q < 3; q++)
        for (int c = 0; c < d; c++) mu[r][c] += D[3 * r + q] * II[q][c];
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < d; c++) total += 0.5 * mu[r][c] * II[r][c];
    if (ev->grad)
      for (int i = 0; i < nv; i++)
        for (int c = 0; c < d; c++)
          for (int r = 0; r < 3; r++) ev->grad[(size_t)v[i] * d + c] += L[NV * r + i] * mu[r][c];
    if (!ev->hess || compact) continue;
    double *blk = sw_ev_block(ev, t, s);
    for (int i = 0; i < nv; i++)
      for (int j = 0; j < nv; j++)
        for (int a = 0; a < d; a++) sw_hess_add(blk, bw, i * d + a, j * d + a, Q[NV * i + j]);
    sw_ev_block_done(ev, t, s, blk);
  }
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static const sw_term_ops morley_ops = {
    .kind = "morley", .eval = morley_eval, .free_param = morley_free, .sink_ok = 1};

static int bends(const sw_model *m, int f) {
  const sw_material *mt = &m->mat[m->face_mat[f]];
  return mt->bending == SW_BENDING_MORLEY && (mt->k_bend > 0.0 || mt->k_bend_u > 0.0) &&
         m->area[f] > 0.0;
}

int sw_morley_bending_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  morley_param *mp = sw_calloc(1, sizeof *mp);
  t->ops = &morley_ops;
  t->param = mp;
  snprintf(t->name, sizeof t->name, "%s", "morley");
  if (!mp) return sw_errf(err, errsz, "out of memory"), -1;
  sw_topology tp;
  if (sw_topology_build(&tp, m, err, errsz)) return -1;
  int *fe = sw_face_edges(m, &tp), *sv = sw_calloc(NV * (size_t)m->nf + 1, sizeof(int));
  mp->Q = sw_calloc((size_t)m->nf + 1, NV * NV * sizeof(double));
  mp->L = sw_calloc((size_t)m->nf + 1, 3 * NV * sizeof(double));
  mp->D = sw_calloc((size_t)m->nf + 1, 9 * sizeof(double));
  t->sptr = sw_calloc((size_t)m->nf + 1, sizeof(int));
  t->hptr = sw_calloc((size_t)m->nf + 1, sizeof(long));
  int rc = !fe || !sv || !mp->Q || !mp->L || !mp->D || !t->sptr || !t->hptr;
  for (int f = 0; !rc && f < m->nf; f++) {
    if (!bends(m, f)) continue;
    int *s = sv + t->sptr[mp->n], k = mp->n;
    int nv = tri_setup(m, &tp, fe, f, s, mp->L + 3 * NV * k, mp->D + 9 * k, mp->Q + NV * NV * k);
    if (nv == 0) continue;
    t->sptr[mp->n + 1] = t->sptr[mp->n] + nv;
    t->hptr[mp->n + 1] = t->hptr[mp->n] + sw_hess_size(nv * m->dim);
    mp->n++;
  }
  t->nstencil = mp->n;
  t->sidx = sv;
  sw_free(fe);
  sw_topology_free(&tp);
  if (rc) return sw_errf(err, errsz, "out of memory for the bending of %d faces", m->nf), -1;
  if (m->opt.bending_matrix == SW_BMATRIX_COMPACT && mp->n > 0)
    return sw_compact_stencils(t, m, mp->Q, NV, &mp->cm, err, errsz);
  return 0;
}
