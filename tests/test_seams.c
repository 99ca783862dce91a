/* test_seams.c — seams, arrangement and the fit stage (docs/garments.md): the seam term through
 * the conformance harness (gradient and Hessian against finite differences, during its ramp
 * and closed), the arc-length pairing of curves of different resolution and length, two flat
 * pieces sewn into a tube around a cylinder (closed to < 1 mm, nothing crossing, exact tests),
 * and every bad input as a file:line:column error naming the seam or the piece. */
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
#include "terms.h"

/* The tube's pieces (tests/data/tube_pieces.obj): front vertices 0..34, back 35..69, each 7
 * columns x 5 rows; the front's right edge 6..34, its left 0..28, the back's 35..63, 41..69. */
#define TUBE_HEAD                                                                             \
  "dimension: 3\n"                                                                            \
  "mesh: {obj: tube_pieces.obj}\n"                                                            \
  "material: {density: 0.15, membrane: {model: bw98, k_u: 2000, k_v: 1500, k_shear: 50}}\n"

#define TUBE_ARRANGE                                                                          \
  "arrange:\n"                                                                                \
  "  front: {cylinder: {angle: 270, top: 0.1, radius: 0.11}}\n"                               \
  "  back: {cylinder: {angle: 90, top: 0.1, radius: 0.11}}\n"

#define TUBE_SEAMS                                                                            \
  "seams:\n"                                                                                  \
  "  - {name: left, a: {panel: front, from: 6, to: 34}, b: {panel: back, from: 35, to: 63}}\n" \
  "  - {name: right, a: {panel: back, from: 41, to: 69}, b: {panel: front, from: 0, to: 28}}\n"

static sw_model *tube(const char *extra) {
  char text[4096];
  snprintf(text, sizeof text, TUBE_HEAD TUBE_ARRANGE TUBE_SEAMS "%s", extra);
  return th_scene("tests/data/tube.yaml", text);
}

/* The seam term during its ramp (rest lengths between the starting gaps and 0, at t = 0 the
 * starting gaps: no force at x0) and closed (zero-length springs). */
static void conformance_ramp(void **st) {
  (void)st;
  sw_model *m = tube("sewing: {ramp: 0.3}\n");
  assert_non_null(m);
  th_conformance(m, "seams", TH_INTERNAL | TH_REST_FREE, 0.1, 777);
  sw_model_free(m);
}

static void conformance_closed(void **st) {
  (void)st;
  sw_model *m = tube("sewing: {ramp: 0, stiffness: 3e5}\n");
  assert_non_null(m);
  th_conformance(m, "seams", TH_INTERNAL, 0.1, 778);
  sw_model_free(m);
}

/* A curve of 3 vertices (edges 1 and 1 m) sewn to one of 5 (edges 0.5, 0.5, 0.6, 0.6 m: 10 %
 * longer): each vertex meets the point at its fraction of arc length on the other, the pairs'
 * lengths add up to the mean length. */
static void pairing(void **st) {
  (void)st;
  int c0[3] = {0, 1, 2}, c1[5] = {3, 4, 5, 6, 7};
  double e0[2] = {1.0, 1.0}, e1[4] = {0.5, 0.5, 0.6, 0.6};
  sw_seam sm;
  memset(&sm, 0, sizeof sm);
  sm.n[0] = 3, sm.n[1] = 5, sm.curve[0] = c0, sm.curve[1] = c1;
  char err[256];
  assert_int_equal(sw_seam_pair(&sm, e0, e1, err, sizeof err), 0);
  assert_int_equal(sm.npair, 8);
  assert_true(fabs(sm.length[0] - 2.0) < 1e-15 && fabs(sm.length[1] - 2.2) < 1e-15);
  /* vertex 1 (s = 0.5) on curve 1: s = 0.5 is 1.1 m along, on edge (5, 6) at 0.1 / 0.6 */
  assert_int_equal(sm.pair[3 * 1 + 1], 5);
  assert_int_equal(sm.pair[3 * 1 + 2], 6);
  assert_true(fabs(sm.w[1] - 0.1 / 0.6) < 1e-12);
  /* vertex 4 of curve 1 (0.5 of 2.2 m: s = 0.5 / 2.2) on edge (0, 1) at weight 2 s */
  assert_int_equal(sm.pair[3 * 4], 4);
  assert_int_equal(sm.pair[3 * 4 + 1], 0);
  assert_true(fabs(sm.w[4] - 2.0 * 0.5 / 2.2) < 1e-12);
  /* the ends meet the ends */
  assert_true(sm.w[0] == 0.0 && sm.pair[1] == 3 && sm.w[2] == 1.0 && sm.pair[3 * 2 + 2] == 7);
  double sum = 0.0;
  for (int p = 0; p < sm.npair; p++) sum += sm.len[p];
  assert_true(fabs(sum - 2.1) < 1e-12);
  free(sm.pair), free(sm.w), free(sm.len);
}

