/* sinew.h — the one public header of libsinew, an implicit cloth-plus-tendon simulator.
 *
 * Data flows one way: scene file -> sw_model (immutable after load) -> sw_data
 * (t, x, v, workspaces, counters) -> integrator step -> terms -> sparse system -> CHOLMOD ->
 * new state -> diagnostics -> logs.  Every numeric callback returns SW_OK (0), a positive
 * code (recoverable: the caller may retry with a smaller step) or a negative code (fatal).
 * Units are SI throughout: m, s, kg, N.  Arrays are flat and their shape is given as (rows x cols).
 */
#ifndef SINEW_H
#define SINEW_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(SINEW_BUILD) && defined(__GNUC__)
#define SW_API __attribute__((visibility("default")))
#else
#define SW_API
#endif

#define SW_VERSION "0.1.0"
#define SW_ERRSZ 1024 /* size of every caller-owned error buffer */
#define SW_NAMESZ 64
#define SW_PATHSZ 4096

/* SW_NOSTART: a run that could not start (its output folder could not be taken: locked, not
 * writable, files of another origin, a first file it could not make); err ends with what became
 * of the folder: an earlier run's files are wholly kept (as they were), and whatever the run
 * wrote is removed (sim/output/aside.c). */
/* SW_INTERRUPTED: a run stopped by sw_interrupt (SIGINT, SIGTERM) after a step. */
enum { SW_OK = 0, SW_RECOVER = 1, SW_FATAL = -1, SW_NOSTART = -2, SW_INTERRUPTED = -3 };

typedef struct sw_model sw_model;
typedef struct sw_data sw_data;
typedef struct sw_mcontact sw_mcontact; /* models/mesh_contact.c: self-contact workspace */
typedef struct sw_term sw_term;

/* ------------------------------------------------------------------ mesh */

/* A triangle mesh as read from an OBJ file or generated: positions and (u,v) are indexed
 * separately per face corner, so a seam vertex has one position and one (u,v) per panel. */
typedef struct sw_mesh {
  int nv;                      /* number of positions */
  int nuv;                     /* number of texture coordinates (0: the mesh has no vt) */
  int nf;                      /* number of triangles (polygons are fan-triangulated) */
  double *x;                   /* (nv x 3) positions, m */
  double *uv;                  /* (nuv x 2) texture coordinates (rest layout, m after scaling) */
  int *f;                      /* (nf x 3) position index of each corner, 0-based */
  int *fuv;                    /* (nf x 3) uv index of each corner, or NULL when nuv == 0 */
  int *fgroup;                 /* (nf) index into group[] (usemtl or g name; 0 = default) */
  int *fpoly;                  /* (nf) source polygon of each triangle (grid quad or OBJ f
                                  line), 0-based: two triangles of one quad share it */
  int ngroup;                  /* number of groups, >= 1 */
  char (*group)[SW_NAMESZ];    /* (ngroup) group names; group[0] is "default" */
} sw_mesh;

SW_API void sw_mesh_free(sw_mesh *mesh);
/* Read an OBJ file.  On error returns nonzero and writes "file:line:column: what was expected". */
SW_API int sw_obj_read(const char *path, sw_mesh *mesh, char *err, size_t errsz);
/* A regular grid of size[0] x size[1] metres with nx x ny vertices in plane "xy", "xz" or "yz";
 * (u,v) is the grid's own planar layout in metres.  Vertex (i, j) has index j*nx + i. */
SW_API int sw_mesh_grid(sw_mesh *mesh, const double size[2], int nx, int ny, const char *plane,
                        char *err, size_t errsz);

/* ----------------------------------------------------------------- terms */

/* How a term filters the eigenvalues of its Hessian blocks (sw_eval.project): none (exact),
 * clamping the negative ones to 0 (the nearest PSD block), or replacing them by their absolute
 * value (Chen et al., "Stabler Neo-Hookean Simulation: Absolute Eigenvalue Filtering for
 * Projected Newton", SIGGRAPH 2024).  Either filtered block is positive semi-definite. */
enum { SW_FILTER_NONE = 0, SW_FILTER_CLAMP = 1, SW_FILTER_ABS = 2 };

/* Where each entry of a sparse symmetric system on the mesh's vertices is stored, by vertex
 * pair: vertex a's pairs (a, b), b >= a, are pptr[a] .. pptr[a+1]-1, the first (a, a), their
 * b in pvert (increasing); pair e holds the slots (indices into the system's values) of its
 * dim x dim entries, row a's component alpha and column b's component beta at
 * pslot[dim^2 e + alpha dim + beta], -1 for a pinned component (a (a, a) pair holds both
 * halves).  A block over stencil vertices v is added through it by sw_slots_add
 * (models/terms.h). */
typedef struct sw_slots {
  int dim;
  const long *pptr;            /* (nv + 1) */
  const int *pvert;            /* (pptr[nv]) */
  const int *pslot;            /* (pptr[nv] dim^2) */
} sw_slots;

/* Where an evaluation puts the Hessian blocks instead of d->hess (sw_eval_terms_into): straight
 * into the values of a sparse system, through its slots.  A term writes each block through
 * sw_ev_block and hands it over with sw_ev_block_done (models/terms.h), into blk, a scratch
 * block as large as the term's largest. */
typedef struct sw_hsink {
  double *values;
  const sw_slots *slots;
  double *blk;
} sw_hsink;

/* What a term is asked to evaluate.  grad and hess are accumulated into (+=), not overwritten. */
typedef struct sw_eval {
  double t;                    /* time, s */
  const double *x;             /* (nv x dim) positions, m (pinned ones included) */
  double *grad;                /* (nv x dim) += dE/dx, N; or NULL */
  double *hess;                /* += d2E/dx2 per stencil block (see sw_term.hptr), N/m, or set
                                  (=) by a term with sets_blocks; or NULL.  Not NULL means the
                                  Hessian is wanted: a term with sink_ok finds block s's place
                                  with sw_ev_block (models/terms.h), not as hess + hptr[s] */
  const sw_hsink *sink;        /* or NULL: the blocks go into this system (hess is then its
                                  scratch block) */
  double *lowrank;             /* the low-rank vectors u_r of the Hessian (see sw_term.lptr),
                                  sqrt(N/m), written (not accumulated) whenever hess is asked
                                  for; never NULL then for a term with nlowrank > 0 */
  int project;                 /* SW_FILTER_*: how each block is made positive semi-definite
                                  (SW_FILTER_NONE: the exact Hessian) */
  int bound;                   /* 1 (with a filter): a block flat along a direction its energy
                                  bends may be replaced by a positive semi-definite bound above
                                  it: friction beyond its stick speed (models/mesh_friction.c),
                                  after a line search backtracked (solvers/newton.c) */
  const struct sw_contact_lag *lag; /* contact friction lagged for the current step, or NULL
                                  (models/contact.c): for a caller that evaluates the term
                                  contact alone; else its workspace in data, when lagged */
  sw_mcontact *mc;             /* mesh contact's workspace (models/mesh_contact.c): the
                                  term lists its active pairs and their Hessian blocks there;
                                  for a caller that evaluates the term alone (else data) */
  void *data;                  /* the term's workspace (sw_term_ops.data_new; sw_eval_terms
                                  passes d->tdata[k]), or NULL */
  char *why;                   /* or NULL: when eval fails, a term may say which element and
                                  why here (whysz bytes, e.g. "face 3 (vertices 0 1 4): energy
                                  inf J"); the first failure is kept */
  size_t whysz;
} sw_eval;

/* The Hessian blocks a term's last evaluation added beyond its declared stencils (contact
 * pairs that come and go, sw_term_ops.blocks): n blocks of nvb vertices each (1 <= nvb <=
 * SW_BLOCK_MAXV); block k's vertices at v + k vstride (an index >= nv has no DOF and is
 * skipped), its dense (nvb dim) x (nvb dim) block (row-major, vertex-major then component) at
 * val + k (nvb dim)^2, N/m, or val NULL when that evaluation did not ask for the Hessian. */
#define SW_BLOCK_MAXV 4
typedef struct sw_blocks {
  int n, nvb;
  const int *v;
  int vstride;                 /* ints from one block's vertices to the next's (>= nvb) */
  const double *val;
} sw_blocks;

/* One number of summary.json that a term adds (sw_term_ops.summary): a count when is_count,
 * else a value. */
typedef struct sw_field {
  const char *name;
  double value;
  long count;
  int is_count;
} sw_field;
enum { SW_SUMMARY_RUN = 0,     /* with the run's counters (each run) */
       SW_SUMMARY_STATE = 1 }; /* of the state written at the end */

struct sw_io;

/* The table of operations of one energy term (models/).  kind and eval are required; every
 * other operation is optional (NULL: the term has none) and the solvers and the run loop call
 * each term that has it, in the order of m->term, never a term by name (docs/models.md,
 * "Adding a term").  `data` is the term's mutable workspace in d (d->tdata[k]; NULL without
 * data_new): the model and its terms' param stay immutable, what changes over a run is
 * there. */
