/* fuzz_targets.c — libFuzzer harness for the targets CSV reader of `sinew inverse`
 * (sim/input/targets.c, via sw_targets_read) on a fixed 2D model of 4 x 3 vertices with one pin.
 * Run:  ./fuzz_targets -max_total_time=180 CORPUS_DIR  (tools/fuzz.sh builds and runs it)
 * Each input is written to a file in $TMPDIR (the reader takes a path).  Besides ASan/UBSan
 * findings, an accepted file that breaks an invariant aborts: distinct free vertices in range,
 * finite forces, at least one target; every error names the file. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene.h"
#include "sinew.h"
#include "util.h"

static const char SCENE[] =
    "dimension: 2\n"
    "mesh: {grid: {size: [0.3, 0.2], vertices: [4, 3]}}\n"
    "material: {density: 0.1, membrane: {model: bw98, k_u: 100, k_v: 100, k_shear: 10}}\n"
    "pins: [{select: {vertices: [0]}}]\n"
    "tendons: [{waypoints: [1, 5, 9], law: cable, stiffness: 100}]\n";

static sw_model *model(void) {
  static sw_model *m;
  char err[SW_ERRSZ];
  if (!m && !(m = sw_scene_parse("fuzz.yaml", SCENE, sizeof SCENE - 1, err, sizeof err))) {
    fprintf(stderr, "fuzz_targets: the fixed scene: %s\n", err);
    abort();
  }
  return m;
}

static void check(const sw_model *m, const sw_targets *tg) {
  if (tg->n < 1 || tg->n > m->nv || tg->dim != m->dim) abort();
  for (int k = 0; k < tg->n; k++) {
    int v = tg->vertex[k];
    if (v < 0 || v >= m->nv || m->pinned[v]) abort();
    for (int j = 0; j < k; j++)
      if (tg->vertex[j] == v) abort();
    for (int a = 0; a < tg->dim; a++)
      if (!isfinite(tg->f[k * tg->dim + a])) abort();
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static char path[64];
  if (!path[0]) snprintf(path, sizeof path, "/tmp/fuzz_targets_%ld.csv", (long)getpid());
  const sw_model *m = model();
  FILE *fp = fopen(path, "wb");
  if (!fp) abort();
  if (size && fwrite(data, 1, size, fp) != size) abort();
  fclose(fp);
  sw_targets tg;
  char err[SW_ERRSZ] = "";
  if (sw_targets_read(path, m, &tg, err, sizeof err) == 0) {
    check(m, &tg);
    sw_targets_free(&tg);
  } else if (strncmp(err, path, strlen(path)) != 0) {
    abort(); /* every error names the file */
  }
  return 0;
}
