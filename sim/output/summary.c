/* summary.c — summary.json (writer.h): scene, method, counters, timers, wall time, peak memory,
 * status and message, and the files of the folder (each format names its own).  Written through
 * summary.json.tmp and rename: at open with status "running", at close "ok" or "failed". */
#include <math.h>
#include <string.h>
#include <sys/resource.h>

#include "contact.h"
#include "contact_geom.h"
#include "terms.h"
#include "writer.h"

/* Length of the well-formed UTF-8 sequence (RFC 3629) at s, of at most rem bytes; 0 if none. */
static int utf8_len(const unsigned char *s, size_t rem) {
  unsigned c = s[0], lo = 0x80, hi = 0xBF;
  int n;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) n = 3, lo = c == 0xE0 ? 0xA0 : lo, hi = c == 0xED ? 0x9F : hi;
  else if (c >= 0xF0 && c <= 0xF4) n = 4, lo = c == 0xF0 ? 0x90 : lo, hi = c == 0xF4 ? 0x8F : hi;
  else return 0;
  if ((size_t)n > rem || s[1] < lo || s[1] > hi) return 0;
  for (int i = 2; i < n; i++)
    if (s[i] < 0x80 || s[i] > 0xBF) return 0;
  return n;
}

/* A JSON string of at most maxlen bytes of s: quotes, backslashes and control characters
 * escaped, ill-formed UTF-8 replaced by U+FFFD. */
void out_json_str(out_file *w, const char *s, size_t maxlen) {
  if (!s) {
    out_puts(w, "null");
    return;
  }
  const unsigned char *p = (const unsigned char *)s, *end = p + strnlen(s, maxlen);
  out_puts(w, "\"");
  while (p < end) {
    char buf[8];
    int n = utf8_len(p, (size_t)(end - p));
    if (n == 0) snprintf(buf, sizeof buf, "\\ufffd"), n = 1;
    else if (*p == '"' || *p == '\\') snprintf(buf, sizeof buf, "\\%c", *p);
    else if (*p < 0x20) snprintf(buf, sizeof buf, "\\u%04X", *p);
    else memcpy(buf, p, (size_t)n), buf[n] = '\0';
    out_puts(w, buf);
    p += n;
  }
  out_puts(w, "\"");
}

static void w_key(out_file *w, const char *key) { out_printf(w, ",\n  \"%s\": ", key); }

static void w_json_num(out_file *w, const char *key, double v) {
  w_key(w, key);
  char buf[SW_OUT_NUMSZ];
  if (isfinite(v)) out_fmt_num(buf, sizeof buf, v), out_puts(w, buf);
  else out_puts(w, "null");
}

static void w_json_long(out_file *w, const char *key, long v) {
  w_key(w, key);
  out_printf(w, "%ld", v);
}

/* The fields the terms add (sw_term_ops.summary) at `at` (SW_SUMMARY_*). */
static void summary_terms(out_file *w, const sw_model *m, const sw_data *d, int at) {
  for (int k = 0; d && k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    sw_field f[8];
    void *data = d->tdata ? d->tdata[k] : NULL; /* NULL before the run started */
    int n = t->ops && t->ops->summary ? t->ops->summary(t, m, d, data, at, f, 8) : 0;
    for (int q = 0; q < n && q < 8; q++) {
      if (f[q].is_count) w_json_long(w, f[q].name, f[q].count);
      else w_json_num(w, f[q].name, f[q].value);
    }
  }
}

static void summary_model(out_file *w, const sw_model *m) {
  w_key(w, "method");
  out_json_str(w, m->opt.method, SW_NAMESZ);
  w_json_long(w, "dimension", m->dim);
  w_json_long(w, "vertices", m->nv);
  w_json_long(w, "faces", m->nf);
  w_json_long(w, "free_dofs", m->ndof);
  w_key(w, "terms");
  out_puts(w, "[");
  for (int k = 0; k < m->nterm; k++) {
    if (k) out_puts(w, ", ");
    out_json_str(w, m->term[k].name, SW_NAMESZ);
  }
  out_puts(w, "]");
  w_json_num(w, "dt", m->opt.dt);             /* s */
  w_json_num(w, "duration", m->opt.duration); /* s */
  w_json_num(w, "stiffness_scale", m->stiffness_scale > 0 ? m->stiffness_scale : 1.0);
  if (sw_method_adaptive(m->opt.method) == 1) {
    w_json_num(w, "rtol", m->opt.rtol);
    w_json_num(w, "atol", m->opt.atol);           /* m and m/s */
    w_json_long(w, "max_order", sw_max_order(m)); /* the order in use, automatic or not */
  }
}

