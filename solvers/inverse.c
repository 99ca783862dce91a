/* inverse.c — the tendon inverse problem (tendon model §2–3, docs/tendons.md,
 * docs/inverse.md).
 *
 * At a configuration x the tendons exert the nodal forces f = A tau (tendon model §2): column t of
 * A is tendon t's force per unit tension, sum over its segments (i, j) of eps_ij = +e^_ij at
 * node i, -e^_ij at node j, e^_ij the unit vector from node i to node j.  That is -grad l_t:
 * with s_k = x_{w_k} - x_{w_{k+1}} (the tendon model §1.2), the force at waypoint a is
 * s^_{a-1} - s^_a (a tension pulls each waypoint towards its neighbours; an end point keeps one
 * term).  Only the rows of the target vertices are kept.  The waypoint tendon model's inverse
 * problem (its section 3) minimises U = 1/2 |A tau - f|^2 over tau >= 0 (NNLS, nnls.c), then
 * (its unfinished section 3.1) maps tensions to
 * rest lengths: with tau = K Delta and Delta = l - alpha, alpha_t = l_t - tau_t / K_t, so
 * Delta = tau / K >= 0 keeps each cable taut (a cable with tau = 0 sits at Delta = 0).
 *
 * The forward check rebuilds a model of the tendons alone with those rest lengths, pins every
 * vertex but the targets, loads the targets by -f (models/point_load.c) and solves for static
 * equilibrium from x: where the tendons produce f, x is already the equilibrium. */
#include <math.h>
#include <string.h>

#include "inverse.h"
#include "terms.h"
#include "util.h"

/* s^ of segment k of td at x (d components); 0 for a zero-length segment.  Returns |s_k| (m). */
static double unit_segment(const sw_tendon *td, const double *x, int d, int k, double *sh) {
  const double *a = x + (size_t)td->way[k] * d, *b = x + (size_t)td->way[k + 1] * d;
  double l = 0.0;
  for (int c = 0; c < d; c++) sh[c] = a[c] - b[c], l += sh[c] * sh[c];
  l = sqrt(l);
  for (int c = 0; c < d; c++) sh[c] = l > 0.0 ? sh[c] / l : 0.0;
  return l;
}

/* Column of tendon td: at each waypoint a that is a target, += s^_{a-1} - s^_a. */
static void tendon_column(const sw_tendon *td, const double *x, int d, const int *row_of,
                          double *col) {
  double sh[3];
  for (int k = 0; k + 1 < td->nway; k++) {
    unit_segment(td, x, d, k, sh);
    int ra = row_of[td->way[k]], rb = row_of[td->way[k + 1]];
    for (int c = 0; c < d; c++) {
      if (ra >= 0) col[ra * d + c] -= sh[c]; /* node w_k pulled towards w_{k+1} */
      if (rb >= 0) col[rb * d + c] += sh[c]; /* node w_{k+1} pulled towards w_k */
    }
  }
}

int sw_inverse_matrix(const sw_model *m, const double *x, const int *target, int nt, double *A) {
  const int d = m->dim;
  const size_t rows = (size_t)nt * d;
  int *row_of = sw_calloc((size_t)m->nv, sizeof(int));
  if (!row_of) return -1;
  for (int i = 0; i < m->nv; i++) row_of[i] = -1;
  for (int k = 0; k < nt; k++) row_of[target[k]] = k;
  memset(A, 0, rows * (size_t)m->ntendon * sizeof(double));
  for (int t = 0; t < m->ntendon; t++)
    if (m->tendon[t].stiffness > 0.0) tendon_column(&m->tendon[t], x, d, row_of, A + rows * t);
  sw_free(row_of);
  return 0;
}

static double norm2(const double *v, size_t n) {
  double s = 0.0;
  for (size_t i = 0; i < n; i++) s += v[i] * v[i];
  return sqrt(s);
}

void sw_inverse_free(sw_inverse *inv) {
  if (!inv) return;
  sw_free(inv->tau), sw_free(inv->length), sw_free(inv->rest);
  memset(inv, 0, sizeof *inv);
}

/* alpha_t = l_t - tau_t / K_t (tendon model §3.1); a tendon with K = 0 keeps its scene rest length. */
static void rest_lengths(const sw_model *m, const double *x, sw_inverse *inv) {
  for (int t = 0; t < m->ntendon; t++) {
    const sw_tendon *td = &m->tendon[t];
    inv->length[t] = sw_tendon_length(td, x, m->dim); /* m */
    inv->rest[t] = td->stiffness > 0.0 ? inv->length[t] - inv->tau[t] / td->stiffness
                                       : sw_tendon_rest(td, 0.0);
  }
}

int sw_inverse_solve(const sw_model *m, const double *x, const sw_targets *tg, sw_inverse *inv,
                     char *err, size_t errsz) {
  memset(inv, 0, sizeof *inv);
  const int nt = m->ntendon, rows = tg->n * m->dim;
  inv->ntendon = nt;
  inv->tau = sw_calloc((size_t)nt + 1, sizeof(double));
  inv->length = sw_calloc((size_t)nt + 1, sizeof(double));
  inv->rest = sw_calloc((size_t)nt + 1, sizeof(double));
  double *A = sw_calloc((size_t)rows * nt + 1, sizeof(double));
  double *r = sw_calloc((size_t)rows + 1, sizeof(double));
  int rc = SW_FATAL;
  if (!inv->tau || !inv->length || !inv->rest || !A || !r ||
      sw_inverse_matrix(m, x, tg->vertex, tg->n, A)) {
    sw_errf(err, errsz, "inverse: out of memory");
    goto done;
  }
  rc = sw_nnls(rows, nt, A, tg->f, inv->tau, 0.0, 0, &inv->iterations, err, errsz);
  if (rc) goto done;
  memcpy(r, tg->f, (size_t)rows * sizeof(double)); /* r = f - A tau, N */
  for (int t = 0; t < nt; t++)
    for (int i = 0; i < rows; i++) r[i] -= A[(size_t)t * rows + i] * inv->tau[t];
  inv->residual = norm2(r, (size_t)rows);
  inv->fnorm = norm2(tg->f, (size_t)rows);
  inv->reachable = inv->residual <= SW_INVERSE_RTOL * inv->fnorm;
  rest_lengths(m, x, inv);
done:
  sw_free(A);
  sw_free(r);
  if (rc) sw_inverse_free(inv);
  return rc;
}
