/* scene.c — the scene loader: YAML (libfyaml) -> validated sw_model.
 *
 * Two stages.  First the YAML text is parsed with libfyaml's event parser into a small tree of
 * our own (ynode) that keeps the 1-based line and column of every node (the libfyaml of
 * Debian 12 has no public node positions); libfyaml's own diagnostics are collected, never
 * printed.  Then the tree is checked against the schema (docs/scenes.md) and the
 * model is filled.  Every error is "file:line:column: what was found; what was expected".
 * Units are SI: m, s, kg, N. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "scene.h"
#include "scene_material.h"
#include "scene_fabric.h"

#include "util.h"

#include <errno.h>
#include <libfyaml.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The scene file's stem: "scenes/hanging_cloth.yaml" -> "hanging_cloth". */
static void file_stem(const char *path, char *out, size_t sz) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  const char *dot = strrchr(base, '.');
  size_t n = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  if (n == 0) base = "scene", n = 5;
  if (n >= sz) n = sz - 1;
  memcpy(out, base, n);
  out[n] = '\0';
}

/* ================================================================ the mesh */

typedef struct mesh_in {
  sw_mesh mesh;
  const ynode *at;        /* the grid or obj value, for messages */
  int grid[2];            /* a grid's vertices nx, ny (0: not a grid) */
  char obj[SW_PATHSZ];    /* the OBJ file as opened */
} mesh_in;

static const char *const grid_keys[] = {"size", "vertices", "plane"};
static const char *const planes[] = {"xy", "xz", "yz"};

static int load_grid(const ctx *c, const ynode *y, mesh_in *mi) {
  const ynode *v[3];
  double size[2];
  int nvert[2], plane = 0;
  if (sy_map(c, y, "mesh grid", grid_keys, 3, v)) return -1;
  if (sy_need(c, y, v[0], "mesh grid", "size", "size: [lx, ly] in m") ||
      sy_need(c, y, v[1], "mesh grid", "vertices", "vertices: [nx, ny], each >= 2"))
    return -1;
  if (sy_vec(c, v[0], "mesh grid size", 2, 0, 1, "m", size)) return -1;
  if (sy_seq(c, v[1], "mesh grid vertices", "a sequence of 2 integers >= 2")) return -1;
  if (v[1]->n != 2)
    return sy_fail(c, v[1], "mesh grid vertices has %d components; expected 2", v[1]->n);
  if (sy_int(c, v[1]->kid[0], "mesh grid vertices[0]", 2, INT_MAX, nvert) ||
      sy_int(c, v[1]->kid[1], "mesh grid vertices[1]", 2, INT_MAX, nvert + 1))
    return -1;
  if ((double)nvert[0] * nvert[1] > (double)SW_SCENE_MAX_VERTICES)
    return sy_fail(c, v[1], "mesh grid vertices is %d x %d; expected at most %ld vertices in all",
                nvert[0], nvert[1], (long)SW_SCENE_MAX_VERTICES);
  if (c->ov && c->ov->grid[0] > 0) { /* sinew run --grid; checked by sw_scene_parse_ex */
    nvert[0] = c->ov->grid[0];
    nvert[1] = c->ov->grid[1];
  }
  if (v[2] && sy_choice(c, v[2], "mesh grid plane", planes, 3, &plane)) return -1;
  if (c->m->dim == 2 && plane != 0)
    return sy_fail(c, v[2], "mesh grid plane is %s in a 2D scene; expected xy (dimension: 2)",
                planes[plane]);
  char e[SW_ERRSZ];
  if (sw_mesh_grid(&mi->mesh, size, nvert[0], nvert[1], planes[plane], e, sizeof e))
    return sy_fail(c, y, "in mesh grid: %s", e);
  mi->grid[0] = nvert[0];
  mi->grid[1] = nvert[1];
  return 0;
}

static int load_obj(const ctx *c, const ynode *y, mesh_in *mi) {
  if (sc_read_obj(c, y, "mesh obj", &mi->mesh, mi->obj)) return -1;
  if (c->m->dim == 2)
    for (int i = 0; i < mi->mesh.nv; i++)
      if (mi->mesh.x[3 * i + 2] != 0.0)
        return sy_fail(c, y, "mesh obj '%s' vertex %d has z = %g m in a 2D scene; expected z = 0 "
                    "for every vertex (dimension: 2)", mi->obj, i + 1, mi->mesh.x[3 * i + 2]);
  return 0;
}

