/* vtu.c — the frames of a run (writer.h): frames/frame_NNNNNN.vtu (VTK XML UnstructuredGrid,
 * ASCII: the faces as triangles and each tendon as a polyline; velocity and pinned on the
 * points; tension XY, stretches, shear and tendon tension on the cells) and their index
 * frames.pvd (a ParaView collection of the complete frames, rewritten after each).  Each file
 * is written to NAME.tmp and renamed when whole.  With opt.frames_every < 0 no frame is written
 * (frames/ is not even made) except the last good state of a failed run. */
#include <dirent.h>
#include <errno.h>
#include <string.h>

#include "util.h"
#include "writer.h"

typedef struct vtu {
  int frames_dir; /* 1 once frames/ exists */
  int nframe, frame_cap;
  double *frame_t; /* (frame_cap) time of each complete frame, s */
} vtu;

/* ---------------------------------------------------------------- folder */

static int ends_with(const char *s, const char *tail) {
  size_t n = strlen(s), k = strlen(tail);
  return n >= k && strcmp(s + n - k, tail) == 0;
}

/* Remove the frames (NAME.vtu, and unfinished NAME.vtu.tmp) of an earlier run (none when
 * there is no frames/ folder). */
static int remove_stale_frames(sw_output *o, char *err, size_t errsz) {
  if (out_join(o->tmp, o->dir, "frames", err, errsz)) return -1;
  DIR *dp = opendir(o->tmp);
  if (!dp && errno == ENOENT) return 0;
  if (!dp) {
    sw_errf(err, errsz, "%s: cannot list: %s", o->tmp, strerror(errno));
    return -1;
  }
  int rc = 0;
  for (;;) {
    errno = 0;
    struct dirent *e = readdir(dp);
    if (!e) {
      if (errno) rc = -1, sw_errf(err, errsz, "%s: cannot list: %s", o->tmp, strerror(errno));
      break;
    }
    if (!ends_with(e->d_name, ".vtu") && !ends_with(e->d_name, ".vtu.tmp")) continue;
    if (out_join(o->path, o->tmp, e->d_name, err, errsz) ||
        out_remove_path(o->path, err, errsz)) {
      rc = -1;
      break;
    }
  }
  closedir(dp);
  return rc;
}

/* frames/ in the run folder (once). */
static int make_frames_dir(vtu *v, sw_output *o, char *err, size_t errsz) {
  if (v->frames_dir) return 0;
  if (out_join(o->path, o->dir, "frames", err, errsz)) return -1;
  if (out_make_dir(o->path, o->dir, err, errsz)) return -1;
  v->frames_dir = 1;
  return 0;
}

/* frames/ when frames are on (before any file is opened: a `frames` that is not a folder
 * fails the run before it writes anything), then the frames of an earlier run go. */
static int vtu_prepare(void *self, sw_output *o, const sw_model *m, char *err, size_t errsz) {
  if (m->opt.frames_every >= 0.0 && make_frames_dir(self, o, err, errsz)) return -1;
  return remove_stale_frames(o, err, errsz);
}

static int vtu_init(void *self, const sw_model *m) {
  vtu *v = self;
  int cap = 2; /* first and last frame */
  if (m->opt.frames_every > 0 && m->opt.duration > 0) {
    double n = m->opt.duration / m->opt.frames_every + 3;
    cap = n < 1 << 16 ? (int)n : 1 << 16; /* beyond that, vtu_write grows the list */
  }
  v->frame_t = sw_calloc((size_t)cap, sizeof(double));
  v->frame_cap = cap;
  return v->frame_t ? 0 : -1;
}

/* ------------------------------------------------------------------ frame */

static void vtu_points(out_file *w, const sw_model *m, const double *x) {
  out_puts(w, "      <Points>\n"
              "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (int i = 0; i < m->nv; i++) {
    const double *p = x + (size_t)i * (size_t)m->dim;
    out_num(w, p[0], " ");
    out_num(w, p[1], " ");
    out_num(w, m->dim == 3 ? p[2] : 0.0, "\n"); /* m; z = 0 in 2D */
  }
  out_puts(w, "        </DataArray>\n      </Points>\n");
}

