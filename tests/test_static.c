/* test_static.c — the static solve against analytic answers, and its stopping rule.
 *
 * The elastic catenary of H. M. Irvine ("Cable Structures", MIT Press 1981, chapter 2; the
 * helper th_irvine_* in harness.c) is checked first on its own (its conditions, the equilibrium
 * equations it integrates, the inextensible catenary as EA -> infinity).  Then chains of N
 * spring links between two pins, each link a two-waypoint `spring` tendon whose density makes
 * it weigh W/N, are solved statically: the lumped masses sit at the nodes, which are the
 * material points s = k L0/N, so the chain is a second-order discretisation of the continuous
 * cable and its error against Irvine's solution (mid-span sag, the horizontal reaction H and the
 * vertical one V) falls as h^2 = (L0/N)^2.  The solver's own error (the round-off floor) is
 * many orders below the N = 160 discretisation error, so what the orders measure is the
 * lumping.
 *
 * The stopping rule (solvers/static.c, docs/integrators.md): converged at the force tolerance
 * or at the round-off floor.  A stiff chain (links of 1e7 N/m under 0.1 N) cannot reach the
 * default tolerance in floating point and stops at the floor with success and its positions;
 * the rule it replaces (1-norm of the free forces <= 1e-10 of the force scale) reported it as
 * "did not converge in 1000 iterations". */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "solver.h"

#define G 9.81 /* m/s^2 */

/* ------------------------------------------------------------ Irvine's solution */

/* H and V of the inextensible catenary of length L0 and weight W between supports l apart
 * with the far one h lower: with a = H/w (w = W/L0), sqrt(L0^2 - h^2) = 2 a sinh(l / (2a))
 * (bisection on a).  Returns H. */
static double inextensible_H(double l, double h, double L0, double W) {
  double lo = 1e-6 * l, hi = 1e6 * l, target = sqrt(L0 * L0 - h * h);
  for (int it = 0; it < 300; it++) {
    double a = sqrt(lo * hi);
    if (2.0 * a * sinh(l / (2.0 * a)) > target) lo = a; /* too long: a larger a is flatter */
    else hi = a;
  }
  return sqrt(lo * hi) * W / L0;
}

static void irvine_solution(void **st) {
  (void)st;
  const double cases[3][5] = {
      /* l, h, L0, EA, W */
      {1.0, 0.0, 1.1, 20.0, 1.0},   /* level, 3 % stretch */
      {1.0, -0.4, 1.2, 50.0, 2.0},  /* far support 0.4 m higher */
      {1.0, 0.3, 1.0, 1e3, 0.5},    /* lower, nearly taut: held by its stretch */
  };
  for (int k = 0; k < 3; k++) {
    th_irvine c = {cases[k][0], cases[k][1], cases[k][2], cases[k][3], cases[k][4], 0, 0};
    assert_int_equal(th_irvine_solve(&c), 0);
    double x, z;
    th_irvine_point(&c, c.L0, &x, &z); /* the far end lands on the support */
    assert_true(fabs(x - c.l) < 1e-12 && fabs(z - c.h) < 1e-12);
    th_irvine_point(&c, 0.0, &x, &z);
    assert_true(fabs(x) < 1e-15 && fabs(z) < 1e-15);
    /* the Jacobian against central differences */
    double f[2], J[4], fp[2], fm[2], Jd[4];
    th_irvine_conditions(&c, c.H, c.V, f, J);
    for (int j = 0; j < 2; j++) {
      double e = 1e-6 * (j ? fabs(c.V) + c.W : c.H);
      th_irvine_conditions(&c, c.H + (j ? 0 : e), c.V + (j ? e : 0), fp, Jd);
      th_irvine_conditions(&c, c.H - (j ? 0 : e), c.V - (j ? e : 0), fm, Jd);
      for (int i = 0; i < 2; i++)
        assert_true(fabs((fp[i] - fm[i]) / (2 * e) - J[2 * i + j]) < 1e-7 * (fabs(J[0]) + fabs(J[3])));
    }
    /* the equilibrium of the stretched cable: dx/ds = H (1/EA + 1/T), dz/ds = (V - w s)(1/EA
     * + 1/T), T = sqrt(H^2 + (V - w s)^2) the tension, w = W/L0 */
    const double w = c.W / c.L0, ds = 1e-4 * c.L0;
    for (int q = 1; q < 8; q++) {
      double s = c.L0 * q / 8.0, x1, z1, x2, z2;
      th_irvine_point(&c, s + ds, &x2, &z2);
      th_irvine_point(&c, s - ds, &x1, &z1);
      double T = hypot(c.H, c.V - w * s), stretch = 1.0 / c.EA + 1.0 / T;
      assert_true(fabs((x2 - x1) / (2 * ds) - c.H * stretch) < 1e-8);
      assert_true(fabs((z2 - z1) / (2 * ds) - (c.V - w * s) * stretch) < 1e-8);
    }
    print_message("Irvine l %g h %g L0 %g EA %g W %g: H %.12g N, V %.12g N\n", c.l, c.h, c.L0,
                  c.EA, c.W, c.H, c.V);
  }
  /* EA -> infinity: the inextensible catenary, level (closed-form sag) and inclined */
  for (int k = 0; k < 2; k++) {
    th_irvine c = {1.0, k ? -0.4 : 0.0, 1.2, 0.0, 2.0, 0, 0};
    c.EA = 1e13 * c.W;
    assert_int_equal(th_irvine_solve(&c), 0);
    double Hi = inextensible_H(c.l, c.h, c.L0, c.W), x, z;
    print_message("EA = 1e13 W, h = %g: H %.12g N, inextensible %.12g N\n", c.h, c.H, Hi);
    assert_true(fabs(c.H - Hi) < 1e-9 * Hi);
    if (k == 0) { /* sag (H/w)(cosh(w l / 2H) - 1), and V = W/2 */
      double w = c.W / c.L0, sag = Hi / w * (cosh(w * c.l / (2 * Hi)) - 1.0);
      th_irvine_point(&c, 0.5 * c.L0, &x, &z);
      assert_true(fabs(z - sag) < 1e-9 * sag && fabs(x - 0.5 * c.l) < 1e-12);
      assert_true(fabs(c.V - 0.5 * c.W) < 1e-12 * c.W);
    }
  }
}

