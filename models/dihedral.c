/* dihedral.c — discrete-shells bending (Grinspun, Hirani, Desbrun, Schröder 2003, "Discrete
 * shells", eq. 3), 3D only.  docs/models.md "dihedral" has the derivation of the constant.
 *
 * Per interior edge e with vertices x0, x1 (e = x1 - x0) and far vertices x2 (face A) and x3
 * (face B):
 *   E_e = k_b (theta_e - theta_rest)^2 |e_rest|^2 / (2 (A1 + A2))          (J)
 * k_b in N m, |e_rest| the edge's rest length (mean of its length in the two faces' (u,v)),
 * A1, A2 the faces' rest (u,v) areas.  In Grinspun's form k (theta - theta_rest)^2 |e|^2 / A_e
 * with A_e = (A1 + A2)/3 this is k = k_b / 6.  Why 1/6: on a grid of hx x hy cells (either
 * diagonal) bent into a cylinder of radius R about an axis along the grid, every triangle of a
 * cell column has the normal of the cylinder at the column's centre, so only the edges along
 * the axis bend, each by theta = hx/R; with |e| = hy and A1 + A2 = hx hy each such edge gives
 * theta^2 |e|^2 / A_e = 3 hx hy / R^2, i.e. sum_e theta^2 |e|^2 / A_e -> 3 Area / R^2, and
 * E -> (k_b/2) Area / R^2 = (k_b/2) int kappa^2 dA.  The error is the half cell at each end
 * of the bent direction, E = (k_b/2)(Area/R^2)(1 - hx/length): first order (tests/test_bending.c).
 * An equilateral mesh in either orientation gives the same limit 3 Area/R^2 (a numerical check;
 * there the chords also tilt the normals along the axis); on general meshes and surfaces the
 * discrete-shells energy is known to depend on the mesh.
 *
 * theta is the signed angle between the face normals NA = e x (x2 - x0), NB = (x3 - x0) x e,
 * theta = atan2((NB x NA).e/|e|, NA.NB) (the sign that makes the gradient below its
 * derivative), which needs no normalisation and is accurate near 0 and near +-pi;
 * theta - theta_rest is wrapped into [-pi, pi).  Its gradient is the classic one (Bridson, Marino, Fedkiw 2003, sec. 4; Tamstorf & Grinspun 2013, "Discrete bending forces
 * and their Jacobians", sec. 3): with psi_F = N_F / |N_F|^2,
 *   dtheta/dx_i = sum_F alpha_{F,i} psi_F,
 *   alpha_A = ((x2-x1).e^, -(x2-x0).e^, |e|, 0),  alpha_B = ((x3-x1).e^, -(x3-x0).e^, 0, |e|).
 * Its exact Hessian is that gradient differentiated here by the product rule (Tamstorf &
 * Grinspun give an equivalent closed form; tests/test_bending.c checks it by differences):
 *   d2theta/dx_i dx_j = sum_F psi_F (grad_j alpha_{F,i})^T + alpha_{F,i} P_F J_{F,j},
 * P_F = (I - 2 n_F n_F^T)/|N_F|^2 (the derivative of N/|N|^2), J_{F,j} = dN_F/dx_j (a cross-
 * product matrix), and for alpha = s (x_k - x_l).e^: grad_k = s e^, grad_l = -s e^,
 * grad_1 += s q, grad_0 -= s q, q = (I - e^ e^T)(x_k - x_l)/|e|.
 * E's Hessian is 2w (g g^T + (theta - theta_rest) d2theta), w = k_b |e_rest|^2/(2(A1+A2)); it is
 * indefinite where the second part dominates, and the eigenvalue filter (SW_FILTER_*) acts on
 * each 12 x 12 block (LAPACK dsyev): negative eigenvalues set to 0 (its PSD part) or replaced
 * by their absolute values. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

/* Collapsing faces.  theta's gradient grows as 1/area and its Hessian as 1/area^2 as a face
 * collapses: a hinge next to a crushed face has blocks of 1e18 N/m beside a mass term of a few
 * N/m, and both the round-off of the filtered block (1e-16 of its largest eigenvalue) and
 * Cholesky's own then make Newton's system indefinite to CHOLMOD (docs/models.md, "Collapsing
 * faces").  So a filtered block gets SHIFT times its largest eigenvalue on its diagonal: far
 * above that round-off, and far below anything that matters where the block is not huge. */
