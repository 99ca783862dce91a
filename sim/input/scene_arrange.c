/* scene_arrange.c — the key `arrange` (docs/garments.md): each flat piece of the pattern (an
 * OBJ group whose vertices no other group uses) placed around the body from its (u,v) layout,
 * so the user never computes 3D coordinates:
 *
 *   arrange:
 *     front: {cylinder: {angle: 90, top: 1.0, clearance: 0.03, center: [0, 0]}}
 *     back:  {cylinder: {angle: 270, top: 1.0, radius: 0.2}}
 *     sleeve: {cylinder: {top: 0, clearance: 0.02, axis: [-1, 0, 1], center: [0.2, 0, 1.37]}}
 *     panel: {cylinder: {angle: 45, top: 1.05, clearance: 0.03, up: u}}
 *     yoke:  {rigid: {rotate: [90, 0, 0], translate: [0, 0.2, 1.1]}}
 *
 * The piece's reference point is the middle of its (u,v) extent across (u) at its top (the
 * largest v).  cylinder: wrapped without stretch onto the cylinder of that radius about the
 * axis (default vertical) through center (x, y for a vertical axis, else x, y, z; default the
 * origin), u going round anticlockwise seen from the axis's tip, v along the axis; the
 * reference point at `angle` (degrees from e1, +x's part across the axis, towards e2 = axis x
 * e1) and at `top` along the axis from center (for a vertical axis, the height).  `clearance`
 * instead of `radius`: the radius is the largest distance from the axis of a mesh obstacle's
 * vertex over the piece's range along the axis (widened by the clearance), on the closed
 * surfaces that hold the axis's point at the middle of that range, plus the clearance.  `up: u`
 * (a piece imported with u along its grain line, which runs down the body): u along the axis
 * and -v round instead (the reference point then the middle of its -v extent at its largest
 * u), so that the cloth's normal u x v still points away from the axis.  rigid:
 * the flat piece (u, v, 0) rotated about x, then y, then z by `rotate` (degrees) and moved so
 * that its reference point is at `translate` (m).
 * Checked exactly (models/intersect.c): no arranged piece may cross or lie inside a mesh
 * obstacle, or cross another piece. */
#include "contact.h"
#include "contact_geom.h"
#include "scene_material.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define ARR_PI 3.14159265358979323846

/* A piece: its vertices (mark[i] = 1), one (u,v) per vertex, its extent. */
typedef struct piece {
  int g;                /* OBJ group */
  double umid, vtop, vbot, width; /* m */
} piece;

/* Mark the vertices of group g and take their (u,v) (uvv: nv x 2); -1 with the message when
 * another group's face shares one of them. */
static int piece_of(const ctx *c, const ynode *at, const char *name, int g, unsigned char *mark,
                    double *uvv, piece *pc) {
  const sw_model *m = c->m;
  double umin = HUGE_VAL, umax = -HUGE_VAL;
  pc->g = g, pc->vtop = -HUGE_VAL, pc->vbot = HUGE_VAL;
  memset(mark, 0, (size_t)m->nv);
  for (int f = 0; f < m->nf; f++)
    for (int i = 0; c->fgroup[f] == g && i < 3; i++) {
      int v = m->face[3 * f + i];
      const double *uv = m->uv + 6 * f + 2 * i;
      mark[v] = 1;
      uvv[2 * v] = uv[0], uvv[2 * v + 1] = uv[1];
      umin = fmin(umin, uv[0]), umax = fmax(umax, uv[0]);
      pc->vtop = fmax(pc->vtop, uv[1]), pc->vbot = fmin(pc->vbot, uv[1]);
    }
  for (int f = 0; f < m->nf; f++)
    for (int i = 0; c->fgroup[f] != g && i < 3; i++)
      if (mark[m->face[3 * f + i]])
        return sy_fail(c, at, "arrange %s: vertex %d of the piece is also in group %s; expected a "
                       "separate piece (sew pieces with seams, not shared vertices)", name,
                       m->face[3 * f + i], c->group[c->fgroup[f]]);
  pc->umid = 0.5 * (umin + umax);
  pc->width = umax - umin;
  return 0;
}

