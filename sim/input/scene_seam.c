/* scene_seam.c — the keys `seams`, `sewing` and `fit` (docs/garments.md):
 *
 *   seams:
 *     - name: left side                       # optional; "seams[k]" otherwise
 *       a: {panel: front, from: 0, to: 24}    # a run of a panel's boundary, vertex to vertex
 *       b: {panel: back, from: 60, to: 84}    # (0-based OBJ vertex indices, either direction)
 *       # or an end by its panel's landmark: {panel: back, from: {corner: 0}, to: {notch: 1}},
 *       # the K-th (0-based) of panels: {back: {corners: [...], notches: [...]}}
 *   sewing: {stiffness: auto, ramp: 0.3, ease_max: 0.1}
 *   fit: {enabled: true, dt: 0.01, damping: 10, gap: 5e-4, speed: 1e-3, max_time: 10,
 *         mode: dynamic, opt_dt: 0.1, opt_growth: 2}
 *
 * A run goes along the panel's boundary (the edges of its faces that only one of its faces
 * holds) from `from` to `to`, the shorter way round.  Each curve's rest length is measured in
 * its panel's (u,v) pattern; the two may differ by at most ease_max of the shorter. */
#include "scene_material.h"
#include "terms.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The defaults of `sewing` and `fit` (docs/garments.md, "Defaults", has the measurements). */
#define SEAM_RAMP 1.0       /* s */
#define SEAM_EASE_MAX 0.1
#define FIT_DT 0.01         /* s */
#define FIT_DAMPING 10.0    /* 1/s */
#define FIT_GAP 5e-4        /* m */
#define FIT_SPEED 1e-3      /* m/s */
#define FIT_MAX_TIME 10.0   /* s */
#define FIT_NEWTON_TOL 1e-2 /* m/s */
#define FIT_OPT_DT 0.1      /* s */
#define FIT_OPT_GROWTH 2.0

/* A panel's boundary: per vertex its (at most two) boundary neighbours and the face of each
 * boundary edge. */
typedef struct boundary {
  int *nb;     /* (nv x 2) neighbours, -1: none */
  int *nbf;    /* (nv x 2) the face of each of those edges */
  int *count;  /* (nv) boundary edges at the vertex */
} boundary;

typedef struct edge_key { int a, b, f; } edge_key;

static int edge_cmp(const void *p, const void *q) {
  const edge_key *x = p, *y = q;
  return x->a != y->a ? (x->a > y->a) - (x->a < y->a) : (x->b > y->b) - (x->b < y->b);
}

/* The boundary of the faces of group g; -1 when out of memory. */
static int panel_boundary(const ctx *c, int g, boundary *bd) {
  const sw_model *m = c->m;
  int ne = 0;
  for (int f = 0; f < m->nf; f++) ne += 3 * (c->fgroup[f] == g);
  edge_key *e = sw_calloc((size_t)ne + 1, sizeof *e);
  bd->nb = sw_calloc(2 * (size_t)m->nv, sizeof(int));
  bd->nbf = sw_calloc(2 * (size_t)m->nv, sizeof(int));
  bd->count = sw_calloc((size_t)m->nv, sizeof(int));
  if (!e || !bd->nb || !bd->nbf || !bd->count) return sw_free(e), -1;
  for (int i = 0; i < 2 * m->nv; i++) bd->nb[i] = -1;
  for (int f = 0, k = 0; f < m->nf; f++)
    for (int i = 0; c->fgroup[f] == g && i < 3; i++, k++) {
      int a = m->face[3 * f + i], b = m->face[3 * f + (i + 1) % 3];
      e[k] = (edge_key){a < b ? a : b, a < b ? b : a, f};
    }
  qsort(e, (size_t)ne, sizeof *e, edge_cmp);
  for (int i = 0; i < ne;) {
    int j = i + 1;
    while (j < ne && e[j].a == e[i].a && e[j].b == e[i].b) j++;
    if (j == i + 1) {
      int v[2] = {e[i].a, e[i].b};
      for (int s = 0; s < 2; s++) {
        int n = bd->count[v[s]]++;
        if (n < 2) bd->nb[2 * v[s] + n] = v[1 - s], bd->nbf[2 * v[s] + n] = e[i].f;
      }
    }
    i = j;
  }
  sw_free(e);
  return 0;
}

