/* mesh_contact.c — the term "mesh_contact": the cloth's triangles kept apart from each other
 * (`contact: {self: true}`) and from the mesh obstacles' (`obstacles: - {mesh: file.obj}`), after Li et al., "Incremental Potential Contact: Intersection-
 * and Inversion-free, Large-Deformation Dynamics", SIGGRAPH 2020 (IPC), with the thickness of
 * Li, Kaufman and Jiang, "Codimensional Incremental Potential Contact", SIGGRAPH 2021 (C-IPC):
 *
 *   E = kappa sum_k w_k m_k(x) b(d_k^2 - xi^2; shat),   shat = (xi + dhat)^2 - xi^2,
 *
 * over every point-triangle and edge-edge pair k of primitives that share no vertex, d_k their
 * distance (closest features), xi the thickness, b IPC's barrier on squared distances
 * (models/distance.c), m_k IPC's mollifier for edge-edge pairs (1 for point-triangle ones) and
 * w_k the mean mass of the pair's vertices, so that, as for obstacles, kappa sets an
 * acceleration and the term does not depend on the mesh's resolution.  Only pairs closer than
 * xi + dhat contribute: a spatial-hash broad phase lists candidates once per Newton update
 * (boxes swept over it), which later evaluations reuse while they cover the positions.
 *
 * The pairs change with the configuration, so their Hessian blocks have no fixed stencil: each
 * evaluation lists them (with their positive semi-definite blocks, 12 x 12) in the run's
 * sw_mcontact workspace, and Newton adds them to the system, growing its pattern when a pair
 * couples two vertices it does not hold yet (solvers/newton.c, docs/contact.md).
 *
 * Mesh obstacles: their vertices follow the cloth's in one numbering (vertex nv + j) and are
 * fixed (at their stated place plus the obstacle's displacement at the evaluation's time): a
 * pair with one of them takes the obstacle's offset as its thickness xi and the mean mass of
 * its cloth vertices as w_k, and no gradient or Hessian entry goes to them.  Pairs of fixed
 * vertices only are skipped, and the cloth's own pairs unless self-contact is on
 * (docs/contact.md, "Mesh obstacles"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cancel.h"
#include "contact.h"
#include "contact_geom.h"
#include "terms.h"
#include "util.h"

/* The candidates' slack, in units of dhat: they are found again only when a vertex leaves its
 * box (swept over the motion they were found for) by more than this.  2 by measurement: the
 * garments' fits 0.83-0.96 times the CPU of 1, larger slacks cost the densely folded drapes
 * more candidates (docs/contact.md, "Self-contact"). */
#ifndef SW_MC_SLACK
#define SW_MC_SLACK 2.0
#endif

/* When the candidates no longer cover a motion, the listing is renewed for the vertices out
 * of their boxes by more than SW_MC_RENEW_MARGIN of the slack alone (renew_candidates) while
 * they are at most nv / SW_MC_RENEW of the cloth's, else made anew; a kept pair's gap is
 * computed again where a bound puts it within SW_MC_REGAP d-hat.  By measurement
 * (docs/contact.md, "Renewed listings"). */
#ifndef SW_MC_RENEW
#define SW_MC_RENEW 16
#endif
#ifndef SW_MC_RENEW_MARGIN
#define SW_MC_RENEW_MARGIN 0.75
#endif
#ifndef SW_MC_REGAP
#define SW_MC_REGAP 2.0
#endif

/* Mesh obstacles of at most this many triangles in all keep each triangle's box (48 bytes a
 * triangle) beside their tree, so a query reads it instead of placing the triangle's corners
 * (docs/contact.md, "What it costs a garment"). */
#ifndef SW_MC_KEEP_BOXES
#define SW_MC_KEEP_BOXES 65536
#endif

/* The term's immutable data: the cloth's edges, and one numbering of the cloth's and the mesh
 * obstacles' vertices (the cloth's nv, then each obstacle's in turn), faces (the cloth's nf,
 * then each obstacle's) and edges (the cloth's ne_cloth, then edge e of obstacle face g as
 * ne_cloth + 3 g + e, joining its vertices e and e + 1 mod 3, the lower first).  The obstacles' vertices and faces
 * are read from the model (sw_obstacle.mesh_x, mesh_face): the term keeps no copy. */
typedef struct mc_param {
  int nvt;           /* cloth and obstacle vertices */
  int ne_cloth;      /* the cloth's edges */
  int *edge;         /* (ne_cloth x 2) */
  int *vface, *eface; /* (nv), (ne_cloth) a cloth face of each cloth vertex and edge (-1: none) */
  int nf;            /* cloth and obstacle faces */
  int nobst;         /* mesh obstacles */
  int *vbase, *fbase; /* (nobst + 1) first vertex and face of obstacle k, counted from nv, nf */
  double *radius;    /* (nobst x 2) largest distance of obstacle k's vertices from its centre
                        and from its rotation axis (0 without rotation), m */
  int moving;        /* 1: a mesh obstacle has keyframes (its tree is refitted per step) */
  sw_bvh tree;       /* the obstacles' faces (bvh.c), fitted to their stated place: the boxes
                        of static obstacles; a workspace refits its own for moving ones */
} mc_param;

/* Where the vertices are: the cloth's x (nv x 3, m) and each mesh obstacle's pose (nobst x 12:
 * the rotation R, row-major, and the place c of its centre, so that a vertex q of its stated
 * place is at R (q - center) + c); pose NULL: every obstacle at its stated place. */
typedef struct mc_place {
  const double *x;
  const double *pose;
} mc_place;

struct sw_mcontact {
  sw_broadphase bp;
  const mc_param *p;
  unsigned char *fixed; /* (nv) 1: pinned (pairs of those and obstacles' only are skipped) */
  double *pose;         /* (6 x nobst x 12) obstacles' poses (mc_place): 0, 1 of the places
                           queried, 2, 3 of the candidates' motion, 4, 5 the tree's fit */
  double *z;            /* (nv x 3) a step's carried start, m */
  int *carrier;         /* (nv) the last mesh obstacle that carried each vertex there, or -1 */
  double *f;            /* (2 x nv x 3) self and obstacle force on each vertex, N */
  sw_mc_pair *pair;     /* (cap) the active pairs of the last evaluation */
  double *block;        /* (cap x 144) their filtered Hessian blocks, when asked for */
  int npair, cap, have_blocks;
  double *vforce;       /* (nv) |contact force| on each vertex at the last diagnostics, N */
  int limit[4];         /* the pair that limited the last CCD (-1: none) */
  /* the candidates: every wanted pair whose boxes, swept over a motion x0 -> x1 and padded by
     (xi + dhat)/2 + slack, overlap; they hold every pair within reach at any positions whose
     vertices each lie within `slack` of their swept box (`covered`) */
  sw_mc_pair *cand;     /* (ncand) kind, vertices and their distance at xref less the pair's
                           thickness (m, in gap) */
  int ncand, capcand, cand_ok;
  double *cbox;         /* (nv x 6) each cloth vertex's box over x0 -> x1, m */
  double *xref;         /* (nv x 3) x0 of the last listing or renewal, m */
  unsigned char *moved; /* (nv) renew's vertices out of their boxes */
  double *blo, *bhi;    /* (nv x 3) renew's boxes' corners, m */
  int renew;            /* 1: listings may be renewed (renew_candidates; the default) */
  long nrenew, nfind;   /* candidate listings renewed for a few vertices, and made anew */
  double *umove;        /* (nv + nobst) how far each cloth vertex, and each obstacle's
                           vertices at most, are from the candidates' x0, m */
  double umax;          /* the largest of umove, m */
  double slack;         /* m */
  double far;           /* a listing's pairs apart by more than this (less their thickness)
                           at x0 stay beyond every evaluation's reach while it is kept, m */
  sw_mfriction *fr;     /* the step's lagged friction (contact.friction > 0), or NULL */
  int nsewn;            /* the seams' sewn vertices (sw_model.sewn_ptr): pairs skipped */
  const int *sewn_ptr, *sewn_idx;
  float *tbox;          /* moving obstacles: the node boxes of p->tree over the motion between
                           poses 4 and 5 */
  double *pbox;         /* moving obstacles of at most SW_MC_KEEP_BOXES triangles: the
                           triangles' boxes over that motion (sw_bvh.pbox), else NULL */
  int pbox_exact;       /* 1: pbox is fitted to the last broad phase's own poses */
  int *near_ptr, *near; /* (nf + 1), (capnear) the obstacle faces whose boxes meet each cloth
                           face's query box in the last broad phase, in the tree's order */
  size_t capnear;
  int tree_fit;         /* 1: tbox is fitted */
  long nrefit;          /* the refits of tbox so far */
  struct mc_dup *dup;   /* (capdup) one query's obstacle vertices or edges, to drop repeats */
  size_t capdup;
  double kscale;        /* the automatic stiffness's factor so far (sw_mcontact_adapt) */
  double gap_min;       /* m: smallest gap of a pair at the last diagnostics (inf: none) */
};

int sw_mesh_contact_on(const sw_model *m) { return m->contact.self || m->nmesh_obstacle > 0; }

/* The thickness xi of pairs against mesh obstacles without self-contact: the largest offset
 * (m); with self-contact, the cloth's thickness. */
static double ref_thickness(const sw_model *m) {
  double xi = m->contact.thickness;
  for (int k = 0; !m->contact.self && k < m->nmesh_obstacle; k++)
    xi = k ? fmax(xi, m->mesh_obstacle[k].offset) : m->mesh_obstacle[k].offset;
  return xi;
}

/* shat = (xi + dhat)^2 - xi^2 for thickness xi, m^2. */
static double shat_of(double xi, double dhat) { return (xi + dhat) * (xi + dhat) - xi * xi; }


double sw_mesh_contact_auto_kappa(const sw_model *m) {
  const sw_contact *c = &m->contact;
  double g = 0.0, db, xi = ref_thickness(m);
  for (int a = 0; a < m->dim; a++) g += m->gravity[a] * m->gravity[a];
  g = m->has_gravity && g > 0.0 ? sqrt(g) : 9.81; /* m/s^2 */
  double d = xi + 0.5 * c->dhat;  /* the resting distance, m */
  sw_barrier(d * d - xi * xi, shat_of(xi, c->dhat), &db, NULL);
  return g / (2.0 * d * fabs(db)); /* 1/(s^2 m^2): kappa w |b'| |grad d^2| = w g */
}

/* The largest thickness of any pair (m): what the broad phase must reach beyond dhat. */
static double max_thickness(const sw_model *m) {
  double xi = m->contact.self ? m->contact.thickness : 0.0;
  for (int k = 0; k < m->nmesh_obstacle; k++) xi = fmax(xi, m->mesh_obstacle[k].offset);
  return xi;
}

/* The mesh obstacle of vertex v (< 0: a cloth vertex); a scan: scenes have few obstacles. */
static int owner_of(const sw_model *m, const mc_param *p, int v) {
  if (v < m->nv) return -1;
  int k = 0;
  while (v - m->nv >= p->vbase[k + 1]) k++;
  return k;
}

/* The mesh obstacle of face f >= nf (obstacle face f - nf). */
static int face_owner(const sw_model *m, const mc_param *p, int f) {
  int k = 0;
  while (f - m->nf >= p->fbase[k + 1]) k++;
  return k;
}

/* The vertices of face f (the cloth's, or an obstacle's) in the term's numbering. */
static void face_vertices(const sw_model *m, const mc_param *p, int f, int *v) {
  if (f < m->nf) {
    for (int c = 0; c < 3; c++) v[c] = m->face[3 * (size_t)f + c];
    return;
  }
  int k = face_owner(m, p, f);
  const int *q = m->mesh_obstacle[k].mesh_face + 3 * (size_t)(f - m->nf - p->fbase[k]);
  for (int c = 0; c < 3; c++) v[c] = m->nv + p->vbase[k] + q[c];
}

/* The vertices of edge e (the cloth's, or ne_cloth + 3 g + j: edge j of obstacle face g). */
static void edge_vertices(const sw_model *m, const mc_param *p, int e, int *v) {
  if (e < p->ne_cloth) {
    v[0] = p->edge[2 * (size_t)e], v[1] = p->edge[2 * (size_t)e + 1];
    return;
  }
  int f[3], j = (e - p->ne_cloth) % 3;
  face_vertices(m, p, m->nf + (e - p->ne_cloth) / 3, f);
  int a = f[j], b = f[(j + 1) % 3];
  v[0] = a < b ? a : b, v[1] = a < b ? b : a; /* the lower first, as the cloth's */
}

