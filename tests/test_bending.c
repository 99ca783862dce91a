/* test_bending.c — springs, dihedral and quadratic bending: the conformance harness
 * (tests/conformance.c) in 2D and 3D and at chosen states (near flat, strongly folded, curved
 * rest), zero force at rest (also across a seam), spring counts and forces on a grid, and the
 * bending energy of a strip bent into a circular arc against (k_b/2) Area / R^2. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "terms.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

static sw_material springs_mat(double kst, double ksh, double kbe) {
  sw_material mt = {.density = 0.2, .membrane = SW_MEMBRANE_SPRINGS, .b_u = 1.0, .b_v = 1.0,
                    .ks_stretch = kst, .ks_shear = ksh, .ks_bend = kbe, .tx_k_u = -1.0,
                    .tx_k_v = -1.0};
  return mt;
}

static sw_material bending_mat(int model, double kb, int rest) {
  sw_material mt = {.density = 0.2, .bending = model, .k_bend = kb, .bend_rest = rest,
                    .b_u = 1.0, .b_v = 1.0, .tx_k_u = -1.0, .tx_k_v = -1.0};
  return mt;
}

/* Energy and gradient (nv x dim, zeroed first) of the term named `name` at x. */
static double term_eval(const sw_model *m, const char *name, const double *x, double *grad) {
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    if (strcmp(t->name, name)) continue;
    if (grad) memset(grad, 0, sizeof(double) * (size_t)m->nv * m->dim);
    sw_eval ev = {.x = x, .grad = grad};
    double e = 0.0;
    assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
    return e;
  }
  fail_msg("no term %s", name);
  return 0.0;
}

static double max_abs(const double *v, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s = fmax(s, fabs(v[i]));
  return s;
}

/* ------------------------------------------------------------- conformance */

static void springs_conformance(int dim) {
  sw_material mt = springs_mat(300.0, 40.0, 5.0);
  sw_model *m = th_grid_model_mat(dim, 4, 3, 0.3, 0.2, &mt);
  assert_non_null(m);
  th_conformance(m, "springs", TH_INTERNAL | TH_REST_FREE, 0.3, 777 + (unsigned long)dim);
  sw_model_free(m);
}
static void springs_3d(void **st) { (void)st, springs_conformance(3); }
static void springs_2d(void **st) { (void)st, springs_conformance(2); }

static void quadratic_conformance(int dim) {
  sw_material mt = bending_mat(SW_BENDING_QUADRATIC, 2e-3, SW_BEND_REST_FLAT);
  sw_model *m = th_grid_model_mat(dim, 4, 3, 0.3, 0.2, &mt);
  assert_non_null(m);
  th_conformance(m, "quadratic", TH_INTERNAL | TH_REST_FREE, 0.3, 99 + (unsigned long)dim);
  sw_model_free(m);
}
static void quadratic_3d(void **st) { (void)st, quadratic_conformance(3); }
static void quadratic_2d(void **st) { (void)st, quadratic_conformance(2); }

/* Grid vertices (u, v) wrapped onto a cylinder of radius R about the y axis direction:
 * (R sin(u/R), v, R (1 - cos(u/R))); u = 0 stays put.  x has 3 components per vertex. */
static void wrap_arc(const sw_model *m, double R, double *x) {
  for (int i = 0; i < m->nv; i++) {
    double u = m->x0[3 * i], v = m->x0[3 * i + 1];
    x[3 * i] = R * sin(u / R);
    x[3 * i + 1] = v;
    x[3 * i + 2] = R * (1.0 - cos(u / R));
  }
}

/* Fold the grid about the line u = u0 by phi (rad) and add noise of amplitude amp (m). */
static void fold(const sw_model *m, double u0, double phi, double amp, double *x) {
  unsigned long rs = 4242;
  for (int i = 0; i < m->nv; i++) {
    double u = m->x0[3 * i], r = u - u0;
    x[3 * i] = r > 0.0 ? u0 + r * cos(phi) : u;
    x[3 * i + 1] = m->x0[3 * i + 1];
    x[3 * i + 2] = r > 0.0 ? r * sin(phi) : 0.0;
    for (int a = 0; a < 3; a++) x[3 * i + a] += amp * th_rand(&rs);
  }
}

