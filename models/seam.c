/* seam.c — the term "seams": separate pattern pieces sewn together along pairs of boundary
 * curves (docs/garments.md), the way pattern tools pair sewing lines (the sewing springs of
 * Blender's cloth, the stitches of Li, Kaufman and Jiang, "Codimensional Incremental Potential
 * Contact", SIGGRAPH 2021).
 *
 * Pairing by arc length: a vertex at fraction s of its curve's rest (u,v) length is paired
 * with the point at the same fraction s of the other curve, which lies on one of its edges
 * (b0, b1) at weight w: p = (1 - w) x_b0 + w x_b1.  Every vertex of both curves is paired this
 * way, so curves of different resolution and of slightly different length (ease) are sewn
 * evenly.  Each pair is a spring of stiffness k l_p, l_p the seam length the pair stands for
 * (half the vertex's share of its curve, scaled to the seam's mean length: the pairs of both
 * curves add up to the seam's length), whose rest length r(t) = g0 (1 - sw_ramp(t, ramp))
 * shrinks smoothly from the pair's starting gap g0 to 0: the seam closes at the ramp's pace
 * whatever its stiffness (a stiff spring ramped in by its stiffness instead snaps the pieces
 * together at metres per second), then holds as a zero-length spring:
 *
 *   E = k l_p (|g| - r)^2 / 2,   g = sum_i c_i x_i,  c = (1, -(1 - w), -w) over (a, b0, b1),
 *   dE/dx_i = k l_p (|g| - r) c_i n,   n = g / |g|,
 *   d2E/dx_i dx_j = k l_p c_i c_j [(1 - r/|g|) (I - n n^T) + n n^T].
 *
 * The 3x3 factor has eigenvalues 1 (along n) and 1 - r/|g| (twice, across n), and c c^T is
 * rank one, so the block is filtered by filtering 1 - r/|g| alone; with r = 0 the block is
 * constant, k l_p c c^T (x) I, and positive semi-definite. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

/* ------------------------------------------------------------------ pairing */

/* Cumulative rest arc length of a curve whose edge lengths are el (n - 1), normalised to 1,
 * into s (n). */
static void arc_fractions(const double *el, int n, double *s) {
  double L = 0.0;
  s[0] = 0.0;
  for (int i = 0; i + 1 < n; i++) s[i + 1] = (L += el[i]);
  for (int i = 1; i < n; i++) s[i] = L > 0.0 ? s[i] / L : (double)i / (n - 1);
}

/* The pair of vertex i of curve `own` (fraction s) with the other curve (fractions t, m
 * vertices): its edge and weight. */
static void partner(const int *other, const double *t, int m, double s, int *b0, int *b1,
                    double *w) {
  int j = 0;
  while (j + 2 < m && t[j + 1] < s) j++;
  double span = t[j + 1] - t[j];
  double u = span > 0.0 ? (s - t[j]) / span : 0.0;
  *b0 = other[j];
  *b1 = other[j + 1];
  *w = fmin(1.0, fmax(0.0, u));
}

int sw_seam_pair(sw_seam *sm, const double *el0, const double *el1, char *err, size_t errsz) {
  const int n0 = sm->n[0], n1 = sm->n[1];
  double *s[2];
  s[0] = sw_calloc((size_t)(n0 + n1), sizeof(double));
  sm->npair = n0 + n1;
  sm->pair = sw_calloc(3 * (size_t)sm->npair, sizeof(int));
  sm->w = sw_calloc((size_t)sm->npair, sizeof(double));
  sm->len = sw_calloc((size_t)sm->npair, sizeof(double));
  if (!s[0] || !sm->pair || !sm->w || !sm->len)
    return sw_free(s[0]), sw_errf(err, errsz, "out of memory"), -1;
  s[1] = s[0] + n0;
  const double *el[2] = {el0, el1};
  for (int k = 0; k < 2; k++) {
    sm->length[k] = 0.0;
    for (int i = 0; i + 1 < sm->n[k]; i++) sm->length[k] += el[k][i]; /* m */
    arc_fractions(el[k], sm->n[k], s[k]);
  }
  const double L = 0.5 * (sm->length[0] + sm->length[1]); /* m */
  int p = 0;
  for (int k = 0; k < 2; k++) {
    const int o = 1 - k, n = sm->n[k];
    for (int i = 0; i < n; i++, p++) {
      int *q = sm->pair + 3 * p;
      q[0] = sm->curve[k][i];
      partner(sm->curve[o], s[o], sm->n[o], s[k][i], q + 1, q + 2, sm->w + p);
      /* the vertex's dual share of its curve, halved (both curves pair), scaled to L */
      double lo = i > 0 ? s[k][i] - s[k][i - 1] : 0.0, hi = i + 1 < n ? s[k][i + 1] - s[k][i] : 0.0;
      sm->len[p] = 0.25 * (lo + hi) * L; /* m */
    }
  }
  sw_free(s[0]);
  return 0;
}