/* Vertex v's stated place (an obstacle's) or rest place (the cloth's x0), m. */
static const double *rest_of(const sw_model *m, const mc_param *p, int v) {
  if (v < m->nv) return m->x0 + 3 * (size_t)v;
  int k = owner_of(m, p, v);
  return m->mesh_obstacle[k].mesh_x + 3 * (size_t)(v - m->nv - p->vbase[k]);
}

/* Vertex v at the place x into q (3), m. */
static void vertex_at(const sw_model *m, const mc_param *p, const mc_place *x, int v, double *q) {
  if (v < m->nv || !x->pose) {
    memcpy(q, v < m->nv ? x->x + 3 * (size_t)v : rest_of(m, p, v), 3 * sizeof(double));
    return;
  }
  int k = owner_of(m, p, v);
  const double *r = rest_of(m, p, v), *o = m->mesh_obstacle[k].center, *R = x->pose + 12 * k;
  double d[3] = {r[0] - o[0], r[1] - o[1], r[2] - o[2]};
  for (int a = 0; a < 3; a++) /* R (q - center) + c, m */
    q[a] = R[3 * a] * d[0] + R[3 * a + 1] * d[1] + R[3 * a + 2] * d[2] + R[9 + a];
}

/* A pair's thickness: a mesh obstacle's offset when it involves one, else the cloth's, m. */
static double pair_xi(const sw_model *m, const mc_param *p, const int *v) {
  for (int k = 0; k < 4; k++)
    if (v[k] >= m->nv) return m->mesh_obstacle[owner_of(m, p, v[k])].offset;
  return m->contact.thickness;
}

/* Whether the pair is one the term keeps: a cloth vertex and an obstacle's, or (with
 * self-contact) the cloth's only. */
static int pair_wanted(const sw_model *m, const int *v) {
  int nc = 0;
  for (int k = 0; k < 4; k++) nc += v[k] < m->nv;
  return nc == 4 ? m->contact.self : nc > 0;
}

/* ------------------------------------------------------------------ workspace */

sw_mcontact *sw_mcontact_new(const sw_model *m) {
  const mc_param *p = NULL;
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].ops->kind, "mesh_contact")) p = m->term[k].param;
  if (!p) return NULL;
  sw_mcontact *mc = sw_calloc(1, sizeof *mc);
  if (!mc) return NULL;
  sw_broadphase_init(&mc->bp);
  mc->p = p;
  size_t nv = (size_t)m->nv, no = (size_t)p->nobst;
  mc->fixed = sw_calloc(nv + 1, 1);
  mc->pose = sw_calloc(6 * 12 * no + 1, sizeof(double));
  mc->z = sw_calloc(3 * nv + 1, sizeof(double));
  mc->carrier = sw_calloc(nv + 1, sizeof(int));
  mc->f = sw_calloc(6 * nv + 1, sizeof(double));
  mc->vforce = sw_calloc(nv + 1, sizeof(double));
  mc->cbox = sw_calloc(6 * nv + 1, sizeof(double));
  mc->xref = sw_calloc(3 * nv + 1, sizeof(double));
  mc->moved = sw_calloc(nv + 1, 1);
  mc->blo = sw_calloc(3 * nv + 1, sizeof(double));
  mc->bhi = sw_calloc(3 * nv + 1, sizeof(double));
  mc->umove = sw_calloc(nv + no + 1, sizeof(double));
  mc->slack = SW_MC_SLACK * m->contact.dhat;
  if (p->nvt > m->nv && !(mc->near_ptr = sw_calloc((size_t)m->nf + 1, sizeof(int))))
    return sw_mcontact_free(mc), NULL;
  if (p->moving && !(mc->tbox = sw_calloc(6 * (size_t)p->tree.nnode + 1, sizeof(float))))
    return sw_mcontact_free(mc), NULL;
  if (p->moving && p->tree.n <= SW_MC_KEEP_BOXES &&
      !(mc->pbox = sw_calloc(6 * (size_t)p->tree.n + 1, sizeof(double))))
    return sw_mcontact_free(mc), NULL;
  if (!mc->fixed || !mc->pose || !mc->z || !mc->carrier || !mc->f || !mc->vforce ||
      !mc->cbox || !mc->xref || !mc->moved || !mc->blo || !mc->bhi || !mc->umove)
    return sw_mcontact_free(mc), NULL;
  for (int i = 0; i < m->nv; i++) mc->fixed[i] = (unsigned char)m->pinned[i];
  if (sw_contact_friction_on(m) && !(mc->fr = sw_mfriction_new()))
    return sw_mcontact_free(mc), NULL;
  mc->nsewn = m->nv, mc->sewn_ptr = m->sewn_ptr, mc->sewn_idx = m->sewn_idx;
  mc->kscale = 1.0;
  mc->gap_min = INFINITY;
  mc->renew = 1;
  return mc;
}

void sw_mcontact_free(sw_mcontact *mc) {
  if (!mc) return;
  sw_broadphase_free(&mc->bp);
  sw_free(mc->fixed);
  sw_free(mc->pose);
  sw_free(mc->z);
  sw_free(mc->carrier);
  sw_free(mc->f);
  sw_free(mc->pair);
  sw_free(mc->block);
  sw_free(mc->vforce);
  sw_free(mc->cand);
  sw_free(mc->cbox);
  sw_free(mc->xref);
  sw_free(mc->moved);
  sw_free(mc->blo);
  sw_free(mc->bhi);
  sw_free(mc->umove);
  sw_mfriction_free(mc->fr);
  sw_free(mc->tbox);
  sw_free(mc->pbox);
  sw_free(mc->near_ptr);
  sw_free(mc->near);
  sw_free(mc->dup);
  sw_free(mc);
}

int sw_mcontact_pairs(const sw_mcontact *mc, const sw_mc_pair **pair, const double **block) {
  if (!mc) return 0;
  if (pair) *pair = mc->pair;
  if (block) *block = mc->have_blocks ? mc->block : NULL;
  return mc->npair;
}

/* Room for one more pair (and its block); -1 when out of memory. */
static int reserve_pair(sw_mcontact *mc) {
  if (mc->npair < mc->cap) return 0;
  int cap = mc->cap + mc->cap / 2 + 64;
  sw_mc_pair *p = sw_realloc(mc->pair, (size_t)cap, sizeof *p);
  if (!p) return -1;
  mc->pair = p;
  double *b = sw_realloc(mc->block, (size_t)cap * 144, sizeof(double));
  if (!b) return -1;
  mc->block = b;
  mc->cap = cap;
  return 0;
}

/* Whether a mesh obstacle moves between times t0 and t1. */
static int obstacles_move(const sw_model *m, double t0, double t1) {
  for (int k = 0; k < m->nmesh_obstacle; k++)
    if (sw_obstacle_moves(&m->mesh_obstacle[k], t0, t1)) return 1;
  return 0;
}

/* The place of the cloth x (nv x 3) and of the mesh obstacles at time t, the poses kept in
 * workspace slot `slot` (static obstacles: at their stated place, no pose). */
static mc_place positions(const sw_model *m, sw_mcontact *mc, const double *x, double t,
                          int slot) {
  mc_place pl = {x, NULL};
  if (!mc->p->moving) return pl;
  double *pose = mc->pose + 12 * (size_t)slot * mc->p->nobst;
  for (int k = 0; k < mc->p->nobst; k++)
    sw_obstacle_pose(&m->mesh_obstacle[k], t, pose + 12 * k, pose + 12 * k + 9);
  pl.pose = pose;
  return pl;
}

/* The cloth's places into the broad phase's input (its own pairs) with the given inflation. */
static sw_bp_input bp_input(const sw_model *m, const sw_mcontact *mc, const mc_place *x0,
                            const mc_place *x1, double inflate) {
  sw_bp_input in = {.nv = m->nv, .x0 = x0->x, .x1 = x1->x, .ne = mc->p->ne_cloth,
                    .edge = mc->p->edge, .nf = m->nf, .face = m->face, .fixed = mc->fixed,
                    .inflate = inflate, .nsewn = mc->nsewn, .sewn_ptr = mc->sewn_ptr,
                    .sewn_idx = mc->sewn_idx};
  return in;
}

/* ------------------------------------------------------------------ broad phase */

/* The box over x0 -> x1 of vertices v (n) into b (lo[3], hi[3]), m. */
typedef struct tree_ctx {
  const sw_model *m;
  const mc_param *p;
  const mc_place *x0, *x1;
} tree_ctx;

static void vertices_box(const tree_ctx *c, const int *v, int n, double *b) {
  for (int a = 0; a < 3; a++) b[a] = INFINITY, b[3 + a] = -INFINITY;
  /* an obstacle's vertex at both ends when no pose moves it: placed once */
  const int once = c->x1 == c->x0 || (!c->x0->pose && !c->x1->pose);
  for (int j = 0; j < n; j++) {
    double p[3], q[3];
    vertex_at(c->m, c->p, c->x0, v[j], p);
    if (once && v[j] >= c->m->nv) memcpy(q, p, sizeof q);
    else vertex_at(c->m, c->p, c->x1, v[j], q);
    for (int a = 0; a < 3; a++) { /* finite: comparisons, not fmin's calls */
      double lo = p[a] < q[a] ? p[a] : q[a], hi = p[a] < q[a] ? q[a] : p[a];
      b[a] = lo < b[a] ? lo : b[a], b[3 + a] = hi > b[3 + a] ? hi : b[3 + a];
    }
  }
}

/* The tree's primitive i: obstacle face nf + i over x0 -> x1. */
static void tree_box(const void *arg, int i, double *b) {
  const tree_ctx *c = arg;
  int v[3];
  face_vertices(c->m, c->p, c->m->nf + i, v);
  vertices_box(c, v, 3, b);
}

/* The tree with the workspace's node boxes (moving obstacles) or its own (static ones). */
static sw_bvh tree_view(const sw_mcontact *mc) {
  sw_bvh t = mc->p->tree;
  if (mc->p->moving) t.box = mc->tbox, t.pbox = mc->pbox_exact ? mc->pbox : NULL;
  return t;
}

/* Whether pose set a (nobst x 12) is one of b's two. */
static int pose_in(const double *a, const double *b, int nobst) {
  size_t n = 12 * (size_t)nobst * sizeof(double);
  return !memcmp(a, b, n) || !memcmp(a, b + 12 * (size_t)nobst, n);
}

/* Moving obstacles: the workspace's node boxes over the obstacles' motion x0 -> x1, refitted
 * (one bottom-up pass over the body) only when a pose is not one of the last fit's ends: the
 * boxes of a fit over a step's motion hold every place queried at its start or end. */
static void fit_tree(const sw_model *m, sw_mcontact *mc, const mc_place *x0, const mc_place *x1) {
  const mc_param *p = mc->p;
  if (!p->moving) return;
  double *fit = mc->pose + 12 * 4 * (size_t)p->nobst;
  size_t np = 12 * (size_t)p->nobst * sizeof(double);
  if (mc->tree_fit && pose_in(x0->pose, fit, p->nobst) && pose_in(x1->pose, fit, p->nobst)) {
    /* the kept triangle boxes are the query's own only at the fit's own two ends */
    mc->pbox_exact = !memcmp(x0->pose, fit, np) && !memcmp(x1->pose, fit + 12 * p->nobst, np);
    return;
  }
  tree_ctx c = {m, p, x0, x1};
  mc->pbox_exact = 1;
  sw_bvh t = tree_view(mc);
  sw_bvh_refit(&t, tree_box, &c);
  memcpy(fit, x0->pose, 12 * (size_t)p->nobst * sizeof(double));
  memcpy(fit + 12 * (size_t)p->nobst, x1->pose, 12 * (size_t)p->nobst * sizeof(double));
  mc->tree_fit = 1;
  mc->nrefit++;
}

/* One query's obstacle primitives (vertices, or edges by their two vertices) with their codes,
 * sorted to keep each once: a vertex or an edge is in several faces of the tree. */
struct mc_dup {
  unsigned long long key; /* vertex, or (lower vertex << 32) + higher vertex */
  int code;               /* the vertex, or the edge's code (mc_param) */
};

/* A query of one cloth primitive against the tree: pairs (cloth, obstacle) or, for a cloth
 * face against the obstacles' vertices, (vertex, face), appended to *pair (capacity *cap, n).
 * what: 0 the obstacles' vertices, 1 their edges, 2 their faces. */
typedef struct hit_arg {
  sw_mcontact *mc;
  const tree_ctx *c;
  int **pair, *n;
  size_t *cap;
  int what, cloth, vertex_first;
  const double *b; /* the query's box */
  size_t ndup;
} hit_arg;

