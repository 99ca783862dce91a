/* scene_tendon.c — a scene's `tendons` (docs/scenes.md, docs/tendons.md):
 *   - {name: s1, waypoints: [0, 41, 82] | {box: [[lo], [hi]], along: x} | {vertices: [...]},
 *      law: cable | spring, stiffness: K (N/m), rest_length: L (m) | {relative: r} |
 *      {keyframes: [[t, L], ...], relative: false, interpolation: smooth | linear},
 *      density: kg/m, damping: N s/m}
 * A selection's vertices are ordered along an axis (`along`, default: the axis on which they
 * spread most).  Rest length default: the initial length (relative 1). */
#include "scene_material.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util.h"

/* Message labels nest (tendon s1 rest_length keyframes[2]); one cut short is still clear. */
#pragma GCC diagnostic ignored "-Wformat-truncation"

static const char *const tendon_keys[] = {"name", "waypoints", "law", "stiffness",
                                          "rest_length", "density", "damping"};
enum { TK_NAME, TK_WAY, TK_LAW, TK_K, TK_REST, TK_DENSITY, TK_DAMP, TK_N };
static const char *const laws[] = {"spring", "cable"}; /* SW_LAW_* order */
static const char *const axes[] = {"x", "y", "z"};
static const char *const way_keys[] = {"vertices", "box", "grid", "along"};

/* Listed waypoints: each index in the mesh, none repeated. */
static int waypoint_list(const ctx *c, const ynode *y, const char *w, sw_tendon *td) {
  char lab[256];
  if (!(td->way = sw_calloc((size_t)y->n + 1, sizeof *td->way))) return sy_oom(c, y);
  sy_note_index(c, y);
  memset(c->sel, 0, (size_t)c->m->nv);
  for (int i = 0; i < y->n; i++) {
    snprintf(lab, sizeof lab, "%s waypoints[%d]", w, i);
    if (sy_int(c, y->kid[i], lab, 0, (long)c->m->nv - 1, &td->way[i])) return -1;
    if (c->sel[td->way[i]])
      return sy_fail(c, y->kid[i], "%s repeats vertex %d; expected distinct waypoints", lab,
                     td->way[i]);
    c->sel[td->way[i]] = 1;
  }
  td->nway = y->n;
  return 0;
}

typedef struct keyed { double key; int i; } keyed; /* a vertex and its coordinate on an axis */

static int cmp_keyed(const void *a, const void *b) {
  const keyed *p = a, *q = b;
  return p->key < q->key ? -1 : p->key > q->key ? 1 : (p->i > q->i) - (p->i < q->i);
}

/* Sort the n vertices way[] by their coordinate on axis (ties by index). */
static int sort_along(const sw_model *m, int axis, int *way, int n) {
  keyed *k = sw_calloc((size_t)n, sizeof *k);
  if (!k) return -1;
  for (int j = 0; j < n; j++) k[j] = (keyed){m->x0[(size_t)way[j] * m->dim + axis], way[j]};
  qsort(k, (size_t)n, sizeof *k, cmp_keyed);
  for (int j = 0; j < n; j++) way[j] = k[j].i;
  sw_free(k);
  return 0;
}

/* A selection's vertices (c->sel) ordered along an axis. */
static int waypoint_selection(const ctx *c, const ynode *y, const char *w, sw_tendon *td) {
  const sw_model *m = c->m;
  const ynode *v[4];
  char lab[256];
  if (sy_map(c, y, w, way_keys, 4, v)) return -1;
  /* the pin selection reads a map of only vertices, box or grid: hand it one without along */
  ynode sub = *y;
  const ynode *kids[6];
  int n = 0;
  for (int p = 0; p < y->n / 2; p++)
    if (y->kid[2 * p + 1] != v[3]) kids[n++] = y->kid[2 * p], kids[n++] = y->kid[2 * p + 1];
  sub.kid = (ynode **)kids;
  sub.n = n;
  if (sy_select(c, &sub, w)) return -1;
  int axis = -1;
  if (v[3]) {
    snprintf(lab, sizeof lab, "%s along", w);
    if (sy_choice(c, v[3], lab, axes, m->dim, &axis)) return -1;
  }
  int cnt = 0;
  for (int i = 0; i < m->nv; i++) cnt += c->sel[i];
  if (!(td->way = sw_calloc((size_t)cnt + 1, sizeof *td->way))) return sy_oom(c, y);
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int i = 0; i < m->nv; i++) {
    if (!c->sel[i]) continue;
    td->way[td->nway++] = i;
    for (int a = 0; a < m->dim; a++) {
      lo[a] = fmin(lo[a], m->x0[i * m->dim + a]);
      hi[a] = fmax(hi[a], m->x0[i * m->dim + a]);
    }
  }
  if (axis < 0) /* the axis of largest spread */
    for (int a = axis = 0; a < m->dim; a++)
      if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  return sort_along(m, axis, td->way, td->nway) ? sy_oom(c, y) : 0;
}

