/* fuzz_obj.c — libFuzzer harness for the OBJ reader (sim/input/obj.c, via sw_obj_parse).
 *
 * Build (from the repository root):
 *   clang -std=c11 -D_POSIX_C_SOURCE=200809L -g -O1 -fsanitize=fuzzer,address,undefined \
 *     -Isim -Isim/input tests/fuzz/fuzz_obj.c sim/input/obj.c sim/input/mesh.c sim/util.c -lm -o fuzz_obj
 * Run:  ./fuzz_obj -max_total_time=180 CORPUS_DIR
 * Any crash input goes to tests/fuzz/regress/obj/ (test_mesh reads every file there).
 * Besides ASan/UBSan findings, an accepted mesh that breaks an invariant aborts.
 * With -DSW_FUZZ_ALLOC the first input byte b makes allocation number b+1 fail (b < 64), to
 * fuzz the out-of-memory paths for leaks. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "obj.h"
#include "sinew.h"
#include "util.h"

static void check_mesh(const sw_mesh *m) {
  if (m->nv <= 0 || m->nf <= 0 || m->ngroup < 1 || !m->x || !m->f || !m->fgroup || !m->group)
    abort();
  if ((m->nuv == 0) != (m->fuv == NULL) || (m->nuv == 0) != (m->uv == NULL)) abort();
  if (strcmp(m->group[0], "default") != 0) abort();
  for (int g = 0; g < m->ngroup; g++)
    if (!memchr(m->group[g], '\0', SW_NAMESZ)) abort();
  for (int t = 0; t < m->nf; t++) {
    const int *f = m->f + 3 * t;
    for (int k = 0; k < 3; k++) {
      if (f[k] < 0 || f[k] >= m->nv) abort();
      if (m->fuv && (m->fuv[3 * t + k] < 0 || m->fuv[3 * t + k] >= m->nuv)) abort();
    }
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) abort();
    if (m->fgroup[t] < 0 || m->fgroup[t] >= m->ngroup) abort();
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char err[SW_ERRSZ];
  sw_mesh m;
  err[0] = '\0';
#ifdef SW_FUZZ_ALLOC
  if (size == 0) return 0;
  sw_alloc_fail_after(data[0] < 64 ? data[0] + 1 : 0);
  data++;
  size--;
#endif
  int rc = sw_obj_parse("fuzz.obj", (const char *)data, size, &m, err, sizeof err);
  sw_alloc_fail_after(0);
  if (rc == 0)
    check_mesh(&m);
  else if (strncmp(err, "fuzz.obj", 8) != 0)
    abort(); /* every error names the file */
  sw_mesh_free(&m);
  return 0;
}