static void boundary_free(boundary *bd) {
  sw_free(bd->nb);
  sw_free(bd->nbf);
  sw_free(bd->count);
}

/* Walk from `from` through neighbour slot s until `to` (or back at from): the vertices into
 * path (nv capacity) and their number, the rest length into *len; 0 when `to` is not reached. */
static int walk(const sw_model *m, const boundary *bd, int from, int to, int s, int *path,
                double *len) {
  int prev = from, cur = bd->nb[2 * from + s], f = bd->nbf[2 * from + s], n = 1;
  path[0] = from;
  *len = 0.0;
  while (cur >= 0 && n < m->nv) {
    *len += sw_face_uv_distance(m, f, prev, cur); /* m */
    path[n++] = cur;
    if (cur == to) return n;
    if (cur == from || bd->count[cur] != 2) return 0;
    int k = bd->nb[2 * cur] == prev ? 1 : 0;
    prev = cur, f = bd->nbf[2 * cur + k], cur = bd->nb[2 * cur + k];
  }
  return 0;
}

int sc_find_group(const ctx *c, const ynode *at, const char *w, const char *says,
                  const char *name, int *g) {
  char list[512];
  if (c->fgroup && !c->gnames->n)
    for (int k = 0; k < c->ngroup; k++)
      if (sw_names_add(c->gnames, c->group[k], k) == -2) return sy_oom(c, at);
  if (c->fgroup && (*g = sw_names_find(c->gnames, name)) >= 0) return 0;
  const char *names[16];
  int n = c->ngroup < 16 ? c->ngroup : 16;
  for (int i = 0; i < n; i++) names[i] = c->group[i];
  return sy_fail(c, at, "%s %s '%s', which is no group of the mesh; expected one of: %s", w,
                 says, name, sy_join(names, n, list, sizeof list));
}

static const char *const side_keys[] = {"panel", "from", "to"};
static const char *const mark_keys[] = {"corner", "notch"};
static const char *const mark_lists[] = {"corners", "notches"};

/* The value of key in mapping y, or NULL. */
static const ynode *map_get(const ynode *y, const char *key) {
  for (int p = 0; y && y->kind == Y_MAP && p < y->n / 2; p++)
    if (y->kid[2 * p]->kind == Y_SCALAR && !strcmp(y->kid[2 * p]->text, key))
      return y->kid[2 * p + 1];
  return NULL;
}

/* A seam end: a vertex index, or {corner: K} / {notch: K}, the K-th (0-based) of the panel's
 * `corners` / `notches` in `panels` (scene_material.c has checked those lists). */
static int seam_end(const ctx *c, const ynode *y, const char *lab, const char *panel, int *v) {
  if (y->kind != Y_MAP) return sy_int(c, y, lab, 0, c->m->nv - 1, v);
  const ynode *k[2];
  char l2[SW_NAMESZ + 112];
  if (sy_map(c, y, lab, mark_keys, 2, k)) return -1;
  if (!k[0] == !k[1])
    return sy_fail(c, y, "%s has %s; expected a vertex index, {corner: K} or {notch: K}", lab,
                   k[0] ? "both corner and notch" : "neither corner nor notch");
  int q = k[0] ? 0 : 1, i = 0;
  const ynode *list = map_get(map_get(map_get(c->root, "panels"), panel), mark_lists[q]);
  int n = list ? list->n : 0;
  snprintf(l2, sizeof l2, "%s %s", lab, mark_keys[q]);
  if (!n)
    return sy_fail(c, y, "%s names a %s of panel %s, which lists no %s; expected a vertex "
                   "index, or panels: {%s: {%s: [vertex, ...]}}", lab, mark_keys[q], panel,
                   mark_lists[q], panel, mark_lists[q]);
  if (sy_int(c, k[q], l2, 0, n - 1, &i)) return -1;
  return sy_int(c, list->kid[i], l2, 0, c->m->nv - 1, v);
}

