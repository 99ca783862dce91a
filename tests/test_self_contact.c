/* test_self_contact.c — self-contact, the term "mesh_contact" (models/mesh_contact.c,
 * docs/contact.md), on meshes read from OBJ files written into a temporary folder:
 *   - two triangles a fraction of d-hat apart, closest at a triangle's interior, an edge and a
 *     vertex, crossing edges and nearly parallel edges (the mollifier active), each with no
 *     thickness and with one: the energy equals the barrier summed over every point-triangle
 *     and edge-edge pair found by brute force (models/contact_geom.h), the gradient matches
 *     central differences of the energy, the Hessian of those exact pair energies matches
 *     central differences of the gradient, and every listed 12 x 12 block is the nearest PSD
 *     matrix (eigenvalues clamped at zero, LAPACK) of its pair's exact Hessian (which is never
 *     PSD itself);
 *   - a flap pinned along one edge swings down onto a sheet pinned at its border 2 cm below:
 *     with self-contact no point-triangle or edge-edge pair is ever within the thickness (brute
 *     force over all pairs after every step) and no triangles intersect; without it the flap
 *     ends through the sheet;
 *   - the scene errors name the file, line and column of the right node. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "contact.h"
#include "contact_geom.h"
#include "harness.h"
#include "scene.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

static char tmpdir[256]; /* the OBJ files and scene names live here */

static int make_tmpdir(void **st) {
  (void)st;
  const char *base = getenv("TMPDIR");
  snprintf(tmpdir, sizeof tmpdir, "%s/sinew_self_contact_XXXXXX", base && *base ? base : "/tmp");
  return mkdtemp(tmpdir) ? 0 : -1;
}

static int remove_tmpdir(void **st) {
  (void)st;
  th_remove_tree(tmpdir);
  return 0;
}

/* ------------------------------------------------------------------- meshes and scenes */

/* An OBJ of nv positions x (m) and nf triangles f (0-based) in tmpdir/name.  With uv (nv x 2,
 * m) every corner takes its vertex's (u,v); without, each face is laid flat on its own
 * (isometric: its rest shape is its shape in x). */
static void write_obj(const char *name, int nv, const double *x, int nf, const int *f,
                      const double *uv) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  FILE *o = fopen(path, "w");
  assert_non_null(o);
  for (int i = 0; i < nv; i++)
    fprintf(o, "v %.17g %.17g %.17g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  for (int i = 0; uv && i < nv; i++) fprintf(o, "vt %.17g %.17g\n", uv[2 * i], uv[2 * i + 1]);
  for (int t = 0; !uv && t < nf; t++) {
    const double *p0 = x + 3 * f[3 * t], *p1 = x + 3 * f[3 * t + 1], *p2 = x + 3 * f[3 * t + 2];
    double e1[3], e2[3], l1 = 0.0, along = 0.0, l2 = 0.0;
    for (int a = 0; a < 3; a++) e1[a] = p1[a] - p0[a], e2[a] = p2[a] - p0[a];
    for (int a = 0; a < 3; a++) l1 += e1[a] * e1[a], along += e1[a] * e2[a], l2 += e2[a] * e2[a];
    l1 = sqrt(l1), along /= l1;
    fprintf(o, "vt 0 0\nvt %.17g 0\nvt %.17g %.17g\n", l1, along, sqrt(l2 - along * along));
  }
  for (int t = 0; t < nf; t++) {
    int c[3];
    for (int k = 0; k < 3; k++) c[k] = uv ? f[3 * t + k] + 1 : 3 * t + k + 1;
    fprintf(o, "f %d/%d %d/%d %d/%d\n", f[3 * t] + 1, c[0], f[3 * t + 1] + 1, c[1],
            f[3 * t + 2] + 1, c[2]);
  }
  assert_int_equal(fclose(o), 0);
}

/* The scene text parsed as tmpdir/self.yaml (so a relative obj is in tmpdir); NULL with the
 * message in err. */
static sw_model *parse_in_tmp(const char *text, char *err, size_t errsz) {
  char name[512];
  snprintf(name, sizeof name, "%s/self.yaml", tmpdir);
  return sw_scene_parse(name, text, strlen(text), err, errsz);
}

static sw_model *parse_ok(const char *text) {
  char err[SW_ERRSZ];
  sw_model *m = parse_in_tmp(text, err, sizeof err);
  if (!m) print_error("%s\n", err);
  assert_non_null(m);
  return m;
}

