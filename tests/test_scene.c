/* test_scene.c — the scene loader: a good scene fills the model as written, every bad scene is
 * refused with "file:line:column:" and a word that says what is wrong.
 *
 * Usage: test_scene [SRCDIR]
 * The scenes are written to a fresh folder made with mkdtemp under $TMPDIR (or /tmp) and
 * removed at the end.  SRCDIR (the source tree; default: the current folder when it holds
 * scenes/hanging_cloth.yaml) adds scenes/hanging_cloth.yaml and every fuzzing regression input
 * in tests/fuzz/regress/scene/ (each must load or fail cleanly, "file:..."). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene.h"
#include "sinew.h"
#include "util.h"

static char tmpdir[1024];
static const char *srcdir;
static char written[256][1100]; /* files to remove at the end */
static int nwritten;

/* Write text to tmpdir/name; the full path into path. */
static void write_file(const char *name, const char *text, char *path, size_t sz) {
  snprintf(path, sz, "%s/%s", tmpdir, name);
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
  for (int i = 0; i < nwritten; i++)
    if (!strcmp(written[i], path)) return;
  if (nwritten < 256) snprintf(written[nwritten++], sizeof written[0], "%s", path);
}

static sw_model *load_text(const char *name, const char *text, char *err) {
  char path[1100];
  write_file(name, text, path, sizeof path);
  return sw_scene_load(path, err, SW_ERRSZ);
}

static int count_pinned(const sw_model *m) {
  int n = 0;
  for (int i = 0; i < m->nv; i++) n += m->pinned[i];
  return n;
}

/* ------------------------------------------------------------------ good scenes */

static const char good_scene[] =
    "name: test cloth\n"
    "dimension: 3\n"
    "mesh:\n"
    "  grid: {size: [1.0, 2.0], vertices: [5, 9], plane: xy}\n"
    "material:\n"
    "  density: 0.2\n"
    "  membrane: {model: bw98, k_u: 1000, k_v: 2000, k_shear: 50, b_v: 1.1}\n"
    "gravity: [0, 0, -9.81]\n"
    "pins:\n"
    "  - {select: {vertices: [0, 4]}}\n"
    "  - {select: {box: [[-0.01, 1.99, -1], [0.01, 2.01, 1]]}}   # vertex (0, 2 m) = 40\n"
    "initial_velocity:\n"
    "  - {velocity: [0, 0, 1.0]}\n"
    "  - {velocity: [1, 0, 0], select: {vertices: [44]}}\n"
    "integrator: {method: backward-euler, dt: 0.005, max_halvings: 4, hessian: projected,\n"
    "             newton: {max_iterations: 20, tol: 1e-8, force_tol: 1e-7, norm: max, reuse: step},\n"
    "             setup_every: 50, ordering: nesdis}\n"
    "duration: 3\n"
    "output: {dir: out/here, frames_every: 0.1, positions_every: 0.25, frames_format: ascii}\n"
    "tension_xy: {clip: 1e4, reference: uv, k_v: 300}\n";

static void test_good_scene(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *m = load_text("good.yaml", good_scene, err);
  if (!m) fail_msg("%s", err);
  assert_string_equal(m->name, "test cloth");
  assert_non_null(strstr(m->path, "good.yaml"));
  assert_int_equal(m->dim, 3);
  assert_int_equal(m->nv, 45);
  assert_int_equal(m->nf, 2 * 4 * 8);
  assert_int_equal(count_pinned(m), 3);
  assert_true(m->pinned[0] && m->pinned[4] && m->pinned[40]);
  assert_true(m->has_gravity);
  assert_float_equal(m->gravity[2], -9.81, 1e-12);
  assert_float_equal(m->gravity[0], 0.0, 0.0);
  /* vertex 44 = (i 4, j 8) at (1, 2, 0) m */
  assert_float_equal(m->x0[3 * 44 + 0], 1.0, 1e-12);
  assert_float_equal(m->x0[3 * 44 + 1], 2.0, 1e-12);
  assert_float_equal(m->x0[3 * 44 + 2], 0.0, 0.0);
  assert_float_equal(m->v0[3 * 44 + 0], 1.0, 0.0);
  assert_float_equal(m->v0[3 * 44 + 2], 0.0, 0.0);
  assert_float_equal(m->v0[3 * 7 + 2], 1.0, 0.0);
  assert_int_equal(m->mat[0].membrane, SW_MEMBRANE_BW98);
  assert_float_equal(m->mat[0].density, 0.2, 1e-15);
  assert_float_equal(m->mat[0].k_u, 1000, 0.0);
  assert_float_equal(m->mat[0].k_v, 2000, 0.0);
  assert_float_equal(m->mat[0].k_shear, 50, 0.0);
  assert_float_equal(m->mat[0].b_u, 1.0, 0.0);
  assert_float_equal(m->mat[0].b_v, 1.1, 1e-15);
  assert_float_equal(m->total_mass, 0.2 * 2.0, 1e-12); /* kg/m^2 * m^2 */
  assert_string_equal(m->opt.method, "backward-euler");
  assert_float_equal(m->opt.dt, 0.005, 0.0);
  assert_int_equal(m->opt.max_halvings, 4);
  assert_int_equal(m->opt.hessian, SW_HESSIAN_PROJECTED);
  assert_int_equal(m->opt.newton_max, 20);
  assert_float_equal(m->opt.newton_tol, 1e-8, 0.0);
  assert_float_equal(m->opt.newton_force_tol, 1e-7, 0.0);
  assert_int_equal(m->opt.newton_norm, SW_NORM_MAX);
  assert_int_equal(m->opt.newton_reuse, SW_REUSE_STEP);
  assert_int_equal(m->opt.setup_every, 50);
  assert_int_equal(m->opt.ordering, SW_ORDERING_NESDIS);
  assert_float_equal(m->opt.duration, 3.0, 0.0);
  assert_string_equal(m->opt.out_dir, "out/here");
  assert_float_equal(m->opt.frames_every, 0.1, 0.0);
  assert_float_equal(m->opt.positions_every, 0.25, 0.0);
  assert_int_equal(m->opt.frames_format, SW_FRAMES_ASCII);
  assert_float_equal(m->opt.tx_clip, 1e4, 0.0);
  assert_int_equal(m->opt.tx_reference_uv, 1);
  assert_float_equal(m->mat[0].tx_k_u, 1000, 0.0); /* the membrane's */
  assert_float_equal(m->mat[0].tx_k_v, 300, 0.0);
  sw_model_free(m);
}

