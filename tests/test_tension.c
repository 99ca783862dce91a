/* test_tension.c — tension XY (Optitex) against its worked example and analytic cases. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"

/* Optitex's worked example triangle: uv (0,0), (1,0), (0,1); positions the same in the plane
 * z = 0; its material still to be set, the model not finished. */
static sw_model *unit_triangle(void) {
  sw_model *m = sw_model_new();
  m->dim = 3;
  m->nv = 3;
  m->nf = 1;
  m->x0 = calloc(9, sizeof(double));
  m->v0 = calloc(9, sizeof(double));
  m->pinned = calloc(3, 1);
  m->face = calloc(3, sizeof(int));
  m->uv = calloc(6, sizeof(double));
  const double uv[6] = {0, 0, 1, 0, 0, 1};
  for (int i = 0; i < 3; i++) {
    m->face[i] = i;
    m->x0[3 * i] = uv[2 * i];
    m->x0[3 * i + 1] = uv[2 * i + 1];
  }
  memcpy(m->uv, uv, sizeof uv);
  return m;
}

static sw_model *seed_triangle(double ku, double kv, int reference_uv) {
  sw_model *m = unit_triangle();
  m->mat[0].density = 0.1;
  m->mat[0].membrane = SW_MEMBRANE_BW98;
  m->mat[0].k_u = ku;
  m->mat[0].k_v = kv;
  m->mat[0].k_shear = 10;
  m->opt.tx_reference_uv = reference_uv;
  char err[SW_ERRSZ];
  assert_int_equal(sw_model_finish(m, err, sizeof err), 0);
  return m;
}

static double tension_at(sw_model *m, const double x[9]) {
  sw_data *d = sw_data_new(m);
  memcpy(d->x, x, 9 * sizeof(double));
  sw_tension_xy(m, d);
  double t = d->txy[0];
  sw_data_free(d);
  return t;
}

/* The worked example: p1 moved to (1.1, 0, 0) gives 0.1 k_u (lu = 1.1, lv = 1). */
static void worked_example(void **st) {
  (void)st;
  for (int ref = 0; ref < 2; ref++) {
    sw_model *m = seed_triangle(2000.0, 800.0, ref);
    const double x[9] = {0, 0, 0, 1.1, 0, 0, 0, 1, 0};
    assert_float_equal(tension_at(m, x), 0.1 * 2000.0, 1e-9);
    sw_model_free(m);
  }
}

/* The stiffness is clipped at 5e4 N/m (Optitex). */
static void clipped(void **st) {
  (void)st;
  sw_model *m = seed_triangle(2e5, 800.0, 1);
  const double x[9] = {0, 0, 0, 1.1, 0, 0, 0, 1, 0};
  assert_float_equal(tension_at(m, x), 0.1 * 5e4, 1e-7);
  sw_model_free(m);
}

/* A measured fabric (the dde membrane, gray-interlock's rows as its file gives them, the
 * negative ones 0): tension XY reads its stiffness at the face's own strain.  Stretched by
 * 1.2 along u (beyond the data's 7/6, along 0 degrees) it is 0.2 x 2 (c11 - c12^2/c22) of the
 * 0-degree row; along v, 0.2 x 2 (c22 - c12^2/c11) of the 90-degree row; with a tension_xy
 * stiffness given, that one. */
