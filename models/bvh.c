/* bvh.c — a bounding-volume hierarchy of axis-aligned boxes over a fixed set of primitives
 * (the triangles of the mesh obstacles), for the broad phase against large bodies:
 * a query costs the depth of the tree times the primitives near the box, not the body's size.
 *
 * Built once, top down: each node's primitives are split at the median of their boxes'
 * centres along the longest side of the centres' bounds (quickselect), down to leaves of at
 * most SW_BVH_LEAF primitives.  The left child takes the first multiple of SW_BVH_LEAF at or
 * above half its parent's primitives, so there are exactly ceil(n / leaf) leaves (2 ceil(n /
 * leaf) - 1 nodes) and the depth is about log2(n / leaf).
 * Children are stored after their parent, so a refit (new primitive boxes, same tree: a body
 * that moves) is one pass over the nodes from the last to the first (Ericson, "Real-Time
 * Collision Detection", 2005, sections 6.1-6.2 and 6.5).  Node boxes are single precision,
 * rounded outwards, so they always contain the double-precision boxes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cancel.h"
#include "contact_geom.h"
#include "sinew.h"
#include "util.h"

enum { SW_BVH_LEAF = 8, SW_BVH_DEPTH = 64 };

void sw_bvh_free(sw_bvh *t) {
  if (!t) return;
  sw_free(t->box);
  sw_free(t->node);
  sw_free(t->prim);
  sw_free(t->pbox);
  memset(t, 0, sizeof *t);
}

/* The centre of the box of prim[i] along axis a, quantised to 16 bits over the centres'
 * bounds (6 bytes a primitive while building: the split only orders them, the boxes are fitted
 * to the primitives themselves): c (n x 3) is kept in prim's order, so the passes over a node's
 * primitives read memory in sequence. */
typedef unsigned short sw_q16;
static int centre(const sw_q16 *c, int i, int a) { return c[3 * (size_t)i + a]; }

static void swap_prims(int *prim, sw_q16 *c, int i, int j) {
  int s = prim[i];
  prim[i] = prim[j], prim[j] = s;
  for (int a = 0; a < 3; a++) {
    sw_q16 f = c[3 * (size_t)i + a];
    c[3 * (size_t)i + a] = c[3 * (size_t)j + a], c[3 * (size_t)j + a] = f;
  }
}

/* Reorder prim[lo, hi) (and c) so that the element at k has its rank along axis a (Hoare's
 * quickselect with the middle element as pivot). */
static void select_k(int *prim, sw_q16 *c, int lo, int hi, int k, int a) {
  hi--;
  while (lo < hi) {
    int pv = centre(c, lo + (hi - lo) / 2, a);
    int i = lo, j = hi;
    while (i <= j) {
      while (centre(c, i, a) < pv) i++;
      while (centre(c, j, a) > pv) j--;
      if (i <= j) swap_prims(prim, c, i++, j--);
    }
    if (k <= j) hi = j;
    else if (k >= i) lo = i;
    else return;
  }
}

/* The axis along which the centres of prim[lo, hi) spread most. */
static int widest_axis(const sw_q16 *c, int lo, int hi) {
  int mn[3] = {65535, 65535, 65535}, mx[3] = {0, 0, 0};
  for (int i = lo; i < hi; i++)
    for (int a = 0; a < 3; a++) {
      int v = centre(c, i, a);
      mn[a] = v < mn[a] ? v : mn[a], mx[a] = v > mx[a] ? v : mx[a];
    }
  int best = 0;
  for (int a = 1; a < 3; a++)
    if (mx[a] - mn[a] > mx[best] - mn[best]) best = a;
  return best;
}

