/* scene_material.c — a scene's `material`, `panels` and `damping`
 * (docs/scenes.md).  The material is mat[0]; each panel (an OBJ usemtl/g group) is a copy of it
 * with the keys the panel gives.  A membrane or bending block replaces the whole block. */
#include "scene_material.h"
#include "scene_fabric.h"
#include "dde.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "util.h"

/* Message labels nest (tendon s1 rest_length keyframes[2]); one cut short is still clear. */
#pragma GCC diagnostic ignored "-Wformat-truncation"

/* One numeric parameter of a membrane model: its key, where it goes, its range. */
typedef struct param {
  const char *key;
  size_t off;        /* offsetof(sw_material, field) */
  double lo;         /* smallest value (strict: excluded) */
  int strict;
  const char *unit;
  int required;
  double dflt;       /* value when absent and not required */
} param;

#define P(k, f, lo, st, u, req, d) {k, offsetof(sw_material, f), lo, st, u, req, d}
static const param bw98_p[] = {P("k_u", k_u, 0, 0, "N/m", 1, 0), P("k_v", k_v, 0, 0, "N/m", 1, 0),
                               P("k_shear", k_shear, 0, 0, "N/m", 1, 0),
                               P("b_u", b_u, 0, 1, NULL, 0, 1), P("b_v", b_v, 0, 1, NULL, 0, 1)};
static const param stvk_p[] = {P("e_u", e_u, 0, 1, "N/m", 1, 0), P("e_v", e_v, 0, 1, "N/m", 1, 0),
                               P("shear_modulus", g_uv, 0, 1, "N/m", 1, 0),
                               P("poisson", nu_uv, -HUGE_VAL, 0, NULL, 0, 0)};
static const param corot_p[] = {P("k", k_corot, 0, 0, "N/m", 1, 0)};
static const param springs_p[] = {P("stretch", ks_stretch, 0, 0, "N/m", 1, 0),
                                  P("shear", ks_shear, 0, 0, "N/m", 0, 0),
                                  P("bend", ks_bend, 0, 0, "N/m", 0, 0)};
#undef P

typedef struct memb_model {
  const char *name;
  int type;          /* SW_MEMBRANE_* */
  const param *p;
  int np;
} memb_model;

static const memb_model memb_models[] = {
    {"bw98", SW_MEMBRANE_BW98, bw98_p, 5},
    {"stvk", SW_MEMBRANE_STVK, stvk_p, 4},
    {"corotated", SW_MEMBRANE_COROTATED, corot_p, 1},
    {"springs", SW_MEMBRANE_SPRINGS, springs_p, 3},
};
enum { N_MEMB = 4 };

/* Every key any membrane takes ("model" first): a key of another model is then named as such. */
static const char *const memb_keys[] = {"model", "k_u",   "k_v",           "k_shear",
                                        "b_u",   "b_v",   "e_u",           "e_v",
                                        "poisson", "shear_modulus", "k", "stretch",
                                        "shear", "bend"};
enum { N_MEMB_KEYS = 14 };

static const param *find_param(const memb_model *mm, const char *key) {
  for (int i = 0; i < mm->np; i++)
    if (!strcmp(mm->p[i].key, key)) return &mm->p[i];
  return NULL;
}

