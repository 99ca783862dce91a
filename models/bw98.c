/* bw98.c — Baraff–Witkin stretch and shear membrane (Baraff and Witkin, "Large Steps in Cloth
 * Simulation", SIGGRAPH 1998; docs/models.md).
 *
 * Per face whose material uses bw98, with that material's constants and F = Ds Dm^-1 = [wu wv]
 * (warp and weft directions after deformation):
 *   E = a [ k_u/2 (|wu| - b_u)^2 + k_v/2 (|wv| - b_v)^2 + k_s/2 (wu.wv)^2 ],
 * a the rest (u,v) area (m^2), k in N/m.  The frame shared by the membranes (models/term.c)
 * turns the density psi(wu, wv), its gradient and P = d2psi/d(wu,wv)^2 (2d x 2d) into forces
 * and face blocks by a congruence, so a positive semi-definite P gives a PSD block: the
 * eigenvalue filter (sinew.h, SW_FILTER_*) is applied to P one condition at a time, in closed
 * form — each condition's negative eigenvalues clamped at 0 (its nearest PSD matrix) or
 * replaced by their absolute values — and the sum of PSD parts is PSD. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

typedef struct bw98_law {
  double k_u, k_v, k_s;   /* N/m */
  double b_u, b_v;        /* rest stretch, 1 */
} bw98_law;

/* k/2 (|w| - b)^2: energy, gradient g (d) and Hessian H (d x d, leading dimension ld),
 * filtered by `project` (SW_FILTER_*). */
static double stretch(const double *w, int d, double k, double b, int project, double *g,
                      double *H, int ld) {
  double l = 0.0;
  for (int a = 0; a < d; a++) l += w[a] * w[a];
  l = sqrt(l);
  double n[3] = {1.0, 0.0, 0.0};
  if (l > 0.0)
    for (int a = 0; a < d; a++) n[a] = w[a] / l;
  for (int a = 0; a < d; a++) g[a] = k * (l - b) * n[a];
  if (H) {
    /* H = k n n^T + k (1 - b/|w|) (I - n n^T): eigenvalues k (along n) and the second
     * coefficient, negative in compression (the only one a filter changes). */
    double perp = l > 0.0 ? k * (1.0 - b / l) : 0.0;
    if (project) perp = sw_filter_eigenvalue(perp, project);
    for (int a = 0; a < d; a++)
      for (int c = 0; c < d; c++)
        H[a * ld + c] = k * n[a] * n[c] + perp * ((a == c) - n[a] * n[c]);
  }
  return 0.5 * k * (l - b) * (l - b);
}

/* A unit vector along v, or any unit vector when v is (nearly) zero; returns |v|. */
static double unit(const double *v, int d, double *n) {
  double l = 0.0;
  for (int a = 0; a < d; a++) l += v[a] * v[a];
  l = sqrt(l);
  for (int a = 0; a < d; a++) n[a] = l > 0.0 ? v[a] / l : (a == 0);
  return l;
}

/* Add c * [x; sx*x][y; sy*y]^T / 2-style rank terms: P += c * [u1; u2][w1; w2]^T. */
static void add_outer(double *P, int ld, int d, double c, const double *u1, const double *u2,
                      const double *w1, const double *w2) {
  for (int a = 0; a < d; a++)
    for (int b = 0; b < d; b++) {
      P[a * ld + b] += c * u1[a] * w1[b];
      P[a * ld + d + b] += c * u1[a] * w2[b];
      P[(d + a) * ld + b] += c * u2[a] * w1[b];
      P[(d + a) * ld + d + b] += c * u2[a] * w2[b];
    }
}

/* The filtered shear Hessian k (g g^T + s J), g = [wv; wu], J = [[0,I],[I,0]].
 * With p = (wu+wv)/2, q = (wv-wu)/2: g = sqrt2|p| e1 + sqrt2|q| e2, e1 = [p^;p^]/sqrt2 (J e1 = e1),
 * e2 = [q^;-q^]/sqrt2 (J e2 = -e2).  On span(e1,e2) the matrix is the 2x2
 * [[2|p|^2 + s, 2|p||q|], [2|p||q|, 2|q|^2 - s]]; on the rest of J's +1 space it is s, on the
 * rest of its -1 space -s.  Each eigenvalue is filtered by `mode` (SW_FILTER_CLAMP: clamped at
 * zero, the nearest PSD matrix; SW_FILTER_ABS: its absolute value). */
