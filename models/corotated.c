/* corotated.c — corotated membrane k/2 |U - I|^2 (docs/models.md; Yan 2019 eqs.
 * 14-20: F = R U, C = F^T F = U^2, U = sqrt(C) from C's eigen-decomposition; docs/models.md).
 *
 * Per face whose material uses corotated, F = [wu wv] (d x 2), C = F^T F (2 x 2) with the
 * closed-form eigenvalues lambda = tr C/2 +- sqrt(((C11 - C22)/2)^2 + C12^2) and principal
 * stretches sigma_i = sqrt(lambda_i):
 *   psi = k/2 |U - I|_F^2 = k/2 [(sigma1 - 1)^2 + (sigma2 - 1)^2]     (J/m^2, k in N/m).
 * Derivatives use the invariant form (smooth where sigma1 = sigma2, no eigenvectors):
 *   psi = k/2 (t - 2 tau + 2),  t = tr C = |wu|^2 + |wv|^2,  tau = tr U = sigma1 + sigma2
 *       = sqrt(t + 2 j),  j = sqrt(det C) = sigma1 sigma2 = |c|,  c = wu x wv
 * (in 2D c = (0, 0, det F)).  With f = [wu; wv] (2d) and dj = dj/df = B^T c^, B = dc/df:
 *   dpsi/df = k (1 - 1/tau) f - (k/tau) dj,
 *   P = k (1 - 1/tau) I - (k/tau) d2j + (k/tau^3) g g^T,  g = f + dj,
 *   d2j = (B^T B - dj dj^T)/j + [[0, -[c^]x], [[c^]x, 0]]
 * ([a]x the cross-product matrix; j = |c| computed from the cross product, not from det C, so
 * it keeps its relative accuracy as the triangle degenerates).
 * Degenerate F: psi is not differentiable where j = 0 (a triangle collapsed onto a line: sigma2
 * = |c|/sigma1 is a cone in c) nor at F = 0.  When j <= 1e-12 t we take c^ = 0, i.e. dj = 0 (the
 * smallest subgradient) and drop the unbounded 1/j curvature: psi, gradient and P are then
 * those of the energy restricted to j = 0.  At F = 0: gradient 0 and P = k I.
 * Filters (SW_FILTER_*): P commutes with the reflection through the plane of wu, wv.  In the
 * frame n = c^, e1 = wu^ (orthogonal to n), e2 = n x e1, where F's in-plane part
 * [[a, b], [c, d]] has det = j > 0, the in-plane 4 x 4 block is k I - (2k/tau) t t^T with the
 * twist t ~ (-(b - c), a + d, -(a + d), -(b - c)) (in a, b, c, d): eigenvalues k (three times)
 * and k (1 - 2/tau); the out-of-plane block, on dwu = x n, dwv = y n, is k (I - U^-1):
 * eigenvalues k (1 - 1/sigma_i) on C's eigenvectors (x, y).  With j = 0, P = k (1 - 1/tau) I +
 * (k/tau^3) f f^T.  So P is PSD and kept when tau >= 2 in 2D or sigma2 >= 1 in 3D; otherwise the
 * filtered P (eigenvalues clamped at 0 or made absolute, as ev->project asks) is built from
 * that eigen-system directly.  Filtering the exact P numerically instead lost the accuracy of
 * its small eigenvalues as j -> 0: the out-of-plane one is ~ -k t/j, and the 1/j entries
 * cancel in the in-plane block, leaving round-off of 1e-16 k t/j. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

typedef struct corot_law {
  double k; /* N/m */
} corot_law;

/* [a]x b = a x b, stored at M (ld) rows r0.., columns c0.., times s. */
static void add_cross(double *M, int ld, int r0, int c0, const double *a, double s) {
  const double X[9] = {0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) M[(r0 + i) * ld + c0 + j] += s * X[i * 3 + j];
}

/* P (6 x 6, on [wu; wv] padded to 3D) of the invariant form above; ch = c^ (0 if degenerate). */
static void corot_hessian(double k, double tau, double j, const double *f, const double *dj,
                          const double *ch, double *P6) {
  double B[18] = {0}; /* dc/df = [-[wv]x, [wu]x] (3 x 6) */
  add_cross(B, 6, 0, 0, f + 3, -1.0);
  add_cross(B, 6, 0, 3, f, 1.0);
  memset(P6, 0, 36 * sizeof(double));
  if (j > 0.0) {
    add_cross(P6, 6, 0, 3, ch, -1.0); /* c^ . d2c: -[c^]x upper right, [c^]x lower left */
    add_cross(P6, 6, 3, 0, ch, 1.0);
  }
  for (int a = 0; a < 6; a++)
    for (int b = 0; b < 6; b++) {
      double d2j = P6[a * 6 + b];
      if (j > 0.0) {
        double btb = B[a] * B[b] + B[6 + a] * B[6 + b] + B[12 + a] * B[12 + b];
        d2j += (btb - dj[a] * dj[b]) / j;
      }
      double g2 = (f[a] + dj[a]) * (f[b] + dj[b]);
      P6[a * 6 + b] = k * (1.0 - 1.0 / tau) * (a == b) - k / tau * d2j + k / (tau * tau * tau) * g2;
    }
}

