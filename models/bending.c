/* bending.c — the triangles of the bending terms (models/dihedral.c, quadratic_bending.c) and
 * their rest weights: a constant curvature per triangle from the bending of its three edges,
 * as in the constant-moment plate element of Morley (1968, "The constant-moment plate-bending
 * element") and the discrete shape operator of Grinspun, Gingold, Reisman and Zorin (2006,
 * "Computing discrete shape operators on general meshes").  docs/models.md "Bending" has the
 * derivation and the measurements.
 *
 * Triangle T (rest area A, corners p0 p1 p2), edge i opposite p_i with unit in-plane normal n_i:
 * an interior edge bent by theta_i (the angle between the normals of T and of the face across)
 * gives T the curvature tensor
 *   II_T = sum_i c_i theta_i n_i n_i^T,   c_i = 2 / (h_i + h'_i)               (1/m)
 * with h_i, h'_i the heights of T and of the face across over edge i (so c = 1/h = l/(2A) on a
 * regular mesh): the part of theta_i that T takes is h_i / (h_i + h'_i), the share that makes
 * the slope at the edge the one interpolated between the two triangles' centroids.  T's energy
 * is that of a plate of bending stiffness k_b and zero bending Poisson ratio,
 *   E_T = (k_b A / 2) |II_T|_F^2 = (1/2) sum_ij W_ij theta_i theta_j,
 *   W_ij = k_b A c_i c_j S_ij,  S = C condensed,  C_ij = (n_i . n_j)^2,
 * where "condensed" is the Schur complement that eliminates the (free) curvature of T's boundary
 * edges: the natural condition of a free edge, zero moment.  Keeping only the diagonal of W
 * (an energy per edge) is the discrete-shells energy; the off-diagonal terms are what make
 * II_T exact for every quadratic surface on a translation-invariant mesh, the diagonal alone
 * is exact only for cylinders about mesh lines.
 *
 * Anisotropic bending replaces k_b |II|^2 by II : D : II, D the orthotropic plate's rigidity in
 * the warp/weft frame (u,v) with no coupling of the two curvatures (zero bending Poisson ratio,
 * as above): in the basis (II_uu, II_vv, sqrt(2) II_uv), D = diag(D_u, D_v, 2 G), so
 *   C_ij = D_u nu_i^2 nu_j^2 + D_v nv_i^2 nv_j^2 + 4 G nu_i nv_i nu_j nv_j
 * (isotropic: D_u = D_v = 2 G = k_b, C = k_b (n_i . n_j)^2).  A narrow strip cut at angle t to
 * warp carries the moment M t t^T alone (free long edges) and reads the rigidity D(t),
 *   1 / D(t) = cos^4 t / D_u + sin^4 t / D_v + cos^2 t sin^2 t / G,
 * so D_u, D_v are the warp and weft strips' and the bias strip's D_45 gives
 *   1 / G = 4 / D_45 - 1 / D_u - 1 / D_v.
 *
 * The condensed curvature itself, II_T = sum_a M_a theta_a in (II_uu, II_vv, sqrt(2) II_uv)
 * with the free edges' curvature at its minimiser (so W = A M^T D M), is kept in sw_bend_tri.M
 * for the bending whose rigidity depends on the curvature (models/dde_bending.c). */
#include <math.h>
#include <string.h>

#include "terms.h"
#include "util.h"

int sw_face_corner(const sw_model *m, int f, int v) {
  for (int i = 0; i < 3; i++)
    if (m->face[3 * f + i] == v) return i;
  return -1;
}

/* Unit normal n (in f's (u,v)) and length (m) of the edge of face f opposite corner k. */
static double edge_normal(const sw_model *m, int f, int k, double n[2]) {
  const double *a = m->uv + 6 * f + 2 * ((k + 1) % 3), *b = m->uv + 6 * f + 2 * ((k + 2) % 3);
  double l = hypot(b[0] - a[0], b[1] - a[1]);
  n[0] = l > 0.0 ? (b[1] - a[1]) / l : 0.0;
  n[1] = l > 0.0 ? (a[0] - b[0]) / l : 0.0;
  return l;
}

