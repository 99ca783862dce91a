/* damping.c — Rayleigh damping D = alpha M + beta K(x) (DESIGN.md "Integrators"), K the
 * PSD-projected Hessian of the terms, so v.D v >= 0: damping only dissipates.  The Newton-based
 * methods hold D on the system pattern, frozen per step at a predictor of the stage state
 * (newton.c, sw_newton_damping); CVODE, IDA and symplectic Euler use D(x) v at the current state
 * (this file).  docs/integrators.md, "Damping". */
#include <string.h>

#include "solver.h"

int sw_damped(const sw_model *m) { return m->damp_mass > 0.0 || m->damp_stiffness > 0.0; }

/* out += beta * (sum of the Hessian blocks) v, block by block. */
static void add_blocks(const sw_model *m, const sw_data *d, double beta, const double *v,
                       double *out) {
  const int dim = m->dim;
  for (int k = 0; k < m->nterm; k++) {
    const sw_term *t = &m->term[k];
    const double *h = d->hess + d->hoff[k];
    for (int s = 0; s < t->nstencil; s++) {
      const int *idx = t->sidx + t->sptr[s];
      int w = (t->sptr[s + 1] - t->sptr[s]) * dim;
      const double *b = h + t->hptr[s];
      for (int i = 0; i < w; i++) {
        double acc = 0.0;
        for (int j = 0; j < w; j++) acc += b[i * w + j] * v[idx[j / dim] * dim + j % dim];
        out[idx[i / dim] * dim + i % dim] += beta * acc;
      }
    }
  }
}

int sw_damping_force(const sw_model *m, sw_data *d, const double *x, double t, const double *v,
                     double *out, double *power) {
  const int dim = m->dim, nd = m->nv * dim;
  memset(out, 0, (size_t)nd * sizeof(double));
  if (m->damp_stiffness > 0.0) {
    double u;
    int rc = sw_eval_terms(m, d, x, t, 0, 1, 1, &u);
    if (rc) return rc;
    add_blocks(m, d, m->damp_stiffness, v, out);
  }
  double p = 0.0; /* W */
  for (int i = 0; i < nd; i++) {
    if (m->dof[i] < 0) {
      out[i] = 0.0;
      continue;
    }
    out[i] += m->damp_mass * m->mass[i / dim] * v[i];
    p += v[i] * out[i];
  }
  if (power) *power = p;
  return SW_OK;
}
