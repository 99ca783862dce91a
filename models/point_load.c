/* point_load.c — external point loads on vertices (scene key `loads`): E = -sum_i f_i . x_i (J),
 * f_i = r_i(t) m->load (N), r_i = sw_ramp(t, m->load_ramp[i]) (1 without ramps).  Linear in
 * x: no Hessian, so it declares no stencils. */
#include <stdio.h>

#include "terms.h"

static int load_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  (void)t;
  const long n = (long)m->nv * m->dim;
  double e = 0.0;
  for (long i = 0; i < n; i++) {
    double f = m->load[i] * (m->load_ramp ? sw_ramp(ev->t, m->load_ramp[i / m->dim]) : 1.0);
    e -= f * ev->x[i];
    if (ev->grad) ev->grad[i] -= f;
  }
  *energy = e;
  return SW_OK;
}

static const sw_term_ops load_ops = {.kind = "loads", .eval = load_eval};

int sw_point_load_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  t->ops = &load_ops;
  snprintf(t->name, sizeof t->name, "%s", "loads");
  if (!m->load) {
    snprintf(err, errsz, "loads: the model has no load array");
    return -1;
  }
  if (sw_term_alloc_stencils(t, 0, 1, m->dim)) {
    snprintf(err, errsz, "out of memory");
    return -1;
  }
  return 0;
}
