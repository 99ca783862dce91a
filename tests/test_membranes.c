/* test_membranes.c — stvk and corotated (models/stvk.c, models/corotated.c): the conformance
 * harness, patch tests against the analytic first Piola–Kirchhoff traction, corotated at equal
 * stretches, parameter errors, panels, and the stiffness tension XY takes from stvk. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "terms.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

enum { NX = 4, NY = 3 };
static const double SX = 0.3, SY = 0.2;                           /* grid size, m */
static const double EU = 800.0, EV = 500.0, NU = 0.3, G = 60.0;    /* stvk, N/m and 1 */
static const double KC = 400.0;                                    /* corotated, N/m */

static void set_material(sw_material *mt, int membrane, double nu) {
  mt->density = 0.2;
  mt->membrane = membrane;
  mt->e_u = EU, mt->e_v = EV, mt->nu_uv = nu, mt->g_uv = G; /* warp != weft */
  mt->k_corot = KC;
}

/* The NX x NY grid with one membrane; NULL (and err) when sw_model_finish refuses it. */
static sw_model *membrane_model(int dim, int membrane, double nu, char *err) {
  sw_model *m = th_grid_unfinished(dim, NX, NY, SX, SY);
  assert_non_null(m);
  set_material(&m->mat[0], membrane, nu);
  if (sw_model_finish(m, err, SW_ERRSZ)) return sw_model_free(m), NULL;
  return m;
}

static int term_index(const sw_model *m, const char *name) {
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].name, name)) return k;
  fail_msg("no term %s", name);
  return -1;
}

/* E and its gradient (nv x dim) of term `name` at x. */
static double eval_grad(const sw_model *m, const char *name, const double *x, double *g) {
  const sw_term *t = &m->term[term_index(m, name)];
  memset(g, 0, sizeof(double) * (size_t)(m->nv * m->dim));
  sw_eval ev = {.x = x, .grad = g};
  double e = 0.0;
  assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
  return e;
}

/* ---------------------------------------------------------------- (a) conformance */

static void conformance(int dim, int membrane, const char *name) {
  char err[SW_ERRSZ];
  sw_model *m = membrane_model(dim, membrane, NU, err);
  assert_non_null(m);
  th_conformance(m, name, TH_INTERNAL | TH_REST_FREE, 0.3, 777 + (unsigned long)dim);
  sw_model_free(m);
}

static void stvk_conformance_3d(void **st) { (void)st, conformance(3, SW_MEMBRANE_STVK, "stvk"); }
static void stvk_conformance_2d(void **st) { (void)st, conformance(2, SW_MEMBRANE_STVK, "stvk"); }
static void corot_conformance_3d(void **st) {
  (void)st, conformance(3, SW_MEMBRANE_COROTATED, "corotated");
}
static void corot_conformance_2d(void **st) {
  (void)st, conformance(2, SW_MEMBRANE_COROTATED, "corotated");
}

/* ---------------------------------------------------------------- (b) patch tests */

/* A fixed rotation Rot (dim x dim, stored 3 x 3) so the deformed patch is not axis-aligned. */
static void rotation(int dim, double Rot[9]) {
  double a[3] = {1.0 / sqrt(14.0), 2.0 / sqrt(14.0), 3.0 / sqrt(14.0)}, th = 0.7;
  if (dim == 2) a[0] = a[1] = 0.0, a[2] = 1.0;
  double c = cos(th), s = sin(th);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double K = (i == j) ? 0.0 : (((j - i + 3) % 3 == 1) ? -1.0 : 1.0) * a[3 - i - j];
      Rot[i * 3 + j] = (i == j) * c + (1 - c) * a[i] * a[j] + s * K;
    }
}