static int append_pair(hit_arg *h, int o) {
  if ((size_t)2 * (*h->n + 1) > *h->cap) {
    size_t cap = 2 * ((size_t)*h->n + 1) * 3 / 2 + 32;
    int *q = realloc(*h->pair, cap * sizeof(int)); /* sw_broadphase_free frees it */
    if (!q) return -1;
    *h->pair = q, *h->cap = cap;
  }
  (*h->pair)[2 * *h->n] = h->vertex_first ? o : h->cloth;
  (*h->pair)[2 * *h->n + 1] = h->vertex_first ? h->cloth : o;
  (*h->n)++;
  return 0;
}

static int boxes_meet(const double *p, const double *q) {
  for (int a = 0; a < 3; a++)
    if (!(p[a] <= q[3 + a] && q[a] <= p[3 + a])) return 0;
  return 1;
}

/* Obstacle face i whose box meets the query's: the face itself, or its vertices or edges whose
 * boxes meet the query's into mc->dup. */
static int hit_face(void *arg, int i) {
  hit_arg *h = arg;
  if (h->what == 2) return append_pair(h, h->c->m->nf + i);
  sw_mcontact *mc = h->mc;
  if (mc->capdup < h->ndup + 3) {
    size_t cap = 2 * mc->capdup + 64;
    struct mc_dup *q = sw_realloc(mc->dup, cap, sizeof *q);
    if (!q) return -1;
    mc->dup = q, mc->capdup = cap;
  }
  int f[3];
  double cb[3][6]; /* each corner's box over x0 -> x1: a vertex's, or two joined an edge's */
  face_vertices(h->c->m, h->c->p, h->c->m->nf + i, f);
  for (int j = 0; j < 3; j++) vertices_box(h->c, f + j, 1, cb[j]);
  for (int j = 0; j < 3; j++) {
    int v[2] = {f[j], f[(j + 1) % 3]}, n = h->what + 1;
    double b[6];
    for (int a = 0; a < 6; a++) {
      double p = cb[j][a], q = cb[(j + 1) % 3][a];
      b[a] = n == 1 ? p : a < 3 ? (p < q ? p : q) : (p > q ? p : q);
    }
    if (!boxes_meet(b, h->b)) continue;
    unsigned long long lo = (unsigned)(v[0] < v[1] || n == 1 ? v[0] : v[1]), hi = (unsigned)(v[0] < v[1] ? v[1] : v[0]);
    struct mc_dup *d = &mc->dup[h->ndup++];
    d->key = n == 1 ? lo : lo << 32 | hi;
    d->code = n == 1 ? v[0] : h->c->p->ne_cloth + 3 * i + j;
  }
  return 0;
}

static int dup_order(const void *a, const void *b) {
  const struct mc_dup *p = a, *q = b;
  return p->key != q->key ? (p->key < q->key ? -1 : 1) : (p->code > q->code) - (p->code < q->code);
}

/* Sort a query's n obstacle primitives by dup_order: by insertion when they are few (a
 * cloth primitive meets a handful of faces), else qsort (d NULL when n is 0). */
static void sort_dup(struct mc_dup *d, size_t n) {
  if (n > 32) {
    qsort(d, n, sizeof *d, dup_order);
    return;
  }
  for (size_t i = 1; i < n; i++) {
    struct mc_dup e = d[i];
    size_t j = i;
    for (; j > 0 && dup_order(&d[j - 1], &e) > 0; j--) d[j] = d[j - 1];
    d[j] = e;
  }
}

/* The box over x0 -> x1 of the cloth vertices v (n) grown by r (m); 0 when one is pinned
 * and all are (nothing to pair), or not finite (-1). */
static int cloth_box(const sw_mcontact *mc, const sw_bp_input *in, const int *v, int n,
                     double r, double *b) {
  int fixed = 1;
  for (int a = 0; a < 3; a++) b[a] = INFINITY, b[3 + a] = -INFINITY;
  for (int j = 0; j < n; j++) {
    fixed = fixed && mc->fixed[v[j]];
    for (int a = 0; a < 3; a++) {
      double p = in->x0[3 * (size_t)v[j] + a], q = in->x1[3 * (size_t)v[j] + a];
      if (!isfinite(p) || !isfinite(q)) return -1;
      b[a] = fmin(b[a], fmin(p, q) - r), b[3 + a] = fmax(b[3 + a], fmax(p, q) + r);
    }
  }
  return !fixed;
}

/* Obstacle face i whose box meets the query's into a near list (int *). */
typedef struct near_arg {
  sw_mcontact *mc;
  int n;
} near_arg;

static int add_near(void *arg, int i) {
  near_arg *a = arg;
  sw_mcontact *mc = a->mc;
  if ((size_t)a->n == mc->capnear) {
    size_t cap = 2 * mc->capnear + 256;
    int *q = sw_realloc(mc->near, cap, sizeof(int));
    if (!q) return -1;
    mc->near = q, mc->capnear = cap;
  }
  mc->near[a->n++] = i;
  return 0;
}

/* The near lists: the tree queried once with each cloth face's swept box grown by r (m); a
 * face whose vertices are all pinned gets none.  -1 when out of memory or not finite. */
static int near_faces(sw_mcontact *mc, const sw_bp_input *in, const tree_ctx *c, double r) {
  sw_bvh t = tree_view(mc);
  near_arg a = {mc, 0};
  for (int f = 0; f < in->nf; f++) {
    double b[6];
    int rc = cloth_box(mc, in, in->face + 3 * (size_t)f, 3, r, b);
    mc->near_ptr[f] = a.n;
    if (rc < 0) return -1;
    if (rc && sw_bvh_query(&t, b, tree_box, c, add_near, &a)) return -1;
  }
  mc->near_ptr[in->nf] = a.n;
  return 0;
}

/* hit_face on every obstacle face whose box meets the query's box h->b: the faces of cloth
 * face f's near list (its query box holds h->b, so none is missed and, the list being in the
 * tree's order, they come in the order a query of the tree gives), all of them when h->b is
 * f's own box (`own`); the tree's when f < 0 (a cloth vertex or edge in no face). */
static int visit_faces(sw_mcontact *mc, hit_arg *h, int f, int own) {
  sw_bvh t = tree_view(mc);
  if (f < 0) return sw_bvh_query(&t, h->b, tree_box, h->c, hit_face, h);
  for (int k = mc->near_ptr[f]; k < mc->near_ptr[f + 1]; k++) {
    int i = mc->near[k];
    double s[6];
    const double *b = t.pbox ? t.pbox + 6 * (size_t)i : s;
    if (!own && (t.pbox || (tree_box(h->c, i, s), 1)) && !boxes_meet(b, h->b)) continue;
    int rc = hit_face(h, i);
    if (rc) return rc;
  }
  return 0;
}

/* Each of the cloth's n primitives of `per` vertices (at idx + per i) against the obstacles'
 * primitives h->what, through the near list of its face face[i] (face NULL: the primitive is
 * that face); -1 when out of memory or not finite. */
static int query_tree(sw_mcontact *mc, const sw_bp_input *in, const int *idx, int per, int n,
                      const int *face, const unsigned char *mark, hit_arg *h) {
  for (int i = 0; i < n; i++) {
    double b[6];
    int v = i, hit = !mark;
    const int *iv = idx ? idx + per * (size_t)i : &v;
    for (int j = 0; !hit && j < per; j++) hit = mark[iv[j]];
    if (!hit) continue;
    int rc = cloth_box(mc, in, iv, per, 2.0 * in->inflate, b);
    if (rc < 0) return -1;
    if (!rc) continue;
    h->cloth = i, h->b = b, h->ndup = 0;
    /* marked: the tree itself (the faces' near lists are of the last full listing's boxes) */
    if (visit_faces(mc, h, mark ? -1 : face ? face[i] : i, !face && !mark)) return -1;
    if (h->what == 2) continue;
    sort_dup(mc->dup, h->ndup);
    for (size_t k = 0; k < h->ndup; k++)
      if ((k == 0 || mc->dup[k].key != mc->dup[k - 1].key) && append_pair(h, mc->dup[k].code))
        return -1;
  }
  return 0;
}

/* The pairs `want` of the cloth's primitives with the obstacles' tree appended to mc->bp's
 * lists: every primitive through its face's near list (near_faces first), or with mark those
 * with a marked vertex alone, each by a query of the tree itself; -1 as query_tree. */
static int tree_pairs(const sw_model *m, sw_mcontact *mc, const sw_bp_input *in,
                      const tree_ctx *c, const unsigned char *mark, int want) {
  sw_broadphase *bp = &mc->bp;
  const mc_param *p = mc->p;
  hit_arg pt = {mc, c, &bp->pt, &bp->npt, &bp->cap_pt, 2, 0, 0, NULL, 0};
  hit_arg tp = {mc, c, &bp->pt, &bp->npt, &bp->cap_pt, 0, 0, 1, NULL, 0};
  hit_arg ee = {mc, c, &bp->ee, &bp->nee, &bp->cap_ee, 1, 0, 0, NULL, 0};
  hit_arg ff = {mc, c, &bp->ff, &bp->nff, &bp->cap_ff, 2, 0, 0, NULL, 0};
  int rc = 0;
  if (want & SW_BP_PT)
    rc = query_tree(mc, in, NULL, 1, m->nv, mark ? NULL : p->vface, mark, &pt) ||
         query_tree(mc, in, m->face, 3, m->nf, NULL, mark, &tp);
  if (!rc && (want & SW_BP_EE))
    rc = query_tree(mc, in, p->edge, 2, p->ne_cloth, mark ? NULL : p->eface, mark, &ee);
  if (!rc && (want & SW_BP_FF)) rc = query_tree(mc, in, m->face, 3, m->nf, NULL, mark, &ff);
  return rc ? -1 : 0;
}

/* The term's broad phase into mc->bp: the cloth's own pairs from the spatial hash
 * (sw_broadphase_query, with self-contact only), its pairs with the obstacles from queries of
 * the cloth's swept boxes in the obstacles' tree (the vertices and edges of the faces found,
 * each once), so the cost grows with the cloth and the part of a body near it.  -1 when the
 * places are not finite or out of memory. */
static int broad_phase(const sw_model *m, sw_mcontact *mc, const mc_place *x0,
                       const mc_place *x1, double inflate, int want) {
  sw_broadphase *bp = &mc->bp;
  sw_bp_input in = bp_input(m, mc, x0, x1, inflate);
  bp->npt = bp->nee = bp->nff = 0;
  if (m->contact.self && (want & (SW_BP_PT | SW_BP_EE)) &&
      sw_broadphase_query(bp, &in, want & (SW_BP_PT | SW_BP_EE)))
    return -1;
  if (mc->p->nvt == m->nv) return 0;
  fit_tree(m, mc, x0, x1);
  tree_ctx c = {m, mc->p, x0, x1};
  int rc = near_faces(mc, &in, &c, 2.0 * inflate) || tree_pairs(m, mc, &in, &c, NULL, want);
  if (rc) bp->npt = bp->nee = bp->nff = 0;
  return rc ? -1 : 0;
}

/* The vertices of broad-phase pair q of kind k (SW_MC_PT: vertex, face; SW_MC_EE: edge,
 * edge) into v[4]. */
static void pair_vertices(const sw_model *m, const sw_mcontact *mc, int kind, const int *q, int *v) {
  if (kind == SW_MC_PT) {
    v[0] = q[0];
    face_vertices(m, mc->p, q[1], v + 1);
  } else {
    edge_vertices(m, mc->p, q[0], v);
    edge_vertices(m, mc->p, q[1], v + 2);
  }
}

/* The places of a pair's vertices v (4) at x into p (12), m. */
static void gather(const sw_model *m, const sw_mcontact *mc, const mc_place *x, const int *v,
                   double *p) {
  for (int k = 0; k < 4; k++) vertex_at(m, mc->p, x, v[k], p + 3 * k);
}

/* The rest positions of a pair's vertices (the cloth's x0, the obstacles' stated place). */
static void gather_rest(const sw_model *m, const mc_param *p, const int *v, double *r) {
  for (int k = 0; k < 4; k++) memcpy(r + 3 * k, rest_of(m, p, v[k]), 3 * sizeof(double));
}

/* Call visit(m, mc, kind, v, arg) on every wanted pair of the last broad-phase query; stops at
 * the first nonzero return and returns it. */
typedef int (*pair_visit)(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg);
static int each_pair(const sw_model *m, sw_mcontact *mc, pair_visit visit, void *arg) {
  for (int kind = SW_MC_PT; kind <= SW_MC_EE; kind++) {
    const int *q = kind == SW_MC_PT ? mc->bp.pt : mc->bp.ee;
    int n = kind == SW_MC_PT ? mc->bp.npt : mc->bp.nee;
    for (int k = 0; k < n; k++) {
      int v[4];
      pair_vertices(m, mc, kind, q + 2 * k, v);
      if (!pair_wanted(m, v)) continue;
      int rc = visit(m, mc, kind, v, arg);
      if (rc) return rc;
    }
  }
  return 0;
}

