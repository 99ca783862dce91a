/* terms.h — constructors of the energy terms (one file each in models/) and the shared
 * helpers they use to declare their Hessian stencils. */
#ifndef SW_TERMS_H
#define SW_TERMS_H

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "sinew.h"

/* blk(r, c) += v for a block stored as its upper triangle (sw_hess_upper): an entry below the
 * diagonal is dropped, since its mirror above is added by the same loop. */
static inline void sw_hess_add(double *blk, int w, int r, int c, double v) {
  if (r <= c) blk[sw_hess_upper(r, c, w)] += v;
}
/* blk(r, c) = v, the same way (the terms with sets_blocks). */
static inline void sw_hess_set(double *blk, int w, int r, int c, double v) {
  if (r <= c) blk[sw_hess_upper(r, c, w)] = v;
}
/* Add (set) the upper triangle of the full symmetric w x w matrix A (row-major) into blk. */
static inline void sw_hess_add_full(double *blk, int w, const double *A) {
  for (int r = 0; r < w; r++)
    for (int c = r; c < w; c++) *blk++ += A[r * w + c];
}
static inline void sw_hess_set_full(double *blk, int w, const double *A) {
  for (int r = 0; r < w; r++)
    for (int c = r; c < w; c++) *blk++ = A[r * w + c];
}

/* Where stencil s's block is written: its place in ev->hess, or with a sink (sw_hsink) the
 * sink's scratch block, zeroed unless the term sets every entry (sets_blocks).  Hand the block
 * over with sw_ev_block_done once it is written. */
static inline double *sw_ev_block(const sw_eval *ev, const sw_term *t, long s) {
  if (!ev->sink) return ev->hess + t->hptr[s];
  if (!t->ops->sets_blocks)
    memset(ev->sink->blk, 0, (size_t)(t->hptr[s + 1] - t->hptr[s]) * sizeof(double));
  return ev->sink->blk;
}
/* The block blk over the nv vertices v (its upper triangle, sw_hess_upper) added into values
 * through sl, entry by entry in their stored order: entry (r, c) of vertices a = v[r / dim],
 * b = v[c / dim] into the slot of its DOFs (the pair (min, max)), and twice when its two DOFs
 * are one and r != c (a vertex twice in the stencil: the entry and its mirror both land on
 * that diagonal entry).  Pinned components are dropped (models/term.c). */
void sw_slots_add(const sw_slots *sl, const int *v, int nv, const double *blk, double *values);

/* With a sink, block s (at blk, from sw_ev_block) added into its system (sw_slots_add);
 * nothing without one. */
static inline void sw_ev_block_done(const sw_eval *ev, const sw_term *t, long s,
                                    const double *blk) {
  if (!ev->sink) return;
  sw_slots_add(ev->sink->slots, t->sidx + t->sptr[s], t->sptr[s + 1] - t->sptr[s], blk,
               ev->sink->values);
}

/* Allocate nstencil stencils of `per` vertices each (sidx left for the caller to fill) and
 * set hptr for blocks of (per*dim)^2 doubles.  Nonzero when out of memory. */
int sw_term_alloc_stencils(sw_term *t, int nstencil, int per, int dim);
void sw_term_free(sw_term *t);

/* sim/data.c: the terms' optional operations of the run (sw_term_ops), on every term that has
 * one, in the order of m->term.  sw_terms_state: each term's diagnostics of d, then the faces'
 * contact pressure (d->contact_pressure: per face, the mean over its corners of the terms'
 * summed |contact force| / the corner's share of the rest area, N/m^2); sw_terms_commit: each
 * term's commit; sw_terms_dissipate: 1 when a term dissipates (friction). */
void sw_terms_state(const sw_model *m, sw_data *d);
void sw_terms_commit(const sw_model *m, sw_data *d);
int sw_terms_dissipate(const sw_model *m);

/* An eigenvalue lam of a Hessian after the filter `mode` (SW_FILTER_*, sinew.h): unchanged
 * (none), clamped at 0 (clamp), or its absolute value (abs).  A NaN stays NaN. */
static inline double sw_filter_eigenvalue(double lam, int mode) {
  return mode == SW_FILTER_ABS ? fabs(lam) : mode == SW_FILTER_CLAMP && lam < 0.0 ? 0.0 : lam;
}

/* Membranes (models/term.c): a term with one 3-vertex stencil per face whose material uses the
 * model, energy sum_f a_f psi(wu, wv).  `density` returns psi (J/m^2 = N/m) of the material
 * constants `law` and fills gu = dpsi/dwu, gv = dpsi/dwv (d each, N/m) and, when P is not NULL,
 * P = d2psi/d(wu,wv)^2 (2d x 2d row-major, N/m), its eigenvalues filtered by `project`
 * (SW_FILTER_*); NaN on failure. */
