/* springs.c — a mass-spring network on the mesh (docs/models.md).
 *
 *   E = sum_s k_s/2 (|x_i - x_j| - L_s)^2        (k in N/m, lengths in m, E in J)
 *
 * over three kinds of spring, all from the mesh topology (models/topology.c):
 *   stretch: every edge except quad diagonals;
 *   shear:   both diagonals of every quad (a source polygon made of exactly two triangles: the
 *            edge they share is one diagonal, their far vertices the other);
 *   bend:    the far vertices of the two triangles across every interior edge that is not a
 *            quad diagonal.
 * Rest lengths come from the (u,v) layout: an edge's length is the mean of its length in each
 * adjacent face's layout (they differ only across a mismatched seam); a far-vertex pair's is
 * the distance with the two faces unfolded flat about the shared edge, each in its own layout.
 * The stiffness of a spring is the mean of ks_stretch / ks_shear / ks_bend over its adjacent
 * faces whose material has membrane SW_MEMBRANE_SPRINGS; a spring with no such face is not
 * made.  With n = (x_i - x_j)/l, l = |x_i - x_j|, the gradient is k (l - L) n at x_i and the
 * exact Hessian block is H = k n n^T + k (1 - L/l)(I - n n^T), [[H, -H], [-H, H]] on the pair;
 * in compression (l < L) the second coefficient is negative, and the eigenvalue filter
 * (SW_FILTER_*) clamps it at 0 or takes its absolute value, which leaves each block PSD. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "terms.h"
#include "util.h"

typedef struct spring {
  int i, j;      /* vertices */
  double L;      /* rest length, m */
  double k;      /* N/m */
  int kind;      /* SW_SPRING_* */
} spring;

typedef struct springs_param {
  int n;
  double *rest; /* (n) m */
  double *k;    /* (n) N/m */
  int count[3]; /* springs of each kind */
} springs_param;

static void springs_free(void *p) {
  springs_param *sp = p;
  if (!sp) return;
  sw_free(sp->rest);
  sw_free(sp->k);
  sw_free(sp);
}

/* Mean over the faces f[0..nf-1] that use springs of the kind's stiffness (N/m); 0 if none. */
static double spring_k(const sw_model *m, const int *f, int nf, int kind) {
  double sum = 0.0;
  int n = 0;
  for (int q = 0; q < nf; q++) {
    const sw_material *mt = &m->mat[m->face_mat[f[q]]];
    if (mt->membrane != SW_MEMBRANE_SPRINGS) continue;
    sum += kind == SW_SPRING_STRETCH ? mt->ks_stretch
           : kind == SW_SPRING_SHEAR ? mt->ks_shear
                                     : mt->ks_bend;
    n++;
  }
  return n ? sum / n : 0.0;
}

/* Number of faces of each source polygon (NULL when the model has no polygons). */
static int *polygon_sizes(const sw_model *m, int *fail) {
  *fail = 0;
  if (!m->face_poly) return NULL;
  int *cnt = sw_calloc((size_t)m->nf + 1, sizeof(int));
  if (!cnt) return *fail = 1, NULL;
  for (int f = 0; f < m->nf; f++)
    if (m->face_poly[f] >= 0 && m->face_poly[f] < m->nf) cnt[m->face_poly[f]]++;
  return cnt;
}

/* The springs that edge e makes (at most 2) into out; returns how many. */
static int edge_springs(const sw_model *m, const sw_topology *tp, const int *polysz, int e,
                        spring *out) {
  const int *f = tp->ef + 2 * e, nf = f[1] >= 0 ? 2 : 1;
  int p0 = m->face_poly ? m->face_poly[f[0]] : -1;
  int diag = nf == 2 && polysz && p0 >= 0 && p0 < m->nf && p0 == m->face_poly[f[1]] &&
             polysz[p0] == 2;
  double L = 0.0; /* the edge's rest length, m */
  for (int q = 0; q < nf; q++) L += sw_face_uv_distance(m, f[q], tp->ev[2 * e], tp->ev[2 * e + 1]);
  int kind = diag ? SW_SPRING_SHEAR : SW_SPRING_STRETCH, n = 0;
  double k = spring_k(m, f, nf, kind);
  if (k > 0.0) out[n++] = (spring){tp->ev[2 * e], tp->ev[2 * e + 1], L / nf, k, kind};
  if (nf < 2) return n;
  kind = diag ? SW_SPRING_SHEAR : SW_SPRING_BEND;
  k = spring_k(m, f, nf, kind);
  if (k > 0.0)
    out[n++] = (spring){tp->efar[2 * e], tp->efar[2 * e + 1], sw_edge_far_distance(m, tp, e), k,
                        kind};
  return n;
}

