/* bench_rss.h — the peak resident memory of a bench program (bench_step, bench_assembly). */
#ifndef SW_BENCH_RSS_H
#define SW_BENCH_RSS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

/* Peak resident memory of this process, MiB: VmHWM of /proc/self/status.  getrusage's ru_maxrss
 * is the fallback only, because Linux carries it over execve: under `meson test` (a Python
 * parent) it reports the parent's peak, 28 MiB for a run that uses 8. */
static inline double bench_peak_rss_mib(void) {
  FILE *fp = fopen("/proc/self/status", "r");
  char line[256];
  long kib = -1;
  if (fp) {
    while (fgets(line, sizeof line, fp))
      if (!strncmp(line, "VmHWM:", 6)) {
        kib = strtol(line + 6, NULL, 10);
        break;
      }
    fclose(fp);
  }
  if (kib < 0) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    kib = ru.ru_maxrss;
  }
  return (double)kib / 1024.0;
}

#endif