static void test_defaults(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *m = load_text("minimal_scene.yaml",
                          "mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
                          "material: {density: 0.1}\n",
                          err);
  if (!m) fail_msg("%s", err);
  assert_string_equal(m->name, "minimal_scene");
  assert_string_equal(m->opt.out_dir, "out/minimal_scene");
  assert_int_equal(m->dim, 3);
  assert_int_equal(m->has_gravity, 0);
  assert_int_equal(m->mat[0].membrane, SW_MEMBRANE_NONE);
  assert_int_equal(count_pinned(m), 0);
  assert_string_equal(m->opt.method, "backward-euler");
  assert_float_equal(m->opt.dt, 0.01, 0.0);
  assert_float_equal(m->opt.duration, 1.0, 0.0);
  assert_int_equal(m->opt.newton_max, 50);
  assert_float_equal(m->opt.newton_force_tol, 1e-10, 0.0);
  assert_int_equal(m->opt.max_halvings, 8);
  assert_int_equal(m->opt.hessian, SW_HESSIAN_ABS);
  assert_float_equal(m->opt.newton_tol, 1e-2, 0.0);
  assert_int_equal(m->opt.newton_norm, SW_NORM_RMS);
  assert_int_equal(m->opt.newton_reuse, SW_REUSE_OFF);
  assert_int_equal(m->opt.setup_every, 200);
  assert_int_equal(m->opt.ordering, SW_ORDERING_AUTO);
  assert_int_equal(m->opt.max_order, 0); /* automatic */
  assert_float_equal(m->opt.tx_k_u, -1.0, 0.0);
  assert_float_equal(m->opt.tx_clip, 5e4, 0.0);
  assert_int_equal(m->opt.tx_reference_uv, 0);
  assert_float_equal(m->opt.frames_every, 0.0, 0.0);
  assert_float_equal(m->opt.positions_every, 0.0, 0.0); /* no positions.bin */
  sw_model_free(m);
}

/* integrator.max_order: auto or 1..5; what sw_max_order makes of auto (cvode: 2 above rtol 1e-4,
 * else 5; ida: 5). */
static void test_max_order(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  static const char *const text[3] = {"integrator: {method: cvode, max_order: auto, rtol: 1e-3}\n",
                                      "integrator: {method: cvode, max_order: 3, rtol: 1e-3}\n",
                                      "integrator: {method: ida, rtol: 1e-3}\n"};
  const int want_opt[3] = {0, 3, 0}, want_used[3] = {2, 3, 5};
  for (int k = 0; k < 3; k++) {
    char buf[256];
    snprintf(buf, sizeof buf, "mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
             "material: {density: 0.1}\n%s", text[k]);
    sw_model *m = load_text("max_order.yaml", buf, err);
    if (!m) fail_msg("%s", err);
    assert_int_equal(m->opt.max_order, want_opt[k]);
    assert_int_equal(sw_max_order(m), want_used[k]);
    if (k == 0) {
      m->opt.rtol = 1e-4; /* the boundary is CVODE's high order */
      assert_int_equal(sw_max_order(m), 5);
      m->opt.rtol = 2e-4;
      assert_int_equal(sw_max_order(m), 2);
    }
    sw_model_free(m);
  }
}

static void test_2d(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *m = load_text("flat.yaml",
                          "dimension: 2\n"
                          "mesh: {grid: {size: [2, 1], vertices: [3, 2]}}\n"
                          "material: {density: 1}\n"
                          "gravity: [0, -9.81]\n"
                          "pins: [{select: {box: [[1.9, -1], [2.1, 2]]}}]\n"
                          "initial_velocity: [{velocity: [0.5, 0]}]\n",
                          err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->dim, 2);
  assert_int_equal(m->nv, 6);
  assert_int_equal(m->nf, 4);
  assert_true(m->pinned[2] && m->pinned[5]);
  assert_int_equal(count_pinned(m), 2);
  assert_float_equal(m->x0[2 * 5 + 0], 2.0, 1e-12); /* vertex (2, 1): (2, 1) m */
  assert_float_equal(m->x0[2 * 5 + 1], 1.0, 1e-12);
  assert_float_equal(m->v0[2 * 3 + 0], 0.5, 0.0);
  assert_float_equal(m->gravity[1], -9.81, 0.0);
  sw_model_free(m);
}

static void test_obj(void **state) {
  (void)state;
  char err[SW_ERRSZ], path[1100];
  snprintf(path, sizeof path, "%s/meshes", tmpdir);
  mkdir(path, 0700);
  write_file("meshes/tri.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 0.5 0\nvt 0 0.5\nf 1/1 2/2 3/3\n", path,
             sizeof path);
  sw_model *m = load_text("objscene.yaml",
                          "mesh: {obj: meshes/tri.obj, uv_scale: 2}\n"
                          "material: {density: 2, membrane: {k_u: 1, k_v: 1, k_shear: 1}}\n"
                          "pins: [{select: {vertices: [0]}}]\n",
                          err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->nv, 3);
  assert_int_equal(m->nf, 1);
  assert_float_equal(m->uv[2], 1.0, 1e-15); /* corner 1: vt (0.5, 0) * 2 m */
  assert_float_equal(m->uv[5], 1.0, 1e-15); /* corner 2: vt (0, 0.5) * 2 m */
  assert_float_equal(m->total_mass, 2.0 * 0.5, 1e-12);
  sw_model_free(m);
}

/* Two panels sewn along x = 1 (shared positions 2 and 5, separate vt): per-panel density,
 * uv_scale and bias; the material of every face; the seam stays one vertex. */
static void test_panels(void **state) {
  (void)state;
  char err[SW_ERRSZ], path[1100];
  snprintf(path, sizeof path, "%s/meshes", tmpdir);
  mkdir(path, 0700);
  write_file("meshes/two.obj",
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0 0.5\n"
             "usemtl front\nf 1/1 2/2 3/3 4/4\nusemtl back\nf 2/5 5/6 6/7 3/8\n",
             path, sizeof path);
  sw_model *m = load_text("panels.yaml",
                          "mesh: {obj: meshes/two.obj}\n"
                          "material: {density: 0.1, membrane: {k_u: 10, k_v: 20, k_shear: 1}}\n"
                          "panels:\n"
                          "  back: {density: 0.3, uv_scale: 2, bias: 90,\n"
                          "         membrane: {model: corotated, k: 7}}\n",
                          err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->nv, 6);
  assert_int_equal(m->nmat, 2);
  assert_string_equal(m->mat[1].group, "back");
  for (int f = 0; f < m->nf; f++) assert_int_equal(m->face_mat[f], f < 2 ? 0 : 1);
  /* front: 1 m^2 at 0.1; back: 1 m^2 after uv_scale 2 at 0.3 */
  assert_float_equal(m->total_mass, 0.1 + 0.3, 1e-12);
  assert_float_equal(m->mat[1].bias, 2.0 * atan(1.0), 1e-15);
  /* bias 90 degrees: the back panel's warp is its v axis: rotated u = v, v = -u */
  assert_float_equal(m->uv[6 * 2 + 2], 0.0, 1e-12); /* corner (0.5, 0) * 2 -> (0, -1) */
  assert_float_equal(m->uv[6 * 2 + 3], -1.0, 1e-12);
  assert_float_equal(m->mat[0].tx_k_u, 10, 0);      /* tension XY: each panel's membrane */
  assert_float_equal(m->mat[1].tx_k_v, 7, 0);
  assert_int_equal(m->mat[1].membrane, SW_MEMBRANE_COROTATED);
  assert_int_equal(m->mat[0].membrane, SW_MEMBRANE_BW98);
  sw_model_free(m);
  /* --stiffness-scale 3: every panel's stiffness, nothing else */
  sw_scene_overrides ov = {{0, 0}, 3.0, 0, NULL};
  snprintf(path, sizeof path, "%s/panels.yaml", tmpdir);
  m = sw_scene_load_ex(path, &ov, err, sizeof err);
  if (!m) fail_msg("%s", err);
  assert_true(m->mat[0].k_u == 30 && m->mat[0].k_v == 60 && m->mat[0].k_shear == 3);
  assert_true(m->mat[1].k_corot == 21 && m->mat[1].tx_k_v == 21 && m->mat[0].tx_k_u == 30);
  assert_true(m->mat[0].density == 0.1 && m->mat[1].density == 0.3);
  assert_float_equal(m->total_mass, 0.1 + 0.3, 1e-12);
  assert_float_equal(m->mat[1].bias, 2.0 * atan(1.0), 1e-15);
  sw_model_free(m);
}