static int load_waypoints(const ctx *c, const ynode *y, const char *w, sw_tendon *td) {
  char lab[256];
  snprintf(lab, sizeof lab, "%s waypoints", w);
  int rc = y->kind == Y_SEQ   ? waypoint_list(c, y, w, td)
           : y->kind == Y_MAP ? waypoint_selection(c, y, lab, td)
                              : sy_type_error(c, y, lab, "a sequence of vertex indices or a "
                                              "selection {box: ..., along: x}");
  if (rc) return rc;
  if (td->nway < 2)
    return sy_fail(c, y, "%s has %d vertex; expected at least two waypoints", lab, td->nway);
  return 0;
}

static const char *const rest_keys[] = {"relative", "keyframes", "interpolation"};
static const char *const interps[] = {"linear", "smooth"}; /* SW_INTERP_* order */

/* Keyframes [[t, L], ...] with increasing t; L relative to l0 when relative. */
static int load_keyframes(const ctx *c, const ynode *y, const char *w, double scale,
                          sw_tendon *td) {
  char lab[256];
  if (sy_seq(c, y, w, "a sequence of [time s, rest length] pairs")) return -1;
  if (y->n < 1) return sy_fail(c, y, "%s is empty; expected at least one [t, L] pair", w);
  td->key_t = sw_calloc((size_t)y->n, sizeof(double));
  td->key_rest = sw_calloc((size_t)y->n, sizeof(double));
  if (!td->key_t || !td->key_rest) return sy_oom(c, y);
  for (int k = 0; k < y->n; k++) {
    double tl[2];
    snprintf(lab, sizeof lab, "%s[%d]", w, k);
    if (sy_vec(c, y->kid[k], lab, 2, -HUGE_VAL, 0, "s, m or ratio", tl)) return -1;
    if (k > 0 && !(tl[0] > td->key_t[k - 1]))
      return sy_fail(c, y->kid[k], "%s has time %g s after %g s; expected increasing times",
                     lab, tl[0], td->key_t[k - 1]);
    if (!(tl[1] >= 0))
      return sy_fail(c, y->kid[k]->kid[1], "%s rest length is %g; expected a number >= 0",
                     lab, tl[1]);
    td->key_t[k] = tl[0];
    td->key_rest[k] = tl[1] * scale; /* m */
  }
  td->nkey = y->n;
  return 0;
}

/* rest_length: a number (m), {relative: r}, or {keyframes: [...], relative: bool}. */
static int load_rest(const ctx *c, const ynode *y, const char *w, double l0, sw_tendon *td) {
  char lab[256];
  snprintf(lab, sizeof lab, "%s rest_length", w);
  if (!y || y->kind == Y_SCALAR) {
    double r = l0;
    if (y && sy_num(c, y, lab, 0, 0, "m", &r)) return -1;
    td->key_t = sw_calloc(1, sizeof(double));
    td->key_rest = sw_calloc(1, sizeof(double));
    if (!td->key_t || !td->key_rest) return sy_oom(c, y ? y : c->root);
    td->nkey = 1;
    td->key_rest[0] = r; /* m */
    return 0;
  }
  const ynode *v[3];
  if (sy_map(c, y, lab, rest_keys, 3, v)) return -1;
  double rel = 1.0;
  int by_ratio = 0;
  char l2[320];
  snprintf(l2, sizeof l2, "%s interpolation", lab);
  if (v[2] && !v[1])
    return sy_fail(c, v[2], "%s is given without keyframes; expected interpolation only with "
                   "keyframes: [...]", l2);
  td->interp = SW_INTERP_SMOOTH; /* the default: docs/scenes.md "Forcing" (measured) */
  if (v[2] && sy_choice(c, v[2], l2, interps, 2, &td->interp)) return -1;
  snprintf(l2, sizeof l2, "%s relative", lab);
  if (v[1]) { /* relative: true/false (default false: keyframes in m) */
    if (v[0]) {
      static const char *const bools[] = {"false", "true"};
      if (sy_choice(c, v[0], l2, bools, 2, &by_ratio)) return -1;
    }
    snprintf(l2, sizeof l2, "%s keyframes", lab);
    return load_keyframes(c, v[1], l2, by_ratio ? l0 : 1.0, td);
  }
  if (!v[0]) return sy_fail(c, y, "%s is empty; expected relative: r or keyframes: [...]", lab);
  if (sy_num(c, v[0], l2, 0, 0, "ratio to the initial length", &rel)) return -1;
  td->key_t = sw_calloc(1, sizeof(double));
  td->key_rest = sw_calloc(1, sizeof(double));
  if (!td->key_t || !td->key_rest) return sy_oom(c, y);
  td->nkey = 1;
  td->key_rest[0] = rel * l0; /* m */
  return 0;
}