/* points: [[x, y(, z)], ...]: vertices without faces (a cable or a tendon net). */
static int load_points(const ctx *c, const ynode *y, mesh_in *mi) {
  char lab[64];
  const int d = c->m->dim;
  if (sy_seq(c, y, "mesh points", "a sequence of points [x, y(, z)] in m")) return -1;
  if (y->n == 0) return sy_fail(c, y, "mesh points is empty; expected at least one point");
  if (y->n > SW_SCENE_MAX_VERTICES)
    return sy_fail(c, y, "mesh points has %d points; expected at most %ld", y->n,
                   (long)SW_SCENE_MAX_VERTICES);
  sw_mesh *me = &mi->mesh;
  me->ngroup = 1;
  me->group = sw_calloc(1, sizeof *me->group);
  me->x = sw_calloc(3 * (size_t)y->n, sizeof *me->x);
  if (!me->group || !me->x) return sy_oom(c, y);
  snprintf(me->group[0], sizeof me->group[0], "default");
  me->nv = y->n;
  for (int i = 0; i < y->n; i++) {
    snprintf(lab, sizeof lab, "mesh points[%d]", i);
    if (sy_vec(c, y->kid[i], lab, d, -HUGE_VAL, 0, "m", me->x + 3 * i)) return -1;
  }
  return 0;
}

static const char *const mesh_keys[] = {"grid", "obj", "uv_scale", "points"};

/* Load the mesh; *uv_scale multiplies the OBJ's (u,v) to metres. */
static int load_mesh(const ctx *c, const ynode *y, mesh_in *mi, double *uv_scale) {
  const ynode *v[4];
  if (sy_map(c, y, "mesh", mesh_keys, 4, v)) return -1;
  int given = !!v[0] + !!v[1] + !!v[3];
  if (given != 1)
    return sy_fail(c, y, "mesh has %s; expected exactly one of grid, obj or points",
                   given ? "more than one of grid, obj and points" : "none of grid, obj, points");
  *uv_scale = 1.0;
  if (v[2] && !v[1])
    return sy_fail(c, v[2], "mesh uv_scale is given without obj; expected uv_scale only with "
                   "obj (a grid's (u,v) layout is already in m)");
  if (v[2] && sy_num(c, v[2], "mesh uv_scale", 0, 1, "m per OBJ (u,v) unit", uv_scale))
    return -1;
  if (c->ov && c->ov->grid[0] > 0 && !v[0])
    return sy_fail(c, y, "mesh is %s, not mesh: {grid: ...}; expected a grid mesh for the grid "
                   "override (--grid)", v[1] ? "an OBJ file (obj)" : "a list of points");
  mi->at = v[0] ? v[0] : v[1] ? v[1] : v[3];
  if (v[3]) snprintf(mi->obj, sizeof mi->obj, "points");
  return v[0] ? load_grid(c, v[0], mi) : v[1] ? load_obj(c, v[1], mi) : load_points(c, v[3], mi);
}

/* ================================================================ filling the model */

/* x0, v0, face, uv and pinned from the mesh. */
static int fill_geometry(const ctx *c, const mesh_in *mi, double uv_scale) {
  sw_model *m = c->m;
  const sw_mesh *me = &mi->mesh;
  int dim = m->dim;
  m->nv = me->nv;
  m->nf = me->nf;
  m->x0 = sw_calloc((size_t)me->nv * (size_t)dim, sizeof *m->x0);
  m->v0 = sw_calloc((size_t)me->nv * (size_t)dim, sizeof *m->v0);
  m->pinned = sw_calloc((size_t)me->nv, 1);
  m->face = sw_calloc((size_t)me->nf * 3, sizeof *m->face);
  m->uv = sw_calloc((size_t)me->nf * 6, sizeof *m->uv);
  if (!m->x0 || !m->v0 || !m->pinned || !m->face || !m->uv) return sy_oom(c, mi->at);
  for (int i = 0; i < me->nv; i++)
    for (int a = 0; a < dim; a++) {
      double x = me->x[3 * i + a]; /* m */
      if (!isfinite(x)) return sy_fail(c, mi->at, "mesh vertex %d is not finite; expected finite "
                                    "coordinates", i);
      m->x0[i * dim + a] = x;
    }
  if (me->nf) memcpy(m->face, me->f, (size_t)me->nf * 3 * sizeof *m->face);
  if (me->nf && me->fpoly) {
    if (!(m->face_poly = sw_calloc((size_t)me->nf, sizeof *m->face_poly))) return sy_oom(c, mi->at);
    memcpy(m->face_poly, me->fpoly, (size_t)me->nf * sizeof *m->face_poly);
  }
  int has_uv = me->nuv > 0 && me->fuv;
  for (long k = 0; has_uv && k < 3L * me->nf; k++) {
    int t = me->fuv[k];
    if (t < 0 || t >= me->nuv) continue; /* refused where (u,v) matter (scene_material.c) */
    m->uv[2 * k] = uv_scale * me->uv[2 * t];         /* m */
    m->uv[2 * k + 1] = uv_scale * me->uv[2 * t + 1]; /* m */
  }
  return 0;
}

