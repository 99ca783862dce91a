/* term.c — what every energy term shares: stencil storage, and the frame of the membranes
 * (bw98, stvk, corotated): per-face corner coefficients, the evaluation loop, the congruence
 * from P = d2psi/d(wu,wv)^2 to the face block and the PSD projection of P. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

int sw_term_alloc_stencils(sw_term *t, int nstencil, int per, int dim) {
  t->nstencil = nstencil;
  t->sptr = sw_calloc((size_t)nstencil + 1, sizeof(int));
  t->sidx = sw_calloc((size_t)nstencil * (size_t)per, sizeof(int));
  t->hptr = sw_calloc((size_t)nstencil + 1, sizeof(long));
  if (!t->sptr || !t->sidx || !t->hptr) return -1;
  long block = sw_hess_size(per * dim);
  for (int s = 0; s <= nstencil; s++) {
    t->sptr[s] = s * per;
    t->hptr[s] = (long)s * block;
  }
  return 0;
}

void sw_term_free(sw_term *t) {
  if (t->ops && t->ops->free_param) t->ops->free_param(t->param);
  sw_free(t->sptr);
  sw_free(t->sidx);
  sw_free(t->hptr);
  sw_free(t->lptr);
  sw_free(t->lidx);
  t->sptr = t->sidx = t->lptr = t->lidx = NULL;
  t->nlowrank = 0;
  t->hptr = NULL;
  t->param = NULL;
}

void sw_face_coeffs(const sw_model *m, int f, double cu[3], double cv[3]) {
  /* wu = (x1-x0) Dinv00 + (x2-x0) Dinv10, wv = (x1-x0) Dinv01 + (x2-x0) Dinv11 (Optitex). */
  const double *di = m->dminv + 4 * f;
  cu[0] = -(di[0] + di[2]);
  cu[1] = di[0];
  cu[2] = di[2];
  cv[0] = -(di[1] + di[3]);
  cv[1] = di[1];
  cv[2] = di[3];
}

void sw_face_F(const sw_model *m, int f, const double *x, double *wu, double *wv) {
  double cu[3], cv[3];
  sw_face_coeffs(m, f, cu, cv);
  const int d = m->dim, *c = m->face + 3 * f;
  for (int a = 0; a < d; a++) {
    wu[a] = wv[a] = 0.0;
    for (int i = 0; i < 3; i++) {
      wu[a] += cu[i] * x[c[i] * d + a];
      wv[a] += cv[i] * x[c[i] * d + a];
    }
  }
}

/* ------------------------------------------------------------- membranes */

/* Every membrane energy is a^f psi(wu, wv) per face with wu = sum_i cu_i x_i, wv = sum_i cv_i
 * x_i (docs/models.md, Optitex; Yan 2019).  By the chain rule dE/dx_i = a (cu_i gu + cv_i
 * gv) with gu, gv = dpsi/dwu, dpsi/dwv, and the Hessian block (i, j) is the congruence
 *   a (cu_i cu_j Puu + cu_i cv_j Puv + cv_i cu_j Pvu + cv_i cv_j Pvv),  P = d2psi/d(wu,wv)^2,
 * so a positive semi-definite P gives a PSD block: every membrane projects P, not the block. */

sw_membrane *sw_membrane_new(sw_term *t, const sw_model *m, const sw_term_ops *ops, int model,
                             size_t lawsz, sw_membrane_density density, char *err, size_t errsz) {
  sw_membrane *mb = sw_calloc(1, sizeof *mb);
  t->ops = ops;
  t->param = mb;
  snprintf(t->name, sizeof t->name, "%s", ops->kind);
  if (!mb) return sw_errf(err, errsz, "out of memory"), NULL;
  int n = 0;
  for (int f = 0; f < m->nf; f++) n += m->mat[m->face_mat[f]].membrane == model;
  mb->density = density;
  mb->lawsz = lawsz;
  mb->face = sw_calloc((size_t)n, sizeof(int));
  mb->cu = sw_calloc((size_t)n, 3 * sizeof(double));
  mb->cv = sw_calloc((size_t)n, 3 * sizeof(double));
  mb->law = sw_calloc((size_t)m->nmat, lawsz);
  if (!mb->face || !mb->cu || !mb->cv || !mb->law || sw_term_alloc_stencils(t, n, 3, m->dim))
    return sw_errf(err, errsz, "out of memory"), NULL;
  for (int f = 0, s = 0; f < m->nf; f++) {
    if (m->mat[m->face_mat[f]].membrane != model) continue;
    mb->face[s] = f;
    sw_face_coeffs(m, f, mb->cu + 3 * s, mb->cv + 3 * s);
    for (int i = 0; i < 3; i++) t->sidx[3 * s + i] = m->face[3 * f + i];
    s++;
  }
  return mb;
}

