/* model.c — the immutable model: rest shapes, lumped masses, the DOF map and the terms. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contact.h"
#include "contact_geom.h"
#include "dde.h"
#include "terms.h"
#include "util.h"

const char *const *sw_hessian_names(void) {
  static const char *const names[SW_HESSIAN_NMODES + 1] = {"projected", "exact", "auto", "abs",
                                                           "progressive", NULL};
  return names;
}

const char *const *sw_factor_names(void) {
  static const char *const names[SW_FACTOR_N + 1] = {"auto", "simplicial", "supernodal", NULL};
  return names;
}

const char *const *sw_ordering_names(void) {
  static const char *const names[SW_ORDERING_N + 1] = {"auto", "amd", "metis", "nesdis", NULL};
  return names;
}

const char *const *sw_bending_matrix_names(void) {
  static const char *const names[SW_BMATRIX_N + 1] = {"exact", "compact", "auto", NULL};
  return names;
}

const char *const *sw_norm_names(void) {
  static const char *const names[SW_NORM_N + 1] = {"rms", "max", NULL};
  return names;
}

const char *const *sw_frames_format_names(void) {
  static const char *const names[SW_FRAMES_N + 1] = {"binary", "binary32", "ascii",
                                                            NULL};
  return names;
}

sw_model *sw_model_new(void) {
  sw_model *m = sw_calloc(1, sizeof *m);
  if (!m) return NULL;
  m->dim = 3;
  sw_options *o = &m->opt;
  snprintf(o->method, sizeof o->method, "%s", "backward-euler");
  o->dt = 0.01;
  o->duration = 1.0;
  o->newton_max = 50;
  o->newton_tol = 1e-2; /* m/s: docs/integrators.md, "Newton" (measured) */
  o->newton_norm = SW_NORM_RMS;
  o->newton_force_tol = 1e-10;
  o->max_halvings = 8;
  o->hessian = SW_HESSIAN_DEFAULT; /* abs in 3D, projected in 2D (sw_model_finish) */
  o->bending_matrix = SW_BMATRIX_EXACT; /* a model built in code: its terms' own Hessians;
                                            a scene's default is auto (sw_scene_parse_ex) */
  o->newton_reuse = SW_REUSE_OFF;
  o->rtol = 1e-6;
  o->atol = 1e-8;
  o->max_order = 0; /* automatic: sw_max_order */
  o->max_step = 0.0;
  o->setup_every = 200;
  o->energy_bound = 0.0;
  o->frames_every = 0.0;
  o->positions_every = 0.0;
  o->restart_every = 60.0; /* s of wall time: a killed run loses at most a minute */
  o->frames_format = SW_FRAMES_BINARY32; /* docs/scenes.md, "Frames" (measured) */
  o->tx_clip = 5e4;
  o->tx_reference_uv = -1; /* sw_model_finish: uv with seams (a garment), else initial */
  o->tx_k_u = o->tx_k_v = -1.0;
  o->tendon_dense_max = SW_TENDON_DENSE_MAX;
  m->stiffness_scale = 1.0;
  m->nmat = 1;
  m->mat = sw_calloc(1, sizeof *m->mat);
  if (!m->mat) return sw_free(m), NULL;
  m->mat[0].b_u = m->mat[0].b_v = 1.0;
  m->mat[0].tx_k_u = m->mat[0].tx_k_v = -1.0;
  return m;
}

