/* test_tendons.c — the tendon term (models/tendon.c, the tendon model) and its low-rank path:
 *   - conformance (gradient, Hessian, symmetry, PSD projection, rigid motions) on tendons of
 *     2, 3 and 20 waypoints in 2D and 3D, spring and taut cable, dense and low-rank storage;
 *   - a slack cable exerts nothing; a straight two-waypoint tendon pulls with K (l - alpha)
 *     along its segment; forces sum to zero; keyframed rest lengths and ev->t;
 *   - coincident waypoints give finite values;
 *   - the low-rank path gives the dense path's Newton step, CVODE and IDA solves;
 *   - a hanging cable solved statically matches the elastic catenary (Irvine). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "solver.h"
#include "sundials_ls.h"
#include "terms.h"

/* A model of n vertices (no faces) on a random zig-zag of about `len` metres, one tendon
 * through all of them; rest = rest_frac times the initial length. */
static sw_model *chain_model(int dim, int n, int law, double rest_frac, int dense_max,
                             unsigned long seed) {
  sw_model *m = sw_model_new();
  m->dim = dim;
  m->nv = n;
  m->x0 = calloc((size_t)n * dim, sizeof(double));
  m->v0 = calloc((size_t)n * dim, sizeof(double));
  m->pinned = calloc((size_t)n, 1);
  int *way = malloc(sizeof(int) * (size_t)n);
  for (int i = 0; i < n; i++) {
    way[i] = i;
    m->x0[i * dim] = 0.1 * i + 0.02 * th_rand(&seed);
    m->x0[i * dim + 1] = 0.05 * (i % 2) + 0.02 * th_rand(&seed);
    if (dim == 3) m->x0[i * dim + 2] = 0.03 * th_rand(&seed);
  }
  m->ntendon = 0;
  th_add_tendon(m, way, n, law, 300.0, 1.0, 0.1);
  m->tendon[0].key_rest[0] = rest_frac * sw_tendon_length(&m->tendon[0], m->x0, dim);
  m->opt.tendon_dense_max = dense_max;
  free(way);
  char err[SW_ERRSZ];
  if (sw_model_finish(m, err, sizeof err)) print_error("%s\n", err);
  return m;
}

static void conformance(int dim, int n, int law, int dense_max) {
  /* a spring at its initial length is force-free at rest; a taut cable is stretched */
  double rest = law == SW_LAW_SPRING ? 1.0 : 1e-3;
  sw_model *m = chain_model(dim, n, law, rest, dense_max, 99 + (unsigned long)(n * dim));
  assert_non_null(m);
  assert_int_equal(m->term[0].nlowrank, n > dense_max ? 1 : 0);
  int flags = TH_INTERNAL | (law == SW_LAW_SPRING ? TH_REST_FREE : 0);
  th_conformance(m, "tendons", flags, 0.1, 777 + (unsigned long)n);
  sw_model_free(m);
}

static void conformance_spring(void **st) {
  (void)st;
  for (int dim = 2; dim <= 3; dim++) {
    conformance(dim, 2, SW_LAW_SPRING, SW_TENDON_DENSE_MAX);
    conformance(dim, 3, SW_LAW_SPRING, SW_TENDON_DENSE_MAX);
    conformance(dim, 20, SW_LAW_SPRING, 100); /* dense */
    conformance(dim, 20, SW_LAW_SPRING, 0);   /* banded + low rank */
    conformance(dim, 3, SW_LAW_SPRING, 0);
  }
}

static void conformance_cable(void **st) {
  (void)st;
  for (int dim = 2; dim <= 3; dim++) {
    conformance(dim, 2, SW_LAW_CABLE, SW_TENDON_DENSE_MAX);
    conformance(dim, 3, SW_LAW_CABLE, SW_TENDON_DENSE_MAX);
    conformance(dim, 20, SW_LAW_CABLE, 100);
    conformance(dim, 20, SW_LAW_CABLE, 0);
  }
}