#define SHIFT 1e-10

typedef struct dihedral_param {
  int n;          /* edges (stencils) */
  double *w;      /* (n) k_b |e_rest|^2 / (2 (A1 + A2)), J/rad^2 */
  double *rest;   /* (n) rest angle, rad */
} dihedral_param;

typedef struct hinge {
  double x[4][3];        /* x0, x1 (edge), x2 (far in A), x3 (far in B), m */
  double eh[3], L;       /* unit edge direction and |e| (m) */
  double psi[2][3];      /* N_F / |N_F|^2, 1/m^2 */
  double P[2][9];        /* (I - 2 n n^T)/|N_F|^2, 1/m^4 */
  double theta;          /* rad */
  int ok;                /* both faces and the edge have non-zero size */
} hinge;

/* alpha_{F,i} = s (x_k - x_l).e^ as {k, l, s}; s = 0: alpha = 0. */
static const int ALPHA[2][4][3] = {{{2, 1, 1}, {2, 0, -1}, {1, 0, 1}, {0, 0, 0}},
                                   {{3, 1, 1}, {3, 0, -1}, {0, 0, 0}, {1, 0, 1}}};
/* dN_F/dx_j = [x_p - x_q]x as {p, q}; p == q: 0. */
static const int JAC[2][4][2] = {{{2, 1}, {0, 2}, {1, 0}, {0, 0}},
                                 {{1, 3}, {3, 0}, {0, 0}, {0, 1}}};

static void dihedral_free(void *p) {
  dihedral_param *dp = p;
  if (!dp) return;
  sw_free(dp->w);
  sw_free(dp->rest);
  sw_free(dp);
}

