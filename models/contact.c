/* contact.c — the term "contact": every free vertex kept outside every obstacle by a log
 * barrier on its distance, with optional smoothed Coulomb friction, after Li et al.,
 * "Incremental Potential Contact: Intersection- and Inversion-free, Large-Deformation
 * Dynamics", SIGGRAPH 2020 (barrier: eq. 6; friction: section 5).
 *
 *   E = kappa sum_i sum_o m_i b(d_io) + sum_i sum_o mu lambda_io f0(|u_io|)
 *
 * d_io is vertex i's signed distance to obstacle o's contact surface (models/obstacle.c),
 * b(d) = -(d - dhat)^2 ln(d / dhat) below dhat and 0 beyond, weighted by the vertex's mass so
 * that kappa |b'(d)| is the acceleration the obstacle gives it (the term does not depend on
 * the mesh's resolution).  Friction is lagged per step: lambda_io = kappa m_i |b'(d_io)| and
 * the normal n_io at the start of the step, u_io the tangential part of the vertex's
 * displacement over the step relative to the obstacle, f0 IPC's C1 smoothing of |u| below
 * eps_v h.  The solvers keep every distance positive: Newton's line search is limited by
 * sw_contact_toi, and every step starts from sw_contact_begin's guess. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contact.h"
#include "terms.h"
#include "util.h"

double sw_contact_barrier(double d, double dhat, double *db, double *d2b) {
  if (d >= dhat) return *db = *d2b = 0.0, 0.0;
  if (d <= 0.0) return *db = -INFINITY, *d2b = INFINITY, INFINITY;
  double r = d - dhat, l = log(d / dhat);
  *db = -2.0 * r * l - r * r / d;                       /* m */
  *d2b = -2.0 * l - 4.0 * r / d + r * r / (d * d);      /* 1 */
  return -r * r * l;                                    /* m^2 */
}

double sw_contact_auto_kappa(const sw_model *m) {
  double g = 0.0, db, d2b;
  for (int a = 0; a < m->dim; a++) g += m->gravity[a] * m->gravity[a];
  g = m->has_gravity && g > 0.0 ? sqrt(g) : 9.81; /* m/s^2 */
  sw_contact_barrier(0.5 * m->contact.dhat, m->contact.dhat, &db, &d2b);
  return g / fabs(db); /* 1/s^2 */
}

/* --------------------------------------------------------------- the lag */

typedef struct lag_store {
  sw_contact_lag pub;
  double *x0;      /* (nv x dim) the step's start */
  double *vforce;  /* (nv) |contact force| on each vertex at the last diagnostics, N */
} lag_store;

sw_contact_lag *sw_contact_lag_new(const sw_model *m) {
  if (m->nobstacle == 0) return NULL;
  lag_store *s = sw_calloc(1, sizeof *s);
  if (!s) return NULL;
  size_t nv = (size_t)m->nv, no = (size_t)m->nobstacle;
  s->x0 = sw_calloc(nv * (size_t)m->dim, sizeof(double));
  s->vforce = sw_calloc(nv, sizeof(double));
  s->pub.lambda = sw_calloc(nv * no, sizeof(double));
  s->pub.normal = sw_calloc(nv * no * 3, sizeof(double));
  if (!s->x0 || !s->vforce || !s->pub.lambda || !s->pub.normal) {
    sw_contact_lag_free(&s->pub);
    return NULL;
  }
  s->pub.x0 = s->x0;
  return &s->pub;
}

void sw_contact_lag_free(sw_contact_lag *lag) {
  lag_store *s = (lag_store *)lag;
  if (!s) return;
  sw_free(s->x0);
  sw_free(s->vforce);
  sw_free(s->pub.lambda);
  sw_free(s->pub.normal);
  sw_free(s);
}

/* ------------------------------------------------------------- friction */

/* Vertex i's tangential displacement u over the step relative to obstacle o (lagged normal
 * n0), at x and time t; returns |u|. */
