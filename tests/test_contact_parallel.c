/* test_contact_parallel.c — nearly parallel edges (models/distance.c, models/ccd.c), at every
 * angle from exactly parallel through 1e-13 .. 1e-3 rad and every scale (edges of 1e-8 m to
 * 1e4 m, placed up to ten edge lengths from the origin), each pair in a random rigid placement
 * (a random rotation and translation):
 *  - the squared distance against a binary128 (__float128) evaluation of the clamped
 *    segment-segment distance (Lumelsky, "On fast computation of distance between line
 *    segments", 1985) from the same double coordinates: never below it by more than round-off,
 *    never above it by more than the parallel switch's stated bound, and the lower bound that
 *    CCD uses never above it;
 *  - additive CCD on pairs built to cross (their lines meet inside both edges at a known time,
 *    a thickness 0 or 1e-3 of the edge) misses none and stops before the crossing; on pairs
 *    built not to meet it stays safe and does not stop while the gap stays above twice the
 *    scaling's share;
 *  - the gradient of the mollified squared distance (what the barrier uses) against central
 *    differences at every angle, across the switch too; the plain one's where differences in
 *    double resolve it (from 1e-4 rad); its jump at the switch within the stated bound. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include <cmocka.h>

#include "contact_geom.h"
#include "harness.h"

typedef __float128 quad;

static double urand(unsigned long *rs) { return 0.5 * (th_rand(rs) + 1.0); } /* [0, 1) */

/* ------------------------------------------------------------ the binary128 reference */

static quad qdot(const quad *a, const quad *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Squared distance from p to the segment e0 e1 (binary128). */
static quad q_point_segment(const quad *p, const quad *e0, const quad *e1) {
  quad e[3], w[3], r[3];
  for (int a = 0; a < 3; a++) e[a] = e1[a] - e0[a], w[a] = p[a] - e0[a];
  quad ee = qdot(e, e), s = ee > 0 ? qdot(w, e) / ee : 0;
  s = s < 0 ? 0 : s > 1 ? 1 : s;
  for (int a = 0; a < 3; a++) r[a] = w[a] - s * e[a];
  return qdot(r, r);
}

/* The segments' squared distance: the line-line minimiser when it lies in the parameter square,
 * else the smallest end-point-to-segment distance (the minimum of a convex quadratic over a
 * square is inside or on its boundary). */
static double ref_d2(const double *x) {
  quad q[12];
  for (int i = 0; i < 12; i++) q[i] = x[i];
  quad *a0 = q, *a1 = q + 3, *b0 = q + 6, *b1 = q + 9, ea[3], eb[3], r[3];
  for (int a = 0; a < 3; a++) ea[a] = a1[a] - a0[a], eb[a] = b1[a] - b0[a], r[a] = a0[a] - b0[a];
  quad best = q_point_segment(a0, b0, b1), t;
  if ((t = q_point_segment(a1, b0, b1)) < best) best = t;
  if ((t = q_point_segment(b0, a0, a1)) < best) best = t;
  if ((t = q_point_segment(b1, a0, a1)) < best) best = t;
  quad A = qdot(ea, ea), B = qdot(ea, eb), C = qdot(eb, eb), D = qdot(ea, r), E = qdot(eb, r);
  quad det = A * C - B * B;
  if (det > 0) {
    quad s = (B * E - C * D) / det, u = (A * E - B * D) / det, w[3];
    if (s >= 0 && s <= 1 && u >= 0 && u <= 1) {
      for (int a = 0; a < 3; a++) w[a] = r[a] + s * ea[a] - u * eb[a];
      if ((t = qdot(w, w)) < best) best = t;
    }
  }
  return (double)best;
}

/* ----------------------------------------------------------------- random rigid placements */

typedef struct placement {
  double Q[9], T[3]; /* x -> Q x + T */
} placement;

/* A uniformly random rotation (a random unit quaternion) and a translation of up to ten
 * times `scale` per axis. */
static placement random_placement(unsigned long *rs, double scale) {
  double q[4], n = 0.0;
  do {
    n = 0.0;
    for (int k = 0; k < 4; k++) q[k] = th_rand(rs), n += q[k] * q[k];
  } while (n > 1.0 || n < 1e-3);
  n = sqrt(n);
  double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
  placement p = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                  2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                  2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)},
                 {0, 0, 0}};
  for (int a = 0; a < 3; a++) p.T[a] = 10.0 * scale * th_rand(rs);
  return p;
}

