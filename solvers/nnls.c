/* nnls.c — non-negative least squares min 1/2 |A x - b|^2, x >= 0, by the active-set method of
 * Lawson and Hanson ("Solving Least Squares Problems", 1974, ch. 23), the tendon inverse
 * problem's optimiser (the tendon model §3: U = 1/2 (A tau - f)^T (A tau - f), tau >= 0).
 *
 * x starts at 0 with every component active (held at 0).  Each outer iteration frees the active
 * component with the largest gradient w_j = [A^T (b - A x)]_j > tol and solves the unconstrained
 * least squares on the free ("passive") columns; while that solution z has a free component
 * <= 0, x moves towards z as far as feasibility allows and the components that reach 0 become
 * active again.  The subproblems are solved by LAPACK dgelsd (SVD with rcond = eps max(m, p)),
 * so nearly dependent columns give the minimum-norm answer instead of a blow-up; a column
 * whose entry would come out <= 0 (possible only through rounding) is refused until x changes. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "inverse.h"
#include "util.h"

extern void dgelsd_(const int *m, const int *n, const int *nrhs, double *a, const int *lda,
                    double *b, const int *ldb, double *s, const double *rcond, int *rank,
                    double *work, const int *lwork, int *iwork, int *info);

typedef struct nnls_ws {
  int m, n;
  const double *A, *b;
  double *w, *z, *r;     /* (n) gradient, (n) subproblem solution, (m) residual b - A x */
  double *As, *bs, *s;   /* (m x n) passive columns, (max(m, n)) right side, (n) singular values */
  double *work;
  int *iwork, *passive, *refused;
  int lwork, liwork;
} nnls_ws;

static void ws_free(nnls_ws *ws) {
  sw_free(ws->w), sw_free(ws->z), sw_free(ws->r), sw_free(ws->As), sw_free(ws->bs);
  sw_free(ws->s), sw_free(ws->work), sw_free(ws->iwork), sw_free(ws->passive);
  sw_free(ws->refused);
}

static int ws_alloc(nnls_ws *ws) {
  size_t m = (size_t)ws->m, n = (size_t)ws->n, ld = m > n ? m : n;
  ws->w = sw_calloc(n, sizeof(double));
  ws->z = sw_calloc(n, sizeof(double));
  ws->r = sw_calloc(m, sizeof(double));
  ws->As = sw_calloc(m * n, sizeof(double));
  ws->bs = sw_calloc(ld, sizeof(double));
  ws->s = sw_calloc(n, sizeof(double));
  ws->passive = sw_calloc(n, sizeof(int));
  ws->refused = sw_calloc(n, sizeof(int));
  return ws->w && ws->z && ws->r && ws->As && ws->bs && ws->s && ws->passive && ws->refused
             ? 0 : -1;
}

/* Make work and iwork at least what dgelsd asks for a p-column subproblem. */
static int ws_lapack(nnls_ws *ws, int p, int ldb) {
  int one = 1, lw = -1, rank, info = 0, iq = 0;
  double q = 0.0, rcond = -1.0;
  dgelsd_(&ws->m, &p, &one, ws->As, &ws->m, ws->bs, &ldb, ws->s, &rcond, &rank, &q, &lw, &iq,
          &info);
  if (info) return -1;
  int need = (int)q + 1, mn = ws->m < p ? ws->m : p;
  int needi = SW_MAX(iq, 3 * mn * 32 + 11 * mn) + 1; /* LAPACK's bound with NLVL <= 32 */
  if (need > ws->lwork) {
    double *w = sw_realloc(ws->work, (size_t)need, sizeof(double));
    if (!w) return -1;
    ws->work = w, ws->lwork = need;
  }
  if (needi > ws->liwork) {
    int *iw = sw_realloc(ws->iwork, (size_t)needi, sizeof(int));
    if (!iw) return -1;
    ws->iwork = iw, ws->liwork = needi;
  }
  return 0;
}

/* z = argmin |A_P z - b| on the passive columns P, z = 0 elsewhere. */
static int passive_ls(nnls_ws *ws, char *err, size_t errsz) {
  const int m = ws->m, n = ws->n, one = 1, ldb = m > n ? m : n;
  int p = 0, rank, info = 0;
  for (int j = 0; j < n; j++)
    if (ws->passive[j]) memcpy(ws->As + (size_t)p++ * m, ws->A + (size_t)j * m, m * sizeof(double));
  memset(ws->z, 0, (size_t)n * sizeof(double));
  if (p == 0) return SW_OK;
  memcpy(ws->bs, ws->b, (size_t)m * sizeof(double));
  double rcond = DBL_EPSILON * (m > p ? m : p);
  if (ws_lapack(ws, p, ldb)) return sw_errf(err, errsz, "nnls: out of memory"), SW_FATAL;
  dgelsd_(&m, &p, &one, ws->As, &m, ws->bs, &ldb, ws->s, &rcond, &rank, ws->work, &ws->lwork,
          ws->iwork, &info);
  if (info) return sw_errf(err, errsz, "nnls: dgelsd failed (info %d)", info), SW_FATAL;
  for (int j = 0, k = 0; j < n; j++)
    if (ws->passive[j]) ws->z[j] = ws->bs[k++];
  return SW_OK;
}

