/* scene_dde.c — a fabric in the format of Wang, Ramamoorthi and O'Brien's data set ("Data-Driven
 * Elastic Models for Cloth: Modeling and Measurement", SIGGRAPH 2011), as ARCSim distributes it
 * (its materials folder; docs/fabrics.md):
 *   {"density": kg/m^2 > 0,
 *    "stretching": 6 rows of 4 numbers (c11, c12, c22, c33, N/m): the zero-strain row, then the
 *                  rows at a principal stretch of 7/6 along 0, 22.5, 45, 67.5, 90 degrees,
 *    "bending": 3 rows (hinge at 0, 45, 90 degrees) of 5 stiffnesses >= 0 (N m; the rigidity is
 *               a quarter of them, models/dde.c) at 0, 5, 10, 15, 20 1/m of half the curvature}
 * (JSON is YAML 1.2, so the scene's parser reads it with every node's line and column).  A
 * negative stretching sample (the data set has them: fitted values of a stiffness that was
 * hardly measured) is clamped at 0, as ARCSim does, and counted in sw_dde.nclamped. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_fabric.h"

#define SC_DDE_MAX_BYTES (1 << 20) /* a data file's byte limit (the data set's are 0.7 KB) */

static const char *const dde_keys[] = {"density", "stretching", "bending"};

/* rows x cols numbers >= lo at y into out. */
static int table(const ctx *c, const ynode *y, const char *what, int rows, int cols, double lo,
                 const char *unit, const char *rowsmean, double *out) {
  char exp[240], lab[64];
  snprintf(exp, sizeof exp, "%d rows of %d numbers (%s): %s", rows, cols, unit, rowsmean);
  if (sy_seq(c, y, what, exp)) return -1;
  if (y->n != rows) return sy_fail(c, y, "%s has %d rows; expected %s", what, y->n, exp);
  for (int i = 0; i < rows; i++) {
    snprintf(lab, sizeof lab, "%s[%d]", what, i);
    const ynode *r = y->kid[i];
    if (r->kind == Y_SEQ && r->n != cols)
      return sy_fail(c, r, "%s has %d numbers; expected %d (%s)", lab, r->n, cols, unit);
    if (sy_vec(c, r, lab, cols, lo, 0, unit, out + cols * i)) return -1;
  }
  return 0;
}

static int dde_load(const ctx *c, const ynode *root, sw_dde *dd) {
  const ynode *v[3];
  if (sy_map(c, root, "fabric data", dde_keys, 3, v)) return -1;
  for (int k = 0; k < 3; k++)
    if (!v[k])
      return sy_fail(c, root, "fabric data has no '%s' key; expected density, stretching and "
                     "bending", dde_keys[k]);
  memset(dd, 0, sizeof *dd);
  if (sy_num(c, v[0], "density", 0, 1, "kg/m^2", &dd->density) ||
      table(c, v[1], "stretching", 6, 4, -HUGE_VAL, "c11, c12, c22, c33 in N/m",
            "the zero-strain row, then 0, 22.5, 45, 67.5 and 90 degrees from warp",
            &dd->stretch[0][0]) ||
      table(c, v[2], "bending", 3, 5, 0, "N m at half-curvatures 0, 5, 10, 15, 20 1/m",
            "the hinge at 0, 45 and 90 degrees from warp", &dd->bend[0][0]))
    return -1;
  for (int i = 0; i < 6; i++)
    for (int l = 0; l < 4; l++)
      if (dd->stretch[i][l] < 0.0) dd->stretch[i][l] = 0.0, dd->nclamped++;
  return 0;
}

int sc_dde_parse(const char *name, const char *buf, size_t len, sw_dde *dd, char *err,
                 size_t errsz) {
  ynode *root = sy_parse(name, buf, len, err, errsz);
  if (!root) return -1;
  ctx c = {.name = name, .err = err, .errsz = errsz, .root = root};
  int rc = dde_load(&c, root, dd);
  sy_free(root);
  return rc;
}

int sc_dde_read(const char *path, sw_dde *dd, char *err, size_t errsz) {
  FILE *f = fopen(path, "rb");
  if (!f) return sw_errf(err, errsz, "%s cannot be opened; expected a fabric data file", path), -1;
  char *buf = NULL;
  size_t len = 0, cap = 0, n;
  char chunk[4096];
  while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) {
    if (len + n > SC_DDE_MAX_BYTES)
      return sw_free(buf), fclose(f),
             sw_errf(err, errsz, "%s is over %d bytes; expected a fabric data file (under 1 KB "
                     "in the data set)", path, SC_DDE_MAX_BYTES), -1;
    if (len + n > cap) {
      char *nb = sw_realloc(buf, cap = 2 * (len + n), 1);
      if (!nb) return sw_free(buf), fclose(f), sw_errf(err, errsz, "out of memory"), -1;
      buf = nb;
    }
    memcpy(buf + len, chunk, n), len += n;
  }
  fclose(f);
  int rc = sc_dde_parse(path, buf ? buf : "", len, dd, err, errsz);
  sw_free(buf);
  return rc;
}

const sc_fabric_preset *sc_fabric_preset_find(const char *name) {
  for (int k = 0; k < sc_nfabric_presets; k++)
    if (!strcmp(sc_fabric_presets[k].name, name)) return &sc_fabric_presets[k];
  return NULL;
}
