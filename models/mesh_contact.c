/* mesh_contact.c — the term "mesh_contact": the cloth's triangles kept apart from each other
 * (`contact: {self: true}`), after Li et al., "Incremental Potential Contact: Intersection-
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
 * xi + dhat contribute: a spatial-hash broad phase finds them at every evaluation.
 *
 * The pairs change with the configuration, so their Hessian blocks have no fixed stencil: each
 * evaluation lists them (with their positive semi-definite blocks, 12 x 12) in the run's
 * sw_mcontact workspace, and Newton adds them to the system, growing its pattern when a pair
 * couples two vertices it does not hold yet (solvers/newton.c, docs/contact.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact.h"
#include "contact_geom.h"
#include "terms.h"
#include "util.h"

/* The term's immutable data: the mesh's edges and its contact constants. */
typedef struct mc_param {
  int ne;
  int *edge;         /* (ne x 2) */
} mc_param;

struct sw_mcontact {
  sw_broadphase bp;
  unsigned char *fixed; /* (nv) 1: pinned (pairs of pinned vertices only are skipped) */
  double *xa, *xb;      /* (nv x 3) scratch positions */
  int ne;
  const int *edge;      /* the term's edges */
  sw_mc_pair *pair;     /* (cap) the active pairs of the last evaluation */
  double *block;        /* (cap x 144) their filtered Hessian blocks, when asked for */
  int npair, cap, have_blocks;
  double min_gap;       /* m: the smallest d - xi of the last evaluation's candidates */
  double *vforce;       /* (nv) |contact force| on each vertex at the last diagnostics, N */
};

double sw_mesh_contact_shat(const sw_contact *c) {
  double r = c->thickness + c->dhat;
  return r * r - c->thickness * c->thickness; /* m^2 */
}

double sw_mesh_contact_auto_kappa(const sw_model *m) {
  const sw_contact *c = &m->contact;
  double g = 0.0, db;
  for (int a = 0; a < m->dim; a++) g += m->gravity[a] * m->gravity[a];
  g = m->has_gravity && g > 0.0 ? sqrt(g) : 9.81; /* m/s^2 */
  double d = c->thickness + 0.5 * c->dhat;  /* the resting distance, m */
  sw_barrier(d * d - c->thickness * c->thickness, sw_mesh_contact_shat(c), &db, NULL);
  return g / (2.0 * d * fabs(db)); /* 1/(s^2 m^2): kappa w |b'| |grad d^2| = w g */
}

/* ------------------------------------------------------------------ workspace */

sw_mcontact *sw_mcontact_new(const sw_model *m) {
  if (!m->contact.self) return NULL;
  sw_mcontact *mc = sw_calloc(1, sizeof *mc);
  if (!mc) return NULL;
  sw_broadphase_init(&mc->bp);
  size_t nv = (size_t)m->nv;
  mc->fixed = sw_calloc(nv + 1, 1);
  mc->xa = sw_calloc(3 * nv + 1, sizeof(double));
  mc->xb = sw_calloc(3 * nv + 1, sizeof(double));
  mc->vforce = sw_calloc(nv + 1, sizeof(double));
  if (!mc->fixed || !mc->xa || !mc->xb || !mc->vforce) return sw_mcontact_free(mc), NULL;
  for (int i = 0; i < m->nv; i++) mc->fixed[i] = (unsigned char)(m->pinned[i] != 0);
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].ops->kind, "mesh_contact")) {
      const mc_param *p = m->term[k].param;
      mc->ne = p->ne;
      mc->edge = p->edge;
    }
  return mc;
}

void sw_mcontact_free(sw_mcontact *mc) {
  if (!mc) return;
  sw_broadphase_free(&mc->bp);
  sw_free(mc->fixed);
  sw_free(mc->xa);
  sw_free(mc->xb);
  sw_free(mc->pair);
  sw_free(mc->block);
  sw_free(mc->vforce);
  sw_free(mc);
}

int sw_mcontact_pairs(const sw_mcontact *mc, const sw_mc_pair **pair, const double **block) {
  if (!mc) return 0;
  if (pair) *pair = mc->pair;
  if (block) *block = mc->have_blocks ? mc->block : NULL;
  return mc->npair;
}

double sw_mcontact_min_gap(const sw_mcontact *mc) { return mc ? mc->min_gap : INFINITY; }

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

