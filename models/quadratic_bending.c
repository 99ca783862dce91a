/* quadratic_bending.c — isometric bending (Bergou, Wardetzky, Harmon, Zorin, Grinspun 2006,
 * "A quadratic bending model for inextensible surfaces"), on the triangles of models/bending.c;
 * 2D and 3D.
 *
 * Each hinge a of a triangle (x0, x1 on the edge, x2 the triangle's far vertex, x3 the one
 * across) measures its bending by Bergou's vector
 *   v_a = sum_i K_a,i x_i,   K_a = (c03 + c04, c01 + c02, -c01 - c03, -c02 - c04),
 * c01, c02 the cotangents of the rest angles at x0 in the two faces, c03, c04 those at x1, each
 * from its own face's (u,v) layout (so K is defined across a seam).  For a hinge bent
 * isometrically by theta, v_a = -|e| (m_A + m_B) (m_F the unit in-face normals of the edge),
 * of length 2 |e| sin(theta/2) ~ |e| theta, pointing along the surface normal: so v_a / |e_a|
 * stands for theta_a in the triangle energy of models/bending.c (isotropic or orthotropic:
 * only W depends on the rigidities),
 *   E_T = (1/2) sum_ab W_ab (v_a . v_b) / (|e_a| |e_b|)                         (J)
 * (|e| the rest edge length).  Quadratic in x: the gradient is Q x and the Hessian the
 * constant Q (x) I with Q = sum_ab W_ab K_a K_b^T / (|e_a| |e_b|) on the stencil, positive
 * semi-definite (W is), so both eigenvalue filters (SW_FILTER_*) leave it unchanged.  K
 * annihilates every affine map of the rest layout (rigid motions, uniform stretch).  The rest
 * state is always the flat (u,v) layout (bend_rest is not used).  In 2D there is no
 * out-of-plane bending: the term then only penalises the non-affine in-plane distortion of
 * neighbouring triangles, which is harmless and kept for scenes that share a material. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

typedef struct quadratic_param {
  int n;       /* triangles (stencils) */
  double *K;   /* (n x 3 x 6) K_a / |e_a| of each hinge on the stencil, 1/m */
  double *W;   /* (n x 9) the triangle's W (models/bending.c), J */
  double *Q;   /* (n x 36) Q of each stencil, nv x nv used, N/m */
  sw_compact cm; /* the compact Newton matrix (cm.C != NULL): the stencils are there */
} quadratic_param;

