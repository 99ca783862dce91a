/* broadphase.c — candidate contact pairs from a uniform grid hashed by integer cell
 * (Teschner, Heidelberger, Mueller, Pomeranets, Gross, "Optimized Spatial Hashing for Collision
 * Detection of Deformable Objects", VMV 2003), with the cell coordinates packed into a 63-bit
 * key (an injective hash) and the entries radix-sorted by key instead of chained in buckets.
 *
 * Each primitive's box is that of its vertices at the start and end of the step, enlarged by
 * the inflation radius; a primitive goes into every cell its box covers.  The cell size is the
 * mean box size of the edges and faces (doubled while the entries would exceed 16 per
 * primitive), so the work grows with the number of primitives and of nearby pairs.  A pair
 * found in several cells is reported only in the cell holding the lower corner of its boxes'
 * overlap, so exactly once, with no set of pairs seen. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "contact_geom.h"

enum { KIND_V = 0, KIND_E = 1, KIND_F = 2 };
enum { CELL_BITS = 21 }; /* per axis: the key is 63 bits */
#define CELL_MAX ((1LL << CELL_BITS) - 1)

void sw_broadphase_init(sw_broadphase *bp) { memset(bp, 0, sizeof *bp); }

void sw_broadphase_free(sw_broadphase *bp) {
  free(bp->pt), free(bp->ee), free(bp->ff), free(bp->box);
  free(bp->key), free(bp->key2), free(bp->code), free(bp->code2), free(bp->grp);
  sw_broadphase_init(bp);
}

/* Make *p hold at least need elements of size sz (capacity *cap, grown by half again). */
static int reserve(void **p, size_t *cap, size_t need, size_t sz) {
  if (need <= *cap) return 0;
  size_t n = need + need / 2 + 16;
  void *q = realloc(*p, n * sz);
  if (!q) return -1;
  *p = q, *cap = n;
  return 0;
}

static int reserve_entries(sw_broadphase *bp, size_t need) {
  if (need <= bp->cap_ent) return 0;
  size_t c[4] = {bp->cap_ent, bp->cap_ent, bp->cap_ent, bp->cap_ent};
  if (reserve((void **)&bp->key, &c[0], need, sizeof *bp->key) ||
      reserve((void **)&bp->key2, &c[1], need, sizeof *bp->key2) ||
      reserve((void **)&bp->code, &c[2], need, sizeof *bp->code) ||
      reserve((void **)&bp->code2, &c[3], need, sizeof *bp->code2))
    return -1;
  bp->cap_ent = c[0];
  return 0;
}

/* ---------------------------------------------------------------------------------- boxes */

static void box_of_vertex(const sw_bp_input *in, int v, double *b) {
  for (int a = 0; a < 3; a++) {
    double p = in->x0[3 * v + a], q = in->x1[3 * v + a];
    b[a] = fmin(p, q) - in->inflate, b[3 + a] = fmax(p, q) + in->inflate;
  }
}

static void box_union(const double *vbox, const int *vert, int n, double *b) {
  memcpy(b, vbox + 6 * vert[0], 6 * sizeof(double));
  for (int k = 1; k < n; k++)
    for (int a = 0; a < 3; a++) {
      b[a] = fmin(b[a], vbox[6 * vert[k] + a]);
      b[3 + a] = fmax(b[3 + a], vbox[6 * vert[k] + 3 + a]);
    }
}

/* All boxes (vertices, then edges, then faces); -1 when a coordinate is not finite or an
 * index is out of range. */
static int make_boxes(sw_broadphase *bp, const sw_bp_input *in) {
  double *b = bp->box;
  for (int v = 0; v < in->nv; v++) {
    box_of_vertex(in, v, b + 6 * v);
    for (int a = 0; a < 6; a++)
      if (!isfinite(b[6 * v + a])) return -1;
  }
  for (int i = 0; i < 2 * in->ne; i++)
    if (in->edge[i] < 0 || in->edge[i] >= in->nv) return -1;
  for (int i = 0; i < 3 * in->nf; i++)
    if (in->face[i] < 0 || in->face[i] >= in->nv) return -1;
  for (int e = 0; e < in->ne; e++) box_union(b, in->edge + 2 * e, 2, b + 6 * (in->nv + e));
  for (int f = 0; f < in->nf; f++) box_union(b, in->face + 3 * f, 3, b + 6 * (in->nv + in->ne + f));
  return 0;
}