/* Only the keys of the chosen model; then each parameter in its range. */
static int membrane_params(const ctx *c, const ynode *y, const memb_model *mm,
                           const ynode *const *v, const char *w, sw_material *mat) {
  char lab[160], keys[160];
  const char *names[8];
  for (int i = 0; i < mm->np; i++) names[i] = mm->p[i].key;
  sy_join(names, mm->np, keys, sizeof keys);
  for (int k = 1; k < N_MEMB_KEYS; k++)
    if (v[k] && !find_param(mm, memb_keys[k]))
      return sy_fail(c, v[k], "%s has '%s', which model %s does not take; expected keys among: "
                     "model, %s", w, memb_keys[k], mm->name, keys);
  for (int i = 0; i < mm->np; i++) {
    const param *p = &mm->p[i];
    const ynode *val = NULL;
    for (int k = 1; k < N_MEMB_KEYS; k++)
      if (!strcmp(memb_keys[k], p->key)) val = v[k];
    double *dst = (double *)((char *)mat + p->off);
    snprintf(lab, sizeof lab, "%s %s", w, p->key);
    if (!val && p->required)
      return sy_fail(c, y, "%s (model %s) has no '%s' key; expected a number %s %g%s%s%s", w,
                     mm->name, p->key, p->strict ? ">" : ">=", p->lo, p->unit ? " (" : "",
                     p->unit ? p->unit : "", p->unit ? ")" : "");
    *dst = p->dflt;
    if (val && sy_num(c, val, lab, p->lo, p->strict, p->unit, dst)) return -1;
  }
  return 0;
}

/* stvk: Q (plane-stress orthotropic) is positive definite iff nu_uv^2 e_v / e_u < 1. */
static int check_stvk(const ctx *c, const ynode *y, const ynode *pois, const char *w,
                      const sw_material *mat) {
  double q = mat->nu_uv * mat->nu_uv * mat->e_v / mat->e_u;
  if (q < 1.0) return 0;
  return sy_fail(c, pois ? pois : y, "%s poisson %g makes the stvk law non-positive "
                 "(poisson^2 e_v/e_u = %g >= 1); expected |poisson| < sqrt(e_u/e_v) = %g", w,
                 mat->nu_uv, q, sqrt(mat->e_u / mat->e_v));
}

static int load_membrane(const ctx *c, const ynode *y, const char *what, sw_material *mat) {
  const ynode *v[N_MEMB_KEYS];
  char w[128], names[96];
  snprintf(w, sizeof w, "%s membrane", what);
  if (sy_map(c, y, w, memb_keys, N_MEMB_KEYS, v)) return -1;
  int model = 0; /* bw98 when no model is given (the first scenes had none) */
  const char *list[N_MEMB];
  for (int i = 0; i < N_MEMB; i++) list[i] = memb_models[i].name;
  snprintf(names, sizeof names, "%s model", w);
  if (v[0] && sy_choice(c, v[0], names, list, N_MEMB, &model)) return -1;
  const memb_model *mm = &memb_models[model];
  mat->membrane = mm->type;
  if (membrane_params(c, y, mm, v, w, mat)) return -1;
  return mm->type == SW_MEMBRANE_STVK ? check_stvk(c, y, v[8], w, mat) : 0;
}

static const char *const bend_keys[] = {"model", "stiffness", "rest", "stiffness_u",
                                        "stiffness_v", "stiffness_bias"};
enum { BK_MODEL, BK_K, BK_REST, BK_KU, BK_KV, BK_KBIAS, BK_N };
static const char *const bend_models[] = {"dihedral", "quadratic", "morley", "dde"};
enum { N_BEND_MODELS = 4 };
static const int bend_type[N_BEND_MODELS] = {SW_BENDING_DIHEDRAL, SW_BENDING_QUADRATIC,
                                             SW_BENDING_MORLEY, SW_BENDING_DDE};

/* `model: dde` (models/dde_bending.c): the rigidities of the measured fabric's data, which
 * mat carries only from a fabric preset or data file (its own, or for a panel the material's);
 * its strips' small-curvature rigidities condense the free edges.  0, or -1 at `at`. */
static int bend_dde(const ctx *c, const ynode *at, const char *w, int has_data,
                    sw_material *mat) {
  if (!has_data)
    return sy_fail(c, at, "%s model dde needs a measured fabric's data beside it; expected "
                   "fabric: {preset: NAME} or fabric: {data: FILE} in the same material or "
                   "panel (or in the material, for a panel), or another bending model", w);
  char why[SW_ERRSZ];
  sw_dde_bend law;
  if (sw_dde_bend_setup(&mat->dde, &law, why, sizeof why))
    return sy_fail(c, at, "%s model dde: %s; expected another bending model for this fabric", w,
                   why);
  double kb[3];
  sc_dde_strips(&mat->dde, kb);
  mat->bending = SW_BENDING_DDE;
  mat->bend_rest = SW_BEND_REST_FLAT;
  mat->k_bend_u = kb[0], mat->k_bend_v = kb[1], mat->k_bend_bias = kb[2];
  mat->k_bend = fmax(fmax(kb[0], kb[1]), kb[2]);
  return 0;
}
static const char *const bend_rests[] = {"initial", "flat"}; /* SW_BEND_REST_* order */

