/* compact.c — the compact Newton matrix of a bending term whose Hessian is constant
 * (`integrator: {bending_matrix: compact}`, docs/integrators.md "The bending matrix").
 *
 * The quadratic (Bergou et al. 2006) and Morley bending energies are E = (1/2) x^T (Q (x) I) x
 * with Q = sum_s Q_s over stencils that reach past a face: a hinge's two far vertices, a
 * triangle's neighbours and theirs (up to 12 vertices).  Those couplings join vertices that no
 * face joins, and they make the sparse factor of Newton's system 2.4 to 3.7 times larger than
 * the membrane's alone on a garment (docs/performance.md, "The bending matrix").  The compact
 * matrix keeps every entry of Q between two vertices that share a face and moves each other
 * one onto the diagonal (diagonal compensation, as in Axelsson, "Iterative Solution Methods",
 * 1994, ch. 7): the entry q of a dropped pair (i, j), summed over the stencils, is replaced by
 * |q| on both diagonals, so
 *   C = Q + sum over dropped pairs of |q| (e_i e_i^T + e_j e_j^T) - q (e_i e_j^T + e_j e_i^T),
 * each added 2 x 2 being positive semi-definite: C >= Q >= 0.  Newton then solves with C in
 * place of the bending's part of its matrix: the energy and gradient are exact, so is the
 * converged answer; the iteration's contraction is that of a matrix that bounds the true one
 * from above.  C lives on the faces: each kept entry is split evenly among the faces that hold
 * its pair, each diagonal among the faces at its vertex, so the term declares one 3-vertex
 * stencil per face, the membrane's, and the sparsity pattern is the membrane's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "terms.h"
#include "util.h"

void sw_compact_free(sw_compact *c) {
  sw_free(c->sptr);
  sw_free(c->sidx);
  sw_free(c->C);
  memset(c, 0, sizeof *c);
}

/* The faces at each vertex, CSR (ptr nv + 1, idx 3 nf); nonzero when out of memory. */
static int vertex_faces(const sw_model *m, int **ptr, int **idx) {
  *ptr = sw_calloc((size_t)m->nv + 1, sizeof(int));
  *idx = sw_calloc(3 * (size_t)m->nf + 1, sizeof(int));
  if (!*ptr || !*idx) return -1;
  for (int k = 0; k < 3 * m->nf; k++) (*ptr)[m->face[k] + 1]++;
  for (int v = 0; v < m->nv; v++) (*ptr)[v + 1] += (*ptr)[v];
  int *fill = sw_calloc((size_t)m->nv + 1, sizeof(int));
  if (!fill) return -1;
  for (int k = 0; k < 3 * m->nf; k++) {
    int v = m->face[k];
    (*idx)[(*ptr)[v] + fill[v]++] = k / 3;
  }
  sw_free(fill);
  return 0;
}

/* A dropped entry: q at (a, b) of the exact matrix, summed over the stencils. */
typedef struct dropped {
  int a, b;
  double q;
} dropped;

static int cmp_dropped(const void *p, const void *q) {
  const dropped *x = p, *y = q;
  return x->a != y->a ? (x->a > y->a) - (x->a < y->a) : (x->b > y->b) - (x->b < y->b);
}

/* Add q to entry (a, b) of C, split among the faces holding both: 1, or 0 when none does. */
static int add_pair(const sw_model *m, const int *vfp, const int *vfi, double *C, int a, int b,
                    double q) {
  int nshare = 0;
  for (int k = vfp[a]; k < vfp[a + 1]; k++) nshare += sw_face_corner(m, vfi[k], b) >= 0;
  for (int k = vfp[a]; nshare && k < vfp[a + 1]; k++) {
    int f = vfi[k], cb = sw_face_corner(m, f, b);
    if (cb >= 0) C[9 * f + 3 * sw_face_corner(m, f, a) + cb] += q / nshare;
  }
  return nshare > 0;
}

/* The entries of the stencils' Q into C (kept) and diag (the exact diagonal), the others into
 * out (*nout of them, unmerged). */
