/* test_compact.c — the compact bending matrix (models/compact.c): on a jittered grid, for
 * quadratic and morley bending in 2D and 3D, the same energy and gradient as the exact term;
 * a matrix that keeps every entry between vertices sharing a face, is zero between the others,
 * carries each dropped entry's absolute value on its diagonals, and bounds the exact one from
 * above (C - Q positive semi-definite); stencils on the faces.  A hanging cloth with morley
 * bending reaches the same static equilibrium and the same backward-Euler trajectory (to the
 * Newton tolerance) with either matrix; the scene key and its bad values. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "scene.h"
#include "terms.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

/* A grid of nx x ny vertices over 0.3 x 0.25 m, its interior jittered by 20 % of a spacing,
 * bending with `model` (k_b 2e-3 N m), its Newton matrix `bmatrix` (SW_BMATRIX_*). */
static sw_model *grid(int dim, int nx, int ny, int model, int bmatrix, unsigned long seed) {
  sw_model *m = th_jittered_unfinished(dim, nx, ny, seed);
  sw_material mt = {.density = 0.2, .bending = model, .k_bend = 2e-3,
                    .bend_rest = SW_BEND_REST_FLAT, .b_u = 1.0, .b_v = 1.0, .tx_k_u = -1.0,
                    .tx_k_v = -1.0};
  m->mat[0] = mt;
  m->opt.bending_matrix = bmatrix;
  return th_finish(m);
}

static int term_index(const sw_model *m, const char *name) {
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].name, name)) return k;
  fail_msg("no term %s", name);
  return -1;
}

/* Energy, gradient (n) and dense Hessian (n x n) of term k at x. */
static double eval_dense(const sw_model *m, int k, const double *x, double *g, double *H) {
  const sw_term *t = &m->term[k];
  const int n = m->nv * m->dim;
  double *blocks = calloc((size_t)t->hptr[t->nstencil] + 1, sizeof(double));
  memset(g, 0, sizeof(double) * (size_t)n);
  sw_eval ev = {.x = x, .grad = g, .hess = blocks};
  double e = 0.0;
  assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
  th_dense_hessian(m, k, blocks, H);
  free(blocks);
  return e;
}

static int share_face(const sw_model *m, int a, int b) {
  for (int f = 0; f < m->nf; f++)
    if (sw_face_corner(m, f, a) >= 0 && sw_face_corner(m, f, b) >= 0) return 1;
  return 0;
}

static double min_eigenvalue(double *A, int n) {
  double *w = malloc(sizeof(double) * (size_t)n), wq;
  int lw = -1, info = 0;
  dsyev_("N", "U", &n, A, &n, w, &wq, &lw, &info);
  lw = (int)wq;
  double *work = malloc(sizeof(double) * (size_t)lw);
  dsyev_("N", "U", &n, A, &n, w, work, &lw, &info);
  assert_int_equal(info, 0);
  double lo = w[0];
  free(w);
  free(work);
  return lo;
}

