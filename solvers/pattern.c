/* pattern.c — the fixed sparsity pattern of S = c^2 M + c D + H on the free DOFs.
 * Built once per run from the terms' stencils: vertex adjacency -> upper-triangle CSC with
 * sorted rows -> for every coupled vertex pair, the slots of its dim x dim entries, through
 * which every term's Hessian blocks add into the system (sw_slots).  The factorisation then
 * stores it in its elimination order (sw_pattern_order), the triangle CHOLMOD factorises
 * without a copy. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "solver.h"
#include "terms.h"
#include "util.h"

static int cmp_long(const void *a, const void *b) {
  long x = *(const long *)a, y = *(const long *)b;
  return (x > y) - (x < y);
}

/* Sorted, unique vertex neighbours (self included) of every vertex, from the stencils and the
 * nextra vertex pairs extra (2 each): CSR in (*ptr, *adj). */
static int vertex_graph(const sw_model *m, const int *extra, long nextra, long **ptr_out,
                        int **adj_out) {
  long npair = m->nv + 2 * nextra; /* self pairs, extra pairs both ways */
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    for (int s = 0; s < t->nstencil; s++) {
      long len = t->sptr[s + 1] - t->sptr[s];
      npair += len * (len - 1);
    }
  }
  long *key = sw_calloc((size_t)npair, sizeof(long));
  long *ptr = sw_calloc((size_t)m->nv + 1, sizeof(long));
  if (!key || !ptr) return sw_free(key), sw_free(ptr), -1;
  long np = 0;
  for (int i = 0; i < m->nv; i++) key[np++] = (long)i * m->nv + i;
  for (long q = 0; q < nextra; q++) {
    key[np++] = (long)extra[2 * q] * m->nv + extra[2 * q + 1];
    key[np++] = (long)extra[2 * q + 1] * m->nv + extra[2 * q];
  }
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    for (int s = 0; s < t->nstencil; s++)
      for (int i = t->sptr[s]; i < t->sptr[s + 1]; i++)
        for (int j = t->sptr[s]; j < t->sptr[s + 1]; j++)
          if (i != j) key[np++] = (long)t->sidx[i] * m->nv + t->sidx[j];
  }
  qsort(key, (size_t)np, sizeof(long), cmp_long);
  long nu = 0;
  for (long q = 0; q < np; q++)
    if (nu == 0 || key[q] != key[nu - 1]) key[nu++] = key[q];
  int *adj = sw_calloc((size_t)nu, sizeof(int));
  if (!adj) return sw_free(key), sw_free(ptr), -1;
  for (long q = 0; q < nu; q++) {
    ptr[key[q] / m->nv + 1]++;
    adj[q] = (int)(key[q] % m->nv);
  }
  for (int i = 0; i < m->nv; i++) ptr[i + 1] += ptr[i];
  sw_free(key);
  *ptr_out = ptr;
  *adj_out = adj;
  return 0;
}

/* Upper-triangle CSC in DOF order: column c (vertex b, component beta) holds rows r <= c of
 * the free components of b's neighbours.  DOFs are numbered vertex-major, so rows come out
 * sorted.  (The order the fill-reducing analysis reads; sw_pattern_order then stores it in
 * the elimination order.) */
static int build_csc(sw_pattern *p, const sw_model *m, const long *vptr, const int *adj) {
  const int d = m->dim;
  p->colptr = sw_calloc((size_t)p->n + 1, sizeof(int));
  p->diag = sw_calloc((size_t)p->n, sizeof(long));
  if (!p->colptr || !p->diag) return -1;
  for (int pass = 0; pass < 2; pass++) {
    long nz = 0;
    for (int b = 0; b < m->nv; b++)
      for (int be = 0; be < d; be++) {
        int c = m->dof[b * d + be];
        if (c < 0) continue;
        if (pass == 0) p->colptr[c] = (int)nz;
        for (long q = vptr[b]; q < vptr[b + 1]; q++)
          for (int al = 0; al < d; al++) {
            int r = m->dof[adj[q] * d + al];
            if (r < 0 || r > c) continue;
            if (pass == 1) {
              if (r == c) p->diag[c] = nz;
              p->rowind[nz] = r;
            }
            nz++;
          }
      }
    if (pass == 0) {
      if (nz > INT_MAX) return -1; /* more than 32-bit indices hold */
      p->colptr[p->n] = (int)nz;
      p->nnz = nz;
      p->rowind = sw_calloc((size_t)nz, sizeof(int));
      if (!p->rowind) return -1;
    }
  }
  return 0;
}