static void split_entries(const sw_term *t, const sw_model *m, const double *Q, int ldq,
                         const int *vfp, const int *vfi, double *C, double *diag, dropped *out,
                         long *nout) {
  for (int s = 0; s < t->nstencil; s++) {
    const int *v = t->sidx + t->sptr[s], nv = t->sptr[s + 1] - t->sptr[s];
    const double *Qs = Q + (size_t)ldq * ldq * s;
    for (int i = 0; i < nv; i++)
      for (int j = 0; j < nv; j++) {
        const double q = Qs[ldq * i + j];
        if (i == j) diag[v[i]] += q;
        else if (q != 0.0 && !add_pair(m, vfp, vfi, C, v[i], v[j], q))
          out[(*nout)++] = (dropped){v[i], v[j], q};
      }
  }
}

int sw_compact_stencils(sw_term *t, const sw_model *m, const double *Q, int ldq,
                        sw_compact *c, char *err, size_t errsz) {
  memset(c, 0, sizeof *c);
  int *vfp = NULL, *vfi = NULL;
  long nentry = 0, nout = 0;
  for (int s = 0; s < t->nstencil; s++) {
    long nv = t->sptr[s + 1] - t->sptr[s];
    nentry += nv * nv;
  }
  double *diag = sw_calloc((size_t)m->nv + 1, sizeof(double));
  dropped *out = sw_calloc((size_t)nentry + 1, sizeof(dropped));
  c->C = sw_calloc(9 * (size_t)m->nf + 1, sizeof(double));
  int rc = !diag || !out || !c->C || vertex_faces(m, &vfp, &vfi);
  if (!rc) split_entries(t, m, Q, ldq, vfp, vfi, c->C, diag, out, &nout);
  /* each dropped pair's total q, |q| onto both diagonals (each order adds to its row's) */
  if (!rc) qsort(out, (size_t)nout, sizeof *out, cmp_dropped);
  for (long k = 0; !rc && k < nout;) {
    long e = k;
    double q = 0.0;
    while (e < nout && out[e].a == out[k].a && out[e].b == out[k].b) q += out[e++].q;
    diag[out[k].a] += fabs(q);
    k = e;
  }
  for (int v = 0; !rc && v < m->nv; v++) {
    int nface = vfp[v + 1] - vfp[v];
    for (int k = vfp[v]; k < vfp[v + 1]; k++) {
      int f = vfi[k], cv = sw_face_corner(m, f, v);
      c->C[9 * f + 4 * cv] += diag[v] / nface;
    }
  }
  sw_free(diag);
  sw_free(out);
  sw_free(vfp);
  sw_free(vfi);
  if (rc) return sw_errf(err, errsz, "out of memory for the compact bending matrix"), -1;
  /* the wide stencils stay the term's own (energy, gradient); the faces become its stencils */
  c->sptr = t->sptr;
  c->sidx = t->sidx;
  sw_free(t->hptr);
  t->sptr = t->sidx = NULL;
  t->hptr = NULL;
  if (sw_term_alloc_stencils(t, m->nf, 3, m->dim))
    return sw_errf(err, errsz, "out of memory for the compact bending matrix"), -1;
  memcpy(t->sidx, m->face, 3 * (size_t)m->nf * sizeof(int));
  return 0;
}

void sw_compact_hess(const sw_term *t, const sw_model *m, const sw_compact *c,
                     const sw_eval *ev) {
  const int d = m->dim, bw = 3 * d;
  for (int f = 0; f < t->nstencil; f++) {
    double *blk = sw_ev_block(ev, t, f);
    const double *Cf = c->C + 9 * f;
    for (int i = 0; i < 3; i++)
      for (int j = i; j < 3; j++)
        for (int a = 0; a < d; a++) sw_hess_add(blk, bw, i * d + a, j * d + a, Cf[3 * i + j]);
    sw_ev_block_done(ev, t, f, blk);
  }
}
