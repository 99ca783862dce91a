/* static.c — static equilibrium: minimise the total potential U(x) over the free DOFs.
 * Newton on U with a Levenberg–Marquardt shift, S = H + mu M (H exact, or projected PSD when the
 * scene asks for hessian: projected), mu shrunk after full steps and grown after line-search
 * cuts or factorisations that find S not positive definite, and a backtracking line search on U.
 *
 * Stopping rule (docs/integrators.md, "The static solve").  g = grad U on the free DOFs is the
 * force each free DOF is out of balance by (N).  The solve has converged when either
 *  - the tolerance is met: max_i |g_i| <= force_tol F, with F (N) the scene's force scale: the
 *    largest force that one term, or the external load (m_v |gravity| + |point load|), puts on
 *    one free vertex at the start (weight, the pull of membranes, seams and tendons, contact);
 *  - or the residual is at its round-off floor: |g_i| <= rho_i for every free DOF i, with
 *      rho_i = 2 eps (X sum_j |H_ij| + |external force on the vertex of i|),
 *    eps the machine epsilon, X the largest coordinate magnitude (m) and H the Hessian on the
 *    free DOFs (low-rank part included) at the current positions.  X sum_j |H_ij| bounds how
 *    much g_i moves when every coordinate moves by one rounding error (eps X), and the same
 *    bound covers the rounding of the forces' own evaluation; hence the 2.  And Newton must
 *    have been given the chance to do better: from an iterate at the floor the next step is a
 *    Newton step, the shift lowered to mu_N = 1e-12 of the stiffness ratio (a Newton step but
 *    in modes more than 1e12 times softer than the mean), or, where H + mu_N M is not positive
 *    definite (a saddle), the shifted step.  If the iterate after it is at the floor too, that
 *    is the answer; if the step left the floor (round-off steered it: the solve itself is that
 *    inexact, as Woodbury's can be when the sparse part is nearly singular) or the line search
 *    found no decrease along it, the iterate at the floor it came from is.  (One iterate at the
 *    floor is not enough: a very stiff model can start with its loads below the floor of every
 *    component, and a Newton step from there still finds its sag, where a step damped by the
 *    start's shift finds a fraction of it.)  The line search may cut that step: near U = 0 its
 *    noise allowance, relative to |U|, lets only steps that round to nothing through.
 * The matrix is H + mu M with H every term's Hessian and the mesh-contact pairs' blocks (the
 * pattern grown for them as in Newton's steps, solvers/newton.c).
 * Then the pin reactions are grad U at the pinned DOFs (the force each pin must supply) and
 * their sum is reported. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "solver.h"
#include "util.h"

#define STATIC_MAX_ITER 1000
#define STATIC_MU_NEWTON 1e-12 /* the shift of a Newton step, relative to stiffness_ratio */

/* max_i |v_i|, or NaN when any v_i is NaN (so that a NaN residual never passes a test). */
static double max_abs(const double *v, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) {
    if (isnan(v[i])) return NAN;
    s = fmax(s, fabs(v[i]));
  }
  return s;
}

/* Sum of the diagonal of H over that of M on the free DOFs: the scale of mu (1/s^2).  (The
 * low-rank part of H is left out: a scale, not a value.) */
static double stiffness_ratio(sw_newton *nw, const sw_model *m, sw_data *d) {
  double h = 0.0, mm = 0.0;
  sw_newton_hessian(nw, m, d, 0.0); /* the pattern holds the pairs already: it cannot fail */
  const double *val = sw_chol_values(&nw->chol);
  for (int c = 0; c < nw->n; c++) h += val[nw->pat.diag[c]];
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) mm += m->mass[i / m->dim];
  return mm > 0.0 && h > 0.0 ? h / mm : 1.0;
}

/* The external force on vertex i, m_i |gravity| + |point load| (N): a magnitude, not a sum. */
static double external_force(const sw_model *m, int i) {
  const double *gv = m->gravity;
  double f = m->mass[i] * sqrt(gv[0] * gv[0] + gv[1] * gv[1] + gv[2] * gv[2]), q = 0.0;
  for (int a = 0; m->load && a < m->dim; a++)
    q += m->load[i * m->dim + a] * m->load[i * m->dim + a];
  return f + sqrt(q);
}

/* The round-off floor rho (n, N) of every free force component at x, from the Hessian that the
 * last sw_newton_phi left in d->hess and d->lowrank (see the top of the file):
 * rho_i = 2 eps (X sum_j |H_ij| + external force on i's vertex).  The system's value array is
 * the scratch for H on the pattern (every iteration refills it before factorising). */