/* The mesh's edges (each once, from its faces) into a new array; their count in *ne. */
static int *mesh_edges(const sw_model *m, int *ne) {
  int *e = malloc(sizeof(int) * 6 * (size_t)m->nf + 1), n = 0;
  assert_non_null(e);
  for (int t = 0; t < m->nf; t++)
    for (int k = 0; k < 3; k++) {
      int a = m->face[3 * t + k], b = m->face[3 * t + (k + 1) % 3], seen = 0;
      if (a > b) a ^= b, b ^= a, a ^= b;
      for (int j = 0; j < n && !seen; j++) seen = e[2 * j] == a && e[2 * j + 1] == b;
      if (!seen) e[2 * n] = a, e[2 * n + 1] = b, n++;
    }
  *ne = n;
  return e;
}

static int shares(const int *v, int n, int w) {
  for (int k = 0; k < n; k++)
    if (v[k] == w) return 1;
  return 0;
}

/* Every point-triangle pair (kind SW_MC_PT, v = point, triangle) and edge-edge pair (SW_MC_EE)
 * of m's primitives that share no vertex, in the order the term lists a pair's vertices:
 * fn(v, kind, arg) for each. */
static void each_pair(const sw_model *m, const int *edge, int ne,
                      void (*fn)(const int *v, int kind, void *arg), void *arg) {
  for (int t = 0; t < m->nf; t++)
    for (int i = 0; i < m->nv; i++) {
      int v[4] = {i, m->face[3 * t], m->face[3 * t + 1], m->face[3 * t + 2]};
      if (!shares(v + 1, 3, i)) fn(v, SW_MC_PT, arg);
    }
  for (int a = 0; a < ne; a++)
    for (int b = a + 1; b < ne; b++) {
      int v[4] = {edge[2 * a], edge[2 * a + 1], edge[2 * b], edge[2 * b + 1]};
      if (!shares(v, 2, v[2]) && !shares(v, 2, v[3])) fn(v, SW_MC_EE, arg);
    }
}

static void gather(const double *x, const int *v, double *p) {
  for (int k = 0; k < 4; k++) memcpy(p + 3 * k, x + 3 * v[k], 3 * sizeof(double));
}

/* The squared distance of pair (kind, v) at x (m^2), with its gradient and Hessian. */
static double pair_d2(int kind, const int *v, const double *x, double *g, double *H) {
  double p[12];
  gather(x, v, p);
  return kind == SW_MC_PT ? sw_d2_point_triangle(p, p + 3, p + 6, p + 9, g, H)
                          : sw_d2_edge_edge(p, p + 3, p + 6, p + 9, g, H);
}

/* The documented energy of one pair at x (J): kappa w m b(d^2 - xi^2; shat), w the mean mass
 * of its vertices, m the mollifier of edge-edge pairs (eps from the rest positions x0), b
 * IPC's barrier; its exact gradient g (12) and Hessian H (144) over its vertices and *mol the
 * mollifier.  -1 (and zeros) beyond the barrier's reach. */
static double ref_pair(const sw_model *m, int kind, const int *v, const double *x, double *g,
                       double *H, double *mol) {
  const sw_contact *c = &m->contact;
  double g2[12], H2[144], bg[12], bH[144], p[12], r[12], mg[12], mH[144];
  double s = pair_d2(kind, v, x, g2, H2) - c->thickness * c->thickness;
  double shat = (c->thickness + c->dhat) * (c->thickness + c->dhat) - c->thickness * c->thickness;
  memset(g, 0, 12 * sizeof(double));
  memset(H, 0, 144 * sizeof(double));
  *mol = 1.0;
  if (s >= shat) return -1.0;
  double w = 0.0;
  for (int k = 0; k < 4; k++) w += m->mass[v[k]] / 4.0;
  w *= c->kappa_mesh;
  double e = sw_barrier_of(12, s, g2, H2, shat, bg, bH);
  if (kind == SW_MC_EE) {
    gather(x, v, p);
    gather(m->x0, v, r);
    double eps = sw_ee_mollifier_eps(r, r + 3, r + 6, r + 9);
    *mol = sw_ee_mollifier(p, p + 3, p + 6, p + 9, eps, mg, mH);
    e = sw_product_derivs(12, *mol, mg, mH, e, bg, bH, g, H);
  } else {
    memcpy(g, bg, sizeof bg);
    memcpy(H, bH, sizeof bH);
  }
  for (int i = 0; i < 12; i++) g[i] *= w;
  for (int i = 0; i < 144; i++) H[i] *= w;
  return w * e;
}

/* ---------------------------------------------------------------- the term's derivatives */

/* The mesh_contact term of m at x: energy (J), gradient grad (nv x 3, N) when not NULL, and the
 * active pairs with their blocks listed in mc when hess. */