/* An nx x ny grid of 0.3 x 0.25 m whose interior vertices are moved by up to +-0.2 of a cell
 * in each direction, in x0 and in the (u,v) layout alike (flat rest): no two triangles across
 * an edge form a parallelogram, so morley fits its slopes on every edge that has the vertices. */
static sw_model *jittered_grid(int dim, int nx, int ny, const sw_material *mt, unsigned long seed) {
  sw_model *m = th_jittered_unfinished(dim, nx, ny, seed);
  m->mat[0] = *mt;
  return th_finish(m);
}

/* morley on the jittered grid: the conformance harness in 2D and 3D, isotropic and
 * orthotropic on a panel cut at a bias of 0.3 rad. */
static void morley_conformance(void **st) {
  (void)st;
  for (int k = 0; k < 4; k++) {
    sw_material mt = bending_mat(SW_BENDING_MORLEY, 6e-3, SW_BEND_REST_FLAT);
    if (k >= 2) mt.k_bend_u = 6e-3, mt.k_bend_v = 2e-3, mt.k_bend_bias = 3e-3, mt.bias = 0.3;
    sw_model *m = jittered_grid(2 + k % 2, 6, 5, &mt, 31 + (unsigned long)k);
    assert_non_null(m);
    th_conformance(m, "morley", TH_INTERNAL | TH_REST_FREE, 0.3, 71 + (unsigned long)k);
    sw_model_free(m);
  }
}

/* Consistency: a twist z = eps u v (curvature tensor [[0, eps], [eps, 0]], no moment across
 * the edges of a rectangle, so its free edges take it whole) has the plate's energy
 * (k_b/2) 2 eps^2 Area on the jittered grid with morley, to round-off; the centroid slopes of
 * quadratic (and dihedral) miss it there by per cents. */
static void morley_twist_exact(void **st) {
  (void)st;
  const int model[2] = {SW_BENDING_MORLEY, SW_BENDING_QUADRATIC};
  const char *name[2] = {"morley", "quadratic"};
  double rel[2];
  for (int k = 0; k < 2; k++) {
    sw_material mt = bending_mat(model[k], 2e-3, SW_BEND_REST_FLAT);
    sw_model *m = jittered_grid(3, 9, 8, &mt, 5);
    assert_non_null(m);
    const double eps = 1e-3; /* 1/m */
    double *x = malloc(sizeof(double) * 3 * (size_t)m->nv);
    memcpy(x, m->x0, sizeof(double) * 3 * (size_t)m->nv);
    for (int i = 0; i < m->nv; i++) x[3 * i + 2] = eps * x[3 * i] * x[3 * i + 1];
    double e = term_eval(m, name[k], x, NULL), exact = 0.5 * 2e-3 * 2.0 * eps * eps * 0.3 * 0.25;
    rel[k] = e / exact - 1.0;
    print_message("%s: twist on a jittered grid, energy / plate's - 1 = %+.3e\n", name[k], rel[k]);
    free(x);
    sw_model_free(m);
  }
  assert_true(fabs(rel[0]) < 1e-9);
  assert_true(fabs(rel[1]) > 1e-3);
}

/* Orthotropic bending (warp 3x weft, a bias rigidity between) on a panel cut at a bias of
 * 0.3 rad: both models' derivatives by the conformance harness, the dihedral also folded. */