/* Energy, gradient (into d->grad) and Hessian (d->hess, d->lowrank) of the model at x, t. */
static double eval_all(const sw_model *m, sw_data *d, const double *x, double t) {
  double e;
  assert_int_equal(sw_eval_terms(m, d, x, t, 1, 1, 0, &e), SW_OK);
  return e;
}

static double max_abs(const double *v, long n) {
  double s = 0.0;
  for (long i = 0; i < n; i++) s = fmax(s, fabs(v[i]));
  return s;
}

/* A cable longer than its path: zero energy, force and Hessian, in both storages. */
static void slack_cable(void **st) {
  (void)st;
  for (int dense_max = 0; dense_max <= 100; dense_max += 100) {
    sw_model *m = chain_model(3, 12, SW_LAW_CABLE, 1.3, dense_max, 5);
    sw_data *d = sw_data_new(m);
    assert_true(eval_all(m, d, m->x0, 0.0) == 0.0);
    assert_true(max_abs(d->grad, m->nv * 3) == 0.0);
    assert_true(max_abs(d->hess, d->hoff[m->nterm]) == 0.0);
    assert_true(max_abs(d->lowrank, d->loff[m->nterm]) == 0.0);
    sw_tendon_state(m, d);
    assert_true(d->tendon_tension[0] == 0.0 && d->tendon_delta[0] < 0.0);
    sw_data_free(d);
    sw_model_free(m);
  }
}

/* Two waypoints at p0, p1: f1 = -grad_1 E = K (l - alpha) (p0 - p1)/l, f0 = -f1. */
static void straight_two(void **st) {
  (void)st;
  for (int law = SW_LAW_SPRING; law <= SW_LAW_CABLE; law++) {
    sw_model *m = chain_model(3, 2, law, 0.8, SW_TENDON_DENSE_MAX, 11);
    sw_data *d = sw_data_new(m);
    const double x[6] = {0.1, -0.2, 0.3, 0.7, 0.1, -0.3};
    double l = sqrt(0.36 + 0.09 + 0.36), alpha = m->tendon[0].key_rest[0], K = 300.0;
    double e = eval_all(m, d, x, 0.0);
    assert_true(fabs(e - 0.5 * K * (l - alpha) * (l - alpha)) < 1e-12 * e);
    for (int a = 0; a < 3; a++) {
      double f1 = K * (l - alpha) * (x[a] - x[3 + a]) / l; /* N */
      assert_true(fabs(-d->grad[3 + a] - f1) < 1e-12 * K);
      assert_true(fabs(d->grad[a] + d->grad[3 + a]) < 1e-12 * K);
    }
    memcpy(d->x, x, sizeof x);
    sw_tendon_state(m, d);
    assert_true(fabs(d->tendon_tension[0] - K * (l - alpha)) < 1e-12 * K);
    assert_true(fabs(d->tendon_length[0] - l) < 1e-15);
    sw_data_free(d);
    sw_model_free(m);
  }
}

/* The forces of a tendon sum to zero over its waypoints (it is internal). */
static void forces_sum_to_zero(void **st) {
  (void)st;
  unsigned long rs = 3;
  for (int dim = 2; dim <= 3; dim++) {
    sw_model *m = chain_model(dim, 20, SW_LAW_CABLE, 0.7, 0, 21);
    sw_data *d = sw_data_new(m);
    double *x = malloc(sizeof(double) * (size_t)(m->nv * dim));
    for (int i = 0; i < m->nv * dim; i++) x[i] = m->x0[i] + 0.05 * th_rand(&rs);
    eval_all(m, d, x, 0.0);
    double net[3] = {0};
    for (int i = 0; i < m->nv; i++)
      for (int a = 0; a < dim; a++) net[a] += d->grad[i * dim + a];
    double scale = max_abs(d->grad, m->nv * dim);
    assert_true(scale > 1.0);
    for (int a = 0; a < dim; a++) assert_true(fabs(net[a]) < 1e-13 * scale * m->nv);
    free(x);
    sw_data_free(d);
    sw_model_free(m);
  }
}

/* Keyframes (0, 1.0), (1, 0.6), (2, 0.8): piecewise linear, constant outside; the term
 * evaluates E at the rest length of ev->t. */