/* Two flat rectangles wrapped 3 cm out round a closed cylinder of radius 8 cm, sewn into a tube
 * by the fit stage with body and self-contact on: the seams close to below 1 mm, no face
 * crosses another or the cylinder (exact tests), every vertex stays out of it, and the tube
 * keeps its pattern's girth (radius 0.6 m / 2 pi). */
static void tube_fit(void **st) {
  (void)st;
  char err[SW_ERRSZ];
  sw_model *m = th_scene_file("tests/data/tube_seams.yaml");
  assert_non_null(m);
  assert_int_equal(m->opt.tx_reference_uv, 1); /* the default with seams */
  assert_true(m->fit.on);
  sw_sim *s = sw_sim_new(m, 0, err, sizeof err); /* the fit runs as the sim starts */
  if (!s) print_error("%s\n", err);
  assert_non_null(s);
  const sw_data *d = sw_sim_data(s);
  assert_true(d->fit_end >= 2.0 * m->seam_ramp);
  assert_true(d->seam_gap_max < 1e-3);
  assert_int_equal(sw_mesh_self_intersections_sewn(m->nv, d->x, m->nf, m->face, m->sewn_ptr,
                                                   m->sewn_idx), 0);
  assert_int_equal(sw_mcontact_obstacle_intersections(m, d->mc, d->x, d->t, NULL), 0);
  double rmin = HUGE_VAL, rmean = 0.0;
  for (int i = 0; i < m->nv; i++) {
    double r = hypot(d->x[3 * i], d->x[3 * i + 1]);
    rmin = fmin(rmin, r);
    rmean += r / m->nv;
  }
  assert_true(rmin > 0.08);
  assert_true(fabs(rmean - 0.3 / 3.14159265358979) < 0.05 * 0.3 / 3.14159265358979);
  sw_sim_free(s);
  sw_model_free(m);
}

/* The tube of tube_fit cut 4 % smaller than its body, a closed 16-sided prism of radius 10 cm
 * (perimeter 0.624 m, the tube 0.6 m), wrapped 3 cm out, with gravity across the axis (a tight
 * sleeve on a level arm), body and self-contact on; `method` after the fit. */
static sw_sim *tight_tube_fit(const char *method, double duration, const char *fit,
                              sw_model **mp) {
  char text[4096], err[SW_ERRSZ];
  snprintf(text, sizeof text,
           "dimension: 3\n"
           "mesh: {obj: tube_pieces.obj}\n"
           "material: {density: 0.15, membrane: {model: bw98, k_u: 2000, k_v: 1500, k_shear: 50},\n"
           "           bending: {model: quadratic, stiffness: 1e-5}}\n"
                     "gravity: [-9.81, 0, 0]\n"
                     "obstacles: [{mesh: cylinder_tight.obj}]\n"
                     "contact: {self: true, thickness: 5e-4}\n"
                     "arrange:\n"
                     "  front: {cylinder: {angle: 270, top: 0.1, radius: 0.13}}\n"
                     "  back: {cylinder: {angle: 90, top: 0.1, radius: 0.13}}\n" TUBE_SEAMS
                     "sewing: {ramp: 0.3}\n"
                     "fit: %s\n"
                     "damping: {mass: 5}\n"
                     "integrator: {method: %s, dt: 0.01}\n"
                     "duration: %g\n",
           fit, method, duration);
  *mp = th_scene("tests/data/tube.yaml", text);
  sw_sim *s = sw_sim_new(*mp, 0, err, sizeof err); /* the fit runs as the sim starts */
  if (!s) print_error("%s\n", err);
  assert_non_null(s);
  (*mp)->opt.newton_tol = 1e-7; /* m/s: the dynamics after the fit to a tight tolerance */
  if (sw_sim_run(s, sw_sim_data(s)->fit_end + duration, err, sizeof err)) print_error("%s\n", err);
  assert_true(sw_sim_data(s)->t >= sw_sim_data(s)->fit_end + duration - 1e-9);
  return s;
}

