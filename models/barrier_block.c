/* barrier_block.c — a contact pair's barrier Hessian block, clamped to positive semi-definite
 * on the (at most 5-dimensional) span of its columns instead of all 12 coordinates.
 *
 * Every pair distance of models/distance.c is d2(x) = min_s |r(x, s)|^2 with r = sum_i c_i x_i
 * and the coefficients c affine in k <= 2 parameters s (the closest point on an edge or a
 * triangle, or one on each of two lines).  Its exact Hessian is (models/distance.c)
 *
 *   Hess d2 = 2 c c^T (x) I - K,   K = 2 sum_jl u_j (G^-1)_jl u_l^T,
 *   u_j = c (x) R_j + dc_j (x) r,  R_j = sum_i dc_ji x_i,  G_jl = R_j . R_l,
 *
 * K positive semi-definite (the closest points sliding as the primitives move).  The barrier
 * w b(d2 - xi^2) therefore has the exact Hessian
 *
 *   w (b'' grad d2 grad d2^T + 2 b' c c^T (x) I - 2 b' sum_m v_m v_m^T),   K = 2 sum v_m v_m^T,
 *
 * of rank at most 5 over 12 coordinates: its columns lie in the span of c (x) e_a (a = 0, 1, 2)
 * and of the k sliding directions v_m.  Its nearest positive semi-definite matrix (the
 * eigenvalues clamped at 0, as sw_psd_project does) is therefore found on that span: an
 * orthonormal basis Q of it in closed form (the c (x) e_a are orthogonal already), the 5 x 5
 * (at most) matrix Q^T H Q from the form without forming H, its clamped eigen-decomposition,
 * and Q (.) Q^T back.  The same block as a 12 x 12 eigen-decomposition gives, to round-off,
 * at a fraction of its cost, with no Hessian of d2 formed.  The structure is the one GIPC
 * exploits (Huang, Chitalu, Lin and Komura, "GIPC: Fast and stable Gauss-Newton optimization
 * of IPC barrier energy", ACM TOG 2024: a rank-one normal part b'' grad d2 grad d2^T and a
 * second part projected analytically); its Gauss-Newton simplification of dropping the negative
 * tangential part 2 b' c c^T (x) (I - n n^T) while keeping |b'| K was measured here and
 * needed more Newton iterations (docs/contact.md, "Cost"), so the block is the exact clamp.
 * A point and a line (k = 1) need only 3 of the 4 dimensions: c (x) (n x t), n the normal and
 * t the line's direction, is an eigenvector of eigenvalue 2 w b' |c|^2 <= 0 (the gradient and
 * v_0 are orthogonal to it), which the clamp takes to 0, so it is left out of Q. */
#include <math.h>
#include <string.h>

#include "contact_geom.h"
#include "terms.h"

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* A distance form on n <= 4 of the pair's vertices (idx into the pair's 4) with k parameters:
 * dc[j][i] the coefficient of vertex i in the direction R_j. */
typedef struct pform {
  int shape; /* 0 point-point, 1 point-line, 2 point-plane, 3 line-line */
  int n, k, idx[4];
  double dc[2][4];
} pform;

/* The forms of models/distance.c: point-point, point-line (p, e0, e1), point-plane
 * (p, t0, t1, t2), line-line (a0, a1, b0, b1); r's coefficient of vertex 0 is 1 in the first
 * three, and those of vertices 0 and 1 sum to 1 in the last. */
static const pform F_PP = {0, 2, 0, {0}, {{0}}};
static const pform F_PL = {1, 3, 1, {0}, {{0, 1, -1, 0}}};
static const pform F_PPLANE = {2, 4, 2, {0}, {{0, 1, -1, 0}, {0, 1, 0, -1}}};
static const pform F_LL = {3, 4, 2, {0}, {{-1, 1, 0, 0}, {0, 0, 1, -1}}};

static pform with_idx(const pform *f, int i0, int i1, int i2, int i3) {
  pform g = *f;
  g.idx[0] = i0, g.idx[1] = i1, g.idx[2] = i2, g.idx[3] = i3;
  return g;
}

/* The form of a point-triangle pair (p, t0, t1, t2) by its closest features. */
static pform pt_form(const double *x) {
  sw_pt_type t = sw_point_triangle_type(x, x + 3, x + 6, x + 9);
  switch (t) {
  case SW_PT_T0: case SW_PT_T1: case SW_PT_T2: return with_idx(&F_PP, 0, 1 + (int)t, 0, 0);
  case SW_PT_E01: return with_idx(&F_PL, 0, 1, 2, 0);
  case SW_PT_E12: return with_idx(&F_PL, 0, 2, 3, 0);
  case SW_PT_E20: return with_idx(&F_PL, 0, 3, 1, 0);
  default: return with_idx(&F_PPLANE, 0, 1, 2, 3);
  }
}

