/* test_dde.c — the measured fabrics (models/dde.c, sim/input/scene_dde.c, docs/fabrics.md): the
 * data-driven membrane's derivatives by finite differences (its density and the whole term
 * through the conformance harness), its stiffness equal to the published samples at the sample
 * strains and directions, the bending rigidity at its samples, the reader's file:line:column
 * errors for bad data, the shipped table equal to the files, and a preset loading with the
 * bending lengths of a hand computation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dde.h"
#include "harness.h"
#include "scene.h"
#include "scene_fabric.h"
#include "sinew.h"



static double urand(unsigned long *s) {
  *s = *s * 6364136223846793005ul + 1442695040888963407ul;
  return (double)(*s >> 11) / 9007199254740992.0;
}

/* The Voigt Green strain of stretch w along the direction theta (rad) from u, 0 across. */
static void along(double w, double theta, double e[3]) {
  double lam = 0.5 * (w * w - 1.0), c = cos(theta), s = sin(theta);
  e[0] = lam * c * c, e[1] = lam * s * s, e[2] = 2.0 * lam * c * s;
}

/* -------------------------------------------------------- (a) derivatives */

/* S against central differences of psi at e, H against those of S (step h), to 1e-6 and htol
 * of H's largest entry. */
static void check_derivatives(const sw_dde *dd, const double e[3], double h, double htol) {
  double S[3], H[9], Sp[3], Sm[3], scale = 1e-3;
  sw_dde_energy(dd, e, S, H);
  for (int i = 0; i < 9; i++) scale = fmax(scale, fabs(H[i]));
  for (int i = 0; i < 3; i++) {
    double ep[3] = {e[0], e[1], e[2]}, em[3] = {e[0], e[1], e[2]};
    ep[i] += h, em[i] -= h;
    double fp = sw_dde_energy(dd, ep, Sp, NULL), fm = sw_dde_energy(dd, em, Sm, NULL);
    th_near(S[i], (fp - fm) / (2 * h), 1e-6 * scale);
    for (int j = 0; j < 3; j++) th_near(H[3 * j + i], (Sp[j] - Sm[j]) / (2 * h), htol * scale);
  }
}

/* S against central differences of psi, H against those of S, at random strains (stretches
 * 0.8..1.35, every direction) of every preset. */
static void density_derivatives(void **st) {
  (void)st;
  unsigned long seed = 37;
  for (int k = 0; k < sc_nfabric_presets; k++) {
    sw_dde dd = th_dde_preset(sc_fabric_presets[k].name);
    for (int n = 0; n < 40; n++) {
      double e[3] = {0.5 * (pow(0.8 + 0.55 * urand(&seed), 2) - 1.0),
                     0.5 * (pow(0.8 + 0.55 * urand(&seed), 2) - 1.0), 0.6 * (urand(&seed) - 0.5)};
      check_derivatives(&dd, e, 1e-7, 1e-5);
    }
  }
}

/* The same at strains where the model is joined from pieces: near isotropic strains (half the
 * principal difference r below 0.02, around the fade's 0.01) and near the sample directions
 * 22.5, 45 and 67.5 degrees (off them by more than the differences' step: the monotone
 * cubic in direction is C1, its second derivative jumps there), stretched into the strain
 * ramp and past it. */
static void density_derivatives_joins(void **st) {
  (void)st;
  unsigned long seed = 41;
  const double pi = 3.14159265358979323846;
  for (int k = 0; k < sc_nfabric_presets; k++) {
    sw_dde dd = th_dde_preset(sc_fabric_presets[k].name);
    for (int n = 0; n < 60; n++) {
      double e[3], mean = 0.02 + 0.2 * urand(&seed), r, th;
      if (n % 2) r = 0.02 * urand(&seed), th = pi * urand(&seed);
      else { /* 1e-5..1e-4 rad off a sample direction, where the second derivative jumps */
        double off = 1e-5 + 9e-5 * urand(&seed);
        r = 0.02 + 0.1 * urand(&seed), th = (1 + n % 3) * pi / 8 + (urand(&seed) < 0.5 ? -off : off);
      }
      e[0] = mean + r * cos(2 * th), e[1] = mean - r * cos(2 * th), e[2] = 2 * r * sin(2 * th);
      check_derivatives(&dd, e, 1e-8, 1e-4);
    }
  }
}

