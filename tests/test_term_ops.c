/* test_term_ops.c — the optional operations of the term table (sw_term_ops) through a term
 * defined here only: a spring between two far corners of a grid that switches on at the
 * term's second evaluation and reports its Hessian as an extra block (not as a stencil), so
 * the Newton solver must grow its sparse pattern for it; a workspace (data_new, data_free),
 * a start-of-step op that makes one attempt fail (the step is retried halved), and a commit
 * op counted once per accepted state.  Nothing in solvers/ or sim/ knows of the term. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "harness.h"
#include "terms.h"

enum { NX = 5 };               /* the grid's vertices per side */
#define SPRING_K 100.0         /* N/m: k h^2 / m of the corners about 10 at dt = 0.01 s */
#define FAIL_BEGIN 2           /* the begin op's call that fails (step 2's first attempt) */

typedef struct tt_param {      /* immutable */
  int v[2];                    /* the two vertices the spring joins */
  double k;                    /* N/m */
  double r[3];                 /* m: the rest offset x_a - x_b */
} tt_param;

typedef struct tt_data {       /* the workspace: what changes over a run */
  int nevals, nbegin, ncommit;
  int have_hess;               /* the last evaluation asked for the Hessian */
  double block[36];            /* its 2-vertex block, N/m */
} tt_data;

static int tt_freed;           /* workspaces released */

/* E = k/2 |x_a - x_b - r|^2 from the second evaluation on (0 before). */
static int tt_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const tt_param *p = t->param;
  tt_data *w = ev->data;
  assert_non_null(w);
  const int a = p->v[0], b = p->v[1], dim = m->dim;
  w->have_hess = ev->hess != NULL;
  *energy = 0.0;
  if (++w->nevals < 2) return SW_OK;
  double q[3] = {0.0, 0.0, 0.0}, e = 0.0;
  for (int c = 0; c < dim; c++) {
    q[c] = ev->x[a * dim + c] - ev->x[b * dim + c] - p->r[c];
    e += 0.5 * p->k * q[c] * q[c];
  }
  for (int c = 0; ev->grad && c < dim; c++) {
    ev->grad[a * dim + c] += p->k * q[c];
    ev->grad[b * dim + c] -= p->k * q[c];
  }
  const int n = 2 * dim;
  memset(w->block, 0, sizeof w->block);
  for (int c = 0; c < dim; c++) { /* k [I -I; -I I] */
    w->block[c * n + c] = w->block[(dim + c) * n + dim + c] = p->k;
    w->block[c * n + dim + c] = w->block[(dim + c) * n + c] = -p->k;
  }
  *energy = e;
  return SW_OK;
}

static void *tt_data_new(const sw_term *t, const sw_model *m, sw_data *d) {
  (void)t, (void)m, (void)d;
  return calloc(1, sizeof(tt_data));
}

static void tt_data_free(void *data) {
  tt_freed++;
  free(data);
}

/* One block from the second evaluation on: the spring's two vertices. */
static void tt_blocks(const sw_term *t, const sw_model *m, const sw_data *d, const void *data,
                      sw_blocks *b) {
  (void)m, (void)d;
  const tt_param *p = t->param;
  const tt_data *w = data;
  if (w->nevals < 2) return;
  *b = (sw_blocks){.n = 1, .nvb = 2, .v = p->v, .vstride = 2,
                   .val = w->have_hess ? w->block : NULL};
}

/* The FAIL_BEGIN-th attempt of a step fails (recoverable: it is retried halved). */
static int tt_begin(const sw_term *t, const sw_model *m, sw_data *d, void *data, double h,
                    double t1, double *y) {
  (void)t, (void)m, (void)h, (void)y;
  tt_data *w = data;
  if (++w->nbegin != FAIL_BEGIN) return SW_OK;
  snprintf(d->err, sizeof d->err, "test term: attempt %d to t = %g s refused", w->nbegin, t1);
  return SW_RECOVER;
}

static void tt_commit(const sw_term *t, const sw_model *m, sw_data *d, void *data) {
  (void)t, (void)m, (void)d;
  ((tt_data *)data)->ncommit++;
}

static void tt_free_param(void *param) { free(param); }

static const sw_term_ops tt_ops = {.kind = "test_spring", .eval = tt_eval,
                                   .free_param = tt_free_param, .data_new = tt_data_new,
                                   .data_free = tt_data_free, .blocks = tt_blocks,
                                   .begin = tt_begin, .commit = tt_commit};

/* A 5 x 5 grid of 1 m with no membrane and no gravity, and the test term appended (after
 * sw_model_finish: the model holds room for more terms than it built). */
