/* fabric_table.c — the table of docs/fabrics.md ("Presets"): what each measured fabric's
 * numbers mean for a user, computed by sinew's own model (models/dde.c) from the shipped data.
 *   build/tools/fabric_table              print the table (Markdown)
 *   build/tools/fabric_table --check F    exit 1 unless every row is in file F (a test)
 * Columns: mass per area; the rigidities B of strips cut along warp, weft and at 45 degrees
 * (the data's small-curvature column) and their cantilever bending lengths c = (B / (rho g))^(1/3)
 * (Peirce 1930; ASTM D1388); the stretch of a strip pulled by 10 N/m along warp and along weft
 * (free across); the negative samples clamped. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dde.h"
#include "scene_fabric.h"

#define G_STANDARD 9.80665 /* m/s^2 */

static int row(const sc_fabric_preset *p, char *out, size_t sz) {
  char err[SW_ERRSZ];
  sw_dde dd;
  if (sc_dde_parse(p->file, p->json, strlen(p->json), &dd, err, sizeof err))
    return fprintf(stderr, "%s\n", err), -1;
  double kb[3], c[3], w[2];
  sc_dde_strips(&dd, kb);
  for (int i = 0; i < 3; i++) c[i] = cbrt(kb[i] / (dd.density * G_STANDARD)) * 100.0; /* cm */
  for (int i = 0; i < 2; i++)
    if (sw_dde_uniaxial(&dd, i, 10.0, &w[i])) return fprintf(stderr, "%s: no stretch\n", p->name), -1;
  snprintf(out, sz, "| `%s` | %.0f | %.1f / %.1f / %.1f | %.2f / %.2f / %.2f | %.1f / %.1f | %d |",
           p->name, dd.density * 1e3, kb[0] * 1e6, kb[1] * 1e6, kb[2] * 1e6, c[0], c[1], c[2],
           (w[0] - 1.0) * 100.0, (w[1] - 1.0) * 100.0, dd.nclamped);
  return 0;
}

int main(int argc, char **argv) {
  char *doc = NULL;
  if (argc == 3 && !strcmp(argv[1], "--check")) {
    FILE *f = fopen(argv[2], "rb");
    if (!f) return fprintf(stderr, "%s cannot be opened\n", argv[2]), 2;
    doc = calloc(1 << 20, 1);
    if (!doc) return fclose(f), 2;
    fread(doc, 1, (1 << 20) - 1, f);
    fclose(f);
  } else if (argc != 1) {
    return fprintf(stderr, "usage: fabric_table [--check FILE]\n"), 2;
  }
  int bad = 0;
  for (int k = 0; k < sc_nfabric_presets; k++) {
    char line[512];
    if (row(&sc_fabric_presets[k], line, sizeof line)) return 2;
    if (!doc) puts(line);
    else if (!strstr(doc, line)) fprintf(stderr, "not in %s: %s\n", argv[2], line), bad = 1;
  }
  free(doc);
  return bad;
}
