/* cholmod.c — the one sparse Cholesky of every implicit method (CHOLMOD's 32-bit interface,
 * cholmod_*: 4-byte indices in the system and its factor, so at most 2^31 - 1 entries in
 * either; docs/performance.md).  Analysed once per run (fill-reducing ordering and
 * symbolic factor), refactorised numerically per Newton iteration, solved with persistent
 * workspaces so a solve allocates nothing.  The pattern is then stored in the elimination
 * order the analysis found, in the triangle each kind of factorisation reads as it stands
 * (supernodal: lower; simplicial: upper), and analysed again in that natural order: CHOLMOD
 * then factorises the system's own arrays, with no permuted copy per factorisation
 * (cholmod_factorize makes one, at least 16 bytes a nonzero, unless the matrix is already
 * in its order and triangle). */
#include <stdio.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "solver.h"
#include "util.h"

extern void dpotrf_(const char *uplo, const int *n, double *a, const int *lda, int *info);
extern void dpotrs_(const char *uplo, const int *n, const int *nrhs, const double *a,
                    const int *lda, double *b, const int *ldb, int *info);

/* A failed CHOLMOD call (what: "analyze", "factorize", "solve", ...) as what went wrong: out of
 * memory and too large say so, with the size of the system and of its factor; returns
 * SW_FATAL. */
static int chol_failed(const sw_chol *ch, const char *what, char *err, size_t errsz) {
  char size[96] = "";
  long n = ch->A ? (long)ch->A->nrow : 0;
  if (ch->c.lnz > 0)
    snprintf(size, sizeof size, " (a %ld x %ld system; %.0f nonzeros in its factor, %.3g MB)", n,
             n, ch->c.lnz, ch->c.lnz * 8.0 / (1 << 20));
  else snprintf(size, sizeof size, " (a %ld x %ld system)", n, n);
  if (ch->c.status == CHOLMOD_OUT_OF_MEMORY)
    sw_errf(err, errsz, "CHOLMOD ran out of memory in %s%s", what, size);
  else if (ch->c.status == CHOLMOD_NOT_INSTALLED)
    sw_errf(err, errsz, "CHOLMOD %s: the ordering %s is not available (this CHOLMOD was built "
            "without METIS); use ordering: amd", what, sw_ordering_names()[ch->ordering]);
  else if (ch->c.status == CHOLMOD_TOO_LARGE)
    sw_errf(err, errsz, "CHOLMOD: the problem is too large for %s%s: more than the 2^31 - 1 "
            "entries its 32-bit indices address", what, size);
  else sw_errf(err, errsz, "CHOLMOD %s failed (status %d)%s", what, ch->c.status, size);
  return SW_FATAL;
}

/* The Woodbury workspaces for the pattern's low-rank vectors (none when p->nlr = 0). */
static int lowrank_init(sw_chol *ch, const sw_pattern *p) {
  size_t n = (size_t)p->n, r = (size_t)p->nlr, nent = (size_t)p->lrptr[p->nlr];
  ch->nlr = p->nlr;
  ch->lrcoef = 1.0;
  if (!r) return 0;
  ch->lrptr = sw_calloc(r + 1, sizeof(long));
  ch->lrrow = sw_calloc(nent + 1, sizeof(long));
  ch->lrval = sw_calloc(nent + 1, sizeof(double));
  ch->C = sw_calloc(r * r, sizeof(double));
  ch->z = sw_calloc(r, sizeof(double));
  ch->V = cholmod_zeros(n, r, CHOLMOD_REAL, &ch->c);
  ch->W = cholmod_zeros(n, r, CHOLMOD_REAL, &ch->c);
  if (!ch->lrptr || !ch->lrrow || !ch->lrval || !ch->C || !ch->z || !ch->V || !ch->W) return -1;
  memcpy(ch->lrptr, p->lrptr, (r + 1) * sizeof(long));
  for (size_t q = 0; q < nent; q++) /* positions, as CHOLMOD's vectors */
    ch->lrrow[q] = p->pos ? p->pos[p->lrrow[q]] : p->lrrow[q];
  return 0;
}

/* CHOLMOD's method for an SW_ORDERING_* (auto: AMD first, sw_chol_init). */
static void chol_ordering(sw_chol *ch, int ordering) {
  static const int method[SW_ORDERING_N] = {CHOLMOD_AMD, CHOLMOD_AMD, CHOLMOD_METIS,
                                            CHOLMOD_NESDIS};
  ch->ordering = ordering > 0 && ordering < SW_ORDERING_N ? ordering : SW_ORDERING_AUTO;
  ch->used = -1;
  ch->c.postorder = 1; /* a weighted postorder of the elimination tree: larger supernodes */
  ch->c.nmethods = 1;
  ch->c.method[0].ordering = method[ch->ordering];
}

