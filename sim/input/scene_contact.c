/* scene_contact.c — the scene keys `obstacles` and `contact` (docs/contact.md):
 *   obstacles:
 *     - {shape: plane, point: [x, y, z], normal: [nx, ny, nz]}
 *     - {shape: sphere, center: [...], radius: r}
 *     - {shape: capsule, ends: [[...], [...]], radius: r}
 *     - {shape: box, center: [...], size: [lx, ly, lz]}     (axis-aligned)
 *     - {mesh: body.obj, scale: s, translate: [x, y, z]}    (3D: a rigid triangle mesh)
 *   each with offset: m (>= 0) and motion: {keyframes: [[t, dx, dy(, dz)], ...],
 *   rotation: {axis: [x, y, z], center: [...], keyframes: [[t, degrees], ...]},
 *   interpolation: smooth | linear} (a rotation about the axis through center, then a
 *   translation, m, from the stated place);
 *   contact: {distance: m, stiffness: 1/s^2, friction: mu, stick_velocity: m/s, self: bool,
 *             thickness: m, self_stiffness: 1/(s^2 m^2), self_friction: mu}. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contact.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#include "scene_material.h"
#include "util.h"

static const char *const obst_keys[] = {"shape", "point",  "normal", "center", "radius",
                                        "ends",  "size",   "offset", "motion", "mesh",
                                        "scale", "translate"};
enum { O_SHAPE, O_POINT, O_NORMAL, O_CENTER, O_RADIUS, O_ENDS, O_SIZE, O_OFFSET, O_MOTION,
       O_MESH, O_SCALE, O_TRANSLATE, O_N };

/* The keys each shape needs (and the only shape keys it takes), SW_SHAPE_* order. */
static const int shape_keys[SW_SHAPE_N][3] = {
    {O_POINT, O_NORMAL, -1}, {O_CENTER, O_RADIUS, -1}, {O_ENDS, O_RADIUS, -1},
    {O_CENTER, O_SIZE, -1}};
static const char *const shape_hint[SW_SHAPE_N] = {
    "point: [...] and normal: [...]", "center: [...] and radius: m", "ends: [[...], [...]] and "
    "radius: m", "center: [...] and size: [...] (full edge lengths, m)"};

static int takes(int shape, int key) {
  for (int k = 0; k < 3 && shape_keys[shape][k] >= 0; k++)
    if (shape_keys[shape][k] == key) return 1;
  return 0;
}

/* Every key of the shape given, and no key of another shape. */
static int check_shape_keys(const ctx *c, const ynode *y, const char *w, int shape,
                            const ynode **v) {
  for (int k = O_POINT; k <= O_SIZE; k++) {
    if (takes(shape, k) && !v[k])
      return sy_fail(c, y, "%s (a %s) has no '%s'; expected %s", w, sw_shape_names()[shape],
                     obst_keys[k], shape_hint[shape]);
    if (!takes(shape, k) && v[k])
      return sy_fail(c, v[k], "%s (a %s) does not take '%s'; expected %s", w,
                     sw_shape_names()[shape], obst_keys[k], shape_hint[shape]);
  }
  return 0;
}

/* A point of dim components (the rest of p stays 0). */
static int point(const ctx *c, const ynode *y, const char *w, const char *key, double *p) {
  char lab[128];
  snprintf(lab, sizeof lab, "%s %s", w, key);
  return sy_vec(c, y, lab, c->m->dim, -HUGE_VAL, 0, "m", p);
}

static int load_plane(const ctx *c, const ynode **v, const char *w, sw_obstacle *o) {
  char lab[128];
  if (point(c, v[O_POINT], w, "point", o->a)) return -1;
  snprintf(lab, sizeof lab, "%s normal", w);
  if (sy_vec(c, v[O_NORMAL], lab, c->m->dim, -HUGE_VAL, 0, "", o->b)) return -1;
  double len = 0.0;
  for (int a = 0; a < c->m->dim; a++) len += o->b[a] * o->b[a];
  len = sqrt(len);
  if (!(len > 0.0) || !isfinite(len))
    return sy_fail(c, v[O_NORMAL], "%s is zero; expected a nonzero vector (it is normalised)",
                   lab);
  for (int a = 0; a < c->m->dim; a++) o->b[a] /= len;
  return 0;
}

