/* contact_geom.h — the geometry of contact: squared distances between primitives with exact
 * gradients and Hessians, the IPC barrier and edge-edge mollifier (models/distance.c), additive
 * continuous collision detection (models/ccd.c), a spatial-hash broad phase
 * (models/broadphase.c) and exact intersection predicates (models/intersect.c).
 *
 * Sources: Li, Ferguson, Schneider, Langlois, Zorin, Panozzo, Jiang, Kaufman, "Incremental
 * Potential Contact: Intersection- and Inversion-free, Large-Deformation Dynamics", SIGGRAPH
 * 2020 (IPC: distances, barrier, mollifier); Li, Kaufman, Jiang, "Codimensional Incremental
 * Potential Contact", SIGGRAPH 2021 (C-IPC: additive CCD); Shewchuk, "Adaptive Precision
 * Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997 (exact orientation).
 *
 * Conventions: points are double[3] in metres; derivative arrays are vertex-major over the
 * primitives' vertices in the order of the arguments (g[3*i + a] is d/d(vertex i, axis a)), and
 * Hessians are dense row-major (3n x 3n).  g and H may be NULL.  Squared distances are in m^2,
 * their gradients in m and their Hessians dimensionless. */
#ifndef SW_CONTACT_GEOM_H
#define SW_CONTACT_GEOM_H

#include <stddef.h>

/* ---------------------------------------------------------------- distances (distance.c) */

/* The closest features of a point and an edge (p, e0, e1): an end point or the interior. */
typedef enum { SW_PE_E0, SW_PE_E1, SW_PE_LINE } sw_pe_type;
/* The closest features of a point and a triangle (p, t0, t1, t2): a vertex, an edge
 * (E01 = t0t1, E12 = t1t2, E20 = t2t0) or the interior (the plane). */
typedef enum {
  SW_PT_T0, SW_PT_T1, SW_PT_T2, SW_PT_E01, SW_PT_E12, SW_PT_E20, SW_PT_PLANE
} sw_pt_type;
/* The closest features of two edges (a0 a1) and (b0 b1): two end points (A0B0 ...), an end
 * point and the other edge's interior (A0_B: a0 and edge b; A_B0: edge a and b0 ...), or both
 * interiors (LINES: line-line). */
typedef enum {
  SW_EE_A0B0, SW_EE_A0B1, SW_EE_A1B0, SW_EE_A1B1,
  SW_EE_A0_B, SW_EE_A1_B, SW_EE_A_B0, SW_EE_A_B1, SW_EE_LINES
} sw_ee_type;

/* |p - q|^2 (m^2); g: 6, H: 36. */
double sw_d2_point_point(const double p[3], const double q[3], double *g, double *H);
/* Squared distance from p to the line through e0, e1 (m^2; unclamped); g: 9, H: 81.  These
 * four take the features as given: for a degenerate edge or triangle, or parallel lines, they
 * return |p - e0|^2, |p - t0|^2 or |a0 - b0|^2 instead (the classified functions below never
 * ask for those cases). */
double sw_d2_point_line(const double p[3], const double e0[3], const double e1[3], double *g,
                        double *H);
/* Squared distance from p to the plane of t0, t1, t2 (m^2); g: 12, H: 144. */
double sw_d2_point_plane(const double p[3], const double t0[3], const double t1[3],
                         const double t2[3], double *g, double *H);
/* Squared distance between the lines a0a1 and b0b1 (m^2; not parallel); g: 12, H: 144. */
double sw_d2_line_line(const double a0[3], const double a1[3], const double b0[3],
                       const double b1[3], double *g, double *H);

/* Which features are closest (a degenerate edge or triangle gives an end point or an edge). */
sw_pe_type sw_point_edge_type(const double p[3], const double e0[3], const double e1[3]);
sw_pt_type sw_point_triangle_type(const double p[3], const double t0[3], const double t1[3],
                                  const double t2[3]);