/* Tendons: listed and selected waypoints, laws, relative keyframes, linear density on a
 * points mesh (no faces: the masses come from the tendons). */
static void test_tendons(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *m = load_text("cable.yaml",
                          "dimension: 2\n"
                          "mesh: {points: [[0, 0], [3, 0], [1, 0], [2, 0]]}\n"
                          "pins: [{select: {vertices: [0, 1]}}]\n"
                          "tendons:\n"
                          "  - name: line\n"
                          "    waypoints: {box: [[-1, -1], [4, 1]]}\n"
                          "    stiffness: 100\n"
                          "    density: 0.5\n"
                          "    rest_length: {keyframes: [[0, 1], [2, 0.5]], relative: true}\n"
                          "  - {name: short, waypoints: [2, 3], law: spring, stiffness: 5,\n"
                          "     rest_length: 2, damping: 0.1}\n"
                          "  - {waypoints: [3, 1], stiffness: 1, rest_length: {relative: 0.5}}\n"
                          "integrator: {tendon_dense_max: 3}\n",
                          err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->ntendon, 3);
  const sw_tendon *a = &m->tendon[0], *b = &m->tendon[1], *c = &m->tendon[2];
  assert_int_equal(a->nway, 4); /* ordered along x: 0, 2, 3, 1 */
  int order[4] = {0, 2, 3, 1};
  for (int i = 0; i < 4; i++) assert_int_equal(a->way[i], order[i]);
  assert_int_equal(a->law, SW_LAW_CABLE);
  assert_int_equal(b->law, SW_LAW_SPRING);
  assert_string_equal(c->name, "tendon2");
  assert_float_equal(sw_tendon_rest(a, 0.0), 3.0, 1e-15);
  assert_float_equal(sw_tendon_rest(a, 1.0), 2.25, 1e-15);
  assert_float_equal(sw_tendon_rest(a, 5.0), 1.5, 1e-15);
  assert_float_equal(sw_tendon_rest(b, 1.0), 2.0, 0);
  assert_float_equal(sw_tendon_rest(c, 0.0), 0.5, 1e-15);
  assert_float_equal(b->damping, 0.1, 0);
  /* 3 m of cable at 0.5 kg/m: vertices 2 and 3 each get 0.5 kg */
  assert_float_equal(m->total_mass, 1.5, 1e-12);
  assert_float_equal(m->mass[2], 0.5, 1e-12);
  assert_int_equal(m->ndof, 4);
  assert_int_equal(m->opt.tendon_dense_max, 3);
  /* the 4-waypoint tendon is past it: banded stencils and one low-rank vector */
  int k = 0;
  while (k < m->nterm && strcmp(m->term[k].name, "tendons")) k++;
  assert_true(k < m->nterm);
  assert_int_equal(m->term[k].nlowrank, 1);
  sw_model_free(m);
}

/* scenes/skirt.yaml: the two panels share their seam vertices (one position, a (u,v) per
 * panel: nothing is split), each face has its panel's material, and the scene runs to its end. */
static void test_skirt(void **state) {
  (void)state;
  char err[SW_ERRSZ], path[4096];
  if (!srcdir) skip();
  snprintf(path, sizeof path, "%s/scenes/skirt.yaml", srcdir);
  sw_model *m = sw_scene_load(path, err, sizeof err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->nv, 32 * 13); /* tools/make_skirt.py defaults: 2 x 16 columns, 13 rows */
  assert_int_equal(m->nmat, 2);
  int seams = 0;
  for (int i = 0; i < m->nv; i++) {
    if (fabs(m->x0[3 * i + 1]) > 1e-9) continue; /* the side seams lie in the plane y = 0 */
    int in[2] = {0, 0};
    for (int f = 0; f < m->nf; f++)
      for (int c = 0; c < 3; c++)
        if (m->face[3 * f + c] == i) in[m->face_mat[f]] = 1;
    assert_true(in[0] && in[1]);
    seams++;
  }
  assert_int_equal(seams, 2 * 13);
  m->opt.duration = 0.1;
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s/skirt", tmpdir);
  if (sw_run(m, 0, err, sizeof err)) fail_msg("%s", err);
  sw_model_free(m);
}

static void test_repo_scene(void **state) {
  (void)state;
  char err[SW_ERRSZ], path[4096];
  if (!srcdir) skip();
  snprintf(path, sizeof path, "%s/scenes/hanging_cloth.yaml", srcdir);
  sw_model *m = sw_scene_load(path, err, sizeof err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->nv, 1600);
  assert_int_equal(m->nf, 2 * 39 * 39);
  assert_int_equal(count_pinned(m), 2);
  assert_true(m->pinned[1560] && m->pinned[1599]);
  assert_float_equal(m->x0[3 * 1599 + 1], 1.0, 1e-12);
  assert_float_equal(m->opt.frames_every, 0.05, 0.0);
  assert_string_equal(m->opt.out_dir, "out/hanging_cloth");
  sw_model_free(m);
}

/* The in-memory entry reads exactly len bytes (ASan sees any overread) and refuses NUL. */
static void test_memory(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  static const char text[] = "mesh: {grid: {size: [1, 1], vertices: [2, 2]}}\n"
                             "material: {density: 1}\nduration: 5";
  char *buf = malloc(sizeof text - 1);
  assert_non_null(buf);
  memcpy(buf, text, sizeof text - 1);
  sw_model *m = sw_scene_parse("mem/scene.yaml", buf, sizeof text - 1, err, sizeof err);
  if (!m) fail_msg("%s", err);
  assert_float_equal(m->opt.duration, 5.0, 0.0);
  assert_string_equal(m->name, "scene");
  sw_model_free(m);
  m = sw_scene_parse("mem/scene.yaml", "a: 1\n  \0b", 9, err, sizeof err);
  assert_null(m);
  assert_non_null(strstr(err, "mem/scene.yaml:2:3: "));
  assert_non_null(strstr(err, "NUL"));
  m = sw_scene_parse("mem/scene.yaml", "a: 1\n%r\xff", 8, err, sizeof err); /* hangs libfyaml */
  assert_null(m);
  assert_non_null(strstr(err, "mem/scene.yaml:2:3: "));
  assert_non_null(strstr(err, "UTF-8"));
  free(buf);
}

