/* scene_fabric.c — fabrics in the units textile laboratories report them, converted to SI in
 * this one place (docs/fabrics.md), and the plausibility warnings of a scene's numbers.
 *
 * A material's (or panel's) `fabric: {...}` sets its density, its bending (quadratic, a
 * rigidity in N m) and its membrane (bw98: warp, weft and shear stiffness in N/m) from:
 *   mass            g/m^2                      -> density  = mass * 1e-3 kg/m^2
 *   kes_b           KES-F B, gf cm^2/cm        -> k_bend   = kes_b * 9.80665e-5 N m
 * (each of the three bending keys takes one number, or [warp, weft]: the warp and weft
 * strips' rigidities, the bias one by sc_bend_bias_default, docs/models.md)
 *   fast_b          FAST bending rigidity, uN m -> k_bend  = fast_b * 1e-6 N m
 *   bending_length  cantilever (ASTM D1388), cm -> k_bend  = rho g c^3 (rho kg/m^2, c m)
 *   kes_g           KES-F G, gf/(cm deg)       -> k_shear  = kes_g * 56.1880 N/m per rad
 *   tensile         [warp, weft] N/m           -> k_u, k_v
 *   fast_e100       FAST E100, % at 100 gf/cm  -> k_u, k_v = 98.0665 N/m / (E100 / 100)
 * 1 gf = 9.80665e-3 N (the standard gravity of 1 g), so 1 gf cm^2/cm = 9.80665e-3 N * 1e-2 m
 * = 9.80665e-5 N m, and 1 gf/(cm deg) = 0.980665 N/m per degree = 0.980665 * 180/pi N/m per
 * rad.  A cantilever strip overhanging by its bending length c bends to 41.5 degrees (Peirce,
 * "The handle of cloth as a measurable quantity", J. Textile Inst. 1930): its rigidity per
 * width is w c^3, w = rho g its weight per area (ASTM D1388).  The bw98 shear condition
 * k_shear/2 (wu.wv)^2 per area gives a shear force per length k_shear * gamma for a small shear
 * angle gamma, which is what KES-F G measures; its warp and weft conditions give k_u and k_v
 * as tensile stiffnesses (N/m), which is what `tensile` and FAST's secant at 100 gf/cm give. */
#include "scene_fabric.h"
#include "dde.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* Message labels nest (panel NAME fabric kes_g); one cut short is still clear. */
#pragma GCC diagnostic ignored "-Wformat-truncation"

#define GRAM_FORCE 9.80665e-3                     /* N */
#define KES_B_SI (GRAM_FORCE * 1e-4 / 1e-2)       /* N m per gf cm^2/cm */
#define KES_G_SI (GRAM_FORCE / 1e-2 * 57.29577951308232) /* N/m per rad per gf/(cm deg) */
#define FAST_E100_LOAD (100.0 * GRAM_FORCE / 1e-2) /* N/m: 100 gf/cm */
#define G_STANDARD 9.80665                        /* m/s^2 */

static const char *const fab_keys[] = {"mass", "kes_b", "fast_b", "bending_length", "kes_g",
                                       "tensile", "fast_e100", "preset", "data"};
enum { F_MASS, F_KES_B, F_FAST_B, F_BLEN, F_KES_G, F_TENSILE, F_E100, F_PRESET, F_DATA, F_N };

double sc_fabric_kes_b(double b) { return b * KES_B_SI; }
double sc_fabric_kes_g(double g) { return g * KES_G_SI; }
double sc_fabric_e100(double e) { return FAST_E100_LOAD / (e / 100.0); }
double sc_fabric_cantilever(double gsm, double c_cm) {
  double c = c_cm * 1e-2; /* m */
  return gsm * 1e-3 * G_STANDARD * c * c * c;
}

/* The default bias rigidity (N m): a twisting rigidity G = sqrt(D_u D_v)/2, the geometric mean
 * of the isotropic ones, so D_45 = 4 / (1/sqrt(D_u) + 1/sqrt(D_v))^2 (models/bending.c). */
double sc_bend_bias_default(double ku, double kv) {
  double s = 1.0 / sqrt(ku) + 1.0 / sqrt(kv);
  return 4.0 / (s * s);
}