static void orthotropic_conformance(void **st) {
  (void)st;
  const int model[3] = {SW_BENDING_QUADRATIC, SW_BENDING_QUADRATIC, SW_BENDING_DIHEDRAL};
  const int dim[3] = {2, 3, 3};
  const char *name[3] = {"quadratic", "quadratic", "dihedral"};
  for (int k = 0; k < 3; k++) {
    sw_material mt = bending_mat(model[k], 6e-3, SW_BEND_REST_FLAT);
    mt.k_bend_u = 6e-3, mt.k_bend_v = 2e-3, mt.k_bend_bias = 3e-3, mt.bias = 0.3; /* N m, rad */
    sw_model *m = th_grid_model_mat(dim[k], 4, 3, 0.3, 0.2, &mt);
    assert_non_null(m);
    th_conformance(m, name[k], TH_INTERNAL | TH_REST_FREE, 0.3, 55 + (unsigned long)k);
    if (dim[k] == 3 && model[k] == SW_BENDING_DIHEDRAL) {
      double *x = calloc((size_t)m->nv * 3, sizeof *x);
      fold(m, 0.1, 2.6, 1e-3, x);
      th_conformance_at(m, name[k], 0, 0.3, x);
      free(x);
    }
    sw_model_free(m);
  }
}

static void dihedral_states(void **st) {
  (void)st;
  sw_material mt = bending_mat(SW_BENDING_DIHEDRAL, 2e-3, SW_BEND_REST_FLAT);
  sw_model *m = th_grid_model_mat(3, 4, 3, 0.3, 0.2, &mt);
  assert_non_null(m);
  th_conformance(m, "dihedral", TH_INTERNAL | TH_REST_FREE, 0.3, 31);
  double *x = calloc((size_t)m->nv * 3, sizeof *x);
  fold(m, 0.1, 0.0, 3e-5, x); /* near flat: angles ~ 1e-3 rad */
  th_conformance_at(m, "dihedral", 0, 0.3, x);
  fold(m, 0.1, 2.6, 1e-3, x); /* folded by 149 degrees */
  th_conformance_at(m, "dihedral", 0, 0.3, x);
  fold(m, 0.1, -2.9, 1e-3, x); /* folded the other way by 166 degrees */
  th_conformance_at(m, "dihedral", 0, 0.3, x);
  free(x);
  sw_model_free(m);
}

/* The filtered block of one triangle (a 2 x 2 grid: two triangles, one hinge each) against
 * LAPACK: folded by 1.2 rad with a rest angle of 0 (indefinite), and at rest (W g g^T, PSD):
 * the filter's V f(Lambda) V^T (f: max(., 0) or |.|) plus 1e-10 x its Frobenius norm on the
 * diagonal, while energy and gradient are the exact ones whatever the filter.  Also with the
 * triangle squashed to 1e-12 of its area, where the block's eigenvalues reach ~1e20 N/m. */