static sw_sim *tight_tube(const char *method, double duration, sw_model **mp) {
  return tight_tube_fit(method, duration, "{speed: 0.05, gap: 2e-3}", mp);
}

/* The seams closed to 1 mm and nothing crossing (exact tests: the cloth itself, the body). */
static void assert_sewn_clear(const sw_model *m, const sw_data *d) {
  assert_true(d->seam_gap_max < 1e-3);
  assert_int_equal(sw_mesh_self_intersections_sewn(m->nv, d->x, m->nf, m->face, m->sewn_ptr,
                                                   m->sewn_idx), 0);
  assert_int_equal(sw_mcontact_obstacle_intersections(m, d->mc, d->x, d->t, NULL), 0);
}

/* A sewn garment pressed on its body: after the fit, the static solve with contact (mesh body,
 * self-contact, seams) reaches its tolerance, 1e-10 of the scene's force scale F (the largest
 * force one term puts on one vertex), in at most 100 iterations, and lands where 3 s of damped
 * dynamics from the same fit (Newton to 1e-7 m/s) come to rest, within 1 nm; nothing crosses in
 * either.  The fit ends early (at 5 cm/s, the seams sewn over 0.3 s), so both have work to do. */
static void tube_static(void **st) {
  (void)st;
  sw_model *ms, *md;
  sw_sim *ss = tight_tube("static", 0.0, &ms);
  const sw_data *ds = sw_sim_data(ss);
  const sw_static_info *info = &ds->static_info;
  double weight = 0.0; /* N: the heaviest vertex's weight */
  for (int i = 0; i < ms->nv; i++) weight = fmax(weight, 9.81 * ms->mass[i]);
  print_message("tight tube, static after the fit: %d iterations, largest free force %.3g N, "
                "tolerance %.3g N (%.3g vertex weights), floor %.3g N%s\n", info->iterations,
                info->force, info->tol, info->tol / (1e-10 * weight), info->floor,
                info->roundoff ? " (at the floor)" : "");
  assert_true(info->force <= info->tol || info->roundoff);
  assert_true(info->tol > 1e-10 * weight); /* the contact and the seams set the scale */
  assert_true(info->iterations <= 100);
  sw_sim *sd = tight_tube("backward-euler", 3.0, &md);
  const sw_data *dd = sw_sim_data(sd);
  double dmax = 0.0, rmin = HUGE_VAL;
  for (int i = 0; i < ms->nv * 3; i++) dmax = fmax(dmax, fabs(ds->x[i] - dd->x[i]));
  for (int i = 0; i < ms->nv; i++) rmin = fmin(rmin, hypot(ds->x[3 * i], ds->x[3 * i + 1]));
  print_message("static against 3 s of damped dynamics: positions differ by at most %.3g m; "
                "closest vertex %.4f m from the axis\n", dmax, rmin);
  assert_true(dmax < 1e-9);
  /* the automatic contact stiffness grew with the tube's pressure on the body (docs/contact.md,
   * "Adaptive stiffness") until the body's pairs sat beyond a gap of dhat/4 */
  double factor = sw_mcontact_kappa_scale(dd->mc);
  print_message("contact stiffness factor %g; smallest gap %.3g m to the body, %.3g m in the "
                "tube (dhat %g m)\n", factor, dd->contact_min, dd->self_min, md->contact.dhat);
  assert_true(factor >= 2.0);
  assert_true(dd->contact_min >= md->contact.dhat / 8.0);
  assert_true(rmin > 0.1 * cos(3.14159265358979 / 16)); /* on the prism, not in it */
  assert_sewn_clear(ms, ds), assert_sewn_clear(md, dd);
  sw_sim_free(ss), sw_sim_free(sd);
  sw_model_free(ms), sw_model_free(md);
}

/* The fit as an optimisation (fit.mode optimize and settle: proximal steps, docs/garments.md)
 * of the tight tube, at the default fit speed and gap: it ends where the dynamic fit followed
 * by the static solve does, within 1 mm RMS over the vertices, with its seams closed to 1 mm,
 * nothing crossing and the garment at rest (no velocity left). */
