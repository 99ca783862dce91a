/* inverse.h — internal pieces of the tendon inverse problem (solvers/inverse.c,
 * docs/tendons.md, docs/inverse.md): the force matrix A (inverse.c) and
 * non-negative least squares (nnls.c).
 * The public entry points (sw_inverse_solve, sw_inverse_check, sw_targets_read) are in sinew.h. */
#ifndef SW_INVERSE_H
#define SW_INVERSE_H

#include <stddef.h>

#include "sinew.h"

/* A (column-major, (nt*dim) x ntendon, leading dimension nt*dim) at x (nv x dim, m): column t
 * holds the nodal force of tendon t per unit tension, -grad l_t (tendon model §2: the sum of its
 * segments' eps_ij, +e^_ij at node i and -e^_ij at node j), on the rows of the nt target
 * vertices target[] (target k, component c: row k*dim + c).  Unitless.  A tendon with
 * K = 0 gets a zero column (no rest length makes it pull).  Nonzero when out of memory. */
int sw_inverse_matrix(const sw_model *m, const double *x, const int *target, int nt, double *A);

/* nnls.c: Lawson–Hanson NNLS: min 1/2 |A x - b|^2 subject to x >= 0, A (m x n, column-major, lda = m).
 * Each passive-set least-squares subproblem is solved by LAPACK dgelsd (SVD, rank-revealing).
 * Stops when no free component has a gradient w = A^T (b - A x) above tol (the default when
 * tol <= 0: 10 eps max(m, n) |A|_1 |b|_inf) or after max_iter outer iterations (<= 0: 3n).
 * SW_OK, SW_RECOVER when the cap was hit (x is the last feasible iterate), SW_FATAL (err) on
 * allocation or LAPACK failure.  *iters (may be NULL): outer iterations. */
int sw_nnls(int m, int n, const double *A, const double *b, double *x, double tol, int max_iter,
            int *iters, char *err, size_t errsz);

#endif
