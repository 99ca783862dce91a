/* test_psd.c — the eigenvalue filters of the Hessian (sinew.h, SW_FILTER_CLAMP and
 * SW_FILTER_ABS) on every term that has a Hessian, with every model, in 2D and 3D:
 *  - every filtered block is positive semi-definite: its smallest eigenvalue (LAPACK dsyev) is
 *    at least -1e-10 times its largest |eigenvalue|, at random deformed states — stretched,
 *    compressed, sheared, collapsed onto a line (parallel warp and weft), with nearly
 *    coincident vertices, inverted, and tangled;
 *  - the absolute filter is what it says: |H| = 2 H+ - H (|lambda| = 2 max(lambda, 0) - lambda)
 *    block by block, where H+ is the clamped block and H the exact one;
 *  - exact values: a spring compressed to half its rest length has the clamped block k n n^T
 *    and the absolute one k I;
 *  - a hinge next to a collapsed face (a drawstring gathering a hem can crush one) does not put
 *    an unbounded stiffness into Newton's system: S = a M + H (clamped) is still factorised;
 *  - the small eigensolver behind every filter (models/eigen.c) against LAPACK from 1 x 1 to
 *    18 x 18, its positive-definiteness test, and the translation-free reduction round trip. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "harness.h"
#include "scene_fabric.h"
#include "solver.h"
#include "terms.h"

extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);

enum { NX = 4, NY = 3 };
static const double SX = 0.3, SY = 0.2; /* grid size, m */
#define NKIND 8
static const char *const KIND[NKIND] = {"stretched", "compressed", "crushed", "sheared",
                                        "collapsed", "coincident", "inverted", "tangled"};

/* ------------------------------------------------------------------ models */

static sw_material base_mat(void) {
  sw_material mt = {.density = 0.2, .b_u = 1.0, .b_v = 1.0, .tx_k_u = -1.0, .tx_k_v = -1.0};
  return mt;
}

static sw_model *membrane_model_k(int dim, int membrane, double k_stretch, double k_shear) {
  sw_material mt = base_mat();
  mt.membrane = membrane;
  mt.k_u = k_stretch, mt.k_v = 0.7 * k_stretch, mt.k_shear = k_shear; /* bw98, N/m */
  mt.b_u = 1.1, mt.b_v = 0.95;                       /* rest stretch: not the layout's */
  mt.e_u = 800.0, mt.e_v = 500.0, mt.nu_uv = 0.3, mt.g_uv = 60.0; /* stvk, N/m */
  mt.k_corot = 400.0;                                              /* corotated, N/m */
  mt.ks_stretch = 300.0, mt.ks_shear = 40.0, mt.ks_bend = 5.0;     /* springs, N/m */
  return th_grid_model_mat(dim, NX, NY, SX, SY, &mt);
}

static sw_model *membrane_model(int dim, int membrane) {
  return membrane_model_k(dim, membrane, 400.0, 35.0);
}

static sw_model *bending_model(int dim, int bending) {
  sw_material mt = base_mat();
  mt.bending = bending;
  mt.k_bend = 2e-3; /* N m */
  mt.bend_rest = SW_BEND_REST_FLAT;
  return th_grid_model_mat(dim, NX, NY, SX, SY, &mt);
}

/* The measured denim with its curvature-dependent bending (models/dde_bending.c). */
static sw_model *dde_bending_model(int dim) {
  char err[SW_ERRSZ];
  const sc_fabric_preset *p = sc_fabric_preset_find("11oz-black-denim");
  sw_material mt = base_mat();
  assert_non_null(p);
  if (sc_dde_parse(p->file, p->json, strlen(p->json), &mt.dde, err, sizeof err))
    fail_msg("%s", err);
  double kb[3];
  sc_dde_strips(&mt.dde, kb);
  mt.bending = SW_BENDING_DDE, mt.bend_rest = SW_BEND_REST_FLAT;
  mt.k_bend_u = kb[0], mt.k_bend_v = kb[1], mt.k_bend_bias = kb[2], mt.k_bend = kb[0];
  mt.bias = 0.4; /* rad */
  return th_grid_model_mat(dim, NX, NY, SX, SY, &mt);
}

/* One tendon zigzagging through every vertex of the grid: a spring far shorter than its rest
 * length (always compressed: E' < 0) or a cable far longer (always taut); dense_max 32 keeps it
 * one dense block, 2 splits it into segment blocks and a low-rank vector. */
static sw_model *tendon_model(int dim, int law, int dense_max) {
  sw_model *m = th_grid_start(dim, NX, NY, SX, SY, 0.1, 0.0, 0.0, NULL, 0);
  assert_non_null(m);
  int way[NX * NY], n = 0;
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) way[n++] = j * NX + (j % 2 ? NX - 1 - i : i);
  th_add_tendon(m, way, n, law, 300.0, law == SW_LAW_SPRING ? 10.0 : 1e-3, 0.0);
  m->opt.tendon_dense_max = dense_max;
  return th_finish(m);
}