/* ---------------------------------------------------------------------------------- grid */

typedef struct grid {
  double lo[3], h; /* origin and spacing, m */
  int bits[3];     /* key bits of each cell coordinate (at most CELL_BITS) */
  int first[3], count[3]; /* the primitives of each kind in the grid: box indices */
} grid;

static long long cell_of(const grid *G, double x, int a) {
  return (long long)floor((x - G->lo[a]) / G->h);
}

/* Cells a box covers (as a double: it may be huge before the spacing is adjusted). */
static double cells_of(const grid *G, const double *b) {
  double n = 1.0;
  for (int a = 0; a < 3; a++) n *= (double)(cell_of(G, b[3 + a], a) - cell_of(G, b[a], a) + 1);
  return n;
}

static double total_cells(const grid *G, const double *box) {
  double n = 0.0;
  for (int k = 0; k < 3; k++)
    for (int i = G->first[k]; i < G->first[k] + G->count[k]; i++) n += cells_of(G, box + 6 * i);
  return n;
}

/* Origin and spacing: the mean largest box side of the edges and faces in the grid, at least
 * the extent / 2^21 (so cell coordinates fit the key), doubled while there would be more than
 * 16 entries per primitive.  The number of entries in *nent. */
static void plan_grid(grid *G, const double *box, size_t *nent) {
  double hi[3] = {-INFINITY, -INFINITY, -INFINITY}, sum = 0.0, ext = 0.0;
  long nbig = 0, nprim = 0;
  for (int a = 0; a < 3; a++) G->lo[a] = INFINITY;
  for (int k = 0; k < 3; k++)
    for (int i = G->first[k]; i < G->first[k] + G->count[k]; i++, nprim++) {
      const double *b = box + 6 * i;
      double side = 0.0;
      for (int a = 0; a < 3; a++) {
        G->lo[a] = fmin(G->lo[a], b[a]), hi[a] = fmax(hi[a], b[3 + a]);
        side = fmax(side, b[3 + a] - b[a]);
      }
      if (k != KIND_V) sum += side, nbig++;
    }
  for (int a = 0; a < 3; a++) ext = fmax(ext, hi[a] - G->lo[a]);
  G->h = nbig ? sum / nbig : 0.0;
  G->h = fmax(G->h, ext / (double)(CELL_MAX - 1));
  if (!(G->h > 0.0)) G->h = 1.0;
  double n;
  while ((n = total_cells(G, box)) > 16.0 * nprim + 1024.0) G->h *= 2.0;
  *nent = (size_t)n;
  for (int a = 0; a < 3; a++) /* as few key bits as the cells need: fewer sorting passes */
    for (G->bits[a] = 1; G->bits[a] < CELL_BITS && (cell_of(G, hi[a], a) >> G->bits[a]);) G->bits[a]++;
}

static void put_entries(sw_broadphase *bp, const grid *G) {
  size_t m = 0;
  for (int k = 0; k < 3; k++)
    for (int i = G->first[k]; i < G->first[k] + G->count[k]; i++) {
      const double *b = bp->box + 6 * i;
      long long c0[3], c1[3];
      for (int a = 0; a < 3; a++) c0[a] = cell_of(G, b[a], a), c1[a] = cell_of(G, b[3 + a], a);
      for (long long x = c0[0]; x <= c1[0]; x++)
        for (long long y = c0[1]; y <= c1[1]; y++)
          for (long long z = c0[2]; z <= c1[2]; z++) {
            bp->key[m] = ((unsigned long long)x << G->bits[1] | (unsigned long long)y) << G->bits[2] |
                         (unsigned long long)z;
            bp->code[m++] = 3 * (i - G->first[k]) + k;
          }
    }
}