sw_ee_type sw_edge_edge_type(const double a0[3], const double a1[3], const double b0[3],
                             const double b1[3]);

/* Squared distances between the closed primitives (m^2): the distance of the closest features
 * (by the classifiers above) with its exact gradient and Hessian over all coordinates, zero
 * for the vertices that feature does not involve.  point-edge: p, e0, e1 (g: 9, H: 81);
 * point-triangle: p, t0, t1, t2 and edge-edge: a0, a1, b0, b1 (g: 12, H: 144). */
double sw_d2_point_edge(const double p[3], const double e0[3], const double e1[3], double *g,
                        double *H);
double sw_d2_point_triangle(const double p[3], const double t0[3], const double t1[3],
                            const double t2[3], double *g, double *H);
double sw_d2_edge_edge(const double a0[3], const double a1[3], const double b0[3],
                       const double b1[3], double *g, double *H);

/* A lower bound of sw_d2_edge_edge's true squared distance (m^2): below the parallel switch
 * (sin^2 of the angle < 1e-14) the end points' distance exceeds the segments' by at most
 * 2 sin^2 min(|ea|, |eb|)^2 in d^2, and round-off by 1e-11 (longer edge + d) in d; both are
 * taken off.  What continuous collision detection uses, so that it never steps past a contact. */
double sw_d2_edge_edge_lower(const double a0[3], const double a1[3], const double b0[3],
                             const double b1[3]);

/* IPC's edge-edge mollifier (Li et al. 2020, sec. 4.3): with c = |(a1 - a0) x (b1 - b0)|^2
 * (m^4) and eps_x = 1e-3 |a1 - a0|^2 |b1 - b0|^2 at rest (sw_ee_mollifier_eps, m^4),
 * m = (2 - c/eps_x) c/eps_x for c < eps_x and 1 beyond; it multiplies the edge-edge barrier
 * so that it vanishes smoothly as the edges become parallel.  Returns m (dimensionless),
 * g (12, 1/m) and H (144, 1/m^2) over a0, a1, b0, b1. */
double sw_ee_mollifier_eps(const double a0[3], const double a1[3], const double b0[3],
                           const double b1[3]);
double sw_ee_mollifier(const double a0[3], const double a1[3], const double b0[3],
                       const double b1[3], double eps_x, double *g, double *H);
/* m(x) sw_d2_edge_edge(x) with its gradient (12) and Hessian (144): m^2 units. */
double sw_d2_edge_edge_mollified(const double a0[3], const double a1[3], const double b0[3],
                                 const double b1[3], double eps_x, double *g, double *H);
/* The product rule: given f, its gradient fg and Hessian fH and the same for h over n
 * coordinates (n <= 12), returns f h and writes its gradient g and Hessian H (NULL skips;
 * g and H may not alias the inputs).  fH, hH are needed only for H. */
double sw_product_derivs(int n, double f, const double *fg, const double *fH, double h,
                         const double *hg, const double *hH, double *g, double *H);

/* IPC's barrier (Li et al. 2020, eq. 6) in the form ipc-toolkit evaluates it on squared
 * distances: b(d2) = -(d2 - dhat2)^2 ln(d2 / dhat2) for 0 < d2 < dhat2 (d2 the squared
 * distance, dhat2 the squared activation distance, m^2; b in m^4), 0 beyond, +inf for d2 <= 0.
 * This is IPC's b(d; dhat) with d -> d2 and dhat -> dhat2: C2 at dhat2, unbounded at 0.
 * db = b'(d2) (m^2), d2b = b''(d2) (dimensionless); NULL skips. */
double sw_barrier(double d2, double dhat2, double *db, double *d2b);
/* The chain rule for b(d2(x)): from d2, its gradient g2 and Hessian H2 over n coordinates
 * (n <= 12), b and its gradient g and Hessian H (b' H2 + b'' g2 g2^T); NULL skips. */
double sw_barrier_of(int n, double d2, const double *g2, const double *H2, double dhat2,
                     double *g, double *H);