static void dihedral_filtered_block(void **st) {
  (void)st;
  sw_material mt = bending_mat(SW_BENDING_DIHEDRAL, 2e-3, SW_BEND_REST_FLAT);
  sw_model *m = th_grid_model_mat(3, 2, 2, 0.1, 0.1, &mt);
  assert_non_null(m);
  const sw_term *t = NULL;
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].name, "dihedral")) t = &m->term[k];
  assert_non_null(t);
  assert_int_equal(t->nstencil, 2);
  assert_int_equal(t->sptr[1], 4);
  /* stencil 0: its face's corners, then the far vertex across; x0, x1 the shared edge, x2 the
   * face's own far corner, x3 the far vertex across */
  int v[4], ne = 0;
  v[3] = t->sidx[3];
  for (int i = 0; i < 3; i++) { /* the edge: corners also in stencil 1's face */
    int c = t->sidx[i], shared = 0;
    for (int j = 4; j < 7; j++) shared |= t->sidx[j] == c;
    if (shared) v[ne++] = c;
    else v[2] = c;
  }
  assert_int_equal(ne, 2);
  const size_t nb = (size_t)t->hptr[t->nstencil];
  double *H = calloc(nb, sizeof *H), *Bf = calloc(nb, sizeof *Bf);
  for (int state = 0; state < 3; state++) {
    double x[12];
    memcpy(x, m->x0, sizeof x);
    if (state >= 1) { /* rotate x3 about the edge by 1.2 rad */
      double o[3], e[3], r[3], L = 0.0;
      for (int i = 0; i < 3; i++) o[i] = x[3 * v[0] + i], e[i] = x[3 * v[1] + i] - o[i];
      for (int i = 0; i < 3; i++) L += e[i] * e[i];
      for (int i = 0; i < 3; i++) e[i] /= sqrt(L), r[i] = x[3 * v[3] + i] - o[i];
      double c = cos(1.2), sn = sin(1.2), er = e[0] * r[0] + e[1] * r[1] + e[2] * r[2];
      double exr[3] = {e[1] * r[2] - e[2] * r[1], e[2] * r[0] - e[0] * r[2], e[0] * r[1] - e[1] * r[0]};
      for (int i = 0; i < 3; i++) x[3 * v[3] + i] = o[i] + r[i] * c + exr[i] * sn + e[i] * er * (1 - c);
    }
    if (state == 2) /* x2 onto the edge's midpoint, 1e-12 of the cell off it (in plane) */
      for (int i = 0; i < 3; i++)
        x[3 * v[2] + i] = 0.5 * (x[3 * v[0] + i] + x[3 * v[1] + i]) +
                          1e-12 * (x[3 * v[2] + i] - 0.5 * (x[3 * v[0] + i] + x[3 * v[1] + i]));
    double g0[12];
    memset(H, 0, nb * sizeof *H), memset(g0, 0, sizeof g0);
    sw_eval ex = {.x = x, .grad = g0, .hess = H, .project = SW_FILTER_NONE};
    double e0 = 0.0;
    assert_int_equal(t->ops->eval(t, m, &ex, &e0), SW_OK);
    for (int mode = SW_FILTER_CLAMP; mode <= SW_FILTER_ABS; mode++) {
      double *B = Bf, g[12], V[144], lam[12], work[12 * 34], R[144] = {0}, e = 0.0;
      int n = 12, lwork = 12 * 34, info = 0;
      memset(B, 0, nb * sizeof *B), memset(g, 0, sizeof g);
      sw_eval ev = {.x = x, .grad = g, .hess = B, .project = mode};
      assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
      assert_true(e == e0);
      for (int i = 0; i < 12; i++) assert_true(g[i] == g0[i]);
      for (int i = 0; i < 144; i++) V[i] = sw_hess_get(H, i / 12, i % 12, 12);
      dsyev_("V", "U", &n, V, &n, lam, work, &lwork, &info);
      assert_int_equal(info, 0);
      if (state >= 1) assert_true(lam[0] < -1e-6 * lam[11]); /* the exact block is indefinite */
      double top = 0.0, fro = 0.0;
      for (int k = 0; k < 12; k++) {
        double l = mode == SW_FILTER_ABS ? fabs(lam[k]) : fmax(lam[k], 0.0);
        top = fmax(top, l), fro += l * l;
        for (int i = 0; i < 12; i++)
          for (int j = 0; j < 12; j++) R[i * 12 + j] += l * V[k * 12 + i] * V[k * 12 + j];
      }
      for (int i = 0; i < 12; i++) R[i * 13] += 1e-10 * sqrt(fro);
      double err = 0.0;
      for (int i = 0; i < 144; i++) err = fmax(err, fabs(sw_hess_get(B, i / 12, i % 12, 12) - R[i]));
      if (state == 2) assert_true(top > 1e18);
      if (!(err <= 1e-13 * top)) print_error("state %d mode %d: |B - R| = %g of %g\n", state, mode, err, top);
      assert_true(err <= 1e-13 * top);
    }
  }
  free(H), free(Bf);
  sw_model_free(m);
}

