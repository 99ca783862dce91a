/* scene_select.c — vertex selections of a scene, {vertices: [...]}, {box: [[lo], [hi]]},
 * {grid: [[i, j], ...]} or {disc: {center, radius}} (docs/scenes.md), shared by pins, velocities and loads (scene.c) and tendon waypoints
 * (scene_tendon.c); it sits below both and calls only the schema getters (scene_yaml.c). */
#include "scene_yaml.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const sel_keys[] = {"vertices", "box", "grid", "disc"};

void sy_note_index(const ctx *c, const ynode *y) {
  if (c->by_index && !*c->by_index) *c->by_index = y;
}

static int select_list(const ctx *c, const ynode *y, const char *what) {
  char lab[176];
  if (sy_seq(c, y, what, "a sequence of vertex indices")) return -1;
  sy_note_index(c, y);
  for (int i = 0; i < y->n; i++) {
    int k;
    snprintf(lab, sizeof lab, "%s[%d]", what, i);
    if (sy_int(c, y->kid[i], lab, 0, (long)c->m->nv - 1, &k)) return -1;
    c->sel[k] = 1;
  }
  return 0;
}

static int select_box(const ctx *c, const ynode *y, const char *what) {
  const sw_model *m = c->m;
  char lab[176];
  double lo[3], hi[3];
  if (sy_seq(c, y, what, "[[min corner], [max corner]]")) return -1;
  if (y->n != 2) return sy_fail(c, y, "%s has %d corners; expected 2 (min and max)", what, y->n);
  snprintf(lab, sizeof lab, "%s min corner", what);
  if (sy_vec(c, y->kid[0], lab, m->dim, -HUGE_VAL, 0, "m", lo)) return -1;
  snprintf(lab, sizeof lab, "%s max corner", what);
  if (sy_vec(c, y->kid[1], lab, m->dim, -HUGE_VAL, 0, "m", hi)) return -1;
  for (int a = 0; a < m->dim; a++)
    if (lo[a] > hi[a])
      return sy_fail(c, y, "%s has min %g > max %g in component %d; expected min <= max", what,
                  lo[a], hi[a], a);
  for (int i = 0; i < m->nv; i++) {
    int in = 1;
    for (int a = 0; a < m->dim; a++) {
      double x = m->x0[i * m->dim + a];
      in = in && x >= lo[a] && x <= hi[a];
    }
    if (in) c->sel[i] = 1;
  }
  return 0;
}

/* grid: [[i, j], ...]: grid vertex (i, j), index j nx + i; a negative i or j counts from the
 * far end (-1: the last), so [-1, -1] stays the far corner on any grid (--grid). */
static int select_grid(const ctx *c, const ynode *y, const char *what) {
  char lab[192];
  const int *g = c->grid;
  if (!g[0])
    return sy_fail(c, y, "%s is given but the mesh is not a grid; expected vertices, box or disc",
                   what);
  if (sy_seq(c, y, what, "a sequence of [i, j] grid positions")) return -1;
  for (int k = 0; k < y->n; k++) {
    int ij[2];
    snprintf(lab, sizeof lab, "%s[%d]", what, k);
    if (sy_seq(c, y->kid[k], lab, "[i, j]: column and row, negative from the far end"))
      return -1;
    if (y->kid[k]->n != 2)
      return sy_fail(c, y->kid[k], "%s has %d numbers; expected [i, j]", lab, y->kid[k]->n);
    for (int a = 0; a < 2; a++) {
      snprintf(lab, sizeof lab, "%s[%d][%d]", what, k, a);
      if (sy_int(c, y->kid[k]->kid[a], lab, -(long)g[a], g[a] - 1L, &ij[a])) return -1;
      if (ij[a] < 0) ij[a] += g[a];
    }
    c->sel[ij[1] * g[0] + ij[0]] = 1;
  }
  return 0;
}

/* disc: {center: [x, y(, z)], radius: r}: the vertices whose initial position (before any
 * perturbation) lies within Euclidean distance r of the centre, boundary included. On a flat
 * cloth with the centre in its plane this is the disc of radius r; off the plane, a ball. */
static const char *const disc_keys[] = {"center", "radius"};

static int select_disc(const ctx *c, const ynode *y, const char *what) {
  const sw_model *m = c->m;
  const ynode *v[2];
  char lab[176];
  double ctr[3], r;
  if (sy_map(c, y, what, disc_keys, 2, v)) return -1;
  if (sy_need(c, y, v[0], what, "center", "center: [x, y(, z)] in m") ||
      sy_need(c, y, v[1], what, "radius", "radius: r > 0 in m"))
    return -1;
  snprintf(lab, sizeof lab, "%s center", what);
  if (sy_vec(c, v[0], lab, m->dim, -HUGE_VAL, 0, "m", ctr)) return -1;
  snprintf(lab, sizeof lab, "%s radius", what);
  if (sy_num(c, v[1], lab, 0, 1, "m", &r)) return -1;
  for (int i = 0; i < m->nv; i++) {
    double d2 = 0;
    for (int a = 0; a < m->dim; a++) {
      double d = m->x0[i * m->dim + a] - ctr[a];
      d2 += d * d;
    }
    if (d2 <= r * r) c->sel[i] = 1;
  }
  return 0;
}

/* Mark the vertices that the selection y picks in c->sel. */
int sy_select(const ctx *c, const ynode *y, const char *what) {
  static const char *const kind[] = {"vertices", "box", "grid", "disc"};
  const ynode *v[4];
  char lab[128];
  memset(c->sel, 0, (size_t)c->m->nv);
  if (sy_map(c, y, what, sel_keys, 4, v)) return -1;
  int given = !!v[0] + !!v[1] + !!v[2] + !!v[3], k = v[0] ? 0 : v[1] ? 1 : v[2] ? 2 : 3;
  if (given != 1)
    return sy_fail(c, y, "%s has %s; expected exactly one of vertices, box, grid or disc", what,
                   given ? "more than one of vertices, box, grid and disc"
                         : "none of vertices, box, grid, disc");
  snprintf(lab, sizeof lab, "%s %s", what, kind[k]);
  int rc = k == 0 ? select_list(c, v[0], lab)
           : k == 1 ? select_box(c, v[1], lab)
           : k == 2 ? select_grid(c, v[2], lab)
                    : select_disc(c, v[3], lab);
  if (rc) return -1;
  for (int i = 0; i < c->m->nv; i++)
    if (c->sel[i]) return 0;
  return sy_fail(c, y, "%s selects no vertex; expected a selection of at least one vertex", what);
}
