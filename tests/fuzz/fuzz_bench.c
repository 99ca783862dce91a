/* fuzz_bench.c — libFuzzer harness of `sinew bench`'s readers (sim/cli/bench_read.c, the plan
 * reader of sim/cli/bench.c): the input, split at lines "@@@", becomes a run folder's summary.json,
 * tension.csv, energy.csv, tendons.csv, positions.bin and logs/ID.exit, and a bench folder's
 * bench_work_precision.cfg and plan_work_precision.csv; reading them must not crash, leak or
 * read out of bounds, whatever they hold. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench.h"

static const char *const parts[] = {"runs/fz/summary.json", "runs/fz/tension.csv",
                                    "runs/fz/energy.csv",   "runs/fz/tendons.csv",
                                    "runs/fz/positions.bin", "logs/fz.exit",
                                    "bench_work_precision.cfg", "plan_work_precision.csv"};
enum { NPART = sizeof parts / sizeof *parts };

static char dir[64];

static void put(int k, const uint8_t *p, size_t n) {
  char path[160];
  snprintf(path, sizeof path, "%s/%s", dir, parts[k]);
  FILE *f = fopen(path, "wb");
  if (!f) return;
  if (n) fwrite(p, 1, n, f);
  fclose(f);
}

/* Split the input at "\n@@@\n" into the files (missing parts: no file). */
static void write_parts(const uint8_t *data, size_t size) {
  char path[160];
  for (int k = 0; k < NPART; k++) snprintf(path, sizeof path, "%s/%s", dir, parts[k]), unlink(path);
  const uint8_t *p = data, *end = data + size;
  for (int k = 0; k < NPART && p <= end; k++) {
    const uint8_t *q = p;
    while (q + 5 <= end && memcmp(q, "\n@@@\n", 5)) q++;
    if (q + 5 > end) q = end;
    put(k, p, (size_t)(q - p));
    p = q + 5;
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (!dir[0]) {
    snprintf(dir, sizeof dir, "/tmp/sinew_fuzz_bench_%d", (int)getpid());
    char sub[100];
    mkdir(dir, 0777);
    snprintf(sub, sizeof sub, "%s/runs", dir), mkdir(sub, 0777);
    snprintf(sub, sizeof sub, "%s/runs/fz", dir), mkdir(sub, 0777);
    snprintf(sub, sizeof sub, "%s/logs", dir), mkdir(sub, 0777);
  }
  write_parts(data, size);
  bench_cfg c = {.mode = BM_WORK, .duration = 0.05, .sample = 0.01, .size = 1.0};
  snprintf(c.dir, sizeof c.dir, "%s", dir);
  bench_job j = {.id = "fz", .role = BR_RUN, .method = "bdf2", .dt = 0.01, .scale = 1, .rep = 1};
  bench_result r;
  bench_read(&c, &j, 1, &r);
  bench_result_free(&r);
  bench_plan p;
  char err[256];
  bench_plan_read(dir, BM_WORK, &p, err, sizeof err);
  free(p.job);
  return 0;
}