/* The slot of the entry of DOFs r and c (either order), or -1: a search down the column of
 * its stored triangle. */
static long find_slot(const sw_pattern *p, int r, int c) {
  if (p->pos) r = p->pos[r], c = p->pos[c];
  if (p->lower ? r < c : r > c) {
    int t = r;
    r = c, c = t;
  }
  long lo = p->colptr[c], hi = p->colptr[c + 1] - 1;
  while (lo <= hi) {
    long mid = (lo + hi) / 2;
    if (p->rowind[mid] == r) return mid;
    if (p->rowind[mid] < r) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* The slots of every vertex pair (a, b), b >= a, of the vertex graph (sw_slots): its dim x dim
 * entries, each at the slot of its two DOFs (either order), -1 where one is pinned. */
static int build_slots(sw_pattern *p, const sw_model *m, const long *vptr, const int *adj) {
  const int d = m->dim;
  long npair = 0;
  for (int a = 0; a < m->nv; a++)
    for (long q = vptr[a]; q < vptr[a + 1]; q++) npair += adj[q] >= a;
  p->nv = m->nv;
  p->pptr = sw_calloc((size_t)m->nv + 1, sizeof(long));
  p->pvert = sw_calloc((size_t)npair + 1, sizeof(int));
  p->pslot = sw_calloc((size_t)npair * (size_t)(d * d) + 1, sizeof(int));
  if (!p->pptr || !p->pvert || !p->pslot) return -1;
  long e = 0;
  for (int a = 0; a < m->nv; a++) {
    for (long q = vptr[a]; q < vptr[a + 1]; q++) {
      const int b = adj[q];
      if (b < a) continue;
      int *ps = p->pslot + (size_t)(d * d) * e;
      for (int al = 0; al < d; al++)
        for (int be = 0; be < d; be++) {
          int r = m->dof[a * d + al], c = m->dof[b * d + be];
          ps[al * d + be] = r < 0 || c < 0 ? -1 : (int)find_slot(p, r, c);
        }
      p->pvert[e++] = b;
    }
    p->pptr[a + 1] = e;
  }
  p->slots = (sw_slots){.dim = d, .pptr = p->pptr, .pvert = p->pvert, .pslot = p->pslot};
  return 0;
}

/* The low-rank vectors' entries on free DOFs (pinned components dropped). */
static int build_lowrank(sw_pattern *p, const sw_model *m) {
  const int d = m->dim;
  long nent = 0, src0 = 0;
  for (int k = 0; k < m->nterm; k++) {
    p->nlr += m->term[k].nlowrank;
    if (m->term[k].nlowrank) nent += (long)m->term[k].lptr[m->term[k].nlowrank] * d;
  }
  p->lrptr = sw_calloc((size_t)p->nlr + 1, sizeof(long));
  p->lrrow = sw_calloc((size_t)nent + 1, sizeof(long));
  p->lrsrc = sw_calloc((size_t)nent + 1, sizeof(long));
  if (!p->lrptr || !p->lrrow || !p->lrsrc) return -1;
  long q = 0;
  int r = 0;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    for (int v = 0; v < t->nlowrank; v++, r++) {
      for (int i = t->lptr[v] * d; i < t->lptr[v + 1] * d; i++) {
        int c = m->dof[t->lidx[i / d] * d + i % d];
        if (c < 0) continue;
        p->lrrow[q] = c;
        p->lrsrc[q++] = src0 + i;
      }
      p->lrptr[r + 1] = q;
    }
    if (t->nlowrank) src0 += (long)t->lptr[t->nlowrank] * d;
  }
  return 0;
}

int sw_pattern_build(sw_pattern *p, const sw_model *m, char *err, size_t errsz) {
  return sw_pattern_build_ex(p, m, NULL, 0, err, errsz);
}

int sw_pattern_build_ex(sw_pattern *p, const sw_model *m, const int *extra, long nextra,
                        char *err, size_t errsz) {
  memset(p, 0, sizeof *p);
  p->n = m->ndof;
  long *vptr = NULL;
  int *adj = NULL;
  if (vertex_graph(m, extra, nextra, &vptr, &adj) || build_csc(p, m, vptr, adj) ||
      build_slots(p, m, vptr, adj) || build_lowrank(p, m)) {
    sw_free(vptr);
    sw_free(adj);
    sw_pattern_free(p);
    sw_errf(err, errsz, "cannot build the sparsity pattern (out of memory or too large)");
    return SW_FATAL;
  }
  sw_free(vptr);
  sw_free(adj);
  return SW_OK;
}

void sw_pattern_free(sw_pattern *p) {
  sw_free(p->pptr);
  sw_free(p->pvert);
  sw_free(p->pslot);
  sw_free(p->pos);
  sw_free(p->dofat);
  sw_free(p->colptr);
  sw_free(p->rowind);
  sw_free(p->diag);
  sw_free(p->lrptr);
  sw_free(p->lrrow);
  sw_free(p->lrsrc);
  memset(p, 0, sizeof *p);
}

void sw_pattern_fill(const sw_pattern *p, const sw_model *m, const sw_data *d, double mass_coef,
                     double hess_coef, double *values) {
  memset(values, 0, (size_t)p->nnz * sizeof(double));
  for (int k = 0; k < m->nterm; k++) { /* the arithmetic of sw_ev_block_done (sw_hsink) */
    const sw_term *t = &m->term[k];
    const double *h = d->hess + d->hoff[k];
    for (int s = 0; s < t->nstencil; s++)
      sw_slots_add(&p->slots, t->sidx + t->sptr[s], t->sptr[s + 1] - t->sptr[s], h + t->hptr[s],
                   values);
  }
  sw_pattern_finish(p, m, mass_coef, hess_coef, values);
}

void sw_pattern_finish(const sw_pattern *p, const sw_model *m, double mass_coef,
                       double hess_coef, double *values) {
  if (hess_coef != 1.0)
    for (long q = 0; q < p->nnz; q++) values[q] *= hess_coef;
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < m->dim; a++) {
      int c = m->dof[i * m->dim + a];
      if (c >= 0) values[p->diag[c]] += mass_coef * m->mass[i];
    }
}