static void place(const placement *p, const double *local, double *x, int n) {
  for (int v = 0; v < n; v++)
    for (int a = 0; a < 3; a++)
      x[3 * v + a] = p->Q[3 * a] * local[3 * v] + p->Q[3 * a + 1] * local[3 * v + 1] +
                     p->Q[3 * a + 2] * local[3 * v + 2] + p->T[a];
}

/* The angle of a sample: exactly 0 one time in eight, else 10^-k for k uniform in [3, 13]. */
static double random_angle(unsigned long *rs) {
  return urand(rs) < 0.125 ? 0.0 : pow(10.0, -3.0 - 10.0 * urand(rs));
}

/* Local frame: edge a along x through the origin region, edge b at angle th in the xy plane,
 * height h along z, shifted by (sa along a, sb along b) so the lines' crossing point sits at
 * parameter 1/2 - sa/La on a and 1/2 - sb/Lb on b. */
static void local_pair(double La, double Lb, double th, double h, double sa, double sb,
                       double slide, double *y) {
  double c = cos(th), s = sin(th);
  double ya[6] = {-0.5 * La + sa + slide, 0, 0, 0.5 * La + sa + slide, 0, 0};
  double yb[6] = {(-0.5 * Lb + sb) * c, (-0.5 * Lb + sb) * s, h,
                  (0.5 * Lb + sb) * c, (0.5 * Lb + sb) * s, h};
  memcpy(y, ya, sizeof ya);
  memcpy(y + 6, yb, sizeof yb);
}

/* ------------------------------------------------------------------------- distances */

/* Twenty thousand static pairs: the distance within the stated bounds of the reference. */
static void parallel_distance(void **st) {
  (void)st;
  unsigned long rs = 101;
  double worst_over = 0.0, worst_under = 0.0, worst_rel = 0.0;
  for (int rep = 0; rep < 20000; rep++) {
    double S = pow(10.0, -8.0 + 12.0 * urand(&rs)); /* m */
    double La = S * (0.2 + 0.8 * urand(&rs)), Lb = S * (0.2 + 0.8 * urand(&rs));
    double th = random_angle(&rs), h = S * pow(10.0, -7.0 + 7.0 * urand(&rs));
    double sa = 1.6 * La * th_rand(&rs), sb = 1.6 * Lb * th_rand(&rs); /* overlap or not */
    double y[12], x[12];
    local_pair(La, Lb, th, h, sa, sb, 0.0, y);
    placement p = random_placement(&rs, S);
    place(&p, y, x, 4);
    double d2 = sw_d2_edge_edge(x, x + 3, x + 6, x + 9, NULL, NULL), ref = ref_d2(x);
    double lo = sw_d2_edge_edge_lower(x, x + 3, x + 6, x + 9);
    double Lmin = fmin(La, Lb), Lmax = fmax(La, Lb), d = sqrt(d2), dr = sqrt(ref);
    /* stated (docs/contact.md): d^2 <= ref + 2e-14 Lmin^2 and d >= d_ref - 1e-11 (Lmax + d),
     * each up to a relative 1e-12 of rounding; the lower bound never above the reference */
    double over = d2 - ref, under = dr - d;
    worst_over = fmax(worst_over, over / (Lmin * Lmin));
    worst_under = fmax(worst_under, under / (Lmax + dr));
    if (dr >= 1e-3 * Lmax) worst_rel = fmax(worst_rel, fabs(d - dr) / dr);
    if (!(over <= 2e-14 * Lmin * Lmin + 1e-12 * ref && under <= 1e-11 * (Lmax + dr) && lo <= ref))
      print_error("rep %d: scale %g angle %g height %g: d2 %.17g ref %.17g lower %.17g type %d\n", rep,
                  S, th, h, d2, ref, lo, (int)sw_edge_edge_type(x, x + 3, x + 6, x + 9));
    if (!(lo <= ref)) { for (int i = 0; i < 12; i++) print_error("%.17g,", x[i]); print_error("\n"); }
    assert_true(over <= 2e-14 * Lmin * Lmin + 1e-12 * ref);
    assert_true(under <= 1e-11 * (Lmax + dr));
    assert_true(lo <= ref);
  }
  print_message("distance: worst excess %.3g Lmin^2 (bound 2e-14), worst deficit %.3g (Lmax + d) "
                "(bound 1e-11), worst relative error where d >= 1e-3 Lmax %.3g\n",
                worst_over, worst_under, worst_rel);
  assert_true(worst_rel < 1e-7);
}

