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
 * v_0 are orthogonal to it), which the clamp takes to 0, so it is left out of Q.  Where the
 * closest points slide (k >= 1) the span's eigensystem is known in closed form up to a
 * rank-one change, and sw_pair_clamp_closed (below) gives the block without an
 * eigen-decomposition; the decomposition on the span is what is left for the cases it cannot
 * give to round-off. */
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
  return sw_pair_d2_form_near(edge_edge, x, INFINITY, pf);
}

double sw_pair_d2_form_near(int edge_edge, const double *x, double d2max, sw_pair_form *pf) {
  pform f = edge_edge ? ee_form(x) : pt_form(x);
  double gf[12], r[3], c[4], R[2][3];
  double d2 = form_d2(&f, x, gf);
  if (!(d2 < d2max)) { /* beyond reach: the distance alone */
    pf->d2 = d2;
    return d2;
  }
  memset(pf, 0, sizeof *pf);
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

/* ------------------------------------------------------------ the clamp in closed form */

/* At an interior minimiser of the distance form (k >= 1) r is orthogonal to every R_j, so with
 * n = r / |r| and the unit tangents tau_m = sum_j L_jm R_j (orthonormal, as L L^T = G^-1) each
 * sliding direction splits as v_m = c (x) tau_m + nu_m (x) n, nu_m = |r| sum_j L_jm dc_j (a
 * weight per vertex).  In the coordinates y_m along chat (x) tau_m (chat = c / |c|) and z (a
 * weight per vertex) along z (x) n the block's quadratic form is then
 *
 *   w [rho0 (chat . z)^2 + gamma0 sum_m (2 |c| y_m (nu_m . z) + (nu_m . z)^2)],
 *   rho0 = b'' |grad d2|^2 + 2 b' |c|^2,   gamma0 = -2 b' >= 0:
 *
 * the tangential block is exactly zero (the curvature 2 b' |c|^2 of sliding cancels against
 * the closest points' own sliding).  With the singular vectors of N = [nu_0 nu_1] (N w_i =
 * sigma_i u_i: a 2 x 2 eigenproblem) the part without rho0 falls apart into 2 x 2 blocks
 * gamma0 [0, |c| sigma_i; |c| sigma_i, sigma_i^2] on (w_i . y, u_i . z), whose eigenpairs are
 * written down, plus a zero eigenvalue on the part of chat outside the u_i.  The block is thus
 * D + rho P P^T (P = chat (x) n, rho = w rho0): a diagonal matrix in a known orthonormal basis
 * plus a rank-one term, whose eigenvalues are the roots of the secular equation
 * 1 + rho sum_i z_i^2 / (d_i - lambda) = 0, one between each two poles (Golub, "Some modified
 * matrix eigenvalue problems", SIAM Review 1973; the merge step of Cuppen's divide and conquer,
 * as in LAPACK's dlaed4), and whose eigenvectors are (D - lambda)^-1 z.  With rho >= 0 only
 * the (at most k) roots left of the first k poles can be negative: the clamp subtracts those
 * eigenpairs from D + rho P P^T.  Each root is found from its nearer pole (so that the
 * differences d_i - lambda that make its eigenvector keep their digits) by Newton's method
 * kept inside the root's bracket.  The cases this leaves inaccurate -- rho < 0, a vanishing
 * singular value, two poles within 1e-9 of the block's size, two computed eigenvectors not
 * orthogonal to 1e-10 -- return 0 and take the eigen-decomposition on the span instead. */

/* The block in the closed-form basis: sum_i d[i] e[i] e[i]^T + rho P P^T, z[i] = e[i] . P. */
typedef struct rank1 {
  int n;
  double d[5], z[5], e[5][12];
} rank1;

/* The 2 x 2 eigenproblem of the symmetric [a, c; c, b]: eigenvalues l[0], l[1] and unit
 * eigenvectors W[.][i] (columns), by one Jacobi rotation. */
static void eig2(double a, double b, double c, double *l, double W[2][2]) {
  double cs = 1.0, sn = 0.0;
  if (c != 0.0) {
    double th = (b - a) / (2.0 * c), at = fabs(th);
    double t = (th >= 0.0 ? 1.0 : -1.0) / (at + (at < 1e150 ? sqrt(th * th + 1.0) : at));
    cs = 1.0 / sqrt(t * t + 1.0), sn = t * cs;
  }
  l[0] = cs * cs * a - 2.0 * cs * sn * c + sn * sn * b;
  l[1] = sn * sn * a + 2.0 * cs * sn * c + cs * cs * b;
  W[0][0] = cs, W[1][0] = -sn, W[0][1] = sn, W[1][1] = cs;
}

/* The basis of the block's span and its rank-one form (see above); 0 when it does not apply. */
static int rank1_form(const sw_pair_form *pf, double db, double d2b, double w, rank1 *R,
                      double *rho) {
  int k = pf->k;
  double cc = 0.0, r[3] = {0.0, 0.0, 0.0}, nu[2][4], t[2][12], gg = 0.0;
  for (int i = 0; i < 4; i++) cc += pf->c[i] * pf->c[i];
  for (int p = 0; p < 12; p++) gg += pf->g[p] * pf->g[p];
  if (k < 1 || !(cc > 0.0) || !(gg > 0.0)) return 0;
  double lc = sqrt(cc), chat[4], nrm[3];
  for (int i = 0; i < 4; i++) /* grad d2 = 2 c (x) r */
    for (int a = 0; a < 3; a++) r[a] += pf->c[i] * pf->g[3 * i + a] / (2.0 * cc);
  double lr = sqrt(dot3(r, r));
  if (!(lr > 0.0)) return 0;
  for (int a = 0; a < 3; a++) nrm[a] = r[a] / lr;
  for (int i = 0; i < 4; i++) chat[i] = pf->c[i] / lc;
  for (int m = 0; m < k; m++)
    for (int i = 0; i < 4; i++) {
      nu[m][i] = dot3(pf->v[m] + 3 * i, nrm);
      for (int a = 0; a < 3; a++) t[m][3 * i + a] = (pf->v[m][3 * i + a] - nu[m][i] * nrm[a]) / lc;
    }
  double sig2[2] = {0.0, 0.0}, W[2][2] = {{1.0, 0.0}, {0.0, 1.0}};
  if (k == 1)
    sig2[0] = nu[0][0] * nu[0][0] + nu[0][1] * nu[0][1] + nu[0][2] * nu[0][2] + nu[0][3] * nu[0][3];
  else {
    double G[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 4; i++)
      G[0] += nu[0][i] * nu[0][i], G[1] += nu[1][i] * nu[1][i], G[2] += nu[0][i] * nu[1][i];
    eig2(G[0], G[1], G[2], sig2, W);
  }
  double gam = -2.0 * w * db, perp[4];
  memcpy(perp, chat, sizeof perp);
  R->n = 0;
  for (int s = 0; s < k; s++) {
    double sig = sqrt(fmax(sig2[s], 0.0)), u[4], Y[12], beta = 0.0;
    if (!(sig > 1e-8 * lc)) return 0;
    for (int i = 0; i < 4; i++) {
      u[i] = 0.0;
      for (int m = 0; m < k; m++) u[i] += W[m][s] * nu[m][i] / sig;
      beta += u[i] * chat[i];
    }
    for (int i = 0; i < 4; i++) perp[i] -= beta * u[i];
    for (int p = 0; p < 12; p++) {
      Y[p] = 0.0;
      for (int m = 0; m < k; m++) Y[p] += W[m][s] * t[m][p];
    }
    /* [0, a; a, b]: mu- = -2 a^2 / (b + h) with eigenvector (a, mu-), mu+ = (b + h) / 2 with
     * (-mu-, a), h = sqrt(b^2 + 4 a^2) */
    double a = lc * sig, b = sig * sig, h = sqrt(b * b + 4.0 * a * a);
    double mum = -2.0 * a * a / (b + h), mup = 0.5 * (b + h), nv = sqrt(a * a + mum * mum);
    double cy[2] = {a / nv, -mum / nv}, cz[2] = {mum / nv, a / nv}, mu[2] = {mum, mup};
    for (int j = 0; j < 2; j++, R->n++) {
      for (int i = 0; i < 4; i++)
        for (int x = 0; x < 3; x++)
          R->e[R->n][3 * i + x] = cy[j] * Y[3 * i + x] + cz[j] * u[i] * nrm[x];
      R->d[R->n] = gam * mu[j];
      R->z[R->n] = cz[j] * beta;
    }
  }
  double lp = sqrt(perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2] + perp[3] * perp[3]);
  if (lp > 1e-14) { /* chat outside the u_i: an eigenvector of eigenvalue 0 without rho */
    for (int i = 0; i < 4; i++)
      for (int x = 0; x < 3; x++) R->e[R->n][3 * i + x] = perp[i] / lp * nrm[x];
    R->d[R->n] = 0.0;
    R->z[R->n++] = lp;
  }
  *rho = w * (d2b * gg + 2.0 * db * cc);
  return isfinite(*rho) && isfinite(gam) && *rho >= 0.0;
}