/* LSD radix sort of the m entries by their nbits-bit keys, 11 bits a pass. */
enum { RADIX = 11 };
static void sort_entries(sw_broadphase *bp, size_t m, int nbits) {
  const unsigned long long mask = (1ULL << RADIX) - 1;
  for (int shift = 0; shift < nbits; shift += RADIX) {
    size_t cnt[(1 << RADIX) + 1] = {0};
    for (size_t i = 0; i < m; i++) cnt[((bp->key[i] >> shift) & mask) + 1]++;
    for (int d = 0; d < 1 << RADIX; d++) cnt[d + 1] += cnt[d];
    for (size_t i = 0; i < m; i++) {
      size_t j = cnt[(bp->key[i] >> shift) & mask]++;
      bp->key2[j] = bp->key[i], bp->code2[j] = bp->code[i];
    }
    unsigned long long *tk = bp->key;
    int *tc = bp->code;
    bp->key = bp->key2, bp->key2 = tk, bp->code = bp->code2, bp->code2 = tc;
  }
}

/* ---------------------------------------------------------------------------------- pairs */

typedef struct cell_ctx {
  const sw_bp_input *in;
  const grid *G;
  long long c[3];          /* the cell's coordinates */
} cell_ctx;

/* A primitive of the cell being paired: its box, its index, and along which axes its box
 * starts in this cell (bit a).  The cell of the lower corner of two boxes' overlap is, axis by
 * axis, the later of their starting cells, so this cell owns the pair iff every axis has a box
 * starting in it: (mask_p | mask_q) == 7. */
struct sw_bp_entry {
  double b[6];
  int idx, mask;
};
typedef struct sw_bp_entry entry;

static int boxes_overlap(const double *p, const double *q) {
  for (int a = 0; a < 3; a++)
    if (p[a] > q[3 + a] || q[a] > p[3 + a]) return 0;
  return 1;
}

/* Vertex a is sewn to b (models/seam.c). */
static int sewn(const sw_bp_input *in, int a, int b) {
  if (!in->sewn_ptr || a >= in->nsewn || b >= in->nsewn) return 0;
  for (int k = in->sewn_ptr[a]; k < in->sewn_ptr[a + 1]; k++) if (in->sewn_idx[k] == b) return 1;
  return 0;
}

/* Vertices u (nu) and w (nw) share (or sew) one, or are all fixed. */
static int skip_pair(const sw_bp_input *in, const int *u, int nu, const int *w, int nw) {
  int fixed = in->fixed != NULL;
  for (int i = 0; i < nu; i++) {
    fixed = fixed && in->fixed[u[i]];
    for (int j = 0; j < nw; j++) if (u[i] == w[j] || sewn(in, u[i], w[j])) return 1;
  }
  for (int j = 0; j < nw; j++) fixed = fixed && in->fixed[w[j]];
  return fixed;
}

static int push_pair(int **arr, size_t *cap, int *n, int a, int b) {
  if (reserve((void **)arr, cap, 2 * ((size_t)*n + 1), sizeof(int))) return -1;
  (*arr)[2 * *n] = a, (*arr)[2 * *n + 1] = b;
  (*n)++;
  return 0;
}

/* The vertices of primitive i of kind k into v; their number. */
static int verts_of(const sw_bp_input *in, int k, int i, int *v) {
  if (k == KIND_V) {
    v[0] = i;
    return 1;
  }
  const int *s = k == KIND_E ? in->edge + 2 * i : in->face + 3 * i;
  for (int j = 0; j <= k; j++) v[j] = s[j];
  return k + 1;
}

/* Report the pairs of one cell between the primitives A (na, kind ka) and B (nb, kind kb):
 * vertex-face, edge-edge or face-face by ka; same = A is B (each pair once, lower index
 * first). */