static double term_at(const sw_model *m, sw_mcontact *mc, const double *x, double *grad,
                      int hess) {
  int k = sw_term_find(m, "mesh_contact");
  assert_true(k >= 0);
  double dummy = 0.0, e = 0.0;
  if (grad) memset(grad, 0, sizeof(double) * 3 * (size_t)m->nv);
  sw_eval ev = {.x = x, .grad = grad, .hess = hess ? &dummy : NULL, .mc = mc};
  assert_int_equal(m->term[k].ops->eval(&m->term[k], m, &ev, &e), SW_OK);
  return e;
}

/* Smallest and largest |eigenvalue| of the symmetric 12 x 12 block B; with P not NULL, the
 * nearest positive semi-definite matrix to B (eigenvalues clamped at 0) into P. */
static double eig12(const double *B, double *amax, double *P) {
  int n = 12, lwork = 64 * 12, info = 0;
  double A[144], lam[12], work[64 * 12];
  memcpy(A, B, sizeof A);
  dsyev_(P ? "V" : "N", "U", &n, A, &n, lam, work, &lwork, &info);
  assert_int_equal(info, 0);
  *amax = fmax(fabs(lam[0]), fabs(lam[11]));
  for (int i = 0; P && i < 144; i++) {
    P[i] = 0.0;
    for (int k = 0; k < 12; k++) /* column k of A is eigenvector k (column-major) */
      P[i] += fmax(lam[k], 0.0) * A[12 * k + i / 12] * A[12 * k + i % 12];
  }
  return lam[0];
}

/* A += the 12 x 12 block B over the vertices v[0..3] (A: n x n over 3 coordinates a vertex). */
static void scatter(double *A, int n, const int *v, const double *B) {
  for (int i = 0; i < 12; i++)
    for (int j = 0; j < 12; j++)
      A[(3 * v[i / 3] + i % 3) * n + 3 * v[j / 3] + j % 3] += B[12 * i + j];
}

/* Sums of the brute-force pass over every pair (each_pair). */
typedef struct sums {
  const sw_model *m;
  const double *x;
  double energy, *H;   /* total and the exact Hessian (3nv x 3nv) of every pair */
  int active;          /* pairs within the barrier's reach */
  double min_mol;      /* the smallest mollifier of an active edge-edge pair */
} sums;

static void add_pair(const int *v, int kind, void *arg) {
  sums *s = arg;
  double g[12], H[144], mol;
  const int n = 3 * s->m->nv;
  double e = ref_pair(s->m, kind, v, s->x, g, H, &mol);
  if (e < 0.0) return;
  s->energy += e;
  s->active++;
  if (kind == SW_MC_EE) s->min_mol = fmin(s->min_mol, mol);
  scatter(s->H, n, v, H);
}

/* One configuration: vertices 0-2 the triangle A = (0,0,0) (0.1,0,0) (0,0.1,0), vertices 3-5
 * the triangle B; the named pair is moved (B rigidly, along its common normal) to the distance
 * dist and must have closest features `type`. */
typedef struct config {
  const char *label;
  double b[9];    /* B's vertices before it is moved, m */
  int kind, v[4]; /* the pair that sets the distance */
  int type;       /* sw_pt_type or sw_ee_type it must have */
  double angle;   /* > 0: B from parallel_edges at this angle (rad; b unused), mollified */
} config;

/* Move B along the pair's common normal until the pair is dist apart. */
static void place(double *x, const config *c, double dist) {
  for (int it = 0; it < 20; it++) {
    double g[12], d = sqrt(pair_d2(c->kind, c->v, x, g, NULL)), n[3] = {0, 0, 0};
    for (int k = 0; k < 4; k++) /* the gradient of d^2 over B's vertices is 2 d n */
      for (int a = 0; a < 3 && c->v[k] >= 3; a++) n[a] += g[3 * k + a] / (2.0 * d);
    for (int i = 3; i < 6; i++)
      for (int a = 0; a < 3; a++) x[3 * i + a] += (dist - d) * n[a];
  }
  double d = sqrt(pair_d2(c->kind, c->v, x, NULL, NULL));
  assert_true(fabs(d - dist) < 1e-15);
}

/* The nearly parallel pair: B's edge 3-4 above A's edge 1-2 (direction (-1, 1, 0)/sqrt 2),
 * along the common normal n = (1, 1, 1.5)/|.| (outward and up), turned by th about n. */