/* ------------------------------------------------------------------ chains */

static int chain_dense_max = SW_TENDON_DENSE_MAX; /* 0: every link on the low-rank path */

/* The chain of N links for cable c, 2D with y up: supports at (ox, oy) and (ox + l, oy - h)
 * pinned.  The nodes start at equal arc lengths on the parabola through the supports whose
 * length is 2 % more than L0 (a straight line when the supports are further apart than that):
 * every link starts stretched, none compressed.  Link k is a spring tendon of stiffness
 * EA N / L0 and rest length L0 / N whose density (per initial length) makes its mass
 * W / (N g), half of it lumped at each end: every free node carries W / N, each pin W / (2N). */
static sw_model *chain_model(int N, const th_irvine *c, double ox, double oy) {
  sw_model *m = sw_model_new();
  m->opt.tendon_dense_max = chain_dense_max;
  m->dim = 2;
  m->nv = N + 1;
  m->x0 = calloc((size_t)m->nv * 2, sizeof(double));
  m->v0 = calloc((size_t)m->nv * 2, sizeof(double));
  m->pinned = calloc((size_t)m->nv, 1);
  m->pinned[0] = m->pinned[N] = 1;
  m->has_gravity = 1;
  m->gravity[1] = -G;
  /* the parabola y = -h t - 4 f t (1 - t), t = x / l, sampled at M points; f by bisection */
  enum { M = 20000 };
  static double arc[M + 1];
  double target = 1.02 * c->L0, lo = 0.0, hi = 0.0, f = 0.0;
  if (target > hypot(c->l, c->h)) {
    hi = c->L0;
    for (int it = 0; it < 100; it++) {
      f = 0.5 * (lo + hi);
      double len = 0.0;
      for (int q = 0; q < M; q++) {
        double t = (q + 0.5) / M, dy = -c->h - 4.0 * f * (1.0 - 2.0 * t);
        len += hypot(c->l, dy) / M;
      }
      if (len > target) hi = f;
      else lo = f;
    }
  }
  arc[0] = 0.0;
  for (int q = 0; q < M; q++) {
    double t = (q + 0.5) / M, dy = -c->h - 4.0 * f * (1.0 - 2.0 * t);
    arc[q + 1] = arc[q] + hypot(c->l, dy) / M;
  }
  for (int k = 0, q = 0; k <= N; k++) { /* t at arc length k/N of the whole, by interpolation */
    double s = arc[M] * k / N;
    while (q < M - 1 && arc[q + 1] < s) q++;
    double t = (q + (s - arc[q]) / (arc[q + 1] - arc[q])) / M;
    if (k == N) t = 1.0;
    m->x0[2 * k] = ox + c->l * t;
    m->x0[2 * k + 1] = oy - c->h * t - 4.0 * f * t * (1.0 - t);
  }
  for (int k = 0; k < N; k++) {
    int way[2] = {k, k + 1};
    double len = hypot(m->x0[2 * k + 2] - m->x0[2 * k], m->x0[2 * k + 3] - m->x0[2 * k + 1]);
    th_add_tendon(m, way, 2, SW_LAW_SPRING, c->EA * N / c->L0, c->L0 / N,
                  c->W / (N * G * len));
  }
  return m;
}

