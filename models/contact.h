/* contact.h — obstacles and the contact term (models/obstacle.c, models/contact.c): what the
 * solvers need to keep every vertex outside every obstacle (docs/contact.md). */
#ifndef SW_CONTACT_H
#define SW_CONTACT_H

#include "sinew.h"

#define SW_OBSTACLE_MAXKEY 4096 /* motion keyframes per obstacle at most (scene loader) */
#define SW_MAX_OBSTACLES 64     /* obstacles per scene at most (scene loader) */
#define SW_TOI_MAX_ITERS 64     /* conservative advancement steps before giving up (safe) */
#define SW_SWEPT_MAX_ITERS 400  /* the same against a moving obstacle over a step */
#define SW_CONTACT_KEEP 0.1     /* a step may close at most 90 % of a vertex's distance */
#ifndef SW_CONTACT_SETTLE
#define SW_CONTACT_SETTLE 0.5   /* Newton's last update moves a vertex in contact by at most this
                                   fraction of its distance (docs/contact.md, measured) */
#endif
#define SW_CONTACT_DHAT 1e-3    /* default barrier distance, m */
#define SW_CONTACT_EPS_V 1e-3   /* default stick-slip velocity of friction, m/s */

/* The displacement of obstacle o at time t (its motion keyframes), m. */
void sw_obstacle_disp(const sw_obstacle *o, double t, double disp[3]);
/* The obstacle's pose at time t: a body point q (stated place) is at R (q - center) + c,
 * R (3 x 3, row-major) its rotation, c = center + displacement (m). */
void sw_obstacle_pose(const sw_obstacle *o, double t, double R[9], double c[3]);
/* The world position p at time t of the body point q (its stated place), m. */
void sw_obstacle_place(const sw_obstacle *o, double t, const double q[3], double p[3]);
/* Where the body point at p at time t0 is at time t1 (the obstacle's rigid motion), m. */
void sw_obstacle_carry(const sw_obstacle *o, double t0, double t1, const double p[3],
                       double out[3]);
/* Whether the obstacle is at another place (or angle) at t1 than at t0. */
int sw_obstacle_moves(const sw_obstacle *o, double t0, double t1);
/* Bounds of an obstacle's motion over [t0, t1] (h = t1 - t0): the translation's largest speed
 * times h (m), its speed's largest departure from (c(t1) - c(t0)) / h times h (m), its largest
 * distance from the chord joining c(t0) and c(t1) uniformly in time (m); the angle's largest
 * rate times h, its largest distance from its own chord (rad), and |angle(t1) - angle(t0)|. */
typedef struct sw_motion_bounds {
  double move, rate_dev, pos_dev;
  double turn, turn_dev, dangle;
} sw_motion_bounds;
void sw_obstacle_bounds(const sw_obstacle *o, double t0, double t1, sw_motion_bounds *b);
/* Signed distance (m) from p (dim components) to o's contact surface at time t, negative
 * inside; its gradient (the outward unit normal, dim) into n and Hessian (dim x dim) into H,
 * each when not NULL. */
double sw_obstacle_sdf(const sw_obstacle *o, int dim, double t, const double *p, double *n,
                       double *H);
/* The fraction s in [0, 1] of the straight motion p0 -> p1 (o fixed at time t) over which the
 * point stays at least keep x its distance at p0 from o (1: the whole motion); 0 if p0 is not
 * outside. */
double sw_obstacle_toi(const sw_obstacle *o, int dim, double t, const double *p0,
                       const double *p1, double keep);

/* The fraction s in [0, 1] of a step from t0 to t1 over which the point p0 + s (p1 - p0), with
 * the obstacle where its motion puts it at t0 + s (t1 - t0), stays more than floor (m) from its
 * contact surface (1: the whole step; 0 if p0 is not beyond floor at t0).  Conservative
 * advancement on the swept distance, whose rate is bounded by the point's motion relative to
 * the body and the body's departure from uniform motion (sw_obstacle_bounds): nothing
 * passes through, however fast the obstacle moves or turns. */
double sw_obstacle_swept_toi(const sw_obstacle *o, int dim, double t0, double t1,
                             const double *p0, const double *p1, double floor);

/* IPC's barrier b(d) = -(d - dhat)^2 ln(d / dhat) on 0 < d < dhat (0 beyond; +inf at d <= 0)
 * and its first and second derivatives (m, 1), as functions of the distance d (m). */
double sw_contact_barrier(double d, double dhat, double *db, double *d2b);

