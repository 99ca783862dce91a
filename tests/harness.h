/* harness.h — helpers shared by the C tests: small models built in code, random states,
 * integrators and solves started with their messages printed, files of a run folder.  No
 * cmocka here (the benchmarks link it too): a helper that fails prints why and returns NULL
 * or nonzero, and the test asserts. */
#ifndef SW_TEST_HARNESS_H
#define SW_TEST_HARNESS_H

#include "sinew.h"
#include "solver.h"

/* A deterministic uniform random number in [-1, 1). */
double th_rand(unsigned long *state);
/* The mesh of th_grid_model in a model not yet finished (no material, nothing pinned): set
 * m->mat[0] and call sw_model_finish.  Vertex (i, j) = j*nx + i sits at its (u,v). */
sw_model *th_grid_mesh(int dim, int nx, int ny, double sx, double sy);
/* A model on an nx x ny grid of size sx x sy (m) in the plane xy, in dimension dim: bw98 with
 * k_u = kuv, k_v = 0.7 kuv, k_shear (N/m) when kuv > 0; gravity g (m/s^2, dim components) when
 * g is not NULL; density rho (kg/m^2); the top row (y = sy) pinned when pin_top. */
sw_model *th_grid_model(int dim, int nx, int ny, double sx, double sy, double rho, double kuv,
                        double kshear, const double *g, int pin_top);
/* The grid of th_grid_model (vertex (i, j) = j*nx + i, two triangles per cell sharing a
 * face_poly) as an unfinished model with the default material: set what a test needs (mat[0],
 * x0, uv), then th_finish (sw_model_finish; frees the model and returns NULL on error). */
sw_model *th_grid_unfinished(int dim, int nx, int ny, double sx, double sy);
sw_model *th_finish(sw_model *m);
/* th_grid_unfinished over 0.3 x 0.25 m with its interior vertices jittered by up to 20 % of a
 * spacing each way (seeded) and the (u,v) layout following them: an unstructured-looking mesh
 * for the bending models' tests. */
sw_model *th_jittered_unfinished(int dim, int nx, int ny, unsigned long seed);
/* The same grid (with its source quads in face_poly) whose material mat[0] is *mat (set
 * every field: density, membrane, springs, bending), finished. */
sw_model *th_grid_model_mat(int dim, int nx, int ny, double sx, double sy,
                            const sw_material *mat);
/* The same model before sw_model_finish (to add tendons or change options first). */
sw_model *th_grid_start(int dim, int nx, int ny, double sx, double sy, double rho, double kuv,
                        double kshear, const double *g, int pin_top);
/* Append a tendon (law SW_LAW_*, K in N/m, constant rest length in m, density in kg/m) to a
 * model not yet finished. */
void th_add_tendon(sw_model *m, const int *way, int nway, int law, double K, double rest,
                   double density);
/* A scene from YAML text (the name is used in messages); NULL with the message printed. */
sw_model *th_scene(const char *name, const char *text);
/* The scene file at path (relative to the source root, where the tests run); NULL with the
 * message printed. */
sw_model *th_scene_file(const char *path);
/* Fails the test unless |got - want| <= tol, printing both. */
void th_near(double got, double want, double tol);
/* The measured fabric NAME of the shipped presets (docs/fabrics.md), read from its file's text;
 * fails the test when it is unknown or does not parse. */
sw_dde th_dde_preset(const char *name);
/* A new state of m and ops started on it (*s); NULL with the message printed when either
 * fails (the state freed). */
sw_data *th_start(const sw_integrator_ops *ops, const sw_model *m, void **s);
/* sw_static_solve of m from d (pin reactions into r[3], N), its message printed on failure. */
int th_static(const sw_model *m, sw_data *d, double r[3]);

/* Peirce's cantilever (scenes/peirce_cantilever.yaml): m a strip along x whose columns at
 * x <= h (h the first grid spacing) are pinned, solved statically; the angle (degrees) below
 * the horizontal of the chord from the ledge (x = h/2, z = 0) to the tip's mean position, or
 * NAN with the message printed when the solve fails. */
double th_peirce_angle(const sw_model *m);

