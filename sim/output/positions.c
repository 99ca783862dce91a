/* positions.c — positions.bin (writer.h): with opt.positions_every > 0, every vertex position at
 * the sampled times, binary.  A 16-byte header "SWPOS001", int32 nv, int32 dim; then per record
 * float64 t (s) and nv x dim float64 positions (m); host byte order.  A log (file.c):
 * positions.bin.part until the run closes, a record in one write(2) (a record of many pages may
 * still be cut by a kill: readers take whole records). */
#include <stdint.h>
#include <string.h>

#include "util.h"
#include "writer.h"

#define POS_MAGIC "SWPOS001" /* 8 bytes of magic, then int32 nv, int32 dim */
#define POS_HEADER 16        /* bytes */

typedef struct positions {
  out_log log; /* first: the log operations of file.c take the state as an out_log */
  double *rec; /* (1 + nv x dim) one record: t (s), x (m); reused, a step allocates nothing */
  size_t recn; /* doubles in rec */
} positions;

static int pos_wanted(const sw_model *m) { return m->opt.positions_every > 0; }

static int pos_init(void *self, const sw_model *m) {
  positions *o = self;
  o->log.fd = -1;
  o->recn = 1 + (size_t)m->nv * (size_t)m->dim;
  o->rec = sw_calloc(o->recn, sizeof *o->rec);
  return o->rec ? 0 : -1;
}

/* The header: magic, int32 nv, int32 dim (host byte order). */
static int pos_open(void *self, sw_output *out, const sw_model *m, char *err, size_t errsz) {
  positions *o = self;
  char h[POS_HEADER];
  int32_t nv = m->nv, dim = m->dim;
  memcpy(h, POS_MAGIC, 8);
  memcpy(h + 8, &nv, 4);
  memcpy(h + 12, &dim, 4);
  return out_log_open(&o->log, "positions.bin", out, h, sizeof h, err, errsz);
}

/* One record: t and every vertex position, in one write. */
static int pos_write(void *self, sw_output *out, const sw_model *m, const sw_data *d, char *err,
                     size_t errsz) {
  positions *o = self;
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  if (o->recn != 1 + nd) { /* cannot happen: rec is sized at open for this model */
    sw_errf(err, errsz, "output: positions.bin record of %zu values; expected %zu", o->recn,
            1 + nd);
    return -1;
  }
  o->rec[0] = d->t;                            /* s */
  memcpy(o->rec + 1, d->x, nd * sizeof *d->x); /* m */
  return out_log_put(&o->log, out, (const char *)o->rec, o->recn * sizeof *o->rec, err, errsz);
}

static void pos_free(void *self) {
  positions *o = self;
  out_log_free(&o->log);
  sw_free(o->rec);
}

const sw_out_ops sw_out_positions = {
    .name = "positions.bin",
    .event = SW_OUT_POSITIONS,
    .size = sizeof(positions),
    .wanted = pos_wanted,
    .init = pos_init,
    .open = pos_open,
    .write = pos_write,
    .undo = out_log_undo,
    .close = out_log_close,
    .files = out_log_files,
    .io = out_log_io,
    .free = pos_free,
};
