/* eigen.c — small dense symmetric matrices: their eigensystem, a positive-definiteness test,
 * and the reduction of a translation-invariant block to the coordinates a translation leaves
 * out.  Fixed-size workspaces, no allocation, no BLAS: these run once per element and
 * evaluation, where LAPACK's per-call overhead exceeds the arithmetic. */
#include <math.h>
#include <string.h>

#include "terms.h"

/* The eigensystem of the symmetric n x n A (n <= SW_EIGEN_NMAX, row-major): Householder's
 * reduction to a tridiagonal matrix, then the QL iteration with implicit Wilkinson shifts
 * (Wilkinson and Reinsch, "Handbook for Automatic Computation II: Linear Algebra", 1971,
 * procedures tred2 and tql2, as in Press et al., "Numerical Recipes", sec. 11.2-11.3).  A
 * becomes the eigenvectors (column k: that of w[k]).  -1 when the iteration does not converge
 * (not finite).  The same algorithm as LAPACK's dsyev (dsytrd, dorgtr, dsteqr), written for
 * small sizes, where dsyev's calls of its level-2 kernels cost more than their arithmetic:
 * sw_pair_clamp_free takes 2.9 us with it against 6.1 us with dsyev (bench/bench_blocks, one
 * thread); a random 18 x 18 matrix 13.6 us against 23.8, 15 x 15 8.6 against 16.4, 9 x 9 2.6
 * against 6.6 (one thread). */
int sw_sym_eigen(double *A, int n, double *w) {
  double e[SW_EIGEN_NMAX];
  if (n < 1 || n > SW_EIGEN_NMAX) return -1;
#define A_(i, j) A[(i) * n + (j)]
  for (int i = n - 1; i > 0; i--) { /* tred2: A's row i reflected onto its subdiagonal */
    int l = i - 1;
    double h = 0.0, scale = 0.0;
    if (l > 0) {
      for (int k = 0; k <= l; k++) scale += fabs(A_(i, k));
      if (scale == 0.0) {
        e[i] = A_(i, l);
      } else {
        for (int k = 0; k <= l; k++) {
          A_(i, k) /= scale;
          h += A_(i, k) * A_(i, k);
        }
        double f = A_(i, l), g = f >= 0.0 ? -sqrt(h) : sqrt(h);
        e[i] = scale * g;
        h -= f * g;
        A_(i, l) = f - g;
        f = 0.0;
        for (int j = 0; j <= l; j++) {
          A_(j, i) = A_(i, j) / h;
          g = 0.0;
          for (int k = 0; k <= j; k++) g += A_(j, k) * A_(i, k);
          for (int k = j + 1; k <= l; k++) g += A_(k, j) * A_(i, k);
          e[j] = g / h;
          f += e[j] * A_(i, j);
        }
        double hh = f / (h + h);
        for (int j = 0; j <= l; j++) {
          f = A_(i, j);
          e[j] = g = e[j] - hh * f;
          for (int k = 0; k <= j; k++) A_(j, k) -= f * e[k] + g * A_(i, k);
        }
      }
    } else {
      e[i] = A_(i, l);
    }
    w[i] = h;
  }
  w[0] = 0.0, e[0] = 0.0;
  for (int i = 0; i < n; i++) { /* the reflections' product into A */
    if (w[i] != 0.0)
      for (int j = 0; j < i; j++) {
        double g = 0.0;
        for (int k = 0; k < i; k++) g += A_(i, k) * A_(k, j);
        for (int k = 0; k < i; k++) A_(k, j) -= g * A_(k, i);
      }
    w[i] = A_(i, i);
    A_(i, i) = 1.0;
    for (int j = 0; j < i; j++) A_(j, i) = A_(i, j) = 0.0;
  }
  for (int i = 1; i < n; i++) e[i - 1] = e[i]; /* tql2 on diagonal w, subdiagonal e */
  e[n - 1] = 0.0;
  for (int l = 0; l < n; l++) {
    int m, iter = 0;
    do {
      for (m = l; m < n - 1; m++) {
        double dd = fabs(w[m]) + fabs(w[m + 1]);
        if (fabs(e[m]) <= 2.2e-16 * dd) break;
      }
      if (m == l) break;
      if (iter++ == 60) return -1;
      double g = (w[l + 1] - w[l]) / (2.0 * e[l]), r = sqrt(g * g + 1.0);
      g = w[m] - w[l] + e[l] / (g + (g >= 0.0 ? r : -r));
      double s = 1.0, c = 1.0, p = 0.0;
      int i;
      for (i = m - 1; i >= l; i--) {
        double f = s * e[i], b = c * e[i];
        e[i + 1] = r = sqrt(f * f + g * g);
        if (r == 0.0) {
          w[i + 1] -= p;
          e[m] = 0.0;
          break;
        }
        s = f / r, c = g / r;
        g = w[i + 1] - p;
        r = (w[i] - g) * s + 2.0 * c * b;
        w[i + 1] = g + (p = s * r);
        g = c * r - b;
        for (int k = 0; k < n; k++) {
          f = A_(k, i + 1);
          A_(k, i + 1) = s * A_(k, i) + c * f;
          A_(k, i) = c * A_(k, i) - s * f;
        }
      }
      if (r == 0.0 && i >= l) continue;
      w[l] -= p, e[l] = g, e[m] = 0.0;
    } while (m != l);
  }
#undef A_
  for (int k = 0; k < n; k++)
    if (!isfinite(w[k])) return -1;
  return 0;
}

