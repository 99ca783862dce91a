/* tendon.c — tendons through mesh-node waypoints (the waypoint tendon model;
 * docs/tendons.md).
 *
 * A tendon with waypoints w_0 .. w_{n-1} has segments s_k = x_{w_k} - x_{w_{k+1}} (the tendon
 * model §1.2), length l = sum |s_k|, rest length alpha(t) (keyframes, models/keyframe.c),
 * Delta = l - alpha and energy
 * E(Delta; K):  spring E = K/2 Delta^2;  cable E = K/2 max(Delta, 0)^2.  With s^_k = s_k/|s_k|:
 *   grad Delta at waypoint a = s^_a - s^_{a-1}            (its "first partials"; the end
 *                                                          points keep one term)
 *   d2 Delta: (a,a) = zeta_a + zeta_{a-1}, (a,a+1) = (a+1,a) = -zeta_a,
 *             zeta_k = (I - s^_k s^_k^T) / |s_k|          (its "second partials")
 *   g = E' grad Delta,  H = E'' grad Delta grad Delta^T + E' d2 Delta   (its §1.2)
 * in 2D and 3D alike.  Both parts of H are PSD when E'' >= 0 (always) and E' >= 0: d2 Delta is
 * PSD, so the eigenvalues of E' d2 Delta are those of d2 Delta times E'.  Where E' < 0 (a
 * compressed spring) the filtered Hessian (SW_FILTER_*) drops that part (clamp) or takes
 * |E'| d2 Delta (absolute eigenvalues).
 *
 * A segment shorter than eps = SW_TENDON_SMOOTH x the tendon's initial rest length per
 * segment counts the length (|s_k|^2 + eps^2) / (2 eps) instead of |s_k| (the same value and
 * gradient at |s_k| = eps): its gradient is s_k / eps in place of s^_k and its second
 * partials I / eps in place of zeta_k.  |s| itself is a cone at s = 0: a taut cable gathering
 * cloth pulls two waypoints together until they meet, its energy's minimiser then sits on the
 * cone's tip, and Newton's iterates jump across it without converging (their updates do not
 * shrink, the line search cuts every step to nothing).  Longer segments are untouched.  With
 * eps = 0 (a tendon of zero rest length) a zero-length segment (|s_k| <= 1e-12 of the
 * coordinates' size) has no direction: it counts its length (~0) in l and contributes s^_k = 0
 * and zeta_k = 0, the subgradient 0 of |s| at s = 0 and no stiffness, so nothing is NaN or Inf.
 *
 * Storage (sparse factor, docs/tendons.md): a tendon of at most opt.tendon_dense_max waypoints
 * is one dense stencil holding all of H; a longer one has one 2-vertex stencil per segment
 * holding E' zeta_k [[I, -I], [-I, I]] and one low-rank vector u = sqrt(E'') grad Delta, so
 * H = (banded blocks) + u u^T and the solvers add u u^T by Woodbury. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

#define SEG_EPS 1e-12 /* a segment shorter than this times its ends' size is degenerate */
/* eps / (rest length per segment) of the smoothed segment length (the header) */
#define SW_TENDON_SMOOTH 1e-3

typedef struct tendon_param {
  int *first;   /* (ntendon) first stencil of each tendon */
  int *rank;    /* (ntendon) its low-rank vector, or -1: one dense stencil */
} tendon_param;

double sw_tendon_rest(const sw_tendon *td, double t) {
  return sw_keyframe_value(td->key_t, td->key_rest, td->nkey, td->interp, t); /* m */
}

double sw_tendon_rest_rate(const sw_tendon *td, double t) {
  return sw_keyframe_rate(td->key_t, td->key_rest, td->nkey, td->interp, t); /* m/s */
}

/* The smoothing width eps of a tendon's segment lengths, m (the header). */
static double smooth_width(const sw_tendon *td) {
  double rest = td->nkey > 0 ? fabs(td->key_rest[0]) : 0.0; /* m */
  return td->nway > 1 ? SW_TENDON_SMOOTH * rest / (td->nway - 1) : 0.0;
}

