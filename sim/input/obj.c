/* obj.c — Wavefront OBJ reader.
 *
 * Positions (v) and texture coordinates (vt) are indexed separately per face corner, so a seam
 * vertex keeps one position and one (u,v) per panel.  Polygons are fan-triangulated from their
 * first corner; a face naming one position twice is an error (degenerate).  `g NAME` and
 * `usemtl NAME` both switch the current face group (NAME: the rest of the line; a bare `g`
 * returns to "default").  Faces all have vt indices or none has.  `v x y z [w]` and
 * `v x y z r g b` (vertex colours) are read; vn (counted for index checks), o, s, mtllib, l, p,
 * comments (also at the end of a line), blank lines, CRLF and a UTF-8 BOM are accepted and
 * ignored.  Anything else is an error "name:line:column: found X, expected Y" (column 1-based,
 * in bytes).  Positions are in the file's units (m for sinew); (u,v) are copied as written.
 * Numbers are read with strtod, so the C locale (decimal point '.') is assumed.
 *
 * The input is untrusted (it is fuzzed): the file by SW_OBJ_MAX_BYTES, every count by
 * OBJ_MAX_COUNT, every array grows with overflow-checked sizes, the text is never assumed to be
 * NUL-terminated, and a message quotes at most 40 bytes of it, non-printable ones as '?'; a
 * file whose first statement is no OBJ keyword is "not an OBJ file", without a quote (it may
 * be any file: a line of /etc/passwd has no place in a message). */
#include "cancel.h"
#include "obj.h"
#include "sinew.h"
#include "util.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define OBJ_MAX_COUNT SW_OBJ_MAX_COUNT /* positions, uvs, normals or triangles in one file */
#define OBJ_MAX_GROUPS 65536
#define OBJ_NUMBER_MAX 127      /* longest accepted number token, bytes */

typedef struct corner {
  int pos, uv;    /* 0-based indices; uv = -1 when the corner has none */
  const char *at; /* where the corner starts in the line, for messages */
} corner;

typedef struct obj_state {
  const char *name;
  char *err;
  size_t errsz;
  size_t line;              /* 1-based number of the current line */
  const char *ls, *le;      /* current line [ls, le), trailing blanks and CR removed */
  const char *p;            /* cursor in the current line */
  double *x;                /* (nv x 3) positions */
  double *uv;               /* (nuv x 2) texture coordinates */
  size_t nv, nuv, nvn, capx, capuv;
  int *f, *fuv, *fgroup;    /* (nf x 3), (nf x 3) or NULL, (nf) */
  int *fpoly;               /* (nf) the f line (0-based serial) each triangle comes from */
  size_t nf, capf, capfuv, capfg, capfp;
  char (*group)[SW_NAMESZ];
  size_t ngroup, capg;
  int *gslot;               /* (nslot) hash table of group names: group index + 1, 0 = empty */
  size_t nslot;
  int cur_group;
  int has_uv;               /* -1: no face yet; 0: faces have no vt; 1: they all have vt */
  size_t has_uv_line;       /* the line of the first face, which set has_uv */
  corner *poly;             /* corners of the current face */
  size_t cappoly;
  size_t *seen;             /* (nv) serial of the last face that used each position */
  size_t capseen, nseen, nface; /* nface: f statements so far (the serial) */
  size_t nstatement;        /* statements read so far (not blank lines and comments) */
} obj_state;

/* ------------------------------------------------------------------ helpers */

