/* obstacle.c — the rigid obstacles of a scene (plane, sphere, capsule, box): where each is at
 * time t, the signed distance of a point to its contact surface with the gradient and Hessian
 * of that distance, and a conservative time of impact of a point moving on a segment.
 *
 * Every distance here is a Euclidean signed distance (exact, 1-Lipschitz: it changes by at most
 * |dp| when the point moves by dp), minus the obstacle's offset.  That is what makes the time
 * of impact conservative (Mirtich's conservative advancement, "Impulse-based Dynamic Simulation
 * of Rigid Body Systems", 1996, applied to one point).  Works in dim = 2 or 3. */
#include <math.h>
#include <string.h>

#include "contact.h"

const char *const *sw_shape_names(void) {
  static const char *const names[] = {"plane", "sphere", "capsule", "box", NULL};
  return names;
}

void sw_obstacle_disp(const sw_obstacle *o, double t, double disp[3]) {
  for (int a = 0; a < 3; a++) /* m */
    disp[a] = o->nkey ? sw_keyframe_value(o->key_t, o->key_d + a * o->nkey, o->nkey, o->interp, t)
                      : 0.0;
}

/* Distance to a point c: phi = |r| - R, r = p - c; gradient r/|r|, Hessian (P - n n^T)/|r| with
 * P the projector on the directions the closest point cannot follow (identity for a point). */
static double round_distance(const double *r, const double *P, int dim, double R, double *n,
                             double *H) {
  double len = 0.0;
  for (int a = 0; a < dim; a++) len += r[a] * r[a];
  len = sqrt(len);
  if (len <= 0.0) { /* at the centre: any direction; the point is deep inside anyway */
    if (n) for (int a = 0; a < dim; a++) n[a] = a == dim - 1;
    if (H) memset(H, 0, (size_t)(dim * dim) * sizeof(double));
    return -R;
  }
  double u[3];
  for (int a = 0; a < dim; a++) u[a] = r[a] / len;
  if (n) memcpy(n, u, (size_t)dim * sizeof(double));
  if (H)
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++) H[a * dim + b] = (P[a * dim + b] - u[a] * u[b]) / len;
  return len - R;
}

static void identity(double *P, int dim) {
  memset(P, 0, (size_t)(dim * dim) * sizeof(double));
  for (int a = 0; a < dim; a++) P[a * dim + a] = 1.0;
}

static double plane_sdf(const sw_obstacle *o, int dim, const double *p, double *n, double *H) {
  double phi = 0.0;
  for (int a = 0; a < dim; a++) phi += o->b[a] * (p[a] - o->a[a]);
  if (n) memcpy(n, o->b, (size_t)dim * sizeof(double));
  if (H) memset(H, 0, (size_t)(dim * dim) * sizeof(double));
  return phi;
}

static double sphere_sdf(const sw_obstacle *o, int dim, const double *p, double *n, double *H) {
  double r[3], P[9];
  for (int a = 0; a < dim; a++) r[a] = p[a] - o->a[a];
  identity(P, dim);
  return round_distance(r, P, dim, o->radius, n, H);
}

/* The closest point of the axis a-b: inside the segment the distance is to a line (the
 * Hessian has no curvature along the axis), at an end cap to a point. */
static double capsule_sdf(const sw_obstacle *o, int dim, const double *p, double *n, double *H) {
  double ab[3], ap[3], L2 = 0.0, s = 0.0, r[3], P[9];
  for (int a = 0; a < dim; a++) {
    ab[a] = o->b[a] - o->a[a];
    ap[a] = p[a] - o->a[a];
    L2 += ab[a] * ab[a];
    s += ab[a] * ap[a];
  }
  s = L2 > 0.0 ? s / L2 : 0.0;
  int inside = s > 0.0 && s < 1.0;
  s = fmin(fmax(s, 0.0), 1.0);
  for (int a = 0; a < dim; a++) r[a] = ap[a] - s * ab[a];
  identity(P, dim);
  if (inside)
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++) P[a * dim + b] -= ab[a] * ab[b] / L2;
  return round_distance(r, P, dim, o->radius, n, H);
}

/* An axis-aligned box, centre a, half sizes b.  Outside: the distance to the nearest point of
 * the box, round over the axes where the point is beyond the box; inside: minus the distance
 * to the nearest face (no curvature). */
static double box_sdf(const sw_obstacle *o, int dim, const double *p, double *n, double *H) {
  double q[3], r[3], P[9];
  int out = 0, kmax = 0;
  for (int a = 0; a < dim; a++) {
    double rel = p[a] - o->a[a];
    q[a] = fabs(rel) - o->b[a];
    r[a] = q[a] > 0.0 ? copysign(q[a], rel) : 0.0;
    out |= q[a] > 0.0;
    if (q[a] > q[kmax]) kmax = a;
  }
  if (out) {
    memset(P, 0, sizeof P);
    for (int a = 0; a < dim; a++) P[a * dim + a] = q[a] > 0.0;
    return round_distance(r, P, dim, 0.0, n, H);
  }
  if (n)
    for (int a = 0; a < dim; a++) n[a] = a == kmax ? copysign(1.0, p[a] - o->a[a]) : 0.0;
  if (H) memset(H, 0, (size_t)(dim * dim) * sizeof(double));
  return q[kmax];
}

double sw_obstacle_sdf(const sw_obstacle *o, int dim, double t, const double *p, double *n,
                       double *H) {
  double disp[3], local[3];
  sw_obstacle_disp(o, t, disp);
  for (int a = 0; a < dim; a++) local[a] = p[a] - disp[a];
  double phi;
  switch (o->shape) {
  case SW_SHAPE_PLANE: phi = plane_sdf(o, dim, local, n, H); break;
  case SW_SHAPE_SPHERE: phi = sphere_sdf(o, dim, local, n, H); break;
  case SW_SHAPE_CAPSULE: phi = capsule_sdf(o, dim, local, n, H); break;
  default: phi = box_sdf(o, dim, local, n, H); break;
  }
  return phi - o->offset; /* m */
}

double sw_obstacle_toi(const sw_obstacle *o, int dim, double t, const double *p0,
                       const double *p1, double keep) {
  double len = 0.0, p[3];
  for (int a = 0; a < dim; a++) len += (p1[a] - p0[a]) * (p1[a] - p0[a]);
  len = sqrt(len); /* m: the whole motion */
  double d0 = sw_obstacle_sdf(o, dim, t, p0, NULL, NULL);
  if (d0 <= 0.0) return 0.0;
  double floor = keep * d0, s = 0.0; /* never closer than this; fraction of the motion done */
  if (d0 - len > floor) return 1.0;
  for (int it = 0; it < SW_TOI_MAX_ITERS; it++) {
    for (int a = 0; a < dim; a++) p[a] = p0[a] + s * (p1[a] - p0[a]);
    double gap = sw_obstacle_sdf(o, dim, t, p, NULL, NULL) - floor;
    if (gap <= 1e-3 * floor) return s; /* at the floor: stop here */
    double ds = gap / len; /* the distance cannot fall faster than the point moves */
    if (s + ds >= 1.0) return 1.0;
    s += ds;
  }
  return s; /* grazing: slow advance, still safe */
}
