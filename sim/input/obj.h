/* obj.h — internal entry of the OBJ reader: parse an OBJ file already in memory.
 * sw_obj_read (sinew.h) reads the file and calls this; the fuzzer calls it directly. */
#ifndef SW_OBJ_H
#define SW_OBJ_H

#include "sinew.h"

#include <stddef.h>

/* Limits (docs/reliability.md): a larger file is refused before it is read, and more of any
 * one kind (positions, texture coordinates, normals, triangles) is refused as it is read; at
 * these counts the arrays take at most about 0.5 GB. */
#define SW_OBJ_MAX_BYTES (256L << 20)
#ifndef SW_OBJ_MAX_COUNT
#define SW_OBJ_MAX_COUNT 4000000
#endif

/* Parse len bytes of OBJ text (need not be NUL-terminated; a NUL byte is an error).  name is
 * used in messages only ("name:line:column: ...").  *mesh is overwritten (not freed) on entry;
 * on error it is left zeroed and the return value is nonzero. */
int sw_obj_parse(const char *name, const char *buf, size_t len, sw_mesh *mesh, char *err,
                 size_t errsz);

#endif