static void tube_optimize(void **st) {
  (void)st;
  sw_model *mr;
  sw_sim *sr = tight_tube_fit("static", 0.0, "{mode: dynamic}", &mr);
  const sw_data *dr = sw_sim_data(sr);
  assert_sewn_clear(mr, dr);
  const char *modes[] = {"{mode: optimize}", "{mode: settle}"};
  for (int k = 0; k < 2; k++) {
    sw_model *m;
    sw_sim *s = tight_tube_fit("backward-euler", 0.0, modes[k], &m);
    const sw_data *d = sw_sim_data(s);
    double ss = 0.0, vmax = 0.0;
    for (int i = 0; i < m->nv * 3; i++) {
      ss += (d->x[i] - dr->x[i]) * (d->x[i] - dr->x[i]);
      vmax = fmax(vmax, fabs(d->v[i]));
    }
    double rms = sqrt(ss / m->nv); /* m */
    print_message("tight tube, fit %s: %ld steps, %ld Newton iterations (dynamic fit and static "
                  "%ld, %ld); %.3g m RMS from the dynamic fit and static; seam gap %.3g m\n",
                  modes[k], d->nstep, d->nnewton, dr->nstep, dr->nnewton, rms, d->seam_gap_max);
    assert_true(rms < 1e-3);
    assert_true(vmax == 0.0);
    assert_sewn_clear(m, d);
    sw_sim_free(s), sw_model_free(m);
  }
  sw_sim_free(sr), sw_model_free(mr);
}

/* The arrangement places each piece from its pattern: on the cylinder every vertex at the
 * radius, its height top + (v - v_top), its angle that of the reference point plus (u - u_mid)
 * / R (so the wrap keeps the pattern's lengths along u); rigidly, R (u - u_mid, v - v_top, 0)
 * + translate.  The tube's pieces are 0.3 x 0.2 m, u in [-0.15, 0.15], v in [-0.2, 0]. */
static void arrangement(void **st) {
  (void)st;
  sw_model *m = th_scene("tests/data/tube.yaml", TUBE_HEAD
                         "arrange:\n"
                         "  front: {cylinder: {angle: 270, top: 0.1, radius: 0.11, center: [0.01, 0.02]}}\n"
                         "  back: {rigid: {rotate: [90, 0, 90], translate: [0.5, 0, 1]}}\n");
  assert_non_null(m);
  for (int i = 0; i < 35; i++) { /* front: vertex (c, r) = 7 r + c at u = -0.15 + 0.05 c */
    const double *x = m->x0 + 3 * i, u = -0.15 + 0.05 * (i % 7), v = -0.05 * (i / 7);
    double th = atan2(x[1] - 0.02, x[0] - 0.01), want = 1.5 * 3.14159265358979 + u / 0.11;
    assert_true(fabs(hypot(x[0] - 0.01, x[1] - 0.02) - 0.11) < 1e-12);
    assert_true(fabs(x[2] - (0.1 + v)) < 1e-12);
    assert_true(fabs(remainder(th - want, 2.0 * 3.14159265358979)) < 1e-12);
  }
  for (int i = 35; i < 70; i++) { /* back: x first (u, 0, v), then z by 90: (0, u, v) */
    const double *x = m->x0 + 3 * i, u = -0.15 + 0.05 * ((i - 35) % 7), v = -0.05 * ((i - 35) / 7);
    assert_true(fabs(x[0] - 0.5) < 1e-12 && fabs(x[1] - u) < 1e-12 && fabs(x[2] - (1 + v)) < 1e-12);
  }
  sw_model_free(m);
}

/* A cylinder about any axis: the tube's front wrapped about the axis (1, 0, 1) through
 * (0.2, 0, 0.5), radius 0.11, top 0.1 along the axis.  The frame, by the test's own hand: e3 =
 * (1, 0, 1)/sqrt 2, e1 = +x's part across the axis = (1, 0, -1)/sqrt 2, e2 = e3 x e1 = +y; the
 * vertex at (u, v) at c + 0.11 (cos th e1 + sin th e2) + (0.1 + v) e3, th = angle + u / 0.11. */