static void parallel_edges(double *b, double th) {
  const double s2 = sqrt(0.5), nl = sqrt(2.0 + 2.25);
  const double n[3] = {1 / nl, 1 / nl, 1.5 / nl}, dA[3] = {-s2, s2, 0};
  double nxd[3] = {n[1] * dA[2] - n[2] * dA[1], n[2] * dA[0] - n[0] * dA[2],
                   n[0] * dA[1] - n[1] * dA[0]};
  for (int a = 0; a < 3; a++) {
    double dir = cos(th) * dA[a] + sin(th) * nxd[a], mid = (a < 2 ? 0.05 : 0.0) + 1e-3 * n[a];
    b[a] = mid - 0.05 * dir;
    b[3 + a] = mid + 0.05 * dir;
    b[6 + a] = mid + (a < 2 ? 0.02 : 0.03);
  }
}

static const config configs[] = {
    {"point over the interior", {0.03, 0.04, 1e-3, 0.08, 0.05, 0.04, 0.04, 0.09, 0.03},
     SW_MC_PT, {3, 0, 1, 2}, SW_PT_PLANE, 0},
    {"point beside an edge", {0.04, -6e-4, 8e-4, 0.09, -0.01, 0.04, 0.04, -0.04, 0.03},
     SW_MC_PT, {3, 0, 1, 2}, SW_PT_E01, 0},
    {"point beside a vertex", {-5e-4, -6e-4, 6e-4, -0.04, -0.02, 0.03, -0.01, -0.05, 0.02},
     SW_MC_PT, {3, 0, 1, 2}, SW_PT_T0, 0},
    {"crossing edges", {0.03, 0.03, 0.003, 0.07, 0.07, -0.001, 0.02, 0.06, 0.04},
     SW_MC_EE, {1, 2, 3, 4}, SW_EE_LINES, 0},
    {"edges 0.01 rad apart", {0}, SW_MC_EE, {1, 2, 3, 4}, SW_EE_LINES, 0.01},
    {"edges 0.001 rad apart", {0}, SW_MC_EE, {1, 2, 3, 4}, SW_EE_LINES, 1e-3},
};

/* The term on configuration c with thickness xi, the pair 0.4 dhat beyond it: energy against
 * the brute-force sum, gradient against central differences of the energy, the exact Hessian
 * against central differences of the gradient, the listed blocks against the clamped exact
 * ones (PSD).  The largest relative errors go into err[0..3]. */