static void measured_fabric(void **st) {
  (void)st;
  static const double rows[6][4] = {
      {16.593832, 0.0, 34.477123, 36.860302},    {46.364765, 53.694656, 261.013855, 0.0},
      {49.285110, 87.596100, 206.373993, 22.768457}, {123.989220, 105.181770, 365.966217, 44.217571},
      {139.686325, 73.592560, 413.553162, 0.0},  {127.443810, 85.848587, 405.872833, 32.238411}};
  for (int given = 0; given < 2; given++) {
    sw_model *m = unit_triangle();
    m->mat[0].density = 0.187;
    m->mat[0].membrane = SW_MEMBRANE_DDE;
    memcpy(m->mat[0].dde.stretch, rows, sizeof rows);
    m->mat[0].dde.density = 0.187;
    if (given) m->opt.tx_k_u = m->opt.tx_k_v = 500.0;
    m->opt.tx_reference_uv = 1;
    char err[SW_ERRSZ];
    assert_int_equal(sw_model_finish(m, err, sizeof err), 0);
    const double xu[9] = {0, 0, 0, 1.2, 0, 0, 0, 1, 0}, xv[9] = {0, 0, 0, 1, 0, 0, 0, 1.2, 0};
    double ku = 2.0 * (rows[1][0] - rows[1][1] * rows[1][1] / rows[1][2]);
    double kv = 2.0 * (rows[5][2] - rows[5][1] * rows[5][1] / rows[5][0]);
    if (given) ku = kv = 500.0;
    assert_float_equal(tension_at(m, xu), 0.2 * ku, 1e-9);
    assert_float_equal(tension_at(m, xv), 0.2 * kv, 1e-9);
    sw_model_free(m);
  }
}

/* Any rotation and translation of the rest shape: 0.  Compression is ignored: 0. */
static void rotation_and_compression(void **st) {
  (void)st;
  sw_model *m = seed_triangle(2000.0, 800.0, 1);
  double c = cos(0.7), s = sin(0.7), x[9];
  const double rest[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (int i = 0; i < 3; i++) { /* rotate about the axis (1,1,1)/sqrt3 by building R x */
    const double *p = rest + 3 * i;
    double k[3] = {1 / sqrt(3.0), 1 / sqrt(3.0), 1 / sqrt(3.0)};
    double kx[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]};
    double kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
    for (int a = 0; a < 3; a++) x[3 * i + a] = p[a] * c + kx[a] * s + k[a] * kp * (1 - c) + 0.3;
  }
  assert_float_equal(tension_at(m, x), 0.0, 1e-9);
  const double squeezed[9] = {0, 0, 0, 0.8, 0, 0, 0, 0.9, 0};
  assert_float_equal(tension_at(m, squeezed), 0.0, 1e-12);
  sw_model_free(m);
}

/* Warp and weft both stretched by 10 %, orthogonal: |(0.1 k_u, 0.1 k_v)|; sheared so that
 * wu.wv < 0: the difference is taken, |wu - wv|. */
static void biaxial_and_shear(void **st) {
  (void)st;
  sw_model *m = seed_triangle(2000.0, 800.0, 1);
  const double x[9] = {0, 0, 0, 1.1, 0, 0, 0, 1.1, 0};
  assert_float_equal(tension_at(m, x), 0.1 * hypot(2000.0, 800.0), 1e-9);
  /* wu = (1.2, 0, 0), wv = (-0.6, 0.8, 0): |wv| = 1, so only the warp term: 0.2 k_u. */
  const double y[9] = {0, 0, 0, 1.2, 0, 0, -0.6, 0.8, 0};
  assert_float_equal(tension_at(m, y), 0.2 * 2000.0, 1e-9);
  /* wu = (1.2,0,0), wv = (-0.66, 0.88, 0) (|wv| = 1.1): amp 400 and 80 along directions with a
   * negative dot product; the value is |400 e_u - 80 e_v|. */
  const double z[9] = {0, 0, 0, 1.2, 0, 0, -0.66, 0.88, 0};
  double eu[2] = {1, 0}, ev[2] = {-0.6, 0.8};
  double want = hypot(400 * eu[0] - 80 * ev[0], 400 * eu[1] - 80 * ev[1]);
  assert_float_equal(tension_at(m, z), want, 1e-9);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(worked_example),
      cmocka_unit_test(clipped), cmocka_unit_test(measured_fabric),
      cmocka_unit_test(rotation_and_compression),
      cmocka_unit_test(biaxial_and_shear),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
