/* test_mesh.c — the grid generator and the OBJ reader (sim/input/mesh.c, sim/input/obj.c).
 *
 * OBJ files are written at run time into a mkdtemp folder.  Usage:
 *   test_mesh [REGRESS_DIR]
 * REGRESS_DIR (or the environment variable SW_OBJ_REGRESS_DIR) holds fuzzer-found inputs
 * (tests/fuzz/regress/obj); each is read and must fail cleanly or give a valid mesh. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "obj.h"
#include "sinew.h"
#include "util.h"

#define V3 "v 0 0 0\nv 1 0 0\nv 0 1 0\n" /* three positions, a valid start */

static char tmpdir[256];

/* |a - b| <= tol (cmocka 1.1 has only a float version) */
#define assert_near(a, b, tol)                                                               \
  do {                                                                                     \
    double a_ = (a), b_ = (b);                                                             \
    if (!(fabs(a_ - b_) <= (tol))) fail_msg("%s = %.17g, expected %.17g", #a, a_, b_);     \
  } while (0)
static const char *regress_dir;

/* ------------------------------------------------------------------ helpers */

static int setup_tmpdir(void **state) {
  (void)state;
  snprintf(tmpdir, sizeof tmpdir, "%s", "/tmp/sw_test_mesh_XXXXXX");
  return mkdtemp(tmpdir) ? 0 : -1;
}

static int teardown_tmpdir(void **state) {
  (void)state;
  DIR *d = opendir(tmpdir);
  if (!d) return -1;
  struct dirent *e;
  char path[SW_PATHSZ];
  while ((e = readdir(d))) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    snprintf(path, sizeof path, "%s/%s", tmpdir, e->d_name);
    unlink(path);
  }
  closedir(d);
  return rmdir(tmpdir);
}

/* Write len bytes to tmpdir/name; path receives the file name. */
static void write_bytes(const char *name, const char *text, size_t len, char path[SW_PATHSZ]) {
  snprintf(path, SW_PATHSZ, "%s/%s", tmpdir, name);
  FILE *fp = fopen(path, "wb");
  assert_non_null(fp);
  assert_int_equal(fwrite(text, 1, len, fp), len);
  assert_int_equal(fclose(fp), 0);
}

static void write_obj(const char *name, const char *text, char path[SW_PATHSZ]) {
  write_bytes(name, text, strlen(text), path);
}

static int mesh_is_zero(const sw_mesh *m) {
  static const sw_mesh zero;
  return memcmp(m, &zero, sizeof zero) == 0;
}

/* Every index in range, groups valid: what any successfully read mesh must satisfy. */
static void assert_mesh_valid(const sw_mesh *m) {
  assert_true(m->nv > 0 && m->nf > 0 && m->ngroup >= 1);
  assert_string_equal(m->group[0], "default");
  assert_true((m->nuv == 0) == (m->fuv == NULL));
  for (int t = 0; t < m->nf; t++) {
    for (int k = 0; k < 3; k++) {
      assert_in_range(m->f[3 * t + k], 0, m->nv - 1);
      if (m->fuv) assert_in_range(m->fuv[3 * t + k], 0, m->nuv - 1);
    }
    assert_in_range(m->fgroup[t], 0, m->ngroup - 1);
  }
}

/* Signed area of triangle t in the (u,v) layout, m^2. */
static double uv_area(const sw_mesh *m, int t) {
  const int *c = m->fuv + 3 * t;
  const double *a = m->uv + 2 * c[0], *b = m->uv + 2 * c[1], *d = m->uv + 2 * c[2];
  return 0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]));
}

/* Read text as an OBJ file that must fail with "path:where: " (where = "LINE:COLUMN"), or with
 * "path: " and a message containing `where` when where has no digit. */
static void expect_obj_error(const char *text, size_t len, const char *where) {
  char path[SW_PATHSZ], err[SW_ERRSZ] = "", prefix[SW_PATHSZ + 64];
  sw_mesh m;
  write_bytes("bad.obj", text, len, path);
  int rc = sw_obj_read(path, &m, err, sizeof err);
  if (rc == 0) fail_msg("expected an error at %s for:\n%s", where, text);
  assert_true(mesh_is_zero(&m));
  if (strpbrk(where, "0123456789")) {
    snprintf(prefix, sizeof prefix, "%s:%s: ", path, where);
    if (strncmp(err, prefix, strlen(prefix)) != 0)
      fail_msg("expected prefix \"%s\", got \"%s\"", prefix, err);
  } else {
    snprintf(prefix, sizeof prefix, "%s: ", path);
    assert_true(strncmp(err, prefix, strlen(prefix)) == 0);
    if (!strstr(err, where)) fail_msg("expected \"%s\" in \"%s\"", where, err);
  }
}