typedef struct sw_term_ops {
  const char *kind;            /* "bw98", "gravity", ... */
  /* energy (J) into *energy; gradient and Hessian blocks as asked by ev. */
  int (*eval)(const sw_term *term, const sw_model *m, const sw_eval *ev, double *energy);
  void (*free_param)(void *param);
  /* 1: whenever hess is asked for, eval sets (=, not +=) every stored entry of every one of its
   * blocks, so they are not zeroed before it (a term that may skip a block leaves this 0). */
  int sets_blocks;
  /* 1: eval writes each block through sw_ev_block and sw_ev_block_done (models/terms.h), so
   * its blocks may go straight into a system (sw_hsink); 0: they are kept in d->hess and added
   * from there, the same sum */
  int sink_ok;

  /* --- workspace */
  /* the term's workspace for d (sw_data_new, after d's own arrays), or NULL when out of
   * memory; data_free releases it (sw_data_free) */
  void *(*data_new)(const sw_term *term, const sw_model *m, sw_data *d);
  void (*data_free)(void *data);

  /* --- assembly */
  /* the Hessian blocks of the last evaluation beyond the stencils, into *b (b->n = 0: none):
   * before each assembly the Newton solver adds the vertex pairs of those its sparse pattern
   * lacks and re-analyses it (the pattern only grows), then adds the blocks */
  void (*blocks)(const sw_term *term, const sw_model *m, const sw_data *d, const void *data,
                 sw_blocks *b);

  /* --- the steps (the Newton integrators, solvers/ipstep.c, solvers/newton.c) */
  /* start a step of size h (s) from (d->x, d->t) to stage time t1: lag what the step keeps
   * fixed, and move the start guess y (nv x dim) to an admissible one; SW_RECOVER when the
   * step cannot start (it is retried smaller) */
  int (*begin)(const sw_term *term, const sw_model *m, sw_data *d, void *data, double h,
               double t1, double *y);
  /* the largest fraction in [0, 1] of the straight update x0 -> x1 at time t that the term
   * admits; bound: checked on the whole update first, clip next, ccd last on what is left
   * (continuous collision detection, also on a final correction) */
  double (*bound)(const sw_term *term, const sw_model *m, sw_data *d, void *data,
                  const double *x0, const double *x1, double t);
  /* each vertex's own admissible fraction of x0 -> x1 into frac (nv): when the bounds cut
   * the update short, each vertex's part is clipped at its own fraction instead */
  void (*clip)(const sw_term *term, const sw_model *m, sw_data *d, void *data,
               const double *x0, const double *x1, double t, double *frac);
  double (*ccd)(const sw_term *term, const sw_model *m, sw_data *d, void *data,
                const double *x0, const double *x1, double t);
  /* 1 when the update x0 -> x1 is small next to every constraint of the term (Newton stops
   * only then), else 0 */
  int (*settled)(const sw_term *term, const sw_model *m, sw_data *d, void *data,
                 const double *x0, const double *x1, double t);
  /* after a step's solve: SW_RECOVER with d->err when the motion from d->x (at d->t) to y (at
   * t1) passed through a constraint on the way */
  int (*swept)(const sw_term *term, const sw_model *m, sw_data *d, void *data,
               const double *y, double t1);
  /* after Newton failed at x, time t: 1 when the term held an update of the solve below half
   * (frac: what its ccd allowed of the last update, vfrac: each vertex's smallest clip
   * fraction over the solve, or NULL), with the obstacle (scene item, or -1) into *item, the
   * vertex into *vertex and its fraction into *held */
  int (*held)(const sw_term *term, const sw_model *m, const sw_data *d, const void *data,
              const double *x, double t, const double *vfrac, double frac, int *item,
              int *vertex, double *held);

  /* --- the run (sim/sim.c) */
  /* once a state is accepted (the first state, then after each accepted step), after its
   * diagnostics: the term's lagged state advanced for the steps from here on */
  void (*commit)(const sw_term *term, const sw_model *m, sw_data *d, void *data);
  /* the term's diagnostics of d (d->x, d->t) into d's fields, before the logs */
  void (*state)(const sw_term *term, const sw_model *m, sw_data *d, void *data);
  /* (nv) |force| of the term's contacts on each vertex at the last state, N (the faces'
   * contact pressure sums them), or NULL */
  const double *(*vertex_force)(const sw_term *term, const sw_model *m, const sw_data *d,
                                const void *data);
  /* 1 when the term dissipates energy (friction): energy.csv logs the dissipation */
  int (*dissipates)(const sw_term *term, const sw_model *m);
  /* up to nmax fields of summary.json into f (at: SW_SUMMARY_*); their number */
  int (*summary)(const sw_term *term, const sw_model *m, const sw_data *d, void *data, int at,
                 sw_field *f, int nmax);
  /* the term's run state into or out of restart.bin (sim/util.h, sw_io_bytes) */
  void (*io)(const sw_term *term, const sw_model *m, void *data, struct sw_io *io);

  /* --- loading (sim/input/scene.c) */
  /* whether the term can start from the scene's state x: 0, or nonzero with err ("what is
   * wrong; expected ...") and *key the scene key the error is reported at ("obstacles",
   * "contact") */
  int (*check_start)(const sw_term *term, const sw_model *m, const double *x, const char **key,
                     char *err, size_t errsz);
} sw_term_ops;

/* Offset of entry (r, c), r <= c, in the upper triangle of a w x w block stored row by row. */
static inline long sw_hess_upper(int r, int c, int w) {
  return (long)r * w - (long)r * (r - 1) / 2 + (c - r);
}
/* Doubles in the upper triangle of a w x w block. */
static inline long sw_hess_size(int w) { return (long)w * (w + 1) / 2; }
/* Entry (r, c) of a symmetric block stored as its upper triangle (either order of r, c). */
static inline double sw_hess_get(const double *blk, int r, int c, int w) {
  return r <= c ? blk[sw_hess_upper(r, c, w)] : blk[sw_hess_upper(c, r, w)];
}

/* One energy term: its operations, its Hessian stencils (declared once), its parameters.
 * Stencil s covers vertices sidx[sptr[s] .. sptr[s+1]-1]; its Hessian block, symmetric of
 * w = n*dim rows (vertex-major then component), is stored as its upper triangle, row by row:
 * entry (r, c), r <= c, at hess + hptr[s] + sw_hess_upper(r, c, w), sw_hess_size(w) doubles in
 * all (the lower half is never stored, assembled or read).
 * A term may also declare low-rank vectors: its Hessian is then the sum of the blocks plus
 * sum_r u_r u_r^T, where u_r covers vertices lidx[lptr[r] .. lptr[r+1]-1] and its n*dim values
 * (vertex-major) start at lowrank + lptr[r]*dim.  They keep a coupling of many vertices (a
 * long tendon's E'' grad(Delta) grad(Delta)^T) out of the sparse factor: the solvers add it
 * by Woodbury on top of CHOLMOD (solvers/cholmod.c, docs/tendons.md).  nlowrank = 0 and NULL
 * pointers for terms without them. */
struct sw_term {
  const sw_term_ops *ops;
  char name[SW_NAMESZ];
  int nstencil;
  int *sptr;                   /* (nstencil + 1) */
  int *sidx;                   /* (sptr[nstencil]) vertex indices */
  long *hptr;                  /* (nstencil + 1) offsets of the blocks, in doubles */
  int nlowrank;                /* low-rank vectors (fixed per model, possibly zero at some x) */
  int *lptr;                   /* (nlowrank + 1) */
  int *lidx;                   /* (lptr[nlowrank]) vertex indices */
  void *param;                 /* the term's own immutable data */
};


/* ---------------------------------------------------------------- contact */

/* Obstacles (models/obstacle.c, docs/contact.md): rigid shapes the cloth's vertices cannot
 * enter.  Each sits where the scene puts it, turned by its rotation keyframes about an axis
 * through `center` and translated by its motion keyframes (a displacement, m), both
 * interpolated as sw_keyframe_value; its contact surface is the shape grown by `offset`.  In 2D, a plane is a line, a sphere a circle, a capsule a stadium and a box a
 * rectangle (the third components are 0). */
enum { SW_SHAPE_PLANE = 0, SW_SHAPE_SPHERE, SW_SHAPE_CAPSULE, SW_SHAPE_BOX, SW_SHAPE_N };
/* The scene's names of the SW_SHAPE_* ("plane", "sphere", "capsule", "box"), in order. */
SW_API const char *const *sw_shape_names(void);

