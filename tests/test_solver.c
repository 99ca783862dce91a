/* test_solver.c — the shared linear-algebra path: the fixed pattern and its fill equal the
 * dense a M + H on the free DOFs (every term's blocks, stored as upper triangles), CHOLMOD solves it, and Newton's minimiser of the incremental
 * potential has zero gradient; the pattern stored in the elimination order holds the same
 * matrix, which CHOLMOD factorises without a permuted copy. */
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
#include "terms.h"

static sw_model *small_model(int dim) {
  const double g[3] = {0.0, -9.81, -9.81};
  return th_grid_model(dim, 5, 4, 0.4, 0.3, 0.1, 300.0, 20.0, g, 1);
}

/* Fill S = a M + H on the pattern; compare to the dense matrix on the free DOFs. */
static void fill_matches_dense(int dim) {
  sw_model *m = small_model(dim);
  sw_data *d = sw_data_new(m);
  unsigned long rs = 7;
  for (int i = 0; i < m->nv * dim; i++) d->x[i] += 0.02 * th_rand(&rs);
  sw_pattern p;
  char err[SW_ERRSZ];
  assert_int_equal(sw_pattern_build(&p, m, err, sizeof err), 0);
  double e, a = 1e4;
  assert_int_equal(sw_eval_terms(m, d, d->x, 0.0, 0, 1, 1, &e), 0);
  double *val = calloc((size_t)p.nnz, sizeof *val);
  sw_pattern_fill(&p, m, d, a, 1.0, val);
  int n = m->nv * dim, k = 0;
  double *H = calloc((size_t)n * n, sizeof *H);
  for (; k < m->nterm && strcmp(m->term[k].name, "bw98"); k++) {}
  th_dense_hessian(m, k, d->hess + d->hoff[k], H);
  long counted = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j <= i; j++) {
      int r = m->dof[i], c = m->dof[j];
      if (r < 0 || c < 0) continue;
      double want = H[(long)i * n + j] + (i == j ? a * m->mass[i / dim] : 0.0), got = 0.0;
      int rr = r < c ? r : c, cc = r < c ? c : r; /* upper triangle: row <= column */
      for (long q = p.colptr[cc]; q < p.colptr[cc + 1]; q++)
        if (p.rowind[q] == rr) got = val[q];
      assert_float_equal(got, want, 1e-9 * (fabs(want) + 1.0));
      counted += want != 0.0;
    }
  assert_true(counted <= p.nnz);
  /* CHOLMOD: solve S y = b and check the residual with the dense matrix. */
  sw_chol ch;
  assert_int_equal(sw_chol_init(&ch, &p, SW_FACTOR_AUTO, err, sizeof err), 0);
  /* the pattern is now stored in the factorisation's order: filled again through its maps */
  sw_pattern_fill(&p, m, d, a, 1.0, sw_chol_values(&ch));
  assert_int_equal(sw_chol_factor(&ch, err, sizeof err), 0);
  double *b = calloc((size_t)p.n, sizeof *b), *y = calloc((size_t)p.n, sizeof *y);
  for (int c = 0; c < p.n; c++) b[c] = th_rand(&rs);
  assert_int_equal(sw_chol_solve(&ch, b, y, err, sizeof err), 0);
  double res = 0.0;
  for (int i = 0; i < n; i++) {
    if (m->dof[i] < 0) continue;
    double s = -b[m->dof[i]];
    for (int j = 0; j < n; j++)
      if (m->dof[j] >= 0)
        s += (H[(long)i * n + j] + (i == j ? a * m->mass[i / dim] : 0.0)) * y[m->dof[j]];
    res = fmax(res, fabs(s));
  }
  assert_true(res < 1e-9);
  sw_chol_free(&ch);
  free(b), free(y), free(val), free(H);
  sw_pattern_free(&p);
  sw_data_free(d);
  sw_model_free(m);
}

static void fill_3d(void **st) { (void)st, fill_matches_dense(3); }
static void fill_2d(void **st) { (void)st, fill_matches_dense(2); }

