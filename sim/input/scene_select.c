/* scene_select.c — vertex selections of a scene, {vertices: [...]} or {box: [[lo], [hi]]}
 * (docs/scenes.md), shared by pins, velocities and loads (scene.c) and tendon waypoints
 * (scene_tendon.c); it sits below both and calls only the schema getters (scene_yaml.c). */
#include "scene_yaml.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const sel_keys[] = {"vertices", "box"};

static int select_list(const ctx *c, const ynode *y, const char *what) {
  char lab[176];
  if (sy_seq(c, y, what, "a sequence of vertex indices")) return -1;
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

/* Mark the vertices that the selection y picks in c->sel. */
int sy_select(const ctx *c, const ynode *y, const char *what) {
  const ynode *v[2];
  char lab[128];
  memset(c->sel, 0, (size_t)c->m->nv);
  if (sy_map(c, y, what, sel_keys, 2, v)) return -1;
  if (!v[0] == !v[1])
    return sy_fail(c, y, "%s has %s; expected exactly one of vertices or box", what,
                v[0] ? "both vertices and box" : "neither vertices nor box");
  snprintf(lab, sizeof lab, "%s %s", what, v[0] ? "vertices" : "box");
  if (v[0] ? select_list(c, v[0], lab) : select_box(c, v[1], lab)) return -1;
  for (int i = 0; i < c->m->nv; i++)
    if (c->sel[i]) return 0;
  return sy_fail(c, y, "%s selects no vertex; expected a selection of at least one vertex", what);
}