/* tendons[k]; names: the names of tendons[0..k-1] (hashed: a scene may have 1e5 tendons). */
static int load_tendon(const ctx *c, const ynode *y, int k, sw_tendon *td, sw_names *names) {
  const ynode *v[TK_N];
  char w[SW_NAMESZ + 32], lab[SW_NAMESZ + 64];
  const char *name;
  snprintf(w, sizeof w, "tendons[%d]", k);
  if (sy_map(c, y, w, tendon_keys, TK_N, v)) return -1;
  if (v[TK_NAME] && sy_str(c, v[TK_NAME], "tendon name", SW_NAMESZ, &name)) return -1;
  snprintf(td->name, sizeof td->name, "%s", v[TK_NAME] ? name : "");
  if (!v[TK_NAME]) snprintf(td->name, sizeof td->name, "tendon%d", k);
  int j = sw_names_add(names, td->name, k);
  if (j == -2) return sy_oom(c, y);
  if (j >= 0)
    return sy_fail(c, v[TK_NAME] ? v[TK_NAME] : y, "%s is named '%s' like tendons[%d]; "
                   "expected distinct names", w, td->name, j);
  snprintf(w, sizeof w, "tendon %s", td->name);
  if (sy_need(c, y, v[TK_WAY], w, "waypoints", "waypoints: [i, j, ...] or a selection") ||
      sy_need(c, y, v[TK_K], w, "stiffness", "stiffness: K >= 0 (N/m)") ||
      load_waypoints(c, v[TK_WAY], w, td))
    return -1;
  td->law = SW_LAW_CABLE;
  snprintf(lab, sizeof lab, "%s law", w);
  if (v[TK_LAW] && sy_choice(c, v[TK_LAW], lab, laws, 2, &td->law)) return -1;
  snprintf(lab, sizeof lab, "%s stiffness", w);
  if (sy_num(c, v[TK_K], lab, 0, 0, "N/m", &td->stiffness)) return -1;
  snprintf(lab, sizeof lab, "%s density", w);
  if (v[TK_DENSITY] && sy_num(c, v[TK_DENSITY], lab, 0, 0, "kg/m", &td->density)) return -1;
  snprintf(lab, sizeof lab, "%s damping", w);
  if (v[TK_DAMP] && sy_num(c, v[TK_DAMP], lab, 0, 0, "N s/m", &td->damping)) return -1;
  double l0 = sw_tendon_length(td, c->m->x0, c->m->dim); /* m */
  return load_rest(c, v[TK_REST], w, l0, td);
}

int sc_load_tendons(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  if (sy_seq(c, y, "tendons", "a sequence of tendons {waypoints: ..., stiffness: ...}"))
    return -1;
  if (!(m->tendon = sw_calloc((size_t)y->n + 1, sizeof *m->tendon))) return sy_oom(c, y);
  sw_names names = {0};
  int rc = 0;
  for (int k = 0; k < y->n && !rc; k++) {
    m->ntendon = k + 1; /* so that sw_model_free releases what was allocated */
    rc = load_tendon(c, y->kid[k], k, &m->tendon[k], &names);
  }
  sw_names_free(&names);
  return rc;
}