/* Inputs the fuzzer once found (hangs and leaks in libfyaml): no crash, no leak, no hang. */
static void test_regress(void **state) {
  (void)state;
  char dir[4096], path[4400], err[SW_ERRSZ];
  if (!srcdir) skip();
  snprintf(dir, sizeof dir, "%s/tests/fuzz/regress/scene", srcdir);
  DIR *d = opendir(dir);
  if (!d) skip();
  struct dirent *de;
  int n = 0;
  while ((de = readdir(d))) {
    if (de->d_name[0] == '.') continue;
    snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
    sw_model *m = sw_scene_load(path, err, sizeof err);
    if (!m && (strncmp(err, path, strlen(path)) || err[strlen(path)] != ':'))
      fail_msg("%s: message \"%s\" does not start with the file name", de->d_name, err);
    sw_model_free(m);
    n++;
  }
  closedir(d);
  assert_true(n > 0);
}

/* Every allocation failing in turn: NULL with a message, never a crash or a leak. */
static void test_alloc_failures(void **state) {
  (void)state;
  char err[SW_ERRSZ], path[1100];
  write_file("alloc.yaml", good_scene, path, sizeof path);
  for (long k = 1; k < 100000; k++) {
    sw_alloc_fail_after(k);
    sw_model *m = sw_scene_load(path, err, sizeof err);
    sw_alloc_fail_after(0);
    if (m) {
      sw_model_free(m);
      return;
    }
    assert_true(err[0] != '\0');
  }
  fail_msg("never succeeded");
}

/* disc: on an 11 x 11 grid of 1 m (spacing 0.1 m, plane xy) the vertices within r of the centre
 * (0.5, 0.5) are the lattice points (i, j) with i^2 + j^2 <= (r / 0.1)^2: 21 for r = 0.25 (Gauss's
 * circle count N(2.5)), 9 for r = 0.15; a centre off the plane by h selects the disc of radius
 * sqrt(r^2 - h^2) (a ball cut by the plane): h = 0.3, r = 0.5 leaves radius 0.4, N(4) = 49 less the
 * four points (+-4, 0), (0, +-4) exactly on the boundary kept, so 49. In 2D two numbers. */
static void test_disc(void **state) {
  (void)state;
  static const struct {
    const char *dim, *ctr;
    double r;
    int n;
  } cases[] = {
      {"3", "[0.5, 0.5, 0]", 0.25, 21},
      {"3", "[0.5, 0.5, 0]", 0.15, 9},
      {"3", "[0.5, 0.5, 0.3]", 0.5, 49},
      {"2", "[0.5, 0.5]", 0.25, 21},
      {"3", "[0, 0, 0]", 0.05, 1},
  };
  char err[SW_ERRSZ], text[512];
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    snprintf(text, sizeof text,
             "dimension: %s\nmesh: {grid: {size: [1, 1], vertices: [11, 11]}}\n"
             "material: {density: 0.1}\npins: [{select: {disc: {center: %s, radius: %.17g}}}]\n",
             cases[k].dim, cases[k].ctr, cases[k].r);
    sw_model *m = load_text("disc.yaml", text, err);
    if (!m) fail_msg("%s", err);
    int n = 0;
    for (int i = 0; i < m->nv; i++) {
      double dx = m->x0[i * m->dim] - 0.5, dy = m->x0[i * m->dim + 1] - 0.5;
      if (m->pinned[i] && k < 4) assert_true(dx * dx + dy * dy <= cases[k].r * cases[k].r);
      n += m->pinned[i];
    }
    assert_int_equal(n, cases[k].n);
    if (k == 4) assert_true(m->pinned[0]);
    sw_model_free(m);
  }
}

/* ------------------------------------------------------------------ bad scenes */

typedef struct bad_case {
  const char *file;
  const char *text;
  int line, col;        /* where the error must point (1-based) */
  const char *keyword;  /* the message must contain this */
} bad_case;

#define GRID "mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
#define MAT "material: {density: 0.1}\n"