static const char *const top_keys[] = {"name",     "dimension", "mesh",     "material",
                                       "gravity",  "pins",      "initial_velocity",
                                       "integrator", "duration", "output",  "tension_xy",
                                       "panels",   "damping",   "tendons",  "loads",
                                       "masses",   "perturb",   "obstacles", "contact",
                                       "seams",    "sewing",    "fit",      "arrange"};
enum { K_NAME, K_DIM, K_MESH, K_MAT, K_GRAV, K_PINS, K_IV, K_INT, K_DUR, K_OUT, K_TXY, K_PANELS,
       K_DAMP, K_TENDONS, K_LOADS, K_MASSES, K_PERTURB, K_OBST, K_CONTACT, K_SEAMS, K_SEWING,
       K_FIT, K_ARRANGE, K_N };

static int load_name_dim(const ctx *c, const ynode **v) {
  sw_model *m = c->m;
  const char *s;
  if (strlen(c->name) >= sizeof m->path)
    return sy_fail(c, c->root, "the scene path is longer than %zu bytes; expected a shorter path",
                sizeof m->path - 1);
  snprintf(m->path, sizeof m->path, "%s", c->name);
  char stem[sizeof m->name];
  file_stem(c->name, stem, sizeof stem);
  if (v[K_NAME] && sy_str(c, v[K_NAME], "name", sizeof m->name, &s)) return -1;
  snprintf(m->name, sizeof m->name, "%s", v[K_NAME] ? s : stem);
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "out/%s", stem);
  m->dim = 3;
  return v[K_DIM] ? sy_int(c, v[K_DIM], "dimension", 2, 3, &m->dim) : 0;
}

static int load_geometry(ctx *c, const ynode **v) {
  mesh_in mi;
  double uv_scale = 1.0;
  memset(&mi, 0, sizeof mi);
  snprintf(mi.obj, sizeof mi.obj, "grid");
  int rc = sy_need(c, c->root, v[K_MESH], "the scene", "mesh",
                   "mesh: {grid: {...}}, {obj: file.obj} or {points: [...]}");
  if (!rc) rc = load_mesh(c, v[K_MESH], &mi, &uv_scale);
  if (!rc && mi.mesh.nf > 0 && !v[K_MAT])
    rc = sy_fail(c, c->root, "the scene has no 'material' key but the mesh has %d triangles; "
                 "expected material: {density: ...}", mi.mesh.nf);
  if (!rc && v[K_PANELS] && !v[K_MAT])
    rc = sy_fail(c, v[K_PANELS], "panels are given but the scene has no 'material' key; "
                 "expected material: {...} that the panels start from");
  if (!rc && v[K_MAT]) rc = sc_load_material(c, v[K_MAT], &mi.mesh, mi.obj);
  if (!rc) rc = fill_geometry(c, &mi, uv_scale);
  memcpy(c->grid, mi.grid, sizeof c->grid);
  if (!rc && v[K_PANELS]) rc = sc_load_panels(c, v[K_PANELS], &mi.mesh, mi.obj, uv_scale);
  c->ngroup = mi.mesh.ngroup; /* kept for the seams and the arrangement */
  c->group = mi.mesh.group, mi.mesh.group = NULL;
  c->fgroup = mi.mesh.fgroup, mi.mesh.fgroup = NULL;
  sw_mesh_free(&mi.mesh);
  if (!rc && !(c->sel = sw_calloc((size_t)c->m->nv, 1))) rc = sy_oom(c, c->root);
  return rc;
}

/* ================================================================ pins, velocities */

static const char *const pin_keys[] = {"select"};

static int load_pins(const ctx *c, const ynode *y) {
  char w[64], lab[96];
  const ynode *v[1];
  if (sy_seq(c, y, "pins", "a sequence of {select: ...}")) return -1;
  for (int p = 0; p < y->n; p++) {
    snprintf(w, sizeof w, "pins[%d]", p);
    if (sy_map(c, y->kid[p], w, pin_keys, 1, v) ||
        sy_need(c, y->kid[p], v[0], w, "select", "select: {vertices: [...]} or {box: [...]}"))
      return -1;
    snprintf(lab, sizeof lab, "%s select", w);
    if (sy_select(c, v[0], lab)) return -1;
    for (int i = 0; i < c->m->nv; i++) c->m->pinned[i] |= c->sel[i];
  }
  return 0;
}

static const char *const iv_keys[] = {"velocity", "select"};