/* models/contact.c: the term "contact", one 1-vertex stencil per free vertex. */
int sw_contact_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* The automatic barrier stiffness: a vertex resting under gravity sits at dhat / 2. */
double sw_contact_auto_kappa(const sw_model *m);
/* Nonzero with err naming the vertex and obstacle when a free vertex of x is not outside an
 * obstacle at time t. */
int sw_contact_outside(const sw_model *m, const double *x, double t, char *err, size_t errsz);
/* The largest fraction of the straight motion x0 -> x1 (nv x dim each) that keeps every free
 * vertex outside every obstacle at time t (at least SW_CONTACT_KEEP of its distance). */
double sw_contact_toi(const sw_model *m, const double *x0, const double *x1, double t);
/* Each vertex's own fraction of that motion (nv values in frac): the step a vertex may take
 * alone.  Only vertex-obstacle contacts exist, so scaling each vertex's motion by its fraction
 * keeps every vertex outside. */
void sw_contact_clip(const sw_model *m, const double *x0, const double *x1, double t,
                     double *frac);
/* Whether the update x0 -> x1 is small next to every contact: a vertex within dhat of an
 * obstacle moves by at most SW_CONTACT_SETTLE of its distance, any other by at most
 * 1 - SW_CONTACT_KEEP of it (so it stays outside).  Newton on a log barrier at most doubles a
 * distance per iteration, so an update that is small in metres may still be far from
 * converged in a contact a few micrometres thick: Newton converges only when this holds.
 * (A test on the change of the distance alone, which lets a vertex slide along the surface,
 * took 1214 Newton iterations on scenes/drape_sphere.yaml against 810.) */
int sw_contact_settled(const sw_model *m, const double *x0, const double *x1, double t);
/* Start a step from (d->x, d->t) to stage time t1 of size h: lag the friction (normal forces
 * and normals at d->x), and move the guess y (nv x dim) so that it is outside every obstacle
 * at t1: a guess inside an obstacle is moved out along the normal to dhat / 2, where the
 * automatic stiffness rests a vertex under its weight; when that is not outside
 * every obstacle (between two), the guess is the farthest point of the vertex's path to it
 * that the obstacles allow, from where it was (carried along by an obstacle moving near it).
 * SW_RECOVER when an obstacle would move into a vertex within the step. */
int sw_contact_begin(const sw_model *m, sw_data *d, double h, double t1, double *y);
/* After a step's solve: SW_RECOVER ("obstacles[k] passes through vertex i between t = ... and
 * ... s") when a free vertex moving straight from d->x (at d->t) to y (at t1) goes deeper than
 * dhat into an obstacle, moving over the step or not, at some instant (sw_obstacle_swept_toi:
 * the chord of a slide over a curved surface may dip under it, by less than dhat); SW_OK when
 * none does. */
int sw_contact_swept(const sw_model *m, sw_data *d, const double *y, double t1);
/* The contact diagnostics of d (sinew.h: contact_count, contact_min, contact_force,
 * friction_force) at d->x, d->t. */
void sw_contact_state(const sw_model *m, sw_data *d);
/* The lag's buffers (NULL: the model has no obstacles), and their release. */
sw_contact_lag *sw_contact_lag_new(const sw_model *m);
void sw_contact_lag_free(sw_contact_lag *lag);


/* ----------------------------------------------- models/mesh_contact.c: triangle meshes */

/* The term "mesh_contact" (contact: {self: true}, or a mesh obstacle): IPC barriers on the
 * point-triangle and edge-edge pairs of the cloth's own triangles (self-contact), within
 * thickness + dhat, and of the cloth's against the mesh obstacles', within the obstacle's
 * offset + dhat.  The obstacles' vertices follow the cloth's in one numbering (vertex nv + j):
 * fixed, they carry no DOF, no gradient and no Hessian entry. */
int sw_mesh_contact_build(sw_term *t, const sw_model *m, char *err, size_t errsz);
/* Whether the model has that term: self-contact or a mesh obstacle. */
int sw_mesh_contact_on(const sw_model *m);
/* The automatic kappa_mesh: a vertex resting on the cloth under gravity sits dhat / 2 beyond
 * the thickness (without self-contact: beyond the largest mesh obstacle offset), 1/(s^2 m^2). */
double sw_mesh_contact_auto_kappa(const sw_model *m);

/* One active pair of the last evaluation: a point and a triangle (v[0]; v[1..3]) or two edges
 * (v[0] v[1]; v[2] v[3]), closer than thickness + dhat; gap = distance - thickness, m.  An
 * index >= nv is a mesh obstacle's vertex (no DOF: the solvers skip it). */