/* ------------------------------------------------- barrier blocks (barrier_block.c) */

/* A pair's squared distance as distance.c's form r = sum_i c_i x_i (closest points), with what
 * its Hessian and a closed-form positive semi-definite barrier block need: Hess d2 =
 * 2 c c^T (x) I - 2 sum_m v_m v_m^T (models/barrier_block.c).  Over the pair's 4 vertices,
 * vertex-major (a vertex the closest features leave out has zeros). */
typedef struct sw_pair_form {
  double d2;        /* m^2 */
  double g[12];     /* grad d2, m */
  double c[4];      /* the closest points' coefficients (1) */
  int k;            /* parameters of the closest features (0, 1, 2) */
  double v[2][12];  /* the sliding directions' factors (dimensionless) */
} sw_pair_form;
/* 1 when the point-triangle (edge_edge 0: p, t0, t1, t2) or edge-edge (1: a0, a1, b0, b1) pair
 * at p (12 values) is certainly farther apart than r (m): a cheap test, 0 does not mean closer. */
int sw_pair_apart(int edge_edge, const double *p, double r);
/* The form of a point-triangle (edge_edge 0: p, t0, t1, t2) or edge-edge (1: a0, a1, b0, b1)
 * pair at x (12 values); returns d2 (as sw_d2_point_triangle / sw_d2_edge_edge). */
double sw_pair_d2_form(int edge_edge, const double *x, sw_pair_form *pf);
/* The same, but when d2 is at least d2max (m^2) only pf->d2 is set: a pair beyond the
 * barrier's reach needs no more of its form. */
double sw_pair_d2_form_near(int edge_edge, const double *x, double d2max, sw_pair_form *pf);
/* The exact Hessian of d2 from its form (144), for tests. */
void sw_pair_hess_d2(const sw_pair_form *pf, double *H);
/* The exact Hessian of the barrier w b(d2 - xi^2) (db = b', d2b = b'' at d2 - xi^2) with its
 * negative eigenvalues clamped at 0 (the nearest positive semi-definite matrix), into H (144),
 * found on the span of its columns (at most 5: models/barrier_block.c).  0, or -1 when not
 * finite. */
int sw_pair_barrier_block(const sw_pair_form *pf, double db, double d2b, double w, double *H);
/* The same block in closed form (k >= 1: the closest features are not two points), without an
 * eigen-decomposition (models/barrier_block.c): 1, or 0 (H undefined) when the closed form
 * cannot give it to round-off (then sw_pair_barrier_block decomposes the span instead). */
int sw_pair_clamp_closed(const sw_pair_form *pf, double db, double d2b, double w, double *H);
/* H (144, symmetric, over 4 vertices) with its negative eigenvalues clamped at 0, for a block
 * of an energy that a common translation of the 4 vertices does not change (H (1 (x) e) = 0):
 * found on the 9 dimensions orthogonal to the translations, the same block as a 12 x 12
 * clamp to round-off at about half its cost.  0, or -1 when not finite. */
int sw_pair_clamp_free(double *H);

/* ------------------------------------------------------------------------- CCD (ccd.c) */

/* C-IPC's scaling s (Li, Kaufman, Jiang 2021, Algorithm 1): CCD stops before the gap
 * d - dmin falls below s times its value at the start, and advances by at most (1 - s) of the
 * current gap per iteration.  0.1: what the IPC Toolkit's default rescaling 0.9 gives; a
 * larger s stops earlier, in fewer iterations. */
#define SW_CCD_SCALE 0.1
/* Additive CCD (C-IPC, sec. 5) of primitives moving linearly from x0 to x1 over a step
 * (vertex-major coordinates: p, t0, t1, t2 or a0, a1, b0, b1 — 12 values; p, e0, e1 — 9;
 * p, q — 6), with a minimum separation dmin >= 0 (m).  Returns toi in [0, tmax]: the
 * primitives at x0 + t (x1 - x0) stay more than dmin apart for every t in [0, toi], and at toi
 * their gap d - dmin is at least SW_CCD_SCALE times its value at t = 0.  tmax means no
 * impact before tmax; 0 when they start within dmin.  Conservative: each advance is bounded
 * by the gap over the largest relative displacement, so nothing tunnels. */