/* A cylinder's frame: a point on the axis, the axis e3 (unit), and e1, e2 spanning the plane
 * across it (e1 along +x's part across the axis, or +y's when the axis is nearly x; e2 = e3 x
 * e1), so that a vertical axis has e1 = +x, e2 = +y as before. */
typedef struct cyl_frame {
  double c[3], e1[3], e2[3], e3[3]; /* m; unit vectors */
} cyl_frame;

static void cross3(const double *a, const double *b, double *o) {
  o[0] = a[1] * b[2] - a[2] * b[1];
  o[1] = a[2] * b[0] - a[0] * b[2];
  o[2] = a[0] * b[1] - a[1] * b[0];
}

static void frame_of(const double *ctr, const double *axis, cyl_frame *f) {
  double n = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (int a = 0; a < 3; a++) f->c[a] = ctr[a], f->e3[a] = axis[a] / n;
  double ref[3] = {1, 0, 0};
  if (fabs(f->e3[0]) > 0.9) ref[0] = 0.0, ref[1] = 1.0;
  double d = ref[0] * f->e3[0] + ref[1] * f->e3[1] + ref[2] * f->e3[2], len = 0.0;
  for (int a = 0; a < 3; a++) f->e1[a] = ref[a] - d * f->e3[a], len += f->e1[a] * f->e1[a];
  for (int a = 0; a < 3; a++) f->e1[a] /= sqrt(len);
  cross3(f->e3, f->e1, f->e2);
}

/* p's coordinate along the axis and its distance from it, m. */
static void axial(const cyl_frame *f, const double *p, double *s, double *r) {
  double q[3], t = 0.0, r2 = 0.0;
  for (int a = 0; a < 3; a++) q[a] = p[a] - f->c[a], t += q[a] * f->e3[a];
  for (int a = 0; a < 3; a++) r2 += (q[a] - t * f->e3[a]) * (q[a] - t * f->e3[a]);
  *s = t, *r = sqrt(r2);
}

/* Which closed surface (connected set of faces) of obstacle o each vertex belongs to, labels
 * 0 .. *nsurf - 1 in lab (mesh_nv); union-find over the faces' vertices. */
static int surfaces(const sw_obstacle *o, int *lab, int *nsurf) {
  int *up = lab;
  for (int i = 0; i < o->mesh_nv; i++) up[i] = i;
  for (int f = 0; f < o->mesh_nf; f++)
    for (int k = 1; k < 3; k++) {
      int a = o->mesh_face[3 * f], b = o->mesh_face[3 * f + k];
      while (up[a] != a) a = up[a] = up[up[a]];
      while (up[b] != b) b = up[b] = up[up[b]];
      if (a != b) up[a < b ? b : a] = a < b ? a : b;
    }
  int n = 0;
  for (int i = 0; i < o->mesh_nv; i++) /* roots come first: up[i] <= i */
    lab[i] = up[i] == i ? n++ : lab[up[i]];
  *nsurf = n;
  return 0;
}

/* Whether point p lies inside each closed surface of o: in[s] = the parity of a long ray's
 * crossings with surface s's faces (a direction no axis-aligned mesh meets edge-on). */
static void inside_surfaces(const sw_obstacle *o, const int *lab, const double *p,
                            unsigned char *in) {
  static const double dir[3] = {0.5427, 0.3111, 0.7807};
  double q[3];
  for (int a = 0; a < 3; a++) q[a] = p[a] + 1e3 * dir[a]; /* m */
  for (int f = 0; f < o->mesh_nf; f++) {
    const int *v = o->mesh_face + 3 * f;
    in[lab[v[0]]] ^= (unsigned char)sw_segment_triangle_intersect(
        p, q, o->mesh_x + 3 * v[0], o->mesh_x + 3 * v[1], o->mesh_x + 3 * v[2]);
  }
}