enum { SW_MC_PT = 0, SW_MC_EE = 1 };
typedef struct sw_mc_pair {
  int kind;
  int v[4];
  double gap;
} sw_mc_pair;

/* The run's mutable workspace of mesh contact (broad phase, the active pairs and their
 * Hessian blocks): NULL for a model without the term mesh_contact. */
/* The automatic stiffness adapts as in IPC (Li et al., "Incremental Potential Contact",
 * SIGGRAPH 2020, section 4.3): after each accepted step whose diagnostics found a pair's gap
 * (distance - thickness) g below g0 = SW_KAPPA_GAP dhat, kappa_s grows by sw_kappa_growth:
 * 2^((1 - g / g0) / SW_KAPPA_BAND), at most 2 (doubled from (1 - SW_KAPPA_BAND) g0 down), so
 * that the factor is continuous in the gap: a gap a hair below g0 (where round-off decides
 * which side a run falls) raises it a hair, not twice (at most SW_KAPPA_SCALE_MAX times its
 * start).  sw_mcontact_adapt returns 1 when it grew; the factor so far is part of the run's
 * state (restart.bin).  A scene's own contact.self_stiffness is never changed. */
#define SW_KAPPA_GAP 0.25 /* measured: docs/contact.md */
#define SW_KAPPA_BAND 0.1 /* g from g0 down to 0.9 g0: the growth from 1 to 2 */
#define SW_KAPPA_SCALE_MAX 65536.0
double sw_kappa_growth(double gap, double dhat);
int sw_mcontact_adapt(const sw_model *m, sw_mcontact *mc);
double sw_mcontact_kappa_scale(const sw_mcontact *mc);
void sw_mcontact_set_kappa_scale(sw_mcontact *mc, double s);
sw_mcontact *sw_mcontact_new(const sw_model *m);
/* The candidate listings so far: made anew (*made) and renewed for the few vertices that left
 * their boxes (*renewed); 0 for mc NULL. */
void sw_mcontact_listings(const sw_mcontact *mc, long *made, long *renewed);
/* on 0: every listing made anew (for comparisons: the default renews). */
void sw_mcontact_set_renew(sw_mcontact *mc, int on);
void sw_mcontact_free(sw_mcontact *mc);
/* The active pairs of the last evaluation (0 for mc NULL) and their filtered Hessian blocks
 * (144 doubles each, vertex-major over v[0..3]; NULL unless that evaluation asked for the
 * Hessian). */
int sw_mcontact_pairs(const sw_mcontact *mc, const sw_mc_pair **pair, const double **block);
/* The largest fraction of the straight motion of the cloth x0 -> x1 (nv x 3 each) and of the
 * mesh obstacles from their place at t0 to that at t1 over which no pair comes within its
 * thickness (additive CCD, models/ccd.c); the broad phase's wall time is added to *time_bp.
 * 1 for mc NULL. */
double sw_mcontact_toi(const sw_model *m, sw_mcontact *mc, const double *x0, double t0,
                       const double *x1, double t1, double *time_bp);
/* The mesh obstacle (its index k of the scene's obstacles[k]) of the pair that limited the last
 * sw_mcontact_toi, and that pair's first cloth vertex into *vertex; -1 when that CCD was not
 * limited, or by a pair of the cloth alone. */
int sw_mcontact_limit(const sw_model *m, const sw_mcontact *mc, int *vertex);
/* Whether the update x0 -> x1 moves every vertex of an active pair of the last evaluation by at
 * most SW_CONTACT_SETTLE of the pair's gap (the test sw_contact_settled makes for obstacles). */
int sw_mcontact_settled(const sw_model *m, const sw_mcontact *mc, const double *x0,
                        const double *x1);
/* Cut the step's start guess y (at stage time t1) back along d->x -> y to where no pair comes
 * within its thickness (d->x at d->t is such a state).  When a mesh obstacle moves over the
 * step and the guess must be cut, the cut starts from d->x with the vertices near a moving
 * obstacle carried along by its motion, once CCD has found that carry safe; SW_RECOVER
 * ("obstacles[k] moves into vertex i") when it is not. */