static void keyframes(void **st) {
  (void)st;
  sw_model *m = chain_model(2, 2, SW_LAW_SPRING, 1.0, SW_TENDON_DENSE_MAX, 8);
  sw_tendon *td = &m->tendon[0];
  td->nkey = 3;
  td->key_t = realloc(td->key_t, 3 * sizeof(double));
  td->key_rest = realloc(td->key_rest, 3 * sizeof(double));
  const double kt[3] = {0.0, 1.0, 2.0}, kr[3] = {1.0, 0.6, 0.8};
  memcpy(td->key_t, kt, sizeof kt);
  memcpy(td->key_rest, kr, sizeof kr);
  const double t[6] = {-1.0, 0.0, 0.5, 1.5, 2.0, 7.0}, want[6] = {1.0, 1.0, 0.8, 0.7, 0.8, 0.8};
  sw_data *d = sw_data_new(m);
  double l = sw_tendon_length(td, m->x0, 2);
  for (int k = 0; k < 6; k++) {
    assert_true(fabs(sw_tendon_rest(td, t[k]) - want[k]) < 1e-15);
    double e = eval_all(m, d, m->x0, t[k]), dl = l - want[k];
    assert_true(fabs(e - 0.5 * 300.0 * dl * dl) < 1e-12 * (e + 1e-300));
  }
  sw_data_free(d);
  sw_model_free(m);
}

/* Coincident waypoints: finite energy, force and Hessian (the segment counts no direction). */
static void coincident_waypoints(void **st) {
  (void)st;
  for (int dense_max = 0; dense_max <= 100; dense_max += 100) {
    sw_model *m = chain_model(3, 4, SW_LAW_SPRING, 0.5, dense_max, 9);
    sw_data *d = sw_data_new(m);
    double x[12];
    memcpy(x, m->x0, sizeof x);
    memcpy(x + 6, x + 3, 3 * sizeof(double)); /* waypoint 2 on waypoint 1 */
    double e = eval_all(m, d, x, 0.0);
    assert_true(isfinite(e) && e > 0.0);
    assert_true(isfinite(max_abs(d->grad, 12)));
    assert_true(isfinite(max_abs(d->hess, d->hoff[m->nterm])));
    assert_true(isfinite(max_abs(d->lowrank, d->loff[m->nterm])));
    sw_data_free(d);
    sw_model_free(m);
  }
}

/* Two waypoints closer than the smoothing width eps (1e-3 of the rest length per segment;
 * docs/tendons.md, "Zero-length segments"): the rounded tip of |s| has the derivatives of
 * central differences, in both storages, and the length there is (|s|^2 + eps^2) / (2 eps). */
static void short_segment(void **st) {
  (void)st;
  for (int dense_max = 0; dense_max <= 100; dense_max += 100) {
    sw_model *m = chain_model(3, 4, SW_LAW_SPRING, 0.5, dense_max, 9);
    const sw_tendon *td = &m->tendon[0];
    double eps = 1e-3 * td->key_rest[0] / 3.0, x[12], r = 0.4 * eps; /* m */
    memcpy(x, m->x0, sizeof x);
    for (int c = 0; c < 3; c++) x[6 + c] = x[3 + c] + r * (c == 0 ? 1.0 : 2.0) / 3.0;
    double l01 = 0.0, l23 = 0.0;
    for (int c = 0; c < 3; c++) {
      l01 += (x[c] - x[3 + c]) * (x[c] - x[3 + c]);
      l23 += (x[6 + c] - x[9 + c]) * (x[6 + c] - x[9 + c]);
    }
    double want = sqrt(l01) + (r * r + eps * eps) / (2.0 * eps) + sqrt(l23);
    assert_true(fabs(sw_tendon_length(td, x, 3) - want) < 1e-14);
    th_conformance_at(m, "tendons", 0, 0.1, x);
    sw_model_free(m);
  }
}

/* ---------------------------------------------------- low-rank path against dense blocks */

/* An 8 x 8 cloth (top row pinned, gravity) with a 30-waypoint spring zig-zag and a
 * 12-waypoint cable that starts on the pinned row, rest lengths rest_frac of the initial
 * ones; dense_max decides the storage. */