int sw_bvh_build(sw_bvh *t, int n, sw_bvh_box_fn box, const void *ctx) {
  memset(t, 0, sizeof *t);
  if (n <= 0) return 0;
  int cap = 2 * ((n + SW_BVH_LEAF - 1) / SW_BVH_LEAF); /* nodes: see the top */
  sw_q16 *c = sw_calloc(3 * (size_t)n, sizeof(sw_q16));
  t->prim = sw_calloc((size_t)n, sizeof(int));
  t->node = sw_calloc(2 * (size_t)cap, sizeof(int));
  t->box = sw_calloc(6 * (size_t)cap, sizeof(float));
  if (!c || !t->prim || !t->node || !t->box) return sw_free(c), sw_bvh_free(t), -1;
  t->n = n;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int pass = 0; pass < 2; pass++) /* the centres' bounds, then the centres */
    for (int i = 0; i < n; i++) {
      if ((i & 0xffff) == 0 && sw_cancelled()) return sw_free(c), sw_bvh_free(t), -2;
      double b[6];
      box(ctx, i, b);
      for (int a = 0; a < 3; a++) {
        double m = 0.5 * (b[a] + b[3 + a]), w = hi[a] - lo[a];
        if (pass == 0) lo[a] = m < lo[a] ? m : lo[a], hi[a] = m > hi[a] ? m : hi[a];
        else c[3 * (size_t)i + a] = (sw_q16)(w > 0.0 && m > lo[a] ? fmin(65535.0, 65535.0 * (m - lo[a]) / w) : 0.0);
      }
      t->prim[i] = i;
    }
  /* node k covers prim[lo, hi): (lo, hi) on a stack until it is split or made a leaf */
  int stack[2 * SW_BVH_DEPTH + 2][3], top = 0;
  t->nnode = 1;
  stack[top][0] = 0, stack[top][1] = 0, stack[top][2] = n, top++;
  while (top > 0) {
    top--;
    int k = stack[top][0], lo = stack[top][1], hi = stack[top][2];
    if (hi - lo > 65536 && sw_cancelled()) return sw_free(c), sw_bvh_free(t), -2;
    if (hi - lo <= SW_BVH_LEAF) {
      t->node[2 * k] = lo, t->node[2 * k + 1] = hi - lo;
      continue;
    }
    int mid = lo + SW_BVH_LEAF * ((hi - lo + 2 * SW_BVH_LEAF - 1) / (2 * SW_BVH_LEAF)), child = t->nnode;
    select_k(t->prim, c, lo, hi, mid, widest_axis(c, lo, hi));
    t->node[2 * k] = child, t->node[2 * k + 1] = 0;
    t->nnode += 2;
    stack[top][0] = child, stack[top][1] = lo, stack[top][2] = mid, top++;
    stack[top][0] = child + 1, stack[top][1] = mid, stack[top][2] = hi, top++;
  }
  sw_free(c);
  sw_bvh_refit(t, box, ctx);
  return 0;
}

/* b (double) into the float box f, rounded outwards. */
static void round_out(const double *b, float *f) {
  for (int a = 0; a < 3; a++) {
    float lo = (float)b[a], hi = (float)b[3 + a];
    if ((double)lo > b[a]) lo = nextafterf(lo, -INFINITY);
    if ((double)hi < b[3 + a]) hi = nextafterf(hi, INFINITY);
    f[a] = lo, f[3 + a] = hi;
  }
}

void sw_bvh_refit(sw_bvh *t, sw_bvh_box_fn box, const void *ctx) {
  for (int k = t->nnode - 1; k >= 0; k--) {
    float *f = t->box + 6 * (size_t)k;
    const int first = t->node[2 * k], count = t->node[2 * k + 1];
    if (count == 0) { /* internal: the union of its children's */
      const float *l = t->box + 6 * (size_t)first, *r = l + 6;
      for (int a = 0; a < 3; a++)
        f[a] = l[a] < r[a] ? l[a] : r[a], f[3 + a] = l[3 + a] > r[3 + a] ? l[3 + a] : r[3 + a];
      continue;
    }
    double u[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY}, s[6];
    for (int i = first; i < first + count; i++) {
      double *b = t->pbox ? t->pbox + 6 * (size_t)t->prim[i] : s;
      box(ctx, t->prim[i], b);
      for (int a = 0; a < 3; a++)
        u[a] = b[a] < u[a] ? b[a] : u[a], u[3 + a] = b[3 + a] > u[3 + a] ? b[3 + a] : u[3 + a];
    }
    round_out(u, f);
  }
}

int sw_bvh_keep_boxes(sw_bvh *t, sw_bvh_box_fn box, const void *ctx) {
  if (!t->pbox && t->n > 0 && !(t->pbox = sw_calloc(6 * (size_t)t->n, sizeof(double)))) return -1;
  sw_bvh_refit(t, box, ctx);
  return 0;
}

/* Whether node box f meets q, the query's box rounded outwards to floats: a node the query's
 * own box misses by less than a float's rounding is visited too, and its primitives are tested
 * against the query's own box. */
static int overlaps(const float *f, const float *q) {
  return f[0] <= q[3] && q[0] <= f[3] && f[1] <= q[4] && q[1] <= f[4] && f[2] <= q[5] &&
         q[2] <= f[5];
}

static int boxes_meet(const double *p, const double *q) {
  for (int a = 0; a < 3; a++)
    if (!(p[a] <= q[3 + a] && q[a] <= p[3 + a])) return 0;
  return 1;
}

int sw_bvh_query(const sw_bvh *t, const double b[6], sw_bvh_box_fn box, const void *ctx,
                 sw_bvh_hit_fn hit, void *arg) {
  if (t->nnode == 0) return 0;
  int stack[SW_BVH_DEPTH + 2], top = 0;
  float q[6];
  round_out(b, q);
  stack[top++] = 0;
  while (top > 0) {
    int k = stack[--top];
    if (!overlaps(t->box + 6 * (size_t)k, q)) continue;
    const int first = t->node[2 * k], count = t->node[2 * k + 1];
    if (count == 0) {
      stack[top++] = first, stack[top++] = first + 1;
      continue;
    }
    for (int i = first; i < first + count; i++) {
      double s[6];
      const double *pb = t->pbox ? t->pbox + 6 * (size_t)t->prim[i] : s;
      if (box && (t->pbox || (box(ctx, t->prim[i], s), 1)) && !boxes_meet(pb, b)) continue;
      int rc = hit(arg, t->prim[i]);
      if (rc) return rc;
    }
  }
  return 0;
}
