/* dde_bending.c — the bending of a measured fabric whose rigidity depends on the curvature, as
 * the data of Wang, Ramamoorthi and O'Brien ("Data-Driven Elastic Models for Cloth: Modeling and
 * Measurement", SIGGRAPH 2011) gives it, on the triangles of models/bending.c with the hinge
 * vectors of the quadratic model (models/quadratic_bending.c); 2D and 3D.  docs/fabrics.md
 * "Bending by the data".
 *
 * The data.  Each row of the file's "bending" is a hinge direction (0, 45, 90 degrees from
 * warp), each column a curvature (0, 10, 20, 30, 40 1/m), each number four times a strip's
 * rigidity (models/dde.c): a strip cut along warp reads the 90 degree row, along weft the 0
 * degree row, at 45 degrees the 45 degree row.  At each column k the three strips give the
 * orthotropic plate of docs/models.md ("Anisotropic bending"), D = diag(D_u, D_v, 2 G) in the
 * basis (II_uu, II_vv, sqrt(2) II_uv), with D_u, D_v the warp and weft strips' rigidities and
 *   1 / G = 4 / D_45 - 1 / D_u - 1 / D_v
 * (a narrow free strip at 45 degrees then reads D_45).  Each of the three D_c (c = u, v, twist
 * 2 G) is a monotone cubic Hermite curve of the curvature r through its five samples
 * (Fritsch and Carlson, "Monotone piecewise cubic interpolation", 1980: the slopes at the inner
 * samples the harmonic mean of the neighbouring secants, 0 where they differ in sign, and 0 at
 * r = 0 and r = 40 1/m), and the 40 1/m value is held beyond: C1, positive, and between two
 * samples never beyond them.  (Linear interpolation between the columns, as ARCSim reads them,
 * has kinks that put jumps into the energy's second derivative.)
 *
 * The energy.  ARCSim applies at each hinge a force with the stiffness read at the current
 * curvature, not differentiated: a moment M(kappa) = D(kappa) kappa.  The potential with
 * exactly that moment is Phi(kappa) = int_0^kappa D(k) k dk per area, and a plate needs it for
 * every curvature tensor II, not only for one direction.  sinew reads the three rigidities at
 * the curvature's magnitude r = |II| = sqrt(kappa_1^2 + kappa_2^2) and integrates along the ray
 * from the flat state: with X_c the components of II in the basis above,
 *   psi(II) = sum_c (X_c^2 / r^2) Phi_c(r)                                        (J/m^2)
 * i.e. the plate (1/2) II : D : II with D read at r where D is constant, and on every ray
 * II = t II^ the radial moment dpsi/dt = (II^ : D(r) : II^) r, the moment law the data states.
 * A cylinder of curvature kappa about any axis (r = kappa) stores
 *   psi = cos^4 a Phi_u(kappa) + sin^4 a Phi_v(kappa) + 4 cos^2 a sin^2 a Phi_G(kappa),
 * a its bending direction from warp, Phi_G = int G k dk: along warp Phi_u, along weft Phi_v, and
 * a strip cut along warp or weft (its moment across zero) has exactly M = D_u(kappa) kappa,
 * D_v(kappa) kappa.  The 45 degree strip reads D_45 at small curvature; beyond, it reads the
 * rigidities at |II|, about 1.1 times its curvature for gray-interlock (its bend-twist
 * coupling makes II not a multiple of t t^T).  Where the moment falls as the curvature grows
 * (dD/dr r < -D: in 9 of the 10 fabrics, all but royal-target, somewhere between 29 and 40 1/m
 * for D_u and D_v, and for some twist curves from 5 or 12 1/m), psi is not convex in the
 * curvature: the Hessian filter keeps Newton's matrix positive semi-definite, and a strip bent
 * there may localise its bend (a softening moment law does so in any model).
 *
 * The discretisation.  II_T of triangle T is that of models/bending.c, its free edges'
 * curvature condensed with the zero-curvature rigidities (the matrix M of sw_bend_tri), and
 * each hinge's bending theta_a is Bergou's v_a / |e_a| (models/quadratic_bending.c): so
 * X = sum_v L_v x_v, L = M K / |e|, is a 3 x d array linear in the positions, and
 * E_T = A psi(X) with s_c = X_c . X_c, q = sum_c s_c = r^2, h_c(q) = Phi_c(r) / q:
 *   psi = sum_c s_c h_c(q),   dpsi/dX_c = 2 F_c X_c,
 *   d2psi/dX_c dX_e = 2 F_c delta_ce I + 4 F_ce X_c X_e^T,
 *   F_c = h_c + sum_k s_k h_k',   F_ce = h_c' + h_e' + sum_k s_k h_k''
 * (h' = dh/dq).  At small curvature E_T is exactly the quadratic model's (W = A M^T D M), and
 * its Hessian there the quadratic's.  The Hessian is A L^T H L, H = d2psi/dX2 (3d x 3d), whose
 * eigen-system is known in closed form (hessian() below: 2 F_c on the directions perpendicular
 * to each X_c, and a 3 x 3 on the span of the X_c): H is PSD when every F_c >= 0 and (F_ce) is;
 * otherwise its eigenvalues are filtered as ev->project asks before it is mapped, so the
 * stencil's block is PSD, and |A L^T H L| = 2 (.)_+ - (.).
 * The free edges are condensed with D at zero curvature, which is exact for free edges along
 * warp or weft (the condensation then only removes the curvature across them) and at small
 * curvature, and an approximation of the zero moment across other free edges when the data's
 * rigidities change their ratios with the curvature.  Rest state: the flat (u,v) layout. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "dde.h"
#include "terms.h"
#include "util.h"

#define SPACING 10.0 /* 1/m between the data's columns */