static const bad_case bad[] = {
    {"syntax.yaml", GRID MAT "duration: 1: 2\n", 3, 12, "invalid YAML"},
    {"unclosed.yaml", GRID MAT "gravity: [0, 0, -9.81\n", 4, 1, "invalid YAML"},
    {"explicit_key.yaml", GRID MAT "? [a, b]\n: 1\n", 3, 1, "an explicit mapping key"},
    {"unknown_top.yaml", GRID MAT "colour: red\n", 3, 1, "unknown key 'colour'"},
    {"unknown_nested.yaml", GRID MAT "integrator: {method: backward-euler, step: 0.1}\n", 3, 38,
     "unknown key 'step'"},
    {"dt_string.yaml", GRID MAT "integrator: {dt: fast}\n", 3, 18, "dt"},
    {"dt_quoted.yaml", GRID MAT "integrator: {dt: \"0.01\"}\n", 3, 18, "quoted string"},
    {"dt_zero.yaml", GRID MAT "integrator:\n  dt: 0\n", 4, 7, "dt is 0"},
    {"dt_neg.yaml", GRID MAT "integrator: {dt: -0.01}\n", 3, 18, "> 0"},
    {"density.yaml", GRID "material: {density: -0.1}\n", 2, 21, "density"},
    {"k_u.yaml", GRID "material:\n  density: 0.1\n  membrane: {k_u: -1, k_v: 1, k_shear: 1}\n",
     4, 19, "k_u"},
    {"k_missing.yaml", GRID "material:\n  density: 0.1\n  membrane: {k_u: 1, k_v: 1}\n", 4, 13,
     "k_shear"},
    {"model.yaml", GRID "material:\n  density: 0.1\n  membrane: {model: neo, k_u: 1, k_v: 1,"
                        " k_shear: 1}\n", 4, 21, "bw98"},
    {"dimension.yaml", "dimension: 4\n" GRID MAT, 1, 12, "dimension"},
    {"vertices.yaml", "mesh: {grid: {size: [1, 1], vertices: [1, 5]}}\n" MAT, 1, 40,
     "vertices[0]"},
    {"size.yaml", "mesh: {grid: {size: [1, 0], vertices: [3, 3]}}\n" MAT, 1, 25, "size[1]"},
    {"pin_index.yaml", GRID MAT "pins:\n  - {select: {vertices: [0, 9]}}\n", 4, 29, "[0, 8]"},
    {"pin_box.yaml", GRID MAT "pins:\n  - select: {box: [[2, 2, 2], [3, 3, 3]]}\n", 4, 13,
     "selects no vertex"},
    {"box_order.yaml", GRID MAT "pins: [{select: {box: [[1, 0, 0], [0, 1, 1]]}}]\n", 3, 23,
     "min <= max"},
    {"select_both.yaml", GRID MAT "pins: [{select: {vertices: [0], box: [[0,0,0],[1,1,1]]}}]\n",
     3, 17, "exactly one"},
    {"disc_radius.yaml", GRID MAT "pins: [{select: {disc: {center: [0, 0, 0], radius: 0}}}]\n",
     3, 52, "> 0"},
    {"disc_center.yaml", GRID MAT "pins: [{select: {disc: {center: [0, 0], radius: 1}}}]\n", 3,
     33, "components"},
    {"disc_no_radius.yaml", GRID MAT "pins: [{select: {disc: {center: [0, 0, 0]}}}]\n", 3, 24,
     "radius"},
    {"disc_key.yaml", GRID MAT "pins: [{select: {disc: {center: [0, 0, 0], r: 1}}}]\n", 3, 44,
     "unknown key 'r'"},
    {"disc_empty.yaml", GRID MAT "pins: [{select: {disc: {center: [5, 5, 5], radius: 1}}}]\n",
     3, 17, "selects no vertex"},
    {"disc_box.yaml", GRID MAT "pins: [{select: {box: [[0,0,0],[1,1,1]], disc: {center: [0, 0, 0],"
     " radius: 1}}}]\n", 3, 17, "exactly one"},
    {"no_mesh.yaml", "name: x\n" MAT, 1, 1, "'mesh'"},
    {"no_material.yaml", GRID "duration: 1\n", 1, 1, "'material'"},
    {"both.yaml", "mesh: {grid: {size: [1, 1], vertices: [3, 3]}, obj: a.obj}\n" MAT, 1, 7,
     "exactly one of grid, obj or points"},
    {"uv_scale.yaml", "mesh: {grid: {size: [1, 1], vertices: [3, 3]}, uv_scale: 2}\n" MAT, 1, 58,
     "uv_scale"},
    {"missing_obj.yaml", "mesh:\n  obj: meshes/nothere.obj\n" MAT, 2, 8, "No such file"},
    {"obj_parse.yaml", "mesh:\n  obj: meshes/bad.obj\n" MAT, 2, 8,
     "in mesh obj: "},  /* then "<tmpdir>/meshes/bad.obj:3:6:" */
    {"obj_novt.yaml", "mesh: {obj: meshes/novt.obj}\nmaterial:\n  density: 0.1\n"
                      "  membrane: {k_u: 1, k_v: 1, k_shear: 1}\n", 4, 13,
     "no texture coordinates"},
    {"obj_2d.yaml", "dimension: 2\nmesh: {obj: meshes/tilted.obj}\n" MAT, 2, 13, "z = 0.5"},
    {"gravity.yaml", GRID MAT "gravity: [0, -9.81]\n", 3, 10, "components"},
    {"gravity_nan.yaml", GRID MAT "gravity: [0, 0, .nan]\n", 3, 17, "not finite"},
    {"method.yaml", GRID MAT "integrator: {method: rk4}\n", 3, 22, "backward-euler"},
    {"halvings.yaml", GRID MAT "integrator: {max_halvings: 61}\n", 3, 28, "[0, 60]"},
    {"hessian.yaml", GRID MAT "integrator: {hessian: fancy}\n", 3, 23, "projected, exact, auto"},
    {"ordering.yaml", GRID MAT "integrator: {ordering: colamd}\n", 3, 24,
     "auto, amd, metis, nesdis"},
    {"ordering_map.yaml", GRID MAT "integrator:\n  ordering: {method: amd}\n", 4, 13, "ordering"},
    {"setup_every.yaml", GRID MAT "integrator: {setup_every: 0}\n", 3, 27, "setup_every"},
    {"max_order.yaml", GRID MAT "integrator: {max_order: 6}\n", 3, 25, "[1, 5]"},
    {"max_order_word.yaml", GRID MAT "integrator: {max_order: high}\n", 3, 25,
     "expected auto or an integer in [1, 5]"},
    {"newton.yaml", GRID MAT "integrator: {newton: {max_iterations: 0}}\n", 3, 39,
     "max_iterations"},
    {"force_tol_zero.yaml", GRID MAT "integrator: {newton: {force_tol: 0}}\n", 3, 34,
     "integrator newton force_tol is 0; expected a number in (0, 1) (relative to the force "
     "scale)"},
    {"force_tol_one.yaml", GRID MAT "integrator: {newton: {force_tol: 1}}\n", 3, 34,
     "force_tol is 1; expected a number in (0, 1)"},
    {"force_tol_text.yaml", GRID MAT "integrator: {newton: {tol: 1e-6, force_tol: tight}}\n", 3,
     45, "force_tol"},
    {"force_tol_inf.yaml", GRID MAT "integrator: {newton: {force_tol: .inf}}\n", 3, 34,
     "force_tol"},
    {"plane_2d.yaml", "dimension: 2\nmesh: {grid: {size: [1, 1], vertices: [3, 3], plane: xz}}\n"
                      MAT, 2, 54, "xy"},
    {"duplicate.yaml", GRID MAT "duration: 1\nduration: 2\n", 4, 1, "duplicate key 'duration'"},
    {"duplicate_nested.yaml", GRID MAT "output: {dir: a, dir: b}\n", 3, 18, "duplicate"},
    {"velocity.yaml", GRID MAT "initial_velocity: [{velocity: [1, 2]}]\n", 3, 31, "components"},
    {"reference.yaml", GRID MAT "tension_xy: {reference: rest}\n", 3, 25, "initial, uv"},
    {"duration.yaml", GRID MAT "duration: -1\n", 3, 11, ">= 0"},
    {"frames.yaml", GRID MAT "output: {frames_every: [1]}\n", 3, 24, "a sequence"},
    {"format.yaml", GRID MAT "output: {frames_format: vtk}\n", 3, 25,
     "binary, binary32, ascii"},
    {"positions.yaml", GRID MAT "output: {positions_every: -0.1}\n", 3, 27,
     "output positions_every is -0.1; expected a number >= 0 (s)"},
    {"name.yaml", "name: {a: 1}\n" GRID MAT, 1, 7, "a string"},
    {"empty.yaml", "", 1, 1, "empty"},
    {"scalar.yaml", "hello\n", 1, 1, "expected a mapping"},
    {"list.yaml", "- mesh\n", 1, 1, "a sequence"},
    {"alias.yaml", GRID MAT "duration: &d 1\noutput: {frames_every: *d}\n", 4, 25, "alias"},
    {"tag.yaml", GRID MAT "duration: !!float 1\n", 3, 19, "tag"},
    {"two_docs.yaml", GRID MAT "---\nname: y\n", 4, 1, "second YAML document"},
    {"deep.yaml", GRID MAT "x: [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[["
                           "]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]\n", 3, 35, "nested"},
    /* materials, panels, damping (sim/input/scene_material.c) */
    {"stvk_neg.yaml", GRID "material:\n  density: 0.1\n"
     "  membrane: {model: stvk, e_u: -1, e_v: 1, shear_modulus: 1}\n", 4, 32, "e_u"},
    {"stvk_poisson.yaml", GRID "material:\n  density: 0.1\n"
     "  membrane: {model: stvk, e_u: 100, e_v: 400, shear_modulus: 10, poisson: 0.6}\n", 4, 75,
     "non-positive"},
    {"stvk_key.yaml", GRID "material:\n  density: 0.1\n"
     "  membrane: {model: stvk, e_u: 1, e_v: 1, shear_modulus: 1, k_u: 3}\n", 4, 66,
     "does not take"},
    {"corot_missing.yaml", GRID "material:\n  density: 0.1\n  membrane: {model: corotated}\n", 4,
     13, "'k'"},
    {"bias_nan.yaml", GRID "material: {density: 0.1, bias: .nan}\n", 2, 32, "bias"},
    {"bias_text.yaml", GRID "material: {density: 0.1, bias: warp}\n", 2, 32, "bias"},
    {"bend_2d.yaml", "dimension: 2\n" GRID "material:\n  density: 0.1\n"
     "  bending: {model: dihedral, stiffness: 1e-3}\n", 5, 20, "3D"},
    {"bend_rest.yaml", GRID "material:\n  density: 0.1\n"
     "  bending: {model: quadratic, stiffness: 1e-3, rest: initial}\n", 4, 54, "dihedral"},
    {"bend_rest_morley.yaml", GRID "material:\n  density: 0.1\n"
     "  bending: {model: morley, stiffness: 1e-3, rest: flat}\n", 4, 51, "dihedral"},
    {"bend_model.yaml", GRID "material:\n  density: 0.1\n"
     "  bending: {model: morly, stiffness: 1e-3}\n", 4, 20, "morley"},
    {"bend_neg.yaml", GRID "material:\n  density: 0.1\n"
     "  bending: {model: quadratic, stiffness: -1}\n", 4, 42, "stiffness"},
    {"panel_group.yaml", GRID MAT "panels: {front: {density: 0.2}}\n", 3, 10, "default"},
    {"damping_neg.yaml", GRID MAT "damping: {mass: -1}\n", 3, 17, "damping mass"},
    /* tendons (sim/input/scene_tendon.c) */
    {"tendon_repeat.yaml", GRID MAT "tendons:\n  - {waypoints: [0, 1, 0], stiffness: 10}\n", 4,
     24, "repeats vertex 0"},
    {"tendon_index.yaml", GRID MAT "tendons:\n  - {waypoints: [0, 9], stiffness: 10}\n", 4, 21,
     "[0, 8]"},
    {"tendon_one.yaml", GRID MAT "tendons:\n  - {waypoints: [4], stiffness: 10}\n", 4, 17,
     "at least two"},
    {"tendon_k.yaml", GRID MAT "tendons:\n  - {waypoints: [0, 1], stiffness: -5}\n", 4, 36,
     "stiffness"},
    {"tendon_keys.yaml", GRID MAT "tendons:\n  - waypoints: [0, 1]\n    stiffness: 5\n"
     "    rest_length: {keyframes: [[0, 1], [1, 0.5], [0.5, 0.7]]}\n", 6, 49, "increasing"},
    {"tendon_law.yaml", GRID MAT "tendons:\n  - {waypoints: [0, 1], stiffness: 5, law: rope}\n",
     4, 44, "cable"},
    {"tendon_name.yaml", GRID MAT "tendons:\n  - {name: a, waypoints: [0, 1], stiffness: 5}\n"
     "  - {name: a, waypoints: [1, 2], stiffness: 5}\n", 5, 12, "distinct names"},
    {"tendon_sel.yaml", GRID MAT "tendons:\n"
     "  - {waypoints: {box: [[-1, -1, -1], [0.1, 0.1, 1]]}, stiffness: 5}\n", 4, 17,
     "at least two"},
    {"dense_max.yaml", GRID MAT "integrator: {tendon_dense_max: -1}\n", 3, 32,
     "tendon_dense_max"},
    {"points_dim.yaml", "mesh: {points: [[0, 0, 0], [1, 0]]}\n", 1, 28, "components"},
    /* grid selections */
    {"grid_range.yaml", GRID MAT "pins: [{select: {grid: [[0, 3]]}}]\n", 3, 29, "[-3, 2]"},
    {"grid_pair.yaml", GRID MAT "pins: [{select: {grid: [[0, 1, 2]]}}]\n", 3, 25, "[i, j]"},
    {"grid_two.yaml", GRID MAT "pins: [{select: {grid: [[0, 0]], box: [[0, 0, 0], [1, 1, 1]]}}]\n",
     3, 17, "more than one"},
    {"grid_points.yaml", "mesh: {points: [[0, 0, 0], [1, 0, 0]]}\n"
     "pins: [{select: {grid: [[0, 0]]}}]\n", 2, 24, "not a grid"},
};