/* ------------------------------------------------------------------- candidates */

/* How far any vertex of obstacle k may be between its poses a and b (12 each): R (q - center)
 * + c differs by (Ra - Rb)(q - center) + ca - cb, at most |ca - cb| + |Ra - Rb|_F radius, m. */
static double pose_gap(const mc_param *p, int k, const double *a, const double *b) {
  double r = 0.0, c = 0.0;
  a += 12 * k, b += 12 * k;
  for (int i = 0; i < 9; i++) r += (a[i] - b[i]) * (a[i] - b[i]);
  for (int i = 9; i < 12; i++) c += (a[i] - b[i]) * (a[i] - b[i]);
  return sqrt(c) + sqrt(r) * p->radius[2 * k];
}

/* Whether every vertex at x lies within mc->slack of its box over the candidates' motion (the
 * cloth's in mc->cbox; an obstacle's vertices when its pose is within slack of the motion's
 * start or end pose): then the candidates hold every pair within reach at x. */
static int covered(const sw_model *m, const sw_mcontact *mc, const mc_place *x) {
  if (!mc->cand_ok) return 0;
  const double h = mc->slack;
  for (int i = 0; i < m->nv; i++) {
    const double *b = mc->cbox + 6 * (size_t)i, *p = x->x + 3 * (size_t)i;
    for (int a = 0; a < 3; a++)
      if (!(p[a] >= b[a] - h && p[a] <= b[3 + a] + h)) return 0;
  }
  const double *a = mc->pose + 24 * (size_t)mc->p->nobst, *b = a + 12 * (size_t)mc->p->nobst;
  for (int k = 0; x->pose && k < mc->p->nobst; k++)
    if (!(fmin(pose_gap(mc->p, k, x->pose, a), pose_gap(mc->p, k, x->pose, b)) <= h)) return 0;
  return 1;
}

/* The distance of a pair's primitives at p (12), m. */
static double pair_d(int kind, const double *p) {
  return sqrt(kind == SW_MC_PT ? sw_d2_point_triangle(p, p + 3, p + 6, p + 9, NULL, NULL)
                               : sw_d2_edge_edge(p, p + 3, p + 6, p + 9, NULL, NULL));
}

/* A pair's distance at x less its thickness, m. */
static double pair_gap(const sw_model *m, const sw_mcontact *mc, int kind, const int *v,
                       const mc_place *x) {
  double p[12];
  gather(m, mc, x, v, p);
  return pair_d(kind, p) - pair_xi(m, mc->p, v);
}

/* Append the pair to the candidates with its distance at arg (an mc_place) less its
 * thickness, unless a bound puts it farther than mc->far; -1 when out of memory. */
static int add_candidate(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  double p[12], xi = pair_xi(m, mc->p, v);
  gather(m, mc, arg, v, p);
  /* 1e-9 m: more than the bound's round-off, far below the distances compared */
  if (sw_pair_apart(kind == SW_MC_EE, p, mc->far + xi + 1e-9)) return 0;
  if (mc->ncand == mc->capcand) {
    int cap = mc->capcand + mc->capcand / 2 + 256;
    sw_mc_pair *c = sw_realloc(mc->cand, (size_t)cap, sizeof *c);
    if (!c) return -1;
    mc->cand = c, mc->capcand = cap;
  }
  sw_mc_pair *c = &mc->cand[mc->ncand++];
  c->kind = kind;
  memcpy(c->v, v, sizeof c->v);
  c->gap = pair_d(kind, p) - xi;
  return 0;
}

/* mc->far for the candidates over x0 -> x1: while they are kept every vertex lies within the
 * slack of its box over that motion on each axis, so within |x1 - x0| + sqrt(3) slack of x0
 * (an obstacle's within the pose gap of its two poses plus the slack), and a pair comes at most
 * twice that closer than at x0; no evaluation reaches farther than d-hat (each_candidate). */
static double far_reach(const sw_model *m, const sw_mcontact *mc, const mc_place *x0,
                        const mc_place *x1) {
  double u = 0.0;
  for (int i = 0; i < m->nv; i++) {
    const double *a = x0->x + 3 * (size_t)i, *b = x1->x + 3 * (size_t)i;
    u = fmax(u, (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                    (b[2] - a[2]) * (b[2] - a[2]));
  }
  u = sqrt(u) + sqrt(3.0) * mc->slack;
  for (int k = 0; x0->pose && x1->pose && k < mc->p->nobst; k++)
    u = fmax(u, pose_gap(mc->p, k, x0->pose, x1->pose) + mc->slack);
  return m->contact.dhat + 2.0 * u;
}

/* mc->far from the boxes and xref (renew_candidates): while the listing is kept every cloth
 * vertex lies within the slack of its box, so within the farthest corner of that box padded by
 * the slack from its xref, and a pair comes at most twice the largest of those closer. */
static double far_boxes(const sw_model *m, const sw_mcontact *mc) {
  double u = 0.0, h = mc->slack;
  for (int i = 0; i < m->nv; i++) {
    const double *b = mc->cbox + 6 * (size_t)i, *r = mc->xref + 3 * (size_t)i;
    double s = 0.0;
    for (int a = 0; a < 3; a++) {
      double d = fmax(r[a] - (b[a] - h), b[3 + a] + h - r[a]);
      s += d * d;
    }
    u = fmax(u, s);
  }
  return m->contact.dhat + 2.0 * sqrt(u);
}

/* The candidates over the motion x0 -> x1 (x1 == x0 for places at rest); -1 when the broad
 * phase fails (places not finite, or out of memory). */
static int find_candidates(const sw_model *m, sw_mcontact *mc, const mc_place *x0,
                           const mc_place *x1) {
  mc->cand_ok = 0;
  mc->ncand = 0;
  mc->nfind++;
  double reach = 0.5 * (max_thickness(m) + m->contact.dhat) + mc->slack;
  mc->far = far_reach(m, mc, x0, x1);
  if (broad_phase(m, mc, x0, x1, reach, SW_BP_PT | SW_BP_EE) ||
      each_pair(m, mc, add_candidate, (void *)x0))
    return -1;
  for (size_t i = 0; i < 3 * (size_t)m->nv; i++) {
    double *bi = mc->cbox + 6 * (i / 3) + i % 3, p = x0->x[i], q = x1->x[i];
    bi[0] = p < q ? p : q, bi[3] = p < q ? q : p;
  }
  memcpy(mc->xref, x0->x, 3 * (size_t)m->nv * sizeof(double));
  size_t np = 12 * (size_t)mc->p->nobst;
  if (x0->pose) memcpy(mc->pose + 2 * np, x0->pose, np * sizeof(double));
  if (x1->pose) memcpy(mc->pose + 3 * np, x1->pose, np * sizeof(double));
  mc->cand_ok = 1;
  return 0;
}

/* mc->umove: how far each cloth vertex at x0 and x1 is from xref, and each obstacle's vertices
 * from the candidates' start pose, at most (so on the whole motion x0 -> x1 too), m. */
static void moves(const sw_model *m, sw_mcontact *mc, const mc_place *x0, const mc_place *x1) {
  for (int i = 0; i < m->nv; i++) {
    const double *r = mc->xref + 3 * (size_t)i, *p = x0->x + 3 * (size_t)i, *q = x1->x + 3 * (size_t)i;
    double s = 0.0, t = 0.0;
    for (int a = 0; a < 3; a++) s += (p[a] - r[a]) * (p[a] - r[a]), t += (q[a] - r[a]) * (q[a] - r[a]);
    mc->umove[i] = sqrt(s > t ? s : t);
  }
  const double *a = mc->pose + 24 * (size_t)mc->p->nobst;
  for (int k = 0; k < mc->p->nobst; k++) /* static obstacles' stay 0 */
    mc->umove[m->nv + k] = !x0->pose ? 0.0 : fmax(pose_gap(mc->p, k, x0->pose, a),
                                                  pose_gap(mc->p, k, x1->pose, a));
  mc->umax = 0.0;
  for (int i = 0; i < m->nv + mc->p->nobst; i++) mc->umax = fmax(mc->umax, mc->umove[i]);
}

/* Whether candidate c stays farther apart than its thickness plus `reach` (m) on the motion
 * mc->umove was made for: a point of a primitive moves at most as far as its farthest vertex,
 * so the distance falls by at most the two primitives' largest moves. */
static int stays_beyond(const sw_model *m, const sw_mcontact *mc, const sw_mc_pair *c,
                        double reach) {
  int na = c->kind == SW_MC_PT ? 1 : 2;
  double ua = 0.0, ub = 0.0;
  for (int j = 0; j < 4; j++) {
    int v = c->v[j];
    double u = mc->umove[v < m->nv ? v : m->nv + owner_of(m, mc->p, v)];
    if (j < na) ua = u > ua ? u : ua;
    else ub = u > ub ? u : ub;
  }
  return c->gap - ua - ub > reach;
}

/* mc->moved: the cloth's vertices out of their boxes by more than h (m) at x0 or x1; how
 * many, counting stopped past lim. */
static int mark_moved(const sw_model *m, sw_mcontact *mc, const mc_place *x0,
                      const mc_place *x1, double h, int lim) {
  int n = 0;
  for (int i = 0; i < m->nv && n <= lim; i++) {
    const double *b = mc->cbox + 6 * (size_t)i;
    int out = 0;
    for (int k = 0; k < 2; k++) {
      const double *p = (k ? x1 : x0)->x + 3 * (size_t)i;
      for (int a = 0; a < 3; a++) out |= !(p[a] >= b[a] - h && p[a] <= b[3 + a] + h);
    }
    mc->moved[i] = (unsigned char)out, n += out;
  }
  return n;
}

/* The pairs of a moved vertex (mc->moved) in the broad phase's lists, from every primitive's
 * box (mc->cbox) padded by reach: the cloth's own pairs and those with the obstacles' tree. */
static int moved_pairs(const sw_model *m, sw_mcontact *mc, const mc_place *x0,
                       const mc_place *x1, double reach) {
  for (int i = 0; i < 3 * m->nv; i++)
    mc->blo[i] = mc->cbox[6 * (i / 3) + i % 3], mc->bhi[i] = mc->cbox[6 * (i / 3) + 3 + i % 3];
  mc_place lo = {mc->blo, x0->pose}, hi = {mc->bhi, x1->pose};
  sw_bp_input in = bp_input(m, mc, &lo, &hi, reach);
  sw_broadphase *bp = &mc->bp;
  bp->npt = bp->nee = bp->nff = 0;
  if (m->contact.self &&
      sw_broadphase_query_marked(bp, &in, SW_BP_PT | SW_BP_EE, mc->moved))
    return -1;
  if (mc->p->nvt == m->nv) return 0;
  tree_ctx c = {m, mc->p, x0, x1}; /* the obstacles' places (they do not move) */
  return tree_pairs(m, mc, &in, &c, mc->moved, SW_BP_PT | SW_BP_EE);
}

/* The kept candidates on the way to a renewal at x0: each cloth vertex's xref moved to x0 and
 * mc->far made from the boxes (far_boxes); the pairs of a moved vertex dropped (they are listed
 * again), and those a bound puts beyond mc->far (they stay beyond every evaluation's reach).
 * A kept pair's gap at x0 is at least its gap at the old xref less its primitives' largest
 * drifts from there; that bound stands as its gap (a lower bound serves each_candidate's
 * test as the gap does), or, below SW_MC_REGAP d-hat, where pairs are visited, its gap at x0. */
static void rebase_kept(const sw_model *m, sw_mcontact *mc, const mc_place *x0) {
  double *drift = mc->umove; /* m; scratch here: each_candidate makes its own */
  for (int i = 0; i < m->nv; i++) {
    const double *r = mc->xref + 3 * (size_t)i, *p = x0->x + 3 * (size_t)i;
    drift[i] = sqrt((p[0] - r[0]) * (p[0] - r[0]) + (p[1] - r[1]) * (p[1] - r[1]) +
                    (p[2] - r[2]) * (p[2] - r[2]));
  }
  memcpy(mc->xref, x0->x, 3 * (size_t)m->nv * sizeof(double));
  mc->far = far_boxes(m, mc);
  int k = 0;
  for (int j = 0; j < mc->ncand; j++) {
    sw_mc_pair *c = &mc->cand[j];
    int keep = 1, na = c->kind == SW_MC_PT ? 1 : 2;
    double da = 0.0, db = 0.0; /* m */
    for (int q = 0; q < 4; q++) {
      int v = c->v[q];
      keep = keep && !(v < m->nv && mc->moved[v]);
      double u = v < m->nv ? drift[v] : 0.0; /* the obstacles do not move */
      if (q < na) da = fmax(da, u);
      else db = fmax(db, u);
    }
    double bound = c->gap - da - db;
    if (!keep || bound > mc->far) continue;
    c->gap = bound < SW_MC_REGAP * m->contact.dhat ? pair_gap(m, mc, c->kind, c->v, x0) : bound;
    mc->cand[k++] = *c;
  }
  mc->ncand = k;
}

/* The kept candidates renewed for the motion x0 -> x1 when at most nv / SW_MC_RENEW cloth
 * vertices are out of their boxes by more than SW_MC_RENEW_MARGIN of the slack (and no
 * obstacle moves): those vertices' boxes are swept over x0 -> x1, their pairs listed again
 * against every primitive's box, the others' boxes as they were.  A pair with no moved vertex
 * keeps its boxes, so its listing (or its absence) holds as it did, and every pair within
 * reach at positions within the slack of the boxes is listed, as after find_candidates.
 * 1: renewed; 0: too many moved; -1 as find_candidates (the listing dropped). */
static int renew_candidates(const sw_model *m, sw_mcontact *mc, const mc_place *x0,
                            const mc_place *x1) {
  int lim = m->nv / SW_MC_RENEW, n;
  if (!mc->renew || !mc->cand_ok || mc->p->moving ||
      (n = mark_moved(m, mc, x0, x1, SW_MC_RENEW_MARGIN * mc->slack, lim)) == 0 || n > lim)
    return 0;
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; mc->moved[i] && a < 3; a++) {
      double *bi = mc->cbox + 6 * (size_t)i + a, p = x0->x[3 * i + a], q = x1->x[3 * i + a];
      bi[0] = p < q ? p : q, bi[3] = p < q ? q : p;
    }
  rebase_kept(m, mc, x0);
  double reach = 0.5 * (max_thickness(m) + m->contact.dhat) + mc->slack;
  if (moved_pairs(m, mc, x0, x1, reach) || each_pair(m, mc, add_candidate, (void *)x0))
    return mc->cand_ok = 0, -1;
  mc->nrenew++;
  return 1;
}