static double slip(const sw_model *m, const sw_contact_lag *lag, int i, int o, const double *x,
                   double t, double *u) {
  const int dim = m->dim;
  const double *n0 = lag->normal + 3 * ((size_t)i * m->nobstacle + o);
  double c[3] = {0.0, 0.0, 0.0}, dn = 0.0, y = 0.0;
  /* where the obstacle's material point under the vertex at the step's start has gone */
  memcpy(c, lag->x0 + (size_t)i * dim, (size_t)dim * sizeof(double));
  sw_obstacle_carry(&m->obstacle[o], lag->t0, t, c, c);
  for (int a = 0; a < dim; a++) {
    u[a] = x[i * dim + a] - c[a];
    dn += u[a] * n0[a];
  }
  for (int a = 0; a < dim; a++) {
    u[a] -= dn * n0[a];
    y += u[a] * u[a];
  }
  return sqrt(y);
}

/* IPC's smoothed friction of slip y (m) for eps = eps_v h: f0 (m) and f1(y)/y (1/m). */
static double friction_f0(double y, double eps, double *f1_over_y) {
  if (y >= eps) return *f1_over_y = 1.0 / y, y;
  *f1_over_y = 2.0 / eps - y / (eps * eps);
  return -y * y * y / (3.0 * eps * eps) + y * y / eps + eps / 3.0;
}

/* Friction of vertex i against obstacle o: energy (J), gradient and Hessian block (dim x dim,
 * its upper triangle; positive semi-definite as it is) added; bound: the bound q P above it
 * (sw_eval.bound, as for the mesh pairs: models/mesh_friction.c). */
static double friction_add(const sw_model *m, const sw_contact_lag *lag, int i, int o,
                           const double *x, double t, double *g, double *H, int bound) {
  const int dim = m->dim;
  double lam = lag->lambda[(size_t)i * m->nobstacle + o];
  if (lam <= 0.0 || m->contact.friction <= 0.0) return 0.0;
  const double *n0 = lag->normal + 3 * ((size_t)i * m->nobstacle + o);
  double u[3], q, eps = m->contact.eps_v * lag->h;
  double y = slip(m, lag, i, o, x, t, u), mul = m->contact.friction * lam; /* N */
  double e = mul * friction_f0(y, eps, &q);
  for (int a = 0; a < dim; a++) g[a] += mul * q * u[a];
  if (!H) return e;
  /* d2/dx2 of f0(|P dx|): q P + c u u^T / y^2, c = -y / eps^2 below eps, -1/y above */
  double c = y <= 0.0 || bound ? 0.0 : (y >= eps ? -1.0 / y : -y / (eps * eps)) / (y * y);
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++)
      sw_hess_add(H, dim, a, b, mul * (q * ((a == b) - n0[a] * n0[b]) + c * u[a] * u[b]));
  return e;
}

/* ------------------------------------------------------------------ term */

/* The barrier of vertex i against obstacle o: energy added (J), gradient and Hessian block;
 * SW_RECOVER (with why) when the vertex is not outside. */
static int barrier_add(const sw_model *m, const sw_eval *ev, int i, int o, double *e,
                       double *g, double *H) {
  const int dim = m->dim;
  double n[3], Hp[9], db, d2b;
  double d = sw_obstacle_sdf(&m->obstacle[o], dim, ev->t, ev->x + (size_t)i * dim, n, Hp);
  if (!(d > 0.0)) {
    sw_eval_why(ev, "vertex %d is not outside obstacle %d (distance %g m)", i,
                m->obstacle[o].item, d);
    return SW_RECOVER;
  }
  if (d >= m->contact.dhat) return SW_OK;
  double w = m->contact.kappa * m->mass[i]; /* kg/s^2 */
  *e += w * sw_contact_barrier(d, m->contact.dhat, &db, &d2b);
  for (int a = 0; a < dim; a++) g[a] += w * db * n[a];
  if (!H) return SW_OK;
  double B[9];
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) B[a * dim + b] = w * (d2b * n[a] * n[b] + db * Hp[a * dim + b]);
  /* b' < 0: the shape's curvature makes the block indefinite along the surface.  Clamped even
   * when the other terms take absolute values: |b'| / R grows without bound as the vertex
   * presses closer, and its absolute value stiffens the tangential directions by twice the
   * exact amount, which made Newton converge linearly on a cloth pressed onto a sphere. */
  sw_psd_project(B, dim, ev->project == SW_FILTER_ABS ? SW_FILTER_CLAMP : ev->project);
  sw_hess_add_full(H, dim, B);
  return SW_OK;
}

