/* quadratic_bending.c — isometric bending (Bergou, Wardetzky, Harmon, Zorin, Grinspun 2006,
 * "A quadratic bending model for inextensible surfaces", sec. 4, eqs. 7-8), 2D and 3D.
 *
 * Per interior edge e with vertices x0, x1 and far vertices x2 (face A), x3 (face B):
 *   K_e = (c03 + c04, c01 + c02, -c01 - c03, -c02 - c04),
 * c01, c02 the cotangents of the rest angles at x0 in A and in B, c03, c04 those at x1, each
 * from its own face's (u,v) layout (so K is defined across a seam), and
 *   E_e = k_b / (2 (A1 + A2)) |sum_i K_e,i x_i|^2                         (J)
 * k_b in N m, A1, A2 the rest (u,v) areas.  Bergou's Q_e = 3/(A1+A2) K K^T, so this is
 * E = sum_e (k_b/6) x^T Q_e x: the same constant 1/6 as the dihedral term (models/dihedral.c),
 * because for a hinge bent isometrically by theta, sum_i K_i x_i = -|e| (m_A + m_B) with m_F
 * the unit in-face normals of the edge, of length 2 |e| sin(theta/2) ~ |e| theta: both terms
 * have the same small-angle energy per edge and the same limit (k_b/2) int kappa^2 dA on a
 * cylinder.  The rest state is always the flat (u,v) layout (bend_rest is not used).
 * K annihilates every affine map of the rest layout (rigid motions, uniform stretch), so the
 * gradient is w K_i s (s = sum K_j x_j, w = k_b/(A1+A2)) and the Hessian block (i,j) is the
 * constant w K_i K_j I: positive semi-definite, so both eigenvalue filters (SW_FILTER_*) leave
 * it unchanged.  In 2D there is no out-of-plane bending: the term then only penalises the
 * non-affine in-plane distortion of each pair of triangles, which is harmless and kept for
 * scenes that share a material. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

typedef struct quadratic_param {
  int n;       /* edges (stencils) */
  double *K;   /* (n x 4) cotangent weights, 1 */
  double *w;   /* (n) k_b / (A1 + A2), N/m */
} quadratic_param;

static void quadratic_free(void *p) {
  quadratic_param *qp = p;
  if (!qp) return;
  sw_free(qp->K);
  sw_free(qp->w);
  sw_free(qp);
}

/* Cotangent of the rest angle at vertex p of face f, between the edges to q and r. */
static double rest_cot(const sw_model *m, int f, int p, int q, int r) {
  const double *uv = m->uv + 6 * f, *a = NULL, *b = NULL, *c = NULL;
  for (int i = 0; i < 3; i++) {
    int v = m->face[3 * f + i];
    if (v == p) a = uv + 2 * i;
    if (v == q) b = uv + 2 * i;
    if (v == r) c = uv + 2 * i;
  }
  double u[2] = {b[0] - a[0], b[1] - a[1]}, w[2] = {c[0] - a[0], c[1] - a[1]};
  double cr = fabs(u[0] * w[1] - u[1] * w[0]);
  return cr > 0.0 ? (u[0] * w[0] + u[1] * w[1]) / cr : 0.0;
}

static int quadratic_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const quadratic_param *qp = t->param;
  const int d = m->dim, bw = 4 * d;
  double total = 0.0;
  for (int s = 0; s < qp->n; s++) {
    const int *v = t->sidx + 4 * s;
    const double *K = qp->K + 4 * s, w = qp->w[s];
    double sum[3] = {0}; /* m */
    for (int i = 0; i < 4; i++)
      for (int a = 0; a < d; a++) sum[a] += K[i] * ev->x[(size_t)v[i] * d + a];
    for (int a = 0; a < d; a++) total += 0.5 * w * sum[a] * sum[a];
    if (ev->grad)
      for (int i = 0; i < 4; i++)
        for (int a = 0; a < d; a++) ev->grad[v[i] * d + a] += w * K[i] * sum[a];
    if (!ev->hess) continue;
    double *blk = ev->hess + t->hptr[s];
    for (int i = 0; i < 4; i++)
      for (int j = 0; j < 4; j++)
        for (int a = 0; a < d; a++) blk[(i * d + a) * bw + j * d + a] += w * K[i] * K[j];
  }
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static const sw_term_ops quadratic_ops = {
    .kind = "quadratic", .eval = quadratic_eval, .free_param = quadratic_free};

/* Bergou's K_e from the rest angles of the two faces (own (u,v) layouts). */
static void cot_weights(const sw_model *m, const sw_bend *b, double *K) {
  const int *v = b->v, *f = b->f;
  double c01 = rest_cot(m, f[0], v[0], v[1], v[2]), c03 = rest_cot(m, f[0], v[1], v[0], v[2]);
  double c02 = rest_cot(m, f[1], v[0], v[1], v[3]), c04 = rest_cot(m, f[1], v[1], v[0], v[3]);
  K[0] = c03 + c04;
  K[1] = c01 + c02;
  K[2] = -c01 - c03;
  K[3] = -c02 - c04;
}

int sw_quadratic_bending_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  quadratic_param *qp = sw_calloc(1, sizeof *qp);
  t->ops = &quadratic_ops;
  t->param = qp;
  snprintf(t->name, sizeof t->name, "%s", "quadratic");
  if (!qp) return sw_errf(err, errsz, "out of memory"), -1;
  sw_bend *be = sw_bend_edges(m, SW_BENDING_QUADRATIC, &qp->n, err, errsz);
  if (!be) return -1;
  qp->K = sw_calloc((size_t)qp->n, 4 * sizeof(double));
  qp->w = sw_calloc((size_t)qp->n, sizeof(double));
  int rc = !qp->K || !qp->w || sw_term_alloc_stencils(t, qp->n, 4, m->dim);
  if (rc) sw_errf(err, errsz, "out of memory for %d bending edges", qp->n);
  for (int s = 0; !rc && s < qp->n; s++) {
    memcpy(t->sidx + 4 * s, be[s].v, sizeof be[s].v);
    cot_weights(m, &be[s], qp->K + 4 * s);
    qp->w[s] = be[s].kb / (m->area[be[s].f[0]] + m->area[be[s].f[1]]); /* N/m */
  }
  sw_free(be);
  return rc ? -1 : 0;
}
