/* test_inverse.c — the tendon inverse problem (solvers/inverse.c, nnls.c, inverse_check.c,
 * sim/input/targets.c, sim/input/scene_write.c; docs/inverse.md): NNLS against known answers and a
 * brute-force enumeration of active sets, recovery of known tensions on cable nets in 2D and 3D,
 * unreachable targets, the forward check, the targets CSV and its errors, the rewritten scene,
 * and the point-load term. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "harness.h"
#include "inverse.h"
#include "scene.h"
#include "util.h"

/* ------------------------------------------------------------------ NNLS */

/* Solve the p x p system M y = r in place (Gaussian elimination, partial pivoting); 0 if
 * singular. */
static int gauss(double *M, double *r, int p) {
  for (int c = 0; c < p; c++) {
    int piv = c;
    for (int i = c + 1; i < p; i++)
      if (fabs(M[i * p + c]) > fabs(M[piv * p + c])) piv = i;
    if (fabs(M[piv * p + c]) < 1e-12) return 0;
    for (int j = 0; j < p; j++) {
      double t = M[c * p + j];
      M[c * p + j] = M[piv * p + j], M[piv * p + j] = t;
    }
    double t = r[c];
    r[c] = r[piv], r[piv] = t;
    for (int i = c + 1; i < p; i++) {
      double f = M[i * p + c] / M[c * p + c];
      for (int j = c; j < p; j++) M[i * p + j] -= f * M[c * p + j];
      r[i] -= f * r[c];
    }
  }
  for (int c = p - 1; c >= 0; c--) {
    for (int j = c + 1; j < p; j++) r[c] -= M[c * p + j] * r[j];
    r[c] /= M[c * p + c];
  }
  return 1;
}

static double objective(int m, int n, const double *A, const double *b, const double *x) {
  double s = 0.0;
  for (int i = 0; i < m; i++) {
    double r = -b[i];
    for (int j = 0; j < n; j++) r += A[j * m + i] * x[j];
    s += r * r;
  }
  return 0.5 * s;
}

/* The NNLS optimum by enumeration: every subset S of columns, its unconstrained least squares
 * (normal equations), kept when all >= 0; the smallest objective. */
static double brute_force(int m, int n, const double *A, const double *b, double *best) {
  double fbest = objective(m, n, A, b, (double[16]){0});
  memset(best, 0, (size_t)n * sizeof *best);
  for (unsigned s = 1; s < (1u << n); s++) {
    int idx[16], p = 0;
    for (int j = 0; j < n; j++)
      if (s & (1u << j)) idx[p++] = j;
    double M[256], r[16], x[16] = {0};
    for (int a = 0; a < p; a++) {
      r[a] = 0.0;
      for (int i = 0; i < m; i++) r[a] += A[idx[a] * m + i] * b[i];
      for (int c = 0; c < p; c++) {
        M[a * p + c] = 0.0;
        for (int i = 0; i < m; i++) M[a * p + c] += A[idx[a] * m + i] * A[idx[c] * m + i];
      }
    }
    if (!gauss(M, r, p)) continue;
    int ok = 1;
    for (int a = 0; a < p; a++) ok &= r[a] >= 0.0, x[idx[a]] = r[a];
    double f = objective(m, n, A, b, x);
    if (ok && f < fbest) fbest = f, memcpy(best, x, (size_t)n * sizeof *x);
  }
  return fbest;
}