/* The energy is continuously differentiable where its pieces meet: its stress S is the same on
 * both sides of each inner sample direction (a linear interpolation in direction jumps there),
 * and at an isotropic stretch (no principal direction) psi and S are the same whichever way
 * the strain approaches it (a direction-dependent stiffness would make psi itself jump). */
static void density_smooth(void **st) {
  (void)st;
  const double pi = 3.14159265358979323846, dth = 1e-7;
  for (int k = 0; k < sc_nfabric_presets; k++) {
    sw_dde dd = th_dde_preset(sc_fabric_presets[k].name);
    for (int iw = 0; iw < 2; iw++) {
      double w = iw ? 1.25 : 1.1, ea[3], eb[3], Sa[3], Sb[3];
      for (int j = 1; j <= 3; j++) {
        along(w, j * pi / 8 - dth, ea);
        along(w, j * pi / 8 + dth, eb);
        sw_dde_energy(&dd, ea, Sa, NULL);
        sw_dde_energy(&dd, eb, Sb, NULL);
        double sc = fabs(Sa[0]) + fabs(Sa[1]) + fabs(Sa[2]);
        for (int i = 0; i < 3; i++) th_near(Sa[i], Sb[i], 1e-4 * sc);
      }
    }
    const double iso = 0.08; /* both principal strains: a stretch of 1.077, in the ramp */
    double e0[3] = {iso, iso, 0}, S0[3], psi0 = sw_dde_energy(&dd, e0, S0, NULL);
    for (int j = 0; j < 8; j++) {
      double th = j * pi / 8, r = 1e-9, S[3];
      double e[3] = {iso + r * cos(2 * th), iso - r * cos(2 * th), 2 * r * sin(2 * th)};
      double psi = sw_dde_energy(&dd, e, S, NULL), lin = 0.0;
      for (int i = 0; i < 3; i++) lin += S0[i] * (e[i] - e0[i]); /* psi's first-order change */
      th_near(psi, psi0 + lin, 1e-12 * psi0);
      for (int i = 0; i < 3; i++) th_near(S[i], S0[i], 1e-6 * (fabs(S0[0]) + fabs(S0[1])));
    }
  }
}

/* The whole term (gradient, Hessian, symmetry, projection) through the harness, 2D and 3D. */
static void term_conformance(void **st) {
  (void)st;
  const char *names[] = {"gray-interlock", "11oz-black-denim", "navy-sparkle-sweat"};
  for (int dim = 2; dim <= 3; dim++)
    for (int k = 0; k < 3; k++) {
      sw_model *m = th_grid_unfinished(dim, 4, 3, 0.3, 0.2);
      assert_non_null(m);
      m->mat[0].density = 0.2;
      m->mat[0].membrane = SW_MEMBRANE_DDE;
      m->mat[0].dde = th_dde_preset(names[k]);
      char err[SW_ERRSZ];
      if (sw_model_finish(m, err, sizeof err)) fail_msg("%s", err);
      th_conformance(m, "dde", TH_INTERNAL | TH_REST_FREE, 0.15, 100u + (unsigned long)(3 * dim + k));
      sw_model_free(m);
    }
}

/* ------------------------------------------------------ (b) sample points */

/* At zero strain the stiffness is row 0; at a stretch of 7/6 along 0, 22.5, ..., 90 degrees it
 * is rows 1..5 (the file's numbers, a negative one 0); half-way in strain, their mean. */