static void write_meshes(void) {
  char path[1100];
  snprintf(path, sizeof path, "%s/meshes", tmpdir);
  mkdir(path, 0700);
  write_file("meshes/bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n", path, sizeof path);
  write_file("meshes/novt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", path, sizeof path);
  write_file("meshes/tilted.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0.5\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n", path,
             sizeof path);
}

static void test_bad_scenes(void **state) {
  (void)state;
  write_meshes();
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    char err[SW_ERRSZ], path[1100], prefix[1200];
    write_file(bad[i].file, bad[i].text, path, sizeof path);
    memset(err, 0, sizeof err);
    sw_model *m = sw_scene_load(path, err, sizeof err);
    if (m) {
      sw_model_free(m);
      fail_msg("%s: loaded, expected an error", bad[i].file);
    }
    snprintf(prefix, sizeof prefix, "%s:%d:%d: ", path, bad[i].line, bad[i].col);
    if (strncmp(err, prefix, strlen(prefix)) || !strstr(err, bad[i].keyword))
      fail_msg("%s: got \"%s\", expected \"%s...%s...\"", bad[i].file, err, prefix,
               bad[i].keyword);
    if (!strcmp(bad[i].file, "obj_parse.yaml") && !strstr(err, "meshes/bad.obj:3:"))
      fail_msg("obj_parse.yaml: got \"%s\", expected the OBJ position", err);
  }
}

static void test_unreadable(void **state) {
  (void)state;
  char err[SW_ERRSZ], path[1100];
  snprintf(path, sizeof path, "%s/nothere.yaml", tmpdir);
  assert_null(sw_scene_load(path, err, sizeof err));
  assert_non_null(strstr(err, "nothere.yaml"));
  assert_non_null(strstr(err, "No such file"));
}

/* ------------------------------------------------------------------ overrides */

/* A 3D grid with a membrane (model line `memb`), bending `bend`, a tendon across the middle and
 * one along an edge, gravity, a point load and damping. */
