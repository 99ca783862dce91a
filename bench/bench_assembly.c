/* bench_assembly.c — CPU time of the assembly of Newton's matrix: the terms' gradient and
 * Hessian blocks (sw_eval_terms) and their scatter into the system's values (sw_pattern_fill),
 * against the blocks added straight into the values as Newton assembles (sw_eval_terms_into and
 * sw_pattern_finish), and the memory the blocks and their slot map take.
 *
 *   bench_assembly [--header] SCENE.yaml [reps]
 *
 * Loads the scene, moves its free vertices by up to 1 mm (a fixed pseudo-random field, so that
 * nothing is exactly flat), then assembles `reps` times (default 50).  Prints one CSV line:
 *
 *   scene, dofs, nnz (upper triangle of the system), block_doubles (all terms' Hessian blocks),
 *   block_mib (the blocks, their slot map and the system's values, MiB), eval_ms, fill_ms (CPU
 *   ms per assembly: the terms' evaluation with Hessian, the scatter), peak_rss_mib (VmHWM),
 *   into_ms (CPU ms per assembly straight into the values; the two ways alternate, and give
 *   the same values bit for bit).
 *
 * CPU time of the process (CLOCK_PROCESS_CPUTIME_ID), one BLAS thread: tools/bench_assembly.sh
 * runs two builds interleaved and prints their ratios (docs/performance.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_rss.h"
#include "solver.h"
#include "util.h"

int main(int argc, char **argv) {
  int a = 1;
  if (a < argc && !strcmp(argv[a], "--header")) {
    puts("scene,dofs,nnz,block_doubles,block_mib,eval_ms,fill_ms,peak_rss_mib,into_ms");
    a++;
  }
  if (a >= argc) return a > 1 ? 0 : (fprintf(stderr, "usage: bench_assembly [--header] SCENE [reps]\n"), 2);
  const char *path = argv[a];
  int reps = a + 1 < argc ? atoi(argv[a + 1]) : 50;
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_load(path, err, sizeof err);
  if (!m) return fprintf(stderr, "%s\n", err), 1;
  sw_data *d = sw_data_new(m);
  sw_pattern p;
  if (!d || sw_pattern_build(&p, m, err, sizeof err)) return fprintf(stderr, "set-up failed\n"), 1;
  unsigned long rs = 12345;
  for (int i = 0; i < m->nv * m->dim; i++) {
    rs = rs * 6364136223846793005UL + 1442695040888963407UL;
    if (m->dof[i] >= 0) d->x[i] += 1e-3 * ((double)(rs >> 11) / 9007199254740992.0 - 0.5);
  }
  double *val = calloc((size_t)p.nnz + 1, sizeof *val), e, te = 0.0, tf = 0.0, ti = 0.0;
  double *val2 = calloc((size_t)p.nnz + 1, sizeof *val2);
  if (!val || !val2) return 1;
  for (int r = 0; r < reps; r++) {
    double t0 = sw_cpu_now();
    if (sw_eval_terms(m, d, d->x, 0.0, 1, 1, SW_FILTER_CLAMP, &e))
      return fprintf(stderr, "%s\n", d->err), 1;
    double t1 = sw_cpu_now();
    sw_pattern_fill(&p, m, d, 1e4, 1.0, val);
    double t2 = sw_cpu_now();
    memset(val2, 0, (size_t)p.nnz * sizeof *val2);
    if (sw_eval_terms_into(m, d, d->x, 0.0, 1, SW_FILTER_CLAMP, val2, &p.slots, &e))
      return fprintf(stderr, "%s\n", d->err), 1;
    sw_pattern_finish(&p, m, 1e4, 1.0, val2);
    ti += sw_cpu_now() - t2, tf += t2 - t1, te += t1 - t0;
  }
  if (memcmp(val, val2, (size_t)p.nnz * sizeof *val))
    return fprintf(stderr, "the two assemblies differ\n"), 1;
  long nb = d->hoff[m->nterm];
  double mib = ((double)nb * (sizeof(double) + sizeof(int)) + (double)p.nnz * sizeof(double)) /
               (1024.0 * 1024.0);
  const char *base = strrchr(path, '/');
  printf("%s,%d,%ld,%ld,%.2f,%.4f,%.4f,%.1f,%.4f\n", base ? base + 1 : path, m->ndof, p.nnz, nb,
         mib, 1e3 * te / reps, 1e3 * tf / reps, bench_peak_rss_mib(), 1e3 * ti / reps);
  free(val), free(val2);
  sw_pattern_free(&p);
  sw_data_free(d);
  sw_model_free(m);
  return 0;
}