/* The candidates for the motion x0 -> x1: the kept ones when they cover both ends (so every
 * position between: the boxes are convex), renewed for a few vertices out of them, else new
 * ones; -1 as find_candidates. */
static int candidates(const sw_model *m, sw_mcontact *mc, const mc_place *x0,
                      const mc_place *x1) {
  if (covered(m, mc, x0) && (x1 == x0 || covered(m, mc, x1))) return 0;
  int rc = renew_candidates(m, mc, x0, x1);
  return rc < 0 ? -1 : rc ? 0 : find_candidates(m, mc, x0, x1);
}

/* Call visit on every candidate that may come within its thickness plus `dhat` (m) on the
 * motion x0 -> x1, as each_pair does.  No pair moves closer by more than twice the largest
 * move, so a gap beyond dhat + 2 umax rules a candidate out before its vertices' moves are
 * read: late Newton iterates and short line-search steps look closer at the near pairs only. */
static int each_candidate(const sw_model *m, sw_mcontact *mc, const mc_place *x0,
                          const mc_place *x1, double dhat, pair_visit visit, void *arg) {
  moves(m, mc, x0, x1);
  const double cut = dhat + 2.0 * mc->umax; /* m */
  for (int k = 0; k < mc->ncand; k++) {
    const sw_mc_pair *c = &mc->cand[k];
    if (c->gap > cut || stays_beyond(m, mc, c, dhat)) continue;
    int rc = visit(m, mc, c->kind, c->v, arg);
    if (rc) return rc;
  }
  return 0;
}

/* -------------------------------------------------------------------- the term */

/* The mean mass of the pair's cloth vertices times kappa_s (with its factor so far), kg/(s^2 m^2). */
static double pair_weight(const sw_model *m, const sw_mcontact *mc, const int *v) {
  double w = 0.0;
  int nc = 0;
  for (int k = 0; k < 4; k++)
    if (v[k] < m->nv) w += m->mass[v[k]], nc++;
  return w * m->contact.kappa_mesh * mc->kscale / nc;
}

/* The energy of one pair with vertices v at x (J), its gradient g (12; NULL: the
 * energy alone) and, when H is not NULL (g then too), its Hessian block clamped to positive
 * semi-definite (144); *gap = d - xi (m).  INFINITY when the pair is within xi.  The clamp is
 * found on the block's span (models/barrier_block.c), except for an edge-edge pair the
 * mollifier scales (nearly parallel edges): its exact 12 x 12 Hessian, eigen-decomposed on
 * the 9 dimensions a translation leaves out (sw_pair_clamp_free). */
static double pair_energy(const sw_model *m, const sw_mcontact *mc, int kind, const int *v,
                          const mc_place *x, double *g, double *H, double *gap) {
  const sw_contact *c = &m->contact;
  const mc_param *pm = mc->p;
  double p[12], g2[12];
  sw_pair_form pf;
  gather(m, mc, x, v, p);
  double *gd = g ? g2 : NULL; /* the energy alone (a line search's) needs no gradient */
  double xi = pair_xi(m, pm, v), shat = shat_of(xi, c->dhat);
  /* with H, a pair beyond the barrier's reach (s >= shat below; the factor 1 + 1e-12 keeps
   * the round-off of s - shat on the safe side) gets its distance alone, not its form */
  double d2 = H ? sw_pair_d2_form_near(kind == SW_MC_EE, p, (xi * xi + shat) * (1.0 + 1e-12), &pf)
          : kind == SW_MC_PT ? sw_d2_point_triangle(p, p + 3, p + 6, p + 9, gd, NULL)
                             : sw_d2_edge_edge(p, p + 3, p + 6, p + 9, gd, NULL);
  double s = d2 - xi * xi;
  *gap = sqrt(fmax(d2, 0.0)) - xi;
  if (!(s > 0.0)) return INFINITY;
  if (s >= shat) return 0.0;
  if (H) memcpy(g2, pf.g, sizeof g2);
  double w = pair_weight(m, mc, v), db, d2b, b = sw_barrier(s, shat, &db, &d2b);
  double mo = 1.0, mg[12], mH[144], r[12];
  if (kind == SW_MC_EE) { /* the mollifier vanishes as the edges become parallel (IPC sec. 4.3) */
    gather_rest(m, pm, v, r);
    double eps = sw_ee_mollifier_eps(r, r + 3, r + 6, r + 9);
    mo = sw_ee_mollifier(p, p + 3, p + 6, p + 9, eps, NULL, NULL); /* 1: no derivatives */
    if (mo < 1.0) mo = sw_ee_mollifier(p, p + 3, p + 6, p + 9, eps, mg, H ? mH : NULL);
  }
  if (mo == 1.0) { /* no mollifier: b and its clamped block */
    for (int i = 0; g && i < 12; i++) g[i] = w * db * g2[i];
    if (H) (void)sw_pair_barrier_block(&pf, db, d2b, w, H); /* not finite: as the clamp's */
    return w * b;
  }
  double bg[12], bH[144], H2[144], *h2 = H ? H2 : NULL;
  if (!g) return w * mo * b; /* the energy alone */
  if (H) sw_d2_edge_edge(p, p + 3, p + 6, p + 9, NULL, H2);
  sw_barrier_of(12, s, g2, h2, shat, bg, H ? bH : NULL);
  double e = sw_product_derivs(12, mo, mg, mH, b, bg, bH, g, H);
  for (int i = 0; i < 12; i++) g[i] *= w;
  for (int i = 0; H && i < 144; i++) H[i] *= w;
  if (H) (void)sw_pair_clamp_free(H); /* indefinite; not finite: as the clamp's */
  return w * e;
}

/* What an evaluation needs of each pair. */
typedef struct eval_arg {
  const sw_eval *ev;
  const mc_place *x;
  double e;          /* J */
} eval_arg;

/* One pair of an evaluation: energy, gradient (on the cloth's vertices), the active list. */
static int eval_pair(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  eval_arg *a = arg;
  const sw_eval *ev = a->ev;
  const int want_h = ev->hess != NULL;
  double g[12], gap, Hb[144];
  double ek = pair_energy(m, mc, kind, v, a->x, ev->grad || want_h ? g : NULL,
                          want_h ? Hb : NULL, &gap);
  if (!isfinite(ek)) {
    sw_eval_why(ev, "%s pair (vertices %d %d %d %d) closer than the thickness (gap %g m)",
                kind == SW_MC_PT ? "point-triangle" : "edge-edge", v[0], v[1], v[2], v[3],
                gap);
    return SW_RECOVER;
  }
  if (gap >= m->contact.dhat) return SW_OK;
  if (reserve_pair(mc)) return SW_FATAL;
  sw_mc_pair *pr = &mc->pair[mc->npair];
  pr->kind = kind;
  memcpy(pr->v, v, sizeof pr->v);
  pr->gap = gap;
  if (want_h) memcpy(mc->block + (size_t)mc->npair * 144, Hb, sizeof Hb);
  mc->npair++;
  a->e += ek;
  for (int j = 0; ev->grad && j < 12; j++)
    if (v[j / 3] < m->nv) ev->grad[3 * v[j / 3] + j % 3] += g[j]; /* g set when grad is asked */
  return SW_OK;
}

/* The lagged friction of the step (models/mesh_friction.c) at x: energy into *e,
 * gradient into ev->grad, and each pair's block appended to the active list as a pair with
 * an infinite gap (so that Newton's settle test ignores it). */
static int eval_friction(const sw_model *m, sw_mcontact *mc, const sw_eval *ev,
                         const mc_place *x, double *e) {
  int nf = sw_mfriction_count(mc->fr);
  for (int k = 0; k < nf; k++) {
    const int *v = sw_mfriction_vertices(mc->fr, k);
    double g[12], p[12], *H = NULL;
    if (ev->hess && reserve_pair(mc)) return SW_FATAL;
    if (ev->hess) H = mc->block + (size_t)mc->npair * 144;
    gather(m, mc, x, v, p);
    *e += sw_mfriction_pair(mc->fr, m->contact.eps_v, k, p, g, H, ev->bound);
    for (int j = 0; ev->grad && j < 12; j++)
      if (v[j / 3] < m->nv) ev->grad[3 * v[j / 3] + j % 3] += g[j];
    if (!ev->hess) continue;
    sw_mc_pair *pr = &mc->pair[mc->npair++];
    pr->kind = SW_MC_PT;
    memcpy(pr->v, v, sizeof pr->v);
    pr->gap = INFINITY;
  }
  return SW_OK;
}

static int mc_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  (void)t;
  sw_mcontact *mc = ev->mc ? ev->mc : ev->data; /* a caller's own, or the run's */
  *energy = 0.0;
  if (!mc) {
    sw_eval_why(ev, "no contact workspace (an evaluation outside a run)");
    return SW_FATAL;
  }
  mc->npair = 0;
  mc->have_blocks = ev->hess != NULL;
  mc_place x = positions(m, mc, ev->x, ev->t, 0);
  eval_arg a = {.ev = ev, .x = &x};
  if (candidates(m, mc, a.x, a.x)) {
    sw_eval_why(ev, "the broad phase failed (positions not finite, or out of memory)");
    return SW_RECOVER;
  }
  int rc = each_candidate(m, mc, a.x, a.x, m->contact.dhat, eval_pair, &a);
  if (!rc) rc = eval_friction(m, mc, ev, a.x, &a.e);
  *energy = a.e;
  return rc;
}

static void mc_free(void *param) {
  mc_param *p = param;
  if (!p) return;
  sw_free(p->edge);
  sw_free(p->vface);
  sw_free(p->eface);
  sw_free(p->vbase);
  sw_free(p->fbase);
  sw_free(p->radius);
  sw_bvh_free(&p->tree);
  sw_free(p);
}

static void *mc_data_new(const sw_term *t, const sw_model *m, sw_data *d);
static void mc_data_free(void *data);
static void mc_blocks(const sw_term *t, const sw_model *m, const sw_data *d, const void *data,
                      sw_blocks *b);
static int mc_begin(const sw_term *t, const sw_model *m, sw_data *d, void *data, double h,
                    double t1, double *y);
static double mc_ccd(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                     const double *x0, const double *x1, double time);
static int mc_settled(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                      const double *x0, const double *x1, double time);
static int mc_swept(const sw_term *t, const sw_model *m, sw_data *d, void *data, const double *y,
                    double t1);