static int load_velocities(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  char w[64], lab[96];
  const ynode *v[2];
  double vel[3];
  if (sy_seq(c, y, "initial_velocity", "a sequence of {velocity: [...], select: ...}"))
    return -1;
  for (int p = 0; p < y->n; p++) {
    snprintf(w, sizeof w, "initial_velocity[%d]", p);
    if (sy_map(c, y->kid[p], w, iv_keys, 2, v) ||
        sy_need(c, y->kid[p], v[0], w, "velocity", "velocity: [vx, vy(, vz)] in m/s"))
      return -1;
    snprintf(lab, sizeof lab, "%s velocity", w);
    if (sy_vec(c, v[0], lab, m->dim, -HUGE_VAL, 0, "m/s", vel)) return -1;
    snprintf(lab, sizeof lab, "%s select", w);
    if (v[1]) {
      if (sy_select(c, v[1], lab)) return -1;
    } else {
      memset(c->sel, 1, (size_t)m->nv);
    }
    for (int i = 0; i < m->nv; i++)
      if (c->sel[i]) memcpy(m->v0 + i * m->dim, vel, (size_t)m->dim * sizeof *vel);
  }
  return 0;
}

/* One item {select: SEL, <keys[1]>: value, ...} of a list of per-vertex quantities: its keys
 * into v, the two first required (hint: how to write the second). */
static int vertex_item(const ctx *c, const ynode *item, const char *w, const char *const *keys,
                       int nkeys, const ynode **v, const char *hint) {
  return sy_map(c, item, w, keys, nkeys, v) ||
                 sy_need(c, item, v[0], w, "select", "select: {vertices: [...]} or {box: [...]}") ||
                 sy_need(c, item, v[1], w, keys[1], hint)
             ? -1
             : 0;
}

static const char *const load_keys[] = {"select", "force", "ramp"};

/* A ramp time (s >= 0) into *T. */
static int load_ramp_time(const ctx *c, const ynode *y, const char *what, double *T) {
  return sy_num(c, y, what, 0, 0, "s", T);
}

/* loads[p] ramp T on the selected vertices: one ramp per vertex. */
static int set_load_ramp(const ctx *c, const ynode *at, const char *w, double T) {
  sw_model *m = c->m;
  if (!m->load_ramp && T == 0.0) return 0;
  if (!m->load_ramp && !(m->load_ramp = sw_calloc((size_t)m->nv, sizeof *m->load_ramp)))
    return sy_oom(c, at);
  for (int i = 0; i < m->nv; i++) {
    if (!c->sel[i]) continue;
    int loaded = 0;
    for (int a = 0; a < m->dim; a++) loaded |= m->load[i * m->dim + a] != 0.0;
    if (loaded && m->load_ramp[i] != T)
      return sy_fail(c, at, "%s ramp is %g s on vertex %d, which an earlier load ramps over "
                     "%g s; expected one ramp time per vertex", w, T, i, m->load_ramp[i]);
    m->load_ramp[i] = T; /* s */
  }
  return 0;
}

/* loads: [{select: SEL, force: [fx, fy(, fz)], ramp: T}]: force (N) on each selected vertex,
 * grown from 0 over T s (sw_ramp; default 0: on at t = 0); the items add up
 * (models/point_load.c). */
static int load_loads(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  char w[64], lab[96];
  const ynode *v[3];
  double f[3];
  if (sy_seq(c, y, "loads", "a sequence of {select: ..., force: [...]}")) return -1;
  if (!(m->load = sw_calloc((size_t)m->nv * (size_t)m->dim, sizeof *m->load)))
    return sy_oom(c, y);
  for (int p = 0; p < y->n; p++) {
    snprintf(w, sizeof w, "loads[%d]", p);
    if (vertex_item(c, y->kid[p], w, load_keys, 3, v, "force: [fx, fy(, fz)] in N")) return -1;
    snprintf(lab, sizeof lab, "%s force", w);
    if (sy_vec(c, v[1], lab, m->dim, -HUGE_VAL, 0, "N", f)) return -1;
    snprintf(lab, sizeof lab, "%s select", w);
    if (sy_select(c, v[0], lab)) return -1;
    double T = 0.0; /* s */
    snprintf(lab, sizeof lab, "%s ramp", w);
    if ((v[2] && load_ramp_time(c, v[2], lab, &T)) ||
        set_load_ramp(c, v[2] ? v[2] : y->kid[p], w, T))
      return -1;
    for (int i = 0; i < m->nv; i++)
      for (int a = 0; c->sel[i] && a < m->dim; a++) m->load[i * m->dim + a] += f[a]; /* N */
  }
  return 0;
}

static const char *const mass_keys[] = {"select", "mass"};

/* masses: [{select: SEL, mass: kg}]: a point mass on each selected vertex, added to its lumped
 * mass (not shared out); the items add up. */