/* s_k = x_{w_k} - x_{w_{k+1}}: its (smoothed) length l_k (m), into sh its gradient dl_k/ds_k
 * (s^_k; s_k / eps when shorter than eps; 0 if degenerate) and, when p is not NULL, its
 * second partials as (I - p p^T) / *hl (p = s^_k, *hl = |s_k|; p = 0, *hl = eps when shorter
 * than eps; *hl = inf, no stiffness, if degenerate). */
static double segment(const sw_tendon *td, const double *x, int d, int k, double *sh, double *p,
                      double *hl) {
  const double *a = x + (size_t)td->way[k] * d, *b = x + (size_t)td->way[k + 1] * d;
  const double eps = smooth_width(td); /* m */
  double l = 0.0, size = 0.0;
  for (int c = 0; c < d; c++) {
    sh[c] = a[c] - b[c];
    l += sh[c] * sh[c];
    size = fmax(size, fmax(fabs(a[c]), fabs(b[c])));
  }
  l = sqrt(l);
  double scale, h; /* sh *= scale; the second partials' length */
  if (l < eps) scale = 1.0 / eps, h = eps;
  else if (!(l > SEG_EPS * size)) scale = 0.0, h = INFINITY; /* also l = 0 and NaN */
  else scale = 1.0 / l, h = l;
  for (int c = 0; c < d; c++) sh[c] *= scale;
  if (p) {
    for (int c = 0; c < d; c++) p[c] = l < eps ? 0.0 : sh[c];
    *hl = h;
  }
  return l < eps ? (l * l + eps * eps) / (2.0 * eps) : l;
}

double sw_tendon_length(const sw_tendon *td, const double *x, int dim) {
  double len = 0.0, sh[3];
  for (int k = 0; k + 1 < td->nway; k++) len += segment(td, x, dim, k, sh, NULL, NULL);
  return len;
}

/* grad Delta at waypoint a (the tendon model): s^_a - s^_{a-1}, the end points keeping one term. */
void sw_tendon_grad(const sw_tendon *td, const double *x, int d, int a, double *g) {
  double sh[3];
  for (int c = 0; c < d; c++) g[c] = 0.0;
  if (a + 1 < td->nway) {
    segment(td, x, d, a, sh, NULL, NULL);
    for (int c = 0; c < d; c++) g[c] += sh[c];
  }
  if (a > 0) {
    segment(td, x, d, a - 1, sh, NULL, NULL);
    for (int c = 0; c < d; c++) g[c] -= sh[c];
  }
}

/* The law: E (J), E' = tension (N) and E'' (N/m) at Delta (m).  A cable is slack (all zero)
 * for Delta <= 0. */
static double law(const sw_tendon *td, double delta, double *e1, double *e2) {
  const double K = td->stiffness; /* N/m */
  if (td->law == SW_LAW_CABLE && !(delta > 0.0)) {
    *e1 = *e2 = 0.0;
    return 0.0;
  }
  *e1 = K * delta;
  *e2 = K;
  return 0.5 * K * delta * delta;
}

/* c (I - p p^T) / len (zeta_k, or I / eps for a short segment) into the (d x d) block at rows
 * r0.., columns c0.. of blk (w x w, its upper triangle); nothing when len is infinite (a
 * degenerate segment). */
static void add_zeta(double *blk, int w, int r0, int c0, int d, const double *sh, double len,
                     double c) {
  for (int a = 0; a < d; a++)
    for (int b = 0; b < d; b++)
      sw_hess_add(blk, w, r0 + a, c0 + b, c * ((a == b) - sh[a] * sh[b]) / len);
}

/* c d2 Delta of segment k (the tendon model: +zeta_k on the diagonal blocks of its two ends,
 * -zeta_k off it) into a block where the ends are local vertices i0 and i1. */
