/* seams_json.c — seams.json (writer.h): the seams of a scene with seams, written once when the
 * run folder opens, for drawing them on the pattern and on the garment (docs/garments.md):
 *
 *   {"stiffness": N/m^2, "ramp": s,
 *    "seams": [{"name": ..., "panels": [a, b], "length": [m, m],
 *               "curves": [[v, ...], [v, ...]],
 *               "pairs": [[a, b0, b1, w, l], ...]}, ...]}
 *
 * panels: the OBJ group (panel) name of each curve; curves: the
 * 0-based vertex indices of each curve in order, from its `from` to its `to`; pairs: each
 * vertex a of either curve, the edge (b0, b1) of the other that holds its partner point
 * (1 - w) x_b0 + w x_b1, and the seam length l (m) the pair stands for. */
#include <stdio.h>
#include <string.h>

#include "util.h"
#include "writer.h"

static int seam_defs_wanted(const sw_model *m) { return m->nseam > 0; }

static void write_seam(out_file *w, const sw_seam *sm) {
  out_puts(w, "{\"name\": ");
  out_json_str(w, sm->name, SW_NAMESZ);
  out_puts(w, ", \"panels\": [");
  for (int k = 0; k < 2; k++) {
    out_json_str(w, sm->group[k], SW_NAMESZ);
    out_puts(w, k ? "], \"length\": [" : ", ");
  }
  out_num(w, sm->length[0], ", ");
  out_num(w, sm->length[1], "],\n    \"curves\": [");
  for (int k = 0; k < 2; k++) {
    out_puts(w, "[");
    for (int i = 0; i < sm->n[k]; i++) out_printf(w, "%s%d", i ? ", " : "", sm->curve[k][i]);
    out_puts(w, k ? "]],\n    \"pairs\": [" : "], ");
  }
  for (int p = 0; p < sm->npair; p++) {
    const int *q = sm->pair + 3 * p;
    out_printf(w, "%s[%d, %d, %d, ", p ? ", " : "", q[0], q[1], q[2]);
    out_num(w, sm->w[p], ", ");
    out_num(w, sm->len[p], "]");
  }
  out_puts(w, "]}");
}

static int seam_defs_open(void *self, sw_output *o, const sw_model *m, char *err, size_t errsz) {
  (void)self;
  if (o->resume) return 0; /* written when the run began */
  if (out_own(o, "seams.json", err, errsz) || out_join(o->tmp, o->dir, "seams.json.tmp", err, errsz) ||
      out_join(o->path, o->dir, "seams.json", err, errsz))
    return -1;
  out_file w;
  if (out_tmp_open(&w, o->tmp, err, errsz)) return -1;
  out_puts(&w, "{\"stiffness\": ");
  out_num(&w, m->seam_stiffness, ", \"ramp\": ");
  out_num(&w, m->seam_ramp, ",\n \"seams\": [\n  ");
  for (int j = 0; j < m->nseam; j++) {
    if (j) out_puts(&w, ",\n  ");
    write_seam(&w, &m->seam[j]);
  }
  out_puts(&w, "]}\n");
  return out_tmp_commit(&w, o->tmp, o->path, err, errsz);
}

static void seam_defs_files(const void *self, void (*add)(void *ctx, const char *name),
                            void *ctx) {
  (void)self;
  add(ctx, "seams.json");
}

const sw_out_ops sw_out_seam_defs = {.name = "seams.json", .event = SW_OUT_STATUS,
                                     .wanted = seam_defs_wanted, .open = seam_defs_open,
                                     .files = seam_defs_files};