static void compact_matrix(int dim, int model, const char *name) {
  sw_model *me = grid(dim, 7, 6, model, SW_BMATRIX_EXACT, 17);
  sw_model *mc = grid(dim, 7, 6, model, SW_BMATRIX_COMPACT, 17);
  assert_non_null(me);
  assert_non_null(mc);
  const int ke = term_index(me, name), kc = term_index(mc, name), n = me->nv * dim;
  const sw_term *tc = &mc->term[kc];
  assert_int_equal(tc->nstencil, mc->nf); /* one stencil per face: the membrane's pattern */
  for (int f = 0; f < mc->nf; f++) {
    assert_int_equal(tc->sptr[f + 1] - tc->sptr[f], 3);
    for (int c = 0; c < 3; c++) assert_int_equal(tc->sidx[3 * f + c], mc->face[3 * f + c]);
  }
  unsigned long seed = 5;
  double *x = malloc(sizeof(double) * (size_t)n), *ge = malloc(sizeof(double) * (size_t)n),
         *gc = malloc(sizeof(double) * (size_t)n);
  for (int i = 0; i < n; i++) x[i] = me->x0[i] + 0.01 * th_rand(&seed);
  double *He = calloc((size_t)n * n, sizeof(double)), *Hc = calloc((size_t)n * n, sizeof(double));
  double ee = eval_dense(me, ke, x, ge, He), ec = eval_dense(mc, kc, x, gc, Hc);
  assert_true(ee > 0.0);
  assert_true(ec == ee); /* the same code on the same stencils */
  assert_true(th_max_diff(ge, gc, n) == 0.0);
  double scale = 0.0;
  for (long q = 0; q < (long)n * n; q++) scale = fmax(scale, fabs(He[q]));
  long dropped = 0;
  for (int a = 0; a < me->nv; a++)
    for (int c = 0; c < dim; c++) {
      const long r = (long)a * dim + c;
      double moved = 0.0; /* |dropped entries| of row r */
      for (int b = 0; b < me->nv; b++) {
        if (b == a) continue;
        const int near = share_face(me, a, b);
        for (int cc = 0; cc < dim; cc++) {
          const long col = (long)b * dim + cc;
          if (near) {
            assert_true(fabs(Hc[r * n + col] - He[r * n + col]) <= 1e-12 * scale);
          } else {
            assert_true(Hc[r * n + col] == 0.0);
            moved += fabs(He[r * n + col]);
            dropped += He[r * n + col] != 0.0;
          }
        }
      }
      assert_true(fabs(Hc[r * n + r] - He[r * n + r] - moved) <= 1e-12 * scale);
    }
  assert_true(dropped > 0); /* the stencils did reach past the faces */
  for (long q = 0; q < (long)n * n; q++) Hc[q] -= He[q];
  double lo = min_eigenvalue(Hc, n);
  print_message("%s %dD: %ld entries moved onto the diagonal, min eig(C - Q) = %.3e (scale %.3e)\n",
                name, dim, dropped, lo, scale);
  assert_true(lo >= -1e-12 * scale);
  free(x), free(ge), free(gc), free(He), free(Hc);
  sw_model_free(me);
  sw_model_free(mc);
}
static void morley_3d(void **st) { (void)st, compact_matrix(3, SW_BENDING_MORLEY, "morley"); }
static void morley_2d(void **st) { (void)st, compact_matrix(2, SW_BENDING_MORLEY, "morley"); }
static void quadratic_3d(void **st) {
  (void)st, compact_matrix(3, SW_BENDING_QUADRATIC, "quadratic");
}
static void quadratic_2d(void **st) {
  (void)st, compact_matrix(2, SW_BENDING_QUADRATIC, "quadratic");
}

/* A 0.4 m cloth of 9 x 9 vertices pinned at two corners, soft in bending, hanging. */
static sw_model *hanging(const char *bmatrix, const char *method) {
  char text[1024];
  snprintf(text, sizeof text,
           "dimension: 3\n"
           "mesh: {grid: {size: [0.4, 0.4], vertices: [9, 9], plane: xz}}\n"
           "material: {density: 0.2, membrane: {model: bw98, k_u: 500, k_v: 500, k_shear: 50},\n"
           "           bending: {model: morley, stiffness: 1e-4}}\n"
           "pins: [{select: {grid: [[0, -1], [-1, -1]]}}]\n"
           "gravity: [0, 0, -9.81]\n"
           "integrator: {method: %s, dt: 0.01, bending_matrix: %s,\n"
           "             newton: {tol: 1e-8}}\n"
           "duration: 0.3\n",
           method, bmatrix);
  return th_scene("hanging", text);
}