/* A positive twisting rigidity needs 4/D_45 > 1/D_u + 1/D_v (models/bending.c).  0 or -1. */
static int check_bias(const ctx *c, const ynode *at, const char *w, const sw_material *mat) {
  double top = 4.0 / (1.0 / mat->k_bend_u + 1.0 / mat->k_bend_v); /* N m */
  if (mat->k_bend_bias < top) return 0;
  return sy_fail(c, at, "%s stiffness_bias %g N m is not below 4/(1/stiffness_u + "
                 "1/stiffness_v) = %g N m, the stiffest bias strip an orthotropic plate with "
                 "these warp and weft rigidities has; expected a smaller stiffness_bias", w,
                 mat->k_bend_bias, top);
}

/* Either stiffness (isotropic) or stiffness_u and stiffness_v (and stiffness_bias). */
static int bend_rigidity(const ctx *c, const ynode *y, const ynode *const *v, const char *w,
                         sw_material *mat) {
  char lab[160];
  mat->k_bend_u = mat->k_bend_v = mat->k_bend_bias = 0.0;
  if (v[BK_K]) {
    const ynode *extra = v[BK_KU] ? v[BK_KU] : v[BK_KV] ? v[BK_KV] : v[BK_KBIAS];
    if (extra)
      return sy_fail(c, extra, "%s gives stiffness (isotropic) and a rigidity per direction; "
                     "expected stiffness, or stiffness_u and stiffness_v", w);
    snprintf(lab, sizeof lab, "%s stiffness", w);
    return sy_num(c, v[BK_K], lab, 0, 0, "N m", &mat->k_bend);
  }
  if (!v[BK_KU] || !v[BK_KV])
    return sy_fail(c, v[BK_KU] ? v[BK_KU] : v[BK_KV] ? v[BK_KV] : v[BK_KBIAS] ? v[BK_KBIAS] : y,
                   "%s has no stiffness, or only one of stiffness_u and stiffness_v; expected "
                   "stiffness: a number >= 0 (N m), or both stiffness_u and stiffness_v (N m, "
                   "> 0)", w);
  snprintf(lab, sizeof lab, "%s stiffness_u", w);
  if (sy_num(c, v[BK_KU], lab, 0, 1, "N m", &mat->k_bend_u)) return -1;
  snprintf(lab, sizeof lab, "%s stiffness_v", w);
  if (sy_num(c, v[BK_KV], lab, 0, 1, "N m", &mat->k_bend_v)) return -1;
  mat->k_bend_bias = sc_bend_bias_default(mat->k_bend_u, mat->k_bend_v);
  snprintf(lab, sizeof lab, "%s stiffness_bias", w);
  if (v[BK_KBIAS] && (sy_num(c, v[BK_KBIAS], lab, 0, 1, "N m", &mat->k_bend_bias) ||
                      check_bias(c, v[BK_KBIAS], w, mat)))
    return -1;
  mat->k_bend = fmax(fmax(mat->k_bend_u, mat->k_bend_v), mat->k_bend_bias);
  return 0;
}