/* auto, after AMD's analysis: a system of at least SW_ORDERING_SWITCH unknowns is analysed
 * again with NESDIS, and the ordering with fewer flops kept (AMD's too when this CHOLMOD has
 * no METIS). */
static int chol_auto(sw_chol *ch, char *err, size_t errsz) {
  const double fl = ch->c.fl, lnz = ch->c.lnz;
  if (ch->ordering != SW_ORDERING_AUTO || ch->A->nrow < SW_ORDERING_SWITCH) return SW_OK;
  ch->c.method[0].ordering = CHOLMOD_NESDIS;
  cholmod_factor *nd = cholmod_analyze(ch->A, &ch->c);
  if (nd && ch->c.status >= CHOLMOD_OK && ch->c.fl < fl) {
    cholmod_free_factor(&ch->L, &ch->c);
    ch->L = nd;
    return SW_OK;
  }
  if (!nd && ch->c.status != CHOLMOD_NOT_INSTALLED && ch->c.status != CHOLMOD_OUT_OF_MEMORY)
    return chol_failed(ch, "analyze", err, errsz);
  cholmod_free_factor(&nd, &ch->c);
  ch->c.status = CHOLMOD_OK;
  ch->c.fl = fl, ch->c.lnz = lnz; /* AMD's stays */
  ch->c.method[0].ordering = CHOLMOD_AMD;
  return SW_OK;
}

void sw_chol_mode(sw_chol *ch, int mode) {
  static const int kind[SW_FACTOR_N] = {CHOLMOD_AUTO, CHOLMOD_SIMPLICIAL, CHOLMOD_SUPERNODAL};
  int k = mode >= 0 ? mode % SW_FACTOR_N : SW_FACTOR_AUTO;
  ch->c.supernodal = kind[k];
  ch->c.supernodal_switch = SW_FACTOR_SWITCH;
  /* Below SW_RELAX_SWITCH unknowns, coarser supernodes than CHOLMOD's defaults ({4, 16, 48},
   * {0.8, 0.1, 0.05}): fewer, larger dense blocks for the BLAS, at the cost of explicit zeros
   * (a factor 2.1-2.6 times its nonzeros against 1.4-1.5).  From there on CHOLMOD's own:
   * as fast or faster, and a third less memory (docs/performance.md, "Simplicial or
   * supernodal"). */
  static const size_t coarse_n[3] = {16, 48, 128};
  static const double coarse_z[3] = {0.8, 0.3, 0.1};
  if (!ch->A || ch->A->nrow < SW_RELAX_SWITCH) /* else cholmod_start's own stay */
    for (int j = 0; j < 3; j++) ch->c.nrelax[j] = coarse_n[j], ch->c.zrelax[j] = coarse_z[j];
  chol_ordering(ch, mode >= 0 ? mode / SW_FACTOR_N : SW_ORDERING_AUTO);
}

int sw_chol_super(const sw_chol *ch) { return ch->started && ch->L ? ch->L->is_super : -1; }

int sw_chol_ordering(const sw_chol *ch) { return ch->started && ch->L ? ch->used : -1; }

/* SW_ORDERING_* of CHOLMOD's ordering method (-1: another). */
static int ordering_of(int method) {
  switch (method) {
  case CHOLMOD_AMD: return SW_ORDERING_AMD;
  case CHOLMOD_METIS: return SW_ORDERING_METIS;
  case CHOLMOD_NESDIS: return SW_ORDERING_NESDIS;
  default: return -1;
  }
}

/* The system as CHOLMOD sees it: the pattern's column pointers and row indices themselves (a
 * copy would cost 8 bytes a nonzero; CHOLMOD reads them only), values of its own (x, or new
 * ones when x is NULL). */
static cholmod_sparse *system_view(sw_chol *ch, const sw_pattern *p, double *x) {
  cholmod_sparse *A = &ch->Ahead;
  memset(A, 0, sizeof *A);
  A->nrow = A->ncol = (size_t)p->n;
  A->nzmax = (size_t)p->nnz;
  A->p = (void *)p->colptr;
  A->i = (void *)p->rowind;
  A->x = x ? x : sw_calloc((size_t)p->nnz + 1, sizeof(double));
  A->stype = p->lower ? -1 : 1; /* the triangle stored */
  A->itype = CHOLMOD_INT;
  A->xtype = CHOLMOD_REAL;
  A->dtype = CHOLMOD_DOUBLE;
  A->sorted = 1;
  A->packed = 1;
  return A;
}