typedef struct config {
  const char *label, *term;
  int dim;
  sw_model *m;
  int acts; /* the filters change the Hessian at some of the states (not: PSD already) */
} config;

static int term_index(const sw_model *m, const char *name) {
  for (int k = 0; k < m->nterm; k++)
    if (!strcmp(m->term[k].name, name)) return k;
  fail_msg("no term %s", name);
  return -1;
}

/* --------------------------------------------------------------- states */

/* A random rotation (3D, about a random axis) or rotation in the plane (2D) into R. */
static void random_rotation(int dim, unsigned long *rs, double R[9]) {
  double th = 3.0 * th_rand(rs), c = cos(th), s = sin(th);
  double a[3] = {0.0, 0.0, 1.0};
  if (dim == 3) {
    for (int i = 0; i < 3; i++) a[i] = th_rand(rs);
    double l = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) + 1e-300;
    for (int i = 0; i < 3; i++) a[i] /= l;
  }
  const double K[9] = {0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double kk = 0.0;
      for (int q = 0; q < 3; q++) kk += K[i * 3 + q] * K[q * 3 + j];
      R[i * 3 + j] = (i == j) + s * K[i * 3 + j] + (1.0 - c) * kk;
    }
}

/* 10^u with u uniform in [lo, hi]. */
static double log_uniform(double lo, double hi, unsigned long *rs) {
  return pow(10.0, lo + (hi - lo) * 0.5 * (th_rand(rs) + 1.0));
}

/* A deformed state of kind `kind` (KIND[]) from the rest grid, rotated and moved at random;
 * SX is the length scale. */
static void deform(const sw_model *m, int kind, unsigned long *rs, double *x) {
  const int d = m->dim, nv = m->nv;
  double A[4] = {1.0, 0.0, 0.0, 1.0}, noise = 0.0; /* in-plane affine map, noise (m) */
  switch (kind) {
  case 0: A[0] = A[3] = 1.3, noise = 0.1 * SX; break;
  case 1: A[0] = A[3] = 0.3, noise = 0.07 * SX; break;
  case 2: A[0] = A[3] = 0.05, noise = 0.007 * SX; break;
  case 3: /* strong shear and anisotropic stretch */
    A[0] = 1.0 + 0.5 * th_rand(rs), A[1] = 3.0 * th_rand(rs), A[2] = 0.5 * th_rand(rs);
    A[3] = 1.0 + 0.5 * th_rand(rs), noise = 1e-3 * SX;
    break;
  case 4: { /* everything onto a line, then a tiny spread: warp and weft nearly parallel */
    double c = th_rand(rs), s = th_rand(rs);
    A[0] = c, A[1] = s, A[2] = 0.7 * c, A[3] = 0.7 * s;
    noise = log_uniform(-12.0, -3.0, rs) * SX;
    break;
  }
  case 5: noise = 0.05 * SX; break; /* then nearly coincident vertices, below */
  case 6: A[3] = -(0.5 + 0.5 * fabs(th_rand(rs))), A[1] = 0.3 * th_rand(rs), noise = 0.02 * SX;
    break; /* mirrored: every triangle inverted in the plane */
  default: A[0] = A[1] = A[2] = A[3] = 0.0, noise = SX; break; /* tangled: random positions */
  }
  for (int i = 0; i < nv; i++) {
    double u = m->x0[i * d], v = m->x0[i * d + 1], p[3];
    p[0] = A[0] * u + A[1] * v + noise * th_rand(rs);
    p[1] = A[2] * u + A[3] * v + noise * th_rand(rs);
    p[2] = d == 3 ? noise * th_rand(rs) : 0.0;
    for (int a = 0; a < d; a++) x[i * d + a] = p[a];
  }
  if (kind == 5) /* about a third of the vertices next to another one, 1e-4 .. 1e-12 SX away */
    for (int i = 1; i < nv; i++) {
      if (th_rand(rs) < 0.33) continue;
      int j = (int)((double)i * 0.5 * (th_rand(rs) + 1.0)) % i;
      double r = log_uniform(-12.0, -4.0, rs) * SX;
      for (int a = 0; a < d; a++) x[i * d + a] = x[j * d + a] + r * th_rand(rs);
    }
  double R[9], t[3] = {th_rand(rs), th_rand(rs), th_rand(rs)};
  random_rotation(d, rs, R);
  for (int i = 0; i < nv; i++) {
    double p[3] = {0.0, 0.0, 0.0}, q[3];
    for (int a = 0; a < d; a++) p[a] = x[i * d + a];
    for (int a = 0; a < 3; a++) q[a] = t[a] + R[a * 3] * p[0] + R[a * 3 + 1] * p[1] + R[a * 3 + 2] * p[2];
    for (int a = 0; a < d; a++) x[i * d + a] = q[a];
  }
}

/* ------------------------------------------------------------ evaluation */

