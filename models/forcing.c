/* forcing.c — what the prescribed quantities do: whether the model's potential depends on
 * time, and the power the forcing puts in (keyframed tendons, ramped gravity and loads; the
 * curves themselves are models/keyframe.c), docs/scenes.md "Forcing". */
#include "sinew.h"

int sw_actuated(const sw_model *m) {
  int a = m->has_gravity && (m->gravity_ramp > 0.0 || m->fit.on); /* the fit ramps it */
  for (int k = 0; k < m->ntendon; k++) a |= m->tendon[k].nkey > 1;
  for (int i = 0; m->load && m->load_ramp && i < m->nv; i++) a |= m->load_ramp[i] > 0.0;
  return a;
}

/* dU/dt at fixed x of one tendon: E'(Delta) dDelta/dt = -tension alpha'(t) (W). */
static double tendon_power(const sw_tendon *td, const double *x, int dim, double t) {
  double rate = sw_tendon_rest_rate(td, t); /* m/s */
  if (rate == 0.0) return 0.0;
  double delta = sw_tendon_length(td, x, dim) - sw_tendon_rest(td, t); /* m */
  return -sw_tendon_tension(td, delta) * rate;
}

double sw_actuation_power(const sw_model *m, const double *x, double t) {
  const int d = m->dim;
  double p = 0.0; /* W */
  for (int k = 0; k < m->ntendon; k++) p += tendon_power(&m->tendon[k], x, d, t);
  double rg = m->has_gravity ? sw_ramp_rate(t - m->gravity_delay, m->gravity_ramp) : 0.0; /* 1/s */
  for (int i = 0; rg != 0.0 && i < m->nv; i++)
    for (int a = 0; a < d; a++) p -= rg * m->mass[i] * m->gravity[a] * x[i * d + a];
  for (int i = 0; m->load && m->load_ramp && i < m->nv; i++) {
    double rl = sw_ramp_rate(t, m->load_ramp[i]); /* 1/s */
    for (int a = 0; rl != 0.0 && a < d; a++) p -= rl * m->load[i * d + a] * x[i * d + a];
  }
  return p;
}