static void add_segment_band(const sw_tendon *td, const double *x, int d, int k, double c,
                             double *blk, int ld, int i0, int i1) {
  double sh[3], p[3], hl;
  segment(td, x, d, k, sh, p, &hl);
  add_zeta(blk, ld, i0 * d, i0 * d, d, p, hl, c);
  add_zeta(blk, ld, i1 * d, i1 * d, d, p, hl, c);
  add_zeta(blk, ld, i0 * d, i1 * d, d, p, hl, -c);
  add_zeta(blk, ld, i1 * d, i0 * d, d, p, hl, -c);
}

/* The whole Hessian E'' grad grad^T + cb d2 Delta of a short tendon: one block of n d rows. */
static void dense_block(const sw_tendon *td, const double *x, int d, double e2, double cb,
                        double *blk) {
  const int n = td->nway, ld = n * d;
  for (int i = 0; i < n; i++) {
    double gi[3], gj[3];
    sw_tendon_grad(td, x, d, i, gi);
    for (int j = i; j < n; j++) {
      sw_tendon_grad(td, x, d, j, gj);
      for (int a = 0; a < d; a++)
        for (int b = 0; b < d; b++) sw_hess_add(blk, ld, i * d + a, j * d + b, e2 * gi[a] * gj[b]);
    }
  }
  if (cb != 0.0)
    for (int k = 0; k + 1 < n; k++) add_segment_band(td, x, d, k, cb, blk, ld, k, k + 1);
}

/* A long tendon: cb zeta_k per segment stencil, u = sqrt(E'') grad Delta as its vector. */
static void banded_lowrank(const sw_term *t, const sw_tendon *td, const double *x, int d,
                           int s0, double e2, double cb, const sw_eval *ev, double *u) {
  if (cb != 0.0)
    for (int k = 0; k + 1 < td->nway; k++) {
      double *blk = sw_ev_block(ev, t, s0 + k);
      add_segment_band(td, x, d, k, cb, blk, 2 * d, 0, 1);
      sw_ev_block_done(ev, t, s0 + k, blk);
    }
  double r = sqrt(e2);
  for (int a = 0; a < td->nway; a++) {
    sw_tendon_grad(td, x, d, a, u + a * d);
    for (int c = 0; c < d; c++) u[a * d + c] *= r;
  }
}

/* One tendon: energy (J); gradient and Hessian as ev asks. */
static double eval_one(const sw_term *t, const sw_model *m, const sw_eval *ev, int k) {
  const tendon_param *tp = t->param;
  const sw_tendon *td = &m->tendon[k];
  const int d = m->dim;
  double delta = sw_tendon_length(td, ev->x, d) - sw_tendon_rest(td, ev->t); /* m */
  double e1, e2, e = law(td, delta, &e1, &e2);
  if (e1 == 0.0 && e2 == 0.0) { /* slack cable (or K = 0): no force, no stiffness */
    if (ev->hess && tp->rank[k] >= 0)
      memset(ev->lowrank + (size_t)t->lptr[tp->rank[k]] * d, 0, sizeof(double) * td->nway * d);
    return e;
  }
  if (ev->grad)
    for (int a = 0; a < td->nway; a++) {
      double g[3];
      sw_tendon_grad(td, ev->x, d, a, g);
      for (int c = 0; c < d; c++) ev->grad[(size_t)td->way[a] * d + c] += e1 * g[c];
    }
  if (ev->hess) {
    double cb = ev->project ? sw_filter_eigenvalue(e1, ev->project) : e1; /* the PSD rule */
    int s0 = tp->first[k];
    if (tp->rank[k] < 0) {
      double *blk = sw_ev_block(ev, t, s0);
      dense_block(td, ev->x, d, e2, cb, blk);
      sw_ev_block_done(ev, t, s0, blk);
    } else {
      double *u = ev->lowrank + (size_t)t->lptr[tp->rank[k]] * d;
      banded_lowrank(t, td, ev->x, d, s0, e2, cb, ev, u);
    }
  }
  return e;
}

static int tendon_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  double total = 0.0;
  for (int k = 0; k < m->ntendon; k++) total += eval_one(t, m, ev, k);
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static void tendon_free(void *p) {
  tendon_param *tp = p;
  if (!tp) return;
  sw_free(tp->first);
  sw_free(tp->rank);
  sw_free(tp);
}

