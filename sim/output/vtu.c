/* vtu.c — the frames of a run (writer.h), in VTK's XML format (vtkxml.h: binary, appended and
 * zlib-compressed as ParaView writes it, or ascii with opt.frames_format):
 *   frames/frame_NNNNNN.vtu    the cloth, an UnstructuredGrid of triangles: positions; on the
 *                              points velocity, pinned and the rest (u,v); on the cells tension
 *                              XY, stretches, shear, the panel (and the (u,v) of each corner
 *                              when some vertex has two, a seam); the time as TimeValue;
 *   frames/tendons_NNNNNN.vtp  the tendons (scenes with tendons), a PolyData of one polyline
 *                              each through its waypoints: on the points the mesh vertex; on the
 *                              cells tension, length and rest length; the time;
 *   frames.pvd                 a ParaView collection of the complete frames (both files of a
 *                              frame at its timestep, part 0 the cloth, part 1 the tendons),
 *                              rewritten after each.
 * Each file is written to NAME.tmp and renamed when whole.  With opt.frames_every < 0 no frame
 * is written (frames/ is not even made) except the last good state of a failed run. */
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"
#include "vtkxml.h"
#include "writer.h"

_Static_assert(sizeof(int) == 4, "connectivity and panel ids are written as Int32");

typedef struct vtu {
  int frames_dir; /* 1 once frames/ exists */
  int nframe, frame_cap;
  double *frame_t;       /* (frame_cap) time of each complete frame, s */
  vx_file vx;            /* the encoder and its buffer */
  double *xyz;           /* (max(nv, tendon waypoints) x 3) points with z = 0 in 2D, m */
  int64_t *offsets;      /* (max(nf, ntendon)) cell offsets */
  unsigned char *types;  /* (nf) VTK_TRIANGLE */
  unsigned char *pinned; /* (nv) 1 where pinned */
  int *panel;            /* (nf) the panel (material) of each face */
  double *uv;            /* (nv x 2) rest (u,v) of each vertex, m (NULL: the model has none) */
  double *uv_corner;     /* (nf x 6) rest (u,v) of each corner, m; NULL without seams */
  int npts;              /* tendon waypoints in all */
  int *way;              /* (npts) their vertices, tendon after tendon */
  int *line;             /* (npts) 0 .. npts-1: the polylines' connectivity */
  int *tendon_id;        /* (ntendon) 0 .. ntendon-1 */
  double *rest;          /* (ntendon) rest length at the frame, m */
} vtu;

/* ---------------------------------------------------------------- folder */

/* A name sinew gives a frame: frame_NNNNNN.vtu, tendons_NNNNNN.vtp, or either + ".tmp". */
static int is_frame_file(const char *name) {
  const char *s = !strncmp(name, "frame_", 6) ? name + 6 : !strncmp(name, "tendons_", 8) ? name + 8 : NULL;
  if (!s || !('0' <= *s && *s <= '9')) return 0;
  while ('0' <= *s && *s <= '9') s++;
  return !strcmp(s, ".vtu") || !strcmp(s, ".vtu.tmp") || !strcmp(s, ".vtp") ||
         !strcmp(s, ".vtp.tmp");
}

/* frames/ holds no frame file (NAME.vtu, NAME.vtp, NAME.vt?.tmp) that the earlier run's
 * manifest does not name: a run never replaces or mixes with frames it did not write. */
static int check_frames(sw_output *o, char *err, size_t errsz) {
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
    char name[SW_OUT_PATHMAX];
    snprintf(name, sizeof name, "frames/%s", e->d_name);
    if (!is_frame_file(e->d_name) || out_owned(o, name)) continue;
    sw_errf(err, errsz, "%s/%s: a frame file that no earlier sinew run here wrote (%s/sinew."
            "manifest does not name it); expected no such file: move it or choose another "
            "output folder", o->dir, name, o->dir);
    rc = -1;
    break;
  }
  closedir(dp);
  return rc;
}