/* The bending rigidity from one of kes_b, fast_b or bending_length (N m). */
static int fabric_bending(const ctx *c, const ynode *y, const ynode *const *v, const char *w,
                          double gsm, sw_material *mat) {
  char lab[160];
  int n = !!v[F_KES_B] + !!v[F_FAST_B] + !!v[F_BLEN];
  if (n > 1)
    return sy_fail(c, y, "%s gives %d bending rigidities; expected one of kes_b, fast_b or "
                   "bending_length", w, n);
  int k = v[F_KES_B] ? F_KES_B : v[F_FAST_B] ? F_FAST_B : F_BLEN;
  static const char *const unit[] = {[F_KES_B] = "gf cm^2/cm (KES-F B)",
                                     [F_FAST_B] = "uN m (FAST)",
                                     [F_BLEN] = "cm (cantilever bending length)"};
  snprintf(lab, sizeof lab, "%s %s", w, fab_keys[k]);
  double x[2]; /* warp, weft: one number is both (isotropic) */
  int two = v[k]->kind == Y_SEQ;
  if (two ? sy_vec(c, v[k], lab, 2, 0, 1, unit[k], x) : sy_num(c, v[k], lab, 0, k == F_BLEN, unit[k], x))
    return -1;
  mat->bending = SW_BENDING_QUADRATIC;
  mat->bend_rest = SW_BEND_REST_FLAT;
  double kb[2];
  for (int i = 0; i < 2; i++) {
    double xi = x[two ? i : 0];
    kb[i] = k == F_KES_B ? sc_fabric_kes_b(xi) : k == F_FAST_B ? xi * 1e-6
                                                : sc_fabric_cantilever(gsm, xi);
  }
  mat->k_bend_u = two ? kb[0] : 0.0, mat->k_bend_v = two ? kb[1] : 0.0;
  mat->k_bend_bias = two ? sc_bend_bias_default(kb[0], kb[1]) : 0.0;
  mat->k_bend = fmax(kb[0], kb[1]);
  return 0;
}

/* The bw98 membrane from kes_g and one of tensile or fast_e100 (N/m). */
static int fabric_membrane(const ctx *c, const ynode *y, const ynode *const *v, const char *w,
                           sw_material *mat) {
  char lab[160];
  double t[2], g;
  if (v[F_TENSILE] && v[F_E100])
    return sy_fail(c, v[F_E100], "%s gives tensile and fast_e100; expected one of them", w);
  if (!v[F_KES_G])
    return sy_fail(c, y, "%s gives a tensile stiffness but no shear; expected kes_g: a number "
                   ">= 0 (gf/(cm deg), KES-F G) for the membrane", w);
  if (!v[F_TENSILE] && !v[F_E100])
    return sy_fail(c, y, "%s gives kes_g but no tensile stiffness; expected tensile: [warp, "
                   "weft] (N/m) or fast_e100: [warp, weft] (%%) for the membrane", w);
  snprintf(lab, sizeof lab, "%s kes_g", w);
  if (sy_num(c, v[F_KES_G], lab, 0, 0, "gf/(cm deg) (KES-F G)", &g)) return -1;
  int k = v[F_TENSILE] ? F_TENSILE : F_E100;
  snprintf(lab, sizeof lab, "%s %s", w, fab_keys[k]);
  if (sy_vec(c, v[k], lab, 2, 0, k == F_E100,
             k == F_E100 ? "% extension at 100 gf/cm, warp and weft" : "N/m, warp and weft", t))
    return -1;
  mat->membrane = SW_MEMBRANE_BW98;
  mat->k_u = k == F_E100 ? sc_fabric_e100(t[0]) : t[0];
  mat->k_v = k == F_E100 ? sc_fabric_e100(t[1]) : t[1];
  mat->k_shear = sc_fabric_kes_g(g);
  mat->b_u = mat->b_v = 1.0;
  return 0;
}