/* The form of an edge-edge pair (a0, a1, b0, b1) by its closest features. */
static pform ee_form(const double *x) {
  switch (sw_edge_edge_type(x, x + 3, x + 6, x + 9)) {
  case SW_EE_A0B0: return with_idx(&F_PP, 0, 2, 0, 0);
  case SW_EE_A0B1: return with_idx(&F_PP, 0, 3, 0, 0);
  case SW_EE_A1B0: return with_idx(&F_PP, 1, 2, 0, 0);
  case SW_EE_A1B1: return with_idx(&F_PP, 1, 3, 0, 0);
  case SW_EE_A0_B: return with_idx(&F_PL, 0, 2, 3, 0);
  case SW_EE_A1_B: return with_idx(&F_PL, 1, 2, 3, 0);
  case SW_EE_A_B0: return with_idx(&F_PL, 2, 0, 1, 0);
  case SW_EE_A_B1: return with_idx(&F_PL, 3, 0, 1, 0);
  default: return with_idx(&F_LL, 0, 1, 2, 3);
  }
}

/* d2 of form f at the pair's points x (12) and its gradient over the form's vertices (3n),
 * by models/distance.c's own distances. */
static double form_d2(const pform *f, const double *x, double *gf) {
  const double *v[4];
  for (int i = 0; i < f->n; i++) v[i] = x + 3 * f->idx[i];
  switch (f->shape) {
  case 0: return sw_d2_point_point(v[0], v[1], gf, NULL);
  case 1: return sw_d2_point_line(v[0], v[1], v[2], gf, NULL);
  case 2: return sw_d2_point_plane(v[0], v[1], v[2], v[3], gf, NULL);
  default: return sw_d2_line_line(v[0], v[1], v[2], v[3], gf, NULL);
  }
}