/* ------------------------------------------------------------------ the term */

/* The partner point's coefficients c over (a, b0, b1) and the gap vector g of pair p; |g|. */
static double pair_gap(const sw_seam *sm, int p, const double *x, int d, double c[3], double *g) {
  const int *q = sm->pair + 3 * p;
  double g2 = 0.0;
  c[0] = 1.0, c[1] = -(1.0 - sm->w[p]), c[2] = -sm->w[p];
  for (int a = 0; a < d; a++) {
    g[a] = 0.0;
    for (int i = 0; i < 3; i++) g[a] += c[i] * x[(size_t)q[i] * d + a];
    g2 += g[a] * g[a];
  }
  return sqrt(g2);
}

/* The rest length of pair p at time t, m. */
static double pair_rest(const sw_model *m, const sw_seam *sm, int p, double t) {
  return sm->gap0 ? sm->gap0[p] * (1.0 - sw_ramp(t, m->seam_ramp)) : 0.0;
}

/* The Hessian block of one pair (3d x 3d, its upper triangle, each entry set once): kp c_i c_j [a (I - n n^T) + n n^T],
 * a = 1 - r/|g| filtered by `project`. */
static void pair_block(double kp, const double c[3], const double *g, double len, double r,
                       int d, int project, double *blk) {
  double a = len > 0.0 ? 1.0 - r / len : 1.0, n[3] = {0, 0, 0};
  a = sw_filter_eigenvalue(a, project);
  for (int q = 0; len > 0.0 && q < d; q++) n[q] = g[q] / len;
  double P[9]; /* a I + (1 - a) n n^T */
  for (int u = 0; u < d; u++)
    for (int v = 0; v < d; v++) P[u * d + v] = (u == v ? a : 0.0) + (1.0 - a) * n[u] * n[v];
  const int nb = 3 * d;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      for (int u = 0; u < d; u++)
        for (int v = 0; v < d; v++)
          sw_hess_set(blk, nb, i * d + u, j * d + v, kp * c[i] * c[j] * P[u * d + v]);
}

static int seam_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const int d = m->dim;
  double e = 0.0;
  long s = 0; /* stencil: one per pair, seams in order */
  for (int j = 0; j < m->nseam; j++) {
    const sw_seam *sm = &m->seam[j];
    for (int p = 0; p < sm->npair; p++, s++) {
      double c[3], g[3];
      const double len = pair_gap(sm, p, ev->x, d, c, g), r = pair_rest(m, sm, p, ev->t); /* m */
      const double kp = m->seam_stiffness * sm->len[p]; /* N/m */
      e += 0.5 * kp * (len - r) * (len - r); /* J */
      const int *q = sm->pair + 3 * p;
      const double f = len > 0.0 ? kp * (len - r) / len : kp; /* N/m: dE/dg = f g */
      for (int i = 0; ev->grad && i < 3; i++)
        for (int a = 0; a < d; a++) ev->grad[(size_t)q[i] * d + a] += f * c[i] * g[a]; /* N */
      if (!ev->hess) continue;
      double *blk = sw_ev_block(ev, t, s);
      pair_block(kp, c, g, len, r, d, ev->project, blk);
      sw_ev_block_done(ev, t, s, blk);
    }
  }
  *energy = e;
  return SW_OK;
}

static const sw_term_ops seam_ops = {.kind = "seams", .eval = seam_eval, .sets_blocks = 1,
                                     .sink_ok = 1};