typedef struct sw_obstacle {
  int shape;                   /* SW_SHAPE_* */
  double a[3];                 /* plane: a point on it; sphere and box: the centre; capsule:
                                  one end of its axis, m */
  double b[3];                 /* plane: the unit normal, pointing out of the solid side;
                                  capsule: the other end, m; box: half sizes along x, y, z, m */
  double radius;               /* sphere, capsule, m */
  double offset;               /* m (>= 0): the contact surface is the shape grown by this (a
                                  thickness, e.g. of the cloth or of skin) */
  int nkey;                    /* motion keyframes (0: static) */
  double *key_t;               /* (nkey) s, increasing */
  double *key_d;               /* (3 x nkey) displacement from the stated place, m: component
                                  a of keyframe k at key_d[a nkey + k] */
  int interp;                  /* SW_INTERP_* of the motion (translation and rotation) */
  int nrot;                    /* rotation keyframes (0: no rotation) */
  double *rot_t;               /* (nrot) s, increasing */
  double *rot_a;               /* (nrot) angle about the axis, rad (right-handed) */
  double axis[3];              /* unit rotation axis ([0, 0, 1] in 2D) */
  double center[3];            /* a point of the axis at the stated place, m (it moves with the
                                  translation: the body turns about center + displacement) */
  int item;                    /* its index in the scene's `obstacles` list (for messages) */
  /* a mesh obstacle (`mesh: file.obj`, models/mesh_contact.c; in m->mesh_obstacle only, never
     in m->obstacle: sw_obstacle_sdf does not apply to it) */
  int mesh_nv, mesh_nf;        /* its vertices and triangles (0 for a shape) */
  double *mesh_x;              /* (mesh_nv x 3) vertices at the stated place, m */
  int *mesh_face;              /* (mesh_nf x 3) vertex indices */
} sw_obstacle;

/* Contact (models/contact.c, docs/contact.md): a log barrier on each vertex's distance to each
 * obstacle (Li et al., "Incremental Potential Contact", SIGGRAPH 2020), energy
 *   E = kappa sum_i m_i b(d_i),  b(d) = -(d - dhat)^2 ln(d / dhat) for 0 < d < dhat, else 0,
 * and optional smoothed Coulomb friction lagged per step. */
typedef struct sw_contact {
  double dhat;                 /* m: the barrier acts below this distance (default 1e-3) */
  double kappa;                /* 1/s^2: barrier stiffness per unit mass, kappa m |b'(d)| is
                                  the contact force (N); 0 in the scene: automatic,
                                  sw_model_finish sets |g| / |b'(dhat/2)| */
  int kappa_auto;              /* 1: kappa was chosen automatically */
  double friction;             /* Coulomb coefficient mu (0: frictionless) of the cloth on
                                  every obstacle, analytic or mesh */
  double self_friction;        /* Coulomb coefficient of the cloth on itself (self-contact;
                                  the scene's default: friction) */
  double eps_v;                /* m/s: friction's stick-slip velocity (below it, friction is
                                  a stiff viscous force: the smoothing of IPC's f0) */
  int self;                    /* 1: the cloth's triangles repel each other (self-contact) */
  double thickness;            /* m: self-contact keeps every point-triangle and edge-edge
                                  pair at least this far apart (C-IPC's thickness) */
  double kappa_mesh;           /* 1/(s^2 m^2): self-contact's and the mesh obstacles' barrier
                                  stiffness per unit mass on squared distances (scene key
                                  self_stiffness); 0 in the scene: automatic */
  int kappa_mesh_auto;         /* 1: kappa_mesh was chosen automatically */
} sw_contact;

/* Friction lagged for one step (IPC): at the start of the step, each vertex-obstacle pair's
 * normal force and normal; friction then acts on the tangential displacement over the step,
 * relative to the obstacle (models/contact.c). */
typedef struct sw_contact_lag {
  double h;                    /* s: the step */
  double t0;                   /* s: its start */
  const double *x0;            /* (nv x dim) positions at its start, m */
  double *lambda;              /* (nv x nobstacle) lagged normal force, N (0: no contact) */
  double *normal;              /* (nv x nobstacle x 3) lagged unit normals */
} sw_contact_lag;

/* ----------------------------------------------------------------- model */

/* Membrane models (models/bw98.c, stvk.c, corotated.c, springs.c) and bending models
 * (models/dihedral.c, quadratic_bending.c, morley_bending.c, dde_bending.c; docs/models.md). */
enum { SW_MEMBRANE_NONE = 0, SW_MEMBRANE_BW98, SW_MEMBRANE_STVK, SW_MEMBRANE_COROTATED,
       SW_MEMBRANE_SPRINGS, SW_MEMBRANE_DDE };
enum { SW_BENDING_NONE = 0, SW_BENDING_DIHEDRAL, SW_BENDING_QUADRATIC, SW_BENDING_MORLEY,
       SW_BENDING_DDE };
enum { SW_BEND_REST_INITIAL = 0, SW_BEND_REST_FLAT = 1 };

/* A measured fabric in the format of Wang, Ramamoorthi and O'Brien's data set ("Data-Driven
 * Elastic Models for Cloth: Modeling and Measurement", SIGGRAPH 2011; models/dde.c,
 * docs/fabrics.md).  The numbers are the file's, in its units. */
typedef struct sw_dde {
  double stretch[6][4];        /* (c11, c12, c22, c33), N/m: row 0 at zero strain, rows 1..5 at
                                  a principal stretch of 7/6 along 0, 22.5, 45, 67.5, 90 degrees
                                  from the u (warp) axis; negative samples clamped at 0 */
  double bend[3][5];           /* the data's bending stiffness k_e, N m: rows hinge edge at 0,
                                  45, 90 degrees from u; columns at its curvature measure 0, 5,
                                  10, 15, 20 1/m (half the curvature); rigidity B = k_e / 4
                                  (models/dde.c) */
  double density;              /* kg/m^2 */
  int nclamped;                /* negative stretch samples clamped at 0 when read */
} sw_dde;

/* The material of a panel.  m->mat[0] is the scene's `material`; m->mat[k > 0] is a panel of
 * `panels:` (an OBJ usemtl/g group), a copy of mat[0] with the keys the panel overrides. */
typedef struct sw_material {
  char group[SW_NAMESZ];       /* the OBJ group it applies to ("" for mat[0]) */
  double density;              /* kg/m^2 of rest (u,v) area */
  int membrane;                /* SW_MEMBRANE_* */
  double k_u, k_v, k_shear;    /* bw98 warp, weft and shear stiffness, N/m */
  double b_u, b_v;             /* bw98 rest stretch of warp and weft (1 = no pre-stretch) */
  double e_u, e_v;             /* stvk warp and weft Young's moduli (thickness folded in), N/m */
  double nu_uv;                /* stvk Poisson ratio: weft contraction under warp stress, 1
                                  (nu_vu = nu_uv e_v / e_u; needs nu_uv nu_vu < 1) */
  double g_uv;                 /* stvk in-plane shear modulus, N/m */
  double k_corot;              /* corotated: k/2 |U - I|^2 per unit area, N/m */
  double ks_stretch, ks_shear, ks_bend; /* springs: stiffness of each kind of spring, N/m */
  sw_dde dde;                  /* dde: the measured fabric (models/dde.c) */
  int bending;                 /* SW_BENDING_* */
  double k_bend;               /* bending stiffness, N m (= J); the largest of the three
                                  below when they are set */
  double k_bend_u, k_bend_v, k_bend_bias; /* orthotropic bending: the rigidity a strip cut
                                  along warp, weft and at 45 degrees reads, N m (0: isotropic
                                  k_bend; docs/models.md "Anisotropic bending") */
  int bend_rest;               /* SW_BEND_REST_*: dihedral rest angle from x0 or flat */
  double bias;                 /* rad: the warp axis is the u axis rotated by bias */
  double tx_k_u, tx_k_v;       /* stiffness tension XY uses on this panel, N/m (set by
                                  sw_model_finish from the membrane unless the scene sets it) */
  int tx_dde;                  /* 1: tension XY reads the dde data's stiffness at each face's
                                  own strain (membrane dde, no tension_xy stiffness given) */
} sw_material;

/* Tendons (models/tendon.c, docs/tendons.md). */
enum { SW_LAW_SPRING = 0, SW_LAW_CABLE = 1 };

typedef struct sw_tendon {
  char name[SW_NAMESZ];
  int law;                     /* SW_LAW_* */
  double stiffness;            /* K, N/m: tension = K (length - rest), E = K/2 (length - rest)^2 */
  int nway;                    /* waypoints, >= 2 */
  int *way;                    /* (nway) distinct vertex indices, in order along the tendon */
  int nkey;                    /* rest-length keyframes, >= 1 (1: constant) */
  double *key_t;               /* (nkey) s, increasing */
  double *key_rest;            /* (nkey) rest length, m (relative ones resolved at load) */
  int interp;                  /* SW_INTERP_*: how the rest length goes between keyframes */
  double density;              /* kg/m: linear density, lumped onto the waypoints */
  double damping;              /* N s/m: force -c (dl/dt) grad l along the tendon */
} sw_tendon;

/* Forcing (models/keyframe.c and forcing.c, docs/scenes.md "Forcing").  Keyframes are
 * interpolated linearly (the slope jumps at each keyframe) or smoothly: the quintic blend
 * 6u^5 - 15u^4 + 10u^3 between consecutive keyframes, C^2 everywhere and never outside the
 * keyframes' range.  Scenes default to smooth; a zeroed sw_tendon is linear. */