static void expect_error_str(const char *text, const char *where) {
  expect_obj_error(text, strlen(text), where);
}

static void read_ok(const char *text, sw_mesh *m) {
  char path[SW_PATHSZ], err[SW_ERRSZ] = "";
  write_obj("ok.obj", text, path);
  int rc = sw_obj_read(path, m, err, sizeof err);
  if (rc != 0) fail_msg("unexpected error: %s", err);
  assert_mesh_valid(m);
}

/* --------------------------------------------------------------------- grid */

static void test_grid_counts(void **state) {
  (void)state;
  static const int dims[][2] = {{2, 2}, {3, 2}, {2, 5}, {4, 7}, {11, 11}};
  double size[2] = {1.0, 2.0};
  char err[SW_ERRSZ];
  for (size_t k = 0; k < sizeof dims / sizeof dims[0]; k++) {
    int nx = dims[k][0], ny = dims[k][1];
    sw_mesh m;
    assert_int_equal(sw_mesh_grid(&m, size, nx, ny, "xy", err, sizeof err), 0);
    assert_int_equal(m.nv, nx * ny);
    assert_int_equal(m.nuv, nx * ny);
    assert_int_equal(m.nf, 2 * (nx - 1) * (ny - 1));
    assert_int_equal(m.ngroup, 1);
    assert_mesh_valid(&m);
    assert_memory_equal(m.f, m.fuv, sizeof(int) * 3 * (size_t)m.nf);
    assert_ptr_not_equal(m.f, m.fuv);
    for (int t = 0; t < m.nf; t++) assert_int_equal(m.fgroup[t], 0);
    sw_mesh_free(&m);
    assert_true(mesh_is_zero(&m));
  }
}

static void test_grid_area(void **state) {
  (void)state;
  double size[2] = {1.5, 0.7}; /* m */
  char err[SW_ERRSZ];
  sw_mesh m;
  assert_int_equal(sw_mesh_grid(&m, size, 7, 4, "xy", err, sizeof err), 0);
  double sum = 0;
  for (int t = 0; t < m.nf; t++) {
    double a = uv_area(&m, t);
    assert_true(a > 0);
    sum += a;
  }
  assert_near(sum, size[0] * size[1], 1e-12);
  /* vertex (i, j) = j*nx + i at u = i*size0/(nx-1), v = j*size1/(ny-1) */
  int k = 2 * 7 + 3;
  assert_near(m.uv[2 * k], 3 * 1.5 / 6, 1e-15);
  assert_near(m.uv[2 * k + 1], 2 * 0.7 / 3, 1e-15);
  assert_near(m.uv[2 * (m.nv - 1)], 1.5, 0);
  assert_near(m.uv[2 * (m.nv - 1) + 1], 0.7, 0);
  sw_mesh_free(&m);
}

/* Neighbouring cells use different diagonals (checkerboard): no directional bias. */
static void test_grid_checkerboard(void **state) {
  (void)state;
  double size[2] = {1, 1};
  char err[SW_ERRSZ];
  sw_mesh m;
  int nx = 5, ny = 4, diag_ac = 0, diag_bd = 0;
  assert_int_equal(sw_mesh_grid(&m, size, nx, ny, "xy", err, sizeof err), 0);
  for (int j = 0; j + 1 < ny; j++)
    for (int i = 0; i + 1 < nx; i++) {
      int t = 2 * (j * (nx - 1) + i), a = j * nx + i, c = a + nx + 1;
      int has_ac = 0;
      for (int s = 0; s < 2; s++) {
        const int *f = m.f + 3 * (t + s);
        int ha = f[0] == a || f[1] == a || f[2] == a, hc = f[0] == c || f[1] == c || f[2] == c;
        has_ac += ha && hc;
      }
      assert_true(has_ac == 0 || has_ac == 2);
      assert_int_equal(has_ac == 2, (i + j) % 2 == 0);
      if (has_ac) diag_ac++;
      else diag_bd++;
    }
  assert_true(abs(diag_ac - diag_bd) <= 1);
  sw_mesh_free(&m);
}