/* ------------------------------------------------------------------ the law */

/* Monotone cubic Hermite through y[0..4] at 0, 10, ..., 40 (slopes 0 at both ends), held
 * beyond: a[j][n] the coefficients of segment j in t = r - 10 j. */
static void hermite(const double y[5], double a[5][4]) {
  double m[5] = {0}, del[4];
  for (int k = 0; k < 4; k++) del[k] = (y[k + 1] - y[k]) / SPACING;
  for (int k = 1; k < 4; k++)
    m[k] = del[k - 1] * del[k] > 0.0 ? 2.0 * del[k - 1] * del[k] / (del[k - 1] + del[k]) : 0.0;
  for (int j = 0; j < 4; j++) {
    a[j][0] = y[j], a[j][1] = m[j];
    a[j][2] = (3.0 * del[j] - 2.0 * m[j] - m[j + 1]) / SPACING;
    a[j][3] = (m[j] + m[j + 1] - 2.0 * del[j]) / (SPACING * SPACING);
  }
  a[4][0] = y[4], a[4][1] = a[4][2] = a[4][3] = 0.0;
}

int sw_dde_bend_setup(const sw_dde *dd, sw_dde_bend *b, char *err, size_t errsz) {
  static const char *const row[3] = {"0", "45", "90"};
  double y[3][5];
  memset(b, 0, sizeof *b);
  for (int k = 0; k < 5; k++) {
    for (int i = 0; i < 3; i++)
      if (!(dd->bend[i][k] > 0.0))
        return sw_errf(err, errsz, "the %s degree bending row is %g at %g 1/m; expected "
                       "positive rigidities for the curvature-dependent bending", row[i],
                       dd->bend[i][k], SPACING * k), -1;
    double Du = 0.25 * dd->bend[2][k], Dv = 0.25 * dd->bend[0][k], Db = 0.25 * dd->bend[1][k];
    double ig = 4.0 / Db - 1.0 / Du - 1.0 / Dv; /* 1/G, 1/(N m) */
    if (!(ig > 0.0))
      return sw_errf(err, errsz, "at %g 1/m the 45 degree bending rigidity %g N m is not below "
                     "4/(1/warp + 1/weft) = %g N m, so no positive twisting rigidity fits the "
                     "three strips", SPACING * k, Db, 4.0 / (1.0 / Du + 1.0 / Dv)), -1;
    y[0][k] = Du, y[1][k] = Dv, y[2][k] = 2.0 / ig; /* N m */
  }
  for (int c = 0; c < 3; c++) {
    hermite(y[c], b->a[c]);
    double phi = 0.0; /* Phi_c at the segment's start, J/m^2 */
    for (int j = 0; j < 5; j++) {
      const double kj = SPACING * j, *a = b->a[c][j];
      double *p = b->p[c][j], tn = 1.0;
      p[0] = phi; /* + int_0^t (a0 + a1 t + a2 t^2 + a3 t^3)(kj + t) dt */
      for (int n = 1; n <= 5; n++)
        p[n] = ((n <= 4 ? kj * a[n - 1] : 0.0) + (n >= 2 ? a[n - 2] : 0.0)) / n;
      for (int n = 1; n <= 5; n++) tn *= SPACING, phi += p[n] * tn;
    }
  }
  return 0;
}

