/* bench_tendon.c — fill and time of a long tendon's Hessian: one dense stencil against banded
 * stencils plus a low-rank vector solved by Woodbury (docs/tendons.md).
 *
 *   bench_tendon [--header] N nway [steps]
 *
 * An N x N hanging cloth (1 m square, 3D, density 0.1 kg/m^2, bw98 k_u = k_v = 5000 N/m
 * (test grid: k_v = 0.7 k_u), k_shear = 100 N/m, gravity (0, 0, -9.81), top edge pinned) and
 * one spring tendon of nway waypoints zig-zagging along the rows from the middle row down
 * (K = 500 N/m, rest length its initial length: it resists the cloth stretching along it).
 * For each storage (dense: tendon_dense_max = nway; lowrank: tendon_dense_max = 1) prints one
 * CSV line:
 *
 *   mode, N, dofs, nway, nnz (upper triangle of S), nnz_L (CHOLMOD's lnz), flops (of one
 *   numeric factorisation, CHOLMOD's fl), analyze_s, factor_s (median of 15
 *   refactorisations, Woodbury set-up included), solve_s (median of 15),
 *   steps, newton, step_s (mean backward-Euler step of dt = 0.01 s), checksum (sum of x)
 *
 * The checksum shows both storages take the same trajectory. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "solver.h"
#include "util.h"

static const char *header = "mode,N,dofs,nway,nnz,nnz_L,flops,analyze_s,factor_s,solve_s,steps,"
                            "newton,step_s,checksum";

static sw_model *cloth_with_tendon(int n, int nway, int dense_max) {
  const double g[3] = {0.0, 0.0, -9.81};
  sw_model *m = th_grid_start(3, n, n, 1.0, 1.0, 0.1, 5000.0, 100.0, g, 1);
  int *way = malloc(sizeof(int) * (size_t)nway);
  for (int k = 0; k < nway; k++) {
    int row = n / 2 - k / n, col = k % n;
    if ((k / n) % 2) col = n - 1 - col; /* back along the next row */
    way[k] = row * n + col;
  }
  th_add_tendon(m, way, nway, SW_LAW_SPRING, 500.0, 1.0, 0.0);
  m->tendon[0].key_rest[0] = sw_tendon_length(&m->tendon[0], m->x0, 3);
  m->opt.tendon_dense_max = dense_max;
  free(way);
  char err[SW_ERRSZ];
  if (sw_model_finish(m, err, sizeof err)) {
    fprintf(stderr, "bench_tendon: %s\n", err);
    exit(1);
  }
  return m;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

#define REPS 15

static double median(double *t) {
  qsort(t, REPS, sizeof *t, cmp_double);
  return t[REPS / 2];
}

/* Factor and solve times of S = M/h^2 + H at x0 (median of REPS each). */
static void time_linear(const sw_model *m, sw_data *d, sw_newton *nw, double *tf, double *ts) {
  double u, f[REPS], s[REPS];
  sw_eval_terms(m, d, m->x0, 0.0, 1, 1, 1, &u);
  for (int k = 0; k < nw->n; k++) nw->g[k] = 1.0;
  for (int r = 0; r < REPS; r++) {
    double t0 = sw_now();
    sw_pattern_fill(&nw->pat, m, d, 1e4, sw_chol_values(&nw->chol));
    sw_pattern_fill_lowrank(&nw->pat, d, sw_chol_lowrank(&nw->chol, 1.0));
    if (sw_chol_factor(&nw->chol, d->err, sizeof d->err)) fprintf(stderr, "%s\n", d->err);
    double t1 = sw_now();
    sw_chol_solve(&nw->chol, nw->g, nw->dx, d->err, sizeof d->err);
    f[r] = t1 - t0;
    s[r] = sw_now() - t1;
  }
  *tf = median(f);
  *ts = median(s);
}

static void run(const char *mode, int n, int nway, int steps) {
  sw_model *m = cloth_with_tendon(n, nway, strcmp(mode, "dense") ? 1 : nway);
  sw_data *d = sw_data_new(m);
  sw_newton nw;
  char err[SW_ERRSZ];
  double t0 = sw_now();
  if (sw_newton_init(&nw, m, err, sizeof err)) fprintf(stderr, "%s\n", err), exit(1);
  double ta = sw_now() - t0, tf, ts;
  time_linear(m, d, &nw, &tf, &ts);
  double lnz = nw.chol.c.lnz, fl = nw.chol.c.fl;
  long nnz = nw.pat.nnz;
  sw_newton_free(&nw);
  const sw_integrator_ops *ops = sw_integrator_find("backward-euler");
  void *st = NULL;
  if (ops->init(&st, m, d, err, sizeof err)) fprintf(stderr, "%s\n", err), exit(1);
  double ts0 = sw_now();
  for (int k = 0; k < steps; k++)
    if (ops->step(st, m, d, 0.01)) fprintf(stderr, "step %d: %s\n", k, d->err), exit(1);
  double tstep = (sw_now() - ts0) / steps, sum = 0.0;
  for (int i = 0; i < m->nv * 3; i++) sum += d->x[i];
  printf("%s,%d,%d,%d,%ld,%.0f,%.4g,%.4g,%.4g,%.4g,%d,%ld,%.4g,%.15g\n", mode, n, m->ndof, nway,
         nnz, lnz, fl, ta, tf, ts, steps, d->nnewton, tstep, sum);
  ops->free(st);
  sw_data_free(d);
  sw_model_free(m);
}

int main(int argc, char **argv) {
  int a = 1;
  if (a < argc && !strcmp(argv[a], "--header")) printf("%s\n", header), a++;
  if (argc - a < 2) /* --header alone: only the header */
    return a > 1 ? 0 : (fprintf(stderr, "usage: bench_tendon [--header] N nway [steps]\n"), 2);
  int n = atoi(argv[a]), nway = atoi(argv[a + 1]), steps = argc - a > 2 ? atoi(argv[a + 2]) : 3;
  if (n < 2 || nway < 2 || nway > n * (n / 2 + 1) || steps < 1)
    return fprintf(stderr, "bench_tendon: N >= 2, 2 <= nway <= N (N/2 + 1), steps >= 1\n"), 2;
  sw_set_threads(1);
  run("dense", n, nway, steps);
  run("lowrank", n, nway, steps);
  return 0;
}