void sw_membrane_free(void *param) {
  sw_membrane *mb = param;
  if (!mb) return;
  sw_free(mb->face);
  sw_free(mb->cu);
  sw_free(mb->cv);
  sw_free(mb->law);
  sw_free(mb);
}

/* Hessian block of one face from P (2d x 2d): (3d x 3d), vertex-major, its upper triangle, set
 * (every entry written: the membranes' ops have sets_blocks). */
static void membrane_block(const double *cu, const double *cv, double area, const double *P,
                           int d, double *blk) {
  const int ld = 2 * d, n = 3 * d;
  for (int i = 0; i < 3; i++)
    for (int j = i; j < 3; j++) {
      double uu = area * cu[i] * cu[j], uv = area * cu[i] * cv[j];
      double vu = area * cv[i] * cu[j], vv = area * cv[i] * cv[j];
      for (int a = 0; a < d; a++)
        for (int b = j == i ? a : 0; b < d; b++)
          blk[sw_hess_upper(i * d + a, j * d + b, n)] =
              uu * P[a * ld + b] + uv * P[a * ld + d + b] + vu * P[(d + a) * ld + b] +
              vv * P[(d + a) * ld + d + b];
    }
}

/* The index of the pair (a, b), a <= b, in sl, or -1 when it holds none: (a, a) first, then
 * the b > a in increasing order (a scan for the short lists of a mesh, a bisection past). */