/* Seams (models/seam.c, docs/garments.md): two boundary curves of the pattern, each a run of
 * a panel's boundary, sewn together.  Each vertex of either curve is paired with the point at
 * the same fraction of arc length (in the (u,v) pattern) on the other curve, which may lie
 * inside one of its edges; a spring pulls them together,
 *   E = k sum_p l_p (|g_p| - r_p(t))^2 / 2,   g_p = x_a - ((1 - w_p) x_b0 + w_p x_b1),
 * k the seam stiffness (N/m^2: per metre of seam), l_p the seam length pair p stands for (m),
 * and a rest length r_p(t) = g0_p (1 - sw_ramp(t, ramp)) that shrinks smoothly from the pair's
 * starting gap g0_p to 0: the seams close at the ramp's pace, then hold as zero-length
 * springs. */
typedef struct sw_seam {
  char name[SW_NAMESZ];
  int panel[2];                /* the material index of each curve's faces */
  char group[2][SW_NAMESZ];    /* the OBJ group (panel) of each curve */
  int n[2];                    /* vertices of each curve, >= 2 */
  int *curve[2];               /* (n[k]) vertex indices along each curve, in order */
  double length[2];            /* rest (u,v) arc length of each curve, m */
  int npair;
  int *pair;                   /* (npair x 3) a, b0, b1: vertex a of one curve and the edge
                                  (b0, b1) of the other holding its partner point */
  double *w;                   /* (npair) the partner point is (1 - w) x_b0 + w x_b1 */
  double *len;                 /* (npair) seam length the pair stands for, m */
  double *gap0;                /* (npair) the pair's gap at x0, m (sw_model_finish) */
} sw_seam;

/* The fit stage (sim/sim.c, docs/garments.md): before the scene's own dynamics, a garment is
 * sewn and settled by backward Euler steps of dt with extra mass damping, the seams ramped in
 * over `ramp`; it ends when the seams are closed to `gap` and the RMS speed is below `speed`,
 * after at least `ramp` s, or fails at `max_time`. */
enum { SW_FIT_DYNAMIC = 0, SW_FIT_OPTIMIZE = 1, SW_FIT_SETTLE = 2 };
typedef struct sw_fit {
  int on;                      /* 1: fit before the dynamics (the default with seams) */
  int mode;                    /* SW_FIT_DYNAMIC: damped backward Euler steps of dt;
                                  SW_FIT_OPTIMIZE: proximal steps of at most opt_dt over the
                                  ramps, then growing; SW_FIT_SETTLE: the dynamic fit's steps
                                  over the ramps, then growing proximal steps */
  double opt_dt;               /* s: the optimisation fit's step over the ramps */
  double opt_growth;           /* >= 1: its step's growth once the ramps are over */
  double dt;                   /* s */
  double damping;              /* 1/s: mass-proportional damping added during the fit */
  double gap;                  /* m: largest seam gap at the end */
  double speed;                /* m/s: RMS speed at the end */
  double max_time;             /* s */
  double newton_tol;           /* m/s: Newton's tolerance during the fit (at most the scene's) */
} sw_fit;

enum { SW_INTERP_LINEAR = 0, SW_INTERP_SMOOTH = 1 };
/* The value at time t (s) of keyframes (kt[k], kv[k]), k < n, kt increasing; constant outside
 * them. */
SW_API double sw_keyframe_value(const double *kt, const double *kv, int n, int interp,
                                double t);
/* Its time derivative at t (units of kv per s; 0 outside the keyframes). */
SW_API double sw_keyframe_rate(const double *kt, const double *kv, int n, int interp,
                               double t);
/* A smooth ramp from 0 at t = 0 to 1 at t = T (the quintic blend of t/T), 1 when T <= 0; and
 * its rate (1/s). */
SW_API double sw_ramp(double t, double T);
SW_API double sw_ramp_rate(double t, double T);

/* Nonzero when the model's potential depends on time (keyframed tendons, ramped gravity or
 * loads): energy.csv then logs the work the forcing does. */
SW_API int sw_actuated(const sw_model *m);
/* The power the forcing puts in at positions x (nv x dim) and time t: dU/dt at fixed x, W
 * (docs/integrators.md, "Energy"): -sum tension alpha'(t) over tendons, -r'(t) sum m g.x for
 * ramped gravity, -sum r_i'(t) f_i.x_i for ramped loads. */
SW_API double sw_actuation_power(const sw_model *m, const double *x, double t);

/* The rest length of a tendon at time t: its keyframes interpolated as td->interp says,
 * constant outside them (m); and its rate (m/s). */
SW_API double sw_tendon_rest(const sw_tendon *td, double t);
SW_API double sw_tendon_rest_rate(const sw_tendon *td, double t);
/* The current length sum |x_{w_k} - x_{w_k+1}| of a tendon at x (nv x dim), m. */
SW_API double sw_tendon_length(const sw_tendon *td, const double *x, int dim);
/* Its tension E'(delta) for delta = length - rest, N (cable: 0 when slack). */
SW_API double sw_tendon_tension(const sw_tendon *td, double delta);

/* Newton's system matrix (docs/integrators.md, "Newton"): every element's Hessian clamped to
 * PSD (always positive definite with a mass term; linear convergence where the cloth is
 * compressed), absolute-value filtered, exact (quadratic convergence; fails where S is
 * indefinite), exact with a fall-back to clamped for an iteration whose S is not positive
 * definite, or progressive: exact except the elements at vertices Newton has not yet
 * converged (clamped), all clamped for the rest of the step when S is not positive definite. */
enum { SW_HESSIAN_PROJECTED = 0, SW_HESSIAN_EXACT = 1, SW_HESSIAN_AUTO = 2, SW_HESSIAN_ABS = 3,
       SW_HESSIAN_PROGRESSIVE = 4, SW_HESSIAN_NMODES = 5,
       SW_HESSIAN_DEFAULT = -1 /* not set: abs in 3D, projected in 2D (sw_model_finish) */ };
/* The scene's and the command line's names of the SW_HESSIAN_* modes, in their order. */
SW_API const char *const *sw_hessian_names(void);
/* How Newton measures its update dx against tol * dt (docs/integrators.md, "Newton"): the
 * mass-weighted RMS over the free DOFs, sqrt(sum m_i |dx_i|^2 / sum m_i), with no coordinate
 * above SW_NEWTON_RMS_CAP x the tolerance; or the largest coordinate, max |dx|. */
enum { SW_NORM_RMS = 0, SW_NORM_MAX = 1, SW_NORM_N = 2 };
#define SW_NEWTON_RMS_CAP 10.0
SW_API const char *const *sw_norm_names(void);
/* The sparse Cholesky factorisation (docs/performance.md, "Simplicial or supernodal"): auto
 * picks from the matrix, by the flops its factorisation takes per nonzero of its factor
 * (simplicial below SW_FACTOR_SWITCH, supernodal above); or forced. */
enum { SW_FACTOR_AUTO = 0, SW_FACTOR_SIMPLICIAL = 1, SW_FACTOR_SUPERNODAL = 2, SW_FACTOR_N = 3 };
SW_API const char *const *sw_factor_names(void);
/* The fill-reducing ordering of the sparse Cholesky factorisation (docs/performance.md,
 * "Factorisation: ordering, kind and threads"): auto, the measured rule (solvers/cholmod.c); or
 * forced: AMD (approximate minimum degree), METIS's nested dissection, or CHOLMOD's own nested
 * dissection (METIS's separators with a constrained minimum degree). */
enum { SW_ORDERING_AUTO = 0, SW_ORDERING_AMD = 1, SW_ORDERING_METIS = 2, SW_ORDERING_NESDIS = 3,
       SW_ORDERING_N = 4 };
/* Their names ("auto", "amd", "metis", "nesdis"), NULL-terminated. */
SW_API const char *const *sw_ordering_names(void);
/* Newton's linear solves (docs/integrators.md, "Newton-Krylov"): off, a factorisation per
 * iteration; on, conjugate gradients preconditioned by the last factorisation; auto, on when
 * the factorisation is simplicial (small systems, where a solve costs little against a
 * factorisation), off when supernodal; step, a fresh factorisation at each solve's first
 * iteration and conjugate gradients preconditioned by it at the solve's later ones.  Scene
 * names false/true/auto/step, CLI off/on/auto/step. */
enum { SW_REUSE_OFF = 0, SW_REUSE_ON = 1, SW_REUSE_AUTO = 2, SW_REUSE_STEP = 3 };

/* The encoding of the frames (sim/output/vtu.c, docs/scenes.md "Frames"): VTK XML with its
 * arrays appended raw and zlib-compressed (as ParaView writes), every real exact (Float64) or
 * as Float32 (about half the size), or inline ascii (exact). */
