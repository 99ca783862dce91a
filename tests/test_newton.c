/* test_newton.c — Newton-Krylov on a lagged factorisation (the direction conjugate gradients
 * give against a fresh factorisation's, runs with and without reuse), the factorisation chosen
 * by size, one copy of the system without reuse, CHOLMOD's OpenMP regions run serially,
 * the idle BLAS workers stopped, and the gathered garment that used to fail. */
#define _GNU_SOURCE /* dlsym(RTLD_DEFAULT) */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <dirent.h>
#include <dlfcn.h>

#include "harness.h"
#include "solver.h"

/* scenes/hanging_cloth.yaml with n x n vertices. */
static sw_model *cloth(int n) {
  char err[SW_ERRSZ];
  sw_scene_overrides ov = {.grid = {n, n}};
  sw_model *m = sw_scene_load_ex("scenes/hanging_cloth.yaml", &ov, err, sizeof err);
  if (!m) fprintf(stderr, "%s\n", err);
  assert_non_null(m);
  return m;
}

/* Take steps of ops from the state in d (each must succeed without halving). */
static void take(const sw_integrator_ops *ops, void *st, const sw_model *m, sw_data *d,
                 int steps) {
  for (int k = 0; k < steps; k++) {
    int rc = ops->step(st, m, d, m->opt.dt);
    if (rc) fprintf(stderr, "%s at t = %g s: %s\n", ops->name, d->t, d->err);
    assert_int_equal(rc, 0);
  }
}