/* Fd = Rot [F; 0] (dim x 2, stored 3 x 2) and x_i = Fd X_i with X_i the (u,v) of vertex i. */
static void uniform_state(const sw_model *m, const double F[4], double Fd[6], double *x) {
  const int d = m->dim;
  double Rot[9];
  rotation(d, Rot);
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 2; b++) Fd[a * 2 + b] = Rot[a * 3] * F[b] + Rot[a * 3 + 1] * F[2 + b];
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < d; a++)
      x[i * d + a] = Fd[a * 2] * m->x0[i * d] + Fd[a * 2 + 1] * m->x0[i * d + 1];
}

/* The analytic first Piola–Kirchhoff stress of F (2 x 2), N/m.  stvk: P = F S, S = Q e;
 * corotated: P = k (F - R), R = (F + cof F)/|F + cof F| the polar rotation of a 2 x 2 F. */
static void piola(int membrane, const double F[4], double P[4]) {
  if (membrane == SW_MEMBRANE_STVK) {
    double c11 = F[0] * F[0] + F[2] * F[2], c22 = F[1] * F[1] + F[3] * F[3];
    double c12 = F[0] * F[1] + F[2] * F[3];
    double e1 = 0.5 * (c11 - 1), e2 = 0.5 * (c22 - 1), D = 1 - NU * NU * EV / EU;
    double S11 = (EU * e1 + NU * EV * e2) / D, S22 = (NU * EV * e1 + EV * e2) / D, S12 = G * c12;
    P[0] = F[0] * S11 + F[1] * S12, P[1] = F[0] * S12 + F[1] * S22;
    P[2] = F[2] * S11 + F[3] * S12, P[3] = F[2] * S12 + F[3] * S22;
  } else {
    double p = F[0] + F[3], q = F[2] - F[1], n = sqrt(p * p + q * q);
    const double R[4] = {p / n, -q / n, q / n, p / n};
    for (int i = 0; i < 4; i++) P[i] = KC * (F[i] - R[i]);
  }
}

/* Under x = Fd X the gradient summed over the vertices of the edge u = max (v = max) per unit
 * rest length is the traction P N, N = (1, 0) ((0, 1)), exactly for linear triangles; the
 * interior vertices feel no net force. */
static void patch(int dim, int membrane, const char *name, const double F[4]) {
  char err[SW_ERRSZ];
  sw_model *m = membrane_model(dim, membrane, NU, err);
  assert_non_null(m);
  const int d = dim;
  double *x = calloc((size_t)(m->nv * d), sizeof *x), *g = calloc((size_t)(m->nv * d), sizeof *g);
  double Fd[6], P[4], Pd[6], tu[3] = {0}, tv[3] = {0}, Rot[9];
  uniform_state(m, F, Fd, x);
  eval_grad(m, name, x, g);
  piola(membrane, F, P);
  rotation(d, Rot);
  double scale = 0.0; /* N/m */
  for (int a = 0; a < d; a++)
    for (int b = 0; b < 2; b++) {
      Pd[a * 2 + b] = Rot[a * 3] * P[b] + Rot[a * 3 + 1] * P[2 + b];
      scale = fmax(scale, fabs(Pd[a * 2 + b]));
    }
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++)
      for (int a = 0; a < d; a++) {
        double gi = g[(j * NX + i) * d + a]; /* N */
        if (i == NX - 1) tu[a] += gi / SY;
        if (j == NY - 1) tv[a] += gi / SX;
        if (i > 0 && i < NX - 1 && j > 0 && j < NY - 1) assert_true(fabs(gi) < 1e-12 * scale);
      }
  for (int a = 0; a < d; a++) {
    if (fabs(tu[a] - Pd[a * 2]) > 1e-12 * scale || fabs(tv[a] - Pd[a * 2 + 1]) > 1e-12 * scale)
      print_error("%s %dD: traction (%g, %g) vs P N (%g, %g)\n", name, d, tu[a], tv[a],
                  Pd[a * 2], Pd[a * 2 + 1]);
    assert_true(fabs(tu[a] - Pd[a * 2]) <= 1e-12 * scale);
    assert_true(fabs(tv[a] - Pd[a * 2 + 1]) <= 1e-12 * scale);
  }
  free(x), free(g);
  sw_model_free(m);
}