/* A term whose stencils name one vertex twice, (0, 0, 1) and (1, 2, 1): the entries off a
 * block's diagonal that land on the matrix's diagonal.  Hessian: the constant symmetric block
 * B(i, j) = 1 + i + j (+ 10 on the diagonal), energy 0 (the fill test reads only blocks). */
static int repeat_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  *energy = 0.0;
  const int w = 3 * m->dim;
  for (int s = 0; ev->hess && s < t->nstencil; s++)
    for (int i = 0; i < w; i++)
      for (int j = i; j < w; j++)
        ev->hess[t->hptr[s] + sw_hess_upper(i, j, w)] += 1.0 + i + j + (i == j ? 10.0 : 0.0);
  return SW_OK;
}
static const sw_term_ops repeat_ops = {.kind = "repeat", .eval = repeat_eval};

static void add_repeat_term(sw_model *m) {
  sw_term *t = realloc(m->term, (size_t)(m->nterm + 1) * sizeof *t);
  assert_non_null(t);
  m->term = t;
  sw_term *nt = &t[m->nterm++];
  memset(nt, 0, sizeof *nt);
  nt->ops = &repeat_ops;
  snprintf(nt->name, sizeof nt->name, "repeat");
  assert_int_equal(sw_term_alloc_stencils(nt, 2, 3, m->dim), 0);
  const int v[6] = {0, 0, 1, 1, 2, 1};
  memcpy(nt->sidx, v, sizeof v);
}

/* A term with sets_blocks writes every stored entry of its blocks: evaluated into a buffer of
 * NaN, it leaves what it leaves in a zeroed one. */
static void check_sets_blocks(const sw_model *m, const sw_data *d, const char *label) {
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    if (!t->ops->sets_blocks) continue;
    long len = t->hptr[t->nstencil];
    double *h = malloc(sizeof(double) * (size_t)(len + 1)), e;
    double *lr = calloc((size_t)(t->nlowrank ? t->lptr[t->nlowrank] * m->dim : 0) + 1, sizeof *lr);
    assert_non_null(h), assert_non_null(lr);
    for (long q = 0; q < len; q++) h[q] = NAN;
    sw_eval ev = {.x = d->x, .hess = h, .lowrank = lr, .project = SW_FILTER_CLAMP};
    assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
    long same = 0;
    for (long q = 0; q < len; q++) same += h[q] == d->hess[d->hoff[k] + q];
    if (same != len) fail_msg("%s: term %s left %ld of %ld entries unset", label, t->name, len - same, len);
    free(h), free(lr);
  }
}

/* The blocks added straight into the system (sw_eval_terms_into, as Newton assembles) give
 * the values of the kept blocks filled in (sw_eval_terms, sw_pattern_fill) bit for bit, and the
 * same energy, with each filter. */
static void check_into(const sw_model *m, sw_data *d, const sw_pattern *p, double a,
                       const char *label) {
  double *want = calloc((size_t)p->nnz + 1, sizeof *want);
  double *got = calloc((size_t)p->nnz + 1, sizeof *got);
  assert_non_null(want), assert_non_null(got);
  for (int f = SW_FILTER_NONE; f <= SW_FILTER_ABS; f++) {
    double e, e2;
    assert_int_equal(sw_eval_terms(m, d, d->x, 0.0, 0, 1, f, &e), SW_OK);
    sw_pattern_fill(p, m, d, a, 1.0, want);
    memset(got, 0, sizeof(double) * (size_t)p->nnz); /* sw_eval_terms_into adds */
    assert_int_equal(sw_eval_terms_into(m, d, d->x, 0.0, 0, f, got, &p->slots, &e2), SW_OK);
    sw_pattern_finish(p, m, a, 1.0, got);
    long differ = 0, nonzero = 0;
    for (long q = 0; q < p->nnz; q++) {
      differ += memcmp(&got[q], &want[q], sizeof *got) != 0;
      nonzero += want[q] != 0.0;
    }
    if (differ || e2 != e)
      fail_msg("%s, filter %d: %ld of %ld entries differ, energy %.17g vs %.17g", label, f,
               differ, p->nnz, e2, e);
    assert_true(nonzero > 0);
  }
  free(want), free(got);
}