void sw_dde_bend_curve(const sw_dde_bend *b, int c, double r, double *D, double *dD,
                       double *Phi) {
  r = fabs(r);
  int j = r >= 4.0 * SPACING ? 4 : (int)(r / SPACING);
  const double t = r - SPACING * j, *a = b->a[c][j], *p = b->p[c][j];
  *D = a[0] + t * (a[1] + t * (a[2] + t * a[3]));
  *dD = a[1] + t * (2.0 * a[2] + t * 3.0 * a[3]);
  *Phi = p[0] + t * (p[1] + t * (p[2] + t * (p[3] + t * (p[4] + t * p[5]))));
}

/* h = Phi(r)/q and its first two derivatives in q = r^2.  On the first segment Phi =
 * p2 r^2 + p4 r^4 + p5 r^5 (its p1 = 0 and p3 = D'(0)/3 = 0), so h = p2 + p4 q + p5 q^(3/2)
 * with no cancellation at small r; h'' ~ 1/r there, but enters only as s_k h'' <= q h''. */
static void curve_h(const sw_dde_bend *b, int c, double q, double r, double h[3]) {
  if (r < SPACING) {
    const double *p = b->p[c][0];
    h[0] = p[2] + q * (p[4] + r * p[5]);
    h[1] = p[4] + 1.5 * p[5] * r;
    h[2] = r > 0.0 ? 0.75 * p[5] / r : 0.0;
    return;
  }
  double D, dD, Phi;
  sw_dde_bend_curve(b, c, r, &D, &dD, &Phi);
  double N = D * q - 2.0 * Phi; /* J/m^2 */
  h[0] = Phi / q;
  h[1] = N / (2.0 * q * q);
  h[2] = dD / (4.0 * q * r) - N / (q * q * q);
}

/* H = d2psi/dX2 (n = 3d square) from F, F_ce and X, its eigenvalues filtered by `mode`.  H acts
 * on z = (z_c) as (H z)_c = 2 F_c z_c + 4 X_c sum_e F_ce X_e . z_e, so its eigen-system is known:
 * each z_c perpendicular to X_c is an eigenvector of eigenvalue 2 F_c (d - 1 of them per c),
 * and on the span of the Xh_c (x) e_c (Xh = X/|X|) H is the 3 x 3
 *   S = 2 diag(F) + 4 diag(|X|) F_ce diag(|X|).
 * So the filtered H = sum_c f(2 F_c) (I - Xh_c Xh_c^T) (x) e_c e_c^T + Yh f(S) Yh^T, Yh =
 * blockdiag(Xh_c), f(S) by sw_psd_project (mode NONE: the exact H).  A zero X_c has Xh_c = 0:
 * its block is f(2 F_c) I.  -1 when S is not finite. */
static int hessian(const double F[3], const double Fe[3][3], const double *X, int d, int mode,
                   double *H) {
  const int n = 3 * d;
  double nx[3], Xh[9], S[9], f[3];
  for (int c = 0; c < 3; c++) {
    double s = 0.0;
    for (int a = 0; a < d; a++) s += X[c * d + a] * X[c * d + a];
    nx[c] = sqrt(s);
    for (int a = 0; a < d; a++) Xh[c * d + a] = nx[c] > 0.0 ? X[c * d + a] / nx[c] : 0.0;
    f[c] = sw_filter_eigenvalue(2.0 * F[c], mode);
  }
  for (int c = 0; c < 3; c++)
    for (int e = 0; e < 3; e++)
      S[3 * c + e] = 4.0 * nx[c] * Fe[c][e] * nx[e] + (c == e ? 2.0 * F[c] : 0.0);
  if (mode != SW_FILTER_NONE && sw_psd_project(S, 3, mode)) return -1;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      const int c = i / d, e = j / d;
      double v = S[3 * c + e] * Xh[i] * Xh[j];
      if (c == e) v += f[c] * ((i == j) - Xh[i] * Xh[j]);
      H[i * n + j] = v;
    }
  return 0;
}