static int contact_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const int dim = m->dim;
  const sw_contact_lag *lag = ev->lag; /* a caller's own, or the step's (lagged: h > 0) */
  if (!lag && ev->data && ((const sw_contact_lag *)ev->data)->h > 0.0) lag = ev->data;
  double e = 0.0;
  for (int s = 0; s < t->nstencil; s++) {
    int i = t->sidx[s];
    double g[3] = {0.0, 0.0, 0.0}, *H = ev->hess ? sw_ev_block(ev, t, s) : NULL;
    for (int o = 0; o < m->nobstacle; o++) {
      int rc = barrier_add(m, ev, i, o, &e, g, H);
      if (rc) return rc;
      if (lag) e += friction_add(m, lag, i, o, ev->x, ev->t, g, H, ev->bound);
    }
    if (H) sw_ev_block_done(ev, t, s, H);
    if (ev->grad)
      for (int a = 0; a < dim; a++) ev->grad[i * dim + a] += g[a];
  }
  *energy = e;
  return SW_OK;
}

static void *contact_data_new(const sw_term *t, const sw_model *m, sw_data *d);
static void contact_data_free(void *data);
static int contact_begin_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            double h, double t1, double *y);
static double contact_bound(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            const double *x0, const double *x1, double time);
static void contact_clip_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            const double *x0, const double *x1, double time, double *frac);
static int contact_settled_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                              const double *x0, const double *x1, double time);
static int contact_swept_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            const double *y, double t1);
static int contact_held(const sw_term *t, const sw_model *m, const sw_data *d, const void *data,
                        const double *x, double time, const double *vfrac, double frac,
                        int *item, int *vertex, double *held);
static void contact_state_op(const sw_term *t, const sw_model *m, sw_data *d, void *data);
static const double *contact_vertex_force(const sw_term *t, const sw_model *m,
                                          const sw_data *d, const void *data);
static int contact_dissipates(const sw_term *t, const sw_model *m);

/* Every free vertex starts outside every obstacle's contact surface. */
static int contact_check_start(const sw_term *t, const sw_model *m, const double *x,
                               const char **key, char *err, size_t errsz) {
  (void)t;
  char e[SW_ERRSZ];
  if (!sw_contact_outside(m, x, 0.0, e, sizeof e)) return 0;
  *key = "obstacles";
  sw_errf(err, errsz, "%s; expected every free vertex to start outside every obstacle's "
          "contact surface", e);
  return -1;
}

static const sw_term_ops contact_ops = {
    .kind = "contact", .eval = contact_eval, .sink_ok = 1,
    .data_new = contact_data_new, .data_free = contact_data_free,
    .begin = contact_begin_op, .bound = contact_bound, .clip = contact_clip_op,
    .settled = contact_settled_op, .swept = contact_swept_op, .held = contact_held,
    .state = contact_state_op, .vertex_force = contact_vertex_force,
    .dissipates = contact_dissipates, .check_start = contact_check_start};

int sw_contact_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  t->ops = &contact_ops;
  snprintf(t->name, sizeof t->name, "%s", "contact");
  int nfree = 0;
  for (int i = 0; i < m->nv; i++) nfree += !m->pinned[i];
  if (sw_term_alloc_stencils(t, nfree, 1, m->dim)) {
    sw_errf(err, errsz, "out of memory for the contact term (%d vertices)", nfree);
    return -1;
  }
  for (int i = 0, s = 0; i < m->nv; i++)
    if (!m->pinned[i]) t->sidx[s++] = i;
  return 0;
}