void sc_dde_strips(const sw_dde *dd, double kb[3]) {
  kb[0] = sw_dde_bend_rigidity(dd, 0.5 * M_PI, 0.0);  /* warp strip: hinges along weft */
  kb[1] = sw_dde_bend_rigidity(dd, 0.0, 0.0);         /* weft strip: hinges along warp */
  kb[2] = sw_dde_bend_rigidity(dd, 0.25 * M_PI, 0.0); /* bias strip */
}

/* The material of a measured fabric dd. */
static void fabric_dde(const sw_dde *dd, sw_material *mat, int *set) {
  double kb[3];
  sc_dde_strips(dd, kb);
  mat->density = dd->density;
  mat->membrane = SW_MEMBRANE_DDE;
  mat->dde = *dd;
  mat->bending = SW_BENDING_QUADRATIC;
  mat->bend_rest = SW_BEND_REST_FLAT;
  mat->k_bend_u = kb[0], mat->k_bend_v = kb[1], mat->k_bend_bias = kb[2];
  mat->k_bend = fmax(fmax(kb[0], kb[1]), kb[2]);
  *set = SC_FABRIC_BENDING | SC_FABRIC_MEMBRANE | SC_FABRIC_DDE;
}

/* `data: FILE`: a fabric file in the data set's format, relative to the scene's folder, into dd. */
static int fabric_data(const ctx *c, const ynode *y, const char *lab, sw_dde *dd) {
  const char *rel;
  char path[SW_PATHSZ], err[SW_ERRSZ];
  if (sy_str(c, y, lab, SW_PATHSZ, &rel) || sy_path(c, y, lab, rel, path)) return -1;
  if (sc_dde_read(path, dd, err, sizeof err)) return sy_fail(c, y, "%s: %s", lab, err);
  return 0;
}

/* `preset: NAME` (a fabric of data/fabrics/) or `data: FILE` (one in their format): its
 * density, the dde membrane, and the quadratic bending with the rigidities its strips read,
 * alone in the block. */
static int fabric_preset(const ctx *c, const ynode *y, const ynode *const *v, const char *w,
                         sw_material *mat, int *set) {
  char lab[192], list[600] = "", t[48];
  const int key = v[F_PRESET] ? F_PRESET : F_DATA;
  for (int k = 0; k < F_N; k++)
    if (k != key && v[k])
      return sy_fail(c, v[k], "%s gives %s and %s; expected %s alone (it sets the mass, "
                     "membrane and bending of a measured fabric)", w, fab_keys[key],
                     fab_keys[k], fab_keys[key]);
  snprintf(lab, sizeof lab, "%s %s", w, fab_keys[key]);
  sw_dde dd;
  if (key == F_DATA) {
    if (fabric_data(c, v[F_DATA], lab, &dd)) return -1;
    return fabric_dde(&dd, mat, set), 0;
  }
  const char *name;
  if (sy_str(c, v[F_PRESET], lab, 64, &name)) return -1;
  const sc_fabric_preset *p = sc_fabric_preset_find(name);
  if (!p) {
    for (int k = 0; k < sc_nfabric_presets; k++)
      snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", k ? ", " : "",
               sc_fabric_presets[k].name);
    return sy_fail(c, v[F_PRESET], "%s is '%s'; expected one of: %s", lab,
                   sy_clip(v[F_PRESET], t, sizeof t), list);
  }
  char err[SW_ERRSZ];
  if (sc_dde_parse(p->file, p->json, strlen(p->json), &dd, err, sizeof err))
    return sy_fail(c, v[F_PRESET], "%s %s: %s", lab, name, err);
  (void)y;
  fabric_dde(&dd, mat, set);
  return 0;
}