typedef struct chain_result {
  int rc;
  double mx, my;          /* the middle node (s = L0/2) relative to the first support, y up */
  double H, V;            /* horizontal and vertical reaction of the first pin, N */
  double Ry;              /* vertical reactions summed, N */
  sw_static_info info;
} chain_result;

/* Solve the chain statically (force_tol > 0: that tolerance instead of the default). */
static chain_result solve_chain(int N, const th_irvine *c, double ox, double oy,
                                double force_tol) {
  sw_model *m = chain_model(N, c, ox, oy);
  if (force_tol > 0.0) m->opt.newton_force_tol = force_tol;
  char err[SW_ERRSZ];
  if (sw_model_finish(m, err, sizeof err)) print_error("%s\n", err);
  assert_true(fabs(m->total_mass * G - c->W) < 1e-12 * c->W);
  sw_data *d = sw_data_new(m);
  double reaction[3] = {0.0, 0.0, 0.0};
  chain_result r = {0};
  r.rc = sw_static_solve(m, d, reaction, err, sizeof err);
  if (r.rc) print_message("N = %d: %s\n", N, err);
  r.mx = d->x[N] - ox; /* vertex N/2, N even */
  r.my = d->x[N + 1] - oy;
  r.H = -d->grad[0]; /* the pin pulls the cable's end back: -H along x */
  r.V = d->grad[1];
  r.Ry = reaction[1];
  r.info = d->static_info;
  sw_data_free(d);
  sw_model_free(m);
  return r;
}

static double order(double e1, double e2) { return log2(e1 / e2); }

/* 40, 80, 160 links against Irvine: mid-span sag, H and V converge as h^2. */
static void catenary_orders(const th_irvine *c, const char *what) {
  double xm, zm;
  th_irvine_point(c, 0.5 * c->L0, &xm, &zm);
  const int Ns[3] = {40, 80, 160};
  double esag[3], eH[3], eV[3], h[3];
  for (int k = 0; k < 3; k++) {
    chain_result r = solve_chain(Ns[k], c, 0.0, 0.0, 0.0);
    assert_int_equal(r.rc, 0);
    h[k] = c->L0 / Ns[k];
    /* level: the mid-span sag, -y at s = L0/2 (z down), relative; inclined: the distance of
     * the middle node from Irvine's point s = L0/2, relative to the span */
    double ex = fabs(r.mx - xm) / c->l;
    esag[k] = c->h == 0.0 ? fabs(-r.my - zm) / zm : hypot(r.mx - xm, -r.my - zm) / c->l;
    eH[k] = fabs(r.H - c->H) / c->H;
    eV[k] = fabs(r.V - c->V) / c->W;
    print_message("%s N = %3d: drop %.10f m (Irvine %.10f, err %.3e), x err %.2e, H %.10f N "
                  "(Irvine %.10f, rel err %.3e), V err %.3e W; %d iterations, largest force "
                  "%.2e N, floor %.2e N (%.3f of it), tolerance %.2e N, stopped at %s\n",
                  what, Ns[k], -r.my, zm, esag[k], ex, r.H, c->H, eH[k], eV[k],
                  r.info.iterations, r.info.force, r.info.floor, r.info.floor_ratio, r.info.tol,
                  r.info.roundoff ? "the round-off floor" : "the tolerance");
    assert_true(fabs(r.Ry - c->W) < 1e-9 * c->W); /* the pins carry the whole weight */
    assert_true(r.info.force <= r.info.tol || r.info.floor_ratio <= 1.0);
    if (c->h == 0.0) assert_true(ex < 1e-12); /* level: the middle node stays mid-span */
  }
  double os[2] = {order(esag[0], esag[1]), order(esag[1], esag[2])};
  double oH[2] = {order(eH[0], eH[1]), order(eH[1], eH[2])};
  double oV[2] = {order(eV[0], eV[1]), order(eV[1], eV[2])};
  print_message("%s: observed orders middle node %.3f %.3f (fit %.3f), H %.3f %.3f, V %.3f %.3f\n", what,
                os[0], os[1], th_slope(h, esag, 3), oH[0], oH[1], oV[0], oV[1]);
  for (int k = 0; k < 2; k++) {
    assert_true(os[k] > 1.8 && os[k] < 2.2);
    assert_true(oH[k] > 1.8 && oH[k] < 2.2);
  }
  if (c->h != 0.0) /* level: V = W/2 by symmetry, its error is round-off */
    for (int k = 0; k < 2; k++) assert_true(oV[k] > 1.8 && oV[k] < 2.2);
  assert_true(esag[2] < 1e-4 && eH[2] < 1e-4);
}