/* ------------------------------------------------------------------------------ CCD */

static double dist_at(const double *x0, const double *x1, double t) {
  double x[12];
  for (int i = 0; i < 12; i++) x[i] = x0[i] + t * (x1[i] - x0[i]);
  return sqrt(ref_d2(x));
}

/* Pairs that cross: the edges' lines meet inside both (at parameters in [0.2, 0.8]) when the
 * height h(t) = h0 - t (h0 + h1) is zero, both edges moving (a common random translation, b
 * down through a, a sliding along itself by up to a tenth of its length); and pairs that do
 * not meet: b stays above (h1 < 0), or b lies beyond the end of a along it. */
static void parallel_ccd(void **st) {
  (void)st;
  unsigned long rs = 202;
  int crossing = 0, apart = 0, stopped_apart = 0;
  for (int rep = 0; rep < 24000; rep++) {
    int cross = rep % 2;
    double S = pow(10.0, -8.0 + 12.0 * urand(&rs));
    double La = S * (0.2 + 0.8 * urand(&rs)), Lb = S * (0.2 + 0.8 * urand(&rs));
    double th = random_angle(&rs), dmin = rep % 4 < 2 ? 0.0 : 1e-3 * fmin(La, Lb);
    double h0 = dmin + S * pow(10.0, -6.0 + 6.0 * urand(&rs)), h1, sa, sb;
    double slide = 0.1 * La * th_rand(&rs);
    if (cross) {
      h1 = S * pow(10.0, -6.0 + 6.0 * urand(&rs));
      sa = 0.3 * La * th_rand(&rs), sb = 0.3 * Lb * th_rand(&rs);
    } else if (rep % 4 == 1) { /* above all the way, closest at the end */
      h1 = -dmin - (h0 - dmin) * (0.3 + 0.7 * urand(&rs));
      sa = 0.3 * La * th_rand(&rs), sb = 0.3 * Lb * th_rand(&rs);
    } else { /* beyond the end of a along the common direction */
      h1 = S * pow(10.0, -6.0 + 6.0 * urand(&rs));
      sa = 0.0, sb = (0.5 * (La + Lb) + 0.1 * La + 0.2 * S * urand(&rs)) / cos(th);
    }
    double y0[12], y1[12], x0[12], x1[12];
    local_pair(La, Lb, th, h0, sa, sb, 0.0, y0);
    local_pair(La, Lb, th, -h1, sa, sb, slide, y1);
    for (int v = 2; v < 4; v++) y1[3 * v] -= slide; /* only a slides */
    placement p = random_placement(&rs, S);
    place(&p, y0, x0, 4);
    double drift[3];
    for (int a = 0; a < 3; a++) drift[a] = S * th_rand(&rs);
    place(&p, y1, x1, 4);
    for (int i = 0; i < 12; i++) x1[i] += drift[i % 3];
    double toi = sw_ccd_edge_edge(x0, x1, dmin, 1.0);
    double g0 = dist_at(x0, x1, 0.0) - dmin;
    assert_true(g0 > 0.0);
    /* safe: above dmin at toi and at 200 samples before it (binary128 distances) */
    for (int i = 0; i <= 200; i++) {
      double d = dist_at(x0, x1, toi * i / 200.0);
      if (!(d > dmin))
        print_error("rep %d (%s): scale %g angle %g: toi %.17g, distance %.17g at %g toi, dmin %g\n",
                    rep, cross ? "crossing" : "apart", S, th, toi, d, i / 200.0, dmin);
      assert_true(d > dmin);
    }
    if (cross) { /* the distance is |h(t)| while the lines meet inside both edges */
      double thit = (h0 - dmin) / (h0 + h1);
      if (!(toi < thit * (1 + 1e-9)))
        print_error("rep %d: missed: scale %g angle %g toi %.17g hit %.17g\n", rep, S, th, toi,
                    thit);
      assert_true(toi < thit * (1 + 1e-9));
      crossing++;
      continue;
    }
    /* apart: the smallest gap over the motion (sampled) above twice the scaling's share of
     * the starting gap means CCD has no reason to stop */
    double gmin = INFINITY;
    for (int i = 0; i <= 400; i++) gmin = fmin(gmin, dist_at(x0, x1, i / 400.0) - dmin);
    apart++;
    if (gmin > 2.0 * SW_CCD_SCALE * g0) {
      stopped_apart += toi < 1.0;
      assert_true(toi == 1.0);
    }
  }
  print_message("CCD: %d crossing pairs, none missed; %d pairs apart (%d stopped early)\n",
                crossing, apart, stopped_apart);
  assert_int_equal(crossing, 12000);
}