int sw_mcontact_begin(const sw_model *m, sw_data *d, double t1, double *y);
/* After a step's solve, with a mesh obstacle moving over it: SW_RECOVER ("obstacles[k] passes
 * through vertex i between t = ... and ... s") when a pair of the cloth moving straight from
 * d->x to y and the obstacles moving from their place at d->t to that at t1 comes within its
 * thickness (additive CCD, restarted; the obstacles' vertices taken on straight lines with the
 * thickness widened by how far their true paths stray from those, sw_obstacle_bounds). */
int sw_mcontact_swept(const sw_model *m, sw_data *d, const double *y, double t1);
/* Nonzero with err when x (at t = 0) has intersecting triangles or a pair within its
 * thickness: the cloth's own pairs (obstacles 0, with self-contact) or the cloth's against
 * the mesh obstacles (obstacles 1). */
int sw_mcontact_check_start(const sw_model *m, const double *x, int obstacles, char *err,
                            size_t errsz);
/* The pairs of a cloth triangle and a mesh obstacle's that intersect with the cloth at x and
 * the obstacles at time t (exact, models/intersect.c); the first pair's faces (numbering the
 * obstacles' after the cloth's) into first when not NULL; -1 when out of memory, -2 when
 * stopped by a signal (cancel.h: sw_cancelled). */
long sw_mcontact_obstacle_intersections(const sw_model *m, sw_mcontact *mc, const double *x,
                                        double t, int *first);
/* The self-contact diagnostics of d at d->x (sinew.h: self_count, self_min, self_force), and
 * the mesh obstacles' pairs added to contact_count, contact_min and contact_force. */
void sw_mcontact_state(const sw_model *m, sw_data *d);
/* (nv) |self-contact force| + |mesh obstacles' force| on each vertex at the last
 * diagnostics, N, or NULL. */
const double *sw_mcontact_vertex_force(const sw_mcontact *mc);
/* How many times the moving mesh obstacles' tree was refitted in this workspace (static
 * obstacles: never; moving ones: when a query's poses are not the last fit's two ends). */
long sw_mcontact_refits(const sw_mcontact *mc);
/* The heap bytes of the model's mesh_contact term (0 without): the cloth's edges and a face of
 * each cloth vertex and edge, the mesh obstacles' numbering and their tree (with its triangles'
 * boxes under SW_MC_KEEP_BOXES triangles); nothing else grows with an obstacle. */
size_t sw_mesh_contact_bytes(const sw_model *m);
/* Lag the friction of the mesh pairs (contact.friction > 0) for a step of size h from
 * (d->x, d->t): every pair closer than its thickness + dhat there (models/mesh_friction.c).
 * SW_RECOVER when the broad phase fails, SW_FATAL when out of memory. */
int sw_mcontact_lag(const sw_model *m, sw_data *d, double h);

/* ------------------------------ models/mesh_friction.c: friction of the mesh pairs, lagged */

/* The lagged pairs of a step: their vertices, closest points' coefficients, normals and
 * normal forces at the step's start (IPC, section 5). */
typedef struct sw_mfriction sw_mfriction;
sw_mfriction *sw_mfriction_new(void);
void sw_mfriction_free(sw_mfriction *f);
/* Start a step of size h (s): no pair lagged yet. */
void sw_mfriction_begin(sw_mfriction *f, double h);
/* Lag pair (kind, v) at p (its 4 vertices, 12 values) with thickness xi (m), shat (m^2),
 * weight w = kappa_s w_k (kg/(s^2 m^2)) and Coulomb coefficient mu; a pair beyond shat or
 * with mu = 0 is skipped.  -1: out of memory. */
int sw_mfriction_lag_pair(sw_mfriction *f, int kind, const int *v, const double *p, double xi,
                          double shat, double w, double mu);
/* The number of lagged pairs (0 for f NULL or before the first step) and pair k's vertices. */
int sw_mfriction_count(const sw_mfriction *f);
const int *sw_mfriction_vertices(const sw_mfriction *f, int k);
/* Pair k's friction mu lambda_k f0(|P_k u_k|) with its 4 vertices at p (12; J; the slip u_k
 * from their places when it was lagged), its gradient over the pair's
 * 4 vertices (12, when g is not NULL) and its positive semi-definite Hessian (144, when H is
 * not NULL; bound 1: the bound above it of sw_eval.bound, models/mesh_friction.c); eps_v in
 * m/s. */
double sw_mfriction_pair(const sw_mfriction *f, double eps_v, int k, const double *x, double *g,
                         double *H, int bound);
/* Whether the model has friction anywhere: contact.friction > 0, or self_friction > 0 with
 * self-contact. */
int sw_contact_friction_on(const sw_model *m);

#endif
