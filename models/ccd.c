/* ccd.c — additive continuous collision detection (Li, Kaufman, Jiang, "Codimensional
 * Incremental Potential Contact", SIGGRAPH 2021, sec. 5 and Algorithm 1).
 *
 * Conservative advancement on the distance itself: when every vertex moves linearly, a point of
 * one primitive moves relative to a point of the other by at most l_p = (largest displacement
 * among the first primitive's vertices) + (largest among the second's), after the mean
 * displacement (a common translation, which changes no distance) is removed.  The distance is
 * therefore l_p-Lipschitz in t, and advancing by (1 - s) gap / l_p (gap = d - dmin) can never
 * close the gap: the search stops at the first sample whose gap is below s times the starting
 * gap and returns the last sample before it. */
#include <math.h>

#include "contact_geom.h"

/* Each returns a lower bound of the squared distance: the value computed, less its round-off
 * (edge-edge: also the parallel switch's overestimate, sw_d2_edge_edge_lower), so that an
 * advance computed from it never passes a contact. */
typedef double (*d2_fn)(const double *x);

/* d2 less a round-off margin of 1e-12 (extent + d) in d, m^2: extent is the largest
 * coordinate difference among the n vertices. */
static double lower(double d2, int n, const double *x) {
  double ext = 0.0;
  for (int v = 1; v < n; v++)
    for (int a = 0; a < 3; a++) ext = fmax(ext, fabs(x[3 * v + a] - x[a]));
  double d = sqrt(fmax(d2, 0.0)), margin = 1e-12 * (ext + d);
  return d > margin ? (d - margin) * (d - margin) : 0.0;
}

static double d2_pp(const double *x) { return sw_d2_point_point(x, x + 3, NULL, NULL); }
static double d2_pe(const double *x) {
  return lower(sw_d2_point_edge(x, x + 3, x + 6, NULL, NULL), 3, x);
}
static double d2_pt(const double *x) {
  return lower(sw_d2_point_triangle(x, x + 3, x + 6, x + 9, NULL, NULL), 4, x);
}
static double d2_ee(const double *x) { return sw_d2_edge_edge_lower(x, x + 3, x + 6, x + 9); }

/* Iterations before giving up with the (still conservative) time reached: reached only when
 * the starting gap is tiny against the motion. */
enum { ACCD_MAX_ITER = 100000 };

/* The relative-motion bound l_p of n vertices (the first nfirst form one primitive), their
 * displacements dx made mean-free. */
static double motion_bound(int n, int nfirst, double *dx) {
  double mean[3] = {0.0, 0.0, 0.0}, m0 = 0.0, m1 = 0.0;
  for (int v = 0; v < n; v++)
    for (int a = 0; a < 3; a++) mean[a] += dx[3 * v + a] / n;
  for (int v = 0; v < n; v++) {
    double *u = dx + 3 * v;
    for (int a = 0; a < 3; a++) u[a] -= mean[a];
    double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (v < nfirst) m0 = fmax(m0, l);
    else m1 = fmax(m1, l);
  }
  return m0 + m1;
}

/* (d^2 - dmin^2) / (d + dmin) = d - dmin without cancellation near contact. */
static double gap_of(double d2, double dmin) { return (d2 - dmin * dmin) / (sqrt(d2) + dmin); }

static double accd(int n, int nfirst, const double *x0, const double *x1, d2_fn dist2,
                   double dmin, double tmax) {
  const double s = SW_CCD_SCALE;
  double x[12], dx[12];
  for (int i = 0; i < 3 * n; i++) x[i] = x0[i], dx[i] = x1[i] - x0[i];
  double lp = motion_bound(n, nfirst, dx), d2 = dist2(x);
  if (!(d2 > dmin * dmin)) return 0.0; /* already within dmin (or not finite) */
  if (!(lp > 0.0)) return tmax;
  double gap = gap_of(d2, dmin), target = s * gap, t = 0.0;
  if ((1.0 - s) * gap / lp >= tmax) return tmax; /* the loop's first advance reaches tmax,
                                                     without a use for the distance there */
  for (int it = 0; it < ACCD_MAX_ITER; it++) {
    double tl = (1.0 - s) * gap / lp;
    for (int i = 0; i < 3 * n; i++) x[i] = x0[i] + (t + tl) * dx[i]; /* mean motion removed */
    gap = gap_of(dist2(x), dmin);
    if (t > 0.0 && !(gap >= target)) break;
    t += tl;
    if (t >= tmax) return tmax;
  }
  return t;
}

double sw_ccd_point_point(const double *x0, const double *x1, double dmin, double tmax) {
  return accd(2, 1, x0, x1, d2_pp, dmin, tmax);
}

double sw_ccd_point_edge(const double *x0, const double *x1, double dmin, double tmax) {
  return accd(3, 1, x0, x1, d2_pe, dmin, tmax);
}

double sw_ccd_point_triangle(const double *x0, const double *x1, double dmin, double tmax) {
  return accd(4, 1, x0, x1, d2_pt, dmin, tmax);
}

double sw_ccd_edge_edge(const double *x0, const double *x1, double dmin, double tmax) {
  return accd(4, 2, x0, x1, d2_ee, dmin, tmax);
}