/* A 2D scene cannot bend out of plane: the dihedral term refuses it. */
static void dihedral_refuses_2d(void **st) {
  (void)st;
  sw_material mt = bending_mat(SW_BENDING_QUADRATIC, 1e-3, SW_BEND_REST_FLAT);
  sw_model *m = th_grid_model_mat(2, 3, 3, 0.2, 0.2, &mt);
  assert_non_null(m);
  sw_term t = {0};
  char err[SW_ERRSZ] = "";
  assert_int_not_equal(sw_dihedral_build(&t, m, err, sizeof err), 0);
  assert_non_null(strstr(err, "dimension 3"));
  sw_term_free(&t);
  sw_model_free(m);
  sw_model *m2 = th_grid_unfinished(2, 3, 3, 0.2, 0.2);
  m2->mat[0] = bending_mat(SW_BENDING_DIHEDRAL, 1e-3, SW_BEND_REST_FLAT);
  assert_int_not_equal(sw_model_finish(m2, err, sizeof err), 0);
  sw_model_free(m2);
}

/* ---------------------------------------------------------------- at rest */

/* Rest = initial on a curved x0 (an arc of radius 0.15 m): zero force there, and the harness
 * (which checks zero force at x0 moved rigidly) at states around it. */
static void dihedral_curved_rest(void **st) {
  (void)st;
  sw_model *m = th_grid_unfinished(3, 5, 3, 0.3, 0.1);
  m->mat[0] = bending_mat(SW_BENDING_DIHEDRAL, 2e-3, SW_BEND_REST_INITIAL);
  double *x = calloc((size_t)m->nv * 3, sizeof *x), *g = calloc((size_t)m->nv * 3, sizeof *g);
  wrap_arc(m, 0.15, x);
  memcpy(m->x0, x, sizeof(double) * (size_t)m->nv * 3);
  assert_non_null(m = th_finish(m));
  assert_true(term_eval(m, "dihedral", m->x0, g) < 1e-28);
  assert_true(max_abs(g, m->nv * 3) < 1e-14);
  th_conformance(m, "dihedral", TH_INTERNAL | TH_REST_FREE, 0.3, 5);
  /* flattened, it is not at rest: the energy is that of the arc */
  for (int i = 0; i < m->nv; i++) x[3 * i + 2] = 0.0, x[3 * i] = 0.3 * (i % 5) / 4.0;
  assert_true(term_eval(m, "dihedral", x, NULL) > 1e-4);
  free(x), free(g);
  sw_model_free(m);
}

/* Shift and rotate the (u,v) of every face in the cells i >= 2 (a second panel sewn to the
 * first along u = 2 h): every rest quantity, measured in each face's own layout, is unchanged,
 * so the flat x0 is still at rest for every term. */
static void seam_rest(void **st) {
  (void)st;
  const int models[4][2] = {{SW_MEMBRANE_SPRINGS, SW_BENDING_NONE},
                            {SW_MEMBRANE_NONE, SW_BENDING_QUADRATIC},
                            {SW_MEMBRANE_NONE, SW_BENDING_DIHEDRAL},
                            {SW_MEMBRANE_NONE, SW_BENDING_MORLEY}};
  const char *names[4] = {"springs", "quadratic", "dihedral", "morley"};
  for (int k = 0; k < 4; k++) {
    sw_model *m = th_grid_unfinished(3, 5, 4, 0.4, 0.3);
    m->mat[0] = springs_mat(100.0, 10.0, 1.0);
    m->mat[0].membrane = models[k][0];
    m->mat[0].bending = models[k][1];
    m->mat[0].k_bend = 1e-3;
    m->mat[0].bend_rest = SW_BEND_REST_FLAT;
    const double c = cos(0.7), s = sin(0.7);
    for (int f = 0; f < m->nf; f++) {
      double umin = 1e9;
      for (int i = 0; i < 3; i++) umin = fmin(umin, m->uv[6 * f + 2 * i]);
      if (umin < 0.19) continue;
      for (int i = 0; i < 3; i++) {
        double *p = m->uv + 6 * f + 2 * i, u = p[0], v = p[1];
        p[0] = 2.0 + c * u - s * v;
        p[1] = -1.0 + s * u + c * v;
      }
    }
    assert_non_null(m = th_finish(m));
    double *g = calloc((size_t)m->nv * 3, sizeof *g);
    double e = term_eval(m, names[k], m->x0, g);
    if (e > 1e-24 || max_abs(g, m->nv * 3) > 1e-11)
      print_error("%s across a seam: E %g, |g| %g\n", names[k], e, max_abs(g, m->nv * 3));
    assert_true(e < 1e-24 && max_abs(g, m->nv * 3) < 1e-11);
    free(g);
    sw_model_free(m);
  }
}