/* For obstacle o: the surface of each vertex (lab) and whether each surface holds point p (in);
 * *any: 1 when one does.  lab and in hold mesh_nv + 1 entries; 0, or -1 out of memory. */
static int holding(const sw_obstacle *o, const double *p, int **lab, unsigned char **in,
                   int *any) {
  *lab = sw_calloc((size_t)o->mesh_nv + 1, sizeof(int));
  *in = *lab ? sw_calloc((size_t)o->mesh_nv + 1, 1) : NULL;
  if (!*in) return sw_free(*lab), *lab = NULL, -1;
  int ns = 0;
  surfaces(o, *lab, &ns);
  inside_surfaces(o, *lab, p, *in);
  for (int j = 0; j < ns; j++) *any |= (*in)[j];
  return 0;
}

/* The largest distance from the axis of a mesh obstacle's vertex with its axial coordinate in
 * [s0, s1], counting only the closed surfaces (of every mesh obstacle) that hold the axis's
 * point at mid, so that arms beside a torso do not widen the torso's cylinder nor the torso an
 * arm's; every surface when none holds it; m (-1: no vertex; -2: out of memory). */
static double body_radius(const sw_model *m, const cyl_frame *f, double s0, double s1, double mid) {
  double r = -1.0, p[3];
  int any = 0, *lab;
  unsigned char *in;
  for (int a = 0; a < 3; a++) p[a] = f->c[a] + mid * f->e3[a];
  for (int k = 0; k < m->nmesh_obstacle; k++) { /* does a surface hold p? */
    if (holding(&m->mesh_obstacle[k], p, &lab, &in, &any)) return -2.0;
    sw_free(lab), sw_free(in);
  }
  for (int k = 0; k < m->nmesh_obstacle; k++) {
    const sw_obstacle *o = &m->mesh_obstacle[k];
    int dummy = 0;
    if (holding(o, p, &lab, &in, &dummy)) return -2.0;
    for (int i = 0; i < o->mesh_nv; i++) {
      double s, d;
      axial(f, o->mesh_x + 3 * i, &s, &d);
      if (s >= s0 && s <= s1 && (!any || in[lab[i]])) r = fmax(r, d);
    }
    sw_free(lab), sw_free(in);
  }
  return r;
}

static const char *const cyl_keys[] = {"angle", "top", "radius", "clearance", "center", "axis",
                                        "up"};
static const char *const up_names[] = {"v", "u"};

/* A vertex's coordinates on the wrap: round (across the axis) and along the axis, m; with
 * up_u the pattern's u runs along the axis and -v round (so that the cloth's normal u x v
 * still points out), else u round and v along. */
static void wrap_uv(const double *uv, int up_u, double *round, double *along) {
  *round = up_u ? -uv[1] : uv[0];
  *along = up_u ? uv[0] : uv[1];
}

/* The piece's extent on the wrap: the middle and width of its round coordinate, the top and
 * bottom of its coordinate along the axis, m. */
static void wrap_extent(const sw_model *m, const unsigned char *mark, const double *uvv, int up_u,
                        double *mid, double *width, double *top, double *bot) {
  double lo = HUGE_VAL, hi = -HUGE_VAL, r, a;
  *top = -HUGE_VAL, *bot = HUGE_VAL;
  for (int i = 0; i < m->nv; i++) {
    if (!mark[i]) continue;
    wrap_uv(uvv + 2 * i, up_u, &r, &a);
    lo = fmin(lo, r), hi = fmax(hi, r), *top = fmax(*top, a), *bot = fmin(*bot, a);
  }
  *mid = 0.5 * (lo + hi), *width = hi - lo;
}

/* Wrapped without stretch onto the cylinder: u round the axis (anticlockwise seen from the
 * axis's tip), v along it; the reference point at `angle` from e1 and at `top` along the axis
 * from `center`. */
