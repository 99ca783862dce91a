/* topology.c — mesh edges for the edge-based terms (springs, dihedral, quadratic bending):
 * unique edges by vertex pair, the faces on each side of an edge, their far vertices, and the
 * rest (u,v) measurements those terms share.  Built once at set-up; not used in a step. */
#include <math.h>
#include <stdlib.h>

#include "terms.h"
#include "util.h"

typedef struct half_edge {
  int a, b;   /* vertex pair, a < b */
  int f;      /* face */
  int far;    /* the face's vertex opposite the edge */
} half_edge;

static int half_cmp(const void *p, const void *q) {
  const half_edge *x = p, *y = q;
  if (x->a != y->a) return x->a < y->a ? -1 : 1;
  if (x->b != y->b) return x->b < y->b ? -1 : 1;
  return (x->f > y->f) - (x->f < y->f);
}

void sw_topology_free(sw_topology *tp) {
  if (!tp) return;
  sw_free(tp->ev);
  sw_free(tp->ef);
  sw_free(tp->efar);
  tp->ev = tp->ef = tp->efar = NULL;
  tp->ne = 0;
}

/* One group of equal half-edges (run of length n starting at h) becomes edge e. */
static void put_edge(sw_topology *tp, int e, const half_edge *h, int n) {
  tp->ev[2 * e] = h->a;
  tp->ev[2 * e + 1] = h->b;
  tp->ef[2 * e] = h->f;
  tp->efar[2 * e] = h->far;
  tp->ef[2 * e + 1] = tp->efar[2 * e + 1] = -1;
  if (n == 2) {
    tp->ef[2 * e + 1] = h[1].f;
    tp->efar[2 * e + 1] = h[1].far;
  }
  if (n > 2) tp->nonmanifold++;
}

int sw_topology_build(sw_topology *tp, const sw_model *m, char *err, size_t errsz) {
  size_t nh = 3 * (size_t)m->nf;
  half_edge *h = sw_calloc(nh, sizeof *h);
  *tp = (sw_topology){0};
  if (!h) return sw_errf(err, errsz, "out of memory for the edges of %d faces", m->nf), -1;
  for (int f = 0; f < m->nf; f++)
    for (int i = 0; i < 3; i++) {
      int va = m->face[3 * f + (i + 1) % 3], vb = m->face[3 * f + (i + 2) % 3];
      h[3 * f + i] = (half_edge){SW_MIN(va, vb), SW_MAX(va, vb), f, m->face[3 * f + i]};
    }
  qsort(h, nh, sizeof *h, half_cmp);
  int ne = 0;
  for (size_t k = 0; k < nh; k++) ne += k == 0 || h[k - 1].a != h[k].a || h[k - 1].b != h[k].b;
  tp->ev = sw_calloc((size_t)ne, 2 * sizeof(int));
  tp->ef = sw_calloc((size_t)ne, 2 * sizeof(int));
  tp->efar = sw_calloc((size_t)ne, 2 * sizeof(int));
  if (!tp->ev || !tp->ef || !tp->efar) {
    sw_free(h);
    sw_topology_free(tp);
    return sw_errf(err, errsz, "out of memory for %d edges", ne), -1;
  }
  for (size_t k = 0; k < nh;) {
    size_t n = 1;
    while (k + n < nh && h[k + n].a == h[k].a && h[k + n].b == h[k].b) n++;
    put_edge(tp, tp->ne++, h + k, (int)n);
    k += n;
  }
  sw_free(h);
  return 0;
}

/* Local corner (0..2) of vertex v in face f, or -1. */
static int corner(const sw_model *m, int f, int v) {
  for (int i = 0; i < 3; i++)
    if (m->face[3 * f + i] == v) return i;
  return -1;
}

double sw_face_uv_distance(const sw_model *m, int f, int va, int vb) {
  const double *p = m->uv + 6 * f + 2 * corner(m, f, va), *q = m->uv + 6 * f + 2 * corner(m, f, vb);
  return hypot(q[0] - p[0], q[1] - p[1]);
}

/* In face f's own (u,v): the far vertex c's distance along the edge a->b from a, and its
 * (unsigned) height above the edge, m. */
static void far_coords(const sw_model *m, int f, int a, int b, int c, double *s, double *hgt) {
  const double *pa = m->uv + 6 * f + 2 * corner(m, f, a), *pb = m->uv + 6 * f + 2 * corner(m, f, b);
  const double *pc = m->uv + 6 * f + 2 * corner(m, f, c);
  double e[2] = {pb[0] - pa[0], pb[1] - pa[1]}, w[2] = {pc[0] - pa[0], pc[1] - pa[1]};
  double l = hypot(e[0], e[1]);
  *s = l > 0.0 ? (e[0] * w[0] + e[1] * w[1]) / l : 0.0;
  *hgt = l > 0.0 ? fabs(e[0] * w[1] - e[1] * w[0]) / l : hypot(w[0], w[1]);
}

double sw_edge_far_distance(const sw_model *m, const sw_topology *tp, int e) {
  const int a = tp->ev[2 * e], b = tp->ev[2 * e + 1];
  double s0, h0, s1, h1;
  far_coords(m, tp->ef[2 * e], a, b, tp->efar[2 * e], &s0, &h0);
  far_coords(m, tp->ef[2 * e + 1], a, b, tp->efar[2 * e + 1], &s1, &h1);
  /* unfolded flat about the edge: the far vertices lie on opposite sides */
  return hypot(s1 - s0, h0 + h1);
}