static void arrangement_axis(void **st) {
  (void)st;
  sw_model *m = th_scene("tests/data/tube.yaml", TUBE_HEAD
                         "arrange:\n"
                         "  front: {cylinder: {angle: 30, top: 0.1, radius: 0.11, axis: [1, 0, 1], "
                         "center: [0.2, 0, 0.5]}}\n");
  assert_non_null(m);
  const double h = sqrt(0.5), e1[3] = {h, 0, -h}, e2[3] = {0, 1, 0}, e3[3] = {h, 0, h};
  const double c[3] = {0.2, 0, 0.5}, pi = 3.14159265358979;
  for (int i = 0; i < 35; i++) {
    const double *x = m->x0 + 3 * i, u = -0.15 + 0.05 * (i % 7), v = -0.05 * (i / 7);
    double th = 30 * pi / 180 + u / 0.11;
    for (int a = 0; a < 3; a++) {
      double want = c[a] + 0.11 * (cos(th) * e1[a] + sin(th) * e2[a]) + (0.1 + v) * e3[a];
      assert_true(fabs(x[a] - want) < 1e-12);
    }
  }
  sw_model_free(m);
}

/* up: u wraps a piece with its u along the axis (a piece whose grain line runs down the body)
 * and -v round: the tube's front (u in [-0.15, 0.15], v in [-0.2, 0]) about the vertical axis,
 * radius 0.11, at angle 270 and top 0.1: height 0.1 + (u - 0.15), angle 270° + (-v - 0.1) /
 * 0.11; its faces' normals (u x v) point away from the axis. */
static void arrangement_up(void **st) {
  (void)st;
  sw_model *m = th_scene("tests/data/tube.yaml", TUBE_HEAD
                         "arrange:\n"
                         "  front: {cylinder: {angle: 270, top: 0.1, radius: 0.11, up: u}}\n"
                         "  back: {rigid: {translate: [0, 1, 1]}}\n");
  assert_non_null(m);
  const double pi = 3.14159265358979;
  for (int i = 0; i < 35; i++) {
    const double *x = m->x0 + 3 * i, u = -0.15 + 0.05 * (i % 7), v = -0.05 * (i / 7);
    double th = atan2(x[1], x[0]), want = 1.5 * pi + (-v - 0.1) / 0.11;
    assert_true(fabs(hypot(x[0], x[1]) - 0.11) < 1e-12);
    assert_true(fabs(x[2] - (0.1 + u - 0.15)) < 1e-12);
    assert_true(fabs(remainder(th - want, 2.0 * pi)) < 1e-12);
  }
  for (int f = 0; f < m->nf; f++) {
    const int *t = m->face + 3 * f;
    if (t[0] >= 35) continue;
    const double *a = m->x0 + 3 * t[0], *b = m->x0 + 3 * t[1], *c = m->x0 + 3 * t[2];
    double e1[3], e2[3], n[3], mid[2] = {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3};
    for (int k = 0; k < 3; k++) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    assert_true(n[0] * mid[0] + n[1] * mid[1] > 0.0); /* outward */
  }
  sw_model_free(m);
}

/* clearance counts only the closed surfaces that hold the axis: beside the cylinder of radius
 * 0.08 (the body) a box reaches 0.30 m from its axis (an arm), so the radius is 0.08 + 0.03,
 * not 0.33; a piece wrapped about an axis through the box takes the box's corners. */
static void clearance_surfaces(void **st) {
  (void)st;
  sw_model *m = th_scene("tests/data/tube.yaml", TUBE_HEAD
                         "obstacles: [{mesh: two_bodies.obj}]\n"
                         "arrange:\n"
                         "  front: {cylinder: {angle: 270, top: 0.1, clearance: 0.03}}\n"
                         "  back: {rigid: {translate: [0, 1, 1]}}\n");
  assert_non_null(m);
  for (int i = 0; i < 35; i++)
    assert_true(fabs(hypot(m->x0[3 * i], m->x0[3 * i + 1]) - 0.11) < 1e-9);
  sw_model_free(m);
  /* about the vertical axis through the box's middle (0.25, 0): its corners 0.0559 m away */
  m = th_scene("tests/data/tube.yaml", TUBE_HEAD
               "obstacles: [{mesh: two_bodies.obj}]\n"
               "arrange:\n"
               "  front: {cylinder: {angle: 0, top: 0.1, clearance: 0.03, center: [0.25, 0]}}\n"
               "  back: {rigid: {translate: [0, 1, 1]}}\n");
  assert_non_null(m);
  double want = hypot(0.05, 0.05) + 0.03;
  for (int i = 0; i < 35; i++)
    assert_true(fabs(hypot(m->x0[3 * i] - 0.25, m->x0[3 * i + 1]) - want) < 1e-9);
  sw_model_free(m);
}