static void stiffness_at_samples(void **st) {
  (void)st;
  const double pi = 3.14159265358979323846;
  for (int k = 0; k < sc_nfabric_presets; k++) {
    sw_dde dd = th_dde_preset(sc_fabric_presets[k].name);
    double c[4], e0[3] = {0, 0, 0}, e[3];
    sw_dde_stiffness(&dd, e0, c);
    for (int l = 0; l < 4; l++) th_near(c[l], dd.stretch[0][l], 0.0);
    for (int j = 0; j < 5; j++)
      for (int sign = -1; sign <= 1; sign += 2) { /* theta and -theta: the mirror image */
        along(7.0 / 6.0, sign * j * pi / 8.0, e);
        sw_dde_stiffness(&dd, e, c);
        for (int l = 0; l < 4; l++) th_near(c[l], dd.stretch[1 + j][l], 1e-9 * (1 + dd.stretch[1 + j][l]));
        along(1.0 + 1.0 / 12.0, sign * j * pi / 8.0, e);
        sw_dde_stiffness(&dd, e, c);
        for (int l = 0; l < 4; l++)
          th_near(c[l], 0.5 * (dd.stretch[0][l] + dd.stretch[1 + j][l]), 1e-9 * (1 + c[l]));
      }
  }
  /* the published numbers themselves (data/fabrics/gray-interlock.json, rows 0 and 3) */
  sw_dde dd = th_dde_preset("gray-interlock");
  double c[4], e[3];
  along(7.0 / 6.0, pi / 4.0, e);
  sw_dde_stiffness(&dd, e, c);
  th_near(c[0], 123.989220, 1e-9), th_near(c[1], 105.181770, 1e-9), th_near(c[2], 365.966217, 1e-9);
  th_near(c[3], 44.217571, 1e-9);
  const double zero[3] = {0, 0, 0};
  sw_dde_stiffness(&dd, zero, c);
  th_near(c[0], 16.593832, 0), th_near(c[1], 0.0, 0), th_near(c[2], 34.477123, 0), th_near(c[3], 36.860302, 0);
  assert_int_equal(dd.nclamped, 3); /* -14.695990, -29.691301, -174.43853 */
}

static void bending_at_samples(void **st) {
  (void)st;
  const double pi = 3.14159265358979323846;
  sw_dde dd = th_dde_preset("11oz-black-denim");
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 5; j++) {
      th_near(sw_dde_bend_rigidity(&dd, i * pi / 4.0, 10.0 * j), dd.bend[i][j] / 4, 1e-18);
      th_near(sw_dde_bend_rigidity(&dd, pi - i * pi / 4.0, -10.0 * j), dd.bend[i][j] / 4, 1e-18);
    }
  th_near(sw_dde_bend_rigidity(&dd, 0.0, 100.0), 19.824701e-6 / 4, 1e-18); /* held past 40 1/m */
  th_near(sw_dde_bend_rigidity(&dd, pi / 8.0, 5.0),
       (64.196457e-6 + 60.286175e-6 + 73.384567e-6 + 59.671982e-6) / 16, 1e-18);
}

/* A strip pulled along warp reads c11's stiffness at small strain: S11 = 2 (c11 - c12^2/c22) E11
 * with the weft free (S22 = 0), so a small tension T stretches it by T / (2 c11 - 2 c12^2/c22). */
static void uniaxial_small(void **st) {
  (void)st;
  sw_dde dd = th_dde_preset("11oz-black-denim"); /* row 0: 205.352005, 10.234077, 1013.88629 */
  double w;
  const double T = 1e-3, k = 2.0 * (205.352005 - 10.234077 * 10.234077 / 1013.88629);
  assert_int_equal(sw_dde_uniaxial(&dd, 0, T, &w), 0);
  th_near(w - 1.0, T / k, 1e-3 * T / k);
  assert_int_equal(sw_dde_uniaxial(&dd, 1, T, &w), 0);
  th_near(w - 1.0, T / (2.0 * (1013.88629 - 10.234077 * 10.234077 / 205.352005)), 1e-3 * T / k);
}

/* ------------------------------------------------------------ (c) the reader */

static void bad(const char *text, const char *want) {
  char err[SW_ERRSZ];
  sw_dde dd;
  assert_int_equal(sc_dde_parse("bad.json", text, strlen(text), &dd, err, sizeof err), -1);
  if (!strstr(err, want)) fail_msg("error '%s' lacks '%s'", err, want);
}

#define ROW4 "[1, 2, 3, 4]"
#define ROW5 "[1e-6, 1e-6, 1e-6, 1e-6, 1e-6]"
#define STRETCH "[" ROW4 "," ROW4 "," ROW4 "," ROW4 "," ROW4 "," ROW4 "]"
#define BEND "[" ROW5 "," ROW5 "," ROW5 "]"