static int load_masses(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  char w[64], lab[96];
  const ynode *v[2];
  if (sy_seq(c, y, "masses", "a sequence of {select: ..., mass: kg}")) return -1;
  if (!(m->point_mass = sw_calloc((size_t)m->nv, sizeof *m->point_mass))) return sy_oom(c, y);
  for (int p = 0; p < y->n; p++) {
    double mass;
    snprintf(w, sizeof w, "masses[%d]", p);
    if (vertex_item(c, y->kid[p], w, mass_keys, 2, v, "mass: kg >= 0")) return -1;
    snprintf(lab, sizeof lab, "%s mass", w);
    if (sy_num(c, v[1], lab, 0, 0, "kg", &mass)) return -1;
    snprintf(lab, sizeof lab, "%s select", w);
    if (sy_select(c, v[0], lab)) return -1;
    for (int i = 0; i < m->nv; i++) m->point_mass[i] += c->sel[i] ? mass : 0.0; /* kg */
  }
  return 0;
}

static const char *const perturb_keys[] = {"amplitude", "seed"};

/* perturb: {amplitude: m, seed: n}: sw_model_finish moves the free vertices of x0 along their
 * normals by a smooth random field of that largest value (3D only). */
static int load_perturb(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  const ynode *v[2];
  int seed = 0;
  if (sy_map(c, y, "perturb", perturb_keys, 2, v) ||
      sy_need(c, y, v[0], "perturb", "amplitude", "amplitude: m > 0"))
    return -1;
  if (m->dim != 3)
    return sy_fail(c, y, "perturb is given in a 2D scene; expected it only with dimension: 3 "
                   "(it moves vertices out of their surface)");
  if (sy_num(c, v[0], "perturb amplitude", 0, 1, "m", &m->perturb_amplitude)) return -1;
  if (v[1] && sy_int(c, v[1], "perturb seed", 0, INT_MAX, &seed)) return -1;
  m->perturb_seed = (unsigned long)seed;
  return 0;
}

static const char *const gravity_keys[] = {"vector", "ramp"};

/* gravity: [gx, gy(, gz)] or {vector: [...], ramp: T} (grown from 0 over T s, sw_ramp). */
static int load_gravity(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  if (!y) return 0;
  const ynode *v[2] = {y, NULL};
  if (y->kind == Y_MAP &&
      (sy_map(c, y, "gravity", gravity_keys, 2, v) ||
       sy_need(c, y, v[0], "gravity", "vector", "vector: [gx, gy(, gz)] in m/s^2")))
    return -1;
  if (sy_vec(c, v[0], "gravity", m->dim, -HUGE_VAL, 0, "m/s^2", m->gravity)) return -1;
  if (v[1] && load_ramp_time(c, v[1], "gravity ramp", &m->gravity_ramp)) return -1;
  m->has_gravity = 1;
  return 0;
}

/* ================================================================ options */

static const char *const int_keys[] = {"method", "dt", "max_halvings", "newton", "hessian",
                                       "rtol", "atol", "max_order", "max_step", "energy_bound",
                                       "tendon_dense_max", "setup_every", "factorization",
                                       "ordering", "bending_matrix"};
static const char *const newton_keys[] = {"max_iterations", "tol", "reuse", "force_tol", "norm"};
static const char *const reuse_names[] = {"false", "true", "auto", "step"};

static int load_method(const ctx *c, const ynode *y) {
  const char *const *names = sw_method_names();
  static const char *const none[] = {NULL};
  int n = 0, k = 0;
  if (!names) names = none;
  while (names[n]) n++;
  if (sy_choice(c, y, "integrator method", names, n, &k)) return -1;
  snprintf(c->m->opt.method, sizeof c->m->opt.method, "%s", names[k]);
  return 0;
}

/* max_order: `auto` (0) or an integer in [1, 5]. */
static int load_max_order(const ctx *c, const ynode *y, int *out) {
  if (y->kind == Y_SCALAR && y->plain && !strcmp(y->text, "auto")) return *out = 0, 0;
  double v;
  if (sy_scalar_number(y, &v))
    return sy_type_error(c, y, "integrator max_order", "auto or an integer in [1, 5]");
  return sy_int(c, y, "integrator max_order", 1, 5, out);
}