void sw_model_free(sw_model *m) {
  if (!m) return;
  for (int k = 0; k < m->nterm; k++) sw_term_free(&m->term[k]);
  sw_free(m->term);
  sw_free(m->input);
  sw_free(m->x0);
  sw_free(m->v0);
  sw_free(m->face);
  sw_free(m->uv);
  sw_free(m->dminv);
  sw_free(m->area);
  sw_free(m->mass);
  sw_free(m->point_mass);
  sw_free(m->pinned);
  for (int k = 0; k < m->nobstacle; k++) {
    sw_free(m->obstacle[k].key_t);
    sw_free(m->obstacle[k].key_d);
    sw_free(m->obstacle[k].rot_t);
    sw_free(m->obstacle[k].rot_a);
  }
  sw_free(m->obstacle);
  for (int k = 0; k < m->nmesh_obstacle; k++) {
    sw_obstacle *o = &m->mesh_obstacle[k];
    sw_free(o->key_t);
    sw_free(o->key_d);
    sw_free(o->rot_t);
    sw_free(o->rot_a);
    sw_free(o->mesh_x);
    sw_free(o->mesh_face);
  }
  sw_free(m->mesh_obstacle);
  sw_free(m->dof);
  sw_free(m->mat);
  sw_free(m->face_mat);
  sw_free(m->face_poly);
  for (int k = 0; k < m->ntendon; k++) {
    sw_free(m->tendon[k].way);
    sw_free(m->tendon[k].key_t);
    sw_free(m->tendon[k].key_rest);
  }
  sw_free(m->tendon);
  for (int k = 0; k < m->nseam; k++) {
    sw_free(m->seam[k].curve[0]);
    sw_free(m->seam[k].curve[1]);
    sw_free(m->seam[k].pair);
    sw_free(m->seam[k].w);
    sw_free(m->seam[k].len);
    sw_free(m->seam[k].gap0);
  }
  sw_free(m->seam);
  sw_free(m->sewn_ptr);
  sw_free(m->sewn_idx);
  sw_free(m->load);
  sw_free(m->load_ramp);
  sw_free(m);
}

static int check_faces(const sw_model *m, char *err, size_t errsz) {
  for (int f = 0; f < m->nf; f++) {
    const int *c = m->face + 3 * f;
    for (int i = 0; i < 3; i++)
      if (c[i] < 0 || c[i] >= m->nv) {
        sw_errf(err, errsz, "face %d: vertex %d outside the mesh (0..%d)", f, c[i], m->nv - 1);
        return -1;
      }
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
      sw_errf(err, errsz, "face %d repeats a vertex (%d %d %d)", f, c[0], c[1], c[2]);
      return -1;
    }
  }
  return 0;
}

/* Dm = [uv1-uv0, uv2-uv0] (Optitex, "Tension XY calculations explanation"; the 2D deformation gradient), its inverse and the rest area |det Dm|/2. */
static int rest_shapes(sw_model *m, int need_area, char *err, size_t errsz) {
  for (int f = 0; f < m->nf; f++) {
    const double *uv = m->uv + 6 * f;
    double a = uv[2] - uv[0], b = uv[4] - uv[0]; /* first row of Dm: du1, du2 */
    double c = uv[3] - uv[1], e = uv[5] - uv[1]; /* second row: dv1, dv2 */
    double det = a * e - b * c;
    double scale = fabs(a * e) + fabs(b * c);
    if (!(fabs(det) > 1e-12 * scale) || !isfinite(det)) {
      if (need_area && !isfinite(det)) /* e.g. a grid of 1e300 m: the product overflows */
        return sw_errf(err, errsz, "face %d has a rest area that overflows in its (u,v) layout "
                       "(2 x area = %g m^2); expected a smaller (u,v) extent", f, det), -1;
      if (need_area)
        return sw_errf(err, errsz, "face %d has zero rest area in its (u,v) layout (2 x area = "
                       "%g m^2 for edges of %g and %g m); expected a triangle of nonzero area",
                       f, det, hypot(a, c), hypot(b, e)), -1;
      memset(m->dminv + 4 * f, 0, 4 * sizeof(double));
      m->area[f] = 0.0;
      continue;
    }
    double *di = m->dminv + 4 * f;
    di[0] = e / det;
    di[1] = -b / det;
    di[2] = -c / det;
    di[3] = a / det;
    m->area[f] = 0.5 * fabs(det);
  }
  return 0;
}

/* Lumped mass: each triangle gives a third of density * area to each corner, each tendon
 * segment half of its linear density * initial length to each end (docs/tendons.md), and each
 * point mass (`masses`) goes to its vertex. */
static void lumped_mass(sw_model *m) {
  m->total_mass = 0.0;
  for (int f = 0; f < m->nf; f++) {
    double share = m->mat[m->face_mat[f]].density * m->area[f] / 3.0; /* kg */
    for (int i = 0; i < 3; i++) m->mass[m->face[3 * f + i]] += share;
    m->total_mass += 3.0 * share;
  }
  const int d = m->dim;
  for (int k = 0; k < m->ntendon; k++) {
    const sw_tendon *td = &m->tendon[k];
    for (int s = 0; s + 1 < td->nway; s++) {
      const double *a = m->x0 + (size_t)td->way[s] * d, *b = m->x0 + (size_t)td->way[s + 1] * d;
      double l = 0.0;
      for (int c = 0; c < d; c++) l += (a[c] - b[c]) * (a[c] - b[c]);
      double share = 0.5 * td->density * sqrt(l); /* kg */
      m->mass[td->way[s]] += share;
      m->mass[td->way[s + 1]] += share;
      m->total_mass += 2.0 * share;
    }
  }
  for (int i = 0; m->point_mass && i < m->nv; i++) {
    m->mass[i] += m->point_mass[i]; /* kg */
    m->total_mass += m->point_mass[i];
  }
}