/* Something positive definite in A for the symbolic analysis, which needs only the
 * pattern. */
static void identity_values(sw_chol *ch, const sw_pattern *p) {
  double *v = ch->A->x;
  memset(v, 0, (size_t)p->nnz * sizeof(double));
  for (int c = 0; c < p->n; c++) v[p->diag[c]] = 1.0;
}

/* The pattern stored in the order of the analysis just made (ch->L) and analysed again in
 * that natural order with no postorder (the order is postordered already), the kind of
 * factor kept: the same factor, which CHOLMOD now computes from A as it stands. */
static int natural_order(sw_chol *ch, sw_pattern *p, char *err, size_t errsz) {
  int super = ch->L->is_super;
  ch->used = ordering_of(ch->L->ordering);
  if (sw_pattern_order(p, ch->L->Perm, super)) {
    sw_errf(err, errsz, "out of memory storing the system in its elimination order");
    return SW_FATAL;
  }
  cholmod_free_factor(&ch->L, &ch->c);
  system_view(ch, p, ch->A->x);
  identity_values(ch, p);
  const double fl = ch->c.fl, lnz = ch->c.lnz;
  ch->c.method[0].ordering = CHOLMOD_NATURAL;
  ch->c.postorder = 0;
  ch->c.supernodal = super ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  ch->L = cholmod_analyze(ch->A, &ch->c);
  if (!ch->L || ch->c.status < CHOLMOD_OK) return chol_failed(ch, "analyze", err, errsz);
  ch->c.fl = fl, ch->c.lnz = lnz; /* the ordering's (the same factor) */
  return SW_OK;
}

/* A pattern a factorisation stored before back in DOF order, upper (as sw_pattern_build makes
 * it): each analysis starts from the same matrix, whatever was analysed before. */
static int dof_order(sw_pattern *p) {
  if (!p->pos) return 0;
  int *perm = sw_calloc((size_t)p->n + 1, sizeof(int));
  if (!perm) return -1;
  for (int c = 0; c < p->n; c++) perm[c] = p->pos[c]; /* position c gets DOF c */
  int rc = sw_pattern_order(p, perm, 0);
  sw_free(perm);
  return rc;
}

int sw_chol_init(sw_chol *ch, sw_pattern *p, int mode, char *err, size_t errsz) {
  memset(ch, 0, sizeof *ch);
  if (dof_order(p)) return sw_errf(err, errsz, "out of memory reordering the system"), SW_FATAL;
  cholmod_start(&ch->c);
  ch->started = 1;
  ch->c.print = 0;
  ch->c.error_handler = NULL;
  ch->c.final_ll = 1; /* simplicial factors as LL^T too, so an indefinite S is detected */
  size_t n = (size_t)p->n;
  ch->A = system_view(ch, p, NULL);
  ch->b = cholmod_zeros(n, 1, CHOLMOD_REAL, &ch->c);
  if (!ch->A->x || !ch->b) {
    sw_errf(err, errsz, "CHOLMOD: out of memory allocating a %zu x %zu system", n, n);
    return SW_FATAL;
  }
  identity_values(ch, p);
  sw_chol_mode(ch, mode);
  ch->L = cholmod_analyze(ch->A, &ch->c);
  if (!ch->L || ch->c.status < CHOLMOD_OK) return chol_failed(ch, "analyze", err, errsz);
  int rc = chol_auto(ch, err, errsz);
  if (!rc) rc = natural_order(ch, p, err, errsz);
  if (!rc && lowrank_init(ch, p)) {
    sw_errf(err, errsz, "CHOLMOD: out of memory allocating a %zu x %zu system", n, n);
    return SW_FATAL;
  }
  ch->pos = p->pos;
#ifdef __GLIBC__
  /* The set-up's scratch (the vertex graph, the old order, the analysis's workspaces) is
   * freed by now; glibc keeps such memory for reuse (its mmap threshold grows with each large
   * block freed), and the factor, allocated at the first factorisation, would be placed beside
   * it: peak RSS 152 against 135 MiB on the 160 x 160 cloth.  Returned to the system here. */
  malloc_trim(0);
#endif
  return rc;
}

double *sw_chol_values(sw_chol *ch) { return ch->A->x; }

double *sw_chol_lowrank(sw_chol *ch, double coef) {
  ch->lrcoef = coef;
  return ch->lrval;
}