/* psi, g and H (when not NULL; its eigenvalues filtered by `mode`) of sw_dde_bend_density.
 * H = 2 diag(F) (x) I + 4 Yh S' Yh^T is PSD, and no filter is needed, when every F_c >= 0 and
 * (F_ce) is PSD (its principal minors >= 0).  NaN when H is not finite. */
static double density(const sw_dde_bend *b, const double *X, int d, double *g, double *H,
                      int mode) {
  double s[3], q = 0.0, h[3][3], F[3], Fe[3][3], psi = 0.0, sh2 = 0.0;
  for (int c = 0; c < 3; c++) {
    s[c] = 0.0;
    for (int a = 0; a < d; a++) s[c] += X[c * d + a] * X[c * d + a];
    q += s[c];
  }
  const double r = sqrt(q);
  for (int c = 0; c < 3; c++) curve_h(b, c, q, r, h[c]);
  const double sh1 = s[0] * h[0][1] + s[1] * h[1][1] + s[2] * h[2][1];
  for (int c = 0; c < 3; c++) psi += s[c] * h[c][0], sh2 += s[c] * h[c][2];
  for (int c = 0; c < 3; c++) {
    F[c] = h[c][0] + sh1;
    for (int a = 0; a < d; a++) g[c * d + a] = 2.0 * F[c] * X[c * d + a];
  }
  if (!H) return psi;
  for (int c = 0; c < 3; c++)
    for (int e = 0; e < 3; e++) Fe[c][e] = h[c][1] + h[e][1] + sh2;
  double m2[3] = {Fe[0][0] * Fe[1][1] - Fe[0][1] * Fe[0][1],
                  Fe[0][0] * Fe[2][2] - Fe[0][2] * Fe[0][2],
                  Fe[1][1] * Fe[2][2] - Fe[1][2] * Fe[1][2]};
  double m3 = Fe[0][0] * m2[2] - Fe[0][1] * (Fe[0][1] * Fe[2][2] - Fe[1][2] * Fe[0][2]) +
              Fe[0][2] * (Fe[0][1] * Fe[1][2] - Fe[1][1] * Fe[0][2]);
  int psd = F[0] >= 0.0 && F[1] >= 0.0 && F[2] >= 0.0 && Fe[0][0] >= 0.0 && Fe[1][1] >= 0.0 &&
            Fe[2][2] >= 0.0 && m2[0] >= 0.0 && m2[1] >= 0.0 && m2[2] >= 0.0 && m3 >= 0.0;
  if (hessian(F, Fe, X, d, psd ? SW_FILTER_NONE : mode, H)) return NAN;
  return psi;
}

double sw_dde_bend_density(const sw_dde_bend *b, const double *X, int d, double *g, double *H) {
  return density(b, X, d, g, H, SW_FILTER_NONE);
}

/* ------------------------------------------------------------------ the term */

typedef struct dde_bending_param {
  int n;              /* triangles (stencils) */
  double *L;          /* (n x 3 x 6) X_c = sum_i L[c][i] x_i, 1/m^2 */
  double *A;          /* (n) rest area, m^2 */
  int *mat;           /* (n) the face's material */
  int *face;          /* (n) the face */
  sw_dde_bend *law;   /* (nmat) the curves of each material that bends with dde */
} dde_bending_param;

static void dde_bending_free(void *p) {
  dde_bending_param *bp = p;
  if (!bp) return;
  sw_free(bp->L), sw_free(bp->A), sw_free(bp->mat), sw_free(bp->face), sw_free(bp->law);
  sw_free(bp);
}

