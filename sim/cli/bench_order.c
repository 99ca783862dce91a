/* bench_order.c — the observed order of convergence of each method of a work-precision bench
 * (docs/benchmarks.md, "Observed order"): orders.csv and the printed table.
 *
 * Per method, its ok runs sorted by setting h (dt, or rtol for an adaptive method) with their
 * position error e (pos_err_max).  Errors within BENCH_ORDER_FLOOR x the reference's own
 * agreement are not resolved and left out.  Between neighbours, the local slope
 * s_k = log(e_k+1 / e_k) / log(h_k+1 / h_k).  The converged range is the longest run of
 * neighbouring points whose local slopes are all above BENCH_ORDER_MIN_SLOPE and differ by at
 * most BENCH_ORDER_SPREAD (ties: the finer range); the observed order is the least-squares
 * slope of log e over log h on it (as DifferentialEquations.jl's test_convergence fits it).
 * A warning names every pair of neighbours whose error does not fall with h (for a fixed-step
 * method run at the scene's Newton tolerance, with the hint to tighten it). */
#include "bench.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One method's points; the caller fills h and e (NaN for a run that is not ok). */
typedef struct order_fit {
  double order;                /* NaN: no converged range */
  int lo, hi;                  /* indices of the range's ends into the sorted points */
  int npts;                    /* resolved ok points */
  int nrise;                   /* neighbour pairs whose error does not fall with h */
} order_fit;

static int by_h(const void *a, const void *b) {
  const double *x = a, *y = b;
  return (x[0] > y[0]) - (x[0] < y[0]);
}

/* Least-squares slope of log e over log h, points lo..hi of p (pairs h, e). */
static double ls_slope(const double *p, int lo, int hi) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = hi - lo + 1;
  for (int k = lo; k <= hi; k++) {
    double x = log(p[2 * k]), y = log(p[2 * k + 1]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/* p: n pairs (h, e) sorted by h, all resolved.  The converged range and its slope. */
static void fit_range(const double *p, int n, order_fit *f) {
  f->order = NAN, f->lo = f->hi = -1, f->nrise = 0;
  for (int k = 0; k + 1 < n; k++) f->nrise += !(p[2 * k + 3] > p[2 * k + 1]);
  int best = 0;
  for (int a = 0; a + 1 < n; a++) {
    double smin = INFINITY, smax = -INFINITY;
    for (int b = a + 1; b < n; b++) {
      double s = log(p[2 * b + 1] / p[2 * b - 1]) / log(p[2 * b] / p[2 * b - 2]);
      smin = fmin(smin, s), smax = fmax(smax, s);
      if (!(smin > BENCH_ORDER_MIN_SLOPE) || smax - smin > BENCH_ORDER_SPREAD) break;
      if (b - a > best) best = b - a, f->lo = a, f->hi = b; /* strictly longer: finer wins */
    }
  }
  if (best) f->order = ls_slope(p, f->lo, f->hi);
}

/* The ok, resolved points of method (rows of one method and kind), sorted: into p. */
static int gather(const bench_point *pt, int npt, const char *method, double floor_e,
                  double *p) {
  int n = 0;
  for (int k = 0; k < npt; k++)
    if (!strcmp(pt[k].method, method) && pt[k].ok && pt[k].e > floor_e && isfinite(pt[k].e) &&
        pt[k].h > 0)
      p[2 * n] = pt[k].h, p[2 * n + 1] = pt[k].e, n++;
  qsort(p, (size_t)n, 2 * sizeof *p, by_h);
  return n;
}

static void warn_rises(const char *method, const char *what, const double *p, int n) {
  for (int k = 0; k + 1 < n; k++)
    if (!(p[2 * k + 3] > p[2 * k + 1]))
      printf("  warning: %s: the error does not fall with %s between %s %.4g and %.4g "
             "(%.3g at %.4g, %.3g at %.4g)\n", method, what, what, p[2 * k], p[2 * k + 2],
             p[2 * k + 1], p[2 * k], p[2 * k + 3], p[2 * k + 2]);
}

/* orders.csv and the table, from the points of every run (rep 1) of a work-precision bench;
 * floor_e: the reference's agreement (NaN: none).  0, or -1 when the file cannot be written. */
int bench_orders(const bench_cfg *c, const bench_point *pt, int npt, double floor_e) {
  char path[SW_PATHSZ + 64], tmp[SW_PATHSZ + 96];
  snprintf(path, sizeof path, "%s/orders.csv", c->dir);
  FILE *f = bench_create(path, tmp, sizeof tmp);
  double *p = malloc((size_t)(npt + 1) * 2 * sizeof *p);
  if (!f || !p) return free(p), f ? fclose(f) : 0, -1;
  fprintf(f, "method,setting,order,range_lo,range_hi,range_points,points,measure\n");
  double fl = isfinite(floor_e) ? BENCH_ORDER_FLOOR * floor_e : 0.0;
  printf("observed order (least-squares slope of log pos_err_max over log dt or rtol, on the "
         "converged range):\n");
  for (int k = 0; k < npt; k++) {
    int first = 1;
    for (int i = 0; i < k; i++) first &= strcmp(pt[i].method, pt[k].method) != 0;
    if (!first) continue;
    const char *what = pt[k].adaptive ? "rtol" : "dt";
    int n = gather(pt, npt, pt[k].method, fl, p);
    order_fit o;
    fit_range(p, n, &o);
    fprintf(f, "%s,%s", pt[k].method, what);
    if (isfinite(o.order))
      fprintf(f, ",%.4g,%.6g,%.6g,%d", o.order, p[2 * o.lo], p[2 * o.hi], o.hi - o.lo + 1);
    else fprintf(f, ",,,,0");
    fprintf(f, ",%d,pos_err_max\n", n);
    if (isfinite(o.order))
      printf("  %-18s %5.2f   over %s %.4g .. %.4g (%d of %d resolved ok runs)\n",
             pt[k].method, o.order, what, p[2 * o.lo], p[2 * o.hi], o.hi - o.lo + 1, n);
    else
      printf("  %-18s   -     no converged range (%d resolved ok runs)\n", pt[k].method, n);
    if (!isfinite(o.order) && n >= 2)
      printf("  warning: %s: the errors do not fall with %s at a steady rate: no converged "
             "range (the %s are too coarse to be asymptotic, or the errors are the reference's)"
             "\n", pt[k].method, what, pt[k].adaptive ? "tolerances" : "steps");
    warn_rises(pt[k].method, what, p, n);
    if (o.nrise && !pt[k].adaptive && !(c->newton_tol > 0))
      printf("  (its runs stop Newton at the scene's tolerance, whose error can exceed a fine "
             "step's: --newton-tol %g measures the method alone)\n", BENCH_ORDER_NEWTON_TOL);
  }
  free(p);
  return bench_commit(f, tmp);
}
