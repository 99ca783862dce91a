/* dde.c — the data-driven membrane of a measured fabric (Wang, Ramamoorthi and O'Brien,
 * "Data-Driven Elastic Models for Cloth: Modeling and Measurement", SIGGRAPH 2011, sec. 4;
 * the sample layout as ARCSim's src/dde.cpp reads it; docs/fabrics.md).
 *
 * Per face whose material uses dde, F = [wu wv], the Green strain in Voigt form
 * e = (a, b, g) = ((|wu|^2 - 1)/2, (|wv|^2 - 1)/2, wu.wv) in the warp/weft frame, and
 *   psi = c11 a^2 + 2 c12 a b + c22 b^2 + c33 g^2 / 2   (J/m^2 = N/m),
 * i.e. psi = 1/2 e^T Q e, Q = [[2 c11, 2 c12, 0], [2 c12, 2 c22, 0], [0, 0, c33]] (the stress
 * ARCSim's physics.cpp applies: its k = 2 c, and its shear force 2 k33 E12 dE12 = c33 g dg).
 * The stiffnesses c depend on the strain as the paper's model, between the same samples:
 *   c = c0 + s (c_dir(q) - c0),  s = t^2 (3 - 2 t),  t = clamp(6 (w - 1), 0, 1),
 * w = sqrt(1 + 2 lambda) the largest principal stretch (lambda the largest eigenvalue of the
 * Green strain), c0 the zero-strain row, c_dir the five rows measured at w = 7/6 along the
 * principal direction theta = 0, 22.5, 45, 67.5, 90 degrees from warp, interpolated linearly
 * between neighbouring directions; beyond w = 7/6 the stiffness stays that of w = 7/6.  In the
 * strain, s is the smoothstep of the paper's linear ramp t: equal to it at the samples (0, 1)
 * and half-way (1/2), and C1 where t reaches 0 and 1.  The linear ramp puts a kink into the
 * energy's gradient at w = 1, which a face crosses wherever stretch turns to compression, and
 * Newton does not converge on it: a 45 degree cantilever strip of gray-interlock stalled at a
 * free force of 2e-7 N after 1000 static iterations with the ramp (tests/test_dde.c's strip).
 * The direction coordinate is q = sin^2 theta = (1 - cos 2 theta)/2 = (1 - d/r)/2,
 * d = (a - b)/2, r = sqrt(d^2 + g^2/4): linear in q between the sample directions, equal to
 * the samples at them, monotone between them (a clamped sample's zero is never undershot), and
 * smooth at 0 and 90 degrees where linear interpolation in theta itself would put a kink into
 * the energy as the shear strain changes sign (the mirror symmetry of an orthotropic fabric).
 * At r = 0 (an isotropic strain) the direction is undefined; there q = 0 and its derivatives
 * are taken as 0.
 *
 * The gradient and Hessian are exact, the derivatives of c included (within each cell of the
 * interpolation): with m = (a^2, 2ab, b^2, g^2/2), psi = c.m,
 *   dpsi = c.dm + m.dc,   d2psi = c.d2m + dc (x) dm + dm (x) dc + m.d2c,
 *   dc = (c_dir - c0) ds + s c_dir' dq,
 *   d2c = (c_dir - c0) d2s + c_dir' (ds (x) dq + dq (x) ds) + s c_dir' d2q,
 * ds = s'(t) dt, d2s = s'(t) d2t + s''(t) dt (x) dt, dt = (6/w) dlambda,
 * d2t = (6/w) d2lambda - (6/w^3) dlambda (x) dlambda inside 0 < t < 1.
 * With S = (dpsi/da, dpsi/db, dpsi/dg) the forces are those of stvk (models/stvk.c):
 * dpsi/dwu = S11 wu + S12 wv, dpsi/dwv = S12 wu + S22 wv, P = J H J^T + S (x) I_d,
 * J = [[wu, 0, wv], [0, wv, wu]].  The energy is not convex (the data's c12 can exceed
 * sqrt(c11 c22), and dc adds indefinite parts), so P is filtered as every membrane's
 * (sw_membrane_project, as ev->project asks). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "dde.h"
#include "terms.h"
#include "util.h"

/* sin^2 of the sample directions 0, 22.5, 45, 67.5, 90 degrees. */
static const double QNODE[5] = {0.0, 0.14644660940672624, 0.5, 0.85355339059327373, 1.0};