/* frames/ in the run folder (once). */
static int make_frames_dir(vtu *v, sw_output *o, char *err, size_t errsz) {
  if (v->frames_dir) return 0;
  struct stat st;
  if (out_join(o->path, o->dir, "frames", err, errsz)) return -1;
  if (lstat(o->path, &st)) o->made_frames = 1;
  if (out_make_dir(o->path, o->dir, err, errsz)) return -1;
  v->frames_dir = 1;
  return 0;
}

/* frames/ when frames are on (before any file is opened: a `frames` that is not a writable
 * folder fails the run before it touches anything), checked: not a symbolic link (it could
 * lead out of the folder), no frame files of another origin. */
static int vtu_prepare(void *self, sw_output *o, const sw_model *m, char *err, size_t errsz) {
  struct stat st;
  if (out_join(o->tmp, o->dir, "frames", err, errsz)) return -1;
  if (lstat(o->tmp, &st) == 0 && S_ISLNK(st.st_mode))
    return sw_errf(err, errsz, "%s: is a symbolic link; expected a folder (sinew writes and "
                   "removes files only inside its output folder): remove the link or choose "
                   "another output folder", o->tmp),
           -1;
  if (m->opt.frames_every >= 0.0 && make_frames_dir(self, o, err, errsz)) return -1;
  if (m->opt.frames_every >= 0.0 && access(o->path, W_OK | X_OK))
    return sw_errf(err, errsz, "%s: the frames folder is not writable: %s", o->path,
                   strerror(errno)),
           -1;
  return check_frames(o, err, errsz);
}

/* ------------------------------------------------------------ constants */

/* The rest (u,v) of corner i of face f as the pattern gives it: m->uv with the panel's bias
 * rotation (sw_model_finish) undone, m. */
static void corner_uv(const sw_model *m, int f, int i, double out[2]) {
  const double *uv = m->uv + 6 * f + 2 * i;
  double b = m->mat && m->face_mat ? m->mat[m->face_mat[f]].bias : 0.0; /* rad */
  double c = cos(b), s = sin(b);
  out[0] = c * uv[0] - s * uv[1];
  out[1] = s * uv[0] + c * uv[1];
}

/* The (u,v) of each vertex (its first corner's); with a seam, also the (u,v) of every corner. */
static int init_uv(vtu *v, const sw_model *m) {
  if (!m->uv) return 0;
  unsigned char *seen = sw_calloc((size_t)m->nv + 1, 1);
  v->uv = sw_calloc(2 * (size_t)m->nv + 1, sizeof(double));
  if (!seen || !v->uv) return sw_free(seen), -1;
  int seams = 0;
  for (int f = 0; f < m->nf; f++)
    for (int i = 0; i < 3; i++) {
      double c[2];
      int p = m->face[3 * f + i];
      corner_uv(m, f, i, c);
      if (!seen[p]) seen[p] = 1, memcpy(v->uv + 2 * p, c, sizeof c);
      else seams |= c[0] != v->uv[2 * p] || c[1] != v->uv[2 * p + 1];
    }
  sw_free(seen);
  if (!seams) return 0;
  if (!(v->uv_corner = sw_calloc(6 * (size_t)m->nf, sizeof(double)))) return -1;
  for (int f = 0; f < m->nf; f++)
    for (int i = 0; i < 3; i++) corner_uv(m, f, i, v->uv_corner + 6 * f + 2 * i);
  return 0;
}

static int init_tendons(vtu *v, const sw_model *m) {
  for (int k = 0; k < m->ntendon; k++) v->npts += m->tendon[k].nway;
  v->way = sw_calloc((size_t)v->npts + 1, sizeof(int));
  v->line = sw_calloc((size_t)v->npts + 1, sizeof(int));
  v->tendon_id = sw_calloc((size_t)m->ntendon + 1, sizeof(int));
  v->rest = sw_calloc((size_t)m->ntendon + 1, sizeof(double));
  if (!v->way || !v->line || !v->tendon_id || !v->rest) return -1;
  for (int k = 0, n = 0; k < m->ntendon; k++) {
    v->tendon_id[k] = k;
    for (int i = 0; i < m->tendon[k].nway; i++, n++) v->way[n] = m->tendon[k].way[i];
  }
  for (int i = 0; i < v->npts; i++) v->line[i] = i;
  return 0;
}