/* Level supports 1 m apart, 1.1 m of cable weighing 1 N, EA = 20 N: a catenary that sags
 * about 0.2 m and stretches by about 3 %. */
static void catenary_level(void **st) {
  (void)st;
  th_irvine c = {1.0, 0.0, 1.1, 20.0, 1.0, 0, 0};
  assert_int_equal(th_irvine_solve(&c), 0);
  catenary_orders(&c, "level");
}

/* The far support 0.4 m higher: the middle node's drop, H and the near support's V. */
static void catenary_inclined(void **st) {
  (void)st;
  th_irvine c = {1.0, -0.4, 1.2, 50.0, 2.0, 0, 0};
  assert_int_equal(th_irvine_solve(&c), 0);
  catenary_orders(&c, "inclined");
}

/* ------------------------------------------------------------ stopping rule */

/* A stiff chain: 20 links of 1e7 N/m (EA = 4.9e5 N), 2 % shorter than the 1 m span, so
 * prestressed to 1e4 N, carrying 0.1 N; it starts straight, where only the weights are out of
 * balance.  Its free forces cannot get below ~1e-9 N in floating point (a rounding error of a
 * position, 1e-16 m, times the links' 1e7 N/m, summed), far above the tolerance of 1e-10 of the
 * 5 mN node weight: the solve stops at the round-off floor and succeeds, with the sag of
 * Irvine's taut cable.  (The rule it replaces, 1-norm of the free forces <= 1e-10 of the
 * weight, ran 1000 iterations and failed.) */
static void stiff_chain_stops_at_roundoff(void **st) {
  (void)st;
  const int N = 20;
  th_irvine c = {1.0, 0.0, 0.98, 1e7 * 0.98 / N, 0.1, 0, 0};
  assert_int_equal(th_irvine_solve(&c), 0);
  double xm, zm;
  th_irvine_point(&c, 0.5 * c.L0, &xm, &zm);
  chain_result r = solve_chain(N, &c, 0.0, 0.0, 0.0);
  double esag = fabs(-r.my - zm) / zm;
  print_message("stiff chain: rc %d, %d iterations, largest force %.3e N, tolerance %.3e N, "
                "floor %.3e N (%.3f of it), sag %.6e m (Irvine %.6e, rel err %.2e), H %.8g N "
                "(Irvine %.8g), reactions %.12g N of %g N\n",
                r.rc, r.info.iterations, r.info.force, r.info.tol, r.info.floor,
                r.info.floor_ratio, -r.my, zm, esag, r.H, c.H, r.Ry, c.W);
  assert_int_equal(r.rc, 0);
  assert_int_equal(r.info.roundoff, 1);
  assert_true(r.info.force > r.info.tol); /* the tolerance was out of reach */
  assert_true(r.info.floor_ratio <= 1.0);
  assert_true(r.info.iterations < 20);
  assert_true(esag < 1e-6);
  assert_true(fabs(r.H - c.H) < 1e-9 * c.H);
  assert_true(fabs(r.Ry - c.W) < 1e-6 * c.W);
}

/* A tolerance far below round-off still converges (at the floor), to the same state as the
 * default; a loose one stops earlier, at the tolerance, close to it. */
