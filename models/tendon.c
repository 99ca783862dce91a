/* tendon.c — tendons through mesh-node waypoints (seed 003; DESIGN.md "Tendons"). */
#include <math.h>

#include "terms.h"

double sw_tendon_rest(const sw_tendon *td, double t) {
  const double *kt = td->key_t, *kr = td->key_rest;
  if (td->nkey == 1 || t <= kt[0]) return kr[0];
  if (t >= kt[td->nkey - 1]) return kr[td->nkey - 1];
  int k = 0;
  while (t > kt[k + 1]) k++;
  double s = (t - kt[k]) / (kt[k + 1] - kt[k]); /* in [0, 1] */
  return kr[k] + s * (kr[k + 1] - kr[k]);
}

double sw_tendon_length(const sw_tendon *td, const double *x, int dim) {
  double len = 0.0;
  for (int k = 0; k + 1 < td->nway; k++) {
    const double *a = x + (size_t)td->way[k] * dim, *b = x + (size_t)td->way[k + 1] * dim;
    double s = 0.0;
    for (int c = 0; c < dim; c++) s += (a[c] - b[c]) * (a[c] - b[c]);
    len += sqrt(s);
  }
  return len;
}
