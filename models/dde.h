/* dde.h — the data-driven membrane of a measured fabric (models/dde.c; Wang, Ramamoorthi and
 * O'Brien, "Data-Driven Elastic Models for Cloth: Modeling and Measurement", SIGGRAPH 2011). */
#ifndef SW_DDE_H
#define SW_DDE_H

#include <stddef.h>

#include "sinew.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* The membrane term "dde" on the faces whose material has membrane dde. */
int sw_dde_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* The stiffnesses c = (c11, c12, c22, c33) (N/m, the data's own) at the Voigt Green strain
 * e = (E11, E22, 2 E12) of the warp/weft frame. */
void sw_dde_stiffness(const sw_dde *dd, const double e[3], double c[4]);
/* psi(e) (J/m^2), S = dpsi/de (N/m) and, when H is not NULL, H = d2psi/de2 (3 x 3, N/m). */
double sw_dde_energy(const sw_dde *dd, const double e[3], double S[3], double H[9]);
/* The stretch (1) of a strip pulled along u (weft 0) or v (weft 1) by the nominal tension T
 * (N per m of rest width), free across and unsheared; -1 past a stretch of sqrt(5). */
int sw_dde_uniaxial(const sw_dde *dd, int weft, double T, double *stretch);
/* The warp and weft stiffness (N/m) of a strip with stiffnesses c = (c11, c12, c22, c33), pulled
 * along u (or v) and free across: 2 (c11 - c12^2/c22), 2 (c22 - c12^2/c11). */
void sw_dde_strip_stiffness(const double c[4], double *ku, double *kv);
/* The bending rigidity B (N m) of a hinge whose edge makes `angle` (rad) with u, at curvature
 * kappa (1/m): a quarter of the data's k_e (models/dde.c), linear in the angle between the 0,
 * 45 and 90 degree rows, linear in the curvature between the columns (kappa = 0, 10, 20, 30,
 * 40 1/m), the last column's beyond 40 1/m. */
double sw_dde_bend_rigidity(const sw_dde *dd, double angle, double kappa);

/* The measured fabric's bending law (models/dde_bending.c, docs/fabrics.md "Bending by the
 * data"): the three plate rigidities D_c(r), c = warp D_u, weft D_v, twist 2 G (N m), as
 * monotone cubic Hermite curves of the curvature r (1/m) through the data's five columns and
 * held beyond 40 1/m, and Phi_c(r) = int_0^r D_c(k) k dk (J/m^2): on segment j (t = r - 10 j,
 * j = 4 beyond 40 1/m) D_c = sum_n a[c][j][n] t^n and Phi_c = sum_n p[c][j][n] t^n. */
typedef struct sw_dde_bend {
  double a[3][5][4]; /* N m per (1/m)^n */
  double p[3][5][6]; /* J/m^2 per (1/m)^n */
} sw_dde_bend;
/* The curves of the data dd; -1 with err when a rigidity is not positive or a column's bias
 * rigidity is not below 4/(1/D_u + 1/D_v) (no positive twisting rigidity G). */
int sw_dde_bend_setup(const sw_dde *dd, sw_dde_bend *b, char *err, size_t errsz);
/* D_c(r) (N m), dD_c/dr (N m^2) and Phi_c(r) (J/m^2) of curve c (0 warp, 1 weft, 2 twist). */
void sw_dde_bend_curve(const sw_dde_bend *b, int c, double r, double *D, double *dD,
                       double *Phi);
/* The energy per area psi (J/m^2) of the curvature X = (II_uu, II_vv, sqrt(2) II_uv), each a
 * d-vector (1/m): g = dpsi/dX (3d, N) and, when H is not NULL, H = d2psi/dX2 (3d x 3d
 * row-major, N m), unfiltered. */
double sw_dde_bend_density(const sw_dde_bend *b, const double *X, int d, double *g, double *H);

#endif