/* Positions x (nv x 3) into the broad phase's input with the given inflation. */
static sw_bp_input bp_input(const sw_model *m, const sw_mcontact *mc, const double *x0,
                            const double *x1, double inflate) {
  sw_bp_input in = {.nv = m->nv, .x0 = x0, .x1 = x1, .ne = mc->ne, .edge = mc->edge,
                    .nf = m->nf, .face = m->face, .fixed = mc->fixed, .inflate = inflate};
  return in;
}

/* The vertices of broad-phase pair q of kind k (SW_MC_PT: vertex, face; SW_MC_EE: edge,
 * edge) into v[4]. */
static void pair_vertices(const sw_model *m, const sw_mcontact *mc, int kind, const int *q,
                          int *v) {
  if (kind == SW_MC_PT) {
    v[0] = q[0];
    for (int c = 0; c < 3; c++) v[1 + c] = m->face[3 * q[1] + c];
  } else {
    v[0] = mc->edge[2 * q[0]], v[1] = mc->edge[2 * q[0] + 1];
    v[2] = mc->edge[2 * q[1]], v[3] = mc->edge[2 * q[1] + 1];
  }
}

/* The broad phase's last pairs of one kind (SW_MC_PT or SW_MC_EE) and their number. */
static const int *candidates(const sw_mcontact *mc, int kind, int *n) {
  *n = kind == SW_MC_PT ? mc->bp.npt : mc->bp.nee;
  return kind == SW_MC_PT ? mc->bp.pt : mc->bp.ee;
}

static void gather(const double *x, const int *v, double *p) {
  for (int k = 0; k < 4; k++) memcpy(p + 3 * k, x + 3 * (size_t)v[k], 3 * sizeof(double));
}

/* -------------------------------------------------------------------- the term */

/* The energy of one pair with vertices v at x (J), its gradient g (12) and, when H is not
 * NULL, its Hessian (144); *gap = d - xi (m).  INFINITY when the pair is within xi. */
static double pair_energy(const sw_model *m, int kind, const int *v, const double *x, double *g,
                          double *H, double *gap) {
  const sw_contact *c = &m->contact;
  double p[12], g2[12], H2[144], *h2 = H ? H2 : NULL;
  gather(x, v, p);
  double d2 = kind == SW_MC_PT ? sw_d2_point_triangle(p, p + 3, p + 6, p + 9, g2, h2)
                               : sw_d2_edge_edge(p, p + 3, p + 6, p + 9, g2, h2);
  double xi2 = c->thickness * c->thickness, s = d2 - xi2, shat = sw_mesh_contact_shat(c);
  *gap = sqrt(fmax(d2, 0.0)) - c->thickness;
  if (!(s > 0.0)) return INFINITY;
  if (s >= shat) return 0.0;
  double w = 0.0;
  for (int k = 0; k < 4; k++) w += 0.25 * m->mass[v[k]];
  w *= c->kappa_mesh; /* kg/(s^2 m^2) */
  double bg[12], bH[144], b = sw_barrier_of(12, s, g2, h2, shat, bg, H ? bH : NULL);
  if (kind == SW_MC_PT) {
    for (int i = 0; i < 12; i++) g[i] = w * bg[i];
    for (int i = 0; H && i < 144; i++) H[i] = w * bH[i];
    return w * b;
  }
  /* edge-edge: the mollifier vanishes as the edges become parallel (IPC sec. 4.3) */
  const double *q = m->x0;
  double r[12], mg[12], mH[144];
  gather(q, v, r);
  double eps = sw_ee_mollifier_eps(r, r + 3, r + 6, r + 9);
  double mo = sw_ee_mollifier(p, p + 3, p + 6, p + 9, eps, mg, H ? mH : NULL);
  double e = sw_product_derivs(12, mo, mg, mH, b, bg, bH, g, H);
  for (int i = 0; i < 12; i++) g[i] *= w;
  for (int i = 0; H && i < 144; i++) H[i] *= w;
  return w * e;
}