static int load_radius(const ctx *c, const ynode *y, const char *w, sw_obstacle *o) {
  char lab[128];
  snprintf(lab, sizeof lab, "%s radius", w);
  return sy_num(c, y, lab, 0, 1, "m", &o->radius);
}

static int load_capsule(const ctx *c, const ynode **v, const char *w, sw_obstacle *o) {
  char lab[128];
  snprintf(lab, sizeof lab, "%s ends", w);
  if (sy_seq(c, v[O_ENDS], lab, "two points [[x, y, z], [x, y, z]]")) return -1;
  if (v[O_ENDS]->n != 2)
    return sy_fail(c, v[O_ENDS], "%s has %d points; expected 2", lab, v[O_ENDS]->n);
  if (point(c, v[O_ENDS]->kid[0], w, "ends[0]", o->a) ||
      point(c, v[O_ENDS]->kid[1], w, "ends[1]", o->b))
    return -1;
  return load_radius(c, v[O_RADIUS], w, o);
}

static int load_box(const ctx *c, const ynode **v, const char *w, sw_obstacle *o) {
  char lab[128];
  if (point(c, v[O_CENTER], w, "center", o->a)) return -1;
  snprintf(lab, sizeof lab, "%s size", w);
  if (sy_vec(c, v[O_SIZE], lab, c->m->dim, 0, 1, "m", o->b)) return -1;
  for (int a = 0; a < c->m->dim; a++) o->b[a] *= 0.5; /* half sizes, m */
  return 0;
}

static const char *const motion_keys[] = {"keyframes", "interpolation", "rotation"};
static const char *const interps[] = {"linear", "smooth"}; /* SW_INTERP_* order */
static const char *const rot_keys[] = {"axis", "center", "keyframes"};

/* keyframes: [[t, v_1, ..., v_ncomp], ...] with increasing times into *kt and kv (component a
 * of keyframe j at kv[a n + j]), each value times scale; what names the values. */
static int load_keys(const ctx *c, const ynode *k, const char *kl, int ncomp, double scale,
                     const char *what, const char *units, double **kt, double **kv, int *n) {
  char lab[192];
  snprintf(lab, sizeof lab, "a sequence of %s", what);
  if (sy_seq(c, k, kl, lab)) return -1;
  if (k->n < 1 || k->n > SW_OBSTACLE_MAXKEY)
    return sy_fail(c, k, "%s has %d keyframes; expected 1 to %d", kl, k->n, SW_OBSTACLE_MAXKEY);
  *kt = sw_calloc((size_t)k->n, sizeof(double));
  *kv = sw_calloc((size_t)k->n * (size_t)ncomp, sizeof(double));
  if (!*kt || !*kv) return sy_oom(c, k);
  for (int j = 0; j < k->n; j++) {
    double row[4];
    snprintf(lab, sizeof lab, "%s[%d]", kl, j);
    if (sy_vec(c, k->kid[j], lab, ncomp + 1, -HUGE_VAL, 0, units, row)) return -1;
    if (j > 0 && !(row[0] > (*kt)[j - 1]))
      return sy_fail(c, k->kid[j], "%s has time %g s after %g s; expected increasing times",
                     lab, row[0], (*kt)[j - 1]);
    (*kt)[j] = row[0]; /* s */
    for (int a = 0; a < ncomp; a++) (*kv)[a * k->n + j] = scale * row[1 + a];
  }
  *n = k->n;
  return 0;
}

/* rotation: {axis: [x, y, z] (3D only), center: [...], keyframes: [[t, angle], ...]} (degrees,
 * right-handed about the axis; in 2D about z, counter-clockwise). */