static int mc_held(const sw_term *t, const sw_model *m, const sw_data *d, const void *data,
                   const double *x, double time, const double *vfrac, double frac, int *item,
                   int *vertex, double *held);
static void mc_commit(const sw_term *t, const sw_model *m, sw_data *d, void *data);
static void mc_state(const sw_term *t, const sw_model *m, sw_data *d, void *data);
static const double *mc_vertex_force(const sw_term *t, const sw_model *m, const sw_data *d,
                                     const void *data);
static int mc_dissipates(const sw_term *t, const sw_model *m);
static int mc_summary(const sw_term *t, const sw_model *m, const sw_data *d, void *data, int at,
                      sw_field *f, int nmax);
static void mc_io(const sw_term *t, const sw_model *m, void *data, sw_io *io);

/* The cloth starts apart from every mesh obstacle by more than its offset, and (with
 * self-contact) its triangles apart by more than the thickness. */
static int mc_check_start(const sw_term *t, const sw_model *m, const double *x, const char **key,
                          char *err, size_t errsz) {
  (void)t;
  char e[SW_ERRSZ];
  if (sw_mcontact_check_start(m, x, 1, e, sizeof e)) {
    *key = "obstacles";
    sw_errf(err, errsz, "%s; expected the cloth to start apart from every mesh obstacle by "
            "more than its offset", e);
    return -1;
  }
  if (sw_mcontact_check_start(m, x, 0, e, sizeof e)) {
    *key = "contact: self";
    sw_errf(err, errsz, "%s; expected a starting mesh whose triangles are apart by more than "
            "the thickness", e);
    return -1;
  }
  return 0;
}

static const sw_term_ops mc_ops = {
    .kind = "mesh_contact", .eval = mc_eval, .free_param = mc_free,
    .data_new = mc_data_new, .data_free = mc_data_free, .blocks = mc_blocks,
    .begin = mc_begin, .ccd = mc_ccd, .settled = mc_settled, .swept = mc_swept,
    .held = mc_held, .commit = mc_commit, .state = mc_state, .vertex_force = mc_vertex_force,
    .dissipates = mc_dissipates, .summary = mc_summary, .io = mc_io,
    .check_start = mc_check_start};

/* The numbering of the mesh obstacles' vertices and faces after the cloth's, and their radii
 * about their centres and rotation axes; -1 when out of memory. */
static int number_obstacles(mc_param *p, const sw_model *m) {
  p->nobst = m->nmesh_obstacle;
  p->vbase = sw_calloc((size_t)p->nobst + 1, sizeof(int));
  p->fbase = sw_calloc((size_t)p->nobst + 1, sizeof(int));
  p->radius = sw_calloc(2 * (size_t)p->nobst + 1, sizeof(double));
  if (!p->vbase || !p->fbase || !p->radius) return -1;
  for (int k = 0; k < p->nobst; k++) {
    const sw_obstacle *o = &m->mesh_obstacle[k];
    p->vbase[k + 1] = p->vbase[k] + o->mesh_nv;
    p->fbase[k + 1] = p->fbase[k] + o->mesh_nf;
    p->moving |= o->nkey > 0 || o->nrot > 0;
    double r2 = 0.0, a2 = 0.0;
    for (int j = 0; j < o->mesh_nv; j++) {
      double r[3], along = 0.0, rr = 0.0, aa = 0.0;
      for (int a = 0; a < 3; a++) r[a] = o->mesh_x[3 * (size_t)j + a] - o->center[a], along += r[a] * o->axis[a];
      for (int a = 0; a < 3; a++) rr += r[a] * r[a], aa += (r[a] - along * o->axis[a]) * (r[a] - along * o->axis[a]);
      r2 = fmax(r2, rr), a2 = fmax(a2, aa);
    }
    p->radius[2 * k] = sqrt(r2), p->radius[2 * k + 1] = o->nrot ? sqrt(a2) : 0.0;
  }
  p->nvt = m->nv + p->vbase[p->nobst];
  p->nf = m->nf + p->fbase[p->nobst];
  return 0;
}

/* The obstacles' tree over their faces at their stated place; -1 when out of memory or
 * stopped by a signal (sw_interrupt) while building. */
static int build_tree(mc_param *p, const sw_model *m, char *err, size_t errsz) {
  mc_place at = {NULL, NULL};
  tree_ctx c = {m, p, &at, &at};
  int rc = sw_bvh_build(&p->tree, p->nf - m->nf, tree_box, &c);
  if (rc == -2)
    return sw_errf(err, errsz, "stopped by signal %d while building the mesh obstacles' "
                   "tree", sw_cancelled()), -1;
  if (rc) return sw_errf(err, errsz, "out of memory for the mesh obstacles' tree"), -1;
  if (p->moving) { /* each workspace fits its own (fit_tree) */
    sw_free(p->tree.box);
    p->tree.box = NULL;
  } else if (p->tree.n <= SW_MC_KEEP_BOXES && sw_bvh_keep_boxes(&p->tree, tree_box, &c)) {
    return sw_errf(err, errsz, "out of memory for the mesh obstacles' tree"), -1;
  }
  return 0;
}

int sw_mesh_contact_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  t->ops = &mc_ops;
  snprintf(t->name, sizeof t->name, "%s", "mesh_contact");
  mc_param *p = sw_calloc(1, sizeof *p);
  t->param = p;
  if (!p || sw_term_alloc_stencils(t, 0, 1, m->dim) || number_obstacles(p, m)) {
    sw_errf(err, errsz, "out of memory for the mesh contact term");
    return -1;
  }
  sw_model cloth = {.nv = m->nv, .nf = m->nf, .face = m->face}; /* for its edges only */
  sw_topology tp;
  if (sw_topology_build(&tp, &cloth, err, errsz)) return -1;
  p->ne_cloth = tp.ne;
  p->edge = tp.ev;
  tp.ev = NULL;
  p->vface = sw_calloc((size_t)m->nv + 1, sizeof(int));
  p->eface = sw_calloc((size_t)tp.ne + 1, sizeof(int));
  if (!p->vface || !p->eface) {
    sw_topology_free(&tp);
    return sw_errf(err, errsz, "out of memory for the mesh contact term"), -1;
  }
  for (int e = 0; e < tp.ne; e++) p->eface[e] = tp.ef[2 * (size_t)e];
  for (int i = 0; i < m->nv; i++) p->vface[i] = -1;
  for (int f = m->nf - 1; f >= 0; f--)
    for (int c = 0; c < 3; c++) p->vface[m->face[3 * (size_t)f + c]] = f;
  sw_topology_free(&tp);
  return build_tree(p, m, err, errsz);
}

/* ------------------------------------------------------------ the solvers' side */

/* What CCD needs of each pair. */
typedef struct toi_arg {
  const mc_place *x0, *x1;
  double toi;
} toi_arg;

static int toi_pair(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  toi_arg *a = arg;
  double p0[12], p1[12], xi = pair_xi(m, mc->p, v);
  gather(m, mc, a->x0, v, p0);
  gather(m, mc, a->x1, v, p1);
  double s = kind == SW_MC_PT ? sw_ccd_point_triangle(p0, p1, xi, a->toi)
                              : sw_ccd_edge_edge(p0, p1, xi, a->toi);
  if (s < a->toi) memcpy(mc->limit, v, sizeof mc->limit);
  a->toi = s;
  return s > 0.0 ? 0 : 1;
}

double sw_mcontact_toi(const sw_model *m, sw_mcontact *mc, const double *x0, double t0,
                       const double *x1, double t1, double *time_bp) {
  if (!mc) return 1.0;
  double start = sw_now();
  mc_place p0 = positions(m, mc, x0, t0, 0), p1 = positions(m, mc, x1, t1, 1);
  toi_arg a = {.x0 = &p0, .x1 = &p1, .toi = 1.0};
  int rc = candidates(m, mc, a.x0, a.x1);
  *time_bp += sw_now() - start;
  mc->limit[0] = -1;
  if (rc) return 0.0;
  each_candidate(m, mc, a.x0, a.x1, 0.0, toi_pair, &a);
  return a.toi;
}

int sw_mcontact_limit(const sw_model *m, const sw_mcontact *mc, int *vertex) {
  int i = -1, k = -1;
  for (int j = 0; mc && mc->limit[0] >= 0 && j < 4; j++) {
    int o = owner_of(m, mc->p, mc->limit[j]);
    if (o < 0 && i < 0) i = mc->limit[j];
    if (o >= 0 && k < 0) k = o;
  }
  *vertex = i;
  return k < 0 || i < 0 ? -1 : m->mesh_obstacle[k].item;
}

int sw_mcontact_settled(const sw_model *m, const sw_mcontact *mc, const double *x0,
                        const double *x1) {
  for (int k = 0; mc && k < mc->npair; k++) {
    const sw_mc_pair *p = &mc->pair[k];
    double move = 0.0;
    for (int j = 0; j < 4; j++) {
      if (p->v[j] >= m->nv) continue; /* an obstacle's: fixed within a solve */
      const double *a = x0 + 3 * (size_t)p->v[j], *b = x1 + 3 * (size_t)p->v[j];
      double s = 0.0;
      for (int c = 0; c < 3; c++) s += (b[c] - a[c]) * (b[c] - a[c]);
      move = fmax(move, sqrt(s)); /* m */
    }
    if (move > SW_CONTACT_SETTLE * p->gap) return 0;
  }
  return 1;
}

/* The largest distance from mesh obstacle k's rotation axis of its vertices (m), and bounds of
 * its vertices' motion over [t0, t1]: how far one moves (m) and how far one strays from the
 * straight line between its places at t0 and t1, joined uniformly in time (m: the
 * translation's departure from its chord plus the arc's from its chord, rho (dev + dangle^2 /
 * 8) for an angle that departs dev from its own chord). */
static double mesh_radius(const sw_model *m, const mc_param *p, int k) {
  (void)m;
  return p->radius[2 * k + 1]; /* found once, at the term's build */
}

static double mesh_motion(const sw_model *m, const mc_param *p, int k, double t0, double t1) {
  sw_motion_bounds b;
  sw_obstacle_bounds(&m->mesh_obstacle[k], t0, t1, &b);
  return b.move + b.turn * mesh_radius(m, p, k);
}

static double mesh_stray(const sw_model *m, const mc_param *p, int k, double t0, double t1) {
  sw_motion_bounds b;
  sw_obstacle_bounds(&m->mesh_obstacle[k], t0, t1, &b);
  return b.pos_dev + mesh_radius(m, p, k) * (b.turn_dev + 0.125 * b.dangle * b.dangle);
}

/* What the swept check needs of each pair: the step's start and end (nvt x 3), and how far the
 * obstacles' vertices may stray from straight lines, m. */
typedef struct swept_arg {
  const mc_place *x0, *x1;
  double stray;
} swept_arg;

/* A pair is clear over the step when additive CCD, restarted from where it stops (each start
 * resets its scaling), reaches the step's end within 12 restarts without the pair coming
 * within its thickness, widened by the obstacles' stray for pairs with an obstacle. */
static int swept_pair(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  swept_arg *a = arg;
  double p0[12], p1[12], q[12], xi = pair_xi(m, mc->p, v), t = 0.0;
  int obst = 0;
  for (int j = 0; j < 4; j++) obst |= v[j] >= m->nv;
  gather(m, mc, a->x0, v, p0);
  gather(m, mc, a->x1, v, p1);
  for (int r = 0; r < 12; r++) {
    for (int i = 0; i < 12; i++) q[i] = p0[i] + t * (p1[i] - p0[i]);
    double dmin = xi + (obst ? a->stray : 0.0);
    double s = kind == SW_MC_PT ? sw_ccd_point_triangle(q, p1, dmin, 1.0)
                                : sw_ccd_edge_edge(q, p1, dmin, 1.0);
    if (s >= 1.0) return 0;
    if (!(s > 0.0)) break;
    t += s * (1.0 - t);
  }
  memcpy(mc->limit, v, sizeof mc->limit);
  return 1;
}