/* Evaluate the pairs of one kind the broad phase found: energy, gradient, the active list. */
static int eval_pairs(const sw_model *m, const sw_eval *ev, sw_mcontact *mc, int kind,
                      const int *q, int n, double *e) {
  const int want_h = ev->hess != NULL;
  for (int k = 0; k < n; k++) {
    int v[4];
    double g[12], gap, Hb[144];
    pair_vertices(m, mc, kind, q + 2 * k, v);
    double ek = pair_energy(m, kind, v, ev->x, g, want_h ? Hb : NULL, &gap);
    mc->min_gap = fmin(mc->min_gap, gap);
    if (!isfinite(ek)) {
      sw_eval_why(ev, "%s pair (vertices %d %d %d %d) closer than the thickness (gap %g m)",
                  kind == SW_MC_PT ? "point-triangle" : "edge-edge", v[0], v[1], v[2], v[3],
                  gap);
      return SW_RECOVER;
    }
    if (gap >= m->contact.dhat) continue;
    if (reserve_pair(mc)) return SW_FATAL;
    sw_mc_pair *pr = &mc->pair[mc->npair];
    pr->kind = kind;
    memcpy(pr->v, v, sizeof v);
    pr->gap = gap;
    if (want_h) {
      sw_psd_project(Hb, 12, SW_FILTER_CLAMP); /* a barrier's Hessian is indefinite */
      memcpy(mc->block + (size_t)mc->npair * 144, Hb, sizeof Hb);
    }
    mc->npair++;
    *e += ek;
    for (int j = 0; ev->grad && j < 12; j++) ev->grad[3 * v[j / 3] + j % 3] += g[j];
  }
  return SW_OK;
}

static int mc_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  (void)t;
  sw_mcontact *mc = ev->mc;
  *energy = 0.0;
  if (!mc) {
    sw_eval_why(ev, "no contact workspace (an evaluation outside a run)");
    return SW_FATAL;
  }
  mc->npair = 0;
  mc->have_blocks = ev->hess != NULL;
  mc->min_gap = INFINITY;
  double r = 0.5 * (m->contact.thickness + m->contact.dhat); /* m */
  sw_bp_input in = bp_input(m, mc, ev->x, ev->x, r);
  if (sw_broadphase_query(&mc->bp, &in, SW_BP_PT | SW_BP_EE)) {
    sw_eval_why(ev, "the broad phase failed (positions not finite, or out of memory)");
    return SW_RECOVER;
  }
  int rc = SW_OK;
  for (int kind = SW_MC_PT; !rc && kind <= SW_MC_EE; kind++) {
    int n;
    const int *q = candidates(mc, kind, &n);
    rc = eval_pairs(m, ev, mc, kind, q, n, energy);
  }
  return rc;
}

static void mc_free(void *param) {
  mc_param *p = param;
  if (!p) return;
  sw_free(p->edge);
  sw_free(p);
}

static const sw_term_ops mc_ops = {.kind = "mesh_contact", .eval = mc_eval,
                                   .free_param = mc_free};

int sw_mesh_contact_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  t->ops = &mc_ops;
  snprintf(t->name, sizeof t->name, "%s", "mesh_contact");
  sw_topology tp;
  if (sw_term_alloc_stencils(t, 0, 1, m->dim) || sw_topology_build(&tp, m, err, errsz)) {
    sw_errf(err, errsz, "out of memory for the mesh contact term");
    return -1;
  }
  mc_param *p = sw_calloc(1, sizeof *p);
  if (!p) {
    sw_topology_free(&tp);
    sw_errf(err, errsz, "out of memory for the mesh contact term");
    return -1;
  }
  p->ne = tp.ne;
  p->edge = tp.ev;
  tp.ev = NULL;
  sw_topology_free(&tp);
  t->param = p;
  return 0;
}

/* ------------------------------------------------------------ the solvers' side */

double sw_mcontact_toi(const sw_model *m, sw_mcontact *mc, const double *x0, const double *x1,
                       double *time_bp) {
  if (!mc) return 1.0;
  double t0 = sw_now();
  sw_bp_input in = bp_input(m, mc, x0, x1, 0.5 * m->contact.thickness);
  int rc = sw_broadphase_query(&mc->bp, &in, SW_BP_PT | SW_BP_EE);
  *time_bp += sw_now() - t0;
  if (rc) return 0.0;
  double toi = 1.0;
  for (int kind = SW_MC_PT; kind <= SW_MC_EE; kind++) {
    int n;
    const int *q = candidates(mc, kind, &n);
    for (int k = 0; k < n && toi > 0.0; k++) {
      int v[4];
      double a[12], b[12];
      pair_vertices(m, mc, kind, q + 2 * k, v);
      gather(x0, v, a);
      gather(x1, v, b);
      toi = kind == SW_MC_PT ? sw_ccd_point_triangle(a, b, m->contact.thickness, toi)
                             : sw_ccd_edge_edge(a, b, m->contact.thickness, toi);
    }
  }
  return toi;
}