static int dof_map(sw_model *m, char *err, size_t errsz) {
  int n = 0;
  for (int i = 0; i < m->nv; i++) {
    if (!m->pinned[i] && !(m->mass[i] > 0.0)) {
      sw_errf(err, errsz, "vertex %d is free but has no mass (in no face with area and density, "
              "on no tendon with density, no point mass); pin it or give it mass", i);
      return -1;
    }
    for (int a = 0; a < m->dim; a++) m->dof[i * m->dim + a] = m->pinned[i] ? -1 : n++;
  }
  m->ndof = n;
  return 0;
}

/* The terms a scene can hold, in the order they are built: each builder is called only when
 * the model uses it (no more model than the scene names). */
typedef int (*term_builder)(sw_term *t, const sw_model *m, char *err, size_t errsz);

static int uses_membrane(const sw_model *m, int model) {
  for (int k = 0; k < m->nmat; k++)
    if (m->mat[k].membrane == model) return 1;
  return 0;
}

static int uses_bending(const sw_model *m, int model) {
  for (int k = 0; k < m->nmat; k++)
    if (m->mat[k].bending == model) return 1;
  return 0;
}

static int add_term(sw_model *m, term_builder build, char *err, size_t errsz) {
  if (build(&m->term[m->nterm], m, err, errsz)) return sw_term_free(&m->term[m->nterm]), -1;
  m->nterm++;
  return 0;
}

#define SW_MAX_TERMS 16

static int build_terms(sw_model *m, char *err, size_t errsz) {
  static const struct { int model; term_builder build; } membranes[] = {
      {SW_MEMBRANE_BW98, sw_bw98_build},
      {SW_MEMBRANE_STVK, sw_stvk_build},
      {SW_MEMBRANE_COROTATED, sw_corotated_build},
      {SW_MEMBRANE_SPRINGS, sw_springs_build},
      {SW_MEMBRANE_DDE, sw_dde_build},
  };
  static const struct { int model; term_builder build; } bendings[] = {
      {SW_BENDING_DIHEDRAL, sw_dihedral_build},
      {SW_BENDING_QUADRATIC, sw_quadratic_bending_build},
      {SW_BENDING_MORLEY, sw_morley_bending_build},
      {SW_BENDING_DDE, sw_dde_bending_build},
  };
  m->term = sw_calloc(SW_MAX_TERMS, sizeof *m->term);
  if (!m->term) return sw_errf(err, errsz, "out of memory"), -1;
  for (size_t k = 0; k < sizeof membranes / sizeof *membranes; k++)
    if (uses_membrane(m, membranes[k].model) && add_term(m, membranes[k].build, err, errsz))
      return -1;
  for (size_t k = 0; k < sizeof bendings / sizeof *bendings; k++)
    if (bendings[k].build && uses_bending(m, bendings[k].model) &&
        add_term(m, bendings[k].build, err, errsz))
      return -1;
  if (m->ntendon > 0 && add_term(m, sw_tendon_build, err, errsz)) return -1;
  if (m->nseam > 0 && add_term(m, sw_seam_build, err, errsz)) return -1;
  if (m->has_gravity && add_term(m, sw_gravity_build, err, errsz)) return -1;
  if (m->load && add_term(m, sw_point_load_build, err, errsz)) return -1;
  if (m->nobstacle > 0) {
    if (m->contact.kappa <= 0.0) {
      m->contact.kappa = sw_contact_auto_kappa(m); /* 1/s^2 */
      m->contact.kappa_auto = 1;
    }
    if (add_term(m, sw_contact_build, err, errsz)) return -1;
  }
  if (sw_mesh_contact_on(m)) {
    if (m->contact.kappa_mesh <= 0.0) {
      m->contact.kappa_mesh = sw_mesh_contact_auto_kappa(m); /* adapted in the run */
      m->contact.kappa_mesh_auto = 1;
    }
    if (add_term(m, sw_mesh_contact_build, err, errsz)) return -1;
  }
  return 0;
}