static void patches(int membrane, const char *name) {
  const double cases[][4] = {
      {1.2, 0, 0, 1},     /* uniaxial stretch */
      {1.15, 0, 0, 0.9},  /* biaxial: stretched warp, compressed weft */
      {1, 0.3, 0, 1},     /* pure shear */
      {0.8, 0.1, -0.2, 1.3},
  };
  for (int dim = 2; dim <= 3; dim++)
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) patch(dim, membrane, name, cases[c]);
}

static void stvk_patch(void **st) { (void)st, patches(SW_MEMBRANE_STVK, "stvk"); }
static void corot_patch(void **st) { (void)st, patches(SW_MEMBRANE_COROTATED, "corotated"); }

/* ------------------------------------------------- (c) corotated at (near-)equal stretches */

static void corot_equal_stretches(void **st) {
  (void)st;
  const double c = cos(0.4), s = sin(0.4);
  const double cases[][4] = {
      {1.3 * c, -1.3 * s, 1.3 * s, 1.3 * c}, /* s R: sigma1 = sigma2 = 1.3 */
      {0.6 * c, -0.6 * s, 0.6 * s, 0.6 * c}, /* compressed, equal */
      {1 + 1e-4, 0, 0, 1 + 1e-4},            /* next to rest (there the gradient is 0) */
      {1.3, 0, 0, 1.3 + 1e-7},               /* near-equal */
      {0.7 * c, -0.7 * s, (0.7 + 1e-9) * s, (0.7 + 1e-9) * c},
  };
  char err[SW_ERRSZ];
  for (int dim = 2; dim <= 3; dim++) {
    sw_model *m = membrane_model(dim, SW_MEMBRANE_COROTATED, NU, err);
    assert_non_null(m);
    double *x = calloc((size_t)(m->nv * dim), sizeof *x), *g = calloc((size_t)(m->nv * dim), sizeof *g);
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
      double Fd[6];
      uniform_state(m, cases[k], Fd, x);
      th_conformance_at(m, "corotated", TH_NO_PROJECTION, 0.3, x);
      /* energy k/2 sum (sigma - 1)^2 times the rest area SX SY */
      double s1 = hypot(cases[k][0], cases[k][2]), s2 = fabs(cases[k][0] * cases[k][3] -
                                                         cases[k][1] * cases[k][2]) / s1;
      double want = 0.5 * KC * ((s1 - 1) * (s1 - 1) + (s2 - 1) * (s2 - 1)) * SX * SY;
      if (k != 3) assert_float_equal(eval_grad(m, "corotated", x, g), want, 1e-12 * KC * SX * SY);
    }
    free(x), free(g);
    sw_model_free(m);
  }
}

/* ---------------------------------------------------------------- (d) parameter errors */

static void stvk_bad_poisson(void **st) {
  (void)st;
  char err[SW_ERRSZ] = "";
  /* nu_uv nu_vu = 1.3^2 * 500/800 = 1.056 >= 1: Q indefinite */
  assert_null(membrane_model(3, SW_MEMBRANE_STVK, 1.3, err));
  assert_non_null(strstr(err, "material: stvk poisson 1.3"));
  /* a negative Poisson ratio is fine as long as Q is positive definite */
  sw_model *m = membrane_model(2, SW_MEMBRANE_STVK, -0.5, err);
  assert_non_null(m);
  sw_model_free(m);
}

static void bad_moduli(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = th_grid_unfinished(2, NX, NY, SX, SY);
  set_material(&m->mat[0], SW_MEMBRANE_STVK, NU);
  m->mat[0].g_uv = 0.0;
  assert_int_not_equal(sw_model_finish(m, err, sizeof err), 0);
  assert_non_null(strstr(err, "shear_modulus > 0"));
  sw_model_free(m);
  m = th_grid_unfinished(2, NX, NY, SX, SY);
  set_material(&m->mat[0], SW_MEMBRANE_COROTATED, NU);
  m->mat[0].k_corot = NAN;
  assert_int_not_equal(sw_model_finish(m, err, sizeof err), 0);
  assert_non_null(strstr(err, "corotated membrane needs a finite k > 0"));
  sw_model_free(m);
}