/* The Hessian blocks (and low-rank vectors) of term k at x with filter `mode`. */
static void term_hessian(const sw_model *m, int k, const double *x, int mode, double *blk,
                         double *lr) {
  const sw_term *t = &m->term[k];
  memset(blk, 0, sizeof(double) * (size_t)t->hptr[t->nstencil]);
  if (t->nlowrank) memset(lr, 0, sizeof(double) * (size_t)t->lptr[t->nlowrank] * (size_t)m->dim);
  sw_eval ev = {.t = 0.0, .x = x, .hess = blk, .lowrank = lr, .project = mode};
  double e = 0.0;
  assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
}

/* Smallest eigenvalue of the symmetric w x w matrix B (row-major, full, or a term's block
 * stored as its upper triangle when packed), and its largest |eigenvalue| in *amax. */
static double eigenvalue_range(const double *B, int w, int packed, double *amax) {
  int lwork = 64 * w, info = 0;
  double *A = malloc(sizeof(double) * (size_t)(w * w)), *lam = malloc(sizeof(double) * (size_t)w);
  double *work = malloc(sizeof(double) * (size_t)lwork);
  assert_non_null(A), assert_non_null(lam), assert_non_null(work);
  for (int i = 0; i < w; i++)
    for (int j = 0; j < w; j++) A[i * w + j] = packed ? sw_hess_get(B, i, j, w) : B[i * w + j];
  dsyev_("N", "U", &w, A, &w, lam, work, &lwork, &info);
  assert_int_equal(info, 0);
  double lmin = lam[0];
  *amax = fmax(fabs(lam[0]), fabs(lam[w - 1]));
  free(A), free(lam), free(work);
  return lmin;
}
static double min_eigenvalue(const double *B, int w, double *amax) {
  return eigenvalue_range(B, w, 0, amax);
}

static size_t lowrank_size(const sw_model *m, const sw_term *t) {
  return (size_t)(t->nlowrank ? t->lptr[t->nlowrank] : 0) * (size_t)m->dim + 1;
}

/* ------------------------------------------------------------ the checks */

enum { REPS = 40 }; /* states of each kind */

/* Every block of every filter, at REPS states of each kind, is PSD; the low-rank vectors (their
 * part u u^T is PSD by construction) are finite. */
static void check_psd(const config *c, unsigned long seed) {
  const sw_model *m = c->m;
  const int k = term_index(m, c->term);
  const sw_term *t = &m->term[k];
  double *x = calloc((size_t)m->nv * (size_t)m->dim, sizeof(double));
  double *blk = calloc((size_t)t->hptr[t->nstencil] + 1, sizeof(double));
  double *lr = calloc(lowrank_size(m, t), sizeof(double));
  assert_non_null(x), assert_non_null(blk), assert_non_null(lr);
  unsigned long rs = seed;
  int failures = 0;
  for (int kind = 0; kind < NKIND; kind++)
    for (int rep = 0; rep < REPS; rep++) {
      deform(m, kind, &rs, x);
      for (int mode = SW_FILTER_CLAMP; mode <= SW_FILTER_ABS; mode++) {
        term_hessian(m, k, x, mode, blk, lr);
        for (int s = 0; s < t->nstencil; s++) {
          int w = (t->sptr[s + 1] - t->sptr[s]) * m->dim;
          double amax, lmin = eigenvalue_range(blk + t->hptr[s], w, 1, &amax);
          if (lmin >= -1e-10 * amax) continue;
          if (failures++ < 5)
            print_message("%s %dD %s: %s state %d, stencil %d: smallest eigenvalue %.3e, "
                          "largest |eigenvalue| %.3e (ratio %.2e)\n", c->label, c->dim,
                          mode == SW_FILTER_ABS ? "abs" : "clamp", KIND[kind], rep, s, lmin,
                          amax, lmin / amax);
        }
        for (int r = 0; t->nlowrank && r < t->lptr[t->nlowrank] * m->dim; r++)
          assert_true(isfinite(lr[r]));
      }
    }
  if (failures) print_message("%s %dD: %d blocks not PSD\n", c->label, c->dim, failures);
  assert_int_equal(failures, 0);
  free(x), free(blk), free(lr);
}

/* |H| = 2 H+ - H, block by block and for the low-rank vectors' outer products (equal for all
 * filters), to round-off: the absolute filter takes |lambda| of the eigenvalues the clamp
 * filter cuts at 0.  At the well-conditioned kinds of state only: where warp and weft are
 * nearly parallel the plane of a face, hence the eigenvectors of the membranes' P, is known to
 * 1e-16 tr C / |wu x wv| only, and so are both sides (the PSD check covers those states). */