/* The arrays every frame repeats. */
static int init_constants(vtu *v, const sw_model *m) {
  size_t np = (size_t)(m->nv > v->npts ? m->nv : v->npts);
  size_t nc = (size_t)(m->nf > m->ntendon ? m->nf : m->ntendon);
  v->xyz = sw_calloc(3 * np + 1, sizeof(double));
  v->offsets = sw_calloc(nc + 1, sizeof(int64_t));
  v->types = sw_calloc((size_t)m->nf + 1, 1);
  v->pinned = sw_calloc((size_t)m->nv + 1, 1);
  v->panel = sw_calloc((size_t)m->nf + 1, sizeof(int));
  if (!v->xyz || !v->offsets || !v->types || !v->pinned || !v->panel) return -1;
  for (int f = 0; f < m->nf; f++) {
    v->types[f] = 5; /* VTK_TRIANGLE */
    v->panel[f] = m->face_mat ? m->face_mat[f] : 0;
  }
  for (int i = 0; i < m->nv; i++) v->pinned[i] = m->pinned && m->pinned[i];
  return 0;
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
  v->vx.ascii = m->opt.frames_format == SW_FRAMES_ASCII;
  v->vx.single = m->opt.frames_format == SW_FRAMES_BINARY32;
  v->vx.level = 1; /* Z_BEST_SPEED: level 6 writes 8 % smaller frames 7x slower (docs/scenes.md) */
  if (!v->frame_t || init_tendons(v, m) || init_constants(v, m)) return -1;
  return init_uv(v, m);
}

/* ------------------------------------------------------------------ frame */

/* n points of dim coordinates at x (rows idx[i] when idx is not NULL) as (n x 3), z = 0 in
 * 2D: x itself when it already is, else v->xyz. */
static const double *points3(vtu *v, const double *x, int dim, const int *idx, int n) {
  if (dim == 3 && !idx) return x;
  for (int i = 0; i < n; i++) {
    const double *p = x + (size_t)(idx ? idx[i] : i) * (size_t)dim;
    double *q = v->xyz + 3 * (size_t)i;
    q[0] = p[0], q[1] = p[1], q[2] = dim == 3 ? p[2] : 0.0;
  }
  return v->xyz;
}

/* Cell offsets of n cells of sizes len[k] (or 3 each when len is NULL). */
static const int64_t *cell_offsets(vtu *v, const sw_model *m, int n, int tendons) {
  int64_t off = 0;
  for (int k = 0; k < n; k++) v->offsets[k] = off += tendons ? m->tendon[k].nway : 3;
  return v->offsets;
}

static void cloth_point_data(vtu *v, const sw_model *m, const sw_data *d) {
  vx_file *x = &v->vx;
  const size_t nv = (size_t)m->nv;
  vx_puts(x, "      <PointData Vectors=\"velocity\">\n");
  vx_array(x, "        ", VX_F64, "velocity", 3, points3(v, d->v, m->dim, NULL, m->nv), nv);
  vx_array(x, "        ", VX_U8, "pinned", 1, v->pinned, nv);
  if (v->uv) vx_array(x, "        ", VX_F64, "uv", 2, v->uv, nv); /* m */
  vx_puts(x, "      </PointData>\n");
}

static void cloth_cell_data(vtu *v, const sw_model *m, const sw_data *d) {
  vx_file *x = &v->vx;
  const size_t nf = (size_t)m->nf;
  vx_puts(x, "      <CellData Scalars=\"tension_xy\">\n");
  vx_array(x, "        ", VX_F64, "tension_xy", 1, d->txy, nf); /* N/m */
  vx_array(x, "        ", VX_F64, "stretch_u", 1, d->stretch_u, nf);
  vx_array(x, "        ", VX_F64, "stretch_v", 1, d->stretch_v, nf);
  vx_array(x, "        ", VX_F64, "shear", 1, d->shear, nf); /* rad */
  if (d->contact_pressure) /* N/m^2 */
    vx_array(x, "        ", VX_F64, "contact_pressure", 1, d->contact_pressure, nf);
  vx_array(x, "        ", VX_I32, "panel", 1, v->panel, nf);
  if (v->uv_corner) vx_array(x, "        ", VX_F64, "uv_corners", 6, v->uv_corner, nf); /* m */
  vx_puts(x, "      </CellData>\n");
}