/* W = A^-1 V (one multi-column solve) and the Cholesky factor of C = I + coef V^T W. */
static int lowrank_factor(sw_chol *ch, char *err, size_t errsz) {
  const long n = (long)ch->A->nrow;
  const int r = ch->nlr;
  double *V = ch->V->x, *C = ch->C;
  memset(V, 0, (size_t)(n * r) * sizeof(double));
  for (int k = 0; k < r; k++)
    for (long q = ch->lrptr[k]; q < ch->lrptr[k + 1]; q++) V[k * n + ch->lrrow[q]] += ch->lrval[q];
  if (!cholmod_solve2(CHOLMOD_A, ch->L, ch->V, NULL, &ch->W, NULL, &ch->Y2, &ch->E2, &ch->c))
    return chol_failed(ch, "the solve for the low-rank part", err, errsz);
  const double *W = ch->W->x;
  for (int k = 0; k < r; k++)
    for (int j = 0; j <= k; j++) {
      double s = 0.0;
      for (long q = ch->lrptr[k]; q < ch->lrptr[k + 1]; q++)
        s += ch->lrval[q] * W[j * n + ch->lrrow[q]];
      C[j * r + k] = (j == k) + ch->lrcoef * s; /* lower triangle, column-major */
    }
  int info = 0;
  dpotrf_("L", &r, C, &r, &info);
  if (info) {
    sw_errf(err, errsz, "the low-rank capacitance matrix is not positive definite (%d)", info);
    return SW_RECOVER;
  }
  return SW_OK;
}

int sw_chol_factor(sw_chol *ch, char *err, size_t errsz) {
  int ok = cholmod_factorize(ch->A, ch->L, &ch->c);
  if (ch->c.status == CHOLMOD_NOT_POSDEF || (ok && ch->L->minor < ch->L->n)) {
    sw_errf(err, errsz, "CHOLMOD: the system matrix is not positive definite (column %ld)",
            (long)ch->L->minor);
    return SW_RECOVER;
  }
  if (!ok || ch->c.status < CHOLMOD_OK) return chol_failed(ch, "factorize", err, errsz);
  return ch->nlr ? lowrank_factor(ch, err, errsz) : SW_OK;
}

long sw_chol_nnz(const sw_chol *ch) {
  return ch->started && ch->L ? (long)ch->c.lnz : 0;
}

/* sol <- sol - coef W C^-1 V^T sol: from A^-1 b to S^-1 b (Woodbury). */
static void lowrank_correct(sw_chol *ch, double *sol) {
  const long n = (long)ch->A->nrow;
  const int r = ch->nlr, one = 1;
  for (int k = 0; k < r; k++) {
    double s = 0.0;
    for (long q = ch->lrptr[k]; q < ch->lrptr[k + 1]; q++) s += ch->lrval[q] * sol[ch->lrrow[q]];
    ch->z[k] = s;
  }
  int info = 0;
  dpotrs_("L", &r, &one, ch->C, &r, ch->z, &r, &info);
  const double *W = ch->W->x;
  for (int k = 0; k < r; k++) {
    double c = ch->lrcoef * ch->z[k];
    for (long i = 0; i < n; i++) sol[i] -= c * W[k * n + i];
  }
}

int sw_chol_solve(sw_chol *ch, const double *rhs, double *sol, char *err, size_t errsz) {
  const long n = (long)ch->A->nrow;
  double *b = ch->b->x;
  for (long c = 0; c < n; c++) b[ch->pos ? ch->pos[c] : c] = rhs[c]; /* DOFs -> positions */
  if (!cholmod_solve2(CHOLMOD_A, ch->L, ch->b, NULL, &ch->x, NULL, &ch->Y, &ch->E, &ch->c))
    return chol_failed(ch, "solve", err, errsz);
  double *x = ch->x->x;
  if (ch->nlr) lowrank_correct(ch, x);
  for (long c = 0; c < n; c++) sol[c] = x[ch->pos ? ch->pos[c] : c];
  return SW_OK;
}

void sw_chol_free(sw_chol *ch) {
  if (!ch->started) return;
  if (ch->A) sw_free(ch->A->x); /* the index arrays are the pattern's */
  ch->A = NULL;
  cholmod_free_factor(&ch->L, &ch->c);
  cholmod_free_dense(&ch->b, &ch->c);
  cholmod_free_dense(&ch->x, &ch->c);
  cholmod_free_dense(&ch->Y, &ch->c);
  cholmod_free_dense(&ch->E, &ch->c);
  cholmod_free_dense(&ch->V, &ch->c);
  cholmod_free_dense(&ch->W, &ch->c);
  cholmod_free_dense(&ch->Y2, &ch->c);
  cholmod_free_dense(&ch->E2, &ch->c);
  sw_free(ch->lrptr);
  sw_free(ch->lrrow);
  sw_free(ch->lrval);
  sw_free(ch->C);
  sw_free(ch->z);
  cholmod_finish(&ch->c);
  ch->started = 0;
}
