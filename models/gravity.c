/* gravity.c — uniform gravity on the lumped masses: E = -r(t) sum_i m_i g.x_i (J), r(t) the
 * ramp sw_ramp(t - m->gravity_delay, m->gravity_ramp) (1 without one).  Linear in x: no Hessian, so it declares
 * no stencils. */
#include <stdio.h>

#include "terms.h"

static int gravity_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  (void)t;
  const int d = m->dim;
  const double r = sw_ramp(ev->t - m->gravity_delay, m->gravity_ramp);
  double e = 0.0;
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < d; a++) {
      double f = r * m->mass[i] * m->gravity[a]; /* N */
      e -= f * ev->x[i * d + a];
      if (ev->grad) ev->grad[i * d + a] -= f;
    }
  *energy = e;
  return SW_OK;
}

static const sw_term_ops gravity_ops = {.kind = "gravity", .eval = gravity_eval};

int sw_gravity_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  t->ops = &gravity_ops;
  snprintf(t->name, sizeof t->name, "%s", "gravity");
  if (sw_term_alloc_stencils(t, 0, 1, m->dim)) {
    snprintf(err, errsz, "out of memory");
    return -1;
  }
  return 0;
}