static const sw_term_ops tendon_ops = {.kind = "tendons", .eval = tendon_eval,
                                       .free_param = tendon_free, .sink_ok = 1};

/* Count stencils, their vertices and doubles, and the low-rank vectors and their vertices. */
static void count(const sw_model *m, tendon_param *tp, int *ns, int *nidx, int *nlr, int *nlidx) {
  *ns = *nidx = *nlr = *nlidx = 0;
  for (int k = 0; k < m->ntendon; k++) {
    int n = m->tendon[k].nway;
    tp->first[k] = *ns;
    if (n <= m->opt.tendon_dense_max) {
      tp->rank[k] = -1;
      *ns += 1;
      *nidx += n;
    } else {
      tp->rank[k] = (*nlr)++;
      *ns += n - 1;
      *nidx += 2 * (n - 1);
      *nlidx += n;
    }
  }
}

/* sptr, sidx, hptr, lptr, lidx of every tendon (count() done). */
static void fill_stencils(sw_term *t, const sw_model *m, const tendon_param *tp) {
  const int d = m->dim;
  int s = 0;
  for (int k = 0; k < m->ntendon; k++) {
    const sw_tendon *td = &m->tendon[k];
    int n = td->nway, per = tp->rank[k] < 0 ? n : 2, nst = tp->rank[k] < 0 ? 1 : n - 1;
    for (int q = 0; q < nst; q++, s++) {
      t->sptr[s + 1] = t->sptr[s] + per;
      t->hptr[s + 1] = t->hptr[s] + sw_hess_size(per * d);
      for (int i = 0; i < per; i++) t->sidx[t->sptr[s] + i] = td->way[q + i];
    }
    int r = tp->rank[k];
    if (r < 0) continue;
    t->lptr[r + 1] = t->lptr[r] + n;
    memcpy(t->lidx + t->lptr[r], td->way, (size_t)n * sizeof(int));
  }
}

int sw_tendon_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  tendon_param *tp = sw_calloc(1, sizeof *tp);
  t->ops = &tendon_ops;
  t->param = tp;
  snprintf(t->name, sizeof t->name, "%s", "tendons");
  if (!tp) return sw_errf(err, errsz, "out of memory"), -1;
  tp->first = sw_calloc((size_t)m->ntendon, sizeof(int));
  tp->rank = sw_calloc((size_t)m->ntendon, sizeof(int));
  if (!tp->first || !tp->rank) return sw_errf(err, errsz, "out of memory"), -1;
  int ns, nidx, nlr, nlidx;
  count(m, tp, &ns, &nidx, &nlr, &nlidx);
  t->nstencil = ns;
  t->nlowrank = nlr;
  t->sptr = sw_calloc((size_t)ns + 1, sizeof(int));
  t->sidx = sw_calloc((size_t)nidx + 1, sizeof(int));
  t->hptr = sw_calloc((size_t)ns + 1, sizeof(long));
  t->lptr = sw_calloc((size_t)nlr + 1, sizeof(int));
  t->lidx = sw_calloc((size_t)nlidx + 1, sizeof(int));
  if (!t->sptr || !t->sidx || !t->hptr || !t->lptr || !t->lidx)
    return sw_errf(err, errsz, "out of memory"), -1;
  fill_stencils(t, m, tp);
  return 0;
}

double sw_tendon_tension(const sw_tendon *td, double delta) {
  double e1, e2;
  law(td, delta, &e1, &e2);
  return e1; /* N */
}

/* What tendons.csv logs after every step (README, "What a run writes"). */
void sw_tendon_state(const sw_model *m, sw_data *d) {
  for (int k = 0; k < m->ntendon; k++) {
    const sw_tendon *td = &m->tendon[k];
    d->tendon_length[k] = sw_tendon_length(td, d->x, m->dim);              /* m */
    d->tendon_delta[k] = d->tendon_length[k] - sw_tendon_rest(td, d->t);  /* m */
    d->tendon_tension[k] = sw_tendon_tension(td, d->tendon_delta[k]);      /* N */
  }
}