static sw_model *cloth_tendons(int dense_max, double rest_frac) {
  const double g[3] = {0.0, 0.0, -9.81};
  const int n = 8;
  sw_model *m = th_grid_start(3, n, n, 0.3, 0.3, 0.1, 200.0, 20.0, g, 1);
  int way[30], way2[12];
  for (int k = 0; k < 30; k++) {
    int row = 5 - k / n, col = (k / n) % 2 ? n - 1 - k % n : k % n;
    way[k] = row * n + col;
  }
  for (int k = 0; k < 12; k++) way2[k] = (n - 1 - k / 2) * n + (k % 2 ? 6 : 5) - (k / 4);
  th_add_tendon(m, way, 30, SW_LAW_SPRING, 80.0, 1.0, 0.0);
  th_add_tendon(m, way2, 12, SW_LAW_CABLE, 50.0, 1.0, 0.0);
  for (int k = 0; k < 2; k++)
    m->tendon[k].key_rest[0] = rest_frac * sw_tendon_length(&m->tendon[k], m->x0, 3);
  m->opt.tendon_dense_max = dense_max;
  char err[SW_ERRSZ];
  if (sw_model_finish(m, err, sizeof err)) print_error("%s\n", err);
  return m;
}

static double rel_diff(const double *a, const double *b, long n) {
  double num = 0.0, den = 0.0;
  for (long i = 0; i < n; i++) {
    num = fmax(num, fabs(a[i] - b[i]));
    den = fmax(den, fabs(b[i]));
  }
  return num / den;
}

/* x0 plus a random displacement of the free vertices (m). */
static void perturbed(const sw_model *m, double amp, double *x) {
  unsigned long rs = 42;
  for (int i = 0; i < m->nv * m->dim; i++)
    x[i] = m->x0[i] + (m->dof[i] >= 0 ? amp * th_rand(&rs) : 0.0);
}

/* S dx = -grad Phi at x for one storage (a in 1/s^2; projected or exact H), and one full
 * Newton step of sw_newton_solve from x into xs.  Returns the pattern's nnz. */
static long newton_system(const sw_model *m, const double *x, double a, int project, double *dx,
                          double *xs) {
  sw_data *d = sw_data_new(m);
  sw_newton nw;
  char err[SW_ERRSZ];
  double phi;
  assert_int_equal(sw_newton_init(&nw, m, err, sizeof err), SW_OK);
  long nnz = nw.pat.nnz;
  assert_int_equal(sw_newton_phi(&nw, m, d, x, m->x0, a, 0.0, 1, 1, project, &phi), 0);
  sw_pattern_fill(&nw.pat, m, d, a, 1.0, sw_chol_values(&nw.chol));
  sw_pattern_fill_lowrank(&nw.pat, d, sw_chol_lowrank(&nw.chol, 1.0));
  int rc = sw_chol_factor(&nw.chol, err, sizeof err);
  if (rc) print_error("%s\n", err);
  assert_int_equal(rc, SW_OK);
  for (int c = 0; c < nw.n; c++) nw.g[c] = -nw.g[c];
  assert_int_equal(sw_chol_solve(&nw.chol, nw.g, dx, err, sizeof err), SW_OK);
  memcpy(xs, x, sizeof(double) * (size_t)(m->nv * m->dim));
  sw_newton_opts o = {.a = a, .max_iter = 1, .tol_dx = 0.0,
                      .hessian = project ? SW_HESSIAN_PROJECTED : SW_HESSIAN_EXACT};
  assert_int_equal(sw_newton_solve(&nw, m, d, xs, m->x0, &o), SW_OK);
  sw_newton_free(&nw);
  sw_data_free(d);
  return nnz;
}

