/* conformance.c — the conformance harness every energy term passes (STYLE.md: one harness,
 * a small driver per term): gradient and Hessian against central finite differences at random
 * deformed and near-degenerate states, symmetry, invariance under rigid motion (zero net force
 * and torque, unchanged energy) for internal terms, and a positive semi-definite projection. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "solver.h"
#include "terms.h"
#include "scene_fabric.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

typedef struct probe {
  const sw_model *m;
  sw_data *d;
  int k;      /* term under test */
  double *x;  /* (n) state */
  int n;
  int rest_free; /* the term exerts no force at x0 (moved rigidly) */
  double *lr; /* the term's low-rank vectors (sw_term.lptr) of the last Hessian */
} probe;

static double term_energy(probe *p, const double *x, double *grad, double *hess, int project) {
  const sw_term *t = &p->m->term[p->k];
  sw_eval ev = {.t = 0.0, .x = x, .grad = grad, .hess = hess, .lowrank = hess ? p->lr : NULL,
                .project = project};
  double e = 0.0;
  if (grad) memset(grad, 0, sizeof(double) * (size_t)p->n);
  if (hess) memset(hess, 0, sizeof(double) * (size_t)t->hptr[t->nstencil]);
  if (hess && t->nlowrank)
    memset(p->lr, 0, sizeof(double) * (size_t)t->lptr[t->nlowrank] * (size_t)p->m->dim);
  assert_int_equal(t->ops->eval(t, p->m, &ev, &e), SW_OK);
  return e;
}

static double max_abs(const double *v, long n) {
  double s = 0.0;
  for (long i = 0; i < n; i++) s = fmax(s, fabs(v[i]));
  return s;
}

/* grad vs central differences of E; step h relative to the state's size. */
static void check_gradient(probe *p, double h) {
  int n = p->n;
  size_t nz = (unsigned)n;
  double *g = calloc(nz, sizeof *g), *fd = calloc(nz, sizeof *fd);
  double *xp = malloc(sizeof(double) * nz);
  term_energy(p, p->x, g, NULL, 0);
  for (int i = 0; i < n; i++) {
    memcpy(xp, p->x, sizeof(double) * (size_t)n);
    xp[i] += h;
    double ep = term_energy(p, xp, NULL, NULL, 0);
    xp[i] -= 2 * h;
    double em = term_energy(p, xp, NULL, NULL, 0);
    fd[i] = (ep - em) / (2 * h) - g[i];
  }
  double scale = fmax(max_abs(g, n), 1e-12);
  if (max_abs(fd, n) / scale >= 1e-6) print_error("gradient rel err %g\n", max_abs(fd, n) / scale);
  assert_true(max_abs(fd, n) / scale < 1e-6);
  free(g), free(fd), free(xp);
}

/* Hessian vs central differences of the gradient, and symmetry. */
static void check_hessian(probe *p, double h) {
  const sw_term *t = &p->m->term[p->k];
  int n = p->n;
  double *blk = calloc((size_t)t->hptr[t->nstencil] + 1, sizeof *blk);
  double *H = calloc((size_t)n * n, sizeof *H), *gp = calloc((size_t)n, sizeof *gp);
  double *gm = calloc((size_t)n, sizeof *gm), *xp = malloc(sizeof(double) * (size_t)n);
  term_energy(p, p->x, NULL, blk, 0);
  th_dense_hessian(p->m, p->k, blk, H);
  th_dense_lowrank(p->m, p->k, p->lr, H);
  double scale = fmax(max_abs(H, (long)n * n), 1e-12), err = 0.0, asym = 0.0;
  for (int j = 0; j < n; j++) {
    memcpy(xp, p->x, sizeof(double) * (size_t)n);
    xp[j] += h;
    term_energy(p, xp, gp, NULL, 0);
    xp[j] -= 2 * h;
    term_energy(p, xp, gm, NULL, 0);
    for (int i = 0; i < n; i++) {
      err = fmax(err, fabs((gp[i] - gm[i]) / (2 * h) - H[(long)i * n + j]));
      asym = fmax(asym, fabs(H[(long)i * n + j] - H[(long)j * n + i]));
    }
  }
  if (err / scale >= 1e-6) print_error("Hessian rel err %g\n", err / scale);
  assert_true(err / scale < 1e-6);
  assert_true(asym / scale < 1e-12);
  free(blk), free(H), free(gp), free(gm), free(xp);
}