int *sw_face_edges(const sw_model *m, const sw_topology *tp) {
  int *fe = sw_calloc(3 * (size_t)m->nf, sizeof(int));
  if (!fe) return NULL;
  for (size_t k = 0; k < 3 * (size_t)m->nf; k++) fe[k] = -1;
  for (int e = 0; e < tp->ne; e++)
    for (int s = 0; s < 2; s++) {
      int f = tp->ef[2 * e + s];
      if (f >= 0) fe[3 * f + sw_face_corner(m, f, tp->efar[2 * e + s])] = e;
    }
  return fe;
}

/* S = C_II - C_IB C_BB^-1 C_BI on the interior edges I (in[k] != 0) of a 3 x 3 C. */
static void condense(const double C[3][3], const int in[3], double S[3][3]) {
  int b[3], nb = 0;
  for (int k = 0; k < 3; k++)
    if (!in[k]) b[nb++] = k;
  double inv[2][2] = {{0}};
  if (nb == 1) inv[0][0] = 1.0 / C[b[0]][b[0]];
  if (nb == 2) {
    double det = C[b[0]][b[0]] * C[b[1]][b[1]] - C[b[0]][b[1]] * C[b[1]][b[0]];
    inv[0][0] = C[b[1]][b[1]] / det, inv[1][1] = C[b[0]][b[0]] / det;
    inv[0][1] = -C[b[0]][b[1]] / det, inv[1][0] = -C[b[1]][b[0]] / det;
  }
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      S[i][j] = in[i] && in[j] ? C[i][j] : 0.0;
      if (!in[i] || !in[j] || nb == 3) continue;
      for (int p = 0; p < nb; p++)
        for (int q = 0; q < nb; q++) S[i][j] -= C[i][b[p]] * inv[p][q] * C[b[q]][j];
    }
}

/* M[.][a] = c_k (N_k - N_B C_BB^-1 C_Bk) for hinge a on edge k, N_k = (n_u^2, n_v^2,
 * sqrt(2) n_u n_v) the curvature of edge k in the basis (II_uu, II_vv, sqrt(2) II_uv): the free
 * edges B take the curvature that minimises the energy (the condensation of condense), so
 * A M^T D M = W. */
static void curvature_map(const double n[3][2], const double C[3][3], const int in[3],
                          const double c[3], const sw_bend_tri *t, double M[3][3]) {
  int b[3], nb = 0;
  for (int k = 0; k < 3; k++)
    if (!in[k]) b[nb++] = k;
  double inv[2][2] = {{0}}, N[3][3];
  if (nb == 1) inv[0][0] = 1.0 / C[b[0]][b[0]];
  if (nb == 2) {
    double det = C[b[0]][b[0]] * C[b[1]][b[1]] - C[b[0]][b[1]] * C[b[1]][b[0]];
    inv[0][0] = C[b[1]][b[1]] / det, inv[1][1] = C[b[0]][b[0]] / det;
    inv[0][1] = -C[b[0]][b[1]] / det, inv[1][0] = -C[b[1]][b[0]] / det;
  }
  for (int k = 0; k < 3; k++) {
    N[k][0] = n[k][0] * n[k][0], N[k][1] = n[k][1] * n[k][1];
    N[k][2] = sqrt(2.0) * n[k][0] * n[k][1];
  }
  memset(M, 0, 9 * sizeof(double));
  for (int a = 0; a < t->nh; a++) {
    int k = t->h[a].k;
    for (int r = 0; r < 3; r++) {
      double v = N[k][r];
      for (int p = 0; p < nb && nb < 3; p++)
        for (int q = 0; q < nb; q++) v -= N[b[p]][r] * inv[p][q] * C[b[q]][k];
      M[r][a] = c[k] * v; /* 1/m */
    }
  }
}

void sw_plate_rigidity(const sw_material *mt, double D[3]) {
  if (!(mt->k_bend_u > 0.0)) {
    D[0] = D[1] = D[2] = mt->k_bend;
    return;
  }
  D[0] = mt->k_bend_u, D[1] = mt->k_bend_v;
  D[2] = 2.0 / (4.0 / mt->k_bend_bias - 1.0 / mt->k_bend_u - 1.0 / mt->k_bend_v);
}