static void test_grid_planes(void **state) {
  (void)state;
  static const char *planes[] = {"xy", "xz", "yz"};
  static const int axes[][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}}; /* u, v, zero component */
  double size[2] = {2, 3};
  char err[SW_ERRSZ];
  for (int p = 0; p < 3; p++) {
    sw_mesh m;
    assert_int_equal(sw_mesh_grid(&m, size, 3, 4, planes[p], err, sizeof err), 0);
    for (int k = 0; k < m.nv; k++) {
      assert_near(m.x[3 * k + axes[p][0]], m.uv[2 * k], 0);
      assert_near(m.x[3 * k + axes[p][1]], m.uv[2 * k + 1], 0);
      assert_near(m.x[3 * k + axes[p][2]], 0, 0);
    }
    sw_mesh_free(&m);
  }
}

static void expect_grid_error(const double *size, int nx, int ny, const char *plane) {
  char err[SW_ERRSZ] = "";
  sw_mesh m;
  memset(&m, 0xab, sizeof m);
  assert_int_not_equal(sw_mesh_grid(&m, size, nx, ny, plane, err, sizeof err), 0);
  assert_true(mesh_is_zero(&m));
  assert_true(strncmp(err, "grid: ", 6) == 0);
}

static void test_grid_errors(void **state) {
  (void)state;
  double ok[2] = {1, 1}, zero[2] = {0, 1}, neg[2] = {1, -1}, nan2[2] = {NAN, 1},
         inf2[2] = {1, INFINITY};
  expect_grid_error(ok, 1, 2, "xy");
  expect_grid_error(ok, 2, 1, "xy");
  expect_grid_error(ok, -5, 3, "xy");
  expect_grid_error(zero, 2, 2, "xy");
  expect_grid_error(neg, 2, 2, "xy");
  expect_grid_error(nan2, 2, 2, "xy");
  expect_grid_error(inf2, 2, 2, "xy");
  expect_grid_error(NULL, 2, 2, "xy");
  expect_grid_error(ok, 2, 2, "zx");
  expect_grid_error(ok, 2, 2, "");
  expect_grid_error(ok, 2, 2, NULL);
  expect_grid_error(ok, 100000, 100000, "xy");
  expect_grid_error(ok, 2147483647, 2147483647, "xy");
  assert_int_not_equal(sw_mesh_grid(NULL, ok, 2, 2, "xy", NULL, 0), 0);
}

static void test_mesh_free_zeroed(void **state) {
  (void)state;
  sw_mesh m;
  memset(&m, 0, sizeof m);
  sw_mesh_free(&m);
  sw_mesh_free(&m);
  sw_mesh_free(NULL);
  assert_true(mesh_is_zero(&m));
}

/* ---------------------------------------------------------------- OBJ: good */

static void test_obj_quad_triangle(void **state) {
  (void)state;
  sw_mesh m;
  read_ok("# a quad and a triangle\n"
          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 2 0\n"
          "f 1/1 2/2 3/3 4/4\n"
          "f 2/2 5/5 3/3\n",
          &m);
  static const int f[] = {0, 1, 2, 0, 2, 3, 1, 4, 2};
  assert_int_equal(m.nv, 5);
  assert_int_equal(m.nuv, 5);
  assert_int_equal(m.nf, 3);
  assert_memory_equal(m.f, f, sizeof f);
  assert_memory_equal(m.fuv, f, sizeof f);
  assert_near(m.x[3 * 4], 2, 0);
  for (int t = 0; t < 3; t++) {
    assert_true(uv_area(&m, t) > 0);
    for (int k = 0; k < 3; k++) { /* here uv = (x, y) of the same corner */
      assert_near(m.uv[2 * m.fuv[3 * t + k]], m.x[3 * m.f[3 * t + k]], 0);
      assert_near(m.uv[2 * m.fuv[3 * t + k] + 1], m.x[3 * m.f[3 * t + k] + 1], 0);
    }
  }
  sw_mesh_free(&m);
}