/* One side of a seam: its curve into sm->curve[k], sm->n[k], its rest edge lengths into *el. */
static int load_side(const ctx *c, const ynode *y, const char *w, sw_seam *sm, int k,
                     double **el) {
  sw_model *m = c->m;
  const ynode *v[3];
  const char *name;
  char lab[SW_NAMESZ + 64];
  snprintf(lab, sizeof lab, "%s %s", w, k ? "b" : "a");
  if (sy_map(c, y, lab, side_keys, 3, v) ||
      sy_need(c, y, v[0], lab, "panel", "panel: an OBJ group name") ||
      sy_need(c, y, v[1], lab, "from", "from: a vertex index on the panel's boundary, or "
              "{corner: K} or {notch: K}") ||
      sy_need(c, y, v[2], lab, "to", "to: a vertex index on the panel's boundary, or "
              "{corner: K} or {notch: K}"))
    return -1;
  int g = 0;
  if (sy_str(c, v[0], lab, SW_NAMESZ, &name) || sc_find_group(c, v[0], w, "panel is", name, &g))
    return -1;
  int ends[2];
  for (int e = 0; e < 2; e++) {
    char l2[SW_NAMESZ + 80];
    snprintf(l2, sizeof l2, "%s %s", lab, side_keys[1 + e]);
    if (seam_end(c, v[1 + e], l2, name, ends + e)) return -1;
  }
  snprintf(sm->group[k], sizeof sm->group[k], "%s", name);
  for (int f = 0; f < m->nf; f++) /* the material of the panel's faces */
    if (c->fgroup[f] == g) sm->panel[k] = m->face_mat ? m->face_mat[f] : 0;
  boundary bd;
  memset(&bd, 0, sizeof bd);
  int *path[2] = {sw_calloc((size_t)m->nv, sizeof(int)), sw_calloc((size_t)m->nv, sizeof(int))};
  int rc = 0, n[2] = {0, 0};
  double len[2] = {0.0, 0.0};
  if (!path[0] || !path[1] || panel_boundary(c, g, &bd)) rc = sy_oom(c, y);
  for (int e = 0; !rc && e < 2; e++)
    if (bd.count[ends[e]] != 2)
      rc = sy_fail(c, v[1 + e], "%s %s is vertex %d, which %s panel %s; expected a vertex on the "
                   "panel's boundary (where one boundary curve passes)", lab, side_keys[1 + e],
                   ends[e], bd.count[ends[e]] ? "is where several boundary curves of" :
                   "is not on the boundary of", name);
  if (!rc && ends[0] == ends[1])
    rc = sy_fail(c, v[2], "%s to is vertex %d, the same as from; expected another vertex of "
                 "the boundary", lab, ends[1]);
  for (int s = 0; !rc && s < 2; s++) n[s] = walk(m, &bd, ends[0], ends[1], s, path[s], len + s);
  if (!rc && !n[0] && !n[1])
    rc = sy_fail(c, v[2], "%s to is vertex %d, which the boundary of panel %s does not reach "
                 "from vertex %d; expected a vertex of the same boundary loop", lab, ends[1],
                 name, ends[0]);
  if (!rc) {
    int s = !n[0] || (n[1] && len[1] < len[0]); /* the shorter way round */
    sm->n[k] = n[s];
    sm->curve[k] = path[s], path[s] = NULL;
    if (!(*el = sw_calloc((size_t)n[s], sizeof(double)))) rc = sy_oom(c, y);
    for (int i = 0; !rc && i + 1 < n[s]; i++) { /* each edge in its face's (u,v) */
      int a = sm->curve[k][i], b = sm->curve[k][i + 1];
      int f = bd.nb[2 * a] == b ? bd.nbf[2 * a] : bd.nbf[2 * a + 1];
      (*el)[i] = sw_face_uv_distance(m, f, a, b); /* m */
    }
  }
  sw_free(path[0]);
  sw_free(path[1]);
  boundary_free(&bd);
  return rc;
}

/* Boundary edge (a, b) of a seam's curve against those earlier seams claimed (claim: the seam
 * index + 1 of each claimed edge, in a sorted list). */
typedef struct claim { int a, b, seam; } claim;

static int claim_cmp(const void *p, const void *q) {
  const claim *x = p, *y = q;
  return x->a != y->a ? (x->a > y->a) - (x->a < y->a) : (x->b > y->b) - (x->b < y->b);
}

