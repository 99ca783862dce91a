/* harness.c — see harness.h. */
#include "harness.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "scene.h"

double th_rand(unsigned long *s) {
  *s = *s * 6364136223846793005UL + 1442695040888963407UL;
  return (double)(*s >> 11) / (double)(1UL << 52) - 1.0;
}

sw_model *th_grid_unfinished(int dim, int nx, int ny, double sx, double sy) {
  sw_mesh mesh;
  char err[SW_ERRSZ];
  double size[2] = {sx, sy};
  if (sw_mesh_grid(&mesh, size, nx, ny, "xy", err, sizeof err)) return NULL;
  sw_model *m = sw_model_new();
  m->dim = dim;
  m->nv = mesh.nv;
  m->nf = mesh.nf;
  m->x0 = calloc((size_t)m->nv * dim, sizeof(double));
  m->v0 = calloc((size_t)m->nv * dim, sizeof(double));
  m->pinned = calloc((size_t)m->nv, 1);
  m->face = calloc((size_t)m->nf * 3, sizeof(int));
  m->uv = calloc((size_t)m->nf * 6, sizeof(double));
  for (int i = 0; i < m->nv; i++)
    for (int a = 0; a < dim; a++) m->x0[i * dim + a] = mesh.x[i * 3 + a];
  for (int f = 0; f < m->nf; f++)
    for (int c = 0; c < 3; c++) {
      m->face[3 * f + c] = mesh.f[3 * f + c];
      m->uv[6 * f + 2 * c] = mesh.uv[2 * mesh.fuv[3 * f + c]];
      m->uv[6 * f + 2 * c + 1] = mesh.uv[2 * mesh.fuv[3 * f + c] + 1];
    }
  m->face_poly = calloc((size_t)m->nf, sizeof(int));
  memcpy(m->face_poly, mesh.fpoly, (size_t)m->nf * sizeof(int));
  sw_mesh_free(&mesh);
  return m;
}

sw_model *th_jittered_unfinished(int dim, int nx, int ny, unsigned long seed) {
  sw_model *m = th_grid_unfinished(dim, nx, ny, 0.3, 0.25);
  if (!m) return NULL;
  const double hx = 0.3 / (nx - 1), hy = 0.25 / (ny - 1);
  for (int j = 1; j < ny - 1; j++)
    for (int i = 1; i < nx - 1; i++) {
      double *x = m->x0 + (size_t)dim * (j * nx + i);
      x[0] += 0.2 * hx * th_rand(&seed), x[1] += 0.2 * hy * th_rand(&seed);
    }
  for (int f = 0; f < m->nf; f++)
    for (int c = 0; c < 3; c++)
      memcpy(m->uv + 6 * f + 2 * c, m->x0 + (size_t)dim * m->face[3 * f + c], 2 * sizeof(double));
  return m;
}

sw_model *th_finish(sw_model *m) {
  char err[SW_ERRSZ];
  if (sw_model_finish(m, err, sizeof err)) {
    sw_model_free(m);
    return NULL;
  }
  return m;
}

sw_model *th_grid_model_mat(int dim, int nx, int ny, double sx, double sy,
                            const sw_material *mat) {
  sw_model *m = th_grid_unfinished(dim, nx, ny, sx, sy);
  if (!m) return NULL;
  m->mat[0] = *mat;
  return th_finish(m);
}

sw_model *th_grid_start(int dim, int nx, int ny, double sx, double sy, double rho, double kuv,
                        double kshear, const double *g, int pin_top) {
  sw_model *m = th_grid_unfinished(dim, nx, ny, sx, sy);
  if (!m) return NULL;
  m->mat[0].density = rho;
  if (kuv > 0) {
    m->mat[0].membrane = SW_MEMBRANE_BW98;
    m->mat[0].k_u = kuv;
    m->mat[0].k_v = 0.7 * kuv; /* warp and weft differ */
    m->mat[0].k_shear = kshear;
  }
  if (g) {
    m->has_gravity = 1;
    for (int a = 0; a < dim; a++) m->gravity[a] = g[a];
  }
  if (pin_top)
    for (int i = 0; i < nx; i++) m->pinned[(ny - 1) * nx + i] = 1;
  return m;
}

sw_model *th_grid_model(int dim, int nx, int ny, double sx, double sy, double rho, double kuv,
                        double kshear, const double *g, int pin_top) {
  sw_model *m = th_grid_start(dim, nx, ny, sx, sy, rho, kuv, kshear, g, pin_top);
  return m ? th_finish(m) : NULL;
}