static void tolerance_strict_and_loose(void **st) {
  (void)st;
  th_irvine c = {1.0, 0.0, 1.1, 20.0, 1.0, 0, 0};
  assert_int_equal(th_irvine_solve(&c), 0);
  chain_result def = solve_chain(80, &c, 0.0, 0.0, 0.0);
  chain_result strict = solve_chain(80, &c, 0.0, 0.0, 1e-300);
  chain_result loose = solve_chain(80, &c, 0.0, 0.0, 1e-4);
  print_message("default: %d iterations, force %.2e N (tolerance %.2e N, floor ratio %.3f); "
                "1e-300: %d iterations, force %.2e N (floor ratio %.3f); 1e-4: %d iterations, "
                "force %.2e N (tolerance %.2e N); the sag differs from the default's by %.2e m "
                "(1e-300) and %.2e m (1e-4)\n",
                def.info.iterations, def.info.force, def.info.tol, def.info.floor_ratio,
                strict.info.iterations, strict.info.force, strict.info.floor_ratio,
                loose.info.iterations, loose.info.force, loose.info.tol,
                fabs(strict.my - def.my), fabs(loose.my - def.my));
  assert_int_equal(def.rc, 0);
  assert_int_equal(strict.rc, 0);
  assert_int_equal(strict.info.roundoff, 1);
  assert_true(strict.info.floor_ratio <= 1.0);
  assert_true(fabs(strict.my - def.my) < 1e-10 && fabs(strict.H - def.H) < 1e-10);
  assert_int_equal(loose.rc, 0);
  assert_int_equal(loose.info.roundoff, 0);
  assert_true(loose.info.force <= loose.info.tol);
  assert_true(loose.info.iterations < def.info.iterations);
  assert_true(fabs(loose.my - def.my) < 1e-5);
}

/* Loads below the floor from the start: links of 6e10 N/m prestressed to 2e6 N far from the
 * origin (x ~ 100 m, where a rounding error of a position is 1.4e-14 m), carrying 1e-4 N.
 * Every free force is below its floor at the straight start, yet the chain must sag by
 * 6e-12 m; the floor stops the solve only after a Newton step from a residual at the floor,
 * so the sag is found (a step damped by the initial shift found less than a thousandth). */
static void loads_below_floor(void **st) {
  (void)st;
  const int N = 640;
  th_irvine c = {1.0, 0.0, 0.98, 1e8, 1e-4, 0, 0};
  assert_int_equal(th_irvine_solve(&c), 0);
  double xm, zm;
  th_irvine_point(&c, 0.5 * c.L0, &xm, &zm);
  chain_result r = solve_chain(N, &c, 100.0, -50.0, 0.0);
  double esag = fabs(-r.my - zm) / zm;
  print_message("loads below the floor: rc %d, %d iterations, sag %.6e m (Irvine %.6e, rel "
                "err %.2e), reactions %.6e N of %g N\n", r.rc, r.info.iterations, -r.my, zm,
                esag, r.Ry, c.W);
  assert_int_equal(r.rc, 0);
  assert_int_equal(r.info.roundoff, 1);
  assert_true(esag < 1e-2);
}

/* Every link on the low-rank path (tendon_dense_max 0: the links' axial stiffness only in the
 * Woodbury update, the sparse part of S nearly singular as the shift shrinks): the solve still
 * stops at the floor, at the answer of the dense path. */
static void lowrank_chain_at_floor(void **st) {
  (void)st;
  th_irvine c = {1.0, 0.0, 0.98, 100.0, 1.0, 0, 0};
  assert_int_equal(th_irvine_solve(&c), 0);
  chain_result dense = solve_chain(320, &c, 0.0, 0.0, 1e-300);
  chain_dense_max = 0;
  chain_result lr = solve_chain(320, &c, 0.0, 0.0, 1e-300);
  chain_dense_max = SW_TENDON_DENSE_MAX;
  print_message("320 links, low rank: %d iterations, floor ratio %.3f; middle node %.3e m from "
                "the dense path's, H %.3e N from it\n", lr.info.iterations, lr.info.floor_ratio,
                fabs(lr.my - dense.my), fabs(lr.H - dense.H));
  assert_int_equal(dense.rc, 0);
  assert_int_equal(lr.rc, 0);
  assert_int_equal(lr.info.roundoff, 1);
  assert_true(fabs(lr.my - dense.my) < 1e-9 && fabs(lr.H - dense.H) < 1e-9 * c.H);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(irvine_solution),
      cmocka_unit_test(catenary_level),
      cmocka_unit_test(catenary_inclined),
      cmocka_unit_test(stiff_chain_stops_at_roundoff),
      cmocka_unit_test(tolerance_strict_and_loose),
      cmocka_unit_test(loads_below_floor),
      cmocka_unit_test(lowrank_chain_at_floor),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