static void cloth_body(vtu *v, const sw_model *m, const sw_data *d) {
  vx_file *x = &v->vx;
  vx_time(x, "    ", d->t);
  out_printf(x->w, "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n", m->nv, m->nf);
  cloth_point_data(v, m, d);
  cloth_cell_data(v, m, d);
  vx_puts(x, "      <Points>\n");
  vx_array(x, "        ", VX_F64, "Points", 3, points3(v, d->x, m->dim, NULL, m->nv),
           (size_t)m->nv); /* m */
  vx_puts(x, "      </Points>\n      <Cells>\n");
  vx_array(x, "        ", VX_I32, "connectivity", 1, m->face, 3 * (size_t)m->nf);
  vx_array(x, "        ", VX_I64, "offsets", 1, cell_offsets(v, m, m->nf, 0), (size_t)m->nf);
  vx_array(x, "        ", VX_U8, "types", 1, v->types, (size_t)m->nf);
  vx_puts(x, "      </Cells>\n    </Piece>\n");
}

static void tendon_body(vtu *v, const sw_model *m, const sw_data *d) {
  vx_file *x = &v->vx;
  const size_t nt = (size_t)m->ntendon;
  for (int k = 0; k < m->ntendon; k++) v->rest[k] = sw_tendon_rest(&m->tendon[k], d->t);
  vx_time(x, "    ", d->t);
  out_printf(x->w, "    <Piece NumberOfPoints=\"%d\" NumberOfVerts=\"0\" NumberOfLines=\"%d\" "
                   "NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n", v->npts, m->ntendon);
  vx_puts(x, "      <PointData Scalars=\"vertex\">\n");
  vx_array(x, "        ", VX_I32, "vertex", 1, v->way, (size_t)v->npts);
  vx_puts(x, "      </PointData>\n      <CellData Scalars=\"tension\">\n");
  vx_array(x, "        ", VX_F64, "tension", 1, d->tendon_tension, nt); /* N */
  vx_array(x, "        ", VX_F64, "length", 1, d->tendon_length, nt);   /* m */
  vx_array(x, "        ", VX_F64, "rest_length", 1, v->rest, nt);       /* m */
  vx_array(x, "        ", VX_I32, "tendon", 1, v->tendon_id, nt);
  vx_puts(x, "      </CellData>\n      <Points>\n");
  vx_array(x, "        ", VX_F64, "Points", 3, points3(v, d->x, m->dim, v->way, v->npts),
           (size_t)v->npts); /* m */
  vx_puts(x, "      </Points>\n      <Lines>\n");
  vx_array(x, "        ", VX_I32, "connectivity", 1, v->line, (size_t)v->npts);
  vx_array(x, "        ", VX_I64, "offsets", 1, cell_offsets(v, m, m->ntendon, 1), nt);
  vx_puts(x, "      </Lines>\n    </Piece>\n");
}

/* frames/NAME_NNNNNN.EXT of the current frame, written through NAME.tmp. */
static int write_piece(vtu *v, sw_output *o, const sw_model *m, const sw_data *d,
                       int tendons, char *err, size_t errsz) {
  const char *type = tendons ? "PolyData" : "UnstructuredGrid";
  char name[64];
  snprintf(name, sizeof name, tendons ? "frames/tendons_%06d.vtp" : "frames/frame_%06d.vtu",
           v->nframe);
  if (out_own(o, name, err, errsz) || out_join(o->path, o->dir, name, err, errsz)) return -1;
  strcat(name, ".tmp");
  if (out_join(o->tmp, o->dir, name, err, errsz)) return -1;
  out_file w;
  if (out_tmp_open(&w, o->tmp, err, errsz)) return -1;
  vx_begin(&v->vx, &w, type);
  if (tendons) tendon_body(v, m, d);
  else cloth_body(v, m, d);
  if (vx_end(&v->vx, type, o->tmp, err, errsz)) { /* out of memory, zlib */
    fclose(w.f);
    remove(o->tmp);
    return -1;
  }
  return out_tmp_commit(&w, o->tmp, o->path, err, errsz);
}