/* ------------------------------------------------------- panels and tension XY stiffness */

/* mat[0] bw98, panel "sleeve" (faces of the right half) stvk: each term covers only its faces;
 * an error in the panel names it. */
static void panels(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  for (int bad = 0; bad < 2; bad++) {
    sw_model *m = th_grid_unfinished(3, NX, NY, SX, SY);
    set_material(&m->mat[0], SW_MEMBRANE_BW98, NU);
    m->mat[0].k_u = m->mat[0].k_v = 300.0, m->mat[0].k_shear = 20.0;
    m->mat = realloc(m->mat, 2 * sizeof *m->mat);
    m->nmat = 2;
    m->mat[1] = m->mat[0];
    snprintf(m->mat[1].group, sizeof m->mat[1].group, "sleeve");
    set_material(&m->mat[1], SW_MEMBRANE_STVK, bad ? 2.0 : NU);
    m->face_mat = calloc((size_t)m->nf, sizeof(int));
    int nright = 0;
    for (int f = 0; f < m->nf; f++) {
      double u = (m->uv[6 * f] + m->uv[6 * f + 2] + m->uv[6 * f + 4]) / 3.0;
      nright += (m->face_mat[f] = u > 0.5 * SX);
    }
    if (bad) {
      assert_int_not_equal(sw_model_finish(m, err, sizeof err), 0);
      assert_non_null(strstr(err, "panel sleeve: stvk poisson 2"));
    } else {
      assert_int_equal(sw_model_finish(m, err, sizeof err), 0);
      assert_int_equal(m->term[term_index(m, "stvk")].nstencil, nright);
      assert_int_equal(m->term[term_index(m, "bw98")].nstencil, m->nf - nright);
      th_conformance(m, "stvk", TH_INTERNAL | TH_REST_FREE, 0.3, 99);
    }
    sw_model_free(m);
  }
}

/* Tension XY reports k_u (lu - 1): for stvk that is the small-strain stress of a strip pulled
 * along the warp with the weft free (S22 = 0), which is E_u, not Q11 = E_u / D. */
static void stvk_strip_stiffness(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = membrane_model(2, SW_MEMBRANE_STVK, NU, err);
  assert_non_null(m);
  double *x = calloc((size_t)(m->nv * 2), sizeof *x), *g = calloc((size_t)(m->nv * 2), sizeof *g);
  const double eps = 1e-6, q11 = EU / (1 - NU * NU * EV / EU), q12 = NU * EV / (1 - NU * NU * EV / EU);
  const double q22 = EV / (1 - NU * NU * EV / EU);
  for (int dir = 0; dir < 2; dir++) {
    double l = 1 + eps, e = 0.5 * (l * l - 1), lat = sqrt(1 - 2 * q12 * e / (dir ? q11 : q22));
    const double F[4] = {dir ? lat : l, 0, 0, dir ? l : lat}; /* S in the other direction 0 */
    double Fd[6], traction = 0.0; /* N/m */
    uniform_state(m, F, Fd, x);
    /* rotation(2) turns x; |sum of gradient| over the pulled edge is rotation-free */
    eval_grad(m, "stvk", x, g);
    double t[2] = {0, 0};
    for (int j = 0; j < NY; j++)
      for (int i = 0; i < NX; i++)
        if (dir ? j == NY - 1 : i == NX - 1)
          for (int a = 0; a < 2; a++) t[a] += g[(j * NX + i) * 2 + a] / (dir ? SX : SY);
    traction = hypot(t[0], t[1]);
    double k = dir ? m->mat[0].tx_k_v : m->mat[0].tx_k_u;
    assert_float_equal(k, dir ? EV : EU, 0.0);
    assert_true(fabs(traction / eps - k) < 1e-5 * k);
  }
  free(x), free(g);
  sw_model_free(m);
}

