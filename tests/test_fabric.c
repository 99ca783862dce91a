/* test_fabric.c — fabrics in measured units (sim/input/scene_fabric.c, docs/fabrics.md): each
 * conversion against its derivation from the definitions of its units, a scene's fabric block
 * filling the material as those conversions say, a strip given by its cantilever bending length
 * drooping to Peirce's 41.5 degrees, the errors of contradictory blocks, and the plausibility
 * warnings (a cloth typed in mm, a density in g/m^2, a KES value typed as N m) that no shipped
 * scene draws. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "scene.h"
#include "scene_fabric.h"
#include "scene_material.h"
#include "sinew.h"

#define PI 3.14159265358979323846

static sw_model *parse(const char *text, char *err) {
  return sw_scene_parse("fabric.yaml", text, strlen(text), err, SW_ERRSZ);
}

static void near(double got, double want, double rel) {
  if (!(fabs(got - want) <= rel * fabs(want))) fail_msg("got %.12g, expected %.12g", got, want);
}

/* The units from their definitions: 1 gf is the weight of 1 g under standard gravity. */
static void conversions(void **st) {
  (void)st;
  const double gf = 1e-3 * 9.80665;                   /* N */
  near(sc_fabric_kes_b(1.0), gf * 0.01 * 0.01 / 0.01, 1e-14); /* gf cm^2 / cm */
  near(sc_fabric_kes_b(1.0), 9.80665e-5, 1e-14);
  near(sc_fabric_kes_g(1.0), gf / 0.01 / (PI / 180.0), 1e-14); /* gf / (cm degree) */
  near(sc_fabric_kes_g(1.0), 56.19, 1e-4);
  near(sc_fabric_e100(2.0), 100 * gf / 0.01 / 0.02, 1e-14); /* 100 gf/cm over a 2 % strain */
  near(sc_fabric_cantilever(200.0, 4.0), 0.2 * 9.80665 * 0.04 * 0.04 * 0.04, 1e-14);
}

static void fabric_block(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = parse("mesh: {grid: {size: [1, 1], vertices: [4, 4]}}\n"
                      "material:\n"
                      "  fabric: {mass: 150, kes_b: 0.08, kes_g: 0.6, fast_e100: [2, 4]}\n",
                      err);
  if (!m) fail_msg("%s", err);
  const sw_material *mt = &m->mat[0];
  near(mt->density, 0.15, 1e-15);
  assert_int_equal(mt->bending, SW_BENDING_QUADRATIC);
  near(mt->k_bend, 0.08 * 9.80665e-5, 1e-14);
  assert_int_equal(mt->membrane, SW_MEMBRANE_BW98);
  near(mt->k_u, 9806.65 / 2, 1e-14);
  near(mt->k_v, 9806.65 / 4, 1e-14);
  near(mt->k_shear, 0.6 * 0.980665 * 180 / PI, 1e-14);
  near(mt->b_u, 1.0, 0), near(mt->b_v, 1.0, 0);
  assert_string_equal(m->warning, "");
  sw_model_free(m);
  /* FAST bending and tensile in N/m; a fabric with only a mass leaves membrane and bending */
  m = parse("mesh: {grid: {size: [1, 1], vertices: [4, 4]}}\n"
            "material:\n"
            "  fabric: {mass: 300, fast_b: 12, kes_g: 1.5, tensile: [4000, 2500]}\n", err);
  if (!m) fail_msg("%s", err);
  near(m->mat[0].k_bend, 12e-6, 1e-14);
  near(m->mat[0].k_u, 4000, 0), near(m->mat[0].k_v, 2500, 0);
  sw_model_free(m);
  m = parse("mesh: {grid: {size: [1, 1], vertices: [4, 4]}}\n"
            "material:\n"
            "  fabric: {mass: 80}\n"
            "  membrane: {model: corotated, k: 100}\n", err);
  if (!m) fail_msg("%s", err);
  near(m->mat[0].density, 0.08, 1e-15);
  assert_int_equal(m->mat[0].membrane, SW_MEMBRANE_COROTATED);
  assert_int_equal(m->mat[0].bending, SW_BENDING_NONE);
  sw_model_free(m);
}

/* scenes/peirce_cantilever.yaml with its strip given as a fabric of 200 g/m^2 and a bending
 * length of 4 cm, and the bending line `bend` ("" or "  bending: {model: M}\n" beside the
 * fabric): overhang 2c droops to the heavy elastica's chord angle 41.487 degrees
 * (tests/test_cantilever.c), within 0.1 degree, with the bending model `model`. */