/* The secular function f = 1 + rho sum_i z_i^2 / (delta_i - tau) over the indices a[0..na),
 * the poles delta = d - origin, and its derivative (> 0) into *df. */
static double secular(const rank1 *R, const int *a, int na, double rho, double origin,
                      double tau, double *df) {
  double f = 1.0, s = 0.0;
  for (int j = 0; j < na; j++) {
    double q = R->z[a[j]] / ((R->d[a[j]] - origin) - tau); /* a component of the vector */
    f += rho * R->z[a[j]] * q;
    s += rho * q * q;
  }
  *df = s;
  return f;
}

/* The root of the secular equation between the poles d[a[j]] and d[a[j + 1]] (or, for the
 * last, below d[a[j]] + rho |z|^2), measured from the nearer pole: *origin, and the root's
 * offset tau from it (returned).  Newton's method on -tau f(tau), which has no pole at the
 * origin (the root's bracket holds no other pole within half the gap), a bisection whenever
 * it leaves the bracket. */
static double secular_root(const rank1 *R, const int *a, int na, int j, double rho, double zz,
                           double *origin) {
  double lo = R->d[a[j]], hi = j + 1 < na ? R->d[a[j + 1]] : lo + rho * zz, df;
  *origin = lo;
  if (j + 1 < na && secular(R, a, na, rho, lo, 0.5 * (hi - lo), &df) < 0.0) *origin = hi;
  double tlo = lo - *origin, thi = hi - *origin, tau = 0.5 * (tlo + thi);
  if (*origin == lo) thi = tau; else tlo = tau; /* the half with the root (f rises) */
  double F0 = 0.0, dF0 = -1.0; /* the start: Newton's step on -tau f from tau = 0 */
  for (int l = 0; l < na; l++) {
    double dl = R->d[a[l]] - *origin;
    if (dl == 0.0) F0 += rho * R->z[a[l]] * R->z[a[l]];
    else dF0 -= rho * R->z[a[l]] * R->z[a[l]] / dl;
  }
  tau = -F0 / dF0;
  if (!(tau > tlo && tau < thi)) tau = 0.5 * (tlo + thi);
  for (int it = 0; it < 100; it++) {
    double f = secular(R, a, na, rho, *origin, tau, &df);
    if (f == 0.0) break;
    if (f < 0.0) tlo = tau; else thi = tau;
    double F = -tau * f, dF = -f - tau * df, step = tau - F / dF;
    if (fabs(step - tau) <= 4e-16 * fabs(tau)) break; /* converged to round-off */
    tau = step > tlo && step < thi ? step : 0.5 * (tlo + thi);
  }
  return tau;
}