long sw_pattern_slot(const sw_pattern *p, int r, int c) { return find_slot(p, r, c); }

int sw_pattern_has_pair(const sw_pattern *p, const sw_model *m, int i, int j) {
  if (i >= m->nv || j >= m->nv) return 1; /* a mesh obstacle's vertex: no DOF */
  for (int a = 0; a < m->dim; a++)
    for (int b = 0; b < m->dim; b++) {
      int r = m->dof[i * m->dim + a], c = m->dof[j * m->dim + b];
      if (r >= 0 && c >= 0) return find_slot(p, r, c) >= 0;
    }
  return 1; /* a pinned vertex: no entry needed */
}

void sw_pattern_remap(const sw_pattern *from, const double *vfrom, const sw_pattern *to,
                      double *vto) {
  memset(vto, 0, (size_t)to->nnz * sizeof(double));
  for (int j = 0; j < from->n; j++)
    for (long k = from->colptr[j]; k < from->colptr[j + 1]; k++) {
      long q = find_slot(to, sw_pattern_dof(from, from->rowind[k]), sw_pattern_dof(from, j));
      if (q >= 0) vto[q] = vfrom[k];
    }
}

void sw_pattern_block_slots(const sw_pattern *p, const sw_model *m, const int *v, int nvert,
                            int *slot) {
  const int d = m->dim, w = nvert * d;
  int dof[12]; /* an index >= nv (a mesh obstacle's vertex) has no DOF */
  if (w > 12) return; /* at most 4 vertices in 3D (solver.h) */
  for (int i = 0; i < w; i++) dof[i] = v[i / d] < m->nv ? m->dof[v[i / d] * d + i % d] : -1;
  for (int i = 0; i < w; i++) /* the upper triangle by DOF: each pair of DOFs once */
    for (int j = 0; j < w; j++) {
      int r = dof[i], c = dof[j];
      slot[i * w + j] = r < 0 || c < 0 || r > c ? -1 : (int)find_slot(p, r, c);
    }
}

void sw_pattern_add_slots(const int *slot, int w, const double *block, double coef,
                          double *values) {
  for (int q = 0; q < w * w; q++)
    if (slot[q] >= 0) values[slot[q]] += coef * block[q];
}

void sw_pattern_add_block(const sw_pattern *p, const sw_model *m, const int *v, int nvert,
                          const double *block, double coef, double *values) {
  int slot[144];
  if (nvert * m->dim > 12) return;
  sw_pattern_block_slots(p, m, v, nvert, slot);
  sw_pattern_add_slots(slot, nvert * m->dim, block, coef, values);
}