static int place_cylinder(const ctx *c, const ynode *y, const char *name,
                          const unsigned char *mark, const double *uvv) {
  sw_model *m = c->m;
  const ynode *v[7];
  double ang = 0.0, top = 0.0, R = 0.0, clear = 0.0, ctr[3] = {0, 0, 0}, axis[3] = {0, 0, 1};
  char w[SW_NAMESZ + 32], lab[SW_NAMESZ + 64];
  int up_u = 0;
  snprintf(w, sizeof w, "arrange %s cylinder", name);
  if (sy_map(c, y, w, cyl_keys, 7, v) ||
      sy_need(c, y, v[1], w, "top", "top: where the piece's top is along the axis, m"))
    return -1;
  if (!!v[2] == !!v[3])
    return sy_fail(c, y, "%s has %s; expected exactly one of radius (m) or clearance (m, from "
                   "the mesh obstacles)", w, v[2] ? "both radius and clearance" : "neither "
                   "radius nor clearance");
  snprintf(lab, sizeof lab, "%s angle", w);
  if (v[0] && sy_num(c, v[0], lab, -HUGE_VAL, 0, "degrees", &ang)) return -1;
  snprintf(lab, sizeof lab, "%s top", w);
  if (sy_num(c, v[1], lab, -HUGE_VAL, 0, "m", &top)) return -1;
  snprintf(lab, sizeof lab, "%s axis", w);
  if (v[5]) {
    if (sy_vec(c, v[5], lab, 3, -HUGE_VAL, 0, "", axis)) return -1;
    double big = fmax(fabs(axis[0]), fmax(fabs(axis[1]), fabs(axis[2])));
    if (!(big > 0.0))
      return sy_fail(c, v[5], "%s is [%g, %g, %g]; expected a nonzero direction", lab, axis[0],
                     axis[1], axis[2]);
    for (int a = 0; a < 3; a++) axis[a] /= big; /* no overflow in its length */
  }
  snprintf(lab, sizeof lab, "%s center", w);
  /* a vertical axis may be placed by [x, y] (top is then the height); any other by a point
   * [x, y, z] */
  int vertical = !v[5] || (axis[0] == 0.0 && axis[1] == 0.0 && axis[2] > 0.0);
  int ncenter = vertical && !(v[4] && v[4]->kind == Y_SEQ && v[4]->n == 3) ? 2 : 3;
  if (v[4] && sy_vec(c, v[4], lab, ncenter, -HUGE_VAL, 0, "m", ctr)) return -1;
  snprintf(lab, sizeof lab, "%s up", w);
  if (v[6] && sy_choice(c, v[6], lab, up_names, 2, &up_u)) return -1;
  cyl_frame fr;
  frame_of(ctr, axis, &fr);
  double mid, width, ptop, pbot; /* m: the piece on the wrap */
  wrap_extent(m, mark, uvv, up_u, &mid, &width, &ptop, &pbot);
  double len = ptop - pbot; /* m: the piece along the axis */
  if (v[2]) {
    snprintf(lab, sizeof lab, "%s radius", w);
    if (sy_num(c, v[2], lab, 0, 1, "m", &R)) return -1;
  } else {
    snprintf(lab, sizeof lab, "%s clearance", w);
    if (sy_num(c, v[3], lab, 0, 0, "m", &clear)) return -1;
    double rb = body_radius(m, &fr, top - len - clear, top + clear, top - 0.5 * len);
    if (rb == -2.0) return sy_oom(c, v[3]);
    if (rb < 0.0)
      return sy_fail(c, v[3], "%s: no mesh obstacle has a vertex between %g and %g m along the "
                     "axis; expected a body (obstacles: - {mesh: ...}) beside the piece, or a "
                     "radius", lab, top - len - clear, top + clear);
    R = rb + clear; /* m */
  }
  if (width >= 2.0 * ARR_PI * R)
    return sy_fail(c, y, "%s: the piece is %g m wide, more than once round a radius of %g m "
                   "(%g m); expected a larger radius", w, width, R, 2.0 * ARR_PI * R);
  double a0 = fmod(ang, 360.0) * ARR_PI / 180.0; /* rad, reduced first so that u / R is not lost beside a huge angle */
  for (int i = 0; i < m->nv; i++) {
    if (!mark[i]) continue;
    double r, a, *x = m->x0 + 3 * i;
    wrap_uv(uvv + 2 * i, up_u, &r, &a);
    double th = a0 + (r - mid) / R, s = top + (a - ptop); /* rad; m along the axis */
    for (int a = 0; a < 3; a++)
      x[a] = fr.c[a] + R * (cos(th) * fr.e1[a] + sin(th) * fr.e2[a]) + s * fr.e3[a];
    if (!isfinite(x[0] + x[1] + x[2]))
      return sy_fail(c, y, "%s puts vertex %d at a non-finite place; expected center, top and "
                     "the radius within the range of double", w, i);
  }
  return 0;
}