/* Two panels folded along a shared edge: 6 positions, each panel with its own (u,v). */
static void test_obj_seam(void **state) {
  (void)state;
  sw_mesh m;
  read_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 1\nv 1 1 1\n"
          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"       /* panel A */
          "vt 5 0\nvt 6 0\nvt 6 1\nvt 5 1\n"       /* panel B, laid out elsewhere */
          "usemtl front\nf 1/1 2/2 3/3 4/4\n"
          "usemtl back\nf 2/5 5/6 6/7 3/8\n",
          &m);
  assert_int_equal(m.nv, 6);
  assert_int_equal(m.nuv, 8);
  assert_int_equal(m.nf, 4);
  /* position 2 (0-based 1): uv (1,0) in panel A, (5,0) in panel B */
  double ua = -1, ub = -1;
  for (int t = 0; t < m.nf; t++)
    for (int k = 0; k < 3; k++)
      if (m.f[3 * t + k] == 1) {
        double u = m.uv[2 * m.fuv[3 * t + k]];
        if (m.fgroup[t] == 1) ua = u;
        else ub = u;
      }
  assert_near(ua, 1, 0);
  assert_near(ub, 5, 0);
  assert_int_equal(m.ngroup, 3);
  assert_string_equal(m.group[1], "front");
  assert_string_equal(m.group[2], "back");
  for (int t = 0; t < m.nf; t++) assert_true(uv_area(&m, t) > 0);
  sw_mesh_free(&m);
}

static void test_obj_negative_indices(void **state) {
  (void)state;
  sw_mesh m;
  read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
          "f -3/-3 -2/-2 -1/-1\n"
          "v 1 1 0\nvt 1 1\n"
          "f -3/-3 -1/-1 -2/-2\n",
          &m);
  static const int f[] = {0, 1, 2, 1, 3, 2};
  assert_int_equal(m.nf, 2);
  assert_memory_equal(m.f, f, sizeof f);
  assert_memory_equal(m.fuv, f, sizeof f);
  sw_mesh_free(&m);
}

static void test_obj_groups(void **state) {
  (void)state;
  sw_mesh m;
  read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\n"
          "f 1 2 3\n"
          "usemtl red cloth\nf 1 2 3\n"
          "g blue\nf 1 2 3\n"
          "usemtl red cloth\nf 1 2 3\n"
          "g\nf 1 2 3\n"
          "g blue\nf 1 2 3\n"
          "g default\nf 1 2 3\n",
          &m);
  static const int g[] = {0, 1, 2, 1, 0, 2, 0};
  assert_int_equal(m.nf, 7);
  assert_memory_equal(m.fgroup, g, sizeof g);
  assert_int_equal(m.ngroup, 3);
  assert_string_equal(m.group[1], "red cloth");
  assert_string_equal(m.group[2], "blue");
  assert_int_equal(m.nuv, 0);
  assert_null(m.fuv);
  assert_null(m.uv);
  sw_mesh_free(&m);
}

/* Many groups (hashed names): reuse by name, and a limit of 65536 including "default". */
static void test_obj_many_groups(void **state) {
  (void)state;
  size_t cap = 16 * 70000 + 100, len = 0;
  char *text = malloc(cap);
  assert_non_null(text);
  len += (size_t)snprintf(text, cap, V3);
  for (int k = 1; k <= 5000; k++)
    len += (size_t)snprintf(text + len, cap - len, "g g%d\nf 1 2 3\n", k % 3000);
  sw_mesh m;
  read_ok(text, &m);
  assert_int_equal(m.ngroup, 3001);
  assert_int_equal(m.nf, 5000);
  for (int t = 0; t < m.nf; t++) {
    char name[16];
    snprintf(name, sizeof name, "g%d", (t + 1) % 3000);
    assert_string_equal(m.group[m.fgroup[t]], name);
  }
  sw_mesh_free(&m);
  len = (size_t)snprintf(text, cap, V3 "f 1 2 3\n");
  for (int k = 1; k <= 65536; k++) len += (size_t)snprintf(text + len, cap - len, "g %d\n", k);
  expect_obj_error(text, len, "65540:3");
  free(text);
}