/* Make room for `need` elements of `size` bytes; returns the (maybe moved) array or NULL. */
static void *reserve(void *p, size_t *cap, size_t need, size_t size) {
  if (need <= *cap) return p;
  size_t c = *cap ? *cap : 16;
  while (c < need) {
    if (c > SIZE_MAX / 2) return NULL;
    c *= 2;
  }
  void *q = sw_realloc(p, c, size);
  if (q) *cap = c;
  return q;
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

/* A token of n bytes as a short printable quoted string, for messages: at most OBJ_QUOTE_MAX
 * bytes of it (fewer if bufsz is smaller), non-printable ones as '?', then "..." if cut. */
#define OBJ_QUOTE_MAX 40
static const char *quote(char *buf, size_t bufsz, const char *s, size_t n) {
  size_t k = 0, max = SW_MIN(bufsz - 6, OBJ_QUOTE_MAX + 1); /* quotes, "...", NUL */
  buf[k++] = '\'';
  for (size_t i = 0; i < n && k < max; i++)
    buf[k++] = (s[i] >= 0x20 && s[i] < 0x7f) ? s[i] : '?';
  if (n > max - 1) {
    memcpy(buf + k, "...", 3);
    k += 3;
  }
  buf[k++] = '\'';
  buf[k] = '\0';
  return buf;
}

/* Write "name:line:column: message" with the column of `at` in the current line; returns -1. */
static int fail_at(obj_state *st, const char *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int fail_at(obj_state *st, const char *at, const char *fmt, ...) {
  char msg[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  sw_errf(st->err, st->errsz, "%s:%zu:%zu: %s", st->name, st->line, (size_t)(at - st->ls) + 1,
          msg);
  return -1;
}

static int fail_oom(obj_state *st) {
  return fail_at(st, st->ls, "out of memory, expected to fit the mesh in memory");
}

/* The next token of the line: its start, and its length in *n (0 at the end of the line or at
 * a '#' comment, where the start is the column to report). */
static const char *next_token(obj_state *st, size_t *n) {
  const char *p = st->p, *q;
  while (p < st->le && is_blank(*p)) p++;
  if (p == st->le || *p == '#') {
    st->p = st->le;
    *n = 0;
    return p;
  }
  for (q = p; q < st->le && !is_blank(*q); q++) {}
  st->p = q;
  *n = (size_t)(q - p);
  return p;
}

static int expect_end(obj_state *st, const char *after) {
  size_t n;
  char q[48];
  const char *t = next_token(st, &n);
  if (!n) return 0;
  return fail_at(st, t, "found %s, expected end of line after %s", quote(q, sizeof q, t, n), after);
}

/* Parse one finite number; what names it in messages ("the x coordinate"). */
static int parse_number(obj_state *st, const char *what, double *out) {
  size_t n;
  char buf[OBJ_NUMBER_MAX + 1], q[48], *end;
  const char *t = next_token(st, &n);
  if (!n) return fail_at(st, t, "found end of line, expected %s", what);
  if (n > OBJ_NUMBER_MAX)
    return fail_at(st, t, "found a %zu-byte token, expected %s (a number)", n, what);
  memcpy(buf, t, n);
  buf[n] = '\0';
  double v = strtod(buf, &end);
  if (end != buf + n)
    return fail_at(st, t, "found %s, expected %s (a number)", quote(q, sizeof q, t, n), what);
  if (!isfinite(v))
    return fail_at(st, t, "found %s, expected %s (a finite number)", quote(q, sizeof q, t, n),
                   what);
  *out = v;
  return 0;
}

/* Is there another token on the line? */
static int more_tokens(obj_state *st) {
  const char *p = st->p;
  while (p < st->le && is_blank(*p)) p++;
  return p < st->le && *p != '#';
}

/* --------------------------------------------------------------- statements */

/* v x y z [w]  or  v x y z r g b (vertex colours, ignored); positions in m. */
static int read_position(obj_state *st) {
  static const char *const what[] = {"the x coordinate", "the y coordinate", "the z coordinate",
                                     "w or r", "g", "b"};
  double c[6];
  int k = 0;
  for (; k < 3; k++)
    if (parse_number(st, what[k], &c[k])) return -1;
  for (; k < 6 && more_tokens(st); k++)
    if (parse_number(st, what[k], &c[k])) return -1;
  if (k == 5) return fail_at(st, st->le, "found end of line, expected b (v x y z r g b)");
  if (expect_end(st, "v x y z [w]")) return -1;
  if (st->nv >= OBJ_MAX_COUNT)
    return fail_at(st, st->ls, "found more than %d positions, expected fewer", OBJ_MAX_COUNT);
  double *x = reserve(st->x, &st->capx, 3 * (st->nv + 1), sizeof *x);
  if (!x) return fail_oom(st);
  st->x = x;
  memcpy(x + 3 * st->nv++, c, 3 * sizeof *c);
  return 0;
}

/* vt u [v [w]]; v defaults to 0, w is ignored. */
static int read_texcoord(obj_state *st) {
  double c[3] = {0, 0, 0};
  if (parse_number(st, "u", &c[0])) return -1;
  if (more_tokens(st) && parse_number(st, "v", &c[1])) return -1;
  if (more_tokens(st) && parse_number(st, "w", &c[2])) return -1;
  if (expect_end(st, "vt u [v [w]]")) return -1;
  if (st->nuv >= OBJ_MAX_COUNT)
    return fail_at(st, st->ls, "found more than %d texture coordinates, expected fewer",
                   OBJ_MAX_COUNT);
  double *uv = reserve(st->uv, &st->capuv, 2 * (st->nuv + 1), sizeof *uv);
  if (!uv) return fail_oom(st);
  st->uv = uv;
  memcpy(uv + 2 * st->nuv++, c, 2 * sizeof *c);
  return 0;
}

/* vn x y z: checked, counted (faces may refer to it), otherwise ignored. */
static int read_normal(obj_state *st) {
  double c;
  if (parse_number(st, "the x component", &c) || parse_number(st, "the y component", &c) ||
      parse_number(st, "the z component", &c) || expect_end(st, "vn x y z"))
    return -1;
  if (st->nvn >= OBJ_MAX_COUNT)
    return fail_at(st, st->ls, "found more than %d normals, expected fewer", OBJ_MAX_COUNT);
  st->nvn++;
  return 0;
}

/* One OBJ index in [s, s+n): 1..count, or -count..-1 counting back from the last element defined
 * so far.  what: "position", "texture", "normal".  Stores the 0-based index. */
static int parse_index(obj_state *st, const char *s, size_t n, size_t count, const char *what,
                       int *out) {
  char q[48];
  size_t i = 0;
  long long v = 0;
  int neg = n > 0 && s[0] == '-';
  if (n > 0 && (s[0] == '-' || s[0] == '+')) i = 1;
  if (i == n) return fail_at(st, s, "found %s, expected a %s index", quote(q, sizeof q, s, n), what);
  for (; i < n; i++) {
    if (s[i] < '0' || s[i] > '9')
      return fail_at(st, s, "found %s, expected a %s index (an integer)", quote(q, sizeof q, s, n),
                     what);
    if (v <= OBJ_MAX_COUNT) v = 10 * v + (s[i] - '0'); /* saturates above the largest count */
  }
  long long r = neg ? (long long)count - v : v - 1;
  if (v == 0 || r < 0 || r >= (long long)count) {
    if (count == 0)
      return fail_at(st, s, "found %s index %s, but no %s is defined above this line", what,
                     quote(q, sizeof q, s, n), what);
    return fail_at(st, s, "found %s index %s, expected 1..%zu or -%zu..-1 (%zu defined above)",
                   what, quote(q, sizeof q, s, n), count, count, count);
  }
  *out = (int)r;
  return 0;
}

/* The texture-coordinate policy: all faces have vt indices, or none has. */
static int check_uv_policy(obj_state *st, const char *at, int has) {
  if (st->has_uv < 0) {
    st->has_uv = has;
    st->has_uv_line = st->line;
  }
  if (st->has_uv == has) return 0;
  if (has)
    return fail_at(st, at, "found a corner with a texture index, expected none (the face on "
                   "line %zu has none, and all faces must agree)", st->has_uv_line);
  return fail_at(st, at, "found a corner without a texture index, expected one (the face on "
                 "line %zu has them, and all faces must agree)", st->has_uv_line);
}

/* One face corner a, a/b, a/b/c or a//c into *c. */
static int parse_corner(obj_state *st, const char *t, size_t n, corner *c) {
  const char *end = t + n, *s1 = memchr(t, '/', n), *s2 = NULL;
  int vn;
  if (s1) s2 = memchr(s1 + 1, '/', (size_t)(end - s1 - 1));
  if (s2) {
    const char *s3 = memchr(s2 + 1, '/', (size_t)(end - s2 - 1));
    if (s3) return fail_at(st, s3, "found a third '/', expected a corner v, v/vt, v/vt/vn or v//vn");
  }
  const char *ea = s1 ? s1 : end, *eb = s2 ? s2 : end;
  c->at = t;
  c->uv = -1;
  if (parse_index(st, t, (size_t)(ea - t), st->nv, "position", &c->pos)) return -1;
  int has = s1 && eb > s1 + 1;
  if (s1 && !s2 && !has) return fail_at(st, s1, "found '/' at the end of a corner, expected a "
                                        "texture index after it");
  if (check_uv_policy(st, t, has)) return -1;
  if (has && parse_index(st, s1 + 1, (size_t)(eb - s1 - 1), st->nuv, "texture", &c->uv))
    return -1;
  if (s2 && s2 + 1 == end)
    return fail_at(st, s2, "found '/' at the end of a corner, expected a normal index after it");
  if (s2 && parse_index(st, s2 + 1, (size_t)(end - s2 - 1), st->nvn, "normal", &vn)) return -1;
  return 0;
}

/* The corners of the current face (nc) must name distinct positions: a repeated one makes a
 * degenerate or folded fan triangle.  O(nc) with a per-position stamp. */
static int check_distinct(obj_state *st, size_t nc) {
  size_t *seen = reserve(st->seen, &st->capseen, st->nv, sizeof *seen);
  if (!seen) return fail_oom(st);
  st->seen = seen;
  for (; st->nseen < st->nv; st->nseen++) seen[st->nseen] = 0; /* new positions: never used */
  st->nface++;
  for (size_t k = 0; k < nc; k++) {
    size_t i = (size_t)st->poly[k].pos;
    if (seen[i] == st->nface)
      return fail_at(st, st->poly[k].at, "found position %d again in the same face "
                     "(degenerate), expected distinct positions", st->poly[k].pos + 1);
    seen[i] = st->nface;
  }
  return 0;
}

/* Append the fan triangles of the current face (nc corners). */
static int append_fan(obj_state *st, size_t nc) {
  size_t nt = nc - 2, n = st->nf + nt;
  if (nt > OBJ_MAX_COUNT || n > OBJ_MAX_COUNT)
    return fail_at(st, st->ls, "found more than %d triangles, expected fewer", OBJ_MAX_COUNT);
  int *f = reserve(st->f, &st->capf, 3 * n, sizeof *f);
  if (f) st->f = f;
  int *g = f ? reserve(st->fgroup, &st->capfg, n, sizeof *g) : NULL;
  if (g) st->fgroup = g;
  int *fp = g ? reserve(st->fpoly, &st->capfp, n, sizeof *fp) : NULL;
  if (fp) st->fpoly = fp;
  int *fuv = st->fuv;
  if (g && st->has_uv) fuv = reserve(st->fuv, &st->capfuv, 3 * n, sizeof *fuv);
  if (fuv) st->fuv = fuv;
  if (!f || !g || !fp || (st->has_uv && !fuv)) return fail_oom(st);
  for (size_t k = 1; k + 1 < nc; k++, st->nf++) {
    size_t c[3] = {0, k, k + 1};
    for (size_t i = 0; i < 3; i++) {
      st->f[3 * st->nf + i] = st->poly[c[i]].pos;
      if (st->has_uv) st->fuv[3 * st->nf + i] = st->poly[c[i]].uv;
    }
    st->fgroup[st->nf] = st->cur_group;
    st->fpoly[st->nf] = (int)st->nface - 1;
  }
  return 0;
}

/* f c1 c2 c3 ...: a polygon of >= 3 corners, fan-triangulated from c1. */
static int read_face(obj_state *st) {
  size_t nc = 0, n;
  const char *t;
  while ((t = next_token(st, &n)), n) {
    corner *poly = reserve(st->poly, &st->cappoly, nc + 1, sizeof *poly);
    if (!poly) return fail_oom(st);
    st->poly = poly;
    if (parse_corner(st, t, n, &poly[nc])) return -1;
    nc++;
  }
  if (nc < 3) return fail_at(st, t, "found end of line after %zu corners, expected at least 3", nc);
  if (check_distinct(st, nc)) return -1;
  return append_fan(st, nc);
}

static size_t name_hash(const char *s, size_t n) { return (size_t)sw_hash64(SW_HASH0, s, n); }

/* The hash slot holding the group called name (n bytes), or the empty slot where it goes. */
static size_t group_slot(const obj_state *st, const char *name, size_t n) {
  size_t mask = st->nslot - 1, i = name_hash(name, n) & mask;
  for (;; i = (i + 1) & mask) {
    int g = st->gslot[i] - 1;
    if (g < 0 || (strlen(st->group[g]) == n && memcmp(st->group[g], name, n) == 0)) return i;
  }
}

/* Keep the hash table of group names at most half full. */
static int group_rehash(obj_state *st) {
  if (2 * (st->ngroup + 1) <= st->nslot) return 0;
  size_t nslot = st->nslot ? 2 * st->nslot : 64;
  int *slot = sw_calloc(nslot, sizeof *slot);
  if (!slot) return -1;
  sw_free(st->gslot);
  st->gslot = slot;
  st->nslot = nslot;
  for (size_t g = 0; g < st->ngroup; g++) {
    const char *name = st->group[g];
    slot[group_slot(st, name, strlen(name))] = (int)g + 1;
  }
  return 0;
}

/* Index of the group called name (n < SW_NAMESZ bytes), added if new; -1 on error (message
 * written).  Hashed: a file may switch groups on every line. */
static int find_group(obj_state *st, const char *name, size_t n) {
  if (group_rehash(st)) return fail_oom(st);
  size_t i = group_slot(st, name, n);
  if (st->gslot[i]) return st->gslot[i] - 1;
  if (st->ngroup >= OBJ_MAX_GROUPS)
    return fail_at(st, name, "found more than %d groups, expected fewer", OBJ_MAX_GROUPS);
  char(*g)[SW_NAMESZ] = reserve(st->group, &st->capg, st->ngroup + 1, sizeof *g);
  if (!g) return fail_oom(st);
  st->group = g;
  memcpy(g[st->ngroup], name, n);
  g[st->ngroup][n] = '\0';
  st->gslot[i] = (int)++st->ngroup;
  return (int)st->ngroup - 1;
}

/* g [NAME] or usemtl NAME: the rest of the line (trimmed) names the current group. */
static int read_group(obj_state *st, int is_usemtl) {
  const char *s = st->p;
  while (s < st->le && is_blank(*s)) s++;
  size_t n = (size_t)(st->le - s);
  if (n == 0 && is_usemtl) return fail_at(st, s, "found end of line, expected a material name");
  if (n == 0) {
    st->cur_group = 0; /* a bare `g` returns to the default group */
    return 0;
  }
  if (n >= SW_NAMESZ)
    return fail_at(st, s, "found a %zu-byte name, expected at most %d bytes", n, SW_NAMESZ - 1);
  int g = find_group(st, s, n);
  if (g < 0) return -1;
  st->cur_group = g;
  return 0;
}

static int keyword_is(const char *k, size_t n, const char *word) {
  return strlen(word) == n && memcmp(k, word, n) == 0;
}

/* One line, already delimited in st->ls .. st->le. */
static int read_statement(obj_state *st) {
  size_t n;
  char q[48];
  const char *k = next_token(st, &n);
  if (!n) return 0; /* blank line or comment */
  int first = !st->nstatement++;
  if (keyword_is(k, n, "v")) return read_position(st);
  if (keyword_is(k, n, "vt")) return read_texcoord(st);
  if (keyword_is(k, n, "vn")) return read_normal(st);
  if (keyword_is(k, n, "f")) return read_face(st);
  if (keyword_is(k, n, "g")) return read_group(st, 0);
  if (keyword_is(k, n, "usemtl")) return read_group(st, 1);
  if (keyword_is(k, n, "o") || keyword_is(k, n, "s") || keyword_is(k, n, "mtllib") ||
      keyword_is(k, n, "l") || keyword_is(k, n, "p"))
    return 0;
  if (first)
    return fail_at(st, k, "not an OBJ file: the first statement is not an OBJ keyword; expected "
                   "v, vt, vn, f, g, usemtl, o, s, mtllib, l, p or #");
  return fail_at(st, k, "found unknown statement %s, expected v, vt, vn, f, g, usemtl, o, s, "
                 "mtllib, l, p or #", quote(q, sizeof q, k, n));
}

/* Delimit the line starting at buf[pos] (ending at '\n' or len), check it, and read it.
 * *next receives the start of the following line. */
static int read_line(obj_state *st, const char *buf, size_t len, size_t pos, size_t *next) {
  const char *ls = buf + pos, *nl = memchr(ls, '\n', len - pos);
  const char *le = nl ? nl : buf + len;
  *next = (size_t)(le - buf) + (nl ? 1 : 0);
  st->line++;
  st->ls = st->p = ls;
  while (le > ls && (is_blank(le[-1]) || le[-1] == '\r')) le--;
  st->le = le;
  const char *bad = memchr(ls, '\0', (size_t)(le - ls));
  if (bad) return fail_at(st, bad, "found a NUL byte, expected text");
  bad = memchr(ls, '\r', (size_t)(le - ls));
  if (bad)
    return fail_at(st, bad, "found a carriage return inside a line, expected LF or CRLF line "
                   "endings");
  return read_statement(st);
}

/* Every line of buf[pos, len) (the last one may lack its '\n'). */
static int read_some_lines(obj_state *st, const char *buf, size_t len, size_t pos) {
  while (pos < len) {
    if ((st->line & 0xffff) == 0 && sw_cancelled()) /* a stop request, every 65536 lines */
      return sw_errf(st->err, st->errsz, "%s: stopped by signal %d at line %zu", st->name,
                     sw_cancelled(), st->line + 1), -1;
    if (read_line(st, buf, len, pos, &pos)) return -1;
  }
  return 0;
}

/* The length of a UTF-8 byte order mark at the start of buf (len bytes): 3 or 0. */
static size_t bom(const char *buf, size_t len) {
  return len >= 3 && memcmp(buf, "\xef\xbb\xbf", 3) == 0 ? 3 : 0;
}

/* 0 when the mesh has a face, else -1 with the message. */
static int check_faces(obj_state *st) {
  if (st->nf == 0) {
    sw_errf(st->err, st->errsz, "%s: found no faces, expected at least one f statement",
            st->name);
    return -1;
  }
  return 0;
}

/* Every line of buf (len bytes), then the check that there was a face. */
static int read_lines(obj_state *st, const char *buf, size_t len) {
  return read_some_lines(st, buf, len, bom(buf, len)) || check_faces(st) ? -1 : 0;
}

static void state_free(obj_state *st) {
  sw_free(st->x);
  sw_free(st->uv);
  sw_free(st->f);
  sw_free(st->fuv);
  sw_free(st->fgroup);
  sw_free(st->fpoly);
  sw_free(st->group);
  sw_free(st->poly);
  sw_free(st->seen);
  sw_free(st->gslot);
}

/* Move the arrays of a successful parse into mesh. */
static void state_to_mesh(obj_state *st, sw_mesh *mesh) {
  mesh->nv = (int)st->nv;
  mesh->nf = (int)st->nf;
  mesh->x = st->x;
  mesh->f = st->f;
  mesh->fgroup = st->fgroup;
  mesh->fpoly = st->fpoly;
  mesh->ngroup = (int)st->ngroup;
  mesh->group = st->group;
  if (st->has_uv == 1) {
    mesh->nuv = (int)st->nuv;
    mesh->uv = st->uv;
    mesh->fuv = st->fuv;
  } else {
    sw_free(st->uv);
    sw_free(st->fuv);
  }
  sw_free(st->poly);
  sw_free(st->seen);
  sw_free(st->gslot);
  memset(st, 0, sizeof *st);
}

/* A parse's state before its first line; -1 when out of memory (st then freed). */
static int state_init(obj_state *st, const char *name, char *err, size_t errsz) {
  memset(st, 0, sizeof *st);
  st->name = name ? name : "(obj)";
  st->err = err;
  st->errsz = errsz;
  st->has_uv = -1;
  st->ls = st->le = st->p = ""; /* no line yet */
  if (find_group(st, "default", 7) == 0) return 0;
  sw_errf(err, errsz, "%s: out of memory", st->name);
  state_free(st);
  return -1;
}

int sw_obj_parse(const char *name, const char *buf, size_t len, sw_mesh *mesh, char *err,
                 size_t errsz) {
  obj_state st;
  if (!mesh) {
    sw_errf(err, errsz, "%s: mesh is NULL", name ? name : "(obj)");
    return SW_FATAL;
  }
  memset(mesh, 0, sizeof *mesh);
  if (state_init(&st, name, err, errsz)) return SW_FATAL;
  if (read_lines(&st, buf, buf ? len : 0)) {
    state_free(&st);
    return SW_FATAL;
  }
  state_to_mesh(&st, mesh);
  return SW_OK;
}

static int too_large(const char *path, char *err, size_t errsz) {
  sw_errf(err, errsz, "%s: larger than %ld bytes, expected an OBJ file of at most %ld MB", path,
          SW_OBJ_MAX_BYTES, SW_OBJ_MAX_BYTES >> 20);
  return -1;
}

/* Parse the open file fp chunk by chunk (OBJ_CHUNK bytes at a time, more for a longer line):
 * a large file is never held whole in memory, only the arrays parsed from it.  A regular file
 * above SW_OBJ_MAX_BYTES is refused before it is read, anything else (a pipe, a device) once
 * it passes the limit.  Reading stops at the first chunk holding a NUL byte: the parser
 * refuses the NUL with its line and column, and /dev/zero is not read for seconds first.
 * The stop request (cancel.h: sw_cancelled) is polled at every chunk and every 65536 lines. */
#define OBJ_CHUNK ((size_t)1 << 20)
static int read_file(obj_state *st, const char *path, FILE *fp) {
  struct stat sb;
  if (fstat(fileno(fp), &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > SW_OBJ_MAX_BYTES)
    return too_large(path, st->err, st->errsz);
  size_t cap = 0, n = 0, total = 0; /* buf holds n bytes: the lines not read yet */
  char *buf = NULL;
  int rc = 0;
  for (int end = 0; !rc && !end;) {
    if (sw_cancelled()) {
      sw_errf(st->err, st->errsz, "%s: stopped by signal %d after reading %zu bytes", path,
              sw_cancelled(), total);
      rc = -1;
      break;
    }
    char *b = reserve(buf, &cap, n + OBJ_CHUNK, 1);
    if (!b) {
      sw_errf(st->err, st->errsz, "%s: out of memory after %zu bytes, expected to fit a line",
              path, total);
      rc = -1;
      break;
    }
    buf = b;
    size_t want = SW_MIN(cap - n, (size_t)SW_OBJ_MAX_BYTES + 1 - total);
    size_t got = fread(buf + n, 1, want, fp);
    end = got < want || memchr(buf + n, '\0', got) != NULL; /* end, error or refused text */
    size_t pos = total == 0 ? bom(buf, got) : 0;
    n += got, total += got;
    if (total > (size_t)SW_OBJ_MAX_BYTES) {
      rc = too_large(path, st->err, st->errsz);
      break;
    }
    size_t upto = n; /* the complete lines (all at the end) */
    while (!end && upto > 0 && buf[upto - 1] != '\n') upto--;
    rc = read_some_lines(st, buf, upto, pos);
    memmove(buf, buf + upto, n - upto);
    n -= upto;
  }
  sw_free(buf);
  if (!rc && ferror(fp)) {
    sw_errf(st->err, st->errsz, "%s: cannot read: %s, expected a readable OBJ file", path,
            strerror(errno));
    rc = -1;
  }
  return rc ? rc : check_faces(st);
}

int sw_obj_read(const char *path, sw_mesh *mesh, char *err, size_t errsz) {
  if (mesh) memset(mesh, 0, sizeof *mesh);
  if (!path || !mesh) {
    sw_errf(err, errsz, "obj: %s is NULL", path ? "mesh" : "path");
    return SW_FATAL;
  }
  errno = 0;
  FILE *fp = fopen(path, "rb");
  if (!fp) {
    sw_errf(err, errsz, "%s: cannot open: %s, expected a readable OBJ file", path,
            strerror(errno));
    return SW_FATAL;
  }
  obj_state st;
  if (state_init(&st, path, err, errsz)) {
    fclose(fp);
    return SW_FATAL;
  }
  int rc = read_file(&st, path, fp);
  fclose(fp);
  if (rc) {
    state_free(&st);
    return SW_FATAL;
  }
  state_to_mesh(&st, mesh);
  return SW_OK;
}