void sw_pattern_symv(const sw_pattern *p, const double *values, const double *x, double *y) {
  memset(y, 0, (size_t)p->n * sizeof(double));
  for (int j = 0; j < p->n; j++) {
    const int c = sw_pattern_dof(p, j);
    for (long k = p->colptr[j]; k < p->colptr[j + 1]; k++) {
      const int r = sw_pattern_dof(p, p->rowind[k]);
      y[r] += values[k] * x[c];
      if (r != c) y[c] += values[k] * x[r];
    }
  }
}

/* An entry of a column being rebuilt: its new row and its old slot. */
typedef struct moved {
  int row, from;
} moved;

static int cmp_moved(const void *a, const void *b) {
  int x = ((const moved *)a)->row, y = ((const moved *)b)->row;
  return (x > y) - (x < y);
}

/* The entries e[0..n) in increasing row: insertion for the short columns of a mesh, qsort for
 * the long ones (a dense tendon's). */
static void sort_moved(moved *e, long n) {
  if (n > 64) {
    qsort(e, (size_t)n, sizeof *e, cmp_moved);
    return;
  }
  for (long i = 1; i < n; i++) {
    moved t = e[i];
    long j = i;
    for (; j > 0 && e[j - 1].row > t.row; j--) e[j] = e[j - 1];
    e[j] = t;
  }
}

int sw_pattern_order(sw_pattern *p, const int *perm, int lower) {
  const int n = p->n;
  int *inv = sw_calloc((size_t)n + 1, sizeof(int)), *pos = sw_calloc((size_t)n + 1, sizeof(int));
  int *dofat = sw_calloc((size_t)n + 1, sizeof(int));
  int *colptr = sw_calloc((size_t)n + 2, sizeof(int)), *rowind = NULL;
  long *slot = NULL;
  moved *e = NULL;
  if (inv && pos && dofat && colptr) {
    rowind = sw_calloc((size_t)p->nnz + 1, sizeof(int));
    slot = sw_calloc((size_t)p->nnz + 1, sizeof(long));
    e = sw_calloc((size_t)p->nnz + 1, sizeof(moved));
  }
  if (!rowind || !slot || !e) {
    sw_free(inv), sw_free(pos), sw_free(dofat), sw_free(colptr), sw_free(rowind), sw_free(slot);
    sw_free(e);
    return -1;
  }
  for (int k = 0; k < n; k++) inv[perm[k]] = k; /* old position -> new */
  for (int pass = 0; pass < 2; pass++) { /* count the new columns, then place the entries */
    for (int j = 0; j < n; j++)
      for (long q = p->colptr[j]; q < p->colptr[j + 1]; q++) {
        int a = inv[p->rowind[q]], b = inv[j];
        int col = lower == (a > b) ? b : a, row = col == a ? b : a;
        if (pass == 0) colptr[col + 2]++;
        else e[colptr[col + 1]++] = (moved){row, (int)q};
      }
    if (pass == 0)
      for (int j = 0; j < n; j++) colptr[j + 2] += colptr[j + 1];
  }
  for (int j = 0; j < n; j++) { /* colptr[j + 1] is now column j's end */
    sort_moved(e + colptr[j], colptr[j + 1] - colptr[j]);
    for (long q = colptr[j]; q < colptr[j + 1]; q++) rowind[q] = e[q].row, slot[e[q].from] = q;
  }
  sw_free(e);
  for (int c = 0; c < n; c++) {
    pos[c] = inv[p->pos ? p->pos[c] : c];
    dofat[pos[c]] = c;
    p->diag[c] = slot[p->diag[c]];
  }
  const int dd = p->slots.dim * p->slots.dim;
  const size_t nps = p->pptr ? (size_t)p->pptr[p->nv] * (size_t)dd : 0;
  for (size_t q = 0; q < nps; q++) /* the pairs' slots follow */
    if (p->pslot[q] >= 0) p->pslot[q] = (int)slot[p->pslot[q]];
  sw_free(slot), sw_free(inv);
  sw_free(p->colptr), sw_free(p->rowind), sw_free(p->pos), sw_free(p->dofat);
  p->colptr = colptr, p->rowind = rowind, p->pos = pos, p->dofat = dofat;
  p->lower = lower;
  return 0;
}

void sw_pattern_fill_lowrank(const sw_pattern *p, const sw_data *d, double *lrval) {
  for (long q = 0; q < p->lrptr[p->nlr]; q++) lrval[q] = d->lowrank[p->lrsrc[q]];
}

long sw_system_nnz(const sw_model *m) {
  sw_pattern p;
  if (sw_pattern_build(&p, m, NULL, 0)) return -1;
  long nnz = p.nnz;
  sw_pattern_free(&p);
  return nnz;
}