/* Files: the whole of path (NUL-terminated, malloc'ed), or NULL; the same for dir/name. */
char *th_slurp(const char *path);
/* The same for a file that may hold NUL bytes (a binary frame): its size in *size. */
char *th_slurp_n(const char *path, size_t *size);
char *th_slurp_in(const char *dir, const char *name);
/* 1 if dir/name exists. */
int th_exists_in(const char *dir, const char *name);
/* rm -r path (no symbolic links are followed: they are removed as such). */
void th_remove_tree(const char *path);

/* max_i |a_i - b_i| over n entries. */
double th_max_diff(const double *a, const double *b, int n);
/* Least-squares slope of log(e) against log(h) over n points: an observed convergence order. */
double th_slope(const double *h, const double *e, int n);
/* The dense (nv*dim)^2 Hessian of term k from its blocks (all DOFs, pinned included). */
/* v (p->nnz) = a diagonally dominant system on the whole pattern: 1 on the diagonal, -0.01 off
 * it (positive definite for any pattern of fewer than 100 entries a column). */
void th_fill_dominant(const sw_pattern *p, double *v);
void th_dense_hessian(const sw_model *m, int k, const double *blocks, double *H);
/* H += sum_r u_r u_r^T over term k's low-rank vectors (values as in d->lowrank + d->loff[k]). */
void th_dense_lowrank(const sw_model *m, int k, const double *vecs, double *H);

/* The elastic catenary (H. M. Irvine, "Cable Structures", MIT Press 1981, chapter 2): a cable
 * of unstretched length L0 (m), axial stiffness EA (N) and weight W (N) spread evenly over its
 * unstretched length, hanging from (0, 0) to (l, h) in a vertical plane, x across, z DOWN.
 * With s in [0, L0] the unstretched (Lagrangian) coordinate, H the horizontal component of the
 * tension (the same everywhere) and V the vertical one at s = 0 (the upward force the support
 * at s = 0 exerts), equilibrium and Hooke's law T = EA (ds'/ds - 1) give
 *   x(s) = H s / EA + (H L0 / W) [asinh(V/H) - asinh((V - W s/L0)/H)]
 *   z(s) = (W s / EA)(V/W - s/(2 L0))
 *          + (H L0 / W) [sqrt(1 + (V/H)^2) - sqrt(1 + ((V - W s/L0)/H)^2)]
 * and H, V solve x(L0) = l, z(L0) = h (th_irvine_solve: Newton on these two conditions, whose
 * Jacobian is the symmetric flexibility matrix). */
typedef struct th_irvine {
  double l, h;                 /* span and drop of the far support (z down), m */
  double L0, EA, W;            /* unstretched length m, axial stiffness N, weight N */
  double H, V;                 /* N, filled by th_irvine_solve */
} th_irvine;
/* H and V; 0 on success, -1 when Newton did not converge (residual > 1e-13 of the size). */
int th_irvine_solve(th_irvine *c);
/* The residual (x(L0) - l, z(L0) - h) at (H, V) and its Jacobian d(f1, f2)/d(H, V), row-major. */
void th_irvine_conditions(const th_irvine *c, double H, double V, double f[2], double J[4]);
/* The position (x, z) of the material point s (0 <= s <= L0), z down. */
void th_irvine_point(const th_irvine *c, double s, double *x, double *z);

/* The conformance harness (tests/conformance.c, cmocka asserts): term `name` of m at 12 random
 * states around x0 (stretched, compressed to 0.3 and to 0.05 of x0), size the model's length
 * scale (m): gradient and Hessian against central differences, symmetry, and with the flags
 * the PSD projection, rigid-motion invariance, zero force at rest. */
enum { TH_INTERNAL = 1, TH_REST_FREE = 2, TH_NO_PROJECTION = 4 };
void th_conformance(const sw_model *m, const char *name, int flags, double size,
                    unsigned long seed);
/* The same checks (gradient, Hessian, symmetry; projection unless TH_NO_PROJECTION) at one
 * given state x (nv x dim). */
void th_conformance_at(const sw_model *m, const char *name, int flags, double size,
                       const double *x);

#endif