static int load_bending(const ctx *c, const ynode *y, const char *what, sw_material *mat) {
  const ynode *v[BK_N];
  char w[128], lab[160];
  int model = 0;
  snprintf(w, sizeof w, "%s bending", what);
  if (sy_map(c, y, w, bend_keys, BK_N, v) ||
      sy_need(c, y, v[BK_MODEL], w, "model", "model: dihedral, quadratic, morley or dde"))
    return -1;
  snprintf(lab, sizeof lab, "%s model", w);
  if (sy_choice(c, v[BK_MODEL], lab, bend_models, N_BEND_MODELS, &model)) return -1;
  if (bend_type[model] == SW_BENDING_DDE) {
    for (int k = 0; k < BK_N; k++)
      if (v[k] && k != BK_MODEL)
        return sy_fail(c, v[k], "%s gives %s for model dde, whose rigidities are the measured "
                       "fabric's; expected only model: dde", w, bend_keys[k]);
    return bend_dde(c, v[BK_MODEL], w, mat->membrane == SW_MEMBRANE_DDE || mat->dde.density > 0.0,
                    mat);
  }
  mat->bending = bend_type[model];
  if (model == 0 && c->m->dim == 2)
    return sy_fail(c, v[BK_MODEL], "%s model dihedral needs a 3D scene (a planar mesh cannot "
                   "fold); expected dimension: 3, or model quadratic", w);
  if (bend_rigidity(c, y, v, w, mat)) return -1;
  mat->bend_rest = model == 0 ? SW_BEND_REST_INITIAL : SW_BEND_REST_FLAT;
  if (!v[BK_REST]) return 0;
  if (model != 0)
    return sy_fail(c, v[BK_REST], "%s rest is given for model %s, whose rest state is "
                   "always the flat (u,v) layout; expected rest only with model dihedral", w,
                   bend_models[model]);
  snprintf(lab, sizeof lab, "%s rest", w);
  return sy_choice(c, v[BK_REST], lab, bend_rests, 2, &mat->bend_rest);
}

/* The (u,v) rest layout is needed for masses, membranes and bending. */
static int check_uv(const ctx *c, const ynode *at, const sw_mesh *me, const char *obj,
                    const char *what) {
  int ok = me->nuv > 0 && me->fuv;
  for (long k = 0; ok && k < 3L * me->nf; k++) ok = me->fuv[k] >= 0 && me->fuv[k] < me->nuv;
  if (ok || me->nf == 0) return 0;
  return sy_fail(c, at, "%s needs the rest (u,v) layout, but mesh obj '%s' has no texture "
                 "coordinates (vt) on every face; expected an OBJ whose faces all have vt", what,
                 obj);
}

/* A panel's map has the material's keys, a uv_scale and its landmarks (corners, notches). */
static const char *const mat_keys[] = {"density", "membrane", "bending", "bias", "fabric",
                                       "uv_scale", "corners", "notches"};
enum { MK_DENSITY, MK_MEMB, MK_BEND, MK_BIAS, MK_FABRIC, MK_UVSCALE, MK_CORNERS, MK_NOTCHES,
       MK_N };

/* Beside a fabric with a bending rigidity, `bending: {model: M}` picks the model that rigidity
 * goes to (quadratic when not given); any other bending key is an error. */
static int fabric_bending_model(const ctx *c, const ynode *y, const char *w, int set,
                                sw_material *mat) {
  const ynode *v[BK_N];
  char lab[160];
  int model = 0;
  snprintf(lab, sizeof lab, "%s bending", w);
  if (sy_map(c, y, lab, bend_keys, BK_N, v)) return -1;
  for (int k = 0; k < BK_N; k++)
    if (v[k] && k != BK_MODEL)
      return sy_fail(c, v[k], "%s gives bending %s and a fabric with a bending rigidity; "
                     "expected only bending: {model: dihedral, quadratic, morley or dde} beside "
                     "the fabric (the rigidity is the fabric's)", w, bend_keys[k]);
  if (sy_need(c, y, v[BK_MODEL], lab, "model", "model: dihedral, quadratic, morley or dde"))
    return -1;
  snprintf(lab, sizeof lab, "%s bending model", w);
  if (sy_choice(c, v[BK_MODEL], lab, bend_models, N_BEND_MODELS, &model)) return -1;
  snprintf(lab, sizeof lab, "%s bending", w);
  if (bend_type[model] == SW_BENDING_DDE)
    return bend_dde(c, v[BK_MODEL], lab, set & SC_FABRIC_DDE, mat);
  if (model == 0 && c->m->dim == 2)
    return sy_fail(c, v[BK_MODEL], "%s bending model dihedral needs a 3D scene (a planar mesh "
                   "cannot fold); expected dimension: 3, or model quadratic", w);
  mat->bending = bend_type[model];
  return 0;
}

