/* fuzz_scene.c — libFuzzer harness for the scene loader (sim/input/scene.c, via sw_scene_parse).
 *
 * Build (from the repository root; the lower vertex cap keeps every input fast):
 *   clang -std=c11 -D_POSIX_C_SOURCE=200809L -DSW_SCENE_MAX_VERTICES=20000 -g -O1 \
 *     -fsanitize=fuzzer,address,undefined -Isim -Imodels -Isolvers -I/usr/include/suitesparse \
 *     tests/fuzz/fuzz_scene.c $(find sim models solvers -name '*.c' ! -name main.c) \
 *     $(pkg-config --cflags --libs libfyaml) -lcholmod -lsundials_cvode -lsundials_ida \
 *     -lsundials_nvecserial -lopenblas -llapack -lm -o fuzz_scene
 * Run:  ./fuzz_scene -max_len=4096 -max_total_time=600 CORPUS_DIR   (seed it with scenes/)
 * Any crash input goes to tests/fuzz/regress/scene/ (test_scene reads every file there).
 * Besides ASan/UBSan findings, an accepted model that breaks an invariant, or an error message
 * that does not start with the file name, aborts.  OBJ paths resolve under "fuzz/".
 * With -DSW_FUZZ_ALLOC the first input byte b makes allocation number b+1 fail (b < 64), to
 * fuzz the out-of-memory paths for leaks. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"
#include "sinew.h"
#include "util.h"

#define NAME "fuzz/scene.yaml"

static void check_model(const sw_model *m) {
  if ((m->dim != 2 && m->dim != 3) || m->nv <= 0 || m->nf < 0) abort();
  if (!m->x0 || !m->v0 || !m->pinned || !memchr(m->name, '\0', sizeof m->name)) abort();
  for (long k = 0; k < (long)m->nv * m->dim; k++)
    if (!isfinite(m->x0[k]) || !isfinite(m->v0[k])) abort();
  for (int i = 0; i < m->nv; i++)
    if (m->pinned[i] > 1) abort();
  const sw_options *o = &m->opt;
  if (!(o->dt > 0) || !(o->duration >= 0) || !(o->frames_every >= 0) || !(o->positions_every >= 0) || o->newton_max < 1 ||
      !(o->newton_tol > 0) || !(o->newton_force_tol > 0 && o->newton_force_tol < 1) ||
      o->max_halvings < 0 || o->max_halvings > 60 || !o->method[0] ||
      !o->out_dir[0] || !(o->tx_clip > 0))
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char err[SW_ERRSZ];
  err[0] = '\0';
#ifdef SW_FUZZ_ALLOC
  if (size == 0) return 0;
  if (data[0] < 64) sw_alloc_fail_after((long)data[0] + 1);
  data++, size--;
#endif
  sw_model *m = sw_scene_parse(NAME, (const char *)data, size, err, sizeof err);
#ifdef SW_FUZZ_ALLOC
  sw_alloc_fail_after(0);
#endif
  if (m) check_model(m);
  else if (strncmp(err, NAME ":", sizeof NAME)) abort();
  sw_model_free(m);
  return 0;
}