void th_add_tendon(sw_model *m, const int *way, int nway, int law, double K, double rest,
                   double density) {
  m->tendon = realloc(m->tendon, sizeof(sw_tendon) * (size_t)(m->ntendon + 1));
  sw_tendon *td = &m->tendon[m->ntendon++];
  memset(td, 0, sizeof *td);
  snprintf(td->name, sizeof td->name, "t%d", m->ntendon - 1);
  td->law = law;
  td->stiffness = K;
  td->nway = nway;
  td->way = malloc(sizeof(int) * (size_t)nway);
  memcpy(td->way, way, sizeof(int) * (size_t)nway);
  td->nkey = 1;
  td->key_t = calloc(1, sizeof(double));
  td->key_rest = malloc(sizeof(double));
  td->key_rest[0] = rest;
  td->density = density;
}

void th_fill_dominant(const sw_pattern *p, double *v) {
  for (long q = 0; q < p->nnz; q++) v[q] = -0.01;
  for (int c = 0; c < p->n; c++) v[p->diag[c]] = 1.0; /* DOF c's, in whichever column */
}

void th_dense_hessian(const sw_model *m, int k, const double *blocks, double *H) {
  const int d = m->dim, n = m->nv * d;
  const sw_term *t = &m->term[k];
  memset(H, 0, sizeof(double) * (size_t)n * n);
  for (int s = 0; s < t->nstencil; s++) {
    int len = t->sptr[s + 1] - t->sptr[s], w = len * d;
    const int *v = t->sidx + t->sptr[s];
    const double *b = blocks + t->hptr[s];
    for (int i = 0; i < w; i++)
      for (int j = 0; j < w; j++)
        H[(long)(v[i / d] * d + i % d) * n + v[j / d] * d + j % d] += sw_hess_get(b, i, j, w);
  }
}

void th_dense_lowrank(const sw_model *m, int k, const double *vecs, double *H) {
  const int d = m->dim, n = m->nv * d;
  const sw_term *t = &m->term[k];
  for (int r = 0; r < t->nlowrank; r++) {
    int w = (t->lptr[r + 1] - t->lptr[r]) * d;
    const int *v = t->lidx + t->lptr[r];
    const double *u = vecs + (long)t->lptr[r] * d;
    for (int i = 0; i < w; i++)
      for (int j = 0; j < w; j++)
        H[(long)(v[i / d] * d + i % d) * n + v[j / d] * d + j % d] += u[i] * u[j];
  }
}

double th_max_diff(const double *a, const double *b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s = fmax(s, fabs(a[i] - b[i]));
  return s;
}