/* ---------------------------------------------------------------- springs */

/* On an nx x ny grid: stretch springs on the (nx-1) ny + nx (ny-1) grid lines, shear springs
 * on both diagonals of the (nx-1)(ny-1) quads, bend springs across the (nx-1)(ny-2) interior
 * horizontal and (nx-2)(ny-1) interior vertical edges.  Without source polygons there are no
 * quads: every edge stretches and every interior edge bends. */
static void springs_counts(void **st) {
  (void)st;
  const int nx = 6, ny = 5;
  sw_material mt = springs_mat(100.0, 10.0, 1.0);
  sw_model *m = th_grid_model_mat(3, nx, ny, 0.5, 0.4, &mt);
  assert_non_null(m);
  int c[3];
  sw_springs_counts(&m->term[0], c);
  assert_int_equal(c[SW_SPRING_STRETCH], (nx - 1) * ny + nx * (ny - 1));
  assert_int_equal(c[SW_SPRING_SHEAR], 2 * (nx - 1) * (ny - 1));
  assert_int_equal(c[SW_SPRING_BEND], (nx - 1) * (ny - 2) + (nx - 2) * (ny - 1));
  assert_int_equal(m->term[0].nstencil, c[0] + c[1] + c[2]);
  free(m->face_poly);
  m->face_poly = NULL;
  sw_term t = {0};
  char err[SW_ERRSZ];
  assert_int_equal(sw_springs_build(&t, m, err, sizeof err), 0);
  sw_springs_counts(&t, c);
  int nd = (nx - 1) * (ny - 1);
  assert_int_equal(c[SW_SPRING_STRETCH], (nx - 1) * ny + nx * (ny - 1) + nd);
  assert_int_equal(c[SW_SPRING_SHEAR], 0);
  assert_int_equal(c[SW_SPRING_BEND], (nx - 1) * (ny - 2) + (nx - 2) * (ny - 1) + nd);
  sw_term_free(&t);
  sw_model_free(m);
}

/* Uniform stretch by s along u (no bend springs): a horizontal spring pulls with
 * k_st (s - 1) hx, each diagonal with k_sh (l_d - L_d); an interior vertex is in balance and a
 * vertex on the right edge (not a corner) feels k_st (s-1) hx + 2 k_sh (l_d - L_d) s hx / l_d
 * along u, nothing along v. */
static void springs_uniform_stretch(int dim) {
  const int nx = 5, ny = 4;
  const double hx = 0.1, hy = 0.1, s = 1.1, kst = 100.0, ksh = 10.0;
  sw_material mt = springs_mat(kst, ksh, 0.0);
  sw_model *m = th_grid_model_mat(dim, nx, ny, hx * (nx - 1), hy * (ny - 1), &mt);
  assert_non_null(m);
  const int n = m->nv * dim;
  double *x = malloc(sizeof(double) * (size_t)n), *g = calloc((size_t)n, sizeof *g);
  memcpy(x, m->x0, sizeof(double) * (size_t)n);
  for (int i = 0; i < m->nv; i++) x[i * dim] *= s;
  term_eval(m, "springs", x, g);
  double Ld = hypot(hx, hy), ld = hypot(s * hx, hy);
  double want = kst * (s - 1.0) * hx + 2.0 * ksh * (ld - Ld) * s * hx / ld; /* N */
  int right = 1 * nx + nx - 1, inner = 2 * nx + 2;
  assert_float_equal(g[right * dim], want, 1e-12 * want);
  for (int a = 1; a < dim; a++) assert_float_equal(g[right * dim + a], 0.0, 1e-12 * want);
  for (int a = 0; a < dim; a++) assert_float_equal(g[inner * dim + a], 0.0, 1e-12 * want);
  free(x), free(g);
  sw_model_free(m);
}
static void springs_stretch_2d(void **st) { (void)st, springs_uniform_stretch(2); }
static void springs_stretch_3d(void **st) { (void)st, springs_uniform_stretch(3); }