static const char *const rigid_keys[] = {"rotate", "translate"};

static int place_rigid(const ctx *c, const ynode *y, const char *name, const piece *pc,
                       const unsigned char *mark, const double *uvv) {
  sw_model *m = c->m;
  const ynode *v[2];
  double rot[3] = {0, 0, 0}, tr[3] = {0, 0, 0};
  char w[SW_NAMESZ + 32], lab[SW_NAMESZ + 64];
  snprintf(w, sizeof w, "arrange %s rigid", name);
  if (sy_map(c, y, w, rigid_keys, 2, v) ||
      sy_need(c, y, v[1], w, "translate", "translate: [x, y, z], m"))
    return -1;
  snprintf(lab, sizeof lab, "%s rotate", w);
  if (v[0] && sy_vec(c, v[0], lab, 3, -HUGE_VAL, 0, "degrees", rot)) return -1;
  snprintf(lab, sizeof lab, "%s translate", w);
  if (sy_vec(c, v[1], lab, 3, -HUGE_VAL, 0, "m", tr)) return -1;
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int a = 0; a < 3; a++) { /* R = Rz Ry Rx: x first */
    double t = rot[a] * ARR_PI / 180.0, cs = cos(t), sn = sin(t), Q[9], P[9];
    int i1 = (a + 1) % 3, i2 = (a + 2) % 3;
    memset(Q, 0, sizeof Q);
    Q[a * 3 + a] = 1.0;
    Q[i1 * 3 + i1] = cs, Q[i1 * 3 + i2] = -sn, Q[i2 * 3 + i1] = sn, Q[i2 * 3 + i2] = cs;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        P[i * 3 + j] = 0.0;
        for (int k = 0; k < 3; k++) P[i * 3 + j] += Q[i * 3 + k] * R[k * 3 + j];
      }
    memcpy(R, P, sizeof R);
  }
  for (int i = 0; i < m->nv; i++) {
    if (!mark[i]) continue;
    double p[3] = {uvv[2 * i] - pc->umid, uvv[2 * i + 1] - pc->vtop, 0.0}, *x = m->x0 + 3 * i;
    for (int a = 0; a < 3; a++) x[a] = tr[a] + R[3 * a] * p[0] + R[3 * a + 1] * p[1] + R[3 * a + 2] * p[2];
  }
  return 0;
}

static const char *const place_keys[] = {"cylinder", "rigid"};

/* ------------------------------------------------------------------ checks */

/* The owner of face k of the combined list: the cloth face's group (>= 0), or -1 - obstacle. */
typedef struct combined {
  int nvt, nft;
  double *x;   /* (nvt x 3) cloth x0, then every mesh obstacle's vertices */
  int *face;   /* (nft x 3) */
  int *owner;  /* (nft) */
} combined;

