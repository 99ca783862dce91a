/* threads.c — the thread settings of the linear algebra (sw_set_threads, sinew.h), which the
 * run loop (sim.c) applies at a sim's start. */
#define _GNU_SOURCE /* dlsym(RTLD_DEFAULT), RTLD_NEXT */
#include <dlfcn.h>
#include <stdlib.h>

#include "sinew.h"

void openblas_set_num_threads(int num_threads); /* OpenBLAS' cblas.h */

/* Whether the user asked for OpenMP threads (then libgomp runs CHOLMOD's regions as it will);
 * looked up once. */
static int omp_wanted(void) {
  static int wanted = -1;
  if (wanted < 0) wanted = getenv("OMP_MAX_ACTIVE_LEVELS") || getenv("OMP_THREAD_LIMIT");
  return wanted;
}

/* CHOLMOD's OpenMP regions (the only OpenMP entry point it calls, with omp_get_num_threads and
 * omp_get_thread_num: plain `parallel for` loops with a static schedule), run here on the
 * calling thread unless the user asked for OpenMP threads.  With nested parallelism off
 * (below) libgomp runs each region on one thread too, but its team's start and end make a
 * futex system call every time: about 16 000 per factorisation of the 80 x 80 cloth, a third
 * of that factorisation's time (docs/performance.md, "CHOLMOD's OpenMP regions without
 * libgomp").  Called outside any team, the loop body sees one thread, thread 0, and does every
 * iteration: the same arithmetic in the same order.  This definition comes before libgomp's
 * in the dynamic linker's search from libcholmod (libsinew, or a program linking sinew's
 * objects, loads it); where another object's libgomp is found first, libgomp's runs, and only
 * the speed differs. */
void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags)
    __attribute__((visibility("default")));
void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags) {
  static void (*next)(void (*)(void *), void *, unsigned, unsigned);
  if (omp_wanted() && !next) *(void **)&next = dlsym(RTLD_NEXT, "GOMP_parallel");
  if (omp_wanted() && next) next(fn, data, num_threads, flags);
  else fn(data);
}

/* OpenBLAS' pthreads build starts its worker threads as it is loaded (one on 2 cores), and a
 * worker with no work spins on sched_yield for its timeout (2^28 clock ticks, about 0.1 s here)
 * before it sleeps: 0.1 s of CPU for every process, 5 % of a garment's run.  With one BLAS
 * thread they never get work, so they are stopped (blas_thread_shutdown_, OpenBLAS'
 * driver/others/blas_server.c); a later request for more threads starts them again (its
 * exec_blas re-creates the pool).  Looked up at run time: absent from the OpenMP and serial
 * builds of OpenBLAS and from other BLAS, which have no such threads. */
static void idle_blas_workers_stop(void) {
  int (*shutdown)(void);
  *(void **)&shutdown = dlsym(RTLD_DEFAULT, "blas_thread_shutdown_");
  if (shutdown) (void)shutdown();
}

/* Threads (docs/performance.md).  Debian's CHOLMOD runs small loops of its factorisation on 4
 * OpenMP threads, compiled in; on 2 cores they fight and a step got 2.3x slower, so nested
 * OpenMP parallelism is switched off unless the user sets OMP_MAX_ACTIVE_LEVELS or
 * OMP_THREAD_LIMIT (looked up at run time: no dependency on libgomp, nothing if it is absent).
 * Then one BLAS thread unless asked: with the OpenMP fix two threads gave no gain per
 * factorisation at 77k DOFs for twice the CPU, and were slower on small systems. */
void sw_set_threads(int blas_threads) {
  if (!omp_wanted()) {
    void (*set_levels)(int);
    *(void **)&set_levels = dlsym(RTLD_DEFAULT, "omp_set_max_active_levels");
    if (set_levels) set_levels(0);
  }
  int one = blas_threads == 1 || (blas_threads <= 0 && !getenv("OPENBLAS_NUM_THREADS"));
  if (blas_threads > 0) openblas_set_num_threads(blas_threads);
  else if (one) openblas_set_num_threads(1);
  if (one) idle_blas_workers_stop();
}