typedef double (*sw_membrane_density)(const void *law, const double *wu, const double *wv,
                                      int d, int project, double *gu, double *gv, double *P);
typedef struct sw_membrane {
  sw_membrane_density density;
  int *face;                   /* (nstencil) the face of each stencil */
  double *cu, *cv;             /* (nstencil x 3) corner coefficients of wu and wv, 1/m */
  void *law;                   /* (nmat) constants of each material, lawsz bytes each; the
                                  builder fills those of the materials that use the model */
  size_t lawsz;
} sw_membrane;

/* Make t the membrane ops->kind on the faces whose material has membrane == model: stencils,
 * coefficients, zeroed laws.  t->param is the result (free it with sw_term_free); NULL and err
 * when out of memory. */
sw_membrane *sw_membrane_new(sw_term *t, const sw_model *m, const sw_term_ops *ops, int model,
                             size_t lawsz, sw_membrane_density density, char *err, size_t errsz);
/* Say in ev->why (when asked for and still empty) which element made eval fail and why. */
void sw_eval_why(const sw_eval *ev, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
int sw_membrane_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy);
void sw_membrane_free(void *param);
/* Small symmetric matrices (models/eigen.c), n <= SW_EIGEN_NMAX, row-major.  sw_sym_eigen:
 * A = V diag(w) V^T, A becomes V (column k: the eigenvector of w[k]); 0, or -1 when n is out of
 * range or the iteration does not converge.  sw_sym_is_pd: 1 when A is positive definite to
 * floating point (its Cholesky factorisation completes).  sw_contrast_reduce/lift, for a block
 * H (3 nv x 3 nv) of an energy of nv vertices in 3D that a translation leaves unchanged:
 * M = Q^T H Q (3 nv - 3 square) on the orthonormal differences Q of the vertices' motions
 * (Helmert's contrasts), and H = Q M Q^T back. */
#define SW_EIGEN_NMAX 18
int sw_sym_eigen(double *A, int n, double *w);
int sw_sym_is_pd(const double *A, int n);
void sw_contrast_reduce(const double *H, int nv, double *M);
void sw_contrast_lift(const double *M, int nv, double *H);
/* Filter the eigenvalues of the symmetric n x n matrix A (row-major, n <= SW_EIGEN_NMAX) by
 * `mode` (SW_FILTER_*): SW_FILTER_CLAMP gives its nearest positive semi-definite matrix,
 * SW_FILTER_ABS V |Lambda| V^T; A is unchanged when it is PSD already, or for SW_FILTER_NONE.
 * Only the rows and columns that are not all zero are decomposed (sw_sym_eigen); the zero
 * ones stay zero.  0, or -1 when n is out of range or A is not finite. */
int sw_psd_project(double *A, int n, int mode);
/* The Voigt Green strain e = ((|wu|^2 - 1)/2, (|wv|^2 - 1)/2, wu.wv) of F = [wu wv] (d each),
 * and the columns of F S, gu = S11 wu + S12 wv, gv = S12 wu + S22 wv, of a stress s = (S11, S22,
 * S12) (N/m): dpsi/dwu and dpsi/dwv of a density of e (stvk, dde). */
static inline void sw_green_voigt(const double *wu, const double *wv, int d, double e[3]) {
  double uu = 0.0, vv = 0.0, uv = 0.0;
  for (int a = 0; a < d; a++) uu += wu[a] * wu[a], vv += wv[a] * wv[a], uv += wu[a] * wv[a];
  e[0] = 0.5 * (uu - 1.0), e[1] = 0.5 * (vv - 1.0), e[2] = uv;
}
static inline void sw_green_forces(const double s[3], const double *wu, const double *wv, int d,
                                   double *gu, double *gv) {
  for (int a = 0; a < d; a++) {
    gu[a] = s[0] * wu[a] + s[2] * wv[a];
    gv[a] = s[2] * wu[a] + s[1] * wv[a];
  }
}
/* The filtered P (2d x 2d) of a density that depends on F only through C = F^T F (stvk,
 * corotated), from the filtered in-plane and out-of-plane blocks (sw_psd_project).  0 or -1. */
int sw_membrane_project(double *P, const double *wu, const double *wv, int d, int mode);

