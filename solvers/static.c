/* static.c — static equilibrium: minimise the total potential U(x) over the free DOFs.
 * Newton on U with a Levenberg–Marquardt shift, S = H + mu M (H exact, or projected PSD when the
 * scene asks for hessian: projected), mu shrunk after full steps and grown after line-search
 * cuts or factorisations that find S not positive definite, and a backtracking line search on U.  Converged
 * when the free forces sum to at most 1e-10 of the force scale (the largest of the initial free
 * forces, the total weight and the total point load) in the 1-norm; then the pin reactions are grad U at the
 * pinned DOFs (the force each pin must supply) and their sum is reported. */
#include <math.h>
#include <string.h>

#include "solver.h"
#include "util.h"

#define STATIC_MAX_ITER 1000
#define STATIC_RTOL 1e-10

static double norm1(const double *v, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s += fabs(v[i]);
  return s;
}

/* Sum of the diagonal of H over that of M on the free DOFs: the scale of mu (1/s^2).  (The
 * low-rank part of H is left out: a scale, not a value.) */
static double stiffness_ratio(sw_newton *nw, const sw_model *m, sw_data *d) {
  double *val = sw_chol_values(&nw->chol), h = 0.0, mm = 0.0;
  sw_pattern_fill(&nw->pat, m, d, 0.0, 1.0, val);
  for (int c = 0; c < nw->n; c++) h += val[nw->pat.diag[c]];
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) mm += m->mass[i / m->dim];
  return mm > 0.0 && h > 0.0 ? h / mm : 1.0;
}

/* Sum over vertices of |point load| (N): a start already in equilibrium under loads (the
 * inverse problem's forward check) converges at once instead of chasing rounding. */
static double total_load(const sw_model *m) {
  double s = 0.0;
  for (int i = 0; m->load && i < m->nv; i++) {
    double q = 0.0;
    for (int a = 0; a < m->dim; a++) q += m->load[i * m->dim + a] * m->load[i * m->dim + a];
    s += sqrt(q);
  }
  return s;
}

static void pin_reactions(const sw_model *m, const sw_data *d, double reaction[3]) {
  reaction[0] = reaction[1] = reaction[2] = 0.0;
  for (int i = 0; i < m->nv; i++)
    if (m->pinned[i])
      for (int a = 0; a < m->dim; a++) reaction[a] += d->grad[i * m->dim + a];
}

/* One damped Newton iteration; *full is set when the whole step was taken. */
static int static_iteration(sw_newton *nw, const sw_model *m, sw_data *d, double *x, double mu,
                            double phi, int *full) {
  sw_pattern_fill(&nw->pat, m, d, mu, 1.0, sw_chol_values(&nw->chol));
  sw_pattern_fill_lowrank(&nw->pat, d, sw_chol_lowrank(&nw->chol, 1.0));
  d->nfactor++;
  int rc = sw_chol_factor(&nw->chol, d->err, sizeof d->err);
  d->factor_nnz = sw_chol_nnz(&nw->chol);
  if (rc) return rc;
  for (int c = 0; c < nw->n; c++) nw->g[c] = -nw->g[c];
  rc = sw_chol_solve(&nw->chol, nw->g, nw->dx, d->err, sizeof d->err);
  if (rc) return rc;
  d->nnewton++;
  double slope = 0.0;
  for (int c = 0; c < nw->n; c++) slope -= nw->g[c] * nw->dx[c];
  long before = d->nlinesearch;
  sw_newton_opts o = {.a = 0.0, .t = d->t};
  rc = sw_newton_line_search(nw, m, d, x, x, &o, phi, slope);
  *full = d->nlinesearch == before;
  return rc;
}

static int static_loop(sw_newton *nw, const sw_model *m, sw_data *d, char *err, size_t errsz) {
  double *x = d->x, phi, scale = 0.0, mu = 0.0, ratio = 1.0;
  int project = sw_hessian_filter(m->opt.hessian);
  for (int it = 0; it < STATIC_MAX_ITER; it++) {
    int rc = sw_newton_phi(nw, m, d, x, x, 0.0, d->t, 1, 1, project, &phi);
    if (rc) return sw_errf(err, errsz, "static solve: %s", d->err), rc;
    double res = norm1(nw->g, nw->n);
    if (it == 0) {
      scale = fmax(res, m->total_mass * sqrt(m->gravity[0] * m->gravity[0] +
                                             m->gravity[1] * m->gravity[1] +
                                             m->gravity[2] * m->gravity[2]));
      scale = fmax(scale, total_load(m));
      ratio = stiffness_ratio(nw, m, d);
      mu = 1e-3 * ratio;
    }
    d->last_newton = it;
    if (res <= STATIC_RTOL * scale) return SW_OK;
    int full = 0;
    rc = static_iteration(nw, m, d, x, mu, phi, &full);
    if (rc < 0) return sw_errf(err, errsz, "static solve: %s", d->err), rc;
    mu = (rc == SW_OK && full) ? fmax(mu / 4.0, 1e-14 * ratio) : fmin(mu * 8.0, 1e12 * ratio);
  }
  sw_errf(err, errsz, "static solve did not converge in %d iterations", STATIC_MAX_ITER);
  return SW_RECOVER;
}

int sw_static_solve(const sw_model *m, sw_data *d, double reaction[3], char *err, size_t errsz) {
  sw_newton nw;
  int rc = sw_newton_init(&nw, m, err, errsz);
  if (rc) { /* say which solve could not start */
    char why[SW_ERRSZ];
    snprintf(why, sizeof why, "%s", err ? err : "");
    sw_errf(err, errsz, "static solve: cannot start: %s", why);
  }
  if (!rc && nw.n > 0) rc = static_loop(&nw, m, d, err, errsz);
  if (!rc) {
    double u;
    rc = sw_eval_terms(m, d, d->x, d->t, 1, 0, 0, &u);
    pin_reactions(m, d, reaction);
    memset(d->v, 0, (size_t)m->nv * (size_t)m->dim * sizeof(double));
  }
  sw_newton_free(&nw);
  return rc;
}
