/* tendon_state.c — what tendons.csv logs after every step (DESIGN.md "Outputs"): each tendon's
 * length l = sum |x_{w_k} - x_{w_k+1}|, delta = l - rest(t) and tension tau = E'(delta)
 * (seed 003: spring K delta, cable K max(delta, 0)). */
#include <math.h>

#include "terms.h"

double sw_tendon_tension(const sw_tendon *td, double delta) {
  if (td->law == SW_LAW_CABLE && delta <= 0.0) return 0.0; /* slack */
  return td->stiffness * delta;                             /* N */
}

void sw_tendon_state(const sw_model *m, sw_data *d) {
  for (int k = 0; k < m->ntendon; k++) {
    const sw_tendon *td = &m->tendon[k];
    double len = sw_tendon_length(td, d->x, m->dim); /* m */
    d->tendon_length[k] = len;
    d->tendon_delta[k] = len - sw_tendon_rest(td, d->t);
    d->tendon_tension[k] = sw_tendon_tension(td, d->tendon_delta[k]);
  }
}