static void roundoff_floor(sw_newton *nw, const sw_model *m, sw_data *d, const double *x,
                           double *rho) {
  const sw_pattern *p = &nw->pat;
  double X = 0.0;
  sw_newton_hessian(nw, m, d, 0.0); /* the pattern holds the pairs already: it cannot fail */
  const double *val = sw_chol_values(&nw->chol);
  for (int i = 0; i < m->nv * m->dim; i++) X = fmax(X, fabs(x[i]));
  memset(rho, 0, (size_t)p->n * sizeof(double));
  for (int j = 0; j < p->n; j++) { /* row sums of |H| from the stored triangle */
    const int c = sw_pattern_dof(p, j);
    for (long k = p->colptr[j]; k < p->colptr[j + 1]; k++) {
      const int r = sw_pattern_dof(p, p->rowind[k]);
      rho[r] += fabs(val[k]);
      if (r != c) rho[c] += fabs(val[k]);
    }
  }
  for (int r = 0; r < p->nlr; r++) { /* |u u^T| row sums: |u_i| sum_j |u_j| */
    double sum = 0.0;
    for (long k = p->lrptr[r]; k < p->lrptr[r + 1]; k++) sum += fabs(d->lowrank[p->lrsrc[k]]);
    for (long k = p->lrptr[r]; k < p->lrptr[r + 1]; k++)
      rho[p->lrrow[k]] += fabs(d->lowrank[p->lrsrc[k]]) * sum;
  }
  for (int c = 0; c < p->n; c++) rho[c] *= X;
  for (int i = 0; i < m->nv * m->dim; i++)
    if (m->dof[i] >= 0) rho[m->dof[i]] += external_force(m, i / m->dim);
  for (int c = 0; c < p->n; c++) rho[c] *= 2.0 * DBL_EPSILON;
}

/* The scene's force scale F (N): the largest force that one term, or the external load, puts on
 * one free vertex at x: weight and point loads, and the pull of the membranes, seams, tendons
 * and contact that the equilibrium balances.  g (nv x dim) is scratch. */
static int force_scale(const sw_model *m, sw_data *d, const double *x, double *g, double *f) {
  const size_t nd = (size_t)m->nv * (size_t)m->dim;
  double scale = 0.0;
  for (int i = 0; i < m->nv; i++)
    if (!m->pinned[i]) scale = fmax(scale, external_force(m, i));
  for (int k = 0; k < m->nterm; k++) {
    memset(g, 0, nd * sizeof *g);
    sw_eval ev = {.t = d->t, .x = x, .grad = g, .mc = d->mc};
    double e = 0.0;
    int rc = m->term[k].ops->eval(&m->term[k], m, &ev, &e);
    if (rc) return sw_errf(d->err, sizeof d->err, "term %s failed at the start", m->term[k].name), rc;
    for (int i = 0; i < m->nv; i++) {
      double s = 0.0;
      for (int a = 0; a < m->dim; a++) s += g[i * m->dim + a] * g[i * m->dim + a];
      if (!m->pinned[i]) scale = fmax(scale, sqrt(s));
    }
  }
  *f = scale;
  return SW_OK;
}

static void pin_reactions(const sw_model *m, const sw_data *d, double reaction[3]) {
  reaction[0] = reaction[1] = reaction[2] = 0.0;
  for (int i = 0; i < m->nv; i++)
    if (m->pinned[i])
      for (int a = 0; a < m->dim; a++) reaction[a] += d->grad[i * m->dim + a];
}

/* One damped Newton iteration; *solved is set when S could be factorised and solved (so a
 * failure is the line search's), *full when the whole step was taken. */
static int static_iteration(sw_newton *nw, const sw_model *m, sw_data *d, double *x, double mu,
                            double phi, int *solved, int *full) {
  int rc = sw_newton_hessian(nw, m, d, mu);
  if (rc) return rc;
  sw_pattern_fill_lowrank(&nw->pat, d, sw_chol_lowrank(&nw->chol, 1.0));
  d->nfactor++;
  rc = sw_chol_factor(&nw->chol, d->err, sizeof d->err);
  d->factor_nnz = sw_chol_nnz(&nw->chol);
  d->factor_super = sw_chol_super(&nw->chol);
  d->factor_ordering = sw_chol_ordering(&nw->chol);
  if (rc) return rc;
  for (int c = 0; c < nw->n; c++) nw->g[c] = -nw->g[c];
  rc = sw_chol_solve(&nw->chol, nw->g, nw->dx, d->err, sizeof d->err);
  if (rc) return rc;
  d->nnewton++;
  *solved = 1;
  double slope = 0.0;
  for (int c = 0; c < nw->n; c++) slope -= nw->g[c] * nw->dx[c];
  long before = d->nlinesearch;
  sw_newton_opts o = {.a = 0.0, .t = d->t};
  rc = sw_newton_line_search(nw, m, d, x, x, &o, phi, slope);
  *full = d->nlinesearch == before;
  return rc;
}

/* Compare the residual nw->g with its floor (into nw->dx, free until the next solve): 1 when
 * every component is at or below it.  Fills the floor figures of d->static_info. */
