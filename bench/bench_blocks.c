/* bench_blocks.c — CPU time of one self-contact pair block (models/barrier_block.c) by the
 * kind of its closest features, on random pairs near contact (docs/contact.md, "The clamp in
 * closed form"):
 *
 *   bench_blocks [--header] [reps]
 *
 * prints one CSV line per case: case, pairs, us_per_pair (CPU time, one thread), where the
 * cases are the distance form alone (form, by k: 0 two points, 1 a point and a line, 2
 * interiors), the form and its clamped block (block, by k: the closed form where the closest
 * points slide), the mollified edge-edge pairs' 9 x 9 clamp (clamp_free, on the exact
 * mollified Hessians of nearly parallel pairs) and, for reference, the 12 x 12 clamp
 * (sw_psd_project) of the same Hessians; then the small symmetric eigensolver of
 * models/eigen.c against LAPACK's dsyev (eigen_N, dsyev_N: us per random N x N matrix, N = 3
 * ... 18).  Run with OPENBLAS_NUM_THREADS=1. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "contact_geom.h"
#include "harness.h"
#include "terms.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

enum { NPAIR = 4000 };

static double cpu_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* A random pair near contact as tests/test_contact_cost.c draws them: kind 0 point-triangle,
 * 1 edge-edge; every few draws the point (or a0) beside a vertex or an edge's midpoint. */
static void random_pair(unsigned long *rs, int kind, int rep, double *x) {
  for (int i = 0; i < 12; i++) x[i] = 0.3 * th_rand(rs);
  int near = rep % 4, j = 1 + rep % 3;
  if (near == 1)
    for (int a = 0; a < 3; a++) x[a] = x[3 * (kind ? 2 : j) + a] + 0.02 * th_rand(rs);
  if (near == 2)
    for (int a = 0; a < 3; a++)
      x[a] = 0.5 * (x[3 * j + a] + x[3 * (j % 3 + 1) + a]) + 0.02 * th_rand(rs);
}

static double X[NPAIR][12], MH[500][144];
static int KIND[NPAIR], K[NPAIR];

/* The exact mollified edge-edge Hessians of n nearly parallel pairs into MH; their count. */
static int mollified(unsigned long *rs) {
  int n = 0;
  for (int rep = 0; rep < 40000 && n < 500; rep++) {
    double x[12], g2[12], H2[144], mg[12], mH[144], bg[12], bH[144], g[12], db, d2b;
    for (int i = 0; i < 6; i++) x[i] = 0.3 * th_rand(rs);
    double off[3] = {0.05 * th_rand(rs), 0.05 * th_rand(rs), 0.05 * th_rand(rs)};
    for (int i = 0; i < 6; i++)
      x[6 + i] = x[i] + off[i % 3] + 0.004 * th_rand(rs) * (i < 3 ? 1.0 : -1.0);
    double d2 = sw_d2_edge_edge(x, x + 3, x + 6, x + 9, g2, H2), shat = 4.0 * d2;
    double eps = sw_ee_mollifier_eps(x, x + 3, x + 6, x + 9) * 400.0;
    double mo = sw_ee_mollifier(x, x + 3, x + 6, x + 9, eps, mg, mH);
    if (!(mo < 1.0) || !(d2 > 0.0)) continue;
    double b = sw_barrier(d2, shat, &db, &d2b);
    sw_barrier_of(12, d2, g2, H2, shat, bg, bH);
    sw_product_derivs(12, mo, mg, mH, b, bg, bH, g, MH[n++]);
  }
  return n;
}

int main(int argc, char **argv) {
  int a = 1, reps = 50;
  if (a < argc && !strcmp(argv[a], "--header")) puts("case,pairs,us_per_pair"), a++;
  if (a < argc) reps = atoi(argv[a]);
  unsigned long rs = 7;
  for (int i = 0; i < NPAIR; i++) {
    sw_pair_form pf;
    KIND[i] = i % 2;
    random_pair(&rs, KIND[i], i / 2, X[i]);
    sw_pair_d2_form(KIND[i], X[i], &pf);
    K[i] = pf.k;
  }
  double sink = 0.0;
  for (int k = 0; k < 3; k++)
    for (int block = 0; block < 2; block++) {
      long n = 0;
      double t0 = cpu_now(), H[144];
      for (int r = 0; r < reps; r++)
        for (int i = 0; i < NPAIR; i++) {
          if (K[i] != k) continue;
          sw_pair_form pf;
          double d2 = sw_pair_d2_form(KIND[i], X[i], &pf); /* b = -log-like: b' < 0 < b'' */
          if (block) sw_pair_barrier_block(&pf, -1.0 / d2, 2.0 / (d2 * d2), 1.0, H), sink += H[0];
          sink += d2;
          n++;
        }
      printf("%s_k%d,%ld,%.4f\n", block ? "block" : "form", k, n, 1e6 * (cpu_now() - t0) / (double)n);
    }
  int nm = mollified(&rs);
  for (int lapack = 0; lapack < 2; lapack++) {
    double t0 = cpu_now(), H[144];
    for (int r = 0; r < reps; r++)
      for (int i = 0; i < nm; i++) {
        memcpy(H, MH[i], sizeof H);
        if (lapack) sw_psd_project(H, 12, SW_FILTER_CLAMP);
        else sw_pair_clamp_free(H);
        sink += H[0];
      }
    printf("%s,%d,%.4f\n", lapack ? "psd_project_12" : "clamp_free", nm,
           1e6 * (cpu_now() - t0) / ((double)nm * reps));
  }
  for (int n = 3; n <= SW_EIGEN_NMAX; n += 3) /* one random symmetric matrix per size */
    for (int lapack = 0; lapack < 2; lapack++) {
      double A0[SW_EIGEN_NMAX * SW_EIGEN_NMAX], A[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
      double w[SW_EIGEN_NMAX], work[SW_EIGEN_NMAX * 34];
      int lwork = SW_EIGEN_NMAX * 34, info = 0, calls = 200 * reps;
      for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++) A0[i * n + j] = A0[j * n + i] = th_rand(&rs);
      double t0 = cpu_now();
      for (int r = 0; r < calls; r++) {
        memcpy(A, A0, sizeof(double) * (size_t)(n * n));
        if (lapack) dsyev_("V", "U", &n, A, &n, w, work, &lwork, &info);
        else sw_sym_eigen(A, n, w);
        sink += w[0];
      }
      printf("%s_%d,%d,%.4f\n", lapack ? "dsyev" : "eigen", n, calls,
             1e6 * (cpu_now() - t0) / (double)calls);
    }
  return isfinite(sink) ? 0 : 1;
}