/* A fabric (scene_fabric.c) instead of the density, and instead of the membrane and bending
 * it gives (with the bending model `bending: {model: M}` may choose). */
static int load_fabric(const ctx *c, const ynode *const *v, const char *w, sw_material *mat) {
  int set;
  if (v[MK_DENSITY])
    return sy_fail(c, v[MK_DENSITY], "%s gives density and fabric (whose mass is the density); "
                   "expected one of them", w);
  if (sc_load_fabric(c, v[MK_FABRIC], w, mat, &set)) return -1;
  if ((set & SC_FABRIC_MEMBRANE) && v[MK_MEMB])
    return sy_fail(c, v[MK_MEMB], "%s gives membrane and a fabric with kes_g and a tensile "
                   "stiffness; expected one of them", w);
  if ((set & SC_FABRIC_BENDING) && v[MK_BEND])
    return fabric_bending_model(c, v[MK_BEND], w, set, mat) ? -1 : 1;
  return 0;
}

/* The keys of a material or panel map into mat.  A panel (panel = 1) may give any subset and
 * a uv_scale; the material must give the density. */
static int load_keys(const ctx *c, const ynode *y, const char *w, int panel, const sw_mesh *me,
                     const char *obj, sw_material *mat, double *uv_scale) {
  const ynode *v[MK_N] = {0};
  char lab[160];
  if (sy_map(c, y, w, mat_keys, panel ? MK_N : MK_UVSCALE, v)) return -1; /* see load_panel */
  if (!panel && !v[MK_FABRIC] &&
      sy_need(c, y, v[MK_DENSITY], w, "density", "density: a number > 0 in kg/m^2 (or "
              "fabric: {mass: g/m^2, ...})"))
    return -1;
  int fab = v[MK_FABRIC] ? load_fabric(c, v, w, mat) : 0; /* 1: bending model taken */
  if (fab < 0) return -1;
  snprintf(lab, sizeof lab, "%s density", w);
  if (v[MK_DENSITY] && sy_num(c, v[MK_DENSITY], lab, 0, 1, "kg/m^2", &mat->density)) return -1;
  if (v[MK_MEMB] && load_membrane(c, v[MK_MEMB], w, mat)) return -1;
  if (v[MK_BEND] && fab != 1 && load_bending(c, v[MK_BEND], w, mat)) return -1;
  snprintf(lab, sizeof lab, "%s bias", w);
  const double rad = 0.017453292519943295; /* pi / 180 */
  double deg = mat->bias / rad;
  if (v[MK_BIAS] && sy_num(c, v[MK_BIAS], lab, -HUGE_VAL, 0, "degrees", &deg)) return -1;
  mat->bias = deg * rad;
  snprintf(lab, sizeof lab, "%s uv_scale", w);
  if (v[MK_UVSCALE] && sy_num(c, v[MK_UVSCALE], lab, 0, 1, "m per OBJ (u,v) unit", uv_scale))
    return -1;
  static const int need_uv[] = {MK_MEMB, MK_BEND, MK_DENSITY, MK_FABRIC, MK_UVSCALE};
  for (int q = 0; q < 5; q++) {
    int k = need_uv[q];
    snprintf(lab, sizeof lab, "%s %s", w, mat_keys[k]);
    if (v[k] && check_uv(c, v[k], me, obj, lab)) return -1;
  }
  return 0;
}

int sc_load_material(const ctx *c, const ynode *y, const sw_mesh *me, const char *obj) {
  double unused = 1.0;
  return load_keys(c, y, "material", 0, me, obj, &c->m->mat[0], &unused);
}