static void same_answer(void **st) {
  (void)st;
  const char *kind[2] = {"exact", "compact"};
  double *x[2] = {NULL, NULL};
  long its[2];
  int nv = 0;
  for (int k = 0; k < 2; k++) {
    sw_model *m = hanging(kind[k], "backward-euler");
    assert_non_null(m);
    char err[SW_ERRSZ];
    sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
    assert_non_null(s);
    assert_int_equal(sw_sim_run(s, 0.3, err, sizeof err), 0);
    const sw_data *d = sw_sim_data(s);
    nv = m->nv;
    x[k] = malloc(sizeof(double) * 3 * (size_t)nv);
    memcpy(x[k], d->x, sizeof(double) * 3 * (size_t)nv);
    its[k] = d->nnewton;
    sw_sim_free(s);
    sw_model_free(m);
  }
  const double diff = th_max_diff(x[0], x[1], 3 * nv);
  print_message("backward Euler, 30 steps: Newton iterations %ld exact, %ld compact; positions "
                "differ by %.3e m\n", its[0], its[1], diff);
  assert_true(diff < 1e-8); /* tol dt per step: 1e-10 m */
  for (int k = 0; k < 2; k++) free(x[k]);
  for (int k = 0; k < 2; k++) {
    sw_model *m = hanging(kind[k], "static");
    assert_non_null(m);
    sw_data *d = sw_data_new(m);
    double r[3];
    assert_int_equal(th_static(m, d, r), 0);
    x[k] = malloc(sizeof(double) * 3 * (size_t)m->nv);
    memcpy(x[k], d->x, sizeof(double) * 3 * (size_t)m->nv);
    sw_data_free(d);
    sw_model_free(m);
  }
  const double sdiff = th_max_diff(x[0], x[1], 3 * nv);
  print_message("static equilibrium: positions differ by %.3e m\n", sdiff);
  assert_true(sdiff < 1e-9);
  for (int k = 0; k < 2; k++) free(x[k]);
}

/* The key, and auto's rule: compact for a time-stepping method, exact for the static one (a
 * bending-dominated static solve does not converge with compact: tests/test_fabric.c's
 * cantilever) and for the optimisation fits, whatever the --method override says. */
static void scene_key(void **st) {
  (void)st;
  const struct { const char *key, *method, *override; int want; } c[] = {
      {"compact", "static", NULL, SW_BMATRIX_COMPACT},
      {"exact", "backward-euler", NULL, SW_BMATRIX_EXACT},
      {"auto", "backward-euler", NULL, SW_BMATRIX_COMPACT},
      {"auto", "bdf2", NULL, SW_BMATRIX_COMPACT},
      {"auto", "static", NULL, SW_BMATRIX_EXACT},
      {"auto", "backward-euler", "static", SW_BMATRIX_EXACT},
      {"auto", "static", "backward-euler", SW_BMATRIX_COMPACT}};
  for (size_t k = 0; k < sizeof c / sizeof *c; k++) {
    char text[1024];
    snprintf(text, sizeof text,
             "dimension: 3\nmesh: {grid: {size: [0.4, 0.4], vertices: [5, 5]}}\n"
             "material: {density: 0.2, bending: {model: quadratic, stiffness: 1e-4}}\n"
             "integrator: {method: %s, bending_matrix: %s}\n", c[k].method, c[k].key);
    sw_scene_overrides ov = {.method = c[k].override};
    char err[SW_ERRSZ];
    sw_model *m = sw_scene_parse_ex("key.yaml", text, strlen(text), &ov, err, sizeof err);
    if (!m) fail_msg("%s", err);
    assert_int_equal(m->opt.bending_matrix, c[k].want);
    sw_model_free(m);
  }
  const char *fit = "dimension: 3\nmesh: {grid: {size: [0.4, 0.4], vertices: [5, 5]}}\n"
                    "material: {density: 0.2, bending: {model: quadratic, stiffness: 1e-4}}\n"
                    "fit: {mode: optimize}\n";
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_parse("fit.yaml", fit, strlen(fit), err, sizeof err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->opt.bending_matrix, SW_BMATRIX_EXACT);
  sw_model_free(m);
  const char *bad = "dimension: 3\nmesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
                    "material: {density: 0.1}\nintegrator: {bending_matrix: lumped}\n";
  assert_null(sw_scene_parse("bad.yaml", bad, strlen(bad), err, sizeof err));
  print_message("%s\n", err);
  assert_non_null(strstr(err, "bad.yaml:4:"));
  assert_non_null(strstr(err, "compact"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(morley_3d),    cmocka_unit_test(morley_2d),
      cmocka_unit_test(quadratic_3d), cmocka_unit_test(quadratic_2d),
      cmocka_unit_test(same_answer),  cmocka_unit_test(scene_key),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