/* Rotate the (u,v) layout of every face whose panel has a bias angle, so that the warp axis
 * (cos b, sin b) in (u,v) becomes the u axis every membrane and tension XY read. */
static void apply_bias(sw_model *m) {
  for (int f = 0; f < m->nf; f++) {
    double b = m->mat[m->face_mat[f]].bias; /* rad */
    if (b == 0.0) continue;
    double c = cos(b), s = sin(b);
    for (int i = 0; i < 3; i++) {
      double *uv = m->uv + 6 * f + 2 * i, u = uv[0], v = uv[1];
      uv[0] = c * u + s * v;
      uv[1] = -s * u + c * v;
    }
  }
}

/* The stiffness tension XY uses on each panel: the scene's tension_xy k_u/k_v if given, else
 * the active membrane's warp and weft stiffness (docs/models.md has the mapping). */
static void tension_stiffness(sw_model *m) {
  for (int k = 0; k < m->nmat; k++) {
    sw_material *mt = &m->mat[k];
    double ku = 0.0, kv = 0.0; /* N/m */
    switch (mt->membrane) {
    case SW_MEMBRANE_BW98: ku = mt->k_u, kv = mt->k_v; break;
    case SW_MEMBRANE_STVK: ku = mt->e_u, kv = mt->e_v; break;
    case SW_MEMBRANE_COROTATED: ku = kv = mt->k_corot; break;
    case SW_MEMBRANE_SPRINGS: ku = kv = mt->ks_stretch; break;
    case SW_MEMBRANE_DDE: /* zero-strain strip, free across (models/dde.c) */
      sw_dde_strip_stiffness(mt->dde.stretch[0], &ku, &kv);
      break;
    default: break;
    }
    mt->tx_dde = mt->membrane == SW_MEMBRANE_DDE && mt->tx_k_u < 0 && mt->tx_k_v < 0 &&
                 m->opt.tx_k_u < 0 && m->opt.tx_k_v < 0;
    if (mt->tx_k_u < 0) mt->tx_k_u = m->opt.tx_k_u >= 0 ? m->opt.tx_k_u : ku;
    if (mt->tx_k_v < 0) mt->tx_k_v = m->opt.tx_k_v >= 0 ? m->opt.tx_k_v : kv;
  }
}

static int check_tendons(const sw_model *m, char *err, size_t errsz) {
  for (int k = 0; k < m->ntendon; k++) {
    const sw_tendon *td = &m->tendon[k];
    if (td->nway < 2 || !td->way || td->nkey < 1 || !td->key_t || !td->key_rest)
      return sw_errf(err, errsz, "tendon %s: fewer than 2 waypoints or no rest length",
                     td->name), -1;
    int dense_max = m->opt.tendon_dense_max; /* the term's rule (models/tendon.c) */
    if (td->damping > 0.0 && td->nway > dense_max)
      return sw_errf(err, errsz, "tendon %s: damping on a tendon of %d waypoints is not supported "
                     "(at most tendon_dense_max = %d: longer tendons keep their rank-one part "
                     "out of the sparse system); expected no damping, or a shorter tendon",
                     td->name, td->nway, dense_max), -1;
    for (int i = 0; i < td->nway; i++)
      if (td->way[i] < 0 || td->way[i] >= m->nv)
        return sw_errf(err, errsz, "tendon %s: waypoint %d outside the mesh (0..%d)", td->name,
                       td->way[i], m->nv - 1), -1;
  }
  return 0;
}

/* splitmix64 (G. Steele, D. Lea, C. Flood, "Fast Splittable Pseudorandom Number Generators",
 * OOPSLA 2014): a uniform number in [-1, 1) from the state. */
static double uniform(unsigned long long *state) {
  unsigned long long z = (*state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1.0p-52 - 1.0;
}

/* The area-weighted normal of every vertex at x0 into n (nv x 3, unit; 0 for a vertex in no
 * face or whose faces cancel). */
static void vertex_normals(const sw_model *m, double *n) {
  for (int f = 0; f < m->nf; f++) {
    const int *v = m->face + 3 * f;
    const double *a = m->x0 + 3 * v[0], *b = m->x0 + 3 * v[1], *c = m->x0 + 3 * v[2];
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0]};
    for (int i = 0; i < 3; i++)
      for (int k = 0; k < 3; k++) n[3 * v[i] + k] += fn[k];
  }
  for (int i = 0; i < m->nv; i++) {
    double *ni = n + 3 * i, l = sqrt(ni[0] * ni[0] + ni[1] * ni[1] + ni[2] * ni[2]);
    for (int k = 0; k < 3; k++) ni[k] = l > 0.0 ? ni[k] / l : 0.0;
  }
}