/* --------------------------------------------------------------- index */

/* One DataSet line of frames.pvd. */
static void pvd_entry(out_file *w, double t, int part, const char *file, int i) {
  out_puts(w, "    <DataSet timestep=\"");
  out_num(w, t, "\"");
  out_printf(w, " group=\"\" part=\"%d\" name=\"%s\" file=\"frames/%s_%06d.%s\"/>\n", part,
             part ? "tendons" : "cloth", file, i, part ? "vtp" : "vtu");
}

/* frames.pvd listing frames 0 .. v->nframe-1: the cloth (part 0) and the tendons (part 1). */
static int write_pvd(const vtu *v, sw_output *o, const sw_model *m, char *err, size_t errsz) {
  if (out_join(o->tmp, o->dir, "frames.pvd.tmp", err, errsz)) return -1;
  if (out_join(o->path, o->dir, "frames.pvd", err, errsz)) return -1;
  out_file w;
  if (out_tmp_open(&w, o->tmp, err, errsz)) return -1;
  out_puts(&w, "<?xml version=\"1.0\"?>\n"
               "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "  <Collection>\n");
  for (int i = 0; i < v->nframe; i++) {
    pvd_entry(&w, v->frame_t[i], 0, "frame", i);
    if (m->ntendon) pvd_entry(&w, v->frame_t[i], 1, "tendons", i);
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
  if (grow_frames(v, o, err, errsz) || make_frames_dir(v, o, err, errsz) ||
      (v->nframe == 0 && out_own(o, "frames.pvd", err, errsz)) ||
      write_piece(v, o, m, d, 0, err, errsz) ||
      (m->ntendon && write_piece(v, o, m, d, 1, err, errsz)))
    return -1;
  v->frame_t[v->nframe++] = d->t;
  return write_pvd(v, o, m, err, errsz);
}

/* The frames written so far: their count and times (the resumed run's frames.pvd lists them). */
static void vtu_io(void *self, sw_io *io) {
  vtu *v = self;
  int n = v->nframe;
  sw_io_bytes(io, &n, sizeof n);
  if (io->load) {
    if (n < 0 || (size_t)n > (io->len - io->pos) / sizeof(double)) return (void)(io->bad = 1);
    double *t = n > v->frame_cap ? sw_realloc(v->frame_t, (size_t)n, sizeof *t) : v->frame_t;
    if (!t) return (void)(io->bad = 1);
    v->frame_t = t;
    v->frame_cap = n > v->frame_cap ? n : v->frame_cap;
    v->nframe = n;
  }
  sw_io_bytes(io, v->frame_t, (size_t)n * sizeof(double));
}

static void vtu_files(const void *self, void (*add)(void *ctx, const char *name), void *ctx) {
  const vtu *v = self;
  char name[40];
  if (v->nframe) add(ctx, "frames.pvd");
  for (int i = 0; i < v->nframe; i++) {
    snprintf(name, sizeof name, "frames/frame_%06d.vtu", i);
    add(ctx, name);
    if (!v->npts) continue;
    snprintf(name, sizeof name, "frames/tendons_%06d.vtp", i);
    add(ctx, name);
  }
}

static void vtu_free(void *self) {
  vtu *v = self;
  void *p[] = {v->frame_t, v->xyz,  v->offsets,   v->types, v->pinned, v->panel,
               v->uv,      v->uv_corner, v->way, v->line,  v->tendon_id, v->rest};
  for (size_t i = 0; i < sizeof p / sizeof p[0]; i++) sw_free(p[i]);
  vx_free(&v->vx);
}

const sw_out_ops sw_out_vtu = {
    .name = "frames",
    .event = SW_OUT_FRAME,
    .size = sizeof(vtu),
    .init = vtu_init,
    .prepare = vtu_prepare,
    .write = vtu_write,
    .files = vtu_files,
    .io = vtu_io,
    .free = vtu_free,
};