/* The Newton system and one Newton step agree to rounding (exact and projected H). */
static void lowrank_newton(void **st) {
  (void)st;
  sw_model *md = cloth_tendons(1000, 0.9), *ml = cloth_tendons(1, 0.9);
  assert_int_equal(md->term[1].nlowrank, 0);
  assert_int_equal(ml->term[1].nlowrank, 2);
  const int nd = md->nv * 3, n = md->ndof;
  double *x = malloc(sizeof(double) * nd), *dx[2], *xs[2];
  for (int k = 0; k < 2; k++) {
    dx[k] = malloc(sizeof(double) * n);
    xs[k] = malloc(sizeof(double) * nd);
  }
  perturbed(md, 0.01, x);
  for (int project = 0; project <= 1; project++) {
    double a = project ? 1e4 : 1e8; /* 1/s^2: the exact H of the compressed cloth needs a
                                       large mass term to keep S positive definite */
    long nnz_d = newton_system(md, x, a, project, dx[0], xs[0]);
    long nnz_l = newton_system(ml, x, a, project, dx[1], xs[1]);
    assert_true(nnz_l < nnz_d);
    double e1 = rel_diff(dx[1], dx[0], n), e2 = rel_diff(xs[1], xs[0], nd);
    print_message("low rank vs dense (project %d): dx %.2e, x %.2e\n", project, e1, e2);
    assert_true(e1 < 1e-11 && e2 < 1e-13);
  }
  for (int k = 0; k < 2; k++) free(dx[k]), free(xs[k]);
  free(x);
  sw_model_free(md);
  sw_model_free(ml);
}

/* The Schur reductions of CVODE and IDA solve the same systems with both storages. */
static void reduce_both(sw_model *m, sw_sunls_reduce_fn reduce, double coef, const double *x,
                        const double *b, double *out) {
  sw_data *d = sw_data_new(m);
  sw_sunls sys;
  char err[SW_ERRSZ];
  assert_int_equal(sw_sunls_init(&sys, m, d, reduce, err, sizeof err), SW_OK);
  double *y = malloc(sizeof(double) * 2 * (size_t)sys.n);
  sw_sunls_gather(&sys, x, d->v, y);
  assert_int_equal(sw_sunls_hessian(&sys, y, 0.0), SW_OK);
  int cvode = reduce == sw_cvode_reduce;
  sys.cm = cvode ? 1.0 : coef * coef;
  sys.ch = cvode ? coef * coef : 1.0;
  sys.coef_next = coef;
  assert_int_equal(SUNLinSolSetup(sys.LS, sys.A), 0);
  assert_int_equal(reduce(&sys, b, out), SW_OK);
  free(y);
  sw_sunls_free(&sys);
  sw_data_free(d);
}

static void lowrank_sundials_systems(void **st) {
  (void)st;
  sw_model *md = cloth_tendons(1000, 0.9), *ml = cloth_tendons(1, 0.9);
  const int nd = md->nv * 3, n = md->ndof;
  double *x = malloc(sizeof(double) * nd), *b = malloc(sizeof(double) * 2 * n);
  double *o0 = malloc(sizeof(double) * 2 * n), *o1 = malloc(sizeof(double) * 2 * n);
  perturbed(md, 0.01, x);
  unsigned long rs = 7;
  for (int c = 0; c < 2 * n; c++) b[c] = th_rand(&rs);
  reduce_both(md, sw_cvode_reduce, 0.01, x, b, o0); /* gamma = 0.01 s */
  reduce_both(ml, sw_cvode_reduce, 0.01, x, b, o1);
  assert_true(rel_diff(o1, o0, 2 * n) < 1e-11);
  reduce_both(md, sw_ida_reduce, 100.0, x, b, o0); /* cj = 100 1/s */
  reduce_both(ml, sw_ida_reduce, 100.0, x, b, o1);
  assert_true(rel_diff(o1, o0, 2 * n) < 1e-11);
  free(x), free(b), free(o0), free(o1);
  sw_model_free(md);
  sw_model_free(ml);
}

