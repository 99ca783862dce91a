/* cholmod.c — the one sparse Cholesky of every implicit method (CHOLMOD, cholmod_l_* API since
 * SUNDIALS' sunindextype is 64-bit here).  Analysed once per run (fill-reducing ordering and
 * symbolic factor), refactorised numerically per Newton iteration, solved with persistent
 * workspaces so a solve allocates nothing. */
#include <string.h>

#include "solver.h"
#include "util.h"

int sw_chol_init(sw_chol *ch, const sw_pattern *p, char *err, size_t errsz) {
  memset(ch, 0, sizeof *ch);
  cholmod_l_start(&ch->c);
  ch->started = 1;
  ch->c.print = 0;
  ch->c.error_handler = NULL;
  ch->c.final_ll = 1; /* simplicial factors as LL^T too, so an indefinite S is detected */
  size_t n = (size_t)p->n;
  ch->A = cholmod_l_allocate_sparse(n, n, (size_t)p->nnz, 1, 1, 1, CHOLMOD_REAL, &ch->c);
  ch->b = cholmod_l_zeros(n, 1, CHOLMOD_REAL, &ch->c);
  if (!ch->A || !ch->b) {
    sw_errf(err, errsz, "CHOLMOD: out of memory allocating a %zu x %zu system", n, n);
    return SW_FATAL;
  }
  memcpy(ch->A->p, p->colptr, (n + 1) * sizeof(long));
  memcpy(ch->A->i, p->rowind, (size_t)p->nnz * sizeof(long));
  /* The symbolic analysis needs only the pattern: put something positive definite in. */
  double *v = ch->A->x;
  memset(v, 0, (size_t)p->nnz * sizeof(double));
  for (size_t c = 0; c < n; c++) v[p->diag[c]] = 1.0;
  ch->L = cholmod_l_analyze(ch->A, &ch->c);
  if (!ch->L || ch->c.status < CHOLMOD_OK) {
    sw_errf(err, errsz, "CHOLMOD analyze failed (status %d)", ch->c.status);
    return SW_FATAL;
  }
  return SW_OK;
}

double *sw_chol_values(sw_chol *ch) { return ch->A->x; }

int sw_chol_factor(sw_chol *ch, char *err, size_t errsz) {
  int ok = cholmod_l_factorize(ch->A, ch->L, &ch->c);
  if (ch->c.status == CHOLMOD_NOT_POSDEF || (ok && ch->L->minor < ch->L->n)) {
    sw_errf(err, errsz, "CHOLMOD: the system matrix is not positive definite (column %ld)",
            (long)ch->L->minor);
    return SW_RECOVER;
  }
  if (!ok || ch->c.status < CHOLMOD_OK) {
    sw_errf(err, errsz, "CHOLMOD factorize failed (status %d)", ch->c.status);
    return SW_FATAL;
  }
  return SW_OK;
}

int sw_chol_solve(sw_chol *ch, const double *rhs, double *sol, char *err, size_t errsz) {
  size_t n = ch->A->nrow;
  memcpy(ch->b->x, rhs, n * sizeof(double));
  if (!cholmod_l_solve2(CHOLMOD_A, ch->L, ch->b, NULL, &ch->x, NULL, &ch->Y, &ch->E, &ch->c)) {
    sw_errf(err, errsz, "CHOLMOD solve failed (status %d)", ch->c.status);
    return SW_FATAL;
  }
  memcpy(sol, ch->x->x, n * sizeof(double));
  return SW_OK;
}

void sw_chol_free(sw_chol *ch) {
  if (!ch->started) return;
  cholmod_l_free_sparse(&ch->A, &ch->c);
  cholmod_l_free_factor(&ch->L, &ch->c);
  cholmod_l_free_dense(&ch->b, &ch->c);
  cholmod_l_free_dense(&ch->x, &ch->c);
  cholmod_l_free_dense(&ch->Y, &ch->c);
  cholmod_l_free_dense(&ch->E, &ch->c);
  cholmod_l_finish(&ch->c);
  ch->started = 0;
}