static void peirce_fabric(const char *bend, int model) {
  char err[SW_ERRSZ], text[1024];
  snprintf(text, sizeof text,
           "mesh: {grid: {size: [0.0809876543209877, 0.02], vertices: [42, 11], plane: xy}}\n"
           "material:\n"
           "  fabric: {mass: 200, bending_length: 4}\n"
           "%s"
           "  membrane: {model: bw98, k_u: 10000, k_v: 10000, k_shear: 10000}\n"
           "gravity: [0, 0, -9.80665]\n"
           "pins: [{select: {box: [[-1, -1, -1], [0.0020, 1, 1]]}}]\n"
           "integrator: {method: static}\n"
           "duration: 0\n", bend);
  sw_model *m = parse(text, err);
  if (!m) fail_msg("%s", err);
  assert_int_equal(m->mat[0].bending, model);
  assert_true(fabs(m->mat[0].k_bend - 0.2 * 9.80665 * 0.04 * 0.04 * 0.04) < 1e-15); /* N m */
  double angle = th_peirce_angle(m);
  print_message("fabric bending_length 4 cm, overhang 8 cm%s: chord angle %.3f deg\n",
                *bend ? ", bending model given" : "", angle);
  assert_true(fabs(angle - 41.487) < 0.1);
  sw_model_free(m);
}
/* The fabric's bending is quadratic. */
static void cantilever_bending_length(void **st) {
  (void)st, peirce_fabric("", SW_BENDING_QUADRATIC);
}
/* Beside a fabric with a bending rigidity, bending: {model: M} picks the model its rigidity
 * goes to. */
static void fabric_bending_model(void **st) {
  (void)st, peirce_fabric("  bending: {model: morley}\n", SW_BENDING_MORLEY);
}

/* Orthotropic bending from a scene: stiffness_u/v/bias, the default bias, fabric [warp, weft]. */
static void orthotropic_keys(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = parse("mesh: {grid: {size: [1, 1], vertices: [4, 4]}}\n"
                      "material:\n  density: 0.1\n"
                      "  bending: {model: quadratic, stiffness_u: 3e-5, stiffness_v: 1e-5, "
                      "stiffness_bias: 2e-5}\n", err);
  if (!m) fail_msg("%s", err);
  near(m->mat[0].k_bend_u, 3e-5, 0), near(m->mat[0].k_bend_v, 1e-5, 0);
  near(m->mat[0].k_bend_bias, 2e-5, 0), near(m->mat[0].k_bend, 3e-5, 0);
  sw_model_free(m);
  /* without a bias: twisting rigidity sqrt(D_u D_v)/2, D_45 = 4/(D_u^-1/2 + D_v^-1/2)^2 */
  m = parse("mesh: {grid: {size: [1, 1], vertices: [4, 4]}}\n"
            "material:\n  density: 0.1\n"
            "  bending: {model: dihedral, stiffness_u: 4e-5, stiffness_v: 1e-5}\n", err);
  if (!m) fail_msg("%s", err);
  near(m->mat[0].k_bend_bias, 4.0 / pow(1.0 / sqrt(4e-5) + 1.0 / sqrt(1e-5), 2), 1e-14);
  near(1.0 / (4.0 / m->mat[0].k_bend_bias - 1.0 / 4e-5 - 1.0 / 1e-5), 0.5 * sqrt(4e-5 * 1e-5),
       1e-12);
  sw_model_free(m);
  m = parse("mesh: {grid: {size: [1, 1], vertices: [4, 4]}}\n"
            "material:\n  fabric: {mass: 200, kes_b: [0.12, 0.04]}\n", err);
  if (!m) fail_msg("%s", err);
  near(m->mat[0].k_bend_u, 0.12 * 9.80665e-5, 1e-14);
  near(m->mat[0].k_bend_v, 0.04 * 9.80665e-5, 1e-14);
  near(m->mat[0].k_bend_bias, sc_bend_bias_default(0.12 * 9.80665e-5, 0.04 * 9.80665e-5), 0);
  sw_model_free(m);
}

typedef struct bad_case {
  const char *text;
  int line, col;
  const char *keyword;
} bad_case;

#define GRID "mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\nmaterial:\n"