/* The projected Hessian: symmetric positive semi-definite (LAPACK eigenvalues). */
static void check_projection(probe *p) {
  const sw_term *t = &p->m->term[p->k];
  int n = p->n, lwork = 8 * n, info = 0;
  double *blk = calloc((size_t)t->hptr[t->nstencil] + 1, sizeof *blk);
  double *H = calloc((size_t)n * n, sizeof *H), *w = calloc((size_t)n, sizeof *w);
  double *work = calloc((size_t)lwork, sizeof *work);
  term_energy(p, p->x, NULL, blk, 1);
  th_dense_hessian(p->m, p->k, blk, H);
  th_dense_lowrank(p->m, p->k, p->lr, H);
  double scale = fmax(max_abs(H, (long)n * n), 1e-12);
  dsyev_("N", "L", &n, H, &n, w, work, &lwork, &info);
  assert_int_equal(info, 0);
  if (w[0] < -1e-10 * scale) print_error("projected min eigenvalue %g (scale %g)\n", w[0], scale);
  assert_true(w[0] >= -1e-10 * scale);
  free(blk), free(H), free(w), free(work);
}

/* A term that takes a sink (sink_ok) hands it every block as it writes them in place: added
 * into the model's system through its slots (sw_slots_add, from zero), its blocks through a
 * sink give the values its stored blocks give, exactly, and the same energy and gradient.  The
 * sink's scratch block starts as NaN: an entry a term leaves unset, or adds into unzeroed,
 * shows. */
static void check_sink(probe *p, int project) {
  const sw_term *t = &p->m->term[p->k];
  if (!t->ops->sink_ok) return;
  sw_pattern pat;
  char err[SW_ERRSZ];
  assert_int_equal(sw_pattern_build(&pat, p->m, err, sizeof err), 0);
  const long len = t->hptr[t->nstencil];
  long wmax = 1;
  for (int s = 0; s < t->nstencil; s++) wmax = fmax(wmax, t->hptr[s + 1] - t->hptr[s]);
  double *blk = calloc((size_t)len + 1, sizeof *blk);
  double *want = calloc((size_t)pat.nnz + 1, sizeof *want);
  double *got = calloc((size_t)pat.nnz + 1, sizeof *got), *g = calloc((size_t)p->n, sizeof *g);
  double *scratch = malloc(sizeof *scratch * (size_t)wmax), *g2 = calloc((size_t)p->n, sizeof *g2);
  for (long q = 0; q < wmax; q++) scratch[q] = NAN;
  double e = term_energy(p, p->x, g, blk, project);
  for (int s = 0; s < t->nstencil; s++)
    sw_slots_add(&pat.slots, t->sidx + t->sptr[s], t->sptr[s + 1] - t->sptr[s], blk + t->hptr[s],
                 want);
  sw_hsink sink = {.values = got, .slots = &pat.slots, .blk = scratch};
  sw_eval ev = {.x = p->x, .grad = g2, .hess = scratch, .sink = &sink, .lowrank = p->lr,
                .project = project};
  double e2 = 0.0;
  assert_int_equal(t->ops->eval(t, p->m, &ev, &e2), SW_OK);
  long differ = 0;
  for (long q = 0; q < pat.nnz; q++) differ += !(got[q] == want[q]);
  if (differ)
    print_error("%s: %ld of %ld entries differ through a sink\n", t->name, differ, pat.nnz);
  assert_int_equal(differ, 0);
  assert_true(e2 == e);
  assert_memory_equal(g, g2, sizeof *g * (size_t)p->n);
  free(blk), free(want), free(got), free(scratch), free(g), free(g2);
  sw_pattern_free(&pat);
}

/* Rotation about a random axis (3D) or in the plane (2D) and a translation. */
static void rigid(const probe *p, const double *x, double *y, unsigned long *rs) {
  const int d = p->m->dim;
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tr[3] = {th_rand(rs), th_rand(rs), th_rand(rs)};
  double th = 3.0 * th_rand(rs), c = cos(th), s = sin(th);
  if (d == 2) {
    double R2[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    memcpy(R, R2, sizeof R);
  } else {
    double a[3] = {th_rand(rs), th_rand(rs), th_rand(rs) + 1.5};
    double l = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int i = 0; i < 3; i++) a[i] /= l;
    double K[9] = {0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0};
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double kk = 0.0;
        for (int q = 0; q < 3; q++) kk += K[i * 3 + q] * K[q * 3 + j];
        R[i * 3 + j] = (i == j) + s * K[i * 3 + j] + (1 - c) * kk;
      }
  }
  for (int v = 0; v < p->n / d; v++)
    for (int i = 0; i < d; i++) {
      y[v * d + i] = tr[i];
      for (int j = 0; j < d; j++) y[v * d + i] += R[i * 3 + j] * x[v * d + j];
    }
}

/* Internal forces: zero net force and torque, energy unchanged by a rigid motion, and zero
 * force at the rest state moved rigidly. */