/* ------------------------------------------------------------------ PSD projection */

/* The filtered matrix by LAPACK: V max(w, 0) V^T (clamp, the nearest PSD matrix) or
 * V |w| V^T (abs). */
static void lapack_psd(double *A, int n, int mode) {
  double w[6], work[256];
  int lwork = 256, info = 0;
  double V[36], R[36] = {0};
  memcpy(V, A, sizeof(double) * (size_t)(n * n));
  dsyev_("V", "U", &n, V, &n, w, work, &lwork, &info);
  assert_int_equal(info, 0);
  for (int k = 0; k < n; k++)
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) R[i * n + j] += (mode == SW_FILTER_ABS ? fabs(w[k]) : fmax(w[k], 0.0)) *
                                             V[k * n + i] * V[k * n + j];
  memcpy(A, R, sizeof(double) * (size_t)(n * n));
}

/* sw_psd_project (models/eigen.c's solver) and sw_membrane_project (in-plane and normal
 * blocks) against LAPACK, on random P = J M J^T + S (x) I, the form of the Hessian of any density of C (stvk.c), with
 * both filters: clamped eigenvalues (the nearest PSD matrix) and absolute ones. */
static void psd_projection(void **st) {
  (void)st;
  unsigned long rs = 4242;
  for (int rep = 0; rep < 400; rep++) {
    int d = 2 + rep % 2, n = 2 * d, mode = rep % 4 < 2 ? SW_FILTER_CLAMP : SW_FILTER_ABS;
    double wu[3] = {0}, wv[3] = {0}, M[9], S[3], P[36], A[36], B[36];
    for (int a = 0; a < d; a++) wu[a] = th_rand(&rs), wv[a] = th_rand(&rs);
    if (rep % 10 == 9) memcpy(wv, wu, sizeof wu); /* degenerate: parallel columns */
    for (int i = 0; i < 3; i++) {
      S[i] = th_rand(&rs);
      for (int j = 0; j <= i; j++) M[i * 3 + j] = M[j * 3 + i] = th_rand(&rs);
    }
    double J[6][3] = {{0}}; /* rows: [wu; wv] components; columns: e11, e22, 2 e12 */
    for (int a = 0; a < d; a++) {
      J[a][0] = wu[a], J[a][2] = wv[a];
      J[d + a][1] = wv[a], J[d + a][2] = wu[a];
    }
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) {
        double v = 0.0;
        for (int p = 0; p < 3; p++)
          for (int q = 0; q < 3; q++) v += J[i][p] * M[p * 3 + q] * J[j][q];
        int bi = i / d, bj = j / d; /* S (x) I */
        if (i % d == j % d) v += bi == bj ? S[bi] : S[2];
        P[i * n + j] = v;
      }
    memcpy(A, P, sizeof P), memcpy(B, P, sizeof P);
    assert_int_equal(sw_psd_project(A, n, mode), 0);
    assert_int_equal(sw_membrane_project(B, wu, wv, d, mode), 0);
    lapack_psd(P, n, mode);
    for (int i = 0; i < n * n; i++) {
      assert_true(fabs(A[i] - P[i]) < 1e-12);
      assert_true(fabs(B[i] - P[i]) < 1e-12);
    }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(stvk_conformance_3d),   cmocka_unit_test(stvk_conformance_2d),
      cmocka_unit_test(corot_conformance_3d),  cmocka_unit_test(corot_conformance_2d),
      cmocka_unit_test(stvk_patch),            cmocka_unit_test(corot_patch),
      cmocka_unit_test(corot_equal_stretches), cmocka_unit_test(stvk_bad_poisson),
      cmocka_unit_test(bad_moduli),            cmocka_unit_test(panels),
      cmocka_unit_test(stvk_strip_stiffness),  cmocka_unit_test(psd_projection),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