/* The panels being loaded: the mesh's groups by name (hashed), the panel of each group (0:
 * none) and each panel's uv_scale. */
typedef struct panels_in {
  sw_names groups;
  int *panel;    /* (ngroup) */
  double *scale; /* (np + 1) */
} panels_in;

/* A panel's landmarks, `corners` or `notches` (which `seams` may name instead of vertex
 * indices, docs/garments.md): a sequence of vertex indices, each a vertex of the panel's
 * faces.  Whether each is on the boundary is checked where a seam uses it. */
static int load_landmarks(const ctx *c, const ynode *y, const char *w, const char *key,
                          const unsigned char *in_panel) {
  char lab[SW_NAMESZ + 48];
  snprintf(lab, sizeof lab, "%s %s", w, key);
  if (sy_seq(c, y, lab, "a sequence of vertex indices (0-based) of the panel")) return -1;
  for (int i = 0; i < y->n; i++) {
    char li[SW_NAMESZ + 64];
    int v = 0;
    snprintf(li, sizeof li, "%s[%d]", lab, i);
    if (sy_int(c, y->kid[i], li, 0, c->m->nv - 1, &v)) return -1;
    if (!in_panel[v])
      return sy_fail(c, y->kid[i], "%s is vertex %d, which no face of the panel holds; "
                     "expected a vertex of the panel", li, v);
  }
  return 0;
}

/* One panel: mat[k] = mat[0] + the panel's keys; its group's faces will get material k
 * (pi->panel) and, with a uv_scale, their (u,v) rescaled from the mesh's uv_scale to the
 * panel's (pi->scale[k]). */
static int load_panel(const ctx *c, const ynode *key, const ynode *val, const sw_mesh *me,
                      const char *obj, double mesh_scale, int k, panels_in *pi) {
  sw_model *m = c->m;
  char w[SW_NAMESZ + 16], d[96], groups[512];
  const char *name;
  if (sy_str(c, key, "panels key", SW_NAMESZ, &name)) return -1;
  int g = sw_names_find(&pi->groups, name);
  if (g < 0) {
    const char *list[16];
    int n = me->ngroup < 16 ? me->ngroup : 16;
    for (int i = 0; i < n; i++) list[i] = me->group[i];
    return sy_fail(c, key, "panels names '%s', which is no group of mesh %s; expected one of: "
                   "%s", sy_clip(key, d, sizeof d), obj, sy_join(list, n, groups, sizeof groups));
  }
  if (pi->panel[g])
    return sy_fail(c, key, "panels names '%s' twice; expected each panel once", name);
  pi->panel[g] = k;
  m->mat[k] = m->mat[0];
  snprintf(m->mat[k].group, sizeof m->mat[k].group, "%s", name);
  snprintf(w, sizeof w, "panel %s", name);
  double scale = mesh_scale;
  if (load_keys(c, val, w, 1, me, obj, &m->mat[k], &scale)) return -1;
  pi->scale[k] = scale;
  const ynode *v[MK_N];
  sy_map(c, val, w, mat_keys, MK_N, v); /* load_keys has checked the map */
  if (!v[MK_CORNERS] && !v[MK_NOTCHES]) return 0;
  unsigned char *in_panel = sw_calloc((size_t)m->nv, 1);
  if (!in_panel) return sy_oom(c, val);
  for (int f = 0; f < m->nf; f++)
    for (int i = 0; me->fgroup[f] == g && i < 3; i++) in_panel[m->face[3 * f + i]] = 1;
  int rc = 0;
  for (int q = MK_CORNERS; !rc && q <= MK_NOTCHES; q++)
    if (v[q]) rc = load_landmarks(c, v[q], w, mat_keys[q], in_panel);
  sw_free(in_panel);
  return rc;
}