/* Peak resident set size of the process so far, MiB (ru_maxrss is in KiB on Linux); 0 if
 * getrusage fails. */
static double max_rss_mb(void) {
  struct rusage ru;
  if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
  return (double)ru.ru_maxrss / 1024.0;
}

static void summary_counters(out_file *w, const sw_model *m, const sw_data *d, double wall,
                             double cpu) {
  w_json_num(w, "time_reached", d->t);
  w_json_long(w, "steps", d->nstep);
  w_json_long(w, "newton_iterations", d->nnewton);
  w_json_long(w, "factorizations", d->nfactor);
  w_json_long(w, "assemblies", d->nassemble);
  w_json_long(w, "force_evaluations", d->nforce);
  w_json_long(w, "retries", d->nretry);
  w_json_long(w, "linesearch_backtracks", d->nlinesearch);
  w_json_long(w, "cg_iterations", d->ncg);
  w_json_long(w, "newton_bound_iterations", d->nbound);
  w_json_long(w, "error_test_failures", d->nerrfail);
  w_json_long(w, "linear_setups", d->nsetup);
  if (sw_method_adaptive(m->opt.method) == 1) { /* steps at BDF order 1..5 */
    w_key(w, "steps_by_order");
    out_printf(w, "[%ld, %ld, %ld, %ld, %ld]", d->nstep_order[0], d->nstep_order[1],
               d->nstep_order[2], d->nstep_order[3], d->nstep_order[4]);
  }
  w_json_num(w, "time_assemble_s", d->time_assemble);
  w_json_num(w, "time_factor_s", d->time_factor);
  w_json_num(w, "time_solve_s", d->time_solve);
  w_key(w, "time_terms_s"); /* each term's evaluations (in assembly, line searches, logging) */
  out_puts(w, "{");
  for (int k = 0; k < m->nterm; k++) {
    if (k) out_puts(w, ", ");
    out_json_str(w, m->term[k].name, SW_NAMESZ);
    out_printf(w, ": %.6g", d->term_time ? d->term_time[k] : 0.0); /* s */
  }
  out_puts(w, "}");
  if (m->nobstacle > 0) w_json_num(w, "time_contact_s", d->time_contact);
  if (sw_mesh_contact_on(m)) {
    w_json_num(w, "time_self_ccd_s", d->time_ccd);
    w_json_num(w, "time_self_broadphase_s", d->time_broadphase);
    w_json_num(w, "time_pattern_s", d->time_pattern);
    w_json_long(w, "pattern_growths", d->npattern);
    long made, renewed;
    sw_mcontact_listings(d->mc, &made, &renewed);
    w_json_long(w, "candidate_listings", made);
    w_json_long(w, "candidate_renewals", renewed);
  }
  summary_terms(w, m, d, SW_SUMMARY_RUN); /* the adapted contact stiffness's factor */
  w_json_num(w, "time_step_s", d->time_step);
  w_json_long(w, "factor_nnz", d->factor_nnz);
  if (d->factor_super >= 0) {
    w_key(w, "factorization");
    out_json_str(w, d->factor_super ? "supernodal" : "simplicial", 16);
  }
  if (d->factor_ordering > 0) { /* the fill-reducing ordering the analysis used */
    w_key(w, "ordering");
    out_json_str(w, sw_ordering_names()[d->factor_ordering], 16);
  }
  w_json_num(w, "wall_time_s", wall); /* this part (since a --resume) */
  w_json_num(w, "wall_time_total_s", d->wall_before + wall); /* every part of the run */
  /* CPU time (user + system, every thread) of this part: what a busy machine's sharing
   * stretches the wall time by, it does not (docs/benchmarks.md, "Timing on a shared machine") */
  w_json_num(w, "cpu_time_s", cpu);
  w_json_num(w, "max_rss_mb", max_rss_mb());
}

/* A 3D cloth's face pairs (sharing no vertex) that intersect at the state written (an exact
 * test, models/intersect.c, independent of the solver): whether the cloth passed through
 * itself (it cannot with self-contact on).  Only at the end of a run (the state NULL at
 * open). */