#define PERTURB_WAVES 6 /* plane waves in the perturbation field */
#define PERTURB_PI 3.14159265358979323846

/* The bounding-box diagonal of x0 (m) and its lower corner. */
static double bbox(const sw_model *m, double lo[3]) {
  double hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, d2 = 0.0;
  lo[0] = lo[1] = lo[2] = HUGE_VAL;
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < 3; a++) {
      lo[a] = fmin(lo[a], m->x0[3 * i + a]);
      hi[a] = fmax(hi[a], m->x0[3 * i + a]);
    }
  for (int a = 0; a < 3; a++) d2 += (hi[a] - lo[a]) * (hi[a] - lo[a]);
  return sqrt(d2);
}

/* The smooth field w(x) = sum_k a_k sin(k_k . x + phi_k), PERTURB_WAVES waves of random
 * direction, wavelength D/2 .. D (D the diagonal), amplitude a_k and phase phi_k, times a taper
 * from 0 at the pinned vertices to 1 at D/4 from them (the quintic ramp): one value per
 * vertex into w.  Smooth in space and defined by position, not by index. */
static void smooth_field(const sw_model *m, unsigned long long *state, double *w) {
  double lo[3], D = bbox(m, lo), k[PERTURB_WAVES][3], a[PERTURB_WAVES], ph[PERTURB_WAVES];
  for (int q = 0; q < PERTURB_WAVES; q++) {
    double dir[3] = {uniform(state), uniform(state), uniform(state)}, l = 0.0;
    for (int c = 0; c < 3; c++) l += dir[c] * dir[c];
    double kk = 2.0 * PERTURB_PI / D * (1.5 + 0.5 * uniform(state)) / (l > 0.0 ? sqrt(l) : 1.0);
    for (int c = 0; c < 3; c++) k[q][c] = l > 0.0 ? kk * dir[c] : 0.0; /* 1/m */
    a[q] = uniform(state);
    ph[q] = PERTURB_PI * uniform(state);
  }
  for (int i = 0; i < m->nv; i++) {
    const double *x = m->x0 + 3 * i;
    double v = 0.0, dmin = HUGE_VAL;
    for (int q = 0; q < PERTURB_WAVES; q++)
      v += a[q] * sin(k[q][0] * (x[0] - lo[0]) + k[q][1] * (x[1] - lo[1]) +
                      k[q][2] * (x[2] - lo[2]) + ph[q]);
    for (int j = 0; j < m->nv; j++) {
      if (!m->pinned[j]) continue;
      double d2 = 0.0;
      for (int c = 0; c < 3; c++) d2 += (x[c] - m->x0[3 * j + c]) * (x[c] - m->x0[3 * j + c]);
      dmin = fmin(dmin, d2);
    }
    w[i] = v * sw_ramp(sqrt(dmin), 0.25 * D);
  }
}

/* `perturb` (docs/scenes.md): each free vertex of a 3D model moves along its normal by the
 * smooth field of smooth_field, scaled so that its largest value is the amplitude; a vertex in
 * no face does not move.  After the terms are built, so rest angles and lengths are those of
 * the mesh. */
static int perturb(sw_model *m, char *err, size_t errsz) {
  if (!(m->perturb_amplitude > 0.0)) return 0;
  if (m->dim != 3) return sw_errf(err, errsz, "perturb needs dimension 3"), -1;
  double *n = sw_calloc((size_t)m->nv * 4, sizeof *n), *w = n + 3 * (size_t)m->nv, wmax = 0.0;
  if (!n) return sw_errf(err, errsz, "out of memory"), -1;
  vertex_normals(m, n);
  unsigned long long state = m->perturb_seed;
  smooth_field(m, &state, w);
  for (int i = 0; i < m->nv; i++) wmax = fmax(wmax, fabs(w[i]));
  for (int i = 0; wmax > 0.0 && i < m->nv; i++) {
    double s = m->pinned[i] ? 0.0 : m->perturb_amplitude * w[i] / wmax; /* m */
    for (int c = 0; c < 3; c++) m->x0[3 * i + c] += s * n[3 * i + c];
  }
  sw_free(n);
  return 0;
}