static void test_obj_crlf_and_ignored(void **state) {
  (void)state;
  sw_mesh m;
  read_ok("\xef\xbb\xbf# exported\r\n"
          "mtllib cloth.mtl\r\n"
          "o panel\r\n"
          "\r\n"
          "   \t\r\n"
          "v 0 0 0 1\r\n"           /* w */
          "v 1.0e0 0 0 0.5 0.5 0.5\r\n" /* r g b */
          "v 0 1 0   \r\n"
          "v +1 1 -0\r\n"
          "vt 0\r\n"                /* v defaults to 0 */
          "vt 1 0 0\r\n"
          "vt 0 1\r\n"
          "vt 1 1\r\n"
          "vn 0 0 1\r\n"
          "s off\r\n"
          "s 1\r\n"
          "l 1 2\r\n"
          "p 1\r\n"
          "f 1/1/1 2/2/1 3/3/1 # trailing comment\r\n"
          "f 2/2/1 4/4/1 3/3/1",    /* no final newline */
          &m);
  assert_int_equal(m.nv, 4);
  assert_int_equal(m.nuv, 4);
  assert_int_equal(m.nf, 2);
  assert_near(m.uv[0], 0, 0);
  assert_near(m.uv[1], 0, 0);
  assert_near(m.x[3 * 1], 1, 0);
  sw_mesh_free(&m);
}

static void test_obj_normals_only(void **state) {
  (void)state;
  sw_mesh m;
  read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1//1 2//1 3//1\n", &m);
  assert_int_equal(m.nf, 1);
  assert_int_equal(m.nuv, 0); /* vt lines exist, but no face uses them */
  assert_null(m.uv);
  assert_null(m.fuv);
  sw_mesh_free(&m);
}

/* Long lines (a 1 MB comment, a 100000-corner polygon) are read without trouble. */
static void test_obj_long_lines(void **state) {
  (void)state;
  const double two_pi = 6.283185307179586;
  size_t n = 100000, cap = 80 * n + (1 << 20) + 100, len = 0;
  char *text = malloc(cap);
  assert_non_null(text);
  text[len++] = '#';
  memset(text + len, 'x', 1 << 20);
  len += 1 << 20;
  text[len++] = '\n';
  for (size_t k = 0; k < n; k++) /* a convex polygon: points on a circle */
    len += (size_t)snprintf(text + len, cap - len, "v %.17g %.17g 0\n", cos(two_pi * (double)k / (double)n),
                            sin(two_pi * (double)k / (double)n));
  len += (size_t)snprintf(text + len, cap - len, "f");
  for (size_t k = 0; k < n; k++) len += (size_t)snprintf(text + len, cap - len, " %zu", k + 1);
  text[len++] = '\n';
  text[len] = '\0';
  sw_mesh m;
  read_ok(text, &m);
  assert_int_equal(m.nf, (int)n - 2);
  sw_mesh_free(&m);
  free(text);
}

/* ---------------------------------------------------------------- OBJ: bad */

static void test_obj_bad_statements(void **state) {
  (void)state;
  expect_error_str(V3 "foo 1 2\n", "4:1");
  expect_error_str(V3 "  vp 1\n", "4:3");
  expect_error_str(V3 "F 1 2 3\n", "4:1");
  expect_error_str(V3 "usemtl\n", "4:7");
  expect_error_str(V3 "g xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\n", "4:3");
  expect_obj_error("v 0 0 0\nv 1\0 0 0\n", sizeof "v 0 0 0\nv 1\0 0 0\n" - 1, "2:4");
  expect_error_str("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", "1:8");
}

static void test_obj_bad_numbers(void **state) {
  (void)state;
  expect_error_str("v 0 0 0\nv 1 x 0\n", "2:5");
  expect_error_str("v 0 0 nan\n", "1:7");
  expect_error_str("v 0 0 -inf\n", "1:7");
  expect_error_str("v 1e999 0 0\n", "1:3");
  expect_error_str("v 1 2 3abc\n", "1:7");
  expect_error_str("v 1,5 2 3\n", "1:3");
  expect_error_str("v 0 0\n", "1:6");
  expect_error_str("v 0 0 # no z\n", "1:7");
  expect_error_str("v\n", "1:2");
  expect_error_str("v 1 2 3 4 5\n", "1:12");
  expect_error_str("v 1 2 3 4 5 6 7\n", "1:15");
  expect_error_str("vt\n", "1:3");
  expect_error_str("vt 0 0 0 0\n", "1:10");
  expect_error_str("vn 0 0\n", "1:7");
  expect_error_str("vn 0 0 1 1\n", "1:10");
  char longnum[300] = "v 1 2 ";
  memset(longnum + 6, '1', 200);
  strcpy(longnum + 206, "\n");
  expect_error_str(longnum, "1:7");
}