static int load_integrator(const ctx *c, const ynode *y) {
  sw_options *o = &c->m->opt;
  const ynode *v[15], *nv[5];
  if (sy_map(c, y, "integrator", int_keys, 15, v)) return -1;
  if (v[14] && sy_choice(c, v[14], "integrator bending_matrix", sw_bending_matrix_names(),
                         SW_BMATRIX_N, &o->bending_matrix)) return -1;
  if (v[13] && sy_choice(c, v[13], "integrator ordering", sw_ordering_names(), SW_ORDERING_N,
                         &o->ordering)) return -1;
  if (v[12] && sy_choice(c, v[12], "integrator factorization", sw_factor_names(), SW_FACTOR_N,
                         &o->factorization)) return -1;
  if (v[11] && sy_int(c, v[11], "integrator setup_every", 1, INT_MAX, &o->setup_every))
    return -1;
  if (v[10] && sy_int(c, v[10], "integrator tendon_dense_max", 0, INT_MAX, &o->tendon_dense_max))
    return -1;
  if (v[5] && sy_num(c, v[5], "integrator rtol", 0, 1, NULL, &o->rtol)) return -1;
  if (v[6] && sy_num(c, v[6], "integrator atol", 0, 1, NULL, &o->atol)) return -1;
  if (v[7] && load_max_order(c, v[7], &o->max_order)) return -1;
  if (v[8] && sy_num(c, v[8], "integrator max_step", 0, 0, "s", &o->max_step)) return -1;
  if (v[9] && sy_num(c, v[9], "integrator energy_bound", 0, 1, "J", &o->energy_bound))
    return -1;
  if (v[4] && sy_choice(c, v[4], "integrator hessian", sw_hessian_names(), SW_HESSIAN_NMODES,
                        &o->hessian)) return -1;
  if (v[0] && load_method(c, v[0])) return -1;
  if (v[1] && sy_num(c, v[1], "integrator dt", 0, 1, "s", &o->dt)) return -1;
  if (v[2] && sy_int(c, v[2], "integrator max_halvings", 0, 60, &o->max_halvings)) return -1;
  if (!v[3]) return 0;
  if (sy_map(c, v[3], "integrator newton", newton_keys, 5, nv)) return -1;
  if (nv[4] && sy_choice(c, nv[4], "integrator newton norm", sw_norm_names(), SW_NORM_N,
                         &o->newton_norm)) return -1;
  if (nv[2] && sy_choice(c, nv[2], "integrator newton reuse", reuse_names, 4,
                         &o->newton_reuse))
    return -1;
  if (nv[0] &&
      sy_int(c, nv[0], "integrator newton max_iterations", 1, INT_MAX, &o->newton_max))
    return -1;
  if (nv[1] && sy_num(c, nv[1], "integrator newton tol", 0, 1, NULL, &o->newton_tol)) return -1;
  if (nv[3]) { /* static solve; relative to the force scale, so below 1 */
    double v = 0.0;
    if (sy_scalar_number(nv[3], &v) || !(v > 0.0 && v < 1.0))
      return sy_type_error(c, nv[3], "integrator newton force_tol",
                           "a number in (0, 1) (relative to the force scale)");
    o->newton_force_tol = v;
  }
  return 0;
}

static const char *const out_keys[] = {"dir", "frames_every", "positions_every",
                                       "frames_format", "restart_every"};

static int load_output(const ctx *c, const ynode *y) {
  sw_options *o = &c->m->opt;
  const ynode *v[5];
  const char *dir;
  if (sy_map(c, y, "output", out_keys, 5, v)) return -1;
  if (v[0]) {
    if (sy_str(c, v[0], "output dir", sizeof o->out_dir, &dir)) return -1;
    snprintf(o->out_dir, sizeof o->out_dir, "%s", dir);
  }
  if (v[1] && sy_num(c, v[1], "output frames_every", 0, 0, "s", &o->frames_every)) return -1;
  if (v[2] && sy_num(c, v[2], "output positions_every", 0, 0, "s", &o->positions_every))
    return -1;
  if (v[3] && sy_choice(c, v[3], "output frames_format", sw_frames_format_names(), SW_FRAMES_N,
                        &o->frames_format))
    return -1;
  if (v[4] && sy_num(c, v[4], "output restart_every", 0, 0, "s of wall time", &o->restart_every))
    return -1;
  return 0;
}

static const char *const txy_keys[] = {"clip", "reference", "k_u", "k_v"};
static const char *const txy_refs[] = {"initial", "uv"};

static int load_tension_xy(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  sw_options *o = &m->opt;
  const ynode *v[4];
  if (!y) return 0;
  if (sy_map(c, y, "tension_xy", txy_keys, 4, v)) return -1;
  if (v[0] && sy_num(c, v[0], "tension_xy clip", 0, 1, "N/m", &o->tx_clip)) return -1;
  if (v[1] && sy_choice(c, v[1], "tension_xy reference", txy_refs, 2, &o->tx_reference_uv))
    return -1;
  if (v[2] && sy_num(c, v[2], "tension_xy k_u", 0, 0, "N/m", &o->tx_k_u)) return -1;
  if (v[3] && sy_num(c, v[3], "tension_xy k_v", 0, 0, "N/m", &o->tx_k_v)) return -1;
  return 0;
}

static int load_options(const ctx *c, const ynode **v) {
  sw_options *o = &c->m->opt;
  if (v[K_INT] && load_integrator(c, v[K_INT])) return -1;
  if (v[K_DUR] && sy_num(c, v[K_DUR], "duration", 0, 0, "s", &o->duration)) return -1;
  if (v[K_OUT] && load_output(c, v[K_OUT])) return -1;
  return load_tension_xy(c, v[K_TXY]);
}

