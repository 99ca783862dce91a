/* targets.c — the target forces of the tendon inverse problem (docs/inverse.md): a CSV file
 *   vertex,fx,fy[,fz]        header: the scene's dimension many force components
 *   4,0,-2.5                 one line per target vertex: index in [0, nv), force in N
 * Spaces around fields, CRLF line ends and blank lines are allowed.  Every error is
 * "file:line:column: what was found; expected what" (1-based, the column of the field).
 * Limits: lines of at most TG_LINE_MAX bytes, files of at most TG_MAX_BYTES, no NUL byte (so
 * /dev/zero or a binary file is refused at its first line, not read into memory). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sinew.h"
#include "util.h"

#define TG_MAXF 8     /* fields kept per line; more are counted */
#define TG_FIELDSZ 64 /* bytes of a field quoted in a message */
#define TG_LINE_MAX 4096              /* a longer line is refused, bytes */
#define TG_MAX_BYTES (64L << 20)      /* a larger file is refused, bytes */

typedef struct csv_line {
  const char *path;
  long line;
  int nf;                  /* fields on the line */
  char *f[TG_MAXF];        /* trimmed, NUL-terminated (inside the line buffer) */
  int col[TG_MAXF];        /* 1-based column of each field */
  int end_col;             /* column just after the line's last character */
} csv_line;