int sw_model_finish(sw_model *m, char *err, size_t errsz) {
  if (m->dim != 2 && m->dim != 3) return sw_errf(err, errsz, "dimension must be 2 or 3"), -1;
  if (m->nv <= 0) return sw_errf(err, errsz, "the model has no vertices"), -1;
  if (!m->x0 || !m->v0 || !m->pinned || (m->nf > 0 && (!m->face || !m->uv)))
    return sw_errf(err, errsz, "model arrays missing"), -1;
  if (check_faces(m, err, errsz) || check_tendons(m, err, errsz)) return -1;
  if (!m->face_mat && !(m->face_mat = sw_calloc((size_t)m->nf + 1, sizeof(int))))
    return sw_errf(err, errsz, "out of memory"), -1;
  for (int f = 0; f < m->nf; f++)
    if (m->face_mat[f] < 0 || m->face_mat[f] >= m->nmat)
      return sw_errf(err, errsz, "face %d: material %d outside 0..%d", f, m->face_mat[f],
                     m->nmat - 1), -1;
  /* measured (docs/integrators.md, "Newton"): in 3D a compressed element's absolute-value
   * curvature lets the cloth buckle out of its plane in few iterations; in 2D it cannot, and
   * clamping converges where abs overshoots */
  if (m->opt.hessian == SW_HESSIAN_DEFAULT)
    m->opt.hessian = m->dim == 3 ? SW_HESSIAN_ABS : SW_HESSIAN_PROJECTED;
  if (m->opt.tx_reference_uv < 0) m->opt.tx_reference_uv = m->nseam > 0;
  /* measured (docs/performance.md, "The bending matrix"): compact wherever inertia sits
   * beside the bending; a static solve with it did not converge on a cantilever */
  if (m->opt.bending_matrix == SW_BMATRIX_AUTO)
    m->opt.bending_matrix = strcmp(m->opt.method, "static") && m->fit.mode == SW_FIT_DYNAMIC
                                ? SW_BMATRIX_COMPACT : SW_BMATRIX_EXACT;
  apply_bias(m);
  size_t nd = (size_t)m->nv * (size_t)m->dim;
  m->dminv = sw_calloc((size_t)m->nf, 4 * sizeof(double));
  m->area = sw_calloc((size_t)m->nf, sizeof(double));
  m->mass = sw_calloc((size_t)m->nv, sizeof(double));
  m->dof = sw_calloc(nd, sizeof(int));
  if (!m->dminv || !m->area || !m->mass || !m->dof)
    return sw_errf(err, errsz, "out of memory"), -1;
  int need_area = 0;
  for (int k = 0; k < m->nmat; k++)
    need_area |= m->mat[k].membrane != SW_MEMBRANE_NONE || m->mat[k].bending != SW_BENDING_NONE ||
                 m->mat[k].density > 0.0;
  if (rest_shapes(m, need_area, err, errsz)) return -1;
  lumped_mass(m);
  if (dof_map(m, err, errsz)) return -1;
  tension_stiffness(m);
  if (m->nseam > 0 && !(m->seam_stiffness > 0.0)) m->seam_stiffness = sw_seam_auto_stiffness(m);
  if (sw_seam_sewn(m, err, errsz) || build_terms(m, err, errsz)) return -1;
  if (perturb(m, err, errsz)) return -1;
  return sw_seam_start(m, err, errsz); /* the seams' starting gaps, from the final x0 */
}