/* P (6 x 6, on [wu; wv] padded to 3D) with its eigenvalues filtered by `mode`, from its
 * eigen-system in closed form (see the head comment): f = [wu; wv], tau = tr U, j = |c|,
 * ch = c^ (any value when j = 0), s1 >= s2 the principal stretches and (c11, c12, c22) = C. */
static void corot_filtered(double k, const double *f, double tau, double j, const double *ch,
                           double s1, double s2, double c11, double c12, double c22, int mode,
                           double *P6) {
  memset(P6, 0, 36 * sizeof(double));
  if (!(tau > 0.0)) { /* F = 0: P = k I */
    for (int a = 0; a < 6; a++) P6[a * 7] = k;
    return;
  }
  if (j == 0.0) { /* degenerate: k (1 - 1/tau) I + (k/tau^3) f f^T, eigenvector f */
    double ff = 0.0;
    for (int a = 0; a < 6; a++) ff += f[a] * f[a];
    double lo = sw_filter_eigenvalue(k * (1.0 - 1.0 / tau), mode);
    double hi = sw_filter_eigenvalue(k * (1.0 - 1.0 / tau) + k * ff / (tau * tau * tau), mode);
    for (int a = 0; a < 6; a++)
      for (int b = 0; b < 6; b++) P6[a * 6 + b] = lo * (a == b) + (hi - lo) * f[a] * f[b] / ff;
    return;
  }
  /* The orthonormal frame n = c^, e1 = wu^ orthogonalised against n (to round-off: c^ loses
   * accuracy as j -> 0, and the frame must stay orthonormal), e2 = n x e1, in which F's in-plane
   * part [[a, b], [c, d]] = [[wu.e1, wv.e1], [wu.e2, wv.e2]] has det ~ j > 0. */
  double e1[3], e2[3], un = f[0] * ch[0] + f[1] * ch[1] + f[2] * ch[2], l1 = 0.0;
  for (int a = 0; a < 3; a++) e1[a] = f[a] - un * ch[a], l1 += e1[a] * e1[a];
  l1 = sqrt(l1);
  for (int a = 0; a < 3; a++) e1[a] /= l1;
  e2[0] = ch[1] * e1[2] - ch[2] * e1[1];
  e2[1] = ch[2] * e1[0] - ch[0] * e1[2];
  e2[2] = ch[0] * e1[1] - ch[1] * e1[0];
  double fa = f[0] * e1[0] + f[1] * e1[1] + f[2] * e1[2];
  double fc = f[0] * e2[0] + f[1] * e2[1] + f[2] * e2[2];
  double fb = f[3] * e1[0] + f[4] * e1[1] + f[5] * e1[2];
  double fd = f[3] * e2[0] + f[4] * e2[1] + f[5] * e2[2];
  /* In-plane: k on the three directions orthogonal to the twist
   * t = (-(b - c), a + d, -(a + d), -(b - c)) (in a, b, c, d), k (1 - 2/tau) on t. */
  double ta = -(fb - fc), tb = fa + fd, tc = -(fa + fd), td = -(fb - fc);
  double tn = sqrt(ta * ta + tb * tb + tc * tc + td * td), tw[6];
  for (int a = 0; a < 3; a++) {
    tw[a] = (ta * e1[a] + tc * e2[a]) / tn;     /* d wu */
    tw[3 + a] = (tb * e1[a] + td * e2[a]) / tn; /* d wv */
  }
  double ltw = sw_filter_eigenvalue(k * (1.0 - 2.0 / tau), mode) - k;
  for (int a = 0; a < 6; a++)
    for (int b = 0; b < 6; b++) {
      int same = a / 3 == b / 3;
      P6[a * 6 + b] = (same ? k * ((a == b) - ch[a % 3] * ch[b % 3]) : 0.0) + ltw * tw[a] * tw[b];
    }
  /* Out of plane, d wu = x n, d wv = y n: the 2 x 2 block k (I - U^-1), eigenvalues
   * k (1 - 1/s_i) on C's eigenvectors v_i. */
  double h = 0.5 * (c11 - c22), r = sqrt(h * h + c12 * c12), v[2] = {1.0, 0.0};
  if (r > 0.0) {
    double x1 = h + r, y1 = c12, x2 = c12, y2 = r - h;
    int first = x1 * x1 + y1 * y1 >= x2 * x2 + y2 * y2;
    double vx = first ? x1 : x2, vy = first ? y1 : y2, vn = sqrt(vx * vx + vy * vy);
    v[0] = vx / vn, v[1] = vy / vn;
  }
  const double vec[2][2] = {{v[0], v[1]}, {-v[1], v[0]}}, sig[2] = {s1, s2};
  for (int i = 0; i < 2; i++) {
    double l = sw_filter_eigenvalue(k * (1.0 - 1.0 / sig[i]), mode), w[6];
    for (int a = 0; a < 3; a++) w[a] = vec[i][0] * ch[a], w[3 + a] = vec[i][1] * ch[a];
    for (int a = 0; a < 6; a++)
      for (int b = 0; b < 6; b++) P6[a * 6 + b] += l * w[a] * w[b];
  }
}