static int pair_lists(sw_broadphase *bp, const cell_ctx *C, int ka, const entry *A, int na,
                      int kb, const entry *B, int nb, int same) {
  for (int i = 0; i < na; i++)
    for (int j = same ? i + 1 : 0; j < nb; j++) {
      if ((A[i].mask | B[j].mask) != 7 || !boxes_overlap(A[i].b, B[j].b)) continue;
      int a = A[i].idx, b = B[j].idx, u[3], w[3];
      if (same && a > b) a = B[j].idx, b = A[i].idx;
      int nu = verts_of(C->in, ka, a, u), nw = verts_of(C->in, kb, b, w);
      if (skip_pair(C->in, u, nu, w, nw)) continue;
      int rc = ka == KIND_V   ? push_pair(&bp->pt, &bp->cap_pt, &bp->npt, a, b)
               : ka == KIND_E ? push_pair(&bp->ee, &bp->cap_ee, &bp->nee, a, b)
                              : push_pair(&bp->ff, &bp->cap_ff, &bp->nff, a, b);
      if (rc) return -1;
    }
  return 0;
}

/* The pairs of the cell whose entries are [i, j) of the sorted list: its primitives gathered
 * by kind with their boxes, then paired. */
static int pair_cell(sw_broadphase *bp, cell_ctx *C, size_t i, size_t j, int want) {
  int n[3] = {0, 0, 0};
  entry *list[3];
  const int *bits = C->G->bits;
  unsigned long long key = bp->key[i];
  C->c[2] = (long long)(key & ((1ULL << bits[2]) - 1)), key >>= bits[2];
  C->c[1] = (long long)(key & ((1ULL << bits[1]) - 1)), C->c[0] = (long long)(key >> bits[1]);
  for (size_t e = i; e < j; e++) n[bp->code[e] % 3]++;
  list[0] = bp->grp, list[1] = list[0] + n[0], list[2] = list[1] + n[1];
  n[0] = n[1] = n[2] = 0;
  for (size_t e = i; e < j; e++) {
    int k = bp->code[e] % 3;
    entry *t = &list[k][n[k]++];
    t->idx = bp->code[e] / 3;
    memcpy(t->b, bp->box + 6 * (C->G->first[k] + t->idx), sizeof t->b);
    t->mask = 0;
    for (int a = 0; a < 3; a++) t->mask |= (cell_of(C->G, t->b[a], a) == C->c[a]) << a;
  }
  if ((want & SW_BP_PT) && pair_lists(bp, C, KIND_V, list[0], n[0], KIND_F, list[2], n[2], 0))
    return -1;
  if ((want & SW_BP_EE) && pair_lists(bp, C, KIND_E, list[1], n[1], KIND_E, list[1], n[1], 1))
    return -1;
  if ((want & SW_BP_FF) && pair_lists(bp, C, KIND_F, list[2], n[2], KIND_F, list[2], n[2], 1))
    return -1;
  return 0;
}

static int pair_cells(sw_broadphase *bp, const sw_bp_input *in, const grid *G, size_t m,
                      int want) {
  cell_ctx C = {in, G, {0, 0, 0}};
  for (size_t i = 0, j; i < m; i = j) {
    for (j = i + 1; j < m && bp->key[j] == bp->key[i];) j++;
    if (reserve((void **)&bp->grp, &bp->cap_grp, j - i, sizeof(entry)) ||
        pair_cell(bp, &C, i, j, want))
      return -1;
  }
  return 0;
}

int sw_broadphase_query(sw_broadphase *bp, const sw_bp_input *in, int want) {
  bp->npt = bp->nee = bp->nff = 0;
  if (in->nv < 0 || in->ne < 0 || in->nf < 0) return -1;
  size_t nbox = (size_t)in->nv + (size_t)in->ne + (size_t)in->nf, m;
  if (reserve((void **)&bp->box, &bp->cap_box, 6 * nbox, sizeof(double)) || make_boxes(bp, in))
    return -1;
  int pt = (want & SW_BP_PT) && in->nf > 0; /* kinds with something to pair */
  grid G = {.first = {0, in->nv, in->nv + in->ne},
            .count = {pt ? in->nv : 0, (want & SW_BP_EE) && in->ne > 1 ? in->ne : 0,
                      pt || ((want & SW_BP_FF) && in->nf > 1) ? in->nf : 0}};
  if (G.count[0] + G.count[1] + G.count[2] == 0) return 0;
  plan_grid(&G, bp->box, &m);
  bp->cell = G.h;
  if (reserve_entries(bp, m)) return -1;
  put_entries(bp, &G);
  sort_entries(bp, m, G.bits[0] + G.bits[1] + G.bits[2]);
  if (pair_cells(bp, in, &G, m, want)) {
    bp->npt = bp->nee = bp->nff = 0;
    return -1;
  }
  return 0;
}

