/* vtkxml.c — VTK's XML file format, binary (appended, zlib) or ascii (vtkxml.h). */
#include "vtkxml.h"

#include <errno.h>
#include <stdint.h>
#include <string.h>
#include <zlib.h>

#include "util.h"

static const char *const type_name[] = {"Float64", "Int32", "Int64", "UInt8", "Float32"};
static const size_t type_size[] = {8, 4, 8, 1, 4};

static int little_endian(void) {
  const uint16_t one = 1;
  return *(const unsigned char *)&one == 1;
}

void vx_begin(vx_file *x, out_file *w, const char *type) {
  x->w = w;
  x->n = 0;
  x->err = 0;
  const char *order = little_endian() ? "LittleEndian" : "BigEndian";
  out_puts(w, "<?xml version=\"1.0\"?>\n");
  if (x->ascii)
    out_printf(w, "<VTKFile type=\"%s\" version=\"0.1\" byte_order=\"%s\">\n", type, order);
  else
    out_printf(w, "<VTKFile type=\"%s\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\""
                  " compressor=\"vtkZLibDataCompressor\">\n", type, order);
  out_printf(w, "  <%s>\n", type);
}

void vx_puts(vx_file *x, const char *s) { out_puts(x->w, s); }

/* Room for n more bytes in the appended block. */
static unsigned char *reserve(vx_file *x, size_t n) {
  if (x->err) return NULL;
  if (x->n + n > x->cap) {
    size_t cap = x->cap ? x->cap : 1 << 16;
    while (cap < x->n + n) cap *= 2;
    unsigned char *b = sw_realloc(x->buf, cap, 1);
    if (!b) {
      x->err = ENOMEM;
      return NULL;
    }
    x->buf = b, x->cap = cap;
  }
  return x->buf + x->n;
}

/* Append n bytes of src as one compressed array: the UInt64 header, then the blocks. */
static size_t append_compressed(vx_file *x, const unsigned char *src, size_t n) {
  const size_t nb = (n + VX_BLOCK - 1) / VX_BLOCK, start = x->n;
  uint64_t head[3] = {nb, VX_BLOCK, n % VX_BLOCK};
  if (!reserve(x, (3 + nb) * 8)) return start;
  memcpy(x->buf + x->n, head, sizeof head);
  x->n += (3 + nb) * 8;
  for (size_t b = 0; b < nb; b++) {
    size_t len = n - b * VX_BLOCK < VX_BLOCK ? n - b * VX_BLOCK : VX_BLOCK;
    uLongf zn = compressBound((uLong)len);
    if (!reserve(x, zn)) return start;
    if (compress2(x->buf + x->n, &zn, src + b * VX_BLOCK, (uLong)len, x->level) != Z_OK) {
      x->err = EIO;
      return start;
    }
    uint64_t z = zn;
    memcpy(x->buf + start + (3 + b) * 8, &z, 8);
    x->n += zn;
  }
  return start;
}

/* One value of an ascii array, then `after`. */
static void put_value(out_file *w, int type, const void *data, size_t i, const char *after) {
  switch (type) {
  case VX_F64: out_num(w, ((const double *)data)[i], after); break;
  case VX_I32: out_printf(w, "%d%s", ((const int32_t *)data)[i], after); break;
  case VX_I64: out_printf(w, "%lld%s", (long long)((const int64_t *)data)[i], after); break;
  case VX_F32: out_num(w, ((const float *)data)[i], after); break;
  default: out_printf(w, "%u%s", ((const unsigned char *)data)[i], after); break;
  }
}

static void array_tag(vx_file *x, const char *indent, int type, const char *name, int ncomp,
                      const char *extra) {
  out_printf(x->w, "%s<DataArray type=\"%s\" Name=\"%s\"", indent, type_name[type], name);
  if (ncomp > 1) out_printf(x->w, " NumberOfComponents=\"%d\"", ncomp);
  out_printf(x->w, "%s format=\"%s\"", extra, x->ascii ? "ascii" : "appended");
}

static void array_body(vx_file *x, const char *indent, int type, int ncomp, const void *data,
                       size_t ntuple) {
  if (!x->ascii) {
    size_t off = append_compressed(x, data, ntuple * (size_t)ncomp * type_size[type]);
    out_printf(x->w, " offset=\"%zu\"/>\n", off);
    return;
  }
  out_puts(x->w, ">\n");
  for (size_t i = 0; i < ntuple * (size_t)ncomp; i++)
    put_value(x->w, type, data, i, (i + 1) % (size_t)ncomp ? " " : "\n");
  out_printf(x->w, "%s</DataArray>\n", indent);
}

/* n doubles at data as floats (x->f32), or NULL when out of memory. */
static const float *to_single(vx_file *x, const double *data, size_t n) {
  if (n > x->f32cap) {
    float *f = sw_realloc(x->f32, n, sizeof *f);
    if (!f) return x->err = ENOMEM, NULL;
    x->f32 = f, x->f32cap = n;
  }
  for (size_t i = 0; i < n; i++) x->f32[i] = (float)data[i];
  return x->f32;
}

void vx_array(vx_file *x, const char *indent, int type, const char *name, int ncomp,
              const void *data, size_t ntuple) {
  if (type == VX_F64 && x->single && !x->ascii) {
    data = to_single(x, data, ntuple * (size_t)ncomp);
    type = VX_F32;
    if (!data) ntuple = 0; /* reported by vx_end */
  }
  array_tag(x, indent, type, name, ncomp, "");
  array_body(x, indent, type, ncomp, data, ntuple);
}

void vx_time(vx_file *x, const char *indent, double t) {
  out_printf(x->w, "%s<FieldData>\n", indent);
  char in2[32];
  snprintf(in2, sizeof in2, "%s  ", indent);
  array_tag(x, in2, VX_F64, "TimeValue", 1, " NumberOfTuples=\"1\"");
  array_body(x, in2, VX_F64, 1, &t, 1);
  out_printf(x->w, "%s</FieldData>\n", indent);
}

int vx_end(vx_file *x, const char *type, const char *path, char *err, size_t errsz) {
  out_printf(x->w, "  </%s>\n", type);
  if (!x->ascii) {
    out_puts(x->w, "  <AppendedData encoding=\"raw\">\n   _");
    if (!x->w->err && x->n && fwrite(x->buf, 1, x->n, x->w->f) != x->n)
      x->w->err = errno ? errno : EIO;
    out_puts(x->w, "\n  </AppendedData>\n");
  }
  out_puts(x->w, "</VTKFile>\n");
  if (!x->err) return 0;
  sw_errf(err, errsz, "%s: %s", path,
          x->err == ENOMEM ? "out of memory for the frame" : "zlib failed to compress");
  return -1;
}

void vx_free(vx_file *x) {
  sw_free(x->buf);
  sw_free(x->f32);
  x->buf = NULL, x->f32 = NULL;
  x->cap = x->f32cap = 0;
}