static void check_config(const config *c, double xi, double *err) {
  const double dhat = 1e-3, dist = xi + 0.4 * dhat;
  double x[18] = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0};
  memcpy(x + 9, c->b, sizeof c->b);
  if (c->angle > 0.0) parallel_edges(x + 9, c->angle);
  place(x, c, dist);
  double p[12];
  gather(x, c->v, p);
  int type = c->kind == SW_MC_PT ? (int)sw_point_triangle_type(p, p + 3, p + 6, p + 9)
                                 : (int)sw_edge_edge_type(p, p + 3, p + 6, p + 9);
  assert_int_equal(type, c->type);
  const int f[6] = {0, 1, 2, 3, 4, 5};
  write_obj("pair.obj", 6, x, 2, f, NULL);
  char text[512];
  snprintf(text, sizeof text, "mesh: {obj: pair.obj}\nmaterial: {density: 0.1}\n"
           "contact: {self: true, thickness: %.17g, distance: %g, self_stiffness: 1e4}\n", xi,
           dhat);
  sw_model *m = parse_ok(text);
  assert_true(m->contact.kappa_mesh == 1e4 && m->contact.thickness == xi);
  sw_mcontact *mc = sw_mcontact_new(m);
  assert_non_null(mc);
  const int n = 18;
  double g[18], gp[18], gm[18], Hfd[18 * 18], Hex[18 * 18] = {0}, Hsum[18 * 18] = {0};
  double e = term_at(m, mc, x, g, 1);
  /* the listed pairs and blocks, and the brute-force sums */
  const sw_mc_pair *pr;
  const double *blk;
  int np = sw_mcontact_pairs(mc, &pr, &blk), ne;
  int *edge = mesh_edges(m, &ne);
  sums s = {.m = m, .x = x, .H = Hex, .min_mol = 1.0};
  each_pair(m, edge, ne, add_pair, &s);
  free(edge);
  assert_int_equal(np, s.active); /* the broad phase missed none */
  assert_non_null(blk);
  assert_true(fabs(e - s.energy) <= 1e-12 * s.energy && e > 0.0);
  int found = 0;
  err[3] = 0.0;
  for (int k = 0; k < np; k++) {
    double gk[12], Hk[144], P[144], mol, amax, bmax = 0.0;
    found |= pr[k].kind == c->kind && !memcmp(pr[k].v, c->v, sizeof c->v);
    if (pr[k].kind == c->kind && !memcmp(pr[k].v, c->v, sizeof c->v))
      assert_true(fabs(pr[k].gap - 0.4 * dhat) < 1e-15);
    ref_pair(m, pr[k].kind, pr[k].v, x, gk, Hk, &mol);
    /* never PSD as it is: b' < 0 times the squared distance's curvature, positive along
     * directions that change the distance only to second order */
    assert_true(eig12(Hk, &amax, P) < -1e-6 * amax);
    for (int i = 0; i < 144; i++) bmax = fmax(bmax, fabs(blk[144 * k + i] - P[i]));
    err[3] = fmax(err[3], bmax / amax);
    assert_true(bmax <= 1e-9 * amax); /* the block is the clamped exact Hessian */
    assert_true(eig12(blk + 144 * k, &amax, NULL) >= -1e-9 * amax); /* PSD */
    scatter(Hsum, n, pr[k].v, blk + 144 * k);
  }
  assert_true(found);
  if (c->angle > 0.0) assert_true(s.min_mol < 0.5); /* the nearly parallel pair is mollified */
  /* central differences: h = 1e-8 m moves d by 2.5 % of the smallest gap at most */
  const double h = 1e-8;
  double gmax = 0.0, hmax = 0.0;
  err[0] = err[1] = 0.0;
  for (int i = 0; i < n; i++) gmax = fmax(gmax, fabs(g[i]));
  for (int i = 0; i < n * n; i++) hmax = fmax(hmax, fabs(Hex[i]));
  for (int i = 0; i < n; i++) {
    double xp[18];
    memcpy(xp, x, sizeof xp);
    xp[i] += h;
    double ep = term_at(m, mc, xp, gp, 0);
    xp[i] -= 2 * h;
    double em = term_at(m, mc, xp, gm, 0);
    err[0] = fmax(err[0], fabs((ep - em) / (2 * h) - g[i]) / gmax);
    for (int j = 0; j < n; j++) {
      Hfd[j * n + i] = (gp[j] - gm[j]) / (2 * h);
      err[1] = fmax(err[1], fabs(Hfd[j * n + i] - Hex[j * n + i]) / hmax);
    }
  }
  /* how far the listed blocks are from the exact Hessian: what the clamp took off */
  err[2] = 0.0;
  for (int i = 0; i < n * n; i++) err[2] = fmax(err[2], fabs(Hsum[i] - Hex[i]) / hmax);
  print_message("%-24s xi %.0e: %d pairs (%.3g J), mollifier %.3g; FD gradient %.1e, "
                "Hessian %.1e; clamp moved %.1e; block vs clamped exact %.1e\n", c->label, xi, np,
                e, s.min_mol, err[0], err[1], err[2], err[3]);
  assert_true(err[0] < 1e-8); /* measured: at most 4e-10 */
  assert_true(err[1] < 5e-6); /* at most 2.7e-7, on the mollified pairs */
  sw_mcontact_free(mc);
  sw_model_free(m);
}

static void derivatives(void **st) {
  (void)st;
  for (size_t k = 0; k < sizeof configs / sizeof *configs; k++)
    for (int t = 0; t < 2; t++) {
      double err[4];
      check_config(&configs[k], t ? 5e-4 : 0.0, err);
    }
}

/* ------------------------------------------------------------- adaptive stiffness */

/* The automatic stiffness's factor after one adaptation at a state whose only close pair is
 * configuration 0 (a point over a triangle's interior) `gap` beyond a thickness of zero. */
static double factor_after(double gap) {
  const double dhat = 1e-3;
  double x[18] = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0};
  memcpy(x + 9, configs[0].b, sizeof configs[0].b);
  place(x, &configs[0], gap);
  const int f[6] = {0, 1, 2, 3, 4, 5};
  write_obj("adapt.obj", 6, x, 2, f, NULL);
  char text[512];
  snprintf(text, sizeof text, "mesh: {obj: adapt.obj}\nmaterial: {density: 0.1}\n"
           "gravity: [0, 0, -9.81]\ncontact: {self: true, thickness: 0, distance: %g}\n", dhat);
  sw_model *m = parse_ok(text);
  assert_true(m->contact.kappa_mesh_auto);
  sw_data *d = sw_data_new(m);
  assert_non_null(d);
  assert_non_null(d->mc);
  memcpy(d->x, x, sizeof x);
  sw_mcontact_state(m, d);
  assert_true(fabs(d->self_min - gap) <= 1e-12 * dhat); /* that pair, and no closer one */
  sw_mcontact_adapt(m, d->mc);
  double s = sw_mcontact_kappa_scale(d->mc);
  for (int k = 0; k < 40; k++) sw_mcontact_adapt(m, d->mc);
  assert_true(sw_mcontact_kappa_scale(d->mc) <= SW_KAPPA_SCALE_MAX);
  sw_data_free(d);
  sw_model_free(m);
  return s;
}