/* ================================================================ entry points */

static int load_scene(ctx *c) {
  const ynode *v[K_N];
  if (sy_map(c, c->root, "the scene", top_keys, K_N, v)) return -1;
  if (load_name_dim(c, v) || load_geometry(c, v) || load_gravity(c, v[K_GRAV])) return -1;
  /* the arrangement places pieces around the obstacles, before pins select by position */
  if (v[K_OBST] && sc_load_obstacles(c, v[K_OBST])) return -1;
  if (v[K_ARRANGE] && sc_load_arrange(c, v[K_ARRANGE])) return -1;
  if (v[K_PINS] && load_pins(c, v[K_PINS])) return -1;
  if (v[K_IV] && load_velocities(c, v[K_IV])) return -1;
  if (v[K_DAMP] && sc_load_damping(c, v[K_DAMP])) return -1;
  if (v[K_TENDONS] && sc_load_tendons(c, v[K_TENDONS])) return -1;
  if (v[K_LOADS] && load_loads(c, v[K_LOADS])) return -1;
  if (v[K_MASSES] && load_masses(c, v[K_MASSES])) return -1;
  if (v[K_PERTURB] && load_perturb(c, v[K_PERTURB])) return -1;
  if (sc_load_contact(c, v[K_CONTACT], v[K_OBST] != NULL)) return -1;
  if (sc_load_seams(c, v[K_SEAMS], v[K_SEWING], v[K_FIT])) return -1;
  return load_options(c, v);
}

/* The overrides themselves: a grid of at least 2 x 2 vertices and at most the scene key's total,
 * a finite stiffness scale >= 0 (0: none). */
static int check_overrides(const char *name, const sw_scene_overrides *ov, char *err,
                           size_t errsz) {
  const int *g = ov->grid;
  if ((g[0] || g[1]) && (g[0] < 2 || g[1] < 2))
    return sw_errf(err, errsz, "%s: the grid override (--grid) is %d x %d vertices; "
                   "expected at least 2 each way", name, g[0], g[1]), -1;
  if ((double)g[0] * g[1] > (double)SW_SCENE_MAX_VERTICES)
    return sw_errf(err, errsz, "%s: the grid override (--grid) is %d x %d vertices; "
                   "expected at most %ld vertices in all", name, g[0], g[1],
                   (long)SW_SCENE_MAX_VERTICES), -1;
  double s = ov->stiffness_scale;
  if (!isfinite(s) || s < 0.0)
    return sw_errf(err, errsz, "%s: the stiffness scale (--stiffness-scale) is %g; "
                   "expected a number > 0", name, s), -1;
  if (ov->bending_matrix < 0 || ov->bending_matrix > SW_BMATRIX_N)
    return sw_errf(err, errsz, "%s: the bending matrix override is %d; expected 0 to %d", name,
                   ov->bending_matrix, SW_BMATRIX_N), -1;
  return 0;
}

/* --grid on a scene that selects by vertex index: where, and what to use instead. */
static void grid_warning(const ctx *c, const ynode *at) {
  snprintf(c->m->warning, sizeof c->m->warning,
           "%s:%d:%d: the scene selects vertices by index, and the grid override (--grid "
           "%dx%d) keeps indices, not places: the same indices are other vertices on the new "
           "grid; select by box or grid: [[i, j], ...] to keep their meaning", c->name, at->line,
           at->col, c->ov->grid[0], c->ov->grid[1]);
}

sw_model *sw_scene_parse(const char *name, const char *buf, size_t len, char *err,
                         size_t errsz) {
  return sw_scene_parse_ex(name, buf, len, NULL, err, errsz);
}