static void reader_errors(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_dde dd;
  const char *good = "{\"density\": 0.2,\n \"stretching\": " STRETCH ",\n \"bending\": " BEND "}";
  if (sc_dde_parse("good.json", good, strlen(good), &dd, err, sizeof err)) fail_msg("%s", err);
  th_near(dd.density, 0.2, 0), th_near(dd.stretch[5][3], 4, 0), th_near(dd.bend[2][4], 1e-6, 0);
  bad("{\"density\": -0.2,\n \"stretching\": " STRETCH ",\n \"bending\": " BEND "}",
      "bad.json:1:13: density is -0.2; expected a number > 0 (kg/m^2)");
  bad("{\"density\": 0.2,\n \"stretching\": [" ROW4 "," ROW4 "," ROW4 "," ROW4 "," ROW4 "],\n "
      "\"bending\": " BEND "}",
      "bad.json:2:16: stretching has 5 rows; expected 6 rows of 4 numbers");
  bad("{\"density\": 0.2,\n \"stretching\": [" ROW4 ",\n [1, 2, 3]," ROW4 "," ROW4 "," ROW4 ","
      ROW4 "],\n \"bending\": " BEND "}",
      "bad.json:3:2: stretching[1] has 3 numbers; expected 4");
  bad("{\"density\": 0.2,\n \"stretching\": " STRETCH ",\n \"bending\": [" ROW5 "," ROW5 ",\n"
      "  [1e-6, NaN, 1e-6, 1e-6, 1e-6]]}",
      "bad.json:4:10: bending[2][1] is 'NaN'; expected a number >= 0");
  bad("{\"density\": 0.2,\n \"stretching\": " STRETCH ",\n \"bending\": [" ROW5 "," ROW5 ",\n"
      "  [1e-6, -1e-6, 1e-6, 1e-6, 1e-6]]}",
      "bad.json:4:10: bending[2][1] is -1e-6; expected a number >= 0");
  bad("{\"density\": 0.2,\n \"stretching\": " STRETCH "}", "bad.json:1:1: fabric data has no "
      "'bending' key");
  bad("{\"density\": 0.2, \"stretch\": 1}", "bad.json:1:18: fabric data has an unknown key 'stretch'");
  bad("{\"density\": 0.2,", "bad.json:2:1: invalid YAML");
  assert_int_equal(sc_dde_read("no/such/fabric.json", &dd, err, sizeof err), -1);
  assert_non_null(strstr(err, "no/such/fabric.json cannot be opened"));
  char path[] = "/tmp/sinew_dde_XXXXXX"; /* over the 1 MB limit: refused before it is parsed */
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "wb");
  for (int i = 0; i < (1 << 20) / 8 + 2; i++) fputs("        ", f);
  fclose(f);
  assert_int_equal(sc_dde_read(path, &dd, err, sizeof err), -1);
  remove(path);
  assert_non_null(strstr(err, "is over 1048576 bytes"));
}

/* The table the presets read is the shipped files, byte for byte (tools/fabric_presets.py). */
static void presets_equal_files(void **st) {
  (void)st;
  assert_int_equal(sc_nfabric_presets, 10);
  for (int k = 0; k < sc_nfabric_presets; k++) {
    const sc_fabric_preset *p = &sc_fabric_presets[k];
    FILE *f = fopen(p->file, "rb");
    if (!f) fail_msg("%s cannot be opened", p->file);
    char buf[4096];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    assert_string_equal(buf, p->json);
    char err[SW_ERRSZ];
    sw_dde a, b = th_dde_preset(p->name);
    if (sc_dde_read(p->file, &a, err, sizeof err)) fail_msg("%s", err);
    assert_memory_equal(&a, &b, sizeof a);
  }
}

/* ---------------------------------------------------------------- (d) presets */

static sw_model *parse(const char *text, char *err) {
  return sw_scene_parse("fabric.yaml", text, strlen(text), err, SW_ERRSZ);
}