static int is_sewn(const sw_model *m, int a, int b) {
  for (int k = m->sewn_ptr[a]; k < m->sewn_ptr[a + 1]; k++)
    if (m->sewn_idx[k] == b) return 1;
  return 0;
}

/* Where seams end at one point (the T-shirt's underarm: the sleeve's two corners, the front's
 * and the back's armpit), every piece is sewn to every other there, both ways, though no seam
 * pairs the sleeve's corner with the back's armpit; a vertex in the middle of a seam is sewn
 * only near its partner. */
static void junction(void **st) {
  (void)st;
  sw_model *m = th_scene_file("scenes/garment_tshirt.yaml");
  assert_non_null(m);
  /* the left underarm: sleeve corners 566, 578; front armpit 112, back armpit 379 */
  const int at[4] = {566, 578, 112, 379};
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      if (i != j) assert_true(is_sewn(m, at[i], at[j]));
  assert_true(is_sewn(m, 566, 367) && is_sewn(m, 367, 566)); /* the back's armhole, next up */
  /* the front's armhole at its middle (59) and the back's (331): no seam joins them */
  assert_false(is_sewn(m, 59, 331));
  assert_false(is_sewn(m, 59, 379));
  sw_model_free(m);
}

/* Seams whose ends name their panels' corners and notches sew the same curves as seams by
 * vertex index; the landmarks change neither the panels' materials nor anything else. */
static void landmarks(void **st) {
  (void)st;
  sw_model *by_index = tube("");
  sw_model *by_mark = th_scene("tests/data/tube.yaml", TUBE_HEAD TUBE_ARRANGE
      "panels:\n"
      "  front: {corners: [0, 6, 34, 28], notches: [20]}\n"
      "  back: {corners: [35, 41, 69, 63], notches: [42]}\n"
      "seams:\n"
      "  - name: left\n"
      "    a: {panel: front, from: {corner: 1}, to: {corner: 2}}\n"
      "    b: {panel: back, from: {corner: 0}, to: {corner: 3}}\n"
      "  - name: right\n"
      "    a: {panel: back, from: {corner: 1}, to: {corner: 2}}\n"
      "    b: {panel: front, from: {corner: 0}, to: {corner: 3}}\n");
  assert_int_equal(by_mark->nseam, 2);
  for (int j = 0; j < 2; j++)
    for (int s = 0; s < 2; s++) {
      assert_int_equal(by_mark->seam[j].n[s], by_index->seam[j].n[s]);
      assert_memory_equal(by_mark->seam[j].curve[s], by_index->seam[j].curve[s],
                          sizeof(int) * (size_t)by_index->seam[j].n[s]);
    }
  for (int f = 0; f < by_mark->nf; f++)
    assert_true(by_mark->mat[by_mark->face_mat[f]].k_u == by_index->mat[0].k_u);
  sw_model_free(by_index);
  sw_model_free(by_mark);
  /* a notch as a seam end: the front's right side from its notch (vertex 20) up to corner 1 */
  sw_model *m = th_scene("tests/data/tube.yaml", TUBE_HEAD
      "panels: {front: {corners: [0, 6, 34, 28], notches: [20]}}\n"
      "seams:\n"
      "  - {a: {panel: front, from: {notch: 0}, to: {corner: 1}},"
      " b: {panel: front, from: 0, to: 14}}\n");
  assert_int_equal(m->seam[0].n[0], 3);
  assert_int_equal(m->seam[0].curve[0][0], 20);
  assert_int_equal(m->seam[0].curve[0][2], 6);
  sw_model_free(m);
}

/* The automatic seam stiffness: 10 x the fabric's tensile stiffness over the seams' mean edge
 * length, for a measured fabric the largest its data reaches (gray-interlock: 2 c22 of its
 * 67.5 degree row, 2 x 413.553162 N/m, against 2 x 34.477123 at rest), for bw98 its k_u. */