static double dot(const double *a, const double *b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* The Newton system at x with xhat = x + h v (backward Euler's), into nw. */
static void system_at(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                      const double *v, double *xhat, const sw_newton_opts *o) {
  for (int i = 0; i < m->nv * m->dim; i++) xhat[i] = x[i] + m->opt.dt * v[i];
  double phi;
  assert_int_equal(sw_newton_system(nw, m, d, x, xhat, o, &phi), 0);
}

/* The 20 x 20 hanging cloth at t = 0.03 s and 0.04 s (backward Euler): the factorisation of the
 * first state's Newton matrix preconditions CG on the second's.  CG's direction agrees with
 * the fresh factorisation's to CG's tolerance in the S-norm (its stopping test estimates that
 * error with the preconditioner's norm: a factor 2 is allowed for the difference), while with
 * the fresh factorisation itself CG stops after one iteration at round-off. */
static void lagged_direction(void **state) {
  (void)state;
  sw_model *m = cloth(20);
  const sw_integrator_ops *ops = sw_integrator_find("backward-euler");
  void *st;
  sw_data *d = th_start(ops, m, &st);
  assert_non_null(d);
  const int nd = m->nv * m->dim;
  double *xa = calloc((size_t)nd, sizeof *xa), *va = calloc((size_t)nd, sizeof *va);
  double *xb = calloc((size_t)nd, sizeof *xb), *vb = calloc((size_t)nd, sizeof *vb);
  double *xhat = calloc((size_t)nd, sizeof *xhat);
  take(ops, st, m, d, 3);
  memcpy(xa, d->x, (size_t)nd * sizeof *xa), memcpy(va, d->v, (size_t)nd * sizeof *va);
  take(ops, st, m, d, 1);
  memcpy(xb, d->x, (size_t)nd * sizeof *xb), memcpy(vb, d->v, (size_t)nd * sizeof *vb);

  sw_newton nw;
  char err[SW_ERRSZ];
  assert_int_equal(sw_newton_init(&nw, m, err, sizeof err), 0);
  assert_int_equal(nw.pat.nlr, 0);
  const int n = nw.n;
  const double h = m->opt.dt;
  /* a strict Newton tolerance: CG's own is then SW_CG_ETA of the direction */
  sw_newton_opts o = {.a = 1.0 / (h * h), .t = d->t, .tol_dx = 1e-12, .norm = SW_NORM_RMS,
                      .hessian = m->opt.hessian, .reuse = SW_REUSE_ON, .h = h};
  system_at(&nw, m, d, xa, va, xhat, &o);
  assert_int_equal(sw_newton_factor(&nw, d), 0);
  system_at(&nw, m, d, xb, vb, xhat, &o);
  int k = sw_newton_pcg(&nw, d, &o);
  double *dcg = calloc((size_t)n, sizeof *dcg), *dex = calloc((size_t)n, sizeof *dex);
  double *e = calloc((size_t)n, sizeof *e), *se = calloc((size_t)n, sizeof *se);
  memcpy(dcg, nw.dx, (size_t)n * sizeof *dcg);
  assert_int_equal(sw_newton_factor(&nw, d), 0);
  assert_int_equal(sw_chol_solve(&nw.chol, nw.g, dex, err, sizeof err), 0);
  for (int c = 0; c < n; c++) e[c] = dcg[c] - dex[c];
  sw_pattern_symv(&nw.pat, nw.sval, e, se);
  double err_s = sqrt(dot(e, se, n));
  sw_pattern_symv(&nw.pat, nw.sval, dex, se);
  double size_s = sqrt(dot(dex, se, n)), rel = err_s / size_s;
  /* the same system with its own factorisation as preconditioner */
  int k1 = sw_newton_pcg(&nw, d, &o);
  for (int c = 0; c < n; c++) e[c] = nw.dx[c] - dex[c];
  sw_pattern_symv(&nw.pat, nw.sval, e, se);
  double rel1 = sqrt(dot(e, se, n)) / size_s;
  print_message("lagged factorisation: %d CG iterations, |dx_cg - dx|_S / |dx|_S = %.3g "
                "(tolerance %g); fresh: %d iteration, %.3g\n", k, rel, SW_CG_ETA, k1, rel1);
  assert_true(k > 1 && k <= SW_CG_MAX);
  assert_true(rel <= 2.0 * SW_CG_ETA);
  assert_int_equal(k1, 1);
  assert_true(rel1 < 1e-10);
  sw_newton_free(&nw);
  free(dcg), free(dex), free(e), free(se);
  free(xa), free(va), free(xb), free(vb), free(xhat);
  ops->free(st);
  sw_data_free(d);
  sw_model_free(m);
}

/* The 24 x 24 hanging cloth to t = 0.1 s by every fixed-step Newton method, with reuse on (CG
 * on the lagged factorisation), reuse step (a factorisation at each step's first iteration, CG
 * on it at the later ones) and without (a factorisation per iteration): the positions agree
 * to Newton's tolerance, tol * dt in the RMS over vertices, while reuse factorises less; with
 * step, exactly one factorisation per step wherever CG converged (none here needs more than
 * SW_CG_MAX iterations), and each later iteration solved by CG. */
static void reuse_matches(void **state) {
  (void)state;
  static const char *const methods[] = {"backward-euler", "bdf2", "implicit-midpoint",
                                        "newmark"};
  static const int modes[3] = {SW_REUSE_OFF, SW_REUSE_ON, SW_REUSE_STEP};
  sw_model *m = cloth(24);
  const int nd = m->nv * m->dim;
  double *x0 = calloc((size_t)nd, sizeof *x0);
  for (int j = 0; j < 4; j++) {
    const sw_integrator_ops *ops = sw_integrator_find(methods[j]);
    long nfac[3], ncg[3], nnewton[3], nstep[3];
    double rms[3] = {0.0, 0.0, 0.0};
    for (int r = 0; r < 3; r++) {
      m->opt.newton_reuse = modes[r];
      void *st;
      sw_data *d = th_start(ops, m, &st);
      assert_non_null(d);
      take(ops, st, m, d, 10);
      nfac[r] = d->nfactor, ncg[r] = d->ncg, nnewton[r] = d->nnewton, nstep[r] = d->nstep;
      if (!r) memcpy(x0, d->x, (size_t)nd * sizeof *x0);
      for (int i = 0; i < nd; i++) rms[r] += (d->x[i] - x0[i]) * (d->x[i] - x0[i]);
      rms[r] = sqrt(rms[r] / m->nv);
      ops->free(st);
      sw_data_free(d);
    }
    double tol = m->opt.newton_tol * m->opt.dt; /* m */
    print_message("%-17s factorisations %ld -> on %ld, step %ld (%ld steps, %ld Newton "
                  "iterations); CG iterations %ld, %ld; RMS difference at t = 0.1 s %.3g, "
                  "%.3g m (tolerance %.3g m)\n", methods[j], nfac[0], nfac[1], nfac[2],
                  nstep[2], nnewton[2], ncg[1], ncg[2], rms[1], rms[2], tol);
    assert_int_equal(ncg[0], 0);
    assert_true(ncg[1] > 0 && ncg[2] > 0);
    assert_true(nfac[1] < nfac[0]);
    assert_int_equal(nfac[0], nnewton[0]);
    assert_int_equal(nfac[2], nstep[2]); /* one per step */
    assert_true(nnewton[2] > nstep[2]);  /* ... which took more than one iteration */
    assert_true(ncg[2] >= nnewton[2] - nstep[2]);
    assert_true(rms[1] <= tol && rms[2] <= tol);
  }
  free(x0);
  sw_model_free(m);
}

/* The size rule (auto): simplicial for the 10 x 10 cloth, whose factorisation takes fewer
 * than SW_FACTOR_SWITCH flops per nonzero of L, supernodal for the 20 x 20 and 80 x 80 ones,
 * with coarse supernodes below SW_RELAX_SWITCH unknowns and CHOLMOD's own above
 * (docs/performance.md, "Simplicial or supernodal"); the forced modes are obeyed, and every
 * mode solves the same system to the same answer. */
static void size_rule(void **state) {
  (void)state;
  const int sizes[3] = {10, 20, 80}, want[3] = {0, 1, 1};
  char err[SW_ERRSZ];
  for (int j = 0; j < 3; j++) {
    sw_model *m = cloth(sizes[j]);
    sw_pattern p;
    sw_chol ch;
    assert_int_equal(sw_pattern_build(&p, m, err, sizeof err), 0);
    assert_int_equal(sw_chol_init(&ch, &p, SW_FACTOR_AUTO, err, sizeof err), 0);
    double per = ch.c.fl / ch.c.lnz;
    print_message("%d x %d: %d DOFs, %.0f flops per nonzero of L: %s\n", sizes[j], sizes[j],
                  p.n, per, sw_chol_super(&ch) ? "supernodal" : "simplicial");
    assert_int_equal(sw_chol_super(&ch), want[j]);
    assert_true(want[j] ? per >= SW_FACTOR_SWITCH : per < SW_FACTOR_SWITCH);
    assert_int_equal(ch.c.nrelax[0], p.n < SW_RELAX_SWITCH ? 16 : 4);
    assert_true(p.n < SW_RELAX_SWITCH ? j < 2 : j == 2); /* both sides of the switch */
    sw_chol_free(&ch);
    if (j == 0) { /* forced modes, and the same answer from each */
      unsigned long rs = 7;
      double *b = calloc((size_t)p.n, sizeof *b), *y[2];
      for (int c = 0; c < p.n; c++) b[c] = th_rand(&rs);
      for (int f = 0; f < 2; f++) {
        int mode = f ? SW_FACTOR_SUPERNODAL : SW_FACTOR_SIMPLICIAL;
        y[f] = calloc((size_t)p.n, sizeof *y[f]);
        assert_int_equal(sw_chol_init(&ch, &p, mode, err, sizeof err), 0);
        assert_int_equal(sw_chol_super(&ch), f);
        th_fill_dominant(&p, sw_chol_values(&ch));
        assert_int_equal(sw_chol_factor(&ch, err, sizeof err), 0);
        assert_int_equal(sw_chol_solve(&ch, b, y[f], err, sizeof err), 0);
        sw_chol_free(&ch);
      }
      assert_true(th_max_diff(y[0], y[1], p.n) < 1e-12);
      free(b), free(y[0]), free(y[1]);
    }
    sw_pattern_free(&p);
    sw_model_free(m);
  }
}

/* One backward-Euler step of the 20 x 20 cloth (supernodal) through sw_ipstep, with Newton
 * reuse off and on: off, Newton assembles S into the factorised values themselves (one copy
 * of the system); on, it keeps S apart (CG needs the current S beside an older factor).  The
 * two runs agree to Newton's tolerance in its RMS norm. */
static void one_copy_of_system(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  double *x[2];
  long n = 0;
  for (int reuse = 0; reuse < 2; reuse++) {
    sw_model *m = cloth(20);
    m->opt.newton_reuse = reuse ? SW_REUSE_ON : SW_REUSE_OFF;
    sw_data *d = sw_data_new(m);
    sw_ipstep ip;
    assert_int_equal(sw_ipstep_init(&ip, m, err, sizeof err), 0);
    assert_int_equal(sw_chol_super(&ip.nw.chol), 1);
    const double h = m->opt.dt;
    n = (long)m->nv * m->dim;
    for (int k = 0; k < 2; k++) { /* two steps: the second may reuse the first's factor */
      for (long i = 0; i < n; i++) ip.xhat[i] = d->x[i] + h * d->v[i], ip.xd[i] = d->x[i];
      sw_newton_opts o = sw_ipstep_opts(m, &ip, 1.0 / (h * h), d->t + h, 1.0 / h, h, 1.0);
      assert_int_equal(sw_ipstep_solve(&ip, m, d, &o, NULL), 0);
      for (long i = 0; i < n; i++) ip.vnew[i] = m->dof[i] < 0 ? 0.0 : (ip.xnew[i] - d->x[i]) / h;
      assert_int_equal(sw_ipstep_commit(&ip, m, d, h, 0), 0);
    }
    if (reuse) assert_ptr_not_equal(ip.nw.sval, sw_chol_values(&ip.nw.chol));
    else assert_ptr_equal(ip.nw.sval, sw_chol_values(&ip.nw.chol));
    assert_true(reuse ? ip.nw.sown != NULL : ip.nw.sown == NULL);
    x[reuse] = malloc((size_t)n * sizeof(double));
    memcpy(x[reuse], d->x, (size_t)n * sizeof(double));
    sw_ipstep_free(&ip);
    sw_data_free(d);
    sw_model_free(m);
  }
  double ss = 0.0;
  for (long i = 0; i < n; i++) ss += (x[0][i] - x[1][i]) * (x[0][i] - x[1][i]);
  double rms = sqrt(ss / (double)n), diff = th_max_diff(x[0], x[1], (int)n);
  print_message("reuse off vs on after two steps: RMS %.3g m, max %.3g m\n", rms, diff);
  /* Newton's tolerance: the RMS of the update below 1e-2 m/s x 0.01 s */
  assert_true(rms < 1e-4);
  assert_true(rms > 0.0); /* CG's direction is not the factorisation's: the runs differ */
  free(x[0]), free(x[1]);
}

/* CHOLMOD's OpenMP regions (sim/threads.c): GOMP_parallel runs the body once, on the calling
 * thread, which libgomp's omp_get_num_threads then calls a team of one. */
void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags);
static void count_region(void *data) {
  int *c = data;
  int (*nthreads)(void);
  *(void **)&nthreads = dlsym(RTLD_DEFAULT, "omp_get_num_threads");
  c[0]++;
  c[1] = nthreads ? nthreads() : 1;
}
static void openmp_regions_serial(void **state) {
  (void)state;
  if (getenv("OMP_MAX_ACTIVE_LEVELS") || getenv("OMP_THREAD_LIMIT")) skip(); /* libgomp's then */
  int c[2] = {0, 0};
  GOMP_parallel(count_region, c, 4, 0);
  assert_int_equal(c[0], 1);
  assert_int_equal(c[1], 1);
}

/* The threads of this process (/proc/self/task), or -1 where that cannot be read. */
static int task_count(void) {
  DIR *dir = opendir("/proc/self/task");
  if (!dir) return -1;
  int n = 0;
  for (struct dirent *e; (e = readdir(dir));) n += e->d_name[0] != '.';
  closedir(dir);
  return n;
}

/* One BLAS thread (sim/threads.c): OpenBLAS' idle workers, which spin for 0.1 s of CPU after
 * they start, are stopped.  Its pthreads build starts one worker per processor but one as it
 * is loaded, so the process loses that many threads (other threads, a sanitizer's or an
 * OpenMP team's, stay).  First in this file, before anything could have stopped them; skipped
 * where OpenBLAS has no such workers (its OpenMP or serial build, another BLAS) or the user
 * set their number; a factorisation after that still runs (the tests that follow). */
static void idle_blas_workers_stopped(void **state) {
  (void)state;
  int (*parallel)(void), (*threads)(void);
  *(void **)&parallel = dlsym(RTLD_DEFAULT, "openblas_get_parallel");
  *(void **)&threads = dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
  if (!parallel || parallel() != 1 || !threads || !dlsym(RTLD_DEFAULT, "blas_thread_shutdown_") ||
      getenv("OPENBLAS_NUM_THREADS") || getenv("GOTO_NUM_THREADS"))
    skip();
  int before = task_count(), workers = threads() - 1; /* as loaded: its pool but this thread */
  if (before < 0) skip();
  sw_set_threads(1);
  int after = task_count();
  print_message("threads before and after sw_set_threads(1): %d, %d (%d OpenBLAS workers)\n",
                before, after, workers);
  assert_int_equal(after, before - workers);
  sw_set_threads(1); /* again: nothing left to stop */
  assert_int_equal(task_count(), after);
}

/* scenes/garment_gather.yaml (StVK and bw98 panels, quadratic bending, a cable drawstring
 * gathering the hem to 60 %): every step of 10 ms converges without halving, and the hem is
 * gathered (the drawstring's length below 70 % of its initial length at the end). */
static void garment_gather(void **state) {
  (void)state;
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_load("scenes/garment_gather.yaml", err, sizeof err);
  if (!m) fprintf(stderr, "%s\n", err);
  assert_non_null(m);
  const sw_integrator_ops *ops = sw_integrator_find(m->opt.method);
  void *st;
  sw_data *d = th_start(ops, m, &st);
  assert_non_null(d);
  double l0 = sw_tendon_length(&m->tendon[0], m->x0, m->dim);
  int steps = (int)lround(m->opt.duration / m->opt.dt);
  take(ops, st, m, d, steps);
  double l1 = sw_tendon_length(&m->tendon[0], d->x, m->dim);
  print_message("garment: %d steps of %g s, %ld Newton iterations, %ld line-search cuts; "
                "drawstring %.3f -> %.3f m\n", steps, m->opt.dt, d->nnewton, d->nlinesearch, l0,
                l1);
  assert_true(l1 < 0.7 * l0);
  ops->free(st);
  sw_data_free(d);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(idle_blas_workers_stopped),
      cmocka_unit_test(lagged_direction),
      cmocka_unit_test(reuse_matches),
      cmocka_unit_test(size_rule),
      cmocka_unit_test(one_copy_of_system),
      cmocka_unit_test(openmp_regions_serial),
      cmocka_unit_test(garment_gather),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
