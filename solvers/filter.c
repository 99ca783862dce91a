/* filter.c — eigenvalue filtering of single Hessian blocks, for the Newton modes that decide per
 * element (stencil) whether its block is used exact or filtered (`hessian: progressive`, and the
 * fall-back of `auto`).  A block A = Q diag(lambda) Q^T becomes Q diag(f(lambda)) Q^T with
 * f = max(lambda, 0) (clamping: the nearest positive semi-definite block) or f = |lambda|
 * (absolute-value filtering, Chen et al., "Stabler Neo-Hookean Simulation: Absolute Eigenvalue
 * Filtering for Projected Newton", SIGGRAPH 2024).  The terms filter their own blocks in closed
 * form where they can (models/); this is the general path for any block size, by LAPACK's
 * dsyev on a workspace allocated once. */
#include <math.h>
#include <string.h>

#include "solver.h"
#include "util.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

int sw_filter_init(sw_filter *f, int nmax) {
  memset(f, 0, sizeof *f);
  if (nmax <= 0) return 0;
  int lwork = -1, info = 0;
  double query = 0.0, dummy = 0.0, w = 0.0;
  dsyev_("V", "U", &nmax, &dummy, &nmax, &w, &query, &lwork, &info);
  f->nmax = nmax;
  f->lwork = info == 0 && query >= 3.0 * nmax ? (int)query : 3 * nmax + 64;
  f->q = sw_calloc((size_t)nmax * (size_t)nmax, sizeof(double));
  f->lambda = sw_calloc((size_t)nmax, sizeof(double));
  f->work = sw_calloc((size_t)f->lwork, sizeof(double));
  return (!f->q || !f->lambda || !f->work) ? -1 : 0;
}

void sw_filter_free(sw_filter *f) {
  sw_free(f->q);
  sw_free(f->lambda);
  sw_free(f->work);
  memset(f, 0, sizeof *f);
}

int sw_filter_block(sw_filter *f, double *A, int n, int mode) {
  if (mode == SW_FILTER_NONE) return 0;
  if (n > f->nmax) return -1;
  for (int i = 0; i < n * n; i++)
    if (!isfinite(A[i])) return -1;
  memcpy(f->q, A, (size_t)n * (size_t)n * sizeof(double));
  int info = 0;
  dsyev_("V", "U", &n, f->q, &n, f->lambda, f->work, &f->lwork, &info);
  if (info) return -1;
  if (f->lambda[0] >= 0.0) return 0; /* ascending: already PSD, keep it exact */
  for (int k = 0; k < n; k++) {
    double l = f->lambda[k];
    f->lambda[k] = mode == SW_FILTER_ABS ? fabs(l) : fmax(l, 0.0);
  }
  /* A = Q diag(lambda) Q^T (Q column-major: column k at q + k n; A symmetric) */
  for (int i = 0; i < n; i++)
    for (int j = i; j < n; j++) {
      double s = 0.0;
      for (int k = 0; k < n; k++) s += f->q[k * n + i] * f->lambda[k] * f->q[k * n + j];
      A[i * n + j] = A[j * n + i] = s;
    }
  return 1;
}