static void summary_intersections(out_file *w, const sw_model *m, const sw_data *d) {
  if (!d || m->dim != 3 || m->nf < 2) return;
  long n = sw_mesh_self_intersections_sewn(m->nv, d->x, m->nf, m->face, m->sewn_ptr,
                                           m->sewn_idx);
  if (n >= 0) w_json_long(w, "self_intersections", n);
  /* the cloth's triangles against the mesh obstacles' (it cannot pass through them) */
  summary_terms(w, m, d, SW_SUMMARY_STATE);
}

/* The seams' largest gap at the state written (m) and the fit stage's end, steps and wall time
 * (docs/garments.md). */
static void summary_seams(out_file *w, const sw_model *m, const sw_data *d) {
  if (m->nseam == 0) return;
  w_json_num(w, "seam_gap_max", d->seam_gap_max);
  w_json_num(w, "seam_stiffness", m->seam_stiffness); /* N/m^2 */
  if (!m->fit.on) return;
  static const char *const modes[] = {"dynamic", "optimize", "settle"}; /* SW_FIT_* */
  w_key(w, "fit_mode");
  out_json_str(w, modes[m->fit.mode], SW_NAMESZ);
  w_json_num(w, "fit_end_s", d->fit_end);
  w_json_long(w, "fit_steps", d->fit_steps);
  w_json_num(w, "fit_wall_s", d->fit_wall);
}

/* Where the static solve stopped (sw_data.static_info; docs/integrators.md, "The static
 * solve"). */
static void summary_static(out_file *w, const sw_model *m, const sw_data *d) {
  if (strcmp(m->opt.method, "static")) return;
  const sw_static_info *s = &d->static_info;
  w_json_long(w, "static_iterations", s->iterations);
  w_json_num(w, "static_force_N", s->force);
  w_json_num(w, "static_tol_N", s->tol);
  w_json_num(w, "static_floor_N", s->floor);
  w_json_long(w, "static_roundoff", s->roundoff);
}

typedef struct file_list {
  out_file *w;
  int n;
} file_list;

static void add_file(void *ctx, const char *name) {
  file_list *l = ctx;
  out_printf(l->w, "%s\"%s\"", l->n++ ? ", " : "", name);
}

/* The files of the folder, relative to it, under their current names, as each format says. */
static void summary_files(out_file *w, const sw_output *o) {
  file_list l = {w, 0};
  w_key(w, "files");
  out_puts(w, "[");
  for (int k = 0; k < o->nw; k++)
    if (o->w[k].on && o->w[k].ops->files) o->w[k].ops->files(o->w[k].self, add_file, &l);
  out_puts(w, "]");
}

/* d NULL: the summary written at open (zero counters). */
static int summary_write(void *self, sw_output *o, const sw_model *m, const sw_data *d,
                         char *err, size_t errsz) {
  static const sw_data not_started; /* zero counters for the summary written by open */
  (void)self;
  if (out_join(o->tmp, o->dir, "summary.json.tmp", err, errsz)) return -1;
  if (out_join(o->path, o->dir, "summary.json", err, errsz)) return -1;
  out_file w;
  if (out_tmp_open(&w, o->tmp, err, errsz)) return -1;
  out_puts(&w, "{\n  \"scene\": ");
  out_json_str(&w, m->name, sizeof m->name);
  w_key(&w, "scene_file");
  out_json_str(&w, m->path, sizeof m->path);
  w_key(&w, "status");
  out_json_str(&w, o->status, SW_ERRSZ);
  w_key(&w, "message");
  out_json_str(&w, o->message, 4 * SW_ERRSZ);
  summary_model(&w, m);
  summary_counters(&w, m, d ? d : &not_started, o->wall, o->cpu);
  summary_intersections(&w, m, d);
  summary_seams(&w, m, d ? d : &not_started);
  summary_static(&w, m, d ? d : &not_started);
  summary_files(&w, o);
  out_puts(&w, "\n}\n");
  return out_tmp_commit(&w, o->tmp, o->path, err, errsz);
}

static int summary_open(void *self, sw_output *o, const sw_model *m, char *err, size_t errsz) {
  (void)self, (void)m;
  return out_own(o, "summary.json", err, errsz);
}

const sw_out_ops sw_out_summary = {
    .open = summary_open,
    .name = "summary.json",
    .event = SW_OUT_STATUS,
    .write = summary_write,
};