/* Each boundary edge in one seam's curve at most once. */
static int check_claims(const ctx *c, const ynode *y) {
  const sw_model *m = c->m;
  int ne = 0;
  for (int j = 0; j < m->nseam; j++) ne += m->seam[j].n[0] + m->seam[j].n[1] - 2;
  claim *cl = sw_calloc((size_t)ne + 1, sizeof *cl);
  if (!cl) return sy_oom(c, y);
  int k = 0;
  for (int j = 0; j < m->nseam; j++)
    for (int s = 0; s < 2; s++)
      for (int i = 0; i + 1 < m->seam[j].n[s]; i++) {
        int a = m->seam[j].curve[s][i], b = m->seam[j].curve[s][i + 1];
        cl[k++] = (claim){a < b ? a : b, a < b ? b : a, j};
      }
  qsort(cl, (size_t)ne, sizeof *cl, claim_cmp);
  int rc = 0;
  for (int i = 0; !rc && i + 1 < ne; i++) {
    if (cl[i].a != cl[i + 1].a || cl[i].b != cl[i + 1].b) continue;
    int j0 = cl[i].seam < cl[i + 1].seam ? cl[i].seam : cl[i + 1].seam;
    int j1 = cl[i].seam < cl[i + 1].seam ? cl[i + 1].seam : cl[i].seam;
    const ynode *at = y->kid[j1];
    rc = j0 == j1 ? sy_fail(c, at, "seam '%s' sews the boundary edge (%d, %d) on both of its "
                            "sides; expected two curves that share no edge",
                            m->seam[j1].name, cl[i].a, cl[i].b)
                  : sy_fail(c, at, "seam '%s' claims the boundary edge (%d, %d), which seam "
                            "'%s' already sews; expected each boundary segment in one seam",
                            m->seam[j1].name, cl[i].a, cl[i].b, m->seam[j0].name);
  }
  sw_free(cl);
  return rc;
}

static const char *const seam_keys[] = {"name", "a", "b"};

/* Seam j: its name, both curves, checked (shared vertices, ease) and paired. */
static int load_seam(const ctx *c, const ynode *y, int j) {
  sw_model *m = c->m;
  sw_seam *sm = &m->seam[j];
  const ynode *v[3];
  char w[SW_NAMESZ + 32], idx[32];
  const char *name;
  snprintf(idx, sizeof idx, "seams[%d]", j);
  snprintf(w, sizeof w, "%s", idx);
  if (sy_map(c, y, w, seam_keys, 3, v) ||
      sy_need(c, y, v[1], w, "a", "a: {panel: ..., from: vertex, to: vertex}") ||
      sy_need(c, y, v[2], w, "b", "b: {panel: ..., from: vertex, to: vertex}"))
    return -1;
  if (v[0] && sy_str(c, v[0], "seam name", SW_NAMESZ, &name)) return -1;
  snprintf(sm->name, sizeof sm->name, "%s", v[0] ? name : idx);
  snprintf(w, sizeof w, "seam '%s'", sm->name);
  double *el[2] = {NULL, NULL};
  int rc = load_side(c, v[1], w, sm, 0, el) || load_side(c, v[2], w, sm, 1, el + 1) ? -1 : 0;
  for (int a = 0; !rc && a < sm->n[0]; a++)
    for (int b = 0; !rc && b < sm->n[1]; b++)
      if (sm->curve[0][a] == sm->curve[1][b])
        rc = sy_fail(c, y, "%s: both curves pass through vertex %d; expected two curves with "
                     "no vertex in common (separate pieces, or separate runs of one)", w,
                     sm->curve[0][a]);
  char e[SW_ERRSZ];
  if (!rc && sw_seam_pair(sm, el[0], el[1], e, sizeof e)) rc = sy_fail(c, y, "%s: %s", w, e);
  if (!rc) {
    double la = sm->length[0], lb = sm->length[1], ease = fabs(la - lb) / fmin(la, lb);
    if (!(ease <= m->seam_ease_max))
      rc = sy_fail(c, y, "%s: its curves are %.6g m (a) and %.6g m (b) long in the pattern, "
                   "%.3g %% apart; expected at most the ease limit of %.3g %% (sewing: ease_max)",
                   w, la, lb, 100.0 * ease, 100.0 * m->seam_ease_max);
  }
  sw_free(el[0]);
  sw_free(el[1]);
  return rc;
}

static const char *const sewing_keys[] = {"stiffness", "ramp", "ease_max"};