/* ----------------------------------------------------------------- finite differences */

/* Largest error of the gradient of f over the 12 coordinates against central differences of
 * step h, relative to the gradient's largest entry (or floor if larger); for the plain distance, -1 when its closest
 * features change within the stencil (its gradient jumps there). */
typedef double (*d2_fn)(const double *x, double *g);
static double eps_x_now;
static double f_d2(const double *x, double *g) {
  return sw_d2_edge_edge(x, x + 3, x + 6, x + 9, g, NULL);
}
static double f_moll(const double *x, double *g) {
  return sw_d2_edge_edge_mollified(x, x + 3, x + 6, x + 9, eps_x_now, g, NULL);
}

static double fd_error(d2_fn f, const double *x, double h, double floor) {
  double g[12], y[12], gmax = floor + 1e-300, err = 0.0;
  f(x, g);
  for (int i = 0; i < 12; i++) gmax = fmax(gmax, fabs(g[i]));
  for (int i = 0; i < 12; i++) {
    memcpy(y, x, sizeof y);
    int ty = (int)sw_edge_edge_type(x, x + 3, x + 6, x + 9);
    y[i] = x[i] + h;
    double fp = f(y, NULL);
    if (f == f_d2 && (int)sw_edge_edge_type(y, y + 3, y + 6, y + 9) != ty) return -1;
    y[i] = x[i] - h;
    double fm = f(y, NULL);
    if (f == f_d2 && (int)sw_edge_edge_type(y, y + 3, y + 6, y + 9) != ty) return -1;
    err = fmax(err, fabs((fp - fm) / (2 * h) - g[i]) / gmax);
  }
  return err;
}

/* Overlapping edges of lengths S and 0.8 S at height 0.1 S (their closest points interior:
 * line-line above the switch, an end point below it), the angle swept from 0 through the
 * switch at sin theta = 1e-7 to 1e-3, each in three random placements of scale S = 1e-6, 1 and
 * 1e3: the mollified squared distance at every angle, the plain one where differences resolve
 * it, and the jump of the plain one at the switch. */