/* ------------------------------------------------------------ the solvers' side */

int sw_contact_outside(const sw_model *m, const double *x, double t, char *err, size_t errsz) {
  for (int i = 0; i < m->nv; i++)
    for (int o = 0; !m->pinned[i] && o < m->nobstacle; o++) {
      double d = sw_obstacle_sdf(&m->obstacle[o], m->dim, t, x + (size_t)i * m->dim, NULL, NULL);
      if (!(d > 0.0)) {
        sw_errf(err, errsz, "vertex %d is not outside obstacles[%d] at t = %g s (signed "
                "distance %g m to its contact surface)", i, m->obstacle[o].item, t, d);
        return -1;
      }
    }
  return 0;
}

/* The fraction of vertex i's straight motion x0 -> x1 that keeps it outside every obstacle. */
static double vertex_toi(const sw_model *m, const double *x0, const double *x1, int i, double t) {
  const int dim = m->dim;
  const double *p0 = x0 + (size_t)i * dim, *p1 = x1 + (size_t)i * dim;
  double len = 0.0, toi = 1.0;
  for (int a = 0; a < dim; a++) len += (p1[a] - p0[a]) * (p1[a] - p0[a]);
  len = sqrt(len);
  if (len == 0.0 || m->pinned[i]) return 1.0;
  for (int o = 0; o < m->nobstacle; o++) {
    double d0 = sw_obstacle_sdf(&m->obstacle[o], dim, t, p0, NULL, NULL);
    if (d0 - len > SW_CONTACT_KEEP * d0) continue; /* cannot get close enough to matter */
    toi = fmin(toi, sw_obstacle_toi(&m->obstacle[o], dim, t, p0, p1, SW_CONTACT_KEEP));
  }
  return toi;
}

double sw_contact_toi(const sw_model *m, const double *x0, const double *x1, double t) {
  double toi = 1.0;
  for (int i = 0; i < m->nv; i++) toi = fmin(toi, vertex_toi(m, x0, x1, i, t));
  return toi;
}

void sw_contact_clip(const sw_model *m, const double *x0, const double *x1, double t,
                     double *frac) {
  for (int i = 0; i < m->nv; i++) frac[i] = vertex_toi(m, x0, x1, i, t);
}

int sw_contact_settled(const sw_model *m, const double *x0, const double *x1, double t) {
  const int dim = m->dim;
  for (int i = 0; i < m->nv; i++) {
    if (m->pinned[i]) continue;
    const double *p0 = x0 + (size_t)i * dim, *p1 = x1 + (size_t)i * dim;
    double len = 0.0;
    for (int a = 0; a < dim; a++) len += (p1[a] - p0[a]) * (p1[a] - p0[a]);
    len = sqrt(len); /* m */
    for (int o = 0; len > 0.0 && o < m->nobstacle; o++) {
      double d0 = sw_obstacle_sdf(&m->obstacle[o], dim, t, p0, NULL, NULL);
      if (len > (d0 < m->contact.dhat ? SW_CONTACT_SETTLE : 1.0 - SW_CONTACT_KEEP) * d0) return 0;
    }
  }
  return 1;
}