/* gray-interlock: 0.187 kg/m^2; its strips' rigidities are a quarter of the data's first
 * column, the warp strip's hinges along weft (row 90 degrees): 14.267624e-6 / 4, weft
 * 23.191698e-6 / 4, bias 24.749964e-6 / 4 N m; the bending length c = (B / (rho g))^(1/3). */
static void preset_loads(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = parse("mesh: {grid: {size: [0.2, 0.2], vertices: [5, 5]}}\n"
                      "material: {fabric: {preset: gray-interlock}}\n", err);
  if (!m) fail_msg("%s", err);
  const sw_material *mt = &m->mat[0];
  th_near(mt->density, 0.187, 0);
  assert_int_equal(mt->membrane, SW_MEMBRANE_DDE);
  assert_int_equal(mt->bending, SW_BENDING_QUADRATIC);
  th_near(mt->k_bend_u, 3.566906e-6, 1e-20);
  th_near(mt->k_bend_v, 5.7979245e-6, 1e-20);
  th_near(mt->k_bend_bias, 6.187491e-6, 1e-20);
  const double w = 0.187 * 9.80665; /* N/m^2 */
  th_near(cbrt(mt->k_bend_u / w), 0.012483, 1e-6); /* hand: (3.566906e-6 / 1.833844)^(1/3) m */
  th_near(cbrt(mt->k_bend_v / w), 0.014677, 1e-6);
  th_near(cbrt(mt->k_bend_bias / w), 0.014999, 1e-6);
  assert_string_equal(m->warning, "");
  int found = 0;
  for (int k = 0; k < m->nterm; k++) found += !strcmp(m->term[k].name, "dde");
  assert_int_equal(found, 1);
  sw_model_free(m);
  for (int k = 0; k < sc_nfabric_presets; k++) { /* every preset loads, without a warning */
    char text[256];
    snprintf(text, sizeof text, "mesh: {grid: {size: [0.2, 0.2], vertices: [3, 3]}}\n"
             "material: {fabric: {preset: %s}}\n", sc_fabric_presets[k].name);
    m = parse(text, err);
    if (!m) fail_msg("%s: %s", sc_fabric_presets[k].name, err);
    assert_string_equal(m->warning, "");
    sw_model_free(m);
  }
}

/* `data: FILE` reads a file of the data set's format (relative to the scene's folder): the same
 * material as the preset; a bad file's error names the scene's key and the file's line. */
static void data_file(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *a = parse("mesh: {grid: {size: [0.2, 0.2], vertices: [3, 3]}}\n"
                      "material: {fabric: {data: data/fabrics/11oz-black-denim.json}}\n", err);
  if (!a) fail_msg("%s", err);
  sw_model *b = parse("mesh: {grid: {size: [0.2, 0.2], vertices: [3, 3]}}\n"
                      "material: {fabric: {preset: 11oz-black-denim}}\n", err);
  if (!b) fail_msg("%s", err);
  assert_memory_equal(&a->mat[0].dde, &b->mat[0].dde, sizeof(sw_dde));
  th_near(a->mat[0].k_bend_u, b->mat[0].k_bend_u, 0);
  th_near(a->mat[0].density, 0.324, 0);
  sw_model_free(a), sw_model_free(b);
  char path[] = "/tmp/sinew_dde_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "wb");
  fputs("{\"density\": 0.2,\n \"stretching\": [[1, 2, 3, 4]],\n \"bending\": []}\n", f);
  fclose(f);
  char text[256], want[128];
  snprintf(text, sizeof text, "mesh: {grid: {size: [0.2, 0.2], vertices: [3, 3]}}\n"
           "material: {fabric: {data: %s}}\n", path);
  assert_null(parse(text, err));
  remove(path);
  snprintf(want, sizeof want, "fabric.yaml:2:27: material fabric data: %s:2:16: stretching has 1 "
           "rows", path);
  if (!strstr(err, want)) fail_msg("error '%s' lacks '%s'", err, want);
  assert_null(parse("mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
                    "material: {fabric: {data: no/such.json, preset: gray-interlock}}\n", err));
  assert_non_null(strstr(err, "fabric.yaml:2:27: material fabric gives preset and data"));
}