double th_slope(const double *h, const double *e, int n) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int i = 0; i < n; i++) {
    double lx = log(h[i]), ly = log(e[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/* ------------------------------------------------------------ elastic catenary */

/* Written without cancellation, so that a taut cable (V/H and (V - W)/H tiny) keeps its sag:
 * asinh a - asinh b = asinh(a sqrt(1 + b^2) - b sqrt(1 + a^2)) and
 * sqrt(1 + a^2) - sqrt(1 + b^2) = (a - b)(a + b) / (sqrt(1 + a^2) + sqrt(1 + b^2)). */
void th_irvine_conditions(const th_irvine *c, double H, double V, double f[2], double J[4]) {
  const double L0 = c->L0, EA = c->EA, W = c->W;
  double a = V / H, b = (V - W) / H, A = sqrt(1.0 + a * a), B = sqrt(1.0 + b * b);
  double dasinh = asinh(a * B - b * A), dsqrt = (W / H) * (a + b) / (A + B);
  f[0] = H * L0 / EA + H * L0 / W * dasinh - c->l;
  f[1] = L0 / EA * (V - 0.5 * W) + H * L0 / W * dsqrt - c->h;
  double dinv = -dsqrt / (A * B);                                     /* 1/A - 1/B */
  J[0] = L0 / EA + L0 / W * (dasinh - a / A + b / B);                 /* d f1 / dH */
  J[1] = L0 / W * dinv;                                               /* d f1 / dV */
  J[2] = J[1];                                                        /* d f2 / dH */
  J[3] = L0 / EA + L0 / W * (a / A - b / B);                          /* d f2 / dV */
}

int th_irvine_solve(th_irvine *c) {
  /* Start from the parabola of the inextensible cable: its length l + 8 f^2/(3 l) (f the sag
   * below the chord) is L0, H = W l / (8 f), and V carries half the weight plus the chord's
   * share; a cable that is taut or nearly so starts from a sag of l/1000. */
  double chord = sqrt(c->l * c->l + c->h * c->h), size = fmax(chord, c->L0);
  double f0 = fmax(sqrt(3.0 * c->l * fmax(c->L0 - chord, 0.0) / 8.0), 1e-3 * c->l);
  double H = c->W * c->l / (8.0 * f0), V = 0.5 * c->W + H * c->h / c->l, f[2], J[4];
  for (int it = 0; it < 200; it++) {
    th_irvine_conditions(c, H, V, f, J);
    double r = hypot(f[0], f[1]);
    if (r <= 1e-13 * size) {
      c->H = H, c->V = V;
      return 0;
    }
    double det = J[0] * J[3] - J[1] * J[2];
    double dH = -(J[3] * f[0] - J[1] * f[1]) / det, dV = -(J[0] * f[1] - J[2] * f[0]) / det;
    /* halve until H stays positive and the residual falls */
    for (double t = 1.0; t > 1e-12; t *= 0.5) {
      double Ht = H + t * dH, Vt = V + t * dV, ft[2], Jt[4];
      if (!(Ht > 0.0)) continue;
      th_irvine_conditions(c, Ht, Vt, ft, Jt);
      if (hypot(ft[0], ft[1]) < r || t < 1e-6) {
        H = Ht, V = Vt;
        break;
      }
    }
  }
  return -1;
}

void th_irvine_point(const th_irvine *c, double s, double *x, double *z) {
  const double H = c->H, V = c->V, W = c->W, L0 = c->L0, EA = c->EA;
  double a = V / H, q = (V - W * s / L0) / H, A = sqrt(1.0 + a * a), Q = sqrt(1.0 + q * q);
  *x = H * s / EA + H * L0 / W * asinh(a * Q - q * A);
  *z = W * s / EA * (V / W - s / (2.0 * L0)) + s * (a + q) / (A + Q); /* (H L0/W)(A - Q) */
}

/* ------------------------------------------------------------ fixtures */

sw_model *th_scene(const char *name, const char *text) {
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_parse(name, text, strlen(text), err, sizeof err);
  if (!m) fprintf(stderr, "%s\n", err);
  return m;
}

sw_model *th_scene_file(const char *path) {
  char err[SW_ERRSZ];
  sw_model *m = sw_scene_load(path, err, sizeof err);
  if (!m) fprintf(stderr, "%s\n", err);
  return m;
}

double th_peirce_angle(const sw_model *m) {
  char err[SW_ERRSZ];
  sw_data *d = sw_data_new(m);
  double reaction[3], xmax = 0.0, h = 1e9, tip[3] = {0};
  int ntip = 0;
  if (!d || sw_static_solve(m, d, reaction, err, sizeof err)) {
    fprintf(stderr, "%s\n", d ? err : "out of memory for the state");
    sw_data_free(d);
    return NAN;
  }
  for (int i = 0; i < m->nv; i++) {
    xmax = fmax(xmax, m->x0[3 * i]);
    if (m->x0[3 * i] > 1e-12) h = fmin(h, m->x0[3 * i]);
  }
  for (int i = 0; i < m->nv; i++)
    if (m->x0[3 * i] > xmax - 1e-12)
      for (int a = 0; a < 3; a++) tip[a] += d->x[3 * i + a], ntip += a == 0;
  sw_data_free(d);
  return atan2(-tip[2] / ntip, tip[0] / ntip - 0.5 * h) * 180.0 / 3.14159265358979323846;
}

sw_data *th_start(const sw_integrator_ops *ops, const sw_model *m, void **s) {
  char err[SW_ERRSZ];
  sw_data *d = sw_data_new(m);
  *s = NULL;
  if (!d) return fprintf(stderr, "%s: out of memory for the state\n", ops->name), NULL;
  if (ops->init(s, m, d, err, sizeof err) == 0) return d;
  fprintf(stderr, "%s: init: %s\n", ops->name, err);
  sw_data_free(d);
  return NULL;
}

int th_static(const sw_model *m, sw_data *d, double r[3]) {
  char err[SW_ERRSZ];
  int rc = sw_static_solve(m, d, r, err, sizeof err);
  if (rc) fprintf(stderr, "%s\n", err);
  return rc;
}

/* ---------------------------------------------------------------- files */

char *th_slurp(const char *path) { return th_slurp_n(path, NULL); }

char *th_slurp_n(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t cap = 4096, n = 0, got;
  char *s = malloc(cap);
  while (s && (got = fread(s + n, 1, cap - n - 1, f)) > 0) {
    n += got;
    if (cap - n - 1 == 0) s = realloc(s, cap *= 2);
  }
  fclose(f);
  if (s) s[n] = '\0';
  if (size) *size = n;
  return s;
}

char *th_slurp_in(const char *dir, const char *name) {
  char path[SW_PATHSZ + 64];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return th_slurp(path);
}

int th_exists_in(const char *dir, const char *name) {
  char path[SW_PATHSZ + 64];
  struct stat st;
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return stat(path, &st) == 0;
}

void th_remove_tree(const char *path) {
  struct stat st;
  if (lstat(path, &st)) return;
  if (S_ISDIR(st.st_mode)) {
    DIR *dp = opendir(path);
    struct dirent *e;
    while (dp && (e = readdir(dp))) {
      if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
      char sub[SW_PATHSZ + 256];
      snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
      th_remove_tree(sub);
    }
    if (dp) closedir(dp);
  }
  remove(path);
}