int sc_load_fabric(const ctx *c, const ynode *y, const char *what, sw_material *mat, int *set) {
  const ynode *v[F_N];
  char w[160], lab[192];
  double gsm;
  snprintf(w, sizeof w, "%s fabric", what);
  *set = 0;
  if (sy_map(c, y, w, fab_keys, F_N, v)) return -1;
  if (v[F_PRESET] || v[F_DATA]) return fabric_preset(c, y, v, w, mat, set);
  if (sy_need(c, y, v[F_MASS], w, "mass", "mass: a number > 0 (g/m^2), or preset: a measured "
              "fabric (docs/fabrics.md)"))
    return -1;
  snprintf(lab, sizeof lab, "%s mass", w);
  if (sy_num(c, v[F_MASS], lab, 0, 1, "g/m^2", &gsm)) return -1;
  mat->density = gsm * 1e-3; /* kg/m^2 */
  if (v[F_KES_B] || v[F_FAST_B] || v[F_BLEN]) {
    if (fabric_bending(c, y, v, w, gsm, mat)) return -1;
    *set |= SC_FABRIC_BENDING;
  }
  if (v[F_KES_G] || v[F_TENSILE] || v[F_E100]) {
    if (fabric_membrane(c, y, v, w, mat)) return -1;
    *set |= SC_FABRIC_MEMBRANE;
  }
  return 0;
}

/* ---------------------------------------------------------------- plausibility */

/* Append one warning to m->warning ("; " between two). */
static void warn(sw_model *m, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void warn(sw_model *m, const char *fmt, ...) {
  size_t n = strlen(m->warning);
  if (n + 3 >= sizeof m->warning) return;
  if (n) n += (size_t)snprintf(m->warning + n, sizeof m->warning - n, "; ");
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(m->warning + n, sizeof m->warning - n, fmt, ap);
  va_end(ap);
}

static const char *mat_name(const sw_material *mt) { return mt->group[0] ? mt->group : ""; }

void sc_plausibility(const ctx *c) {
  sw_model *m = c->m;
  if (m->nf == 0) return;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int i = 0; i < m->nv; i++)
    for (int d = 0; d < m->dim; d++) {
      lo[d] = fmin(lo[d], m->x0[i * m->dim + d]);
      hi[d] = fmax(hi[d], m->x0[i * m->dim + d]);
    }
  double size = 0;
  for (int d = 0; d < m->dim; d++) size = fmax(size, hi[d] - lo[d]);
  if (size > SC_PLAUSIBLE_SIZE)
    warn(m, "%s: the cloth is %.3g m across, more than %g m: are the mesh's units metres? (a "
         "mesh drawn in mm is 1000 times too large)", c->name, size, SC_PLAUSIBLE_SIZE);
  for (int k = 0; k < m->nmat; k++) {
    const sw_material *mt = &m->mat[k];
    const char *p = k ? "panel " : "material", *g = mat_name(mt);
    if (mt->density > SC_PLAUSIBLE_DENSITY_MAX || mt->density < SC_PLAUSIBLE_DENSITY_MIN)
      warn(m, "%s: %s%s density is %g kg/m^2, outside the %g to %g kg/m^2 of fabrics: is it "
           "in kg/m^2? (150 g/m^2 is density 0.15; fabric: {mass: 150} takes g/m^2)", c->name,
           p, g, mt->density, SC_PLAUSIBLE_DENSITY_MIN, SC_PLAUSIBLE_DENSITY_MAX);
    if (mt->bending && mt->k_bend > SC_PLAUSIBLE_BENDING_MAX)
      warn(m, "%s: %s%s bending stiffness is %g N m, above the %g N m of the stiffest "
           "fabrics: is it in N m? (KES-F B is in gf cm^2/cm: fabric: {kes_b: ...} converts "
           "it)", c->name, p, g, mt->k_bend, SC_PLAUSIBLE_BENDING_MAX);
    double k = mt->membrane == SW_MEMBRANE_BW98 ? fmax(mt->k_u, mt->k_v)
               : mt->membrane == SW_MEMBRANE_STVK ? fmax(mt->e_u, mt->e_v)
               : mt->membrane == SW_MEMBRANE_COROTATED ? mt->k_corot
               : mt->membrane == SW_MEMBRANE_DDE ? 2.0 * fmax(mt->dde.stretch[0][0], mt->dde.stretch[0][2])
               : 0;
    if (k > SC_PLAUSIBLE_TENSILE_MAX)
      warn(m, "%s: %s%s tensile stiffness is %g N/m, above the %g N/m of the stiffest "
           "fabrics: is it in N/m? (a modulus in Pa times the thickness in m)", c->name, p, g,
           k, SC_PLAUSIBLE_TENSILE_MAX);
  }
}