static void check_abs_identity(const config *c, unsigned long seed) {
  const sw_model *m = c->m;
  const int k = term_index(m, c->term);
  const sw_term *t = &m->term[k];
  const size_t nb = (size_t)t->hptr[t->nstencil] + 1, nl = lowrank_size(m, t);
  double *x = calloc((size_t)m->nv * (size_t)m->dim, sizeof(double));
  double *H = calloc(nb, sizeof(double)), *Hc = calloc(nb, sizeof(double));
  double *Ha = calloc(nb, sizeof(double)), *lr = calloc(nl, sizeof(double));
  double *lra = calloc(nl, sizeof(double));
  assert_non_null(x), assert_non_null(H), assert_non_null(Hc), assert_non_null(Ha);
  assert_non_null(lr), assert_non_null(lra);
  unsigned long rs = seed;
  int changed = 0; /* states where the filters differ from the exact Hessian */
  for (int kind = 0; kind < NKIND; kind++)
    for (int rep = 0; rep < REPS / 4 && kind != 4 && kind != 5; rep++) {
      deform(m, kind, &rs, x);
      term_hessian(m, k, x, SW_FILTER_NONE, H, lr);
      term_hessian(m, k, x, SW_FILTER_CLAMP, Hc, lr);
      term_hessian(m, k, x, SW_FILTER_ABS, Ha, lra);
      for (size_t r = 0; r + 1 < nl; r++) assert_true(lr[r] == lra[r]);
      for (int s = 0; s < t->nstencil; s++) {
        long w2 = t->hptr[s + 1] - t->hptr[s];
        const double *h = H + t->hptr[s], *hc = Hc + t->hptr[s], *ha = Ha + t->hptr[s];
        double scale = 0.0, err = 0.0, diff = 0.0;
        for (long q = 0; q < w2; q++) scale = fmax(scale, fmax(fabs(h[q]), fabs(ha[q])));
        for (long q = 0; q < w2; q++) {
          err = fmax(err, fabs(ha[q] - (2.0 * hc[q] - h[q])));
          diff = fmax(diff, fabs(ha[q] - h[q]));
        }
        changed += diff > 1e-6 * scale;
        if (!(err <= 1e-9 * scale))
          print_message("%s %dD: %s state %d, stencil %d: |H| - (2 H+ - H) = %.3e of %.3e\n",
                        c->label, c->dim, KIND[kind], rep, s, err, scale);
        assert_true(err <= 1e-9 * scale);
      }
    }
  assert_true(c->acts ? changed > 0 : changed == 0);
  free(x), free(H), free(Hc), free(Ha), free(lr), free(lra);
}

/* ------------------------------------------------------------------ tests */

static void run_config(config c, unsigned long seed) {
  assert_non_null(c.m);
  check_psd(&c, seed);
  check_abs_identity(&c, seed + 1000);
  sw_model_free(c.m);
}

#define MEMBRANE_TEST(fn, model, name, dim)                                                  \
  static void fn(void **st) {                                                                \
    (void)st;                                                                                \
    run_config((config){name, name, dim, membrane_model(dim, model), 1}, 11 + (unsigned long)dim); \
  }
/* bw98: every block PSD with stretch and shear; |H| = 2 H+ - H for the stretch conditions (a
 * model without shear); the shear condition is clamped under both filters (models/bw98.c), so
 * a shear-only model's abs blocks equal its clamped ones. */
static void check_bw98(int dim, unsigned long seed) {
  config c = {"bw98", "bw98", dim, membrane_model(dim, SW_MEMBRANE_BW98), 1};
  assert_non_null(c.m);
  check_psd(&c, seed);
  sw_model_free(c.m);
  c.m = membrane_model_k(dim, SW_MEMBRANE_BW98, 400.0, 0.0);
  assert_non_null(c.m);
  check_abs_identity(&c, seed + 1000);
  sw_model_free(c.m);
  sw_model *m = membrane_model_k(dim, SW_MEMBRANE_BW98, 0.0, 35.0);
  assert_non_null(m);
  const int k = term_index(m, "bw98");
  const sw_term *t = &m->term[k];
  const size_t nb = (size_t)t->hptr[t->nstencil] + 1;
  double *x = calloc((size_t)m->nv * (size_t)m->dim, sizeof(double));
  double *Hc = calloc(nb, sizeof(double)), *Ha = calloc(nb, sizeof(double));
  double *lr = calloc(lowrank_size(m, t), sizeof(double));
  assert_non_null(x), assert_non_null(Hc), assert_non_null(Ha), assert_non_null(lr);
  unsigned long rs = seed + 2000;
  for (int kind = 0; kind < NKIND; kind++) {
    deform(m, kind, &rs, x);
    term_hessian(m, k, x, SW_FILTER_CLAMP, Hc, lr);
    term_hessian(m, k, x, SW_FILTER_ABS, Ha, lr);
    for (size_t q = 0; q + 1 < nb; q++) assert_true(Ha[q] == Hc[q]);
  }
  free(x), free(Hc), free(Ha), free(lr);
  sw_model_free(m);
}
static void bw98_2d(void **st) { (void)st, check_bw98(2, 13); }
static void bw98_3d(void **st) { (void)st, check_bw98(3, 14); }
MEMBRANE_TEST(stvk_2d, SW_MEMBRANE_STVK, "stvk", 2)
MEMBRANE_TEST(stvk_3d, SW_MEMBRANE_STVK, "stvk", 3)
MEMBRANE_TEST(corotated_2d, SW_MEMBRANE_COROTATED, "corotated", 2)
MEMBRANE_TEST(corotated_3d, SW_MEMBRANE_COROTATED, "corotated", 3)
MEMBRANE_TEST(springs_2d, SW_MEMBRANE_SPRINGS, "springs", 2)
MEMBRANE_TEST(springs_3d, SW_MEMBRANE_SPRINGS, "springs", 3)