void sw_model_print(const sw_model *m, void *file) {
  FILE *fp = file;
  int npin = 0;
  for (int i = 0; i < m->nv; i++) npin += m->pinned[i];
  double area = 0.0;
  for (int f = 0; f < m->nf; f++) area += m->area[f];
  fprintf(fp, "scene       %s (%s)\n", m->name, m->path);
  fprintf(fp, "dimension   %d\n", m->dim);
  fprintf(fp, "vertices    %d (%d pinned)\n", m->nv, npin);
  fprintf(fp, "faces       %d\n", m->nf);
  fprintf(fp, "rest area   %.6g m^2\n", area);
  for (int k = 0; m->nmat > 1 && k < m->nmat; k++) {
    double a = 0.0; /* m^2 */
    for (int f = 0; f < m->nf; f++) a += m->face_mat[f] == k ? m->area[f] : 0.0;
    fprintf(fp, "  panel %-12s %.6g m^2\n", k ? m->mat[k].group : "(material)", a);
  }
  if (m->ntendon) fprintf(fp, "tendons     %d\n", m->ntendon);
  fprintf(fp, "mass        %.6g kg\n", m->total_mass);
  fprintf(fp, "free DOFs   %d\n", m->ndof);
  if (m->stiffness_scale > 0 && m->stiffness_scale != 1.0)
    fprintf(fp, "stiffness   x %g (every elastic stiffness of the scene)\n", m->stiffness_scale);
  fprintf(fp, "terms      ");
  for (int k = 0; k < m->nterm; k++) fprintf(fp, " %s", m->term[k].name);
  fprintf(fp, "%s\n", m->nterm ? "" : " (none)");
  for (int i = 0, j = 0; i < m->nobstacle || j < m->nmesh_obstacle;) { /* in the scene's order */
    int shape = j == m->nmesh_obstacle ||
                (i < m->nobstacle && m->obstacle[i].item <= m->mesh_obstacle[j].item);
    const sw_obstacle *o = shape ? &m->obstacle[i++] : &m->mesh_obstacle[j++];
    if (shape)
      fprintf(fp, "obstacle %d  %s", o->item, sw_shape_names()[o->shape]);
    else
      fprintf(fp, "obstacle %d  mesh, %d vertices, %d faces", o->item, o->mesh_nv, o->mesh_nf);
    fprintf(fp, "%s, offset %g m\n", o->nkey > 1 && o->nrot > 1 ? " (moving and turning)" : o->nkey > 1 ? " (moving)" : o->nrot > 1 ? " (turning)" : "", o->offset);
  }
  if (m->nobstacle)
    fprintf(fp, "contact     distance %g m, stiffness %g 1/s^2%s, friction %g\n", m->contact.dhat,
            m->contact.kappa, m->contact.kappa_auto ? " (automatic)" : "", m->contact.friction);
  if (m->contact.self)
    fprintf(fp, "self        distance %g m, thickness %g m, stiffness %g 1/(s^2 m^2)%s, "
            "friction %g\n", m->contact.dhat, m->contact.thickness, m->contact.kappa_mesh,
            m->contact.kappa_mesh_auto ? " (automatic, at the start)" : "", m->contact.self_friction);
  else if (m->nmesh_obstacle) /* the mesh obstacles' pairs use the same kappa_mesh */
    fprintf(fp, "mesh        distance %g m, stiffness %g 1/(s^2 m^2)%s, friction %g\n",
            m->contact.dhat, m->contact.kappa_mesh,
            m->contact.kappa_mesh_auto ? " (automatic, at the start)" : "", m->contact.friction);
  for (int k = 0; k < m->nseam; k++) {
    const sw_seam *sm = &m->seam[k];
    fprintf(fp, "seam %-7s %s %d vertices (%.4g m) to %s %d vertices (%.4g m), %d pairs\n",
            sm->name, sm->group[0], sm->n[0], sm->length[0], sm->group[1], sm->n[1],
            sm->length[1], sm->npair);
  }
  if (m->nseam)
    fprintf(fp, "sewing      stiffness %g N/m^2, ramp %g s; fit %s%s\n", m->seam_stiffness,
            m->seam_ramp, m->fit.on ? "on" : "off",
            !m->fit.on ? "" : m->fit.mode == SW_FIT_OPTIMIZE ? " (optimize)"
                            : m->fit.mode == SW_FIT_SETTLE   ? " (settle)" : " (dynamic)");
  if (m->dim == 3 && m->nf > 1) /* an exact test, independent of the solver */
    fprintf(fp, "crossings   %ld face pairs intersect at the start\n",
            sw_mesh_self_intersections_sewn(m->nv, m->x0, m->nf, m->face, m->sewn_ptr,
                                            m->sewn_idx));
  fprintf(fp, "system nnz  %ld (upper triangle, free DOFs)\n", sw_system_nnz(m));
  fprintf(fp, "integrator  %s, dt = %g s, duration = %g s\n", m->opt.method, m->opt.dt,
          m->opt.duration);
  fprintf(fp, "output      %s\n", m->opt.out_dir);
}