/* 0.1 s of CVODE and of IDA (rtol 1e-8): both storages follow the same trajectory. */
static void lowrank_sundials_runs(void **st) {
  (void)st;
  const sw_integrator_ops *ops[2] = {&sw_cvode_ops, &sw_ida_ops};
  for (int k = 0; k < 2; k++) {
    double *xe[2];
    long nst[2];
    for (int s = 0; s < 2; s++) {
      sw_model *m = cloth_tendons(s ? 1 : 1000, 1.0); /* no buckling: a smooth trajectory */
      m->opt.rtol = 1e-8;
      m->opt.atol = 1e-10;
      sw_data *d = sw_data_new(m);
      void *state = NULL;
      char err[SW_ERRSZ];
      assert_int_equal(ops[k]->init(&state, m, d, err, sizeof err), SW_OK);
      int rc = ops[k]->step(state, m, d, 0.1);
      if (rc) print_error("%s: %s\n", ops[k]->name, d->err);
      assert_int_equal(rc, SW_OK);
      xe[s] = malloc(sizeof(double) * (size_t)(m->nv * 3));
      memcpy(xe[s], d->x, sizeof(double) * (size_t)(m->nv * 3));
      nst[s] = d->nstep;
      ops[k]->free(state);
      sw_data_free(d);
      sw_model_free(m);
    }
    double e = rel_diff(xe[1], xe[0], 64 * 3);
    print_message("%s: low rank vs dense %.2e (steps %ld, %ld)\n", ops[k]->name, e,
                              nst[0], nst[1]);
    assert_true(e < 1e-9);
    free(xe[0]), free(xe[1]);
  }
}

/* ------------------------------------------------------------------ hanging cable */

/* The elastic catenary (Irvine 1981): a cable of unstretched length L0, axial stiffness EA
 * (N) and weight w per unstretched length (N/m) between level supports S apart.  The
 * horizontal tension H solves S = H L0/EA + (2H/w) asinh(w L0 / 2H); the mid-span sag is
 * (H/w) (sqrt(1 + (w L0/2H)^2) - 1) + w L0^2 / (8 EA). */
static double catenary_sag(double S, double L0, double EA, double w) {
  double lo = 1e-9, hi = 1e9;
  for (int it = 0; it < 200; it++) {
    double H = sqrt(lo * hi);
    double span = H * L0 / EA + 2.0 * H / w * asinh(w * L0 / (2.0 * H));
    if (span > S) hi = H;
    else lo = H;
  }
  double H = sqrt(lo * hi), v = w * L0 / (2.0 * H);
  return H / w * (sqrt(1.0 + v * v) - 1.0) + w * L0 * L0 / (8.0 * EA);
}

/* N two-waypoint cable tendons (K = EA N / L0, rest L0/N each) from (0,0,0) to (S,0,0), both
 * ends pinned, linear density giving the weight W, statically solved: |z| at mid-span. */
static double discrete_sag(int N, double S, double L0, double EA, double W, int dense_max,
                           double *reaction_z) {
  sw_model *m = sw_model_new();
  m->dim = 3;
  m->nv = N + 1;
  m->x0 = calloc((size_t)m->nv * 3, sizeof(double));
  m->v0 = calloc((size_t)m->nv * 3, sizeof(double));
  m->pinned = calloc((size_t)m->nv, 1);
  m->pinned[0] = m->pinned[N] = 1;
  m->has_gravity = 1;
  m->gravity[2] = -9.81;
  for (int i = 0; i <= N; i++) m->x0[3 * i] = S * i / N;
  double rho = W / (9.81 * S); /* kg/m of the initial (straight) length, as lumped_mass uses */
  for (int i = 0; i < N; i++) {
    int way[2] = {i, i + 1};
    th_add_tendon(m, way, 2, SW_LAW_CABLE, EA * N / L0, L0 / N, rho);
  }
  m->opt.tendon_dense_max = dense_max;
  char err[SW_ERRSZ];
  assert_int_equal(sw_model_finish(m, err, sizeof err), 0);
  sw_data *d = sw_data_new(m);
  double reaction[3];
  int rc = sw_static_solve(m, d, reaction, err, sizeof err);
  if (rc) print_error("%s\n", err);
  assert_int_equal(rc, 0);
  double sag = -d->x[3 * (N / 2) + 2];
  *reaction_z = reaction[2];
  sw_data_free(d);
  sw_model_free(m);
  return sag;
}