/* 1 when the symmetric n x n A (row-major, n <= SW_EIGEN_NMAX) is positive definite to
 * floating point: its Cholesky factorisation completes with every pivot positive and finite
 * (Golub and Van Loan, "Matrix Computations", 4th ed., alg. 4.2.1); A is left unchanged. */
int sw_sym_is_pd(const double *A, int n) {
  double L[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
  if (n < 1 || n > SW_EIGEN_NMAX) return 0;
  for (int j = 0; j < n; j++) {
    double d = A[j * n + j];
    for (int k = 0; k < j; k++) d -= L[j * n + k] * L[j * n + k];
    if (!(d > 0.0) || !isfinite(d)) return 0;
    double ljj = sqrt(d);
    L[j * n + j] = ljj;
    for (int i = j + 1; i < n; i++) {
      double s = A[i * n + j];
      for (int k = 0; k < j; k++) s -= L[i * n + k] * L[j * n + k];
      L[i * n + j] = s / ljj;
    }
  }
  return 1;
}

/* Helmert's contrasts: an orthonormal basis h_k (k = 0 .. nv-2) of the vectors of R^nv whose
 * entries sum to 0, h_k = (1, .., 1, -(k+1), 0, ..) / sqrt((k+1)(k+2)) with k+1 ones.  Q =
 * [h_0 .. h_{nv-2}] (x) I_3 spans the differences of nv vertices' motions, which is all an
 * energy that a translation leaves unchanged sees: its Hessian H = Q (Q^T H Q) Q^T. */

/* Y = Q^T X: X has 3 nv rows of ncol entries (row-major), Y 3 (nv - 1).  A running sum of X's
 * vertex rows gives each contrast in O(1): (Q^T X)_k = (S_k - (k+1) X_{k+1}) / sqrt((k+1)(k+2)),
 * S_k = X_0 + .. + X_k. */
static void contrast_rows(const double *X, int nv, int ncol, double *Y) {
  double S[3 * SW_EIGEN_NMAX];
  const int w = 3 * ncol;
  memcpy(S, X, (size_t)w * sizeof(double));
  for (int k = 0; k + 1 < nv; k++) {
    const double *Xn = X + (size_t)(k + 1) * w;
    double c = 1.0 / sqrt((double)(k + 1) * (k + 2));
    for (int q = 0; q < w; q++) {
      Y[(size_t)k * w + q] = c * (S[q] - (k + 1) * Xn[q]);
      S[q] += Xn[q];
    }
  }
}

/* X = Q Y (the adjoint): X_i = sum_{k >= i} c_k Y_k - i c_{i-1} Y_{i-1}, a running sum from
 * the last contrast down. */
static void uncontrast_rows(const double *Y, int nv, int ncol, double *X) {
  double S[3 * SW_EIGEN_NMAX] = {0};
  const int w = 3 * ncol;
  for (int i = nv - 1; i >= 0; i--) {
    double *Xi = X + (size_t)i * w;
    if (i < nv - 1) { /* S = sum_{k >= i} c_k Y_k */
      double c = 1.0 / sqrt((double)(i + 1) * (i + 2));
      for (int q = 0; q < w; q++) S[q] += c * Y[(size_t)i * w + q];
    }
    double ci = i > 0 ? (double)i / sqrt((double)i * (i + 1)) : 0.0;
    for (int q = 0; q < w; q++) Xi[q] = S[q] - (i > 0 ? ci * Y[(size_t)(i - 1) * w + q] : 0.0);
  }
}

/* The n x m row-major A transposed into T (m x n). */
static void transpose(const double *A, int n, int m, double *T) {
  for (int i = 0; i < n; i++)
    for (int j = 0; j < m; j++) T[j * n + i] = A[i * m + j];
}

void sw_contrast_reduce(const double *H, int nv, double *M) {
  double T[SW_EIGEN_NMAX * SW_EIGEN_NMAX], U[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
  const int w = 3 * nv, r = w - 3;
  if (nv < 2 || w > SW_EIGEN_NMAX) return;
  contrast_rows(H, nv, w, T); /* Q^T H: r x w */
  transpose(T, r, w, U);      /* H Q: w x r */
  contrast_rows(U, nv, r, M); /* Q^T H Q: r x r */
  for (int i = 0; i < r; i++) /* symmetric to round-off: make it exactly so */
    for (int j = i + 1; j < r; j++)
      M[i * r + j] = M[j * r + i] = 0.5 * (M[i * r + j] + M[j * r + i]);
}

void sw_contrast_lift(const double *M, int nv, double *H) {
  double T[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
  double U[SW_EIGEN_NMAX * SW_EIGEN_NMAX] = {0}; /* {0}: else gcc -Wmaybe-uninitialized */
  const int w = 3 * nv, r = w - 3;
  if (nv < 2 || w > SW_EIGEN_NMAX) return;
  uncontrast_rows(M, nv, r, T); /* Q M: w x r */
  transpose(T, w, r, U);        /* M Q^T: r x w */
  uncontrast_rows(U, nv, w, H); /* Q M Q^T: w x w */
  for (int i = 0; i < w; i++)
    for (int j = i + 1; j < w; j++)
      H[i * w + j] = H[j * w + i] = 0.5 * (H[i * w + j] + H[j * w + i]);
}
