/* threads.c — the thread settings of the linear algebra (sw_set_threads, sinew.h), which the
 * run loop (sim.c) applies at a sim's start. */
#define _GNU_SOURCE /* dlsym(RTLD_DEFAULT) */
#include <dlfcn.h>
#include <stdlib.h>

#include "sinew.h"

void openblas_set_num_threads(int num_threads); /* OpenBLAS' cblas.h */

/* Threads (docs/performance.md).  Debian's CHOLMOD runs small loops of its factorisation on 4
 * OpenMP threads, compiled in; on 2 cores they fight and a step got 2.3x slower, so nested
 * OpenMP parallelism is switched off unless the user sets OMP_MAX_ACTIVE_LEVELS or
 * OMP_THREAD_LIMIT (looked up at run time: no dependency on libgomp, nothing if it is absent).
 * Then one BLAS thread unless asked: with the OpenMP fix two threads gave no gain per
 * factorisation at 77k DOFs for twice the CPU, and were slower on small systems. */
void sw_set_threads(int blas_threads) {
  if (!getenv("OMP_MAX_ACTIVE_LEVELS") && !getenv("OMP_THREAD_LIMIT")) {
    void (*set_levels)(int);
    *(void **)&set_levels = dlsym(RTLD_DEFAULT, "omp_set_max_active_levels");
    if (set_levels) set_levels(0);
  }
  if (blas_threads > 0) openblas_set_num_threads(blas_threads);
  else if (!getenv("OPENBLAS_NUM_THREADS")) openblas_set_num_threads(1);
}