static int load_rotation(const ctx *c, const ynode *y, const char *w, sw_obstacle *o) {
  char lab[128], kl[192];
  const ynode *v[3];
  const int dim = c->m->dim;
  snprintf(lab, sizeof lab, "%s motion rotation", w);
  if (sy_map(c, y, lab, rot_keys, 3, v) ||
      sy_need(c, y, v[2], lab, "keyframes", "keyframes: [[t, angle], ...] in s and degrees") ||
      sy_need(c, y, v[1], lab, "center", "center: a point of the axis, m"))
    return -1;
  o->axis[0] = o->axis[1] = 0.0, o->axis[2] = 1.0;
  if (dim == 2 && v[0])
    return sy_fail(c, v[0], "%s axis is given in a 2D scene; expected no axis (a 2D body turns "
                   "about z)", lab);
  if (dim == 3) {
    if (sy_need(c, y, v[0], lab, "axis", "axis: [x, y, z] (normalised)")) return -1;
    snprintf(kl, sizeof kl, "%s axis", lab);
    if (sy_vec(c, v[0], kl, 3, -HUGE_VAL, 0, "", o->axis)) return -1;
    double len = sqrt(o->axis[0] * o->axis[0] + o->axis[1] * o->axis[1] + o->axis[2] * o->axis[2]);
    if (!(len > 0.0) || !isfinite(len))
      return sy_fail(c, v[0], "%s is zero; expected a nonzero vector (it is normalised)", kl);
    for (int a = 0; a < 3; a++) o->axis[a] /= len;
  }
  snprintf(kl, sizeof kl, "%s center", lab);
  if (sy_vec(c, v[1], kl, dim, -HUGE_VAL, 0, "m", o->center)) return -1;
  snprintf(kl, sizeof kl, "%s keyframes", lab);
  return load_keys(c, v[2], kl, 1, M_PI / 180.0, "[t, angle] (s, degrees)", "s, degrees",
                   &o->rot_t, &o->rot_a, &o->nrot);
}

/* motion: {keyframes: [[t, dx, dy(, dz)], ...], rotation: {...}, interpolation: smooth |
 * linear}: a translation, a rotation or both. */
static int load_motion(const ctx *c, const ynode *y, const char *w, sw_obstacle *o) {
  char lab[160], kl[128];
  const ynode *v[3];
  const int dim = c->m->dim;
  snprintf(lab, sizeof lab, "%s motion", w);
  if (sy_map(c, y, lab, motion_keys, 3, v)) return -1;
  if (!v[0] && !v[2])
    return sy_fail(c, y, "%s has neither keyframes nor rotation; expected keyframes: [[t, dx, "
                   "dy(, dz)], ...] in s and m, rotation: {...}, or both", lab);
  o->interp = SW_INTERP_SMOOTH;
  snprintf(kl, sizeof kl, "%s motion interpolation", w);
  if (v[1] && sy_choice(c, v[1], kl, interps, 2, &o->interp)) return -1;
  snprintf(kl, sizeof kl, "%s motion keyframes", w);
  if (v[0] && load_keys(c, v[0], kl, dim, 1.0, dim == 3 ? "[t, dx, dy, dz]" : "[t, dx, dy]",
                        "s, m", &o->key_t, &o->key_d, &o->nkey))
    return -1;
  if (o->key_d && dim == 2) { /* stored 3 x nkey: the z row stays 0 */
    double *kd = sw_calloc((size_t)o->nkey * 3, sizeof(double));
    if (!kd) return sy_oom(c, v[0]);
    memcpy(kd, o->key_d, (size_t)o->nkey * 2 * sizeof(double));
    sw_free(o->key_d);
    o->key_d = kd;
  }
  return v[2] ? load_rotation(c, v[2], w, o) : 0;
}

/* The obstacle's offset and motion (every obstacle takes them). */
static int load_offset_motion(const ctx *c, const ynode **v, const char *w, sw_obstacle *o) {
  char lab[96];
  snprintf(lab, sizeof lab, "%s offset", w);
  if (v[O_OFFSET] && sy_num(c, v[O_OFFSET], lab, 0, 0, "m", &o->offset)) return -1;
  return v[O_MOTION] ? load_motion(c, v[O_MOTION], w, o) : 0;
}