/* Lag the friction at (d->x, d->t) for a step of size h. */
static void lag_friction(const sw_model *m, sw_data *d, double h) {
  sw_contact_lag *lag = d->lag;
  const int dim = m->dim, no = m->nobstacle;
  lag->h = h;
  lag->t0 = d->t;
  memcpy(((lag_store *)lag)->x0, d->x, (size_t)m->nv * dim * sizeof(double));
  for (int i = 0; i < m->nv; i++)
    for (int o = 0; o < no; o++) {
      double n[3] = {0.0, 0.0, 0.0}, db, d2b;
      double dist = sw_obstacle_sdf(&m->obstacle[o], dim, d->t, d->x + (size_t)i * dim, n, NULL);
      sw_contact_barrier(dist, m->contact.dhat, &db, &d2b);
      lag->lambda[(size_t)i * no + o] =
          m->pinned[i] || !isfinite(db) ? 0.0 : m->contact.kappa * m->mass[i] * fabs(db); /* N */
      memcpy(lag->normal + 3 * ((size_t)i * no + o), n, sizeof n);
    }
}

/* Vertex i of x at t0 carried by every moving obstacle it is near (within dhat plus that
 * obstacle's motion at the vertex from t0 to t1) into z. */
static void carry(const sw_model *m, const double *x, int i, double t0, double t1, double *z) {
  const int dim = m->dim;
  const double *xi = x + (size_t)i * dim;
  memcpy(z, xi, (size_t)dim * sizeof(double));
  for (int o = 0; o < m->nobstacle; o++) {
    const sw_obstacle *ob = &m->obstacle[o];
    if (!sw_obstacle_moves(ob, t0, t1)) continue;
    double p[3] = {0.0, 0.0, 0.0}, q[3], move = 0.0;
    memcpy(p, xi, (size_t)dim * sizeof(double));
    sw_obstacle_carry(ob, t0, t1, p, q);
    for (int a = 0; a < dim; a++) move += (q[a] - p[a]) * (q[a] - p[a]);
    move = sqrt(move); /* m */
    if (sw_obstacle_sdf(ob, dim, t0, xi, NULL, NULL) < m->contact.dhat + move)
      for (int a = 0; a < dim; a++) z[a] += q[a] - p[a];
  }
}

/* The first obstacle (moving or not) that the straight motion of a vertex from p0 (at t0) to p1
 * (at t1) goes deeper than dhat into at some instant (sw_obstacle_swept_toi with floor -dhat), or that
 * p1 is not outside of at t1; -1 when none.  The allowance: a vertex sliding over a curved
 * surface cuts a chord under it, ell^2 / (8 R) deep for a relative slide ell over a radius R;
 * passing through an obstacle means going deeper than any allowance. */
static int swept_hit(const sw_model *m, const double *p0, double t0, const double *p1,
                     double t1) {
  for (int o = 0; o < m->nobstacle; o++) {
    const sw_obstacle *ob = &m->obstacle[o];
    if (!(sw_obstacle_sdf(ob, m->dim, t1, p1, NULL, NULL) > 0.0) ||
        sw_obstacle_swept_toi(ob, m->dim, t0, t1, p0, p1, -m->contact.dhat) < 1.0)
      return o;
  }
  return -1;
}

/* The guess yi (dim) moved out to dhat / 2 from every obstacle it is inside of, along the
 * normal there (the distances are exact: that lands on dhat / 2); 1 if it is then outside every
 * obstacle. */
static int lift(const sw_model *m, double t1, double *yi) {
  const int dim = m->dim;
  for (int o = 0; o < m->nobstacle; o++) {
    double n[3], dist = sw_obstacle_sdf(&m->obstacle[o], dim, t1, yi, n, NULL);
    if (!(dist > 0.0))
      for (int a = 0; a < dim; a++) yi[a] += (0.5 * m->contact.dhat - dist) * n[a];
  }
  for (int o = 0; o < m->nobstacle; o++)
    if (!(sw_obstacle_sdf(&m->obstacle[o], dim, t1, yi, NULL, NULL) > 0.0)) return 0;
  return 1;
}

/* Vertex i's start guess yi when lifting the guess is not enough (between obstacles) or would
 * take it through a moving one: from its carried start z, which must be reachable over the
 * step, the part of the path to the guess that the obstacles at t1 allow, halved until the
 * straight motion from x_n is clear of the moving obstacles too. */