/* r = b - A x and w = A^T r. */
static void gradient(nnls_ws *ws, const double *x) {
  const int m = ws->m, n = ws->n;
  memcpy(ws->r, ws->b, (size_t)m * sizeof(double));
  for (int j = 0; j < n; j++)
    for (int i = 0; i < m; i++) ws->r[i] -= ws->A[(size_t)j * m + i] * x[j];
  for (int j = 0; j < n; j++) {
    double s = 0.0;
    for (int i = 0; i < m; i++) s += ws->A[(size_t)j * m + i] * ws->r[i];
    ws->w[j] = s;
  }
}

/* Move x towards z as far as x >= 0 allows; the passive components that reach 0 leave P. */
static void step_to_boundary(nnls_ws *ws, double *x) {
  double alpha = 1.0;
  int at = -1;
  for (int j = 0; j < ws->n; j++)
    if (ws->passive[j] && ws->z[j] <= 0.0) {
      double a = x[j] / (x[j] - ws->z[j]);
      if (at < 0 || a < alpha) alpha = a, at = j;
    }
  for (int j = 0; j < ws->n; j++)
    if (ws->passive[j]) {
      x[j] += alpha * (ws->z[j] - x[j]);
      if (j == at || x[j] <= 0.0) x[j] = 0.0, ws->passive[j] = 0;
    }
}

/* The inner loop of an outer iteration that freed component j. */
static int inner_loop(nnls_ws *ws, double *x, int j, char *err, size_t errsz) {
  for (int guard = 0; guard <= ws->n; guard++) { /* each pass shrinks P: at most n of them */
    int rc = passive_ls(ws, err, errsz);
    if (rc) return rc;
    if (j >= 0 && ws->z[j] <= 0.0) { /* rounding: the freed column does not help */
      ws->passive[j] = 0, ws->refused[j] = 1;
      return SW_OK;
    }
    j = -1;
    int feasible = 1;
    for (int k = 0; k < ws->n; k++) feasible &= !ws->passive[k] || ws->z[k] > 0.0;
    if (feasible) {
      memcpy(x, ws->z, (size_t)ws->n * sizeof(double));
      memset(ws->refused, 0, (size_t)ws->n * sizeof(int));
      return SW_OK;
    }
    step_to_boundary(ws, x);
  }
  return SW_OK;
}

/* 10 eps max(m, n) |A|_1 |b|_inf: the rounding level of w (N for A unitless, b in N). */
static double default_tol(const nnls_ws *ws) {
  double a1 = 0.0, binf = 0.0;
  for (int j = 0; j < ws->n; j++) {
    double c = 0.0;
    for (int i = 0; i < ws->m; i++) c += fabs(ws->A[(size_t)j * ws->m + i]);
    a1 = fmax(a1, c);
  }
  for (int i = 0; i < ws->m; i++) binf = fmax(binf, fabs(ws->b[i]));
  return 10.0 * DBL_EPSILON * (ws->m > ws->n ? ws->m : ws->n) * a1 * binf;
}

static int nnls_loop(nnls_ws *ws, double *x, double tol, int max_iter, int *iters, char *err,
                     size_t errsz) {
  for (int it = 0;; it++) {
    gradient(ws, x);
    int j = -1;
    double best = tol;
    for (int k = 0; k < ws->n; k++)
      if (!ws->passive[k] && !ws->refused[k] && ws->w[k] > best) best = ws->w[k], j = k;
    if (iters) *iters = it;
    if (j < 0) return SW_OK;
    if (it >= max_iter) {
      sw_errf(err, errsz, "nnls: no convergence in %d iterations (largest gradient %g > tol %g)",
              max_iter, best, tol);
      return SW_RECOVER;
    }
    ws->passive[j] = 1;
    int rc = inner_loop(ws, x, j, err, errsz);
    if (rc) return rc;
  }
}

int sw_nnls(int m, int n, const double *A, const double *b, double *x, double tol, int max_iter,
            int *iters, char *err, size_t errsz) {
  if (iters) *iters = 0;
  if (n <= 0 || m <= 0) {
    for (int j = 0; j < n; j++) x[j] = 0.0;
    return SW_OK;
  }
  nnls_ws ws = {.m = m, .n = n, .A = A, .b = b};
  if (ws_alloc(&ws)) return ws_free(&ws), sw_errf(err, errsz, "nnls: out of memory"), SW_FATAL;
  memset(x, 0, (size_t)n * sizeof(double));
  if (!(tol > 0.0)) tol = default_tol(&ws);
  if (max_iter <= 0) max_iter = 3 * n;
  int rc = nnls_loop(&ws, x, tol, max_iter, iters, err, errsz);
  ws_free(&ws);
  return rc;
}