static void quadratic_free(void *p) {
  quadratic_param *qp = p;
  if (!qp) return;
  sw_free(qp->K);
  sw_free(qp->W);
  sw_free(qp->Q);
  sw_compact_free(&qp->cm);
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

/* Energy and gradient of stencil s from the hinge vectors v_a = sum_i K_a,i x_i / |e_a| (so
 * that both are exactly 0 where the v_a are, e.g. at a flat rest across a seam). */
static double tri_energy(const quadratic_param *qp, int s, const int *v, int nv, int d,
                         const sw_eval *ev) {
  const double *K = qp->K + 18 * s, *W = qp->W + 9 * s;
  double va[3][3] = {{0}}, mu[3][3] = {{0}}, e = 0.0; /* v_a (1), W v (J) */
  for (int a = 0; a < 3; a++)
    for (int i = 0; i < nv; i++)
      for (int c = 0; c < d; c++) va[a][c] += K[6 * a + i] * ev->x[(size_t)v[i] * d + c];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      for (int c = 0; c < d; c++) mu[a][c] += W[3 * a + b] * va[b][c];
  for (int a = 0; a < 3; a++)
    for (int c = 0; c < d; c++) e += 0.5 * mu[a][c] * va[a][c];
  if (ev->grad)
    for (int i = 0; i < nv; i++)
      for (int c = 0; c < d; c++)
        for (int a = 0; a < 3; a++) ev->grad[(size_t)v[i] * d + c] += K[6 * a + i] * mu[a][c];
  return e;
}

static int quadratic_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const quadratic_param *qp = t->param;
  const int d = m->dim, compact = qp->cm.C != NULL;
  const int *sptr = compact ? qp->cm.sptr : t->sptr, *sidx = compact ? qp->cm.sidx : t->sidx;
  double total = 0.0;
  if (ev->hess && compact) sw_compact_hess(t, m, &qp->cm, ev);
  for (int s = 0; s < qp->n; s++) {
    const int *v = sidx + sptr[s], nv = sptr[s + 1] - sptr[s], bw = nv * d;
    total += tri_energy(qp, s, v, nv, d, ev);
    if (!ev->hess || compact) continue;
    const double *Q = qp->Q + 36 * s;
    double *blk = sw_ev_block(ev, t, s);
    for (int i = 0; i < nv; i++)
      for (int j = 0; j < nv; j++)
        for (int a = 0; a < d; a++) sw_hess_add(blk, bw, i * d + a, j * d + a, Q[6 * i + j]);
    sw_ev_block_done(ev, t, s, blk);
  }
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static const sw_term_ops quadratic_ops = {
    .kind = "quadratic", .eval = quadratic_eval, .free_param = quadratic_free,
    .sink_ok = 1};

/* Bergou's K of hinge h of triangle tr, on the stencil's vertices (6). */
void sw_bend_hinge_K(const sw_model *m, const sw_bend_tri *tr, const sw_bend_hinge *h,
                     double *K) {
  const int x0 = tr->v[h->v[0]], x1 = tr->v[h->v[1]], x2 = tr->v[h->v[2]], x3 = tr->v[h->v[3]];
  const int fa = tr->face, fb = h->far_face;
  double c01 = rest_cot(m, fa, x0, x1, x2), c03 = rest_cot(m, fa, x1, x0, x2);
  double c02 = rest_cot(m, fb, x0, x1, x3), c04 = rest_cot(m, fb, x1, x0, x3);
  memset(K, 0, 6 * sizeof(double));
  K[h->v[0]] = c03 + c04;
  K[h->v[1]] = c01 + c02;
  K[h->v[2]] = -c01 - c03;
  K[h->v[3]] = -c02 - c04;
}

/* K_a / |e_a|, W and Q = sum_ab W_ab K_a K_b^T / (|e_a| |e_b|) of triangle tr. */
static void tri_setup(const sw_model *m, const sw_bend_tri *tr, double *K, double *W, double *Q) {
  memset(K, 0, 18 * sizeof(double));
  memset(W, 0, 9 * sizeof(double));
  memset(Q, 0, 36 * sizeof(double));
  for (int a = 0; a < tr->nh; a++) {
    sw_bend_hinge_K(m, tr, &tr->h[a], K + 6 * a);
    for (int i = 0; i < 6; i++) K[6 * a + i] /= tr->h[a].len;
  }
  for (int a = 0; a < tr->nh; a++)
    for (int b = 0; b < tr->nh; b++) {
      W[3 * a + b] = tr->W[a][b];
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) Q[6 * i + j] += tr->W[a][b] * K[6 * a + i] * K[6 * b + j];
    }
}

int sw_quadratic_bending_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  quadratic_param *qp = sw_calloc(1, sizeof *qp);
  t->ops = &quadratic_ops;
  t->param = qp;
  snprintf(t->name, sizeof t->name, "%s", "quadratic");
  if (!qp) return sw_errf(err, errsz, "out of memory"), -1;
  sw_bend_tri *tr = sw_bend_tris(m, SW_BENDING_QUADRATIC, &qp->n, err, errsz);
  if (!tr) return -1;
  qp->K = sw_calloc((size_t)qp->n + 1, 18 * sizeof(double));
  qp->W = sw_calloc((size_t)qp->n + 1, 9 * sizeof(double));
  qp->Q = sw_calloc((size_t)qp->n + 1, 36 * sizeof(double));
  int rc = !qp->K || !qp->W || !qp->Q || sw_bend_alloc_stencils(t, tr, qp->n, m->dim);
  if (rc) sw_errf(err, errsz, "out of memory for %d bending triangles", qp->n);
  for (int s = 0; !rc && s < qp->n; s++)
    tri_setup(m, &tr[s], qp->K + 18 * s, qp->W + 9 * s, qp->Q + 36 * s);
  sw_free(tr);
  if (rc) return -1;
  if (m->opt.bending_matrix == SW_BMATRIX_COMPACT && qp->n > 0)
    return sw_compact_stencils(t, m, qp->Q, 6, &qp->cm, err, errsz);
  return 0;
}