/* The faces as triangles, then each tendon as a polyline through its waypoints. */
static void vtu_cells(out_file *w, const sw_model *m) {
  out_puts(w, "      <Cells>\n"
              "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
  for (int f = 0; f < m->nf; f++)
    out_printf(w, "%d %d %d\n", m->face[3 * f], m->face[3 * f + 1], m->face[3 * f + 2]);
  for (int k = 0; k < m->ntendon; k++)
    for (int i = 0; i < m->tendon[k].nway; i++)
      out_printf(w, "%d%s", m->tendon[k].way[i], i + 1 < m->tendon[k].nway ? " " : "\n");
  out_puts(w, "        </DataArray>\n"
              "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  long off = 0;
  for (int f = 0; f < m->nf; f++) out_printf(w, "%ld\n", off += 3);
  for (int k = 0; k < m->ntendon; k++) out_printf(w, "%ld\n", off += m->tendon[k].nway);
  out_puts(w, "        </DataArray>\n"
              "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (int f = 0; f < m->nf; f++) out_puts(w, "5\n");      /* VTK_TRIANGLE */
  for (int k = 0; k < m->ntendon; k++) out_puts(w, "4\n"); /* VTK_POLY_LINE */
  out_puts(w, "        </DataArray>\n      </Cells>\n");
}

/* A cell array: a[0..n-1] on the faces (or 0 when a is NULL), then t[0..nt-1] on the tendon
 * polylines (or 0 when t is NULL). */
static void vtu_scalars(out_file *w, const char *name, const double *a, int n, const double *t,
                        int nt) {
  out_printf(w, "        <DataArray type=\"Float64\" Name=\"%s\" format=\"ascii\">\n", name);
  for (int i = 0; i < n; i++) out_num(w, a ? a[i] : 0.0, "\n");
  for (int i = 0; i < nt; i++) out_num(w, t ? t[i] : 0.0, "\n");
  out_puts(w, "        </DataArray>\n");
}

static void vtu_cell_data(out_file *w, const sw_model *m, const sw_data *d) {
  const int nf = m->nf, nt = m->ntendon;
  out_puts(w, "      <CellData Scalars=\"tension_xy\">\n");
  vtu_scalars(w, "tension_xy", d->txy, nf, NULL, nt); /* N/m */
  vtu_scalars(w, "stretch_u", d->stretch_u, nf, NULL, nt);
  vtu_scalars(w, "stretch_v", d->stretch_v, nf, NULL, nt);
  vtu_scalars(w, "shear", d->shear, nf, NULL, nt); /* rad */
  if (nt) vtu_scalars(w, "tendon_tension", NULL, nf, d->tendon_tension, nt); /* N */
  out_puts(w, "      </CellData>\n");
}

static void vtu_point_data(out_file *w, const sw_model *m, const sw_data *d) {
  out_puts(w, "      <PointData Vectors=\"velocity\">\n"
              "        <DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" "
              "format=\"ascii\">\n");
  for (int i = 0; i < m->nv; i++) { /* m/s */
    const double *v = d->v + (size_t)i * (size_t)m->dim;
    out_num(w, v[0], " ");
    out_num(w, v[1], " ");
    out_num(w, m->dim == 3 ? v[2] : 0.0, "\n");
  }
  out_puts(w, "        </DataArray>\n"
              "        <DataArray type=\"UInt8\" Name=\"pinned\" format=\"ascii\">\n");
  for (int i = 0; i < m->nv; i++) out_puts(w, m->pinned && m->pinned[i] ? "1\n" : "0\n");
  out_puts(w, "        </DataArray>\n      </PointData>\n");
}

static void vtu_body(out_file *w, const sw_model *m, const sw_data *d) {
  out_puts(w, "<?xml version=\"1.0\"?>\n"
              "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
              "  <UnstructuredGrid>\n");
  out_printf(w, "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n", m->nv,
             m->nf + m->ntendon);
  vtu_point_data(w, m, d);
  vtu_cell_data(w, m, d);
  vtu_points(w, m, d->x);
  vtu_cells(w, m);
  out_puts(w, "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

static int write_vtu(vtu *v, sw_output *o, const sw_model *m, const sw_data *d, char *err,
                     size_t errsz) {
  char name[64];
  if (make_frames_dir(v, o, err, errsz)) return -1;
  snprintf(name, sizeof name, "frames/frame_%06d.vtu.tmp", v->nframe);
  if (out_join(o->tmp, o->dir, name, err, errsz)) return -1;
  name[strlen(name) - 4] = '\0'; /* drop ".tmp" */
  if (out_join(o->path, o->dir, name, err, errsz)) return -1;
  out_file w;
  if (out_tmp_open(&w, o->tmp, err, errsz)) return -1;
  vtu_body(&w, m, d);
  return out_tmp_commit(&w, o->tmp, o->path, err, errsz);
}

/* --------------------------------------------------------------- index */

/* frames.pvd listing frames 0 .. v->nframe-1. */
static int write_pvd(const vtu *v, sw_output *o, char *err, size_t errsz) {
  if (out_join(o->tmp, o->dir, "frames.pvd.tmp", err, errsz)) return -1;
  if (out_join(o->path, o->dir, "frames.pvd", err, errsz)) return -1;
  out_file w;
  if (out_tmp_open(&w, o->tmp, err, errsz)) return -1;
  out_puts(&w, "<?xml version=\"1.0\"?>\n"
               "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "  <Collection>\n");
  for (int i = 0; i < v->nframe; i++) {
    out_puts(&w, "    <DataSet timestep=\"");
    out_num(&w, v->frame_t[i], "\"");
    out_printf(&w, " group=\"\" part=\"0\" file=\"frames/frame_%06d.vtu\"/>\n", i);
  }
  out_puts(&w, "  </Collection>\n</VTKFile>\n");
  return out_tmp_commit(&w, o->tmp, o->path, err, errsz);
}

static int grow_frames(vtu *v, const sw_output *o, char *err, size_t errsz) {
  if (v->nframe < v->frame_cap) return 0;
  int cap = v->frame_cap < 4 ? 4 : 2 * v->frame_cap;
  double *t = sw_realloc(v->frame_t, (size_t)cap, sizeof *t);
  if (!t) {
    sw_errf(err, errsz, "%s: out of memory for the list of frames", o->dir);
    return -1;
  }
  v->frame_t = t;
  v->frame_cap = cap;
  return 0;
}

static int vtu_write(void *self, sw_output *o, const sw_model *m, const sw_data *d, char *err,
                     size_t errsz) {
  vtu *v = self;
  if (grow_frames(v, o, err, errsz) || write_vtu(v, o, m, d, err, errsz)) return -1;
  v->frame_t[v->nframe++] = d->t;
  return write_pvd(v, o, err, errsz);
}

static void vtu_files(const void *self, void (*add)(void *ctx, const char *name), void *ctx) {
  const vtu *v = self;
  char name[32];
  if (v->nframe) add(ctx, "frames.pvd");
  for (int i = 0; i < v->nframe; i++) {
    snprintf(name, sizeof name, "frames/frame_%06d.vtu", i);
    add(ctx, name);
  }
}

static void vtu_free(void *self) { sw_free(((vtu *)self)->frame_t); }

const sw_out_ops sw_out_vtu = {
    .name = "frames",
    .stale = (const char *const[]){"frames.pvd", "frames.pvd.tmp", NULL},
    .event = SW_OUT_FRAME,
    .size = sizeof(vtu),
    .init = vtu_init,
    .prepare = vtu_prepare,
    .write = vtu_write,
    .files = vtu_files,
    .free = vtu_free,
};