static void sub(const double *a, const double *b, double *c) {
  for (int i = 0; i < 3; i++) c[i] = a[i] - b[i];
}
static void cross(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The hinge's angle and the quantities its derivatives need, from the 4 positions in h->x. */
static void hinge_setup(hinge *h) {
  double e[3], a[3], b[3], N[2][3], c[3];
  sub(h->x[1], h->x[0], e);
  sub(h->x[2], h->x[0], a);
  sub(h->x[3], h->x[0], b);
  cross(e, a, N[0]);
  cross(b, e, N[1]);
  h->L = sqrt(dot(e, e));
  cross(N[1], N[0], c);
  h->theta = atan2(h->L > 0.0 ? dot(c, e) / h->L : 0.0, dot(N[0], N[1]));
  double n2[2] = {dot(N[0], N[0]), dot(N[1], N[1])};
  h->ok = h->L > 0.0 && n2[0] > 0.0 && n2[1] > 0.0;
  if (!h->ok) return;
  for (int k = 0; k < 3; k++) h->eh[k] = e[k] / h->L;
  for (int F = 0; F < 2; F++)
    for (int r = 0; r < 3; r++) {
      h->psi[F][r] = N[F][r] / n2[F];
      for (int s = 0; s < 3; s++)
        h->P[F][3 * r + s] = ((r == s) - 2.0 * N[F][r] * N[F][s] / n2[F]) / n2[F];
    }
}

static double alpha(const hinge *h, const int *t) {
  if (!t[2]) return 0.0;
  double v[3];
  sub(h->x[t[0]], h->x[t[1]], v);
  return t[2] * dot(v, h->eh);
}

/* dtheta/dx (12). */
static void theta_gradient(const hinge *h, double *g) {
  memset(g, 0, 12 * sizeof(double));
  for (int F = 0; F < 2; F++)
    for (int i = 0; i < 4; i++) {
      double al = alpha(h, ALPHA[F][i]);
      for (int r = 0; r < 3; r++) g[3 * i + r] += al * h->psi[F][r];
    }
}

/* The gradient of alpha = s (x_k - x_l).e^ with respect to each vertex: ga (4 x 3). */
static void alpha_gradient(const hinge *h, const int *t, double ga[4][3]) {
  memset(ga, 0, 12 * sizeof(double));
  if (!t[2]) return;
  double v[3], s = t[2];
  sub(h->x[t[0]], h->x[t[1]], v);
  double ve = dot(v, h->eh);
  for (int r = 0; r < 3; r++) {
    double q = (v[r] - ve * h->eh[r]) / h->L;
    ga[t[0]][r] += s * h->eh[r];
    ga[t[1]][r] -= s * h->eh[r];
    ga[1][r] += s * q;
    ga[0][r] -= s * q;
  }
}

/* M = P [v]x (3 x 3): column c of [v]x is v x e_c. */
static void times_cross(const double *P, const double *v, double *M) {
  const double X[9] = {0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0};
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      M[3 * r + c] = P[3 * r] * X[c] + P[3 * r + 1] * X[3 + c] + P[3 * r + 2] * X[6 + c];
}

/* d2theta/dx2 (12 x 12, row-major), symmetrised. */
static void theta_hessian(const hinge *h, double *Ht) {
  memset(Ht, 0, 144 * sizeof(double));
  for (int F = 0; F < 2; F++)
    for (int i = 0; i < 4; i++) {
      double ga[4][3], al = alpha(h, ALPHA[F][i]);
      alpha_gradient(h, ALPHA[F][i], ga);
      for (int j = 0; j < 4; j++) {
        double M[9] = {0}, v[3];
        const int *p = JAC[F][j];
        if (p[0] != p[1]) sub(h->x[p[0]], h->x[p[1]], v), times_cross(h->P[F], v, M);
        for (int r = 0; r < 3; r++)
          for (int c = 0; c < 3; c++)
            Ht[(3 * i + r) * 12 + 3 * j + c] += h->psi[F][r] * ga[j][c] + al * M[3 * r + c];
      }
    }
  for (int r = 0; r < 12; r++)
    for (int c = 0; c < r; c++) {
      double s = 0.5 * (Ht[r * 12 + c] + Ht[c * 12 + r]);
      Ht[r * 12 + c] = Ht[c * 12 + r] = s;
    }
}

/* Filter the eigenvalues of the symmetric 12 x 12 block B by `mode`: its PSD part (the sum over
 * positive eigenvalues) or V |Lambda| V^T; then SHIFT x its largest eigenvalue on the diagonal. */
static void project_psd(double *B, int mode) {
  const int n = 12, lwork = 12 * 34;
  double A[144], lam[12], work[12 * 34];
  int info = 0;
  memcpy(A, B, sizeof A);
  dsyev_("V", "U", &n, A, &n, lam, work, &lwork, &info);
  if (info != 0) return; /* LAPACK failed: keep it */
  double top = fmax(sw_filter_eigenvalue(lam[0], mode), lam[n - 1]);
  if (lam[0] >= 0.0) { /* already PSD */
    for (int k = 0; k < n; k++) B[k * 13] += SHIFT * top;
    return;
  }
  memset(B, 0, sizeof A);
  for (int k = 0; k < n; k++) B[k * 13] = SHIFT * top;
  for (int k = 0; k < n; k++) {
    double l = sw_filter_eigenvalue(lam[k], mode);
    if (l <= 0.0) continue;
    const double *v = A + k * n; /* column k (symmetric, so row/column order is moot) */
    for (int r = 0; r < n; r++)
      for (int c = 0; c < n; c++) B[r * n + c] += l * v[r] * v[c];
  }
}

/* Wrap an angle difference into [-pi, pi). */
static double wrap(double a) {
  const double pi = 3.14159265358979323846;
  return a - 2.0 * pi * floor((a + pi) / (2.0 * pi));
}

/* The 4 positions of stencil s from x (nv x 3). */
static void gather(const sw_term *t, int s, const double *x, hinge *h) {
  for (int i = 0; i < 4; i++)
    memcpy(h->x[i], x + 3 * (size_t)t->sidx[4 * s + i], 3 * sizeof(double));
  hinge_setup(h);
}

static double edge_eval(const sw_term *t, int s, const sw_eval *ev) {
  const dihedral_param *dp = t->param;
  hinge h;
  gather(t, s, ev->x, &h);
  double dth = wrap(h.theta - dp->rest[s]), w = dp->w[s]; /* rad, J/rad^2 */
  if (!h.ok || (!ev->grad && !ev->hess)) return w * dth * dth;
  double g[12];
  theta_gradient(&h, g);
  if (ev->grad)
    for (int i = 0; i < 4; i++)
      for (int r = 0; r < 3; r++)
        ev->grad[3 * t->sidx[4 * s + i] + r] += 2.0 * w * dth * g[3 * i + r];
  if (ev->hess) {
    double Ht[144];
    theta_hessian(&h, Ht);
    for (int r = 0; r < 12; r++)
      for (int c = 0; c < 12; c++) Ht[r * 12 + c] = 2.0 * w * (g[r] * g[c] + dth * Ht[r * 12 + c]);
    if (ev->project && dth != 0.0) {
      project_psd(Ht, ev->project);
    } else if (ev->project) { /* dth = 0: 2w g g^T, PSD, its eigenvalue 2w |g|^2 */
      double gg = 0.0;
      for (int k = 0; k < 12; k++) gg += g[k] * g[k];
      for (int k = 0; k < 12; k++) Ht[k * 13] += SHIFT * 2.0 * w * gg;
    }
    double *blk = ev->hess + t->hptr[s];
    for (int k = 0; k < 144; k++) blk[k] += Ht[k];
  }
  return w * dth * dth;
}

static int dihedral_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  (void)m;
  const dihedral_param *dp = t->param;
  double total = 0.0;
  for (int s = 0; s < dp->n; s++) total += edge_eval(t, s, ev);
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static const sw_term_ops dihedral_ops = {
    .kind = "dihedral", .eval = dihedral_eval, .free_param = dihedral_free};

int sw_dihedral_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  dihedral_param *dp = sw_calloc(1, sizeof *dp);
  t->ops = &dihedral_ops;
  t->param = dp;
  snprintf(t->name, sizeof t->name, "%s", "dihedral");
  if (!dp) return sw_errf(err, errsz, "out of memory"), -1;
  if (m->dim != 3)
    return sw_errf(err, errsz, "dihedral bending needs dimension 3: a %dD scene has no "
                   "out-of-plane bending (use bending model quadratic, or none)", m->dim), -1;
  sw_bend *be = sw_bend_edges(m, SW_BENDING_DIHEDRAL, &dp->n, err, errsz);
  if (!be) return -1;
  dp->w = sw_calloc((size_t)dp->n, sizeof(double));
  dp->rest = sw_calloc((size_t)dp->n, sizeof(double));
  int rc = !dp->w || !dp->rest || sw_term_alloc_stencils(t, dp->n, 4, 3);
  if (rc) sw_errf(err, errsz, "out of memory for %d bending edges", dp->n);
  for (int s = 0; !rc && s < dp->n; s++) {
    memcpy(t->sidx + 4 * s, be[s].v, sizeof be[s].v);
    dp->w[s] = be[s].kb * be[s].len * be[s].len /
               (2.0 * (m->area[be[s].f[0]] + m->area[be[s].f[1]])); /* J/rad^2 */
    hinge h;
    gather(t, s, m->x0, &h);
    dp->rest[s] = be[s].rest_flat ? 0.0 : h.theta;
  }
  sw_free(be);
  return rc ? -1 : 0;
}