static void nnls_identity(void **st) {
  (void)st;
  const double A[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, b[3] = {1, -2, 3};
  double x[3];
  char err[256];
  assert_int_equal(sw_nnls(3, 3, A, b, x, 0.0, 0, NULL, err, sizeof err), SW_OK);
  assert_true(fabs(x[0] - 1) < 1e-14 && x[1] == 0.0 && fabs(x[2] - 3) < 1e-14);
}

/* By hand: columns (1,0,0) and (1,1,0), b = (-1, 2, 5).  Unconstrained least squares gives
 * x = (-3, 2); at x = 0, w = A^T b = (-1, 1) frees column 2 alone: x = (0, 1/2). */
static void nnls_by_hand(void **st) {
  (void)st;
  const double A[6] = {1, 0, 0, 1, 1, 0}, b[3] = {-1, 2, 5};
  double x[2];
  char err[256];
  assert_int_equal(sw_nnls(3, 2, A, b, x, 0.0, 0, NULL, err, sizeof err), SW_OK);
  assert_true(x[0] == 0.0 && fabs(x[1] - 0.5) < 1e-14);
}

/* Random problems whose unconstrained least squares has negative components, tall, square and
 * wide: NNLS reaches the brute-force optimum and satisfies the KKT conditions. */
static void nnls_against_enumeration(void **st) {
  (void)st;
  static const int shapes[][2] = {{6, 4}, {5, 5}, {3, 6}, {8, 7}, {2, 2}};
  unsigned long seed = 7;
  int negative_seen = 0;
  for (int trial = 0; trial < 60; trial++) {
    int m = shapes[trial % 5][0], n = shapes[trial % 5][1], it = 0;
    double A[64], b[8], x[8], xb[16], w;
    for (int i = 0; i < m * n; i++) A[i] = th_rand(&seed);
    for (int i = 0; i < m; i++) b[i] = 3.0 * th_rand(&seed);
    char err[256];
    assert_int_equal(sw_nnls(m, n, A, b, x, 0.0, 0, &it, err, sizeof err), SW_OK);
    double fb = brute_force(m, n, A, b, xb), f = objective(m, n, A, b, x);
    assert_true(f <= fb * (1 + 1e-10) + 1e-12);
    for (int j = 0; j < n; j++) {
      assert_true(x[j] >= 0.0);
      negative_seen |= x[j] == 0.0;
      w = 0.0; /* KKT: w_j = [A^T (b - A x)]_j <= 0, and = 0 where x_j > 0 */
      for (int i = 0; i < m; i++) {
        double r = b[i];
        for (int k = 0; k < n; k++) r -= A[k * m + i] * x[k];
        w += A[j * m + i] * r;
      }
      assert_true(w <= 1e-9);
      if (x[j] > 0.0) assert_true(fabs(w) <= 1e-9);
    }
    assert_true(it <= 3 * n);
  }
  assert_true(negative_seen); /* some answers sit on the constraints */
}

/* A dependent column (a copy of another) and a zero column: no blow-up, the optimum. */
static void nnls_degenerate_columns(void **st) {
  (void)st;
  const double A[16] = {1, 2, 0, 1, /* col 1 = col 0 */ 1, 2, 0, 1, 0, 1, 1, 0, 0, 0, 0, 0};
  const double b[4] = {2, 5, 1, 2};
  double x[4], xb[4];
  char err[256];
  assert_int_equal(sw_nnls(4, 4, A, b, x, 0.0, 0, NULL, err, sizeof err), SW_OK);
  assert_true(objective(4, 4, A, b, x) <= brute_force(4, 4, A, b, xb) + 1e-12);
  assert_true(x[3] == 0.0);
}

/* --------------------------------------------------------------- cable nets */

static const char net2d[] =
    "dimension: 2\n"
    "mesh: {points: [[0, 0], [2, 0], [0, 2], [2, 2], [0.8, 0.9], [1.2, 0.9], [1, 2.4]]}\n"
    "pins: [{select: {vertices: [0, 1, 2, 3, 6]}}]\n"
    "tendons:\n"
    "  - {name: bottom, waypoints: [0, 4, 5, 1], stiffness: 1000, density: 0.01}\n"
    "  - {name: left, waypoints: [2, 4], stiffness: 1000, density: 0.01}\n"
    "  - {name: right, waypoints: [3, 5], stiffness: 800, density: 0.01}\n"
    "  - {name: top, waypoints: [6, 5, 4], law: spring, stiffness: 1200, density: 0.01}\n";

static const char net3d[] =
    "mesh: {points: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 1, 1],\n"
    "                [0.4, 0.5, 0.5], [0.6, 0.45, 0.55]]}\n"
    "pins: [{select: {vertices: [0, 1, 2, 3, 4, 5]}}]\n"
    "tendons:\n"
    "  - {waypoints: [0, 6, 7, 1], stiffness: 500, density: 0.01}\n"
    "  - {waypoints: [2, 6], stiffness: 500, density: 0.01}\n"
    "  - {waypoints: [4, 6], stiffness: 500, density: 0.01}\n"
    "  - {waypoints: [3, 7], stiffness: 500, density: 0.01}\n"
    "  - {waypoints: [5, 7], stiffness: 500, density: 0.01}\n"
    "  - {waypoints: [2, 7], stiffness: 500, density: 0.01}\n";

static sw_model *load(const char *text) {
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_parse("mem/net.yaml", text, strlen(text), err, sizeof err);
  if (!m) fprintf(stderr, "%s\n", err);
  assert_non_null(m);
  return m;
}

/* Targets on the free vertices with f = A tau (tau given). */
static void targets_from(const sw_model *m, const double *tau, sw_targets *tg) {
  tg->dim = m->dim;
  tg->vertex = calloc((size_t)m->nv, sizeof(int));
  tg->f = calloc((size_t)m->nv * m->dim, sizeof(double));
  assert_true(tg->vertex && tg->f);
  tg->n = 0;
  for (int i = 0; i < m->nv; i++)
    if (!m->pinned[i]) tg->vertex[tg->n++] = i;
  int rows = tg->n * m->dim;
  double *A = calloc((size_t)rows * m->ntendon, sizeof *A);
  assert_int_equal(sw_inverse_matrix(m, m->x0, tg->vertex, tg->n, A), 0);
  for (int t = 0; t < m->ntendon; t++)
    for (int i = 0; i < rows; i++) tg->f[i] += A[(size_t)t * rows + i] * tau[t];
  free(A);
}

static void free_targets(sw_targets *tg) {
  free(tg->vertex);
  free(tg->f);
}

/* A's columns are -grad l (the tendon model §2) by central differences of sw_tendon_length. */
static void matrix_is_minus_grad_length(void **st) {
  (void)st;
  sw_model *m = load(net3d);
  int target[2] = {6, 7}, rows = 6;
  double A[36], x[24], h = 1e-6;
  assert_int_equal(sw_inverse_matrix(m, m->x0, target, 2, A), 0);
  for (int t = 0; t < m->ntendon; t++)
    for (int r = 0; r < rows; r++) {
      memcpy(x, m->x0, sizeof x);
      int k = target[r / 3] * 3 + r % 3;
      x[k] += h;
      double lp = sw_tendon_length(&m->tendon[t], x, 3);
      x[k] -= 2 * h;
      double lm = sw_tendon_length(&m->tendon[t], x, 3);
      assert_true(fabs(A[t * rows + r] + (lp - lm) / (2 * h)) < 1e-8);
    }
  sw_model_free(m);
}

static void recover(const char *text, const double *tau_true) {
  sw_model *m = load(text);
  sw_targets tg;
  targets_from(m, tau_true, &tg);
  sw_inverse inv;
  char err[SW_ERRSZ];
  assert_int_equal(sw_inverse_solve(m, m->x0, &tg, &inv, err, sizeof err), 0);
  for (int t = 0; t < m->ntendon; t++) {
    assert_true(fabs(inv.tau[t] - tau_true[t]) <= 1e-10 * (1 + tau_true[t]));
    double l = sw_tendon_length(&m->tendon[t], m->x0, m->dim);
    assert_true(fabs(inv.rest[t] - (l - tau_true[t] / m->tendon[t].stiffness)) < 1e-12);
  }
  assert_true(inv.reachable && inv.residual <= 1e-12 * inv.fnorm);
  /* the forward check: the tendons with those rest lengths hold the loads -f at x */
  assert_int_equal(sw_inverse_check(m, m->x0, &tg, &inv, err, sizeof err), 0);
  assert_int_equal(inv.check_rc, SW_OK);
  assert_true(inv.check_pass);
  assert_true(inv.check_dx < 1e-9 && inv.check_ferr < 1e-9 && inv.check_ferr0 < 1e-9);
  sw_inverse_free(&inv);
  free_targets(&tg);
  sw_model_free(m);
}

static void recover_2d(void **st) { (void)st, recover(net2d, (double[]){3.0, 7.0, 5.0, 2.0}); }
static void recover_3d(void **st) {
  (void)st, recover(net3d, (double[]){4.0, 2.5, 6.0, 3.0, 1.5, 2.0});
}

/* Q pulled straight down with no net force on P: the one cable that pulls Q down (bottom)
 * also pulls P, and nothing balances that exactly.  tau >= 0, the residual is the NNLS optimum
 * of the brute-force enumeration (|r| = 0.416 |f|), not reachable, the forward check fails. */
static void unreachable(void **st) {
  (void)st;
  sw_model *m = load(net2d);
  sw_targets tg = {.n = 2, .dim = 2, .vertex = (int[]){4, 5}, .f = (double[]){0, 0, 0, -3}};
  sw_inverse inv;
  char err[SW_ERRSZ];
  assert_int_equal(sw_inverse_solve(m, m->x0, &tg, &inv, err, sizeof err), 0);
  assert_false(inv.reachable);
  double A[16], xb[4];
  assert_int_equal(sw_inverse_matrix(m, m->x0, tg.vertex, 2, A), 0);
  double fb = brute_force(4, 4, A, tg.f, xb);
  for (int t = 0; t < 4; t++) assert_true(inv.tau[t] >= 0.0 && fabs(inv.tau[t] - xb[t]) < 1e-9);
  assert_true(fabs(0.5 * inv.residual * inv.residual - fb) <= 1e-10 * (1 + fb));
  assert_true(fabs(inv.residual / inv.fnorm - 0.41590019592802907) < 1e-9);
  assert_int_equal(sw_inverse_check(m, m->x0, &tg, &inv, err, sizeof err), 0);
  assert_false(inv.check_pass);
  sw_inverse_free(&inv);
  sw_model_free(m);
}

/* A tendon with K = 0 gets tau = 0 and keeps its rest length; zero targets give tau = 0. */
static void zero_stiffness_and_zero_force(void **st) {
  (void)st;
  char text[2048];
  snprintf(text, sizeof text, "%s", net2d);
  char *k = strstr(text, "stiffness: 800");
  memcpy(k, "stiffness: 0  ", 14);
  sw_model *m = load(text);
  sw_targets tg = {.n = 2, .dim = 2, .vertex = (int[]){4, 5}, .f = (double[]){-3, 4, 2, 5}};
  sw_inverse inv;
  char err[SW_ERRSZ];
  assert_int_equal(sw_inverse_solve(m, m->x0, &tg, &inv, err, sizeof err), 0);
  assert_true(inv.tau[2] == 0.0 && inv.rest[2] == sw_tendon_rest(&m->tendon[2], 0.0));
  sw_inverse_free(&inv);
  memset(tg.f, 0, 4 * sizeof *tg.f);
  assert_int_equal(sw_inverse_solve(m, m->x0, &tg, &inv, err, sizeof err), 0);
  for (int t = 0; t < 4; t++) assert_true(inv.tau[t] == 0.0);
  assert_true(inv.reachable);
  assert_int_equal(sw_inverse_check(m, m->x0, &tg, &inv, err, sizeof err), 0);
  assert_true(inv.check_pass);
  sw_inverse_free(&inv);
  sw_model_free(m);
}

/* Every allocation of the solve and the check failing in turn: an error, never a crash. */
static void allocation_failures(void **st) {
  (void)st;
  sw_model *m = load(net2d);
  sw_targets tg = {.n = 2, .dim = 2, .vertex = (int[]){4, 5}, .f = (double[]){-3, 4, 2, 5}};
  sw_inverse inv;
  char err[SW_ERRSZ];
  int done = 0, k;
  for (k = 1; k < 2000 && !done; k++) {
    sw_alloc_fail_after(k);
    int rc = sw_inverse_solve(m, m->x0, &tg, &inv, err, sizeof err);
    if (!rc) rc = sw_inverse_check(m, m->x0, &tg, &inv, err, sizeof err), done = !rc;
    sw_alloc_fail_after(0);
    if (!done) assert_non_null(strstr(err, "out of memory"));
    if (!rc || inv.tau) sw_inverse_free(&inv);
  }
  assert_true(done && k > 10);
  sw_model_free(m);
}

/* ------------------------------------------------------------ files */

static char tmpdir[256];

static void write_file(const char *name, const char *text, char *path, size_t sz) {
  snprintf(path, sz, "%s/%s", tmpdir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

static void targets_csv(void **st) {
  (void)st;
  sw_model *m = load(net2d);
  char path[512], err[SW_ERRSZ];
  sw_targets tg;
  write_file("good.csv", "vertex, fx, fy\r\n\n4, -3, 4\r\n 5 ,2,5e0\n", path, sizeof path);
  assert_int_equal(sw_targets_read(path, m, &tg, err, sizeof err), 0);
  assert_int_equal(tg.n, 2);
  assert_true(tg.vertex[1] == 5 && tg.f[0] == -3 && tg.f[3] == 5);
  sw_targets_free(&tg);
  static const struct { const char *text, *where, *what; } bad[] = {
      {"vertex,fx,fy,fz\n4,1,2,3\n", ":1:14:", "expected the header vertex,fx,fy"},
      {"vertex,fx\n4,1\n", ":1:10:", "the header has 2 fields"},
      {"vertex,fx,fy\n4,1,2\n9,1,2\n", ":3:1:", "expected an integer in 0..6"},
      {"vertex,fx,fy\n4,1,2\n4,1,2\n", ":3:1:", "vertex 4 is repeated"},
      {"vertex,fx,fy\n4,1,abc\n", ":2:5:", "fy is 'abc'; expected a finite number"},
      {"vertex,fx,fy\n4,1\n", ":2:4:", "the line has 2 fields; expected 3"},
      {"vertex,fx,fy\n4,1,2,3\n", ":2:7:", "the line has 4 fields"},
      {"vertex,fx,fy\n4, nan,2\n", ":2:4:", "fx is 'nan'"},
      {"vertex,fx,fy\n", ":1:1:", "no target line"},
      {"", ":1:1:", "the file is empty"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    write_file("bad.csv", bad[k].text, path, sizeof path);
    assert_int_not_equal(sw_targets_read(path, m, &tg, err, sizeof err), 0);
    if (!strstr(err, bad[k].where) || !strstr(err, bad[k].what) || !strstr(err, "bad.csv"))
      fail_msg("case %zu: %s", k, err);
  }
  assert_int_not_equal(sw_targets_read("/nonexistent/t.csv", m, &tg, err, sizeof err), 0);
  sw_model_free(m);
}

/* The rewritten scene loads and has exactly the new rest lengths (replacing a number, a
 * relative one, keyframes, and adding the key where there was none). */
static void scene_rewrite(void **st) {
  (void)st;
  char scene[512], out[512], err[SW_ERRSZ];
  write_file("net.yaml",
             "dimension: 2\n"
             "mesh: {points: [[0, 0], [1, 0], [0.5, 0.5]]}  # a comment\n"
             "pins: [{select: {vertices: [0, 1]}}]\n"
             "tendons:\n"
             "  - {waypoints: [0, 2], stiffness: 10, density: 1, rest_length: 0.5}\n"
             "  - {waypoints: [1, 2], stiffness: 10, density: 1, rest_length: {relative: 0.9}}\n"
             "  - {waypoints: [2, 0, 1], stiffness: 10, density: 1,\n"
             "     rest_length: {keyframes: [[0, 1], [1, 2]]}}\n"
             "  - waypoints: [0, 1]\n"
             "    stiffness: 10\n",
             scene, sizeof scene);
  sw_model *m = sw_scene_load(scene, err, sizeof err);
  assert_non_null(m);
  const double rest[4] = {0.1, 1.0 / 3.0, 2.0 / 7.0, 0.7071067811865476};
  snprintf(out, sizeof out, "%s/out.yaml", tmpdir);
  assert_int_equal(sw_scene_write_rest(scene, out, m, rest, err, sizeof err), 0);
  sw_model *m2 = sw_scene_load(out, err, sizeof err);
  if (!m2) fail_msg("%s", err);
  for (int t = 0; t < 4; t++) {
    assert_int_equal(m2->tendon[t].nkey, 1);
    assert_true(m2->tendon[t].key_rest[0] == rest[t]);
  }
  assert_true(access(out, F_OK) == 0);
  assert_int_not_equal(sw_scene_write_rest(scene, "/nonexistent/dir/x.yaml", m, rest, err,
                                           sizeof err), 0);
  sw_model_free(m2);
  sw_model_free(m);
}

/* ------------------------------------------------------------ point loads */

static void loads_term(void **st) {
  (void)st;
  sw_model *m = load("mesh: {points: [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}\n"
                     "tendons: [{waypoints: [0, 1, 2], stiffness: 5, density: 1}]\n"
                     "loads:\n"
                     "  - {select: {vertices: [1, 2]}, force: [1, 2, 3]}\n"
                     "  - {select: {box: [[0.5, -1, -1], [2, 1, 1]]}, force: [0, 0, -1]}\n");
  assert_true(m->load[3] == 1 && m->load[5] == 2 && m->load[8] == 3 && m->load[0] == 0);
  int k = m->nterm - 1;
  assert_string_equal(m->term[k].name, "loads");
  th_conformance(m, "loads", 0, 1.0, 99);
  sw_model_free(m);
  char err[SW_ERRSZ];
  const char *bad = "mesh: {points: [[0, 0], [1, 0]]}\ndimension: 2\n"
                    "tendons: [{waypoints: [0, 1], stiffness: 5, density: 1}]\n"
                    "loads: [{select: {vertices: [1]}, force: [1, 2, 3]}]\n";
  assert_null(sw_scene_parse("mem/bad.yaml", bad, strlen(bad), err, sizeof err));
  assert_non_null(strstr(err, "mem/bad.yaml:4:"));
  assert_non_null(strstr(err, "loads[0] force"));
}

static int setup(void **st) {
  (void)st;
  const char *base = getenv("TMPDIR");
  snprintf(tmpdir, sizeof tmpdir, "%s/sinew_inverse_XXXXXX", base && *base ? base : "/tmp");
  return mkdtemp(tmpdir) ? 0 : -1;
}

static int teardown(void **st) {
  (void)st;
  char cmd[600];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  return system(cmd) == 0 ? 0 : -1;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(nnls_identity),
      cmocka_unit_test(nnls_by_hand),
      cmocka_unit_test(nnls_against_enumeration),
      cmocka_unit_test(nnls_degenerate_columns),
      cmocka_unit_test(matrix_is_minus_grad_length),
      cmocka_unit_test(recover_2d),
      cmocka_unit_test(recover_3d),
      cmocka_unit_test(unreachable),
      cmocka_unit_test(zero_stiffness_and_zero_force),
      cmocka_unit_test(allocation_failures),
      cmocka_unit_test(targets_csv),
      cmocka_unit_test(scene_rewrite),
      cmocka_unit_test(loads_term),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