static int combine(const ctx *c, combined *cb) {
  const sw_model *m = c->m;
  cb->nvt = m->nv, cb->nft = m->nf;
  for (int k = 0; k < m->nmesh_obstacle; k++) {
    cb->nvt += m->mesh_obstacle[k].mesh_nv;
    cb->nft += m->mesh_obstacle[k].mesh_nf;
  }
  cb->x = sw_calloc(3 * (size_t)cb->nvt + 1, sizeof(double));
  cb->face = sw_calloc(3 * (size_t)cb->nft + 1, sizeof(int));
  cb->owner = sw_calloc((size_t)cb->nft + 1, sizeof(int));
  if (!cb->x || !cb->face || !cb->owner) return -1;
  memcpy(cb->x, m->x0, 3 * (size_t)m->nv * sizeof(double));
  memcpy(cb->face, m->face, 3 * (size_t)m->nf * sizeof(int));
  for (int f = 0; f < m->nf; f++) cb->owner[f] = c->fgroup[f];
  int nv = m->nv, nf = m->nf;
  for (int k = 0; k < m->nmesh_obstacle; k++) {
    const sw_obstacle *o = &m->mesh_obstacle[k];
    memcpy(cb->x + 3 * (size_t)nv, o->mesh_x, 3 * (size_t)o->mesh_nv * sizeof(double));
    for (int f = 0; f < o->mesh_nf; f++, nf++) {
      for (int i = 0; i < 3; i++) cb->face[3 * nf + i] = o->mesh_face[3 * f + i] + nv;
      cb->owner[nf] = -1 - k;
    }
    nv += o->mesh_nv;
  }
  return 0;
}

/* Whether point p lies inside the closed mesh obstacle k: the parity of the crossings of a
 * long ray from p (in a direction no axis-aligned mesh meets edge-on). */
static int inside(const sw_obstacle *o, const double *p) {
  static const double dir[3] = {0.5427, 0.3111, 0.7807};
  double q[3];
  for (int a = 0; a < 3; a++) q[a] = p[a] + 1e3 * dir[a]; /* m */
  int n = 0;
  for (int f = 0; f < o->mesh_nf; f++) {
    const int *v = o->mesh_face + 3 * f;
    n += sw_segment_triangle_intersect(p, q, o->mesh_x + 3 * v[0], o->mesh_x + 3 * v[1],
                                       o->mesh_x + 3 * v[2]);
  }
  return n & 1;
}

/* No arranged piece (arranged[g]) crosses a mesh obstacle or another group, or lies inside a
 * mesh obstacle; at[g] is the piece's key in `arrange` (cleared as each piece is checked
 * for inside). */
static int check_arranged(const ctx *c, const unsigned char *arranged, const ynode **at) {
  const sw_model *m = c->m;
  combined cb = {0};
  sw_broadphase bp;
  sw_broadphase_init(&bp);
  int rc = combine(c, &cb) ? sy_oom(c, c->root) : 0;
  sw_bp_input in = {.nv = cb.nvt, .x0 = cb.x, .x1 = cb.x, .nf = cb.nft, .face = cb.face};
  if (!rc && sw_broadphase_query(&bp, &in, SW_BP_FF)) rc = sy_oom(c, c->root);
  for (int k = 0; !rc && k < bp.nff; k++) {
    int f = bp.ff[2 * k], g = bp.ff[2 * k + 1], of = cb.owner[f], og = cb.owner[g];
    if (of == og || (of < 0 && og < 0)) continue;
    if (!((of >= 0 && arranged[of]) || (og >= 0 && arranged[og]))) continue;
    const int *p = cb.face + 3 * f, *q = cb.face + 3 * g;
    const double *x = cb.x;
    if (!sw_triangles_intersect(x + 3 * p[0], x + 3 * p[1], x + 3 * p[2], x + 3 * q[0],
                                x + 3 * q[1], x + 3 * q[2]))
      continue;
    if (of < 0 || (og >= 0 && !arranged[of])) { /* the arranged one first */
      int t = of; of = og, og = t;
      t = f, f = g, g = t;
    }
    if (og < 0)
      rc = sy_fail(c, at[of], "arrange %s: the piece crosses obstacles[%d] (its face %d meets "
                   "one of the body's); expected the piece apart from the body: a larger "
                   "radius or clearance, or another place", c->group[of],
                   m->mesh_obstacle[-1 - og].item, f);
    else
      rc = sy_fail(c, at[of], "arrange %s: the piece crosses piece %s (its face %d meets face "
                   "%d); expected the pieces apart: another angle, height or radius",
                   c->group[of], c->group[og], f, g);
  }
  for (int f = 0; !rc && f < m->nf; f++) { /* one vertex of each arranged piece */
    int g = c->fgroup[f];
    if (!arranged[g] || at[g] == NULL) continue;
    for (int k = 0; !rc && k < m->nmesh_obstacle; k++)
      if (inside(&m->mesh_obstacle[k], m->x0 + 3 * m->face[3 * f]))
        rc = sy_fail(c, at[g], "arrange %s: the piece lies inside obstacles[%d] (its vertex %d "
                     "does); expected the piece outside the body: a larger radius or "
                     "clearance", c->group[g], m->mesh_obstacle[k].item, m->face[3 * f]);
    at[g] = NULL; /* one vertex per piece */
  }
  sw_broadphase_free(&bp);
  sw_free(cb.x);
  sw_free(cb.face);
  sw_free(cb.owner);
  return rc;
}