int sw_mcontact_settled(const sw_model *m, const sw_mcontact *mc, const double *x0,
                        const double *x1) {
  for (int k = 0; mc && k < mc->npair; k++) {
    const sw_mc_pair *p = &mc->pair[k];
    double move = 0.0;
    for (int j = 0; j < 4; j++) {
      const double *a = x0 + 3 * (size_t)p->v[j], *b = x1 + 3 * (size_t)p->v[j];
      double s = 0.0;
      for (int c = 0; c < 3; c++) s += (b[c] - a[c]) * (b[c] - a[c]);
      move = fmax(move, sqrt(s)); /* m */
    }
    if (move > SW_CONTACT_SETTLE * p->gap) return 0;
  }
  (void)m;
  return 1;
}

int sw_mcontact_begin(const sw_model *m, sw_data *d, double *y) {
  if (!d->mc) return SW_OK;
  double s = sw_mcontact_toi(m, d->mc, d->x, y, &d->time_broadphase);
  if (s >= 1.0) return SW_OK;
  const int nd = m->nv * m->dim;
  for (int i = 0; i < nd; i++) y[i] = d->x[i] + s * (y[i] - d->x[i]);
  return SW_OK;
}

int sw_mcontact_check_start(const sw_model *m, const double *x, char *err, size_t errsz) {
  if (!m->contact.self) return 0;
  long cross = sw_mesh_self_intersections(m->nv, x, m->nf, m->face);
  if (cross != 0) {
    sw_errf(err, errsz, cross < 0 ? "out of memory checking the mesh for self-intersections"
                                  : "the mesh intersects itself (%ld pairs of triangles)", cross);
    return -1;
  }
  sw_mcontact *mc = sw_mcontact_new(m);
  if (!mc) return sw_errf(err, errsz, "out of memory for the contact workspace"), -1;
  sw_bp_input in = bp_input(m, mc, x, x, 0.5 * m->contact.thickness);
  int rc = sw_broadphase_query(&mc->bp, &in, SW_BP_PT | SW_BP_EE);
  for (int kind = SW_MC_PT; !rc && kind <= SW_MC_EE; kind++) {
    int n;
    const int *q = candidates(mc, kind, &n);
    for (int k = 0; k < n && !rc; k++) {
      int v[4];
      double g[12], gap;
      pair_vertices(m, mc, kind, q + 2 * k, v);
      if (!isfinite(pair_energy(m, kind, v, x, g, NULL, &gap))) {
        sw_errf(err, errsz, "vertices %d %d %d %d (%s) start %g m apart, within the thickness "
                "%g m", v[0], v[1], v[2], v[3], kind == SW_MC_PT ? "a point and a triangle" :
                "two edges", gap + m->contact.thickness, m->contact.thickness);
        rc = 1;
      }
    }
  }
  sw_mcontact_free(mc);
  return rc ? -1 : 0;
}

void sw_mcontact_state(const sw_model *m, sw_data *d) {
  sw_mcontact *mc = d->mc;
  if (!mc) return;
  d->self_count = 0;
  d->self_min = INFINITY;
  d->self_force = 0.0;
  memset(mc->vforce, 0, (size_t)m->nv * sizeof(double));
  double r = 0.5 * (m->contact.thickness + m->contact.dhat);
  sw_bp_input in = bp_input(m, mc, d->x, d->x, r);
  if (sw_broadphase_query(&mc->bp, &in, SW_BP_PT | SW_BP_EE)) return;
  double *f = mc->xa; /* (nv x 3) the contact force on each vertex, N */
  memset(f, 0, (size_t)m->nv * 3 * sizeof(double));
  for (int kind = SW_MC_PT; kind <= SW_MC_EE; kind++) {
    int n;
    const int *q = candidates(mc, kind, &n);
    for (int k = 0; k < n; k++) {
      int v[4];
      double g[12], gap;
      pair_vertices(m, mc, kind, q + 2 * k, v);
      double e = pair_energy(m, kind, v, d->x, g, NULL, &gap);
      if (!isfinite(e) || gap >= m->contact.dhat) continue;
      d->self_min = fmin(d->self_min, gap);
      d->self_count++;
      for (int j = 0; j < 12; j++) f[3 * v[j / 3] + j % 3] -= g[j];
    }
  }
  for (int i = 0; i < m->nv; i++) {
    double s = 0.0;
    for (int a = 0; a < 3; a++) s += f[3 * i + a] * f[3 * i + a];
    mc->vforce[i] = sqrt(s);
    d->self_force += 0.5 * mc->vforce[i]; /* each pair pushes both sides: half is one side */
  }
}

const double *sw_mcontact_vertex_force(const sw_mcontact *mc) { return mc ? mc->vforce : NULL; }