typedef struct dde_eval {
  double c[4];      /* c11, c12, c22, c33, N/m */
  double dc[4][3];  /* dc/de, e = (a, b, g) */
  double d2c[4][9]; /* d2c/de2, row-major 3 x 3 */
} dde_eval;

/* lambda (largest principal Green strain), q = sin^2 theta and their first and second
 * derivatives in e = (a, b, g). */
static void principal(const double e[3], double *lam, double dl[3], double d2l[9], double *q,
                      double dq[3], double d2q[9]) {
  double d = 0.5 * (e[0] - e[1]), h = 0.5 * e[2], r = sqrt(d * d + h * h);
  double J[2][3] = {{0.5, -0.5, 0.0}, {0.0, 0.0, 0.5}}; /* d(d, h)/d(a, b, g) */
  *lam = 0.5 * (e[0] + e[1]) + r;
  memset(d2l, 0, 9 * sizeof *d2l);
  memset(d2q, 0, 9 * sizeof *d2q);
  if (!(r > 1e-14)) {
    dl[0] = dl[1] = 0.5, dl[2] = 0.0;
    *q = 0.0, dq[0] = dq[1] = dq[2] = 0.0;
    return;
  }
  double r3 = r * r * r, r5 = r3 * r * r;
  double gr[2] = {d / r, h / r};                                     /* dr/d(d, h) */
  double Hr[2][2] = {{h * h / r3, -d * h / r3}, {-d * h / r3, d * d / r3}};
  double gp[2] = {h * h / r3, -d * h / r3};                          /* d(d/r)/d(d, h) */
  double pdh = h * (2.0 * d * d - h * h) / r5;
  double Hp[2][2] = {{-3.0 * h * h * d / r5, pdh}, {pdh, -d / r3 + 3.0 * d * h * h / r5}};
  *q = 0.5 * (1.0 - d / r);
  for (int i = 0; i < 3; i++) {
    dl[i] = (i < 2 ? 0.5 : 0.0) + gr[0] * J[0][i] + gr[1] * J[1][i];
    dq[i] = -0.5 * (gp[0] * J[0][i] + gp[1] * J[1][i]);
    for (int j = 0; j < 3; j++)
      for (int u = 0; u < 2; u++)
        for (int v = 0; v < 2; v++) {
          d2l[3 * i + j] += J[u][i] * Hr[u][v] * J[v][j];
          d2q[3 * i + j] -= 0.5 * J[u][i] * Hp[u][v] * J[v][j];
        }
  }
}

/* c(e) and its derivatives (the model in the head comment). */
static void dde_stiffness_eval(const sw_dde *dd, const double e[3], dde_eval *out) {
  double lam, dl[3], d2l[9], q, dq[3], d2q[9];
  principal(e, &lam, dl, d2l, &q, dq, d2q);
  double w = sqrt(fmax(1.0 + 2.0 * lam, 1e-300)); /* principal stretch, 1 */
  double t = 6.0 * (w - 1.0), s, ds[3] = {0}, d2s[9] = {0};
  if (t <= 0.0) s = 0.0;
  else if (t >= 1.0) s = 1.0;
  else {
    s = t * t * (3.0 - 2.0 * t);                          /* smoothstep: C1 at t = 0 and 1 */
    double st = 6.0 * t * (1.0 - t), stt = 6.0 - 12.0 * t; /* ds/dt, d2s/dt2 */
    for (int i = 0; i < 3; i++) {
      double ti = 6.0 / w * dl[i];
      ds[i] = st * ti;
      for (int j = 0; j < 3; j++)
        d2s[3 * i + j] = st * (6.0 / w * d2l[3 * i + j] - 6.0 / (w * w * w) * dl[i] * dl[j]) +
                         stt * ti * 6.0 / w * dl[j];
    }
  }
  int k = 0;
  while (k < 3 && q > QNODE[k + 1]) k++;
  double dqn = QNODE[k + 1] - QNODE[k], f = (q - QNODE[k]) / dqn;
  for (int l = 0; l < 4; l++) {
    double c0 = dd->stretch[0][l], lo = dd->stretch[1 + k][l], hi = dd->stretch[2 + k][l];
    double cd = lo + f * (hi - lo), cdq = (hi - lo) / dqn; /* c_dir and dc_dir/dq */
    out->c[l] = c0 + s * (cd - c0);
    for (int i = 0; i < 3; i++) {
      out->dc[l][i] = (cd - c0) * ds[i] + s * cdq * dq[i];
      for (int j = 0; j < 3; j++)
        out->d2c[l][3 * i + j] = (cd - c0) * d2s[3 * i + j] +
                                 cdq * (ds[i] * dq[j] + dq[i] * ds[j]) + s * cdq * d2q[3 * i + j];
    }
  }
}