/* The assembled S = a M + sum of the terms' blocks, as a product S v on the pattern
 * (sw_pattern_symv of sw_pattern_fill), against the blocks multiplied out one by one, each
 * read in full (both halves of its stored upper triangle): every term of the model, every
 * entry of every block. */
static void check_fill_products(sw_model *m, const char *label) {
  sw_data *d = sw_data_new(m);
  assert_non_null(d);
  sw_pattern p;
  char err[SW_ERRSZ];
  assert_int_equal(sw_pattern_build(&p, m, err, sizeof err), 0);
  double e, a = 1e3; /* 1/s^2 */
  int rc = sw_eval_terms(m, d, d->x, 0.0, 0, 1, SW_FILTER_CLAMP, &e);
  if (rc) fail_msg("%s: evaluation failed (%d)", label, rc);
  const int dim = m->dim, n = m->nv * dim;
  double *val = calloc((size_t)p.nnz + 1, sizeof *val), *v = calloc((size_t)p.n + 1, sizeof *v);
  double *y = calloc((size_t)p.n + 1, sizeof *y), *want = calloc((size_t)p.n + 1, sizeof *want);
  assert_non_null(val), assert_non_null(v), assert_non_null(y), assert_non_null(want);
  sw_pattern_fill(&p, m, d, a, 1.0, val);
  unsigned long rs = 5;
  for (int c = 0; c < p.n; c++) v[c] = th_rand(&rs);
  sw_pattern_symv(&p, val, v, y);
  for (int i = 0; i < n; i++)
    if (m->dof[i] >= 0) want[m->dof[i]] += a * m->mass[i / dim] * v[m->dof[i]];
  long entries = 0;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    for (int s = 0; s < t->nstencil; s++) {
      const int *idx = t->sidx + t->sptr[s], w = (t->sptr[s + 1] - t->sptr[s]) * dim;
      const double *b = d->hess + d->hoff[k] + t->hptr[s];
      for (int i = 0; i < w; i++)
        for (int j = 0; j < w; j++) {
          int r = m->dof[idx[i / dim] * dim + i % dim], c = m->dof[idx[j / dim] * dim + j % dim];
          if (r < 0 || c < 0) continue;
          want[r] += sw_hess_get(b, i, j, w) * v[c];
          entries++;
        }
    }
  }
  double err_max = 0.0, scale = 0.0;
  for (int c = 0; c < p.n; c++) {
    err_max = fmax(err_max, fabs(y[c] - want[c]));
    scale = fmax(scale, fabs(want[c]));
  }
  print_message("%s: %d terms, %ld block entries, %ld pattern entries, |S v - sum B v| %.2e "
                "of %.2e\n", label, m->nterm, entries, p.nnz, err_max, scale);
  assert_true(err_max <= 1e-12 * scale);
  check_sets_blocks(m, d, label);
  check_into(m, d, &p, a, label);
  free(val), free(v), free(y), free(want);
  sw_pattern_free(&p);
  sw_data_free(d);
}

/* Every term of the shipped scenes (membranes, bending, seams, tendons, contact; 2D and 3D). */
static void fill_every_term(void **st) {
  (void)st;
  const char *scenes[] = {"scenes/hanging_cloth.yaml", "scenes/cloth_drawstring.yaml",
                          "scenes/garment_skirt.yaml", "scenes/drape_sphere.yaml",
                          "scenes/tendon_membrane_2d.yaml", "scenes/peirce_cantilever.yaml"};
  for (size_t q = 0; q < sizeof scenes / sizeof *scenes; q++) {
    char err[SW_ERRSZ];
    sw_model *m = sw_scene_load(scenes[q], err, sizeof err);
    if (!m) fail_msg("%s", err);
    check_fill_products(m, scenes[q]);
    sw_model_free(m);
  }
}