static void shear_projected(const double *wu, const double *wv, int d, double k, int mode,
                            double *P, int ld) {
  double p[3] = {0}, q[3] = {0}, ph[3], qh[3];
  for (int a = 0; a < d; a++) {
    p[a] = 0.5 * (wu[a] + wv[a]);
    q[a] = 0.5 * (wv[a] - wu[a]);
  }
  double lp = unit(p, d, ph), lq = unit(q, d, qh);
  double s = 0.0;
  for (int a = 0; a < d; a++) s += wu[a] * wv[a];
  /* 2x2 block: eigen-decomposition in closed form. */
  double A = 2 * lp * lp + s, B = 2 * lq * lq - s, C = 2 * lp * lq;
  double mean = 0.5 * (A + B), r = sqrt(0.25 * (A - B) * (A - B) + C * C);
  double lam[2] = {mean + r, mean - r};
  double v1[2];
  if (r > 0.0) {
    double x1 = C, y1 = lam[0] - A, x2 = lam[0] - B, y2 = C;
    if (x1 * x1 + y1 * y1 >= x2 * x2 + y2 * y2) { v1[0] = x1; v1[1] = y1; }
    else { v1[0] = x2; v1[1] = y2; }
    double n = sqrt(v1[0] * v1[0] + v1[1] * v1[1]);
    v1[0] /= n;
    v1[1] /= n;
  } else {
    v1[0] = 1.0;
    v1[1] = 0.0;
  }
  double vec[2][2] = {{v1[0], v1[1]}, {-v1[1], v1[0]}};
  const double h = sqrt(0.5);
  for (int e = 0; e < 2; e++) {
    double le = sw_filter_eigenvalue(lam[e], mode);
    if (le <= 0.0) continue;
    /* z = c1 e1 + c2 e2 = h [c1 p^ + c2 q^; c1 p^ - c2 q^] */
    double z1[3], z2[3];
    for (int a = 0; a < d; a++) {
      z1[a] = h * (vec[e][0] * ph[a] + vec[e][1] * qh[a]);
      z2[a] = h * (vec[e][0] * ph[a] - vec[e][1] * qh[a]);
    }
    add_outer(P, ld, d, k * le, z1, z2, z1, z2);
  }
  /* J's +1 space orthogonal to e1: (1/2)[[Pp, Pp],[Pp, Pp]], Pp = I - p^p^T, eigenvalue s;
   * J's -1 space orthogonal to e2: (1/2)[[Pq, -Pq],[-Pq, Pq]], eigenvalue -s. */
  double cplus = mode == SW_FILTER_ABS ? k * fabs(s) : k * SW_MAX(s, 0.0);
  double cminus = mode == SW_FILTER_ABS ? k * fabs(s) : k * SW_MAX(-s, 0.0);
  for (int a = 0; a < d; a++)
    for (int b = 0; b < d; b++) {
      double pp = ((a == b) - ph[a] * ph[b]) * 0.5 * cplus;
      double pq = ((a == b) - qh[a] * qh[b]) * 0.5 * cminus;
      P[a * ld + b] += pp + pq;
      P[a * ld + d + b] += pp - pq;
      P[(d + a) * ld + b] += pp - pq;
      P[(d + a) * ld + d + b] += pp + pq;
    }
}

/* Exact shear Hessian k [[wv wv^T, wv wu^T + s I], [wu wv^T + s I, wu wu^T]]. */
static void shear_exact(const double *wu, const double *wv, int d, double k, double *P, int ld) {
  double s = 0.0;
  for (int a = 0; a < d; a++) s += wu[a] * wv[a];
  add_outer(P, ld, d, k, wv, wu, wv, wu);
  for (int a = 0; a < d; a++) {
    P[a * ld + d + a] += k * s;
    P[(d + a) * ld + a] += k * s;
  }
}

/* psi and its derivatives for one face: gu, gv (d) and P (2d x 2d) when asked. */
static double density(const void *law, const double *wu, const double *wv, int d, int project,
                      double *gu, double *gv, double *P) {
  const bw98_law *bp = law;
  const int ld = 2 * d;
  double Hu[9], Hv[9], s = 0.0;
  double e = stretch(wu, d, bp->k_u, bp->b_u, project, gu, P ? Hu : NULL, d);
  e += stretch(wv, d, bp->k_v, bp->b_v, project, gv, P ? Hv : NULL, d);
  for (int a = 0; a < d; a++) s += wu[a] * wv[a];
  e += 0.5 * bp->k_s * s * s;
  for (int a = 0; a < d; a++) {
    gu[a] += bp->k_s * s * wv[a];
    gv[a] += bp->k_s * s * wu[a];
  }
  if (P) {
    memset(P, 0, sizeof(double) * (size_t)(ld * ld));
    for (int a = 0; a < d; a++)
      for (int b = 0; b < d; b++) {
        P[a * ld + b] = Hu[a * d + b];
        P[(d + a) * ld + d + b] = Hv[a * d + b];
      }
    /* The shear condition's Hessian is clamped under both filters: with |lambda| (SW_FILTER_ABS)
     * backward Euler on the default hanging cloth stops converging at t = 0.46 s (its
     * indefinite part is large and keeps flipping as the cloth folds); see
     * docs/integrators.md, "Newton". */
    if (project) shear_projected(wu, wv, d, bp->k_s, SW_FILTER_CLAMP, P, ld);
    else shear_exact(wu, wv, d, bp->k_s, P, ld);
  }
  return e;
}

static const sw_term_ops bw98_ops = {
    .kind = "bw98", .eval = sw_membrane_eval, .free_param = sw_membrane_free,
    .sets_blocks = 1, .sink_ok = 1};

int sw_bw98_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  sw_membrane *mb =
      sw_membrane_new(t, m, &bw98_ops, SW_MEMBRANE_BW98, sizeof(bw98_law), density, err, errsz);
  if (!mb) return -1;
  bw98_law *law = mb->law;
  for (int k = 0; k < m->nmat; k++) {
    const sw_material *mt = &m->mat[k];
    law[k] = (bw98_law){mt->k_u, mt->k_v, mt->k_shear, mt->b_u, mt->b_v};
  }
  return 0;
}
