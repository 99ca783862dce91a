/* sim_access.c — the stepping API by name, for bindings that do not read C structs (the Python
 * package python/sinew reads it through ctypes): arrays, counters, sizes and names of a sim, and
 * the options of a model before a sim is made from it. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "solver.h"
#include "util.h"

typedef struct named_array {
  const char *name;
  size_t offset;               /* of the double * in sw_data, or (model) in sw_model */
  int model;                   /* 1: a field of sw_model */
  char rows, cols;             /* 'v' nv, 'f' nf, 't' ntendon, 'e' nterm, 'd' dim, or a digit */
} named_array;

static const named_array arrays[] = {
    {"x", offsetof(sw_data, x), 0, 'v', 'd'},
    {"v", offsetof(sw_data, v), 0, 'v', 'd'},
    {"tension_xy", offsetof(sw_data, txy), 0, 'f', '1'},
    {"stretch_u", offsetof(sw_data, stretch_u), 0, 'f', '1'},
    {"stretch_v", offsetof(sw_data, stretch_v), 0, 'f', '1'},
    {"shear", offsetof(sw_data, shear), 0, 'f', '1'},
    {"tendon_length", offsetof(sw_data, tendon_length), 0, 't', '1'},
    {"tendon_tension", offsetof(sw_data, tendon_tension), 0, 't', '1'},
    {"tendon_delta", offsetof(sw_data, tendon_delta), 0, 't', '1'},
    {"term_energy", offsetof(sw_data, term_energy), 0, 'e', '1'},
    {"contact_pressure", offsetof(sw_data, contact_pressure), 0, 'f', '1'},
    {"x0", offsetof(sw_model, x0), 1, 'v', 'd'},
    {"mass", offsetof(sw_model, mass), 1, 'v', '1'},
    {"area", offsetof(sw_model, area), 1, 'f', '1'},
    {"uv", offsetof(sw_model, uv), 1, 'f', '6'},
    {"load", offsetof(sw_model, load), 1, 'v', 'd'},
};

/* The extent a shape letter stands for. */
static int extent(const sw_model *m, char c) {
  switch (c) {
  case 'v': return m->nv;
  case 'f': return m->nf;
  case 't': return m->ntendon;
  case 'e': return m->nterm;
  case 'd': return m->dim;
  default: return c - '0';
  }
}

double *sw_sim_array(sw_sim *s, const char *name, int *rows, int *cols) {
  const sw_model *m = sw_sim_model(s);
  const sw_data *d = sw_sim_data(s);
  if (!strcmp(name, "energy")) { /* inline in sw_data */
    if (rows) *rows = 4;
    if (cols) *cols = 1;
    return (double *)d->energy;
  }
  for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++) {
    const named_array *a = &arrays[k];
    if (strcmp(a->name, name)) continue;
    const char *base = a->model ? (const char *)m : (const char *)d;
    double *p = *(double *const *)(base + a->offset);
    if (rows) *rows = extent(m, a->rows);
    if (cols) *cols = extent(m, a->cols);
    return p;
  }
  return NULL;
}

int *sw_sim_iarray(sw_sim *s, const char *name, int *rows, int *cols) {
  const sw_model *m = sw_sim_model(s);
  int r = 0, c = 0, *p = NULL;
  if (!strcmp(name, "face")) r = m->nf, c = 3, p = m->face;
  else if (!strcmp(name, "dof")) r = m->nv, c = m->dim, p = m->dof;
  if (rows) *rows = r;
  if (cols) *cols = c;
  return p;
}

static const char *const counter_names[] = {"nstep",  "nnewton",     "nfactor",  "nassemble",
                                            "nforce", "nretry",      "nlinesearch", "nerrfail",
                                            "nsetup", "ncg", "nbound"};
#define NCOUNTER (int)(sizeof counter_names / sizeof *counter_names)

int sw_sim_counters(const sw_sim *s, long *out, int n) {
  const sw_data *d = sw_sim_data(s);
  const long vals[NCOUNTER] = {d->nstep,  d->nnewton,     d->nfactor,  d->nassemble, d->nforce,
                               d->nretry, d->nlinesearch, d->nerrfail, d->nsetup,    d->ncg,
                               d->nbound};
  for (int k = 0; k < n && k < NCOUNTER; k++) out[k] = vals[k];
  return NCOUNTER;
}

long sw_sim_counter(const sw_sim *s, const char *name) {
  long vals[NCOUNTER];
  sw_sim_counters(s, vals, NCOUNTER);
  for (int k = 0; k < NCOUNTER; k++)
    if (!strcmp(counter_names[k], name)) return vals[k];
  return -1;
}