/* A vertex twice in one stencil: its off-diagonal entries on the matrix's diagonal count. */
static void fill_repeated_vertex(void **st) {
  (void)st;
  for (int dim = 2; dim <= 3; dim++) {
    sw_model *m = small_model(dim);
    add_repeat_term(m);
    check_fill_products(m, dim == 2 ? "repeated vertex, 2D" : "repeated vertex, 3D");
    sw_model_free(m);
  }
}

static void *no_memory(size_t n) { (void)n; return NULL; }
static void *no_memory2(size_t n, size_t k) { (void)n, (void)k; return NULL; }
static void *no_memory_re(void *p, size_t n) { (void)p, (void)n; return NULL; }

/* Factor the diagonal system of small_model(3) with diagonal entry `neg` in column 3 (1 else);
 * with oom, every SuiteSparse allocation fails during the factorisation.  Its return code, the
 * message in err and the system's size in *n. */
static int factor_diagonal(double neg, int oom, char *err, size_t errsz, int *n) {
  sw_model *m = small_model(3);
  sw_pattern p;
  sw_chol ch;
  assert_int_equal(sw_pattern_build(&p, m, err, errsz), 0);
  assert_int_equal(sw_chol_init(&ch, &p, SW_FACTOR_AUTO, err, errsz), 0);
  double *v = sw_chol_values(&ch);
  memset(v, 0, sizeof(double) * (size_t)p.nnz);
  for (int c = 0; c < p.n; c++) v[p.diag[c]] = c == 3 ? neg : 1.0;
  struct SuiteSparse_config_struct saved = SuiteSparse_config;
  if (oom) {
    SuiteSparse_config.malloc_func = no_memory;
    SuiteSparse_config.calloc_func = no_memory2;
    SuiteSparse_config.realloc_func = no_memory_re;
  }
  int rc = sw_chol_factor(&ch, err, errsz);
  SuiteSparse_config = saved;
  *n = p.n;
  sw_chol_free(&ch);
  sw_pattern_free(&p);
  sw_model_free(m);
  return rc;
}

/* A negative-definite system is reported as recoverable, not a crash. */
static void not_positive_definite(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  int n;
  assert_int_equal(factor_diagonal(-1.0, 0, err, sizeof err, &n), SW_RECOVER);
  assert_non_null(strstr(err, "not positive definite"));
}

/* CHOLMOD out of memory in the factorisation is reported as such, with the size of the system
 * and the factor's nonzeros, and is fatal. */
static void cholmod_out_of_memory(void **st) {
  (void)st;
  char err[SW_ERRSZ], want[96];
  int n;
  assert_int_equal(factor_diagonal(1.0, 1, err, sizeof err, &n), SW_FATAL);
  snprintf(want, sizeof want, "CHOLMOD ran out of memory in factorize (a %d x %d system; ", n, n);
  if (!strstr(err, want) || !strstr(err, "nonzeros in its factor")) fail_msg("message: %s", err);
  print_message("%s\n", err);
}

/* Newton's answer for one backward Euler step, with each Hessian mode: grad Phi = 0, the same
 * minimiser, and few iterations with the exact Hessian (quadratic convergence). */