void sw_dde_stiffness(const sw_dde *dd, const double e[3], double c[4]) {
  dde_eval ev;
  dde_stiffness_eval(dd, e, &ev);
  memcpy(c, ev.c, sizeof ev.c);
}

double sw_dde_energy(const sw_dde *dd, const double e[3], double S[3], double H[9]) {
  dde_eval ev;
  dde_stiffness_eval(dd, e, &ev);
  const double a = e[0], b = e[1], g = e[2];
  const double m[4] = {a * a, 2.0 * a * b, b * b, 0.5 * g * g};
  const double dm[4][3] = {{2 * a, 0, 0}, {2 * b, 2 * a, 0}, {0, 2 * b, 0}, {0, 0, g}};
  const double d2m[4][9] = {{2, 0, 0, 0, 0, 0, 0, 0, 0}, {0, 2, 0, 2, 0, 0, 0, 0, 0},
                            {0, 0, 0, 0, 2, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0, 0, 0, 1}};
  double psi = 0.0;
  for (int i = 0; i < 3; i++) S[i] = 0.0;
  if (H) memset(H, 0, 9 * sizeof *H);
  for (int l = 0; l < 4; l++) {
    psi += ev.c[l] * m[l];
    for (int i = 0; i < 3; i++) {
      S[i] += ev.c[l] * dm[l][i] + m[l] * ev.dc[l][i];
      if (H)
        for (int j = 0; j < 3; j++)
          H[3 * i + j] += ev.c[l] * d2m[l][3 * i + j] + ev.dc[l][i] * dm[l][j] +
                          dm[l][i] * ev.dc[l][j] + m[l] * ev.d2c[l][3 * i + j];
    }
  }
  return psi;
}

/* The symmetric 3 x 3 H positive definite (its leading minors > 0): then J H J^T is PSD, and
 * P = J H J^T + S (x) I is PSD when S is, so no filter would change it. */
static int pd3(const double H[9]) {
  double m2 = H[0] * H[4] - H[1] * H[3];
  double m3 = H[0] * (H[4] * H[8] - H[5] * H[7]) - H[1] * (H[3] * H[8] - H[5] * H[6]) +
              H[2] * (H[3] * H[7] - H[4] * H[6]);
  return H[0] > 0.0 && m2 > 0.0 && m3 > 0.0;
}

static double dde_density(const void *law, const double *wu, const double *wv, int d,
                          int project, double *gu, double *gv, double *P) {
  double e[3], S[3], H[9]; /* Voigt Green strain (1), its stress and stiffness (N/m) */
  sw_green_voigt(wu, wv, d, e);
  double psi = sw_dde_energy(law, e, S, P ? H : NULL);
  sw_green_forces(S, wu, wv, d, gu, gv);
  if (P) {
    const int ld = 2 * d;
    for (int i = 0; i < ld; i++) /* P = J H J^T + S (x) I */
      for (int j = 0; j < ld; j++) {
        double Ji[3], Jj[3], v = 0.0;
        const int ai = i % d, aj = j % d;
        Ji[0] = i < d ? wu[ai] : 0.0, Ji[1] = i < d ? 0.0 : wv[ai], Ji[2] = i < d ? wv[ai] : wu[ai];
        Jj[0] = j < d ? wu[aj] : 0.0, Jj[1] = j < d ? 0.0 : wv[aj], Jj[2] = j < d ? wv[aj] : wu[aj];
        for (int p = 0; p < 3; p++)
          for (int r = 0; r < 3; r++) v += Ji[p] * H[3 * p + r] * Jj[r];
        if (ai == aj) v += i < d && j < d ? S[0] : i >= d && j >= d ? S[1] : S[2];
        P[i * ld + j] = v;
      }
    if (project && !(pd3(H) && S[0] >= 0.0 && S[1] >= 0.0 && S[0] * S[1] >= S[2] * S[2]) &&
        sw_membrane_project(P, wu, wv, d, project))
      return NAN;
  }
  return psi;
}

