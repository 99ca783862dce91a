/* mesh.c — struct sw_mesh: freeing, and the regular grid generator.
 *
 * Units: positions and (u,v) in metres. */
#include "sinew.h"
#include "util.h"

#include <math.h>
#include <string.h>

#define GRID_MAX_VERTICES 50000000LL /* nx * ny above this is refused */

void sw_mesh_free(sw_mesh *mesh) {
  if (!mesh) return;
  sw_free(mesh->x);
  sw_free(mesh->uv);
  sw_free(mesh->f);
  sw_free(mesh->fuv);
  sw_free(mesh->fgroup);
  sw_free(mesh->fpoly);
  sw_free(mesh->group);
  memset(mesh, 0, sizeof *mesh);
}

/* Which position component takes u and which takes v; the third one is 0. */
static int grid_axes(const char *plane, int *au, int *av) {
  if (!plane) return -1;
  if (strcmp(plane, "xy") == 0) { *au = 0; *av = 1; return 0; }
  if (strcmp(plane, "xz") == 0) { *au = 0; *av = 2; return 0; }
  if (strcmp(plane, "yz") == 0) { *au = 1; *av = 2; return 0; }
  return -1;
}

static int grid_check(const double size[2], int nx, int ny, const char *plane, char *err,
                      size_t errsz) {
  int au, av;
  if (!size) { sw_errf(err, errsz, "grid: size is NULL, expected two lengths in m"); return -1; }
  for (int k = 0; k < 2; k++)
    if (!isfinite(size[k]) || !(size[k] > 0)) {
      sw_errf(err, errsz, "grid: size[%d] = %g m, expected a finite length > 0", k, size[k]);
      return -1;
    }
  if (nx < 2 || ny < 2) {
    sw_errf(err, errsz, "grid: %d x %d vertices, expected at least 2 x 2", nx, ny);
    return -1;
  }
  if ((long long)nx * ny > GRID_MAX_VERTICES) {
    sw_errf(err, errsz, "grid: %d x %d vertices, expected at most %lld in all", nx, ny,
            GRID_MAX_VERTICES);
    return -1;
  }
  if (grid_axes(plane, &au, &av)) {
    sw_errf(err, errsz, "grid: plane \"%.32s\", expected \"xy\", \"xz\" or \"yz\"",
            plane ? plane : "(null)");
    return -1;
  }
  return 0;
}

/* Positions (m) and the (u,v) layout (m) of every vertex. */
static void grid_vertices(sw_mesh *mesh, const double size[2], int nx, int ny, int au, int av) {
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      int k = j * nx + i;
      /* u = i * size[0] / (nx - 1), m; the fraction first, so the far edge is exactly size */
      double u = size[0] * ((double)i / (nx - 1));
      double v = size[1] * ((double)j / (ny - 1));
      mesh->uv[2 * k] = u;
      mesh->uv[2 * k + 1] = v;
      mesh->x[3 * k + au] = u;
      mesh->x[3 * k + av] = v;
    }
}

/* Two counter-clockwise triangles per cell; the diagonal alternates like a checkerboard. */
static void grid_faces(sw_mesh *mesh, int nx, int ny) {
  int t = 0;
  for (int j = 0; j + 1 < ny; j++)
    for (int i = 0; i + 1 < nx; i++) {
      int a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx; /* corners, ccw from (i,j) */
      int tri[6];
      if ((i + j) % 2 == 0) { /* diagonal a-c */
        int q[6] = {a, b, c, a, c, d};
        memcpy(tri, q, sizeof tri);
      } else { /* diagonal b-d */
        int q[6] = {a, b, d, b, c, d};
        memcpy(tri, q, sizeof tri);
      }
      memcpy(mesh->f + 3 * t, tri, sizeof tri);
      memcpy(mesh->fuv + 3 * t, tri, sizeof tri);
      mesh->fpoly[t] = mesh->fpoly[t + 1] = t / 2; /* the quad */
      t += 2;
    }
}

int sw_mesh_grid(sw_mesh *mesh, const double size[2], int nx, int ny, const char *plane,
                 char *err, size_t errsz) {
  int au = 0, av = 1;
  if (!mesh) { sw_errf(err, errsz, "grid: mesh is NULL"); return SW_FATAL; }
  memset(mesh, 0, sizeof *mesh);
  if (grid_check(size, nx, ny, plane, err, errsz)) return SW_FATAL;
  grid_axes(plane, &au, &av);
  size_t nv = (size_t)nx * (size_t)ny, nf = 2 * (size_t)(nx - 1) * (size_t)(ny - 1);
  mesh->x = sw_calloc(3 * nv, sizeof *mesh->x);
  mesh->uv = sw_calloc(2 * nv, sizeof *mesh->uv);
  mesh->f = sw_calloc(3 * nf, sizeof *mesh->f);
  mesh->fuv = sw_calloc(3 * nf, sizeof *mesh->fuv);
  mesh->fgroup = sw_calloc(nf, sizeof *mesh->fgroup);
  mesh->fpoly = sw_calloc(nf, sizeof *mesh->fpoly);
  mesh->group = sw_calloc(1, sizeof *mesh->group);
  if (!mesh->x || !mesh->uv || !mesh->f || !mesh->fuv || !mesh->fgroup || !mesh->fpoly || !mesh->group) {
    sw_mesh_free(mesh);
    sw_errf(err, errsz, "grid: out of memory for %d x %d vertices", nx, ny);
    return SW_FATAL;
  }
  mesh->nv = mesh->nuv = (int)nv;
  mesh->nf = (int)nf;
  mesh->ngroup = 1;
  strcpy(mesh->group[0], "default");
  grid_vertices(mesh, size, nx, ny, au, av);
  grid_faces(mesh, nx, ny);
  return SW_OK;
}