static void overrides_scene(char *buf, size_t sz, const char *memb, const char *bend,
                            const char *txy) {
  snprintf(buf, sz,
           "mesh: {grid: {size: [1, 0.8], vertices: [6, 5]}}\n"
           "material:\n"
           "  density: 0.2\n"
           "  membrane: %s\n"
           "  bending: %s\n"
           "gravity: [0, 0, -9.81]\n"
           "damping: {mass: 0.5, stiffness: 0.01}\n"
           "pins: [{select: {box: [[-0.01, 0.79, -1], [1.01, 0.81, 1]]}}]\n"
           "loads: [{select: {vertices: [2]}, force: [0, 0, -1]}]\n"
           "tendons:\n"
           "  - {waypoints: {box: [[-0.01, 0.39, -1], [1.01, 0.41, 1]]}, law: spring,\n"
           "     stiffness: 300, rest_length: {relative: 0.9}, density: 0.01}\n"
           "  - {waypoints: [0, 1, 2], stiffness: 50, rest_length: 0.3}\n"
           "%s",
           memb, bend, txy);
}

/* The energy of every term at a deformed state x (nv x dim): into e (nterm). */
static void term_energies(const sw_model *m, const double *x, double *e) {
  sw_data *d = sw_data_new(m);
  assert_non_null(d);
  double u;
  assert_int_equal(sw_eval_terms(m, d, x, 0.0, 0, 0, 0, &u), SW_OK);
  memcpy(e, d->term_energy, (size_t)m->nterm * sizeof *e);
  sw_data_free(d);
}

static int elastic(const char *term) { return strcmp(term, "gravity") && strcmp(term, "loads"); }

/* With stiffness_scale s every elastic term's energy at a deformed state is s times the
 * unscaled one (s = 4 exactly: a power of two commutes with rounding); gravity and loads are
 * unchanged; so are masses, damping, rest lengths, the tension XY clip.  Every membrane model,
 * every bending model, tendons, derived and explicit tension XY stiffness; a measured fabric's
 * data (the dde membrane and bending). */
static void test_stiffness_scale(void **state) {
  (void)state;
  static const char *const memb[] = {
      "{model: bw98, k_u: 1000, k_v: 700, k_shear: 20, b_u: 1.02}",
      "{model: stvk, e_u: 800, e_v: 500, shear_modulus: 30, poisson: 0.3}",
      "{model: corotated, k: 600}",
      "{model: springs, stretch: 400, shear: 40, bend: 4}",
  };
  static const char *const bend[] = {"{model: dihedral, stiffness: 0.002, rest: flat}",
                                     "{model: quadratic, stiffness: 0.003}",
                                     "{model: morley, stiffness_u: 0.003, stiffness_v: 0.001}"};
  static const double scales[] = {4.0, 0.3};
  char text[2048];
  for (int k = 0; k < 12; k++) {
    overrides_scene(text, sizeof text, memb[k / 3], bend[k % 3],
                    k % 2 ? "" : "tension_xy: {k_u: 900, clip: 2000}\n");
    char err[SW_ERRSZ];
    sw_model *m0 = sw_scene_parse("scale.yaml", text, strlen(text), err, sizeof err);
    if (!m0) fail_msg("%s", err);
    assert_true(m0->stiffness_scale == 1.0);
    double x[90], e0[16], e1[16];
    assert_int_equal(m0->nv * m0->dim, 90);
    for (int i = 0; i < 90; i++) x[i] = m0->x0[i] + 0.05 * sin(1.3 * i + 0.7) + 0.02 * (i % 3 == 2);
    term_energies(m0, x, e0);
    for (int q = 0; q < 2; q++) {
      const double sc = scales[q];
      sw_scene_overrides ov = {{0, 0}, sc, 0, NULL};
      sw_model *m1 = sw_scene_parse_ex("scale.yaml", text, strlen(text), &ov, err, sizeof err);
      if (!m1) fail_msg("%s", err);
      assert_true(m1->stiffness_scale == sc);
      assert_int_equal(m1->nterm, m0->nterm);
      assert_true(m1->nterm == 5); /* membrane, bending, tendons, gravity, loads */
      term_energies(m1, x, e1);
      for (int t = 0; t < m1->nterm; t++) {
        assert_string_equal(m1->term[t].name, m0->term[t].name);
        double want = elastic(m0->term[t].name) ? sc * e0[t] : e0[t];
        if (!(fabs(e0[t]) > 0)) fail_msg("%s: energy 0 at the deformed state", m0->term[t].name);
        if (sc == 4.0 ? e1[t] != want : fabs(e1[t] - want) > 1e-13 * fabs(want))
          fail_msg("scene %d, s = %g, term %s: %.17g, expected %.17g", k, sc,
                   m0->term[t].name, e1[t], want);
      }
      assert_true(m1->total_mass == m0->total_mass);
      assert_true(m1->damp_mass == m0->damp_mass && m1->damp_stiffness == m0->damp_stiffness);
      assert_true(m1->opt.tx_clip == m0->opt.tx_clip);
      assert_true(m1->mat[0].b_u == m0->mat[0].b_u && m1->mat[0].nu_uv == m0->mat[0].nu_uv);
      assert_true(m1->mat[0].tx_k_u == sc * m0->mat[0].tx_k_u);
      assert_true(m1->mat[0].tx_k_v == sc * m0->mat[0].tx_k_v);
      for (int j = 0; j < 2; j++) {
        assert_true(m1->tendon[j].stiffness == sc * m0->tendon[j].stiffness);
        assert_true(m1->tendon[j].key_rest[0] == m0->tendon[j].key_rest[0]);
        assert_true(m1->tendon[j].density == m0->tendon[j].density);
      }
      for (int i = 0; i < m1->nv * m1->dim; i++)
        assert_true(m1->load ? m1->load[i] == m0->load[i] : 1);
      sw_model_free(m1);
    }
    sw_model_free(m0);
  }
  /* a measured fabric: the dde membrane and the data's curvature-dependent bending */
  snprintf(text, sizeof text,
           "mesh: {grid: {size: [1, 0.8], vertices: [6, 5]}}\n"
           "material: {fabric: {preset: gray-interlock}, bending: {model: dde}}\n"
           "gravity: [0, 0, -9.81]\n"
           "pins: [{select: {box: [[-0.01, 0.79, -1], [1.01, 0.81, 1]]}}]\n");
  char err[SW_ERRSZ];
  sw_model *m0 = sw_scene_parse("scale.yaml", text, strlen(text), err, sizeof err);
  if (!m0) fail_msg("%s", err);
  double x[90], e0[16], e1[16];
  for (int i = 0; i < 90; i++) x[i] = m0->x0[i] + 0.05 * sin(1.3 * i + 0.7) + 0.02 * (i % 3 == 2);
  term_energies(m0, x, e0);
  for (int q = 0; q < 2; q++) {
    sw_scene_overrides ov = {{0, 0}, scales[q], 0, NULL};
    sw_model *m1 = sw_scene_parse_ex("scale.yaml", text, strlen(text), &ov, err, sizeof err);
    if (!m1) fail_msg("%s", err);
    term_energies(m1, x, e1);
    for (int t = 0; t < m1->nterm; t++) {
      double want = elastic(m0->term[t].name) ? scales[q] * e0[t] : e0[t];
      if (!(fabs(e0[t]) > 0)) fail_msg("%s: energy 0 at the deformed state", m0->term[t].name);
      if (!(fabs(e1[t] - want) <= 1e-13 * fabs(want)))
        fail_msg("dde, s = %g, term %s: %.17g, expected %.17g", scales[q], m0->term[t].name,
                 e1[t], want);
    }
    if (scales[q] == 4.0) assert_true(m1->mat[0].tx_k_u == 4.0 * m0->mat[0].tx_k_u);
    sw_model_free(m1);
  }
  sw_model_free(m0);
}