/* ------------------------------------------------------------------ arc */

/* A 1 m x 0.1 m strip with square cells of side h bent along its length into an arc of radius
 * R: E against (k_b/2) Area / R^2 at four resolutions.  Returns the fitted rate of the
 * relative error in h and the finest relative error. */
static double arc_rate(int model, const char *name, double *finest) {
  const double R = 0.5, kb = 1e-3, area = 0.1, want = 0.5 * kb * area / (R * R); /* J */
  const int ny[4] = {3, 5, 9, 17};
  double lh[4], le[4];
  for (int r = 0; r < 4; r++) {
    int nx = 10 * (ny[r] - 1) + 1;
    sw_material mt = bending_mat(model, kb, SW_BEND_REST_FLAT);
    sw_model *m = th_grid_model_mat(3, nx, ny[r], 1.0, 0.1, &mt);
    assert_non_null(m);
    double *x = calloc((size_t)m->nv * 3, sizeof *x);
    wrap_arc(m, R, x);
    double e = term_eval(m, name, x, NULL), rel = fabs(e - want) / want;
    print_message("%-9s h = %.5f m: E = %.8e J, (k_b/2) A/R^2 = %.8e J, rel. error %.3e\n", name,
                  1.0 / (nx - 1), e, want, rel);
    lh[r] = log(1.0 / (nx - 1));
    le[r] = log(rel);
    *finest = rel;
    free(x);
    sw_model_free(m);
  }
  double mh = 0, me = 0, sxx = 0, sxy = 0;
  for (int r = 0; r < 4; r++) mh += lh[r] / 4, me += le[r] / 4;
  for (int r = 0; r < 4; r++) {
    sxx += (lh[r] - mh) * (lh[r] - mh);
    sxy += (lh[r] - mh) * (le[r] - me);
  }
  print_message("%s: observed convergence rate %.3f\n", name, sxy / sxx);
  return sxy / sxx;
}

static void arc_dihedral(void **st) {
  (void)st;
  double fine, rate = arc_rate(SW_BENDING_DIHEDRAL, "dihedral", &fine);
  assert_true(rate > 0.9 && rate < 1.2);
  assert_true(fine < 0.02);
}

static void arc_quadratic(void **st) {
  (void)st;
  double fine, rate = arc_rate(SW_BENDING_QUADRATIC, "quadratic", &fine);
  assert_true(rate > 0.9 && rate < 1.2);
  assert_true(fine < 0.02);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(springs_3d),          cmocka_unit_test(springs_2d),
      cmocka_unit_test(quadratic_3d),        cmocka_unit_test(quadratic_2d),
      cmocka_unit_test(dihedral_states),     cmocka_unit_test(dihedral_refuses_2d),
      cmocka_unit_test(dihedral_filtered_block),
      cmocka_unit_test(dihedral_curved_rest), cmocka_unit_test(seam_rest),
      cmocka_unit_test(springs_counts),      cmocka_unit_test(springs_stretch_2d),
      cmocka_unit_test(springs_stretch_3d),  cmocka_unit_test(arc_dihedral),
      cmocka_unit_test(arc_quadratic),       cmocka_unit_test(orthotropic_conformance),
      cmocka_unit_test(morley_conformance),  cmocka_unit_test(morley_twist_exact),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