int sw_pair_clamp_closed(const sw_pair_form *pf, double db, double d2b, double w, double *H) {
  rank1 R;
  double rho, zz = 0.0, scale = 0.0, U[2][5] = {{0.0}}, lam[2], S[5][5], T[5][12];
  if (!rank1_form(pf, db, d2b, w, &R, &rho)) return 0;
  for (int i = 0; i < R.n; i++) zz += R.z[i] * R.z[i], scale = fmax(scale, fabs(R.d[i]));
  scale += rho * zz;
  int a[5], na = 0, nneg = 0, moved[5] = {0};
  for (int i = 0; i < R.n; i++) /* the poles the rank-one term moves, in increasing order */
    if (rho * fabs(R.z[i]) * sqrt(zz) > 1e-14 * scale) {
      int j = na++;
      for (; j > 0 && R.d[a[j - 1]] > R.d[i]; j--) a[j] = a[j - 1];
      a[j] = i, moved[i] = 1;
    }
  for (int j = 0; j + 1 < na; j++)
    if (!(R.d[a[j + 1]] - R.d[a[j]] > 1e-9 * scale)) return 0;
  for (int j = 0; j < na && R.d[a[j]] < 0.0; j++) {
    double df, origin;
    if ((j + 1 == na || R.d[a[j + 1]] > 0.0) && secular(&R, a, na, rho, 0.0, 0.0, &df) <= 0.0)
      break; /* f(0) <= 0: this root and those above it are >= 0 */
    double tau = secular_root(&R, a, na, j, rho, zz, &origin), nu = 0.0;
    lam[nneg] = origin + tau;
    if (!(lam[nneg] < 0.0)) break;
    for (int l = 0; l < na; l++) { /* the eigenvector (D - lambda)^-1 z, in the basis e */
      U[nneg][a[l]] = R.z[a[l]] / ((R.d[a[l]] - origin) - tau);
      nu += U[nneg][a[l]] * U[nneg][a[l]];
    }
    for (int i = 0; i < R.n; i++) U[nneg][i] /= sqrt(nu);
    nneg++;
  }
  if (nneg == 2) {
    double o = 0.0;
    for (int i = 0; i < R.n; i++) o += U[0][i] * U[1][i];
    if (!(fabs(o) <= 1e-10)) return 0;
  }
  /* S: the clamped block in the basis e (P = sum_i z_i e_i): D without the negative eigenpairs
   * the rank-one term leaves alone, plus rho z z^T, minus the negative eigenpairs */
  for (int i = 0; i < R.n; i++)
    for (int j = 0; j < R.n; j++) {
      double v = rho * R.z[i] * R.z[j] + (i == j && (moved[i] || R.d[i] > 0.0) ? R.d[i] : 0.0);
      for (int l = 0; l < nneg; l++) v -= lam[l] * U[l][i] * U[l][j];
      S[i][j] = v;
    }
  for (int i = 0; i < R.n; i++) /* H = E^T S E, E's rows the e_i */
    for (int p = 0; p < 12; p++) {
      double v = 0.0;
      for (int j = 0; j < R.n; j++) v += S[i][j] * R.e[j][p];
      T[i][p] = v;
    }
  for (int p = 0; p < 12; p++)
    for (int q = p; q < 12; q++) {
      double v = 0.0;
      for (int i = 0; i < R.n; i++) v += R.e[i][p] * T[i][q];
      if (!isfinite(v)) return 0;
      H[p * 12 + q] = H[q * 12 + p] = v;
    }
  return 1;
}

int sw_pair_barrier_block(const sw_pair_form *pf, double db, double d2b, double w, double *H) {
  double Q[5][12], M[25], gq[5], vq[2][5];
  if (sw_pair_clamp_closed(pf, db, d2b, w, H)) return 0;
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

int sw_pair_clamp_free(double *H) {
  /* M = Q^T H Q on the 9 differences of the 4 vertices' motions, its clamp, H = Q M Q^T */
  double M[81];
  sw_contrast_reduce(H, 4, M);
  if (sw_psd_project(M, 9, SW_FILTER_CLAMP)) return -1;
  sw_contrast_lift(M, 4, H);
  return 0;
}