/* Count (fill == 0) or fill the springs from the topology. */
static int make_springs(sw_term *t, springs_param *sp, const sw_model *m, const sw_topology *tp,
                        const int *polysz, int fill) {
  int n = 0;
  for (int e = 0; e < tp->ne; e++) {
    spring s[2];
    int ns = edge_springs(m, tp, polysz, e, s);
    for (int q = 0; q < ns; q++, n++) {
      if (!fill) continue;
      t->sidx[2 * n] = s[q].i;
      t->sidx[2 * n + 1] = s[q].j;
      sp->rest[n] = s[q].L;
      sp->k[n] = s[q].k;
      sp->count[s[q].kind]++;
    }
  }
  return n;
}

/* k/2 (l - L)^2 of one spring: energy, gradient at x_i (d), the d x d block H (or NULL),
 * filtered by `project` (SW_FILTER_*). */
static double spring_eval(const double *xi, const double *xj, int d, double k, double L,
                          int project, double *g, double *H) {
  double n[3] = {1.0, 0.0, 0.0}, l = 0.0;
  for (int a = 0; a < d; a++) l += (xi[a] - xj[a]) * (xi[a] - xj[a]);
  l = sqrt(l);
  if (l > 0.0)
    for (int a = 0; a < d; a++) n[a] = (xi[a] - xj[a]) / l;
  for (int a = 0; a < d; a++) g[a] = k * (l - L) * n[a];
  if (H) {
    double perp = l > 0.0 ? k * (1.0 - L / l) : 0.0; /* N/m; negative in compression */
    if (project) perp = sw_filter_eigenvalue(perp, project);
    for (int a = 0; a < d; a++)
      for (int c = 0; c < d; c++) H[a * d + c] = k * n[a] * n[c] + perp * ((a == c) - n[a] * n[c]);
  }
  return 0.5 * k * (l - L) * (l - L);
}

static int springs_eval(const sw_term *t, const sw_model *m, const sw_eval *ev, double *energy) {
  const springs_param *sp = t->param;
  const int d = m->dim, w = 2 * d;
  double total = 0.0;
  for (int s = 0; s < sp->n; s++) {
    const int i = t->sidx[2 * s], j = t->sidx[2 * s + 1];
    double g[3], H[9];
    total += spring_eval(ev->x + (size_t)i * d, ev->x + (size_t)j * d, d, sp->k[s], sp->rest[s],
                         ev->project, g, ev->hess ? H : NULL);
    if (ev->grad)
      for (int a = 0; a < d; a++) {
        ev->grad[i * d + a] += g[a];
        ev->grad[j * d + a] -= g[a];
      }
    if (!ev->hess) continue;
    double *blk = sw_ev_block(ev, t, s);
    for (int a = 0; a < d; a++)
      for (int c = 0; c < d; c++) {
        sw_hess_set(blk, w, a, c, H[a * d + c]); /* every stored entry, once */
        sw_hess_set(blk, w, d + a, d + c, H[a * d + c]);
        sw_hess_set(blk, w, a, d + c, -H[a * d + c]);
      }
    sw_ev_block_done(ev, t, s, blk);
  }
  *energy = total;
  return isfinite(total) ? SW_OK : SW_RECOVER;
}

static const sw_term_ops springs_ops = {
    .kind = "springs", .eval = springs_eval, .free_param = springs_free, .sets_blocks = 1,
    .sink_ok = 1};

void sw_springs_counts(const sw_term *t, int count[3]) {
  const springs_param *sp = t->param;
  for (int k = 0; k < 3; k++) count[k] = sp ? sp->count[k] : 0;
}

int sw_springs_build(sw_term *t, const sw_model *m, char *err, size_t errsz) {
  springs_param *sp = sw_calloc(1, sizeof *sp);
  t->ops = &springs_ops;
  t->param = sp;
  snprintf(t->name, sizeof t->name, "%s", "springs");
  if (!sp) return sw_errf(err, errsz, "out of memory"), -1;
  sw_topology tp;
  if (sw_topology_build(&tp, m, err, errsz)) return -1;
  int fail, *polysz = polygon_sizes(m, &fail);
  int rc = -1;
  if (fail) goto done;
  sp->n = make_springs(t, sp, m, &tp, polysz, 0);
  sp->rest = sw_calloc((size_t)sp->n, sizeof(double));
  sp->k = sw_calloc((size_t)sp->n, sizeof(double));
  if (!sp->rest || !sp->k || sw_term_alloc_stencils(t, sp->n, 2, m->dim)) goto done;
  make_springs(t, sp, m, &tp, polysz, 1);
  rc = 0;
done:
  if (rc) sw_errf(err, errsz, "out of memory for the springs");
  sw_free(polysz);
  sw_topology_free(&tp);
  return rc;
}