static void test_obj_bad_indices(void **state) {
  (void)state;
  expect_error_str(V3 "f 1 2 0\n", "4:7");
  expect_error_str(V3 "f 1 2 4\n", "4:7");
  expect_error_str(V3 "f -4 1 2\n", "4:3");
  expect_error_str(V3 "f 1 -0 2\n", "4:5");
  expect_error_str("f 1 2 3\n" V3, "1:3");
  expect_error_str(V3 "f 99999999999999999999999 1 2\n", "4:3");
  expect_error_str(V3 "f -99999999999999999999999 1 2\n", "4:3");
  expect_error_str(V3 "f 1 2 3.0\n", "4:7");
  expect_error_str(V3 "f 1 2 x\n", "4:7");
  expect_error_str(V3 "f 1 2 -\n", "4:7");
  expect_error_str(V3 "f /1 2 3\n", "4:3");
  expect_error_str(V3 "vt 0 0\nf 1/ 2/ 3/\n", "5:4");
  expect_error_str(V3 "vt 0 0\nf 1/1 2/1 3/2\n", "5:13");
  expect_error_str(V3 "vt 0 0\nf 1/0 2/1 3/1\n", "5:5");
  expect_error_str(V3 "f 1//1 2//1 3//1\n", "4:6");
  expect_error_str(V3 "vn 0 0 1\nf 1// 2// 3//\n", "5:5");
  expect_error_str(V3 "vt 0 0\nvn 0 0 1\nf 1/1/1/1 2/1/1 3/1/1\n", "6:8");
}

static void test_obj_bad_faces(void **state) {
  (void)state;
  expect_error_str(V3 "f 1 2\n", "4:6");
  expect_error_str(V3 "f\n", "4:2");
  expect_error_str(V3 "f 1 2 # 3\n", "4:7");
  expect_error_str(V3 "f 1 2 1\n", "4:7");
  expect_error_str(V3 "f 1 1 2\n", "4:5");
  expect_error_str(V3 "v 1 1 0\nf 1 2 3 2\n", "5:9");
  expect_error_str(V3 "f 1 2 -3\n", "4:7");
}

static void test_obj_mixed_uv(void **state) {
  (void)state;
  expect_error_str(V3 "vt 0 0\nf 1/1 2/1 3/1\nf 1 2 3\n", "6:3");
  expect_error_str(V3 "vt 0 0\nf 1/1 2 3\n", "5:7");
  expect_error_str(V3 "vt 0 0\nf 1 2 3\nf 3/1 2/1 1/1\n", "6:3");
  expect_error_str(V3 "vt 0 0\nvn 0 0 1\nf 1/1/1 2//1 3/1/1\n", "6:9");
}

static void test_obj_no_faces(void **state) {
  (void)state;
  expect_error_str(V3, "found no faces");
  expect_error_str("", "found no faces");
  expect_error_str("# nothing\n\n", "found no faces");
}

static void test_obj_cannot_open(void **state) {
  (void)state;
  char path[SW_PATHSZ], err[SW_ERRSZ] = "";
  sw_mesh m;
  snprintf(path, sizeof path, "%s/missing.obj", tmpdir);
  assert_int_not_equal(sw_obj_read(path, &m, err, sizeof err), 0);
  assert_true(mesh_is_zero(&m));
  assert_true(strncmp(err, path, strlen(path)) == 0);
  assert_non_null(strstr(err, "cannot open"));
  assert_non_null(strstr(err, strerror(ENOENT)));
  /* a folder opens but cannot be read */
  assert_int_not_equal(sw_obj_read(tmpdir, &m, err, sizeof err), 0);
  assert_true(mesh_is_zero(&m));
  assert_true(strncmp(err, tmpdir, strlen(tmpdir)) == 0);
  /* a NULL or tiny error buffer is fine */
  assert_int_not_equal(sw_obj_read(path, &m, NULL, 0), 0);
  assert_int_not_equal(sw_obj_read(path, &m, err, 1), 0);
  assert_int_equal(err[0], '\0');
}

/* Every allocation failing in turn: an error, never a crash or a leak (ASan checks leaks). */
static void test_alloc_failures(void **state) {
  (void)state;
  char path[SW_PATHSZ], err[SW_ERRSZ];
  double size[2] = {1, 1};
  write_obj("alloc.obj",
            V3 "v 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nusemtl a\nf 1/1 2/2 4/4 3/3\n"
               "g b\nf 1/1 2/2 3/3\n",
            path);
  int ok_obj = 0, ok_grid = 0;
  for (long k = 1; k < 200 && !(ok_obj && ok_grid); k++) {
    sw_mesh m;
    sw_alloc_fail_after(k);
    int rc = sw_obj_read(path, &m, err, sizeof err);
    sw_alloc_fail_after(0);
    if (rc) assert_true(mesh_is_zero(&m));
    else ok_obj = 1;
    sw_mesh_free(&m);
    sw_alloc_fail_after(k);
    rc = sw_mesh_grid(&m, size, 3, 3, "xy", err, sizeof err);
    sw_alloc_fail_after(0);
    if (rc) assert_true(mesh_is_zero(&m));
    else ok_grid = 1;
    sw_mesh_free(&m);
  }
  assert_true(ok_obj && ok_grid);
}

