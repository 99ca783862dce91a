/* damping.c — the damping matrix D = alpha M + beta K(x) + sum_t c_t grad l_t grad l_t^T
 * (docs/integrators.md): Rayleigh damping, K the PSD-projected Hessian of the terms, and
 * tendon damping, the force -c_t (dl_t/dt) grad l_t along each tendon.  v.D v >= 0: damping
 * only dissipates.  The Newton-based
 * methods hold D on the system pattern, frozen per step at a predictor of the stage state
 * (newton.c, sw_newton_damping); CVODE, IDA and symplectic Euler use D(x) v at the current state
 * (this file).  docs/integrators.md, "Damping". */
#include <string.h>

#include "solver.h"
#include "terms.h"

int sw_damped(const sw_model *m) {
  int tendons = 0;
  for (int k = 0; k < m->ntendon; k++) tendons |= m->tendon[k].damping > 0.0;
  return m->damp_mass > 0.0 || m->damp_stiffness > 0.0 || tendons;
}

/* out += c g (g.v) for each damped tendon, g = grad l at x (nway x dim, in scratch g). */
static void add_tendons(const sw_model *m, const double *x, const double *v, double *out) {
  const int d = m->dim;
  double g[3];
  for (int k = 0; k < m->ntendon; k++) {
    const sw_tendon *td = &m->tendon[k];
    if (!(td->damping > 0.0)) continue;
    double rate = 0.0; /* dl/dt, m/s */
    for (int a = 0; a < td->nway; a++) {
      sw_tendon_grad(td, x, d, a, g);
      for (int c = 0; c < d; c++) rate += g[c] * v[td->way[a] * d + c];
    }
    for (int a = 0; a < td->nway; a++) {
      sw_tendon_grad(td, x, d, a, g);
      for (int c = 0; c < d; c++) out[td->way[a] * d + c] += td->damping * rate * g[c]; /* N */
    }
  }
}

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
        for (int j = 0; j < w; j++) acc += sw_hess_get(b, i, j, w) * v[idx[j / dim] * dim + j % dim];
        out[idx[i / dim] * dim + i % dim] += beta * acc;
      }
    }
  }
}

void sw_damping_tendons_fill(const sw_pattern *p, const sw_model *m, const double *x,
                             double *values) {
  const int d = m->dim;
  double ga[3], gb[3];
  for (int k = 0; k < m->ntendon; k++) {
    const sw_tendon *td = &m->tendon[k];
    if (!(td->damping > 0.0)) continue;
    for (int a = 0; a < td->nway; a++) {
      sw_tendon_grad(td, x, d, a, ga);
      for (int b = 0; b < td->nway; b++) {
        sw_tendon_grad(td, x, d, b, gb);
        for (int i = 0; i < d; i++)
          for (int j = 0; j < d; j++) {
            int r = m->dof[td->way[a] * d + i], c = m->dof[td->way[b] * d + j];
            long q = r < 0 || c < 0 || r > c ? -1 : sw_pattern_slot(p, r, c);
            if (q >= 0) values[q] += td->damping * ga[i] * gb[j]; /* N s/m */
          }
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
  add_tendons(m, x, v, out);
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