static void bad_fabrics(void **st) {
  (void)st;
  static const bad_case bad[] = {
      {GRID "  density: 0.1\n  fabric: {mass: 100}\n", 3, 12, "density and fabric"},
      {GRID "  fabric: {kes_b: 0.1}\n", 3, 11, "no 'mass'"},
      {GRID "  fabric: {mass: 0}\n", 3, 18, "mass"},
      {GRID "  fabric: {mass: 100, kes_b: 0.1, fast_b: 3}\n", 3, 11, "2 bending rigidities"},
      {GRID "  fabric: {mass: 100, kes_g: 0.5}\n", 3, 11, "no tensile stiffness"},
      {GRID "  fabric: {mass: 100, tensile: [1, 2]}\n", 3, 11, "no shear"},
      {GRID "  fabric: {mass: 100, kes_g: 1, tensile: [1, 2], fast_e100: [1, 2]}\n", 3, 61,
       "tensile and fast_e100"},
      {GRID "  fabric: {mass: 100, kes_g: 1, fast_e100: [0, 2]}\n", 3, 45, "fast_e100[0]"},
      {GRID "  fabric: {mass: 100, bending_length: 0}\n", 3, 39, "bending_length"},
      {GRID "  fabric: {mass: 100, kes_b: 0.1}\n  bending: {model: quadratic, stiffness: 1}\n",
       4, 42, "bending stiffness and a fabric"},
      {GRID "  fabric: {mass: 100, kes_b: 0.1}\n  bending: {model: shell}\n", 4, 20, "morley"},
      {GRID "  fabric: {mass: 100, kes_g: 1, tensile: [1, 2]}\n"
            "  membrane: {model: bw98, k_u: 1, k_v: 1, k_shear: 1}\n", 4, 13, "membrane and a "},
      {GRID "  fabric: {mass: 100, gsm: 3}\n", 3, 23, "unknown key 'gsm'"},
      {GRID "  density: 0.1\n  bending: {model: quadratic, stiffness: 1, stiffness_u: 2}\n", 4,
       58, "rigidity per direction"},
      {GRID "  density: 0.1\n  bending: {model: quadratic, stiffness_u: 2}\n", 4, 44,
       "only one of"},
      {GRID "  density: 0.1\n  bending: {model: quadratic, stiffness_u: 3, stiffness_v: 1, "
            "stiffness_bias: 3}\n", 4, 79, "stiffest bias strip"},
      {GRID "  density: 0.1\n  bending: {model: quadratic, stiffness_u: 0, stiffness_v: 1}\n",
       4, 44, "stiffness_u"},
      {GRID "  fabric: {mass: 100, kes_b: [0.1, 0]}\n", 3, 36, "kes_b[1]"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    char err[SW_ERRSZ], prefix[64];
    sw_model *m = parse(bad[i].text, err);
    if (m) {
      sw_model_free(m);
      fail_msg("case %zu loaded, expected an error", i);
    }
    snprintf(prefix, sizeof prefix, "fabric.yaml:%d:%d: ", bad[i].line, bad[i].col);
    if (strncmp(err, prefix, strlen(prefix)) || !strstr(err, bad[i].keyword))
      fail_msg("case %zu: got \"%s\", expected \"%s...%s...\"", i, err, prefix, bad[i].keyword);
  }
}

static void expect_warning(const char *text, const char *words) {
  char err[SW_ERRSZ];
  sw_model *m = parse(text, err);
  if (!m) fail_msg("%s", err);
  if (!strstr(m->warning, words)) fail_msg("warning \"%s\", expected \"%s\"", m->warning, words);
  sw_model_free(m);
}

static void warnings(void **st) {
  (void)st;
  /* a 1 m cloth typed in mm, 150 g/m^2 typed as kg/m^2, KES-F B typed as N m, a modulus in Pa */
  expect_warning("mesh: {grid: {size: [1000, 1000], vertices: [3, 3]}}\n"
                 "material: {density: 0.15}\n", "1e+03 m across");
  expect_warning(GRID "  density: 150\n", "density is 150 kg/m^2");
  expect_warning(GRID "  density: 0.005\n", "density is 0.005 kg/m^2");
  expect_warning(GRID "  density: 0.1\n  bending: {model: quadratic, stiffness: 0.08}\n",
                 "bending stiffness is 0.08 N m");
  expect_warning(GRID "  density: 0.1\n  membrane: {model: stvk, e_u: 2e9, e_v: 1, "
                 "shear_modulus: 1}\n", "tensile stiffness is 2e+09 N/m");
  /* each number once, in one line: the cloth in mm and its density in g/m^2 */
  expect_warning("mesh: {grid: {size: [500, 500], vertices: [3, 3]}}\n"
                 "material: {density: 150}\n", "500 m across, more than 10 m: are the mesh's "
                 "units metres? (a mesh drawn in mm is 1000 times too large); fabric.yaml: "
                 "material density is 150 kg/m^2");
}

/* No shipped scene draws a warning (run from the source tree). */
static void shipped_scenes_are_plausible(void **st) {
  (void)st;
  static const char *const dirs[] = {"scenes", "scenes/models", "scenes/bench"};
  int n = 0;
  for (int k = 0; k < 3; k++) {
    DIR *dir = opendir(dirs[k]);
    if (!dir) fail_msg("%s: not found (run from the source tree)", dirs[k]);
    struct dirent *e;
    while ((e = readdir(dir))) {
      size_t len = strlen(e->d_name);
      if (len < 6 || strcmp(e->d_name + len - 5, ".yaml")) continue;
      char path[512], err[SW_ERRSZ];
      snprintf(path, sizeof path, "%s/%s", dirs[k], e->d_name);
      sw_model *m = sw_scene_load(path, err, sizeof err);
      if (!m) fail_msg("%s", err);
      if (m->warning[0]) fail_msg("%s warns: %s", path, m->warning);
      sw_model_free(m);
      n++;
    }
    closedir(dir);
  }
  assert_true(n >= 20);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(conversions),  cmocka_unit_test(fabric_block),
      cmocka_unit_test(cantilever_bending_length),
      cmocka_unit_test(fabric_bending_model), cmocka_unit_test(bad_fabrics),
      cmocka_unit_test(orthotropic_keys),
      cmocka_unit_test(warnings),     cmocka_unit_test(shipped_scenes_are_plausible),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
