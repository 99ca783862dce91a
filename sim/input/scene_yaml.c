/* scene_yaml.c — the YAML tree of the scene loader and its schema getters (scene_yaml.h).
 *
 * The YAML text is parsed with libfyaml's event parser into a small tree of our own (ynode)
 * that keeps the 1-based line and column of every node (the libfyaml of Debian 12 has no
 * public node positions); libfyaml's own diagnostics are collected, never printed. */
#include "scene_yaml.h"

#include "scene.h"
#include "util.h"

#include <errno.h>
#include <float.h>
#include <libfyaml.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ================================================================ the YAML tree */


typedef struct yparser {
  struct fy_parser *fyp;
  struct fy_diag *diag;
  const char *name;  /* file name for messages */
  const char *buf;   /* the YAML text */
  size_t len;        /* bytes in buf */
  char *err;
  size_t errsz;
  int line, col;     /* position of the last event that had one, 1-based */
  long nodes;        /* nodes made so far (at most SW_SCENE_MAX_VALUES) */
} yparser;

void sy_free(ynode *y) {
  if (!y) return;
  for (int i = 0; i < y->n; i++) sy_free(y->kid[i]);
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

static void *too_many_values(yparser *p);

static ynode *node_new(yparser *p, int kind) {
  if (++p->nodes > SW_SCENE_MAX_VALUES) return too_many_values(p);
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
    sy_free(y);
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
      sy_free(kid);
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
    sy_free(y);
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
    sy_free(root);
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

static void *too_many_values(yparser *p) {
  return yerr(p, "more than %ld YAML values (numbers, strings, lists); expected a smaller "
              "scene (the loader's memory budget: each value may take 0.5 kB)",
              (long)SW_SCENE_MAX_VALUES);
}

/* Refuse a NUL byte (it ends libfyaml's input silently) and invalid UTF-8 (libfyaml 0.7.12
 * loops forever on some, e.g. "%r\xff"), with the position of the offending byte; and explicit
 * mapping keys ("? key"), which no scene needs and on which Debian 12's libfyaml crashes while
 * destroying its parser after some errors (found by fuzzing).  Also
 * refuse more commas than SW_SCENE_MAX_VALUES outside comments: libfyaml scans a whole flow
 * sequence before it yields its first item (30 million indices took 12 GB and 74 s), and in a
 * flow collection each comma follows a value, so the values are at least the commas. */
/* Whether the '?' at s[i] is YAML's explicit-key indicator: followed by a blank or the end, and
 * preceded on its line (blanks skipped) by nothing, '-', '{', '[' or ','. */
static int explicit_key(const unsigned char *s, size_t i, size_t len) {
  if (s[i] != '?' || (i + 1 < len && s[i + 1] != ' ' && s[i + 1] != '\t' && s[i + 1] != '\n' &&
                      s[i + 1] != '\r'))
    return 0;
  size_t j = i;
  while (j > 0 && (s[j - 1] == ' ' || s[j - 1] == '\t')) j--;
  return j == 0 || s[j - 1] == '\n' || s[j - 1] == '-' || s[j - 1] == '{' || s[j - 1] == '[' ||
         s[j - 1] == ',';
}

static int check_text(yparser *p, const char *buf, size_t len) {
  const unsigned char *s = (const unsigned char *)buf;
  long commas = 0;
  int comment = 0, quote = 0; /* in a comment; in a '...' or "..." scalar (its quote char) */
  p->line = p->col = 1;
  for (size_t i = 0; i < len;) {
    size_t k = s[i] ? utf8_len(s + i, len - i) : 0;
    if (k == 0) {
      yerr(p, "%s; expected UTF-8 text", s[i] ? "a byte that is not valid UTF-8" : "a NUL byte");
      return -1;
    }
    if (s[i] == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t' || s[i - 1] == '\n'))
      comment = 1;
    if (s[i] == ',' && !comment && ++commas > SW_SCENE_MAX_VALUES)
      return too_many_values(p), -1;
    if (!comment && (s[i] == '\'' || s[i] == '"') && (!quote || quote == s[i]))
      quote = quote ? 0 : s[i];
    if (!comment && !quote && explicit_key(s, i, len)) { /* libfyaml 0.8 crashes on some */
      yerr(p, "an explicit mapping key ('? '); expected plain keys (key: value)");
      return -1;
    }
    if (s[i] == '\n') p->line++, p->col = 1, comment = 0;
    else p->col++;
    i += k;
  }
  p->line = p->col = 1;
  return 0;
}

/* Parse YAML text into a ynode tree; NULL with "name:line:column: ..." in err. */
ynode *sy_parse(const char *name, const char *buf, size_t len, char *err, size_t errsz) {
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


int sy_fail(const ctx *c, const ynode *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
int sy_fail(const ctx *c, const ynode *at, const char *fmt, ...) {
  char msg[SW_ERRSZ];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  sw_errf(c->err, c->errsz, "%s:%d:%d: %s", c->name, at->line, at->col, msg);
  return -1;
}

int sy_oom(const ctx *c, const ynode *at) { return sy_fail(c, at, "out of memory"); }

int sy_is_null(const ynode *y) {
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
int sy_scalar_number(const ynode *y, double *v) {
  if (y->kind != Y_SCALAR || !y->plain || strlen(y->text) != y->len) return -1;
  if (is_special_float(y->text)) return 1;
  if (!number_syntax(y->text)) return -1;
  *v = strtod(y->text, NULL);
  return isfinite(*v) ? 0 : 1;
}

/* A scalar's text for a message: at most 40 bytes, control characters shown as '?'. */
const char *sy_clip(const ynode *y, char *t, size_t sz) {
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
const char *sy_describe(const ynode *y, char *buf, size_t sz) {
  char t[48];
  double v;
  if (y->kind == Y_MAP) return "a mapping";
  if (y->kind == Y_SEQ) return "a sequence";
  if (sy_is_null(y)) return "empty";
  sy_clip(y, t, sizeof t);
  int num = sy_scalar_number(y, &v);
  if (num == 0) snprintf(buf, sz, "%s", t);
  else if (num == 1) snprintf(buf, sz, "%s (not finite)", t);
  else if (y->plain) snprintf(buf, sz, "'%s'", t);
  else snprintf(buf, sz, "the quoted string \"%s\"", t);
  return buf;
}

/* "a, b, c" */
const char *sy_join(const char *const *names, int n, char *buf, size_t sz) {
  size_t at = 0;
  buf[0] = '\0';
  for (int i = 0; i < n && names[i] && at < sz; i++) {
    int w = snprintf(buf + at, sz - at, "%s%s", i ? ", " : "", names[i]);
    if (w < 0) break;
    at += (size_t)w;
  }
  return buf;
}

int sy_type_error(const ctx *c, const ynode *y, const char *what, const char *expected) {
  char d[96];
  return sy_fail(c, y, "%s is %s; expected %s", what, sy_describe(y, d, sizeof d), expected);
}

/* A mapping whose keys are all in keys[]: val[i] is the value of keys[i] or NULL. */
int sy_map(const ctx *c, const ynode *y, const char *what, const char *const *keys,
                   int nkeys, const ynode **val) {
  char list[256], d[96];
  sy_join(keys, nkeys, list, sizeof list);
  for (int i = 0; i < nkeys; i++) val[i] = NULL;
  if (y->kind != Y_MAP) {
    char exp[300];
    snprintf(exp, sizeof exp, "a mapping with keys among: %s", list);
    return sy_type_error(c, y, what, exp);
  }
  for (int p = 0; p < y->n / 2; p++) {
    const ynode *k = y->kid[2 * p];
    int i = 0;
    if (k->kind == Y_SCALAR && strlen(k->text) == k->len)
      while (i < nkeys && strcmp(k->text, keys[i])) i++;
    else
      i = nkeys;
    if (i == nkeys && k->kind != Y_SCALAR)
      return sy_fail(c, k, "%s has %s as a key; expected one of: %s", what,
                  sy_describe(k, d, sizeof d), list);
    if (i == nkeys)
      return sy_fail(c, k, "%s has an unknown key '%s'; expected one of: %s", what,
                  sy_clip(k, d, sizeof d), list);
    if (val[i])
      return sy_fail(c, k, "%s has a duplicate key '%s'; expected each key once", what, keys[i]);
    val[i] = y->kid[2 * p + 1];
  }
  return 0;
}

int sy_need(const ctx *c, const ynode *map, const ynode *val, const char *what,
                    const char *key, const char *hint) {
  if (val) return 0;
  return sy_fail(c, map, "%s has no '%s' key; expected %s", what, key, hint);
}

/* "a number > 0 (s)" */
static const char *num_expect(char *buf, size_t sz, double lo, int strict, const char *unit) {
  int at = lo == -HUGE_VAL ? snprintf(buf, sz, "a number")
                           : snprintf(buf, sz, "a number %s %g", strict ? ">" : ">=", lo);
  if (unit && at >= 0 && (size_t)at < sz) snprintf(buf + at, sz - (size_t)at, " (%s)", unit);
  return buf;
}

/* A number written nonzero that is zero or subnormal as a double (strtod: ERANGE). */
static int underflows(const ynode *y) {
  errno = 0;
  double v = strtod(y->text, NULL);
  return errno == ERANGE && fabs(v) < DBL_MIN;
}

/* A finite number >= lo (> lo when strict; lo = -HUGE_VAL: any), not below the smallest normal
 * double in magnitude unless it is 0 (1e-320 would silently lose digits or become 0; the
 * command line refuses it the same way, sim/cli/cli.c). */
int sy_num(const ctx *c, const ynode *y, const char *what, double lo, int strict,
                   const char *unit, double *out) {
  double v = 0;
  char exp[96], t[48];
  if (!sy_scalar_number(y, &v) && underflows(y))
    return sy_fail(c, y, "%s is %s, too small to compute with (below %g); expected %s", what,
                   sy_clip(y, t, sizeof t), DBL_MIN,
                   num_expect(exp, sizeof exp, lo, strict, unit));
  if (sy_scalar_number(y, &v) || (strict ? !(v > lo) : !(v >= lo)))
    return sy_type_error(c, y, what, num_expect(exp, sizeof exp, lo, strict, unit));
  *out = v;
  return 0;
}

/* A decimal integer in [lo, hi]. */
int sy_int(const ctx *c, const ynode *y, const char *what, long lo, long hi, int *out) {
  char exp[96];
  snprintf(exp, sizeof exp, "an integer in [%ld, %ld]", lo, hi);
  const char *s = y->text;
  if (y->kind != Y_SCALAR || !y->plain || strlen(s) != y->len) return sy_type_error(c, y, what, exp);
  const char *d = s + (*s == '+' || *s == '-');
  size_t nd = strspn(d, "0123456789");
  if (nd == 0 || d[nd] != '\0') return sy_type_error(c, y, what, exp);
  errno = 0;
  long v = strtol(s, NULL, 10);
  if (errno || v < lo || v > hi) return sy_type_error(c, y, what, exp);
  *out = (int)v;
  return 0;
}

/* A non-empty string of fewer than maxsz bytes. */
int sy_str(const ctx *c, const ynode *y, const char *what, size_t maxsz,
                   const char **out) {
  if (y->kind != Y_SCALAR || sy_is_null(y)) return sy_type_error(c, y, what, "a string");
  if (strlen(y->text) != y->len)
    return sy_fail(c, y, "%s contains a NUL character; expected text", what);
  if (y->len == 0) return sy_fail(c, y, "%s is an empty string; expected a non-empty string", what);
  if (y->len >= maxsz)
    return sy_fail(c, y, "%s is %zu bytes long; expected at most %zu", what, y->len, maxsz - 1);
  *out = y->text;
  return 0;
}

/* A string among choices[]: its index. */
int sy_choice(const ctx *c, const ynode *y, const char *what, const char *const *choices,
                      int n, int *out) {
  char list[256], exp[300];
  snprintf(exp, sizeof exp, "one of: %s", sy_join(choices, n, list, sizeof list));
  if (y->kind != Y_SCALAR || sy_is_null(y) || strlen(y->text) != y->len)
    return sy_type_error(c, y, what, exp);
  for (int i = 0; i < n && choices[i]; i++)
    if (!strcmp(y->text, choices[i])) return *out = i, 0;
  return sy_type_error(c, y, what, exp);
}

int sy_seq(const ctx *c, const ynode *y, const char *what, const char *expected) {
  return y->kind == Y_SEQ ? 0 : sy_type_error(c, y, what, expected);
}

/* A sequence of exactly n numbers, each >= lo (> lo when strict). */
int sy_vec(const ctx *c, const ynode *y, const char *what, int n, double lo, int strict,
                   const char *unit, double *out) {
  char exp[160], lab[224];
  snprintf(exp, sizeof exp, "a sequence of %d numbers (%s)", n, unit ? unit : "");
  if (sy_seq(c, y, what, exp)) return -1;
  if (y->n != n) return sy_fail(c, y, "%s has %d components; expected %d", what, y->n, n);
  for (int i = 0; i < n; i++) {
    snprintf(lab, sizeof lab, "%s[%d]", what, i);
    if (sy_num(c, y->kid[i], lab, lo, strict, unit, out + i)) return -1;
  }
  return 0;
}