static void newton_minimises(void **st) {
  (void)st;
  sw_model *m = small_model(3);
  sw_data *d = sw_data_new(m);
  sw_newton nw;
  char err[SW_ERRSZ];
  assert_int_equal(sw_newton_init(&nw, m, err, sizeof err), 0);
  int nd = m->nv * 3;
  double h = 0.02, *xhat = calloc((size_t)nd, sizeof *xhat), *x = calloc((size_t)nd, sizeof *x);
  double *xref = calloc((size_t)nd, sizeof *xref), wmax = 0.0;
  unsigned long rs = 3;
  for (int i = 0; i < nd; i++) xhat[i] = d->x[i] + (m->dof[i] >= 0 ? 0.05 * th_rand(&rs) : 0.0);
  for (int i = 0; i < m->nv; i++) wmax = fmax(wmax, m->mass[i] * 9.81);
  const int modes[2] = {SW_HESSIAN_AUTO, SW_HESSIAN_PROJECTED};
  const int max_iters[2] = {20, 50};
  for (int k = 0; k < 2; k++) {
    memcpy(x, xhat, sizeof(double) * (size_t)nd);
    sw_newton_opts o = {.a = 1 / (h * h), .max_iter = 60, .tol_dx = 1e-12, .line_search = 1,
                        .must_converge = 1, .hessian = modes[k]};
    assert_int_equal(sw_newton_solve(&nw, m, d, x, xhat, &o), 0);
    double phi, gmax = 0.0;
    assert_int_equal(sw_newton_phi(&nw, m, d, x, xhat, o.a, 0.0, 1, 0, 0, &phi), 0);
    for (int c = 0; c < nw.n; c++) gmax = fmax(gmax, fabs(nw.g[c]));
    print_message("hessian mode %d: %d Newton iterations, max |g| %g N\n", modes[k],
                  d->last_newton, gmax);
    assert_true(gmax < 1e-8 * wmax);
    assert_true(d->last_newton <= max_iters[k]);
    if (k == 0) memcpy(xref, x, sizeof(double) * (size_t)nd);
    for (int i = 0; i < nd; i++) assert_float_equal(x[i], xref[i], 1e-9);
  }
  /* The exact Hessian alone: S is indefinite here (compressed cloth), which is reported as
   * recoverable with the reason, never a wrong answer. */
  memcpy(x, xhat, sizeof(double) * (size_t)nd);
  sw_newton_opts o = {.a = 1 / (h * h), .max_iter = 60, .tol_dx = 1e-12, .line_search = 1,
                      .must_converge = 1, .hessian = SW_HESSIAN_EXACT};
  int rc = sw_newton_solve(&nw, m, d, x, xhat, &o);
  assert_true(rc == SW_OK || (rc == SW_RECOVER && strstr(d->err, "not positive definite")));
  sw_newton_free(&nw);
  free(xhat), free(x), free(xref);
  sw_data_free(d);
  sw_model_free(m);
}

/* One Newton iteration (no line search) of every Hessian mode from a compressed, crumpled
 * state: its step dx is a descent direction of Phi, grad Phi . dx < 0 (the exact Hessian may
 * instead be refused as not positive definite, never give an ascent step). */
static void every_mode_descends(void **st) {
  (void)st;
  const int modes[5] = {SW_HESSIAN_PROJECTED, SW_HESSIAN_ABS, SW_HESSIAN_PROGRESSIVE,
                        SW_HESSIAN_AUTO, SW_HESSIAN_EXACT};
  for (int k = 0; k < 5; k++) {
    sw_model *m = small_model(3);
    m->opt.hessian = modes[k];
    sw_data *d = sw_data_new(m);
    sw_newton nw;
    char err[SW_ERRSZ];
    assert_int_equal(sw_newton_init(&nw, m, err, sizeof err), 0);
    int nd = m->nv * 3, descents = 0;
    double *x = calloc((size_t)nd, sizeof *x), *x1 = calloc((size_t)nd, sizeof *x1);
    double *g = calloc((size_t)nw.n, sizeof *g);
    unsigned long rs = 11;
    for (int trial = 0; trial < 8; trial++) {
      for (int i = 0; i < nd; i++) /* compressed to 60 %, crumpled out of plane by 1 cm */
        x[i] = m->dof[i] < 0 ? m->x0[i] : 0.6 * m->x0[i] + 0.01 * th_rand(&rs);
      memcpy(x1, x, sizeof(double) * (size_t)nd);
      double phi, h = 0.01;
      assert_int_equal(sw_newton_phi(&nw, m, d, x, x, 1 / (h * h), 0.0, 1, 0, 0, &phi), 0);
      memcpy(g, nw.g, sizeof(double) * (size_t)nw.n);
      sw_newton_opts o = {.a = 1 / (h * h), .max_iter = 1, .tol_dx = 0.0, .line_search = 0,
                          .must_converge = 0, .hessian = modes[k]};
      int rc = sw_newton_solve(&nw, m, d, x1, x, &o);
      if (modes[k] == SW_HESSIAN_EXACT && rc == SW_RECOVER) {
        assert_non_null(strstr(d->err, "not positive definite"));
        continue;
      }
      assert_int_equal(rc, 0);
      double slope = 0.0;
      for (int i = 0; i < nd; i++)
        if (m->dof[i] >= 0) slope += g[m->dof[i]] * (x1[i] - x[i]);
      assert_true(slope < 0.0);
      descents++;
    }
    print_message("hessian %s: %d of 8 steps are descent directions\n",
                  sw_hessian_names()[modes[k]], descents);
    if (modes[k] != SW_HESSIAN_EXACT) assert_int_equal(descents, 8);
    sw_newton_free(&nw);
    free(x), free(x1), free(g);
    sw_data_free(d);
    sw_model_free(m);
  }
}