static int guess_from_carry(const sw_model *m, sw_data *d, int i, double t1, const double *z,
                            const double *guess, double *yi) {
  const int dim = m->dim;
  const double *xi = d->x + (size_t)i * dim;
  double s = 1.0;
  for (int o = 0; o < m->nobstacle; o++) {
    double dist = sw_obstacle_sdf(&m->obstacle[o], dim, t1, z, NULL, NULL);
    int k = dist > 0.0 ? swept_hit(m, xi, d->t, z, t1) : o;
    if (k >= 0) {
      sw_errf(d->err, sizeof d->err, "obstacles[%d] moves into vertex %d between t = %g s "
              "and %g s", m->obstacle[k].item, i, d->t, t1);
      return SW_RECOVER;
    }
    s = fmin(s, sw_obstacle_toi(&m->obstacle[o], dim, t1, z, guess, SW_CONTACT_KEEP));
  }
  for (int it = 0; it < 30; it++, s *= 0.5) {
    for (int a = 0; a < dim; a++) yi[a] = z[a] + s * (guess[a] - z[a]);
    if (swept_hit(m, xi, d->t, yi, t1) < 0) return SW_OK;
  }
  memcpy(yi, z, (size_t)dim * sizeof(double));
  return SW_OK;
}

int sw_contact_begin(const sw_model *m, sw_data *d, double h, double t1, double *y) {
  if (!d->lag) return SW_OK;
  const int dim = m->dim;
  lag_friction(m, d, h);
  for (int i = 0; i < m->nv; i++) {
    if (m->pinned[i]) continue;
    double z[3], *yi = y + (size_t)i * dim, guess[3];
    carry(m, d->x, i, d->t, t1, z);
    memcpy(guess, yi, (size_t)dim * sizeof(double));
    /* lifted out of the obstacles at t1, unless the lift or the motion to it passes through a
     * moving one (a fast obstacle can leave the guess on its far side) */
    if (lift(m, t1, yi) && swept_hit(m, d->x + (size_t)i * dim, d->t, yi, t1) < 0) continue;
    int rc = guess_from_carry(m, d, i, t1, z, guess, yi);
    if (rc) return rc;
  }
  return SW_OK;
}

int sw_contact_swept(const sw_model *m, sw_data *d, const double *y, double t1) {
  if (!d->lag) return SW_OK;
  for (int i = 0; i < m->nv; i++) {
    if (m->pinned[i]) continue;
    int o = swept_hit(m, d->x + (size_t)i * m->dim, d->t, y + (size_t)i * m->dim, t1);
    if (o < 0) continue;
    sw_errf(d->err, sizeof d->err, "obstacles[%d] passes through vertex %d between t = %g s and "
            "%g s", m->obstacle[o].item, i, d->t, t1);
    return SW_RECOVER;
  }
  return SW_OK;
}

void sw_contact_state(const sw_model *m, sw_data *d) {
  if (!d->lag) return;
  lag_store *ls = (lag_store *)d->lag;
  const int dim = m->dim;
  d->contact_count = 0;
  d->contact_min = INFINITY;
  memset(d->contact_force, 0, sizeof d->contact_force);
  memset(d->friction_force, 0, sizeof d->friction_force);
  d->friction_power = 0.0;
  for (int i = 0; i < m->nv; i++) {
    double fi[3] = {0.0, 0.0, 0.0};
    for (int o = 0; !m->pinned[i] && o < m->nobstacle; o++) {
      double n[3], db, d2b, ff[3] = {0.0, 0.0, 0.0};
      double dist = sw_obstacle_sdf(&m->obstacle[o], dim, d->t, d->x + (size_t)i * dim, n, NULL);
      d->contact_min = fmin(d->contact_min, dist);
      if (dist < m->contact.dhat) d->contact_count++;
      sw_contact_barrier(dist, m->contact.dhat, &db, &d2b);
      for (int a = 0; isfinite(db) && a < dim; a++) fi[a] -= m->contact.kappa * m->mass[i] * db * n[a];
      if (d->lag->h > 0.0) friction_add(m, d->lag, i, o, d->x, d->t, ff, NULL, 0);
      for (int a = 0; a < dim; a++) {
        d->friction_force[a] -= ff[a];
        d->friction_power += ff[a] * d->v[i * dim + a]; /* W dissipated: -f.v */
      }
    }
    double mag = 0.0;
    for (int a = 0; a < dim; a++) {
      d->contact_force[a] += fi[a];
      mag += fi[a] * fi[a];
    }
    ls->vforce[i] = sqrt(mag); /* N */
  }
}