int sw_sim_size(const sw_sim *s, const char *name) {
  const sw_model *m = sw_sim_model(s);
  if (!strcmp(name, "nv")) return m->nv;
  if (!strcmp(name, "dim")) return m->dim;
  if (!strcmp(name, "nf")) return m->nf;
  if (!strcmp(name, "ntendon")) return m->ntendon;
  if (!strcmp(name, "nterm")) return m->nterm;
  if (!strcmp(name, "ndof")) return m->ndof;
  return -1;
}

const char *sw_sim_name(const sw_sim *s, const char *kind, int k) {
  const sw_model *m = sw_sim_model(s);
  if (!strcmp(kind, "tendon") && k >= 0 && k < m->ntendon) return m->tendon[k].name;
  if (!strcmp(kind, "term") && k >= 0 && k < m->nterm) return m->term[k].name;
  if (!strcmp(kind, "method")) return m->opt.method;
  return NULL;
}

int sw_tendon_find(const sw_model *m, const char *name) {
  for (int k = 0; k < m->ntendon; k++)
    if (!strcmp(m->tendon[k].name, name)) return k;
  return -1;
}

int sw_term_find(const sw_model *m, const char *name) {
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].name, name)) return k;
  return -1;
}

/* ------------------------------------------------------------------ options */

typedef struct num_option {
  const char *key;
  size_t offset;               /* in sw_options */
  int is_int;
  double lo, hi;               /* accepted range (inclusive) */
} num_option;

static const num_option num_options[] = {
    {"dt", offsetof(sw_options, dt), 0, 1e-300, INFINITY},
    {"duration", offsetof(sw_options, duration), 0, 0.0, INFINITY},
    {"rtol", offsetof(sw_options, rtol), 0, 1e-300, 1.0},
    {"atol", offsetof(sw_options, atol), 0, 1e-300, INFINITY},
    {"max_order", offsetof(sw_options, max_order), 1, 0, 5},
    {"max_step", offsetof(sw_options, max_step), 0, 0.0, INFINITY},
    {"newton_tol", offsetof(sw_options, newton_tol), 0, 1e-300, INFINITY},
    {"newton_max", offsetof(sw_options, newton_max), 1, 1, 1e6},
    {"max_halvings", offsetof(sw_options, max_halvings), 1, 0, 60},
    {"frames_every", offsetof(sw_options, frames_every), 0, -INFINITY, INFINITY},
    {"positions_every", offsetof(sw_options, positions_every), 0, 0.0, INFINITY},
};

/* One of names (NULL-terminated) into *index; -1 if none. */
static int choice(const char *const *names, const char *value) {
  for (int k = 0; names[k]; k++)
    if (!strcmp(names[k], value)) return k;
  return -1;
}

static int set_number(sw_options *o, const num_option *n, const char *value, char *err,
                      size_t errsz) {
  char *end;
  double v = strtod(value, &end);
  if (end == value || *end || !(v >= n->lo && v <= n->hi) || (n->is_int && v != floor(v)))
    return sw_errf(err, errsz, "option %s: '%s'; expected %s in [%g, %g]", n->key, value,
                   n->is_int ? "an integer" : "a number", n->lo, n->hi),
           SW_FATAL;
  char *field = (char *)o + n->offset;
  if (n->is_int) *(int *)field = (int)v;
  else *(double *)field = v;
  return SW_OK;
}

int sw_model_set_option(sw_model *m, const char *key, const char *value, char *err,
                        size_t errsz) {
  sw_options *o = &m->opt;
  for (size_t k = 0; k < sizeof num_options / sizeof *num_options; k++)
    if (!strcmp(num_options[k].key, key)) return set_number(o, &num_options[k], value, err, errsz);
  if (!strcmp(key, "method")) {
    if (choice(sw_method_names(), value) < 0)
      return sw_errf(err, errsz, "unknown method '%s'", value), SW_FATAL;
    snprintf(o->method, sizeof o->method, "%s", value);
  } else if (!strcmp(key, "hessian")) {
    int h = choice(sw_hessian_names(), value);
    if (h < 0) return sw_errf(err, errsz, "unknown hessian mode '%s'", value), SW_FATAL;
    o->hessian = h;
  } else if (!strcmp(key, "newton_norm")) {
    int n = choice(sw_norm_names(), value);
    if (n < 0) return sw_errf(err, errsz, "unknown Newton norm '%s'", value), SW_FATAL;
    o->newton_norm = n;
  } else if (!strcmp(key, "frames_format")) {
    int f = choice(sw_frames_format_names(), value);
    if (f < 0) return sw_errf(err, errsz, "unknown frames format '%s'", value), SW_FATAL;
    o->frames_format = f;
  } else if (!strcmp(key, "out")) {
    if (strlen(value) >= sizeof o->out_dir)
      return sw_errf(err, errsz, "option out: the path is too long"), SW_FATAL;
    snprintf(o->out_dir, sizeof o->out_dir, "%s", value);
  } else {
    return sw_errf(err, errsz, "unknown option '%s'", key), SW_FATAL;
  }
  return SW_OK;
}