static void parallel_gradients(void **st) {
  (void)st;
  unsigned long rs = 303;
  const double angles[] = {0.0,  1e-13, 1e-11, 1e-10, 1e-9, 1e-8, 3e-8,  5e-8, 9.9e-8,
                           1e-7, 1.01e-7, 2e-7, 5e-7,  1e-6, 1e-5, 1e-4,  1e-3};
  const double scales[] = {1e-6, 1.0, 1e3};
  double worst_d2 = 0.0, worst_moll = 0.0;
  int tested = 0;
  for (size_t k = 0; k < sizeof angles / sizeof *angles; k++)
    for (int sc = 0; sc < 3; sc++) {
      double S = scales[sc], y[12], x[12];
      local_pair(S, 0.8 * S, angles[k], 0.1 * S, 0.05 * S, -0.03 * S, 0.0, y);
      placement p = random_placement(&rs, S);
      place(&p, y, x, 4);
      double th = angles[k];
      /* the plain distance where its derivatives can be resolved by differences in double:
       * its minimiser moves by (gap / theta^2) per unit tilt out of the edges' plane, so the
       * step is 1e-2 theta^2 S (about the origin), from theta = 1e-4 on */
      if (th >= 1e-4) {
        double xc[12];
        for (int i = 0; i < 12; i++) xc[i] = x[i] - p.T[i % 3];
        double e = fd_error(f_d2, xc, 1e-2 * th * th * S, 0.0);
        assert_true(e >= 0.0); /* the closest features stay both interiors */
        worst_d2 = fmax(worst_d2, e);
        if (!(e < 1e-4)) print_error("d2: angle %g scale %g: error %g\n", th, S, e);
        assert_true(e < 1e-4);
      }
      /* continuity across the switch: the value just below it exceeds the one just above
       * by at most the stated 2 sin^2 min(|ea|, |eb|)^2 */
      if (th == 1e-7) {
        double yb[12], ya[12], xb[12], xa[12];
        local_pair(S, 0.8 * S, 0.999e-7, 0.1 * S, 0.05 * S, -0.03 * S, 0.0, yb);
        local_pair(S, 0.8 * S, 1.001e-7, 0.1 * S, 0.05 * S, -0.03 * S, 0.0, ya);
        place(&p, yb, xb, 4);
        place(&p, ya, xa, 4);
        double jump = f_d2(xb, NULL) - f_d2(xa, NULL), L = 0.8 * S;
        assert_true(sw_edge_edge_type(xb, xb + 3, xb + 6, xb + 9) != SW_EE_LINES);
        assert_true(sw_edge_edge_type(xa, xa + 3, xa + 6, xa + 9) == SW_EE_LINES);
        assert_true(fabs(jump) <= 2e-14 * L * L);
        tested++;
      }
      /* the mollified distance everywhere, across the switch too; its gradient vanishes as
       * sin theta at parallel, so errors are relative to d^2 / S when it is smaller (the
       * unmollified gradient there is 2 d = 20 d^2 / S) */
      eps_x_now = sw_ee_mollifier_eps(y, y + 3, y + 6, y + 9);
      double e = fd_error(f_moll, x, 1e-9 * S, f_d2(x, NULL) / S);
      worst_moll = fmax(worst_moll, e);
      if (!(e < 1e-5)) print_error("mollified: angle %g scale %g: error %g\n", th, S, e);
      assert_true(e < 1e-5);
    }
  print_message("gradients: worst relative error %.3g (squared distance, 6 states), %.3g "
                "(mollified, 51 states)\n", worst_d2, worst_moll);
  assert_int_equal(tested, 3);
}

/* The case: overlapping unit edges 1 apart at 1e-9 rad, distance 1 (it was 5). */
static void parallel_example(void **st) {
  (void)st;
  double y[12];
  local_pair(1.0, 1.0, 1e-9, 1.0, 0.2, -0.1, 0.0, y);
  double d = sqrt(sw_d2_edge_edge(y, y + 3, y + 6, y + 9, NULL, NULL));
  assert_true(fabs(d - 1.0) < 1e-12);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(parallel_example),
      cmocka_unit_test(parallel_distance),
      cmocka_unit_test(parallel_ccd),
      cmocka_unit_test(parallel_gradients),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