static sw_model *spring_model(void) {
  sw_model *m = th_grid_model(3, NX, NX, 1.0, 1.0, 0.1, 0.0, 0.0, NULL, 0);
  assert_non_null(m);
  sw_term *t = &m->term[m->nterm];
  memset(t, 0, sizeof *t);
  t->ops = &tt_ops;
  snprintf(t->name, sizeof t->name, "test_spring");
  assert_int_equal(sw_term_alloc_stencils(t, 0, 1, m->dim), 0); /* no stencils */
  tt_param *p = calloc(1, sizeof *p);
  assert_non_null(p);
  p->v[0] = 0, p->v[1] = NX * NX - 1; /* opposite corners */
  p->k = SPRING_K;
  p->r[0] = -0.8, p->r[1] = -0.9, p->r[2] = 0.1; /* m: not the start's offset (-1, -1, 0) */
  t->param = p;
  m->nterm++;
  snprintf(m->opt.method, sizeof m->opt.method, "backward-euler");
  m->opt.dt = 0.01;
  return m;
}

/* One backward Euler step of size h of the spring alone, exact: with xhat = x + h v,
 * q = (xhat_a - xhat_b - r) / (1 + k h^2 (1/m_a + 1/m_b)), x_a = xhat_a - k h^2 q / m_a,
 * x_b = xhat_b + k h^2 q / m_b, v = (x_new - x) / h; every other vertex keeps its velocity. */
static void exact_step(const sw_model *m, const tt_param *p, double h, double *x, double *v) {
  const int a = p->v[0], b = p->v[1];
  const double ma = m->mass[a], mb = m->mass[b], k = p->k;
  for (int c = 0; c < 3; c++) {
    double xa = x[3 * a + c] + h * v[3 * a + c], xb = x[3 * b + c] + h * v[3 * b + c];
    double q = (xa - xb - p->r[c]) / (1.0 + k * h * h * (1.0 / ma + 1.0 / mb));
    double na = xa - k * h * h * q / ma, nb = xb + k * h * h * q / mb;
    v[3 * a + c] = (na - x[3 * a + c]) / h, x[3 * a + c] = na;
    v[3 * b + c] = (nb - x[3 * b + c]) / h, x[3 * b + c] = nb;
  }
}

static double max_diff(const double *a, const double *b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s = fmax(s, fabs(a[i] - b[i]));
  return s;
}

/* The pattern grows once for the block, Newton then solves the coupled step exactly (a
 * quadratic energy: its first iteration is the answer, the second confirms it), the state
 * matches the exact steps, and commit runs once for the first state and once per accepted
 * step (a refused attempt is not committed). */
static void grows_and_commits(void **state) {
  (void)state;
  sw_model *m = spring_model();
  const int k = m->nterm - 1, nd = 3 * m->nv;
  const tt_param *p = m->term[k].param;
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  if (!s) fprintf(stderr, "%s\n", err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  const tt_data *w = d->tdata[k];
  assert_non_null(w);
  assert_int_equal(d->npattern, 0);
  assert_int_equal(w->ncommit, 1); /* the first state */
  double *x = malloc(sizeof(double) * (size_t)nd), *v = calloc((size_t)nd, sizeof(double));
  assert_non_null(x);
  assert_non_null(v);
  memcpy(x, m->x0, sizeof(double) * (size_t)nd);
  const double h = m->opt.dt;
  for (int step = 1; step <= 4; step++) {
    long retries = d->nretry;
    int rc = sw_sim_step(s, err, sizeof err);
    if (rc) fprintf(stderr, "%s\n", err);
    assert_int_equal(rc, SW_OK);
    if (d->nretry > retries) { /* the refused attempt: two steps of h/2 instead */
      assert_int_equal(step, 2);
      exact_step(m, p, 0.5 * h, x, v);
      exact_step(m, p, 0.5 * h, x, v);
    } else {
      exact_step(m, p, h, x, v);
    }
    double ex = max_diff(x, d->x, nd), ev = max_diff(v, d->v, nd);
    if (ex > 1e-12 || ev > 1e-10 || d->last_newton > 2)
      fprintf(stderr, "step %d: |x - exact| = %g m, |v - exact| = %g m/s, %d Newton "
              "iterations\n", step, ex, ev, d->last_newton);
    assert_true(ex <= 1e-12);
    assert_true(ev <= 1e-10);
    assert_true(d->last_newton <= 2);
    assert_int_equal(d->npattern, 1); /* grown at step 1's first assembly, once */
    assert_int_equal(w->ncommit, d->nstep + 1);
  }
  assert_int_equal(d->nretry, 1);
  assert_int_equal(d->nstep, 5); /* steps 1, 3, 4 and step 2's two halves */
  assert_true(fabs(d->x[0] - m->x0[0]) > 1e-4); /* the spring moved the corner */
  tt_freed = 0;
  sw_sim_free(s);
  assert_int_equal(tt_freed, 1);
  free(x);
  free(v);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(grows_and_commits),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