static void hanging_cable(void **st) {
  (void)st;
  const double S = 1.0, L0 = 0.98, EA = 100.0, W = 1.0; /* m, m, N, N */
  double exact = catenary_sag(S, L0, EA, W / L0), err[3], rz;
  const int Ns[3] = {10, 20, 40};
  for (int k = 0; k < 3; k++) {
    double sag = discrete_sag(Ns[k], S, L0, EA, W, SW_TENDON_DENSE_MAX, &rz);
    err[k] = fabs(sag - exact) / exact;
    print_message("hanging cable N = %d: sag %.8f m, elastic catenary %.8f m, rel err %.2e\n",
                  Ns[k], sag, exact, err[k]);
    assert_true(fabs(rz - W) < 1e-8 * W); /* the pins carry the whole weight */
  }
  assert_true(err[2] < 1e-3);
  assert_true(err[1] < err[0] / 3.0 && err[2] < err[1] / 3.0); /* second order in 1/N */
  /* every segment on the low-rank path: the same equilibrium */
  double sag_lr = discrete_sag(20, S, L0, EA, W, 0, &rz);
  double sag_d = discrete_sag(20, S, L0, EA, W, SW_TENDON_DENSE_MAX, &rz);
  assert_true(fabs(sag_lr - sag_d) < 1e-9 * sag_d);
}

/* 2D: a membrane held along its bottom edge and pulled down by a contracted cable through its
 * middle column settles (damped backward Euler) where the static solve puts it. */
static void membrane_2d_static(void **st) {
  (void)st;
  const int n = 7;
  sw_model *m = th_grid_start(2, n, n, 1.0, 1.0, 0.1, 500.0, 50.0, NULL, 0);
  assert_non_null(m);
  for (int i = 0; i < n; i++) m->pinned[i] = 1; /* the bottom row, y = 0 */
  int way[7];
  for (int j = 0; j < n; j++) way[j] = j * n + n / 2;
  th_add_tendon(m, way, n, SW_LAW_CABLE, 2000.0, 0.85, 0.0); /* 85 % of its 1 m */
  m->damp_mass = 30.0;                                         /* 1/s: settles in a few s */
  m = th_finish(m);
  assert_non_null(m);
  char err[SW_ERRSZ];
  double reaction[3];
  sw_data *ds = sw_data_new(m), *dd = sw_data_new(m);
  if (sw_static_solve(m, ds, reaction, err, sizeof err)) print_error("static: %s\n", err);
  void *s = NULL;
  assert_int_equal(sw_backward_euler_ops.init(&s, m, dd, err, sizeof err), 0);
  for (int k = 0; k < 400; k++) assert_int_equal(sw_backward_euler_ops.step(s, m, dd, 0.025), 0);
  sw_backward_euler_ops.free(s);
  double diff = 0.0, moved = 0.0; /* m */
  for (int i = 0; i < m->nv * 2; i++) {
    diff = fmax(diff, fabs(dd->x[i] - ds->x[i]));
    moved = fmax(moved, fabs(ds->x[i] - m->x0[i]));
  }
  sw_tendon_state(m, ds);
  print_message("2D membrane: static moved %.4g m, cable tension %.4g N, dynamic - static %.3g m\n",
                moved, ds->tendon_tension[0], diff);
  assert_true(moved > 0.02);                 /* the cable did pull the membrane */
  assert_true(ds->tendon_tension[0] > 0.0);
  assert_true(diff < 1e-6);
  assert_float_equal(reaction[1], 0.0, 1e-6 * ds->tendon_tension[0]); /* no external load */
  sw_data_free(ds), sw_data_free(dd);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(conformance_spring),
      cmocka_unit_test(conformance_cable),
      cmocka_unit_test(slack_cable),
      cmocka_unit_test(straight_two),
      cmocka_unit_test(forces_sum_to_zero),
      cmocka_unit_test(keyframes),
      cmocka_unit_test(coincident_waypoints),
      cmocka_unit_test(short_segment),
      cmocka_unit_test(lowrank_newton),
      cmocka_unit_test(lowrank_sundials_systems),
      cmocka_unit_test(lowrank_sundials_runs),
      cmocka_unit_test(hanging_cable),
      cmocka_unit_test(membrane_2d_static),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