static void check_rigid(probe *p, unsigned long *rs) {
  const int d = p->m->dim, n = p->n;
  double *g = calloc((size_t)n, sizeof *g), *y = calloc((size_t)n, sizeof *y);
  double e = term_energy(p, p->x, g, NULL, 0);
  double net[3] = {0}, tq[3] = {0}, scale = fmax(max_abs(g, n), 1e-12);
  for (int v = 0; v < n / d; v++) {
    double xv[3] = {0}, gv[3] = {0};
    for (int a = 0; a < d; a++) {
      xv[a] = p->x[v * d + a];
      gv[a] = g[v * d + a];
      net[a] += gv[a];
    }
    tq[0] += xv[1] * gv[2] - xv[2] * gv[1];
    tq[1] += xv[2] * gv[0] - xv[0] * gv[2];
    tq[2] += xv[0] * gv[1] - xv[1] * gv[0];
  }
  for (int a = 0; a < 3; a++) {
    assert_true(fabs(net[a]) < 1e-9 * scale * n);
    assert_true(fabs(tq[a]) < 1e-9 * scale * n);
  }
  rigid(p, p->x, y, rs);
  double e2 = term_energy(p, y, NULL, NULL, 0);
  assert_true(fabs(e2 - e) <= 1e-9 * fmax(fabs(e), 1e-12));
  if (p->rest_free) {
    rigid(p, p->m->x0, y, rs);
    term_energy(p, y, g, NULL, 0);
    if (max_abs(g, n) >= 1e-9 * scale) print_error("force at rest %g\n", max_abs(g, n));
    assert_true(max_abs(g, n) < 1e-9 * scale);
  }
  free(g), free(y);
}



/* A deformed state: x0 * scale + amp * random (scale 0.3: strongly compressed). */
static void deform(probe *p, double amp, double scale, unsigned long *rs) {
  for (int i = 0; i < p->n; i++) p->x[i] = p->m->x0[i] * scale + amp * th_rand(rs);
}

static probe make_probe(const sw_model *m, const char *name, int flags) {
  probe p = {.m = m, .n = m->nv * m->dim, .k = -1, .rest_free = !!(flags & TH_REST_FREE)};
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].name, name)) p.k = k;
  if (p.k < 0) print_error("no term named %s\n", name);
  assert_true(p.k >= 0);
  const sw_term *t = &m->term[p.k];
  p.x = calloc((size_t)p.n, sizeof(double));
  p.lr = calloc((size_t)(t->nlowrank ? t->lptr[t->nlowrank] : 0) * (size_t)m->dim + 1,
                sizeof(double));
  return p;
}

void th_conformance_at(const sw_model *m, const char *name, int flags, double size,
                       const double *x) {
  probe p = make_probe(m, name, flags);
  memcpy(p.x, x, sizeof(double) * (size_t)p.n);
  check_gradient(&p, 1e-6 * size);
  check_hessian(&p, 1e-6 * size);
  if (!(flags & TH_NO_PROJECTION)) check_projection(&p);
  for (int f = SW_FILTER_NONE; f <= SW_FILTER_ABS; f++) check_sink(&p, f);
  free(p.x);
  free(p.lr);
}

void th_conformance(const sw_model *m, const char *name, int flags, double size,
                    unsigned long seed) {
  probe p = make_probe(m, name, flags);
  unsigned long rs = seed;
  /* amplitude of the random displacement (relative to size) and scale of x0 */
  const double states[][2] = {{0.1, 1.0}, {0.17, 1.3}, {0.07, 0.3}, {0.007, 0.05}};
  for (size_t s = 0; s < sizeof states / sizeof states[0]; s++)
    for (int rep = 0; rep < 3; rep++) {
      deform(&p, states[s][0] * size, states[s][1], &rs);
      check_gradient(&p, 1e-6 * size);
      check_hessian(&p, 1e-6 * size);
      if (!(flags & TH_NO_PROJECTION)) check_projection(&p);
      if (flags & TH_INTERNAL) check_rigid(&p, &rs);
      check_sink(&p, rep % 3); /* each filter (SW_FILTER_*) at each kind of state */
    }
  free(p.x);
  free(p.lr);
}

void th_near(double got, double want, double tol) {
  if (!(fabs(got - want) <= tol)) fail_msg("got %.15g, expected %.15g (tol %g)", got, want, tol);
}

sw_dde th_dde_preset(const char *name) {
  char err[SW_ERRSZ];
  const sc_fabric_preset *p = sc_fabric_preset_find(name);
  if (!p) fail_msg("no preset %s", name);
  sw_dde dd;
  if (sc_dde_parse(p->file, p->json, strlen(p->json), &dd, err, sizeof err)) fail_msg("%s", err);
  return dd;
}
