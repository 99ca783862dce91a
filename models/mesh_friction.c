/* mesh_friction.c — smoothed Coulomb friction of the pairs of the term "mesh_contact" (the
 * cloth against mesh obstacles, and self-contact), lagged per step after Li et al.,
 * "Incremental Potential Contact: Intersection- and Inversion-free, Large-Deformation
 * Dynamics", SIGGRAPH 2020, section 5:
 *
 *   E_f = sum_k mu_k lambda_k f0(|P_k u_k|),   u_k = sum_j c_kj (x_j - x_j^0)
 *
 * (mu_k: contact.friction for a pair with a mesh obstacle, contact.self_friction for the
 * cloth's own),
 * over the pairs k active (closer than thickness + dhat) at the step's start x^0.  Lagged
 * there, per pair: the closest points' coefficients c_kj (the pair's r = sum_j c_kj x_j joins
 * its closest points: (1, -b1, -b2, -b3) for a point and a triangle, (1 - a, a, -(1 - b), -b)
 * for two edges; models/barrier_block.c), the normal n_k = r / |r| (P_k = I - n_k n_k^T, IPC's
 * T_k T_k^T) and the normal force lambda_k = kappa_s w_k |db/dd| = kappa_s w_k |b'(s)| 2 d of
 * the pair's barrier b(s), s = d^2 - xi^2 (models/mesh_contact.c).  u_k is the relative
 * displacement over the step of the two closest points; a mesh obstacle's vertices x_j move
 * with the obstacle, so the slip is relative to the obstacle's motion.  f0 is IPC's C1
 * smoothing of |u| below eps = eps_v h, as for the analytic obstacles (models/contact.c):
 * the Hessian mu lambda (c c^T) (x) (f1/y P + (f1' - f1/y) uhat uhat^T) is positive
 * semi-definite as it is (f1' >= 0, f1/y > 0).  Beyond eps it has no curvature along the slip
 * uhat, where the energy's slope turns as the slip does; with sw_eval.bound it is replaced by
 * mu lambda (c c^T) (x) f1/y P, the Hessian of the quadratic f0(y) + (|P u|^2 - y^2) f1(y) / 2y
 * that touches f0(|P u|) at u and lies above it (f1(y)/y >= f1'(y)), as in iteratively
 * reweighted least squares (docs/contact.md, "Friction's matrix"). */
#include <math.h>
#include <string.h>

#include "contact.h"
#include "terms.h"
#include "contact_geom.h"
#include "util.h"

/* One lagged pair. */
typedef struct mf_pair {
  int v[4];       /* the pair's vertices (>= nv: a mesh obstacle's) */
  double c[4];    /* the closest points' coefficients at the step's start */
  double n[3];    /* the unit normal there */
  double mul;     /* mu times the normal force there, N */
  double p0[12];  /* its vertices there, m */
} mf_pair;

struct sw_mfriction {
  double h;       /* the step, s (0: no step lagged yet: no friction) */
  mf_pair *pair;
  int npair, cap;
};

sw_mfriction *sw_mfriction_new(void) { return sw_calloc(1, sizeof(sw_mfriction)); }

void sw_mfriction_free(sw_mfriction *f) {
  if (!f) return;
  sw_free(f->pair);
  sw_free(f);
}

void sw_mfriction_begin(sw_mfriction *f, double h) {
  f->h = h;
  f->npair = 0;
}

int sw_mfriction_lag_pair(sw_mfriction *f, int kind, const int *v, const double *p, double xi,
                          double shat, double w, double mu) {
  if (!(mu > 0.0)) return 0;
  sw_pair_form pf;
  double d2 = sw_pair_d2_form(kind == SW_MC_EE, p, &pf), s = d2 - xi * xi, db;
  if (!(s > 0.0) || s >= shat) return 0;
  double r[3] = {0.0, 0.0, 0.0}, d = sqrt(d2);
  for (int j = 0; j < 4; j++)
    for (int a = 0; a < 3; a++) r[a] += pf.c[j] * p[3 * j + a];
  double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]); /* m: d, up to round-off */
  sw_barrier(s, shat, &db, NULL);
  if (!(len > 0.0) || !isfinite(db)) return 0;
  if (f->npair == f->cap) {
    int cap = f->cap + f->cap / 2 + 64;
    mf_pair *q = sw_realloc(f->pair, (size_t)cap, sizeof *q);
    if (!q) return -1;
    f->pair = q, f->cap = cap;
  }
  mf_pair *q = &f->pair[f->npair++];
  memcpy(q->v, v, sizeof q->v);
  memcpy(q->c, pf.c, sizeof q->c);
  memcpy(q->p0, p, sizeof q->p0);
  for (int a = 0; a < 3; a++) q->n[a] = r[a] / len;
  q->mul = mu * w * fabs(db) * 2.0 * d; /* N: mu kappa_s w |b'(s)| |ds/dd| */
  return 0;
}

int sw_mfriction_count(const sw_mfriction *f) { return f && f->h > 0.0 ? f->npair : 0; }

const int *sw_mfriction_vertices(const sw_mfriction *f, int k) { return f->pair[k].v; }

/* IPC's smoothed friction of slip y (m) for eps = eps_v h: f0 (m), f1(y)/y (1/m) and the
 * coefficient c of uhat uhat^T / y in its Hessian, (f1' - f1/y) (1/m). */
static double f0_of(double y, double eps, double *q, double *c) {
  if (y >= eps) return *q = 1.0 / y, *c = -1.0 / y, y;
  *q = 2.0 / eps - y / (eps * eps);
  *c = -y / (eps * eps);
  return -y * y * y / (3.0 * eps * eps) + y * y / eps + eps / 3.0;
}

double sw_mfriction_pair(const sw_mfriction *f, double eps_v, int k, const double *p, double *g,
                         double *H, int bound) {
  const mf_pair *q = &f->pair[k];
  double u[3] = {0.0, 0.0, 0.0}, un = 0.0, y = 0.0;
  for (int j = 0; j < 4; j++)
    for (int a = 0; a < 3; a++) u[a] += q->c[j] * (p[3 * j + a] - q->p0[3 * j + a]); /* m */
  for (int a = 0; a < 3; a++) un += u[a] * q->n[a];
  for (int a = 0; a < 3; a++) u[a] -= un * q->n[a], y += u[a] * u[a];
  y = sqrt(y);
  double eps = eps_v * f->h, qy, cy, mul = q->mul; /* m, 1/m, 1/m, N */
  double e = mul * f0_of(y, eps, &qy, &cy);
  if (g)
    for (int j = 0; j < 4; j++)
      for (int a = 0; a < 3; a++) g[3 * j + a] = mul * qy * q->c[j] * u[a];
  if (!H) return e;
  double B[9]; /* d2 f0(|P u|) / du2 */
  double cyy = y > 0.0 && !bound ? cy / (y * y) : 0.0;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      B[3 * a + b] = mul * (qy * ((a == b) - q->n[a] * q->n[b]) + cyy * u[a] * u[b]);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
          H[(3 * i + a) * 12 + 3 * j + b] = q->c[i] * q->c[j] * B[3 * a + b];
  return e;
}

int sw_contact_friction_on(const sw_model *m) {
  const sw_contact *c = &m->contact;
  return (c->friction > 0.0 && (m->nobstacle > 0 || m->nmesh_obstacle > 0)) ||
         (c->self && c->self_friction > 0.0);
}