static int dde_bending_eval(const sw_term *t, const sw_model *m, const sw_eval *ev,
                            double *energy) {
  const dde_bending_param *bp = t->param;
  const int d = m->dim, n9 = 3 * d;
  double total = 0.0;
  for (int s = 0; s < bp->n; s++) {
    const int *v = t->sidx + t->sptr[s], nv = t->sptr[s + 1] - t->sptr[s], w = nv * d;
    const double *L = bp->L + 18 * s, A = bp->A[s];
    double X[9] = {0}, g[9], H[81];
    for (int c = 0; c < 3; c++)
      for (int i = 0; i < nv; i++)
        for (int a = 0; a < d; a++) X[c * d + a] += L[6 * c + i] * ev->x[(size_t)v[i] * d + a];
    double psi = density(&bp->law[bp->mat[s]], X, d, g, ev->hess ? H : NULL, ev->project);
    if (!isfinite(psi)) {
      sw_eval_why(ev, "dde_bending: triangle %d (face %d): energy or Hessian not finite", s,
                  bp->face[s]);
      *energy = NAN;
      return SW_RECOVER;
    }
    total += A * psi; /* J */
    if (ev->grad)
      for (int i = 0; i < nv; i++)
        for (int a = 0; a < d; a++) {
          double f = 0.0;
          for (int c = 0; c < 3; c++) f += L[6 * c + i] * g[c * d + a];
          ev->grad[(size_t)v[i] * d + a] += A * f;
        }
    if (!ev->hess) continue;
    double T[9 * 18]; /* T = H (L (x) I) (n9 x w) */
    for (int p = 0; p < n9; p++)
      for (int j = 0; j < nv; j++)
        for (int b = 0; b < d; b++) {
          double acc = 0.0;
          for (int e = 0; e < 3; e++) acc += H[p * n9 + e * d + b] * L[6 * e + j];
          T[p * 18 + j * d + b] = acc;
        }
    double *blk = sw_ev_block(ev, t, s);
    for (int i = 0; i < nv; i++)
      for (int a = 0; a < d; a++)
        for (int j = 0; j < nv; j++)
          for (int b = 0; b < d; b++) {
            if (i * d + a > j * d + b) continue; /* the upper triangle is stored */
            double acc = 0.0;
            for (int c = 0; c < 3; c++) acc += L[6 * c + i] * T[(c * d + a) * 18 + j * d + b];
            sw_hess_set(blk, w, i * d + a, j * d + b, A * acc);
          }
    sw_ev_block_done(ev, t, s, blk);
  }
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static const sw_term_ops dde_bending_ops = {.kind = "dde_bending",
                                            .eval = dde_bending_eval,
                                            .free_param = dde_bending_free,
                                            .sets_blocks = 1,
                                            .sink_ok = 1};

int sw_dde_bending_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  dde_bending_param *bp = sw_calloc(1, sizeof *bp);
  t->ops = &dde_bending_ops;
  t->param = bp;
  snprintf(t->name, sizeof t->name, "%s", "dde_bending");
  if (!bp) return sw_errf(err, errsz, "out of memory"), -1;
  bp->law = sw_calloc((size_t)m->nmat + 1, sizeof *bp->law);
  if (!bp->law) return sw_errf(err, errsz, "out of memory"), -1;
  for (int k = 0; k < m->nmat; k++) {
    if (m->mat[k].bending != SW_BENDING_DDE) continue;
    char why[SW_ERRSZ];
    if (sw_dde_bend_setup(&m->mat[k].dde, &bp->law[k], why, sizeof why))
      return sw_errf(err, errsz, "bending model dde of %s%s: %s", k ? "panel " : "the material",
                     m->mat[k].group, why), -1;
  }
  sw_bend_tri *tr = sw_bend_tris(m, SW_BENDING_DDE, &bp->n, err, errsz);
  if (!tr) return -1;
  bp->L = sw_calloc((size_t)bp->n + 1, 18 * sizeof(double));
  bp->A = sw_calloc((size_t)bp->n + 1, sizeof(double));
  bp->mat = sw_calloc((size_t)bp->n + 1, sizeof(int));
  bp->face = sw_calloc((size_t)bp->n + 1, sizeof(int));
  int rc = !bp->L || !bp->A || !bp->mat || !bp->face ||
           sw_bend_alloc_stencils(t, tr, bp->n, m->dim);
  if (rc) sw_errf(err, errsz, "out of memory for %d bending triangles", bp->n);
  for (int s = 0; !rc && s < bp->n; s++) {
    const sw_bend_tri *T = &tr[s];
    double K[6], *L = bp->L + 18 * s;
    for (int a = 0; a < T->nh; a++) {
      sw_bend_hinge_K(m, T, &T->h[a], K);
      for (int c = 0; c < 3; c++)
        for (int i = 0; i < 6; i++) L[6 * c + i] += T->M[c][a] * K[i] / T->h[a].len; /* 1/m^2 */
    }
    bp->A[s] = m->area[T->face];
    bp->mat[s] = m->face_mat[T->face];
    bp->face[s] = T->face;
  }
  sw_free(tr);
  return rc ? -1 : 0;
}