static void preset_errors(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  assert_null(parse("mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
                    "material: {fabric: {preset: denim}}\n", err));
  assert_non_null(strstr(err, "fabric.yaml:2:29: material fabric preset is 'denim'; expected one "
                              "of: 11oz-black-denim, camel-ponte-roma, gray-interlock"));
  assert_null(parse("mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
                    "material: {fabric: {preset: gray-interlock, mass: 150}}\n", err));
  assert_non_null(strstr(err, "fabric.yaml:2:51: material fabric gives preset and mass"));
  assert_null(parse("mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\n"
                    "material: {fabric: {preset: gray-interlock}, membrane: {model: bw98, k_u: 1,"
                    " k_v: 1, k_shear: 1}}\n", err));
  assert_non_null(strstr(err, "fabric.yaml:2:"));
}

/* ------------------------------------------------- (e) the orthotropic cantilever */

/* Peirce's cantilever (scenes/peirce_cantilever.yaml) of a preset cut along warp (bias 0), at
 * 45 degrees and along weft (bias 90): each strip overhangs by twice the bending length of its
 * cut, c = (B / (rho g))^(1/3) with the rigidity of that cut, and must droop to the exact heavy
 * elastica's chord angle, 41.487 degrees (w L^3 / D = 8), within 1 %.  The strip is narrow
 * (width L/80, 161 x 2 cells): a bias strip reads its rigidity only as it narrows, the clamp
 * holding its bend-twist coupling over about its width (docs/models.md, "Anisotropic bending"). */
static void cantilever_cut(const char *name) {
  const double elastica = 41.487;                 /* degrees (tests/test_cantilever.c) */
  const double bias[3] = {0.0, 45.0, 90.0};       /* degrees: warp, bias and weft strips */
  const int nx = 162, ny = 3;
  sw_dde dd = th_dde_preset(name);
  double kb[3];
  sc_dde_strips(&dd, kb);
  const double B[3] = {kb[0], kb[2], kb[1]};      /* N m: warp, bias, weft */
  for (int k = 0; k < 3; k++) {
    double c = cbrt(B[k] / (dd.density * 9.81));  /* m; the scene's gravity is 9.81 */
    double size = 2.0 * c * (nx - 1) / (nx - 1.5), h = size / (nx - 1); /* overhang (nx - 1.5) h */
    char text[1024];
    snprintf(text, sizeof text,
             "dimension: 3\n"
             "mesh: {grid: {size: [%.15g, %.15g], vertices: [%d, %d], plane: xy}}\n"
             "material: {fabric: {preset: %s}, bending: {model: dihedral}, bias: %g}\n"
             "gravity: [0, 0, -9.81]\n"
             "pins: [{select: {box: [[-1, -1, -1], [%.15g, 1, 1]]}}]\n"
             "integrator: {method: static}\nduration: 0\n",
             size, size / 80.0, nx, ny, name, bias[k], 1.01 * h);
    sw_model *m = th_scene("cut.yaml", text);
    assert_non_null(m);
    double angle = th_peirce_angle(m);
    print_message("%s cut at %g degrees, B = %.4g N m, overhang %.4f m: chord %.3f deg "
                  "(elastica %.3f)\n", name, bias[k], B[k], 2 * c, angle, elastica);
    if (!(fabs(angle - elastica) < 0.01 * elastica)) fail_msg("chord %.3f deg", angle);
    sw_model_free(m);
  }
}
static void cantilever_cuts(void **st) {
  (void)st;
  cantilever_cut("gray-interlock");
  cantilever_cut("11oz-black-denim");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(density_derivatives), cmocka_unit_test(density_derivatives_joins),
      cmocka_unit_test(density_smooth),      cmocka_unit_test(term_conformance),
      cmocka_unit_test(stiffness_at_samples), cmocka_unit_test(bending_at_samples),
      cmocka_unit_test(uniaxial_small),      cmocka_unit_test(reader_errors),
      cmocka_unit_test(presets_equal_files), cmocka_unit_test(preset_loads),
      cmocka_unit_test(preset_errors),       cmocka_unit_test(cantilever_cuts),
      cmocka_unit_test(data_file),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