/* The OBJ's triangles, scaled then translated, into o (a mesh obstacle): its arrays move from
 * me to o, so a large body is never held twice while loading. */
static int mesh_from_obj(const ctx *c, const ynode **v, const char *w, sw_mesh *me,
                         sw_obstacle *o) {
  char lab[96];
  double scale = 1.0, shift[3] = {0.0, 0.0, 0.0};
  snprintf(lab, sizeof lab, "%s scale", w);
  if (v[O_SCALE] && sy_num(c, v[O_SCALE], lab, 0, 1, "", &scale)) return -1;
  snprintf(lab, sizeof lab, "%s translate", w);
  if (v[O_TRANSLATE] && sy_vec(c, v[O_TRANSLATE], lab, 3, -HUGE_VAL, 0, "m", shift)) return -1;
  if (me->nf < 1)
    return sy_fail(c, v[O_MESH], "%s mesh has no faces; expected a triangle mesh ('f' lines)", w);
  o->mesh_x = me->x, o->mesh_face = me->f;
  me->x = NULL, me->f = NULL;
  for (int i = 0; i < 3 * me->nv; i++) o->mesh_x[i] = scale * o->mesh_x[i] + shift[i % 3]; /* m */
  o->mesh_nv = me->nv;
  o->mesh_nf = me->nf;
  return 0;
}

/* obstacles[k] with a mesh: {mesh: file.obj, scale, translate, offset, motion}. */
static int load_mesh_obstacle(const ctx *c, const ynode **v, const char *w, sw_obstacle *o) {
  char lab[96], path[SW_PATHSZ];
  for (int k = O_SHAPE; k <= O_SIZE; k++)
    if (v[k])
      return sy_fail(c, v[k], "%s (a mesh) does not take '%s'; expected mesh: file.obj with "
                     "scale, translate, offset and motion", w, obst_keys[k]);
  if (c->m->dim != 3)
    return sy_fail(c, v[O_MESH], "%s mesh is given in a 2D scene; expected mesh obstacles only "
                   "in a 3D scene", w);
  snprintf(lab, sizeof lab, "%s mesh", w);
  sw_mesh me = {0};
  int rc = sc_read_obj(c, v[O_MESH], lab, &me, path) || mesh_from_obj(c, v, w, &me, o);
  sw_mesh_free(&me);
  return rc ? -1 : load_offset_motion(c, v, w, o);
}

static int load_obstacle(const ctx *c, const ynode *y, int k) {
  char w[64], lab[96];
  const ynode *v[O_N];
  sw_model *m = c->m;
  snprintf(w, sizeof w, "obstacles[%d]", k);
  if (sy_map(c, y, w, obst_keys, O_N, v)) return -1;
  if (v[O_MESH]) {
    sw_obstacle *o = &m->mesh_obstacle[m->nmesh_obstacle++];
    o->item = k;
    return load_mesh_obstacle(c, v, w, o);
  }
  sw_obstacle *o = &m->obstacle[m->nobstacle++];
  o->item = k;
  if (sy_need(c, y, v[O_SHAPE], w, "shape", "shape: plane, sphere, capsule or box, or mesh: "
              "file.obj"))
    return -1;
  for (int j = O_SCALE; j <= O_TRANSLATE; j++)
    if (v[j])
      return sy_fail(c, v[j], "%s (a shape) does not take '%s'; expected it only with mesh: "
                     "file.obj", w, obst_keys[j]);
  snprintf(lab, sizeof lab, "%s shape", w);
  if (sy_choice(c, v[O_SHAPE], lab, sw_shape_names(), SW_SHAPE_N, &o->shape) ||
      check_shape_keys(c, y, w, o->shape, v))
    return -1;
  static int (*const loaders[SW_SHAPE_N])(const ctx *, const ynode **, const char *,
                                          sw_obstacle *) = {load_plane, NULL, load_capsule,
                                                            load_box};
  int rc = o->shape == SW_SHAPE_SPHERE
               ? point(c, v[O_CENTER], w, "center", o->a) || load_radius(c, v[O_RADIUS], w, o)
               : loaders[o->shape](c, v, w, o);
  return rc ? -1 : load_offset_motion(c, v, w, o);
}

