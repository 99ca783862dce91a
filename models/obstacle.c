/* obstacle.c — the rigid obstacles of a scene (plane, sphere, capsule, box): where each is at
 * time t (a rigid motion: rotation keyframes about an axis, then translation keyframes), the
 * signed distance of a point to its contact surface with the gradient and Hessian of that
 * distance, and conservative times of impact of a point moving on a segment: against the
 * obstacle fixed at one time, and swept against its motion over a step.
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

/* ------------------------------------------------------------------- rigid motion */

static double angle_at(const sw_obstacle *o, double t) { /* rad */
  return o->nrot ? sw_keyframe_value(o->rot_t, o->rot_a, o->nrot, o->interp, t) : 0.0;
}

/* Rodrigues' rotation by th (rad) about the unit axis k, row-major. */
static void rotation(const double *k, double th, double *R) {
  double c = cos(th), s = sin(th), v = 1.0 - c;
  R[0] = c + v * k[0] * k[0], R[1] = v * k[0] * k[1] - s * k[2], R[2] = v * k[0] * k[2] + s * k[1];
  R[3] = v * k[1] * k[0] + s * k[2], R[4] = c + v * k[1] * k[1], R[5] = v * k[1] * k[2] - s * k[0];
  R[6] = v * k[2] * k[0] - s * k[1], R[7] = v * k[2] * k[1] + s * k[0], R[8] = c + v * k[2] * k[2];
}

void sw_obstacle_pose(const sw_obstacle *o, double t, double R[9], double c[3]) {
  sw_obstacle_disp(o, t, c);
  rotation(o->axis, angle_at(o, t), R);
  for (int a = 0; a < 3; a++) c[a] += o->center[a];
}

/* p = R (q - center) + c and its inverse q = R^T (p - c) + center. */
static void body_to_world(const sw_obstacle *o, const double *R, const double *c,
                          const double *q, double *p) {
  double r[3] = {q[0] - o->center[0], q[1] - o->center[1], q[2] - o->center[2]};
  for (int a = 0; a < 3; a++) p[a] = R[3 * a] * r[0] + R[3 * a + 1] * r[1] + R[3 * a + 2] * r[2] + c[a];
}