/* Fill triangle f's hinges and weights; returns its number of hinges (0: no bending). */
static int make_tri(const sw_model *m, const sw_topology *tp, const int *fe, int f,
                    sw_bend_tri *t) {
  const sw_material *mt = &m->mat[m->face_mat[f]];
  double n[3][2], C[3][3], S[3][3], c[3] = {0}, D[3];
  int in[3] = {0};
  sw_plate_rigidity(mt, D);
  memset(t, 0, sizeof *t);
  t->face = f, t->kb = mt->k_bend, t->rest_flat = mt->bend_rest == SW_BEND_REST_FLAT;
  for (int i = 0; i < 3; i++) t->v[i] = m->face[3 * f + i];
  t->nv = 3;
  for (int k = 0; k < 3; k++) {
    double l = edge_normal(m, f, k, n[k]);
    int e = fe[3 * f + k];
    if (e < 0 || tp->ef[2 * e + 1] < 0 || l <= 0.0) continue;
    int side = tp->ef[2 * e] == f ? 1 : 0, g = tp->ef[2 * e + side]; /* the face across */
    double lg = sw_face_uv_distance(m, g, t->v[(k + 1) % 3], t->v[(k + 2) % 3]);
    if (lg <= 0.0 || m->area[g] <= 0.0 || m->area[f] <= 0.0) continue;
    sw_bend_hinge *h = &t->h[t->nh++];
    in[k] = 1;
    h->k = k, h->far_face = g;
    h->v[0] = (k + 1) % 3, h->v[1] = (k + 2) % 3, h->v[2] = k, h->v[3] = t->nv;
    t->v[t->nv++] = tp->efar[2 * e + side];
    h->len = 0.5 * (l + lg);
    c[k] = 2.0 / (2.0 * m->area[f] / l + 2.0 * m->area[g] / lg); /* 1/m */
  }
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      C[i][j] = D[0] * n[i][0] * n[i][0] * n[j][0] * n[j][0] +
                D[1] * n[i][1] * n[i][1] * n[j][1] * n[j][1] +
                2.0 * D[2] * n[i][0] * n[i][1] * n[j][0] * n[j][1]; /* N m */
    }
  condense(C, in, S);
  curvature_map(n, C, in, c, t, t->M);
  for (int a = 0; a < t->nh; a++)
    for (int b = 0; b < t->nh; b++) {
      int i = t->h[a].k, j = t->h[b].k;
      t->W[a][b] = m->area[f] * c[i] * c[j] * S[i][j]; /* J/rad^2 */
    }
  return t->nh;
}

sw_bend_tri *sw_bend_tris(const sw_model *m, int model, int *n, char *err, size_t errsz) {
  sw_topology tp;
  *n = 0;
  if (sw_topology_build(&tp, m, err, errsz)) return NULL;
  int *fe = sw_face_edges(m, &tp);
  sw_bend_tri *out = sw_calloc((size_t)m->nf + 1, sizeof *out);
  if (!fe || !out) {
    sw_free(fe), sw_free(out), sw_topology_free(&tp);
    return sw_errf(err, errsz, "out of memory for the bending of %d faces", m->nf), NULL;
  }
  for (int f = 0; f < m->nf; f++) {
    const sw_material *mt = &m->mat[m->face_mat[f]];
    if (mt->bending != model || !(mt->k_bend > 0.0 || mt->k_bend_u > 0.0)) continue;
    if (make_tri(m, &tp, fe, f, &out[*n]) > 0) (*n)++;
  }
  sw_free(fe);
  sw_topology_free(&tp);
  return out;
}

int sw_bend_alloc_stencils(sw_term *t, const sw_bend_tri *tri, int n, int dim) {
  t->nstencil = n;
  t->sptr = sw_calloc((size_t)n + 1, sizeof(int));
  t->hptr = sw_calloc((size_t)n + 1, sizeof(long));
  t->sidx = sw_calloc(6 * (size_t)n + 1, sizeof(int));
  if (!t->sptr || !t->sidx || !t->hptr) return -1;
  for (int s = 0; s < n; s++) {
    int w = tri[s].nv * dim;
    t->sptr[s + 1] = t->sptr[s] + tri[s].nv;
    t->hptr[s + 1] = t->hptr[s] + sw_hess_size(w);
    memcpy(t->sidx + t->sptr[s], tri[s].v, (size_t)tri[s].nv * sizeof(int));
  }
  return 0;
}