static int load_sewing(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  const ynode *v[3];
  m->seam_ramp = SEAM_RAMP;
  m->seam_ease_max = SEAM_EASE_MAX;
  m->seam_stiffness = 0.0; /* automatic */
  if (!y) return 0;
  if (sy_map(c, y, "sewing", sewing_keys, 3, v)) return -1;
  if (v[0] && !(v[0]->kind == Y_SCALAR && v[0]->plain && !strcmp(v[0]->text, "auto")) &&
      sy_num(c, v[0], "sewing stiffness", 0, 1, "N/m^2 (or auto)", &m->seam_stiffness))
    return -1;
  if (v[1] && sy_num(c, v[1], "sewing ramp", 0, 0, "s", &m->seam_ramp)) return -1;
  if (v[2] && sy_num(c, v[2], "sewing ease_max", 0, 0, NULL, &m->seam_ease_max)) return -1;
  return 0;
}

static const char *const fit_keys[] = {"enabled",  "dt",         "damping", "gap",
                                       "speed",    "max_time",   "newton_tol", "mode",
                                       "opt_dt",   "opt_growth"};
static const char *const on_off[] = {"false", "true"};
static const char *const fit_modes[] = {"dynamic", "optimize", "settle"}; /* SW_FIT_* */

static int load_fit(const ctx *c, const ynode *y) {
  sw_fit *f = &c->m->fit;
  const ynode *v[10];
  *f = (sw_fit){.on = c->m->nseam > 0, .dt = FIT_DT, .damping = FIT_DAMPING, .gap = FIT_GAP,
                .speed = FIT_SPEED, .max_time = FIT_MAX_TIME, .newton_tol = FIT_NEWTON_TOL,
                .mode = SW_FIT_DYNAMIC, .opt_dt = FIT_OPT_DT, .opt_growth = FIT_OPT_GROWTH};
  if (!y) return 0;
  if (sy_map(c, y, "fit", fit_keys, 10, v)) return -1;
  if (v[0] && sy_choice(c, v[0], "fit enabled", on_off, 2, &f->on)) return -1;
  if (v[1] && sy_num(c, v[1], "fit dt", 0, 1, "s", &f->dt)) return -1;
  if (v[2] && sy_num(c, v[2], "fit damping", 0, 0, "1/s", &f->damping)) return -1;
  if (v[3] && sy_num(c, v[3], "fit gap", 0, 1, "m", &f->gap)) return -1;
  if (v[4] && sy_num(c, v[4], "fit speed", 0, 1, "m/s", &f->speed)) return -1;
  if (v[5] && sy_num(c, v[5], "fit max_time", 0, 1, "s", &f->max_time)) return -1;
  if (v[6] && sy_num(c, v[6], "fit newton_tol", 0, 1, "m/s", &f->newton_tol)) return -1;
  if (v[7] && sy_choice(c, v[7], "fit mode", fit_modes, 3, &f->mode)) return -1;
  if (v[8] && sy_num(c, v[8], "fit opt_dt", 0, 1, "s", &f->opt_dt)) return -1;
  if (v[9] && sy_num(c, v[9], "fit opt_growth", 1, 0, NULL, &f->opt_growth)) return -1;
  if (c->m->dim != 3 && f->on)
    return sy_fail(c, y, "fit is on in a 2D scene; expected fit only with dimension: 3");
  return 0;
}

int sc_load_seams(const ctx *c, const ynode *seams, const ynode *sewing, const ynode *fit) {
  sw_model *m = c->m;
  if (load_sewing(c, sewing)) return -1;
  if (seams) {
    if (sy_seq(c, seams, "seams", "a sequence of {name: ..., a: {...}, b: {...}}")) return -1;
    if (m->dim != 3)
      return sy_fail(c, seams, "seams are given in a 2D scene; expected dimension: 3");
    if (!(m->seam = sw_calloc((size_t)seams->n + 1, sizeof *m->seam))) return sy_oom(c, seams);
    for (int j = 0; j < seams->n; j++) {
      m->nseam = j + 1; /* freed with the model from here on */
      if (load_seam(c, seams->kid[j], j)) return -1;
    }
    if (check_claims(c, seams)) return -1;
  }
  return load_fit(c, fit);
}