static void dihedral_3d(void **st) {
  (void)st;
  run_config((config){"dihedral", "dihedral", 3, bending_model(3, SW_BENDING_DIHEDRAL), 1}, 31);
}
static void quadratic_2d(void **st) {
  (void)st;
  run_config((config){"quadratic", "quadratic", 2, bending_model(2, SW_BENDING_QUADRATIC), 0}, 41);
}
static void quadratic_3d(void **st) {
  (void)st;
  run_config((config){"quadratic", "quadratic", 3, bending_model(3, SW_BENDING_QUADRATIC), 0}, 43);
}

static void morley_2d(void **st) {
  (void)st;
  run_config((config){"morley", "morley", 2, bending_model(2, SW_BENDING_MORLEY), 0}, 45);
}
static void morley_3d(void **st) {
  (void)st;
  run_config((config){"morley", "morley", 3, bending_model(3, SW_BENDING_MORLEY), 0}, 47);
}

static void dde_bending_2d(void **st) {
  (void)st;
  run_config((config){"dde_bending", "dde_bending", 2, dde_bending_model(2), 1}, 61);
}
static void dde_bending_3d(void **st) {
  (void)st;
  /* at these states every block is PSD already (the filter changes none); in 2D's it acts */
  run_config((config){"dde_bending", "dde_bending", 3, dde_bending_model(3), 0}, 63);
}

#define TENDON_TEST(fn, law, label, dim, dense_max)                                         \
  static void fn(void **st) {                                                               \
    (void)st;                                                                               \
    run_config((config){label, "tendons", dim, tendon_model(dim, law, dense_max),          \
                        law == SW_LAW_SPRING},                                              \
               51 + (unsigned long)(dim * 7 + dense_max));                                  \
  }
TENDON_TEST(spring_compressed_dense_2d, SW_LAW_SPRING, "compressed spring (dense)", 2, 32)
TENDON_TEST(spring_compressed_dense_3d, SW_LAW_SPRING, "compressed spring (dense)", 3, 32)
TENDON_TEST(spring_compressed_lowrank_2d, SW_LAW_SPRING, "compressed spring (low-rank)", 2, 2)
TENDON_TEST(spring_compressed_lowrank_3d, SW_LAW_SPRING, "compressed spring (low-rank)", 3, 2)
TENDON_TEST(cable_taut_dense_2d, SW_LAW_CABLE, "taut cable (dense)", 2, 32)
TENDON_TEST(cable_taut_dense_3d, SW_LAW_CABLE, "taut cable (dense)", 3, 32)
TENDON_TEST(cable_taut_lowrank_2d, SW_LAW_CABLE, "taut cable (low-rank)", 2, 2)
TENDON_TEST(cable_taut_lowrank_3d, SW_LAW_CABLE, "taut cable (low-rank)", 3, 2)

/* A spring compressed to half its rest length L along n: H = k n n^T + k (1 - L/l)(I - n n^T)
 * with 1 - L/l = -1, so the clamped block is k n n^T and the absolute one k I (and -k on the
 * off-diagonal vertex blocks). */
static void spring_half_length(void **st) {
  (void)st;
  sw_material mt = base_mat();
  mt.membrane = SW_MEMBRANE_SPRINGS, mt.ks_stretch = 250.0; /* N/m; no shear or bend springs */
  sw_model *m = th_grid_model_mat(3, 2, 2, 0.4, 0.4, &mt);
  assert_non_null(m);
  const int k = term_index(m, "springs");
  const sw_term *t = &m->term[k];
  double x[12], blk[4 * 36], n[3] = {0.6, 0.0, 0.8};
  for (int s = 0; s < t->nstencil; s++) {
    const int i = t->sidx[2 * s], j = t->sidx[2 * s + 1];
    double L = 0.0; /* rest length, m */
    for (int a = 0; a < 2; a++) L += pow(m->x0[i * 3 + a] - m->x0[j * 3 + a], 2);
    L = sqrt(L);
    memcpy(x, m->x0, sizeof x);
    for (int a = 0; a < 3; a++) x[j * 3 + a] = x[i * 3 + a] - 0.5 * L * n[a];
    for (int mode = SW_FILTER_CLAMP; mode <= SW_FILTER_ABS; mode++) {
      memset(blk, 0, sizeof blk);
      sw_eval ev = {.x = x, .hess = blk, .project = mode};
      double e = 0.0;
      assert_int_equal(t->ops->eval(t, m, &ev, &e), SW_OK);
      const double *b = blk + t->hptr[s];
      for (int p = 0; p < 6; p++)
        for (int q = 0; q < 6; q++) {
          int a = p % 3, c = q % 3;
          double h = mode == SW_FILTER_ABS ? 250.0 * (a == c) : 250.0 * n[a] * n[c];
          if (p / 3 != q / 3) h = -h;
          assert_true(fabs(sw_hess_get(b, p, q, 6) - h) < 1e-10);
        }
    }
  }
  sw_model_free(m);
}