enum { SW_FRAMES_BINARY = 0, SW_FRAMES_BINARY32 = 1, SW_FRAMES_ASCII = 2, SW_FRAMES_N = 3 };
/* Their names ("binary", "binary32", "ascii"), NULL-terminated. */
SW_API const char *const *sw_frames_format_names(void);

/* The bending's part of Newton's matrix, for the bending models with a constant Hessian
 * (quadratic, morley; docs/integrators.md, "The bending matrix"): exact, compact (the
 * couplings of vertices that share no face moved onto the diagonal, models/compact.c), or
 * auto: compact for the time-stepping methods, exact for the static method and the fit modes
 * optimize and settle, whose large steps leave bending without inertia beside it (resolved by
 * sw_model_finish). */
enum { SW_BMATRIX_EXACT = 0, SW_BMATRIX_COMPACT = 1, SW_BMATRIX_AUTO = 2, SW_BMATRIX_N = 3 };
SW_API const char *const *sw_bending_matrix_names(void);
typedef struct sw_options {
  char method[SW_NAMESZ];      /* integrator name, see sw_method_names() */
  double dt;                   /* step, s */
  double duration;             /* simulated time, s */
  int newton_max;              /* Newton iterations per step before the step fails */
  double newton_tol;           /* m/s: Newton converges when its estimate of the error left in
                                  the stage positions, in the newton_norm, is at most
                                  newton_tol * dt (docs/integrators.md, "Newton") */
  int newton_norm;             /* SW_NORM_*: how that error is measured */
  double newton_force_tol;     /* static solve: converged when the largest free force component
                                  is <= newton_force_tol x the force scale (dimensionless; or
                                  at its round-off floor, docs/integrators.md) */
  int max_halvings;            /* a failed step is retried with dt/2 at most this many times */
  int hessian;                 /* SW_HESSIAN_*: which Hessian Newton's systems use */
  int newton_reuse;            /* SW_REUSE_*: Newton-Krylov, each direction by conjugate
                                  gradients preconditioned with the last factorisation, or a
                                  fresh factorisation per iteration */
  int factorization;           /* SW_FACTOR_* */
  int ordering;                /* SW_ORDERING_*: the factorisation's fill-reducing ordering */
  int bending_matrix;          /* SW_BMATRIX_*: set before sw_model_finish builds the terms */
  int blas_threads;            /* OpenBLAS threads; 0: $OPENBLAS_NUM_THREADS if set, else 1 */
  double rtol, atol;           /* adaptive methods (CVODE, IDA): relative, absolute (m, m/s) */
  int max_order;               /* adaptive methods: largest BDF order (1..5); 0: automatic,
                                  sw_max_order */
  double max_step;             /* adaptive methods: largest internal step, s (0: no limit) */
  int setup_every;             /* cvode: most steps between two setups of its Newton matrix
                                  (CVodeSetLSetupFrequency; SUNDIALS' default is 20) */
  double energy_bound;         /* J: a step whose total energy exceeds it fails (0: automatic,
                                  1e3 x the initial energy scale above the initial energy) */
  char out_dir[SW_PATHSZ];     /* output folder */
  double frames_every;         /* s between VTU frames (0: first and last only; < 0: none at
                                  all, no frames.pvd, except the last good state of a failed
                                  run) */
  double positions_every;      /* s between records of positions.bin (0: no positions.bin) */
  int frames_format;           /* SW_FRAMES_*: how the frames are encoded */
  double restart_every;        /* s of wall time: restart.bin is written at the start, with each
                                  frame and at the first logged step this long after the last
                                  one (0: at the start and with frames only; default 60) */
  double tx_clip;              /* tension XY stiffness clip, N/m (Optitex's: 5e4) */
  int tx_reference_uv;         /* 1: rlu = rlv = 1 (uv layout); 0: the initial configuration;
                                  -1 (the default): uv with seams, else initial (resolved
                                  by sw_model_finish) */
  double tx_k_u, tx_k_v;       /* stiffness used by tension XY, N/m (defaults: the membrane's) */
  int tendon_dense_max;        /* tendons of at most this many waypoints put their whole
                                  Hessian in one dense stencil; longer ones only the banded
                                  part, the rank-one part as a low-rank vector (default
                                  SW_TENDON_DENSE_MAX; docs/tendons.md has the measurement) */
} sw_options;

/* A file the scene loader read (the scene file itself, each OBJ), as it was: a resumed run
 * refuses to join a run of other files (sw_resume). */
typedef struct sw_input {
  char path[SW_PATHSZ];        /* as the loader opened it */
  long long bytes;             /* its size */
  unsigned long long hash;     /* FNV-1a 64 of its bytes */
} sw_input;

/* The default of sw_options.tendon_dense_max (docs/tendons.md). */
#define SW_TENDON_DENSE_MAX 32

struct sw_model {
  char name[128];              /* scene name */
  char path[SW_PATHSZ];        /* scene file */
  int dim;                     /* 2 or 3: DOFs per vertex */
  int nv, nf;                  /* vertices, triangles */
  double *x0;                  /* (nv x dim) initial positions, m */
  double *v0;                  /* (nv x dim) initial velocities, m/s */
  double perturb_amplitude;    /* m: sw_model_finish moves each free vertex of x0 along its
                                  normal by a smooth random field of this largest value, after
                                  the rest shapes are taken (0: none; docs/scenes.md) */
  unsigned long perturb_seed;  /* the seed of that perturbation (the same seed, the same x0) */
  int *face;                   /* (nf x 3) vertex indices */
  double *uv;                  /* (nf x 6) rest (u,v) of each corner, m */
  double *dminv;               /* (nf x 4) Dm^-1 row-major, Dm = [uv1-uv0, uv2-uv0], 1/m */
  double *area;                /* (nf) rest area |det Dm|/2, m^2 */
  double *mass;                /* (nv) lumped mass, kg */
  double *point_mass;          /* (nv) point masses the scene adds (`masses`), kg, or NULL */
  double total_mass;           /* kg */
  unsigned char *pinned;       /* (nv) 1 if the vertex is pinned */
  int *dof;                    /* (nv x dim) free DOF index, or -1 for a pinned component */
  int ndof;                    /* free DOFs */
  double gravity[3];           /* m/s^2 */
  int has_gravity;
  double gravity_ramp;         /* s: gravity grows as sw_ramp(t - gravity_delay, gravity_ramp)
                                  (0: on at t = 0) */
  double gravity_delay;        /* s: 0, except during the fit stage (sim/sim.c), which sews
                                  the seams before gravity grows */
  int nmat;                    /* materials, >= 1 */
  sw_material *mat;            /* (nmat) mat[0]: the scene's material; others: panels */
  int *face_mat;               /* (nf) material of each face */
  int *face_poly;              /* (nf) source polygon of each face (quads: two faces share
                                  one; springs put shear springs on quad diagonals), or NULL */
  double damp_mass;            /* Rayleigh mass-proportional damping alpha, 1/s */
  double damp_stiffness;       /* Rayleigh stiffness-proportional damping beta, s */
  int ntendon;
  sw_tendon *tendon;           /* (ntendon) */
  double *load;                /* (nv x dim) external point load on each vertex, N (scene key
                                  `loads`, term "loads", models/point_load.c), or NULL */
  double *load_ramp;           /* (nv) s: vertex i's load grows as sw_ramp(t, load_ramp[i]);
                                  NULL: every load on at t = 0 */
  int nobstacle;
  sw_obstacle *obstacle;       /* (nobstacle) the scene's `obstacles` with a `shape` */
  int nmesh_obstacle;
  sw_obstacle *mesh_obstacle;  /* (nmesh_obstacle) the scene's `obstacles` with a `mesh`:
                                  rigid triangle meshes (models/mesh_contact.c, 3D only) */
  sw_contact contact;          /* the scene's `contact` (used with obstacles or self-contact) */
  int nseam;
  sw_seam *seam;               /* (nseam) the scene's `seams` */
  double seam_stiffness;       /* N/m^2: k of every seam (sewing: stiffness) */
  double seam_ramp;            /* s: the seams are sewn in as sw_ramp(t, seam_ramp) */
  double seam_ease_max;        /* the largest relative difference of a seam's curve lengths */
  int *sewn_ptr, *sewn_idx;    /* (nv + 1), (sewn_ptr[nv]): the vertices each vertex is sewn
                                  to or sewn next to (contact skips pairs of those, as pairs
                                  sharing a vertex), or NULL without seams */
  sw_fit fit;

  int nterm;
  sw_term *term;               /* (nterm) energy terms, only those the scene names */
  sw_options opt;
  double stiffness_scale;      /* the factor every elastic stiffness of the scene was multiplied
                                  by at load (sw_scene_overrides; 1: none, 0 read as 1) */
  int grid_override[2];        /* sw_scene_overrides grid the scene was loaded with (0: none) */
  int ninput;
  sw_input *input;             /* (ninput) the files the loader read, the scene's first */
  char warning[SW_ERRSZ];      /* what the loader warns of ("" when nothing): a grid override
                                  on a scene that selects vertices by index */
};