sw_model *sw_scene_parse_ex(const char *name, const char *buf, size_t len,
                            const sw_scene_overrides *ov, char *err, size_t errsz) {
  if (err && errsz) err[0] = '\0';
  if (!name) name = "<scene>";
  if (!buf) len = 0;
  if (ov && check_overrides(name, ov, err, errsz)) return NULL;
  ynode *root = sy_parse(name, buf, len, err, errsz);
  if (!root) return NULL;
  const ynode *by_index = NULL;
  sw_names gnames = {0};
  ctx c = {.name = name, .err = err, .errsz = errsz, .root = root, .ov = ov,
           .by_index = &by_index, .gnames = &gnames};
  c.m = sw_model_new();
  /* measured (docs/performance.md, "The bending matrix"): compact where inertia sits beside
   * the bending, exact for the static method and the optimisation fits */
  if (c.m) c.m->opt.bending_matrix = SW_BMATRIX_AUTO;
  int rc = c.m ? sc_note_input(&c, root, name, buf, len) : sy_oom(&c, root);
  if (!rc && ov) memcpy(c.m->grid_override, ov->grid, sizeof ov->grid);
  if (!rc) rc = load_scene(&c);
  if (!rc && by_index && ov && ov->grid[0] > 0) grid_warning(&c, by_index);
  if (!rc) sc_plausibility(&c); /* the scene's own numbers, before --stiffness-scale */
  int at[2] = {0, 0}; /* line and column of the mesh, for the model's own checks */
  int ob[2] = {0, 0}, ct[2] = {0, 0}; /* and of the obstacles and of contact */
  for (int k = 0; root->kind == Y_MAP && k + 1 < root->n; k += 2) {
    if (root->kid[k]->kind != Y_SCALAR) continue;
    int *p = !strcmp(root->kid[k]->text, "mesh") ? at
             : !strcmp(root->kid[k]->text, "obstacles") ? ob
             : !strcmp(root->kid[k]->text, "contact") ? ct : NULL;
    if (p) p[0] = root->kid[k + 1]->line, p[1] = root->kid[k + 1]->col;
  }
  sw_free(c.sel);
  sw_names_free(&gnames);
  sw_free(c.group);
  sw_free(c.fgroup);
  sy_free(root);
  if (!rc && ov && ov->stiffness_scale > 0.0) sc_scale_stiffness(c.m, ov->stiffness_scale);
  if (!rc && ov && ov->bending_matrix > 0) c.m->opt.bending_matrix = ov->bending_matrix - 1;
  if (!rc && ov && ov->method && ov->method[0])
    snprintf(c.m->opt.method, sizeof c.m->opt.method, "%s", ov->method);
  if (rc) {
    sw_model_free(c.m);
    return NULL;
  }
  char e[SW_ERRSZ];
  if (sw_model_finish(c.m, e, sizeof e)) { /* e.g. a face of zero rest area: at the mesh */
    if (at[0] > 0) sw_errf(err, errsz, "%s:%d:%d: mesh: %s", name, at[0], at[1], e);
    else sw_errf(err, errsz, "%s: %s", name, e);
    sw_model_free(c.m);
    return NULL;
  }
  for (int k = 0; k < c.m->nterm; k++) { /* each term's start check (contact's) */
    const sw_term *t = &c.m->term[k];
    const char *key = "";
    if (!t->ops->check_start || !t->ops->check_start(t, c.m, c.m->x0, &key, e, sizeof e))
      continue;
    const int *at_key = !strncmp(key, "contact", 7) ? ct : ob;
    sw_errf(err, errsz, "%s:%d:%d: %s: %s", name, at_key[0], at_key[1], key, e);
    sw_model_free(c.m);
    return NULL;
  }
  return c.m;
}

/* The whole file into a NUL-terminated buffer; NULL with err. */
static char *read_file(const char *path, size_t *len, char *err, size_t errsz) {
  FILE *f = fopen(path, "rb");
  if (!f) {
    sw_errf(err, errsz, "%s: cannot open the scene file: %s", path, strerror(errno));
    return NULL;
  }
  size_t n = 0, cap = 4096;
  char *buf = sw_calloc(cap, 1);
  while (buf) {
    n += fread(buf + n, 1, cap - n - 1, f);
    if (n + 1 < cap || ferror(f) || n > (size_t)SW_SCENE_MAX_BYTES) break;
    char *b = sw_realloc(buf, 2 * cap, 1);
    if (!b) sw_free(buf);
    buf = b;
    cap *= 2;
  }
  int bad = !buf || ferror(f) || n > (size_t)SW_SCENE_MAX_BYTES;
  if (!buf) sw_errf(err, errsz, "%s: out of memory reading the scene file", path);
  else if (ferror(f)) sw_errf(err, errsz, "%s: cannot read the scene file: %s", path,
                              strerror(errno));
  else if (bad) sw_errf(err, errsz, "%s: the scene file is larger than %ld bytes; expected a "
                        "smaller file", path, (long)SW_SCENE_MAX_BYTES);
  fclose(f);
  if (bad) {
    sw_free(buf);
    return NULL;
  }
  buf[n] = '\0';
  *len = n;
  return buf;
}

sw_model *sw_scene_load(const char *path, char *err, size_t errsz) {
  return sw_scene_load_ex(path, NULL, err, errsz);
}

sw_model *sw_scene_load_ex(const char *path, const sw_scene_overrides *ov, char *err,
                           size_t errsz) {
  size_t len = 0;
  if (!path) {
    sw_errf(err, errsz, "(null): no scene file given");
    return NULL;
  }
  char *buf = read_file(path, &len, err, errsz);
  if (!buf) return NULL;
  sw_model *m = sw_scene_parse_ex(path, buf, len, ov, err, errsz);
  sw_free(buf);
  return m;
}