static void cross3(const double *p, const double *q, double *c) {
  c[0] = p[1] * q[2] - p[2] * q[1], c[1] = p[2] * q[0] - p[0] * q[2], c[2] = p[0] * q[1] - p[1] * q[0];
}
static double norm3(const double *p) { return sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); }

/* Newton's system next to a collapsed face.  A 3 x 3 grid of 0.1 m cells (bw98 and dihedral
 * bending, the materials of a light garment), curved into a cylinder of radius 0.5 m, whose
 * centre vertex is moved, in the plane of one of its faces, to `rel` x the cell size from the
 * midpoint of the opposite edge: that face's area falls to ~rel of its rest area, as when a
 * drawstring crushes a hem.  The clamped Hessian with backward Euler's mass term at dt = 10 ms,
 * S = M/dt^2 + H, must be positive definite to CHOLMOD and the Newton step finite.  A hinge
 * next to such a face has a 12 x 12 block growing as 1/area^2; before its filtered blocks got a
 * diagonal shift relative to their size (models/dihedral.c), the round-off of the filtered
 * eigenvalues (1e-16 of the block) swamped the mass term (20 N/m at the centre vertex) and
 * CHOLMOD refused S from an area ratio of 1e-11 on. */
static void collapsed_system(double rel) {
  sw_material mt = base_mat();
  mt.density = 0.15;                                                                  /* kg/m^2 */
  mt.membrane = SW_MEMBRANE_BW98, mt.k_u = 2000.0, mt.k_v = 1500.0, mt.k_shear = 50.0; /* N/m */
  mt.bending = SW_BENDING_DIHEDRAL, mt.k_bend = 1e-5, mt.bend_rest = SW_BEND_REST_FLAT; /* N m */
  sw_model *m = th_grid_model_mat(3, 3, 3, 0.2, 0.2, &mt);
  assert_non_null(m);
  const int nd = m->nv * 3;
  double *x = calloc((size_t)nd, sizeof(double));
  assert_non_null(x);
  for (int i = 0; i < m->nv; i++) {
    double u = m->x0[3 * i] - 0.1;
    x[3 * i] = 0.1 + 0.5 * sin(u / 0.5);
    x[3 * i + 1] = m->x0[3 * i + 1];
    x[3 * i + 2] = 0.5 * (1.0 - cos(u / 0.5));
  }
  int f = -1, c = 0; /* the first face of the centre vertex 4, and its corner there */
  for (int q = 0; q < m->nf && f < 0; q++)
    for (int k = 0; k < 3; k++)
      if (m->face[3 * q + k] == 4) f = q, c = k;
  assert_true(f >= 0);
  const int va = m->face[3 * f + (c + 1) % 3], vb = m->face[3 * f + (c + 2) % 3];
  double e[3], g[3], nrm[3], side[3]; /* edge, to the centre, face normal, in-plane normal */
  for (int k = 0; k < 3; k++) e[k] = x[3 * vb + k] - x[3 * va + k], g[k] = x[12 + k] - x[3 * va + k];
  cross3(e, g, nrm);
  cross3(nrm, e, side);
  double sl = norm3(side);
  for (int k = 0; k < 3; k++) x[12 + k] = x[3 * va + k] + 0.5 * e[k] + rel * 0.1 * side[k] / sl;
  const int *v = m->face + 3 * f;
  double p[3], q[3], cr[3];
  for (int k = 0; k < 3; k++)
    p[k] = x[3 * v[1] + k] - x[3 * v[0] + k], q[k] = x[3 * v[2] + k] - x[3 * v[0] + k];
  cross3(p, q, cr);
  double ratio = 0.5 * norm3(cr) / m->area[f]; /* deformed / rest area */
  assert_true(ratio > 0.1 * rel && ratio < 10.0 * rel);

  sw_data *d = sw_data_new(m);
  sw_newton nw;
  char err[SW_ERRSZ];
  assert_non_null(d);
  assert_int_equal(sw_newton_init(&nw, m, err, sizeof err), SW_OK);
  double u = 0.0, dt = 0.01; /* J, s */
  assert_int_equal(sw_eval_terms(m, d, x, 0.0, 1, 1, SW_FILTER_CLAMP, &u), SW_OK);
  assert_true(isfinite(u));
  sw_pattern_fill(&nw.pat, m, d, 1.0 / (dt * dt), 1.0, sw_chol_values(&nw.chol));
  int rc = sw_chol_factor(&nw.chol, err, sizeof err);
  if (rc) print_message("face at %g of its area: %s\n", ratio, err);
  assert_int_equal(rc, SW_OK);
  double *rhs = calloc((size_t)nw.n, sizeof(double)), *dx = calloc((size_t)nw.n, sizeof(double));
  assert_non_null(rhs), assert_non_null(dx);
  for (int i = 0; i < nd; i++)
    if (m->dof[i] >= 0) rhs[m->dof[i]] = -d->grad[i];
  assert_int_equal(sw_chol_solve(&nw.chol, rhs, dx, err, sizeof err), SW_OK);
  for (int i = 0; i < nw.n; i++) assert_true(isfinite(dx[i]));
  free(rhs), free(dx), free(x);
  sw_newton_free(&nw);
  sw_data_free(d);
  sw_model_free(m);
}