int sw_seam_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  t->ops = &seam_ops;
  snprintf(t->name, sizeof t->name, "%s", "seams");
  int n = 0;
  for (int j = 0; j < m->nseam; j++) n += m->seam[j].npair;
  if (sw_term_alloc_stencils(t, n, 3, m->dim)) return sw_errf(err, errsz, "out of memory"), -1;
  for (int j = 0, s = 0; j < m->nseam; j++)
    for (int p = 0; p < m->seam[j].npair; p++, s++)
      memcpy(t->sidx + 3 * s, m->seam[j].pair + 3 * p, 3 * sizeof(int));
  return 0;
}

/* ------------------------------------------------------------------ sewn vertices */

/* Add the link (a, b) both ways to the counts (idx NULL) or the lists. */
static void link(int *ptr, int *fill, int *idx, int a, int b) {
  if (a == b) return;
  if (!idx) {
    ptr[a + 1]++, ptr[b + 1]++;
    return;
  }
  idx[ptr[a] + fill[a]++] = b;
  idx[ptr[b] + fill[b]++] = a;
}

/* The links of pair p: a with b0, b1 and their neighbours along their curve. */
static void pair_links(const sw_seam *sm, int k, int p, int *ptr, int *fill, int *idx) {
  const int *q = sm->pair + 3 * p, o = 1 - k, *c = sm->curve[o], n = sm->n[o];
  int j = 0;
  while (j < n && c[j] != q[1]) j++;
  for (int i = j - 1; i <= j + 2; i++)
    if (i >= 0 && i < n) link(ptr, fill, idx, q[0], c[i]);
}

/* Every link of the seams, each once per direction it is given: pass the pairs' links
 * (a with the points round its partner on the other curve) and, with `end` (the curves' end
 * vertices), the links through a junction: an end a sewn to an end b is also sewn to every
 * vertex b is sewn to.  add(a, c) is called for each; dp/di: the direct links (CSR), NULL on
 * the first pass. */
typedef struct links {
  int *ptr, *fill, *idx; /* CSR: counted (idx NULL), then filled */
} links;

static void links_add(links *l, int a, int b) { link(l->ptr, l->fill, l->idx, a, b); }

static void pair_links_all(const sw_model *m, links *l) {
  for (int j = 0; j < m->nseam; j++) {
    const sw_seam *sm = &m->seam[j];
    for (int p = 0; p < sm->npair; p++) pair_links(sm, p < sm->n[0] ? 0 : 1, p, l->ptr, l->fill, l->idx);
  }
}

/* Fill l (two passes: count, then fill) with the pairs' links and, when dl (the direct links)
 * and end are given, the junctions' (both ways); -1 out of memory. */
static int build_links(const sw_model *m, const links *dl, const unsigned char *end, links *l) {
  l->ptr = sw_calloc((size_t)m->nv + 1, sizeof(int)), l->fill = sw_calloc((size_t)m->nv + 1, sizeof(int));
  l->idx = NULL;
  if (!l->ptr || !l->fill) return -1;
  for (int pass = 0; pass < 2; pass++) {
    pair_links_all(m, l);
    for (int a = 0; dl && a < m->nv; a++)
      for (int k = dl->ptr[a]; end[a] && k < dl->ptr[a + 1]; k++) {
        int b = dl->idx[k];
        for (int q = dl->ptr[b]; end[b] && q < dl->ptr[b + 1]; q++)
          if (dl->idx[q] != a) links_add(l, a, dl->idx[q]);
      }
    if (pass) break;
    for (int i = 0; i < m->nv; i++) l->ptr[i + 1] += l->ptr[i];
    if (!(l->idx = sw_calloc((size_t)l->ptr[m->nv] + 1, sizeof(int)))) return -1;
  }
  sw_free(l->fill);
  l->fill = NULL;
  return 0;
}

static void links_free(links *l) { sw_free(l->ptr), sw_free(l->fill), sw_free(l->idx); }

/* The vertices sewn to each: the pairs' links and, where seams meet at a point (the ends of
 * their curves: the underarm of a T-shirt, where a sleeve's two edges, the front and the back
 * meet), the links of every curve end an end is sewn to, so that the pieces meeting there are
 * one point of the garment for self-contact, not layers held a thickness apart. */
