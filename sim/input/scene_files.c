/* scene_files.c — the files a scene names (sim/input/scene*.c): paths relative to the scene
 * file's folder, the OBJ meshes read, and every file read noted with its size and hash in
 * m->input (a resumed run checks that none changed). */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_material.h"
#include "util.h"

int sy_path(const ctx *c, const ynode *y, const char *what, const char *rel, char *out) {
  const char *slash = strrchr(c->name, '/');
  size_t dir = rel[0] != '/' && slash ? (size_t)(slash - c->name) + 1 : 0;
  if (dir + strlen(rel) >= SW_PATHSZ)
    return sy_fail(c, y, "%s makes a path longer than %d bytes; expected a shorter path", what,
                   SW_PATHSZ - 1);
  memcpy(out, c->name, dir);
  strcpy(out + dir, rel);
  return 0;
}

/* The size and hash of file `path` into in, read 64 KiB at a time (a large OBJ is not held
 * whole beside its mesh); -1 with err. */
static int hash_file(const char *path, sw_input *in, char *err, size_t errsz) {
  FILE *f = fopen(path, "rb");
  if (!f) return sw_errf(err, errsz, "%s: cannot open: %s", path, strerror(errno)), -1;
  unsigned char b[65536];
  size_t n;
  in->bytes = 0, in->hash = SW_HASH0;
  while ((n = fread(b, 1, sizeof b, f)) > 0) /* FNV-1a: hashed piece by piece as whole */
    in->hash = sw_hash64(in->hash, b, n), in->bytes += (long long)n;
  int bad = ferror(f);
  if (bad) sw_errf(err, errsz, "%s: cannot read: %s", path, strerror(errno));
  fclose(f);
  return bad ? -1 : 0;
}

int sc_note_input(const ctx *c, const ynode *y, const char *path, const char *buf, size_t len) {
  sw_model *m = c->m;
  sw_input *in = sw_realloc(m->input, (size_t)m->ninput + 1, sizeof *in);
  if (!in) return sy_oom(c, y);
  m->input = in;
  in += m->ninput;
  memset(in, 0, sizeof *in);
  if (!realpath(path, in->path)) snprintf(in->path, sizeof in->path, "%s", path); /* absolute */
  if (!buf) { /* an OBJ, read again as bytes (sw_obj_read keeps no copy), by pieces */
    char e[SW_ERRSZ];
    if (hash_file(path, in, e, sizeof e)) return sy_fail(c, y, "%s", e);
  } else {
    in->bytes = (long long)len;
    in->hash = sw_hash64(SW_HASH0, buf, len);
  }
  m->ninput++;
  return 0;
}

int sc_read_obj(const ctx *c, const ynode *y, const char *what, sw_mesh *mesh, char *path) {
  const char *rel;
  if (sy_str(c, y, what, SW_PATHSZ, &rel) || sy_path(c, y, what, rel, path)) return -1;
  FILE *f = fopen(path, "rb");
  if (!f)
    return sy_fail(c, y, "%s '%s' cannot be opened: %s; expected an OBJ file (relative to "
                   "the scene's folder)", what, path, strerror(errno));
  fclose(f);
  char e[SW_ERRSZ];
  if (sw_obj_read(path, mesh, e, sizeof e)) return sy_fail(c, y, "in %s: %s", what, e);
  if (sc_note_input(c, y, path, NULL, 0)) return -1;
  if (mesh->nv <= 0)
    return sy_fail(c, y, "%s '%s' has no vertices; expected at least one 'v' line", what, path);
  return 0;
}