int sc_load_arrange(const ctx *c, const ynode *y) {
  sw_model *m = c->m;
  if (y->kind != Y_MAP)
    return sy_type_error(c, y, "arrange", "a mapping from piece (OBJ group) names to "
                         "{cylinder: {...}} or {rigid: {...}}");
  if (m->dim != 3) return sy_fail(c, y, "arrange is given in a 2D scene; expected dimension: 3");
  if (!c->fgroup || m->nf == 0)
    return sy_fail(c, y, "arrange is given but the mesh has no faces; expected an OBJ mesh of "
                   "pieces");
  unsigned char *mark = sw_calloc((size_t)m->nv + 1, 1), *arranged = sw_calloc((size_t)c->ngroup, 1);
  double *uvv = sw_calloc(2 * (size_t)m->nv + 1, sizeof(double));
  const ynode **at = sw_calloc((size_t)c->ngroup, sizeof *at), *v[2];
  int rc = !mark || !arranged || !uvv || !at ? sy_oom(c, y) : 0;
  for (int p = 0; !rc && p < y->n / 2; p++) {
    const ynode *key = y->kid[2 * p], *val = y->kid[2 * p + 1];
    const char *name;
    char w[SW_NAMESZ + 16];
    if (sy_str(c, key, "arrange key", SW_NAMESZ, &name)) { rc = -1; break; }
    int g = 0;
    if (sc_find_group(c, key, "arrange", "names", name, &g)) { rc = -1; break; }
    if (arranged[g]) { rc = sy_fail(c, key, "arrange names '%s' twice; expected each piece "
                                    "once", name); break; }
    snprintf(w, sizeof w, "arrange %s", name);
    piece pc = {0};
    if (sy_map(c, val, w, place_keys, 2, v) || piece_of(c, key, name, g, mark, uvv, &pc)) {
      rc = -1;
      break;
    }
    if (!!v[0] == !!v[1]) {
      rc = sy_fail(c, val, "%s has %s; expected exactly one of cylinder: {...} or rigid: {...}",
                   w, v[0] ? "both cylinder and rigid" : "neither cylinder nor rigid");
      break;
    }
    rc = v[0] ? place_cylinder(c, v[0], name, mark, uvv)
              : place_rigid(c, v[1], name, &pc, mark, uvv);
    arranged[g] = 1, at[g] = key;
  }
  if (!rc) rc = check_arranged(c, arranged, at);
  sw_free(mark);
  sw_free(arranged);
  sw_free(uvv);
  sw_free(at);
  return rc;
}