int sw_seam_sewn(sw_model *m, char *err, size_t errsz) {
  if (m->nseam == 0) return 0;
  links dl = {0}, all = {0};
  unsigned char *end = sw_calloc((size_t)m->nv + 1, 1);
  int rc = !end || build_links(m, NULL, NULL, &dl) ? -1 : 0;
  for (int j = 0; !rc && j < m->nseam; j++)
    for (int k = 0; k < 2; k++)
      end[m->seam[j].curve[k][0]] = end[m->seam[j].curve[k][m->seam[j].n[k] - 1]] = 1;
  if (!rc) rc = build_links(m, &dl, end, &all);
  sw_free(end);
  links_free(&dl);
  if (rc) return links_free(&all), sw_errf(err, errsz, "out of memory"), -1;
  m->sewn_ptr = all.ptr, m->sewn_idx = all.idx;
  return 0;
}

/* ------------------------------------------------------------------ diagnostics */

/* The current length of curve k of a seam at x, m. */
static double curve_length(const sw_seam *sm, int k, const double *x, int d) {
  double L = 0.0;
  for (int i = 0; i + 1 < sm->n[k]; i++) {
    const double *a = x + (size_t)sm->curve[k][i] * d, *b = x + (size_t)sm->curve[k][i + 1] * d;
    double l2 = 0.0;
    for (int c = 0; c < d; c++) l2 += (b[c] - a[c]) * (b[c] - a[c]);
    L += sqrt(l2);
  }
  return L;
}

void sw_seam_state(const sw_model *m, sw_data *d) {
  const int dim = m->dim;
  d->seam_gap_max = 0.0;
  for (int j = 0; j < m->nseam; j++) {
    const sw_seam *sm = &m->seam[j];
    double gmax = 0.0, gsum = 0.0, f = 0.0;
    for (int p = 0; p < sm->npair; p++) {
      double c[3], g[3], gap = pair_gap(sm, p, d->x, dim, c, g); /* m */
      gmax = fmax(gmax, gap);
      gsum += gap;
      f += m->seam_stiffness * sm->len[p] * fabs(gap - pair_rest(m, sm, p, d->t)); /* N */
    }
    double *st = d->seam_state + 4 * j;
    st[0] = gmax;
    st[1] = sm->npair ? gsum / sm->npair : 0.0;
    st[2] = f;
    double la = curve_length(sm, 0, d->x, dim);
    st[3] = la > 0.0 ? curve_length(sm, 1, d->x, dim) / la : 0.0;
    d->seam_gap_max = fmax(d->seam_gap_max, gmax);
  }
}

int sw_seam_start(sw_model *m, char *err, size_t errsz) {
  for (int j = 0; j < m->nseam; j++) {
    sw_seam *sm = &m->seam[j];
    sw_free(sm->gap0);
    if (!(sm->gap0 = sw_calloc((size_t)sm->npair + 1, sizeof(double))))
      return sw_errf(err, errsz, "out of memory"), -1;
    for (int p = 0; p < sm->npair; p++) {
      double c[3], g[3];
      sm->gap0[p] = pair_gap(sm, p, m->x0, m->dim, c, g); /* m */
    }
  }
  return 0;
}

/* A material's tensile stiffness for the automatic seam stiffness, N/m: tension XY's (the
 * small-strain one), or for a measured fabric (dde) the largest its data reaches, 2 c11 or
 * 2 c22 of any row: a knit stiffens tenfold and more where it is stretched, as a garment's
 * fabric is beside its seams (docs/garments.md, `sewing`). */
static double seam_fabric_stiffness(const sw_material *mt) {
  double k = fmax(mt->tx_k_u, mt->tx_k_v);
  if (mt->membrane == SW_MEMBRANE_DDE)
    for (int r = 0; r < 6; r++)
      k = fmax(k, 2.0 * fmax(mt->dde.stretch[r][0], mt->dde.stretch[r][2]));
  return k;
}

double sw_seam_auto_stiffness(const sw_model *m) {
  double kmax = 0.0, h = 0.0; /* N/m, m */
  int ne = 0;
  for (int k = 0; k < m->nmat; k++) kmax = fmax(kmax, seam_fabric_stiffness(&m->mat[k]));
  for (int j = 0; j < m->nseam; j++)
    for (int k = 0; k < 2; k++) {
      h += m->seam[j].length[k];
      ne += m->seam[j].n[k] - 1;
    }
  h = ne > 0 ? h / ne : 1.0;
  return SW_SEAM_STIFFNESS_FACTOR * (kmax > 0.0 ? kmax : 1.0) / h; /* N/m^2 */
}