/* ------------------------------------------------------ the term's optional operations */

/* The workspace: the lag (also d->lag, by name for the functions above). */
static void *contact_data_new(const sw_term *t, const sw_model *m, sw_data *d) {
  (void)t;
  return d->lag = sw_contact_lag_new(m);
}

static void contact_data_free(void *data) { sw_contact_lag_free(data); }

/* The solvers' contact checks, each timed into d->time_contact. */
static int contact_begin_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            double h, double t1, double *y) {
  (void)t, (void)data;
  double t0 = sw_now();
  int rc = sw_contact_begin(m, d, h, t1, y);
  d->time_contact += sw_now() - t0;
  return rc;
}

static double contact_bound(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            const double *x0, const double *x1, double time) {
  (void)t, (void)data;
  double t0 = sw_now(), r = sw_contact_toi(m, x0, x1, time);
  d->time_contact += sw_now() - t0;
  return r;
}

static void contact_clip_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            const double *x0, const double *x1, double time, double *frac) {
  (void)t, (void)data;
  double t0 = sw_now();
  sw_contact_clip(m, x0, x1, time, frac);
  d->time_contact += sw_now() - t0;
}

static int contact_settled_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                              const double *x0, const double *x1, double time) {
  (void)t, (void)data;
  double t0 = sw_now();
  int r = sw_contact_settled(m, x0, x1, time);
  d->time_contact += sw_now() - t0;
  return r;
}

static int contact_swept_op(const sw_term *t, const sw_model *m, sw_data *d, void *data,
                            const double *y, double t1) {
  (void)t, (void)data;
  double t0 = sw_now();
  int rc = sw_contact_swept(m, d, y, t1);
  d->time_contact += sw_now() - t0;
  return rc;
}

/* After Newton failed: when the clip held a vertex below 1/2 of its update, the most held
 * one and the obstacle nearest it. */
static int contact_held(const sw_term *t, const sw_model *m, const sw_data *d, const void *data,
                        const double *x, double time, const double *vfrac, double frac,
                        int *item, int *vertex, double *held) {
  (void)t, (void)d, (void)data, (void)frac;
  int iv = -1;
  for (int i = 0; vfrac && i < m->nv; i++)
    if (vfrac[i] < 0.5 && (iv < 0 || vfrac[i] < vfrac[iv])) iv = i;
  if (iv < 0) return 0;
  double best = INFINITY;
  *item = -1;
  for (int k = 0; k < m->nobstacle; k++) {
    double dist = sw_obstacle_sdf(&m->obstacle[k], m->dim, time, x + (size_t)iv * m->dim, NULL,
                                  NULL);
    if (dist < best) best = dist, *item = m->obstacle[k].item;
  }
  *vertex = iv;
  *held = vfrac[iv];
  return 1;
}

static void contact_state_op(const sw_term *t, const sw_model *m, sw_data *d, void *data) {
  (void)t, (void)data;
  sw_contact_state(m, d);
}

static const double *contact_vertex_force(const sw_term *t, const sw_model *m,
                                          const sw_data *d, const void *data) {
  (void)t, (void)m, (void)d;
  return data ? ((const lag_store *)data)->vforce : NULL;
}

static int contact_dissipates(const sw_term *t, const sw_model *m) {
  (void)t;
  return m->contact.friction > 0.0;
}
