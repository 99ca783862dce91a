/* dihedral.c — discrete-shells bending (Grinspun, Hirani, Desbrun, Schröder 2003, "Discrete
 * shells") on the triangles of models/bending.c, 3D only.  docs/models.md "Bending".
 *
 * Each hinge a of a triangle T (x0, x1 on the edge in T's corner order, x2 T's own far vertex,
 * x3 the far vertex across) bends by theta_a - theta_rest_a, and T's energy is
 *   E_T = (1/2) sum_ab W_ab dth_a dth_b,   dth = wrap(theta - theta_rest)           (J)
 * with W (J/rad^2) from models/bending.c: the plate energy (k_b A/2)|II_T|^2 of T's constant
 * curvature II_T = sum_a c_a dth_a n_a n_a^T, or (A/2) II_T : D : II_T of an orthotropic plate
 * (warp, weft and bias rigidities; W stays constant, so the derivatives below are unchanged).  With face A = T every hinge of T measures its
 * angle against T's own normal, so the three angles have one sign convention.
 *
 * theta is the signed angle between the face normals NA = e x (x2 - x0), NB = (x3 - x0) x e,
 * theta = atan2((NB x NA).e/|e|, NA.NB) (the sign that makes the gradient below its
 * derivative), which needs no normalisation and is accurate near 0 and near +-pi;
 * theta - theta_rest is wrapped into [-pi, pi).  Its gradient is the classic one (Bridson,
 * Marino, Fedkiw 2003, sec. 4; Tamstorf & Grinspun 2013, "Discrete bending forces and their
 * Jacobians", sec. 3): with psi_F = N_F / |N_F|^2,
 *   dtheta/dx_i = sum_F alpha_{F,i} psi_F,
 *   alpha_A = ((x2-x1).e^, -(x2-x0).e^, |e|, 0),  alpha_B = ((x3-x1).e^, -(x3-x0).e^, 0, |e|).
 * Its exact Hessian is that gradient differentiated here by the product rule (Tamstorf &
 * Grinspun give an equivalent closed form; tests/test_bending.c checks it by differences):
 *   d2theta/dx_i dx_j = sum_F psi_F (grad_j alpha_{F,i})^T + alpha_{F,i} P_F J_{F,j},
 * P_F = (I - 2 n_F n_F^T)/|N_F|^2 (the derivative of N/|N|^2), J_{F,j} = dN_F/dx_j (a cross-
 * product matrix), and for alpha = s (x_k - x_l).e^: grad_k = s e^, grad_l = -s e^,
 * grad_1 += s q, grad_0 -= s q, q = (I - e^ e^T)(x_k - x_l)/|e|.
 * E_T's gradient is sum_a mu_a g_a (mu = W dth, g_a = dtheta_a/dx) and its Hessian
 * sum_ab W_ab g_a g_b^T + sum_a mu_a d2theta_a: indefinite where the second part dominates, so
 * the eigenvalue filter (SW_FILTER_*) acts on each triangle's block (at most 18 x 18, on the
 * 15 coordinates a translation leaves out): negative eigenvalues set to 0 (its PSD part) or
 * replaced by their absolute values. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

/* Collapsing faces.  theta's gradient grows as 1/area and its Hessian as 1/area^2 as a face
 * collapses: a hinge next to a crushed face has blocks of 1e18 N/m beside a mass term of a few
 * N/m, and both the round-off of the filtered block (1e-16 of its largest eigenvalue) and
 * Cholesky's own then make Newton's system indefinite to CHOLMOD (docs/models.md, "Collapsing
 * faces").  So a filtered block gets SHIFT times its Frobenius norm (between its largest
 * eigenvalue and sqrt(15) times it) on its diagonal: far above that round-off, and far below
 * anything that matters where the block is not huge. */
#define SHIFT 1e-10