static void auto_stiffness(void **st) {
  (void)st;
  sw_model *woven = tube("");
  sw_model *knit = th_scene("tests/data/tube.yaml",
      "dimension: 3\nmesh: {obj: tube_pieces.obj}\n"
      "material: {fabric: {preset: gray-interlock}}\n" TUBE_ARRANGE TUBE_SEAMS);
  assert_non_null(woven);
  assert_non_null(knit);
  double ratio = knit->seam_stiffness / woven->seam_stiffness;
  if (!(fabs(ratio - 2.0 * 413.553162 / 2000.0) < 1e-12))
    fail_msg("seam stiffness ratio %.15g, expected %.15g", ratio, 2.0 * 413.553162 / 2000.0);
  sw_model_free(woven);
  sw_model_free(knit);
}

/* A bad scene's message: at the line and column given, naming `name`. */
static void bad(const char *text, const char *where, const char *name) {
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_parse("tests/data/tube.yaml", text, strlen(text), err, sizeof err);
  if (m || !strstr(err, where) || !strstr(err, name))
    print_error("expected an error at %s naming %s; got: %s\n", where, name, m ? "(none)" : err);
  assert_null(m);
  assert_non_null(strstr(err, where));
  assert_non_null(strstr(err, name));
}

static void bad_input(void **st) {
  (void)st;
  /* a fit mode that is none of them */
  bad(TUBE_HEAD TUBE_ARRANGE TUBE_SEAMS "fit: {mode: quasi}\n", "tube.yaml:10:", "fit mode");
  bad(TUBE_HEAD TUBE_ARRANGE TUBE_SEAMS "fit: {opt_growth: 0.5}\n", "tube.yaml:10:",
      "fit opt_growth");
  /* an unknown panel */
  bad(TUBE_HEAD TUBE_ARRANGE "seams:\n"
      "  - {name: left, a: {panel: frnt, from: 6, to: 34}, b: {panel: back, from: 35, to: 63}}\n",
      "tube.yaml:8:29: ", "seam 'left' panel is 'frnt'");
  /* a vertex inside the panel (11: column 4 of row 1), not on its boundary */
  bad(TUBE_HEAD TUBE_ARRANGE "seams:\n"
      "  - {name: left, a: {panel: front, from: 11, to: 34}, b: {panel: back, from: 35, to: 63}}\n",
      "tube.yaml:8:42: ", "seam 'left' a from is vertex 11, which is not on the boundary");
  /* a vertex of another panel */
  bad(TUBE_HEAD TUBE_ARRANGE "seams:\n"
      "  - {name: left, a: {panel: front, from: 6, to: 40}, b: {panel: back, from: 35, to: 63}}\n",
      "tube.yaml:8:49: ", "seam 'left' a to is vertex 40");
  /* two seams claiming one boundary segment */
  bad(TUBE_HEAD TUBE_ARRANGE TUBE_SEAMS
      "  - {name: again, a: {panel: front, from: 13, to: 27}, b: {panel: back, from: 42, to: 56}}\n",
      "tube.yaml:10:5: ", "seam 'again' claims the boundary edge (13, 20), which seam 'left'");
  /* curves whose lengths differ past the limit: the front's side (0.2 m) to half the back's
   * top (0.15 m) */
  bad(TUBE_HEAD TUBE_ARRANGE "seams:\n"
      "  - {name: odd, a: {panel: front, from: 6, to: 34}, b: {panel: back, from: 35, to: 38}}\n",
      "tube.yaml:8:5: ", "seam 'odd': its curves are 0.2 m (a) and 0.15 m (b) long");
  /* an arrangement that intersects the body: radius 7 cm inside a cylinder of 8 */
  bad(TUBE_HEAD "obstacles: [{mesh: cylinder.obj}]\n"
      "arrange:\n"
      "  front: {cylinder: {angle: 270, top: 0.1, radius: 0.07}}\n"
      "  back: {cylinder: {angle: 90, top: 0.1, radius: 0.11}}\n" TUBE_SEAMS,
      "tube.yaml:6:3: ", "arrange front: the piece lies inside obstacles[0]");
  /* one that crosses it: the back flat through the cylinder's axis */
  bad(TUBE_HEAD "obstacles: [{mesh: cylinder.obj}]\n"
      "arrange:\n"
      "  front: {cylinder: {angle: 270, top: 0.3, radius: 0.11}}\n"
      "  back: {rigid: {rotate: [90, 0, 0], translate: [0, 0, 0.1]}}\n" TUBE_SEAMS,
      "tube.yaml:7:3: ", "arrange back: the piece crosses obstacles[0]");
  /* pieces crossing each other */
  bad(TUBE_HEAD "arrange:\n"
      "  front: {cylinder: {angle: 270, top: 0.1, radius: 0.11}}\n"
      "  back: {cylinder: {angle: 300, top: 0.1, radius: 0.11}}\n" TUBE_SEAMS,
      "tube.yaml:5:3: ", "arrange front: the piece crosses piece back");
  /* a zero axis; a tilted axis placed by a point of two coordinates */
  bad(TUBE_HEAD "arrange:\n"
      "  front: {cylinder: {top: 0.1, radius: 0.11, axis: [0, 0, 0]}}\n",
      "tube.yaml:5:52: ", "arrange front cylinder axis is [0, 0, 0]; expected a nonzero direction");
  bad(TUBE_HEAD "arrange:\n"
      "  front: {cylinder: {top: 0.1, radius: 0.11, axis: [1, 0, 1], center: [0, 0]}}\n",
      "tube.yaml:5:", "arrange front cylinder center");
  /* a placement past the range of double */
  bad(TUBE_HEAD "arrange:\n"
      "  front: {cylinder: {top: 0.1, radius: 1e307, axis: [1, 0, 0], center: [1.7e308, 0, 0]}}\n",
      "tube.yaml:5:21: ", "arrange front cylinder puts vertex 0 at a non-finite place");
  /* an unknown piece */
  bad(TUBE_HEAD "arrange: {sleeve: {rigid: {translate: [0, 0, 0]}}}\n",
      "tube.yaml:4:11: ", "arrange names 'sleeve'");
  /* an `up` that is no axis of the pattern */
  bad(TUBE_HEAD "arrange: {front: {cylinder: {top: 0.1, radius: 0.11, up: w}}}\n",
      "tube.yaml:4:", "arrange front cylinder up");
  /* landmarks: a vertex of another panel; a corner past the list; a panel listing no
   * notches; both keys; a landmark inside the panel, not on its boundary */
  bad(TUBE_HEAD "panels: {front: {corners: [0, 6, 40]}}\n",
      "tube.yaml:4:", "panel front corners[2] is vertex 40, which no face of the panel holds");
#define LM_PANELS "panels: {front: {corners: [0, 6, 34, 28, 11]}, back: {}}\nseams:\n"
  bad(TUBE_HEAD LM_PANELS "  - {a: {panel: front, from: {corner: 4}, to: {corner: 5}},"
      " b: {panel: back, from: 35, to: 63}}\n",
      "tube.yaml:6:56: ", "a to corner is 5");
  bad(TUBE_HEAD LM_PANELS "  - {a: {panel: back, from: {notch: 0}, to: 63},"
      " b: {panel: front, from: 6, to: 34}}\n",
      "tube.yaml:6:", "names a notch of panel back, which lists no notches");
  bad(TUBE_HEAD LM_PANELS "  - {a: {panel: front, from: {corner: 0, notch: 0}, to: 28},"
      " b: {panel: back, from: 35, to: 63}}\n",
      "tube.yaml:6:", "has both corner and notch");
  bad(TUBE_HEAD LM_PANELS "  - {a: {panel: front, from: {corner: 4}, to: 34},"
      " b: {panel: back, from: 35, to: 63}}\n",
      "tube.yaml:6:", "a from is vertex 11, which is not on the boundary");
#undef LM_PANELS
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(conformance_ramp),
      cmocka_unit_test(conformance_closed),
      cmocka_unit_test(pairing),
      cmocka_unit_test(arrangement),
      cmocka_unit_test(arrangement_axis),
      cmocka_unit_test(arrangement_up),
      cmocka_unit_test(clearance_surfaces),
      cmocka_unit_test(junction),
      cmocka_unit_test(landmarks), cmocka_unit_test(auto_stiffness),
      cmocka_unit_test(tube_fit),
      cmocka_unit_test(tube_static),
      cmocka_unit_test(tube_optimize),
      cmocka_unit_test(bad_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