double sw_pair_d2_form(int edge_edge, const double *x, sw_pair_form *pf) {
  pform f = edge_edge ? ee_form(x) : pt_form(x);
  double gf[12], r[3], c[4], R[2][3];
  memset(pf, 0, sizeof *pf);
  double d2 = form_d2(&f, x, gf);
  pf->d2 = d2;
  for (int i = 0; i < f.n; i++)
    for (int a = 0; a < 3; a++) pf->g[3 * f.idx[i] + a] = gf[3 * i + a];
  /* r from grad d2 = 2 c (x) r: c_0 = 1, or c_0 + c_1 = 1 for two lines */
  for (int a = 0; a < 3; a++) r[a] = 0.5 * (f.shape == 3 ? gf[a] + gf[3 + a] : gf[a]);
  double rr = dot3(r, r);
  if (!(rr > 0.0)) return d2; /* touching: no normal (the barrier is infinite there anyway) */
  for (int i = 0; i < f.n; i++) pf->c[f.idx[i]] = c[i] = dot3(gf + 3 * i, r) / (2.0 * rr);
  for (int j = 0; j < f.k; j++)
    for (int a = 0; a < 3; a++) {
      R[j][a] = 0.0;
      for (int i = 0; i < f.n; i++) R[j][a] += f.dc[j][i] * x[3 * f.idx[i] + a];
    }
  /* G^-1 = L L^T (2 x 2 at most), so that K = 2 sum_m v_m v_m^T with v_m = sum_j u_j L_jm */
  double L[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
  if (f.k == 1) {
    double G = dot3(R[0], R[0]);
    if (!(G > 0.0)) return d2;
    L[0][0] = 1.0 / sqrt(G);
  } else if (f.k == 2) {
    double G00 = dot3(R[0], R[0]), G11 = dot3(R[1], R[1]), G01 = dot3(R[0], R[1]);
    double w[3] = {R[0][1] * R[1][2] - R[0][2] * R[1][1], R[0][2] * R[1][0] - R[0][0] * R[1][2],
                   R[0][0] * R[1][1] - R[0][1] * R[1][0]};
    double det = dot3(w, w); /* G00 G11 - G01^2 without its cancellation */
    if (!(det > 0.0) || !(G11 > 0.0)) return d2;
    /* G^-1 = [G11 -G01; -G01 G00] / det = L L^T with L lower triangular */
    double l00 = sqrt(G11 / det), l10 = -G01 / (det * l00);
    L[0][0] = l00, L[1][0] = l10, L[1][1] = sqrt(fmax(G00 / det - l10 * l10, 0.0));
  }
  pf->k = f.k;
  for (int m = 0; m < f.k; m++)
    for (int i = 0; i < f.n; i++)
      for (int a = 0; a < 3; a++) {
        double s = 0.0;
        for (int j = 0; j < f.k; j++) s += L[j][m] * (c[i] * R[j][a] + f.dc[j][i] * r[a]);
        pf->v[m][3 * f.idx[i] + a] = s;
      }
  return d2;
}

void sw_pair_hess_d2(const sw_pair_form *pf, double *H) {
  for (int p = 0; p < 12; p++)
    for (int q = 0; q < 12; q++) {
      double s = p % 3 == q % 3 ? 2.0 * pf->c[p / 3] * pf->c[q / 3] : 0.0;
      for (int m = 0; m < pf->k; m++) s -= 2.0 * pf->v[m][p] * pf->v[m][q];
      H[p * 12 + q] = s;
    }
}

/* Gram-Schmidt of vector q (12) against Q[0..r), twice for round-off; 1 and q normalised when
 * it keeps more than 1e-12 of its size (else it lies in their span already). */
static int orthonormalise(double Q[5][12], int r, double *q) {
  double n0 = 0.0, n1 = 0.0;
  for (int p = 0; p < 12; p++) n0 += q[p] * q[p];
  for (int j = 0; j < r; j++)
    for (int pass = 0; pass < 2; pass++) {
      double s = 0.0;
      for (int p = 0; p < 12; p++) s += Q[j][p] * q[p];
      for (int p = 0; p < 12; p++) q[p] -= s * Q[j][p];
    }
  for (int p = 0; p < 12; p++) n1 += q[p] * q[p];
  if (!(n1 > 1e-24 * n0)) return 0;
  for (int p = 0; p < 12; p++) q[p] /= sqrt(n1);
  return 1;
}

/* For one sliding direction (a point and a line): the unit normal n = r/|r| and the unit
 * tangent t along the line, into e[0] and e[1]; 0 when they cannot be told apart. */
static int line_frame(const sw_pair_form *pf, double e[2][3]) {
  int i = 0; /* the vertex of the largest coefficient: r = g_i / (2 c_i) there */
  for (int j = 1; j < 4; j++)
    if (fabs(pf->c[j]) > fabs(pf->c[i])) i = j;
  double nn = 0.0, tt = 0.0, vn = 0.0;
  for (int a = 0; a < 3; a++) nn += pf->g[3 * i + a] * pf->g[3 * i + a];
  if (!(nn > 0.0)) return 0;
  for (int a = 0; a < 3; a++) e[0][a] = pf->g[3 * i + a] / sqrt(nn) * (pf->c[i] > 0.0 ? 1.0 : -1.0);
  for (int a = 0; a < 3; a++) vn += pf->v[0][3 * i + a] * e[0][a];
  for (int a = 0; a < 3; a++) { /* v_0 at vertex i is L (c_i R + dc_i r), R orthogonal to r */
    e[1][a] = pf->v[0][3 * i + a] - vn * e[0][a];
    tt += e[1][a] * e[1][a];
  }
  if (!(tt > 1e-24 * (tt + vn * vn))) return 0;
  for (int a = 0; a < 3; a++) e[1][a] /= sqrt(tt);
  return 1;
}

/* The orthonormal basis Q (12 x *r, column j at Q[j]) of the span of c (x) e_a (a = 0, 1, 2)
 * and the v_m, which holds every column of the exact Hessian; directions of v_m below 1e-12 of
 * its size are dropped (they lie in the span already).  *nc: how many columns are of the form
 * c (x) e (the first ones).  With one sliding direction and drop_side, the direction
 * c (x) (n x t) (n the normal, t the line's direction) is left out: v_0 and the gradient are
 * orthogonal to it, so it is an eigenvector of eigenvalue 2 w b' |c|^2 <= 0, which the clamp
 * takes to 0. */
static int span_basis(const sw_pair_form *pf, int drop_side, double Q[5][12], int *nc) {
  double cc = 0.0, e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 4; i++) cc += pf->c[i] * pf->c[i];
  double lc = sqrt(cc);
  memset(Q, 0, 5 * sizeof Q[0]);
  *nc = pf->k == 1 && drop_side && line_frame(pf, e) ? 2 : 3;
  for (int j = 0; j < *nc; j++)
    for (int i = 0; i < 4; i++)
      for (int a = 0; a < 3; a++) Q[j][3 * i + a] = pf->c[i] / lc * e[j][a];
  int r = *nc;
  for (int m = 0; m < pf->k; m++) {
    memcpy(Q[r], pf->v[m], sizeof Q[0]);
    r += orthonormalise(Q, r, Q[r]);
  }
  return r;
}