static int fail(const csv_line *l, int col, char *err, size_t errsz, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static int fail(const csv_line *l, int col, char *err, size_t errsz, const char *fmt, ...) {
  char msg[SW_ERRSZ];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  sw_errf(err, errsz, "%s:%ld:%d: %s", l->path, l->line > 0 ? l->line : 1, col, msg);
  return -1;
}

/* Split buf (modified) at commas; trim spaces and a trailing CR.  Returns 0 for a blank line. */
static int split(char *buf, csv_line *l) {
  size_t n = strlen(buf);
  while (n && (buf[n - 1] == '\n' || buf[n - 1] == '\r')) buf[--n] = '\0';
  l->end_col = (int)n + 1;
  l->nf = 0;
  char *p = buf;
  int blank = 1;
  for (size_t i = 0; i < n; i++) blank &= buf[i] == ' ' || buf[i] == '\t';
  if (blank) return 0;
  for (;;) {
    char *comma = strchr(p, ',');
    if (comma) *comma = '\0';
    while (*p == ' ' || *p == '\t') p++;
    char *e = p + strlen(p);
    while (e > p && (e[-1] == ' ' || e[-1] == '\t')) *--e = '\0';
    if (l->nf < TG_MAXF) l->f[l->nf] = p, l->col[l->nf] = (int)(p - buf) + 1;
    l->nf++;
    if (!comma) break;
    p = comma + 1;
  }
  return 1;
}

static int check_header(const csv_line *l, int dim, char *err, size_t errsz) {
  static const char *const names[] = {"vertex", "fx", "fy", "fz"};
  const char *want = dim == 2 ? "vertex,fx,fy" : "vertex,fx,fy,fz";
  for (int k = 0; k < l->nf && k < TG_MAXF; k++)
    if (k > dim || strcmp(l->f[k], names[k]))
      return fail(l, l->col[k], err, errsz, "header field %d is '%.*s'; expected the header %s "
                  "(a %dD scene)", k + 1, TG_FIELDSZ, l->f[k], want, dim);
  if (l->nf != dim + 1)
    return fail(l, l->end_col, err, errsz, "the header has %d fields; expected %s (a %dD scene)",
                l->nf, want, dim);
  return 0;
}

static int parse_vertex(const csv_line *l, const sw_model *m, const unsigned char *seen,
                        int *out, char *err, size_t errsz) {
  const int nv = m->nv;
  char *end;
  errno = 0;
  long v = strtol(l->f[0], &end, 10);
  if (!*l->f[0] || *end || errno || v < 0 || v >= nv)
    return fail(l, l->col[0], err, errsz, "vertex is '%.*s'; expected an integer in 0..%d",
                TG_FIELDSZ, l->f[0], nv - 1);
  if (seen[v])
    return fail(l, l->col[0], err, errsz, "vertex %ld is repeated; expected one line per "
                "target vertex", v);
  if (m->pinned[v]) /* the forward check would free it and move it */
    return fail(l, l->col[0], err, errsz, "vertex %ld is pinned by the scene; expected a free "
                "vertex (a pin takes any force, so a target on it means nothing)", v);
  *out = (int)v;
  return 0;
}

static int parse_line(const csv_line *l, const sw_model *m, unsigned char *seen,
                      sw_targets *tg, char *err, size_t errsz) {
  static const char *const comp[] = {"fx", "fy", "fz"};
  if (l->nf != m->dim + 1)
    return fail(l, l->nf > m->dim + 1 && l->nf <= TG_MAXF ? l->col[m->dim + 1] : l->end_col,
                err, errsz, "the line has %d fields; expected %d (vertex and %d force "
                "components in N)", l->nf, m->dim + 1, m->dim);
  int v = -1;
  if (parse_vertex(l, m, seen, &v, err, errsz)) return -1;
  double *f = tg->f + (size_t)tg->n * m->dim;
  for (int a = 0; a < m->dim; a++) {
    char *end;
    errno = 0;
    f[a] = strtod(l->f[a + 1], &end); /* N */
    if (!*l->f[a + 1] || *end || errno || !isfinite(f[a]))
      return fail(l, l->col[a + 1], err, errsz, "%s is '%.*s'; expected a finite number (N)",
                  comp[a], TG_FIELDSZ, l->f[a + 1]);
  }
  seen[v] = 1;
  tg->vertex[tg->n++] = v;
  return 0;
}

/* The next line of fp into buf (TG_LINE_MAX + 2 bytes), NUL-terminated: 1, 0 at the end of
 * the file, -1 with a message for a line too long, a NUL byte or a file too large (*total:
 * bytes read so far). */
static int next_line(FILE *fp, csv_line *l, char *buf, size_t *total, char *err, size_t errsz) {
  size_t n = 0;
  int ch = EOF;
  while (n <= TG_LINE_MAX && (ch = getc(fp)) != EOF) {
    if (ch == '\0')
      return fail(l, (int)n + 1, err, errsz, "a NUL byte; expected text (a CSV file)");
    buf[n++] = (char)ch;
    if (ch == '\n') break;
  }
  buf[n] = '\0';
  if (n > TG_LINE_MAX && buf[n - 1] != '\n')
    return fail(l, TG_LINE_MAX + 1, err, errsz, "a line longer than %d bytes; expected "
                "vertex,fx,fy[,fz]", TG_LINE_MAX);
  if ((*total += n) > (size_t)TG_MAX_BYTES)
    return fail(l, 1, err, errsz, "the file passes %ld bytes; expected a targets file of at "
                "most %ld MB", TG_MAX_BYTES, TG_MAX_BYTES >> 20);
  return n > 0;
}

/* The lines of an open file: header first, then targets. */
static int read_lines(FILE *fp, csv_line *l, const sw_model *m, unsigned char *seen,
                      sw_targets *tg, char *err, size_t errsz) {
  char buf[TG_LINE_MAX + 2];
  size_t total = 0;
  int have_header = 0, rc = 0, got;
  errno = 0;
  while (!rc) {
    l->line++;
    if ((got = next_line(fp, l, buf, &total, err, errsz)) <= 0) {
      if (got == 0) l->line--; /* the end of the file: messages name the last line */
      rc = got;
      break;
    }
    if (!split(buf, l)) continue;
    if (!have_header) rc = check_header(l, m->dim, err, errsz), have_header = 1;
    else if (tg->n >= m->nv) rc = fail(l, 1, err, errsz, "more target lines than the %d "
                                       "vertices; expected one line per target vertex", m->nv);
    else rc = parse_line(l, m, seen, tg, err, errsz);
  }
  if (!rc && ferror(fp))
    rc = -1, sw_errf(err, errsz, "%s: cannot read the targets file: %s", l->path,
                     strerror(errno ? errno : EIO));
  if (!rc && tg->n == 0)
    rc = fail(l, 1, err, errsz, "%s; expected the header vertex,fx,fy%s and at least one "
              "target line", have_header ? "no target line" : "the file is empty",
              m->dim == 3 ? ",fz" : "");
  return rc;
}

void sw_targets_free(sw_targets *tg) {
  if (!tg) return;
  sw_free(tg->vertex);
  sw_free(tg->f);
  memset(tg, 0, sizeof *tg);
}

int sw_targets_read(const char *path, const sw_model *m, sw_targets *tg, char *err,
                    size_t errsz) {
  memset(tg, 0, sizeof *tg);
  tg->dim = m->dim;
  FILE *fp = fopen(path, "r");
  if (!fp) return sw_errf(err, errsz, "%s: cannot open the targets file: %s", path,
                          strerror(errno)), -1;
  struct stat sb;
  if (fstat(fileno(fp), &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > TG_MAX_BYTES)
    return fclose(fp), sw_errf(err, errsz, "%s: %lld bytes; expected a targets file of at most "
                               "%ld MB", path, (long long)sb.st_size, TG_MAX_BYTES >> 20), -1;
  csv_line l = {.path = path};
  unsigned char *seen = sw_calloc((size_t)m->nv, 1);
  tg->vertex = sw_calloc((size_t)m->nv, sizeof(int));
  tg->f = sw_calloc((size_t)m->nv * (size_t)m->dim, sizeof(double));
  int rc = !seen || !tg->vertex || !tg->f
               ? (sw_errf(err, errsz, "%s: out of memory", path), -1)
               : read_lines(fp, &l, m, seen, tg, err, errsz);
  fclose(fp);
  sw_free(seen);
  if (rc) sw_targets_free(tg);
  return rc;
}