static int at_floor(sw_newton *nw, const sw_model *m, sw_data *d, const double *x) {
  double *rho = nw->dx, worst = 0.0, top = 0.0;
  int nan = 0;
  roundoff_floor(nw, m, d, x, rho);
  for (int c = 0; c < nw->n; c++) {
    double g = fabs(nw->g[c]);
    top = fmax(top, rho[c]);
    if (isnan(g)) nan = 1;
    else if (g > 0.0) worst = fmax(worst, rho[c] > 0.0 ? g / rho[c] : INFINITY);
  }
  if (nan) worst = NAN;
  d->static_info.floor = top;
  d->static_info.floor_ratio = worst;
  return worst <= 1.0;
}

/* xf (nv x dim): where the last step from an iterate at the floor started. */
static int static_loop(sw_newton *nw, const sw_model *m, sw_data *d, double *xf, double scale,
                       char *err, size_t errsz) {
  const size_t nx = (size_t)m->nv * (size_t)m->dim;
  double *x = d->x, phi, tol = 0.0, mu = 0.0, ratio = 1.0;
  int project = m->opt.hessian == SW_HESSIAN_PROJECTED, from_floor = 0, newton_failed = 0;
  sw_static_info *info = &d->static_info, saved = {0};
  for (int it = 0; it < STATIC_MAX_ITER; it++) {
    int rc = sw_newton_phi(nw, m, d, x, x, 0.0, d->t, 1, 1, project, &phi);
    if (!rc) rc = sw_newton_hessian(nw, m, d, 0.0); /* grows the pattern for new contact pairs */
    if (rc) return sw_errf(err, errsz, "static solve: %s", d->err), rc;
    double res = max_abs(nw->g, nw->n); /* N */
    if (it == 0) {
      tol = m->opt.newton_force_tol * scale;
      ratio = stiffness_ratio(nw, m, d);
      mu = 1e-3 * ratio;
    }
    int floor_now = at_floor(nw, m, d, x);
    d->last_newton = it;
    info->iterations = it;
    info->force = res;
    info->tol = tol;
    info->roundoff = 0;
    if (res <= tol) return SW_OK;
    if (from_floor) { /* the last step was Newton's from an iterate at the floor */
      if (floor_now) return info->roundoff = 1, SW_OK;
      memcpy(x, xf, nx * sizeof *x); /* it left the floor: the iterate it came from is the answer */
      saved.iterations = it;
      *info = saved;
      return SW_OK;
    }
    /* From the floor, a Newton step (unless one just failed here: S not positive definite;
     * the shift then stays where it was and the shifted step stands in for it). */
    int solved = 0, full = 0, newton = floor_now && !newton_failed;
    double step_mu = newton ? fmin(mu, STATIC_MU_NEWTON * ratio) : mu;
    if (floor_now) {
      memcpy(xf, x, nx * sizeof *x);
      saved = *info;
      saved.roundoff = 1;
    }
    rc = static_iteration(nw, m, d, x, step_mu, phi, &solved, &full);
    if (rc < 0) return sw_errf(err, errsz, "static solve: %s", d->err), rc;
    if (rc && solved && floor_now) return info->roundoff = 1, SW_OK; /* no decrease from here */
    if (rc == SW_OK) { /* x moved */
      from_floor = floor_now && (newton || newton_failed);
      newton_failed = 0;
    } else if (newton) {
      newton_failed = 1;
      continue;
    }
    mu = (rc == SW_OK && full) ? fmax(step_mu / 4.0, 1e-14 * ratio) : fmin(mu * 8.0, 1e12 * ratio);
  }
  sw_errf(err, errsz,
          "static solve did not converge in %d iterations (largest free force %.3g N; "
          "tolerance %.3g N; %.3g times its round-off floor)",
          STATIC_MAX_ITER, info->force, info->tol, info->floor_ratio);
  return SW_RECOVER;
}

int sw_static_solve(const sw_model *m, sw_data *d, double reaction[3], char *err, size_t errsz) {
  sw_newton nw;
  double *xf = NULL;
  int rc = sw_newton_init(&nw, m, err, errsz);
  if (!rc && nw.n > 0 && !(xf = sw_calloc((size_t)m->nv * (size_t)m->dim, sizeof *xf)))
    rc = SW_FATAL, sw_errf(err, errsz, "out of memory for its workspace (%d DOFs)",
                           nw.n);
  if (rc) { /* say which solve could not start */
    char why[SW_ERRSZ];
    snprintf(why, sizeof why, "%s", err ? err : "");
    sw_errf(err, errsz, "static solve: cannot start: %s", why);
  }
  memset(&d->static_info, 0, sizeof d->static_info);
  double scale = 0.0; /* N */
  if (!rc && nw.n > 0 && (rc = force_scale(m, d, d->x, xf, &scale)))
    sw_errf(err, errsz, "static solve: %s", d->err);
  if (!rc && nw.n > 0) rc = static_loop(&nw, m, d, xf, scale, err, errsz);
  if (!rc) {
    double u;
    rc = sw_eval_terms(m, d, d->x, d->t, 1, 0, 0, &u);
    pin_reactions(m, d, reaction);
    memset(d->v, 0, (size_t)m->nv * (size_t)m->dim * sizeof(double));
  }
  sw_free(xf);
  sw_newton_free(&nw);
  return rc;
}
