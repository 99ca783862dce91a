/* scene_yaml.h — internal to the scene loader (sim/input/scene*.c): the YAML tree with positions
 * (libfyaml's event parser, scene_yaml.c), the loader's context and the schema getters that
 * check one node and report "file:line:column: what was found; expected what". */
#ifndef SW_SCENE_YAML_H
#define SW_SCENE_YAML_H

#include <stddef.h>

#include "sinew.h"
#include "util.h"

enum { Y_SCALAR, Y_SEQ, Y_MAP };

typedef struct ynode ynode;
struct ynode {
  int kind;          /* Y_* */
  int line, col;     /* 1-based position of the node's first character */
  int plain;         /* scalar: written unquoted (may be a number or null) */
  char *text;        /* scalar: NUL-terminated copy of the value */
  size_t len;        /* scalar: bytes in text (a YAML escape may put a NUL inside) */
  int n, cap;        /* sequence: items; mapping: keys + values */
  ynode **kid;       /* sequence: kid[i]; mapping: key kid[2i], value kid[2i+1] */
};

typedef struct ctx {
  const char *name;        /* scene file, for messages */
  char *err;
  size_t errsz;
  sw_model *m;
  const ynode *root;
  unsigned char *sel;      /* (nv) scratch of the vertex selections */
  const sw_scene_overrides *ov; /* or NULL (sw_scene_load_ex) */
  int grid[2];             /* a grid mesh's vertices nx, ny (0: not a grid) */
  const ynode **by_index;  /* where *by_index is the first selection by vertex index (for the
                              --grid warning), NULL until one is seen */
  int ngroup;              /* the mesh's OBJ groups (seams and arrangement name them) */
  char (*group)[SW_NAMESZ];
  sw_names *gnames;        /* group's names hashed (sc_find_group fills it on first use) */
  int *fgroup;             /* (nf) the group of each face, or NULL */
} ctx;

ynode *sy_parse(const char *name, const char *buf, size_t len, char *err, size_t errsz);
void sy_free(ynode *y);
int sy_fail(const ctx *c, const ynode *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
int sy_oom(const ctx *c, const ynode *at);
int sy_is_null(const ynode *y);
int sy_map(const ctx *c, const ynode *y, const char *what, const char *const *keys,
    int nkeys, const ynode **val);
int sy_need(const ctx *c, const ynode *map, const ynode *val, const char *what,
    const char *key, const char *hint);
int sy_num(const ctx *c, const ynode *y, const char *what, double lo, int strict,
    const char *unit, double *out);
int sy_int(const ctx *c, const ynode *y, const char *what, long lo, long hi, int *out);
int sy_str(const ctx *c, const ynode *y, const char *what, size_t maxsz,
    const char **out);
int sy_choice(const ctx *c, const ynode *y, const char *what, const char *const *choices,
    int n, int *out);
int sy_seq(const ctx *c, const ynode *y, const char *what, const char *expected);
int sy_vec(const ctx *c, const ynode *y, const char *what, int n, double lo, int strict,
    const char *unit, double *out);
int sy_type_error(const ctx *c, const ynode *y, const char *what, const char *expected);
const char *sy_describe(const ynode *y, char *buf, size_t sz);
const char *sy_clip(const ynode *y, char *t, size_t sz);
const char *sy_join(const char *const *names, int n, char *buf, size_t sz);
int sy_scalar_number(const ynode *y, double *v);

/* The path rel relative to the scene file's folder (absolute paths are kept) into out
 * (SW_PATHSZ bytes); -1 with the error at y when it is too long (scene_files.c). */
int sy_path(const ctx *c, const ynode *y, const char *what, const char *rel, char *out);

/* Selections (scene_select.c): mark in c->sel the vertices y picks ({vertices: [...]},
 * {box: ...}, {grid: [[i, j], ...]} or {disc: {center, radius}}). */
int sy_select(const ctx *c, const ynode *y, const char *what);
/* Note y as a selection by vertex index (the first one is kept for the --grid warning). */
void sy_note_index(const ctx *c, const ynode *y);

#endif