/* The factor grows continuously with how far the smallest gap fell below g0 = SW_KAPPA_GAP
 * dhat (doubled from (1 - SW_KAPPA_BAND) g0 down): a gap a hair below g0, which round-off may put on
 * either side, changes the stiffness by a hair (it used to double it: on a real tank top's fit
 * one vertex landing at 0.99 g0 in one build and not in the other made the self-contact twice
 * as stiff for the rest of the fit, and its steps twice as costly). */
static void stiffness_continuous(void **st) {
  (void)st;
  const double g0 = SW_KAPPA_GAP * 1e-3;
  double above = factor_after(1.01 * g0), hair = factor_after((1.0 - 1e-6) * g0);
  double mid = factor_after((1.0 - 0.5 * SW_KAPPA_BAND) * g0), deep = factor_after(0.3 * g0);
  print_message("stiffness factor after one step at a gap of 1.01 g0: %g; (1 - 1e-6) g0: %.9g; "
                "(1 - %g / 2) g0: %.9g; 0.3 g0: %g\n", above, hair, SW_KAPPA_BAND, mid, deep);
  assert_true(above == 1.0);
  assert_true(hair > 1.0 && hair < 1.0 + 1e-4); /* 2^(1e-5) = 1 + 6.9e-6 */
  assert_true(fabs(mid - sqrt(2.0)) < 1e-9);
  assert_true(deep == 2.0); /* as before: a gap well below g0 doubles it */
  assert_true(factor_after((1.0 - SW_KAPPA_BAND) * g0 * 0.999) == 2.0 && factor_after(g0) == 1.0);
}

/* ------------------------------------------------------------------ a flap on a sheet */

/* Two 9 x 9 sheets in one OBJ: the lower one 12 cm square at z = 0 (vertices 0-80), the flap
 * 10 cm square 2 cm above it (81-161), its row y = 1 cm pinned; (u,v) = (x, y). */
static void write_sheets(void) {
  enum { N = 9, NV = 2 * N * N, NF = 2 * 2 * (N - 1) * (N - 1) };
  double x[3 * NV], uv[2 * NV];
  int f[3 * NF], nf = 0;
  for (int s = 0; s < 2; s++)
    for (int j = 0; j < N; j++)
      for (int i = 0; i < N; i++) {
        int k = s * N * N + j * N + i;
        double size = s ? 0.1 : 0.12, o = s ? 0.01 : 0.0;
        uv[2 * k] = x[3 * k] = o + size * i / (N - 1);
        uv[2 * k + 1] = x[3 * k + 1] = o + size * j / (N - 1);
        x[3 * k + 2] = s ? 0.02 : 0.0;
        if (i + 1 < N && j + 1 < N) {
          int q[6] = {k, k + 1, k + N + 1, k, k + N + 1, k + N};
          memcpy(f + 3 * nf, q, sizeof q);
          nf += 2;
        }
      }
  write_obj("sheets.obj", NV, x, nf, f, uv);
}

static const char flap_scene[] =
    "mesh: {obj: sheets.obj}\n"
    "material: {density: 0.1, membrane: {model: bw98, k_u: 1000, k_v: 1000, k_shear: 50},\n"
    "           bending: {model: quadratic, stiffness: 1e-6}}\n"
    "gravity: [0, 0, -9.81]\n"
    "pins: [{select: {box: [[-1, -1, -1e-3], [1e-3, 1, 1e-3]]}},\n"
    "       {select: {box: [[0.119, -1, -1e-3], [1, 1, 1e-3]]}},\n"
    "       {select: {box: [[-1, -1, -1e-3], [1, 1e-3, 1e-3]]}},\n"
    "       {select: {box: [[-1, 0.119, -1e-3], [1, 1, 1e-3]]}},\n"
    "       {select: {box: [[-1, 0.0099, 0.0199], [1, 0.0101, 0.0201]]}}]\n"
    "damping: %s\n"
    "integrator: {method: backward-euler, dt: 0.01}\n"
    "duration: 0.4\n"
    "%s";

typedef struct closest {
  const double *x;
  double d2;  /* m^2: the smallest squared distance */
} closest;

static void min_pair(const int *v, int kind, void *arg) {
  closest *c = arg;
  c->d2 = fmin(c->d2, pair_d2(kind, v, c->x, NULL, NULL));
}

/* The flap run to the end with or without self-contact: the smallest distance of any pair of
 * primitives sharing no vertex at any step (brute force, m), the largest count of intersecting
 * triangle pairs at any step and at the end, and the pairs in contact at the end. */
