/* harness.c — see harness.h. */
#include "harness.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
        H[(long)(v[i / d] * d + i % d) * n + v[j / d] * d + j % d] += b[i * w + j];
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