/* Allocate an empty model with default options. */
SW_API sw_model *sw_model_new(void);
/* After a loader filled dim, nv, nf, x0, v0, face, uv, pinned, gravity, mat (face_mat: NULL
 * for all faces on mat[0]), tendons and opt: rotate each panel's layout by its bias, compute
 * rest shapes, lumped masses, the DOF map and build the terms; then perturb x0 when
 * perturb_amplitude > 0.  Nonzero on error. */
SW_API int sw_model_finish(sw_model *m, char *err, size_t errsz);
SW_API void sw_model_free(sw_model *m);
/* Load and validate a scene file (YAML).  NULL on error, with "file:line:column: message". */
SW_API sw_model *sw_scene_load(const char *path, char *err, size_t errsz);

/* What sw_scene_load_ex changes in a scene as it loads it (sinew run --grid, --stiffness-scale).
 * grid replaces mesh.grid.vertices (the scene's mesh must be a grid; both >= 2, at most the
 * scene key's total); vertex indices in selections and tendons stay indices (and may then be
 * out of range: the usual error; m->warning says where the scene selects by index), boxes and
 * grid selections ({grid: [[i, j], ...]}) select on the new grid.  stiffness_scale multiplies
 * every elastic stiffness before the terms are built: the membrane's (bw98 k_u, k_v, k_shear;
 * stvk e_u, e_v, shear_modulus; corotated k; springs stretch, shear, bend), bending stiffness,
 * every tendon's stiffness and the stiffness tension XY uses (derived or explicit); not
 * density, damping, bias, rest values, the tension XY clip or loads. */
typedef struct sw_scene_overrides {
  int grid[2];                 /* vertices nx, ny; 0: the scene's */
  double stiffness_scale;      /* > 0; 0 or 1: none */
  int bending_matrix;          /* SW_BMATRIX_* + 1; 0: the scene's */
  const char *method;          /* the integrator (sinew run --method), or NULL: the scene's;
                                  applied before the terms are built (the bending matrix's
                                  auto depends on it) */
} sw_scene_overrides;

/* sw_scene_load with overrides (ov NULL: none).  A bad override is an error naming the scene
 * file (and the mesh node for a scene whose mesh is not a grid). */
SW_API sw_model *sw_scene_load_ex(const char *path, const sw_scene_overrides *ov, char *err,
                                  size_t errsz);
/* Nonzeros of the upper triangle of the system matrix on the free DOFs (-1 on error). */
SW_API long sw_system_nnz(const sw_model *m);
/* Print what `sinew check` shows. */
SW_API void sw_model_print(const sw_model *m, void *file /* FILE* */);

/* ------------------------------------------------------------------ data */

/* Where a static solve stopped (docs/integrators.md, "The static solve"). */
typedef struct sw_static_info {
  int iterations;              /* Newton iterations */
  int roundoff;                /* 1: stopped at the round-off floor; 0: at the tolerance (or
                                  not converged) */
  double force;                /* N: the largest free force component max_i |dU/dx_i| */
  double tol;                  /* N: the tolerance, force_tol x the force scale */
  double floor;                /* N: the largest round-off floor rho_i of a free component */
  double floor_ratio;          /* max_i |dU/dx_i| / rho_i: <= 1 at the floor */
} sw_static_info;

struct sw_data {
  double t;                    /* s */
  double *x, *v;               /* (nv x dim) positions m, velocities m/s */
  double *grad;                /* (nv x dim) gradient workspace */
  double *hess;                /* Hessian blocks of every term; term k starts at hoff[k]:
                                  allocated at the first sw_eval_terms that asks for them (an
                                  evaluation into a system, sw_eval_terms_into, needs none) */
  long *hoff;                  /* (nterm + 1) */
  double *hblk;                /* (the largest block) sw_eval_terms_into's scratch block */
  double *lowrank;             /* low-rank Hessian vectors of every term; term k at loff[k] */
  long *loff;                  /* (nterm + 1) */
  double *term_energy;         /* (nterm) J, at the last evaluation */
  double *term_time;           /* (nterm) s of wall time in each term's evaluations, cumulative */
  int ntdata;                  /* m->nterm */
  void **tdata;                /* (ntdata) each term's workspace (sw_term_ops.data_new), or NULL */
  void (**tdata_free)(void *); /* (ntdata) its release (sw_term_ops.data_free), or NULL */
  /* diagnostics (after every accepted step) */
  double *txy;                 /* (nf) tension XY, N/m */
  double *stretch_u, *stretch_v; /* (nf) warp and weft stretch |wu|, |wv| */
  double *shear;               /* (nf) shear angle between wu and wv, rad (0 = orthogonal) */
  double *rlu, *rlv;           /* (nf) reference stretch of tension XY */
  double *scratch;             /* (nf) for percentiles */
  double *tendon_length;       /* (ntendon) m, at the last diagnostics */
  double *tendon_delta;        /* (ntendon) length - rest, m */
  double *tendon_tension;      /* (ntendon) E'(delta), N */
  /* contact (models/contact.c; only with obstacles) */
  sw_contact_lag *lag;         /* friction lagged for the current step, or NULL: the term
                                  contact's workspace (its d->tdata), named for models/ */
  int contact_count;           /* vertex-obstacle pairs closer than dhat at the last diagnostics
                                  (with mesh obstacles: their point-triangle and edge-edge
                                  pairs too) */
  double contact_min;          /* m: smallest vertex-obstacle distance, or mesh obstacle pair's
                                  distance - offset (inf: no obstacle) */
  double contact_force[3];     /* N: total force the obstacles exert (barrier, mesh obstacles
                                  included) */
  double friction_force[3];    /* N: total friction force of the last step's lag */
  double friction_power;       /* W: the power friction dissipates at the last diagnostics */
  sw_mcontact *mc;             /* mesh contact's workspace, or NULL (contact: {self: true}
                                  or a mesh obstacle): the term mesh_contact's d->tdata */
  int self_count;              /* self-contact pairs closer than dhat beyond the thickness */
  double self_min;             /* m: smallest gap (distance - thickness) of a self-contact
                                  candidate pair (inf: none within thickness + dhat) */
  double self_force;           /* N: half the sum over vertices of |self-contact force| */
  double *vertex_area;         /* (nv) each vertex's third of its faces' rest areas, m^2 (with
                                  contact only) */
  double *contact_pressure;    /* (nf) N/m^2: mean over its corners of |contact force| / the
                                  corner's rest area share, or NULL */
  double damp_power;           /* W: v.D v dissipated by damping at the last diagnostics */
  double dissipated;           /* J: its integral over the run so far (trapezoid on the logs) */
  double actuation_power;      /* W: dU/dt at fixed x (sw_actuation_power) at the last log */
  double work_in;              /* J: its integral over the run so far (trapezoid on the logs) */
  double *seam_state;          /* (nseam x 4) per seam at the last diagnostics: largest and
                                  mean gap between paired points (m), the force the seam
                                  carries (N: the sum of |spring force| over its pairs) and the
                                  ratio of its current curve lengths b/a (sw_seam_state) */
  double seam_gap_max;         /* m: the largest gap of any seam then (0 without seams) */
  double fit_end;              /* s: when the fit stage ended (0: no fit) */
  long fit_steps;              /* steps of the fit stage */
  double fit_wall;             /* s of wall time in the fit stage */
  /* counters (cumulative over the run) */
  long nstep, nnewton, nfactor, nassemble, nforce, nretry, nlinesearch;
  long ncg;                    /* conjugate-gradient iterations of Newton-Krylov (reuse) */
  long nbound;                 /* Newton iterations with friction's bound in their matrix */
  long nerrfail;               /* error-test failures of adaptive methods */
  long nsetup;                 /* linear-solver setups of SUNDIALS methods */
  long nstep_order[5];         /* adaptive methods: steps taken at BDF order 1..5 */
  double energy_bound;         /* J: a step whose K + U exceeds this fails (0: no check; sw_run
                                  sets it from opt.energy_bound) */
  int last_newton;             /* Newton iterations of the last step */
  int hess_bound;              /* 1: the next linearisation asks for sw_eval.bound (Newton) */
  sw_static_info static_info;  /* where the last static solve stopped (sw_static_solve) */
  double last_dt;              /* size of the last accepted step, s */
  double time_assemble, time_factor, time_solve, time_step; /* s of wall time */
  double wall_before;          /* s of wall time of a resumed run's earlier parts (0: none) */
  double time_contact;         /* s of wall time in the solvers' contact checks: continuous
                                  collision detection, settling, each step's start */
  double time_broadphase;      /* s in self-contact's broad phase for the CCD */
  double time_ccd;             /* s in self-contact's CCD (broad and narrow phase) */
  double time_pattern;         /* s growing the sparse pattern and re-analysing it */
  long npattern;               /* times the pattern grew (a CHOLMOD analysis each) */
  long factor_nnz;             /* nonzeros of the Cholesky factor L of the last factorisation
                                  (CHOLMOD's count for its ordering; 0: no factor yet, or a
                                  method without one) */
  int factor_super;            /* 1: the factor is supernodal, 0: simplicial (-1: none yet) */
  int factor_ordering;         /* SW_ORDERING_* the analysis used (never auto; -1: none yet) */
  double energy[4];            /* J at the current state (the stepping API, after each step and
                                  change): kinetic, potential, their total, dissipated so far */
  char err[SW_ERRSZ];          /* why the last failing call failed */
};

