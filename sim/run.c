/* run.c — a whole run: the stepping API (sim.c) from t = 0 to the scene's duration, writing the
 * run folder.  A run that cannot go on stops with a message naming the time, the method and the
 * reason, keeps its logs, writes the last good state as a frame and a summary.json with status
 * "failed".  And the thread settings of the linear algebra. */
#define _GNU_SOURCE /* dlsym(RTLD_DEFAULT) */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "output.h"
#include "solver.h"
#include "util.h"

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

/* The scene to its duration through the stepping API, writing the run folder.  sw_run leaves m
 * as it was: the sim changes its model only through the sw_sim_set_* calls, which it makes
 * none of, and for the fit stage's length (its damping, Newton tolerance and gravity ramp,
 * restored when it ends, sim.c). */
static int run_to_end(const sw_model *m, int progress, int resume, char *err, size_t errsz) {
  int flags = SW_SIM_OUTPUT | (progress ? SW_SIM_PROGRESS : 0) | (resume > 1 ? SW_SIM_FORCE : 0);
  int start = SW_OK;
  sw_sim *s = resume ? sw_sim_resume((sw_model *)m, flags, &start, err, errsz)
                     : sw_sim_start((sw_model *)m, flags, &start, err, errsz);
  if (!s) return start;
  /* the duration counts from the end of the fit stage (0 without one) */
  int rc = sw_sim_run(s, sw_sim_data(s)->fit_end + m->opt.duration, err, errsz);
  char cerr[SW_ERRSZ];
  int crc = sw_sim_close(s, cerr, sizeof cerr);
  if (!rc && crc) sw_errf(err, errsz, "%s", cerr), rc = SW_FATAL;
  sw_sim_free(s);
  return rc;
}

int sw_run(const sw_model *m, int progress, char *err, size_t errsz) {
  return run_to_end(m, progress, 0, err, errsz);
}

int sw_resume(const sw_model *m, int progress, char *err, size_t errsz) {
  return run_to_end(m, progress, 1, err, errsz);
}

int sw_resume_ex(const sw_model *m, int progress, int force, char *err, size_t errsz) {
  return run_to_end(m, progress, force ? 2 : 1, err, errsz);
}
