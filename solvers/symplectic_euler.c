/* symplectic_euler.c — symplectic (semi-implicit) Euler ("symplectic-euler"), explicit:
 *   v_{n+1} = v_n + h M^-1 f(x_n, t_n),
 *   x_{n+1} = x_n + h v_{n+1},
 * one force evaluation per step and no linear solve; pinned components keep x, v = 0.
 * Order 1, symplectic (bounded energy error, no drift, while stable), but only conditionally
 * stable: an undamped mode of angular frequency w is stable for h w < 2, and the stiffest mode
 * of a cloth grows as sqrt(k / m_vertex) ~ 1/spacing, so fine or stiff cloth needs tiny steps.
 * It is here as the baseline that shows where explicit methods fail: every step's total
 * energy is checked (sw_energy_check), so a blow-up fails the step ("energy blow-up", or a
 * non-finite energy) and, once the run loop's halvings are used up, the run, instead of
 * writing garbage. */
#include <string.h>

#include "solver.h"
#include "util.h"

typedef struct se_state {
  double *xnew, *vnew; /* (nv x dim) */
} se_state;

static void se_free(void *p) {
  se_state *s = p;
  if (!s) return;
  sw_free(s->xnew);
  sw_free(s->vnew);
  sw_free(s);
}

static int se_init(void **state, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  (void)d;
  se_state *s = sw_calloc(1, sizeof *s);
  if (!s) return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  s->xnew = sw_calloc(nd, sizeof(double));
  s->vnew = sw_calloc(nd, sizeof(double));
  if (!s->xnew || !s->vnew) {
    se_free(s);
    return sw_errf(err, errsz, "out of memory"), SW_FATAL;
  }
  *state = s;
  return SW_OK;
}

static int se_step(void *p, const sw_model *m, sw_data *d, double h) {
  se_state *s = p;
  const int dim = m->dim;
  double u;
  /* damping force D(x_n) v_n into xnew (scratch until x_{n+1} is written) */
  int rc = sw_damped(m) ? sw_damping_force(m, d, d->x, d->t, d->v, s->xnew, NULL) : SW_OK;
  if (!rc && !sw_damped(m)) memset(s->xnew, 0, (size_t)m->nv * (size_t)dim * sizeof(double));
  if (!rc) rc = sw_eval_terms(m, d, d->x, d->t, 1, 0, 0, &u);
  if (rc) return rc;
  for (int i = 0; i < m->nv; i++)
    for (int al = 0; al < dim; al++) {
      int k = i * dim + al;
      if (m->dof[k] < 0) {
        s->vnew[k] = 0.0;
        s->xnew[k] = d->x[k];
      } else {
        s->vnew[k] = d->v[k] - h * (d->grad[k] + s->xnew[k]) / m->mass[i];
        s->xnew[k] = d->x[k] + h * s->vnew[k];
      }
    }
  rc = sw_energy_check(m, d, s->xnew, s->vnew, d->t + h);
  if (rc) return rc;
  memcpy(d->x, s->xnew, (size_t)m->nv * (size_t)dim * sizeof(double));
  memcpy(d->v, s->vnew, (size_t)m->nv * (size_t)dim * sizeof(double));
  d->t += h;
  d->last_dt = h;
  d->last_newton = 0;
  d->nstep++;
  return SW_OK;
}

const sw_integrator_ops sw_symplectic_euler_ops = {
    .name = "symplectic-euler",
    .summary = "symplectic Euler, explicit (order 1, stable for h w_max < 2)",
    .init = se_init,
    .step = se_step,
    .free = se_free,
};