double sw_ccd_point_point(const double *x0, const double *x1, double dmin, double tmax);
double sw_ccd_point_edge(const double *x0, const double *x1, double dmin, double tmax);
double sw_ccd_point_triangle(const double *x0, const double *x1, double dmin, double tmax);
double sw_ccd_edge_edge(const double *x0, const double *x1, double dmin, double tmax);

/* ------------------------------------------------------------ broad phase (broadphase.c) */

/* Inputs of a query: one vertex array at the start and end of a step (x1 == x0 for a static
 * check), edges and faces over it, and which vertices are fixed (obstacle vertices; NULL: none).
 * Each primitive's box is that of its vertices at both times, enlarged by `inflate` (m) on
 * every side, so a pair whose boxes overlap may come within 2 inflate during the step. */
typedef struct sw_bp_input {
  int nv;
  const double *x0, *x1;       /* (nv x 3) positions at the start and end of the step, m */
  int ne;
  const int *edge;             /* (ne x 2) vertices of each edge */
  int nf;
  const int *face;             /* (nf x 3) vertices of each face */
  const unsigned char *fixed;  /* (nv) 1 = obstacle vertex, or NULL */
  double inflate;              /* m */
  int nsewn;                   /* vertices below this may be sewn (sw_model.sewn_ptr) */
  const int *sewn_ptr, *sewn_idx; /* vertices sewn together count as shared, or NULL */
} sw_bp_input;

enum { SW_BP_PT = 1, SW_BP_EE = 2, SW_BP_FF = 4 }; /* which pairs a query finds */

/* A uniform grid hashed by integer cell: each primitive goes into the cells its box covers,
 * entries are sorted by cell (radix sort), and each cell's primitives are paired when their
 * boxes overlap; a pair is reported only in the cell of its boxes' overlap's lower corner, so
 * once.  Pairs with a shared (or sewn) vertex, or whose vertices are all fixed, are skipped.  Buffers
 * persist across queries: no allocation once the capacity suffices. */
typedef struct sw_broadphase {
  int npt, nee, nff;           /* pairs found by the last query */
  int *pt;                     /* (npt x 2) vertex, face */
  int *ee;                     /* (nee x 2) edge e, edge e' > e */
  int *ff;                     /* (nff x 2) face f, face f' > f */
  double cell;                 /* grid spacing of the last query, m */
  /* private */
  size_t cap_pt, cap_ee, cap_ff, cap_box, cap_ent, cap_grp;
  double *box;                 /* (nv + ne + nf) x 6: lo[3], hi[3] */
  unsigned long long *key, *key2;
  int *code, *code2;           /* primitive of each entry: 3 * index + kind */
  struct sw_bp_entry *grp;     /* the primitives of one cell */
} sw_broadphase;

void sw_broadphase_init(sw_broadphase *bp);
/* Find the pairs `want` (SW_BP_* bits): vertex-face, edge-edge, face-face.  0, or -1 when out
 * of memory or the input is not finite (no pairs then). */
int sw_broadphase_query(sw_broadphase *bp, const sw_bp_input *in, int want);
/* The pairs of sw_broadphase_query (SW_BP_PT and SW_BP_EE only) that have a vertex v with
 * mark[v] != 0, each once, by testing the primitives that touch one against all: the cost
 * grows with the marked primitives times all, for a few moved vertices (models/mesh_contact.c).
 * -1 as sw_broadphase_query, or with SW_BP_FF. */
int sw_broadphase_query_marked(sw_broadphase *bp, const sw_bp_input *in, int want,
                               const unsigned char *mark);
void sw_broadphase_free(sw_broadphase *bp);