int sw_mcontact_swept(const sw_model *m, sw_data *d, const double *y, double t1) {
  sw_mcontact *mc = d->mc;
  if (!mc || !obstacles_move(m, d->t, t1)) return SW_OK;
  double start = sw_now();
  mc_place p0 = positions(m, mc, d->x, d->t, 0), p1 = positions(m, mc, y, t1, 1);
  swept_arg a = {.x0 = &p0, .x1 = &p1};
  for (int k = 0; k < m->nmesh_obstacle; k++) a.stray = fmax(a.stray, mesh_stray(m, mc->p, k, d->t, t1));
  int rc = broad_phase(m, mc, &p0, &p1, 0.5 * (max_thickness(m) + a.stray), SW_BP_PT | SW_BP_EE);
  d->time_broadphase += sw_now() - start;
  if (rc) {
    sw_errf(d->err, sizeof d->err, "the broad phase failed at t = %g s", d->t);
    return SW_RECOVER;
  }
  mc->limit[0] = -1;
  if (!each_pair(m, mc, swept_pair, &a)) return SW_OK;
  int i = -1, k = -1;
  for (int j = 0; j < 4; j++) {
    int o = owner_of(m, mc->p, mc->limit[j]);
    if (o < 0 && i < 0) i = mc->limit[j];
    if (o >= 0 && k < 0) k = o;
  }
  if (k < 0)
    sw_errf(d->err, sizeof d->err, "the cloth passes through itself near vertex %d between t = %g s "
            "and %g s", i, d->t, t1);
  else
    sw_errf(d->err, sizeof d->err, "obstacles[%d] passes through vertex %d between t = %g s and "
            "%g s", m->mesh_obstacle[k].item, i, d->t, t1);
  return SW_RECOVER;
}

/* The carry of a step's start: the free cloth vertices near mesh obstacle k (a pair within its
 * offset + dhat + its motion) move with it. */
typedef struct carry_arg {
  const mc_place *x;    /* at the step's start */
  int k;                /* the obstacle */
  double reach;         /* m */
  double t0, t1;        /* the step, s */
  unsigned char *done;  /* (nv) vertices carried by k already */
} carry_arg;

static int carry_pair(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  carry_arg *a = arg;
  int mine = 0;
  for (int j = 0; j < 4; j++) mine |= owner_of(m, mc->p, v[j]) == a->k;
  if (!mine) return 0;
  double p[12];
  gather(m, mc, a->x, v, p);
  double d2 = kind == SW_MC_PT ? sw_d2_point_triangle(p, p + 3, p + 6, p + 9, NULL, NULL)
                               : sw_d2_edge_edge(p, p + 3, p + 6, p + 9, NULL, NULL);
  if (d2 >= a->reach * a->reach) return 0;
  for (int j = 0; j < 4; j++) {
    int i = v[j];
    if (i >= m->nv || m->pinned[i] || a->done[i]) continue;
    a->done[i] = 1;
    mc->carrier[i] = a->k;
    double q[3]; /* the obstacle's rigid motion applied to the vertex */
    const double *xi = a->x->x + 3 * (size_t)i;
    sw_obstacle_carry(&m->mesh_obstacle[a->k], a->t0, a->t1, xi, q);
    for (int c = 0; c < 3; c++) mc->z[3 * (size_t)i + c] += q[c] - xi[c];
  }
  return 0;
}

/* mc->z: d->x with the free vertices near each moving mesh obstacle carried along by its
 * motion from d->t to t1 (the `carry` of the analytic obstacles, models/contact.c).  Uses
 * mc->f as scratch for the marks. */
static int carry(const sw_model *m, sw_data *d, double t1) {
  sw_mcontact *mc = d->mc;
  memcpy(mc->z, d->x, (size_t)m->nv * 3 * sizeof(double));
  for (int i = 0; i < m->nv; i++) mc->carrier[i] = -1;
  mc_place x = positions(m, mc, d->x, d->t, 0);
  for (int k = 0; k < m->nmesh_obstacle; k++) {
    const sw_obstacle *o = &m->mesh_obstacle[k];
    carry_arg a = {.x = &x, .k = k, .done = (unsigned char *)mc->f, .t0 = d->t, .t1 = t1};
    if (!sw_obstacle_moves(o, d->t, t1)) continue;
    a.reach = o->offset + m->contact.dhat + mesh_motion(m, mc->p, k, d->t, t1); /* m */
    memset(a.done, 0, (size_t)m->nv);
    if (broad_phase(m, mc, &x, &x, 0.5 * a.reach, SW_BP_PT | SW_BP_EE)) return -1;
    each_pair(m, mc, carry_pair, &a);
  }
  return 0;
}

/* Why the carry failed, from the pair that limited its CCD: "obstacles[k] moves into vertex
 * i", or "obstacles[c] moves vertex i into obstacles[k]" when obstacle c carried the vertex
 * into one that does not move. */
static int moves_into(const sw_model *m, const sw_mcontact *mc, sw_data *d, double t1) {
  int i = -1, k = -1;
  for (int j = 0; j < 4 && mc->limit[0] >= 0; j++) {
    int o = owner_of(m, mc->p, mc->limit[j]);
    if (o < 0 && i < 0) i = mc->limit[j];
    if (o >= 0 && k < 0) k = o;
  }
  int c = i >= 0 ? mc->carrier[i] : -1;
  int still = k >= 0 && !sw_obstacle_moves(&m->mesh_obstacle[k], d->t, t1);
  if (k < 0)
    sw_errf(d->err, sizeof d->err, "the cloth cannot follow the mesh obstacles between t = %g s "
            "and %g s (vertex %d)", d->t, t1, i);
  else if (still && c >= 0 && c != k)
    sw_errf(d->err, sizeof d->err, "obstacles[%d] moves vertex %d into obstacles[%d] between "
            "t = %g s and %g s", m->mesh_obstacle[c].item, i, m->mesh_obstacle[k].item, d->t, t1);
  else
    sw_errf(d->err, sizeof d->err, "obstacles[%d] moves into vertex %d between t = %g s and %g s",
            m->mesh_obstacle[k].item, i, d->t, t1);
  return SW_RECOVER;
}

int sw_mcontact_begin(const sw_model *m, sw_data *d, double t1, double *y) {
  sw_mcontact *mc = d->mc;
  if (!mc) return SW_OK;
  double s = sw_mcontact_toi(m, mc, d->x, d->t, y, t1, &d->time_broadphase);
  if (s >= 1.0) return SW_OK;
  const int nd = m->nv * 3;
  if (!obstacles_move(m, d->t, t1)) {
    for (int i = 0; i < nd; i++) y[i] = d->x[i] + s * (y[i] - d->x[i]);
    return SW_OK;
  }
  /* a moving obstacle: from the carried start, reached safely with the obstacle's motion */
  if (carry(m, d, t1)) {
    sw_errf(d->err, sizeof d->err, "the broad phase failed at t = %g s", d->t);
    return SW_RECOVER;
  }
  if (sw_mcontact_toi(m, mc, d->x, d->t, mc->z, t1, &d->time_broadphase) < 1.0)
    return moves_into(m, mc, d, t1);
  s = sw_mcontact_toi(m, mc, mc->z, t1, y, t1, &d->time_broadphase);
  for (int i = 0; i < nd; i++) y[i] = mc->z[i] + s * (y[i] - mc->z[i]);
  return SW_OK;
}

/* A pair's description for the start check: which primitives of what. */
static void describe_pair(const sw_model *m, const mc_param *p, int kind, const int *v,
                          double gap, char *err, size_t errsz) {
  int k = -1;
  for (int j = 0; j < 4 && k < 0; j++) k = owner_of(m, p, v[j]);
  if (k < 0) {
    sw_errf(err, errsz, "vertices %d %d %d %d (%s) start %g m apart, within the thickness %g m",
            v[0], v[1], v[2], v[3], kind == SW_MC_PT ? "a point and a triangle" : "two edges",
            gap + m->contact.thickness, m->contact.thickness);
    return;
  }
  const sw_obstacle *o = &m->mesh_obstacle[k];
  const char *what = kind == SW_MC_EE ? "an edge (vertices %d %d) starts %g m from obstacles[%d]"
                   : v[0] < m->nv ? "vertex %d starts %g m from obstacles[%d]"
                                  : "a triangle (vertices %d %d %d) starts %g m from obstacles[%d]";
  char head[160];
  if (kind == SW_MC_EE) snprintf(head, sizeof head, what, v[0], v[1], gap + o->offset, o->item);
  else if (v[0] < m->nv) snprintf(head, sizeof head, what, v[0], gap + o->offset, o->item);
  else snprintf(head, sizeof head, what, v[1], v[2], v[3], gap + o->offset, o->item);
  sw_errf(err, errsz, "%s, within its offset %g m", head, o->offset);
}

/* What the start check needs of each pair. */
typedef struct start_arg {
  const mc_place *x;
  int obstacles;  /* 1: pairs with an obstacle; 0: the cloth's own */
  char *err;
  size_t errsz;
} start_arg;

static int start_pair(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  start_arg *a = arg;
  int with_obstacle = 0;
  for (int j = 0; j < 4; j++) with_obstacle |= v[j] >= m->nv;
  if (with_obstacle != a->obstacles) return 0;
  double g[12], gap;
  if (isfinite(pair_energy(m, mc, kind, v, a->x, g, NULL, &gap))) return 0;
  describe_pair(m, mc->p, kind, v, gap, a->err, a->errsz);
  return 1;
}

long sw_mcontact_obstacle_intersections(const sw_model *m, sw_mcontact *mc, const double *x,
                                        double t, int *first) {
  mc_place q = positions(m, mc, x, t, 0);
  if (broad_phase(m, mc, &q, &q, 0.0, SW_BP_FF)) return -1;
  long count = 0;
  for (int k = 0; k < mc->bp.nff; k++) {
    if ((k & 0xffff) == 0xffff && sw_cancelled()) return -2; /* a stop request */
    int v[6];
    double p[18];
    face_vertices(m, mc->p, mc->bp.ff[2 * k], v);
    face_vertices(m, mc->p, mc->bp.ff[2 * k + 1], v + 3);
    if ((v[0] >= m->nv) == (v[3] >= m->nv)) continue; /* the cloth's own, or two obstacles' */
    for (int j = 0; j < 6; j++) vertex_at(m, mc->p, &q, v[j], p + 3 * j);
    if (!sw_triangles_intersect(p, p + 3, p + 6, p + 9, p + 12, p + 15)) continue;
    if (first && count == 0) first[0] = mc->bp.ff[2 * k], first[1] = mc->bp.ff[2 * k + 1];
    count++;
  }
  return count;
}

int sw_mcontact_check_start(const sw_model *m, const double *x, int obstacles, char *err,
                            size_t errsz) {
  if (obstacles ? m->nmesh_obstacle == 0 : !m->contact.self) return 0;
  long cross = obstacles ? 0 : sw_mesh_self_intersections_sewn(m->nv, x, m->nf, m->face,
                                                               m->sewn_ptr, m->sewn_idx);
  if (cross != 0) {
    sw_errf(err, errsz, cross == -2 ? "stopped while checking the mesh for self-intersections"
                        : cross < 0 ? "out of memory checking the mesh for self-intersections"
                                    : "the mesh intersects itself (%ld pairs of triangles)", cross);
    return -1;
  }
  sw_mcontact *mc = sw_mcontact_new(m);
  if (!mc) return sw_errf(err, errsz, "out of memory for the contact workspace"), -1;
  int ff[2] = {0, 0}, rc = 0;
  if (obstacles && (cross = sw_mcontact_obstacle_intersections(m, mc, x, 0.0, ff)) != 0) {
    int f = ff[0] < m->nf ? ff[0] : ff[1], g = ff[0] < m->nf ? ff[1] : ff[0];
    if (cross < 0) sw_errf(err, errsz, cross == -2 ? "stopped while checking the cloth against "
                           "the obstacles" : "out of memory checking the cloth against the obstacles");
    else
      sw_errf(err, errsz, "face %d of the cloth (vertices %d %d %d) intersects obstacles[%d] "
              "(%ld pairs of triangles intersect)", f, m->face[3 * f], m->face[3 * f + 1],
              m->face[3 * f + 2], m->mesh_obstacle[face_owner(m, mc->p, g)].item,
              cross);
    rc = 1;
  }
  mc_place at = positions(m, mc, x, 0.0, 0);
  start_arg a = {.x = &at, .obstacles = obstacles, .err = err, .errsz = errsz};
  if (!rc && broad_phase(m, mc, &at, &at, 0.5 * max_thickness(m), SW_BP_PT | SW_BP_EE)) {
    sw_errf(err, errsz, "the positions are not finite, or out of memory");
    rc = 1;
  }
  if (!rc) rc = each_pair(m, mc, start_pair, &a);
  sw_mcontact_free(mc);
  return rc ? -1 : 0;
}

/* The diagnostics of one pair within dhat: its force on each cloth vertex into mc->f (the
 * self-contact or the obstacles' half), counts and smallest gaps into d. */
typedef struct state_arg {
  sw_data *d;
  const mc_place *x;
} state_arg;

