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
 * principal direction theta = 0, 22.5, 45, 67.5, 90 degrees from warp, interpolated between
 * the directions by a monotone cubic (below); beyond w = 7/6 the stiffness stays that of
 * w = 7/6.  In the strain, s is the smoothstep of the paper's linear ramp t: equal to it at
 * the samples (0, 1) and half-way (1/2), and C1 where t reaches 0 and 1.  The linear ramp puts
 * a kink into the energy's gradient at w = 1, which a face crosses wherever stretch turns to
 * compression, and Newton does not converge on it: a 45 degree cantilever strip of
 * gray-interlock stalled at a free force of 2e-7 N after 1000 static iterations with the ramp
 * (tests/test_dde.c's strip).
 * The direction coordinate is q = sin^2 theta = (1 - cos 2 theta)/2 = (1 - d/r)/2,
 * d = (a - b)/2, r = sqrt(d^2 + g^2/4), smooth at 0 and 90 degrees (the mirror symmetry of an
 * orthotropic fabric).  In q, c_dir is the monotone piecewise cubic through the five samples
 * (Fritsch and Carlson 1980; pchip_slopes): equal to the samples, C1 across them, monotone
 * between them (a clamped sample's zero is never undershot).  Linear interpolation, as the
 * paper's, puts a kink into the energy's gradient wherever a face's principal direction
 * crosses 22.5, 45 or 67.5 degrees, and Newton then stalls short of a tight tolerance (the
 * T-shirt in gray-interlock did: docs/bench/dde.md).
 * At an isotropic strain (r = 0) the direction is undefined, and c_dir(q) would make the energy
 * itself jump there; so below r = R0 = 0.01 the direction's part fades out,
 *   c_dir -> cbar + phi (c_dir(q) - cbar),   phi = u^2 (3 - 2 u),  u = r^2 / R0^2,
 * cbar the mean of the five rows over theta (trapezoidal), and lambda's cone at r = 0 is
 * rounded, lambda = (a + b)/2 + p, p = (3/2) r^2/R0 - r^4/(2 R0^3) below R0 (p = r with its
 * slope at R0, p = 0 at r = 0).  Both are polynomials in r^2, smooth in e, and phi vanishes as
 * r^4, so the energy is twice differentiable at r = 0.  Every sample (a stretch along one
 * direction, r >= 0.04) and the zero strain keep the data's numbers.
 *
 * The gradient and Hessian are exact, the derivatives of c included (within each cell of the
 * interpolation): with m = (a^2, 2ab, b^2, g^2/2), psi = c.m,
 *   dpsi = c.dm + m.dc,   d2psi = c.d2m + dc (x) dm + dm (x) dc + m.d2c,
 *   c = c0 + s D,  D = cbar + phi (c_dir - cbar) - c0,
 *   dc = D ds + s dD,   d2c = D d2s + ds (x) dD + dD (x) ds + s d2D,
 *   dD = (c_dir - cbar) dphi + phi c_dir' dq,
 *   d2D = (c_dir - cbar) d2phi + c_dir' (dphi (x) dq + dq (x) dphi)
 *         + phi (c_dir'' dq (x) dq + c_dir' d2q),
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

/* The strain's principal quantities and their first and second derivatives in e = (a, b, g):
 * lambda the largest principal Green strain, with its cone at isotropic strains rounded
 * (mean + p(r) below R0), q = sin^2 theta of its direction, and phi the weight of the
 * direction's part (1 from r = R0 on, 0 at r = 0).  r = sqrt(d^2 + h^2), d = (a - b)/2,
 * h = g/2 is half the difference of the principal strains; below R0 lambda and phi are
 * polynomials in rho = r^2, smooth in e: p = (3/2) rho/R0 - rho^2/(2 R0^3) (p(0) = 0, and
 * p = r, p' = 1 at R0), phi = u^2 (3 - 2 u) with u = rho/R0^2 (phi = 1, phi' = 0 at R0;
 * phi ~ r^4 at 0, so that phi times q's derivatives, which grow as 1/r and 1/r^2, vanishes
 * there and the energy is twice differentiable at isotropic strains). */
typedef struct dde_principal {
  double lam, dl[3], d2l[9]; /* lambda (rounded), 1 */
  double q, dq[3], d2q[9];   /* sin^2 theta; 0 with zero derivatives at r = 0 */
  double phi, dp[3], d2p[9]; /* the direction's weight, 1 */
} dde_principal;

#define DDE_R0 0.01 /* 1: half the principal strain difference below which theta fades out */

static void principal(const double e[3], dde_principal *pr) {
  double d = 0.5 * (e[0] - e[1]), h = 0.5 * e[2], rho = d * d + h * h, r = sqrt(rho);
  double J[2][3] = {{0.5, -0.5, 0.0}, {0.0, 0.0, 0.5}}; /* d(d, h)/d(a, b, g) */
  memset(pr, 0, sizeof *pr);
  double drho[3], d2rho[9];
  for (int i = 0; i < 3; i++) {
    drho[i] = 2.0 * (d * J[0][i] + h * J[1][i]);
    for (int j = 0; j < 3; j++) d2rho[3 * i + j] = 2.0 * (J[0][i] * J[0][j] + J[1][i] * J[1][j]);
  }
  pr->lam = 0.5 * (e[0] + e[1]);
  if (r < DDE_R0) { /* the polynomials in rho */
    const double R3 = DDE_R0 * DDE_R0 * DDE_R0, R2 = DDE_R0 * DDE_R0, u = rho / R2;
    double p1 = 1.5 / DDE_R0 - rho / R3, p2 = -1.0 / R3; /* dp/drho, d2p/drho2 */
    double f1 = 6.0 * u * (1.0 - u) / R2, f2 = (6.0 - 12.0 * u) / (R2 * R2); /* dphi/drho.. */
    pr->lam += 1.5 * rho / DDE_R0 - 0.5 * rho * rho / R3;
    pr->phi = u * u * (3.0 - 2.0 * u);
    for (int i = 0; i < 3; i++) {
      pr->dl[i] = (i < 2 ? 0.5 : 0.0) + p1 * drho[i];
      pr->dp[i] = f1 * drho[i];
      for (int j = 0; j < 3; j++) {
        pr->d2l[3 * i + j] = p1 * d2rho[3 * i + j] + p2 * drho[i] * drho[j];
        pr->d2p[3 * i + j] = f1 * d2rho[3 * i + j] + f2 * drho[i] * drho[j];
      }
    }
  } else {
    pr->lam += r, pr->phi = 1.0;
  }
  if (!(r > 1e-14)) return; /* isotropic: no direction, phi = 0 */
  double r3 = r * r * r, r5 = r3 * r * r;
  double gr[2] = {d / r, h / r};                                     /* dr/d(d, h) */
  double Hr[2][2] = {{h * h / r3, -d * h / r3}, {-d * h / r3, d * d / r3}};
  double gp[2] = {h * h / r3, -d * h / r3};                          /* d(d/r)/d(d, h) */
  double pdh = h * (2.0 * d * d - h * h) / r5;
  double Hp[2][2] = {{-3.0 * h * h * d / r5, pdh}, {pdh, -d / r3 + 3.0 * d * h * h / r5}};
  pr->q = 0.5 * (1.0 - d / r);
  for (int i = 0; i < 3; i++) {
    if (r >= DDE_R0) pr->dl[i] = (i < 2 ? 0.5 : 0.0) + gr[0] * J[0][i] + gr[1] * J[1][i];
    pr->dq[i] = -0.5 * (gp[0] * J[0][i] + gp[1] * J[1][i]);
    for (int j = 0; j < 3; j++)
      for (int u = 0; u < 2; u++)
        for (int v = 0; v < 2; v++) {
          if (r >= DDE_R0) pr->d2l[3 * i + j] += J[u][i] * Hr[u][v] * J[v][j];
          pr->d2q[3 * i + j] -= 0.5 * J[u][i] * Hp[u][v] * J[v][j];
        }
  }
}

/* The slopes of the monotone cubic through the five direction samples y (in q): Fritsch and
 * Carlson, "Monotone piecewise cubic interpolation", SIAM J. Numer. Anal. 17(2), 1980, with
 * the weighted harmonic mean of Fritsch and Butland inside and the three-point end slopes
 * limited as Moler's pchip does; 0 wherever the data turns, so a clamped 0 is never
 * undershot. */
static void pchip_slopes(const double y[5], double sl[5]) {
  double hq[4], dl[4];
  for (int k = 0; k < 4; k++) hq[k] = QNODE[k + 1] - QNODE[k], dl[k] = (y[k + 1] - y[k]) / hq[k];
  for (int k = 1; k < 4; k++) {
    double w1 = 2.0 * hq[k] + hq[k - 1], w2 = hq[k] + 2.0 * hq[k - 1];
    sl[k] = dl[k - 1] * dl[k] > 0.0 ? (w1 + w2) / (w1 / dl[k - 1] + w2 / dl[k]) : 0.0;
  }
  for (int end = 0; end < 2; end++) { /* q = 0 (k = 0) and q = 1 (k = 4) */
    int a = end ? 3 : 0, b = end ? 2 : 1;
    double s = ((2.0 * hq[a] + hq[b]) * dl[a] - hq[a] * dl[b]) / (hq[a] + hq[b]);
    if (s * dl[a] <= 0.0) s = 0.0;
    else if (dl[a] * dl[b] <= 0.0 && fabs(s) > 3.0 * fabs(dl[a])) s = 3.0 * dl[a];
    sl[end ? 4 : 0] = s;
  }
}

/* c_dir(q) and its first two derivatives in q for stiffness l: the monotone cubic's piece on
 * cell k, f = (q - q_k)/h_k. */
static void dir_cubic(const sw_dde *dd, int l, int k, double f, double *c, double *cq,
                      double *cqq) {
  double y[5], sl[5], hq = QNODE[k + 1] - QNODE[k];
  for (int j = 0; j < 5; j++) y[j] = dd->stretch[1 + j][l];
  pchip_slopes(y, sl);
  double f2 = f * f, f3 = f2 * f, y0 = y[k], y1 = y[k + 1], m0 = hq * sl[k], m1 = hq * sl[k + 1];
  *c = (2 * f3 - 3 * f2 + 1) * y0 + (f3 - 2 * f2 + f) * m0 + (3 * f2 - 2 * f3) * y1 + (f3 - f2) * m1;
  *cq = ((6 * f2 - 6 * f) * y0 + (3 * f2 - 4 * f + 1) * m0 + (6 * f - 6 * f2) * y1 +
         (3 * f2 - 2 * f) * m1) / hq;
  *cqq = ((12 * f - 6) * y0 + (6 * f - 4) * m0 + (6 - 12 * f) * y1 + (6 * f - 2) * m1) / (hq * hq);
}

/* c(e) and its derivatives (the model in the head comment). */
static void dde_stiffness_eval(const sw_dde *dd, const double e[3], dde_eval *out) {
  dde_principal pr;
  principal(e, &pr);
  const double *dl = pr.dl, *d2l = pr.d2l;
  double w = sqrt(fmax(1.0 + 2.0 * pr.lam, 1e-300)); /* principal stretch, 1 */
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
  while (k < 3 && pr.q > QNODE[k + 1]) k++;
  double f = (pr.q - QNODE[k]) / (QNODE[k + 1] - QNODE[k]);
  for (int l = 0; l < 4; l++) {
    double c0 = dd->stretch[0][l], cd, cq, cqq;
    double cbar = (0.5 * dd->stretch[1][l] + dd->stretch[2][l] + dd->stretch[3][l] +
                   dd->stretch[4][l] + 0.5 * dd->stretch[5][l]) / 4.0; /* mean over theta */
    dir_cubic(dd, l, k, f, &cd, &cq, &cqq);
    double D = cbar + pr.phi * (cd - cbar) - c0, dD[3], d2D[9]; /* c_dir - c0 with the fade */
    for (int i = 0; i < 3; i++) {
      dD[i] = (cd - cbar) * pr.dp[i] + pr.phi * cq * pr.dq[i];
      for (int j = 0; j < 3; j++)
        d2D[3 * i + j] = (cd - cbar) * pr.d2p[3 * i + j] +
                         cq * (pr.dp[i] * pr.dq[j] + pr.dq[i] * pr.dp[j]) +
                         pr.phi * (cqq * pr.dq[i] * pr.dq[j] + cq * pr.d2q[3 * i + j]);
    }
    out->c[l] = c0 + s * D;
    for (int i = 0; i < 3; i++) {
      out->dc[l][i] = D * ds[i] + s * dD[i];
      for (int j = 0; j < 3; j++)
        out->d2c[l][3 * i + j] = D * d2s[3 * i + j] + ds[i] * dD[j] + dD[i] * ds[j] +
                                 s * d2D[3 * i + j];
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
    .sets_blocks = 1, .sink_ok = 1};

int sw_dde_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  sw_membrane *mb = sw_membrane_new(t, m, &dde_ops, SW_MEMBRANE_DDE, sizeof(sw_dde),
                                    dde_density, err, errsz);
  if (!mb) return -1;
  sw_dde *law = mb->law;
  for (int k = 0; k < m->nmat; k++)
    if (m->mat[k].membrane == SW_MEMBRANE_DDE) law[k] = m->mat[k].dde;
  return 0;
}

void sw_dde_strip_stiffness(const double c[4], double *ku, double *kv) {
  *ku = 2.0 * (c[2] > 0.0 ? c[0] - c[1] * c[1] / c[2] : c[0]);
  *kv = 2.0 * (c[0] > 0.0 ? c[2] - c[1] * c[1] / c[0] : c[2]);
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
