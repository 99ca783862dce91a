/* energy_check.c — the energy bound that fails a step blowing up (solver.h): the explicit
 * and the Newton integrators check their new state against it. */
#include <math.h>
#include <stdio.h>

#include "solver.h"

int sw_energy_check(const sw_model *m, sw_data *d, const double *x, const double *v, double t) {
  double u;
  int rc = sw_eval_terms(m, d, x, t, 0, 0, 0, &u);
  if (rc) return rc;
  double e = u + sw_kinetic(m, v);
  if (!isfinite(e) || (d->energy_bound > 0.0 && e > d->energy_bound)) {
    snprintf(d->err, sizeof d->err,
             "energy blow-up: total energy %.6g J exceeds the bound %.6g J at t = %g s", e,
             d->energy_bound, t);
    return SW_RECOVER;
  }
  return SW_OK;
}

double sw_energy_bound(const sw_model *m, sw_data *d) {
  double u, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  if (sw_eval_terms(m, d, m->x0, 0.0, 0, 0, 0, &u)) return 0.0;
  double k0 = sw_kinetic(m, m->v0), scale = fabs(u + k0) + k0 + 1e-6, diam = 0.0, g = 0.0;
  for (int k = 0; k < m->nterm; k++) scale += fabs(d->term_energy[k]);
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < m->dim; a++) {
      lo[a] = fmin(lo[a], m->x0[i * m->dim + a]);
      hi[a] = fmax(hi[a], m->x0[i * m->dim + a]);
    }
  for (int a = 0; a < m->dim; a++) {
    diam += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    g += m->gravity[a] * m->gravity[a];
  }
  double fsum = 0.0; /* N: point loads do at most sum |f_i| diam(x0) of work, as gravity does */
  for (int i = 0; m->load && i < m->nv; i++) {
    double f2 = 0.0;
    for (int a = 0; a < m->dim; a++) f2 += m->load[i * m->dim + a] * m->load[i * m->dim + a];
    fsum += sqrt(f2);
  }
  scale += (m->total_mass * sqrt(g) + fsum) * sqrt(diam);
  /* an actuated tendon stores up to K/2 (l0 - rest)^2 as its rest length shrinks (at rest,
   * the scene may start with no energy at all: its scale is then all in the actuation) */
  for (int t = 0; t < m->ntendon; t++) {
    const sw_tendon *td = &m->tendon[t];
    double l0 = sw_tendon_length(td, m->x0, m->dim), dl = 0.0;
    for (int k = 0; k < td->nkey; k++) dl = fmax(dl, fabs(l0 - td->key_rest[k]));
    scale += 0.5 * td->stiffness * dl * dl;
  }
  return u + k0 + 1e3 * scale;
}
