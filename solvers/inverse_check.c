/* inverse_check.c — the forward check of the tendon inverse problem (docs/inverse.md): do the
 * rest lengths found by sw_inverse_solve make the tendons exert f on the targets?
 *
 * A model of the tendons alone (no faces, no gravity; every tendon with constant rest length
 * alpha_t, linear density 1 kg/m so that the free vertices have mass for the static solver's
 * Levenberg–Marquardt shift) with every vertex pinned except the targets some tendon with K > 0
 * passes through, and the point loads -f on the targets (models/point_load.c).  The static
 * solve (solvers/static.c) starts from x; at its equilibrium x* the tendon forces on the free
 * targets balance the loads.  Reported: max |x* - x| (m) and |f_tendons - f| / |f| at x and x*,
 * f_tendons = -grad of the "tendons" term on the targets.  The check passes when the solve
 * converged, max |x* - x| <= SW_INVERSE_XTOL x the longest tendon and the force error at x* is
 * <= SW_INVERSE_RTOL. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "inverse.h"
#include "terms.h"
#include "util.h"

static int copy_tendon(sw_tendon *dst, const sw_tendon *src, double rest) {
  *dst = *src;
  dst->way = sw_calloc((size_t)src->nway, sizeof(int));
  dst->key_t = sw_calloc(1, sizeof(double));
  dst->key_rest = sw_calloc(1, sizeof(double));
  if (!dst->way || !dst->key_t || !dst->key_rest) return -1;
  memcpy(dst->way, src->way, (size_t)src->nway * sizeof(int));
  dst->nkey = 1;
  dst->key_rest[0] = rest; /* m, constant */
  dst->density = 1.0;      /* kg/m: mass for the LM shift only (no gravity) */
  dst->damping = 0.0;
  return 0;
}

/* Free the targets that a tendon with K > 0 reaches; pin everything else. */
static void pin_all_but_targets(sw_model *c, const sw_model *m, const sw_targets *tg) {
  unsigned char *reach = c->pinned; /* reused: 2 = reached by a tendon */
  memset(reach, 1, (size_t)c->nv);
  for (int t = 0; t < m->ntendon; t++)
    for (int k = 0; m->tendon[t].stiffness > 0.0 && k < m->tendon[t].nway; k++)
      reach[m->tendon[t].way[k]] = 2;
  for (int k = 0; k < tg->n; k++)
    if (reach[tg->vertex[k]] == 2) reach[tg->vertex[k]] = 0;
  for (int i = 0; i < c->nv; i++) reach[i] = reach[i] != 0;
}

static int fill_check_model(sw_model *c, const sw_model *m, const double *x,
                            const sw_targets *tg, const double *rest) {
  const size_t nd = (size_t)m->nv * (size_t)m->dim;
  snprintf(c->name, sizeof c->name, "%.100s (forward check)", m->name);
  c->dim = m->dim;
  c->nv = m->nv;
  c->x0 = sw_calloc(nd, sizeof(double));
  c->v0 = sw_calloc(nd, sizeof(double));
  c->pinned = sw_calloc((size_t)m->nv, 1);
  c->load = sw_calloc(nd, sizeof(double));
  c->tendon = sw_calloc((size_t)m->ntendon + 1, sizeof(sw_tendon));
  if (!c->x0 || !c->v0 || !c->pinned || !c->load || !c->tendon) return -1;
  memcpy(c->x0, x, nd * sizeof(double));
  pin_all_but_targets(c, m, tg);
  for (int k = 0; k < tg->n; k++)
    for (int a = 0; a < m->dim; a++)
      c->load[tg->vertex[k] * m->dim + a] = -tg->f[k * m->dim + a]; /* N */
  for (int t = 0; t < m->ntendon; t++) {
    c->ntendon = t + 1; /* so that sw_model_free releases what was allocated */
    if (copy_tendon(&c->tendon[t], &m->tendon[t], rest[t])) return -1;
  }
  c->opt.hessian = m->opt.hessian;
  return 0;
}

/* |f_tendons(x) - f| on the targets, relative to |f| (|f| = 0: absolute, N). */
static int force_error(const sw_model *c, const double *x, const sw_targets *tg, double *out) {
  const int d = c->dim;
  int k = 0;
  while (k < c->nterm && strcmp(c->term[k].name, "tendons")) k++;
  double *g = sw_calloc((size_t)c->nv * d, sizeof(double)), e = 0.0, fn = 0.0;
  if (!g) return -1;
  if (k < c->nterm) {
    sw_eval ev = {.t = 0.0, .x = x, .grad = g};
    int rc = c->term[k].ops->eval(&c->term[k], c, &ev, &e);
    if (rc) return sw_free(g), rc;
  }
  e = 0.0;
  for (int j = 0; j < tg->n; j++)
    for (int a = 0; a < d; a++) {
      double ft = -g[tg->vertex[j] * d + a], f = tg->f[j * d + a]; /* N */
      e += (ft - f) * (ft - f);
      fn += f * f;
    }
  sw_free(g);
  *out = fn > 0.0 ? sqrt(e / fn) : sqrt(e);
  return 0;
}

static double max_move(const sw_model *c, const double *x0, const double *x) {
  double mx = 0.0;
  for (int i = 0; i < c->nv; i++) {
    double s = 0.0;
    for (int a = 0; a < c->dim; a++) {
      double dx = x[i * c->dim + a] - x0[i * c->dim + a];
      s += dx * dx;
    }
    mx = fmax(mx, sqrt(s)); /* m */
  }
  return mx;
}

static int run_check(const sw_model *c, const sw_targets *tg, sw_inverse *inv, char *err,
                     size_t errsz) {
  sw_data *d = sw_data_new(c);
  if (!d) return sw_errf(err, errsz, "forward check: out of memory"), SW_FATAL;
  double reaction[3], lmax = 0.0;
  int rc = force_error(c, c->x0, tg, &inv->check_ferr0);
  if (!rc) {
    char why[SW_ERRSZ] = "";
    inv->check_rc = sw_static_solve(c, d, reaction, why, sizeof why);
    if (inv->check_rc < 0) sw_errf(err, errsz, "forward check: %s", why);
    rc = inv->check_rc < 0 ? inv->check_rc : force_error(c, d->x, tg, &inv->check_ferr);
  }
  inv->check_dx = max_move(c, c->x0, d->x);
  for (int t = 0; t < inv->ntendon; t++) lmax = fmax(lmax, inv->length[t]);
  inv->check_pass = !rc && inv->check_rc == SW_OK &&
                    inv->check_dx <= SW_INVERSE_XTOL * (lmax > 0.0 ? lmax : 1.0) &&
                    inv->check_ferr <= SW_INVERSE_RTOL;
  sw_data_free(d);
  if (rc > 0) sw_errf(err, errsz, "forward check: a tendon term failed (%d)", rc);
  return rc;
}

int sw_inverse_check(const sw_model *m, const double *x, const sw_targets *tg, sw_inverse *inv,
                     char *err, size_t errsz) {
  inv->check_pass = 0;
  sw_model *c = sw_model_new();
  if (!c || fill_check_model(c, m, x, tg, inv->rest)) {
    sw_model_free(c);
    return sw_errf(err, errsz, "forward check: out of memory"), SW_FATAL;
  }
  char why[SW_ERRSZ];
  if (sw_model_finish(c, why, sizeof why)) {
    sw_model_free(c);
    return sw_errf(err, errsz, "forward check: %s", why), SW_FATAL;
  }
  int rc = run_check(c, tg, inv, err, errsz);
  sw_model_free(c);
  return rc;
}
