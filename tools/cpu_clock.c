/* cpu_clock.c — an LD_PRELOAD shim for benchmarks on a shared machine: the monotonic clock reads
 * the process's CPU time instead, so that every timer sinew writes to summary.json (terms,
 * factorisations, CCD, wall_time_s itself) counts the CPU seconds the process used and not the
 * time it waited for a core.  Built and used by tools/bench_contact_compare.sh:
 *   cc -O2 -shared -fPIC tools/cpu_clock.c -o cpu_clock.so -ldl
 *   LD_PRELOAD=./cpu_clock.so sinew run ... */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <time.h>

int clock_gettime(clockid_t id, struct timespec *ts) {
  static int (*real)(clockid_t, struct timespec *);
  if (!real) real = (int (*)(clockid_t, struct timespec *))dlsym(RTLD_NEXT, "clock_gettime");
  return real(id == CLOCK_MONOTONIC ? CLOCK_PROCESS_CPUTIME_ID : id, ts);
}
