/* term.c — what every energy term shares: stencil storage, and the frame of the membranes
 * (bw98, stvk, corotated): per-face corner coefficients, the evaluation loop, the congruence
 * from P = d2psi/d(wu,wv)^2 to the face block and the PSD projection of P. */
#include <math.h>
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
  long block = (long)(per * dim) * (per * dim);
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
  t->sptr = t->sidx = NULL;
  t->hptr = NULL;
  t->param = NULL;
}

void sw_face_coeffs(const sw_model *m, int f, double cu[3], double cv[3]) {
  /* wu = (x1-x0) Dinv00 + (x2-x0) Dinv10, wv = (x1-x0) Dinv01 + (x2-x0) Dinv11 (seed 000). */
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
 * x_i (DESIGN.md "Energy terms", seeds 000/001).  By the chain rule dE/dx_i = a (cu_i gu + cv_i
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

/* Hessian block of one face from P (2d x 2d): (3d x 3d), row-major, vertex-major. */
static void membrane_block(const double *cu, const double *cv, double area, const double *P,
                           int d, double *blk) {
  const int ld = 2 * d, n = 3 * d;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double uu = area * cu[i] * cu[j], uv = area * cu[i] * cv[j];
      double vu = area * cv[i] * cu[j], vv = area * cv[i] * cv[j];
      for (int a = 0; a < d; a++)
        for (int b = 0; b < d; b++)
          blk[(i * d + a) * n + j * d + b] +=
              uu * P[a * ld + b] + uv * P[a * ld + d + b] + vu * P[(d + a) * ld + b] +
              vv * P[(d + a) * ld + d + b];
    }
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
    total += area * mb->density(law, wu, wv, d, ev->project, gu, gv, ev->hess ? P : NULL);
    if (ev->grad)
      for (int i = 0; i < 3; i++)
        for (int a = 0; a < d; a++)
          ev->grad[c[i] * d + a] += area * (cu[i] * gu[a] + cv[i] * gv[a]);
    if (ev->hess) membrane_block(cu, cv, area, P, d, ev->hess + t->hptr[s]);
  }
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

int sw_psd_project(double *A, int n) {
  /* The nearest PSD matrix in the Frobenius norm keeps the eigenvectors and clamps the
   * eigenvalues at 0 (Higham 1988).  LAPACK is column-major; A is symmetric, so row i of the
   * returned array is eigenvector i.  Fixed-size workspace: no allocation (n <= 6). */
  double V[36], w[6], work[256];
  int lwork = 256, info = 0;
  if (n < 1 || n > 6) return -1;
  memcpy(V, A, sizeof(double) * (size_t)(n * n));
  dsyev_("V", "U", &n, V, &n, w, work, &lwork, &info);
  if (info != 0) return -1;
  if (w[0] >= 0.0) return 0; /* already PSD: A unchanged */
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      double s = 0.0;
      for (int k = 0; k < n; k++)
        if (w[k] > 0.0) s += w[k] * V[k * n + i] * V[k * n + j];
      A[i * n + j] = s;
    }
  return 0;
}