typedef struct dihedral_param {
  int n;          /* triangles (stencils) */
  sw_bend_tri *tri; /* (n) hinges and weights */
  double *rest;   /* (n x 3) rest angle of each hinge, rad */
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
  sw_free(dp->tri);
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

/* Filter the eigenvalues of the symmetric block B (w x w, w = 3 nv <= 18) by `mode`: its PSD
 * part (the sum over positive eigenvalues) or V |Lambda| V^T; then SHIFT x the filtered
 * block's Frobenius norm on the diagonal.  The energy does not change when the nv vertices
 * move together, so B's translations are its null space and the filter acts on the 3 nv - 3
 * differences of their motions only (sw_contrast_reduce): an eigensystem of 15 x 15 instead of
 * 18 x 18, half its cost, and none at all for a block that a Cholesky factorisation proves
 * positive definite on those differences (sw_psd_project). */
static void project_psd(double *B, int nv, int mode) {
  double M[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
  const int w = 3 * nv, r = w - 3;
  sw_contrast_reduce(B, nv, M);
  if (sw_psd_project(M, r, mode)) return; /* not finite: keep it */
  sw_contrast_lift(M, nv, B);
  double top = 0.0;
  for (int i = 0; i < r * r; i++) top += M[i] * M[i];
  top = sqrt(top);
  for (int k = 0; k < w; k++) B[k * (w + 1)] += SHIFT * top;
}

/* Wrap an angle difference into [-pi, pi). */
static double wrap(double a) {
  const double pi = 3.14159265358979323846;
  return a - 2.0 * pi * floor((a + pi) / (2.0 * pi));
}

/* Hinge a of triangle stencil s: its 4 positions from x (nv x 3). */
static void gather(const sw_term *t, int s, const sw_bend_hinge *hg, const double *x, hinge *h) {
  const int *v = t->sidx + t->sptr[s];
  for (int i = 0; i < 4; i++) memcpy(h->x[i], x + 3 * (size_t)v[hg->v[i]], 3 * sizeof(double));
  hinge_setup(h);
}

/* The hinge vector u (12, on the hinge's stencil-local vertices pu) as a stencil vector U
 * (w = 3 nv). */
static void spread(const double *u, const int *pu, int w, double *U) {
  memset(U, 0, (size_t)w * sizeof(double));
  for (int i = 0; i < 12; i++) U[3 * pu[i / 3] + i % 3] = u[i];
}

/* Energy of triangle stencil s; its gradient and (filtered) Hessian block as ev asks. */
static double tri_eval(const sw_term *t, int s, const sw_eval *ev) {
  const dihedral_param *dp = t->param;
  const sw_bend_tri *tr = &dp->tri[s];
  const int nh = tr->nh, w = 3 * tr->nv;
  hinge h[3];
  double dth[3], mu[3] = {0}, g[3][12], e = 0.0;
  int ok = 1;
  for (int a = 0; a < nh; a++) {
    gather(t, s, &tr->h[a], ev->x, &h[a]);
    dth[a] = wrap(h[a].theta - dp->rest[3 * s + a]); /* rad */
    ok = ok && h[a].ok;
  }
  for (int a = 0; a < nh; a++) {
    for (int b = 0; b < nh; b++) mu[a] += tr->W[a][b] * dth[b]; /* J/rad */
    e += 0.5 * mu[a] * dth[a];
  }
  if (!ok && ev->hess && !ev->sink) /* a sink adds nothing for it */
    memset(ev->hess + t->hptr[s], 0, sizeof(double) * (size_t)sw_hess_size(w));
  if (!ok || (!ev->grad && !ev->hess)) return e;
  const int *v = t->sidx + t->sptr[s];
  for (int a = 0; a < nh; a++) theta_gradient(&h[a], g[a]);
  if (ev->grad)
    for (int a = 0; a < nh; a++)
      for (int i = 0; i < 12; i++) ev->grad[3 * v[tr->h[a].v[i / 3]] + i % 3] += mu[a] * g[a][i];
  if (!ev->hess) return e;
  /* B = G^T W G + sum_a mu_a d2theta_a, G's rows the hinges' gradients on the stencil */
  double B[18 * 18] = {0}, Ht[144], G[3][18], WG[3][18] = {{0}};
  for (int a = 0; a < nh; a++) spread(g[a], tr->h[a].v, w, G[a]);
  for (int a = 0; a < nh; a++)
    for (int b = 0; b < nh; b++)
      for (int c = 0; c < w; c++) WG[a][c] += tr->W[a][b] * G[b][c];
  for (int r = 0; r < w; r++)
    for (int c = 0; c < w; c++) {
      double sum = 0.0;
      for (int a = 0; a < nh; a++) sum += G[a][r] * WG[a][c];
      B[r * w + c] = sum;
    }
  for (int a = 0; a < nh; a++) {
    int at[12]; /* the hinge's coordinates among the stencil's */
    for (int i = 0; i < 12; i++) at[i] = 3 * tr->h[a].v[i / 3] + i % 3;
    theta_hessian(&h[a], Ht);
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) B[at[i] * w + at[j]] += mu[a] * Ht[i * 12 + j];
  }
  if (ev->project) project_psd(B, tr->nv, ev->project);
  double *blk = sw_ev_block(ev, t, s);
  sw_hess_set_full(blk, w, B); /* every block set: sets_blocks */
  sw_ev_block_done(ev, t, s, blk);
  return e;
}

static int dihedral_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  (void)m;
  const dihedral_param *dp = t->param;
  double total = 0.0;
  for (int s = 0; s < dp->n; s++) total += tri_eval(t, s, ev);
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static const sw_term_ops dihedral_ops = {
    .kind = "dihedral", .eval = dihedral_eval, .free_param = dihedral_free, .sets_blocks = 1,
    .sink_ok = 1};

int sw_dihedral_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  dihedral_param *dp = sw_calloc(1, sizeof *dp);
  t->ops = &dihedral_ops;
  t->param = dp;
  snprintf(t->name, sizeof t->name, "%s", "dihedral");
  if (!dp) return sw_errf(err, errsz, "out of memory"), -1;
  if (m->dim != 3)
    return sw_errf(err, errsz, "dihedral bending needs dimension 3: a %dD scene has no "
                   "out-of-plane bending (use bending model quadratic, or none)", m->dim), -1;
  dp->tri = sw_bend_tris(m, SW_BENDING_DIHEDRAL, &dp->n, err, errsz);
  if (!dp->tri) return -1;
  dp->rest = sw_calloc((size_t)dp->n + 1, 3 * sizeof(double));
  int rc = !dp->rest || sw_bend_alloc_stencils(t, dp->tri, dp->n, 3);
  if (rc) return sw_errf(err, errsz, "out of memory for %d bending triangles", dp->n), -1;
  for (int s = 0; s < dp->n; s++)
    for (int a = 0; a < dp->tri[s].nh; a++) {
      hinge h;
      gather(t, s, &dp->tri[s].h[a], m->x0, &h);
      dp->rest[3 * s + a] = dp->tri[s].rest_flat ? 0.0 : h.theta;
    }
  return 0;
}