/* The ordering rule (auto): AMD for a 40 x 40 cloth (fewer than SW_ORDERING_SWITCH
 * unknowns), NESDIS for a 160 x 160 one, where it needs fewer flops; each forced ordering is the one the factor records; every ordering solves the same
 * system to the same answer (docs/performance.md, "Factorisation: ordering, kind and
 * threads"). */
static void ordering_rule(void **st) {
  (void)st;
  const double g[3] = {0.0, 0.0, -9.81};
  const int sizes[2] = {40, 160}, want[2] = {SW_ORDERING_AMD, SW_ORDERING_NESDIS};
  char err[SW_ERRSZ];
  for (int j = 0; j < 2; j++) {
    sw_model *m = th_grid_model(3, sizes[j], sizes[j], 1.0, 1.0, 0.1, 5000.0, 100.0, g, 1);
    assert_non_null(m);
    sw_pattern p;
    assert_int_equal(sw_pattern_build(&p, m, err, sizeof err), 0);
    unsigned long rs = 11;
    double *b = calloc((size_t)p.n, sizeof *b), *y[SW_ORDERING_N];
    for (int c = 0; c < p.n; c++) b[c] = th_rand(&rs);
    double fl[SW_ORDERING_N] = {0}, lnz[SW_ORDERING_N] = {0};
    for (int o = 0; o < SW_ORDERING_N; o++) {
      sw_chol ch;
      assert_int_equal(sw_chol_init(&ch, &p, SW_CHOL_MODE(SW_FACTOR_AUTO, o), err, sizeof err),
                       0);
      fl[o] = ch.c.fl, lnz[o] = ch.c.lnz;
      assert_int_equal(sw_chol_ordering(&ch), o ? o : want[j]);
      assert_true(sw_chol_nnz(&ch) > 0); /* analysed */
      th_fill_dominant(&p, sw_chol_values(&ch));
      assert_int_equal(sw_chol_factor(&ch, err, sizeof err), 0);
      y[o] = calloc((size_t)p.n, sizeof *y[o]);
      assert_int_equal(sw_chol_solve(&ch, b, y[o], err, sizeof err), 0);
      sw_chol_free(&ch);
      if (o) assert_true(th_max_diff(y[0], y[o], p.n) < 1e-12);
    }
    print_message("%d x %d: %d DOFs, AMD %.0f flops per nonzero; auto %s\n", sizes[j],
                  sizes[j], p.n, fl[SW_ORDERING_AMD] / lnz[SW_ORDERING_AMD],
                  sw_ordering_names()[want[j]]);
    /* auto is AMD below the switch; above it, NESDIS with fewer flops than AMD */
    assert_true(j ? p.n >= SW_ORDERING_SWITCH : p.n < SW_ORDERING_SWITCH);
    assert_true(fl[0] == fl[want[j]] && lnz[0] == lnz[want[j]]);
    assert_true(!j || fl[SW_ORDERING_NESDIS] < fl[SW_ORDERING_AMD]);
    for (int o = 0; o < SW_ORDERING_N; o++) free(y[o]);
    free(b);
    sw_pattern_free(&p);
    sw_model_free(m);
  }
}

