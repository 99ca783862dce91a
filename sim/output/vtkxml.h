/* vtkxml.h — internal to sim/output/: VTK's XML file format (Kitware, "VTK File Formats",
 * the XML section) as vtu.c writes it, in one of two encodings:
 *
 *   binary: every DataArray is format="appended"; its bytes go zlib-compressed into one raw
 *           <AppendedData encoding="raw"> block after the XML, as ParaView writes by default
 *           (compressor="vtkZLibDataCompressor", header_type="UInt64": each array is a header
 *           of UInt64 [number of blocks, block size, size of the last partial block (0: none),
 *           compressed size of each block] and then the compressed blocks, each block at most
 *           VX_BLOCK bytes before compression; offset= counts bytes after the '_' marker),
 *           every real at full precision (Float64) or, with `single`, as Float32;
 *   ascii:  every DataArray is written inline, one tuple per line (numbers that read back
 *           exactly, out_fmt_num).
 *
 * A file is begun (vx_begin), its arrays and tags written in document order (vx_array,
 * vx_puts), and ended (vx_end), which writes the appended block.  Arrays are buffered until
 * vx_end in the binary encoding (their offsets must precede their bytes). */
#ifndef SW_OUTPUT_VTKXML_H
#define SW_OUTPUT_VTKXML_H

#include <stddef.h>

#include "writer.h"

#define VX_BLOCK 32768 /* bytes of one block before compression (VTK's default) */

enum { VX_F64, VX_I32, VX_I64, VX_U8, VX_F32 }; /* Float64, Int32, Int64, UInt8, Float32 */

typedef struct vx_file {
  out_file *w;          /* the file */
  int ascii;            /* 1: inline ascii arrays; 0: appended, zlib */
  int level;            /* zlib compression level (1..9) */
  int single;           /* 1: Float64 arrays are written as Float32 (binary; not TimeValue) */
  float *f32;           /* conversion scratch */
  size_t f32cap;
  unsigned char *buf;   /* the appended block so far (binary) */
  size_t n, cap;        /* its bytes, its capacity */
  int err;              /* ENOMEM, or EIO for a zlib failure: reported by vx_end */
} vx_file;

/* Start a VTKFile of `type` (UnstructuredGrid, PolyData) on w; x keeps its buffers from an
 * earlier file (zero it before the first). */
void vx_begin(vx_file *x, out_file *w, const char *type);
/* Write s to the XML (indentation and tags). */
void vx_puts(vx_file *x, const char *s);
/* One DataArray of ntuple tuples of ncomp components of the given VX_* type at data, named
 * name, indented by indent. */
void vx_array(vx_file *x, const char *indent, int type, const char *name, int ncomp,
              const void *data, size_t ntuple);
/* The FieldData of a time value (ParaView's TimeValue), s. */
void vx_time(vx_file *x, const char *indent, double t);
/* Close the type's element, write the appended block, close the VTKFile.  0, or -1 with a
 * message naming path when the encoder ran out of memory or zlib failed (write errors are
 * w's, reported by out_tmp_commit). */
int vx_end(vx_file *x, const char *type, const char *path, char *err, size_t errsz);
/* Release the buffers. */
void vx_free(vx_file *x);

#endif