static void collapsed_face_system(void **st) {
  (void)st;
  for (double rel = 1e-8; rel > 1e-14; rel *= 0.1) collapsed_system(rel);
}

/* The filter of a symmetric n x n matrix by a full eigen-decomposition (LAPACK dsyev),
 * V f(Lambda) V^T, into F: the reference for sw_psd_project. */
static void filter_by_dsyev(const double *A, int n, int mode, double *F) {
  int lwork = 64 * n, info = 0;
  double V[144], lam[12], work[64 * 12];
  memcpy(V, A, sizeof(double) * (size_t)(n * n));
  dsyev_("V", "U", &n, V, &n, lam, work, &lwork, &info);
  assert_int_equal(info, 0);
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      double s = 0.0;
      for (int k = 0; k < n; k++) s += sw_filter_eigenvalue(lam[k], mode) * V[k * n + i] * V[k * n + j];
      F[i * n + j] = s;
    }
}

/* ------------------------------------------------------------ models/eigen.c */

/* A random symmetric n x n matrix with entries in [-1, 1] (scale s), row-major. */
static void random_sym(double *A, int n, double s, unsigned *seed) {
  for (int i = 0; i < n; i++)
    for (int j = 0; j <= i; j++) {
      *seed = *seed * 1103515245u + 12345u;
      A[i * n + j] = A[j * n + i] = s * ((double)(*seed >> 8) / (double)(1u << 24) * 2.0 - 1.0);
    }
}

/* sw_sym_eigen from 1 x 1 to 18 x 18, random matrices at scales 1e-12 to 1e12 and one with a
 * repeated eigenvalue: A V = V diag(w) and V^T V = I to 1e-13 of |A|, the eigenvalues those of
 * LAPACK's dsyev; sw_sym_is_pd says 1 exactly when the smallest eigenvalue is clearly positive,
 * 0 when clearly negative. */
static void sym_eigen_matches_lapack(void **st) {
  (void)st;
  unsigned seed = 7;
  const double scales[3] = {1e-12, 1.0, 1e12};
  for (int n = 1; n <= SW_EIGEN_NMAX; n++)
    for (int k = 0; k < 4; k++) {
      double A[SW_EIGEN_NMAX * SW_EIGEN_NMAX], V[SW_EIGEN_NMAX * SW_EIGEN_NMAX];
      double L[SW_EIGEN_NMAX * SW_EIGEN_NMAX], w[SW_EIGEN_NMAX], lw[SW_EIGEN_NMAX], work[18 * 34];
      double s = k < 3 ? scales[k] : 1.0;
      random_sym(A, n, s, &seed);
      if (k == 3) /* I + e e^T: eigenvalue 1 n - 1 times */
        for (int i = 0; i < n; i++)
          for (int j = 0; j < n; j++) A[i * n + j] = (i == j) + 0.5;
      memcpy(V, A, sizeof(double) * (size_t)(n * n));
      assert_int_equal(sw_sym_eigen(V, n, w), 0);
      double norm = 0.0;
      for (int i = 0; i < n * n; i++) norm = fmax(norm, fabs(A[i]));
      for (int i = 0; i < n; i++)
        for (int c = 0; c < n; c++) {
          double av = 0.0, vv = 0.0;
          for (int j = 0; j < n; j++)
            av += A[i * n + j] * V[j * n + c], vv += V[j * n + i] * V[j * n + c];
          assert_true(fabs(av - w[c] * V[i * n + c]) <= 1e-13 * n * norm);
          assert_true(fabs(vv - (i == c)) <= 1e-13 * n);
        }
      int lwork = 18 * 34, info = 0;
      memcpy(L, A, sizeof(double) * (size_t)(n * n));
      dsyev_("N", "U", &n, L, &n, lw, work, &lwork, &info);
      assert_int_equal(info, 0);
      double ws[SW_EIGEN_NMAX];
      memcpy(ws, w, sizeof ws);
      for (int i = 1; i < n; i++) /* ascending, as LAPACK's */
        for (int j = i; j > 0 && ws[j] < ws[j - 1]; j--) {
          double t = ws[j];
          ws[j] = ws[j - 1], ws[j - 1] = t;
        }
      for (int i = 0; i < n; i++) assert_true(fabs(ws[i] - lw[i]) <= 1e-13 * n * norm);
      if (lw[0] > 1e-8 * norm) assert_int_equal(sw_sym_is_pd(A, n), 1);
      if (lw[0] < -1e-8 * norm) assert_int_equal(sw_sym_is_pd(A, n), 0);
    }
  double A[4] = {1.0, NAN, NAN, 1.0}, w[2];
  assert_int_equal(sw_sym_eigen(A, 2, w), -1); /* not finite */
  assert_int_equal(sw_sym_eigen(A, SW_EIGEN_NMAX + 1, w), -1);
  assert_int_equal(sw_sym_is_pd(A, 2), 0);
}