/* The in-memory parser: the buffer need not be NUL-terminated. */
static void test_obj_parse_buffer(void **state) {
  (void)state;
  char buf[] = {'v', ' ', '0', ' ', '0', ' ', '0', '\n', 'v', ' ', '1', ' ', '0', ' ', '0',
                '\n', 'v', ' ', '0', ' ', '1', ' ', '0', '\n', 'f', ' ', '1', ' ', '2', ' ',
                '3'};
  char err[SW_ERRSZ];
  sw_mesh m;
  assert_int_equal(sw_obj_parse("mem", buf, sizeof buf, &m, err, sizeof err), 0);
  assert_int_equal(m.nf, 1);
  sw_mesh_free(&m);
  assert_int_not_equal(sw_obj_parse("mem", buf, sizeof buf - 1, &m, err, sizeof err), 0);
  assert_true(strncmp(err, "mem:4:6: ", 9) == 0);
  assert_int_not_equal(sw_obj_parse("mem", NULL, 0, &m, err, sizeof err), 0);
}

/* Fuzzer-found inputs: each must fail cleanly or give a valid mesh. */
static void test_obj_regressions(void **state) {
  (void)state;
  if (!regress_dir) {
    print_message("no regression folder given (argument or SW_OBJ_REGRESS_DIR); skipped\n");
    skip();
  }
  DIR *d = opendir(regress_dir);
  if (!d) fail_msg("cannot open %s: %s", regress_dir, strerror(errno));
  struct dirent *e;
  int nfile = 0;
  while ((e = readdir(d))) {
    char path[SW_PATHSZ], err[SW_ERRSZ] = "";
    struct stat sb;
    snprintf(path, sizeof path, "%s/%s", regress_dir, e->d_name);
    if (e->d_name[0] == '.' || stat(path, &sb) || !S_ISREG(sb.st_mode)) continue;
    sw_mesh m;
    if (sw_obj_read(path, &m, err, sizeof err) == 0) assert_mesh_valid(&m);
    else assert_true(mesh_is_zero(&m) && strncmp(err, path, strlen(path)) == 0);
    sw_mesh_free(&m);
    nfile++;
  }
  closedir(d);
  print_message("%d regression inputs\n", nfile);
}

int main(int argc, char **argv) {
  regress_dir = argc > 1 ? argv[1] : getenv("SW_OBJ_REGRESS_DIR");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_grid_counts),
      cmocka_unit_test(test_grid_area),
      cmocka_unit_test(test_grid_checkerboard),
      cmocka_unit_test(test_grid_planes),
      cmocka_unit_test(test_grid_errors),
      cmocka_unit_test(test_mesh_free_zeroed),
      cmocka_unit_test(test_obj_quad_triangle),
      cmocka_unit_test(test_obj_seam),
      cmocka_unit_test(test_obj_negative_indices),
      cmocka_unit_test(test_obj_groups),
      cmocka_unit_test(test_obj_many_groups),
      cmocka_unit_test(test_obj_crlf_and_ignored),
      cmocka_unit_test(test_obj_normals_only),
      cmocka_unit_test(test_obj_long_lines),
      cmocka_unit_test(test_obj_bad_statements),
      cmocka_unit_test(test_obj_bad_numbers),
      cmocka_unit_test(test_obj_bad_indices),
      cmocka_unit_test(test_obj_bad_faces),
      cmocka_unit_test(test_obj_mixed_uv),
      cmocka_unit_test(test_obj_no_faces),
      cmocka_unit_test(test_obj_cannot_open),
      cmocka_unit_test(test_alloc_failures),
      cmocka_unit_test(test_obj_parse_buffer),
      cmocka_unit_test(test_obj_regressions),
  };
  return cmocka_run_group_tests(tests, setup_tmpdir, teardown_tmpdir);
}