SW_API sw_data *sw_data_new(const sw_model *m);
SW_API void sw_data_free(sw_data *d);
/* Evaluate every term at x, time t: d->term_energy, and (when asked) d->grad, d->hess (SW_FATAL
 * when d->hess cannot be allocated). */
SW_API int sw_eval_terms(const sw_model *m, sw_data *d, const double *x, double t, int want_grad,
                         int want_hess, int project, double *energy);
/* The same with the Hessian added straight into a system's values instead of d->hess, through
 * its slots (sw_hsink): the arithmetic of adding d->hess's blocks through the same slots in
 * term, stencil and entry order. */
SW_API int sw_eval_terms_into(const sw_model *m, sw_data *d, const double *x, double t,
                              int want_grad, int project, double *values,
                              const sw_slots *slots, double *energy);
SW_API double sw_kinetic(const sw_model *m, const double *v);
/* Nonzero when the model has Rayleigh damping (damping: {mass, stiffness}). */
SW_API int sw_damped(const sw_model *m);
/* Tension XY (Optitex, "Tension XY calculations explanation"; docs/models.md) and the strain diagnostics of every face at d->x. */
SW_API void sw_tension_xy(const sw_model *m, sw_data *d);
/* Length, delta and tension of every tendon at d->x, d->t (d->tendon_*). */
SW_API void sw_tendon_state(const sw_model *m, sw_data *d);
/* Gap, force and length ratio of every seam at d->x, d->t (d->seam_state, d->seam_gap_max). */
SW_API void sw_seam_state(const sw_model *m, sw_data *d);

/* ------------------------------------------------------------------- run */

SW_API const char *const *sw_method_names(void);
/* The one-line summary of a method (as `sinew run --help` shows it), or NULL if unknown. */
SW_API const char *sw_method_summary(const char *name);
/* 1 for a method that chooses its own steps to a tolerance (cvode, ida: rtol, atol; dt is then
 * the output interval), 0 for a fixed-step method and static, -1 for an unknown name. */
SW_API int sw_method_adaptive(const char *name);
/* The largest BDF order the model's adaptive method uses: opt.max_order, or when that is 0
 * (automatic, the default) 2 for cvode at rtol > SW_AUTO_ORDER_RTOL and 5 otherwise (ida
 * always 5).  docs/integrators.md, "Which BDF order", has the measurements. */
#define SW_AUTO_ORDER_RTOL 1e-4
SW_API int sw_max_order(const sw_model *m);
/* Thread settings of the linear algebra (sw_run calls it): OpenMP nesting in CHOLMOD off unless
 * OMP_MAX_ACTIVE_LEVELS or OMP_THREAD_LIMIT is set; OpenBLAS threads = blas_threads, or when 0,
 * $OPENBLAS_NUM_THREADS if set, else 1. */
SW_API void sw_set_threads(int blas_threads);
/* Simulate the model and write the output folder.  0 on success; nonzero with err on failure
 * (the logs are flushed up to the failure and summary.json says "failed"); SW_NOSTART when
 * the folder could not be taken (nothing written). */
SW_API int sw_run(const sw_model *m, int progress, char *err, size_t errsz);
/* The scene file and the options of the run whose folder is dir, from its restart.bin (a run
 * writes it with each frame and when it stops), for sw_resume.  SW_OK or SW_FATAL with err. */
SW_API int sw_restart_options(const char *dir, char *scene, size_t scenesz, sw_options *opt,
                              char *err, size_t errsz);
/* Go on with the run in m->opt.out_dir from its restart.bin to m->opt.duration, appending to
 * its logs (m: the scene loaded again, with the options sw_restart_options gave); a run stopped
 * in its fit stage goes on with the fit where it stopped.  Returns as
 * sw_run; SW_NOSTART when the folder or its restart file cannot be used (nothing changed). */
SW_API int sw_resume(const sw_model *m, int progress, char *err, size_t errsz);
/* sw_restart_options, the overrides the run's scene was loaded with (sw_scene_load_ex) and
 * the time of the restart, s. */
SW_API int sw_restart_options_ex(const char *dir, char *scene, size_t scenesz, sw_options *opt,
                                 sw_scene_overrides *ov, double *t, char *err, size_t errsz);
/* sw_resume; force: go on although the model changed (the scene file or a file it reads,
 * the overrides, an option that defines the run), which sw_resume refuses with a message
 * naming the change.  A damaged restart file or another mesh or method is refused anyway. */
SW_API int sw_resume_ex(const sw_model *m, int progress, int force, char *err, size_t errsz);
/* ------------------------------------------------------------ stepping */

/* A simulation stepped by its caller (sim/sim.c): the loop sw_run is made of, one step at a
 * time, with the state and the diagnostics readable after every step and the tendons' rest
 * lengths, the pins' positions, the point loads and the state itself writable between steps.
 * Each step (sw_sim_step) goes from d->t to the next point of the grid t0 + n dt (t0: the start
 * time, 0 or the t of the last sw_sim_set_state), halving on recoverable failures as sw_run
 * does; after it the diagnostics (tension XY and strains per face, tendon lengths and
 * tensions, term energies) belong to the new state.  A change between steps makes the
 * integrator restart where its history no longer holds: CVODE and IDA are reinitialised at the
 * current state, Newmark re-evaluates its acceleration, BDF2 restarts with a backward Euler
 * step after a change of the state (not after a change of the model: its history is still the
 * solution's), and a kept Newton factorisation is dropped.  The setters change the model m the
 * sim was made from (a tendon's keyframes, m->load): m must outlive the sim and is not const. */
typedef struct sw_sim sw_sim;

enum { SW_SIM_OUTPUT = 1,   /* write the run folder m->opt.out_dir as sw_run does */
       SW_SIM_PROGRESS = 2, /* a progress line on stderr when it is a terminal */
       SW_SIM_FORCE = 4     /* resume although the model changed (sw_resume_ex) */ };

/* A simulation of m at its initial state (t = 0, x0, v0; with SW_SIM_OUTPUT the folder is
 * opened and the first state logged).  NULL with err on failure (unknown method, output). */
SW_API sw_sim *sw_sim_new(sw_model *m, int flags, char *err, size_t errsz);
/* One step of m->opt.dt (static: one static solve from the current positions).  0, or nonzero
 * with err naming the time, the method and the reason; the state is then the last good one,
 * and the sim can go on (after a change, say). */
SW_API int sw_sim_step(sw_sim *s, char *err, size_t errsz);
/* Steps until t = until (the last one shortened to land on it; a frame and a record of
 * positions.bin at until when the folder is written).  0 or nonzero with err. */
SW_API int sw_sim_run(sw_sim *s, double until, char *err, size_t errsz);
/* sw_sim_run taking at most max_steps steps (< 0: no limit): a caller that must see signals
 * (Python's Ctrl-C) between steps runs one step a call until it reaches until.  Both refuse an
 * until that is not finite or is before the current time (nonzero, err). */
SW_API int sw_sim_run_steps(sw_sim *s, double until, long max_steps, char *err, size_t errsz);
/* Back to the initial state as sw_sim_new made it (t = 0, x0, v0, counters and integrals 0,
 * the fit stage again if the scene has one, the integrator started afresh); changes of the
 * model (rest lengths, loads, dt) stay.  The arrays of sw_sim_array keep their addresses.  Not
 * for a sim writing a run folder (nonzero, err). */
SW_API int sw_sim_reset(sw_sim *s, char *err, size_t errsz);
/* The time step from now on (s, > 0; not for the static method): the step grid starts again at
 * the current time, and the integrator restarts its history as after sw_sim_set_state. */
SW_API int sw_sim_set_dt(sw_sim *s, double dt, char *err, size_t errsz);
/* Every tendon's rest length from now on (ntendon values, m, >= 0), with one evaluation of the
 * changed state; and every tendon's rest length at the current time into rest (ntendon). */
SW_API int sw_sim_set_rests(sw_sim *s, const double *rest, char *err, size_t errsz);
SW_API void sw_sim_rests(const sw_sim *s, double *rest);
/* A copy of the sim's whole state as bytes: what restart.bin holds (time, step grid, positions,
 * velocities, counters and integrals, the integrator's history).  Returns its size; copies it
 * into buf when size is enough (buf NULL: the size only).  sw_sim_put_state makes it the sim's
 * state again (a copy from a sim of the same sizes and method): the steps after it are those
 * after the copy was taken, to the bit, for methods with a history (all but CVODE and IDA,
 * which restart there).  The model (rest lengths, loads) is not part of it. */