static double corot_density(const void *law, const double *wu, const double *wv, int d,
                            int project, double *gu, double *gv, double *P) {
  const double k = ((const corot_law *)law)->k;
  double f[6] = {0}, c[3], ch[3] = {0}, dj[6] = {0}, P6[36];
  memcpy(f, wu, sizeof(double) * (size_t)d);
  memcpy(f + 3, wv, sizeof(double) * (size_t)d);
  c[0] = f[1] * f[5] - f[2] * f[4];
  c[1] = f[2] * f[3] - f[0] * f[5];
  c[2] = f[0] * f[4] - f[1] * f[3];
  double c11 = f[0] * f[0] + f[1] * f[1] + f[2] * f[2], c22 = f[3] * f[3] + f[4] * f[4] + f[5] * f[5];
  double c12 = f[0] * f[3] + f[1] * f[4] + f[2] * f[5], t = c11 + c22;
  double j = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  if (j <= 1e-12 * t) j = 0.0; /* degenerate: see the head comment */
  double h = 0.5 * (c11 - c22), lam1 = 0.5 * t + sqrt(h * h + c12 * c12);
  double s1 = sqrt(lam1), s2 = s1 > 0.0 ? j / s1 : 0.0, tau = s1 + s2; /* stretches, 1 */
  for (int a = 0; a < 3 && j > 0.0; a++) ch[a] = c[a] / j;
  /* dj = B^T c^: d|c|/dwu = wv x c^, d|c|/dwv = c^ x wu */
  dj[0] = f[4] * ch[2] - f[5] * ch[1], dj[1] = f[5] * ch[0] - f[3] * ch[2];
  dj[2] = f[3] * ch[1] - f[4] * ch[0], dj[3] = ch[1] * f[2] - ch[2] * f[1];
  dj[4] = ch[2] * f[0] - ch[0] * f[2], dj[5] = ch[0] * f[1] - ch[1] * f[0];
  double cf = tau > 0.0 ? k * (1.0 - 1.0 / tau) : 0.0, cj = tau > 0.0 ? k / tau : 0.0;
  for (int a = 0; a < d; a++) {
    gu[a] = cf * f[a] - cj * dj[a];
    gv[a] = cf * f[3 + a] - cj * dj[3 + a];
  }
  if (P) {
    int psd = d == 2 ? tau >= 2.0 : s2 >= 1.0;
    if (project && !psd)
      corot_filtered(k, f, tau, j, ch, s1, s2, c11, c12, c22, project, P6);
    else if (tau > 0.0)
      corot_hessian(k, tau, j, f, dj, ch, P6);
    else
      for (int a = 0; a < 36; a++) P6[a] = k * (a % 7 == 0);
    const int ld = 2 * d, at[4] = {0, 1, 3, 4}; /* 2D: the in-plane rows of P6 */
    for (int a = 0; a < ld; a++)
      for (int b = 0; b < ld; b++)
        P[a * ld + b] = d == 3 ? P6[a * 6 + b] : P6[at[a] * 6 + at[b]];
    for (int a = 0; project && !psd && a < ld * ld; a++)
      if (!isfinite(P[a])) return NAN;
  }
  return 0.5 * k * ((s1 - 1.0) * (s1 - 1.0) + (s2 - 1.0) * (s2 - 1.0));
}

static const sw_term_ops corot_ops = {
    .kind = "corotated", .eval = sw_membrane_eval, .free_param = sw_membrane_free,
    .sets_blocks = 1, .sink_ok = 1};

int sw_corotated_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  sw_membrane *mb = sw_membrane_new(t, m, &corot_ops, SW_MEMBRANE_COROTATED, sizeof(corot_law),
                                    corot_density, err, errsz);
  if (!mb) return -1;
  corot_law *law = mb->law;
  for (int k = 0; k < m->nmat; k++) {
    const sw_material *mt = &m->mat[k];
    if (mt->membrane != SW_MEMBRANE_COROTATED) continue;
    if (!(mt->k_corot > 0.0) || !isfinite(mt->k_corot))
      return sw_errf(err, errsz, "%s%s: corotated membrane needs a finite k > 0 (got %g N/m)",
                     mt->group[0] ? "panel " : "", mt->group[0] ? mt->group : "material",
                     mt->k_corot), -1;
    law[k].k = mt->k_corot;
  }
  return 0;
}