static void flap_run(int self, const char *damping, double *dmin, long *cross_max,
                     long *cross_end, int *contacts) {
  char text[2048];
  snprintf(text, sizeof text, flap_scene, damping,
           self ? "contact: {self: true, thickness: 1e-3}\n" : "");
  sw_model *m = parse_ok(text);
  char err[SW_ERRSZ];
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  int ne, *edge = mesh_edges(m, &ne);
  *dmin = INFINITY;
  *cross_max = 0;
  while (d->t < m->opt.duration - 1e-9) {
    int rc = sw_sim_step(s, err, sizeof err);
    if (rc) print_error("%s\n", err);
    assert_int_equal(rc, 0);
    closest c = {.x = d->x, .d2 = INFINITY};
    each_pair(m, edge, ne, min_pair, &c);
    *dmin = fmin(*dmin, sqrt(c.d2));
    *cross_end = sw_mesh_self_intersections(m->nv, d->x, m->nf, m->face);
    *cross_max = *cross_end > *cross_max ? *cross_end : *cross_max;
  }
  print_message("flap, self-contact %s: %ld steps, %ld Newton iterations, %ld pattern growths, "
                "smallest distance %.3g m, intersecting pairs at most %ld, at the end %ld; "
                "%d pairs in contact at the end\n", self ? "on" : "off", d->nstep, d->nnewton,
                d->npattern, *dmin, *cross_max, *cross_end, d->self_count);
  *contacts = d->self_count;
  free(edge);
  sw_sim_free(s);
  sw_model_free(m);
}

/* With self-contact the flap lands on the sheet and stays beyond the thickness; without, it
 * swings through the sheet. */
static void flap_on_sheet(void **st) {
  (void)st;
  write_sheets();
  double dmin;
  long cmax, cend;
  int contacts;
  flap_run(1, "{mass: 1.0}", &dmin, &cmax, &cend, &contacts);
  assert_true(dmin > 1e-3);          /* the thickness */
  assert_true(dmin < 1e-3 + 1e-3);   /* it did land: within the barrier's reach */
  assert_true(contacts > 100);       /* and lies on the sheet at the end */
  assert_int_equal(cmax, 0);
  flap_run(0, "{mass: 1.0}", &dmin, &cmax, &cend, &contacts);
  assert_true(cend > 0);
  /* stiffness damping: its matrix is taken at the step's admissible start guess (at the
   * predictor, which swings through the sheet, the barriers have no Hessian) */
  flap_run(1, "{mass: 1.0, stiffness: 0.01}", &dmin, &cmax, &cend, &contacts);
  assert_true(dmin > 1e-3);
  assert_int_equal(cmax, 0);
}

/* The flap run with the candidate listings renewed for the vertices that left their boxes
 * (the default) and with every listing made anew: the same trajectory to round-off, the
 * distance of every pair beyond the thickness in both, and renewals taken (so that path is
 * what the first run tested). */
static void renewed_listings(void **st) {
  (void)st;
  write_sheets();
  char text[2048];
  snprintf(text, sizeof text, flap_scene, "{mass: 1.0}", "contact: {self: true, thickness: 1e-3}\n");
  sw_model *m[2];
  sw_sim *s[2];
  char err[SW_ERRSZ];
  for (int k = 0; k < 2; k++) {
    m[k] = parse_ok(text);
    s[k] = sw_sim_new(m[k], 0, err, sizeof err);
    assert_non_null(s[k]);
    sw_mcontact_set_renew(sw_sim_data(s[k])->mc, k == 0);
  }
  int ne, *edge = mesh_edges(m[0], &ne);
  double dmin = INFINITY, dx = 0.0;
  const sw_data *d0 = sw_sim_data(s[0]), *d1 = sw_sim_data(s[1]);
  while (d0->t < m[0]->opt.duration - 1e-9) {
    for (int k = 0; k < 2; k++) {
      int rc = sw_sim_step(s[k], err, sizeof err);
      if (rc) print_error("%s\n", err);
      assert_int_equal(rc, 0);
      closest c = {.x = sw_sim_data(s[k])->x, .d2 = INFINITY};
      each_pair(m[k], edge, ne, min_pair, &c);
      dmin = fmin(dmin, sqrt(c.d2));
    }
    for (int i = 0; i < 3 * m[0]->nv; i++) dx = fmax(dx, fabs(d0->x[i] - d1->x[i]));
  }
  long made[2], renewed[2];
  for (int k = 0; k < 2; k++) sw_mcontact_listings(sw_sim_data(s[k])->mc, &made[k], &renewed[k]);
  print_message("flap, listings renewed: %ld made, %ld renewed; made anew: %ld; largest "
                "difference of the positions %.3g m, smallest distance %.6g m\n", made[0],
                renewed[0], made[1], dx, dmin);
  assert_true(renewed[0] > 0 && renewed[1] == 0);
  assert_true(dx < 1e-9); /* m: round-off (the pairs are visited in another order) */
  assert_true(dmin > 1e-3); /* the thickness */
  free(edge);
  for (int k = 0; k < 2; k++) sw_sim_free(s[k]), sw_model_free(m[k]);
}