static int state_pair(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  sw_data *d = ((state_arg *)arg)->d;
  double g[12], gap;
  double e = pair_energy(m, mc, kind, v, ((state_arg *)arg)->x, g, NULL, &gap);
  if (!isfinite(e) || gap >= m->contact.dhat) return 0;
  mc->gap_min = fmin(mc->gap_min, gap);
  int obst = 0;
  for (int j = 0; j < 4; j++) obst |= v[j] >= m->nv;
  if (obst) {
    d->contact_min = fmin(d->contact_min, gap);
    d->contact_count++;
  } else {
    d->self_min = fmin(d->self_min, gap);
    d->self_count++;
  }
  double *f = mc->f + (obst ? 3 * (size_t)m->nv : 0);
  for (int j = 0; j < 12; j++)
    if (v[j / 3] < m->nv) f[3 * v[j / 3] + j % 3] -= g[j];
  return 0;
}

static void state_friction(const sw_model *m, sw_data *d, const mc_place *x);

void sw_mcontact_state(const sw_model *m, sw_data *d) {
  sw_mcontact *mc = d->mc;
  if (!mc) return;
  d->self_count = 0;
  d->self_min = INFINITY;
  d->self_force = 0.0;
  mc->gap_min = INFINITY;
  if (m->nobstacle == 0) { /* else sw_contact_state has set them for the shapes */
    d->contact_count = 0;
    d->contact_min = INFINITY;
    memset(d->contact_force, 0, sizeof d->contact_force);
    memset(d->friction_force, 0, sizeof d->friction_force);
    d->friction_power = 0.0;
  }
  memset(mc->vforce, 0, (size_t)m->nv * sizeof(double));
  mc_place x = positions(m, mc, d->x, d->t, 0);
  if (mc->fr) state_friction(m, d, &x);
  if (candidates(m, mc, &x, &x)) return;
  memset(mc->f, 0, (size_t)m->nv * 6 * sizeof(double));
  state_arg a = {d, &x};
  each_candidate(m, mc, &x, &x, m->contact.dhat, state_pair, &a);
  const double *fs = mc->f, *fo = mc->f + 3 * (size_t)m->nv; /* N */
  for (int i = 0; i < m->nv; i++) {
    double s = 0.0, o = 0.0;
    for (int a = 0; a < 3; a++) {
      s += fs[3 * i + a] * fs[3 * i + a];
      o += fo[3 * i + a] * fo[3 * i + a];
      d->contact_force[a] += fo[3 * i + a];
    }
    mc->vforce[i] = sqrt(s) + sqrt(o);
    d->self_force += 0.5 * sqrt(s); /* each pair pushes both sides: half is one side */
  }
}

const double *sw_mcontact_vertex_force(const sw_mcontact *mc) { return mc ? mc->vforce : NULL; }

long sw_mcontact_refits(const sw_mcontact *mc) { return mc ? mc->nrefit : 0; }

size_t sw_mesh_contact_bytes(const sw_model *m) {
  const mc_param *p = NULL;
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].ops->kind, "mesh_contact")) p = m->term[k].param;
  if (!p) return 0;
  size_t nobst = (size_t)p->nobst, nnode = (size_t)p->tree.nnode;
  return sizeof *p + 3 * (size_t)p->ne_cloth * sizeof(int) + (size_t)m->nv * sizeof(int) +
         2 * (nobst + 1) * sizeof(int) + 2 * nobst * sizeof(double) + (size_t)p->tree.n * sizeof(int) +
         nnode * (2 * sizeof(int) + (p->tree.box ? 6 * sizeof(float) : 0)) +
         (p->tree.pbox ? 6 * (size_t)p->tree.n * sizeof(double) : 0);
}

/* ------------------------------------------------------------------- friction */

static int lag_pair(const sw_model *m, sw_mcontact *mc, int kind, const int *v, void *arg) {
  double p[12], r[12], xi = pair_xi(m, mc->p, v), mo = 1.0;
  int self = 1;
  for (int j = 0; j < 4; j++) self &= v[j] < m->nv;
  gather(m, mc, arg, v, p);
  if (kind == SW_MC_EE) { /* the normal force of the pair's barrier, mollified as it is */
    gather_rest(m, mc->p, v, r);
    double eps = sw_ee_mollifier_eps(r, r + 3, r + 6, r + 9);
    mo = sw_ee_mollifier(p, p + 3, p + 6, p + 9, eps, NULL, NULL);
  }
  return sw_mfriction_lag_pair(mc->fr, kind, v, p, xi, shat_of(xi, m->contact.dhat),
                               mo * pair_weight(m, mc, v),
                               self ? m->contact.self_friction : m->contact.friction);
}

int sw_mcontact_lag(const sw_model *m, sw_data *d, double h) {
  sw_mcontact *mc = d->mc;
  if (!mc || !mc->fr) return SW_OK;
  mc_place x = positions(m, mc, d->x, d->t, 0);
  sw_mfriction_begin(mc->fr, h);
  if (candidates(m, mc, &x, &x)) {
    sw_errf(d->err, sizeof d->err, "the broad phase failed at t = %g s", d->t);
    return SW_RECOVER;
  }
  if (each_candidate(m, mc, &x, &x, m->contact.dhat, lag_pair, &x)) {
    sw_errf(d->err, sizeof d->err, "out of memory lagging the friction of mesh contact");
    return SW_FATAL;
  }
  return SW_OK;
}

/* The friction of the mesh pairs at d->x (the last step's lag) added to d->friction_force and
 * d->friction_power (W dissipated: -f.v). */
static void state_friction(const sw_model *m, sw_data *d, const mc_place *x) {
  sw_mcontact *mc = d->mc;
  int nf = sw_mfriction_count(mc->fr);
  for (int k = 0; k < nf; k++) {
    const int *v = sw_mfriction_vertices(mc->fr, k);
    double g[12], p[12];
    gather(m, mc, x, v, p);
    sw_mfriction_pair(mc->fr, m->contact.eps_v, k, p, g, NULL, 0);
    for (int j = 0; j < 12; j++) {
      if (v[j / 3] >= m->nv) continue;
      d->friction_force[j % 3] -= g[j];
      d->friction_power += g[j] * d->v[3 * v[j / 3] + j % 3];
    }
  }
}

void sw_mcontact_listings(const sw_mcontact *mc, long *made, long *renewed) {
  *made = mc ? mc->nfind : 0, *renewed = mc ? mc->nrenew : 0;
}

void sw_mcontact_set_renew(sw_mcontact *mc, int on) {
  if (mc) mc->renew = on != 0;
}

/* ------------------------------------------------------------ adaptive stiffness */

double sw_mcontact_kappa_scale(const sw_mcontact *mc) { return mc ? mc->kscale : 1.0; }

void sw_mcontact_set_kappa_scale(sw_mcontact *mc, double s) {
  if (mc && s >= 1.0 && isfinite(s)) mc->kscale = s;
}

double sw_kappa_growth(double gap, double dhat) {
  const double g0 = SW_KAPPA_GAP * dhat; /* m */
  if (!(gap < g0)) return 1.0;
  return exp2(fmin(1.0, (1.0 - gap / g0) / SW_KAPPA_BAND));
}

int sw_mcontact_adapt(const sw_model *m, sw_mcontact *mc) {
  if (!mc || !m->contact.kappa_mesh_auto || mc->kscale >= SW_KAPPA_SCALE_MAX) return 0;
  double f = sw_kappa_growth(mc->gap_min, m->contact.dhat);
  if (f <= 1.0) return 0;
  mc->kscale = fmin(mc->kscale * f, SW_KAPPA_SCALE_MAX);
  return 1;
}

/* ------------------------------------------------------ the term's optional operations */

/* The workspace (also d->mc, by name for the functions above). */
static void *mc_data_new(const sw_term *t, const sw_model *m, sw_data *d) {
  (void)t;
  return d->mc = sw_mcontact_new(m);
}

static void mc_data_free(void *data) { sw_mcontact_free(data); }

/* The active pairs' blocks: 4 vertices each, their indices in sw_mc_pair.v. */
_Static_assert(sizeof(sw_mc_pair) % sizeof(int) == 0, "sw_mc_pair in whole ints");
static void mc_blocks(const sw_term *t, const sw_model *m, const sw_data *d, const void *data,
                      sw_blocks *b) {
  (void)t, (void)m, (void)d;
  const sw_mc_pair *pr = NULL;
  const double *blk = NULL;
  b->n = sw_mcontact_pairs(data, &pr, &blk);
  b->nvb = 4;
  b->v = b->n > 0 ? pr[0].v : NULL;
  b->vstride = (int)(sizeof(sw_mc_pair) / sizeof(int));
  b->val = blk;
}

/* The step's start: the mesh pairs' friction lagged at d->x, the guess cut back (timed into
 * d->time_ccd). */
static int mc_begin(const sw_term *t, const sw_model *m, sw_data *d, void *data, double h,
                    double t1, double *y) {
  (void)t, (void)data;
  double t0 = sw_now();
  int rc = sw_mcontact_lag(m, d, h);
  if (!rc) rc = sw_mcontact_begin(m, d, t1, y);
  d->time_ccd += sw_now() - t0;
  return rc;
}

static double mc_ccd(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                     const double *x0, const double *x1, double time) {
  (void)t;
  double t0 = sw_now(), s = sw_mcontact_toi(m, data, x0, time, x1, time, &d->time_broadphase);
  d->time_ccd += sw_now() - t0;
  return s;
}

static int mc_settled(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                      const double *x0, const double *x1, double time) {
  (void)t, (void)time;
  double t0 = sw_now();
  int r = sw_mcontact_settled(m, data, x0, x1);
  d->time_contact += sw_now() - t0;
  return r;
}

static int mc_swept(const sw_term *t, const sw_model *m, sw_data *d, void *data, const double *y,
                    double t1) {
  (void)t, (void)data;
  double t0 = sw_now();
  int rc = sw_mcontact_swept(m, d, y, t1);
  d->time_contact += sw_now() - t0;
  return rc;
}

/* After Newton failed: when the CCD cut the last update below 1/2, the mesh obstacle of the
 * pair that limited it and that pair's cloth vertex. */
static int mc_held(const sw_term *t, const sw_model *m, const sw_data *d, const void *data,
                   const double *x, double time, const double *vfrac, double frac, int *item,
                   int *vertex, double *held) {
  (void)t, (void)d, (void)x, (void)time, (void)vfrac;
  if (!(frac < 0.5)) return 0;
  int iv = -1;
  *item = sw_mcontact_limit(m, data, &iv);
  *vertex = iv;
  *held = frac;
  return 1;
}

/* The automatic stiffness adapted after each accepted state (sw_mcontact_adapt). */
static void mc_commit(const sw_term *t, const sw_model *m, sw_data *d, void *data) {
  (void)t, (void)d;
  sw_mcontact_adapt(m, data);
}

static void mc_state(const sw_term *t, const sw_model *m, sw_data *d, void *data) {
  (void)t, (void)data;
  sw_mcontact_state(m, d);
}

static const double *mc_vertex_force(const sw_term *t, const sw_model *m, const sw_data *d,
                                     const void *data) {
  (void)t, (void)m, (void)d;
  return sw_mcontact_vertex_force(data);
}

static int mc_dissipates(const sw_term *t, const sw_model *m) {
  (void)t;
  const sw_contact *c = &m->contact;
  return (c->friction > 0.0 && m->nmesh_obstacle > 0) || (c->self && c->self_friction > 0.0);
}

/* summary.json: the adapted stiffness's factor at the end; the cloth's triangles that
 * intersect a mesh obstacle's at the state written (it cannot pass through them). */
static int mc_summary(const sw_term *t, const sw_model *m, const sw_data *d, void *data, int at,
                      sw_field *f, int nmax) {
  (void)t;
  if (nmax < 1) return 0;
  if (at == SW_SUMMARY_RUN && m->contact.kappa_mesh_auto) {
    f[0] = (sw_field){.name = "self_stiffness_factor", .value = sw_mcontact_kappa_scale(data)};
    return 1;
  }
  long n = at == SW_SUMMARY_STATE && data && m->nmesh_obstacle
               ? sw_mcontact_obstacle_intersections(m, data, d->x, d->t, NULL)
               : -1;
  if (n < 0) return 0;
  f[0] = (sw_field){.name = "obstacle_intersections", .count = n, .is_count = 1};
  return 1;
}

/* restart.bin: the automatic stiffness's factor so far. */
static void mc_io(const sw_term *t, const sw_model *m, void *data, sw_io *io) {
  (void)t, (void)m;
  double ks = sw_mcontact_kappa_scale(data);
  sw_io_bytes(io, &ks, sizeof ks);
  sw_mcontact_set_kappa_scale(data, ks);
}