/* The peak of CHOLMOD's allocations during one factorisation beyond what it keeps (bytes):
 * the transient copies and workspaces. */
static double factor_transient(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c) {
  c->memory_usage = c->memory_inuse; /* the peak from here */
  assert_true(cholmod_factorize(A, L, c));
  assert_true(L->minor == L->n);
  return (double)c->memory_usage - (double)c->memory_inuse;
}

/* sw_chol_init stores the pattern in its factorisation's elimination order (lower for a
 * supernodal factor, upper for a simplicial one) and analyses it in that natural order: the
 * same matrix entry for entry (bitwise), the same product, the same solution as CHOLMOD's own
 * permuted path on the pattern as built, the same factor size, and 12 bytes a nonzero less
 * of transient memory during a factorisation (CHOLMOD's own path permutes a copy).  The
 * larger cloth has a tendon along its diagonal whose dense block gives columns of more than
 * 64 entries (sorted another way). */
static void elimination_order(void **st) {
  (void)st;
  const double g[3] = {0.0, 0.0, -9.81};
  const int sizes[2] = {10, 24};
  char err[SW_ERRSZ];
  for (int j = 0; j < 2; j++) {
    sw_model *m = th_grid_start(3, sizes[j], sizes[j], 1.0, 1.0, 0.1, 5000.0, 100.0, g, 1);
    int way[24];
    for (int k = 0; k < sizes[j]; k++) way[k] = k * sizes[j] + k;
    if (j) th_add_tendon(m, way, sizes[j], SW_LAW_SPRING, 200.0, 1.2, 0.0);
    assert_non_null(m = th_finish(m));
    sw_data *d = sw_data_new(m);
    unsigned long rs = 3;
    for (int i = 0; i < m->nv * 3; i++) d->x[i] += 0.01 * th_rand(&rs);
    double e, a = 1e4;
    assert_int_equal(sw_eval_terms(m, d, d->x, 0.0, 0, 1, SW_FILTER_CLAMP, &e), 0);
    sw_pattern p0, p1;
    assert_int_equal(sw_pattern_build(&p0, m, err, sizeof err), 0);
    assert_int_equal(sw_pattern_build(&p1, m, err, sizeof err), 0);
    double *v0 = calloc((size_t)p0.nnz, sizeof *v0);
    sw_pattern_fill(&p0, m, d, a, 1.0, v0);
    sw_chol ch;
    assert_int_equal(sw_chol_init(&ch, &p1, SW_FACTOR_AUTO, err, sizeof err), 0);
    const int super = sw_chol_super(&ch);
    assert_int_equal(super, j); /* both kinds */
    assert_int_equal(p1.lower, super);
    assert_int_equal(ch.L->ordering, CHOLMOD_NATURAL);
    assert_int_equal(sw_chol_ordering(&ch), SW_ORDERING_AMD);
    double *v1 = sw_chol_values(&ch);
    sw_pattern_fill(&p1, m, d, a, 1.0, v1);
    assert_int_equal(p1.nnz, p0.nnz);
    for (int c = 0; c < p0.n; c++) /* every entry where the DOFs say, bit for bit */
      for (long q = p0.colptr[c]; q < p0.colptr[c + 1]; q++) {
        long q1 = sw_pattern_slot(&p1, (int)p0.rowind[q], c);
        assert_true(q1 >= 0);
        assert_memory_equal(&v1[q1], &v0[q], sizeof(double));
      }
    long longest = 0;
    for (int i = 0; i < p1.n; i++) { /* its triangle, rows sorted */
      if (p1.colptr[i + 1] - p1.colptr[i] > longest) longest = p1.colptr[i + 1] - p1.colptr[i];
      for (long q = p1.colptr[i]; q < p1.colptr[i + 1]; q++) {
        assert_true(p1.lower ? p1.rowind[q] >= i : p1.rowind[q] <= i);
        assert_true(q == p1.colptr[i] || p1.rowind[q] > p1.rowind[q - 1]);
      }
    }
    assert_true(j ? longest > 64 : longest <= 64);
    const int n = p0.n;
    double *b = calloc((size_t)n, sizeof *b), *y0 = calloc((size_t)n, sizeof *y0);
    double *y1 = calloc((size_t)n, sizeof *y1);
    for (int c = 0; c < n; c++) b[c] = th_rand(&rs);
    sw_pattern_symv(&p0, v0, b, y0);
    sw_pattern_symv(&p1, v1, b, y1);
    assert_true(th_max_diff(y0, y1, n) < 1e-12 * a);
    /* CHOLMOD's own path on the pattern as built: upper, permuted at each factorisation */
    cholmod_common c;
    cholmod_start(&c);
    c.final_ll = 1;
    c.supernodal = super ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c.nmethods = 1, c.method[0].ordering = CHOLMOD_AMD, c.postorder = 1;
    for (int k = 0; k < 3; k++) c.nrelax[k] = ch.c.nrelax[k], c.zrelax[k] = ch.c.zrelax[k];
    cholmod_sparse A0 = {.nrow = (size_t)n, .ncol = (size_t)n, .nzmax = (size_t)p0.nnz,
                         .p = p0.colptr, .i = p0.rowind, .x = v0, .stype = 1,
                         .itype = CHOLMOD_INT, .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE,
                         .sorted = 1, .packed = 1};
    cholmod_factor *L0 = cholmod_analyze(&A0, &c);
    assert_non_null(L0);
    assert_true(c.lnz == ch.c.lnz && c.fl == ch.c.fl); /* the same factor */
    double copy0 = factor_transient(&A0, L0, &c), copy1 = factor_transient(ch.A, ch.L, &ch.c);
    print_message("%d x %d, %s: %ld nonzeros; transient bytes per nonzero during a "
                  "factorisation: %.1f in CHOLMOD's own path, %.1f stored in order\n",
                  sizes[j], sizes[j], super ? "supernodal" : "simplicial", p0.nnz,
                  copy0 / p0.nnz, copy1 / p0.nnz);
    const double entry = sizeof(double) + sizeof(int); /* a copied nonzero: value and row */
    assert_true(copy0 >= entry * p0.nnz);
    assert_true(copy1 <= copy0 - entry * p0.nnz);
    cholmod_dense B = {.nrow = (size_t)n, .ncol = 1, .nzmax = (size_t)n, .d = (size_t)n,
                       .x = b, .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE};
    cholmod_dense *X0 = cholmod_solve(CHOLMOD_A, L0, &B, &c);
    assert_non_null(X0);
    assert_int_equal(sw_chol_solve(&ch, b, y1, err, sizeof err), 0);
    double ymax = 0.0;
    for (int k = 0; k < n; k++) ymax = fmax(ymax, fabs(y1[k]));
    assert_true(ymax > 0.0);
    assert_true(th_max_diff(X0->x, y1, n) <= 1e-12 * ymax);
    cholmod_free_dense(&X0, &c);
    cholmod_free_factor(&L0, &c);
    cholmod_finish(&c);
    sw_chol_free(&ch);
    free(b), free(y0), free(y1), free(v0);
    sw_pattern_free(&p0);
    sw_pattern_free(&p1);
    sw_data_free(d);
    sw_model_free(m);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fill_3d),
      cmocka_unit_test(fill_2d),
      cmocka_unit_test(fill_every_term), cmocka_unit_test(fill_repeated_vertex),
      cmocka_unit_test(not_positive_definite), cmocka_unit_test(cholmod_out_of_memory),
      cmocka_unit_test(newton_minimises),
      cmocka_unit_test(every_mode_descends),
      cmocka_unit_test(ordering_rule),
      cmocka_unit_test(elimination_order),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