/* ------------------------------------------------------------------------ scene errors */

static void scene_errors(void **st) {
  (void)st;
  static const char grid[] = "mesh: {grid: {size: [0.1, 0.1], vertices: [3, 3]}}\n"
                             "material: {density: 0.1}\n";
  static const char plane[] = "obstacles: [{shape: plane, point: [0, 0, -1], normal: [0, 0, 1]}]\n";
  static const char obj[] = "mesh: {obj: two.obj}\nmaterial: {density: 0.1}\n";
  const double tri[9] = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0};
  const double crossing[9] = {0.03, 0.03, -0.01, 0.05, 0.03, 0.01, 0.03, 0.05, 0.01};
  const double close[9] = {0.01, 0.01, 5e-4, 0.05, 0.01, 5e-4, 0.01, 0.05, 5e-4};
  const struct {
    const char *head, *tail;
    const double *b; /* the second triangle of two.obj (the first: tri), or NULL */
    const char *want, *want2; /* in the message, both (want2 NULL: only want) */
  } bad[] = {
      {"dimension: 2\n", "contact: {self: true}\n", NULL,
       "self.yaml:4:17: contact self is true in a 2D scene", NULL},
      {plane, "contact: {self: false, thickness: 1e-3}\n", NULL,
       "self.yaml:4:35: contact thickness is given without self: true", NULL},
      {plane, "contact: {self_stiffness: 10}\n", NULL,
       "self.yaml:4:27: contact self_stiffness is given without self: true", NULL},
      {"", "contact: {distance: 1e-3}\n", NULL,
       "self.yaml:3:10: contact is given but the scene has no obstacles and no self-contact", NULL},
      {"", "contact: {self: false}\n", NULL,
       "self.yaml:3:10: contact is given but the scene has no obstacles and no self-contact", NULL},
      {"", "contact: {self: true}\n", crossing,
       "self.yaml:3:10: contact: self: the mesh intersects itself (1 pairs of triangles)", NULL},
      {"", "contact:\n  self: true\n  thickness: 1e-3\n", close,
       "self.yaml:4:3: contact: self: vertices ", /* whichever of the 3 pairs comes first */
       "(a point and a triangle) start 0.0005 m apart, within the thickness 0.001 m"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    char text[1024], err[SW_ERRSZ];
    if (bad[k].b) {
      double x[18];
      const int f[6] = {0, 1, 2, 3, 4, 5};
      memcpy(x, tri, sizeof tri);
      memcpy(x + 9, bad[k].b, sizeof tri);
      write_obj("two.obj", 6, x, 2, f, NULL);
    }
    snprintf(text, sizeof text, "%s%s%s", bad[k].b ? obj : grid, bad[k].head, bad[k].tail);
    sw_model *m = parse_in_tmp(text, err, sizeof err);
    int ok = !m && strstr(err, bad[k].want) && (!bad[k].want2 || strstr(err, bad[k].want2));
    if (!ok) print_error("case %zu: %s\n", k, m ? "loaded" : err);
    assert_null(m);
    assert_true(ok);
  }
  /* the same triangles 2 mm apart load, with the term */
  double x[18];
  const int f[6] = {0, 1, 2, 3, 4, 5};
  memcpy(x, tri, sizeof tri);
  memcpy(x + 9, close, sizeof tri);
  for (int i = 3; i < 6; i++) x[3 * i + 2] = 2e-3;
  write_obj("two.obj", 6, x, 2, f, NULL);
  char text[256];
  snprintf(text, sizeof text, "%scontact: {self: true, thickness: 1e-3}\n", obj);
  sw_model *m = parse_ok(text);
  assert_true(sw_term_find(m, "mesh_contact") >= 0);
  sw_model_free(m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(derivatives),
      cmocka_unit_test(stiffness_continuous),
      cmocka_unit_test(flap_on_sheet),
      cmocka_unit_test(renewed_listings),
      cmocka_unit_test(scene_errors),
  };
  return cmocka_run_group_tests(tests, make_tmpdir, remove_tmpdir);
}