/* Helmert's contrasts, 2 to 6 vertices: Q^T Q = I (the reduction of the identity is the
 * identity), a block H = Q M Q^T of a translation-free energy comes back as M and goes back to
 * H, and such an H has the translations in its null space. */
static void contrasts_round_trip(void **st) {
  (void)st;
  unsigned seed = 11;
  for (int nv = 2; nv <= 6; nv++) {
    const int w = 3 * nv, r = w - 3;
    double I[18 * 18] = {0}, M[18 * 18], M2[18 * 18], H[18 * 18];
    for (int i = 0; i < w; i++) I[i * (w + 1)] = 1.0;
    sw_contrast_reduce(I, nv, M);
    for (int i = 0; i < r * r; i++) assert_true(fabs(M[i] - (i % (r + 1) == 0)) <= 1e-15);
    random_sym(M, r, 1.0, &seed);
    sw_contrast_lift(M, nv, H);
    for (int i = 0; i < w; i++)
      for (int a = 0; a < 3; a++) { /* H (1 (x) e_a) = 0 */
        double t = 0.0;
        for (int v = 0; v < nv; v++) t += H[i * w + 3 * v + a];
        assert_true(fabs(t) <= 1e-14);
      }
    sw_contrast_reduce(H, nv, M2);
    for (int i = 0; i < r * r; i++) assert_true(fabs(M2[i] - M[i]) <= 1e-14);
  }
}

/* A block with zero rows (a contact pair whose closest features involve 2 or 3 of its 4
 * vertices): sw_psd_project filters only its nonzero rows and columns, and the result is the
 * filter of the whole 12 x 12 block by a full eigen-decomposition, to 1e-12 of its largest
 * eigenvalue; the zero rows stay exactly zero.  Random indefinite blocks, 6 and 9 nonzero rows
 * (the ends of the rows, the middle), both filters. */
static void zero_rows_block(void **st) {
  (void)st;
  unsigned long rs = 99;
  for (int nk = 6; nk <= 9; nk += 3)
    for (int mode = SW_FILTER_CLAMP; mode <= SW_FILTER_ABS; mode++) {
      int keep[9];
      for (int a = 0; a < nk; a++) keep[a] = nk == 9 ? (a < 3 ? a : a + 3) : a + 6;
      double S[81], F[144] = {0}, want[144];
      for (int a = 0; a < nk; a++)
        for (int b = 0; b <= a; b++) S[a * nk + b] = S[b * nk + a] = 2.0 * th_rand(&rs) - 1.0;
      for (int a = 0; a < nk; a++)
        for (int b = 0; b < nk; b++) F[keep[a] * 12 + keep[b]] = S[a * nk + b];
      double amax = 0.0;
      assert_true(min_eigenvalue(F, 12, &amax) < -0.1 * amax); /* the filter has work to do */
      filter_by_dsyev(F, 12, mode, want);
      assert_int_equal(sw_psd_project(F, 12, mode), 0);
      for (int i = 0; i < 144; i++) {
        int row = 0, col = 0;
        for (int a = 0; a < nk; a++) row |= keep[a] == i / 12, col |= keep[a] == i % 12;
        if (!(row && col)) assert_true(F[i] == 0.0);
        assert_true(fabs(F[i] - want[i]) <= 1e-12 * amax);
      }
    }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(sym_eigen_matches_lapack),
      cmocka_unit_test(contrasts_round_trip),
      cmocka_unit_test(zero_rows_block),
      cmocka_unit_test(bw98_2d),
      cmocka_unit_test(bw98_3d),
      cmocka_unit_test(stvk_2d),
      cmocka_unit_test(stvk_3d),
      cmocka_unit_test(corotated_2d),
      cmocka_unit_test(corotated_3d),
      cmocka_unit_test(springs_2d),
      cmocka_unit_test(springs_3d),
      cmocka_unit_test(dihedral_3d),
      cmocka_unit_test(quadratic_2d),
      cmocka_unit_test(quadratic_3d),
      cmocka_unit_test(morley_2d),
      cmocka_unit_test(morley_3d),           cmocka_unit_test(dde_bending_2d),
      cmocka_unit_test(dde_bending_3d),
      cmocka_unit_test(spring_compressed_dense_2d),
      cmocka_unit_test(spring_compressed_dense_3d),
      cmocka_unit_test(spring_compressed_lowrank_2d),
      cmocka_unit_test(spring_compressed_lowrank_3d),
      cmocka_unit_test(cable_taut_dense_2d),
      cmocka_unit_test(cable_taut_dense_3d),
      cmocka_unit_test(cable_taut_lowrank_2d),
      cmocka_unit_test(cable_taut_lowrank_3d),
      cmocka_unit_test(spring_half_length),
      cmocka_unit_test(collapsed_face_system),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
