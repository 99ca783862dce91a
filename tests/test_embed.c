/* test_embed.c — a client of the installed library: only the public header (included first,
 * so it must compile alone) and only exported symbols (linked against the shared libsinew). */
#include "sinew.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(void) {
  char err[SW_ERRSZ], dir[] = "/tmp/sinew_embed_XXXXXX";
  if (!mkdtemp(dir)) return perror("mkdtemp"), 1;
  sw_model *m = sw_scene_load("scenes/hanging_cloth.yaml", err, sizeof err);
  if (!m) return fprintf(stderr, "load: %s\n", err), 1;
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "%s/run", dir);
  m->opt.duration = 0.02;
  int rc = sw_run(m, 0, err, sizeof err);
  if (rc) fprintf(stderr, "run: %s\n", err);
  sw_data *d = sw_data_new(m);
  double ke = sw_kinetic(m, d->v);
  sw_data_free(d);
  sw_model_free(m);
  char cmd[256];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd)) return 1;
  return rc || ke != 0.0;
}