/* Each face of a panel's group: its material and (u,v) scale, in one pass over the faces. */
static void apply_panels(sw_model *m, const sw_mesh *me, const panels_in *pi, double mesh_scale) {
  for (int f = 0; me->fgroup && f < m->nf; f++) {
    int k = pi->panel[me->fgroup[f]];
    if (!k) continue;
    m->face_mat[f] = k;
    for (int q = 0; q < 6; q++) m->uv[6 * f + q] *= pi->scale[k] / mesh_scale;
  }
}

int sc_load_panels(const ctx *c, const ynode *y, const sw_mesh *me, const char *obj,
                   double mesh_scale) {
  sw_model *m = c->m;
  if (y->kind != Y_MAP)
    return sy_type_error(c, y, "panels", "a mapping from OBJ group names to materials");
  int np = y->n / 2;
  sw_material *mat = sw_realloc(m->mat, (size_t)np + 1, sizeof *mat);
  if (!mat) return sy_oom(c, y);
  m->mat = mat;
  if (!m->face_mat && !(m->face_mat = sw_calloc((size_t)m->nf + 1, sizeof *m->face_mat)))
    return sy_oom(c, y);
  panels_in pi = {.panel = sw_calloc((size_t)me->ngroup, sizeof(int)),
                  .scale = sw_calloc((size_t)np + 1, sizeof(double))};
  int rc = !pi.panel || !pi.scale ? sy_oom(c, y) : 0;
  for (int g = 0; !rc && g < me->ngroup; g++)
    if (sw_names_add(&pi.groups, me->group[g], g) == -2) rc = sy_oom(c, y);
  for (int p = 0; !rc && p < np; p++) {
    rc = load_panel(c, y->kid[2 * p], y->kid[2 * p + 1], me, obj, mesh_scale, p + 1, &pi);
    if (!rc) m->nmat = p + 2;
  }
  if (!rc) apply_panels(m, me, &pi, mesh_scale);
  sw_names_free(&pi.groups);
  sw_free(pi.panel);
  sw_free(pi.scale);
  return rc;
}

/* The stiffnesses of a material (N/m, bending N m); an explicit tension XY stiffness too. */
static void scale_material(sw_material *mt, double s) {
  double *k[] = {&mt->k_u, &mt->k_v, &mt->k_shear, &mt->e_u, &mt->e_v, &mt->g_uv, &mt->k_corot,
                 &mt->ks_stretch, &mt->ks_shear, &mt->ks_bend, &mt->k_bend,
                 &mt->k_bend_u, &mt->k_bend_v, &mt->k_bend_bias};
  for (size_t i = 0; i < sizeof k / sizeof k[0]; i++) *k[i] *= s;
  for (int r = 0; r < 6; r++) /* a measured fabric's data: its stretching and bending, N/m, N m */
    for (int c = 0; c < 4; c++) mt->dde.stretch[r][c] *= s;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 5; c++) mt->dde.bend[r][c] *= s;
  if (mt->tx_k_u >= 0) mt->tx_k_u *= s; /* < 0: derived from the (scaled) membrane */
  if (mt->tx_k_v >= 0) mt->tx_k_v *= s;
}

void sc_scale_stiffness(sw_model *m, double s) {
  for (int k = 0; k < m->nmat; k++) scale_material(&m->mat[k], s);
  for (int t = 0; t < m->ntendon; t++) m->tendon[t].stiffness *= s; /* N/m */
  if (m->opt.tx_k_u >= 0) m->opt.tx_k_u *= s; /* tension_xy k_u, k_v when the scene sets them */
  if (m->opt.tx_k_v >= 0) m->opt.tx_k_v *= s;
  m->stiffness_scale *= s;
}

static const char *const damp_keys[] = {"mass", "stiffness"};

int sc_load_damping(const ctx *c, const ynode *y) {
  const ynode *v[2];
  if (sy_map(c, y, "damping", damp_keys, 2, v)) return -1;
  if (v[0] && sy_num(c, v[0], "damping mass", 0, 0, "1/s", &c->m->damp_mass)) return -1;
  if (v[1] && sy_num(c, v[1], "damping stiffness", 0, 0, "s", &c->m->damp_stiffness)) return -1;
  return 0;
}