/* ---------------------------------------------------- bounding-volume hierarchy (bvh.c) */

/* A tree of boxes over n primitives 0..n-1 (the mesh obstacles' triangles), built
 * once from their boxes and refitted when they move: a query visits the primitives whose box
 * overlaps a given box, at a cost of the tree's depth (log2 n) per primitive found. */
typedef void (*sw_bvh_box_fn)(const void *ctx, int i, double b[6]); /* lo[3], hi[3], m */
typedef int (*sw_bvh_hit_fn)(void *arg, int i); /* nonzero stops the query and is returned */
typedef struct sw_bvh {
  int n, nnode;
  float *box;    /* (nnode x 6) node boxes (lo, hi), rounded outwards, m */
  int *node;     /* (nnode x 2) leaf: first of prim, count > 0; internal: left child, 0 (the
                    right child follows the left one) */
  int *prim;     /* (n) the primitives in leaf order */
  double *pbox;  /* (n x 6) NULL, or the primitives' own boxes (pbox + 6 i is primitive i's),
                    kept by sw_bvh_keep_boxes: a query reads them instead of asking its box
                    function */
} sw_bvh;

/* 0, -1 when out of memory, -2 when stopped by a signal (sw_interrupt) while building (t
 * then empty in both). */
int sw_bvh_build(sw_bvh *t, int n, sw_bvh_box_fn box, const void *ctx);
void sw_bvh_refit(sw_bvh *t, sw_bvh_box_fn box, const void *ctx);
/* Keep the primitives' boxes in the tree (48 bytes a primitive) and refit it: 0, -1 when out
 * of memory (t unchanged).  Later refits refresh them. */
int sw_bvh_keep_boxes(sw_bvh *t, sw_bvh_box_fn box, const void *ctx);
/* Call hit on every primitive whose box overlaps b (closed boxes): the primitives of every
 * leaf whose box does, each tested against b when box is not NULL (with ctx: the boxes the
 * tree was fitted to; the kept ones, t->pbox, when it has them).  0, or hit's first nonzero
 * return. */
int sw_bvh_query(const sw_bvh *t, const double b[6], sw_bvh_box_fn box, const void *ctx,
                 sw_bvh_hit_fn hit, void *arg);
void sw_bvh_free(sw_bvh *t);

/* ------------------------------------------------------- exact predicates (intersect.c) */

/* The sign (+1, 0, -1) of det[b - a; c - a; d - a] = ((b - a) x (c - a)) . (d - a), exact:
 * positive when d lies on the side of the plane abc that (b - a) x (c - a) points to (this is
 * Shewchuk's orient3d(b, c, d, a)). */
int sw_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]);
/* 1 when the closed segment ab and the closed triangle t0 t1 t2 share a point (touching
 * counts; degenerate segments and triangles are handled), exactly. */
int sw_segment_triangle_intersect(const double a[3], const double b[3], const double t0[3],
                                  const double t1[3], const double t2[3]);
/* 1 when two closed triangles share a point (an edge of one meets the other), exactly; for
 * triangles with no shared vertex. */
int sw_triangles_intersect(const double p0[3], const double p1[3], const double p2[3],
                           const double q0[3], const double q1[3], const double q2[3]);
/* The number of pairs of faces with no shared vertex that intersect (x: nv x 3, faces:
 * nf x 3), with the broad phase; -1 when out of memory, -2 when stopped by a signal
 * (cancel.h: sw_cancelled, polled every 65536 candidate pairs). */
long sw_mesh_self_intersections(int nv, const double *x, int nf, const int *faces);
/* The same where faces with vertices sewn together (sw_model.sewn_ptr, sewn_idx over the
 * first nv vertices; NULL: none) count as sharing one: a closed seam's two sides touch. */
long sw_mesh_self_intersections_sewn(int nv, const double *x, int nf, const int *faces,
                                     const int *sewn_ptr, const int *sewn_idx);

#endif
