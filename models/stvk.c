/* stvk.c — orthotropic Saint Venant–Kirchhoff membrane (docs/models.md; Yan 2019 for
 * F and C; docs/models.md "stvk").
 *
 * Per face whose material uses stvk, F = [wu wv] (d x 2), C = F^T F, the Green strain
 * E = (C - I)/2 in the warp/weft frame (u = warp; bias is already applied to the layout), in
 * Voigt form e = [E11, E22, 2 E12] = [(|wu|^2 - 1)/2, (|wv|^2 - 1)/2, wu.wv].  Plane-stress
 * orthotropic law (e.g. Bathe, "Finite Element Procedures", sec. 6.6; Jones, "Mechanics of
 * Composite Materials", eq. 2.61), moduli per unit rest width (thickness folded in), N/m:
 *   Q = 1/D [[E_u, nu_vu E_u, 0], [nu_uv E_v, E_v, 0], [0, 0, D G]],
 *   nu_vu = nu_uv E_v / E_u (so Q is symmetric),  D = 1 - nu_uv nu_vu,
 *   psi = 1/2 e^T Q e (J/m^2),  E = a psi.
 * With s = Q e = [S11, S22, S12] (second Piola–Kirchhoff stress, N/m):
 *   dpsi/dwu = S11 wu + S12 wv,  dpsi/dwv = S12 wu + S22 wv   (the columns of F S),
 *   P = J Q J^T + S (x) I_d,  J = [[wu, 0, wv], [0, wv, wu]] (2d x 3), S = [[S11, S12], [S12, S22]].
 * J Q J^T is PSD (Q is positive definite), so P is PSD whenever S is (stretched faces): a
 * filter then keeps P; otherwise its eigenvalues are clamped at 0 or replaced by their
 * absolute values (sw_membrane_project, as ev->project asks). */
#include <math.h>
#include <stdio.h>

#include "terms.h"
#include "util.h"

typedef struct stvk_law {
  double q11, q12, q22, g; /* N/m */
} stvk_law;

/* P = J Q J^T + S (x) I (2d x 2d, row-major). */
static void stvk_hessian(const stvk_law *q, const double *wu, const double *wv, int d,
                         const double s[3], double *P) {
  const int ld = 2 * d;
  for (int a = 0; a < d; a++)
    for (int b = 0; b < d; b++) {
      double id = a == b;
      double uv = q->q12 * wu[a] * wv[b] + q->g * wv[a] * wu[b] + s[2] * id;
      P[a * ld + b] = q->q11 * wu[a] * wu[b] + q->g * wv[a] * wv[b] + s[0] * id;
      P[(d + a) * ld + d + b] = q->q22 * wv[a] * wv[b] + q->g * wu[a] * wu[b] + s[1] * id;
      P[a * ld + d + b] = uv;
      P[(d + b) * ld + a] = uv;
    }
}

static double stvk_density(const void *law, const double *wu, const double *wv, int d,
                           int project, double *gu, double *gv, double *P) {
  const stvk_law *q = law;
  double e[3]; /* Voigt Green strain, 1 */
  sw_green_voigt(wu, wv, d, e);
  const double s[3] = {q->q11 * e[0] + q->q12 * e[1], q->q12 * e[0] + q->q22 * e[1],
                       q->g * e[2]}; /* S11, S22, S12: N/m */
  sw_green_forces(s, wu, wv, d, gu, gv);
  if (P) {
    stvk_hessian(q, wu, wv, d, s, P);
    int s_psd = s[0] >= 0.0 && s[1] >= 0.0 && s[0] * s[1] >= s[2] * s[2];
    if (project && !s_psd && sw_membrane_project(P, wu, wv, d, project)) return NAN;
  }
  return 0.5 * (e[0] * s[0] + e[1] * s[1] + e[2] * s[2]);
}

static const sw_term_ops stvk_ops = {
    .kind = "stvk", .eval = sw_membrane_eval, .free_param = sw_membrane_free,
    .sets_blocks = 1, .sink_ok = 1};

/* Q of one material, or nonzero with err naming the panel when it is not positive definite. */
static int stvk_law_of(const sw_material *mt, stvk_law *q, char *err, size_t errsz) {
  const char *who = mt->group[0] ? mt->group : "material";
  const char *kind = mt->group[0] ? "panel " : "";
  double eu = mt->e_u, ev = mt->e_v, nu = mt->nu_uv, g = mt->g_uv; /* N/m, N/m, 1, N/m */
  if (!(eu > 0.0 && ev > 0.0 && g > 0.0) || !isfinite(eu) || !isfinite(ev) || !isfinite(g) ||
      !isfinite(nu))
    return sw_errf(err, errsz, "%s%s: stvk membrane needs finite e_u, e_v, shear_modulus > 0 "
                   "and a finite poisson (got %g, %g, %g N/m and %g)", kind, who, eu, ev, g, nu),
           -1;
  double nu_vu = nu * ev / eu, det = 1.0 - nu * nu_vu; /* 1 */
  if (!(det > 0.0))
    return sw_errf(err, errsz, "%s%s: stvk poisson %g gives nu_uv nu_vu = %g >= 1 (nu_vu = "
                   "poisson e_v/e_u); |poisson| must be below sqrt(e_u/e_v) = %g", kind, who, nu,
                   nu * nu_vu, sqrt(eu / ev)),
           -1;
  *q = (stvk_law){eu / det, nu * ev / det, ev / det, g};
  return 0;
}

int sw_stvk_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  sw_membrane *mb = sw_membrane_new(t, m, &stvk_ops, SW_MEMBRANE_STVK, sizeof(stvk_law),
                                    stvk_density, err, errsz);
  if (!mb) return -1;
  stvk_law *law = mb->law;
  for (int k = 0; k < m->nmat; k++)
    if (m->mat[k].membrane == SW_MEMBRANE_STVK && stvk_law_of(&m->mat[k], &law[k], err, errsz))
      return -1;
  return 0;
}