int sc_load_obstacles(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  if (sy_seq(c, y, "obstacles", "a sequence of {shape: plane | sphere | capsule | box, ...} "
             "or {mesh: file.obj, ...}"))
    return -1;
  if (y->n < 1) return sy_fail(c, y, "obstacles is empty; expected at least one obstacle");
  if (y->n > SW_MAX_OBSTACLES)
    return sy_fail(c, y, "obstacles has %d items; expected at most %d", y->n, SW_MAX_OBSTACLES);
  m->obstacle = sw_calloc((size_t)y->n, sizeof *m->obstacle);
  m->mesh_obstacle = sw_calloc((size_t)y->n, sizeof *m->mesh_obstacle);
  if (!m->obstacle || !m->mesh_obstacle) return sy_oom(c, y);
  for (int k = 0; k < y->n; k++) /* shapes into m->obstacle, meshes into m->mesh_obstacle */
    if (load_obstacle(c, y->kid[k], k)) return -1;
  return 0;
}

static const char *const contact_keys[] = {"distance", "stiffness", "friction",
                                           "stick_velocity", "self", "thickness",
                                           "self_stiffness", "self_friction"};
enum { C_DIST, C_STIFF, C_FRIC, C_STICK, C_SELF, C_THICK, C_SSTIFF, C_SFRIC, C_N };

int sc_load_contact(const ctx *c, const ynode *y, int has_obstacles) {
  sw_contact *ct = &c->m->contact;
  static const char *const bools[] = {"false", "true"};
  ct->dhat = SW_CONTACT_DHAT;
  ct->eps_v = SW_CONTACT_EPS_V;
  if (!y) return 0;
  const ynode *v[C_N];
  if (sy_map(c, y, "contact", contact_keys, C_N, v)) return -1;
  if (v[C_SELF] && sy_choice(c, v[C_SELF], "contact self", bools, 2, &ct->self)) return -1;
  if (!has_obstacles && !ct->self)
    return sy_fail(c, y, "contact is given but the scene has no obstacles and no self-contact; "
                   "expected obstacles: [...] or self: true with it");
  if (ct->self && c->m->dim != 3)
    return sy_fail(c, v[C_SELF], "contact self is true in a 2D scene; expected it only in a "
                   "3D scene (a 2D cloth lies in its plane and cannot fold onto itself)");
  const ynode *s3[] = {v[C_THICK], v[C_SSTIFF], v[C_SFRIC]};
  static const char *const s3name[] = {"thickness", "self_stiffness", "self_friction"};
  for (int k = 0; k < 3; k++)
    if (s3[k] && !ct->self && !(k == 1 && c->m->nmesh_obstacle > 0)) /* kappa_mesh: both */
      return sy_fail(c, s3[k], "contact %s is given without self: true; expected it only with "
                     "self-contact%s", s3name[k], k == 1 ? " or a mesh obstacle" : "");
  if ((v[C_DIST] && sy_num(c, v[C_DIST], "contact distance", 0, 1, "m", &ct->dhat)) ||
      (v[C_STIFF] && sy_num(c, v[C_STIFF], "contact stiffness", 0, 1, "1/s^2", &ct->kappa)) ||
      (v[C_FRIC] && sy_num(c, v[C_FRIC], "contact friction", 0, 0, "", &ct->friction)) ||
      (v[C_STICK] && sy_num(c, v[C_STICK], "contact stick_velocity", 0, 1, "m/s", &ct->eps_v)) ||
      (v[C_THICK] && sy_num(c, v[C_THICK], "contact thickness", 0, 0, "m", &ct->thickness)) ||
      (v[C_SSTIFF] &&
       sy_num(c, v[C_SSTIFF], "contact self_stiffness", 0, 1, "1/(s^2 m^2)", &ct->kappa_mesh)))
    return -1;
  ct->self_friction = ct->friction;
  if (v[C_SFRIC] && sy_num(c, v[C_SFRIC], "contact self_friction", 0, 0, "", &ct->self_friction))
    return -1;
  return 0;
}