static void world_to_body(const sw_obstacle *o, const double *R, const double *c,
                          const double *p, double *q) {
  double r[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
  for (int a = 0; a < 3; a++) q[a] = R[a] * r[0] + R[3 + a] * r[1] + R[6 + a] * r[2] + o->center[a];
}

void sw_obstacle_place(const sw_obstacle *o, double t, const double q[3], double p[3]) {
  double R[9], c[3];
  sw_obstacle_pose(o, t, R, c);
  body_to_world(o, R, c, q, p);
}

void sw_obstacle_carry(const sw_obstacle *o, double t0, double t1, const double p[3],
                       double out[3]) {
  double R[9], c[3], q[3];
  sw_obstacle_pose(o, t0, R, c);
  world_to_body(o, R, c, p, q);
  sw_obstacle_place(o, t1, q, out);
}

int sw_obstacle_moves(const sw_obstacle *o, double t0, double t1) {
  double d0[3], d1[3];
  sw_obstacle_disp(o, t0, d0);
  sw_obstacle_disp(o, t1, d1);
  return d0[0] != d1[0] || d0[1] != d1[1] || d0[2] != d1[2] || angle_at(o, t0) != angle_at(o, t1);
}

/* Bounds of keyframes kv (ncomp components, component a of keyframe k at kv[a n + k]) over
 * [t0, t1] of length h: out[0] >= sup |v'| h, out[1] >= sup |v' h - (v(t1) - v(t0))| and
 * out[2] >= sup |v(t) - chord(t)|, the chord joining v(t0) and v(t1) linearly in time.
 * Within one interval: linear 0 and 0; the quintic blend q has |q'| <= 15/8 and
 * |q''| <= 10/sqrt(3), so out[1] <= |q''| |dv| du^2 and out[2] <= |q''| |dv| du^2 / 8 (du the
 * step's share of the interval).  Across intervals: the speed bound alone. */
static void key_bounds(const double *kt, const double *kv, int n, int ncomp, int interp,
                       double t0, double t1, double out[3]) {
  out[0] = out[1] = out[2] = 0.0;
  if (n < 2 || !(t1 > t0) || t1 <= kt[0] || t0 >= kt[n - 1]) return;
  const double f = interp == SW_INTERP_SMOOTH ? 1.875 : 1.0, q2 = 10.0 / sqrt(3.0);
  double h = t1 - t0, vmax = 0.0, dv1 = 0.0, du1 = 0.0;
  int single = 0;
  for (int k = 0; k + 1 < n; k++) {
    if (kt[k + 1] <= t0 || kt[k] >= t1) continue;
    double dv = 0.0, dt = kt[k + 1] - kt[k];
    for (int a = 0; a < ncomp; a++) dv += (kv[a * n + k + 1] - kv[a * n + k]) * (kv[a * n + k + 1] - kv[a * n + k]);
    dv = sqrt(dv);
    vmax = fmax(vmax, f * dv / dt);
    if (kt[k] <= t0 && t1 <= kt[k + 1]) single = 1, dv1 = dv, du1 = h / dt;
  }
  out[0] = vmax * h;
  if (single && interp == SW_INTERP_LINEAR) return;
  if (single) {
    out[1] = q2 * dv1 * du1 * du1;
    out[2] = 0.125 * out[1];
    return;
  }
  double chord = 0.0;
  for (int a = 0; a < ncomp; a++) {
    double d = sw_keyframe_value(kt, kv + a * n, n, interp, t1) - sw_keyframe_value(kt, kv + a * n, n, interp, t0);
    chord += d * d;
  }
  out[1] = out[0] + sqrt(chord);
  out[2] = out[0];
}

void sw_obstacle_bounds(const sw_obstacle *o, double t0, double t1, sw_motion_bounds *b) {
  double tr[3] = {0.0, 0.0, 0.0}, an[3] = {0.0, 0.0, 0.0};
  if (o->nkey) key_bounds(o->key_t, o->key_d, o->nkey, 3, o->interp, t0, t1, tr);
  if (o->nrot) key_bounds(o->rot_t, o->rot_a, o->nrot, 1, o->interp, t0, t1, an);
  b->move = tr[0], b->rate_dev = tr[1], b->pos_dev = tr[2];
  b->turn = an[0], b->turn_dev = an[2];
  b->dangle = fabs(angle_at(o, t1) - angle_at(o, t0));
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

/* The distance of a point in the body's frame (its stated place). */
static double body_sdf(const sw_obstacle *o, int dim, const double *q, double *n, double *H) {
  double phi;
  switch (o->shape) {
  case SW_SHAPE_PLANE: phi = plane_sdf(o, dim, q, n, H); break;
  case SW_SHAPE_SPHERE: phi = sphere_sdf(o, dim, q, n, H); break;
  case SW_SHAPE_CAPSULE: phi = capsule_sdf(o, dim, q, n, H); break;
  default: phi = box_sdf(o, dim, q, n, H); break;
  }
  return phi - o->offset; /* m */
}

double sw_obstacle_sdf(const sw_obstacle *o, int dim, double t, const double *p, double *n,
                       double *H) {
  double R[9], c[3], q[3] = {0.0, 0.0, 0.0}, pw[3] = {0.0, 0.0, 0.0};
  memcpy(pw, p, (size_t)dim * sizeof(double));
  if (!o->nrot) { /* a translation only */
    sw_obstacle_disp(o, t, c);
    for (int a = 0; a < dim; a++) q[a] = p[a] - c[a];
    return body_sdf(o, dim, q, n, H);
  }
  sw_obstacle_pose(o, t, R, c);
  world_to_body(o, R, c, pw, q);
  double nb[3] = {0.0, 0.0, 0.0}, Hb[9], phi = body_sdf(o, dim, q, n ? nb : NULL, H ? Hb : NULL);
  /* back to the world: n = R nb, H = R Hb R^T (in 2D the axis is z: R's upper 2 x 2 block) */
  for (int a = 0; n && a < dim; a++) {
    n[a] = 0.0;
    for (int b = 0; b < dim; b++) n[a] += R[3 * a + b] * nb[b];
  }
  for (int a = 0; H && a < dim; a++)
    for (int b = 0; b < dim; b++) {
      double v = 0.0;
      for (int i = 0; i < dim; i++)
        for (int j = 0; j < dim; j++) v += R[3 * a + i] * Hb[i * dim + j] * R[3 * b + j];
      H[a * dim + b] = v;
    }
  return phi;
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

/* The rate bound of the swept distance (m per unit of the step's fraction): the point's motion
 * relative to the body's material point under it, |(p1 - p0) - dc| (dc the translation over
 * the step) + the translation's departure from uniform speed + the turn rate times the
 * largest distance from the axis the point can have. */
static double swept_rate(const sw_obstacle *o, int dim, double t0, double t1, const double *p0,
                         const double *p1, const sw_motion_bounds *b) {
  double c0[3], c1[3], rel = 0.0, rho = 0.0, len = 0.0;
  sw_obstacle_disp(o, t0, c0);
  sw_obstacle_disp(o, t1, c1);
  for (int a = 0; a < dim; a++) {
    double u = (p1[a] - p0[a]) - (c1[a] - c0[a]), r = p0[a] - c0[a] - o->center[a];
    rel += u * u, rho += r * r, len += (p1[a] - p0[a]) * (p1[a] - p0[a]);
  }
  return sqrt(rel) + b->rate_dev + b->turn * (sqrt(rho) + sqrt(len) + b->move);
}

double sw_obstacle_swept_toi(const sw_obstacle *o, int dim, double t0, double t1,
                             const double *p0, const double *p1, double floor) {
  sw_motion_bounds b;
  sw_obstacle_bounds(o, t0, t1, &b);
  double L = swept_rate(o, dim, t0, t1, p0, p1, &b), s = 0.0, p[3];
  double d = sw_obstacle_sdf(o, dim, t0, p0, NULL, NULL), gap0 = d - floor;
  if (!(gap0 > 0.0)) return 0.0;
  if (!(L > 0.0)) return 1.0;
  for (int it = 0; it < SW_SWEPT_MAX_ITERS; it++) {
    double gap = d - floor;
    if (s > 0.0 && gap <= 1e-3 * gap0) return s; /* at the floor: stop here */
    double ds = gap / L; /* the distance cannot fall faster than L */
    if (s + ds >= 1.0) return 1.0;
    s += ds;
    for (int a = 0; a < dim; a++) p[a] = p0[a] + s * (p1[a] - p0[a]);
    d = sw_obstacle_sdf(o, dim, t0 + s * (t1 - t0), p, NULL, NULL);
  }
  return s; /* grazing: slow advance, still safe */
}