static long slots_pair(const sw_slots *sl, int a, int b) {
  long lo = sl->pptr[a], hi = sl->pptr[a + 1] - 1;
  if (a == b) return lo <= hi && sl->pvert[lo] == a ? lo : -1;
  if (hi - lo < 16) {
    for (long e = lo + 1; e <= hi; e++)
      if (sl->pvert[e] == b) return e;
    return -1;
  }
  while (lo <= hi) {
    long mid = lo + (hi - lo) / 2;
    if (sl->pvert[mid] == b) return mid;
    if (sl->pvert[mid] < b) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* The slots of the pair of stencil vertices a and b (stored as (min, max)), or NULL. */
static const int *pair_slots(const sw_slots *sl, int a, int b) {
  const long e = a > b ? slots_pair(sl, b, a) : slots_pair(sl, a, b);
  return e < 0 ? NULL : sl->pslot + (size_t)(sl->dim * sl->dim) * (size_t)e;
}

/* Stencils of at most this many vertices have their pairs' slots looked up once (a mesh's
 * elements); longer ones (a dense tendon's) once per row. */
#define SLOTS_CACHE 8

/* sw_slots_add for a short stencil in 3D (a mesh's elements), its loops of constant length:
 * row (i, al) of the block is the rest of vertex i's pair, then each pair (i, j > i) in full,
 * the pairs' slots looked up once. */
static void add_short3(const sw_slots *sl, const int *v, int nv, const double *h,
                       double *values) {
  const int *pc[SLOTS_CACHE * SLOTS_CACHE];
  for (int i = 0; i < nv; i++)
    for (int j = i; j < nv; j++) pc[i * nv + j] = pair_slots(sl, v[i], v[j]);
  for (int i = 0; i < nv; i++)
    for (int al = 0; al < 3; al++) {
      const int *pd = pc[i * nv + i];
      for (int be = al; be < 3; be++, h++) { /* its own vertex: (a, a) holds both halves */
        const int s = pd ? pd[3 * al + be] : -1;
        if (s >= 0) values[s] += *h;
      }
      for (int j = i + 1; j < nv; j++, h += 3) {
        const int *ps = pc[i * nv + j];
        if (!ps) continue;
        if (v[i] < v[j]) { /* row al of the pair's slots */
          for (int be = 0; be < 3; be++)
            if (ps[3 * al + be] >= 0) values[ps[3 * al + be]] += h[be];
        } else if (v[i] > v[j]) { /* its column al */
          for (int be = 0; be < 3; be++)
            if (ps[3 * be + al] >= 0) values[ps[3 * be + al]] += h[be];
        } else { /* one vertex twice: the mirror lands on the diagonal too */
          for (int be = 0; be < 3; be++)
            if (ps[3 * al + be] >= 0) values[ps[3 * al + be]] += be == al ? 2.0 * h[be] : h[be];
        }
      }
    }
}

void sw_slots_add(const sw_slots *sl, const int *v, int nv, const double *blk, double *values) {
  if (sl->dim == 3 && nv <= SLOTS_CACHE) {
    add_short3(sl, v, nv, blk, values);
    return;
  }
  const int d = sl->dim, cache = nv <= SLOTS_CACHE;
  const int *pc[SLOTS_CACHE * SLOTS_CACHE];
  for (int i = 0; cache && i < nv; i++)
    for (int j = i; j < nv; j++) pc[i * nv + j] = pair_slots(sl, v[i], v[j]);
  const double *h = blk; /* the entries in their stored order: rows (i, al), columns >= */
  for (int i = 0; i < nv; i++)
    for (int al = 0; al < d; al++)
      for (int j = i; j < nv; j++) {
        const int a = v[i], b = v[j], swap = a > b, dup = a == b && i != j;
        const int *ps = cache ? pc[i * nv + j] : pair_slots(sl, a, b);
        const int be0 = j == i ? al : 0;
        if (!ps) {
          h += d - be0;
          continue;
        }
        for (int be = be0; be < d; be++, h++) {
          const int s = swap ? ps[be * d + al] : ps[al * d + be];
          if (s >= 0) values[s] += dup && al == be ? 2.0 * *h : *h; /* its mirror lands too */
        }
      }
}

void sw_eval_why(const sw_eval *ev, const char *fmt, ...) {
  if (!ev->why || !ev->whysz || ev->why[0]) return; /* none asked, or the first one kept */
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(ev->why, ev->whysz, fmt, ap);
  va_end(ap);
}

int sw_membrane_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const sw_membrane *mb = t->param;
  const int d = m->dim;
  double total = 0.0; /* J */
  for (int s = 0; s < t->nstencil; s++) {
    const int f = mb->face[s], *c = m->face + 3 * f;
    const double *cu = mb->cu + 3 * s, *cv = mb->cv + 3 * s;
    const void *law = (const char *)mb->law + mb->lawsz * (size_t)m->face_mat[f];
    double wu[3] = {0}, wv[3] = {0}, gu[3], gv[3], P[36];
    for (int i = 0; i < 3; i++)
      for (int a = 0; a < d; a++) {
        wu[a] += cu[i] * ev->x[c[i] * d + a];
        wv[a] += cv[i] * ev->x[c[i] * d + a];
      }
    double area = m->area[f]; /* m^2 */
    double e = area * mb->density(law, wu, wv, d, ev->project, gu, gv, ev->hess ? P : NULL);
    if (!isfinite(e))
      sw_eval_why(ev, "face %d (vertices %d %d %d): energy %g J (rest area %g m^2, stretch "
                  "|w_u| = %g, |w_v| = %g)", f, c[0], c[1], c[2], e, area,
                  sqrt(wu[0] * wu[0] + wu[1] * wu[1] + wu[2] * wu[2]),
                  sqrt(wv[0] * wv[0] + wv[1] * wv[1] + wv[2] * wv[2]));
    total += e;
    if (ev->grad)
      for (int i = 0; i < 3; i++)
        for (int a = 0; a < d; a++)
          ev->grad[c[i] * d + a] += area * (cu[i] * gu[a] + cv[i] * gv[a]);
    if (!ev->hess) continue;
    double *blk = sw_ev_block(ev, t, s);
    membrane_block(cu, cv, area, P, d, blk);
    sw_ev_block_done(ev, t, s, blk);
  }
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

/* The rows of the symmetric n x n matrix A that are not all zero, into keep; their count.  A
 * zero row (and column) is an eigenvector of eigenvalue 0, which no filter changes. */
static int nonzero_rows(const double *A, int n, int *keep) {
  int nk = 0;
  for (int i = 0; i < n; i++) {
    int zero = 1;
    for (int j = 0; j < n && zero; j++) zero = A[i * n + j] == 0.0;
    if (!zero) keep[nk++] = i;
  }
  return nk;
}

/* sw_psd_project on the rows and columns keep[0..nk) of A only, the others being zero: a
 * contact pair whose closest features are a vertex and an edge has 9 of its 12 rows nonzero,
 * two vertices 6, and an eigen-decomposition of 9 x 9 costs about half of one of 12 x 12. */
static int project_rows(double *A, int n, const int *keep, int nk, int mode) {
  double S[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
  for (int a = 0; a < nk; a++)
    for (int b = 0; b < nk; b++) S[a * nk + b] = A[keep[a] * n + keep[b]];
  if (sw_psd_project(S, nk, mode)) return -1;
  for (int a = 0; a < nk; a++)
    for (int b = 0; b < nk; b++) A[keep[a] * n + keep[b]] = S[a * nk + b];
  return 0;
}

int sw_psd_project(double *A, int n, int mode) {
  /* Both filters keep the eigenvectors.  Clamping the eigenvalues at 0 gives the nearest PSD
   * matrix in the Frobenius norm (Higham 1988, "Computing a nearest symmetric positive
   * semidefinite matrix"); their absolute values give V |Lambda| V^T, which keeps the curvature
   * of the negative directions (Chen, Liu, Levin, Zheng, Jacobson, "Stabler Neo-Hookean
   * Simulation: Absolute Eigenvalue Filtering for Projected Newton", SIGGRAPH 2024).  A
   * Cholesky factorisation first (sw_sym_is_pd, n^3/6 multiplications against some 10 n^3 for
   * the eigensystem) proves a block that is positive definite already so.
   * Fixed-size workspace: no allocation. */
  double V[SW_EIGEN_NMAX * SW_EIGEN_NMAX], w[SW_EIGEN_NMAX], wmin = 0.0;
  if (n < 1 || n > SW_EIGEN_NMAX) return -1;
  if (mode == SW_FILTER_NONE) return 0;
  for (int i = 0; i < n * n; i++)
    if (!isfinite(A[i])) return -1;
  if (sw_sym_is_pd(A, n)) return 0;
  int keep[SW_EIGEN_NMAX], nk = nonzero_rows(A, n, keep);
  if (nk == 0) return 0;
  if (nk < n) return project_rows(A, n, keep, nk, mode);
  memcpy(V, A, sizeof(double) * (size_t)(n * n));
  if (sw_sym_eigen(V, n, w)) return -1; /* column k of V: the eigenvector of w[k] */
  for (int k = 0; k < n; k++) wmin = fmin(wmin, w[k]);
  if (wmin >= 0.0) return 0; /* already PSD: A unchanged */
  /* A = U U^T, U's columns the eigenvectors of positive filtered eigenvalue l scaled by
   * sqrt(l), its rows contiguous */
  double U[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
  int np = 0;
  for (int k = 0; k < n; k++) {
    double l = sw_filter_eigenvalue(w[k], mode);
    if (!(l > 0.0)) continue;
    double r = sqrt(l);
    for (int i = 0; i < n; i++) U[i * n + np] = r * V[i * n + k];
    np++;
  }
  for (int i = 0; i < n; i++)
    for (int j = i; j < n; j++) {
      double s = 0.0;
      for (int p = 0; p < np; p++) s += U[i * n + p] * U[j * n + p];
      A[i * n + j] = A[j * n + i] = s;
    }
  return 0;
}

/* An orthonormal frame E = [e1 e2 n] (3 x 3, E[a*3 + k] = component a of column k) whose first
 * two columns span wu and wv (any such frame when they are parallel or zero). */
static void plane_frame(const double *wu, const double *wv, double *E) {
  double e1[3], e2[3], lu = sqrt(wu[0] * wu[0] + wu[1] * wu[1] + wu[2] * wu[2]);
  const double *w = lu > 0.0 ? wu : wv;
  double lw = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  for (int a = 0; a < 3; a++) e1[a] = lw > 0.0 ? w[a] / lw : (a == 0);
  /* e2: wv without its e1 part, else the axis least aligned with e1, orthogonalised */
  double p = wv[0] * e1[0] + wv[1] * e1[1] + wv[2] * e1[2], l2 = 0.0;
  for (int a = 0; a < 3; a++) {
    e2[a] = wv[a] - p * e1[a];
    l2 += e2[a] * e2[a];
  }
  if (!(l2 > 1e-24 * (wv[0] * wv[0] + wv[1] * wv[1] + wv[2] * wv[2]))) {
    int ax = fabs(e1[0]) <= fabs(e1[1]) ? (fabs(e1[0]) <= fabs(e1[2]) ? 0 : 2)
                                        : (fabs(e1[1]) <= fabs(e1[2]) ? 1 : 2);
    l2 = 0.0;
    for (int a = 0; a < 3; a++) {
      e2[a] = (a == ax) - e1[ax] * e1[a];
      l2 += e2[a] * e2[a];
    }
  }
  for (int a = 0; a < 3; a++) e2[a] /= sqrt(l2);
  for (int a = 0; a < 3; a++) {
    E[a * 3] = e1[a];
    E[a * 3 + 1] = e2[a];
  }
  E[2] = e1[1] * e2[2] - e1[2] * e2[1];
  E[5] = e1[2] * e2[0] - e1[0] * e2[2];
  E[8] = e1[0] * e2[1] - e1[1] * e2[0];
}

/* P <- blockdiag(E, E)^T P blockdiag(E, E) (fwd) or blockdiag(E, E) P blockdiag(E, E)^T: each
 * 3 x 3 block P_XY becomes G^T P_XY G (G = E, or E^T), as two 3 x 3 products. */
static void frame_congruence(double *P, const double *E, int fwd) {
  double G[9];
  for (int a = 0; a < 3; a++)
    for (int k = 0; k < 3; k++) G[a * 3 + k] = fwd ? E[a * 3 + k] : E[k * 3 + a];
  for (int X = 0; X < 2; X++)
    for (int Y = 0; Y < 2; Y++) {
      double T[9]; /* P_XY G */
      for (int a = 0; a < 3; a++)
        for (int l = 0; l < 3; l++) {
          const double *r = P + (3 * X + a) * 6 + 3 * Y;
          T[a * 3 + l] = r[0] * G[l] + r[1] * G[3 + l] + r[2] * G[6 + l];
        }
      for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++)
          P[(3 * X + k) * 6 + 3 * Y + l] =
              G[k] * T[l] + G[3 + k] * T[3 + l] + G[6 + k] * T[6 + l];
    }
}

int sw_membrane_project(double *P, const double *wu, const double *wv, int d, int mode) {
  /* A density of C = F^T F only is unchanged by the reflection through the plane of wu, wv,
   * so P commutes with it: in a frame [e1 e2 n] of that plane P is block diagonal, the 4 x 4
   * in-plane block (rows e1, e2 of wu and wv) and the 2 x 2 block on [a n; b n]; P's
   * eigenvectors are those of the blocks, and its filtered matrix (nearest PSD, or absolute
   * eigenvalues) is made of the blocks' filtered ones. */
  if (mode == SW_FILTER_NONE) return 0;
  if (d == 2) return sw_psd_project(P, 4, mode);
  double E[9], A[16], B[4];
  const int in[4] = {0, 1, 3, 4}, out[2] = {2, 5};
  plane_frame(wu, wv, E);
  frame_congruence(P, E, 1);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) A[i * 4 + j] = P[in[i] * 6 + in[j]];
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) B[i * 2 + j] = P[out[i] * 6 + out[j]];
  if (sw_psd_project(A, 4, mode) || sw_psd_project(B, 2, mode)) return -1;
  memset(P, 0, 36 * sizeof(double));
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) P[in[i] * 6 + in[j]] = A[i * 4 + j];
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) P[out[i] * 6 + out[j]] = B[i * 2 + j];
  frame_congruence(P, E, 0);
  return 0;
}