/* The grid override: vertices replaced, boxes on the new grid, indices kept as indices (out of
 * range: the usual error), a mesh that is not a grid and bad overrides refused. */
static void test_grid_override(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  const char *text = "mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n" MAT
                     "pins: [{select: {box: [[-0.01, 0.99, -1], [1.01, 1.01, 1]]}}]\n";
  sw_scene_overrides ov = {{7, 5}, 0.0, 0, NULL};
  sw_model *m = sw_scene_parse_ex("grid.yaml", text, strlen(text), &ov, err, sizeof err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->nv, 35);
  assert_int_equal(m->nf, 2 * 6 * 4);
  assert_int_equal(count_pinned(m), 7); /* the top row of the new grid */
  for (int i = 28; i < 35; i++) assert_true(m->pinned[i]);
  assert_float_equal(m->x0[3 * 34 + 0], 1.0, 1e-12);
  assert_float_equal(m->x0[3 * 1 + 0], 1.0 / 6.0, 1e-12);
  assert_true(m->stiffness_scale == 1.0);
  sw_model_free(m);
  /* index 8 exists in 3 x 3, not in 2 x 2 */
  const char *idx = GRID MAT "pins: [{select: {vertices: [0, 8]}}]\n";
  ov = (sw_scene_overrides){{2, 2}, 0.0, 0, NULL};
  assert_null(sw_scene_parse_ex("idx.yaml", idx, strlen(idx), &ov, err, sizeof err));
  assert_non_null(strstr(err, "idx.yaml:3:"));
  assert_non_null(strstr(err, "vertices[1] is 8; expected an integer in [0, 3]"));
  ov = (sw_scene_overrides){{4, 4}, 0.0, 0, NULL};
  m = sw_scene_parse_ex("idx.yaml", idx, strlen(idx), &ov, err, sizeof err);
  if (!m) fail_msg("%s", err);
  assert_true(m->nv == 16 && m->pinned[0] && m->pinned[8] && count_pinned(m) == 2);
  /* 8 is no longer the far corner: the model says where the scene selects by index */
  assert_non_null(strstr(m->warning, "idx.yaml:3:28: the scene selects vertices by index"));
  sw_model_free(m);
  /* the same pins by grid position: the far corner on every grid, and no warning */
  const char *gp = GRID MAT "pins: [{select: {grid: [[0, 0], [-1, -1]]}}]\n";
  for (int n = 2; n <= 5; n++) {
    ov = (sw_scene_overrides){{n, n + 1}, 0.0, 0, NULL};
    m = sw_scene_parse_ex("gp.yaml", gp, strlen(gp), &ov, err, sizeof err);
    if (!m) fail_msg("%s", err);
    assert_true(m->pinned[0] && m->pinned[n * (n + 1) - 1] && count_pinned(m) == 2);
    assert_string_equal(m->warning, "");
    sw_model_free(m);
  }
  m = sw_scene_parse("gp.yaml", gp, strlen(gp), err, sizeof err);
  assert_true(m && m->pinned[8] && count_pinned(m) == 2 && !m->warning[0]);
  sw_model_free(m);
  /* not a grid: the mesh node, and what is expected */
  const char *obj = "mesh:\n  obj: nothere.obj\n" MAT;
  assert_null(sw_scene_parse_ex("obj.yaml", obj, strlen(obj), &ov, err, sizeof err));
  assert_non_null(strstr(err, "obj.yaml:2:3: mesh is an OBJ file (obj), not mesh: {grid: ...}"));
  const char *pts = "mesh: {points: [[0, 0, 0], [1, 0, 0]]}\n";
  assert_null(sw_scene_parse_ex("pts.yaml", pts, strlen(pts), &ov, err, sizeof err));
  assert_non_null(strstr(err, "pts.yaml:1:7: mesh is a list of points"));
  /* bad overrides: named, before the scene is read */
  const sw_scene_overrides bad[] = {{{1, 5}, 0.0, 0, NULL}, {{5, 0}, 0.0, 0, NULL}, {{2000, 2000}, 0.0, 0, NULL},
                                    {{0, 0}, -1.0, 0, NULL}, {{0, 0}, NAN, 0, NULL}};
  const char *want[] = {"grid override (--grid) is 1 x 5 vertices; expected at least 2",
                        "is 5 x 0 vertices", "expected at most 1000000 vertices in all",
                        "stiffness scale (--stiffness-scale) is -1; expected a number > 0",
                        "is nan"};
  for (int k = 0; k < 5; k++) {
    assert_null(sw_scene_parse_ex("g.yaml", text, strlen(text), &bad[k], err, sizeof err));
    if (strncmp(err, "g.yaml: ", 8) || !strstr(err, want[k]))
      fail_msg("override %d: \"%s\", expected \"%s\"", k, err, want[k]);
  }
  /* NULL and zero overrides are none */
  ov = (sw_scene_overrides){{0, 0}, 0.0, 0, NULL};
  m = sw_scene_parse_ex("g.yaml", text, strlen(text), &ov, err, sizeof err);
  assert_non_null(m);
  assert_true(m->nv == 9 && m->stiffness_scale == 1.0);
  sw_model_free(m);
}

/* ------------------------------------------------------------------ main */

static void cleanup(void) {
  char path[1100];
  for (int i = nwritten - 1; i >= 0; i--) unlink(written[i]);
  snprintf(path, sizeof path, "%s/meshes", tmpdir);
  rmdir(path);
  rmdir(tmpdir);
}

int main(int argc, char **argv) {
  const char *base = getenv("TMPDIR");
  srcdir = argc > 1 ? argv[1] : access("scenes/hanging_cloth.yaml", R_OK) == 0 ? "." : NULL;
  snprintf(tmpdir, sizeof tmpdir, "%s/sinew_test_scene_XXXXXX", base && *base ? base : "/tmp");
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_good_scene),   cmocka_unit_test(test_defaults),
      cmocka_unit_test(test_max_order),
      cmocka_unit_test(test_2d),           cmocka_unit_test(test_obj),
      cmocka_unit_test(test_repo_scene),   cmocka_unit_test(test_memory),
      cmocka_unit_test(test_bad_scenes),   cmocka_unit_test(test_unreadable),
      cmocka_unit_test(test_regress),      cmocka_unit_test(test_alloc_failures),
      cmocka_unit_test(test_panels),       cmocka_unit_test(test_tendons),
      cmocka_unit_test(test_skirt),        cmocka_unit_test(test_stiffness_scale),
      cmocka_unit_test(test_grid_override), cmocka_unit_test(test_disc),
  };
  int rc = cmocka_run_group_tests(tests, NULL, NULL);
  cleanup();
  return rc;
}