SW_API size_t sw_sim_get_state(sw_sim *s, void *buf, size_t size);
SW_API int sw_sim_put_state(sw_sim *s, const void *buf, size_t size, char *err, size_t errsz);
/* Ask every sw_sim_run going to stop after its current step, as for signal sig (async-signal
 * safe: for a SIGINT or SIGTERM handler; 0 withdraws the request).  The run then returns
 * SW_INTERRUPTED, and sw_sim_close writes the state reached as a frame and summary.json with
 * status "interrupted", its time_reached and the signal. */
SW_API void sw_interrupt(int sig);
/* The signal of the pending sw_interrupt request, 0 if none. */
SW_API int sw_interrupted(void);
/* Finish the run folder (summary.json "ok", or "failed" with the message of the last step
 * when it failed, after a frame of the last good state).  0 without a folder.  After it, steps
 * and changes fail with "the simulation is closed"; the state stays readable. */
SW_API int sw_sim_close(sw_sim *s, char *err, size_t errsz);
/* sw_sim_close (errors dropped) and free; the model is the caller's. */
SW_API void sw_sim_free(sw_sim *s);
/* The state: d->t, d->x, d->v, the diagnostics and the counters (read only). */
SW_API const sw_data *sw_sim_data(const sw_sim *s);
SW_API const sw_model *sw_sim_model(const sw_sim *s);
/* Kinetic and potential energy of the current state, and what damping dissipated so far, J. */
SW_API void sw_sim_energy(const sw_sim *s, double *kinetic, double *potential,
                          double *dissipated);
/* Set the state: time t (s), positions x (nv x dim, m; pinned components move the pins) and
 * velocities v (nv x dim, m/s; pinned components are taken as 0); x or v NULL: unchanged.
 * The step grid goes on from t (n dt when t is one of its points, else t + n dt).  0, or
 * nonzero with err (a value not finite). */
SW_API int sw_sim_set_state(sw_sim *s, double t, const double *x, const double *v, char *err,
                            size_t errsz);
/* Tendon k's rest length from now on (m, >= 0; its keyframes are replaced by this one). */
SW_API int sw_sim_set_rest(sw_sim *s, int k, double rest, char *err, size_t errsz);
/* Move pinned vertex i to x (dim values, m): its pinned components only. */
SW_API int sw_sim_set_pin(sw_sim *s, int i, const double *x, char *err, size_t errsz);
/* The point load on vertex i (dim values, N).  The scene must have `loads` (zero is fine). */
SW_API int sw_sim_set_load(sw_sim *s, int i, const double *f, char *err, size_t errsz);
/* The index of the tendon or term called name, or -1. */
SW_API int sw_tendon_find(const sw_model *m, const char *name);
SW_API int sw_term_find(const sw_model *m, const char *name);

/* For bindings that do not read C structs (Python's ctypes, python/sinew): the sim's arrays
 * by name, their shape in *rows x *cols (may be NULL); NULL for an unknown name.  Doubles:
 * "x", "v" (nv x dim), "x0" (nv x dim), "mass" (nv x 1), "tension_xy", "stretch_u",
 * "stretch_v", "shear", "area" (nf x 1), "uv" (nf x 6), "tendon_length", "tendon_tension",
 * "tendon_delta" (ntendon x 1), "term_energy" (nterm x 1), "load" (nv x dim, or NULL without
 * loads), "contact_pressure" (nf x 1, or NULL without obstacles or self-contact), "energy"
 * (4 x 1: kinetic, potential, total, dissipated, J).  Ints: "face" (nf x 3), "dof" (nv x dim: the free DOF of each component, -1 where
 * pinned).  The memory is the sim's (valid until sw_sim_free; x and v change as it steps). */
SW_API double *sw_sim_array(sw_sim *s, const char *name, int *rows, int *cols);
SW_API int *sw_sim_iarray(sw_sim *s, const char *name, int *rows, int *cols);
/* A counter of sw_data by its field name ("nstep", "nnewton", "nfactor", "nassemble",
 * "nforce", "nretry", "nlinesearch", "nerrfail", "nsetup", "ncg", "nbound"), or -1. */
SW_API long sw_sim_counter(const sw_sim *s, const char *name);
/* The first n of those counters, in that order, into out; returns how many there are. */
SW_API int sw_sim_counters(const sw_sim *s, long *out, int n);
/* Sizes and names: "nv", "dim", "nf", "ntendon", "nterm", "ndof"; names of tendon or term k. */
SW_API int sw_sim_size(const sw_sim *s, const char *name);
SW_API const char *sw_sim_name(const sw_sim *s, const char *kind, int k);
/* The current time d->t, s. */
SW_API double sw_sim_time(const sw_sim *s);
/* The time step m->opt.dt, s (sw_sim_set_dt changes it). */
SW_API double sw_sim_dt(const sw_sim *s);
/* Tendon k's rest length at the current time, m; its waypoints (vertex indices) and their
 * number in *n. */
SW_API double sw_sim_rest(const sw_sim *s, int k);
SW_API const int *sw_sim_waypoints(const sw_sim *s, int k, int *n);
/* An option of m before sw_sim_new, by its scene or command-line name: "method", "dt",
 * "duration", "rtol", "atol", "max_order", "max_step", "newton_tol", "newton_max",
 * "max_halvings", "frames_every", "positions_every", "out" (the output folder), "hessian".
 * 0, or nonzero with err (unknown key, a value out of range). */
SW_API int sw_model_set_option(sw_model *m, const char *key, const char *value, char *err,
                               size_t errsz);

/* Static equilibrium from x0: minimise the total potential.  Fills x (nv x dim) and the sum of
 * the pin reactions (3, N).  0 on success. */
SW_API int sw_static_solve(const sw_model *m, sw_data *d, double reaction[3], char *err,
                           size_t errsz);

/* --------------------------------------------------------------- inverse */

/* The tendon inverse problem (solvers/inverse.c, docs/inverse.md): which
 * tensions tau >= 0 make the tendons exert the target forces f on chosen vertices at a
 * configuration x, and which rest lengths give those tensions. */
typedef struct sw_targets {
  int n;                       /* target vertices */
  int dim;                     /* components of each force */
  int *vertex;                 /* (n) distinct vertex indices */
  double *f;                   /* (n x dim) target force on each, N */
} sw_targets;

/* Read a targets CSV: a header `vertex,fx,fy` (2D) or `vertex,fx,fy,fz` (3D), then one line
 * per vertex.  Nonzero with "file:line:column: what was found; expected what" on error. */
SW_API int sw_targets_read(const char *path, const sw_model *m, sw_targets *tg, char *err,
                           size_t errsz);
SW_API void sw_targets_free(sw_targets *tg);

#define SW_INVERSE_RTOL 1e-6   /* reachable: |A tau - f| <= RTOL |f| (2-norms) */
#define SW_INVERSE_XTOL 1e-6   /* forward check: max |x* - x| <= XTOL x the longest tendon */

typedef struct sw_inverse {
  int ntendon;
  double *tau;                 /* (ntendon) tension, N */
  double *length;              /* (ntendon) length l at x, m */
  double *rest;                /* (ntendon) rest length alpha = l - tau / K, m (K = 0: as in
                                  the scene at t = 0) */
  double residual;             /* |A tau - f|, N */
  double fnorm;                /* |f|, N */
  int iterations;              /* NNLS outer iterations */
  int reachable;               /* residual <= SW_INVERSE_RTOL fnorm */
  /* forward check (sw_inverse_check) */
  int check_rc;                /* the static solve's return code (0: converged) */
  double check_dx;             /* max over vertices of |x* - x|, m */
  double check_ferr0;          /* |f_tendons(x) - f| / |f| on the targets (|f| = 0: in N) */
  double check_ferr;           /* |f_tendons(x*) - f| / |f| */
  int check_pass;              /* converged, dx <= XTOL l_max and ferr <= RTOL */
} sw_inverse;

/* Tensions by non-negative least squares and the rest lengths, at x (nv x dim, m).  0, or
 * nonzero with err (out of memory, NNLS failure). */
SW_API int sw_inverse_solve(const sw_model *m, const double *x, const sw_targets *tg,
                            sw_inverse *inv, char *err, size_t errsz);
/* The forward check: the tendons alone with the rest lengths inv->rest (constant), every
 * vertex but the targets pinned, the targets loaded by -f; a static solve from x.  Fills
 * inv->check_*.  0 when the check could be run (passed or not); nonzero with err otherwise. */
SW_API int sw_inverse_check(const sw_model *m, const double *x, const sw_targets *tg,
                            sw_inverse *inv, char *err, size_t errsz);
SW_API void sw_inverse_free(sw_inverse *inv);
/* Write the scene file `scene` to `out` with each tendon's rest_length set to rest[k] (m),
 * through libfyaml's document API, atomically (a temporary file renamed).  0 or nonzero with
 * err. */
SW_API int sw_scene_write_rest(const char *scene, const char *out, const sw_model *m,
                               const double *rest, char *err, size_t errsz);

#ifdef __cplusplus
}
#endif
#endif