/* Designated initializers only: optional fields of the ops table may be added elsewhere. */
static const sw_term_ops dde_ops = {
    .kind = "dde", .eval = sw_membrane_eval, .free_param = sw_membrane_free,
    .sets_blocks = 1};

int sw_dde_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  sw_membrane *mb = sw_membrane_new(t, m, &dde_ops, SW_MEMBRANE_DDE, sizeof(sw_dde),
                                    dde_density, err, errsz);
  if (!mb) return -1;
  sw_dde *law = mb->law;
  for (int k = 0; k < m->nmat; k++)
    if (m->mat[k].membrane == SW_MEMBRANE_DDE) law[k] = m->mat[k].dde;
  return 0;
}

/* ------------------------------------------------------------- what the numbers mean */

/* Uniaxial pull along u (weft = 0) or v (weft = 1), the other direction free (S22 = 0, or
 * S11 = 0) and no shear: the stretch whose nominal tension w S (N per m of rest width) is T.
 * Bisection on the pulled strain, and inside it on the free one. */
static double free_strain(const sw_dde *dd, int weft, double ep) {
  double lo = -0.45, hi = ep, S[3], e[3] = {0, 0, 0};
  for (int it = 0; it < 100; it++) {
    double mid = 0.5 * (lo + hi);
    e[weft] = ep, e[1 - weft] = mid;
    sw_dde_energy(dd, e, S, NULL);
    if (S[1 - weft] > 0.0) hi = mid;
    else lo = mid;
  }
  return 0.5 * (lo + hi);
}

int sw_dde_uniaxial(const sw_dde *dd, int weft, double T, double *stretch) {
  double lo = 0.0, hi = 2.0, S[3], e[3] = {0, 0, 0};
  for (int it = 0; it < 100; it++) {
    double mid = 0.5 * (lo + hi);
    e[weft] = mid, e[1 - weft] = free_strain(dd, weft, mid);
    sw_dde_energy(dd, e, S, NULL);
    if (sqrt(1.0 + 2.0 * mid) * S[weft] > T) hi = mid;
    else lo = mid;
  }
  if (hi >= 2.0) return -1;
  *stretch = sqrt(1.0 + 2.0 * 0.5 * (lo + hi));
  return 0;
}

/* The data's bending (ARCSim's physics.cpp and dde.cpp): a hinge of length l between faces of
 * areas a0 + a1 = a, bent by theta, has the energy k_e l^2 theta^2 / (8 a), k_e read at
 * alpha = theta l / (2 a) with the columns 5 1/m apart in alpha.  Bent into a cylinder of
 * curvature kappa, a strip of hinges d apart (a = l d, theta = kappa d: the cells between them
 * stay flat) stores k_e kappa^2 / 8 per area, which is the plate's B kappa^2 / 2 for B = k_e / 4;
 * and alpha = kappa / 2.  So the rigidity is a quarter of the file's number and the columns are
 * 10 1/m apart in the curvature. */
double sw_dde_bend_rigidity(const sw_dde *dd, double angle, double kappa) {
  double t = fabs(remainder(angle, M_PI)) / (0.25 * M_PI); /* 0..2: 0, 45, 90 degrees */
  double x = fmin(fmax(0.5 * fabs(kappa) / 5.0, 0.0), 4.0); /* column: alpha = kappa/2, 5 1/m apart */
  int i = t >= 1.0, j = x >= 4.0 ? 3 : (int)x;
  double ft = t - i, fx = x - j;
  return 0.25 * ((1 - ft) * ((1 - fx) * dd->bend[i][j] + fx * dd->bend[i][j + 1]) +
                 ft * ((1 - fx) * dd->bend[i + 1][j] + fx * dd->bend[i + 1][j + 1]));
}