int sw_pair_barrier_block(const sw_pair_form *pf, double db, double d2b, double w, double *H) {
  double Q[5][12], M[25], gq[5], vq[2][5];
  memset(H, 0, 144 * sizeof(double));
  double cc = 0.0;
  for (int i = 0; i < 4; i++) cc += pf->c[i] * pf->c[i];
  if (!(cc > 0.0)) return 0; /* touching: the barrier is infinite there */
  if (pf->k == 0 && db <= 0.0) { /* two points: Q^T H Q = w (b'' g g^T + 2 b' |c|^2 I_3), whose
                                    only eigenvalue that may be positive is along g */
    double gg = 0.0;
    for (int p = 0; p < 12; p++) gg += pf->g[p] * pf->g[p];
    double lam = w * (d2b * gg + 2.0 * db * cc);
    if (!isfinite(lam)) return -1;
    if (!(lam > 0.0) || !(gg > 0.0)) return 0;
    for (int p = 0; p < 12; p++)
      for (int q = 0; q < 12; q++) H[p * 12 + q] = lam / gg * pf->g[p] * pf->g[q];
    return 0;
  }
  int nc, r = span_basis(pf, db <= 0.0, Q, &nc);
  for (int j = 0; j < r; j++) { /* the coordinates of g and the v_m in Q */
    gq[j] = vq[0][j] = vq[1][j] = 0.0;
    for (int p = 0; p < 12; p++) {
      gq[j] += Q[j][p] * pf->g[p];
      for (int m = 0; m < pf->k; m++) vq[m][j] += Q[j][p] * pf->v[m][p];
    }
  }
  /* Q^T Hess b Q = b'' gq gq^T + 2 b' |c|^2 (I_nc + 0) - 2 b' sum_m vq_m vq_m^T */
  for (int i = 0; i < r; i++)
    for (int j = 0; j < r; j++) {
      double s = d2b * gq[i] * gq[j] + (i == j && i < nc ? 2.0 * db * cc : 0.0);
      for (int m = 0; m < pf->k; m++) s -= 2.0 * db * vq[m][i] * vq[m][j];
      M[i * r + j] = w * s;
    }
  if (sw_psd_project(M, r, SW_FILTER_CLAMP)) return -1;
  double QM[5][12]; /* (Q M)^T */
  for (int j = 0; j < r; j++)
    for (int p = 0; p < 12; p++) {
      double s = 0.0;
      for (int i = 0; i < r; i++) s += Q[i][p] * M[i * r + j];
      QM[j][p] = s;
    }
  for (int p = 0; p < 12; p++)
    for (int q = p; q < 12; q++) {
      double s = 0.0;
      for (int j = 0; j < r; j++) s += QM[j][p] * Q[j][q];
      H[p * 12 + q] = H[q * 12 + p] = s;
    }
  return 0;
}

/* An orthonormal basis of the vectors of R^4 whose entries sum to 0 (Helmert's contrasts):
 * the differences of the 4 vertices' motions, which is all a translation-free energy sees. */
static const double HELMERT[3][4] = {
    {0.70710678118654752, -0.70710678118654752, 0.0, 0.0},
    {0.40824829046386302, 0.40824829046386302, -0.81649658092772603, 0.0},
    {0.28867513459481289, 0.28867513459481289, 0.28867513459481289, -0.86602540378443865}};

int sw_pair_clamp_free(double *H) {
  /* Q = HELMERT^T (x) I_3 (12 x 9): M = Q^T H Q, its clamp, then H = Q M Q^T; each product
   * goes vertex by vertex (T = Q^T H is 9 x 12) */
  double T[9][12], M[81];
  for (int k = 0; k < 3; k++)
    for (int a = 0; a < 3; a++)
      for (int q = 0; q < 12; q++) {
        double s = 0.0;
        for (int i = 0; i < 4; i++) s += HELMERT[k][i] * H[(3 * i + a) * 12 + q];
        T[3 * k + a][q] = s;
      }
  for (int r = 0; r < 9; r++)
    for (int l = 0; l < 3; l++)
      for (int b = 0; b < 3; b++) {
        double s = 0.0;
        for (int j = 0; j < 4; j++) s += T[r][3 * j + b] * HELMERT[l][j];
        M[r * 9 + 3 * l + b] = s;
      }
  for (int r = 0; r < 9; r++) /* symmetric to round-off: make it exactly so */
    for (int c = r + 1; c < 9; c++) M[r * 9 + c] = M[c * 9 + r] = 0.5 * (M[r * 9 + c] + M[c * 9 + r]);
  if (sw_psd_project(M, 9, SW_FILTER_CLAMP)) return -1;
  for (int r = 0; r < 9; r++) /* T = M Q^T (9 x 12) */
    for (int j = 0; j < 4; j++)
      for (int b = 0; b < 3; b++) {
        double s = 0.0;
        for (int l = 0; l < 3; l++) s += M[r * 9 + 3 * l + b] * HELMERT[l][j];
        T[r][3 * j + b] = s;
      }
  for (int i = 0; i < 4; i++)
    for (int a = 0; a < 3; a++)
      for (int q = 0; q < 12; q++) {
        double s = 0.0;
        for (int k = 0; k < 3; k++) s += HELMERT[k][i] * T[3 * k + a][q];
        H[(3 * i + a) * 12 + q] = s;
      }
  return 0;
}