/* models/bw98.c: Baraff-Witkin stretch and shear (Baraff and Witkin, "Large Steps in Cloth Simulation", 1998). */
int sw_bw98_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/stvk.c: orthotropic Saint Venant-Kirchhoff on the Green strain (docs/models.md). */
int sw_stvk_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/corotated.c: k/2 |U - I|^2, U = sqrt(F^T F) (docs/models.md). */
int sw_corotated_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/tendon.c: every tendon of the model in one term "tendons" (docs/tendons.md
 * "Tendons", docs/tendons.md): tendons of at most m->opt.tendon_dense_max waypoints as one
 * dense stencil each; longer ones as one 2-vertex stencil per segment (E' d2Delta) and one
 * low-rank vector sqrt(E'') grad(Delta). */
int sw_tendon_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* grad l (= grad Delta) of a tendon at its waypoint a (0..nway-1), d components (docs/tendons.md). */
void sw_tendon_grad(const sw_tendon *td, const double *x, int d, int a, double *g);
/* models/gravity.c: E = -sum_i m_i g.x_i (no Hessian, no stencils). */
int sw_gravity_build(sw_term *t, const sw_model *m, char *err, size_t errsz);

/* models/springs.c: mass-spring network, E = sum k/2 (|x_i - x_j| - L)^2 over stretch springs
 * (edges), shear springs (both diagonals of each quad) and bend springs (far vertices across
 * interior edges), docs/models.md "springs". */
int sw_springs_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
enum { SW_SPRING_STRETCH = 0, SW_SPRING_SHEAR = 1, SW_SPRING_BEND = 2 };
/* How many springs of each kind (SW_SPRING_*) a springs term holds. */
void sw_springs_counts(const sw_term *t, int count[3]);
/* models/dihedral.c: discrete-shells bending (Grinspun et al. 2003), 3D only. */
int sw_dihedral_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/quadratic_bending.c: isometric bending (Bergou et al. 2006), constant Hessian. */
int sw_quadratic_bending_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/dde_bending.c: the measured fabric's bending, its rigidities depending on the
 * curvature (docs/fabrics.md, "Bending by the data"). */
int sw_dde_bending_build(sw_term *t, const sw_model *m, char *err, size_t errsz);

/* models/topology.c: the edges of the mesh, for the edge-based terms (built at set-up). */
typedef struct sw_topology {
  int ne;          /* unique edges */
  int *ev;         /* (ne x 2) the vertex pair of each edge, ev[0] < ev[1] */
  int *ef;         /* (ne x 2) the faces on each side; ef[1] = -1 on a boundary edge (and on a
                      non-manifold one: only its lowest-numbered face is kept) */
  int *efar;       /* (ne x 2) each face's vertex opposite the edge, -1 where ef is -1 */
  int nonmanifold; /* edges with more than two faces */
} sw_topology;
int sw_topology_build(sw_topology *tp, const sw_model *m, char *err, size_t errsz);
void sw_topology_free(sw_topology *tp);
/* Distance between vertices va and vb in face f's own (u,v) layout, m. */
double sw_face_uv_distance(const sw_model *m, int f, int va, int vb);
/* Rest distance of the far vertices of interior edge e: the two faces unfolded flat about the
 * edge, each in its own (u,v) layout (so it is defined across a seam), m. */
double sw_edge_far_distance(const sw_model *m, const sw_topology *tp, int e);
/* One hinge of a bending triangle (models/bending.c): the triangle's edge opposite its corner k,
 * bent against the face far_face across it.  v: stencil-local vertices x0, x1 (the edge, in the
 * triangle's corner order), x2 (the triangle's own corner k), x3 (the far vertex across). */
typedef struct sw_bend_hinge {
  int k, far_face, v[4];
  double len;      /* rest edge length: mean of its length in the two faces' (u,v), m */
} sw_bend_hinge;
/* One bending triangle: its energy is (1/2) sum_ab W_ab theta_a theta_b over its interior
 * edges (hinges), theta the bending of each (docs/models.md "Bending"). */
typedef struct sw_bend_tri {
  int face, nv, nh;
  int v[6];               /* stencil: the face's 3 corners, then the far vertex of each hinge */
  sw_bend_hinge h[3];
  double W[3][3];         /* J/rad^2, positive semi-definite */
  double M[3][3];         /* the triangle's curvature II_T = sum_a M[.][a] theta_a in the basis
                             (II_uu, II_vv, sqrt(2) II_uv), its free edges' curvature condensed
                             with the rigidities D (so W = A M^T diag(D) M), 1/m per rad */
  double kb;              /* the face material's bending stiffness, N m */
  int rest_flat;          /* 1: rest angles 0; 0: the angles in x0 */
} sw_bend_tri;
/* The faces whose material bends with `model` (SW_BENDING_*), with k_bend > 0 and at least one
 * interior edge, in a new array of *n (sw_free it; NULL with err when out of memory). */
sw_bend_tri *sw_bend_tris(const sw_model *m, int model, int *n, char *err, size_t errsz);
/* Stencils of t: one per triangle, its nv vertices.  Nonzero when out of memory. */
int sw_bend_alloc_stencils(sw_term *t, const sw_bend_tri *tri, int n, int dim);
/* Bergou's K (6, on the stencil's local vertices) of hinge h of triangle tr: v_h = sum_i K_i x_i,
 * of length ~ |e| theta for an isometric bending (models/quadratic_bending.c). */
void sw_bend_hinge_K(const sw_model *m, const sw_bend_tri *tr, const sw_bend_hinge *h, double *K);
/* Local corner (0..2) of vertex v in face f, or -1 (models/bending.c). */
int sw_face_corner(const sw_model *m, int f, int v);
/* For each face corner k, the edge of tp opposite it (-1: none recorded, a non-manifold
 * extra), in a new array of 3 nf (sw_free it; NULL when out of memory). */
int *sw_face_edges(const sw_model *m, const sw_topology *tp);
/* The bending rigidities (N m) of material mt in the basis (II_uu, II_vv, sqrt(2) II_uv):
 * D = (D_u, D_v, 2 G) (docs/models.md "Anisotropic bending"). */
void sw_plate_rigidity(const sw_material *mt, double D[3]);
/* models/morley_bending.c: Morley's constant-curvature triangle with mid-edge slopes from a
 * quadratic fitted around each edge; constant Hessian (docs/models.md "morley"). */
int sw_morley_bending_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* models/compact.c: the compact Newton matrix of a bending term with a constant Hessian
 * Q (x) I, Q = sum_s Q_s on the term's stencils (Q_s at Q + s ldq^2, row-major, ldq wide):
 * the entries between vertices that share no face moved onto the diagonal as their absolute
 * values (C >= Q), C split onto the faces.  sw_compact_stencils keeps t's stencils in c (for
 * the term's energy and gradient) and makes t's stencils the mesh's faces; sw_compact_hess
 * adds C (x) I into their blocks (sw_ev_block of ev). */
typedef struct sw_compact {
  int *sptr, *sidx;  /* the term's own stencils' vertices (as sw_term's) */
  double *C;         /* (nf x 9) each face's share of C on its corners, N/m */
} sw_compact;
int sw_compact_stencils(sw_term *t, const sw_model *m, const double *Q, int ldq,
                        sw_compact *c, char *err, size_t errsz);
void sw_compact_hess(const sw_term *t, const sw_model *m, const sw_compact *c,
                     const sw_eval *ev);
void sw_compact_free(sw_compact *c);
/* models/point_load.c: E = -sum_i f_i . x_i with f = m->load (no Hessian, no stencils). */
int sw_point_load_build(sw_term *t, const sw_model *m, char *err, size_t errsz);

/* models/seam.c: the term "seams", one 3-vertex stencil per pair of every seam. */
int sw_seam_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* Pair a seam whose curves (sm->curve, sm->n) have rest edge lengths el0 (n[0] - 1) and el1
 * (n[1] - 1), m: sm->length, npair, pair, w, len.  Nonzero when out of memory. */
int sw_seam_pair(sw_seam *sm, const double *el0, const double *el1, char *err, size_t errsz);
/* m->sewn_ptr, sewn_idx from the seams' pairs: each vertex is linked to its partner edge's
 * vertices and their neighbours along that curve.  Nonzero when out of memory. */
int sw_seam_sewn(sw_model *m, char *err, size_t errsz);
/* Each seam pair's gap at x0 (sw_seam.gap0): where its rest length starts.  Nonzero when out
 * of memory. */
int sw_seam_start(sw_model *m, char *err, size_t errsz);
/* The automatic seam stiffness (sewing: {stiffness: auto}), N/m^2: SW_SEAM_STIFFNESS_FACTOR
 * times the stiffest panel's tension XY stiffness over the mean rest edge length of the seams
 * (docs/garments.md has the measurement). */
#define SW_SEAM_STIFFNESS_FACTOR 10.0
double sw_seam_auto_stiffness(const sw_model *m);

/* models/tension_xy.c: the reference stretch rlu, rlv of every face (Optitex, "Tension XY calculations explanation"). */
void sw_tension_xy_reference(const sw_model *m, sw_data *d);

/* The deformation gradient F = Ds Dm^-1 = [wu wv] of face f at positions x (Optitex; Yan 2019),
 * with the coefficients that make it linear in the corners: wu = sum_i cu[i] x_i,
 * wv = sum_i cv[i] x_i.  wu, wv have m->dim components. */
void sw_face_coeffs(const sw_model *m, int f, double cu[3], double cv[3]);
void sw_face_F(const sw_model *m, int f, const double *x, double *wu, double *wv);

#endif
