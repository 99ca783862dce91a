/* scene.c — the scene loader: YAML (libfyaml) -> validated sw_model.
 *
 * Two stages.  First the YAML text is parsed with libfyaml's event parser into a small tree of
 * our own (ynode) that keeps the 1-based line and column of every node (the libfyaml of
 * Debian 12 has no public node positions); libfyaml's own diagnostics are collected, never
 * printed.  Then the tree is checked against the schema (DESIGN.md, "Scene files") and the
 * model is filled.  Every error is "file:line:column: what was found; what was expected".
 * Units are SI: m, s, kg, N. */
#include "scene.h"

#include "util.h"

#include <errno.h>
#include <libfyaml.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ================================================================ the YAML tree */

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

typedef struct yparser {
  struct fy_parser *fyp;
  struct fy_diag *diag;
  const char *name;  /* file name for messages */
  const char *buf;   /* the YAML text */
  size_t len;        /* bytes in buf */
  char *err;
  size_t errsz;
  int line, col;     /* position of the last event that had one, 1-based */
} yparser;

static void node_free(ynode *y) {
  if (!y) return;
  for (int i = 0; i < y->n; i++) node_free(y->kid[i]);
  sw_free(y->kid);
  sw_free(y->text);
  sw_free(y);
}

static void *yerr(yparser *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void *yerr(yparser *p, const char *fmt, ...) {
  char msg[SW_ERRSZ];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  sw_errf(p->err, p->errsz, "%s:%d:%d: %s", p->name, p->line, p->col, msg);
  return NULL;
}

/* libfyaml failed: report its first collected error (its positions are already 1-based). */
static void *syntax_error(yparser *p) {
  void *it = NULL;
  struct fy_diag_error *de;
  while ((de = fy_diag_errors_iterate(p->diag, &it)))
    if (de->type >= FYET_ERROR) {
      if (de->line > 0 && de->column > 0) {
        p->line = de->line;
        p->col = de->column;
      }
      return yerr(p, "invalid YAML: %s; expected well-formed YAML",
                  de->msg ? de->msg : "syntax error");
    }
  return yerr(p, "invalid YAML (unexpected end of input); expected well-formed YAML");
}

static struct fy_event *next_event(yparser *p) {
  struct fy_event *e = fy_parser_parse(p->fyp);
  if (!e) return syntax_error(p);
  const struct fy_mark *mk = fy_event_start_mark(e);
  if (mk && mk->line >= 0 && mk->column >= 0) {
    p->line = mk->line + 1;
    p->col = mk->column + 1;
  }
  return e;
}

static ynode *node_new(yparser *p, int kind) {
  ynode *y = sw_calloc(1, sizeof *y);
  if (!y) return yerr(p, "out of memory");
  y->kind = kind;
  y->line = p->line;
  y->col = p->col;
  return y;
}

static int node_append(yparser *p, ynode *y, ynode *kid) {
  if (y->n == y->cap) {
    int cap = y->cap ? 2 * y->cap : 8;
    ynode **k = y->cap < INT_MAX / 2 ? sw_realloc(y->kid, (size_t)cap, sizeof *k) : NULL;
    if (!k) return yerr(p, "out of memory"), -1;
    y->kid = k;
    y->cap = cap;
  }
  y->kid[y->n++] = kid;
  return 0;
}

/* The text of a scalar token (escapes processed) into y->text.  libfyaml 0.7.12's
 * fy_token_get_text leaks on some single-quoted scalars with '' escapes; its chunk iterator
 * does not. */
static int scalar_text(yparser *p, struct fy_token *tok, ynode *y) {
  struct fy_token_iter *it = tok ? fy_token_iter_create(tok) : NULL;
  const struct fy_iter_chunk *ch = NULL;
  size_t cap = 0;
  int bad = tok && !it, rc = 0;
  while (!bad && (ch = fy_token_iter_chunk_next(it, ch, &rc))) {
    if (ch->len >= SIZE_MAX / 2 - y->len) bad = 1;
    if (!bad && y->len + ch->len + 1 > cap) {
      size_t want = SW_MAX(2 * cap, y->len + ch->len + 1);
      char *t = sw_realloc(y->text, want, 1);
      if (!t) bad = 1;
      else y->text = t, cap = want;
    }
    if (!bad && ch->len) memcpy(y->text + y->len, ch->str, ch->len), y->len += ch->len;
  }
  if (it) fy_token_iter_destroy(it);
  if (!bad && !rc && !y->text && !(y->text = sw_calloc(1, 1))) bad = 1;
  if (bad || rc)
    return yerr(p, "%s", bad ? "out of memory" : "an unreadable YAML scalar; expected text"), -1;
  y->text[y->len] = '\0';
  return 0;
}

static ynode *build_scalar(yparser *p, struct fy_event *e) {
  ynode *y = node_new(p, Y_SCALAR);
  if (!y) return NULL;
  struct fy_token *tok = e->scalar.value;
  enum fy_scalar_style style = tok ? fy_token_scalar_style(tok) : FYSS_PLAIN;
  y->plain = style == FYSS_PLAIN;
  /* libfyaml marks a quoted scalar after its opening quote: point at the quote */
  const struct fy_mark *mk = fy_event_start_mark(e);
  char before = mk && mk->input_pos > 0 && mk->input_pos <= p->len ? p->buf[mk->input_pos - 1] : 0;
  if ((style == FYSS_SINGLE_QUOTED || style == FYSS_DOUBLE_QUOTED) && y->col > 1 &&
      (before == '\'' || before == '"'))
    y->col--;
  if (scalar_text(p, tok, y)) {
    node_free(y);
    return NULL;
  }
  return y;
}

static ynode *build_node(yparser *p, struct fy_event *e, int depth);

/* Read the items of a collection up to its end event. */
static int build_items(yparser *p, ynode *y, enum fy_event_type end, int depth) {
  for (;;) {
    struct fy_event *e = next_event(p);
    if (!e) return -1;
    if (e->type == end) {
      fy_parser_event_free(p->fyp, e);
      return 0;
    }
    ynode *kid = build_node(p, e, depth + 1);
    if (!kid) return -1;
    if (node_append(p, y, kid)) {
      node_free(kid);
      return -1;
    }
  }
}

static ynode *build_collection(yparser *p, int kind, int depth) {
  ynode *y = node_new(p, kind);
  if (!y) return NULL;
  int rc = build_items(p, y, kind == Y_MAP ? FYET_MAPPING_END : FYET_SEQUENCE_END, depth);
  if (!rc && kind == Y_MAP && y->n % 2)
    rc = -1, yerr(p, "invalid YAML: a key without a value; expected key: value pairs");
  if (rc) {
    node_free(y);
    return NULL;
  }
  return y;
}

/* Build the node that starts with event e (always freed here). */
static ynode *build_node(yparser *p, struct fy_event *e, int depth) {
  enum fy_event_type type = e->type;
  int tagged = fy_event_get_tag_token(e) != NULL;
  ynode *y = type == FYET_SCALAR && !tagged ? build_scalar(p, e) : NULL;
  fy_parser_event_free(p->fyp, e);
  if (tagged) return yerr(p, "a YAML tag; expected a plain value without a tag");
  if (type == FYET_SCALAR) return y;
  if (depth >= SW_SCENE_MAX_DEPTH)
    return yerr(p, "YAML nested more than %d levels deep; expected a shallower scene",
                SW_SCENE_MAX_DEPTH);
  if (type == FYET_MAPPING_START) return build_collection(p, Y_MAP, depth);
  if (type == FYET_SEQUENCE_START) return build_collection(p, Y_SEQ, depth);
  if (type == FYET_ALIAS)
    return yerr(p, "a YAML alias; expected a plain value (anchors and aliases are not supported)");
  return yerr(p, "an unexpected YAML event (%s); expected a value", fy_event_type_get_text(type));
}

/* Consume the event that must come next, of the given type. */
static int expect_event(yparser *p, enum fy_event_type type, const char *what) {
  struct fy_event *e = next_event(p);
  if (!e) return -1;
  enum fy_event_type got = e->type;
  fy_parser_event_free(p->fyp, e);
  if (got != type) return yerr(p, "%s; expected %s", fy_event_type_get_text(got), what), -1;
  return 0;
}

/* After the first document: only the end of the stream may follow. */
static int expect_stream_end(yparser *p) {
  struct fy_event *e = next_event(p);
  if (!e) return -1;
  enum fy_event_type got = e->type;
  fy_parser_event_free(p->fyp, e);
  if (got == FYET_STREAM_END) return 0;
  if (got == FYET_DOCUMENT_START) {  /* its mark may be missing: take its first node's */
    e = next_event(p);
    if (!e) return -1;
    fy_parser_event_free(p->fyp, e);
  }
  yerr(p, "a second YAML document; expected one document per scene file");
  return -1;
}

/* The root node of the one document of the stream, or NULL with p->err. */
static ynode *parse_stream(yparser *p) {
  if (expect_event(p, FYET_STREAM_START, "the start of the YAML stream")) return NULL;
  struct fy_event *e = next_event(p);
  if (!e) return NULL;
  enum fy_event_type got = e->type;
  fy_parser_event_free(p->fyp, e);
  if (got == FYET_STREAM_END)
    return yerr(p, "an empty file; expected a mapping of scene keys (mesh: ..., material: ...)");
  if (got != FYET_DOCUMENT_START)
    return yerr(p, "%s; expected a YAML document", fy_event_type_get_text(got));
  if (!(e = next_event(p))) return NULL;
  ynode *root = build_node(p, e, 0);
  if (!root) return NULL;
  if (expect_event(p, FYET_DOCUMENT_END, "the end of the document") || expect_stream_end(p)) {
    node_free(root);
    return NULL;
  }
  return root;
}

static void diag_discard(struct fy_diag *diag, void *user, const char *buf, size_t len) {
  (void)diag, (void)user, (void)buf, (void)len;
}

/* Bytes in the UTF-8 sequence at s (at most n bytes), or 0 if it is not valid UTF-8
 * (overlong forms, surrogates and code points above U+10FFFF are invalid). */
static size_t utf8_len(const unsigned char *s, size_t n) {
  size_t k;
  if (s[0] < 0x80) return 1;
  if (s[0] >= 0xC2 && s[0] <= 0xDF) k = 2;
  else if (s[0] >= 0xE0 && s[0] <= 0xEF) k = 3;
  else if (s[0] >= 0xF0 && s[0] <= 0xF4) k = 4;
  else return 0;
  if (k > n) return 0;
  for (size_t i = 1; i < k; i++)
    if ((s[i] & 0xC0) != 0x80) return 0;
  if (k == 3 && ((s[0] == 0xE0 && s[1] < 0xA0) || (s[0] == 0xED && s[1] >= 0xA0))) return 0;
  if (k == 4 && ((s[0] == 0xF0 && s[1] < 0x90) || (s[0] == 0xF4 && s[1] >= 0x90))) return 0;
  return k;
}

/* Refuse a NUL byte (it ends libfyaml's input silently) and invalid UTF-8 (libfyaml 0.7.12
 * loops forever on some, e.g. "%r\xff"), with the position of the offending byte. */
static int check_text(yparser *p, const char *buf, size_t len) {
  const unsigned char *s = (const unsigned char *)buf;
  p->line = p->col = 1;
  for (size_t i = 0; i < len;) {
    size_t k = s[i] ? utf8_len(s + i, len - i) : 0;
    if (k == 0) {
      yerr(p, "%s; expected UTF-8 text", s[i] ? "a byte that is not valid UTF-8" : "a NUL byte");
      return -1;
    }
    if (s[i] == '\n') p->line++, p->col = 1;
    else p->col++;
    i += k;
  }
  p->line = p->col = 1;
  return 0;
}

/* Parse YAML text into a ynode tree; NULL with "name:line:column: ..." in err. */
static ynode *yaml_parse(const char *name, const char *buf, size_t len, char *err, size_t errsz) {
  yparser p = {.name = name, .buf = buf, .len = len, .err = err, .errsz = errsz, .line = 1,
               .col = 1};
  if (check_text(&p, buf, len)) return NULL;
  struct fy_diag_cfg dcfg;
  fy_diag_cfg_default(&dcfg);
  dcfg.fp = NULL;                 /* never print: collect instead */
  dcfg.output_fn = diag_discard;
  dcfg.colorize = false;
  dcfg.level = FYET_ERROR;
  p.diag = fy_diag_create(&dcfg);
  if (!p.diag) return yerr(&p, "out of memory (YAML diagnostics)");
  fy_diag_set_collect_errors(p.diag, true);
  struct fy_parse_cfg pcfg = {.search_path = "", .flags = FYPCF_QUIET, .diag = p.diag};
  p.fyp = fy_parser_create(&pcfg);
  ynode *root = NULL;
  if (!p.fyp)
    yerr(&p, "out of memory (YAML parser)");
  else if (fy_parser_set_string(p.fyp, len ? buf : "", len))
    yerr(&p, "cannot read the YAML input; expected text");
  else
    root = parse_stream(&p);
  if (p.fyp) fy_parser_destroy(p.fyp);
  fy_diag_destroy(p.diag);
  return root;
}

/* ================================================================ schema helpers */

typedef struct ctx {
  const char *name;        /* scene file, for messages */
  char *err;
  size_t errsz;
  sw_model *m;
  const ynode *root;
  unsigned char *sel;      /* (nv) scratch of the vertex selections */
} ctx;

static int fail(const ctx *c, const ynode *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int fail(const ctx *c, const ynode *at, const char *fmt, ...) {
  char msg[SW_ERRSZ];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  sw_errf(c->err, c->errsz, "%s:%d:%d: %s", c->name, at->line, at->col, msg);
  return -1;
}

static int oom(const ctx *c, const ynode *at) { return fail(c, at, "out of memory"); }

static int is_null(const ynode *y) {
  if (y->kind != Y_SCALAR || !y->plain) return 0;
  const char *s = y->text;
  return y->len == 0 || !strcmp(s, "~") || !strcmp(s, "null") || !strcmp(s, "Null") ||
         !strcmp(s, "NULL");
}

/* YAML 1.2 core float/int syntax (decimal only): [-+]? (d+ (. d*)? | . d+) ([eE] [-+]? d+)? */
static int number_syntax(const char *s) {
  int digits = 0;
  if (*s == '+' || *s == '-') s++;
  while (*s >= '0' && *s <= '9') s++, digits++;
  if (*s == '.') {
    s++;
    while (*s >= '0' && *s <= '9') s++, digits++;
  }
  if (!digits) return 0;
  if (*s == 'e' || *s == 'E') {
    s++;
    if (*s == '+' || *s == '-') s++;
    if (!(*s >= '0' && *s <= '9')) return 0;
    while (*s >= '0' && *s <= '9') s++;
  }
  return *s == '\0';
}

static int is_special_float(const char *s) {
  static const char *const names[] = {".inf", ".Inf", ".INF", ".nan", ".NaN", ".NAN"};
  if ((*s == '+' || *s == '-') && s[1] == '.' && s[2] != 'n' && s[2] != 'N') s++;
  for (size_t i = 0; i < sizeof names / sizeof *names; i++)
    if (!strcmp(s, names[i])) return 1;
  return 0;
}

/* 0: a finite number in *v; 1: a number that is not finite; -1: not a number. */
static int scalar_number(const ynode *y, double *v) {
  if (y->kind != Y_SCALAR || !y->plain || strlen(y->text) != y->len) return -1;
  if (is_special_float(y->text)) return 1;
  if (!number_syntax(y->text)) return -1;
  *v = strtod(y->text, NULL);
  return isfinite(*v) ? 0 : 1;
}

/* A scalar's text for a message: at most 40 bytes, control characters shown as '?'. */
static const char *clip_text(const ynode *y, char *t, size_t sz) {
  size_t n = 0, lim = sz > 44 ? 40 : sz - 4;
  for (size_t i = 0; i < y->len && n < lim; i++) {
    unsigned char ch = (unsigned char)y->text[i];
    t[n++] = (ch < 32 || ch == 127) ? '?' : (char)ch;
  }
  if (y->len > n) {  /* cut at a character boundary */
    while (n > 0 && ((unsigned char)y->text[n] & 0xC0) == 0x80) n--;
    memcpy(t + n, "...", 3), n += 3;
  }
  t[n] = '\0';
  return t;
}

/* What a node is, for "... is FOUND; expected ...". */
static const char *describe(const ynode *y, char *buf, size_t sz) {
  char t[48];
  double v;
  if (y->kind == Y_MAP) return "a mapping";
  if (y->kind == Y_SEQ) return "a sequence";
  if (is_null(y)) return "empty";
  clip_text(y, t, sizeof t);
  int num = scalar_number(y, &v);
  if (num == 0) snprintf(buf, sz, "%s", t);
  else if (num == 1) snprintf(buf, sz, "%s (not finite)", t);
  else if (y->plain) snprintf(buf, sz, "'%s'", t);
  else snprintf(buf, sz, "the quoted string \"%s\"", t);
  return buf;
}

/* "a, b, c" */
static const char *join(const char *const *names, int n, char *buf, size_t sz) {
  size_t at = 0;
  buf[0] = '\0';
  for (int i = 0; i < n && names[i] && at < sz; i++) {
    int w = snprintf(buf + at, sz - at, "%s%s", i ? ", " : "", names[i]);
    if (w < 0) break;
    at += (size_t)w;
  }
  return buf;
}

static int type_error(const ctx *c, const ynode *y, const char *what, const char *expected) {
  char d[96];
  return fail(c, y, "%s is %s; expected %s", what, describe(y, d, sizeof d), expected);
}

/* A mapping whose keys are all in keys[]: val[i] is the value of keys[i] or NULL. */
static int get_map(const ctx *c, const ynode *y, const char *what, const char *const *keys,
                   int nkeys, const ynode **val) {
  char list[256], d[96];
  join(keys, nkeys, list, sizeof list);
  for (int i = 0; i < nkeys; i++) val[i] = NULL;
  if (y->kind != Y_MAP) {
    char exp[300];
    snprintf(exp, sizeof exp, "a mapping with keys among: %s", list);
    return type_error(c, y, what, exp);
  }
  for (int p = 0; p < y->n / 2; p++) {
    const ynode *k = y->kid[2 * p];
    int i = 0;
    if (k->kind == Y_SCALAR && strlen(k->text) == k->len)
      while (i < nkeys && strcmp(k->text, keys[i])) i++;
    else
      i = nkeys;
    if (i == nkeys && k->kind != Y_SCALAR)
      return fail(c, k, "%s has %s as a key; expected one of: %s", what,
                  describe(k, d, sizeof d), list);
    if (i == nkeys)
      return fail(c, k, "%s has an unknown key '%s'; expected one of: %s", what,
                  clip_text(k, d, sizeof d), list);
    if (val[i])
      return fail(c, k, "%s has a duplicate key '%s'; expected each key once", what, keys[i]);
    val[i] = y->kid[2 * p + 1];
  }
  return 0;
}

static int need_key(const ctx *c, const ynode *map, const ynode *val, const char *what,
                    const char *key, const char *hint) {
  if (val) return 0;
  return fail(c, map, "%s has no '%s' key; expected %s", what, key, hint);
}

/* "a number > 0 (s)" */
static const char *num_expect(char *buf, size_t sz, double lo, int strict, const char *unit) {
  int at = lo == -HUGE_VAL ? snprintf(buf, sz, "a number")
                           : snprintf(buf, sz, "a number %s %g", strict ? ">" : ">=", lo);
  if (unit && at >= 0 && (size_t)at < sz) snprintf(buf + at, sz - (size_t)at, " (%s)", unit);
  return buf;
}

/* A finite number >= lo (> lo when strict; lo = -HUGE_VAL: any). */
static int get_num(const ctx *c, const ynode *y, const char *what, double lo, int strict,
                   const char *unit, double *out) {
  double v = 0;
  char exp[96];
  if (scalar_number(y, &v) || (strict ? !(v > lo) : !(v >= lo)))
    return type_error(c, y, what, num_expect(exp, sizeof exp, lo, strict, unit));
  *out = v;
  return 0;
}

/* A decimal integer in [lo, hi]. */
static int get_int(const ctx *c, const ynode *y, const char *what, long lo, long hi, int *out) {
  char exp[96];
  if (hi == INT_MAX) snprintf(exp, sizeof exp, "an integer >= %ld", lo);
  else snprintf(exp, sizeof exp, "an integer in [%ld, %ld]", lo, hi);
  const char *s = y->text;
  if (y->kind != Y_SCALAR || !y->plain || strlen(s) != y->len) return type_error(c, y, what, exp);
  const char *d = s + (*s == '+' || *s == '-');
  size_t nd = strspn(d, "0123456789");
  if (nd == 0 || d[nd] != '\0') return type_error(c, y, what, exp);
  errno = 0;
  long v = strtol(s, NULL, 10);
  if (errno || v < lo || v > hi) return type_error(c, y, what, exp);
  *out = (int)v;
  return 0;
}

/* A non-empty string of fewer than maxsz bytes. */
static int get_str(const ctx *c, const ynode *y, const char *what, size_t maxsz,
                   const char **out) {
  if (y->kind != Y_SCALAR || is_null(y)) return type_error(c, y, what, "a string");
  if (strlen(y->text) != y->len)
    return fail(c, y, "%s contains a NUL character; expected text", what);
  if (y->len == 0) return fail(c, y, "%s is an empty string; expected a non-empty string", what);
  if (y->len >= maxsz)
    return fail(c, y, "%s is %zu bytes long; expected at most %zu", what, y->len, maxsz - 1);
  *out = y->text;
  return 0;
}

/* A string among choices[]: its index. */
static int get_choice(const ctx *c, const ynode *y, const char *what, const char *const *choices,
                      int n, int *out) {
  char list[256], exp[300];
  snprintf(exp, sizeof exp, "one of: %s", join(choices, n, list, sizeof list));
  if (y->kind != Y_SCALAR || is_null(y) || strlen(y->text) != y->len)
    return type_error(c, y, what, exp);
  for (int i = 0; i < n && choices[i]; i++)
    if (!strcmp(y->text, choices[i])) return *out = i, 0;
  return type_error(c, y, what, exp);
}

static int get_seq(const ctx *c, const ynode *y, const char *what, const char *expected) {
  return y->kind == Y_SEQ ? 0 : type_error(c, y, what, expected);
}

/* A sequence of exactly n numbers, each >= lo (> lo when strict). */
static int get_vec(const ctx *c, const ynode *y, const char *what, int n, double lo, int strict,
                   const char *unit, double *out) {
  char exp[160], lab[224];
  snprintf(exp, sizeof exp, "a sequence of %d numbers (%s)", n, unit ? unit : "");
  if (get_seq(c, y, what, exp)) return -1;
  if (y->n != n) return fail(c, y, "%s has %d components; expected %d", what, y->n, n);
  for (int i = 0; i < n; i++) {
    snprintf(lab, sizeof lab, "%s[%d]", what, i);
    if (get_num(c, y->kid[i], lab, lo, strict, unit, out + i)) return -1;
  }
  return 0;
}

/* The scene file's stem: "scenes/hanging_cloth.yaml" -> "hanging_cloth". */
static void file_stem(const char *path, char *out, size_t sz) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  const char *dot = strrchr(base, '.');
  size_t n = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  if (n == 0) base = "scene", n = 5;
  if (n >= sz) n = sz - 1;
  memcpy(out, base, n);
  out[n] = '\0';
}

/* ================================================================ the mesh */

typedef struct mesh_in {
  sw_mesh mesh;
  const ynode *at;        /* the grid or obj value, for messages */
  char obj[SW_PATHSZ];    /* the OBJ file as opened */
} mesh_in;

static const char *const grid_keys[] = {"size", "vertices", "plane"};
static const char *const planes[] = {"xy", "xz", "yz"};

static int load_grid(const ctx *c, const ynode *y, mesh_in *mi) {
  const ynode *v[3];
  double size[2];
  int nvert[2], plane = 0;
  if (get_map(c, y, "mesh grid", grid_keys, 3, v)) return -1;
  if (need_key(c, y, v[0], "mesh grid", "size", "size: [lx, ly] in m") ||
      need_key(c, y, v[1], "mesh grid", "vertices", "vertices: [nx, ny], each >= 2"))
    return -1;
  if (get_vec(c, v[0], "mesh grid size", 2, 0, 1, "m", size)) return -1;
  if (get_seq(c, v[1], "mesh grid vertices", "a sequence of 2 integers >= 2")) return -1;
  if (v[1]->n != 2)
    return fail(c, v[1], "mesh grid vertices has %d components; expected 2", v[1]->n);
  if (get_int(c, v[1]->kid[0], "mesh grid vertices[0]", 2, INT_MAX, nvert) ||
      get_int(c, v[1]->kid[1], "mesh grid vertices[1]", 2, INT_MAX, nvert + 1))
    return -1;
  if ((double)nvert[0] * nvert[1] > (double)SW_SCENE_MAX_VERTICES)
    return fail(c, v[1], "mesh grid vertices is %d x %d; expected at most %ld vertices in all",
                nvert[0], nvert[1], (long)SW_SCENE_MAX_VERTICES);
  if (v[2] && get_choice(c, v[2], "mesh grid plane", planes, 3, &plane)) return -1;
  if (c->m->dim == 2 && plane != 0)
    return fail(c, v[2], "mesh grid plane is %s in a 2D scene; expected xy (dimension: 2)",
                planes[plane]);
  char e[SW_ERRSZ];
  if (sw_mesh_grid(&mi->mesh, size, nvert[0], nvert[1], planes[plane], e, sizeof e))
    return fail(c, y, "in mesh grid: %s", e);
  return 0;
}

/* The OBJ path relative to the scene file's folder (absolute paths are kept). */
static int obj_path(const ctx *c, const ynode *y, const char *rel, char *out) {
  const char *slash = strrchr(c->name, '/');
  size_t dir = rel[0] != '/' && slash ? (size_t)(slash - c->name) + 1 : 0;
  if (dir + strlen(rel) >= SW_PATHSZ)
    return fail(c, y, "mesh obj makes a path longer than %d bytes; expected a shorter path",
                SW_PATHSZ - 1);
  memcpy(out, c->name, dir);
  strcpy(out + dir, rel);
  return 0;
}

static int load_obj(const ctx *c, const ynode *y, mesh_in *mi) {
  const char *rel;
  if (get_str(c, y, "mesh obj", SW_PATHSZ, &rel) || obj_path(c, y, rel, mi->obj)) return -1;
  FILE *f = fopen(mi->obj, "rb");
  if (!f)
    return fail(c, y, "mesh obj '%s' cannot be opened: %s; expected an OBJ file (relative to "
                "the scene's folder)", mi->obj, strerror(errno));
  fclose(f);
  char e[SW_ERRSZ];
  if (sw_obj_read(mi->obj, &mi->mesh, e, sizeof e)) return fail(c, y, "in mesh obj: %s", e);
  if (mi->mesh.nv <= 0)
    return fail(c, y, "mesh obj '%s' has no vertices; expected at least one 'v' line", mi->obj);
  if (c->m->dim == 2)
    for (int i = 0; i < mi->mesh.nv; i++)
      if (mi->mesh.x[3 * i + 2] != 0.0)
        return fail(c, y, "mesh obj '%s' vertex %d has z = %g m in a 2D scene; expected z = 0 "
                    "for every vertex (dimension: 2)", mi->obj, i + 1, mi->mesh.x[3 * i + 2]);
  return 0;
}

static const char *const mesh_keys[] = {"grid", "obj", "uv_scale"};

/* Load the mesh; *uv_scale multiplies the OBJ's (u,v) to metres. */
static int load_mesh(const ctx *c, const ynode *y, mesh_in *mi, double *uv_scale) {
  const ynode *v[3];
  if (get_map(c, y, "mesh", mesh_keys, 3, v)) return -1;
  if (!v[0] == !v[1])
    return fail(c, y, "mesh has %s; expected exactly one of grid or obj",
                v[0] ? "both grid and obj" : "neither grid nor obj");
  *uv_scale = 1.0;
  if (v[2] && v[0])
    return fail(c, v[2], "mesh uv_scale is given with a grid; expected uv_scale only with obj "
                "(a grid's (u,v) layout is already in m)");
  if (v[2] && get_num(c, v[2], "mesh uv_scale", 0, 1, "m per OBJ (u,v) unit", uv_scale))
    return -1;
  mi->at = v[0] ? v[0] : v[1];
  return v[0] ? load_grid(c, v[0], mi) : load_obj(c, v[1], mi);
}

/* ================================================================ the material */

static const char *const mat_keys[] = {"density", "membrane"};
static const char *const memb_keys[] = {"model", "k_u", "k_v", "k_shear", "b_u", "b_v"};
static const char *const memb_models[] = {"bw98"};

static int load_membrane(const ctx *c, const ynode *y, sw_material *mat) {
  const ynode *v[6];
  int model = 0;
  const char *w = "material membrane";
  if (get_map(c, y, w, memb_keys, 6, v)) return -1;
  for (int i = 1; i <= 3; i++)
    if (need_key(c, y, v[i], w, memb_keys[i], "a stiffness >= 0 in N/m")) return -1;
  if (v[0] && get_choice(c, v[0], "material membrane model", memb_models, 1, &model)) return -1;
  mat->membrane = SW_MEMBRANE_BW98;
  if (get_num(c, v[1], "material membrane k_u", 0, 0, "N/m", &mat->k_u) ||
      get_num(c, v[2], "material membrane k_v", 0, 0, "N/m", &mat->k_v) ||
      get_num(c, v[3], "material membrane k_shear", 0, 0, "N/m", &mat->k_shear))
    return -1;
  mat->b_u = mat->b_v = 1.0;
  if (v[4] && get_num(c, v[4], "material membrane b_u", 0, 1, NULL, &mat->b_u)) return -1;
  if (v[5] && get_num(c, v[5], "material membrane b_v", 0, 1, NULL, &mat->b_v)) return -1;
  return 0;
}

/* The (u,v) rest layout is needed for masses and the membrane. */
static int check_uv(const ctx *c, const ynode *at, const mesh_in *mi, const char *what) {
  const sw_mesh *me = &mi->mesh;
  int ok = me->nuv > 0 && me->fuv;
  for (long k = 0; ok && k < 3L * me->nf; k++) ok = me->fuv[k] >= 0 && me->fuv[k] < me->nuv;
  if (ok || me->nf == 0) return 0;
  return fail(c, at, "%s needs the rest (u,v) layout, but mesh obj '%s' has no texture "
              "coordinates (vt) on every face; expected an OBJ whose faces all have vt", what,
              mi->obj);
}

static int load_material(const ctx *c, const ynode *y, const mesh_in *mi) {
  const ynode *v[2];
  sw_material *mat = &c->m->mat[0];
  if (get_map(c, y, "material", mat_keys, 2, v)) return -1;
  if (need_key(c, y, v[0], "material", "density", "density: a number > 0 in kg/m^2")) return -1;
  if (get_num(c, v[0], "material density", 0, 1, "kg/m^2", &mat->density)) return -1;
  if (v[1] && (load_membrane(c, v[1], mat) || check_uv(c, v[1], mi, "material membrane")))
    return -1;
  return check_uv(c, v[0], mi, "material density");
}

/* ================================================================ filling the model */

/* x0, v0, face, uv and pinned from the mesh. */
static int fill_geometry(const ctx *c, const mesh_in *mi, double uv_scale) {
  sw_model *m = c->m;
  const sw_mesh *me = &mi->mesh;
  int dim = m->dim;
  m->nv = me->nv;
  m->nf = me->nf;
  m->x0 = sw_calloc((size_t)me->nv * (size_t)dim, sizeof *m->x0);
  m->v0 = sw_calloc((size_t)me->nv * (size_t)dim, sizeof *m->v0);
  m->pinned = sw_calloc((size_t)me->nv, 1);
  m->face = sw_calloc((size_t)me->nf * 3, sizeof *m->face);
  m->uv = sw_calloc((size_t)me->nf * 6, sizeof *m->uv);
  if (!m->x0 || !m->v0 || !m->pinned || !m->face || !m->uv) return oom(c, mi->at);
  for (int i = 0; i < me->nv; i++)
    for (int a = 0; a < dim; a++) {
      double x = me->x[3 * i + a]; /* m */
      if (!isfinite(x)) return fail(c, mi->at, "mesh vertex %d is not finite; expected finite "
                                    "coordinates", i);
      m->x0[i * dim + a] = x;
    }
  if (me->nf) memcpy(m->face, me->f, (size_t)me->nf * 3 * sizeof *m->face);
  if (me->nf && me->fpoly) {
    if (!(m->face_poly = sw_calloc((size_t)me->nf, sizeof *m->face_poly))) return oom(c, mi->at);
    memcpy(m->face_poly, me->fpoly, (size_t)me->nf * sizeof *m->face_poly);
  }
  int has_uv = me->nuv > 0 && me->fuv;
  for (long k = 0; has_uv && k < 3L * me->nf; k++) {
    int t = me->fuv[k];
    if (t < 0 || t >= me->nuv) continue; /* check_uv refused this where (u,v) matter */
    m->uv[2 * k] = uv_scale * me->uv[2 * t];         /* m */
    m->uv[2 * k + 1] = uv_scale * me->uv[2 * t + 1]; /* m */
  }
  return 0;
}

static const char *const top_keys[] = {"name",   "dimension",        "mesh",       "material",
                                       "gravity", "pins",            "initial_velocity",
                                       "integrator", "duration",     "output",     "tension_xy"};
enum { K_NAME, K_DIM, K_MESH, K_MAT, K_GRAV, K_PINS, K_IV, K_INT, K_DUR, K_OUT, K_TXY, K_N };

static int load_name_dim(const ctx *c, const ynode **v) {
  sw_model *m = c->m;
  const char *s;
  if (strlen(c->name) >= sizeof m->path)
    return fail(c, c->root, "the scene path is longer than %zu bytes; expected a shorter path",
                sizeof m->path - 1);
  snprintf(m->path, sizeof m->path, "%s", c->name);
  char stem[sizeof m->name];
  file_stem(c->name, stem, sizeof stem);
  if (v[K_NAME] && get_str(c, v[K_NAME], "name", sizeof m->name, &s)) return -1;
  snprintf(m->name, sizeof m->name, "%s", v[K_NAME] ? s : stem);
  snprintf(m->opt.out_dir, sizeof m->opt.out_dir, "out/%s", stem);
  m->dim = 3;
  return v[K_DIM] ? get_int(c, v[K_DIM], "dimension", 2, 3, &m->dim) : 0;
}

static int load_geometry(ctx *c, const ynode **v) {
  mesh_in mi;
  double uv_scale = 1.0;
  memset(&mi, 0, sizeof mi);
  snprintf(mi.obj, sizeof mi.obj, "grid");
  int rc = need_key(c, c->root, v[K_MESH], "the scene", "mesh",
                    "mesh: {grid: {...}} or mesh: {obj: file.obj}");
  if (!rc) rc = load_mesh(c, v[K_MESH], &mi, &uv_scale);
  if (!rc && mi.mesh.nf > 0 && !v[K_MAT])
    rc = fail(c, c->root, "the scene has no 'material' key but the mesh has %d triangles; "
              "expected material: {density: ...}", mi.mesh.nf);
  if (!rc && v[K_MAT]) rc = load_material(c, v[K_MAT], &mi);
  if (!rc) rc = fill_geometry(c, &mi, uv_scale);
  sw_mesh_free(&mi.mesh);
  if (!rc && !(c->sel = sw_calloc((size_t)c->m->nv, 1))) rc = oom(c, c->root);
  return rc;
}

/* ================================================================ selections, pins, velocities */

static const char *const sel_keys[] = {"vertices", "box"};

static int select_list(const ctx *c, const ynode *y, const char *what) {
  char lab[176];
  if (get_seq(c, y, what, "a sequence of vertex indices")) return -1;
  for (int i = 0; i < y->n; i++) {
    int k;
    snprintf(lab, sizeof lab, "%s[%d]", what, i);
    if (get_int(c, y->kid[i], lab, 0, (long)c->m->nv - 1, &k)) return -1;
    c->sel[k] = 1;
  }
  return 0;
}

static int select_box(const ctx *c, const ynode *y, const char *what) {
  const sw_model *m = c->m;
  char lab[176];
  double lo[3], hi[3];
  if (get_seq(c, y, what, "[[min corner], [max corner]]")) return -1;
  if (y->n != 2) return fail(c, y, "%s has %d corners; expected 2 (min and max)", what, y->n);
  snprintf(lab, sizeof lab, "%s min corner", what);
  if (get_vec(c, y->kid[0], lab, m->dim, -HUGE_VAL, 0, "m", lo)) return -1;
  snprintf(lab, sizeof lab, "%s max corner", what);
  if (get_vec(c, y->kid[1], lab, m->dim, -HUGE_VAL, 0, "m", hi)) return -1;
  for (int a = 0; a < m->dim; a++)
    if (lo[a] > hi[a])
      return fail(c, y, "%s has min %g > max %g in component %d; expected min <= max", what,
                  lo[a], hi[a], a);
  for (int i = 0; i < m->nv; i++) {
    int in = 1;
    for (int a = 0; a < m->dim; a++) {
      double x = m->x0[i * m->dim + a];
      in = in && x >= lo[a] && x <= hi[a];
    }
    if (in) c->sel[i] = 1;
  }
  return 0;
}

/* Mark the vertices that the selection y picks in c->sel. */
static int select_vertices(const ctx *c, const ynode *y, const char *what) {
  const ynode *v[2];
  char lab[128];
  memset(c->sel, 0, (size_t)c->m->nv);
  if (get_map(c, y, what, sel_keys, 2, v)) return -1;
  if (!v[0] == !v[1])
    return fail(c, y, "%s has %s; expected exactly one of vertices or box", what,
                v[0] ? "both vertices and box" : "neither vertices nor box");
  snprintf(lab, sizeof lab, "%s %s", what, v[0] ? "vertices" : "box");
  if (v[0] ? select_list(c, v[0], lab) : select_box(c, v[1], lab)) return -1;
  for (int i = 0; i < c->m->nv; i++)
    if (c->sel[i]) return 0;
  return fail(c, y, "%s selects no vertex; expected a selection of at least one vertex", what);
}

static const char *const pin_keys[] = {"select"};

static int load_pins(const ctx *c, const ynode *y) {
  char w[64], lab[96];
  const ynode *v[1];
  if (get_seq(c, y, "pins", "a sequence of {select: ...}")) return -1;
  for (int p = 0; p < y->n; p++) {
    snprintf(w, sizeof w, "pins[%d]", p);
    if (get_map(c, y->kid[p], w, pin_keys, 1, v) ||
        need_key(c, y->kid[p], v[0], w, "select", "select: {vertices: [...]} or {box: [...]}"))
      return -1;
    snprintf(lab, sizeof lab, "%s select", w);
    if (select_vertices(c, v[0], lab)) return -1;
    for (int i = 0; i < c->m->nv; i++) c->m->pinned[i] |= c->sel[i];
  }
  return 0;
}

static const char *const iv_keys[] = {"velocity", "select"};

static int load_velocities(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  char w[64], lab[96];
  const ynode *v[2];
  double vel[3];
  if (get_seq(c, y, "initial_velocity", "a sequence of {velocity: [...], select: ...}"))
    return -1;
  for (int p = 0; p < y->n; p++) {
    snprintf(w, sizeof w, "initial_velocity[%d]", p);
    if (get_map(c, y->kid[p], w, iv_keys, 2, v) ||
        need_key(c, y->kid[p], v[0], w, "velocity", "velocity: [vx, vy(, vz)] in m/s"))
      return -1;
    snprintf(lab, sizeof lab, "%s velocity", w);
    if (get_vec(c, v[0], lab, m->dim, -HUGE_VAL, 0, "m/s", vel)) return -1;
    snprintf(lab, sizeof lab, "%s select", w);
    if (v[1]) {
      if (select_vertices(c, v[1], lab)) return -1;
    } else {
      memset(c->sel, 1, (size_t)m->nv);
    }
    for (int i = 0; i < m->nv; i++)
      if (c->sel[i]) memcpy(m->v0 + i * m->dim, vel, (size_t)m->dim * sizeof *vel);
  }
  return 0;
}

static int load_gravity(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  if (!y) return 0;
  if (get_vec(c, y, "gravity", m->dim, -HUGE_VAL, 0, "m/s^2", m->gravity)) return -1;
  m->has_gravity = 1;
  return 0;
}

/* ================================================================ options */

static const char *const int_keys[] = {"method", "dt", "max_halvings", "newton", "hessian",
                                       "rtol", "atol", "max_order", "max_step", "energy_bound"};
/* in the order of SW_HESSIAN_PROJECTED, _EXACT, _AUTO */
static const char *const hessian_modes[] = {"projected", "exact", "auto"};
static const char *const newton_keys[] = {"max_iterations", "tol"};

static int load_method(const ctx *c, const ynode *y) {
  const char *const *names = sw_method_names();
  static const char *const none[] = {NULL};
  int n = 0, k = 0;
  if (!names) names = none;
  while (names[n]) n++;
  if (get_choice(c, y, "integrator method", names, n, &k)) return -1;
  snprintf(c->m->opt.method, sizeof c->m->opt.method, "%s", names[k]);
  return 0;
}

static int load_integrator(const ctx *c, const ynode *y) {
  sw_options *o = &c->m->opt;
  const ynode *v[10], *nv[2];
  if (get_map(c, y, "integrator", int_keys, 10, v)) return -1;
  if (v[5] && get_num(c, v[5], "integrator rtol", 0, 1, NULL, &o->rtol)) return -1;
  if (v[6] && get_num(c, v[6], "integrator atol", 0, 1, NULL, &o->atol)) return -1;
  if (v[7] && get_int(c, v[7], "integrator max_order", 1, 5, &o->max_order)) return -1;
  if (v[8] && get_num(c, v[8], "integrator max_step", 0, 0, "s", &o->max_step)) return -1;
  if (v[9] && get_num(c, v[9], "integrator energy_bound", 0, 1, "J", &o->energy_bound))
    return -1;
  if (v[4] && get_choice(c, v[4], "integrator hessian", hessian_modes, 3, &o->hessian)) return -1;
  if (v[0] && load_method(c, v[0])) return -1;
  if (v[1] && get_num(c, v[1], "integrator dt", 0, 1, "s", &o->dt)) return -1;
  if (v[2] && get_int(c, v[2], "integrator max_halvings", 0, 60, &o->max_halvings)) return -1;
  if (!v[3]) return 0;
  if (get_map(c, v[3], "integrator newton", newton_keys, 2, nv)) return -1;
  if (nv[0] &&
      get_int(c, nv[0], "integrator newton max_iterations", 1, INT_MAX, &o->newton_max))
    return -1;
  if (nv[1] && get_num(c, nv[1], "integrator newton tol", 0, 1, NULL, &o->newton_tol)) return -1;
  return 0;
}

static const char *const out_keys[] = {"dir", "frames_every"};

static int load_output(const ctx *c, const ynode *y) {
  sw_options *o = &c->m->opt;
  const ynode *v[2];
  const char *dir;
  if (get_map(c, y, "output", out_keys, 2, v)) return -1;
  if (v[0]) {
    if (get_str(c, v[0], "output dir", sizeof o->out_dir, &dir)) return -1;
    snprintf(o->out_dir, sizeof o->out_dir, "%s", dir);
  }
  if (v[1] && get_num(c, v[1], "output frames_every", 0, 0, "s", &o->frames_every)) return -1;
  return 0;
}

static const char *const txy_keys[] = {"clip", "reference", "k_u", "k_v"};
static const char *const txy_refs[] = {"initial", "uv"};

static int load_tension_xy(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  sw_options *o = &m->opt;
  const ynode *v[4];
  if (!y) return 0;
  if (get_map(c, y, "tension_xy", txy_keys, 4, v)) return -1;
  if (v[0] && get_num(c, v[0], "tension_xy clip", 0, 1, "N/m", &o->tx_clip)) return -1;
  if (v[1] && get_choice(c, v[1], "tension_xy reference", txy_refs, 2, &o->tx_reference_uv))
    return -1;
  if (v[2] && get_num(c, v[2], "tension_xy k_u", 0, 0, "N/m", &o->tx_k_u)) return -1;
  if (v[3] && get_num(c, v[3], "tension_xy k_v", 0, 0, "N/m", &o->tx_k_v)) return -1;
  return 0;
}

static int load_options(const ctx *c, const ynode **v) {
  sw_options *o = &c->m->opt;
  if (v[K_INT] && load_integrator(c, v[K_INT])) return -1;
  if (v[K_DUR] && get_num(c, v[K_DUR], "duration", 0, 0, "s", &o->duration)) return -1;
  if (v[K_OUT] && load_output(c, v[K_OUT])) return -1;
  return load_tension_xy(c, v[K_TXY]);
}

/* ================================================================ entry points */

static int load_scene(ctx *c) {
  const ynode *v[K_N];
  if (get_map(c, c->root, "the scene", top_keys, K_N, v)) return -1;
  if (load_name_dim(c, v) || load_geometry(c, v) || load_gravity(c, v[K_GRAV])) return -1;
  if (v[K_PINS] && load_pins(c, v[K_PINS])) return -1;
  if (v[K_IV] && load_velocities(c, v[K_IV])) return -1;
  return load_options(c, v);
}

sw_model *sw_scene_parse(const char *name, const char *buf, size_t len, char *err,
                         size_t errsz) {
  if (err && errsz) err[0] = '\0';
  if (!name) name = "<scene>";
  if (!buf) len = 0;
  ynode *root = yaml_parse(name, buf, len, err, errsz);
  if (!root) return NULL;
  ctx c = {.name = name, .err = err, .errsz = errsz, .root = root};
  c.m = sw_model_new();
  int rc = c.m ? load_scene(&c) : oom(&c, root);
  sw_free(c.sel);
  node_free(root);
  if (rc) {
    sw_model_free(c.m);
    return NULL;
  }
  char e[SW_ERRSZ];
  if (sw_model_finish(c.m, e, sizeof e)) {
    sw_errf(err, errsz, "%s: %s", name, e);
    sw_model_free(c.m);
    return NULL;
  }
  return c.m;
}

/* The whole file into a NUL-terminated buffer; NULL with err. */
static char *read_file(const char *path, size_t *len, char *err, size_t errsz) {
  FILE *f = fopen(path, "rb");
  if (!f) {
    sw_errf(err, errsz, "%s: cannot open the scene file: %s", path, strerror(errno));
    return NULL;
  }
  size_t n = 0, cap = 4096;
  char *buf = sw_calloc(cap, 1);
  while (buf) {
    n += fread(buf + n, 1, cap - n - 1, f);
    if (n + 1 < cap || ferror(f) || n > (size_t)SW_SCENE_MAX_BYTES) break;
    char *b = sw_realloc(buf, 2 * cap, 1);
    if (!b) sw_free(buf);
    buf = b;
    cap *= 2;
  }
  int bad = !buf || ferror(f) || n > (size_t)SW_SCENE_MAX_BYTES;
  if (!buf) sw_errf(err, errsz, "%s: out of memory reading the scene file", path);
  else if (ferror(f)) sw_errf(err, errsz, "%s: cannot read the scene file: %s", path,
                              strerror(errno));
  else if (bad) sw_errf(err, errsz, "%s: the scene file is larger than %ld bytes; expected a "
                        "smaller file", path, (long)SW_SCENE_MAX_BYTES);
  fclose(f);
  if (bad) {
    sw_free(buf);
    return NULL;
  }
  buf[n] = '\0';
  *len = n;
  return buf;
}

sw_model *sw_scene_load(const char *path, char *err, size_t errsz) {
  size_t len = 0;
  if (!path) {
    sw_errf(err, errsz, "(null): no scene file given");
    return NULL;
  }
  char *buf = read_file(path, &len, err, errsz);
  if (!buf) return NULL;
  sw_model *m = sw_scene_parse(path, buf, len, err, errsz);
  sw_free(buf);
  return m;
}