/* ------------------------------------------------------------------------- marked pairs */

/* Whether primitive i of kind k has a marked vertex. */
static int touches(const sw_bp_input *in, const unsigned char *mark, int k, int i) {
  int v[3], n = verts_of(in, k, i, v);
  for (int j = 0; j < n; j++)
    if (mark[v[j]]) return 1;
  return 0;
}

/* Pair primitive a of kind ka with every primitive of kind kb whose box meets its own, as
 * pair_lists does; b_marked: also those of kb that touch a marked vertex (else they are
 * left to their own turn), and for ka == kb only those above a. */
static int pair_one(sw_broadphase *bp, const sw_bp_input *in, const unsigned char *mark,
                    int ka, int a, int kb, int first_b, int nb, int b_marked) {
  const double *ba = bp->box + 6 * ((ka == KIND_V ? 0 : ka == KIND_E ? in->nv : in->nv + in->ne) + a);
  int u[3], w[3], nu = verts_of(in, ka, a, u);
  for (int b = 0; b < nb; b++) {
    if (!boxes_overlap(ba, bp->box + 6 * (first_b + b))) continue;
    if (ka == kb ? b <= a && touches(in, mark, kb, b) : !b_marked && touches(in, mark, kb, b))
      continue; /* found from b's side */
    int nw = verts_of(in, kb, b, w);
    if (skip_pair(in, u, nu, w, nw)) continue;
    int lo = ka == kb && b < a ? b : a, hi = ka == kb && b < a ? a : b;
    int rc = ka == KIND_V ? push_pair(&bp->pt, &bp->cap_pt, &bp->npt, lo, hi)
                          : push_pair(&bp->ee, &bp->cap_ee, &bp->nee, lo, hi);
    if (rc) return -1;
  }
  return 0;
}

int sw_broadphase_query_marked(sw_broadphase *bp, const sw_bp_input *in, int want,
                               const unsigned char *mark) {
  bp->npt = bp->nee = bp->nff = 0;
  if (in->nv < 0 || in->ne < 0 || in->nf < 0 || (want & SW_BP_FF)) return -1;
  size_t nbox = (size_t)in->nv + (size_t)in->ne + (size_t)in->nf;
  if (reserve((void **)&bp->box, &bp->cap_box, 6 * nbox, sizeof(double)) || make_boxes(bp, in))
    return -1;
  int fe = in->nv, ff = in->nv + in->ne, rc = 0;
  for (int v = 0; !rc && (want & SW_BP_PT) && v < in->nv; v++) /* a marked vertex, any face */
    if (mark[v]) rc = pair_one(bp, in, mark, KIND_V, v, KIND_F, ff, in->nf, 1);
  for (int f = 0; !rc && (want & SW_BP_PT) && f < in->nf; f++) /* a marked face, the others */
    if (touches(in, mark, KIND_F, f)) {
      const double *bf = bp->box + 6 * (ff + f);
      int w[3], nw = verts_of(in, KIND_F, f, w);
      for (int v = 0; !rc && v < in->nv; v++) {
        if (mark[v] || !boxes_overlap(bp->box + 6 * v, bf) || skip_pair(in, &v, 1, w, nw))
          continue;
        rc = push_pair(&bp->pt, &bp->cap_pt, &bp->npt, v, f);
      }
    }
  for (int e = 0; !rc && (want & SW_BP_EE) && e < in->ne; e++)
    if (touches(in, mark, KIND_E, e)) rc = pair_one(bp, in, mark, KIND_E, e, KIND_E, fe, in->ne, 0);
  if (rc) bp->npt = bp->nee = 0;
  return rc ? -1 : 0;
}
